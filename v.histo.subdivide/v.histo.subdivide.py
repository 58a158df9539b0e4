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
# % description: With a plot column (as v.histo.align writes them); without it, each goes to the plot it overlaps most (overlapping none: the nearest within 10 map units)
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
# %option
# % key: year
# % type: integer
# % required: no
# % label: Year of the map (a dynamic chain): the footprints get a building identity
# % description: Column building: the BAG id of an aligned footprint, the earlier identity of a kept one, else building_<year>_<cat>
# % guisection: Epochs
# %end
# %option G_OPT_V_INPUT
# % key: previous
# % required: no
# % label: Footprints of the earlier epoch (v.histo.subdivide year= of an earlier map)
# % description: Kept where the plots did not change; needs previous_plots= and year=
# % guisection: Epochs
# %end
# %option G_OPT_V_INPUT
# % key: previous_plots
# % required: no
# % label: Plots of the earlier epoch (the input= of its v.histo.subdivide)
# % guisection: Epochs
# %end
# %option
# % key: tolerance
# % type: double
# % required: no
# % answer: 4
# % label: Width of the widest difference between two drawings of an unchanged plot (map units)
# % description: With previous=: after the later map's offset is taken out; what is thinner is the drawing, not a change
# % guisection: Epochs
# %end
# %option G_OPT_DB_COLUMN
# % key: id_column
# % required: no
# % label: BAG id column of the aligned footprints (default: identificatie, identifica or pand_id)
# % description: The building identity of an aligned footprint (with year=)
# % guisection: Epochs
# %end
# %option G_OPT_R_INPUTS
# % key: map
# % required: no
# % label: Scanned map (red,green,blue rasters, or one greyscale raster) whose lines divide the plots: footprints follow them
# % description: A plot the map divides by drawn lines (parcels, buildings) gets those as footprints (source drawn); the others are subdivided as without it. Read in the current region
# % guisection: Drawn
# %end
# %option
# % key: stroke
# % type: double
# % required: no
# % label: Width of the map's lines (map units)
# % description: Default: measured on map=
# % guisection: Drawn
# %end
# %option
# % key: min_parcel
# % type: double
# % required: no
# % label: Least unit the map draws (square map units)
# % description: Default: 6 stroke widths square
# % guisection: Drawn
# %end
# %flag
# % key: d
# % label: The map draws every unit (a cadaster's parcels, an insurance map's buildings)
# % description: A plot map= does not divide is one footprint (source drawn), not subdivided
# % guisection: Drawn
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
# % requires: -d, map
# % requires: stroke, map
# % requires: min_parcel, map
# % requires: -a, aligned
# % requires: previous, previous_plots
# % requires: previous, year
# % requires: previous_plots, previous
# %end

import dataclasses
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
    from reconstruction import grassio, subdivide
    from reconstruction.core.errors import InputError

    grassio.register_cleanup()
    grassio.check_outputs(options, vectors=("output",),
                          inputs={"vector": ("input", "aligned", "previous", "previous_plots")})
    config = subdivide.read_config(options, flags)
    grassio.require_projected()
    for name, what in ((config.plots, "plots"), (config.aligned, "aligned footprints"),
                       (config.previous, "the earlier epoch's footprints"),
                       (config.previous_plots, "the earlier epoch's plots")):
        if name:
            grassio.require_vector(name)
            if grassio.vector_counts(name).get("areas", 0) == 0:
                raise InputError("Vector map <{}> has no areas: {} must be areas".format(
                    name, what))
    for name in config.maps:
        grassio.require_raster(name)

    start = time.perf_counter()
    with grassio.doing("reading the plots <{}>".format(config.plots)):
        plots, cats = subdivide.plots_with_category(
            *grassio.read_features(config.plots, "area"), config.plots)
    aligned, aligned_columns = None, {}
    if config.aligned:
        with grassio.doing("reading the aligned footprints <{}>".format(config.aligned)):
            aligned, aligned_columns = grassio.read_features(config.aligned, "area")
    previous = None
    if config.previous:
        with grassio.doing("reading the earlier epoch <{}>".format(config.previous)):
            previous = subdivide.read_previous(
                *subdivide.plots_with_category(
                    *grassio.read_features(config.previous_plots, "area"), config.previous_plots),
                *grassio.read_features(config.previous, "area"), config)
    inputs = subdivide.read_inputs(plots, cats, aligned, aligned_columns, config, previous)
    if config.maps:
        inputs = dataclasses.replace(inputs, image=grassio.read_region_image(config.maps),
                                     progress=lambda done, total: gs.percent(done, total, 5))
    grassio.say(subdivide.announce(inputs, config))
    result = subdivide.run(inputs, config)
    if not result.geometries:
        grassio.say(subdivide.report(result, config))
        raise InputError("No footprints: every plot was skipped")
    with grassio.doing("writing the footprints <{}>".format(config.output)):
        grassio.write_areas(config.output, result.geometries, result.table,
                            title="Footprints of <{}> (v.histo.subdivide)".format(config.plots))
        gs.vector_history(config.output)
    grassio.say(subdivide.report(result, config, start, time.perf_counter()))
    return 0


if __name__ == "__main__":
    options, flags = gs.parser()
    find_core()
    from reconstruction import grassio

    sys.exit(grassio.run_main(main, options, flags))
