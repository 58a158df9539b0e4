"""testsuite/lod2_ends.py, the roof ends read back from a model's geometry, without GRASS."""

import json

import numpy as np
from shapely.geometry import Polygon, box

import lod2_ends as le
from reconstruction.lod2 import stage as lod2

X0, Y0 = 85000.0, 446000.0


def model(geoms, types, eaves=9.0, attic=4.0):
    """The CityJSON document v.histo.lod2 writes for ``geoms`` with roofs ``types``."""
    n = len(geoms)
    heights = lod2.Heights(np.full(n, eaves), np.full(n, attic), 0.0, ground_default=0.0)
    requests = lod2.RoofRequests(np.array([types] * n, dtype=object), np.full(n, np.nan))
    config = lod2.Lod2Config(seed=1)
    result = lod2.build(lod2.prepare(lod2.Footprints(geoms), heights, requests, config), config)
    return json.loads(lod2.citymodel_text(result, 28992))


def ends(doc):
    return [row[2] for row in le.model_ends(doc)[0]]


def test_hip_and_gable_ends_of_free_standing_houses_are_found():
    houses = [box(X0, Y0, X0 + 6, Y0 + 12), box(X0 + 20, Y0, X0 + 26, Y0 + 12)]
    for kind, end in (("hip", "hip"), ("gable", "wall")):
        for oid, ring, found, shared, attrs in le.model_ends(model(houses, kind))[0]:
            length = np.hypot(*(np.roll(ring, -1, axis=0) - ring).T)
            assert found == {int(k): end for k in np.nonzero(length < 7)[0]}, (kind, oid)


def test_a_hip_roof_of_one_pitch_has_no_ends():
    ell = Polygon([(X0, Y0), (X0 + 12, Y0), (X0 + 12, Y0 + 6), (X0 + 6, Y0 + 6),
                   (X0 + 6, Y0 + 14), (X0, Y0 + 14)])
    assert ends(model([ell], "hip")) == [{}]


def test_a_sliver_face_a_few_millimetres_high_sets_no_pitch():
    """The skeleton's sliver face over a very short edge, its vertices rounded
    to the millimetre, can be degrees shallower than the long faces: it is
    not the long faces' pitch, else every face of the roof is a 'hip end'."""
    doc = model([Polygon([(X0, Y0), (X0 + 12, Y0), (X0 + 12, Y0 + 6), (X0 + 6, Y0 + 6),
                          (X0 + 6, Y0 + 14), (X0, Y0 + 14)])], "hip")
    oid, ring, walls, roofs, attrs = le.buildings(doc)[0]
    z = attrs["ground_height"] + attrs["eaves_height"]
    pitch = max(le._pitch(f) for f in roofs)
    assert le.ends_of(ring, walls, roofs, z) == {}
    # a sliver on edge 0: 11 mm high, 2 degrees shallower than the long faces
    a, b = ring[0], ring[1]
    u = (b - a) / np.linalg.norm(b - a)
    inward = np.array([-u[1], u[0], 0.0])
    rise = 0.011
    run = rise / np.tan(np.radians(pitch - 2.0))
    top = a + 0.003 * u + run * inward + [0, 0, rise]
    sliver = np.array([a + [0, 0, z], a + 0.006 * u + [0, 0, z], top + [0, 0, z]])
    assert le._pitch(sliver) < pitch - 1.5
    assert le.ends_of(ring, walls, roofs + [sliver], z) == {}
    # a needle up the slope from the eaves, its second vertex 2 cm up and 1 mm off the line
    top = a + 2.0 * u + 2.0 / np.tan(np.radians(pitch)) * inward + [0, 0, 2.0]
    needle = np.array([a, 0.01 * top + 0.99 * a + 1e-3 * inward, top]) + [0, 0, z]
    assert le._pitch(needle) < pitch - 1.5 and np.ptp(needle[:, 2]) > 1.0
    assert le.ends_of(ring, walls, roofs + [needle], z) == {}


def test_a_wall_leaning_within_the_wall_angle_is_a_wall_end():
    """v.histo.lod2 makes a face a WallSurface when it is vertical within 5
    degrees: such a face rising above the eaves on an edge is a wall end, as
    the near-vertical lower faces of a mansard capped by a millimetre edge were."""
    doc = model([box(X0, Y0, X0 + 6, Y0 + 12)], "flat")
    oid, ring, walls, roofs, attrs = le.buildings(doc)[0]
    z = attrs["ground_height"] + attrs["eaves_height"]
    a, b = ring[0], ring[1]
    u = (b - a) / np.linalg.norm(b - a)
    inward = np.array([-u[1], u[0], 0.0]) * 2.0 * np.tan(np.radians(3.0))   # 3 degrees over 2 m
    up = np.array([0, 0, z + 2.0])
    lean = np.array([a + [0, 0, z], b + [0, 0, z], b + inward + up, a + inward + up])
    assert le.ends_of(ring, walls, roofs, z) == {}
    assert le.ends_of(ring, walls + [lean], roofs, z) == {0: "wall"}
