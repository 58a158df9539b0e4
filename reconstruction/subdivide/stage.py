"""Subdivision of building plots into individual footprints (2D procedural modelling).

Historical maps draw blocks ("building plots"), not buildings. This module
splits every plot into plausible footprints with the five cases of Morlighem
(2021), Section 3.3.2, and keeps footprints that already come from the map
alignment (Section 3.3.3):

1. a plot smaller than the area threshold is one footprint;
2. a plot too shallow for two rows of buildings (the shortest side of its
   minimum rotated rectangle below 2 ``depth[0]``) is one row: the long side
   (the one along the street) is cut perpendicular into facade lengths drawn
   from ``length``, each building ``depth`` deep (drawn from the range; a
   building reaches the back of the plot when less than half the minimum
   depth would be left behind it: no sliver of garden);
3. a plot at most two buildings deep (shortest side <= 2 ``depth[1]``) is
   split along its longest median line into two rows, back to back, each as
   case 2;
4. a larger plot gets buildings along every street edge around a courtyard:
   the band inside the street edges is split by the straight skeleton of the
   plot (for a convex polygon, the face of an edge is the set of points
   nearer to that edge's line than to any other), each face cut perpendicular
   to its street edge at facade lengths measured along the inward offset at
   half the minimum depth (the thesis walks the offset at the maximum depth;
   this line is crossed by every building and keeps corner buildings from
   swallowing a street's worth of facades), each building ``depth`` deep, so
   the inward offset at the maximum depth is the courtyard; a building
   reaches the face's ridge when less than the minimum depth would be left
   behind it, so no courtyard strip is narrower than a building (measured
   on the Delft 1961 plots against the real footprints: median count ratio
   0.92 and area ratio 0.88, where measuring at the maximum depth and always
   leaving the courtyard gave 0.79 and 0.74);
5. a concave plot (or a plot with holes) is decomposed into convex parts
   (chords from reflex vertices, as in Bayazit's decomposition: see
   :func:`convex_parts`), each part is handled by cases 1-4 with only the
   plot's exterior edges as street edges, and footprints without an edge on
   the plot's exterior are dropped (no building without street access).

Guarantees (all tested): every footprint is a valid polygon inside its plot,
generated footprints are convex, touch the plot's exterior and front its
boundary (outer ring or a courtyard hole, not a seam with a touching plot:
no street there) over at least ``MIN_FRONTAGE``, have no corner under
``MIN_ANGLE`` unless the plot has one there (wedges are cut square), footprints
never overlap (plots overlapping each other are made disjoint first, and
generated footprints overlapping aligned ones are clipped or dropped), no
generated footprint is a sliver (narrower than ``MIN_WIDTH`` or smaller than
``MIN_AREA`` unless its plot is), and neighbours share exact vertices
(:func:`node_footprints`), so a GIS that builds topology keeps their shared
edges shared. The same seed gives the same output: each plot draws from its
own generator seeded by ``(seed, plot category)``, independent of plot order.

Everything here is pure: shapely 2 geometries and numpy, no GRASS. This file
is the stage's entry point (:func:`subdivide`, its result and report); the
work lives in one file per concern: :mod:`~reconstruction.subdivide.plots` (repair,
overlapping plots, street edges), :mod:`~reconstruction.subdivide.cases`
(cases 1-5 on one plot), :mod:`~reconstruction.subdivide.decomposition` (convex parts),
:mod:`~reconstruction.subdivide.convex_rings` (rings as tuples, slivers),
:mod:`~reconstruction.subdivide.aligned_footprints`, :mod:`~reconstruction.subdivide.noding`
(shared vertices) and :mod:`~reconstruction.subdivide.invariants`.
"""

from dataclasses import dataclass, field, replace
from typing import Optional

import numpy as np
import shapely
from shapely.geometry import Polygon

from ..core.contract import SOURCE_ALIGNED, SOURCE_DRAWN, SOURCE_PROCEDURAL
from ..core.errors import InputError
from ..core.options import parse_number, parse_range
from ..core.work_limits import check_facades
from ..geom.polygons import polygon_parts
from .aligned_footprints import (AlignedRepairs, assign_plots, attach_to_plots, calibrate,
                                 clip_generated, prepare_aligned)
from .cases import STREET_TURN, subdivide_plot
from .convex_rings import (MIN_AREA, MIN_WIDTH, SNAP, is_convex, is_sliver, polygon_width,
                           to_polygons)
from .decomposition import convex_parts
from .drawn import free_parcels
from .invariants import invariant_violations
from .noding import node_footprints
from .plots import (CHECK_GRID, CLIP_AREA, MIN_STREET, OVERLAP_TOLERANCE, PlotRepairs,
                    exterior_lines, front, frontage, neighbour_index, prepare_plots, seams)
from .previous import KeptFootprints, keep_previous

# the stage's names, importable from here as before the split into files
__all__ = [
    "AlignedRepairs", "CASE_ALIGNED", "CHECK_GRID", "CLIP_AREA", "MIN_AREA", "MIN_STREET",
    "MIN_WIDTH", "OVERLAP_TOLERANCE", "PlotRepairs", "SNAP", "STREET_TURN", "Subdivision",
    "SubdivisionReport", "assign_plots", "calibrate", "convex_parts", "invariant_violations",
    "is_convex", "is_sliver", "node_footprints", "plot_rng", "polygon_width", "prepare_aligned",
    "prepare_plots", "subdivide", "subdivide_plot",
]

#: the case of a footprint not generated: a kept aligned one, or one the map draws
#: (generated ones are cases 1-5)
CASE_ALIGNED = 0


@dataclass(frozen=True)
class SubdivisionReport:
    """What :func:`subdivide` did, for the module to report.

    ``plots`` and ``aligned``: what repair and overlap removal did to the
    plots and the aligned footprints; ``aligned_without_plot``: aligned
    footprints left out for want of a plot; ``length``, ``depth`` and
    ``area_threshold``: the parameters used (``calibrated``: ``length`` and
    ``depth`` measured on ``calibration_samples`` aligned row buildings
    fronting the street, see :func:`calibrate`);
    ``generated_clipped`` / ``generated_dropped``: generated footprints
    clipped or dropped where they overlapped aligned ones; ``footprints``
    and ``generated``: how many footprints in all, and generated.
    """

    plots: PlotRepairs
    aligned: AlignedRepairs
    length: tuple
    depth: tuple
    area_threshold: float
    aligned_without_plot: int = 0
    calibrated: bool = False
    calibration_samples: int = 0
    generated_clipped: int = 0
    generated_dropped: int = 0
    footprints: int = 0
    generated: int = 0
    previous: Optional[KeptFootprints] = None
    kept: int = 0
    kept_clipped: int = 0
    kept_dropped: int = 0
    #: footprints the map draws, and the plots they divide
    drawn: int = 0
    drawn_plots: int = 0


@dataclass(frozen=True)
class Subdivision:
    """The footprints of a set of plots and what happened on the way.

    ``geometries`` (shapely Polygons), ``plot`` (category of the plot),
    ``case`` (0 for a kept aligned or a drawn footprint, else 1-5), ``source``
    (``2pm``, ``aligned`` or ``drawn``) and ``aligned`` (index of the aligned footprint, -1 for a
    generated one) are parallel lists; ``report`` is a :class:`SubdivisionReport`.
    """

    geometries: list = field(default_factory=list)
    plot: list = field(default_factory=list)
    case: list = field(default_factory=list)
    source: list = field(default_factory=list)
    aligned: list = field(default_factory=list)
    report: Optional[SubdivisionReport] = None
    kept: list = field(default_factory=list)

    def add(self, geometry, plot, case, source=SOURCE_PROCEDURAL, aligned=-1, kept=-1):
        self.geometries.append(geometry)
        self.plot.append(plot)
        self.case.append(case)
        self.source.append(source)
        self.aligned.append(aligned)
        self.kept.append(kept)

    def replaced(self, pieces):
        """A new Subdivision where footprint ``i`` is replaced by the geometries ``pieces[i]``."""
        out = Subdivision(report=self.report)
        for i, g in enumerate(self.geometries):
            for piece in pieces.get(i, [g]):
                out.add(piece, self.plot[i], self.case[i], self.source[i], self.aligned[i],
                        self.kept[i])
        return out

    @property
    def area(self):
        return [float(g.area) for g in self.geometries]


def plot_rng(seed, cat):
    """The random generator of one plot: depends on the seed and the plot only."""
    return np.random.default_rng([int(seed) & 0xFFFFFFFF, int(cat) & 0xFFFFFFFF])


def _positive_range(values, name):
    """A (min, max) pair of positive numbers from a pair or "min,max" text."""
    pair = parse_range(values, name, positive=True, allow_zero=False)
    if pair is None:
        raise InputError("Option {}= must be two numbers min,max".format(name))
    return pair


def subdivide(plots, cats=None, length=(5.0, 8.0), depth=(12.0, 16.0), area_threshold=None,
              seed=0, decompose=True, aligned=None, aligned_plots=None, calibrate_ranges=False,
              previous=None, aligned_ids=(), tolerance=None, drawn=None):
    """Footprints of all plots.

    ``plots``: shapely geometries (invalid ones are repaired, overlapping ones
    made disjoint); ``cats``: their categories (default 1..n). ``aligned``:
    optional aligned footprints kept as they are (case 0), with
    ``aligned_plots`` the category of their plot (None: the plot they overlap
    most). ``length`` and ``depth``: (min, max) ranges of positive numbers
    (or "min,max" text). ``area_threshold`` defaults to the mean area of the
    aligned footprints, else 100. ``calibrate_ranges`` replaces ``length``
    and ``depth`` by ranges learnt from the aligned footprints that front the
    street, not from back buildings (:func:`calibrate`).
    ``previous``: the earlier epoch of a dynamic chain
    (:class:`~reconstruction.subdivide.previous.PreviousEpoch`), whose
    footprints are kept where the plots did not change
    (:func:`~reconstruction.subdivide.previous.keep_previous`, plots matched
    within ``tolerance``; ``aligned_ids``: the BAG id of each aligned footprint).
    ``drawn``: {plot category: [Polygon, ...]}, the units the map draws in a plot
    (:func:`~reconstruction.subdivide.drawn.read_divisions`): such a plot's
    footprints are those (``drawn``, case 0) less the aligned and kept footprints
    in it, and none is generated there.
    Returns a :class:`Subdivision`; bad parameters raise
    :class:`~reconstruction.core.errors.InputError`.
    """
    length = _positive_range(length, "length")
    depth = _positive_range(depth, "depth")
    check_facades(length, depth)      # before any work: narrower footprints cost without bound
    cats = list(range(1, len(plots) + 1)) if cats is None else list(cats)
    if len(cats) != len(plots):
        raise InputError("cats and plots differ in length")
    cats, geoms, plot_repairs = prepare_plots(plots, cats)
    aligned = list(aligned or [])
    aligned_geoms, aligned_repairs = prepare_aligned(aligned)
    without_plot = 0
    if aligned:
        aligned_geoms, aligned_plots, without_plot = attach_to_plots(
            aligned_geoms, aligned_plots, geoms, cats)
    if area_threshold is None:
        present = [g.area for g in aligned_geoms if g is not None]
        area_threshold = float(np.mean(present)) if present else 100.0
    area_threshold = parse_number(area_threshold, "area_threshold", minimum=0)
    calibrated, samples = False, 0
    if calibrate_ranges and aligned:
        new_length, new_depth, samples = calibrate(aligned_geoms, aligned_plots, geoms, cats,
                                                   length, depth)
        if (new_length, new_depth) != (length, depth):
            length, depth = new_length, new_depth
            calibrated = True
    result = Subdivision()
    for i, g in enumerate(aligned_geoms):
        # a footprint that make_valid or clipping split stays one footprint per part
        for part in polygon_parts(g):
            if part.area > OVERLAP_TOLERANCE:
                result.add(part, aligned_plots[i], CASE_ALIGNED, SOURCE_ALIGNED, i)
    kept = None
    if previous is not None:
        kept = keep_previous(previous, geoms, cats, [b for b, g in zip(aligned_ids, aligned_geoms)
                                                     if g is not None and b is not None],
                             **({} if tolerance is None else {"tolerance": tolerance}))
        for k, cat in zip(kept.index, kept.plot):
            result.add(previous.footprints[k], cat, previous.case[k], previous.source[k], kept=k)
    seed = 0 if seed is None else int(seed)
    exterior_of, seam_of = {}, {}
    neighbours = neighbour_index(geoms)
    for k, (cat, geom) in enumerate(zip(cats, geoms)):
        exterior_of[cat] = exterior_lines(geom)
        # no street along a seam with a touching plot: no building locked in there
        seam_of[cat] = seams(geoms, neighbours, k)
        if kept is not None and (cat in kept.done or (
                cat in kept.free and kept.free[cat].area < MIN_AREA)):
            continue                # nothing changed here since the earlier epoch
        if drawn and cat in drawn:
            for poly in free_parcels(drawn[cat], geom, [g for g, c in zip(result.geometries,
                                                                          result.plot) if c == cat]):
                result.add(poly, cat, CASE_ALIGNED, SOURCE_DRAWN)
            continue
        rng = plot_rng(seed, cat)
        plot_front = front(geom, [geoms[j] for j in neighbours[k]]) if neighbours[k] else None
        for poly, case in subdivide_plot(geom, length, depth, area_threshold, rng, decompose,
                                         seam_of[cat]):
            # an edge only partly along a seam counts as street above: measure what is left
            if plot_front is not None and frontage(
                    poly if not isinstance(poly, list) else Polygon(poly), plot_front) < MIN_STREET:
                continue
            result.add(poly, cat, case)
    rings = [i for i, g in enumerate(result.geometries) if isinstance(g, list)]
    for i, poly in zip(rings, to_polygons([result.geometries[i] for i in rings])):
        result.geometries[i] = poly
    plot_of = dict(zip(cats, geoms))
    is_kept = [k >= 0 for k in result.kept]
    pieces, clipped, dropped = clip_generated(
        result, aligned_geoms, exterior_of, seam_of, plot_of,
        clippable=[s == SOURCE_PROCEDURAL or k for s, k in zip(result.source, is_kept)],
        settled=is_kept)
    kept_clipped = sum(is_kept[f] and bool(p) for f, p in pieces.items())
    kept_dropped = sum(is_kept[f] and not p for f, p in pieces.items())
    if pieces:
        result = result.replaced(pieces)
    if kept is not None:        # the new footprints give way to the kept ones and stay
        fixed = [g for g, k in zip(result.geometries, result.kept) if k >= 0]
        fixed += [settled for cat, free in kept.free.items()   # on the ground that changed
                  for settled in polygon_parts(shapely.difference(plot_of[cat], free))
                  if settled.area > OVERLAP_TOLERANCE]
        with np.errstate(divide="ignore", invalid="ignore"):   # GEOS's floating-point flags
            more, more_clipped, more_dropped = clip_generated(
                result, fixed, exterior_of, seam_of, plot_of,
                clippable=[s == SOURCE_PROCEDURAL and k < 0
                           for s, k in zip(result.source, result.kept)])
        clipped, dropped = clipped + more_clipped, dropped + more_dropped
        if more:
            result = result.replaced(more)
    clipped, dropped = clipped - kept_clipped, dropped - kept_dropped
    noded = node_footprints(result.geometries)
    return replace(result, geometries=noded, report=SubdivisionReport(
        plots=plot_repairs, aligned=aligned_repairs, length=length, depth=depth,
        area_threshold=float(area_threshold), aligned_without_plot=without_plot,
        calibrated=calibrated, calibration_samples=samples, generated_clipped=clipped,
        generated_dropped=dropped, footprints=len(noded),
        generated=sum(s == SOURCE_PROCEDURAL and k < 0
                      for s, k in zip(result.source, result.kept)),
        previous=kept, kept=sum(k >= 0 for k in result.kept), kept_clipped=kept_clipped,
        kept_dropped=kept_dropped,
        drawn=sum(s == SOURCE_DRAWN for s in result.source),
        drawn_plots=len({p for p, s in zip(result.plot, result.source) if s == SOURCE_DRAWN})))
