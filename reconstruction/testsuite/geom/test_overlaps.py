"""One overlap resolver, three rules (no GRASS)."""

import pytest
import shapely
from shapely.geometry import box

from reconstruction.geom.overlaps import OverlapRule, group_conflicts, resolve_overlaps


def test_group_conflicts_one_per_loser_in_rank_order():
    # rank: 2 beats 0 beats 1
    conflicts = group_conflicts([(0, 1), (1, 2), (0, 2)], {0: 1, 1: 2, 2: 0})
    assert conflicts == [(0, [2]), (1, [0, 2])]


def test_a_loser_gives_up_what_it_shares_with_its_merged_winners():
    geoms = [box(0, 0, 10, 10), box(8, 0, 20, 10), box(18, 0, 30, 10)]
    # 1 loses to 0 and 2: what is left lies between them
    out, shared = resolve_overlaps(geoms, [(1, [0, 2])], OverlapRule())
    assert out[1].equals(box(10, 0, 18, 10))
    assert out[0] is geoms[0] and out[2] is geoms[2]
    assert shared == [None]


def test_min_shared_leaves_small_overlaps_and_reports_the_shared_area():
    geoms = [box(0, 0, 10, 10), box(9.99, 0, 20, 10)]
    out, shared = resolve_overlaps(geoms, [(1, [0])], OverlapRule(min_shared=0.5))
    assert out[1] is geoms[1]
    assert shared[0] == pytest.approx(0.1)


def test_a_vanishing_loser_takes_the_area_from_its_winner_when_the_rule_swaps():
    big, inner = box(0, 0, 10, 10), box(2, 2, 4, 4)
    rule = OverlapRule(keep=lambda g: None if g.is_empty else g, min_shared=1e-6,
                       merge_winners=False, swap=True)
    out, _ = resolve_overlaps([big, inner], [(1, [0])], rule)
    assert out[1] is inner
    assert out[0].area == pytest.approx(96) and len(out[0].interiors) == 1
    # without swap the loser vanishes
    out, _ = resolve_overlaps([big, inner], [(1, [0])], OverlapRule(keep=rule.keep))
    assert out[1] is None


def test_a_swapping_rule_needs_one_winner_per_conflict():
    with pytest.raises(ValueError):
        OverlapRule(swap=True)


def test_later_conflicts_see_earlier_results():
    geoms = [box(0, 0, 10, 10), box(5, 0, 15, 10), box(12, 0, 25, 10)]
    out, _ = resolve_overlaps(geoms, [(1, [0]), (2, [1])], OverlapRule())
    assert out[1].equals(box(10, 0, 15, 10))
    assert out[2].equals(box(15, 0, 25, 10))
    assert shapely.union_all(out).area == pytest.approx(250)
