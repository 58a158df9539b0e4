"""Render the v.histo.lod2 manual's picture of street edges chosen on a block.

    python3 tools/street_edges_picture.py v.histo.lod2

writes v_histo_lod2_street_edges.png: a made-up street block (two rows of
houses back to back, streets all round; no real data) in plan, with the
shared edges grey and each footprint's street edge red, labelled with the
case that chose it (1 one unshared edge, 2 from a neighbour, 3 vote, 4
shortest), beside the buildings v.histo.lod2's library builds on them
(gable ends and stepped facades on the street edges; a shared back gets a
hip at the long faces' pitch). Needs matplotlib and pyvista (off-screen).
"""

import os
import sys

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path[:0] = [ROOT, os.path.join(ROOT, "v.histo.lod2", "testsuite")]

from reconstruction.lod2 import stage as lod2  # noqa: E402
from reconstruction.lod2 import inputs as lod2_inputs  # noqa: E402
from render_manual_pictures import render  # noqa: E402


def block(seed=3):
    """Footprints of the block: a south row and a north row meeting at their backs."""
    import shapely

    rng = np.random.default_rng(seed)
    fps = []
    for row, (y0, y1) in enumerate(((0.0, 15.0), (15.0, 29.0))):
        x = 0.0
        while x < 44.0:
            w = min(rng.uniform(5.5, 8.5), 50.0 - x)
            fps.append(shapely.box(x, y0, x + w, y1))
            x += w
    return fps


def build(fps, seed=3):
    rng = np.random.default_rng(seed)
    n = len(fps)
    kinds = np.array(["gable", "stepped", "hip", "gable", "stepped", "mansard"] * n)[:n]
    heights = lod2.Heights(rng.uniform(7, 10, n), rng.uniform(4, 5.5, n), 0.0)
    requests = lod2.RoofRequests(kinds.astype(object), np.full(n, 1880.0))
    prepared = lod2.prepare(lod2.Footprints(fps), heights, requests, lod2.Lod2Config(seed=seed))
    prepared, edges = lod2_inputs.with_street_edges(prepared)
    return prepared, edges, lod2.build(prepared)


def plan(ax, prepared, edges):
    rings = prepared.buildings.footprints
    e = edges.edges
    for r, ring in enumerate(rings):
        closed = np.vstack([ring, ring[:1]])
        ax.fill(closed[:, 0], closed[:, 1], color=(0.93, 0.90, 0.84), zorder=1)
    for k in range(len(e.a)):
        colour, width = ((0.55, 0.55, 0.55), 1.0) if edges.shared[k] else ((0.2, 0.2, 0.2), 1.0)
        ax.plot([e.a[k, 0], e.b[k, 0]], [e.a[k, 1], e.b[k, 1]], color=colour, lw=width, zorder=2)
    for r, ring in enumerate(rings):
        k = edges.edge[r]
        if k < 0:
            continue
        a, b = ring[k], ring[(k + 1) % len(ring)]
        ax.plot([a[0], b[0]], [a[1], b[1]], color=(0.80, 0.1, 0.1), lw=4, zorder=3)
        mid = 0.5 * (a + b)
        inward = np.array([-(b - a)[1], (b - a)[0]]) / np.hypot(*(b - a))
        p = mid + 1.6 * inward
        ax.text(p[0], p[1], str(int(edges.case[r])), ha="center", va="center", fontsize=9,
                zorder=4)
    ax.set_aspect("equal")
    ax.set_axis_off()
    ax.set_title("street edges (red) and the case that chose each", fontsize=10)


def main(out="."):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    prepared, edges, result = build(block())
    shot = os.path.join(out, ".street_edges_3d.png")
    render(result.solids, shot, (700, 500), elevation=38, azimuth=-20, zoom=1.5)
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.2),
                                      gridspec_kw={"width_ratios": [1, 1.25]})
    plan(left, prepared, edges)
    right.imshow(plt.imread(shot))
    right.set_axis_off()
    right.set_title("the buildings: ends on the street edges", fontsize=10)
    fig.tight_layout()
    path = os.path.join(out, "v_histo_lod2_street_edges.png")
    fig.savefig(path, dpi=90)
    os.remove(shot)
    print(path, np.bincount(edges.case, minlength=6).tolist(), result.roof_counts())


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else ".")
