"""Removal of classes printed over a map (text, symbols), of thin parts and specks.

The end of the thesis's first stage (Morlighem 2021, Section 3.2.1): the
cells of the removed classes, the classes' parts thinner than a minimum
width and their regions smaller than a minimum mapping unit are refilled
from around them (:func:`remove_classes`): each with the class of the
nearest known cell, in a window sized from the thickness of the removed
objects; a fill that would join two plots facing each other across a street
(a street name printed between them) is refused there (:func:`bridges`).

Arrays are (rows, cols) of class labels; pure numpy and scipy, no GRASS.
"""

import numpy as np
from scipy import ndimage

from ..geom.strokes import ridge, typical_thickness


def object_thickness(mask):
    """Largest thickness (in cells) over the objects of a boolean mask.

    The thickness of an object is its longest transect across its median
    line: twice the largest distance from the median line to the object's
    edge, minus the centre cell (a one-cell line has thickness 1). 0 for an
    empty mask.
    """
    mask = np.asarray(mask, dtype=bool)
    if not mask.any():
        return 0.0
    distance = ndimage.distance_transform_edt(np.pad(mask, 1))
    return float(2 * distance.max() - 1)


def line_counts(classes, remove, within=None):
    """For each ``remove`` label, ``(cells of its long objects, its cells)``
    (:func:`line_classes`), counted in ``within`` (slices of ``classes``:
    a tile's core in its outer window, whose objects are seen whole) or
    everywhere."""
    classes = np.asarray(classes)
    counts = {}
    for label in remove:
        mask = classes == label
        objects, n = ndimage.label(mask, _EIGHT)
        if not n:
            counts[label] = (0, 0)
            continue
        distance, median_line = ridge(mask)
        ids = np.arange(1, n + 1)
        width = 2 * np.asarray(ndimage.median(distance, objects * median_line, ids))
        area = np.bincount(objects.ravel(), minlength=n + 1)[1:]
        long = np.concatenate([[False], area >= LINE_ELONGATION * width ** 2])
        counted = objects if within is None else objects[within]
        counts[label] = (int(long[counted].sum()), int((counted > 0).sum()))
    return counts


def line_classes(classes, remove, counts=None):
    """The ``remove`` labels drawn as lines (the outlines of the blocks), not
    as letters or symbols: the objects holding most of their cells are long,
    their area at least :data:`LINE_ELONGATION` times the square of their
    width (twice the median distance from their median line to their edge).
    A block's outline stroke is a long ring; a letter, a symbol, or a name
    whose paper between the letters was read as ink, a short blob.
    ``counts``: the :func:`line_counts` to decide by (a tiled map's, added
    up over its tiles: one decision for the whole map), else those of
    ``classes``."""
    if counts is None:
        counts = line_counts(classes, remove)
    return tuple(label for label in remove
                 if counts.get(label, (0, 0))[1] and 2 * counts[label][0] > counts[label][1])


def removed_thickness(classes, remove, lines=None):
    """The thickness (cells, :func:`object_thickness`) of the thickest
    letter or symbol of the ``remove`` classes: of those not drawn as lines
    (:func:`line_classes`; all of them when every one is). Where a block's
    outline strokes meet or touch the letters they make knots thicker than
    any letter, which would set a larger window and minimum mapping unit
    (on a 0.1 m map of Venice with its outline class removed: 18 cells).
    ``lines``: the labels drawn as lines when decided already (a tiled map's,
    :func:`line_classes` of the whole map's counts)."""
    classes = np.asarray(classes)
    lines = line_classes(classes, remove) if lines is None else lines
    letters = [label for label in remove if label not in lines] or list(remove)
    return object_thickness(np.isin(classes, letters))


def removal_window(mask):
    """Moving window size from the objects to remove: thickness / 2 + 1, odd, >= 3."""
    return window_for_thickness(object_thickness(mask))


def window_for_thickness(thickness):
    """Moving window size for removed objects ``thickness`` cells thick: thickness / 2 + 1,
    odd, >= 3."""
    window = int(thickness / 2.0 + 1)
    if window % 2 == 0:
        window += 1
    return max(window, 3)


def _window_counts(binary, window):
    """Number of True cells in the window x window box around each cell."""
    r = window // 2
    padded = np.pad(binary.astype(np.int32), ((r + 1, r), (r + 1, r)))
    integral = padded.cumsum(axis=0).cumsum(axis=1)
    return (integral[window:, window:] - integral[:-window, window:]
            - integral[window:, :-window] + integral[:-window, :-window])


def fill_from_surroundings(classes, holes, window=3, iterations=None, nodata=0, exclude=()):
    """Fill ``holes`` with the modal class of the surrounding cells.

    Each iteration gives every hole cell with at least one known cell (not a
    hole, not ``nodata``, not an ``exclude`` label) in its window x window
    neighbourhood the most frequent known class there (the lowest label among
    equals); filled cells are known in the next iteration, as repeated
    r.neighbors method=mode would do. Stops when no hole is left, nothing
    changes, or after ``iterations``. Returns ``(filled classes, remaining
    holes)``.
    """
    classes = np.array(classes, copy=True)
    holes = np.array(holes, dtype=bool, copy=True)
    if window < 1 or window % 2 == 0:
        raise ValueError("window must be a positive odd number")
    done = 0
    while holes.any() and (iterations is None or done < iterations):
        known = ~holes & (classes != nodata)
        if len(exclude):
            known &= ~np.isin(classes, list(exclude))
        labels = np.unique(classes[known])
        if not len(labels):
            break
        # work only on the bounding box of the holes, grown by the window
        rows, cols = np.nonzero(holes)
        r = window // 2
        r0, r1 = max(rows.min() - r, 0), min(rows.max() + r + 1, classes.shape[0])
        c0, c1 = max(cols.min() - r, 0), min(cols.max() + r + 1, classes.shape[1])
        sub_classes = classes[r0:r1, c0:c1]
        sub_known = known[r0:r1, c0:c1]
        sub_holes = holes[r0:r1, c0:c1]
        best_count = np.zeros(sub_classes.shape, dtype=np.int32)
        best_label = np.zeros(sub_classes.shape, dtype=classes.dtype)
        for label in labels:
            count = _window_counts(sub_known & (sub_classes == label), window)
            better = count > best_count
            best_count[better] = count[better]
            best_label[better] = label
        fill = sub_holes & (best_count > 0)
        if not fill.any():
            break
        sub_classes[fill] = best_label[fill]
        sub_holes[fill] = False
        done += 1
    return classes, holes


def fill_from_nearest(classes, holes, window=3, reach=None, nodata=0, exclude=()):
    """Fill ``holes`` with the class of the nearest known cells.

    Known cells are those that are not holes, not ``nodata`` and not an
    ``exclude`` label. Each hole cell takes the label of the known cell
    closest to it (Euclidean distance between cell centres); when cells of
    several labels are equally close, the one with the most known cells in
    the window x window neighbourhood wins (the lowest label among equals;
    the default 3 x 3 is the cell's immediate neighbours: a wider window
    brings back the bias below).
    Two classes on either side of a hole thus meet halfway across it,
    whichever of them has more cells around: the modal class of a window
    alone (:func:`fill_from_surroundings`) favours the class whose cells the
    hole did not cover, a solid plot beside a street cut up by the letters
    of its name, and lets it grow across the hole. Cells farther than
    ``reach`` cells from every known cell stay holes. Returns ``(filled
    classes, remaining holes)``.
    """
    classes = np.array(classes, copy=True)
    holes = np.array(holes, dtype=bool, copy=True)
    known = ~holes & (classes != nodata)
    if len(exclude):
        known &= ~np.isin(classes, list(exclude))
    labels = np.unique(classes[known])
    if not holes.any() or not len(labels):
        return classes, holes
    distances = np.stack([ndimage.distance_transform_edt(~(known & (classes == label)))
                          for label in labels])
    nearest = distances.min(axis=0)
    # the window's count of each equally near label; the others never win
    votes = np.stack([np.where(d <= nearest + 1e-9, _window_counts(known & (classes == label),
                                                                    window), -1)
                      for label, d in zip(labels, distances)])
    fill = holes if reach is None else holes & (nearest <= reach)
    classes[fill] = labels[votes.argmax(axis=0)][fill]
    holes[fill] = False
    return classes, holes


#: the 4- and 8-neighbourhoods of a cell (the classify package's connectivity)
FOUR = ndimage.generate_binary_structure(2, 1)
_EIGHT = np.ones((3, 3), dtype=bool)


def small_regions(classes, min_cells, nodata=0, hidden=None, exact=()):
    """Cells of 4-connected single-class regions smaller than ``min_cells``.

    With ``hidden`` cells (the removed objects: what lies under them is
    unknown), a small region that reaches a region of its class of at least
    ``min_cells`` through them is part of it, for every class but the
    ``exact`` ones: the street between the letters of its name belongs to
    the street around the name. What a removed object encloses (the digits
    of a symbol, a letter's counter) stays small.
    """
    classes = np.asarray(classes)
    small = np.zeros(classes.shape, dtype=bool)
    if min_cells <= 1:
        return small
    if hidden is not None:
        # what a removed object encloses (a symbol's digits, a letter's counter)
        # is under it, not beside it
        enclosed = ndimage.binary_fill_holes(hidden) & ~hidden
    for label in np.unique(classes):
        if label == nodata:
            continue
        mask = classes == label
        regions, n = ndimage.label(mask, FOUR)
        if not n:
            continue
        sizes = np.bincount(regions.ravel(), minlength=n + 1)
        tiny = sizes < min_cells
        tiny[0] = False
        cells = tiny[regions]
        if hidden is not None and label not in exact and cells.any():
            joined, _ = ndimage.label(mask | hidden, FOUR)
            reached = np.unique(joined[mask & ~cells])
            cells &= ~np.isin(joined, reached[reached > 0]) | enclosed
        small |= cells
    return small


def thin_parts(classes, width, nodata=0, hidden=None, exact=()):
    """Cells of every class that a width x width square cannot cover (opening).

    ``hidden`` cells (the removed objects: what lies under them is unknown)
    count as any class but the ``exact`` ones: a strip of street between a
    street name and a plot is thin beside the letters, not under them.
    """
    classes = np.asarray(classes)
    thin = np.zeros(classes.shape, dtype=bool)
    if width <= 1:
        return thin
    square = np.ones((width, width), dtype=bool)
    for label in np.unique(classes):
        if label == nodata:
            continue
        mask = classes == label
        cover = mask if hidden is None or label in exact else mask | hidden
        thin |= mask & ~ndimage.binary_opening(cover, square, border_value=1)
    return thin


#: a cell lies between two regions when the directions to their nearest cells are at
#: least this far apart (degrees): across a street, not beside two corners
BETWEEN = 135.0


#: Cells of a plot's outline: the refilled cells this close to a plot may
#: join it wherever they lie (its drawn outline stroke, split halfway by the
#: nearest fill; :func:`outgrowths`, :func:`_facing_gaps`).
OUTLINE = 1.0
#: Two plots across a refilled label face each other up to this many refill
#: windows apart (a label can cover a street twice as wide as its letters are
#: thick: a 10-cell street under a 5-cell window in the synthetic town's 1880 map).
FACING = 2
#: A removed class is drawn as lines when most of its cells lie in objects at
#: least this many times as large as the square of their width
#: (:func:`line_classes`): a 2-cell outline stroke round a 10 x 15-cell plot
#: is 25 times; a solid 5 x 10-cell name 2 times, a letter H drawn with a
#: 3-cell pen 15 x 21 cells large 10 times.
LINE_ELONGATION = 20


def _facing_gaps(regions, ids, hole, distance, share=0.1):
    """The gaps between the regions ``ids`` that face each other beside ``hole``.

    The front of two regions is the cells outside them within ``distance``
    of both. Two plots on either side of a street face each other along the
    street beyond the street name printed in it: part of their front (at
    least ``share`` of the part inside the hole: a name may cover nine
    tenths of the street two plots face each other along) lies outside the hole
    *between* them (the directions to the two plots' nearest cells at least
    :data:`BETWEEN` apart: across the street). The two pieces of one plot cut
    by a label meet only through the label: outside it, their front is the
    lens beside the two corners of the cut, in the streets on either side,
    which lies beside both pieces, not between them. Returns the union of
    the fronts of the pairs that face each other (empty when none do): the
    street between two plots, not the plot a label cut, nor the other
    plots the same hole touches (a label across a block and the streets on
    either side, joined to the plots' outline strokes along the streets).
    A plot's outline (its cells within :data:`OUTLINE`) is left out of the
    gaps where every other plot is farther than two outlines.
    """
    free = ~np.isin(regions, ids)
    reach = int(np.ceil(max(distance, 2 * OUTLINE))) + 1
    boxes = ndimage.find_objects(np.where(np.isin(regions, ids), regions, 0))
    # each region's distances in its own box, widened by what is read of them
    # (its front, its outline's two outlines): a street network's outline
    # class is one hole beside hundreds of plots, each measured over the whole
    # hole made the removal most of Venice 1808's classification
    near = []
    first = np.full(regions.shape, np.inf)
    second = np.full(regions.shape, np.inf)
    for i in ids:
        box = boxes[i - 1]
        window = tuple(slice(max(b.start - reach, 0), b.stop + reach) for b in box)
        d, nearest = ndimage.distance_transform_edt(regions[window] != i, return_indices=True)
        toward = (nearest - np.indices(d.shape)).astype(float)
        near.append((window, (d <= distance) & free[window], toward))
        lower = np.minimum(first[window], d)
        second[window] = np.minimum(second[window], np.maximum(first[window], d))
        first[window] = lower
    limit = np.cos(np.radians(BETWEEN))
    gaps = np.zeros(hole.shape, dtype=bool)
    for a in range(len(near)):
        for b in range(a + 1, len(near)):
            wa, na, ta = near[a]
            wb, nb, tb = near[b]
            both = tuple(slice(max(x.start, y.start), min(x.stop, y.stop)) for x, y in zip(wa, wb))
            if any(s.start >= s.stop for s in both):
                continue
            ia = tuple(slice(s.start - w.start, s.stop - w.start) for s, w in zip(both, wa))
            ib = tuple(slice(s.start - w.start, s.stop - w.start) for s, w in zip(both, wb))
            front = na[ia] & nb[ib]
            if not front.any():
                continue
            va, vb = ta[(slice(None),) + ia][:, front], tb[(slice(None),) + ib][:, front]
            cos = (va * vb).sum(axis=0) / np.maximum(
                np.hypot(*va) * np.hypot(*vb), 1e-12)
            between = np.zeros(front.shape, dtype=bool)
            between[front] = cos <= limit
            inside = int((front & hole[both]).sum())
            outside = int((between & ~hole[both]).sum())
            if outside > 0 and outside >= share * inside:
                gaps[both] |= front
    # each plot keeps its outline where the other plots are farther than both
    # outlines: the gap between them stays open
    return gaps & ~((first <= OUTLINE) & (second > 2 * OUTLINE))


def bridges(before, after, holes, min_cells=1, distance=3, nodata=0, labels=None):
    """Filled cells that join separate objects of their class.

    ``before`` holds the classes with the holes not filled yet, ``after``
    the filled result. For each class (or only ``labels``), the hole
    components (8-connected) whose filled cells of that class join two or
    more regions of at least ``min_cells`` cells (4-connected) that were
    apart are checked: where two of those regions also face each other within
    ``distance`` cells along a front that goes on beside the hole
    (:func:`_facing_gaps`), they are separate objects (two plots across a
    narrow street, the hole a street name printed between them) and the
    hole's cells of that class in the gap between them are returned; where
    two meet only through the hole, the hole had cut one object in two and
    the fill restores it.
    """
    before = np.asarray(before)
    after = np.asarray(after)
    holes = np.asarray(holes, dtype=bool)
    known = ~holes & (before != nodata)
    components, _ = ndimage.label(holes, _EIGHT)
    joined = np.zeros(before.shape, dtype=bool)
    margin = int(np.ceil(distance)) + 2
    for label in np.unique(after[holes]) if labels is None else labels:
        if label == nodata:
            continue
        pre, n_pre = ndimage.label(known & (before == label), FOUR)
        if n_pre < 2:
            continue
        sizes = np.bincount(pre.ravel(), minlength=n_pre + 1)
        small = sizes < max(min_cells, 1)
        small[0] = True
        pre[small[pre]] = 0
        filled = holes & (after == label)
        # regions touching each hole component's filled cells of this class
        grown = ndimage.grey_dilation(np.where(filled, components, 0), footprint=_EIGHT)
        touch = (pre > 0) & (grown > 0)
        pairs = np.unique(np.stack([grown[touch], pre[touch]], axis=1), axis=0)
        per_component = np.bincount(pairs[:, 0], minlength=components.max() + 1)
        # where each region ends up after the fill
        post, _ = ndimage.label(after == label, FOUR)
        index = np.zeros(n_pre + 1, dtype=np.int64)
        index[pre.ravel()] = post.ravel()
        for component in np.flatnonzero(per_component >= 2):
            ids = pairs[pairs[:, 0] == component, 1]
            ends = index[ids]
            shared = np.unique(ends)[np.bincount(np.unique(ends, return_inverse=True)[1]) >= 2]
            ids = ids[np.isin(ends, shared)]
            if len(ids) < 2:
                continue  # the fill joined nothing that was apart
            rows, cols = np.nonzero(components == component)
            r0, r1 = max(rows.min() - margin, 0), rows.max() + margin + 1
            c0, c1 = max(cols.min() - margin, 0), cols.max() + margin + 1
            hole = components[r0:r1, c0:c1] == component
            gaps = _facing_gaps(pre[r0:r1, c0:c1], ids, hole, distance)
            joined[r0:r1, c0:c1] |= gaps & hole & filled[r0:r1, c0:c1]
    return joined


def _to_ink(colours, ink, pure):
    """How far each colour of ``colours`` (n, B) lies from the mixes of ``ink``
    (B,) and the ``pure`` colour (B,): from the nearest point of the segment
    between them."""
    towards, seen = pure - ink, colours - ink
    mix = np.clip(seen @ towards / max(float(towards @ towards), 1e-9), 0.0, 1.0)
    return np.linalg.norm(seen - mix[:, None] * towards[None, :], axis=1)


#: A cell of a separate class near a removed letter, not in a thin part of
#: it, changes class only where its colour is clearly another's: at least
#: this many times closer to that class's mixes with the ink than to its own
#: class's, and at least this far (0-255 RGB distance) from its own class's
#: (:func:`letter_gaps`). Measured on Delft's building cells (offset / IoU
#: against the 10 digitised plots; no cell decided: +0.106 m / 0.957; thin
#: parts only: +0.094 / 0.956): ratio 2 -> +0.021 / 0.956, 3 -> +0.073,
#: 4 -> +0.087 / 0.956; the synthetic seeds' plots (registered): thin parts
#: only 0.971 / 0.983 / 0.977, ratio 2 or 4: 0.975 / 0.983 / 0.978
GAP_RATIO, GAP_DISTANCE = 4.0, 25.0


def letter_gaps(classes, image, removed, labels, width, nodata=0):
    """``classes`` with the cells between removed letters decided by colour.

    A street name printed in a narrow street between two plots leaves the
    paper between its letters a cell or two wide; the segmentation may
    merge those cells with the plots' fill and the classifier give them to
    the plots (a colour plane off by a cell does: issue 32's synthetic map).
    The refill then has no street left between the plots and joins them, or
    grows a plot out into the name. Each cell of the ``labels`` classes (the
    separate ones, e.g. buildings) next to a ``removed`` cell (8 neighbours:
    the paper between letters is) is compared with the classes' colours
    mixed with the removed objects' ink (:func:`_to_ink`; each class's colour and the ink: the
    medians of their cells, the classes' away from their edges): in a thin
    part of its class (:func:`thin_parts`, ``width`` cells: between letters)
    it takes the class that comes closest; elsewhere only a class it is
    clearly of (:data:`GAP_RATIO`, :data:`GAP_DISTANCE`). Not every cell
    near a letter by the nearest colour: on the Delft 1961 map, whose black
    outlines are centred on the plots' edges, an edge cell beside a street
    name is ink and paper as much as ink and fill, and deciding all of them
    so moved the building cells 0.66 m inwards (IoU 0.957 -> 0.917).
    ``image``: (rows, cols, bands) floats. The cells of a plot a label is
    printed over keep their class: their colour is the plot's.
    """
    classes = np.asarray(classes)
    removed = np.asarray(removed, dtype=bool)
    out = classes.copy()
    if not removed.any():
        return out
    valid = np.isfinite(image).all(axis=-1)
    base = np.where(removed, nodata, classes)
    near = ndimage.binary_dilation(removed, _EIGHT)
    rows, cols = np.nonzero(near & valid & np.isin(classes, list(labels)))
    names, colours = [], []
    for label in np.unique(base[valid]):
        core = ndimage.binary_erosion(base == label, _EIGHT) & valid
        if label != nodata and core.any():
            names.append(label)
            colours.append(np.median(image[core], axis=0))
    if not len(rows) or not names or not (removed & valid).any():
        return out
    names = np.asarray(names)
    ink = np.median(image[removed & valid], axis=0)
    seen = image[rows, cols]
    distance = np.stack([_to_ink(seen, ink, colour) for colour in colours], axis=1)
    best = distance.argmin(axis=1)
    closest = distance[np.arange(len(rows)), best]
    own = np.full(len(rows), np.inf)
    known = np.isin(classes[rows, cols], names)
    own[known] = distance[np.flatnonzero(known),
                          np.searchsorted(names, classes[rows, cols][known])]
    thin = thin_parts(base, width, nodata, hidden=removed, exact=labels)[rows, cols]
    clear = (own >= GAP_RATIO * closest) & (own >= GAP_DISTANCE)
    change = thin | clear
    out[rows[change], cols[change]] = names[best[change]]
    return out


#: The four axes along which a refilled cell is looked at from both sides
#: (:func:`outgrowths`), as (row, column) steps.
AXES = ((0, 1), (1, 0), (1, 1), (1, -1))


def _first_known(classes, known, rows, cols, step, nodata=0):
    """The class of the first ``known`` cell met from each cell (``rows``,
    ``cols``) going by ``step``; ``nodata`` where the map's edge comes first."""
    found = np.full(len(rows), nodata, dtype=classes.dtype)
    open_ = np.arange(len(rows))
    r, c = rows.copy(), cols.copy()
    while len(open_):
        r, c = r + step[0], c + step[1]
        inside = (r >= 0) & (r < classes.shape[0]) & (c >= 0) & (c < classes.shape[1])
        open_, r, c = open_[inside], r[inside], c[inside]
        hit = known[r, c]
        found[open_[hit]] = classes[r[hit], c[hit]]
        open_, r, c = open_[~hit], r[~hit], c[~hit]
    return found


def outgrowths(before, after, holes, label, nodata=0):
    """Refilled cells of ``label`` that grow its regions out into a hole.

    ``before`` holds the classes with the holes not filled yet, ``after``
    the filled result. A filled cell of ``label`` farther than one cell from
    the known cells of that class (:data:`OUTLINE`) is an outgrowth unless it lies *between*
    them: the first known cells on both sides of it, along a row, a column
    or a diagonal (:data:`AXES`), are of that class. A label printed over a
    plot, or across its edge, lies between the plot's cells and restores it;
    a street name printed beside a plot, against its outline, has the plot
    on one side only, and is given back to the street. The plot's own
    outline strokes (one cell to either side of the nearest-class line) are
    kept.
    """
    before = np.asarray(before)
    holes = np.asarray(holes, dtype=bool)
    known = ~holes & (before != nodata)
    own = known & (before == label)
    filled = holes & (np.asarray(after) == label)
    if not filled.any() or not own.any():
        return np.zeros(holes.shape, dtype=bool)
    far = filled & (ndimage.distance_transform_edt(~own) > OUTLINE)
    rows, cols = np.nonzero(far)
    between = np.zeros(len(rows), dtype=bool)
    for dr, dc in AXES:
        ahead = _first_known(before, known, rows, cols, (dr, dc), nodata)
        behind = _first_known(before, known, rows, cols, (-dr, -dc), nodata)
        between |= (ahead == label) & (behind == label)
    grown = np.zeros(holes.shape, dtype=bool)
    grown[rows[~between], cols[~between]] = True
    return grown


def remove_classes(classes, remove, window=None, iterations=None, min_cells=0, min_width=0,
                   separate=(), nodata=0, image=None, lines=None):
    """Remove classes (e.g. text, symbols), thin parts and tiny regions from a class raster.

    1. Holes: the cells of the ``remove`` labels, the thin parts of every
       other class (narrower than ``min_width`` cells, :func:`thin_parts`) and
       its regions smaller than ``min_cells`` cells (a minimum mapping unit,
       :func:`small_regions`), such as pieces of letters classified as
       something else. For the classes not in ``separate``, the removed
       cells may be of their class: a part is thin, or a region small, only
       if it still is with them (the street beside and between the letters
       of its name stays street, so that the name's refill does not join
       the plots on either side).
    2. The holes are refilled from their surroundings, each cell with the
       class of the nearest known cell (:func:`fill_from_nearest`, ties by
       the 3 x 3 neighbourhood); with
       ``iterations``, only as far as that many passes of the window would
       reach (``iterations`` x ``window // 2`` cells). The window is computed
       from the thickness of the removed letters and symbols
       (:func:`removed_thickness`) unless given.
    3. For the ``separate`` labels (e.g. buildings): where the fill of a
       hole joins two regions of such a class that were apart within
       :data:`FACING` windows (a street name printed across a narrow street
       between two plots, :func:`bridges`), or grows such a class out into
       the hole (a street name printed beside a plot, :func:`outgrowths`),
       that class is refused there and the hole is refilled from the
       nearest of the other classes around. When a removed class is drawn
       as lines (:func:`line_classes`: the blocks' outline strokes), every
       class is refused where it would join two of its regions so: with
       the strokes removed, nothing but the street name is left between two
       blocks across a narrow street, and the blocks are nearer to it than
       the street beyond the name.
    4. Regions left smaller than ``min_cells`` are refilled once more (the
       modal class of their 3 x 3 surroundings, :func:`fill_from_surroundings`).

    With the map's ``image`` (rows, cols, bands), the cells of the
    ``separate`` classes between the removed letters are first given the
    class of their colour (:func:`letter_gaps`). ``lines``: the removed
    labels drawn as lines, when decided for a whole map cut in tiles (else
    :func:`line_classes` of ``classes``).

    Returns ``(classes, window used)``; cells that could not be filled (no
    known cell within reach) become ``nodata``.
    """
    classes = np.asarray(classes)
    removed = np.isin(classes, list(remove)) if len(remove) else np.zeros(classes.shape, bool)
    if window is None:
        window = (window_for_thickness(removed_thickness(classes, remove, lines)) if len(remove)
                  else 3)
    if image is not None and len(separate):
        classes = letter_gaps(classes, image, removed, separate, min_width, nodata)
    base = np.where(removed, nodata, classes)
    holes = removed.copy()
    if min_width > 1:
        holes |= thin_parts(base, min_width, nodata, hidden=removed, exact=separate)
    if min_cells > 1:
        holes |= small_regions(base, min_cells, nodata, hidden=removed, exact=separate)
    holes &= classes != nodata
    before = np.where(holes, nodata, classes)
    reach = None if iterations is None else iterations * (window // 2)
    out, left = fill_from_nearest(classes, holes, reach=reach, nodata=nodata)
    kept_apart = list(separate)
    if (line_classes(classes, remove) if lines is None else lines):
        kept_apart += [label for label in np.unique(out[holes])
                       if label != nodata and label not in separate]
    for label in kept_apart:
        joined = bridges(before, out, holes, min_cells, FACING * window, nodata, labels=(label,))
        if label in separate:
            joined |= outgrowths(before, out, holes, label, nodata)
        if joined.any():
            refilled, still = fill_from_nearest(out, joined, reach=reach, nodata=nodata,
                                                exclude=(label,))
            refilled[still] = label
            out = refilled
    out[left] = nodata
    if min_cells > 1:
        small = small_regions(out, min_cells, nodata)
        if small.any():
            out, left = fill_from_surroundings(out, small, 3, iterations, nodata)
            out[left] = nodata
    return out, window
