"""Read the reference shapefiles of ../shared/data without GRASS (tests, benchmarks).

GDAL's ``ogr2ogr`` (Debian's gdal-bin, which GRASS depends on) converts a
shapefile to GeoJSON in a temporary folder; shapely reads the geometries.
Column names stay as in the shapefile (``roof-0.25``, not GRASS's
``roof_0_25``).
"""

import json
import os
import shutil
import subprocess
import tempfile

import numpy as np


def have_ogr2ogr():
    return shutil.which("ogr2ogr") is not None


def read_shapefile(path):
    """``(geometries, columns)``: a shapely geometry array and a dict of column
    name -> list of values (None for NULL), one entry per feature."""
    import shapely

    if not have_ogr2ogr():
        raise RuntimeError("ogr2ogr (GDAL) is needed to read '{}'".format(path))
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "layer.geojson")
        subprocess.run(["ogr2ogr", "-f", "GeoJSON", out, path], check=True,
                       capture_output=True)
        with open(out) as f:
            data = json.load(f)
    features = data["features"]
    geoms = shapely.from_geojson([json.dumps(f["geometry"]) for f in features]) \
        if features else np.zeros(0, dtype=object)
    names = []
    for f in features:
        for k in f["properties"]:
            if k not in names:
                names.append(k)
    columns = {k: [f["properties"].get(k) for f in features] for k in names}
    return np.asarray(geoms, dtype=object), columns
