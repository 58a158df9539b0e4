#!/usr/bin/env python3
"""r.histo.classify on a window of the Paris 1925 atlas (../shared/data/maps/paris_1925),
untiled and in tiles (issue 51, item 4): the share of the cells classified alike,
overall and within 5 cells of a tile's edge, written as JSON.

Run inside a GRASS session of an EPSG:2154 location with the suite on the module
path (test_r_histo_classify_paris_tiles.py runs it): ``paris_tiles.py SCAN REPORT``.
Training points are derived at run time by simple rules on the scan (a stand-in
for a user's points by eye; none stored), 15 per class, seeded:

== ======== =====================================================================
1  hatching  ink cells (mean RGB < 110, not red) where ink covers 25-60 % of a 9 x 9 window
2  ink       ink cells where it covers less than 15 %: outlines, text
3  red       red lines and text (red - green > 50, mean < 200)
4  paper     paper (mean > 190, not red) at least 4 cells from ink
== ======== =====================================================================

``remove=2,3`` (the ink and the red lines).
"""

import json
import os
import sys

import numpy as np
from scipy import ndimage

import grass.script as gs

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, ROOT)
sys.path.insert(0, os.path.join(ROOT, "testsuite"))

from real_maps import draw_cells  # noqa: E402

from reconstruction import grassio  # noqa: E402
from reconstruction.classify import tiling  # noqa: E402

#: the window (first row, first column, side in cells) and the memory= of its tiles (4)
ROW0, COL0, SIDE, MEMORY = 750, 1500, 1500, 300
NAMES = {1: "hatching", 2: "ink", 3: "red", 4: "paper"}
EDGE = 5


def training_masks(rgb):
    """The cells each class's points are drawn from (the module docstring's rules)."""
    mean, red = rgb.mean(axis=-1), rgb[..., 0] - rgb[..., 1]
    ink = (mean < 110) & (red < 40)
    density = ndimage.uniform_filter(ink.astype(float), 9)
    far_from_ink = ndimage.distance_transform_edt(~ink) >= 4
    return {1: (density > 0.25) & (density < 0.6) & ink, 2: ink & (density < 0.15),
            3: (red > 50) & (mean < 200), 4: (mean > 190) & far_from_ink & (red < 25)}


def edge_cells(shape, tiles, width=EDGE):
    """The cells within ``width`` cells of a tile's edge inside the map."""
    rows, cols = shape
    edge = np.zeros(shape, dtype=bool)
    for t in tiles:
        for r in (t.row0, t.row1):
            if 0 < r < rows:
                edge[max(r - width, 0):r + width, t.col0:t.col1] = True
        for c in (t.col0, t.col1):
            if 0 < c < cols:
                edge[t.row0:t.row1, max(c - width, 0):c + width] = True
    return edge


def main(scan, report):
    gs.run_command("r.in.gdal", input=scan, output="paris", quiet=True)
    gs.run_command("g.region", raster="paris.red", quiet=True)
    r = gs.region()
    north, west = r["n"] - ROW0 * r["nsres"], r["w"] + COL0 * r["ewres"]
    gs.run_command("g.region", n=north, s=north - SIDE * r["nsres"], w=west,
                   e=west + SIDE * r["ewres"], quiet=True)
    bands = ["paris." + b for b in ("red", "green", "blue")]
    rgb = np.stack([np.nan_to_num(grassio.read_raster(b)) for b in bands], axis=-1)
    cells = draw_cells(training_masks(rgb), 15, 1)
    region = gs.region()
    xy = np.column_stack([region["w"] + (cells.cols + 0.5) * region["ewres"],
                          region["n"] - (cells.rows + 0.5) * region["nsres"]])
    grassio.write_points("training", xy, {"label": [int(v) for v in cells.labels],
                                          "class": [NAMES[int(v)] for v in cells.labels]})
    whole_memory = int(SIDE * SIDE * tiling.BYTES_PER_CELL / 2 ** 20) + 10
    out = {}
    for name, memory in (("whole", whole_memory), ("tiled", MEMORY)):
        gs.run_command("r.histo.classify", input=",".join(bands), training="training",
                       output=name, remove="2,3", seed=1, nprocs=2, memory=memory, quiet=True)
        out[name] = grassio.read_raster(name, dtype=np.int32)
    tiles = tiling.plan_tiles(SIDE, SIDE, tiling.tile_side(MEMORY), tiling.tile_overlap(3, 0))
    edge = edge_cells((SIDE, SIDE), tiles)
    same = out["whole"] == out["tiled"]
    with open(report, "w") as f:
        json.dump({"tiles": len(tiles), "agreement": float(same.mean()),
                   "edge_agreement": float(same[edge].mean()),
                   "other_agreement": float(same[~edge].mean())}, f)


if __name__ == "__main__":
    main(*sys.argv[1:3])
