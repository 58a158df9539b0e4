"""Footprint outlines: the rings LoD2 buildings stand on, and what roofs need to know of them.

:func:`footprint_polygons` takes footprint geometries apart into polygons,
:func:`clean_rings` turns their exteriors into rings ready for extrusion
(millimetre grid, no duplicate or collinear vertices, counter-clockwise) and
:func:`rings_are_simple` finds the self-intersecting ones. The rest are facts
of a clean counter-clockwise ring (convexity, edge lengths, the street end
and the edge opposite it, the gable ends of concave footprints), in bulk
where the roofs need them in bulk (:func:`outline_facts`).
"""

import heapq
import math
from dataclasses import dataclass

import numpy as np

from ..geom.rings import following, preceding, ring_neighbours, starts


# ---------------------------------------------------------------------------
# Footprints ready for extrusion
# ---------------------------------------------------------------------------

@dataclass(frozen=True)
class FootprintPolygons:
    """The polygons of footprint geometries (see :func:`footprint_polygons`)."""

    #: (P,) shapely polygons
    polygons: np.ndarray
    #: (P,) index of the footprint of each polygon
    source: np.ndarray
    #: (P,) part number in a footprint of several polygons, -1 for a single polygon
    part: np.ndarray
    #: number of holes of all polygons
    holes: int
    #: number of missing or empty footprints
    empty: int


def footprint_polygons(geometries, skip=None):
    """The polygons to build on: every polygon of every footprint geometry
    (shapely Polygon or MultiPolygon; None, empty and other geometries are
    left out, as are footprints where ``skip`` is True), in bulk.

    Returns the :class:`FootprintPolygons`, by footprint.
    """
    import shapely

    geoms = np.empty(len(geometries), dtype=object)
    geoms[:] = list(geometries)
    empty = shapely.is_missing(geoms) | shapely.is_empty(geoms)
    use = ~empty
    if skip is not None:
        use &= ~np.asarray(skip, dtype=bool)
    idx = np.nonzero(use)[0]
    kind = shapely.get_type_id(geoms[idx])
    single = idx[kind == 3]
    multi = idx[kind == 6]
    parts, owner = shapely.get_parts(geoms[multi], return_index=True)
    count = shapely.get_num_geometries(geoms[multi])
    number = np.arange(len(parts)) - np.repeat(starts(count), count)
    polygons = np.concatenate([geoms[single], parts])
    source = np.concatenate([single, multi[owner]])
    part = np.concatenate([np.full(len(single), -1), np.where(count[owner] > 1, number, -1)])
    order = np.argsort(source, kind="stable")
    polygons, source, part = polygons[order], source[order], part[order].astype(np.int64)
    holes = int(shapely.get_num_interior_rings(polygons).sum()) if len(polygons) else 0
    return FootprintPolygons(polygons, source, part, holes, int(empty.sum()))


def clean_ring(coords, tol=0.001):
    """A footprint ring ready for extrusion, or ``(None, reason)``.

    ``coords``: (n, 2) exterior ring (closed or not). Rounds to the
    millimetre, removes duplicate and collinear vertices (closer than ``tol``
    to the line of their neighbours), orients counter-clockwise.
    Returns ``(xy, None)``.
    """
    xy = np.round(np.asarray(coords, dtype=float)[:, :2] * 1000.0) / 1000.0
    if len(xy) > 1 and np.all(xy[0] == xy[-1]):
        xy = xy[:-1]
    for _ in range(len(xy)):
        if len(xy) < 3:
            return None, "fewer than 3 distinct vertices"
        keep = np.any(xy != following(xy), axis=1)
        xy = xy[keep]
        if len(xy) < 3:
            return None, "fewer than 3 distinct vertices"
        prev = preceding(xy)
        nxt = following(xy)
        d = nxt - prev
        ln = np.hypot(d[:, 0], d[:, 1])
        cross = (xy[:, 0] - prev[:, 0]) * d[:, 1] - (xy[:, 1] - prev[:, 1]) * d[:, 0]
        dist = np.abs(cross) / np.maximum(ln, 1e-12)
        # a vertex on the line of its neighbours, or a spike (neighbours coincide)
        bad = (dist < tol) | (ln < tol)
        if not bad.any():
            break
        # remove one vertex at a time (the most collinear), then re-check
        xy = np.delete(xy, int(np.argmin(np.where(bad, dist, np.inf))), axis=0)
    if len(xy) < 3:
        return None, "fewer than 3 distinct vertices"
    area2 = float(np.sum(xy[:, 0] * following(xy[:, 1]) - following(xy[:, 0]) * xy[:, 1]))
    if abs(area2) < 1e-6:
        return None, "zero area"
    if area2 < 0:
        xy = xy[::-1].copy()
    return xy, None


def clean_rings(polygons, tol=0.001):
    """:func:`clean_ring` of the exterior of many shapely polygons, in bulk.

    Returns ``(rings, reasons)``: per polygon an (n, 2) ring or None, and the
    reason (or None). Rings that need no repair take a numpy fast path.
    """
    import shapely

    polygons = np.asarray(polygons, dtype=object)
    P = len(polygons)
    rings, reasons = [None] * P, [None] * P
    if P == 0:
        return rings, reasons
    coords, which = shapely.get_coordinates(shapely.get_exterior_ring(polygons), return_index=True)
    xy = np.round(coords * 1000.0) / 1000.0
    counts = np.bincount(which, minlength=P)
    first = starts(counts)
    closed = (counts > 1)
    closed[closed] = np.all(xy[first[closed]] == xy[(first + counts - 1)[closed]], axis=1)
    keep = np.ones(len(xy), dtype=bool)
    keep[(first + counts - 1)[closed]] = False
    xy, which = xy[keep], which[keep]
    dead = np.zeros(P, dtype=bool)
    # remove, in every ring at once, its worst vertex (a duplicate, else the
    # most collinear one) until no ring has any: as clean_ring, in bulk; the
    # few rings that still have some after a few passes (digitised curves:
    # thousands of vertices a fraction of a millimetre off the line) go on
    # one by one, with a heap (each pass here costs the vertices of all rings)
    for passes in range(int(counts.max(initial=0)) + 1):
        n = np.bincount(which, minlength=P)
        dead |= n < 3
        alive = ~dead[which]
        if not alive.all():
            xy, which = xy[alive], which[alive]
            n = np.bincount(which, minlength=P)
        before, after = ring_neighbours(n)
        prev, nxt = xy[before], xy[after]
        dup = np.all(xy == nxt, axis=1)
        d = nxt - prev
        ln = np.hypot(d[:, 0], d[:, 1])
        cross = (xy[:, 0] - prev[:, 0]) * d[:, 1] - (xy[:, 1] - prev[:, 1]) * d[:, 0]
        dist = np.abs(cross) / np.maximum(ln, 1e-12)
        bad = dup | (dist < tol) | (ln < tol)
        if not bad.any():
            break
        if passes == _BULK_PASSES:
            xy, which = _clean_one_by_one(xy, which, np.unique(which[bad]), tol)
            break
        score = np.where(dup, -1.0, np.where(bad, dist, np.inf))
        order = np.lexsort((score, which))
        first = np.ones(len(order), dtype=bool)
        first[1:] = which[order][1:] != which[order][:-1]
        drop = order[first & np.isfinite(score[order])]
        keep = np.ones(len(xy), dtype=bool)
        keep[drop] = False
        xy, which = xy[keep], which[keep]
    n = np.bincount(which, minlength=P)
    nidx = ring_neighbours(n)[1]
    nxt_x, nxt_y = xy[nidx, 0], xy[nidx, 1]
    area2 = np.bincount(which, weights=xy[:, 0] * nxt_y - nxt_x * xy[:, 1], minlength=P)
    parts = np.split(xy, np.cumsum(n)[:-1])
    for k in range(P):
        if dead[k] or n[k] < 3:
            reasons[k] = "fewer than 3 distinct vertices"
        elif abs(area2[k]) < 1e-6:
            reasons[k] = "zero area"
        else:
            rings[k] = parts[k] if area2[k] > 0 else parts[k][::-1].copy()
    return rings, reasons


#: passes of clean_rings over every ring before the rings still to clean go on one by one
_BULK_PASSES = 8


def _clean_one_by_one(xy, which, todo, tol):
    """The vertices ``xy`` of rings ``which`` (sorted) with the rings
    ``todo`` cleaned as :func:`clean_rings` does, one vertex at a time, with
    a heap of the removable vertices and their scores (duplicates first, then
    the most collinear; ties: the first vertex)."""
    first = np.searchsorted(which, todo)
    last = np.searchsorted(which, todo, side="right")
    keep = np.ones(len(xy), dtype=bool)
    for a, b in zip(first.tolist(), last.tolist()):
        keep[a:b] = _removable_kept(xy[a:b], tol)
    return xy[keep], which[keep]


def _removable_kept(xy, tol):
    """(n,) True for the vertices of one ring that stay (see :func:`_clean_one_by_one`)."""
    n = len(xy)
    x, y = xy[:, 0].tolist(), xy[:, 1].tolist()
    before = [(i - 1) % n for i in range(n)]
    after = [(i + 1) % n for i in range(n)]
    alive = [True] * n
    inf = float("inf")

    def score(i):
        p, q = before[i], after[i]
        if x[i] == x[q] and y[i] == y[q]:
            return -1.0
        dx, dy = x[q] - x[p], y[q] - y[p]
        ln = float(np.hypot(dx, dy))
        dist = abs((x[i] - x[p]) * dy - (y[i] - y[p]) * dx) / max(ln, 1e-12)
        return dist if dist < tol or ln < tol else inf

    current = [score(i) for i in range(n)]
    heap = [(c, i) for i, c in enumerate(current) if c < inf]
    heapq.heapify(heap)
    left = n
    while heap and left >= 3:
        c, i = heapq.heappop(heap)
        if not alive[i] or c != current[i]:
            continue
        alive[i] = False
        left -= 1
        p, q = before[i], after[i]
        after[p], before[q] = q, p
        for k in (p, q):
            current[k] = score(k)
            if current[k] < inf:
                heapq.heappush(heap, (current[k], k))
    return np.array(alive, dtype=bool)


def ring_is_simple(xy):
    """True when a ring (n, 2) does not self-intersect."""
    return bool(rings_are_simple([xy])[0])


def rings_are_simple(rings):
    """For each ring (n, 2): True when it does not self-intersect (in bulk)."""
    import shapely

    if not len(rings):
        return np.zeros(0, dtype=bool)
    counts = np.array([len(xy) for xy in rings])
    ends = np.cumsum(counts)
    flat = np.concatenate(rings)
    closed = np.insert(flat, ends, flat[ends - counts], axis=0)
    ids = np.repeat(np.arange(len(rings)), counts + 1)
    return shapely.is_simple(shapely.linearrings(closed, indices=ids))


# ---------------------------------------------------------------------------
# Facts of a clean ring
# ---------------------------------------------------------------------------

def edge_lengths(xy):
    """Lengths of the edges ``xy[i] -> xy[i+1]`` of one ring (n, 2)."""
    return np.hypot(*(following(xy) - xy).T)


def _edge_vectors(xy):
    """Edge vectors ``xy[i] -> xy[i+1]`` and lengths of rings (G, n, 2)."""
    d = np.roll(xy, -1, axis=1) - xy
    return d, np.hypot(d[..., 0], d[..., 1])


def convex_rings(xy, tol=1e-9):
    """(G,) True for counter-clockwise rings (G, n, 2) without a reflex vertex."""
    d2, l2 = _edge_vectors(xy)
    d1, l1 = np.roll(d2, 1, axis=1), np.roll(l2, 1, axis=1)
    cross = d1[..., 0] * d2[..., 1] - d1[..., 1] * d2[..., 0]
    return np.all(cross > -tol * l1 * l2, axis=1)


def opposite_edges(xy, ends):
    """(G,) for rings (G, n, 2): the edge most anti-parallel to edge
    ``ends[g]`` (more than 135 degrees) and not next to it, or -1."""
    G, n, _ = xy.shape
    ends = np.asarray(ends, dtype=np.int64)
    d, ln = _edge_vectors(xy)
    d = d / np.maximum(ln, 1e-300)[..., None]
    rows = np.arange(G)
    c = np.einsum("gjx,gx->gj", d, d[rows, ends])
    j = np.arange(n)[None, :]
    e = ends[:, None]
    c = np.where((j == e) | (j == (e - 1) % n) | (j == (e + 1) % n), np.inf, c)
    best = np.argmin(c, axis=1)
    return np.where(c[rows, best] < -math.cos(math.radians(45)), best, -1)


def is_convex(xy, tol=1e-9):
    """True when a counter-clockwise ring has no reflex vertex."""
    return bool(convex_rings(np.asarray(xy, dtype=float)[None], tol)[0])


def opposite_edge(xy, i):
    """The edge most anti-parallel to edge ``i`` and not adjacent to it, or None."""
    best = int(opposite_edges(np.asarray(xy, dtype=float)[None], [i])[0])
    return None if best < 0 else best


def end_edges(xy):
    """Gable ends of a concave footprint: edges between two convex corners that
    are shorter than both neighbouring edges (the ends of the L/U/T arms)."""
    n = len(xy)
    d1 = xy - preceding(xy)
    d2 = following(xy) - xy
    convex = d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0] > 0
    length = edge_lengths(xy)
    ends = []
    for i in range(n):
        if convex[i] and convex[(i + 1) % n] and length[i] < length[i - 1] \
                and length[i] < length[(i + 1) % n]:
            ends.append(i)
    return ends


def street_end(xy, street=None):
    """The street end of a footprint: ``street`` when given, else the shortest edge."""
    if street is not None and 0 <= int(street) < len(xy):
        return int(street)
    return int(np.argmin(edge_lengths(xy)))


@dataclass(frozen=True)
class OutlineFacts:
    """What the roofs need to know of footprint outlines, one entry per footprint."""

    #: True for a ring without a reflex vertex
    convex: np.ndarray
    #: the street end (see :func:`street_end`)
    end: np.ndarray
    #: length of the shortest edge
    shortest: np.ndarray
    #: length of the street end
    end_length: np.ndarray
    #: the edge opposite the street end (see :func:`opposite_edge`; -1 = none)
    opposite: np.ndarray


def outline_facts(footprints, street=None):
    """The :class:`OutlineFacts` of footprints (counter-clockwise rings; ``street``:
    optional street edge per footprint), in bulk: one numpy pass per vertex count."""
    B = len(footprints)
    out = OutlineFacts(convex=np.zeros(B, dtype=bool), end=np.zeros(B, dtype=np.int64),
                       shortest=np.zeros(B), end_length=np.zeros(B),
                       opposite=np.full(B, -1, dtype=np.int64))
    by_n = {}
    for i, xy in enumerate(footprints):
        by_n.setdefault(len(xy), []).append(i)
    for n, idx in by_n.items():
        idx = np.array(idx, dtype=np.int64)
        xy = np.stack([footprints[i] for i in idx]).astype(float)
        _, ln = _edge_vectors(xy)
        end = np.argmin(ln, axis=1)
        if street is not None:
            given = np.array([-1 if street[i] is None else int(street[i]) for i in idx])
            end = np.where((given >= 0) & (given < n), given, end)
        out.convex[idx] = convex_rings(xy)
        out.end[idx] = end
        out.shortest[idx] = ln.min(axis=1)
        out.end_length[idx] = ln[np.arange(len(idx)), end]
        out.opposite[idx] = opposite_edges(xy, end) if n > 3 else -1
    return out
