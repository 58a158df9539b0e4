"""Calibration of facade and depth ranges on aligned footprints (issue 14): learnt from
the row buildings on a street, not from back buildings, wide buildings or the rectangle's
orientation."""

import numpy as np
import pytest
from shapely import affinity
from shapely.geometry import box

from reconstruction.subdivide.aligned_footprints import (Frontage, calibrate, exterior_segments,
                                               street_frontage)

PLOT = box(0, 0, 200, 40)
GIVEN = ((20.0, 30.0), (2.0, 3.0))


def street_row(rng, y0=0.0, facade=(6, 9), depth=(14, 18)):
    """Row buildings along the plot's south side, from x = 10 to about 190 (no corner)."""
    out, x = [], 10.0
    while x < 180:
        w, d = rng.uniform(*facade), rng.uniform(*depth)
        out.append(box(x, y0, x + w, y0 + d))
        x += w
    return out


def calibrated(aligned, plot=PLOT):
    return calibrate(aligned, [1] * len(aligned), [plot], [1], *GIVEN)


def test_street_frontage_measures_along_the_street_and_skips_back_buildings():
    seg = exterior_segments(PLOT)
    assert seg.shape == (4, 2, 2)
    assert street_frontage(box(10, 0, 16, 15), seg) == Frontage(6.0, 15.0)
    # crossing the outline (an offset map) still fronts the street
    assert street_frontage(box(10, -1.5, 16, 13.5), seg) == Frontage(6.0, 15.0)
    assert street_frontage(box(10, 15, 14, 19), seg) is None  # a back building
    # touching the outline at a corner only is no frontage
    assert street_frontage(box(-4, -4, 0, 0), seg) is None


def test_back_buildings_and_annexes_do_not_shrink_the_ranges():
    rng = np.random.default_rng(1)
    row = street_row(rng)
    back = [box(x, 22, x + 3, 25) for x in range(10, 180, 6)]  # small back buildings
    alone = calibrated(row)
    with_back = calibrated(row + back)
    assert with_back == alone
    length, depth, samples = alone
    assert samples == len(row)
    assert 6 <= length[0] <= length[1] <= 9
    assert 14 <= depth[0] <= depth[1] <= 18


def test_wide_buildings_are_left_out():
    rng = np.random.default_rng(2)
    row = street_row(rng)
    wide = street_row(rng, facade=(20, 30), depth=(8, 10))  # merged or corner buildings
    length, depth, samples = calibrated(row + [affinity.translate(w, 0, 0) for w in wide[:3]])
    assert samples == len(row)
    assert length[1] <= 9 and depth[0] >= 14


@pytest.mark.parametrize("angle", [0, 30, 73])
def test_offset_and_rotated_maps_give_the_same_ranges(angle):
    rng = np.random.default_rng(3)
    row = street_row(rng)
    base = calibrated(row)
    # the buildings 1.5 m across the outline (the map is offset), all of it rotated
    moved = [affinity.rotate(affinity.translate(b, 0.7, -1.5), angle, origin=(0, 0))
             for b in row]
    plot = affinity.rotate(PLOT, angle, origin=(0, 0))
    length, depth, samples = calibrated(moved, plot)
    assert samples == base[2]
    assert length == pytest.approx(base[0], abs=1e-6)
    assert depth == pytest.approx(base[1], abs=1e-6)


def test_too_few_row_buildings_keep_the_given_ranges():
    length, depth, samples = calibrated([box(20, 0, 27, 15), box(27, 0, 34, 15),
                                         box(50, 20, 54, 24)])
    assert (length, depth) == GIVEN
    assert samples == 2
