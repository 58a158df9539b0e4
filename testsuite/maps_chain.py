#!/usr/bin/env python3
"""The chain on the real maps of other styles (../shared/data/maps, issue 50), scored.

Run inside a GRASS session of a metric location with the suite on the module
path (testsuite/test_maps_venice.py runs it in a fresh EPSG:32633 location):

    python3 testsuite/maps_chain.py venice REPORT.json [--picture /tmp/venice.png]
    python3 testsuite/maps_chain.py sanborn REPORT.json --window COL,ROW,SIZE \\
        [--picture /tmp/sanborn.png]

``venice``: Venice 1808 sample 3 imported with its published parcels;
training points derived from them at run time (testsuite/real_maps.py: a
stand-in for a user's points by eye, never stored); r.histo.classify,
v.histo.generalize on the building class (on Venice ``-d map=`` the scan's
bands: the plots the drawn outlines close), v.histo.subdivide with ``map=``
the scan's bands when it has that option (footprints that follow the lines
drawn inside each plot). The plots and footprints are
rasterised on the scan's grid and scored
(reconstruction.generalize.assessment): blocks (the parcels' union closed by
0.6 m) against the plots as objects matched one-to-one at IoU > 0.5 (F-score,
panoptic quality), parcels matched one-to-one by a footprint at IoU >= 0.5
(share of the parcels, count ratio); classification seconds per megapixel.

``sanborn``: a window of the Sanborn 1892 sheet (cells of the 0.25 m warp),
training points by colour rules, the same chain; the footprints in the
window counted (against a count by eye made outside the repository).

REPORT.json gets the figures; --picture draws the footprints over the scan
(a file outside the repository: pictures of the shared data never go in it).
Options of the modules: --classify, --generalize, --subdivide (KEY=VALUE ...).
"""

import argparse
import json
import os
import re
import subprocess
import sys
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
for _path in (ROOT, os.path.join(ROOT, "testsuite")):
    if _path not in sys.path:
        sys.path.insert(0, _path)

MAPS = os.path.join(ROOT, "..", "shared", "data", "maps")
VENICE_SCAN = os.path.join("venice_1808", "venice_1808_sample3.tif")
VENICE_TRUTH = os.path.join("venice_1808", "venice_1808_sample3_parcels_gt.tif")
SANBORN_SCAN = os.path.join("sanborn_1892", "alexandria_1892_sheet2_utm15n_0.25m.tif")
#: the blocks close the lines between parcels: buffer +0.6 m then -0.6 m (README of the maps)
CLOSE_METRES = 0.6
BUILDING = 1

#: the modules' options on each map; the options given on the command line replace them
#: Venice washes its parcels in pinks and yellows thinned to near white: their CIELAB
#: colour (features=lab) tells them from white yards where RGB does not
CLASSIFY = {"venice": {"remove": "2,6", "separate": "1", "features": "lab,size"},
            "sanborn": {"remove": "6", "separate": "1"}}
#: Venice outlines every block and parcel: the plots are read from its lines (-d), the
#: classification deciding which regions are built; simplify keeps the drawn outline
GENERALIZE = {"venice": {"flags": "d", "method": "simplify"}, "sanborn": {}}
#: both maps draw every unit (parcels, buildings): a plot without inner lines is one (-d)
SUBDIVIDE = {"venice": {"flags": "d"}, "sanborn": {"flags": "d"}}


def missing(path):
    """A message naming ``path`` when it does not exist, else None."""
    return None if os.path.exists(path) else "reference data not found at '{}'".format(
        os.path.abspath(path))


def has_option(module, key):
    """Does ``module`` have option ``key`` (from its --interface-description)?"""
    out = subprocess.run([module, "--interface-description"], capture_output=True, text=True)
    return re.search(r'<parameter name="{}"'.format(re.escape(key)), out.stdout) is not None


def run(module, **options):
    """Run a module (raises with its error output when it fails); returns its wall time."""
    import grass.script as gs

    start = time.perf_counter()
    proc = gs.start_command(module, stdout=gs.PIPE, stderr=gs.PIPE, overwrite=True, **options)
    out, err = proc.communicate()
    if proc.returncode != 0:
        raise RuntimeError("{} failed:\n{}".format(module, gs.decode(err)[-3000:]))
    return time.perf_counter() - start


def import_bands(path, output):
    """r.in.gdal ``path`` as ``output``.*; the region set to it. Returns the band names
    (red, green, blue[, alpha]) in that order."""
    import grass.script as gs

    run("r.in.gdal", input=path, output=output, flags="o", quiet=True)
    names = [n.split("@")[0] for n in gs.list_strings("raster", pattern=output + ".*")]
    order = {"red": 0, "green": 1, "blue": 2, "alpha": 3, "1": 0, "2": 1, "3": 2, "4": 3}
    names.sort(key=lambda n: order.get(n.rsplit(".", 1)[-1], 9))
    gs.run_command("g.region", raster=names[0], quiet=True)
    return names


def read_stack(names):
    """The rasters ``names`` in the current region as one (rows, cols, bands) uint8 array."""
    from reconstruction import grassio

    return np.stack([np.nan_to_num(grassio.read_raster(n)).astype(np.uint8) for n in names],
                    axis=-1)


def write_training(cells, name="training"):
    """The training cells (real_maps.TrainingCells) as points ``name`` (label, class)."""
    import grass.script as gs

    from reconstruction import grassio

    region = gs.region()
    xy = cells.xy(region["w"], region["n"], region["ewres"], region["nsres"])
    grassio.write_points(name, xy, {"label": [int(v) for v in cells.labels],
                                    "class": cells.classes()})
    return name


def classify(bands, training, options, output="classes"):
    """r.histo.classify on ``bands``; returns the seconds per megapixel of the region."""
    import grass.script as gs

    seconds = run("r.histo.classify", input=",".join(bands[:3]), training=training,
                  output=output, seed=1, nprocs=2, quiet=True, **options)
    region = gs.region()
    return seconds, seconds / (region["rows"] * region["cols"] / 1e6)


def rasterised(vector):
    """The areas of ``vector`` on the current grid, labelled by category (0: none)."""
    from reconstruction import grassio

    run("v.to.rast", input=vector, output=vector + "_cells", use="cat", type="area", quiet=True)
    return np.nan_to_num(grassio.read_raster(vector + "_cells")).astype(np.int64)


def chain(style, bands, training, args):
    """Classification, plots, footprints; returns the figures of the run (a dict)."""
    figures = {"options": {}}
    opts = dict(CLASSIFY[style], **dict(args.classify))
    figures["options"]["classify"] = opts
    seconds, per_mp = classify(bands, training, opts)
    figures["classify_seconds"], figures["classify_s_per_mp"] = seconds, per_mp
    opts = dict(GENERALIZE[style], **dict(args.generalize))
    if "d" in opts.get("flags", ""):
        opts.setdefault("map", ",".join(bands[:3]))
    figures["options"]["generalize"] = opts
    run("v.histo.generalize", raster="classes", **{"class": BUILDING}, output="plots", quiet=True,
        **opts)
    opts = dict(SUBDIVIDE[style], **dict(args.subdivide))
    figures["drawn_lines"] = has_option("v.histo.subdivide", "map")
    if figures["drawn_lines"]:
        opts.setdefault("map", ",".join(bands[:3]))
    figures["options"]["subdivide"] = opts
    run("v.histo.subdivide", input="plots", output="footprints", seed=1, quiet=True, **opts)
    return figures


def lines_in_blocks(bands, blocks, args):
    """v.histo.subdivide map= -d alone, in the published blocks (``blocks``: their
    labels on the grid) as the plots: how well the lines the map draws are read,
    apart from how well the classification finds the blocks."""
    from reconstruction import grassio

    grassio.write_raster("blocks_true", np.where(blocks > 0, blocks, 0).astype(np.int32),
                         null=0)
    run("r.to.vect", input="blocks_true", output="plots", type="area", quiet=True)
    opts = dict(SUBDIVIDE["venice"], **dict(args.subdivide))
    opts.setdefault("map", ",".join(bands[:3]))
    seconds = run("v.histo.subdivide", input="plots", output="footprints", seed=1, quiet=True,
                  **opts)
    return {"options": {"subdivide": opts}, "drawn_lines": True, "plots": "published blocks",
            "subdivide_seconds": seconds}


def venice(args):
    """The chain on Venice 1808 sample 3, scored against the published parcels."""
    import grass.script as gs

    from real_maps import venice_training_cells
    from reconstruction.generalize import assessment

    bands = import_bands(os.path.join(args.data, VENICE_SCAN), "venice")
    truth_bands = import_bands(os.path.join(args.data, VENICE_TRUTH), "truth")
    gs.run_command("g.region", raster=bands[0], quiet=True)
    rgb, truth = read_stack(bands[:3]), read_stack(truth_bands[:1])[..., 0]
    radius = CLOSE_METRES / gs.region()["ewres"]
    parcels = assessment.parcels_from_mask(truth)
    blocks = assessment.blocks_from_parcels(parcels, radius)
    if args.published_blocks:
        figures = lines_in_blocks(bands, blocks, args)
        cells = None
    else:
        cells = venice_training_cells(rgb, truth, seed=args.seed, per_class=args.per_class)
        figures = chain("venice", bands, write_training(cells), args)
    plots, footprints = rasterised("plots"), rasterised("footprints")
    figures["blocks"] = assessment.object_scores(plots, blocks).__dict__
    figures["parcels"] = assessment.parcel_scores(footprints, parcels, blocks).__dict__
    figures["training_points"] = int(len(cells.labels)) if cells is not None else 0
    figures["megapixels"] = rgb.shape[0] * rgb.shape[1] / 1e6
    if args.picture:
        picture(rgb, footprints, args.picture)
    return figures


def sanborn(args):
    """The chain on a window of the Sanborn 1892 sheet; the footprints counted."""
    import grass.script as gs

    from real_maps import sanborn_training_cells

    bands = import_bands(os.path.join(args.data, SANBORN_SCAN), "sanborn")
    col, row, size = args.window
    r = gs.region()
    north, west = r["n"] - row * r["nsres"], r["w"] + col * r["ewres"]
    gs.run_command("g.region", n=north, s=north - size * r["nsres"], w=west,
                   e=west + size * r["ewres"], align=bands[0], quiet=True)
    rgba = read_stack(bands)
    cells = sanborn_training_cells(rgba, seed=args.seed, per_class=args.per_class)
    figures = chain("sanborn", bands, write_training(cells), args)
    footprints = rasterised("footprints")
    ids, counts = np.unique(footprints[footprints > 0], return_counts=True)
    figures["window"] = {"col": col, "row": row, "size": size}
    figures["footprints"] = int(len(ids))
    figures["plots"] = int(len(np.unique(rasterised("plots"))) - 1)
    figures["training_points"] = int(len(cells.labels))
    if args.picture:
        picture(rgba[..., :3], footprints, args.picture)
    return figures


def picture(rgb, labels, path):
    """The footprints' outlines (labels' edges, red) over the scan, as a PNG at ``path``."""
    from PIL import Image

    edge = np.zeros(labels.shape, dtype=bool)
    edge[1:, :] |= labels[1:, :] != labels[:-1, :]
    edge[:, 1:] |= labels[:, 1:] != labels[:, :-1]
    out = np.array(rgb, dtype=np.uint8)
    out[edge] = (220, 0, 0)
    Image.fromarray(out).save(path)


def _key_values(text):
    return [tuple(part.split("=", 1)) for part in text] if text else []


def parse(argv):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("style", choices=("venice", "sanborn"))
    parser.add_argument("report", help="JSON file of the figures")
    parser.add_argument("--data", default=MAPS, help="the maps folder (../shared/data/maps)")
    parser.add_argument("--window", type=lambda t: tuple(int(v) for v in t.split(",")),
                        help="sanborn: COL,ROW,SIZE in cells of the 0.25 m warp")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--per-class", type=int, default=15)
    parser.add_argument("--published-blocks", action="store_true",
                        help="venice: the published blocks as the plots, v.histo.subdivide "
                        "map= alone (the lines read, apart from the classification)")
    parser.add_argument("--picture", help="a PNG of the footprints over the scan (outside the "
                        "repository)")
    for stage in ("classify", "generalize", "subdivide"):
        parser.add_argument("--" + stage, nargs="*", metavar="KEY=VALUE")
    args = parser.parse_args(argv)
    for stage in ("classify", "generalize", "subdivide"):
        setattr(args, stage, _key_values(getattr(args, stage)))
    return args


def main(argv=None):
    args = parse(argv)
    scan = VENICE_SCAN if args.style == "venice" else SANBORN_SCAN
    problem = missing(os.path.join(args.data, scan))
    if problem:
        print("skipped: " + problem)
        return 0
    if args.style == "sanborn" and not args.window:
        sys.exit("sanborn needs --window COL,ROW,SIZE")
    figures = (venice if args.style == "venice" else sanborn)(args)
    with open(args.report, "w") as f:
        json.dump(figures, f, indent=1, sort_keys=True)
    print(json.dumps(figures, indent=1, sort_keys=True))
    return 0


if __name__ == "__main__":
    sys.exit(main())
