"""The closed shapes of a map's line work as segments (r.histo.classify segmentation=lines).

An engraved or printed monochrome map (the Paris atlas of 1925, most town
maps of the nineteenth century) outlines its blocks in ink on paper and
hatches its buildings and water; blocks and streets have the paper's colour,
and a colour segmentation finds no edge between them. What separates them
is the line work, so here the segments are the shapes the lines close (pure
numpy and scipy; the ink as read in :mod:`reconstruction.geom.ink`):

1. **Ink**: a cell darker than the paper around it by more than the map's
   spread (:func:`~reconstruction.geom.ink.ink_contrast`,
   :func:`~reconstruction.geom.ink.ink_threshold`), the strokes' width
   measured on the map (:func:`~reconstruction.geom.ink.stroke_scale`); on a
   colour scan, ink of a colour (:data:`COLOURED`: red district limits and
   names) is not read, but a black line one crosses goes on under it.
2. **Hatching**: dense parallel strokes: the ink closed over gaps of
   :data:`HATCH_GAP` stroke widths and opened by a disk :data:`HATCH_OPENING`
   stroke widths wide (a lone line or a word's strokes go), where the
   strokes run one way (:data:`HATCH_COHERENCE`), in patches of at least the
   map's least region: the hatching of a building or of the river; a line,
   a dotted line or a word is none.
3. **Lines**: the ink outside the hatching's interior that runs at least
   :data:`~reconstruction.geom.ink.LINE_STROKES` stroke widths (its box's
   diagonal: letters and numbers are no lines, and stay in the shape they
   are written in), small gaps closed, plus the hatching's own boundary
   (a hatched building drawn against a block without an outline of its own).
4. **Shapes**: the 4-connected regions between the lines; a region smaller
   than the map's least region (the inside of a letter, a speck between two
   lines) joins the region nearest to each of its cells.

The segments are the shapes, numbered first, then the 8-connected parts of
the lines, then those of the strokes of colour: the classifier decides, from
the training points, what each is (block, hatched building, water, street,
garden; outline). What a shape is
filled with is in :func:`fill_features`.
"""

from dataclasses import dataclass

import numpy as np
from scipy import ndimage

from ..geom.ink import (LINE_STROKES, StrokeScale, brightness, close_gaps, grow, ink_contrast,
                        ink_threshold, long_parts, otsu, stroke_scale)
from ..geom.strokes import disk

#: hatching: the gaps between its strokes are closed by a disk this many
#: stroke widths wide (radius) ...
HATCH_GAP = 1.5
#: ... and what stays after an opening by a disk this many stroke widths wide
#: (radius) is hatching: a lone line or a word's strokes go
HATCH_OPENING = 1.0
#: the coherence (below) is measured over a Gaussian this many stroke widths wide
HATCH_WINDOW = 1.5
#: ... where the strokes run one way: the coherence of the ink's structure tensor
#: over the window at least this (parallel strokes near 1; letters, stipple and
#: crossing lines lower)
HATCH_COHERENCE = 0.5
#: the hatching's interior, whose ink is no outline: the hatching shrunk by
#: this many stroke widths (its boundary strokes are the building's outline)
HATCH_INTERIOR = 1.0
#: ink of a colour (red district limits and names, a coloured stamp) is no
#: outline: ink brighter than Otsu's threshold of the map's brightness (black
#: ink, with the colour fringes of a scan, is darker) whose chroma (largest
#: band minus smallest, 0-255) is at least this; grey ink and the paper stay
#: well below
COLOURED = 60.0
#: a line a stroke of colour crosses is bridged across it over gaps up to
#: twice this many stroke widths
BRIDGE_STROKES = 3.0
#: the names of the features :func:`fill_features` gives each segment
FILL_FEATURES = ("ink_share", "hatching_share", "orientation_cos", "orientation_sin",
                 "coherence", "edge_density")

FOUR = ndimage.generate_binary_structure(2, 1)
EIGHT = np.ones((3, 3), dtype=bool)


@dataclass(frozen=True)
class InkReading:
    """The ink of a scanned map (:func:`read_ink`): ``ink`` and ``hatched`` (bool)
    the cells read as ink and as hatching, ``valid`` where the map is,
    ``scale`` the map's :class:`~reconstruction.geom.ink.StrokeScale`,
    ``coloured`` (bool) the ink of a colour left out of ``ink``."""
    ink: np.ndarray
    hatched: np.ndarray
    valid: np.ndarray
    scale: StrokeScale
    coloured: np.ndarray


@dataclass(frozen=True)
class LineShapes:
    """What :func:`line_shapes` read: ``segments`` (int32, 1..``shapes`` the closed
    shapes, then the parts of the lines, then the strokes of colour; 0 where
    the map is not), ``shapes`` how many closed shapes, ``lines`` (bool) the cells of line work,
    ``reading`` the :class:`InkReading` they come from."""
    segments: np.ndarray
    shapes: int
    lines: np.ndarray
    reading: InkReading


def _greyscale(bands):
    """The bands (a list of 2-D arrays) as the (rows, cols[, 3]) array ``ink`` reads."""
    return bands[0] if len(bands) == 1 else np.stack(bands[:3], axis=-1)


def hatching(ink, scale):
    """The cells of hatched areas (bool): the ink closed over the gaps between
    parallel strokes (a disk :data:`HATCH_GAP` stroke widths wide) and opened
    by a disk :data:`HATCH_OPENING` stroke widths wide (a lone line stays thin
    and goes), where the strokes run one way (:data:`HATCH_COHERENCE`), in
    patches of at least the map's least region (``scale`` a
    :class:`~reconstruction.geom.ink.StrokeScale`)."""
    gap = max(1, int(round(HATCH_GAP * scale.stroke)))
    dense = _closed(ink, gap)
    dense = ndimage.binary_opening(dense, structure=disk(max(1, int(round(
        HATCH_OPENING * scale.stroke)))))
    tensor = structure_tensor(ink.astype(np.float32), HATCH_WINDOW * scale.stroke)
    dense &= _coherence(*tensor) >= HATCH_COHERENCE
    parts, count = ndimage.label(dense)
    if not count:
        return dense
    keep = np.bincount(parts.ravel()) >= scale.min_cells
    keep[0] = False
    return keep[parts]


def _closed(cells, reach):
    """``cells`` (bool) closed by a disk of ``reach`` cells, nothing beyond the map."""
    return ndimage.binary_closing(np.pad(cells, reach), structure=disk(reach))[
        reach:-reach, reach:-reach]


def read_ink(bands, cell, stroke=None, min_area=None):
    """The ink and hatching of a scanned map: an :class:`InkReading`.

    ``bands``: the map's bands (one greyscale or red, green, blue; 2-D arrays,
    nan = no data: the map is where every band is finite), ``cell`` the cell
    width in map units; ``stroke`` (map units) and ``min_area`` (square map
    units) replace the stroke width and least region measured on the map.
    """
    valid = np.logical_and.reduce([np.isfinite(b) for b in bands])
    if not valid.any():
        raise ValueError("the map has no cell with data")
    image = np.nan_to_num(_greyscale(bands), nan=float(np.nanmedian(bands[0])))
    scale = stroke_scale(image, cell, stroke=stroke, min_area=min_area)
    contrast = ink_contrast(image, scale.radius)
    ink = (contrast > ink_threshold(contrast[valid])) & valid
    coloured = np.zeros_like(ink)
    if len(bands) >= 3:
        stack = np.stack(bands[:3])
        # a bright stroke of colour: black ink, colour fringes and all, is darker
        level = brightness(image)
        coloured = (ink & (level > otsu(level[valid]))
                    & (np.nan_to_num(stack.max(axis=0) - stack.min(axis=0)) >= COLOURED))
    return InkReading(ink=ink & ~coloured, hatched=hatching(ink & ~coloured, scale) & valid,
                      valid=valid, scale=scale, coloured=coloured)


def line_shapes(reading):
    """The closed shapes of the line work of a scanned map (read as an
    :class:`InkReading`) and its lines, as segments: a :class:`LineShapes`."""
    ink, hatched, valid, scale = reading.ink, reading.hatched, reading.valid, reading.scale
    interior = ndimage.binary_erosion(hatched, structure=disk(max(1, int(round(
        HATCH_INTERIOR * scale.stroke)))))
    lines = long_parts(ink & ~interior, LINE_STROKES * scale.stroke)
    lines = close_gaps(lines, scale.stroke) | (hatched & ~ndimage.binary_erosion(hatched))
    # a black line a stroke of colour is drawn across goes on under it
    reach = max(1, int(round(BRIDGE_STROKES * scale.stroke)))
    lines |= reading.coloured & _closed(lines, reach)
    lines &= valid
    regions, count = ndimage.label(valid & ~lines, structure=FOUR)
    sizes = np.bincount(regions.ravel(), minlength=count + 1)
    kept = sizes >= scale.min_cells
    kept[0] = False
    renumber = np.zeros(count + 1, dtype=np.int32)
    renumber[kept] = np.arange(1, int(kept.sum()) + 1)
    regions = renumber[regions]
    shapes = int(kept.sum())
    if shapes:
        regions = grow(regions, valid & ~lines)
    else:  # no shape of the least size: the open cells are one shape
        regions = (valid & ~lines).astype(np.int32)
        shapes = int(regions.any())
    parts, n_parts = ndimage.label(lines, structure=EIGHT)
    segments = np.where(lines, parts + shapes, regions).astype(np.int32)
    # strokes of colour (district limits, their names) are segments of their own
    colour = reading.coloured & ~lines
    colour_parts, _ = ndimage.label(colour, structure=EIGHT)
    segments = np.where(colour, colour_parts + shapes + n_parts, segments).astype(np.int32)
    return LineShapes(segments=np.where(valid, segments, 0), shapes=shapes, lines=lines,
                      reading=reading)


def structure_tensor(image, sigma):
    """The smoothed structure tensor (Jxx, Jxy, Jyy) of a 2-D array (Gaussian
    derivatives, then a Gaussian of ``sigma`` cells)."""
    gx = ndimage.sobel(image, axis=1)
    gy = ndimage.sobel(image, axis=0)
    return tuple(ndimage.gaussian_filter(v, sigma) for v in (gx * gx, gx * gy, gy * gy))


def _coherence(jxx, jxy, jyy):
    """How much one direction dominates the gradients (0-1): the structure
    tensor's eigenvalues' difference over their sum."""
    trace = jxx + jyy
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(trace > 1e-6, np.hypot(jxx - jyy, 2 * jxy) / trace, 0.0)


def fill_features(segments, reading):
    """What each segment is filled with: one row per segment 1..n (segments
    numbered 1..n, 0 = none), the columns of :data:`FILL_FEATURES`:

    - ``ink_share``: its cells that are ink;
    - ``hatching_share``: its cells that are hatching;
    - ``orientation_cos``, ``orientation_sin``: the strokes' dominant direction,
      as the cosine and sine of twice its angle (a direction and its opposite
      are one), weighted by how strongly they are oriented;
    - ``coherence``: how much one direction dominates (0 none, 1 parallel
      strokes only), from the segment's summed structure tensor;
    - ``edge_density``: the mean gradient energy of the ink, per cell.

    ``reading``: the map's :class:`InkReading`. Hatching of buildings and of
    water differ by direction and spacing (edge density), not by colour.
    """
    index = np.maximum(segments, 0).ravel()
    n = int(segments.max())
    counts = np.maximum(np.bincount(index, minlength=n + 1), 1).astype(float)

    def mean(values):
        return (np.bincount(index, weights=values.ravel().astype(float), minlength=n + 1)
                / counts)[1:]

    ink = reading.ink.astype(np.float32)
    jxx, jxy, jyy = structure_tensor(ink, max(1.0, reading.scale.stroke))
    sxx, sxy, syy = mean(jxx), mean(jxy), mean(jyy)
    trace = sxx + syy
    diff = np.hypot(sxx - syy, 2 * sxy)
    with np.errstate(divide="ignore", invalid="ignore"):
        coherence = np.where(trace > 0, diff / trace, 0.0)
        # the gradient is across the strokes: their direction is 90 degrees from it
        cos2 = np.where(diff > 0, -(sxx - syy) / diff, 0.0) * coherence
        sin2 = np.where(diff > 0, -2 * sxy / diff, 0.0) * coherence
    return np.column_stack([mean(ink), mean(reading.hatched), cos2, sin2, coherence, trace])
