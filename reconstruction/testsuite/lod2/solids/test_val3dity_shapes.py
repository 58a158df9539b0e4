"""Property test with val3dity as oracle (issue 11): LoD2 solids of generated
footprints (concave L/U/T, many-vertex cadastre-like outlines, very steep and
very flat roofs, every roof type) written to CityJSON are valid by val3dity,
as by the module's own validator. Skips where val3dity cannot run."""

import dataclasses
import math

import numpy as np
import shapely
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st
from shapely.geometry import Polygon, box

from reconstruction.cityjson import model as cityjson
from reconstruction.lod2 import outlines
from reconstruction.lod2.roofs import plan as roofs
from reconstruction.lod2.solids import build as solids
from reconstruction.geom import solidset
from reconstruction.lod2.solids import validation
from reconstruction.testsuite.lod2.solids.test_solids import l_u_t
from val3dity import require_val3dity, val3dity_report

ORIGIN = np.array([85123.4567, 446789.0123])


def cadastre_like(rng, n_boxes):
    """A concave outline of many vertices: the union of overlapping boxes,
    slightly jittered (as footprints aligned on the cadastre)."""
    shape = box(0, 0, rng.uniform(8, 20), rng.uniform(8, 20))
    for _ in range(n_boxes):
        x, y = rng.uniform(0, 15, 2)
        shape = shape.union(box(x, y, x + rng.uniform(2, 9), y + rng.uniform(2, 9)))
    if shape.geom_type != "Polygon":
        shape = max(shape.geoms, key=lambda g: g.area)
    xy = np.asarray(shape.exterior.coords)[:-1]
    return xy + rng.normal(0, 0.02, xy.shape)


def rotate(xy, angle):
    c, s = math.cos(angle), math.sin(angle)
    return xy @ np.array([[c, s], [-s, c]])


def shape_buildings(seed, attic, eaves):
    """Six L/U/T and six cadastre-like footprints drawn from ``seed``, every
    roof type in turn, as :class:`~reconstruction.lod2.solids.build.Buildings`."""
    rng = np.random.default_rng(seed)
    footprints = []
    for k, shape in enumerate("LUTLUT"):
        a, b = rng.uniform(8, 40, 2)
        footprints.append(l_u_t(shape, a, b, rng.uniform(0.15, 0.4) * min(a, b)))
    footprints.extend(cadastre_like(rng, int(rng.integers(2, 8))) for _ in range(6))
    fps = []
    for k, xy in enumerate(footprints):
        c, why = outlines.clean_ring(rotate(xy, rng.uniform(0, 2 * math.pi)) + ORIGIN + [60.0 * k, 0])
        if c is not None and outlines.ring_is_simple(c) and Polygon(c).area > 1:
            fps.append(c)
    B = len(fps)
    kinds = [roofs.ROOF_TYPES[k % len(roofs.ROOF_TYPES)] for k in range(B)]
    return solids.Buildings(fps, np.zeros(B), np.full(B, eaves), np.full(B, attic), kinds,
                            rng.random((B, 3)))


def shapes(seed, attic, eaves):
    """Solids of :func:`shape_buildings`: (count, SolidSet, kept, fallbacks)."""
    buildings = shape_buildings(seed, attic, eaves)
    built = solids.build_solids(buildings)
    return len(buildings), built.solids, built.kept, built.log


@settings(max_examples=24, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(seed=st.integers(0, 2 ** 31), attic=st.sampled_from([0.05, 0.3, 3.0, 12.0, 40.0]),
       eaves=st.floats(2.0, 30.0))
# a crow-stepped facade of 25 steps whose corners, rounded to the millimetre,
# make a sliver in val3dity's triangulation (error 204; found by the explore profile)
@example(seed=1947, attic=12.0, eaves=2.0)
def test_generated_footprints_valid_by_val3dity(tmp_path_factory, seed, attic, eaves):
    require_val3dity()
    B, ss, kept, log = shapes(seed, attic, eaves)
    assert len(kept) == B, log
    assert validation.validate(ss) == [None] * B
    path = str(tmp_path_factory.mktemp("v3") / "shapes.city.json")
    ids = ["building_{}".format(k) for k in range(B)]
    cityjson.write_text(path, cityjson.citymodel_text(ss, solidset.semantics(ss), ids))
    report = val3dity_report(path)
    assert report.valid == report.objects == B, str(report)


def test_a_sliver_of_val3ditys_triangulation_makes_the_roof_fall_back():
    """The module's own check triangulates each face on its plane, as
    val3dity does: the 25-step facade of the example above had a sliver
    deviating 39 degrees on its back face (three inner corners, collinear
    but for the millimetre rounding, with no vertex on the gable profile
    below them), and its roof fell back to a gable. Its back face now has
    the profile's points under the inner corners (issue 33, item 6): the
    roof is stepped and valid; built without them, the sliver is found
    again, without val3dity."""
    B, ss, kept, log = shapes(1947, 12.0, 2.0)
    assert [f for f in log if f.index == 9] == []
    assert validation.validate(ss) == [None] * B
    buildings = shape_buildings(1947, 12.0, 2.0)
    xy = buildings.footprints[9]
    local = xy - xy[0]
    rs = roofs.make_roofs([local], ["stepped"], buildings.attic[9:10], buildings.uniforms[9:10])
    assert rs.kinds == ["stepped"]
    roof = rs.each()[0]
    steps = (len(roof.faces[0]) - 4) // 4 + 1
    assert steps == 25
    under = set(range(len(roof.vertices) - 2 * (steps - 1), len(roof.vertices)))
    before = dataclasses.replace(roof, faces=[[k for k in f if k not in under]
                                              for f in roof.faces])
    for r, why in ((roof, None), (before, "non-planar face (normals deviate > 20 degrees)")):
        shell = solids.assemble(local, r, 0.0, 2.0)
        assert validation.validate(solidset.to_solidset([shell], xy[:1])) == [why]
