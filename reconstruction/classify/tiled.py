"""r.histo.classify on a whole map sheet: tuned on a sample, classified in tiles.

The same stage as :func:`reconstruction.classify.stage.classify_map`, for maps too
large to tune on whole or to hold in one process:

1. :func:`tune_on_windows`: the segmentation parameters are chosen on a
   sample of windows (:func:`reconstruction.classify.tiling.tuning_windows`): each
   pair's VW and Moran's I are the cell-weighted means over the windows;
2. the caller segments every tile's outer window with the chosen pair
   (in the order of :func:`training_first`, while the first ones are
   classified: ``read_segments`` may wait for a tile's segmentation);
3. :func:`classify_tiles`: the ensemble is fitted once, on the segments of
   the training points (each seen in the tile whose core holds it), and
   predicts the segments of each tile; each tile's core keeps its classes.
   The removal's rule (window, minimum mapping unit) comes from the thickest
   removed object over all tiles, and which removed classes are drawn as
   lines (:func:`~reconstruction.classify.removal.line_classes`) from the
   counts of all tiles, then each tile is cleaned in its outer
   window and keeps its core: a segment, a hole or a region cut by a tile's
   edge is seen whole from the tile whose core holds it, up to the overlap.
   With outline=inside, each tile's edge cells are then decided in its outer
   window (:func:`~reconstruction.classify.outlines.inside_outlines`, the
   stroke's colour from that window).

Pure: the caller reads the bands and segments of a tile's outer window
(functions of a :class:`~reconstruction.classify.tiling.Tile`) and gets progress
through ``percent(done, total)``.
"""

import time

import numpy as np

from ..core.errors import InputError
from . import outlines, removal
from . import segments as cl
from .stage import ClassifyResult, removal_rule, _ignore
from .tiling import check_tiles


def tune_on_windows(criteria, cells, alpha=1.0):
    """Tuning over a sample: ``criteria[w][k]`` the (VW, Moran's I) of pair k in
    window w, ``cells[w]`` its number of cells. Returns the
    :class:`~reconstruction.classify.segments.TuningResult` of the weighted means."""
    weights = np.asarray(cells, dtype=float)
    stacked = np.asarray(criteria, dtype=float)  # (windows, pairs, 2)
    mean = (stacked * weights[:, None, None]).sum(axis=0) / weights.sum()
    return cl.tune(mean, alpha), [tuple(row) for row in mean]


def _training_in(tile, training):
    keep = tile.holds(training.rows, training.cols)
    return np.flatnonzero(keep)


def training_first(tiles, training):
    """The tiles whose cores hold training points first, then the others, each
    in their order: the order to segment them in when the classification of
    the first tiles (which needs the model, fitted on the training tiles)
    runs while the next ones are segmented."""
    holding = [len(_training_in(tile, training)) > 0 for tile in tiles]
    return [t for t, h in zip(tiles, holding) if h] + [t for t, h in zip(tiles, holding) if not h]


def classify_tiles(tiles, read_bands, read_segments, training, config, grid, pairs, tuning,
                   side, keep_segments=False, message=_ignore, percent=_ignore):
    """Classify a map tile by tile with the chosen segmentation of each tile.

    ``read_bands(tile)``: the bands of the tile's outer window (nan = no
    data); ``read_segments(tile)``: its segments. ``pairs`` and ``tuning``:
    the tried pairs and their :class:`TuningResult`; ``side``: the tiles' size
    (a derived refill window larger than that is refused). Returns a
    :class:`~reconstruction.classify.stage.ClassifyResult` (``chosen`` is the whole
    map's segment ids when ``keep_segments``, else None).
    """
    start = time.perf_counter()
    total = 2 * len(tiles) + sum(1 for t in tiles if len(_training_in(t, training)))
    done = 0
    # 1. the training segments' features, from the tiles whose cores hold the points
    rows_of = np.full(len(training.labels), -1)
    x_train = [None] * len(training.labels)
    for tile in tiles:
        members = _training_in(tile, training)
        if not len(members):
            continue
        bands = read_bands(tile)
        r = training.rows[members] - tile.orow0
        c = training.cols[members] - tile.ocol0
        if not all(np.isfinite(b[r, c]).all() for b in bands):
            raise InputError("Some training points lie on no-data cells of the input maps")
        segments = read_segments(tile)
        index, _n = cl.relabel(segments)
        _ids, features = cl.object_features(segments, bands, config.features)
        model_features = cl.finite_features(features)
        at = index[r, c]
        if (at < 0).any():
            raise InputError("Some training points lie outside every segment")
        for k, row in zip(members, at):
            x_train[k] = model_features[row]
            rows_of[k] = row
        done += 1
        percent(done, total)
    message("Classifying the segments of {} tiles with {}...".format(
        len(tiles), ",".join(config.classifiers)))
    models = cl.fit_ensemble(np.stack(x_train), training.labels, config.classifiers, config.seed,
                             config.nprocs)

    # 2. every tile's segments classified; the core kept
    classes = np.zeros((grid.rows, grid.cols), dtype=np.int32)
    segment_ids = np.zeros((grid.rows, grid.cols), dtype=np.int32) if keep_segments else None
    n_segments = 0
    counts = {label: (0, 0) for label in config.remove}
    for tile in tiles:
        bands = read_bands(tile)
        segments = read_segments(tile)
        index, n = cl.relabel(segments)
        _ids, features = cl.object_features(segments, bands, config.features)
        voted, _p = cl.predict_ensemble(models, features)
        tile_classes = cl.class_raster(index, voted.astype(np.int32))
        for label, (long, cells) in removal.line_counts(tile_classes, config.remove,
                                                         tile.core_in_outer).items():
            counts[label] = (counts[label][0] + long, counts[label][1] + cells)
        classes[tile.core] = tile_classes[tile.core_in_outer]
        core_index = index[tile.core_in_outer]
        present = np.unique(core_index[core_index >= 0])
        if keep_segments:
            renumber = np.zeros(n + 1, dtype=np.int32)
            renumber[present + 1] = np.arange(1, len(present) + 1) + n_segments
            segment_ids[tile.core] = renumber[core_index + 1]
        n_segments += len(present)
        done += 1
        percent(done, total)
    timing = [("classification", time.perf_counter() - start)]
    start = time.perf_counter()

    # 3. the removal, by the rule of the thickest removed letter or symbol of the whole map,
    # which removed classes are drawn as lines decided once for the whole map (decided per
    # tile, a tile could refill its blocks otherwise than the next: issue 51, item 4)
    lines = removal.line_classes(None, config.remove, counts)
    thickness = max((removal.removed_thickness(classes[tile.outer], config.remove, lines)
                     for tile in tiles), default=0.0) if config.remove else 0.0
    rule = removal_rule(thickness, config, grid)
    check_tiles(side, rule.window)
    printed = outlines.printed_cells(classes, config)
    if rule.active(config.remove):
        out = np.zeros_like(classes)
        for tile in tiles:
            cleaned, _w = removal.remove_classes(classes[tile.outer], config.remove, rule.window,
                                            config.iterations, rule.min_cells, rule.width_cells,
                                            config.separate,
                                            image=(np.stack(read_bands(tile), axis=-1)
                                                   if config.separate and config.in_register
                                                   else None), lines=lines)
            out[tile.core] = cleaned[tile.core_in_outer]
            done += 1
            percent(done, total)
        classes = out
    else:
        rule = None
    if printed is not None:
        out = classes.copy()
        for tile in tiles:
            edged = outlines.inside_outlines(classes[tile.outer], read_bands(tile), config.separate,
                                             printed=printed[tile.outer],
                                             unmix=config.in_register)
            out[tile.core] = edged[tile.core_in_outer]
        classes = out
    percent(total, total)
    timing.append(("removal", time.perf_counter() - start))
    return ClassifyResult(
        classes=classes, pairs=pairs, criteria=None, tuning=tuning, chosen=segment_ids,
        segments=n_segments, window=rule.window if rule else None, rule=rule,
        present=[c for c in training.classes if c not in config.remove], timing=timing,
        names=training.names, grid=grid)
