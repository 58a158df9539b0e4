"""What makes an existing city model, or one of its buildings, unusable (issue 33).

A model read from a file may be broken in ways that the JSON parser does
not see and that would otherwise give silently wrong geometry or a
traceback far from the cause:

- :func:`check_transform`: a ``transform`` whose scale is not three
  positive numbers (a scale of 0 puts every vertex at the translation) or
  whose translation is not three numbers, and vertices that are not
  integers under a transform: the whole model is refused
  (:class:`~reconstruction.core.errors.InputError`);
- :func:`broken_buildings`: per building (a top-level object with its
  children), a child that is not in the model, a geometry that is not an
  object or has no ``boundaries``, boundaries nested to the wrong depth,
  vertex indices that are not integers (``1.5``, ``null``, ``true``), are
  negative, or point past the building's vertices (in CityJSONSeq: past
  its own feature's, which would take the next feature's), and a building
  with no geometry at all. Such a building is left out of the model's
  matchable buildings (its footprint is then generated) and named with
  its problem, so that one broken object of a large model costs that
  building only.

The check is made in bulk: the boundaries of every building are written
by orjson once (a text of digits, brackets and commas only when every
index is a non-negative integer) and walked once
(:func:`reconstruction.cityjson.geometry.layout`); only the buildings that
fail are walked one by one for the words of their problem.
"""

import json
import math

import numpy as np

from ..core.errors import InputError
from . import geometry as citygeometry
from . import versions
from .copied import COPYABLE

#: the bytes of the JSON text of nested lists of non-negative integers
_PLAIN = b"0123456789[],"
#: geometries written by orjson at a time
_CHUNK = 2000


def _numbers(values, size=3):
    return (isinstance(values, list) and len(values) == size and all(
        isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)
        for v in values))


def check_transform(path, transform):
    """InputError unless ``transform`` (the document's, or None) has a scale
    of three positive numbers and a translation of three numbers."""
    if transform is None:
        return
    if not isinstance(transform, dict):
        raise InputError("'{}': its transform is not an object".format(path))
    scale, translate = transform.get("scale"), transform.get("translate")
    if not _numbers(scale) or min(scale) <= 0:
        raise InputError("'{}': the scale of its transform must be three positive numbers, not "
                         "{}: its vertices would all be put on one point".format(
                             path, json.dumps(scale)))
    if not _numbers(translate):
        raise InputError("'{}': the translate of its transform must be three numbers, not "
                         "{}".format(path, json.dumps(translate)))


def vertices_array(path, vertices, transformed):
    """The (N, 3) array of a document's ``vertices`` (int64 under a
    transform, else float); InputError for anything but x, y, z numbers,
    and for fractions under a transform (they would be cut to integers)."""
    if not vertices:
        return np.zeros((0, 3), dtype=np.int64)
    try:
        array = np.asarray(vertices)
    except ValueError:
        array = None                            # rows of different lengths
    if array is None or array.ndim != 2 or array.shape[1] != 3:
        raise InputError("'{}' is not a CityJSON file or CityJSONSeq file (its vertices are not "
                         "x, y, z triples)".format(path))
    if array.dtype.kind not in "iuf" or (array.dtype.kind == "f" and
                                         not np.isfinite(array).all()):
        raise InputError("'{}': its vertices hold something else than numbers".format(path))
    if not transformed:
        return array.astype(float, copy=False)
    if array.dtype.kind == "f":
        if not np.array_equal(array, np.round(array)):
            row = int(np.nonzero(array != np.round(array))[0][0])
            raise InputError("'{}': vertex {} {} is not integer, as the vertices of a model "
                             "with a transform must be".format(path, row,
                                                               json.dumps(vertices[row])))
    return array.astype(np.int64, copy=False)


def _tree(objects, building):
    """The ids of a building's tree (itself first) and the first problem of
    its children (None)."""
    out, seen, k = [building], {building}, 0
    while k < len(out):
        children = objects[out[k]].get("children") or []
        if not isinstance(children, list):
            return out, "<{}> has children that are not a list".format(out[k])
        for child in children:
            if not isinstance(child, str) or not isinstance(objects.get(child), dict):
                return out, "its child {} is not in the model".format(json.dumps(child))
            if child not in seen:
                seen.add(child)
                out.append(child)
        k += 1
    return out, None


def _geometry_problem(oid, obj):
    """The first problem of the geometry list (or the attributes) of one object (None)."""
    if not isinstance(obj.get("attributes") or {}, dict):
        return "<{}> has attributes that are not an object".format(oid)
    geometries = obj.get("geometry", [])
    if not isinstance(geometries, list):
        return "<{}> has a geometry that is not a list".format(oid)
    for k, g in enumerate(geometries):
        if not isinstance(g, dict):
            return "<{}>, geometry {}: not an object".format(oid, k)
        if not isinstance(g.get("type"), str):
            return "<{}>, geometry {}: its type is not a text".format(oid, k)
        if g.get("type") in citygeometry.DEPTH and not isinstance(g.get("boundaries"), list):
            return "<{}>, geometry {} ({}): no boundaries".format(oid, k, g.get("type"))
    return None


def _index_problem(node, depth, count):
    """The first problem of the vertex indices of ``node`` (boundaries
    ``depth`` list levels above the leaves) with ``count`` vertices (None)."""
    if not isinstance(node, list):
        return "{} where a list is expected".format(json.dumps(node))
    if depth == 0:
        for v in node:
            if isinstance(v, bool) or not isinstance(v, int):
                return "vertex index {} is not an integer".format(json.dumps(v))
            if v < 0:
                return "vertex index {} is negative".format(v)
            if v >= count:
                return "vertex index {} is past its {} vertices".format(v, count)
        return None
    for child in node:
        problem = _index_problem(child, depth - 1, count)
        if problem is not None:
            return problem
    return None


def _indices_problem(objects, tree, count):
    """The first problem of the vertex indices of a building's tree (None)."""
    for oid in tree:
        for k, g in enumerate(objects[oid].get("geometry", ())):
            depth = citygeometry.DEPTH.get(g.get("type"))
            if depth is None:
                continue
            problem = _index_problem(g["boundaries"], depth, count)
            if problem is not None:
                return "<{}>, geometry {} ({}, lod {}): {}".format(
                    oid, k, g["type"], g.get("lod"), problem)
    return None


def _plain(geometries):
    """Whether every index of ``geometries``' boundaries is a non-negative
    integer and their lists are nested as their types say, with the
    :class:`~reconstruction.cityjson.geometry.Layout` then (else None)."""
    import orjson

    for a in range(0, len(geometries), _CHUNK):
        raw = orjson.dumps([g["boundaries"] for g in geometries[a:a + _CHUNK]])
        if raw.translate(None, _PLAIN):
            return None
    try:
        return citygeometry.layout(geometries)
    except (TypeError, ValueError):
        return None                     # an index where a list is, or a list where an index is


def broken_buildings(objects, buildings, counts):
    """What is wrong with each building that cannot be used: a dict, id ->
    its problem, of the ``buildings`` (top-level object ids) that are
    broken (see the module's docstring). ``counts``: per building, the
    number of vertices its indices may point to (its feature's in
    CityJSONSeq, the model's in one file)."""
    problems, trees = {}, {}
    geometries, owner = [], []
    # a building of a model over time has its geometry in its versions (city objects
    # of their own, checked as buildings are)
    versioned = {o.get("versionOf") for o in objects.values() if isinstance(o, dict)
                 and o.get("type") == versions.VERSION and isinstance(o.get("versionOf"), str)}
    for b, oid in enumerate(buildings):
        tree, problem = _tree(objects, oid)
        for o in tree:
            problem = problem or _geometry_problem(o, objects[o])
        if problem is None:
            mine = [g for o in tree for g in objects[o].get("geometry", ())
                    if g.get("type") in citygeometry.DEPTH]
            if not any(g["type"] in COPYABLE for g in mine) and oid not in versioned:
                problem = "it has no geometry"
        if problem is not None:
            problems[oid] = problem
            continue
        trees[b] = tree
        geometries.extend(mine)
        owner.extend([b] * len(mine))
    if not geometries:
        return problems
    lay = _plain(geometries)
    counts = np.asarray(counts, dtype=np.int64)
    if lay is None:
        suspects = sorted(trees)
    else:
        entry_owner = np.asarray(owner, dtype=np.int64)[lay.entry_geometry]
        suspects = np.unique(entry_owner[lay.flat >= counts[entry_owner]]).tolist()
    for b in suspects:
        problem = _indices_problem(objects, trees[b], int(counts[b]))
        if problem is not None:
            problems[buildings[b]] = problem
    return problems
