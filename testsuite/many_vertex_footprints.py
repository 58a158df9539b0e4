"""Footprints of many vertices, as cadastres and digitisations have them.

For the benchmark of v.histo.lod2 on large footprints
(``testsuite/benchmarks/bench_many_vertices.py``) and the property tests of
the solids: rings (n, 2) of ``n`` vertices in metres, counter-clockwise,
local coordinates. Digitised outlines have their vertices a few millimetres
to centimetres off the line they follow, so that cleaning (millimetre grid,
no vertex within 1 mm of its neighbours' line) keeps most of them; a smooth
convex curve of many vertices cannot keep them on the millimetre grid.

- :func:`round`: an elliptic convex outline (a smooth curve; cleaning keeps
  about 240 of its vertices at most);
- :func:`curved`: a 24 x 14 m block whose street facade is a digitised arc
  (a building on a curved street corner);
- :func:`digitised`: an L-shaped block whose every edge is digitised;
- :func:`wavy`: a digitised round concave outline (a rotunda with bays).
"""

import math

import numpy as np

SHAPES = ("round", "curved", "digitised", "wavy")


def _offsets(rng, count, noise):
    """``count`` offsets of 4 mm to ``noise`` m, either side."""
    return rng.uniform(0.004, noise, count) * rng.choice([-1.0, 1.0], count)


def round(n, a=12.0, b=8.0):
    """A convex ellipse of ``n`` vertices."""
    t = np.linspace(0.0, 2.0 * math.pi, n, endpoint=False)
    return np.column_stack([a * np.cos(t), b * np.sin(t)])


def curved(n, seed=0, width=24.0, depth=14.0, bulge=4.0, noise=0.03):
    """A block of three straight walls and a digitised arc of ``n - 2`` vertices."""
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 1.0, n - 2)
    x = width * (1.0 - t)
    y = depth + bulge * np.sin(math.pi * t)     # from (width, depth) back to (0, depth)
    y[1:-1] += _offsets(rng, n - 4, noise)      # x runs on: the outline stays simple
    arc = np.column_stack([x, y])
    return np.vstack([[[0.0, 0.0], [width, 0.0]], arc])


def digitised(n, seed=0, a=30.0, b=22.0, arm=9.0, noise=0.03):
    """An L-shaped block with ``n`` vertices, every edge digitised with
    vertices up to ``noise`` m off its line."""
    rng = np.random.default_rng(seed)
    corners = np.array([[0, 0], [a, 0], [a, arm], [arm, arm], [arm, b], [0, b]], dtype=float)
    lengths = np.hypot(*(np.roll(corners, -1, axis=0) - corners).T)
    extra = n - len(corners)
    per = np.floor(extra * lengths / lengths.sum()).astype(int)
    per[np.argsort(-lengths)[:extra - per.sum()]] += 1
    out = []
    for c0, c1, m in zip(corners, np.roll(corners, -1, axis=0), per):
        out.append(c0[None])
        if m:
            t = (np.arange(1, m + 1) / (m + 1))[:, None]
            d = c1 - c0
            nrm = np.array([-d[1], d[0]]) / np.hypot(*d)
            off = _offsets(rng, m, noise)
            out.append(c0 + t * d + off[:, None] * nrm)
    return np.vstack(out)


def wavy(n, seed=0, radius=12.0, waves=9, depth=0.12, noise=0.03):
    """A round concave outline of ``n`` digitised vertices: the radius waves
    ``waves`` times around by ``depth`` of itself."""
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 2.0 * math.pi, n, endpoint=False)
    r = radius * (1.0 + depth * np.sin(waves * t)) + _offsets(rng, n, noise)
    return np.column_stack([r * np.cos(t), r * np.sin(t)])      # star-shaped: simple


def footprint(shape, n, seed=0):
    """The footprint ``shape`` (one of :data:`SHAPES`) with ``n`` vertices."""
    if shape == "round":
        return round(n)
    if shape == "curved":
        return curved(n, seed)
    if shape == "digitised":
        return digitised(n, seed)
    return wavy(n, seed)
