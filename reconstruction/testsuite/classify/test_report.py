"""What r.histo.classify prints after its run (reconstruction.classify.report): no GRASS."""

import numpy as np

from reconstruction.classify.config import ClassifyConfig
from reconstruction.classify.report import report
from reconstruction.classify.segments import TuningResult
from reconstruction.classify.stage import ClassifyResult, Grid, RemovalRule

GRID = Grid(None, north=100.0, west=0.0, nsres=0.5, ewres=0.5, size=(10, 10))
TUNING = TuningResult(np.zeros(1), np.zeros(1), np.zeros(1), np.zeros(1), np.ones(1), 0)


def _result(rule=None, timing=(("segmentation", 1.25), ("classification", 0.5))):
    return ClassifyResult(classes=np.zeros((10, 10), dtype=np.int32), pairs=[(0.1, 5)],
                          criteria=[(1.0, 0.1)], tuning=TUNING, chosen="seg", segments=3,
                          window=rule.window if rule else None, present=[1, 2], rule=rule,
                          timing=list(timing), grid=GRID)


def test_without_cleaning_only_the_timing_with_verbose():
    messages = report(_result().timed("output", 0.04), ClassifyConfig((0.1,), (5,)))
    assert [(m.level, m.text) for m in messages] == [
        ("verbose", "Timing (s): segmentation 1.2, classification 0.5, output 0.0")]


def test_the_cleaning_rule_in_map_units_before_the_timing():
    rule = RemovalRule(window=9, min_cells=225, width_cells=3, thickness=15.0,
                       derived=("window", "min_area", "min_width"))
    config = ClassifyConfig((0.1,), (5,), remove=(2,))
    messages = report(_result(rule), config)
    assert [(m.level, m.text) for m in messages] == [
        ("message", "Removed classes 2 with a 9x9 moving window (derived from the thickest "
                    "removed letter or symbol: 15 cells of 0.5 map units); minimum mapping unit "
                    "56.25 square map units (derived: a square as thick); minimum width 1.5 map "
                    "units (derived: 3 cells, the mixed cells along a scan's edges)"),
        ("verbose", "Timing (s): segmentation 1.2, classification 0.5")]


def test_a_given_rule_without_removal_is_not_derived():
    rule = RemovalRule(window=3, min_cells=40, width_cells=0, thickness=0.0)
    config = ClassifyConfig((0.1,), (5,), min_area=10.0, min_width=0.0)
    text = report(_result(rule), config)[0].text
    assert text == "Minimum mapping unit 10 square map units; minimum width 0 map units"
