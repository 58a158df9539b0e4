"""LoD2 solids: footprint, heights and roof -> one closed, valid shell each.

- ``build``: walls and ground put under the roofs, rounded to the millimetre
  grid, validated, a roof that fails replaced by a simpler one
  (:func:`build_solids`);
- ``validation``: the checks val3dity makes of a solid (:func:`validate`);
- ``vertex_budget``: footprints of many vertices simplified for pitched roofs.
"""

from . import build, validation, vertex_budget
from .build import Buildings, build_solids
from .validation import validate

__all__ = ["Buildings", "build", "build_solids", "validate", "validation", "vertex_budget"]
