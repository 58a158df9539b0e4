"""r.histo.classify's whole sequence: :func:`run` (``reconstruction.classify.run``).

From the training points and the map's bands to a :class:`ClassifyResult`:
the training points are checked and located (:func:`~reconstruction.classify.stage.read_training`),
the tiles planned (:mod:`reconstruction.classify.tiling`); a map that fits
one tile is classified whole (:func:`~reconstruction.classify.stage.classify_map`),
a larger sheet tuned on a sample of windows and classified in tiles
(:mod:`reconstruction.classify.tiled`).

The GRASS side comes in as callables of :class:`ClassifyInputs` (the module
binds them to :mod:`reconstruction.grassio`): the bands and segments are read
lazily, tile by tile, and the segmentations stream in as i.segment finishes
them, so that the classification of a tile runs while the next ones are
segmented. Progress lines go out through ``say`` as they happen.
"""

import contextlib
import time
from dataclasses import dataclass, replace
from typing import Callable, Iterator, Optional

import numpy as np

from ..core.messages import Message, note
from ..geom.grid import Grid
from . import lines
from . import segments as cl
from . import tiled, tiling
from .config import ClassifyConfig
from .stage import ClassifyResult, classify_map, read_training, segmentation_chains
from .tiling import Tile


def _silent(messages):
    pass


def _no_percent(done, total):
    pass


@dataclass(frozen=True)
class ClassifyInputs:
    """What r.histo.classify reads from GRASS, and how it reaches i.segment.

    - ``grid``: the computational region;
    - ``training_xy``, ``training_columns``: the training points'
      coordinates and attribute columns, of the map ``training_map``;
    - ``read_bands(tile)``: the three bands (float64, nan = no data) of a
      :class:`~reconstruction.classify.tiling.Tile`'s outer window, of the
      whole region for None;
    - ``read_segments(id, tile)``: the segments (int32) of a finished
      segmentation, in the tile's outer window (None: the whole region);
    - ``segment(chains)``: i.segment for ``config.pairs`` in the whole region,
      run as :func:`~reconstruction.classify.stage.segmentation_chains`:
      yields ``(pair index, id)`` as each run finishes;
    - ``window_criteria(windows, chains, criterion)``: the same in each
      tuning window: ``criteria[w][k] = criterion(segments, bands)``;
    - ``segment_tiles(pair, tiles)``: i.segment with ``pair`` in each tile's
      outer window: yields ``(tile index, id)`` as each finishes (closed when
      the run stops);
    - ``say(messages)``: prints progress :class:`~reconstruction.core.messages.Message` s
      as they happen; ``percent(done, total)``: the progress of the
      segmentations of a map classified whole, of the tiles of a sheet.
    """

    grid: Grid
    training_xy: np.ndarray
    training_columns: dict
    training_map: str
    read_bands: Callable[[Optional[Tile]], list]
    read_segments: Callable[[str, Optional[Tile]], np.ndarray]
    segment: Callable[[list], Iterator]
    window_criteria: Callable[[list, list, Callable], list]
    segment_tiles: Callable[[tuple, list], Iterator]
    say: Callable[[list], None] = _silent
    percent: Callable[[int, int], None] = _no_percent


def _sayer(say, level):
    return lambda text: say([Message(text, level)])


def run(inputs, config: ClassifyConfig) -> ClassifyResult:
    """Classify the map of ``inputs`` as ``config`` says: a
    :class:`~reconstruction.classify.stage.ClassifyResult` (its ``chosen`` the
    id of the whole map's chosen segmentation, or its segment array when
    tiled and ``config.keep_segments``)."""
    grid = inputs.grid
    training = read_training(inputs.training_xy, inputs.training_columns, config.label_column,
                             config.class_column, config, grid, inputs.training_map)
    if config.segmentation == "lines":
        return _classify_lines(inputs, training, config)
    windows = tiling.tuning_windows(grid.rows, grid.cols)
    side = tiling.tile_side(config.memory)
    if config.window:
        tiling.check_tiles(side, config.window)
    given_cells = int(np.ceil((config.min_area or 0) / (grid.nsres * grid.ewres)))
    tiles = tiling.plan_tiles(grid.rows, grid.cols, side,
                              tiling.tile_overlap(config.window or 3, given_cells))
    chains = segmentation_chains(config.pairs, config.exhaustive)
    if len(windows) == 1 and len(tiles) == 1:
        bands = inputs.read_bands(None)
        inputs.say([note("Segmenting with {} parameter pairs...".format(len(config.pairs)))])
        runs = inputs.segment(chains)
        with contextlib.closing(runs):
            return classify_map(bands, runs, lambda name: inputs.read_segments(name, None),
                                training, config, grid, message=_sayer(inputs.say, "message"),
                                verbose=_sayer(inputs.say, "verbose"), percent=inputs.percent)
    return _classify_sheet(inputs, windows, tiles, side, chains, training, config)


def _classify_lines(inputs, training, config):
    """The segments are the shapes the map's lines close (and the lines): read
    on the whole map at once, as a shape may reach across any tile."""
    bands = inputs.read_bands(None)
    inputs.say([note("Reading the shapes the map's lines close...")])
    start = time.perf_counter()
    reading = lines.read_ink(bands, inputs.grid.ewres)
    shapes = lines.line_shapes(reading)
    inputs.say([note("{} shapes closed by the lines (stroke {:.1f} cells, least shape {} "
                     "cells)".format(shapes.shapes, reading.scale.stroke,
                                     reading.scale.min_cells))])
    took = time.perf_counter() - start
    result = classify_map(bands, [(0, shapes.segments)], lambda segments: segments, training,
                          replace(config, thresholds=(0.0,), minsizes=(0,)), inputs.grid,
                          message=_sayer(inputs.say, "verbose"), reading=reading)
    return replace(result, timing=[("segmentation", took)] + result.timing[1:])


def _classify_sheet(inputs, windows, tiles, side, chains, training, config):
    """A large map: tuned on a sample of windows, segmented and classified in tiles."""
    start = time.perf_counter()
    inputs.say([note("Tuning {} parameter pairs on {} windows of {} cells...".format(
        len(config.pairs), len(windows), windows[0].cells))])
    criteria = inputs.window_criteria(windows, chains, cl.segmentation_criteria)
    tuning, _mean = tiled.tune_on_windows(criteria, [w.cells for w in windows], config.alpha)
    pair = config.pairs[tuning.best]
    inputs.say([note("Chosen segmentation: threshold={} minsize={} (F={:.3f}); segmenting {} "
                     "tiles of up to {}x{} cells...".format(pair[0], pair[1],
                                                           tuning.f[tuning.best], len(tiles),
                                                           side, side))])
    timing = [("tuning", time.perf_counter() - start)]
    # the tiles are classified as their segmentations finish (the training points' tiles
    # first), so the classification works while the next tiles are segmented
    tiles = tiled.training_first(tiles, training)
    segmented = inputs.segment_tiles(pair, tiles)
    names = {}

    def read_segments(tile):
        while tile not in names:
            k, name = next(segmented)
            names[tiles[k]] = name
        return inputs.read_segments(names[tile], tile)

    inputs.say([note("Segmenting, classifying and cleaning {} tiles...".format(len(tiles)))])
    with contextlib.closing(segmented):
        result = tiled.classify_tiles(
            tiles, inputs.read_bands, read_segments, training, config, inputs.grid, config.pairs,
            tuning, side, keep_segments=config.keep_segments,
            message=_sayer(inputs.say, "message"), percent=inputs.percent)
    return replace(result, timing=timing + result.timing)

