"""Shape metrics of building plots and shape comparison with reference plots.

Pure functions over shapely 2 geometries and numpy arrays (no GRASS):

- :func:`plot_metrics`: the per-plot metrics of the thesis's Table 3.1
  (Morlighem 2021): area, perimeter, vertices, holes, compactness, elongation,
  roundness, convexity, concavity, solidity, rectangularity; vectorised over
  many polygons with shapely 2's array functions;
- :func:`summarise_metrics`: count, sum, mean, median and standard deviation
  of each metric (one row of the ``metrics=`` CSV of v.histo.generalize);
- :func:`turning_distance`: the turning-function distance of Arkin et al.
  (1991): L2 distance between the turning functions over normalised arc
  length, minimised over the starting point and the rotation;
- :func:`buffer_similarity`: the buffer shape similarity of Samal et al.
  (2004) as used by the thesis: ``(A phi B + B phi A) / 2`` in %, where
  ``A phi B`` is the share of A's area inside B buffered by a distance;
- :func:`match_plots`: which output plot stands for each reference plot;
- :func:`outline_agreement`: how far a plot's outline lies outside its
  reference's on average (the outward offset) and their intersection over
  union, the reference matched with the plot that overlaps it most.

Definitions (thesis, Table 3.1):
    compactness    4 pi area / perimeter^2
    elongation     short side / long side of the minimum rotated rectangle
    roundness      4 pi area / (perimeter of the convex hull)^2
    convexity      perimeter of the convex hull / perimeter
    concavity      1 when the plot is concave (convexity < 1), else 0; its sum
                   is the thesis's number of concave plots
    solidity       area / area of the convex hull
    rectangularity area / area of the minimum rotated rectangle
    vertices       distinct vertices of all rings (a rectangle has 4; the
                   thesis counted the closing point too, i.e. 5)
    holes          number of interior rings
"""

import math
from dataclasses import dataclass

import numpy as np
import shapely

from ..geom.polygons import largest_polygon

METRICS = ("area", "perimeter", "vertices", "holes", "compactness", "elongation",
           "roundness", "convexity", "concavity", "solidity", "rectangularity")
STATISTICS = ("sum", "mean", "median", "std")

_CONCAVE_TOLERANCE = 1e-6


def _as_array(polygons):
    arr = np.empty(len(polygons), dtype=object)
    arr[:] = list(polygons)
    return arr


def plot_metrics(polygons):
    """The Table 3.1 metrics of each polygon, as a dict metric -> float array.

    ``polygons`` is a sequence of shapely Polygons or MultiPolygons; missing or
    empty geometries give NaN (0 for the counts).
    """
    geoms = _as_array(polygons)
    present = np.array([g is not None and not g.is_empty for g in geoms], dtype=bool)
    geoms = np.where(present, geoms, shapely.Polygon())
    area = shapely.area(geoms)
    perimeter = shapely.length(geoms)
    parts, part_index = shapely.get_parts(geoms, return_index=True)
    rings, ring_part = shapely.get_rings(parts, return_index=True)
    vertices = np.bincount(part_index[ring_part], weights=shapely.get_num_coordinates(rings) - 1,
                           minlength=len(geoms))
    holes = np.bincount(part_index, weights=shapely.get_num_interior_rings(parts),
                        minlength=len(geoms))
    hull = shapely.convex_hull(geoms)
    hull_perimeter = shapely.length(hull)
    hull_area = shapely.area(hull)
    mrr = shapely.oriented_envelope(geoms)
    mrr_area = shapely.area(mrr)
    sides = _rectangle_sides(mrr)
    with np.errstate(divide="ignore", invalid="ignore"):
        compactness = 4 * math.pi * area / perimeter ** 2
        roundness = 4 * math.pi * area / hull_perimeter ** 2
        convexity = hull_perimeter / perimeter
        solidity = area / hull_area
        rectangularity = area / mrr_area
        elongation = sides.min(axis=1) / sides.max(axis=1)
    concavity = (convexity < 1 - _CONCAVE_TOLERANCE).astype(float)
    result = {
        "area": area, "perimeter": perimeter, "vertices": vertices.astype(float),
        "holes": holes.astype(float), "compactness": compactness,
        "elongation": elongation, "roundness": roundness, "convexity": convexity,
        "concavity": concavity, "solidity": solidity, "rectangularity": rectangularity,
    }
    for key, values in result.items():
        values = np.asarray(values, dtype=float)
        if key not in ("vertices", "holes", "concavity"):
            values[~present] = np.nan
        result[key] = values
    return result


def _rectangle_sides(rectangles):
    """Lengths of the first two sides of each rectangle (n, 2); degenerate -> 0."""
    sides = np.zeros((len(rectangles), 2))
    for i, rect in enumerate(rectangles):
        if rect.geom_type == "Polygon" and not rect.is_empty:
            xy = np.asarray(rect.exterior.coords)
            if len(xy) >= 4:
                sides[i] = np.hypot(*(xy[1:3] - xy[0:2]).T)
    return sides


def summarise_metrics(metrics):
    """Count and sum, mean, median, std (population) of each metric.

    Returns an ordered dict ``{"plots": n, "area_sum": ..., "area_mean": ...}``
    with the metrics in the order of :data:`METRICS`; NaNs are ignored.
    """
    n = len(next(iter(metrics.values()))) if metrics else 0
    row = {"plots": n}
    for key in METRICS:
        values = np.asarray(metrics[key], dtype=float)
        values = values[~np.isnan(values)]
        if len(values):
            stats = (values.sum(), values.mean(), np.median(values), values.std())
        else:
            stats = (0.0, math.nan, math.nan, math.nan)
        for name, value in zip(STATISTICS, stats):
            row["{}_{}".format(key, name)] = float(value)
    return row


# ---------------------------------------------------------------------------
# Turning function (Arkin et al. 1991)
# ---------------------------------------------------------------------------

def turning_function(polygon):
    """Turning function of a polygon's exterior ring (counter-clockwise).

    Returns ``(starts, angles)``: the normalised arc length at which each
    edge starts (``starts[0] == 0``) and the cumulative tangent angle along
    that edge in radians (first edge's direction, then + signed turns).
    """
    polygon = largest_polygon(polygon)
    if polygon is None:
        raise ValueError("turning function of an empty geometry")
    ring = shapely.orient_polygons(polygon).exterior
    xy = np.asarray(ring.coords)[:, :2]
    edges = np.diff(xy, axis=0)
    lengths = np.hypot(edges[:, 0], edges[:, 1])
    keep = lengths > 1e-12 * max(lengths.max(), 1.0)
    edges, lengths = edges[keep], lengths[keep]
    if len(edges) < 3:
        raise ValueError("turning function of a degenerate polygon")
    heading = np.arctan2(edges[:, 1], edges[:, 0])
    turns = np.diff(heading)
    turns = (turns + math.pi) % (2 * math.pi) - math.pi
    angles = np.concatenate([[heading[0]], heading[0] + np.cumsum(turns)])
    starts = np.concatenate([[0.0], np.cumsum(lengths)[:-1]]) / lengths.sum()
    return starts, angles


def turning_distance(a, b):
    """Arkin et al.'s (1991) turning-function distance between two polygons.

    ``sqrt(min over t, theta of integral_0^1 (TA(s + t) - TB(s) + theta)^2 ds)``
    with TA extended by ``TA(s + 1) = TA(s) + 2 pi``. The optimal rotation is
    the mean difference; the optimal shift lies at a critical event, where a
    breakpoint of A meets one of B, and all of them are evaluated exactly.
    0 for identical shapes (at any scale, position and rotation).
    """
    sa, ta = turning_function(a)
    sb, tb = turning_function(b)
    shifts = np.unique(((sa[:, None] - sb[None, :]) % 1.0).ravel())
    # breakpoints of B and of A shifted by t, in [0, 1]
    shifted = (sa[None, :] - shifts[:, None]) % 1.0
    k = len(shifts)
    cuts = np.concatenate([np.broadcast_to(sb, (k, len(sb))), shifted,
                           np.zeros((k, 1)), np.ones((k, 1))], axis=1)
    cuts.sort(axis=1)
    widths = np.diff(cuts, axis=1)
    mids = (cuts[:, 1:] + cuts[:, :-1]) / 2
    value_b = tb[np.searchsorted(sb, mids, side="right") - 1]
    pos = mids + shifts[:, None]
    wraps = np.floor(pos)
    value_a = ta[np.searchsorted(sa, pos - wraps, side="right") - 1] + 2 * math.pi * wraps
    diff = value_a - value_b
    mean = (widths * diff).sum(axis=1)
    squares = (widths * diff ** 2).sum(axis=1) - mean ** 2
    return float(math.sqrt(max(squares.min(), 0.0)))


# ---------------------------------------------------------------------------
# Buffer shape similarity (Samal et al. 2004)
# ---------------------------------------------------------------------------

def buffer_similarity(a, b, distance=2.0):
    """Buffer shape similarity of two polygons in % (Samal et al. 2004).

    ``A phi B`` = 100 x area(A within B buffered by ``distance``) / area(A),
    with square, mitred buffers as in the thesis; returns
    ``(A phi B + B phi A) / 2``: 100 for shapes within ``distance`` of each
    other, lower the more they differ.
    """
    if a is None or b is None or a.is_empty or b.is_empty:
        return 0.0
    a_in_b = shapely.intersection(a, shapely.buffer(b, distance, cap_style="square",
                                                    join_style="mitre")).area / a.area
    b_in_a = shapely.intersection(b, shapely.buffer(a, distance, cap_style="square",
                                                    join_style="mitre")).area / b.area
    return float(100.0 * (a_in_b + b_in_a) / 2.0)


def match_plots(plots, references, min_overlap=0.5):
    """For each reference plot, the index of the plot standing for it (or -1).

    The match is the plot with the largest intersection over union with the
    reference, kept when the overlap covers at least ``min_overlap`` of the
    reference or of the plot.
    """
    plots = _as_array(plots)
    refs = _as_array(references)
    matches = np.full(len(refs), -1, dtype=int)
    valid = np.array([g is not None and not g.is_empty for g in plots], dtype=bool)
    if not valid.any() or not len(refs):
        return matches
    index = np.flatnonzero(valid)
    tree = shapely.STRtree(plots[valid])
    for i, ref in enumerate(refs):
        if ref is None or ref.is_empty:
            continue
        candidates = index[tree.query(ref, predicate="intersects")]
        best, best_iou = -1, 0.0
        for j in candidates:
            inter = shapely.intersection(plots[j], ref).area
            union = shapely.union(plots[j], ref).area
            iou = inter / union if union > 0 else 0.0
            if iou > best_iou and inter >= min_overlap * min(ref.area, plots[j].area):
                best, best_iou = j, iou
        matches[i] = best
    return matches


@dataclass(frozen=True)
class OutlineAgreement:
    """Per reference plot, its match's outward ``offset`` (map units: the plot's area
    less the reference's, over the reference's perimeter; positive outside) and
    ``iou`` (None where no plot overlaps the reference), and their means over the
    matched references (None without any)."""

    offsets: list
    ious: list

    def _mean(self, values):
        found = [v for v in values if v is not None]
        return float(np.mean(found)) if found else None

    @property
    def offset(self):
        return self._mean(self.offsets)

    @property
    def iou(self):
        return self._mean(self.ious)


def outline_agreement(plots, references):
    """The :class:`OutlineAgreement` of ``plots`` with the ``references`` (shapely
    geometries): each reference matched with the plot that overlaps it most.

    The offset measures a bias the turning function and the buffer similarity
    do not see: plots drawn too large (or too small) all round (issue 32)."""
    plots = _as_array(plots)
    refs = _as_array(references)
    offsets, ious = [None] * len(refs), [None] * len(refs)
    valid = np.flatnonzero([g is not None and not g.is_empty for g in plots])
    if not len(valid) or not len(refs):
        return OutlineAgreement(offsets, ious)
    tree = shapely.STRtree(plots[valid])
    for i, ref in enumerate(refs):
        if ref is None or ref.is_empty:
            continue
        candidates = valid[tree.query(ref, predicate="intersects")]
        if not len(candidates):
            continue
        shared = shapely.area(shapely.intersection(plots[candidates], ref))
        if shared.max() <= 0:
            continue
        j = candidates[int(np.argmax(shared))]
        offsets[i] = float((plots[j].area - ref.area) / ref.length)
        ious[i] = float(shared.max() / shapely.union(plots[j], ref).area)
    return OutlineAgreement(offsets, ious)


def shape_scores(plots, references, buffer=2.0):
    """Mean turning-function distance and buffer similarity to reference plots.

    Returns a dict with ``matched`` (references with a matching plot),
    ``turning_distance`` (mean over the matches), ``buffer_similarity``
    (mean over the matches, %) and the per-reference lists
    ``turning_distances`` and ``buffer_similarities`` (None when unmatched).
    """
    matches = match_plots(plots, references)
    distances, similarities = [], []
    for ref, j in zip(references, matches):
        if j < 0:
            distances.append(None)
            similarities.append(None)
            continue
        distances.append(turning_distance(plots[j], ref))
        similarities.append(buffer_similarity(plots[j], ref, buffer))
    found = [d for d in distances if d is not None]
    sims = [s for s in similarities if s is not None]
    return {
        "references": len(references),
        "matched": len(found),
        "turning_distance": float(np.mean(found)) if found else None,
        "buffer_similarity": float(np.mean(sims)) if sims else None,
        "turning_distances": distances,
        "buffer_similarities": similarities,
        "matches": [int(j) for j in matches],
    }
