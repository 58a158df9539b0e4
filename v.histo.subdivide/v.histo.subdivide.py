#!/usr/bin/env python3
############################################################################
#
# MODULE:       v.histo.subdivide
# AUTHOR(S):    histo developers
# PURPOSE:      Splits building plots into individual building footprints
#               by 2D procedural modelling (Morlighem 2021, Section 3.3)
# COPYRIGHT:    (C) 2026 the histo developers
#
#               This program is free software under the GNU General Public
#               License (>=v2). Read the file COPYING that comes with GRASS
#               for details.
#
############################################################################

# %module
# % description: Splits building plots into individual building footprints by 2D procedural modelling.
# % keyword: vector
# % keyword: building
# % keyword: footprint
# % keyword: procedural modelling
# % keyword: histo
# %end
# %option G_OPT_V_INPUT
# % description: Building plots (areas), e.g. from v.histo.generalize
# %end
# %option G_OPT_V_OUTPUT
# % description: Footprints (areas) with columns plot, case, source, area
# %end
# %option G_OPT_V_INPUT
# % key: aligned
# % required: no
# % label: Aligned current footprints (areas) kept as they are
# % description: With a plot column (as v.histo.align writes them); without it, each goes to the plot it overlaps most
# % guisection: Aligned
# %end
# %option
# % key: length
# % type: double
# % required: no
# % multiple: yes
# % key_desc: min,max
# % answer: 5,8
# % description: Range of facade lengths (map units)
# %end
# %option
# % key: depth
# % type: double
# % required: no
# % multiple: yes
# % key_desc: min,max
# % answer: 12,16
# % description: Range of building depths (map units)
# %end
# %option
# % key: area_threshold
# % type: double
# % required: no
# % label: Plots (and convex parts) smaller than this are one building (square map units)
# % description: Default: mean area of the aligned footprints when given, else 100
# %end
# %option
# % key: seed
# % type: integer
# % required: no
# % answer: 1
# % description: Seed of the random facade lengths and depths (same seed, same footprints)
# %end
# %flag
# % key: c
# % description: Do not decompose concave plots into convex parts (case 5); footprints may then be concave
# %end
# %flag
# % key: a
# % description: Calibrate facade length and depth ranges from the aligned footprints
# % guisection: Aligned
# %end
# %rules
# % requires: -a, aligned
# %end

import os
import sys
import time

import grass.script as gs


def find_core():
    """Put the histo core library on sys.path (installed in etc/histo, or the checkout)."""
    here = os.path.dirname(os.path.realpath(__file__))
    for base in (os.path.join(os.path.dirname(here), "etc", "histo"), os.path.dirname(here)):
        if os.path.isfile(os.path.join(base, "reconstruction", "__init__.py")):
            sys.path.insert(0, base)
            return


OWN_COLUMNS = ("cat", "plot", "case", "source", "area")


def _aligned_columns(columns, indices):
    """The aligned footprints' own columns, one value per output footprint (NULL for 2PM)."""
    out = {}
    for name, values in columns.items():
        if name.lower() in OWN_COLUMNS:
            continue
        out[name] = [values[i] if i >= 0 else None for i in indices]
    return out


def main():
    from reconstruction import grassio, subdivision

    grassio.register_cleanup()
    options, flags = OPTIONS, FLAGS
    plots_name = options["input"]
    output = options["output"]
    aligned_name = options["aligned"]

    try:
        length = subdivision.check_range(options["length"], "length")
        depth = subdivision.check_range(options["depth"], "depth")
    except ValueError as err:
        gs.fatal(str(err))
    area_threshold = None
    if options["area_threshold"]:
        area_threshold = float(options["area_threshold"])
        if area_threshold < 0:
            gs.fatal(_("area_threshold= must not be negative, got {}").format(area_threshold))
    seed = int(options["seed"]) if options["seed"] else 1

    grassio.require_projected()
    grassio.require_vector(plots_name)
    if grassio.vector_counts(plots_name).get("areas", 0) == 0:
        gs.fatal(_("Vector map <{}> has no areas: plots must be areas").format(plots_name))
    if aligned_name:
        grassio.require_vector(aligned_name)
        if grassio.vector_counts(aligned_name).get("areas", 0) == 0:
            gs.fatal(_("Vector map <{}> has no areas: aligned footprints must be areas").format(
                aligned_name))

    start = time.perf_counter()
    plots, plot_columns = grassio.read_features(plots_name, "area")
    cats = plot_columns["cat"]
    keep = [i for i, g in enumerate(plots) if g is not None and cats[i] is not None]
    plots = [plots[i] for i in keep]
    cats = [int(cats[i]) for i in keep]
    if not plots:
        gs.fatal(_("Vector map <{}> has no areas with a category").format(plots_name))

    aligned, aligned_plots, aligned_columns = None, None, {}
    if aligned_name:
        aligned, aligned_columns = grassio.read_features(aligned_name, "area")
        names = {k.lower(): k for k in aligned_columns}
        if "plot" in names:
            aligned_plots = [None if v is None else int(v) for v in aligned_columns[names["plot"]]]
        else:
            gs.message(_("Aligned map <{}> has no plot column: each aligned footprint goes to "
                         "the plot it overlaps most").format(aligned_name))

    read = time.perf_counter()
    gs.message(_("Subdividing {} plots...").format(len(plots)))
    result = subdivision.subdivide(
        plots, cats, length=length, depth=depth, area_threshold=area_threshold, seed=seed,
        decompose=not flags["c"], aligned=aligned, aligned_plots=aligned_plots,
        calibrate_ranges=flags["a"])
    report = result.report
    core = time.perf_counter()

    if report["repaired"]:
        gs.warning(_("{} invalid plots repaired (make_valid)").format(report["repaired"]))
    if report["skipped"]:
        gs.warning(_("{} plots without area skipped").format(report["skipped"]))
    if report["overlapping_pairs"]:
        gs.warning(_("{} pairs of overlapping plots: the shared area ({:.2f} square map units) "
                     "went to the larger plot of each pair").format(
                         report["overlapping_pairs"], report["overlap_area"]))
    if aligned_name:
        if report.get("aligned_repaired"):
            gs.warning(_("{} invalid aligned footprints repaired").format(
                report["aligned_repaired"]))
        if report.get("aligned_clipped"):
            gs.warning(_("{} aligned footprints overlapping earlier ones were clipped").format(
                report["aligned_clipped"]))
        if report.get("aligned_without_plot"):
            gs.warning(_("{} aligned footprints without a plot left out").format(
                report["aligned_without_plot"]))
        if report["generated_dropped"] or report["generated_clipped"]:
            gs.message(_("Generated footprints overlapping aligned ones: {} clipped, "
                         "{} dropped").format(
                report["generated_clipped"], report["generated_dropped"]))
        if flags["a"]:
            if report["calibrated"]:
                gs.message(_("Calibrated from {} aligned footprints: length={:.2f},{:.2f} "
                             "depth={:.2f},{:.2f}").format(report["calibration_samples"],
                                                          *(report["length"] + report["depth"])))
            else:
                gs.warning(_("Too few aligned footprints on a street ({}) to calibrate: "
                             "length= and depth= kept").format(
                                 report.get("calibration_samples", 0)))
    if not result.geometries:
        gs.fatal(_("No footprints: every plot was skipped"))

    columns = {
        "plot": result.plot,
        "case": result.case,
        "source": result.source,
        "area": [round(a, 3) for a in result.area],
    }
    if aligned_name:
        columns.update(_aligned_columns(aligned_columns, result.aligned))
    grassio.write_areas(output, result.geometries, columns,
                        title="Footprints of <{}> (v.histo.subdivide)".format(plots_name))
    gs.vector_history(output)
    gs.verbose(_("Timing (s): read {:.2f}, subdivide {:.2f}, write {:.2f}").format(
        read - start, core - read, time.perf_counter() - core))
    counts = {c: result.case.count(c) for c in sorted(set(result.case))}
    gs.message(_("{} footprints written to <{}> ({} generated, {} aligned); by case: {}").format(
        len(result.geometries), output, report["generated"],
        len(result.geometries) - report["generated"],
        ", ".join("{}: {}".format(c, n) for c, n in counts.items())))
    return 0


if __name__ == "__main__":
    OPTIONS, FLAGS = gs.parser()
    find_core()
    sys.exit(main())
