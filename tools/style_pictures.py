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
maps' true blocks): v.histo.subdivide/v_histo_subdivide_drawn.png; and
r.histo.classify's picture of the monochrome map read as the shapes its lines
close (segmentation=lines): r.histo.classify/r_histo_classify_lines.png. No
GRASS needed; made from the synthetic maps only.
"""

import os
import sys

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "testsuite"))

import synthetic_map as sm  # noqa: E402

sys.path.insert(0, ROOT)
from reconstruction.classify import config as classify_config  # noqa: E402
from reconstruction.classify import lines, stage  # noqa: E402
from reconstruction.geom.grid import Grid  # noqa: E402
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


#: the colours of the classes of the monochrome map's shapes (the lines black)
SHAPE_COLOURS = {sm.BLOCK: (250, 232, 160), sm.BUILDING: (220, 70, 60),
                 sm.WATER: (70, 130, 220), sm.STREET: (255, 255, 255)}


def lines_picture(seed=1, size=600):
    """The monochrome map (a crop) beside the shapes r.histo.classify
    segmentation=lines reads and classifies (features spectral, fill, size;
    the map's training points without those on text), each shape filled with
    its class's colour (:data:`SHAPE_COLOURS`), lines and strokes of colour black."""
    smap = sm.generate(seed=seed, size=size, style="monochrome")
    bands = [smap.rgb[..., b].astype(float) for b in range(3)]
    reading = lines.read_ink(bands, smap.res)
    shapes = lines.line_shapes(reading)
    xy, labels = np.asarray(smap.training["xy"]), np.asarray(smap.training["label"])
    keep = labels != sm.TEXT
    training = stage.Training(labels=labels[keep], names=dict(smap.classes),
                              rows=((smap.north - xy[keep, 1]) / smap.res).astype(int),
                              cols=((xy[keep, 0] - smap.west) / smap.res).astype(int))
    grid = Grid(values=None, north=smap.north, west=smap.west, nsres=smap.res,
                ewres=smap.res, size=shapes.segments.shape)
    config = classify_config.ClassifyConfig(thresholds=(0.0,), minsizes=(0,),
                                            features=("spectral", "fill", "size"),
                                            segmentation="lines")
    classes = stage.classify_map(bands, [(0, shapes.segments)], lambda s: s, training, config,
                                 grid, reading=reading).classes
    read = np.zeros_like(smap.rgb)
    for label, colour in SHAPE_COLOURS.items():
        read[classes == label] = colour
    gap = np.full((CROP[0].stop - CROP[0].start, GAP, 3), 255, dtype=np.uint8)
    return np.concatenate([smap.rgb[CROP], gap, read[CROP]], axis=1)


def main(folder):
    os.makedirs(folder, exist_ok=True)
    for style in ("cadaster", "insurance"):
        path = os.path.join(folder, "style_{}.png".format(style))
        sm.write_png(path, picture(style), colours=COLOURS)
        print("{}: {} bytes".format(path, os.path.getsize(path)))
    path = os.path.join(ROOT, "r.histo.classify", "r_histo_classify_lines.png")
    sm.write_png(path, lines_picture(), colours=COLOURS)
    print("{}: {} bytes".format(path, os.path.getsize(path)))
    path = os.path.join(ROOT, "v.histo.subdivide", "v_histo_subdivide_drawn.png")
    sm.write_png(path, drawn_picture(), colours=COLOURS)
    print("{}: {} bytes".format(path, os.path.getsize(path)))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "docs", "img")))
