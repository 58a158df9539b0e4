#!/usr/bin/env python3
"""Benchmark of v.histo.lod2: buildings per second, end to end.

Goal (issue 6): at least 5,000 buildings per second end to end (reading the
footprints from GRASS, building the solids, writing the CityJSON file) on
the thesis's Brussels 1924 footprints (3,706, with their inferred heights,
``../shared/data/bxls_1924/thesis_output/final_all_footprints.shp``) and on
a larger synthetic set (rectangles, trapezoids, L shapes and pentagons in
street rows, heights drawn from the Brussels ranges, roof=auto). Prints the
median wall time of several runs of the whole module and the rate, with the
median CPU time of the module and its child processes and the load average
(the machine may be shared: wall times are only as good as the load).

Run inside a GRASS session with the suite on the module path, e.g. through
``testsuite/benchmarks/run_all.sh`` (``make bench``), or:

    grass --tmp-location EPSG:28992 --exec python3 testsuite/benchmarks/bench_v_histo_lod2.py
"""

import argparse
import json
import os
import resource
import statistics
import sys
import tempfile
import time

import numpy as np

import grass.script as gs

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SHP = os.path.join(ROOT, "..", "shared", "data", "bxls_1924", "thesis_output",
                   "final_all_footprints.shp")
BXL_COLUMNS = ("cat,idx,feaid,g00,g01,g02,g03,g04,g05,buffer_val,nr_ground,h_building,"
               "h_attic,roof_025,roof_099,bouwjaar")
GOAL = 5000.0


def synthetic_geojson(path, n, seed=11):
    """n separate footprints in street rows (EPSG:28992 coordinates)."""
    rng = np.random.default_rng(seed)
    per_row = 200
    feats = []
    for i in range(n):
        x0 = 80000.0 + (i % per_row) * 25.0
        y0 = 440000.0 + (i // per_row) * 30.0
        w, d = rng.uniform(5, 9), rng.uniform(10, 18)
        k = i % 10
        if k < 6:
            xy = [[0, 0], [w, 0], [w, d], [0, d]]
        elif k < 8:
            xy = [[0, 0], [w, rng.uniform(-0.8, 0.8)], [w + rng.uniform(-0.8, 0.8), d], [0, d]]
        elif k < 9:
            xy = [[0, 0], [d, 0], [d, w / 2], [w / 2, w / 2], [w / 2, d], [0, d]]
            xy = [[x * 0.9, y * 0.9] for x, y in xy]
        else:
            xy = [[0, 0], [w, 0], [w + 2, d / 2], [w, d], [0, d]]
        ring = [[round(x0 + x, 3), round(y0 + y, 3)] for x, y in xy]
        ring.append(ring[0])
        feats.append({"type": "Feature", "properties": {"plot": i // 4},
                      "geometry": {"type": "Polygon", "coordinates": [ring]}})
    with open(path, "w") as f:
        json.dump({"type": "FeatureCollection", "features": feats}, f)


def children_cpu():
    """CPU time (user + system, s) of the finished child processes so far."""
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def median_run(runs, **kwargs):
    """(median wall time, wall times, median CPU time of the module and its
    children) of ``runs`` runs of v.histo.lod2."""
    times, cpu = [], []
    for _ in range(runs):
        start, cpu0 = time.perf_counter(), children_cpu()
        gs.run_command("v.histo.lod2", overwrite=True, quiet=True, **kwargs)
        times.append(time.perf_counter() - start)
        cpu.append(children_cpu() - cpu0)
    return statistics.median(times), times, statistics.median(cpu)


def report(label, n, median, times, cpu):
    rate = n / median
    print("v.histo.lod2 {}: {} buildings; median {:.2f} s over {} runs (runs: {}) = {:.0f} "
          "buildings/s (median CPU {:.2f} s = {:.0f} buildings per CPU s; load {:.2f}); "
          "goal >= {:.0f}/s: {}".format(
              label, n, median, len(times), ", ".join("{:.2f}".format(t) for t in times), rate,
              cpu, n / max(cpu, 1e-9), os.getloadavg()[0], GOAL,
              "met" if rate >= GOAL else "NOT met"))
    return rate >= GOAL


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--synthetic", type=int, default=40000,
                        help="number of synthetic footprints (default 40000; 0: Brussels only)")
    args = parser.parse_args()
    ok = True
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "model.city.json")
        if os.path.exists(SHP):
            gs.run_command("v.in.ogr", input=SHP, output="bench_lod2_bxl", columns=BXL_COLUMNS,
                           flags="o", quiet=True, overwrite=True)
            median, times, cpu = median_run(args.runs, input="bench_lod2_bxl", output=out,
                                            ground_column="g02", year=1924, crs=31370)
            with open(out) as f:
                n = len(json.load(f)["CityObjects"])
            ok &= report("Brussels 1924 footprints", n, median, times, cpu)
            gs.run_command("g.remove", flags="f", type="vector", name="bench_lod2_bxl",
                           quiet=True)
        else:
            print("SKIP Brussels: {} not found (reference data is only beside the "
                  "checkout)".format(SHP))
        if args.synthetic <= 0:
            return 0 if ok else 1
        src = os.path.join(tmp, "synthetic.geojson")
        synthetic_geojson(src, args.synthetic)
        gs.run_command("v.in.ogr", input=src, output="bench_lod2_syn", flags="o", quiet=True,
                       overwrite=True)
        median, times, cpu = median_run(args.runs, input="bench_lod2_syn", output=out,
                                        height="6.7,17", attic="2.6,6", year=1900, seed=3)
        with open(out) as f:
            n = len(json.load(f)["CityObjects"])
        ok &= report("synthetic footprints", n, median, times, cpu)
        median, times, cpu = median_run(args.runs, input="bench_lod2_syn", output=out,
                                        height="6.7,17", attic="2.6,6", year=1900, seed=3,
                                        nprocs=2)
        report("synthetic footprints, nprocs=2", n, median, times, cpu)
        gs.run_command("g.remove", flags="f", type="vector", name="bench_lod2_syn", quiet=True)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
