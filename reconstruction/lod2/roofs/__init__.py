"""The roof families of LoD2 buildings: flat, hip, gable, mansard, crow-stepped,
neck, bell and spout gables, half-hip, pyramid, gambrel, shed, and the ridge
along the street behind a cornice.

- ``model``: the types roofs travel in (:class:`RoofConfig`, a roof, roofs in bulk);
- ``plan``: which footprint gets which roof, and all roofs made in bulk
  (:func:`make_roofs`);
- ``envelope``: roofs of convex footprints, the lower envelope of their edge
  planes and raised planes (half-hip, gambrel); ``skeleton``: roofs of any
  footprint, CGAL's weighted straight skeleton; ``staged``: two-slope roofs
  of any footprint in two stages of it; ``pyramid``, ``shed``: those roofs
  in bulk; ``facades``: crow-stepped and other gable facades;
- ``codes``: each roof type's OSM, CityGML and ALKIS names and gable profile;
- ``rules``: roof types by construction period, footprint shape and span,
  from a rules file.

A new roof family is a new module here, planned in ``plan``.
"""

from . import codes, envelope, facades, model, plan, pyramid, rules, shed, skeleton, staged
from .model import RoofConfig
from .plan import ROOF_TYPES, make_roofs
from .rules import read_rules

__all__ = ["ROOF_TYPES", "RoofConfig", "codes", "envelope", "facades", "make_roofs", "model",
           "plan", "pyramid", "read_rules", "rules", "shed", "skeleton", "staged"]
