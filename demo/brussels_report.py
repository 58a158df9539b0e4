"""The report of demo/brussels_1924.sh (the shortened chain: plots -> subdivide -> lod2).

    python3 demo/brussels_report.py OUT [SHARED_DATA]

Reads OUT/times.txt, OUT/lod2.txt, OUT/model.city.json and the maps plots
and footprints of the current mapset; writes OUT/report.json and
OUT/report.txt (printed too): plots, footprints, overlapping pairs (over
0.01 m² of map units, chain_report.OVERLAP_TOLERANCE), plots with
footprints, valid solids, the CityJSON against
SHARED_DATA/../schemas/cityjson-2.0.2 (the document and the first
:data:`SCHEMA_OBJECTS` buildings: the schema checks about 40 a second, every
one of 17,000 would take minutes) and the stages' wall times.
"""

import os
import sys

import chain_report as cr

#: city objects checked against the schema (the first ones)
SCHEMA_OBJECTS = 1000
#: what the thesis reports for Brussels 1924 (../shared/data/README.md)
THESIS_PLOTS, THESIS_FOOTPRINTS = 616, "15,015 (615 plots)"


def build(out, shared_data):
    from reconstruction import grassio

    plots = len(grassio.read_areas("plots", table=False)[0])
    seconds = cr.stage_seconds(out)
    model = cr.model(out)
    return {
        "seconds": seconds,
        "total_seconds": round(sum(seconds.values()), 3),
        "plots": plots,
        "subdivide": cr.footprint_figures(*cr.footprints()),
        "lod2": cr.lod2_figures(out, model),
        "cityjson": cr.schema_figures(model, os.path.join(shared_data, "..", "schemas"),
                                      SCHEMA_OBJECTS),
    }


def rows(report):
    fp = report["subdivide"]
    return [("plots", report["plots"], THESIS_PLOTS),
            ("footprints", fp["footprints"], THESIS_FOOTPRINTS)] + \
        cr.footprint_rows(fp, report["lod2"], report["plots"]) + \
        [("CityJSON 2.0.2 schema", cr.schema_text(report["cityjson"]), ""),
         ("CityJSON reference system", report["lod2"]["crs"], "")] + \
        cr.time_rows(report["seconds"])


def main(out, shared_data="../shared/data"):
    report = build(out, shared_data)
    cr.write(out, report, rows(report))


if __name__ == "__main__":
    main(*sys.argv[1:])
