"""Statistics of many small groups of values at once (no Python loop per group).

``groups`` gives the group number (0 .. n-1) of each value; empty groups get
NaN. Used for the percentiles of the points of every footprint and for the
medians of every footprint's neighbours.
"""

import numpy as np


def _sorted(values, groups, n):
    """Values sorted by group then value, the start of each group and its size."""
    values = np.asarray(values, dtype=float)
    groups = np.asarray(groups, dtype=np.int64)
    order = np.lexsort((values, groups))
    counts = np.bincount(groups, minlength=n)
    starts = np.cumsum(counts) - counts
    return values[order], order, starts, counts


def group_percentiles(values, groups, n, percentiles):
    """(n, P) percentiles (numpy's linear interpolation) of the values of every group."""
    ordered, _, starts, counts = _sorted(values, groups, n)
    q = np.asarray(percentiles, dtype=float).reshape(1, -1) / 100.0
    out = np.full((n, q.shape[1]), np.nan)
    has = counts > 0
    pos = (counts[has, None] - 1) * q
    lo = np.floor(pos).astype(np.int64)
    hi = np.minimum(lo + 1, counts[has, None] - 1)
    frac = pos - lo
    base = starts[has, None]
    out[has] = ordered[base + lo] * (1 - frac) + ordered[base + hi] * frac
    return out


def group_median(values, groups, n):
    """(n,) median of the values of every group."""
    return group_percentiles(values, groups, n, [50.0])[:, 0]


def group_weighted_median(values, weights, groups, n):
    """(n,) weighted median of every group: its smallest value at which the
    cumulated weight reaches half the group's weight."""
    ordered, order, starts, counts = _sorted(values, groups, n)
    w = np.asarray(weights, dtype=float)[order]
    g = np.asarray(groups, dtype=np.int64)[order]
    cum = np.cumsum(w)
    before = np.concatenate([[0.0], cum])[starts]          # weight of the earlier groups
    total = np.bincount(g, weights=w, minlength=n)
    out = np.full(n, np.nan)
    # the first value of each group whose cumulated weight reaches half its total
    reached = cum - before[g] >= 0.5 * total[g] - 1e-12 * np.maximum(total[g], 1.0)
    first = np.full(n, -1, dtype=np.int64)
    hits = np.nonzero(reached)[0]
    gh = g[hits]
    keep = np.ones(len(hits), dtype=bool)
    keep[1:] = gh[1:] != gh[:-1]
    first[gh[keep]] = hits[keep]
    ok = (counts > 0) & (first >= 0)
    out[ok] = ordered[first[ok]]
    return out
