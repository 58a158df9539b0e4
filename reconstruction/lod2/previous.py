"""The earlier epoch's buildings in a dynamic chain (v.histo.lod2 previous=, issue 28).

A footprint that v.histo.subdivide kept from the earlier epoch carries its
building identity (column ``building``) and its outline; the earlier
epoch's model holds that building under that id. :func:`match_previous`
says, per footprint, whether the earlier building is *kept*: copied as it
is (its solid, roof and heights: nothing changes where the maps did not),
when its footprint has the same outline (:func:`~reconstruction.geom.polygons.same_outline`,
within :data:`OUTLINE_TOLERANCE`) and this epoch measures no other heights
for it (a measured, points or column height source more than
:data:`HEIGHT_TOLERANCE` from the earlier eaves or roof height; a flat
roof has no roof height to compare). A building
of the same identity that is not kept is built anew with its earlier roof
type (:attr:`PreviousMatch.roof_type`). :func:`with_previous` joins the
kept buildings to the existing model's matches, so that both are copied
the same way (:mod:`reconstruction.lod2.output`).
"""

from dataclasses import dataclass, replace
from typing import Optional

import numpy as np

from ..cityjson import existing
from ..core.contract import (HEIGHTS_COLUMN, HEIGHTS_MEASURED, HEIGHTS_POINTS, PLOT, SOURCE)
from ..core.errors import InputError
from ..epochs.dynamic import check_one_epoch, map_years
from ..geom.polygons import polygon_parts, same_outline
from .config import AUTO, ExistingRequest
from .output import ExistingMatch, read_existing
from .roofs.plan import ROOF_TYPES
from .stage import ROOF_EARLIER

#: the same footprint: its outline within this (m) of the earlier one (the model's
#: millimetre grid and a GRASS round trip)
OUTLINE_TOLERANCE = 0.002
#: measured heights that agree with the earlier building within this (m) keep it
HEIGHT_TOLERANCE = 0.01
#: the height sources that measure a building in this epoch
MEASURING = (HEIGHTS_MEASURED, HEIGHTS_POINTS, HEIGHTS_COLUMN)
#: the attributes of a generated building that belong to its epoch, not to the
#: building: taken from this epoch's footprint when a building is kept
PER_EPOCH = ("footprint", PLOT, SOURCE, "map_year")


@dataclass(frozen=True)
class PreviousReport:
    """Of the ``footprints`` with an identity: ``kept`` (copied from the earlier model),
    ``measured`` (rebuilt: this epoch measures other heights), ``reshaped``
    (rebuilt: another outline) and ``new`` (no earlier building of that identity)."""

    footprints: int = 0
    kept: int = 0
    measured: int = 0
    reshaped: int = 0
    new: int = 0


@dataclass(frozen=True)
class PreviousMatch:
    """The earlier ``model`` and, per footprint, the index of its kept building in
    ``model.buildings`` (``building``, -1: built in this epoch) and the earlier roof
    type of its identity (``roof_type``, None: none) and why it had it
    (``roof_source``, None: not said); the :class:`PreviousReport`."""

    model: existing.ExistingModel
    building: np.ndarray
    roof_type: list
    report: PreviousReport
    roof_source: Optional[list] = None


def read_previous(path, map_year, location_epsg=None):
    """The earlier epoch's model (previous=), read and checked as an existing model is
    (its broken buildings left out and named in ``skipped``, for the warning
    existing= gives), and refused (InputError) unless it is the model of one map
    before this one's ``map_year``: not a model over time (v.histo.timeline's, whose
    buildings would be kept with every version), not of the same or a later map year."""
    model = read_existing(ExistingRequest(path=path), location_epsg)
    check_one_epoch({"CityObjects": model.objects}, path, what="earlier epoch's model")
    years = map_years({"CityObjects": model.objects})
    if years and years[0] >= map_year:
        raise InputError("The earlier epoch's model '{}' (previous=) is of the map of {}, not "
                         "of a map before this one's ({}, year=): give the model of the "
                         "epoch before".format(path, years[0], map_year))
    return model


def _height(attributes, name):
    value = attributes.get(name)
    return float(value) if isinstance(value, (int, float)) and not isinstance(value, bool) \
        else np.nan


def _per_footprint(values, n):
    if values is None or np.ndim(values) == 0 and not isinstance(values, np.ndarray):
        return np.full(n, np.nan)
    return np.asarray(values, dtype=float)


def match_previous(model, identities, geometries, eaves=None, attic=None, sources=None,
                   map_year=None):
    """The :class:`PreviousMatch` of the footprints (shapely ``geometries`` with their
    building ``identities``, None where none) with the earlier ``model``
    (:class:`~reconstruction.cityjson.existing.ExistingModel`); ``eaves``, ``attic``
    (per footprint, m) and ``sources`` (their height source) are this epoch's heights."""
    n = len(geometries)
    index = {oid: b for b, oid in enumerate(model.buildings)}
    eaves, attic = _per_footprint(eaves, n), _per_footprint(attic, n)
    sources = [None] * n if sources is None else list(sources)
    fps = existing.footprints(model)
    building = np.full(n, -1, dtype=np.int64)
    roof_type, roof_source = [None] * n, [None] * n
    counts = dict(footprints=0, kept=0, measured=0, reshaped=0, new=0)
    for i, (identity, geom) in enumerate(zip(identities, geometries)):
        if identity is None or geom is None:
            continue
        counts["footprints"] += 1
        b = index.get(str(identity))
        if b is None:
            counts["new"] += 1
            continue
        attributes = model.objects[model.buildings[b]].get("attributes") or {}
        roof_type[i], roof_source[i] = attributes.get("roof_type"), attributes.get("roof_source")
        before, parts = polygon_parts(fps.geometry(b)), polygon_parts(geom)
        if len(parts) != 1 or len(before) != 1 or \
                not same_outline(before[0], parts[0], OUTLINE_TOLERANCE):
            counts["reshaped"] += 1
            continue
        # a flat roof has no attic: built anew with it, the building would be the same
        flat = roof_type[i] == "flat"
        if sources[i] in MEASURING and not (
                abs(eaves[i] - _height(attributes, "eaves_height")) <= HEIGHT_TOLERANCE and
                (flat or abs(attic[i] - _height(attributes, "roof_height")) <= HEIGHT_TOLERANCE)):
            counts["measured"] += 1
            continue
        building[i] = b
        counts["kept"] += 1
    return PreviousMatch(_this_epoch(model, building, map_year), building, roof_type,
                         PreviousReport(**counts), roof_source)


def _this_epoch(model, building, map_year):
    """The earlier model with the per-epoch attributes of its kept buildings left out
    (:data:`PER_EPOCH`: the footprint's are written instead) and this epoch's map year."""
    objects = dict(model.objects)
    for b in np.unique(building[building >= 0]).tolist():
        oid = model.buildings[b]
        obj = dict(objects[oid])
        attributes = {k: v for k, v in (obj.get("attributes") or {}).items()
                      if k not in PER_EPOCH}
        if map_year is not None:
            attributes["map_year"] = map_year
        obj["attributes"] = attributes
        objects[oid] = obj
    return replace(model, objects=objects)


def with_earlier_roofs(requests, previous):
    """The :class:`~reconstruction.lod2.stage.RoofRequests` with the earlier roof type
    asked for where a building of an earlier identity is built anew (another outline,
    other measured heights) and the roof was to be drawn: it keeps its roof, and why
    it had it (the earlier ``roof_source``, else
    :data:`~reconstruction.lod2.stage.ROOF_EARLIER`)."""
    types = np.asarray(requests.types, dtype=object).copy()
    source = None if requests.source is None else np.asarray(requests.source, dtype=object).copy()
    why = previous.roof_source or [None] * len(types)
    for i, (b, earlier) in enumerate(zip(previous.building, previous.roof_type)):
        if b < 0 and earlier in ROOF_TYPES and types[i] == AUTO:
            types[i] = earlier
            if source is not None:
                source[i] = why[i] or ROOF_EARLIER
    return replace(requests, types=types, source=source)


def with_previous(match, previous, request, count):
    """One :class:`~reconstruction.lod2.output.ExistingMatch` copying both the existing
    model's matched buildings (``match``, None without existing=) and the kept
    earlier buildings (``previous``, a :class:`PreviousMatch`) of ``count``
    footprints; a footprint the existing model matched keeps that match."""
    kept = previous.building
    if match is None:
        model = previous.model
        building = kept
        request = ExistingRequest(path=previous.model.path)
        report = existing.MatchReport(footprints=0, by_id=0, by_geometry=0, unmatched=0,
                                      ids_not_found=0)
    else:
        model = existing.combined(match.model, previous.model)
        building = np.where(kept >= 0, kept + len(match.model.buildings), -1)
        building[match.candidates] = np.where(match.matches.building >= 0,
                                              match.matches.building,
                                              building[match.candidates])
        report = match.matches.report
        lods = match.request.lods
        if isinstance(lods, list):
            lods = lods + sorted({g.get("lod") for o in previous.model.objects.values()
                                  for g in o.get("geometry", ())} - set(lods))
        request = replace(match.request, lods=lods)
    matches = existing.Matches(building=building, by_id=building >= 0,
                               overlap=np.full(count, np.nan), report=report, model=model)
    ids = frozenset(previous.model.buildings[b] for b in kept[kept >= 0].tolist())
    return ExistingMatch(model, request, np.arange(count), matches, kept_previous=ids,
                         only_previous=match is None,
                         existing_candidates=None if match is None else len(match.candidates))
