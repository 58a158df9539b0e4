"""Figures every chain report has (demo/delft_report.py, demo/brussels_report.py).

Each function reads one output of the chain (the OUT folder of the chain
script, or a map of the current GRASS mapset) and returns plain numbers, so a
report is one JSON document; :func:`write` writes it with its text table.
Run inside the GRASS session of the chain.
"""

import collections
import json
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
if ROOT not in sys.path:
    sys.path.insert(0, ROOT)

#: two footprints overlap when their intersection is larger than this (m²):
#: footprints that only share an edge, up to the rounding of the coordinates,
#: do not
OVERLAP_TOLERANCE = 0.01


def load(out, name):
    with open(os.path.join(out, name)) as f:
        return json.load(f)


def stage_seconds(out):
    """{stage: wall seconds} from OUT/times.txt (steps.sh's timed), in the order the stages ran."""
    with open(os.path.join(out, "times.txt")) as f:
        return {s: int(ms) / 1000.0 for s, ms in (line.split() for line in f if line.strip())}


def footprints(name="footprints"):
    """The footprints of <name> with their columns (grassio.read_areas)."""
    from reconstruction import grassio

    return grassio.read_areas(name)


def footprint_figures(geometries, columns):
    """How many footprints of each source (aligned, 2pm), how many overlapping pairs
    (intersection over :data:`OVERLAP_TOLERANCE`, shapely STRtree:
    generalization.overlapping_pairs) and how many plots hold footprints."""
    from reconstruction.core import contract
    from reconstruction.generalize.operators import overlapping_pairs

    sources = collections.Counter(columns[contract.SOURCE])
    pairs = overlapping_pairs(geometries, min_area=OVERLAP_TOLERANCE)
    return {"footprints": len(geometries), "by_source": dict(sorted(sources.items())),
            "overlapping_pairs": len(pairs), "overlap_tolerance_m2": OVERLAP_TOLERANCE,
            "plots_with_footprints": len(set(columns[contract.PLOT]))}


def model(out):
    """The chain's CityJSON model, OUT/model.city.json (read once, for
    :func:`lod2_figures` and :func:`schema_figures`)."""
    return load(out, "model.city.json")


def lod2_figures(out, model):
    """v.histo.lod2 -v's figures (OUT/lod2.txt) and the ``model``'s buildings by height source."""
    with open(os.path.join(out, "lod2.txt")) as f:
        lod2 = dict(line.strip().split("=", 1) for line in f if "=" in line)
    heights = collections.Counter(o["attributes"].get("height_source")
                                  for o in model["CityObjects"].values())
    return dict({k: (float(v) if "." in v else int(v)) for k, v in lod2.items()},
                buildings=len(model["CityObjects"]), height_source=dict(sorted(heights.items())),
                crs=model["metadata"].get("referenceSystem"))


def ends_figures(model):
    """The roof ends of the ``model`` read back from its geometry alone
    (testsuite/lod2_ends.py, as the module's tests read them): ``ends`` the
    edges with a gable or crow-stepped wall rising above the eaves or a hip
    end steeper than the long faces, ``on_shared`` those on an edge shared
    with a neighbour, by kind (``wall``, ``hip``): what the roof rules
    promise never to build."""
    folder = os.path.join(ROOT, "testsuite")
    if folder not in sys.path:
        sys.path.insert(0, folder)
    import lod2_ends

    return lod2_ends.ends_on_shared(model)


def ends_text(figures):
    """:func:`ends_figures` in a few words."""
    return "{} walls, {} hip ends (of {} ends)".format(figures["wall"], figures["hip"],
                                                      figures["ends"])


def schema_figures(model, schemas, max_objects=None):
    """The CityJSON ``model`` against the official 2.0.2 schemas in ``schemas`` (its folder
    cityjson-2.0.2), by the library's cityjson.schema_errors, as the module tests
    check it: the document and every city object, or the first ``max_objects``
    (about 40 objects a second)."""
    from reconstruction.cityjson import model as cityjson

    folder = os.path.join(schemas, "cityjson-2.0.2")
    if not os.path.isdir(folder):
        return {"schema": None, "errors": None, "valid": None}
    errors = cityjson.schema_errors(model, folder, max_objects)
    checked = len(model["CityObjects"]) if max_objects is None else \
        min(max_objects, len(model["CityObjects"]))
    return {"schema": os.path.normpath(folder), "objects_checked": checked,
            "objects": len(model["CityObjects"]), "errors": len(errors),
            "first_errors": errors[:5], "valid": not errors}


def schema_text(figures):
    """:func:`schema_figures` in a few words."""
    if figures["valid"] is None:
        return "not checked (no schemas)"
    text = "valid" if figures["valid"] else "{} errors".format(figures["errors"])
    if figures["objects_checked"] < figures["objects"]:
        text += " (document + first {} of {} objects)".format(figures["objects_checked"],
                                                             figures["objects"])
    return text


def write(out, report, rows):
    """OUT/report.json and OUT/report.txt (the table of ``rows``: (figure, ours,
    thesis) texts), the table printed too."""
    with open(os.path.join(out, "report.json"), "w") as f:
        json.dump(report, f, indent=1)  # stages in the order they ran
    rows = [("figure", "this suite", "thesis")] + [tuple(str(c) for c in r) for r in rows]
    widths = [max(len(r[i]) for r in rows) for i in range(3)]
    lines = ["  ".join(c.ljust(w) for c, w in zip(r, widths)).rstrip() for r in rows]
    lines.insert(1, "  ".join("-" * w for w in widths))
    text = "\n".join(lines) + "\n"
    with open(os.path.join(out, "report.txt"), "w") as f:
        f.write(text)
    print(text, end="")


def footprint_rows(fp, lod2, plots, thesis=("", "")):
    """Table rows of :func:`footprint_figures` and :func:`lod2_figures`; ``thesis``:
    the thesis's aligned and generated footprints."""
    from reconstruction.core import contract

    return [
        ("aligned footprints", fp["by_source"].get(contract.SOURCE_ALIGNED, 0), thesis[0]),
        ("generated footprints", fp["by_source"].get(contract.SOURCE_PROCEDURAL, 0), thesis[1]),
        ("plots with footprints", "{}/{}".format(fp["plots_with_footprints"], plots), ""),
        ("overlapping footprint pairs (> {} m²)".format(fp["overlap_tolerance_m2"]),
         fp["overlapping_pairs"], ""),
        ("valid solids", "{}/{} ({} %)".format(lod2["valid"], lod2["solids"],
                                               lod2["percent_valid"]), ""),
    ]


def time_rows(seconds):
    """Table rows of the stages' wall times and their total."""
    rows = [("time " + stage + " (s)", "{:.1f}".format(s), "") for stage, s in seconds.items()]
    return rows + [("time total (s)", "{:.1f}".format(sum(seconds.values())), "")]


def percent(part, whole):
    return round(100.0 * part / whole, 2) if whole else None
