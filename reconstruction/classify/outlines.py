"""Edge cells of areas whose outline a map draws inside them (r.histo.classify outline=inside).

A map may draw a building plot's outline as a darker stroke just inside
the plot: the plot's edge is the stroke's outer edge. A scan's pixel on that
edge mixes the stroke with what lies outside (paper, a garden), and the mix
looks like the plot's pale fill: the classifier gives the plot the cell
whether the plot covers a fifth or four fifths of it, and every plot grows by
about half a cell all round (issue 32: on the synthetic map 4,900 of the
6,650 cells wrongly given to plots were such edge cells, a quarter to a half
covered).

:func:`inside_outlines` decides each edge cell by its colour. An outermost
cell of an area is a mix of three colours at most: the stroke's, the
colour outside (paper, a garden) and the area's fill (where the classifier
stopped a cell short of the stroke); it stays in the area when the outside
covers less than half of it (unmixed by least squares against the local
colours). A cell beside an area joins it when it lies at least halfway
from the outside's colour to the stroke's: the stroke fills a strip about
one cell wide along the outline, so such a cell holds the area's edge.

Maps that centre the outline on the boundary (the digitised Delft plots
follow the line's centre) keep their edge cells as classified
(``outline=centre``, the default).

Pure numpy and scipy, no GRASS.
"""

import numpy as np
from scipy import ndimage

from .removal import FOUR

#: where a map may draw the outline of an area (r.histo.classify outline=)
OUTLINES = ("centre", "inside")

#: the window (cells) over which the colour outside an edge is averaged; the
#: cells at least OUTSIDE_DEPTH cells away from the area count as outside
WINDOW = 7
OUTSIDE_DEPTH = 2


def _local_mean(image, mask, size):
    """Mean of ``image`` (rows, cols, bands) over the ``mask`` cells in a ``size``
    window around each cell, and the share of such cells in the window."""
    weight = ndimage.uniform_filter(mask.astype(float), size, mode="constant")
    means = np.stack([ndimage.uniform_filter(np.where(mask, image[..., k], 0.0), size,
                                             mode="constant")
                      for k in range(image.shape[-1])], axis=-1)
    return means / np.maximum(weight, 1e-12)[..., None], weight


def stroke_colour(image, ring):
    """The stroke's colour: the median colour of the darkest quarter of the
    areas' outermost cells (their sum of bands)."""
    colours = image[ring]
    darkest = np.argsort(colours.sum(axis=1), kind="stable")[:max(1, len(colours) // 4)]
    return np.median(colours[darkest], axis=0)


def stroke_share(colours, stroke, outside):
    """How much of each cell the stroke covers: the cell's colour projected on the
    line from the ``outside`` colour (0) to the ``stroke`` colour (1); (n, bands)."""
    direction = stroke - outside
    return ((colours - outside) * direction).sum(axis=1) / np.maximum(
        (direction * direction).sum(axis=1), 1e-12)


def outside_share(colours, stroke, outside, fill):
    """How much of each cell the outside covers: the cell's colour unmixed
    into the ``outside``, ``stroke`` and ``fill`` colours (least squares, the
    weights adding up to 1, not bounded); (n, bands) each, ``stroke`` (bands,)
    too."""
    to_stroke, to_fill, seen = stroke - outside, fill - outside, colours - outside
    a11 = (to_stroke * to_stroke).sum(axis=1)
    a12 = (to_stroke * to_fill).sum(axis=1)
    a22 = (to_fill * to_fill).sum(axis=1)
    b1, b2 = (to_stroke * seen).sum(axis=1), (to_fill * seen).sum(axis=1)
    det = np.maximum(a11 * a22 - a12 * a12, 1e-9)
    return 1.0 - ((a22 * b1 - a12 * b2) + (a11 * b2 - a12 * b1)) / det


def _between_areas(area):
    """Cells 4-next to two or more separate areas of ``area``."""
    parts, _n = ndimage.label(area, FOUR)
    padded = np.pad(parts, 1)
    rows, cols = area.shape
    neighbours = np.stack([padded[1 + dr:1 + dr + rows, 1 + dc:1 + dc + cols]
                           for dr, dc in ((-1, 0), (1, 0), (0, -1), (0, 1))])
    low = np.where(neighbours > 0, neighbours, np.iinfo(parts.dtype).max).min(axis=0)
    return low < neighbours.max(axis=0)


def printed_cells(classes, config):
    """The cells of the classes ``config`` removes (printed over the map), which
    :func:`inside_outlines` leaves as they are; None unless ``config.outline``
    is ``inside``."""
    return np.isin(classes, list(config.remove)) if config.outline == "inside" else None


def inside_outlines(classes, bands, labels, share=0.5, printed=None, unmix=True):
    """``classes`` with the edge cells of the ``labels`` areas decided by colour.

    ``bands``: the map's bands (arrays like ``classes``, nan for no data);
    an outermost cell of an area that the area covers less than ``share`` of
    (the outside more than 1 - ``share``, :func:`outside_share`; without fill
    cells nearby, or not ``unmix``, the stroke less than ``share``,
    :func:`stroke_share`) takes the class of the
    nearest cell outside the area; a cell next to an area (4-connected) whose
    stroke share reaches ``share`` joins the area. The outside colour is the
    mean of the cells at least :data:`OUTSIDE_DEPTH` cells away from the area
    in a :data:`WINDOW` window, the fill's the mean of the area's cells
    farther than that inside it; an edge cell without outside cells, on no
    data, or ``printed`` (a boolean array: the cells of classes printed over
    the map, e.g. text, whose colour is ink, not the outline's) stays as it
    is, and so does a cell next to two areas of a label (it would join them).
    ``unmix``: False for bands not in register (a colour plane off by a cell
    makes a cell's colour no mix of its neighbours'; unmixed, the edges of
    the synthetic town's plots came out differently on its three maps).
    """
    image = np.stack([np.asarray(b, dtype=float) for b in bands], axis=-1)
    valid = np.isfinite(image).all(axis=-1)
    image = np.where(valid[..., None], image, 0.0)
    if printed is not None:
        valid &= ~np.asarray(printed, dtype=bool)
    out = np.array(classes, copy=True)
    for label in labels:
        area = out == label
        if not area.any() or area.all():
            continue
        ring = area & ~ndimage.binary_erosion(area, FOUR, border_value=1) & valid
        if not ring.any():
            continue
        beside = ~area & ndimage.binary_dilation(area, FOUR) & valid & ~_between_areas(area)
        _, (near_r, near_c) = ndimage.distance_transform_edt(area, return_indices=True)
        far = ~area & valid & (ndimage.distance_transform_edt(~area) >= OUTSIDE_DEPTH)
        outside, seen = _local_mean(image, far, WINDOW)
        stroke = stroke_colour(image, ring)
        # the ring: cells the outside covers most of leave the area
        r, c = np.nonzero(ring & (seen > 0))
        colours, around = image[r, c], outside[r, c]
        leaves = stroke_share(colours, stroke[None, :], around) < share
        if unmix:
            deep = area & valid & (ndimage.distance_transform_edt(area) > OUTSIDE_DEPTH)
            fill, filled = _local_mean(image, deep, WINDOW)
            unmixed = outside_share(colours, stroke[None, :], around, fill[r, c]) > 1.0 - share
            leaves = np.where(filled[r, c] > 0, unmixed, leaves)
        r, c = r[leaves], c[leaves]
        out[r, c] = out[near_r[r, c], near_c[r, c]]
        # beside: cells the stroke covers most of join it
        r, c = np.nonzero(beside & (seen > 0))
        joins = stroke_share(image[r, c], stroke[None, :], outside[r, c]) >= share
        out[r[joins], c[joins]] = label
    return out
