"""What a viewer draws of a CityJSON city model: triangles by building, in typed arrays.

A :class:`Scene` is the model made ready for a browser or a glTF file: one
list of vertices (float32, metres east, north and up from a local origin)
and one of triangles, grouped in *chunks*, one per building and version of
its geometry. A building of a single map has one chunk; a building of a
dynamic model (v.histo.timeline, :mod:`reconstruction.epochs.dynamic`: its
versions ``+BuildingVersion`` city objects of the suite's Extension) has
one per version, and each chunk says in which years it stands
(:attr:`Scene.chunk_years`), by the snapshot's own rule
(:func:`reconstruction.epochs.dynamic.standing_versions`): the slider of a
viewer shows exactly the buildings of that year's snapshot.

Within a chunk, the triangles of one kind of surface (ground, wall, roof)
share their vertices; a vertex on the eaves is stored once for the walls and
once for the roof, so that a viewer can colour by vertex and shade flat.
Faces are triangulated by VTK's polygon triangulation (pyvista, as the
pictures of v.histo.lod2 are), which handles the concave faces of concave
footprints.

A CityJSONSeq file is drawn without ever holding its whole document
(:func:`scene_of_seq`, issue 49 item 14): its features are read a batch at a
time, twice (first for the model's lowest corner, the scene's origin), each
batch cut into triangles with the whole model's origin and let go, its arrays
gathered in temporary files beside the model and read into one array each at
the end; the buildings' attributes are kept as zlib-compressed JSON texts
(:class:`AttributeTexts`). The scene is the one :func:`build_scene` makes of
the whole document, array for array.

Pure: numpy and the CityJSON document (a dict); pyvista imported lazily.
"""

import json
import os
import tempfile
import zlib
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Optional

import numpy as np

from ..cityjson import geometry as citygeometry
from ..cityjson import seq as cityjsonseq
from ..cityjson.seq import object_tree
from ..core.errors import InputError
from ..cityjson import versions as cityversions
from ..epochs.dynamic import buildings, epoch_years, standing_versions, version_index

#: surface kinds, as the pictures of v.histo.lod2 colour them
GROUND, WALL, ROOF, OTHER = 0, 1, 2, 3
KIND = {"GroundSurface": GROUND, "WallSurface": WALL, "RoofSurface": ROOF,
        "ClosureSurface": OTHER}
#: the suite's colours (sRGB 0-255) by surface kind, for every picture, page and glTF:
#: roofs red, walls white, ground grey, as in the thesis's Fig. 5.22; the buildings
#: copied from an existing model in a second scheme (blue roofs, pale blue walls)
COLOURS = np.array([[150, 150, 150], [245, 245, 245], [200, 30, 25], [190, 190, 190]],
                   dtype=np.uint8)
COPIED_COLOURS = np.array([[150, 150, 150], [205, 222, 240], [35, 85, 170], [190, 200, 215]],
                          dtype=np.uint8)
#: the background behind a model
BACKGROUND = (214, 224, 235)
#: attributes of a dynamic model's building that describe its versions, not the building
VERSION_ATTRIBUTES = (cityversions.TRANSITIONS,)
#: features of a CityJSONSeq file read and cut into triangles at a time (:func:`scene_of_seq`)
STEP = 500
#: a scene's arrays: (name, dtype, what its values count (None: nothing), whether it ends
#: with the count of that, the end of its last item)
ARRAYS = (("copied", bool, None, False), ("positions", np.float32, None, False),
          ("kinds", np.uint8, None, False), ("triangles", np.uint32, "vertices", False),
          ("chunk_start", np.uint32, "triangles", True),
          ("chunk_vertex", np.uint32, "vertices", True),
          ("chunk_building", np.uint32, "buildings", False))


def attribute_text(attributes):
    """A building's attributes (a dict) as the JSON text the page and the glTF write."""
    return json.dumps(attributes, ensure_ascii=False, separators=(",", ":"))


@dataclass(frozen=True)
class AttributeTexts(Sequence):
    """The buildings' attributes as JSON texts (:func:`attribute_text`) in blocks, each
    block its buildings' texts joined by commas, UTF-8, zlib-compressed: a building's
    attributes take some tens of bytes instead of a dict's kilobyte or two. ``blocks``: the
    compressed blocks; ``starts``: per block, where each text starts in it and where
    the last ends (int64 arrays). An item is the building's dict, decoded."""

    blocks: tuple
    starts: tuple
    #: the first building of each block, and the last block decompressed (its index and
    #: bytes): texts are read in order
    _cache: dict = field(default_factory=dict, init=False, repr=False, compare=False)

    @staticmethod
    def of(dicts):
        """One block of the attributes ``dicts``: its compressed bytes and its starts."""
        texts = [attribute_text(a).encode("utf-8") for a in dicts]
        starts = np.cumsum([0] + [len(t) + 1 for t in texts], dtype=np.int64)
        return zlib.compress(b",".join(texts), 1), starts

    @property
    def _first(self):
        if "first" not in self._cache:
            self._cache["first"] = np.cumsum([0] + [len(s) - 1 for s in self.starts])
        return self._cache["first"]

    def __len__(self):
        return int(self._first[-1])

    def __getitem__(self, b):
        if isinstance(b, slice):
            return [self[i] for i in range(*b.indices(len(self)))]
        return json.loads(self.text(b))

    def _block(self, k):
        if self._cache.get("k") != k:
            self._cache.update(k=k, block=zlib.decompress(self.blocks[k]))
        return self._cache["block"]

    def text(self, b):
        """The JSON text of building ``b``'s attributes."""
        k = int(np.searchsorted(self._first, b, side="right")) - 1
        i = b - int(self._first[k])
        start, end = self.starts[k][i], self.starts[k][i + 1] - 1
        return str(self._block(k)[start:end], "utf-8")

    def joined(self):
        """The texts of every building, joined by commas, a block at a time (str)."""
        for k in range(len(self.blocks)):
            if len(self.starts[k]) > 1:
                yield str(zlib.decompress(self.blocks[k]), "utf-8")


@dataclass(frozen=True)
class Scene:
    """A city model as a viewer draws it.

    ``ids`` and ``attributes``: per building (a top-level city object), its
    id and attributes; ``copied``: per building, whether it was copied from
    an existing 3D model (drawn in the second colour scheme).
    ``positions``: (n, 3) float32 vertices, metres from ``origin`` (the
    model's coordinates of the local zero, float64); ``kinds``: (n,) uint8
    the surface kind of each vertex (:data:`GROUND`, :data:`WALL`,
    :data:`ROOF`, :data:`OTHER`); ``triangles``: (m, 3) uint32, grouped by
    chunk. Chunk ``k`` holds triangles ``chunk_start[k]`` to
    ``chunk_start[k + 1]`` and vertices ``chunk_vertex[k]`` to
    ``chunk_vertex[k + 1]`` of building ``chunk_building[k]``;
    ``chunk_years[k]``: the (first, last) years, both included, in which it
    stands, or () for a model of one date (always drawn). ``years``: the
    dynamic model's (first, last) epoch, or (); ``crs``: the model's
    reference system (a URL) or None.
    """

    ids: tuple
    attributes: Sequence
    copied: np.ndarray
    positions: np.ndarray
    kinds: np.ndarray
    triangles: np.ndarray
    chunk_start: np.ndarray
    chunk_vertex: np.ndarray
    chunk_building: np.ndarray
    chunk_years: tuple
    origin: np.ndarray
    years: tuple = ()
    crs: Optional[str] = None

    @property
    def buildings(self):
        return len(self.ids)

    def attribute_texts(self):
        """The attributes of every building as JSON text (:func:`attribute_text`), joined
        by commas, a few hundred buildings at a time (str)."""
        if isinstance(self.attributes, AttributeTexts):
            yield from self.attributes.joined()
            return
        for a in range(0, len(self.attributes), 500):
            yield ",".join(map(attribute_text, self.attributes[a:a + 500]))

    def standing(self, year):
        """The chunks drawn in ``year`` (all of them for a model of one date)."""
        return np.array([not spans or any(a <= year <= b for a, b in spans)
                         for spans in self.chunk_years], dtype=bool)


def _vertices(document):
    t = document.get("transform") or {"scale": [1, 1, 1], "translate": [0, 0, 0]}
    vertices = np.asarray(document.get("vertices") or np.zeros((0, 3)), dtype=float)
    return vertices.reshape(-1, 3) * t["scale"] + t["translate"]


def _surfaces(obj):
    return [g for g in obj.get("geometry", ()) if g.get("type") in citygeometry.SURFACE_DEPTH]


def _versions(document, oid, index=None):
    """The geometries of a building's tree to draw, grouped by version: {key: [(geometry)]},
    the key the epochs of the version (a tuple) or None for a model of one date;
    ``index``: the model's :func:`~reconstruction.epochs.dynamic.version_index` (None: a
    model of one date)."""
    objects = document["CityObjects"]
    out = {}
    for member in object_tree(objects, oid):
        if index is not None:
            for version in index.get(member, ()):
                for g in _surfaces(version):
                    out.setdefault(tuple(version["epochs"]), []).append(g)
            continue
        geoms = _surfaces(objects[member])
        if geoms:
            top = max(citygeometry.lod_value(g.get("lod")) for g in geoms)
            out.setdefault(None, []).extend(
                g for g in geoms if citygeometry.lod_value(g.get("lod")) == top)
    return out


def _attributes(objects, oid, index):
    """The attributes a viewer shows of building ``oid``: its own, and for a model over
    time its lifespan over those of its first version (without its transitions)."""
    own = objects[oid].get("attributes") or {}
    first = (index or {}).get(oid)
    base = dict(first[0].get("attributes") or {}) if first else {}
    base.update((n, v) for n, v in own.items() if n not in VERSION_ATTRIBUTES)
    return base


def _spans(document, tops, keys):
    """Per chunk (building index, version epochs), the (first, last) year spans in which it
    stands: the snapshot's choice only changes at an epoch or a construction year."""
    years = epoch_years(document)
    objects = document["CityObjects"]
    built = {a.get("dateOfConstruction") for a in
             ((objects[o].get("attributes") or {}) for o in tops)}
    breaks = sorted(set(years) | {y for y in built
                                  if isinstance(y, int) and years[0] < y < years[-1]})
    shown = {b: standing_versions(document, b) for b in breaks}
    out = []
    for building, epochs in keys:
        spans, start = [], None
        for k, b in enumerate(breaks):
            on = shown[b].get(tops[building]) in epochs
            if on and start is None:
                start = b
            if start is not None and (not on or k == len(breaks) - 1):
                spans.append((start, b if on else b - 1))
                start = None
        out.append(tuple(spans))
    return tuple(out), (years[0], years[-1])


def _triangulated(points, rings):
    """Triangles (t, 3) of planar polygons given as index lists into ``points``, and the
    polygon of each triangle (VTK's polygon triangulation, through pyvista)."""
    import pyvista as pv

    flat, start = citygeometry.flat_indices(rings)
    faces = np.insert(flat, start[:-1], np.diff(start))
    mesh = pv.PolyData(points, faces=faces)
    mesh.cell_data["face"] = np.arange(len(rings))
    tri = mesh.triangulate()
    cells = tri.faces.reshape(-1, 4)
    if len(cells) and (cells[:, 0] != 3).any():
        raise InputError("Some faces of the model could not be cut into triangles")
    return cells[:, 1:], np.asarray(tri.cell_data["face"]), np.asarray(tri.points)


def build_scene(document, copied=()):
    """The :class:`Scene` of a CityJSON document (dict); ``copied``: ids of top-level
    objects copied from an existing 3D model. InputError when it has nothing to draw."""
    xyz = _vertices(document)
    scene, faces = _scene(document, set(copied or ()), xyz.min(axis=0) if len(xyz) else None)
    if not faces:
        raise InputError("The model has no surfaces to draw")
    return scene


def _scene(document, copied, origin):
    """The :class:`Scene` of ``document`` with its vertices from ``origin`` (None: none
    to draw), and the number of faces drawn (0: the scene is empty)."""
    objects = document.get("CityObjects") or {}
    index = version_index(objects) if cityversions.is_versioned(document) else None
    tops = buildings(objects)
    rings, face_kind, face_chunk, keys = [], [], [], []
    for b, oid in enumerate(tops):
        for key, geoms in _versions(document, oid, index).items():
            chunk = len(keys)
            keys.append((b, key))
            for g in geoms:
                faces, types = citygeometry.surface_types(g)
                for face, kind in zip(faces, types):
                    if face and len(face[0]) >= 3:
                        rings.append(face[0])
                        face_kind.append(KIND.get(kind, OTHER))
                        face_chunk.append(chunk)
    if rings:
        triangles, face, points = _triangulated(_vertices(document) - origin, rings)
    else:
        triangles, face, points = (np.zeros((0, 3), np.int64), np.zeros(0, np.int64),
                                   np.zeros((0, 3)))
    kind = np.asarray(face_kind, dtype=np.uint8)[face]
    chunk = np.asarray(face_chunk, dtype=np.int64)[face]
    order = np.lexsort((kind, chunk))
    triangles, kind, chunk = triangles[order], kind[order], chunk[order]
    # one vertex per (chunk, kind, point): shared within a chunk's surfaces of one kind
    corner = np.column_stack([np.repeat(chunk, 3), np.repeat(kind, 3), triangles.ravel()])
    if len(corner):
        unique, inverse = np.unique(corner, axis=0, return_inverse=True)
    else:
        unique, inverse = np.zeros((0, 3), np.int64), np.zeros(0, np.int64)
    dynamic = any(key is not None for _b, key in keys)
    if dynamic:
        chunk_years, years = _spans(document, tops, [(b, key) for b, key in keys])
    else:
        chunk_years, years = tuple(() for _ in keys), ()
    attributes = tuple(_attributes(objects, o, index) for o in tops)
    crs = (document.get("metadata") or {}).get("referenceSystem")
    return Scene(
        ids=tuple(tops), attributes=attributes,
        copied=np.array([o in copied for o in tops], dtype=bool),
        positions=points[unique[:, 2]].astype(np.float32),
        kinds=unique[:, 1].astype(np.uint8),
        triangles=inverse.reshape(-1, 3).astype(np.uint32),
        chunk_start=np.searchsorted(chunk, np.arange(len(keys) + 1)).astype(np.uint32),
        chunk_vertex=np.searchsorted(unique[:, 0], np.arange(len(keys) + 1)).astype(np.uint32),
        chunk_building=np.array([b for b, _key in keys], dtype=np.uint32),
        chunk_years=chunk_years, origin=origin, years=years, crs=crs), len(rings)


def scene_of_seq(path, copied=(), step=None, name=None):
    """The :class:`Scene` of the CityJSONSeq file at ``path`` (what :func:`build_scene`
    makes of its document), read ``step`` (default :data:`STEP`) features at a time:
    never the whole model's objects at once (issue 49, item 14). A dynamic model (a
    building with versions) is read whole. ``name``: the file's name in messages
    (default ``path``). InputError when it has nothing to draw."""
    copied, name, step = set(copied or ()), name or path, step or STEP
    with open(path, encoding="utf-8") as f:
        low, head, dynamic = _lowest(cityjsonseq.read_batches(f, name, step))
    if dynamic:
        with open(path, encoding="utf-8") as f:
            return build_scene(cityjsonseq.collect(f, name), copied)
    origin = None if low is None else _vertices({"transform": head.get("transform"),
                                                 "vertices": [low]})[0]
    parts = _Parts(os.path.dirname(os.path.abspath(path)))
    try:
        with open(path, encoding="utf-8") as f:
            for doc, offsets, _counts in cityjsonseq.read_batches(f, name, step):
                parts.add(*_scene(cityjsonseq.joined(doc, offsets), copied, origin))
        if not parts.faces:
            raise InputError("The model has no surfaces to draw")
        return parts.scene(origin, (head.get("metadata") or {}).get("referenceSystem"))
    finally:
        parts.close()


def _lowest(batches):
    """The lowest corner (integer vertex rows) of every vertex the geometries of the
    batches use (None: none), the header, and whether a building has versions."""
    low, head, dynamic = None, {}, False
    for doc, offsets, _counts in batches:
        head = {"transform": doc.get("transform"), "metadata": doc.get("metadata")}
        geoms, shift = [], []
        for oid, obj in doc["CityObjects"].items():
            dynamic = dynamic or obj.get("type") == cityversions.VERSION
            for g in obj.get("geometry", ()):
                geoms.append(g)
                shift.append(offsets[oid])
        used = citygeometry.indices(geoms, shift) if geoms else np.zeros(0, np.int64)
        if len(used):
            rows = np.asarray(doc["vertices"], dtype=np.int64).reshape(-1, 3)[np.unique(used)]
            least = rows.min(axis=0)
            low = least if low is None else np.minimum(low, least)
    return low, head, dynamic


class _Parts:
    """The scenes of consecutive batches of a model, gathered into one: their arrays
    (indices counted on from the batches before) each in a temporary file in ``folder``
    until the last batch (then read into one array: never held twice), ids and
    attributes (a block of :class:`AttributeTexts` a batch)."""

    def __init__(self, folder=None):
        self.files = {name: tempfile.TemporaryFile(dir=folder) for name, *_ in ARRAYS}
        self.count = {"vertices": 0, "triangles": 0, "buildings": 0, "chunks": 0}
        self.ids, self.blocks, self.faces = [], [], 0

    def close(self):
        for f in self.files.values():
            f.close()

    def add(self, part, faces):
        for name, dtype, counts, ends in ARRAYS:
            values = getattr(part, name)
            if counts is not None:
                values = (values[:-1] if ends else values) + dtype(self.count[counts])
            self.files[name].write(np.ascontiguousarray(values, dtype=dtype).tobytes())
        self.count["vertices"] += len(part.positions)
        self.count["triangles"] += len(part.triangles)
        self.count["buildings"] += len(part.ids)
        self.count["chunks"] += len(part.chunk_building)
        self.ids.extend(part.ids)
        self.blocks.append(AttributeTexts.of(part.attributes))
        self.faces += faces

    def scene(self, origin, crs):
        """The scene of every batch."""
        shape = {"copied": (self.count["buildings"],), "positions": (self.count["vertices"], 3),
                 "kinds": (self.count["vertices"],), "triangles": (self.count["triangles"], 3),
                 "chunk_start": (self.count["chunks"] + 1,),
                 "chunk_vertex": (self.count["chunks"] + 1,),
                 "chunk_building": (self.count["chunks"],)}
        arrays = {}
        for name, dtype, counts, ends in ARRAYS:
            out = arrays[name] = np.empty(shape[name], dtype=dtype)
            data = memoryview(out).cast("B")
            f = self.files[name]
            f.seek(0)
            if ends:
                out[-1] = self.count[counts]
                data = data[:-out.itemsize]
            if f.readinto(data) != len(data):
                raise OSError("a temporary file of the viewer's scene was cut short")
        return Scene(ids=tuple(self.ids), attributes=AttributeTexts(*zip(*self.blocks)),
                     chunk_years=((),) * self.count["chunks"], origin=origin, crs=crs,
                     **arrays)
