#!/usr/bin/env python3
"""Benchmark of v.histo.generalize's fit step (issue 32): the synthetic map's
true plots, grown by 0.4 m (as cells would place them), fitted back onto the
outline strokes the map draws inside them.

Prints the median wall time of ``fitting.fit_outlines`` over several runs
and the mean IoU with the true plots before and after. No GRASS needed:

    python3 testsuite/benchmarks/bench_fit.py --runs 5
"""

import argparse
import os
import statistics
import sys
import time

import numpy as np
import shapely

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path[:0] = [os.path.dirname(HERE), os.path.dirname(os.path.dirname(HERE))]

from reconstruction.generalize import fitting  # noqa: E402
from reconstruction.geom.grid import MapImage  # noqa: E402
from synthetic_map import generate  # noqa: E402


def mean_iou(plots, truth):
    return float(np.mean([shapely.intersection(p, t).area / shapely.union(p, t).area
                          for p, t in zip(plots, truth)]))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()
    smap = generate(seed=args.seed, size=600)
    region = smap.region()
    image = MapImage(smap.rgb, (region["w"], region["e"], region["s"], region["n"]))
    truth = list(smap.plots)
    grown = [p.buffer(0.4, join_style="mitre") for p in truth]
    times = []
    for _ in range(args.runs):
        start = time.perf_counter()
        fit = fitting.fit_outlines(grown, image, "inside")
        times.append(time.perf_counter() - start)
    print("fit step: {} plots, {} of {} edges fitted; median {:.3f} s over {} runs (runs: {}); "
          "mean IoU with the true plots {:.3f} -> {:.3f}, stroke width {:.2f} m".format(
              len(truth), fit.fitted, fit.edges, statistics.median(times), len(times),
              ", ".join("{:.3f}".format(t) for t in times), mean_iou(grown, truth),
              mean_iou(fit.plots, truth), fit.stroke_width))
    return 0


if __name__ == "__main__":
    sys.exit(main())
