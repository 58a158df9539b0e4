"""The earlier epoch's footprints kept in a later map's plots (a dynamic chain, issue 28).

A block the two maps show unchanged keeps its buildings: the same
footprints, not a new random subdivision. With the earlier epoch's plots and
footprints (:class:`PreviousEpoch`), :func:`keep_previous` matches the plots
of the two maps (:func:`reconstruction.epochs.match_plots`, tolerant to the
later map's offset and drawing) and keeps:

- in an unchanged plot, every earlier footprint of it; the plot is not
  subdivided anew;
- elsewhere, every earlier footprint that the change of ground leaves
  standing: at least :data:`FIT` of its area (moved by the map's offset)
  still drawn as plot, not on ground that was plot and is not any more
  (:attr:`~reconstruction.epochs.PlotMatches.removed`: a demolished plot, a
  wide passage cut through), and not cut in two by a narrow passage (at
  least :data:`CUT` of it in each of two later plots), in the later plot it
  overlaps most. A difference thinner than the tolerance is the drawing,
  not a change, so a block one map draws a little smaller keeps its
  buildings whatever label its plot gets; and a building most of whose
  ground the later map still draws stands: two maps of one unchanged block
  can differ by more than any tolerance that still sees a new passage (one
  draws the end of a row 3 m long, the next 2 m short; a label refilled as
  street), and a building is a whole, not what lies under one map's outline;
- new footprints only on the ground that changed (:attr:`KeptFootprints.free`):
  a plot's ground that is new (:attr:`~reconstruction.epochs.PlotMatches.added`)
  or was under an earlier footprint not kept; the plot is subdivided anew and
  what is generated elsewhere in it is clipped away, as around an aligned
  footprint; a plot linked to no earlier one is subdivided whole.

An earlier footprint is never kept where today's register is aligned again:
an earlier aligned footprint whose BAG id is aligned in this epoch is the
same building, and the current one stands in for it. A kept footprint
keeps its geometry exactly (the map's offset is a drawing error, the
building did not move) and its identity (:func:`identities`).
"""

import re
from dataclasses import dataclass, field
from typing import Optional

import numpy as np
import shapely

from ..core.contract import BUILDING, NEW_BUILDING, SOURCE_ALIGNED
from ..core.errors import InputError
from ..core.register import column_named
from ..epochs import match_plots
from ..epochs.plots import NEW, TOLERANCE, UNCHANGED, PlotMatches
from .aligned_footprints import assign_plots

#: an earlier footprint stands with at least this share of its area still drawn as plot
#: (not on removed ground): most of it (calibrated on the synthetic town over time, seed 1:
#: 0.9 kept 1,593 of the 1,602 buildings of truth-unchanged plots, 0.5 keeps 1,596, and
#: every building of a demolished plot is dated right with both)
FIT = 0.5
#: an earlier footprint is cut in two by a passage with at least this share of it in each
#: of two later plots
CUT = 0.1


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
    ``realigned``: earlier aligned footprints whose BAG id is aligned again;
    ``free``: {later plot category: the ground of it to build anew (a shapely
    geometry, possibly empty)} of the plots neither unchanged nor new (a new
    plot is built anew whole)."""

    index: list
    plot: list
    done: set
    change: dict
    matches: Optional[PlotMatches] = None
    realigned: int = 0
    free: dict = field(default_factory=dict)


#: the identity of a footprint new in the epoch of a year (:data:`NEW_BUILDING`), that year
#: a group (a repeat's ``_2`` suffix aside)
_NEW_IN = re.compile("^" + re.escape(NEW_BUILDING).replace(re.escape("{year}"), r"(\d+)")
                     .replace(re.escape("{number}"), r"\d+") + r"(?:_\d+)?$")


def earlier_identities(columns, name, year):
    """The building identities (column ``building``) of the earlier epoch's footprints
    (map ``name``, previous=; ``columns``: its table), checked: InputError for a map
    without the column (not footprints of v.histo.subdivide year=: a plots map would
    be kept whole, as footprints) and for footprints new in an epoch not before
    ``year`` (the identities name the year of the map they were made on)."""
    named = column_named(columns, BUILDING)
    if named is None:
        raise InputError("Vector map <{}> (previous=) has no {} column: give the footprints "
                         "v.histo.subdivide made with year= of the earlier map".format(
                             name, BUILDING))
    made = [int(m.group(1)) for m in map(_NEW_IN.match, (str(v) for v in named if v)) if m]
    if made and max(made) >= year:
        raise InputError("Vector map <{}> (previous=) holds footprints made on the map of {}, "
                         "not before this map's year {} (year=): give the footprints of the "
                         "epoch before".format(name, max(made), year))
    return named


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


def keep_previous(previous, plots, cats, aligned_ids=(), tolerance=TOLERANCE, fit=FIT, cut=CUT):
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
    footprints = np.array(previous.footprints, dtype=object)
    moved = shapely.transform(footprints, lambda xy: xy + np.asarray(matches.offset))
    area = np.maximum(shapely.area(footprints), 1e-12)
    change = {cats[a]: kind for a, kind in enumerate(matches.change)}
    done = {cats[a] for a, kind in enumerate(matches.change) if kind == UNCHANGED}
    plot = {}                       # earlier footprint -> the later plot it is kept in
    unchanged = matches.unchanged()
    of_earlier = {}
    for i, p in enumerate(earlier.tolist()):
        of_earlier.setdefault(p, []).append(i)
    for a, b in unchanged.items():
        for i in of_earlier.get(b, ()):
            if i not in realigned:
                plot[i] = cats[a]
    rest = np.array([i for i in range(len(footprints)) if i not in plot and i not in realigned],
                    dtype=int)
    if len(rest) and len(plots):
        gone = shapely.area(shapely.intersection(moved[rest], matches.removed)) / area[rest]
        standing = rest[gone < 1.0 - fit]
        later = np.array(plots, dtype=object)
        f, a = shapely.STRtree(later).query(moved[standing], predicate="intersects")
        shared = shapely.area(shapely.intersection(moved[standing][f], later[a]))
        best, parts = {}, {}
        for k, j, s in zip(f.tolist(), a.tolist(), shared.tolist()):
            if s > best.get(k, (0.0, None))[0]:
                best[k] = (s, j)
            # a footprint a passage now cuts in two lies in two plots
            parts[k] = parts.get(k, 0) + (s >= cut * area[standing[k]])
        for k, (s, j) in best.items():
            if cats[j] not in done and parts[k] < 2:
                plot[int(standing[k])] = cats[j]
    index = sorted(plot)
    dropped = [i for i in range(len(footprints)) if i not in plot]
    freed = shapely.union_all(moved[dropped]) if dropped else shapely.Polygon()
    changed_ground = shapely.union(matches.added, freed)
    free = {cats[a]: shapely.intersection(plots[a], changed_ground)
            for a, kind in enumerate(matches.change) if kind not in (UNCHANGED, NEW)}
    return KeptFootprints(index, [plot[i] for i in index], done, change, matches,
                          len(realigned), free)


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
