"""The fit step (reconstruction.generalize.fitting): plot edges moved onto the
boundary line a map draws, on maps drawn here at sub-cell precision."""

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st
from shapely import affinity
from shapely.geometry import box

from reconstruction.generalize import fitting
from reconstruction.generalize import operators as generalization
from reconstruction.geom.grid import MapImage

PAPER = (238, 231, 212)
FILL = (236, 183, 166)
STROKE = (176, 100, 92)
INK = (30, 27, 30)
SIZE = 60          # cells a side, 1 m each
SUB = 6            # sub-cells a side per cell


def draw(plots, outline, stroke=0.9, seed=0, noise=4.0, ink=()):
    """A scanned map of ``plots`` on a SIZE x SIZE grid of 1 m cells, origin
    (0, 0): pink fill, a darker outline stroke ``stroke`` wide on the plot's
    boundary line's centre (``outline="centre"``) or inside the plot
    (``"inside"``), black ``ink`` (text) over it, each cell the mean of its
    SUB x SUB sub-cells, plus noise."""
    n = SIZE * SUB
    xs = (np.arange(n) + 0.5) / SUB
    gx, gy = np.meshgrid(xs, SIZE - xs)
    colours = np.empty((n, n, 3))
    colours[:] = PAPER
    for plot in plots:
        lines = (plot.difference(plot.buffer(-stroke, join_style="mitre")) if outline == "inside"
                 else plot.boundary.buffer(stroke / 2.0, cap_style="flat", join_style="mitre"))
        colours[shapely.contains_xy(plot, gx, gy)] = FILL
        colours[shapely.contains_xy(lines, gx, gy)] = STROKE
    for geometry in ink:
        colours[shapely.contains_xy(geometry, gx, gy)] = INK
    rgb = colours.reshape(SIZE, SUB, SIZE, SUB, 3).mean(axis=(1, 3))
    rgb += np.random.default_rng(seed).normal(0, noise, rgb.shape)
    return MapImage(np.clip(np.rint(rgb), 0, 255).astype(np.uint8), (0.0, SIZE, 0.0, SIZE))


def iou(a, b):
    return shapely.intersection(a, b).area / shapely.union(a, b).area


@pytest.mark.parametrize("outline", fitting.OUTLINES)
@pytest.mark.parametrize("grow", [0.3, -0.5])
def test_edges_move_onto_the_drawn_line(outline, grow):
    truth = box(10.37, 12.81, 41.52, 30.26)
    image = draw([truth], outline)
    plot = truth.buffer(grow, join_style="mitre")
    fit = fitting.fit_outlines([plot], image, outline, stroke=0.9)
    fitted = fit.plots[0]
    assert fit.edges == fit.fitted == 4
    assert shapely.hausdorff_distance(fitted, truth) < 0.2
    assert iou(fitted, truth) > 0.975 > iou(plot, truth)
    assert fit.stroke_width == (0.9 if outline == "inside" else None)


@pytest.mark.parametrize("stroke", [1.2, 1.6])
def test_the_stroke_width_is_measured_on_the_map(stroke):
    """A stroke wider than a cell shows its full colour: its width is the
    area under the profile's bump over that colour's contrast."""
    truth = [box(8.4, 8.6, 28.9, 50.3), box(33.2, 10.1, 52.7, 51.4)]
    fit = fitting.fit_outlines(truth, draw(truth, "inside", stroke=stroke), "inside")
    assert fit.stroke_width == pytest.approx(stroke, rel=0.15)
    assert all(shapely.hausdorff_distance(p, t) < 0.3 for p, t in zip(fit.plots, truth))


def test_a_wrong_angle_is_fitted_and_the_corners_meet_again():
    """A tilted edge gets its slope from the map; the corners are where the
    fitted lines meet, so a tip cut short by the cells grows back."""
    truth = shapely.Polygon([(8.3, 10.2), (50.6, 16.4), (8.3, 30.7)])
    image = draw([truth], "centre")
    plot = shapely.Polygon([(8.9, 10.9), (45.0, 17.4), (8.9, 29.6)])
    fitted = fitting.fit_outlines([plot], image, "centre").plots[0]
    assert shapely.hausdorff_distance(fitted, truth) < 0.6 < shapely.hausdorff_distance(plot, truth)
    assert iou(fitted, truth) > 0.97 > iou(plot, truth)


def test_courtyard_edges_move_outwards_from_the_plot():
    truth = box(10.4, 10.2, 50.3, 49.6).difference(box(22.1, 21.7, 37.8, 38.3))
    image = draw([truth], "inside")
    plot = shapely.orient_polygons(truth.buffer(0.5, join_style="mitre"))
    fitted = fitting.fit_outlines([plot], image, "inside", stroke=0.9).plots[0]
    assert len(fitted.interiors) == 1
    assert shapely.hausdorff_distance(fitted, truth) < 0.3
    assert iou(fitted, truth) > 0.98 > iou(plot, truth)


def test_no_line_no_move():
    """On a blank map, or for edges too short to fit, the plot stays as it was."""
    blank = MapImage(np.full((SIZE, SIZE, 3), 230, dtype=np.uint8), (0.0, SIZE, 0.0, SIZE))
    plot = box(10.5, 10.5, 30.5, 25.5)
    fit = fitting.fit_outlines([plot], blank, "inside")
    assert fit.fitted == 0 and fit.stroke_width is None
    assert shapely.equals_exact(fit.plots[0].normalize(), plot.normalize(), 1e-9)
    tiny = box(10.2, 10.2, 11.4, 11.4)
    fit = fitting.fit_outlines([tiny], draw([tiny], "centre"), "centre")
    assert fit.edges == 0 and fit.plots[0] is tiny


def test_a_line_beyond_reach_is_not_taken():
    """The stroke of a plot across a street (farther than REACH cells) does
    not pull the edge over; the edge stays or goes to its own line."""
    truth, other = box(10.3, 10.3, 30.3, 40.3), box(33.8, 10.3, 50.3, 40.3)
    image = draw([truth, other], "inside")
    plot = truth.buffer(0.4, join_style="mitre")
    fitted = fitting.fit_outlines([plot], image, "inside", stroke=0.9).plots[0]
    assert fitted.bounds[2] < 30.7
    assert iou(fitted, truth) > 0.97


@pytest.mark.parametrize("gap", [0.9, 1.8])
def test_text_beside_an_edge_is_not_taken_for_the_stroke(gap):
    """A street name printed along a plot's edge, ``gap`` beyond it, is a
    darker line than the stroke (the fit took it without the check): on a map
    that draws the outline inside the plots a line must have the stroke's
    colour, so the edge stays on its stroke."""
    truth = box(10.3, 10.3, 45.3, 30.3)
    letters = box(12.0, 30.3 + gap, 43.0, 31.4 + gap)  # strokes 1.1 m thick
    image = draw([truth], "inside", ink=[letters])
    fit = fitting.fit_outlines([truth], image, "inside", stroke=0.9)
    assert abs(fit.plots[0].bounds[3] - truth.bounds[3]) < 0.2
    assert iou(fit.plots[0], truth) > 0.98


def test_inside_outlines_are_fitted_wherever_the_line_lies_within_a_cell():
    """The flanks' midpoint is off by up to a fifth of a cell as the stroke's
    place within a cell goes; the model of the drawing, averaged over the
    cells, is not: noise-free rectangles at ten sub-cell places, straight and
    turned 17 degrees, each within 0.12 m."""
    worst = 0.0
    for k, phase in enumerate(np.linspace(0.0, 0.9, 10)):
        for angle in (0, 17):
            truth = affinity.rotate(box(10 + phase, 12 + 0.7 * phase, 40 + 0.3 * phase,
                                        35 + 0.9 * phase), angle, origin=(30, 30))
            image = draw([truth], "inside", noise=0.0, seed=k)
            fitted = fitting.fit_outlines([truth.buffer(0.3, join_style="mitre")], image,
                                          "inside", stroke=0.9).plots[0]
            worst = max(worst, shapely.hausdorff_distance(fitted, truth))
    assert worst < 0.12


def test_outline_support_is_the_share_of_the_outline_on_the_drawn_line():
    truth = box(10.4, 12.3, 31.7, 30.6)
    image = draw([truth], "inside")
    turned = affinity.rotate(truth, 9, origin="centroid")
    on, off = fitting.outline_support([truth, turned], image, "inside", stroke=0.9)
    assert on > 0.8 > 0.4 > off
    assert fitting.outline_support([box(40.2, 40.2, 41.0, 41.0)], image, "inside")[0] == 0.0


def test_a_turned_plot_takes_its_cells_outline_where_the_map_draws_that():
    """A generalisation gone astray (turned 15 degrees, as buffered lines may
    turn a small plot of ragged cells; the fit cannot turn it back) is
    replaced by the fitted outline of its cells, which the map draws its line
    along; a right one is kept."""
    truth = [box(10.4, 12.3, 31.7, 30.6), box(36.2, 35.3, 52.6, 50.8)]
    image = draw(truth, "inside", seed=5)
    cells = [box(*np.round(t.bounds)) for t in truth]
    fitted = fitting.fit_outlines([affinity.rotate(truth[0], 15, origin="centroid"), truth[1]],
                                  image, "inside", stroke=0.9).plots
    better = dict(generalization._better_supported(fitted, cells, image, 0.9, 1.0))
    assert list(better) == [0]
    assert iou(better[0], truth[0]) > 0.97 > 0.9 > iou(fitted[0], truth[0])


def test_no_alternative_outline_where_the_cells_outline_breaks():
    """Cells whose simplified outline breaks (a sliver simplified away) offer
    no alternative, even for a plot the map supports nowhere."""
    image = draw([box(10.4, 12.3, 31.7, 30.6)], "inside")
    sliver = shapely.Polygon([(40.0, 40.0), (40.6, 40.0), (40.0, 40.6)])
    assert generalization.douglas(sliver, 1.0) is None
    assert list(generalization._better_supported([box(40, 40, 46, 46)], [sliver], image,
                                                 0.9, 1.0)) == []


def test_a_cut_corner_is_restored_where_its_neighbours_are_drawn():
    ring = np.array([(0.0, 0.0), (10.0, 0.0), (10.0, 7.0), (7.0, 10.0), (0.0, 10.0)])
    restored = fitting.restore_corners(ring, np.array([1.0, 0.9, 0.0, 0.8, 1.0]))
    assert shapely.Polygon(restored).equals(box(0, 0, 10, 10))
    # a corner the map draws cut (a line along it), or whose neighbours it does
    # not draw, stays
    for shares in ([1.0, 0.9, 0.7, 0.8, 1.0], [1.0, 0.3, 0.0, 0.8, 1.0]):
        assert fitting.restore_corners(ring, np.array(shares)) is ring


def test_a_courtyard_corner_cut_by_the_generalisation_comes_back():
    """The inner corner of a courtyard, cut off by the generalisation where
    the map draws none, is restored: the edges either side of it meet."""
    truth = box(10.4, 10.2, 50.3, 49.6).difference(box(22.1, 21.7, 37.8, 38.3))
    image = draw([truth], "inside", seed=2)
    cut = box(10.4, 10.2, 50.3, 49.6).difference(shapely.Polygon(
        [(22.1, 21.7), (37.8, 21.7), (37.8, 33.3), (32.8, 38.3), (22.1, 38.3)]))
    fitted = fitting.fit_outlines([cut], image, "inside", stroke=0.9).plots
    restored = dict(generalization._corners_restored(fitted, image, 0.9))
    assert list(restored) == [0]
    assert iou(restored[0], truth) > 0.99 > iou(fitted[0], truth)
    assert len(restored[0].interiors[0].coords) == 5


def test_fit_step_in_the_chain():
    truth = [box(10.4, 10.6, 28.9, 24.3), box(33.2, 30.1, 52.7, 51.4)]
    image = draw(truth, "inside", seed=3)
    cells = [box(round(p.bounds[0]), round(p.bounds[1]), round(p.bounds[2]),
                 round(p.bounds[3])) for p in truth]
    result = generalization.generalize_plots(cells, ("douglas", "fit"), image=image,
                                             outline="inside", stroke=0.9)
    assert [name for name, _ in result.steps] == ["raw", "douglas", "fit"]
    assert result.methods == ["douglas+fit"] * 2
    assert result.outline_fit.fitted == result.outline_fit.edges == 8
    # the fit's error is about a sixth of a cell, as a line's place within a
    # cell goes (0.12 m rms on these maps): on 1 m cells IoU 0.97-0.98 here
    assert all(iou(p, t) > iou(c, t) + 0.02 and shapely.hausdorff_distance(p, t) < 0.3
               for p, t, c in zip(result.plots, truth, cells))
    with pytest.raises(ValueError, match="scanned map"):
        generalization.generalize_plots(cells, ("fit",))


@settings(deadline=None)
@given(x=st.floats(8, 12), y=st.floats(8, 12), width=st.floats(12, 30),
       height=st.floats(12, 30), angle=st.floats(-40, 40), grow=st.floats(-0.5, 0.5),
       outline=st.sampled_from(fitting.OUTLINES))
def test_property_fitted_outline_lies_on_the_drawn_plot(x, y, width, height, angle, grow,
                                                        outline):
    """Any rectangle at any sub-cell position and angle, its cells' outline up
    to half a cell off: the fitted outline lies within 0.4 m of the drawn plot
    (the line's centre is found to about a tenth of a cell, depending on
    where it falls in the cells; a corner also takes the slope's error)."""
    truth = affinity.rotate(box(x, y, x + width, y + height), angle, origin=(30, 30))
    # (GEOS buffers by a denormal distance to nothing)
    plot = truth.buffer(grow, join_style="mitre") if abs(grow) > 1e-6 else truth
    fitted = fitting.fit_outlines([plot], draw([truth], outline), outline, stroke=0.9).plots[0]
    assert fitted.is_valid
    assert shapely.hausdorff_distance(fitted, truth) < 0.4
