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

import json
import re
from dataclasses import dataclass, field

import numpy as np

from . import citygeometry
from .errors import InputError
from .solids import unique_rows

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

    ``ids``: the top-level object ids; ``objects``: per building, its city
    objects by id (itself first), boundaries indexing the building's own
    vertices ``vertices[vertex_start[b]:vertex_start[b + 1]]``; ``vertices``:
    (N, 3) int64 absolute coordinates in units of ``scale``;
    ``reference_system`` and ``extensions``: of the model they come from
    (extensions only when a copied object uses one).
    """
    ids: list
    objects: list
    vertices: np.ndarray
    vertex_start: np.ndarray
    scale: float
    reference_system: object
    extensions: dict
    report: CopyReport

    def __len__(self):
        return len(self.ids)

    def extent(self):
        """(lo, hi) integer corners of the copied vertices (None when there are none)."""
        if len(self.vertices) == 0:
            return None
        return self.vertices.min(axis=0), self.vertices.max(axis=0)


def _chosen_lods(geometries, lods):
    """The LoDs to copy of one building tree, and whether it fell back to its highest."""
    present = {g.get("lod") for g in geometries if _copyable(g)}
    if not present:
        return set(), False
    if lods == "all":
        return present, False
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
    """Model vertices ``src`` as integers of ``scale`` (absolute).

    When the model's scale is a whole multiple of the output's, every
    vertex moves by the same rounding of the translation (at most half the
    output scale), so distinct vertices stay distinct."""
    v = model.vertices[src]
    ratio = model.scale / scale
    k = np.rint(ratio)
    if v.dtype.kind == "i" and np.all(np.abs(ratio - k) < 1e-9) and np.all(k >= 1):
        return v * k.astype(np.int64) + np.rint(model.translate / scale).astype(np.int64)
    return np.rint((v * model.scale + model.translate) / scale).astype(np.int64)


def copy_buildings(model, buildings, lods=None, scale=SCALE, attributes=None):
    """The buildings ``buildings`` (indices into ``model.buildings``) ready to be merged.

    ``lods``: None for each building's highest LoD, "all", or a list of LoD
    strings ("1.2", "2.2"; a building with none of them is copied at its
    highest, counted in the report); ``attributes``: name -> one value per
    building, added to the copied top-level objects (None values and names
    the object already has are left alone).
    """
    buildings = [int(b) for b in buildings]
    report = CopyReport(buildings=len(buildings))
    big = max(len(model.vertices), 1)
    trees, geoms, shift, where = [], [], [], []
    uses_extension = False
    for n, b in enumerate(buildings):
        oid = model.buildings[b]
        tree = {o: model.objects[o] for o in model.tree(oid)}
        all_geoms = [g for obj in tree.values() for g in obj.get("geometry", ())]
        chosen, fell = _chosen_lods(all_geoms, lods)
        report.lod_fallback += fell
        objs = {}
        for o, obj in tree.items():
            uses_extension = uses_extension or _uses_extension(obj)
            copy = dict(obj)
            kept = []
            for g in obj.get("geometry", ()):
                if not _copyable(g):
                    report.skipped_geometries += 1
                    continue
                if g.get("lod") not in chosen:
                    continue
                g = {k: v for k, v in g.items() if k not in ("material", "texture")}
                where.append((n, o, len(kept)))
                kept.append(g)
                geoms.append(g)
                shift.append(int(model.offset[b]) + n * big)
                report.geometries[g.get("lod")] = report.geometries.get(g.get("lod"), 0) + 1
            if "geometry" in obj:
                copy["geometry"] = kept
            objs[o] = copy
        if attributes:
            top = objs[oid]
            attrs = dict(top.get("attributes") or {})
            for name, values in attributes.items():
                value = values[n]
                if isinstance(value, np.generic):
                    value = value.item()
                if value is not None and value == value and name not in attrs:
                    attrs[name] = value
            top["attributes"] = attrs
        trees.append(objs)
        report.objects += len(objs)
    state = {}

    def local(flat):
        # global source index with the building number on top -> per building local index
        uniq, inv = np.unique(flat, return_inverse=True)
        owner = uniq // big
        first = np.searchsorted(owner, np.arange(len(buildings)))
        state.update(uniq=uniq, owner=owner, first=first)
        return inv - first[flat // big]

    new = citygeometry.reindex(geoms, local, shift) if geoms else []
    uniq = state.get("uniq", np.zeros(0, dtype=np.int64))
    owner = state.get("owner", np.zeros(0, dtype=np.int64))
    rows = _to_grid(model, uniq % big, scale) if len(uniq) else np.zeros((0, 3), np.int64)
    start = np.zeros(len(buildings) + 1, dtype=np.int64)
    np.cumsum(np.bincount(owner, minlength=len(buildings)), out=start[1:])
    if len(rows):
        rows, start, new, report.collapsed_surfaces = _collapse(rows, owner, start, new, where)
    for (n, o, k), g in zip(where, new):
        if g is not None:
            trees[n][o]["geometry"][k] = g
    for objs in trees:
        for obj in objs.values():
            if "geometry" in obj:
                obj["geometry"] = [g for g in obj["geometry"] if g is not None]
    return CopiedBuildings(ids=[model.buildings[b] for b in buildings], objects=trees,
                           vertices=rows, vertex_start=start, scale=scale,
                           reference_system=model.reference_system,
                           extensions=model.extensions if uses_extension else None,
                           report=report)


def _collapse(rows, owner, start, geoms, where):
    """Vertices of one building that met on the output grid made one, rings
    and surfaces that collapsed dropped, vertices left unused removed (only
    happens when the model's grid is finer than the output's)."""
    keyed = np.column_stack([owner, rows])
    if len(unique_rows(keyed)[0]) == len(rows):
        return rows, start, geoms, 0
    uniq, inv = np.unique(keyed, axis=0, return_inverse=True)     # grouped by building
    inv = inv.ravel()
    merged = citygeometry.reindex(geoms, lambda flat: inv[flat],
                                  [int(start[n]) for n, _, _ in where])
    cleaned, dropped = [], 0
    for g in merged:
        g, d = citygeometry.drop_collapsed(g)
        cleaned.append(g)
        dropped += d
    kept = [g for g in cleaned if g is not None]
    used = np.zeros(len(uniq), dtype=bool)
    if kept:
        used[citygeometry.flat_indices(citygeometry.leaves_of(kept))[0]] = True
    remap = np.cumsum(used) - 1
    new_start = np.zeros(len(start), dtype=np.int64)
    np.cumsum(np.bincount(uniq[used, 0], minlength=len(start) - 1), out=new_start[1:])
    local = citygeometry.reindex(kept, lambda flat: remap[flat] - new_start[uniq[flat, 0]])
    it = iter(local)
    out = [None if g is None else next(it) for g in cleaned]
    return uniq[used, 1:], new_start, out, dropped


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
    """Output index of every copied vertex (the generated vertex it equals,
    or a new one after them) and the new rows, in order."""
    G = len(generated)
    if len(copied.vertices) == 0:
        return np.zeros(0, dtype=np.int64), copied.vertices
    both = np.concatenate([generated, copied.vertices]) if G else copied.vertices
    uniq, inv = unique_rows(both)
    target = np.full(len(uniq), -1, dtype=np.int64)
    if G:
        target[inv[:G]] = np.arange(G)
    mine = inv[G:]
    fresh = target[mine] < 0
    # the new rows, in the order they first appear
    groups, first = np.unique(mine[fresh], return_index=True)
    order = np.argsort(first, kind="stable")
    target[groups[order]] = G + np.arange(len(groups))
    return target[mine], uniq[groups[order]]


def _copied_objects(copied, to_out):
    """The copied city objects (one dict, ids in order) with output vertex indices."""
    geoms, shift, where = [], [], []
    for n, objs in enumerate(copied.objects):
        for o, obj in objs.items():
            for k, g in enumerate(obj.get("geometry", ())):
                geoms.append(g)
                shift.append(int(copied.vertex_start[n]))
                where.append((n, o, k))
    new = citygeometry.reindex(geoms, lambda flat: to_out[flat], shift) if geoms else []
    out = {}
    for objs in copied.objects:
        for o, obj in objs.items():
            out[o] = dict(obj)
            if "geometry" in obj:
                out[o]["geometry"] = list(obj["geometry"])
    for (n, o, k), g in zip(where, new):
        out[o]["geometry"][k] = g
    return out


_KEY = re.compile(r'"((?:[^"\\]|\\.)*)":\{"type":"')


def _check_ids(copied, generated_keys):
    clash = [i for objs in copied.objects for i in objs
             if json.dumps(i)[1:-1] in generated_keys]
    if clash:
        raise InputError("{} copied objects have the id of a generated building (e.g. <{}>): "
                         "rename the generated buildings".format(len(clash), clash[0]))


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
        return _merge_text(generated, copied)
    doc = dict(generated)
    scale, translate = _transform(doc, copied)
    gen = np.asarray(doc.get("vertices") or np.zeros((0, 3)), dtype=np.int64).reshape(-1, 3)
    _check_ids(copied, {json.dumps(k)[1:-1] for k in doc.get("CityObjects", {})})
    head, to_out, rows = _head_and_rows(doc, gen, translate, copied, scale)
    objects = dict(doc.get("CityObjects", {}))
    objects.update(_copied_objects(copied, to_out))
    head["CityObjects"] = objects
    head["vertices"] = list(doc.get("vertices") or []) + rows.tolist()
    return head


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
    head = {k: v for k, v in doc.items() if k not in ("CityObjects", "vertices")}
    translate = translate.astype(np.int64)
    if len(gen) == 0:
        translate = copied.vertices.min(axis=0)
    absolute = gen + translate
    to_out, rows = _placement(absolute, copied)
    lo = absolute.min(axis=0) if len(gen) else None
    hi = absolute.max(axis=0) if len(gen) else None
    head["transform"] = {"scale": [scale] * 3, "translate": (translate * scale).round(6).tolist()}
    head["metadata"] = merged_metadata(doc.get("metadata"), lo, hi, copied, scale)
    if copied.extensions:
        head["extensions"] = dict(doc.get("extensions") or {}, **copied.extensions)
    return head, to_out, rows - translate


def _merge_text(text, copied):
    from .cityjsonseq import vertices_texts

    head_end = text.find(',"CityObjects":{')
    vstart = text.rfind(',"vertices":')
    if head_end < 0 or vstart < head_end or not text.endswith("}") or text[vstart - 1] != "}":
        return json.dumps(merge(json.loads(text), copied), separators=(",", ":"))
    doc = json.loads(text[:head_end] + "}")
    body = text[head_end + len(',"CityObjects":{'):vstart - 1]
    inner = text[vstart + len(',"vertices":'):-1]
    scale, translate = _transform(doc, copied)
    flat = np.fromstring(inner.replace("[", " ").replace("]", " "), dtype=np.int64, sep=",") \
        if inner.strip() != "[]" else np.zeros(0, dtype=np.int64)
    gen = flat.reshape(-1, 3)
    # every object key of the generated text starts '"id":{"type":"' (a superset of them)
    _check_ids(copied, set(_KEY.findall(body)))
    head, to_out, rows = _head_and_rows(doc, gen, translate, copied, scale)
    objects = json.dumps(_copied_objects(copied, to_out), separators=(",", ":"))[1:-1]
    new_vertices = vertices_texts(rows, np.array([0, len(rows)]))[0]
    if len(gen) == 0:
        vertices = new_vertices
    elif len(rows) == 0:
        vertices = inner
    else:
        vertices = inner[:-1] + "," + new_vertices[1:]
    head_text = json.dumps(head, separators=(",", ":"))
    return "".join([head_text[:-1], ',"CityObjects":{', body, "," if body and objects else "",
                    objects, '},"vertices":', vertices, "}"])
