"""The report of demo/delft_1961.sh: one JSON of what each stage's module reported.

    python3 demo/delft_report.py OUT

Reads OUT/times.txt (stage, wall ms), OUT/generalize.json, OUT/align.json,
OUT/lod2.txt (v.histo.lod2 -v), OUT/model.city.json (buildings by
height source) and the footprints map of the current
mapset; writes OUT/report.json and prints a short table.
"""

import collections
import json
import os
import sys


def footprint_sources():
    """How many footprints of each source (aligned, 2pm) <footprints> holds."""
    import grass.script as gs

    rows = gs.read_command("v.db.select", map="footprints", columns="source", flags="c")
    return dict(collections.Counter(rows.split()))


def build(out):
    def load(name):
        with open(os.path.join(out, name)) as f:
            return json.load(f)

    with open(os.path.join(out, "times.txt")) as f:
        seconds = {s: int(ms) / 1000.0 for s, ms in (line.split() for line in f if line.strip())}
    with open(os.path.join(out, "lod2.txt")) as f:
        lod2 = dict(line.strip().split("=", 1) for line in f if "=" in line)
    generalize = load("generalize.json")
    sources = footprint_sources()
    model = load("model.city.json")
    heights = collections.Counter(o["attributes"].get("height_source")
                                  for o in model["CityObjects"].values())
    return {
        "seconds": seconds,
        "total_seconds": round(sum(seconds.values()), 3),
        "generalize": generalize,
        "align": load("align.json"),
        "subdivide": {"footprints": sum(sources.values()), "by_source": sources},
        "lod2": dict({k: (float(v) if "." in v else int(v)) for k, v in lod2.items()},
                     buildings=len(model["CityObjects"]), height_source=dict(heights)),
    }


def main(out):
    report = build(out)
    with open(os.path.join(out, "report.json"), "w") as f:
        json.dump(report, f, indent=1)  # stages in the order they ran
    for stage, s in report["seconds"].items():
        print("{:<12} {:8.1f} s".format(stage, s))
    print("{:<12} {:8.1f} s".format("total", report["total_seconds"]))


if __name__ == "__main__":
    main(sys.argv[1])
