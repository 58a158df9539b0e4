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
