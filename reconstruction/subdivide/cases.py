"""The five cases of the subdivision on one plot (Morlighem 2021, Section 3.3.2).

:func:`subdivide_plot` gives the footprints of one valid plot: case 1 (a
small plot is one footprint), 2 (one row along the street), 3 (two rows back
to back), 4 (buildings around a courtyard, along every street line) on a
convex plot or convex part, and 5 (a concave plot: its convex parts, see
:mod:`reconstruction.subdivide.decomposition`, each as cases 1-4 with only the plot's
exterior edges as streets). The cases are described in full in
:mod:`reconstruction.subdivide.stage`.

Every row is cut in one pass over the ring (:func:`_slab_cells`), so
neighbours share their cut vertices exactly.
"""

import bisect
import math

import numpy as np
import shapely

from ..geom.polygons import polygon_parts
from .convex_rings import (ccw_ring, clip_half_plane, has_wedge, is_convex, is_sliver,
                           is_sliver_ring, merge_close, rectangle_frame, sharp_corners,
                           signed_area, square_wedges, to_polygons)
from .decomposition import convex_parts, reflex_vertices
from .plots import MIN_STREET, exterior_lines, overlay, street_edges, street_length

#: consecutive street edges turning less than this (degrees) share one street line in case 4
STREET_TURN = 20.0


def _facade_cuts(u0, u1, length, rng):
    """Cut positions strictly inside (u0, u1) from facade lengths drawn in ``length``.

    Draws lengths until they cover the street, takes the number of buildings
    whose total is nearest to the street length and scales them to fit.
    """
    total = u1 - u0
    low, high = length
    if total <= low:
        return []
    count = int(total / low) + 2
    drawn = rng.uniform(low, high, size=count)
    sums = np.cumsum(drawn)
    n = int(np.argmin(np.abs(sums - total))) + 1
    scaled = sums[: n - 1] * (total / sums[n - 1])
    return [u0 + float(s) for s in scaled]


def _slab_cells(ring, ox, oy, ex, ey, cuts):
    """Split a convex ring by lines perpendicular to (ex, ey) at ``cuts``.

    The ring is noded once with every cut, so neighbouring cells share their
    cut vertices exactly. Returns ``len(cuts) + 1`` rings (possibly empty).
    """
    m = len(cuts)
    us = [(x - ox) * ex + (y - oy) * ey for x, y in ring]
    eps = 1e-9 * max(1.0, max(abs(u) for u in us))
    noded = []  # (point, first cell, last cell)
    n = len(ring)
    for i in range(n):
        u = us[i]
        j = bisect.bisect_left(cuts, u - eps)
        if j < m and abs(cuts[j] - u) <= eps:
            noded.append((ring[i], j, j + 1))
        else:
            noded.append((ring[i], j, j))
        p, q = ring[i], ring[(i + 1) % n]
        up, uq = u, us[(i + 1) % n]
        lo, hi = (up, uq) if up < uq else (uq, up)
        k0 = bisect.bisect_right(cuts, lo + eps)
        k1 = bisect.bisect_left(cuts, hi - eps)
        if k0 >= k1:
            continue
        if p <= q:
            a, b, ua, ub = p, q, up, uq
        else:
            a, b, ua, ub = q, p, uq, up
        ks = range(k0, k1) if up < uq else range(k1 - 1, k0 - 1, -1)
        for k in ks:
            t = (cuts[k] - ua) / (ub - ua)
            noded.append(((a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])), k, k + 1))
    cells = []
    for c in range(m + 1):
        cell = [p for p, lo, hi in noded if lo <= c <= hi]
        cells.append(cell if len(cell) >= 3 and abs(signed_area(cell)) > 0 else [])
    return cells


def _depth(cell, nx, ny, c0, drawn, free):
    """A building's depth: the drawn one, or the whole cell (to the back of the
    plot, or to the straight skeleton's ridge in case 4) when less than
    ``free`` would be left behind it: half the minimum depth for a garden in
    a row, the minimum depth for a courtyard (so corner buildings take the
    corners of the courtyard, and small blocks are built through)."""
    back = max(nx * x + ny * y for x, y in cell) - c0
    return math.inf if back - drawn < free else drawn


def _row(face, line, length, depth, rng, inner=False):
    """Buildings of one face along its street line: facade cuts, depth per building.

    ``line`` is ``(ox, oy, ex, ey)``: a point of the street line and its unit
    direction, the face on its left. Cells that are slivers are merged with a
    neighbour; a face that is only a sliver gives nothing.
    """
    ox, oy, ex, ey = line
    nx, ny = -ey, ex
    c0 = nx * ox + ny * oy
    span = face
    free = depth[0] / 2
    if inner:
        # case 4: facade lengths along the inward offset at half the minimum depth
        # (the middle of the shallowest building: every building of the face
        # crosses it), or halfway to the face's apex when the face closes before
        # that; corner buildings take the corners up to it
        top = max(nx * x + ny * y for x, y in face) - c0
        span = clip_half_plane(face, -nx, -ny, -(c0 + min(depth[0] / 2, top / 2))) or face
        free = depth[0]
    us = [(x - ox) * ex + (y - oy) * ey for x, y in span]
    cuts = _facade_cuts(min(us), max(us), length, rng)
    depths = list(rng.uniform(depth[0], depth[1], size=len(cuts) + 1))
    while True:
        cells = _slab_cells(face, ox, oy, ex, ey, cuts)
        rings = [merge_close(clip_half_plane(cell, nx, ny, c0 + _depth(cell, nx, ny, c0, d, free)))
                 if cell else [] for cell, d in zip(cells, depths)]
        bad = [i for i, r in enumerate(rings) if r and is_sliver_ring(r)]
        bad += [i for i, r in enumerate(rings) if not r]
        if not bad or not cuts:
            break
        i = bad[0]
        # merge the cell with its smaller neighbour by removing the cut between them
        left = abs(signed_area(rings[i - 1])) if i > 0 and rings[i - 1] else math.inf
        right = abs(signed_area(rings[i + 1])) if i < len(rings) - 1 and rings[i + 1] else math.inf
        if i == 0 or (i < len(cuts) and right <= left):
            cut = i
        else:
            cut = i - 1
        depths[cut] = max(depths[cut], depths[cut + 1])
        del depths[cut + 1]
        del cuts[cut]
    return [r for r in rings if r and not is_sliver_ring(r)]


def _faces(ring, lines):
    """The face of each street line: points of the ring nearer to it than to any other line.

    For a convex polygon this is the straight skeleton's partition of the
    band along those edges (exact for the plot's own edge lines).
    """
    normals = [(-ey, ex, -ey * ox + ex * oy) for ox, oy, ex, ey in lines]
    faces = []
    for k, (nkx, nky, ck) in enumerate(normals):
        face = ring
        for j, (njx, njy, cj) in enumerate(normals):
            if j == k or not face:
                continue
            ax, ay = njx - nkx, njy - nky
            c = cj - ck
            # d_k <= d_j  <=>  (n_j - n_k) . p >= c_j - c_k  <=>  (n_k - n_j) . p <= c_k - c_j
            if math.hypot(ax, ay) < 1e-9:
                if c > 1e-9 or (abs(c) <= 1e-9 and j < k):
                    face = []
                continue
            face = clip_half_plane(face, -ax, -ay, -c)
        faces.append(face)
    return faces


def _street_support(ring, street, frame):
    """Street length along each long side of the rectangle frame (side 0, side 1)."""
    (cx, cy), (ex, ey), (nx, ny), _, s = frame
    support = [0.0, 0.0]
    n = len(ring)
    for i in range(n):
        if not street[i]:
            continue
        (x1, y1), (x2, y2) = ring[i], ring[(i + 1) % n]
        along = abs((x2 - x1) * ex + (y2 - y1) * ey)
        v = ((x1 + x2) / 2 - cx) * nx + ((y1 + y2) / 2 - cy) * ny
        support[0 if v < s / 2 else 1] += along
    return support


def _street_lines(ring, street):
    """Street lines of case 4: runs of street edges turning less than STREET_TURN."""
    n = len(ring)
    edges = []
    for i in range(n):
        (x1, y1), (x2, y2) = ring[i], ring[(i + 1) % n]
        length = math.hypot(x2 - x1, y2 - y1)
        if length > 0:
            edges.append((i, x1, y1, (x2 - x1) / length, (y2 - y1) / length, length, street[i]))
    if not edges:
        return []
    # start where a run must start: after a non-street edge, else at the sharpest turn
    cos_turn = math.cos(math.radians(STREET_TURN))
    def turn(k):
        prev, cur = edges[k - 1], edges[k]
        if not cur[6] or not prev[6]:
            return -2.0
        return prev[3] * cur[3] + prev[4] * cur[4]
    start = min(range(len(edges)), key=turn)
    order = edges[start:] + edges[:start]
    groups, current = [], []
    for e in order:
        if not e[6]:
            if current:
                groups.append(current)
            current = []
            continue
        if current and current[0][3] * e[3] + current[0][4] * e[4] < cos_turn:
            groups.append(current)
            current = []
        current.append(e)
    if current:
        groups.append(current)
    lines = []
    for g in groups:
        longest = max(g, key=lambda e: e[5])
        lines.append((longest[1], longest[2], longest[3], longest[4]))
    return lines


def _convex_cells(ring, street, length, depth, area_threshold, rng):
    """Cases 1-4 on one convex ring; ``street[i]`` tells whether edge i is a street edge.

    Returns ``(case, [rings])``.
    """
    area = abs(signed_area(ring))
    if area < area_threshold:
        return 1, [] if is_sliver_ring(ring) else [ring]
    frame = rectangle_frame(ring)
    if frame is None:
        return 1, [ring]
    (cx, cy), (ex, ey), (nx, ny), long_side, short = frame
    side0 = (cx, cy, ex, ey)  # the face on its left is the rectangle
    far = (cx + nx * short + ex * long_side, cy + ny * short + ey * long_side)
    side1 = (far[0], far[1], -ex, -ey)
    if short <= 2 * depth[1]:
        support = _street_support(ring, street, frame)
        if short < 2 * depth[0] or min(support) == 0:
            line = side0 if support[0] >= support[1] else side1
            return 2, _row(ring, line, length, depth, rng)
        cells = []
        for face, line in zip(_faces(ring, [side0, side1]), (side0, side1)):
            if face:
                cells.extend(_row(face, line, length, depth, rng))
        return 3, cells
    lines = _street_lines(ring, street)
    if not lines:
        return 4, []
    cells = []
    for face, line in zip(_faces(ring, lines), lines):
        if face:
            cells.extend(_row(face, line, length, depth, rng, inner=True))
    return 4, cells


def _square(cells, part):
    """Cells with their wedges cut square (:func:`square_wedges`), slivers left out."""
    keep = sharp_corners(part)
    cut = [square_wedges(c, keep) for c in cells]
    return [c for c, old in zip(cut, cells) if c and (c is old or not is_sliver_ring(c))]


def subdivide_plot(plot, length, depth, area_threshold, rng, decompose=True, seam=None):
    """Footprints of one valid plot (Polygon or MultiPolygon) as ``[(footprint, case)]``.

    A footprint is a shapely Polygon or a counter-clockwise ring (list of
    (x, y) tuples, see :func:`to_polygons`). ``seam``: the boundaries of
    the plots touching this one (:func:`reconstruction.subdivide.plots.seams`): an
    edge along them is no street; every footprint has at least
    ``MIN_STREET`` of street edges.
    """
    out = []
    parts = polygon_parts(plot)
    whole_sliver = all(is_sliver(p) for p in parts)
    for part in parts:
        if is_sliver(part):
            if whole_sliver:
                out.append((part, 1))
            continue
        if part.area < area_threshold:
            out.append((part, 1))
            continue
        exterior = exterior_lines(part)
        ring = ccw_ring(part.exterior.coords)
        concave = bool(part.interiors) or bool(reflex_vertices(ring))
        if not concave:
            street = ([True] * len(ring) if seam is None
                      else list(street_edges([ring], exterior, seam)[0][0]))
            case, cells = _convex_cells(ring, street, length, depth, area_threshold, rng)
            cells = _square(cells, part)
            access = street_length(cells, exterior, seam)
            out.extend((c, case) for c, a in zip(cells, access) if a >= MIN_STREET)
            continue
        if decompose:
            cells = []
            subs = convex_parts(part)
            for sub, (street, _) in zip(subs, street_edges(subs, exterior, seam)):
                if not street.any():
                    continue
                _, sub_cells = _convex_cells(sub, list(street), length, depth, area_threshold, rng)
                cells.extend(sub_cells)
            cells = _square(cells, part)
            access = street_length(cells, exterior, seam)
            out.extend((c, 5) for c, a in zip(cells, access) if a >= MIN_STREET)
            continue
        # -c: cases 1-4 on the convex hull, cut back to the plot (may be concave)
        hull = ccw_ring(shapely.convex_hull(part).exterior.coords)
        street = list(street_edges([hull], exterior, seam)[0][0])
        case, cells = _convex_cells(hull, street, length, depth, area_threshold, rng)
        pieces = []
        keep = sharp_corners(part)
        for c in to_polygons(cells):
            for p in polygon_parts(overlay(shapely.intersection, c, part)):
                ring = ccw_ring(p.exterior.coords)
                if has_wedge(ring, keep):
                    # cut square when convex; a concave wedge is left unbuilt
                    ring = square_wedges(ring, keep) if is_convex(p) else []
                    if not ring or is_sliver_ring(ring):
                        continue
                    p = to_polygons([ring])[0]
                if not is_sliver(p):
                    pieces.append(p)
        access = street_length([ccw_ring(p.exterior.coords) for p in pieces], exterior, seam)
        out.extend((p, case) for p, a in zip(pieces, access) if a >= MIN_STREET)
    return out
