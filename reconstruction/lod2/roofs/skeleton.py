"""Roofs of any simple footprint: CGAL's weighted straight skeleton through ``pySVCGAL``.

Concave footprints (L, U, T shapes) get their hip, gable and mansard roofs
here. ``pySVCGAL`` is optional: without it :func:`cgal_roofs` builds nothing
and those footprints fall back to a flat roof. Its C++ library writes to
the process's standard output, which is silenced while it runs; the
skeletons of many footprints are computed in one call (which releases the
interpreter, so that it runs beside other work in a thread).
"""

import contextlib
import ctypes
import os
import sys

import numpy as np

from ...geom.rings import offsets
from .model import Roof

_CGAL = []


@contextlib.contextmanager
def _quiet_stdout():
    """Silence what the C++ library writes straight to file descriptors 1 and 2."""
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
                bounds = offsets(cnt)
                faces = [flat[bounds[j]:bounds[j + 1]].tolist() for j in range(len(cnt))]
                objects.append({"object_index": int(idx[i]),
                                "vertices": allv[v0:v0 + nv[i]].astype(float), "faces": faces})
                v0 += nv[i]
                f0 += nf[i]
                k0 += int(cnt.sum())
        return {"objects": objects}
    finally:
        free(md)


def _guarded_extrude(footprints, pitches, heights, index):
    """``[(footprint index, object), ...]`` of :func:`_cgal_extrude` on the
    footprints ``index``: where the library fails on a batch, the two halves
    are tried apart, so that one footprint it cannot solve costs only its
    own roof."""
    try:
        result = _cgal_extrude([footprints[i] for i in index], [pitches[i] for i in index],
                               [heights[i] for i in index])
    except Exception:
        if len(index) == 1:
            return []
        half = len(index) // 2
        return (_guarded_extrude(footprints, pitches, heights, index[:half])
                + _guarded_extrude(footprints, pitches, heights, index[half:]))
    return [(int(index[obj["object_index"]]), obj) for obj in result.get("objects", [])]


def cgal_roofs(footprints, pitches, heights):
    """Roofs over any simple footprints with CGAL's weighted straight skeleton.

    ``footprints``: list of (n, 2) counter-clockwise rings (local coordinates);
    ``pitches``: list of per-edge pitch angles in degrees (90 = gable end);
    ``heights``: list of flat-top heights (mansard) or None. Returns a list of
    :class:`~reconstruction.lod2.roofs.model.Roof` (faces are triangles) or None
    where CGAL failed (a failure costs only the footprints it fails on).
    """
    if not cgal_available():
        return [None] * len(footprints)
    out = [None] * len(footprints)
    with _quiet_stdout():
        objects = _guarded_extrude(footprints, pitches, heights, np.arange(len(footprints)))
    for i, obj in objects:
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
        out[i] = Roof(v, merge_needles(v, weld(v, faces, n)), False, float(v[:, 2].max()))
    return out


#: a triangle whose vertex lies within this (m) of its opposite side is a
#: needle; vertices closer than this are one (val3dity snaps them together)
NEEDLE_WIDTH = 1e-3


def weld(vertices, faces, fixed=0, tol=NEEDLE_WIDTH):
    """``faces`` with the vertices closer than ``tol`` to an earlier one
    replaced by it (the first ``fixed``, the footprint's, are never merged
    with each other), repeated vertices in a ring dropped, and the rings
    left with fewer than three vertices gone. The skeleton ends arcs a
    fraction of a millimetre apart where a face over a very short edge
    closes; val3dity would snap those vertices together."""
    v = np.asarray(vertices, dtype=float)
    V = len(v)
    rep = np.arange(V)
    if V > 1:
        d = np.linalg.norm(v[:, None, :] - v[None, :, :], axis=-1)
        close = np.triu(d < tol, k=1)
        close[:fixed, :fixed] = False
        for i, j in zip(*np.nonzero(close)):
            if rep[j] == j:
                rep[j] = rep[i]
    if np.all(rep == np.arange(V)):
        return [list(f) for f in faces]
    out = []
    for f in faces:
        ring = [int(rep[k]) for k in f]
        ring = [k for t, k in enumerate(ring) if k != ring[t - 1]] if len(ring) > 1 else ring
        if len(set(ring)) >= 3:
            out.append(ring)
    return out


def merge_needles(vertices, faces, width=NEEDLE_WIDTH):
    """``faces`` (rings of indices into ``vertices`` (V, 3), consistently
    oriented) without their needles: a triangle whose vertex ``m`` lies
    within ``width`` of the opposite side ``a - b`` (between them) and the
    triangle across that side, ``a -> b -> c``, become ``a -> m -> c`` and
    ``m -> b -> c`` (the side flipped to ``m - c``).

    The skeleton makes such triangles along its arcs where a face over a
    very short footprint edge ends; once the vertices are rounded to the
    millimetre, a needle may face downwards, which is a self-intersecting
    shell (val3dity). The two new triangles lie within ``width`` of the
    plane of the one across. Not a polygon with ``m`` nearly on its side:
    val3dity's triangulation of it has a needle too, its normal astray
    (error 204). Needles with no triangle across (the footprint's boundary,
    a polygon face) are kept."""
    faces = [list(f) for f in faces]
    v = np.asarray(vertices, dtype=float)
    for _ in range(len(faces)):                           # each split removes a needle
        needles = _needles(v, faces, width)
        if not needles:
            return faces
        across = {(a, b): k for k, f in enumerate(faces) for a, b in zip(f, f[1:] + f[:1])}
        for k, j in needles:
            f = faces[k]
            a, m, b = f[j - 1], f[j], f[(j + 1) % 3]      # the ring runs a -> m -> b -> a
            other = across.get((a, b))
            if other is None or len(faces[other]) != 3 or m in faces[other]:
                continue
            g = faces[other]
            c = g[(g.index(a) + 2) % 3]                       # it runs a -> b -> c
            if _off_line(v[c], v[a], v[b]) > 2.0 * width:     # not a needle itself
                faces[other] = [a, m, c]
                faces[k] = [m, b, c]
                break
        else:
            return faces                                  # no needle can go
    return faces


def _off_line(p, a, b):
    """Distance of point ``p`` to the line through ``a`` and ``b``."""
    d = b - a
    return float(np.linalg.norm(np.cross(p - a, d)) / max(np.linalg.norm(d), 1e-300))


def _needles(v, faces, width):
    """(face, corner) of the triangles among ``faces`` whose vertex ``corner``
    lies within ``width`` of the opposite side, between its ends: all at once."""
    k = np.array([i for i, f in enumerate(faces) if len(f) == 3], dtype=np.int64)
    if not len(k):
        return []
    p = v[np.array([faces[i] for i in k])]                  # (T, 3, 3)
    m = p
    a = np.roll(p, 1, axis=1)                               # the vertex before each corner
    d = np.roll(p, -1, axis=1) - a                          # its opposite side, a -> b
    dd = np.einsum("tjx,tjx->tj", d, d)
    t = np.einsum("tjx,tjx->tj", m - a, d) / np.where(dd > 0, dd, 1.0)
    gap = np.linalg.norm(a + t[..., None] * d - m, axis=-1)
    hit = (dd > 0) & (t > 0.0) & (t < 1.0) & (gap < width)
    return [(int(k[i]), int(j)) for i, j in zip(*np.nonzero(hit))]

