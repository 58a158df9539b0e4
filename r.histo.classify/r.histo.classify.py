#!/usr/bin/env python3
############################################################################
#
# MODULE:       r.histo.classify
# AUTHOR(S):    histo developers
# PURPOSE:      Object-based classification of a scanned historical map with
#               tuned segmentation, an ensemble of classifiers and removal of
#               text and symbols
# COPYRIGHT:    (C) 2026 the histo developers
#
#               This program is free software under the GNU General Public
#               License (>=v2). Read the file COPYING that comes with GRASS
#               for details.
#
############################################################################

# %module
# % description: Classifies a scanned historical map (RGB or greyscale) by segments (tuned i.segment, random forest + kNN + SVM vote) and removes text and symbols.
# % keyword: raster
# % keyword: classification
# % keyword: segmentation
# % keyword: historical map
# % keyword: histo
# %end
# %option G_OPT_R_INPUTS
# % description: Red, green and blue raster maps of the scanned map, or one raster map of a greyscale scan
# % guisection: Input
# %end
# %option G_OPT_V_INPUT
# % key: training
# % label: Training points
# % description: Vector points labelling the classes of the map
# % guisection: Input
# %end
# %option G_OPT_DB_COLUMN
# % key: label_column
# % description: Integer column of the training points with the class label
# % answer: label
# % required: yes
# % guisection: Input
# %end
# %option G_OPT_DB_COLUMN
# % key: class_column
# % description: Text column naming the classes (category labels of the output; ignored when absent)
# % answer: class
# % guisection: Input
# %end
# %option G_OPT_R_OUTPUT
# % description: Classified raster map (categories are the training labels)
# % guisection: Output
# %end
# %option G_OPT_R_OUTPUT
# % key: segments
# % required: no
# % description: Chosen segmentation
# % guisection: Output
# %end
# %option
# % key: threshold
# % type: double
# % multiple: yes
# % key_desc: min,max
# % description: Range of i.segment similarity thresholds to try (0-1)
# % answer: 0.07,0.10
# % guisection: Segmentation
# %end
# %option
# % key: threshold_step
# % type: double
# % description: Step of the threshold range
# % answer: 0.01
# % guisection: Segmentation
# %end
# %option
# % key: minsize
# % type: integer
# % multiple: yes
# % key_desc: min,max
# % description: Range of i.segment minimum segment sizes to try (cells)
# % answer: 7,10
# % guisection: Segmentation
# %end
# %option
# % key: minsize_step
# % type: integer
# % description: Step of the minimum size range
# % answer: 1
# % guisection: Segmentation
# %end
# %option
# % key: alpha
# % type: double
# % description: Weight of the F-function combining normalised Moran's I and intra-segment variance
# % answer: 1
# % guisection: Segmentation
# %end
# %option
# % key: segmentation
# % type: string
# % options: superpixels,lines
# % description: What the segments are
# % descriptions: superpixels;regions of like colour (i.segment, tuned over threshold= and minsize=);lines;the shapes the map's line work closes, and its lines (monochrome maps: outlined blocks, hatched buildings)
# % answer: superpixels
# % guisection: Segmentation
# %end
# %option
# % key: classifiers
# % type: string
# % multiple: yes
# % options: rf,knn,svm
# % description: Classifiers of the ensemble (majority vote, ties go to the first)
# % answer: rf,knn,svm
# % guisection: Classification
# %end
# %option
# % key: features
# % type: string
# % multiple: yes
# % options: spectral,lab,size,shape,fill
# % description: Object features the classifiers use: band statistics (of the bands, of their CIELAB colour), log area and perimeter, shape indices, what a shape is filled with
# % descriptions: spectral;mean, median, variance, first and third quartile of each band;lab;the same of the CIELAB lightness L* and colour a*, b* of the red, green, blue bands (pale washes apart from white paper, needs three bands);size;logarithm of area and perimeter;shape;compact square, compact circle, fractal dimension;fill;share of ink and of hatching, the strokes' direction and how parallel they are (needs segmentation=lines)
# % answer: spectral,size
# % guisection: Classification
# %end
# %option
# % key: remove
# % type: integer
# % multiple: yes
# % description: Class labels to remove (e.g. text, symbols): refilled from their surroundings
# % guisection: Removal
# %end
# %option
# % key: window
# % type: integer
# % description: Refill window size (odd; reach of a pass, half the distance of separate=; default: from the thickness of the removed letters and symbols, in cells)
# % guisection: Removal
# %end
# %option
# % key: iterations
# % type: integer
# % description: Maximum number of refill passes: cells farther than iterations x (window - 1) / 2 cells from every kept cell stay empty (default: until filled)
# % guisection: Removal
# %end
# %option
# % key: min_area
# % type: double
# % label: Minimum mapping unit: regions of one class smaller than this (square map units) are refilled from their surroundings
# % description: Default with remove=: a square as thick as the thickest removed letter or symbol (cells; removed outline strokes do not count); 0: none
# % guisection: Removal
# %end
# %option
# % key: min_width
# % type: double
# % label: Parts of a class narrower than this (map units) are refilled from their surroundings (e.g. colour fringes, pieces of letters)
# % description: Default with remove=: 3 cells; 0: none
# % guisection: Removal
# %end
# %option
# % key: separate
# % type: integer
# % multiple: yes
# % description: Class labels (e.g. buildings) whose separate objects the refill must not join across a removed label, nor grow out into it
# % guisection: Removal
# %end
# %option
# % key: outline
# % type: string
# % options: centre,inside
# % answer: centre
# % label: Where the map draws the outline of the areas of the separate= classes
# % description: inside: a darker stroke within the area, its outer edge the area's edge (an edge cell goes to the area when the stroke covers half of it); centre: on the boundary (edge cells stay as classified)
# % descriptions: centre;the outline's centre line is the boundary;inside;the outline is drawn within the area
# % guisection: Removal
# %end
# %option
# % key: seed
# % type: integer
# % description: Seed of the random forest
# % answer: 1
# %end
# %option G_OPT_M_NPROCS
# %end
# %option G_OPT_MEMORYMB
# %end
# %flag
# % key: e
# % description: Exhaustive tuning: a full i.segment run for every parameter pair (slower; by default each threshold grows once and larger minimum sizes are reseeded from it)
# % guisection: Segmentation
# %end
# %flag
# % key: b
# % description: Register the bands (three; refused with one): a band found a whole cell off the others is moved back before the classification (without it, a warning says so)
# %end
# %flag
# % key: p
# % description: Print the tuning table (threshold, minsize, VW, Moran's I, normalised criteria, F) and the chosen pair
# %end

import os
import signal
import sys
import time
from dataclasses import replace

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
    import numpy as np

    from reconstruction import classify, grassio
    from reconstruction.core.errors import InputError

    grassio.register_cleanup()
    grassio.check_outputs(options, rasters=("output", "segments"),
                          inputs={"raster": ("input",), "vector": ("training",)})
    grassio.require_projected()
    config = classify.read_config(options, flags)
    bands = config.bands
    for name in bands:
        grassio.require_raster(name)
    if not grassio.raster_region_matches(bands):
        raise InputError("Input maps <{}> do not share the same extent and resolution".format(
            ",".join(bands)))
    grassio.require_vector(options["training"])
    grid = classify.stage.Grid.from_region(None, gs.region())
    shifts = grassio.read_band_shifts(bands, grid)
    if config.register:
        bands = grassio.registered_bands(bands, shifts)
    grassio.say([shifts.message(config.bands, config.register)])
    config = replace(config, in_register=config.register or not shifts.moved)
    xy, columns = grassio.read_points(options["training"])
    grassio.require_columns(options, columns, ("class_column",), options["training"])

    def env(tile):
        return None if tile is None else grassio.window_env(grid, tile)

    inputs = classify.ClassifyInputs(
        grid=grid, training_xy=xy, training_columns=columns, training_map=options["training"],
        read_bands=lambda tile: [grassio.read_raster(name, np.float64, env(tile))
                                 for name in bands],
        read_segments=lambda name, tile: grassio.read_raster(name, np.int32, env(tile)),
        segment=lambda chains: grassio.run_segmentations(bands, config, chains),
        window_criteria=lambda windows, chains, criterion: grassio.window_criteria(
            bands, windows, grid, config, chains, criterion),
        segment_tiles=lambda pair, tiles: grassio.segment_tiles(bands, pair, tiles, grid, config),
        say=grassio.say, percent=lambda done, total: gs.percent(done, total, 1))
    result = classify.run(inputs, config)
    if config.print_table:
        print("\n".join(classify.stage.tuning_table(result)))

    start = time.perf_counter()
    # written whole under a temporary name, renamed when complete
    with grassio.staged("raster", options["output"]) as output:
        grassio.write_raster(output, result.classes, title="Classified historical map", null=0)
        with grassio.doing("writing the categories, colours and history of <{}>".format(
                options["output"])):
            gs.write_command("r.category", map=output, rules="-", separator=":", quiet=True,
                             stdin=classify.stage.category_rules(result.present, result.names)
                             + "\n")
            gs.write_command("r.colors", map=output, rules="-", quiet=True,
                             stdin=classify.stage.colour_rules(result.present, result.names)
                             + "\nnv 255:255:255\n")
            gs.run_command("r.support", map=output,
                           source1="training points <{}>, inputs <{}>".format(
                               options["training"], ",".join(config.bands)),
                           description=("shapes closed by the map's lines"
                                        if config.segmentation == "lines" else
                                        "i.segment threshold={} minsize={}".format(
                                            *result.best_pair)))
            gs.raster_history(output, overwrite=True)
    if options["segments"] and not isinstance(result.chosen, str):
        grassio.write_raster(options["segments"], result.chosen, title="Segments", null=0)
    elif options["segments"]:
        with grassio.doing("writing the segments <{}>".format(options["segments"])):
            gs.run_command("g.rename", raster="{},{}".format(result.chosen, options["segments"]),
                           quiet=True)
            grassio.forget_temp_map("raster", result.chosen)
            gs.raster_history(options["segments"], overwrite=True)
    grassio.say(classify.report(result.timed("output", time.perf_counter() - start), config))
    return 0


if __name__ == "__main__":
    options, flags = gs.parser()
    find_core()
    from reconstruction import grassio

    sys.exit(grassio.run_main(main, options, flags))
