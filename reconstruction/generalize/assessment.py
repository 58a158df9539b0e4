"""Assessment of reconstructed building plots against reference data.

Pure functions over shapely geometries and numpy arrays, shared by the
modules that report quality figures (r.histo.classify, v.histo.generalize).
"""

from dataclasses import dataclass

import numpy as np
import shapely


@dataclass(frozen=True)
class DetectionScores:
    """Point-based detection scores (each in [0, 1])."""

    precision: float
    recall: float
    f_score: float


def _points_array(points):
    """Points as an (n, 2) float array, from shapely points or coordinates."""
    if points is None:
        return np.empty((0, 2))
    if isinstance(points, np.ndarray) and points.dtype != object:
        return np.asarray(points, dtype=float).reshape(-1, 2)
    points = list(points)
    if not points:
        return np.empty((0, 2))
    if hasattr(points[0], "geom_type"):
        return shapely.get_coordinates(np.asarray(points, dtype=object))[:, :2].reshape(-1, 2)
    return np.asarray(points, dtype=float).reshape(-1, 2)


def point_hits(polygons, points):
    """Boolean matrix (polygons x points): does polygon i cover point j?

    A point on a polygon's boundary counts as inside. Empty or missing
    geometries cover nothing.
    """
    polygons = np.asarray(list(polygons) if polygons is not None else [], dtype=object)
    xy = _points_array(points)
    hits = np.zeros((len(polygons), len(xy)), dtype=bool)
    if not len(polygons) or not len(xy):
        return hits
    pts = shapely.points(xy)
    valid = np.array([g is not None and not g.is_empty for g in polygons], dtype=bool)
    if not valid.any():
        return hits
    tree = shapely.STRtree(polygons[valid])
    pt_idx, poly_idx = tree.query(pts, predicate="covered_by")
    hits[np.flatnonzero(valid)[poly_idx], pt_idx] = True
    return hits


def point_detection_scores(polygons, points):
    """Precision, recall and F-score of detected areas against reference points.

    As in the thesis (Morlighem 2021, Section 4): with one ground-truth point
    inside each true building plot,

    - recall = share of points inside (or on the boundary of) any polygon;
    - precision = share of polygons holding at least one point;
    - F-score = harmonic mean of the two (0 when both are 0).

    ``polygons`` is a sequence of shapely (Multi)Polygons; ``points`` a
    sequence of shapely Points or an (n, 2) array of coordinates. Returns a
    :class:`DetectionScores` (``precision``, ``recall``, ``f_score``); precision is 0
    without polygons, recall 0 without points.
    """
    hits = point_hits(polygons, points)
    n_polygons, n_points = hits.shape
    precision = float(hits.any(axis=1).sum()) / n_polygons if n_polygons else 0.0
    recall = float(hits.any(axis=0).sum()) / n_points if n_points else 0.0
    total = precision + recall
    f_score = 2.0 * precision * recall / total if total > 0 else 0.0
    return DetectionScores(precision, recall, f_score)
