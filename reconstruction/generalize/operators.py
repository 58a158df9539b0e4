"""Generalisation of raw building plots into simple plot polygons.

Pure functions over shapely 2 geometries and numpy arrays (no GRASS), after
Morlighem (2021, Sections 3.2.2-3.2.3):

- ``alpha``: the alpha-shape operator of Arteaga (2013), on the centre line of
  a raster outline's stairs (:func:`_centre_lines`): points are sampled in the
  plot (``regular`` grid, ``hexagonal`` grid, ``stratified`` (one
  jittered point per grid cell) or ``random``, each with the densified
  boundary), their alpha shape is the union of the Delaunay triangles whose
  circumradius is at most alpha (scipy's Delaunay); its boundary is cleaned
  to the largest cycle (dangling edges and pinched-off pieces dropped) and
  stripped of collinear points. Holes wider than the alpha disk survive, so
  courtyard plots keep their courtyard (the thesis lost such plots);
- ``lines``: the buffered-lines generalisation of Commandeur (2012): the
  segments of all rings become lines ranked by length; shorter segments are
  merged into a line while all their end points lie within ``distance`` of
  it and their direction within ``angle``; each final line is the
  orthogonal least-squares line of its members (:class:`_LineSet`);
  consecutive lines along each ring
  are intersected back into a polygon (nearly parallel ones joined by a
  short step). Holes and concave shapes are kept; plots that touch are
  generalised together, so a shared edge becomes one line and stays shared.
  ``orthogonal=True`` turns lines close to the dominant direction (or
  perpendicular to it) exactly parallel or perpendicular;
- ``simplify``: topology-preserving simplification (GEOS coverage
  simplification, Visvalingam-Whyatt, which keeps shared edges shared; plain
  topology-preserving Douglas-Peucker when the plots are not a coverage);
- ``douglas``: plain Douglas-Peucker (``shapely.simplify``).
- ``fit``: each edge moved onto the boundary line the scanned map draws
  (:mod:`reconstruction.generalize.fitting`; a plot whose fit is not sound
  stays as it was).

:func:`generalize_plots` chains the steps and never loses a plot: when a step
fails or gives an invalid or collapsed polygon for a plot, the next sensible
method is tried for that plot only (another sampling, a smaller distance,
Douglas-Peucker, topology-preserving simplification, the plot unchanged),
and the method used is recorded per plot. Overlaps created between plots are
removed at the end (GEOS coverage cleaning), so the output is a polygon
coverage: plots may share boundaries, never overlap.
"""

import math
from dataclasses import dataclass
from typing import Optional

import numpy as np
import shapely
from shapely.geometry import Polygon

from ..geom.overlaps import OverlapRule, resolve_overlaps

# one home for the polygons of a geometry; both names stay importable from here
from ..geom.polygons import centre_line, clean_polygon, overlay, stair_step
from ..geom.polygons import explode as explode_plots, largest_polygon  # noqa: F401
from . import fitting
from .lines import buffered_lines

# Tuning (checked on the thesis's Delft 1961 plots): the alpha outline is
# simplified by ALPHA_TOL x the boundary spacing; the interior is sampled every
# INNER x alpha (the boundary every alpha / 4): denser inner points change
# nothing but the run time. The buffered lines' own: lines.SHIFT, lines.CLEAN.
ALPHA_TOL = 0.1
INNER = 0.5
#: the alpha shape may close notches narrower than 2 x CLOSING x alpha, no more
#: (see :func:`alpha_generalize`)
CLOSING = 0.25
#: what the alpha shape adds is a dent it closes, not a corner it fills, when
#: its area is at least NOTCH x the square of its opening
NOTCH = 0.5
#: ... or when its walls cover at least DENT_WALLS of the edges they lie on
DENT_WALLS = 0.75
#: ... and it is not a yard: wider than 2 x YARD x CLOSING x alpha everywhere
#: and, unless enclosed, deeper than YARD_DEPTH x its opening (a courtyard, a
#: garden between a plot's wings; not a square symbol printed on a plot's edge)
YARD, YARD_DEPTH = 1.5, 2.0
#: the buffered lines of a plot overlap it by at least this IoU, or the plot
#: takes the next method (lines half as far apart, ...): lines 5 m apart at any
#: angle (the thesis's parameters) made triangles (IoU 0.6-0.7) of plots of
#: 10 x 10 m. At 0.8 a plot of the synthetic town over time took another
#: method on one map than on the next, and its buildings were cut anew
LINES_IOU = 0.75
#: On maps that draw the outline inside the plots (outline="inside"), the fit
#: step also fits the raw cells' outline, simplified (douglas): where the map
#: draws its line along at least SUPPORT_GAIN more of that outline's perimeter
#: (fitting.outline_support) and its area is within SUPPORT_AREA of the raw
#: cells', the plot takes it: the generalisation had gone astray (a wedge's
#: tip cut short into a triangle, seed 1: IoU 0.84 -> 0.96; a plot made a
#: triangle half as large again as its cells, seed 3: 0.67 -> 0.95). Only there
#: does the support count nothing but the plots' own stroke; on Delft's centred
#: lines it took five plots back to outlines of 9-43 vertices from 3-5, and the
#: turning distance rose (0.156 -> 0.169)
SUPPORT_GAIN, SUPPORT_AREA = 0.1, 0.2
#: ... and a corner the generalisation cut off where the map draws none
#: (fitting.restore_corners) is restored when the outline changes area by less
#: than CORNER_AREA and the map supports it no less (a courtyard's corner, the
#: inside corner of a U: seed 1 IoU 0.972 -> 0.992 and 0.953 -> 0.976)
CORNER_AREA = 0.1

METHODS = ("alpha", "lines", "simplify", "douglas", "fit")
SAMPLINGS = ("regular", "hexagonal", "stratified", "random")


@dataclass(frozen=True)
class Generalization:
    """Result of :func:`generalize_plots`.

    plots: list of shapely Polygons, one per input plot, in input order;
    methods: per plot, the methods used joined by ``+`` (e.g. ``alpha/regular+lines``);
    steps: list of ``(step name, list of polygons)`` after each method step
    (the first is ``("raw", inputs)``), for the per-step metrics;
    fallbacks: dict step -> number of plots that needed a fallback there (for
    ``fit``: the plots kept as they were);
    outline_fit: the :class:`~reconstruction.generalize.fitting.OutlineFit` of
    the fit step, None without one.
    """

    plots: list
    methods: list
    steps: list
    fallbacks: dict
    outline_fit: Optional[fitting.OutlineFit] = None


# ---------------------------------------------------------------------------
# Helpers
# ---------------------------------------------------------------------------

def acceptable(new, old, min_share=0.6, max_growth=1.6, min_iou=0.0):
    """Is ``new`` a sound generalisation of ``old``?

    One valid polygon, covering at least ``min_share`` of the old area, not
    larger than ``max_growth`` times it, and overlapping it by at least
    ``min_iou`` (intersection over union).
    """
    if new is None or new.is_empty or new.geom_type != "Polygon" or not new.is_valid:
        return False
    if new.area <= 0 or new.area > max_growth * old.area:
        return False
    common = shapely.intersection(new, old).area
    return common >= min_share * old.area and common >= min_iou * (new.area + old.area - common)


# ---------------------------------------------------------------------------
# Alpha-shape step (Arteaga 2013)
# ---------------------------------------------------------------------------

def sample_points(polygon, spacing, sampling="regular", rng=None, inner_spacing=None):
    """Points sampled in a polygon (interior by ``sampling``, plus its boundary).

    The boundary (all rings) is densified to ``spacing`` so the alpha shape
    follows the outline; the interior gets, at ``inner_spacing`` (default
    ``spacing``), a regular square grid, a hexagonal grid, one random point
    per grid cell (stratified) or uniform random points of the same density.
    """
    if sampling not in SAMPLINGS:
        raise ValueError("unknown sampling '{}'".format(sampling))
    rng = rng if rng is not None else np.random.default_rng(0)
    step = inner_spacing or spacing
    minx, miny, maxx, maxy = polygon.bounds
    if sampling == "hexagonal":
        ys = np.arange(miny + step / 2, maxy, step * math.sqrt(3) / 2)
        rows = []
        for k, y in enumerate(ys):
            xs = np.arange(minx + (step / 2) * (1 + k % 2), maxx, step)
            rows.append(np.column_stack([xs, np.full(len(xs), y)]))
        inner = np.concatenate(rows) if rows else np.empty((0, 2))
    elif sampling == "random":
        n = max(int((maxx - minx) * (maxy - miny) / step ** 2), 1)
        inner = np.column_stack([rng.uniform(minx, maxx, n), rng.uniform(miny, maxy, n)])
    else:
        gx, gy = np.meshgrid(np.arange(minx + step / 2, maxx, step),
                             np.arange(miny + step / 2, maxy, step))
        inner = np.column_stack([gx.ravel(), gy.ravel()])
        if sampling == "stratified":
            inner = inner + rng.uniform(-step / 2, step / 2, inner.shape)
    inner = inner.reshape(-1, 2)
    inner = inner[shapely.contains_xy(polygon, inner[:, 0], inner[:, 1])]
    edge = shapely.get_coordinates(shapely.segmentize(polygon.boundary, spacing))
    return np.unique(np.concatenate([edge, inner]), axis=0)


def alpha_shape(points, alpha):
    """Union of the Delaunay triangles of ``points`` with circumradius <= alpha."""
    from scipy.spatial import Delaunay, QhullError

    points = np.asarray(points, dtype=float)
    if len(points) < 3:
        return Polygon()
    origin = points.mean(axis=0)
    local = points - origin
    try:
        tri = Delaunay(local)
    except QhullError:
        return Polygon()
    a, b, c = (local[tri.simplices[:, k]] for k in range(3))
    la = np.hypot(*(b - c).T)
    lb = np.hypot(*(a - c).T)
    lc = np.hypot(*(a - b).T)
    area2 = np.abs((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))
    with np.errstate(divide="ignore", invalid="ignore"):
        radius = la * lb * lc / (2 * area2)
    keep = (area2 > 1e-12) & (radius <= alpha)
    if not keep.any():
        return Polygon()
    simplices = tri.simplices[keep]
    rings = (points[simplices])
    triangles = shapely.polygons(np.concatenate([rings, rings[:, :1]], axis=1))
    return shapely.coverage_union_all(triangles)


def _without_corner_fills(shape, polygon, reach):
    """``shape`` (an alpha shape of ``polygon``) without what it adds in the polygon's
    concave corners and yards.

    What the shape adds beyond the polygon closed by ``reach`` (mitred) is, piece
    by piece, a corner fill or a yard, dropped, or a dent, kept (the alpha shape
    closes it):

    - a corner fill spans a concave corner between two edges that go on beyond
      it (its walls cover less than DENT_WALLS of the edges they lie on, the
      outline simplified by reach / 4) and is shallow (its area below NOTCH x
      the square of the length it spans, its opening: at most a quarter for a
      triangle in a right-angled corner);
    - a yard is wider than 2 x YARD x ``reach`` everywhere and enclosed or
      deeper than YARD_DEPTH x its opening (a courtyard, the garden between a
      plot's wings);
    - a dent is the rest: deep (a notch: the gap of a removed label, a square
      symbol printed on the plot's edge) or between whole edges (a V the
      classification cut into a plot's front: drawn on one map of a block and
      not on the next).
    """
    closed = polygon.buffer(reach, join_style="mitre").buffer(-reach, join_style="mitre")
    beyond = shapely.get_parts(shapely.difference(shape, closed))
    if not len(beyond):
        return shape
    rim = shapely.buffer(closed.boundary, 1e-6)
    on_rim = overlay(shapely.intersection, shapely.boundary(beyond), rim)
    opening = shapely.length(beyond) - shapely.length(on_rim)
    area, span2 = shapely.area(beyond), np.maximum(opening, 0) ** 2
    shallow = area < NOTCH * span2
    dropped = (~shapely.is_empty(shapely.buffer(beyond, -YARD * reach, join_style="mitre"))
               & (area >= YARD_DEPTH * span2))                     # the yards
    low = np.flatnonzero(shallow & ~dropped)
    if len(low):
        thin = reach / 4
        walls = _walls(beyond[low], on_rim[low], thin)
        dropped[low] = _wall_shares(walls, _edges(closed, thin), thin) < DENT_WALLS
    if not dropped.any():
        return shape
    return overlay(shapely.difference, shape, shapely.union_all(beyond[dropped]))


def _walls(pieces, on_rim, thin):
    """The boundary of each of ``pieces`` on the polygon (``on_rim``: the part of
    its boundary on the polygon's outline) where the piece is thicker than
    ``2 x thin``: the alpha shape's slivers along the outline, joined to a piece,
    are not its walls."""
    thick = shapely.buffer(shapely.buffer(pieces, -thin, join_style="mitre"), 1.5 * thin)
    return overlay(shapely.intersection, on_rim, thick)


def _edges(polygon, tolerance):
    """The edges of ``polygon``'s rings, simplified by ``tolerance`` (LineStrings)."""
    rings = shapely.get_rings(shapely.get_parts(shapely.simplify(polygon, tolerance)))
    if not len(rings):
        return np.empty(0, dtype=object)
    ends = np.concatenate([np.stack([c[:-1], c[1:]], axis=1)
                           for c in (shapely.get_coordinates(r) for r in rings)])
    return shapely.linestrings(ends)


def _wall_shares(walls, edges, tolerance):
    """For each of ``walls`` (a piece's boundary on the polygon), how much of the
    ``edges`` (:func:`_edges`) it lies along, within ``tolerance``, it covers: 1 for
    a dent between whole edges, less for a corner, 0 along none. Only the edges
    near each wall are cut (an STRtree: a large plot on a fine grid has thousands)."""
    zones = shapely.buffer(walls, tolerance)
    if not len(edges):
        return np.zeros(len(walls))
    piece, edge = shapely.STRtree(edges).query(zones, predicate="intersects")
    shared = shapely.length(shapely.intersection(edges[edge], zones[piece]))
    along = shared > 2 * tolerance
    covered = np.bincount(piece[along], weights=shared[along], minlength=len(walls))
    total = np.bincount(piece[along], weights=shapely.length(edges[edge[along]]),
                        minlength=len(walls))
    return np.divide(covered, total, out=np.zeros(len(walls)), where=total > 0)


def alpha_generalize(polygon, alpha, sampling="regular", spacing=None, rng=None):
    """Alpha-shape generalisation of one plot (None when it fails).

    Samples points (see :func:`sample_points`, default spacing alpha / 4),
    takes their alpha shape, keeps the largest cycle with the holes wider
    than the alpha disk, and drops collinear vertices.

    The alpha shape closes notches (:func:`_without_corner_fills`), but it does
    not fill the plot's yards (courtyards and gardens at least 9 m wide with
    alpha 12) nor its concave corners. Alone it would: a Delaunay triangle
    across a right-angled corner has the corner's hypotenuse as its
    circumcircle's diameter, so with alpha 12 every inner corner of a
    courtyard or an L lost a triangle with legs up to 17 m (issue 32: on the
    thesis's raw Delft plots this step pushed the outline out by 0.12 m).
    """
    spacing = spacing or alpha / 4.0
    points = sample_points(polygon, spacing, sampling, rng, inner_spacing=alpha * INNER)
    shape = alpha_shape(points, alpha)
    main = largest_polygon(_without_corner_fills(shape, polygon, CLOSING * alpha))
    if main is None:
        return None
    min_hole = math.pi * alpha ** 2 / 4
    holes = [ring for ring in main.interiors if Polygon(ring).area >= min_hole]
    main = Polygon(main.exterior, holes)
    return clean_polygon(main, spacing * ALPHA_TOL)


# ---------------------------------------------------------------------------
# Buffered-lines step (Commandeur 2012)
# ---------------------------------------------------------------------------

def douglas(polygon, tolerance):
    """Douglas-Peucker simplification of one plot (None when it breaks)."""
    out = shapely.simplify(polygon, tolerance, preserve_topology=False)
    return clean_polygon(out) if out is not None and out.is_valid and not out.is_empty else None


def simplify_one(polygon, tolerance):
    """Topology-preserving Douglas-Peucker simplification of one plot."""
    return clean_polygon(shapely.simplify(polygon, tolerance, preserve_topology=True))


def simplify_coverage(polygons, tolerance):
    """Topology-preserving simplification of all plots, shared edges kept shared."""
    arr = np.empty(len(polygons), dtype=object)
    arr[:] = list(polygons)
    try:
        if len(arr) and shapely.coverage_is_valid(arr):
            return [clean_polygon(g) for g in shapely.coverage_simplify(arr, tolerance)]
    except shapely.errors.GEOSException:
        pass
    return [simplify_one(g, tolerance) for g in arr]


# ---------------------------------------------------------------------------
# Groups and overlaps
# ---------------------------------------------------------------------------

def touching_groups(polygons, gap=0.0):
    """Groups (lists of indices) of plots that touch or lie within ``gap``."""
    arr = np.empty(len(polygons), dtype=object)
    arr[:] = list(polygons)
    n = len(arr)
    parent = np.arange(n)

    def find(i):
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    if n:
        tree = shapely.STRtree(arr)
        if gap > 0:
            a, b = tree.query(arr, predicate="dwithin", distance=gap)
        else:
            a, b = tree.query(arr, predicate="intersects")
        for i, j in zip(a, b):
            ri, rj = find(i), find(j)
            if ri != rj:
                parent[max(ri, rj)] = min(ri, rj)
    groups = {}
    for i in range(n):
        groups.setdefault(find(i), []).append(i)
    return list(groups.values())


def overlapping_pairs(polygons, min_area=1e-6):
    """Pairs (i, j), i < j, of plots whose interiors overlap by more than ``min_area``."""
    arr = np.empty(len(polygons), dtype=object)
    arr[:] = list(polygons)
    if not len(arr):
        return []
    tree = shapely.STRtree(arr)
    a, b = tree.query(arr, predicate="intersects")
    pairs = []
    for i, j in zip(a, b):
        if i < j and shapely.intersection(arr[i], arr[j]).area > min_area:
            pairs.append((int(i), int(j)))
    return pairs


def remove_overlaps(polygons):
    """Remove overlaps between plots, keeping one polygon per plot.

    GEOS coverage cleaning gives each overlap to the plot with the longest
    shared border; a plot split or emptied by it keeps its largest part, or
    its own area minus its neighbours. Coverage cleaning is made for slivers:
    where plots overlap widely (one grown over another) it can return parts
    that are not what each plot loses to its neighbours, and then plain
    differences are used instead (pair by pair, the later plot loses the
    shared area, or the earlier one when the later would vanish).
    """
    polygons = list(polygons)
    pairs = overlapping_pairs(polygons)
    if not pairs:
        return polygons
    involved = sorted({k for pair in pairs for k in pair})
    arr = np.empty(len(involved), dtype=object)
    arr[:] = [polygons[k] for k in involved]
    try:
        cleaned = shapely.coverage_clean(arr, snapping_distance=0.0)
    except shapely.errors.GEOSException:
        cleaned = None
    if cleaned is not None:
        # a plot may only lose (part of) what it shares with its neighbours
        shared = dict.fromkeys(involved, 0.0)
        for i, j in pairs:
            area = shapely.intersection(polygons[i], polygons[j]).area
            shared[i] += area
            shared[j] += area
        for k, geom in zip(involved, cleaned):
            if geom is None or shapely.difference(geom, polygons[k]).area > 1e-6 or \
                    geom.area < polygons[k].area - shared[k] - 1e-6:
                cleaned = None
                break
    if cleaned is None:
        return _plain_differences(polygons, pairs)
    for k, geom in zip(involved, cleaned):
        poly = clean_polygon(largest_polygon(geom))
        if poly is None:
            others = shapely.union_all([polygons[j] for j in involved if j != k])
            poly = clean_polygon(largest_polygon(shapely.difference(polygons[k], others)))
        if poly is not None:
            polygons[k] = poly
    # what is left: a plot lying wholly inside a neighbour's generalisation
    # keeps its own shape and is cut out of the neighbour (which may get a hole)
    return _out_of_holes(_plain_differences(polygons, overlapping_pairs(polygons)))


def _out_of_holes(polygons):
    """A plot in a neighbour's hole that :func:`_clean` kept 1 cm off the neighbour's
    outline (the hole shrunk: the two overlap by that centimetre) gives the
    centimetre up."""
    for i, j in overlapping_pairs(polygons):
        for inner, outer in ((i, j), (j, i)):
            if shapely.difference(polygons[inner], Polygon(polygons[outer].exterior)).area < 1e-6:
                cut = _plot_kept(shapely.difference(polygons[inner], polygons[outer]))
                if cut is not None:
                    polygons[inner] = cut
                break
    return polygons


def _plot_kept(geometry):
    return clean_polygon(largest_polygon(geometry))


#: pair by pair, the later plot loses the shared area, or the earlier one when
#: the later would vanish (it lies inside the earlier)
LATER_PLOT_LOSES = OverlapRule(
    keep=_plot_kept, min_shared=1e-6, merge_winners=False, swap=True,
    intersection=lambda later, earlier: shapely.intersection(earlier, later))


def _plain_differences(polygons, pairs):
    """Overlaps removed pair by pair (:data:`LATER_PLOT_LOSES`)."""
    return resolve_overlaps(polygons, [(b, [a]) for a, b in pairs], LATER_PLOT_LOSES)[0]


# ---------------------------------------------------------------------------
# The chain
# ---------------------------------------------------------------------------

def _lines_for(polygon, distance, angle, orthogonal):
    return buffered_lines([polygon], distance, angle, orthogonal)[0]


def _centre_lines(polygons):
    """The plots the alpha step samples: an outline vectorised from raster cells, on
    the centre line of its stairs (the alpha shape of the stairs' points runs along
    their outer corners, half a cell out); a plot touching another stays as it is
    (the centre line would cut into its neighbour)."""
    cell, out = stair_step(polygons), list(polygons)
    for group in touching_groups(polygons) if cell else ():
        if len(group) == 1:
            out[group[0]] = centre_line(polygons[group[0]], cell)
    return out


def generalize_plots(polygons, methods=("alpha", "lines"), alpha=12.0, distance=5.0,
                     angle=180.0, orthogonal=False, tolerance=1.0, seed=1, image=None,
                     outline="centre", stroke=None, reach=None):
    """Generalise building plots, one output polygon per input polygon.

    ``polygons``: valid shapely Polygons (see :func:`explode_plots`);
    ``methods``: the steps in order (from :data:`METHODS`); ``alpha``: alpha
    radius; ``distance`` / ``angle`` (degrees): the epsilons of the
    buffered-lines step; ``orthogonal``: parallel / perpendicular lines;
    ``tolerance``: the simplify and douglas tolerance; ``seed``: for the
    stratified and random samplings; ``image``: the scanned map (a
    :class:`~reconstruction.geom.grid.MapImage`) whose drawn boundary lines the
    ``fit`` step moves the edges onto, by the map's ``outline`` convention and
    ``stroke`` width, looking for the line within ``reach`` cells of the edges
    (:func:`~reconstruction.generalize.fitting.fit_outlines`). Returns a
    :class:`Generalization`.
    """
    for method in methods:
        if method not in METHODS:
            raise ValueError("unknown method '{}' (one of {})".format(method, ", ".join(METHODS)))
    if "fit" in methods and image is None:
        raise ValueError("the fit step needs the scanned map (image=)")
    outline_fit = None
    rng = np.random.default_rng(seed)
    current = [shapely.orient_polygons(p) for p in polygons]
    used = [[] for _ in current]
    steps = [("raw", list(current))]
    fallbacks = {}
    previous = None
    stairs = _centre_lines(current) if "alpha" in methods else current
    for step_no, method in enumerate(methods):
        step_name = method if method not in [s[0] for s in steps] else "{}_{}".format(method, step_no + 1)
        new = [None] * len(current)
        labels = [None] * len(current)
        if method == "alpha":
            for i, poly in enumerate(current):
                for sampling in SAMPLINGS:
                    out = alpha_generalize(stairs[i], alpha, sampling, rng=rng)
                    if acceptable(out, poly):
                        new[i], labels[i] = out, "alpha/" + sampling
                        break
        elif method == "lines":
            for group in touching_groups(current):
                outs = buffered_lines([current[i] for i in group], distance, angle, orthogonal)
                for i, out in zip(group, outs):
                    if acceptable(out, current[i], min_iou=LINES_IOU):
                        new[i], labels[i] = out, "lines"
            # a plot of a group may have failed because of its neighbours: alone
            for i in range(len(current)):
                if new[i] is None:
                    out = _lines_for(current[i], distance, angle, orthogonal)
                    if acceptable(out, current[i], min_iou=LINES_IOU):
                        new[i], labels[i] = out, "lines"
        elif method == "simplify":
            outs = simplify_coverage(current, tolerance)
            for i, out in enumerate(outs):
                if acceptable(out, current[i]):
                    new[i], labels[i] = out, "simplify"
        elif method == "douglas":
            for i, poly in enumerate(current):
                out = douglas(poly, tolerance)
                if acceptable(out, poly):
                    new[i], labels[i] = out, "douglas"
        elif method == "fit":
            outline_fit = fitting.fit_outlines(current, image, outline, stroke, reach)
            kept = 0
            for i, (poly, out) in enumerate(zip(current, outline_fit.plots)):
                fitted = acceptable(out, poly)
                new[i], labels[i] = (out, "fit") if fitted else (poly, "fit/none")
                kept += not fitted
            if kept:
                fallbacks[step_name] = kept
            if outline == "inside":
                for i, plain in _better_supported(new, steps[0][1], image,
                                                  outline_fit.stroke_width, tolerance, reach):
                    new[i], labels[i] = plain, "fit/douglas"
                for i, squared in _corners_restored(new, image, outline_fit.stroke_width,
                                                    reach):
                    new[i], labels[i] = squared, labels[i] + "/corner"
        failed = [i for i in range(len(current)) if new[i] is None]
        for i in failed:
            new[i], labels[i], redone = _fallback(method, i, current, steps, previous, alpha,
                                                  distance, angle, orthogonal, tolerance, rng, used,
                                                  stairs)
            if redone is not None:  # the previous step was redone with another sampling
                steps[-1][1][i] = redone
                used[i][-1], labels[i] = labels[i].split("+", 1)
        if failed:
            fallbacks[step_name] = len(failed)
        for i, label in enumerate(labels):
            used[i].append(label)
        current = new
        steps.append((step_name, list(current)))
        previous = method
    final = remove_overlaps(current)
    for i, poly in enumerate(final):
        if not (poly is not None and poly.geom_type == "Polygon" and poly.is_valid):
            final[i] = current[i]
    if steps and final != current:
        steps[-1] = (steps[-1][0], list(final))
    return Generalization(final, ["+".join(u) if u else "none" for u in used], steps, fallbacks,
                          outline_fit)


def _better_supported(fitted, raw, image, width, tolerance, reach=None):
    """(index, outline) of the plots whose raw cells' outline, simplified and
    fitted, a map that draws its outlines ``width`` wide inside the plots
    draws its line along more of than their ``fitted`` outline (see
    :data:`SUPPORT_GAIN`)."""
    support = fitting.outline_support(fitted, image, "inside", width, reach)
    # only a plot whose outline the map supports along less than all but
    # SUPPORT_GAIN of it can gain
    simplified = ((int(i), douglas(raw[i], tolerance))
                  for i in np.flatnonzero(support <= 1.0 - SUPPORT_GAIN))
    candidates = [(i, p) for i, p in simplified if p is not None]  # a plot that breaks: none
    if not candidates:
        return
    room, plain = zip(*candidates)
    plain = fitting.fit_outlines(list(plain), image, "inside", width, reach).plots
    plain_support = fitting.outline_support(plain, image, "inside", width, reach)
    for i, new, new_support in zip(room, plain, plain_support):
        old = fitted[i]
        if (new_support >= support[i] + SUPPORT_GAIN and new.is_valid
                and abs(new.area - raw[i].area) < SUPPORT_AREA * raw[i].area
                and acceptable(new, old)):
            yield i, new


def _corners_restored(plots, image, width, reach=None):
    """(index, outline) of the plots with a corner the generalisation cut and
    the map draws (fitting.restore_corners), where the restored outline is
    valid, within CORNER_AREA of the plot's area and no less supported."""
    changed = {}
    for i, rings in enumerate(fitting.edge_support(plots, image, "inside", width, reach)):
        restored = [fitting.restore_corners(ring, shares) for ring, shares in rings]
        if any(len(new) != len(ring) for new, (ring, _) in zip(restored, rings)):
            outline = shapely.Polygon(restored[0], restored[1:])
            if (outline.is_valid and not outline.is_empty
                    and abs(outline.area - plots[i].area) < CORNER_AREA * plots[i].area):
                changed[i] = shapely.orient_polygons(outline)
    if not changed:
        return
    before = fitting.outline_support([plots[i] for i in changed], image, "inside", width, reach)
    after = fitting.outline_support(list(changed.values()), image, "inside", width, reach)
    for (i, outline), old, new in zip(changed.items(), before, after):
        if new >= old:
            yield i, outline


def _fallback(method, i, current, steps, previous, alpha, distance, angle, orthogonal,
              tolerance, rng, used, stairs):
    """The next sensible method for plot ``i`` whose ``method`` step failed.

    Returns ``(polygon, label, redone)``: ``redone`` is the new result of the
    previous (alpha) step when it was redone with another sampling, else None.
    """
    poly = current[i]
    if method == "lines":
        if previous == "alpha":
            # another sampling for the alpha step, then the lines again
            source = steps[-2][1][i]
            done = used[i][-1].split("/")[-1] if used[i] else None
            for sampling in SAMPLINGS:
                if sampling == done:
                    continue
                alt = alpha_generalize(stairs[i], alpha, sampling, rng=rng)
                if acceptable(alt, source):
                    out = _lines_for(alt, distance, angle, orthogonal)
                    if (acceptable(out, alt, min_iou=LINES_IOU)
                            and acceptable(out, source, min_iou=LINES_IOU)):
                        return out, "alpha/{}+lines".format(sampling), alt
        for factor in (2.0, 4.0):
            out = _lines_for(poly, distance / factor, angle, orthogonal)
            if acceptable(out, poly, min_iou=LINES_IOU):
                return out, "lines/{:g}".format(distance / factor), None
        out = douglas(poly, tolerance)
        if acceptable(out, poly):
            return out, "douglas", None
    out = simplify_one(poly, tolerance)
    if acceptable(out, poly):
        return out, "simplify", None
    return poly, "none", None
