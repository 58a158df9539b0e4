#!/usr/bin/env python3
"""Benchmark of r.histo.classify on the Delft 1961 subset, tuning included.

Goal (issue 15): the whole module on ``../shared/data/delft_1961_subset``
(488 x 613 cells, 36 training points) with the default options (4 thresholds
x 4 minimum sizes = 16 i.segment runs, grown once per threshold and reseeded
per minimum size) and only ``remove=2,6``, in under 15 s on the 2-core
machine; ``--exhaustive`` times flag -e (a full run per pair, as before). Prints the median wall time of
several runs and the median time of each stage (from the module's --verbose
timing line: segmentation and tuning, features and classification, removal,
output), so that what dominates is visible.

Run inside a GRASS session with the suite on the module path, e.g. through
``testsuite/benchmarks/run_all.sh`` (``make bench``), or:

    grass --tmp-location EPSG:28992 --exec python3 testsuite/benchmarks/bench_r_histo_classify.py
"""

import argparse
import os
import re
import statistics
import subprocess
import sys
import time

import resource

import grass.script as gs

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
DELFT = os.path.join(ROOT, "..", "shared", "data", "delft_1961_subset", "input")
GOAL = 15.0


def import_delft():
    gs.run_command("r.in.gdal", input=os.path.join(DELFT, "delft_1961.tif"), output="delft",
                   flags="o", quiet=True, overwrite=True)
    gs.run_command("v.in.ogr", input=os.path.join(DELFT, "training_points_delft_1961.shp"),
                   output="training", flags="o", quiet=True, overwrite=True)
    bands = sorted(gs.list_strings("raster", pattern="delft.*"))
    order = {"red": 0, "green": 1, "blue": 2, "1": 0, "2": 1, "3": 2}
    bands.sort(key=lambda n: order.get(n.split("@")[0].rsplit(".", 1)[-1], 9))
    gs.run_command("g.region", raster=bands[0])
    return ",".join(b.split("@")[0] for b in bands)


def _children_cpu():
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def run_once(inputs, nprocs, exhaustive=False):
    start = time.perf_counter()
    cpu = _children_cpu()
    proc = subprocess.run(
        ["r.histo.classify", "input=" + inputs, "training=training", "output=cls",
         "remove=2,6", "nprocs={}".format(nprocs), "seed=1", "--overwrite", "--verbose"]
        + (["-e"] if exhaustive else []),
        capture_output=True, text=True)
    wall = time.perf_counter() - start
    cpu = _children_cpu() - cpu
    if proc.returncode != 0:
        sys.exit("r.histo.classify failed:\n" + proc.stderr)
    match = re.search(r"Timing \(s\): (.*)", proc.stderr)
    stages = {}
    if match:
        for part in match.group(1).split(","):
            name, value = part.strip().rsplit(" ", 1)
            stages[name] = float(value)
    return wall, cpu, stages


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--nprocs", type=int, default=2)
    parser.add_argument("--exhaustive", action="store_true", help="flag -e: a full run per pair")
    args = parser.parse_args()
    if not os.path.isfile(os.path.join(DELFT, "delft_1961.tif")):
        print("skipped: reference data not found at '{}'".format(DELFT))
        return 0
    inputs = import_delft()
    walls, cpus, stages = [], [], {}
    load_before = os.getloadavg()[0]
    for _ in range(args.runs):
        wall, cpu, parts = run_once(inputs, args.nprocs, args.exhaustive)
        walls.append(wall)
        cpus.append(cpu)
        for key, value in parts.items():
            stages.setdefault(key, []).append(value)
    median = statistics.median(walls)
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    print("r.histo.classify{}, Delft 1961 subset, 16 parameter pairs, remove=2,6, nprocs={}: "
          "median {:.1f} s (runs {}) over {} runs, CPU {:.1f} s median (module and its tools) "
          "(goal < {:.0f} s: {}); load average {:.1f} before, {:.1f} after".format(
              " -e" if args.exhaustive else "", args.nprocs, median,
              " ".join("{:.1f}".format(w) for w in walls), len(walls), statistics.median(cpus),
              GOAL, "met" if median < GOAL else "NOT met", load_before, load))
    print("  stages (median s): " + ", ".join(
        "{} {:.1f}".format(k, statistics.median(v)) for k, v in stages.items()))
    return 0


if __name__ == "__main__":
    sys.exit(main())
