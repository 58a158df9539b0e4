"""Neck, bell and spout gables (issue 31): facade outlines on the street end,
inside the footprint, symmetric about the apex, a margin above the body's
gable profile, valid solids; a footprint too narrow for one gets a gable."""

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st
from shapely.geometry import Point, Polygon

from reconstruction.cityjson import model as cityjson
from reconstruction.geom import solidset
from reconstruction.lod2 import outlines
from reconstruction.lod2.roofs import facades
from reconstruction.lod2.roofs import plan as roofs
from reconstruction.lod2.solids import build as solids
from reconstruction.lod2.solids import validation
from val3dity import val3dity_problem, val3dity_report

NEW = ("neck", "bell", "spout")
ORIGIN = np.array([85000.0, 446000.0])
QUADS = {
    "rectangle": np.array([[0.0, 0.0], [7.0, 0.0], [7.0, 15.0], [0.0, 15.0]]),
    "isosceles trapezoid": np.array([[0.0, 0.0], [8.0, 0.0], [7.0, 14.0], [1.0, 14.0]]),
    "trapezoid": np.array([[0.0, 0.0], [7.0, 0.0], [8.5, 16.0], [0.0, 16.0]]),
    "slanted street edge": np.array([[0.0, 0.0], [7.0, 1.2], [7.0, 15.0], [0.0, 15.0]]),
}
SYMMETRIC = ("rectangle", "isosceles trapezoid")


def roof_of(xy, kind, attic=4.0):
    """The roof (or None) and the type make_roofs gives it, street edge 0."""
    rs = roofs.make_roofs([xy], [kind], [attic], np.full((1, 3), 0.5), street=[0])
    return rs.each()[0], rs.kinds[0]


def outline(xy, roof):
    """The front facade's corners (u along street edge 0, z), left to right."""
    a, b = xy[0], xy[1]
    t = (b - a) / np.hypot(*(b - a))
    front = roof.vertices[roof.faces[0]][::-1]
    return np.column_stack([(front[:, :2] - a) @ t, front[:, 2]]), t


def body_height(xy, roof, t, u, depth):
    """The body roof's height at ``u`` along the line ``depth`` behind the
    street edge, from its faces behind the slab (not from the facade code)."""
    a = xy[0]
    nrm = np.array([-t[1], t[0]])
    m = len(roof.faces[0]) - 2
    out = np.full(len(u), -np.inf)
    for face in roof.faces[4 + m - 1:]:
        p = roof.vertices[face]
        normal = np.cross(p, np.roll(p, -1, axis=0)).sum(axis=0)        # Newell's
        if abs(normal[2]) < 1e-9 * np.linalg.norm(normal):
            continue
        poly = Polygon(p[:, :2]).buffer(1e-7)
        for k, uk in enumerate(u):
            q = a + uk * t + depth * nrm
            if poly.contains(Point(q)):
                z = p[0, 2] - (normal[0] * (q[0] - p[0, 0]) + normal[1] * (q[1] - p[0, 1])) / normal[2]
                out[k] = max(out[k], z)
    return out


@pytest.mark.parametrize("shape", sorted(QUADS))
@pytest.mark.parametrize("kind", NEW)
def test_the_facade_is_inside_symmetric_and_above_the_body(kind, shape):
    xy = QUADS[shape]
    roof, got = roof_of(xy, kind)
    assert got == kind and roof is not None
    fp = Polygon(xy).buffer(1e-6)
    used = sorted({k for f in roof.faces for k in f})
    assert all(fp.contains(Point(p)) for p in roof.vertices[used, :2])
    corners, t = outline(xy, roof)
    assert corners[0, 1] == 0 and corners[-1, 1] == 0
    # segments of 2 cm or more, no three nearly collinear corners
    d = np.diff(corners, axis=0)
    assert np.all(np.hypot(*d.T) >= 0.02)
    cross = d[:-1, 0] * d[1:, 1] - d[:-1, 1] * d[1:, 0]
    turn = np.abs(cross) / (np.hypot(*d[:-1].T) * np.hypot(*d[1:].T))
    assert np.all(turn >= math.sin(math.radians(4.9)))
    # symmetric about the apex: the part between the shoulders or kneelers on a
    # skewed footprint, all of it on a symmetric one
    top = corners[np.argmax(corners[:, 1])] if kind != "spout" else corners[4:6].mean(axis=0)
    uc = top[0]
    inner = corners[3:-3] if kind == "spout" else corners[2:-2]
    if shape in SYMMETRIC:
        inner = corners[1:-1]
    mirrored = np.column_stack([2 * uc - inner[::-1, 0], inner[::-1, 1]])
    assert np.allclose(mirrored, inner, atol=1e-9)
    # a margin above the body's roof behind the slab, along the whole facade
    u = np.linspace(corners[0, 0] + 1e-3, corners[-1, 0] - 1e-3, 400)
    z_outline = np.minimum(np.interp(u, corners[:, 0], corners[:, 1]),
                           np.interp(-u, -corners[::-1, 0], corners[::-1, 1]))
    z_body = body_height(xy, roof, t, u, 0.5 + 1e-4)
    seen = np.isfinite(z_body)
    assert seen.mean() > 0.9
    assert np.all(z_outline[seen] >= z_body[seen] + facades.MARGIN - 1e-6)
    assert corners[:, 1].max() > 4.0 + facades.MARGIN


def build(footprints, kinds, attic=4.0):
    B = len(footprints)
    rings = [outlines.clean_ring(np.asarray(xy, dtype=float) + ORIGIN)[0] for xy in footprints]
    return solids.build_solids(solids.Buildings(rings, np.zeros(B), np.full(B, 9.0),
                                                np.full(B, attic), list(kinds),
                                                np.full((B, 3), 0.5), [0] * B))


def test_every_profile_on_every_quadrilateral_is_a_valid_solid(tmp_path):
    """By the suite's validator and by val3dity (where it runs)."""
    kinds = [k for k in NEW for _ in QUADS]
    fps = [xy + [25.0 * i, 0] for i, xy in enumerate(list(QUADS.values()) * len(NEW))]
    built = build(fps, kinds)
    assert built.log == [] and list(built.types) == kinds
    assert validation.validate(built.solids) == [None] * len(kinds)
    assert np.all(solidset.volumes(built.solids) > 0)
    if val3dity_problem() is None:
        path = str(tmp_path / "gables.city.json")
        cityjson.write_text(path, cityjson.citymodel_text(
            built.solids, solidset.semantics(built.solids),
            ["b{}".format(k) for k in range(len(kinds))]))
        report = val3dity_report(path)
        assert report.valid == report.objects == len(kinds), str(report)


@pytest.mark.parametrize("kind", NEW)
def test_a_footprint_too_narrow_for_the_shape_gets_a_gable(kind):
    narrow = np.array([[0.0, 0.0], [0.8, 0.0], [0.8, 12.0], [0.0, 12.0]])
    roof, got = roof_of(narrow, kind, attic=1.5)
    assert got == kind and roof is None                  # out of the groups
    built = build([narrow], [kind], attic=1.5)
    assert list(built.types) == ["gable"] and [f.kind for f in built.log] == [kind]


def test_the_profiles_do_not_change_the_default_rules():
    assert all(set(w).isdisjoint(NEW) for w in roofs.ROOF_PROBABILITIES.values())


unit = st.floats(0.0, 1.0)


@pytest.mark.parametrize("kind", NEW)
@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(w=st.floats(1.0, 25.0), d=st.floats(3.0, 40.0), skew=st.floats(-0.4, 0.4),
       taper=st.floats(-0.4, 0.4), angle=st.floats(0, 2 * math.pi), attic=st.floats(1.0, 12.0),
       extra=st.booleans(), bulge=unit)
# a bell on a skewed square whose outline check sits on its threshold: the
# roof was built from the module's local coordinates but not from the ring's
# own (they differ in the last bits); the roof is now compared on the same ones
@example(w=6.71875, d=6.71875, skew=-0.25, taper=0.0, angle=0.0, attic=10.0, extra=False,
         bulge=0.0)
def test_a_convex_footprint_gets_a_valid_facade_or_a_gable(kind, w, d, skew, taper, angle, attic,
                                                          extra, bulge):
    """Quadrilaterals (rectangles, trapezoids, slanted street edges) and
    pentagons: every roof is built valid with its facade, or is in no group
    and the building gets a gable."""
    xy = np.array([[0, 0], [w, skew * w], [w + taper * w, d], [0, d]], dtype=float)
    if extra:
        xy = np.insert(xy, 2, [w + (0.2 + bulge) * abs(taper * w) + 0.2 * bulge,
                               skew * w + (d - skew * w) / 2], axis=0)
    ring, why = outlines.clean_ring(xy)
    if ring is None or not outlines.is_convex(ring) or Polygon(ring).area < 1.0:
        return
    c, s = math.cos(angle), math.sin(angle)
    ring = ring @ np.array([[c, s], [-s, c]])
    placed = ring + ORIGIN
    built = solids.build_solids(solids.Buildings([placed], [0.0], [9.0], [attic], [kind],
                                                 np.full((1, 3), 0.5)))
    assert list(built.kept) == [0]
    assert validation.validate(built.solids) == [None]
    # the local coordinates build_solids gives the roof (origin: the first vertex)
    rs = roofs.make_roofs([placed - placed[0]], [kind], [attic], np.full((1, 3), 0.5))
    roof = rs.each()[0]
    if built.types[0] == kind:
        assert built.log == [] and roof is not None
    elif rs.kinds[0] == kind:               # planned, out of the groups or invalid: fell back
        assert built.types[0] in ("gable", "mansard", "flat")
        assert built.log and built.log[0].kind == kind
    else:                                   # no room for the strip: planned as a gable
        assert rs.kinds[0] in ("gable", "hip") and built.types[0] in ("gable", "hip", "mansard",
                                                                      "flat")
