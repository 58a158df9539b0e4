"""CityJSONSeq (``.city.jsonl``): a city model streamed as one building per line.

The first line is a CityJSON object with the ``transform`` and ``metadata``
and empty ``CityObjects`` and ``vertices``; every next line is a
``CityJSONFeature``: one building with its children and its own list of
vertices (indices start at 0 in every feature), in the header's transform.
It is the form the 3D BAG's API and tiles serve, and cjio (``cjio stdin``),
cjseq and val3dity read it.

:func:`write` writes the generated buildings (a
:class:`~reconstruction.lod2.solids.build.SolidSet` and its attributes, as
``cityjson.citymodel_text`` takes them) and the copied ones
(:class:`~reconstruction.cityjson.copied.CopiedBuildings`) feature by feature,
chunk by chunk, never as one document; the features collected back
(:func:`collect`) are the single-file model: same objects, same vertex
coordinates. The text is built in bulk with the integer writer of
:mod:`reconstruction.cityjson.model`, as the single file is.
"""

import io
import itertools
import json
import os
import shutil
import tempfile

import numpy as np

from ..core import crs, jsontext
from ..core.errors import InputError
from ..geom.rings import corners, unique_rows
from ..geom.solidset import SEMANTIC_NAMES, take
from . import geometry as citygeometry
from .copied import by_building
from .merge import merged_metadata
from .model import CITYJSON_VERSION, LOD, _attr_list, _member_texts, _split_by_solid

#: copied buildings, and groups of vertices, written at a time (each text's
#: memory used again by the next)
_COPIED_CHUNK = 2000
_GROUPS = 2000


def vertices_texts(rows, starts):
    """JSON text ``[[x,y,z],...]`` of the integer vertex rows of every group
    ``rows[starts[k]:starts[k + 1]]`` ("[]" for an empty group), in bulk:
    the groups written by orjson as a list of arrays, :data:`_GROUPS` at a
    time (orjson writes an array of 635,000 rows twice as slowly as many
    small ones), the text cut where one group ends and the next begins (the
    only "]],[[" in it)."""
    import orjson

    rows = np.ascontiguousarray(rows, dtype=np.int64).reshape(-1, 3)
    bounds = np.asarray(starts, dtype=np.int64).tolist()
    out = ["[]"] * (len(bounds) - 1)
    full = [k for k in range(len(out)) if bounds[k + 1] > bounds[k]]
    for a in range(0, len(full), _GROUPS):
        some = full[a:a + _GROUPS]
        text = orjson.dumps([rows[bounds[k]:bounds[k + 1]] for k in some],
                            option=orjson.OPT_SERIALIZE_NUMPY)
        for k, piece in zip(some, text[3:-3].split(b"]],[[")):
            out[k] = "[[" + str(piece, "ascii") + "]]"
    return out


def _local_vertices(ss):
    """Per ring entry the index of its vertex among its solid's own, the
    vertex rows solid after solid, and the offset of each solid's rows."""
    S = len(ss)
    sizes = np.diff(ss.face_start)
    entry_solid = np.repeat(ss.face_solid, sizes)
    owner = np.full(len(ss.vertices), -1, dtype=np.int64)
    owner[ss.rings] = entry_solid
    if np.all(owner[ss.rings] == entry_solid) and np.all(owner >= 0):
        # every vertex belongs to one solid (as build_solids makes them)
        order = np.argsort(owner, kind="stable")
        starts = np.searchsorted(owner[order], np.arange(S + 1))
        pos = np.empty(len(order), dtype=np.int64)
        pos[order] = np.arange(len(order)) - starts[owner[order]]
        return pos[ss.rings], ss.vertices[order], starts
    NV = max(len(ss.vertices), 1)
    uniq, inv = np.unique(entry_solid * NV + ss.rings, return_inverse=True)
    starts = np.searchsorted(uniq // NV, np.arange(S + 1))
    return inv - starts[entry_solid], ss.vertices[uniq % NV], starts


def building_texts(ss, semantics, ids, attributes, rings):
    """The JSON text ``"id":{"type":"Building",...}`` of every solid, with
    ring vertex indices ``rings`` (one per entry of ``ss.rings``).

    ``attributes``: name -> plain values per solid (see
    ``cityjson._attr_list``); the members come in the order of
    ``cityjson.citymodel_text``: type, attributes, geometry.
    """
    S = len(ss)
    nf = np.diff(ss.solid_start)
    if np.any(nf == 0):
        raise ValueError("solids without faces cannot be written")
    shells = _split_by_solid(rings, (ss.face_start, ss.solid_start[:-1]), S, True)
    sem = np.asarray(semantics, dtype=np.int64)
    counts = np.bincount(np.repeat(np.arange(S), nf) * 3 + sem, minlength=3 * S).reshape(S, 3)
    dumps = json.JSONEncoder(separators=(",", ":")).encode
    surfaces_all = [{"type": name} for name in SEMANTIC_NAMES]
    surf = [dumps(surfaces_all)] * S
    vals = ["[[" + v + "]]" for v in _split_by_solid(sem, ss.solid_start, S, False)]
    for s in np.nonzero(~np.all(counts > 0, axis=1))[0].tolist():
        v = sem[ss.solid_start[s]:ss.solid_start[s + 1]].tolist()
        used = sorted(set(v))
        surf[s] = dumps([surfaces_all[u] for u in used])
        vals[s] = dumps([[used.index(x) for x in v]])
    members = [_member_texts(k, v) for k, v in attributes.items()]
    attrs = (['"attributes":{' + m[:-1] + "}," if m else "" for m in map("".join, zip(*members))]
             if members else [""] * S)
    keys = [json.encoder.encode_basestring_ascii(str(i)) for i in ids]
    geometry = '"geometry":[{"type":"Solid","lod":"' + LOD + '","boundaries":[[[['
    return list(map("".join, zip(
        keys, itertools.repeat(':{"type":"Building",'), attrs, itertools.repeat(geometry),
        shells, itertools.repeat(']]]],"semantics":{"surfaces":'), surf,
        itertools.repeat(',"values":'), vals, itertools.repeat("}}]}"))))


def header(translate, lo, hi, reference_system=None, title=None, copied=None, scale=0.001):
    """The first line of a CityJSONSeq (a dict): transform, metadata, empty objects and vertices.

    ``translate``, ``lo``, ``hi``: integer corners of ``scale``.
    """
    metadata = {"geographicalExtent": (np.concatenate([lo, hi]) * scale).round(6).tolist()}
    if reference_system is not None:
        metadata["referenceSystem"] = crs.crs_url(reference_system)
    if title:
        metadata["title"] = str(title)
    out = {"type": "CityJSON", "version": CITYJSON_VERSION,
           "transform": {"scale": [scale] * 3,
                         "translate": (np.asarray(translate) * scale).round(6).tolist()},
           "metadata": metadata, "CityObjects": {}, "vertices": []}
    if copied is not None and len(copied):
        out["metadata"] = merged_metadata(metadata, lo, hi, copied, scale)
        if copied.extensions:
            out["extensions"] = dict(copied.extensions)
    return out


@citygeometry.gc_paused()
def write(f, ss, semantics, ids, attributes=None, reference_system=None, title=None,
          copied=None, chunk=20000):
    """Write a CityJSONSeq to the file ``f`` (binary, or text): the header, one feature per
    generated building (solids of ``ss``, as ``cityjson.citymodel_text``
    takes them), then one per copied building (``copied``:
    :class:`~reconstruction.cityjson.copied.CopiedBuildings`), ``chunk`` buildings
    at a time. Returns the number of features written."""
    boxes = [corners(ss.vertices)] if len(ss.vertices) else []
    if copied is not None and len(copied.vertices):
        boxes.append(copied.extent())
    if boxes:
        lo = np.min([c[0] for c in boxes], axis=0).astype(np.int64)
        hi = np.max([c[1] for c in boxes], axis=0).astype(np.int64)
    else:
        lo = hi = np.zeros(3, dtype=np.int64)
    writer = SeqWriter(f, lo, reference_system, title, copied, extent=(lo, hi))
    writer.add(ss, semantics, ids, attributes, chunk)
    return writer.finish()


class SeqWriter:
    """A CityJSONSeq written in steps (issue 33, item 9: a city whose solids
    are built a step at a time never holds them all): :meth:`add` writes the
    features of some generated buildings, :meth:`finish` those of the copied
    ones (``copied``, as for :func:`write`) and ends the file.

    ``translate``: the integer origin of the vertices (scale 1 mm), fixed
    beforehand. ``extent``: (lo, hi) integer corners of every vertex, when
    known beforehand: the header is written at once and the features after
    it; otherwise (None) the features go to a temporary file beside ``f``
    (removed whatever happens) until :meth:`finish` knows the extent, writes
    the header and copies them after it.
    """

    def __init__(self, f, translate, reference_system=None, title=None, copied=None,
                 extent=None):
        self.f, self.text_file = f, isinstance(f, io.TextIOBase)
        self.translate = np.asarray(translate, dtype=np.int64)
        self.reference_system, self.title = reference_system, title
        self.copied = by_building(copied) if copied is not None and len(copied) else None
        # each copied feature indexes its own vertices
        self.copied_ids = (set() if self.copied is None else
                           {o for objs in self.copied.trees for o in objs})
        self.count = 0
        self.boxes = [] if self.copied is None or not len(self.copied.vertices) else [
            self.copied.extent()]
        self.spool = None
        if extent is not None:
            self._write(self._header(*extent))
        else:
            self.spool = tempfile.TemporaryFile(dir=_directory_of(f))

    def _header(self, lo, hi):
        head = header(self.translate, lo, hi, self.reference_system, self.title, self.copied)
        return json.dumps(head, separators=(",", ":")) + "\n"

    def _write(self, text):
        self.f.write(text if self.text_file else text.encode())

    def add(self, ss, semantics, ids, attributes=None, chunk=20000):
        """Write the features of the generated buildings ``ss`` (their face
        ``semantics``, ``ids``, ``attributes``: name -> one value per building)."""
        attributes = {k: _attr_list(v) for k, v in (attributes or {}).items()}
        ids = [str(i) for i in ids]
        clash = self.copied_ids.intersection(ids)
        if clash:
            raise InputError("{} copied objects have the id of a generated building (e.g. <{}>)"
                             .format(len(clash), sorted(clash)[0]))
        if len(ss.vertices):
            self.boxes.append(corners(ss.vertices))
        out = self.spool if self.spool is not None else self.f
        text_file = self.spool is None and self.text_file
        S = len(ss)
        for a in range(0, S, chunk):
            b = min(S, a + chunk)
            part = take(ss, np.arange(a, b)) if (a, b) != (0, S) else ss
            local, rows, starts = _local_vertices(part)
            objects = building_texts(part, np.asarray(semantics)[_faces_of(ss, a, b)], ids[a:b],
                                     {k: v[a:b] for k, v in attributes.items()}, local)
            verts = vertices_texts(rows - self.translate, starts)
            keys = [json.encoder.encode_basestring_ascii(i) for i in ids[a:b]]
            lines = map("".join, zip(
                itertools.repeat('{"type":"CityJSONFeature","id":'), keys,
                itertools.repeat(',"CityObjects":{'), objects, itertools.repeat('},"vertices":'),
                verts, itertools.repeat("}\n")))
            out.writelines(lines if text_file else (line.encode() for line in lines))
        self.count += S

    def finish(self):
        """Write the copied buildings' features (and, spooled, the header
        and the features before them); returns the number of features."""
        if self.spool is not None:
            if self.boxes:
                lo = np.min([c[0] for c in self.boxes], axis=0).astype(np.int64)
                hi = np.max([c[1] for c in self.boxes], axis=0).astype(np.int64)
            else:
                lo = hi = self.translate
            self._write(self._header(lo, hi))
            self.spool.seek(0)
            if self.text_file:
                self.f.write(str(self.spool.read(), "utf-8"))
            else:
                shutil.copyfileobj(self.spool, self.f, 1 << 22)
            self.spool.close()
            self.spool = None
        copied = self.copied
        if copied is not None:
            for text in _copied_features(copied, self.translate, _COPIED_CHUNK):
                self.f.write(str(text, "utf-8") if self.text_file else text)
        return self.count + (len(copied) if copied is not None else 0)

    def close(self):
        """Let go of the temporary file (also when the writing failed)."""
        if self.spool is not None:
            self.spool.close()
            self.spool = None


def _directory_of(f):
    """The directory of an open file (None: the system's temporary one)."""
    name = getattr(f, "name", None)
    return os.path.dirname(os.path.abspath(name)) if isinstance(name, str) else None


def _copied_features(copied, lo, chunk):
    """The feature lines of the copied buildings, ``chunk`` buildings a
    UTF-8 text: each feature written by orjson around its boundaries and
    vertices, which are written in bulk beforehand (the boundaries as they
    were read where they index the building's own vertices as stored:
    :attr:`~reconstruction.cityjson.copied.CopiedBuildings.stored_local`); by
    json.dumps a feature that orjson does not write (a lone surrogate)."""
    as_read = copied.stored_local
    fills = iter(()) if as_read else iter(copied.boundary_texts())
    verts = vertices_texts(copied.vertices - lo, copied.vertex_start)
    plain = []                          # every building's objects, made once if wanted

    def plain_feature(n):
        if not plain:
            plain.append(copied.objects())
        rows = copied.vertices[copied.vertex_start[n]:copied.vertex_start[n + 1]] - lo
        return {"type": "CityJSONFeature", "id": copied.ids[n],
                "CityObjects": plain[0][n], "vertices": rows.tolist()}

    for a in range(0, len(copied), chunk):
        lines = []
        for n in range(a, min(len(copied), a + chunk)):
            feature = {"type": "CityJSONFeature", "id": copied.ids[n],
                       "CityObjects": copied.trees[n] if as_read else copied.filled(n, fills),
                       "vertices": citygeometry.fragment(verts[n])}
            lines.append(citygeometry.json_bytes(feature, lambda: plain_feature(n)))
        lines.append(b"")
        yield b"\n".join(lines)


def _faces_of(ss, a, b):
    """The face range of solids ``a`` to ``b`` (a slice)."""
    return slice(int(ss.solid_start[a]), int(ss.solid_start[b]))


# ---------------------------------------------------------------------------
# Reading
# ---------------------------------------------------------------------------

def _json_line(line, number, path):
    return jsontext.loads(line, "CityJSONSeq file (line {})".format(number), path)


def features(f, path="<stream>"):
    """The header (dict) of a CityJSONSeq text file and an iterator over its
    features; InputError for a line that is not what it should be."""
    head = _json_line(f.readline(), 1, path)
    if not isinstance(head, dict) or head.get("type") != "CityJSON":
        raise InputError("'{}' is not a CityJSONSeq file: its first line is not a CityJSON "
                         "object".format(path))

    def lines():
        for number, line in enumerate(f, 2):
            if not line.strip():
                continue
            feature = _json_line(line, number, path)
            if (not isinstance(feature, dict) or feature.get("type") != "CityJSONFeature"
                    or not isinstance(feature.get("CityObjects"), dict)):
                raise InputError("'{}', line {}: not a CityJSONFeature".format(path, number))
            yield feature

    return head, lines()


@citygeometry.gc_paused()
def read_features(f, path="<stream>"):
    """All features of a CityJSONSeq as one document whose objects keep their
    feature's indices, the vertex offset of every object's feature and the
    number of its feature's vertices (its indices must stay below it)."""
    head, lines = features(f, path)
    return _gathered(head, lines, path)


def read_batches(f, path="<stream>", step=2000):
    """The features of a CityJSONSeq ``step`` at a time, each batch as
    :func:`read_features` gives them all (a document, offsets and counts), so that a
    reader holds one batch at a time (issue 49, item 14)."""
    head, lines = features(f, path)
    while True:
        with citygeometry.gc_paused():
            batch = list(itertools.islice(lines, step))
            if not batch:
                return
            gathered = _gathered(head, batch, path)
        yield gathered


def _gathered(head, lines, path):
    """The features ``lines`` as one document (see :func:`read_features`)."""
    objects, vertices, offsets, counts = {}, [], {}, {}
    for feature in lines:
        offset = len(vertices)
        own = feature.get("vertices") or []
        vertices.extend(own)
        for oid, obj in feature["CityObjects"].items():
            if oid in objects:
                raise InputError("'{}': the city object <{}> is in two features".format(path, oid))
            objects[oid] = obj
            offsets[oid] = offset
            counts[oid] = len(own)
    doc = dict(head)
    doc["CityObjects"] = objects
    doc["vertices"] = vertices
    return doc, offsets, counts


def collect(f, path="<stream>"):
    """The CityJSON document (dict) of a CityJSONSeq text file: the features'
    objects with indices into one vertex list, shared vertices once and
    unused ones left out."""
    doc, offsets, _ = read_features(f, path)
    return joined(doc, offsets)


@citygeometry.gc_paused()
def joined(doc, offsets):
    """The document of :func:`read_features` (``doc``, ``offsets``) with indices into
    one vertex list: shared vertices once, unused ones left out."""
    geoms, shift, where = [], [], []
    for oid, obj in doc["CityObjects"].items():
        for k, g in enumerate(obj.get("geometry", ())):
            geoms.append(g)
            shift.append(offsets[oid])
            where.append((oid, k))
    vertices = np.asarray(doc["vertices"], dtype=np.int64).reshape(-1, 3)
    state = {"rows": np.zeros((0, 3), dtype=np.int64)}

    def used_once(flat):
        used, pos = np.unique(flat, return_inverse=True)
        state["rows"], inv = unique_rows(vertices[used])
        return inv[pos]

    new = citygeometry.reindex(geoms, used_once, shift) if geoms else []
    objects = {oid: dict(obj) for oid, obj in doc["CityObjects"].items()}
    for oid, obj in objects.items():
        if "geometry" in obj:
            obj["geometry"] = list(obj["geometry"])
    for (oid, k), g in zip(where, new):
        objects[oid]["geometry"][k] = g
    doc["CityObjects"] = objects
    doc["vertices"] = state["rows"].tolist()
    return doc


def object_tree(objects, oid):
    """The ids of a city object's tree in ``objects``: itself first, then its descendants."""
    tree, k = [oid], 0
    while k < len(tree):
        tree.extend(c for c in objects[tree[k]].get("children", ()) if c in objects
                    and c not in tree)
        k += 1
    return tree


def document_features(doc):
    """A CityJSON document (dict) as CityJSONSeq: its header, then one
    ``CityJSONFeature`` per top-level object with its children and its own
    vertices (dicts, in the document's order; the transform is the header's)."""
    head = {k: v for k, v in doc.items() if k not in ("CityObjects", "vertices")}
    head["CityObjects"], head["vertices"] = {}, []
    yield head
    objects = doc.get("CityObjects", {})
    vertices = np.asarray(doc.get("vertices") or np.zeros((0, 3)), dtype=np.int64).reshape(
        -1, 3)
    for oid, obj in objects.items():
        if obj.get("parents"):
            continue
        tree = object_tree(objects, oid)
        members = {m: dict(objects[m]) for m in tree}
        where = [(m, k) for m in tree for k in range(len(objects[m].get("geometry", ())))]
        geoms = [objects[m]["geometry"][k] for m, k in where]
        own = np.zeros((0, 3), dtype=np.int64)
        if geoms:
            used, local = np.unique(citygeometry.indices(geoms), return_inverse=True)
            own = vertices[used]
            new = citygeometry.reindex(geoms, lambda flat: local)
            for m in tree:
                if "geometry" in members[m]:
                    members[m]["geometry"] = list(members[m]["geometry"])
            for (m, k), g in zip(where, new):
                members[m]["geometry"][k] = g
        yield {"type": "CityJSONFeature", "id": oid, "CityObjects": members,
               "vertices": own.tolist()}
