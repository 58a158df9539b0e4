"""Plot outlines fitted to the boundary line the map draws: v.histo.generalize's
``fit`` step (:func:`fit_outlines`).

The cells of a classified map place a plot's outline to the nearest cell
(on 1 m cells, IoU with the true plots tops out at about 0.96 however good
the classification). The map itself says more: across each edge of a
generalised plot, the drawn boundary line is a dark bump in the colour
profile, and where that bump lies is known to a tenth of a cell.

For each edge at least :data:`MIN_EDGE` cells long, profiles across it are
sampled (bilinear) every half cell along it, away from its corners. In each
profile the bump is the colour farthest from the outside's (the median of
the profile beyond :data:`REACH` outward) within :data:`REACH` of the edge;
its two flanks are where the profile, measured along the line from the
outside colour to the bump's, crosses half-way to the bump from either
side's level. The midpoint of the flanks is the line's centre: the plot's
outline for maps whose plots are digitised on the line's centre
(``outline="centre"``). For maps that draw the outline stroke inside the
plot (``outline="inside"``), the plot ends at the stroke's outer edge: the
centre plus half the stroke width, which the map gives too
(:func:`stroke_width`). There the stroke is a darker shade of the plots'
own colour, which text and symbols do not share: the profiles are read a
second time with the stroke's colour (the median of the lines first
found), only a colour on the way from the outside's to it is a line
(:func:`_stroke_like`), and a profile that crosses something darker (text)
near the edge is not read, so that a street name printed along an edge does
not pull the edge onto its letters; the line is looked for a little farther
(:data:`REACH`). Lines centred on the boundary are printed in the same black
as the text (Delft 1961), and are not checked so.

The flanks' midpoint is off by up to a fifth of a cell, depending on where a
line narrower than a cell lies within it (its samples are cells' means,
interpolated). On maps that draw the outline inside the plots each profile's
edge is then refined by a model of the drawing (fill, stroke, outside),
averaged over the cells and sampled as the profile was (:func:`_drawn_edges`):
rectangles drawn at every sub-cell place are fitted to 0.04-0.06 m instead of
0.16 m (mean Hausdorff distance). On Delft's centred lines the model puts the
edges on the line's centre more exactly, and that centre lies outside the
digitised plots (+0.29 m instead of +0.25 m, IoU 0.955 instead of 0.956):
there the midpoint stays.

Each edge's line is then fitted to the centres found along it: a
Theil-Sen line (robust to the few profiles a label or a symbol crosses),
straight through the median when the edge is short or the slope uncertain.
The plot's new corners are where the fitted lines of consecutive edges
meet (the mean of the two shifted corners where they are nearly parallel).
Edges without a clear line (no bump, too little contrast, a fill as dark as
the line, under half the profiles) stay where they were.
"""

from dataclasses import dataclass
from typing import Optional

import numpy as np
import shapely
from scipy import ndimage, stats

#: drawing conventions of the plots' outlines (r.histo.classify's outline= too)
OUTLINES = ("centre", "inside")
#: the line is looked for within this many cells of the edge, either side, by
#: outline convention: farther where only a colour like the stroke's is a line
#: (the synthetic maps: more edges fitted, IoU up 0.003-0.005 from 1.5 cells);
#: Delft's centred lines, told from text by nothing but their place, lose IoU
#: with a reach of 2 cells
REACH = {"centre": 1.5, "inside": 2.0}
#: the profiles reach this many cells beyond REACH; the outside and inside
#: colours are the medians of their last cell either side
MARGIN = 1.0
#: sampling along a profile and between profiles, and the part of an edge near
#: its corners left out (cells)
STEP, SPACING, END = 0.1, 0.5, 0.75
#: edges shorter than this (cells) are not fitted
MIN_EDGE = 2 * END + SPACING
#: a line's colour differs from the outside by at least this (0-255 scale, RGB
#: distance) ...
MIN_CONTRAST = 20.0
#: ... and the inside is at most this far from the outside towards the line
MAX_FILL = 0.75
#: the profiles of an edge in which a line must be found, as a share
MIN_FOUND = 0.5
#: an edge gets a slope from at least this many profiles, when its 95 %
#: confidence interval is narrower than :data:`MAX_SLOPE_SPREAD`
MIN_SLOPE_PROFILES, MAX_SLOPE_SPREAD = 8, 0.05
#: consecutive edges closer to parallel than this (degrees) are not intersected,
#: nor those whose fitted lines meet farther than this (cells) from the corner
MIN_CORNER, MAX_CORNER_MOVE = 15.0, 10.0
#: the stroke colour: the median of the darkest this share of the profiles' lines
DARKEST = 0.05
#: on maps that draw the outline inside the plots, a line's colour lies on the
#: way from the outside's colour to the stroke's (the median colour of the
#: lines first found), at most this far along it (text ink is darker) and off
#: it by at most this share of it (:func:`_stroke_like`)
MAX_DEPTH, MAX_ASIDE = 1.5, 0.35
#: passes of the fit, each from where the one before left the edges
PASSES = 2
#: on maps that draw the outline inside the plots, each profile's edge is then
#: placed where the drawing it implies (fill, stroke, outside), averaged over
#: the cells and sampled as the profile was, matches the profile best: searched
#: within this many cells of the flanks' estimate, in steps of this many cells,
#: refined by a parabola (:func:`_drawn_edges`)
MODEL_MOVE, MODEL_STEP = 0.3, 0.05
#: ... on every this many samples of a profile (0.3 cells apart: enough)
MODEL_EVERY = 3
#: an edge lies on the drawn line where its profiles find it within this many
#: cells (:func:`outline_support`; the flanks' estimate is off by up to 0.2)
ON_LINE = 0.35


@dataclass(frozen=True)
class OutlineFit:
    """Result of :func:`fit_outlines`: the ``plots`` (one per input, in
    order; an unfitted one unchanged), how many ``edges`` were long enough to
    fit and how many of them were ``fitted`` (a line found), and the
    ``stroke_width`` (map units) used for ``outline="inside"`` (else None)."""

    plots: list
    edges: int
    fitted: int
    stroke_width: Optional[float] = None


@dataclass(frozen=True)
class _Edges:
    """The fittable edges of a set of rings: start ``p`` and unit direction ``u``,
    outward normal ``n`` (F, 2), length ``length`` (F,); the profiles across them
    ``colours`` (P, T, B) at offsets ``offsets`` (T,), each profile's edge
    ``edge`` (P,) and its position ``along`` (P,) the edge."""

    p: np.ndarray
    u: np.ndarray
    n: np.ndarray
    length: np.ndarray
    colours: np.ndarray
    offsets: np.ndarray
    edge: np.ndarray
    along: np.ndarray


def _rings(polygon):
    """The rings of ``polygon`` (oriented: exterior counter-clockwise, holes
    clockwise, so that (u_y, -u_x) points out of the plot) as (k, 2) arrays
    without the closing vertex."""
    polygon = shapely.orient_polygons(polygon)
    return [np.asarray(r.coords)[:-1, :2] for r in (polygon.exterior, *polygon.interiors)]


def _sample(bands, image_place, x, y):
    """Bilinear colours (len(x), B) of ``bands`` (B, rows, cols) at points ``(x, y)``."""
    north, west, nsres, ewres = image_place
    rows = (north - np.asarray(y)) / nsres - 0.5
    cols = (np.asarray(x) - west) / ewres - 0.5
    return np.stack([ndimage.map_coordinates(band, [rows, cols], order=1, mode="nearest")
                     for band in bands], axis=-1)


def _edge_profiles(rings, bands, place, cell, reach):
    """The :class:`_Edges` of every edge of ``rings`` at least :data:`MIN_EDGE`
    cells long, and for each ring edge its index among them (-1: too short)."""
    starts = np.concatenate(rings)
    ends = np.concatenate([np.roll(r, -1, axis=0) for r in rings])
    d = ends - starts
    length = np.hypot(d[:, 0], d[:, 1])
    index = np.full(len(starts), -1)
    long_ = length >= MIN_EDGE * cell
    index[long_] = np.arange(long_.sum())
    if not long_.any():
        empty = np.zeros((0, 2))
        return _Edges(empty, empty, empty, np.zeros(0), np.zeros((0, 0, len(bands))),
                      np.zeros(0), np.zeros(0, dtype=int), np.zeros(0)), index
    p, length = starts[long_], length[long_]
    u = d[long_] / length[:, None]
    n = np.stack([u[:, 1], -u[:, 0]], axis=1)
    offsets = np.arange(-reach - MARGIN, reach + MARGIN + 1e-9, STEP) * cell
    counts = np.floor((length - 2 * END * cell) / (SPACING * cell)).astype(int) + 1
    edge = np.repeat(np.arange(len(p)), counts)
    along = END * cell + (np.arange(len(edge)) - np.repeat(np.cumsum(counts) - counts, counts)) \
        * SPACING * cell
    points = (p[edge][:, None, :] + along[:, None, None] * u[edge][:, None, :]
              + offsets[None, :, None] * n[edge][:, None, :])
    colours = _sample(bands, place, points[..., 0].ravel(), points[..., 1].ravel())
    colours = colours.reshape(len(edge), len(offsets), -1)
    return _Edges(p, u, n, length, colours, offsets, edge, along), index


@dataclass(frozen=True)
class _Lines:
    """What the profiles of :class:`_Edges` show: the line's ``centre`` (P,)
    (NaN where no clear line), its ``colour`` (P, B), the ``outside`` and
    ``inside`` colours (P, B)."""

    centre: np.ndarray
    colour: np.ndarray
    outside: np.ndarray
    inside: np.ndarray


def _shares(colours, outside, towards):
    """How far each colour of ``colours`` (P, T, B) lies from ``outside`` (P, B)
    towards ``outside + towards`` (0: the outside, 1: the line), (P, T)."""
    norm2 = np.maximum(np.einsum("pb,pb->p", towards, towards), 1e-9)
    return np.einsum("ptb,pb->pt", colours - outside[:, None], towards) / norm2[:, None]


def _crossing(share, first, level, offsets):
    """Where ``share`` (P, T) first falls below ``level`` (P,) after index
    ``first`` (P,) (linear between samples), or NaN."""
    count = share.shape[1]
    below = (share < level[:, None]) & (np.arange(count)[None] > first[:, None])
    j = np.where(below.any(axis=1), below.argmax(axis=1), -1)
    jj = np.clip(j, 1, count - 1)
    rows = np.arange(len(share))
    a, b = share[rows, jj - 1], share[rows, jj]
    step = offsets[jj] - offsets[jj - 1]
    where = offsets[jj - 1] + (a - level) / np.maximum(a - b, 1e-9) * step
    return np.where(j > 0, where, np.nan)


def _stroke_like(colours, outside, stroke):
    """Which colours of ``colours`` (P, T, B) look like the outline ``stroke``
    (B,) seen against ``outside`` (P, B): how far along the way from the
    outside to the stroke, (P, T), NaN for those farther than
    :data:`MAX_DEPTH` or off the way by more than :data:`MAX_ASIDE` of it."""
    towards = stroke[None] - outside
    depth = _shares(colours, outside, towards)
    aside = np.linalg.norm(colours - outside[:, None] - depth[..., None] * towards[:, None],
                           axis=2) / np.maximum(np.linalg.norm(towards, axis=1), 1e-9)[:, None]
    return np.where((depth <= MAX_DEPTH) & (aside <= MAX_ASIDE), depth, np.nan)


def _lines(profiles, cell, reach, stroke=None):
    """The :class:`_Lines` of the profiles of an :class:`_Edges`; with the
    ``stroke`` colour (B,), only colours like it are lines."""
    colours, offsets = profiles.colours, profiles.offsets
    inside = np.median(colours[:, offsets <= -(reach + MARGIN - 1.0) * cell], axis=1)
    outside = np.median(colours[:, offsets >= (reach + MARGIN - 1.0) * cell], axis=1)
    near = np.abs(offsets) <= reach * cell
    inked = np.zeros(len(colours), dtype=bool)
    if stroke is None:
        score = np.linalg.norm(colours - outside[:, None], axis=2)
    else:
        like = _stroke_like(colours, outside, stroke)
        score = np.nan_to_num(like, nan=-np.inf)
        # a profile across text (darker than the stroke) near the edge is not read
        darker = _shares(colours, outside, stroke[None] - outside) > MAX_DEPTH
        inked = (near[None] & darker).any(axis=1)
    score = np.where(near[None], score, -np.inf)
    peak = np.argmax(score, axis=1)
    some = np.isfinite(score[np.arange(len(score)), peak]) & ~inked
    colour = colours[np.arange(len(colours)), peak]
    towards = colour - outside
    share = _shares(colours, outside, towards)
    fill = _shares(inside[:, None], outside, towards)[:, 0]
    outer = _crossing(share, peak, np.full(len(peak), 0.5), offsets)
    # the inner flank: the same crossing on the profile read inward
    last = len(offsets) - 1
    inner = -_crossing(share[:, ::-1], last - peak, (1.0 + fill) / 2.0, -offsets[::-1])
    centre = (inner + outer) / 2.0
    clear = (some & (np.linalg.norm(towards, axis=1) >= MIN_CONTRAST) & (fill <= MAX_FILL)
             & (np.abs(centre) <= reach * cell))
    return _Lines(np.where(clear, centre, np.nan), colour, outside, inside)


def stroke_width(profiles, lines):
    """The width (map units) of the outline stroke the profiles cross, or None
    when no profile shows a line.

    The median over the profiles with a line of the area under their bump
    divided by the stroke's full contrast: a fill level up to the stroke's
    inner edge, 1 across the stroke, 0 outside, whatever the blur. The
    stroke's colour is the median of the darkest :data:`DARKEST` of the
    lines found (a line as narrow as a cell never shows its full colour in a
    single profile).
    """
    found = ~np.isnan(lines.centre)
    if not found.any():
        return None
    contrast = np.linalg.norm(lines.colour - lines.outside, axis=1)
    darkest = found & (contrast >= np.quantile(contrast[found], 1.0 - DARKEST))
    stroke = np.median(lines.colour[darkest], axis=0)
    outside = lines.outside[found]
    towards = stroke[None] - outside
    share = _shares(profiles.colours[found], outside, towards)
    fill = _shares(lines.inside[found][:, None], outside, towards)[:, 0]
    offsets = profiles.offsets
    step = offsets[1] - offsets[0]
    area = share.sum(axis=1) * step
    widths = (area - fill * (lines.centre[found] - offsets[0])) / (1.0 - fill / 2.0)
    return float(np.median(widths))


def _cell_share(t, p, q):
    """The share of a cell whose centre lies ``t`` before a straight line,
    along the line's normal: the cell's extent along the normal is the sum of
    two uniform spans ``p`` and ``q`` wide (its sides projected), a trapezoid."""
    p, q = np.maximum(p, q), np.maximum(np.minimum(p, q), 1e-6)
    a, b = (p - q) / 2.0, (p + q) / 2.0
    ramp = np.where(t < -a, (t + b) ** 2 / (2.0 * p * q),
                    np.where(t <= a, 0.5 + t / p, 1.0 - (b - t) ** 2 / (2.0 * p * q)))
    return np.where(t <= -b, 0.0, np.where(t >= b, 1.0, ramp))


def _drawn_edges(profiles, share, place, width, start, cell):
    """Per profile, where the plot's edge lies (offset, map units) on a map
    that draws its outline stroke ``width`` wide inside the plot: the drawing
    fill | stroke | outside with the edge there, averaged over each cell and
    sampled bilinearly as the profile ``share`` (P, T) was, fitted to it by
    least squares (the fill's and the stroke's levels free), the edge searched
    within :data:`MODEL_MOVE` cells of ``start`` (P,) (NaN: none). Unlike the
    flanks' midpoint, this does not depend on where the line lies within a cell."""
    north, west, nsres, ewres = place
    rows = np.flatnonzero(~np.isnan(start))
    result = np.full(len(start), np.nan)
    if not len(rows):
        return result
    share = share[rows, ::MODEL_EVERY].astype(np.float32)
    n = profiles.n[profiles.edge[rows]]
    base = profiles.p[profiles.edge[rows]] + profiles.along[rows, None] \
        * profiles.u[profiles.edge[rows]]
    points = base[:, None, :] + profiles.offsets[None, ::MODEL_EVERY, None] * n[:, None, :]
    col = (points[..., 0] - west) / ewres - 0.5
    row = (north - points[..., 1]) / nsres - 0.5
    c0, r0 = np.floor(col), np.floor(row)
    fc, fr = col - c0, row - r0
    # the four cells each sample is interpolated from: their weights and their
    # centres' places along the normal
    weights, places = [], []
    for dr, dc in ((0, 0), (0, 1), (1, 0), (1, 1)):
        weights.append((fr if dr else 1.0 - fr) * (fc if dc else 1.0 - fc))
        x = west + (c0 + dc + 0.5) * ewres - base[:, None, 0]
        y = north - (r0 + dr + 0.5) * nsres - base[:, None, 1]
        places.append(x * n[:, None, 0] + y * n[:, None, 1])
    weights = np.stack(weights, -1).astype(np.float32)
    places = np.stack(places, -1).astype(np.float32)
    spans = tuple((np.abs(n[:, k])[:, None, None] * res).astype(np.float32)
                  for k, res in ((0, ewres), (1, nsres)))

    def misfit(edge):
        edge = edge.astype(np.float32)[:, None, None]
        fill = (weights * _cell_share(edge - np.float32(width) - places, *spans)).sum(-1)
        stroke = (weights * _cell_share(edge - places, *spans)).sum(-1) - fill
        a11, a12, a22 = (fill * fill).sum(1), (fill * stroke).sum(1), (stroke * stroke).sum(1)
        b1, b2 = (fill * share).sum(1), (stroke * share).sum(1)
        det = np.maximum(a11 * a22 - a12 ** 2, 1e-12)
        level_fill, level_stroke = (a22 * b1 - a12 * b2) / det, (a11 * b2 - a12 * b1) / det
        left = share - level_fill[:, None] * fill - level_stroke[:, None] * stroke
        return np.where(level_stroke > 0, (left * left).sum(1), np.inf)

    grid = np.arange(-MODEL_MOVE, MODEL_MOVE + 1e-9, MODEL_STEP) * cell
    costs = np.stack([misfit(start[rows] + g) for g in grid], axis=1)
    best = np.argmin(costs, axis=1)
    centre = start[rows] + grid[best]
    # a parabola through the best step and its neighbours
    inner = (best > 0) & (best < len(grid) - 1)
    k = np.arange(len(rows))
    b = np.clip(best, 1, len(grid) - 2)
    y0, y1, y2 = costs[k, b - 1], costs[k, b], costs[k, b + 1]
    ok = inner & np.isfinite(y0) & np.isfinite(y1) & np.isfinite(y2)
    y0, y1, y2 = (np.where(ok, y, 0.0) for y in (y0, y1, y2))
    curve = y0 - 2.0 * y1 + y2
    ok &= curve > 0
    centre = centre + np.where(ok, 0.5 * (y0 - y2) / np.where(ok, curve, 1.0), 0.0) \
        * MODEL_STEP * cell
    result[rows] = np.where(np.isfinite(costs[k, best]), centre, np.nan)
    return result


def _edge_offsets(profiles, centre, reach):
    """Per edge of ``profiles``: the fitted line as (offset at the edge's start,
    slope along it) in map units, NaN where the edge has no line; a slope that
    would take either end of the edge farther than ``reach`` from where it was
    is not taken (the line is only looked for that far)."""
    result = np.full((len(profiles.p), 2), np.nan)
    # the profiles come edge after edge (:func:`_edge_profiles`)
    bounds = np.searchsorted(profiles.edge, np.arange(len(profiles.p) + 1))
    for k in range(len(profiles.p)):
        mine = slice(bounds[k], bounds[k + 1])
        found = ~np.isnan(centre[mine])
        count = int(found.sum())
        if count < max(3, MIN_FOUND * (bounds[k + 1] - bounds[k])):
            continue
        values, along = centre[mine][found], profiles.along[mine][found]
        offset, slope = float(np.median(values)), 0.0
        if count >= MIN_SLOPE_PROFILES:
            fitted = stats.theilslopes(values, along)
            ends = fitted.intercept + fitted.slope * np.array([0.0, profiles.length[k]])
            if (fitted.high_slope - fitted.low_slope <= MAX_SLOPE_SPREAD
                    and np.abs(ends).max() <= reach):
                offset, slope = float(fitted.intercept), float(fitted.slope)
        result[k] = offset, slope
    return result


def _cross(a, b):
    """The z of the cross product of 2D vectors ``a`` and ``b``."""
    return a[0] * b[1] - a[1] * b[0]


def _meet(a1, d1, a2, d2):
    """Where lines ``a1 + s d1`` and ``a2 + t d2`` meet (not parallel)."""
    return a1 + _cross(a2 - a1, d2) / _cross(d1, d2) * d1


def _refit_ring(ring, index, profiles, fits, cell):
    """The corners of ``ring`` (k, 2) where its edges' fitted lines meet (the
    mean of the two edges' moved ends where the lines are nearly parallel or
    meet farther than :data:`MAX_CORNER_MOVE` cells from the corner)."""
    count = len(ring)
    starts, ends = [], []
    for i in range(count):
        p, q = ring[i], ring[(i + 1) % count]
        k = index[i]
        if k < 0 or np.isnan(fits[k, 0]):
            starts.append(p)
            ends.append(q)
            continue
        offset, slope = fits[k]
        n = profiles.n[k]
        starts.append(p + offset * n)
        ends.append(q + (offset + slope * profiles.length[k]) * n)
    corners = []
    sin_min = np.sin(np.radians(MIN_CORNER))
    for i in range(count):
        a1, b1 = starts[i - 1], ends[i - 1]
        a2, b2 = starts[i], ends[i]
        d1, d2 = b1 - a1, b2 - a2
        sine = _cross(d1, d2) / max(np.hypot(*d1) * np.hypot(*d2), 1e-12)
        corner = _meet(a1, d1, a2, d2) if abs(sine) >= sin_min else None
        if corner is None or np.hypot(*(corner - ring[i])) > MAX_CORNER_MOVE * cell:
            corner = (b1 + a2) / 2.0
        corners.append(corner)
    return np.array(corners)


@dataclass(frozen=True)
class _Reading:
    """What the map shows across the edges of a set of plots: their ``rings``
    (per plot), the :class:`_Edges` ``profiles`` and each ring edge's
    ``index`` among them, the :class:`_Lines` ``lines`` read in them, the
    stroke ``width`` (``outline="inside"``, else None) and ``edges``: where
    the plot's edge lies by the flanks of the line (P,), NaN where no line."""

    rings: list
    profiles: _Edges
    index: np.ndarray
    lines: _Lines
    width: Optional[float]
    edges: np.ndarray


def _reach(outline, reach):
    """How far from an edge the line is looked for (cells): ``reach``, or
    :data:`REACH` of the ``outline`` convention when None."""
    return REACH[outline] if reach is None else float(reach)


def _read(polygons, bands, place, cell, outline, stroke, reach=None):
    """The :class:`_Reading` of the plots ``polygons`` on the map ``bands``, or
    None when none of their edges is long enough; the line is looked for
    within ``reach`` cells of the edges (:func:`_reach`)."""
    rings = [_rings(p) for p in polygons]
    flat = [r for plot in rings for r in plot]
    reach = _reach(outline, reach)
    profiles, index = _edge_profiles(flat, bands, place, cell, reach)
    if not len(profiles.edge):
        return None
    lines = _lines(profiles, cell, reach)
    found = ~np.isnan(lines.centre)
    if outline == "inside" and found.any():
        # the stroke has the plots' own colour: text and symbols beside an edge
        # are not taken for it
        lines = _lines(profiles, cell, reach, np.median(lines.colour[found], axis=0))
    width, edges = None, lines.centre
    if outline == "inside":
        width = stroke if stroke is not None else stroke_width(profiles, lines)
        if width is not None:
            edges = edges + width / 2.0
    return _Reading(rings, profiles, index, lines, width, edges)


def _fit_once(polygons, bands, place, cell, outline, stroke, reach=None):
    """One pass of :func:`fit_outlines` over the plots ``polygons``."""
    reading = _read(polygons, bands, place, cell, outline, stroke, reach)
    if reading is None:
        return OutlineFit(list(polygons), 0, 0, None)
    profiles, lines, width, centre = reading.profiles, reading.lines, reading.width, reading.edges
    if width is not None:  # outline="inside": the drawing model
        colour = np.median(lines.colour[~np.isnan(lines.centre)], axis=0)
        share = _shares(profiles.colours, lines.outside, colour[None] - lines.outside)
        centre = _drawn_edges(profiles, share, place, width, centre, cell)
    fits = _edge_offsets(profiles, centre, _reach(outline, reach) * cell + (width or 0.0) / 2.0)
    out, first = [], 0
    for polygon, plot in zip(polygons, reading.rings):
        new_rings = []
        for ring in plot:
            new_rings.append(_refit_ring(ring, reading.index[first:first + len(ring)], profiles,
                                         fits, cell))
            first += len(ring)
        fitted = shapely.Polygon(new_rings[0], new_rings[1:])
        out.append(fitted if fitted.is_valid and not fitted.is_empty else polygon)
    return OutlineFit(out, len(profiles.p), int((~np.isnan(fits[:, 0])).sum()), width)


def _bands(image):
    """The bands (float), place (north, west, nsres, ewres) and cell size of a
    :class:`~reconstruction.geom.grid.MapImage`."""
    rows, cols = image.rgb.shape[:2]
    west, east, south, north = (float(v) for v in image.extent)
    nsres, ewres = (north - south) / rows, (east - west) / cols
    bands = [image.rgb[..., b].astype(np.float64) for b in range(image.rgb.shape[2])]
    return bands, (north, west, nsres, ewres), (nsres + ewres) / 2.0


def _check(outline):
    if outline not in OUTLINES:
        raise ValueError("unknown outline '{}' (one of {})".format(outline, ", ".join(OUTLINES)))


def fit_outlines(polygons, image, outline="centre", stroke=None, reach=None):
    """The plots ``polygons`` with their edges moved onto the boundary line
    that ``image`` (a :class:`~reconstruction.geom.grid.MapImage`, the scanned
    map) draws: on its centre (``outline="centre"``) or on the outer edge of a
    stroke drawn inside the plots (``"inside"``), ``stroke`` map units wide
    (None: measured on the map, :func:`stroke_width`; a stroke narrower than
    a cell is measured too wide); the line is looked for within ``reach``
    cells of each edge (None: :data:`REACH`; a map drawing strokes several
    cells wide needs more, :mod:`~reconstruction.generalize.scale`).

    :data:`PASSES` passes: an edge a cell off the line has the line's inner
    flank in its inside reference; from where the first pass put it, the
    second reads the profile centred. An :class:`OutlineFit` (the figures of
    the last pass); a plot whose fitted outline is not one valid polygon is
    kept as it was.
    """
    _check(outline)
    bands, place, cell = _bands(image)
    fit = OutlineFit(list(polygons), 0, 0, None)
    for _ in range(PASSES):
        if not fit.plots:
            break
        fit = _fit_once(fit.plots, bands, place, cell, outline, stroke, reach)
    return fit


def edge_support(polygons, image, outline="centre", stroke=None, reach=None):
    """Where the map draws a line along each plot's edges: per plot, per ring
    (exterior first, counter-clockwise; holes clockwise), ``(ring, shares)``:
    the ring's vertices (k, 2) and, for the edge from each vertex to the
    next, the share (0-1) of its profiles that find the line within
    :data:`ON_LINE` cells of the edge (NaN: too short to read); ``reach``
    as :func:`fit_outlines`'s."""
    _check(outline)
    bands, place, cell = _bands(image)
    reading = _read(polygons, bands, place, cell, outline, stroke, reach)
    if reading is None:
        return [[(ring, np.full(len(ring), np.nan)) for ring in _rings(p)] for p in polygons]
    profiles = reading.profiles
    on_line = np.abs(np.nan_to_num(reading.edges, nan=np.inf)) <= ON_LINE * cell
    share = (np.bincount(profiles.edge, weights=on_line, minlength=len(profiles.p))
             / np.maximum(np.bincount(profiles.edge, minlength=len(profiles.p)), 1))
    result, first = [], 0
    for plot in reading.rings:
        rings = []
        for ring in plot:
            index = reading.index[first:first + len(ring)]
            rings.append((ring, np.where(index >= 0, share[np.maximum(index, 0)], np.nan)))
            first += len(ring)
        result.append(rings)
    return result


def outline_support(polygons, image, outline="centre", stroke=None, reach=None):
    """How much of each plot's outline the map draws a line on: the share
    (0-1, (n,) array) of its perimeter along edges whose profiles find the
    line within :data:`ON_LINE` cells of the edge (the share of the edge's
    profiles that do; edges too short to read count as unsupported)."""
    support = np.zeros(len(polygons))
    for k, rings in enumerate(edge_support(polygons, image, outline, stroke, reach)):
        supported = perimeter = 0.0
        for ring, shares in rings:
            length = np.hypot(*(np.roll(ring, -1, axis=0) - ring).T)
            supported += float((length * np.nan_to_num(shares, nan=0.0)).sum())
            perimeter += float(length.sum())
        support[k] = supported / perimeter if perimeter > 0 else 0.0
    return support


#: a cut corner: an edge the map draws no line along (its profiles' share on
#: the line below the first), between two it does (at least the second),
#: whose lines meet at this angle or more (degrees) beyond both of them, at
#: most twice the edge's length (plus a cell) from its middle
#: (:func:`restore_corners`)
CUT, DRAWN, CORNER_ANGLE = 0.2, 0.6, 45.0


def restore_corners(ring, shares, cell=1.0):
    """The ring (k, 2) with each cut corner (see :data:`CUT`) restored: the
    edge dropped, its neighbours extended to where they meet; ``shares``: per
    edge, as :func:`edge_support` gives them; ``cell``: the map's cell size (map
    units). The same array when none is."""
    count = len(ring)
    if count < 4:
        return ring
    drawn = np.nan_to_num(shares, nan=0.0) >= DRAWN
    cut = np.nan_to_num(shares, nan=0.0) < CUT
    corners = {}
    sin_min = np.sin(np.radians(CORNER_ANGLE))
    for i in range(count):
        if not (cut[i] and drawn[i - 1] and drawn[(i + 1) % count]):
            continue
        a0, a1 = ring[i - 1], ring[i]
        b0, b1 = ring[(i + 1) % count], ring[(i + 2) % count]
        d1, d2 = a1 - a0, b1 - b0
        sine = _cross(d1, d2) / max(np.hypot(*d1) * np.hypot(*d2), 1e-12)
        if abs(sine) < sin_min:
            continue
        corner = _meet(a0, d1, b0, d2)
        beyond = np.dot(corner - a1, d1) >= 0 and np.dot(corner - b0, d2) <= 0
        near = np.hypot(*(corner - (a1 + b0) / 2.0)) <= 2 * np.hypot(*(b0 - a1)) + cell
        if beyond and near:
            corners[i] = corner
    if not corners:
        return ring
    out = []
    for k in range(count):
        if k in corners:
            out.append(corners[k])
        elif (k - 1) % count not in corners:
            out.append(ring[k])
    return np.array(out)
