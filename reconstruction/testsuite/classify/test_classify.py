"""The r.histo.classify stage (reconstruction.classify.stage, .pipeline): training, the
whole classification on small arrays (no GRASS needed). Its options: test_config.py."""

import numpy as np
import pytest

from reconstruction.classify import pipeline
from reconstruction.classify import stage as classify
from reconstruction.classify.config import read_config
from reconstruction.classify.report import rule_message
from reconstruction.core.errors import InputError

#: the module's option texts with their defaults (as g.parser gives them)
DEFAULTS = {"input": "r,g,b", "threshold": "0.07,0.10", "threshold_step": "0.01",
            "minsize": "7,10", "minsize_step": "1", "alpha": "1", "classifiers": "rf,knn,svm",
            "features": "spectral,size", "remove": "", "window": "", "iterations": "",
            "min_area": "", "min_width": "", "separate": "", "seed": "1", "nprocs": "1"}


def options(**changes):
    return dict(DEFAULTS, **changes)


GRID = classify.Grid(None, north=10.0, west=0.0, nsres=1.0, ewres=1.0, size=(10, 10))


def _points(*labels):
    """One point per label, along the diagonal of GRID."""
    xy = np.array([[i + 0.5, 9.5 - i] for i in range(len(labels))])
    return xy, {"cat": list(range(1, len(labels) + 1)), "label": list(labels),
                "class": ["building" if v == 1 else "street" for v in labels]}


def test_training_points_located_with_their_class_names():
    xy, columns = _points(1, 2, 2.0)
    training = classify.read_training(xy, columns, "label", "class", read_config(options()),
                                      GRID)
    assert training.labels.tolist() == [1, 2, 2] and training.classes == [1, 2]
    assert training.names == {1: "building", 2: "street"}
    assert training.rows.tolist() == [0, 1, 2] and training.cols.tolist() == [0, 1, 2]
    # no class column: no names
    assert classify.read_training(xy, columns, "label", "", read_config(options()),
                                  GRID).names == {}


@pytest.mark.parametrize("labels,column,changes,message", [
    ((1, 2), "code", {}, "has no column <code>"),
    ((1, 1), "label", {}, "at least two are needed"),
    ((1, 2.5), "label", {}, "positive integer class labels"),
    ((1, None), "label", {}, "without a value"),
    ((1, "x"), "label", {}, "integer class labels"),
    ((1, 2), "label", {"remove": "3"}, "No training point has the label(s) 3"),
    ((1, 2), "label", {"remove": "1,2"}, "nothing would be left"),
    ((1, 2), "label", {"remove": "2", "separate": "2"}, "separate="),
])
def test_bad_training_points_are_refused(labels, column, changes, message):
    xy, columns = _points(*labels)
    with pytest.raises(InputError) as error:
        classify.read_training(xy, columns, column, "class",
                               read_config(options(**changes)), GRID, "train")
    assert message in str(error.value)


def test_training_points_outside_the_grid_and_no_points_are_refused():
    xy, columns = _points(1, 2)
    xy[1] = [50, 50]
    config = read_config(options())
    with pytest.raises(InputError, match="1 of 2 training points lie outside"):
        classify.read_training(xy, columns, "label", "class", config, GRID)
    with pytest.raises(InputError, match="has no points"):
        classify.read_training(np.zeros((0, 2)), {"label": []}, "label", "class", config, GRID)


def _map():
    """A 10 x 10 map: a bright building block (label 1) in a dark street (label 2),
    with a one-cell 'letter' (label 3) in the street; two segmentations to choose from."""
    band = np.full((10, 10), 20.0)
    band[2:6, 2:6] = 200.0
    band[8, 8] = 120.0
    good = np.ones((10, 10), dtype=np.int32)
    good[2:6, 2:6] = 2
    good[8, 8] = 3
    bad = np.arange(1, 101, dtype=np.int32).reshape(10, 10) // 50 + 1   # two halves
    xy = np.array([[3.5, 6.5], [0.5, 0.5], [8.5, 1.5], [9.5, 9.5], [8.5, 1.5]])
    columns = {"label": [1, 2, 3, 2, 3], "class": ["building", "street", "text", "", None]}
    return [band, band, band], {"good": good, "bad": bad}, xy, columns


def test_classify_map_chooses_the_segmentation_classifies_and_removes():
    bands, segmentations, xy, columns = _map()
    config = read_config(options(threshold="0.1,0.2", threshold_step="0.1",
                                          minsize="1,1", remove="3", classifiers="rf,knn"))
    training = classify.read_training(xy, columns, "label", "class", config, GRID)
    said, detail = [], []
    result = classify.classify_map(bands, [(1, "bad"), (0, "good")], segmentations.get, training,
                                   config, GRID, message=said.append, verbose=detail.append)
    assert result.chosen == "good" and result.best_pair == (0.1, 1)
    assert result.segments == 3
    expected = np.full((10, 10), 2)
    expected[2:6, 2:6] = 1          # the letter is refilled from the street around it
    assert result.classes.tolist() == expected.tolist()
    assert result.present == [1, 2] and result.window == 3
    assert [step for step, _ in result.timing] == ["segmentation", "classification", "removal"]
    assert said[0].startswith("Chosen segmentation: threshold=0.1 minsize=1 (F=")
    assert said[1] == "Classifying 3 segments with rf,knn..."
    assert detail[0].startswith("threshold=0.2 minsize=1: VW=")
    lines = classify.tuning_table(result)
    assert lines[0] == "threshold,minsize,vw,moran,vw_norm,moran_norm,f"
    assert lines[1].startswith("0.1,1,0.000000,") and lines[-1] == "best: threshold=0.1 minsize=1"


def test_classify_map_refuses_training_points_on_no_data():
    bands, segmentations, xy, columns = _map()
    bands[1] = bands[1].copy()
    bands[1][3, 3] = np.nan  # under the building point
    config = read_config(options(threshold="0.1", minsize="1"))
    training = classify.read_training(xy, columns, "label", "class", config, GRID)
    with pytest.raises(InputError, match="no-data cells"):
        classify.classify_map(bands, [(0, "good")], segmentations.get, training, config, GRID)


def test_category_and_colour_rules():
    names = {1: "Building", 4: "water"}
    assert classify.category_rules([1, 3], names) == "1:Building\n3:class 3"
    assert classify.colour_rules([1, 3, 4], names) == \
        "1 230:80:80\n3 {}\n4 60:120:220".format(classify.PALETTE[1])


def test_removal_rule_derives_what_is_not_given_from_the_removed_objects():
    grid = classify.Grid(None, 100.0, 0.0, 0.5, 0.5, (10, 10))
    rule = classify.removal_rule(15.0, read_config(options(remove="2")), grid)
    # window thickness / 2 + 1, odd; a 15 x 15 cells minimum mapping unit; 3-cell fringes
    assert (rule.window, rule.min_cells, rule.width_cells) == (9, 225, 3)
    assert rule.derived == ("window", "min_area", "min_width")
    assert rule_message(rule, read_config(options(remove="2")), grid) == (
        "Removed classes 2 with a 9x9 moving window (derived from the thickest removed letter "
        "or symbol: 15 cells of 0.5 map units); minimum mapping unit 56.25 square map units "
        "(derived: a square as thick); minimum width 1.5 map units (derived: 3 cells, the mixed "
        "cells along a scan's edges)")
    # explicit values win, 0 turns a rule off
    config = read_config(options(remove="2", window="5", min_area="10", min_width="0"))
    rule = classify.removal_rule(15.0, config, grid)
    assert (rule.window, rule.min_cells, rule.width_cells, rule.derived) == (5, 40, 0, ())
    # nothing removed: only what is given applies
    rule = classify.removal_rule(0.0, read_config(options()), grid)
    assert (rule.min_cells, rule.width_cells) == (0, 0) and not rule.active(())
    rule = classify.removal_rule(0.0, read_config(options(min_area="1")), grid)
    assert rule.min_cells == 4 and rule.active(())


def test_segmentation_chains_grow_once_per_threshold():
    pairs = read_config(options(threshold="0.1,0.2", threshold_step="0.1",
                                         minsize="3,5", minsize_step="2")).pairs
    assert pairs == [(0.1, 3), (0.1, 5), (0.2, 3), (0.2, 5)]
    assert classify.segmentation_chains(pairs) == [[(0, None), (1, 0)], [(2, None), (3, 2)]]
    assert classify.segmentation_chains(pairs, exhaustive=True) == [[(i, None)] for i in range(4)]


def _inputs(bands, segmentations, xy, columns, said, percent=None):
    return pipeline.ClassifyInputs(
        grid=GRID, training_xy=xy, training_columns=columns, training_map="train",
        read_bands=lambda tile: bands if tile is None else None,
        read_segments=lambda name, tile: segmentations[name] if tile is None else None,
        segment=lambda chains: (run for run in [(1, "bad"), (0, "good")]),
        window_criteria=None, segment_tiles=None, say=said.extend,
        **({} if percent is None else {"percent": percent}))


def test_run_classifies_a_map_of_one_tile_whole_and_says_what_it_does():
    bands, segmentations, xy, columns = _map()
    config = read_config(options(threshold="0.1,0.2", threshold_step="0.1", minsize="1,1",
                                 remove="3", classifiers="rf,knn"))
    said = []
    result = pipeline.run(_inputs(bands, segmentations, xy, columns, said), config)
    direct = classify.classify_map(bands, [(1, "bad"), (0, "good")], segmentations.get,
                                   classify.read_training(xy, columns, "label", "class", config,
                                                          GRID),
                                   config, GRID)
    assert result.chosen == "good" and result.classes.tolist() == direct.classes.tolist()
    assert result.names == {1: "building", 2: "street", 3: "text"} and result.grid == GRID
    assert [(m.level, m.text[:22]) for m in said] == [
        ("message", "Segmenting with 2 para"), ("verbose", "threshold=0.2 minsize="),
        ("verbose", "threshold=0.1 minsize="), ("message", "Chosen segmentation: t"),
        ("message", "Classifying 3 segments")]
    assert said[0].text == "Segmenting with 2 parameter pairs..."
    assert [step for step, _ in result.timed("output", 1.0).timing] == [
        "segmentation", "classification", "removal", "output"]


def test_run_tells_the_progress_of_the_segmentations_of_a_map_classified_whole():
    """One percent step as each pair's segmentation is read (issue 33, item 10:
    the module was silent while i.segment ran for every pair); the result is
    the same as without."""
    bands, segmentations, xy, columns = _map()
    config = read_config(options(threshold="0.1,0.2", threshold_step="0.1", minsize="1,1",
                                 remove="3", classifiers="rf,knn"))
    said, steps = [], []
    result = pipeline.run(_inputs(bands, segmentations, xy, columns, said,
                                  lambda done, total: steps.append((done, total))), config)
    assert steps == [(1, 2), (2, 2)]
    quiet = pipeline.run(_inputs(bands, segmentations, xy, columns, []), config)
    assert result.classes.tolist() == quiet.classes.tolist() and result.chosen == quiet.chosen
    # one pair: nothing to tune, nothing to count
    steps.clear()
    config = read_config(options(threshold="0.1", minsize="1", remove="3", classifiers="rf,knn"))
    classify.classify_map(bands, [(0, "good")], segmentations.get,
                          classify.read_training(xy, columns, "label", "class", config, GRID),
                          config, GRID, percent=lambda done, total: steps.append((done, total)))
    assert steps == []


def test_run_checks_the_training_points_first():
    bands, segmentations, xy, columns = _map()
    with pytest.raises(InputError, match="has no column <code>"):
        pipeline.run(_inputs(bands, segmentations, xy, columns, []),
                     read_config(dict(options(), label_column="code")))
