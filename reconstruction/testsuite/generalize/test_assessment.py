"""Point-based detection scores (no GRASS needed)."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from shapely.geometry import MultiPolygon, Point, Polygon, box

from reconstruction.generalize.assessment import DetectionScores, point_detection_scores, point_hits


def test_scores_count_polygons_with_points_and_points_in_polygons():
    polygons = [box(0, 0, 10, 10), box(20, 0, 30, 10), box(40, 0, 50, 10), box(60, 0, 70, 10)]
    # two points in the first plot, one in the second, one outside everything
    points = [(1, 1), (9, 9), (25, 5), (100, 100)]
    scores = point_detection_scores(polygons, points)
    p, r, f = scores.precision, scores.recall, scores.f_score
    assert p == pytest.approx(2 / 4)
    assert r == pytest.approx(3 / 4)
    assert f == pytest.approx(2 * 0.5 * 0.75 / 1.25)


def test_named_fields_and_shapely_points_and_boundary_points():
    scores = point_detection_scores([box(0, 0, 10, 10)], [Point(10, 5), Point(0, 0)])
    assert scores.precision == 1.0
    assert scores.recall == 1.0
    assert scores.f_score == 1.0


def test_holes_and_multipolygons():
    courtyard = Polygon(box(0, 0, 10, 10).exterior.coords, [box(4, 4, 6, 6).exterior.coords])
    multi = MultiPolygon([box(20, 0, 22, 2), box(30, 0, 32, 2)])
    hits = point_hits([courtyard, multi], np.array([[5, 5], [2, 2], [31, 1]]))
    assert hits.tolist() == [[False, True, False], [False, False, True]]


def test_empty_inputs_score_zero():
    assert point_detection_scores([], [(0, 0)]) == DetectionScores(0.0, 0.0, 0.0)
    assert point_detection_scores([box(0, 0, 1, 1)], []) == DetectionScores(0.0, 0.0, 0.0)
    assert point_detection_scores([None, Polygon()], np.empty((0, 2))) == DetectionScores(0.0, 0.0, 0.0)


@settings(max_examples=40, deadline=None)
@given(st.lists(st.tuples(st.integers(0, 20), st.integers(0, 20)), min_size=1, max_size=15),
       st.lists(st.tuples(st.floats(-5, 105), st.floats(-5, 105)), min_size=1, max_size=20))
def test_scores_within_bounds_and_f_between(corners, points):
    polygons = [box(5 * i, 5 * j, 5 * i + 4, 5 * j + 4) for i, j in corners]
    scores = point_detection_scores(polygons, points)
    p, r, f = scores.precision, scores.recall, scores.f_score
    assert 0 <= p <= 1 and 0 <= r <= 1
    assert min(p, r) - 1e-12 <= f <= max(p, r) + 1e-12
    # a point in every polygon gives precision 1
    centres = [g.centroid.coords[0] for g in polygons]
    assert point_detection_scores(polygons, centres).precision == 1.0
