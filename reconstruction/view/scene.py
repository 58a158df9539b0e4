"""What a viewer draws of a CityJSON city model: triangles by building, in typed arrays.

A :class:`Scene` is the model made ready for a browser or a glTF file: one
list of vertices (float32, metres east, north and up from a local origin)
and one of triangles, grouped in *chunks*, one per building and version of
its geometry. A building of a single map has one chunk; a building of a
dynamic model (v.histo.timeline, :mod:`reconstruction.epochs.dynamic`) has
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

Pure: numpy and the CityJSON document (a dict); pyvista imported lazily.
"""

from dataclasses import dataclass
from typing import Optional

import numpy as np

from ..cityjson import geometry as citygeometry
from ..cityjson.seq import object_tree
from ..core.errors import InputError
from ..epochs.dynamic import epoch_years, standing_versions

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
VERSION_ATTRIBUTES = ("geometry_epochs",)


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
    attributes: tuple
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

    def standing(self, year):
        """The chunks drawn in ``year`` (all of them for a model of one date)."""
        return np.array([not spans or any(a <= year <= b for a, b in spans)
                         for spans in self.chunk_years], dtype=bool)


def _vertices(document):
    t = document.get("transform") or {"scale": [1, 1, 1], "translate": [0, 0, 0]}
    vertices = np.asarray(document.get("vertices") or np.zeros((0, 3)), dtype=float)
    return vertices.reshape(-1, 3) * t["scale"] + t["translate"]


def _versions(document, oid):
    """The geometries of a building's tree to draw, grouped by version: {key: [(geometry)]},
    the key the epochs of the version (a tuple) or None for a model of one date."""
    objects = document["CityObjects"]
    out = {}
    for member in object_tree(objects, oid):
        obj = objects[member]
        geoms = [g for g in obj.get("geometry", ()) if g.get("type") in citygeometry.SURFACE_DEPTH]
        if not geoms:
            continue
        epochs = (obj.get("attributes") or {}).get("geometry_epochs")
        if epochs is not None and len(epochs) == len(obj.get("geometry", ())):
            keyed = [(tuple(e), g) for g, e in zip(obj["geometry"], epochs)
                     if g.get("type") in citygeometry.SURFACE_DEPTH]
        else:
            top = max(citygeometry.lod_value(g.get("lod")) for g in geoms)
            keyed = [(None, g) for g in geoms if citygeometry.lod_value(g.get("lod")) == top]
        for key, g in keyed:
            out.setdefault(key, []).append(g)
    return out


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
    objects = document.get("CityObjects") or {}
    xyz = _vertices(document)
    tops = [oid for oid, obj in objects.items() if not obj.get("parents")]
    copied = set(copied or ())
    rings, face_kind, face_chunk, keys = [], [], [], []
    for b, oid in enumerate(tops):
        for key, geoms in _versions(document, oid).items():
            chunk = len(keys)
            keys.append((b, key))
            for g in geoms:
                faces, types = citygeometry.surface_types(g)
                for face, kind in zip(faces, types):
                    if face and len(face[0]) >= 3:
                        rings.append(face[0])
                        face_kind.append(KIND.get(kind, OTHER))
                        face_chunk.append(chunk)
    if not rings:
        raise InputError("The model has no surfaces to draw")
    origin = xyz.min(axis=0)
    triangles, face, points = _triangulated(xyz - origin, rings)
    kind = np.asarray(face_kind, dtype=np.uint8)[face]
    chunk = np.asarray(face_chunk, dtype=np.int64)[face]
    order = np.lexsort((kind, chunk))
    triangles, kind, chunk = triangles[order], kind[order], chunk[order]
    # one vertex per (chunk, kind, point): shared within a chunk's surfaces of one kind
    corner = np.column_stack([np.repeat(chunk, 3), np.repeat(kind, 3), triangles.ravel()])
    unique, inverse = np.unique(corner, axis=0, return_inverse=True)
    dynamic = any(key is not None for _b, key in keys)
    if dynamic:
        chunk_years, years = _spans(document, tops, [(b, key) for b, key in keys])
    else:
        chunk_years, years = tuple(() for _ in keys), ()
    attributes = tuple({n: v for n, v in (objects[o].get("attributes") or {}).items()
                        if n not in VERSION_ATTRIBUTES} for o in tops)
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
        chunk_years=chunk_years, origin=origin, years=years, crs=crs)
