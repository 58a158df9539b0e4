"""The polygons of a geometry: parts, the largest part, many geometries exploded (no GRASS)."""

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st
from shapely.geometry import GeometryCollection, LineString, MultiPolygon, Point, Polygon, box

from reconstruction.geom import polygons

NESTED = GeometryCollection([
    box(0, 0, 1, 1),
    LineString([(0, 0), (5, 5)]),
    GeometryCollection([Point(3, 3), MultiPolygon([box(2, 2, 4, 4), box(6, 6, 7, 7)])]),
    Polygon(),
])


def test_parts_of_one_geometry_depth_first_without_lines_points_or_empties():
    parts = polygons.polygon_parts(NESTED)
    assert [p.bounds for p in parts] == [(0, 0, 1, 1), (2, 2, 4, 4), (6, 6, 7, 7)]
    square = box(0, 0, 1, 1)
    assert polygons.polygon_parts(square)[0] is square
    assert polygons.polygon_parts(None) == []
    assert polygons.polygon_parts(Polygon()) == []
    assert polygons.polygon_parts(Point(0, 0)) == []


def test_parts_of_many_geometries_in_the_same_order_with_their_source():
    geometries = [None, box(10, 10, 11, 11), NESTED, LineString([(0, 0), (1, 1)])]
    parts, index = polygons.polygon_parts(geometries, return_index=True)
    assert list(index) == [1, 2, 2, 2]
    one_by_one = [p for g in geometries for p in polygons.polygon_parts(g)]
    assert [p.wkb for p in parts] == [p.wkb for p in one_by_one]


def test_largest_polygon_first_of_equals_and_none_without_area():
    assert polygons.largest_polygon(NESTED).bounds == (2, 2, 4, 4)
    twins = MultiPolygon([box(0, 0, 2, 2), box(5, 5, 7, 7)])
    assert polygons.largest_polygon(twins).bounds == (0, 0, 2, 2)
    assert polygons.largest_polygon(LineString([(0, 0), (1, 1)])) is None
    assert polygons.largest_polygon(None) is None


def test_explode_repairs_and_keeps_parts_with_area():
    bowtie = Polygon([(0, 0), (2, 2), (2, 0), (0, 2)])
    flat = Polygon([(0, 0), (1, 0), (2, 0)])
    parts, index = polygons.explode([MultiPolygon([box(0, 0, 1, 1), box(5, 5, 6, 6)]), None,
                                     bowtie, flat, NESTED])
    assert index == [0, 0, 2, 2, 4, 4, 4]
    assert all(p.is_valid and p.geom_type == "Polygon" and p.area > 0 for p in parts)
    assert sum(p.area for p in parts[2:4]) == np.float64(shapely.make_valid(bowtie).area)


def test_repair_gives_one_valid_geometry_per_input_and_tells_which_were_invalid():
    bowtie = Polygon([(0, 0), (2, 2), (2, 0), (0, 2)])
    two = MultiPolygon([box(0, 0, 1, 1), box(5, 5, 6, 6)])
    out, repaired = polygons.repair([box(0, 0, 1, 1), None, bowtie, Polygon(), two,
                                     LineString([(0, 0), (1, 1)])])
    assert list(repaired) == [False, False, True, False, False, False]
    assert out[0].equals(box(0, 0, 1, 1)) and out[1] is None and out[3] is None and out[5] is None
    assert out[2].is_valid and out[2].area == pytest.approx(2)
    assert out[4].geom_type == "MultiPolygon" and out[4].area == pytest.approx(2)


def test_the_same_outline_whatever_its_first_corner_and_turn():
    house = Polygon([(0, 0), (8, 0), (8, 6), (0, 6)])
    assert polygons.same_outline(house, Polygon([(8, 6), (0, 6), (0, 0), (8, 0)]))
    assert polygons.same_outline(house, Polygon([(0, 0), (0, 6), (8, 6), (8, 0)]))
    # a neighbour's vertex in a shared wall is no corner
    assert polygons.same_outline(house, Polygon([(0, 0), (5, 0), (8, 0), (8, 6), (0, 6)]))
    assert not polygons.same_outline(house, box(0, 0, 8, 6.01), 0.002)
    assert not polygons.same_outline(house, Polygon([(0, 0), (8, 0), (8, 6), (1, 6)]))
    yard = Polygon(house.exterior.coords, [box(2, 2, 3, 3).exterior.coords])
    assert polygons.same_outline(yard, Polygon(house.exterior.coords[::-1],
                                                [box(2, 2, 3, 3).exterior.coords[::-1]]))
    assert not polygons.same_outline(yard, house)
    assert not polygons.same_outline(yard, Polygon(house.exterior.coords,
                                                   [box(4, 2, 5, 3).exterior.coords]))


def test_the_same_outline_rounded_to_the_millimetre_with_a_wall_almost_north_south():
    # a footprint of the synthetic town and the same footprint read back from its
    # model (millimetres): its west wall's two ends lie 0.34 nm apart in x, so that
    # shapely.normalize starts one copy at its north-west corner and the other at its
    # south-west one; equals_exact then compares other corners
    drawn = Polygon([(84375.84, 446217.32), (84375.84, 446218.93), (84368.93, 446218.93),
                     (84368.56871, 446218.93), (84368.56871033768, 446212.62967790116),
                     (84375.84, 446212.76314524625)])
    rounded = Polygon([(84375.84, 446212.763), (84368.569, 446212.63), (84368.569, 446218.93),
                       (84375.84, 446218.93)])
    assert polygons.same_outline(drawn, rounded, 0.002)
    assert polygons.same_outline(rounded, drawn, 0.002)
    assert not polygons.same_outline(drawn, rounded, 0.0002)


@settings(max_examples=60, deadline=None)
@given(st.integers(3, 12), st.integers(0, 11), st.booleans(), st.floats(0, 2 * np.pi))
def test_a_convex_ring_is_the_same_outline_from_any_corner_either_way(n, start, turn, angle):
    t = angle + np.linspace(0, 2 * np.pi, n, endpoint=False)
    ring = np.column_stack([84000 + 10 * np.cos(t), 446000 + 6 * np.sin(t)])
    other = np.roll(ring, -(start % n), axis=0)
    if turn:
        other = other[::-1]
    assert polygons.same_outline(Polygon(ring), Polygon(other + 0.0005), 0.001)
    assert not polygons.same_outline(Polygon(ring), Polygon(other + 0.002), 0.001)


def _cells(shape, cell=1.0):
    """The outline of the raster cells (``cell`` wide) whose centres lie in ``shape``:
    the staircase r.to.vect makes of a classified patch."""
    x0, y0, x1, y1 = shape.bounds
    gi, gj = np.meshgrid(np.arange(np.floor(x0 / cell) - 1, np.ceil(x1 / cell) + 1),
                         np.arange(np.floor(y0 / cell) - 1, np.ceil(y1 / cell) + 1))
    inside = shapely.contains_xy(shape, (gi + 0.5) * cell, (gj + 0.5) * cell)
    i, j = gi[inside], gj[inside]
    # corners from whole cell numbers: neighbours share their edges exactly
    return polygons.largest_polygon(shapely.union_all(
        shapely.box(i * cell, j * cell, (i + 1) * cell, (j + 1) * cell)))


def test_the_cells_of_a_raster_outline_are_found_a_hand_drawn_plot_has_none():
    plot = shapely.affinity.rotate(box(0, 0, 40, 18), 23)
    assert polygons.stair_step([_cells(plot, 0.9)]) == pytest.approx(0.9)
    assert polygons.stair_step([plot, box(50, 0, 80, 30)]) is None
    assert polygons.stair_step([]) is None


@settings(max_examples=40, deadline=None)
@given(st.floats(15, 75), st.floats(0.5, 1.5), st.floats(20, 60), st.floats(8, 25))
def test_the_centre_line_of_a_plots_cells_lies_on_its_edges(angle, cell, length, depth):
    # a rotated rectangular plot classified on a grid: its cells' outline, a staircase,
    # has about the plot's area, but its convex hull (what an alpha shape of its points
    # draws) lies outside the plot by a good part of a cell; the centre line's hull
    # lies nearer (v.histo.generalize's test measures the plots it makes), its corners cut by less than one and a half cells (the fitted lines
    # of v.histo.generalize draw them again); a hand-drawn plot stays
    plot = shapely.affinity.rotate(box(0, 0, length, depth), angle, origin=(0, 0))
    cells = _cells(plot, cell)
    line = polygons.centre_line(cells, cell)
    assert line.is_valid and line.area == pytest.approx(cells.area, rel=0.03)
    assert shapely.hausdorff_distance(line, plot) < 1.5 * cell
    outer = (shapely.convex_hull(cells).area - plot.area) / plot.length
    inner = (shapely.convex_hull(line).area - plot.area) / plot.length
    assert abs(inner) < outer
    assert polygons.same_outline(polygons.centre_line(plot, cell), plot, 1e-9)


def test_a_plot_of_straight_cells_keeps_its_corners():
    # an L of whole cells: its corners are between long segments, no stairs
    ell = Polygon([(0, 0), (30, 0), (30, 10), (10, 10), (10, 25), (0, 25)])
    assert polygons.same_outline(polygons.centre_line(ell, 1.0), ell)
    assert polygons.centre_line(ell, None) is ell


def test_the_same_outline_with_a_run_of_nearly_straight_vertices():
    # a footprint of the synthetic town over time (GRASS) and the same footprint read
    # back from its model (millimetres, two of its near-straight vertices left out):
    # dropping the vertices within 2 mm of their neighbours' line one at a time left
    # different corners in the two
    drawn = shapely.from_wkt(
        "POLYGON ((84055.93 446567.14, 84056.95 446563.89, 84057.93 446560.78, "
        "84057.95018869743 446560.71593178675, 84059.733208 446561.293392, "
        "84057.855306 446567.893888, 84055.87061264983 446567.32922440005, "
        "84055.93 446567.14))")
    model = shapely.from_wkt(
        "POLYGON ((84055.871 446567.329, 84057.855 446567.894, 84059.733 446561.293, "
        "84057.95 446560.716, 84056.95 446563.89, 84055.871 446567.329))")
    assert polygons.same_outline(drawn, model, 0.002)
    assert not polygons.same_outline(drawn, model, 0.0002)


def test_an_overlay_that_geos_cannot_float_is_snap_rounded():
    # v.histo.generalize's alpha step on Venice 1808 ended in a traceback ("Unable to
    # determine overlay result geometry dimension"): the overlay retries on a grid
    import shapely
    from shapely.geometry import box

    from reconstruction.geom.polygons import overlay

    calls = []

    def fragile(a, b, grid_size=None):
        calls.append(grid_size)
        if grid_size is None:
            raise shapely.errors.GEOSException("Unable to determine overlay result geometry "
                                               "dimension")
        return shapely.intersection(a, b, grid_size=grid_size)

    out = overlay(fragile, box(0, 0, 2, 2), box(1, 1, 3, 3), grid_size=1e-3)
    assert calls == [None, 1e-3] and out.equals(box(1, 1, 2, 2))
    assert overlay(shapely.intersection, box(0, 0, 2, 2), box(1, 1, 3, 3)).equals(box(1, 1, 2, 2))
