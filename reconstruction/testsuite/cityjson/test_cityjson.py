"""CityJSON 2.0 output: schema-valid, consistent, millimetre transform, attributes."""

import json
import os

import numpy as np
import pytest
from hypothesis import given, strategies as st

from reconstruction.core import crs
from reconstruction.core.errors import InputError
from reconstruction.cityjson import model as cityjson
from reconstruction.lod2 import outlines
from reconstruction.lod2.roofs import plan as roofs
from reconstruction.lod2.solids import build as solids
from reconstruction.geom import solidset

ORIGIN = np.array([85000.1234, 446000.5678])


def model_of(kinds, crs=28992):
    fps, n = [], len(kinds)
    for i in range(n):
        xy = np.array([[0, 0], [12, 0], [12, 6], [0, 6]], dtype=float) + [i * 12.0, 0]
        fps.append(outlines.clean_ring(xy + ORIGIN)[0])
    built = solids.build_solids(solids.Buildings(fps, np.full(n, 1.5), np.full(n, 9.0),
                                np.full(n, 3.0), kinds, np.full((n, 3), 0.3)))
    ss, kept, got, log = built.solids, built.kept, built.types, built.log
    attrs = {"roof_type": list(got), "eaves_height": np.full(n, 9.0),
             "roof_height": np.full(n, 3.0), "ground_height": np.full(n, 1.5),
             "map_year": [1924] * n, "plot": [7] * n, "source": ["2pm"] * n,
             "nothing": [np.nan] * n}
    return ss, cityjson.citymodel(ss, solidset.semantics(ss), ["b{}".format(i) for i in kept],
                                  attrs, crs)


@pytest.fixture(scope="module")
def schema_dir(schemas):
    return os.path.join(schemas, "cityjson-2.0.2")


def test_schema_valid_and_consistent(schema_dir, tmp_path):
    ss, model = model_of(list(roofs.ROOF_TYPES) * 2)
    path = tmp_path / "m.city.json"
    cityjson.write(str(path), model)
    with open(path) as f:
        back = json.load(f)
    assert cityjson.schema_errors(back, schema_dir) == []
    assert cityjson.consistency_errors(back) == []
    assert len(back["CityObjects"]) == 2 * len(roofs.ROOF_TYPES)


def test_text_writer_gives_the_same_document():
    ss, model = model_of(list(roofs.ROOF_TYPES) * 3)
    n = 3 * len(roofs.ROOF_TYPES)
    attrs = {"roof_type": [model["CityObjects"][k]["attributes"]["roof_type"]
                           for k in model["CityObjects"]],
             "eaves_height": np.full(n, 9.0), "roof_height": np.full(n, 3.0),
             "ground_height": np.full(n, 1.5), "map_year": [1924] * n, "plot": [7] * n,
             "source": ["2pm"] * n, "nothing": [np.nan] * n}
    sem = solidset.semantics(ss)
    ids = ["b{}".format(i) for i in range(n)]
    text = cityjson.citymodel_text(ss, sem, ids, attrs, 28992)
    assert json.loads(text) == json.loads(json.dumps(cityjson.citymodel(ss, sem, ids, attrs, 28992)))
    # a solid without a roof surface keeps its semantics consistent
    sem2 = sem.copy()
    sem2[sem2 == solidset.ROOF] = solidset.WALL
    text = cityjson.citymodel_text(ss, sem2, ids, attrs, 28992, title="t")
    back = json.loads(text)
    assert back == json.loads(json.dumps(cityjson.citymodel(ss, sem2, ids, attrs, 28992, "t")))
    assert cityjson.consistency_errors(back) == []


def test_whole_file_against_the_schema(schema_dir):
    _, model = model_of(["hip", "stepped"])
    validator = cityjson.schema_validator(schema_dir)
    assert list(validator.iter_errors(model)) == []


def test_schema_catches_a_broken_file(schema_dir):
    _, model = model_of(["hip"])
    obj = next(iter(model["CityObjects"].values()))
    obj["geometry"][0]["lod"] = 2
    model["version"] = "1.0"
    errors = cityjson.schema_errors(model, schema_dir)
    assert len(errors) >= 2


def test_transform_metadata_and_vertices():
    ss, model = model_of(["gable", "flat"])
    assert model["type"] == "CityJSON" and model["version"] == "2.0"
    assert model["transform"]["scale"] == [0.001, 0.001, 0.001]
    assert model["metadata"]["referenceSystem"] == "https://www.opengis.net/def/crs/EPSG/0/28992"
    t = np.array(model["transform"]["translate"])
    v = np.array(model["vertices"]) * 0.001 + t
    assert v[:, 2].min() == pytest.approx(1.5)
    assert v[:, 2].max() == pytest.approx(1.5 + 9 + 3)
    assert v[:, 0].min() == pytest.approx(85000.123)
    ext = model["metadata"]["geographicalExtent"]
    assert ext[0] == pytest.approx(v[:, 0].min()) and ext[5] == pytest.approx(v[:, 2].max())
    # the two buildings share the wall between them: shared vertices are stored once
    assert len(model["vertices"]) < len(ss.vertices)
    assert cityjson.consistency_errors(model) == []


def test_building_geometry_semantics_and_attributes():
    _, model = model_of(["hip"])
    obj = model["CityObjects"]["b0"]
    assert obj["type"] == "Building"
    geom = obj["geometry"][0]
    assert geom["type"] == "Solid" and geom["lod"] == "2.0"
    shell = geom["boundaries"][0]
    types = [geom["semantics"]["surfaces"][k]["type"] for k in geom["semantics"]["values"][0]]
    assert len(types) == len(shell)
    assert types.count("GroundSurface") == 1
    assert types.count("WallSurface") == 4 and types.count("RoofSurface") == 4
    a = obj["attributes"]
    assert a["roof_type"] == "hip" and a["map_year"] == 1924 and a["source"] == "2pm"
    assert a["eaves_height"] == 9.0 and a["plot"] == 7
    assert "nothing" not in a


def test_crs_url():
    assert crs.crs_url(7415) == "https://www.opengis.net/def/crs/EPSG/0/7415"
    assert crs.crs_url("EPSG:31370").endswith("/31370")
    url = "https://www.opengis.net/def/crs/EPSG/0/28992"
    assert crs.crs_url(url) == url
    with pytest.raises(ValueError):
        crs.crs_url("RD New")


def test_consistency_checks_find_defects():
    _, model = model_of(["flat"])
    model["vertices"].append([0, 0, 0])
    shell = model["CityObjects"]["b0"]["geometry"][0]["boundaries"][0]
    shell[0][0] = [shell[0][0][0]] + shell[0][0]
    model["CityObjects"]["b0"]["geometry"][0]["semantics"]["values"][0].pop()
    errors = " | ".join(cityjson.consistency_errors(model))
    assert "orphan" in errors
    assert "duplicate consecutive" in errors
    assert "semantic values do not match" in errors


def test_text_writer_attributes_as_json_dumps():
    """Attribute values of every kind (text with quotes, commas and accents,
    booleans, big integers, infinity, NULL) and identifiers are written as
    json.dumps writes them."""
    ss, _ = model_of(["flat", "hip", "gable", "stepped"])
    sem = solidset.semantics(ss)
    attrs = {"name": ['Rue "Haute", 12', None, "caf\u00e9 \\ \n", ""],
             "flag": [True, False, None, np.True_], "big": [2 ** 62, -1, 0, None],
             "height": np.array([1.25, np.nan, np.inf, 1e-7]), "empty": [None] * 4,
             "year": np.array([1924, 1930, 1900, 2000])}
    ids = ["b,1", 'b"2', "b\u00e93", 4]
    text = cityjson.citymodel_text(ss, sem, ids, attrs, 28992)
    assert json.loads(text) == json.loads(json.dumps(cityjson.citymodel(ss, sem, ids, attrs, 28992)))
    assert json.loads(text)["CityObjects"]["b,1"]["attributes"]["name"] == 'Rue "Haute", 12'
    no_attrs = cityjson.citymodel_text(ss, sem, ids, {"empty": [None] * 4}, 28992)
    assert "attributes" not in no_attrs


def test_integer_text_as_json_dumps():
    """The numpy writer of integers gives json.dumps's text: vertices, rings
    cut per solid with face brackets, semantic values per solid."""
    rng = np.random.default_rng(4)
    v = np.concatenate([np.array([[0, 9, 10], [99, 100, 999], [1000, 10 ** 9, 10 ** 12 - 1]]),
                        rng.integers(0, 10 ** 8, (500, 3))])
    assert cityjson._vertices_text(v) == json.dumps(v.tolist(), separators=(",", ":"))
    assert cityjson._vertices_text(v[:1]) == "[[0,9,10]]"
    assert cityjson._vertices_text(np.zeros((0, 3), dtype=np.int64)) == "[]"
    sizes = rng.integers(3, 9, 60)
    face_start = np.concatenate([[0], np.cumsum(sizes)])
    solid_first_face = np.array([0, 1, 7, 20, 21, 59])
    values = rng.integers(0, 100000, int(sizes.sum()))
    pieces = cityjson._split_by_solid(values, (face_start, solid_first_face), 6, True)
    bounds = list(solid_first_face) + [60]
    for s in range(6):
        rings = [values[face_start[f]:face_start[f + 1]].tolist()
                 for f in range(bounds[s], bounds[s + 1])]
        assert "[[[" + pieces[s] + "]]]" == json.dumps([[r] for r in rings], separators=(",", ":"))
    sem = rng.integers(0, 3, 60)
    pieces = cityjson._split_by_solid(sem, np.array(bounds), 6, False)
    assert ["[" + p + "]" for p in pieces] == [
        json.dumps(sem[a:b].tolist(), separators=(",", ":")) for a, b in zip(bounds[:-1], bounds[1:])]
    with pytest.raises(ValueError):
        cityjson._int_text(np.array([1, -1]), np.zeros(2, dtype=np.int64), [","])


def test_integer_text_of_every_width_and_separator():
    """Four digits at a time: every number of digits (1 to 18, across 2**31),
    separators of 0 to 9 characters, as str() and the table give them."""
    rng = np.random.default_rng(5)
    table = ["", ",", "]],[[", "]]]],[[[[", "[[[["]
    values = np.concatenate([[0, 9, 10, 9999, 10000, 2 ** 31 - 1, 2 ** 31, 10 ** 17],
                             10 ** rng.integers(0, 18, 2000) + rng.integers(0, 10, 2000)])
    prefix = rng.integers(0, len(table), len(values))
    text, offsets = cityjson._int_text(values, prefix, table)
    pieces = [table[p] + str(v) for p, v in zip(prefix.tolist(), values.tolist())]
    assert text == "".join(pieces)
    assert offsets.tolist() == np.cumsum([0] + [len(p) for p in pieces[:-1]]).tolist()
    small = np.array([7, 0, 42])
    assert cityjson._int_text(small, np.array([1, 1, 1]), table)[0] == ",7,0,42"


nested = st.recursive(st.lists(st.integers(0, 10 ** 12), min_size=1, max_size=6),
                      lambda inner: st.lists(inner, min_size=1, max_size=4), max_leaves=40)


@given(lists=st.lists(nested, min_size=1, max_size=6), shift=st.integers(0, 10 ** 9))
def test_shifted_lists_add_the_shift_to_every_integer(lists, shift):
    """shifted_lists rewrites the numbers of nested lists' texts as json.dumps
    writes the lists with the shift added, list by list."""
    def plus(x):
        return [plus(y) for y in x] if isinstance(x, list) else x + shift

    texts = [json.dumps(x, separators=(",", ":")) for x in lists]
    assert cityjson.shifted_lists(texts, shift) == [
        json.dumps(plus(x), separators=(",", ":")) for x in lists]


@pytest.mark.parametrize("text", ["[[1,2],[]]", "[1.5]", "[-1,2]", "[null]", '["1"]', "[1e5]",
                                  "[[1,{}]]", "[9223372036854775808]"])
def test_only_plain_lists_of_indices_are_read_as_such(text):
    """An empty list (np.fromstring would read a 0), a negative or
    non-integer number, anything but numbers, or one past int64: not plain."""
    assert cityjson.plain_integers(text.encode()) is None
    assert cityjson.shifted_lists([text], 1) is None


def test_plain_lists_of_indices_are_read_in_order():
    assert cityjson.plain_integers(b"[[[0,12],[3]],[[45678]]]").tolist() == [0, 12, 3, 45678]


def test_write_text_writes_texts_and_bytes_in_order(tmp_path):
    path = tmp_path / "m.city.json"
    pieces = ['{"a":', memoryview("\"\u00e9t\u00e9\",".encode())[:-1], b',"b":', '"\u00e9"}']
    cityjson.write_text(str(path), iter(pieces))
    assert path.read_text(encoding="utf-8") == '{"a":"\u00e9t\u00e9","b":"\u00e9"}'
    assert cityjson.joined_text(pieces) == path.read_text(encoding="utf-8")


def test_write_text_leaves_no_partial_file(tmp_path):
    path = tmp_path / "m.city.json"
    cityjson.write_text(str(path), '{"type":"CityJSON"}')
    assert path.read_text() == '{"type":"CityJSON"}' and not (tmp_path / "m.city.json.part").exists()
    missing = tmp_path / "no_such_dir" / "m.city.json"
    with pytest.raises(InputError, match="Cannot write '.*no_such_dir/m.city.json': No such file"):
        cityjson.write_text(str(missing), "{}")
    assert not missing.exists() and not (tmp_path / "no_such_dir").exists()


def test_write_text_removes_the_part_file_when_writing_fails(tmp_path, monkeypatch):
    path = tmp_path / "m.city.json"

    def refuse(src, dst):
        raise OSError("disk full")

    monkeypatch.setattr(cityjson.os, "replace", refuse)
    with pytest.raises(OSError, match="disk full"):
        cityjson.write_text(str(path), "{}")
    assert list(tmp_path.iterdir()) == []


def geometry_of(kind, depth):
    leaves = st.lists(st.integers(0, 10 ** 7), min_size=1, max_size=5)
    level = leaves
    for _ in range(depth):
        level = st.lists(level, min_size=1, max_size=3)
    return level.map(lambda b: {"type": kind, "boundaries": b})


@given(geometries=st.lists(st.one_of(geometry_of("MultiPoint", 0), geometry_of("MultiSurface", 2),
                                     geometry_of("Solid", 3), geometry_of("MultiSolid", 4)),
                           min_size=1, max_size=8))
def test_boundaries_written_between_markers_as_json_dumps_writes_them(geometries):
    """The marker writer of citygeometry.texts: every geometry's boundaries as
    json.dumps writes them, whatever their depth and list lengths."""
    from reconstruction.cityjson import geometry as citygeometry

    lay = citygeometry.layout(geometries)
    assert citygeometry.texts(lay, lay.flat) == [
        json.dumps(g["boundaries"], separators=(",", ":")) for g in geometries]
