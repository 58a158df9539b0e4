"""Roofs: types drawn with the thesis's probabilities, and the geometry of each roof."""

import dataclasses
import math

import numpy as np
import pytest
from shapely.geometry import Point, Polygon

from reconstruction.lod2 import outlines
from reconstruction.lod2.roofs import envelope as roof_envelope
from reconstruction.lod2.roofs import skeleton as roof_skeleton
from reconstruction.lod2.roofs import facades as roof_facades
from reconstruction.lod2.roofs import plan as roofs
from reconstruction.lod2.roofs.model import RoofConfig

RECT = np.array([[0.0, 0.0], [12.0, 0.0], [12.0, 6.0], [0.0, 6.0]])
L_SHAPE = np.array([[0, 0], [10, 0], [10, 4], [4, 4], [4, 10], [0, 10]], dtype=float)


def make(footprints, kinds, attic, uniforms, street=None, **config):
    """Every roof (or None) and the type each got, from make_roofs."""
    rs = roofs.make_roofs(footprints, kinds, attic, uniforms, street, RoofConfig(**config))
    return rs.each(), rs.kinds


def one(xy, kind, attic=3.0, u=0.5, street=None, **config):
    """One roof, with only the vertices its faces use (candidates are dropped)."""
    r, kinds = make([xy], [kind], [attic], np.full((1, 3), u), street, **config)
    roof = r[0]
    if roof is not None:
        used = sorted({k for f in roof.faces for k in f})
        remap = {k: i for i, k in enumerate(used)}
        roof = dataclasses.replace(roof, vertices=roof.vertices[used],
                                   faces=[[remap[k] for k in f] for f in roof.faces])
    return roof, kinds[0]


def test_draw_roof_types_follows_the_table():
    rng = np.random.default_rng(3)
    n = 40000
    t = roofs.draw_roof_types(np.full(n, 4), np.full(n, 1900), np.full(n, 3.0), rng.random(n))
    weights = roofs.ROOF_PROBABILITIES[("before", 4)]
    for kind, w in weights.items():
        assert abs(np.mean(t == kind) - w / 100.0) < 0.015
    t = roofs.draw_roof_types(np.full(n, 6), np.full(n, 1961), np.full(n, 3.0), rng.random(n))
    for kind, w in roofs.ROOF_PROBABILITIES[("after", "n")].items():
        assert abs(np.mean(t == kind) - w / 100.0) < 0.015
    assert not np.any(t == "stepped")


def test_draw_roof_types_low_roofs_are_flat_and_seeded():
    a, b = (roofs.draw_roof_types([4, 4, 5, 4], [1900] * 4, [0.5, 3, 3, 3],
                                  np.random.default_rng(1).random(4)) for _ in range(2))
    assert a[0] == "flat"
    assert list(a) == list(b)


def test_hip_roof_on_rectangle():
    roof, kind = one(RECT, "hip", attic=3.0)
    assert kind == "hip"
    v = roof.vertices
    assert v[:, 2].max() == pytest.approx(3.0)
    # long faces at the pitch of Eq. 3.13 with the end as baseline: ridge at width/2
    ridge = v[np.isclose(v[:, 2], 3.0)]
    assert np.allclose(ridge[:, 1], 3.0)
    # steeper hip ends (>= 60 degrees): ridge ends closer to the ends than 3 m
    assert ridge[:, 0].min() < 3.0 and ridge[:, 0].max() > 9.0
    assert len(roof.faces) == 4


def test_gable_roof_has_vertical_ends():
    roof, _ = one(RECT, "gable", attic=4.0)
    v = roof.vertices
    ridge = v[np.isclose(v[:, 2], 4.0)]
    assert sorted(np.round(ridge[:, 0], 6)) == [0.0, 12.0]
    assert np.allclose(ridge[:, 1], 3.0)


def test_mansard_top_is_inset_and_flat():
    roof, _ = one(RECT, "mansard", attic=2.5, u=0.0, inset=(1.5, 1.5))
    v = roof.vertices
    top = [f for f in roof.faces if np.allclose(v[f, 2], 2.5)]
    assert len(top) == 1
    poly = Polygon(v[top[0], :2])
    assert poly.area == pytest.approx((12 - 3) * (6 - 3))


def test_mansard_inset_below_half_the_shortest_edge():
    thin = np.array([[0, 0], [10, 0], [10, 1.5], [0, 1.5]], dtype=float)
    roof, _ = one(thin, "mansard", attic=2.0, inset=(2.0, 2.0))
    v = roof.vertices
    top = [f for f in roof.faces if np.allclose(v[f, 2], 2.0)]
    assert len(top) == 1 and Polygon(v[top[0], :2]).area > 0


def test_mansard_caps_are_0_9_of_the_inscribed_radius_where_asked():
    thin = np.array([[0, 0], [10, 0], [10, 1.5], [0, 1.5]], dtype=float)
    caps = roofs.mansard_caps([RECT, L_SHAPE, thin, L_SHAPE], [True, True, True, False])
    # the L's circle touches its outer sides x = 0, y = 0 and its inner corner (4, 4)
    r_l = 4 * math.sqrt(2) / (1 + math.sqrt(2))
    assert caps == pytest.approx([0.45 * 6, 0.9 * r_l, 0.45 * 1.5, 0.0], abs=1e-3)


def test_mansard_caps_above_the_wanted_inset_need_not_be_exact():
    # a long near-rectangle (its circle's centres line a ridge: the slow case)
    long = np.array([[0, 0], [30, 0], [30, 6.02], [0, 6]], dtype=float)
    thin = np.array([[0, 0], [10, 0], [10, 1.5], [0, 1.5]], dtype=float)
    rings = [RECT, L_SHAPE, thin, long, long]
    which = [True, True, True, True, False]
    exact = roofs.mansard_caps(rings, which)
    wanted = np.array([1.5, 1.2, 1.0, 2.0, 1.0])
    caps = roofs.mansard_caps(rings, which, wanted)
    assert caps[2] == exact[2] and caps[4] == 0.0      # the thin one's cap binds: exact
    assert np.all(caps[:4] <= exact[:4])
    assert np.array_equal(np.minimum(wanted, caps)[:4], np.minimum(wanted, exact)[:4])


def test_envelope_matches_cgal_on_convex_footprints():
    if not roof_skeleton.cgal_available():
        pytest.skip("pySVCGAL not installed")
    quads = [RECT, np.array([[0, 0], [11, 1], [10, 7], [1, 6]], dtype=float),
             np.array([[0, 0], [8, 0], [10, 5], [5, 9], [-1, 5]], dtype=float)]
    for xy in quads:
        env = roof_envelope.envelope_roofs(xy[None], np.ones((1, len(xy))))[0]
        cg = roof_skeleton.cgal_roofs([xy], [np.full(len(xy), 45.0)], [None])[0]
        assert env.zmax == pytest.approx(cg.zmax, abs=1e-4)


def test_cgal_edge_angles_go_to_the_right_edges():
    if not roof_skeleton.cgal_available():
        pytest.skip("pySVCGAL not installed")
    pitch = np.full(6, 45.0)
    pitch[[1, 4]] = 90.0          # the ends of the two arms of the L
    roof = roof_skeleton.cgal_roofs([L_SHAPE], [pitch], [None])[0]
    v = roof.vertices
    top = v[v[:, 2] > 1e-6]
    # ridge ends on the gable edges x = 10 (edge 1) and y = 10 (edge 4)
    assert np.any(np.isclose(top[:, 0], 10.0) & np.isclose(top[:, 1], 2.0))
    assert np.any(np.isclose(top[:, 1], 10.0) & np.isclose(top[:, 0], 2.0))


def test_concave_hip_and_gable_use_the_skeleton():
    if not roof_skeleton.cgal_available():
        pytest.skip("pySVCGAL not installed")
    for kind in ("hip", "gable", "mansard"):
        roof, got = one(L_SHAPE, kind, attic=3.0)
        assert roof is not None and got == kind
        assert roof.vertices[:, 2].max() == pytest.approx(3.0, abs=1e-4)
    roof, got = one(L_SHAPE, "stepped")
    assert got == "gable"


def test_stepped_facade_steps_above_the_roof_and_inside():
    roof, kind = one(RECT, "stepped", attic=3.0, u=0.0, step=(0.5, 0.5), thickness=0.5)
    assert kind == "stepped"
    v = roof.vertices
    fp = Polygon(RECT).buffer(1e-6)
    assert all(fp.contains(Point(p)) for p in v[:, :2])
    # steps: heights are multiples of the step height, top above the ridge
    zs = np.unique(np.round(v[v[:, 2] > 0, 2], 6))
    steps = zs[np.isclose(np.mod(zs + 1e-9, 0.5), 0, atol=1e-6)]
    assert len(steps) >= 6
    assert v[:, 2].max() > 3.0
    assert v[:, 2].max() <= 3.0 + 0.5 + 1e-9
    # the facade sits on the shortest edge (x = 0 or x = 12)
    high = v[np.isclose(v[:, 2], v[:, 2].max())]
    assert np.all((high[:, 0] < 0.5 + 1e-9) | (high[:, 0] > 11.5 - 1e-9))


def test_stepped_on_street_edge():
    roof, kind = one(RECT, "stepped", street=[0])
    v = roof.vertices
    high = v[np.isclose(v[:, 2], v[:, 2].max())]
    assert np.all(high[:, 1] <= 0.5 + 1e-9)


def test_flat_roof_is_the_footprint():
    roof, _ = one(RECT, "flat")
    assert roof.faces == [[0, 1, 2, 3]]
    assert np.all(roof.vertices[:, 2] == 0)


def test_interp_rows_is_np_interp_per_row():
    rng = np.random.default_rng(2)
    xp = np.sort(rng.uniform(0, 20, (7, 5)), axis=1)
    fp = rng.uniform(-5, 5, (7, 5))
    xp[:, -1], fp[:, -1] = xp[:, -2], fp[:, -2]      # padding repeats the last point
    x = xp[:, :1] + rng.random((7, 3)) * (xp[:, -1:] - xp[:, :1])
    got = roof_facades._interp_rows(x, xp, fp)
    for r in range(7):
        assert np.allclose(got[r], np.interp(x[r], xp[r], fp[r]), atol=1e-9)


@pytest.mark.parametrize("xy", [
    RECT,
    np.array([[0.0, 0.0], [7.0, 0.4], [6.5, 15.0], [0.0, 14.0]]),          # trapezoid
    np.array([[0.0, 0.0], [6.0, 0.0], [8.0, 7.0], [6.0, 14.0], [0.0, 14.0]]),  # pentagon
])
@pytest.mark.parametrize("attic,step", [(3.0, 0.5), (2.6, 0.4), (6.0, 0.7), (1.2, 0.65)])
def test_stepped_facades_in_bulk_have_the_right_steps(xy, attic, step):
    """The facades of many footprints at once (one pass per step count):
    each rises in steps of the step height (on a rectangle ceil((h + margin) /
    step) of them, above the ridge), inside the footprint, with the street
    edge as its front."""
    roof, kind = one(xy, "stepped", attic=attic, u=0.0, step=(step, step), thickness=0.5)
    assert kind == "stepped" and roof is not None
    v = roof.vertices
    facade = v[roof.faces[0]]
    nsteps = int(round(facade[:, 2].max() / step))
    assert facade[:, 2].max() == pytest.approx(nsteps * step)
    assert nsteps >= 1 and nsteps * step <= attic + step + min(0.1, step / 4.0) + 1e-9
    if len(xy) == 4 and xy is RECT:      # gable profile as high as the ridge
        assert nsteps == math.ceil((attic + min(0.1, step / 4.0)) / step)
    levels = np.unique(np.round(facade[:, 2], 9))
    assert np.allclose(levels, step * np.arange(0, nsteps + 1))
    fp = Polygon(xy).buffer(1e-6)
    assert all(fp.contains(Point(p)) for p in v[:, :2])
    # the front facade: 4 + 4 (nsteps - 1) corners on the street (shortest) edge
    end = outlines.street_end(xy)
    assert len(roof.faces[0]) == 4 + 4 * (nsteps - 1)
    a, b = xy[end], xy[(end + 1) % len(xy)]
    t = (b - a) / np.hypot(*(b - a))
    assert np.allclose((v[roof.faces[0], :2] - a) @ np.array([-t[1], t[0]]), 0, atol=1e-9)


def test_stepped_facades_in_bulk_match_one_by_one():
    """A batch of footprints with different step counts gives, per footprint,
    the roof it gets alone."""
    rng = np.random.default_rng(5)
    fps, hs, us = [], [], []
    for k in range(30):
        w, d = rng.uniform(5, 9), rng.uniform(10, 18)
        fps.append(np.array([[0, 0], [w, rng.uniform(-0.5, 0.5)], [w, d], [0, d]]))
        hs.append(rng.uniform(1.5, 6.0))
        us.append(rng.random(3))
    together, kinds = make(fps, ["stepped"] * 30, hs, np.array(us))
    assert set(kinds) == {"stepped"}
    assert sum(r is not None for r in together) >= 25
    for k in range(30):
        alone, _ = make([fps[k]], ["stepped"], [hs[k]], np.array([us[k]]))
        assert (together[k] is None) == (alone[0] is None)
        if together[k] is None:
            continue
        assert together[k].faces == alone[0].faces
        assert together[k].chains == alone[0].chains
        assert np.allclose(together[k].vertices, alone[0].vertices, atol=1e-9)


def _closed(faces, boundary):
    """True when every directed edge of ``faces`` has its reverse, but the ``boundary`` ones."""
    edges = {(a, b) for f in faces for a, b in zip(f, f[1:] + f[:1])}
    return all((b, a) in edges or (a, b) in boundary for a, b in edges)


def test_weld_and_merge_needles_keep_the_roof_closed():
    # a pyramid over the unit square (apex 4) with a needle along its edge 0 - 4:
    # vertex 5 lies 0.3 mm off that edge, and vertex 6 0.2 mm from the apex
    v = np.array([[0, 0, 0], [2, 0, 0], [2, 2, 0], [0, 2, 0], [1, 1, 1],
                  [0.5, 0.5 + 3e-4, 0.5], [1.0002, 1, 1]], dtype=float)
    boundary = {(0, 1), (1, 2), (2, 3), (3, 0)}
    faces = [[0, 1, 4], [1, 2, 4], [2, 3, 6], [2, 6, 4], [3, 0, 5], [3, 5, 4, 6], [0, 4, 5]]
    assert _closed(faces, boundary)
    welded = roof_skeleton.weld(v, faces, fixed=4)
    assert [2, 6, 4] not in welded and [2, 3, 4] in welded and _closed(welded, boundary)
    merged = roof_skeleton.merge_needles(v, welded)
    assert [0, 4, 5] not in merged and [0, 1, 4] not in merged and len(merged) == 6
    assert [4, 5, 1] in merged and [5, 0, 1] in merged and all(len(f) == 3 for f in merged)
    assert _closed(merged, boundary)
    # nothing to do: the same faces
    plain = [[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]]
    assert roof_skeleton.weld(v, plain, 4) == plain == roof_skeleton.merge_needles(v, plain)
