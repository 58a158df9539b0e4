"""Plots of two epochs matched (reconstruction.epochs.plots): the kinds of change, the
offset between two maps, and what drawing differences must not turn into a change."""

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st
from shapely import affinity
from shapely.geometry import box

from reconstruction.epochs import estimate_offset, match_plots
from reconstruction.epochs.plots import (CHANGED, EXTENDED, MERGED, NEW, REDUCED, SPLIT,
                                         TOLERANCE, UNCHANGED)


def street_of_plots(n=6, width=20.0, depth=15.0, gap=10.0, y=0.0):
    return [box(k * (width + gap), y, k * (width + gap) + width, y + depth) for k in range(n)]


def moved(geoms, dx, dy):
    return [affinity.translate(g, dx, dy) for g in geoms]


def test_each_kind_of_change_is_told_apart():
    before = street_of_plots() + [box(0, 40, 20, 55), box(22, 40, 42, 55),
                                  box(60, 40, 80, 55), box(200, 200, 210, 210)]
    after = street_of_plots()[:5] + [
        box(150, 0, 170, 10),                       # plot 5 shortened: reduced
        box(0, 40, 42, 55),                         # plots 6 and 7 merged
        box(60, 40, 69.5, 55), box(70.5, 40, 80, 55),  # plot 8 split
        box(300, 300, 320, 315),                    # new
    ]
    after[2] = box(60, 0, 80, 22)                   # plot 2 extended into its garden
    m = match_plots(before, moved(after, 0.9, -0.6))
    assert m.offset == pytest.approx((0.9, -0.6), abs=1e-6)
    assert m.change == [UNCHANGED, UNCHANGED, EXTENDED, UNCHANGED, UNCHANGED, REDUCED,
                        MERGED, SPLIT, SPLIT, NEW]
    assert m.before[6] == (6, 7) and m.before[7] == m.before[8] == (8,) and m.before[9] == ()
    assert m.gone == [9]
    assert m.unchanged() == {0: 0, 1: 1, 3: 3, 4: 4}
    assert m.counts() == {UNCHANGED: 4, EXTENDED: 1, REDUCED: 1, SPLIT: 2, MERGED: 1,
                          CHANGED: 0, NEW: 1, "gone": 1}


def test_plots_redrawn_many_to_many_are_changed():
    before = [box(0, 0, 20, 15), box(20, 0, 40, 15)]
    after = [box(0, 0, 13, 15), box(13, 0, 27, 15), box(27, 0, 40, 15)]
    m = match_plots(before, after, offset=(0, 0))
    assert m.change == [CHANGED] * 3 and not m.gone


def test_a_plot_drawn_with_another_outline_beyond_the_tolerance_is_changed():
    before = [box(0, 0, 30, 20)]
    notched = shapely.difference(box(0, 0, 30, 20), box(0, 16, 4, 20))   # 4 m from the corner
    assert match_plots(before, [notched], offset=(0, 0)).change == [UNCHANGED]
    assert match_plots(before, [notched], offset=(0, 0), tolerance=1.5).change == [REDUCED]


def test_slivers_and_a_spike_are_the_drawing_a_strip_beyond_the_tolerance_a_change():
    """A block drawn again a metre smaller along one side and with a 10 m spike (what
    the Hausdorff distance takes for a change) is unchanged; the same block grown by
    a 5 m strip into its garden is extended, and that strip is the added ground."""
    before = [box(0, 0, 30, 20)]
    redrawn = shapely.union(box(0, 1, 30, 20), box(14, 20, 15, 30))
    m = match_plots(before, [redrawn], offset=(0, 0))
    assert m.change == [UNCHANGED] and m.removed.area == 0 and m.added.area == 0
    grown = box(0, 0, 30, 25)
    m = match_plots(before, [grown], offset=(0, 0))
    assert m.change == [EXTENDED]
    assert m.added.area == pytest.approx(30 * 5) and m.removed.area == 0
    assert m.added.equals(box(0, 20, 30, 25))


def test_no_offset_without_enough_pairs_to_measure_it():
    assert estimate_offset([box(0, 0, 10, 10)], [box(1, 1, 11, 11)]) == (0.0, 0.0)
    assert estimate_offset([], []) == (0.0, 0.0)


def test_an_offset_larger_than_a_street_is_found():
    before = street_of_plots(8)
    m = match_plots(before, moved(before, 6.0, 3.0))
    assert m.offset == pytest.approx((6.0, 3.0), abs=1e-6)
    assert m.change == [UNCHANGED] * 8


def test_no_plots_on_either_side():
    m = match_plots([], [box(0, 0, 1, 1)])
    assert m.change == [NEW] and m.gone == []
    m = match_plots([box(0, 0, 1, 1)], [])
    assert m.change == [] and m.gone == [0]


def jittered(geom, rng, amount):
    """The plot drawn again: every vertex moved by up to ``amount`` (a new classification)."""
    xy = np.asarray(geom.exterior.coords)[:-1]
    xy = xy + rng.uniform(-amount, amount, xy.shape)
    return shapely.Polygon(xy)


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2 ** 16), dx=st.floats(-3, 3), dy=st.floats(-3, 3),
       jitter=st.floats(0, 0.8), n=st.integers(3, 9))
def test_a_town_drawn_again_offset_and_redrawn_is_unchanged(seed, dx, dy, jitter, n):
    """Property: the same plots on a second map, offset by up to 3 m and every corner
    redrawn up to 0.8 m off, are all unchanged, one to one, and the offset is found
    within the redrawing."""
    rng = np.random.default_rng(seed)
    before = street_of_plots(n, width=float(rng.uniform(12, 30)), depth=float(rng.uniform(10, 20)))
    after = [affinity.translate(jittered(g, rng, jitter), dx, dy) for g in before]
    m = match_plots(before, after)
    assert m.change == [UNCHANGED] * n
    assert [b for b in m.before] == [(k,) for k in range(n)]
    assert np.hypot(m.offset[0] - dx, m.offset[1] - dy) <= 2 * jitter + 1e-6
    assert TOLERANCE >= 2 * jitter


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 2 ** 16), grow=st.floats(TOLERANCE + 0.5, 12))
def test_a_plot_grown_by_more_than_the_tolerance_is_extended(seed, grow):
    """Property: a plot that grows into its garden by more than the tolerance is not
    taken for unchanged, whatever the others do."""
    rng = np.random.default_rng(seed)
    before = street_of_plots(6)
    k = int(rng.integers(0, 6))
    after = list(before)
    x0, y0, x1, y1 = before[k].bounds
    after[k] = box(x0, y0, x1, y1 + grow)
    m = match_plots(before, after)
    assert m.change[k] == EXTENDED
    assert all(c == UNCHANGED for j, c in enumerate(m.change) if j != k)
