"""Street edges: shared edges, the thesis's four cases, the streets raster, and the
rule on the thesis's Delft 1961 and Brussels 1924 footprints."""

import os

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st

from reconstruction.lod2 import street_edges as se
from reconstruction.core.errors import InputError
from reconstruction.geom.grid import Grid


def box(x0, y0, x1, y1):
    """A counter-clockwise ring starting at the south-west corner (edge 0 = south)."""
    return np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1]], dtype=float)


def street_row(n, width=6.0, depth=12.0, x0=0.0, y0=0.0):
    return [box(x0 + i * width, y0, x0 + (i + 1) * width, y0 + depth) for i in range(n)]


def test_an_edge_is_shared_within_a_tenth_of_a_metre_over_half_its_length():
    a = box(0, 0, 6, 12)
    for gap, expected in ((0.0, True), (0.05, True), (0.1, True), (0.2, False)):
        b = box(6 + gap, 0, 12, 12) + [100000.0, 400000.0]  # exactly 0.1 m apart counts
        res = se.street_edges([a + [100000.0, 400000.0], b])
        assert bool(res.shared[1]) is expected, gap          # a's east edge
    # a neighbour along 60 % of the edge: shared; along 40 %: not
    for depth, expected in ((7.2, True), (4.8, False)):
        res = se.street_edges([a, box(6, 0, 12, depth)])
        assert bool(res.shared[1]) is expected, depth


@settings(max_examples=60, deadline=None)
@given(st.lists(st.tuples(st.floats(3, 9), st.floats(0, 0.3), st.floats(6, 14), st.floats(-2, 2),
                          st.floats(-3, 3)), min_size=2, max_size=6))
def test_the_cover_of_every_edge_is_what_shapely_measures(houses):
    """Rows of slightly gapped, shifted, rotated houses: the length of each edge
    within 0.1 m of the others' edges, against shapely's buffers."""
    rings, x = [], 0.0
    for width, gap, depth, shift, angle in houses:
        ring = box(x + gap, shift, x + gap + width, shift + depth)
        c = ring.mean(axis=0)
        t = np.radians(angle)
        rot = np.array([[np.cos(t), -np.sin(t)], [np.sin(t), np.cos(t)]])
        rings.append((ring - c) @ rot.T + c)
        x += gap + width
    edges = se.Edges.of(rings)
    covered, _ = se.edge_cover(edges, 0.1)
    polys = [shapely.Polygon(r) for r in rings]
    for k in range(len(edges.a)):
        others = [p.boundary for r, p in enumerate(polys) if r != edges.ring[k]]
        near = shapely.union_all([shapely.buffer(o, 0.1, quad_segs=64) for o in others])
        want = shapely.LineString([edges.a[k], edges.b[k]]).intersection(near).length
        assert covered[k] == pytest.approx(want, abs=2e-3)


def test_one_unshared_edge_is_the_street_edge():
    # a row whose backs are shared with a back row: every house has only its front free
    front = street_row(4)
    back = [box(i * 6.0, 12, (i + 1) * 6.0, 24) for i in range(4)]
    left, right = box(-6, 0, 0, 24), box(24, 0, 30, 24)
    res = se.street_edges(front + back + [left, right])
    assert res.case[1:3].tolist() == [se.ONE_FREE] * 2
    assert res.edge[1:3].tolist() == [0, 0]                   # the south edge
    assert res.case[5] == se.ONE_FREE and res.edge[5] == 2    # a back-row house: its north edge


def test_a_street_edge_spreads_along_the_row():
    # the first house has an annex behind it and a neighbour block to the west:
    # it knows its front
    rings = street_row(8) + [box(0, 12, 6, 20), box(-10, 0, 0, 20)]
    res = se.street_edges(rings)
    assert res.case[0] == se.ONE_FREE
    assert res.case[1:8].tolist() == [se.FROM_NEIGHBOUR] * 7
    assert res.edge[:8].tolist() == [0] * 8
    assert not res.edge_shared().any()


def test_the_index_is_in_the_ring_as_given():
    rings = street_row(3) + [box(0, 12, 6, 20), box(-10, 0, 0, 20)]
    rings[2] = np.roll(rings[2], 1, axis=0)                  # starts at the north-west corner
    res = se.street_edges(rings)
    assert res.edge[2] == 1
    assert np.allclose(rings[2][1], [12, 0]) and np.allclose(rings[2][2], [18, 0])


def test_a_vote_by_alignment_with_the_neighbours():
    # fronts in line; the backs not (the second house is deeper)
    rings = [box(0, 0, 6, 12), box(6, 0, 12, 15)]
    res = se.street_edges(rings)
    assert sorted(res.case.tolist()) == [se.FROM_NEIGHBOUR, se.VOTE]
    assert res.edge.tolist() == [0, 0]


def test_no_clear_vote_takes_the_shortest_unshared_edge():
    alone = box(0, 0, 12, 7)
    res = se.street_edges([alone])
    assert res.case[0] == se.SHORTEST and res.edge[0] in (1, 3)
    # a tie between front and back of a plain row: the shortest unshared edge,
    # never a shared one
    res = se.street_edges(street_row(3, width=14, depth=9))
    assert set(res.case) <= {se.SHORTEST, se.FROM_NEIGHBOUR}
    assert not res.edge_shared().any()


def test_an_enclosed_footprint_has_no_street_edge():
    inner = box(6, 6, 12, 12)
    ring_around = [box(0, 0, 18, 6), box(0, 12, 18, 18), box(0, 6, 6, 12), box(12, 6, 18, 12)]
    res = se.street_edges([inner] + ring_around)
    assert res.case[0] == se.ENCLOSED and res.edge[0] == -1
    assert not res.edge_shared().any()


def street_raster(width=60, height=40, street_rows=(0, 6)):
    """1 m cells, origin (0, 0) at the south-west; class 4 (street) for y in
    [street_rows), class 1 (building) elsewhere; north of y=30 a canal (3)."""
    values = np.ones((height, width))
    y = height - 0.5 - np.arange(height)
    values[(y >= street_rows[0]) & (y < street_rows[1])] = 4
    values[y >= 30] = 3
    return Grid(values, north=float(height), west=0.0, nsres=1.0, ewres=1.0)


def test_the_streets_raster_picks_the_edge_facing_the_street():
    # a row 6 m north of the street, backs free towards the yards (class 1)
    rings = street_row(5, y0=6.0, x0=10.0)
    res = se.street_edges(rings, streets=street_raster(), classes=[3, 4])
    assert res.case.tolist() == [se.STREETS] * 5
    assert res.edge.tolist() == [0] * 5
    # a house between street and canal faces both: the four cases choose between them
    res = se.street_edges([box(10, 6, 16, 30)], streets=street_raster(), classes=[3, 4])
    assert res.case[0] == se.SHORTEST and res.edge[0] in (0, 2)


def test_street_polygons_work_as_the_raster_does():
    rings = street_row(5, y0=6.0, x0=10.0)
    street = shapely.box(0, 0, 60, 6)
    res = se.street_edges(rings, streets=[street])
    assert res.case.tolist() == [se.STREETS] * 5 and res.edge.tolist() == [0] * 5
    with pytest.raises(InputError, match="street polygons"):
        se.street_edges(rings, streets=[shapely.LineString([(0, 3), (60, 3)])])


def test_the_streets_raster_must_hold_the_classes():
    with pytest.raises(InputError, match="no cells of the classes 7"):
        se.street_edges(street_row(2), streets=street_raster(), classes=[7])
    with pytest.raises(InputError):
        se.street_edges(street_row(2), streets=street_raster(), classes=[])


def test_strip_fractions_sample_in_front_of_the_edge():
    rings = [box(10, 6, 16, 18)]
    e = se.Edges.of(rings)
    frac = se.strip_fractions(e, [0, 1, 2], street_raster(), [4], depth=3.0)
    assert frac[0] == pytest.approx(1.0) and frac[1] == 0 and frac[2] == 0


def _thesis_rings(shared_data, folder):
    from shapefiles import have_ogr2ogr, read_shapefile

    from reconstruction.lod2 import outlines

    if not have_ogr2ogr():
        pytest.skip("ogr2ogr (GDAL) is needed to read the shapefiles")
    geoms, _ = read_shapefile(os.path.join(shared_data, folder, "thesis_output",
                                           "final_all_footprints.shp"))
    polygons = outlines.footprint_polygons(geoms).polygons
    rings, _ = outlines.clean_rings(polygons)
    return [r for r in rings if r is not None]


@pytest.mark.acceptance
@pytest.mark.parametrize("folder,count", [("delft_1961_subset", 895), ("bxls_1924", 3706)])
def test_street_edges_on_the_thesis_footprints(shared_data, folder, count):
    rings = _thesis_rings(shared_data, folder)
    assert len(rings) == count
    res = se.street_edges(rings)
    free = res.unshared_count()
    one = free == 1
    k = res.edges.start[:-1] + res.edge
    print("{}: {} footprints, cases {}, street edge shared: {}, one unshared edge: {} "
          "(using it: {})".format(folder, len(rings), np.bincount(res.case, minlength=6).tolist(),
                                  int(res.edge_shared().sum()), int(one.sum()),
                                  int(np.sum(one & ~res.shared[k]))))
    assert not res.edge_shared().any()
    assert np.all(res.case[one] == se.ONE_FREE) and not res.shared[k[one]].any()
    assert np.all((res.edge >= 0) == (free > 0))
    # independent check of "shared" with shapely: the street edge's length within
    # 0.1 m of the other footprints' boundaries is below half its length
    polys = np.array([shapely.Polygon(r) for r in rings], dtype=object)
    tree = shapely.STRtree(polys)
    for r in np.nonzero(res.edge >= 0)[0][::7]:
        a, b = rings[r][res.edge[r]], rings[r][(res.edge[r] + 1) % len(rings[r])]
        line = shapely.LineString([a, b])
        others = [j for j in tree.query(line, predicate="dwithin", distance=0.1) if j != r]
        if others:
            near = shapely.union_all(shapely.buffer(shapely.boundary(polys[others]), 0.1))
            assert line.intersection(near).length < 0.5 * line.length + 1e-6
