#!/usr/bin/env python3
"""Fallbacks of ``roof=stepped`` on many plain rectangles (issue 33, item 6).

Builds the solids of ``--count`` rectangles (``testsuite/stepped_rectangles.py``,
the generator of the property test, drawn from ``--seed``) with a
crow-stepped gable each, as v.histo.lod2 builds them
(:func:`reconstruction.lod2.solids.build.build_solids`: roof, walls,
validation, fallback), and prints how many fell back to a gable and why,
with the fractional step count of the roof height (roof height / step
height) of the first few. A valid stepped facade exists on each of them:
the goal is 0. Needs no GRASS:

    python3 testsuite/benchmarks/bench_stepped_rectangles.py [--count 20000] [--seed 0]
"""

import argparse
import collections
import os
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, ROOT)
sys.path.insert(0, os.path.join(ROOT, "testsuite"))

import numpy as np  # noqa: E402

from stepped_rectangles import DRAWS, rectangles  # noqa: E402
from reconstruction.lod2 import outlines  # noqa: E402
from reconstruction.lod2.roofs.model import RoofConfig  # noqa: E402
from reconstruction.lod2.solids import build as solids  # noqa: E402

GOAL = 0


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--count", type=int, default=20000)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--show", type=int, default=10, help="failures to print one by one")
    args = parser.parse_args()
    uniforms = np.random.default_rng(args.seed).random((args.count, DRAWS))
    footprints, eaves, attic, roof_uniforms = rectangles(uniforms)
    rings = [outlines.clean_ring(xy)[0] for xy in footprints]
    B = len(rings)
    start = time.perf_counter()
    built = solids.build_solids(solids.Buildings(rings, np.zeros(B), eaves, attic,
                                                 ["stepped"] * B, roof_uniforms))
    seconds = time.perf_counter() - start
    failed = [f for f in built.log if f.kind == "stepped"]
    print("{} rectangles (seed {}), roof=stepped: {} fell back ({:.2%}), {} kept, "
          "{:.1f} s".format(B, args.seed, len(failed), len(failed) / max(B, 1),
                            len(built.kept), seconds))
    for reason, count in collections.Counter(f.reason for f in failed).most_common():
        print("  {:6d}  {}".format(count, reason))
    low, high = RoofConfig().step
    for f in failed[:args.show]:
        i = f.index
        step = low + (high - low) * roof_uniforms[i, 2]
        w, d = np.hypot(*(footprints[i][1:3] - footprints[i][:2]).T)
        print("  building {}: {:.2f} x {:.2f} m, eaves {:.2f} m, roof {:.2f} m, step {:.3f} m, "
              "fractional step count {:.2f}: {}".format(i, min(w, d), max(w, d), eaves[i],
                                                         attic[i], step, (attic[i] / step) % 1,
                                                         f.reason))
    return 0 if len(failed) <= GOAL else 1


if __name__ == "__main__":
    sys.exit(main())
