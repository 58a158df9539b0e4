"""Edge cells of areas whose outline is drawn inside them (reconstruction.classify.outlines)."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from reconstruction.classify import outlines

PAPER, FILL, STROKE = (238.0, 231.0, 212.0), (236.0, 183.0, 166.0), (176.0, 100.0, 92.0)
SUB = 10  # sub-cells per cell side


def drawn_plots(rectangles, size=40, stroke=0.9):
    """Rectangular plots (x0, x1, y0, y1 in cell units) drawn as a map does: pale
    fill, a darker stroke ``stroke`` wide inside each edge, paper outside; each
    cell the mean of its sub-cells. Returns (bands, plot share of each cell,
    truth by cell centre)."""
    centres = (np.arange(size * SUB) + 0.5) / SUB
    x, y = np.meshgrid(centres, centres)
    c = np.arange(size) + 0.5
    cx, cy = np.meshgrid(c, c)
    inside, fill, truth = (np.zeros_like(x, dtype=bool), np.zeros_like(x, dtype=bool),
                           np.zeros_like(cx, dtype=bool))
    for x0, x1, y0, y1 in rectangles:
        inside |= (x > x0) & (x < x1) & (y > y0) & (y < y1)
        fill |= (x > x0 + stroke) & (x < x1 - stroke) & (y > y0 + stroke) & (y < y1 - stroke)
        truth |= (cx > x0) & (cx < x1) & (cy > y0) & (cy < y1)
    colour = np.where(fill[..., None], FILL, np.where(inside[..., None], STROKE, PAPER))
    bands = [colour[..., k].reshape(size, SUB, size, SUB).mean(axis=(1, 3)) for k in range(3)]
    share = inside.reshape(size, SUB, size, SUB).mean(axis=(1, 3))
    return bands, share, truth


def drawn_plot(x0, x1, y0, y1):
    return drawn_plots([(x0, x1, y0, y1)])


#: a plot whose edges lie near cell boundaries: the stroke nearly fills the cells
#: along them, and its colour is seen there
NEAR_CELL_EDGES = (26.05, 36.95, 26.1, 37.0)


@settings(max_examples=60, deadline=None)
@given(st.floats(3, 5), st.floats(16, 20), st.floats(3, 5), st.floats(16, 20))
def test_each_edge_cell_goes_to_the_side_that_covers_most_of_it(x0, x1, y0, y1):
    bands, share, truth = drawn_plots([(x0, x1, y0, y1), NEAR_CELL_EDGES])
    # as a classifier sees it: every cell the plot covers by a fifth looks like the fill
    classes = np.where(share > 0.2, 1, 2)
    out = outlines.inside_outlines(classes, bands, (1,))
    decided = np.abs(share - 0.5) > 0.05  # a cell half covered may go either way
    assert ((out == 1) == (share > 0.5))[decided].all()
    assert set(np.unique(out)) <= {1, 2}
    assert ((out == 1) != truth)[decided].sum() <= 8   # corner cells: share and centre differ


def test_the_plots_grown_by_their_edge_cells_shrink_back():
    bands, share, truth = drawn_plots([(3.7, 17.3, 4.65, 18.3), NEAR_CELL_EDGES])
    classes = np.where(share > 0.2, 1, 2)
    assert ((classes == 1) & ~truth).sum() >= 40      # what the classifier gives
    out = outlines.inside_outlines(classes, bands, (1,))
    assert ((out == 1) != truth).sum() == 0


def test_a_cell_classified_outside_joins_when_the_stroke_covers_most_of_it():
    bands, share, truth = drawn_plot(6.2, 21.8, 6.2, 21.8)
    classes = np.where(truth, 1, 2)
    classes[10:15, 6] = 2          # the stroke along the west edge missed (a colour fringe)
    out = outlines.inside_outlines(classes, bands, (1,))
    assert (out == np.where(truth, 1, 2)).all()


def test_no_data_and_other_classes_stay():
    bands, share, truth = drawn_plot(6.3, 21.3, 6.3, 21.3)
    classes = np.where(share > 0.2, 1, 2)
    classes[:, :3] = 3
    bands[0][:, 21:] = np.nan       # the east edge without data: kept as classified
    out = outlines.inside_outlines(classes, bands, (1,))
    assert (out[:, :3] == 3).all()
    assert (out[:, 21:] == classes[:, 21:]).all()
    assert (out[:, :21] != classes[:, :21]).any()


def test_stroke_share_is_the_colour_s_place_between_outside_and_stroke():
    stroke, outside = np.array([[100.0, 90.0, 80.0]]), np.array([[240.0, 230.0, 210.0]])
    colours = 0.3 * stroke + 0.7 * outside
    assert outlines.stroke_share(colours, stroke, outside) == pytest.approx([0.3])


def test_a_cell_between_two_areas_or_under_print_does_not_join_them():
    # two plots one cell apart, the cell between them dark (a letter's fringe)
    bands, share, truth = drawn_plots([(3.1, 10.0, 4.05, 8.0), (11.0, 18.0, 4.05, 8.0),
                                       (3.1, 10.0, 12.05, 15.0), NEAR_CELL_EDGES])
    classes = np.where(share > 0.5, 1, 2)
    for b, ink in zip(bands, (30.0, 27.0, 30.0)):
        b[5:7, 10] = ink
        b[15, 5:9] = ink
    classes[15, 5:9] = 2
    printed = np.zeros_like(classes, dtype=bool)
    printed[15:17, 5:9] = True           # a label printed beside the first plot
    out = outlines.inside_outlines(classes, bands, (1,), printed=printed)
    assert (out[:, 10] == 2).all()
    assert (out[15:17, 5:9] == classes[15:17, 5:9]).all()
    without = outlines.inside_outlines(classes, bands, (1,))
    assert (without[15, 5:9] == 1).all()  # the ink looks like the outline: it would join


def test_a_fill_cell_stays_when_the_classifier_stopped_short_of_the_stroke():
    # the stroke along every edge of a plot classified as the outside (a
    # colour plane off by a cell gives it the garden's colour): the fill
    # cells that are now the area's outermost keep it, the stroke joins it
    bands, share, truth = drawn_plots([(6.0, 22.0, 6.0, 22.0), NEAR_CELL_EDGES])
    classes = np.where(share > 0.2, 1, 2)
    classes[6, 6:22] = classes[21, 6:22] = classes[6:22, 6] = classes[6:22, 21] = 2
    assert (classes[:24, :24] == 1).sum() == 14 * 14
    out = outlines.inside_outlines(classes, bands, (1,))
    # all but the four corner cells, which touch the area only diagonally
    wrong = np.argwhere(out != np.where(truth, 1, 2))
    assert sorted(map(tuple, wrong)) == [(6, 6), (6, 21), (21, 6), (21, 21)]
    # bands not in register: by the stroke share alone, the fill cells leave
    plain = outlines.inside_outlines(classes, bands, (1,), unmix=False)
    assert (plain[7, 8:20] == 2).all()


def test_outside_share_unmixes_three_colours():
    outside, stroke, fill = np.array(PAPER), np.array(STROKE), np.array(FILL)
    colours = np.array([outside, stroke, fill, 0.5 * outside + 0.5 * stroke,
                        0.3 * outside + 0.2 * stroke + 0.5 * fill])
    n = len(colours)
    share = outlines.outside_share(colours, stroke[None], np.tile(outside, (n, 1)),
                                   np.tile(fill, (n, 1)))
    assert share == pytest.approx([1.0, 0.0, 0.0, 0.5, 0.3], abs=1e-9)
