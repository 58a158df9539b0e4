"""v.histo.align's messages (report) for made-up results, without GRASS."""

import numpy as np

from reconstruction.align import (Alignment, AlignmentConfig, AlignmentResult, FootprintMap,
                                  report, shell_counts)
from reconstruction.align.stage import AlignmentReport, PlotShifts
from reconstruction.core.messages import Message

CONFIG = AlignmentConfig(year=1900, footprints="fp", plots="plots", output="al",
                         year_text="1900")


def result(shifted=None, **counts):
    base = dict(footprints=10, candidates=6, aligned=4, unmatched=2, plots=5, plots_matched=3)
    base.update(counts)
    empty = np.array([], dtype=int)
    shifts = None
    if shifted is not None:
        shifts = PlotShifts(np.zeros(5), np.zeros(5), np.ones(5), np.zeros(5, dtype=bool))
        base["shifted_plots"] = shifted
    alignment = Alignment(empty, empty, np.array([]), empty, np.array([]), shifts,
                          AlignmentReport(**base))
    out = FootprintMap("al", [], [], {}, "title")
    return AlignmentResult(alignment, "bouwjaar", [1, 2, 3, 4, 5], out, None, None, (2.0, 5.5))


SUMMARY = Message("4 of 6 candidate footprints (built before 1900) aligned with 3 of 5 plots "
                  "into <al>", "message")


def test_a_clean_run_gives_the_summary_only():
    assert report(result(), CONFIG) == [SUMMARY]


def test_the_warnings_appear_when_their_condition_holds():
    got = report(result(without_year=3, repaired=2), CONFIG)
    assert got == [
        Message("3 of 10 footprints have no year in <bouwjaar> (NULL, empty or a placeholder "
                "such as 9999) and were left out", "warning"),
        Message("2 invalid geometries repaired", "warning"),
        SUMMARY]


def test_no_candidate_warns():
    got = report(result(candidates=0, aligned=0, unmatched=0, plots_matched=0), CONFIG)
    assert got[0] == Message("No footprint of <fp> was built before 1900", "warning")
    assert got[1].text.startswith("0 of 0 candidate footprints (built before 1900)")
    assert [m.level for m in got] == ["warning", "message"]


def test_the_offset_correction_counts_the_shifted_plots():
    got = report(result(shifted=2), CONFIG)
    assert got == [Message(SUMMARY.text + "; 2 plots matched at a shifted place", "message")]


def test_the_timing_is_a_verbose_line_when_the_times_are_given():
    got = report(result(), CONFIG, started=1.0, finished=6.25)
    assert got == [Message("Timing (s): read 1.00, align 3.50, write 0.75", "verbose"), SUMMARY]


def test_the_shell_counts_are_every_count_in_order():
    assert shell_counts(result()) == [
        "footprints=10", "without_year=0", "after_year=0", "candidates=6", "aligned=4",
        "contested=0", "unmatched=2", "plots=5", "plots_matched=3", "shifted_plots=0",
        "repaired=0"]


def test_no_candidate_aligned_far_from_the_plots_warns_with_both_boxes():
    """Footprints 100 km from the plots ended with an empty map and no word
    (issue 33, item 7)."""
    from dataclasses import replace

    from reconstruction.geom.grid import Extent

    far = replace(result(aligned=0, unmatched=6, plots_matched=0),
                  footprints_extent=Extent(185000, 446000, 185300, 446200),
                  plots_extent=Extent(85000, 446000, 85300, 446200))
    got = report(far, CONFIG)
    assert got[0] == Message(
        "The 6 candidate footprints of <fp> (x 185000..185300, y 446000..446200) do not "
        "overlap the plots of <plots> (x 85000..85300, y 446000..446200): nothing aligned, "
        "<al> is empty. Are they of another region or reference system?", "warning")
    assert [m.level for m in got] == ["warning", "message"]


def test_no_candidate_aligned_on_the_plots_warns_with_the_best_similarity():
    from dataclasses import replace

    from reconstruction.geom.grid import Extent

    near = result(aligned=0, unmatched=6, plots_matched=0)
    near = replace(near, footprints_extent=Extent(85005, 446000, 85300, 446200),
                   plots_extent=Extent(85000, 446000, 85300, 446200),
                   alignment=replace(near.alignment, best_similarity=np.array([0.2, 0.45])))
    assert report(near, CONFIG)[0] == Message(
        "None of the 6 candidate footprints of <fp> aligned with a plot of <plots> (best "
        "similarity 0.45, overlap= asks 0.6): <al> is empty", "warning")
