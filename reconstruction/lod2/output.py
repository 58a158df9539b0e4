"""The output side of v.histo.lod2: merge an existing city model, write
CityJSON or CityJSONSeq, render a picture (issue 17).

The sequence, after the buildings are built (:func:`reconstruction.lod2.stage.build`):

1. :func:`read_existing` (before building, so that a wrong file fails
   fast): the existing model (:func:`reconstruction.cityjson.existing.read_model`),
   its reference system checked against the location's;
2. :func:`match_existing`: the candidates are the footprints whose source
   is ``aligned`` (:data:`~reconstruction.core.contract.SOURCE_ALIGNED`; every
   footprint when the map has no source column, e.g. v.histo.align's output
   itself); each is matched by id, then by geometry
   (:func:`reconstruction.cityjson.existing.match`);
3. :func:`build`: the footprints that are not copied built
   (:func:`reconstruction.lod2.stage.build`);
4. :func:`write_model`: the matched buildings copied
   (:func:`reconstruction.cityjson.copied.copy_buildings`, with the footprint's
   ``plot``, ``source`` and ``footprint`` as attributes where the building
   has none of its own), the model written as one CityJSON file
   (:func:`reconstruction.cityjson.merge.merge`) or as CityJSONSeq
   (:func:`reconstruction.cityjson.seq.write`), whole or not at all
   (:mod:`reconstruction.core.safefile`); then, if asked, the picture
   (:func:`reconstruction.lod2.render.render`).
"""

import json
import os
from contextlib import nullcontext
from dataclasses import dataclass, field, replace
from typing import Optional

import numpy as np

from ..cityjson import existing
from ..cityjson import copied as citycopy
from ..cityjson import merge as citymerge
from ..cityjson import model as cityjson
from ..cityjson import seq as cityjsonseq
from ..cityjson import versions
from ..core import crs, safefile
from ..core.contract import PLOT, SOURCE, SOURCE_ALIGNED
from ..core.errors import InputError
from ..geom.grid import Extent
from ..geom.solidset import concat, semantics, take
from .. import view
from . import render
from . import stage as lod2
from .config import FORMATS, ExistingRequest, OutputRequest  # noqa: F401 (also read here)
from .certainty import COPIED_ATTRIBUTES
from .heights import height_columns
from .inputs import AlignedFootprints
from .report import drawing_messages
from .solids import validation
from .solids.build import Buildings, build_solids

@dataclass(frozen=True)
class ExistingMatch:
    """The existing model and the building matched with every footprint.

    ``candidates``: the footprints that may be copied (indices);
    ``matches``: :class:`~reconstruction.cityjson.existing.Matches` of the candidates.
    """
    model: existing.ExistingModel
    request: ExistingRequest
    candidates: np.ndarray
    matches: existing.Matches
    #: with previous= (a dynamic chain, :func:`reconstruction.lod2.previous.with_previous`):
    #: the earlier epoch's buildings kept (copied too; ids), whether there is no
    #: existing model besides, and the existing model's own candidates (their count)
    kept_previous: frozenset = frozenset()
    only_previous: bool = False
    existing_candidates: Optional[int] = None
    #: per footprint count, the arrays of building() and copied()
    _building: dict = field(default_factory=dict, init=False, repr=False, compare=False)

    def building(self, count):
        """Per footprint (``count`` of them) the index of its existing building,
        -1 for none (worked out once; do not change the array)."""
        if count not in self._building:
            out = np.full(count, -1, dtype=np.int64)
            out[self.candidates] = self.matches.building
            self._building[count] = out
        return self._building[count]

    def copied(self, count):
        """The footprints (indices, of ``count``) whose existing building is
        copied (worked out once)."""
        key = ("copied", count)
        if key not in self._building:
            self._building[key] = np.nonzero(self.building(count) >= 0)[0]
        return self._building[key]


@dataclass(frozen=True)
class OutputReport:
    """What was written: ``generated`` and ``copied`` buildings (top-level
    objects), generated buildings left out because their footprint was
    copied, the copy's :class:`~reconstruction.cityjson.copied.CopyReport` and the
    match's :class:`~reconstruction.cityjson.existing.MatchReport` (None without an
    existing model), the picture's path."""
    generated: int
    copied: int = 0
    replaced: int = 0
    copy: Optional[citycopy.CopyReport] = None
    match: Optional[existing.MatchReport] = None
    rendered: Optional[str] = None
    #: buildings drawn when the picture shows only some
    #: (:data:`reconstruction.lod2.render.MAX_DRAWN`), else None
    drawn: Optional[int] = None
    candidates: int = 0
    notes: tuple = ()
    #: with -v, the validation of the copied Solids
    #: (:func:`reconstruction.cityjson.copied.copied_solids`): per solid checked,
    #: (its label, None or the reasons it is invalid)
    copied_checked: Optional[tuple] = None
    #: with -v, the copied Solids not checked (inner shells, faces with holes)
    copied_unchecked: int = 0
    #: buildings of the earlier epoch kept (previous=: copied from its model, not
    #: counted in ``copied``)
    kept: int = 0


def footprint_ids(columns, name):
    """The values of the id column ``name`` (None when no column is given)."""
    if not name:
        return None
    if name not in columns:
        raise InputError("Column <{}> (id_column=, the building ids) not found in the input "
                         "map; available: {}".format(name, ", ".join(sorted(columns))))
    return columns[name]


def read_existing(request, location_epsg=None):
    """The existing model of ``request`` (:class:`ExistingRequest`), read and
    checked: InputError for a file that is not CityJSON (2.0, 1.1 or
    CityJSONSeq), for a model over time (versions of buildings: take an
    epoch's snapshot) and for a reference system that disagrees with the
    location's."""
    if not 0 < request.min_overlap <= 1:
        raise InputError("The least overlap must be in (0, 1], not {}".format(
            request.min_overlap))
    model = existing.read_model(request.path)
    if versions.is_versioned({"CityObjects": model.objects}):
        raise InputError("The existing model '{}' is a model over several epochs "
                         "(v.histo.timeline's): take the epoch wanted from it with "
                         "v.histo.timeline input= snapshot=".format(request.path))
    existing.check_reference_system(model, location_epsg)
    return model


def candidates(source, count):
    """Indices of the footprints that may be copied: source ``aligned``
    (every footprint when ``source`` is None: the map has no source column)."""
    if source is None:
        return np.arange(count)
    return np.array([i for i, s in enumerate(source) if str(s).strip() == SOURCE_ALIGNED]
                    if count else [], dtype=np.int64)


def match_existing(model, request, footprints, ids=None):
    """:class:`ExistingMatch` of the footprints (a
    :class:`~reconstruction.lod2.stage.Footprints`) with the buildings of
    ``model``; ``ids``: one building id per footprint (the ``id_column``), or None."""
    todo = candidates(footprints.source, len(footprints.geometries))
    polygons = [footprints.geometries[i] for i in todo.tolist()]
    chosen = None if ids is None else [ids[i] for i in todo.tolist()]
    matches = existing.match(model, polygons, ids=chosen, prefix=request.prefix,
                             min_overlap=request.min_overlap)
    check_placed(model, matches.report, Extent.of(polygons))
    return ExistingMatch(model, request, todo, matches)


def check_placed(model, report, footprints):
    """InputError when every building an id named lies far from its
    footprint and nothing matched otherwise (issue 33, item 8): the model's
    coordinates are not where its reference system says (longitude and
    latitude in a model that claims EPSG:7415), and copying it would put
    the buildings tens of kilometres away. ``footprints``: their Extent."""
    if not report.far_ids or report.by_id or report.by_geometry:
        return
    place = model.place()
    said = "EPSG:{}".format(model.epsg) if model.epsg else "the location's system"
    raise InputError(
        "The buildings of the existing model '{}' that the building ids name lie far from "
        "their footprints ({} of them; <{}> {:.0f} m away): the model ({}) does not cover the "
        "footprints ({}){}; is it in {}, as it says?".format(
            model.path, report.far_ids, report.far_example[0], report.far_example[1],
            place.text() if place else "no vertices",
            footprints.text() if footprints else "none",
            ", and its coordinates look like longitude and latitude"
            if crs.looks_geographic(place) else "", said))


def attribute_columns(match, count, names=None):
    """The attributes of the existing building matched with each of ``count``
    footprints, as columns: name -> one value per footprint (None where it
    matched nothing or the building lacks it); ``names``: the attributes
    wanted (None: every one the matched buildings have). With the 3D BAG's
    heights (``b3_h_maaiveld``, ``b3_h_50p``/``b3_h_dak_50p`` ...) these are
    measured heights of the aligned footprints:
    ``heights.measured_heights(attribute_columns(match, n))``."""
    building = match.building(count)
    attrs = [None if b < 0 else
             match.model.objects[match.model.buildings[b]].get("attributes") or {}
             for b in building.tolist()]
    if names is None:
        names = list(dict.fromkeys(k for a in attrs if a for k in a))
    return {name: [None if a is None else a.get(name) for a in attrs] for name in names}


def matched_heights(match, geometries, choice="auto"):
    """The footprints (``geometries``) that ``match`` (an :class:`ExistingMatch`)
    matched, with their existing buildings' attributes as columns, as
    :class:`~reconstruction.lod2.inputs.AlignedFootprints`: for the 3D BAG
    (``b3_h_maaiveld``, ``b3_h_50p`` ...) measured heights for the
    neighbourhood analysis, so that no separate height columns are needed.
    None when nothing matched or the buildings have no height attributes."""
    hit = match.copied(len(geometries))
    if not len(hit):
        return None
    columns = {name: [values[i] for i in hit.tolist()]
               for name, values in attribute_columns(match, len(geometries)).items()}
    try:
        height_columns(list(columns), choice)
    except InputError:
        return None
    return AlignedFootprints([geometries[i] for i in hit.tolist()], columns, choice)


def without_copied(prepared, match):
    """The :class:`~reconstruction.lod2.stage.Prepared` footprints without those
    that ``match`` (an :class:`ExistingMatch` or None) copies: they are not built."""
    if match is None:
        return prepared
    copied = match.copied(len(prepared.footprints.geometries))
    keep = np.nonzero(~np.isin(prepared.source, copied))[0]
    if len(keep) == len(prepared.source):
        return prepared
    b = prepared.buildings
    return replace(prepared, buildings=b.subset(keep), source=prepared.source[keep],
                   part=prepared.part[keep],
                   extra=tuple((name, _subset(values, keep)) for name, values in prepared.extra),
                   report=replace(prepared.report, rings=len(keep)))


def _subset(values, keep):
    """The entries ``keep`` of per-building ``values`` (an array, a list or None)."""
    if values is None:
        return None
    return values[keep] if isinstance(values, np.ndarray) else [values[i] for i in keep.tolist()]


def build(prepared, config, match=None):
    """:func:`reconstruction.lod2.stage.build` of ``prepared``, the footprints that
    ``match`` does not copy (:func:`without_copied`'s result: v.histo.lod2
    reports their count before building); an empty result when it copies
    every one. (Footprints it copies that are built anyway are left out
    when written, see :func:`write_model`.)"""
    if len(prepared.buildings) or match is None or not len(match.matches.matched):
        return lod2.build(prepared, config)
    ss = build_solids(Buildings([], [], [], [], [], np.zeros((0, 3)))).solids
    return lod2.Lod2Result(ss, semantics(ss), [], np.zeros(0, dtype=object),
                           np.zeros(0, dtype=np.int64), {}, prepared.report)


def without_footprints(result, footprints):
    """A :class:`~reconstruction.lod2.stage.Lod2Result` without the buildings of
    the footprints ``footprints`` (indices)."""
    drop = np.isin(result.footprint, np.asarray(footprints, dtype=np.int64))
    if not drop.any():
        return result
    keep = np.nonzero(~drop)[0]
    ss = take(result.solids, keep)
    attributes = {k: _pick(v, keep) for k, v in result.attributes.items()}
    return replace(result, solids=ss, semantics=semantics(ss), ids=[result.ids[i] for i in keep],
                   roof_types=np.asarray(result.roof_types)[keep],
                   footprint=np.asarray(result.footprint)[keep], attributes=attributes)


def _pick(values, keep):
    if isinstance(values, np.ndarray):
        return values[keep]
    return [values[i] for i in keep.tolist()]


def copy_matched(match, footprints, count, fmt="cityjson", among=None):
    """The matched buildings (:class:`~reconstruction.cityjson.copied.CopiedBuildings`),
    in footprint order, with their footprint's plot, source and category as
    attributes where they have none of their own, ready to be written in
    the format ``fmt``; ``among``: only those of these footprints (a mask
    of ``count``; None: all)."""
    building = match.building(count)
    matched = match.copied(count)
    if among is not None:
        matched = matched[among[matched]]
    cats = footprints.cats if footprints.cats is not None else list(range(1, count + 1))
    attributes = {"footprint": [cats[i] for i in matched.tolist()]}
    for name, values in ((PLOT, footprints.plot), (SOURCE, footprints.source)):
        if values is not None:
            attributes[name] = [values[i] for i in matched.tolist()]
    attributes.update((name, [value] * len(matched)) for name, value in COPIED_ATTRIBUTES)
    return citycopy.copy_buildings(match.model, building[matched], lods=match.request.lods,
                                    attributes=attributes, keep_numbering=fmt == "cityjson")


def _single_text(result, copied, request):
    """The single-file model's text, as pieces written in turn (one pass:
    see ``citymerge.merged_pieces``)."""
    text = cityjson.citymodel_text(result.solids, result.semantics, result.ids,
                                   result.attributes, request.reference_system,
                                   title=request.title)
    return citymerge.merged_pieces(text, copied)


def drawn_footprints(geometries, most=None):
    """Which footprints the picture draws: None for all (at most ``most``,
    default :data:`reconstruction.lod2.render.MAX_DRAWN`), else a mask of
    the ``most`` whose centroids are nearest the middle of the footprints'
    bounding box (ties by order)."""
    import shapely

    most = render.MAX_DRAWN if most is None else most
    if len(geometries) <= most:
        return None
    polygons = np.array([g if g is not None else shapely.Point() for g in geometries])
    present = ~shapely.is_empty(polygons)
    xy = shapely.get_coordinates(shapely.centroid(polygons[present]))
    lo, hi = xy.min(axis=0), xy.max(axis=0)
    distance = np.full(len(polygons), np.inf)
    distance[present] = np.hypot(*(xy - (lo + hi) / 2.0).T)
    mask = np.zeros(len(polygons), dtype=bool)
    mask[np.argsort(distance, kind="stable")[:most]] = True
    return mask


def _drawn(result, drawn):
    """The buildings of ``result`` on the ``drawn`` footprints (a mask; None: all)."""
    if drawn is None:
        return result
    return without_footprints(result, np.nonzero(~drawn)[0])


def _joined(results):
    """One :class:`~reconstruction.lod2.stage.Lod2Result` of several (for the picture)."""
    results = [r for r in results if len(r.ids)]
    if len(results) == 1:
        return results[0]
    ss = concat([r.solids for r in results])
    attributes = {k: [v for r in results for v in _pick(r.attributes[k], np.arange(len(r.ids)))]
                  for k in (results[0].attributes if results else {})}
    return lod2.Lod2Result(ss, semantics(ss), [i for r in results for i in r.ids],
                           np.concatenate([r.roof_types for r in results]) if results else
                           np.zeros(0, dtype=object),
                           np.concatenate([r.footprint for r in results]) if results else
                           np.zeros(0, dtype=np.int64), attributes,
                           results[0].report if results else None)


def _copied(match, footprints, fmt, validate=False):
    """The copied buildings and the report of what was matched and copied
    (with ``validate``, their Solids checked as the generated ones are)."""
    count = len(footprints.geometries)
    copied = copy_matched(match, footprints, count, fmt)
    kept = sum(i in match.kept_previous for i in copied.ids)
    report = OutputReport(generated=0, copied=len(copied) - kept, kept=kept, copy=copied.report,
                          match=None if match.only_previous else match.matches.report,
                          candidates=len(match.candidates) if match.existing_candidates is None
                          else match.existing_candidates)
    if validate:
        solids = citycopy.copied_solids(copied)
        report = replace(report, copied_unchecked=solids.unchecked, copied_checked=tuple(
            zip(solids.labels, validation.validate(solids.solids))))
    return copied, report


def write_model(result, footprints, request, match=None, doing=nullcontext, say=None,
                validate=False):
    """Write the model of a :class:`~reconstruction.lod2.stage.Lod2Result` (and the
    buildings ``match`` copies, an :class:`ExistingMatch` or None) as
    ``request`` (:class:`OutputRequest`) says; returns an :class:`OutputReport`.

    The model and its picture appear together or not at all
    (:func:`reconstruction.core.safefile.together`): a failure or an
    interruption while either is written leaves both files as they were.
    ``doing(what)``: a context manager naming each step for the error of a
    failure (v.histo.lod2: :class:`reconstruction.grassio.doing`); ``say``
    prints a step's messages (:mod:`reconstruction.lod2.report`);
    ``validate``: the copied Solids are checked (:attr:`OutputReport.copied_checked`)."""
    fmt = request.format
    copied, report = None, OutputReport(generated=len(result.ids))
    if match is not None:
        before = len(result.ids)
        result = without_footprints(result, match.copied(len(footprints.geometries)))
        copied, report = _copied(match, footprints, fmt, validate)
        report = replace(report, generated=len(result.ids), replaced=before - len(result.ids))
    drawn = drawn_footprints(footprints.geometries) if request.render else None
    every_copied = copied                # the picture may draw some of them, the viewer all
    with safefile.together() as files:
        model_file = files.reserve(request.path)
        picture_file = files.reserve(request.render, ".png") if request.render else None
        viewer_file = files.reserve(request.viewer, ".html") if request.viewer else None
        gltf_file = files.reserve(request.gltf, ".glb") if request.gltf else None
        tiles_dir = files.reserve_dir(request.tiles) if request.tiles else None
        pieces = None
        with doing("writing '{}'".format(request.path)), open(model_file, "wb") as f:
            if fmt == "cityjson":
                pieces = _single_text(result, copied, request)
                if request.render and drawn is None:
                    pieces = list(pieces)           # written, then drawn
                cityjson.write_pieces(f, pieces)
            else:
                cityjsonseq.write(f, result.solids, result.semantics, result.ids,
                                  result.attributes, request.reference_system, request.title,
                                  copied=copied)
        if request.render:
            if drawn is not None:
                pieces = None
                result = _drawn(result, drawn)
                if copied is not None:
                    copied = copy_matched(match, footprints, len(footprints.geometries),
                                          among=drawn)
            report = _render(pieces or _single_text(result, copied, request), picture_file,
                             request, copied, report, drawn, doing, say,
                             match.kept_previous if match is not None else frozenset())
        if request.viewer or request.gltf or request.tiles:
            _views(model_file, viewer_file, gltf_file, request, every_copied, doing, match,
                   tiles_dir)
    return report


def _views(model_file, viewer_path, gltf_path, request, copied, doing, match=None,
           tiles_path=None):
    """Write the page of ``viewer=``, the glTF of ``gltf=`` and the 3D Tiles of ``tiles=``
    to their temporary files and directory (``viewer_path``, ``gltf_path``,
    ``tiles_path``; None: not asked for) from the model just written to ``model_file``:
    every building, the copied ones in their colours."""
    kept = match.kept_previous if match is not None else frozenset()
    shown = _shown_copied(copied, kept)
    with doing("reading back '{}' for the viewer, glTF and 3D Tiles".format(request.path)):
        if request.format == "cityjson":
            with open(model_file, encoding="utf-8") as f:
                scene = view.build_scene(json.load(f), copied=shown)
        else:   # a few thousand features at a time, as it was written (issue 49, item 14)
            scene = view.scene_of_seq(model_file, copied=shown, name=request.path)
    if viewer_path:
        with doing("writing the viewer '{}'".format(request.viewer)):
            title = request.title or os.path.basename(request.path)
            with open(viewer_path, "w", encoding="utf-8") as f:
                view.write_viewer(f, scene, title, request.map_image)
    if gltf_path:
        with doing("writing the glTF '{}'".format(request.gltf)), open(gltf_path, "wb") as f:
            view.write_glb(f, scene, folder=os.path.dirname(os.path.abspath(gltf_path)))
    if tiles_path:
        with doing("writing the 3D Tiles '{}'".format(request.tiles)):
            view.write_tileset(tiles_path, scene, request.title)


def _shown_copied(copied, kept):
    """The ids of the copied buildings drawn in the copied buildings' colours: those of
    ``copied`` (None: none) but the earlier epoch's (``kept``), drawn as generated ones."""
    return [i for i in copied.ids if i not in kept] if copied is not None else ()


def _render(pieces, path, request, copied, report, drawn, doing, say, kept=frozenset()):
    """Draw the model given as ``pieces`` to ``path`` (the picture's temporary
    file); the report with what was drawn. ``kept``: the ids of the copied
    buildings that are the earlier epoch's, drawn as generated ones."""
    if say is not None:
        say(drawing_messages(request.render))
    with doing("drawing the picture '{}'".format(request.render)):
        document = json.loads(cityjson.joined_text(pieces))
        render.render(document, path, request.view, map_image=request.map_image,
                      copied=_shown_copied(copied, kept))
    return replace(report, rendered=request.render,
                   drawn=None if drawn is None else int(drawn.sum()))


def write_in_steps(prepared, config, footprints, request, match=None, doing=nullcontext,
                   say=None, validate=False):
    """Build and write the CityJSONSeq model of ``prepared`` (without the
    footprints ``match`` copies: :func:`without_copied`) a step of buildings
    at a time (:func:`reconstruction.lod2.stage.build_in_steps`), so that
    memory is bounded by a step, not by the city (issue 33, item 9): each
    step's solids are written and let go. The copied buildings follow, as
    :func:`write_model` writes them; the picture draws the buildings of
    :func:`drawn_footprints`, kept as the steps go.

    Returns the whole run's :class:`~reconstruction.lod2.stage.Lod2Result`
    (:func:`reconstruction.lod2.stage.summary`: no solids), the
    :class:`OutputReport` and, with ``validate``, the validation of every
    solid (:func:`reconstruction.lod2.solids.validation.validate`, step by
    step; the copied ones in the report, as :func:`write_model` does)."""
    copied, report = None, OutputReport(generated=0)
    count = len(footprints.geometries)
    if match is not None:
        copied, report = _copied(match, footprints, request.format, validate)
    drawn = drawn_footprints(footprints.geometries) if request.render else None
    every_copied = copied                # the picture may draw some of them, the viewer all
    steps, kept, invalid = [], [], [] if validate else None
    with safefile.together() as files:
        model_file = files.reserve(request.path)
        picture_file = files.reserve(request.render, ".png") if request.render else None
        viewer_file = files.reserve(request.viewer, ".html") if request.viewer else None
        gltf_file = files.reserve(request.gltf, ".glb") if request.gltf else None
        tiles_dir = files.reserve_dir(request.tiles) if request.tiles else None
        with doing("writing '{}'".format(request.path)), open(model_file, "wb") as f:
            writer = cityjsonseq.SeqWriter(f, _origin(prepared, copied), request.reference_system,
                                           request.title, copied)
            try:
                built = (lod2.build_in_steps(prepared, config) if len(prepared.buildings) or
                         match is None or not len(match.matches.matched) else ())
                for step in built:
                    before = len(step.ids)
                    if match is not None:
                        step = without_footprints(step, match.copied(count))
                    report = replace(report, generated=report.generated + len(step.ids),
                                     replaced=report.replaced + before - len(step.ids))
                    writer.add(step.solids, step.semantics, step.ids, step.attributes)
                    if validate:
                        invalid.extend(validation.validate(step.solids))
                    if request.render:
                        kept.append(_drawn(step, drawn))
                    steps.append(replace(step, solids=None, semantics=None, attributes={}))
                writer.finish()
            finally:
                writer.close()
        if request.render:
            if copied is not None and drawn is not None:
                copied = copy_matched(match, footprints, count, among=drawn)
            report = _render(_single_text(_joined(kept), copied, request), picture_file,
                             request, copied, report, drawn, doing, say,
                             match.kept_previous if match is not None else frozenset())
        if request.viewer or request.gltf or request.tiles:
            _views(model_file, viewer_file, gltf_file, request, every_copied, doing, match,
                   tiles_dir)
    return lod2.summary(steps, prepared.report), report, invalid


def _origin(prepared, copied=None):
    """The integer origin (1 mm) of a model's vertices, known before its
    solids: the lowest corner of the footprints and their ground, and of
    the copied buildings (the lowest vertex of the solids built on them)."""
    b = prepared.buildings
    corners_ = []
    if len(b):
        xy = np.concatenate([np.asarray(ring, dtype=float).reshape(-1, 2) for ring in
                             b.footprints])
        corners_.append(np.round(np.append(xy.min(axis=0), np.min(b.ground)) * 1000.0))
    if copied is not None and len(copied.vertices):
        corners_.append(copied.extent()[0])
    if not corners_:
        return np.zeros(3, dtype=np.int64)
    return np.min(corners_, axis=0).astype(np.int64)
