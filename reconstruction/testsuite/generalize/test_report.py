"""What v.histo.generalize prints after its run (reconstruction.generalize.report): no GRASS."""

from reconstruction.generalize.config import GeneralizeConfig
from reconstruction.generalize.report import report, shell_figures
from reconstruction.generalize.stage import (GeneralizedPlots, GeneralizeReport, PointScores,
                                             ShapeScores)


def _result(fallbacks=None, scores=True):
    points = PointScores(2 / 3, 1.0, 0.8, 4) if scores else None
    shapes = ShapeScores(3, 2, None, 94.93421, [], [], 0.61234, 0.9, [0.61234, None],
                         [0.9, None], {"raw": {"offset": 0.3, "iou": 0.95}}) if scores else None
    return GeneralizedPlots([], {}, GeneralizeReport(
        plots=3, raw_areas=4, dropped_small=1, methods={"alpha/regular+lines": 3},
        fallbacks=fallbacks or {}, steps=[], points=points, shapes=shapes))


def test_the_figures_in_one_message():
    assert [(m.level, m.text) for m in report(_result(), GeneralizeConfig())] == [
        ("message", "plots 3, raw_areas 4, dropped_small 1, precision 0.6667, recall 1.0, "
                    "f_score 0.8, gt_points 4, gt_polygons 3, matched 2, turning_distance None, "
                    "buffer_similarity 94.9342, outline_offset 0.6123, iou 0.9")]
    assert [m.text for m in report(_result(scores=False), GeneralizeConfig())] == [
        "plots 3, raw_areas 4, dropped_small 1"]


def test_a_warning_for_each_step_with_fallbacks_first():
    messages = report(_result({"alpha": 2, "lines": 1}), GeneralizeConfig())
    assert [(m.level, m.text) for m in messages[:2]] == [
        ("warning", "Step alpha: 2 plots needed a fallback method (see column 'method')"),
        ("warning", "Step lines: 1 plots needed a fallback method (see column 'method')")]
    assert len(messages) == 3 and messages[2].level == "message"


def test_shell_style_figures_on_standard_output_instead_of_the_message():
    shell = GeneralizeConfig(shell=True)
    assert report(_result(), shell) == []
    assert [m.level for m in report(_result({"alpha": 1}), shell)] == ["warning"]
    assert shell_figures(_result()) == [
        "plots=3", "raw_areas=4", "dropped_small=1", "precision=0.6666666666666666",
        "recall=1.0", "f_score=0.8", "gt_points=4", "gt_polygons=3", "matched=2",
        "turning_distance=", "buffer_similarity=94.93421", "outline_offset=0.61234", "iou=0.9"]
