"""Roofs of two slopes on any footprint: the straight skeleton truncated at a
knee, then the skeleton of its top.

A gambrel is steep up to its knee and flatter above it; a half-hip has a
gable wall up to a height and a small hip above it. On a convex footprint
both are lower envelopes (:mod:`~reconstruction.lod2.roofs.envelope`); on a
concave one they are built in two stages with CGAL's weighted straight
skeleton: the footprint's skeleton with the lower pitches, truncated at the
knee height (as a mansard's), and on each piece of its flat top the
skeleton with the upper pitches. Each top edge is the offset of one
footprint edge (parallel to it, at the knee height over that edge's
tangent from it) and takes that edge's upper pitch. An arm narrower than
the knee's run is steep up to its ridge (its skeleton ends below the knee).
"""

import numpy as np

from .model import Roof
from .skeleton import cgal_roofs, merge_needles, weld

#: a vertex of the truncated roof is on its top within this (m) (CGAL works in float32)
TOP_TOLERANCE = 1e-4
#: the upper roof's nodes closer than this (m) are one: where three ridges
#: meet in one point of a symmetric top (a T's crossing), CGAL's inexact
#: kernel leaves three nodes a millimetre apart, with slivers between them
UPPER_WELD = 1e-2


def _top_rings(roof, knee):
    """The counter-clockwise rings (vertex numbers of ``roof``) bounding the
    flat top of a truncated roof at height ``knee``, and its other faces."""
    v = roof.vertices
    on_top = np.abs(v[:, 2] - knee) < TOP_TOLERANCE
    top = [f for f in roof.faces if all(on_top[k] for k in f)]
    rest = [f for f in roof.faces if not all(on_top[k] for k in f)]
    directed = {(a, b) for f in top for a, b in zip(f, f[1:] + f[:1])}
    nxt = {}
    for a, b in directed:
        if (b, a) not in directed:
            nxt.setdefault(a, []).append(b)
    rings = []
    while nxt:
        start = next(iter(nxt))
        ring = [start]
        while True:
            following = nxt.get(ring[-1])
            if not following:
                return None, rest               # the boundary does not close: give up
            k = following.pop()
            if not following:
                del nxt[ring[-1]]
            if k == start:
                break
            ring.append(k)
            if len(ring) > len(v):
                return None, rest
        rings.append(ring)
    return rings, rest


def _source_edges(xy, pitches, points, knee):
    """For each edge of a top ring (``points`` (m, 2), counter-clockwise), the
    footprint edge it is the offset of: parallel, same direction, and at
    ``knee / tan(pitch)`` inside it (0 for a vertical end)."""
    nxt = np.roll(xy, -1, axis=0)
    t = nxt - xy
    t /= np.hypot(t[:, 0], t[:, 1])[:, None]
    run = np.where(np.asarray(pitches) >= 90.0 - 1e-9, 0.0,
                   knee / np.tan(np.radians(np.minimum(pitches, 89.999))))
    a, b = points, np.roll(points, -1, axis=0)
    u = b - a
    u /= np.maximum(np.hypot(u[:, 0], u[:, 1]), 1e-300)[:, None]
    cross = u[:, None, 0] * t[None, :, 1] - u[:, None, 1] * t[None, :, 0]
    dot = u @ t.T
    mid = (a + b) / 2.0
    dist = (t[None, :, 0] * (mid[:, None, 1] - xy[None, :, 1])
            - t[None, :, 1] * (mid[:, None, 0] - xy[None, :, 0]))
    miss = np.abs(dist - run[None, :]) + np.where((np.abs(cross) < 1e-3) & (dot > 0), 0.0, np.inf)
    return np.argmin(miss, axis=1)


def staged_roofs(footprints, lower, upper, knees):
    """Two-slope roofs of any simple footprints (local coordinates,
    counter-clockwise): ``lower`` and ``upper``: per footprint the pitch of
    each edge (degrees, 90 = vertical) below and above its knee; ``knees``:
    the knee heights above the eaves. Returns a
    :class:`~reconstruction.lod2.roofs.model.Roof` per footprint (unscaled:
    the ridge is where the pitches put it), None where one cannot be built."""
    out = [None] * len(footprints)
    stage1 = cgal_roofs(footprints, lower, list(knees))
    jobs = []                       # (footprint, its truncated roof, a top ring)
    below = {}                      # footprint -> its truncated roof's faces but the top
    for i, roof in enumerate(stage1):
        if roof is None:
            continue
        knee = float(knees[i])
        if roof.zmax < knee - TOP_TOLERANCE:
            out[i] = roof                        # no top: the knee is above every ridge
            continue
        rings, below[i] = _top_rings(roof, knee)
        if rings is None:
            continue
        jobs.extend((i, roof, ring) for ring in rings)
    tops = [roof.vertices[ring, :2] for _, roof, ring in jobs]
    pitches = [np.asarray(upper[i], dtype=float)[
        _source_edges(footprints[i], lower[i], top, float(knees[i]))]
        for (i, _, _), top in zip(jobs, tops)]
    stage2 = cgal_roofs(tops, pitches, [None] * len(tops))
    parts = {}
    for (i, roof, ring), top in zip(jobs, stage2):
        parts.setdefault(i, [roof]).append((ring, top))
    for i, (roof, *pieces) in parts.items():
        if any(top is None for _, top in pieces):
            continue
        knee = float(knees[i])
        faces = list(below[i])
        vertices = [roof.vertices]
        count = len(roof.vertices)
        for ring, top in pieces:
            m = len(ring)
            # the upper roof's footprint vertices are the top ring's own
            number = np.concatenate([np.asarray(ring), count + np.arange(len(top.vertices) - m)])
            faces.extend([int(number[k]) for k in f]
                         for f in weld(top.vertices, top.faces, m, UPPER_WELD))
            above = top.vertices[m:].copy()
            above[:, 2] += knee
            vertices.append(above)
            count += len(above)
        v = np.concatenate(vertices)
        n = len(footprints[i])
        out[i] = Roof(v, merge_needles(v, weld(v, faces, n)), False, float(v[:, 2].max()))
    return out
