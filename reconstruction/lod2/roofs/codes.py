"""Standard names of the suite's roof types: OSM, CityGML 2.0, ALKIS, and
the profile of the gable on the street.

Each roof type of :data:`~reconstruction.lod2.roofs.plan.ROOF_TYPES` has

- an OpenStreetMap ``roof:shape`` value (Simple 3D Buildings: flat, gabled,
  hipped, half-hipped, pyramidal, gambrel, mansard, skillion);
- a CityGML 2.0 ``bldg:roofType`` code, from SIG3D's code list for
  ``_AbstractBuilding_roofType`` (1000 flat, 1010 monopitch, 1030 gabled,
  1040 hipped, 1050 half-hipped, 1060 mansard, 1070 pavilion);
- a German ALKIS ``Dachform`` code (1000 Flachdach, 2100 Pultdach,
  3100 Satteldach, 3200 Walmdach, 3300 Krüppelwalmdach, 3400 Mansardendach,
  3500 Zeltdach);
- the profile of its gable on the street edge: ``plain`` (a straight gable),
  ``stepped`` (crow-stepped, trapgevel), ``neck`` (halsgevel), ``bell``
  (klokgevel), ``spout`` (tuitgevel), ``cornice`` (a straight cornice
  facade, lijstgevel, in front of a ridge along the street), or empty for
  the roofs without a gable (flat, hip, mansard, pyramid, shed).

Gambrel and mansard roofs share CityGML's and ALKIS's mansard code (German
"Mansarddach" is both the gambrel, Mansardgiebeldach, and the hipped
mansard, Mansardwalmdach); OSM tells them apart.
"""

from dataclasses import dataclass


@dataclass(frozen=True)
class RoofCode:
    """The standard names of one roof type."""

    #: OpenStreetMap ``roof:shape``
    osm: str
    #: CityGML 2.0 ``roofType`` code (SIG3D code list)
    citygml: str
    #: ALKIS ``Dachform`` code
    alkis: str
    #: the gable's profile on the street edge ("" = no gable)
    profile: str


ROOF_CODES = {
    "flat": RoofCode("flat", "1000", "1000", ""),
    "hip": RoofCode("hipped", "1040", "3200", ""),
    "gable": RoofCode("gabled", "1030", "3100", "plain"),
    "mansard": RoofCode("mansard", "1060", "3400", ""),
    "stepped": RoofCode("gabled", "1030", "3100", "stepped"),
    "half_hip": RoofCode("half-hipped", "1050", "3300", "plain"),
    "pyramid": RoofCode("pyramidal", "1070", "3500", ""),
    "gambrel": RoofCode("gambrel", "1060", "3400", "plain"),
    "shed": RoofCode("skillion", "1010", "2100", ""),
    "cornice": RoofCode("gabled", "1030", "3100", "cornice"),
    "neck": RoofCode("gabled", "1030", "3100", "neck"),
    "bell": RoofCode("gabled", "1030", "3100", "bell"),
    "spout": RoofCode("gabled", "1030", "3100", "spout"),
}

#: the attributes a building carries its roof's codes in, and the field of each
CODE_ATTRIBUTES = (("roof_shape", "osm"), ("citygml_roof_type", "citygml"),
                   ("alkis_roof_form", "alkis"), ("gable_profile", "profile"))


def code_attributes(roof_types):
    """{attribute: per building value} of the codes of ``roof_types``."""
    codes = [ROOF_CODES[t] for t in roof_types]
    return {name: [getattr(c, field) for c in codes] for name, field in CODE_ATTRIBUTES}
