"""The polygons of a geometry: parts, the largest part, many geometries exploded (no GRASS)."""

import numpy as np
import pytest
import shapely
from shapely.geometry import GeometryCollection, LineString, MultiPolygon, Point, Polygon, box

from reconstruction.geom import polygons

NESTED = GeometryCollection([
    box(0, 0, 1, 1),
    LineString([(0, 0), (5, 5)]),
    GeometryCollection([Point(3, 3), MultiPolygon([box(2, 2, 4, 4), box(6, 6, 7, 7)])]),
    Polygon(),
])


def test_parts_of_one_geometry_depth_first_without_lines_points_or_empties():
    parts = polygons.polygon_parts(NESTED)
    assert [p.bounds for p in parts] == [(0, 0, 1, 1), (2, 2, 4, 4), (6, 6, 7, 7)]
    square = box(0, 0, 1, 1)
    assert polygons.polygon_parts(square)[0] is square
    assert polygons.polygon_parts(None) == []
    assert polygons.polygon_parts(Polygon()) == []
    assert polygons.polygon_parts(Point(0, 0)) == []


def test_parts_of_many_geometries_in_the_same_order_with_their_source():
    geometries = [None, box(10, 10, 11, 11), NESTED, LineString([(0, 0), (1, 1)])]
    parts, index = polygons.polygon_parts(geometries, return_index=True)
    assert list(index) == [1, 2, 2, 2]
    one_by_one = [p for g in geometries for p in polygons.polygon_parts(g)]
    assert [p.wkb for p in parts] == [p.wkb for p in one_by_one]


def test_largest_polygon_first_of_equals_and_none_without_area():
    assert polygons.largest_polygon(NESTED).bounds == (2, 2, 4, 4)
    twins = MultiPolygon([box(0, 0, 2, 2), box(5, 5, 7, 7)])
    assert polygons.largest_polygon(twins).bounds == (0, 0, 2, 2)
    assert polygons.largest_polygon(LineString([(0, 0), (1, 1)])) is None
    assert polygons.largest_polygon(None) is None


def test_explode_repairs_and_keeps_parts_with_area():
    bowtie = Polygon([(0, 0), (2, 2), (2, 0), (0, 2)])
    flat = Polygon([(0, 0), (1, 0), (2, 0)])
    parts, index = polygons.explode([MultiPolygon([box(0, 0, 1, 1), box(5, 5, 6, 6)]), None,
                                     bowtie, flat, NESTED])
    assert index == [0, 0, 2, 2, 4, 4, 4]
    assert all(p.is_valid and p.geom_type == "Polygon" and p.area > 0 for p in parts)
    assert sum(p.area for p in parts[2:4]) == np.float64(shapely.make_valid(bowtie).area)


def test_repair_gives_one_valid_geometry_per_input_and_tells_which_were_invalid():
    bowtie = Polygon([(0, 0), (2, 2), (2, 0), (0, 2)])
    two = MultiPolygon([box(0, 0, 1, 1), box(5, 5, 6, 6)])
    out, repaired = polygons.repair([box(0, 0, 1, 1), None, bowtie, Polygon(), two,
                                     LineString([(0, 0), (1, 1)])])
    assert list(repaired) == [False, False, True, False, False, False]
    assert out[0].equals(box(0, 0, 1, 1)) and out[1] is None and out[3] is None and out[5] is None
    assert out[2].is_valid and out[2].area == pytest.approx(2)
    assert out[4].geom_type == "MultiPolygon" and out[4].area == pytest.approx(2)
