"""The suite's CityJSON Extension of a city over time: versions of buildings (issue 52).

``histo_versions.ext.json`` (beside this module, installed with the library)
is a CityJSON 2.0 Extension after the CityJSON versioning proposal (Vitalis
et al.: versions and the transitions between them in one file) and CityGML
3.0's Versioning module (``Version``, ``VersionTransition``) and lifespans:

- each version of a building (or of a building part) is a first-level city
  object of type ``+BuildingVersion``, linked by ``versionOf`` to what it is a
  version of (not its child: val3dity takes a building's children for parts
  that must not overlap, 601, and versions overlap), with its own
  geometry (a valid solid of its own: val3dity checks it alone), its
  ``epochs`` (the map years that show it), its validity interval
  ``validFrom``/``validTo`` (years, both included; no ``validTo``: it stands
  after the last map, or until a demolition the building's lifespan dates),
  its ``attributes`` (the first of its epochs' model's), in
  ``epochAttributes`` what a later epoch says otherwise, and in ``paradata``
  the provenance of its heights and roof type (:func:`paradata`);
- the building keeps its identity and lifespan (``epochs``,
  ``dateOfConstruction``, ``dateOfDemolition...`` as CityGML 3.0 names them)
  and lists in ``+transitions`` what happened between two maps: ``kept``,
  ``changed``, ``new``, ``demolished``, with the evidence;
- ``+versioning`` at the root: the city's versions (one per map) and the
  transitions between them.

Pure: the JSON document.
"""

import json
import os

#: the Extension's file, installed with the library
PATH = os.path.join(os.path.dirname(os.path.abspath(__file__)), "histo_versions.ext.json")
#: its name in a document's ``extensions``
NAME = "HistoVersions"
#: the city object type of a version
VERSION = "+BuildingVersion"
#: the building's attribute of its transitions
TRANSITIONS = "+transitions"
#: the root property of the city's versions
ROOT = "+versioning"
#: height_source values (v.histo.lod2) -> the paradata's method
HEIGHT_METHODS = {"measured": "measured", "points": "measured", "plot": "inferred",
                  "neighbours": "inferred", "range": "generated", "column": "given",
                  "copied": "copied"}
#: roof_source values (v.histo.lod2) -> the paradata's method
ROOF_METHODS = {"rule": "generated", "option": "given", "column": "given",
                "earlier epoch": "copied", "copied": "copied"}


def extension():
    """The Extension document (a dict), read from :data:`PATH`."""
    with open(PATH, encoding="utf-8") as f:
        return json.load(f)


def reference():
    """The document's ``extensions`` member naming the Extension: {name: {url, version}}."""
    ext = extension()
    return {NAME: {"url": ext["url"], "version": ext["version"]}}


def is_versioned(document):
    """Whether a CityJSON document (dict) is a model over time in the Extension's form."""
    return NAME in (document.get("extensions") or {}) or any(
        isinstance(o, dict) and o.get("type") == VERSION
        for o in (document.get("CityObjects") or {}).values())


def _number(value):
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _interval(low, high, minus=0.0):
    """[low, high] less ``minus`` (not below 0), None unless both are numbers."""
    if not (_number(low) and _number(high)):
        return None
    return [round(max(float(low) - minus, 0.0), 3), round(max(float(high) - minus, 0.0), 3)]


def paradata(attributes):
    """The paradata of a building's heights and roof type from its attributes
    (v.histo.lod2's ``height_source``, ``roof_source``, the height interval
    ``eaves_height_low``... ``ridge_height_high``): {attribute: {source, method,
    uncertainty}}; the uncertainty the interval [low, high] of the value (m; the
    roof's height given the eaves). Only what the attributes say."""
    out = {}
    heights = attributes.get("height_source")
    if isinstance(heights, str) and heights in HEIGHT_METHODS:
        eaves = attributes.get("eaves_height")
        out["eaves_height"] = {"source": heights, "method": HEIGHT_METHODS[heights]}
        out["roof_height"] = {"source": heights, "method": HEIGHT_METHODS[heights]}
        spans = (("eaves_height", _interval(attributes.get("eaves_height_low"),
                                            attributes.get("eaves_height_high"))),
                 ("roof_height", _interval(attributes.get("ridge_height_low"),
                                           attributes.get("ridge_height_high"), eaves)
                  if _number(eaves) else None))
        for name, span in spans:
            if span is not None:
                out[name]["uncertainty"] = span
    roof = attributes.get("roof_source")
    if isinstance(roof, str) and roof in ROOF_METHODS and "roof_type" in attributes:
        out["roof_type"] = {"source": roof, "method": ROOF_METHODS[roof]}
    return out
