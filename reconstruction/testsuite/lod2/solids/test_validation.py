"""The validator finds each defect of a solid, as val3dity would."""

import numpy as np
import pytest

from reconstruction.geom import solidset
from reconstruction.lod2.solids import validation


def box_solidset():
    v = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0],
                  [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]], dtype=float)
    faces = [[3, 2, 1, 0], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]]
    return v, faces


def test_box_is_valid_with_semantics_and_volume():
    v, faces = box_solidset()
    ss = solidset.to_solidset([(v, faces)], np.zeros((1, 2)))
    assert validation.validate(ss) == [None]
    assert list(solidset.semantics(ss)) == [solidset.GROUND, solidset.ROOF] + [solidset.WALL] * 4
    assert solidset.volumes(ss)[0] == pytest.approx(1.0)


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
    ss = solidset.to_solidset([(v, faces)], np.zeros((1, 2)))
    res = validation.validate(ss)
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
    ss = solidset.to_solidset([(v, faces)], np.zeros((1, 2)))
    worst = 0.0
    for f in faces:
        pts = v[f] - v[f].mean(axis=0)
        normal = np.linalg.svd(pts)[2][-1]
        worst = max(worst, np.abs(pts @ normal).max())
    res = validation.validate(ss)[0]
    assert (res is not None and "non-planar" in res) == (worst > validation.PLANARITY_TOL)


def test_duplicate_consecutive_vertices_are_removed_and_degenerate_rings_flagged():
    v, faces = box_solidset()
    faces[1] = [4, 4, 5, 6, 7]
    ss = solidset.to_solidset([(v, faces)], np.zeros((1, 2)))
    assert validation.validate(ss) == [None]
    assert np.diff(ss.face_start)[1] == 4
    v2 = v.copy()
    v2[5] = v2[4] + [0.0001, 0, 0]       # 0.1 mm apart: one vertex on the mm grid
    ss = solidset.to_solidset([(v2, faces)], np.zeros((1, 2)))
    assert validation.validate(ss)[0] is not None
