"""Footprints of many vertices (issue 12, item 1): every roof type builds,
valid, in bounded work; one hard footprint never costs the others theirs."""

import numpy as np
import pytest
import shapely
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from many_vertex_footprints import SHAPES, footprint
from reconstruction.lod2 import stage as lod2
from reconstruction.lod2 import outlines
from reconstruction.lod2.roofs import envelope as roof_envelope
from reconstruction.lod2.roofs import skeleton as roof_skeleton
from reconstruction.lod2.roofs import plan as roofs
from reconstruction.lod2.solids import build as solids
from reconstruction.lod2.solids import validation
from reconstruction.lod2.solids import vertex_budget

ORIGIN = np.array([85123.4567, 446789.0123])
BUDGET = vertex_budget.MAX_ROOF_VERTICES


def ring(shape, n, seed=0, at=(0.0, 0.0)):
    xy, why = outlines.clean_ring(footprint(shape, n, seed) + ORIGIN + np.asarray(at))
    assert why is None
    return xy


def build(rings, kinds, attic=4.0):
    B = len(rings)
    kinds = list(kinds) if not isinstance(kinds, str) else [kinds] * B
    return solids.build_solids(solids.Buildings(rings, np.zeros(B), np.full(B, 9.0),
                                                np.full(B, attic), kinds, np.full((B, 3), 0.5)))


def ground_vertices(ss, s):
    """Vertices of the ground face (the first face) of solid ``s``."""
    return len(ss.solid(s)[1][0])


# ---------------------------------------------------------------------------
# Property tests: many vertices, every shape and roof type
# ---------------------------------------------------------------------------

@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(shape=st.sampled_from(SHAPES), n=st.integers(60, 1500), seed=st.integers(0, 10 ** 6),
       kind=st.sampled_from(roofs.ROOF_TYPES), attic=st.floats(0.5, 12.0))
def test_many_vertex_footprints_give_valid_solids_within_the_budget(shape, n, seed, kind, attic):
    xy = ring(shape, n, seed)
    built = build([xy], kind, attic)
    ss, kept, got, log = built.solids, built.kept, built.types, built.log
    assert list(kept) == [0], log
    assert validation.validate(ss) == [None]
    if got[0] == "flat":
        assert ground_vertices(ss, 0) == len(xy)           # a flat roof keeps every vertex
    else:
        assert ground_vertices(ss, 0) <= BUDGET


@settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(n=st.integers(13, 80), a=st.floats(3.0, 30.0), b=st.floats(3.0, 30.0),
       turn=st.floats(0, 6.3), kind=st.sampled_from(roofs.ROOF_TYPES), attic=st.floats(0.5, 12.0))
def test_convex_footprints_either_side_of_the_envelope_limit(n, a, b, turn, kind, attic):
    t = np.linspace(0, 2 * np.pi, n, endpoint=False) + turn
    xy, _ = outlines.clean_ring(np.column_stack([a * np.cos(t), b * np.sin(t)]) + ORIGIN)
    built = build([xy], kind, attic)
    ss, kept, got, log = built.solids, built.kept, built.types, built.log
    assert list(kept) == [0], log
    assert validation.validate(ss) == [None]


@settings(max_examples=10, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(shape=st.sampled_from(SHAPES), n=st.integers(150, 3000), seed=st.integers(0, 10 ** 6))
def test_simplified_outlines_are_simple_close_and_within_the_budget(shape, n, seed):
    xy = ring(shape, n, seed)
    out = vertex_budget.simplify_rings([xy])
    simple = out.rings[0]
    if len(xy) <= BUDGET:
        return
    assert simple is not None and 3 <= len(simple) <= BUDGET
    assert outlines.ring_is_simple(simple)
    assert shapely.Polygon(simple).is_valid
    # Douglas-Peucker moves the outline by at most its tolerance; the cleaning
    # after it (millimetre grid, collinear vertices) by a little more
    distance = shapely.hausdorff_distance(shapely.Polygon(xy).exterior,
                                          shapely.Polygon(simple).exterior)
    assert distance <= 1.25 * out.tolerance[0] + 0.005


# ---------------------------------------------------------------------------
# Each guard on its own
# ---------------------------------------------------------------------------

def test_a_huge_footprint_costs_the_others_nothing():
    rng = np.random.default_rng(4)
    ordinary = []
    for i in range(40):
        w, d = rng.uniform(5, 9), rng.uniform(9, 16)
        xy = np.array([[0, 0], [d, 0], [d, w], [0, w]]) + [i * 30.0, 0.0]
        ordinary.append(outlines.clean_ring(xy + ORIGIN)[0])
    kinds = list(rng.choice(roofs.ROOF_TYPES, 40))
    alone = build(ordinary, kinds)
    huge = [ring(s, 5000, at=(0.0, 100.0 + 60 * k)) for k, s in enumerate(SHAPES)]
    mixed = build(ordinary[:20] + huge + ordinary[20:], kinds[:20] + ["hip"] * 4 + kinds[20:])
    assert len(mixed.kept) == 44
    assert validation.validate(mixed.solids) == [None] * 44
    others = [k for k in range(44) if not 20 <= k < 24]
    assert list(mixed.types[others]) == list(alone.types)
    for a, b in zip(range(40), others):
        va, fa = alone.solids.solid(a)
        vb, fb = mixed.solids.solid(b)
        assert np.array_equal(va, vb) and fa == fb


def test_lod2_reports_the_simplified_footprints():
    geoms = [shapely.Polygon(footprint("digitised", 800) + ORIGIN),
             shapely.Polygon(footprint("wavy", 800) + ORIGIN + [100.0, 0.0]),
             shapely.box(*(ORIGIN + [200.0, 0.0]), *(ORIGIN + [210.0, 8.0]))]
    result = lod2.build(lod2.prepare(
        lod2.Footprints(geoms), lod2.Heights(np.full(3, 9.0), np.full(3, 4.0)),
        lod2.RoofRequests(np.array(["hip", "flat", "hip"], dtype=object), np.full(3, np.nan))))
    assert result.report.simplified == 1
    assert list(result.roof_types) == ["hip", "flat", "hip"]


def test_unsimplifiable_outline_falls_back_to_flat(monkeypatch):
    monkeypatch.setattr(solids, "simplify_rings",
                        lambda rings: vertex_budget.Simplified([None] * len(rings),
                                                               np.full(len(rings), np.nan)))
    built = build([ring("wavy", 400)], "hip")
    ss, kept, got, log = built.solids, built.kept, built.types, built.log
    assert list(got) == ["flat"] and "cannot be simplified" in log[0].reason
    assert ground_vertices(ss, 0) == len(ring("wavy", 400))


def test_convex_footprints_of_many_vertices_use_the_skeleton():
    xy = ring("round", 60)
    assert outlines.is_convex(xy) and len(xy) > roof_envelope.MAX_VERTICES
    plan = roofs.plan_roofs([xy - xy[0]], ["hip"], [4.0], np.full((1, 3), 0.5))
    assert not plan.envelope and len(plan.skeleton) == 1


def test_envelope_batches_are_cut_without_changing_the_roofs(monkeypatch):
    rng = np.random.default_rng(2)
    fps = [outlines.clean_ring(np.array([[0, 0], [9, rng.uniform(-1, 1)], [9, 6], [0, 6]])
                               + ORIGIN + [i * 20.0, 0])[0] for i in range(30)]
    kinds = list(rng.choice(["hip", "gable", "mansard", "stepped"], 30))
    whole = build(fps, kinds)
    monkeypatch.setattr(roofs, "batch_rows", lambda n, has_top=False, raised=0: 4)
    cut = build(fps, kinds)
    assert list(cut.types) == list(whole.types)
    for s in range(30):
        assert np.array_equal(cut.solids.solid(s)[0], whole.solids.solid(s)[0])


def test_a_cgal_failure_costs_only_its_footprint(monkeypatch):
    if not roof_skeleton.cgal_available():
        pytest.skip("pySVCGAL is not installed")
    real = roof_skeleton._cgal_extrude
    fps = [ring("wavy", 60, seed=k) - ring("wavy", 60, seed=k)[0] for k in range(5)]
    bad = fps[2]

    def fails_on_bad(footprints, pitches, heights):
        if any(xy is bad for xy in footprints):
            raise RuntimeError("CGAL failed")
        return real(footprints, pitches, heights)

    monkeypatch.setattr(roof_skeleton, "_cgal_extrude", fails_on_bad)
    out = roof_skeleton.cgal_roofs(fps, [np.full(len(xy), 45.0) for xy in fps], [None] * 5)
    assert [r is None for r in out] == [False, False, True, False, False]


def test_clean_rings_one_by_one_as_in_bulk(monkeypatch):
    rng = np.random.default_rng(3)
    polys = [shapely.Polygon(footprint(s, n) + ORIGIN) for s in ("round", "curved", "wavy")
             for n in (300, 1000)]
    for _ in range(200):
        m = int(rng.integers(3, 40))
        t = np.sort(rng.uniform(0, 2 * np.pi, m))
        r = 5 + (rng.random(m) < 0.5) * rng.uniform(0, 0.002, m) \
            + (rng.random(m) < 0.3) * rng.uniform(0, 1, m)
        polys.append(shapely.Polygon(np.column_stack([r * np.cos(t), r * np.sin(t)])
                                     * rng.choice([0.001, 1.0, 100.0])))
    fast, why_fast = outlines.clean_rings(polys)
    monkeypatch.setattr(outlines, "_BULK_PASSES", 10 ** 9)
    slow, why_slow = outlines.clean_rings(polys)
    assert why_fast == why_slow
    for a, b in zip(fast, slow):
        assert (a is None and b is None) or np.array_equal(a, b)


def test_many_vertex_models_are_valid_by_val3dity(tmp_path):
    from val3dity import require_val3dity, val3dity_report

    require_val3dity()
    geoms, kinds = [], []
    for k, shape in enumerate(SHAPES):
        for j, kind in enumerate(roofs.ROOF_TYPES):
            geoms.append(shapely.Polygon(footprint(shape, 1000) + ORIGIN + [60.0 * j, 60.0 * k]))
            kinds.append(kind)
    B = len(geoms)
    result = lod2.build(lod2.prepare(
        lod2.Footprints(geoms), lod2.Heights(np.full(B, 9.0), np.full(B, 4.0)),
        lod2.RoofRequests(np.array(kinds, dtype=object), np.full(B, np.nan))))
    assert len(result.ids) == B
    path = tmp_path / "many.city.json"
    path.write_text(lod2.citymodel_text(result, "https://www.opengis.net/def/crs/EPSG/0/7415"))
    report = val3dity_report(str(path))
    assert report.valid == report.objects == B, str(report)
