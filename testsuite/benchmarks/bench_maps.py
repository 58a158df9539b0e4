#!/usr/bin/env python3
"""Benchmark of r.histo.classify on a real map of another style: Venice 1808 sample 3.

Issue 50, item 6: the classification per megapixel on these maps no slower
than on the synthetic benchmark's. Times r.histo.classify on
``../shared/data/maps/venice_1808/venice_1808_sample3.tif`` (2242 x 1744
cells, 3.9 MP) with the acceptance's options (``remove=2,6 separate=1
features=lab,size``) and training points derived at run time from the published parcels
(testsuite/real_maps.py: 15 per class, seed 1; none stored); prints the
median wall time of several runs (3 by default) in seconds per megapixel.
``--synthetic SIZE`` also times the synthetic map of SIZE x SIZE cells as
testsuite/benchmarks/bench_r_histo_classify_tiles.py does (``remove=2,6``;
2000: 4 MP, about Venice's size), the same number of runs, for the
comparison. Prints "skipped" naming the missing path without the shared data.

Run inside a GRASS session with the suite on the module path (``make
bench``), or:

    grass --tmp-location EPSG:32633 --exec python3 testsuite/benchmarks/bench_maps.py \\
        --runs 3 --synthetic 2000
"""

import argparse
import os
import statistics
import sys

import grass.script as gs

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
for _path in (ROOT, os.path.join(ROOT, "testsuite"), os.path.dirname(os.path.abspath(__file__))):
    if _path not in sys.path:
        sys.path.insert(0, _path)

import maps_chain  # noqa: E402
from real_maps import venice_training_cells  # noqa: E402


def venice_seconds(runs):
    """Wall seconds of each run of the classification on Venice sample 3, and its MP."""
    data = maps_chain.MAPS
    bands = maps_chain.import_bands(os.path.join(data, maps_chain.VENICE_SCAN), "venice")
    truth = maps_chain.import_bands(os.path.join(data, maps_chain.VENICE_TRUTH), "truth")
    gs.run_command("g.region", raster=bands[0], quiet=True)
    rgb = maps_chain.read_stack(bands[:3])
    cells = venice_training_cells(rgb, maps_chain.read_stack(truth[:1])[..., 0])
    training = maps_chain.write_training(cells)
    seconds = [maps_chain.classify(bands, training, maps_chain.CLASSIFY["venice"])[0]
               for _ in range(runs)]
    return seconds, rgb.shape[0] * rgb.shape[1] / 1e6


def synthetic_seconds(size, runs):
    """Wall seconds of each run on the synthetic map of ``size`` cells a side, and its MP."""
    from bench_r_histo_classify_tiles import run
    from synthetic_map import generate, write_to_grass

    prefix = "m{}".format(size)
    write_to_grass(generate(seed=1, size=size), prefix)
    gs.run_command("g.region", raster=prefix + ".red", quiet=True)
    return [run(prefix, "cls_" + prefix)[0] for _ in range(runs)], size * size / 1e6


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--synthetic", type=int, metavar="SIZE",
                        help="also the synthetic map of SIZE cells a side (e.g. 2000)")
    args = parser.parse_args()
    problem = maps_chain.missing(os.path.join(maps_chain.MAPS, maps_chain.VENICE_SCAN))
    if problem:
        print("skipped: " + problem)
        return 0
    os.environ["GRASS_OVERWRITE"] = "1"
    load = os.getloadavg()[0]
    rows = [("Venice 1808 sample 3, remove=2,6 separate=1 features=lab,size",)
            + venice_seconds(args.runs)]
    if args.synthetic:
        rows.append(("synthetic {0} x {0}, remove=2,6".format(args.synthetic),)
                    + synthetic_seconds(args.synthetic, args.runs))
    for name, seconds, mp in rows:
        median = statistics.median(seconds)
        print("r.histo.classify, {}: {:.2f} MP, median {:.0f} s over {} runs ({}), {:.1f} s per "
              "MP".format(name, mp, median, len(seconds),
                          " ".join("{:.0f}".format(s) for s in seconds), median / mp))
    print("load average {:.1f} before, {:.1f} after".format(load, os.getloadavg()[0]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
