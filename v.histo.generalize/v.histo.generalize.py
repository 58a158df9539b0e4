#!/usr/bin/env python3
############################################################################
#
# MODULE:       v.histo.generalize
# AUTHOR(S):    histo developers
# PURPOSE:      Building plots from a classified historical map: vectorise,
#               generalise (alpha shape, buffered lines, simplification) and
#               measure their shape and quality against reference data
# COPYRIGHT:    (C) 2026 the histo developers
#
#               This program is free software under the GNU General Public
#               License (>=v2). Read the file COPYING that comes with GRASS
#               for details.
#
############################################################################

# %module
# % description: Generalises raw building plots (areas, or a class of a classified map) into simple plot polygons with the alpha-shape and buffered-lines methods, and measures them.
# % keyword: vector
# % keyword: generalization
# % keyword: building
# % keyword: historical map
# % keyword: histo
# %end
# %option G_OPT_V_INPUT
# % required: no
# % label: Raw building plots (vector map of areas)
# % description: Or give raster= and class=
# % guisection: Input
# %end
# %option G_OPT_R_INPUT
# % key: raster
# % required: no
# % description: Classified raster map (CELL) whose class= is vectorised into raw plots
# % guisection: Input
# %end
# %option
# % key: class
# % type: integer
# % description: Category of the building class in raster=
# % guisection: Input
# %end
# %option G_OPT_V_OUTPUT
# % description: Generalised building plots (areas with the method used and the shape metrics)
# % guisection: Output
# %end
# %option
# % key: method
# % type: string
# % multiple: yes
# % options: alpha,lines,simplify,douglas
# % description: Generalisation steps, run in this order
# % descriptions: alpha;alpha shape of points sampled in the plot (Arteaga 2013);lines;buffered lines (Commandeur 2012);simplify;topology-preserving simplification (tolerance=);douglas;Douglas-Peucker simplification (tolerance=)
# % answer: alpha,lines
# % guisection: Method
# %end
# %option
# % key: alpha
# % type: double
# % description: Alpha radius of the alpha-shape step (map units)
# % answer: 12
# % guisection: Method
# %end
# %option
# % key: distance
# % type: double
# % description: Epsilon distance of the buffered-lines step (map units)
# % answer: 5
# % guisection: Method
# %end
# %option
# % key: angle
# % type: double
# % description: Epsilon angle of the buffered-lines step (degrees, 0-180)
# % answer: 180
# % guisection: Method
# %end
# %option
# % key: tolerance
# % type: double
# % description: Tolerance of the simplify and douglas steps (map units)
# % answer: 1
# % guisection: Method
# %end
# %option
# % key: min_area
# % type: double
# % description: Raw areas smaller than this are dropped before generalising (square map units)
# % answer: 20
# % guisection: Method
# %end
# %option
# % key: seed
# % type: integer
# % description: Seed of the random samplings tried when the regular one fails
# % answer: 1
# % guisection: Method
# %end
# %option G_OPT_F_OUTPUT
# % key: metrics
# % required: no
# % description: CSV file with the shape metrics summed and averaged after each step
# % guisection: Assessment
# %end
# %option G_OPT_V_INPUT
# % key: gt_points
# % required: no
# % label: Ground-truth points, one in each true building plot
# % description: Gives precision, recall and F-score
# % guisection: Assessment
# %end
# %option G_OPT_V_INPUT
# % key: gt_polygons
# % required: no
# % label: Hand-digitised reference plots (areas)
# % description: Gives the turning-function distance and the buffer shape similarity
# % guisection: Assessment
# %end
# %option
# % key: gt_buffer
# % type: double
# % description: Buffer distance of the buffer shape similarity (map units)
# % answer: 2
# % guisection: Assessment
# %end
# %option G_OPT_F_OUTPUT
# % key: report
# % required: no
# % description: JSON file with all assessment figures
# % guisection: Assessment
# %end
# %flag
# % key: r
# % description: Make lines close to the dominant direction parallel or perpendicular to it
# % guisection: Method
# %end
# %flag
# % key: g
# % description: Print the assessment figures in shell script style (key=value)
# % guisection: Assessment
# %end
# %rules
# % required: input,raster
# % exclusive: input,raster
# % requires: raster,class
# %end

import csv
import json
import os
import sys

import grass.script as gs


def find_core():
    """Put the histo core library on sys.path (installed in etc/histo, or the checkout)."""
    here = os.path.dirname(os.path.realpath(__file__))
    for base in (os.path.join(os.path.dirname(here), "etc", "histo"), os.path.dirname(here)):
        if os.path.isfile(os.path.join(base, "reconstruction", "__init__.py")):
            sys.path.insert(0, base)
            return


def _positive(key, allow_zero=False):
    value = float(options[key])
    if value < 0 or (value == 0 and not allow_zero):
        gs.fatal(_("Option {}= must be {} (got {})").format(
            key, "zero or more" if allow_zero else "positive", options[key]))
    return value


def _require_feature(name, kind, key):
    """Fail unless vector map ``name`` holds features of ``kind`` (areas or points)."""
    from reconstruction import grassio

    grassio.require_vector(name)
    counts = grassio.vector_counts(name)
    if counts.get(kind, 0) == 0:
        held = ", ".join("{} {}".format(counts.get(k, 0), k)
                         for k in ("points", "lines", "boundaries", "centroids", "areas"))
        gs.fatal(_("Vector map <{}> given as {}= has no {} (it holds {}): give a map of {}").format(
            name, key, kind, held, kind))


def _raster_plots(raster, category):
    """Vectorise the cells of ``category`` into a temporary map of areas."""
    from reconstruction import grassio

    grassio.require_raster(raster)
    if gs.raster_info(raster)["datatype"] != "CELL":
        gs.fatal(_("Raster map <{}> is not a CELL (integer) map: give a classified map").format(raster))
    stats = gs.read_command("r.stats", flags="cn", input=raster, quiet=True)
    counts = {}
    for line in stats.splitlines():
        parts = line.split()
        if len(parts) == 2:
            counts[int(parts[0])] = int(parts[1])
    if counts.get(category, 0) == 0:
        gs.fatal(_("Raster map <{}> has no cell of class {} in the current region (classes: {})").format(
            raster, category, ", ".join(str(k) for k in sorted(counts)) or "none"))
    mask = grassio.temp_map("raster", "building")
    gs.mapcalc("{} = if({} == {}, 1, null())".format(mask, raster, category), quiet=True)
    areas = grassio.temp_map("vector", "raw_plots")
    gs.run_command("r.to.vect", input=mask, output=areas, type="area", quiet=True)
    return areas


def _step_rows(steps):
    """One row of summary statistics of the Table 3.1 metrics per step."""
    from reconstruction import shape_metrics

    rows = []
    for name, polygons in steps:
        row = {"step": name}
        row.update(shape_metrics.summarise_metrics(shape_metrics.plot_metrics(polygons)))
        rows.append(row)
    return rows


def _write_metrics_csv(path, rows):
    with open(path, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        writer.writeheader()
        for row in rows:
            writer.writerow({k: (round(v, 6) if isinstance(v, float) else v) for k, v in row.items()})


def main():
    from collections import Counter

    from reconstruction import assessment, generalization, grassio, shape_metrics

    grassio.register_cleanup()
    grassio.require_projected()

    output = options["output"]
    methods = [m for m in options["method"].split(",") if m]
    alpha = _positive("alpha")
    distance = _positive("distance")
    angle = float(options["angle"])
    if not 0 <= angle <= 180:
        gs.fatal(_("Option angle= must lie between 0 and 180 degrees (got {})").format(options["angle"]))
    tolerance = _positive("tolerance")
    min_area = _positive("min_area", allow_zero=True)
    gt_buffer = _positive("gt_buffer")
    seed = int(options["seed"])
    for key in ("metrics", "report"):
        grassio.require_new_file(options[key], key)
    if options["gt_points"]:
        _require_feature(options["gt_points"], "points", "gt_points")
    if options["gt_polygons"]:
        _require_feature(options["gt_polygons"], "areas", "gt_polygons")

    if options["input"]:
        source_map = options["input"]
        _require_feature(source_map, "areas", "input")
    else:
        source_map = _raster_plots(options["raster"], int(options["class"]))

    geoms, columns = grassio.read_features(source_map, "area")
    polygons, index = generalization.explode_plots(geoms)
    if not polygons:
        gs.fatal(_("No area with a category in <{}>: nothing to generalise").format(source_map))
    source_cats = [columns["cat"][k] for k in index]
    keep = [k for k, p in enumerate(polygons) if p.area >= min_area]
    dropped = len(polygons) - len(keep)
    if not keep:
        gs.fatal(_("All {} raw areas are smaller than min_area={}: nothing to generalise").format(
            len(polygons), min_area))
    polygons = [polygons[k] for k in keep]
    source_cats = [source_cats[k] for k in keep]
    if dropped:
        gs.verbose(_("{} raw areas smaller than {} dropped").format(dropped, min_area))

    gs.message(_("Generalising {} plots ({})...").format(len(polygons), ", ".join(methods)))
    result = generalization.generalize_plots(
        polygons, methods, alpha=alpha, distance=distance, angle=angle,
        orthogonal=flags["r"], tolerance=tolerance, seed=seed)
    for step, count in result.fallbacks.items():
        gs.warning(_("Step {}: {} plots needed a fallback method (see column 'method')").format(
            step, count))

    plot_metrics = shape_metrics.plot_metrics(result.plots)
    out_columns = {"source": source_cats} if options["input"] else {}
    out_columns["method"] = result.methods
    out_columns.update({k: plot_metrics[k] for k in shape_metrics.METRICS})
    grassio.write_features(output, result.plots, out_columns,
                           title="Generalised building plots ({})".format(", ".join(methods)))
    gs.vector_history(output)

    figures = {"plots": len(result.plots), "raw_areas": len(polygons) + dropped,
               "dropped_small": dropped, "methods": dict(Counter(result.methods)),
               "fallbacks": result.fallbacks}
    figures["steps"] = _step_rows(result.steps)
    if options["metrics"]:
        _write_metrics_csv(options["metrics"], figures["steps"])
    if options["gt_points"]:
        xy, _cols = grassio.read_points(options["gt_points"])
        scores = assessment.point_detection_scores(result.plots, xy)
        figures.update({"precision": scores.precision, "recall": scores.recall,
                        "f_score": scores.f_score, "gt_points": len(xy)})
    if options["gt_polygons"]:
        ref_geoms, _cols = grassio.read_features(options["gt_polygons"], "area")
        refs, _idx = generalization.explode_plots(ref_geoms)
        scores = shape_metrics.shape_scores(result.plots, refs, gt_buffer)
        figures.update({"gt_polygons": scores["references"], "matched": scores["matched"],
                        "turning_distance": scores["turning_distance"],
                        "buffer_similarity": scores["buffer_similarity"],
                        "turning_distances": scores["turning_distances"],
                        "buffer_similarities": scores["buffer_similarities"]})
    if options["report"]:
        with open(options["report"], "w") as f:
            json.dump(figures, f, indent=2)
    scalars = {k: v for k, v in figures.items()
               if isinstance(v, (int, float)) or v is None}
    if flags["g"]:
        for key, value in scalars.items():
            print("{}={}".format(key, "" if value is None else value))
    else:
        gs.message(", ".join("{} {}".format(k, round(v, 4) if isinstance(v, float) else v)
                             for k, v in scalars.items()))
    return 0


if __name__ == "__main__":
    options, flags = gs.parser()
    find_core()
    sys.exit(main())
