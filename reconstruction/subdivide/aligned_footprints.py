"""Aligned footprints in the subdivision (Morlighem 2021, Section 3.3.3).

Current footprints that still stood at the map's date (from v.histo.align)
are kept as they are: :func:`prepare_aligned` makes them valid and disjoint,
:func:`attach_to_plots` finds the plot of each, :func:`calibrate` measures
facade length and depth ranges on them, and :func:`clip_generated` clips
generated footprints where they overlap them.
"""

from dataclasses import dataclass

import numpy as np
import shapely

from ..core.contract import ALIGN_BUFFER, SOURCE_PROCEDURAL
from ..geom.overlaps import OverlapRule, group_conflicts, resolve_overlaps
from ..geom.polygons import polygon_parts, repair
from .convex_rings import (MIN_AREA, SNAP, ccw_ring, is_convex, is_sliver_ring,
                           sharp_corners, signed_area, square_wedges, to_polygons)
from .decomposition import convex_parts
from .plots import (CLIP_AREA, MIN_STREET, OVERLAP_TOLERANCE, overlay, polygonal,
                    street_length)


@dataclass(frozen=True)
class AlignedRepairs:
    """What :func:`prepare_aligned` did: footprints given, repaired (make_valid),
    skipped (no area left) and clipped by earlier ones."""

    aligned: int = 0
    repaired: int = 0
    skipped: int = 0
    clipped: int = 0


def assign_plots(footprints, plots, cats, reach=0.0):
    """The category of the plot each footprint overlaps most; a footprint that overlaps
    none, that of the nearest plot within ``reach`` (map units); None when none."""
    tree = shapely.STRtree(plots)
    out = [None] * len(footprints)
    best = [0.0] * len(footprints)
    left, right = tree.query(footprints, predicate="intersects")
    for f, p in zip(left, right):
        a = overlay(shapely.intersection, footprints[f], plots[p]).area
        if a > best[f]:
            best[f], out[f] = a, cats[p]
    outside = [f for f, c in enumerate(out) if c is None and footprints[f] is not None]
    if outside and reach > 0:
        f, p = tree.query_nearest([footprints[f] for f in outside], max_distance=reach,
                                  all_matches=False)
        for k, j in zip(f.tolist(), p.tolist()):
            out[outside[k]] = cats[j]
    return out


def _aligned_left(geometry):
    """What an aligned footprint keeps of its difference with earlier ones: parts above
    the tolerance."""
    return polygonal([p for p in polygon_parts(geometry) if p.area > OVERLAP_TOLERANCE])


#: earlier aligned footprints keep the shared area
EARLIER_KEEPS = OverlapRule(
    difference=lambda loser, winners: overlay(shapely.difference, loser, winners),
    keep=_aligned_left, min_shared=CLIP_AREA,
    intersection=lambda loser, winners: overlay(shapely.intersection, loser, winners))


def prepare_aligned(footprints):
    """Valid, pairwise disjoint aligned footprints (earlier ones keep shared areas).

    Returns ``(geometries or None per input, repairs)`` (an
    :class:`AlignedRepairs`); a geometry may be a MultiPolygon when repair or
    clipping split it.
    """
    geoms, invalid = repair(footprints)
    repaired = int(sum(bad for bad, g in zip(invalid, geoms) if g is not None))
    valid = [i for i, g in enumerate(geoms) if g is not None]
    clipped = 0
    if valid:
        tree = shapely.STRtree([geoms[i] for i in valid])
        left, right = tree.query([geoms[i] for i in valid], predicate="intersects")
        pairs = [(valid[a], valid[b]) for a, b in zip(left, right) if a > b]
        geoms, shared = resolve_overlaps(geoms, group_conflicts(pairs, range(len(geoms))),
                                         EARLIER_KEEPS)
        clipped = sum(area is not None and area > OVERLAP_TOLERANCE for area in shared)
    skipped = sum(g is None for g in geoms)
    return geoms, AlignedRepairs(len(footprints), repaired, skipped, clipped)


def attach_to_plots(aligned, aligned_plots, plots, cats, reach=ALIGN_BUFFER):
    """The plot of every aligned footprint; footprints without a known plot left out.

    ``aligned_plots`` gives the category of each footprint's plot, None (or
    no list) for the plot it overlaps most, or, overlapping none, the nearest
    within ``reach`` (the alignment's buffer: v.histo.align, and the thesis,
    align a current footprint with a plot it lies beside). Returns ``(aligned,
    plot of each, number left out)``: a new list where the footprints without a
    plot are None.
    """
    aligned = list(aligned)
    plot_of = list(aligned_plots) if aligned_plots is not None else [None] * len(aligned)
    missing = [i for i, c in enumerate(plot_of) if c is None and aligned[i] is not None]
    if missing and plots:
        for i, c in zip(missing, assign_plots([aligned[i] for i in missing], plots, cats,
                                              reach)):
            plot_of[i] = c
    known = set(cats)
    without = [i for i, c in enumerate(plot_of) if aligned[i] is not None and c not in known]
    for i in without:
        aligned[i] = None
    return aligned, plot_of, len(without)


#: how far (map units) from its plot's exterior an aligned footprint still fronts the
#: street: today's footprints cross a historical plot's outline, or stop short of it,
#: by the map's offset; back buildings stand a building's depth behind it
STREET_TOLERANCE = 2.0
#: the least length of the plot's exterior along a footprint that fronts the street
MIN_STREET_RUN = 2.0


@dataclass(frozen=True)
class Frontage:
    """A street-fronting footprint measured along its street: ``facade`` its extent
    along the street, ``depth`` its extent across it."""

    facade: float
    depth: float


def exterior_segments(plot):
    """The segments of a plot's exterior (its outer rings) as an ``(n, 2, 2)`` array."""
    rings = [np.asarray(p.exterior.coords)[:, :2] for p in polygon_parts(plot)]
    return np.concatenate([np.stack([c[:-1], c[1:]], axis=1) for c in rings])


def street_frontage(footprint, segments, tolerance=STREET_TOLERANCE):
    """The :class:`Frontage` of a footprint on the exterior ``segments`` of its plot
    (:func:`exterior_segments`); None when it does not front the street.

    It fronts the street when an exterior segment runs along it over at least
    :data:`MIN_STREET_RUN`, within ``tolerance`` of it (crossing it counts:
    today's footprints and a historical map are offset; a corner that only
    touches does not). The street's direction there is that of the segment
    running longest along it (the longer street of a corner building).
    """
    zone = shapely.buffer(footprint, tolerance)
    # a segment within the zone runs about 2 x tolerance beyond the footprint
    run = shapely.length(shapely.intersection(shapely.linestrings(segments), zone))
    k = int(np.argmax(run))
    if run[k] < MIN_STREET_RUN + 2 * tolerance:
        return None
    along = segments[k, 1] - segments[k, 0]
    along = along / np.hypot(*along)
    across = np.array([-along[1], along[0]])
    coords = np.concatenate([np.asarray(p.exterior.coords)[:, :2]
                             for p in polygon_parts(footprint)])
    return Frontage(float(np.ptp(coords @ along)), float(np.ptp(coords @ across)))


def calibrate(aligned, aligned_plots, plots, cats, length, depth, min_samples=5,
              percentiles=(25, 50)):
    """Facade length and depth ranges from the aligned row buildings on a street.

    Learnt only from footprints that front the street (:func:`street_frontage`:
    they touch their plot's outer boundary), not from back buildings and
    annexes, which the subdivision does not make; and of those only from
    row buildings, narrower along the street than deep: wider ones are
    corner buildings measured along their long side, or today's buildings
    spanning several historical ones. Facade and depth are measured along
    the street (not on the minimum rotated rectangle, which an offset map
    turns across it). Each range runs from the lower quartile to the median
    (``percentiles``): the long tail of large current buildings would make
    the upper quartile far too large. Returns ``(length, depth, samples)``;
    the given ranges when fewer than ``min_samples`` footprints qualify.
    """
    by_cat = {c: g for c, g in zip(cats, plots)}
    segments = {}
    facades, depths = [], []
    for geom, cat in zip(aligned, aligned_plots):
        if geom is None or cat not in by_cat:
            continue
        if cat not in segments:
            segments[cat] = exterior_segments(by_cat[cat])
        front = street_frontage(geom, segments[cat])
        if front is None or front.facade > front.depth:
            continue
        facades.append(front.facade)
        depths.append(front.depth)
    if len(facades) < min_samples:
        return length, depth, len(facades)
    f = np.percentile(facades, percentiles)
    d = np.percentile(depths, percentiles)
    return (float(f[0]), float(f[1])), (float(d[0]), float(d[1])), len(facades)


def clip_generated(footprints, aligned, exterior_of, seam_of=None, plot_of=None, clippable=None,
                   settled=None):
    """Clip or drop generated footprints that overlap aligned footprints.

    What is left of a generated footprint outside the aligned ones is kept
    as convex pieces (its convex parts when it is concave) with their
    corners under ``MIN_ANGLE`` cut square (an aligned footprint crossing a
    generated one at a shallow angle leaves a wedge; the plot's own sharp
    corners stay) that are no slivers, have street access and keep at least
    a quarter of the footprint's area; a footprint with no such piece is
    dropped. ``footprints`` has parallel ``geometries``, ``source`` and
    ``plot`` (a :class:`reconstruction.subdivide.stage.Subdivision`);
    ``exterior_of`` maps a plot category to its
    :func:`reconstruction.subdivide.plots.exterior_lines` (``seam_of`` to
    its :func:`reconstruction.subdivide.plots.seams`, ``plot_of`` to the
    plot itself); ``clippable``: which footprints may be clipped (default: the
    generated ones); ``settled``: which of them are buildings of an earlier epoch,
    clipped only where they overlap an aligned footprint by more than
    ``OVERLAP_TOLERANCE``: an overlap of a rounding error leaves them as they were.
    Returns ``(pieces, clipped, dropped)``: the Polygons that replace each
    clipped or dropped footprint (none for a dropped one), by index, and
    the two counts.
    """
    present = [g for g in aligned if g is not None]
    if not present:
        return {}, 0, 0
    tree = shapely.STRtree(present)
    left, right = tree.query(footprints.geometries, predicate="intersects")
    hits = {}
    for f, a in zip(left, right):
        hits.setdefault(int(f), []).append(int(a))
    replace = {}
    for f, idx in hits.items():
        if not (footprints.source[f] == SOURCE_PROCEDURAL if clippable is None
                else clippable[f]):
            continue
        fp = footprints.geometries[f]
        union = shapely.union_all([present[i] for i in idx])
        least = OVERLAP_TOLERANCE if settled is not None and settled[f] else CLIP_AREA
        if overlay(shapely.intersection, fp, union).area <= least:
            continue
        pieces = []
        # snap-rounded: an aligned corner a rounding error from the footprint's
        # edge would leave a notch whose tip nearly touches that edge, which no
        # chord decomposes (a concave piece)
        for rest in polygon_parts(shapely.difference(fp, union, grid_size=SNAP)):
            if rest.area < max(MIN_AREA, 0.25 * fp.area):
                continue
            if is_convex(rest):
                pieces.append(ccw_ring(rest.exterior.coords))
            else:
                pieces.extend(convex_parts(rest))
        keep = sharp_corners(plot_of[footprints.plot[f]]) if plot_of else ()
        pieces = [square_wedges(r, keep) for r in pieces]
        pieces = [r for r in pieces
                  if r and not is_sliver_ring(r) and abs(signed_area(r)) >= 0.25 * fp.area]
        access = street_length(pieces, exterior_of[footprints.plot[f]],
                               (seam_of or {}).get(footprints.plot[f]))
        pieces = [r for r, a in zip(pieces, access) if a >= MIN_STREET]
        replace[f] = to_polygons(pieces)
    clipped = sum(bool(pieces) for pieces in replace.values())
    return replace, clipped, len(replace) - clipped
