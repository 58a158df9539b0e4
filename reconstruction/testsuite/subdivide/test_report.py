"""v.histo.subdivide's messages (announce, report) for made-up results, without GRASS."""

from dataclasses import replace

from shapely.geometry import box

from reconstruction.core.messages import Message
from reconstruction.subdivide import (Subdivision, SubdivisionConfig, SubdivisionInputs,
                                      SubdivisionResult, announce, report)
from reconstruction.subdivide.aligned_footprints import AlignedRepairs
from reconstruction.subdivide.plots import PlotRepairs
from reconstruction.subdivide.stage import SubdivisionReport

PLAIN = SubdivisionConfig(plots="plots", output="fp")
ALIGNED = replace(PLAIN, aligned="al")
CALIBRATING = replace(ALIGNED, calibrate=True)


def result(footprints=3, plots=None, aligned=None, **counts):
    fields = dict(length=(5.0, 8.0), depth=(12.0, 16.0), area_threshold=100.0,
                  footprints=footprints, generated=2)
    fields.update(counts)
    rep = SubdivisionReport(plots=plots or PlotRepairs(plots=2),
                            aligned=aligned or AlignedRepairs(), **fields)
    cases = [0, 2, 2, 4][:footprints]
    sub = Subdivision([box(0, 0, 1, 1)] * footprints, [1] * footprints, cases,
                      ["aligned"] + ["2pm"] * (footprints - 1), [0] + [-1] * (footprints - 1),
                      rep)
    return SubdivisionResult(sub, {}, (10.0, 12.5))


WRITTEN = Message("3 footprints written to <fp> (2 generated, 1 aligned); by case: 0: 1, 2: 2",
                  "message")


def test_announce_counts_the_plots_and_says_when_the_plot_column_is_missing():
    plots = [box(0, 0, 1, 1)] * 4
    assert announce(SubdivisionInputs(plots, [1, 2, 3, 4]), PLAIN) == [
        Message("Subdividing 4 plots...", "message")]
    missing = SubdivisionInputs(plots, [1, 2, 3, 4], [box(0, 0, 1, 1)], None, {}, True)
    assert announce(missing, ALIGNED) == [
        Message("Aligned map <al> has no plot column: each aligned footprint goes to the plot "
                "it overlaps most", "message"),
        Message("Subdividing 4 plots...", "message")]


def test_a_clean_run_gives_the_summary_only():
    assert report(result(), PLAIN) == [WRITTEN]
    assert report(result(), ALIGNED) == [WRITTEN]


def test_the_timing_is_a_verbose_line_when_the_times_are_given():
    assert report(result(), PLAIN, started=9.0, finished=13.75) == [
        Message("Timing (s): read 1.00, subdivide 2.50, write 1.25", "verbose"), WRITTEN]


def test_the_plot_repairs_warn():
    got = report(result(plots=PlotRepairs(plots=9, repaired=2, skipped=1, overlapping_pairs=3,
                                          overlap_area=12.345)), PLAIN)
    assert got == [
        Message("2 invalid plots repaired (make_valid)", "warning"),
        Message("1 plots without area skipped", "warning"),
        Message("3 pairs of overlapping plots: the shared area (12.35 square map units) went "
                "to the larger plot of each pair", "warning"),
        WRITTEN]


def test_the_aligned_footprints_warnings_only_with_aligned_footprints():
    res = result(aligned=AlignedRepairs(aligned=5, repaired=1, clipped=2),
                 aligned_without_plot=3, generated_clipped=4, generated_dropped=0)
    expected = [
        Message("1 invalid aligned footprints repaired", "warning"),
        Message("2 aligned footprints overlapping earlier ones were clipped", "warning"),
        Message("3 aligned footprints without a plot left out", "warning"),
        Message("Generated footprints overlapping aligned ones: 4 clipped, 0 dropped",
                "message"),
        WRITTEN]
    assert report(res, ALIGNED) == expected
    assert report(res, PLAIN) == [WRITTEN]


def test_the_calibration():
    done = result(calibrated=True, calibration_samples=12, length=(4.5, 7.25),
                  depth=(10.0, 13.5))
    assert report(done, CALIBRATING)[0] == Message(
        "Calibrated from 12 aligned footprints: length=4.50,7.25 depth=10.00,13.50", "message")
    assert report(done, ALIGNED) == [WRITTEN]     # without -a: nothing about it
    few = result(calibration_samples=2)
    assert report(few, CALIBRATING)[0] == Message(
        "Too few aligned footprints on a street (2) to calibrate: length= and depth= kept",
        "warning")


def test_no_footprint_gives_the_warnings_but_no_summary():
    got = report(result(footprints=0, generated=0,
                        plots=PlotRepairs(plots=1, skipped=1)), PLAIN, 0.0, 1.0)
    assert got == [Message("1 plots without area skipped", "warning")]
