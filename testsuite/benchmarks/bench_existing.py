#!/usr/bin/env python3
"""Benchmark of merging an existing 3D city model and of writing CityJSONSeq (issue 17).

Goals: merging a 10,000-building existing model (matching the aligned
footprints, copying the buildings, merging them into the generated model's
text and writing the file) takes at most the time of reading that model
once; writing CityJSONSeq is no slower than writing the single file.

The existing model is synthesised from the 3D BAG sample
(``../shared/data/3dbag_sample``): its two buildings replicated on a grid
(``--buildings`` in all, as CityJSONSeq and as one CityJSON file). The
aligned footprints are the ground surfaces of those buildings (every one
matches), plus ``--generated`` footprints that are built (gable roofs) as
v.histo.lod2 builds them. Prints the median of ``--runs`` runs of each step
(wall and CPU time: the machine is shared, CPU time is the steadier figure),
the load average before and after, and whether each goal is met; what a
goal compares is timed in the same rounds, not in separate blocks of runs
that the machine's drift in speed would tell apart: the read and the merge
in each of ``--runs`` fresh processes (as a v.histo.lod2 run reads the
model, then merges it), the two formats' writes alternating; also the
module's whole output side (``lod2_output.write_model``: match, copy,
merge, write) in both formats. The writes are timed for the buildings copied
from the CityJSON file and, beside them, from the CityJSONSeq (whose
features are written as they were read), each format's copy made as
v.histo.lod2 makes it (for one file a whole model keeps its vertex
numbering; CityJSONSeq features number their own vertices), the CityJSONSeq
written to a binary file as v.histo.lod2 writes it.

Pure library code; runs with ``python3`` from the checkout or inside the
GRASS session of ``run_all.sh``:

    python3 testsuite/benchmarks/bench_existing.py --runs 5
"""

import argparse
import json
import os
import statistics
import sys
import tempfile
import time

import numpy as np
import shapely

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, ROOT)
SAMPLE = os.path.join(ROOT, "..", "shared", "data", "3dbag_sample", "3dbag_b2.city.jsonl")

from reconstruction.cityjson import copied as citycopy  # noqa: E402
from reconstruction.cityjson import merge as citymerge  # noqa: E402
from reconstruction.cityjson import model as cityjson  # noqa: E402
from reconstruction.cityjson import seq as cityjsonseq  # noqa: E402
from reconstruction.cityjson import existing  # noqa: E402
from reconstruction.lod2 import stage as lod2  # noqa: E402
from reconstruction.lod2 import output as lod2_output  # noqa: E402
from reconstruction.lod2 import outlines  # noqa: E402
from reconstruction.lod2.solids import build as solids  # noqa: E402
from reconstruction.geom import solidset  # noqa: E402


def with_lod1(feature, header):
    """The feature with LoD 1.2 and 1.3 prisms on its ground surface (at the
    3D BAG's 70th and 50th percentile roof heights) before its LoD 2.2
    solid, as every 3D BAG BuildingPart has them."""
    oid = feature["id"]
    part = feature["CityObjects"][oid + "-0"]
    attrs = feature["CityObjects"][oid]["attributes"]
    solid = part["geometry"][0]
    values = solid["semantics"]["values"][0]
    ground = [s[0] for s, v in zip(solid["boundaries"][0], values) if v == 0][0]
    vertices = [list(v) for v in feature["vertices"]]
    scale, translate = header["transform"]["scale"][2], header["transform"]["translate"][2]
    prisms = []
    for lod, height in (("1.2", attrs["b3_h_dak_70p"]), ("1.3", attrs["b3_h_dak_50p"])):
        z = int(round((height - translate) / scale))
        top = []
        for i in ground:
            vertices.append([vertices[i][0], vertices[i][1], z])
            top.append(len(vertices) - 1)
        n = len(ground)
        walls = [[[ground[(k + 1) % n], ground[k], top[k], top[(k + 1) % n]]] for k in range(n)]
        prisms.append({"type": "Solid", "lod": lod,
                       "boundaries": [[[ground], [top[::-1]]] + walls],
                       "semantics": {"surfaces": solid["semantics"]["surfaces"][:3],
                                     "values": [[0, 1] + [2] * n]}})
    feature = json.loads(json.dumps(feature))
    feature["CityObjects"][oid + "-0"]["geometry"] = prisms + [solid]
    feature["vertices"] = vertices
    return feature


def synthesise(folder, n, lod1=False):
    """An n-building 3D BAG-like model: the sample's buildings on a 40 m grid
    (with ``lod1``, LoD 1.2 and 1.3 prisms beside the LoD 2.2 solids)."""
    with open(SAMPLE) as f:
        header = json.loads(f.readline())
        features = [json.loads(line) for line in f if line.strip()]
    if lod1:
        features = [with_lod1(feature, header) for feature in features]
    scale = header["transform"]["scale"][0]
    per_row = 100
    lines = [json.dumps(header, separators=(",", ":"))]
    for k in range(n):
        feature = features[k % len(features)]
        dx = int(round((k // len(features) % per_row) * 40.0 / scale))
        dy = int(round((k // len(features) // per_row) * 40.0 / scale))
        old = feature["id"]
        new = "NL.IMBAG.Pand.0503100{:09d}".format(k)
        text = json.dumps({"type": "CityJSONFeature", "id": new,
                           "CityObjects": feature["CityObjects"],
                           "vertices": (np.asarray(feature["vertices"]) + [dx, dy, 0]).tolist()},
                          separators=(",", ":"))
        lines.append(text.replace(old, new))
    seq = os.path.join(folder, "existing.city.jsonl")
    with open(seq, "w") as f:
        f.write("\n".join(lines) + "\n")
    with open(seq) as f:
        doc = cityjsonseq.collect(f)
    single = os.path.join(folder, "existing.city.json")
    with open(single, "w") as f:
        json.dump(doc, f, separators=(",", ":"))
    return single, seq


def generated_model(n, seed=3):
    """Solids of n rectangles south of the existing buildings (as v.histo.lod2 builds them)."""
    rng = np.random.default_rng(seed)
    rings = []
    for i in range(n):
        x0, y0 = 80000.0 + (i % 200) * 25.0, 440000.0 + (i // 200) * 30.0
        w, d = rng.uniform(5, 9), rng.uniform(10, 18)
        rings.append(outlines.clean_ring(np.array([[0, 0], [w, 0], [w, d], [0, d]]) + [x0, y0])[0])
    built = solids.build_solids(solids.Buildings(
        rings, np.zeros(n), np.full(n, 9.0), np.full(n, 3.0), np.array(["gable"] * n, dtype=object),
        rng.random((n, 3))))
    ss, kept, got = built.solids, built.kept, built.types
    ids = ["building_{}".format(k + 1) for k in kept]
    return ss, solidset.semantics(ss), ids, {"roof_type": list(got), "source": ["2pm"] * len(kept)}


def generated_result(gen):
    """The :class:`~reconstruction.lod2.stage.Lod2Result` of the generated buildings
    ``gen`` (as :func:`generated_model` makes them); the aligned footprints
    are not built (v.histo.lod2 leaves the copied ones out)."""
    ss, sem, ids, attrs = gen
    return lod2.Lod2Result(ss, sem, ids, np.array(attrs["roof_type"], dtype=object),
                           np.arange(len(ids)), attrs, None)


def verdict(ok):
    return "goal met" if ok else "goal NOT met"


def median_time(fn, runs):
    """Median wall time and median CPU time of the process (the machine is
    shared: CPU time is the steadier figure) of ``fn()``, what it returns
    freed after the clock stops."""
    wall, cpu = [], []
    for _ in range(runs):
        t, c = time.perf_counter(), time.process_time()
        result = fn()
        wall.append(time.perf_counter() - t)
        cpu.append(time.process_time() - c)
        del result
    return Timing.median(wall, cpu)


def interleaved(steps, runs):
    """The median :class:`Timing` of each of ``steps`` (callables), run once
    each in every one of ``runs`` rounds, in the opposite order every other
    round: the machine's speed drifts (a shared virtual machine: the same
    code ran 50 % slower from one minute to the next here), and steps timed
    in separate blocks of runs compare that drift, not the steps."""
    wall, cpu = [[] for _ in steps], [[] for _ in steps]
    for r in range(runs):
        order = range(len(steps)) if r % 2 == 0 else reversed(range(len(steps)))
        for k in order:
            t, c = time.perf_counter(), time.process_time()
            result = steps[k]()
            wall[k].append(time.perf_counter() - t)
            cpu[k].append(time.process_time() - c)
            del result
    return [Timing.median(w, c) for w, c in zip(wall, cpu)]


def one_round(folder, by):
    """In a fresh process, as v.histo.lod2 runs: read the model of ``folder``
    then merge it (by "id" or by "geometry"); prints the wall and CPU times
    of both as JSON."""
    import pickle

    with open(os.path.join(folder, "inputs.pickle"), "rb") as f:
        text, wkb, bag_ids = pickle.load(f)
    aligned = list(shapely.from_wkb(wkb))
    t, c = time.perf_counter(), time.process_time()
    model = existing.read_model(os.path.join(folder, "existing.city.json"))
    read = (time.perf_counter() - t, time.process_time() - c)
    t, c = time.perf_counter(), time.process_time()
    matches = merge_and_write(model, aligned, bag_ids if by == "id" else None, text,
                              os.path.join(folder, "out-{}.city.json".format(by)))
    merge = (time.perf_counter() - t, time.process_time() - c)
    print(json.dumps({"read": read, "merge": merge, "copied": len(matches.matched)}))


def merge_and_write(model, aligned, ids, text, out):
    """What merging costs: match the aligned footprints (by ``ids``, None: by
    geometry), copy the matched buildings, merge them into the generated
    model's ``text`` and write it to ``out``, as v.histo.lod2 does; returns
    the matches."""
    matches = existing.match(model, aligned, ids=ids)
    copied = citycopy.copy_buildings(model, matches.building[matches.matched])
    cityjson.write_text(out, citymerge.merged_pieces(text, copied))
    return matches


def fresh_rounds(folder, text, aligned, bag_ids, runs):
    """Median :class:`Timing` of the read and of the merges by id and by
    geometry, each round a fresh process reading the model then merging it
    (:func:`one_round`), as a v.histo.lod2 run does: the read and the merge
    it is compared with pay the same costs of a new process's memory."""
    import pickle
    import subprocess

    with open(os.path.join(folder, "inputs.pickle"), "wb") as f:
        pickle.dump((text, shapely.to_wkb(aligned), bag_ids), f)
    reads, merges = [], {"id": [], "geometry": []}          # (wall, CPU) pairs
    for r in range(runs):
        for by in (("id", "geometry") if r % 2 == 0 else ("geometry", "id")):
            got = json.loads(subprocess.run(
                [sys.executable, os.path.abspath(__file__), "--round", folder, by],
                check=True, capture_output=True, text=True).stdout)
            assert got["copied"] == len(bag_ids)
            reads.append(got["read"])
            merges[by].append(got["merge"])
    return tuple(Timing.median(*zip(*pairs)) for pairs in (reads, merges["id"],
                                                            merges["geometry"]))


class Timing:
    def __init__(self, wall, cpu):
        self.wall, self.cpu = wall, cpu

    @staticmethod
    def median(wall, cpu):
        """The median of some runs' wall and CPU times."""
        return Timing(statistics.median(wall), statistics.median(cpu))

    def __sub__(self, other):
        return Timing(self.wall - other.wall, self.cpu - other.cpu)

    def __str__(self):
        return "{:.3f} s ({:.3f} s CPU)".format(self.wall, self.cpu)

    def ratio(self, other):
        return "{:.2f} x ({:.2f} x CPU)".format(self.wall / other.wall, self.cpu / other.cpu)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--buildings", type=int, default=10000)
    parser.add_argument("--generated", type=int, default=10000)
    parser.add_argument("--lod1", action="store_true",
                        help="LoD 1.2 and 1.3 beside LoD 2.2, as in the 3D BAG (copied: 2.2)")
    parser.add_argument("--round", nargs=2, metavar=("FOLDER", "BY"), help=argparse.SUPPRESS)
    args, _ = parser.parse_known_args()
    if args.round:
        one_round(*args.round)
        return 0
    if not os.path.exists(SAMPLE):
        print("skipped: the 3D BAG sample is not at '{}'".format(SAMPLE))
        return 0
    print("load average before: {:.2f} {:.2f} {:.2f}".format(*os.getloadavg()))
    with tempfile.TemporaryDirectory() as folder:
        single, seq = synthesise(folder, args.buildings, args.lod1)
        print("existing model: {} buildings, {:.1f} MB (CityJSON), {:.1f} MB (CityJSONSeq)".format(
            args.buildings, os.path.getsize(single) / 1e6, os.path.getsize(seq) / 1e6))
        gen = generated_model(args.generated)
        text = cityjson.citymodel_text(*gen, 28992, title="bench")
        model = existing.read_model(single)
        fps = existing.footprints(model)
        # the aligned footprints as they come back from GRASS: counter-clockwise, millimetres
        aligned = list(shapely.set_precision(shapely.orient_polygons(fps.polygons), 0.001))
        bag_ids = [b.rsplit(".", 1)[1] for b in model.buildings]
        out = os.path.join(folder, "out.city.json")

        for ids, by in ((bag_ids, "by_id"), (None, "by_geometry")):
            matches = merge_and_write(existing.read_model(single), aligned, ids, text, out)
            assert getattr(matches.report, by) == args.buildings
        t_read, t_id, t_geom = fresh_rounds(folder, text, aligned, bag_ids, args.runs)
        t_read_seq = median_time(lambda: existing.read_model(seq), args.runs)
        print("read existing model: {} (CityJSON), {} (CityJSONSeq)".format(t_read, t_read_seq))
        print("merge by id (match, copy, merge, write, after the read): {} = {} the read".format(
            t_id, t_id.ratio(t_read)))
        print("merge by geometry (footprints, match, copy, merge, write, after the read): "
              "{} = {} the read".format(t_geom, t_geom.ratio(t_read)))
        matches = existing.match(model, aligned, ids=bag_ids)
        copied = citycopy.copy_buildings(model, matches.building[matches.matched])
        steps = {
            "match by id": lambda: existing.match(model, aligned, ids=bag_ids),
            "footprints": lambda: existing.footprints(model),
            "match by geometry": lambda: existing.match(model, aligned, fps=fps),
            "copy": lambda: citycopy.copy_buildings(model, matches.building[matches.matched]),
            "merge into the text (pieces)": lambda: citymerge.merged_pieces(text, copied),
        }
        for name, fn in steps.items():
            print("  {}: {}".format(name, median_time(fn, args.runs)))

        def write_single(c):
            body = cityjson.citymodel_text(*gen, 28992, title="bench")
            cityjson.write_text(out, citymerge.merged_pieces(body, c))

        def write_seq(c):
            with open(out + "l", "wb") as f:            # as v.histo.lod2 opens it
                cityjsonseq.write(f, *gen, 28992, title="bench", copied=c)

        single_cpu = seq_cpu = 0.0
        model_seq = existing.read_model(seq)
        copied_seq = citycopy.copy_buildings(
            model_seq, existing.match(model_seq, aligned, ids=bag_ids).building)
        del model_seq
        # each format's copy as v.histo.lod2 makes it (CityJSONSeq features number their own)
        for_seq = citycopy.copy_buildings(model, matches.building[matches.matched],
                                           keep_numbering=False)
        for label, c, c_seq in (
                ("{} generated".format(len(gen[2])), None, None),
                ("{} generated + {} copied".format(len(gen[2]), len(copied)), copied, for_seq),
                ("{} generated + {} copied from the CityJSONSeq".format(
                    len(gen[2]), len(copied_seq)), copied_seq, copied_seq)):
            t_single, t_seq = interleaved([lambda: write_single(c), lambda: write_seq(c_seq)],
                                          args.runs)
            if c is not copied_seq:     # the verdict below: the single-file input, as before
                single_cpu, seq_cpu = single_cpu + t_single.cpu, seq_cpu + t_seq.cpu
            print("write {}: single file {}, CityJSONSeq {} ({})".format(
                label, t_single, t_seq, t_seq.ratio(t_single)))
        with open(out + "l") as f:
            back = cityjsonseq.collect(f)
        assert len(back["CityObjects"]) == len(gen[2]) + 2 * len(copied)

        # the module's output side, as v.histo.lod2 existing= runs it
        result = generated_result(gen)
        n = len(gen[2])
        footprints = lod2.Footprints([None] * n + aligned, cats=list(range(1, n + len(aligned) + 1)),
                                     source=["2pm"] * n + ["aligned"] * len(aligned))
        wanted = lod2_output.ExistingRequest(single)
        all_ids = [None] * n + bag_ids

        def output_side(fmt, with_existing):
            request = lod2_output.OutputRequest(out + "." + fmt, fmt, 28992, "bench")
            match = None
            if with_existing:
                match = lod2_output.match_existing(model, wanted, footprints, all_ids)
            return lod2_output.write_model(result, footprints, request, match)

        assert output_side("cityjsonseq", True).copied == args.buildings
        for fmt in lod2_output.FORMATS:
            t_plain, t_with = interleaved([lambda: output_side(fmt, False),
                                           lambda: output_side(fmt, True)], args.runs)
            extra = t_with - t_plain
            print("v.histo.lod2 output side, format={}: {} generated {}, with existing= "
                  "(by id) {}: existing= adds {} = {} the read".format(
                      fmt, n, t_plain, t_with, extra, extra.ratio(t_read)))
        print("merging adds at most one read (CPU, by id): {} ({:.2f} x); "
              "CityJSONSeq no slower than one file (CPU): {}".format(
                  verdict(t_id.cpu <= t_read.cpu), t_id.cpu / t_read.cpu,
                  verdict(seq_cpu <= single_cpu * 1.02)))
    print("load average after: {:.2f} {:.2f} {:.2f}".format(*os.getloadavg()))
    return 0


if __name__ == "__main__":
    sys.exit(main())
