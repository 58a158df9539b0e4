"""Measures of a dynamic chain's models against the true history of the synthetic town
(on sys.path through the root conftest.py; used by test_dynamic_town.py).

The chain (demo/dynamic_chain.sh) writes one model per epoch and the town's
truth (testsuite/synthetic_epochs.py); these functions say, building by
building, how far the models keep what the maps did not change, date what
was demolished, keep still-standing buildings one identity and give
snapshots equal to the epochs' models. Pure: the CityJSON documents as
dicts, the truth of :func:`synthetic_epochs.load_truth`, shapely and numpy.
"""

import json
from dataclasses import dataclass, field

import numpy as np
import shapely

from reconstruction.cityjson.geometry import resolved


def buildings(document):
    """{top-level id: (geometry with coordinates in place of indices, as JSON text,
    attributes, (x, y) of its vertices' mean)} of a CityJSON document."""
    out = {}
    for oid, obj in resolved(document, digits=3).items():
        if obj.get("parents"):
            continue
        geometry = obj.get("geometry", ())
        xyz = np.array([c for g in geometry for c in coordinates(g["boundaries"])] or
                       [[np.nan] * 3], dtype=float)
        out[oid] = (json.dumps(geometry, sort_keys=True), obj.get("attributes") or {},
                    tuple(np.nanmean(xyz[:, :2], axis=0)))
    return out


def coordinates(nested):
    """The (x, y, z) of resolved boundaries (nested lists), one after the other."""
    if nested and isinstance(nested[0], (int, float)):
        yield nested
        return
    for item in nested:
        yield from coordinates(item)


def _in_plots(centres, plots):
    """Per truth plot index, the ids whose centre lies in it."""
    ids = list(centres)
    points = shapely.points(np.array([centres[i] for i in ids]).reshape(-1, 2))
    inside = {}
    p, b = shapely.STRtree(plots).query(points, predicate="within")
    for k, j in zip(p.tolist(), b.tolist()):
        inside.setdefault(j, []).append(ids[k])
    return inside


@dataclass
class UnchangedPlots:
    """Buildings of truth-unchanged plots: ``kept`` of ``buildings`` identical (same id,
    geometry to the millimetre, attributes other than the map year and plot number)
    in the next epoch, plots whose buildings all are (``plots_kept`` of ``plots``),
    and the ones that are not (``lost``: (year, id, why))."""

    buildings: int = 0
    kept: int = 0
    plots: int = 0
    plots_kept: int = 0
    lost: list = field(default_factory=list)


#: attributes that name the epoch, not the building
EPOCH_ATTRIBUTES = ("map_year", "plot", "footprint")


def unchanged_plots(truth, models):
    """The :class:`UnchangedPlots` of the chain's ``models`` ({year: document})."""
    years = truth["years"]
    shapes = {y: buildings(models[y]) for y in years}
    out = UnchangedPlots()
    for ev in truth["history"]:
        if ev.kind != "unchanged":
            continue
        (e, p), = ev.before
        (f, q), = ev.after
        before, after = shapes[years[e]], shapes[years[f]]
        ids_before = _in_plots({i: s[2] for i, s in before.items()},
                               truth["epochs"][e]["plots"]).get(p, [])
        ids_after = _in_plots({i: s[2] for i, s in after.items()},
                              truth["epochs"][f]["plots"]).get(q, [])
        whole = True
        for oid in ids_before:
            out.buildings += 1
            why = None
            if oid not in after:
                why = "not in {}".format(years[f])
            elif after[oid][0] != before[oid][0]:
                why = "geometry differs"
            elif _same(after[oid][1]) != _same(before[oid][1]):
                why = "attributes differ"
            if why:
                whole = False
                out.lost.append((years[f], oid, why))
            else:
                out.kept += 1
        for oid in sorted(set(ids_after) - set(before)):
            whole = False
            out.lost.append((years[f], oid, "new in an unchanged plot"))
        out.plots += 1
        out.plots_kept += whole
    return out


def _same(attributes):
    return {k: v for k, v in attributes.items() if k not in EPOCH_ATTRIBUTES}


def demolitions(truth, models, merged):
    """(demolished buildings, those whose demolition interval in the merged model holds
    the true year, [(id, true year, interval) of the others]): the buildings of
    every plot the truth demolishes, from the model of the epoch before."""
    years = truth["years"]
    objects = merged["CityObjects"]
    total, right, wrong = 0, 0, []
    for ev in truth["history"]:
        if ev.kind != "demolished":
            continue
        (e, p), = ev.before
        shapes = buildings(models[years[e]])
        for oid in _in_plots({i: s[2] for i, s in shapes.items()},
                             truth["epochs"][e]["plots"]).get(p, []):
            a = objects[oid]["attributes"]
            span = (a.get("dateOfDemolitionEarliest"), a.get("dateOfDemolitionLatest"))
            total += 1
            if span[0] is not None and span[1] is not None and span[0] <= ev.year <= span[1]:
                right += 1
            else:
                wrong.append((oid, ev.year, span))
    return total, right, wrong


def standing_identities(truth, models, merged):
    """(register ids in any epoch's model, those that are one building over a run of
    consecutive epochs up to the last in the merged model, [the others with their
    epochs]): a still-standing building, once on a map, is on every later one."""
    years = truth["years"]
    register = {c["identificatie"] for c in truth["current"]}
    objects = merged["CityObjects"]
    found = {oid for y in years for oid in models[y]["CityObjects"] if oid in register}
    good, bad = 0, []
    for oid in sorted(found):
        shown = (objects.get(oid) or {}).get("attributes", {}).get("epochs", [])
        if shown and shown == years[years.index(shown[0]):]:
            good += 1
        else:
            bad.append((oid, shown))
    return len(found), good, bad


def same_model(a, b):
    """Differences between two CityJSON documents' buildings (ids, geometry to the
    millimetre, attributes; None for an attribute one lacks): [] when equal."""
    x, y = resolved(a, digits=3), resolved(b, digits=3)
    out = ["only in the first: {}".format(sorted(set(x) - set(y))[:5])] if set(x) - set(y) else []
    if set(y) - set(x):
        out.append("only in the second: {}".format(sorted(set(y) - set(x))[:5]))
    for oid in sorted(set(x) & set(y)):
        gx = json.dumps(x[oid].get("geometry"), sort_keys=True)
        gy = json.dumps(y[oid].get("geometry"), sort_keys=True)
        if gx != gy:
            out.append("{}: geometry differs".format(oid))
        ax = {k: v for k, v in (x[oid].get("attributes") or {}).items() if v is not None}
        ay = {k: v for k, v in (y[oid].get("attributes") or {}).items() if v is not None}
        if ax != ay:
            out.append("{}: attributes differ".format(oid))
    return out

