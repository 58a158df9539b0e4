"""Measured and given heights are bounded (issue 49, item 8): a ground of
-1,000 m, eaves of 1e9, a roof top below its eaves or eaves below the
ground are never built on nor lent to the neighbours; the footprints' own
columns and grounds outside the bounds stop with one error naming the
column (or input) and the feature."""

import numpy as np
import pytest
import shapely

from reconstruction.core.errors import InputError
from reconstruction.lod2 import heights
from reconstruction.lod2 import inputs as li
from reconstruction.lod2 import stage as lod2
from reconstruction.lod2.config import HeightConfig, Lod2Config
from reconstruction.lod2.report import height_messages
from reconstruction.geom.grid import Grid


def row(n, width=6.0, depth=12.0):
    return [shapely.box(i * width, 0.0, (i + 1) * width, depth) for i in range(n)]


def thesis_columns(ground, eaves, top):
    """The thesis's absolute percentile columns (None: NULL)."""
    return {"ground-0.2": list(ground), "roof-0.25": list(eaves), "roof-0.99": list(top)}


#: eight aligned footprints: 0-2 measured well (ground 1 m, eaves 9-11 m, roofs 4 m),
#: then a NULL, a ground of -1,000 m, eaves in millimetres, a roof top below the
#: eaves, and eaves below the ground
GROUND = [1.0, 1.0, 1.0, None, -1000.0, 1.0, 1.0, 1.0]
EAVES = [10.0, 11.0, 12.0, 10.0, 9.75, 10000.0, 11.0, -3.0]
TOP = [14.0, 15.0, 16.0, 14.0, 13.75, 14000.0, 7.0, 2.0]


def test_implausible_measured_heights_are_unknown_each_for_its_reason():
    m = heights.measured_heights(thesis_columns(GROUND, EAVES, TOP))
    assert m.known.tolist() == [True] * 3 + [False] * 5
    assert m.problem.tolist() == [None] * 3 + [heights.NULL, heights.GROUND_OUTSIDE,
                                               heights.TOO_TALL, heights.INVERTED,
                                               heights.NOT_ABOVE]
    assert m.problems() == {heights.NULL: 1, heights.GROUND_OUTSIDE: 1, heights.TOO_TALL: 1,
                            heights.INVERTED: 1, heights.NOT_ABOVE: 1}
    # a top within a centimetre below the eaves is a flat roof, not inverted
    flat = heights.measured_heights(thesis_columns([1.0], [10.0], [9.995]))
    assert flat.known.tolist() == [True] and flat.attic.tolist() == [0.0]
    # a ground 600 m from the others' (all plausible on their own)
    apart = heights.measured_heights(thesis_columns([1.0, 2.0, 3.0, 601.0],
                                                    [9.0, 10.0, 11.0, 610.0],
                                                    [13.0, 14.0, 15.0, 614.0]))
    assert apart.problem.tolist() == [None] * 3 + [heights.GROUND_APART]


def inferred(columns, n_aligned):
    """footprint_heights of a row of 4 + n_aligned footprints, the last n_aligned of
    which are the aligned ones with ``columns``: (result, the first four's intervals)."""
    fps = row(4 + n_aligned)
    opts = li.HeightOptions(aligned=li.AlignedFootprints(fps[4:], columns))
    r = li.footprint_heights(fps, {}, options=opts)
    return r, r.interval[:4]


def test_implausible_measured_heights_are_counted_apart_and_never_lent_to_neighbours():
    """Before, the ground of -1,000 m gave eaves of 1,008.75 m to its footprint and
    the neighbours' intervals reached up to them; every bad row was counted as
    "no measured heights (NULL)"."""
    good = thesis_columns(GROUND[:3], EAVES[:3], TOP[:3])
    _, clean = inferred(good, 3)
    r, got = inferred(thesis_columns(GROUND, EAVES, TOP), 8)
    assert np.array_equal(got, clean)
    assert np.nanmax(r.heights.eaves) < 12.0 and np.nanmax(r.interval) < 16.0
    assert r.report.aligned_measured == 3 and r.report.aligned_unmeasured == 1
    assert r.report.aligned_implausible == {heights.GROUND_OUTSIDE: 1, heights.TOO_TALL: 1,
                                            heights.INVERTED: 1, heights.NOT_ABOVE: 1}
    assert r.source[4:].tolist() == ["measured"] * 3 + ["neighbours"] * 5
    config = Lod2Config(heights=HeightConfig(aligned="al"))
    texts = [m.text for m in height_messages(r.report, config)]
    assert "1 aligned footprints have no measured heights (NULL)" in texts
    assert "1 aligned footprints have implausible measured heights (ground outside -450..8850 " \
        "m): not used, their heights inferred as for footprints without" in texts
    assert sum("implausible" in t for t in texts) == 4


def test_none_measured_says_why():
    cols = thesis_columns([None, -1000.0], [10.0, 9.0], [14.0, 13.0])
    opts = li.HeightOptions(aligned=li.AlignedFootprints(row(2), cols))
    with pytest.raises(InputError, match=r"None of the 2 aligned footprints has measured "
                                         r"heights \(1 NULL, 1 ground outside"):
        li.footprint_heights(row(2), {}, options=opts)


@pytest.mark.parametrize("column, values, message", [
    ("h_building", [9.0, 1e9, 10.0], r"^Column <h_building> \(eaves height\) of feature cat 12: "
                                     r"1e\+09 m is not a plausible eaves height \(at most 300 m\)"),
    ("h_attic", [3.0, 3.0, 4000.0], r"^Column <h_attic> \(roof height\) of feature cat 13: 4000 m"),
    ("h_building", [9.0, float("inf"), 10.0], r"of feature cat 12: inf m"),
    ("g", [1.0, -1000.0, 2.0], r"^Column <g> \(ground elevation\) of feature cat 12: -1000 m is "
                               r"not a plausible ground elevation \(-450 to 8850 m\)"),
])
def test_a_footprint_column_out_of_bounds_is_one_error_naming_column_and_feature(column, values,
                                                                               message):
    cols = {"cat": [11, 12, 13], "h_building": [9.0, 10.0, 11.0], "h_attic": [3.0, 3.0, 3.0],
            "g": [1.0, 1.0, 1.0]}
    cols[column] = values
    with pytest.raises(InputError, match=message):
        li.footprint_heights(row(3), cols, options=li.HeightOptions(ground_column="g"))
    with pytest.raises(InputError, match=message):
        lod2.heights_from_columns(cols, 3, "h_building", "h_attic", ground_column="g")


def test_negative_and_null_column_heights_keep_their_counted_meaning():
    # a zero or negative eaves height leaves the footprint out, a negative roof
    # height gives a flat roof, each with a warning and a count (not an error)
    cols = {"cat": [1, 2, 3], "h_building": [9.0, -2.0, None], "h_attic": [-1.0, 3.0, 3.0]}
    r = li.footprint_heights(row(3), cols)
    assert np.isnan(r.heights.eaves[2]) and r.heights.eaves[1] == -2.0


def test_a_dtm_no_data_value_read_as_ground_is_one_error():
    values = np.full((40, 40), 2.0)
    values[:, 12:17] = -9999.0             # under footprint 2 (x 6-12 m): no data
    dtm = Grid(values, north=30.0, west=-5.0, nsres=1.0, ewres=1.0)
    with pytest.raises(InputError, match=r"^The ground of footprint cat 2 from the elevation "
                                         r"raster is -9999 m, not a plausible ground .*no-data"):
        li.footprint_heights(row(3), {"cat": [1, 2, 3], "h_building": [9, 9, 9],
                                      "h_attic": [3, 3, 3]},
                             options=li.HeightOptions(elevation=dtm, ground_percentile=20))
