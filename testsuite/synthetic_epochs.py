#!/usr/bin/env python3
"""A synthetic town over time: several map epochs of one region with a known history.

The dynamic city model follows each building plot across map epochs (one
identity per plot, a lifespan), so its tests and the demo need one town
drawn at several years with the truth of what happened in between. This
module makes it from the seeded map of synthetic_map.py:

- epoch 0 is the layout :func:`synthetic_map._layout` makes, drawn exactly
  as :func:`synthetic_map.generate` draws it (``maps[0]`` *is*
  ``generate(seed, size)``);
- between two epochs most plots stay **unchanged**; a few are **split**
  (cut across by a new passage), **merged** (two plots close together
  become one), **extended** (grown a few metres into the garden or the
  street), **new** (on garden, park or empty land) or **demolished** (the
  ground becomes garden or street); each change has a true year strictly
  between the two maps' years (:class:`PlotEvent`);
- every later map is drawn with a small global offset (0.5-1.5 m, as two
  surveys of the same block never register exactly): the plots recorded for
  an epoch are the drawn ones, offset included; an unchanged plot is the same
  polygon moved by the difference of the two offsets;
- today's footprints (``town.current``, in the frame of epoch 0, i.e. true
  ground) stand over the last map's plots with construction years that agree
  with the history: before the first map where the ground was a plot then,
  between two maps where it became one in between, after the last map
  elsewhere. A few footprints deliberately disagree (``town.conflicts``): an
  old year in a plot that is new on the second map, as a register can have.

Pure part: :func:`generate_town` (numpy, scipy, shapely; no GRASS),
:func:`write_truth` / :func:`load_truth` (JSON). In GRASS:
:func:`write_to_grass`, or from the command line inside a session::

    grass --tmp-location EPSG:28992 --exec python3 testsuite/synthetic_epochs.py \\
        --seed 1 --size 600 --prefix town --truth town.json
"""

import json
import math
import os
import sys
from dataclasses import dataclass, field

import numpy as np
import shapely
from shapely import affinity
from shapely.geometry import Polygon, box
from shapely.ops import unary_union

import synthetic_map as sm

EVENT_KINDS = ("unchanged", "split", "merged", "extended", "new", "demolished")
#: the years of the default epochs (the Delft maps of the thesis: 1880, 1915, 1961)
YEARS = (1880, 1915, 1961)
#: last year a current footprint may be built in
NOW = 2023
#: share of an epoch's plots each change takes (at least one of each kind)
_CHANGE_SHARE = {"demolished": 0.06, "split": 0.06, "merged": 0.05, "extended": 0.08,
                 "new": 0.07}
_MERGE_GAP = 10.0     # plots at most this far apart may merge (m)
_PASSAGE = (2.5, 4.0)  # width of the passage cutting a split plot (m)
_CLEARANCE = 3.0      # grown and new plots stay this far from other plots (m)


@dataclass
class PlotEvent:
    """What happened to plots between two consecutive epochs.

    ``before`` and ``after`` are tuples of (epoch index, plot index in
    ``maps[epoch].plots``); ``year`` is the true year of the change, strictly
    between the two epochs' years (None for ``unchanged``). ``new`` has no
    ``before``, ``demolished`` no ``after``.
    """

    kind: str
    year: object
    before: tuple
    after: tuple


@dataclass
class SyntheticTown:
    """One region drawn at several epochs, with the truth of its history.

    ``maps``: one :class:`synthetic_map.SyntheticMap` per year; ``offsets``:
    the global (dx, dy) each map is drawn with (epoch 0: (0, 0)); ``history``:
    :class:`PlotEvent` covering every plot of every transition; ``current``:
    today's footprints (:class:`synthetic_map.CurrentFootprints`, true ground,
    ``map_year`` the last year); ``current_plot``: the (epoch, plot index) of
    the last map each footprint stands in (None: none); ``current_since``: the
    first epoch from which the ground under the footprint (its representative
    point) is a plot on every later map (None: not a plot on the last map);
    ``conflicts``: indices of the footprints whose year deliberately
    contradicts the history.
    """

    seed: int
    years: tuple
    maps: list
    offsets: list
    history: list
    current: object
    current_plot: list
    current_since: list
    conflicts: list
    born: list = field(default_factory=list, repr=False)  # per epoch, per plot: epoch it is new in

    def events(self, kind=None, transition=None):
        """The events of one kind and/or one transition (``transition`` e: from e to e + 1)."""
        return [ev for ev in self.history
                if (kind is None or ev.kind == kind)
                and (transition is None or _transition_of(ev) == transition)]

    def true_plot(self, epoch, index):
        """A plot of ``maps[epoch]`` moved back by the epoch's offset: on true ground."""
        dx, dy = self.offsets[epoch]
        return _moved(self.maps[epoch].plots[index], -dx, -dy)


def _moved(geom, dx, dy):
    """``geom`` moved by (dx, dy) onto the 1 cm grid, its vertices in the same order (an
    unchanged plot keeps its ring as drawn before, only moved)."""
    return shapely.transform(geom, lambda xy: np.round(xy + (dx, dy), 2))


def _transition_of(event):
    """The epoch a transition starts from (before's epoch, or after's less one)."""
    return event.before[0][0] if event.before else event.after[0][0] - 1


# ---------------------------------------------------------------------------
# Changes of the plots between two epochs (local metres, true ground)
# ---------------------------------------------------------------------------

def _polygons(geom):
    """The polygons of a geometry (any type)."""
    return [g for g in getattr(geom, "geoms", [geom]) if g.geom_type == "Polygon"]


def _clean(geom):
    """One valid polygon on the 1 cm grid, or None."""
    parts = _polygons(shapely.set_precision(geom, 0.01)) if not geom.is_empty else []
    return parts[0] if len(parts) == 1 and parts[0].is_valid else None


def _split(rng, plot):
    """Two plots cut from one by a passage across its long axis, or None."""
    rect = plot.minimum_rotated_rectangle
    xy = np.asarray(rect.exterior.coords)[:4]
    a, b = xy[1] - xy[0], xy[2] - xy[1]
    axis, across = (a, b) if np.hypot(*a) >= np.hypot(*b) else (b, a)
    length = np.hypot(*axis)
    if length < 20:
        return None
    u = axis / length
    centre = np.asarray(rect.centroid.coords[0]) + u * length * rng.uniform(-0.15, 0.15)
    half, reach = rng.uniform(*_PASSAGE) / 2, np.hypot(*across)
    v = across / np.hypot(*across)
    passage = Polygon([centre + s * u * half + t * v * reach
                       for s, t in ((-1, -1), (1, -1), (1, 1), (-1, 1))])
    parts = [_clean(p) for p in _polygons(plot.difference(passage))]
    if len(parts) != 2 or any(p is None or p.area < 60 for p in parts):
        return None
    return parts


def _merge(a, b):
    """The plot of two close plots joined across the gap between them, or None."""
    r = a.distance(b) / 2 + 0.5
    joined = unary_union([a.buffer(r, join_style="mitre"), b.buffer(r, join_style="mitre")])
    return _clean(joined.buffer(-r, join_style="mitre").union(a).union(b))


def _extend(rng, plot, free):
    """The plot grown by 3-6 m outward from one of its long edges, inside ``free``
    ground, or None."""
    ring = shapely.geometry.polygon.orient(plot, 1.0).exterior.simplify(0.05)
    xy = np.asarray(ring.coords)
    edges = sorted(range(len(xy) - 1), key=lambda k: -np.hypot(*(xy[k + 1] - xy[k])))
    for k in edges[:4]:
        p, q = xy[k], xy[k + 1]
        length = np.hypot(*(q - p))
        if length < 8:
            break
        out = np.array([(q - p)[1], -(q - p)[0]]) / length  # right of a CCW ring: outward
        depth = rng.uniform(3, 6)
        wing = Polygon([p, q, q + out * depth, p + out * depth])
        if not free.contains(wing):
            continue
        grown = _clean(plot.union(wing))
        if grown is not None:
            return grown
    return None


def _new_plot(rng, gardens, free, extent):
    """A rectangular plot on garden, park or (failing that) empty land, or None."""
    green = unary_union(gardens) if gardens else Polygon()
    shapely.prepare(free)
    for attempt in range(600):
        w, h = rng.uniform(10, 18), rng.uniform(9, 14)
        on_green = attempt < 400 and not green.is_empty
        minx, miny, maxx, maxy = green.bounds if on_green else (0, 0, extent, extent)
        x, y = rng.uniform(minx, maxx), rng.uniform(miny, maxy)
        rect = shapely.set_precision(box(x - w / 2, y - h / 2, x + w / 2, y + h / 2), 0.01)
        if not free.contains(rect):
            continue
        if on_green and rect.intersection(green).area < 0.6 * rect.area:
            continue
        return rect
    return None


def _free_ground(plots, quays, extent):
    """Where a plot may grow or appear: inside the map, off the quays, clear of ``plots``."""
    frame = box(5, 5, extent - 5, extent - 5)
    return frame.difference(quays).difference(unary_union(plots).buffer(_CLEARANCE))


def _count(kind, n):
    return max(1, int(round(_CHANGE_SHARE[kind] * n)))


class _Changes:
    """The changes of one transition as they are chosen: what becomes of each
    earlier plot (``fate``: index -> (kind, year, [later (polygon, kind, angle)],
    merged partner or None)), the new plots and the garden ground."""

    def __init__(self, rng, plots, gardens, keep, quays, extent, years):
        self.rng, self.plots, self.keep = rng, plots, keep
        self.polys = [p for p, _, _ in plots]
        self.quays, self.extent, self.years = quays, extent, years
        self.green, self.gardens = list(gardens), list(gardens)
        self.order = [int(i) for i in rng.permutation(len(plots)) if int(i) not in keep]
        self.fate, self.used, self.added = {}, set(), []

    def year(self):
        return int(self.rng.integers(self.years[0] + 1, self.years[1]))

    def wanted(self, kind):
        return _count(kind, len(self.plots))

    def free(self):
        """The earlier plots no change has taken yet, in random order."""
        return [i for i in self.order if i not in self.used]

    def settle(self, i, kind, results, partner=None):
        self.fate[i] = (kind, self.year(), results, partner)
        self.used.update([i] if partner is None else [i, partner])

    def cleared(self):
        """Ground of the plots demolished in this transition: no plot grows or appears
        on it in the same years, so it is garden or street on the next map."""
        return [self.polys[i] for i, f in self.fate.items() if f[0] == "demolished"]

    def later(self):
        """The later epoch's polygons so far (and the new ones)."""
        return _later_polygons(self.plots, self.fate, self.used) + [a for a, _, _ in self.added]

    def close_pairs(self):
        """Pairs of free plots at most _MERGE_GAP apart, the closest first (ties in
        random order): plots that (nearly) touch merge before plots across a yard."""
        polys, free = self.polys, set(self.free())
        tree = shapely.STRtree(polys)
        pairs = {}
        for i in self.free():
            for j in (int(j) for j in tree.query(polys[i].buffer(_MERGE_GAP))):
                gap = polys[i].distance(polys[j])
                if i < j and j in free and gap <= _MERGE_GAP:
                    pairs[(i, j)] = gap
        tie = self.rng.permutation(len(pairs))
        return [pair for _, _, pair in sorted(zip(pairs.values(), tie, pairs))]

    def merge(self):
        """Merged: two plots at most _MERGE_GAP apart, joined across the gap."""
        polys, tree, wanted = self.polys, shapely.STRtree(self.polys), self.wanted("merged")
        for i, j in self.close_pairs():
            if not wanted:
                break
            if i in self.used or j in self.used:
                continue
            joined = _merge(polys[i], polys[j])
            if joined is None or joined.intersects(self.quays):
                continue
            rest = [polys[k] for k in tree.query(joined.buffer(_CLEARANCE)) if k not in (i, j)]
            if any(joined.distance(r) < _CLEARANCE for r in rest):
                continue
            big = i if polys[i].area >= polys[j].area else j
            self.settle(i, "merged", [(joined,) + tuple(self.plots[big][1:])], j)
            wanted -= 1

    def demolish(self):
        """Demolished: the ground becomes garden (half of them) or street."""
        for i in self.free()[:self.wanted("demolished")]:
            self.settle(i, "demolished", [])
            if self.rng.random() < 0.5:
                self.gardens.append(self.polys[i])

    def split(self):
        """Split: cut across by a new passage."""
        wanted = self.wanted("split")
        for i in self.free():
            parts = _split(self.rng, self.polys[i]) if wanted else None
            if parts:
                self.settle(i, "split", [(p,) + tuple(self.plots[i][1:]) for p in parts])
                wanted -= 1

    def extend(self):
        """Extended: grown a few metres into the garden or the street."""
        wanted = self.wanted("extended")
        for i in self.free():
            if not wanted:
                break
            others = [p for p in self.later() if p is not self.polys[i]] + self.cleared()
            free = _free_ground(others, self.quays, self.extent).union(self.polys[i])
            grown = _extend(self.rng, self.polys[i], free)
            if grown:
                self.settle(i, "extended", [(grown,) + tuple(self.plots[i][1:])])
                wanted -= 1

    def build_new(self):
        """New: a plot on garden, park or empty land (not on ground cleared now)."""
        for _ in range(self.wanted("new")):
            free = _free_ground(self.later() + self.cleared(), self.quays, self.extent)
            rect = _new_plot(self.rng, self.green, free, self.extent)
            if rect is not None:
                self.added.append((rect, "single", 0.0))


def _transition(rng, plots, gardens, keep, quays, extent, years):
    """Change the plots between two epochs.

    ``plots``: [(polygon, kind, angle)] of the earlier epoch (true ground,
    local metres); ``keep``: indices no change may touch; ``years``: the two
    epochs' years. Merges go first (close pairs are the rarest candidates).
    Returns the later epoch's plots, its gardens, the events as (kind, year,
    [before indices], [after indices]) and which later plots are new.
    """
    changes = _Changes(rng, plots, gardens, keep, quays, extent, years)
    for step in (changes.merge, changes.demolish, changes.split, changes.extend,
                 changes.build_new):
        step()
    later, events, new = _assemble(plots, changes.fate, changes.added, rng, years)
    return later, changes.gardens, events, new


def _later_polygons(plots, fate, used):
    """The later epoch's polygons so far: changed results and the plots not used."""
    out = [p for i, (p, _, _) in enumerate(plots) if i not in used]
    for _, _, results, _ in fate.values():
        out.extend(p for p, _, _ in results)
    return out


def _assemble(plots, fate, added, rng, years):
    """The later epoch's plot list (in the earlier order, new ones last) and the events."""
    later, events, partners = [], [], {f[3]: i for i, f in fate.items() if f[3] is not None}
    for i, plot in enumerate(plots):
        if i in partners:
            continue  # the second plot of a merger: its event is the first's
        kind, year, results, partner = fate.get(i, ("unchanged", None, [plot], None))
        before = [i] if partner is None else [i, partner]
        after = list(range(len(later), len(later) + len(results)))
        later.extend(results)
        events.append((kind, year, before, after))
    new = []
    for plot in added:
        new.append(len(later))
        events.append(("new", int(rng.integers(years[0] + 1, years[1])), [], [len(later)]))
        later.append(plot)
    return later, events, new


# ---------------------------------------------------------------------------
# Drawing an epoch
# ---------------------------------------------------------------------------

def _random_offset(rng):
    """A global drawing offset of 0.5-1.5 m in any direction, on the 1 cm grid."""
    angle, step = rng.uniform(0, 2 * math.pi), rng.uniform(0.5, 1.5)
    return (round(step * math.cos(angle), 2), round(step * math.sin(angle), 2))


def _drawn_layout(layout, plots, gardens, offset):
    """The layout of an epoch as drawn: its plots and gardens, everything moved by ``offset``."""
    dx, dy = offset

    def move(g):
        return affinity.translate(g, dx, dy)

    anchors = [(d, pos + (dy if d == "h" else dx), width)
               for d, pos, width in layout["street_anchors"]]
    return dict(layout,
                plots=[(_moved(p, dx, dy), k, a) for p, k, a in plots],
                gardens=[move(g) for g in gardens], canal=move(layout["canal"]),
                quays=move(layout["quays"]), canal_line=move(layout["canal_line"]),
                street_anchors=anchors)


# ---------------------------------------------------------------------------
# Today's footprints over the last epoch
# ---------------------------------------------------------------------------

def _since(point, true_plots):
    """First epoch from which ``point`` is in a plot on every later map (None: not on the last)."""
    since = None
    for e in range(len(true_plots) - 1, -1, -1):
        if not any(p.covers(point) for p in true_plots[e]):
            break
        since = e
    return since


def _current_year(rng, since, kind, years):
    """A construction year that agrees with the history of the ground under a footprint:
    mostly of the period the ground became a plot in (before the first map for
    ground built up on it), some after the last map (rebuilt), a few unknown.
    Modern blocks and buildings off the last map's plots are after it."""
    late = (years[-1] + 1, max(years[-1] + 2, NOW + 1))
    if since is None or kind == "rebuilt":
        return int(rng.integers(*late))
    u = rng.random()
    if u < (0.78 if since == 0 else 0.85):
        return int(rng.integers(1550, years[0]) if since == 0 else
                   rng.integers(years[since - 1] + 1, years[since]))
    if u < 0.95:
        return int(rng.integers(*late))
    return None if u < 0.975 else 9999


def _current(rng, town_maps, offsets, true_plots, born, years):
    """Today's footprints, their plots, since-epochs and the deliberate conflicts."""
    last = len(town_maps) - 1
    made = sm.current_footprints(rng, town_maps[last], map_year=years[0])
    dx, dy = offsets[last]
    polygons = [_moved(p, -dx, -dy) for p in made.polygons]
    plot = [(last, k - 1) if k else None for k in made.plot]
    kinds = list(made.kind)
    candidates = [i for i, at in enumerate(plot) if at and len(years) > 1
                  and born[last][at[1]] == 1]
    if not candidates and len(years) > 1:
        # no footprint on a plot new in epoch 1: one house on such a plot
        for k, b in enumerate(born[last]):
            house = _clean(true_plots[last][k].buffer(-1.5, join_style="mitre"))
            if b == 1 and house is not None:
                polygons.append(house)
                plot.append((last, k))
                kinds.append("standing")
                candidates = [len(polygons) - 1]
                break
    since = [_since(p.representative_point(), true_plots) for p in polygons]
    years_now = [_current_year(rng, s, k, years) for s, k in zip(since, kinds)]
    conflicts = sorted(int(i) for i in rng.permutation(candidates)[:2])
    for i in conflicts:
        years_now[i] = int(rng.integers(1600, years[0]))
    ids = ["0503100000{:06d}".format(200000 + 17 * k) for k in range(len(polygons))]
    current = sm.CurrentFootprints(polygons, years_now, [at[1] + 1 if at else 0 for at in plot],
                                   kinds, ids, years[-1])
    return current, plot, since, conflicts


# ---------------------------------------------------------------------------
# The town
# ---------------------------------------------------------------------------

def generate_town(seed=1, size=600, years=YEARS, res=1.0, origin=(84000.0, 446000.0)):
    """The synthetic town drawn at ``years`` (increasing), with its history.

    The same arguments give identical arrays and vectors. ``maps[0]`` is
    ``synthetic_map.generate(seed, size, res, origin)``.
    """
    years = tuple(int(y) for y in years)
    if len(years) < 1 or any(b - a < 2 for a, b in zip(years, years[1:])):
        raise ValueError("years must increase, at least two years apart: {}".format(years))
    if size < 200:
        raise ValueError("size must be at least 200 pixels")
    extent = size * res
    first = np.random.default_rng(seed)
    layout = sm._layout(first, extent)
    changes = np.random.default_rng([seed, 21])
    plots, gardens = list(layout["plots"]), list(layout["gardens"])
    offsets, history, born = [(0.0, 0.0)], [], [[0] * len(plots)]
    maps = [sm.render(layout, first, seed=seed, size=size, res=res, origin=origin)]
    true_plots = [[p for p, _, _ in plots]]
    new = []
    for e in range(1, len(years)):
        plots, gardens, events, new = _transition(changes, plots, gardens, set(new),
                                                  layout["quays"], extent, years[e - 1:e + 1])
        born.append(_born(born[-1], events, e, len(plots)))
        for kind, year, before, after in events:
            history.append(PlotEvent(kind, year, tuple((e - 1, i) for i in before),
                                     tuple((e, i) for i in after)))
        offsets.append(_random_offset(changes))
        drawn = _drawn_layout(layout, plots, gardens, offsets[-1])
        maps.append(sm.render(drawn, np.random.default_rng([seed, 22, e]), seed=seed,
                              size=size, res=res, origin=origin))
        true_plots.append([affinity.translate(p, *origin) for p, _, _ in plots])
    true_plots[0] = [affinity.translate(p, *origin) for p in true_plots[0]]
    current, at, since, conflicts = _current(np.random.default_rng([seed, 23]), maps, offsets,
                                             true_plots, born, years)
    for smap in maps:
        smap._current = current  # today's footprints are the same under every map
    return SyntheticTown(seed=seed, years=years, maps=maps, offsets=offsets, history=history,
                         current=current, current_plot=at, current_since=since,
                         conflicts=conflicts, born=born)


def _born(earlier, events, epoch, n):
    """The epoch each later plot is new in: ``epoch`` for new ones, else the
    earliest of the plots it comes from."""
    out = [epoch] * n
    for kind, _, before, after in events:
        for j in after:
            out[j] = min(earlier[i] for i in before) if before else epoch
    return out


# ---------------------------------------------------------------------------
# Truth as JSON
# ---------------------------------------------------------------------------

def truth_dict(town):
    """The truth of a town as plain data (plots and footprints as WKT)."""
    m = town.maps[0]
    return {
        "seed": town.seed, "years": list(town.years),
        "region": m.region(), "offsets": [list(o) for o in town.offsets],
        "epochs": [{"year": y, "plots": [p.wkt for p in smap.plots],
                    "kinds": list(smap.plot_kinds)} for y, smap in zip(town.years, town.maps)],
        "history": [{"kind": ev.kind, "year": ev.year, "before": [list(b) for b in ev.before],
                     "after": [list(a) for a in ev.after]} for ev in town.history],
        "current": [{"wkt": p.wkt, "bouwjaar": y, "identificatie": i, "kind": k,
                     "plot": list(at) if at else None, "since": s}
                    for p, y, i, k, at, s in zip(town.current.polygons, town.current.years,
                                                  town.current.ids, town.current.kind,
                                                  town.current_plot, town.current_since)],
        "conflicts": list(town.conflicts),
    }


def write_truth(town, path):
    """Write the truth of ``town`` (:func:`truth_dict`) as JSON to ``path``."""
    with open(path, "w") as f:
        json.dump(truth_dict(town), f, indent=1)
    return path


def load_truth(path):
    """Read a truth file: the dict of :func:`truth_dict` with shapely polygons in place of
    WKT, :class:`PlotEvent` in ``history`` and tuples for plot references."""
    with open(path) as f:
        data = json.load(f)
    for epoch in data["epochs"]:
        epoch["plots"] = [shapely.from_wkt(w) for w in epoch["plots"]]
    data["history"] = [PlotEvent(ev["kind"], ev["year"], tuple(map(tuple, ev["before"])),
                                 tuple(map(tuple, ev["after"]))) for ev in data["history"]]
    for c in data["current"]:
        c["polygon"] = shapely.from_wkt(c.pop("wkt"))
        c["plot"] = tuple(c["plot"]) if c["plot"] else None
    data["offsets"] = [tuple(o) for o in data["offsets"]]
    return data


# ---------------------------------------------------------------------------
# GRASS
# ---------------------------------------------------------------------------

def map_names(town, prefix="town"):
    """Names :func:`write_to_grass` writes: {year: synthetic_map.map_names of
    ``<prefix>_<year>`` without ``current``} and ``current``."""
    epochs = {}
    for year in town.years:
        names = sm.map_names("{}_{}".format(prefix, year))
        del names["current"]
        epochs[year] = names
    return {"epochs": epochs, "current": prefix + "_current"}


def write_to_grass(town, prefix="town"):
    """Write every epoch's map as synthetic_map.write_to_grass does (prefix
    ``<prefix>_<year>``: ``town_1880.red``, ``town_1880_plots``, ...) and
    today's footprints as ``<prefix>_current`` (``bouwjaar``, ``identificatie``
    and the measured heights); returns :func:`map_names`."""
    names = map_names(town, prefix)
    for year, smap in zip(town.years, town.maps):
        sm.write_map_to_grass(smap, "{}_{}".format(prefix, year))
    sm.write_current_to_grass(names["current"], town.current,
                              sm.footprint_heights(town.current.polygons, town.seed))
    return names


def main(argv=None):
    parser = sm.map_arguments(
        "Write a synthetic town drawn at several years into the current GRASS "
        "mapset (run inside a GRASS session), its truth as JSON, or PNG pictures.")
    parser.add_argument("--years", default=",".join(map(str, YEARS)),
                        help="the map epochs, comma separated")
    parser.add_argument("--prefix", default="town", help="prefix of the map names")
    parser.add_argument("--truth", help="write the truth (history, offsets, plots) as JSON here")
    parser.add_argument("--png", help="write only PNG pictures (plots outlined) to this folder")
    parser.add_argument("--overwrite", action="store_true", help="replace existing maps")
    args = parser.parse_args(argv)
    years = tuple(int(y) for y in args.years.split(","))
    if not args.png and not os.environ.get("GISRC"):
        parser.error("not inside a GRASS session: run it with grass <mapset> --exec "
                     "(or give --png)")
    town = generate_town(seed=args.seed, size=args.size, years=years, res=args.res)
    if args.truth:
        write_truth(town, args.truth)
    if args.png:
        os.makedirs(args.png, exist_ok=True)
        for year, smap in zip(town.years, town.maps):
            path = os.path.join(args.png, "{}_{}.png".format(args.prefix, year))
            sm.write_png(path, sm.outline_plots(smap), colours=48)
        print("pictures written to '{}'".format(args.png))
        return 0
    if args.overwrite:
        os.environ["GRASS_OVERWRITE"] = "1"
    os.environ.setdefault("GRASS_VERBOSE", "1")
    names = write_to_grass(town, args.prefix)
    counts = {kind: len(town.events(kind)) for kind in EVENT_KINDS}
    print("synthetic town (seed {}, {} x {} px at {} m) written: {}; {} ({} current "
          "footprints); events: {}".format(
              args.seed, args.size, args.size, args.res,
              ", ".join("{} ({} plots)".format(names["epochs"][y]["plots"], len(m.plots))
                        for y, m in zip(town.years, town.maps)),
              names["current"], len(town.current.polygons),
              ", ".join("{} {}".format(k, v) for k, v in counts.items())))
    return 0


if __name__ == "__main__":
    sys.exit(main())
