"""GRASS rasters as pictures: the historical map's red, green and blue
rasters read into a :class:`~reconstruction.geom.grid.MapImage` to drape on the
ground of v.histo.lod2's picture (``map=``, :func:`read_map_image`), or cell for
cell in the current region for v.histo.generalize's fit step
(:func:`read_region_image`).

For the picture, the rasters are read over their own extent (not the
computational region), resampled so that the longer side has at most
``max_size`` cells: a picture needs no more, and a scanned map of 20,000
pixels a side would take gigabytes. Values are taken as 0-255 (as ``d.rgb`` shows them); NULL cells
are white.
"""

import math
import os

import numpy as np

import grass.script as gs

from ..core.options import parse_bands
from ..geom.grid import MapImage
from .checks import require_raster
from .maps import read_raster
from .run import doing

#: the longer side of the map picture, in cells
MAX_SIZE = 2048


def _rgb_names(names):
    """The raster names of option map= (red, green, blue; or one, a greyscale
    scan), each checked."""
    names = parse_bands(",".join(n for n in names if n), "map")
    for name in names:
        require_raster(name)
    return names


def _rgb(bands):
    """Bands read as floats (NULL: NaN) as one (rows, cols, 3) uint8 picture, NULL
    white; one band (a greyscale scan) is grey: its value in all three."""
    bands = list(bands) * (3 if len(bands) == 1 else 1)
    return np.rint(np.dstack([np.where(np.isnan(b), 255.0, np.clip(b, 0, 255))
                              for b in bands])).astype(np.uint8)


def read_region_image(names):
    """The :class:`~reconstruction.geom.grid.MapImage` of three rasters (red,
    green, blue), or of one (grey), in the current region, cell for cell (v.histo.generalize's
    fit step)."""
    names = _rgb_names(names)
    with doing("reading the current region"):
        region = gs.region()
    image = _rgb([read_raster(name, np.float64) for name in names])
    return MapImage(image, (float(region["w"]), float(region["e"]), float(region["s"]),
                            float(region["n"])))


def read_map_image(names, max_size=MAX_SIZE):
    """The :class:`~reconstruction.geom.grid.MapImage` of three rasters (red, green, blue)."""
    names = _rgb_names(names)
    with doing("reading the extent of raster map <{}>".format(names[0])):
        info = gs.raster_info(names[0])
    rows, cols = int(info["rows"]), int(info["cols"])
    factor = max(1, math.ceil(max(rows, cols) / float(max_size)))
    rows, cols = max(1, rows // factor), max(1, cols // factor)
    env = os.environ.copy()
    env["GRASS_REGION"] = gs.region_env(n=info["north"], s=info["south"], e=info["east"],
                                        w=info["west"], rows=rows, cols=cols)
    rgb = _rgb([read_raster(name, np.float64, env) for name in names])
    extent = (float(info["west"]), float(info["east"]), float(info["south"]),
              float(info["north"]))
    return MapImage(rgb, extent)
