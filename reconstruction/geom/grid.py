"""A raster as a numpy array with its place on the ground (and the box an input covers,
:class:`Extent`).

GRASS's region conventions: row 0 is the northern row, cells are
``nsres`` by ``ewres`` map units, ``north`` and ``west`` are the outer edges
of the raster. :func:`reconstruction.grassio.maps.read_raster` reads a raster in
the current region, so ``Grid.from_region(values, gs.region())`` places
it.
"""

from dataclasses import dataclass
from typing import Optional

import numpy as np

from ..core.errors import InputError


@dataclass(frozen=True)
class Grid:
    """A raster: ``values`` (rows, cols), NaN for no data, north-up.

    ``values`` may be None for the place of a raster alone (a GRASS region:
    r.histo.classify locates its training points on it before reading any
    map); ``size`` (rows, cols) then gives its shape.
    """

    values: Optional[np.ndarray]
    north: float
    west: float
    nsres: float
    ewres: float
    size: Optional[tuple] = None

    def __post_init__(self):
        if self.values is None:
            if self.size is None or len(self.size) != 2:
                raise InputError("A grid without values needs its size (rows, cols)")
        elif np.ndim(self.values) != 2:
            raise InputError("A raster must be a 2D array, not of shape {}".format(
                np.shape(self.values)))
        if not (self.nsres > 0 and self.ewres > 0):
            raise InputError("A raster's resolution must be positive (nsres={}, ewres={})".format(
                self.nsres, self.ewres))

    @classmethod
    def from_region(cls, values, region):
        """A grid from a GRASS region dict (keys ``n``, ``w``, ``nsres``, ``ewres``; and
        ``rows``, ``cols`` when ``values`` is None)."""
        size = (int(region["rows"]), int(region["cols"])) if values is None else None
        return cls(None if values is None else np.asarray(values), float(region["n"]),
                   float(region["w"]), float(region["nsres"]), float(region["ewres"]), size)

    @property
    def shape(self):
        return tuple(self.size) if self.values is None else self.values.shape

    @property
    def rows(self):
        return self.shape[0]

    @property
    def cols(self):
        return self.shape[1]

    def cells(self, x, y):
        """Row and column of the cells holding points ``(x, y)``; -1 outside the raster."""
        x = np.asarray(x, dtype=float)
        y = np.asarray(y, dtype=float)
        rows, cols = self.shape
        row = np.floor((self.north - y) / self.nsres).astype(np.int64)
        col = np.floor((x - self.west) / self.ewres).astype(np.int64)
        inside = (row >= 0) & (row < rows) & (col >= 0) & (col < cols)
        return np.where(inside, row, -1), np.where(inside, col, -1)

    def centres(self, row, col):
        """Coordinates ``(x, y)`` of the centres of cells ``(row, col)``."""
        x = self.west + (np.asarray(col, dtype=float) + 0.5) * self.ewres
        y = self.north - (np.asarray(row, dtype=float) + 0.5) * self.nsres
        return x, y

    def sample(self, x, y, fill=np.nan):
        """The value of the cell under each point ``(x, y)``; ``fill`` outside the raster."""
        row, col = self.cells(x, y)
        inside = row >= 0
        out = np.full(np.shape(row), fill, dtype=np.result_type(self.values.dtype, type(fill)))
        out[inside] = self.values[row[inside], col[inside]]
        return out

    def window(self, bounds):
        """Cell ranges ``(row0, row1, col0, col1)`` (inclusive, clipped; row1 < row0 when
        empty) of the cells whose centres may lie inside boxes ``bounds`` (F, 4) =
        ``(xmin, ymin, xmax, ymax)``."""
        bounds = np.asarray(bounds, dtype=float).reshape(-1, 4)
        rows, cols = self.shape
        col0 = np.ceil((bounds[:, 0] - self.west) / self.ewres - 0.5).astype(np.int64)
        col1 = np.floor((bounds[:, 2] - self.west) / self.ewres - 0.5).astype(np.int64)
        row0 = np.ceil((self.north - bounds[:, 3]) / self.nsres - 0.5).astype(np.int64)
        row1 = np.floor((self.north - bounds[:, 1]) / self.nsres - 0.5).astype(np.int64)
        return (np.maximum(row0, 0), np.minimum(row1, rows - 1),
                np.maximum(col0, 0), np.minimum(col1, cols - 1))


def expand_ranges(starts, stops):
    """The indices ``start, ..., stop - 1`` of every range, concatenated, and the
    number of the range each comes from (ranges with stop <= start are empty)."""
    starts = np.asarray(starts, dtype=np.int64)
    lengths = np.maximum(np.asarray(stops, dtype=np.int64) - starts, 0)
    owner = np.repeat(np.arange(len(starts)), lengths)
    offset = np.cumsum(lengths) - lengths
    return starts[owner] + np.arange(int(lengths.sum())) - offset[owner], owner


@dataclass(frozen=True)
class Extent:
    """The box ``x0..x1``, ``y0..y1`` (map units) an input covers: for the
    warnings and errors of inputs that do not meet (footprints 100 km from
    the plots, a map picture of another area), which name both boxes."""
    x0: float
    y0: float
    x1: float
    y1: float

    @classmethod
    def of(cls, geometries):
        """The extent of shapely ``geometries`` (None and empty ones left out);
        None when there is none."""
        import shapely

        geoms = np.asarray([g for g in geometries if g is not None], dtype=object)
        if not len(geoms) or shapely.is_empty(geoms).all():
            return None
        return cls(*(float(v) for v in shapely.total_bounds(geoms)))

    def meets(self, other, margin=0.0):
        """Whether the two boxes, this one grown by ``margin``, overlap or touch."""
        return (self.x0 - margin <= other.x1 and other.x0 <= self.x1 + margin
                and self.y0 - margin <= other.y1 and other.y0 <= self.y1 + margin)

    def text(self):
        """``x 85000..85200, y 446000..446300``, to the map unit."""
        return "x {:.0f}..{:.0f}, y {:.0f}..{:.0f}".format(self.x0, self.x1, self.y0, self.y1)


@dataclass(frozen=True)
class MapImage:
    """A map to drape on the ground: ``rgb`` (rows, columns, 3) uint8, row 0
    at the north; ``extent``: west, east, south, north (model x, y)."""
    rgb: np.ndarray
    extent: tuple

    @property
    def place(self):
        """Its :class:`Extent` on the ground."""
        west, east, south, north = (float(v) for v in self.extent)
        return Extent(west, south, east, north)
