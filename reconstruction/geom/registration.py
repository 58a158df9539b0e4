"""A scan's colour planes registered to each other (r.histo.classify, and
v.histo.generalize's fit step, read the map registered).

A scanner may record one colour plane a whole pixel off the others (a line
sensor's colour rows read at different moments, a drum's channels out of
step): every edge of the map then gets a false colour fringe on one side.
The fringe is the colour of a neighbouring class: the classification gives
the cells between the letters of a street name to the plots beside it, and
the fill just inside a plot's stroke to the garden outside (issue 32: on the
synthetic map, whose red plane lies one cell east of green and blue, two
plots joined across a street name and garden plots lost a strip).

:func:`band_shifts` finds, for each band, the whole-cell shift that lines up
its edges with the others': the correlation of the bands' gradient
magnitudes (edges, whatever their colour), best over the shifts within
:data:`REACH` cells. The band the others agree with most stays in place (the
reference); a printing plate printed out of register moves one ink, not a
plane, so its edges stay where the black lines are and nothing is shifted.

Pure numpy and scipy, no GRASS.
"""

from dataclasses import dataclass

import numpy as np
from scipy import ndimage

from ..core.messages import note, verbose, warning
from .grid import MapImage

#: shifts tried, in cells either way along rows and columns
REACH = 2
#: the shifts are estimated on at most this many cells a side around the
#: map's centre (a few hundred edges are plenty; a sheet may be 20,000 a side)
SAMPLE = 1024
#: a shift is taken where the correlation of the edges gains at least this
#: much over the bands left as they are (noise alone moves it by thousandths)
MIN_GAIN = 0.02


@dataclass(frozen=True)
class BandShifts:
    """The shift of each band, ``(rows, cols)`` whole cells (positive: the
    band's content lies that many cells south / east of the reference's), the
    ``reference`` band's index, and the edges' correlation with the reference
    before and after the shift (``before``, ``after``; 1.0 for the reference)."""

    shifts: tuple
    reference: int
    before: tuple
    after: tuple

    @property
    def moved(self):
        """The indices of the bands that are shifted."""
        return [i for i, s in enumerate(self.shifts) if s != (0, 0)]

    def message(self, names, registered=True):
        """What was found, in the terms of ``names`` (the bands' maps), as a
        :class:`~reconstruction.core.messages.Message`: with --verbose when no
        band is off; when one is, a message that it was moved back
        (``registered``) or a warning that it was not (flag -b would)."""
        if not self.moved:
            return verbose("Bands in register: no band is off by a whole cell")
        parts = []
        for i in self.moved:
            dr, dc = self.shifts[i]
            where = ", ".join(p for p in (_cells(dr, "south", "north"),
                                         _cells(dc, "east", "west")) if p)
            parts.append("<{}> lies {} of <{}> (edges' correlation {:.3f} as it is, {:.3f} "
                         "moved back)".format(names[i], where, names[self.reference],
                                              self.before[i], self.after[i]))
        if registered:
            return note("Bands registered: {}; moved back before reading the map".format(
                "; ".join(parts)))
        return warning("Bands out of register: {}; read as they are (flag -b registers "
                       "them)".format("; ".join(parts)))


def _cells(count, positive, negative):
    if not count:
        return ""
    return "{} cell{} {}".format(abs(count), "" if abs(count) == 1 else "s",
                                 positive if count > 0 else negative)


def _edges(band):
    """The gradient magnitude of ``band`` standardised over its valid cells (0
    where the band or a neighbour has no data), and the valid cells."""
    band = np.asarray(band, dtype=float)
    valid = np.isfinite(band)
    filled = np.where(valid, band, np.nanmean(band) if valid.any() else 0.0)
    magnitude = np.hypot(ndimage.sobel(filled, 0), ndimage.sobel(filled, 1))
    valid = ndimage.binary_erosion(valid, np.ones((3, 3), dtype=bool), border_value=0)
    if valid.sum() < 2:
        return np.zeros_like(magnitude), valid
    values = magnitude[valid]
    return np.where(valid, (magnitude - values.mean()) / max(values.std(), 1e-9), 0.0), valid


def _overlap(shape, dr, dc):
    """The cells of a grid of ``shape`` that have a cell ``dr`` rows south and
    ``dc`` columns east of them, and those cells: two (rows, cols) slices."""
    rows, cols = shape
    here = (slice(max(0, -dr), rows - max(0, dr)), slice(max(0, -dc), cols - max(0, dc)))
    there = (slice(max(0, dr), rows - max(0, -dr)), slice(max(0, dc), cols - max(0, -dc)))
    return here, there


def _correlation(a, b, valid_a, valid_b, dr, dc):
    """Correlation of edges ``a`` with ``b`` moved back by ``(dr, dc)``: ``a``
    at a cell against ``b`` ``dr`` rows south and ``dc`` columns east of it."""
    here, there = _overlap(a.shape, dr, dc)
    both = valid_a[here] & valid_b[there]
    if both.sum() < 2:
        return 0.0
    x, y = a[here][both], b[there][both]
    x, y = x - x.mean(), y - y.mean()
    return float((x * y).sum() / max(np.sqrt((x * x).sum() * (y * y).sum()), 1e-12))


def _offset(a, b, valid_a, valid_b, reach):
    """The whole-cell shift of ``b``'s content against ``a``'s, and the
    correlations without and with it."""
    scores = {(dr, dc): _correlation(a, b, valid_a, valid_b, dr, dc)
              for dr in range(-reach, reach + 1) for dc in range(-reach, reach + 1)}
    best = max(scores, key=lambda s: (scores[s], s == (0, 0)))
    if scores[best] < scores[(0, 0)] + MIN_GAIN:
        best = (0, 0)
    return best, scores[(0, 0)], scores[best]


def central_window(shape, size=SAMPLE):
    """The rows and columns ``(row0, row1, col0, col1)`` of the window of at
    most ``size`` x ``size`` cells at the centre of a grid of ``shape``."""
    rows, cols = min(shape[0], size), min(shape[1], size)
    row0, col0 = (shape[0] - rows) // 2, (shape[1] - cols) // 2
    return row0, row0 + rows, col0, col0 + cols


def band_shifts(bands, reach=REACH):
    """The :class:`BandShifts` of ``bands`` (2-D arrays of one grid, nan for
    no data), estimated on their :func:`central_window`: for every pair, the
    whole-cell shift (within ``reach`` cells) that best lines up their edges;
    the reference is the band whose shifts to the others add up to the fewest
    cells (the first of equals), each other band gets its shift against it."""
    if bands:
        row0, row1, col0, col1 = central_window(np.shape(bands[0]))
        bands = [np.asarray(b)[row0:row1, col0:col1] for b in bands]
    edges = [_edges(b) for b in bands]
    count = len(edges)
    if count < 2:
        return BandShifts(((0, 0),) * count, 0, (1.0,) * count, (1.0,) * count)
    pairs = {}
    for i in range(count):
        for j in range(i + 1, count):
            (dr, dc), before, after = _offset(edges[i][0], edges[j][0], edges[i][1],
                                               edges[j][1], reach)
            pairs[i, j] = ((dr, dc), before, after)
            pairs[j, i] = ((-dr, -dc), before, after)
    reference = min(range(count), key=lambda r: (
        sum(abs(pairs[r, j][0][0]) + abs(pairs[r, j][0][1]) for j in range(count) if j != r), r))
    shifts, before, after = [], [], []
    for j in range(count):
        if j == reference:
            shifts.append((0, 0))
            before.append(1.0)
            after.append(1.0)
        else:
            shift, b, a = pairs[reference, j]
            shifts.append(shift)
            before.append(b)
            after.append(a)
    return BandShifts(tuple(shifts), reference, tuple(before), tuple(after))


def registered(band, shift):
    """``band`` moved back by its ``shift`` ``(rows, cols)``: the content found
    ``rows`` south and ``cols`` east of a cell comes to that cell; a cell with
    nothing to take (along the map's edge) keeps its own value, as
    ``r.mapcalc "out = if(isnull(band[rows,cols]), band, band[rows,cols])"``
    writes it."""
    band = np.asarray(band, dtype=float)
    here, there = _overlap(band.shape, *shift)
    out = band.copy()
    out[here] = band[there]
    return out


def _image_bands(image):
    return [image.rgb[..., k].astype(float) for k in range(image.rgb.shape[-1])]


def image_shifts(image):
    """The :class:`BandShifts` of a :class:`~reconstruction.geom.grid.MapImage`'s bands."""
    return band_shifts(_image_bands(image))


def register_image(image, shifts):
    """The :class:`~reconstruction.geom.grid.MapImage` with its bands moved back
    by their ``shifts`` (:func:`image_shifts`, :func:`registered`); the same
    image when none moves."""
    if not shifts.moved:
        return image
    rgb = np.dstack([registered(b, s) for b, s in zip(_image_bands(image), shifts.shifts)])
    return MapImage(rgb.astype(image.rgb.dtype), image.extent)
