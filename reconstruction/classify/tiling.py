"""Tiles of a large raster: bounded memory, overlap for seamless joins.

A whole map sheet is tens of megapixels, more than one process should hold
at once. :func:`plan_tiles` cuts the grid into square tiles whose *core*
cells partition it; each tile is worked on with an *outer* window that adds
an overlap on every side (clipped at the map's edge), so that segments,
refilled holes and regions cut by a tile's edge are seen whole from the
tile whose core holds them, and only the core is kept. :func:`tile_side`
sizes the tiles from a memory budget (``memory=`` as GRASS modules take it,
in MB per process). :func:`tuning_windows` picks the sample of a large map
on which the segmentation parameters are tuned.

Cells are (row, col), row 0 the northern row; ranges are half-open. Nothing
here imports GRASS.
"""

import math
from dataclasses import dataclass

from ..core.errors import InputError

#: Memory (bytes) the classification of one cell takes at its peak in one
#: process: three float64 bands, segment ids and their relabelled index,
#: sorts of the band statistics, classes and the refill's counts (measured
#: on the synthetic map: peak resident size over cells, rounded up).
BYTES_PER_CELL = 260
#: Cells of the sample a large map's segmentation is tuned on (about the
#: 0.36-megapixel synthetic map): tuning costs the same whatever the map's size.
TUNING_CELLS = 360_000
#: Windows of that sample, spread over the map.
TUNING_WINDOWS = 4


@dataclass(frozen=True)
class Tile:
    """A tile: its core cells ``[row0, row1) x [col0, col1)`` and its outer
    window (the core with the overlap, clipped to the map)."""

    row0: int
    row1: int
    col0: int
    col1: int
    orow0: int
    orow1: int
    ocol0: int
    ocol1: int

    @property
    def cells(self):
        return (self.row1 - self.row0) * (self.col1 - self.col0)

    @property
    def outer_shape(self):
        return self.orow1 - self.orow0, self.ocol1 - self.ocol0

    @property
    def core(self):
        """Slices of the core in the whole grid."""
        return slice(self.row0, self.row1), slice(self.col0, self.col1)

    @property
    def outer(self):
        """Slices of the outer window in the whole grid."""
        return slice(self.orow0, self.orow1), slice(self.ocol0, self.ocol1)

    @property
    def core_in_outer(self):
        """Slices of the core in an array of the outer window."""
        return (slice(self.row0 - self.orow0, self.row1 - self.orow0),
                slice(self.col0 - self.ocol0, self.col1 - self.ocol0))

    def holds(self, rows, cols):
        """Which cells (arrays of rows and cols) lie in the core."""
        return (rows >= self.row0) & (rows < self.row1) & (cols >= self.col0) & (cols < self.col1)


def tile_side(memory_mb, bytes_per_cell=BYTES_PER_CELL):
    """Side (cells) of the largest square outer window that ``memory_mb`` MB hold."""
    return int(math.sqrt(memory_mb * 1024 * 1024 / bytes_per_cell))


def plan_tiles(rows, cols, side, overlap):
    """Tiles covering a ``rows`` x ``cols`` grid whose outer windows are at
    most ``side`` cells square, with ``overlap`` cells on every side of the core.

    One tile (no overlap) when the grid fits. Refuses (InputError) a side that
    leaves no core: side must exceed twice the overlap.
    """
    if rows <= side and cols <= side:
        return [Tile(0, rows, 0, cols, 0, rows, 0, cols)]
    core = side - 2 * overlap
    if core < 1:
        raise InputError("Tiles of {} cells cannot hold an overlap of {} cells on each side: give "
                         "more memory (memory=)".format(side, overlap))
    n_rows, n_cols = math.ceil(rows / core), math.ceil(cols / core)
    # cores of equal size (within a cell), so that no tile is a thin strip
    row_edges = [round(i * rows / n_rows) for i in range(n_rows + 1)]
    col_edges = [round(j * cols / n_cols) for j in range(n_cols + 1)]
    tiles = []
    for r0, r1 in zip(row_edges, row_edges[1:]):
        for c0, c1 in zip(col_edges, col_edges[1:]):
            tiles.append(Tile(r0, r1, c0, c1, max(r0 - overlap, 0), min(r1 + overlap, rows),
                              max(c0 - overlap, 0), min(c1 + overlap, cols)))
    return tiles


def tile_overlap(window, min_cells):
    """Overlap (cells) of the tiles: room for the segments, the refill
    window and a region of the minimum mapping unit on either side of an edge.

    At least 64 cells (about the size of a building block's segment), four
    refill windows, or twice the side of the minimum mapping unit.
    """
    return max(64, 4 * int(window), 2 * int(math.ceil(math.sqrt(max(min_cells, 0)))))


def check_tiles(side, window):
    """Refuse tiles smaller than the refill window (InputError)."""
    if side < window:
        raise InputError("Tiles of {0}x{0} cells (memory=) are smaller than the refill window "
                         "({1}x{1} cells): give more memory or a smaller window=".format(side, window))


def tuning_windows(rows, cols, cells=TUNING_CELLS, count=TUNING_WINDOWS):
    """The windows (tiles without overlap) of the sample a map is tuned on.

    The whole map when it has at most ``cells`` cells; otherwise ``count``
    square windows of ``cells / count`` cells, centred in the quarters of
    the map (clipped to it).
    """
    if rows * cols <= cells:
        return [Tile(0, rows, 0, cols, 0, rows, 0, cols)]
    side = int(math.sqrt(cells / count))
    half = max(1, int(round(math.sqrt(count))))
    windows = []
    for i in range(half):
        for j in range(half):
            cr = int((i + 0.5) * rows / half)
            cc = int((j + 0.5) * cols / half)
            r0 = min(max(cr - side // 2, 0), max(rows - side, 0))
            c0 = min(max(cc - side // 2, 0), max(cols - side, 0))
            r1, c1 = min(r0 + side, rows), min(c0 + side, cols)
            windows.append(Tile(r0, r1, c0, c1, r0, r1, c0, c1))
    return windows
