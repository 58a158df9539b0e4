"""Stage 5, v.histo.lod2: footprints with heights -> valid LoD2 solids -> CityJSON.

The thesis's Section 3.4: each footprint gets its heights (measured, from a
DTM or points, or inferred from its neighbours), its street edge (where
gable ends and stepped facades face the street), a roof type drawn for the
map's date, and a closed, valid solid built in bulk in numpy; the buildings
that still stand are copied from a current 3D model; the model is written
as CityJSON or CityJSONSeq, and drawn.

The module script's three calls:

- :func:`read_config` (``config``): the options as one frozen
  :class:`Lod2Config` (roof parameters, height, street and output
  sub-configs, the existing model to copy from);
- :func:`run` (``pipeline``): the whole stage on :class:`Lod2Inputs` (the
  script's readers of GRASS maps), returning a :class:`Lod2Run`;
- :func:`report` (``report``): the messages of the finished run (each
  step's messages are printed as it is done), and :func:`validity_lines`
  the -v report's lines.

The parts:

- ``stage``: :func:`prepare` and :func:`build`, the buildings of footprints
  with :class:`Heights` and :class:`RoofRequests` (a :class:`Lod2Result`);
- ``inputs``: reference heights and street edges added to the footprints;
  ``heights``, ``neighbourhood``, ``street_edges``: how they are found;
- ``outlines``: the rings buildings stand on, and what roofs know of them;
- ``roofs``: the roof families; ``solids``: solids built and validated;
- ``output``: existing models matched and copied, the model written;
  ``render``: its picture.
"""

from . import (config, groupstats, heights, inputs, neighbourhood, outlines, output, pipeline,
               render, report, roofs, solids, stage, street_edges)
from .config import (ExistingRequest, HeightConfig, Lod2Config, OutputRequest, StreetConfig,
                     read_config)
from .pipeline import Lod2Inputs, Lod2Run, run
from .report import report, validity_lines
from .stage import Footprints, Heights, Lod2Result, RoofRequests, Uniform, build, prepare

__all__ = ["ExistingRequest", "Footprints", "HeightConfig", "Heights", "Lod2Config",
           "Lod2Inputs", "Lod2Result", "Lod2Run", "OutputRequest", "RoofRequests",
           "StreetConfig", "Uniform", "build", "config", "groupstats", "heights", "inputs",
           "neighbourhood", "outlines", "output", "pipeline", "prepare", "read_config", "render",
           "report", "roofs", "run", "solids", "stage", "street_edges", "validity_lines"]
