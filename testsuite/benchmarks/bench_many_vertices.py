#!/usr/bin/env python3
"""Benchmark of the LoD2 stage on footprints of many vertices (issue 12, item 1).

Every roof type on footprints of 200, 1,000 and 5,000 vertices
(``testsuite/many_vertex_footprints.py``: a smooth convex curve, a block
with a digitised curved facade, a digitised L-shaped block, a digitised
concave rotunda), each built alone by the library's whole stage
(:func:`reconstruction.lod2.stage.build` of ``prepare``: cleaning, roofs, walls,
validation, fallbacks) in a forked process. Prints per footprint the
vertices after cleaning, the roof type it got, whether its outline was
simplified for the roof (``vertex_budget``) and to how many vertices, the
CPU time, and the peak memory (resident set of the process, and above the
same process before building); with val3dity available (``../shared/tools``),
whether val3dity finds every solid valid. Goals: under 1 s and well under
1 GB per footprint.

    python3 testsuite/benchmarks/bench_many_vertices.py [--sizes 200,1000,5000] [--no-val3dity]
"""

import argparse
import os
import pickle
import resource
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, ROOT)
sys.path.insert(0, os.path.join(ROOT, "testsuite"))

import numpy as np  # noqa: E402

from many_vertex_footprints import SHAPES, footprint  # noqa: E402
from reconstruction.lod2 import stage as lod2  # noqa: E402
from reconstruction.lod2.roofs import plan as roofs  # noqa: E402
from reconstruction.lod2.solids import vertex_budget  # noqa: E402

ORIGIN = np.array([85000.0, 445000.0])
TIME_GOAL = 1.0
MEMORY_GOAL_MB = 1024.0


def build_one(shape, n, kind):
    """The stage on one footprint: (vertices after cleaning, roof type, vertices
    of its outline, the model's text, CPU s)."""
    import shapely

    geom = shapely.Polygon(footprint(shape, n) + ORIGIN)
    start = time.process_time()
    result = lod2.build(lod2.prepare(
        lod2.Footprints([geom]), lod2.Heights(np.array([9.0]), np.array([4.0]), 0.0),
        lod2.RoofRequests(np.array([kind], dtype=object), np.array([np.nan]))))
    cpu = time.process_time() - start
    prepared = result.report.rings
    cleaned = lod2.prepare(lod2.Footprints([geom]), lod2.Heights(np.array([9.0]), np.array([4.0])),
                           lod2.RoofRequests(np.array([kind], dtype=object),
                                             np.array([np.nan]))).buildings.footprints
    got = str(result.roof_types[0]) if len(result.roof_types) else "none"
    ground = int((result.semantics == 0).sum()) and len(result.solids.solid(0)[1][0]) \
        if len(result.ids) else 0
    text = lod2.citymodel_text(result, "https://www.opengis.net/def/crs/EPSG/0/7415")
    return (len(cleaned[0]) if prepared else 0, got, ground, text, cpu)


def in_child(fn, *args):
    """``fn(*args)`` in a forked process: (its result, its peak resident set
    in MB, the peak before it started in MB)."""
    read, write = os.pipe()
    pid = os.fork()
    if pid == 0:                                   # the child
        os.close(read)
        before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
        try:
            out = ("ok", fn(*args), before)
        except BaseException as error:             # reported by the parent
            out = ("error", repr(error), before)
        with os.fdopen(write, "wb") as f:
            pickle.dump(out, f)
        os._exit(0)
    os.close(write)
    with os.fdopen(read, "rb") as f:
        data = f.read()
    _, _, usage = os.wait4(pid, 0)
    status, value, before = pickle.loads(data) if data else ("error", "killed", 0.0)
    return status, value, usage.ru_maxrss / 1024.0, before


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", default="200,1000,5000")
    parser.add_argument("--no-val3dity", action="store_true")
    args = parser.parse_args()
    sizes = [int(v) for v in args.sizes.split(",")]
    check = None
    if not args.no_val3dity:
        from val3dity import val3dity_problem, val3dity_report

        problem = val3dity_problem()
        if problem:
            print("val3dity not run: {}".format(problem))
        else:
            check = val3dity_report
    # import everything the stage needs before forking, as v.histo.lod2 has it
    build_one("wavy", 200, "hip")
    print("load average {:.2f}; vertex budget of pitched roofs: {}".format(
        os.getloadavg()[0], vertex_budget.MAX_ROOF_VERTICES))
    print("{:10} {:>5} {:>7} {:16} {:>7} {:>7} {:>8} {:>6} {}".format(
        "shape", "n", "cleaned", "roof", "outline", "CPU s", "peak MB", "+MB", "val3dity"))
    ok = True
    worst_time = worst_mem = 0.0
    with tempfile.TemporaryDirectory() as tmp:
        for shape in SHAPES:
            for n in sizes:
                for kind in roofs.ROOF_TYPES:
                    status, value, peak, before = in_child(build_one, shape, n, kind)
                    if status != "ok":
                        print("{:10} {:>5} FAILED: {}".format(shape, n, value))
                        ok = False
                        continue
                    cleaned, got, outline, text, cpu = value
                    verdict = "-"
                    if check is not None:
                        path = os.path.join(tmp, "model.city.json")
                        with open(path, "w") as f:
                            f.write(text)
                        rep = check(path)
                        verdict = "valid" if rep.valid == rep.objects == 1 else str(rep)
                        ok &= verdict == "valid"
                    worst_time, worst_mem = max(worst_time, cpu), max(worst_mem, peak)
                    print("{:10} {:>5} {:>7} {:16} {:>7} {:>7.3f} {:>8.0f} {:>6.0f} {}".format(
                        shape, n, cleaned, "{}>{}".format(kind, got) if got != kind else got,
                        outline if outline != cleaned else "all", cpu, peak, peak - before,
                        verdict))
    met = worst_time < TIME_GOAL and worst_mem < MEMORY_GOAL_MB
    print("largest CPU time {:.3f} s per footprint (goal < {} s), largest peak {:.0f} MB "
          "(goal < {:.0f} MB): {}".format(worst_time, TIME_GOAL, worst_mem, MEMORY_GOAL_MB,
                                          "met" if met else "NOT met"))
    return 0 if ok and met else 1


if __name__ == "__main__":
    sys.exit(main())
