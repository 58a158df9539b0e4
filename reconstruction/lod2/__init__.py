"""Stage 5, v.histo.lod2: footprints with heights -> valid LoD2 solids -> CityJSON.

The thesis's Section 3.4: each footprint gets its heights (measured, from a
DTM or points, or inferred from its neighbours), its street edge (where
gable ends and stepped facades face the street), a roof type drawn for the
map's date, and a closed, valid solid built in bulk in numpy; the buildings
that still stand are copied from a current 3D model; the model is written
as CityJSON or CityJSONSeq, and drawn.

- ``stage``: the stage's entry point (:func:`build_model`, or
  :func:`prepare` and :func:`build`);
- ``inputs``: reference heights and street edges added to the footprints;
  ``heights``, ``neighbourhood``, ``street_edges``: how they are found;
- ``outlines``: the rings buildings stand on, and what roofs know of them;
- ``roofs``: the roof families; ``solids``: solids built and validated;
- ``output``: existing models matched and copied, the model written;
  ``render``: its picture.
"""

from . import (groupstats, heights, inputs, neighbourhood, outlines, output, render, roofs,
               solids, stage, street_edges)
from .stage import Lod2Config, Lod2Result, build, build_model, prepare

__all__ = ["Lod2Config", "Lod2Result", "build", "build_model", "groupstats", "heights",
           "inputs", "neighbourhood", "outlines", "output", "prepare", "render", "roofs",
           "solids", "stage", "street_edges"]
