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
# % options: alpha,lines,simplify,douglas,fit
# % description: Generalisation steps, run in this order
# % descriptions: alpha;alpha shape of points sampled in the plot (Arteaga 2013);lines;buffered lines (Commandeur 2012);simplify;topology-preserving simplification (tolerance=);douglas;Douglas-Peucker simplification (tolerance=);fit;each edge moved onto the boundary line the scanned map draws (map=, outline=)
# % answer: alpha,lines
# % guisection: Method
# %end
# %option
# % key: alpha
# % type: double
# % label: Alpha radius of the alpha-shape step (map units)
# % description: Default: 12 cells (from the cell size)
# % guisection: Method
# %end
# %option
# % key: distance
# % type: double
# % label: Epsilon distance of the buffered-lines step (map units)
# % description: Default: 5 cells (from the cell size)
# % guisection: Method
# %end
# %option
# % key: angle
# % type: double
# % description: Epsilon angle of the buffered-lines step (degrees, 0-180)
# % answer: 180
# % guisection: Method
# %end
# %option G_OPT_R_INPUTS
# % key: map
# % required: no
# % label: Red, green and blue rasters of the scanned map (or one, a greyscale scan), for the fit step and -d
# % description: Read in the current region
# % guisection: Method
# %end
# %option
# % key: outline
# % type: string
# % options: centre,inside
# % description: Where the map's plot outline lies, for the fit step
# % descriptions: centre;on the centre of the drawn boundary line;inside;on the outer edge of a stroke drawn inside the plot
# % answer: centre
# % guisection: Method
# %end
# %option
# % key: stroke
# % type: double
# % required: no
# % label: Width of the outline stroke drawn inside the plots (map units), for outline=inside
# % description: Default: measured on the map
# % guisection: Method
# %end
# %option
# % key: tolerance
# % type: double
# % label: Tolerance of the simplify and douglas steps (map units)
# % description: Default: 1 cell (from the cell size)
# % guisection: Method
# %end
# %option
# % key: min_area
# % type: double
# % label: Raw areas smaller than this are dropped before generalising (square map units)
# % description: Default: 20 cells, or a square 4 stroke widths wide when the drawn lines are wider (from the cell size and stroke= or map=)
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
# % description: Gives the turning-function distance, the buffer shape similarity, the outward offset, the intersection over union and the ICDAR 2021 MapSeg panoptic quality (pq, sq, rq)
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
# % key: b
# % description: Register the bands of map=: a band found a whole cell off the others is moved back before the fit reads them (without it, a warning says so)
# % guisection: Method
# %end
# %flag
# % key: d
# % label: Read the plots from the outlines drawn on map=: the classified areas decide which regions they close are built
# % description: For maps that outline every block (cadasters, atlases): the regions between the map's lines, built whole where 80 % of their cells lie in the raw areas (as classified where fewer than 80 % agree), become the raw plots that method= generalises
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

import os
import signal
import sys

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


def _raster_plots(raster, category):
    """Vectorise the cells of ``category`` into a temporary map of areas."""
    from reconstruction import grassio
    from reconstruction.core.errors import InputError

    grassio.require_raster(raster)
    with grassio.doing("vectorising class {} of raster map <{}>".format(category, raster)):
        if gs.raster_info(raster)["datatype"] != "CELL":
            raise InputError("Raster map <{}> is not a CELL (integer) map: give a classified "
                             "map".format(raster))
        stats = gs.read_command("r.stats", flags="cn", input=raster, quiet=True)
        counts = {}
        for line in stats.splitlines():
            parts = line.split()
            if len(parts) == 2:
                counts[int(parts[0])] = int(parts[1])
        if counts.get(category, 0) == 0:
            raise InputError("Raster map <{}> has no cell of class {} in the current region "
                             "(classes: {})".format(raster, category,
                                                    ", ".join(str(k) for k in sorted(counts))
                                                    or "none"))
        mask = grassio.temp_map("raster", "building")
        gs.mapcalc("{} = if({} == {}, 1, null())".format(mask, raster, category), quiet=True)
        areas = grassio.temp_map("vector", "raw_plots")
        gs.run_command("r.to.vect", input=mask, output=areas, type="area", quiet=True)
    return areas


def _cell_size():
    """The current region's cell size (map units): the scale the parameters
    not given follow (the raster= map is vectorised in it)."""
    region = gs.region()
    return (float(region["nsres"]) + float(region["ewres"])) / 2.0


def main(options, flags):
    from reconstruction import generalize, grassio
    from reconstruction.core import safefile

    grassio.register_cleanup()
    grassio.require_projected()
    config = generalize.read_config(options, flags)
    grassio.check_outputs(options, vectors=("output",), files=("metrics", "report"),
                          inputs={"vector": ("input", "gt_points", "gt_polygons")})
    if options["gt_points"]:
        grassio.require_features(options["gt_points"], "points", "gt_points")
    if options["gt_polygons"]:
        grassio.require_features(options["gt_polygons"], "areas", "gt_polygons")
    if options["input"]:
        source_map = options["input"]
        grassio.require_features(source_map, "areas", "input")
    else:
        source_map = _raster_plots(options["raster"], config.category)

    geoms, columns = grassio.read_features(source_map, "area")
    inputs = generalize.GeneralizeInputs(
        geometries=geoms, source_map=source_map,
        cats=columns["cat"] if options["input"] else None,
        gt_points=grassio.read_points(options["gt_points"])[0] if options["gt_points"] else None,
        gt_polygons=(grassio.read_features(options["gt_polygons"], "area")[0]
                     if options["gt_polygons"] else None),
        image=grassio.read_region_image(config.maps) if config.maps else None,
        say=grassio.say, cell=_cell_size())
    result = generalize.run(inputs, config)

    with safefile.together() as files:      # the files appear with the map, or none
        with grassio.doing("writing the metrics and report files"):
            result.report.write_files(files, options["metrics"], options["report"])
        grassio.write_features(options["output"], result.plots, result.columns,
                               title="Generalised building plots ({})".format(
                                   ", ".join(config.methods)))
    with grassio.doing("writing the history of <{}>".format(options["output"])):
        gs.vector_history(options["output"])
    if config.shell:
        for line in generalize.shell_figures(result):
            print(line)
    grassio.say(generalize.report(result, config))
    return 0


if __name__ == "__main__":
    options, flags = gs.parser()
    find_core()
    from reconstruction import grassio

    sys.exit(grassio.run_main(main, options, flags))
