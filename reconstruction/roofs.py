"""Roofs of LoD2 buildings: flat, hip, gable, mansard and crow-stepped gable.

The roof set of Morlighem (2021), Section 3.4.2, built in numpy:

- **hip**: the straight skeleton of the footprint raised at the roof pitch.
  The long faces get the pitch of the thesis's Eq. 3.13,
  ``atan(height / (baseline / 2))``, the hip ends (the shortest edge and the
  edge opposite it) a steeper pitch in ``[pitch_min, 90)`` degrees; the roof
  is then scaled so that its ridge sits exactly at the roof height.
- **gable**: a hip roof whose ends are vertical.
- **mansard**: the skeleton truncated at the roof height with a flat top; the
  inset (horizontal run of the lower faces) stays below half the shortest edge.
- **stepped**: a gable roof whose street end (the shortest edge until the
  street edge is known) is a crow-stepped facade of the given step height and
  thickness, kept inside the footprint.
- **flat**: the footprint at the eaves.

Roofs are computed relative to the eaves (z = 0 along the footprint) in local
coordinates. Convex footprints use the exact identity *straight skeleton of
a convex polygon = lower envelope of the edge planes*: every skeleton node is
the intersection of three planes (sloped edge planes, vertical gable planes,
the flat mansard top) that lies on the envelope, so all footprints with the
same number of vertices are solved in one numpy pass. Concave footprints (L,
U, T shapes) use CGAL's weighted straight skeleton through ``pySVCGAL``
(optional: without it they fall back to a flat roof).

A roof is a dict ``{"vertices": (m, 3) float, "faces": [ring, ...],
"boundary": bool}`` whose first ``n`` vertices are the footprint at z = 0;
faces are rings of vertex indices oriented outwards (seen from outside,
counter-clockwise). ``boundary`` is True when the roof's free boundary is
exactly the footprint outline (walls are then plain quads); otherwise
:mod:`reconstruction.solids` walks the boundary to build the walls.
"""

import contextlib
import itertools
import math
import os

import numpy as np

ROOF_TYPES = ("flat", "hip", "gable", "mansard", "stepped")

#: Roof type probabilities (weights in percent) by period of construction and
#: footprint shape, as in the thesis's Table B.1 as implemented in its published
#: procedural-modelling script (histo3d, ``blender_procedural_mod.py``):
#: "stepped" is its "dutch" roof. For n-sided footprints the script's
#: complex-hip weights are used, since hip and gable roofs work on any
#: footprint here; the split year is 1915 (the thesis's table; the script
#: uses 1930).
ROOF_PROBABILITIES = {
    ("before", 4): {"flat": 10, "hip": 20, "gable": 20, "mansard": 10, "stepped": 40},
    ("after", 4): {"flat": 25, "hip": 25, "gable": 25, "mansard": 10, "stepped": 15},
    ("before", "n"): {"flat": 15, "hip": 65, "mansard": 20},
    ("after", "n"): {"flat": 40, "hip": 40, "mansard": 20},
}
SPLIT_YEAR = 1915
#: Roofs lower than this (m) are flat when the type is drawn (thesis: < 1 m).
MIN_PITCHED_HEIGHT = 1.0

_TOL = 1e-6


def draw_roof_types(n_vertices, years, attic, rng, probabilities=None):
    """Draw a roof type per footprint with the thesis's probabilities.

    ``n_vertices``: vertices per footprint; ``years``: construction year (or
    the map year) per footprint, None/nan = before 1915; ``attic``: roof
    height, below :data:`MIN_PITCHED_HEIGHT` the roof is flat. Returns an
    object array of roof type names.
    """
    probabilities = probabilities or ROOF_PROBABILITIES
    n_vertices = np.asarray(n_vertices)
    years = np.asarray([np.nan if y is None else y for y in np.broadcast_to(
        np.asarray(years, dtype=object), n_vertices.shape)], dtype=float)
    out = np.empty(n_vertices.shape, dtype=object)
    u = rng.random(n_vertices.shape)
    after = np.where(np.isnan(years), False, years > SPLIT_YEAR)
    for period, is_after in (("before", False), ("after", True)):
        for shape in (4, "n"):
            sel = (after == is_after) & ((n_vertices == 4) if shape == 4 else (n_vertices != 4))
            weights = probabilities[(period, shape)]
            names = list(weights)
            cum = np.cumsum([weights[k] for k in names], dtype=float)
            cum /= cum[-1]
            idx = np.minimum(np.searchsorted(cum, u[sel], side="right"), len(names) - 1)
            out[sel] = np.asarray(names, dtype=object)[idx]
    out[np.asarray(attic, dtype=float) < MIN_PITCHED_HEIGHT] = "flat"
    return out


# ---------------------------------------------------------------------------
# Footprint helpers
# ---------------------------------------------------------------------------

def _nxt(a):
    """``a`` shifted by one (next element), cheaper than np.roll on small arrays."""
    return np.concatenate((a[1:], a[:1]))


def _prv(a):
    """``a`` shifted back by one (previous element)."""
    return np.concatenate((a[-1:], a[:-1]))


def edge_lengths(xy):
    """Lengths of the edges ``xy[i] -> xy[i+1]`` of one ring (n, 2)."""
    return np.hypot(*(_nxt(xy) - xy).T)


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
    d1 = xy - _prv(xy)
    d2 = _nxt(xy) - xy
    convex = d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0] > 0
    length = edge_lengths(xy)
    ends = []
    for i in range(n):
        if convex[i] and convex[(i + 1) % n] and length[i] < length[i - 1] \
                and length[i] < length[(i + 1) % n]:
            ends.append(i)
    return ends


# ---------------------------------------------------------------------------
# Convex footprints: lower envelope of planes, in batch
# ---------------------------------------------------------------------------

def envelope_arrays(xy, slopes, top=None):
    """Roofs over convex footprints with the same number of vertices, as arrays.

    ``xy``: (B, n, 2) counter-clockwise footprints in local coordinates;
    ``slopes``: (B, n) tangent of each edge's pitch, ``inf`` for a vertical
    (gable) end; ``top``: (B,) height of a flat top (mansard) or None.
    Returns a dict of arrays: ``nodes`` (B, C, 3) skeleton node candidates
    (z relative to the eaves, unscaled), ``ring_idx`` (B, P, K) and ``cnt``
    (B, P): the faces (one per plane; the first ``cnt`` entries of a ring,
    indices as in a roof dict: footprint vertices 0..n-1, node c -> n + c),
    ``zmax`` (B,) and ``ok`` (B,) (False for degenerate input).
    """
    xy = np.asarray(xy, dtype=float)
    B, n, _ = xy.shape
    slopes = np.asarray(slopes, dtype=float)
    has_top = top is not None
    P = n + 1 if has_top else n
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
    z = nodes[..., 2]
    scale = 1.0 + np.abs(xy).max(axis=(1, 2))[:, None]
    tol = _TOL * scale
    valid = ok & (d.min(axis=-1) > -tol) & (z > tol) & (np.abs(z - env) < tol * (1 + np.abs(env)))
    active = np.empty((B, C, P), dtype=bool)
    active[..., :n] = np.where(vertical[:, None, :], np.abs(d) < tol[..., None],
                               np.abs(plane_z - z[..., None]) < tol[..., None] * (1 + np.abs(z[..., None])))
    if has_top:
        active[..., n] = np.abs(z - top[:, None]) < tol * (1 + np.abs(z))
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
    return {"xy": xy, "nodes": nodes, "ring_idx": ring_idx, "cnt": cnt,
            "zmax": np.where(ok, zmax, 0.0), "ok": ok}


def envelope_roofs(xy, slopes, top=None):
    """Roofs over convex footprints with the same number of vertices, as a
    list of roof dicts (see the module doc); see :func:`envelope_arrays`."""
    g = envelope_arrays(xy, slopes, top)
    return [_roof_dict(g, b) for b in range(len(g["xy"]))]


def _roof_dict(g, b):
    """The roof dict of footprint ``b`` of an :func:`envelope_arrays` group."""
    xy = g["xy"][b]
    n = len(xy)
    cnt = g["cnt"][b].tolist()
    rings = g["ring_idx"][b].tolist()
    faces = [r[:k] for r, k in zip(rings, cnt) if k >= 3] if g["ok"][b] else None
    verts = np.concatenate([np.concatenate([xy, np.zeros((n, 1))], axis=1), g["nodes"][b]])
    return {"vertices": verts, "faces": faces, "boundary": True, "zmax": float(g["zmax"][b])}


# ---------------------------------------------------------------------------
# Concave footprints: CGAL's straight skeleton through pySVCGAL
# ---------------------------------------------------------------------------

_CGAL = []


@contextlib.contextmanager
def _quiet_stdout():
    """Silence what the C++ library writes straight to file descriptors 1 and 2."""
    import sys

    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except Exception:  # pragma: no cover
            pass
    try:
        saved = [os.dup(1), os.dup(2)]
    except OSError:  # pragma: no cover
        yield
        return
    try:
        with open(os.devnull, "w") as null:
            os.dup2(null.fileno(), 1)
            os.dup2(null.fileno(), 2)
            try:
                yield
            finally:
                _flush_c_stdout()
                os.dup2(saved[0], 1)
                os.dup2(saved[1], 2)
    finally:
        for fd in saved:
            os.close(fd)


def _flush_c_stdout():
    """Flush C stdio and C++ std::cout (the CGAL wrapper writes to both)."""
    import ctypes

    try:
        ctypes.CDLL(None).fflush(None)
    except Exception:  # pragma: no cover
        pass
    try:
        lib = ctypes.CDLL("libstdc++.so.6")
        for name in ("_ZSt4cout", "_ZSt4clog", "_ZSt4cerr"):
            stream = ctypes.addressof(ctypes.c_char.in_dll(lib, name))
            lib._ZNSo5flushEv(ctypes.c_void_p(stream))
    except Exception:  # pragma: no cover
        pass


def cgal_available():
    """True when pySVCGAL (CGAL's straight skeleton) can be imported."""
    if not _CGAL:
        try:
            with _quiet_stdout(), contextlib.redirect_stdout(open(os.devnull, "w")):
                from pySVCGAL.pySVCGAL import pySVCGAL_straight_skeleton_2d_extrude
            _CGAL.append(pySVCGAL_straight_skeleton_2d_extrude)
        except Exception:  # pragma: no cover - optional dependency
            _CGAL.append(None)
    return _CGAL[0] is not None


def _cgal_extrude(footprints, pitches, heights):
    """Call CGAL's skeleton extrusion of pySVCGAL's library with numpy arrays
    (its Python wrapper converts every vertex one by one). Returns
    ``{"objects": [{"object_index", "vertices", "faces"}]}`` as the wrapper."""
    import ctypes

    from pySVCGAL.pySVCGAL import MESH_DATA2, SVCGAL_clib

    fn = SVCGAL_clib.straight_skeleton_2d_extrude
    fn.argtypes = [ctypes.c_int, ctypes.POINTER(ctypes.c_int), ctypes.POINTER(ctypes.c_bool),
                   ctypes.POINTER(ctypes.c_double), ctypes.POINTER(ctypes.c_double),
                   ctypes.POINTER(ctypes.c_int), ctypes.POINTER(ctypes.c_int),
                   ctypes.POINTER(ctypes.c_int), ctypes.POINTER(ctypes.c_float * 3),
                   ctypes.c_bool, ctypes.c_bool, ctypes.c_int, ctypes.c_bool]
    fn.restype = ctypes.POINTER(MESH_DATA2)
    free = SVCGAL_clib.free_mem2
    free.argtypes = [ctypes.POINTER(MESH_DATA2)]
    B = len(footprints)
    counts = np.array([len(xy) for xy in footprints], dtype=np.int32)
    verts = np.zeros((int(counts.sum()), 3), dtype=np.float32)
    verts[:, :2] = np.concatenate(footprints)
    # the library takes the angle of edge i at position i + 1
    angles = np.concatenate([np.roll(np.asarray(a, dtype=float), 1) for a in pitches])
    restrict = np.array([h is not None for h in heights], dtype=np.bool_)
    height = np.array([0.0 if h is None else float(h) for h in heights], dtype=np.float64)
    modes = np.zeros(B, dtype=np.int32)
    ones = np.ones(B, dtype=np.int32)

    def ptr(a, t):
        return a.ctypes.data_as(ctypes.POINTER(t))

    md = fn(B, ptr(modes, ctypes.c_int), ptr(restrict, ctypes.c_bool),
            ptr(height, ctypes.c_double), ptr(np.ascontiguousarray(angles), ctypes.c_double),
            ptr(ones, ctypes.c_int), ptr(ones, ctypes.c_int), ptr(counts, ctypes.c_int),
            ptr(verts, ctypes.c_float * 3), False, False, 0, False)
    try:
        m = md.contents
        nobj = m.nn_objects
        objects = []
        if nobj > 0:
            def arr(pointer, n, t=ctypes.c_int):
                if n == 0:
                    return np.zeros(0)
                return np.ctypeslib.as_array(ctypes.cast(pointer, ctypes.POINTER(t)), shape=(n,)).copy()

            idx = arr(m.nn_objects_indexes, nobj)
            nv = arr(m.nn_verts, nobj)
            nf = arr(m.nn_faces, nobj)
            counters = arr(m.nn_faces_indexes_counters, int(nf.sum()))
            allv = arr(m.vertices, int(nv.sum()) * 3, ctypes.c_float).reshape(-1, 3)
            allf = arr(m.faces, int(counters.sum()))
            v0 = f0 = k0 = 0
            for i in range(nobj):
                cnt = counters[f0:f0 + nf[i]]
                flat = allf[k0:k0 + int(cnt.sum())]
                bounds = np.concatenate([[0], np.cumsum(cnt)])
                faces = [flat[bounds[j]:bounds[j + 1]].tolist() for j in range(len(cnt))]
                objects.append({"object_index": int(idx[i]),
                                "vertices": allv[v0:v0 + nv[i]].astype(float), "faces": faces})
                v0 += nv[i]
                f0 += nf[i]
                k0 += int(cnt.sum())
        return {"objects": objects}
    finally:
        free(md)


def cgal_roofs(footprints, pitches, heights):
    """Roofs over any simple footprints with CGAL's weighted straight skeleton.

    ``footprints``: list of (n, 2) counter-clockwise rings (local coordinates);
    ``pitches``: list of per-edge pitch angles in degrees (90 = gable end);
    ``heights``: list of flat-top heights (mansard) or None. Returns a list of
    roof dicts (faces are triangles) or None where CGAL failed.
    """
    if not cgal_available():
        return [None] * len(footprints)
    try:
        with _quiet_stdout():
            result = _cgal_extrude(footprints, pitches, heights)
    except Exception:
        return [None] * len(footprints)
    out = [None] * len(footprints)
    for obj in result.get("objects", []):
        i = obj["object_index"]
        xy = footprints[i]
        n = len(xy)
        v = np.asarray(obj["vertices"], dtype=float).reshape(-1, 3)
        if len(v) < n or not np.allclose(v[:n, :2], xy, atol=1e-3):
            continue
        v[:n, :2] = xy
        v[:n, 2] = 0.0
        faces = [list(f) for f in obj["faces"] if not all(k < n for k in f)]
        if not faces:
            continue
        # orient outwards: the roof seen from above is counter-clockwise
        nz = 0.0
        for f in faces:
            a, b, cc = v[f[0]], v[f[1]], v[f[2]]
            nz += (b[0] - a[0]) * (cc[1] - a[1]) - (b[1] - a[1]) * (cc[0] - a[0])
        if nz < 0:
            faces = [f[::-1] for f in faces]
        out[i] = {"vertices": v, "faces": faces, "boundary": False,
                  "zmax": float(v[:, 2].max())}
    return out


# ---------------------------------------------------------------------------
# Roof parameters per type
# ---------------------------------------------------------------------------

def scale_roof(roof, height):
    """Scale a roof's heights so that its highest point is at ``height``."""
    if roof is None or roof["faces"] is None or roof["zmax"] <= 1e-9:
        return None
    v = roof["vertices"].copy()
    v[:, 2] *= height / roof["zmax"]
    return dict(roof, vertices=v, zmax=height)


def flat_roof(xy):
    """The flat roof: the footprint itself at the eaves."""
    n = len(xy)
    v = np.concatenate([xy, np.zeros((n, 1))], axis=1)
    return {"vertices": v, "faces": [list(range(n))], "boundary": True, "zmax": 0.0}


# ---------------------------------------------------------------------------
# Crow-stepped gable
# ---------------------------------------------------------------------------

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


def stepped_arrays(xy, ends, body, steps, thickness):
    """Crow-stepped gable roofs over convex footprints with the same number of
    vertices, as arrays.

    ``xy``: (G, n, 2) footprints (local coordinates, counter-clockwise);
    ``ends``: (G,) index of the stepped edge; ``body``: the
    :func:`envelope_arrays` gable roofs (scaled to the roof height) of the main
    bodies from :func:`clip_strips` (inner edge first, vertical face on edge
    0); ``steps``: (G,) step heights; ``thickness`` of the facade. The facade
    is a slab between the street edge and the inner edge whose profile rises
    in steps of ``steps`` above the body roof's gable profile.

    Returns a list of groups, one per number of steps, dicts of arrays:
    ``rows`` (indices into the input), ``roof`` (g, R, 3) roof vertices (the
    footprint at z = 0 first, then the body roof, then the facade corners),
    ``ring_idx`` (g, F, K) and ``cnt`` (g, F) the faces (first ``cnt``
    entries; 0 = no face), ``wall_mid`` (g, n) the roof vertex on the
    boundary along each footprint edge between its ends (-1 = none: the
    inner edge's ends on the edges next to the street edge), ``zmax``. Rows
    whose facade cannot be built (steps too narrow, no gable profile) are in
    no group.
    """
    xy = np.asarray(xy, dtype=float)
    G, n, _ = xy.shape
    ends = np.asarray(ends, dtype=np.int64)
    steps = np.asarray(steps, dtype=float)
    rows = np.arange(G)
    bxy, nodes, ring_idx, cnt = body["xy"], body["nodes"], body["ring_idx"], body["cnt"]
    C = nodes.shape[1]
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
    s = steps
    margin = np.minimum(0.1, s / 4.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        nsteps = np.ceil((H + margin) / s)
    ok = body["ok"] & (T > 0) & (H > 1e-3) & np.isfinite(nsteps)
    nsteps = np.where(ok, nsteps, 1).astype(np.int64)
    iapex = np.argmax(pz, axis=1)
    last = T + 1
    rising = np.minimum(col[None, :], iapex[:, None])
    falling = np.maximum(last[:, None] - col[None, :], iapex[:, None])
    lo, hi = np.maximum(0.0, ua), np.minimum(L, ub)
    out = []
    for q in np.unique(nsteps[ok]):
        sel = np.nonzero(ok & (nsteps == q))[0]
        g = len(sel)
        Q = int(q) - 1
        zq = np.arange(1, Q + 1, dtype=float)[None, :] * s[sel, None] - margin[sel, None]
        uL = _interp_rows(zq, np.take_along_axis(pz[sel], rising[sel], axis=1),
                          np.take_along_axis(pu[sel], rising[sel], axis=1))
        uR = _interp_rows(zq, np.take_along_axis(pz[sel], falling[sel], axis=1),
                          np.take_along_axis(pu[sel], falling[sel], axis=1))
        seq = np.concatenate([lo[sel, None], uL, uR[:, ::-1], hi[sel, None]], axis=1)
        wide = np.all(np.diff(seq, axis=1) >= 0.02, axis=1)
        sel, uL, uR = sel[wide], uL[wide], uR[wide]
        g = len(sel)
        if g == 0:
            continue
        zs = np.arange(1, Q + 2, dtype=float)[None, :] * s[sel, None]
        # outline of the stepped profile, left to right: (u, z) corners
        nc = 4 + 4 * Q
        cu = np.empty((g, nc))
        cz = np.empty((g, nc))
        cu[:, 0] = cu[:, 1] = lo[sel]
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
        cu[:, -2] = cu[:, -1] = hi[sel]
        cz[:, -2], cz[:, -1] = zs[:, 0], 0.0
        # inner corners on the front (the street edge) and the back (inner edge)
        m = nc - 2
        fxy = a[sel, None] + cu[:, 1:-1, None] * t[sel, None]
        bk = fxy + (nrm[sel] * thickness)[:, None]
        fxy[:, 0], fxy[:, -1] = a[sel], b[sel]
        bk[:, 0], bk[:, -1] = qa[sel], qb[sel]
        # roof vertices: footprint, body roof (its base, then its nodes), facade
        R = 2 * n + C + 2 * m
        roof = np.zeros((g, R, 3))
        roof[:, :n, :2] = xy[sel]
        roof[:, n:2 * n, :2] = bxy[sel]
        roof[:, 2 * n:2 * n + C] = nodes[sel]
        base = 2 * n + C
        roof[:, base:base + m, :2] = fxy
        roof[:, base + m:, :2] = bk
        roof[:, base:base + m, 2] = cz[:, 1:-1]
        roof[:, base + m:, 2] = cz[:, 1:-1]
        e = ends[sel]
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
        Kf = max(m + 2 + K, Kb, 4)
        faces = np.zeros((g, F, Kf), dtype=np.int64)
        fcnt = np.zeros((g, F), dtype=np.int64)
        # front facade, seen from the street
        faces[:, 0, :m + 2] = front[:, ::-1]
        fcnt[:, 0] = m + 2
        # back face (towards the ridge): the gable profile (right to left), then the outline
        Tg = T[sel]
        prof_rev = np.where(np.arange(K)[None, :] < Tg[:, None],
                            np.take_along_axis(top_k[sel], np.clip(Tg[:, None] - 1 - np.arange(K), 0,
                                                                   K - 1), axis=1), 0) + 2 * n
        pos = np.arange(Kf)[None, :]
        faces[:, 1] = np.where(pos < Tg[:, None], prof_rev[:, np.minimum(np.arange(Kf), K - 1)],
                               back[np.arange(g)[:, None], np.clip(pos - Tg[:, None], 0, m + 1)])
        fcnt[:, 1] = Tg + m + 2
        # side faces of the slab
        faces[:, 2, :4] = np.stack([ia, front[:, 1], back[:, 1], np.full(g, i_qa)], axis=1)
        faces[:, 3, :4] = np.stack([ib, np.full(g, i_qb), back[:, -2], front[:, -2]], axis=1)
        fcnt[:, 2:4] = 4
        # treads and risers
        i = np.arange(1, m)
        faces[:, 4:4 + m - 1, :4] = np.stack([front[:, i], front[:, i + 1], back[:, i + 1],
                                              back[:, i]], axis=2)
        fcnt[:, 4:4 + m - 1] = 4
        # the body roof but its vertical face on the inner edge; its base vertices
        # beyond the inner edge are the footprint's
        k = ring_idx[sel, 1:]
        mapped = np.where((k >= 2) & (k < n), (e[:, None, None] + k) % n, n + k)
        faces[:, 4 + m - 1:, :Kb] = mapped
        bc = cnt[sel, 1:]
        fcnt[:, 4 + m - 1:] = np.where(bc >= 3, bc, 0)
        wall_mid = np.full((g, n), -1, dtype=np.int64)
        wall_mid[np.arange(g), (e - 1) % n] = i_qa
        wall_mid[np.arange(g), ib] = i_qb
        out.append({"rows": sel, "roof": roof, "ring_idx": faces, "cnt": fcnt,
                    "wall_mid": wall_mid, "zmax": roof[..., 2].max(axis=1)})
    return out


def _walked_roof_dict(group, j):
    """The roof dict (with boundary ``chains``) of row ``j`` of a
    :func:`stepped_arrays` group."""
    roof = group["roof"][j]
    n = group["wall_mid"].shape[1]
    faces = [r[:c] for r, c in zip(group["ring_idx"][j].tolist(), group["cnt"][j].tolist()) if c]
    chains = [[k, (k + 1) % n] if mid < 0 else [k, mid, (k + 1) % n]
              for k, mid in enumerate(group["wall_mid"][j].tolist())]
    return {"vertices": roof, "faces": faces, "boundary": False, "chains": chains,
            "zmax": float(group["zmax"][j])}


# ---------------------------------------------------------------------------
# All roofs of a set of footprints
# ---------------------------------------------------------------------------

def street_end(xy, street=None):
    """The street end of a footprint: ``street`` when given, else the shortest edge."""
    if street is not None and 0 <= int(street) < len(xy):
        return int(street)
    return int(np.argmin(edge_lengths(xy)))


def outline_facts(footprints, street=None):
    """What the roofs need to know of each footprint's outline, in bulk
    (one numpy pass per vertex count): a dict of arrays ``convex``, ``end``
    (see :func:`street_end`), ``shortest`` (edge length), ``end_length`` and
    ``opposite`` (see :func:`opposite_edge`; -1 = none)."""
    B = len(footprints)
    out = {"convex": np.zeros(B, dtype=bool), "end": np.zeros(B, dtype=np.int64),
           "shortest": np.zeros(B), "end_length": np.zeros(B),
           "opposite": np.full(B, -1, dtype=np.int64)}
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
        out["convex"][idx] = convex_rings(xy)
        out["end"][idx] = end
        out["shortest"][idx] = ln.min(axis=1)
        out["end_length"][idx] = ln[np.arange(len(idx)), end]
        out["opposite"][idx] = opposite_edges(xy, end) if n > 3 else -1
    return out


def _batch_envelope(jobs):
    """Run :func:`envelope_arrays` on jobs ``(key, xy, slopes, top)`` grouped
    by vertex count; returns a list of groups (the arrays plus ``keys``)."""
    groups = {}
    for key, xy, slopes, top in jobs:
        groups.setdefault((len(xy), top is not None), []).append((key, xy, slopes, top))
    out = []
    for (n, has_top), items in groups.items():
        xy = np.stack([it[1] for it in items])
        slopes = np.stack([it[2] for it in items])
        top = np.array([it[3] for it in items], dtype=float) if has_top else None
        g = envelope_arrays(xy, slopes, top)
        g["keys"] = [it[0] for it in items]
        g["top"] = has_top
        out.append(g)
    return out


def make_roofs(footprints, roof_types, attic, uniforms, street=None, pitch_min=60.0,
               inset=(1.0, 2.0), step=(0.4, 0.7), thickness=0.5, bulk=False):
    """Roofs of footprints (local coordinates, counter-clockwise rings).

    ``roof_types``: a type per footprint; ``attic``: roof heights above the
    eaves; ``uniforms``: (B, 3) uniform numbers in [0, 1) per footprint (hip
    end pitch, mansard inset, crow-step height), so that the result does not
    depend on the order of work; ``street``: optional street edge index per
    footprint. Returns a list of roof dicts, None where the type could not be
    built (the caller falls back to a simpler type), and the type each roof
    really got (a stepped gable on a concave or triangular footprint is a
    gable). With ``bulk=True`` flat roofs and the roofs of convex footprints
    come as a third result instead, groups of arrays (``index``, ``xy`` and,
    but for flat roofs, the :func:`envelope_arrays` ``nodes``, ``ring_idx``,
    ``cnt``, or for crow-stepped gables the :func:`stepped_arrays` ``roof``,
    ``ring_idx``, ``cnt``, ``wall_mid``) for
    :func:`reconstruction.solids.build_solids`.
    """
    B = len(footprints)
    roofs = [None] * B
    kinds = list(roof_types)
    uniforms = np.asarray(uniforms, dtype=float).reshape(B, 3)
    env_jobs, cgal_jobs, stepped, flat_jobs = [], [], {}, {}
    facts = outline_facts(footprints, street)
    convex_all, end_all, opp_all = (facts[k].tolist() for k in ("convex", "end", "opposite"))
    attic = np.asarray(attic, dtype=float)
    # crow-stepped gables on convex footprints: the main body behind the facade
    flat = np.array([k == "flat" for k in roof_types], dtype=bool) | (attic <= 1e-3)
    want = np.array([k == "stepped" for k in roof_types], dtype=bool) & ~flat & facts["convex"]
    want &= np.array([len(xy) >= 4 for xy in footprints], dtype=bool)
    bodies = {}
    for n in sorted({len(footprints[i]) for i in np.nonzero(want)[0]}):
        idx = np.array([i for i in np.nonzero(want)[0] if len(footprints[i]) == n])
        body, ok = clip_strips(np.stack([footprints[i] for i in idx]), facts["end"][idx], thickness)
        opp = opposite_edges(body, np.zeros(len(idx), dtype=np.int64))
        for k in np.nonzero(ok)[0]:
            bodies[int(idx[k])] = (body[k], int(opp[k]))
    for i, (xy, kind) in enumerate(zip(footprints, roof_types)):
        h = float(attic[i])
        n = len(xy)
        if flat[i]:
            if bulk:
                flat_jobs.setdefault(n, []).append(i)
            else:
                roofs[i] = flat_roof(xy)
            continue
        end = end_all[i]
        convex = convex_all[i]
        if kind == "mansard":
            lo, hi = inset
            cap = 0.45 * float(facts["shortest"][i])
            ins = max(min(lo + (hi - lo) * uniforms[i, 1], cap), 1e-3)
            if convex:
                env_jobs.append((i, xy, np.full(n, h / ins), h))
            else:
                cgal_jobs.append((i, xy, np.full(n, math.degrees(math.atan2(h, ins))), h))
            continue
        if kind == "stepped" and i in bodies:
            body, opp = bodies[i]
            slopes = np.ones(len(body))
            slopes[0] = np.inf
            if opp >= 0:
                slopes[opp] = np.inf
            s_lo, s_hi = step
            stepped[i] = (end, s_lo + (s_hi - s_lo) * uniforms[i, 2])
            env_jobs.append((("body", i), body, slopes, None))
            continue
        if kind == "stepped":
            kind = "gable"
        kinds[i] = kind
        if convex:
            slopes = np.ones(n)
            opp = opp_all[i]
            if kind == "hip" and n == 4:
                base = float(facts["end_length"][i])
                p_long = math.degrees(math.atan2(h, base / 2.0))
                low = min(max(pitch_min, p_long), 89.0)
                p_end = low + (89.0 - low) * uniforms[i, 0]
                ratio = math.tan(math.radians(p_end)) / math.tan(math.radians(p_long))
                slopes[end] = ratio
                if opp >= 0:
                    slopes[opp] = ratio
            elif kind == "gable":
                slopes[end] = np.inf
                if opp >= 0:
                    slopes[opp] = np.inf
            env_jobs.append((i, xy, slopes, None))
        else:
            pitch = np.full(n, 45.0)
            if kind == "gable":
                ends = end_edges(xy) or [end]
                pitch[ends] = 90.0
            cgal_jobs.append((i, xy, pitch, None))
    bulk_groups = []
    for g in _batch_envelope(env_jobs):
        keys = g["keys"]
        if not g["top"]:                  # hip, gable, stepped bodies: ridge at the roof height
            h = np.array([attic[k[1]] if isinstance(k, tuple) else attic[k] for k in keys],
                         dtype=float)
            factor = np.where(g["ok"], h / np.where(g["zmax"] > 0, g["zmax"], 1.0), 0.0)
            g["nodes"] = g["nodes"].copy()
            g["nodes"][..., 2] *= factor[:, None]
            g["zmax"] = np.where(g["ok"], h, 0.0)
        plain = [j for j, k in enumerate(keys) if not isinstance(k, tuple)]
        bodies = np.array([j for j, k in enumerate(keys) if isinstance(k, tuple)], dtype=int)
        if len(bodies):
            owner = np.array([keys[j][1] for j in bodies], dtype=int)
            facades = stepped_arrays(
                np.stack([footprints[i] for i in owner]), [stepped[i][0] for i in owner],
                {k: g[k][bodies] for k in ("xy", "nodes", "ring_idx", "cnt", "ok")},
                [stepped[i][1] for i in owner], thickness)
            for sg in facades:
                idx = owner[sg["rows"]]
                if bulk:
                    bulk_groups.append(dict(sg, index=idx, xy=np.stack([footprints[i] for i in idx])))
                else:
                    for j, i in enumerate(idx):
                        roofs[i] = _walked_roof_dict(sg, j)
        if bulk:
            sel = np.array(plain, dtype=int)
            sel = sel[g["ok"][sel]]
            if len(sel):
                bulk_groups.append({"index": np.array([keys[j] for j in sel], dtype=int),
                                    "xy": g["xy"][sel], "nodes": g["nodes"][sel],
                                    "ring_idx": g["ring_idx"][sel], "cnt": g["cnt"][sel]})
        else:
            for j in plain:
                roofs[keys[j]] = _roof_dict(g, j) if g["ok"][j] else None
    for n, idx in flat_jobs.items():
        bulk_groups.append({"index": np.array(idx, dtype=int),
                            "xy": np.stack([footprints[i] for i in idx])})
    if cgal_jobs:
        res = cgal_roofs([j[1] for j in cgal_jobs], [j[2] for j in cgal_jobs],
                         [j[3] for j in cgal_jobs])
        for (i, _, _, top), roof in zip(cgal_jobs, res):
            roofs[i] = roof if top is not None else scale_roof(roof, float(attic[i]))
    if bulk:
        return roofs, kinds, bulk_groups
    return roofs, kinds
