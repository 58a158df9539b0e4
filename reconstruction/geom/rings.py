"""Rings and ragged arrays: the index helpers every geometry file needs.

Many rings (or faces, or solids) travel as one flat array of entries, the
entries of each item one after the other, with the item sizes (``counts``)
or their ``offsets`` (``offsets[i]`` is where item ``i`` starts,
``offsets[-1]`` the total). A ring's entries are cyclic: the entry after its
last is its first.
"""

import numpy as np

_HASH = np.array([0x9E3779B97F4A7C15, 0xC2B2AE3D27D4EB4F, 0x165667B19E3779F9,
                  0x27D4EB2F165667C5], dtype=np.uint64)


def corners(rows):
    """The (lo, hi) corners of an (n, k) array of rows, column by column
    (numpy's reduction over axis 0 of a C-ordered array is six times slower)."""
    rows = np.asarray(rows)
    return (np.array([rows[:, k].min() for k in range(rows.shape[1])], dtype=rows.dtype),
            np.array([rows[:, k].max() for k in range(rows.shape[1])], dtype=rows.dtype))


def offsets(counts):
    """``(len(counts) + 1,)`` offsets of items of ``counts`` entries stored one after the other."""
    return np.concatenate([[0], np.cumsum(counts)])


def starts(counts):
    """Where each item of ``counts`` entries starts (:func:`offsets` without the total)."""
    return offsets(counts)[:-1]


def gather(first, counts):
    """Entry indices of items that start at ``first`` with ``counts`` entries,
    one item after the other."""
    return np.repeat(first - starts(counts), counts) + np.arange(int(np.sum(counts)))


def next_in_ring(offsets):
    """For every entry of rings given by their ``offsets``, the index of the
    next entry of its ring (the last entry's next is the first). Rings must
    not be empty (see :func:`ring_neighbours`)."""
    nxt = np.arange(int(offsets[-1])) + 1
    nxt[offsets[1:] - 1] = offsets[:-1]
    return nxt


def ring_neighbours(counts):
    """``(previous, next)``: for every entry of rings of ``counts`` entries,
    the index of the entry before and after it in its ring (empty rings allowed)."""
    counts = np.asarray(counts)
    rep = np.repeat(starts(counts), counts)
    pos = np.arange(len(rep)) - rep
    size = np.maximum(np.repeat(counts, counts), 1)
    return rep + (pos - 1) % size, rep + (pos + 1) % size


def following(a):
    """The vertices (rows) of one ring shifted by one: row ``i`` is ``a[i + 1]``, the last ``a[0]``
    (cheaper than ``np.roll`` on small arrays)."""
    return np.concatenate((a[1:], a[:1]))


def preceding(a):
    """The vertices (rows) of one ring shifted back by one: row ``i`` is ``a[i - 1]``."""
    return np.concatenate((a[-1:], a[:-1]))


def unique_rows(rows):
    """Distinct rows of an (n, k <= 4) integer array and the inverse index
    (as ``np.unique(rows, axis=0, return_inverse=True)``, but sorted by a
    hash of the rows, which is much faster; exact: hash collisions are
    detected and then fall back to a lexicographic sort)."""
    rows = np.asarray(rows)
    if len(rows) == 0:
        return rows.copy(), np.zeros(0, dtype=np.int64)
    k = rows.shape[1]
    with np.errstate(over="ignore"):
        h = (rows.astype(np.uint64) * _HASH[:k]).sum(axis=1, dtype=np.uint64)
        h ^= h >> np.uint64(29)
    order = np.argsort(h)
    hs = h[order]
    srt = rows[order]
    same_hash = hs[1:] == hs[:-1]
    same_row = np.all(srt[1:] == srt[:-1], axis=1)
    if np.any(same_hash & ~same_row):
        order = np.lexsort(rows.T[::-1])
        srt = rows[order]
        same_row = np.all(srt[1:] == srt[:-1], axis=1)
    new = np.empty(len(rows), dtype=bool)
    new[0] = True
    new[1:] = ~same_row
    group = np.cumsum(new) - 1
    inv = np.empty(len(rows), dtype=np.int64)
    inv[order] = group
    return srt[new], inv


def components(n, a, b):
    """Connected component label (smallest member) of n nodes joined by edges a-b,
    by min-label propagation (shells have a small diameter)."""
    labels = np.arange(n)
    while True:
        new = labels.copy()
        np.minimum.at(new, a, labels[b])
        np.minimum.at(new, b, labels[a])
        new = new[new]
        if np.array_equal(new, labels):
            return labels
        labels = new
