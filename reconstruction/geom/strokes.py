"""The width of a map's drawn strokes (lines, letters) from a boolean mask of them.

Shared by the stages that read a map's ink: r.histo.classify (the window of
the removed letters), v.histo.generalize (parameters in the map's scale)
and v.histo.subdivide (the lines drawn inside the plots). Pure numpy and
scipy.
"""

import numpy as np
from scipy import ndimage


def disk(radius):
    """A disk of ``radius`` cells as a boolean structuring element."""
    r = int(np.ceil(radius))
    y, x = np.mgrid[-r:r + 1, -r:r + 1]
    return x * x + y * y <= radius * radius


def ridge(mask):
    """The distance of each cell of ``mask`` to its edge (the map's border counts
    as outside), and its ridge: the cells no neighbour of which lies farther
    inside (the objects' median lines)."""
    mask = np.asarray(mask, dtype=bool)
    distance = ndimage.distance_transform_edt(np.pad(mask, 1))[1:-1, 1:-1]
    return distance, mask & (distance >= ndimage.maximum_filter(distance, size=3))


def typical_thickness(mask):
    """The typical thickness (cells) of the objects of a boolean mask: twice the
    median distance from their median lines (:func:`ridge`) to their edge, minus
    the centre cell (a one-cell line is 1, a three-cell stroke 3; a two-cell one
    1, like a line between two cells); the few places where lines meet or
    letters touch do not change it. 0 for an empty mask."""
    mask = np.asarray(mask, dtype=bool)
    if not mask.any():
        return 0.0
    distance, median_line = ridge(mask)
    return float(2 * np.median(distance[median_line]) - 1)


def stroke_widths(mask):
    """The widths (cells) of the strokes of a boolean mask along their median lines:
    twice the distance to the edge less the centre cell, rounded up to a whole
    cell (a line two cells wide is 2 wide); [1.0] when there is none."""
    mask = np.asarray(mask, dtype=bool)
    if not mask.any():
        return np.array([1.0])
    distance, median_line = ridge(mask)
    return np.maximum(1.0, np.ceil(2 * distance[median_line] - 0.5))
