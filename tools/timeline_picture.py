#!/usr/bin/env python3
"""The picture of v.histo.timeline's manual page: the snapshots of a merged model
(v.histo.timeline output=) at its epochs, side by side, each building in grey when the
previous map has it already, in orange when it is new, outlined in blue when it still
stands today.

    python3 tools/timeline_picture.py town.city.json v.histo.timeline/v_histo_timeline_town.png

Made from the suite's synthetic town (demo/dynamic_chain.sh, then v.histo.timeline),
never from the reference data.
"""

import json
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import shapely  # noqa: E402

from reconstruction.cityjson import existing  # noqa: E402
from reconstruction.epochs.dynamic import epoch_years, snapshot  # noqa: E402


def outlines(document):
    """{building id: its footprint (shapely)} of a one-year document."""
    model = existing.model_of(document)
    fps = existing.footprints(model)
    return {oid: fps.geometry(b) for b, oid in enumerate(model.buildings)}


def draw(ax, shapes, colour, edge, width):
    for geom in shapes:
        for part in getattr(geom, "geoms", [geom]):
            if part.is_empty or part.geom_type != "Polygon":
                continue
            x, y = part.exterior.xy
            ax.fill(x, y, facecolor=colour, edgecolor=edge, linewidth=width)


def main(model_path, out):
    with open(model_path) as f:
        document = json.load(f)
    years = epoch_years(document)
    fig, axes = plt.subplots(1, len(years), figsize=(4.2 * len(years), 4.4))
    before = set()
    for ax, year in zip(axes, years):
        doc = snapshot(document, year)
        shapes = outlines(doc)
        standing = {oid for oid, o in doc["CityObjects"].items()
                    if (document["CityObjects"].get(oid, {}).get("attributes") or {}).get(
                        "standing")}
        kept = [g for oid, g in shapes.items() if oid in before]
        new = [g for oid, g in shapes.items() if oid not in before]
        draw(ax, kept, "#b8b8b8", "#808080", 0.2)
        draw(ax, new, "#f28e2b", "#a0521a", 0.2)
        draw(ax, [g for oid, g in shapes.items() if oid in standing], "none", "#1f5fbf", 0.6)
        ax.set_title("{}: {} buildings, {} new".format(year, len(shapes), len(new)),
                     fontsize=10)
        ax.set_aspect("equal")
        ax.set_axis_off()
        before = set(shapes)
    fig.tight_layout()
    fig.savefig(out, dpi=80, bbox_inches="tight", pad_inches=0.1)  # the titles whole
    print("{} written".format(out))


if __name__ == "__main__":
    main(*sys.argv[1:3])
