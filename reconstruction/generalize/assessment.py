"""Assessment of reconstructed building plots against reference data.

Pure functions over shapely geometries and numpy arrays, shared by the
modules that report quality figures (r.histo.classify, v.histo.generalize)
and by the acceptance on real maps of other styles (issue 50):

- points: :func:`point_detection_scores` (the thesis's precision, recall and
  F-score of plots against one ground-truth point per plot);
- objects: :func:`object_scores` (objects on a grid, as label rasters,
  matched one-to-one by their intersection over union: F-score and COCO
  panoptic quality), :func:`parcels_from_mask` and :func:`blocks_from_parcels`
  (a published parcel mask read as parcels and as the blocks they make),
  :func:`parcel_scores` (footprints against the parcels);
- the field's metric: :func:`icdar_panoptic_quality` (label rasters),
  :func:`polygon_panoptic_quality` (polygons) and :func:`shapes_from_edges`
  (an edge image read as its closed shapes): panoptic quality as the ICDAR
  2021 MapSeg competition computes it (:func:`icdar_quality`).
"""

from dataclasses import dataclass

import numpy as np
import shapely
from scipy import ndimage

from ..geom.strokes import disk


@dataclass(frozen=True)
class DetectionScores:
    """Point-based detection scores (each in [0, 1])."""

    precision: float
    recall: float
    f_score: float


def _points_array(points):
    """Points as an (n, 2) float array, from shapely points or coordinates."""
    if points is None:
        return np.empty((0, 2))
    if isinstance(points, np.ndarray) and points.dtype != object:
        return np.asarray(points, dtype=float).reshape(-1, 2)
    points = list(points)
    if not points:
        return np.empty((0, 2))
    if hasattr(points[0], "geom_type"):
        return shapely.get_coordinates(np.asarray(points, dtype=object))[:, :2].reshape(-1, 2)
    return np.asarray(points, dtype=float).reshape(-1, 2)


def point_hits(polygons, points):
    """Boolean matrix (polygons x points): does polygon i cover point j?

    A point on a polygon's boundary counts as inside. Empty or missing
    geometries cover nothing.
    """
    polygons = np.asarray(list(polygons) if polygons is not None else [], dtype=object)
    xy = _points_array(points)
    hits = np.zeros((len(polygons), len(xy)), dtype=bool)
    if not len(polygons) or not len(xy):
        return hits
    pts = shapely.points(xy)
    valid = np.array([g is not None and not g.is_empty for g in polygons], dtype=bool)
    if not valid.any():
        return hits
    tree = shapely.STRtree(polygons[valid])
    pt_idx, poly_idx = tree.query(pts, predicate="covered_by")
    hits[np.flatnonzero(valid)[poly_idx], pt_idx] = True
    return hits


def point_detection_scores(polygons, points):
    """Precision, recall and F-score of detected areas against reference points.

    As in the thesis (Morlighem 2021, Section 4): with one ground-truth point
    inside each true building plot,

    - recall = share of points inside (or on the boundary of) any polygon;
    - precision = share of polygons holding at least one point;
    - F-score = harmonic mean of the two (0 when both are 0).

    ``polygons`` is a sequence of shapely (Multi)Polygons; ``points`` a
    sequence of shapely Points or an (n, 2) array of coordinates. Returns a
    :class:`DetectionScores` (``precision``, ``recall``, ``f_score``); precision is 0
    without polygons, recall 0 without points.
    """
    hits = point_hits(polygons, points)
    n_polygons, n_points = hits.shape
    precision = float(hits.any(axis=1).sum()) / n_polygons if n_polygons else 0.0
    recall = float(hits.any(axis=0).sum()) / n_points if n_points else 0.0
    total = precision + recall
    f_score = 2.0 * precision * recall / total if total > 0 else 0.0
    return DetectionScores(precision, recall, f_score)


# ---------------------------------------------------------------------------
# Objects on a grid matched one-to-one (issue 50's acceptance)
# ---------------------------------------------------------------------------

@dataclass(frozen=True)
class ObjectScores:
    """Predicted objects matched one-to-one to true ones by their IoU.

    ``predicted``, ``true``: the objects' counts; ``matched``: the matched
    pairs (true positives); ``iou_sum``: the sum of their IoUs;
    ``precision`` = matched / predicted, ``recall`` = matched / true,
    ``f_score`` their harmonic mean; ``pq`` = COCO panoptic quality,
    iou_sum / (matched + (predicted - matched) / 2 + (true - matched) / 2).
    """

    predicted: int
    true: int
    matched: int
    iou_sum: float
    precision: float
    recall: float
    f_score: float
    pq: float


def _label_areas(labels):
    """(ids, cell counts) of the labels > 0 of an integer array."""
    ids, counts = np.unique(labels[labels > 0], return_counts=True)
    return ids, counts


def matched_pairs(predicted, true, iou=0.5, strict=True):
    """Pairs (predicted id, true id, IoU) of two label rasters matched one-to-one.

    ``predicted`` and ``true`` are integer arrays of the same shape, 0 where
    there is no object, each other value one object (its cells need not be
    connected). Two objects may pair when their IoU (cells in both / cells in
    either) exceeds ``iou`` (``strict``) or reaches it (not ``strict``); the
    pairs are taken by decreasing IoU, each object in one pair at most (above
    0.5 with ``strict`` no object can pair twice anyway: the matching is
    COCO's). Returns a list of (int, int, float).
    """
    predicted = np.asarray(predicted)
    true = np.asarray(true)
    if predicted.shape != true.shape:
        raise ValueError("label rasters of different shapes {} and {}".format(
            predicted.shape, true.shape))
    p_ids, p_area = _label_areas(predicted)
    t_ids, t_area = _label_areas(true)
    both = (predicted > 0) & (true > 0)
    if not both.any():
        return []
    p_at = np.searchsorted(p_ids, predicted[both])
    t_at = np.searchsorted(t_ids, true[both])
    pair, inter = np.unique(p_at.astype(np.int64) * len(t_ids) + t_at, return_counts=True)
    pi, ti = np.divmod(pair, len(t_ids))
    ious = inter / (p_area[pi] + t_area[ti] - inter)
    ok = ious > iou if strict else ious >= iou
    order = np.argsort(-ious[ok], kind="stable")
    used_p, used_t, pairs = set(), set(), []
    for a, b, v in zip(pi[ok][order], ti[ok][order], ious[ok][order]):
        if a in used_p or b in used_t:
            continue
        used_p.add(a)
        used_t.add(b)
        pairs.append((int(p_ids[a]), int(t_ids[b]), float(v)))
    return pairs


def object_scores(predicted, true, iou=0.5, strict=True):
    """F-score and panoptic quality of predicted objects against true ones.

    Both are label rasters on one grid (see :func:`matched_pairs`, which
    matches them one-to-one at IoU > ``iou``). precision = matched /
    predicted, recall = matched / true (each 0 without objects), F-score
    their harmonic mean, PQ = sum of the matched IoUs / (TP + FP/2 + FN/2)
    (Kirillov et al. 2019; the ICDAR 2021 MapSeg competition scored map
    blocks with it). Returns an :class:`ObjectScores`.
    """
    pairs = matched_pairs(predicted, true, iou, strict)
    n_pred = len(_label_areas(np.asarray(predicted))[0])
    n_true = len(_label_areas(np.asarray(true))[0])
    tp = len(pairs)
    iou_sum = float(sum(v for _, _, v in pairs))
    precision = tp / n_pred if n_pred else 0.0
    recall = tp / n_true if n_true else 0.0
    total = precision + recall
    f_score = 2.0 * precision * recall / total if total > 0 else 0.0
    denominator = tp + (n_pred - tp) / 2.0 + (n_true - tp) / 2.0
    pq = iou_sum / denominator if denominator else 0.0
    return ObjectScores(n_pred, n_true, tp, iou_sum, precision, recall, f_score, pq)


FOUR_CONNECTED = ndimage.generate_binary_structure(2, 1)


# ---------------------------------------------------------------------------
# The ICDAR 2021 MapSeg competition's panoptic quality (issue 51)
# ---------------------------------------------------------------------------

@dataclass(frozen=True)
class PanopticQuality:
    """Panoptic quality as the ICDAR 2021 MapSeg competition (task 1, building
    blocks) computes it (:func:`icdar_quality`).

    ``predicted``, ``true``: the shapes' counts; ``matched``: the pairs of
    IoU > 0.5; ``rq`` = 2 matched / (predicted + true) (the detection F-score);
    ``sq``: the mean IoU of the matches (see :func:`icdar_quality` for how the
    competition averages); ``pq`` = sq * rq. Each 0 without a match.
    """

    predicted: int
    true: int
    matched: int
    pq: float
    sq: float
    rq: float


def icdar_quality(ious, predicted, true):
    """The competition's PQ, SQ and RQ from the IoUs of the matched pairs.

    ``ious``: the IoU (> 0.5) of each pair of one predicted and one true shape
    matched one-to-one; ``predicted``, ``true``: how many shapes there are.
    As the competition's evaluation tool (PyPI ``icdar21-mapseg-eval`` 1.0.4,
    ``COCO`` of task 1) computes it: RQ = 2 TP / (P + T), SQ = the mean of the
    *distinct* IoU values of the matches (the tool averages the index of its
    table of IoU thresholds: two matches of exactly the same IoU count once;
    Kirillov et al.'s SQ, the mean over all matches, differs only there) and
    PQ = SQ * RQ; all 0 without a prediction or without a match.
    Returns a :class:`PanopticQuality`.
    """
    ious = np.asarray(list(ious), dtype=float)
    if not len(ious) or not predicted or not true:
        return PanopticQuality(int(predicted), int(true), len(ious), 0.0, 0.0, 0.0)
    sq = float(np.unique(ious).mean())
    rq = 2.0 * len(ious) / (predicted + true)
    return PanopticQuality(int(predicted), int(true), len(ious), sq * rq, sq, rq)


def _four_connected(shapes):
    """A boolean raster as its 4-connected regions (a label raster); other
    arrays unchanged."""
    shapes = np.asarray(shapes)
    if shapes.dtype == bool:
        return ndimage.label(shapes, structure=FOUR_CONNECTED)[0]
    return shapes


def icdar_panoptic_quality(predicted, true, mask=None):
    """The ICDAR 2021 MapSeg panoptic quality of predicted shapes on a grid.

    ``predicted`` and ``true``: label rasters of one shape (0 = no shape, each
    other value one shape) or boolean rasters, whose 4-connected regions of
    True are the shapes (the tool's reading of a binary image: its
    ``skimage.measure.label(..., connectivity=1)``). ``mask`` (optional,
    True/non-zero where the map is): cells outside it belong to no shape, as
    in the competition, whose inputs are masked (the shapes are not
    renumbered: a shape the mask cuts stays one). Shapes pair when their IoU
    (cells in both / cells in either, the whole grid counted) exceeds 0.5,
    which makes the pairing one-to-one. Returns :func:`icdar_quality`'s
    :class:`PanopticQuality`.

    Where the tool differs: it counts every label number up to the largest
    as a shape (a gap in the numbering is an empty shape, never matched; here
    only labels present count) and fails when a shape's best partner at
    IoU > 0.5 is the other raster's 0; neither arises with shapes numbered
    1..n that the 0 cells do not engulf.
    """
    predicted = _four_connected(predicted)
    true = _four_connected(true)
    if mask is not None:
        outside = ~np.asarray(mask).astype(bool)
        predicted = np.where(outside, 0, predicted)
        true = np.where(outside, 0, true)
    pairs = matched_pairs(predicted, true, 0.5, strict=True)
    return icdar_quality([v for _, _, v in pairs], len(_label_areas(predicted)[0]),
                         len(_label_areas(true)[0]))


def shapes_from_edges(edges, mask=None):
    """The closed shapes of an edge image, as the competition's ground truth has them.

    ``edges``: a 2-D array, non-zero on the (1-pixel) boundaries drawn around
    every shape (the published ground truth of the Paris atlas: 255 on the
    edges); ``mask``: non-zero where the map is (the content mask). The shapes
    are the 4-connected regions of the zero cells inside the mask, numbered
    1, 2, ... in raster order; edge cells and cells outside the mask are 0
    (no shape). No size filter: every region counts, the open space of the
    streets (the largest region) too, as in the competition's reference.
    """
    inside = np.asarray(edges) == 0
    if mask is not None:
        inside &= np.asarray(mask) != 0
    return ndimage.label(inside, structure=FOUR_CONNECTED)[0]


def polygon_panoptic_quality(polygons, references):
    """The competition's panoptic quality (:func:`icdar_quality`) of polygons.

    ``polygons``: the predicted shapes, ``references``: the true ones
    (shapely polygons; empty or missing ones are left out). The IoU of two
    shapes is their areas' (the area of their intersection over that of their
    union, exact where the competition counts pixels); pairs of IoU > 0.5 are
    taken by decreasing IoU, each shape in one pair at most (shapes of one
    side may overlap, unlike a raster's). Returns a :class:`PanopticQuality`.
    """
    def usable(shapes):
        return np.asarray([g for g in (shapes if shapes is not None else [])
                           if g is not None and not g.is_empty], dtype=object)

    polygons, references = usable(polygons), usable(references)
    ious = []
    if len(polygons) and len(references):
        pi, ti = shapely.STRtree(references).query(polygons, predicate="intersects")
        inter = shapely.area(shapely.intersection(polygons[pi], references[ti]))
        union = shapely.area(polygons[pi]) + shapely.area(references[ti]) - inter
        iou = np.divide(inter, union, out=np.zeros(len(inter)), where=union > 0)
        used_p, used_t = set(), set()
        for k in np.argsort(-iou, kind="stable"):
            if iou[k] <= 0.5:
                break
            if pi[k] in used_p or ti[k] in used_t:
                continue
            used_p.add(pi[k])
            used_t.add(ti[k])
            ious.append(float(iou[k]))
    return icdar_quality(ious, len(polygons), len(references))


def parcels_from_mask(mask, threshold=128, min_cells=50):
    """The parcels of a published parcel mask, as a label raster.

    ``mask`` is a 2-D array (white = parcel; JPEG noise, hence ``threshold``):
    the parcels are the 4-connected regions of cells >= ``threshold`` of at
    least ``min_cells`` cells, numbered 1, 2, ... in raster order; 0 elsewhere.
    """
    labels, _ = ndimage.label(np.asarray(mask) >= threshold, structure=FOUR_CONNECTED)
    sizes = np.bincount(labels.ravel())
    keep = sizes >= min_cells
    keep[0] = False
    renumber = np.zeros(len(sizes), dtype=np.int32)
    renumber[keep] = np.arange(1, keep.sum() + 1)
    return renumber[labels]


def blocks_from_parcels(parcels, radius):
    """The blocks the parcels make: their union with the lines between them closed.

    The raster form of buffering the parcels' union by +``radius`` and then
    by -``radius`` (cells; e.g. 0.6 m on a 0.1 m grid: 6): a morphological
    closing by a disk, computed on a grid padded with the edge cells'
    values: a block or a line cut by the map's edge goes on beyond it.
    Returns the blocks as a label raster (4-connected regions of the closed
    union, 1, 2, ... in raster order). Courtyards wider than 2 ``radius``
    stay holes in their block.
    """
    union = np.asarray(parcels) > 0
    r = int(np.ceil(radius)) + 1
    shape = disk(radius)
    padded = np.pad(union, r, mode="edge")
    closed = ndimage.binary_erosion(ndimage.binary_dilation(padded, shape), shape)
    closed = closed[r:-r, r:-r] | union
    return ndimage.label(closed, structure=FOUR_CONNECTED)[0]


@dataclass(frozen=True)
class ParcelScores:
    """Footprints against the published parcels.

    ``parcels``: the true parcels; ``footprints``: the footprints inside the
    true blocks (at least half of their cells); ``matched``: parcels matched
    one-to-one by a footprint at IoU >= 0.5; ``matched_share`` = matched /
    parcels; ``count_ratio`` = footprints / parcels.
    """

    parcels: int
    footprints: int
    matched: int
    matched_share: float
    count_ratio: float


def parcel_scores(footprints, parcels, blocks, iou=0.5):
    """How many published parcels the footprints find (label rasters on one grid).

    A parcel is found when a footprint matches it one-to-one at IoU >= ``iou``
    (:func:`matched_pairs`, not strict); the count ratio counts the footprints
    at least half of whose cells lie in the true ``blocks`` (> 0) against the
    parcels. Returns a :class:`ParcelScores`.
    """
    footprints = np.asarray(footprints)
    n_parcels = len(_label_areas(np.asarray(parcels))[0])
    matched = len(matched_pairs(footprints, parcels, iou, strict=False))
    ids, area = _label_areas(footprints)
    inside = np.asarray(blocks)[footprints > 0] > 0
    at = np.searchsorted(ids, footprints[footprints > 0])
    in_blocks = np.bincount(at, weights=inside, minlength=len(ids))
    n_in = int((in_blocks * 2 >= area).sum())
    share = matched / n_parcels if n_parcels else 0.0
    ratio = n_in / n_parcels if n_parcels else 0.0
    return ParcelScores(n_parcels, n_in, matched, share, ratio)
