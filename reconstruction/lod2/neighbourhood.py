"""Heights of footprints without measurements, from measured neighbours.

Two rules, both from the aligned footprints' measured heights (eaves above
the ground and total height = eaves + attic; attic = total - eaves):

- ``plot`` -- the thesis's neighbourhood analysis (Section 3.4.1, its
  ``assign_height_using_neighbours``): a plot gets the median of its aligned
  footprints; a plot without any gets the median over its neighbouring plots
  (plots within ``plot_distance``, or the 5 nearest where none is that
  close), revisited until every plot is resolved; its generated footprints
  inherit it. One tall aligned building (a church, a tower) then gives its
  height to every generated footprint of its plot (the thesis's Fig. 5.23).
- ``robust`` (the default) -- per footprint, from the aligned footprints
  within ``radius`` (300 m; the 256 nearest at most):

  1. *outliers are no donors*: with the median ``M`` and the MAD (scaled to
     a standard deviation, at least 10 % of ``M``) of the neighbours'
     heights, a neighbour further than ``k_mad`` (3) MADs from ``M`` (the
     tower among houses) gives nothing;
  2. *size*: bigger footprints are taller (on Delft 1880, Spearman 0.69
     between area and total height, 0.34 for the eaves): each neighbour's
     total height is moved by ``beta * log(area / its area)``, ``beta``
     fitted on the measured footprints themselves (leave-one-out against
     their own neighbours); the eaves are not (it made them worse);
  3. *proximity*: the weighted median of those heights, weights
     ``1 / (distance + offset)`` (2 m offset; the distance between the
     footprints' outlines, between their centres beyond 60 m), so the houses
     of the same row count most, the district still a good deal;
  4. the result is kept within ``M +- k_mad * MAD`` and within the
     neighbours' range.

  A footprint with no aligned footprint within ``radius`` falls back to the
  plot rule. Chosen and measured on Delft 1880 (674 aligned footprints in
  184 plots; 5-fold cross-validation, seed 0, in
  ``reconstruction/testsuite/lod2/test_neighbourhood.py``): mean / 90th
  percentile absolute error of the eaves 1.39 / 2.94 m (plot rule 1.53 /
  3.22 m), of the total height 1.09 / 2.38 m (plot rule 1.43 / 3.07 m);
  better on all four figures for every seed tried (0-7). Without the size
  step the total height's are 1.22 / 2.64 m; with it on the eaves too, the
  eaves' are 1.40 / 2.98 m. The radius (300 m) and the offset (2 m) were
  chosen on these folds.

Every footprint gets a source label: ``measured``, ``plot`` (its plot's own
aligned footprints), ``neighbours`` (aligned footprints around it or
neighbouring plots), or ``""`` when nothing was measured anywhere.
"""

from dataclasses import dataclass
from typing import Optional

import numpy as np

from ..core.contract import HEIGHTS_MEASURED, HEIGHTS_NEIGHBOURS, HEIGHTS_PLOT
from ..core.errors import InputError
from .groupstats import group_median

MEASURED, PLOT, NEIGHBOURS = HEIGHTS_MEASURED, HEIGHTS_PLOT, HEIGHTS_NEIGHBOURS
#: MAD of a normal distribution -> its standard deviation
_MAD_SCALE = 1.4826


@dataclass(frozen=True)
class HeightRule:
    """How heights are inferred (lengths in metres)."""

    method: str = "robust"
    radius: float = 300.0
    offset: float = 2.0
    k_mad: float = 3.0
    area: bool = True
    #: the plot rule: plots closer than this are neighbours
    plot_distance: float = 20.0
    #: the plot rule: plots with no neighbour that close take their nearest ones
    plot_nearest: int = 5
    #: exact boundary distances for footprints whose centres are closer than this;
    #: beyond, the distance of the centres (the weights hardly differ there)
    near: float = 60.0
    #: at most this many nearest aligned footprints count
    donors: int = 256
    #: the uncertainty interval of an inferred height: these weighted quantiles of the
    #: neighbours' heights it comes from (issue 31; on Delft 1880's held-out aligned
    #: footprints, see InferredHeights)
    interval: tuple = (0.1, 0.9)

    def __post_init__(self):
        if self.method not in ("robust", "plot"):
            raise InputError("Unknown height rule <{}> (known: robust, plot)".format(self.method))
        if self.radius <= 0 or self.offset <= 0 or self.k_mad <= 0:
            raise InputError("The height rule's radius, offset and k_mad must be positive")


@dataclass(frozen=True)
class Plots:
    """Plot polygons and their ids (the ``plot`` values of the footprints)."""

    geometries: np.ndarray
    ids: np.ndarray


@dataclass(frozen=True)
class InferredHeights:
    """Eaves (above the ground) and attic (above the eaves) of every footprint,
    NaN where nothing could be inferred, and where each came from; ``low`` and
    ``high`` (F, 2): the interval of the eaves and of the total height (eaves
    + attic), the value itself where measured, the rule's quantiles of the
    neighbours' heights (:attr:`HeightRule.interval`) where the robust rule
    inferred it, NaN where the plot rule did (it gives no spread)."""

    eaves: np.ndarray
    attic: np.ndarray
    source: np.ndarray
    low: Optional[np.ndarray] = None
    high: Optional[np.ndarray] = None

    @property
    def total(self):
        return self.eaves + self.attic

    def count(self, label):
        return int(np.sum(self.source == label))


def _geometry_array(geoms):
    out = np.empty(len(geoms), dtype=object)
    out[:] = list(geoms)
    return out


def _centres(geoms):
    import shapely

    return shapely.get_coordinates(shapely.centroid(geoms)).reshape(-1, 2)


# ---------------------------------------------------------------------------
# The thesis's rule: plot medians, neighbouring plots
# ---------------------------------------------------------------------------

def _plot_neighbours(n, geoms, distance, nearest):
    """Pairs (a, b) of neighbouring plots: closer than ``distance``, or the
    ``nearest`` plots by centre for a plot with none that close."""
    import shapely
    from scipy.spatial import cKDTree

    a, b = shapely.STRtree(geoms).query(geoms, predicate="dwithin", distance=distance)
    keep = a != b
    a, b = a[keep], b[keep]
    lonely = np.setdiff1d(np.arange(n), a)
    if len(lonely) and n > 1:
        k = min(nearest + 1, n)
        _, nb = cKDTree(_centres(geoms)).query(_centres(geoms[lonely]), k=k)
        nb = nb.reshape(len(lonely), -1)
        la = np.repeat(lonely, nb.shape[1])
        lb = nb.ravel()
        keep = la != lb
        a, b = np.concatenate([a, la[keep]]), np.concatenate([b, lb[keep]])
    return a, b


def _plot_index(plot_ids, plot):
    """Index in ``plot_ids`` of every value of ``plot`` (-1: None or not a plot)."""
    lookup = {p: i for i, p in enumerate(plot_ids)}
    return np.array([lookup.get(p, -1) if p is not None and p == p else -1 for p in plot],
                    dtype=np.int64)


def plot_heights(plot_ids, plot_geoms, known_plot, known_values, distance=20.0, nearest=5):
    """The thesis's plot-level neighbourhood analysis.

    ``plot_ids`` (P,) and ``plot_geoms`` (P,) the plots; ``known_plot`` (K,)
    the plot id of each measured footprint, ``known_values`` (K, Q) its
    measured heights. Returns ``(values (P, Q), source (P,))``: the median of
    the plot's own measured footprints (``plot``), else the median over its
    neighbouring plots (``neighbours``), revisited until no plot is left
    (NaN and ``""`` only when nothing at all is measured).
    """
    plot_ids = np.asarray(plot_ids, dtype=object)
    P = len(plot_ids)
    values = np.asarray(known_values, dtype=float)
    if values.ndim != 2:               # (K,) one height each; (0, Q) stays as it is
        values = values.reshape(len(known_plot), -1)
    Q = values.shape[1]
    which = _plot_index(plot_ids, known_plot)
    hit = which >= 0
    which = which[hit]
    out = np.full((P, Q), np.nan)
    for q in range(Q):
        good = np.isfinite(values[hit, q])
        out[:, q] = group_median(values[hit, q][good], which[good], P)
    source = np.where(np.isfinite(out[:, 0]), PLOT, "").astype(object)
    if P == 0 or not np.isfinite(out[:, 0]).any():
        return out, source
    a, b = _plot_neighbours(P, _geometry_array(plot_geoms), distance, nearest)
    while True:
        missing = ~np.isfinite(out[:, 0])
        if not missing.any():
            break
        use = missing[a] & ~missing[b]
        if not use.any():
            # islands of plots without any measured neighbour: their nearest resolved plots
            from scipy.spatial import cKDTree

            done = np.nonzero(~missing)[0]
            k = min(nearest, len(done))
            c = _centres(_geometry_array(plot_geoms))
            _, nb = cKDTree(c[done]).query(c[missing], k=k)
            nb = done[np.asarray(nb).reshape(int(missing.sum()), -1)]
            a = np.concatenate([a, np.repeat(np.nonzero(missing)[0], nb.shape[1])])
            b = np.concatenate([b, nb.ravel()])
            continue
        for q in range(Q):
            med = group_median(out[b[use], q], a[use], P)
            out[:, q] = np.where(missing, med, out[:, q])
        source = np.where(missing & np.isfinite(out[:, 0]), NEIGHBOURS, source).astype(object)
    return out, source


# ---------------------------------------------------------------------------
# The robust rule
# ---------------------------------------------------------------------------

def _neighbours(t_geoms, d_geoms, rule, exclude_self=False):
    """The ``rule.donors`` nearest donors of every target within ``rule.radius``:
    (T, K) donor index (K = none) and distance (inf = none); centre distance,
    boundary distance below ``rule.near``."""
    import shapely
    from scipy.spatial import cKDTree

    K = len(d_geoms)
    k = min(rule.donors + (1 if exclude_self else 0), K)
    dist, idx = cKDTree(_centres(d_geoms)).query(_centres(t_geoms), k=k,
                                                 distance_upper_bound=rule.radius)
    dist, idx = dist.reshape(len(t_geoms), k), idx.reshape(len(t_geoms), k)
    if exclude_self:
        self_ = idx == np.arange(len(t_geoms))[:, None]
        dist, idx = np.where(self_, np.inf, dist), np.where(self_, K, idx)
    close = np.nonzero(dist < rule.near)
    if len(close[0]):
        dist[close] = shapely.distance(t_geoms[close[0]], d_geoms[idx[close]])
    return idx, dist


def _row_median(v):
    """Median of every row of (T, K) ignoring NaN (NaN for empty rows)."""
    n = np.sum(np.isfinite(v), axis=1)
    s = np.sort(v, axis=1)                       # NaN sort last
    lo = np.clip((n - 1) // 2, 0, None)
    hi = np.clip(n // 2, 0, None)
    rows = np.arange(len(v))
    k = max(v.shape[1] - 1, 0)
    med = 0.5 * (s[rows, np.minimum(lo, k)] + s[rows, np.minimum(hi, k)]) if v.shape[1] else \
        np.full(len(v), np.nan)
    return np.where(n > 0, med, np.nan)


def _row_weighted_quantile(v, w, q):
    """Weighted ``q`` quantile (0-1: the first value whose cumulative weight reaches
    ``q`` of the row's) of every row (NaN values and their weights ignored)."""
    w = np.where(np.isfinite(v), w, 0.0)
    order = np.argsort(np.where(np.isfinite(v), v, np.inf), axis=1, kind="stable")
    sv = np.take_along_axis(v, order, axis=1)
    cw = np.cumsum(np.take_along_axis(w, order, axis=1), axis=1)
    total = cw[:, -1:] if v.shape[1] else np.zeros((len(v), 1))
    first = np.argmax(cw >= q * total - 1e-12 * np.maximum(total, 1.0), axis=1)
    out = sv[np.arange(len(v)), first] if v.shape[1] else np.full(len(v), np.nan)
    return np.where(total[:, 0] > 0, out, np.nan)


def _row_weighted_median(v, w):
    """Weighted median of every row (NaN values and their weights ignored)."""
    return _row_weighted_quantile(v, w, 0.5)


def _robust_estimate(v, dist, la_t, la_d, beta, rule, quantiles=()):
    """Per target row: the rule's estimate of one height from its neighbours'
    heights ``v`` (T, K) (NaN = no neighbour) at distances ``dist``; with
    ``quantiles``, also the weighted quantiles of the same neighbours' heights
    (outliers left out, moved by the size step, the same weights): a list of
    (T,) arrays after the estimate."""
    n = np.sum(np.isfinite(v), axis=1)
    M = _row_median(v)
    mad = np.maximum(_MAD_SCALE * _row_median(np.abs(v - M[:, None])), 0.1 * np.abs(M))
    big = n >= 3
    out = big[:, None] & (np.abs(v - M[:, None]) > rule.k_mad * mad[:, None])
    v = np.where(out, np.nan, v)
    adj = v + beta * (la_t[:, None] - la_d)
    weights = 1.0 / (dist + rule.offset)
    est = _row_weighted_median(adj, weights)
    est = np.where(big, np.clip(est, M - rule.k_mad * mad, M + rule.k_mad * mad), est)
    with np.errstate(invalid="ignore"):
        lo, hi = np.nanmin(np.where(np.isfinite(v), v, np.inf), axis=1), \
            np.nanmax(np.where(np.isfinite(v), v, -np.inf), axis=1)
    est = np.where(np.isfinite(lo), np.clip(est, lo, hi), est)
    if not quantiles:
        return est
    return [est] + [_row_weighted_quantile(adj, weights, q) for q in quantiles]


def _area_slope(self_idx, self_dist, values, la_d, rule):
    """The height-per-log-area slope: measured footprints against their own
    neighbours (``self_idx``, ``self_dist`` from :func:`_neighbours`, leave one
    out), least squares through the origin."""
    if not rule.area or len(values) < 10:
        return 0.0
    w = 1.0 / (self_dist + rule.offset)
    x = la_d - _row_weighted_median(np.append(la_d, np.nan)[self_idx], w)
    y = values - _row_weighted_median(np.append(values, np.nan)[self_idx], w)
    ok = np.isfinite(x) & np.isfinite(y)
    sxx = float(np.sum(x[ok] ** 2))
    return float(np.sum(x[ok] * y[ok]) / sxx) if sxx > 1e-9 else 0.0


def robust_heights(targets, donors, donor_values, rule=None, sized=None, interval=None):
    """The robust rule for footprints ``targets`` from measured footprints
    ``donors`` with heights ``donor_values`` (K, Q), estimated column by
    column; ``sized`` (Q,) says which columns take the size step (default:
    all, when ``rule.area``). Returns (T, Q) estimates, NaN where no donor is
    within the radius; with ``interval`` (low, high quantiles, e.g. (0.1,
    0.9)), also the (T, Q) low and high ends of the neighbours' heights'
    weighted quantiles: ``(estimates, low, high)``."""
    import shapely

    rule = rule or HeightRule()
    t_geoms, d_geoms = _geometry_array(targets), _geometry_array(donors)
    values = np.asarray(donor_values, dtype=float).reshape(len(d_geoms), -1)
    good = np.all(np.isfinite(values), axis=1)
    d_geoms, values = d_geoms[good], values[good]
    T, Q = len(t_geoms), values.shape[1]
    out = np.full((T, Q), np.nan)
    low, high = out.copy(), out.copy()
    if not T or not len(d_geoms):
        return out if interval is None else (out, low, high)
    la_t = np.log(np.maximum(shapely.area(t_geoms), 1e-6))
    la_d = np.log(np.maximum(shapely.area(d_geoms), 1e-6))
    sized = np.broadcast_to(np.asarray(True if sized is None else sized, dtype=bool), (Q,)) \
        & rule.area & (len(d_geoms) >= 10)
    idx, dist = _neighbours(t_geoms, d_geoms, rule)
    if sized.any():
        self_idx, self_dist = _neighbours(d_geoms, d_geoms, rule, exclude_self=True)
    la_pad = np.append(la_d, np.nan)[idx]
    for q in range(Q):
        beta = _area_slope(self_idx, self_dist, values[:, q], la_d, rule) if sized[q] else 0.0
        v = np.append(values[:, q], np.nan)[idx]
        if interval is None:
            out[:, q] = _robust_estimate(v, dist, la_t, la_pad, beta, rule)
        else:
            out[:, q], low[:, q], high[:, q] = _robust_estimate(v, dist, la_t, la_pad, beta,
                                                                rule, tuple(interval))
    return out if interval is None else (out, low, high)


# ---------------------------------------------------------------------------
# Every footprint
# ---------------------------------------------------------------------------

def infer_heights(footprints, eaves, attic, plot=None, plots=None, rule=None,
                  measured_label=MEASURED):
    """Eaves and attic of every footprint: its own where measured, else inferred.

    ``footprints`` (F,) polygons; ``eaves``, ``attic`` (F,) measured heights,
    NaN where unknown (generated footprints; to add measured footprints that
    are not among those to build, append them and drop their results);
    ``plot`` (F,) plot id of each footprint (None: unknown); ``plots``
    (:class:`Plots`) the plot polygons for the plot rule's neighbours (without
    them a plot's place is the hull of its footprints); ``rule``: a
    :class:`HeightRule`; ``measured_label``: the source label of the measured
    footprints (``points`` for heights from building points).
    """
    rule = rule or HeightRule()
    geoms = _geometry_array(footprints)
    F = len(geoms)
    eaves = np.asarray(eaves, dtype=float).reshape(F)
    attic = np.asarray(attic, dtype=float).reshape(F)
    known = np.isfinite(eaves) & np.isfinite(attic) & (eaves > 0)
    values = np.stack([eaves, eaves + np.maximum(attic, 0.0)], axis=1)
    out = np.where(known[:, None], values, np.nan)
    low, high = out.copy(), out.copy()
    source = np.where(known, measured_label, "").astype(object)
    todo = np.nonzero(~known)[0]
    if not len(todo) or not known.any():
        return _result(out, source, low, high)
    if rule.method == "robust":
        # the size step for the total height only: the roof grows with the
        # span; the eaves (storeys) do not follow the area (it made them worse)
        est, lo, hi = robust_heights(geoms[todo], geoms[known], values[known], rule,
                                     sized=(False, True), interval=rule.interval)
        got = np.isfinite(est).all(axis=1)
        # the estimate, kept within M +- k MAD and the neighbours' range after the
        # size step moved their heights, can stand outside their moved
        # quantiles: the interval holds it still
        out[todo[got]] = est[got]
        low[todo[got]] = np.fmin(lo[got], est[got])
        high[todo[got]] = np.fmax(hi[got], est[got])
        source[todo[got]] = NEIGHBOURS
        todo = todo[~got]
    if len(todo) and plot is not None:
        plot = np.asarray(plot, dtype=object).reshape(F)
        if plots is None:
            ids = np.array(list(dict.fromkeys(p for p in plot if p is not None and p == p)),
                           dtype=object)
            index = _plot_index(ids, plot)
            has = index >= 0
            pg = _plot_hulls(geoms[has], index[has], len(ids))
        else:
            ids = np.asarray(plots.ids, dtype=object)
            index = _plot_index(ids, plot)
            pg = _geometry_array(plots.geometries)
        use = known & (index >= 0)
        pv, ps = plot_heights(ids, pg, plot[use], values[use], rule.plot_distance,
                              rule.plot_nearest)
        idx = index[todo]
        got = idx >= 0
        got[got] &= np.isfinite(pv[idx[got], 0])
        out[todo[got]] = pv[idx[got]]
        source[todo[got]] = ps[idx[got]]
        todo = todo[~got]
    if len(todo):
        # no plot to go by: the median of the nearest measured footprints
        from scipy.spatial import cKDTree

        k = min(rule.plot_nearest, int(known.sum()))
        _, nb = cKDTree(_centres(geoms[known])).query(_centres(geoms[todo]), k=k)
        nb = np.asarray(nb).reshape(len(todo), -1)
        out[todo] = np.median(values[known][nb], axis=1)
        source[todo] = NEIGHBOURS
    return _result(out, source, low, high)


def _plot_hulls(geoms, owner, n):
    """One polygon per plot: the convex hull of its footprints (for plot distances)."""
    import shapely

    parts = [[] for _ in range(n)]
    for g, o in zip(geoms, owner):
        parts[o].append(g)
    return _geometry_array([shapely.convex_hull(shapely.GeometryCollection(p)) for p in parts])


def _result(values, source, low=None, high=None):
    eaves = values[:, 0]
    attic = np.maximum(values[:, 1] - values[:, 0], 0.0)
    return InferredHeights(eaves, np.where(np.isfinite(eaves), attic, np.nan), source, low,
                           high)
