"""CityJSON 2.0 output of LoD2 solids.

One ``Building`` per footprint with one ``Solid`` geometry of lod "2.0" and
its semantic surfaces, vertices shared and de-duplicated over the whole
model, stored as integers with a millimetre ``transform``. Built from the
flat arrays of a :class:`reconstruction.geom.solidset.SolidSet` in bulk.
"""

import itertools
import json
import math
import os
import warnings

import numpy as np

from ..core import crs
from ..core import safefile
from ..geom.rings import next_in_ring, offsets, unique_rows
from ..geom.solidset import SEMANTIC_NAMES

CITYJSON_VERSION = "2.0"
LOD = "2.0"


def _attr_value(value):
    """A plain JSON value: numpy scalars as Python numbers, nan as None."""
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float) and value != value:
        return None
    return value


def _attr_list(values):
    """Attribute values as plain Python values (numpy arrays in bulk; nan -> None)."""
    if isinstance(values, np.ndarray) and values.dtype.kind in "fiub":
        out = values.tolist()
        if values.dtype.kind == "f" and np.isnan(values).any():
            out = [None if v != v else v for v in out]
        return out
    return [_attr_value(v) for v in values]


def citymodel(ss, semantics, ids, attributes=None, reference_system=None, title=None):
    """The CityJSON document (a dict) of a set of solids.

    ``ss``: a :class:`~reconstruction.geom.solidset.SolidSet`; ``semantics``: a code
    per face (0 ground, 1 wall, 2 roof); ``ids``: an identifier per solid;
    ``attributes``: dict name -> sequence of values per solid (None/nan
    values are left out); ``reference_system``: EPSG code or OGC URL.
    """
    attributes = attributes or {}
    S = len(ss)
    if len(ss.vertices):
        uniq, inv = unique_rows(ss.vertices)
        lo = uniq.min(axis=0)
        hi = uniq.max(axis=0)
        verts = (uniq - lo).tolist()
        rings = inv[ss.rings].tolist()
    else:
        lo = hi = np.zeros(3, dtype=np.int64)
        verts, rings = [], []
    fs = ss.face_start.tolist()
    sstart = ss.solid_start.tolist()
    sem = np.asarray(semantics, dtype=np.int64).tolist()
    attr_lists = {k: _attr_list(vals) for k, vals in attributes.items()}
    surfaces_all = [{"type": name} for name in SEMANTIC_NAMES]
    objects = {}
    # every surface as [ring] once, then each shell is a slice of that list
    surfaces_list = [[rings[a:b]] for a, b in zip(fs[:-1], fs[1:])]
    for s in range(S):
        f0, f1 = sstart[s], sstart[s + 1]
        shell = surfaces_list[f0:f1]
        values = sem[f0:f1]
        used = sorted(set(values))
        if used == [0, 1, 2]:
            surfaces = surfaces_all
        else:
            remap = {u: k for k, u in enumerate(used)}
            surfaces = [surfaces_all[u] for u in used]
            values = [remap[v] for v in values]
        obj = {"type": "Building",
               "geometry": [{"type": "Solid", "lod": LOD, "boundaries": [shell],
                             "semantics": {"surfaces": surfaces, "values": [values]}}]}
        attrs = {k: vals[s] for k, vals in attr_lists.items() if vals[s] is not None}
        if attrs:
            obj["attributes"] = attrs
        objects[str(ids[s])] = obj
    metadata = {"geographicalExtent": (np.concatenate([lo, hi]) / 1000.0).tolist()}
    if reference_system is not None:
        metadata["referenceSystem"] = crs.crs_url(reference_system)
    if title:
        metadata["title"] = str(title)
    return {
        "type": "CityJSON",
        "version": CITYJSON_VERSION,
        "transform": {"scale": [0.001, 0.001, 0.001], "translate": (lo / 1000.0).tolist()},
        "metadata": metadata,
        "CityObjects": objects,
        "vertices": verts,
    }


#: the four ASCII digits of 0000-9999, each as one uint32 (see :func:`_int_text`)
_QUADS = []


def _quads():
    if not _QUADS:
        n = np.arange(10000)
        digits = np.stack([n // 1000, n // 100 % 10, n // 10 % 10, n % 10], axis=1) + 48
        _QUADS.append(np.ascontiguousarray(digits.astype(np.uint8)).view(np.uint32).ravel())
    return _QUADS[0]


def _int_text(values, prefix, table):
    """Decimal text of non-negative integers, each after its separator
    ``table[prefix[i]]``, built in numpy (as ``json.dumps`` writes ints).

    Every value gets a row of characters (separator, then its digits right
    aligned, written four at a time from a table of 0000-9999); the text is
    the row-major selection of the characters in use (which, and how many,
    looked up by separator and digit count in one table), chunk by chunk
    into one buffer of the text's length. Returns the text and the offset
    in it of each value's separator.
    """
    values = np.asarray(values, dtype=np.int64)
    if len(values) == 0:
        return "", np.zeros(0, dtype=np.int64)
    if values.min() < 0:
        raise ValueError("negative value")
    top = int(values.max())
    W = len(str(top))
    tables = _separator_tables(tuple(table), W)
    prefix = np.asarray(prefix)
    # (separator, digit count) of every value, and so its characters'
    # count, chunk by chunk in small integers (a large model's temporaries
    # are new memory, page after page, in a fresh process)
    bounds = 10 ** np.arange(1, W, dtype=np.int64)
    kind = np.uint8 if len(table) * (W + 1) < 256 else np.int64
    code = np.empty(len(values), dtype=kind)
    for a in range(0, len(values), _CHUNK):
        digits = np.searchsorted(bounds, values[a:a + _CHUNK], side="right") + 1
        code[a:a + _CHUNK] = digits + prefix[a:a + _CHUNK].astype(np.int64) * (W + 1)
    size = tables[4][code]
    ends = np.cumsum(size, dtype=np.int64)
    out = np.empty(int(ends[-1]), dtype=np.uint8)
    # in chunks that stay in the processor's cache (a fifth faster than in one go)
    for a in range(0, len(values), _CHUNK):
        b = min(a + _CHUNK, len(values))
        first = int(ends[a - 1]) if a else 0
        _int_chars(values[a:b], code[a:b], W, top, tables, out[first:int(ends[b - 1])])
    ends -= size                                    # each value's offset
    return str(memoryview(out), "ascii"), ends


_CHUNK = 1 << 14


def _int_chars(values, code, W, top, tables, out):
    """The characters of :func:`_int_text` for a chunk of values (``code``:
    their separator and digit count), written into ``out`` (uint8, their length)."""
    SB, WB, sep_blocks, used_chars, sizes = tables
    n = len(values)
    chars = np.empty((n, SB + WB), dtype=np.uint32)
    sep = code // (W + 1)
    for j in range(SB):
        chars[:, j] = sep_blocks[:, j][sep]
    quads = _quads()
    rest = values.astype(np.int32) if top < 2 ** 31 else values.copy()
    block = np.empty_like(rest)
    for j in range(SB + WB - 1, SB - 1, -1):
        np.divmod(rest, 10000, out=(rest, block))
        chars[:, j] = quads[block]
    np.compress(used_chars[code].ravel(), chars.view(np.uint8).ravel(), out=out)


_SEPARATOR_TABLES = {}


def _separator_tables(table, W):
    """For :func:`_int_text`: the 4-character blocks of separators (SB) and
    digits (WB) of a row, the separators as uint32 blocks, and per
    (separator, digit count) the characters of a row in use and their count."""
    key = (table, W)
    if key not in _SEPARATOR_TABLES:
        seps = [t.encode("ascii") for t in table]
        sep_len = np.array([len(t) for t in seps], dtype=np.int64)
        SB, WB = -(-int(sep_len.max()) // 4), -(-W // 4)
        width = 4 * (SB + WB)
        sep_chars = np.zeros((len(seps), 4 * SB), dtype=np.uint8)
        for code, sep in enumerate(seps):
            sep_chars[code, :len(sep)] = np.frombuffer(sep, dtype=np.uint8)
        col, digits = np.arange(width), np.arange(W + 1)
        used = (col < sep_len[:, None, None]) | (col >= width - digits[None, :, None])
        sizes = (sep_len[:, None] + digits[None, :]).ravel()
        if sizes.max() < 256:
            sizes = sizes.astype(np.uint8)
        if len(_SEPARATOR_TABLES) > 64:
            _SEPARATOR_TABLES.clear()
        _SEPARATOR_TABLES[key] = (SB, WB, np.ascontiguousarray(sep_chars.view(np.uint32)),
                                  np.ascontiguousarray(used.reshape(-1, width)), sizes)
    return _SEPARATOR_TABLES[key]


def _pieces(text, offsets, first):
    """``text`` cut at the ``offsets`` of the entries ``first`` (one piece each)."""
    cuts = offsets[first].tolist() + [len(text)]
    return [text[a:b] for a, b in zip(cuts[:-1], cuts[1:])]


def shifted_lists(lists, shift):
    """The JSON texts ``lists`` (plain nested lists of non-negative integers:
    digits, brackets and commas, no empty list) with ``shift`` added to
    every integer, in bulk: the texts joined, their numbers read and
    written again by :func:`_int_text`, each after the brackets and the
    comma that stood before it. None where a text is not such a list."""
    if not lists:
        return []
    blob = ",".join(lists)
    raw = blob.encode("ascii", "replace")
    values = plain_integers(raw)
    if values is None:
        return None
    chars = np.frombuffer(raw, dtype=np.uint8)
    digit = (chars - np.uint8(48)) < np.uint8(10)
    edges = np.flatnonzero(digit[1:] != digit[:-1]) + 1
    starts, ends = edges[0::2], edges[1::2]
    commas = np.flatnonzero(chars == 44)
    n = len(starts)
    if n == 0 or digit[0] or len(ends) != n or len(commas) != n - 1:
        return None
    # between two numbers: "]" * close, the comma, "[" * open
    close, open_ = commas - ends[:-1], starts[1:] - commas - 1
    if np.any(close < 0) or np.any(open_ < 0):
        return None
    most = int(max(close.max(initial=0), open_.max(initial=0))) + 1
    table = ["]" * i + "," + "[" * j for i in range(most) for j in range(most)] + [blob[:starts[0]]]
    code = np.empty(n, dtype=np.int64)
    code[0] = len(table) - 1
    code[1:] = close * most + open_
    out, at = _int_text(values + shift, code, table)
    # list k + 1 starts after the comma that joined it to list k
    joins = np.cumsum([len(t) + 1 for t in lists[:-1]], dtype=np.int64) - 1
    after = np.searchsorted(starts, joins)              # its first number
    cut = at[after] + close[after - 1]
    bounds = [0] + np.column_stack([cut, cut + 1]).ravel().tolist() + [len(out)]
    pieces = [out[a:b] for a, b in zip(bounds[0::2], bounds[1::2])]
    pieces[-1] += blob[ends[-1]:]
    return pieces


def plain_integers(raw):
    """The integers of ``raw`` (bytes: the compact JSON text, as orjson or
    json writes it, of nested lists of non-negative integers, no list
    empty), in order, as int64; None where it is not such a text."""
    if b"[]" in raw:                    # np.fromstring would read an empty list as 0
        return None
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error", DeprecationWarning)      # numpy < 2.3
            values = np.fromstring(raw.translate(_BRACKETS), dtype=np.int64, sep=",")
    except (ValueError, DeprecationWarning):                        # not digits and commas
        return None
    if len(values) and (values.min() < 0 or values.max() == np.iinfo(np.int64).max):
        return None                     # negative, or read past int64
    return values


#: brackets read as spaces (the text of nested lists of integers as ``np.fromstring`` reads it)
_BRACKETS = bytes.maketrans(b"[]", b"  ")


def _split_by_solid(values, starts, S, face_level):
    """JSON text of ``values`` (one non-negative int per entry) cut into one
    piece per solid: ``a,b,c`` per solid, or with ``face_level`` the rings
    of its faces ``a,b,c]],[[d,e,f``.

    ``starts``: offset of each solid's first entry, or with ``face_level``
    the pair (offset of every face's first entry, first face of each solid).
    """
    values = np.asarray(values, dtype=np.int64)
    prefix = np.full(len(values), 2, dtype=np.int8)
    if face_level:
        face_start, solid_first_face = starts
        prefix[face_start[:-1]] = 1
        first = face_start[solid_first_face]
    else:
        first = np.asarray(starts[:-1], dtype=np.int64)
    prefix[first] = 0
    text, offsets = _int_text(values, prefix, ["", "]],[[", ","])
    pieces = _pieces(text, offsets, first)
    if len(pieces) != S:
        raise ValueError("cannot split the boundaries by solid")
    return pieces


def _vertices_text(vertices):
    """JSON text of an (n, 3) array of non-negative integers ``[[x,y,z],...]``."""
    if len(vertices) == 0:
        return "[]"
    prefix = np.full(vertices.shape, 2, dtype=np.int8)
    prefix[:, 0] = 1
    prefix[0, 0] = 0
    text, _ = _int_text(vertices.ravel(), prefix.ravel(), ["[", "],[", ","])
    return "[" + text + "]]"


def _member_texts(name, values):
    """JSON text ``"name":value,`` of one attribute per object ('' where the
    value is None), as ``json.dumps`` writes it, in bulk."""
    key = json.encoder.encode_basestring_ascii(name) + ":"
    out = []
    for v in values:
        if v is None:
            out.append("")
        elif type(v) is str:
            out.append(key + json.encoder.encode_basestring_ascii(v) + ",")
        elif type(v) is float and math.isfinite(v) or type(v) is int:
            out.append(key + repr(v) + ",")
        else:
            out.append(key + json.dumps(v, separators=(",", ":")) + ",")
    return out


def citymodel_text(ss, semantics, ids, attributes=None, reference_system=None, title=None):
    """The CityJSON document of a set of solids as compact JSON text.

    Same document as ``json.dumps(citymodel(...))`` (see :func:`citymodel`;
    attributes come before the geometry), written in bulk: the rings of all buildings go
    through the C JSON encoder in one list, attributes column by column, and
    the city objects are joined from columns of text.
    """
    attributes = attributes or {}
    S = len(ss)
    nf = np.diff(ss.solid_start)
    if S == 0 or np.any(nf == 0):
        return json.dumps(citymodel(ss, semantics, ids, attributes, reference_system, title),
                          separators=(",", ":"))
    uniq, inv = unique_rows(ss.vertices)
    lo = uniq.min(axis=0)
    hi = uniq.max(axis=0)
    rings = inv[ss.rings]
    shells = _split_by_solid(rings, (ss.face_start, ss.solid_start[:-1]), S, True)
    sem = np.asarray(semantics, dtype=np.int64)
    face_solid = np.repeat(np.arange(S), nf)
    counts = np.bincount(face_solid * 3 + sem, minlength=3 * S).reshape(S, 3)
    all_used = np.all(counts > 0, axis=1)
    values = _split_by_solid(sem, ss.solid_start, S, False)
    surfaces_all = [{"type": name} for name in SEMANTIC_NAMES]
    dumps = json.JSONEncoder(separators=(",", ":")).encode
    surf_all_text = dumps(surfaces_all)
    surf = [surf_all_text] * S
    vals = ["[[" + v + "]]" for v in values]
    if not all_used.all():
        sem_list = sem.tolist()
        for s in np.nonzero(~all_used)[0].tolist():
            v = sem_list[ss.solid_start[s]:ss.solid_start[s + 1]]
            used = sorted(set(v))
            remap = {u: k for k, u in enumerate(used)}
            surf[s] = dumps([surfaces_all[u] for u in used])
            vals[s] = dumps([[remap[x] for x in v]])
    members = [_member_texts(k, _attr_list(v)) for k, v in attributes.items()]
    if members:
        attrs = ['"attributes":{' + m[:-1] + "}," if m else ""
                 for m in map("".join, zip(*members))]
    else:
        attrs = [""] * S
    keys = [json.encoder.encode_basestring_ascii(str(i)) for i in ids]
    geometry = '"geometry":[{"type":"Solid","lod":"' + LOD + '","boundaries":[[[['
    pieces = map("".join, zip(keys, itertools.repeat(':{"type":"Building",'), attrs,
                              itertools.repeat(geometry), shells,
                              itertools.repeat(']]]],"semantics":{"surfaces":'), surf,
                              itertools.repeat(',"values":'), vals, itertools.repeat("}}]}")))
    metadata = {"geographicalExtent": (np.concatenate([lo, hi]) / 1000.0).tolist()}
    if reference_system is not None:
        metadata["referenceSystem"] = crs.crs_url(reference_system)
    if title:
        metadata["title"] = str(title)
    head = dumps({"type": "CityJSON", "version": CITYJSON_VERSION,
                  "transform": {"scale": [0.001, 0.001, 0.001],
                                "translate": (lo / 1000.0).tolist()},
                  "metadata": metadata})
    return "".join([head[:-1], ',"CityObjects":{', ",".join(pieces), '},"vertices":',
                    _vertices_text(uniq - lo), "}"])


def write_text(path, text):
    """Write a CityJSON document given as text (or a list of pieces, in
    order, each a text or UTF-8 bytes: see :func:`reconstruction.cityjson.merge.merged_pieces`),
    whole or not at all (a unique temporary file renamed into place; through
    a symbolic link; never over something that is not a regular file:
    :mod:`reconstruction.core.safefile`)."""
    with safefile.replacing(path, "wb") as f:
        write_pieces(f, [text] if isinstance(text, str) else text)


def write_pieces(f, pieces):
    """Write a document's pieces (texts or UTF-8 bytes) to the binary file ``f``."""
    for piece in pieces:
        f.write(piece.encode() if isinstance(piece, str) else piece)


def joined_text(pieces):
    """The text of a document given as pieces (texts or UTF-8 bytes), as
    :func:`write_text` writes them."""
    return "".join(p if isinstance(p, str) else str(p, "utf-8") for p in pieces)


def write(path, model):
    """Write a CityJSON document (a dict) compactly, as :func:`write_text` writes text."""
    write_text(path, json.dumps(model, separators=(",", ":")))


def consistency_errors(model):
    """cjio-style consistency checks of a CityJSON document.

    Vertex indices in range, no orphan and no duplicate vertices, rings of at
    least 3 vertices without duplicate consecutive ones, semantic values
    matching the boundaries. Returns a list of error strings (empty when
    consistent).
    """
    errors = []
    nv = len(model.get("vertices", []))
    flat, sizes, owners = [], [], []
    for oid, obj in model.get("CityObjects", {}).items():
        for g in obj.get("geometry", []):
            if g.get("type") != "Solid":
                errors.append("{}: geometry is not a Solid".format(oid))
                continue
            shells = g["boundaries"]
            for shell in shells:
                for surface in shell:
                    for ring in surface:
                        flat.extend(ring)
                        sizes.append(len(ring))
                        owners.append(oid)
            sem = g.get("semantics")
            if sem is not None:
                values = sem["values"]
                if len(values) != len(shells) or any(
                        len(v) != len(sh) for v, sh in zip(values, shells)):
                    errors.append("{}: semantic values do not match the boundaries".format(oid))
                else:
                    ns = len(sem["surfaces"])
                    if any(x is not None and not 0 <= x < ns for v in values for x in v):
                        errors.append("{}: semantic value out of range".format(oid))
    flat = np.asarray(flat, dtype=np.int64)
    sizes = np.asarray(sizes, dtype=np.int64)
    for k in np.nonzero(sizes < 3)[0][:10]:
        errors.append("{}: ring with fewer than 3 vertices".format(owners[k]))
    if len(flat):
        out = (flat < 0) | (flat >= nv)
        if out.any():
            errors.append("{} vertex indices out of range".format(int(out.sum())))
            flat = np.clip(flat, 0, max(nv - 1, 0))
        bounds = offsets(sizes)
        start = bounds[:-1]
        dup = np.nonzero(flat == flat[next_in_ring(bounds)])[0]
        if len(dup):
            ring_of = np.searchsorted(start, dup, side="right") - 1
            for k in np.unique(ring_of)[:10]:
                errors.append("{}: duplicate consecutive vertices".format(owners[k]))
    used = np.zeros(nv, dtype=bool)
    used[flat] = True
    if nv and not used.all():
        errors.append("{} orphan vertices".format(int((~used).sum())))
    if nv:
        v = np.asarray(model["vertices"])
        if len(np.unique(v, axis=0)) != len(v):
            errors.append("duplicate vertices")
    return errors


def schema_validator(schema_dir, definition="cityjson.schema.json", extensions=None):
    """A jsonschema validator of the official CityJSON schemas in ``schema_dir``
    (e.g. ``../shared/schemas/cityjson-2.0.2``), with every ``$ref`` resolved
    locally through a ``referencing`` registry. ``definition`` may point
    inside a file, e.g. ``cityobjects.schema.json#/Building``, or inside an
    Extension of ``extensions`` ({name: its document}, each read as the file
    ``<name>.ext.json`` beside the schemas), e.g.
    ``HistoVersions.ext.json#/extraCityObjects/+BuildingVersion``."""

    from jsonschema import Draft7Validator
    from referencing import Registry, Resource
    from referencing.jsonschema import DRAFT7

    resources = []
    base = None
    for name in sorted(os.listdir(schema_dir)):
        if not name.endswith(".json"):
            continue
        with open(os.path.join(schema_dir, name)) as f:
            contents = json.load(f)
        resource = Resource.from_contents(contents, default_specification=DRAFT7)
        uri = contents.get("$id", name)
        resources.append((uri, resource))
        if name == "cityjson.schema.json":
            base = uri.rsplit("/", 1)[0] + "/"
    for name, contents in (extensions or {}).items():
        resources.append(((base or "") + name + ".ext.json", Resource.from_contents(
            contents, default_specification=DRAFT7)))
    registry = Registry().with_resources(resources)
    return Draft7Validator({"$ref": (base or "") + definition}, registry=registry)


def _extension_definitions(model, extensions):
    """{what: definition} of what a document's Extensions define ({name: document}):
    ``("object", type)``, ``("attribute", type, name)`` and ``("root", name)``, each a
    definition for :func:`schema_validator`; and the errors of Extensions the document
    names but that are not given."""
    found, errors = {}, []
    for name in (model.get("extensions") or {}):
        ext = (extensions or {}).get(name)
        if ext is None:
            errors.append("Extension {} is not given: its definitions are not checked".format(
                name))
            continue
        where = name + ".ext.json#/"
        for kind in ext.get("extraCityObjects") or {}:
            found["object", kind] = where + "extraCityObjects/" + kind
        for kind, names in (ext.get("extraAttributes") or {}).items():
            for attribute in names:
                found["attribute", kind, attribute] = "{}extraAttributes/{}/{}".format(
                    where, kind, attribute)
        for prop in ext.get("extraRootProperties") or {}:
            found["root", prop] = where + "extraRootProperties/" + prop
    return found, errors


def schema_errors(model, schema_dir, max_objects=None, extensions=None):
    """Schema errors of a CityJSON document (list of messages, empty if valid).

    The document without its city objects (plus the first 10) is checked
    against ``cityjson.schema.json``, then every city object (or the first
    ``max_objects``) against its own definition: the same checks as the whole
    file at once, much faster than the schema's ``oneOf`` over all types.
    ``extensions``: {name: Extension document} of the Extensions the document
    names: its new city object types (``+Type``), attributes (``+name``) and
    root properties (``+name``) are checked against their definitions; one
    that no Extension defines is an error.
    """
    found, errors = _extension_definitions(model, extensions)
    validators = {}

    def check(definition, value, label):
        if definition not in validators:
            validators[definition] = schema_validator(schema_dir, definition, extensions)
        errors.extend(label + e.message for e in validators[definition].iter_errors(value))

    objects = model.get("CityObjects", {})
    head = dict(model)
    head["CityObjects"] = dict(itertools.islice(objects.items(), 10))
    check("cityjson.schema.json", head, "")
    for prop in (p for p in model if p.startswith("+")):
        if ("root", prop) not in found:
            errors.append("root property {} is in no Extension".format(prop))
        else:
            check(found["root", prop], model[prop], prop + ": ")
    for oid, obj in itertools.islice(objects.items(), max_objects):
        kind = obj.get("type", "")
        label = "{}: ".format(oid)
        if kind.startswith("+"):
            if ("object", kind) not in found:
                errors.append("{}type {} is in no Extension".format(label, kind))
                continue
            check(found["object", kind], obj, label)
        else:
            check("cityobjects.schema.json#/" + kind, obj, label)
        attributes = obj.get("attributes")
        for name in (n for n in (attributes if isinstance(attributes, dict) else ())
                     if n.startswith("+")):
            key = ("attribute", kind, name)
            if key not in found:
                errors.append("{}attribute {} of a {} is in no Extension".format(label, name,
                                                                                 kind))
            else:
                check(found[key], attributes[name], "{}{}: ".format(label, name))
    return errors
