"""Copied buildings merged into the CityJSON document of the generated ones.

:func:`merge` adds the buildings of :func:`reconstruction.cityjson.copied.copy_buildings`
to the CityJSON document of the generated buildings (the dict of
``cityjson.citymodel`` or the text of ``cityjson.citymodel_text``): one
multi-LoD CityJSON 2.0 model in the generated model's ``transform``, vertices
shared and without duplicates; :func:`merged_pieces` writes it piece by piece.
"""

import itertools
import json
import re

import numpy as np

from ..core.errors import InputError
from ..geom.rings import corners, unique_rows
from . import geometry as citygeometry
from ..core.crs import as_ogc_url, epsg_code, horizontal_epsg, same_place
from .model import joined_text, shifted_lists

from .copied import _objects_pieces


# ---------------------------------------------------------------------------
# Into the generated document
# ---------------------------------------------------------------------------

def output_reference_system(generated, copied):
    """The reference system of the merged model: the copied model's when it
    is the generated one's with heights (7415 for 28992), else the one they
    share; InputError when they locate points differently. An EPSG code
    spelt otherwise than as an OGC URL (``urn:ogc:def:crs:EPSG::7415``,
    ``EPSG:7415``) is written as its OGC URL, as CityJSON 2.0 wants it."""
    if copied is None or generated is None:
        return generated if copied is None else as_ogc_url(copied)
    a, b = epsg_code(generated), epsg_code(copied)
    if a == b:
        return generated
    if a is not None and b is not None and same_place(a, b):
        return generated if horizontal_epsg(b) == b else as_ogc_url(copied)
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
