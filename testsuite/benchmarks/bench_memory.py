#!/usr/bin/env python3
"""Benchmark of v.histo.lod2's memory: peak RSS per format, with and without a picture.

Goal (issue 33, item 9): ``format=cityjsonseq`` on 200,000 synthetic
footprints under 1 GB peak RSS (the model built and written a step of
buildings at a time); ``render=`` capped (the picture draws at most
``reconstruction.lod2.render.MAX_DRAWN`` buildings); the single-file
CityJSON's peak measured and given per building (one document: every solid
is held until it is written).

Each run is one v.histo.lod2 started by a small Python process that prints
the largest peak RSS (``ru_maxrss``) of its descendants: the module and the
processes it starts (v.out.ogr, the forked builders of nprocs=). The
footprints are the synthetic street rows of ``bench_v_histo_lod2.py``.
Memory is the same run to run; the wall time of each run is printed too.

Run inside a GRASS session with the suite on the module path, e.g. through
``testsuite/benchmarks/run_all.sh`` (``make bench``), or:

    grass --tmp-location EPSG:28992 --exec python3 testsuite/benchmarks/bench_memory.py
"""

import argparse
import os
import subprocess
import sys
import tempfile

import grass.script as gs

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_v_histo_lod2 import synthetic_geojson  # noqa: E402

GOAL_MB = 1024

#: prints the exit code, the wall time and the largest peak RSS (MB) of its command's processes
PEAK = ("import resource, subprocess, sys, time\n"
        "t = time.perf_counter()\n"
        "code = subprocess.run(sys.argv[1:]).returncode\n"
        "print(code, time.perf_counter() - t,"
        " resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024.0)\n")


def peak_run(**options):
    """(wall time s, peak RSS MB) of one v.histo.lod2 run."""
    args = ["v.histo.lod2", "--overwrite", "--quiet"] + [
        "{}={}".format(k, v) for k, v in options.items()]
    out = subprocess.run([sys.executable, "-c", PEAK] + args, capture_output=True, text=True,
                         check=True)
    code, wall, peak = out.stdout.split()
    if code != "0":
        raise SystemExit("v.histo.lod2 failed: " + out.stderr[-2000:])
    return float(wall), float(peak)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--footprints", type=int, nargs="+", default=[60000, 200000])
    args = parser.parse_args()
    ok = True
    with tempfile.TemporaryDirectory() as tmp:
        for n in args.footprints:
            src = os.path.join(tmp, "synthetic.geojson")
            synthetic_geojson(src, n)
            gs.run_command("v.in.ogr", input=src, output="bench_memory", flags="o", quiet=True,
                           overwrite=True)
            common = dict(input="bench_memory", height="6.7,17", attic="2.6,6", year=1900,
                          seed=3)
            for label, options in (
                    ("cityjsonseq", dict(format="cityjsonseq",
                                         output=os.path.join(tmp, "m.city.jsonl"))),
                    ("cityjsonseq + render", dict(format="cityjsonseq",
                                                  output=os.path.join(tmp, "m.city.jsonl"),
                                                  render=os.path.join(tmp, "m.png"))),
                    ("cityjson", dict(output=os.path.join(tmp, "m.city.json"))),
                    ("cityjson + render", dict(output=os.path.join(tmp, "m.city.json"),
                                               render=os.path.join(tmp, "m.png")))):
                wall, peak = peak_run(**common, **options)
                line = ("v.histo.lod2 {} footprints, {}: peak RSS {:.0f} MB = {:.1f} KB per "
                        "footprint ({:.1f} s)".format(n, label, peak, peak * 1024.0 / n, wall))
                if label == "cityjsonseq" and n >= 200000:
                    met = peak < GOAL_MB
                    ok &= met
                    line += "; goal < {} MB: {}".format(GOAL_MB, "met" if met else "NOT met")
                print(line, flush=True)
            gs.run_command("g.remove", flags="f", type="vector", name="bench_memory",
                           quiet=True)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
