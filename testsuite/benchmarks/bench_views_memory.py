#!/usr/bin/env python3
"""Benchmark of v.histo.lod2's memory with viewer= and gltf= on a CityJSONSeq output.

Goal (issue 49, item 14): ``format=cityjsonseq`` on 200,000 synthetic
footprints with both ``viewer=`` and ``gltf=`` under 1 GB peak RSS: the page
and the glTF are written from the model read back a few thousand features at
a time into compact arrays, never from one document of every building
(before: 50,000 footprints took 226 MB without them, 1.54 GB with viewer=,
1.68 GB with gltf=).

Measured on the 2-core machine of issue 49 (shared with other work): 50,000
footprints, median of 3: none 222 MB, viewer 339 MB, gltf 329 MB, both 341 MB
(57d2396: 222 / 1,509 / 1,719 / 1,712 MB, one run each); 200,000 footprints:
none 595 MB, viewer 784 MB, gltf 804 MB (one run each), both 802 MB (median
of 3, 802-803).

For each number of footprints, v.histo.lod2 runs with neither, with
``viewer=``, with ``gltf=`` and with both; each run is one process started
by a small Python process that prints the largest peak RSS (``ru_maxrss``)
of its descendants (``bench_memory.peak_run``). Prints the median of
``--runs`` runs, the spread and the wall time. The footprints are the
synthetic street rows of ``bench_v_histo_lod2.py``.

Run inside a GRASS session with the suite on the module path, e.g. through
``testsuite/benchmarks/run_all.sh`` (``make bench``), or:

    grass --tmp-location EPSG:28992 --exec python3 testsuite/benchmarks/bench_views_memory.py \\
        --footprints 50000 200000 --runs 3
"""

import argparse
import os
import statistics
import sys
import tempfile

import grass.script as gs

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_memory import GOAL_MB, peak_run  # noqa: E402
from bench_v_histo_lod2 import synthetic_geojson  # noqa: E402

OUTPUTS = (("none", ()), ("viewer", ("viewer",)), ("gltf", ("gltf",)),
           ("viewer + gltf", ("viewer", "gltf")))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--footprints", type=int, nargs="+", default=[50000, 200000])
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--only", nargs="+", choices=[label for label, _ in OUTPUTS],
                        help="run only these outputs")
    args = parser.parse_args()
    ok = True
    with tempfile.TemporaryDirectory() as tmp:
        files = {"viewer": os.path.join(tmp, "m.html"), "gltf": os.path.join(tmp, "m.glb")}
        for n in args.footprints:
            src = os.path.join(tmp, "synthetic.geojson")
            synthetic_geojson(src, n)
            gs.run_command("v.in.ogr", input=src, output="bench_views", flags="o", quiet=True,
                           overwrite=True)
            for label, outputs in OUTPUTS:
                if args.only and label not in args.only:
                    continue
                options = dict(input="bench_views", height="6.7,17", attic="2.6,6", year=1900,
                               seed=3, format="cityjsonseq",
                               output=os.path.join(tmp, "m.city.jsonl"),
                               **{key: files[key] for key in outputs})
                runs = [peak_run(**options) for _ in range(args.runs)]
                peaks = [peak for _wall, peak in runs]
                peak = statistics.median(peaks)
                line = ("v.histo.lod2 {:,} footprints, cityjsonseq, {}: peak RSS {:.0f} MB "
                        "(median of {}, {:.0f}-{:.0f}), {:.1f} s".format(
                            n, label, peak, len(runs), min(peaks), max(peaks),
                            statistics.median(wall for wall, _peak in runs)))
                if label == "viewer + gltf" and n >= 200000:
                    met = peak < GOAL_MB
                    ok &= met
                    line += "; goal < {} MB: {}".format(GOAL_MB, "met" if met else "NOT met")
                print(line, flush=True)
            gs.run_command("g.remove", flags="f", type="vector", name="bench_views", quiet=True)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
