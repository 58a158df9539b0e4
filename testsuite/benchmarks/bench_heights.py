#!/usr/bin/env python3
"""Benchmark of the reference heights (reconstruction/heights.py, neighbourhood.py).

Goal (issue 16): ground from 1,000,000 ground points for 4,000 footprints in
under 3 s. Also times the same from a DTM (0.5 m cells over the same area)
and the robust height rule on Delft 1880 (3,109 generated footprints from
674 aligned ones, when ``../shared/data`` is there). Prints the median wall
time (and CPU time) of several runs. Pure library: runs with or without GRASS

    python3 testsuite/benchmarks/bench_heights.py [--runs 5]
"""

import argparse
import os
import sys

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path[:0] = [ROOT, os.path.join(ROOT, "testsuite")]

from histo_testing import timed  # noqa: E402
from reconstruction import heights, neighbourhood  # noqa: E402
from reconstruction.grid import Grid  # noqa: E402

GOAL = 3.0
DELFT_1880 = os.path.join(ROOT, "..", "shared", "data", "delft_1880")


def site(n_footprints=4000, n_points=1_000_000, seed=0):
    """Footprints in street rows and ground points around them on a slope."""
    import shapely

    rng = np.random.default_rng(seed)
    per_row = 80
    i = np.arange(n_footprints)
    x0, y0 = (i % per_row) * 14.0, (i // per_row) * 20.0
    fps = shapely.box(x0, y0, x0 + 8 + rng.random(n_footprints) * 3,
                      y0 + 12 + rng.random(n_footprints) * 4)
    extent = np.array([per_row * 14.0, (n_footprints // per_row) * 20.0])
    xy = rng.random((n_points, 2)) * extent
    z = 1.0 + 0.005 * xy[:, 0] + 0.002 * xy[:, 1]
    return fps, np.column_stack([xy, z]), extent


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=5)
    args, _ = parser.parse_known_args()
    fps, pts, extent = site()
    wall, cpu, g = timed(args.runs, lambda: heights.ground_from_points(fps, pts))
    ok = wall < GOAL
    print("ground from {:,} points for {:,} footprints: median {:.2f} s wall, {:.2f} s CPU over "
          "{} runs; {} without ground; goal < {:.0f} s: {}".format(
              len(pts), len(fps), wall, cpu, args.runs, g.missing, GOAL,
              "met" if ok else "NOT met"))
    res = 0.5
    cols, rows = int(extent[0] / res), int(extent[1] / res)
    x = (np.arange(cols) + 0.5) * res
    y = extent[1] - (np.arange(rows) + 0.5) * res
    dtm = Grid(1.0 + 0.005 * x[None, :] + 0.002 * y[:, None], float(extent[1]), 0.0, res, res)
    wall, cpu, g = timed(args.runs, lambda: heights.ground_from_raster(fps, dtm))
    print("ground from a {}x{} DTM for {:,} footprints: median {:.2f} s wall, {:.2f} s CPU".format(
        rows, cols, len(fps), wall, cpu))
    if os.path.isdir(DELFT_1880):
        from shapefiles import read_shapefile

        geoms, columns = read_shapefile(os.path.join(DELFT_1880, "final_all_footprints.shp"))
        m = heights.measured_heights(columns)
        aligned = np.array([p is not None for p in columns["pand_id"]])
        e = np.where(aligned, m.eaves, np.nan)
        a = np.where(aligned, m.attic, np.nan)
        plot = np.array(columns["FeaID"], dtype=object)
        wall, cpu, r = timed(args.runs, lambda: neighbourhood.infer_heights(geoms, e, a, plot=plot))
        print("robust height rule on Delft 1880 ({:,} footprints, {} aligned): median {:.2f} s "
              "wall, {:.2f} s CPU".format(len(geoms), int(aligned.sum()), wall, cpu))
    else:
        print("SKIP Delft 1880: {} not found".format(DELFT_1880))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
