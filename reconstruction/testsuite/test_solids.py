"""Solids: every building is one closed, valid shell; the validator finds each defect."""

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from shapely.geometry import Polygon

from reconstruction import roofs, solids

ORIGIN = np.array([85123.4567, 446789.0123])
RECT = np.array([[0.0, 0.0], [12.0, 0.0], [12.0, 6.0], [0.0, 6.0]])


def build(xy, kind, ground=1.0, eaves=8.0, attic=3.0, u=0.5, **kw):
    xy, why = solids.clean_ring(np.asarray(xy, dtype=float) + ORIGIN)
    assert why is None
    return solids.build_solids([xy], [ground], [eaves], [attic], [kind], np.full((1, 3), u), **kw)


def box_solidset():
    v = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0],
                  [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]], dtype=float)
    faces = [[3, 2, 1, 0], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]]
    return v, faces


def test_box_is_valid_with_semantics_and_volume():
    v, faces = box_solidset()
    ss = solids.to_solidset([(v, faces)], np.zeros((1, 2)))
    assert solids.validate(ss) == [None]
    assert list(solids.semantics(ss)) == [solids.GROUND, solids.ROOF] + [solids.WALL] * 4
    assert solids.volumes(ss)[0] == pytest.approx(1.0)


@pytest.mark.parametrize("defect,reason", [
    ("flip", "edge used twice in the same direction"),
    ("extra", "edge used more than twice"),
    ("touching", "non-manifold vertex"),
    ("missing", "edge used only once"),
    ("inward", "zero or negative volume"),
    ("nonplanar", "non-planar face"),
    ("bowtie", "self-intersecting ring"),
    ("bowtie5", "self-intersecting ring"),
    ("two", "more than one shell"),
])
def test_validator_reports_each_defect(defect, reason):
    v, faces = box_solidset()
    if defect == "flip":
        faces[1] = faces[1][::-1]
    elif defect == "touching":
        # two boxes sharing one corner vertex: closed, but not a 2-manifold there
        v2 = np.vstack([v, v[1:] + [1, 1, 1]])
        remap = {0: 6}
        remap.update({k: k + 7 for k in range(1, 8)})
        faces = faces + [[remap[k] for k in f] for f in faces]
        v = v2
    elif defect == "extra":
        faces = faces + [[0, 1, 2]]
    elif defect == "missing":
        faces = faces[:-1]
    elif defect == "inward":
        faces = [f[::-1] for f in faces]
    elif defect == "nonplanar":
        v[6, 2] = 1.01
    elif defect == "bowtie":
        v[6] = [1.6, 1.6, 1.0]
        faces[1] = [4, 5, 7, 6]
    elif defect == "bowtie5":
        v = np.vstack([v, [[0.5, -0.2, 1.0]]])
        faces[1] = [4, 8, 5, 7, 6]
        faces[2] = [0, 1, 5, 8, 4]
    elif defect == "two":
        v2 = np.vstack([v, v + [3, 0, 0]])
        faces = faces + [[k + 8 for k in f] for f in faces]
        v = v2
    ss = solids.to_solidset([(v, faces)], np.zeros((1, 2)))
    res = solids.validate(ss)
    assert res[0] is not None and reason in res[0], res


@pytest.mark.parametrize("lift", [0.0, 0.002, 0.003, 0.0034, 0.0047, 0.005, 0.02])
def test_planarity_is_the_least_squares_distance(lift):
    """A corner of a 10 m box lifted by ``lift``: the face is non-planar
    exactly when a vertex is more than 1 mm from its least-squares plane (for
    a square, lift / 4, on the millimetre grid), whether or not the cheap
    bound decides it."""
    v, faces = box_solidset()
    v = v * 10.0
    v[6, 2] += lift
    v = np.rint(v * 1000.0) / 1000.0
    ss = solids.to_solidset([(v, faces)], np.zeros((1, 2)))
    worst = 0.0
    for f in faces:
        pts = v[f] - v[f].mean(axis=0)
        normal = np.linalg.svd(pts)[2][-1]
        worst = max(worst, np.abs(pts @ normal).max())
    res = solids.validate(ss)[0]
    assert (res is not None and "non-planar" in res) == (worst > solids.PLANARITY_TOL)


def test_duplicate_consecutive_vertices_are_removed_and_degenerate_rings_flagged():
    v, faces = box_solidset()
    faces[1] = [4, 4, 5, 6, 7]
    ss = solids.to_solidset([(v, faces)], np.zeros((1, 2)))
    assert solids.validate(ss) == [None]
    assert np.diff(ss.face_start)[1] == 4
    v2 = v.copy()
    v2[5] = v2[4] + [0.0001, 0, 0]       # 0.1 mm apart: one vertex on the mm grid
    ss = solids.to_solidset([(v2, faces)], np.zeros((1, 2)))
    assert solids.validate(ss)[0] is not None


def test_clean_ring_removes_duplicates_and_collinear_points_and_orients():
    ring = [[0, 0], [0, 5], [0, 5.0001], [5, 5], [5, 2.5], [5, 0], [0, 0]]
    xy, why = solids.clean_ring(ring)
    assert why is None
    assert len(xy) == 4
    area2 = np.sum(xy[:, 0] * np.roll(xy[:, 1], -1) - np.roll(xy[:, 0], -1) * xy[:, 1])
    assert area2 > 0
    assert solids.clean_ring([[0, 0], [1, 0], [2, 0]])[0] is None


def test_clean_rings_in_bulk_match_clean_ring():
    rng = np.random.default_rng(2)
    polys = [Polygon([[0, 0], [0, 5], [0, 5.0001], [5, 5], [5, 2.5], [5, 0]]),
             Polygon([[0, 0], [4, 0], [4, 3]]), Polygon([[0, 0], [0, 3], [4, 3], [4, 0]]),
             Polygon([[0, 0], [1, 0], [2, 0], [1, 0.0001]])]
    for _ in range(30):
        pts = rng.uniform(0, 20, (int(rng.integers(3, 9)), 2))
        polys.append(Polygon(pts).convex_hull)
    rings, reasons = solids.clean_rings(polys)
    for poly, ring, why in zip(polys, rings, reasons):
        one, one_why = solids.clean_ring(np.asarray(poly.exterior.coords))
        assert why == one_why
        if one is None:
            assert ring is None
        else:
            assert np.array_equal(ring, one)


@pytest.mark.parametrize("kind", roofs.ROOF_TYPES)
def test_every_roof_type_on_a_rectangle(kind):
    ss, kept, got, log = build(RECT, kind)
    assert list(kept) == [0] and got[0] == kind and not log
    assert solids.validate(ss) == [None]
    sem = solids.semantics(ss)
    assert (sem == solids.GROUND).sum() == 1
    vol = solids.volumes(ss)[0]
    prism = 12 * 6 * 8
    if kind == "flat":
        assert vol == pytest.approx(prism, rel=1e-6)
    else:
        assert prism < vol < prism + 12 * 6 * 3
    v, faces = ss.solid(0)
    assert v[:, 2].min() == pytest.approx(1.0)
    top = 1.0 + 8.0 + (0.0 if kind == "flat" else 3.0)
    if kind != "stepped":
        assert v[:, 2].max() == pytest.approx(top, abs=1e-3)


def test_gable_volume_is_exact():
    ss, *_ = build(RECT, "gable", eaves=5.0, attic=3.0)
    assert solids.volumes(ss)[0] == pytest.approx(12 * 6 * 5 + 0.5 * 6 * 3 * 12, rel=1e-6)


def test_walls_and_ground_semantics_and_orientation():
    ss, *_ = build(RECT, "hip")
    v, faces = ss.solid(0)
    sem = solids.semantics(ss)
    assert list(sem).count(solids.WALL) == 4
    assert list(sem).count(solids.ROOF) == 4


# ---------------------------------------------------------------------------
# Property tests: every solid is valid
# ---------------------------------------------------------------------------

def rotate(xy, angle):
    c, s = math.cos(angle), math.sin(angle)
    return xy @ np.array([[c, s], [-s, c]])


angles = st.floats(0, 2 * math.pi)
kinds = st.sampled_from(roofs.ROOF_TYPES)
heights = st.tuples(st.floats(2.0, 40.0), st.floats(0.0, 25.0))


def assert_all_valid(footprints, kind, eaves, attic, u=0.5):
    fps = []
    for xy in footprints:
        c, why = solids.clean_ring(xy + ORIGIN)
        if c is not None and solids.ring_is_simple(c) and Polygon(c).area > 0.01:
            fps.append(c)
    if not fps:
        return
    B = len(fps)
    ss, kept, got, log = solids.build_solids(fps, np.zeros(B), np.full(B, eaves),
                                             np.full(B, attic), [kind] * B, np.full((B, 3), u))
    assert len(kept) == B, log
    assert solids.validate(ss) == [None] * B
    assert np.all(solids.volumes(ss) > 0)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(w=st.floats(0.3, 30), d=st.floats(0.3, 40), skew=st.floats(-0.45, 0.45),
       taper=st.floats(-0.45, 0.45), a=angles, kind=kinds, h=heights, u=st.floats(0, 0.999))
def test_quads_rectangles_trapezoids_slanted(w, d, skew, taper, a, kind, h, u):
    xy = np.array([[0, 0], [d, skew * w], [d + taper * w, w + skew * w], [0, w]])
    if not roofs.is_convex(solids.clean_ring(xy)[0] if solids.clean_ring(xy)[0] is not None else xy):
        return
    assert_all_valid([rotate(xy, a)], kind, h[0], h[1], u)


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(n=st.integers(3, 12), r=st.floats(1.0, 25), jitter=st.lists(st.floats(0.6, 1.0), min_size=12,
       max_size=12), a=angles, kind=kinds, h=heights)
def test_convex_ngons(n, r, jitter, a, kind, h):
    t = np.linspace(0, 2 * math.pi, n, endpoint=False)
    xy = np.column_stack([np.cos(t), np.sin(t)]) * r * np.array(jitter[:n])[:, None]
    hull = np.asarray(Polygon(xy).convex_hull.exterior.coords)[:-1]
    assert_all_valid([rotate(hull, a)], kind, h[0], h[1])


def l_u_t(shape, a, b, c):
    if shape == "L":
        return np.array([[0, 0], [a, 0], [a, c], [c, c], [c, b], [0, b]])
    if shape == "U":
        return np.array([[0, 0], [a, 0], [a, b], [a - c, b], [a - c, c], [c, c], [c, b], [0, b]])
    return np.array([[0, 0], [a, 0], [a, c], [(a + c) / 2, c], [(a + c) / 2, b],
                     [(a - c) / 2, b], [(a - c) / 2, c], [0, c]])


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(shape=st.sampled_from("LUT"), a=st.floats(8, 40), b=st.floats(8, 40),
       frac=st.floats(0.15, 0.4), ang=angles, kind=kinds, h=heights)
def test_concave_l_u_t(shape, a, b, frac, ang, kind, h):
    c = frac * min(a, b)
    assert_all_valid([rotate(l_u_t(shape, a, b, c), ang)], kind, h[0], h[1])


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(w=st.floats(0.005, 0.3), d=st.floats(0.01, 50), a=angles, kind=kinds,
       h=st.tuples(st.floats(0.5, 60.0), st.floats(0.0, 40.0)))
def test_thin_tiny_and_extreme_heights(w, d, a, kind, h):
    xy = np.array([[0, 0], [d, 0], [d, w], [0, w]])
    assert_all_valid([rotate(xy, a)], kind, h[0], h[1])


def test_many_roofs_in_bulk_keep_each_building():
    rng = np.random.default_rng(5)
    fps = []
    for i in range(300):
        w, d = rng.uniform(4, 10), rng.uniform(8, 20)
        xy = np.array([[0, 0], [d, rng.uniform(-1, 1)], [d, w], [0, w]]) + [i * 25, 0]
        fps.append(solids.clean_ring(xy + ORIGIN)[0])
    kinds_ = rng.choice(roofs.ROOF_TYPES, 300)
    ss, kept, got, log = solids.build_solids(fps, np.zeros(300), np.full(300, 9.0),
                                             np.full(300, 3.5), kinds_, rng.random((300, 3)))
    assert len(kept) == 300
    assert solids.validate(ss) == [None] * 300
    # each solid sits on its own footprint
    for s in (0, 150, 299):
        v, _ = ss.solid(s)
        assert Polygon(fps[s]).buffer(0.002).contains(Polygon(v[v[:, 2] == 0][:, :2]).convex_hull)


def test_parallel_build_gives_the_same_solids():
    rng = np.random.default_rng(8)
    B = 3100
    fps = []
    for i in range(B):
        w, d = rng.uniform(4, 10), rng.uniform(8, 20)
        xy = np.array([[0, 0], [d, rng.uniform(-1, 1)], [d, w], [0, w]]) + [i * 25.0, 0]
        fps.append(solids.clean_ring(xy + ORIGIN)[0])
    kinds_ = rng.choice(roofs.ROOF_TYPES, B)
    u = rng.random((B, 3))
    args = (fps, np.zeros(B), np.full(B, 9.0), np.full(B, 3.5), kinds_, u)
    a = solids.build_solids(*args)
    b = solids.build_solids_parallel(*args, nprocs=2)
    assert np.array_equal(a[1], b[1]) and list(a[2]) == list(b[2])
    c = solids.build_solids_parallel(*args, nprocs=3)
    assert np.array_equal(a[1], c[1]) and list(a[2]) == list(c[2]) and sorted(a[3]) == sorted(c[3])
    assert np.array_equal(solids.semantics(a[0]), solids.semantics(c[0]))
    # the same model is written (vertices are stored in a global order)
    from reconstruction import cityjson

    models = [cityjson.citymodel(r[0], solids.semantics(r[0]), list(r[1]), {"t": list(r[2])})
              for r in (a, b)]
    assert models[0] == models[1]
    for s in (0, 1549, 1550, 2066, 2067, 3099):
        va, fa = a[0].solid(s)
        vb, fb = b[0].solid(s)
        assert len(fa) == len(fb)
        assert np.array_equal(np.unique(va, axis=0), np.unique(vb, axis=0))


def test_stepped_solids_in_bulk_are_valid_with_pentagon_walls():
    """Crow-stepped gables built in bulk (flat arrays, walls next to the
    facade are pentagons) are valid and equal the solids assembled from each
    building's roof dict."""
    rng = np.random.default_rng(8)
    fps = []
    for k in range(40):
        w, d = rng.uniform(5, 9), rng.uniform(10, 18)
        xy = [[0, 0], [w, rng.uniform(-0.8, 0.8)], [w + rng.uniform(-0.8, 0.8), d], [0, d]]
        if k % 4 == 3:
            xy = [[0, 0], [w, 0], [w + 2, d / 2], [w, d], [0, d]]
        fps.append(solids.clean_ring(np.array(xy) + ORIGIN + [30.0 * k, 0])[0])
    B = len(fps)
    u = rng.random((B, 3))
    h = rng.uniform(1.5, 6, B)
    ss, kept, types, log = solids.build_solids(fps, np.ones(B), np.full(B, 7.0), h,
                                               ["stepped"] * B, u)
    assert len(kept) == B and all(r is None for r in solids.validate(ss))
    assert np.mean(types == "stepped") > 0.9
    assert solids.volumes(ss).min() > 0
    origins = np.array([xy[0] for xy in fps])
    local = [xy - o for xy, o in zip(fps, origins)]
    rf, kinds = roofs.make_roofs(local, ["stepped"] * B, h, u)
    for k in np.nonzero(types == "stepped")[0]:
        shell = solids.assemble(local[k], rf[k], 1.0, 7.0)
        one = solids.to_solidset([shell], origins[k:k + 1])
        mine = solids.take(ss, [k])
        assert np.array_equal(one.vertices[one.rings], mine.vertices[mine.rings])
        assert np.array_equal(one.face_start, mine.face_start)


def test_concave_roofs_built_beside_give_the_same_model():
    """Concave footprints' skeleton roofs are built in a thread beside the
    others: the same solids, types, log and file as one pass over all."""
    if not roofs.cgal_available():
        pytest.skip("pySVCGAL not installed")
    from reconstruction import cityjson

    rng = np.random.default_rng(12)
    fps = []
    for i in range(60):
        w, d = rng.uniform(5, 9), rng.uniform(10, 18)
        if i % 3 == 0:
            xy = np.array([[0, 0], [d, 0], [d, w / 2], [w / 2, w / 2], [w / 2, d], [0, d]])
        else:
            xy = np.array([[0, 0], [w, rng.uniform(-0.8, 0.8)], [w, d], [0, d]])
        fps.append(solids.clean_ring(xy + ORIGIN + [i * 25.0, 0])[0])
    B = len(fps)
    kinds_ = rng.choice(roofs.ROOF_TYPES, B)
    args = (fps, np.zeros(B), np.full(B, 9.0), rng.uniform(0.5, 5, B), kinds_, rng.random((B, 3)))
    a = solids.build_solids(*args)
    b = solids._build_solids(*args)
    assert np.array_equal(a[1], b[1]) and list(a[2]) == list(b[2])
    assert sorted(a[3]) == sorted(b[3])
    texts = [cityjson.citymodel_text(r[0], solids.semantics(r[0]), list(r[1]), {"t": list(r[2])})
             for r in (a, b)]
    assert texts[0] == texts[1]
    assert all(r is None for r in solids.validate(a[0]))


def test_footprint_polygons_parts_holes_and_empties():
    from shapely.geometry import GeometryCollection, MultiPolygon, box

    courtyard = Polygon([(0, 0), (10, 0), (10, 10), (0, 10)], [[(2, 2), (4, 2), (4, 4), (2, 4)]])
    geoms = [box(0, 0, 1, 1), None, MultiPolygon([box(0, 0, 1, 1), box(2, 0, 3, 1)]),
             Polygon(), courtyard, MultiPolygon([box(5, 5, 6, 6)]),
             GeometryCollection([box(0, 0, 1, 1)]), box(7, 7, 8, 8)]
    polys, src, part, holes, empty = solids.footprint_polygons(geoms, skip=[0, 0, 0, 0, 0, 0, 0, 1])
    assert list(src) == [0, 2, 2, 4, 5]
    assert list(part) == [-1, 0, 1, -1, -1]
    assert polys[2].equals(box(2, 0, 3, 1)) and polys[3].equals(courtyard)
    assert holes == 1 and empty == 2
    none = solids.footprint_polygons([])
    assert len(none[0]) == 0 and none[3:] == (0, 0)


def test_semantics_from_the_normals_kept_since_validation():
    """build_solids keeps the face normals of validation through take and
    concat: semantics from them equal semantics computed afresh."""
    rng = np.random.default_rng(3)
    fps = [solids.clean_ring(np.array([[0, 0], [w, 0], [w, d], [0, d]]) + ORIGIN + [20.0 * i, 0])[0]
           for i, (w, d) in enumerate(zip(rng.uniform(5, 9, 30), rng.uniform(10, 18, 30)))]
    B = len(fps)
    ss, kept, types, log = solids.build_solids(fps, np.zeros(B), np.full(B, 7.0),
                                               rng.uniform(0.5, 5, B),
                                               rng.choice(roofs.ROOF_TYPES, B), rng.random((B, 3)))
    assert ss.face_normal is not None and len(ss.face_normal) == len(ss.face_start) - 1
    fresh = solids.SolidSet(ss.vertices, ss.rings, ss.face_start, ss.solid_start)
    assert np.array_equal(solids.semantics(ss), solids.semantics(fresh))
    part = solids.take(ss, [5, 2, 7])
    assert np.array_equal(solids.semantics(part), solids.semantics(
        solids.SolidSet(part.vertices, part.rings, part.face_start, part.solid_start)))
