"""GRASS readers of the LoD2 stage's extra inputs: 3D points and rasters near footprints.

The GRASS side of :mod:`reconstruction.lod2_inputs` (which is pure): 3D
point maps (ground or building points, e.g. imported with v.in.pdal or
v.in.ascii -z) as an (N, 3) array, and rasters (a DTM, r.histo.classify's
classes) as a :class:`~reconstruction.grid.Grid` read at their own
resolution over the footprints' extent grown by a margin (a temporary
region; the user's region is left alone).
"""

import numpy as np

import grass.script as gs

from .errors import InputError
from .grassrun import doing
from .grid import Grid


def read_points_3d(name, layer=-1):
    """The points of vector map ``name`` as an (N, 3) array of x, y, z.

    Raises :class:`InputError` when the map is 2D (no heights) or has no points.
    """
    with doing("reading the 3D points <{}>".format(name)):
        info = gs.vector_info_topo(name)
        if int(info.get("map3d", 0)) != 1:
            raise InputError("Vector map <{}> is 2D: give 3D points (e.g. v.in.pdal, or "
                             "v.in.ascii -z)".format(name))
        if int(info.get("points", 0)) == 0:
            raise InputError("Vector map <{}> has no points".format(name))
        text = gs.read_command("v.out.ascii", input=name, layer=layer, type="point",
                               format="point", separator="space", quiet=True)
    return parse_points(text)


def parse_points(text):
    """x, y, z of ``v.out.ascii format=point`` lines (``x y z [cat]``) as (N, 3)."""
    lines = text.splitlines()
    if not lines:
        return np.zeros((0, 3))
    width = len(lines[0].split())
    values = np.array(text.split(), dtype=float)
    if width < 3 or values.size % width:
        # points with and without categories mixed: line by line
        rows = [ln.split()[:3] for ln in lines if len(ln.split()) >= 3]
        return np.array(rows, dtype=float).reshape(-1, 3)
    return values.reshape(-1, width)[:, :3]


def read_grid(name, bounds, margin):
    """Raster ``name`` as a :class:`Grid` at its own resolution, over ``bounds``
    (x0, y0, x1, y1) grown by ``margin`` map units; NULL -> NaN."""
    from grass.script import array as garray

    x0, y0, x1, y1 = (float(v) for v in bounds)
    with doing("reading raster map <{}>".format(name)):
        gs.use_temp_region()
        try:
            gs.run_command("g.region", n=y1 + margin, s=y0 - margin, e=x1 + margin,
                           w=x0 - margin, align=name, quiet=True)
            region = gs.region()
            values = np.array(garray.array(mapname=name, dtype=np.float64, null=np.nan))
        finally:
            gs.del_temp_region()
    return Grid.from_region(values, region)


def raster_labels(name):
    """Category label -> category value of a raster (r.category), empty when it has none."""
    with doing("reading the categories of raster map <{}>".format(name)):
        text = gs.read_command("r.category", map=name, separator="tab", quiet=True)
    out = {}
    for line in text.splitlines():
        value, _, label = line.partition("\t")
        if label.strip():
            try:
                out[label.strip()] = int(float(value))
            except ValueError:
                continue
    return out
