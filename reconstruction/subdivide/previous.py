"""The earlier epoch's footprints kept in a later map's plots (a dynamic chain, issue 28).

A block the two maps show unchanged keeps its buildings: the same
footprints, not a new random subdivision. With the earlier epoch's plots and
footprints (:class:`PreviousEpoch`), :func:`keep_previous` matches the plots
of the two maps (:func:`reconstruction.epochs.match_plots`, tolerant to the
later map's offset and drawing) and keeps:

- in an unchanged plot, every earlier footprint of it; the plot is not
  subdivided anew;
- in a changed plot (split, merged, extended, reduced, changed), the
  earlier footprints of its linked plots that still fit in it (at least
  :data:`FIT` of their area inside it, moved by the map's offset); the plot
  is subdivided anew and the new footprints are clipped around the kept ones;
- in a new plot, nothing.

An earlier footprint is never kept where today's register is aligned again:
an earlier aligned footprint whose BAG id is aligned in this epoch is the
same building, and the current one stands in for it. A kept footprint
keeps its geometry exactly (the map's offset is a drawing error, the
building did not move) and its identity (:func:`identities`).
"""

from dataclasses import dataclass, field
from typing import Optional

import numpy as np
import shapely

from ..core.contract import NEW_BUILDING, SOURCE_ALIGNED
from ..epochs import match_plots
from ..epochs.plots import NEW, TOLERANCE, UNCHANGED, PlotMatches
from .aligned_footprints import assign_plots

#: an earlier footprint fits in a changed plot with at least this share of its area in it
FIT = 0.9


@dataclass(frozen=True)
class PreviousEpoch:
    """The earlier epoch of a dynamic chain, as v.histo.subdivide reads it.

    Its ``plots`` (shapely geometries) and their ``cats``; its ``footprints``
    with, per footprint, the category of its ``plot`` (None: the plot it
    overlaps most), its building ``identity``, ``source`` and ``case``;
    ``columns``: the footprints' attribute table ({column: values}), for the
    kept footprints' own columns.
    """

    plots: list
    cats: list
    footprints: list
    plot: list
    identity: list
    source: list
    case: list
    bag_id: list = field(default_factory=list)
    columns: dict = field(default_factory=dict)


@dataclass(frozen=True)
class KeptFootprints:
    """What :func:`keep_previous` kept: the earlier footprints (``index`` into
    :attr:`PreviousEpoch.footprints`) and the later plot each is kept in
    (``plot``, a category); ``done``: the later plots kept whole (unchanged,
    not subdivided anew); ``change``: {later plot category: its kind of
    change}; ``matches``: the :class:`~reconstruction.epochs.PlotMatches`;
    ``realigned``: earlier aligned footprints whose BAG id is aligned again."""

    index: list
    plot: list
    done: set
    change: dict
    matches: Optional[PlotMatches] = None
    realigned: int = 0


def _earlier_plot_of(previous):
    """The earlier plot (index into ``previous.plots``) of every earlier footprint (-1: none)."""
    where = {c: k for k, c in enumerate(previous.cats)}
    plot = list(previous.plot)
    missing = [i for i, c in enumerate(plot) if c not in where]
    if missing and previous.plots:
        for i, c in zip(missing, assign_plots([previous.footprints[i] for i in missing],
                                              previous.plots, previous.cats)):
            plot[i] = c
    return np.array([where.get(c, -1) for c in plot], dtype=int)


def keep_previous(previous, plots, cats, aligned_ids=(), tolerance=TOLERANCE, fit=FIT):
    """The :class:`KeptFootprints` of ``previous`` (:class:`PreviousEpoch`) in the later
    ``plots`` (valid, disjoint, with their ``cats``); ``aligned_ids``: the BAG ids
    aligned in this epoch; ``tolerance``: the largest distance between the outlines
    of a plot drawn twice unchanged (map units)."""
    matches = match_plots(previous.plots, plots, tolerance=tolerance)
    earlier = _earlier_plot_of(previous)
    now = set(aligned_ids)
    realigned = {i for i, (s, b) in enumerate(zip(previous.source, previous.bag_id or
                                                  [None] * len(previous.source)))
                 if s == SOURCE_ALIGNED and b is not None and b in now}
    of_plot = {}                    # earlier plot index -> its footprints, realigned left out
    for i, p in enumerate(earlier.tolist()):
        if i not in realigned:
            of_plot.setdefault(p, []).append(i)
    footprints = np.array(previous.footprints, dtype=object)
    moved = shapely.transform(footprints, lambda xy: xy + np.asarray(matches.offset))
    area = shapely.area(footprints)
    best = {}                       # earlier footprint -> (share in its later plot, later plot)
    done, change = set(), {}
    for a, (kind, linked) in enumerate(zip(matches.change, matches.before)):
        change[cats[a]] = kind
        if kind == NEW:
            continue
        members = sorted(i for p in linked for i in of_plot.get(p, ()))
        if kind == UNCHANGED:
            done.add(cats[a])
            for i in members:
                best[i] = (2.0, cats[a])          # before any share of a changed plot
            continue
        if not members:
            continue
        share = shapely.area(shapely.intersection(moved[members], plots[a])) / np.maximum(
            area[members], 1e-12)
        for i, s in zip(members, share):
            if s >= fit and s > best.get(i, (0.0, None))[0]:
                best[i] = (float(s), cats[a])
    index = sorted(best)
    return KeptFootprints(index, [best[i][1] for i in index], done, change, matches,
                          len(realigned))


def identities(subdivision, previous, aligned_ids, year):
    """The building identity of every footprint of ``subdivision`` (a
    :class:`~reconstruction.subdivide.stage.Subdivision`): a kept footprint's
    earlier identity, an aligned footprint's BAG id (``aligned_ids`` by aligned
    index; None: none), else :data:`~reconstruction.core.contract.NEW_BUILDING`
    of ``year`` and its number (1-based, its category in the footprints map).
    A footprint split into pieces (clipped, repaired) gives its identity to the
    first piece; the others, and any other repeat, get ``_2``, ``_3``...
    """
    out, seen = [], {}
    for n, (kept, aligned) in enumerate(zip(subdivision.kept, subdivision.aligned), 1):
        if kept >= 0 and previous is not None:
            name = previous.identity[kept]
        elif aligned >= 0 and aligned < len(aligned_ids) and aligned_ids[aligned] is not None:
            name = str(aligned_ids[aligned])
        else:
            name = NEW_BUILDING.format(year=year, number=n)
        seen[name] = seen.get(name, 0) + 1
        out.append(name if seen[name] == 1 else "{}_{}".format(name, seen[name]))
    return out
