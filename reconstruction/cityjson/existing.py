"""An existing 3D city model (e.g. the 3D BAG): read it, find its buildings'
footprints and measured heights, and match them with aligned footprints.

In the complete workflow (thesis Sections 3.4.1 and 3.4.3) the buildings
that still stand are copied from a current 3D city model rather than rebuilt.
This file reads such a model and says which of its buildings is which
aligned footprint; :mod:`reconstruction.cityjson.merge` copies them.

Formats: a CityJSON 2.0 file, or CityJSONSeq (``.city.jsonl``: a CityJSON
header line, then one ``CityJSONFeature`` per building, as the 3D BAG's API
and tiles serve it); the format is told by the content, not the name.
CityJSON 1.1 is upgraded to 2.0 on read by the rules of the 2.0 changelog
(the version, ``+GenericCityObject`` -> ``GenericCityObject``, the metadata's
address as an object; cjio's ``upgrade`` does the same); anything else is an
:class:`InputError`.

Why not cjio (0.10.1, pinned for its command line): importing
``cjio.cityjson`` replaces, for the whole process, json's C encoder by the
pure-Python one and writes every float with six decimals (``1e-07`` becomes
``0.000000``), which would slow down and change every CityJSON file this
library writes afterwards. And what its Python API still offers does not
serve here: ``cityjson.reader`` parses with a Python hook on every JSON
object (to refuse duplicate keys) and keeps every vertex as a Python list,
CityJSONSeq is read only from standard input (``read_stdin``), and
``CityJSON.merge`` decompresses every vertex to floats and removes
duplicates in a Python loop, compares no reference systems and merges
objects of the same id instead of refusing them. Reading the JSON once and
walking the geometries in bulk (:mod:`reconstruction.cityjson.geometry`) keeps
merging a 10,000-building model near the time of reading it.

Matching (:func:`match`), by id first, then by geometry:

- by id: the id of a footprint (``id_column``, e.g. the BAG's ``pand_id``
  ``0503100000000034``) is the object id with ``prefix`` in front when a
  prefix is given (``NL.IMBAG.Pand.``). Without a prefix the automatic rule
  applies: the object id itself, else the part of the object id after its
  last '.', compared without leading zeros when it is all digits (so an
  integer column holding 503100000000034 matches
  ``NL.IMBAG.Pand.0503100000000034``); a suffix that two objects share
  matches neither.
- by geometry, for the footprints left: the building whose footprint (its
  LoD0 surfaces, else the GroundSurface surfaces of its solids or of its
  children's) overlaps the footprint most, with an intersection over union
  of at least ``min_overlap``. Each building matches at most one footprint.
"""

import dataclasses
import json
from dataclasses import dataclass, field
from typing import Optional

import numpy as np

from ..core import crs
from ..core.errors import InputError
from ..geom.grid import Extent
from . import checks
from .files import VERSION, check_version, load, not_cityjson, upgrade  # noqa: F401
from . import geometry as citygeometry
from . import seq as cityjsonseq

#: 3D BAG attributes of the measured heights (2025 names first, then the older ones)
HEIGHT_ATTRIBUTES = {
    "ground": ("b3_h_maaiveld",),
    "roof_min": ("b3_h_min", "b3_h_dak_min"),
    "roof_50p": ("b3_h_50p", "b3_h_dak_50p"),
    "roof_70p": ("b3_h_70p", "b3_h_dak_70p"),
    "roof_max": ("b3_h_max", "b3_h_dak_max"),
    "ridge": ("b3_h_nok",),
}


@dataclass
class ExistingModel:
    """A city model as read, in CityJSON 2.0 form.

    ``objects``: every CityObject by id (boundaries index ``vertices`` plus
    the ``offset`` of the top-level object they belong to: 0 for a single
    file, the start of the feature's vertices for CityJSONSeq);
    ``vertices``: (N, 3) the stored integers (or floats, without a transform)
    of ``scale`` and ``translate``; ``buildings``: ids of the top-level
    objects that can be matched, in file order, and ``offset`` per building.
    """
    path: str
    version: str
    #: the ``metadata.referenceSystem`` as read (an OGC URL or URN, ``EPSG:7415``), or None
    reference_system: Optional[str]
    scale: np.ndarray
    translate: np.ndarray
    objects: dict
    vertices: np.ndarray
    buildings: list
    offset: np.ndarray
    metadata: dict = field(default_factory=dict)
    extensions: dict = None
    sequence: bool = False
    #: buildings left out because they are broken: id -> the problem
    #: (:func:`reconstruction.cityjson.checks.broken_buildings`)
    skipped: dict = field(default_factory=dict)

    @property
    def epsg(self):
        """The EPSG code of the reference system (None when absent or not EPSG)."""
        return crs.epsg_code(self.reference_system)

    def place(self):
        """The :class:`~reconstruction.geom.grid.Extent` of its vertices (x, y; None without any)."""
        if not len(self.vertices):
            return None
        lo = self.vertices.min(axis=0) * self.scale + self.translate
        hi = self.vertices.max(axis=0) * self.scale + self.translate
        return Extent(float(lo[0]), float(lo[1]), float(hi[0]), float(hi[1]))

    def coordinates(self, index):
        """Coordinates (float, metres) of the vertices ``index`` (global: offset included)."""
        return self.vertices[np.asarray(index, dtype=np.int64)] * self.scale + self.translate

    def tree(self, building):
        """Ids of a top-level object and all its descendants (parents first)."""
        objects = self.objects
        if building not in objects:
            return []
        out, seen, k = [building], {building}, 0
        while k < len(out):
            for child in objects[out[k]].get("children", ()):
                if child in objects and child not in seen:
                    seen.add(child)
                    out.append(child)
            k += 1
        return out


def check_reference_system(model, location_epsg):
    """InputError unless the model's reference system agrees with the location's
    EPSG code, and is not geographic (the location is in metres)."""
    code = model.epsg
    if code is not None and crs.geographic(code):
        raise InputError(
            "The reference system of the existing model '{}' is EPSG:{}, a geographic one "
            "(degrees of longitude and latitude): reproject the model to the location's "
            "system first (e.g. with cjio's crs_reproject)".format(model.path, code))
    if code is None or location_epsg is None:
        return
    if not crs.same_place(code, location_epsg):
        raise InputError(
            "The reference system of the existing model '{}' (EPSG:{}) does not agree with "
            "the location's (EPSG:{}): reproject the model first (e.g. with cjio's "
            "crs_reproject)".format(model.path, code, location_epsg))


# ---------------------------------------------------------------------------
# Reading (the file itself: reconstruction.cityjson.files)
# ---------------------------------------------------------------------------

def read_model(path, types=("Building",)):
    """Read an existing model: CityJSON 2.0 / 1.1 file or CityJSONSeq.

    ``types``: the types of top-level objects that can be matched. Raises
    :class:`InputError` for a missing file, a file that is not CityJSON, an
    unsupported version or a broken CityJSONSeq line.
    """
    doc, offsets, counts, sequence = load(path)
    return model_of(doc, path, offsets, sequence, types, counts)


def read_document(path):
    """The CityJSON document (a dict, indices into one vertex list) of a CityJSON file
    or CityJSONSeq, checked as :func:`read_model` checks a model, every top-level
    object of any type: where :func:`read_model` leaves a broken building out (and
    says so), a whole document is refused (InputError naming the first broken
    ones), as is a city object that is not a JSON object."""
    doc, offsets, counts, sequence = load(path, "model")
    model = model_of(doc, path, offsets, sequence, types=None, counts=counts)
    odd = [oid for oid, obj in doc["CityObjects"].items() if not isinstance(obj, dict)]
    if odd:
        raise InputError("'{}': the city object <{}> is not a JSON object".format(path, odd[0]))
    if model.skipped:
        raise InputError("'{}': {} of its buildings {} broken: {}".format(
            path, len(model.skipped), "is" if len(model.skipped) == 1 else "are",
            broken_named(model.skipped)))
    if sequence:
        doc = cityjsonseq.joined(doc, offsets)
    return doc


#: broken buildings named in a message (:func:`broken_named`)
BROKEN_NAMED = 3


def broken_named(skipped):
    """The first :data:`BROKEN_NAMED` broken buildings of ``skipped`` ({id: problem})
    with their problem, and how many more, as text for a message."""
    named = ["<{}>: {}".format(oid, problem) for oid, problem in
             list(skipped.items())[:BROKEN_NAMED]]
    more = len(skipped) - len(named)
    return "; ".join(named) + ("; and {} more".format(more) if more else "")


@citygeometry.gc_paused()
def model_of(doc, path="<model>", offsets=None, sequence=False, types=("Building",),
             counts=None):
    """An :class:`ExistingModel` of a CityJSON document (dict), upgraded from 1.1.

    ``offsets``: vertex offset per top-level object id (CityJSONSeq features
    keep their own indices), None for one document; ``counts``: with
    ``offsets``, the number of vertices of each one's feature; ``types``: the
    types of the top-level objects to match (None: every type). A broken
    transform, vertices or metadata raise InputError; broken buildings are left out
    of ``buildings`` and named in ``skipped``
    (:mod:`reconstruction.cityjson.checks`).
    """
    if not isinstance(doc, dict) or doc.get("type") != "CityJSON":
        kind = doc.get("type") if isinstance(doc, dict) else type(doc).__name__
        raise not_cityjson(path, "its type is {}".format(json.dumps(kind)))
    version = check_version(path, doc)
    if not isinstance(doc.get("CityObjects"), dict) or not isinstance(doc.get("vertices"), list):
        raise not_cityjson(path, "no CityObjects or vertices")
    for member in ("metadata", "extensions"):
        if not isinstance(doc.get(member) or {}, dict):
            raise not_cityjson(path, "its {} is not an object".format(member))
    if version != VERSION:
        upgrade(doc)                   # 1.1
    transform = doc.get("transform")
    checks.check_transform(path, transform)
    transform = transform or {}
    scale = np.asarray(transform.get("scale", [1.0, 1.0, 1.0]), dtype=float)
    translate = np.asarray(transform.get("translate", [0.0, 0.0, 0.0]), dtype=float)
    objects = doc["CityObjects"]
    vertices = checks.vertices_array(path, doc["vertices"], bool(transform))
    wanted = None if types is None else set(types)
    buildings = [oid for oid, obj in objects.items()
                 if isinstance(obj, dict) and not obj.get("parents") and
                 (wanted is None or isinstance(obj.get("type"), str) and obj["type"] in wanted)]
    if offsets is None:
        offset = np.zeros(len(buildings), dtype=np.int64)
        count = np.full(len(buildings), len(vertices), dtype=np.int64)
    else:
        offset = np.array([offsets.get(b, 0) for b in buildings], dtype=np.int64)
        count = np.array([counts.get(b, 0) for b in buildings], dtype=np.int64)
    skipped = checks.broken_buildings(objects, buildings, count)
    if skipped:
        keep = [b for b, oid in enumerate(buildings) if oid not in skipped]
        buildings, offset = [buildings[b] for b in keep], offset[keep]
    metadata = doc.get("metadata") or {}
    return ExistingModel(path=path, version=version,
                         reference_system=metadata.get("referenceSystem"),
                         scale=scale, translate=translate, objects=objects, vertices=vertices,
                         buildings=buildings, offset=offset, metadata=metadata,
                         extensions=doc.get("extensions"), sequence=sequence,
                         skipped=skipped)


def _on_grid_of(model, other):
    """``other``'s vertices stored as ``model`` stores its own: on its grid (integers of
    its scale and translate), exactly where the two grids agree."""
    if other.vertices.dtype.kind == "i" and model.vertices.dtype.kind == "i" and np.allclose(
            other.scale, model.scale, rtol=0, atol=1e-12):
        shift = (other.translate - model.translate) / model.scale
        if np.allclose(shift, np.rint(shift), rtol=0, atol=1e-6):
            return other.vertices + np.rint(shift).astype(np.int64)
    xyz = other.vertices * other.scale + other.translate
    if model.vertices.dtype.kind == "i":
        return np.rint((xyz - model.translate) / model.scale).astype(np.int64)
    return xyz


def combined(first, second):
    """One :class:`ExistingModel` holding the buildings of two (``first``'s, then
    ``second``'s), on ``first``'s grid and in its reference system: e.g. the 3D BAG and
    the earlier epoch's model, copied from as one. Object ids must differ
    (InputError naming one that does not)."""
    shared = set(first.objects).intersection(second.objects)
    if shared:
        raise InputError("The models '{}' and '{}' both hold a city object <{}>".format(
            first.path, second.path, min(shared)))
    vertices = _on_grid_of(first, second)
    if vertices.dtype != first.vertices.dtype:
        vertices = vertices.astype(np.result_type(vertices, first.vertices))
    return dataclasses.replace(
        first, path="{} + {}".format(first.path, second.path),
        objects={**first.objects, **second.objects},
        vertices=np.concatenate([first.vertices, vertices.astype(first.vertices.dtype)]),
        buildings=list(first.buildings) + list(second.buildings),
        offset=np.concatenate([first.offset, second.offset + len(first.vertices)]),
        extensions={**(second.extensions or {}), **(first.extensions or {})} or None,
        sequence=first.sequence or second.sequence,
        skipped={**first.skipped, **second.skipped})


# ---------------------------------------------------------------------------
# Footprints and heights
# ---------------------------------------------------------------------------

@dataclass(frozen=True)
class BuildingFootprints:
    """The footprints of a model's buildings, as polygons in bulk.

    ``polygons``: shapely Polygons (x, y of the model); ``owner``: index of
    the building (in ``model.buildings``) of each polygon; ``area``: the
    footprint area of every building (0 where none was found); ``source``:
    per building "lod0", "ground" or "" (no footprint).
    """
    polygons: np.ndarray
    owner: np.ndarray
    area: np.ndarray
    source: list

    def geometry(self, b):
        """The footprint of building ``b`` as one shapely geometry (None where it has none)."""
        import shapely

        parts = self.polygons[self.owner == b]
        return shapely.union_all(parts) if len(parts) else None


def _footprint_surfaces(model, building):
    """(surfaces, source) of one building: its LoD0 surfaces, else the
    GroundSurface surfaces of the highest-LoD geometry that has any, object
    by object of its tree."""
    objs = [model.objects[o] for o in model.tree(building)]
    lod0 = [g for obj in objs for g in obj.get("geometry", ())
            if citygeometry.lod_value(g.get("lod")) == 0 and g.get("type") in
            citygeometry.SURFACE_DEPTH]
    if lod0:
        return [s for g in lod0 for s in citygeometry.surfaces_of(g)[0]], "lod0"
    found = []
    for obj in objs:
        geoms = obj.get("geometry", ())
        if len(geoms) > 1:
            geoms = sorted(geoms, key=lambda g: citygeometry.lod_value(g.get("lod")), reverse=True)
        for g in geoms:
            ground = citygeometry.surfaces_of_type(g, "GroundSurface")
            if ground:
                found.extend(ground)
                break
    return found, ("ground" if found else "")


@citygeometry.gc_paused()
def footprints(model):
    """The footprints of all buildings of a model (:class:`BuildingFootprints`), in bulk."""
    import shapely

    rings, ring_poly, poly_owner, sources = [], [], [], []
    shifts = []
    for b, oid in enumerate(model.buildings):
        surfaces, source = _footprint_surfaces(model, oid)
        sources.append(source)
        for surface in surfaces:
            if not surface or len(surface[0]) < 3:
                continue
            poly = len(poly_owner)
            poly_owner.append(b)
            for ring in surface:
                if len(ring) >= 3:
                    rings.append(ring)
                    ring_poly.append(poly)
                    shifts.append(int(model.offset[b]))
    B = len(model.buildings)
    if not rings:
        return BuildingFootprints(np.empty(0, dtype=object), np.zeros(0, dtype=np.int64),
                                  np.zeros(B), sources)
    flat, offsets = citygeometry.flat_indices(rings)
    sizes = np.diff(offsets)
    flat = flat + np.repeat(np.asarray(shifts, dtype=np.int64), sizes)
    xy = model.coordinates(flat)[:, :2]
    ring_geoms = shapely.linearrings(xy, indices=np.repeat(np.arange(len(rings)), sizes))
    polygons = shapely.polygons(ring_geoms, indices=np.asarray(ring_poly))
    bad = ~shapely.is_valid(polygons)
    if bad.any():
        polygons[bad] = shapely.make_valid(polygons[bad])
    owner = np.asarray(poly_owner, dtype=np.int64)
    area = np.bincount(owner, weights=shapely.area(polygons), minlength=B)
    return BuildingFootprints(polygons, owner, area, sources)


@dataclass(frozen=True)
class MeasuredHeights:
    """Heights measured in the existing model (the 3D BAG's), one value per
    aligned footprint, nan where the footprint matched nothing or the model
    has no such attribute. Absolute heights in the model's vertical reference
    (NAP for the 3D BAG): ``ground`` (``b3_h_maaiveld``), roof percentiles
    ``roof_min``/``roof_50p``/``roof_70p``/``roof_max`` (``b3_h_min`` ...,
    before 2025 ``b3_h_dak_min`` ...) and ``ridge`` (``b3_h_nok``, 2025 on)."""
    ground: np.ndarray
    roof_min: np.ndarray
    roof_50p: np.ndarray
    roof_70p: np.ndarray
    roof_max: np.ndarray
    ridge: np.ndarray

    def above_ground(self, name):
        """Height ``name`` (e.g. "roof_70p") above the measured ground."""
        return getattr(self, name) - self.ground


def measured_heights(model, building):
    """:class:`MeasuredHeights` per footprint; ``building``: the index of the
    matched building of each footprint (-1 for none, see :class:`Matches`)."""
    building = np.asarray(building, dtype=np.int64)
    matched = np.nonzero(building >= 0)[0]
    attrs = [model.objects[model.buildings[b]].get("attributes") or {}
             for b in building[matched].tolist()]
    values = {}
    for key, names in HEIGHT_ATTRIBUTES.items():
        column = np.full(len(building), np.nan)
        for name in reversed(names):                # the first name wins
            got = np.array([_number(a.get(name)) for a in attrs], dtype=float)
            known = ~np.isnan(got)
            column[matched[known]] = got[known]
        values[key] = column
    return MeasuredHeights(**values)


def _number(value):
    return float(value) if isinstance(value, (int, float)) and not isinstance(value, bool) \
        else np.nan


# ---------------------------------------------------------------------------
# Matching
# ---------------------------------------------------------------------------

@dataclass(frozen=True)
class MatchReport:
    """Counts of a match: footprints matched by id, by geometry, not at all,
    and footprints whose id matched no building (these were then tried by
    geometry); ``duplicate_ids``: footprints whose id names the building an
    earlier footprint's id already took (one footprint per building: these
    too were tried by geometry), not counted in ``unmatched`` when they
    matched nothing, ``duplicates_unmatched`` of them; ``duplicate_examples``:
    the first three of these ids; ``far_ids``: see below."""
    footprints: int
    by_id: int
    by_geometry: int
    unmatched: int
    ids_not_found: int
    duplicate_ids: int = 0
    duplicates_unmatched: int = 0
    duplicate_examples: tuple = ()
    #: footprints whose id named a building farther than :data:`FAR_ID_MATCH`
    #: from them (not taken: tried by geometry), and the first one's id and distance
    far_ids: int = 0
    far_example: tuple = ()


@dataclass
class Matches:
    """The existing building of every aligned footprint.

    ``building``: index into ``model.buildings`` (-1: none, to be generated);
    ``by_id``: matched by its id; ``overlap``: intersection over union of
    the footprints (nan for id matches without footprint overlap measured);
    ``model``: the model matched with. :attr:`heights`: the measured heights
    (:class:`MeasuredHeights`), read from the attributes when first asked for.
    """
    building: np.ndarray
    by_id: np.ndarray
    overlap: np.ndarray
    report: MatchReport
    model: ExistingModel = field(default=None, repr=False)

    @property
    def heights(self):
        """The :class:`MeasuredHeights` of the matched buildings, per footprint."""
        if not hasattr(self, "_heights"):
            self._heights = measured_heights(self.model, self.building)
        return self._heights

    @property
    def matched(self):
        """Indices of the footprints that matched a building."""
        return np.nonzero(self.building >= 0)[0]


def _id_text(value):
    """A footprint id as text (None for missing): 34.0 -> '34', ' x ' -> 'x'."""
    if value is None:
        return None
    if isinstance(value, float):
        if value != value:
            return None
        if value.is_integer():
            value = int(value)
    text = str(value).strip()
    return text or None


def id_key(text):
    """The automatic rule's key of an id: the part after its last '.', without
    leading zeros when it is all digits."""
    tail = text.rsplit(".", 1)[-1]
    if tail.isdigit():
        return tail.lstrip("0") or "0"
    return tail


def _by_id(model, ids, prefix):
    """Building index per footprint id (-1 when none), and the number not found."""
    index = {oid: b for b, oid in enumerate(model.buildings)}
    keys = {}
    if prefix is None:
        for b, oid in enumerate(model.buildings):
            k = id_key(oid)
            keys[k] = -2 if k in keys else b          # -2: shared by two, matches neither
    out = np.full(len(ids), -1, dtype=np.int64)
    missing = 0
    for i, value in enumerate(ids):
        text = _id_text(value)
        if text is None:
            continue
        if prefix is not None:
            b = index.get(prefix + text, -1)
        else:
            b = index.get(text, -1)
            if b < 0:
                b = max(keys.get(id_key(text), -1), -1)
        out[i] = b
        missing += b < 0
    return out, missing


#: a building matched by id lies within this distance (map units) of its
#: footprint, or the match is not taken: the same building in the same
#: place, perhaps drawn a little apart; a model whose coordinates are not
#: what its reference system says (longitude and latitude in a model that
#: claims EPSG:7415) would otherwise be copied tens of kilometres away
FAR_ID_MATCH = 100.0


def _far_from_footprints(polygons, building, fps, reach=FAR_ID_MATCH):
    """Per footprint, its distance to the footprint of its building
    (``building``: index per footprint, -1 for none; nan where either has no
    footprint)."""
    import shapely

    n = len(building)
    distance = np.full(n, np.nan)
    owner_fp = np.full(len(fps.area), -1, dtype=np.int64)
    matched = np.nonzero(building >= 0)[0]
    owner_fp[building[matched]] = matched
    part = np.nonzero(owner_fp[fps.owner] >= 0)[0]
    if not len(part):
        return distance
    fp = owner_fp[fps.owner[part]]
    mine = np.asarray(polygons, dtype=object)
    d = shapely.distance(mine[fp], fps.polygons[part])
    best = np.full(n, np.inf)
    np.fmin.at(best, fp, d)
    distance[np.isfinite(best)] = best[np.isfinite(best)]
    return distance


def _intersection_areas(a, b, tolerance=1e-3):
    """Areas of the intersections of pairs of polygons. The aligned footprints
    usually are the model's own footprints (the 3D BAG's ground surfaces are
    the BAG's polygons), perhaps rounded, reoriented or started elsewhere:
    pairs equal within ``tolerance`` once normalised skip the overlay."""
    import shapely

    same = shapely.equals_exact(shapely.normalize(a), shapely.normalize(b), tolerance=tolerance)
    out = np.minimum(shapely.area(a), shapely.area(b))
    if not same.all():
        out[~same] = shapely.area(shapely.intersection(a[~same], b[~same]))
    return out


def _by_geometry(polygons, todo, fps, free, min_overlap):
    """Building per footprint ``todo`` by the largest intersection over union
    (at least ``min_overlap``), one footprint per building; returns (building, overlap)."""
    import shapely

    building = np.full(len(todo), -1, dtype=np.int64)
    overlap = np.full(len(todo), np.nan)
    use = np.nonzero(free[fps.owner])[0]
    if len(todo) == 0 or len(use) == 0:
        return building, overlap
    mine = np.asarray(polygons, dtype=object)[todo]
    ok = ~(shapely.is_missing(mine) | shapely.is_empty(mine))
    tree = shapely.STRtree(fps.polygons[use])
    pairs = tree.query(mine[ok], predicate="intersects")
    if pairs.shape[1] == 0:
        return building, overlap
    fp = np.nonzero(ok)[0][pairs[0]]
    part = use[pairs[1]]
    inter = _intersection_areas(mine[fp], fps.polygons[part])
    owner = fps.owner[part]
    # sum the parts of one building per footprint
    key = fp * len(fps.area) + owner
    uniq, inv = np.unique(key, return_inverse=True)
    inter = np.bincount(inv, weights=inter)
    fp, owner = uniq // len(fps.area), uniq % len(fps.area)
    area = shapely.area(mine)
    union = area[fp] + fps.area[owner] - inter
    iou = np.where(union > 0, inter / np.maximum(union, 1e-12), 0.0)
    taken_fp = np.zeros(len(todo), dtype=bool)
    taken_b = np.zeros(len(fps.area), dtype=bool)
    for k in np.argsort(-iou, kind="stable").tolist():
        if iou[k] < min_overlap:
            break
        f, b = fp[k], owner[k]
        if taken_fp[f] or taken_b[b]:
            continue
        taken_fp[f] = taken_b[b] = True
        building[f] = b
        overlap[f] = iou[k]
    return building, overlap


@citygeometry.gc_paused()
def match(model, polygons, ids=None, prefix=None, min_overlap=0.5, fps=None):
    """The existing building of every aligned footprint (:class:`Matches`).

    ``polygons``: the aligned footprints (shapely Polygons/MultiPolygons in
    the model's x, y); ``ids``: their building ids (None or an empty value
    where absent); ``prefix``: put in front of each id to make the object id
    (None: the automatic rule of the module docstring); ``min_overlap``:
    least intersection over union for a match by geometry; ``fps``: the
    model's :class:`BuildingFootprints` if already computed.
    """
    if not 0 < min_overlap <= 1:
        raise InputError("The least overlap must be in (0, 1], not {}".format(min_overlap))
    n = len(polygons)
    building = np.full(n, -1, dtype=np.int64)
    duplicate = np.zeros(n, dtype=bool)
    missing = 0
    if ids is not None:
        if len(ids) != n:
            raise ValueError("one id per footprint is needed")
        building, missing = _by_id(model, ids, prefix)
        # one footprint per building: the first one keeps it, the others are duplicates
        seen = set()
        for i in np.nonzero(building >= 0)[0].tolist():
            if building[i] in seen:
                building[i] = -1
                duplicate[i] = True
            else:
                seen.add(int(building[i]))
    far, far_example = np.zeros(n, dtype=bool), ()
    if (building >= 0).any():
        fps = fps if fps is not None else footprints(model)
        distance = _far_from_footprints(polygons, building, fps)
        far = distance > FAR_ID_MATCH           # nan: not far
        if far.any():
            first = int(np.nonzero(far)[0][0])
            far_example = (_id_text(ids[first]), float(distance[first]))
            building[far] = -1
    by_id = building >= 0
    overlap = np.full(n, np.nan)
    todo = np.nonzero(~by_id)[0]
    if len(todo):
        fps = fps if fps is not None else footprints(model)
        free = np.ones(len(model.buildings), dtype=bool)
        free[building[by_id]] = False
        got, iou = _by_geometry(polygons, todo, fps, free, min_overlap)
        building[todo] = got
        overlap[todo] = iou
    report = MatchReport(footprints=n, by_id=int(by_id.sum()),
                         by_geometry=int(((building >= 0) & ~by_id).sum()),
                         unmatched=int(((building < 0) & ~duplicate).sum()),
                         ids_not_found=int(missing), duplicate_ids=int(duplicate.sum()),
                         duplicates_unmatched=int(((building < 0) & duplicate).sum()),
                         duplicate_examples=tuple(dict.fromkeys(
                             _id_text(ids[i]) for i in np.nonzero(duplicate)[0].tolist()))[:3],
                         far_ids=int(far.sum()), far_example=far_example)
    return Matches(building=building, by_id=by_id, overlap=overlap, report=report, model=model)
