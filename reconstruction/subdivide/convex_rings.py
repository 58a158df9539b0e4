"""Small convex geometry of the subdivision: rings as lists of (x, y) tuples.

The subdivision cuts plots into convex cells of a few vertices, thousands of
times per plot; plain Python on lists of tuples is faster there than making
shapely geometries, and cutting a ring by a half-plane and by its complement
gives bit-identical points on the cut (:func:`clip_half_plane`), so that
neighbouring footprints share their vertices exactly. Rings are
counter-clockwise without the closing vertex (:func:`ccw_ring`);
:func:`to_polygons` turns many of them into shapely Polygons in one call.

Also here: the sliver and convexity tests of shapely polygons, and the
tolerances every subdivision file shares.
"""

import math

import numpy as np
import shapely
from shapely.geometry import Polygon

from ..geom.polygons import polygon_parts
from ..geom.rings import offsets

#: generated footprints narrower than this (map units) are slivers
MIN_WIDTH = 2.0
#: generated footprints smaller than this (square map units) are slivers
MIN_AREA = 10.0
#: vertices closer than this are the same vertex (map units)
SNAP = 1e-6


def signed_area(ring):
    """Signed area of a ring (positive when counter-clockwise)."""
    s = 0.0
    n = len(ring)
    for i in range(n):
        x1, y1 = ring[i]
        x2, y2 = ring[(i + 1) % n]
        s += x1 * y2 - x2 * y1
    return s / 2.0


def dedupe_ring(points):
    """The ring without repeated consecutive vertices, nor a closing one."""
    out = []
    for p in points:
        if not out or p != out[-1]:
            out.append(p)
    while len(out) > 1 and out[0] == out[-1]:
        out.pop()
    return out


def ccw_ring(coords):
    """A counter-clockwise ring without the closing vertex, as tuples."""
    out = dedupe_ring([(float(x), float(y)) for x, y in coords])
    if signed_area(out) < 0:
        out.reverse()
    return out


def clip_half_plane(ring, nx, ny, c):
    """Part of a convex ring where nx*x + ny*y <= c.

    The crossing point of an edge is computed from its endpoints in a fixed
    (sorted) order, so clipping a ring by a half-plane and by its complement
    gives bit-identical points on the cut.
    """
    if not ring:
        return ring
    vals = [nx * x + ny * y - c for x, y in ring]
    if max(vals) <= 0:
        return ring
    if min(vals) >= 0:
        return []
    out = []
    n = len(ring)
    for i in range(n):
        p, q = ring[i], ring[(i + 1) % n]
        vp, vq = vals[i], vals[(i + 1) % n]
        if vp <= 0:
            out.append(p)
        if (vp < 0 < vq) or (vq < 0 < vp):
            if p <= q:
                a, b, va, vb = p, q, vp, vq
            else:
                a, b, va, vb = q, p, vq, vp
            t = va / (va - vb)
            out.append((a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])))
    return out if len(out) >= 3 else []


def ring_width(ring):
    """Minimum width of a convex ring (rotating calipers over its edges).

    In Python on purpose: it is asked for every cell of every row, and on the
    16,936 Brussels 1924 footprints it takes 11 us a ring where making a
    Polygon for ``shapely.minimum_width`` takes 28 us (and gives other last
    bits in 97 % of them).
    """
    n = len(ring)
    best = math.inf
    for i in range(n):
        x1, y1 = ring[i]
        x2, y2 = ring[(i + 1) % n]
        dx, dy = x2 - x1, y2 - y1
        length = math.hypot(dx, dy)
        if length < 1e-12:
            continue
        far = max(abs((x - x1) * dy - (y - y1) * dx) for x, y in ring) / length
        best = min(best, far)
    return 0.0 if best is math.inf else best


def is_sliver_ring(ring):
    """True for a convex ring narrower than MIN_WIDTH or smaller than MIN_AREA."""
    area = abs(signed_area(ring))
    if area < MIN_AREA:
        return True
    # a convex ring of width w fits in a w x diameter strip: area <= w * diagonal
    xs = [p[0] for p in ring]
    ys = [p[1] for p in ring]
    if area >= MIN_WIDTH * math.hypot(max(xs) - min(xs), max(ys) - min(ys)):
        return False
    return ring_width(ring) < MIN_WIDTH


def polygon_width(polygon):
    """Minimum width of a polygon (of its convex hull: rotating calipers).

    The same computation as :func:`ring_width`, not ``shapely.minimum_width``
    (4x faster on shapely polygons, but other last bits): the invariant check
    must call a footprint a sliver exactly when the generation did.
    """
    if polygon.is_empty:
        return 0.0
    if polygon.area <= 0:
        return 0.0
    return ring_width(ccw_ring(shapely.convex_hull(polygon).exterior.coords))


def is_sliver(polygon):
    """True for a polygon narrower than MIN_WIDTH or smaller than MIN_AREA."""
    return polygon.area < MIN_AREA or polygon_width(polygon) < MIN_WIDTH


def is_convex(polygon, tolerance=1e-3):
    """True when the polygon differs from its convex hull by at most ``tolerance`` area."""
    return polygon.geom_type == "Polygon" and not polygon.interiors and \
        shapely.convex_hull(polygon).area - polygon.area <= tolerance


def merge_close(ring):
    """The ring without vertices closer than SNAP to the previous one (a cut
    through a vertex can add a copy of it a rounding error away, which GEOS
    takes for a self-intersection); [] when fewer than three are left."""
    out = []
    for p in ring:
        if not out or abs(p[0] - out[-1][0]) > SNAP or abs(p[1] - out[-1][1]) > SNAP:
            out.append(p)
    while len(out) > 1 and abs(out[0][0] - out[-1][0]) <= SNAP \
            and abs(out[0][1] - out[-1][1]) <= SNAP:
        out.pop()
    return out if len(out) >= 3 else []


def rectangle_frame(ring):
    """Minimum rotated rectangle of a convex ring as (corner, long unit, short unit, L, s)."""
    rect = shapely.oriented_envelope(Polygon(ring))
    if rect.geom_type != "Polygon":
        return None
    r = ccw_ring(rect.exterior.coords)
    if len(r) < 4:
        return None
    (x0, y0), (x1, y1), (x2, y2) = r[0], r[1], r[2]
    a = math.hypot(x1 - x0, y1 - y0)
    b = math.hypot(x2 - x1, y2 - y1)
    if a >= b:
        return (x0, y0), ((x1 - x0) / a, (y1 - y0) / a), ((x2 - x1) / b, (y2 - y1) / b), a, b
    # make the long side start at r[1]: direction r1->r2, across r1->r0 reversed
    return (x1, y1), ((x2 - x1) / b, (y2 - y1) / b), ((x0 - x1) / a, (y0 - y1) / a), b, a


def to_polygons(rings):
    """Shapely polygons from rings (lists of (x, y)) in one call."""
    if not rings:
        return []
    closed = [r + [r[0]] for r in rings]
    coords = np.array([p for r in closed for p in r], dtype=float)
    ring_offsets = offsets([len(r) for r in closed])
    poly_offsets = np.arange(len(rings) + 1)
    return list(shapely.from_ragged_array(shapely.GeometryType.POLYGON, coords,
                                          (ring_offsets, poly_offsets)))


#: footprints have no corner sharper than this (degrees) unless their plot has one there
MIN_ANGLE = 20.0


def corner_angles(ring):
    """Interior angle (degrees) at each vertex of a counter-clockwise ring (reflex > 180)."""
    n = len(ring)
    out = []
    for i in range(n):
        (ax, ay), (px, py), (bx, by) = ring[i - 1], ring[i], ring[(i + 1) % n]
        turn = math.atan2((px - ax) * (by - py) - (py - ay) * (bx - px),
                          (px - ax) * (bx - px) + (py - ay) * (by - py))
        out.append(180.0 - math.degrees(turn))
    return out


def sharp_corners(polygon):
    """The vertices of a polygon (all rings) with an interior angle under ``MIN_ANGLE``."""
    out = []
    for part in polygon_parts(polygon):
        for k, ring in enumerate([part.exterior, *part.interiors]):
            r = ccw_ring(ring.coords)
            # a hole's counter-clockwise angle is the plot's angle seen from outside
            angles = corner_angles(r) if k == 0 else [360.0 - a for a in corner_angles(r)]
            out.extend(p for p, a in zip(r, angles) if a < MIN_ANGLE)
    return out


def has_wedge(ring, keep=(), tolerance=10 * SNAP):
    """Whether a ring has a corner under ``MIN_ANGLE`` farther than ``tolerance``
    from every point of ``keep`` (the plot's :func:`sharp_corners`)."""
    return any(a < MIN_ANGLE and all(math.hypot(p[0] - x, p[1] - y) > tolerance for x, y in keep)
               for p, a in zip(ring, corner_angles(ring)))


def square_wedges(ring, keep=(), width=MIN_WIDTH):
    """A convex ring with its corners under ``MIN_ANGLE`` cut square, as a builder would:
    perpendicular to the corner's bisector where the wedge is ``width`` wide.

    Corners at a point of ``keep`` (the plot's own sharp corners) stay. Returns
    the cut ring ([] when nothing but the wedge was left).
    """
    for _ in range(len(ring)):
        if not ring:
            return ring
        angles = corner_angles(ring)
        sharp = [i for i, a in enumerate(angles) if a < MIN_ANGLE
                 and not any(math.hypot(ring[i][0] - x, ring[i][1] - y) <= 10 * SNAP
                             for x, y in keep)]
        if not sharp:
            return ring
        i = sharp[0]
        (ax, ay), (px, py), (bx, by) = ring[i - 1], ring[i], ring[(i + 1) % len(ring)]
        ua, ub = math.hypot(ax - px, ay - py), math.hypot(bx - px, by - py)
        ux, uy = (ax - px) / ua + (bx - px) / ub, (ay - py) / ua + (by - py) / ub
        norm = math.hypot(ux, uy)
        ux, uy = ux / norm, uy / norm
        reach = width / 2 / math.tan(math.radians(angles[i]) / 2)
        # keep u . (x - p) >= reach, i.e. -u . x <= -(u . p + reach)
        ring = clip_half_plane(ring, -ux, -uy, -(ux * px + uy * py + reach))
    return ring
