#!/usr/bin/env python3
"""Benchmark of v.histo.subdivide on the 616 Brussels 1924 plots.

Goal (issue 5): the core (``reconstruction.subdivide.stage.subdivide``) splits
all 616 plots (length 8,15, depth 23,30, area threshold 300, in EPSG:3857
map units as the thesis) in under 2 s. For scale: the thesis's own code needs
about 43 s for 615 of them and never finishes the 616th. Prints the median
core time of several runs, the footprint count (thesis: 15,015) and the
median end-to-end time of the module (GRASS import and export included).

Run inside a GRASS session with the suite on the module path, e.g. through
``testsuite/benchmarks/run_all.sh`` (``make bench``), or:

    grass --tmp-location EPSG:28992 --exec python3 testsuite/benchmarks/bench_v_histo_subdivide.py
"""

import argparse
import os
import statistics
import subprocess
import sys
import time

import grass.script as gs

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
PLOTS = os.path.join(ROOT, "..", "shared", "data", "bxls_1924", "thesis_output",
                     "final_plots_bxls_1924.shp")
GOAL = 2.0
OPTIONS = {"length": (8, 15), "depth": (23, 30), "area_threshold": 300}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=7, help="core runs (median)")
    parser.add_argument("--module-runs", type=int, default=3, help="module runs (median)")
    args = parser.parse_args()
    if not os.path.exists(PLOTS):
        print("skipped: reference data not found at '{}'".format(PLOTS))
        return 0
    if ROOT not in sys.path:
        sys.path.insert(0, ROOT)
    from reconstruction import grassio
    from reconstruction.subdivide import stage as subdivision

    gs.run_command("v.in.ogr", input=PLOTS, output="bxls", flags="o", quiet=True, overwrite=True)
    plots, columns = grassio.read_features("bxls")
    cats = columns["cat"]
    times = []
    for _ in range(args.runs):
        start = time.perf_counter()
        result = subdivision.subdivide(plots, cats, seed=1, **OPTIONS)
        times.append(time.perf_counter() - start)
    core = statistics.median(times)
    print("core: {} plots -> {} footprints (thesis 15015) in {:.2f} s median of {} runs "
          "(min {:.2f}, max {:.2f}); goal < {:.0f} s: {}".format(
              len(plots), len(result.geometries), core, args.runs, min(times), max(times), GOAL,
              "met" if core < GOAL else "NOT met"))
    walls = []
    for _ in range(args.module_runs):
        start = time.perf_counter()
        subprocess.run(["v.histo.subdivide", "input=bxls", "output=bxls_fp", "length=8,15",
                        "depth=23,30", "area_threshold=300", "seed=1", "--overwrite", "--quiet"],
                       check=True)
        walls.append(time.perf_counter() - start)
    print("module end to end (import, core, export with attribute table): {:.2f} s median of "
          "{} runs".format(statistics.median(walls), args.module_runs))
    return 0 if core < GOAL else 1


if __name__ == "__main__":
    sys.exit(main())
