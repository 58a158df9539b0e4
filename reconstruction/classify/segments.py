"""Object-based classification of a scanned historical map.

The thesis's first stage (Morlighem 2021, Section 3.2.1, after Gobbi et al.
2019), as pure functions over numpy arrays:

- segmentation quality criteria for unsupervised parameter optimisation:
  area-weighted intra-segment variance (VW) and inter-segment spatial
  autocorrelation (Moran's I), their normalisation over all tried parameter
  pairs and the F-function combining them;
- object features per segment (band statistics and shape indices), computed
  for all segments at once with ``np.bincount`` and one sort per band;
- an ensemble of random forest, k-nearest-neighbours and SVM classifiers with
  a majority vote;
- removal of classes such as text and symbols: their pixels are refilled with
  the modal class of their surroundings, in a moving window sized from the
  thickness of the removed objects; the same fill removes regions smaller than
  a minimum mapping unit.

Arrays are (rows, cols); a segment array holds integer ids with ``0`` (or any
value <= 0) for no data. Nothing here imports GRASS.
"""

from dataclasses import dataclass

import numpy as np
from scipy import ndimage

#: Names of the features of :func:`segment_features`, per band then shape.
BAND_STATISTICS = ("mean", "median", "variance", "q1", "q3")
SHAPE_FEATURES = ("area", "perimeter", "compact_square", "compact_circle", "fractal_dimension")
CLASSIFIERS = ("rf", "knn", "svm")
#: Feature groups a classification can use: band statistics, size, shape indices.
FEATURE_GROUPS = ("spectral", "size", "shape")


@dataclass(frozen=True)
class TuningResult:
    """The tried pairs' criteria (arrays, one value per pair): VW, Moran's I,
    both normalised, the F-function; ``best`` the index of the chosen pair."""

    vw: np.ndarray
    moran: np.ndarray
    vw_norm: np.ndarray
    moran_norm: np.ndarray
    f: np.ndarray
    best: int


# ---------------------------------------------------------------------------
# Parameters
# ---------------------------------------------------------------------------

def parameter_values(low, high, step, digits=6):
    """Values from ``low`` to ``high`` inclusive by ``step`` (rounded, no float drift)."""
    if step <= 0:
        raise ValueError("step must be positive")
    if high < low:
        raise ValueError("range maximum is below its minimum")
    n = int(np.floor((high - low) / step + 1e-9)) + 1
    return [round(low + i * step, digits) for i in range(n)]


# ---------------------------------------------------------------------------
# Segments
# ---------------------------------------------------------------------------

def relabel(segments):
    """Segment ids made consecutive: ``(index, n)`` with index -1 on no data.

    ``index`` has the shape of ``segments``; ids keep their order.
    """
    segments = np.asarray(segments)
    valid = segments > 0
    index = np.full(segments.shape, -1, dtype=np.int64)
    ids, inverse = np.unique(segments[valid], return_inverse=True)
    index[valid] = inverse
    return index, len(ids)


def _band_stack(bands):
    bands = [np.asarray(b, dtype=np.float64) for b in bands]
    if not bands:
        raise ValueError("at least one band is needed")
    shape = bands[0].shape
    if any(b.shape != shape for b in bands):
        raise ValueError("bands and segments must have the same shape")
    return bands


def adjacent_pairs(index):
    """Unique pairs (a, b), a < b, of segments sharing an edge (4-neighbours)."""
    codes = []
    n = int(index.max()) + 1 if index.size else 1
    for a, b in ((index[:, :-1], index[:, 1:]), (index[:-1, :], index[1:, :])):
        keep = (a != b) & (a >= 0) & (b >= 0)
        lo = np.minimum(a[keep], b[keep]).astype(np.int64)
        hi = np.maximum(a[keep], b[keep]).astype(np.int64)
        codes.append(lo * n + hi)
    codes = np.unique(np.concatenate(codes))  # one sort of int64 codes, not of rows
    return np.stack([codes // n, codes % n], axis=1)


def segmentation_criteria(segments, bands):
    """Area-weighted variance (VW) and Moran's I of one segmentation.

    For each band: VW = sum(a_i * var_i) / sum(a_i) over segments i (a_i the
    number of cells, var_i the variance of the band inside segment i), and
    Moran's I of the segment means with binary weights between segments that
    share an edge. Both are averaged over the bands. Low VW means homogeneous
    segments, low Moran's I means segments distinct from their neighbours.
    """
    index, n = relabel(segments)
    bands = _band_stack(bands)
    if bands[0].shape != index.shape:
        raise ValueError("bands and segments must have the same shape")
    valid = index >= 0
    for band in bands:
        valid &= np.isfinite(band)
    seg = index[valid]
    area = np.bincount(seg, minlength=n).astype(float)
    pairs = adjacent_pairs(np.where(valid, index, -1))
    present = area > 0
    vws, morans = [], []
    for band in bands:
        x = band[valid]
        total = np.bincount(seg, weights=x, minlength=n)
        total2 = np.bincount(seg, weights=x * x, minlength=n)
        with np.errstate(invalid="ignore", divide="ignore"):
            mean = np.where(present, total / np.maximum(area, 1), 0.0)
            var = np.where(present, total2 / np.maximum(area, 1) - mean * mean, 0.0)
        var = np.maximum(var, 0.0)
        vws.append(float((area * var).sum() / max(area.sum(), 1.0)))
        z = mean[present] - mean[present].mean() if present.any() else np.zeros(0)
        zfull = np.zeros(n)
        zfull[present] = z
        denominator = float((z * z).sum())
        if len(pairs) and denominator > 0:
            cross = float((zfull[pairs[:, 0]] * zfull[pairs[:, 1]]).sum())
            morans.append(present.sum() * cross / (len(pairs) * denominator))
        else:
            morans.append(0.0)
    return float(np.mean(vws)), float(np.mean(morans))


def normalise(values):
    """(max - x) / (max - min) over all values: 1 is best (lowest), 0 worst.

    All values equal give 1 everywhere.
    """
    values = np.asarray(values, dtype=float)
    span = values.max() - values.min()
    if not np.isfinite(span) or span <= 0:
        return np.ones_like(values)
    return (values.max() - values) / span


def f_function(sa_norm, vw_norm, alpha=1.0):
    """F = (1 + a^2) SA VW / (a^2 SA + VW), 0 where both criteria are 0."""
    sa_norm = np.asarray(sa_norm, dtype=float)
    vw_norm = np.asarray(vw_norm, dtype=float)
    a2 = float(alpha) ** 2
    denominator = a2 * sa_norm + vw_norm
    with np.errstate(invalid="ignore", divide="ignore"):
        f = np.where(denominator > 0, (1 + a2) * sa_norm * vw_norm / denominator, 0.0)
    return f


def tune(criteria, alpha=1.0):
    """Choose the best segmentation from its criteria.

    ``criteria`` is a sequence of (VW, Moran's I), one per tried parameter
    pair. Returns a :class:`TuningResult` with the raw and normalised
    criteria, F per pair and the index of the best pair (the first of equals).
    """
    criteria = np.asarray(criteria, dtype=float).reshape(-1, 2)
    if not len(criteria):
        raise ValueError("no segmentation to choose from")
    vw, moran = criteria[:, 0], criteria[:, 1]
    vw_norm, moran_norm = normalise(vw), normalise(moran)
    f = f_function(moran_norm, vw_norm, alpha)
    return TuningResult(vw, moran, vw_norm, moran_norm, f, int(np.argmax(f)))


# ---------------------------------------------------------------------------
# Object features
# ---------------------------------------------------------------------------

def feature_names(n_bands):
    names = ["b{}_{}".format(b + 1, s) for b in range(n_bands) for s in BAND_STATISTICS]
    return names + list(SHAPE_FEATURES)


def _sorted_quantiles(sorted_values, starts, counts, q):
    """Quantile q (linear interpolation, as numpy's default) of each run."""
    pos = starts + (counts - 1) * q
    lo = np.floor(pos).astype(np.int64)
    hi = np.ceil(pos).astype(np.int64)
    frac = pos - lo
    return sorted_values[lo] * (1 - frac) + sorted_values[hi] * frac


def segment_perimeters(index, n):
    """Perimeter of each segment in cell edges (region border and no data count)."""
    padded = np.pad(index, 1, constant_values=-1)
    perimeter = np.zeros(n)
    for a, b in ((padded[:, :-1], padded[:, 1:]), (padded[:-1, :], padded[1:, :])):
        edge = a != b
        for side in (a, b):
            ids = side[edge]
            ids = ids[ids >= 0]
            perimeter += np.bincount(ids, minlength=n)
    return perimeter


def segment_features(segments, bands):
    """Object features of every segment.

    Returns ``(ids, features)``: the sorted segment ids present and an
    (n_segments, 5 * n_bands + 5) array with, per band, mean, median,
    variance, first and third quartile; then area and perimeter (in cells and
    cell edges), compact square 4 sqrt(area) / perimeter, compact circle
    perimeter / (2 sqrt(pi area)) and fractal dimension
    2 log(perimeter) / log(area + 0.0001), as r.object.geometry computes them
    in cell units. Column names: :func:`feature_names`. No-data cells
    (segment <= 0 or a non-finite band value) are left out of the band
    statistics.
    """
    segments = np.asarray(segments)
    bands = _band_stack(bands)
    if bands[0].shape != segments.shape:
        raise ValueError("bands and segments must have the same shape")
    valid_ids = segments > 0
    ids = np.unique(segments[valid_ids])
    index, n = relabel(segments)
    area = np.bincount(index[valid_ids], minlength=n).astype(float)
    columns = []
    for band in bands:
        ok = valid_ids & np.isfinite(band)
        seg = index[ok]
        x = band[ok]
        counts = np.bincount(seg, minlength=n)
        order = np.lexsort((x, seg))
        sx = x[order]
        starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
        has = counts > 0
        safe_counts = np.maximum(counts, 1)
        safe_starts = np.minimum(starts, max(len(sx) - 1, 0))
        mean = np.bincount(seg, weights=x, minlength=n) / safe_counts
        var = np.maximum(np.bincount(seg, weights=x * x, minlength=n) / safe_counts - mean ** 2, 0)
        if len(sx):
            quantiles = [_sorted_quantiles(sx, safe_starts, safe_counts, q) for q in (0.5, 0.25, 0.75)]
        else:
            quantiles = [np.zeros(n)] * 3
        median, q1, q3 = (np.where(has, q, np.nan) for q in quantiles)
        columns += [np.where(has, mean, np.nan), median, np.where(has, var, np.nan), q1, q3]
    perimeter = segment_perimeters(index, n)
    with np.errstate(divide="ignore", invalid="ignore"):
        compact_square = 4 * np.sqrt(area) / perimeter
        compact_circle = perimeter / (2 * np.sqrt(np.pi * area))
        fractal = 2 * np.log(perimeter) / np.log(area + 0.0001)
    columns += [area, perimeter, compact_square, compact_circle, fractal]
    features = np.stack(columns, axis=1)
    return ids, features


def select_features(features, n_bands, groups=("spectral", "size")):
    """Columns of :func:`segment_features` for the chosen feature groups.

    ``spectral``: the band statistics; ``size``: area and perimeter, as
    logarithms (so that distances in kNN and SVM are not ruled by the few
    very large segments); ``shape``: compact square, compact circle and
    fractal dimension.
    """
    features = np.asarray(features, dtype=float)
    unknown = [g for g in groups if g not in FEATURE_GROUPS]
    if unknown or not groups:
        raise ValueError("feature groups must be among {}".format(", ".join(FEATURE_GROUPS)))
    nb = 5 * n_bands
    parts = []
    if "spectral" in groups:
        parts.append(features[:, :nb])
    if "size" in groups:
        with np.errstate(divide="ignore", invalid="ignore"):
            parts.append(np.log(np.maximum(features[:, nb:nb + 2], 1.0)))
    if "shape" in groups:
        parts.append(features[:, nb + 2:nb + 5])
    return np.concatenate(parts, axis=1)


def finite_features(features):
    """Features with non-finite values replaced by the column median (0 if none)."""
    features = np.array(features, dtype=float)
    bad = ~np.isfinite(features)
    if bad.any():
        with np.errstate(all="ignore"):
            good = np.where(bad, np.nan, features)
            fill = np.nanmedian(good, axis=0) if features.shape[0] else np.zeros(features.shape[1])
        fill = np.where(np.isfinite(fill), fill, 0.0)
        features[bad] = np.take(fill, np.nonzero(bad)[1])
    return features


# ---------------------------------------------------------------------------
# Training points and classifiers
# ---------------------------------------------------------------------------

def make_classifiers(names=CLASSIFIERS, seed=0, n_jobs=1, n_samples=None):
    """The scikit-learn estimators of the ensemble, by name, in the given order.

    - ``rf``: random forest of 500 trees;
    - ``knn``: k nearest neighbours on standardised features (k = 5, at most
      the number of samples), weighted by distance;
    - ``svm``: support vector machine with a radial kernel on standardised
      features.
    """
    from sklearn.ensemble import RandomForestClassifier
    from sklearn.neighbors import KNeighborsClassifier
    from sklearn.pipeline import make_pipeline
    from sklearn.preprocessing import StandardScaler
    from sklearn.svm import SVC

    k = 5 if n_samples is None else max(1, min(5, n_samples))
    built = {
        "rf": lambda: RandomForestClassifier(n_estimators=500, random_state=seed, n_jobs=n_jobs),
        "knn": lambda: make_pipeline(StandardScaler(), KNeighborsClassifier(n_neighbors=k, weights="distance")),
        "svm": lambda: make_pipeline(StandardScaler(), SVC(kernel="rbf", C=10.0, gamma="scale",
                                                            random_state=seed)),
    }
    unknown = [n for n in names if n not in built]
    if unknown:
        raise ValueError("unknown classifier(s): {}".format(", ".join(unknown)))
    return [(name, built[name]()) for name in names]


def majority_vote(predictions):
    """Label chosen by most classifiers; ties go to the first classifier.

    ``predictions`` is (n_classifiers, n_samples); row 0 is the tie-breaker
    (the random forest in the default order).
    """
    predictions = np.asarray(predictions)
    if predictions.ndim == 1:
        return predictions.copy()
    n_clf = predictions.shape[0]
    votes = np.zeros(predictions.shape, dtype=np.int64)
    for i in range(n_clf):
        votes += predictions == predictions[i]
    # the first classifier whose label has the most votes (row order breaks ties)
    best = np.argmax(votes, axis=0)
    return predictions[best, np.arange(predictions.shape[1])]


def classify_segments(features, train_rows, train_labels, classifiers=CLASSIFIERS, seed=0, n_jobs=1):
    """Fit the ensemble on the training segments and predict every segment.

    ``features`` is (n_segments, n_features); ``train_rows`` the feature row of
    each training point, ``train_labels`` its class label. Returns the voted
    label per segment and a dict classifier -> its own predictions.
    """
    features = finite_features(features)
    train_rows = np.asarray(train_rows, dtype=np.int64)
    models = fit_ensemble(features[train_rows], train_labels, classifiers, seed, n_jobs)
    return predict_ensemble(models, features)


def fit_ensemble(x_train, train_labels, classifiers=CLASSIFIERS, seed=0, n_jobs=1):
    """The ensemble's models fitted on training features ``x_train`` (finite),
    as (name, model) pairs in the order of ``classifiers``."""
    train_labels = np.asarray(train_labels)
    if len(np.unique(train_labels)) < 2:
        raise ValueError("training needs at least two classes")
    models = make_classifiers(classifiers, seed, n_jobs, len(train_labels))
    for _name, model in models:
        model.fit(x_train, train_labels)
    return models


def predict_ensemble(models, features):
    """Voted label per row of ``features`` (made finite) and each model's predictions."""
    features = finite_features(features)
    predictions = {name: model.predict(features) for name, model in models}
    voted = majority_vote(np.stack([predictions[name] for name, _model in models]))
    return voted, predictions


# ---------------------------------------------------------------------------
# Removal of classes (text, symbols) and of small regions
# ---------------------------------------------------------------------------

def object_thickness(mask):
    """Largest thickness (in cells) over the objects of a boolean mask.

    The thickness of an object is its longest transect across its median
    line: twice the largest distance from the median line to the object's
    edge, minus the centre cell (a one-cell line has thickness 1). 0 for an
    empty mask.
    """
    mask = np.asarray(mask, dtype=bool)
    if not mask.any():
        return 0.0
    distance = ndimage.distance_transform_edt(np.pad(mask, 1))
    return float(2 * distance.max() - 1)


def removal_window(mask):
    """Moving window size from the objects to remove: thickness / 2 + 1, odd, >= 3."""
    return window_for_thickness(object_thickness(mask))


def window_for_thickness(thickness):
    """Moving window size for removed objects ``thickness`` cells thick: thickness / 2 + 1,
    odd, >= 3."""
    window = int(thickness / 2.0 + 1)
    if window % 2 == 0:
        window += 1
    return max(window, 3)


def _window_counts(binary, window):
    """Number of True cells in the window x window box around each cell."""
    r = window // 2
    padded = np.pad(binary.astype(np.int32), ((r + 1, r), (r + 1, r)))
    integral = padded.cumsum(axis=0).cumsum(axis=1)
    return (integral[window:, window:] - integral[:-window, window:]
            - integral[window:, :-window] + integral[:-window, :-window])


def fill_from_surroundings(classes, holes, window=3, iterations=None, nodata=0, exclude=()):
    """Fill ``holes`` with the modal class of the surrounding cells.

    Each iteration gives every hole cell with at least one known cell (not a
    hole, not ``nodata``, not an ``exclude`` label) in its window x window
    neighbourhood the most frequent known class there (the lowest label among
    equals); filled cells are known in the next iteration, as repeated
    r.neighbors method=mode would do. Stops when no hole is left, nothing
    changes, or after ``iterations``. Returns ``(filled classes, remaining
    holes)``.
    """
    classes = np.array(classes, copy=True)
    holes = np.array(holes, dtype=bool, copy=True)
    if window < 1 or window % 2 == 0:
        raise ValueError("window must be a positive odd number")
    done = 0
    while holes.any() and (iterations is None or done < iterations):
        known = ~holes & (classes != nodata)
        if len(exclude):
            known &= ~np.isin(classes, list(exclude))
        labels = np.unique(classes[known])
        if not len(labels):
            break
        # work only on the bounding box of the holes, grown by the window
        rows, cols = np.nonzero(holes)
        r = window // 2
        r0, r1 = max(rows.min() - r, 0), min(rows.max() + r + 1, classes.shape[0])
        c0, c1 = max(cols.min() - r, 0), min(cols.max() + r + 1, classes.shape[1])
        sub_classes = classes[r0:r1, c0:c1]
        sub_known = known[r0:r1, c0:c1]
        sub_holes = holes[r0:r1, c0:c1]
        best_count = np.zeros(sub_classes.shape, dtype=np.int32)
        best_label = np.zeros(sub_classes.shape, dtype=classes.dtype)
        for label in labels:
            count = _window_counts(sub_known & (sub_classes == label), window)
            better = count > best_count
            best_count[better] = count[better]
            best_label[better] = label
        fill = sub_holes & (best_count > 0)
        if not fill.any():
            break
        sub_classes[fill] = best_label[fill]
        sub_holes[fill] = False
        done += 1
    return classes, holes


def fill_from_nearest(classes, holes, window=3, reach=None, nodata=0, exclude=()):
    """Fill ``holes`` with the class of the nearest known cells.

    Known cells are those that are not holes, not ``nodata`` and not an
    ``exclude`` label. Each hole cell takes the label of the known cell
    closest to it (Euclidean distance between cell centres); when cells of
    several labels are equally close, the one with the most known cells in
    the window x window neighbourhood wins (the lowest label among equals;
    the default 3 x 3 is the cell's immediate neighbours: a wider window
    brings back the bias below).
    Two classes on either side of a hole thus meet halfway across it,
    whichever of them has more cells around: the modal class of a window
    alone (:func:`fill_from_surroundings`) favours the class whose cells the
    hole did not cover, a solid plot beside a street cut up by the letters
    of its name, and lets it grow across the hole. Cells farther than
    ``reach`` cells from every known cell stay holes. Returns ``(filled
    classes, remaining holes)``.
    """
    classes = np.array(classes, copy=True)
    holes = np.array(holes, dtype=bool, copy=True)
    known = ~holes & (classes != nodata)
    if len(exclude):
        known &= ~np.isin(classes, list(exclude))
    labels = np.unique(classes[known])
    if not holes.any() or not len(labels):
        return classes, holes
    distances = np.stack([ndimage.distance_transform_edt(~(known & (classes == label)))
                          for label in labels])
    nearest = distances.min(axis=0)
    # the window's count of each equally near label; the others never win
    votes = np.stack([np.where(d <= nearest + 1e-9, _window_counts(known & (classes == label),
                                                                    window), -1)
                      for label, d in zip(labels, distances)])
    fill = holes if reach is None else holes & (nearest <= reach)
    classes[fill] = labels[votes.argmax(axis=0)][fill]
    holes[fill] = False
    return classes, holes


_FOUR = ndimage.generate_binary_structure(2, 1)
_EIGHT = np.ones((3, 3), dtype=bool)


def small_regions(classes, min_cells, nodata=0):
    """Cells of 4-connected single-class regions smaller than ``min_cells``."""
    classes = np.asarray(classes)
    small = np.zeros(classes.shape, dtype=bool)
    if min_cells <= 1:
        return small
    for label in np.unique(classes):
        if label == nodata:
            continue
        regions, n = ndimage.label(classes == label, _FOUR)
        if not n:
            continue
        sizes = np.bincount(regions.ravel(), minlength=n + 1)
        tiny = sizes < min_cells
        tiny[0] = False
        small |= tiny[regions]
    return small


def thin_parts(classes, width, nodata=0):
    """Cells of every class that a width x width square cannot cover (opening)."""
    classes = np.asarray(classes)
    thin = np.zeros(classes.shape, dtype=bool)
    if width <= 1:
        return thin
    square = np.ones((width, width), dtype=bool)
    for label in np.unique(classes):
        if label == nodata:
            continue
        mask = classes == label
        thin |= mask & ~ndimage.binary_opening(mask, square, border_value=1)
    return thin


#: a cell lies between two regions when the directions to their nearest cells are at
#: least this far apart (degrees): across a street, not beside two corners
BETWEEN = 135.0


def _facing_gaps(regions, ids, hole, distance, share=0.25):
    """The gaps between the regions ``ids`` that face each other beside ``hole``.

    The front of two regions is the cells outside them within ``distance``
    of both. Two plots on either side of a street face each other along the
    street beyond the street name printed in it: a good part of their front
    (at least ``share`` of the part inside the hole) lies outside the hole
    *between* them (the directions to the two plots' nearest cells at least
    :data:`BETWEEN` apart: across the street). The two pieces of one plot cut
    by a label meet only through the label: outside it, their front is the
    lens beside the two corners of the cut, in the streets on either side,
    which lies beside both pieces, not between them. Returns the union of
    the fronts of the pairs that face each other (empty when none do): the
    street between two plots, not the plot a label cut, nor the other
    plots the same hole touches (a label across a block and the streets on
    either side, joined to the plots' outline strokes along the streets).
    """
    free = ~np.isin(regions, ids)
    cells = np.indices(regions.shape)
    near, toward = [], []
    for i in ids:
        d, nearest = ndimage.distance_transform_edt(regions != i, return_indices=True)
        near.append((d <= distance) & free)
        toward.append((nearest - cells).astype(float))
    limit = np.cos(np.radians(BETWEEN))
    gaps = np.zeros(hole.shape, dtype=bool)
    for a in range(len(near)):
        for b in range(a + 1, len(near)):
            front = near[a] & near[b]
            if not front.any():
                continue
            va, vb = toward[a][:, front], toward[b][:, front]
            cos = (va * vb).sum(axis=0) / np.maximum(
                np.hypot(*va) * np.hypot(*vb), 1e-12)
            between = np.zeros(hole.shape, dtype=bool)
            between[front] = cos <= limit
            inside = int((front & hole).sum())
            outside = int((between & ~hole).sum())
            if outside > 0 and outside >= share * inside:
                gaps |= front
    return gaps


def bridges(before, after, holes, min_cells=1, distance=3, nodata=0, labels=None):
    """Filled cells that join separate objects of their class.

    ``before`` holds the classes with the holes not filled yet, ``after``
    the filled result. For each class (or only ``labels``), the hole
    components (8-connected) whose filled cells of that class join two or
    more regions of at least ``min_cells`` cells (4-connected) that were
    apart are checked: where two of those regions also face each other within
    ``distance`` cells along a front that goes on beside the hole
    (:func:`_facing_gaps`), they are separate objects (two plots across a
    narrow street, the hole a street name printed between them) and the
    hole's cells of that class in the gap between them are returned; where
    two meet only through the hole, the hole had cut one object in two and
    the fill restores it.
    """
    before = np.asarray(before)
    after = np.asarray(after)
    holes = np.asarray(holes, dtype=bool)
    known = ~holes & (before != nodata)
    components, _ = ndimage.label(holes, _EIGHT)
    joined = np.zeros(before.shape, dtype=bool)
    margin = int(np.ceil(distance)) + 2
    for label in np.unique(after[holes]) if labels is None else labels:
        if label == nodata:
            continue
        pre, n_pre = ndimage.label(known & (before == label), _FOUR)
        if n_pre < 2:
            continue
        sizes = np.bincount(pre.ravel(), minlength=n_pre + 1)
        small = sizes < max(min_cells, 1)
        small[0] = True
        pre[small[pre]] = 0
        filled = holes & (after == label)
        # regions touching each hole component's filled cells of this class
        grown = ndimage.grey_dilation(np.where(filled, components, 0), footprint=_EIGHT)
        touch = (pre > 0) & (grown > 0)
        pairs = np.unique(np.stack([grown[touch], pre[touch]], axis=1), axis=0)
        per_component = np.bincount(pairs[:, 0], minlength=components.max() + 1)
        # where each region ends up after the fill
        post, _ = ndimage.label(after == label, _FOUR)
        index = np.zeros(n_pre + 1, dtype=np.int64)
        index[pre.ravel()] = post.ravel()
        for component in np.flatnonzero(per_component >= 2):
            ids = pairs[pairs[:, 0] == component, 1]
            ends = index[ids]
            shared = np.unique(ends)[np.bincount(np.unique(ends, return_inverse=True)[1]) >= 2]
            ids = ids[np.isin(ends, shared)]
            if len(ids) < 2:
                continue  # the fill joined nothing that was apart
            rows, cols = np.nonzero(components == component)
            r0, r1 = max(rows.min() - margin, 0), rows.max() + margin + 1
            c0, c1 = max(cols.min() - margin, 0), cols.max() + margin + 1
            hole = components[r0:r1, c0:c1] == component
            gaps = _facing_gaps(pre[r0:r1, c0:c1], ids, hole, distance)
            joined[r0:r1, c0:c1] |= gaps & hole & filled[r0:r1, c0:c1]
    return joined


def remove_classes(classes, remove, window=None, iterations=None, min_cells=0, min_width=0,
                   separate=(), nodata=0):
    """Remove classes (e.g. text, symbols), thin parts and tiny regions from a class raster.

    1. Holes: the cells of the ``remove`` labels, the thin parts of every
       other class (narrower than ``min_width`` cells, :func:`thin_parts`) and
       its regions smaller than ``min_cells`` cells (a minimum mapping unit,
       :func:`small_regions`), such as pieces of letters classified as
       something else.
    2. The holes are refilled from their surroundings, each cell with the
       class of the nearest known cell (:func:`fill_from_nearest`, ties by
       the 3 x 3 neighbourhood); with
       ``iterations``, only as far as that many passes of the window would
       reach (``iterations`` x ``window // 2`` cells). The window is computed
       from the thickness of the removed objects (:func:`removal_window`)
       unless given.
    3. For the ``separate`` labels (e.g. buildings): where the fill of a
       hole joins two regions of such a class that were apart within the
       window (a street name printed across a narrow street between two
       plots), that class is refused there and the hole is refilled from the
       nearest of the other classes around.
    4. Regions left smaller than ``min_cells`` are refilled once more (the
       modal class of their 3 x 3 surroundings, :func:`fill_from_surroundings`).

    Returns ``(classes, window used)``; cells that could not be filled (no
    known cell within reach) become ``nodata``.
    """
    classes = np.asarray(classes)
    removed = np.isin(classes, list(remove)) if len(remove) else np.zeros(classes.shape, bool)
    if window is None:
        window = removal_window(removed)
    base = np.where(removed, nodata, classes)
    holes = removed.copy()
    if min_width > 1:
        holes |= thin_parts(base, min_width, nodata)
    if min_cells > 1:
        holes |= small_regions(base, min_cells, nodata)
    holes &= classes != nodata
    before = np.where(holes, nodata, classes)
    reach = None if iterations is None else iterations * (window // 2)
    out, left = fill_from_nearest(classes, holes, reach=reach, nodata=nodata)
    for label in separate:
        joined = bridges(before, out, holes, min_cells, window, nodata, labels=(label,))
        if joined.any():
            refilled, still = fill_from_nearest(out, joined, reach=reach, nodata=nodata,
                                                exclude=(label,))
            refilled[still] = label
            out = refilled
    out[left] = nodata
    if min_cells > 1:
        small = small_regions(out, min_cells, nodata)
        if small.any():
            out, left = fill_from_surroundings(out, small, 3, iterations, nodata)
            out[left] = nodata
    return out, window


def class_raster(index, segment_labels, nodata=0):
    """Map the label of each segment (by relabelled index) back onto the cells."""
    segment_labels = np.asarray(segment_labels)
    out = np.full(index.shape, nodata, dtype=segment_labels.dtype if len(segment_labels) else np.int32)
    valid = index >= 0
    out[valid] = segment_labels[index[valid]]
    return out
