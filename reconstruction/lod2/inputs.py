"""The LoD2 stage's inputs beyond the footprints' columns: reference heights and street edges.

Two typed entry points for v.histo.lod2 (pure: the GRASS readers are in
:mod:`reconstruction.grassio.points`):

- :func:`footprint_heights` -- the :class:`~reconstruction.lod2.stage.Heights` of
  every footprint and where each came from (``height_source``): ground from
  3D ground points or a DTM (:mod:`~reconstruction.lod2.heights`, the buffered
  footprint's percentile) or from a column or a constant; eaves and attic
  from ranges (``range``), else measured on aligned footprints
  (``measured``: an input footprint that is an aligned footprint, by
  overlap) or building points (``points``) and inferred for the others by
  the height rule (:mod:`~reconstruction.lod2.neighbourhood`: ``neighbours``,
  ``plot``), else from columns (``column``).
- :func:`with_street_edges` -- the street edge of every ring
  (:mod:`~reconstruction.lod2.street_edges`, with a streets raster or street
  areas when given), handed to the roofs with the shared edges (no gable
  end, hip end or stepped facade on a shared edge, see
  :func:`reconstruction.lod2.roofs.plan.plan_roofs`), and written as attributes
  ``street_edge`` (index of the edge in the footprint ring as written: edge
  k runs from vertex k to k + 1 of the counter-clockwise ring, the wall
  standing on it) and ``street_case`` (0-5, see :mod:`street_edges`).
"""

from dataclasses import dataclass, field, replace
from typing import Optional, Union

import numpy as np

from ..core.contract import (HEIGHT_SOURCE, HEIGHTS_COLUMN, HEIGHTS_MEASURED, HEIGHTS_POINTS,
                       HEIGHTS_RANGE)
from ..core.errors import InputError
from ..geom.grid import Grid
from .config import HeightColumns
from . import heights as hts
from . import neighbourhood as nb
from . import stage as lod2
from . import street_edges as se

#: an input footprint is an aligned footprint when they overlap by this much
#: (intersection over union)
SAME_FOOTPRINT = 0.8
#: ground points or cells are looked for up to this far around a footprint (m)
MAX_GROUND_BUFFER = 50.0
#: building points whose top (percentile 99) stands less than this above the
#: ground (m) make a footprint "low"; when more than half the footprints with
#: building points are low, the points are likely ground points (a house is
#: 2.5 m tall at the least; ground points give 0.01-1.4 m), and a warning says so
LOW_BUILDING = 2.0


@dataclass(frozen=True)
class AlignedFootprints:
    """Aligned footprints with measured heights: geometries, their columns
    (name -> values) and which height columns to read (``auto``, ``thesis``,
    ``3dbag``, ``3dbag-2024``, see :func:`reconstruction.lod2.heights.height_columns`)."""

    geometries: list
    columns: dict
    choice: str = "auto"


@dataclass(frozen=True)
class HeightOptions(HeightColumns):
    """Where the heights come from (see the module doc), the maps read."""

    #: (N, 3) ground points, or a DTM :class:`~reconstruction.geom.grid.Grid`
    ground_points: Optional[np.ndarray] = None
    elevation: Optional[Grid] = None
    aligned: Optional[AlignedFootprints] = None
    #: (N, 3) building points (the shortened version)
    building_points: Optional[np.ndarray] = None
    #: plot polygons for the plot rule (:class:`~reconstruction.lod2.neighbourhood.Plots`)
    plots: Optional[nb.Plots] = None
    rule: nb.HeightRule = field(default_factory=nb.HeightRule)


@dataclass(frozen=True)
class HeightReport:
    """What :func:`footprint_heights` did, in counts."""

    #: where the ground came from: points, elevation, column or constant
    ground_from: str
    #: footprints without ground points or cells within the largest buffer
    ground_missing: int = 0
    #: footprints whose buffer had to grow beyond the first (a hole in the data)
    ground_grown: int = 0
    #: input footprints that are aligned footprints with measured heights
    matched: int = 0
    #: aligned footprints with measured heights (donors), and those without: NULL
    #: in a height column (``aligned_unmeasured``), or implausible heights, not
    #: used (``aligned_implausible``: reason -> count, see
    #: :func:`reconstruction.lod2.heights.implausible`)
    aligned_measured: int = 0
    aligned_unmeasured: int = 0
    aligned_implausible: dict = field(default_factory=dict)
    #: footprints with building points, and of those the heights not used as
    #: implausible (reason -> count)
    with_points: int = 0
    points_implausible: dict = field(default_factory=dict)
    #: of those with a known ground, the number whose points' top stands less than
    #: :data:`LOW_BUILDING` above it, the number measured and their median top (m)
    points_low: int = 0
    points_measured: int = 0
    points_median_top: float = float("nan")
    #: height_source label -> number of footprints
    sources: dict = field(default_factory=dict)


@dataclass(frozen=True)
class FootprintHeights:
    """The :class:`~reconstruction.lod2.stage.Heights` of the footprints, the
    ``height_source`` of each and the :class:`HeightReport`; ``interval``: (F, 4)
    the low and high ends of each footprint's eaves height and ridge height (eaves
    + roof) above the ground (:data:`INTERVAL_ATTRIBUTES`): a measured height is
    its own interval, an inferred one spans its neighbours'
    (:class:`~reconstruction.lod2.neighbourhood.InferredHeights`), a drawn one its
    range; NaN where nothing says how sure it is (heights given in columns, the
    plot rule), or None."""

    heights: lod2.Heights
    source: np.ndarray
    report: HeightReport
    interval: Optional[np.ndarray] = None


#: the attributes of a building's height interval (issue 31), in FootprintHeights.interval's order
INTERVAL_ATTRIBUTES = lod2.INTERVAL_ATTRIBUTES


def _array(geoms):
    out = np.empty(len(geoms), dtype=object)
    out[:] = list(geoms)
    return out


def check_points_near(points, geometries, what, margin=MAX_GROUND_BUFFER):
    """Raise :class:`InputError` when no point (N, 3) lies within ``margin`` of
    the footprints' extent (points of another reference system or region)."""
    import shapely

    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    x0, y0, x1, y1 = shapely.total_bounds(_array(geometries))
    near = ((pts[:, 0] >= x0 - margin) & (pts[:, 0] <= x1 + margin)
            & (pts[:, 1] >= y0 - margin) & (pts[:, 1] <= y1 + margin))
    if not near.any():
        px0, py0 = pts[:, :2].min(axis=0) if len(pts) else (np.nan, np.nan)
        px1, py1 = pts[:, :2].max(axis=0) if len(pts) else (np.nan, np.nan)
        raise InputError("None of the {:,} {} lies within {:g} m of the footprints (footprints "
                         "x {:.0f}..{:.0f}, y {:.0f}..{:.0f}; points x {:.0f}..{:.0f}, y "
                         "{:.0f}..{:.0f}): are they in another reference system or "
                         "region?".format(len(pts), what, margin, x0, x1, y0, y1, px0, px1,
                                          py0, py1))


def check_streets_near(grid, classes, name, margin, footprints):
    """Raise :class:`InputError` when the streets raster ``name``, read as
    ``grid`` over the footprints' :class:`~reconstruction.geom.grid.Extent`
    grown by ``margin``, has no cell of the street and water ``classes``
    there: no data at all (a raster of another area), or cells of other
    classes only (named, as the classes near the footprints are what the
    user must choose from). A raster that has such cells elsewhere is no
    help: the street edges are looked for next to the footprints."""
    values = np.asarray(grid.values, dtype=float)
    wanted = ", ".join("{:g}".format(c) for c in classes)
    where = "within {:g} m of the footprints ({})".format(margin, footprints.text())
    known = values[np.isfinite(values)]
    if not len(known):
        raise InputError("The streets raster <{}> has no data {}: does it cover another area "
                         "(or is it in another reference system)?".format(name, where))
    if not np.isin(known, np.asarray(classes, dtype=float)).any():
        present = np.unique(known)
        raise InputError("The streets raster <{}> has no cells of the classes {} {}; its cells "
                         "there are of the classes {}".format(
                             name, wanted, where, ", ".join(
                                 "{:g}".format(c) for c in present[:12])
                             + (", ..." if len(present) > 12 else "")))


def _ground(geoms, columns, opts):
    """Absolute ground per footprint (NaN: unknown) and the report's ground fields."""
    n = len(geoms)
    if opts.ground_points is not None or opts.elevation is not None:
        if opts.ground_points is not None:
            check_points_near(opts.ground_points, geoms, "ground points")
            g = hts.ground_from_points(geoms, opts.ground_points, opts.ground_percentile,
                                       max_buffer=MAX_GROUND_BUFFER)
            kind = "points"
        else:
            g = hts.ground_from_raster(geoms, opts.elevation, opts.ground_percentile,
                                       max_buffer=MAX_GROUND_BUFFER)
            kind = "elevation"
        grown = int(np.sum(np.isfinite(g.buffer) & (g.buffer > 0.5 + 1e-9)))
        return g.ground, dict(ground_from=kind, ground_missing=g.missing, ground_grown=grown)
    if opts.ground_column:
        return lod2.numeric_column(columns, opts.ground_column, "ground elevation"), \
            dict(ground_from="column")
    return np.full(n, float(opts.ground)), dict(ground_from="constant")


def check_ground(ground, cats=None, points=True):
    """Raise :class:`InputError` when a footprint's ground from the ground points
    (``points``) or the DTM lies outside :data:`~reconstruction.lod2.heights.GROUND_RANGE`
    (a DTM's no-data value read as a height, -9999, or points of another
    datum): every height of the building would stand on it."""
    ground = np.asarray(ground, dtype=float)
    low, high = hts.GROUND_RANGE
    with np.errstate(invalid="ignore"):
        bad = (ground < low) | (ground > high)
    if bad.any():
        first = int(np.argmax(bad))
        raise InputError("The ground of footprint {} from the {} is {:g} m, not a plausible "
                         "ground ({:g} to {:g} m){}: {}".format(
                             "cat {}".format(cats[first]) if cats is not None else first + 1,
                             "ground points" if points else "elevation raster", ground[first],
                             low, high, "" if bad.sum() == 1 else
                             " (and {} more footprints)".format(int(bad.sum()) - 1),
                             "are they of another datum or unit?" if points else
                             "is it the raster's no-data value (r.null setnull=)?"))


def match_footprints(geoms, other, threshold=SAME_FOOTPRINT):
    """Per footprint of ``geoms``: the index of the footprint of ``other`` it is
    (intersection over union at least ``threshold``, the best), -1 for none."""
    import shapely

    a_geoms, b_geoms = _array(geoms), _array(other)
    out = np.full(len(a_geoms), -1, dtype=np.int64)
    if not len(a_geoms) or not len(b_geoms):
        return out
    a, b = shapely.STRtree(b_geoms).query(a_geoms, predicate="intersects")
    if not len(a):
        return out
    inter = shapely.area(shapely.intersection(a_geoms[a], b_geoms[b]))
    union = shapely.area(a_geoms[a]) + shapely.area(b_geoms[b]) - inter
    iou = inter / np.maximum(union, 1e-12)
    order = np.lexsort((-iou, a))
    a, b, iou = a[order], b[order], iou[order]
    first = np.concatenate([[True], a[1:] != a[:-1]])
    keep = first & (iou >= threshold)
    out[a[keep]] = b[keep]
    return out


def _plot_of(geoms, plots):
    """Plot id of the plot holding each footprint's representative point (None: none)."""
    import shapely

    out = np.full(len(geoms), None, dtype=object)
    if plots is None or not len(geoms):
        return out
    pts = shapely.point_on_surface(_array(geoms))
    i, j = shapely.STRtree(_array(plots.geometries)).query(pts, predicate="within")
    out[i] = np.asarray(plots.ids, dtype=object)[j]
    return out


def _measured(geoms, ground, opts, report):
    """Eaves, attic (NaN: unknown) and labels of the footprints from aligned
    footprints and building points, then the donors to append."""
    n = len(geoms)
    eaves, attic = np.full(n, np.nan), np.full(n, np.nan)
    label = np.full(n, "", dtype=object)
    donors = ([], np.zeros(0), np.zeros(0), np.zeros(0, dtype=object))
    if opts.aligned is not None:
        al = opts.aligned
        if not len(al.geometries):
            raise InputError("The aligned footprints map has no areas")
        al_ground = None
        if opts.ground_points is not None or opts.elevation is not None:
            al_ground = _ground(al.geometries, {}, opts)[0]
        m = hts.measured_heights(al.columns, al.choice, ground=al_ground)
        problems = m.problems()
        if not m.known.any():
            raise InputError("None of the {} aligned footprints has measured heights ({})".format(
                len(m.known), ", ".join("{} {}".format(n, k) for k, n in problems.items())))
        which = match_footprints(geoms, al.geometries)
        hit = which >= 0
        hit[hit] &= m.known[which[hit]]
        eaves[hit], attic[hit] = m.eaves[which[hit]], m.attic[which[hit]]
        label[hit] = HEIGHTS_MEASURED
        rest = np.setdiff1d(np.nonzero(m.known)[0], which[hit])
        donor_geoms = [al.geometries[k] for k in rest]
        donors = (donor_geoms, m.eaves[rest], m.attic[rest], _plot_of(donor_geoms, opts.plots))
        unmeasured = problems.pop(hts.NULL, 0)
        report.update(matched=int(hit.sum()), aligned_measured=int(m.known.sum()),
                      aligned_unmeasured=unmeasured, aligned_implausible=problems)
    if opts.building_points is not None:
        check_points_near(opts.building_points, geoms, "building points", margin=0.0)
        roof = hts.roof_from_points(geoms, opts.building_points)
        rh = hts.roof_heights(roof, ground)
        use = ~np.isfinite(eaves) & np.isfinite(rh.eaves) & np.isfinite(rh.attic)
        eaves[use], attic[use] = rh.eaves[use], rh.attic[use]
        label[use] = HEIGHTS_POINTS
        problems = rh.problems()
        problems.pop(hts.NULL, None)
        report.update(with_points=int(np.sum(roof.count > 0)), points_implausible=problems,
                      **_points_tops(roof, ground))
    return eaves, attic, label, donors


def _points_tops(roof, ground):
    """The report's fields on how tall the building points make the footprints:
    the top (percentile 99) above the ground of every footprint with points and
    a known ground; many under :data:`LOW_BUILDING` mean ground points given
    as building points."""
    top = np.asarray(roof.high, dtype=float) - np.broadcast_to(
        np.asarray(ground, dtype=float), np.shape(roof.high))
    top = top[np.isfinite(top)]
    return dict(points_low=int(np.sum(top < LOW_BUILDING)), points_measured=len(top),
                points_median_top=float(np.median(top)) if len(top) else float("nan"))


def footprint_heights(geometries, columns, plot=None, options=None):
    """The :class:`FootprintHeights` of footprints (shapely polygons) with their
    attribute ``columns`` (name -> values) and plot ids ``plot`` (None:
    unknown), from :class:`HeightOptions` (see the module doc)."""
    opts = options or HeightOptions()
    geoms = _array(geometries)
    n = len(geoms)
    ground, report = _ground(geoms, columns, opts)
    if report["ground_from"] in ("points", "elevation"):
        check_ground(ground, columns.get("cat"), opts.ground_points is not None)
    source = np.full(n, HEIGHTS_COLUMN, dtype=object)
    interval = np.full((n, 4), np.nan)
    if opts.aligned is not None or opts.building_points is not None:
        eaves, attic, label, (dg, de, da, dp) = _measured(geoms, ground, opts, report)
        plot = np.full(n, None, dtype=object) if plot is None else np.asarray(plot, dtype=object)
        r = nb.infer_heights(list(geoms) + list(dg), np.concatenate([eaves, de]),
                             np.concatenate([attic, da]), plot=np.concatenate([plot, dp]),
                             plots=opts.plots, rule=opts.rule)
        eaves, attic = r.eaves[:n], r.attic[:n]
        source = np.where(label != "", label, r.source[:n]).astype(object)
        interval = np.column_stack([r.low[:n, 0], r.high[:n, 0], r.low[:n, 1], r.high[:n, 1]])
    else:
        eaves = lod2.numeric_column(columns, opts.eaves_column, "eaves height") \
            if opts.eaves_range is None else None
        attic = lod2.numeric_column(columns, opts.attic_column, "roof height") \
            if opts.attic_range is None else None
    if opts.eaves_range is not None:
        eaves = lod2.Uniform(*opts.eaves_range)
        source = np.full(n, HEIGHTS_RANGE, dtype=object)
        interval[:, :2] = opts.eaves_range
        interval[:, 2:] = np.add(opts.eaves_range, opts.attic_range) \
            if opts.attic_range is not None else np.nan
    if opts.attic_range is not None:
        attic = lod2.Uniform(*opts.attic_range)
    labels, counts = np.unique(source.astype(str), return_counts=True)
    report["sources"] = {k or "none": int(c) for k, c in zip(labels, counts)}
    return FootprintHeights(lod2.Heights(eaves, attic, ground, float(opts.ground)), source,
                            HeightReport(**report), interval)


# ---------------------------------------------------------------------------
# Street edges
# ---------------------------------------------------------------------------

@dataclass(frozen=True)
class StreetOptions:
    """How street edges are found: ``streets`` a classified
    :class:`~reconstruction.geom.grid.Grid` with ``classes`` its street and water
    labels, or street polygons, or None (the four cases alone); ``depth``
    the strip (m) looked at in front of each edge."""

    streets: Union[Grid, list, None] = None
    classes: Optional[tuple] = None
    depth: float = 3.0
    tol: float = 0.1


def with_street_edges(prepared, options=None):
    """``prepared`` (:class:`~reconstruction.lod2.stage.Prepared`) with the street
    edge and the shared edges of every ring given to its roofs, and the
    attributes ``street_edge`` and ``street_case``; and the
    :class:`~reconstruction.lod2.street_edges.StreetEdges`."""
    opts = options or StreetOptions()
    b = prepared.buildings
    res = se.street_edges(b.footprints, tol=opts.tol, streets=opts.streets,
                          classes=opts.classes, depth=opts.depth)
    start = res.edges.start
    shared = [res.shared[start[r]:start[r + 1]] for r in range(len(b))]
    street = [int(e) if e >= 0 else None for e in res.edge]
    buildings = lod2.Buildings(b.footprints, b.ground, b.eaves, b.attic, b.roof_types,
                               b.uniforms, street=street, shared=shared)
    prepared = with_attributes(replace(prepared, buildings=buildings),
                               street_edge=res.edge.astype(int), street_case=res.case.astype(int))
    return prepared, res


def with_attributes(prepared, **per_ring):
    """``prepared`` with more attributes written per building (values per ring)."""
    return replace(prepared, extra=tuple(prepared.extra) + tuple(
        (name, np.asarray(values).tolist()) for name, values in per_ring.items()))


def with_height_source(prepared, source, interval=None):
    """``prepared`` with the ``height_source`` attribute (values per footprint) and,
    given the (F, 4) ``interval`` of :class:`FootprintHeights`, the attributes of
    :data:`INTERVAL_ATTRIBUTES` (null where unknown), which
    :func:`~reconstruction.lod2.stage.build` sets for the roofs as built
    (:func:`~reconstruction.lod2.stage.built_intervals`)."""
    source = np.asarray(source, dtype=object)
    prepared = with_attributes(prepared, **{HEIGHT_SOURCE: source[prepared.source]})
    if interval is None:
        return prepared
    ends = np.asarray(interval, dtype=float)[prepared.source]
    return with_attributes(prepared, **{name: ends[:, k] for k, name in
                                        enumerate(INTERVAL_ATTRIBUTES)})
