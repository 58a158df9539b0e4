"""Footprints read from the lines a map draws inside its plots (subdivide.drawn), on
small maps drawn here cell by cell: no GRASS."""

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st
from shapely.geometry import box

from reconstruction.core.contract import SOURCE_ALIGNED, SOURCE_DRAWN, SOURCE_PROCEDURAL
from reconstruction.subdivide import drawn, subdivide

PINK, WHITE, YELLOW = (236, 190, 180), (250, 248, 242), (240, 214, 110)
LINE, OUTLINE, INK, STREET = (70, 62, 60), (150, 45, 45), (20, 18, 20), (232, 220, 190)


def cadaster(rng=None, size=200, cell=0.1, cuts=(60, 110, 150), fills=(PINK, WHITE, YELLOW, PINK),
             gap=0, numbers=True, noise=0.0):
    """A block 16 x 16 m (cells 20..180) outlined thick on a street, cut by thin vertical
    lines at ``cuts`` (cells) into parcels washed ``fills``; a number written over each
    parcel (and one across a line); ``gap`` cells of each line left out at its top.
    Returns the picture, its extent and the block and true parcels in map units."""
    rgb = np.empty((size, size, 3), float)
    rgb[:] = STREET
    lo, hi = 20, size - 20
    edges = [lo, *cuts, hi]
    for (a, b), fill in zip(zip(edges[:-1], edges[1:]), fills):
        rgb[lo:hi, a:b] = fill
    rgb[lo:lo + 4, lo:hi] = rgb[hi - 4:hi, lo:hi] = OUTLINE
    rgb[lo:hi, lo:lo + 4] = rgb[lo:hi, hi - 4:hi] = OUTLINE
    for c in cuts:
        rgb[lo + 4 + gap:hi - 4, c - 1:c + 1] = LINE
    if numbers:
        for a, b in zip(edges[:-1], edges[1:]):
            m = (a + b) // 2
            for k in range(3):                       # three digits, 2 cells wide strokes
                rgb[90:104, m - 10 + 7 * k:m - 8 + 7 * k] = INK
                rgb[90:92, m - 10 + 7 * k:m - 5 + 7 * k] = INK
        if cuts:
            rgb[40:44, cuts[0] - 6:cuts[0] + 6] = INK   # a number written across a line
    if noise:
        rgb += (rng or np.random.default_rng(0)).normal(0, noise, rgb.shape)
    extent = (0.0, size * cell, 0.0, size * cell)
    top = size * cell

    def xy(c):
        return c * cell
    block = box(xy(lo), top - xy(hi), xy(hi), top - xy(lo))
    parcels = [box(xy(a), top - xy(hi), xy(b), top - xy(lo)) for a, b in zip(edges[:-1], edges[1:])]
    return np.clip(rgb, 0, 255).astype(np.uint8), extent, block, parcels


def best_iou(found, truth):
    return [max(p.intersection(t).area / p.union(t).area for p in found) for t in truth]


def test_a_cadaster_block_is_cut_along_its_drawn_lines_whatever_the_wash_and_the_numbers():
    rgb, extent, block, truth = cadaster()
    result = drawn.read_divisions(rgb, extent, [block], [7])
    assert list(result.parcels) == [7]
    parcels = result.parcels[7]
    assert len(parcels) == 4
    assert min(best_iou(parcels, truth)) > 0.95
    # they tile the block: no gap, no overlap
    assert shapely.union_all(parcels).symmetric_difference(block).area < 0.01 * block.area
    assert sum(p.area for p in parcels) == pytest.approx(block.area, rel=0.01)
    # the scale came from the map: thin strokes of two cells, at 0.1 m
    assert 1.0 <= result.scale.stroke <= 4.0 and result.scale.cell == pytest.approx(0.1)


def test_a_block_without_inner_lines_is_left_to_the_procedural_cases():
    rgb, extent, block, _ = cadaster(cuts=(), fills=(PINK,))
    result = drawn.read_divisions(rgb, extent, [block], [1])
    assert result.parcels == {} and result.plots_read == 1


def test_jpeg_like_noise_and_a_short_line_keep_the_parcels():
    rgb, extent, block, truth = cadaster(noise=6.0, rng=np.random.default_rng(3))
    parcels = drawn.read_divisions(rgb, extent, [block], [1]).parcels[1]
    assert len(parcels) == 4 and min(best_iou(parcels, truth)) > 0.9


def test_a_line_stopping_short_joins_two_parcels_rather_than_inventing_one():
    # a gap of 6 cells between each line and the outline: the parcels meet there, and
    # the block is one footprint (today's reading closes no gap; never more units)
    rgb, extent, block, truth = cadaster(gap=6)
    parcels = drawn.read_divisions(rgb, extent, [block], [1]).parcels
    assert len(parcels.get(1, [])) in (0, 4)
    short = cadaster(gap=1)
    assert len(drawn.read_divisions(short[0], short[1], [short[2]], [1]).parcels[1]) == 4


def test_the_least_unit_and_the_stroke_can_be_given():
    rgb, extent, block, _ = cadaster()
    # a least unit larger than the narrowest parcels (4 m x 16 m): fewer drawn units
    some = drawn.read_divisions(rgb, extent, [block], [1], min_area=70.0)
    assert some.scale.min_area == pytest.approx(70.0, rel=0.01)
    assert len(some.parcels.get(1, [])) < 4
    wide = drawn.read_divisions(rgb, extent, [block], [1], stroke=0.5)
    assert wide.scale.stroke == pytest.approx(5.0) and wide.scale.radius >= 8


def test_a_plot_off_the_map_is_not_read():
    rgb, extent, block, _ = cadaster()
    far = shapely.affinity.translate(block, 1000, 0)
    assert drawn.read_divisions(rgb, extent, [far], [1]).plots_read == 0


def test_subdivide_keeps_the_drawn_parcels_and_generates_the_other_plots():
    rgb, extent, block, truth = cadaster()
    other = box(100, 0, 140, 30)                       # a plot the map does not cover
    found = drawn.read_divisions(rgb, extent, [block, other], [1, 2])
    result = subdivide([block, other], [1, 2], seed=1, drawn=found.parcels)
    sources = {(p, s) for p, s in zip(result.plot, result.source)}
    assert sources == {(1, SOURCE_DRAWN), (2, SOURCE_PROCEDURAL)}
    assert result.report.drawn == 4 and result.report.drawn_plots == 1
    assert all(c == 0 for c, s in zip(result.case, result.source) if s == SOURCE_DRAWN)
    # the same as without the map where the map draws nothing
    alone = subdivide([block, other], [1, 2], seed=1)
    mine = [g for g, p in zip(result.geometries, result.plot) if p == 2]
    theirs = [g for g, p in zip(alone.geometries, alone.plot) if p == 2]
    assert len(mine) == len(theirs) and all(a.equals(b) for a, b in zip(mine, theirs))


def test_an_aligned_footprint_takes_its_ground_from_the_drawn_parcels():
    rgb, extent, block, truth = cadaster()
    standing = box(2.5, 10, 5.0, 17.5)                # inside the first parcel, on the street
    found = drawn.read_divisions(rgb, extent, [block], [1])
    result = subdivide([block], [1], aligned=[standing], aligned_plots=[1], drawn=found.parcels)
    aligned = [g for g, s in zip(result.geometries, result.source) if s == SOURCE_ALIGNED]
    parcels = [g for g, s in zip(result.geometries, result.source) if s == SOURCE_DRAWN]
    assert len(aligned) == 1 and len(parcels) == 4
    assert all(p.intersection(aligned[0]).area < 1e-6 for p in parcels)


@settings(max_examples=25, deadline=None)
@given(cuts=st.lists(st.integers(30, 170), min_size=0, max_size=4, unique=True),
       noise=st.floats(0, 8))
def test_drawn_parcels_are_valid_disjoint_and_inside_their_plot(cuts, noise):
    cuts = sorted(c for c in cuts)
    cuts = [c for i, c in enumerate(cuts) if i == 0 or c - cuts[i - 1] >= 3]
    rgb, extent, block, _ = cadaster(cuts=tuple(cuts), fills=(PINK,) * (len(cuts) + 1),
                                     numbers=False, noise=noise)
    parcels = drawn.read_divisions(rgb, extent, [block], [1]).parcels.get(1, [])
    for p in parcels:
        assert p.is_valid and p.area > 0 and block.buffer(1e-6).contains(p)
    for i, a in enumerate(parcels):
        for b in parcels[i + 1:]:
            assert a.intersection(b).area < 1e-9
    assert len(parcels) <= len(cuts) + 1


def test_a_map_that_draws_every_unit_makes_an_undivided_plot_one_footprint():
    rgb, extent, block, _ = cadaster(cuts=(), fills=(PINK,))
    found = drawn.read_divisions(rgb, extent, [block], [1], whole=True)
    assert found.parcels == {1: [block]} and found.whole == 1
    result = subdivide([block], [1], seed=1, drawn=found.parcels)
    assert result.source == [SOURCE_DRAWN] and result.geometries[0].equals(block)


def two_parcels(**kwargs):
    """The cadaster block cut once, at cell 100 (its strokes: four cells wide)."""
    return cadaster(cuts=(100,), fills=(PINK, WHITE), **kwargs)


def parcels_of(rgb, extent, block):
    return drawn.read_divisions(rgb, extent, [block], [1]).parcels.get(1, [])


def test_a_line_broken_by_a_gap_of_one_and_a_half_strokes_still_divides():
    rgb, extent, block, truth = two_parcels()
    rgb[118:124, 99:101] = PINK                      # six cells of the line left out
    parcels = parcels_of(rgb, extent, block)
    assert len(parcels) == 2 and min(best_iou(parcels, truth)) > 0.95


def test_a_line_stopping_short_of_the_line_it_joins_meets_it():
    rgb, extent, block, truth = two_parcels()
    rgb[129:131, 24:94] = LINE                       # from the outline to six cells short
    parcels = parcels_of(rgb, extent, block)
    assert len(parcels) == 3
    left = [box(2.0, 2.0, 10.0, 7.0), box(2.0, 7.0, 10.0, 18.0)]
    assert min(best_iou(parcels, left)) > 0.9


def test_a_line_ending_farther_than_its_reach_from_any_line_stays_as_it_is():
    rgb, extent, block, truth = two_parcels()
    rgb[129:131, 24:80] = LINE                       # twenty cells short: five strokes
    parcels = parcels_of(rgb, extent, block)
    assert len(parcels) == 2 and min(best_iou(parcels, truth)) > 0.95


def test_a_number_beyond_a_line_end_is_not_joined_to_it():
    # a line from the outline ends three cells before a number written in its
    # parcel: it is not drawn on into the number, which stays in the parcel
    rgb, extent, block, truth = two_parcels(numbers=False)
    rgb[139:141, 24:40] = LINE
    for k in range(3):                               # "111", strokes two cells wide
        rgb[133:147, 44 + 6 * k:46 + 6 * k] = INK
    parcels = parcels_of(rgb, extent, block)
    assert len(parcels) == 2 and min(best_iou(parcels, truth)) > 0.95


def test_the_ends_drawn_on_are_straight_and_stop_at_the_line_they_meet():
    inside = np.zeros((40, 60), bool)
    inside[1:-1, 1:-1] = True
    line = np.zeros_like(inside)
    line[:, 40:42] = True                             # a vertical line ...
    line[19:21, 1:34] = True                          # ... and one stopping six cells short
    line[5:7, 1:20] = True                            # one stopping far from anything
    extended = drawn.extend_ends(line & inside, inside, 2.0)
    rows, cols = np.nonzero(extended)
    assert set(rows) <= {19, 20} and set(cols) == set(range(34, 40))
