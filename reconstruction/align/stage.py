"""One-to-many alignment of historical building plots with current footprints.

A building older than the map may still stand; its real current footprint
then subdivides the historical plot better than any procedure can
(Morlighem 2021, Section 3.3.1). Every plot is grown by a buffer (the two
maps never coincide exactly), and a current footprint ``b`` that was built
before the map's year matches plot ``a`` when

    similarity(a, b) = area(b ∩ buffer(a)) / min(area(b), area(buffer(a)))

(the thesis's Eq. 3.9 on the buffered plot) reaches the threshold. A
footprint inside the buffered plot scores 1 whatever its size; one that
matches several plots goes to the one with the highest similarity, and
between equal similarities to the plot that holds more of it (then to the
first plot). The buffer is a distance, or Ying et al.'s (2011)
``k * sqrt(SR_a**2 + SR_b**2)`` from the two maps' resolutions.

Beyond the thesis: old map sheets are often shifted against today's
footprints by several metres (georeferencing of old sheets is inaccurate;
the thesis's Section 5.3.1), and a larger buffer then matches wrong
buildings. :func:`estimate_shifts` finds, per plot, the translation within
a search radius that lays the candidate footprints of the plot's
neighbourhood best onto the plots (the peak of the cross-correlation of the
two rasterised maps: buildings that are not on the map only lower the peak,
they do not move it), and :func:`align` matches each plot at its shifted
place. The footprints keep their own geometry.

Everything here is pure: shapely 2 geometries and numpy, no GRASS. Lengths
are in map units (metres).
"""

import math
from dataclasses import asdict, dataclass
from typing import Optional

import numpy as np
import shapely

from ..core.errors import InputError
# construction_years and PLACEHOLDER_YEAR: importable from here as before core.register
from ..core.register import PLACEHOLDER_YEAR, construction_years  # noqa: F401
from ..core.work_limits import check_alignment
from ..geom.polygons import cells_inside
# AlignmentConfig and buffer_from_resolution: importable from here as before config.py
from .config import AlignmentConfig, buffer_from_resolution, matching_options  # noqa: F401

#: similarities this close to the threshold count as reaching it (rounding of areas)
SIMILARITY_TOLERANCE = 1e-9
#: most raster cells of the offset estimate (its cell grows beyond that)
MAX_SHIFT_CELLS = 40_000_000
#: the offset is the centre of the correlation peak down to this share below its top
PEAK_TOLERANCE = 0.02
#: neighbouring plots' offsets agree when they differ by at most this (map units)
AGREEMENT = 1.5
#: a plot's shift needs this many neighbours' estimates (or all there are)
MIN_AGREEING = 3


@dataclass(frozen=True)
class AlignmentReport:
    """What :func:`align` did, in counts (``counts()`` gives the key=value set of -g)."""

    footprints: int = 0        # current footprints given
    without_year: int = 0      # no year (NULL, empty, placeholder): left out
    after_year: int = 0        # built in or after the map's year: left out
    candidates: int = 0        # built before the map's year
    aligned: int = 0           # candidates that matched a plot
    contested: int = 0         # aligned footprints that matched more than one plot
    unmatched: int = 0         # candidates that matched no plot
    plots: int = 0             # plots with an area
    plots_matched: int = 0     # plots with at least one aligned footprint
    shifted_plots: int = 0     # plots matched at a shifted place (offset correction)
    repaired: int = 0          # invalid geometries repaired

    def counts(self):
        return asdict(self)


@dataclass(frozen=True)
class PlotShifts:
    """Offset of the map against the footprints, per plot (same order as the plots).

    A footprint moved by (``dx``, ``dy``) lies where the map draws it (0
    where no shift is applied). ``gain``: the plot's own estimate, overlap
    of plots and footprints at the best shift divided by the overlap
    without it; ``applied``: whether the plot is matched at the shifted
    place (:func:`estimate_shifts`, then :func:`align`).
    """

    dx: np.ndarray
    dy: np.ndarray
    gain: np.ndarray
    applied: np.ndarray


@dataclass(frozen=True)
class Alignment:
    """The result of :func:`align`; indices refer to the footprints given."""

    aligned: np.ndarray          # indices of the aligned footprints, ascending
    plot: np.ndarray             # category of the plot each one went to
    similarity: np.ndarray       # its similarity with that plot
    unmatched: np.ndarray        # indices of the candidates that matched no plot
    best_similarity: np.ndarray  # highest similarity each unmatched one reached (0: none)
    shifts: Optional[PlotShifts]  # None without the offset correction
    report: AlignmentReport


def _polygonal(geometries):
    """Geometries as a numpy array of valid polygonal geometries (None where there is no area);
    and how many had to be repaired."""
    geoms = np.empty(len(geometries), dtype=object)
    geoms[:] = list(geometries)
    present = ~shapely.is_missing(geoms)
    invalid = present & ~shapely.is_valid(geoms)
    repaired = int(invalid.sum())
    for i in np.flatnonzero(invalid):
        fixed = shapely.make_valid(geoms[i])
        parts = [p for p in shapely.get_parts(fixed) if p.geom_type in ("Polygon", "MultiPolygon")]
        geoms[i] = shapely.union_all(parts) if parts else None
    present = ~shapely.is_missing(geoms)
    area = np.zeros(len(geoms))
    area[present] = shapely.area(geoms[present])
    geoms[area <= 0] = None
    return geoms, repaired


def _translate(geoms, dx, dy):
    """Copies of ``geoms`` each moved by its own (dx, dy)."""
    coords, index = shapely.get_coordinates(geoms, return_index=True)
    coords = coords + np.column_stack([dx, dy])[index]
    return shapely.set_coordinates(np.array(geoms, dtype=object).copy(), coords)


# ---------------------------------------------------------------------------
# Offset correction
# ---------------------------------------------------------------------------

def _fast_length(n):
    """The smallest length >= n with no prime factor above 5 (fast for an FFT)."""
    best = 1 << max(int(n - 1).bit_length(), 0)
    p5 = 1
    while p5 < best:
        p35 = p5
        while p35 < best:
            p = p35
            while p < n:
                p *= 2
            best = min(best, p)
            p35 *= 3
        p5 *= 5
    return best


def _correlation(plots, footprints, reach):
    """``out[a, b] = sum(plots[y, x] * footprints[y + a, x + b])`` for a, b in [0, 2 reach],
    by FFT (``footprints`` is ``plots`` grown by ``reach`` cells on every side)."""
    shape = tuple(_fast_length(n) for n in footprints.shape)
    f = np.fft.rfft2(footprints.astype(np.float32), shape)
    p = np.fft.rfft2(plots.astype(np.float32), shape)
    full = np.fft.irfft2(f * np.conj(p), shape)
    return np.rint(full[:2 * reach + 1, :2 * reach + 1])


def _grow_within(seed, mask):
    """The cells of ``mask`` connected (8-neighbours) to the ``seed`` cells."""
    region = seed & mask
    while True:
        rows = region.copy()
        rows[1:] |= region[:-1]
        rows[:-1] |= region[1:]
        grown = rows.copy()
        grown[:, 1:] |= rows[:, :-1]
        grown[:, :-1] |= rows[:, 1:]
        grown &= mask
        if np.array_equal(grown, region):
            return region
        region = grown


def _peak(corr, tolerance=PEAK_TOLERANCE):
    """Sub-cell position (row, col) of the maximum of a correlation surface.

    The centre of mass of the cells around the maximum that come within
    ``tolerance`` (a share) of it: the peak itself where it is sharp (a map
    whose plots fit the footprints' street fronts), the middle of the
    plateau where it is flat (footprints that fit inside the plots at many
    shifts, e.g. plots drawn smaller than the blocks).
    """
    top = corr.max()
    floor = top * (1 - tolerance)
    seed = np.zeros(corr.shape, dtype=bool)
    seed[np.unravel_index(np.argmax(corr), corr.shape)] = True
    region = _grow_within(seed, corr >= floor)
    weight = np.where(region, corr - floor, 0.0)
    if weight.sum() <= 0:
        weight = region.astype(float)
    rows, cols = np.indices(corr.shape)
    return float((weight * rows).sum() / weight.sum()), float((weight * cols).sum() / weight.sum())


def _local_shifts(plots, footprints, radius, window, cell, min_gain):
    """Each plot's own estimate: (dx, dy, gain, valid) arrays (see :func:`estimate_shifts`)."""
    n = len(plots)
    dx, dy, gain = np.zeros(n), np.zeros(n), np.ones(n)
    valid = np.zeros(n, dtype=bool)
    plot_ok = ~shapely.is_missing(plots)
    minx, miny, maxx, maxy = shapely.total_bounds(plots[plot_ok])
    margin = window + radius + cell
    x0, y0, x1, y1 = minx - margin, miny - margin, maxx + margin, maxy + margin
    cell = max(cell, math.sqrt((x1 - x0) * (y1 - y0) / MAX_SHIFT_CELLS))
    nx, ny = int(math.ceil((x1 - x0) / cell)), int(math.ceil((y1 - y0) / cell))
    near = shapely.STRtree(footprints).query(shapely.box(x0, y0, x1, y1))
    plot_mask = cells_inside(plots[plot_ok], x0, y1, (cell, cell), (ny, nx))
    foot_mask = cells_inside(footprints[near], x0, y1, (cell, cell), (ny, nx))
    reach = int(math.ceil(radius / cell))
    pad = int(math.ceil(window / cell))
    bounds = shapely.bounds(plots)
    for i in np.flatnonzero(plot_ok):
        bx0, by0, bx1, by1 = bounds[i]
        c0 = max(int(math.floor((bx0 - x0) / cell)) - pad, reach)
        c1 = min(int(math.ceil((bx1 - x0) / cell)) + pad, nx - reach)
        r0 = max(int(math.floor((y1 - by1) / cell)) - pad, reach)
        r1 = min(int(math.ceil((y1 - by0) / cell)) + pad, ny - reach)
        corr = _correlation(plot_mask[r0:r1, c0:c1],
                            foot_mask[r0 - reach:r1 + reach, c0 - reach:c1 + reach], reach)
        best, still = corr.max(), corr[reach, reach]
        if best <= 0:
            continue
        top_row, top_col = np.unravel_index(np.argmax(corr), corr.shape)
        a, b = _peak(corr)
        # out[a, b] pairs plot row y with footprint row y + a: the footprints
        # move reach - a rows down (south) and reach - b columns east
        dx[i], dy[i] = (reach - b) * cell, (a - reach) * cell
        gain[i] = best / still if still > 0 else np.inf
        # a peak on the edge of the search: the offset is beyond the radius, or there is none
        inside = 0 < top_row < 2 * reach and 0 < top_col < 2 * reach
        valid[i] = inside and best >= still * (1 + min_gain)
    return dx, dy, gain, valid


def estimate_shifts(plots, footprints, radius, window=150.0, cell=1.0, min_gain=0.02,
                    agree=AGREEMENT):
    """The offset of the map against the footprints around every plot (:class:`PlotShifts`).

    ``plots`` and ``footprints`` are polygonal geometries (None is skipped).
    For each plot, the plots and footprints within ``window`` of it are
    rasterised at ``cell``, and the translation within ``radius`` that
    maximises their overlap (the peak of the cross-correlation) is its own
    estimate; it counts when the peak lies inside the search and raises the
    overlap by ``min_gain`` (a share) over no shift. Buildings that are not
    on the map (built later, or missing from it) lower the peak but do not
    move it.

    The shift of a plot is then the median of the estimates that count
    among the plots within ``window`` of it (its neighbourhood; a
    georeferencing error is shared by neighbouring plots), applied when
    most of them agree with that median within ``agree`` and there are at
    least three (or all there are): a lone estimate off a flat correlation
    is noise, and a plot with too few buildings of its own takes its
    neighbours' shift.
    """
    plots = np.asarray(plots, dtype=object)
    n = len(plots)
    shifts = PlotShifts(np.zeros(n), np.zeros(n), np.ones(n), np.zeros(n, dtype=bool))
    plot_ok = ~shapely.is_missing(plots)
    footprints = np.asarray(footprints, dtype=object)
    footprints = footprints[~shapely.is_missing(footprints)]
    if radius <= 0 or not plot_ok.any() or len(footprints) == 0:
        return shifts
    dx, dy, gain, valid = _local_shifts(plots, footprints, radius, window, cell, min_gain)
    shifts = PlotShifts(shifts.dx, shifts.dy, gain, shifts.applied)
    counted = np.flatnonzero(valid)
    if not len(counted):
        return shifts
    needed = min(MIN_AGREEING, len(counted))
    centres = shapely.centroid(plots[counted])
    tree = shapely.STRtree(centres)
    for i in np.flatnonzero(plot_ok):
        mine = counted[tree.query(shapely.centroid(plots[i]), predicate="dwithin",
                                  distance=window)]
        if len(mine) < needed:
            continue
        mx, my = np.median(dx[mine]), np.median(dy[mine])
        agreeing = np.hypot(dx[mine] - mx, dy[mine] - my) <= agree
        if agreeing.sum() >= needed and agreeing.mean() >= 0.5:
            shifts.dx[i], shifts.dy[i] = mx, my
            shifts.applied[i] = True
    return shifts


# ---------------------------------------------------------------------------
# Matching
# ---------------------------------------------------------------------------

def candidate_mask(years, config):
    """Which footprints are candidates (built before the map's year) and which have no year."""
    years = np.asarray(years, dtype=float)
    known = np.isfinite(years)
    before = np.zeros(len(years), dtype=bool)
    before[known] = (years[known] <= config.year) if config.include_year else (
        years[known] < config.year)
    return before, ~known


@dataclass(frozen=True)
class _Pairs:
    """Plot-footprint pairs whose buffered plot and footprint intersect."""

    plot: np.ndarray        # plot index
    footprint: np.ndarray   # candidate index
    similarity: np.ndarray
    inside: np.ndarray      # area of the footprint inside the (unbuffered) plot

    def take(self, keep):
        return _Pairs(self.plot[keep], self.footprint[keep], self.similarity[keep],
                      self.inside[keep])

    def matching(self, overlap):
        return self.take(self.similarity >= overlap - SIMILARITY_TOLERANCE)

    def join(self, other):
        return _Pairs(*(np.concatenate([a, b]) for a, b in zip(
            (self.plot, self.footprint, self.similarity, self.inside),
            (other.plot, other.footprint, other.similarity, other.inside))))


def _pairs(grown, placed, which, candidates, tree):
    """Similarities of the plots ``which`` (buffered: ``grown``, as drawn: ``placed``)
    with the ``candidates`` footprints they reach."""
    if len(which) == 0 or len(candidates) == 0:
        empty = np.array([], dtype=int)
        return _Pairs(empty, empty, np.array([]), np.array([]))
    local, footprint = tree.query(grown[which], predicate="intersects")
    plot = which[local]
    inter = shapely.area(shapely.intersection(grown[plot], candidates[footprint]))
    smaller = np.minimum(shapely.area(candidates[footprint]), shapely.area(grown[plot]))
    inside = shapely.area(shapely.intersection(placed[plot], candidates[footprint]))
    return _Pairs(plot, footprint, np.minimum(inter / smaller, 1.0), inside)


def _match_counts(pairs, overlap, n_plots):
    return np.bincount(pairs.matching(overlap).plot, minlength=n_plots)


def _shift_plots(pairs, plots, grown, candidates, tree, config):
    """The offset correction: the pairs with every plot whose shift is applied at its
    shifted place, and the :class:`PlotShifts` (see :func:`align`)."""
    shifts = estimate_shifts(plots, candidates, config.shift, config.shift_window,
                             config.shift_cell, config.min_gain)
    trial = np.flatnonzero(shifts.applied)
    # the plot moves onto the footprints: minus the footprints' shift
    moved_grown, moved = grown.copy(), plots.copy()
    if len(trial):
        moved_grown[trial] = _translate(grown[trial], -shifts.dx[trial], -shifts.dy[trial])
        moved[trial] = _translate(plots[trial], -shifts.dx[trial], -shifts.dy[trial])
    shifted = _pairs(moved_grown, moved, trial, candidates, tree)
    shifts.applied[:] &= (_match_counts(shifted, config.overlap, len(plots)) >
                          _match_counts(pairs, config.overlap, len(plots)))
    shifts.dx[~shifts.applied] = 0.0
    shifts.dy[~shifts.applied] = 0.0
    pairs = pairs.take(~shifts.applied[pairs.plot]).join(
        shifted.take(shifts.applied[shifted.plot]))
    return pairs, shifts


def align(plots, cats, footprints, years, config):
    """Match current footprints with historical plots (:class:`Alignment`).

    ``plots`` with their categories ``cats``; ``footprints`` with their
    construction ``years`` (NaN: none, see :func:`construction_years`);
    ``config`` an :class:`AlignmentConfig`. Only candidates (built before
    the map's year) are matched; each aligned footprint goes to one plot.
    A footprint may be None (e.g. not read because it is no candidate).

    With the offset correction (``config.shift``), a plot is matched at
    its shifted place (:func:`estimate_shifts`) when the shift raises the
    overlap of plots and footprints by ``config.min_gain`` and more
    footprints match there than at the plot's own place; else at its own
    place (a shift that only fits a flat correlation better is noise).
    """
    counts = {}      # the AlignmentReport's, as they are known
    plots, repaired_plots = _polygonal(plots)
    footprints, repaired_footprints = _polygonal(footprints)
    counts["repaired"] = repaired_plots + repaired_footprints
    cats = np.asarray(cats)
    years = np.asarray(years, dtype=float)
    if len(years) != len(footprints) or len(cats) != len(plots):
        raise ValueError("one year per footprint and one category per plot")
    counts["footprints"] = len(footprints)
    candidate, no_year = candidate_mask(years, config)
    candidate &= ~shapely.is_missing(footprints)
    counts["without_year"] = int(no_year.sum())
    counts["after_year"] = int((~candidate & ~no_year).sum())
    counts["candidates"] = int(candidate.sum())
    plot_ok = np.flatnonzero(~shapely.is_missing(plots))
    counts["plots"] = len(plot_ok)

    index = np.flatnonzero(candidate)
    cand = footprints[index]
    check_alignment(plots[plot_ok], cand, config.buffer, config.shift, config.shift_window,
                    config.shift_cell)
    tree = shapely.STRtree(cand)
    grown = plots.copy()
    grown[plot_ok] = shapely.buffer(plots[plot_ok], config.buffer)
    pairs = _pairs(grown, plots, plot_ok, cand, tree)

    shifts = None
    if config.shift > 0:
        pairs, shifts = _shift_plots(pairs, plots, grown, cand, tree, config)
        counts["shifted_plots"] = int(shifts.applied.sum())

    best = np.zeros(len(index))
    np.maximum.at(best, pairs.footprint, pairs.similarity)
    match = pairs.matching(config.overlap)
    # the highest similarity; between equal ones, the plot holding more of the
    # footprint, then the first plot
    order = np.lexsort((match.plot, -match.inside, -np.round(match.similarity, 9),
                        match.footprint))
    first = np.ones(len(order), dtype=bool)
    first[1:] = match.footprint[order][1:] != match.footprint[order][:-1]
    chosen = order[first]
    per_footprint = np.bincount(match.footprint, minlength=len(index))
    counts["contested"] = int(np.sum(per_footprint[match.footprint[chosen]] > 1))

    aligned_local = match.footprint[chosen]
    unmatched_local = np.setdiff1d(np.arange(len(index)), aligned_local)
    counts["aligned"] = len(aligned_local)
    counts["unmatched"] = len(unmatched_local)
    counts["plots_matched"] = len(np.unique(match.plot[chosen]))
    return Alignment(
        aligned=index[aligned_local], plot=cats[match.plot[chosen]],
        similarity=match.similarity[chosen], unmatched=index[unmatched_local],
        best_similarity=best[unmatched_local], shifts=shifts,
        report=AlignmentReport(**counts))


def report_json(result, config, cats):
    """What an alignment did, as a JSON-ready dict: the options, the counts and, per plot
    (categories ``cats``, in the order of the plots given), its aligned footprints and
    offset."""
    aligned = {}
    for cat in result.plot.tolist():
        aligned[cat] = aligned.get(cat, 0) + 1
    plots = []
    for i, cat in enumerate(cats):
        row = {"plot": cat, "aligned": aligned.get(cat, 0)}
        if result.shifts is not None:
            gain = float(result.shifts.gain[i])
            row.update(dx=round(float(result.shifts.dx[i]), 3),
                       dy=round(float(result.shifts.dy[i]), 3),
                       gain=round(gain, 4) if math.isfinite(gain) else None,
                       shifted=bool(result.shifts.applied[i]))
        plots.append(row)
    return {"options": matching_options(config), "counts": result.report.counts(),
            "plots": plots}
