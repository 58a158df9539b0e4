"""The v.histo.generalize stage (reconstruction.generalize.stage, .pipeline): raw plots,
columns and report figures (no GRASS needed). Its options: test_config.py."""

import csv
import json

import numpy as np
import pytest
from shapely.geometry import MultiPolygon, Point, box

from reconstruction import generalize
from reconstruction.generalize import shape_metrics
from reconstruction.core import safefile
from reconstruction.core.errors import InputError

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
                                  "buffer_similarity", "turning_distances", "buffer_similarities",
                                  "outline_offset", "iou", "outline_offsets", "ious",
                                  "outline_by_step", "pq", "sq", "rq", "pq_matched",
                                  "pq_plots", "pq_references"]
    assert figures["methods"] == {"douglas": 3}
    # the ICDAR 2021 MapSeg panoptic quality: 1 of 3 plots matches the one
    # reference (IoU 1): RQ = 2 * 1 / (3 + 1), SQ = 1
    assert (report.panoptic.pq_matched, report.panoptic.pq_plots,
            report.panoptic.pq_references) == (1, 3, 1)
    assert (report.panoptic.pq, report.panoptic.sq, report.panoptic.rq) == pytest.approx(
        (0.5, 1.0, 0.5))
    assert (report.points.precision, report.points.recall) == (pytest.approx(1 / 3), 0.5)
    assert report.shapes.matched == 1 and report.shapes.buffer_similarity == pytest.approx(100)
    assert report.shapes.outline_offset == pytest.approx(0) and report.shapes.iou == 1
    assert set(report.shapes.outline_by_step) == {"raw", "douglas"}
    scalars = report.scalars()
    assert "steps" not in scalars and "turning_distances" not in scalars
    assert scalars["plots"] == 3 and scalars["gt_points"] == 2
    with safefile.together() as files:
        report.write_files(files, str(tmp_path / "m.csv"), str(tmp_path / "r.json"))
    with open(tmp_path / "r.json") as f:
        assert json.load(f) == json.loads(json.dumps(figures))
    with open(tmp_path / "m.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert [row["step"] for row in rows] == ["raw", "douglas"]
    assert float(rows[0]["area_sum"]) == pytest.approx(400 + 500 + 144)


def test_report_without_ground_truth_has_no_scores():
    raw = generalize.raw_plots([box(0, 0, 20, 20)], 20, "raw")
    result = generalize.generalize_map(raw, generalize.GeneralizeConfig(methods=("douglas",)))
    assert "source" not in result.columns
    assert result.report.points is None and result.report.shapes is None
    assert result.report.panoptic is None
    assert list(result.report.scalars()) == ["plots", "raw_areas", "dropped_small"]
    assert Point(10, 10).within(result.plots[0])


def test_run_drops_small_areas_says_what_it_does_and_generalises():
    said = []
    geoms = [box(0, 0, 20, 20), box(30, 0, 31, 1), box(0, 40, 12, 52)]
    inputs = generalize.GeneralizeInputs(geometries=geoms, source_map="raw", cats=[7, 8, 9],
                                         gt_points=np.array([[10, 10]]), say=said.extend)
    config = generalize.GeneralizeConfig(methods=("douglas", "simplify"))
    result = generalize.run(inputs, config)
    assert [(m.level, m.text) for m in said] == [
        ("verbose", "1 raw areas smaller than 20.0 dropped"),
        ("message", "Generalising 2 plots (douglas, simplify)...")]
    assert result.columns["source"] == [7, 9] and result.report.points.recall == 1.0
    direct = generalize.generalize_map(generalize.raw_plots(geoms, 20.0, "raw", cats=[7, 8, 9]),
                                       config, np.array([[10, 10]]))
    assert [p.wkb for p in result.plots] == [p.wkb for p in direct.plots]


def test_run_says_nothing_dropped_when_nothing_is_and_refuses_no_areas():
    said = []
    generalize.run(generalize.GeneralizeInputs([box(0, 0, 20, 20)], "raw", say=said.extend),
                   generalize.GeneralizeConfig(methods=("douglas",)))
    assert [m.text for m in said] == ["Generalising 1 plots (douglas)..."]
    with pytest.raises(InputError, match="No area with a category in <empty>"):
        generalize.run(generalize.GeneralizeInputs([None], "empty"), generalize.GeneralizeConfig())
