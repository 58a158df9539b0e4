"""CityJSON 2.0: the generated model written, an existing model read and merged.

- ``model``: the CityJSON document of many LoD2 solids (one ``Building``
  each, semantic surfaces, integer vertices on a millimetre ``transform``),
  written whole; its consistency and schema checks;
- ``seq``: the same as CityJSONSeq, one ``CityJSONFeature`` per building;
- ``geometry``: walking and writing the boundaries of CityJSON geometries;
- ``existing``: an existing model (CityJSON or CityJSONSeq, e.g. the 3D BAG)
  read, its buildings' footprints and measured heights, matched with footprints;
- ``copied``: matched buildings copied onto the output's grid;
- ``merge``: the copied buildings merged into the generated model;
- ``versions``: the suite's CityJSON Extension of a city over time
  (``histo_versions.ext.json``: a building's versions, their transitions and
  paradata), read by the schema check of ``model``.
"""

from . import copied, existing, geometry, merge, model, seq, versions
from .copied import CopiedBuildings, CopyReport, copy_buildings
from .existing import ExistingModel, read_model
from .merge import merge as merge_models
from .model import CITYJSON_VERSION, citymodel, citymodel_text, schema_errors

__all__ = ["CITYJSON_VERSION", "CopiedBuildings", "CopyReport", "ExistingModel", "citymodel",
           "citymodel_text", "copied", "copy_buildings", "existing", "geometry", "merge",
           "merge_models", "model", "read_model", "schema_errors", "seq", "versions"]
