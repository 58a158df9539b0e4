#!/usr/bin/env python3
"""The pictures of v.histo.generalize's manual page: 200 m x 200 m of the
synthetic map with the building class's cells outlined (before) and with the
generalised plots and the ground-truth points (after).

Run inside the GRASS session of the manual page's example (the synthetic
map written by testsuite/synthetic_map.py, classified, generalised):

    python3 tools/generalize_pictures.py CLASSES PLOTS v.histo.generalize

Made from the suite's synthetic map, never from the reference data.
"""

import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import shapely  # noqa: E402

import grass.script as gs  # noqa: E402

from reconstruction import grassio  # noqa: E402

#: the window shown (the manual page's caption names it)
WINDOW = {"n": 446440, "s": 446240, "w": 84100, "e": 84300}
PIXELS = 400


def cell_outlines(classes, label, west, north, res):
    """The outline of the cells of ``label`` (one polygon per connected area)."""
    rows, cols = np.nonzero(classes == label)
    boxes = shapely.box(west + cols * res, north - (rows + 1) * res,
                        west + (cols + 1) * res, north - rows * res)
    return shapely.union_all(boxes)


def draw_outline(ax, geom, colour, width):
    for part in getattr(geom, "geoms", [geom]):
        if part.is_empty or part.geom_type != "Polygon":
            continue
        for ring in (part.exterior, *part.interiors):
            ax.plot(*ring.xy, color=colour, linewidth=width)


def picture(path, rgb, shapes, points=None):
    fig = plt.figure(figsize=(PIXELS / 100.0, PIXELS / 100.0), dpi=100)
    ax = fig.add_axes([0, 0, 1, 1])
    ax.imshow(rgb, extent=(WINDOW["w"], WINDOW["e"], WINDOW["s"], WINDOW["n"]),
              interpolation="nearest")
    for geom, colour in shapes:
        draw_outline(ax, geom, colour, 1.5)
    if points is not None:
        ax.scatter(points[:, 0], points[:, 1], s=40, facecolor="#e8d44d", edgecolor="#555555",
                   zorder=3)
    ax.set_xlim(WINDOW["w"], WINDOW["e"])
    ax.set_ylim(WINDOW["s"], WINDOW["n"])
    ax.axis("off")
    fig.savefig(path, dpi=100)
    plt.close(fig)


def main(classes_name, plots_name, folder):
    env = os.environ.copy()
    env["GRASS_REGION"] = gs.region_env(res=1, **WINDOW)
    rgb = np.dstack([np.clip(grassio.read_raster("map." + band, np.float64, env), 0, 255)
                     for band in ("red", "green", "blue")]).astype(np.uint8)
    classes = grassio.read_raster(classes_name, np.float64, env)
    raw = cell_outlines(classes, 1, WINDOW["w"], WINDOW["n"], 1.0)
    plots, _ = grassio.read_features(plots_name, "area")
    window = shapely.box(WINDOW["w"], WINDOW["s"], WINDOW["e"], WINDOW["n"])
    plots = [p for p in plots if p is not None and p.intersects(window)]
    xy, _ = grassio.read_points("map_gt_points")
    inside = ((xy[:, 0] > WINDOW["w"]) & (xy[:, 0] < WINDOW["e"])
              & (xy[:, 1] > WINDOW["s"]) & (xy[:, 1] < WINDOW["n"]))
    picture(os.path.join(folder, "v_histo_generalize_before.png"), rgb, [(raw, "#d62728")])
    picture(os.path.join(folder, "v_histo_generalize_after.png"), rgb,
            [(p, "#1f3fbf") for p in plots], xy[inside])


if __name__ == "__main__":
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    main(*sys.argv[1:])
