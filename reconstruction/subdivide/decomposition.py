"""Convex decomposition of concave plots (case 5 of the subdivision).

:func:`convex_parts` cuts a polygon (holes allowed) into convex rings: holes
are removed by straight cuts across them, then every simple polygon is split
by chords from its reflex vertices, after Bayazit's idea of resolving reflex
vertices one by one.
"""

import math

import numpy as np
import shapely
from shapely.geometry import Polygon

from ..geom.polygons import polygon_parts
from .convex_rings import ccw_ring, rectangle_frame, signed_area
from .plots import overlay

_REFLEX_SIN = 1e-7


def reflex_vertices(ring):
    """Indices of the reflex (inward-turning) vertices of a counter-clockwise ring."""
    n = len(ring)
    out = []
    for i in range(n):
        (x0, y0), (x1, y1), (x2, y2) = ring[i - 1], ring[i], ring[(i + 1) % n]
        ax, ay, bx, by = x1 - x0, y1 - y0, x2 - x1, y2 - y1
        cross = ax * by - ay * bx
        norm = math.hypot(ax, ay) * math.hypot(bx, by)
        if norm > 0 and cross < -_REFLEX_SIN * norm:
            out.append(i)
    return out


def _ray_hit(ring, i, dx, dy):
    """First boundary point hit by the ray from vertex i: (distance, edge, t)."""
    pts = np.asarray(ring)
    n = len(ring)
    a = pts
    b = np.roll(pts, -1, axis=0)
    ox, oy = ring[i]
    ex, ey = b[:, 0] - a[:, 0], b[:, 1] - a[:, 1]
    denom = dx * ey - dy * ex
    wx, wy = a[:, 0] - ox, a[:, 1] - oy
    with np.errstate(divide="ignore", invalid="ignore"):
        s = (wx * ey - wy * ex) / denom
        t = (wx * dy - wy * dx) / denom
    ok = (np.abs(denom) > 1e-12) & (s > 1e-9) & (t >= -1e-12) & (t <= 1 + 1e-12)
    ok[i] = False
    ok[(i - 1) % n] = False
    if not ok.any():
        return None
    j = int(np.argmin(np.where(ok, s, np.inf)))
    return float(s[j]), j, float(min(max(t[j], 0.0), 1.0))


def _split_ring(ring, i, j, t):
    """Split a ring by the chord from vertex i to the point at t on edge j."""
    n = len(ring)
    if t <= 1e-9:
        k = j
    elif t >= 1 - 1e-9:
        k = (j + 1) % n
    else:
        k = None
    if k is not None:
        if k in (i, (i + 1) % n, (i - 1) % n):
            return None
        first = [ring[(i + m) % n] for m in range((k - i) % n + 1)]
        second = [ring[(k + m) % n] for m in range((i - k) % n + 1)]
    else:
        (x1, y1), (x2, y2) = ring[j], ring[(j + 1) % n]
        hit = (x1 + t * (x2 - x1), y1 + t * (y2 - y1))
        first = [ring[(i + m) % n] for m in range((j - i) % n + 1)] + [hit]
        second = [hit] + [ring[(j + 1 + m) % n] for m in range((i - j - 1) % n + 1)]
    if len(first) < 3 or len(second) < 3:
        return None
    return first, second


def _decompose_ring(ring, budget):
    """Convex parts of a simple counter-clockwise ring by chords from reflex vertices.

    Each step takes, over all reflex vertices, the shortest chord along the
    extension of one of its edges or along its angle bisector: the reflex
    vertex becomes convex in both parts (Bayazit's idea of resolving reflex
    vertices one by one; here the chord ends on the boundary, a Steiner point
    when no vertex is hit). Returns a list of rings.
    """
    stack, parts = [ring], []
    while stack:
        r = stack.pop()
        reflex = reflex_vertices(r)
        if not reflex or budget[0] <= 0:
            parts.append(r)
            continue
        n = len(r)
        best = None
        for i in reflex:
            (x0, y0), (x1, y1), (x2, y2) = r[i - 1], r[i], r[(i + 1) % n]
            d_in = (x1 - x0, y1 - y0)
            d_out = (x1 - x2, y1 - y2)
            l_in, l_out = math.hypot(*d_in), math.hypot(*d_out)
            u_in = (d_in[0] / l_in, d_in[1] / l_in)
            u_out = (d_out[0] / l_out, d_out[1] / l_out)
            bis = (u_in[0] + u_out[0], u_in[1] + u_out[1])
            lb = math.hypot(*bis)
            directions = [u_in, u_out] + ([(bis[0] / lb, bis[1] / lb)] if lb > 1e-9 else [])
            for dx, dy in directions:
                hit = _ray_hit(r, i, dx, dy)
                if hit is not None and (best is None or hit[0] < best[0]):
                    best = (hit[0], i, hit[1], hit[2])
        split = _split_ring(r, best[1], best[2], best[3]) if best else None
        if split is None:
            parts.append(r)
            continue
        budget[0] -= 1
        for part in split:
            if abs(signed_area(part)) > 0:
                stack.append(part)
    return parts


def _cut_holes(polygon):
    """Simple polygons from a polygon with holes: full cuts through each hole.

    A piece that still has a hole after many cuts (never seen) is left out
    rather than built over its hole.
    """
    todo, out = [polygon], []
    budget = 50 + 4 * len(polygon.interiors)
    while todo:
        p = todo.pop()
        if not p.interiors:
            out.append(p)
            continue
        budget -= 1
        frame = rectangle_frame(ccw_ring(shapely.convex_hull(p).exterior.coords))
        if budget < 0 or frame is None:
            continue
        hole = Polygon(p.interiors[0])
        c = hole.representative_point()
        ex, ey = frame[1]
        big = 4 * (math.sqrt(p.area) + p.length)
        # cut across the plot's long axis through the hole's centre
        nx, ny = ex, ey
        px, py = -ey, ex
        halves = []
        for sign in (1, -1):
            quad = Polygon([
                (c.x + px * big, c.y + py * big),
                (c.x - px * big, c.y - py * big),
                (c.x - px * big + sign * nx * big, c.y - py * big + sign * ny * big),
                (c.x + px * big + sign * nx * big, c.y + py * big + sign * ny * big),
            ])
            halves.append(overlay(shapely.intersection, p, quad))
        for h in halves:
            for g in polygon_parts(h):
                if g.area > 0:
                    todo.append(g)
    return out


def convex_parts(polygon, max_cuts=500):
    """Convex parts of a polygon (holes allowed) as counter-clockwise rings.

    Holes are removed first by a straight cut across each hole; every simple
    polygon is then split by chords from its reflex vertices
    (:func:`_decompose_ring`). Simpler than Bayazit's algorithm but robust on
    real plots: every chord makes at least one reflex vertex convex and never
    creates a new one, so it ends after at most as many cuts as reflex
    vertices.
    """
    rings = []
    for simple in _cut_holes(polygon):
        rings.extend(_decompose_ring(ccw_ring(simple.exterior.coords), [max_cuts]))
    return rings
