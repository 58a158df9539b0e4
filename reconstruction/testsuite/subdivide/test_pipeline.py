"""subdivide.run and its inputs: v.histo.subdivide's sequence on made-up maps (no GRASS)."""

import pytest
from shapely.geometry import box

from reconstruction.core.errors import InputError
from reconstruction.subdivide import (SubdivisionConfig, plots_with_category, read_inputs,
                                      run)

CONFIG = SubdivisionConfig(plots="plots", output="fp", aligned="al", area_threshold=100.0)


def test_plots_without_area_or_category_are_left_out():
    geoms = [box(0, 0, 10, 10), None, box(20, 0, 30, 10)]
    assert plots_with_category(geoms, {"cat": [3, 4, None]}, "p") == ([geoms[0]], [3])
    with pytest.raises(InputError, match=r"^Vector map <p> has no areas with a category$"):
        plots_with_category([None], {"cat": [1]}, "p")


def test_the_plot_column_of_the_aligned_footprints():
    plots, cats = [box(0, 0, 10, 10)], [7]
    inputs = read_inputs(plots, cats, [box(1, 1, 4, 4)], {"cat": [1], "PLOT": ["7"]}, CONFIG)
    assert inputs.aligned_plots == [7] and not inputs.plot_column_missing
    missing = read_inputs(plots, cats, [box(1, 1, 4, 4)], {"cat": [1]}, CONFIG)
    assert missing.aligned_plots is None and missing.plot_column_missing
    with pytest.raises(InputError, match=r"Column <plot> of vector map <al> must hold whole"):
        read_inputs(plots, cats, [box(1, 1, 4, 4)], {"cat": [1], "plot": [1.5]}, CONFIG)
    alone = read_inputs(plots, cats, None, {}, CONFIG)
    assert alone.aligned is None and not alone.plot_column_missing


def test_run_gives_the_footprints_and_their_table():
    plots, cats = [box(0, 0, 40, 14)], [7]
    aligned = [box(0, 0, 6, 12)]
    inputs = read_inputs(plots, cats, aligned, {"cat": [5], "plot": [7], "name": ["x"]}, CONFIG)
    result = run(inputs, CONFIG)
    sub = result.subdivision
    assert result.geometries is sub.geometries and len(sub.geometries) > 1
    assert result.table["plot"] == sub.plot and result.table["pm_case"] == sub.case
    assert result.table["source"][0] == "aligned" and result.table["pm_case"][0] == 0
    # the aligned footprints' own columns, NULL for the generated ones
    assert result.table["name"] == ["x"] + [None] * (len(sub.geometries) - 1)
    assert "cat" not in result.table
    assert result.clock[0] <= result.clock[1]


def test_the_aligned_footprints_bag_ids_are_read_for_any_year():
    """With year= the aligned footprints keep their BAG ids as identities (issue 49,
    item 7: a year that is false as a number, 0, dropped them)."""
    import dataclasses

    plots, cats = [box(0, 0, 10, 10)], [1]
    columns = {"cat": [1], "plot": [1], "identificatie": ["0503100000000009"]}
    for year in (0, 1915):
        inputs = read_inputs(plots, cats, [box(1, 1, 4, 4)], columns,
                             dataclasses.replace(CONFIG, year=year))
        assert inputs.aligned_ids == ["0503100000000009"]
