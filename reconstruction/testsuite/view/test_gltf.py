"""The binary glTF of a city model (reconstruction.view.gltf), read back with trimesh
(not the writer) and checked by Khronos's glTF validator where it is installed."""

import dataclasses
import io
import json
import os
import shutil
import struct
import subprocess

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from reconstruction.core.errors import InputError
from reconstruction.epochs.dynamic import Epoch, merge_epochs
from reconstruction.testsuite.view.models import L_SHAPE, ORIGIN, SQUARE, document
from reconstruction.view import Scene, build_scene, glb_bytes

trimesh = pytest.importorskip("trimesh", reason="trimesh reads the glTF files back "
                                                "(requirements.txt; make deps installs it)")

NODE_DIR = os.environ.get("HISTO_NODE", os.path.expanduser("~/.local/share/histo/node"))
VALIDATOR = os.path.join(NODE_DIR, "node_modules", "gltf-validator")


def read(glb):
    """The glTF as trimesh reads it: a Scene whose base frame's children are the nodes."""
    return trimesh.load_scene(io.BytesIO(glb), file_type="glb", process=False)


def nodes(loaded):
    """{node name: its extras} of the top-level nodes."""
    graph = loaded.graph
    return {name: graph.transforms.edge_data[(graph.base_frame, name)].get("metadata")
            for name in graph.transforms.children.get(graph.base_frame, ())}


def gltf_points(loaded, node=None):
    """Every vertex (of ``node`` only, when given) in glTF's frame: its node's transform
    applied (x east, y up, z south)."""
    out = []
    for frame in loaded.graph.nodes_geometry:
        if node is None or loaded.graph.transforms.parents.get(frame) == node:
            matrix, name = loaded.graph[frame]
            out.append(trimesh.transform_points(np.asarray(loaded.geometry[name].vertices,
                                                           dtype=float), matrix))
    return np.concatenate(out)


def model_points(loaded, node=None):
    """The same in model coordinates: glTF's y-up turned back to east, north, up, and
    the origin of the scene's extras added."""
    xyz = gltf_points(loaded, node)
    return np.column_stack([xyz[:, 0], -xyz[:, 2], xyz[:, 1]]) + loaded.metadata["origin"]


def triangle_count(loaded):
    return sum(len(loaded.geometry[loaded.graph[f][1]].faces) for f in loaded.graph.nodes_geometry)


def cityjson_bounds(doc):
    xyz = np.asarray(doc["vertices"], dtype=float) * doc["transform"]["scale"]
    xyz += doc["transform"]["translate"]
    return xyz.min(axis=0), xyz.max(axis=0)


def json_chunk(glb):
    """The JSON of a GLB, read from its container by hand (for what trimesh hides)."""
    magic, version, length = struct.unpack_from("<4sII", glb)
    assert (magic, version, length) == (b"glTF", 2, len(glb))
    size, kind = struct.unpack_from("<I4s", glb, 12)
    assert kind == b"JSON" and size % 4 == 0
    return json.loads(glb[20:20 + size])


def srgb_to_linear(v):
    c = v / 255
    return c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4


def test_a_node_per_building_with_its_id_attributes_and_place():
    doc = document({"L": (L_SHAPE, 9.0), "box": (SQUARE, 6.0)})
    scene = build_scene(doc, copied=["box"])
    glb = glb_bytes(scene)
    loaded = read(glb)
    assert nodes(loaded) == {"L": {"roof_type": "flat", "eaves_height": 9.0},
                             "box": {"roof_type": "flat", "eaves_height": 6.0}}
    assert loaded.metadata["origin"] == pytest.approx(ORIGIN)
    assert loaded.metadata["crs"] == "https://www.opengis.net/def/crs/EPSG/0/7415"
    points = model_points(loaded)
    low, high = cityjson_bounds(doc)
    assert points.min(axis=0) == pytest.approx(low, abs=1e-3)
    assert points.max(axis=0) == pytest.approx(high, abs=1e-3)
    assert triangle_count(loaded) == len(scene.triangles) == 32
    # y is up: the L stands 9 m tall along glTF's y
    heights = gltf_points(loaded, "L")[:, 1]
    assert (heights.min(), heights.max()) == pytest.approx((0, 9), abs=1e-3)
    # a material per kind of surface; the copied building's walls and roof in blue
    colours = {(name.rstrip("_0123456789"), g.visual.material.name):
               tuple(g.visual.material.baseColorFactor[:3]) for name, g in loaded.geometry.items()}
    expected = {("L", "ground"): (150, 150, 150), ("L", "wall"): (245, 245, 245),
                ("L", "roof"): (200, 30, 25), ("box", "copied ground"): (150, 150, 150),
                ("box", "copied wall"): (205, 222, 240), ("box", "copied roof"): (35, 85, 170)}
    assert set(colours) == set(expected)
    for key, rgb in expected.items():   # trimesh keeps glTF's linear factor, times 255
        assert np.abs(np.array(colours[key]) / 255 - [srgb_to_linear(v) for v in rgb]).max() < 0.003
    gltf = json_chunk(glb)
    assert gltf["asset"]["generator"].startswith("histo")
    assert {a["componentType"] for a in gltf["accessors"] if a["type"] == "SCALAR"} == {5123}
    assert all("min" in a and "max" in a for a in gltf["accessors"] if a["type"] == "VEC3")
    # the same scene, the same bytes
    assert glb_bytes(scene) == glb


def test_a_dynamic_model_gives_the_buildings_of_one_year():
    early = document({"kept": (SQUARE, 8.0), "gone": (L_SHAPE, 9.0),
                      "raised": ([(40, 0), (48, 0), (48, 8), (40, 8)], 6.0)})
    late = document({"kept": (SQUARE, 8.0), "raised": ([(40, 0), (48, 0), (48, 8), (40, 8)], 9.0),
                     "new": ([(60, 0), (66, 0), (66, 9), (60, 9)], 7.0)})
    scene = build_scene(merge_epochs([Epoch(1880, early), Epoch(1915, late)]).document)
    for year, doc in ((1880, early), (1900, early), (1915, late), (None, late)):
        loaded = read(glb_bytes(scene, year))
        assert sorted(nodes(loaded)) == sorted(doc["CityObjects"])
        assert loaded.metadata["year"] == (year or 1915)
        standing = scene.standing(year or 1915)
        assert triangle_count(loaded) == int(np.diff(scene.chunk_start)[standing].sum())
        points = model_points(loaded)
        low, high = cityjson_bounds(doc)
        assert points.min(axis=0) == pytest.approx(low, abs=1e-3)
        assert points.max(axis=0) == pytest.approx(high, abs=1e-3)
    # "raised" is 6 m tall until 1914 and 9 m from 1915 on
    for year, height in ((1914, 6.0), (1915, 9.0)):
        raised = model_points(read(glb_bytes(scene, year)), "raised")
        assert raised[:, 2].max() == pytest.approx(height, abs=1e-3)
    with pytest.raises(InputError, match="1880 to 1915"):
        glb_bytes(scene, 1850)


def gone_by(scene, year):
    """``scene`` with every version of every building demolished before ``year``."""
    spans = tuple(((year - 50, year - 1),) for _ in scene.chunk_years)
    return dataclasses.replace(scene, years=(year - 50, year), chunk_years=spans)


def test_a_year_with_no_building_gives_an_empty_scene():
    glb = glb_bytes(gone_by(build_scene(document({"a": (SQUARE, 6.0)})), 1900), 1900)
    gltf = json_chunk(glb)
    assert "nodes" not in gltf and "nodes" not in gltf["scenes"][0] and "buffers" not in gltf
    assert gltf["scenes"][0]["extras"]["year"] == 1900


@settings(max_examples=25, deadline=None)
@given(st.lists(st.tuples(st.floats(-500, 500), st.floats(-500, 500), st.floats(2, 40),
                          st.floats(2, 40), st.floats(2.5, 30)), min_size=1, max_size=4))
def test_property_the_glb_covers_the_model_s_bounding_box(boxes):
    doc = document({"b{}".format(i): ([(x, y), (x + w, y), (x + w, y + d), (x, y + d)], h)
                    for i, (x, y, w, d, h) in enumerate(boxes)})
    loaded = read(glb_bytes(build_scene(doc)))
    assert len(nodes(loaded)) == len(boxes)
    points = model_points(loaded)
    low, high = cityjson_bounds(doc)
    assert points.min(axis=0) == pytest.approx(low, abs=1e-3)
    assert points.max(axis=0) == pytest.approx(high, abs=1e-3)


def strip_scene(n):
    """A made-up Scene: one wall of ``n`` vertices in a zigzag strip, ``n - 2`` triangles."""
    x = np.arange(n) // 2 * 0.01
    positions = np.column_stack([x, np.zeros(n), np.arange(n) % 2 * 3.0]).astype(np.float32)
    i = np.arange(n - 2)
    triangles = np.where((i % 2 == 0)[:, None], np.column_stack([i, i + 1, i + 2]),
                         np.column_stack([i + 1, i, i + 2])).astype(np.uint32)
    return Scene(ids=("strip",), attributes=({"note": "long"},), copied=np.zeros(1, bool),
                 positions=positions, kinds=np.ones(n, np.uint8), triangles=triangles,
                 chunk_start=np.array([0, n - 2], np.uint32),
                 chunk_vertex=np.array([0, n], np.uint32), chunk_building=np.zeros(1, np.uint32),
                 chunk_years=((),), origin=np.array([1000.0, 2000.0, 3.0]))


def test_indices_are_uint32_only_beyond_65535_vertices():
    for n, component in ((65535, 5123), (65536, 5125)):
        glb = glb_bytes(strip_scene(n))
        indices = [a for a in json_chunk(glb)["accessors"] if a["type"] == "SCALAR"]
        assert [a["componentType"] for a in indices] == [component]
        loaded = read(glb)
        assert triangle_count(loaded) == n - 2
        assert model_points(loaded).max(axis=0) == pytest.approx(
            [1000 + (n - 1) // 2 * 0.01, 2000, 6], abs=1e-3)


def test_uint16_and_uint32_indices_in_one_file_name_their_own_views():
    # write_glb spools each view apart and names it by index once the views used are known
    big, small = strip_scene(65536), strip_scene(10)
    nv, nt = len(big.positions), len(big.triangles)
    both = dataclasses.replace(
        big, ids=("big", "small"), attributes=({"n": 1}, {"n": 2}), copied=np.zeros(2, bool),
        positions=np.concatenate([big.positions, small.positions]),
        kinds=np.concatenate([big.kinds, small.kinds]),
        triangles=np.concatenate([big.triangles, small.triangles + nv]).astype(np.uint32),
        chunk_start=np.array([0, nt, nt + len(small.triangles)], np.uint32),
        chunk_vertex=np.array([0, nv, nv + len(small.positions)], np.uint32),
        chunk_building=np.array([0, 1], np.uint32), chunk_years=((), ()))
    glb = glb_bytes(both)
    document = json_chunk(glb)
    views = document["bufferViews"]
    for accessor in document["accessors"]:
        view = views[accessor["bufferView"]]
        size = {5126: 12, 5125: 4, 5123: 2}[accessor["componentType"]]   # VEC3 or SCALAR
        assert accessor["byteOffset"] + accessor["count"] * size <= view["byteLength"]
        assert ("byteStride" in view) == (accessor["componentType"] == 5126)
    assert sorted(a["componentType"] for a in document["accessors"]
                  if a["type"] == "SCALAR") == [5123, 5125]
    assert triangle_count(read(glb)) == 65534 + 8


def test_extras_are_plain_json():
    scene = build_scene(document({"a": (SQUARE, 6.0)}))
    odd = {"h": np.float64(6.5), "n": np.int32(3), "nan": float("nan"), "t": (1, 2),
           "when": np.datetime64("1900-01-01"), "nested": {1: [np.bool_(True)]}}
    loaded = read(glb_bytes(dataclasses.replace(scene, attributes=(odd,))))
    assert nodes(loaded) == {"a": {"h": 6.5, "n": 3, "nan": None, "t": [1, 2],
                                   "when": "1900-01-01", "nested": {"1": [True]}}}


VALIDATE = """
const validator = require(process.argv[1]);
const bytes = new Uint8Array(require("fs").readFileSync(process.argv[2]));
validator.validateBytes(bytes).then(
  (report) => console.log(JSON.stringify(report.issues)),
  (error) => { console.error(String(error)); process.exit(2); });
"""


def validator_issues(path):
    """The issues Khronos's validator finds in the file at ``path`` (its report's
    ``issues``); skips the test when node or the validator is missing."""
    node = shutil.which("node")
    if node is None:
        pytest.skip("node (Debian's nodejs) not found: Khronos's glTF validator cannot run")
    if not os.path.isfile(os.path.join(VALIDATOR, "package.json")):
        pytest.skip("Khronos's glTF validator is not installed in {}: `make deps` installs "
                    "npm's gltf-validator there when npm is present".format(NODE_DIR))
    run = subprocess.run([node, "-e", VALIDATE, VALIDATOR, str(path)],
                         capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    return json.loads(run.stdout)


def test_khronos_validator_finds_no_problem(tmp_path):
    early = document({"gone": (L_SHAPE, 9.0), "kept": (SQUARE, 6.0)})
    late = document({"kept": (SQUARE, 6.0), "new": ([(40, 0), (48, 0), (48, 8), (40, 8)], 7.0)})
    files = {"static.glb": glb_bytes(build_scene(early, copied=["kept"])),
             "dynamic.glb": glb_bytes(build_scene(merge_epochs(
                 [Epoch(1880, early), Epoch(1915, late)]).document), 1900),
             "uint32.glb": glb_bytes(strip_scene(70000)),
             "empty.glb": glb_bytes(gone_by(build_scene(early), 1900), 1900)}
    for name, glb in files.items():
        path = tmp_path / name
        path.write_bytes(glb)
        issues = validator_issues(path)
        assert (name, issues["numErrors"], issues["numWarnings"]) == (name, 0, 0), \
            issues["messages"]
    # and it does find a broken file: positions without their bounds
    gltf = json_chunk(files["static.glb"])
    del gltf["accessors"][0]["min"]
    text = json.dumps(gltf).encode()
    text += b" " * (-len(text) % 4)
    rest = files["static.glb"][20 + struct.unpack_from("<I", files["static.glb"], 12)[0]:]
    broken = tmp_path / "broken.glb"
    broken.write_bytes(struct.pack("<4sII", b"glTF", 2, 20 + len(text) + len(rest))
                       + struct.pack("<I4s", len(text), b"JSON") + text + rest)
    assert validator_issues(broken)["numErrors"] > 0
