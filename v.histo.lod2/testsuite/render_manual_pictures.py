"""Render the pictures of the v.histo.lod2 manual from synthetic footprints.

    python3 v.histo.lod2/testsuite/render_manual_pictures.py v.histo.lod2

writes v_histo_lod2_roofs.png (one building per roof type),
v_histo_lod2_block.png (a synthetic street block, roof=auto) and
v_histo_lod2_family_<type>.png (one per roof type but flat: the row houses
of one plot of the synthetic map, testsuite/synthetic_map.py, seed 1,
with that roof forced, their street and shared edges found as the module
finds them), rendered off-screen with pyvista. Walls are light, roofs red,
as in the thesis's figures.
"""

import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(os.path.dirname(HERE)))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(HERE)), "testsuite"))

from reconstruction.lod2 import outlines  # noqa: E402
from reconstruction.lod2.roofs import plan as roofs  # noqa: E402
from reconstruction.lod2.solids import build as solids  # noqa: E402
from reconstruction.geom import solidset  # noqa: E402
from reconstruction.lod2.roofs.model import RoofConfig  # noqa: E402

COLOURS = {solidset.GROUND: (0.5, 0.5, 0.5), solidset.WALL: (0.93, 0.90, 0.84),
           solidset.ROOF: (0.72, 0.25, 0.18)}


def polydata(ss):
    import pyvista as pv

    verts = ss.vertices / 1000.0
    centre = verts.min(axis=0)
    sizes = np.diff(ss.face_start)
    faces = np.insert(ss.rings, ss.face_start[:-1], sizes)
    mesh = pv.PolyData(verts - centre, faces)
    sem = solidset.semantics(ss)
    mesh.cell_data["rgb"] = np.array([COLOURS[k] for k in sem])
    return mesh


def render(ss, path, size, elevation=25, azimuth=-60, zoom=1.0):
    import pyvista as pv

    pl = pv.Plotter(off_screen=True, window_size=size)
    pl.set_background("white")
    pl.add_mesh(polydata(ss), scalars="rgb", rgb=True, show_edges=True, edge_color=(0.25, 0.25, 0.25),
                line_width=1, lighting=True)
    a = np.radians(azimuth)
    e = np.radians(elevation)
    pl.view_vector((np.sin(a) * np.cos(e), -np.cos(a) * np.cos(e), np.sin(e)), viewup=(0, 0, 1))
    pl.camera.zoom(zoom)
    pl.screenshot(path)
    pl.close()


def roof_types_picture(path, per_row=7):
    """Every roof type on the same rectangle (street edge in front), in rows
    of ``per_row`` in :data:`~reconstruction.lod2.roofs.plan.ROOF_TYPES` order."""
    fps, kinds = [], list(roofs.ROOF_TYPES)
    for i, kind in enumerate(kinds):
        xy = np.array([[0, 0], [8, 0], [8, 14], [0, 14]], dtype=float) + \
            [(i % per_row) * 14.0, -(i // per_row) * 30.0]
        fps.append(outlines.clean_ring(xy)[0])
    n = len(fps)
    buildings = solids.Buildings(fps, np.zeros(n), np.full(n, 9.0), np.full(n, 4.5), kinds,
                                 np.full((n, 3), 0.5), street=[0] * n)
    built = solids.build_solids(buildings, RoofConfig(step=(0.6, 0.6)))
    ss, kept, got = built.solids, built.kept, built.types
    assert list(got) == kinds
    render(ss, path, (1100, 560), elevation=38, azimuth=-12, zoom=1.45)


def block_picture(path):
    rng = np.random.default_rng(7)
    fps = []
    x = 0.0
    while x < 60:                     # a row of narrow houses along a street
        w = rng.uniform(5, 9)
        d = rng.uniform(12, 17)
        fps.append(outlines.clean_ring(np.array([[x, 0], [x + w, 0], [x + w, d], [x, d]]))[0])
        x += w
    ell = np.array([[62, 0], [80, 0], [80, 22], [72, 22], [72, 8], [62, 8]], dtype=float)
    fps.append(outlines.clean_ring(ell)[0])
    fps.append(outlines.clean_ring(np.array([[85, 2], [97, 0], [99, 12], [91, 17], [84, 11]]))[0])
    n = len(fps)
    kinds = roofs.draw_roof_types([len(f) for f in fps], np.full(n, 1900), np.full(n, 4.0),
                                  rng.random(n))
    kinds[-2] = "gable"
    built = solids.build_solids(solids.Buildings(
        fps, np.zeros(n), rng.uniform(7, 12, n), rng.uniform(3, 5, n), kinds, rng.random((n, 3)),
        street=[0] * n))
    ss, kept, got = built.solids, built.kept, built.types
    render(ss, path, (900, 380), elevation=35, azimuth=-25, zoom=1.75)


def synthetic_row(seed=1, radius=30.0):
    """Footprints of the synthetic map (seed ``seed``): the row houses of the
    true plot with the most of them, within ``radius`` (m) of its corner
    house, with their street edges and shared edges as the module finds
    them: (rings, street, shared)."""
    import synthetic_map
    from reconstruction.lod2.street_edges import street_edges

    smap = synthetic_map.generate(seed=seed, size=600)
    current = smap.current
    by_plot = {}
    for k, (plot, kind) in enumerate(zip(current.plot, current.kind)):
        if kind == "standing" and plot > 0:
            by_plot.setdefault(plot, []).append(k)
    chosen = max(by_plot.values(), key=len)
    centres = np.array([current.polygons[k].centroid.coords[0] for k in chosen])
    corner = centres[np.argmin(centres.sum(axis=1))]
    rings = []
    for k in sorted(k for k, c in zip(chosen, centres) if np.hypot(*(c - corner)) < radius):
        xy = np.asarray(current.polygons[k].exterior.coords)[:-1]
        ring, why = outlines.clean_ring(xy)
        if ring is not None:
            rings.append(ring)
    edges = street_edges(rings)
    start = edges.edges.start
    shared = [edges.shared[start[r]:start[r + 1]] for r in range(len(rings))]
    return rings, [int(e) if e >= 0 else None for e in edges.edge], shared


def family_pictures(out):
    """One picture per roof type but flat: a row of the synthetic map's
    houses, all with that roof."""
    rings, street, shared = synthetic_row()
    n = len(rings)
    rng = np.random.default_rng(3)
    eaves, attic, u = rng.uniform(8, 11, n), rng.uniform(4, 6, n), rng.random((n, 3))
    for kind in roofs.ROOF_TYPES:
        if kind == "flat":
            continue
        built = solids.build_solids(solids.Buildings(
            rings, np.zeros(n), eaves, attic, [kind] * n, u, street=street, shared=shared))
        render(built.solids, os.path.join(out, "v_histo_lod2_family_{}.png".format(kind)),
               (480, 300), elevation=30, azimuth=-30, zoom=1.3)


if __name__ == "__main__":
    out = sys.argv[1] if len(sys.argv) > 1 else "."
    roof_types_picture(os.path.join(out, "v_histo_lod2_roofs.png"))
    block_picture(os.path.join(out, "v_histo_lod2_block.png"))
    family_pictures(out)
