"""Gable facades on the street end of convex footprints, in batch.

A roof with a gable facade (crow-stepped, neck, bell or spout gable) is a
gable roof over the main body of the footprint (an
:mod:`~reconstruction.lod2.roofs.envelope` roof of the footprint less a strip
of the facade's thickness along its street end) and, on that strip, a facade
slab whose outline rises above the body's gable profile, kept inside the
footprint. One builder makes the slab of any outline
(:func:`facade_arrays`); one outline function per profile
(:data:`OUTLINES`) draws its corners.
"""

from typing import Callable, NamedTuple

import numpy as np

from .model import RoofGroup

#: the gable profiles, in the order their groups are built
PROFILES = ("stepped", "neck", "bell", "spout")

#: a crow-stepped facade of more steps (a side) is no crow-stepped gable: the roof falls
#: back to a gable
MAX_STEPS = 64
#: the crown's corners stand on the profile at least this share of a step
#: height below its apex: on a straight gable the crown is then at least one
#: step's run wide (the run of the gable over one step height), the step below
#: it at least half a run
CROWN_DROP = 0.5
#: about the largest memory (bytes) of the facade arrays of one batch
BATCH_BYTES = 64 * 2 ** 20
#: a facade's outline stays this far (m) above the body's gable profile (a
#: crow-stepped one at most a quarter step), so that the slab's back face
#: is a proper polygon
MARGIN = 0.1
#: the shortest segment (m) of an outline, and the least distance along the
#: street edge between the points under its corners and the profile's nodes
MIN_SEGMENT = 0.02


def clip_strips(xy, ends, thickness):
    """Split convex footprints (G, n, 2) at distance ``thickness`` from their
    edge ``ends``.

    Returns ``(body, ok)``: the main body rings (G, n, 2), each starting
    with its inner edge (parallel to the end edge) and going on with the
    footprint's vertices after the end edge, and False where the strip would
    cut more than the two edges next to the end edge.
    """
    G, n, _ = xy.shape
    ends = np.asarray(ends, dtype=np.int64)
    ring = xy[np.arange(G)[:, None], (ends[:, None] + np.arange(n)) % n]   # end edge first
    a, b = ring[:, 0], ring[:, 1]
    t = (b - a) / np.hypot(*(b - a).T)[:, None]
    nrm = np.stack([-t[:, 1], t[:, 0]], axis=1)
    d = np.einsum("gkx,gx->gk", ring - a[:, None], nrm)
    ok = d[:, 2:].min(axis=1) > thickness + 0.05
    dd = np.where(ok[:, None], d, 1.0)
    body = ring.copy()
    body[:, 0] = a + (ring[:, -1] - a) * (thickness / dd[:, -1])[:, None]
    body[:, 1] = b + (ring[:, 2] - b) * (thickness / dd[:, 2])[:, None]
    return body, ok


def _interp_rows(x, xp, fp):
    """``np.interp`` row by row: ``x`` (G, Q) at the points ``xp`` (G, K)
    (non-decreasing in every row) with values ``fp`` (G, K), in one call
    (rows are shifted apart along the axis, so ``x`` must lie within its
    row's range)."""
    G = len(xp)
    if G == 0 or x.shape[1] == 0:
        return np.zeros(x.shape)
    span = float(max(np.abs(xp).max(), np.abs(x).max())) * 2.0 + 1.0
    off = (np.arange(G, dtype=float) * (2.0 * span))[:, None]
    return np.interp(x + off, (xp + off).ravel(), fp.ravel())


def _on_profile(rings, counts, profile, profile_u, points_u, points, width):
    """The body roof's faces ``rings`` (g, F, K) with ``counts`` (g, F) entries,
    with the ``points`` (roof vertex numbers, one row of (2Q,) or (g, 2Q)) at
    ``points_u`` (g, 2Q) along the inner edge (ascending) inserted into the
    profile edges they lie on.

    ``profile``: (g, K + 2) the profile's vertex numbers left to right (the
    inner edge's ends first and last, padded with the last) at ``profile_u``
    (g, K + 2). Each profile edge is an edge of one face of the body's roof;
    the points on it go into that face between its ends, in its direction.
    Returns ``(faces, counts)``, faces (g, F, ``width``).
    """
    g, F, K = rings.shape
    S = profile.shape[1] - 1
    pos = np.arange(K)
    valid = pos < counts[..., None]
    nxt = np.take_along_axis(rings, np.where(pos + 1 < counts[..., None], pos + 1, 0), axis=2)
    left, right = profile[:, None, None, :-1], profile[:, None, None, 1:]
    v, w = rings[..., None], nxt[..., None]
    forward = (v == left) & (w == right) & valid[..., None]
    backward = (v == right) & (w == left) & valid[..., None]
    on = forward | backward
    seg = np.argmax(on, axis=3)                                    # (g, F, K)
    # the points on each profile edge: a run of the ascending points
    edge = (profile_u[:, None, :] < points_u[:, :, None]).sum(axis=2) - 1     # (g, 2Q)
    per = np.zeros((g, S), dtype=np.int64)
    np.add.at(per, (np.arange(g)[:, None], edge), 1)
    first = np.cumsum(per, axis=1) - per
    rows = np.arange(g)[:, None, None]
    add = np.where(on.any(axis=3), per[rows, seg], 0)
    up = np.take_along_axis(forward, seg[..., None], axis=3)[..., 0]
    at = pos + np.cumsum(add, axis=2) - add                        # each entry's new place
    out = np.zeros((g, F, width), dtype=np.int64)
    gi, fi, ki = np.nonzero(valid)
    out[gi, fi, at[gi, fi, ki]] = rings[gi, fi, ki]
    gi, fi, ki = np.nonzero(add)
    c = add[gi, fi, ki]
    r = np.repeat(np.arange(len(c)), c)
    k = np.arange(len(r)) - np.repeat(np.cumsum(c) - c, c)       # 0 .. c - 1 in each run
    pick = np.where(up[gi, fi, ki][r], k, c[r] - 1 - k)          # in the face's direction
    points = np.broadcast_to(points, points_u.shape)
    out[gi[r], fi[r], at[gi, fi, ki][r] + 1 + k] = \
        points[gi[r], first[gi[r], seg[gi, fi, ki][r]] + pick]
    return out, counts + add.sum(axis=2)


class Bodies(NamedTuple):
    """The rows of :func:`facade_arrays`: footprints, street edges, body roofs
    and the bodies' gable profiles on their inner edges, as arrays (G rows)."""

    #: (G, n, 2) footprints
    xy: np.ndarray
    #: (G,) street edges
    ends: np.ndarray
    #: (G, 2) the street edge's ends
    a: np.ndarray
    b: np.ndarray
    #: (G, 2) its direction and inward normal
    t: np.ndarray
    nrm: np.ndarray
    #: (G, 2) the inner edge's ends (body vertices 0 and 1)
    qa: np.ndarray
    qb: np.ndarray
    #: the :class:`~reconstruction.lod2.roofs.envelope.Envelope` body roofs
    body: object
    #: (G,) profile nodes per row; (G, K) their places along the street
    #: edge (ascending, inf past ``T``) and body node numbers
    T: np.ndarray
    up: np.ndarray
    top_k: np.ndarray
    #: (G, K + 2) the profile (u, z) from the inner edge's start to its end,
    #: padded with its end
    pu: np.ndarray
    pz: np.ndarray
    #: (G,) its height and the index of its apex in ``pu``
    H: np.ndarray
    iapex: np.ndarray
    #: (G, K + 2) indices into ``pu`` of the profile up to its apex and
    #: from its end down to it (for :func:`_interp_rows` by height)
    rising: np.ndarray
    falling: np.ndarray
    #: (G,) the facade's ends along the street edge
    lo: np.ndarray
    hi: np.ndarray
    #: (G,) False where there is no gable profile to stand on
    ok: np.ndarray


def _bodies(xy, ends, body):
    """The :class:`Bodies` of footprints, street edges and body roofs (see
    :func:`facade_arrays`)."""
    xy = np.asarray(xy, dtype=float)
    G, n, _ = xy.shape
    ends = np.asarray(ends, dtype=np.int64)
    rows = np.arange(G)
    bxy, nodes, ring_idx, cnt = body.xy, body.nodes, body.faces, body.counts
    a = xy[rows, ends]
    b = xy[rows, (ends + 1) % n]
    L = np.hypot(*(b - a).T)
    t = (b - a) / L[:, None]
    nrm = np.stack([-t[:, 1], t[:, 0]], axis=1)
    qa, qb = bxy[:, 0], bxy[:, 1]
    # the gable profile on the inner edge: the face of the body's plane 0,
    # its nodes (roof vertices n + k) sorted along the edge
    prof = ring_idx[:, 0]
    K = prof.shape[1]
    is_top = (np.arange(K) < cnt[:, 0, None]) & (prof >= n)
    T = is_top.sum(axis=1)
    node_of = np.where(is_top, prof - n, 0)
    pts = nodes[rows[:, None], node_of]                             # (G, K, 3)
    up = np.where(is_top, np.einsum("gkx,gx->gk", pts[..., :2] - a[:, None], t), np.inf)
    order = np.argsort(up, axis=1, kind="stable")
    top_k = np.take_along_axis(node_of, order, axis=1)             # body node numbers
    up = np.take_along_axis(up, order, axis=1)
    zp = np.take_along_axis(pts[..., 2], order, axis=1)
    ua = np.einsum("gx,gx->g", qa - a, t)
    ub = np.einsum("gx,gx->g", qb - a, t)
    # profile (u, z), padded at the end with its last point
    col = np.arange(K + 2)
    inside = (col >= 1) & (col[None, :] <= T[:, None])
    src = np.clip(col - 1, 0, K - 1)
    pu = np.where(inside, up[:, src], ub[:, None])
    pz = np.where(inside, zp[:, src], 0.0)
    pu[:, 0], pz[:, 0] = ua, 0.0
    H = pz.max(axis=1)
    iapex = np.argmax(pz, axis=1)
    last = T + 1
    rising = np.minimum(col[None, :], iapex[:, None])
    falling = np.maximum(last[:, None] - col[None, :], iapex[:, None])
    lo, hi = np.maximum(0.0, ua), np.minimum(L, ub)
    ok = body.ok & (T > 0) & (H > 1e-3)
    return Bodies(xy, ends, a, b, t, nrm, qa, qb, body, T, up, top_k, pu, pz, H, iapex, rising,
                  falling, lo, hi, ok)


class Corners(NamedTuple):
    """Facade outlines of some rows, left to right along the street edge."""

    #: (g, M) corners (u along the street edge, z above the eaves), from
    #: (lo, 0) up to (lo, z), ..., down from (hi, z) to (hi, 0); the
    #: corners next to the ends at their heights (the outline starts and
    #: ends with a tread: the slab's first and last faces are horizontal)
    u: np.ndarray
    z: np.ndarray
    #: (g, U) the points of the body's profile under the inner corners
    #: (ascending in u; not at the profile's nodes)
    under_u: np.ndarray
    under_z: np.ndarray
    #: (g,) False where the outline cannot be built (the row falls out)
    ok: np.ndarray


class Outline(NamedTuple):
    """How one profile draws its facade outlines."""

    #: ``(bodies, rows, steps) -> (M, U)``: per row the number of corners and
    #: of points under them (0 corners: no facade)
    count: Callable
    #: ``(bodies, sel, steps, M) -> Corners`` of rows ``sel`` with M corners each
    draw: Callable


def facade_arrays(xy, ends, body, profiles, steps, thickness):
    """Gable facades on convex footprints with the same number of vertices,
    as arrays.

    ``xy``: (G, n, 2) footprints (local coordinates, counter-clockwise);
    ``ends``: (G,) index of the street edge; ``body``: the
    :class:`~reconstruction.lod2.roofs.envelope.Envelope` gable roofs (scaled to
    the roof height) of the main bodies from :func:`clip_strips` (inner edge
    first, vertical face on edge 0); ``profiles``: (G,) a name of
    :data:`PROFILES` each; ``steps``: (G,) crow-step heights (the stepped
    rows'; the others ignore theirs); ``thickness`` of the facade. The
    facade is a slab between the street edge and the inner edge whose
    outline (of :data:`OUTLINES`) rises above the body roof's gable profile.

    Returns a list of :class:`~reconstruction.lod2.roofs.model.RoofGroup`, per
    profile one per number of outline corners (in batches of about
    :data:`BATCH_BYTES`), named after the profile, whose ``index`` are rows of
    the input; their vertices past the footprint are the body roof's (its
    base, then its nodes), then the facade corners, then the points of the
    gable profile under the inner corners; ``wall_mid`` is set where the
    inner edge's ends lie on the edges next to the street edge. Rows whose
    facade cannot be built (too narrow for the outline, no gable profile)
    are in no group.

    The back face (between the profile and the outline) has a vertex on the
    profile under each inner corner, and the body roof's faces have them on
    their profile edges: without them the face's strip along the profile,
    one margin high, had no vertex below its inner corners but the
    profile's ends and apex, and its triangulation (val3dity's, after the
    millimetre rounding) had slivers of three nearly collinear inner corners
    whose normals deviate by more than 20 degrees on crow-stepped facades of
    some twenty steps or more.
    """
    bodies = _bodies(xy, ends, body)
    profiles = np.asarray(profiles, dtype=object)
    steps = np.asarray(steps, dtype=float)
    ring_idx = body.faces
    out = []
    for name in PROFILES:
        rows = np.nonzero(profiles == name)[0]
        if not len(rows):
            continue
        outline = OUTLINES[name]
        corners, unders = outline.count(bodies, rows, steps[rows])
        for M, U in np.unique(np.stack([corners, unders], axis=1)[corners > 0], axis=0):
            same = rows[(corners == M) & (unders == U)]
            # about 8 arrays of (rows, faces, face size) numbers of 8 bytes
            m = int(M) - 2
            size = (4 + m + ring_idx.shape[1]) * max(m + int(U) + 4 + ring_idx.shape[2], 4) * 64
            batch = max(1, BATCH_BYTES // size)
            for first in range(0, len(same), batch):
                sel = same[first:first + batch]
                drawn = outline.draw(bodies, sel, steps[sel], int(M))
                if drawn.ok.any():
                    out.append(_slab(name, bodies, sel, drawn, thickness))
    return out


def _slab(kind, bodies, sel, corners, thickness):
    """The :class:`~reconstruction.lod2.roofs.model.RoofGroup` of the facades of
    rows ``sel`` of the ``bodies`` with outlines ``corners`` (those rows whose
    outline is ok): the slab on the strip and the body roof but its face on
    the inner edge (see :func:`facade_arrays`)."""
    keep = corners.ok
    sel = sel[keep]
    cu, cz = corners.u[keep], corners.z[keep]
    under_u, under_z = corners.under_u[keep], corners.under_z[keep]
    g = len(sel)
    xy = bodies.xy
    n = xy.shape[1]
    a, b, t, nrm, qa, qb = (v[sel] for v in (bodies.a, bodies.b, bodies.t, bodies.nrm,
                                              bodies.qa, bodies.qb))
    bxy, nodes, ring_idx, cnt = (bodies.body.xy, bodies.body.nodes, bodies.body.faces,
                                 bodies.body.counts)
    C = nodes.shape[1]
    K = ring_idx.shape[2]
    nc = cu.shape[1]
    U = under_u.shape[1]
    # inner corners on the front (the street edge) and the back (inner edge)
    m = nc - 2
    fxy = a[:, None] + cu[:, 1:-1, None] * t[:, None]
    bk = fxy + (nrm * thickness)[:, None]
    fxy[:, 0], fxy[:, -1] = a, b
    bk[:, 0], bk[:, -1] = qa, qb
    # roof vertices: footprint, body roof (its base, then its nodes),
    # facade, the profile under its inner corners
    R = 2 * n + C + 2 * m + U
    roof = np.zeros((g, R, 3))
    roof[:, :n, :2] = xy[sel]
    roof[:, n:2 * n, :2] = bxy[sel]
    roof[:, 2 * n:2 * n + C] = nodes[sel]
    base = 2 * n + C
    roof[:, base:base + m, :2] = fxy
    roof[:, base + m:base + 2 * m, :2] = bk
    roof[:, base:base + m, 2] = cz[:, 1:-1]
    roof[:, base + m:base + 2 * m, 2] = cz[:, 1:-1]
    roof[:, base + 2 * m:, :2] = (a[:, None] + under_u[..., None] * t[:, None]
                                  + (nrm * thickness)[:, None])
    roof[:, base + 2 * m:, 2] = under_z
    under = base + 2 * m + np.arange(U)
    e = bodies.ends[sel]
    ia, ib = e, (e + 1) % n
    i_qa, i_qb = n, n + 1
    front = np.empty((g, m + 2), dtype=np.int64)
    front[:, 0], front[:, -1] = ia, ib
    front[:, 1:-1] = base + np.arange(m)
    back = np.empty((g, m + 2), dtype=np.int64)
    back[:, 0], back[:, -1] = i_qa, i_qb
    back[:, 1:-1] = base + m + np.arange(m)
    P = ring_idx.shape[1]
    Kb = ring_idx.shape[2]
    F = 4 + (m - 1) + (P - 1)
    Kf = max(m + 2 + K + U, Kb + U, 4)
    faces = np.zeros((g, F, Kf), dtype=np.int64)
    fcnt = np.zeros((g, F), dtype=np.int64)
    # front facade, seen from the street
    faces[:, 0, :m + 2] = front[:, ::-1]
    fcnt[:, 0] = m + 2
    # back face (towards the ridge): the gable profile with the points
    # under the inner corners (right to left), then the outline
    Tg = bodies.T[sel]
    Tu = Tg + U
    along = np.concatenate([bodies.up[sel], under_u], axis=1)     # inf past the T nodes
    ids = np.concatenate([bodies.top_k[sel] + 2 * n, np.broadcast_to(under, (g, U))], axis=1)
    prof_rev = np.take_along_axis(
        ids, np.argsort(np.where(np.isfinite(along), -along, np.inf), axis=1,
                        kind="stable"), axis=1)
    pos = np.arange(Kf)[None, :]
    outline = back[np.arange(g)[:, None], np.clip(pos - Tu[:, None], 0, m + 1)]
    faces[:, 1] = np.where(pos < Tu[:, None],
                           prof_rev[:, np.minimum(np.arange(Kf), K + U - 1)],
                           outline)
    fcnt[:, 1] = Tu + m + 2
    # side faces of the slab
    faces[:, 2, :4] = np.stack([ia, front[:, 1], back[:, 1], np.full(g, i_qa)], axis=1)
    faces[:, 3, :4] = np.stack([ib, np.full(g, i_qb), back[:, -2], front[:, -2]], axis=1)
    fcnt[:, 2:4] = 4
    # the slab's top: a face per outline segment (treads and risers)
    i = np.arange(1, m)
    faces[:, 4:4 + m - 1, :4] = np.stack([front[:, i], front[:, i + 1], back[:, i + 1],
                                          back[:, i]], axis=2)
    fcnt[:, 4:4 + m - 1] = 4
    # the body roof but its vertical face on the inner edge; its base vertices
    # beyond the inner edge are the footprint's
    k = ring_idx[sel, 1:]
    mapped = np.where((k >= 2) & (k < n), (e[:, None, None] + k) % n, n + k)
    bc = np.where(cnt[sel, 1:] >= 3, cnt[sel, 1:], 0)
    profile_ids = np.concatenate([np.full((g, 1), i_qa), 2 * n + bodies.top_k[sel],
                                  np.full((g, 1), i_qb)], axis=1)
    profile_ids[np.arange(K + 2)[None, :] > Tg[:, None]] = i_qb
    faces[:, 4 + m - 1:], fcnt[:, 4 + m - 1:] = _on_profile(
        mapped, bc, profile_ids, bodies.pu[sel], under_u, under, Kf)
    wall_mid = np.full((g, n), -1, dtype=np.int64)
    wall_mid[np.arange(g), (e - 1) % n] = i_qa
    wall_mid[np.arange(g), ib] = i_qb
    return RoofGroup(kind, sel, xy[sel], roof[:, n:], faces, fcnt, roof[..., 2].max(axis=1),
                     wall_mid)


# ---------------------------------------------------------------------------
# Outlines: one per profile
# ---------------------------------------------------------------------------

def _stepped_margin(steps):
    """The crow-stepped facade's margin above the profile: :data:`MARGIN`, at
    most a quarter step."""
    return np.minimum(MARGIN, steps / 4.0)


def _stepped_count(bodies, rows, steps):
    """``ceil((H + margin) / step)`` steps of 4 corners, one point under each
    of the 2 (steps - 1) inner corners; none of more than :data:`MAX_STEPS`."""
    with np.errstate(divide="ignore", invalid="ignore"):
        nsteps = np.ceil((bodies.H[rows] + _stepped_margin(steps)) / steps)
    ok = bodies.ok[rows] & np.isfinite(nsteps) & (nsteps <= MAX_STEPS)
    q = np.where(ok, nsteps, 0).astype(np.int64)
    return 4 * q, np.maximum(2 * q - 2, 0)


def _stepped_draw(bodies, sel, s, M):
    """The crow-stepped outline: treads at multiples of the step height ``s``,
    each step's corners where the profile is a margin below its tread."""
    Q = M // 4 - 1
    margin = _stepped_margin(s)
    H, pu, pz, lo, hi = (v[sel] for v in (bodies.H, bodies.pu, bodies.pz, bodies.lo, bodies.hi))
    rising, falling = bodies.rising[sel], bodies.falling[sel]
    # a step's corners stand where the profile is a margin below its
    # tread; the crown's (the top step's) at most CROWN_DROP steps below
    # the apex, lest the profile reach the tread's margin just below the
    # apex and make the crown a needle
    zq = np.minimum(np.arange(1, Q + 1, dtype=float)[None, :] * s[:, None] - margin[:, None],
                    (H - CROWN_DROP * s)[:, None])
    uL = _interp_rows(zq, np.take_along_axis(pz, rising, axis=1),
                      np.take_along_axis(pu, rising, axis=1))
    uR = _interp_rows(zq, np.take_along_axis(pz, falling, axis=1),
                      np.take_along_axis(pu, falling, axis=1))
    seq = np.concatenate([lo[:, None], uL, uR[:, ::-1], hi[:, None]], axis=1)
    wide = np.all(np.diff(seq, axis=1) >= MIN_SEGMENT, axis=1)
    g = len(sel)
    zs = np.arange(1, Q + 2, dtype=float)[None, :] * s[:, None]
    # outline of the stepped profile, left to right: (u, z) corners
    cu = np.empty((g, M))
    cz = np.empty((g, M))
    cu[:, 0] = cu[:, 1] = lo
    cz[:, 0], cz[:, 1] = 0.0, zs[:, 0]
    cu[:, 2:2 + 2 * Q:2] = uL
    cu[:, 3:3 + 2 * Q:2] = uL
    cz[:, 2:2 + 2 * Q:2] = zs[:, :Q]
    cz[:, 3:3 + 2 * Q:2] = zs[:, 1:Q + 1]
    k0 = 2 + 2 * Q
    cu[:, k0:k0 + 2 * Q:2] = uR[:, ::-1]
    cu[:, k0 + 1:k0 + 2 * Q:2] = uR[:, ::-1]
    cz[:, k0:k0 + 2 * Q:2] = zs[:, Q:0:-1]
    cz[:, k0 + 1:k0 + 2 * Q:2] = zs[:, Q - 1::-1] if Q else zs[:, :0]
    cu[:, -2] = cu[:, -1] = hi
    cz[:, -2], cz[:, -1] = zs[:, 0], 0.0
    # the profile under the inner corners, left to right (see _on_profile)
    under_u = np.concatenate([uL, uR[:, ::-1]], axis=1)
    under_z = np.concatenate([zq, zq[:, ::-1]], axis=1)
    return Corners(cu, cz, under_u, under_z, wide)


#: outlines by profile name
OUTLINES = {
    "stepped": Outline(_stepped_count, _stepped_draw),
}
