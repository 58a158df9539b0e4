"""The plots a map's drawn outlines close (reconstruction.generalize.drawn), pure."""

import numpy as np

from reconstruction.generalize import drawn


def _two_blocks():
    """Paper with two blocks outlined 3 cells wide, a street 12 cells wide
    between them, and a number written in the street (short ink)."""
    rgb = np.full((80, 120, 3), 235, np.uint8)
    for c0, c1 in ((10, 54), (66, 110)):
        rgb[10:70, c0:c1] = 40
        rgb[13:67, c0 + 3:c1 - 3] = 235
    rgb[38:42, 58:62] = 40           # a number written in the street
    return rgb


def test_the_lines_decide_where_a_plot_ends_the_classification_which_regions_are_built():
    rgb = _two_blocks()
    building = np.zeros(rgb.shape[:2], bool)
    building[10:70, 10:110] = True   # the street between the blocks classified building ...
    building[:, 54:66] = False
    building[30:50, 54:66] = True    # ... where it crosses (a third of the street)
    found = drawn.drawn_plots(rgb, (0, 120, 0, 80), building, stroke=3, min_area=100)
    assert len(found.polygons) == 2 and found.built == 2
    # each plot is its block out to the middle of the outline
    areas = sorted(p.area for p in found.polygons)
    assert all(abs(a - 41 * 57) < 0.05 * 41 * 57 for a in areas), areas


def test_a_region_the_classification_splits_keeps_its_cells_as_classified():
    """A map that draws no outline between its blocks and streets: plain paper,
    buildings filled (lighter than ink) -- one region, a third of it built.
    The plots are the classified cells, not the whole region nor nothing."""
    rgb = np.full((80, 120, 3), 235, np.uint8)
    building = np.zeros(rgb.shape[:2], bool)
    for c0, c1 in ((10, 50), (70, 110)):
        rgb[20:60, c0:c1] = (230, 120, 120)
        building[20:60, c0:c1] = True
    found = drawn.drawn_plots(rgb, (0, 120, 0, 80), building, stroke=3, min_area=100)
    assert found.built == 0 and len(found.polygons) == 2
    assert sorted(round(p.area) for p in found.polygons) == [1600, 1600]


def test_a_region_mostly_unclassified_is_no_plot_and_small_regions_never_are():
    rgb = _two_blocks()
    building = np.zeros(rgb.shape[:2], bool)
    building[13:67, 13:51] = True    # the first block
    building[13:20, 69:107] = True   # an eighth of the second
    found = drawn.drawn_plots(rgb, (0, 120, 0, 80), building, stroke=3, min_area=100)
    assert len(found.polygons) == 1 and found.polygons[0].bounds[2] < 60
    line = np.zeros((20, 20), bool)
    line[:, 10] = True
    mask, regions, built = drawn.built_cells(line, np.ones((20, 20), bool), min_cells=250)
    assert (regions, built) == (0, 0) and not mask.any()
