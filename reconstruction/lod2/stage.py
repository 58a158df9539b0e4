"""The LoD2 buildings of footprints with heights: :func:`prepare`, then :func:`build`.

The core of the stage, which :func:`reconstruction.lod2.run` runs (with the
heights, street edges and existing model around it); a caller with its own
footprints, heights and roof requests calls ``build(prepare(...), config)``:

1. per footprint, its heights (:class:`Heights`: values, e.g. from columns,
   or ranges drawn at random) and its requested roof type
   (:class:`RoofRequests`), checked: no eaves height -> left out, no roof
   height -> flat roof, no ground -> the default ground;
2. the footprints taken apart into polygons and cleaned into rings
   (:mod:`~reconstruction.lod2.outlines`), counting what is left out and why;
3. roof types drawn with the thesis's probabilities where "auto" is
   requested (:meth:`reconstruction.lod2.roofs.rules.RoofRules.draw`);
4. the solids (:func:`reconstruction.lod2.solids.build.build_solids`), their ids
   (``building_<cat>``, ``building_<cat>_<part>`` for footprints of several
   polygons), attributes and semantic surfaces;
5. the CityJSON text (:func:`citymodel_text`).

Random numbers come from one seeded generator, drawn per footprint (roof
type, roof shape, heights) before any footprint is left out, so that a
footprint's building does not depend on the others.
"""

from dataclasses import dataclass, field, replace
from typing import Optional, Union

import numpy as np

from ..cityjson import model as cityjson
from ..core.contract import PLOT, SOURCE
from ..core.errors import InputError
from ..geom.solidset import SolidSet, concat, semantics
from .config import AUTO, Lod2Config
from .heights import GROUND_RANGE, MAX_HEIGHT
from .outlines import clean_rings, footprint_polygons, rings_are_simple
from .roofs.codes import code_attributes
from .roofs.plan import ROOF_TYPES
from .roofs.rules import DEFAULT_RULES, footprint_spans
from .solids.build import Buildings, build_solids, build_solids_steps
from .solids.vertex_budget import needs_budget



# ---------------------------------------------------------------------------
# Inputs
# ---------------------------------------------------------------------------

@dataclass(frozen=True)
class Uniform:
    """Heights drawn at random per footprint, uniformly in [low, high]."""

    low: float
    high: float

    def draw(self, uniforms):
        """The heights for uniform numbers in [0, 1)."""
        return self.low + (self.high - self.low) * uniforms


@dataclass(frozen=True)
class Heights:
    """The heights of every footprint (m): per footprint values (nan = unknown)
    or a :class:`Uniform` range."""

    #: wall height above the ground; unknown, zero or negative: the footprint is left out
    eaves: Union[np.ndarray, Uniform, float]
    #: roof height above the eaves; unknown or negative: a flat roof
    attic: Union[np.ndarray, Uniform, float]
    #: terrain elevation, one value or per footprint; unknown: ``ground_default``
    ground: Union[np.ndarray, float] = 0.0
    ground_default: float = 0.0


@dataclass(frozen=True)
class RoofRequests:
    """What each footprint asks of its roof."""

    #: per footprint, a roof type of :data:`~reconstruction.lod2.roofs.plan.ROOF_TYPES`
    #: or "auto" (drawn with the thesis's probabilities)
    types: np.ndarray
    #: per footprint, its construction year (or the map's); nan = unknown,
    #: which draws as built before the split year
    years: np.ndarray
    #: per footprint, why it gets that roof (the ``roof_source`` attribute, issue 31):
    #: :data:`ROOF_RULE` (drawn by the map's year), :data:`ROOF_OPTION` (roof=),
    #: :data:`ROOF_COLUMN` (roof_column=) or :data:`ROOF_EARLIER` (the earlier
    #: epoch's building); None: not said
    source: Optional[np.ndarray] = None


#: why a building has its roof type (RoofRequests.source)
ROOF_RULE, ROOF_OPTION, ROOF_COLUMN, ROOF_EARLIER = "rule", "option", "column", "earlier epoch"

#: the attributes of a building's height interval (issue 31): the low and high
#: ends of its eaves height and of its ridge height (its top) above the ground.
#: Per footprint (F, 4) in this order they are the heights' intervals (a measured
#: height its own, an inferred one its neighbours' spread, a drawn one its
#: range); given as :attr:`Prepared.extra` under these names, :func:`build`
#: writes them for the building as built (:func:`built_intervals`)
INTERVAL_ATTRIBUTES = ("eaves_height_low", "eaves_height_high", "ridge_height_low",
                       "ridge_height_high")


@dataclass(frozen=True)
class Footprints:
    """Footprint geometries and what is written of them."""

    #: shapely Polygon or MultiPolygon per footprint (None or empty: left out)
    geometries: list
    #: category per footprint (ids ``building_<cat>``); None: 1, 2, ...
    cats: Optional[list] = None
    #: per footprint, its building plot and source (written as attributes), or None
    plot: Optional[list] = None
    source: Optional[list] = None
    #: per footprint, its building identity over the epochs (the ``building``
    #: column of a dynamic chain), the id of its building; None: ``building_<cat>``
    identity: Optional[list] = None


# ---------------------------------------------------------------------------
# Outputs
# ---------------------------------------------------------------------------

@dataclass(frozen=True)
class RoofFallback:
    """A roof that failed validation and fell back to a simpler type."""

    #: category of the footprint
    footprint: Union[int, str]
    kind: str
    reason: str


@dataclass(frozen=True)
class Lod2Report:
    """What happened to the footprints, in counts."""

    #: footprints left out for an unknown, zero or negative eaves height
    bad_eaves: int
    #: footprints with an unknown or negative roof height (flat roof)
    bad_attic: int
    #: footprints with an unknown ground elevation (on the default ground)
    bad_ground: int
    #: holes (inner courtyards) filled
    holes_filled: int
    #: footprints or polygons of footprints left out as empty or degenerate, and why
    left_out: int
    left_out_reasons: dict
    #: footprint polygons to build on
    rings: int
    #: polygons that gave no valid solid, even flat (known after :func:`build`)
    dropped: int = 0
    #: buildings whose roof failed validation and is simpler than requested
    fell_back: int = 0
    #: buildings whose roof type the roof rules changed (a stepped facade with
    #: no free street end is a gable; a gable with no free end is a hip)
    by_rule: int = 0
    #: every roof that failed validation (a building may fall back more than once)
    fallbacks: list = field(default_factory=list)
    #: buildings whose pitched roof stands on their simplified outline (more
    #: than :data:`~reconstruction.lod2.solids.vertex_budget.MAX_ROOF_VERTICES` vertices)
    simplified: int = 0


@dataclass(frozen=True)
class Prepared:
    """The footprints ready to build (see :func:`prepare`)."""

    buildings: Buildings
    #: per building, its footprint (index) and part number (-1: a single polygon)
    source: np.ndarray
    part: np.ndarray
    #: the eaves and roof heights of every footprint as used
    eaves: np.ndarray
    attic: np.ndarray
    ground: np.ndarray
    cats: list
    footprints: Footprints
    report: Lod2Report
    #: more attributes to write: (name, values per building of ``buildings``) pairs
    extra: tuple = ()


@dataclass(frozen=True)
class Lod2Result:
    """The LoD2 buildings of :func:`build`."""

    #: the valid solids (:class:`~reconstruction.geom.solidset.SolidSet`), one per building
    solids: SolidSet
    #: per face, its semantic surface (GROUND, WALL, ROOF of :mod:`~reconstruction.geom.solidset`)
    semantics: np.ndarray
    #: per building, its CityJSON id and the roof type it got
    ids: list
    roof_types: np.ndarray
    #: per building, the index of its footprint
    footprint: np.ndarray
    #: attribute name -> values, one per building
    attributes: dict
    report: Lod2Report

    def roof_counts(self):
        """Roof type -> number of buildings, for every type of
        :data:`~reconstruction.lod2.roofs.plan.ROOF_TYPES`."""
        return {k: int(np.sum(self.roof_types == k)) for k in ROOF_TYPES}


# ---------------------------------------------------------------------------
# Inputs from attribute columns
# ---------------------------------------------------------------------------

#: the plausible values (low, high; None: open) of a column of heights, by its
#: label (:func:`numeric_column`): an eaves or roof height of more than
#: :data:`~reconstruction.lod2.heights.MAX_HEIGHT` (a height in millimetres,
#: 1e9) or a ground outside :data:`~reconstruction.lod2.heights.GROUND_RANGE`
#: (-1,000 m) is a mistake in the data, which no building can be built from
#: (a zero or negative eaves height only leaves its footprint out, a negative
#: roof height gives a flat roof: the thesis's columns use them for "none")
PLAUSIBLE = {"eaves height": (None, MAX_HEIGHT), "roof height": (None, MAX_HEIGHT),
             "ground elevation": GROUND_RANGE}


def numeric_column(columns, name, label):
    """Values of a numeric column as floats (None or '' -> nan).

    ``columns``: name -> values; ``label`` says what the column is for in
    the messages. Raises :class:`InputError` when it is missing or not
    numeric, or, for the heights of :data:`PLAUSIBLE`, a value is outside
    its bounds (naming the first such feature by its ``cat``).
    """
    if name not in columns:
        raise InputError("Column <{}> ({}) not found in the input map; available: {}".format(
            name, label, ", ".join(sorted(columns))))
    out = []
    for v in columns[name]:
        if v is None or v == "":
            out.append(np.nan)
            continue
        try:
            out.append(float(v))
        except (TypeError, ValueError):
            raise InputError("Column <{}> ({}) is not numeric: value <{}>".format(
                name, label, v)) from None
    values = np.asarray(out, dtype=float)
    low, high = PLAUSIBLE.get(label, (None, None))
    with np.errstate(invalid="ignore"):
        bad = np.isinf(values) | (values < (-np.inf if low is None else low)) \
            | (values > (np.inf if high is None else high))
    if bad.any():
        first = int(np.argmax(bad))
        cats = columns.get("cat")
        raise InputError("Column <{}> ({}) of {}: {:g} m is not a plausible {} ({}): is the "
                         "column in another unit, or its value a placeholder?{}".format(
                             name, label, "feature cat {}".format(cats[first]) if cats is not None
                             else "row {}".format(first + 1), values[first], label,
                             "at most {:g} m".format(high) if low is None else
                             "{:g} to {:g} m".format(low, high),
                             "" if bad.sum() == 1 else " ({} such values)".format(int(bad.sum()))))
    return values


def heights_from_columns(columns, count, eaves_column=None, attic_column=None,
                         ground_column=None, ground=0.0, eaves_range=None, attic_range=None):
    """The :class:`Heights` of ``count`` footprints: eaves and roof heights
    from ranges ``(low, high)`` where given, else from their columns; the
    ground from its column where given, else ``ground`` (also for its NULLs)."""
    if eaves_range is not None:
        eaves = Uniform(*eaves_range)
    else:
        eaves = numeric_column(columns, eaves_column, "eaves height")
    if attic_range is not None:
        attic = Uniform(*attic_range)
    else:
        attic = numeric_column(columns, attic_column, "roof height")
    if ground_column:
        values = numeric_column(columns, ground_column, "ground elevation")
    else:
        values = np.full(count, float(ground))
    return Heights(eaves, attic, values, float(ground))


def requests_from_columns(columns, count, roof=AUTO, roof_column=None, map_year=None,
                          year_column=None):
    """The :class:`RoofRequests` of ``count`` footprints: ``roof`` for all,
    but the roof column's type where it has one; the construction year from
    its column where known and not after ``map_year`` (later values, e.g.
    9999, are unknown), else ``map_year``."""
    requested = np.full(count, roof, dtype=object)
    source = np.full(count, ROOF_RULE if roof == AUTO else ROOF_OPTION, dtype=object)
    if roof_column:
        if roof_column not in columns:
            raise InputError("Column <{}> (roof type) not found in the input map".format(
                roof_column))
        values = [None if v is None else str(v).strip().lower() for v in columns[roof_column]]
        known = ROOF_TYPES + (AUTO,)
        unknown = sorted({v for v in values if v not in (None, "") and v not in known})
        if unknown:
            raise InputError("Unknown roof types in column <{}>: {} (known: {})".format(
                roof_column, ", ".join(unknown), ", ".join(ROOF_TYPES)))
        requested = np.array([v if v not in (None, "") else roof for v in values], dtype=object)
        source = np.where([v not in (None, "") for v in values], ROOF_COLUMN, source)
        source[requested == AUTO] = ROOF_RULE           # "auto" in the column: drawn
    years = np.full(count, np.nan if map_year is None else float(map_year))
    if year_column:
        built = numeric_column(columns, year_column, "construction year")
        known = ~np.isnan(built) & (built > 0)
        if map_year is not None:
            known &= built <= map_year
        years = np.where(known, built, years)
    return RoofRequests(requested, years, source.astype(object))


# ---------------------------------------------------------------------------
# The stage
# ---------------------------------------------------------------------------

def prepare(footprints, heights, requests, config=None):
    """The footprints as buildings ready to build (:class:`Prepared`): heights
    checked, polygons cleaned, roof types drawn. Steps 1 to 3 of the module doc."""
    config = config or Lod2Config()
    n = len(footprints.geometries)
    rng = np.random.default_rng(config.seed)
    u_type = rng.random(n)
    u_shape = rng.random((n, 3))
    u_height = rng.random((n, 2))
    eaves = _per_footprint(heights.eaves, u_height[:, 0], n)
    attic = _per_footprint(heights.attic, u_height[:, 1], n)
    ground = _per_footprint(heights.ground, None, n)
    requested = np.asarray(requests.types, dtype=object)
    bad_eaves = np.isnan(eaves) | (eaves <= 0)
    bad_attic = np.isnan(attic) | (attic < 0)
    if bad_attic.any():
        attic = np.where(bad_attic, 0.0, attic)
        requested = np.where(bad_attic, "flat", requested)
    bad_ground = np.isnan(ground)
    if bad_ground.any():
        ground = np.where(bad_ground, float(heights.ground_default), ground)
    rings, src, part, holes, left_out, reasons = _footprint_rings(footprints.geometries, bad_eaves)
    nverts = np.array([len(r) for r in rings])
    rules = DEFAULT_RULES if config.rules is None else config.rules
    drawn = rules.draw(nverts, np.asarray(requests.years)[src], attic[src], u_type[src],
                       *footprint_spans(rings))
    types = np.where(requested[src] == AUTO, drawn, requested[src])
    report = Lod2Report(bad_eaves=int(bad_eaves.sum()), bad_attic=int(bad_attic.sum()),
                        bad_ground=int(bad_ground.sum()), holes_filled=holes, left_out=left_out,
                        left_out_reasons=reasons, rings=len(rings))
    cats = footprints.cats if footprints.cats is not None else list(range(1, n + 1))
    return Prepared(Buildings(rings, ground[src], eaves[src], attic[src], types, u_shape[src]),
                    src, part, eaves, attic, ground, cats, footprints, report)


def _per_footprint(values, uniforms, n):
    """Per footprint values (floats) of a height: drawn from a :class:`Uniform`, or given."""
    if isinstance(values, Uniform):
        return values.draw(uniforms)
    values = np.asarray(values, dtype=float)
    return np.full(n, float(values)) if values.ndim == 0 else values


def _footprint_rings(geometries, skip):
    """The clean rings of every polygon of the footprints (but those to ``skip``):
    ``(rings, footprint of each, part of each, holes, left out, reasons)``."""
    fp = footprint_polygons(geometries, skip=skip)
    polys, src, part, holes, left_out = fp.polygons, fp.source, fp.part, fp.holes, fp.empty
    reasons = {}
    cleaned, why = clean_rings(polys)
    ok = np.array([r is not None for r in cleaned], dtype=bool)
    for w in why:
        if w is not None:
            left_out += 1
            reasons[w] = reasons.get(w, 0) + 1
    rings = [r for r, good in zip(cleaned, ok) if good]
    src, part = src[ok], part[ok]
    simple = rings_are_simple(rings)
    if not simple.all():
        left_out += int((~simple).sum())
        reasons["self-intersecting outline"] = int((~simple).sum())
        rings = [r for r, good in zip(rings, simple) if good]
        src, part = src[simple], part[simple]
    return rings, src, part, holes, left_out, reasons


def build(prepared, config=None):
    """The :class:`Lod2Result` of :func:`prepare`'s buildings: steps 4 of the module doc.

    Raises :class:`InputError` when no footprint is left to build.
    """
    config = config or Lod2Config()
    if not len(prepared.buildings):
        raise InputError("No footprint left to build")
    return _result(prepared, build_solids(prepared.buildings, config.roof, nprocs=config.nprocs),
                   len(prepared.buildings), config)


def build_in_steps(prepared, config=None):
    """:func:`build` a step of buildings at a time
    (:func:`~reconstruction.lod2.solids.build.build_solids_steps`), for a
    writer that streams: yields the :class:`Lod2Result` of every step in
    turn, its report counting the dropped, fallen back, changed and
    simplified buildings of that step (:func:`summary` adds them up).

    Raises :class:`InputError` when no footprint is left to build.
    """
    config = config or Lod2Config()
    if not len(prepared.buildings):
        raise InputError("No footprint left to build")
    for idx, built in build_solids_steps(prepared.buildings, config.roof, nprocs=config.nprocs):
        yield _result(prepared, built, len(idx), config)


def summary(steps, report):
    """One :class:`Lod2Result` of the ``steps`` of :func:`build_in_steps`,
    without their solids (written step by step and let go): ids, roof types
    and footprints of every building and the counts of ``report`` (the
    prepared footprints') with the steps' added up."""
    steps = list(steps)
    ss = concat([])
    return Lod2Result(
        ss, semantics(ss), [i for r in steps for i in r.ids],
        np.concatenate([r.roof_types for r in steps]) if steps else np.zeros(0, dtype=object),
        np.concatenate([r.footprint for r in steps]) if steps else np.zeros(0, dtype=np.int64),
        {}, replace(report, dropped=sum(r.report.dropped for r in steps),
                    fell_back=sum(r.report.fell_back for r in steps),
                    by_rule=sum(r.report.by_rule for r in steps),
                    simplified=sum(r.report.simplified for r in steps),
                    fallbacks=[f for r in steps for f in r.report.fallbacks]))


def _result(prepared, built, count, config):
    """The :class:`Lod2Result` of ``built`` (:class:`~reconstruction.lod2.solids.build.BuiltSolids`
    of ``count`` of the prepared buildings, indexed among all)."""
    buildings = prepared.buildings
    ss, kept, got, log = built.solids, built.kept, built.types, built.log
    src, cats = prepared.source, prepared.cats
    fsrc = src[kept]
    part = prepared.part
    ids = []
    identity = prepared.footprints.identity
    for j, i in zip(kept, fsrc):
        base = "building_{}".format(cats[i]) if identity is None or identity[i] in (None, "") \
            else str(identity[i])
        ids.append(base if part[j] < 0 else "{}_{}".format(base, part[j] + 1))

    def per_building(values):
        return [values[i] for i in fsrc] if values is not None else [None] * len(fsrc)

    attributes = {
        "roof_type": list(got),
        **code_attributes(got),
        "eaves_height": np.round(prepared.eaves[fsrc], 3),
        "roof_height": np.round(np.where(got == "flat", 0.0, prepared.attic[fsrc]), 3),
        "ground_height": np.round(prepared.ground[fsrc], 3),
        "map_year": [config.map_year] * len(fsrc),
        PLOT: per_building(prepared.footprints.plot),
        SOURCE: per_building(prepared.footprints.source),
        "footprint": [cats[i] for i in fsrc],
    }
    for name, values in prepared.extra:
        attributes[name] = [values[j] for j in kept]
    if INTERVAL_ATTRIBUTES[0] in attributes:
        ends = built_intervals(
            np.column_stack([np.asarray(attributes[k], dtype=float) for k in INTERVAL_ATTRIBUTES]),
            prepared.eaves[fsrc], np.where(got == "flat", 0.0, buildings.attic[kept]),
            np.round(solid_tops(ss) - attributes["ground_height"], 3))
        attributes.update((name, ends[:, k]) for k, name in enumerate(INTERVAL_ATTRIBUTES))
    failed = np.zeros(len(buildings), dtype=bool)
    failed[[f.index for f in log]] = True
    changed = got != buildings.roof_types[kept]
    report = replace(prepared.report, dropped=count - len(kept),
                                      fell_back=int(np.sum(changed & failed[kept])),
                                      by_rule=int(np.sum(changed & ~failed[kept])),
                                      simplified=int(needs_budget(
                                          [buildings.footprints[k] for k in kept], got).sum()),
                                      fallbacks=[RoofFallback(cats[src[f.index]], f.kind, f.reason)
                                                 for f in log])
    return Lod2Result(ss, semantics(ss), ids, got, fsrc, attributes, report)


def solid_tops(ss):
    """The highest z (m, absolute) of every solid of ``ss`` (a SolidSet); NaN for an empty one."""
    top = np.full(len(ss), -np.inf)
    if len(ss.rings):
        owner = ss.face_solid[ss.entry_face]
        np.maximum.at(top, owner, ss.vertices[ss.rings, 2] / 1000.0)
    return np.where(np.isfinite(top), top, np.nan)


def built_intervals(interval, eaves, roof, top):
    """The (B, 4) height intervals of :data:`INTERVAL_ATTRIBUTES` of buildings as built.

    ``interval`` (B, 4): those of their heights (NaN: unknown); ``eaves`` and
    ``roof``: the eaves and roof heights they were built with (0 for a flat
    roof); ``top``: the highest z of each solid above its ground (m).

    The heights' intervals bound the eaves and the ridge the roof was asked
    to reach, but the roof that stands may end elsewhere: a flat roof (drawn
    by the rules, asked for, or a pitched roof that failed and fell back)
    ends at the eaves, so its ridge interval is the eaves'; a gable facade
    (neck, bell, spout, crow-stepped) rises above the roof's ridge by its
    crown, which raises both ends by as much. So the ridge interval is the
    eaves' (flat) or the ridge's (pitched) moved by ``top - (eaves + roof)``:
    it holds the built top wherever the heights' interval held the heights
    (a measured building's is its top exactly). The ends are rounded to the
    millimetre (the solids' grid, the written heights') and widened to hold
    the values as written (the eaves rounded to the millimetre, the top):
    the top is never outside by rounding."""
    interval = np.asarray(interval, dtype=float).reshape(-1, 4)
    eaves, roof, top = (np.asarray(v, dtype=float) for v in (eaves, roof, top))
    flat = roof <= 0
    shift = top - (eaves + roof)
    ridge = np.where(flat[:, None], interval[:, 0:2], interval[:, 2:4]) + shift[:, None]
    out = np.round(np.column_stack([interval[:, 0:2], ridge]), 3)
    value = np.column_stack([np.round(eaves, 3), top])
    known = ~np.isnan(out)
    out[:, 0::2] = np.where(known[:, 0::2], np.fmin(out[:, 0::2], value), np.nan)
    out[:, 1::2] = np.where(known[:, 1::2], np.fmax(out[:, 1::2], value), np.nan)
    return out


def citymodel_text(result, reference_system=None, title=None):
    """The CityJSON 2.0 text of a :class:`Lod2Result` (see
    :func:`reconstruction.cityjson.model.citymodel_text`)."""
    return cityjson.citymodel_text(result.solids, result.semantics, result.ids, result.attributes,
                                   reference_system, title=title)
