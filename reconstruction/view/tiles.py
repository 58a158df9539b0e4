"""A city model as 3D Tiles 1.1 for CesiumJS, ArcGIS, deck.gl and the like (issue 52, item 2).

:func:`write_tileset` writes a directory: ``tileset.json`` and a binary glTF
per tile in ``content/``. It reads the model only through a
:class:`~reconstruction.view.scene.Scene` and writes each tile's glTF with
:func:`reconstruction.view.gltf.write_parts` (the glTF export's colours and
axes; a tile's buildings one node, a primitive per material, so that a viewer
draws a tile in a few calls).

Choices:

- **Features**: a feature per building of a model of one date; per version
  of a building of a model over time (v.histo.timeline), each version with
  the years it stands (``Scene.chunk_years``; a version standing in two
  spans of years, which a map between them missed, is a feature per span: its
  geometry twice, the years exact), so that a viewer shows the town
  of a year by styling (``${first_year} <= year && year <= ${last_year}``).
  Each glTF carries them as 3D Tiles 1.1 wants, EXT_mesh_features (a feature
  id per vertex) and EXT_structural_metadata (a property table of class
  ``building``: :data:`PROPERTIES`): ``id`` (the CityJSON id), ``first_year``
  and ``last_year`` (0: a model of one date, which knows no years),
  ``years`` (the spans as text, ``1880-1914`` or ``1880-1900, 1915-1930``),
  ``certainty`` (the model's class 1-5, :mod:`reconstruction.lod2.certainty`;
  0 where a building has none) and ``attributes`` (every attribute, as JSON
  text: the schema of a property table is fixed, a model's attributes are not).
- **Tiling: an explicit quadtree by extent**, not implicit tiling. A series
  of sheets covers its ground unevenly (sheets apart, empty fields between
  them), which an explicit tree follows: a tile is split in four while it
  holds more than :data:`LEAF_FEATURES` features (each in the quarter of its
  foot's middle, down to :data:`MAX_DEPTH`), empty quarters have no tile,
  and ``tileset.json`` stays small (a few hundred tiles for a city) with no
  binary availability subtrees to write. Only leaves have content; inner
  tiles refine by ``ADD`` and have the horizontal diagonal of their box as
  ``geometricError`` (what is missing while their children are not drawn),
  the leaves 0, the tileset the diagonal of the whole model (the error of
  drawing nothing): a viewer loads the tiles near the camera and in view, the
  sheets far away not at all. Bounding boxes are the tight boxes of a
  tile's buildings.
- **Placement**: the glTF is y-up in metres from the scene's origin (east,
  north, up of the model's CRS), which a 3D Tiles reader turns z-up; the
  root's ``transform`` puts those local metres on the globe (ECEF). It is the
  linear map of the model's CRS to ECEF at the model's middle (PROJ, through
  pyproj: the grid's convergence and scale included), exact there and off by
  millimetres at a few kilometres; heights are taken as ellipsoidal (the
  viewer has no terrain). InputError for a model without a reference system
  PROJ knows.
"""

import json
import os
from dataclasses import dataclass

import numpy as np

from ..core.errors import InputError
from ..core import crs as crs_codes
from . import gltf

GENERATOR = "histo (GRASS GIS addon suite), reconstruction.view.tiles"
#: a tile with more features is split in four
LEAF_FEATURES = 1000
#: the deepest level of the quadtree (a tile of 1/4**12 of the extent holds any count)
MAX_DEPTH = 12
#: the folder of the tiles' glTF in the tileset's directory
CONTENT = "content"
TILESET = "tileset.json"
#: the metadata class of the features and its properties (EXT_structural_metadata)
CLASS = "building"
PROPERTIES = {
    "id": {"description": "The building's CityJSON id", "type": "STRING", "required": True},
    "first_year": {"description": "First year the building (this version) stands; 0: a model "
                   "of one date", "type": "SCALAR", "componentType": "INT32", "noData": 0},
    "last_year": {"description": "Last year the building (this version) stands; 0: a model "
                  "of one date", "type": "SCALAR", "componentType": "INT32", "noData": 0},
    "years": {"description": "The spans of years the building (this version) stands, e.g. "
              "1880-1914 or 1880-1900, 1915-1930", "type": "STRING"},
    "certainty": {"description": "Certainty class: 5 copied, 4 measured, 3 aligned, "
                  "2 generated, 1 drawn; 0: none", "type": "SCALAR", "componentType": "UINT8",
                  "noData": 0},
    "attributes": {"description": "The building's attributes as JSON text", "type": "STRING"},
}


@dataclass(frozen=True)
class Tile:
    """A tile of the quadtree: ``level`` and ``x``, ``y`` (its quarter at each level),
    ``box``: (min x, y, z, max x, y, z) of its features in metres from the scene's
    origin, ``features``: indices of the :class:`Feature` it holds (a leaf; () for an inner
    tile), ``children``: its tiles."""

    level: int
    x: int
    y: int
    box: tuple
    features: tuple = ()
    children: tuple = ()

    @property
    def name(self):
        return "{}_{}_{}".format(self.level, self.x, self.y)


@dataclass(frozen=True)
class TilesetReport:
    """What :func:`write_tileset` wrote: ``features`` (buildings, or versions of them),
    ``tiles`` (with content) and ``depth`` (levels of the quadtree)."""

    features: int
    tiles: int
    depth: int


@dataclass(frozen=True)
class Feature:
    """A feature of the tiles: ``chunk`` of the scene (of ``building``) standing from
    ``first`` to ``last`` (years, both included; 0 and 0 for a model of one date)."""

    building: int
    chunk: int
    first: int = 0
    last: int = 0


def features_of(scene):
    """The :class:`Feature` list of ``scene``: every chunk with triangles (a building of
    a model of one date; a version of one of a model over time), once per span of
    years it stands (a version that a map missed between two that show it stands
    twice: a feature each, so that first and last year say exactly when it stands)."""
    out = []
    for c in np.flatnonzero(np.diff(scene.chunk_start.astype(np.int64)) > 0):
        b = int(scene.chunk_building[c])
        out.extend(Feature(b, int(c), int(first), int(last))
                   for first, last in scene.chunk_years[c] or ((0, 0),))
    return out


def _boxes(scene, features):
    """(n, 6) min and max corners of each feature's vertices (metres from the origin)."""
    out = np.empty((len(features), 6))
    for i, feature in enumerate(features):
        k = feature.chunk
        p = scene.positions[scene.chunk_vertex[k]:scene.chunk_vertex[k + 1]]
        out[i, :3], out[i, 3:] = p.min(axis=0), p.max(axis=0)
    return out


def quadtree(boxes, leaf=LEAF_FEATURES, max_depth=MAX_DEPTH):
    """The root :class:`Tile` of the features of ``boxes`` ((n, 6), :func:`_boxes`):
    split in four while a tile holds more than ``leaf`` features."""
    middle = (boxes[:, :2] + boxes[:, 3:5]) / 2
    low, high = middle.min(axis=0), middle.max(axis=0)
    size = max(float((high - low).max()), 1e-9)

    def tile(level, x, y, members):
        box = tuple(float(v) for v in np.concatenate([boxes[members, :3].min(axis=0),
                                                      boxes[members, 3:].max(axis=0)]))
        if len(members) <= leaf or level >= max_depth:
            return Tile(level, x, y, box, features=tuple(int(m) for m in members))
        cell = size / 2 ** (level + 1)
        qx = np.clip((middle[members, 0] - low[0]) // cell - 2 * x, 0, 1).astype(int)
        qy = np.clip((middle[members, 1] - low[1]) // cell - 2 * y, 0, 1).astype(int)
        children = tuple(tile(level + 1, 2 * x + i, 2 * y + j, members[(qx == i) & (qy == j)])
                         for j in (0, 1) for i in (0, 1) if ((qx == i) & (qy == j)).any())
        return Tile(level, x, y, box, children=children)

    return tile(0, 0, 0, np.arange(len(boxes)))


def enu_to_ecef(reference_system, origin, middle):
    """The 4x4 matrix (column-major list of 16, as 3D Tiles' ``transform``) from metres
    from ``origin`` (east, north, up of the model's CRS) to ECEF, linear at ``middle``
    (model coordinates). InputError when PROJ does not know the reference system."""
    from pyproj import CRS, Transformer
    from pyproj.exceptions import CRSError

    code = crs_codes.epsg_code(reference_system)
    if code is None:
        raise InputError("The model has no reference system (EPSG code) to put its 3D Tiles "
                         "on the globe: give the location an EPSG code")
    try:
        to_ecef = Transformer.from_crs(CRS.from_epsg(code), CRS.from_epsg(4978), always_xy=True)
    except CRSError as error:
        raise InputError("The model's reference system EPSG:{} is unknown to PROJ: {}".format(
            code, error)) from None
    step = 100.0
    centre = np.asarray(middle, dtype=float)
    points = np.array([centre] + [centre + s * step * e for e in np.eye(3) for s in (1, -1)])
    x, y, z = to_ecef.transform(points[:, 0], points[:, 1], points[:, 2])
    ecef = np.column_stack([x, y, z])
    if not np.isfinite(ecef).all():
        raise InputError("The model's coordinates are outside the area of its reference "
                         "system EPSG:{}: no place on the globe".format(code))
    axes = np.column_stack([(ecef[1 + 2 * i] - ecef[2 + 2 * i]) / (2 * step) for i in range(3)])
    matrix = np.eye(4)
    matrix[:3, :3] = axes
    matrix[:3, 3] = ecef[0] - axes @ (centre - np.asarray(origin, dtype=float))
    return [float(v) for v in matrix.T.ravel()]


def _box_volume(box):
    low, high = np.asarray(box[:3]), np.asarray(box[3:])
    middle, half = (low + high) / 2, np.maximum((high - low) / 2, 0.01)
    return {"box": [float(v) for v in middle] + [float(half[0]), 0.0, 0.0, 0.0, float(half[1]),
                                                 0.0, 0.0, 0.0, float(half[2])]}


def _spans_text(spans):
    return ", ".join("{}-{}".format(a, b) if a != b else str(a) for a, b in spans)


def _feature_rows(scene, features):
    """Per feature: id, first and last year, years text, certainty, attributes."""
    for feature in features:
        attributes = scene.attributes[feature.building]
        certainty = attributes.get("certainty")
        yield (scene.ids[feature.building], feature.first, feature.last,
               _spans_text(scene.chunk_years[feature.chunk]),
               int(certainty) if isinstance(certainty, (int, float)) and 0 < certainty < 256
               else 0, gltf.json_safe(attributes))


def _strings(texts):
    """A STRING property's values and UINT32 offsets (bytes)."""
    data = [t.encode("utf-8") for t in texts]
    offsets = np.cumsum([0] + [len(d) for d in data]).astype("<u4")
    return b"".join(data), offsets.tobytes()


def property_table(scene, features):
    """The ``features`` callable of :func:`reconstruction.view.gltf.write_parts` for the
    parts of ``features`` (:class:`Feature`, in order): their EXT_structural_metadata
    (schema :data:`PROPERTIES`, one property table) and its blobs."""
    def metadata_of(_parts, first_view):
        rows = list(_feature_rows(scene, features))
        ids, first, last, years, certainty, attributes = (
            list(c) for c in zip(*rows)) if rows else ([],) * 6
        blobs, properties = [], {}

        def view(data):
            blobs.append(data)
            return first_view + len(blobs) - 1

        for name, texts in (("id", ids), ("years", years),
                            ("attributes", [json.dumps(a, ensure_ascii=False,
                                                       separators=(",", ":"))
                                            for a in attributes])):
            values, offsets = _strings(texts)
            properties[name] = {"values": view(values), "stringOffsets": view(offsets),
                                "stringOffsetType": "UINT32"}
        for name, values, dtype in (("first_year", first, "<i4"), ("last_year", last, "<i4"),
                                    ("certainty", certainty, "u1")):
            properties[name] = {"values": view(np.asarray(values, dtype=dtype).tobytes())}
        metadata = {"schema": {"id": "histo_building", "classes": {CLASS: {
            "name": "Building", "properties": PROPERTIES}}},
            "propertyTables": [{"name": "buildings", "class": CLASS, "count": len(rows),
                                "properties": properties}]}
        return metadata, blobs

    return metadata_of


def _tile_json(tile, scene, features, directory, folder, written):
    node = {"boundingVolume": _box_volume(tile.box),
            "geometricError": 0.0 if tile.features else float(np.hypot(
                tile.box[3] - tile.box[0], tile.box[4] - tile.box[1])),
            "refine": "ADD"}
    if tile.features:
        uri = "{}/{}.glb".format(CONTENT, tile.name)
        with open(os.path.join(directory, uri), "wb") as f:
            own = [features[i] for i in tile.features]
            gltf.write_parts(f, scene, [(t.building, [t.chunk]) for t in own], folder,
                             property_table(scene, own))
        node["content"] = {"uri": uri}
        written.append(tile)
    if tile.children:
        node["children"] = [_tile_json(c, scene, features, directory, folder, written)
                            for c in tile.children]
    return node


def write_tileset(directory, scene, title=None, leaf=LEAF_FEATURES, folder=None):
    """Write ``scene`` (a :class:`~reconstruction.view.scene.Scene` with a reference
    system) as 3D Tiles 1.1 into ``directory`` (an existing, empty directory):
    ``tileset.json`` and ``content/<level>_<x>_<y>.glb``. Returns a
    :class:`TilesetReport`. InputError when the model has nothing to draw or no
    reference system PROJ knows."""
    features = features_of(scene)
    if not features:
        raise InputError("The model has no surfaces to draw")
    boxes = _boxes(scene, features)
    low, high = boxes[:, :3].min(axis=0), boxes[:, 3:].max(axis=0)
    middle = np.asarray(scene.origin, dtype=float) + (low + high) / 2
    transform = enu_to_ecef(scene.crs, scene.origin, middle)
    root = quadtree(boxes, leaf)
    os.makedirs(os.path.join(directory, CONTENT), exist_ok=True)
    written = []
    node = _tile_json(root, scene, features, directory, folder or directory, written)
    node["transform"] = transform
    asset = {"version": "1.1", "generator": GENERATOR}
    extras = {"crs": scene.crs, "origin": [float(v) for v in scene.origin]}
    if scene.years:
        extras["years"] = list(scene.years)
    if title:
        asset["extras"] = {"title": title}
    # the error of drawing nothing at all: the whole model (a viewer draws no tile while
    # this is small on the screen)
    error = float(np.linalg.norm(np.subtract(root.box[3:], root.box[:3])))
    tileset = {"asset": asset, "geometricError": max(error, node["geometricError"], 1.0),
               "root": node, "extras": extras}
    with open(os.path.join(directory, TILESET), "w", encoding="utf-8") as f:
        json.dump(tileset, f, ensure_ascii=False, indent=1)
    return TilesetReport(features=len(features), tiles=len(written), depth=_depth(root))


def _depth(tile):
    return 1 + max((_depth(c) for c in tile.children), default=0)

