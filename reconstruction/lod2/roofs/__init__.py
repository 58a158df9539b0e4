"""The roof families of LoD2 buildings: flat, hip, gable, mansard, crow-stepped gable.

- ``model``: the types roofs travel in (:class:`RoofConfig`, a roof, roofs in bulk);
- ``plan``: which footprint gets which roof, and all roofs made in bulk
  (:func:`make_roofs`);
- ``envelope``: roofs of convex footprints, the lower envelope of their edge
  planes; ``skeleton``: roofs of any footprint, CGAL's weighted straight
  skeleton; ``facades``: crow-stepped and other gable facades;
- ``rules``: roof types by construction period and footprint shape, from a
  rules file.

A new roof family is a new module here, planned in ``plan``.
"""

from . import envelope, facades, model, plan, rules, skeleton
from .model import RoofConfig
from .plan import ROOF_TYPES, make_roofs
from .rules import read_rules

__all__ = ["ROOF_TYPES", "RoofConfig", "envelope", "facades", "make_roofs", "model", "plan",
           "read_rules", "rules", "skeleton"]
