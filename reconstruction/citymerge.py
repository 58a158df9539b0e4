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
import json
import re
from dataclasses import dataclass, field

import numpy as np

from . import citygeometry
from .errors import InputError
from .rings import unique_rows

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
    them (use :meth:`objects` or :func:`objects_text` for indices into
    ``vertices``); ``vertices``: (N, 3) int64 absolute coordinates in units
    of ``scale``, building after building from ``vertex_start``;
    ``reference_system`` and ``extensions``: of the model they come from
    (extensions only when a copied object uses one). ``layout`` (a
    :class:`~reconstruction.citygeometry.Layout` of :meth:`geometries`) and
    ``rows`` (the vertex row of each of its entries) let the buildings be
    written with any numbering of the rows without walking their lists again;
    ``copied_geometries``: the list :meth:`geometries` returns, kept;
    ``source``: the model's vertex of every row (None once vertices met on
    the output grid); ``stored_global``: the geometries' boundaries, as the
    model stores them, index the model's one vertex list (a CityJSON file,
    not CityJSONSeq): where the rows are numbered by their ``source``, the
    boundaries are written as they are (:meth:`model_order`);
    ``stored_local``: the boundaries as stored index each building's own
    rows (:meth:`local_index`: CityJSONSeq features whose vertices are all
    copied, in their order): its feature is written as it was read.
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
    source: np.ndarray = None
    stored_global: bool = False
    stored_local: bool = False

    def __len__(self):
        return len(self.ids)

    def extent(self):
        """(lo, hi) integer corners of the copied vertices (None when there are none)."""
        if len(self.vertices) == 0:
            return None
        cached = getattr(self, "_extent", None)
        if cached is None or cached[0] is not self.vertices:
            cached = (self.vertices, self.vertices.min(axis=0), self.vertices.max(axis=0))
            self._extent = cached
        return cached[1], cached[2]

    def model_order(self):
        """The rows in the model's order, where they are the model's vertices
        0 to N - 1 each once (a whole model copied): numbered so, the copied
        boundaries index them as stored. None otherwise."""
        if not self.stored_global or self.source is None or len(self.source) == 0:
            return None
        n = len(self.source)
        if int(self.source.max()) != n - 1:
            return None
        order = np.full(n, -1, dtype=np.int64)
        order[self.source] = np.arange(n)
        return order if order.min() >= 0 else None

    def geometries(self):
        """Every copied geometry (building after building, object after object)."""
        if self.copied_geometries is not None:
            return self.copied_geometries
        return [g for tree in self.trees for obj in tree.values() for g in obj.get("geometry", ())]

    def geometry_counts(self):
        """The number of copied geometries of every building."""
        return [sum(len(o.get("geometry", ())) for o in tree.values()) for tree in self.trees]

    def holed(self, n):
        """The city objects of building ``n`` with :data:`~reconstruction.citygeometry.HOLE`
        for every geometry's boundaries (see :func:`citygeometry.splice`)."""
        objs = {}
        hole = citygeometry.HOLE
        for oid, obj in self.trees[n].items():
            if obj.get("geometry"):
                objs[oid] = dict(obj)
                objs[oid]["geometry"] = [dict(g, boundaries=hole) for g in obj["geometry"]]
            else:
                objs[oid] = obj                 # nothing to put in: the copy as it is
        return objs

    def local_index(self):
        """Per vertex row its index among its building's own rows."""
        owner = np.repeat(np.arange(len(self.ids)), np.diff(self.vertex_start))
        return np.arange(len(self.vertices)) - self.vertex_start[owner]

    def boundary_texts(self, index=None):
        """The JSON text of the boundaries of every copied geometry with vertex
        indices ``index[row]`` (None: :meth:`local_index`)."""
        index = self.local_index() if index is None else index
        return citygeometry.texts(self.layout, index[self.rows])

    def objects(self, index=None):
        """Per building, its city objects with vertex indices ``index[row]``
        (None: :meth:`local_index`, each building's own from 0)."""
        index = self.local_index() if index is None else index
        new = iter(citygeometry.rebuild(self.layout, self.geometries(), index[self.rows]))
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


def _copyable(geometry):
    """Geometries copied: all but GeometryInstances (templates are not copied) and unknown types."""
    kind = geometry.get("type")
    return kind in citygeometry.DEPTH and kind != "GeometryInstance"


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
def copy_buildings(model, buildings, lods=None, scale=SCALE, attributes=None):
    """The buildings ``buildings`` (indices into ``model.buildings``) ready to be merged.

    ``lods``: None for each building's highest LoD, "all", or a list of LoD
    strings ("1.2", "2.2"; a building with none of them is copied at its
    highest, counted in the report); ``attributes``: name -> one value per
    building, added to the copied top-level objects (None values and names
    the object already has are left alone). The model is not changed.
    Each building's vertices are numbered in the order its geometries first
    use them (see :func:`_rows`).
    """
    buildings = [int(b) for b in buildings]
    report = CopyReport(buildings=len(buildings))
    trees, geometries, counts = [], [], []
    uses_extension = False
    chosen_of = {}                      # LoDs present -> (LoDs copied, fell back)
    for n, b in enumerate(buildings):
        oid = model.buildings[b]
        tree = [(o, model.objects[o]) for o in model.tree(oid)]
        present = frozenset(g.get("lod") for _, obj in tree for g in obj.get("geometry", ())
                            if _copyable(g))
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
                kept = [g for g in obj["geometry"] if g.get("lod") in chosen and _copyable(g)]
                report.skipped_geometries += sum(not _copyable(g) for g in obj["geometry"]) \
                    if len(kept) < len(obj["geometry"]) else 0
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
    building_of = np.repeat(np.arange(len(buildings)), counts)
    offset = model.offset[buildings] if buildings else np.zeros(0, dtype=np.int64)
    copied.layout = citygeometry.layout(geometries, offset[building_of] if offset.any() else None)
    lay = copied.layout
    source, row_owner, copied.rows = _rows(
        lay.flat, np.repeat(building_of[lay.leaf_geometry], np.diff(lay.offsets)),
        len(model.vertices))
    copied.vertices, exact = _to_grid(model, source, scale)
    copied.vertex_start = np.searchsorted(row_owner, np.arange(len(buildings) + 1))
    copied.source, copied.stored_global = source, not offset.any()
    copied.stored_local = exact and np.array_equal(source - offset[row_owner],
                                                   copied.local_index())
    if not exact and len(source) and len(
            unique_rows(np.column_stack([row_owner, copied.vertices]))[0]) < len(source):
        _collapse(copied, row_owner)
    return copied


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
    copied.source = None
    copied.stored_local = False


def objects_text(copied, index):
    """The JSON text of the copied city objects (members of a CityObjects
    object, without the braces) with vertex indices ``index[row]``, the
    boundaries written in bulk."""
    return "".join(p if isinstance(p, str) else str(p, "utf-8")
                   for p in _objects_pieces(copied, index))


def _objects_pieces(copied, index):
    """:func:`objects_text` in pieces (joined once by the caller, not copied
    on the way): texts, or UTF-8 bytes.

    Where the index of every row is its vertex's index in the model and the
    model's boundaries index its one vertex list (a whole CityJSON file
    copied, :meth:`CopiedBuildings.model_order`), the objects are written as
    they are, boundaries included, in one call."""
    if copied.stored_global and copied.source is not None and np.array_equal(index,
                                                                             copied.source):
        structure = {}
        for tree in copied.trees:
            structure.update(tree)
        return [memoryview(citygeometry.json_bytes(structure))[1:-1]]
    structure = {}
    for n in range(len(copied)):
        structure.update(copied.holed(n))
    fills = copied.boundary_texts(index)
    pieces = citygeometry.pieces_around_holes(structure, len(fills))
    if pieces is None:                  # an attribute that is the placeholder itself
        merged = {}
        for objs in copied.objects(index):
            merged.update(objs)
        return [json.dumps(merged, separators=(",", ":"))[1:-1]]
    out = [None] * (2 * len(pieces) - 1)
    out[0::2] = pieces
    out[1::2] = fills
    out[0], out[-1] = out[0][1:], out[-1][:-1]          # without the braces
    return out


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
    corners = [c for c in ((lo, hi), ext) if c is not None and c[0] is not None]
    if corners:
        low = np.min([c[0] for c in corners], axis=0)
        high = np.max([c[1] for c in corners], axis=0)
        metadata["geographicalExtent"] = (np.concatenate([low, high]) * scale).round(6).tolist()
    rs = output_reference_system(metadata.get("referenceSystem"), copied.reference_system)
    if rs is not None:
        metadata["referenceSystem"] = rs
    return metadata


def _placement(generated, copied):
    """Where the copied and the generated vertices go in the merged model's
    vertex list: each distinct vertex once, where first met.

    Where the copied rows are a whole model's vertices
    (:meth:`CopiedBuildings.model_order`) they come first, in the model's
    order: without duplicates each keeps its model index and the copied
    boundaries are written as they were read; the generated vertices
    follow. Otherwise the generated vertices come first, as they are, and
    the copied rows after them, in row order. Returns the output index of
    every copied row and of every generated vertex, and the output's rows."""
    G, C = len(generated), len(copied.vertices)
    order = copied.model_order() if hasattr(copied, "model_order") else None
    mine = copied.vertices if order is None else np.take(copied.vertices, order, axis=0)
    corners = {}
    if C:
        corners["copied"] = copied.extent() if hasattr(copied, "extent") else (
            mine.min(axis=0), mine.max(axis=0))
    if G:
        corners["generated"] = (generated.min(axis=0), generated.max(axis=0))
    parts = [("copied", mine), ("generated", generated)]
    if order is None:
        parts.reverse()
    parts = [(name, p) for name, p in parts if len(p)]
    if not parts:
        empty = np.zeros(0, dtype=np.int64)
        return empty, empty, np.zeros((0, 3), dtype=np.int64)
    rows = np.concatenate([p for _, p in parts]) if len(parts) > 1 else parts[0][1]
    start = {"copied": 0, "generated": 0}
    if order is None and G:
        start["copied"] = G
    elif C:
        start["generated"] = C
    keys = _packed([p for _, p in parts], [corners[name] for name, _ in parts])
    if keys is not None:
        ordered = np.sort(keys)
        if not np.any(ordered[1:] == ordered[:-1]):             # no vertex met another
            mine_out = start["copied"] + (np.arange(C) if order is None else copied.source)
            return mine_out, start["generated"] + np.arange(G), rows
        uniq, inv = np.unique(keys, return_inverse=True)
    else:
        uniq, inv = unique_rows(rows)
    N = len(rows)
    entry = np.arange(N)
    first = np.full(len(uniq), N, dtype=np.int64)
    np.minimum.at(first, inv, entry)
    at = first[inv]                                 # the first row of its vertex
    new = at == entry
    out = (np.cumsum(new) - 1)[at]
    a, g = start["copied"], start["generated"]
    mine_out = out[a:a + C] if order is None else out[a:a + C][copied.source]
    return mine_out, out[g:g + G], rows[new]


def _packed(parts, corners):
    """One int64 per integer (x, y, z) row of the arrays ``parts``, equal for
    equal rows (None when the extent is too large to pack the three into 63
    bits); ``corners``: (lo, hi) of each part."""
    lo = np.min([c[0] for c in corners], axis=0)
    span = np.max([c[1] for c in corners], axis=0) - lo + 1
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
    writes it (the result is then the merged text as UTF-8 bytes, ready to
    be written, built without parsing the generated city objects). The output keeps the generated ``transform``
    (its scale must be the copied buildings' scale); the metadata's extent
    and reference system cover both. Its vertex list starts with the copied
    vertices (:func:`_placement`): a whole model copied keeps its numbering
    and its boundaries are written as they were read; the generated
    buildings' indices move behind them.
    """
    if copied is None or len(copied) == 0:
        return generated
    if isinstance(generated, str):
        return _merge_text(generated, copied)
    doc = dict(generated)
    scale, translate = _transform(doc, copied)
    gen = np.asarray(doc.get("vertices") or np.zeros((0, 3)), dtype=np.int64).reshape(-1, 3)
    _check_ids(copied, {json.dumps(k)[1:-1] for k in doc.get("CityObjects", {})})
    head, to_out, gen_out, rows = _head_and_rows(doc, gen, translate, copied, scale)
    objects = _renumbered_objects(doc.get("CityObjects", {}), gen_out)
    for objs in copied.objects(to_out):
        objects.update(objs)
    head["CityObjects"] = objects
    head["vertices"] = rows.tolist()
    return head


def _renumbered_objects(objects, mapping):
    """Copies of the city objects (a dict) whose vertex indices ``i`` are ``mapping[i]``."""
    objects = dict(objects)
    where, geoms = [], []
    for oid, obj in objects.items():
        for k, g in enumerate(obj.get("geometry", ())):
            where.append((oid, k))
            geoms.append(g)
        if "geometry" in obj:
            objects[oid] = dict(obj, geometry=list(obj["geometry"]))
    if geoms:
        for (oid, k), g in zip(where, citygeometry.reindex(geoms, lambda flat: mapping[flat])):
            objects[oid]["geometry"][k] = g
    return objects


def _transform(doc, copied):
    t = doc.get("transform") or {}
    scale = t.get("scale", [copied.scale] * 3)
    if not np.allclose(scale, copied.scale, rtol=0, atol=1e-12):
        raise ValueError("the copied buildings are on a grid of {}, the model's is {}".format(
            copied.scale, scale))
    return copied.scale, np.rint(np.asarray(t.get("translate", [0, 0, 0])) / copied.scale)


def _head_and_rows(doc, gen, translate, copied, scale):
    """The merged document without its objects and vertices, the output
    index of every copied row and of every generated vertex, and the
    output's vertex rows (relative to the output translate; :func:`_placement`)."""
    head = {k: v for k, v in doc.items() if k not in ("CityObjects", "vertices")}
    translate = translate.astype(np.int64)
    if len(gen) == 0:
        translate = copied.extent()[0] if len(copied.vertices) else np.zeros(3, dtype=np.int64)
    absolute = gen + translate
    to_out, gen_out, rows = _placement(absolute, copied)
    lo = absolute.min(axis=0) if len(gen) else None
    hi = absolute.max(axis=0) if len(gen) else None
    head["transform"] = {"scale": [scale] * 3, "translate": (translate * scale).round(6).tolist()}
    head["metadata"] = merged_metadata(doc.get("metadata"), lo, hi, copied, scale)
    if copied.extensions:
        head["extensions"] = dict(doc.get("extensions") or {}, **copied.extensions)
    return head, to_out, gen_out, rows - translate


def _merge_text(text, copied):
    from .cityjsonseq import vertices_texts

    head_end = text.find(',"CityObjects":{')
    vstart = text.rfind(',"vertices":')
    if head_end < 0 or vstart < head_end or not text.endswith("}") or text[vstart - 1] != "}":
        return _merged_as_dict(text, copied)
    doc = json.loads(text[:head_end] + "}")
    body = text[head_end + len(',"CityObjects":{'):vstart - 1]
    inner = text[vstart + len(',"vertices":'):-1]
    scale, translate = _transform(doc, copied)
    flat = np.fromstring(inner.replace("[", " ").replace("]", " "), dtype=np.int64, sep=",") \
        if inner.strip() != "[]" else np.zeros(0, dtype=np.int64)
    gen = flat.reshape(-1, 3)
    _check_ids(copied, _keys(body))
    head, to_out, gen_out, rows = _head_and_rows(doc, gen, translate, copied, scale)
    G, N = len(gen), len(rows)
    if G and not np.array_equal(gen_out, np.arange(G)):
        body = _renumbered_text(body, gen_out)
        if body is None:
            return _merged_as_dict(text, copied)
    objects = _objects_pieces(copied, to_out)
    # the generated vertices' text as it is where they stand together, in order
    if G == 0 or N == G:
        vertices = [inner if G else vertices_texts(rows, np.array([0, N]))[0]]
    elif np.array_equal(gen_out, np.arange(G)):
        vertices = [inner[:-1], ",", vertices_texts(rows[G:], np.array([0, N - G]))[0][1:]]
    elif np.array_equal(gen_out, N - G + np.arange(G)):
        vertices = [vertices_texts(rows[:N - G], np.array([0, N - G]))[0][:-1], ",", inner[1:]]
    else:
        vertices = [vertices_texts(rows, np.array([0, N]))[0]]
    head_text = json.dumps(head, separators=(",", ":"))
    return _utf8([head_text[:-1], ',"CityObjects":{', body, "," if body and objects else ""]
                 + objects + ['},"vertices":'] + vertices + ["}"])


def _utf8(parts):
    """The UTF-8 bytes of pieces of text (str, or bytes-like already UTF-8)
    joined: each run of str joined and encoded once, the bytes not copied
    before the final join (a 50 MB model is copied twice, not five times)."""
    out, run = [], []
    for part in parts:
        if isinstance(part, str):
            run.append(part)
            continue
        if run:
            out.append("".join(run).encode("utf-8"))
            run = []
        out.append(part)
    if run:
        out.append("".join(run).encode("utf-8"))
    return out[0] if len(out) == 1 and isinstance(out[0], bytes) else b"".join(out)


def _merged_as_dict(text, copied):
    """:func:`merge` of a generated text that :func:`_merge_text` cannot take apart."""
    return json.dumps(merge(json.loads(text), copied), separators=(",", ":")).encode("utf-8")


#: the boundaries of a geometry in JSON text, a plain list (of lists ...) of
#: indices up to the next member or the end of the geometry
_BOUNDARIES = re.compile(r'(?<="boundaries":)(\[[0-9,\[\]]*\])(?=,"|\})')


def _renumbered_text(body, mapping):
    """``body`` (JSON text of city objects) with the vertex index ``i`` of
    every geometry's boundaries written ``mapping[i]``; None where they are
    not plain lists of indices (the caller then parses the text)."""
    parts = _BOUNDARIES.split(body)
    outside, lists = parts[0::2], parts[1::2]
    if len(lists) != body.count('"boundaries":'):
        return None
    new = _renumbered_lists(lists, mapping)
    if new is None:
        return None
    out = [None] * (len(outside) + len(new))
    out[0::2] = outside
    out[1::2] = new
    return "".join(out)


def _renumbered_lists(lists, mapping):
    """The JSON texts ``lists`` (nested lists of indices) with every index
    ``i`` written ``mapping[i]``, in bulk: the texts are joined, their
    numbers read and written again by the integer writer of ``cityjson``,
    each after the brackets and the comma that stood before it. None unless
    every text is a plain list (digits, brackets, commas, no empty list)
    whose indices are in ``mapping``."""
    from .cityjson import _int_text

    if not lists:
        return []
    blob = ",".join(lists)
    raw = blob.encode("ascii", "replace")
    chars = np.frombuffer(raw, dtype=np.uint8)
    digit = (chars - np.uint8(48)) < np.uint8(10)
    edges = np.flatnonzero(digit[1:] != digit[:-1]) + 1
    starts, ends = edges[0::2], edges[1::2]
    n = len(starts)
    commas = np.flatnonzero(chars == 44)
    if n == 0 or len(ends) != n or len(commas) != n - 1 or raw.translate(None, b"0123456789[],"):
        return None
    # one comma between two numbers: ``]`` * close, the comma, ``[`` * open
    close, open_ = commas - ends[:-1], starts[1:] - commas - 1
    if np.any(close < 0) or np.any(open_ < 0):
        return None
    values = np.fromstring(blob.replace("[", " ").replace("]", " "), dtype=np.int64, sep=",")
    if len(values) != n or values.max() >= len(mapping):
        return None
    most = int(max(close.max(initial=0), open_.max(initial=0))) + 1
    table = ["]" * i + "," + "[" * j for i in range(most) for j in range(most)] + [blob[:starts[0]]]
    code = np.empty(n, dtype=np.int64)
    code[0] = len(table) - 1
    code[1:] = close * most + open_
    out, at = _int_text(mapping[values], code, table)
    # list k + 1 starts after the comma that joined it to list k
    joins = np.cumsum([len(t) + 1 for t in lists[:-1]]) - 1
    after = np.searchsorted(starts, joins)                  # its first number
    cut = at[after] + close[after - 1]
    bounds = [0] + np.column_stack([cut, cut + 1]).ravel().tolist() + [len(out)]
    suffix = blob[ends[-1]:]
    pieces = [out[a:b] for a, b in zip(bounds[0::2], bounds[1::2])]
    pieces[-1] += suffix
    return pieces
