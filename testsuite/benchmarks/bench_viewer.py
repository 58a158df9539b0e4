#!/usr/bin/env python3
"""Benchmark of the web viewer (v.histo.lod2 viewer=): page size and first frame.

Goals (issue 29): the page of the Brussels 1924 chain (``demo/brussels_1924.sh``:
17,235 buildings) loads and draws its first frame in under 5 s in headless
chromium on this 2-core machine, with software WebGL; the page of the Delft
1961 chain (``demo/delft_1961.sh``, with its map draped) stays under 5 MB.

Runs both chains (their ``city.html``), then opens each page ``--runs`` times
in a fresh headless chromium (testsuite/browser.py: offline, SwiftShader) and
prints the median wall time from opening the file to the page's first frame
(``histo.ready``) and the page's own figure (``histo.firstFrameMs``, from its
script's start), the file size and the buildings drawn. Needs
``../shared/data`` (skipped with a message without it).

    grass --tmp-location EPSG:28992 --exec python3 testsuite/benchmarks/bench_viewer.py
"""

import argparse
import os
import statistics
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path[:0] = [os.path.join(ROOT, "testsuite"), ROOT]

from browser import headless_page, missing  # noqa: E402
from chain_testing import run_chain  # noqa: E402

SHARED = os.path.join(ROOT, "..", "shared", "data")
CHAINS = (("Brussels 1924", "brussels_1924.sh", 3857, "bxls_1924"),
          ("Delft 1961", "delft_1961.sh", 28992, "delft_1961_subset"))
FIRST_FRAME_GOAL, SIZE_GOAL = 5.0, 5e6


def first_frame(path, runs):
    """(median seconds from opening ``path`` to its first frame, median of the page's own
    figure in seconds, buildings drawn) over ``runs`` fresh browsers."""
    walls, inside, drawn = [], [], None
    for _ in range(runs):
        with headless_page() as view:
            start = time.perf_counter()
            view.open(path)
            view.wait_ready("window.histo && window.histo.ready === true", timeout_ms=120_000)
            walls.append(time.perf_counter() - start)
            inside.append(view.page.evaluate("histo.firstFrameMs") / 1000)
            drawn = view.page.evaluate("histo.drawn()")
            if view.errors:
                raise AssertionError("errors in the page: {}".format(view.errors))
    return statistics.median(walls), statistics.median(inside), drawn


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--runs", type=int, default=3)
    args = parser.parse_args()
    problem = missing()
    if problem:
        print("skipped: " + problem)
        return 0
    with tempfile.TemporaryDirectory() as tmp:
        for name, script, epsg, folder in CHAINS:
            if not os.path.isdir(os.path.join(SHARED, folder)):
                print("{}: skipped, ../shared/data/{} is absent".format(name, folder))
                continue
            os.makedirs(os.path.join(tmp, folder, "grassdata"))
            run_chain(script, epsg, os.path.join(tmp, folder), SHARED)
            page = os.path.join(tmp, folder, "out", "city.html")
            wall, inside, drawn = first_frame(page, args.runs)
            size = os.path.getsize(page)
            print("{}: {:,} buildings drawn; city.html {:.2f} MB (goal < {:.0f} MB); first "
                  "frame {:.2f} s from opening (page's own {:.2f} s), median of {} (goal < "
                  "{:.0f} s); load {:.1f}".format(name, drawn, size / 1e6, SIZE_GOAL / 1e6,
                                                 wall, inside, args.runs, FIRST_FRAME_GOAL,
                                                 os.getloadavg()[0]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
