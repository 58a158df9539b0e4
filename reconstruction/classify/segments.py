"""Object-based classification of a scanned historical map.

The thesis's first stage (Morlighem 2021, Section 3.2.1, after Gobbi et al.
2019), as pure functions over numpy arrays:

- segmentation quality criteria for unsupervised parameter optimisation:
  area-weighted intra-segment variance (VW) and inter-segment spatial
  autocorrelation (Moran's I), their normalisation over all tried parameter
  pairs and the F-function combining them;
- object features per segment (band statistics, also of the CIELAB
  lightness and colour of an RGB scan, and shape indices), computed for all
  segments at once with ``np.bincount`` and one sort per band;
- an ensemble of random forest, k-nearest-neighbours and SVM classifiers with
  a majority vote;
- the segments' classes as a raster (:func:`class_raster`).

The removal of classes such as text and symbols is in
:mod:`~reconstruction.classify.removal`.

Arrays are (rows, cols); a segment array holds integer ids with ``0`` (or any
value <= 0) for no data. Nothing here imports GRASS.
"""

from dataclasses import dataclass

import numpy as np

#: Names of the features of :func:`segment_features`, per band then shape.
BAND_STATISTICS = ("mean", "median", "variance", "q1", "q3")
SHAPE_FEATURES = ("area", "perimeter", "compact_square", "compact_circle", "fractal_dimension")
CLASSIFIERS = ("rf", "knn", "svm")
#: Feature groups a classification can use: band statistics, the same of the
#: CIELAB L*, a*, b* of the first three bands (red, green, blue), size, shape
#: indices, what a segment is filled with (ink, hatching and its direction:
#: :func:`reconstruction.classify.lines.fill_features`, given by the caller).
FEATURE_GROUPS = ("spectral", "lab", "size", "shape", "fill")
#: The groups that are columns of :func:`segment_features` (lab: of bands derived first)
COLUMN_GROUPS = ("spectral", "size", "shape")
#: CIELAB's reference white (D65) in XYZ, and sRGB's linear RGB -> XYZ matrix
_WHITE = np.array([0.95047, 1.0, 1.08883])
_SRGB_TO_XYZ = np.array([[0.4124564, 0.3575761, 0.1804375],
                         [0.2126729, 0.7151522, 0.0721750],
                         [0.0193339, 0.1191920, 0.9503041]])


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


def cielab(red, green, blue):
    """CIELAB lightness L* and colour a*, b* (D65) of 8-bit sRGB bands (0-255;
    arrays of one shape, no data NaN): three arrays.

    A wash of colour thinned on white paper keeps its hue in a*, b* while its
    RGB values approach the paper's: the pale pink of a parcel and the white
    of a courtyard are 10 apart in green and 6 in a* (from 0), the pink
    parcels 12 (Venice 1808).
    """
    rgb = np.stack([np.asarray(b, dtype=float) for b in (red, green, blue)], axis=-1) / 255.0
    rgb = np.clip(rgb, 0.0, 1.0)
    linear = np.where(rgb > 0.04045, ((rgb + 0.055) / 1.055) ** 2.4, rgb / 12.92)
    xyz = linear @ _SRGB_TO_XYZ.T / _WHITE
    f = np.where(xyz > (6 / 29) ** 3, np.cbrt(xyz), xyz / (3 * (6 / 29) ** 2) + 4 / 29)
    return 116 * f[..., 1] - 16, 500 * (f[..., 0] - f[..., 1]), 200 * (f[..., 1] - f[..., 2])


def object_features(segments, bands, groups=("spectral", "size"), fill=None):
    """The features the classifiers use for every segment: ``(ids, features)``,
    the sorted segment ids present and, per segment, the statistics of the
    bands (``spectral``), of their :func:`cielab` colour (``lab``: the first
    three bands must be red, green and blue), then the size and shape columns
    of :func:`select_features` (``size``, ``shape``), then (``fill``) the rows of
    ``fill``, one per segment present in the order of their ids; the statistics
    of only the bands a group asks for are computed."""
    unknown = [g for g in groups if g not in FEATURE_GROUPS]
    if unknown or not groups:
        raise ValueError("feature groups must be among {}".format(", ".join(FEATURE_GROUPS)))
    if ("fill" in groups) != (fill is not None):
        raise ValueError("the fill features are given with the group fill, and only then")
    bands = list(_band_stack(bands))
    stats = (bands if "spectral" in groups else []) + (
        list(cielab(*bands[:3])) if "lab" in groups else [])
    # a band is needed for the shape columns alone: the segments give those
    ids, features = segment_features(segments, stats or bands[:1])
    n_stats = len(stats) or 1
    parts = [features[:, :5 * len(stats)]]
    others = tuple(g for g in groups if g in COLUMN_GROUPS and g != "spectral")
    if others:
        parts.append(select_features(features, n_stats, others))
    if fill is not None:
        fill = np.asarray(fill, dtype=float)
        if len(fill) != len(ids):
            raise ValueError("fill has {} rows for {} segments".format(len(fill), len(ids)))
        parts.append(fill)
    return ids, np.concatenate(parts, axis=1)


def select_features(features, n_bands, groups=("spectral", "size")):
    """Columns of :func:`segment_features` for the chosen feature groups.

    ``spectral``: the band statistics; ``size``: area and perimeter, as
    logarithms (so that distances in kNN and SVM are not ruled by the few
    very large segments); ``shape``: compact square, compact circle and
    fractal dimension. (``lab``: see :func:`object_features`.)
    """
    features = np.asarray(features, dtype=float)
    unknown = [g for g in groups if g not in COLUMN_GROUPS]
    if unknown or not groups:
        raise ValueError("feature groups must be among {}".format(", ".join(COLUMN_GROUPS)))
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
# The segments' classes as a raster (removal of classes: removal.py)
# ---------------------------------------------------------------------------

def class_raster(index, segment_labels, nodata=0):
    """Map the label of each segment (by relabelled index) back onto the cells."""
    segment_labels = np.asarray(segment_labels)
    out = np.full(index.shape, nodata, dtype=segment_labels.dtype if len(segment_labels) else np.int32)
    valid = index >= 0
    out[valid] = segment_labels[index[valid]]
    return out
