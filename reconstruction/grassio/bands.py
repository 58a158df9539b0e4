"""A scanned map's colour rasters registered to each other in GRASS
(r.histo.classify): the shifts are estimated on the map's central window
(:func:`~reconstruction.geom.registration.band_shifts`), and each band found a
whole cell off the others is moved back into a temporary raster by r.mapcalc
(``out = band[rows,cols]``; along the map's edge, where there is nothing to
take, a cell keeps its own value) in the current region; the others are
used as they are.
"""

import numpy as np

import grass.script as gs

from ..geom.registration import band_shifts, central_window
from .maps import read_raster
from .run import doing
from .temp import temp_map
from .tiles import cells_env

def read_band_shifts(names, grid):
    """The :class:`~reconstruction.geom.registration.BandShifts` of the rasters
    ``names``, estimated on the central window of ``grid`` (only that window is
    read)."""
    row0, row1, col0, col1 = central_window((grid.rows, grid.cols))
    env = cells_env(grid, row0, row1, col0, col1)
    return band_shifts([read_raster(name, np.float64, env) for name in names])


def registered_bands(names, shifts):
    """The rasters to read in place of ``names``: each band ``shifts`` moves,
    moved back into a temporary raster (removed at exit), the others as they are."""
    out = list(names)
    for i in shifts.moved:
        dr, dc = shifts.shifts[i]
        out[i] = temp_map("raster", "registered")
        with doing("moving raster map <{}> back by {} rows, {} columns".format(
                names[i], dr, dc)):
            moved = "{}[{},{}]".format(names[i], dr, dc)
            gs.run_command("r.mapcalc", expression="{} = if(isnull({}), {}, {})".format(
                out[i], moved, names[i], moved), quiet=True)
    return out
