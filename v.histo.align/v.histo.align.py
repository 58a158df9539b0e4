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


def main(options, flags):
    from reconstruction import grassio

    start = time.perf_counter()
    grassio.register_cleanup()
    # the plots (their categories only) are exported while we go on
    plots_job = grassio.start_read_areas(options["input"], table=False)
    grassio.prefetch_checks()
    from reconstruction import align
    from reconstruction.core import safefile

    grassio.check_outputs(options, vectors=("output", "unmatched"), files=("report",),
                          inputs={"vector": ("input", "footprints")})
    config = align.read_config(options, flags)
    reading = grassio.doing("reading the footprints <{}>".format(config.footprints))
    with reading:
        table = grassio.read_table(config.footprints)
    grassio.require_projected()      # its answer came meanwhile

    def read_footprints(cats):
        """Only the candidates' geometries are read."""
        with reading:
            geoms, found = grassio.read_areas(config.footprints, cats=cats, table=False)
        return geoms, found["cat"]

    def read_plots():
        with grassio.doing("reading the plots <{}>".format(config.plots)):
            plots, columns = grassio.finish_read_areas(plots_job)
        return plots, columns["cat"]

    result = align.run(align.AlignmentInputs(table, read_footprints, read_plots,
                                             grassio.vector_counts), config)
    with safefile.together() as files:      # the report appears with the maps, or not
        if config.report_file:
            with files.open(config.report_file) as f:
                json.dump(result.report_json, f, indent=2)
        for out in (result.output, result.unmatched):
            if out is not None:
                with grassio.doing("writing <{}>".format(out.name)):
                    grassio.write_areas(out.name, out.geometries, out.table, cats=out.cats,
                                        title=out.title, history=True)
    grassio.say(align.report(result, config, start, time.perf_counter()))
    if config.shell:
        print("\n".join(align.shell_counts(result)))
    return 0


if __name__ == "__main__":
    options, flags = gs.parser()
    find_core()
    from reconstruction import grassio

    sys.exit(grassio.run_main(main, options, flags))
