"""The vertex budget of pitched roofs: footprints of many vertices are
simplified before their roof is built.

A straight skeleton costs more than linear time and memory in the number of
vertices (CGAL's: about a second and 250 MB for 1,000 vertices, 2 GB for
5,000), and a footprint digitised with a vertex every few centimetres gives
a roof of slivers that val3dity rejects anyway. A footprint of more than
:data:`MAX_ROOF_VERTICES` vertices (curved facades, digitised detail: real
cadastre footprints) therefore gets its pitched roof on a simplified outline
(:func:`simplify_rings`: Douglas-Peucker, topology preserved, with the
smallest tolerance that leaves at most that many vertices); the walls and
the ground then follow the simplified outline. A flat roof keeps every
vertex. No footprint of the thesis's three footprint sets has more than 83
vertices.
"""


from dataclasses import dataclass

import numpy as np

from ..outlines import clean_rings, rings_are_simple

#: pitched roofs are built on footprints of at most this many vertices
MAX_ROOF_VERTICES = 100
#: at most this many steps of the tolerance search
_STEPS = 40


@dataclass(frozen=True)
class Simplified:
    """Rings simplified to a vertex budget (see :func:`simplify_rings`)."""

    #: per ring, the simplified ring (counter-clockwise, millimetre grid), or
    #: None where no simple ring within the budget was found
    rings: list
    #: per ring, the Douglas-Peucker tolerance used (m), nan where None
    tolerance: np.ndarray


def needs_budget(rings, kinds, max_vertices=MAX_ROOF_VERTICES):
    """(B,) True for the rings whose roof kind is pitched (not "flat") and
    that have more than ``max_vertices`` vertices."""
    return np.array([len(xy) > max_vertices and kind != "flat"
                     for xy, kind in zip(rings, kinds)], dtype=bool)


def simplify_rings(rings, max_vertices=MAX_ROOF_VERTICES):
    """Each ring (n, 2) simplified to at most ``max_vertices`` vertices, in bulk.

    Douglas-Peucker with ``preserve_topology`` (the outline stays a simple
    polygon) and the smallest tolerance (found by bisection, to about 5 %)
    whose result, cleaned as every footprint (millimetre grid, no collinear
    vertex: :func:`reconstruction.lod2.outlines.clean_rings`), is simple and
    within the budget. Returns the :class:`Simplified` rings.
    """
    import shapely


    R = len(rings)
    out = Simplified([None] * R, np.full(R, np.nan))
    if R == 0:
        return out
    polygons = np.array([shapely.Polygon(xy) for xy in rings], dtype=object)
    # geometric bisection of the tolerance between half a millimetre (too
    # small: the rings are over the budget after cleaning at 1 mm) and the
    # ring's size (large enough: topology-preserving simplification keeps
    # a polygon), to within 5 %
    lo = np.full(R, 0.0005)
    hi = np.array([max(float(np.ptp(xy, axis=0).max()), 0.001) for xy in rings])
    for _ in range(_STEPS):
        todo = np.nonzero(hi > 1.05 * lo)[0]
        if not len(todo):
            break
        tol = np.sqrt(lo[todo] * hi[todo])
        cand, _ = clean_rings(shapely.simplify(polygons[todo], tol, preserve_topology=True))
        fits = np.array([c is not None and len(c) <= max_vertices for c in cand], dtype=bool)
        if fits.any():
            fits[fits] = rings_are_simple([c for c, f in zip(cand, fits) if f])
        for k, t, c, f in zip(todo, tol, cand, fits):
            if f:
                out.rings[k], out.tolerance[k], hi[k] = c, t, t
            else:
                lo[k] = t
    return out
