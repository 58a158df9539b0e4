#!/usr/bin/env python3
"""Benchmark of the chain scripts: demo/delft_1961.sh and demo/brussels_1924.sh, stage by stage.

Runs each script ``--runs`` times (default 3), each time in a fresh
temporary GRASS location (EPSG:28992 for Delft, EPSG:3857 for Brussels),
and prints the median wall time of every stage (from the script's
times.txt), of the stages' total (map to CityJSON and PNG; issue 18's goal
for Delft: under 60 s on the 2-core machine) and of the whole script (its
report included), the median CPU time of the script's processes (user +
system of all children) and the load average (``uptime``) before and after;
the thesis's figures beside: about 4 h for Delft 1982 and about 15 h for the
4,481 buildings of Brussels 1700 (issue 18). Skips a script whose data is
not in ../shared/data.

    python3 testsuite/benchmarks/bench_chain.py [--runs N] [--only delft|brussels]

Needs GRASS and the staged suite (dist/, or $HISTO_DIST); it makes its own
locations, so it runs inside a GRASS session (``make bench``) or outside.
"""

import argparse
import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
DATA = os.path.join(ROOT, "..", "shared", "data")
for _path in (os.path.join(ROOT, "testsuite"), os.path.join(ROOT, "demo")):
    if _path not in sys.path:
        sys.path.insert(0, _path)

#: name, script, EPSG code of its location, data folder, the thesis's figure
CHAINS = (
    ("delft", "delft_1961.sh", 28992, "delft_1961_subset",
     "thesis: about 4 h for Delft 1982 (the complete workflow)"),
    ("brussels", "brussels_1924.sh", 3857, "bxls_1924",
     "thesis: about 15 h for the 4,481 buildings of Brussels 1700"),
)
#: issue 18: the whole Delft chain, map to CityJSON and PNG, in under 60 s
DELFT_GOAL = 60.0


def children_cpu():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def uptime():
    return subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()


def run_once(script, epsg):
    """One run in a fresh location: ({stage: s}, script wall s, CPU s)."""
    from chain_report import stage_seconds
    from chain_testing import run_chain

    folder = tempfile.mkdtemp(prefix="bench_chain_")
    try:
        wall, cpu = time.perf_counter(), children_cpu()
        run_chain(script, epsg, folder, DATA)
        wall, cpu = time.perf_counter() - wall, children_cpu() - cpu
        return stage_seconds(os.path.join(folder, "out")), wall, cpu
    finally:
        shutil.rmtree(folder, ignore_errors=True)


def bench(name, script, epsg, runs, thesis):
    print("== demo/{}: {} runs, each in a fresh EPSG:{} location".format(script, runs, epsg))
    print("load before: " + uptime())
    stages, walls, cpus = [], [], []
    for i in range(runs):
        seconds, wall, cpu = run_once(script, epsg)
        stages.append(seconds)
        walls.append(wall)
        cpus.append(cpu)
        print("run {}: stages {:.1f} s, script {:.1f} s wall, {:.1f} s CPU".format(
            i + 1, sum(seconds.values()), wall, cpu))
    print("load after:  " + uptime())
    print("{:<12} {:>9} {:>9} {:>9}".format("stage", "median s", "min s", "max s"))
    for stage in stages[0]:
        values = [s[stage] for s in stages]
        print("{:<12} {:9.1f} {:9.1f} {:9.1f}".format(stage, statistics.median(values),
                                                     min(values), max(values)))
    totals = [sum(s.values()) for s in stages]
    print("{:<12} {:9.1f} {:9.1f} {:9.1f}".format("total", statistics.median(totals),
                                                 min(totals), max(totals)))
    print("script (with its report): {:.1f} s wall, {:.1f} s CPU (medians); {}".format(
        statistics.median(walls), statistics.median(cpus), thesis))
    if name == "delft":
        met = statistics.median(totals) < DELFT_GOAL
        print("goal: the chain in under {:.0f} s: {}".format(DELFT_GOAL,
                                                            "met" if met else "NOT met"))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3, help="runs of each script (median)")
    parser.add_argument("--only", choices=[c[0] for c in CHAINS], help="one of the chains")
    args = parser.parse_args()
    for name, script, epsg, folder, thesis in CHAINS:
        if args.only and name != args.only:
            continue
        if not os.path.isdir(os.path.join(DATA, folder)):
            print("== demo/{}: skipped, '{}' not found".format(script, os.path.join(DATA, folder)))
            continue
        bench(name, script, epsg, args.runs, thesis)
    return 0


if __name__ == "__main__":
    sys.exit(main())
