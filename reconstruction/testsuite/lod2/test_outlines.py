"""Footprint outlines: polygons of footprints, clean rings, facts of a ring."""

import math

import numpy as np
from shapely.geometry import Polygon

from reconstruction.lod2 import outlines

RECT = np.array([[0.0, 0.0], [12.0, 0.0], [12.0, 6.0], [0.0, 6.0]])
L_SHAPE = np.array([[0, 0], [10, 0], [10, 4], [4, 4], [4, 10], [0, 10]], dtype=float)


def test_clean_ring_removes_duplicates_and_collinear_points_and_orients():
    ring = [[0, 0], [0, 5], [0, 5.0001], [5, 5], [5, 2.5], [5, 0], [0, 0]]
    xy, why = outlines.clean_ring(ring)
    assert why is None
    assert len(xy) == 4
    area2 = np.sum(xy[:, 0] * np.roll(xy[:, 1], -1) - np.roll(xy[:, 0], -1) * xy[:, 1])
    assert area2 > 0
    assert outlines.clean_ring([[0, 0], [1, 0], [2, 0]])[0] is None


def test_clean_rings_in_bulk_match_clean_ring():
    rng = np.random.default_rng(2)
    polys = [Polygon([[0, 0], [0, 5], [0, 5.0001], [5, 5], [5, 2.5], [5, 0]]),
             Polygon([[0, 0], [4, 0], [4, 3]]), Polygon([[0, 0], [0, 3], [4, 3], [4, 0]]),
             Polygon([[0, 0], [1, 0], [2, 0], [1, 0.0001]])]
    for _ in range(30):
        pts = rng.uniform(0, 20, (int(rng.integers(3, 9)), 2))
        polys.append(Polygon(pts).convex_hull)
    rings, reasons = outlines.clean_rings(polys)
    for poly, ring, why in zip(polys, rings, reasons):
        one, one_why = outlines.clean_ring(np.asarray(poly.exterior.coords))
        assert why == one_why
        if one is None:
            assert ring is None
        else:
            assert np.array_equal(ring, one)


def test_footprint_polygons_parts_holes_and_empties():
    from shapely.geometry import GeometryCollection, MultiPolygon, box

    courtyard = Polygon([(0, 0), (10, 0), (10, 10), (0, 10)], [[(2, 2), (4, 2), (4, 4), (2, 4)]])
    geoms = [box(0, 0, 1, 1), None, MultiPolygon([box(0, 0, 1, 1), box(2, 0, 3, 1)]),
             Polygon(), courtyard, MultiPolygon([box(5, 5, 6, 6)]),
             GeometryCollection([box(0, 0, 1, 1)]), box(7, 7, 8, 8)]
    fp = outlines.footprint_polygons(geoms, skip=[0, 0, 0, 0, 0, 0, 0, 1])
    polys, src, part, holes, empty = fp.polygons, fp.source, fp.part, fp.holes, fp.empty
    assert list(src) == [0, 2, 2, 4, 5]
    assert list(part) == [-1, 0, 1, -1, -1]
    assert polys[2].equals(box(2, 0, 3, 1)) and polys[3].equals(courtyard)
    assert holes == 1 and empty == 2
    none = outlines.footprint_polygons([])
    assert len(none.polygons) == 0 and (none.holes, none.empty) == (0, 0)


def test_helpers():
    assert outlines.is_convex(RECT)
    assert not outlines.is_convex(L_SHAPE)
    assert outlines.opposite_edge(RECT, 1) == 3
    assert outlines.end_edges(L_SHAPE) == [1, 4]
    assert outlines.street_end(RECT) in (1, 3)
    assert outlines.street_end(RECT, 0) == 0
    assert math.isclose(outlines.edge_lengths(RECT).sum(), 36.0)
