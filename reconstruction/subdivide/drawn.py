"""Footprints read from the lines a map draws inside its plots (v.histo.subdivide map=).

Cadasters draw every parcel, insurance maps every building: thin dark lines
divide a block (a plot, in the chain's terms) into the units the map
records. Where a plot holds such lines, its footprints follow them instead
of being generated (issue 50); a plot without inner lines is left to the
procedural cases as before.

How the lines are read, on a plot's cells of the scanned map (pure numpy,
scipy and shapely):

1. **Ink is darker than the paper around it.** Each cell's brightness is
   the largest of its three bands (a yellow or pink wash stays bright, dark
   red, grey and black ink do not); the paper under the ink is the
   brightness closed (grey-level dilation then erosion) over a disk wider
   than any stroke, and a cell's ink contrast is how much darker it is than
   that. A cell is ink where its contrast stands out from the plot's own
   spread (:func:`~reconstruction.geom.ink.ink_threshold`: median +
   :data:`~reconstruction.geom.ink.SPREAD` median absolute deviations, at
   least :data:`~reconstruction.geom.ink.MIN_CONTRAST`): the threshold
   follows the plot's wash and the scan's noise, not a colour trained on
   another map.
2. **Regions are what the lines leave.** Letters and numbers written over
   a parcel are no lines: only the ink connected to the plot's outline, or
   drawn as a thin long stroke, is a line (:func:`lines`); writing stays a
   hole in its parcel's region. Gaps in a line up to half a stroke wide (two
   cells at least) are closed, and the plot's edge is read
   :data:`EDGE_STROKES` widths wide, so that a line stopping that short of
   the block's outline still meets it (wider closings would join the
   numbers written across narrow parcels to their lines). A line's end is
   then drawn on straight (:func:`extend_ends`): the lines are thinned to
   their median lines (:func:`thin`), and an end whose last
   :data:`TRACE_STROKES` to :data:`STRAIGHT_STROKES` widths run straight goes
   on along them, across at most :data:`EXTEND_STROKES` widths of paper,
   when it meets another line or the plot's edge there: the gaps of one to
   two strokes in a line, the ends stopping short of the line they join. An
   end that meets nothing stays as it is, and writing is never met (it is no
   line) nor drawn on (a letter's strokes are short or curved); a line broken
   by a wider gap joins the two sides (one footprint where the map has two:
   the safe side). The plot's other cells fall into 4-connected regions; a
   region smaller than the least area (:func:`stroke_scale`: in the map's
   own scale, from the stroke width) is no unit of the map.
3. **Regions grow over the ink.** Every cell of the plot goes to the
   nearest region (a line between two parcels is split along its middle; a
   number's cells go to the parcel it is written on), the regions become
   polygons (rows of cells merged, stairs simplified as one coverage, so
   neighbours keep one shared edge) and are cut to the plot.

A plot is divided when at least two regions remain. The width of the
strokes is measured once on the whole map (:func:`stroke_scale`): the
median width across the dark cells' median lines.
"""

from dataclasses import dataclass, field
from typing import Optional

import numpy as np
import shapely
from scipy import ndimage

from ..geom.ink import (LINE_STROKES, THIN, StrokeScale, close_gaps, grow, ink_contrast,
                        ink_threshold, labels_coverage, stroke_scale)
from ..geom.polygons import cells_inside, polygon_parts
from .plots import OVERLAP_TOLERANCE

#: a line that stops at most this many stroke widths short of the plot's edge
#: meets it: the cells that near both the edge and a line are a line
EDGE_STROKES = 3.0
#: a line's end is read over at least this many stroke widths of its median
#: line (an end whose branch is shorter, a spur of the thinning or a letter's
#: stroke touching a line, is no end) ...
TRACE_STROKES = 3.0
#: ... and at most this many: its direction is the principal axis of those
#: cells, and they keep within :data:`STRAIGHT` widths of it, or one cell (a
#: sloping line steps by one; a digit touching a line curves away: Venice 1808
#: loses a parcel to a 6 drawn on at 0.4 or 0.5)
STRAIGHT_STROKES = 8.0
STRAIGHT = 0.3
#: a line's end is drawn on straight, over at most this many stroke widths of
#: paper, when it meets another line or the plot's edge there: the ends that
#: stop short of the line they join (1-3 cells on the synthetic cadaster), the
#: gaps of two to four cells in a line; a wider closing of every line would join
#: the numbers written across narrow parcels to their lines
EXTEND_STROKES = 4.0


def _neighbour_tables():
    """For each of the 256 codes of a cell's eight neighbours (bit k: the k-th of
    N, NE, E, SE, S, SW, W, NW set): how many are set, how many times the ring
    goes from unset to set, and whether Zhang and Suen's two passes remove the
    cell."""
    bits = (np.arange(256)[:, None] >> np.arange(8)) & 1
    count = bits.sum(axis=1)
    crossings = ((bits == 0) & (np.roll(bits, -1, axis=1) == 1)).sum(axis=1)
    n, e, s, w = bits[:, 0], bits[:, 2], bits[:, 4], bits[:, 6]
    removable = (count >= 2) & (count <= 6) & (crossings == 1)
    first = removable & (n * e * s == 0) & (e * s * w == 0)
    second = removable & (n * e * w == 0) & (n * s * w == 0)
    return count, crossings, first, second


_COUNT, _CROSSINGS, _FIRST, _SECOND = _neighbour_tables()
#: the weights of the eight neighbours in a cell's code (N, NE, E, SE, S, SW, W, NW)
_WEIGHTS = np.array([[128, 1, 2], [64, 0, 4], [32, 16, 8]], np.int32)
#: the offsets (row, column) of the eight neighbours
_STEPS = ((-1, 0), (-1, 1), (0, 1), (1, 1), (1, 0), (1, -1), (0, -1), (-1, -1))


def _codes(mask):
    return ndimage.correlate(mask.astype(np.int32), _WEIGHTS, mode="constant")


def thin(mask):
    """The median lines of a boolean mask, one cell wide (Zhang and Suen's thinning)."""
    skeleton = np.asarray(mask, dtype=bool).copy()
    changed = True
    while changed:
        changed = False
        for table in (_FIRST, _SECOND):
            gone = skeleton & table[_codes(skeleton)]
            if gone.any():
                skeleton &= ~gone
                changed = True
    return skeleton


def _trace(skeleton, junction, start, length):
    """The cells of the skeleton's branch from the end ``start`` up to a junction or
    its other end, at most ``length`` of them (from ``start`` on)."""
    rows, cols = skeleton.shape
    path, seen = [start], {start}
    r, c = start
    while len(path) < length:
        nxt = [(r + dr, c + dc) for dr, dc in _STEPS
               if 0 <= r + dr < rows and 0 <= c + dc < cols and skeleton[r + dr, c + dc]
               and (r + dr, c + dc) not in seen]
        if not nxt or any(junction[q] for q in nxt):
            break
        if any(max(abs(a[0] - b[0]), abs(a[1] - b[1])) > 1 for a in nxt for b in nxt):
            break                            # two ways on: a junction
        seen.update(nxt)
        r, c = max(nxt, key=lambda q: abs(q[0] - r) + abs(q[1] - c))
        path.append((r, c))
    return path


def extend_ends(line, inside, stroke):
    """The cells that draw the lines' ends on (bool): each end of the median lines
    of ``line`` (:func:`thin`) whose branch is at least :data:`TRACE_STROKES` stroke
    widths long goes on along its direction; the cells it crosses count when, within
    :data:`EXTEND_STROKES` widths of paper, it meets a line or leaves the plot
    (``inside`` false). An end that meets nothing stays as it is."""
    extended = np.zeros(line.shape, bool)
    skeleton = thin(line)
    codes = _codes(skeleton)
    ends = skeleton & (_CROSSINGS[codes] == 1) & (_COUNT[codes] <= 2)
    if not ends.any():
        return extended
    junction = skeleton & (_CROSSINGS[codes] >= 3)
    barrier = line | ~inside
    length = max(3, int(round(TRACE_STROKES * stroke)))
    longest = max(length, int(round(STRAIGHT_STROKES * stroke)))
    reach = EXTEND_STROKES * stroke
    for start in zip(*np.nonzero(ends)):
        path = _trace(skeleton, junction, (int(start[0]), int(start[1])), longest)
        if len(path) < length:
            continue
        points = np.asarray(path, float)
        centred = points - points.mean(axis=0)
        direction = np.linalg.svd(centred, full_matrices=False)[2][0]
        if np.abs(centred @ (direction[1], -direction[0])).max() > max(STRAIGHT * stroke, 1.0):
            continue                         # a curve: a letter's stroke
        if direction @ centred[0] < 0:
            direction = -direction
        cells = _ray(barrier, points[0], direction, reach, stroke)
        if cells is not None:
            extended[tuple(np.asarray(cells).T)] = True
    return extended


def _ray(barrier, origin, direction, reach, stroke):
    """The cells (4-connected) from ``origin`` along ``direction`` out of its ink and
    across at most ``reach`` cells of paper up to the first cell of ``barrier``
    (or the window's edge: outside the plot); None when it meets none."""
    rows, cols = barrier.shape
    cells, free, last = [], 0, None
    out_of_ink = False
    for t in np.arange(0.5, reach + 2 * stroke + 2, 0.5):
        r, c = (int(v) for v in np.rint(origin + t * direction))
        if (r, c) == last:
            continue
        if last is not None and r != last[0] and c != last[1]:
            corner = (r, last[1])
            if not (0 <= corner[0] < rows and 0 <= corner[1] < cols) or barrier[corner]:
                if out_of_ink:
                    return cells
            elif out_of_ink:
                cells.append(corner)
                free += 1
        last = (r, c)
        if not (0 <= r < rows and 0 <= c < cols):
            return cells if out_of_ink else None
        if barrier[r, c]:
            if out_of_ink:
                return cells
            if t > 2 * stroke + 1:
                return None                  # still in the ink: no end here
            continue
        out_of_ink = True
        cells.append((r, c))
        free += 1
        if free > reach:
            return None
    return None


@dataclass(frozen=True)
class DrawnDivisions:
    """What :func:`read_divisions` found: ``parcels`` {plot category: [Polygon, ...]}
    for every plot the map divides (two parcels or more) and, when the map draws
    every unit, every plot it does not divide (the plot itself: ``whole`` of
    them); ``scale`` the :class:`StrokeScale` used, ``plots_read`` how many
    plots lay on the map."""
    parcels: dict = field(default_factory=dict)
    scale: Optional[StrokeScale] = None
    plots_read: int = 0
    whole: int = 0

    @property
    def count(self):
        return sum(len(p) for p in self.parcels.values())


def lines(ink, inside, stroke):
    """The ink of lines, not of writing: the ink connected (8 ways) to what lies
    outside the plot (its outline and the lines that meet it), and the ink apart
    from it that is drawn as a line: at least :data:`LINE_STROKES` stroke widths
    long (its box's diagonal) and thin (its cells at most :data:`THIN` stroke widths
    times that length: a line's cells are about one width times its length, a
    number's strokes wind over three to four times its length)."""
    labels, n = ndimage.label(ink | ~inside, structure=np.ones((3, 3), bool))
    if n == 0:
        return ink
    keep = np.zeros(n + 1, bool)
    keep[np.unique(labels[~inside])] = True
    boxes = ndimage.find_objects(labels)
    sizes = np.bincount(labels.ravel(), minlength=n + 1)
    for k, box in enumerate(boxes, 1):
        if keep[k] or box is None:
            continue
        length = float(np.hypot(box[0].stop - box[0].start, box[1].stop - box[1].start))
        keep[k] = length >= LINE_STROKES * stroke and sizes[k] <= THIN * stroke * length
    keep[0] = False
    return keep[labels] & inside


def regions(contrast, inside, scale):
    """The regions of one plot: ``inside`` its cells (bool), ``contrast`` their ink
    contrast, ``scale`` the map's :class:`StrokeScale`. The plot's ink is read
    (its threshold from the plot's own spread), its lines kept (:func:`lines`),
    and gaps in them closed (:func:`~reconstruction.geom.ink.close_gaps`, on
    the lines and what lies outside the plot). Returns labels (int32, 0
    elsewhere) of the 4-connected regions of at least ``scale.min_cells`` cells
    between the lines, and their count (0 or 1: the plot is not divided, and
    the labels are all 0)."""
    values = contrast[inside]
    if values.size == 0:
        return np.zeros(inside.shape, np.int32), 0
    ink = contrast > ink_threshold(values)
    line = lines(ink, inside, scale.stroke)
    barrier = close_gaps(line | ~inside, scale.stroke, beyond=True)
    barrier |= extend_ends(barrier & inside, inside, scale.stroke)
    edge = EDGE_STROKES * scale.stroke
    if edge and line.any():
        # a line's end near the plot's edge meets it: the cells near both
        outside = ndimage.distance_transform_edt(np.pad(inside, 1))[1:-1, 1:-1]
        barrier |= (outside <= edge) & (ndimage.distance_transform_edt(~line) <= edge)
    labels, n = ndimage.label(inside & ~barrier)
    if n < 2:
        return np.zeros(inside.shape, np.int32), n
    # a region's size: the cells nearest to it (what it grows to), not the cells
    # the lines and the edge leave of it (a small annex is mostly edge)
    sizes = np.bincount(grow(labels, inside).ravel(), minlength=n + 1)
    big = sizes >= scale.min_cells
    big[0] = False
    count = int(big.sum())
    if count < 2:
        return np.zeros(inside.shape, np.int32), min(count, 1)
    renumber = np.zeros(n + 1, np.int32)
    renumber[big] = np.arange(1, count + 1)
    return renumber[labels], count


def plot_parcels(polygon, contrast, west, north, cell, scale):
    """The parcels one plot's drawn lines make (Polygons, at least two), or [] when the
    map draws no division in it. ``contrast``: the window's ink contrast, its
    north-west corner at (``west``, ``north``), cells ``cell`` (width, height)."""
    rows, cols = contrast.shape
    inside = cells_inside([polygon], west, north, cell, (rows, cols))
    labels, count = regions(contrast, inside, scale)
    if count < 2:
        return []
    # every cell goes to the nearest region, one cell beyond the plot too, so
    # that the parcels cut to the plot cover it
    labels = grow(labels, ndimage.binary_dilation(inside, iterations=1))
    simple = labels_coverage(labels, count, west, north, cell)
    out = []
    for g in shapely.intersection(simple, polygon):
        parts = [p for p in polygon_parts(g) if p.area >= 0.5 * scale.min_area]
        if parts:
            out.append(max(parts, key=lambda p: p.area))
    return out if len(out) >= 2 else []


def read_divisions(rgb, extent, plots, cats, stroke=None, min_area=None, progress=None,
                   whole=False):
    """The parcels the map draws in each plot: a :class:`DrawnDivisions`.

    ``rgb`` (rows, cols, 3) uint8, north-up, with ``extent`` (west, east, south,
    north); ``plots`` shapely polygons with their categories ``cats``;
    ``stroke`` (map units) and ``min_area`` (square map units) override what is
    measured on the map (:func:`stroke_scale`); ``progress(done, total)`` is
    called as plots are read. ``whole``: the map draws every unit (a cadaster's
    parcels, an insurance map's buildings), so a plot on the map without inner
    lines is one unit; otherwise it is left to the procedural cases."""
    rgb = np.asarray(rgb)
    west, east, south, north = (float(v) for v in extent)
    rows, cols = rgb.shape[:2]
    cell = ((east - west) / cols, (north - south) / rows)
    scale = stroke_scale(rgb, float(np.sqrt(cell[0] * cell[1])), stroke, min_area)
    contrast = ink_contrast(rgb, scale.radius)
    parcels, read, alone = {}, 0, 0
    for k, (polygon, cat) in enumerate(zip(plots, cats)):
        if progress is not None:
            progress(k, len(plots))
        if polygon is None or polygon.is_empty:
            continue
        x0, y0, x1, y1 = polygon.bounds
        c0 = max(int((x0 - west) / cell[0]) - 1, 0)
        c1 = min(int((x1 - west) / cell[0]) + 2, cols)
        r0 = max(int((north - y1) / cell[1]) - 1, 0)
        r1 = min(int((north - y0) / cell[1]) + 2, rows)
        if c1 - c0 < 2 or r1 - r0 < 2:
            continue
        read += 1
        found = plot_parcels(polygon, contrast[r0:r1, c0:c1], west + c0 * cell[0],
                             north - r0 * cell[1], cell, scale)
        if found:
            parcels[cat] = found
        elif whole:
            parcels[cat] = [polygon]
            alone += 1
    return DrawnDivisions(parcels, scale, read, alone)


def free_parcels(parcels, plot, taken):
    """``parcels`` within their ``plot`` (as repaired and made disjoint from its
    neighbours), less the footprints ``taken`` before them in it (aligned, kept
    from an earlier epoch): each parcel's polygons of at least a tenth of its area
    (and more than :data:`~reconstruction.subdivide.plots.OVERLAP_TOLERANCE`); a
    parcel under a taken footprint is gone."""
    cut = shapely.union_all([g for g in taken if g is not None]) if taken else None
    out = []
    for parcel in parcels:
        rest = shapely.intersection(parcel, plot)
        if cut is not None and rest.intersects(cut):
            rest = shapely.difference(rest, cut)
        out.extend(p for p in polygon_parts(rest)
                   if p.area > max(OVERLAP_TOLERANCE, 0.1 * parcel.area))
    return out
