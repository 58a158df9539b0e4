"""Issue 51, items 1-2, on the Paris 1925 atlas: blocks and hatched buildings
read as the shapes the map's lines close (r.histo.classify segmentation=lines,
through the library), scored with the ICDAR panoptic quality per class as
testsuite/paris_lines.py defines the classes; and its pure parts on made-up
arrays."""

import numpy as np
import pytest

from paris_lines import BLOCK, HATCHED, STREET, truth_classes
from paris_shapes import ParisTruth, paris_files

#: issue 51's acceptance: blocks and hatched buildings PQ >= 0.60 each
ACCEPTANCE = 0.60
#: what the reading gives today (seed 1): blocks 0.404, hatched 0.168, all
#: shapes 0.358; a change that loses more than a little fails
TODAY = {"blocks": 0.39, "hatched": 0.15, "shapes": 0.35}


def test_truth_classes_by_what_fills_a_shape():
    shapes = np.full((20, 70), 4)        # the open space around: the largest shape
    shapes[1:19, 1:13], shapes[1:19, 14:26], shapes[1:19, 27:39] = 1, 2, 3
    shapes[1:19, [13, 26]] = 0           # edges
    rgb = np.full((20, 70, 3), 230.0)
    rgb[:, 14:26][::2] = 30.0            # shape 2: every other row black (hatched)
    rgb[8, 30] = 30.0                    # shape 3: a speck
    truth = ParisTruth(shapes, np.ones(shapes.shape, bool))
    classes = truth_classes(rgb, truth)
    assert classes.tolist() == [0, BLOCK, HATCHED, BLOCK, STREET]


@pytest.fixture(scope="module")
def paris(shared_data):
    files = paris_files(shared_data)
    if files.missing():
        pytest.skip("the Paris 1925 atlas is not complete in '{}' (missing {})".format(
            shared_data, ", ".join(files.missing())))
    from paris_lines import read_and_score

    scores = read_and_score(files, seed=1)
    print("Paris 1925 (west), segmentation=lines: blocks PQ {:.3f}, hatched PQ {:.3f}, all "
          "shapes PQ {:.3f} ({:.0f} s)".format(scores.blocks.pq, scores.hatched.pq,
                                              scores.shapes.pq, scores.seconds))
    return scores


@pytest.mark.acceptance
def test_paris_shapes_read_from_the_lines_as_well_as_today(paris):
    for name, floor in TODAY.items():
        assert getattr(paris, name).pq >= floor, name


@pytest.mark.acceptance
@pytest.mark.xfail(reason="issue 51 open: hatched buildings drawn side by side merge (the "
                   "lines between them lie in the hatching), gardens and text touching the "
                   "outlines are read as line work (blocks PQ 0.40, hatched 0.17)")
def test_paris_blocks_and_hatched_buildings_meet_the_acceptance(paris):
    assert paris.blocks.pq >= ACCEPTANCE and paris.hatched.pq >= ACCEPTANCE
