#!/usr/bin/env python3
"""Benchmark of v.histo.generalize: the Brussels 1924 plots re-generalised.

Goal (issue 4): the 616 building plots of the thesis's Brussels 1924 result
(``../shared/data/bxls_1924/thesis_output/final_plots_bxls_1924.shp``)
re-generalised by the module (alpha 12, distance 5, angle 180, with metrics
and report) in under 20 s. Prints the median wall time of several runs of
the whole module (reading, generalising, writing the map and the files).

Run inside a GRASS session with the suite on the module path, e.g. through
``testsuite/benchmarks/run_all.sh`` (``make bench``), or:

    grass --tmp-location EPSG:3857 --exec python3 testsuite/benchmarks/bench_v_histo_generalize.py
"""

import argparse
import os
import statistics
import sys
import tempfile
import time

import grass.script as gs

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SHP = os.path.join(ROOT, "..", "shared", "data", "bxls_1924", "thesis_output",
                   "final_plots_bxls_1924.shp")
GOAL = 20.0


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3)
    args = parser.parse_args()
    if not os.path.exists(SHP):
        print("SKIP: {} not found (reference data is only beside the checkout)".format(SHP))
        return 0
    gs.run_command("v.in.ogr", input=SHP, output="bench_bxls_plots", flags="o", quiet=True,
                   overwrite=True)
    areas = int(gs.vector_info_topo("bench_bxls_plots")["areas"])
    times = []
    with tempfile.TemporaryDirectory() as tmp:
        for run in range(args.runs):
            start = time.perf_counter()
            gs.run_command("v.histo.generalize", input="bench_bxls_plots",
                           output="bench_bxls_generalized", alpha=12, distance=5, angle=180,
                           metrics=os.path.join(tmp, "m.csv"), report=os.path.join(tmp, "r.json"),
                           overwrite=True, quiet=True)
            times.append(time.perf_counter() - start)
    plots = int(gs.vector_info_topo("bench_bxls_generalized")["areas"])
    median = statistics.median(times)
    print("v.histo.generalize: {} Brussels 1924 areas -> {} plots; median {:.2f} s over {} runs "
          "(runs: {}); goal < {:.0f} s: {}".format(
              areas, plots, median, len(times), ", ".join("{:.2f}".format(t) for t in times),
              GOAL, "met" if median < GOAL else "NOT met"))
    gs.run_command("g.remove", flags="f", type="vector",
                   name="bench_bxls_plots,bench_bxls_generalized", quiet=True)
    return 0 if median < GOAL else 1


if __name__ == "__main__":
    sys.exit(main())
