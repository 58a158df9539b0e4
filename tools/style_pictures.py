#!/usr/bin/env python3
"""Pictures of the synthetic map's styles (testsuite/synthetic_styles.py) for the
README and the manuals: for each of the cadaster (Venice 1808) and the
fire-insurance map (Sanborn 1892), a crop of 300 x 300 pixels of the map
(seed 1, 600 x 600 pixels at the style's resolution) beside the same crop with
its parcels' truth outlined (a line one pixel wide just inside each parcel;
the insurance map's parcels are its buildings):

    python3 tools/style_pictures.py [FOLDER]

writes FOLDER/style_cadaster.png and FOLDER/style_insurance.png (default
FOLDER: docs/img), and v.histo.subdivide's picture of the footprints read
from the lines each map draws (the library's ``subdivide.drawn``, on the
maps' true blocks): v.histo.subdivide/v_histo_subdivide_drawn.png. No GRASS
needed; made from the synthetic maps only.
"""

import os
import sys

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "testsuite"))

import synthetic_map as sm  # noqa: E402

sys.path.insert(0, ROOT)
from reconstruction.subdivide import drawn  # noqa: E402

#: the crop shown (rows, columns of the 600 x 600 map) and the outline's colour
CROP = (slice(150, 450), slice(150, 450))
OUTLINE = {"cadaster": (0, 140, 255), "insurance": (200, 0, 170)}
GAP = 8  # white pixels between the two halves
COLOURS = 64


def picture(style, seed=1, size=600):
    """The picture of one style: the crop, and the crop with its parcels outlined."""
    smap = sm.generate(seed=seed, size=size, style=style)
    outlined = sm.outline_plots(smap, polygons=smap.parcels, width=smap.res,
                                colour=OUTLINE[style])
    left, right = smap.rgb[CROP], outlined[CROP]
    gap = np.full((left.shape[0], GAP, 3), 255, dtype=np.uint8)
    return np.concatenate([left, gap, right], axis=1)


def drawn_picture(seed=1, size=600):
    """The cadaster and the insurance map (crops), each with the footprints read from
    its lines outlined in green (as v.histo.subdivide map= -d reads them in the
    true blocks), side by side."""
    halves = []
    for style in ("cadaster", "insurance"):
        smap = sm.generate(seed=seed, size=size, style=style)
        found = drawn.read_divisions(smap.rgb, (smap.west, smap.east, smap.south, smap.north),
                                     smap.plots, list(range(1, len(smap.plots) + 1)),
                                     whole=True)
        parcels = [p for cat in sorted(found.parcels) for p in found.parcels[cat]]
        halves.append(sm.outline_plots(smap, polygons=parcels, width=smap.res,
                                       colour=(0, 170, 60))[CROP])
    gap = np.full((halves[0].shape[0], GAP, 3), 255, dtype=np.uint8)
    return np.concatenate([halves[0], gap, halves[1]], axis=1)


def main(folder):
    os.makedirs(folder, exist_ok=True)
    for style in ("cadaster", "insurance"):
        path = os.path.join(folder, "style_{}.png".format(style))
        sm.write_png(path, picture(style), colours=COLOURS)
        print("{}: {} bytes".format(path, os.path.getsize(path)))
    path = os.path.join(ROOT, "v.histo.subdivide", "v_histo_subdivide_drawn.png")
    sm.write_png(path, drawn_picture(), colours=COLOURS)
    print("{}: {} bytes".format(path, os.path.getsize(path)))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "docs", "img")))
