"""Many LoD2 solids as flat numpy arrays: storage, selection and semantics.

A solid is one closed 2-manifold shell: vertices (absolute coordinates,
rounded to the millimetre grid CityJSON stores) and faces, rings of vertex
indices oriented outwards. Many solids travel together as a
:class:`SolidSet`, so that rounding, de-duplication, validation
(:mod:`~reconstruction.lod2.solids.validation`) and semantic classification run in bulk.
"""

import itertools
import math
from dataclasses import dataclass

import numpy as np

from .rings import components, gather, next_in_ring, offsets, starts, unique_rows

GROUND, WALL, ROOF = 0, 1, 2
SEMANTIC_NAMES = ("GroundSurface", "WallSurface", "RoofSurface")
SEMANTIC_ANGLE = 5.0


class SolidSet:
    """Solids on the millimetre grid as flat arrays.

    - ``vertices``: (N, 3) int64, absolute coordinates in millimetres; each
      solid's vertices are distinct and all used;
    - ``rings``: (K,) vertex indices of all rings, one after the other;
    - ``face_start``: (F + 1,) offsets of the rings in ``rings``;
    - ``solid_start``: (S + 1,) offsets of each solid's faces;
    - ``bad``: (S,) reason why a solid could not even be stored (or None);
    - ``face_normal``: (F, 3) Newell normals of the faces once
      :func:`~reconstruction.lod2.solids.validation.validate` has computed them (kept by :func:`take` and
      :func:`concat`, used by :func:`semantics`), else None.
    """

    def __init__(self, vertices, rings, face_start, solid_start, bad=None, face_normal=None):
        self.vertices = vertices
        self.rings = rings
        self.face_start = face_start
        self.solid_start = solid_start
        S = len(solid_start) - 1
        self.bad = bad if bad is not None else [None] * S
        self.face_normal = face_normal

    def __len__(self):
        return len(self.solid_start) - 1

    @property
    def face_solid(self):
        return np.repeat(np.arange(len(self)), np.diff(self.solid_start))

    @property
    def entry_face(self):
        return np.repeat(np.arange(len(self.face_start) - 1), np.diff(self.face_start))

    def solid(self, s):
        """Vertices (float metres) and faces (lists, local indices) of solid ``s``."""
        f0, f1 = self.solid_start[s], self.solid_start[s + 1]
        idx = self.rings[self.face_start[f0]:self.face_start[f1]]
        if len(idx) == 0:
            return np.zeros((0, 3)), []
        used, inv = np.unique(idx, return_inverse=True)
        faces, pos = [], 0
        for f in range(f0, f1):
            k = self.face_start[f + 1] - self.face_start[f]
            faces.append(inv[pos:pos + k].tolist())
            pos += k
        return self.vertices[used] / 1000.0, faces


def to_solidset(shells, origins, why=None):
    """Round shells to the millimetre grid and store them as a :class:`SolidSet`.

    ``shells``: list of ``(vertices, faces)`` (local x, y; None for a missing
    shell, with its reason in ``why``), ``origins``: (S, 2) offsets added to x, y. Removes duplicate
    vertices and duplicate consecutive ring vertices; rings left with fewer
    than three vertices are dropped (the validator then checks that the shell
    is still closed).
    """
    parts = shell_parts(shells, origins, np.arange(len(shells)))
    bad = [None] * len(shells)
    for s, shell in enumerate(shells):
        if shell is None:
            bad[s] = (why[s] if why is not None and why[s] else "no shell")
    return from_parts([parts], len(shells), bad)


def shell_parts(shells, origins, owners):
    """Flat arrays ``(vertices, rings, face sizes, face owners)`` of shells
    given as ``(vertices, faces)`` lists (None shells are skipped)."""
    vparts, ring_parts, sizes, face_owner = [], [], [], []
    voff = 0
    for s, shell in enumerate(shells):
        if shell is None:
            continue
        v, faces = shell
        w = v.copy()
        w[:, :2] += origins[s]
        vparts.append(w)
        ring_parts.append(np.fromiter(itertools.chain.from_iterable(faces), dtype=np.int64) + voff)
        sizes.extend(len(f) for f in faces)
        face_owner.extend([owners[s]] * len(faces))
        voff += len(v)
    if not vparts:
        return (np.zeros((0, 3)), np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64),
                np.zeros(0, dtype=np.int64))
    return (np.concatenate(vparts), np.concatenate(ring_parts),
            np.asarray(sizes, dtype=np.int64), np.asarray(face_owner, dtype=np.int64))


def from_parts(parts, S, bad):
    """A :class:`SolidSet` of S solids from flat parts (see :func:`shell_parts`):
    faces ordered by owner (stable), millimetre rounding, distinct vertices
    per solid, no duplicate consecutive ring vertices, collapsed rings dropped."""
    vs, rs, ss_, os_ = [], [], [], []
    voff = 0
    for v, r, sz, ow in parts:
        vs.append(v)
        rs.append(r + voff)
        ss_.append(sz)
        os_.append(ow)
        voff += len(v)
    allv = np.rint(np.concatenate(vs) * 1000.0).astype(np.int64) if vs else np.zeros((0, 3), np.int64)
    rings = np.concatenate(rs) if rs else np.zeros(0, dtype=np.int64)
    sizes = np.concatenate(ss_) if ss_ else np.zeros(0, dtype=np.int64)
    owner = np.concatenate(os_) if os_ else np.zeros(0, dtype=np.int64)
    # faces ordered by solid, keeping each solid's face order
    perm = np.argsort(owner, kind="stable")
    if len(perm) and np.any(perm != np.arange(len(perm))):
        new_sizes = sizes[perm]
        rings = rings[gather(starts(sizes)[perm], new_sizes)]
        sizes = new_sizes
        owner = owner[perm]
    face_solid = owner
    entry_face = np.repeat(np.arange(len(sizes)), sizes)
    entry_solid = face_solid[entry_face]
    # distinct vertices per solid, only those used
    used = np.zeros(len(allv), dtype=bool)
    used[rings] = True
    uidx = np.nonzero(used)[0]
    remap = np.full(len(allv), -1, dtype=np.int64)
    remap[uidx] = np.arange(len(uidx))
    local = remap[rings]
    vsolid = np.empty(len(uidx), dtype=np.int64)
    vsolid[local] = entry_solid
    uniq, inv_u = unique_rows(np.column_stack([vsolid, snap(allv[uidx], vsolid)]))
    inv = inv_u[local]
    vertices = np.ascontiguousarray(uniq[:, 1:])
    # duplicate consecutive vertices
    nxt = next_in_ring(offsets(sizes))
    keep = inv != inv[nxt] if len(inv) else np.zeros(0, dtype=bool)
    inv = inv[keep]
    sizes = np.bincount(entry_face[keep], minlength=len(sizes))
    # rings that collapse on the grid (fewer than 3 distinct vertices) are
    # dropped: the shell stays closed only if their neighbours meet, which
    # the validator checks
    small = sizes < 3
    if small.any():
        drop_entries = small[entry_face[keep]]
        inv = inv[~drop_entries]
        sizes_kept = sizes[~small]
        face_solid = face_solid[~small]
    else:
        sizes_kept = sizes
    face_start = offsets(sizes_kept).astype(np.int64)
    solid_start = offsets(np.bincount(face_solid, minlength=S)).astype(np.int64)
    return SolidSet(vertices, inv.astype(np.int64), face_start, solid_start, list(bad))


#: vertices of a solid closer than this (mm) are one vertex: val3dity snaps
#: them together (its ``--snap_tol``, 1 mm), which may leave a ring with
#: consecutive equal points
SNAP_TOL = 1.5


def close_pairs(vertices, vsolid, tol=SNAP_TOL):
    """Pairs ``(i, j)``, i < j, of vertices (int mm) of the same solid closer
    than ``tol`` (at most ``tol`` apart).

    A sweep along x in numpy (no k-d tree: importing scipy.spatial costs
    v.histo.lod2 a third of a second at every run): vertices sorted by
    solid and x are compared with the k-th next one, for k = 1, 2, ..., as
    long as some pair is still of the same solid and within ``tol`` along
    x; the work is the number of such pairs.
    """
    vertices = np.asarray(vertices)
    n = len(vertices)
    if n < 2:
        return np.zeros((0, 2), dtype=np.int64)
    vsolid = np.asarray(vsolid)
    order = np.lexsort((vertices[:, 0], vsolid))
    solid = vsolid[order]
    pts = vertices[order]
    x = pts[:, 0]
    found = []
    first = np.arange(n - 1)
    k = 1
    while len(first):
        first = first[first + k < n]
        second = first + k
        near = (solid[second] == solid[first]) & (x[second] - x[first] <= tol)
        first, second = first[near], second[near]
        d = (pts[second] - pts[first]).astype(float)
        close = np.einsum("ij,ij->i", d, d) <= tol * tol
        found.append(np.column_stack([order[first[close]], order[second[close]]]))
        k += 1
    pairs = np.concatenate(found).astype(np.int64)
    pairs.sort(axis=1)
    return pairs


def snap(vertices, vsolid, tol=SNAP_TOL):
    """The vertices with those of a solid closer than ``tol`` (chains of them)
    moved onto one of them, as val3dity snaps them: the rings then lose the
    consecutive duplicates and collapsed rings of :func:`from_parts`."""
    pairs = close_pairs(vertices, vsolid, tol)
    if not len(pairs):
        return vertices
    labels = components(len(vertices), pairs[:, 0], pairs[:, 1])
    return vertices[labels]


def take(ss, idx):
    """The solids ``idx`` (in that order) of a :class:`SolidSet`, as a new set."""
    idx = np.asarray(idx, dtype=np.int64)
    f0 = ss.solid_start[idx]
    nf = ss.solid_start[idx + 1] - f0
    faces = gather(f0, nf)
    sizes = ss.face_start[faces + 1] - ss.face_start[faces]
    taken = ss.rings[gather(ss.face_start[faces], sizes)]
    # the vertices used, in their order (as np.unique, without sorting)
    used = np.zeros(len(ss.vertices), dtype=bool)
    used[taken] = True
    remap = np.cumsum(used) - 1
    return SolidSet(ss.vertices[used], remap[taken].astype(np.int64),
                    offsets(sizes).astype(np.int64), offsets(nf).astype(np.int64),
                    [ss.bad[i] for i in idx],
                    None if ss.face_normal is None else ss.face_normal[faces])


def concat(sets):
    """One :class:`SolidSet` of several, solids in order."""
    voff = foff = eoff = 0
    v, r, fs, ss_, bad = [], [], [np.zeros(1, dtype=np.int64)], [np.zeros(1, dtype=np.int64)], []
    for s in sets:
        v.append(s.vertices)
        r.append(s.rings + voff)
        fs.append(s.face_start[1:] + eoff)
        ss_.append(s.solid_start[1:] + foff)
        bad.extend(s.bad)
        voff += len(s.vertices)
        eoff += int(s.face_start[-1])
        foff += int(s.solid_start[-1])
    normals = [s.face_normal for s in sets]
    known = bool(sets) and all(n is not None for n in normals)
    return SolidSet(np.concatenate(v) if v else np.zeros((0, 3), np.int64),
                    np.concatenate(r) if r else np.zeros(0, np.int64),
                    np.concatenate(fs), np.concatenate(ss_), bad,
                    np.concatenate(normals) if known else None)


@dataclass(frozen=True)
class FaceGeometry:
    """The faces of a :class:`SolidSet` as :func:`face_geometry` measures them."""

    #: per ring entry, its coordinates (m, relative to the solid's first vertex)
    points: np.ndarray
    #: per ring entry, the index of the next entry of its ring
    next: np.ndarray
    #: per ring entry, its face
    entry_face: np.ndarray
    #: per face, its Newell normal (length: twice the face's area)
    normal: np.ndarray
    #: per face, the mean of its ring's points
    centroid: np.ndarray
    #: per face, the number of entries of its ring
    sizes: np.ndarray


def face_geometry(ss):
    """The :class:`FaceGeometry` of a :class:`SolidSet`, in bulk."""
    face_start = ss.face_start
    F = len(face_start) - 1
    sizes = np.diff(face_start)
    entry_face = np.repeat(np.arange(F), sizes)
    # reference point per solid: its first ring vertex
    first = face_start[ss.solid_start]
    ref_idx = np.zeros(len(ss), dtype=np.int64)
    has = np.diff(first) > 0
    ref_idx[has] = ss.rings[first[:-1][has]]
    p = ss.vertices[ss.rings] - np.repeat(ss.vertices[ref_idx], np.diff(first), axis=0)
    p = p / 1000.0
    nxt = next_in_ring(face_start)
    q = p[nxt]
    d = p - q
    t = p + q
    cr = np.empty_like(p)
    np.multiply(d[:, 1], t[:, 2], out=cr[:, 0])
    np.multiply(d[:, 2], t[:, 0], out=cr[:, 1])
    np.multiply(d[:, 0], t[:, 1], out=cr[:, 2])
    if F:
        normal = np.add.reduceat(cr, face_start[:-1], axis=0)
        centroid = np.add.reduceat(p, face_start[:-1], axis=0) / sizes[:, None]
    else:
        normal = np.zeros((0, 3))
        centroid = np.zeros((0, 3))
    return FaceGeometry(p, nxt, entry_face, normal, centroid, sizes)


def semantics(ss):
    """Semantic surface per face (GROUND, WALL, ROOF) from its normal:
    ground when pointing down within 5 degrees, wall when horizontal within
    5 degrees, roof otherwise."""
    normal = ss.face_normal
    if normal is None:
        normal = face_geometry(ss).normal
    ln = np.linalg.norm(normal, axis=1)
    nz = normal[:, 2] / np.maximum(ln, 1e-300)
    out = np.full(len(nz), ROOF, dtype=np.int8)
    out[np.abs(nz) < math.sin(math.radians(SEMANTIC_ANGLE))] = WALL
    out[nz < -math.cos(math.radians(SEMANTIC_ANGLE))] = GROUND
    return out


def volumes(ss):
    """Volume (m3) of every solid."""
    geometry = face_geometry(ss)
    vol = np.einsum("ij,ij->i", geometry.normal, geometry.centroid) / 6.0
    out = np.zeros(len(ss))
    np.add.at(out, ss.face_solid, vol)
    return out

