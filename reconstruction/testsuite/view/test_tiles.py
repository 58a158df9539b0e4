"""Tests of reconstruction.view.tiles: 3D Tiles 1.1 read back (issue 52, item 2)."""

import dataclasses
import json
import struct

import numpy as np
import pytest

from reconstruction.core.errors import InputError
from reconstruction.epochs.dynamic import Epoch, merge_epochs
from reconstruction.testsuite.view.models import L_SHAPE, SQUARE, document
from reconstruction.testsuite.view.test_gltf import validator_issues
from reconstruction.view import build_scene, tiles

pyproj = pytest.importorskip("pyproj", reason="pyproj puts the tileset on the globe "
                                              "(requirements.txt; make deps installs it)")

RAISED = [(40, 0), (48, 0), (48, 8), (40, 8)]
NEW = [(60, 0), (66, 0), (66, 9), (60, 9)]
# glTF's component types as numpy's
DTYPES = {5120: "i1", 5121: "u1", 5122: "<i2", 5123: "<u2", 5125: "<u4", 5126: "<f4"}
SIZES = {"SCALAR": 1, "VEC3": 3}
METADATA_TYPES = {"INT32": "<i4", "UINT8": "u1"}


def dynamic_scene():
    early = document({"kept": (SQUARE, 8.0), "gone": (L_SHAPE, 9.0), "raised": (RAISED, 6.0)})
    late = document({"kept": (SQUARE, 8.0), "raised": (RAISED, 9.0), "new": (NEW, 7.0)})
    return build_scene(merge_epochs([Epoch(1880, early), Epoch(1915, late)]).document)


def read_glb(path):
    """The JSON and binary chunk of a GLB file, read from its container by hand."""
    data = path.read_bytes()
    magic, version, length = struct.unpack_from("<4sII", data)
    assert (magic, version, length) == (b"glTF", 2, len(data))
    size, kind = struct.unpack_from("<I4s", data, 12)
    assert kind == b"JSON" and size % 4 == 0
    size2, kind2 = struct.unpack_from("<I4s", data, 20 + size)
    assert kind2 == b"BIN\0"
    return json.loads(data[20:20 + size]), data[28 + size:28 + size + size2]


def view_bytes(gltf, binary, index):
    view = gltf["bufferViews"][index]
    return binary[view.get("byteOffset", 0):view.get("byteOffset", 0) + view["byteLength"]]


def accessor(gltf, binary, index):
    a = gltf["accessors"][index]
    view = gltf["bufferViews"][a["bufferView"]]
    n = SIZES[a["type"]]
    dtype = np.dtype(DTYPES[a["componentType"]])
    stride = view.get("byteStride", dtype.itemsize * n)
    start = view.get("byteOffset", 0) + a.get("byteOffset", 0)
    rows = [np.frombuffer(binary, dtype, n, start + i * stride) for i in range(a["count"])]
    return np.array(rows).reshape(a["count"], n)


def property_table(gltf, binary):
    """The first property table as {property: list of values}, decoded from its views."""
    ext = gltf["extensions"]["EXT_structural_metadata"]
    table = ext["propertyTables"][0]
    schema = ext["schema"]["classes"][table["class"]]["properties"]
    out = {}
    for name, column in table["properties"].items():
        values = view_bytes(gltf, binary, column["values"])
        if schema[name]["type"] == "STRING":
            assert column["stringOffsetType"] == "UINT32"
            offsets = np.frombuffer(view_bytes(gltf, binary, column["stringOffsets"]), "<u4")
            assert len(offsets) == table["count"] + 1
            out[name] = [values[a:b].decode("utf-8") for a, b in zip(offsets[:-1], offsets[1:])]
        else:
            out[name] = np.frombuffer(values, METADATA_TYPES[schema[name]["componentType"]]
                                      ).tolist()
            assert len(out[name]) == table["count"]
    return out


def tile_nodes(tileset):
    """Every tile of a tileset.json, depth first, with its parent (None for the root)."""
    stack = [(tileset["root"], None)]
    while stack:
        tile, parent = stack.pop()
        yield tile, parent
        stack.extend((child, tile) for child in tile.get("children", ()))


def check_tileset(tileset, directory):
    """The essentials of the 3D Tiles 1.1 schema (tileset.schema.json, tile.schema.json,
    boundingVolume.schema.json): asset.version, geometricError >= 0, a root whose every
    tile has a bounding volume, a geometric error no larger than its parent's, refine
    ADD or REPLACE where given, a transform of 16 numbers, content with a uri of a file."""
    assert tileset["asset"]["version"] == "1.1"
    root = tileset["root"]
    # a viewer draws nothing while the tileset's error (of drawing nothing) is small on
    # the screen: it is the size of the model (the box's diagonal), not a leaf's 0
    half = np.abs(np.array(root["boundingVolume"]["box"])[[3, 7, 11]])
    assert tileset["geometricError"] >= max(2 * np.linalg.norm(half) - 1e-6,
                                            root["geometricError"])
    assert root["refine"] in ("ADD", "REPLACE")
    assert len(root["transform"]) == 16 and root["transform"][15] == 1
    contents = []
    for tile, parent in tile_nodes(tileset):
        assert set(tile) <= {"boundingVolume", "geometricError", "refine", "content",
                             "children", "transform", "viewerRequestVolume", "extras"}
        box = tile["boundingVolume"]["box"]
        assert len(box) == 12 and all(np.isfinite(box))
        assert tile["geometricError"] >= 0
        assert tile.get("refine", "ADD") in ("ADD", "REPLACE")
        if parent is not None:
            assert tile["geometricError"] <= parent["geometricError"]
            assert "transform" not in tile
        if "content" in tile:
            assert (directory / tile["content"]["uri"]).is_file()
            contents.append(directory / tile["content"]["uri"])
        else:
            assert tile.get("children"), "a tile with neither content nor children"
    return contents


def features_of(directory):
    """Every feature of every tile: (its vertices in the tile, id, first year, last year,
    years text, certainty, attributes); and checks each tile's glTF: one node, a
    primitive per material, a feature id per vertex (EXT_mesh_features) naming a row of
    the one property table, every row drawn."""
    tileset = json.loads((directory / "tileset.json").read_text())
    out = []
    for path in check_tileset(tileset, directory):
        gltf, binary = read_glb(path)
        assert {"EXT_mesh_features", "EXT_structural_metadata"} <= set(gltf["extensionsUsed"])
        table = property_table(gltf, binary)
        count = gltf["extensions"]["EXT_structural_metadata"]["propertyTables"][0]["count"]
        assert len(gltf["nodes"]) == 1
        primitives = gltf["meshes"][gltf["nodes"][0]["mesh"]]["primitives"]
        assert len({p["material"] for p in primitives}) == len(primitives)
        vertices = np.zeros(count, dtype=int)
        for primitive in primitives:
            ids = primitive["extensions"]["EXT_mesh_features"]["featureIds"]
            assert ids == [{"featureCount": count, "attribute": 0, "propertyTable": 0}]
            feature = accessor(gltf, binary, primitive["attributes"]["_FEATURE_ID_0"]).ravel()
            positions = gltf["accessors"][primitive["attributes"]["POSITION"]]["count"]
            assert len(feature) == positions and feature.min() >= 0 and feature.max() < count
            assert np.array_equal(feature, np.round(feature))
            triangles = accessor(gltf, binary, primitive["indices"]).reshape(-1, 3)
            # a triangle's corners are one feature's
            assert (feature[triangles] == feature[triangles[:, :1]]).all()
            vertices += np.bincount(feature.astype(int), minlength=count)
        assert vertices.min() > 0
        out.extend((int(vertices[i]), table["id"][i], table["first_year"][i],
                    table["last_year"][i], table["years"][i], table["certainty"][i],
                    json.loads(table["attributes"][i])) for i in range(count))
    return tileset, out


def test_a_feature_per_version_with_its_id_and_years(tmp_path):
    report = tiles.write_tileset(str(tmp_path), dynamic_scene(), title="town")
    tileset, features = features_of(tmp_path)
    assert tileset["extras"]["years"] == [1880, 1915]
    assert tileset["asset"]["extras"]["title"] == "town"
    assert sorted(f[1:5] for f in features) == [
        ("gone", 1880, 1914, "1880-1914"),
        ("kept", 1880, 1915, "1880-1915"),
        ("new", 1915, 1915, "1915"),
        ("raised", 1880, 1914, "1880-1914"),
        ("raised", 1915, 1915, "1915")]
    assert all(f[6]["roof_type"] == "flat" for f in features)
    assert (report.features, report.tiles, report.depth) == (5, 1, 1)


def test_a_version_standing_twice_is_a_feature_per_span_of_years(tmp_path):
    # a version a map between two others missed stands in two spans: a feature each,
    # so that "first_year <= year <= last_year" shows exactly the year's buildings
    scene = dynamic_scene()
    kept = [k for k in range(len(scene.chunk_years))
            if scene.ids[scene.chunk_building[k]] == "kept"]
    spans = list(scene.chunk_years)
    spans[kept[0]] = ((1880, 1890), (1900, 1915))
    tiles.write_tileset(str(tmp_path), dataclasses.replace(scene, chunk_years=tuple(spans)))
    _tileset, features = features_of(tmp_path)
    assert sorted(f[1:5] for f in features if f[1] == "kept") == [
        ("kept", 1880, 1890, "1880-1890, 1900-1915"), ("kept", 1900, 1915, "1880-1890, 1900-1915")]
    shown = {y: sorted(f[1] for f in features if f[2] <= y <= f[3]) for y in (1885, 1895, 1915)}
    assert shown == {1885: ["gone", "kept", "raised"], 1895: ["gone", "raised"],
                     1915: ["kept", "new", "raised"]}


def test_a_model_of_one_date_has_no_years_and_its_certainty(tmp_path):
    doc = document({"a": (SQUARE, 6.0), "b": (L_SHAPE, 9.0)})
    doc["CityObjects"]["a"]["attributes"]["certainty"] = 4
    tiles.write_tileset(str(tmp_path), build_scene(doc))
    tileset, features = features_of(tmp_path)
    assert sorted((f[1], f[2], f[3], f[4], f[5]) for f in features) == [
        ("a", 0, 0, "", 4), ("b", 0, 0, "", 0)]
    assert "years" not in tileset["extras"]
    prop = {k: v for k, v in tiles.PROPERTIES["first_year"].items() if k != "description"}
    assert prop == {"type": "SCALAR", "componentType": "INT32", "noData": 0}


def test_the_root_transform_puts_the_vertices_where_proj_does(tmp_path):
    """A vertex of the glTF, turned z-up as 3D Tiles does (x, -z, y) and through the
    root's transform, is where PROJ puts its model coordinates (EPSG:7415 -> ECEF)."""
    scene = dynamic_scene()
    tiles.write_tileset(str(tmp_path), scene)
    tileset = json.loads((tmp_path / "tileset.json").read_text())
    matrix = np.array(tileset["root"]["transform"]).reshape(4, 4).T
    to_ecef = pyproj.Transformer.from_crs(7415, 4978, always_xy=True)
    gltf, binary = read_glb(tmp_path / tileset["root"]["content"]["uri"])
    checked = 0
    node = gltf["nodes"][0]
    for primitive in gltf["meshes"][node["mesh"]]["primitives"]:
        y_up = accessor(gltf, binary, primitive["attributes"]["POSITION"]) + node["translation"]
        local = np.column_stack([y_up[:, 0], -y_up[:, 2], y_up[:, 1]])
        ecef = (matrix @ np.column_stack([local, np.ones(len(local))]).T).T[:, :3]
        model = local + gltf["scenes"][0]["extras"]["origin"]
        expected = np.column_stack(to_ecef.transform(*model.T))
        assert np.abs(ecef - expected).max() < 0.01
        checked += len(local)
    assert checked > 0
    # the box of the root holds every vertex (in the root's frame, before the transform)
    box = np.array(tileset["root"]["boundingVolume"]["box"])
    low = scene.positions.min(axis=0)
    high = scene.positions.max(axis=0)
    assert np.all(box[:3] - np.abs(box[[3, 7, 11]]) <= low + 1e-3)
    assert np.all(box[:3] + np.abs(box[[3, 7, 11]]) >= high - 1e-3)


def test_many_buildings_make_a_quadtree_with_each_once(tmp_path):
    squares = {"b{}_{}".format(i, j): ([(x, y), (x + 6, y), (x + 6, y + 6), (x, y + 6)], 5.0)
               for i in range(30) for j in range(20)
               for x, y in [(i * 10 + (200 if i >= 15 else 0), j * 10)]}
    report = tiles.write_tileset(str(tmp_path), build_scene(document(squares)), leaf=50)
    tileset, features = features_of(tmp_path)
    assert sorted(f[1] for f in features) == sorted(squares)
    # a square prism: 4 corners of its ground, 4 of its roof, 8 of its walls
    assert {f[0] for f in features} == {16}
    assert report.tiles > 12 and report.depth >= 3
    for tile, parent in tile_nodes(tileset):
        if "content" in tile:
            gltf, _binary = read_glb(tmp_path / tile["content"]["uri"])
            table = gltf["extensions"]["EXT_structural_metadata"]["propertyTables"][0]
            assert 0 < table["count"] <= 50
            assert tile["geometricError"] == 0 and "children" not in tile
        else:
            assert tile["geometricError"] > 0
        if parent is not None:   # a child's box lies in its parent's
            a = np.array(tile["boundingVolume"]["box"])
            b = np.array(parent["boundingVolume"]["box"])
            ha, hb = np.abs(a[[3, 7, 11]]), np.abs(b[[3, 7, 11]])
            assert np.all(a[:3] - ha >= b[:3] - hb - 1e-6)
            assert np.all(a[:3] + ha <= b[:3] + hb + 1e-6)
    # the gap between the two blocks of squares has no tile: no leaf spans it
    for tile, _parent in tile_nodes(tileset):
        if "content" in tile:
            box = np.array(tile["boundingVolume"]["box"])
            assert box[3] < 150


def test_a_model_without_a_reference_system_is_refused(tmp_path):
    doc = document({"a": (SQUARE, 6.0)})
    del doc["metadata"]["referenceSystem"]
    with pytest.raises(InputError, match="no reference system"):
        tiles.write_tileset(str(tmp_path), build_scene(doc))
    doc["metadata"]["referenceSystem"] = "https://www.opengis.net/def/crs/EPSG/0/999999"
    with pytest.raises(InputError, match="unknown to PROJ"):
        tiles.write_tileset(str(tmp_path), build_scene(doc))


def test_khronos_validator_finds_no_error_in_a_tile(tmp_path):
    tiles.write_tileset(str(tmp_path), dynamic_scene())
    tileset = json.loads((tmp_path / "tileset.json").read_text())
    issues = validator_issues(tmp_path / tileset["root"]["content"]["uri"])
    assert issues["numErrors"] == 0, issues["messages"]
    unexpected = [m for m in issues["messages"] if m["code"] != "UNSUPPORTED_EXTENSION"]
    assert issues["numWarnings"] == 0 or not unexpected, unexpected
