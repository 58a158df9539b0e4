"""Reference heights of footprints from elevation data and measured columns.

The thesis's Section 3.4.1 (after Dukai et al. 2019), in bulk:

- **ground** (:func:`ground_from_points`, :func:`ground_from_raster`): the
  ground points (or DTM cells) in the footprint buffered by 0.5 m; where
  there are none, the buffer grows step by step (0.5 m) until there are (a
  building replaced by a larger one leaves a hole in today's point cloud);
  the percentiles 0, 10, ..., 50 of their heights, ``percentile`` (20 by
  default) the one used.
- **roof** (:func:`roof_from_points`): the percentiles 25 and 99 of the
  building points inside each footprint, the thesis's ``roof-0.25`` (eaves)
  and ``roof-0.99`` (top).
- **measured heights** of aligned footprints (:func:`measured_heights`) from
  the thesis's percentile columns (ground-0.2, roof-0.25, roof-0.99; GRASS
  spells them ground_0_2 ...) or the 3D BAG's attributes
  (:class:`HeightColumns`): ground ``b3_h_maaiveld``, eaves the thesis's
  25th roof percentile extrapolated from the 50th and 70th, top the main
  ridge ``b3_h_nok`` (2025 releases; else the maximum).

All heights here are absolute (terrain and roofs above the datum), but the
measured ones, which follow the data-flow contract: ``eaves`` above the
ground and ``attic`` above the eaves.

Speed: the points are sorted once into square buckets (the thesis's
clusters, as one numpy sort); a footprint reads only the buckets under its
buffered bounding box, tested with shapely's vectorised point-in-polygon.
No footprint scans all points.
"""

import math
import re
from dataclasses import dataclass
from typing import Optional

import numpy as np

from ..core.errors import InputError
from ..geom.grid import Grid, expand_ranges
from ..geom.rings import offsets
from .groupstats import group_percentiles

#: the ground percentiles the thesis computes (columns ground-0.0 ... ground-0.5)
GROUND_PERCENTILES = (0.0, 10.0, 20.0, 30.0, 40.0, 50.0)
#: the roof percentiles the thesis computes from building points (roof-0.25, roof-0.99)
ROOF_PERCENTILES = (25.0, 99.0)

# Plausible heights (issue 49, item 8). A value outside them is a mistake in
# the data (a ground of -1,000 m, a height in millimetres, 1e9), never a
# building: measured heights outside are not used (counted by reason, the
# footprint's heights inferred as an unmeasured one's), heights from the
# footprints' own columns and grounds outside stop the module with one error.
#: the tallest plausible building (m, its top above its ground): the
#: tallest church towers of the historical maps' towns stand 100-160 m
#: (Ulm 161.5 m), a 20th-century tower a few hundred
MAX_HEIGHT = 300.0
#: plausible ground elevations (m): land lies between the Dead Sea's shore
#: (-430 m) and the top of Everest (8,849 m)
GROUND_RANGE = (-450.0, 8850.0)
#: a measured ground this far (m) from the median of the table's other grounds
#: is implausible: a town's ground spans less (Delft 1880: -2.5..3.2 m;
#: Brussels about 15-100 m)
MAX_GROUND_SPREAD = 500.0
#: a measured roof top this far (m) below the eaves is inverted (within it: a flat roof)
INVERTED_TOLERANCE = 0.01

#: why measured heights are not used (:attr:`MeasuredHeights.problem`), in the order checked
NULL = "NULL"
GROUND_OUTSIDE = "ground outside {:g}..{:g} m".format(*GROUND_RANGE)
GROUND_APART = "ground more than {:g} m from the others' median".format(MAX_GROUND_SPREAD)
NOT_ABOVE = "eaves not above the ground"
INVERTED = "roof top below the eaves"
TOO_TALL = "taller than {:g} m".format(MAX_HEIGHT)


# ---------------------------------------------------------------------------
# Points and cells near footprints
# ---------------------------------------------------------------------------

class PointBuckets:
    """3D points sorted into square buckets: the one spatial index of the points."""

    def __init__(self, xyz, size=None):
        xyz = np.asarray(xyz, dtype=float)
        if xyz.size and (xyz.ndim != 2 or xyz.shape[1] != 3):
            raise InputError("Points must have x, y and z (an N x 3 array), not shape {}: "
                             "a 2D point map has no heights".format(xyz.shape))
        xyz = xyz.reshape(-1, 3)
        xyz = xyz[np.all(np.isfinite(xyz), axis=1)]
        self.xyz = xyz
        if not len(xyz):
            self.size, self.x0, self.y0, self.ncols, self.nrows = 1.0, 0.0, 0.0, 0, 0
            self.starts = np.zeros(1, dtype=np.int64)
            return
        lo = xyz[:, :2].min(axis=0)
        hi = xyz[:, :2].max(axis=0)
        if size is None:
            # about 16 points a bucket, but never below 1 m
            area = max(float(np.prod(hi - lo)), 1.0)
            size = max(1.0, 4.0 * math.sqrt(area / len(xyz)))
        self.size = float(size)
        self.x0, self.y0 = float(lo[0]), float(lo[1])
        self.ncols = int((hi[0] - lo[0]) // size) + 1
        self.nrows = int((hi[1] - lo[1]) // size) + 1
        col = ((xyz[:, 0] - self.x0) // size).astype(np.int64)
        row = ((xyz[:, 1] - self.y0) // size).astype(np.int64)
        cell = row * self.ncols + col
        order = np.argsort(cell, kind="stable")
        self.xyz = xyz[order]
        counts = np.bincount(cell, minlength=self.nrows * self.ncols)
        self.starts = offsets(counts)

    def candidates(self, bounds):
        """Points in the buckets under boxes ``bounds`` (F, 4): the box of each
        (owner) and the points' ``x, y, z``."""
        if not len(self.xyz):
            e = np.zeros(0)
            return np.zeros(0, dtype=np.int64), e, e, e
        bounds = np.asarray(bounds, dtype=float).reshape(-1, 4)
        c0 = np.clip(((bounds[:, 0] - self.x0) // self.size).astype(np.int64), 0, self.ncols)
        c1 = np.clip(((bounds[:, 2] - self.x0) // self.size).astype(np.int64), -1, self.ncols - 1)
        r0 = np.clip(((bounds[:, 1] - self.y0) // self.size).astype(np.int64), 0, self.nrows)
        r1 = np.clip(((bounds[:, 3] - self.y0) // self.size).astype(np.int64), -1, self.nrows - 1)
        ok = (c1 >= c0) & (r1 >= r0)
        # one range of sorted points per (box, bucket row)
        rows, box = expand_ranges(np.where(ok, r0, 0), np.where(ok, r1 + 1, 0))
        first = rows * self.ncols + c0[box]
        last = rows * self.ncols + c1[box]
        idx, which = expand_ranges(self.starts[first], self.starts[last + 1])
        p = self.xyz[idx]
        return box[which], p[:, 0], p[:, 1], p[:, 2]


class GridCells:
    """The cells of a raster with data, in the same interface as :class:`PointBuckets`."""

    def __init__(self, grid):
        self.grid = grid

    def candidates(self, bounds):
        """Cells whose centres lie in boxes ``bounds`` (F, 4): owner, centre x, y and value."""
        g = self.grid
        r0, r1, c0, c1 = g.window(bounds)
        ncol = np.maximum(c1 - c0 + 1, 0)
        rows, box = expand_ranges(r0, np.where(ncol > 0, r1 + 1, r0))
        cols, which = expand_ranges(c0[box], c1[box] + 1)
        row, owner = rows[which], box[which]
        value = np.asarray(g.values, dtype=float)[row, cols]
        good = np.isfinite(value)
        x, y = g.centres(row[good], cols[good])
        return owner[good], x, y, value[good]


def _polygons(footprints):
    import shapely

    geoms = np.empty(len(footprints), dtype=object)
    geoms[:] = list(footprints)
    bad = shapely.is_missing(geoms) | shapely.is_empty(geoms)
    if bad.any():
        geoms[bad] = shapely.Polygon()
    return geoms, ~bad


def _values_near(footprints, source, buffer, step, max_buffer):
    """The samples (points or cells) of ``source`` for every footprint: those in
    the footprint buffered by ``buffer``, the buffer growing by ``step`` for
    footprints without any, up to ``max_buffer``. Returns the footprint of
    each sample, its height, and per footprint the buffer used (NaN: none found)."""
    import shapely

    geoms, good = _polygons(footprints)
    F = len(geoms)
    used = np.full(F, np.nan)
    owners, values = [], []
    todo = np.nonzero(good)[0]
    b = float(buffer)
    first = True
    while len(todo):
        area = geoms[todo] if b <= 0 else shapely.buffer(geoms[todo], b, join_style="mitre")
        shapely.prepare(area)
        box, x, y, z = source.candidates(shapely.bounds(area))
        inside = shapely.intersects_xy(area[box], x, y) if len(box) else np.zeros(0, dtype=bool)
        found = np.bincount(box[inside], minlength=len(todo)) > 0
        owners.append(todo[box[inside]])
        values.append(z[inside])
        used[todo[found]] = b
        todo = todo[~found]
        b += step
        if not len(todo) or step <= 0 or b > max_buffer + 1e-9:
            break
        if first:
            # footprints with nothing at all within the largest buffer stop here
            first = False
            far = shapely.buffer(geoms[todo], max_buffer, join_style="mitre")
            box, _, _, _ = source.candidates(shapely.bounds(far))
            todo = todo[np.bincount(box, minlength=len(todo)) > 0]
    owner = np.concatenate(owners) if owners else np.zeros(0, dtype=np.int64)
    value = np.concatenate(values) if values else np.zeros(0)
    return owner, value, used


# ---------------------------------------------------------------------------
# Ground
# ---------------------------------------------------------------------------

@dataclass(frozen=True)
class GroundHeights:
    """Ground elevation of every footprint (NaN where no point or cell was found).

    ``ground``: the chosen percentile; ``percentiles``: (F, 6) at
    :data:`GROUND_PERCENTILES`; ``buffer``: the buffer (m) that found samples;
    ``count``: how many samples were used.
    """

    ground: np.ndarray
    percentiles: np.ndarray
    buffer: np.ndarray
    count: np.ndarray

    @property
    def missing(self):
        """Number of footprints without ground."""
        return int(np.isnan(self.ground).sum())


def _check_percentile(percentile):
    p = float(percentile)
    if not (0.0 <= p <= 50.0):
        raise InputError("The ground percentile must be between 0 and 50, not {}".format(percentile))
    return p


def _ground(footprints, source, percentile, buffer, step, max_buffer, what):
    p = _check_percentile(percentile)
    if buffer < 0 or step < 0:
        raise InputError("The ground buffer and its step must not be negative")
    owner, z, used = _values_near(footprints, source, buffer, step, max_buffer)
    F = len(used)
    qs = sorted(set(GROUND_PERCENTILES) | {p})
    table = group_percentiles(z, owner, F, qs)
    count = np.bincount(owner, minlength=F)
    if F and not count.any():
        raise InputError("None of the {} footprints has {} within {:g} m: is the elevation "
                         "data in another reference system, or outside the footprints' "
                         "region?".format(F, what, max_buffer))
    cols = [qs.index(q) for q in GROUND_PERCENTILES]
    return GroundHeights(table[:, qs.index(p)], table[:, cols], used, count)


def ground_from_points(footprints, points, percentile=20.0, buffer=0.5, step=0.5,
                       max_buffer=50.0):
    """Ground elevation of footprints (shapely polygons) from 3D ground points (N, 3).

    Raises InputError when no footprint has a point within ``max_buffer``
    (the points are elsewhere: another reference system or region).
    """
    return _ground(footprints, PointBuckets(points), percentile, buffer, step, max_buffer,
                   "a ground point")


def ground_from_raster(footprints, grid, percentile=20.0, buffer=0.5, step=0.5,
                       max_buffer=50.0):
    """Ground elevation of footprints from a DTM (:class:`reconstruction.geom.grid.Grid`,
    NaN = no data): the cells whose centres lie in the buffered footprint."""
    if not isinstance(grid, Grid):
        raise InputError("The DTM must be a Grid (values with north, west and resolution)")
    return _ground(footprints, GridCells(grid), percentile, buffer, step, max_buffer,
                   "a DTM cell with data")


# ---------------------------------------------------------------------------
# Roofs from building points (the shortened version)
# ---------------------------------------------------------------------------

@dataclass(frozen=True)
class RoofPoints:
    """Roof heights (absolute) from building points: ``low`` (percentile 25, the
    eaves), ``high`` (percentile 99, the top); NaN where a footprint has no point."""

    low: np.ndarray
    high: np.ndarray
    count: np.ndarray

    @property
    def missing(self):
        return int(np.isnan(self.low).sum())


def roof_from_points(footprints, points, percentiles=ROOF_PERCENTILES):
    """Percentiles of the building points (N, 3) inside each footprint."""
    lo, hi = (float(p) for p in percentiles)
    if not (0 <= lo <= hi <= 100):
        raise InputError("Roof percentiles must be 0 <= low <= high <= 100, not {}".format(
            percentiles))
    owner, z, _ = _values_near(footprints, PointBuckets(points), 0.0, 0.0, 0.0)
    F = len(footprints)
    table = group_percentiles(z, owner, F, [lo, hi])
    count = np.bincount(owner, minlength=F)
    if F and not count.any():
        raise InputError("None of the {} footprints has a building point inside: are the "
                         "points in another reference system, or outside the footprints' "
                         "region?".format(F))
    return RoofPoints(table[:, 0], table[:, 1], count)


# ---------------------------------------------------------------------------
# Measured heights in attribute columns
# ---------------------------------------------------------------------------

def column_key(name):
    """A column name as GRASS stores it: ``roof-0.25`` and ``roof_0_25`` match."""
    return re.sub(r"[^0-9a-z]", "_", str(name).strip().lower())


def _terms(alternative):
    """An alternative of :class:`HeightColumns`: a column name, or a tuple of
    (column name, weight) pairs (a weighted sum of columns)."""
    if isinstance(alternative, str):
        return ((alternative, 1.0),)
    return tuple((str(name), float(w)) for name, w in alternative)


@dataclass(frozen=True)
class HeightColumns:
    """Where measured heights are: absolute ``ground``, roof base (``eaves``) and
    roof ``top``; each a tuple of alternatives tried in turn (a row takes the
    first that is not NULL); an alternative is a column name or a weighted
    sum of columns, ``(("b3_h_50p", 2.25), ("b3_h_70p", -1.25))``."""

    name: str
    ground: tuple
    eaves: tuple
    top: tuple

    def all_names(self):
        return tuple(dict.fromkeys(n for group in (self.ground, self.eaves, self.top)
                                   for alt in group for n, _ in _terms(alt)))


#: the thesis's percentile columns (absolute): ground = ground-0.2,
#: eaves = roof-0.25 - ground, attic = roof-0.99 - roof-0.25
THESIS_COLUMNS = HeightColumns("thesis", ("ground-0.2",), ("roof-0.25",), ("roof-0.99",))


def _bag_p25(p50, p70):
    """The 3D BAG publishes no 25th percentile of the roof points (the thesis's
    eaves, roof-0.25): extrapolated from the 50th and 70th, p25 = p50 -
    1.25 (p70 - p50). The 50th alone puts the eaves half an attic too high
    (on the 3D BAG sample's 1949 house: 50p 6.97 m, its LoD2.2 eaves 3.3-4.3 m,
    the estimate 5.93 m); the minimum is a chimney's foot or noise (-0.07 m
    there)."""
    return ((p50, 2.25), (p70, -1.25))


#: the 3D BAG since 2025: roof percentiles renamed, b3_h_nok the main ridge
#: (NULL on flat roofs: then the maximum)
BAG_COLUMNS = HeightColumns("3dbag", ("b3_h_maaiveld",), (_bag_p25("b3_h_50p", "b3_h_70p"),),
                            ("b3_h_nok", "b3_h_max"))
#: the 3D BAG up to its 2024 releases
BAG_2024_COLUMNS = HeightColumns("3dbag-2024", ("b3_h_maaiveld",),
                                 (_bag_p25("b3_h_dak_50p", "b3_h_dak_70p"),), ("b3_h_dak_max",))
HEIGHT_COLUMNS = {c.name: c for c in (THESIS_COLUMNS, BAG_COLUMNS, BAG_2024_COLUMNS)}


def height_columns(names, choice="auto"):
    """The :class:`HeightColumns` to read from a table with columns ``names``.

    ``choice``: ``auto`` (the first of thesis, 3dbag, 3dbag-2024 whose
    columns are all there), one of those names, or a HeightColumns. Raises
    InputError when the columns are missing.
    """
    have = {column_key(n) for n in names}

    def present(cols):
        return all(any(all(column_key(n) in have for n, _ in _terms(alt)) for alt in group)
                   for group in (cols.ground, cols.eaves, cols.top))

    if isinstance(choice, HeightColumns):
        candidates = [choice]
    elif choice in (None, "", "auto"):
        candidates = list(HEIGHT_COLUMNS.values())
    elif choice in HEIGHT_COLUMNS:
        candidates = [HEIGHT_COLUMNS[choice]]
    else:
        raise InputError("Unknown height columns <{}> (known: auto, {})".format(
            choice, ", ".join(HEIGHT_COLUMNS)))
    for cols in candidates:
        if present(cols):
            return cols
    wanted = "; ".join("{}: {}".format(c.name, ", ".join(c.all_names())) for c in candidates)
    raise InputError("The aligned footprints have no height columns (looked for {})".format(
        wanted))


@dataclass(frozen=True)
class MeasuredHeights:
    """Heights by the data-flow contract (NaN where unknown): ``ground``
    (absolute), ``eaves`` (above the ground), ``attic`` (above the eaves);
    ``problem``: per row, why its heights are unknown (:data:`NULL`, or one of
    the implausible values of :func:`implausible`), None where they are known."""

    ground: np.ndarray
    eaves: np.ndarray
    attic: np.ndarray
    problem: Optional[np.ndarray] = None

    def problems(self):
        """Reason -> number of rows, for the rows whose heights are unknown."""
        if self.problem is None:
            return {}
        reasons = [p for p in self.problem.tolist() if p is not None]
        return {r: reasons.count(r) for r in dict.fromkeys(reasons)}

    @property
    def total(self):
        return self.eaves + self.attic

    @property
    def known(self):
        return np.isfinite(self.eaves) & np.isfinite(self.attic)


def _first_present(columns, alternatives, n):
    by_key = {column_key(k): k for k in columns}
    out = np.full(n, np.nan)
    for alt in alternatives:
        terms = _terms(alt)
        if not all(column_key(name) in by_key for name, _ in terms):
            continue
        value = np.zeros(n)
        for name, weight in terms:
            value = value + weight * np.array(
                [np.nan if v is None or v == "" else v for v in columns[by_key[column_key(name)]]],
                dtype=float)
        out = np.where(np.isnan(out), value, out)
    return out


def measured_heights(columns, source="auto", ground=None):
    """Measured heights from attribute ``columns`` (name -> sequence of values).

    ``source``: see :func:`height_columns`. ``ground``: optional absolute
    ground per row that replaces the table's (e.g. from
    :func:`ground_from_points`). A row whose eaves are not above its ground
    is unknown (NaN); a roof top below the eaves gives attic 0.
    """
    cols = height_columns(list(columns), source)
    n = len(next(iter(columns.values()))) if columns else 0
    g = _first_present(columns, cols.ground, n)
    if ground is not None:
        given = np.asarray(ground, dtype=float)
        g = np.where(np.isfinite(given), given, g)
    return _measured(g, _first_present(columns, cols.eaves, n),
                     _first_present(columns, cols.top, n))


def roof_heights(roof, ground):
    """:class:`MeasuredHeights` from :class:`RoofPoints` and the absolute ground."""
    return _measured(np.broadcast_to(np.asarray(ground, dtype=float), np.shape(roof.low)),
                     roof.low, roof.high)


def _measured(ground, eaves, top):
    """:class:`MeasuredHeights` of absolute ``ground``, ``eaves`` and roof ``top``;
    unknown where a value is NULL (NaN) or :func:`implausible`."""
    ground, eaves, top = (np.asarray(v, dtype=float) for v in (ground, eaves, top))
    problem = implausible(ground, eaves, top)
    bad = problem.astype(bool)
    return MeasuredHeights(ground, np.where(bad, np.nan, eaves - ground),
                           np.where(bad, np.nan, np.maximum(top - eaves, 0.0)),
                           problem)


def implausible(ground, eaves, top):
    """Per row of absolute ``ground``, ``eaves`` and roof ``top`` heights, why
    they are not a building's: :data:`NULL` (one is NaN), a ground outside
    :data:`GROUND_RANGE` or :data:`MAX_GROUND_SPREAD` from the median of
    the other rows' plausible grounds, eaves not above the ground, a top
    more than :data:`INVERTED_TOLERANCE` below the eaves, a top more than
    :data:`MAX_HEIGHT` above the ground; None where they are plausible."""
    ground, eaves, top = (np.asarray(v, dtype=float) for v in (ground, eaves, top))
    problem = np.full(ground.shape, None, dtype=object)
    with np.errstate(invalid="ignore"):
        null = np.isnan(ground) | np.isnan(eaves) | np.isnan(top)
        outside = ~null & ((ground < GROUND_RANGE[0]) | (ground > GROUND_RANGE[1]))
        usual = ground[~null & ~outside]
        apart = ~null & ~outside & (np.abs(ground - np.median(usual)) > MAX_GROUND_SPREAD) \
            if len(usual) else np.zeros(ground.shape, dtype=bool)
        checks = ((TOO_TALL, np.maximum(eaves, top) - ground > MAX_HEIGHT),
                  (INVERTED, top < eaves - INVERTED_TOLERANCE), (NOT_ABOVE, ~(eaves > ground)),
                  (GROUND_APART, apart), (GROUND_OUTSIDE, outside), (NULL, null))
    for reason, where in checks:           # the first of the order checked wins: set last
        problem[where] = reason
    return problem
