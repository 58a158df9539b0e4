"""LoD2 solids: footprint + heights + roof -> one closed, valid shell.

A solid is one closed 2-manifold shell: vertices (absolute coordinates,
rounded to the millimetre grid CityJSON stores) and faces, rings of vertex
indices oriented outwards. Many solids travel together as a
:class:`SolidSet` of flat numpy arrays, so that rounding, de-duplication,
validation and semantic classification run in bulk.

The validator (:func:`validate`) checks what val3dity checks for a Solid,
on the millimetre geometry that is written: rings of at least three distinct
vertices, no duplicate consecutive vertices, no self-intersecting or
degenerate (zero-area) ring, faces planar within 1 mm, every edge used
exactly twice in opposite directions (closed, 2-manifold along edges,
consistently oriented), V - E + F = 2 (one fan of faces around every vertex:
2-manifold at the vertices, no handle), one connected shell, positive
volume (outward orientation). :func:`build_solids` never returns an invalid solid: a roof
that fails falls back to a simpler type (stepped -> gable -> mansard ->
flat), and a footprint whose flat prism still fails is dropped and counted.
"""

import itertools
import math

import numpy as np

from . import roofs as _roofs
from .roofs import _nxt, _prv

GROUND, WALL, ROOF = 0, 1, 2
SEMANTIC_NAMES = ("GroundSurface", "WallSurface", "RoofSurface")
#: Fallback chain when a roof type fails validation.
FALLBACK = {"stepped": "gable", "gable": "mansard", "hip": "mansard", "mansard": "flat",
            "flat": None}
PLANARITY_TOL = 0.001
SEMANTIC_ANGLE = 5.0


# ---------------------------------------------------------------------------
# Footprints
# ---------------------------------------------------------------------------

def footprint_polygons(geometries, skip=None):
    """The polygons to build on: every polygon of every footprint geometry
    (shapely Polygon or MultiPolygon; None, empty and other geometries are
    left out, as are footprints where ``skip`` is True), in bulk.

    Returns ``(polygons, source, part, holes, empty)``: the polygons, the
    index of the footprint of each, its part number in a MultiPolygon of
    several parts (-1 for a single polygon), the number of holes of all
    polygons and the number of missing or empty footprints.
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
    number = np.arange(len(parts)) - np.repeat(np.cumsum(count) - count, count)
    polygons = np.concatenate([geoms[single], parts])
    source = np.concatenate([single, multi[owner]])
    part = np.concatenate([np.full(len(single), -1), np.where(count[owner] > 1, number, -1)])
    order = np.argsort(source, kind="stable")
    polygons, source, part = polygons[order], source[order], part[order].astype(np.int64)
    holes = int(shapely.get_num_interior_rings(polygons).sum()) if len(polygons) else 0
    return polygons, source, part, holes, int(empty.sum())


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
        keep = np.any(xy != _nxt(xy), axis=1)
        xy = xy[keep]
        if len(xy) < 3:
            return None, "fewer than 3 distinct vertices"
        prev = _prv(xy)
        nxt = _nxt(xy)
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
    area2 = float(np.sum(xy[:, 0] * _nxt(xy[:, 1]) - _nxt(xy[:, 0]) * xy[:, 1]))
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
    starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
    closed = (counts > 1)
    closed[closed] = np.all(xy[starts[closed]] == xy[(starts + counts - 1)[closed]], axis=1)
    keep = np.ones(len(xy), dtype=bool)
    keep[(starts + counts - 1)[closed]] = False
    xy, which = xy[keep], which[keep]
    dead = np.zeros(P, dtype=bool)
    # remove, in every ring at once, its worst vertex (a duplicate, else the
    # most collinear one) until no ring has any: as clean_ring, in bulk
    for _ in range(int(counts.max(initial=0)) + 1):
        n = np.bincount(which, minlength=P)
        dead |= n < 3
        alive = ~dead[which]
        if not alive.all():
            xy, which = xy[alive], which[alive]
            n = np.bincount(which, minlength=P)
        st = np.concatenate([[0], np.cumsum(n)[:-1]])
        rep = np.repeat(st, n)
        pos = np.arange(len(xy)) - rep
        nn = np.maximum(np.repeat(n, n), 1)
        prev, nxt = xy[rep + (pos - 1) % nn], xy[rep + (pos + 1) % nn]
        dup = np.all(xy == nxt, axis=1)
        d = nxt - prev
        ln = np.hypot(d[:, 0], d[:, 1])
        cross = (xy[:, 0] - prev[:, 0]) * d[:, 1] - (xy[:, 1] - prev[:, 1]) * d[:, 0]
        dist = np.abs(cross) / np.maximum(ln, 1e-12)
        bad = dup | (dist < tol) | (ln < tol)
        if not bad.any():
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
    nxt_x = np.empty(len(xy))
    nxt_y = np.empty(len(xy))
    st = np.concatenate([[0], np.cumsum(n)[:-1]])
    rep = np.repeat(st, n)
    pos = np.arange(len(xy)) - rep
    nidx = rep + (pos + 1) % np.maximum(np.repeat(n, n), 1)
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
# Assembly
# ---------------------------------------------------------------------------

def assemble(xy, roof, ground, eaves):
    """One shell from a footprint (local coordinates), a roof and heights.

    Returns ``(vertices, faces)`` with vertices (V, 3) in local x, y and
    absolute z, faces as lists of indices, or None when the roof's boundary
    does not follow the footprint.
    """
    n = len(xy)
    rv = roof["vertices"]
    verts = np.empty((n + len(rv), 3))
    verts[:n, :2] = xy
    verts[:n, 2] = ground
    verts[n:, :2] = rv[:, :2]
    verts[n:, 2] = rv[:, 2] + ground + eaves
    verts[n:2 * n, :2] = xy          # exact footprint under the eaves
    faces = [list(range(n - 1, -1, -1))]
    if roof["boundary"]:
        faces.extend([i, (i + 1) % n, n + (i + 1) % n, n + i] for i in range(n))
    elif roof.get("chains") is not None:
        faces.extend([i, (i + 1) % n] + [n + k for k in reversed(chain)]
                     for i, chain in enumerate(roof["chains"]))
    else:
        nxt = {}
        directed = set()
        for f in roof["faces"]:
            for a, b in zip(f, f[1:] + f[:1]):
                directed.add((a, b))
        for a, b in directed:
            if (b, a) not in directed and abs(rv[a, 2]) < 1e-9 and abs(rv[b, 2]) < 1e-9:
                if a in nxt:
                    return None
                nxt[a] = b
        for i in range(n):
            chain = [i]
            target = (i + 1) % n
            while chain[-1] != target:
                k = nxt.get(chain[-1])
                if k is None or len(chain) > len(rv):
                    return None
                chain.append(k)
            faces.append([i, target] + [n + k for k in reversed(chain)])
    faces.extend([n + k for k in f] for f in roof["faces"])
    return verts, faces


# ---------------------------------------------------------------------------
# Many solids as flat arrays
# ---------------------------------------------------------------------------

class SolidSet:
    """Solids on the millimetre grid as flat arrays.

    - ``vertices``: (N, 3) int64, absolute coordinates in millimetres; each
      solid's vertices are distinct and all used;
    - ``rings``: (K,) vertex indices of all rings, one after the other;
    - ``face_start``: (F + 1,) offsets of the rings in ``rings``;
    - ``solid_start``: (S + 1,) offsets of each solid's faces;
    - ``bad``: (S,) reason why a solid could not even be stored (or None);
    - ``face_normal``: (F, 3) Newell normals of the faces once
      :func:`validate` has computed them (kept by :func:`take` and
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


_HASH = np.array([0x9E3779B97F4A7C15, 0xC2B2AE3D27D4EB4F, 0x165667B19E3779F9,
                  0x27D4EB2F165667C5], dtype=np.uint64)


def unique_rows(rows):
    """Distinct rows of an (n, k <= 4) integer array and the inverse index
    (as ``np.unique(rows, axis=0, return_inverse=True)``, but sorted by a
    hash of the rows, which is much faster; exact: hash collisions are
    detected and then fall back to a lexicographic sort)."""
    rows = np.asarray(rows)
    if len(rows) == 0:
        return rows.copy(), np.zeros(0, dtype=np.int64)
    k = rows.shape[1]
    with np.errstate(over="ignore"):
        h = (rows.astype(np.uint64) * _HASH[:k]).sum(axis=1, dtype=np.uint64)
        h ^= h >> np.uint64(29)
    order = np.argsort(h)
    hs = h[order]
    srt = rows[order]
    same_hash = hs[1:] == hs[:-1]
    same_row = np.all(srt[1:] == srt[:-1], axis=1)
    if np.any(same_hash & ~same_row):
        order = np.lexsort(rows.T[::-1])
        srt = rows[order]
        same_row = np.all(srt[1:] == srt[:-1], axis=1)
    new = np.empty(len(rows), dtype=bool)
    new[0] = True
    new[1:] = ~same_row
    group = np.cumsum(new) - 1
    inv = np.empty(len(rows), dtype=np.int64)
    inv[order] = group
    return srt[new], inv


def to_solidset(shells, origins, why=None):
    """Round shells to the millimetre grid and store them as a :class:`SolidSet`.

    ``shells``: list of ``(vertices, faces)`` (local x, y; None for a missing
    shell, with its reason in ``why``), ``origins``: (S, 2) offsets added to x, y. Removes duplicate
    vertices and duplicate consecutive ring vertices; rings left with fewer
    than three vertices are dropped (the validator then checks that the shell
    is still closed).
    """
    parts = _shell_parts(shells, origins, np.arange(len(shells)))
    bad = [None] * len(shells)
    for s, shell in enumerate(shells):
        if shell is None:
            bad[s] = (why[s] if why is not None and why[s] else "no shell")
    return _finish([parts], len(shells), bad)


def _shell_parts(shells, origins, owners):
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


def _group_parts(group, origins, ground, eaves):
    """Flat arrays ``(vertices, rings, face sizes, face owners)`` of the
    solids of one bulk roof group (see :func:`reconstruction.roofs.make_roofs`):
    ground, walls and roof of every footprint in one numpy pass. The walls
    are quads, or pentagons along the footprint edges whose roof boundary
    has a vertex between the edge's ends (``wall_mid``)."""
    idx = group["index"]
    xy = group["xy"]
    G, n, _ = xy.shape
    flat = "ring_idx" not in group
    if "roof" in group:
        extra = group["roof"][:, n:]          # roof vertices past the footprint
    elif not flat:
        extra = group["nodes"]
    else:
        extra = np.zeros((G, 0, 3))
    C = extra.shape[1]
    Vb = 2 * n + C
    org = origins[idx]
    z0 = np.asarray(ground, dtype=float)[idx]
    z1 = z0 + np.asarray(eaves, dtype=float)[idx]
    v = np.empty((G, Vb, 3))
    v[:, :n, :2] = xy + org[:, None, :]
    v[:, :n, 2] = z0[:, None]
    v[:, n:2 * n, :2] = v[:, :n, :2]
    v[:, n:2 * n, 2] = z1[:, None]
    v[:, 2 * n:, :2] = extra[..., :2] + org[:, None, :]
    v[:, 2 * n:, 2] = extra[..., 2] + z1[:, None]
    base = (np.arange(G) * Vb)[:, None]
    j = np.arange(n)
    ground_r = (base + j[::-1]).ravel()
    mid = group.get("wall_mid")
    if mid is None:
        walls_r = (base[:, :, None] + np.stack([j, (j + 1) % n, n + (j + 1) % n, n + j],
                                               axis=1)).ravel()
        wall_sizes = np.full(G * n, 4)
    else:
        w = np.empty((G, n, 5), dtype=np.int64)
        w[..., 0], w[..., 1], w[..., 2] = j, (j + 1) % n, n + (j + 1) % n
        w[..., 3] = np.where(mid >= 0, n + mid, n + j)
        w[..., 4] = n + j
        walls_r = (base[:, :, None] + w)[np.broadcast_to(
            (np.arange(5) < 4) | (mid >= 0)[..., None], w.shape)]
        wall_sizes = np.where(mid >= 0, 5, 4).ravel()
    if flat:
        roof_r = (base + n + j).ravel()
        roof_sizes = np.full(G, n)
        roof_owner = idx
    else:
        cnt = group["cnt"]
        K = group["ring_idx"].shape[2]
        use = cnt >= 3
        mask = (np.arange(K) < cnt[..., None]) & use[..., None]
        roof_r = (base[:, :, None] + n + group["ring_idx"])[mask]
        roof_sizes = cnt[use]
        roof_owner = np.broadcast_to(idx[:, None], cnt.shape)[use]
    rings = np.concatenate([ground_r, walls_r, roof_r])
    sizes = np.concatenate([np.full(G, n), wall_sizes, roof_sizes])
    owner = np.concatenate([idx, np.repeat(idx, n), roof_owner])
    return v.reshape(-1, 3), rings, sizes, owner


def _finish(parts, S, bad):
    """A :class:`SolidSet` of S solids from flat parts (see :func:`_shell_parts`):
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
        starts = np.concatenate([[0], np.cumsum(sizes)[:-1]])
        new_sizes = sizes[perm]
        new_starts = np.concatenate([[0], np.cumsum(new_sizes)[:-1]])
        total = int(new_sizes.sum())
        gather = np.arange(total) - np.repeat(new_starts, new_sizes) + np.repeat(starts[perm], new_sizes)
        rings = rings[gather]
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
    uniq, inv_u = unique_rows(np.column_stack([vsolid, allv[uidx]]))
    inv = inv_u[local]
    vertices = np.ascontiguousarray(uniq[:, 1:])
    # duplicate consecutive vertices
    face_start = np.concatenate([[0], np.cumsum(sizes)])
    nxt = np.arange(len(inv)) + 1
    ends = face_start[1:] - 1
    nxt[ends] = face_start[:-1]
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
    face_start = np.concatenate([[0], np.cumsum(sizes_kept)]).astype(np.int64)
    solid_start = np.concatenate([[0], np.cumsum(np.bincount(face_solid, minlength=S))]).astype(np.int64)
    return SolidSet(vertices, inv.astype(np.int64), face_start, solid_start, list(bad))


def take(ss, idx):
    """The solids ``idx`` (in that order) of a :class:`SolidSet`, as a new set."""
    idx = np.asarray(idx, dtype=np.int64)
    f0 = ss.solid_start[idx]
    nf = ss.solid_start[idx + 1] - f0
    faces = np.repeat(f0 - np.concatenate([[0], np.cumsum(nf)[:-1]]), nf) + np.arange(int(nf.sum()))
    sizes = ss.face_start[faces + 1] - ss.face_start[faces]
    e0 = ss.face_start[faces]
    entries = np.repeat(e0 - np.concatenate([[0], np.cumsum(sizes)[:-1]]), sizes) + np.arange(int(sizes.sum()))
    taken = ss.rings[entries]
    # the vertices used, in their order (as np.unique, without sorting)
    used = np.zeros(len(ss.vertices), dtype=bool)
    used[taken] = True
    remap = np.cumsum(used) - 1
    return SolidSet(ss.vertices[used], remap[taken].astype(np.int64),
                    np.concatenate([[0], np.cumsum(sizes)]).astype(np.int64),
                    np.concatenate([[0], np.cumsum(nf)]).astype(np.int64),
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


def _face_geometry(ss):
    """Per ring entry coordinates (m, relative to the solid's first vertex),
    next-entry index, per face Newell normal, centroid and size."""
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
    nxt = np.arange(len(ss.rings)) + 1
    if F:
        nxt[face_start[1:] - 1] = face_start[:-1]
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
    return p, nxt, entry_face, normal, centroid, sizes


def semantics(ss):
    """Semantic surface per face (GROUND, WALL, ROOF) from its normal:
    ground when pointing down within 5 degrees, wall when horizontal within
    5 degrees, roof otherwise."""
    normal = ss.face_normal
    if normal is None:
        normal = _face_geometry(ss)[3]
    ln = np.linalg.norm(normal, axis=1)
    nz = normal[:, 2] / np.maximum(ln, 1e-300)
    out = np.full(len(nz), ROOF, dtype=np.int8)
    out[np.abs(nz) < math.sin(math.radians(SEMANTIC_ANGLE))] = WALL
    out[nz < -math.cos(math.radians(SEMANTIC_ANGLE))] = GROUND
    return out


def _components(n, a, b):
    """Connected component label (smallest member) of n nodes joined by edges a-b,
    by min-label propagation (shells have a small diameter)."""
    labels = np.arange(n)
    while True:
        new = labels.copy()
        np.minimum.at(new, a, labels[b])
        np.minimum.at(new, b, labels[a])
        new = new[new]
        if np.array_equal(new, labels):
            return labels
        labels = new


def validate(ss, tol=PLANARITY_TOL):
    """Check every solid; returns a list with None (valid) or the reasons
    (joined by "; ")."""
    import shapely

    S = len(ss)
    reasons = list(ss.bad)

    def flag(solids, reason):
        for s in np.unique(solids):
            if ss.bad[s] is not None:
                continue
            if reasons[s] is None:
                reasons[s] = reason
            elif reason not in reasons[s]:
                reasons[s] += "; " + reason

    F = len(ss.face_start) - 1
    nf = np.diff(ss.solid_start)
    flag(np.nonzero(nf < 4)[0], "fewer than 4 faces")
    if F == 0:
        return reasons
    p, nxt, entry_face, normal, centroid, sizes = _face_geometry(ss)
    ss.face_normal = normal
    face_solid = ss.face_solid
    area2 = np.linalg.norm(normal, axis=1)
    # degenerate rings: zero area
    degenerate = area2 < 2e-7
    flag(face_solid[degenerate], "degenerate ring (zero area)")
    unit = normal / np.maximum(area2, 1e-300)[:, None]
    # planarity: distance of each vertex to the least-squares plane (as
    # val3dity). The plane through the centroid normal to the Newell normal
    # bounds it: the least-squares plane's largest distance is at most the
    # root of its sum of squares, at most that of any other plane through
    # the centroid, at most sqrt(k) times that plane's largest distance; only
    # faces this bound does not clear need the least-squares fit
    rel = p - centroid[entry_face]
    dist = np.abs(np.einsum("ij,ij->i", rel, unit[entry_face]))
    maxdist = np.maximum.reduceat(dist, ss.face_start[:-1])
    fit_faces = np.nonzero((maxdist * np.sqrt(sizes) > tol) & ~degenerate)[0]
    if len(fit_faces):
        e0 = ss.face_start[fit_faces]
        k = sizes[fit_faces]
        entries = np.repeat(e0 - np.concatenate([[0], np.cumsum(k)[:-1]]), k) + np.arange(int(k.sum()))
        r = rel[entries]
        starts = np.concatenate([[0], np.cumsum(k)[:-1]])
        cov = np.add.reduceat(r[:, :, None] * r[:, None, :], starts, axis=0)
        _, vecs = np.linalg.eigh(cov)
        fit = np.repeat(vecs[:, :, 0], k, axis=0)
        far = np.maximum.reduceat(np.abs(np.einsum("ij,ij->i", r, fit)), starts) > tol
        flag(face_solid[fit_faces[far]], "non-planar face (> 1 mm)")
    # self-intersection: quads by segment tests in numpy, larger rings with
    # shapely, all projected on their plane
    quads = np.nonzero((sizes == 4) & ~degenerate)[0]
    if len(quads):
        axis = np.argmax(np.abs(unit[quads]), axis=1)
        cols = np.array([[1, 2], [0, 2], [0, 1]])[axis]
        q = p[ss.face_start[quads][:, None] + np.arange(4)]          # (Q, 4, 3)
        q2 = np.take_along_axis(q, np.repeat(cols[:, None, :], 4, axis=1), axis=2)

        def crosses(a, b, c, d):
            def orient(u, v, w):
                return np.sign((v[:, 0] - u[:, 0]) * (w[:, 1] - u[:, 1])
                               - (v[:, 1] - u[:, 1]) * (w[:, 0] - u[:, 0]))
            return (orient(a, b, c) * orient(a, b, d) < 0) & (orient(c, d, a) * orient(c, d, b) < 0)

        bow = crosses(q2[:, 0], q2[:, 1], q2[:, 2], q2[:, 3]) | \
            crosses(q2[:, 1], q2[:, 2], q2[:, 3], q2[:, 0])
        flag(face_solid[quads[bow]], "self-intersecting ring")
    big = np.nonzero((sizes >= 5) & ~degenerate)[0]
    if len(big):
        axis = np.argmax(np.abs(unit[big]), axis=1)
        sel = np.isin(entry_face, big)
        ef = entry_face[sel]
        pos = np.searchsorted(big, ef)
        drop = axis[pos]
        pts = p[sel]
        keep_cols = np.array([[1, 2], [0, 2], [0, 1]])[drop]
        xy2 = np.take_along_axis(pts, keep_cols, axis=1)
        # close each ring
        starts = np.searchsorted(ef, big)
        closed = np.insert(xy2, np.r_[starts[1:], len(xy2)], xy2[starts], axis=0)
        ids = np.insert(pos, np.r_[starts[1:], len(xy2)], np.arange(len(big)))
        rings = shapely.linearrings(closed, indices=ids)
        simple = shapely.is_simple(rings)
        flag(face_solid[big[~simple]], "self-intersecting ring")
    # edges: every undirected edge exactly twice, in opposite directions
    a = ss.rings
    b = ss.rings[nxt]
    N = max(len(ss.vertices), 1)
    ukey = np.minimum(a, b) * N + np.maximum(a, b)
    forward = a < b
    order = np.argsort(ukey, kind="stable")      # (timsort: faster on these runs)
    sk = ukey[order]
    E = len(sk)
    start = np.ones(E, dtype=bool)
    start[1:] = sk[1:] != sk[:-1]
    starts = np.nonzero(start)[0]
    run_len = np.diff(np.append(starts, E))
    entry_run_len = np.repeat(run_len, run_len)          # in sorted order
    once = order[entry_run_len == 1]
    flag(face_solid[entry_face[once]], "edge used only once (shell not closed)")
    many = order[entry_run_len > 2]
    flag(face_solid[entry_face[many]], "edge used more than twice (non-manifold)")
    pairs = starts[run_len == 2]
    ea, eb = order[pairs], order[pairs + 1]
    same = forward[ea] == forward[eb]
    flag(face_solid[entry_face[ea[same]]],
         "edge used twice in the same direction (faces not consistently oriented)")
    # 2-manifold at the vertices: with every edge used twice, the shell is a
    # closed surface; V - E + F = 2 holds for a genus-0 surface whose every
    # vertex has one fan of faces (a vertex with k fans lowers it by k - 1)
    vsol = np.full(N, -1, dtype=np.int64)
    vsol[a] = face_solid[entry_face]
    nv = np.bincount(vsol[vsol >= 0], minlength=S)
    ne = np.bincount(face_solid[entry_face], minlength=S) / 2.0
    euler = nv - ne + nf
    flag(np.nonzero((euler != 2) & (nf > 0))[0],
         "non-manifold vertex or handle (V - E + F != 2)")
    # one connected shell
    if len(ea):
        labels = _components(F, entry_face[ea], entry_face[eb])
        lo = np.minimum.reduceat(labels, ss.solid_start[:-1][nf > 0])
        hi = np.maximum.reduceat(labels, ss.solid_start[:-1][nf > 0])
        flag(np.nonzero(nf > 0)[0][lo != hi], "more than one shell")
    # volume (divergence theorem) must be positive: outward orientation
    vol = np.einsum("ij,ij->i", normal, centroid) / 6.0
    svol = np.zeros(S)
    np.add.at(svol, face_solid, vol)
    flag(np.nonzero(svol <= 1e-9)[0], "zero or negative volume (faces oriented inwards)")
    return reasons


def volumes(ss):
    """Volume (m3) of every solid."""
    _, _, _, normal, centroid, _ = _face_geometry(ss)
    vol = np.einsum("ij,ij->i", normal, centroid) / 6.0
    out = np.zeros(len(ss))
    np.add.at(out, ss.face_solid, vol)
    return out


# ---------------------------------------------------------------------------
# Buildings in bulk, with fallback
# ---------------------------------------------------------------------------

def build_solids(footprints, ground, eaves, attic, roof_types, uniforms, street=None,
                 pitch_min=60.0, inset=(1.0, 2.0), step=(0.4, 0.7), thickness=0.5):
    """Valid LoD2 solids of many buildings.

    ``footprints``: list of cleaned counter-clockwise rings (n, 2) in
    absolute coordinates (see :func:`clean_ring`); ``ground``, ``eaves``,
    ``attic``: heights per footprint; ``roof_types``: requested types;
    ``uniforms``: (B, 3) uniform numbers per footprint (see
    :func:`reconstruction.roofs.make_roofs`).

    Returns ``(solidset, kept, types, log)``: the valid solids of the
    footprints ``kept`` (indices into the input), the roof type each one got
    after any fallback, and a log of ``(footprint index, roof type, reason)``
    for every roof that failed and fell back (by footprint).

    The pitched roofs of concave footprints (CGAL's straight skeleton, which
    releases the interpreter while it runs) are built in a thread beside the
    others; the result does not depend on it.
    """
    import threading

    args = [list(footprints), np.asarray(ground, dtype=float),
            np.asarray(eaves, dtype=float), np.asarray(attic, dtype=float),
            np.array(roof_types, dtype=object),
            np.asarray(uniforms, dtype=float).reshape(len(footprints), 3),
            None if street is None else list(street)]
    kwargs = dict(pitch_min=pitch_min, inset=inset, step=step, thickness=thickness)
    concave = ~_roofs.outline_facts(footprints)["convex"] if len(footprints) else np.zeros(0, bool)
    skeleton = concave & (args[4] != "flat") & (args[3] > 1e-3)
    if not skeleton.any() or skeleton.all():
        return _build_solids(*args, **kwargs)
    parts = [np.nonzero(skeleton)[0], np.nonzero(~skeleton)[0]]
    results = [None, None]

    def run(k):
        try:
            results[k] = _build_solids(*[_subset(a, parts[k]) for a in args], **kwargs)
        except BaseException as error:  # re-raised below
            results[k] = error

    worker = threading.Thread(target=run, args=(0,))
    worker.start()
    run(1)
    worker.join()
    for r in results:
        if isinstance(r, BaseException):
            raise r
    return _merge(list(zip(parts, results)))


def _subset(values, idx):
    """The elements ``idx`` of a list or array (None stays None)."""
    if values is None or isinstance(values, np.ndarray):
        return None if values is None else values[idx]
    return [values[i] for i in idx]


def _merge(parts):
    """One :func:`build_solids` result from results on subsets of the
    footprints, ``[(footprint indices, result), ...]``: solids in footprint
    order, the log by footprint."""
    sets, kept, types, log = [], [], [], []
    for idx, (ss, k, t, lg) in parts:
        sets.append(ss)
        kept.append(idx[k])
        types.append(t)
        log.extend((int(idx[i]), kind, why) for i, kind, why in lg)
    kept = np.concatenate(kept)
    types = np.concatenate(types)
    perm = np.argsort(kept, kind="stable")
    merged = concat(sets)
    if np.any(perm != np.arange(len(perm))):
        merged, kept, types = take(merged, perm), kept[perm], types[perm]
    return merged, kept, types, sorted(log, key=lambda entry: entry[0])


def _build_solids(footprints, ground, eaves, attic, roof_types, uniforms, street=None,
                  pitch_min=60.0, inset=(1.0, 2.0), step=(0.4, 0.7), thickness=0.5):
    """:func:`build_solids` in one thread."""
    B = len(footprints)
    origins = np.array([xy[0] for xy in footprints], dtype=float).reshape(B, 2)
    local = [xy - o for xy, o in zip(footprints, origins)]
    types = np.array(roof_types, dtype=object).copy()
    uniforms = np.asarray(uniforms, dtype=float).reshape(B, 3)
    ground = np.asarray(ground, dtype=float)
    eaves = np.asarray(eaves, dtype=float)
    attic = np.asarray(attic, dtype=float)
    todo = np.arange(B)
    accepted = []
    log = []
    while len(todo):
        T = len(todo)
        rf, kinds, groups = _roofs.make_roofs(
            [local[i] for i in todo], types[todo], attic[todo], uniforms[todo],
            None if street is None else [street[i] for i in todo],
            pitch_min=pitch_min, inset=inset, step=step, thickness=thickness, bulk=True)
        types[todo] = kinds
        inbulk = np.zeros(T, dtype=bool)
        for g in groups:
            inbulk[g["index"]] = True
        shells, bad = [None] * T, [None] * T
        for k in np.nonzero(~inbulk)[0]:
            roof = rf[k]
            i = todo[k]
            if roof is not None and roof["faces"]:
                shells[k] = assemble(local[i], roof, float(ground[i]), float(eaves[i]))
                if shells[k] is None:
                    bad[k] = "roof boundary does not follow the footprint"
            else:
                bad[k] = "roof cannot be built on this footprint"
        org = origins[todo]
        parts = [_shell_parts(shells, org, np.arange(T))]
        parts.extend(_group_parts(g, org, ground[todo], eaves[todo]) for g in groups)
        ss = _finish(parts, T, bad)
        reasons = validate(ss)
        good = np.array([r is None for r in reasons], dtype=bool)
        if good.any():
            accepted.append((take(ss, np.nonzero(good)[0]), todo[good]))
        retry = []
        for k in np.nonzero(~good)[0]:
            i = todo[k]
            log.append((int(i), types[i], reasons[k]))
            nxt_type = FALLBACK.get(types[i])
            if nxt_type is not None:
                types[i] = nxt_type
                retry.append(i)
        todo = np.array(retry, dtype=int)
    if not accepted:
        return concat([]), np.zeros(0, dtype=int), types[:0], log
    kept = np.concatenate([a[1] for a in accepted])
    merged = concat([a[0] for a in accepted])
    perm = np.argsort(kept, kind="stable")
    return take(merged, perm), kept[perm], types[kept[perm]], log


#: The work of build_solids_parallel, inherited by its forked processes.
_CHUNKS = []


def _build_chunk(k):
    """Build chunk ``k`` of the work in :data:`_CHUNKS`."""
    bounds, (footprints, ground, eaves, attic, roof_types, uniforms), kwargs = _CHUNKS[0]
    a, b = bounds[k], bounds[k + 1]
    return build_solids(footprints[a:b], ground[a:b], eaves[a:b], attic[a:b], roof_types[a:b],
                        uniforms[a:b], **kwargs)


def build_solids_parallel(footprints, ground, eaves, attic, roof_types, uniforms, nprocs=1,
                          **kwargs):
    """:func:`build_solids` over ``nprocs`` processes (chunks of footprints).

    The result is the same as with one process: every building depends only
    on its own footprint, heights, type and uniform numbers. Every chunk has
    at least 1,000 footprints (fewer processes otherwise). The calling
    process builds the first chunk itself; forked processes build the others
    from the input they inherit (only their results are sent back).
    """
    B = len(footprints)
    nprocs = min(int(nprocs), B // 1000)          # chunks of at least 1,000 footprints
    if nprocs <= 1:
        return build_solids(footprints, ground, eaves, attic, roof_types, uniforms, **kwargs)
    import multiprocessing

    bounds = np.linspace(0, B, nprocs + 1).astype(int)
    work = (list(footprints), np.asarray(ground, dtype=float), np.asarray(eaves, dtype=float),
            np.asarray(attic, dtype=float), np.array(roof_types, dtype=object),
            np.asarray(uniforms, dtype=float).reshape(B, 3))
    _CHUNKS[:] = [(bounds, work, kwargs)]
    try:
        with multiprocessing.get_context("fork").Pool(nprocs - 1) as pool:
            others = pool.map_async(_build_chunk, range(1, nprocs))
            results = [_build_chunk(0)] + others.get()
    finally:
        _CHUNKS[:] = []
    return _merge([(np.arange(a, b), r) for a, b, r in zip(bounds[:-1], bounds[1:], results)])
