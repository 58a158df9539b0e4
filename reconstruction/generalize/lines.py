"""Commandeur's (2012) buffered-lines generalisation of building plots.

The segments of all rings of a group of plots become lines ranked by length;
a shorter segment is merged into a line while all its end points lie within
``distance`` of it and its direction within ``angle``; each final line is the
orthogonal least-squares line of its members (:class:`_LineSet`);
consecutive lines along each ring are intersected back into a polygon
(nearly parallel ones joined by a short step). A shared edge of two touching
plots is one segment, so it becomes one line and stays shared.

Pure: shapely 2 and numpy, no GRASS.
"""

import math

import numpy as np
import shapely
from shapely.geometry import Polygon

from ..geom.polygons import clean_polygon

# Tuning (checked on the thesis's Delft 1961 plots): a join moves a corner at
# most SHIFT x distance; vertices closer than CLEAN x distance to their
# neighbours' line are dropped.
SHIFT = 3.0
CLEAN = 0.05


def _ring_arrays(polygon):
    """Vertex arrays (open, counter-clockwise exterior first) of a polygon's rings."""
    polygon = shapely.orient_polygons(polygon)
    rings = [polygon.exterior] + list(polygon.interiors)
    return [np.asarray(r.coords)[:-1, :2] for r in rings]


class _LineSet:
    """Lines made of merged segments, each the orthogonal least-squares line of its
    segments (every point of them weighted alike, so a long edge outweighs a short
    corner cut that joined it: an axial mean of the segments' directions let a 4 m
    corner segment at 19 degrees turn a 100 m edge by 1.9 degrees, which put the
    edge 1.5 m out at its far end; issue 32). Coordinates are kept relative to the
    first segment's start (the squares of map coordinates would lose the metres)."""

    def __init__(self, distance, angle, capacity):
        self.distance = distance
        self.angle = math.radians(min(angle, 90.0))  # axial directions differ by <= 90 deg
        self.n = 0
        self.ref = None                        # the first point added: the local origin
        self.weight = np.zeros(capacity)       # total length
        self.centre = np.zeros((capacity, 2))  # sum of length * midpoint
        self.moment = np.zeros((capacity, 3))  # sums of the integrals of x², xy, y²
        self.theta = np.zeros(capacity)        # direction (radians, axial)
        self.origin = np.zeros((capacity, 2))  # weighted centre
        self.unit = np.zeros((capacity, 2))    # unit direction
        self.points = []                       # (k, 2) end points of the members

    def line(self, k):
        return self.origin[k] + self.ref, self.unit[k]

    @staticmethod
    def _moments(p, q, length):
        """length x (mean of x², xy, y²) along segment pq."""
        m = (np.outer(p, p) + np.outer(q, q)) / 3 + (np.outer(p, q) + np.outer(q, p)) / 6
        return length * np.array([m[0, 0], m[0, 1], m[1, 1]])

    @staticmethod
    def _direction(weight, centre, moment):
        """The principal direction (radians) of segments with these sums."""
        c = centre / weight
        xx, xy, yy = moment / weight - (c[0] * c[0], c[0] * c[1], c[1] * c[1])
        return 0.5 * math.atan2(2 * xy, xx - yy)

    def set_direction(self, k, theta):
        self.theta[k] = theta
        self.unit[k] = (math.cos(theta), math.sin(theta))

    def update(self, k):
        self.origin[k] = self.centre[k] / self.weight[k]
        self.set_direction(k, self._direction(self.weight[k], self.centre[k], self.moment[k]))

    def _fits(self, k, p, q, length):
        weight = self.weight[k] + length
        centre = self.centre[k] + length * (p + q) / 2
        theta = self._direction(weight, centre, self.moment[k] + self._moments(p, q, length))
        normal = np.array([-math.sin(theta), math.cos(theta)])
        points = np.concatenate([self.points[k], [p, q]])
        return np.abs((points - centre / weight) @ normal).max() <= self.distance

    def add(self, p, q):
        """Merge segment pq into the nearest line it fits, or start a line; its index."""
        if self.ref is None:
            self.ref = np.array(p, dtype=float)
        p, q = p - self.ref, q - self.ref
        v = q - p
        length = float(np.hypot(*v))
        best = -1
        if self.n:
            origin, unit = self.origin[:self.n], self.unit[:self.n]
            normal = np.column_stack([-unit[:, 1], unit[:, 0]])
            d = np.maximum(np.abs(((p - origin) * normal).sum(axis=1)),
                           np.abs(((q - origin) * normal).sum(axis=1)))
            cosine = np.abs(unit @ v) / length
            ok = np.flatnonzero((d <= self.distance) & (cosine >= math.cos(self.angle + 1e-9)))
            for k in ok[np.argsort(d[ok], kind="stable")]:
                if self._fits(k, p, q, length):
                    best = int(k)
                    break
        if best < 0:
            best = self.n
            self.n += 1
            self.points.append(np.array([p, q]))
        else:
            self.points[best] = np.concatenate([self.points[best], [p, q]])
        self.centre[best] += length * (p + q) / 2
        self.moment[best] += self._moments(p, q, length)
        self.weight[best] += length
        self.update(best)
        return best


def _absorb_interruptions(lines, seg_line, ring_segments, seg_points):
    """Give a run of segments between two runs of the same line to that line.

    An edge that reads line A, then briefly line B, then A again is one edge
    when B's points lie within the distance of A: B's segments there join A.
    """
    changed = True
    while changed:
        changed = False
        for ids in ring_segments:
            ids = np.asarray(ids)
            seq = seg_line[ids]
            starts = np.flatnonzero(seq != np.roll(seq, 1))
            if len(starts) < 4:
                continue
            for j in range(len(starts)):
                s0, s1 = starts[j], starts[(j + 1) % len(starts)]
                run = np.arange(s0, s1 if s1 > s0 else s1 + len(seq)) % len(seq)
                before, after = seq[(s0 - 1) % len(seq)], seq[s1 % len(seq)]
                if before != after:
                    continue
                origin, u = lines.line(before)
                normal = np.array([-u[1], u[0]])
                pts = np.array([pt for k in ids[run] for pt in seg_points[k]])
                if np.abs((pts - origin) @ normal).max() <= lines.distance:
                    seg_line[ids[run]] = before
                    changed = True
                    break


def _orthogonalize(lines, tolerance_deg=20.0):
    """Snap line directions to the dominant direction or its perpendicular."""
    weights = lines.weight[:lines.n]
    thetas = lines.theta[:lines.n]
    dominant = math.atan2((weights * np.sin(4 * thetas)).sum(),
                          (weights * np.cos(4 * thetas)).sum()) / 4
    tol = math.radians(tolerance_deg)
    for k, theta in enumerate(thetas):
        off = (theta - dominant + math.pi / 4) % (math.pi / 2) - math.pi / 4
        if abs(off) <= tol:
            new = theta - off
            lines.set_direction(k, new)


def _join(la, lb, corner, min_angle, max_shift, offset):
    """Vertices joining line a to line b near ``corner``.

    The intersection of the two lines when they cross at ``min_angle`` or more
    within ``max_shift`` of the corner; otherwise the corner projected on both
    lines: one vertex between them when they lie within ``offset`` of each
    other, else a short step.
    """
    (pa, ua), (pb, ub) = la, lb
    cross = ua[0] * ub[1] - ua[1] * ub[0]
    if abs(cross) >= math.sin(min_angle):
        t = ((pb - pa)[0] * ub[1] - (pb - pa)[1] * ub[0]) / cross
        x = pa + t * ua
        if np.hypot(*(x - corner)) <= max_shift:
            return [x]
    # nearly parallel (or far intersection): a short step through the corner
    xa = pa + ((corner - pa) @ ua) * ua
    xb = pb + ((corner - pb) @ ub) * ub
    if np.hypot(*(xa - xb)) <= offset:
        return [(xa + xb) / 2]
    return [xa, xb]


def buffered_lines(polygons, distance=5.0, angle=180.0, orthogonal=False, shift=None):
    """Commandeur's buffered-lines generalisation of a group of plots.

    All rings of all ``polygons`` share one set of lines, so an edge shared
    by two plots becomes one line and stays shared. Returns one polygon (or
    None where the reconstruction failed) per input polygon.
    """
    shift = SHIFT if shift is None else shift
    rings = []              # (plot index, vertex array)
    for i, polygon in enumerate(polygons):
        for ring in _ring_arrays(polygon):
            if len(ring) >= 3:
                rings.append((i, ring))
    # unique segments (shared edges of touching plots are one segment)
    seg_index = {}
    seg_points = []
    ring_segments = []
    for _, ring in rings:
        ids = []
        nxt = np.roll(ring, -1, axis=0)
        for p, q in zip(ring, nxt):
            kp, kq = tuple(np.round(p, 6)), tuple(np.round(q, 6))
            key = (kp, kq) if kp <= kq else (kq, kp)
            if key not in seg_index:
                seg_index[key] = len(seg_points)
                seg_points.append((np.array(key[0]), np.array(key[1])))
            ids.append(seg_index[key])
        ring_segments.append(ids)
    if not seg_points:
        return [None] * len(polygons)
    lengths = np.array([np.hypot(*(q - p)) for p, q in seg_points])
    order = np.lexsort((np.arange(len(lengths)), -lengths))
    lines = _LineSet(distance, angle, len(seg_points))
    seg_line = np.empty(len(seg_points), dtype=int)
    for s in order:
        p, q = seg_points[s]
        seg_line[s] = lines.add(p, q)
    _absorb_interruptions(lines, seg_line, ring_segments, seg_points)
    if orthogonal:
        _orthogonalize(lines)
    line_params = {k: lines.line(k) for k in np.unique(seg_line)}
    min_angle = math.radians(10.0)
    max_shift = shift * distance
    joins = {}
    out_rings = {}
    for (plot, ring), ids in zip(rings, ring_segments):
        seq = seg_line[ids]
        # rotate so the ring starts at a change of line
        changes = np.flatnonzero(seq != np.roll(seq, 1))
        if len(changes) < 3:
            out_rings.setdefault(plot, []).append(None)
            continue
        start = changes[0]
        seq = np.roll(seq, -start)
        verts = np.roll(ring, -start, axis=0)
        starts = np.flatnonzero(seq != np.roll(seq, 1))
        coords = []
        for j, s in enumerate(starts):
            prev_line = seq[s - 1]
            this_line = seq[s]
            corner = verts[s]
            key = (tuple(np.round(corner, 6)), prev_line, this_line)
            if key not in joins:
                joins[key] = _join(line_params[prev_line], line_params[this_line], corner,
                                   min_angle, max_shift, distance)
            coords.extend(joins[key])
        out_rings.setdefault(plot, []).append(np.array(coords))
    result = []
    for i in range(len(polygons)):
        parts = out_rings.get(i, [])
        if not parts or parts[0] is None or len(parts[0]) < 3:
            result.append(None)
            continue
        holes = [h for h in parts[1:] if h is not None and len(h) >= 3]
        try:
            polygon = Polygon(parts[0], holes)
        except (ValueError, shapely.errors.GEOSException):
            result.append(None)
            continue
        result.append(clean_polygon(polygon, distance * CLEAN) if polygon.is_valid else None)
    return result


# ---------------------------------------------------------------------------
# Simplification
# ---------------------------------------------------------------------------
