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


# ---------------------------------------------------------------------------
# Objects on a grid (issue 50's acceptance measure)
# ---------------------------------------------------------------------------

from reconstruction.generalize.assessment import (  # noqa: E402
    ObjectScores, ParcelScores, blocks_from_parcels, matched_pairs, object_scores,
    parcel_scores, parcels_from_mask)


def _labels(shape, *boxes):
    """A label raster with box i (row0, row1, col0, col1) labelled i + 1."""
    out = np.zeros(shape, dtype=np.int32)
    for i, (r0, r1, c0, c1) in enumerate(boxes):
        out[r0:r1, c0:c1] = i + 1
    return out


def test_objects_matched_one_to_one_above_half_iou():
    true = _labels((20, 40), (0, 10, 0, 10), (0, 10, 20, 30), (12, 20, 0, 8))
    # the first found exactly, the second by a box of IoU 60/100 (> 0.5), the
    # third by half of it: IoU 32/64 = 0.5 (not > 0.5), plus a false positive
    predicted = _labels((20, 40), (0, 10, 0, 10), (0, 6, 20, 30), (12, 20, 0, 4),
                        (0, 5, 35, 40))
    scores = object_scores(predicted, true)
    assert (scores.predicted, scores.true, scores.matched) == (4, 3, 2)
    assert scores.iou_sum == pytest.approx(1.0 + 0.6)
    assert scores.precision == pytest.approx(2 / 4) and scores.recall == pytest.approx(2 / 3)
    assert scores.f_score == pytest.approx(2 * 0.5 * (2 / 3) / (0.5 + 2 / 3))
    # PQ = sum of IoUs / (TP + FP / 2 + FN / 2) = 1.6 / (2 + 1 + 0.5)
    assert scores.pq == pytest.approx(1.6 / 3.5)
    # at IoU >= 0.5 the third pairs too
    assert object_scores(predicted, true, strict=False).matched == 3


def test_one_object_pairs_once_and_the_better_pair_wins():
    # two predictions over one true object, IoU 0.6 and 0.4: one pair (0.6);
    # with threshold 0.3 still one, the larger
    true = _labels((10, 10), (0, 10, 0, 10))
    predicted = _labels((10, 10), (0, 6, 0, 10), (6, 10, 0, 10))
    assert matched_pairs(predicted, true, 0.3) == [(1, 1, pytest.approx(0.6))]


def test_perfect_and_empty_scores():
    true = _labels((10, 10), (0, 5, 0, 5), (5, 10, 5, 10))
    assert object_scores(true * 7, true) == ObjectScores(2, 2, 2, 2.0, 1.0, 1.0, 1.0, 1.0)
    empty = np.zeros_like(true)
    assert object_scores(empty, true) == ObjectScores(0, 2, 0, 0.0, 0.0, 0.0, 0.0, 0.0)
    assert object_scores(empty, empty).pq == 0.0
    with pytest.raises(ValueError, match="shapes"):
        object_scores(empty, np.zeros((3, 3)))


def test_parcels_are_four_connected_white_regions_of_50_cells():
    mask = np.zeros((30, 30), dtype=np.uint8)
    mask[0:10, 0:10] = 200          # 100 cells: a parcel
    mask[10:20, 10:20] = 255        # touches the first only at a corner: another
    mask[25:29, 25:29] = 255        # 16 cells: too small
    mask[0:10, 12:17] = 127         # below the threshold: no parcel
    parcels = parcels_from_mask(mask)
    assert parcels.max() == 2 and set(np.unique(parcels)) == {0, 1, 2}
    assert (parcels[0:10, 0:10] == 1).all() and (parcels[10:20, 10:20] == 2).all()
    assert (parcels[25:29, 25:29] == 0).all()


def test_blocks_close_the_lines_between_parcels_but_not_streets_or_courtyards():
    # two blocks 20 cells apart; the first of two parcels split by a 2-cell
    # line, the second a ring around a 16 x 16 courtyard; all on the map's edge
    parcels = np.zeros((40, 70), dtype=np.int32)
    parcels[0:40, 0:14] = 1
    parcels[0:40, 16:30] = 2
    parcels[0:40, 50:70] = 3
    parcels[12:28, 52:68] = 0
    blocks = blocks_from_parcels(parcels, 6)
    assert blocks.max() == 2
    assert (blocks[:, 0:30] == 1).all()             # the line closed, the edge kept
    assert (blocks[:, 31:49] == 0).all()            # the street stays open
    assert (blocks[16:24, 56:64] == 0).all()        # the courtyard stays a hole
    assert (blocks[parcels == 3] == 2).all()


def test_parcel_scores_share_matched_and_count_ratio():
    parcels = _labels((20, 40), (0, 10, 0, 10), (0, 10, 10, 20), (10, 20, 0, 20))
    blocks = (parcels > 0).astype(int)
    # the first parcel found; the second split in two halves (IoU 0.5 each:
    # one pairs, at >= 0.5); the third missed (a footprint over a quarter of
    # it); one footprint out in the street (not counted)
    footprints = _labels((20, 40), (0, 10, 0, 10), (0, 10, 10, 15), (0, 10, 15, 20),
                         (10, 20, 0, 20), (0, 10, 30, 40))
    footprints[10:20, 0:20] = 0
    footprints[10:20, 0:5] = 4
    scores = parcel_scores(footprints, parcels, blocks)
    assert scores == ParcelScores(parcels=3, footprints=4, matched=2,
                                  matched_share=pytest.approx(2 / 3),
                                  count_ratio=pytest.approx(4 / 3))


# ---------------------------------------------------------------------------
# The ICDAR 2021 MapSeg competition's panoptic quality (issue 51, item 6).
# The expected figures below were computed with the competition's own tool,
# icdar21-mapseg-eval 1.0.4 (``COCO(gt, prediction)``, the ground truth given
# as the binary image 255 * (edges == 0 & mask), the prediction as a uint16
# label map or a binary image, both masked), on these very arrays.
# ---------------------------------------------------------------------------

from reconstruction.generalize.assessment import (  # noqa: E402
    PanopticQuality, icdar_panoptic_quality, icdar_quality, polygon_panoptic_quality,
    shapes_from_edges)


def _paris_like_edges():
    """A 12 x 14 edge image like the Paris ground truth: 1-pixel boundaries
    (255) closing five shapes and the open space around them, and a content
    mask (255 where the map is) that ends at column 11 without a drawn edge."""
    edges = np.zeros((12, 14), np.uint8)
    edges[0, :] = edges[-1, :] = 255
    edges[:, 0] = edges[:, -1] = 255
    edges[5, 0:8] = 255
    edges[:, 7] = 255
    edges[3, 7:] = 255
    edges[8, 7:] = 255
    mask = np.full_like(edges, 255)
    mask[:, 11:] = 0
    return edges, mask


def test_shapes_from_edges_are_the_four_connected_zero_regions_inside_the_mask():
    edges, mask = _paris_like_edges()
    shapes = shapes_from_edges(edges, mask)
    assert shapes.max() == 5
    assert (shapes[edges > 0] == 0).all() and (shapes[mask == 0] == 0).all()
    sizes = np.bincount(shapes.ravel())[1:]
    assert sorted(sizes.tolist()) == [6, 6, 12, 24, 30]
    # without the mask the right-hand regions reach the frame: still 5 shapes, larger
    assert shapes_from_edges(edges).max() == 5
    assert np.bincount(shapes_from_edges(edges).ravel())[1:].sum() > sizes.sum()


def test_icdar_pq_of_a_label_map_as_the_competition_tool_gives_it():
    edges, mask = _paris_like_edges()
    predicted = np.zeros(edges.shape, np.uint16)
    predicted[1:5, 1:7] = 1      # the top-left shape exactly
    predicted[6:11, 1:5] = 2     # 20 of the 30 cells of the bottom-left shape
    predicted[4:8, 8:11] = 3     # the middle right shape exactly
    predicted[9:11, 8:14] = 4    # the bottom right shape, and beyond the mask
    predicted[1:3, 8:10] = 5     # 4 of the 6 cells of the top right shape
    scores = icdar_panoptic_quality(predicted, shapes_from_edges(edges, mask), mask > 0)
    # icdar21-mapseg-eval 1.0.4: PQ 0.8333, SQ 0.8333, RQ 1.0
    assert (scores.predicted, scores.true, scores.matched) == (5, 5, 5)
    assert scores.rq == pytest.approx(1.0)
    # the tool's SQ: the mean of the distinct IoUs (1 and 2/3), not of all five (0.8667)
    assert scores.sq == pytest.approx(0.8333333333333333)
    assert scores.pq == pytest.approx(0.8333333333333333)


def test_icdar_pq_of_binary_predictions_as_the_competition_tool_gives_them():
    edges, mask = _paris_like_edges()
    true = shapes_from_edges(edges, mask)
    merged = np.zeros(edges.shape, bool)
    merged[1:11, 1:7] = True     # the two left shapes and the line between: one shape
    merged[4:8, 8:11] = True     # exact
    merged[9:11, 12:14] = True   # outside the mask: no shape
    scores = icdar_panoptic_quality(merged, true, mask)
    # icdar21-mapseg-eval 1.0.4: PQ 0.2857, SQ 1.0, RQ 0.2857
    assert (scores.predicted, scores.true, scores.matched) == (2, 5, 1)
    assert (scores.pq, scores.sq, scores.rq) == pytest.approx((2 / 7, 1.0, 2 / 7))
    split = merged.copy()
    split[1:11, 1:7] = False
    split[1:4, 1:7] = True       # 18 of 24 cells of the top-left shape
    split[6:11, 1:7] = True      # the bottom-left shape exactly
    scores = icdar_panoptic_quality(split, true, mask)
    # icdar21-mapseg-eval 1.0.4: PQ 0.65625, SQ 0.875, RQ 0.75
    assert (scores.predicted, scores.true, scores.matched) == (3, 5, 3)
    assert (scores.pq, scores.sq, scores.rq) == pytest.approx((0.65625, 0.875, 0.75))


def test_icdar_quality_counts_and_empty_cases():
    assert icdar_quality([], 0, 4) == PanopticQuality(0, 4, 0, 0.0, 0.0, 0.0)
    assert icdar_quality([], 3, 4).pq == 0.0
    q = icdar_quality([0.9, 0.7], 4, 2)
    assert (q.sq, q.rq) == pytest.approx((0.8, 4 / 6))
    assert q.pq == pytest.approx(0.8 * 4 / 6)


def test_polygon_pq_matches_areas_one_to_one_above_half():
    references = [box(0, 0, 10, 10), box(20, 0, 30, 10), box(40, 0, 50, 10)]
    plots = [box(0, 0, 10, 8),          # IoU 0.8
             box(0, 0, 10, 7),          # IoU 0.7 with the same reference: left over
             box(20, 0, 30, 10),        # IoU 1
             box(45, 0, 55, 10),        # IoU 1/3: no match
             Polygon()]                 # empty: not a shape
    q = polygon_panoptic_quality(plots, references)
    assert (q.predicted, q.true, q.matched) == (4, 3, 2)
    assert (q.sq, q.rq) == pytest.approx((0.9, 4 / 7))
    assert q.pq == pytest.approx(0.9 * 4 / 7)
    assert polygon_panoptic_quality([], references) == PanopticQuality(0, 3, 0, 0.0, 0.0, 0.0)
