"""v.histo.subdivide's whole sequence: :func:`run` (inputs and config in, result out).

The plots with a category (:func:`plots_with_category`), the aligned
footprints and the plot each one names (:func:`read_inputs`), the
subdivision (:func:`~.stage.subdivide`) and the attribute table of the
footprints map. GRASS stays in the module: it reads the maps and writes the
result.
"""

import time
from dataclasses import dataclass
from typing import Callable, Optional

from ..core import contract
from ..core.errors import InputError
from ..core.options import integer_column
from ..core.register import bag_ids, column_named
from ..geom.grid import MapImage
from ..geom.polygons import polygon_parts
from .drawn import DrawnDivisions, read_divisions
from .plots import OVERLAP_TOLERANCE
from .previous import PreviousEpoch, earlier_identities, identities
from .stage import Subdivision, subdivide


@dataclass(frozen=True)
class SubdivisionInputs:
    """What v.histo.subdivide read from GRASS.

    ``plots`` (shapely geometries) with their categories ``cats``;
    ``aligned``: the aligned footprints (None without aligned=), with
    ``aligned_plots`` the category of the plot each names (None: the plot
    it overlaps most, e.g. when the map has no ``plot`` column, then
    ``plot_column_missing``) and ``aligned_columns`` their attribute table.
    """

    plots: list
    cats: list
    aligned: Optional[list] = None
    aligned_plots: Optional[list] = None
    aligned_columns: Optional[dict] = None
    plot_column_missing: bool = False
    #: the earlier epoch (:class:`~.previous.PreviousEpoch`, previous=), None without
    previous: Optional[PreviousEpoch] = None
    #: the BAG id of every aligned footprint (None: none), for their building identity
    aligned_ids: Optional[list] = None
    #: the scanned map (:class:`~reconstruction.geom.grid.MapImage`, map=) whose lines
    #: divide the plots, None without; ``progress(done, total)`` while it is read
    image: Optional[MapImage] = None
    progress: Optional[Callable] = None


@dataclass(frozen=True)
class SubdivisionResult:
    """What :func:`run` did: the ``subdivision`` (:class:`~.stage.Subdivision`), the
    attribute ``table`` of the footprints map ({column: values}) and ``clock``:
    the ``time.perf_counter()`` when the subdivision started and when it was done;
    ``drawn``: what the map's lines gave (:class:`~.drawn.DrawnDivisions`), None
    without map=."""

    subdivision: Subdivision
    table: dict
    clock: tuple
    drawn: Optional[DrawnDivisions] = None

    @property
    def geometries(self):
        return self.subdivision.geometries


def plots_with_category(geometries, columns, name):
    """The plots of map ``name`` that have an area and a category, and their categories
    (``geometries`` and ``columns`` as read); InputError when there is none."""
    keep = [i for i, (g, c) in enumerate(zip(geometries, columns["cat"]))
            if g is not None and c is not None]
    if not keep:
        raise InputError("Vector map <{}> has no areas with a category".format(name))
    return [geometries[i] for i in keep], [int(columns["cat"][i]) for i in keep]


def read_previous(plots, cats, footprints, columns, config):
    """The :class:`~.previous.PreviousEpoch` of the earlier epoch's maps read: its plots
    (with their categories) and its footprints with their table. A footprint's
    identity is its ``building`` column (InputError without one:
    :func:`~.previous.earlier_identities`), else the BAG id of an aligned one, else
    ``building_<cat>`` (what v.histo.lod2 names a footprint's building)."""
    # one footprint per polygon (GRASS hands back single polygons as MultiPolygons),
    # without the slivers of a rounding error that GRASS's cleaning can leave
    # beside a footprint under its category (each would be a building of its own)
    keep, parts = [], []
    for i, g in enumerate(footprints):
        pieces = polygon_parts(g) if g is not None else []
        solid = [p for p in pieces if p.area >= OVERLAP_TOLERANCE]
        for part in solid or pieces:
            keep.append(i)
            parts.append(part)
    footprints = parts
    columns = {k: [v[i] for i in keep] for k, v in columns.items()}
    n = len(footprints)
    plot = column_named(columns, contract.PLOT)
    plot = integer_column(plot, contract.PLOT, config.previous) if plot is not None else [None] * n
    source = column_named(columns, contract.SOURCE) or [contract.SOURCE_PROCEDURAL] * n
    case = column_named(columns, contract.CASE) or [None] * n
    bag = bag_ids(columns, config.id_column, config.previous) or [None] * n
    named = earlier_identities(columns, config.previous, config.year)
    footprint_cats = columns.get("cat") or list(range(1, n + 1))
    identity = []
    for k in range(n):
        if named is not None and named[k] not in (None, ""):
            identity.append(str(named[k]))
        elif source[k] == contract.SOURCE_ALIGNED and bag[k] is not None:
            identity.append(bag[k])
        else:
            identity.append("building_{}".format(footprint_cats[k]))
    return PreviousEpoch(plots, cats, footprints, plot, identity, list(source),
                         [int(c) if c is not None else 0 for c in case], bag, columns)


def read_inputs(plots, cats, aligned, aligned_columns, config, previous=None):
    """The :class:`SubdivisionInputs` of the maps read: the aligned footprints' plot
    column (``plot``, any case) read as whole numbers (InputError otherwise), and
    with ``year=`` their BAG ids; ``previous``: the earlier epoch
    (:func:`read_previous`), or None."""
    if aligned is None:
        return SubdivisionInputs(plots, cats, aligned_columns=aligned_columns or {},
                                 previous=previous)
    ids = bag_ids(aligned_columns, config.id_column, config.aligned) \
        if config.year is not None else None
    plot = column_named(aligned_columns, contract.PLOT)
    if plot is None:
        return SubdivisionInputs(plots, cats, aligned, None, aligned_columns, True, previous,
                                 ids)
    aligned_plots = integer_column(plot, contract.PLOT, config.aligned)
    return SubdivisionInputs(plots, cats, aligned, aligned_plots, aligned_columns, False,
                             previous, ids)


def _own_columns(columns, indices, own, previous=None, kept=None):
    """The aligned footprints' own columns, one value per output footprint (NULL for 2PM),
    and those of the ``previous`` epoch's footprints: a footprint kept from it
    (``kept`` index) takes its own value of a column of that name."""
    earlier = {k.lower(): v for k, v in (previous.columns if previous else {}).items()}
    names = {k.lower(): k for k in earlier}
    names.update({k.lower(): k for k in columns})
    now = {k.lower(): v for k, v in columns.items()}
    kept = kept or [-1] * len(indices)
    out = {}
    for low, name in names.items():
        if low in own:
            continue
        values, before = now.get(low), earlier.get(low)
        out[name] = [values[i] if values is not None and i >= 0
                     else before[k] if before is not None and k >= 0 else None
                     for i, k in zip(indices, kept)]
    return out


def run(inputs, config):
    """v.histo.subdivide on ``inputs`` (:class:`SubdivisionInputs`) with ``config``
    (:class:`~.config.SubdivisionConfig`): a :class:`SubdivisionResult`. Bad
    parameters (too much work) raise :class:`~reconstruction.core.errors.InputError`."""
    started = time.perf_counter()
    drawn = None
    if inputs.image is not None:
        drawn = read_divisions(inputs.image.rgb, inputs.image.extent, inputs.plots, inputs.cats,
                               stroke=config.stroke, min_area=config.min_parcel,
                               progress=inputs.progress, whole=config.whole)
    result = subdivide(
        inputs.plots, inputs.cats, length=config.length, depth=config.depth,
        area_threshold=config.area_threshold, seed=config.seed, decompose=config.decompose,
        aligned=inputs.aligned, aligned_plots=inputs.aligned_plots,
        calibrate_ranges=config.calibrate, previous=inputs.previous,
        aligned_ids=inputs.aligned_ids or (), tolerance=config.tolerance,
        drawn=drawn.parcels if drawn is not None else None)
    done = time.perf_counter()
    table = {
        contract.PLOT: result.plot,
        contract.CASE: result.case,
        contract.SOURCE: result.source,
        contract.AREA: [round(a, 3) for a in result.area],
    }
    if config.year is not None:
        table[contract.BUILDING] = identities(result, inputs.previous, inputs.aligned_ids or [],
                                              config.year)
    if inputs.previous is not None:
        change = result.report.previous.change
        table[contract.PLOT_CHANGE] = [change.get(p) for p in result.plot]
    if result.geometries:
        own = {"cat"} | set(table)
        table.update(_own_columns(inputs.aligned_columns or {}, result.aligned, own,
                                  inputs.previous, result.kept))
    return SubdivisionResult(result, table, (started, done), drawn)
