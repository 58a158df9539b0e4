"""The types roofs travel in: their parameters, one roof, and roofs in bulk.

Roofs are relative to the eaves (z = 0 along the footprint) in the local
coordinates of their footprint (a counter-clockwise ring). Faces are rings
of roof vertex indices oriented outwards (seen from outside,
counter-clockwise); the first ``n`` roof vertices are the footprint's.
"""

from dataclasses import dataclass
from typing import Optional

import numpy as np


@dataclass(frozen=True)
class RoofConfig:
    """The roof parameters that are the same for every building."""

    #: minimum pitch of the hip ends (degrees)
    pitch_min: float = 60.0
    #: (low, high) range of the mansard inset (m), the horizontal run of its lower faces
    inset: tuple = (1.0, 2.0)
    #: (low, high) range of the crow-step height (m)
    step: tuple = (0.4, 0.7)
    #: thickness of the crow-stepped facade (m)
    thickness: float = 0.5


@dataclass(frozen=True)
class Roof:
    """One roof: ``vertices`` (m, 3), the footprint's first, and ``faces``."""

    vertices: np.ndarray
    #: rings of vertex indices, oriented outwards
    faces: list
    #: True when the roof's free boundary is exactly the footprint outline
    #: (walls are then plain quads)
    boundary: bool
    #: height of the highest vertex above the eaves
    zmax: float
    #: per footprint edge ``i``, the roof vertices along it from ``i`` to
    #: ``i + 1`` (the walls follow them); None: walk the roof's boundary
    chains: Optional[list] = None


@dataclass(frozen=True)
class RoofGroup:
    """Roofs of footprints with the same number of vertices, as arrays.

    ``kind`` names the solver family that made them ("flat", "envelope",
    "stepped"); the arrays mean the same whatever it is, so that walls and
    faces of every group are assembled in one numpy pass.
    """

    kind: str
    #: (G,) footprint index of each roof
    index: np.ndarray
    #: (G, n, 2) the footprints (local coordinates)
    xy: np.ndarray
    #: (G, C, 3) roof vertices past the footprint's n (their numbers are n, n + 1, ...)
    vertices: np.ndarray
    #: (G, F, K) faces: the first ``counts`` entries of each are roof vertex
    #: numbers; faces with fewer than 3 are no faces
    faces: np.ndarray
    #: (G, F) entries in use per face
    counts: np.ndarray
    #: (G,) height of the highest vertex above the eaves
    zmax: np.ndarray
    #: (G, n) or None: the roof vertex on the boundary along each footprint
    #: edge between its ends (-1 = none); None: every edge has none
    wall_mid: Optional[np.ndarray] = None

    def roof(self, j):
        """Roof ``j`` of the group as a :class:`Roof`."""
        xy = self.xy[j]
        n = len(xy)
        faces = [r[:k] for r, k in zip(self.faces[j].tolist(), self.counts[j].tolist()) if k >= 3]
        base = np.concatenate([xy, np.zeros((n, 1))], axis=1)
        vertices = np.concatenate([base, self.vertices[j]])
        chains = None
        if self.wall_mid is not None:
            chains = [[k, (k + 1) % n] if mid < 0 else [k, mid, (k + 1) % n]
                      for k, mid in enumerate(self.wall_mid[j].tolist())]
        return Roof(vertices, faces, self.wall_mid is None, float(self.zmax[j]), chains)


def flat_group(index, xy):
    """The flat roofs (the footprints at the eaves) of footprints ``xy`` (G, n, 2)."""
    G, n, _ = xy.shape
    return RoofGroup("flat", index, xy, np.zeros((G, 0, 3)),
                     np.broadcast_to(np.arange(n), (G, 1, n)), np.full((G, 1), n), np.zeros(G))
