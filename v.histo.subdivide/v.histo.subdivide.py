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
# % description: Footprints (areas) with columns plot, pm_case, source, area
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
import signal
import sys
import time

# Ctrl-C before the module runs (while Python loads it, while GRASS parses its
# options): one error line, as during its work (grassio.run_main takes over)
signal.signal(signal.SIGINT, lambda *_: sys.exit("ERROR: Interrupted while starting"))

import grass.script as gs  # noqa: E402


def find_core():
    """Put the histo core library on sys.path (installed in etc/histo, or the checkout)."""
    here = os.path.dirname(os.path.realpath(__file__))
    for base in (os.path.join(os.path.dirname(here), "etc", "histo"), os.path.dirname(here)):
        if os.path.isfile(os.path.join(base, "reconstruction", "__init__.py")):
            sys.path.insert(0, base)
            return


def _aligned_columns(columns, indices, own):
    """The aligned footprints' own columns, one value per output footprint (NULL for 2PM)."""
    out = {}
    for name, values in columns.items():
        if name.lower() not in own:
            out[name] = [values[i] if i >= 0 else None for i in indices]
    return out


def read_plots(grassio, name):
    """The plots with a category, and their categories."""
    plots, columns = grassio.read_features(name, "area")
    keep = [i for i, (g, c) in enumerate(zip(plots, columns["cat"]))
            if g is not None and c is not None]
    return [plots[i] for i in keep], [int(columns["cat"][i]) for i in keep]


def read_aligned(grassio, name, plot_column):
    """Aligned footprints, the plot of each (None without a plot column) and their columns."""
    aligned, columns = grassio.read_features(name, "area")
    names = {k.lower(): k for k in columns}
    if plot_column not in names:
        gs.message(_("Aligned map <{}> has no {} column: each aligned footprint goes to the plot "
                     "it overlaps most").format(name, plot_column))
        return aligned, None, columns
    from reconstruction.core.options import integer_column

    return aligned, integer_column(columns[names[plot_column]], plot_column, name), columns


def report(rep, aligned, calibrating):
    """Warnings and messages about what the subdivision repaired, clipped and measured."""
    if rep.plots.repaired:
        gs.warning(_("{} invalid plots repaired (make_valid)").format(rep.plots.repaired))
    if rep.plots.skipped:
        gs.warning(_("{} plots without area skipped").format(rep.plots.skipped))
    if rep.plots.overlapping_pairs:
        gs.warning(_("{} pairs of overlapping plots: the shared area ({:.2f} square map units) "
                     "went to the larger plot of each pair").format(
                         rep.plots.overlapping_pairs, rep.plots.overlap_area))
    if not aligned:
        return
    if rep.aligned.repaired:
        gs.warning(_("{} invalid aligned footprints repaired").format(rep.aligned.repaired))
    if rep.aligned.clipped:
        gs.warning(_("{} aligned footprints overlapping earlier ones were clipped").format(
            rep.aligned.clipped))
    if rep.aligned_without_plot:
        gs.warning(_("{} aligned footprints without a plot left out").format(
            rep.aligned_without_plot))
    if rep.generated_dropped or rep.generated_clipped:
        gs.message(_("Generated footprints overlapping aligned ones: {} clipped, "
                     "{} dropped").format(rep.generated_clipped, rep.generated_dropped))
    if calibrating and rep.calibrated:
        gs.message(_("Calibrated from {} aligned footprints: length={:.2f},{:.2f} "
                     "depth={:.2f},{:.2f}").format(rep.calibration_samples,
                                                  *(rep.length + rep.depth)))
    elif calibrating:
        gs.warning(_("Too few aligned footprints on a street ({}) to calibrate: length= and depth= "
                     "kept").format(rep.calibration_samples))


def main(options, flags):
    from reconstruction.core import contract
    from reconstruction import grassio
    from reconstruction.subdivide import stage as subdivision
    from reconstruction.core.errors import InputError
    from reconstruction.core.options import parse_number, parse_range

    grassio.register_cleanup()
    grassio.check_outputs(options, vectors=("output",))
    plots_name, output, aligned_name = options["input"], options["output"], options["aligned"]
    length = parse_range(options["length"], "length", positive=True, allow_zero=False)
    depth = parse_range(options["depth"], "depth", positive=True, allow_zero=False)
    area_threshold = None
    if options["area_threshold"]:
        area_threshold = parse_number(options["area_threshold"], "area_threshold", minimum=0)
    seed = int(options["seed"] or 1)
    grassio.require_projected()
    for name, what in ((plots_name, "plots"), (aligned_name, "aligned footprints")):
        if name:
            grassio.require_vector(name)
            if grassio.vector_counts(name).get("areas", 0) == 0:
                raise InputError(_("Vector map <{}> has no areas: {} must be areas").format(
                    name, what))

    start = time.perf_counter()
    with grassio.doing("reading the plots <{}>".format(plots_name)):
        plots, cats = read_plots(grassio, plots_name)
    if not plots:
        raise InputError(_("Vector map <{}> has no areas with a category").format(plots_name))
    aligned, aligned_plots, aligned_columns = None, None, {}
    if aligned_name:
        with grassio.doing("reading the aligned footprints <{}>".format(aligned_name)):
            aligned, aligned_plots, aligned_columns = read_aligned(grassio, aligned_name,
                                                                   contract.PLOT)
    read = time.perf_counter()
    gs.message(_("Subdividing {} plots...").format(len(plots)))
    result = subdivision.subdivide(
        plots, cats, length=length, depth=depth, area_threshold=area_threshold, seed=seed,
        decompose=not flags["c"], aligned=aligned, aligned_plots=aligned_plots,
        calibrate_ranges=flags["a"])
    core = time.perf_counter()
    report(result.report, bool(aligned_name), flags["a"])
    if not result.geometries:
        raise InputError(_("No footprints: every plot was skipped"))

    columns = {
        contract.PLOT: result.plot,
        contract.CASE: result.case,
        contract.SOURCE: result.source,
        contract.AREA: [round(a, 3) for a in result.area],
    }
    own = {"cat"} | set(columns)
    columns.update(_aligned_columns(aligned_columns, result.aligned, own))
    with grassio.doing("writing the footprints <{}>".format(output)):
        grassio.write_areas(output, result.geometries, columns,
                            title="Footprints of <{}> (v.histo.subdivide)".format(plots_name))
        gs.vector_history(output)
    gs.verbose(_("Timing (s): read {:.2f}, subdivide {:.2f}, write {:.2f}").format(
        read - start, core - read, time.perf_counter() - core))
    counts = {c: result.case.count(c) for c in sorted(set(result.case))}
    gs.message(_("{} footprints written to <{}> ({} generated, {} aligned); by case: {}").format(
        len(result.geometries), output, result.report.generated,
        len(result.geometries) - result.report.generated,
        ", ".join("{}: {}".format(c, n) for c, n in counts.items())))
    return 0


if __name__ == "__main__":
    options, flags = gs.parser()
    find_core()
    from reconstruction import grassio

    sys.exit(grassio.run_main(main, options, flags))
