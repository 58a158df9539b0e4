"""The GRASS side of the suite: the only package that imports ``grass.script``.

Module scripts reach GRASS through these names only (``from reconstruction
import grassio``; ``grassio.read_areas(...)``):

- ``maps``: rasters <-> numpy arrays, vectors <-> shapely geometries and
  attribute columns, every output map written under a temporary name and
  renamed into place;
- ``run``: the one error convention (:func:`run_main`, :func:`doing`,
  :func:`finish_tool`): an ``InputError``, a failing child tool, Ctrl-C or
  SIGTERM become one ``ERROR:`` line; :func:`say` prints a stage's report;
- ``temp``: temporary maps and files removed at exit, outputs ``staged``;
- ``checks``: the checks of inputs and outputs before any work;
- ``points``: 3D point maps and rasters near footprints (v.histo.lod2);
- ``images``: the map's colour rasters as a picture (v.histo.lod2 ``map=``,
  v.histo.generalize's fit step);
- ``bands``: the map's colour rasters registered to each other
  (r.histo.classify: :func:`read_band_shifts`, :func:`registered_bands`);
- ``tiles``: i.segment runs on tiles and windows (r.histo.classify).
"""

from .bands import read_band_shifts, registered_bands
from .checks import (check_outputs, given, location_epsg, prefetch_checks, projection,
                     require_columns, require_features, require_new_file, require_projected,
                     require_raster, require_vector, vector_counts)
from .images import read_map_image, read_region_image
from .maps import (area_boundaries, cat_ranges, column_names, finish_read_areas, raster_region_matches,
                   read_areas, read_features, read_points, read_raster, read_table,
                   start_read_areas, write_areas, write_features, write_points, write_raster)
from .points import (finish_read_points, parse_points, raster_labels, read_grid,
                     read_points_3d, start_read_points)
from .run import Terminated, doing, failure_message, finish_tool, run_main, say
from .temp import (forget_temp_map, is_temp_map, output_name, register_cleanup, rename_map,
                   staged, stop_children, temp_file, temp_map, uninterrupted)
from .tiles import run_segmentations, segment_tiles, window_criteria, window_env

__all__ = [
    "read_band_shifts", "registered_bands",
    "check_outputs", "given", "location_epsg", "prefetch_checks", "projection",
    "require_columns", "require_features", "require_new_file", "require_projected",
    "require_raster", "require_vector", "vector_counts",
    "read_map_image", "read_region_image",
    "area_boundaries", "cat_ranges", "column_names", "finish_read_areas",
    "raster_region_matches", "read_areas", "read_features", "read_points", "read_raster",
    "read_table", "start_read_areas", "write_areas", "write_features", "write_points",
    "write_raster",
    "finish_read_points", "parse_points", "raster_labels", "read_grid", "read_points_3d",
    "start_read_points",
    "Terminated", "doing", "failure_message", "finish_tool", "run_main", "say",
    "forget_temp_map", "is_temp_map", "output_name", "register_cleanup", "rename_map",
    "staged", "stop_children", "temp_file", "temp_map", "uninterrupted",
    "run_segmentations", "segment_tiles", "window_criteria", "window_env",
]
