#!/usr/bin/env python3
############################################################################
#
# MODULE:       v.histo.align
# AUTHOR(S):    histo developers
# PURPOSE:      Finds the current building footprints that already stood at
#               the date of a historical map, by one-to-many alignment with
#               its building plots (Morlighem 2021, Section 3.3.1)
# COPYRIGHT:    (C) 2026 the histo developers
#
#               This program is free software under the GNU General Public
#               License (>=v2). Read the file COPYING that comes with GRASS
#               for details.
#
############################################################################

# %module
# % description: Finds the current building footprints that already stood at the date of a historical map, by one-to-many alignment with its building plots.
# % keyword: vector
# % keyword: building
# % keyword: footprint
# % keyword: alignment
# % keyword: histo
# %end
# %option G_OPT_V_INPUT
# % description: Building plots of the historical map (areas), e.g. from v.histo.generalize
# %end
# %option G_OPT_V_INPUT
# % key: footprints
# % description: Current building footprints (areas) with a construction year
# %end
# %option G_OPT_DB_COLUMN
# % key: year_column
# % label: Column of the footprints' construction year
# % description: Default bouwjaar (BAG), else oorspronkelijkbouwjaar (3D BAG) when the map has no bouwjaar
# % answer: bouwjaar
# %end
# %option
# % key: year
# % type: integer
# % required: yes
# % description: Year of the map: footprints built before it are candidates
# %end
# %option
# % key: buffer
# % type: double
# % required: no
# % label: Distance each plot grows by before matching (map units)
# % description: Default 10; or give resolution= and k=
# % guisection: Matching
# %end
# %option
# % key: resolution
# % type: double
# % required: no
# % multiple: yes
# % key_desc: map,footprints
# % description: Pixel sizes of the two maps: buffer = k * sqrt(map^2 + footprints^2) (Ying et al. 2011)
# % guisection: Matching
# %end
# %option
# % key: k
# % type: double
# % required: no
# % description: Factor of the buffer from resolution=
# % guisection: Matching
# %end
# %option
# % key: overlap
# % type: double
# % label: Similarity threshold, in (0, 1]
# % description: A footprint matches a plot when area(footprint within the buffered plot) / min(area footprint, area buffered plot) reaches it
# % answer: 0.6
# % guisection: Matching
# %end
# %option
# % key: shift
# % type: double
# % required: no
# % label: Largest offset of the map against the footprints to correct (map units; default: no correction)
# % description: Each plot is matched at the place where the plots and footprints of its neighbourhood fit best
# % guisection: Offset
# %end
# %option
# % key: shift_window
# % type: double
# % description: Neighbourhood of a plot that estimates its offset: plots and footprints this far around it (map units)
# % answer: 150
# % guisection: Offset
# %end
# %option G_OPT_V_OUTPUT
# % description: Aligned footprints: the footprints' columns plus plot and similarity (and dx, dy with shift=)
# %end
# %option G_OPT_V_OUTPUT
# % key: unmatched
# % required: no
# % description: Candidate footprints that matched no plot, with the best similarity they reached
# %end
# %option G_OPT_F_OUTPUT
# % key: report
# % required: no
# % description: JSON file with the counts, the options and the offset of every plot
# %end
# %flag
# % key: i
# % description: Also footprints built in the map's year (year <= map year, as the thesis)
# %end
# %flag
# % key: g
# % description: Print the counts in shell script style (key=value)
# %end
# %rules
# % exclusive: buffer, resolution
# % collective: resolution, k
# %end

import json
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


FALLBACK_YEAR_COLUMN = "oorspronkelijkbouwjaar"


def no_areas(grassio, name, key, what):
    """The InputError for a map that holds no areas."""
    from reconstruction.core.errors import InputError

    counts = grassio.vector_counts(name)
    return InputError("Vector map <{}> given as {}= has no areas (it holds {}): {} must be "
                      "areas".format(name, key, ", ".join(
                          "{} {}".format(counts.get(k, 0), k)
                          for k in ("points", "lines", "boundaries", "areas")), what))


def year_column(columns, wanted, given, name):
    """The footprints' year column: ``wanted`` (any case), or the 3D BAG's name for the default."""
    from reconstruction.core.errors import InputError

    names = {c.lower(): c for c in columns if c != "cat"}
    for candidate in [wanted] + ([] if given else [FALLBACK_YEAR_COLUMN]):
        if candidate.lower() in names:
            return names[candidate.lower()]
    raise InputError("Footprints <{}> have no year column <{}>{}; columns: {}".format(
        name, wanted, "" if given else " (nor <{}>)".format(FALLBACK_YEAR_COLUMN),
        ", ".join(sorted(names.values())) or "none (no attribute table)"))


def parse_config(options, flags):
    """The AlignmentConfig of the options (InputError on bad ones)."""
    from reconstruction.align import stage as alignment
    from reconstruction.core import options as opts

    if options["resolution"]:
        buffer = alignment.buffer_from_resolution(
            opts.parse_list(options["resolution"], float), opts.parse_number(options["k"], "k"))
    else:
        buffer = opts.parse_number(options["buffer"] or 10, "buffer")
    return alignment.AlignmentConfig(
        year=opts.parse_number(options["year"], "year", cast=int), buffer=buffer,
        overlap=opts.parse_number(options["overlap"], "overlap"), include_year=flags["i"],
        shift=opts.parse_number(options["shift"] or 0, "shift"),
        shift_window=opts.parse_number(options["shift_window"], "shift_window", minimum=0))


def read_footprints(grassio, name, wanted_column, config):
    """The footprints' table, year column, years and geometries (None where not a candidate:
    only the candidates' geometry is read)."""
    import numpy as np

    from reconstruction.align import stage as alignment

    reading = grassio.doing("reading the footprints <{}>".format(name))
    with reading:
        columns = grassio.read_table(name)
    grassio.require_projected()      # its answer came meanwhile
    column = year_column(columns, wanted_column, wanted_column != "bouwjaar", name)
    cats = columns["cat"]
    years = alignment.construction_years(columns[column], column, ids=cats)
    candidate = alignment.candidate_mask(years, config)[0]
    footprints = [None] * len(cats)
    with reading:
        if candidate.any():
            geoms, found = grassio.read_areas(
                name, cats=[cats[i] for i in np.flatnonzero(candidate)], table=False)
            row = {c: i for i, c in enumerate(cats)}
            for geom, cat in zip(geoms, found["cat"]):
                footprints[row[cat]] = geom
        if not any(g is not None for g in footprints) and \
                grassio.vector_counts(name).get("areas", 0) == 0:
            raise no_areas(grassio, name, "footprints", "footprints")
    return columns, column, years, footprints


def write_footprints(grassio, output, footprints, columns, indices, extra, title):
    """Footprints ``indices`` with their own categories and columns, plus ``extra`` columns."""
    from reconstruction.core import contract

    own = {contract.PLOT.lower(), contract.SIMILARITY.lower(), "cat"} | {k.lower() for k in extra}
    table = {k: [values[i] for i in indices] for k, values in columns.items()
             if k.lower() not in own}
    table.update(extra)
    with grassio.doing("writing <{}>".format(output)):
        grassio.write_areas(output, [footprints[i] for i in indices], table,
                            cats=[columns["cat"][i] for i in indices], title=title,
                            history=True)


def main(options, flags):
    from reconstruction import grassio

    start = time.perf_counter()
    grassio.register_cleanup()
    # the plots (their categories only) are exported while we go on
    plots_job = grassio.start_read_areas(options["input"], table=False)
    grassio.prefetch_checks()
    import numpy as np

    from reconstruction.align import stage as alignment
    from reconstruction.core import contract
    from reconstruction.core import safefile

    grassio.check_outputs(options, vectors=("output", "unmatched"), files=("report",))
    config = parse_config(options, flags)
    name = options["footprints"]
    columns, column, years, footprints = read_footprints(
        grassio, name, options["year_column"], config)
    with grassio.doing("reading the plots <{}>".format(options["input"])):
        plots, plot_columns = grassio.finish_read_areas(plots_job)
    if not plots:
        raise no_areas(grassio, options["input"], "input", "plots")
    read = time.perf_counter()
    result = alignment.align(plots, plot_columns["cat"], footprints, years, config)
    report = result.report
    matched = time.perf_counter()

    if report.without_year:
        gs.warning(_("{} of {} footprints have no year in <{}> (NULL, empty or a placeholder "
                     "such as 9999) and were left out").format(
                         report.without_year, report.footprints, column))
    if not report.candidates:
        gs.warning(_("No footprint of <{}> was built before {}").format(name, options["year"]))
    if report.repaired:
        gs.warning(_("{} invalid geometries repaired").format(report.repaired))
    extra = {contract.PLOT: result.plot.tolist(),
             contract.SIMILARITY: np.round(result.similarity, 4).tolist()}
    if result.shifts is not None:
        row = {c: i for i, c in enumerate(plot_columns["cat"])}
        rows = [row[c] for c in result.plot.tolist()]
        extra["dx"] = np.round(result.shifts.dx[rows], 2).tolist()
        extra["dy"] = np.round(result.shifts.dy[rows], 2).tolist()
    write_footprints(grassio, options["output"], footprints, columns, result.aligned.tolist(),
                     extra, "Footprints of <{}> standing on <{}> in {} (v.histo.align)".format(
                         name, options["input"], options["year"]))
    if options["unmatched"]:
        write_footprints(grassio, options["unmatched"], footprints, columns,
                         result.unmatched.tolist(),
                         {contract.SIMILARITY: np.round(result.best_similarity, 4).tolist()},
                         "Candidate footprints of <{}> matching no plot".format(name))
    if options["report"]:
        with safefile.replacing(options["report"]) as f:
            json.dump(alignment.report_json(result, config, plot_columns["cat"]), f, indent=2)

    gs.verbose(_("Timing (s): read {:.2f}, align {:.2f}, write {:.2f}").format(
        read - start, matched - read, time.perf_counter() - matched))
    gs.message(_("{} of {} candidate footprints (built before {}) aligned with {} of {} plots "
                 "into <{}>{}").format(
                     report.aligned, report.candidates, options["year"], report.plots_matched,
                     report.plots, options["output"],
                     "; {} plots matched at a shifted place".format(report.shifted_plots)
                     if result.shifts is not None else ""))
    if flags["g"]:
        for key, value in report.counts().items():
            print("{}={}".format(key, value))
    return 0


if __name__ == "__main__":
    options, flags = gs.parser()
    find_core()
    from reconstruction import grassio

    sys.exit(grassio.run_main(main, options, flags))
