"""Buildings copied from an existing city model, ready to merge into the generated one.

:func:`copy_buildings` takes the matched buildings of an
:class:`~reconstruction.cityjson.existing.ExistingModel` with their attributes, their
children (``BuildingPart`` ...) and the geometries of the LoDs chosen, and
puts their vertices on the output's grid (integers of the output scale,
absolute: a coordinate is ``value * scale``): no coordinate moves by more
than half the output scale. The copied buildings keep their ids and LoDs;
appearances (materials, textures) and geometry templates are not copied.
:mod:`reconstruction.cityjson.merge` adds them to the generated model;
:func:`by_building` numbers their vertices building by building, as
CityJSONSeq features need them.
"""

import collections
import dataclasses
from dataclasses import dataclass, field
from typing import Optional

import numpy as np

from ..geom.rings import corners, offsets, unique_rows
from ..geom.solidset import SolidSet
from . import geometry as citygeometry

SCALE = 0.001


@dataclass
class CopyReport:
    """What was copied: buildings, city objects (with their children),
    geometries by LoD, buildings without the LoDs asked for (copied at their
    highest LoD instead), geometries left out (GeometryInstances, unknown
    types) and surfaces that collapsed on the output grid."""
    buildings: int = 0
    objects: int = 0
    geometries: dict = field(default_factory=dict)
    lod_fallback: int = 0
    skipped_geometries: int = 0
    collapsed_surfaces: int = 0


@dataclass
class CopiedBuildings:
    """Buildings ready to be written.

    ``ids``: the top-level object ids; ``trees``: per building, its city
    objects by id (itself first), their geometries as the source model has
    them (use :meth:`objects` or :meth:`boundary_texts` for indices into
    ``vertices``); ``vertices``: (N, 3) int64 absolute coordinates in units
    of ``scale``, building after building from ``vertex_start``;
    ``reference_system`` and ``extensions``: of the model they come from
    (extensions only when a copied object uses one). ``layout`` (a
    :class:`~reconstruction.cityjson.geometry.Layout` of :meth:`geometries`) and
    ``rows`` (the vertex row of each of its entries) let the buildings be
    written with any numbering of the rows without walking their lists again;
    ``copied_geometries``: the list :meth:`geometries` returns, kept;
    ``stored_local``: the boundaries as stored index each building's own
    rows (:meth:`local_index`: CityJSONSeq features whose vertices are all
    copied, in their order): its feature is written as it was read.

    ``model_numbered``: the copy is a whole single-file model (every
    geometry of every object, each of its vertices used): ``vertices`` are
    then the model's, in its order, and the boundaries as stored index them
    (``rows``: the stored indices; ``vertex_start`` None; the layout walked
    only where a writer asks for it), so that the merged file can hold them
    as they were read; :func:`by_building` numbers such a copy building by
    building, as a CityJSONSeq feature wants its vertices.
    """
    ids: list
    trees: list
    vertices: np.ndarray
    vertex_start: np.ndarray
    scale: float
    reference_system: Optional[str]
    extensions: dict
    report: CopyReport
    layout: Optional[citygeometry.Layout] = None
    rows: Optional[np.ndarray] = None
    copied_geometries: Optional[list] = None
    stored_local: bool = False
    model_numbered: bool = False

    def __len__(self):
        return len(self.ids)

    def extent(self):
        """(lo, hi) integer corners of the copied vertices (None when there are none)."""
        if len(self.vertices) == 0:
            return None
        cached = getattr(self, "_extent", None)
        if cached is None or cached[0] is not self.vertices:
            cached = (self.vertices,) + corners(self.vertices)
            self._extent = cached
        return cached[1], cached[2]

    def geometries(self):
        """Every copied geometry (building after building, object after object)."""
        if self.copied_geometries is not None:
            return self.copied_geometries
        return [g for tree in self.trees for obj in tree.values() for g in obj.get("geometry", ())]

    def geometry_counts(self):
        """The number of copied geometries of every building."""
        return [sum(len(o.get("geometry", ())) for o in tree.values()) for tree in self.trees]

    def filled(self, n, fills):
        """The city objects of building ``n`` whose geometries' boundaries
        are the JSON texts of ``fills`` (an iterator, one text per geometry in
        order) as fragments (:func:`~reconstruction.cityjson.geometry.fragment`),
        written as they are by ``citygeometry.json_bytes``."""
        objs = {}
        for oid, obj in self.trees[n].items():
            if obj.get("geometry"):
                objs[oid] = dict(obj)
                objs[oid]["geometry"] = [dict(g, boundaries=citygeometry.fragment(next(fills)))
                                         for g in obj["geometry"]]
            else:
                objs[oid] = obj                 # nothing to put in: the copy as it is
        return objs

    def local_index(self):
        """Per vertex row its index among its building's own rows (not for a
        copy numbered as its model: see :func:`by_building`)."""
        if self.model_numbered:
            raise ValueError("the copy is numbered as its model: number it by building first")
        owner = np.repeat(np.arange(len(self.ids)), np.diff(self.vertex_start))
        return np.arange(len(self.vertices)) - self.vertex_start[owner]

    def walked(self):
        """The :class:`~reconstruction.cityjson.geometry.Layout` of :meth:`geometries`
        and the vertex row of each of its entries (walked on first use where
        the copy is numbered as its model: the rows are the stored indices)."""
        if self.layout is None:
            self.layout = citygeometry.layout(self.geometries())
            self.rows = self.layout.flat
        return self.layout, self.rows

    def boundary_texts(self, index=None):
        """The JSON text of the boundaries of every copied geometry with vertex
        indices ``index[row]`` (None: :meth:`local_index`)."""
        if index is None and self.model_numbered:
            return by_building(self).boundary_texts()
        index = self.local_index() if index is None else index
        lay, rows = self.walked()
        return citygeometry.texts(lay, index[rows])

    def objects(self, index=None):
        """Per building, its city objects with vertex indices ``index[row]``
        (None: :meth:`local_index`, each building's own from 0)."""
        if index is None and self.model_numbered:
            return by_building(self).objects()
        index = self.local_index() if index is None else index
        lay, rows = self.walked()
        new = iter(citygeometry.rebuild(lay, self.geometries(), index[rows]))
        out = []
        for tree in self.trees:
            objs = {}
            for oid, obj in tree.items():
                objs[oid] = dict(obj)
                if "geometry" in obj:
                    objs[oid]["geometry"] = [next(new) for _ in obj["geometry"]]
            out.append(objs)
        return out


@dataclass(frozen=True)
class CopiedSolids:
    """The copied Solid geometries as a :class:`~reconstruction.geom.solidset.SolidSet`
    (each solid's own vertices, millimetres), to be validated as the
    generated ones are; ``labels``: per solid, "<object id> (lod L)";
    ``unchecked``: Solids left out of ``solids`` because they have inner
    shells or faces with holes (the set holds outer rings of one shell)."""
    solids: SolidSet
    labels: list
    unchecked: int


def copied_solids(copied):
    """The :class:`CopiedSolids` of ``copied`` (a :class:`CopiedBuildings`
    on the millimetre grid)."""
    if abs(copied.scale - 0.001) > 1e-12:
        raise ValueError("copied solids are checked on the millimetre grid")
    lay, rows = copied.walked()
    labels_of = [(oid, g.get("lod")) for tree in copied.trees for oid, obj in tree.items()
                 for g in obj.get("geometry", ())]
    empty = SolidSet(np.zeros((0, 3), dtype=np.int64), np.zeros(0, dtype=np.int64),
                     np.zeros(1, dtype=np.int64), np.zeros(1, dtype=np.int64))
    group = [g for g in lay.groups if len(g[3]) == citygeometry.DEPTH["Solid"] and
             all(copied.geometries()[k].get("type") == "Solid" for k in g[0][:1])]
    if not group:
        return CopiedSolids(empty, [], 0)
    positions, first_leaf, _, (shells, surfaces, rings) = group[0]
    shell_start, surface_start = offsets(shells), offsets(surfaces)
    holed = np.bincount(np.repeat(np.arange(len(surfaces)), surfaces), weights=rings != 1,
                        minlength=len(surfaces)) > 0
    one = np.nonzero(shells == 1)[0]
    checked = one[~holed[shell_start[one]]]
    # the faces of the checked solids: the surfaces of their shell, one ring each
    shell = shell_start[checked]
    face_count = surfaces[shell]
    face_surface = np.repeat(surface_start[shell], face_count) + (
        np.arange(face_count.sum()) - np.repeat(offsets(face_count)[:-1], face_count))
    leaf = first_leaf + offsets(rings)[face_surface]
    sizes = lay.offsets[leaf + 1] - lay.offsets[leaf]
    entry = np.repeat(lay.offsets[leaf], sizes) + (
        np.arange(sizes.sum()) - np.repeat(offsets(sizes)[:-1], sizes))
    solid_of_entry = np.repeat(np.repeat(np.arange(len(checked)), face_count), sizes)
    count = max(len(copied.vertices), 1)
    uniq, inv = np.unique(solid_of_entry * count + rows[entry], return_inverse=True)
    ss = SolidSet(copied.vertices[uniq % count], inv.ravel().astype(np.int64),
                  offsets(sizes), offsets(face_count))
    labels = ["<{}> (lod {})".format(*labels_of[positions[k]]) for k in checked.tolist()]
    return CopiedSolids(ss, labels, len(shells) - len(checked))


def _chosen_lods(present, lods):
    """The LoDs to copy of one building tree whose copyable geometries have
    the LoDs ``present``, and whether it fell back to its highest."""
    if not present:
        return set(), False
    if lods == "all":
        return set(present), False
    if lods:
        wanted = {citygeometry.lod_value(x) for x in lods}
        chosen = {p for p in present if citygeometry.lod_value(p) in wanted}
        if chosen:
            return chosen, False
    top = max(citygeometry.lod_value(p) for p in present)
    return {p for p in present if citygeometry.lod_value(p) == top}, bool(lods)


#: the geometry types copied: all but GeometryInstances (templates are not copied) and unknown ones
COPYABLE = frozenset(citygeometry.DEPTH) - {"GeometryInstance"}


def _uses_extension(obj):
    if str(obj.get("type", "")).startswith("+"):
        return True
    if any(str(k).startswith("+") for k in obj) or any(
            str(k).startswith("+") for k in (obj.get("attributes") or {})):
        return True
    return any(str(s.get("type", "")).startswith("+") for g in obj.get("geometry", ())
               for s in (g.get("semantics") or {}).get("surfaces", ()))


def _to_grid(model, src, scale):
    """Model vertices ``src`` as integers of ``scale`` (absolute), and whether exactly.

    When the model's scale is a whole multiple of the output's, every
    vertex moves by the same rounding of the translation (at most half the
    output scale), so distinct vertices stay distinct; else each is rounded
    on its own and neighbours closer than the output scale may meet."""
    if len(src) and src[-1] - src[0] == len(src) - 1 and np.array_equal(
            src, np.arange(src[0], src[0] + len(src))):
        v = model.vertices[src[0]:src[0] + len(src)]        # a range: no gather
    else:
        v = model.vertices[src]
    ratio = model.scale / scale
    k = np.rint(ratio)
    if v.dtype.kind == "i" and np.all(np.abs(ratio - k) < 1e-9) and np.all(k >= 1):
        shift = np.rint(model.translate / scale).astype(np.int64)
        if np.all(k == 1):
            v = v + shift                   # the same grid: no multiplication
        else:
            v = v * k.astype(np.int64)
            v += shift
        return v, True
    return np.rint((v * model.scale + model.translate) / scale).astype(np.int64), False


@citygeometry.gc_paused()
def copy_buildings(model, buildings, lods=None, scale=SCALE, attributes=None,
                   keep_numbering=True):
    """The buildings ``buildings`` (indices into ``model.buildings``) ready to be merged.

    ``lods``: None for each building's highest LoD, "all", or a list of LoD
    strings ("1.2", "2.2"; a building with none of them is copied at its
    highest, counted in the report); ``attributes``: name -> one value per
    building, added to the copied top-level objects (None values and names
    the object already has are left alone). The model is not changed.
    Each building's vertices are numbered in the order its geometries first
    use them (see :func:`_rows`), except, with ``keep_numbering`` (for one
    merged CityJSON file; CityJSONSeq features number their own), where the
    copy is a whole single-file model, which keeps the model's numbering
    (:attr:`CopiedBuildings.model_numbered`).
    """
    buildings = [int(b) for b in buildings]
    report = CopyReport(buildings=len(buildings))
    trees, geometries, counts = [], [], []
    uses_extension = False
    kept_all = True                     # every geometry of the trees copied
    chosen_of = {}                      # LoDs present -> (LoDs copied, fell back)
    objects = model.objects
    for n, b in enumerate(buildings):
        oid = model.buildings[b]
        tree = [(o, objects[o]) for o in model.tree(oid)]
        present = frozenset(g.get("lod") for _, obj in tree for g in obj.get("geometry", ())
                            if g.get("type") in COPYABLE)
        if present not in chosen_of:
            chosen_of[present] = _chosen_lods(present, lods)
        chosen, fell = chosen_of[present]
        report.lod_fallback += fell
        objs = {}
        before = len(geometries)
        for o, obj in tree:
            if model.extensions and not uses_extension:
                uses_extension = _uses_extension(obj)
            copy = dict(obj)
            if "geometry" in obj:
                stored = obj["geometry"]
                kept = [g for g in stored if g.get("lod") in chosen and g.get("type") in COPYABLE]
                if len(kept) < len(stored):
                    kept_all = False
                    report.skipped_geometries += sum(g.get("type") not in COPYABLE for g in stored)
                if any("material" in g or "texture" in g for g in kept):
                    kept = [{k: v for k, v in g.items() if k not in ("material", "texture")}
                            for g in kept]
                copy["geometry"] = kept
                geometries.extend(kept)
            objs[o] = copy
        if attributes:
            _add_attributes(objs[oid], attributes, n)
        trees.append(objs)
        counts.append(len(geometries) - before)
        report.objects += len(objs)
    report.geometries = dict(collections.Counter(g["lod"] for g in geometries))
    copied = CopiedBuildings(ids=[model.buildings[b] for b in buildings], trees=trees,
                             vertices=None, vertex_start=None, scale=scale,
                             reference_system=model.reference_system,
                             extensions=model.extensions if uses_extension else None,
                             report=report, copied_geometries=geometries)
    offset = model.offset[buildings] if buildings else np.zeros(0, dtype=np.int64)
    whole = (keep_numbering and not offset.any() and kept_all
             and len(set(buildings)) == len(model.buildings)
             and sum(map(len, trees)) == len(model.objects))
    if whole and _number_as_model(copied, model):
        return copied
    _number_by_building(copied, counts, offset, len(model.vertices),
                        lambda source: _to_grid(model, source, scale))
    return copied


def _number_as_model(copied, model):
    """Number a whole model's copy as the model (see
    :attr:`CopiedBuildings.model_numbered`) where its geometries use every
    vertex of the model and the model's grid is a whole multiple of the
    output's; False (nothing changed) otherwise."""
    geometries = copied.geometries()
    if not geometries or len(model.vertices) == 0:
        return False
    used = citygeometry.used_vertices(geometries, len(model.vertices))
    if used is None or not used.all():
        return False                    # an orphan vertex: the rows are numbered anew
    vertices, exact = _to_grid(model, np.arange(len(model.vertices)), copied.scale)
    if not exact:
        return False
    copied.vertices, copied.model_numbered = vertices, True
    return True


def _number_by_building(copied, counts, shift, count, to_grid):
    """Number the vertex rows of ``copied`` building by building, in the
    order its geometries first use them (see :func:`_rows`). ``counts``: the
    geometries of each building; ``shift``: per building, added to its
    stored indices to index the source's ``count`` vertices; ``to_grid``:
    the source vertices (indices) -> their rows on the output grid and
    whether exactly (see :func:`_to_grid`)."""
    building_of = np.repeat(np.arange(len(copied)), counts)
    copied.layout = citygeometry.layout(copied.geometries(),
                                        shift[building_of] if shift.any() else None)
    lay = copied.layout
    source, row_owner, copied.rows = _rows(
        lay.flat, np.repeat(building_of[lay.leaf_geometry], np.diff(lay.offsets)), count)
    copied.vertices, exact = to_grid(source)
    copied.vertex_start = np.searchsorted(row_owner, np.arange(len(copied) + 1))
    copied.stored_local = exact and np.array_equal(source - shift[row_owner],
                                                   copied.local_index())
    if not exact and len(source) and len(
            unique_rows(np.column_stack([row_owner, copied.vertices]))[0]) < len(source):
        _collapse(copied, row_owner)


def by_building(copied):
    """``copied`` with its vertex rows numbered building by building (a copy
    numbered as its model is renumbered; any other is returned as it is)."""
    if not copied.model_numbered:
        return copied
    grid = copied.vertices
    out = dataclasses.replace(copied, vertices=None, layout=None, rows=None,
                              model_numbered=False)
    _number_by_building(out, out.geometry_counts(), np.zeros(len(out), dtype=np.int64),
                        len(grid), lambda source: (grid[source], True))
    return out


def _rows(source, owner, count):
    """The vertex rows of copied entries: one row per (building, model vertex)
    used, building after building.

    ``source``: the model vertex of every entry, ``owner``: its building,
    ``count``: the model's vertex count. Returns the model vertex and the
    building of every row and the row of every entry. Usually the entries
    come building after building and each vertex is used by one building
    only: the rows are then numbered in the order the entries first use them,
    without a sort (a building's boundaries then index its rows in the order
    they were written); else by model vertex within each building."""
    E = len(source)
    if E == 0:
        empty = np.zeros(0, dtype=np.int64)
        return empty, empty, empty
    entry = np.arange(E)
    first = np.full(count, E, dtype=np.int64)
    np.minimum.at(first, source, entry)
    at = first[source]                                  # the first entry using its vertex
    if np.all(owner[1:] >= owner[:-1]) and np.array_equal(owner[at], owner):
        new = at == entry
        rank = np.cumsum(new) - 1
        return source[new], owner[new], rank[at]
    keys, rows = np.unique(owner * count + source, return_inverse=True)
    return keys % count, keys // count, rows.ravel()


def _add_attributes(obj, attributes, n):
    attrs = dict(obj.get("attributes") or {})
    for name, values in attributes.items():
        value = values[n]
        if isinstance(value, np.generic):
            value = value.item()
        if value is not None and value == value and name not in attrs:
            attrs[name] = value
    obj["attributes"] = attrs


def _collapse(copied, owner):
    """Vertices of one building that met on the output grid made one, rings
    and surfaces that collapsed dropped, vertices left unused removed (only
    happens when the model's grid is finer than the output's). The
    geometries then index the rows directly."""
    uniq, inv = np.unique(np.column_stack([owner, copied.vertices]), axis=0,
                          return_inverse=True)                 # grouped by building
    merged = citygeometry.rebuild(copied.layout, copied.geometries(), inv.ravel()[copied.rows])
    cleaned = []
    for g in merged:
        g, dropped = citygeometry.drop_collapsed(g)
        cleaned.append(g)
        copied.report.collapsed_surfaces += dropped
    kept = [g for g in cleaned if g is not None]
    used = np.zeros(len(uniq), dtype=bool)
    if kept:
        used[citygeometry.indices(kept)] = True
    remap = np.cumsum(used) - 1
    final = iter(citygeometry.reindex(kept, lambda flat: remap[flat]) if kept else [])
    it = iter(cleaned)
    for tree in copied.trees:
        for obj in tree.values():
            if "geometry" in obj:
                obj["geometry"] = [next(final) for g in [next(it) for _ in obj["geometry"]]
                                   if g is not None]
    copied.vertices = uniq[used, 1:]
    copied.vertex_start[1:] = np.cumsum(np.bincount(uniq[used, 0], minlength=len(copied.ids)))
    copied.copied_geometries = None
    copied.layout = citygeometry.layout(copied.geometries())
    copied.rows = copied.layout.flat
    copied.stored_local = False


def _objects_pieces(copied, index):
    """The JSON text of the copied city objects (members of a CityObjects
    object, without the braces) with vertex indices ``index[row]``, the
    boundaries written in bulk, as a list of pieces."""
    fills = iter(copied.boundary_texts(index))
    structure = {}
    for n in range(len(copied)):
        structure.update(copied.filled(n, fills))

    def plain():
        merged = {}
        for objs in copied.objects(index):
            merged.update(objs)
        return merged

    return [memoryview(citygeometry.json_bytes(structure, plain))[1:-1]]
