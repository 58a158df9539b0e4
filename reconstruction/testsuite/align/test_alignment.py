"""One-to-many alignment of plots with current footprints, on made-up cases (no GRASS)."""

import json
import math

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st
from shapely import affinity
from shapely.geometry import Polygon, box

from reconstruction.align import stage as al
from reconstruction.core.errors import InputError

YEAR = 1900


def run(plots, footprints, years, cats=None, **kw):
    kw.setdefault("year", YEAR)
    cats = list(range(1, len(plots) + 1)) if cats is None else cats
    return al.align(plots, cats, footprints, al.construction_years(years), al.AlignmentConfig(**kw))


def aligned_to(result):
    """{footprint index: plot category} of the aligned footprints."""
    return dict(zip(result.aligned.tolist(), result.plot.tolist()))


# ---------------------------------------------------------------------------
# Years
# ---------------------------------------------------------------------------

def test_construction_years_read_numbers_and_text_and_drop_placeholders():
    years = al.construction_years([1850, "1650", " 1700 ", None, "", 0, -5, 9999, 3000, 1899.0],
                                  today=__import__("datetime").date(2026, 1, 1))
    assert years[:3].tolist() == [1850, 1650, 1700]
    assert np.isnan(years[3:9]).all()
    assert years[9] == 1899


def test_construction_years_refuse_text_that_is_no_number():
    with pytest.raises(InputError, match=r"Year column <bouwjaar> is not numeric: <onbekend> "
                                         r"\(footprint 12\)"):
        al.construction_years([1850, "onbekend"], "bouwjaar", ids=[11, 12])


def test_a_footprint_built_in_or_after_the_map_year_is_never_aligned():
    plot = box(0, 0, 30, 12)
    footprints = [box(1, 1, 8, 10), box(10, 1, 18, 10), box(20, 1, 28, 10)]
    result = run([plot], footprints, [1850, YEAR, 1960])
    assert aligned_to(result) == {0: 1}
    assert result.report.after_year == 2 and result.report.candidates == 1
    assert result.unmatched.tolist() == []
    # the thesis's rule (year <= map year) takes the one of the map's year too
    assert aligned_to(run([plot], footprints, [1850, YEAR, 1960], include_year=True)) == {
        0: 1, 1: 1}


def test_footprints_without_a_year_are_counted_and_left_out():
    plot = box(0, 0, 30, 12)
    footprints = [box(1, 1, 8, 10), box(10, 1, 18, 10), box(20, 1, 28, 10)]
    result = run([plot], footprints, [None, 9999, ""])
    assert result.report.without_year == 3 and result.report.candidates == 0
    assert len(result.aligned) == 0


# ---------------------------------------------------------------------------
# Matching
# ---------------------------------------------------------------------------

def test_similarity_is_the_share_of_the_smaller_inside_the_buffered_plot():
    plot = box(0, 0, 20, 10)
    inside = box(2, 2, 8, 8)                   # wholly inside: 1
    half = box(15, 2, 35, 8)                   # 20 x 6, buffer 2: x up to 22 -> 7 of 20
    result = run([plot], [inside, half], [1800, 1800], buffer=2, overlap=0.3)
    assert aligned_to(result) == {0: 1, 1: 1}
    assert result.similarity.tolist() == pytest.approx([1.0, 7 / 20], abs=1e-3)
    # a footprint larger than the buffered plot: the plot's area is the smaller one
    small = box(0, 0, 4, 4)
    huge = box(-10, -10, 30, 30)
    result = run([small], [huge], [1800], buffer=1)
    assert result.similarity.tolist() == pytest.approx([1.0], abs=1e-9)


def test_a_footprint_straddling_two_plots_goes_to_the_better_one():
    a, b = box(0, 0, 40, 12), box(0, 20, 40, 32)
    # over the street between them: 6 m in a, the 8 m street, 3 m in b
    straddling = box(10, 6, 18, 23)
    # buffer 10: wholly inside both buffered plots (equal similarity 1), more of it in a
    result = run([a, b], [straddling], [1800], cats=[7, 9])
    assert aligned_to(result) == {0: 7}
    assert result.report.contested == 1
    # buffer 4: it reaches 14 m into a's buffer and only 7 m into b's
    result = run([a, b], [straddling], [1800], cats=[7, 9], buffer=4, overlap=0.3)
    assert aligned_to(result) == {0: 7}
    assert result.similarity[0] == pytest.approx(min(17, 12 + 4 - 6) / 17, abs=1e-3)


def test_a_footprint_outside_every_buffer_is_unmatched():
    plot = box(0, 0, 30, 12)
    far = box(60, 0, 70, 10)                   # 30 m away
    near = box(33, 2, 40, 10)                  # 3 m away, 2 of its 7 m inside buffer 5
    result = run([plot], [far, near], [1800, 1800], buffer=5)
    assert aligned_to(result) == {}
    assert result.unmatched.tolist() == [0, 1]
    assert result.best_similarity.tolist() == pytest.approx([0.0, 2 / 7], abs=1e-3)


def test_the_buffer_from_the_two_resolutions_is_applied():
    buffer = al.buffer_from_resolution([0.9, 0.3], 3)
    assert buffer == pytest.approx(3 * math.hypot(0.9, 0.3))    # 2.85
    plot = box(0, 0, 30, 12)
    beside = box(32, 2, 34.5, 10)              # 2 to 4.5 m away: inside 2.85 for 0.85 of 2.5
    result = run([plot], [beside], [1800], buffer=buffer, overlap=0.3)
    assert result.similarity.tolist() == pytest.approx([0.85 / 2.5], abs=2e-3)
    assert aligned_to(run([plot], [beside], [1800], buffer=al.buffer_from_resolution(
        [0.9, 0.3], 6))) == {0: 1}              # 5.7 m: wholly inside
    with pytest.raises(InputError, match="two positive pixel sizes"):
        al.buffer_from_resolution([0.9, 0], 3)
    with pytest.raises(InputError, match="factor k"):
        al.buffer_from_resolution([0.9, 0.3], -1)


@pytest.mark.parametrize("kw, message", [
    ({"buffer": 0}, "buffer must be positive"),
    ({"buffer": -3}, "buffer must be positive"),
    ({"overlap": 0}, r"overlap threshold must be in \(0, 1\]"),
    ({"overlap": 1.2}, r"overlap threshold must be in \(0, 1\]"),
    ({"shift": -1}, "shift search radius"),
])
def test_bad_options_are_input_errors(kw, message):
    with pytest.raises(InputError, match=message):
        al.AlignmentConfig(year=YEAR, **kw)


def test_invalid_and_missing_geometries_are_repaired_or_skipped():
    bow_tie = Polygon([(0, 0), (10, 10), (10, 0), (0, 10)])
    plot = box(-2, -2, 12, 12)
    result = run([plot, None], [bow_tie, None, box(1, 1, 3, 3)], [1800, 1800, 1800],
                 cats=[1, 2])
    assert sorted(aligned_to(result)) == [0, 2]
    assert result.report.repaired == 1 and result.report.plots == 1
    assert result.report.candidates == 2      # the missing one is no candidate


def test_counts_and_report():
    plots = [box(0, 0, 30, 12), box(0, 40, 30, 52), box(0, 80, 30, 92)]
    footprints = [box(1, 1, 8, 10), box(10, 1, 18, 10), box(1, 41, 8, 50), box(100, 0, 110, 8)]
    result = run(plots, footprints, [1800, 1950, 1700, 1800], cats=[3, 5, 8])
    counts = result.report.counts()
    assert counts["candidates"] == 3 and counts["aligned"] == 2 and counts["unmatched"] == 1
    assert counts["plots_matched"] == 2 and counts["plots"] == 3 and counts["after_year"] == 1
    report = al.report_json(result, al.AlignmentConfig(year=YEAR), [3, 5, 8])
    json.dumps(report)
    assert [row["aligned"] for row in report["plots"]] == [1, 1, 0]
    assert report["options"]["buffer"] == 10


# ---------------------------------------------------------------------------
# Offset correction
# ---------------------------------------------------------------------------

def city(rows=3, cols=4, seed=3):
    """Blocks (plots) separated by streets, with row houses along every street edge."""
    rng = np.random.default_rng(seed)
    plots, houses = [], []
    for r in range(rows):
        for c in range(cols):
            x0, y0 = c * 62.0, r * 44.0
            w, h = rng.uniform(40, 50), rng.uniform(26, 32)
            block = box(x0, y0, x0 + w, y0 + h)
            plots.append(block)
            band = block.difference(block.buffer(-10, join_style="mitre"))
            x = x0
            while x < x0 + w:
                step = rng.uniform(5, 9)
                for piece in shapely.get_parts(band.intersection(box(x, y0, x + step, y0 + h))):
                    if piece.area > 10:
                        houses.append(piece)
                x += step
    return plots, houses


def test_the_offset_correction_recovers_a_known_shift():
    plots, houses = city()
    years = [1800 if i % 5 else 1990 for i in range(len(houses))]   # a fifth are new
    moved = [affinity.translate(h, 5.3, -3.6) for h in houses]
    config = dict(buffer=2, overlap=0.9)
    baseline = run(plots, houses, years, **config)
    offset = run(plots, moved, years, **config)
    corrected = run(plots, moved, years, shift=10, **config)
    assert len(offset.aligned) < 0.7 * len(baseline.aligned)
    assert len(corrected.aligned) == len(baseline.aligned)
    assert aligned_to(corrected) == aligned_to(baseline)
    shifts = corrected.shifts
    assert shifts.applied.all() and corrected.report.shifted_plots == len(plots)
    assert np.hypot(shifts.dx + 5.3, shifts.dy - 3.6).max() < 0.5
    # without an offset nothing moves
    still = run(plots, houses, years, shift=10, **config)
    assert not still.shifts.applied.any() and aligned_to(still) == aligned_to(baseline)


def test_a_lone_estimate_off_a_flat_correlation_is_not_applied():
    # one small plot, a footprint well inside it: any shift up to 3 m fits as well
    result = run([box(0, 0, 20, 20)], [box(8, 8, 12, 12)], [1800], buffer=1, shift=5)
    assert not result.shifts.applied.any()
    assert result.shifts.dx.tolist() == [0.0]


def test_estimate_shifts_needs_footprints_and_plots():
    shifts = al.estimate_shifts([box(0, 0, 10, 10)], [], 5)
    assert not shifts.applied.any() and shifts.dx.tolist() == [0.0]


def test_peak_of_a_plateau_is_its_middle():
    corr = np.zeros((9, 9))
    corr[2:5, 3:8] = 100.0
    assert al._peak(corr) == pytest.approx((3.0, 5.0))
    corr = np.zeros((5, 5))
    corr[2, 1], corr[2, 2], corr[2, 3] = 50.0, 100.0, 99.0
    # the cells within 2 % of the top, weighted by how far above that floor (98) they are
    assert al._peak(corr) == pytest.approx((2.0, (2 * 2 + 3 * 1) / 3))


def test_fast_fft_lengths():
    assert [al._fast_length(n) for n in (1, 7, 97, 437, 1025)] == [1, 8, 100, 450, 1080]


# ---------------------------------------------------------------------------
# Invariants on random cases
# ---------------------------------------------------------------------------

boxes = st.tuples(st.floats(0, 100), st.floats(0, 100), st.floats(2, 30), st.floats(2, 30)).map(
    lambda t: box(t[0], t[1], t[0] + t[2], t[1] + t[3]))


@settings(max_examples=60, deadline=None)
@given(plots=st.lists(boxes, min_size=1, max_size=6),
       footprints=st.lists(st.tuples(boxes, st.sampled_from([1700, 1899, 1900, 1950, None])),
                           min_size=1, max_size=25),
       buffer=st.floats(0.5, 12), overlap=st.floats(0.05, 1.0))
def test_every_candidate_is_aligned_to_its_best_plot_or_unmatched(plots, footprints, buffer,
                                                                  overlap):
    geoms = [g for g, _ in footprints]
    years = [y for _, y in footprints]
    result = run(plots, geoms, years, buffer=buffer, overlap=overlap)
    candidates = {i for i, y in enumerate(years) if y is not None and y < YEAR}
    assert set(result.aligned.tolist()) | set(result.unmatched.tolist()) == candidates
    assert not set(result.aligned.tolist()) & set(result.unmatched.tolist())
    grown = [shapely.buffer(p, buffer) for p in plots]   # as align: 8 segments a quarter

    def similarity(b, a):
        return min(b.intersection(a).area / min(b.area, a.area), 1.0)

    for i, cat, sim in zip(result.aligned, result.plot, result.similarity):
        sims = [similarity(geoms[i], a) for a in grown]
        assert sim == pytest.approx(sims[cat - 1], abs=1e-9)
        assert sim >= overlap - 1e-9 and sim == pytest.approx(max(sims), abs=1e-8)
    for i, best in zip(result.unmatched, result.best_similarity):
        sims = [similarity(geoms[i], a) for a in grown]
        assert max(sims) < overlap + 1e-9 and best == pytest.approx(max(sims), abs=1e-9)
