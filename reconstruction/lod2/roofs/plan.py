"""Roofs of LoD2 buildings: flat, hip, gable, mansard and crow-stepped gable.

The roof set of Morlighem (2021), Section 3.4.2, built in numpy:

- **hip**: the straight skeleton of the footprint raised at the roof pitch.
  The long faces get the pitch of the thesis's Eq. 3.13,
  ``atan(height / (baseline / 2))``, the hip ends (the shortest edge and the
  edge opposite it) a steeper pitch in ``[pitch_min, 90)`` degrees; the roof
  is then scaled so that its ridge sits exactly at the roof height.
- **gable**: a hip roof whose ends are vertical.
- **mansard**: the skeleton truncated at the roof height with a flat top; the
  inset (horizontal run of the lower faces) stays below :data:`MANSARD_CAP`
  of the radius of the largest circle in the footprint, so that the flat top
  is there (for a rectangle: below 0.45 of its width).
- **stepped**: a gable roof whose street end (the shortest edge until the
  street edge is known) is a crow-stepped facade of the given step height and
  thickness, kept inside the footprint.
- **flat**: the footprint at the eaves.

This file draws the roof types and plans each roof (:func:`plan_roofs`:
which solver family builds it, with which slopes); one function per family
then solves the plan. The families: flat roofs; the lower envelope of the
edge planes for convex footprints (:mod:`~reconstruction.lod2.roofs.envelope`, in
batch), with the crow-stepped facade on top of a stepped roof's body
(:mod:`~reconstruction.lod2.roofs.facades`); CGAL's straight skeleton for concave
ones (:mod:`~reconstruction.lod2.roofs.skeleton`). Roofs come as
:class:`~reconstruction.lod2.roofs.model.RoofGroup` arrays where a family builds
them in batch, as one :class:`~reconstruction.lod2.roofs.model.Roof` each
otherwise.
"""

import dataclasses
import math
from dataclasses import dataclass
from typing import Optional

import numpy as np
import shapely

from ..outlines import edge_lengths, end_edges, is_convex, opposite_edges, outline_facts
from .envelope import MAX_VERTICES as ENVELOPE_MAX_VERTICES
from .envelope import Raised, batch_rows, envelope_arrays
from .facades import PROFILES as FACADE_PROFILES
from .facades import clip_strips, facade_arrays
from .model import RoofConfig, flat_group
from .pyramid import apexes, pyramid_group
from .shed import shed_group
from .skeleton import cgal_roofs
from .staged import staged_roofs

#: the gable facades (neck, bell, spout) are planned as "stepped" is, with their own outline
ROOF_TYPES = ("flat", "hip", "gable", "mansard", "stepped", "neck", "bell", "spout", "half_hip",
              "pyramid", "gambrel", "shed", "cornice")

#: Roof type probabilities (weights in percent) by period of construction and
#: footprint shape, as in the thesis's Table B.1 as implemented in its published
#: procedural-modelling script (histo3d, ``blender_procedural_mod.py``):
#: "stepped" is its "dutch" roof. For n-sided footprints the script's
#: complex-hip weights are used, since hip and gable roofs work on any
#: footprint here; the split year is 1915 (the thesis's table; the script
#: uses 1930).
ROOF_PROBABILITIES = {
    ("before", 4): {"flat": 10, "hip": 20, "gable": 20, "mansard": 10, "stepped": 40},
    ("after", 4): {"flat": 25, "hip": 25, "gable": 25, "mansard": 10, "stepped": 15},
    ("before", "n"): {"flat": 15, "hip": 65, "mansard": 20},
    ("after", "n"): {"flat": 40, "hip": 40, "mansard": 20},
}
SPLIT_YEAR = 1915
#: Roofs lower than this (m) are flat when the type is drawn (thesis: < 1 m).
MIN_PITCHED_HEIGHT = 1.0
#: a mansard's inset is at most this share of the footprint's inscribed radius
MANSARD_CAP = 0.9
#: the inscribed radius is found to this (m) where it caps an inset, ...
MANSARD_CAP_TOLERANCE = 1e-3
#: ... to this (m) first, to tell where it may (see :func:`mansard_caps`)
MANSARD_CAP_COARSE = 0.05


def draw_roof_types(n_vertices, years, attic, uniforms, probabilities=None):
    """Draw a roof type per footprint with the thesis's probabilities.

    ``n_vertices``: vertices per footprint; ``years``: construction year (or
    the map year) per footprint, None/nan = before 1915; ``attic``: roof
    height, below :data:`MIN_PITCHED_HEIGHT` the roof is flat; ``uniforms``:
    a uniform number in [0, 1) per footprint, so that a footprint's type does
    not depend on the others. Returns an object array of roof type names.
    """
    probabilities = probabilities or ROOF_PROBABILITIES
    n_vertices = np.asarray(n_vertices)
    years = np.asarray([np.nan if y is None else y for y in np.broadcast_to(
        np.asarray(years, dtype=object), n_vertices.shape)], dtype=float)
    out = np.empty(n_vertices.shape, dtype=object)
    u = np.asarray(uniforms, dtype=float).reshape(n_vertices.shape)
    after = np.where(np.isnan(years), False, years > SPLIT_YEAR)
    for period, is_after in (("before", False), ("after", True)):
        for shape in (4, "n"):
            sel = (after == is_after) & ((n_vertices == 4) if shape == 4 else (n_vertices != 4))
            out[sel] = weighted_pick(list(probabilities[(period, shape)].items()), u[sel])
    out[np.asarray(attic, dtype=float) < MIN_PITCHED_HEIGHT] = "flat"
    return out


def weighted_pick(weights, uniforms):
    """The names of ``weights`` ((name, weight) pairs) picked by uniform numbers
    in [0, 1): each name for a share of [0, 1) proportional to its weight."""
    names = [name for name, _ in weights]
    cum = np.cumsum([w for _, w in weights], dtype=float)
    cum /= cum[-1]
    idx = np.minimum(np.searchsorted(cum, uniforms, side="right"), len(names) - 1)
    return np.asarray(names, dtype=object)[idx]


# ---------------------------------------------------------------------------
# Planning: which family builds each roof, with which slopes
# ---------------------------------------------------------------------------

@dataclass(frozen=True)
class EnvelopeJob:
    """A roof of a convex footprint for :func:`~reconstruction.lod2.roofs.envelope.envelope_arrays`."""

    #: footprint index
    index: int
    #: the footprint, or the main body of a stepped roof (its inner edge first)
    xy: np.ndarray
    #: tangent of each edge's pitch, inf for a vertical (gable) end
    slopes: np.ndarray
    #: height of the flat top (mansard), or None: the ridge is scaled to the roof height
    top: Optional[float]
    #: True for the main body of a stepped roof (its facade is in ``RoofPlan.facades``)
    body: bool = False
    #: planes rising above the eaves (half-hip ends, a gambrel's upper slopes):
    #: a :class:`~reconstruction.lod2.roofs.envelope.Raised` of (E,) arrays, or None
    raised: Optional[Raised] = None


@dataclass(frozen=True)
class SkeletonJob:
    """A roof of a concave footprint for :func:`~reconstruction.lod2.roofs.skeleton.cgal_roofs`."""

    index: int
    xy: np.ndarray
    #: pitch of each edge (degrees, 90 = gable end)
    pitches: np.ndarray
    #: height of the flat top (mansard), or None: the ridge is scaled to the roof height
    top: Optional[float]


@dataclass(frozen=True)
class StagedJob:
    """A two-slope roof of a concave footprint for
    :func:`~reconstruction.lod2.roofs.staged.staged_roofs` (half-hip, gambrel)."""

    index: int
    xy: np.ndarray
    #: pitch of each edge below and above the knee (degrees, 90 = vertical)
    lower: np.ndarray
    upper: np.ndarray
    #: knee height (before the roof is scaled to its height)
    knee: float


@dataclass(frozen=True)
class Facade:
    """The gable facade of a stepped (neck, bell, spout) roof."""

    #: the footprint edge it stands on
    end: int
    #: step height (m)
    step: float
    #: its outline, a name of :data:`~reconstruction.lod2.roofs.facades.PROFILES`
    profile: str = "stepped"


@dataclass(frozen=True)
class RoofPlan:
    """Which solver family builds each roof, and its parameters."""

    #: the roof type each footprint gets (a stepped roof on a concave or
    #: triangular footprint, or too short for its facade, is a gable)
    kinds: list
    #: vertex count -> footprints with a flat roof
    flat: dict
    #: convex roofs and stepped roofs' bodies, in footprint order
    envelope: list
    #: footprint -> its :class:`Facade`, for the stepped roofs among ``envelope``
    facades: dict
    #: concave roofs, in footprint order
    skeleton: list
    #: footprint -> its ends: ``(edge, "gable" | "hip" | "stepped")`` pairs, the
    #: edges with a vertical gable end, a hip end steeper than the long faces
    #: or a crow-stepped facade
    ends: dict
    #: pyramid roofs: (footprint, apex (2,)) pairs
    pyramids: list = dataclasses.field(default_factory=list)
    #: shed roofs: (footprint, (edge, low along it)) pairs
    sheds: list = dataclasses.field(default_factory=list)
    #: two-slope roofs of concave footprints (:class:`StagedJob`)
    staged: list = dataclasses.field(default_factory=list)


def plan_roofs(footprints, roof_types, attic, uniforms, config=None, street=None, shared=None):
    """The :class:`RoofPlan` of footprints (local coordinates, counter-clockwise
    rings); arguments as :func:`make_roofs`.

    No end goes on a shared edge (``shared``), as a builder would do it: a
    gable or stepped roof whose far end (opposite the street edge) is shared
    with the neighbour behind gets a hip there at the pitch of its long faces
    (a front gable with a hipped back, the common Dutch town house), so no
    gable wall and no steep end stands against the neighbour; a hip roof's
    shared end takes the long faces' pitch too; a stepped facade needs a free
    street end (else the roof is a gable); a gable with both ends shared is a
    hip at one pitch; a concave gable keeps its free arm ends only."""
    config = config or RoofConfig()
    B = len(footprints)
    kinds = list(roof_types)
    uniforms = np.asarray(uniforms, dtype=float).reshape(B, 3)
    facts = outline_facts(footprints, street)
    convex_all, end_all, opp_all = (v.tolist() for v in (facts.convex, facts.end, facts.opposite))
    attic = np.asarray(attic, dtype=float)
    flat = np.array([k == "flat" for k in roof_types], dtype=bool) | (attic <= 1e-3)
    bodies = _stepped_bodies(footprints, roof_types, flat, facts, config.thickness)
    lo, hi = config.inset
    wanted = lo + (hi - lo) * uniforms[:, 1]                  # the mansards' insets, uncapped
    caps = mansard_caps(footprints, [k == "mansard" and not f for k, f in zip(roof_types, flat)],
                        wanted)
    apex = _pyramid_apexes(footprints, [k == "pyramid" and not f for k, f in zip(roof_types, flat)])
    plan = RoofPlan(kinds, {}, [], {}, [], {})
    for i, (xy, kind) in enumerate(zip(footprints, roof_types)):
        h = float(attic[i])
        n = len(xy)
        mask = None if shared is None else shared[i]
        if flat[i]:
            plan.flat.setdefault(n, []).append(i)
            continue
        end = end_all[i]
        convex = convex_all[i] and n <= ENVELOPE_MAX_VERTICES
        if kind == "pyramid":
            if i in apex and (mask is None or not np.any(mask[:n])):
                plan.pyramids.append((i, apex[i]))
                continue
            # no apex sees every edge, or a neighbour shares an edge (its face
            # there would be a steep end against it): a tent roof is a hip
            kind = "hip"
        if kind == "shed":
            edge, low = _shed_edge(xy, mask, None if street is None else street[i])
            if edge >= 0:
                plan.sheds.append((i, (edge, low)))
                continue
            kinds[i] = "flat"                   # no side free for a shed's walls
            plan.flat.setdefault(n, []).append(i)
            continue
        if kind == "cornice" and n >= 4:
            # the ends beside the street edge: gable walls where free, a hip at
            # the long faces' pitch against a neighbour; with none free, a hip
            sides = [e for e in ((end - 1) % n, (end + 1) % n) if _free(mask, e)]
            if sides:
                plan.ends[i] = [(e, "gable") for e in sides]
                if convex:
                    slopes = np.ones(n)
                    slopes[sides] = np.inf
                    plan.envelope.append(EnvelopeJob(i, xy, slopes, None))
                else:
                    pitch = np.full(n, 45.0)
                    pitch[sides] = 90.0
                    plan.skeleton.append(SkeletonJob(i, xy, pitch, None))
                continue
            kind = "hip"
        if kind in ("half_hip", "gambrel") and convex:
            job, ends, kind = _raised_job(kind, i, xy, h, end if _free(mask, end) else -1,
                                          opp_all[i] if _free(mask, opp_all[i]) else -1,
                                          float(facts.end_length[i]), uniforms[i], config)
            plan.envelope.append(job)
            kinds[i] = kind
            if ends:
                plan.ends[i] = ends
            continue
        if kind in ("half_hip", "gambrel") and n >= 4:
            ends = [e for e in (end_edges(xy) or [end]) if _free(mask, e)]
            plan.staged.append(_staged_job(kind, i, xy, ends, h, uniforms[i], config))
            kinds[i] = kind
            plan.ends[i] = [(e, "half_hip" if kind == "half_hip" else "gable") for e in ends]
            continue
        if kind in ("half_hip", "gambrel", "cornice"):
            kind = "gable"                    # a triangle: no second slope, no cornice
        if kind == "mansard":
            ins = max(min(wanted[i], caps[i]), 1e-3)
            if convex:
                plan.envelope.append(EnvelopeJob(i, xy, np.full(n, h / ins), h))
            else:
                pitch = np.full(n, math.degrees(math.atan2(h, ins)))
                plan.skeleton.append(SkeletonJob(i, xy, pitch, h))
            continue
        opp = opp_all[i]
        if kind in FACADE_PROFILES and i in bodies and _free(mask, end):
            body, body_opp = bodies[i]
            slopes = np.ones(len(body))
            slopes[0] = np.inf
            plan.ends[i] = [(end, kind)]
            if body_opp >= 0 and _free(mask, opp):
                slopes[body_opp] = np.inf
                plan.ends[i].append((opp, "gable"))
            s_lo, s_hi = config.step
            plan.facades[i] = Facade(end, s_lo + (s_hi - s_lo) * uniforms[i, 2], kind)
            plan.envelope.append(EnvelopeJob(i, body, slopes, None, body=True))
            continue
        if kind in FACADE_PROFILES:
            kind = "gable"
        if convex:
            if kind == "gable" and not _free(mask, end) and not _free(mask, opp):
                kind = "hip"                 # no free end: one pitch all round
            slopes = _convex_slopes(kind, n, h, end if _free(mask, end) else -1,
                                    opp if _free(mask, opp) else -1, float(facts.end_length[i]),
                                    uniforms[i, 0], config.pitch_min)
            plan.envelope.append(EnvelopeJob(i, xy, slopes, None))
            ends = [(e, kind) for e in (end, opp) if _free(mask, e) and slopes[e] > 1.0 + 1e-9]
        else:
            pitch = np.full(n, 45.0)
            ends = []
            if kind == "gable":
                ends = [(e, "gable") for e in (end_edges(xy) or [end]) if _free(mask, e)]
                pitch[[e for e, _ in ends]] = 90.0
                if not ends:
                    kind = "hip"
            plan.skeleton.append(SkeletonJob(i, xy, pitch, None))
        kinds[i] = kind
        if ends:
            plan.ends[i] = ends
    return plan


#: half-hip: the gable wall rises to this share of the ridge height (low, high) ...
HALF_HIP_SHARE = (0.5, 0.75)
#: ... and the small hip above it is steeper than the long faces, up to this pitch (degrees)
HALF_HIP_PITCH = 75.0
#: gambrel: the knee is this share of the half span in from the eaves (low, high) ...
GAMBREL_KNEE = (0.3, 0.45)
#: ... and the lower faces this many times as steep as the upper ones (low, high)
GAMBREL_RATIO = (3.0, 4.0)


def _drawn(bounds, u):
    """The value a uniform number ``u`` in [0, 1) draws in ``(low, high)``."""
    return bounds[0] + (bounds[1] - bounds[0]) * u


def _half_hip_shape(h, half, u):
    """A half-hip's (ratio of its small hip's slope to the long faces', share
    of the ridge height its gable walls reach) for a roof ``h`` high over a
    half span ``half``, drawn by ``u``."""
    p_long = math.degrees(math.atan2(h, half))
    p_hip = p_long + (max(HALF_HIP_PITCH, p_long) - p_long) * u[0]
    return math.tan(math.radians(p_hip)) / math.tan(math.radians(p_long)), \
        _drawn(HALF_HIP_SHARE, u[1])


def _gambrel_shape(half, u):
    """A gambrel's (ratio of its lower faces' slope to the upper ones', the
    knee's run in from the eaves) over a half span ``half``, drawn by ``u``."""
    return _drawn(GAMBREL_RATIO, u[0]), _drawn(GAMBREL_KNEE, u[1]) * half


def _raised_job(kind, i, xy, h, end, opp, end_length, u, config):
    """The envelope job of a half-hip or gambrel roof on a convex footprint
    whose free ends are ``end`` and ``opp`` (-1: shared or none), the ends
    it gets and the kind it really is.

    Half-hip: the free ends are gable walls up to :data:`HALF_HIP_SHARE` of
    the ridge height (drawn by ``u[1]``) under a small hip between the long
    faces' pitch and :data:`HALF_HIP_PITCH` (``u[0]``); with no free end it
    is a hip roof. Gambrel: every edge but the free ends has a lower face
    :data:`GAMBREL_RATIO` times as steep as the upper one (``u[0]``), the
    knee :data:`GAMBREL_KNEE` of the half span in (``u[1]``); the free ends
    are gable walls (with none, a hipped gambrel). Heights are before the
    roof is scaled to its height (the long faces at slope 1, the half span
    ``end_length / 2`` high), which keeps every ratio."""
    n = len(xy)
    free = [e for e in (end, opp) if e >= 0]
    if kind == "half_hip" and not free:
        slopes = _convex_slopes("hip", n, h, -1, -1, end_length, u[0], config.pitch_min)
        return EnvelopeJob(i, xy, slopes, None), [], "hip"
    slopes = np.ones(n)
    slopes[free] = np.inf
    half = end_length / 2.0
    if kind == "half_hip":
        ratio, share = _half_hip_shape(h, half, u)
        raised = Raised(np.array(free), np.full(len(free), ratio),
                        share * edge_lengths(xy)[free] / 2.0)
        return EnvelopeJob(i, xy, slopes, None, raised=raised), \
            [(e, "half_hip") for e in free], kind
    ratio, knee = _gambrel_shape(half, u)
    sides = np.array([e for e in range(n) if e not in free])
    slopes[sides] = ratio
    raised = Raised(sides, np.ones(len(sides)), np.full(len(sides), (ratio - 1.0) * knee))
    return EnvelopeJob(i, xy, slopes, None, raised=raised), [(e, "gable") for e in free], kind


def _staged_job(kind, i, xy, ends, h, u, config):
    """The :class:`StagedJob` of a half-hip or gambrel roof on a concave
    footprint with free ends ``ends``, in the proportions of
    :func:`_raised_job` (the half span: half the narrowest free end, else
    the radius of the largest circle inside)."""
    n = len(xy)
    half = float(edge_lengths(xy)[ends].min() / 2.0) if ends else float(shapely.length(
        shapely.maximum_inscribed_circle(shapely.Polygon(xy), tolerance=1e-2)))
    lower = np.full(n, 45.0)
    upper = np.full(n, 45.0)
    if kind == "half_hip":
        ratio, share = _half_hip_shape(h, half, u)
        lower[ends] = 90.0
        upper[ends] = math.degrees(math.atan(ratio))
        return StagedJob(i, xy, lower, upper, share * half)
    ratio, knee = _gambrel_shape(half, u)
    lower[:] = math.degrees(math.atan(ratio))
    lower[ends] = upper[ends] = 90.0
    return StagedJob(i, xy, lower, upper, ratio * knee)


def _pyramid_apexes(footprints, which):
    """footprint -> the apex of its pyramid roof, for the footprints ``which``
    that have one (see :mod:`~reconstruction.lod2.roofs.pyramid`)."""
    out = {}
    pairs = [(int(i), None) for i in np.nonzero(np.asarray(which, dtype=bool))[0]]
    for idx, xy, _ in _by_vertex_count(footprints, pairs):
        apex, sees = apexes(xy)
        out.update((int(i), a) for i, a, ok in zip(idx, apex, sees) if ok)
    return out


def _shed_edge(xy, shared, street):
    """The edge a shed roof runs along and whether it is low there, or
    ``(-1, False)`` for none (a flat roof). A shed has walls above the eaves
    on every edge but its low side, so, like every roof's ends, it keeps
    them off its neighbours: with no shared edge it is high along its street
    edge where known, else its longest edge (the roof falls across the
    narrow span); a convex 4-sided footprint with one shared edge is low
    along it (the roof falls to it); any other sharing leaves no side free
    for its walls: none."""
    n = len(xy)
    on = np.zeros(n, dtype=bool) if shared is None else np.asarray(shared[:n], dtype=bool)
    if not on.any():
        if street is not None and 0 <= int(street) < n:
            return int(street), False
        return int(np.argmax(edge_lengths(xy))), False
    if n == 4 and on.sum() == 1 and is_convex(xy):
        return int(np.argmax(on)), True
    return -1, False


def mansard_caps(footprints, which, wanted=None):
    """Per footprint the largest inset of a mansard roof (m): :data:`MANSARD_CAP`
    of the radius of the largest circle inside it, where ``which`` (else 0).

    Not the footprint's shortest edge: the lower faces of the short edges of
    a footprint end below the top, as hip faces do, and a cadastre outline
    has edges of a few millimetres; capped by those, its mansard had lower
    faces within a degree of vertical, walls above the eaves on every edge,
    the shared ones too.

    ``wanted`` (per footprint, or None): the insets the caps are for; a cap
    above its footprint's wanted inset need not be exact and may be any
    value at least that inset. GEOS's search for the circle refines a grid
    of cells until no cell could hold a centre :data:`MANSARD_CAP_TOLERANCE`
    farther from the boundary than the best one; where the centres line a
    ridge (a long near-rectangle) it splits cells all along it, up to its
    iteration limit (2,000 + 2,000 ln(diameter / tolerance)): up to 20 ms a
    footprint, 0.25 s for the 403 mansards of the Brussels 1924 footprints,
    99 % of it for 40 of them. So the radius is first found to
    :data:`MANSARD_CAP_COARSE`: the best centre's distance to the boundary
    is at most the true radius, which the fine search comes within its
    tolerance of; where that distance less the fine tolerance already puts
    the cap at or above the wanted inset, ``min(wanted, cap)`` is the wanted
    inset either way, and the fine search runs only for the others."""
    idx = np.nonzero(np.asarray(which, dtype=bool))[0]
    out = np.zeros(len(footprints))
    if not len(idx):
        return out
    polygons = np.empty(len(idx), dtype=object)
    polygons[:] = [shapely.Polygon(np.asarray(footprints[i], dtype=float)) for i in idx]
    if wanted is not None:
        coarse = shapely.length(shapely.maximum_inscribed_circle(
            polygons, tolerance=MANSARD_CAP_COARSE))
        out[idx] = MANSARD_CAP * (coarse - MANSARD_CAP_TOLERANCE)     # at most the cap
        fine = out[idx] < np.asarray(wanted, dtype=float)[idx]
        idx, polygons = idx[fine], polygons[fine]
    if len(idx):
        out[idx] = MANSARD_CAP * shapely.length(
            shapely.maximum_inscribed_circle(polygons, tolerance=MANSARD_CAP_TOLERANCE))
    return out


def _free(shared, edge):
    """True when ``edge`` (-1: none) exists and is not ``shared`` (None: no edge is)."""
    return edge >= 0 and (shared is None or edge >= len(shared) or not shared[edge])


def _stepped_bodies(footprints, roof_types, flat, facts, thickness):
    """footprint -> (main body ring, the body edge opposite its inner edge or
    -1) of the stepped roofs of convex footprints whose facade strip fits."""
    want = np.array([k in FACADE_PROFILES for k in roof_types], dtype=bool) & ~flat & facts.convex
    want &= np.array([4 <= len(xy) <= ENVELOPE_MAX_VERTICES for xy in footprints], dtype=bool)
    bodies = {}
    for n in sorted({len(footprints[i]) for i in np.nonzero(want)[0]}):
        idx = np.array([i for i in np.nonzero(want)[0] if len(footprints[i]) == n])
        body, ok = clip_strips(np.stack([footprints[i] for i in idx]), facts.end[idx], thickness)
        opp = opposite_edges(body, np.zeros(len(idx), dtype=np.int64))
        for k in np.nonzero(ok)[0]:
            bodies[int(idx[k])] = (body[k], int(opp[k]))
    return bodies


def _convex_slopes(kind, n, h, end, opp, end_length, u, pitch_min):
    """Edge slopes of a hip or gable roof on a convex footprint: hip ends of a
    quadrilateral steeper (between ``pitch_min`` and 89 degrees, drawn by
    ``u``), gable ends vertical."""
    slopes = np.ones(n)
    ends = [e for e in (end, opp) if e >= 0]
    if kind == "hip" and n == 4:
        p_long = math.degrees(math.atan2(h, end_length / 2.0))
        low = min(max(pitch_min, p_long), 89.0)
        p_end = low + (89.0 - low) * u
        slopes[ends] = math.tan(math.radians(p_end)) / math.tan(math.radians(p_long))
    elif kind == "gable":
        slopes[ends] = np.inf
    return slopes


# ---------------------------------------------------------------------------
# Solving the plan: one function per family
# ---------------------------------------------------------------------------

@dataclass(frozen=True)
class RoofSet:
    """The roofs of a set of footprints (see :func:`make_roofs`)."""

    #: the roof type each footprint really got
    kinds: list
    #: roofs built in batch (:class:`~reconstruction.lod2.roofs.model.RoofGroup`)
    groups: list
    #: per footprint, its roof when built alone (a
    #: :class:`~reconstruction.lod2.roofs.model.Roof`), else None (in a group, or not built)
    single: list

    def each(self):
        """Every footprint's :class:`~reconstruction.lod2.roofs.model.Roof`, None
        where it could not be built."""
        out = list(self.single)
        for group in self.groups:
            for j, i in enumerate(group.index.tolist()):
                out[i] = group.roof(j)
        return out


def make_roofs(footprints, roof_types, attic, uniforms, street=None, config=None, shared=None):
    """Roofs of footprints (local coordinates, counter-clockwise rings).

    ``roof_types``: a type per footprint; ``attic``: roof heights above the
    eaves; ``uniforms``: (B, 3) uniform numbers in [0, 1) per footprint (hip
    end pitch, mansard inset, crow-step height), so that the result does not
    depend on the order of work; ``street``: optional street edge index per
    footprint; ``config``: the :class:`~reconstruction.lod2.roofs.model.RoofConfig`;
    ``shared``: optional per footprint a boolean array, True for its edges
    shared with a neighbour (see :func:`plan_roofs`). Returns the
    :class:`RoofSet`; a roof that could not be built is in no
    group and None (the caller falls back to a simpler type).
    """
    config = config or RoofConfig()
    attic = np.asarray(attic, dtype=float)
    plan = plan_roofs(footprints, roof_types, attic, uniforms, config, street, shared)
    groups = _envelope_roofs(plan, footprints, attic, config.thickness)
    groups.extend(_flat_roofs(plan, footprints))
    groups.extend(_pyramid_roofs(plan, footprints, attic))
    groups.extend(_shed_roofs(plan, footprints, attic))
    single = [None] * len(footprints)
    for i, roof in _skeleton_roofs(plan, attic):
        single[i] = roof
    for i, roof in _staged_roofs(plan, attic):
        single[i] = roof
    return RoofSet(plan.kinds, groups, single)


def _envelope_roofs(plan, footprints, attic, thickness):
    """The envelope roofs of the plan and the stepped roofs on their bodies,
    as groups: per batch (vertex count, with or without a flat top), the
    stepped roofs, then the others."""
    groups = []
    for jobs, env in _batch_envelope(plan.envelope):
        if jobs[0].top is None:           # hip, gable, stepped bodies: ridge at the roof height
            env = env.scaled_to(np.array([attic[j.index] for j in jobs], dtype=float))
        bodies = np.array([k for k, j in enumerate(jobs) if j.body], dtype=int)
        if len(bodies):
            owner = np.array([jobs[k].index for k in bodies], dtype=int)
            facades = [plan.facades[i] for i in owner]
            for group in facade_arrays(np.stack([footprints[i] for i in owner]),
                                       [f.end for f in facades], env.take(bodies),
                                       [f.profile for f in facades], [f.step for f in facades],
                                       thickness):
                groups.append(dataclasses.replace(group, index=owner[group.index]))
        plain = np.array([k for k, j in enumerate(jobs) if not j.body], dtype=int)
        plain = plain[env.ok[plain]]
        if len(plain):
            groups.append(env.group(np.array([jobs[k].index for k in plain], dtype=int), plain))
    return groups


def _batch_envelope(jobs):
    """:func:`~reconstruction.lod2.roofs.envelope.envelope_arrays` of the jobs,
    batched by vertex count and flat top (at most
    :func:`~reconstruction.lod2.roofs.envelope.batch_rows` at once): a list of
    (jobs, envelope)."""
    batches = {}
    for job in jobs:
        E = 0 if job.raised is None else len(job.raised.edge)
        batches.setdefault((len(job.xy), job.top is not None, E), []).append(job)
    out = []
    for (n, has_top, E), jobs_n in batches.items():
        rows = batch_rows(n, has_top, E)
        for k in range(0, len(jobs_n), rows):
            items = jobs_n[k:k + rows]
            xy = np.stack([it.xy for it in items])
            slopes = np.stack([it.slopes for it in items])
            top = np.array([it.top for it in items], dtype=float) if has_top else None
            raised = None
            if E:
                raised = Raised(*(np.stack([getattr(it.raised, f) for it in items])
                                  for f in ("edge", "slope", "height")))
            out.append((items, envelope_arrays(xy, slopes, top, raised)))
    return out


def _flat_roofs(plan, footprints):
    """The flat roofs of the plan, one group per vertex count."""
    return [flat_group(np.array(idx, dtype=int), np.stack([footprints[i] for i in idx]))
            for idx in plan.flat.values()]


def _by_vertex_count(footprints, pairs):
    """(footprint, value) pairs grouped by the footprints' vertex counts:
    a list of (index array, footprints (G, n, 2), values)."""
    by_n = {}
    for i, value in pairs:
        by_n.setdefault(len(footprints[i]), []).append((i, value))
    return [(np.array([i for i, _ in items], dtype=int),
             np.stack([footprints[i] for i, _ in items]), [v for _, v in items])
            for items in by_n.values()]


def _pyramid_roofs(plan, footprints, attic):
    """The pyramid roofs of the plan, one group per vertex count."""
    return [pyramid_group(idx, xy, np.stack(apex), attic[idx])
            for idx, xy, apex in _by_vertex_count(footprints, plan.pyramids)]


def _shed_roofs(plan, footprints, attic):
    """The shed roofs of the plan, one group per vertex count."""
    return [shed_group(idx, xy, np.array([e for e, _ in along]), attic[idx],
                       np.array([low for _, low in along]))
            for idx, xy, along in _by_vertex_count(footprints, plan.sheds)]


def _skeleton_roofs(plan, attic):
    """(footprint, roof or None) of the skeleton roofs of the plan."""
    jobs = plan.skeleton
    if not jobs:
        return []
    res = cgal_roofs([j.xy for j in jobs], [j.pitches for j in jobs], [j.top for j in jobs])
    return [(j.index, roof if j.top is not None else scale_roof(roof, float(attic[j.index])))
            for j, roof in zip(jobs, res)]


def _staged_roofs(plan, attic):
    """(footprint, roof or None) of the two-slope roofs of concave footprints."""
    jobs = plan.staged
    if not jobs:
        return []
    res = staged_roofs([j.xy for j in jobs], [j.lower for j in jobs], [j.upper for j in jobs],
                       [j.knee for j in jobs])
    return [(j.index, scale_roof(roof, float(attic[j.index]))) for j, roof in zip(jobs, res)]


def scale_roof(roof, height):
    """A roof with its heights scaled so that its highest point is at
    ``height`` (None stays None)."""
    if roof is None or roof.zmax <= 1e-9:
        return None
    v = roof.vertices.copy()
    v[:, 2] *= height / roof.zmax
    return dataclasses.replace(roof, vertices=v, zmax=height)

