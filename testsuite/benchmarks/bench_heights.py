#!/usr/bin/env python3
"""Benchmark of the reference heights (reconstruction/lod2/heights.py, neighbourhood.py).

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
from reconstruction.lod2 import heights  # noqa: E402
from reconstruction.lod2 import neighbourhood  # noqa: E402
from reconstruction.geom.grid import Grid  # noqa: E402

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
    ok &= bench_module(args.runs, fps, pts)
    return 0 if ok else 1


def bench_module(runs, fps, pts):
    """Inside GRASS: v.histo.lod2 on the 4,000 footprints with ground_points= (the
    1,000,000 points) against the same run on a constant ground; the
    difference is what the ground costs through the module (goal < 3 s, checked
    on CPU time: the export of the points by v.out.ascii is most of it)."""
    import shutil
    import tempfile

    if "GISBASE" not in os.environ or shutil.which("v.histo.lod2") is None:
        print("SKIP v.histo.lod2 ground_points=: not in a GRASS session with the suite on "
              "the path")
        return True
    import json

    import grass.script as gs
    import shapely
    from histo_testing import timed_children

    x0, y0 = 85000.0, 446000.0
    with tempfile.TemporaryDirectory() as tmp:
        src = os.path.join(tmp, "fp.geojson")
        feats = [{"type": "Feature", "properties": {"h_building": 9.0, "h_attic": 3.0},
                  "geometry": json.loads(shapely.to_geojson(shapely.affinity.translate(
                      g, x0, y0)))} for g in fps]
        with open(src, "w") as f:
            json.dump({"type": "FeatureCollection", "features": feats}, f)
        gs.run_command("v.in.ogr", input=src, output="bench_h_fp", flags="o", quiet=True,
                       overwrite=True)
        txt = os.path.join(tmp, "pts.txt")
        np.savetxt(txt, pts + [x0, y0, 0.0], fmt="%.2f", delimiter="|")
        gs.run_command("v.in.ascii", input=txt, output="bench_h_pts", flags="ztb", z=3,
                       quiet=True, overwrite=True)
        out = os.path.join(tmp, "m.json")

        def module(**kw):
            return lambda: gs.run_command("v.histo.lod2", input="bench_h_fp", output=out,
                                          roof="flat", overwrite=True, quiet=True, **kw)

        with_w, with_c, _ = timed_children(runs, module(ground_points="bench_h_pts"))
        base_w, base_c, _ = timed_children(runs, module())
    gs.run_command("g.remove", flags="f", type="vector", name="bench_h_fp,bench_h_pts",
                   quiet=True)
    cost = with_w - base_w
    met = with_c - base_c < GOAL          # CPU time: the machine may be shared
    print("v.histo.lod2 ground_points= ({:,} points, {:,} footprints, roof=flat): median "
          "{:.2f} s wall, {:.2f} s CPU; with ground=: {:.2f} s wall, {:.2f} s CPU; the ground "
          "costs {:.2f} s wall, {:.2f} s CPU; goal < {:.0f} s (CPU): {}; load {}".format(
              len(pts), len(fps), with_w, with_c, base_w, base_c, cost, with_c - base_c, GOAL,
              "met" if met else "NOT met", " ".join("{:.2f}".format(v) for v in os.getloadavg())))
    return met


if __name__ == "__main__":
    sys.exit(main())
