"""A city model as one binary glTF 2.0 file (.glb), for Blender, CesiumJS and the like (issue 29).

One node per building, named by its CityJSON id, with the building's
attributes as the node's ``extras``; for a dynamic model (v.histo.timeline)
only the buildings standing in one year, in the version of that year (the
snapshot's rule, :meth:`Scene.standing`). The node's one mesh has a primitive
per kind of surface, each with its own vertices (POSITION, with min and max)
and indices local to them (uint16 when they fit, else uint32).

Choices:

- **Colours as materials**, one per kind of surface (roof red, walls white,
  ground grey; the walls and roofs of copied buildings pale blue and blue),
  the colours of the HTML viewer and of v.histo.lod2's pictures. Every glTF
  reader shows a material's base colour, whereas Blender's importer only
  uses COLOR_0 where a material asks for it; a user restyles every roof by
  editing one material. The colours are sRGB converted to the linear values
  glTF's ``baseColorFactor`` holds; matte (metallic 0, roughness 1) and
  double-sided, so that a face of a copied model turned inwards still shows.
- **No normals**: glTF readers must then shade flat (the specification says
  so; three.js, CesiumJS and Blender do), which is what a building's planar
  faces want. Per-vertex normals would need a vertex per face instead of
  per kind of surface, a larger file for the same picture.
- **Axes**: glTF is y-up (x east, y up, z south): the vertices are turned
  -90 degrees about x here, not by a node rotation, so that Blender, which
  turns glTF back to z-up, shows each building upright with no rotation of
  its own. Units are metres. Each node is translated to the middle of its
  building's foot (an object's pivot in Blender), its vertices relative to
  it. The scene's ``extras`` hold ``origin``, the model's coordinates of the
  local zero (east, north, up), and ``crs``, so that a user can put it back
  in place: model = origin + (x, -z, y) of a vertex with its node's
  translation.

The container is written here with numpy, struct and json rather than with
pygltflib: a GLB is a 12-byte header, a JSON chunk and a binary chunk, both
4-byte aligned, and pygltflib would only spell the same JSON as dataclasses
while bringing five packages (dataclasses-json, marshmallow, typing-inspect,
deprecated, wrapt) into every run of the modules. The same scene gives the
same bytes. The tests read the files back with trimesh and run Khronos's
validator on them.
"""

import io
import json
import math
import struct
import tempfile

import numpy as np

from ..core.errors import InputError
from .scene import COLOURS as PALETTE, COPIED_COLOURS, GROUND, OTHER, ROOF, WALL

GENERATOR = "histo (GRASS GIS addon suite), reconstruction.view.gltf"
#: the material (name, sRGB colour) of each (copied, kind of surface): the suite's palette
COLOURS = {(copied, kind): (("copied " if copied else "") + name,
                            tuple(int(v) for v in (COPIED_COLOURS if copied else PALETTE)[kind]))
           for copied in (False, True)
           for kind, name in ((GROUND, "ground"), (WALL, "wall"), (ROOF, "roof"),
                              (OTHER, "other"))}
# glTF's constants: component types, buffer view targets, primitive mode
FLOAT, UINT16, UINT32 = 5126, 5123, 5125
ARRAY_BUFFER, ELEMENT_ARRAY_BUFFER = 34962, 34963
TRIANGLES = 4
#: the largest vertex count indexed by uint16 (65535 is the primitive restart value)
UINT16_VERTICES = 65535
#: the view of the feature ids of EXT_mesh_features (float32 scalars, one per vertex:
#: their own view, as the vertices' view has a stride of 12 bytes)
FEATURE_IDS = "feature ids"
#: the buffer views in the order they lie in the binary chunk, their component types,
#: targets and strides
COMPONENTS = (FLOAT, UINT32, UINT16, FEATURE_IDS)
COMPONENT = {FLOAT: FLOAT, UINT32: UINT32, UINT16: UINT16, FEATURE_IDS: FLOAT}
TARGET = {FLOAT: ARRAY_BUFFER, UINT32: ELEMENT_ARRAY_BUFFER, UINT16: ELEMENT_ARRAY_BUFFER,
          FEATURE_IDS: ARRAY_BUFFER}
STRIDE = {FLOAT: 12, FEATURE_IDS: 4}
#: the placeholder of each view's index in an accessor's text: control characters, which
#: JSON text never holds raw
VIEW_MARK = {FLOAT: b"\x01", UINT32: b"\x02", UINT16: b"\x03", FEATURE_IDS: b"\x04"}
#: bytes of a spool kept in memory before it goes to a temporary file
SPOOLED = 1 << 22
#: the lists of the glTF document written from spools
SPOOLED_LISTS = ("nodes", "meshes", "accessors")


def _linear(value):
    """An sRGB component 0-255 as the linear value of glTF's colour factors."""
    c = value / 255.0
    return c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4


def _material(name, rgb):
    return {"name": name,
            "pbrMetallicRoughness": {"baseColorFactor": [round(_linear(v), 6) for v in rgb] + [1.0],
                                     "metallicFactor": 0.0, "roughnessFactor": 1.0},
            "doubleSided": True}


def json_safe(value):
    """``value`` (attributes of a city object) as plain JSON: numpy scalars as numbers,
    non-finite numbers as None, tuples as lists, keys as strings, anything else as text."""
    if isinstance(value, dict):
        return {str(k): json_safe(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [json_safe(v) for v in value]
    if isinstance(value, np.generic):
        value = value.item()
    if value is None or isinstance(value, (bool, str, int)):
        return value
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    return str(value)


def _y_up(points):
    """East, north, up as glTF's x east, y up, z south (-90 degrees about x)."""
    return np.column_stack([points[:, 0], points[:, 2], -points[:, 1]])


class _Spools:
    """The binary chunk's three buffer views (vertices float32 x, y, z; uint32 and uint16
    indices) and the JSON texts of the nodes, meshes and accessors, each written to a
    temporary file as the buildings go (kept in memory while small), so that a city's
    glTF is never held whole (issue 49, item 14). An accessor's text names its buffer
    view by a placeholder byte (:data:`VIEW_MARK`), the view's index once the views
    used are known (:meth:`finish`)."""

    def __init__(self, folder=None):
        def spool():
            return tempfile.SpooledTemporaryFile(max_size=SPOOLED, dir=folder)

        self.binary = {component: spool() for component in COMPONENTS}
        self.size = dict.fromkeys(COMPONENTS, 0)
        self.texts = {name: spool() for name in SPOOLED_LISTS}
        self.count = dict.fromkeys(self.texts, 0)

    def close(self):
        for f in list(self.binary.values()) + list(self.texts.values()):
            f.close()

    def text(self, name, value, prefix=b"{"):
        """Append ``value`` (a JSON-able dict; its text starting with ``prefix``) to the
        list ``name``; returns its index."""
        f = self.texts[name]
        f.write((b"," if self.count[name] else b"") + prefix + _json_bytes(value)[1:])
        self.count[name] += 1
        return self.count[name] - 1

    def add(self, array, component, kind, **extra):
        """An accessor over ``array`` (its bytes appended to the view of ``component``)."""
        data = np.ascontiguousarray(array).tobytes()
        accessor = dict({"byteOffset": self.size[component],
                         "componentType": COMPONENT[component],
                         "count": int(len(array)), "type": kind}, **extra)
        self.binary[component].write(data)
        self.size[component] += len(data)
        return self.text("accessors", accessor, b'{"bufferView":' + VIEW_MARK[component] + b",")

    def views(self, blobs=()):
        """The buffer views (dicts) of the views used, their start in the binary chunk,
        and its length: each view 4-byte aligned, one after the other; then a view of
        each of ``blobs`` (bytes, e.g. a property table's columns), 8-byte aligned as
        EXT_structural_metadata wants, the i-th's start ``starts["blob", i]``."""
        views, starts, at = [], {}, 0
        for component in COMPONENTS:
            if not self.size[component]:
                continue
            at += -at % 4
            starts[component] = at
            view = {"buffer": 0, "byteOffset": at, "byteLength": self.size[component],
                    "target": TARGET[component]}
            if component in STRIDE:
                # several accessors share it: glTF then wants the stride
                view["byteStride"] = STRIDE[component]
            views.append(view)
            at += self.size[component]
        for i, blob in enumerate(blobs):
            at += -at % 8
            starts["blob", i] = at
            views.append({"buffer": 0, "byteOffset": at, "byteLength": len(blob)})
            at += len(blob)
        return views, starts, at

    def marks(self):
        """The placeholder bytes of the accessors' views as the views' indices."""
        used = [c for c in COMPONENTS if self.size[c]]
        table = bytes(range(256))
        for component, mark in VIEW_MARK.items():
            if component in used:
                table = table[:mark[0]] + str(used.index(component)).encode() + table[mark[0] + 1:]
        return table


def _chunks(scene, year):
    """The chunks to write, and the year they were chosen for (None: a model of one date)."""
    if not scene.years:
        return np.arange(len(scene.chunk_building)), None
    first, last = scene.years
    year = last if year is None else int(year)
    if not first <= year <= last:
        raise InputError("The model covers the years {} to {}: no glTF of {}".format(
            first, last, year))
    return np.flatnonzero(scene.standing(year)), year


def glb_bytes(scene, year=None):
    """The binary glTF (bytes) of ``scene`` (a :class:`~reconstruction.view.scene.Scene`):
    for a dynamic model the buildings standing in ``year`` (default: its last year).
    A building with no triangle to draw has no node. InputError when ``year`` lies
    outside the model's years."""
    out = io.BytesIO()
    write_glb(out, scene, year)
    return out.getvalue()


def write_glb(f, scene, year=None, folder=None):
    """Write the glTF of :func:`glb_bytes` to the binary file ``f``, building by building
    through temporary files in ``folder`` (None: the system's), never holding a
    city's glTF whole (issue 49, item 14)."""
    chunks, year = _chunks(scene, year)
    write_parts(f, scene, _drawn(scene, chunks), folder, year=year)


def write_parts(f, scene, parts, folder=None, features=None, year=None):
    """Write to ``f`` the glTF of ``parts`` of ``scene``: (building, its chunks) pairs,
    a node each (a building drawn with several chunks). ``features``: None, or a
    callable ``features(parts, first_view)`` giving the metadata of the parts as
    (EXT_structural_metadata's object, its blobs): the parts are then one node, part i
    feature i of EXT_mesh_features (a ``_FEATURE_ID_0`` per vertex, the property table
    0), the blobs the buffer views ``first_view`` on (3D Tiles' contents,
    :mod:`reconstruction.view.tiles`). ``year``: the year drawn, in extras."""
    spools = _Spools(folder)
    try:
        if features is None:
            materials = _buildings(scene, parts, spools)
        else:
            parts = list(parts)
            materials = _features(scene, parts, spools)
        extras = {"origin": [float(v) for v in scene.origin], "crs": scene.crs,
                  "axes": "x east, y up, z south; metres from origin (east, north, up)"}
        if year is not None:
            extras["year"] = year
        metadata, blobs = (None, ()) if features is None else features(
            parts, len(spools.views()[0]))
        _container(f, spools, materials, extras, metadata, blobs)
    finally:
        spools.close()


def _drawn(scene, chunks):
    """Each building with triangles among ``chunks`` and its chunks that have some, in
    the order of its first such chunk (building, list of chunks), one at a time."""
    chunks = np.asarray(chunks, dtype=np.int64)
    chunks = chunks[scene.chunk_start[chunks + 1] > scene.chunk_start[chunks]]
    building = scene.chunk_building[chunks].astype(np.int64)
    _unique, first, which = np.unique(building, return_index=True, return_inverse=True)
    rank = np.argsort(np.argsort(first))[which.reshape(-1)]    # buildings by first chunk
    order = np.argsort(rank, kind="stable")
    chunks, rank = chunks[order], rank[order]
    ends = np.flatnonzero(np.diff(rank)) + 1
    for ks in np.split(chunks, ends) if len(chunks) else ():
        yield int(scene.chunk_building[ks[0]]), ks.tolist()


def _runs(scene, ks):
    """The triangles of chunks ``ks`` by kind of surface: (kind, first vertex, end vertex,
    triangles (t, 3) indexing from the first), a chunk's vertices of a kind being one run."""
    for k in ks:
        triangles = scene.triangles[scene.chunk_start[k]:scene.chunk_start[k + 1]]
        kinds = scene.kinds[triangles[:, 0]]
        for kind in np.unique(kinds):
            own = triangles[kinds == kind]
            first, last = int(own.min()), int(own.max()) + 1
            yield int(kind), first, last, own - first


def _anchor(points):
    """A node's translation: the middle of the foot of ``points`` (glTF's y-up)."""
    low, high = points.min(axis=0), points.max(axis=0)
    return np.array([(low[0] + high[0]) / 2, low[1], (low[2] + high[2]) / 2])


def _chunk_points(scene, ks):
    vertex = np.concatenate([np.arange(scene.chunk_vertex[k], scene.chunk_vertex[k + 1])
                             for k in ks])
    return _y_up(scene.positions[vertex].astype(np.float64))


class _Materials:
    """The materials used, in the order of their first use: their index by key."""

    def __init__(self):
        self.list, self.index = [], {}

    def __call__(self, key):
        if key not in self.index:
            self.index[key] = len(self.list)
            self.list.append(_material(*COLOURS[key]))
        return self.index[key]


def _primitive(spools, local, triangles, material, feature_ids=None, features=0):
    """The primitive of vertices ``local`` (float32, y-up) and ``triangles`` (indexing
    them); with ``feature_ids`` (one per vertex) EXT_mesh_features of ``features``."""
    position = spools.add(local, FLOAT, "VEC3", min=local.min(axis=0).tolist(),
                          max=local.max(axis=0).tolist())
    small = len(local) <= UINT16_VERTICES
    index = spools.add(triangles.astype(np.uint16 if small else np.uint32).ravel(),
                       UINT16 if small else UINT32, "SCALAR")
    primitive = {"attributes": {"POSITION": position}, "indices": index,
                 "material": material, "mode": TRIANGLES}
    if feature_ids is not None:
        primitive["attributes"]["_FEATURE_ID_0"] = spools.add(
            feature_ids.astype(np.float32), FEATURE_IDS, "SCALAR")
        primitive["extensions"] = {"EXT_mesh_features": {"featureIds": [
            {"featureCount": features, "attribute": 0, "propertyTable": 0}]}}
    return primitive


def _buildings(scene, drawn, spools):
    """Write the node, mesh and accessors of each building of ``drawn`` ((building, its
    chunks), :func:`_drawn`); returns the materials used, in the order of their first use."""
    materials = _Materials()
    for b, ks in drawn:
        copied = bool(scene.copied[b])
        anchor = _anchor(_chunk_points(scene, ks))
        primitives = []
        for kind, first, last, own in _runs(scene, ks):
            local = (_y_up(scene.positions[first:last].astype(np.float64))
                     - anchor).astype(np.float32)
            primitives.append(_primitive(spools, local, own, materials((copied, kind))))
        mesh = spools.text("meshes", {"name": scene.ids[b], "primitives": primitives})
        spools.text("nodes", {"name": scene.ids[b], "mesh": mesh,
                              "translation": [float(v) for v in anchor],
                              "extras": json_safe(scene.attributes[b])})
    return materials.list


def _features(scene, drawn, spools):
    """Write ``drawn`` ((building, its chunks), a list) as one node whose mesh has a
    primitive per material, each part i its vertices' feature id i (EXT_mesh_features):
    what 3D Tiles' content wants, a few draw calls a tile instead of some per building.
    Returns the materials used."""
    materials = _Materials()
    runs = {}         # material: [(first, last, triangles, feature)]
    for feature, (b, ks) in enumerate(drawn):
        for kind, first, last, own in _runs(scene, ks):
            runs.setdefault(materials((bool(scene.copied[b]), kind)), []).append(
                (first, last, own, feature))
    anchor = _anchor(_chunk_points(scene, [k for _b, ks in drawn for k in ks]))
    primitives = []
    for material, items in runs.items():
        local = (_y_up(np.concatenate([scene.positions[a:e] for a, e, _t, _f in items])
                       .astype(np.float64)) - anchor).astype(np.float32)
        starts = np.cumsum([0] + [e - a for a, e, _t, _f in items])
        triangles = np.concatenate([t + s for (_a, _e, t, _f), s in zip(items, starts)])
        ids = np.repeat([f for _a, _e, _t, f in items], np.diff(starts))
        primitives.append(_primitive(spools, local, triangles, material, ids, len(drawn)))
    if primitives:
        mesh = spools.text("meshes", {"name": "buildings", "primitives": primitives})
        spools.text("nodes", {"name": "buildings", "mesh": mesh,
                              "translation": [float(v) for v in anchor]})
    return materials.list


#: the glTF's JSON as ``json.dumps(..., ensure_ascii=False, separators=(",", ":"),
#: allow_nan=False)`` writes it (one encoder: json.dumps makes one a call otherwise)
_ENCODER = json.JSONEncoder(ensure_ascii=False, separators=(",", ":"), allow_nan=False)


def _json_bytes(value):
    return _ENCODER.encode(value).encode("utf-8")


def _container(f, spools, materials, extras, metadata=None, blobs=()):
    """Write the GLB container: header, JSON chunk (padded with spaces), binary chunk
    (zeros); the JSON's lists of nodes, meshes and accessors and the binary views
    copied from their spools. ``metadata``: EXT_structural_metadata's object (None:
    none), its ``blobs`` (bytes) after the views of the spools."""
    views, starts, length = spools.views(blobs)
    view = {"name": "histo city model", "nodes": list(range(spools.count["nodes"])),
            "extras": extras}
    head = {"asset": {"version": "2.0", "generator": GENERATOR},
            "scene": 0, "scenes": [{k: v for k, v in view.items() if v != []}]}
    if metadata is not None:
        used = ["EXT_mesh_features", "EXT_structural_metadata"]
        head.update(extensionsUsed=used, extensions={"EXT_structural_metadata": metadata})
    # the document's members in order: text, or the name of a spooled list
    members = [_json_bytes(head)[:-1]]
    for key, value in (("nodes", None), ("meshes", None), ("materials", materials),
                       ("accessors", None), ("bufferViews", views),
                       ("buffers", [{"byteLength": length}] if length else [])):
        if value is None and spools.count[key]:
            members += [b',"' + key.encode() + b'":[', key, b"]"]
        elif value:
            members.append(b',"' + key.encode() + b'":' + _json_bytes(value))
    members.append(b"}")
    size = sum(spools.texts[m].tell() if isinstance(m, str) else len(m) for m in members)
    pad = -size % 4
    binary = length + (-length % 4)
    f.write(struct.pack("<4sII", b"glTF", 2, 12 + 8 + size + pad + (8 + binary if length else 0)))
    f.write(struct.pack("<I4s", size + pad, b"JSON"))
    marks = spools.marks()
    for member in members:
        if isinstance(member, str):
            _copy(spools.texts[member], f, marks if member == "accessors" else None)
        else:
            f.write(member)
    f.write(b" " * pad)
    if length:
        f.write(struct.pack("<I4s", binary, b"BIN\0"))
        at = 0
        for component in COMPONENTS:
            if component in starts:
                f.write(b"\0" * (starts[component] - at))
                _copy(spools.binary[component], f)
                at = starts[component] + spools.size[component]
        for i, blob in enumerate(blobs):
            f.write(b"\0" * (starts["blob", i] - at))
            f.write(blob)
            at = starts["blob", i] + len(blob)
        f.write(b"\0" * (binary - at))


def _copy(spool, f, table=None):
    """Copy a spool's bytes to ``f`` (translated by ``table`` when given)."""
    spool.seek(0)
    while True:
        block = spool.read(SPOOLED)
        if not block:
            return
        f.write(block.translate(table) if table is not None else block)
