"""Geometry every stage shares: rings, polygons, overlaps, grids and solids.

- ``rings``: many rings (faces, solids) as flat arrays and their index helpers;
- ``polygons``: the polygons of any shapely geometry, repaired and exploded;
- ``overlaps``: overlapping geometries made disjoint, the policy an
  :class:`OverlapRule`;
- ``grid``: a raster as a numpy array with its place on the ground
  (:class:`Grid`), a map picture (:class:`MapImage`), the box an input
  covers (:class:`Extent`);
- ``registration``: a scan's colour planes moved back by the whole cells
  one lies off the others (:func:`~reconstruction.geom.registration.band_shifts`);
- ``strokes``: the width of a map's drawn strokes from a mask of its ink;
- ``solidset``: many LoD2 solids as flat numpy arrays (:class:`SolidSet`) and
  their semantic surfaces.
"""

from . import grid, overlaps, polygons, registration, rings, solidset, strokes
from .grid import Extent, Grid, MapImage
from .overlaps import OverlapRule, resolve_overlaps
from .solidset import SolidSet

__all__ = ["Extent", "Grid", "MapImage", "OverlapRule", "SolidSet", "grid", "overlaps",
           "polygons", "registration", "resolve_overlaps", "rings", "solidset", "strokes"]
