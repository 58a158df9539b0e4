"""Reading the ink of a scanned map: what its lines divide (pure numpy, scipy, shapely).

Maps draw their units with dark strokes on washes or paper. Each cell's
:func:`brightness` is its largest band (a yellow or pink wash stays bright,
dark red, grey and black ink do not); the paper under the ink is the
brightness closed over a disk wider than any stroke, and a cell's
:func:`ink_contrast` is how much darker it is than that. The strokes' width
is measured once on the whole map (:func:`stroke_scale`, a
:class:`StrokeScale`); regions between the lines :func:`grow` over the ink
and become polygons (:func:`cells_polygon`). Used by the parcels read inside
each plot (``reconstruction.subdivide.drawn``) and the blocks read from the
whole map (``reconstruction.generalize.drawn``).
"""

from dataclasses import dataclass

import numpy as np
import shapely
from scipy import ndimage

from .strokes import disk, stroke_widths

#: a cell is ink where its contrast exceeds the plot's median by this many
#: (scaled) median absolute deviations ...
SPREAD = 3.0
#: ... and by at least this much (0-255 brightness)
MIN_CONTRAST = 24.0
#: the least region, in stroke widths squared (a parcel is at least this many
#: stroke widths on a side)
REGION_STROKES = 6
#: the disk of the paper's closing, in stroke widths (radius)
CLOSING_STROKES = 1.5
#: ink apart from the plot's outline is a line when at least this many stroke
#: widths long ...
LINE_STROKES = 12
#: ... and thin: its cells at most this many widths times its length
THIN = 2.0
#: gaps in the lines up to this many stroke widths are closed (two cells at
#: least): wider closings join the numbers written across narrow parcels to
#: their lines (Venice 1808: 0.5 widths keeps the parcels matched as without,
#: 1 or 2 widths lose 1.3 % of them)
GAP_STROKES = 0.5

@dataclass(frozen=True)
class StrokeScale:
    """The map's own scale for reading its lines: ``stroke`` the median stroke width
    (cells), ``radius`` of the closing disk (cells), ``min_cells`` the least region
    (cells) and ``cell`` the cell size (map units)."""
    stroke: float
    radius: int
    min_cells: int
    cell: float

    @property
    def min_area(self):
        """The least region in square map units."""
        return self.min_cells * self.cell * self.cell


def brightness(rgb):
    """Each cell's largest band (float32): washes stay bright, ink does not."""
    rgb = np.asarray(rgb)
    return rgb.max(axis=2).astype(np.float32) if rgb.ndim == 3 else rgb.astype(np.float32)


def otsu(values):
    """Otsu's threshold of ``values`` (0-255)."""
    hist = np.bincount(np.clip(values, 0, 255).astype(np.int64).ravel(), minlength=256)
    weight = np.cumsum(hist).astype(float)
    mean = np.cumsum(hist * np.arange(256)).astype(float)
    total, grand = weight[-1], mean[-1]
    with np.errstate(divide="ignore", invalid="ignore"):
        between = (grand * weight - total * mean) ** 2 / (weight * (total - weight))
    return float(np.nanargmax(between[:-1])) if total else 128.0


def stroke_scale(rgb, cell, stroke=None, min_area=None):
    """The :class:`StrokeScale` of a scanned map ``rgb`` with cells ``cell`` map
    units wide: the median stroke width measured on the cells at most as bright
    as Otsu's threshold of the brightness (or ``stroke`` map units given), the
    closing's radius :data:`CLOSING_STROKES` times the widths of the thickest
    strokes (their 90th percentile: block outlines are thicker than parcel
    lines; at least 2 cells) and the least region :data:`REGION_STROKES` median
    widths on a side (or ``min_area`` square map units)."""
    if stroke is None:
        level = brightness(rgb)
        widths = stroke_widths(level <= otsu(level))
        width, thick = float(np.median(widths)), float(np.percentile(widths, 90))
    else:
        width = thick = max(1.0, stroke / cell)
    radius = max(2, int(np.ceil(CLOSING_STROKES * thick)))
    cells = (int(np.ceil(min_area / (cell * cell))) if min_area is not None
             else int(np.ceil((REGION_STROKES * width) ** 2)))
    return StrokeScale(stroke=width, radius=radius, min_cells=max(4, cells), cell=cell)


def ink_contrast(rgb, radius):
    """How much darker each cell is than the paper around it: the brightness closed
    over a disk of ``radius`` cells minus the brightness (float32, >= 0)."""
    level = brightness(rgb)
    paper = ndimage.grey_closing(level, footprint=disk(radius))
    return paper - level


def ink_threshold(contrast):
    """The contrast above which a cell is ink: the median of ``contrast`` (the
    cells read) plus :data:`SPREAD` scaled median absolute deviations, at least
    :data:`MIN_CONTRAST`."""
    median = float(np.median(contrast))
    spread = 1.4826 * float(np.median(np.abs(contrast - median)))
    return max(median + SPREAD * spread, MIN_CONTRAST)


def long_parts(cells, length):
    """The 8-connected parts of ``cells`` (bool) whose box's diagonal is at least
    ``length`` cells: the ink of lines, not of letters and numbers."""
    labels, n = ndimage.label(cells, structure=np.ones((3, 3), bool))
    keep = np.zeros(n + 1, bool)
    for k, box in enumerate(ndimage.find_objects(labels), 1):
        if box is not None:
            keep[k] = np.hypot(box[0].stop - box[0].start, box[1].stop - box[1].start) >= length
    return keep[labels]


def close_gaps(lines, stroke, beyond=False):
    """``lines`` (bool) with gaps up to :data:`GAP_STROKES` stroke widths (a cell
    at least) closed, the cells beyond the window taken as ``beyond``."""
    reach = max(1, int(np.ceil(GAP_STROKES * stroke / 2)))
    padded = np.pad(lines, reach + 1, constant_values=beyond)
    return ndimage.binary_closing(padded, structure=disk(reach))[reach + 1:-reach - 1,
                                                                 reach + 1:-reach - 1]


def grow(labels, within):
    """Every cell of ``within`` given the label of the nearest labelled cell (0
    elsewhere)."""
    _, (row, col) = ndimage.distance_transform_edt(labels == 0, return_indices=True)
    return np.where(within, labels[row, col], 0)


def cells_polygon(mask, west, north, cell, row0=0, col0=0):
    """The cells of a boolean mask as one (multi)polygon: each row's runs of cells
    as rectangles, merged (``cell``: the cells' width and height; the mask's first
    cell is cell ``row0``, ``col0`` of the grid whose corner is ``west``,
    ``north``: neighbours' edges get the same coordinates)."""
    padded = np.pad(mask, ((0, 0), (1, 1))).astype(np.int8)
    step = np.diff(padded, axis=1)
    r0, c0 = np.nonzero(step == 1)
    _, c1 = np.nonzero(step == -1)
    r0, c0, c1 = r0 + row0, c0 + col0, c1 + col0
    boxes = shapely.box(west + c0 * cell[0], north - (r0 + 1) * cell[1],
                        west + c1 * cell[0], north - r0 * cell[1])
    return shapely.union_all(boxes)


def labels_coverage(labels, count, west, north, cell):
    """The regions ``labels`` 1 to ``count`` as polygons that share their edges:
    each one's cells (:func:`cells_polygon`), simplified as one coverage by a
    cell (an array of geometries, in label order)."""
    cells = [cells_polygon(labels[box] == k, west, north, cell, box[0].start, box[1].start)
             for k, box in enumerate(ndimage.find_objects(labels, count), 1)]
    return shapely.coverage_simplify(np.asarray(cells, dtype=object), max(cell))
