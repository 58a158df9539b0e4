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
# % description: Classifies a scanned RGB historical map by segments (tuned i.segment, random forest + kNN + SVM vote) and removes text and symbols.
# % keyword: raster
# % keyword: classification
# % keyword: segmentation
# % keyword: historical map
# % keyword: histo
# %end
# %option G_OPT_R_INPUTS
# % description: Red, green and blue raster maps of the scanned map
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
# % options: spectral,size,shape
# % description: Object features the classifiers use: band statistics, log area and perimeter, shape indices
# % descriptions: spectral;mean, median, variance, first and third quartile of each band;size;logarithm of area and perimeter;shape;compact square, compact circle, fractal dimension
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
# % description: Refill window size (odd; reach of a pass, distance of separate=; default: from the thickness of the removed objects)
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
# % description: Default with remove=: a square as thick as the thickest removed object; 0: none
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
# % description: Class labels (e.g. buildings) whose separate objects the refill must not join across a removed label
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
# % key: p
# % description: Print the tuning table (threshold, minsize, VW, Moran's I, normalised criteria, F) and the chosen pair
# %end

import contextlib
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


def _classify_sheet(inputs, windows, tiles, side, grid, training, config, flags, keep_segments):
    """A large map: tuned on a sample of windows, segmented and classified in tiles."""
    import numpy as np

    from reconstruction.classify import segments
    from reconstruction.classify import stage as classify
    from reconstruction.classify import tiled as classify_tiled
    from reconstruction import grassio
    from reconstruction.grassio import tiles as grasstiles

    start = time.perf_counter()
    gs.message(_("Tuning {} parameter pairs on {} windows of {} cells...").format(
        len(config.pairs), len(windows), windows[0].cells))
    criteria = grasstiles.window_criteria(
        inputs, windows, grid, config, classify.segmentation_chains(config.pairs, flags["e"]),
        segments.segmentation_criteria)
    tuning, _mean = classify_tiled.tune_on_windows(criteria, [w.cells for w in windows],
                                                   config.alpha)
    pair = config.pairs[tuning.best]
    gs.message(_("Chosen segmentation: threshold={} minsize={} (F={:.3f}); segmenting {} tiles "
                 "of up to {}x{} cells...").format(pair[0], pair[1], tuning.f[tuning.best],
                                                   len(tiles), side, side))
    timing = [("tuning", time.perf_counter() - start)]
    # the tiles are classified as their segmentations finish (the training points' tiles
    # first), so the classification works while the next tiles are segmented
    tiles = classify_tiled.training_first(tiles, training)
    segmented = grasstiles.segment_tiles(inputs, pair, tiles, grid, config)
    names = {}

    def read_bands(tile):
        env = grasstiles.window_env(grid, tile)
        return [grassio.read_raster(name, np.float64, env) for name in inputs]

    def read_segments(tile):
        while tile not in names:
            k, name = next(segmented)
            names[tiles[k]] = name
        return grassio.read_raster(names[tile], np.int32, grasstiles.window_env(grid, tile))

    gs.message(_("Segmenting, classifying and cleaning {} tiles...").format(len(tiles)))
    with contextlib.closing(segmented):
        result = classify_tiled.classify_tiles(
            tiles, read_bands, read_segments, training, config, grid, config.pairs, tuning,
            side, keep_segments=keep_segments, message=gs.message,
            percent=lambda d, t: gs.percent(d, t, 1))
    result.timing = timing + result.timing
    return result


def main(options, flags):
    import numpy as np

    from reconstruction.classify import stage as classify
    from reconstruction import grassio
    from reconstruction.grassio import tiles as grasstiles
    from reconstruction.classify import tiling
    from reconstruction.core.errors import InputError
    from reconstruction.core.options import parse_list

    grassio.register_cleanup()
    grassio.check_outputs(options, rasters=("output", "segments"))
    grassio.require_projected()
    inputs = parse_list(options["input"])
    if len(inputs) != 3:
        raise InputError("Option input= needs three raster maps (red,green,blue), got {}".format(
            len(inputs)))
    for name in inputs:
        grassio.require_raster(name)
    if not grassio.raster_region_matches(inputs):
        raise InputError("Input maps <{}> do not share the same extent and resolution".format(
            ",".join(inputs)))
    grassio.require_vector(options["training"])
    config = classify.read_config(options)
    grid = classify.Grid.from_region(None, gs.region())
    xy, columns = grassio.read_points(options["training"])
    grassio.require_columns(options, columns, ("class_column",), options["training"])
    training = classify.read_training(xy, columns, options["label_column"],
                                      options["class_column"], config, grid, options["training"])

    windows = tiling.tuning_windows(grid.rows, grid.cols)
    side = tiling.tile_side(config.memory)
    if config.window:
        tiling.check_tiles(side, config.window)
    given_cells = int(np.ceil((config.min_area or 0) / (grid.nsres * grid.ewres)))
    tiles = tiling.plan_tiles(grid.rows, grid.cols, side,
                              tiling.tile_overlap(config.window or 3, given_cells))
    if len(windows) == 1 and len(tiles) == 1:
        bands = [grassio.read_raster(name) for name in inputs]
        gs.message(_("Segmenting with {} parameter pairs...").format(len(config.pairs)))
        runs = grasstiles.run_segmentations(
            inputs, config, classify.segmentation_chains(config.pairs, flags["e"]))
        with contextlib.closing(runs):
            result = classify.classify_map(
                bands, runs, lambda name: grassio.read_raster(name, dtype=np.int32), training,
                config, grid, message=gs.message, verbose=gs.verbose)
        del bands
    else:
        result = _classify_sheet(inputs, windows, tiles, side, grid, training, config, flags,
                                 bool(options["segments"]))
    if result.rule:
        gs.message(classify.rule_message(result.rule, config, grid))
    if flags["p"]:
        print("\n".join(classify.tuning_table(result)))

    start = time.perf_counter()
    # written whole under a temporary name, renamed when complete
    with grassio.staged("raster", options["output"]) as output:
        grassio.write_raster(output, result.classes, title="Classified historical map", null=0)
        with grassio.doing("writing the categories, colours and history of <{}>".format(
                options["output"])):
            gs.write_command("r.category", map=output, rules="-", separator=":", quiet=True,
                             stdin=classify.category_rules(result.present, training.names) + "\n")
            gs.write_command("r.colors", map=output, rules="-", quiet=True,
                             stdin=classify.colour_rules(result.present, training.names)
                             + "\nnv 255:255:255\n")
            gs.run_command("r.support", map=output,
                           source1="training points <{}>, inputs <{}>".format(
                               options["training"], ",".join(inputs)),
                           description="i.segment threshold={} minsize={}".format(
                               *result.best_pair))
            gs.raster_history(output, overwrite=True)
    if options["segments"] and not isinstance(result.chosen, str):
        grassio.write_raster(options["segments"], result.chosen, title="Segments", null=0)
    elif options["segments"]:
        with grassio.doing("writing the segments <{}>".format(options["segments"])):
            gs.run_command("g.rename", raster="{},{}".format(result.chosen, options["segments"]),
                           quiet=True)
            grassio.forget_temp_map("raster", result.chosen)
            gs.raster_history(options["segments"], overwrite=True)
    timing = result.timing + [("output", time.perf_counter() - start)]
    gs.verbose(_("Timing (s): {}").format(", ".join("{} {:.1f}".format(k, v) for k, v in timing)))
    return 0


if __name__ == "__main__":
    options, flags = gs.parser()
    find_core()
    from reconstruction import grassio

    sys.exit(grassio.run_main(main, options, flags))
