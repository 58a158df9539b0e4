"""One CityJSON model of a town over several map epochs, and a snapshot of any year.

The chain writes one model per epoch (v.histo.lod2, with ``previous=`` from
the second on), its buildings named by their identity. :func:`merge_epochs`
makes one CityJSON 2.0 document of them that holds every building once:

- a building (with its children, e.g. a copied 3D BAG building's parts)
  is a city object of its own, its identity, without geometry; each
  *version* of it (or of a part) is a ``+BuildingVersion`` city object that
  names it in ``versionOf`` (a first-level object: not a part, which val3dity
  would require not to overlap the others), in the suite's CityJSON Extension
  (:mod:`~reconstruction.cityjson.versions`, ``HistoVersions``): the
  consecutive epochs whose models give it the same geometry (the same
  vertices, to the millimetre) share one version, a building kept from epoch
  to epoch is stored once. A version holds its geometry, its ``epochs``, its
  validity interval (``validFrom``, ``validTo``: the years the snapshot shows
  it), the attributes of its first epoch, in ``epochAttributes`` what
  another epoch says otherwise ({year: {name: value}}: the map year, the plot
  number), and the ``paradata`` of its heights and roof type;
- its identity: its id, while each map's footprint of it overlaps the
  one before (an id that two runs of the chain gave unrelated buildings
  is kept apart, the later one as ``<id>@<year>``);
- its lifespan (:mod:`~reconstruction.epochs.lifespans`): ``epochs``,
  ``dateOfConstruction`` (the register's year, where the maps agree),
  ``dateOfConstructionEarliest``/``Latest``, ``dateOfDemolitionEarliest``/
  ``Latest``, ``standing`` and, where the evidence conflicts, ``conflict``;
  in ``+transitions`` what happened to it between two consecutive maps
  (kept, changed, new, demolished) and the evidence.

The file validates against the official CityJSON 2.0.2 schemas with the
Extension, opens in cjio, and each version is a solid of its own (val3dity
checks each alone: no overlapping parts). A generic viewer draws every
version of a building at once; :func:`snapshot` gives the model of one year,
one version per building, for those. A merged model of the form before the
Extension (``geometry_epochs`` attributes) is refused with how to make it
again (:data:`EARLIER_FORM`).

The snapshot of a year *y* is the model of the latest epoch at or before
*y* (the maps are the evidence: what changed between two maps is not
placed in time), plus the buildings of the next epoch whose register year
of construction lies after that epoch and by *y*, with that epoch's
geometry. At an epoch's year it is that epoch's model: the same buildings,
geometries (vertex coordinates to the millimetre, semantics) and attributes
(an attribute an epoch lacks is null).
"""

import json
from dataclasses import dataclass, field
from typing import Optional

import numpy as np

from ..cityjson import geometry as citygeometry
from ..cityjson import versions
from ..cityjson.seq import object_tree
from ..cityjson.existing import id_key
from ..core import crs
from ..core.errors import InputError
from . import versioning
from .lifespans import lifespan
from .plots import LINK_SHARE

#: the output grid (m): the chain's models are written in millimetres
SCALE = 0.001
#: the farthest coordinate (m) from a reference system's origin a model may have
#: (a projected system spans some thousands of km; millimetres stay well in 64 bits)
FARTHEST = 1e8
#: projected reference systems whose unit is not the metre on the ground: Web
#: Mercator's (EPSG:3857 and its older codes) is 1/cos(latitude) m, 1.6 m at Delft,
#: so footprints would stand 1.6 times too large under heights in metres and every
#: tolerance of the chain (the millimetre grid, the outlines) would be off
NOT_METRIC = frozenset({3857, 3785, 900913, 102100, 102113})
#: what joins an object id to the year of the epoch where an unrelated building of
#: the same id first stands (:func:`merge_epochs`)
APART = "@"


@dataclass(frozen=True)
class Epoch:
    """One epoch's model: the map's ``year`` and the CityJSON ``document`` (a dict)
    read from ``path``."""

    year: int
    document: dict
    path: str = "<model>"


@dataclass(frozen=True)
class MergeReport:
    """What :func:`merge_epochs` found: ``buildings`` (distinct identities), per
    epoch year its building count (``per_epoch``), the ``versions`` stored
    (``+BuildingVersion`` city objects), the buildings still ``standing``, the
    ``conflicts`` ({id: what}) and the ids kept ``apart``."""

    buildings: int
    per_epoch: dict
    versions: int
    standing: int
    conflicts: dict = field(default_factory=dict)
    #: {id given: the ids it became} of the ids that name buildings in different
    #: places on different maps (footprints apart), each kept as a building of its own
    apart: dict = field(default_factory=dict)


@dataclass(frozen=True)
class DynamicModel:
    document: dict
    report: MergeReport


def _millimetres(doc, path="<model>"):
    """The document's vertices as absolute integer millimetres (N, 3); InputError for
    a coordinate farther than :data:`FARTHEST` from the origin."""
    t = doc.get("transform") or {"scale": [1, 1, 1], "translate": [0, 0, 0]}
    v = np.asarray(doc.get("vertices") or np.zeros((0, 3)), dtype=float).reshape(-1, 3)
    with np.errstate(over="ignore", invalid="ignore"):
        xyz = v * np.asarray(t["scale"]) + np.asarray(t["translate"])
    if not np.all(np.abs(xyz) <= FARTHEST):
        raise InputError("'{}' has a vertex more than {:g} km from its reference system's "
                         "origin: not a town's model".format(path, FARTHEST / 1000))
    return np.rint(xyz / SCALE).astype(np.int64)


def _reindexed(geometries, mapping):
    """Copies of ``geometries`` with every vertex index ``i`` replaced by ``mapping[i]``."""
    return citygeometry.reindex(geometries, lambda flat: mapping[flat]) if geometries else []


def _trees(doc):
    """{top-level id: [object ids of its tree, itself first]} of a document."""
    objects = doc.get("CityObjects", {})
    return {oid: object_tree(objects, oid) for oid, obj in objects.items()
            if not obj.get("parents")}


def _check_years(epochs):
    years = [e.year for e in epochs]
    if len(set(years)) != len(years):
        raise InputError("Two epochs have the same year ({})".format(
            ", ".join(map(str, years))))
    if not epochs:
        raise InputError("No epochs to merge")
    epochs = sorted(epochs, key=lambda e: e.year)
    for k, e in enumerate(epochs):
        check_one_epoch(e.document, e.path, e.year)
        for other in epochs[:k]:
            if other.document == e.document:
                raise InputError("The models of {} '{}' and of {} '{}' are one and the same: "
                                 "one model per map".format(other.year, other.path, e.year,
                                                            e.path))
    return epochs


def _top_attributes(document):
    """The attributes of the top-level objects of a document (an object's that are not
    a JSON object, of a broken building, as none)."""
    return [obj.get("attributes") if isinstance(obj.get("attributes"), dict) else {}
            for obj in document.get("CityObjects", {}).values()
            if isinstance(obj, dict) and not obj.get("parents")]


def map_years(document):
    """The map years (``map_year``, v.histo.lod2 year=) its buildings give, sorted."""
    return sorted({a["map_year"] for a in _top_attributes(document) if isinstance(
        a.get("map_year"), int) and not isinstance(a.get("map_year"), bool)})


def check_one_epoch(document, path, year=None, what="model"):
    """InputError unless ``document`` (read from ``path``, a ``what``) is the model of
    one epoch: not a model over time (:func:`merge_epochs`' output), its buildings of
    one map year, that year ``year`` where given, and (with ``year``) not empty: an
    epoch without buildings would date the demolition of every building before it."""
    attributes = _top_attributes(document)
    if versions.is_versioned(document) or any(
            name in a for a in attributes for name in ("epochs", "geometry_epochs")):
        raise InputError("The {} '{}' is a model over several epochs (v.histo.timeline's), "
                         "not the model of one map: take the epoch wanted from it with "
                         "v.histo.timeline input= snapshot=".format(what, path))
    found = map_years(document)
    if len(found) > 1:
        raise InputError("The {} '{}' holds buildings of several maps (map_year {}): not the "
                         "model of one map".format(what, path, ", ".join(map(str, found))))
    if year is None:
        return
    if found and found[0] != year:
        raise InputError("The {} '{}' is of the map of {} (its buildings' map_year), not of {} "
                         "as years= says".format(what, path, found[0], year))
    if not attributes:
        raise InputError("The {} of {} '{}' has no buildings: a map of the town shows some, "
                         "and an empty epoch would date the demolition of every building "
                         "before it".format(what, year, path))


def epochs_reference_system(epochs):
    """The ``referenceSystem`` of the epochs' models (the first one given), None when
    none gives one; InputError for two that locate points differently (e.g. EPSG:31370
    and EPSG:28992), and for one in degrees (EPSG:4326) or in Web Mercator's
    units (:data:`NOT_METRIC`), which are not metres on the ground."""
    first = None
    for e in epochs:
        text = (e.document.get("metadata") or {}).get("referenceSystem")
        code = crs.epsg_code(text)
        if code is None:
            continue
        if code in NOT_METRIC or crs.geographic(code):
            raise InputError(
                "The model of {} '{}' is in EPSG:{}, whose units are not metres on the "
                "ground ({}): reproject it to the town's projected system first (e.g. with "
                "cjio's crs_reproject)".format(e.year, e.path, code, "degrees of longitude and "
                                               "latitude" if crs.geographic(code)
                                               else "Web Mercator"))
        if first is None:
            first = (e, code, text)
        elif not crs.same_place(first[1], code):
            raise InputError("The models of {} '{}' (EPSG:{}) and of {} '{}' (EPSG:{}) are in "
                             "different reference systems: reproject them to one first".format(
                                 first[0].year, first[0].path, first[1], e.year, e.path, code))
    return None if first is None else first[2]


def _boxes(document, trees, grid):
    """{top-level id: its tree's box (x0, y0, x1, y1, mm): the extent of its vertices}
    of the ``trees`` of a document whose vertices are ``grid`` (:func:`_millimetres`);
    a tree without geometry has an empty box (x0 > x1)."""
    objects = document["CityObjects"]
    ids, geometries, owner = list(trees), [], []
    for n, oid in enumerate(ids):
        for m in trees[oid]:
            got = objects[m].get("geometry", ())
            geometries.extend(got)
            owner.extend([n] * len(got))
    lo = np.full((len(ids), 2), np.iinfo(np.int64).max)
    hi = np.full((len(ids), 2), np.iinfo(np.int64).min)
    if geometries:
        lay = citygeometry.layout(geometries)
        points = np.asarray(owner, dtype=np.int64)[lay.entry_geometry]
        if len(points):
            order = np.argsort(points, kind="stable")
            xy, points = grid[lay.flat[order], :2], points[order]
            starts = np.flatnonzero(np.r_[True, points[1:] != points[:-1]])
            lo[points[starts]] = np.minimum.reduceat(xy, starts)
            hi[points[starts]] = np.maximum.reduceat(xy, starts)
    return dict(zip(ids, np.hstack([lo, hi])))


def _same_places(a, b):
    """Per pair of boxes (rows of ``a`` and ``b``: x0, y0, x1, y1), whether they are one
    building's: they share at least :data:`~reconstruction.epochs.plots.LINK_SHARE` of
    the smaller one's area (or touch, for a box without area; an empty box, of a
    tree without geometry, is no evidence: the same)."""
    a, b = np.asarray(a, dtype=float).reshape(-1, 4), np.asarray(b, dtype=float).reshape(-1, 4)
    size = np.maximum(np.minimum(a[:, 2:], b[:, 2:]) - np.maximum(a[:, :2], b[:, :2]), -1.0)
    area = [np.prod(np.maximum(x[:, 2:] - x[:, :2], 0), axis=1) for x in (a, b)]
    smaller = np.minimum(*area)
    shared = np.prod(np.maximum(size, 0), axis=1)
    unknown = (a[:, 0] > a[:, 2]) | (b[:, 0] > b[:, 2])       # no geometry: no evidence
    return unknown | np.where(smaller > 0, shared >= LINK_SHARE * smaller,
                              (size >= 0).all(axis=1))


def _covering(document, tree, grid, extents):
    """Per epoch, whether its map covers the place of a building (its ``tree`` in
    ``document``, whose vertices are ``grid``): the centre of the building's extent
    lies in the extent of the epoch's model (``extents``: x0, y0, x1, y1 per epoch),
    so that a map of part of the town says nothing of the buildings elsewhere."""
    box = _boxes(document, {"b": tree}, grid)["b"]
    if box[0] > box[2]:
        return None
    centre = (box[:2] + box[2:]) / 2.0
    return [bool(np.all(e[:2] <= centre) and np.all(centre <= e[2:])) for e in extents]


def _renamed(document, names):
    """A copy of ``document`` whose objects are renamed by ``names`` ({old id: new id}),
    their links too."""
    objects = {}
    for oid, obj in document["CityObjects"].items():
        if oid in names:
            obj = dict(obj)
            for link in ("children", "parents"):
                if obj.get(link):
                    obj[link] = [names.get(x, x) for x in obj[link]]
        objects[names.get(oid, oid)] = obj
    return {**document, "CityObjects": objects}


def _apart(epochs, grids):
    """The epochs with the buildings that share an id but not a place kept apart.

    An id is one building across the epochs while each map's footprint of it
    (its extent) overlaps the one before (:func:`_same_places`): the chain keeps a building's
    footprint as it was, or redraws it where it stands. Where an id's footprint
    lies elsewhere than on the map before (two runs that each numbered their
    buildings from 1), it names another building from there on: its tree is
    renamed ``<id>@<year>`` (:data:`APART`). Returns (epochs, {id: [new ids]})."""
    trees = [_trees(e.document) for e in epochs]
    seen = {}
    for k, t in enumerate(trees):
        for oid in t:
            seen.setdefault(oid, []).append(k)
    shared = {oid for oid, ks in seen.items() if len(ks) > 1}
    if not shared:
        return epochs, {}
    boxes = [_boxes(e.document, {o: t[o] for o in t if o in shared}, g)
             for e, t, g in zip(epochs, trees, grids)]
    steps = [(oid, before, k) for oid in sorted(shared)
             for before, k in zip(seen[oid], seen[oid][1:])]
    same = dict(zip(steps, _same_places([boxes[before][oid] for oid, before, _ in steps],
                                        [boxes[k][oid] for oid, _, k in steps]).tolist()))
    taken = {m for e in epochs for m in e.document.get("CityObjects", {})}
    renames = [dict() for _ in epochs]
    apart = {}
    for oid in sorted(shared):
        ks, name = seen[oid], None
        for before, k in zip(ks, ks[1:]):
            if not same[oid, before, k]:
                name = oid + APART + str(epochs[k].year)
                while name in taken:
                    name += APART
                taken.add(name)
                apart.setdefault(oid, []).append(name)
            if name is not None:
                suffix = name[len(oid):]
                renames[k].update({m: (name if m == oid else m + suffix) for m in trees[k][oid]})
    out = [Epoch(e.year, _renamed(e.document, names), e.path) if names else e
           for e, names in zip(epochs, renames)]
    return out, apart


def merge_epochs(epochs, register=None, reference_system=None, title=None):
    """The :class:`DynamicModel` of the epochs' models (:class:`Epoch`, any order).

    ``register``: {building id: construction year or None} of today's
    register (the BAG): a building whose id (or, for an id with dots such as
    ``NL.IMBAG.Pand.0503100000012345``, the part after its last dot, leading
    zeros aside) is in it still stands; ``reference_system``: the output's
    (None: the models'). Raises InputError for two epochs of one year, a
    model that is not one epoch's (:func:`check_one_epoch`: another map
    year than its epoch's, a merged model, no buildings), models in
    different reference systems or one not in metres
    (:func:`epochs_reference_system`), and an object id that is a building
    in one epoch and a part in another. An id whose footprints lie apart on
    two maps names two buildings (:func:`_apart`).
    """
    epochs = _check_years(epochs)
    given = epochs_reference_system(epochs)
    if reference_system is None:
        reference_system = given
    years = [e.year for e in epochs]
    grids = [_millimetres(e.document, e.path) for e in epochs]
    epochs, apart = _apart(epochs, grids)
    extents = [np.r_[g[:, :2].min(axis=0), g[:, :2].max(axis=0)] if len(g) else
               np.array([1, 1, 0, 0]) for g in grids]
    rows = np.concatenate(grids) if grids else np.zeros((0, 3), np.int64)
    unique, inverse = np.unique(rows, axis=0, return_inverse=True)
    inverse = inverse.reshape(-1)
    starts = np.cumsum([0] + [len(g) for g in grids])
    present = {}                # top-level id -> {epoch index: tree}
    for k, e in enumerate(epochs):
        for oid, tree in _trees(e.document).items():
            present.setdefault(oid, {})[k] = tree
    objects, versioned, used = {}, {}, []
    taken = {m for e in epochs for m in e.document.get("CityObjects", {})}
    keys = _register_keys(register or {})
    conflicts, standing, count = {}, 0, {}
    for oid, trees in present.items():
        built = _built(oid, keys)
        covered = None
        if built[0] and max(trees) < len(years) - 1:
            k = max(trees)
            covered = _covering(epochs[k].document, trees[k], grids[k], extents)
        span = lifespan(years, [k in trees for k in range(len(years))],
                        built=built[1], standing=built[0], covered=covered)
        lived = span.attributes()
        standing += span.standing
        if span.conflict:
            conflicts[oid] = span.conflict
        shown = versioning.shown_years(years, set(trees), lived.get("dateOfConstruction"))
        members = list(dict.fromkeys(o for t in trees.values() for o in t))
        at = {}                 # (member, epoch index) -> version id
        for member in members:
            if member in objects:
                raise InputError("City object <{}> is in the tree of two buildings".format(
                    member))
            runs, kind, links = [], None, {}
            for k in sorted(trees):
                obj = epochs[k].document["CityObjects"].get(member)
                if obj is None or member not in trees[k]:
                    continue
                kind = kind or obj.get("type")
                for name in ("parents", "children"):
                    if obj.get(name):
                        links.setdefault(name, [])
                        links[name].extend(x for x in obj[name] if x not in links[name])
                geometry = _reindexed(obj["geometry"], inverse[starts[k]:starts[k + 1]]) \
                    if "geometry" in obj else None
                versioning.add_epoch(runs, k, years[k], obj, geometry)
            out = {"type": kind}
            out.update(links)
            for run in runs:
                vid = versioning.free_id("{}{}{}".format(
                    member, versioning.VERSION_JOIN, years[run.epochs[0]]), taken)
                at.update(((member, k), vid) for k in run.epochs)
                versioned[vid] = run.city_object(member, years, shown)
                if run.geometry:
                    used.append(citygeometry.indices(run.geometry))
            if member == oid:
                lived[versions.TRANSITIONS] = versioning.transitions(years, trees, members, at)
                out["attributes"] = lived
            objects[member] = out
        for k in trees:
            count[k] = count.get(k, 0) + 1
    report = MergeReport(len(present), {years[k]: count.get(k, 0) for k in range(len(years))},
                         len(versioned), standing, conflicts, apart)
    objects.update(versioned)
    document = _document(objects, unique, used, epochs, reference_system, title)
    document["extensions"] = versions.reference()
    document[versions.ROOT] = versioning.versioning(years, objects, present, count)
    return DynamicModel(document, report)


def _register_keys(register):
    """The register by id and by the key of :func:`~reconstruction.cityjson.existing.id_key`
    (the rule that matches footprints with an existing model's buildings)."""
    keys = {}
    for rid, year in register.items():
        text = str(rid).strip()
        keys[text] = year
        keys.setdefault(id_key(text), year)
    return keys


def _built(oid, keys):
    """(standing, construction year) of a building id in today's register."""
    if oid in keys:
        return True, keys[oid]
    k = id_key(oid)
    if "." in oid and k in keys:
        return True, keys[k]
    return False, None


def _document(objects, unique, used, epochs, reference_system, title):
    """The CityJSON document of the merged ``objects`` whose boundaries index
    ``unique`` (integer millimetres): the vertices used, renumbered from 0."""
    flat = np.unique(np.concatenate(used)) if used else np.zeros(0, np.int64)
    renumber = np.full(len(unique), -1, dtype=np.int64)
    renumber[flat] = np.arange(len(flat))
    rows = unique[flat]
    translate = rows.min(axis=0) if len(rows) else np.zeros(3, np.int64)
    for obj in objects.values():
        if "geometry" in obj:
            obj["geometry"] = _reindexed(obj["geometry"], renumber)
    first = epochs[-1].document
    metadata = dict(first.get("metadata") or {})
    if reference_system is not None:
        metadata["referenceSystem"] = reference_system
    if title is not None:
        metadata["title"] = title
    if len(rows):
        lo, hi = rows.min(axis=0) * SCALE, rows.max(axis=0) * SCALE
        metadata["geographicalExtent"] = [round(float(v), 3) for v in (*lo, *hi)]
    return {"type": "CityJSON", "version": "2.0",
            "transform": {"scale": [SCALE] * 3,
                          "translate": [round(float(v) * SCALE, 3) for v in translate]},
            "metadata": metadata, "CityObjects": objects,
            "vertices": (rows - translate).tolist()}


def epoch_years(document):
    """The epochs (years) of a merged model: every year its buildings name."""
    objects = document.get("CityObjects", {})
    return sorted({y for oid in buildings(objects)
                   for y in (objects[oid].get("attributes") or {}).get("epochs", ())})


def _integers(value):
    return isinstance(value, list) and all(
        isinstance(v, int) and not isinstance(v, bool) for v in value)


#: what a model over time of the form before the Extension (issue 52) is told
EARLIER_FORM = ("'{}' is a model over time of an earlier v.histo.timeline (a building's "
                "versions as extra geometries, with geometry_epochs): make it again from the "
                "epochs' models (v.histo.timeline models= years=, with register= as before), "
                "which writes each version as a city object of its own (the HistoVersions "
                "CityJSON Extension)")


def _version_problem(obj, objects):
    """What of a ``+BuildingVersion`` city object a model over time cannot hold (None:
    nothing)."""
    of = objects.get(obj.get("versionOf")) if isinstance(obj.get("versionOf"), str) else None
    if not isinstance(of, dict) or of.get("type") == versions.VERSION or obj.get("parents"):
        return "is not the version of a city object of the model (versionOf)"
    if not (_integers(obj.get("epochs")) and obj["epochs"]):
        return "has no list of epochs (years)"
    if not isinstance(obj.get("attributes", {}), dict):
        return "has attributes that are not an object"
    extra = obj.get("epochAttributes", {})
    if not (isinstance(extra, dict) and all(isinstance(v, dict) for v in extra.values())):
        return "has epochAttributes that are not {year: {name: value}}"
    if not isinstance(obj.get("geometry", []), list):
        return "has a geometry that is not a list"
    return None


def _merged_problem(oid, obj, objects, index):
    """What of a city object (a dict) of a model over time (whose
    :func:`version_index` is ``index``) it cannot hold (None: nothing): see
    :func:`check_merged`."""
    if not isinstance(obj, dict):
        return "is not a JSON object"
    for link in ("children", "parents"):
        if not isinstance(obj.get(link) or [], list):
            return "has {} that are not a list".format(link)
    if obj.get("type") == versions.VERSION:
        return _version_problem(obj, objects)
    if obj.get("geometry"):
        return "has a geometry of its own, not one per version"
    if obj.get("parents"):
        return None
    a = obj.get("attributes")
    if not (isinstance(a, dict) and _integers(a.get("epochs")) and a["epochs"]):
        return "has no list of epochs (years)"
    drawn = {y for v in index.get(oid, ()) if _integers(v.get("epochs")) for y in v["epochs"]}
    lacking = sorted(set(a["epochs"]) - drawn)
    if lacking:
        return "has no version of its epoch {}".format(lacking[0])
    return None


def check_merged(document, path):
    """InputError unless ``document`` (read from ``path`` by
    :func:`~reconstruction.cityjson.existing.read_document`) is a model over time as
    :func:`merge_epochs` writes it (the HistoVersions Extension): each top-level object
    with its ``epochs`` (years) and, among its children, a ``+BuildingVersion`` of each
    epoch; each version with its parent, its epochs, ``epochAttributes`` {year: {name:
    value}} where given. A model of the form before the Extension (``geometry_epochs``)
    is told how to make it again (:data:`EARLIER_FORM`)."""
    objects = document["CityObjects"]
    if not versions.is_versioned(document):
        if any(isinstance(o, dict) and "geometry_epochs" in (o.get("attributes") or {})
               for o in objects.values()):
            raise InputError(EARLIER_FORM.format(path))
        raise InputError("'{}' is not a model over time of v.histo.timeline: it has no "
                         "versions of buildings (the HistoVersions Extension)".format(path))
    index = version_index(objects)
    # the versions first: a building's problem may be that of its version
    for oid in sorted(objects, key=lambda o: not (isinstance(objects[o], dict) and objects[
            o].get("type") == versions.VERSION)):
        problem = _merged_problem(oid, objects[oid], objects, index)
        if problem is not None:
            raise InputError("'{}' is not a model over time of v.histo.timeline: its city "
                             "object <{}> {}".format(path, oid, problem))
    if not epoch_years(document):
        raise InputError("'{}' is not a model over time of v.histo.timeline: it has no "
                         "epochs".format(path))


def standing_versions(document, year):
    """{top-level object id: the epoch whose geometry and attributes it has} of the
    buildings standing in ``year`` in a merged model (the snapshot's rule, see the
    module doc); InputError for a year before the first epoch."""
    years = epoch_years(document)
    if not years:
        raise InputError("The model has no epochs (not a model of v.histo.timeline)")
    if year < years[0]:
        raise InputError("Year {} is before the model's first epoch ({})".format(
            year, years[0]))
    shown = max(y for y in years if y <= year)
    later = [y for y in years if y > shown]
    following = later[0] if later else None
    chosen = {}
    objects = document["CityObjects"]
    for oid in buildings(objects):
        a = objects[oid].get("attributes") or {}
        if shown in a.get("epochs", ()):
            chosen[oid] = shown
        elif following is not None and following in a.get("epochs", ()) and isinstance(
                a.get("dateOfConstruction"), int) and shown < a["dateOfConstruction"] <= year:
            chosen[oid] = following
    return chosen


def version_index(objects):
    """{city object id: its ``+BuildingVersion`` objects (dicts), in the model's order}
    of the ``objects`` of a model over time."""
    out = {}
    for obj in objects.values():
        if isinstance(obj, dict) and obj.get("type") == versions.VERSION and isinstance(
                obj.get("versionOf"), str):
            out.setdefault(obj["versionOf"], []).append(obj)
    return out


def buildings(objects):
    """The ids of the buildings (top-level city objects, not versions) among ``objects``."""
    return [oid for oid, obj in objects.items()
            if not obj.get("parents") and obj.get("type") != versions.VERSION]


def _version_at(index, member, epoch):
    """The version of city object ``member`` in ``epoch`` (a year) in a
    :func:`version_index`, None when it is not in that epoch."""
    return next((v for v in index.get(member, ()) if epoch in v.get("epochs", ())), None)


def snapshot(document, year):
    """The CityJSON document of the town in ``year`` (see the module doc) from a merged
    model (:func:`merge_epochs`): each building's versions of the epoch chosen; InputError
    for a year before the first epoch, and for a model of the form before the Extension
    (:data:`EARLIER_FORM`)."""
    if not versions.is_versioned(document):
        raise InputError(EARLIER_FORM.format("The model"))
    objects = document["CityObjects"]
    chosen = standing_versions(document, year)
    index = version_index(objects)
    out, used = {}, []
    for oid, epoch in chosen.items():
        for member in object_tree(objects, oid):
            obj = objects[member]
            version = _version_at(index, member, epoch)
            if version is None:
                continue                # a part of the building in other epochs
            attributes = dict(version.get("attributes") or {})
            attributes.update((version.get("epochAttributes") or {}).get(str(epoch), {}))
            new = {n: v for n, v in obj.items() if n not in ("attributes", "geometry")}
            if "geometry" in version:
                new["geometry"] = version["geometry"]
                if version["geometry"]:
                    used.append(citygeometry.indices(version["geometry"]))
            new["attributes"] = attributes
            out[member] = new
    for obj in out.values():                         # children of another epoch left out
        for name in ("children", "parents"):
            if name in obj:
                obj[name] = [x for x in obj[name] if x in out]
                if not obj[name]:
                    del obj[name]
    unique = _millimetres(document)
    metadata = {k: v for k, v in (document.get("metadata") or {}).items()
                if k != "geographicalExtent"}
    doc = _document(out, unique, used, [Epoch(year, {"metadata": metadata})], None, None)
    return doc
