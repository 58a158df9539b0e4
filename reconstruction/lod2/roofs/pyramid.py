"""Pyramid roofs (tent roofs): every footprint edge rises to one apex, in batch.

A pyramid roof is one triangle per footprint edge up to an apex above the
footprint's centroid (the pole of inaccessibility when the centroid does not
see every edge). The triangles tile the footprint exactly when the apex
lies inside every edge's half plane (in the footprint's kernel): always for
a convex footprint, for a concave one only when it is star-shaped around the
apex. Where no apex sees every edge by at least :data:`MIN_SETBACK` of the
footprint's size, the footprint gets no pyramid (the caller builds a hip
roof, the tent roof of a footprint that is not star-shaped); nor does one
that shares an edge with a neighbour (a tent roof stands free; its face on
a shorter edge is steeper, an end against the neighbour).
"""

import numpy as np
import shapely

from .model import RoofGroup

#: the apex stands at least this share of the footprint's diameter inside every edge line
MIN_SETBACK = 0.02


def _setback(xy, apex):
    """(G,) the smallest distance of ``apex`` (G, 2) inside the edge lines of
    ``xy`` (G, n, 2) (negative: outside one)."""
    nxt = np.roll(xy, -1, axis=1)
    t = nxt - xy
    length = np.maximum(np.hypot(t[..., 0], t[..., 1]), 1e-300)
    cross = t[..., 0] * (apex[:, None, 1] - xy[..., 1]) - t[..., 1] * (apex[:, None, 0] - xy[..., 0])
    return (cross / length).min(axis=1)


def apexes(xy):
    """The apex (G, 2) of the pyramid roof of each footprint ``xy`` (G, n, 2)
    and whether it sees every edge (G,): the centroid, else the pole of
    inaccessibility (GEOS's largest inscribed circle's centre)."""
    xy = np.asarray(xy, dtype=float)
    polygons = shapely.polygons(xy)
    apex = shapely.get_coordinates(shapely.centroid(polygons)).reshape(-1, 2)
    need = MIN_SETBACK * np.ptp(xy, axis=1).max(axis=1)
    setback = _setback(xy, apex)
    bad = setback < need
    if bad.any():
        apex[bad] = shapely.get_coordinates(shapely.get_point(
            shapely.maximum_inscribed_circle(polygons[bad], tolerance=1e-3), 0)).reshape(-1, 2)
        setback[bad] = _setback(xy[bad], apex[bad])
    return apex, setback >= need


def pyramid_group(index, xy, apex, height):
    """The pyramid roofs of footprints ``xy`` (G, n, 2) with apexes ``apex``
    (G, 2) at ``height`` (G,) above the eaves, as a
    :class:`~reconstruction.lod2.roofs.model.RoofGroup` of the footprints ``index``."""
    xy = np.asarray(xy, dtype=float)
    G, n, _ = xy.shape
    height = np.asarray(height, dtype=float)
    top = np.concatenate([apex, height[:, None]], axis=1)[:, None, :]
    j = np.arange(n)
    faces = np.broadcast_to(np.stack([j, (j + 1) % n, np.full(n, n)], axis=1), (G, n, 3))
    return RoofGroup("pyramid", np.asarray(index), xy, top, faces.copy(), np.full((G, n), 3),
                     height.copy())
