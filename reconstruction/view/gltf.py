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

import json
import math
import struct

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


class _Buffer:
    """The binary chunk, built in three buffer views: vertices (float32 x, y, z),
    uint32 and uint16 indices."""

    def __init__(self):
        self.parts = {FLOAT: [], UINT32: [], UINT16: []}
        self.size = dict.fromkeys(self.parts, 0)
        self.accessors = []

    def add(self, array, component, kind, **extra):
        """An accessor over ``array`` (its bytes appended to the view of ``component``)."""
        data = np.ascontiguousarray(array).tobytes()
        self.accessors.append(dict({"bufferView": component, "byteOffset": self.size[component],
                                    "componentType": component, "count": int(len(array)),
                                    "type": kind}, **extra))
        self.parts[component].append(data)
        self.size[component] += len(data)
        return len(self.accessors) - 1

    def finish(self):
        """The buffer views, the accessors pointing at them and the binary chunk's bytes."""
        views, blob, index = [], bytearray(), {}
        for component, target in ((FLOAT, ARRAY_BUFFER), (UINT32, ELEMENT_ARRAY_BUFFER),
                                  (UINT16, ELEMENT_ARRAY_BUFFER)):
            if not self.size[component]:
                continue
            blob += b"\0" * (-len(blob) % 4)
            index[component] = len(views)
            view = {"buffer": 0, "byteOffset": len(blob), "byteLength": self.size[component],
                    "target": target}
            if target == ARRAY_BUFFER:
                view["byteStride"] = 12   # several accessors share it: glTF then wants the stride
            views.append(view)
            blob += b"".join(self.parts[component])
        accessors = [dict(a, bufferView=index[a["bufferView"]]) for a in self.accessors]
        return views, accessors, bytes(blob)


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
    chunks, year = _chunks(scene, year)
    buffer, materials, material_of = _Buffer(), [], {}
    nodes, meshes, drawn = [], [], {}
    for k in chunks:
        if scene.chunk_start[k + 1] > scene.chunk_start[k]:
            drawn.setdefault(int(scene.chunk_building[k]), []).append(int(k))
    for b, ks in drawn.items():
        copied = bool(scene.copied[b])
        vertex = np.concatenate([np.arange(scene.chunk_vertex[k], scene.chunk_vertex[k + 1])
                                 for k in ks])
        points = _y_up(scene.positions[vertex].astype(np.float64))
        low, high = points.min(axis=0), points.max(axis=0)
        anchor = np.array([(low[0] + high[0]) / 2, low[1], (low[2] + high[2]) / 2])
        primitives = []
        for k in ks:
            triangles = scene.triangles[scene.chunk_start[k]:scene.chunk_start[k + 1]]
            kinds = scene.kinds[triangles[:, 0]]
            for kind in np.unique(kinds):
                # a chunk's vertices are sorted by kind: each kind's are one run
                own = triangles[kinds == kind]
                first, last = int(own.min()), int(own.max()) + 1
                local = (_y_up(scene.positions[first:last].astype(np.float64))
                         - anchor).astype(np.float32)
                position = buffer.add(local, FLOAT, "VEC3", min=local.min(axis=0).tolist(),
                                      max=local.max(axis=0).tolist())
                small = last - first <= UINT16_VERTICES
                indices = (own - first).astype(np.uint16 if small else np.uint32).ravel()
                index = buffer.add(indices, UINT16 if small else UINT32, "SCALAR")
                key = (copied, int(kind))
                if key not in material_of:
                    material_of[key] = len(materials)
                    materials.append(_material(*COLOURS[key]))
                primitives.append({"attributes": {"POSITION": position}, "indices": index,
                                   "material": material_of[key], "mode": TRIANGLES})
        meshes.append({"name": scene.ids[b], "primitives": primitives})
        nodes.append({"name": scene.ids[b], "mesh": len(meshes) - 1,
                      "translation": [float(v) for v in anchor],
                      "extras": json_safe(scene.attributes[b])})
    extras = {"origin": [float(v) for v in scene.origin], "crs": scene.crs,
              "axes": "x east, y up, z south; metres from origin (east, north, up)"}
    if year is not None:
        extras["year"] = year
    views, accessors, blob = buffer.finish()
    view = {"name": "histo city model", "nodes": list(range(len(nodes))), "extras": extras}
    document = {"asset": {"version": "2.0", "generator": GENERATOR},
                "scene": 0, "scenes": [{k: v for k, v in view.items() if v != []}],
                "nodes": nodes, "meshes": meshes, "materials": materials,
                "accessors": accessors, "bufferViews": views}
    if blob:
        document["buffers"] = [{"byteLength": len(blob)}]
    document = {k: v for k, v in document.items() if v != []}
    return _container(document, blob)


def _container(document, blob):
    """The GLB container: header, JSON chunk (padded with spaces), binary chunk (zeros)."""
    text = json.dumps(document, ensure_ascii=False, separators=(",", ":"),
                      allow_nan=False).encode("utf-8")
    text += b" " * (-len(text) % 4)
    chunks = struct.pack("<I4s", len(text), b"JSON") + text
    if blob:
        blob += b"\0" * (-len(blob) % 4)
        chunks += struct.pack("<I4s", len(blob), b"BIN\0") + blob
    return struct.pack("<4sII", b"glTF", 2, 12 + len(chunks)) + chunks
