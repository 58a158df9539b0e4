"""The Paris 1925 ground truth read and scored as the ICDAR 2021 MapSeg
competition does it (testsuite/paris_shapes.py, issue 51 item 6): synthetic
arrays, and the published data when ../shared/data has it."""

import numpy as np
import pytest

from paris_shapes import paris_files, paris_truth, read_band, read_paris_truth, score_prediction


def synthetic_edges():
    """A 10 x 16 edge image: a frame and lines closing four regions, the
    right-hand one outside the content mask."""
    edges = np.zeros((10, 16), np.uint8)
    edges[[0, -1], :] = 255
    edges[:, [0, 6, 11, -1]] = 255
    edges[4, 0:7] = 255
    mask = np.full(edges.shape, 255, np.uint8)
    mask[:, 12:] = 0
    return edges, mask


def test_truth_is_the_closed_shapes_inside_the_mask():
    edges, mask = synthetic_edges()
    truth = paris_truth(edges, mask)
    assert truth.count == 3          # two on the left, one in the middle; not the right strip
    assert (truth.shapes[edges > 0] == 0).all() and (truth.shapes[mask == 0] == 0).all()
    assert sorted(np.bincount(truth.shapes.ravel())[1:].tolist()) == [15, 20, 32]


def test_scores_of_the_truth_itself_a_merge_and_nothing():
    edges, mask = synthetic_edges()
    truth = paris_truth(edges, mask)
    q = score_prediction(truth.shapes, truth)
    assert (q.pq, q.sq, q.rq, q.matched) == (1.0, 1.0, 1.0, 3)
    # the two left shapes read as one with the line between (40 cells): IoU
    # 15/40 and exactly 20/40 with them, not above 0.5: only the middle one found
    merged = truth.shapes.copy()
    merged[1:9, 1:6] = 1
    q = score_prediction(merged, truth)
    assert (q.predicted, q.true, q.matched) == (2, 3, 1)
    assert (q.pq, q.sq, q.rq) == pytest.approx((2 / 5, 1.0, 2 / 5))
    # a prediction beyond the map's edge loses what lies outside the mask
    beyond = truth.shapes.copy()
    beyond[1:9, 12:15] = 9
    assert score_prediction(beyond, truth).pq == 1.0
    assert score_prediction(np.zeros(edges.shape, int), truth).pq == 0.0
    with pytest.raises(ValueError, match="grid"):
        score_prediction(np.zeros((3, 3), int), truth)


def test_truth_read_from_files(tmp_path):
    from PIL import Image

    edges, mask = synthetic_edges()
    Image.fromarray(edges).save(tmp_path / "e.tif")
    Image.fromarray(mask).save(tmp_path / "m.tif")
    assert (read_band(str(tmp_path / "e.tif")) == edges).all()
    files = paris_files(str(tmp_path))
    assert files.missing() == [files.scan, files.edges, files.mask]


@pytest.mark.acceptance
def test_published_paris_ground_truth(shared_data):
    files = paris_files(shared_data)
    if files.missing():
        pytest.skip("the Paris 1925 atlas is not complete in '{}' (missing {})".format(
            shared_data, ", ".join(files.missing())))
    truth = read_paris_truth(files)
    assert truth.shapes.shape == read_band(files.scan).shape[:2]
    assert truth.count > 0 and truth.mask.any()
    sizes = np.bincount(truth.shapes.ravel())[1:]
    assert (sizes > 0).all()
    # the shapes cover most of the map: the edges are thin lines
    assert sizes.sum() > 0.5 * truth.mask.sum()
    q = score_prediction(truth.shapes, truth)
    assert (q.pq, q.matched) == (1.0, truth.count)
    print("Paris 1925 (west): {} ground-truth shapes".format(truth.count))
