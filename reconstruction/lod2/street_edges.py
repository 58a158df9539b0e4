"""The street edge of every footprint: where gable ends and stepped facades go.

The thesis's Section 3.4.2 (its ``find_facade_edge_idx``), in bulk. An edge
is **shared** when it lies within ``tol`` (0.1 m) of other footprints' edges
over at least ``share`` (half) of its length; a shared edge is never a street
edge. Then, per footprint:

1. one unshared edge: it;
2. a neighbour (a footprint sharing an edge) already has a street edge: the
   unshared edge nearly parallel to it (same direction within ``parallel``
   degrees: neighbours in a row run the same way round) whose middle is
   closest to the middle of the neighbour's;
3. otherwise a vote: the unshared edge in line (within ``align`` m) with the
   most unshared edges of the neighbours; a tie goes to 4;
4. the shortest unshared edge. The thesis's code takes the shortest of the
   unshared edges too (never a shared one, which is the point of the rule):
   a row house's narrow front is its shortest free edge.

``0`` is a footprint whose edges are all shared (enclosed in a block): it
has no street edge (index -1); the roof code falls back to its own choice.

Order: case 1 first (independent of order); then case 2 spreads in waves
from every footprint with a street edge to its unresolved neighbours, all of
a wave at once, so a row is resolved house by house from its known end; when
the waves stop, one footprint of every group of unresolved neighbours is
resolved by case 3 or 4 (the one with the clearest vote), and the waves go
on from there.

Beyond the thesis (its future work): the map knows where the streets are.
With ``streets`` (a classified :class:`reconstruction.geom.grid.Grid` and
``classes`` its street and water labels, or street polygons), a strip
``depth`` (3) m deep in front of each unshared edge is sampled: when one
edge has a ``majority`` (half) of street or water in front of it, it is the
street edge (case 5); when several do (a corner house), cases 2-4 choose
among those only; when none does, cases 2-4 as before.
"""

import math
from dataclasses import dataclass

import numpy as np

from ..core.errors import InputError
from ..geom.grid import Grid, expand_ranges
from ..geom.rings import components, offsets

ENCLOSED, ONE_FREE, FROM_NEIGHBOUR, VOTE, SHORTEST, STREETS = 0, 1, 2, 3, 4, 5


@dataclass(frozen=True)
class Edges:
    """Every edge of every ring, flat: edge ``k`` runs ``a[k] -> b[k]`` and is
    edge ``index[k]`` of ring ``ring[k]``; ring ``r``'s edges are
    ``start[r]:start[r + 1]``. ``length``, ``unit`` (direction) and ``middle``
    are computed once."""

    a: np.ndarray
    b: np.ndarray
    ring: np.ndarray
    index: np.ndarray
    start: np.ndarray
    length: np.ndarray
    unit: np.ndarray
    middle: np.ndarray

    @classmethod
    def of(cls, rings):
        counts = np.array([len(r) for r in rings], dtype=np.int64)
        start = offsets(counts)
        a = np.concatenate(rings, axis=0)[:, :2].astype(float) if len(rings) else np.zeros((0, 2))
        ring = np.repeat(np.arange(len(rings)), counts)
        index = np.arange(len(a)) - start[ring]
        nxt = np.where(index + 1 < counts[ring], np.arange(len(a)) + 1, start[ring])
        b = a[nxt]
        v = b - a
        length = np.hypot(v[:, 0], v[:, 1])
        unit = v / np.maximum(length, 1e-15)[:, None]
        return cls(a, b, ring, index, start, length, unit, 0.5 * (a + b))

    @property
    def vector(self):
        return self.b - self.a


@dataclass(frozen=True)
class StreetEdges:
    """Per ring: ``edge`` the street edge's index in the ring (-1: none) and
    ``case`` the rule that chose it (0-5, see the module doc); per edge (flat,
    :class:`Edges` order): ``covered`` its length within ``tol`` of other
    rings' edges and ``shared``; ``neighbours``: the pairs (r, s) of rings
    that touch (both ways)."""

    edge: np.ndarray
    case: np.ndarray
    edges: Edges
    covered: np.ndarray
    shared: np.ndarray
    neighbours: np.ndarray

    def shared_at(self, index):
        """Per ring: True when its edge ``index[r]`` (in the ring; -1 = none) is shared,
        e.g. the edge opposite the street edge, where a gable's other end goes."""
        index = np.asarray(index, dtype=np.int64)
        k = self.edges.start[:-1] + np.maximum(index, 0)
        return (index >= 0) & self.shared[k] if len(index) else np.zeros(0, dtype=bool)

    def edge_shared(self):
        """Per ring: True when its street edge is shared (never, by the rule)."""
        return self.shared_at(self.edge)

    def unshared_count(self):
        """Per ring: how many of its edges are not shared."""
        return np.bincount(self.edges.ring[~self.shared], minlength=len(self.edge))


# ---------------------------------------------------------------------------
# Shared edges
# ---------------------------------------------------------------------------

def _slab(c0, dc, lo, hi):
    """t-interval where lo <= c0 + t dc <= hi, (inf, -inf) when empty."""
    flat = np.abs(dc) < 1e-15
    with np.errstate(divide="ignore", invalid="ignore"):
        t1 = (lo - c0) / dc
        t2 = (hi - c0) / dc
    inside = (c0 >= lo) & (c0 <= hi)
    tmin = np.where(flat, np.where(inside, -np.inf, np.inf), np.minimum(t1, t2))
    tmax = np.where(flat, np.where(inside, np.inf, -np.inf), np.maximum(t1, t2))
    return tmin, tmax


def _disc(rx, ry, dx, dy, qa, tol):
    """t-interval where |(rx, ry) + t (dx, dy)| <= tol, (inf, -inf) when empty."""
    qb = rx * dx + ry * dy                      # half the linear coefficient
    qc = rx * rx + ry * ry - tol * tol
    disc = qb * qb - qa * qc
    ok = (disc >= 0) & (qa > 0)
    root = np.sqrt(np.where(ok, disc, 0.0))
    qa = np.where(qa > 0, qa, 1.0)
    return np.where(ok, (-qb - root) / qa, np.inf), np.where(ok, (-qb + root) / qa, -np.inf)


def covered_intervals(a, b, c, d, tol):
    """For segments ``a -> b`` (k, 2) and ``c -> d`` (k, 2): the interval of
    ``t`` in [0, 1] along ``a -> b`` that lies within ``tol`` of ``c -> d``
    (the line through a capsule, which is convex: one interval; empty when
    lo >= hi)."""
    ax, ay = a[:, 0], a[:, 1]
    dx, dy = b[:, 0] - ax, b[:, 1] - ay
    cx, cy = c[:, 0], c[:, 1]
    ex, ey = d[:, 0] - cx, d[:, 1] - cy
    ln = np.hypot(ex, ey)
    inv = 1.0 / np.maximum(ln, 1e-15)
    tx, ty = ex * inv, ey * inv
    rx, ry = ax - cx, ay - cy
    u_lo, u_hi = _slab(rx * tx + ry * ty, dx * tx + dy * ty, 0.0, ln)
    w_lo, w_hi = _slab(ry * tx - rx * ty, dy * tx - dx * ty, -tol, tol)
    lo, hi = np.maximum(u_lo, w_lo), np.minimum(u_hi, w_hi)
    empty = lo > hi
    lo[empty], hi[empty] = np.inf, -np.inf
    qa = dx * dx + dy * dy
    for ox, oy in ((rx, ry), (rx - ex, ry - ey)):
        d_lo, d_hi = _disc(ox, oy, dx, dy, qa, tol)
        lo, hi = np.minimum(lo, d_lo), np.maximum(hi, d_hi)
    return np.clip(lo, 0.0, 1.0), np.clip(hi, 0.0, 1.0)


def _candidate_pairs(edges, tol):
    """Edge pairs (i, j) of different rings whose boxes, grown by ``tol``, meet:
    one STRtree query of the rings' boxes, then for every ring pair the edges
    of each that meet the other's box, then a box test per edge pair."""
    import shapely

    x0 = np.minimum(edges.a[:, 0], edges.b[:, 0]) - tol
    x1 = np.maximum(edges.a[:, 0], edges.b[:, 0]) + tol
    y0 = np.minimum(edges.a[:, 1], edges.b[:, 1]) - tol
    y1 = np.maximum(edges.a[:, 1], edges.b[:, 1]) + tol
    first = edges.start[:-1]
    rx0, ry0 = np.minimum.reduceat(x0, first), np.minimum.reduceat(y0, first)
    rx1, ry1 = np.maximum.reduceat(x1, first), np.maximum.reduceat(y1, first)
    boxes = shapely.box(rx0, ry0, rx1, ry1)
    p, q = shapely.STRtree(boxes).query(boxes)
    keep = p != q
    p, q = p[keep], q[keep]

    def meeting(rings, other):
        k, row = expand_ranges(edges.start[rings], edges.start[rings + 1])
        o = other[row]
        ok = (x0[k] <= rx1[o]) & (rx0[o] <= x1[k]) & (y0[k] <= ry1[o]) & (ry0[o] <= y1[k])
        return k[ok], row[ok]

    i, ri = meeting(p, q)
    j, rj = meeting(q, p)
    nj = np.bincount(rj, minlength=len(p))
    sj = np.cumsum(nj) - nj
    jj, owner = expand_ranges(sj[ri], sj[ri] + nj[ri])
    i, j = i[owner], j[jj]
    meet = (x0[i] <= x1[j]) & (x0[j] <= x1[i]) & (y0[i] <= y1[j]) & (y0[j] <= y1[i])
    return i[meet], j[meet]


def edge_cover(edges, tol=0.1):
    """Per edge: its length within ``tol`` of other rings' edges; and the ring
    pairs (r, s), r != s, with edges within ``tol`` of each other over more
    than a millimetre."""
    import shapely

    E = len(edges.a)
    if E == 0:
        return np.zeros(0), np.zeros((0, 2), dtype=np.int64)
    tol = tol + 1e-7               # exactly tol away is within tol, whatever the rounding
    i, j = _candidate_pairs(edges, tol)
    # no part of edge j within tol of the line of edge i (or beyond its ends): no cover
    ux, uy = edges.unit[i, 0], edges.unit[i, 1]
    cx, cy = edges.a[j, 0] - edges.a[i, 0], edges.a[j, 1] - edges.a[i, 1]
    dx, dy = edges.b[j, 0] - edges.a[i, 0], edges.b[j, 1] - edges.a[i, 1]
    side_c, side_d = ux * cy - uy * cx, ux * dy - uy * dx
    along_c, along_d = ux * cx + uy * cy, ux * dx + uy * dy
    li = edges.length[i]
    near = ~(((side_c > tol) & (side_d > tol)) | ((side_c < -tol) & (side_d < -tol))
             | ((along_c < -tol) & (along_d < -tol)) | ((along_c > li + tol) & (along_d > li + tol)))
    i, j = i[near], j[near]
    lo, hi = covered_intervals(edges.a[i], edges.b[i], edges.a[j], edges.b[j], tol)
    good = hi > lo
    i, j, lo, hi = i[good], j[good], lo[good], hi[good]
    # the covered length of every edge: the union of its intervals
    order = np.argsort(2.0 * i + lo, kind="stable")
    i, j, lo, hi = i[order], j[order], lo[order], hi[order]
    reach = np.maximum.accumulate(hi + 2.0 * i) - 2.0 * i   # furthest end so far in the edge
    first = np.ones(len(i), dtype=bool)
    first[1:] = i[1:] != i[:-1]
    prev = np.where(first, 0.0, np.concatenate([[0.0], reach[:-1]]))
    gain = np.maximum(hi - np.maximum(lo, prev), 0.0)
    length = edges.length
    covered = np.bincount(i, weights=gain, minlength=E) * length
    touch = (hi - lo) * length[i] > 1e-3
    R = len(edges.start) - 1
    key = np.unique(edges.ring[i[touch]] * R + edges.ring[j[touch]])
    return covered, np.stack([key // R, key % R], axis=1)


# ---------------------------------------------------------------------------
# Streets in front of edges
# ---------------------------------------------------------------------------

def strip_fractions(edges, which, streets, classes=None, depth=3.0, step=None):
    """Per edge ``which`` (indices into ``edges``): the share of a strip ``depth``
    m deep in front of it (outside a counter-clockwise ring) that is street.

    ``streets``: a classified :class:`~reconstruction.geom.grid.Grid` (street =
    cells of ``classes``; NaN where the strip is outside the raster), or
    street polygons (shapely). Samples every ``step`` m (default: the cell
    size, or 1 m)."""
    which = np.asarray(which, dtype=np.int64)
    if not len(which):
        return np.zeros(0)
    is_grid = isinstance(streets, Grid)
    if step is None:
        step = min(streets.nsres, streets.ewres) if is_grid else 1.0   # a sample a cell
    a, v = edges.a[which], edges.vector[which]
    ln = edges.length[which]
    out = np.stack([v[:, 1], -v[:, 0]], axis=1) / np.maximum(ln, 1e-15)[:, None]
    n_along = np.maximum(np.ceil(ln / step).astype(np.int64), 1)
    n_deep = max(int(math.ceil(depth / step)), 1)
    k, owner = expand_ranges(np.zeros(len(which)), n_along * n_deep)
    along = (k // n_deep + 0.5) / n_along[owner]
    deep = (k % n_deep + 0.5) * depth / n_deep
    p = a[owner] + along[:, None] * v[owner] + deep[:, None] * out[owner]
    if is_grid:
        value = streets.sample(p[:, 0], p[:, 1])
        known = np.isfinite(value)
        hit = known & np.isin(value, np.asarray(classes, dtype=float))
    else:
        import shapely

        known = np.ones(len(p), dtype=bool)
        hit = np.zeros(len(p), dtype=bool)
        tree = shapely.STRtree(np.asarray(streets, dtype=object))
        inside, _ = tree.query(shapely.points(p), predicate="intersects")
        hit[inside] = True
    n_known = np.bincount(owner, weights=known, minlength=len(which))
    n_hit = np.bincount(owner, weights=hit, minlength=len(which))
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(n_known > 0, n_hit / n_known, np.nan)


# ---------------------------------------------------------------------------
# The four cases
# ---------------------------------------------------------------------------

def _first_per_group(groups, keys):
    """Index of the row with the smallest key in every group (rows sorted)."""
    order = np.lexsort((keys, groups))
    g = groups[order]
    first = np.concatenate([[True], g[1:] != g[:-1]]) if len(g) else np.zeros(0, bool)
    return order[first]


def _neighbour_edges(pairs, edges, rings_sel):
    """Rows (ring r, neighbour s, edge k of r) for the pairs whose r is selected."""
    p = pairs[rings_sel[pairs[:, 0]]]
    k, row = expand_ranges(edges.start[p[:, 0]], edges.start[p[:, 0] + 1])
    return p[row, 0], p[row, 1], k


def _propagate(edge_k, case, rows, edges, cos_par):
    """Case 2, in waves: unresolved rings next to a ring resolved in the last
    wave take their candidate edge nearly parallel to that ring's street edge
    with the closest middle. ``rows`` = (ring r, neighbour s, candidate edge k
    of r) for every neighbour pair."""
    rr, rs, rk = rows
    open_ = (edge_k < 0) & (case != ENCLOSED)
    new = edge_k >= 0
    while True:
        idx = np.nonzero(new[rs] & open_[rr])[0]
        if not len(idx):
            return
        r, k, ks = rr[idx], rk[idx], edge_k[rs[idx]]
        ok = np.einsum("ij,ij->i", edges.unit[k], edges.unit[ks]) >= cos_par
        if not ok.any():
            return
        r, k, ks = r[ok], k[ok], ks[ok]
        best = _first_per_group(r, np.hypot(*(edges.middle[k] - edges.middle[ks]).T))
        done = r[best]
        edge_k[done] = k[best]
        case[done] = FROM_NEIGHBOUR
        new = np.zeros(len(edge_k), dtype=bool)
        new[done] = True
        open_[done] = False


def _vote(rings_sel, candidate, free, pairs, edges, cos_par, align):
    """Case 3 for the selected rings: per candidate edge, the number of the
    neighbours' unshared edges in line with it. Returns the winning edge per
    ring (-1: no neighbour in line, or a tie) and the winner's margin."""
    R = len(rings_sel)
    r, s, k = _neighbour_edges(pairs, edges, rings_sel)
    keep = candidate[k]
    r, s, k = r[keep], s[keep], k[keep]
    win = np.full(R, -1, dtype=np.int64)
    margin = np.zeros(R)
    if not len(r):
        return win, margin
    # every unshared edge of the neighbour s
    k2, row = expand_ranges(edges.start[s], edges.start[s + 1])
    r2, k1 = r[row], k[row]
    use = free[k2]
    r2, k1, k2 = r2[use], k1[use], k2[use]
    unit = edges.unit
    normal = np.stack([-unit[:, 1], unit[:, 0]], axis=1)
    parallel = np.abs(np.einsum("ij,ij->i", unit[k1], unit[k2])) >= cos_par
    offset = np.abs(np.einsum("ij,ij->i", edges.middle[k1] - edges.a[k2], normal[k2]))
    inline = parallel & (offset <= align)
    votes = np.bincount(k1[inline], minlength=len(edges.a))
    # the best and the second best candidate edge of every ring
    cand = np.unique(k)
    rr = edges.ring[cand]
    v = votes[cand].astype(float)
    order = np.lexsort((-v, rr))
    cand, rr, v = cand[order], rr[order], v[order]
    top = np.nonzero(np.concatenate([[True], rr[1:] != rr[:-1]]))[0]
    nxt = np.minimum(top + 1, len(rr) - 1)
    second = np.where((top + 1 < len(rr)) & (rr[nxt] == rr[top]), v[nxt], 0.0)
    clear = (v[top] > 0) & (v[top] > second)
    win[rr[top[clear]]] = cand[top[clear]]
    margin[rr[top]] = v[top] - second
    return win, margin


def _components(n, pairs, members):
    """Connected component of every member ring over ``pairs`` restricted to
    members (numpy: importing scipy's graph module costs v.histo.lod2 more
    than finding the street edges)."""
    keep = members[pairs[:, 0]] & members[pairs[:, 1]]
    p = pairs[keep]
    return components(n, p[:, 0], p[:, 1])


def street_edges(rings, tol=0.1, share=0.5, parallel=20.0, align=0.5, streets=None,
                 classes=None, depth=3.0, majority=0.5):
    """The street edge of every ring (counter-clockwise (n, 2) arrays, as
    :func:`reconstruction.lod2.solids.build.clean_rings` gives them); see the module doc.

    ``streets``: optional classified :class:`~reconstruction.geom.grid.Grid` with
    ``classes`` its street and water labels, or street polygons; ``depth``
    the strip (m) sampled in front of each edge, ``majority`` the share of it
    that must be street or water. Returns :class:`StreetEdges`.
    """
    edges = Edges.of(rings)
    R = len(rings)
    covered, pairs = edge_cover(edges, tol)
    shared = (covered >= share * edges.length - 1e-9) & (edges.length > 0)
    free = ~shared & (edges.length > 0)
    n_free = np.bincount(edges.ring[free], minlength=R)
    edge_k = np.full(R, -1, dtype=np.int64)           # flat index of the street edge
    case = np.full(R, -1, dtype=np.int64)
    case[n_free == 0] = ENCLOSED
    one = n_free == 1
    k_free = np.nonzero(free)[0]
    lone = k_free[one[edges.ring[k_free]]]
    edge_k[edges.ring[lone]] = lone
    case[edges.ring[lone]] = ONE_FREE
    candidate = free.copy()
    if streets is not None:
        _street_case(edges, free, n_free, edge_k, case, candidate, streets, classes, depth,
                     majority)
    cos_par = math.cos(math.radians(parallel))
    r, n, k = _neighbour_edges(pairs, edges, np.ones(R, dtype=bool))
    rows = (r[candidate[k]], n[candidate[k]], k[candidate[k]])
    while True:
        _propagate(edge_k, case, rows, edges, cos_par)
        todo = case < 0
        if not todo.any():
            break
        win, margin = _vote(todo, candidate, free, pairs, edges, cos_par, align)
        # one ring per group of unresolved neighbours: the clearest vote, else the first
        label = _components(R, pairs, todo)
        idx = np.nonzero(todo)[0]
        key = np.where(win[idx] >= 0, -margin[idx], np.inf)
        seeds = idx[_first_per_group(label[idx], key)]
        voted = seeds[win[seeds] >= 0]
        edge_k[voted] = win[voted]
        case[voted] = VOTE
        rest = seeds[win[seeds] < 0]
        if len(rest):
            cand = np.nonzero(candidate & np.isin(edges.ring, rest))[0]
            best = cand[_first_per_group(edges.ring[cand], edges.length[cand])]
            edge_k[edges.ring[best]] = best
            case[edges.ring[best]] = SHORTEST
    index = np.where(edge_k >= 0, edge_k - edges.start[:-1], -1)
    return StreetEdges(index, case, edges, covered, shared, pairs)


def _street_case(edges, free, n_free, edge_k, case, candidate, streets, classes, depth,
                 majority):
    """Case 5 from a classified raster or street polygons; narrows ``candidate``
    to the edges that face a street where several do."""
    if isinstance(streets, Grid):
        classes = np.atleast_1d(np.asarray(classes if classes is not None else [], dtype=float))
        if not len(classes):
            raise InputError("Give the street and water classes of the streets raster")
        if not np.isin(np.asarray(streets.values, dtype=float), classes).any():
            raise InputError("The streets raster has no cells of the classes {}".format(
                ", ".join("{:g}".format(c) for c in classes)))
    else:
        import shapely

        streets = np.asarray(streets, dtype=object).ravel()
        kind = shapely.get_type_id(streets) if len(streets) else np.zeros(0)
        if not len(streets) or not np.isin(kind, (3, 6)).all():
            raise InputError("streets must be a classified raster (Grid) or street polygons "
                             "(buffer street lines first)")
    many = (n_free >= 2)[edges.ring] & free
    k = np.nonzero(many)[0]
    frac = strip_fractions(edges, k, streets, classes, depth)
    facing = k[np.nan_to_num(frac, nan=0.0) >= majority]
    n_facing = np.bincount(edges.ring[facing], minlength=len(edge_k))
    single = facing[n_facing[edges.ring[facing]] == 1]
    edge_k[edges.ring[single]] = single
    case[edges.ring[single]] = STREETS
    several = n_facing >= 2
    narrow = several[edges.ring] & free
    candidate[narrow] = False
    candidate[facing[several[edges.ring[facing]]]] = True
