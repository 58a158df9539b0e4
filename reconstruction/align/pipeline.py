"""v.histo.align's whole sequence: :func:`run` (inputs and config in, result out).

From the footprints' table to the tables of the output maps: the year
column found, the construction years read, only the candidates' geometries
asked for (``AlignmentInputs.read_footprints``), the plots collected (read
in the background meanwhile), the alignment (:func:`~.stage.align`), and
the rows of the aligned and unmatched footprints and of the JSON report.
GRASS stays in the module: it hands the reads in as callables.
"""

import time
from dataclasses import dataclass
from typing import Callable, Optional

import numpy as np

from ..core import contract
from ..core.errors import InputError
from ..geom.grid import Extent
from ..core.register import year_column
from .stage import Alignment, align, candidate_mask, construction_years, report_json


@dataclass(frozen=True)
class AlignmentInputs:
    """What v.histo.align reads from GRASS, when the stage asks for it.

    ``table``: the footprints' attribute table ({column: values}, ``cat``
    included); ``read_footprints(cats)``: the geometries of the footprints
    of categories ``cats`` and the categories found, ``(geometries, cats)``;
    ``read_plots()``: the plots and their categories, ``(geometries, cats)``;
    ``counts(name)``: the topology counts of map ``name`` (``{"areas": n,
    ...}``), for the error of a map without areas.
    """

    table: dict
    read_footprints: Callable[[list], tuple]
    read_plots: Callable[[], tuple]
    counts: Callable[[str], dict]


@dataclass(frozen=True)
class FootprintMap:
    """One output map: ``geometries`` with their categories ``cats``, the attribute
    ``table`` ({column: values}) and the map's ``title``; ``name`` the map."""

    name: str
    geometries: list
    cats: list
    table: dict
    title: str


@dataclass(frozen=True)
class AlignmentResult:
    """What :func:`run` did: the ``alignment`` (:class:`~.stage.Alignment`), the
    ``year_column`` read, the plots' categories ``plot_cats``, the maps to
    write (``output``; ``unmatched`` None when not asked for), the JSON
    report (``report_json``, None when not asked for) and ``clock``: the
    ``time.perf_counter()`` when the inputs were read and when the alignment
    was done."""

    alignment: Alignment
    year_column: str
    plot_cats: list
    output: FootprintMap
    unmatched: Optional[FootprintMap]
    report_json: Optional[dict]
    clock: tuple
    #: the boxes the candidate footprints and the plots cover (None: none), for
    #: the warning when nothing aligned because they do not meet
    footprints_extent: Optional[Extent] = None
    plots_extent: Optional[Extent] = None


def no_areas(name, key, what, counts):
    """The InputError for map ``name`` (option ``key``) that holds no areas (``counts``:
    its topology counts)."""
    return InputError("Vector map <{}> given as {}= has no areas (it holds {}): {} must be "
                      "areas".format(name, key, ", ".join(
                          "{} {}".format(counts.get(k, 0), k)
                          for k in ("points", "lines", "boundaries", "areas")), what))


def _footprints(inputs, config):
    """The year column, the years and the footprints' geometries (None where not a
    candidate: only the candidates' geometry is read)."""
    columns, name = inputs.table, config.footprints
    column = year_column(columns, config.year_column, config.year_column_given, name)
    cats = columns["cat"]
    years = construction_years(columns[column], column, ids=cats)
    candidate = candidate_mask(years, config)[0]
    footprints = [None] * len(cats)
    if candidate.any():
        geoms, found = inputs.read_footprints([cats[i] for i in np.flatnonzero(candidate)])
        row = {c: i for i, c in enumerate(cats)}
        for geom, cat in zip(geoms, found):
            footprints[row[cat]] = geom
    if not any(g is not None for g in footprints) and \
            inputs.counts(name).get("areas", 0) == 0:
        raise no_areas(name, "footprints", "footprints", inputs.counts(name))
    return column, years, footprints


def _footprint_map(name, footprints, columns, indices, extra, title):
    """Footprints ``indices`` with their own categories and columns, plus ``extra`` columns."""
    own = {contract.PLOT.lower(), contract.SIMILARITY.lower(), "cat"} | {k.lower() for k in extra}
    table = {k: [values[i] for i in indices] for k, values in columns.items()
             if k.lower() not in own}
    table.update(extra)
    return FootprintMap(name, [footprints[i] for i in indices],
                        [columns["cat"][i] for i in indices], table, title)


def run(inputs, config):
    """v.histo.align on ``inputs`` (:class:`AlignmentInputs`) with ``config``
    (:class:`~.config.AlignmentConfig`): an :class:`AlignmentResult`.

    Bad input (no year column, a year that is no number, a map without
    areas, too much work) raises :class:`~reconstruction.core.errors.InputError`.
    """
    column, years, footprints = _footprints(inputs, config)
    plots, plot_cats = inputs.read_plots()
    if not plots:
        raise no_areas(config.plots, "input", "plots", inputs.counts(config.plots))
    read = time.perf_counter()
    result = align(plots, plot_cats, footprints, years, config)
    matched = time.perf_counter()
    extra = {contract.PLOT: result.plot.tolist(),
             contract.SIMILARITY: np.round(result.similarity, 4).tolist()}
    if result.shifts is not None:
        row = {c: i for i, c in enumerate(plot_cats)}
        rows = [row[c] for c in result.plot.tolist()]
        extra["dx"] = np.round(result.shifts.dx[rows], 2).tolist()
        extra["dy"] = np.round(result.shifts.dy[rows], 2).tolist()
    columns, name = inputs.table, config.footprints
    output = _footprint_map(
        config.output, footprints, columns, result.aligned.tolist(), extra,
        "Footprints of <{}> standing on <{}> in {} (v.histo.align)".format(
            name, config.plots, config.map_year))
    unmatched = None
    if config.unmatched:
        unmatched = _footprint_map(
            config.unmatched, footprints, columns, result.unmatched.tolist(),
            {contract.SIMILARITY: np.round(result.best_similarity, 4).tolist()},
            "Candidate footprints of <{}> matching no plot".format(name))
    report = report_json(result, config, plot_cats) if config.report_file else None
    return AlignmentResult(result, column, list(plot_cats), output, unmatched, report,
                           (read, matched), footprints_extent=Extent.of(footprints),
                           plots_extent=Extent.of(plots))
