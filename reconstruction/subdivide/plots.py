"""Plots for the subdivision: repaired, made disjoint, and their street edges.

A plot's exterior boundary is its street: a footprint has street access when
enough of its boundary lies on it (:func:`street_length`, ``MIN_STREET``).
:func:`prepare_plots` makes any input plots valid and pairwise disjoint (the
larger plot of an overlapping pair keeps the shared area), so that the
footprints of different plots never overlap.
"""

from dataclasses import dataclass

import numpy as np
import shapely
from shapely.geometry import MultiPolygon

from ..geom.overlaps import OverlapRule, group_conflicts, resolve_overlaps
from ..geom.polygons import overlay as polygons_overlay, polygon_parts, repair
from ..geom.rings import offsets as ring_offsets
from .convex_rings import SNAP, is_sliver

#: shortest stretch of a footprint boundary on the plot exterior that counts as street access
MIN_STREET = 1.0
#: overlaps up to this area (square map units) are not counted as overlaps
OVERLAP_TOLERANCE = 0.01
#: overlaps larger than this are removed all the same (GRASS would make them areas of their own)
CLIP_AREA = 0.0
#: precision grid of the overlays that check the invariants (map units)
CHECK_GRID = 1e-6


@dataclass(frozen=True)
class PlotRepairs:
    """What :func:`prepare_plots` did: plots given, repaired (make_valid),
    skipped (no area left), overlapping pairs and the area they shared."""

    plots: int = 0
    repaired: int = 0
    skipped: int = 0
    overlapping_pairs: int = 0
    overlap_area: float = 0.0


def overlay(operation, a, b):
    """A shapely overlay that falls back to snap-rounding on :data:`CHECK_GRID` when
    GEOS's floating one fails (:func:`~reconstruction.geom.polygons.overlay`)."""
    return polygons_overlay(operation, a, b, CHECK_GRID)


def polygonal(parts):
    """One geometry of polygon parts: the part, a MultiPolygon, or None for no part."""
    if not parts:
        return None
    return parts[0] if len(parts) == 1 else MultiPolygon(parts)


def _plot_left(geometry):
    """What a plot keeps of its difference with larger plots: parts above the
    tolerance, and no sliver beside a part that is none."""
    parts = [p for p in polygon_parts(geometry) if p.area > OVERLAP_TOLERANCE]
    if len(parts) > 1:
        parts = [p for p in parts if not is_sliver(p)] or parts[:1]
    return polygonal(parts)


#: the larger plot keeps the shared area; snap-rounded: a winner's vertex a
#: rounding error from the loser's boundary would leave a notch whose tip
#: nearly touches the boundary, which no chord can decompose
LARGER_PLOT_KEEPS = OverlapRule(
    difference=lambda loser, winners: shapely.difference(loser, winners, grid_size=SNAP),
    keep=_plot_left)


def prepare_plots(plots, cats):
    """Valid, pairwise disjoint plots.

    Invalid plots are repaired with make_valid; plots without area are
    skipped; an area shared by overlapping plots goes to the larger plot.
    Returns ``(cats, geometries, repairs)`` (a :class:`PlotRepairs`).
    """
    fixed, invalid = repair(plots)
    keep_cats = [cat for cat, g in zip(cats, fixed) if g is not None]
    geoms = [g for g in fixed if g is not None]
    repaired = int(sum(bad for bad, g in zip(invalid, fixed) if g is not None))
    skipped = len(plots) - len(geoms)
    pairs_counted, shared_area = 0, 0.0
    if geoms:
        tree = shapely.STRtree(geoms)
        left, right = tree.query(geoms, predicate="intersects")
        pairs = []
        for a, b in zip(left, right):
            if a >= b:
                continue
            shared = overlay(shapely.intersection, geoms[a], geoms[b]).area
            if shared <= CLIP_AREA:
                continue
            if shared > OVERLAP_TOLERANCE:
                pairs_counted += 1
                shared_area += shared
            pairs.append((a, b))
        if pairs:
            # ties: the smaller category
            rank = sorted(range(len(geoms)), key=lambda i: (-geoms[i].area, keep_cats[i]))
            order = {i: r for r, i in enumerate(rank)}
            geoms, _ = resolve_overlaps(geoms, group_conflicts(pairs, order), LARGER_PLOT_KEEPS)
            keep = [i for i, g in enumerate(geoms) if g is not None]
            skipped += len(geoms) - len(keep)
            keep_cats = [keep_cats[i] for i in keep]
            geoms = [geoms[i] for i in keep]
    return keep_cats, geoms, PlotRepairs(len(plots), repaired, skipped, pairs_counted, shared_area)


def exterior_lines(polygon):
    """The plot's exterior (street) boundary: its outer rings as one geometry."""
    rings = [p.exterior for p in polygon_parts(polygon)]
    if len(rings) > 1:
        return shapely.multilinestrings(rings)
    return shapely.linestrings(rings[0].coords)


#: the least length (m) of a footprint's boundary on its plot's boundary (outer ring or hole)
MIN_FRONTAGE = 0.5


def neighbour_index(plots):
    """For each plot, the indices of the other plots it touches (an STRtree query)."""
    out = [[] for _ in plots]
    if not out:
        return out
    plots = np.array(plots, dtype=object)
    tree = shapely.STRtree(plots)
    left, right = tree.query(plots, predicate="dwithin", distance=SNAP * 10)
    for a, b in zip(left, right):
        if a != b:
            out[int(a)].append(int(b))
    return out


def seams(plots, neighbours, k):
    """The boundaries of the plots touching plot ``k`` (None when none does).

    A plot that lost area to an overlapping neighbour (:func:`prepare_plots`)
    has a seam along it: no street, and a building there would be locked in.
    """
    if not neighbours[k]:
        return None
    return shapely.union_all([shapely.boundary(plots[j]) for j in neighbours[k]])


def front(plot, neighbours):
    """The plot's boundary (outer rings and holes) not against one of the
    ``neighbours`` (plots), buffered by a few ``SNAP`` to measure :func:`frontage` on."""
    lines = shapely.boundary(plot)
    if neighbours:
        lines = shapely.difference(lines, shapely.buffer(shapely.union_all(neighbours), SNAP * 5))
    return shapely.buffer(lines, SNAP * 10)


def frontage(footprint, front_area):
    """Length of a footprint's boundary on its plot's :func:`front`."""
    return float(shapely.intersection(shapely.boundary(footprint), front_area).length)


def street_edges(rings, exterior, seam=None):
    """For each ring, which of its edges lie on the exterior (endpoints and midpoint on it)
    and not all along ``seam`` (see :func:`seams`).

    Returns one ``(on_street, lengths)`` pair of arrays per ring.
    """
    if not rings:
        return []
    pts = np.vstack([np.asarray(r, dtype=float) for r in rings])
    sizes = np.array([len(r) for r in rings])
    offsets = ring_offsets(sizes)
    nxt = np.arange(1, len(pts) + 1)
    nxt[offsets[1:] - 1] = offsets[:-1]
    probe = np.vstack([pts, (pts + pts[nxt]) / 2])
    on = shapely.distance(shapely.points(probe), exterior) <= SNAP * 10
    n = len(pts)
    edge = on[:n] & on[nxt] & on[n:]
    if seam is not None:
        on = shapely.distance(shapely.points(probe), seam) <= SNAP * 10
        edge &= ~(on[:n] & on[nxt] & on[n:])
    lengths = np.hypot(*(pts[nxt] - pts).T)
    return [(edge[offsets[k]:offsets[k + 1]], lengths[offsets[k]:offsets[k + 1]])
            for k in range(len(rings))]


def street_length(rings, exterior, seam=None):
    """Length of each ring's boundary that lies on the exterior (not along ``seam``)."""
    return [float(length[edge].sum()) for edge, length in street_edges(rings, exterior, seam)]
