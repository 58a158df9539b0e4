"""Tiles of a large raster (reconstruction.classify.tiling) and the tiled classification's
tuning (reconstruction.classify.tiled): no GRASS needed."""

import numpy as np
import pytest

from reconstruction.classify import tiled as classify_tiled
from reconstruction.classify import tiling
from reconstruction.core.errors import InputError


def test_one_tile_when_the_map_fits():
    assert tiling.plan_tiles(50, 80, 100, 10) == [tiling.Tile(0, 50, 0, 80, 0, 50, 0, 80)]


def test_tile_cores_partition_the_map_and_outer_windows_add_the_overlap():
    rows, cols, side, overlap = 230, 170, 100, 20
    tiles = tiling.plan_tiles(rows, cols, side, overlap)
    count = np.zeros((rows, cols), dtype=int)
    for tile in tiles:
        count[tile.core] += 1
        height, width = tile.outer_shape
        assert height <= side and width <= side
        assert tile.orow0 == max(tile.row0 - overlap, 0) and tile.ocol1 == min(tile.col1 + overlap, cols)
        inner = np.zeros(tile.outer_shape, dtype=bool)
        inner[tile.core_in_outer] = True
        assert inner.sum() == tile.cells
    assert (count == 1).all()


def test_tiles_that_leave_no_core_or_are_smaller_than_the_window_are_refused():
    with pytest.raises(InputError, match="give more memory"):
        tiling.plan_tiles(500, 500, 100, 50)
    with pytest.raises(InputError, match="smaller than the refill window"):
        tiling.check_tiles(7, 9)
    tiling.check_tiles(9, 9)


def test_tile_side_from_memory():
    assert tiling.tile_side(300) == int((300 * 2 ** 20 / tiling.BYTES_PER_CELL) ** 0.5)
    assert tiling.tile_overlap(9, 225) == 64 and tiling.tile_overlap(31, 0) == 124


def test_tuning_windows_whole_map_or_four_spread_windows():
    assert tiling.tuning_windows(500, 600, cells=300_000) == [tiling.Tile(0, 500, 0, 600, 0, 500, 0, 600)]
    windows = tiling.tuning_windows(4000, 4000, cells=360_000)
    assert len(windows) == 4 and {w.cells for w in windows} == {300 * 300}
    assert len({(w.row0, w.col0) for w in windows}) == 4
    assert all(0 <= w.row0 and w.row1 <= 4000 for w in windows)


def test_tuning_on_windows_weighs_the_criteria_by_cells():
    criteria = [[(1.0, 0.5), (3.0, 0.1)], [(3.0, 0.5), (1.0, 0.3)]]
    tuning, mean = classify_tiled.tune_on_windows(criteria, [3, 1])
    assert np.allclose(mean, [(1.5, 0.5), (2.5, 0.15)])
    assert tuning.best in (0, 1) and len(tuning.f) == 2


def test_tiles_holding_training_points_are_segmented_first_each_in_their_order():
    import types

    tiles = tiling.plan_tiles(300, 300, 150, 25)  # 3 x 3 tiles of 100-cell cores
    assert len(tiles) == 9
    # points in the cores of tiles 8, 1 and 1 again (row-major order)
    training = types.SimpleNamespace(rows=np.array([250, 10, 20]), cols=np.array([250, 150, 160]))
    order = classify_tiled.training_first(tiles, training)
    assert order[:2] == [tiles[1], tiles[8]]
    assert order[2:] == [t for k, t in enumerate(tiles) if k not in (1, 8)]
