"""The v.histo.generalize stage (reconstruction.generalize.stage): options, raw plots,
columns and report (no GRASS needed)."""

import csv
import json

import numpy as np
import pytest
from shapely.geometry import MultiPolygon, Point, box

from reconstruction.generalize import stage as generalize
from reconstruction.generalize import shape_metrics
from reconstruction.core.errors import InputError

DEFAULTS = {"method": "alpha,lines", "alpha": "12", "distance": "5", "angle": "180",
            "tolerance": "1", "min_area": "20", "gt_buffer": "2", "seed": "1"}


def options(**changes):
    return dict(DEFAULTS, **changes)


def test_default_options_give_the_default_config():
    assert generalize.read_config(options(), {"r": False}) == generalize.GeneralizeConfig()
    config = generalize.read_config(options(method="douglas", min_area="0"), {"r": True})
    assert config.methods == ("douglas",) and config.min_area == 0 and config.orthogonal


@pytest.mark.parametrize("key,value", [("alpha", "0"), ("distance", "-1"), ("tolerance", "0"),
                                       ("min_area", "-1"), ("gt_buffer", "0"), ("angle", "200"),
                                       ("angle", "-1"), ("alpha", "x")])
def test_bad_options_are_refused_with_the_option_named(key, value):
    with pytest.raises(InputError, match="{}=".format(key)):
        generalize.read_config(options(**{key: value}), {"r": False})


def test_raw_plots_one_per_part_small_ones_dropped():
    geoms = [MultiPolygon([box(0, 0, 10, 10), box(20, 0, 21, 1)]), None, box(0, 20, 10, 30)]
    raw = generalize.raw_plots(geoms, 20, "raw", cats=[5, 6, 7])
    assert len(raw.polygons) == 2 and raw.cats == [5, 7]
    assert (raw.areas, raw.dropped) == (3, 1)
    assert generalize.raw_plots(geoms, 20, "raw").cats is None
    with pytest.raises(InputError, match="smaller than min_area"):
        generalize.raw_plots(geoms, 1e9, "raw")
    with pytest.raises(InputError, match="No area with a category in <raw>"):
        generalize.raw_plots([None], 0, "raw")


def test_generalize_map_columns_report_and_files(tmp_path):
    squares = [box(0, 0, 20, 20), box(30, 0, 50, 25), box(0, 40, 12, 52)]
    raw = generalize.raw_plots(squares, 20, "raw", cats=[3, 4, 5])
    config = generalize.GeneralizeConfig(methods=("douglas",))
    result = generalize.generalize_map(raw, config, gt_points=np.array([[10, 10], [100, 100]]),
                                       gt_polygons=[box(0, 0, 20, 20)])
    assert len(result.plots) == 3
    assert list(result.columns) == ["source", "method"] + list(shape_metrics.METRICS)
    assert result.columns["source"] == [3, 4, 5]
    assert result.columns["method"] == ["douglas"] * 3
    report = result.report
    figures = report.figures()
    assert list(figures)[:6] == ["plots", "raw_areas", "dropped_small", "methods", "fallbacks",
                                 "steps"]
    assert list(figures)[6:10] == ["precision", "recall", "f_score", "gt_points"]
    assert list(figures)[10:] == ["gt_polygons", "matched", "turning_distance",
                                  "buffer_similarity", "turning_distances", "buffer_similarities"]
    assert figures["methods"] == {"douglas": 3}
    assert (report.points.precision, report.points.recall) == (pytest.approx(1 / 3), 0.5)
    assert report.shapes.matched == 1 and report.shapes.buffer_similarity == pytest.approx(100)
    scalars = report.scalars()
    assert "steps" not in scalars and "turning_distances" not in scalars
    assert scalars["plots"] == 3 and scalars["gt_points"] == 2
    report.write_json(tmp_path / "r.json")
    with open(tmp_path / "r.json") as f:
        assert json.load(f) == json.loads(json.dumps(figures))
    report.write_metrics_csv(tmp_path / "m.csv")
    with open(tmp_path / "m.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert [row["step"] for row in rows] == ["raw", "douglas"]
    assert float(rows[0]["area_sum"]) == pytest.approx(400 + 500 + 144)


def test_report_without_ground_truth_has_no_scores():
    raw = generalize.raw_plots([box(0, 0, 20, 20)], 20, "raw")
    result = generalize.generalize_map(raw, generalize.GeneralizeConfig(methods=("douglas",)))
    assert "source" not in result.columns
    assert result.report.points is None and result.report.shapes is None
    assert list(result.report.scalars()) == ["plots", "raw_areas", "dropped_small"]
    assert Point(10, 10).within(result.plots[0])
