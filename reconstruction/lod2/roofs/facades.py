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


#: neck gable (halsgevel): the neck's half width, a share of the facade's
#: narrower side of the apex (the neck about 2/5 of a symmetric facade's width)
NECK_WIDTH = 0.4
#: the claw pieces' radius, a share of the neck's half width, and their segments
CLAW = 0.5
CLAW_SEGMENTS = 3
#: the neck's top (m) above the apex, and the least height of its sides (m)
NECK_TOP = 0.5
NECK_SIDE = 0.3
#: the triangular pediment's height, a share of the neck's half width (about 22 degrees)
PEDIMENT = 0.4
#: a neck's least half width and a shoulder's least width (m): narrower, no neck gable
MIN_NECK = 0.3
MIN_SHOULDER = 0.1
#: bell gable (klokgevel): the bell's half width at its foot, a share of the
#: facade's narrower side of the apex
BELL_WIDTH = 0.75
#: the bell's height: this share of the roof's rise over the bell, at least
#: BELL_ASPECT of its half width
BELL_RISE = 1.25
BELL_ASPECT = 0.8
#: the bell's left half, from its foot (0, 0) to its top (1, 1) as shares of
#: its half width and height: a hollow (concave) band rising steeply to a
#: waist, then a rounded (convex) top
BELL = np.array([[0.0, 0.0], [0.28, 0.10], [0.42, 0.35], [0.48, 0.62], [0.60, 0.85],
                 [0.80, 0.97], [1.0, 1.0]])
#: a bell's least half width (m)
MIN_BELL = 0.5
#: spout gable (tuitgevel): the spout's half width, a share of the facade's
#: narrower side of the apex, at least MIN_SPOUT (m)
SPOUT_WIDTH = 0.15
MIN_SPOUT = 0.2
#: the outline's rise (m) above the roof's slopes, the kneelers' width at
#: its feet (m), the spout's height (a share of its width)
SPOUT_LIFT = 0.25
KNEELER = 0.3
SPOUT_HEIGHT = 1.0
#: the least turn (degrees) of an outline at a corner: no three nearly
#: collinear corners (slivers in a face's triangulation)
MIN_TURN = 5.0


def _fixed_count(M, U):
    """The ``count`` of an outline of ``M`` corners and ``U`` points under them."""
    def count(bodies, rows, steps):
        ok = bodies.ok[rows]
        return np.where(ok, M, 0), np.where(ok, U, 0)
    return count


def _apex(bodies, sel):
    """``(lo, hi, uc, side, H)`` of rows ``sel``: the facade's ends, the
    apex's place along the street edge, the room on its narrower side and
    the profile's height."""
    lo, hi, H = bodies.lo[sel], bodies.hi[sel], bodies.H[sel]
    uc = np.take_along_axis(bodies.pu[sel], bodies.iapex[sel, None], axis=1)[:, 0]
    return lo, hi, uc, np.minimum(uc - lo, hi - uc), H


def _profile_at(bodies, sel, u):
    """The body's gable profile's height at ``u`` (g, Q) (within the inner edge)."""
    return _at(u, bodies.pu[sel], bodies.pz[sel])


def _at(x, xp, fp):
    """The polyline of corners ``(xp, fp)`` (g, K; ``xp`` non-decreasing) at
    ``x`` (g, Q) (within its row's range), row by row. Unlike
    :func:`_interp_rows` exactly the same whatever the other rows: a
    roof does not depend on the batch it is built in."""
    seg = np.clip((xp[:, None, :] <= x[:, :, None]).sum(axis=2) - 1, 0, xp.shape[1] - 2)
    x0, x1 = (np.take_along_axis(xp, seg + k, axis=1) for k in (0, 1))
    f0, f1 = (np.take_along_axis(fp, seg + k, axis=1) for k in (0, 1))
    run = x1 - x0
    share = np.where(run > 0, (x - x0) / np.where(run > 0, run, 1.0), 0.0)
    return f0 + share * (f1 - f0)


def _symmetric(lo, hi, uc, left_u, left_z, top_u, top_z, foot_l, foot_r):
    """The outline of corners: (lo, 0), (lo, foot_l), the ``left`` corners (g,
    k), the ``top`` ones (g, j; on the axis ``uc``), the left ones mirrored
    about ``uc`` in reverse order, (hi, foot_r), (hi, 0)."""
    g = len(lo)
    zero = np.zeros((g, 1))
    cu = np.concatenate([lo[:, None], lo[:, None], left_u, top_u,
                         (2.0 * uc[:, None] - left_u)[:, ::-1], hi[:, None], hi[:, None]], axis=1)
    cz = np.concatenate([zero, foot_l[:, None], left_z, top_z, left_z[:, ::-1],
                         foot_r[:, None], zero], axis=1)
    return cu, cz


def _drawn(bodies, sel, cu, cz, under_u, room):
    """The :class:`Corners` of an outline with the profile's points under
    ``under_u``, ok where there is ``room`` and the outline is sound
    (:func:`_sound`)."""
    under_z = _profile_at(bodies, sel, under_u)
    return Corners(cu, cz, under_u, under_z, room & _sound(bodies, sel, cu, cz, under_u))


def _sound(bodies, sel, cu, cz, under_u):
    """True for the rows whose outline a slab can stand on: it goes left to
    right (vertical segments allowed) in segments of :data:`MIN_SEGMENT` or
    more, turns by :data:`MIN_TURN` or more at every corner, starts and ends
    with a tread, stays :data:`MARGIN` above the profile (at its corners
    and the profile's nodes: both are piecewise linear), and its points on
    the profile are apart and off the profile's nodes."""
    du, dz = np.diff(cu, axis=1), np.diff(cz, axis=1)
    length = np.hypot(du, dz)
    ok = np.all(du >= 0.0, axis=1) & np.all(length >= MIN_SEGMENT, axis=1)
    cross = du[:, :-1] * dz[:, 1:] - dz[:, :-1] * du[:, 1:]
    ok &= np.all(np.abs(cross) >= np.sin(np.radians(MIN_TURN)) * length[:, :-1] * length[:, 1:],
                 axis=1)
    ok &= (cz[:, 2] == cz[:, 1]) & (cz[:, -3] == cz[:, -2])
    ok &= np.all(cz[:, 1:-1] >= _profile_at(bodies, sel, cu[:, 1:-1]) + MARGIN - 1e-9, axis=1)
    pu, pz = bodies.pu[sel], bodies.pz[sel]
    inside = (pu > cu[:, :1]) & (pu < cu[:, -1:])
    at = _at(np.clip(pu, cu[:, :1], cu[:, -1:]), cu, cz)
    ok &= np.all(~inside | (at >= pz + MARGIN - 1e-9), axis=1)
    ok &= np.all(np.diff(under_u, axis=1) >= MIN_SEGMENT, axis=1)
    ok &= np.all(np.abs(under_u[:, :, None] - pu[:, None, :]) >= MIN_SEGMENT, axis=(1, 2))
    return ok


def _neck_draw(bodies, sel, steps, M):
    """The neck gable: full-width shoulders a margin above the profile at the
    neck's sides, a claw piece (a quarter circle of :data:`CLAW_SEGMENTS`)
    in each corner between shoulder and neck, the neck's vertical sides up
    to :data:`NECK_TOP` above the apex and a triangular pediment."""
    lo, hi, uc, side, H = _apex(bodies, sel)
    w = NECK_WIDTH * side
    r = CLAW * w
    sides = np.stack([uc - w, uc + w], axis=1)
    z_sh = _profile_at(bodies, sel, sides).max(axis=1) + MARGIN
    angle = np.linspace(np.pi, np.pi / 2.0, CLAW_SEGMENTS + 1)
    claw_u = (uc - w)[:, None] + r[:, None] * np.cos(angle)
    claw_z = z_sh[:, None] + r[:, None] * np.sin(angle)
    claw_u[:, -1] = uc - w                      # exactly under the neck's side
    z_n = np.maximum(H + NECK_TOP, z_sh + r + NECK_SIDE)
    left_u = np.concatenate([claw_u, (uc - w)[:, None]], axis=1)
    left_z = np.concatenate([claw_z, z_n[:, None]], axis=1)
    cu, cz = _symmetric(lo, hi, uc, left_u, left_z, uc[:, None], (z_n + PEDIMENT * w)[:, None],
                        z_sh, z_sh)
    under_u = np.concatenate([claw_u, (2.0 * uc[:, None] - claw_u)[:, ::-1]], axis=1)
    room = (w >= MIN_NECK) & (side - w - r >= MIN_SHOULDER)
    return _drawn(bodies, sel, cu, cz, under_u, room)


def _bell_draw(bodies, sel, steps, M):
    """The bell gable: shoulders, then the :data:`BELL` curve on each side
    up to a rounded top on the apex, the whole lifted until it is a margin
    above the profile everywhere."""
    lo, hi, uc, side, H = _apex(bodies, sel)
    W = BELL_WIDTH * side
    feet = np.stack([uc - W, uc + W], axis=1)
    rise = H - _profile_at(bodies, sel, feet).max(axis=1)
    hb = np.maximum(BELL_RISE * rise, BELL_ASPECT * W)
    left_u = (uc - W)[:, None] + W[:, None] * BELL[None, :-1, 0]
    left_z = hb[:, None] * BELL[None, :-1, 1]
    bell_u = np.concatenate([left_u, uc[:, None], (2.0 * uc[:, None] - left_u)[:, ::-1]], axis=1)
    bell_z = np.concatenate([left_z, hb[:, None], left_z[:, ::-1]], axis=1)
    # the foot's height: the bell a margin above the profile at its corners
    # and at the profile's nodes under it
    need = (_profile_at(bodies, sel, bell_u) + MARGIN - bell_z).max(axis=1)
    pu, pz = bodies.pu[sel], bodies.pz[sel]
    under = (pu > bell_u[:, :1]) & (pu < bell_u[:, -1:])
    at = _at(np.clip(pu, bell_u[:, :1], bell_u[:, -1:]), bell_u, bell_z)
    need = np.maximum(need, np.where(under, pz + MARGIN - at, -np.inf).max(axis=1))
    z_sh = np.maximum(need, MARGIN)
    cu, cz = _symmetric(lo, hi, uc, left_u, z_sh[:, None] + left_z, uc[:, None],
                        (z_sh + hb)[:, None], z_sh, z_sh)
    under_u = np.concatenate([left_u, (2.0 * uc[:, None] - left_u)[:, ::-1]], axis=1)
    room = (W >= MIN_BELL) & (side - W >= MIN_SHOULDER)
    return _drawn(bodies, sel, cu, cz, under_u, room)


def _spout_draw(bodies, sel, steps, M):
    """The spout gable: from a kneeler at each end, a straight line
    :data:`SPOUT_LIFT` above the roof's slope (lifted over any node of the
    profile under it) up to the spout's foot, the spout's vertical sides and
    its flat crown."""
    lo, hi, uc, side, H = _apex(bodies, sel)
    ws = np.maximum(SPOUT_WIDTH * side, MIN_SPOUT)
    knee = np.stack([lo + KNEELER, hi - KNEELER], axis=1)
    foot = np.stack([uc - ws, uc + ws], axis=1)
    z_knee = _profile_at(bodies, sel, knee) + SPOUT_LIFT
    z_foot = np.repeat(_profile_at(bodies, sel, foot).max(axis=1, keepdims=True), 2,
                       axis=1) + SPOUT_LIFT
    # the slopes' lines a lift above the profile's nodes between kneeler and foot
    pu, pz = bodies.pu[sel], bodies.pz[sel]
    for k in (0, 1):
        a_u, b_u = np.minimum(knee[:, k], foot[:, k]), np.maximum(knee[:, k], foot[:, k])
        span = np.where(np.abs(foot[:, k] - knee[:, k]) > 0, foot[:, k] - knee[:, k], 1.0)
        share = np.clip((pu - knee[:, k, None]) / span[:, None], 0.0, 1.0)
        line = z_knee[:, k, None] + share * (z_foot[:, k] - z_knee[:, k])[:, None]
        between = (pu > a_u[:, None]) & (pu < b_u[:, None])
        lift = np.maximum(np.where(between, pz + SPOUT_LIFT - line, 0.0).max(axis=1), 0.0)
        z_knee[:, k] += lift
        z_foot[:, k] += lift
    z_foot = np.repeat(z_foot.max(axis=1, keepdims=True), 2, axis=1)
    z_top = np.maximum(z_foot[:, 0] + SPOUT_HEIGHT * 2.0 * ws, H + SPOUT_LIFT)
    g = len(sel)
    zero = np.zeros(g)
    cu = np.stack([lo, lo, knee[:, 0], foot[:, 0], foot[:, 0], foot[:, 1], foot[:, 1], knee[:, 1],
                   hi, hi], axis=1)
    cz = np.stack([zero, z_knee[:, 0], z_knee[:, 0], z_foot[:, 0], z_top, z_top, z_foot[:, 1],
                   z_knee[:, 1], z_knee[:, 1], zero], axis=1)
    under_u = np.concatenate([knee[:, :1], foot, knee[:, 1:]], axis=1)
    room = knee[:, 0] + MIN_SEGMENT <= foot[:, 0]
    return _drawn(bodies, sel, cu, cz, under_u, room & (foot[:, 1] + MIN_SEGMENT <= knee[:, 1]))


#: outlines by profile name
OUTLINES = {
    "stepped": Outline(_stepped_count, _stepped_draw),
    "neck": Outline(_fixed_count(9 + 2 * CLAW_SEGMENTS, 2 * (CLAW_SEGMENTS + 1)),
                    _neck_draw),
    "bell": Outline(_fixed_count(4 + 2 * len(BELL) - 1, 2 * (len(BELL) - 1)), _bell_draw),
    "spout": Outline(_fixed_count(10, 4), _spout_draw),
}
