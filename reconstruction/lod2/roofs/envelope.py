"""Roofs of convex footprints: the lower envelope of the edge planes, in batch.

The straight skeleton of a convex polygon is the lower envelope of its edge
planes: every skeleton node is the intersection of three planes (sloped edge
planes, vertical gable planes, the flat mansard top) that lies on the
envelope, so all footprints with the same number of vertices are solved in
one numpy pass. Hip, gable and mansard roofs of convex footprints and the
main body behind a crow-stepped facade are envelopes.

Every triple of planes is a candidate node, so the work grows with the
fourth power of the number of vertices: footprints of at most
:data:`MAX_VERTICES` are solved here (larger convex ones go to the straight
skeleton), in batches of at most :data:`BATCH_BYTES` of arrays.
"""

import itertools
from dataclasses import dataclass

import numpy as np

from .model import RoofGroup

_TOL = 1e-6
#: convex footprints of more vertices get their roof from the straight skeleton
MAX_VERTICES = 24
#: about the largest memory (bytes) of one call of :func:`envelope_arrays`
BATCH_BYTES = 64 * 2 ** 20


def batch_rows(n, has_top=False, raised=0):
    """How many footprints of ``n`` vertices :func:`envelope_arrays` solves
    at once within :data:`BATCH_BYTES` (its largest arrays hold about 16
    numbers of 8 bytes per plane and candidate point), with a flat top or not
    and ``raised`` planes."""
    P = n + int(has_top) + raised
    C = P * (P - 1) * (P - 2) // 6
    return max(1, BATCH_BYTES // (16 * 8 * P * (C + 2 + n)))


@dataclass(frozen=True)
class Envelope:
    """Envelope roofs of B convex footprints with the same number of vertices n."""

    #: (B, n, 2) the footprints (local coordinates, counter-clockwise)
    xy: np.ndarray
    #: (B, C, 3) skeleton node candidates (z relative to the eaves); roof vertex n + c is node c
    nodes: np.ndarray
    #: (B, P, K) one face per plane: the first ``counts`` entries are roof vertex numbers
    faces: np.ndarray
    #: (B, P) entries in use per face
    counts: np.ndarray
    #: (B,) height of the highest node
    zmax: np.ndarray
    #: (B,) False for degenerate input (an edge without a face)
    ok: np.ndarray

    def take(self, rows):
        """The envelopes ``rows``."""
        return Envelope(self.xy[rows], self.nodes[rows], self.faces[rows], self.counts[rows],
                        self.zmax[rows], self.ok[rows])

    def scaled_to(self, height):
        """The envelopes with their highest node at ``height`` (B,) (where ok)."""
        factor = np.where(self.ok, height / np.where(self.zmax > 0, self.zmax, 1.0), 0.0)
        nodes = self.nodes.copy()
        nodes[..., 2] *= factor[:, None]
        return Envelope(self.xy, nodes, self.faces, self.counts,
                        np.where(self.ok, height, 0.0), self.ok)

    def group(self, index, rows):
        """The envelopes ``rows`` as a :class:`~reconstruction.lod2.roofs.model.RoofGroup`
        of the footprints ``index``."""
        return RoofGroup("envelope", index, self.xy[rows], self.nodes[rows], self.faces[rows],
                         self.counts[rows], self.zmax[rows])


@dataclass(frozen=True)
class Raised:
    """Planes that rise from a line parallel to a footprint edge, above the
    eaves: plane ``k`` of row ``b`` is ``z = height + slope * d(x)``, ``d`` the
    distance inside from edge ``edge`` (all (B, E) arrays). Over a vertical
    gable end it cuts the gable's top (a half-hip); beside a steep edge plane
    it is the upper, flatter slope of a gambrel."""

    edge: np.ndarray
    slope: np.ndarray
    height: np.ndarray


def envelope_arrays(xy, slopes, top=None, raised=None):
    """Roofs over convex footprints with the same number of vertices, as arrays.

    ``xy``: (B, n, 2) counter-clockwise footprints in local coordinates;
    ``slopes``: (B, n) tangent of each edge's pitch, ``inf`` for a vertical
    (gable) end; ``top``: (B,) height of a flat top (mansard) or None;
    ``raised``: :class:`Raised` planes (the same number in every row) or None.
    Returns the :class:`Envelope` (unscaled: the ridge is where the slopes
    put it); a plane with no part in the roof has no face (fewer than 3
    entries).
    """
    xy = np.asarray(xy, dtype=float)
    B, n, _ = xy.shape
    slopes = np.asarray(slopes, dtype=float)
    has_top = top is not None
    E = 0 if raised is None else np.asarray(raised.edge).shape[1]
    T = n + int(has_top)                                       # the raised planes' first row
    P = T + E
    nxt = np.roll(xy, -1, axis=1)
    t = nxt - xy
    length = np.hypot(t[..., 0], t[..., 1])
    t = t / np.maximum(length, 1e-300)[..., None]
    nrm = np.stack([-t[..., 1], t[..., 0]], axis=-1)          # inward normals
    c = np.einsum("bij,bij->bi", nrm, xy)                      # d_j(x) = nrm.x - c
    vertical = ~np.isfinite(slopes)
    s = np.where(vertical, 1.0, slopes)
    # plane rows a.x = r
    rows = np.zeros((B, P, 3))
    rhs = np.zeros((B, P))
    rows[:, :n, 0] = np.where(vertical, nrm[..., 0], s * nrm[..., 0])
    rows[:, :n, 1] = np.where(vertical, nrm[..., 1], s * nrm[..., 1])
    rows[:, :n, 2] = np.where(vertical, 0.0, -1.0)
    rhs[:, :n] = np.where(vertical, c, s * c)
    if has_top:
        top = np.asarray(top, dtype=float)
        rows[:, n, 2] = 1.0
        rhs[:, n] = top
    if E:
        r_edge = np.asarray(raised.edge, dtype=np.int64)
        r_slope = np.asarray(raised.slope, dtype=float)
        r_height = np.asarray(raised.height, dtype=float)
        r_nrm = np.take_along_axis(nrm, r_edge[..., None], axis=1)           # (B, E, 2)
        r_c = np.take_along_axis(c, r_edge, axis=1)
        rows[:, T:, :2] = r_slope[..., None] * r_nrm
        rows[:, T:, 2] = -1.0
        rhs[:, T:] = r_slope * r_c - r_height
    norm = np.linalg.norm(rows, axis=-1)
    rows_u = rows / norm[..., None]
    rhs_u = rhs / norm
    combos = np.array(list(itertools.combinations(range(P), 3)), dtype=int)
    C = len(combos)
    M = rows_u[:, combos]                                      # (B, C, 3, 3)
    r = rhs_u[:, combos]                                       # (B, C, 3)
    det = np.linalg.det(M)
    ok = np.abs(det) > 1e-9
    M = np.where(ok[..., None, None], M, np.eye(3))
    nodes = np.linalg.solve(M, r[..., None])[..., 0]            # (B, C, 3)
    # distances of the nodes to every edge line and plane values
    d = np.einsum("bcx,bjx->bcj", nodes[..., :2], nrm) - c[:, None, :]   # (B, C, n)
    plane_z = np.where(vertical[:, None, :], np.inf, s[:, None, :] * d)
    env = plane_z.min(axis=-1)
    if has_top:
        env = np.minimum(env, top[:, None])
    if E:
        d_r = np.einsum("bcx,bex->bce", nodes[..., :2], r_nrm) - r_c[:, None, :]   # (B, C, E)
        raised_z = r_height[:, None, :] + r_slope[:, None, :] * d_r
        env = np.minimum(env, raised_z.min(axis=-1))
    z = nodes[..., 2]
    scale = 1.0 + np.abs(xy).max(axis=(1, 2))[:, None]
    tol = _TOL * scale
    valid = ok & (d.min(axis=-1) > -tol) & (z > tol) & (np.abs(z - env) < tol * (1 + np.abs(env)))
    active = np.empty((B, C, P), dtype=bool)
    active[..., :n] = np.where(vertical[:, None, :], np.abs(d) < tol[..., None],
                               np.abs(plane_z - z[..., None]) < tol[..., None] * (1 + np.abs(z[..., None])))
    if has_top:
        active[..., n] = np.abs(z - top[:, None]) < tol * (1 + np.abs(z))
    if E:
        active[..., T:] = np.abs(raised_z - z[..., None]) < tol[..., None] * (1 + np.abs(z[..., None]))
    active &= valid[..., None]
    # candidate points of every face: 2 base vertices + C nodes
    K = C + 2
    pts = np.zeros((B, P, K, 3))
    mask = np.zeros((B, P, K), dtype=bool)
    j = np.arange(n)
    pts[:, :n, 0, :2] = xy
    pts[:, :n, 1, :2] = nxt
    mask[:, :n, :2] = True
    pts[:, :, 2:, :] = nodes[:, None, :, :]
    mask[:, :, 2:] = np.transpose(active, (0, 2, 1))
    cnt = mask.sum(axis=-1)
    centre = (pts * mask[..., None]).sum(axis=2) / np.maximum(cnt, 1)[..., None]
    rel = pts - centre[:, :, None, :]
    # sorting coordinates: xy for sloped faces and the top, (u, z) for vertical ones
    a1 = rel[..., 0].copy()
    a2 = rel[..., 1].copy()
    vert_faces = np.zeros((B, P), dtype=bool)
    vert_faces[:, :n] = vertical
    tt = np.zeros((B, P, 2))
    tt[:, :n] = t
    u = rel[..., 0] * tt[..., 0][..., None] + rel[..., 1] * tt[..., 1][..., None]
    a1 = np.where(vert_faces[..., None], u, a1)
    a2 = np.where(vert_faces[..., None], rel[..., 2], a2)
    ang = np.arctan2(a2, a1)
    ang = np.where(mask, ang, np.inf)
    order = np.argsort(ang, axis=-1, kind="stable")
    # vertex index of each candidate: base j, j+1 -> j, (j+1)%n; node k -> n + k
    index = np.empty((P, K), dtype=int)
    index[:, 2:] = n + np.arange(C)
    index[:n, 0] = j
    index[:n, 1] = (j + 1) % n
    index[n:, :2] = -1
    ring_idx = np.take_along_axis(np.broadcast_to(index, (B, P, K)), order, axis=-1)
    zmax = np.where(valid, z, -np.inf).max(axis=1)
    # an edge without a face: degenerate input
    ok = np.all(cnt[:, :n] >= 3, axis=1) & np.isfinite(zmax) & (zmax > 1e-9)
    return Envelope(xy, nodes, ring_idx, cnt, np.where(ok, zmax, 0.0), ok)


def envelope_roofs(xy, slopes, top=None):
    """Roofs over convex footprints with the same number of vertices, as a
    list of :class:`~reconstruction.lod2.roofs.model.Roof` (None for degenerate
    input); see :func:`envelope_arrays`."""
    env = envelope_arrays(xy, slopes, top)
    rows = np.arange(len(env.xy))
    group = env.group(rows, rows)
    return [group.roof(b) if env.ok[b] else None for b in rows]
