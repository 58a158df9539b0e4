"""Shed roofs (lean-to, skillion): one plane over the footprint, in batch.

A shed roof is the footprint lifted onto one plane that is highest along
its high edge and falls to the eaves at the footprint's farthest vertex
from that edge (:func:`~reconstruction.lod2.roofs.plan.plan_roofs` chooses
the edge so that no wall above the eaves stands against a neighbour). The
walls rise to the plane: above the eaves each footprint edge has a
vertical face up to the roof (a quad, a triangle where one end stays at the
eaves, none along the low edge). Any simple footprint, convex or concave,
gets one.
"""

import numpy as np

from .model import RoofGroup


def shed_group(index, xy, edge, height, low=None):
    """The shed roofs of footprints ``xy`` (G, n, 2) (counter-clockwise),
    ``height`` (G,) above the eaves at their highest, as a
    :class:`~reconstruction.lod2.roofs.model.RoofGroup` of the footprints
    ``index``. The plane runs parallel to each one's edge ``edge`` (G,): high
    along it, falling to the eaves at the farthest vertex; where ``low``
    (G,) is True it is low along it (at the eaves over its whole length),
    rising to the farthest vertex.

    Roof vertex ``n + k`` is footprint vertex ``k`` lifted onto the plane;
    where the plane meets the eaves the faces use the footprint's own
    vertex instead, so that no face has a side of zero length (the lifted
    copy is then unused).
    """
    xy = np.asarray(xy, dtype=float)
    G, n, _ = xy.shape
    height = np.asarray(height, dtype=float)
    edge = np.asarray(edge, dtype=np.int64)
    low = np.zeros(G, dtype=bool) if low is None else np.asarray(low, dtype=bool)
    rows = np.arange(G)
    a = xy[rows, edge]
    t = xy[rows, (edge + 1) % n] - a
    t /= np.hypot(t[:, 0], t[:, 1])[:, None]
    depth = t[:, None, 0] * (xy[..., 1] - a[:, None, 1]) - t[:, None, 1] * (xy[..., 0] - a[:, None, 0])
    lo, hi = depth.min(axis=1), depth.max(axis=1)
    rise = np.where(low[:, None], depth - lo[:, None], hi[:, None] - depth)
    z = height[:, None] * rise / np.maximum(hi - lo, 1e-12)[:, None]
    at_eaves = rise <= 1e-9 * (1.0 + np.abs(hi - lo))[:, None]
    z[at_eaves] = 0.0
    lifted = np.concatenate([xy, z[..., None]], axis=2)
    up = np.where(at_eaves, np.arange(n), n + np.arange(n))           # (G, n) roof vertex numbers
    j = np.arange(n)
    # the wall face above edge j: j, j + 1, then the lifted j + 1 and j (those off the eaves)
    ring = np.stack([np.broadcast_to(j, (G, n)), np.broadcast_to((j + 1) % n, (G, n)),
                     up[:, (j + 1) % n], up[:, j]], axis=2)
    keep = np.ones((G, n, 4), dtype=bool)
    keep[..., 2] = ~at_eaves[:, (j + 1) % n]
    keep[..., 3] = ~at_eaves[:, j]
    order = np.argsort(~keep, axis=2, kind="stable")
    walls = np.take_along_axis(ring, order, axis=2)
    counts = keep.sum(axis=2)
    F = n + 1
    faces = np.zeros((G, F, max(n, 4)), dtype=np.int64)
    faces[:, :n, :4] = walls
    faces[:, n, :n] = up
    cnt = np.concatenate([np.where(counts >= 3, counts, 0), np.full((G, 1), n)], axis=1)
    return RoofGroup("shed", np.asarray(index), xy, lifted, faces, cnt, height.copy())
