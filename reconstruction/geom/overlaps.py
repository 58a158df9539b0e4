"""Overlap resolution: one implementation, the policy as a parameter.

Three stages make overlapping geometries disjoint, each by its own rule:
generalised plots (:func:`reconstruction.generalize.operators.remove_overlaps`:
the later plot of a pair loses the shared area, or the earlier one when the
later would vanish), subdivision plots (the larger plot keeps the shared
area) and aligned footprints (earlier ones keep it). They share this loop:
a list of *conflicts*, ``(loser, winners)`` in the order they are resolved,
and an :class:`OverlapRule` that says how a loser gives up what it shares
with its winners. A conflict sees the geometries as earlier conflicts left
them.
"""

from dataclasses import dataclass
from typing import Callable, Optional

import shapely


def _as_is(geometry):
    return geometry


@dataclass(frozen=True)
class OverlapRule:
    """How a loser gives up what it shares with its winners.

    ``difference(loser, winners)`` is what is left of the loser and
    ``keep(left)`` its new geometry (None: it vanishes). ``min_shared``: a
    conflict whose loser shares at most this area with its winners (measured
    by ``intersection(loser, winners)``) is left alone; None resolves every
    conflict without measuring. ``merge_winners``: the winners are merged
    (``union_all``) first; else a conflict has exactly one winner, used as it
    is. ``swap``: when the loser would vanish, the winner loses the shared
    area instead (and when that would make it vanish too, both stay; one
    winner per conflict).
    """

    difference: Callable = shapely.difference
    keep: Callable = _as_is
    min_shared: Optional[float] = None
    intersection: Callable = shapely.intersection
    merge_winners: bool = True
    swap: bool = False

    def __post_init__(self):
        if self.swap and self.merge_winners:
            raise ValueError("an OverlapRule that swaps has one winner per conflict: "
                             "merge_winners=False")


def resolve_overlaps(geometries, conflicts, rule):
    """Resolve ``conflicts`` (``(loser, winners)`` pairs of indices) in order, by ``rule``.

    Returns ``(geometries, shared)``: a new list of the geometries (None for
    one that vanished) and, per conflict, the shared area measured (None
    when the rule measures none, or the loser had already vanished).
    """
    geoms = list(geometries)
    shared = []
    for loser, winners in conflicts:
        if geoms[loser] is None:
            shared.append(None)
            continue
        if rule.merge_winners:
            winner = shapely.union_all([geoms[w] for w in winners])
        else:
            (index,) = winners
            winner = geoms[index]
        area = None
        if rule.min_shared is not None:
            area = rule.intersection(geoms[loser], winner).area
        shared.append(area)
        if area is not None and area <= rule.min_shared:
            continue
        rest = rule.keep(rule.difference(geoms[loser], winner))
        if rest is None and rule.swap:
            rest = rule.keep(rule.difference(winner, geoms[loser]))
            if rest is not None:
                geoms[index] = rest
            continue
        geoms[loser] = rest
    return geoms, shared


def group_conflicts(pairs, rank):
    """Conflicts of overlapping ``pairs``: in each pair the lower ``rank`` wins.

    One conflict per loser, with its winners in the order of ``pairs``;
    losers in rank order, so a loser that wins elsewhere has lost its own
    share before it takes one.
    """
    winners = {}
    for a, b in pairs:
        winner, loser = (a, b) if rank[a] < rank[b] else (b, a)
        winners.setdefault(loser, []).append(winner)
    return [(loser, winners[loser]) for loser in sorted(winners, key=lambda i: rank[i])]
