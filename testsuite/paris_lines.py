"""The Paris 1925 atlas read as the shapes its lines close (issue 51, items 1-2):
blocks and hatched buildings, each scored with the ICDAR panoptic quality.

The published ground truth outlines every closed shape but gives it no class.
The acceptance of issue 51 asks for blocks and hatched buildings apart, so a
shape's class is defined here, on the scan, independently of what the suite
reads (:func:`truth_classes`):

- **hatched**: at least :data:`HATCHED_SHARE` of its interior (the shape
  shrunk by two cells, off its outline) is darker than Otsu's threshold of
  the scan's grey (the mean of its bands) inside the content mask;
- **block**: less than :data:`PAPER_SHARE` of its interior dark (paper, a
  few letters), and not the street network;
- **street**: the largest shape (the open space of the streets);
- in between (gardens drawn with trees, shapes crowded with text): no class,
  scored in neither.

The training points are placed at random, seeded, as a user would place a
few by eye (:func:`training_points`): one in each of
:data:`POINTS` shapes of the two classes at least 2000 cells large, a few in
the street and as many on the drawn outlines (cells of the published edges
that are dark on the scan). Nothing read from ../shared is kept.

Run: ``python3 testsuite/paris_lines.py [--seed N] [--features ...]`` (the
venv's Python; reads ``../shared/data``).
"""

import argparse
import os
import sys
import time
from dataclasses import dataclass

import numpy as np
from scipy import ndimage

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path[:0] = [p for p in (HERE, os.path.dirname(HERE)) if p not in sys.path]

from paris_shapes import paris_files, read_band, read_paris_truth  # noqa: E402

from reconstruction.classify import config as classify_config  # noqa: E402
from reconstruction.classify import lines, stage  # noqa: E402
from reconstruction.generalize.assessment import icdar_panoptic_quality  # noqa: E402
from reconstruction.geom.grid import Grid  # noqa: E402
from reconstruction.geom.ink import grow, otsu  # noqa: E402

#: the scan's cell size (m), as the data's README gives it
CELL = 0.44
HATCHED_SHARE, PAPER_SHARE = 0.4, 0.15
#: training points: shapes of each class, and the street's and outlines' share of that
POINTS = 15
HATCHED, BLOCK, STREET, OUTLINE = 1, 2, 3, 4
NAMES = {HATCHED: "hatched", BLOCK: "block", STREET: "street", OUTLINE: "outline"}


@dataclass(frozen=True)
class ParisScores:
    """The panoptic quality of the blocks, of the hatched buildings and of all
    shapes (:class:`~reconstruction.generalize.assessment.PanopticQuality`),
    and the seconds the reading and classification took."""
    blocks: object
    hatched: object
    shapes: object
    seconds: float


def truth_classes(rgb, truth):
    """The class of each true shape (an array indexed by shape, 0: no class),
    by the definition of this module's docstring."""
    grey = rgb.mean(axis=-1)
    dark = grey <= otsu(grey[truth.mask])
    interior = np.where(ndimage.binary_erosion(truth.shapes > 0, iterations=2), truth.shapes, 0)
    n = truth.count + 1
    share = (np.bincount(interior.ravel(), weights=dark.ravel(), minlength=n)
             / np.maximum(np.bincount(interior.ravel(), minlength=n), 1))
    area = np.bincount(truth.shapes.ravel(), minlength=n)
    classes = np.zeros(n, int)
    classes[share >= HATCHED_SHARE] = HATCHED
    classes[share < PAPER_SHARE] = BLOCK
    classes[int(np.argmax(area[1:])) + 1] = STREET
    classes[0] = 0
    return classes


def training_points(rgb, edges, truth, classes, seed=1):
    """A :class:`~reconstruction.classify.stage.Training` as described above."""
    rng = np.random.default_rng(seed)
    interior = ndimage.binary_erosion(truth.shapes > 0, iterations=3)
    area = np.bincount(truth.shapes.ravel())
    cols = truth.shapes.shape[1]
    cells, labels = [], []
    for label, count in ((HATCHED, POINTS), (BLOCK, POINTS), (STREET, max(5, POINTS // 3))):
        shapes = np.flatnonzero((classes == label) & (area >= 2000))
        for k in rng.choice(shapes, size=min(count, len(shapes)), replace=False):
            cells.append(rng.choice(np.flatnonzero(((truth.shapes == k) & interior).ravel())))
            labels.append(label)
    grey = rgb.mean(axis=-1)
    drawn = np.flatnonzero(((edges > 0) & truth.mask & (grey <= otsu(grey[truth.mask]))).ravel())
    cells += list(rng.choice(drawn, size=POINTS, replace=False))
    labels += [OUTLINE] * POINTS
    cells = np.asarray(cells)
    return stage.Training(labels=np.asarray(labels), names=dict(NAMES), rows=cells // cols,
                          cols=cells % cols)


def read_and_score(files, seed=1, features=("spectral", "fill", "size")):
    """Read the Paris scan as shapes, classify them with the training points
    and score the blocks, the hatched buildings and all shapes: a
    :class:`ParisScores`."""
    truth = read_paris_truth(files)
    edges = read_band(files.edges)
    rgb = np.stack([read_band(files.scan, b) for b in range(3)], axis=-1).astype(float)
    classes = truth_classes(rgb, truth)
    training = training_points(rgb, edges, truth, classes, seed)
    bands = [np.where(truth.mask, rgb[..., b], np.nan) for b in range(3)]
    start = time.perf_counter()
    reading = lines.read_ink(bands, CELL)
    shapes = lines.line_shapes(reading)
    grid = Grid(values=None, north=0.0, west=0.0, nsres=CELL, ewres=CELL,
                size=truth.shapes.shape)
    config = classify_config.ClassifyConfig(thresholds=(0.0,), minsizes=(0,),
                                            features=tuple(features), segmentation="lines",
                                            seed=seed)
    result = stage.classify_map(bands, [(0, shapes.segments)], lambda s: s, training, config,
                                grid, reading=reading)
    seconds = time.perf_counter() - start
    own = (shapes.segments > 0) & (shapes.segments <= shapes.shapes)
    regions = grow(np.where(own, shapes.segments, 0), truth.mask)
    votes = np.stack([np.bincount(shapes.segments[own & (result.classes == c)],
                                  minlength=shapes.shapes + 1) for c in sorted(NAMES)])
    shape_class = np.asarray(sorted(NAMES))[np.argmax(votes, axis=0)]

    def of(label):
        predicted = np.where(shape_class[regions] == label, regions, 0)
        true = np.where(classes[truth.shapes] == label, truth.shapes, 0)
        return icdar_panoptic_quality(predicted, true, truth.mask)

    return ParisScores(blocks=of(BLOCK), hatched=of(HATCHED),
                       shapes=icdar_panoptic_quality(regions, truth.shapes, truth.mask),
                       seconds=seconds)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--shared", default=os.path.join(os.path.dirname(HERE), "..", "shared",
                                                         "data"))
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--features", default="spectral,fill,size")
    args = parser.parse_args(argv)
    files = paris_files(args.shared)
    if files.missing():
        sys.exit("ERROR: the Paris atlas is not in {}".format(args.shared))
    scores = read_and_score(files, args.seed, args.features.split(","))
    for name in ("blocks", "hatched", "shapes"):
        q = getattr(scores, name)
        print("{:8s} PQ {:.3f}  SQ {:.3f}  RQ {:.3f}  ({} predicted, {} true, {} matched)".format(
            name, q.pq, q.sq, q.rq, q.predicted, q.true, q.matched))
    print("read and classified in {:.0f} s".format(scores.seconds))


if __name__ == "__main__":
    main()
