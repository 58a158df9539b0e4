"""How much work a parameter asks for, estimated before doing it (issue 12, item 2).

Some numeric options multiply the work without bound: an alpha of a
millimetre samples billions of points, a facade length of a millimetre cuts
millions of facades, a threshold step of a millionth runs i.segment tens of
thousands of times. Each check here estimates the work from the parameter
and the data (plot areas and perimeters, footprint density), before any of
it is done, and raises :class:`~reconstruction.core.errors.InputError` naming the
option, what it would cost and the value from which it is reasonable.
"""

import math

import numpy as np

from .errors import InputError

#: most points v.histo.generalize's alpha shapes may sample in all (about 25 us each)
MAX_ALPHA_POINTS = 2_000_000
#: smallest facade length and building depth of v.histo.subdivide: narrower
#: footprints are slivers, which the subdivision merges away (convex_rings.MIN_WIDTH)
MIN_FACADE = 2.0
#: most i.segment runs of r.histo.classify's tuning grid
MAX_SEGMENTATIONS = 100
#: lowest crow step of v.histo.lod2 (m): a facade of many more steps is no crow-stepped gable
MIN_CROW_STEP = 0.1
#: most (footprint, plot) candidate pairs of v.histo.align's buffer
MAX_ALIGN_PAIRS = 5_000_000
#: most raster cells of v.histo.align's offset correlations, over all plots
MAX_SHIFT_CELLS = 2_000_000_000


def _fmt(value):
    """A number for a message: 3 significant digits, no exponent for usual sizes."""
    return "{:.3g}".format(value) if 1e-3 <= abs(value) < 1e6 else "{:g}".format(value)


def alpha_points(areas, perimeters, alpha):
    """Points the alpha shapes of plots with these ``areas`` and
    ``perimeters`` sample at ``alpha`` (see
    :func:`reconstruction.generalize.operators.alpha_generalize`: the interior
    every alpha / 2, the boundary every alpha / 4)."""
    return float(4.0 * np.sum(areas) / alpha ** 2 + 4.0 * np.sum(perimeters) / alpha)


def check_alpha(polygons, alpha, limit=MAX_ALPHA_POINTS):
    """Refuse an ``alpha`` whose alpha shapes of ``polygons`` would sample
    more than ``limit`` points, saying from which alpha it is reasonable."""
    areas = np.array([p.area for p in polygons], dtype=float)
    perimeters = np.array([p.length for p in polygons], dtype=float)
    points = alpha_points(areas, perimeters, alpha)
    if points <= limit:
        return
    # 4 A u^2 + 4 L u = limit for u = 1 / alpha
    a, b = 4.0 * areas.sum(), 4.0 * perimeters.sum()
    u = (-b + math.sqrt(b * b + 4.0 * a * limit)) / (2.0 * a) if a > 0 else limit / b
    raise InputError(
        "alpha={} asks for about {:,.0f} sample points in the {} plots (at most {:,}; "
        "a million take about half a minute): use alpha >= {} "
        "(the default is 12 cells)".format(_fmt(alpha), points, len(polygons), limit,
                                     _fmt(1.001 / u)))


def check_facades(length, depth, minimum=MIN_FACADE):
    """Refuse facade lengths or building depths (min, max) below ``minimum``:
    the subdivision would cut footprints narrower than the slivers it merges
    away, at a cost that grows with the inverse square of the length."""
    for key, (low, high), default in (("length", length, "5,8"), ("depth", depth, "12,16")):
        if low < minimum:
            raise InputError(
                "{}={},{}: footprints narrower than {:g} map units are slivers that the "
                "subdivision merges away, and cutting them costs without bound (length=0.5 "
                "takes 60 times as long as 5); give a {} of at least {:g} (the default is "
                "{})".format(key, _fmt(low), _fmt(high), minimum,
                             "facade length" if key == "length" else "building depth",
                             minimum, default))


def _steps(low, high, step):
    return int(math.floor((high - low) / step + 1e-9)) + 1


def check_segmentations(threshold, threshold_step, minsize, minsize_step,
                        limit=MAX_SEGMENTATIONS):
    """Refuse a tuning grid of more than ``limit`` i.segment runs: ``threshold``
    and ``minsize`` are (min, max) ranges with their steps."""
    n_t = _steps(threshold[0], threshold[1], threshold_step)
    n_m = _steps(minsize[0], minsize[1], minsize_step)
    if n_t * n_m <= limit:
        return
    if n_m >= limit:
        hint = "minsize_step >= {}{}".format(
            int(math.ceil((minsize[1] - minsize[0]) / (limit - 1))),
            "" if n_t == 1 else " and a single threshold (threshold={0},{0})".format(
                _fmt(threshold[0])))
    else:
        per = max(limit // n_m, 1)
        step = (threshold[1] - threshold[0]) / max(per - 1, 1)
        hint = "threshold_step >= {}".format(_fmt(step * 1.0001)) if per > 1 else \
            "a single threshold"
    raise InputError(
        "threshold={},{} by {} and minsize={},{} by {} ask for {:,} segmentations (each one "
        "i.segment run over the map; at most {}): use {}".format(
            _fmt(threshold[0]), _fmt(threshold[1]), _fmt(threshold_step), minsize[0],
            minsize[1], minsize_step, n_t * n_m, limit, hint))


def check_crow_steps(step, minimum=MIN_CROW_STEP):
    """Refuse crow steps (min, max) lower than ``minimum`` (m)."""
    if step[0] < minimum:
        raise InputError(
            "step={},{}: crow steps lower than {:g} m would give facades of hundreds of steps "
            "(and arrays growing with their square); give steps of at least {:g} m (the "
            "default is 0.4,0.7)".format(_fmt(step[0]), _fmt(step[1]), minimum, minimum))


def check_alignment(plots, footprints, buffer, shift=0.0, window=150.0, cell=1.0,
                    max_pairs=MAX_ALIGN_PAIRS, max_cells=MAX_SHIFT_CELLS, grid_cells=40_000_000):
    """Refuse a ``buffer`` or ``shift`` larger than the maps themselves, a
    ``buffer`` that would pair more than ``max_pairs`` candidate
    footprints with plots (estimated from the footprints' density over their
    extent), and a ``shift`` search whose correlations would cover more than
    ``max_cells`` raster cells over all plots (the grid's cell grows beyond
    ``grid_cells`` cells, as :func:`reconstruction.align.stage.estimate_shifts`)."""
    import shapely

    plots = np.asarray(plots, dtype=object)
    footprints = np.asarray(footprints, dtype=object)
    if not len(plots) or not len(footprints):
        return
    pb = shapely.bounds(plots)
    w, h = pb[:, 2] - pb[:, 0], pb[:, 3] - pb[:, 1]
    ax0, ay0, ax1, ay1 = shapely.total_bounds(np.concatenate([plots, footprints]))
    diagonal = math.hypot(ax1 - ax0, ay1 - ay0)
    for key, value in (("buffer", buffer), ("shift", shift)):
        if value > diagonal:
            raise InputError(
                "{}={} is larger than the maps themselves (the plots and footprints span "
                "{:.0f} map units): every footprint would be a candidate of every plot; "
                "use {} <= {:.0f} (the default {})".format(
                    key, _fmt(value), diagonal, key, diagonal,
                    "is 10; a few times the maps' pixel size" if key == "buffer"
                    else "search is off; a few metres to tens of metres"))
    fx0, fy0, fx1, fy1 = shapely.total_bounds(footprints)
    extent = max((fx1 - fx0) * (fy1 - fy0), 1.0)
    density = len(footprints) / extent

    def pairs(b):
        return float(density * np.minimum((w + 2 * b) * (h + 2 * b), extent).sum())

    if pairs(buffer) > max_pairs:
        lo = _largest_within(pairs, buffer, max_pairs)
        raise InputError(
            "buffer={} pairs about {:,.0f} candidate footprints with the {} plots (at most "
            "{:,}): use buffer <= {} (the default is 10; a few times the maps' pixel "
            "size)".format(_fmt(buffer), pairs(buffer), len(plots), max_pairs, _fmt(lo)))
    if shift <= 0:
        return
    x0, y0, x1, y1 = shapely.total_bounds(plots)

    def cells(s):
        margin = window + s + cell
        c = max(cell, math.sqrt((x1 - x0 + 2 * margin) * (y1 - y0 + 2 * margin) / grid_cells))
        return float((((w + 2 * (window + s)) / c + 1) * ((h + 2 * (window + s)) / c + 1)).sum())

    if cells(shift) > max_cells:
        lo = _largest_within(cells, shift, max_cells)
        raise InputError(
            "shift={} (with shift_window={}) asks for correlations over about {:,.0f} raster "
            "cells (at most {:,}): use shift <= {} or a smaller shift_window".format(
                _fmt(shift), _fmt(window), cells(shift), max_cells, _fmt(lo)))


def _largest_within(work, value, limit):
    """The largest value in [0, ``value``] whose ``work(value)`` (growing with
    it) stays within ``limit``, by bisection."""
    lo, hi = 0.0, value
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if work(mid) <= limit else (lo, mid)
    return lo
