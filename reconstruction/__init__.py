"""Core library of the histo suite: from a scanned historical map to LoD2 buildings.

Pure functions over numpy arrays and shapely geometries, one module per stage:
classification of the map, generalisation of building plots, subdivision of
plots into footprints, roofs and solids, CityJSON. ``grassio`` is the only
module that talks to GRASS.
"""

__version__ = "0.1.0"
