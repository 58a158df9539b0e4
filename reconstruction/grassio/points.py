"""GRASS readers of the LoD2 stage's extra inputs: 3D points and rasters near footprints.

The GRASS side of :mod:`reconstruction.lod2.inputs` (which is pure): 3D
point maps (ground or building points, e.g. imported with v.in.pdal or
v.in.ascii -z) as an (N, 3) array, and rasters (a DTM, r.histo.classify's
classes) as a :class:`~reconstruction.geom.grid.Grid` read at their own
resolution over the footprints' extent grown by a margin (a temporary
region; the user's region is left alone).
"""

import os
import shutil

import numpy as np

import grass.script as gs

from ..core.errors import InputError
from ..geom.grid import Grid
from .temp import temp_file
from .maps import read_raster
from .run import doing


def start_read_points(name, layer=-1):
    """Start exporting the points of vector map ``name`` in the background (a
    million points take seconds); :func:`finish_read_points` waits for them.
    None when ``name`` is empty."""
    if not name:
        return None
    outdir = os.path.dirname(temp_file())     # removed at exit, whatever happens
    os.makedirs(outdir, exist_ok=True)
    procs = {}
    for key, (cmd, kw) in {
            "points": ("v.out.ascii", dict(input=name, layer=layer, type="point",
                                           format="point", separator="space")),
            "topo": ("v.info", dict(map=name, flags="t"))}.items():
        with open(os.path.join(outdir, key), "wb") as out, \
                open(os.path.join(outdir, key + ".err"), "wb") as err:
            procs[key] = gs.start_command(cmd, quiet=True, stdout=out, stderr=err, **kw)
    return {"name": name, "dir": outdir, "procs": procs}


def finish_read_points(job):
    """The points of a :func:`start_read_points` job as an (N, 3) array of x, y, z.

    Raises :class:`InputError` when the map is missing, 2D (no heights) or has no points.
    """
    if job is None:
        return None
    name, outdir = job["name"], job["dir"]
    try:
        text = {}
        for key, proc in job["procs"].items():
            proc.wait()
            with open(os.path.join(outdir, key), "rb") as f:
                text[key] = gs.decode(f.read())
            if proc.returncode != 0:
                if not gs.find_file(name, element="vector")["fullname"]:
                    raise InputError("Vector map <{}> not found".format(name))
                with open(os.path.join(outdir, key + ".err"), "rb") as f:
                    raise InputError("Cannot read the points <{}>: {}".format(
                        name, gs.decode(f.read()).strip()))
    finally:
        shutil.rmtree(outdir, ignore_errors=True)
    info = gs.parse_key_val(text["topo"])
    if int(info.get("map3d", 0)) != 1:
        raise InputError("Vector map <{}> is 2D: give 3D points (e.g. v.in.pdal, or "
                         "v.in.ascii -z)".format(name))
    if int(info.get("points", 0)) == 0:
        raise InputError("Vector map <{}> has no points".format(name))
    return parse_points(text["points"])


def read_points_3d(name, layer=-1):
    """The points of vector map ``name`` as an (N, 3) array of x, y, z (see
    :func:`finish_read_points`)."""
    with doing("reading the 3D points <{}>".format(name)):
        return finish_read_points(start_read_points(name, layer))


def parse_points(text):
    """x, y, z of ``v.out.ascii format=point`` lines (``x y z [cat]``) as (N, 3)."""
    first = text[:text.find("\n")] if "\n" in text else text
    width = len(first.split())
    if not width:
        return np.zeros((0, 3))
    values = np.fromstring(text, sep=" ")
    if width < 3 or values.size % width or values.size // width != text.count("\n") + \
            (0 if text.endswith("\n") else 1):
        # points with and without categories mixed: line by line
        rows = [ln.split()[:3] for ln in text.splitlines() if len(ln.split()) >= 3]
        return np.array(rows, dtype=float).reshape(-1, 3)
    return values.reshape(-1, width)[:, :3]


def read_grid(name, bounds, margin):
    """Raster ``name`` as a :class:`Grid` at its own resolution, over ``bounds``
    (x0, y0, x1, y1) grown by ``margin`` map units; NULL -> NaN."""
    x0, y0, x1, y1 = (float(v) for v in bounds)
    with doing("reading raster map <{}>".format(name)):
        gs.use_temp_region()
        try:
            gs.run_command("g.region", n=y1 + margin, s=y0 - margin, e=x1 + margin,
                           w=x0 - margin, align=name, quiet=True)
            region = gs.region()
            values = read_raster(name)
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
