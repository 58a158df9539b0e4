"""Shared vertices: neighbouring footprints get identical vertices on their shared edges.

GRASS builds topology from the footprints it is given: two neighbours whose
common edge differs by a rounding error, or where one has a vertex on the
other's edge (a T-junction), would get a sliver area or a gap between them.
:func:`node_footprints` snaps vertices closer than a tolerance together and
inserts T-junction vertices, so a GIS that builds topology keeps their
shared edges shared.
"""

import numpy as np
import shapely
from shapely.geometry import Polygon

from ..geom.rings import offsets as ring_offsets
from .convex_rings import SNAP, ccw_ring, dedupe_ring, to_polygons
from .plots import OVERLAP_TOLERANCE


def node_footprints(geometries, tolerance=SNAP):
    """Make neighbours share exact vertices.

    Vertices closer than ``tolerance`` get the same coordinates, and a vertex
    lying on another footprint's edge is inserted into that edge, so that
    shared edges are identical vertex for vertex. Footprints that would
    become invalid are left as they were.
    """
    if not geometries:
        return []
    geometries = list(geometries)
    ring_geoms = []
    owner = []
    for f, g in enumerate(geometries):
        ring_geoms.append(g.exterior)
        owner.append((f, 0))
        for r, hole in enumerate(g.interiors, 1):
            ring_geoms.append(hole)
            owner.append((f, r))
    closed_coords, index = shapely.get_coordinates(ring_geoms, return_index=True)
    # drop each ring's closing vertex
    last = np.r_[index[1:] != index[:-1], True]
    original = closed_coords[~last]
    ring_of = index[~last]
    sizes = np.bincount(ring_of, minlength=len(ring_geoms))
    offsets = ring_offsets(sizes)
    points = shapely.points(original)
    tree = shapely.STRtree(points)
    a, b = tree.query(points, predicate="dwithin", distance=tolerance)
    rep = np.arange(len(original))
    np.minimum.at(rep, a, b)
    rep = rep[rep]
    coords = original[rep]
    moved = np.zeros(len(ring_geoms), bool)
    moved[ring_of[np.any(coords != original, axis=1)]] = True
    # edges, and vertices lying on them (T-junctions)
    n = len(coords)
    ends = np.arange(1, n + 1)
    ends[offsets[1:] - 1] = offsets[:-1]
    segs = shapely.linestrings(np.stack([coords, coords[ends]], axis=1))
    uniq, inverse = np.unique(coords, axis=0, return_inverse=True)
    inverse = inverse.reshape(-1)
    utree = shapely.STRtree(shapely.points(uniq))
    e, v = utree.query(segs, predicate="dwithin", distance=tolerance)
    keep = (inverse[e] != v) & (inverse[ends[e]] != v)
    e, v = e[keep], v[keep]
    inserts = {}
    for edge, vert in zip(e.tolist(), v.tolist()):
        inserts.setdefault(edge, []).append(vert)
    moved[ring_of[e]] = True
    changed = {}
    for k in np.flatnonzero(moved):
        lo, hi = offsets[k], offsets[k + 1]
        ring = []
        for idx in range(lo, hi):
            ring.append((coords[idx, 0], coords[idx, 1]))
            if idx in inserts:
                p0 = coords[idx]
                d = coords[ends[idx]] - p0
                pts = uniq[inserts[idx]]
                t = (pts - p0) @ d / max(float(d @ d), 1e-300)
                for j in np.argsort(t):
                    if 0 < t[j] < 1:
                        ring.append((pts[j, 0], pts[j, 1]))
        f, r = owner[k]
        changed.setdefault(f, {})[r] = dedupe_ring(ring)
    out = list(geometries)
    simple = [f for f, rings in changed.items() if not geometries[f].interiors
              and len(rings[0]) >= 3]
    candidates = dict(zip(simple, to_polygons([changed[f][0] for f in simple])))
    for f, new_rings in changed.items():
        g = geometries[f]
        if f in candidates or not g.interiors:
            continue
        rings = [new_rings.get(r) or ccw_ring(ring.coords)
                 for r, ring in enumerate([g.exterior] + list(g.interiors))]
        if len(rings[0]) >= 3:
            candidates[f] = Polygon(rings[0], [h for h in rings[1:] if len(h) >= 3])
    if candidates:
        fs = list(candidates)
        polys = np.array([candidates[f] for f in fs], dtype=object)
        before = np.array([geometries[f].area for f in fs])
        ok = shapely.is_valid(polys) & (np.abs(shapely.area(polys) - before) <= OVERLAP_TOLERANCE)
        for f, poly, good in zip(fs, polys, ok):
            if good:
                out[f] = poly
    return out
