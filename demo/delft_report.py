"""The report of demo/delft_1961.sh: every acceptance figure of issue 18, computed.

    python3 demo/delft_report.py OUT [SHARED_DATA]

Reads OUT/times.txt (stage, wall ms), OUT/generalize.json, OUT/align.json,
OUT/import.json (the thesis's aligned footprints among the current ones,
demo/delft_import.py), OUT/lod2.txt (v.histo.lod2 -v), OUT/model.city.json,
and the maps of the current mapset: plots, aligned, footprints, the ground
truth (delft_gt_points, delft_gt_polygons) and the thesis's final plots
(plots1961). Writes OUT/report.json and OUT/report.txt (printed too). The
CityJSON is validated against SHARED_DATA/../schemas/cityjson-2.0.2.

The thesis's final plots are scored by the same library code as ours
(the functions v.histo.generalize reports with, against the same
ground-truth points and polygons), so the two columns compare.

Definitions:
- a ground-truth plot is lost when no plot holds its ground-truth point (31
  points, one in each true plot) or, for the 10 digitised ground-truth
  polygons, when no plot intersects it; "plots kept" counts the others;
- a thesis aligned footprint is found when one of the aligned footprints
  (<aligned>) has its outline (the identity test by which the import finds
  it among the current ones); also reported: when the current footprint
  identical to it (its category in <current>) is aligned at all;
- two footprints overlap when their intersection exceeds 0.01 m²
  (chain_report.OVERLAP_TOLERANCE);
- a roof end is on a shared edge when a gable or crow-stepped wall rises
  above the eaves, or a hip end steeper than the long faces stands, on an
  edge within 0.1 m of a neighbour's over half its length
  (chain_report.ends_figures, read from the model's geometry).
"""

import os
import sys

import chain_report as cr

#: the ground-truth points' and polygons' maps (demo/delft_import.py), the
#: thesis's final plots and its aligned footprints (testsuite/histo_testing.py's
#: import_delft_alignment)
GT_POINTS, GT_POLYGONS = "delft_gt_points", "delft_gt_polygons"
THESIS_PLOTS, THESIS_ALIGNED = "plots1961", "thesis61"
#: the thesis's raw building plots (demo/delft_import.py)
THESIS_RAW_PLOTS = "thesis_raw_plots"


def plot_scores(plots, gt_points, gt_polygons):
    """Scores of plots against the ground truth, by the library's functions
    v.histo.generalize reports with (reconstruction.generalize.stage): P/R/F by
    point in polygon, mean turning-function distance and buffer similarity
    against the digitised polygons, the mean outward offset and intersection over
    union of each digitised polygon with the plot that overlaps it most, and the lost
    ground-truth plots."""
    import numpy as np
    import shapely

    from reconstruction.generalize import assessment
    from reconstruction.generalize import operators as generalization
    from reconstruction.generalize import config as generalize
    from reconstruction.generalize import shape_metrics

    points = assessment.point_detection_scores(plots, gt_points)
    refs, _index = generalization.explode_plots(gt_polygons)
    shapes = shape_metrics.shape_scores(plots, refs, generalize.GeneralizeConfig().gt_buffer)
    outline = shape_metrics.outline_agreement(plots, refs)
    hits = assessment.point_hits(plots, gt_points).any(axis=0)
    arr = np.array(plots, dtype=object)
    touched = [bool(shapely.intersects(arr, ref).any()) for ref in gt_polygons]
    return {"plots": len(plots), "precision": points.precision, "recall": points.recall,
            "f_score": points.f_score, "turning_distance": shapes["turning_distance"],
            "buffer_similarity": shapes["buffer_similarity"], "matched": shapes["matched"],
            "outline_offset": outline.offset, "iou": outline.iou,
            "gt_points": len(gt_points), "gt_points_in_a_plot": int(hits.sum()),
            "gt_polygons": len(gt_polygons), "gt_polygons_intersected": sum(touched),
            "lost": int((~hits).sum()) + len(touched) - sum(touched)}


def thesis_aligned_found(out):
    """The thesis's 651 aligned footprints present as aligned buildings here.

    ``found``: an aligned footprint has its geometry (symmetric difference
    under 1e-6 of its area: the identity test of testsuite/histo_testing.py's
    import_delft_alignment, by which the thesis's footprints were found among
    the current ones); ``same_footprint``: the current footprint identical to
    it (its category) is among the aligned ones, whatever v.histo.align did
    to its outline.
    """
    import numpy as np
    import shapely

    from reconstruction import grassio

    thesis = np.array(grassio.read_areas(THESIS_ALIGNED, table=False)[0], dtype=object)
    aligned, columns = grassio.read_areas("aligned", table=False)
    aligned = np.array(aligned, dtype=object)
    i, j = shapely.STRtree(aligned).query(thesis, predicate="intersects")
    same = shapely.area(shapely.symmetric_difference(thesis[i], aligned[j])) < \
        1e-6 * shapely.area(thesis[i])
    found = len(set(i[same].tolist()))
    cats = set(cr.load(out, "import.json")["thesis1961"]) & set(columns["cat"])
    return {"thesis": len(thesis), "found": found, "percent": cr.percent(found, len(thesis)),
            "same_footprint": len(cats),
            "same_footprint_percent": cr.percent(len(cats), len(thesis))}


def build(out, shared_data):
    from reconstruction import grassio

    gt_points = grassio.read_points(GT_POINTS)[0]
    gt_polygons = grassio.read_features(GT_POLYGONS, "area")[0]
    ours = plot_scores(grassio.read_features("plots", "area")[0], gt_points, gt_polygons)
    thesis = plot_scores(grassio.read_areas(THESIS_PLOTS, table=False)[0], gt_points,
                         gt_polygons)
    thesis_raw = plot_scores(grassio.read_areas(THESIS_RAW_PLOTS, table=False)[0], gt_points,
                             gt_polygons)
    seconds = cr.stage_seconds(out)
    model = cr.model(out)
    return {
        "seconds": seconds,
        "total_seconds": round(sum(seconds.values()), 3),
        "plots": ours,
        "thesis_plots": thesis,
        "thesis_raw_plots": thesis_raw,
        "generalize": cr.load(out, "generalize.json"),
        "align": cr.load(out, "align.json"),
        "thesis_aligned": thesis_aligned_found(out),
        "subdivide": cr.footprint_figures(*cr.footprints()),
        "lod2": cr.lod2_figures(out, model),
        "ends": cr.ends_figures(model),
        "cityjson": cr.schema_figures(model, os.path.join(shared_data, "..", "schemas")),
    }


def rows(report):
    """The text table: our figure and the thesis's beside it, where there is one (the
    outlines: our classified cells and plots, the thesis's raw and final plots)."""
    ours, thesis, gen = report["plots"], report["thesis_plots"], report["generalize"]
    raw = report["thesis_raw_plots"]
    fp, lod2, found = report["subdivide"], report["lod2"], report["thesis_aligned"]

    def f3(x):
        return "" if x is None else "{:.3f}".format(x)

    def signed(x):
        return "" if x is None else "{:+.2f}".format(x)

    def step(figures, name, key):
        return (figures.get("outline_by_step") or {}).get(name, {}).get(key)

    return [
        ("precision / recall / F (generalize.json)",
         "{} / {} / {}".format(f3(gen["precision"]), f3(gen["recall"]), f3(gen["f_score"])),
         "{} / {} / {}".format(f3(thesis["precision"]), f3(thesis["recall"]),
                               f3(thesis["f_score"]))),
        ("mean turning-function distance", f3(gen["turning_distance"]),
         f3(thesis["turning_distance"])),
        ("mean buffer similarity (%)", "{:.2f}".format(gen["buffer_similarity"]),
         "{:.2f}".format(thesis["buffer_similarity"])),
        ("mean outward offset (m): cells / plots", "{} / {}".format(
            signed(step(gen, "raw", "offset")), signed(gen.get("outline_offset"))),
         "{} / {}".format(signed(raw["outline_offset"]), signed(thesis["outline_offset"]))),
        ("mean IoU with the digitised plots: cells / plots", "{} / {}".format(
            f3(step(gen, "raw", "iou")), f3(gen.get("iou"))),
         "{} / {}".format(f3(raw["iou"]), f3(thesis["iou"]))),
        ("plots", ours["plots"], thesis["plots"]),
        ("ground-truth plots kept (points; polygons)",
         "{}/{}; {}/{}".format(ours["gt_points_in_a_plot"], ours["gt_points"],
                               ours["gt_polygons_intersected"], ours["gt_polygons"]),
         "{}/{}; {}/{}".format(thesis["gt_points_in_a_plot"], thesis["gt_points"],
                               thesis["gt_polygons_intersected"], thesis["gt_polygons"])),
        ("ground-truth plots lost", ours["lost"], thesis["lost"]),
        ("thesis's aligned footprints found (identical outline)",
         "{}/{} ({} %)".format(found["found"], found["thesis"], found["percent"]), ""),
        ("  the same current footprint aligned (any outline)",
         "{}/{} ({} %)".format(found["same_footprint"], found["thesis"],
                               found["same_footprint_percent"]), ""),
    ] + cr.footprint_rows(fp, lod2, ours["plots"], (found["thesis"], "")) + [
        ("roof ends on shared edges", cr.ends_text(report["ends"]), ""),
        ("CityJSON 2.0.2 schema", cr.schema_text(report["cityjson"]), ""),
    ] + cr.time_rows(report["seconds"])


def main(out, shared_data="../shared/data"):
    report = build(out, shared_data)
    cr.write(out, report, rows(report))


if __name__ == "__main__":
    main(*sys.argv[1:])
