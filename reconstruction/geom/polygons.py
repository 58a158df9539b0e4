"""The polygons of a geometry: one home for every stage.

Overlays, ``make_valid`` and GRASS maps hand back Polygons, MultiPolygons
and GeometryCollections (a collection may hold lines and points beside its
areas, and collections inside collections). Every stage wants the same
thing from them: the non-empty Polygon parts, in order
(:func:`polygon_parts`), the largest one (:func:`largest_polygon`), or the
valid parts with area of many geometries and the index of the geometry each
came from (:func:`explode`). They are written with shapely 2's
``get_parts(return_index=True)``: one call per level of nesting for any
number of geometries.
"""

import numpy as np
import shapely
from shapely.geometry import Polygon

_POLYGON = 3  # shapely.GeometryType.POLYGON
_MULTIPART = 4  # type ids from here on (multi-points, -lines, -polygons, collections) have parts


def _parts(geometries):
    """The non-empty Polygon parts of an array of geometries and the index of each one's source.

    Collections are opened level by level with ``get_parts``, which keeps the
    order of its input: the parts come in depth-first order, each geometry's
    parts together. None, empty geometries, points and lines give nothing.
    """
    index = np.arange(len(geometries))
    types = shapely.get_type_id(geometries)
    while (types >= _MULTIPART).any():
        geometries, sub = shapely.get_parts(geometries, return_index=True)
        index = index[sub]
        types = shapely.get_type_id(geometries)
    keep = types == _POLYGON
    keep[keep] = ~shapely.is_empty(geometries[keep])
    return geometries[keep], index[keep]


def polygon_parts(geometry, return_index=False):
    """The non-empty Polygon parts of one geometry (a list), or of many (an array).

    Parts of collections inside collections are found too, depth first;
    lines, points, None and empty parts are left out. For an array (or list)
    of geometries, ``return_index=True`` also gives, for each part, the index
    of the geometry it came from.
    """
    if geometry is not None and not isinstance(geometry, shapely.Geometry):
        array = np.empty(len(geometry), dtype=object)
        array[:] = list(geometry)
        parts, index = _parts(array)
        return (parts, index) if return_index else parts
    if geometry is None or geometry.is_empty:
        return []
    if geometry.geom_type == "Polygon":
        return [geometry]  # the common case, without a copy
    # one geometry: walking ``.geoms`` takes 1 us for a one-part MultiPolygon
    # (the way GRASS areas arrive), ``get_parts`` 4.6 us and the array path 11 us
    # (measured on the 616 Brussels 1924 plots); the subdivision asks this for
    # every plot and footprint
    out = []
    for part in getattr(geometry, "geoms", ()):
        out.extend(polygon_parts(part))
    return out


def largest_polygon(geometry):
    """The largest Polygon part of a geometry (the first of equal ones), None when it has none."""
    parts = polygon_parts(geometry)
    if len(parts) <= 1:
        return parts[0] if parts else None
    return parts[int(np.argmax(shapely.area(parts)))]


def clean_polygon(polygon, tolerance=1e-6):
    """``polygon`` without repeated and collinear vertices (within ``tolerance``), its
    holes kept 1 cm off its outline and each other; None when nothing valid remains."""
    if polygon is None or polygon.is_empty:
        return None
    cleaned = shapely.simplify(polygon, tolerance, preserve_topology=True)
    cleaned = largest_polygon(cleaned if cleaned.is_valid else shapely.make_valid(cleaned))
    if cleaned is not None and cleaned.interiors:
        # a hole touching the outline or another hole becomes one self-touching ring in
        # GRASS's topology, invalid once exported: shrink such holes 1 cm off (issue 13)
        holes = [Polygon(h) for h in cleaned.interiors]
        edges = [cleaned.exterior, *cleaned.interiors]
        kept = []
        for k, hole in enumerate(holes):
            if min(hole.distance(e) for j, e in enumerate(edges) if j != k + 1) < 0.01:
                shrunk = shapely.get_parts(shapely.buffer(hole, -0.01, join_style="mitre"))
                kept.extend(h for h in shrunk if h.geom_type == "Polygon" and not h.is_empty)
            else:
                kept.append(hole)
        cleaned = Polygon(cleaned.exterior, [h.exterior for h in kept])
    return shapely.orient_polygons(cleaned) if cleaned is not None else None


def _made_valid(geometries):
    """An object array of the geometries, invalid ones made valid, and which ones were."""
    array = np.empty(len(geometries), dtype=object)
    array[:] = list(geometries)
    present = ~shapely.is_missing(array)
    invalid = np.zeros(len(array), bool)
    invalid[present] = ~shapely.is_valid(array[present]) & ~shapely.is_empty(array[present])
    if invalid.any():
        array[invalid] = shapely.make_valid(array[invalid])
    return array, invalid


def explode(geometries):
    """The valid Polygon parts with area of many geometries, each with the index of its source.

    Invalid geometries are made valid first (``make_valid``). Returns
    ``(polygons, index)``: a list of Polygons and, for each, the index in
    ``geometries`` of the geometry it came from.
    """
    array, _ = _made_valid(geometries)
    parts, index = _parts(array)
    keep = shapely.area(parts) > 0
    return list(parts[keep]), [int(i) for i in index[keep]]


def repair(geometries):
    """Each geometry as one valid Polygon or MultiPolygon, or None when it has no area.

    Invalid geometries are made valid (``make_valid``); the parts with area
    of each are kept, several parts merged into one (``union_all``). Returns
    ``(geometries, repaired)``: a list with one geometry or None per input,
    and a boolean array telling which inputs were invalid.
    """
    array, invalid = _made_valid(geometries)
    parts, index = _parts(array)
    keep = shapely.area(parts) > 0
    groups = {}
    for part, i in zip(parts[keep], index[keep]):
        groups.setdefault(int(i), []).append(part)
    out = [None] * len(array)
    for i, group in groups.items():
        out[i] = group[0] if len(group) == 1 else shapely.union_all(group)
    return out, invalid



def same_outline(a, b, tolerance=1e-6):
    """Whether polygons ``a`` and ``b`` have the same outline within ``tolerance``: as
    many holes, and no point of either's boundary farther than ``tolerance`` from the
    other's (their Hausdorff distance; whatever vertex the rings start at, whichever
    way they turn). A vertex on a straight edge (a neighbour's vertex inserted into a
    shared wall, as GRASS's topology and
    :func:`~reconstruction.subdivide.noding.node_footprints` do) changes nothing; nor
    does a run of vertices each nearly on the line through its neighbours, which a
    comparison corner by corner (dropping the vertices within the tolerance of that
    line, one at a time) could reduce to different corners in the two copies (a
    footprint of the synthetic town read back from its model: 0.4 mm apart, judged
    another outline)."""
    if a is None or b is None:
        return a is b
    if len(a.interiors) != len(b.interiors):
        return False
    return bool(shapely.hausdorff_distance(a.boundary, b.boundary) <= tolerance)


def stair_step(polygons, share=0.3, least=50):
    """The cell size of outlines vectorised from a raster, or None.

    The outline of a patch of raster cells (r.to.vect) is a staircase whose
    segments are whole numbers of cells: the commonest segment length, when
    at least ``share`` of the ``least`` or more segments of all rings have it,
    is the cell size. A plot drawn by hand has no such length."""
    rings = [r for p in polygons if p is not None
             for r in [p.exterior, *p.interiors]] if polygons else []
    if not rings:
        return None
    xy, index = shapely.get_coordinates(rings, return_index=True)
    same = index[1:] == index[:-1]
    lengths = np.hypot(*np.diff(xy, axis=0)[same].T)
    if len(lengths) < least:
        return None
    values, counts = np.unique(np.round(lengths, 4), return_counts=True)
    k = int(np.argmax(counts))
    return float(values[k]) if values[k] > 0 and counts[k] >= share * len(lengths) else None


def _unstair(xy, step):
    """One pass over an open ring ``xy``: each vertex of a stair (its turn the other way
    from a neighbour's, one of its segments at most 1.5 ``step`` long) replaced by the
    midpoints of its two segments."""
    prev, nxt = np.roll(xy, 1, axis=0), np.roll(xy, -1, axis=0)
    a, b = xy - prev, nxt - xy
    turn = np.sign(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0])
    zig = (turn != np.roll(turn, 1)) | (turn != np.roll(turn, -1))
    short = np.minimum(np.hypot(*a.T), np.hypot(*b.T)) <= 1.5 * step
    stair = zig & short
    out = np.repeat(xy, np.where(stair, 2, 1), axis=0)
    first = np.cumsum(np.where(stair, 2, 1)) - np.where(stair, 2, 1)
    out[first[stair]] = (prev[stair] + xy[stair]) / 2
    out[first[stair] + 1] = (xy[stair] + nxt[stair]) / 2
    keep = np.any(np.abs(out - np.roll(out, 1, axis=0)) > 1e-9, axis=1)
    return out[keep]


def _corners(xy):
    """An open ring without its vertices on a straight run (a run of whole cells is one
    segment, as r.to.vect draws it)."""
    a, b = xy - np.roll(xy, 1, axis=0), np.roll(xy, -1, axis=0) - xy
    cross = np.abs(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0])
    bend = cross > 1e-9 * np.hypot(*a.T) * np.hypot(*b.T)
    return xy[bend] if bend.sum() >= 3 else xy


def centre_line(polygon, step, passes=3):
    """``polygon`` with the stairs of its raster cells (``step`` their size, see
    :func:`stair_step`) replaced by their centre line: each pass cuts every stair
    corner at the midpoints of its segments (as much area cut at the outer corners as
    filled at the inner ones); corners between longer segments stay. The outline of
    the cells runs half a step outside an oblique edge at its outer corners, where an
    alpha shape of its points lies (issue 32); the centre line is the edge. The
    polygon unchanged where the result is not one valid polygon."""
    if polygon is None or not step:
        return polygon

    def ring(coords):
        xy = _corners(np.asarray(coords, dtype=float)[:-1, :2])
        for _ in range(passes):
            if len(xy) < 4:
                break
            xy = _unstair(xy, step)
        return xy

    try:
        smooth = shapely.Polygon(ring(polygon.exterior.coords),
                                 [ring(h.coords) for h in polygon.interiors])
    except (ValueError, shapely.errors.GEOSException):
        return polygon
    return smooth if smooth.is_valid and smooth.area > 0 else polygon


def overlay(operation, a, b, grid_size=1e-6):
    """A shapely overlay (``operation``: ``shapely.intersection``, ``difference``,
    ...) that falls back to snap-rounding on a grid of ``grid_size`` map units when
    GEOS's floating one fails (``TopologyException``, "Unable to determine overlay
    result geometry dimension" on nearly degenerate input)."""
    try:
        return operation(a, b)
    except shapely.errors.GEOSException:
        return operation(a, b, grid_size=grid_size)


def cells_inside(geometries, west, north, cell, shape):
    """Boolean raster of ``shape`` (rows, cols; row 0 at the north) whose cells
    ``cell`` (width, height) wide from the corner (``west``, ``north``) have their
    centres inside one of ``geometries`` (each tested in the cells of its box only;
    None and empty ones skipped)."""
    rows, cols = shape
    mask = np.zeros((rows, cols), dtype=bool)
    for geom in geometries:
        if geom is None or geom.is_empty:
            continue
        minx, miny, maxx, maxy = geom.bounds
        c0 = max(int(np.floor((minx - west) / cell[0])), 0)
        c1 = min(int(np.ceil((maxx - west) / cell[0])), cols)
        r0 = max(int(np.floor((north - maxy) / cell[1])), 0)
        r1 = min(int(np.ceil((north - miny) / cell[1])), rows)
        if c0 >= c1 or r0 >= r1:
            continue
        xs = west + (np.arange(c0, c1) + 0.5) * cell[0]
        ys = north - (np.arange(r0, r1) + 0.5) * cell[1]
        mask[r0:r1, c0:c1] |= shapely.contains_xy(geom, xs[None, :], ys[:, None])
    return mask
