"""The LoD2 stage's inputs (reconstruction/lod2/inputs.py) and the roofs' shared edges."""

import numpy as np
import pytest
import shapely

from reconstruction.lod2 import stage as lod2
from reconstruction.lod2 import inputs as li
from reconstruction.lod2.roofs import plan as roofs
from reconstruction.core.errors import InputError
from reconstruction.geom.grid import Grid


def row(n=6, width=6.0, depth=12.0, y0=0.0):
    return [shapely.box(i * width, y0, (i + 1) * width, y0 + depth) for i in range(n)]


def test_columns_and_ranges_keep_their_meaning():
    fps = row(3)
    cols = {"h_building": [9, 10, None], "h_attic": [3, 3, 3], "g": [1, 2, 3]}
    r = li.footprint_heights(fps, cols, options=li.HeightOptions(ground_column="g"))
    assert np.allclose(r.heights.ground, [1, 2, 3]) and r.source.tolist() == ["column"] * 3
    assert np.isnan(r.heights.eaves[2])
    r = li.footprint_heights(fps, {}, options=li.HeightOptions(eaves_range=(6, 7),
                                                               attic_range=(2, 3)))
    assert isinstance(r.heights.eaves, lod2.Uniform) and set(r.source) == {"range"}
    with pytest.raises(InputError, match="h_building"):
        li.footprint_heights(fps, {})


def test_aligned_footprints_are_matched_by_overlap_and_the_rest_inferred():
    fps = row(6)
    aligned = [fps[0], shapely.affinity.translate(fps[3], 0.3, 0.0),   # digitised 0.3 m off
               shapely.box(100, 0, 106, 12)]                          # not among the inputs
    cols = {"ground-0.2": [1.0, 1.0, 1.0], "roof-0.25": [10.0, 11.0, 12.0],
            "roof-0.99": [14.0, 15.0, 16.0]}
    opts = li.HeightOptions(aligned=li.AlignedFootprints(aligned, cols))
    r = li.footprint_heights(fps, {}, options=opts)
    assert r.source.tolist() == ["measured", "neighbours", "neighbours", "measured",
                                 "neighbours", "neighbours"]
    assert r.heights.eaves[0] == pytest.approx(9.0) and r.heights.attic[3] == pytest.approx(4.0)
    assert r.report.matched == 2 and r.report.aligned_measured == 3
    assert li.match_footprints(fps, aligned).tolist() == [0, -1, -1, 1, -1, -1]


def test_aligned_footprints_without_height_columns_are_refused():
    opts = li.HeightOptions(aligned=li.AlignedFootprints(row(2), {"cat": [1, 2]}))
    with pytest.raises(InputError, match="no height columns"):
        li.footprint_heights(row(2), {}, options=opts)
    nulls = {"ground-0.2": [None, None], "roof-0.25": [None, None], "roof-0.99": [None, None]}
    opts = li.HeightOptions(aligned=li.AlignedFootprints(row(2), nulls))
    with pytest.raises(InputError, match="None of the 2 aligned footprints"):
        li.footprint_heights(row(2), {}, options=opts)


def test_ground_from_points_and_a_dtm_on_a_plane():
    fps = row(4)
    rng = np.random.default_rng(0)
    xy = rng.uniform([-10, -10], [34, 22], (20000, 2))
    xy = xy[~((xy[:, 0] > 0) & (xy[:, 0] < 24) & (xy[:, 1] > 0) & (xy[:, 1] < 12))]
    pts = np.column_stack([xy, 3.0 + 0.01 * xy[:, 0]])
    r = li.footprint_heights(fps, {"h_building": [9] * 4, "h_attic": [3] * 4},
                             options=li.HeightOptions(ground_points=pts))
    centres = np.array([g.centroid.x for g in fps])
    assert np.allclose(r.heights.ground, 3.0 + 0.01 * centres, atol=0.1)
    assert r.report.ground_from == "points"
    x = np.arange(-10, 34) + 0.5
    dtm = Grid(np.tile(3.0 + 0.01 * x, (32, 1)), 22.0, -10.0, 1.0, 1.0)
    r = li.footprint_heights(fps, {"h_building": [9] * 4, "h_attic": [3] * 4},
                             options=li.HeightOptions(elevation=dtm))
    assert np.allclose(r.heights.ground, 3.0 + 0.01 * centres, atol=0.1)


def test_points_far_away_are_refused_with_both_extents():
    pts = np.array([[5.0e6, 5.0e6, 1.0], [5.0e6 + 1, 5.0e6, 1.0]])
    with pytest.raises(InputError, match="another reference system"):
        li.footprint_heights(row(2), {"h_building": [9, 9], "h_attic": [3, 3]},
                             options=li.HeightOptions(ground_points=pts))


def _prepared(fps, kind="gable"):
    n = len(fps)
    heights = lod2.Heights(np.full(n, 9.0), np.full(n, 4.0), 0.0)
    requests = lod2.RoofRequests(np.full(n, kind, dtype=object), np.full(n, 1880.0))
    return lod2.prepare(lod2.Footprints(fps), heights, requests)


def test_street_edges_reach_the_roofs_and_the_attributes():
    fps = row(5) + row(5, y0=12.0)                     # two rows back to back
    prepared, edges = li.with_street_edges(_prepared(fps))
    result = lod2.build(prepared)
    assert result.attributes["street_edge"] == edges.edge.tolist()
    assert result.attributes["street_case"] == edges.case.tolist()
    assert not edges.edge_shared().any()
    assert prepared.buildings.shared is not None


def test_no_end_goes_on_a_shared_edge():
    # a 6 x 12 house: street edge 0 (south), its back (edge 2) shared
    xy = np.array([[0, 0], [6, 0], [6, 12], [0, 12]], dtype=float)
    shared = np.array([False, True, True, True])
    u = np.full((1, 3), 0.5)
    for kind in ("gable", "stepped", "hip"):
        plan = roofs.plan_roofs([xy], [kind], np.array([4.0]), u, street=[0], shared=[shared])
        assert [e for e, _ in plan.ends[0]] == [0], (kind, plan.ends)
    # without the shared back, both ends
    plan = roofs.plan_roofs([xy], ["gable"], np.array([4.0]), u, street=[0])
    assert sorted(e for e, _ in plan.ends[0]) == [0, 2]
    # every edge shared: a gable has no end left and is a hip at one pitch
    plan = roofs.plan_roofs([xy], ["gable"], np.array([4.0]), u, street=[0],
                            shared=[np.ones(4, dtype=bool)])
    assert plan.kinds == ["hip"] and 0 not in plan.ends


def test_roofs_changed_by_the_rules_are_not_counted_as_fallbacks():
    # a 3 x 3 block of 6 x 12 houses: the middle one shares every edge, so its
    # requested gable has no free end and the roof rules make it a hip; that
    # is a rule, not a roof that failed validation and fell back
    fps = row(3) + row(3, y0=12.0) + row(3, y0=24.0)
    prepared, _ = li.with_street_edges(_prepared(fps))
    result = lod2.build(prepared)
    assert result.roof_types[4] == "hip"
    assert result.report.by_rule >= 1
    assert result.report.fell_back == len({f.footprint for f in result.report.fallbacks}) == 0


def streets_grid(values, west=0.0, north=20.0):
    return Grid(np.asarray(values, dtype=float), north=north, west=west, nsres=1.0, ewres=1.0)


def test_a_streets_raster_with_its_classes_near_the_footprints_passes():
    from reconstruction.geom.grid import Extent

    grid = streets_grid([[1, 4], [np.nan, 1]])
    li.check_streets_near(grid, (3, 4), "cls", 10.0, Extent(0, 0, 5, 5))


def test_a_streets_raster_of_another_area_says_it_has_no_data_near_the_footprints():
    """It said "has no cells of the classes 3, 4" of a raster that has them,
    only not near the footprints (issue 33, item 7)."""
    from reconstruction.geom.grid import Extent

    with pytest.raises(InputError, match=r"The streets raster <cls> has no data within 10 m of "
                                         r"the footprints \(x 0\.\.5, y 0\.\.5\): does it cover "
                                         r"another area"):
        li.check_streets_near(streets_grid(np.full((3, 3), np.nan)), (3, 4), "cls", 10.0,
                              Extent(0, 0, 5, 5))


def test_a_streets_raster_without_the_classes_near_the_footprints_names_those_there():
    from reconstruction.geom.grid import Extent

    with pytest.raises(InputError, match=r"no cells of the classes 3, 4 within 10 m of the "
                                         r"footprints \(x 0\.\.5, y 0\.\.5\); its cells there "
                                         r"are of the classes 1, 2$"):
        li.check_streets_near(streets_grid([[1, 2], [np.nan, 1]]), (3, 4), "cls", 10.0,
                              Extent(0, 0, 5, 5))


def plane_points(xy0, xy1, n, z, seed=0):
    """n points uniform over the box xy0..xy1 at height z(x, y)."""
    xy = np.random.default_rng(seed).uniform(xy0, xy1, (n, 2))
    return np.column_stack([xy, z(xy[:, 0], xy[:, 1])])


def test_ground_points_given_as_building_points_are_counted_as_low():
    """Ground points given as building_points= gave buildings 0.01-1.4 m tall
    without a word (issue 33, item 8): the report counts the footprints whose
    points stand less than LOW_BUILDING above the ground."""
    fps = row(4)
    ground = plane_points([-10, -10], [34, 22], 20000, lambda x, y: 3.0 + 0.01 * x)
    noisy = plane_points([0, 0], [24, 12], 4000, lambda x, y: 3.0 + 0.01 * x
                         + np.random.default_rng(1).uniform(0, 1.2, len(x)), seed=2)
    r = li.footprint_heights(fps, {}, options=li.HeightOptions(ground_points=ground,
                                                               building_points=noisy))
    assert (r.report.points_low, r.report.points_measured) == (4, 4)
    assert 0 < r.report.points_median_top < li.LOW_BUILDING
    # real roofs, 9 to 12 m above the ground: none low
    roofs = plane_points([0, 0], [24, 12], 4000, lambda x, y: 12.0 + 0.01 * x
                         + np.random.default_rng(1).uniform(0, 3, len(x)), seed=2)
    r = li.footprint_heights(fps, {}, options=li.HeightOptions(ground_points=ground,
                                                               building_points=roofs))
    assert (r.report.points_low, r.report.points_measured) == (0, 4)
    assert r.report.points_median_top > 9
