"""The plots of two map epochs matched: which plot of the later map is which of the earlier.

Two maps of one town drawn decades apart show the same block a little
differently: the later sheet is georeferenced a metre or so off, and its
plots come out of another classification and generalisation. What changed
between the two dates must be told apart from how they were drawn:

1. :func:`estimate_offset`: the later map's offset against the earlier one,
   the median displacement of the plots that overlap one to one;
2. :func:`match_plots`: with the earlier plots moved by that offset, a
   later plot is *linked* to an earlier one when they share at least
   :data:`LINK_SHARE` of the smaller one's area. Each connected group of
   links is one change: one earlier and one later plot are ``unchanged``
   when they are the same outline up to the drawing (:func:`drawn_apart`
   of the two leaves less than :data:`MIN_CHANGE`), else ``extended`` or
   ``reduced`` (by area); one earlier plot and several later ones:
   ``split``; several and one: ``merged``; several and several:
   ``changed``; a later plot linked to none is ``new``, an earlier one
   linked to none is gone (demolished).
3. the ground that changed, whatever the plots' labels: what was plot on
   the earlier map and is not on the later (``removed``: demolished, cut
   by a new passage) and the other way round (``added``), each without what
   is thinner than ``tolerance`` (:func:`drawn_apart`). A building of the
   earlier map stands on the later one unless removed ground takes it.

Why not the outlines' Hausdorff distance or their intersection over union:
two classifications of one unchanged block differ by slivers along the
outline and a spike here and there (a symbol, a gap closed by the
generalisation), which move the Hausdorff distance by 5-10 m and the
intersection over union of a small plot below 0.7; a real change (a plot
grown into its garden, a passage cut through it) is a piece several metres
thick. Calibrated on the synthetic town over time (seed 1, 3 epochs, the
plots of the whole chain): see the README's dynamic-city section.

Pure: shapely 2 geometries and numpy, no GRASS.
"""

from dataclasses import dataclass

import numpy as np
import shapely

#: the kinds of change of a later plot (see the module doc)
UNCHANGED = "unchanged"
EXTENDED = "extended"
REDUCED = "reduced"
SPLIT = "split"
MERGED = "merged"
CHANGED = "changed"
NEW = "new"
KINDS = (UNCHANGED, EXTENDED, REDUCED, SPLIT, MERGED, CHANGED, NEW)

#: two plots are linked when they share at least this share of the smaller one's area
LINK_SHARE = 0.5
#: default width (map units) of the widest difference between two drawings of one
#: plot: what is thinner is the drawing, not a change
TOLERANCE = 4.0
#: the smallest change of a plot (map units²) once the drawing is taken out
MIN_CHANGE = 10.0
#: largest offset (map units) looked for between two maps of one town
MAX_OFFSET = 10.0
#: pairs that overlap one to one this much (IoU) measure the offset
OFFSET_IOU = 0.5
#: fewest such pairs that give an offset (fewer: no offset)
OFFSET_PAIRS = 3


@dataclass(frozen=True)
class PlotMatches:
    """How the later plots relate to the earlier ones.

    ``offset``: (dx, dy) of the later map against the earlier one (the
    earlier plots moved by it lie on the later ones); per later plot, its
    ``change`` (one of :data:`KINDS`), the indices of the earlier plots it
    is linked to (``before``, empty for a new plot) and its ``similarity``
    (intersection over union with those earlier plots moved by the
    offset, 0 for a new plot); ``gone``: the earlier plots linked to no
    later one (demolished); ``removed`` and ``added``: the ground (a
    shapely geometry, in the later map's frame) that was plot on the
    earlier map and is not on the later one, and the other way round,
    both without the drawing (:func:`drawn_apart`).
    """

    offset: tuple
    change: list
    before: list
    similarity: list
    gone: list
    removed: object = None
    added: object = None

    def counts(self):
        """{kind: number of later plots of that kind}, and ``gone``."""
        out = {k: 0 for k in KINDS}
        for c in self.change:
            out[c] += 1
        out["gone"] = len(self.gone)
        return out

    def unchanged(self):
        """{later plot index: its earlier plot index} of the unchanged plots."""
        return {j: b[0] for j, (c, b) in enumerate(zip(self.change, self.before))
                if c == UNCHANGED}


def _valid(geometries):
    geoms = np.array([g if g is not None else shapely.Polygon() for g in geometries],
                     dtype=object)
    return np.where(shapely.is_valid(geoms), geoms, shapely.make_valid(geoms))


def drawn_apart(geometry, tolerance=TOLERANCE):
    """What of ``geometry`` (a difference between two maps' plots) is a change rather
    than the drawing: ``geometry`` opened by half the ``tolerance`` (every part
    thinner than ``tolerance`` gone, the rest as it was; square joins keep its
    corners)."""
    if shapely.is_empty(geometry):
        return shapely.Polygon()
    r = tolerance / 2.0
    with np.errstate(divide="ignore", invalid="ignore"):   # GEOS's floating-point flags
        return shapely.buffer(shapely.buffer(geometry, -r, join_style="mitre"), r,
                              join_style="mitre")


def _overlaps(before, after):
    """The (earlier, later) index pairs whose plots intersect, and their shared areas."""
    if not len(before) or not len(after):
        return np.zeros(0, int), np.zeros(0, int), np.zeros(0)
    tree = shapely.STRtree(before)
    j, i = tree.query(after, predicate="intersects")
    shared = shapely.area(shapely.intersection(before[i], after[j]))
    return i, j, shared


def estimate_offset(before, after, max_offset=MAX_OFFSET):
    """The (dx, dy) of the later map's plots ``after`` against the earlier ``before``.

    The median displacement of the centroids of the plots that overlap one
    to one (intersection over union at least :data:`OFFSET_IOU`, each the
    other's only such partner), measured twice: the second time with the
    earlier plots moved by the first estimate, so that offsets of a plot's
    width are found too (a search ``max_offset`` wide). (0, 0) when fewer
    than :data:`OFFSET_PAIRS` pairs measure it.
    """
    before, after = _valid(before), _valid(after)
    offset = np.zeros(2)
    reach = [max_offset, max_offset / 2]
    for step in reach:
        moved = shapely.transform(before, lambda xy, d=offset: xy + d)
        grown = shapely.buffer(moved, step)
        tree = shapely.STRtree(grown)
        j, i = tree.query(after, predicate="intersects")
        if not len(i):
            break
        # how each pair overlaps once the earlier plot is moved onto the later one
        d = shapely.get_coordinates(shapely.centroid(after[j])) - shapely.get_coordinates(
            shapely.centroid(moved[i]))
        placed = _moved_each(moved[i], d)
        inter = shapely.area(shapely.intersection(placed, after[j]))
        iou = inter / np.maximum(shapely.area(placed) + shapely.area(after[j]) - inter, 1e-12)
        good = (iou >= OFFSET_IOU) & (np.hypot(d[:, 0], d[:, 1]) <= step)
        i, j, d, iou = i[good], j[good], d[good], iou[good]
        one_to_one = (np.bincount(i, minlength=len(before))[i] == 1) & (
            np.bincount(j, minlength=len(after))[j] == 1)
        if one_to_one.sum() < OFFSET_PAIRS:
            break
        offset = offset + np.median(d[one_to_one], axis=0)
    return float(offset[0]), float(offset[1])


def _moved_each(geometries, d):
    """Each geometry moved by its own displacement ``d[k]``."""
    index = shapely.get_coordinates(geometries, return_index=True)[1]
    return shapely.transform(geometries, lambda xy: xy + d[index])


def _components(n_before, n_after, i, j):
    """Connected groups of the links (earlier ``i[k]``, later ``j[k]``): a label per node,
    earlier plots first."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    n = n_before + n_after
    graph = coo_matrix((np.ones(len(i)), (i, n_before + j)), shape=(n, n))
    return connected_components(graph, directed=False)[1]


def match_plots(before, after, tolerance=TOLERANCE, offset=None):
    """The :class:`PlotMatches` of the later plots ``after`` with the earlier ``before``
    (shapely geometries; None counts as no plot).

    ``offset``: the later map's (dx, dy) against the earlier, None to
    estimate it (:func:`estimate_offset`); ``tolerance``: the width of the
    widest difference between two drawings of one plot (map units).
    """
    before, after = _valid(before), _valid(after)
    if offset is None:
        offset = estimate_offset(before, after)
    moved = shapely.transform(before, lambda xy: xy + np.asarray(offset))
    i, j, shared = _overlaps(moved, after)
    smaller = np.minimum(shapely.area(moved)[i], shapely.area(after)[j]) if len(i) else shared
    link = shared >= LINK_SHARE * np.maximum(smaller, 1e-12)
    i, j = i[link], j[link]
    label = _components(len(before), len(after), i, j)
    pairs = set(zip(i.tolist(), j.tolist()))
    groups = {}
    for b in range(len(before)):
        groups.setdefault(label[b], ([], []))[0].append(b)
    for a in range(len(after)):
        groups.setdefault(label[len(before) + a], ([], []))[1].append(a)
    change = [NEW] * len(after)
    linked = [()] * len(after)
    similarity = [0.0] * len(after)
    gone = []
    for earlier, later in groups.values():
        if not later:
            gone.extend(earlier)
            continue
        if not earlier:
            continue
        union = shapely.union_all(moved[earlier])
        for a in later:
            linked[a] = tuple(b for b in earlier if (b, a) in pairs)
            inter = shapely.area(shapely.intersection(union, after[a]))
            similarity[a] = float(inter / max(shapely.area(shapely.union(union, after[a])),
                                              1e-12))
        if len(earlier) == 1 and len(later) == 1:
            a, b = later[0], earlier[0]
            same = shapely.area(drawn_apart(shapely.symmetric_difference(moved[b], after[a]),
                                            tolerance)) < MIN_CHANGE
            change[a] = UNCHANGED if same else (
                EXTENDED if shapely.area(after[a]) > shapely.area(moved[b]) else REDUCED)
        else:
            kind = SPLIT if len(earlier) == 1 else MERGED if len(later) == 1 else CHANGED
            for a in later:
                change[a] = kind
    was, now = shapely.union_all(moved), shapely.union_all(after)
    return PlotMatches((float(offset[0]), float(offset[1])), change, linked, similarity,
                       sorted(gone), removed=drawn_apart(shapely.difference(was, now), tolerance),
                       added=drawn_apart(shapely.difference(now, was), tolerance))
