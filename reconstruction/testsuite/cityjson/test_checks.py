"""Broken existing models (issue 33, items 1 and 2): refused as a whole
with one InputError, or the broken building left out and named."""

import copy
import io
import json
import os
import tempfile

import numpy as np
from hypothesis import given, settings, strategies as st

import pytest
import shapely

from reconstruction.cityjson import checks, existing
from reconstruction.cityjson import copied as citycopy
from reconstruction.core.errors import InputError

CUBE = [[[[0, 3, 2, 1]], [[4, 5, 6, 7]], [[0, 1, 5, 4]], [[1, 2, 6, 5]], [[2, 3, 7, 6]],
         [[3, 0, 4, 7]]]]

SEMANTICS = {"surfaces": [{"type": "GroundSurface"}, {"type": "RoofSurface"},
                          {"type": "WallSurface"}], "values": [[0, 1, 2, 2, 2, 2]]}


def cube_vertices(x0):
    return [[x0 + dx, dy, dz] for dz in (0, 5000) for dx, dy in
            ((0, 0), (4000, 0), (4000, 4000), (0, 4000))]


def building(oid, boundaries=None):
    """A building with its geometry in one BuildingPart (as the 3D BAG has them)."""
    return {oid: {"type": "Building", "children": [oid + "-0"]},
            oid + "-0": {"type": "BuildingPart", "parents": [oid], "geometry": [
                {"type": "Solid", "lod": "2.2",
                 "boundaries": copy.deepcopy(CUBE if boundaries is None else boundaries),
                 "semantics": SEMANTICS}]}}


def single(buildings, **transform):
    objects, vertices = {}, []
    for k, (oid, boundaries) in enumerate(buildings):
        shifted = json.loads(json.dumps(CUBE if boundaries is None else boundaries))
        shift = len(vertices)

        def add(node):
            return [add(n) for n in node] if isinstance(node, list) else (
                node + shift if isinstance(node, int) and not isinstance(node, bool) else node)
        objects.update(building(oid, add(shifted)))
        vertices.extend(cube_vertices(10000 * k))
    return {"type": "CityJSON", "version": "2.0",
            "transform": dict({"scale": [0.001] * 3, "translate": [0, 0, 0]}, **transform),
            "CityObjects": objects, "vertices": vertices}


def sequence(buildings):
    head = {"type": "CityJSON", "version": "2.0",
            "transform": {"scale": [0.001] * 3, "translate": [0, 0, 0]},
            "CityObjects": {}, "vertices": []}
    lines = [json.dumps(head)]
    for k, (oid, boundaries) in enumerate(buildings):
        lines.append(json.dumps({"type": "CityJSONFeature", "id": oid,
                                 "CityObjects": building(oid, boundaries),
                                 "vertices": cube_vertices(10000 * k)}))
    return "\n".join(lines) + "\n"


def bent(change):
    """CUBE with ``change`` (a function of a deep copy) applied."""
    out = copy.deepcopy(CUBE)
    change(out)
    return out


def set_index(value, face=1):
    def change(b):
        b[0][face][0][0] = value
    return bent(change)


BROKEN = {
    "past": (set_index(8), "vertex index 8 is past its 8 vertices"),
    "negative": (set_index(-1), "vertex index -1 is negative"),
    "fractional": (set_index(1.5), "vertex index 1.5 is not an integer"),
    "null": (set_index(None), "vertex index null is not an integer"),
    "boolean": (set_index(True), "vertex index true is not an integer"),
    "too shallow": (CUBE[0], "where a list is expected"),
}


def read_sequence(tmp_path, buildings):
    path = tmp_path / "m.city.jsonl"
    path.write_text(sequence(buildings))
    return existing.read_model(str(path))


@pytest.mark.parametrize("kind", sorted(BROKEN))
def test_a_broken_feature_of_a_sequence_is_left_out_and_named(tmp_path, kind):
    boundaries, words = BROKEN[kind]
    model = read_sequence(tmp_path, [("a", None), ("b", boundaries), ("c", None)])
    assert model.buildings == ["a", "c"]
    assert list(model.skipped) == ["b"]
    assert "<b-0>" in model.skipped["b"] and words in model.skipped["b"]
    # the others are whole: their footprints are where their vertices are
    fps = existing.footprints(model)
    assert fps.area.tolist() == pytest.approx([16.0, 16.0])
    assert shapely.get_coordinates(fps.polygons[1])[:, 0].min() == pytest.approx(20.0)


def test_an_index_past_its_feature_does_not_take_the_next_features_vertices(tmp_path):
    """Index 8 of the first feature is the second feature's first vertex:
    valid as an index into all the vertices read, wrong for the feature."""
    model = read_sequence(tmp_path, [("a", set_index(8)), ("b", None)])
    assert model.buildings == ["b"]
    assert "past its 8 vertices" in model.skipped["a"]


@pytest.mark.parametrize("kind", sorted(BROKEN))
def test_a_broken_building_of_one_file_is_left_out_and_named(kind):
    boundaries, words = BROKEN[kind]
    if kind == "past":
        boundaries = set_index(24)          # past the 3 buildings' 24 vertices
        words = "vertex index 24 is past its 24 vertices"
    doc = single([("a", None), ("b", None), ("c", None)])
    doc["CityObjects"]["b-0"]["geometry"][0]["boundaries"] = boundaries
    model = existing.model_of(doc)
    assert model.buildings == ["a", "c"] and list(model.skipped) == ["b"]
    assert words in model.skipped["b"]
    copied = citycopy.copy_buildings(model, [0, 1])
    assert len(copied.vertices) == 16


def test_missing_children_and_no_geometry_leave_the_building_out():
    doc = single([("a", None), ("b", None), ("c", None)])
    del doc["CityObjects"]["b-0"]
    doc["CityObjects"]["c-0"]["geometry"] = []
    model = existing.model_of(doc)
    assert model.buildings == ["a"]
    assert model.skipped == {"b": 'its child "b-0" is not in the model',
                             "c": "it has no geometry"}


def test_a_geometry_without_boundaries_is_named():
    doc = single([("a", None), ("b", None)])
    del doc["CityObjects"]["b-0"]["geometry"][0]["boundaries"]
    model = existing.model_of(doc)
    assert model.skipped == {"b": "<b-0>, geometry 0 (Solid): no boundaries"}


@pytest.mark.parametrize("transform,words", [
    ({"scale": [0, 0, 0]}, "three positive numbers"),
    ({"scale": [0.001, 0.001, -0.001]}, "three positive numbers"),
    ({"scale": [0.001, 0.001]}, "three positive numbers"),
    ({"translate": [0, "x", 0]}, "three numbers"),
])
def test_a_broken_transform_refuses_the_model(transform, words):
    with pytest.raises(InputError, match=words):
        existing.model_of(single([("a", None)], **transform), "m.json")


@pytest.mark.parametrize("vertex,words", [
    ([1.5, 0, 0], "is not integer"), ([None, 0, 0], "something else than numbers"),
    ([1, 2], "x, y, z triples")])
def test_broken_vertices_refuse_the_model(vertex, words):
    doc = single([("a", None)])
    doc["vertices"][3] = vertex
    with pytest.raises(InputError, match=words):
        existing.model_of(doc, "m.json")


def test_a_sound_model_skips_nothing(bag_sample):
    import os
    for name in ("3dbag_b2.city.json", "3dbag_b2.city.jsonl"):
        model = existing.read_model(os.path.join(bag_sample, name))
        assert model.skipped == {} and len(model.buildings) == 2


def test_the_check_walks_only_the_suspects(monkeypatch):
    """The words of a problem are found by walking the suspects only."""
    walked = []
    real = checks._indices_problem

    def spy(objects, tree, count):
        walked.append(tree[0])
        return real(objects, tree, count)

    monkeypatch.setattr(checks, "_indices_problem", spy)
    doc = single([("a", None), ("b", set_index(99)), ("c", None)])
    model = existing.model_of(doc)
    assert walked == ["b"] and model.buildings == ["a", "c"]


def test_the_fast_check_agrees_with_the_walk():
    """A deep list where an index is (and the reverse) is found."""
    doc = single([("a", None), ("b", bent(lambda b: b[0][2][0].__setitem__(1, [1])))])
    assert list(existing.model_of(doc).skipped) == ["b"]
    doc = single([("a", None), ("b", bent(lambda b: b[0].__setitem__(3, 5)))])
    assert "13 where a list is expected" in existing.model_of(doc).skipped["b"]


def test_copied_solids_are_validated_as_the_generated_ones():
    from reconstruction.lod2.solids import validation

    flipped = bent(lambda b: b[0][1][0].reverse())          # the roof turned inwards
    holed = bent(lambda b: b[0][2].append([0, 1, 5]))        # a wall with an inner ring
    doc = single([("a", None), ("b", flipped), ("c", holed)])
    model = existing.model_of(doc)
    for keep in (True, False):
        solids = citycopy.copied_solids(citycopy.copy_buildings(model, [0, 1, 2],
                                                                keep_numbering=keep))
        assert solids.labels == ["<a-0> (lod 2.2)", "<b-0> (lod 2.2)"]
        assert solids.unchecked == 1
        reasons = validation.validate(solids.solids)
        assert reasons[0] is None and reasons[1] is not None
        # each solid's own vertices, on the millimetre grid
        assert len(solids.solids.vertices) == 16




@settings(max_examples=25, deadline=None)
@given(st.lists(st.tuples(st.floats(4, 30), st.floats(4, 30), st.sampled_from(
    ["flat", "hip", "gable", "mansard", "stepped"])), min_size=1, max_size=6),
    st.booleans())
def test_generated_solids_read_back_and_copied_check_as_they_were_built(rects, sequence):
    """Property: buildings as v.histo.lod2 writes them, read back as an
    existing model and copied, are all checkable and check as they did when
    built; the check of the model leaves none out."""
    from reconstruction.cityjson import model as cityjson
    from reconstruction.cityjson import seq as cityjsonseq
    from reconstruction.lod2 import stage as lod2
    from reconstruction.lod2.solids import validation

    n = len(rects)
    polygons = [shapely.box(85000 + 40 * k, 446000, 85000 + 40 * k + w, 446000 + d)
                for k, (w, d, _) in enumerate(rects)]
    result = lod2.build(lod2.prepare(
        lod2.Footprints(polygons, cats=list(range(1, n + 1)), source=["2pm"] * n),
        lod2.Heights(eaves=np.full(n, 7.0), attic=np.full(n, 4.0)),
        lod2.RoofRequests(types=np.array([r for _, _, r in rects], dtype=object),
                          years=np.full(n, np.nan))))
    built = validation.validate(result.solids)
    if sequence:
        out = io.BytesIO()
        cityjsonseq.write(out, result.solids, result.semantics, result.ids, {}, 28992)
        with tempfile.TemporaryDirectory() as folder:
            path = os.path.join(folder, "m.city.jsonl")
            with open(path, "wb") as f:
                f.write(out.getvalue())
            model = existing.read_model(path)
    else:
        model = existing.model_of(json.loads(cityjson.citymodel_text(
            result.solids, result.semantics, result.ids, {}, 28992)))
    assert model.skipped == {} and len(model.buildings) == len(result.ids)
    solids = citycopy.copied_solids(citycopy.copy_buildings(model, range(len(model.buildings)),
                                                            keep_numbering=not sequence))
    assert solids.unchecked == 0 and len(solids.labels) == len(result.ids)
    assert [r is None for r in validation.validate(solids.solids)] == [r is None for r in built]
