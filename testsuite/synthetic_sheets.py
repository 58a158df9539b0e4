#!/usr/bin/env python3
"""Adjacent map sheets of one synthetic town: a map series (issue 30).

:func:`synthetic_map.generate` draws one town; :func:`cut` cuts it into a
grid of sheets that share their edges (no overlap, as the sheets of a real
series), so plots cross the edges. Each sheet is written as files, as a
scanned sheet and its data would come (:func:`write`): the picture as an
ENVI raster (three bands of bytes, header with the sheet's corner and pixel
size; GDAL reads it), the training points that fall on the sheet and today's
footprints over it (with a margin) as GeoJSON, and a manifest of the series
(``series.json``, read by ``reconstruction.series.manifest``). No GRASS
needed::

    python3 testsuite/synthetic_sheets.py OUT --seed 1 --size 400 --sheet 200 --sheets 0,0 1,0 0,1

Also the truth for the tests: the true plots of the whole town
(``plots.geojson``).
"""

import argparse
import json
import os
import sys

import numpy as np
import shapely
from shapely.geometry import box, mapping

import synthetic_map

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
from reconstruction.series.manifest import MARGIN  # noqa: E402


def sheet_box(smap, column, row, side):
    """The (west, south, east, north) of sheet (column, row) of ``side`` metres,
    counted from the town's south-west corner."""
    west, south = smap.west + column * side, smap.south + row * side
    return (west, south, west + side, south + side)


def _window(smap, extent):
    """The rows and columns of the sheet ``extent`` in the town's arrays."""
    west, south, east, north = extent
    c0, c1 = int(round((west - smap.west) / smap.res)), int(round((east - smap.west) / smap.res))
    r0, r1 = int(round((smap.north - north) / smap.res)), int(round((smap.north - south) / smap.res))
    return slice(r0, r1), slice(c0, c1)


def sheet_training(smap, extent, seed):
    """Training points of one sheet, picked on the sheet as the town's are on
    the town (3-8 per class on clean pixels, spread out; text and symbols on
    black ink): every sheet of a series comes with its own. ``seed``: the
    sheet's own random stream. Returns (xy (n, 2), labels (n,))."""
    rows, cols = _window(smap, extent)
    drawn = smap.drawn[rows, cols]
    ink = smap.ink_cover[rows, cols]
    cover = {label: (drawn == label).astype(float) for label in synthetic_map.CLASSES}
    for label in (synthetic_map.TEXT, synthetic_map.SYMBOL):
        cover[label] = np.where(drawn == label, ink, 0.0)
    west, north = extent[0], extent[3]

    def xy_of(r, c):
        return (west + (c + 0.5) * smap.res, north - (r + 0.5) * smap.res)

    return synthetic_map._pick_training(np.random.default_rng(seed), drawn, cover, xy_of)


def write_envi(path, rgb, extent, res):
    """A three-band byte raster (band sequential) with its ENVI header."""
    west, _, _, north = extent
    rows, cols = rgb.shape[:2]
    with open(path, "wb") as f:
        f.write(np.ascontiguousarray(np.moveaxis(rgb, 2, 0), dtype=np.uint8).tobytes())
    with open(os.path.splitext(path)[0] + ".hdr", "w", encoding="ascii") as f:
        f.write("ENVI\nsamples = {}\nlines = {}\nbands = 3\nheader offset = 0\n"
                "file type = ENVI Standard\ndata type = 1\ninterleave = bsq\nbyte order = 0\n"
                "map info = {{Arbitrary, 1, 1, {}, {}, {}, {}}}\n"
                "band names = {{red, green, blue}}\n".format(cols, rows, west, north, res, res))


def write_geojson(path, geometries, properties):
    """Features of shapely ``geometries`` with ``properties`` (name -> values)."""
    names = list(properties)
    features = [{"type": "Feature", "geometry": mapping(g),
                 "properties": {n: properties[n][k] for n in names}}
                for k, g in enumerate(geometries)]
    with open(path, "w", encoding="utf-8") as f:
        json.dump({"type": "FeatureCollection", "features": features}, f)


def write(out, smap, sheets, side, margin=MARGIN, year=synthetic_map.MAP_YEAR):
    """Write every sheet (column, row) of ``sheets`` into ``out`` and the
    manifest ``out/series.json``; returns the manifest's path."""
    os.makedirs(out, exist_ok=True)
    current = smap.current
    heights = synthetic_map.measured_heights(smap)
    entries = []
    for column, row in sheets:
        name = "sheet_{}_{}".format(column, row)
        extent = sheet_box(smap, column, row, side)
        rows, cols = _window(smap, extent)
        write_envi(os.path.join(out, name + ".map.bsq"), smap.rgb[rows, cols], extent, smap.res)
        xy, labels = sheet_training(smap, extent, [smap.seed, 30, column, row])
        write_geojson(os.path.join(out, name + ".training.geojson"),
                      [shapely.Point(p) for p in xy],
                      {"label": [int(v) for v in labels],
                       "class": [synthetic_map.CLASSES[int(v)] for v in labels]})
        near = box(*extent).buffer(margin, join_style="mitre")
        chosen = [k for k, p in enumerate(current.polygons) if p.intersects(near)]
        write_geojson(os.path.join(out, name + ".current.geojson"),
                      [current.polygons[k] for k in chosen],
                      dict({"bouwjaar": [current.years[k] for k in chosen],
                            "identificatie": [current.ids[k] for k in chosen]},
                           **{c: [v[k] for k in chosen] for c, v in heights.items()}))
        # the print removed where the sheet has training points of it
        printed = sorted({int(v) for v in labels} & {synthetic_map.TEXT, synthetic_map.SYMBOL})
        entries.append({"name": name, "map": name + ".map.bsq",
                        "training": name + ".training.geojson",
                        "footprints": name + ".current.geojson",
                        "extent": [round(v, 3) for v in extent], "year": year,
                        "options": {"remove": ",".join(map(str, printed))}})
    write_geojson(os.path.join(out, "plots.geojson"), smap.plots,
                  {"kind": list(smap.plot_kinds)})
    manifest = {"epsg": 28992, "margin": margin, "seed": smap.seed, "sheets": entries}
    path = os.path.join(out, "series.json")
    with open(path, "w", encoding="utf-8") as f:
        json.dump(manifest, f, indent=1)
    return path


def main(argv=None):
    parser = synthetic_map.map_arguments("Write adjacent sheets of one synthetic town as files "
                                         "and the manifest of their series.")
    parser.add_argument("out", help="folder of the sheets")
    parser.add_argument("--sheet", type=float, default=200.0, help="side of a sheet (m)")
    parser.add_argument("--margin", type=float, default=MARGIN,
                        help="margin each sheet's chain reads from its neighbours (m)")
    parser.add_argument("--sheets", nargs="+", default=None,
                        help="sheets as COLUMN,ROW (default: the whole grid)")
    args = parser.parse_args(argv)
    smap = synthetic_map.generate(seed=args.seed, size=args.size, res=args.res)
    n = int(args.size * args.res // args.sheet)
    sheets = ([tuple(int(v) for v in s.split(",")) for s in args.sheets] if args.sheets
              else [(c, r) for r in range(n) for c in range(n)])
    path = write(args.out, smap, sheets, args.sheet, args.margin)
    print("{} sheets written; manifest '{}'".format(len(sheets), path))
    return 0


if __name__ == "__main__":
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    sys.exit(main())
