"""The invariants of the subdivision's footprints, as a check anyone can run.

:func:`invariant_violations` lists the footprints that break what
:func:`reconstruction.subdivide.stage.subdivide` guarantees (valid, inside their
plot, convex, on the street, fronting their plot's boundary, no sliver, no
overlaps); the tests run it on
every result, and on the footprints as GRASS stored them.
"""

import numpy as np
import shapely
from shapely.geometry import Polygon

from ..core.contract import SOURCE_PROCEDURAL
from ..geom.polygons import polygon_parts
from .convex_rings import SNAP, ccw_ring, has_wedge, is_convex, is_sliver, sharp_corners
from .plots import (CHECK_GRID, MIN_FRONTAGE, OVERLAP_TOLERANCE, exterior_lines, front,
                    frontage, neighbour_index)


def invariant_violations(geometries, plot, source, plots_by_cat, case=None,
                         tolerance=OVERLAP_TOLERANCE):
    """Footprints breaking the invariants, by kind (an empty dict when none).

    ``plots_by_cat`` maps a plot category to its (prepared, disjoint) plot.
    Checks: valid single polygons; generated ones convex (except case 1,
    where the footprint is the plot itself, when ``case`` is given), inside their plot
    (area outside <= ``tolerance``), on its exterior boundary and no sliver
    unless the plot is one; fronting the plot's boundary (outer ring or a
    hole, not a seam against another plot) over at least ``MIN_FRONTAGE``
    ("no_frontage": no building locked inside the block); no corner under
    ``MIN_ANGLE`` unless the plot has one there ("wedge"); no two footprints
    overlapping by more than ``tolerance`` (pairs found with an STRtree).
    """
    bad = {}
    fronts = _fronts(plots_by_cat)

    def count(kind, index):
        bad.setdefault(kind, []).append(index)

    for i, (g, cat, src) in enumerate(zip(geometries, plot, source)):
        if g is None or g.geom_type != "Polygon" or not g.is_valid or g.is_empty:
            count("invalid", i)
            continue
        if src != SOURCE_PROCEDURAL:
            continue
        parcel = plots_by_cat[cat]
        # snap-rounded overlay: GEOS's floating overlay can lose a polygon that
        # shares a vertex with the plot and has one on the plot's edge
        if shapely.difference(g, parcel, grid_size=CHECK_GRID).area > tolerance:
            count("outside", i)
        if not is_convex(g) and (case is None or case[i] != 1):
            count("concave", i)
        if is_sliver(g) and not any(is_sliver(p) for p in polygon_parts(parcel)):
            count("sliver", i)
        if g.distance(exterior_lines(parcel)) > 10 * SNAP:
            count("no_street", i)
        elif frontage(g, fronts[cat]) < MIN_FRONTAGE:
            count("no_frontage", i)
        if (case is None or case[i] != 1) and _wedge(g, parcel):
            count("wedge", i)
    valid = [g if g is not None and g.is_valid else Polygon() for g in geometries]
    if valid:
        tree = shapely.STRtree(valid)
        left, right = tree.query(valid, predicate="intersects")
        pairs = left < right
        if pairs.any():
            areas = shapely.area(shapely.intersection(np.array(valid, dtype=object)[left[pairs]],
                                                      np.array(valid, dtype=object)[right[pairs]],
                                                      grid_size=CHECK_GRID))
            for a, b, area in zip(left[pairs], right[pairs], areas):
                if area > tolerance:
                    count("overlap", (int(a), int(b)))
    return bad


def _fronts(plots_by_cat):
    """Each plot's :func:`~reconstruction.subdivide.plots.front`, by category."""
    cats = list(plots_by_cat)
    plots = [plots_by_cat[c] for c in cats]
    near = neighbour_index(plots)
    return {c: front(p, [plots[j] for j in n]) for c, p, n in zip(cats, plots, near)}


def _wedge(footprint, parcel, tolerance=1e-3):
    """Whether a footprint has a corner under ``MIN_ANGLE`` where its plot has none."""
    ring = ccw_ring(footprint.exterior.coords)
    return has_wedge(ring, sharp_corners(parcel) if has_wedge(ring) else (), tolerance)
