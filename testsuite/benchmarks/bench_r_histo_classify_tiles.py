#!/usr/bin/env python3
"""Benchmark of r.histo.classify on whole synthetic map sheets, in tiles.

Goal (issue 15): synthetic maps (``testsuite/synthetic_map.py``, seed 1,
1 m cells) of 600, 1000, 2000 and 4000 pixels a side (0.36 to 16
megapixels), default options (``memory=300`` MB per process, tiles when the
map does not fit one) and only ``remove=2,6``: time per megapixel flat from
0.36 to 16 megapixels, the 16-megapixel sheet in under 5 minutes on the
2-core machine, peak memory (all the module's processes together) under
4 GB; and on the largest map the tiled classification agrees with an
untiled one (``memory=`` large enough for one tile; the same tuning sample)
on at least 99 % of the cells where both have a class.

Prints one row per size: wall time, CPU time (the module and its tools),
seconds per megapixel, peak memory, the number of tiles and the module's
stage times; then the agreement. Run inside a GRASS session with the suite
on the module path (``make bench``), or:

    grass --tmp-location EPSG:28992 --exec python3 \\
        testsuite/benchmarks/bench_r_histo_classify_tiles.py --sizes 600,4000
"""

import argparse
import os
import re
import resource
import subprocess
import sys
import threading
import time

import numpy as np

import grass.script as gs

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "testsuite"))
sys.path.insert(0, ROOT)


def _tree_rss(pid):
    """Resident memory (bytes) of a process and all its descendants, from /proc."""
    parents = {}
    rss = {}
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        try:
            with open("/proc/{}/stat".format(entry)) as f:
                fields = f.read().rsplit(")", 1)[1].split()
            parents[int(entry)] = int(fields[1])
            rss[int(entry)] = int(fields[21]) * os.sysconf("SC_PAGE_SIZE")
        except (OSError, IndexError, ValueError):
            continue
    members, frontier = {pid}, [pid]
    while frontier:
        parent = frontier.pop()
        for child, ppid in parents.items():
            if ppid == parent and child not in members:
                members.add(child)
                frontier.append(child)
    return sum(rss.get(p, 0) for p in members)


def _children_cpu():
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def run(prefix, output, memory=None):
    """r.histo.classify on map ``prefix``: (wall s, CPU s, peak bytes, stages, tiles)."""
    args = ["r.histo.classify", "input={0}.red,{0}.green,{0}.blue".format(prefix),
            "training={}_training".format(prefix), "output=" + output, "remove=2,6",
            "nprocs=2", "seed=1", "--overwrite", "--verbose"]
    if memory:
        args.append("memory={}".format(memory))
    start, cpu = time.perf_counter(), _children_cpu()
    proc = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    peak = [0]

    def watch():
        while proc.poll() is None:
            peak[0] = max(peak[0], _tree_rss(proc.pid))
            time.sleep(0.5)

    watcher = threading.Thread(target=watch, daemon=True)
    watcher.start()
    _out, err = proc.communicate()
    watcher.join()
    wall, cpu = time.perf_counter() - start, _children_cpu() - cpu
    if proc.returncode != 0:
        sys.exit("r.histo.classify failed:\n" + err)
    timing = " ".join(err.split()).partition("Timing (s): ")[2]
    stages = {name: float(value) for name, value in re.findall(r"([a-z]+) (\d+\.\d)", timing)}
    tiles = re.search(r"segmenting (\d+) tiles", " ".join(err.split()))
    return wall, cpu, peak[0], stages, int(tiles.group(1)) if tiles else 1


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", default="600,1000,2000,4000")
    parser.add_argument("--no-untiled", action="store_true", help="skip the untiled comparison")
    parser.add_argument("--compare-only", action="store_true",
                        help="only the untiled run of the largest size, against its tiled "
                             "result of an earlier run in this mapset")
    args = parser.parse_args()
    from reconstruction import grassio
    from synthetic_map import generate, write_to_grass

    os.environ["GRASS_OVERWRITE"] = "1"
    os.environ.setdefault("GRASS_VERBOSE", "1")
    sizes = [int(s) for s in args.sizes.split(",")]
    print("load average before: {:.1f}".format(os.getloadavg()[0]), flush=True)
    rows = []
    for size in [] if args.compare_only else sizes:
        prefix = "m{}".format(size)
        if not gs.find_file(prefix + ".red", element="cell")["fullname"]:
            smap = generate(seed=1, size=size)
            write_to_grass(smap, prefix)
            del smap
        gs.run_command("g.region", raster=prefix + ".red", quiet=True)
        wall, cpu, peak, stages, tiles = run(prefix, "cls_" + prefix)
        mp = size * size / 1e6
        rows.append((size, mp, wall, cpu, peak, tiles, stages))
        print("{} x {} ({:.2f} MP): {} tiles, wall {:.0f} s ({:.1f} s/MP), CPU {:.0f} s "
              "({:.1f} s/MP), peak {:.2f} GB; stages {}; load {:.1f}".format(
                  size, size, mp, tiles, wall, wall / mp, cpu, cpu / mp, peak / 1e9,
                  ", ".join("{} {:.0f}".format(k, v) for k, v in stages.items()),
                  os.getloadavg()[0]), flush=True)
    largest = max(sizes)
    if not args.no_untiled:
        prefix = "m{}".format(largest)
        gs.run_command("g.region", raster=prefix + ".red", quiet=True)
        wall, cpu, peak, stages, tiles = run(prefix, "untiled_" + prefix, memory=6000)
        tiled = grassio.read_raster("cls_" + prefix, dtype=np.int32)
        whole = grassio.read_raster("untiled_" + prefix, dtype=np.int32)
        both = (tiled > 0) & (whole > 0)
        agreement = float((tiled[both] == whole[both]).mean())
        print("untiled {} x {}: {} tile, wall {:.0f} s, CPU {:.0f} s, peak {:.2f} GB; tiled and "
              "untiled agree on {:.2%} of {} cells (goal >= 99 %: {})".format(
                  largest, largest, tiles, wall, cpu, peak / 1e9, agreement, int(both.sum()),
                  "met" if agreement >= 0.99 else "NOT met"), flush=True)
    # the tuning sample costs the same at every size: the CPU time per megapixel added
    # (from the previous row) is what stays flat when the tiles scale
    print("\n| size | MP | tiles | wall s | s/MP | CPU s | CPU s/MP | CPU s per added MP | peak GB |")
    print("|---|---|---|---|---|---|---|---|---|")
    previous = None
    for size, mp, wall, cpu, peak, tiles, _stages in rows:
        added = "" if previous is None else "{:.1f}".format((cpu - previous[1]) / (mp - previous[0]))
        print("| {0} x {0} | {1:.2f} | {2} | {3:.0f} | {4:.1f} | {5:.0f} | {6:.1f} | {7} | {8:.2f} |"
              .format(size, mp, tiles, wall, wall / mp, cpu, cpu / mp, added, peak / 1e9))
        previous = (mp, cpu)
    print("load average after: {:.1f}".format(os.getloadavg()[0]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
