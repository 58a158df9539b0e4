"""align.run: v.histo.align's sequence on made-up maps, the GRASS reads faked (no GRASS)."""

from dataclasses import replace

import pytest
from shapely.geometry import box

from reconstruction.align import AlignmentConfig, AlignmentInputs, run
from reconstruction.core.errors import InputError

PLOTS = [box(0, 0, 30, 12), box(40, 0, 70, 12)]
FOOTPRINTS = {1: box(1, 1, 10, 11), 2: box(41, 1, 50, 11), 3: box(12, 1, 20, 11),
              4: box(100, 100, 110, 110)}
TABLE = {"cat": [1, 2, 3, 4], "bouwjaar": [1850, 1870, 1950, None], "name": ["a", "b", "c", "d"],
         "plot": [0, 0, 0, 0]}
CONFIG = AlignmentConfig(year=1900, plots="plots", footprints="fp", output="al",
                         unmatched="un", report_file="r.json")


def inputs(table=TABLE, plots=PLOTS, counts=None, asked=None):
    def read_footprints(cats):
        if asked is not None:
            asked.extend(cats)
        return [FOOTPRINTS[c] for c in cats], list(cats)

    return AlignmentInputs(table, read_footprints, lambda: (plots, [10, 20][:len(plots)]),
                           lambda name: (counts or {}).get(name, {"areas": 3}))


def test_only_the_candidates_are_read_and_the_output_tables_made():
    asked = []
    result = run(inputs(asked=asked), CONFIG)
    assert asked == [1, 2]                    # 3 is too young, 4 has no year
    assert result.year_column == "bouwjaar" and result.plot_cats == [10, 20]
    out = result.output
    assert (out.name, out.cats, out.title) == (
        "al", [1, 2], "Footprints of <fp> standing on <plots> in 1900 (v.histo.align)")
    # the footprints' own columns, the old plot column replaced by the alignment's
    assert out.table == {"bouwjaar": [1850, 1870], "name": ["a", "b"], "plot": [10, 20],
                         "similarity": [1.0, 1.0]}
    assert result.unmatched.cats == [] and result.unmatched.title == (
        "Candidate footprints of <fp> matching no plot")
    assert result.report_json["options"]["year"] == 1900
    assert [row["aligned"] for row in result.report_json["plots"]] == [1, 1]
    assert result.alignment.report.candidates == 2


def test_no_unmatched_map_nor_report_unless_asked():
    result = run(inputs(), replace(CONFIG, unmatched="", report_file=""))
    assert result.unmatched is None and result.report_json is None


def test_the_offset_correction_adds_dx_dy():
    result = run(inputs(), replace(CONFIG, shift=3))
    assert set(result.output.table) >= {"dx", "dy"}


def test_the_3d_bag_column_is_the_fallback_of_the_default_only():
    table = {"cat": [1], "OorspronkelijkBouwjaar": [1850]}
    assert run(inputs(table), CONFIG).year_column == "OorspronkelijkBouwjaar"
    with pytest.raises(InputError, match=r"Footprints <fp> have no year column <jaar>; "
                                         r"columns: OorspronkelijkBouwjaar$"):
        run(inputs(table), replace(CONFIG, year_column="jaar", year_column_given=True))
    with pytest.raises(InputError, match=r"no year column <bouwjaar> \(nor "
                                         r"<oorspronkelijkbouwjaar>\); columns: none"):
        run(inputs({"cat": [1]}), CONFIG)


def test_maps_without_areas_are_refused_naming_the_option():
    counts = {"fp": {"points": 1}, "plots": {"lines": 2}}
    table = {"cat": [1], "bouwjaar": [1950]}        # no candidate: nothing read
    with pytest.raises(InputError, match=r"Vector map <fp> given as footprints= has no areas "
                                         r"\(it holds 1 points, 0 lines, 0 boundaries, 0 "
                                         r"areas\): footprints must be areas"):
        run(inputs(table, counts=counts), CONFIG)
    with pytest.raises(InputError, match=r"<plots> given as input= has no areas \(it holds 0 "
                                         r"points, 2 lines"):
        run(inputs(plots=[], counts=counts), CONFIG)


def test_the_result_holds_the_boxes_of_the_candidates_and_of_the_plots():
    """For the warning when they do not meet (issue 33, item 7)."""
    result = run(inputs(), CONFIG)
    fp, plots = result.footprints_extent, result.plots_extent
    assert (fp.x0, fp.y0, fp.x1, fp.y1) == (1, 1, 50, 11)      # candidates 1 and 2 only
    assert (plots.x0, plots.y0, plots.x1, plots.y1) == (0, 0, 70, 12)
