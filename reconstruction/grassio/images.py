"""GRASS rasters as pictures: the historical map's red, green and blue
rasters read into a :class:`~reconstruction.geom.grid.MapImage` to drape on the
ground of v.histo.lod2's picture (``map=``).

The rasters are read over their own extent (not the computational region),
resampled so that the longer side has at most ``max_size`` cells: a picture
needs no more, and a scanned map of 20,000 pixels a side would take
gigabytes. Values are taken as 0-255 (as ``d.rgb`` shows them); NULL cells
are white.
"""

import math
import os

import numpy as np

import grass.script as gs

from ..core.errors import InputError
from ..geom.grid import MapImage
from .checks import require_raster
from .maps import read_raster
from .run import doing

#: the longer side of the map picture, in cells
MAX_SIZE = 2048


def read_map_image(names, max_size=MAX_SIZE):
    """The :class:`~reconstruction.geom.grid.MapImage` of three rasters (red, green, blue)."""
    names = [n for n in names if n]
    if len(names) != 3:
        raise InputError("Option map= needs three rasters: red, green and blue, not {}".format(
            len(names)))
    for name in names:
        require_raster(name)
    with doing("reading the extent of raster map <{}>".format(names[0])):
        info = gs.raster_info(names[0])
    rows, cols = int(info["rows"]), int(info["cols"])
    factor = max(1, math.ceil(max(rows, cols) / float(max_size)))
    rows, cols = max(1, rows // factor), max(1, cols // factor)
    env = os.environ.copy()
    env["GRASS_REGION"] = gs.region_env(n=info["north"], s=info["south"], e=info["east"],
                                        w=info["west"], rows=rows, cols=cols)
    bands = []
    for name in names:
        values = read_raster(name, np.float64, env)
        bands.append(np.where(np.isnan(values), 255.0, np.clip(values, 0, 255)))
    rgb = np.rint(np.dstack(bands)).astype(np.uint8)
    extent = (float(info["west"]), float(info["east"]), float(info["south"]),
              float(info["north"]))
    return MapImage(rgb, extent)
