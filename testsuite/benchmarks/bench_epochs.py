#!/usr/bin/env python3
"""Benchmark of merge_epochs: four epochs of a town of 15,000 buildings into one model.

The four epoch models (1880, 1915, 1961, 2000) are made synthetically in
numpy, CityJSON 2.0 as v.histo.lod2 writes it (millimetre transform; one
LoD2 gable Solid with ground, wall and roof semantics per building). Each
later epoch keeps 90 % of the earlier buildings with identical geometry,
replaces 5 % (a new building, new id, on the same site) and demolishes 5 %,
and adds 5 % on empty sites: 15,000 buildings in each. A third of the
buildings of the last epoch have BAG-like ids (``0503100000......``) and are
in the register with a construction year (one in 20 contradicting the
maps). Prints the median wall time of ``--runs`` (default 3) merges and of
as many writes of the merged file (compact JSON), the building count, the
geometry versions and the size ratio (merged compact bytes / the sum of the
epoch files' compact bytes). Goal: the merge under 60 s on 2 cores; slower,
it prints cProfile's hot spots.

    python3 testsuite/benchmarks/bench_epochs.py [--runs N] [--buildings N] [--profile]
"""

import argparse
import cProfile
import io
import json
import os
import pstats
import statistics
import sys
import tempfile
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
if ROOT not in sys.path:
    sys.path.insert(0, ROOT)

from reconstruction.epochs.dynamic import Epoch, merge_epochs  # noqa: E402

YEARS = (1880, 1915, 1961, 2000)
GOAL = 60.0
#: share of the earlier buildings replaced and demolished, and of new ones added
REPLACED, DEMOLISHED, ADDED = 0.05, 0.05, 0.05
SPACING = 12.0          # m between sites
#: a gable house's faces on its 10 vertices (outward), and their semantics
FACES = ([0, 3, 2, 1], [0, 1, 5, 4], [1, 2, 6, 9, 5], [2, 3, 7, 6], [3, 0, 4, 8, 7],
         [4, 5, 9, 8], [6, 7, 8, 9])
SEMANTICS = {"surfaces": [{"type": "GroundSurface"}, {"type": "WallSurface"},
                          {"type": "RoofSurface"}], "values": [[0, 1, 1, 1, 1, 2, 2]]}


def houses(sites, rng, n_sites_x):
    """(N, 10, 3) integer millimetre vertices of gable houses on the sites (cell numbers)."""
    n = len(sites)
    x0 = (sites % n_sites_x) * SPACING + 1.0
    y0 = (sites // n_sites_x) * SPACING + 1.0
    w, d = rng.uniform(5, 10, n), rng.uniform(6, 10, n)
    ground = rng.uniform(0, 2, n)
    eaves = ground + rng.uniform(5, 12, n)
    ridge = eaves + rng.uniform(2, 6, n)
    xs = np.stack([x0, x0 + w, x0 + w, x0, x0, x0 + w, x0 + w, x0, x0, x0 + w], 1)
    ys = np.stack([y0, y0, y0 + d, y0 + d, y0, y0, y0 + d, y0 + d, y0 + d / 2, y0 + d / 2], 1)
    zs = np.stack([ground] * 4 + [eaves] * 4 + [ridge] * 2, 1)
    return np.rint(np.stack([xs + 85000, ys + 447000, zs], 2) * 1000).astype(np.int64)


def town(buildings, seed=1):
    """The four epochs' {id: (N vertices of the house, attributes)} histories: per epoch
    [(id, site, vertices (10, 3), built)], and the register {BAG id: year}."""
    rng = np.random.default_rng(seed)
    n_sites = int(buildings * (1 + ADDED * len(YEARS)) * 1.05)
    n_x = int(np.ceil(np.sqrt(n_sites)))
    free = list(rng.permutation(n_x * n_x))
    counter = [0]

    def new(sites, year):
        counter[0] += len(sites)
        verts = houses(np.asarray(sites), rng, n_x)
        first = counter[0] - len(sites)
        return [("building_{}_{}".format(year, first + k), s, v)
                for k, (s, v) in enumerate(zip(sites, verts))]

    epochs = [new([free.pop() for _ in range(buildings)], YEARS[0])]
    for year in YEARS[1:]:
        earlier = epochs[-1]
        fate = rng.random(len(earlier))
        kept = [b for b, f in zip(earlier, fate) if f >= REPLACED + DEMOLISHED]
        replaced = [b[1] for b, f in zip(earlier, fate) if f < REPLACED]
        for b, f in zip(earlier, fate):
            if REPLACED <= f < REPLACED + DEMOLISHED:
                free.insert(0, b[1])        # a demolished site is free again, later
        added = [free.pop() for _ in range(buildings - len(kept) - len(replaced))]
        epochs.append(kept + new(replaced + added, year))
    # BAG-like ids for a third of the last epoch's buildings, the same id in every epoch
    last = epochs[-1]
    chosen = rng.random(len(last)) < 1 / 3
    rename = {b[0]: "0503100000{:06d}".format(k) for k, (b, c) in enumerate(zip(last, chosen))
              if c}
    first_year = {}
    for year, epoch in zip(YEARS, epochs):
        for b in epoch:
            first_year.setdefault(b[0], year)
    register = {}
    for old, bag in rename.items():
        y = first_year[old]
        k = YEARS.index(y)
        lo = YEARS[k - 1] + 1 if k else 1600
        built = int(rng.integers(lo, y + 1))
        if rng.random() < 0.05:
            built = y + 5                            # the register contradicts the maps
        register[bag] = built
    epochs = [[(rename.get(i, i), s, v) for i, s, v in epoch] for epoch in epochs]
    return epochs, register


def document(year, epoch):
    """The CityJSON 2.0 document of one epoch, as v.histo.lod2 writes it."""
    verts = np.concatenate([v for _, _, v in epoch])
    translate = verts.min(axis=0)
    objects = {}
    for k, (oid, site, v) in enumerate(epoch):
        base = 10 * k
        objects[oid] = {"type": "Building", "attributes": {
            "map_year": year, "plot": int(site) // 20, "roof_type": "gable",
            "eaves_height": round(float(v[4, 2] - v[0, 2]) / 1000, 3),
            "roof_height": round(float(v[8, 2] - v[4, 2]) / 1000, 3),
            "ground_height": round(float(v[0, 2]) / 1000, 3), "height_source": "measured"},
            "geometry": [{"type": "Solid", "lod": "2", "boundaries": [
                [[[base + i for i in face]] for face in FACES]], "semantics": SEMANTICS}]}
    return {"type": "CityJSON", "version": "2.0",
            "transform": {"scale": [0.001] * 3,
                          "translate": [float(t) / 1000 for t in translate]},
            "metadata": {"referenceSystem": "https://www.opengis.net/def/crs/EPSG/0/7415",
                         "title": "synthetic town {}".format(year)},
            "CityObjects": objects, "vertices": (verts - translate).tolist()}


def compact(doc):
    return json.dumps(doc, separators=(",", ":"))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--buildings", type=int, default=15000)
    parser.add_argument("--profile", action="store_true", help="profile one merge anyway")
    args = parser.parse_args(argv)
    t = time.perf_counter()
    histories, register = town(args.buildings)
    with tempfile.TemporaryDirectory() as tmp:
        epochs, epoch_bytes = [], 0
        for year, history in zip(YEARS, histories):
            doc = document(year, history)
            path = os.path.join(tmp, "model_{}.city.json".format(year))
            with open(path, "w") as f:
                f.write(compact(doc))
            epoch_bytes += os.path.getsize(path)
            with open(path) as f:                     # as a chain would: read back
                epochs.append(Epoch(year, json.load(f), path))
        made = time.perf_counter() - t
        print("four epochs of {} buildings made, written and read in {:.1f} s; register {} "
              "ids".format(args.buildings, made, len(register)))
        for year, e in zip(YEARS, epochs):
            print("  {}: {} buildings, {} vertices".format(
                year, len(e.document["CityObjects"]), len(e.document["vertices"])))
        merges, model = [], None
        for _ in range(args.runs):
            t = time.perf_counter()
            model = merge_epochs(epochs, register=register)
            merges.append(time.perf_counter() - t)
        out = os.path.join(tmp, "merged.city.json")
        writes = []
        for _ in range(args.runs):
            t = time.perf_counter()
            with open(out, "w") as f:
                json.dump(model.document, f, separators=(",", ":"))
            writes.append(time.perf_counter() - t)
        merged_bytes = os.path.getsize(out)
    r = model.report
    merge = statistics.median(merges)
    print("merge_epochs: median {:.2f} s of {} runs ({}); goal < {:.0f} s: {}".format(
        merge, args.runs, ", ".join("{:.2f}".format(s) for s in merges), GOAL,
        "met" if merge < GOAL else "NOT met"))
    print("write merged (compact JSON): median {:.2f} s of {} runs".format(
        statistics.median(writes), args.runs))
    print("buildings {}, per epoch {}, geometry versions {}, standing {}, conflicts {}".format(
        r.buildings, r.per_epoch, r.versions, r.standing, len(r.conflicts)))
    print("size: merged {:,} bytes / epochs {:,} bytes = {:.3f}".format(
        merged_bytes, epoch_bytes, merged_bytes / epoch_bytes))
    if merge >= GOAL or args.profile:
        profile = cProfile.Profile()
        profile.enable()
        merge_epochs(epochs, register=register)
        profile.disable()
        text = io.StringIO()
        pstats.Stats(profile, stream=text).sort_stats("cumulative").print_stats(20)
        print(text.getvalue())
    return 0


if __name__ == "__main__":
    sys.exit(main())
