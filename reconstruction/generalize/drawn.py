"""Plots read from the outlines a map draws (v.histo.generalize map= -d).

A cadaster outlines every block and every parcel in ink; the classification
tells which cells are built, but its edges wander and a few wrongly
classified cells in a narrow street join the blocks on both sides (Venice
1808: the chain's blocks F 0.24). Here the map's lines decide where a plot
ends and the classification only which of the regions they close are built
(pure numpy, scipy and shapely; the ink as read in
:mod:`reconstruction.geom.ink`):

1. **The lines.** A cell is ink where it is darker than the paper around it
   by more than the map's own spread (median + :data:`~reconstruction.geom.ink.SPREAD`
   median absolute deviations, at least :data:`~reconstruction.geom.ink.MIN_CONTRAST`);
   the ink of lines is the 8-connected ink at least
   :data:`~reconstruction.geom.ink.LINE_STROKES` stroke widths long (its box's
   diagonal): numbers written over a parcel are no line. Gaps of half a
   stroke width (a cell at least) are closed, as inside the plots (wider
   closings join the letters of a narrow street's name to the outlines on
   both sides and close the street).
2. **The regions they close** are the 4-connected cells between the lines.
   A region is built whole when at least :data:`UNIFORM` of its cells are
   classified building, open when as many are not, and keeps its cells as
   classified in between (the lines do not close what the classification
   finds there); it is built whole only when at least the map's least unit
   (:func:`~reconstruction.geom.ink.stroke_scale`: a square
   :data:`~reconstruction.geom.ink.REGION_STROKES` stroke widths wide): the
   pieces of a street that the letters of its name cut off are smaller, and
   a few of their cells classified building no longer join two blocks.
3. **The plots.** Every line cell takes the decision of the nearest region
   (a line between two built parcels is built, the outline between a block
   and its street is split along its middle); the built cells' 4-connected
   parts are the plots, polygonised row runs simplified as one coverage.
"""

from dataclasses import dataclass

import numpy as np
from scipy import ndimage

from ..geom.ink import (LINE_STROKES, StrokeScale, close_gaps, ink_contrast, ink_threshold,
                        labels_coverage, long_parts, stroke_scale)
from ..geom.polygons import cells_inside, polygon_parts

#: a region the lines close is decided whole when at least this share of its
#: cells agree (built when classified building, open when not); between, the
#: lines do not close what the classification finds (a map that draws no outline
#: between its blocks and streets: one region, a third of it built) and its
#: cells stay as classified (synthetic Delft style: 97-100 % of the plots with
#: it, 0-5 % when every region is decided by a half; Venice 1808 blocks F 0.63
#: with it, 0.68 by a half)
UNIFORM = 0.8


@dataclass(frozen=True)
class DrawnPlots:
    """What :func:`drawn_plots` read: ``polygons`` the plots (Polygons),
    ``regions`` how many regions of at least the least unit the lines close,
    ``built`` how many of them are built whole, ``scale`` the map's
    :class:`~reconstruction.geom.ink.StrokeScale`."""
    polygons: list
    regions: int
    built: int
    scale: StrokeScale


def building_cells(polygons, extent, shape):
    """The cells of a grid of ``shape`` (rows, cols) over ``extent`` (west, east,
    south, north) whose centres lie in one of ``polygons``."""
    rows, cols = shape
    west, east, south, north = (float(v) for v in extent)
    return cells_inside(polygons, west, north, ((east - west) / cols, (north - south) / rows),
                        shape)


def line_cells(contrast, stroke):
    """The ink of lines (bool): cells darker than the paper beyond the map's own
    spread, in 8-connected parts at least :data:`LINE_STROKES` stroke widths long,
    gaps up to :data:`~reconstruction.geom.ink.GAP_STROKES` widths closed."""
    ink = contrast > ink_threshold(contrast)
    return close_gaps(long_parts(ink, LINE_STROKES * stroke), stroke)


def built_cells(line, building, min_cells):
    """Which cells are built (bool): the regions between the ``line`` cells of at
    least ``min_cells`` cells with at least :data:`UNIFORM` of them ``building``
    cells, and the ``building`` cells of those with less but more than 1 -
    :data:`UNIFORM`; each line cell as its nearest region. Returns the mask, the
    count of such regions and of the ones built whole."""
    regions, n = ndimage.label(~line)
    cells = np.bincount(regions.ravel(), minlength=n + 1)
    share = np.bincount(regions.ravel(), weights=building.ravel(), minlength=n + 1)
    share /= np.maximum(cells, 1)
    big = cells >= min_cells
    big[0] = False
    whole = big & (share >= UNIFORM)
    mixed = big & (share > 1.0 - UNIFORM) & ~whole
    decided = whole[regions] | (mixed[regions] & building)
    _, (row, col) = ndimage.distance_transform_edt(line, return_indices=True)
    return decided[row, col], int(big.sum()), int(whole.sum())


def drawn_plots(rgb, extent, building, stroke=None, min_area=None):
    """The plots a map's drawn outlines close, the built ones: a :class:`DrawnPlots`.

    ``rgb`` (rows, cols, 3) uint8, north-up, over ``extent`` (west, east,
    south, north); ``building`` (rows, cols) bool: the cells classified
    building; ``stroke`` (map units) and ``min_area`` (square map units)
    override what is measured on the map (the least unit).
    """
    rgb = np.asarray(rgb)
    west, east, south, north = (float(v) for v in extent)
    rows, cols = rgb.shape[:2]
    cell = ((east - west) / cols, (north - south) / rows)
    scale = stroke_scale(rgb, float(np.sqrt(cell[0] * cell[1])), stroke, min_area)
    line = line_cells(ink_contrast(rgb, scale.radius), scale.stroke)
    mask, regions, built = built_cells(line, np.asarray(building, bool), scale.min_cells)
    labels, count = ndimage.label(mask)
    polygons = []
    if count:
        for g in labels_coverage(labels, count, west, north, cell):
            polygons.extend(p for p in polygon_parts(g) if p.area >= scale.min_area)
    return DrawnPlots(polygons, regions, built, scale)
