"""Buildings copied from an existing city model into the generated one.

:func:`copy_buildings` takes the matched buildings of an
:class:`~reconstruction.existing.ExistingModel` with their attributes, their
children (``BuildingPart`` ...) and the geometries of the LoDs chosen, and
puts their vertices on the output's grid (integers of the output scale,
absolute: a coordinate is ``value * scale``): no coordinate moves by more
than half the output scale. :func:`merge` adds them to the CityJSON document
of the generated buildings (the dict of ``cityjson.citymodel`` or the text
of ``cityjson.citymodel_text``): one multi-LoD CityJSON 2.0 model in the
generated model's ``transform``, vertices shared and without duplicates.
The copied buildings keep their ids and LoDs; appearances (materials,
textures) and geometry templates are not copied.
"""

import collections
import dataclasses
import itertools
import json
import re
from dataclasses import dataclass, field

import numpy as np

from . import citygeometry
from .errors import InputError
from .rings import corners, unique_rows

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
    :class:`~reconstruction.citygeometry.Layout` of :meth:`geometries`) and
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
    reference_system: object
    extensions: dict
    report: CopyReport
    layout: object = None
    rows: np.ndarray = None
    copied_geometries: list = None
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
        order) as fragments (:func:`~reconstruction.citygeometry.fragment`),
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
        """The :class:`~reconstruction.citygeometry.Layout` of :meth:`geometries`
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


# ---------------------------------------------------------------------------
# Into the generated document
# ---------------------------------------------------------------------------

def output_reference_system(generated, copied):
    """The reference system of the merged model: the copied model's when it
    is the generated one's with heights (7415 for 28992), else the one they
    share; InputError when they locate points differently."""
    from .existing import epsg_code, same_place

    if copied is None or generated is None:
        return generated if copied is None else copied
    a, b = epsg_code(generated), epsg_code(copied)
    if a == b:
        return generated
    if a is not None and b is not None and same_place(a, b):
        from .existing import horizontal_epsg

        return generated if horizontal_epsg(b) == b else copied
    raise InputError("The reference system of the existing model ({}) does not agree with "
                     "the generated model's ({})".format(copied, generated))


def merged_metadata(metadata, lo, hi, copied, scale):
    """Metadata of the merged model: extent over generated (integer corners
    ``lo``/``hi`` of ``scale``, or None) and copied vertices, reference system."""
    metadata = dict(metadata or {})
    ext = copied.extent()
    boxes = [c for c in ((lo, hi), ext) if c is not None and c[0] is not None]
    if boxes:
        low = np.min([c[0] for c in boxes], axis=0)
        high = np.max([c[1] for c in boxes], axis=0)
        metadata["geographicalExtent"] = (np.concatenate([low, high]) * scale).round(6).tolist()
    rs = output_reference_system(metadata.get("referenceSystem"), copied.reference_system)
    if rs is not None:
        metadata["referenceSystem"] = rs
    return metadata


def _placement(generated, copied):
    """Output index of every copied vertex (the generated vertex it equals,
    or a new one after them) and the new rows, in the order they are first
    used (the copied rows' order: without duplicates the rows as they are)."""
    G, C = len(generated), len(copied.vertices)
    if C == 0:
        return np.zeros(0, dtype=np.int64), copied.vertices
    ends = [copied.extent() if hasattr(copied, "extent") else corners(copied.vertices)]
    if G:
        ends.insert(0, corners(generated))
    keys = _packed([generated, copied.vertices] if G else [copied.vertices], ends)
    if keys is not None:
        if _all_different(keys):
            return G + np.arange(C), copied.vertices            # no vertex met another
        uniq, inv = np.unique(keys, return_inverse=True)
    else:
        uniq, inv = unique_rows(np.concatenate([generated, copied.vertices]))
    target = np.full(len(uniq), -1, dtype=np.int64)
    if G:
        target[inv[:G]] = np.arange(G)
    mine = inv[G:]
    row = np.arange(C)
    first = np.full(len(uniq), C, dtype=np.int64)
    np.minimum.at(first, mine, row)
    at = first[mine]                                # the first copied row of its vertex
    known = target[mine]
    new = (at == row) & (known < 0)
    rank = np.cumsum(new) - 1
    return np.where(known >= 0, known, G + rank[at]), copied.vertices[new]


def _packed(parts, boxes):
    """One int64 per integer (x, y, z) row of the arrays ``parts``, equal for
    equal rows (None when the extent is too large to pack the three into 63
    bits); ``boxes``: the (lo, hi) corners of each part."""
    lo = np.min([c[0] for c in boxes], axis=0)
    span = np.max([c[1] for c in boxes], axis=0) - lo + 1
    if int(span[0]) * int(span[1]) * int(span[2]) >= 2 ** 62:
        return None
    keys = []
    for p in parts:
        k = p[:, 0] - lo[0]
        k *= span[1]
        k += p[:, 1] - lo[1]
        k *= span[2]
        k += p[:, 2] - lo[2]
        keys.append(k)
    return np.concatenate(keys) if len(keys) > 1 else keys[0]


def _keys(body):
    """The object ids (JSON-escaped) in the text of a CityObjects member: every
    object starts ``"id":{"type":"`` (the result may hold a few more strings
    than the ids, never fewer)."""
    keys = set()
    for piece in body.split('":{"type":"')[:-1]:
        k = piece.rfind('"')
        while k > 0 and (len(piece[:k]) - len(piece[:k].rstrip("\\"))) % 2:
            k = piece.rfind('"', 0, k)                  # an escaped quote inside the id
        keys.add(piece[k + 1:])
    return keys


def _plain(text):
    """Whether ``json.dumps`` writes the string as it is (between its quotes)."""
    return text.isascii() and text.isprintable() and '"' not in text and "\\" not in text


def _check_ids(copied, generated_keys):
    clash = [i for objs in copied.trees for i in objs
             if (i if _plain(i) else json.dumps(i)[1:-1]) in generated_keys]
    if clash:
        raise InputError("{} copied objects have the id of a generated building (e.g. <{}>): "
                         "rename the generated buildings".format(len(clash), clash[0]))


@citygeometry.gc_paused()
def merge(generated, copied):
    """The generated CityJSON document with the ``copied`` buildings added.

    ``generated``: a CityJSON dict, or its text as ``cityjson.citymodel_text``
    writes it (the result is then text too, built without parsing the
    generated city objects). The output keeps the generated ``transform``
    (its scale must be the copied buildings' scale); the metadata's extent
    and reference system cover both.
    """
    if copied is None or len(copied) == 0:
        return generated
    if isinstance(generated, str):
        from .cityjson import joined_text

        return joined_text(merged_pieces(generated, copied))
    doc = dict(generated)
    scale, translate = _transform(doc, copied)
    gen = np.asarray(doc.get("vertices") or np.zeros((0, 3)), dtype=np.int64).reshape(-1, 3)
    _check_ids(copied, {json.dumps(k)[1:-1] for k in doc.get("CityObjects", {})})
    stored = _stored_first(doc, gen, translate, copied, scale)
    if stored is not None:                      # a copy numbered as its model
        head, translate = stored
        rows = copied.vertices - translate
        objects = _shifted_objects(doc.get("CityObjects", {}), len(rows))
        for tree in copied.trees:
            objects.update(tree)
        head["CityObjects"] = objects
        head["vertices"] = rows.tolist() + list(doc.get("vertices") or [])
        return head
    head, to_out, rows = _head_and_rows(doc, gen, translate, copied, scale)
    objects = dict(doc.get("CityObjects", {}))
    for objs in copied.objects(to_out):
        objects.update(objs)
    head["CityObjects"] = objects
    head["vertices"] = list(doc.get("vertices") or []) + rows.tolist()
    return head


def _shifted_objects(objects, shift):
    """Copies of city objects (by id) whose geometries' vertex indices are ``shift`` more."""
    geoms = [g for obj in objects.values() for g in obj.get("geometry", ())]
    new = iter(citygeometry.reindex(geoms, lambda flat: flat + shift))
    out = {}
    for oid, obj in objects.items():
        out[oid] = obj
        if obj.get("geometry"):
            out[oid] = dict(obj, geometry=[next(new) for _ in obj["geometry"]])
    return out


def _transform(doc, copied):
    t = doc.get("transform") or {}
    scale = t.get("scale", [copied.scale] * 3)
    if not np.allclose(scale, copied.scale, rtol=0, atol=1e-12):
        raise ValueError("the copied buildings are on a grid of {}, the model's is {}".format(
            copied.scale, scale))
    return copied.scale, np.rint(np.asarray(t.get("translate", [0, 0, 0])) / copied.scale)


def _head_and_rows(doc, gen, translate, copied, scale):
    """The merged document without its objects and vertices, the output
    index of every copied vertex and the new vertex rows (relative to the
    output translate)."""
    head, translate, absolute = _head(doc, gen, translate, copied, scale)
    to_out, rows = _placement(absolute, copied)
    return head, to_out, rows - translate


def _head(doc, gen, translate, copied, scale):
    """The merged document without its objects and vertices, its integer
    translate, and the generated vertices ``gen`` (relative to the
    document's ``translate``) as absolute integers."""
    head = {k: v for k, v in doc.items() if k not in ("CityObjects", "vertices")}
    translate = translate.astype(np.int64)
    if len(gen) == 0:
        translate = copied.extent()[0]
    absolute = gen + translate
    lo, hi = corners(absolute) if len(gen) else (None, None)
    head["transform"] = {"scale": [scale] * 3, "translate": (translate * scale).round(6).tolist()}
    head["metadata"] = merged_metadata(doc.get("metadata"), lo, hi, copied, scale)
    if copied.extensions:
        head["extensions"] = dict(doc.get("extensions") or {}, **copied.extensions)
    return head, translate, absolute


@citygeometry.gc_paused()
def merged_pieces(text, copied):
    """:func:`merge` of the generated model's ``text`` as the pieces (texts
    or UTF-8 bytes) that make the merged model's, in order: written one
    after the other (``cityjson.write_text`` takes them), the 50 MB of a
    large model are neither joined into one text nor encoded at once. A
    list, or where the copy keeps its model's numbering an iterator that
    makes the copied objects' and vertices' pieces as they are written (one
    pass: :func:`_as_stored_pieces`); every check is made before it is
    returned."""
    if copied is None or len(copied) == 0:
        return [text]
    head_end = text.find(',"CityObjects":{')
    vstart = text.rfind(',"vertices":')
    if head_end < 0 or vstart < head_end or not text.endswith("}") or text[vstart - 1] != "}":
        return [json.dumps(merge(json.loads(text), copied), separators=(",", ":"))]
    doc = json.loads(text[:head_end] + "}")
    body = text[head_end + len(',"CityObjects":{'):vstart - 1]
    inner = text[vstart + len(',"vertices":'):-1]
    scale, translate = _transform(doc, copied)
    flat = np.fromstring(inner.replace("[", " ").replace("]", " "), dtype=np.int64, sep=",") \
        if inner.strip() != "[]" else np.zeros(0, dtype=np.int64)
    gen = flat.reshape(-1, 3)
    _check_ids(copied, _keys(body))
    if copied.model_numbered:
        pieces = _as_stored_pieces(doc, body, inner, gen, translate, copied, scale)
        if pieces is not None:
            return pieces
    head, to_out, rows = _head_and_rows(doc, gen, translate, copied, scale)
    objects = _objects_pieces(copied, to_out)
    if len(rows):
        vertices = ([inner[:-1], ","] if len(gen) else ["["]) + list(_rows_text(rows)) + ["]"]
    else:
        vertices = [inner]
    head_text = json.dumps(head, separators=(",", ":"))
    return ([head_text[:-1], ',"CityObjects":{', body, "," if body and objects else ""]
            + objects + ['},"vertices":'] + vertices + ["}"])


def _stored_first(doc, gen, translate, copied, scale):
    """The head of the merged document (:func:`_head`) and its integer
    translate where the copy is numbered as its model
    (:attr:`CopiedBuildings.model_numbered`) and no copied vertex equals
    another one: the copied vertices then come first, in the model's order,
    so that the copied objects keep their boundaries as they were read, and
    the generated buildings' indices (of ``gen``, the generated vertices)
    move behind them. None otherwise (the caller then places the vertices
    one by one, :func:`_placement`)."""
    if not copied.model_numbered:
        return None
    head, translate, absolute = _head(doc, gen, translate, copied, scale)
    ends = [copied.extent()] + ([corners(absolute)] if len(gen) else [])
    if not _distinct([copied.vertices, absolute], ends):
        return None
    return head, translate


def _as_stored_pieces(doc, body, inner, gen, translate, copied, scale):
    """:func:`merged_pieces` of a copy numbered as its model, its vertices
    first (:func:`_stored_first`): the copied objects written as they were
    read, boundaries included, by orjson, chunk after chunk as the file is
    written (:func:`_stored_objects`, :func:`_rows_text`). ``body``,
    ``inner``: the texts of the generated objects and vertices ``gen``.
    None where :func:`_stored_first` is, or where the generated boundaries
    are not plain lists of indices."""
    stored = _stored_first(doc, gen, translate, copied, scale)
    if stored is None:
        return None
    head, translate = stored
    body = _shifted_boundaries(body, len(copied.vertices)) if len(gen) else body
    if body is None:
        return None
    head_text = json.dumps(head, separators=(",", ":"))
    return itertools.chain(
        [head_text[:-1], ',"CityObjects":{', body, "," if body else ""], _stored_objects(copied),
        ['},"vertices":['], _rows_text(copied.vertices, translate),
        ["," + inner[1:] if len(gen) else "]", "}"])


#: buildings, or vertex rows, written at a time: each chunk's memory is used again by
#: the next instead of one text of the whole being made in new memory, page after page
_CHUNK = 2000
_ROWS = 65536


def _stored_objects(copied):
    """The JSON text of the copied city objects (members of a CityObjects
    object) as they are stored, UTF-8 bytes, :data:`_CHUNK` buildings a piece."""
    for a in range(0, len(copied), _CHUNK):
        structure = {}
        for tree in copied.trees[a:a + _CHUNK]:
            structure.update(tree)
        if a:
            yield ","
        yield memoryview(citygeometry.json_bytes(structure))[1:-1]


def _rows_text(rows, translate=0):
    """The JSON text ``[x,y,z],[x,y,z],...`` (no list's brackets) of the
    integer rows ``rows - translate`` (none empty), written by orjson
    :data:`_ROWS` rows a piece (it writes an array of 635,000 rows twice as
    slowly as many small ones)."""
    import orjson

    for a in range(0, len(rows), _ROWS):
        text = orjson.dumps(rows[a:a + _ROWS] - translate, option=orjson.OPT_SERIALIZE_NUMPY)
        yield memoryview(text)[1:-1] if a == 0 else b"," + text[1:-1]


def _distinct(parts, boxes):
    """Whether the integer (x, y, z) rows of the arrays ``parts`` (their
    (lo, hi) corners ``boxes``) are all different."""
    parts = [p for p in parts if len(p)]
    keys = _packed(parts, boxes)
    if keys is None:
        rows = np.concatenate(parts)
        return len(unique_rows(rows)[0]) == len(rows)
    return _all_different(keys)


def _all_different(keys):
    """Whether no two of the integers ``keys`` are equal."""
    ordered = np.sort(keys)
    return not np.any(ordered[1:] == ordered[:-1])


#: the boundaries of a geometry in a CityObjects text: a plain list of integers
_BOUNDARIES = re.compile(r'"boundaries":(\[[0-9,\[\]]*\])')


def _shifted_boundaries(body, shift):
    """``body`` (the JSON text of city objects, as ``cityjson.citymodel_text``
    writes them) with ``shift`` added to every vertex index of its
    geometries' boundaries; None where a boundaries list is not a plain list
    of indices."""
    from .cityjson import shifted_lists

    parts = _BOUNDARIES.split(body)
    outside, lists = parts[0::2], parts[1::2]
    if len(lists) != body.count('"boundaries":'):
        return None
    new = shifted_lists(lists, shift)
    if new is None:
        return None
    out = [None] * (len(outside) + len(new))
    out[0::2] = outside
    out[1::2] = ['"boundaries":' + t for t in new]
    return "".join(out)
