"""v.histo.subdivide's whole sequence: :func:`run` (inputs and config in, result out).

The plots with a category (:func:`plots_with_category`), the aligned
footprints and the plot each one names (:func:`read_inputs`), the
subdivision (:func:`~.stage.subdivide`) and the attribute table of the
footprints map. GRASS stays in the module: it reads the maps and writes the
result.
"""

import time
from dataclasses import dataclass
from typing import Optional

from ..core import contract
from ..core.errors import InputError
from ..core.options import integer_column
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


@dataclass(frozen=True)
class SubdivisionResult:
    """What :func:`run` did: the ``subdivision`` (:class:`~.stage.Subdivision`), the
    attribute ``table`` of the footprints map ({column: values}) and ``clock``:
    the ``time.perf_counter()`` when the subdivision started and when it was done."""

    subdivision: Subdivision
    table: dict
    clock: tuple

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


def read_inputs(plots, cats, aligned, aligned_columns, config):
    """The :class:`SubdivisionInputs` of the maps read: the aligned footprints' plot
    column (``plot``, any case) read as whole numbers (InputError otherwise)."""
    if aligned is None:
        return SubdivisionInputs(plots, cats, aligned_columns=aligned_columns or {})
    names = {k.lower(): k for k in aligned_columns}
    if contract.PLOT not in names:
        return SubdivisionInputs(plots, cats, aligned, None, aligned_columns, True)
    aligned_plots = integer_column(aligned_columns[names[contract.PLOT]], contract.PLOT,
                                   config.aligned)
    return SubdivisionInputs(plots, cats, aligned, aligned_plots, aligned_columns)


def _aligned_columns(columns, indices, own):
    """The aligned footprints' own columns, one value per output footprint (NULL for 2PM)."""
    out = {}
    for name, values in columns.items():
        if name.lower() not in own:
            out[name] = [values[i] if i >= 0 else None for i in indices]
    return out


def run(inputs, config):
    """v.histo.subdivide on ``inputs`` (:class:`SubdivisionInputs`) with ``config``
    (:class:`~.config.SubdivisionConfig`): a :class:`SubdivisionResult`. Bad
    parameters (too much work) raise :class:`~reconstruction.core.errors.InputError`."""
    started = time.perf_counter()
    result = subdivide(
        inputs.plots, inputs.cats, length=config.length, depth=config.depth,
        area_threshold=config.area_threshold, seed=config.seed, decompose=config.decompose,
        aligned=inputs.aligned, aligned_plots=inputs.aligned_plots,
        calibrate_ranges=config.calibrate)
    done = time.perf_counter()
    table = {
        contract.PLOT: result.plot,
        contract.CASE: result.case,
        contract.SOURCE: result.source,
        contract.AREA: [round(a, 3) for a in result.area],
    }
    if result.geometries:
        own = {"cat"} | set(table)
        table.update(_aligned_columns(inputs.aligned_columns or {}, result.aligned, own))
    return SubdivisionResult(result, table, (started, done))
