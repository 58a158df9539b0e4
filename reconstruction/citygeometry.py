"""The vertex indices of CityJSON geometries, walked and rewritten in bulk.

A CityJSON geometry's ``boundaries`` nest lists of vertex indices to a depth
that depends on its type (a Solid: shells, surfaces, rings, indices). The
innermost lists (the rings, or the points of a MultiPoint) are the
*leaves*. Reading every index of many geometries, and writing them back
re-indexed, goes through one flat numpy array: the lists are only taken
apart and put together again level by level, never index by index in
Python.
"""

import itertools

import numpy as np

#: list levels above the leaves, by geometry type (a GeometryInstance's
#: boundaries are the one vertex where its template is put)
DEPTH = {"GeometryInstance": 0, "MultiPoint": 0, "MultiLineString": 1, "MultiSurface": 2, "CompositeSurface": 2,
         "Solid": 3, "MultiSolid": 4, "CompositeSolid": 4}
#: list levels above the surfaces (surfaces = lists of rings), by surface geometry type
SURFACE_DEPTH = {"MultiSurface": 0, "CompositeSurface": 0, "Solid": 1, "MultiSolid": 2,
                 "CompositeSolid": 2}


def lod_value(lod):
    """A geometry's ``lod`` ("2.2", "0", 1) as a number, for comparisons (None -> -1)."""
    try:
        return float(lod)
    except (TypeError, ValueError):
        return -1.0


def parts(nested, depth):
    """The items ``depth`` list levels below ``nested`` (a list of trees), in order."""
    level = nested
    for _ in range(depth):
        level = list(itertools.chain.from_iterable(level))
    return level


def flat_indices(leaves):
    """The indices of many leaves as one int64 array, and the offsets of each leaf."""
    sizes = np.fromiter(map(len, leaves), dtype=np.int64, count=len(leaves))
    offsets = np.zeros(len(leaves) + 1, dtype=np.int64)
    np.cumsum(sizes, out=offsets[1:])
    flat = np.fromiter(itertools.chain.from_iterable(leaves), dtype=np.int64,
                       count=int(offsets[-1]))
    return flat, offsets


def _regroup(items, counts):
    """``items`` cut into consecutive lists of ``counts`` items."""
    it = iter(items)
    return [list(itertools.islice(it, n)) for n in counts]


def leaves_of(geometries):
    """The leaves of many geometries (GeometryInstances and unknown types have none)."""
    out = []
    for depth, group in _by_depth(geometries).items():
        out.extend(parts([g["boundaries"] for _, g in group], depth))
    return out


def _by_depth(geometries):
    groups = {}
    for k, g in enumerate(geometries):
        depth = DEPTH.get(g.get("type"))
        if depth is not None:
            groups.setdefault(depth, []).append((k, g))
    return groups


def reindex(geometries, mapping, shift=None):
    """Copies of ``geometries`` with new vertex indices: ``mapping(flat)``.

    ``mapping`` takes the flat int64 array of every index of every geometry
    (plus ``shift[k]``, an offset per geometry, where given) and returns the
    new indices, same length (or any array of one row per entry: the rows
    then stand in the leaves); the order of the entries is that of
    :func:`leaves_of`. The input geometries are not changed; other members
    (``semantics``, ``lod``...) are shared with them.
    """
    geometries = list(geometries)
    groups = _by_depth(geometries)
    order, leaves, shapes, owner = [], [], [], []
    for depth, group in groups.items():
        top = [g["boundaries"] for _, g in group]
        counts, level = [], top
        for _ in range(depth):
            counts.append([len(p) for p in level])
            level = list(itertools.chain.from_iterable(level))
        order.append(group)
        shapes.append((len(leaves), len(level), counts))
        leaves.extend(level)
        if shift is not None:
            per_top = np.array([k for k, _ in group], dtype=np.int64)
            for c in counts:
                per_top = np.repeat(per_top, c)
            owner.append(per_top)
    flat, offsets = flat_indices(leaves)
    if shift is not None and len(flat):
        leaf_owner = np.concatenate(owner)
        flat = flat + np.repeat(np.asarray(shift, dtype=np.int64)[leaf_owner], np.diff(offsets))
    new = np.asarray(mapping(flat)).tolist()
    new_leaves = [new[a:b] for a, b in zip(offsets[:-1].tolist(), offsets[1:].tolist())]
    out = list(geometries)
    for group, (start, n, counts) in zip(order, shapes):
        level = new_leaves[start:start + n]
        for c in reversed(counts):
            level = _regroup(level, c)
        for (k, g), b in zip(group, level):
            copy = dict(g)
            copy["boundaries"] = b
            out[k] = copy
    return out


def resolved(document, digits=6):
    """The city objects of a CityJSON document (dict) with the coordinates
    of their vertices (rounded to ``digits``) in place of the indices: two
    documents with the same objects and vertex coordinates give equal
    results, whatever their vertex order or transform."""
    t = document.get("transform") or {"scale": [1, 1, 1], "translate": [0, 0, 0]}
    vertices = np.asarray(document.get("vertices") or np.zeros((0, 3)), dtype=float)
    xyz = np.round(vertices.reshape(-1, 3) * t["scale"] + t["translate"], digits)
    geoms, where = [], []
    objects = {}
    for oid, obj in document.get("CityObjects", {}).items():
        objects[oid] = dict(obj)
        for k, g in enumerate(obj.get("geometry", ())):
            geoms.append(g)
            where.append((oid, k))
        if "geometry" in obj:
            objects[oid]["geometry"] = list(obj["geometry"])
    for (oid, k), g in zip(where, reindex(geoms, lambda flat: xyz[flat]) if geoms else []):
        objects[oid]["geometry"][k] = g
    return objects


def surfaces_of(geometry):
    """The surfaces (lists of rings, exterior first) of a surface geometry and
    their semantic values (None where it has none), in order; ([], []) for
    other types."""
    depth = SURFACE_DEPTH.get(geometry.get("type"))
    if depth is None:
        return [], []
    surfaces = parts([geometry["boundaries"]], depth + 1)
    sem = geometry.get("semantics")
    if sem is None or sem.get("values") is None:
        return surfaces, [None] * len(surfaces)
    values = parts(sem["values"], depth)
    if len(values) != len(surfaces):
        return surfaces, [None] * len(surfaces)
    return surfaces, values


def surface_types(geometry):
    """The semantic type ("RoofSurface", ...) of every surface of a geometry (None where unknown)."""
    surfaces, values = surfaces_of(geometry)
    kinds = [s.get("type") for s in (geometry.get("semantics") or {}).get("surfaces", [])]
    return surfaces, [kinds[v] if v is not None and 0 <= v < len(kinds) else None for v in values]


def drop_collapsed(geometry):
    """A copy of a geometry without repeated consecutive vertices in its rings,
    without the rings left with fewer than three vertices, and without the
    surfaces whose exterior ring collapsed (their semantic values go with
    them); None when nothing is left. Returns ``(geometry, surfaces_dropped)``.

    Only surface geometries are cleaned (points and lines are returned as they are).
    """
    depth = SURFACE_DEPTH.get(geometry.get("type"))
    if depth is None:
        return geometry, 0
    sem = geometry.get("semantics")
    values = sem.get("values") if sem else None
    dropped = [0]

    def ring(r):
        out = [v for k, v in enumerate(r) if v != r[k - 1]] if len(r) > 1 else list(r)
        return out if len(out) >= 3 else None

    def clean(node, vals, level):
        """``node`` at surface depth ``level`` with its semantic values ``vals``."""
        if level == 0:
            keep_s, keep_v = [], []
            for k, surface in enumerate(node):
                rings = [ring(r) for r in surface]
                if rings[0] is None:
                    dropped[0] += 1
                    continue
                keep_s.append([r for r in rings if r is not None])
                if vals is not None:
                    keep_v.append(vals[k])
            return keep_s, keep_v
        keep_s, keep_v = [], []
        for k, sub in enumerate(node):
            s, v = clean(sub, None if vals is None else vals[k], level - 1)
            if s:
                keep_s.append(s)
                keep_v.append(v)
        return keep_s, keep_v

    boundaries, new_values = clean(geometry["boundaries"], values, depth)
    if not boundaries:
        return None, dropped[0]
    out = dict(geometry)
    out["boundaries"] = boundaries
    if values is not None:
        out["semantics"] = dict(sem, values=new_values)
    return out, dropped[0]
