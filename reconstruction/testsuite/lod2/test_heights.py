"""Reference heights: ground from points and DTMs, roofs from building points,
measured heights from the thesis's and the 3D BAG's columns."""

import numpy as np
import pytest
import shapely

from reconstruction.lod2 import groupstats
from reconstruction.lod2 import heights
from reconstruction.core.errors import InputError
from reconstruction.geom.grid import Grid


def plane(x, y):
    return 5.0 + 0.005 * x + 0.003 * y


def slope_site(seed=0, hole=True):
    """Footprints on a sloping plane, ground points on a jittered 1 m grid
    outside the buildings; the points around footprint 7 are gone (a larger
    building stood there when the points were measured)."""
    rng = np.random.default_rng(seed)
    fps = [shapely.box(x, y, x + 8.0 + (i % 3), y + 12.0)
           for i, (x, y) in enumerate((x, y) for y in range(10, 140, 30) for x in range(10, 190, 20))]
    fps = np.array(fps, dtype=object)
    gx, gy = np.meshgrid(np.arange(0, 200, 1.0), np.arange(0, 150, 1.0))
    xy = np.stack([gx.ravel(), gy.ravel()], axis=1) + rng.uniform(-0.3, 0.3, (gx.size, 2))
    inside = np.zeros(len(xy), dtype=bool)
    for g in fps:
        inside |= shapely.contains_xy(g, xy[:, 0], xy[:, 1])
    if hole:
        inside |= shapely.contains_xy(shapely.buffer(fps[7], 6.0, join_style="mitre"),
                                      xy[:, 0], xy[:, 1])
    xy = xy[~inside]
    return fps, np.column_stack([xy, plane(xy[:, 0], xy[:, 1])])


def brute_force_ground(fp, pts, percentile=20.0, buffer=0.5, step=0.5):
    """The thesis's loop for one footprint: grow the buffer until points are in it."""
    b = buffer
    while True:
        area = shapely.buffer(fp, b, join_style="mitre")
        z = pts[shapely.intersects_xy(area, pts[:, 0], pts[:, 1]), 2]
        if len(z):
            return np.percentile(z, percentile), b
        b += step


def test_ground_from_points_follows_the_plane_and_fills_the_hole():
    fps, pts = slope_site()
    g = heights.ground_from_points(fps, pts)
    c = shapely.get_coordinates(shapely.centroid(fps))
    assert g.missing == 0
    assert np.all(np.abs(g.ground - plane(c[:, 0], c[:, 1])) < 0.1)
    assert g.buffer[7] > 6.0 and np.all(np.delete(g.buffer, 7) == 0.5)
    for i in (0, 7, 20):
        value, b = brute_force_ground(fps[i], pts)
        assert g.ground[i] == pytest.approx(value, abs=1e-9)
        assert g.buffer[i] == b
    assert g.percentiles.shape == (len(fps), 6)
    assert np.all(np.diff(g.percentiles, axis=1) >= 0)
    assert np.allclose(g.percentiles[:, 2], g.ground)


def test_ground_percentile_picks_the_column():
    fps, pts = slope_site(hole=False)
    low = heights.ground_from_points(fps, pts, percentile=0)
    mid = heights.ground_from_points(fps, pts, percentile=35)
    assert np.allclose(low.ground, low.percentiles[:, 0])
    assert np.all(low.ground <= mid.ground) and np.all(mid.ground <= mid.percentiles[:, 4])


def test_ground_from_a_dtm_is_the_plane_within_a_cell_slope():
    fps, pts = slope_site()
    res = 1.0
    rows, cols = 150, 200
    x, y = np.meshgrid(np.arange(cols) * res + res / 2, 150 - (np.arange(rows) * res + res / 2))
    values = plane(x, y)
    # no data under the buildings and in the hole, as in a DTM made from that point cloud
    under = np.zeros(values.shape, dtype=bool)
    for g in list(fps) + [shapely.buffer(fps[7], 6.0, join_style="mitre")]:
        under |= shapely.contains_xy(g, x, y)
    values[under] = np.nan
    dtm = heights.ground_from_raster(fps, Grid(values, north=150.0, west=0.0, nsres=res, ewres=res))
    assert dtm.missing == 0
    assert dtm.buffer[7] > 6.0
    # the truth: the percentile of the plane over the ground the buffer reaches
    cell_rise = (0.005 + 0.003) * res              # the plane's rise across one cell
    hole = shapely.buffer(fps[7], 6.0, join_style="mitre")
    for i in range(len(fps)):
        ring = shapely.buffer(fps[i], dtm.buffer[i], join_style="mitre").difference(
            hole if i == 7 else fps[i])
        fx, fy = np.meshgrid(*(np.arange(lo, hi, 0.05) for lo, hi in
                               zip(ring.bounds[:2], ring.bounds[2:])))
        inside = shapely.contains_xy(ring, fx, fy)
        truth = np.percentile(plane(fx[inside], fy[inside]), 20)
        assert abs(dtm.ground[i] - truth) <= cell_rise, i


def test_ground_points_elsewhere_are_refused():
    fps, pts = slope_site(hole=False)
    moved = pts + [155000.0, 463000.0, 0.0]         # the points in another reference system
    with pytest.raises(InputError, match="another reference system"):
        heights.ground_from_points(fps, moved)
    with pytest.raises(InputError, match="between 0 and 50"):
        heights.ground_from_points(fps, pts, percentile=60)
    with pytest.raises(InputError, match="no heights"):
        heights.ground_from_points(fps, pts[:, :2])


def test_footprints_far_from_every_point_get_no_ground():
    fps, pts = slope_site(hole=False)
    far = np.append(fps, shapely.box(5000, 5000, 5010, 5010))
    g = heights.ground_from_points(far, pts)
    assert g.missing == 1 and np.isnan(g.ground[-1]) and g.count[-1] == 0


def test_no_points_give_no_candidates():
    pts = np.zeros((0, 3))
    b = heights.PointBuckets(pts)
    owner, x, y, z = b.candidates([[0, 0, 1, 1]])
    assert len(owner) == 0


def test_roof_from_building_points():
    fp = shapely.box(0, 0, 10, 6)
    rng = np.random.default_rng(1)
    xy = rng.uniform([0, 0], [10, 6], (2000, 2))
    z = 10.0 + 4.0 * (1 - np.abs(xy[:, 1] - 3.0) / 3.0)       # a gable roof, eaves 10, ridge 14
    pts = np.column_stack([xy, z])
    roof = heights.roof_from_points([fp, shapely.box(50, 50, 60, 60)], pts)
    assert roof.low[0] == pytest.approx(np.percentile(z, 25))
    assert roof.high[0] == pytest.approx(np.percentile(z, 99))
    assert roof.missing == 1
    m = heights.roof_heights(roof, [0.5, 0.5])
    assert m.eaves[0] == pytest.approx(roof.low[0] - 0.5) and np.isnan(m.eaves[1])


def test_measured_heights_from_the_thesis_columns_in_either_spelling():
    cols = {"ground-0.2": [1.0, 1.0, None], "roof-0.25": [9.0, 0.5, 8.0],
            "roof-0.99": [13.0, 4.0, 12.0]}
    m = heights.measured_heights(cols)
    assert m.eaves[0] == 8.0 and m.attic[0] == 4.0 and m.total[0] == 12.0
    assert np.isnan(m.eaves[1]) and np.isnan(m.eaves[2])      # below ground; no ground
    grass = {"ground_0_2": [1.0], "roof_0_25": [9.0], "roof_0_99": [13.0], "cat": [1]}
    assert heights.measured_heights(grass).eaves[0] == 8.0
    assert heights.height_columns(grass).name == "thesis"


def test_measured_heights_from_the_3d_bag():
    # the 3D BAG sample's 1949 house (../shared/data/3dbag_sample)
    old = {"b3_h_maaiveld": [-0.277], "b3_h_dak_50p": [6.97], "b3_h_dak_70p": [7.8],
           "b3_h_dak_max": [9.83], "b3_h_dak_min": [-0.07]}
    m = heights.measured_heights(old)
    assert heights.height_columns(old).name == "3dbag-2024"
    p25 = 6.97 - 1.25 * (7.8 - 6.97)                  # extrapolated: no 25th percentile
    assert m.eaves[0] == pytest.approx(p25 + 0.277)
    assert m.attic[0] == pytest.approx(9.83 - p25)
    new = {"b3_h_maaiveld": [0.5, 0.5], "b3_h_50p": [9.5, 7.0], "b3_h_70p": [10.5, 7.0],
           "b3_h_max": [13.5, 7.2], "b3_h_nok": [12.5, None]}
    m = heights.measured_heights(new)
    assert heights.height_columns(new).name == "3dbag"
    assert m.eaves.tolist() == [pytest.approx(8.25 - 0.5), pytest.approx(6.5)]
    assert m.attic.tolist() == [pytest.approx(12.5 - 8.25), pytest.approx(0.2)]  # ridge, else max
    assert heights.measured_heights(new, ground=[1.5, np.nan]).eaves[0] == pytest.approx(6.75)
    # a choice of one's own
    mine = heights.HeightColumns("mine", ("b3_h_maaiveld",), ("b3_h_50p",), ("b3_h_max",))
    assert heights.measured_heights(new, mine).eaves[0] == 9.0


def test_aligned_footprints_without_height_columns_are_refused():
    with pytest.raises(InputError, match="no height columns"):
        heights.measured_heights({"cat": [1], "bouwjaar": [1900]})
    with pytest.raises(InputError, match="Unknown height columns"):
        heights.height_columns(["roof-0.25"], "lidar")


def test_group_statistics_match_numpy():
    rng = np.random.default_rng(2)
    v = rng.normal(size=500)
    g = rng.integers(0, 40, 500)
    g[g == 5] = 6                                        # an empty group
    pct = groupstats.group_percentiles(v, g, 41, [0, 20, 50, 99])
    for k in (0, 6, 39):
        assert np.allclose(pct[k], np.percentile(v[g == k], [0, 20, 50, 99]))
    assert np.isnan(pct[5]).all() and np.isnan(pct[40]).all()
    w = rng.uniform(0.1, 1.0, 500)
    wm = groupstats.group_weighted_median(v, w, g, 41)
    for k in (0, 6, 39):
        vv, ww = v[g == k], w[g == k]
        o = np.argsort(vv)
        c = np.cumsum(ww[o])
        assert wm[k] == vv[o][np.searchsorted(c, 0.5 * c[-1])]
