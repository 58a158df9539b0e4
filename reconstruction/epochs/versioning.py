"""The versions of a model over time as the suite's CityJSON Extension writes them
(:mod:`reconstruction.cityjson.versions`; issue 52): what
:func:`~reconstruction.epochs.dynamic.merge_epochs` gathers of each city object
epoch by epoch (:class:`Run`, :func:`add_epoch`), the validity interval of each
version (:func:`shown_years`), a building's transitions between maps
(:func:`transitions`) and the city's versions (:func:`versioning`)."""

import json
from dataclasses import dataclass
from typing import Optional

from ..cityjson import versions

#: what joins an object id to the year of the first epoch of one of its versions
#: (the ``+BuildingVersion`` city objects, :mod:`~reconstruction.cityjson.versions`)
VERSION_JOIN = "~"


@dataclass
class Run:
    """One version of a city object being gathered: consecutive epochs (indices) whose
    models give it the same geometry; the attributes of the first, what the others
    say otherwise ({year: {name: value}})."""

    text: str
    geometry: Optional[list]
    attributes: dict
    epochs: list
    extra: dict

    def city_object(self, member, years, shown):
        """The ``+BuildingVersion`` city object of the run (a version of ``member``);
        ``shown``: {epoch index: (first, last) years it is shown in, last None: open}."""
        out = {"type": versions.VERSION, "versionOf": member,
               "epochs": [years[k] for k in self.epochs],
               "validFrom": shown[self.epochs[0]][0]}
        if shown[self.epochs[-1]][1] is not None:
            out["validTo"] = shown[self.epochs[-1]][1]
        out["attributes"] = self.attributes
        if self.extra:
            out["epochAttributes"] = self.extra
        described = versions.paradata(self.attributes)
        if described:
            out["paradata"] = described
        if self.geometry is not None:
            out["geometry"] = self.geometry
        return out


def add_epoch(runs, k, year, obj, geometry):
    """Add the city object ``obj`` of epoch ``k`` (of ``year``; ``geometry``: its
    geometry on the merged vertices, None where it has none) to its ``runs``
    (:class:`Run`): the last one when it is of the epoch before with the same
    geometry, else a new one."""
    text = json.dumps(geometry, sort_keys=True)
    attributes = obj.get("attributes") or {}
    last = runs[-1] if runs else None
    if last is None or last.text != text or last.epochs[-1] != k - 1:
        runs.append(Run(text, geometry, dict(attributes), [k], {}))
        return
    base = last.attributes
    differ = {n: v for n, v in attributes.items() if base.get(n) != v}
    differ.update({n: None for n in base if n not in attributes})
    if differ:
        last.extra[str(year)] = differ
    last.epochs.append(k)


def free_id(name, taken):
    """``name``, or with :data:`VERSION_JOIN` added until no object has it; taken now."""
    while name in taken:
        name += VERSION_JOIN
    taken.add(name)
    return name


def shown_years(years, present, built):
    """{epoch index of a building: (first, last) year in which the snapshot shows it
    as that epoch's (last None: after the last map)}, by the rule of
    :func:`~reconstruction.epochs.dynamic.standing_versions`: from the epoch's year
    (or from the register's ``built`` year, between the map before that does not
    show it and this one) to the year before the next map."""
    out = {}
    for k in present:
        first = years[k]
        if k > 0 and k - 1 not in present and isinstance(built, int) and \
                years[k - 1] < built < years[k]:
            first = built
        out[k] = (first, years[k + 1] - 1 if k + 1 < len(years) else None)
    return out


def transitions(years, trees, members, at):
    """A building's transitions between consecutive maps (the Extension's
    ``+transitions``): kept (every member the same version), changed, new, demolished,
    with the evidence; ``at``: {(member, epoch index): version id}."""
    out = []
    oid = members[0]
    for k in range(min(trees), min(max(trees) + 2, len(years))):
        if k == 0 or (k - 1 not in trees and k not in trees):
            continue
        a, b = years[k - 1], years[k]
        step = {"from": a, "to": b}
        if k - 1 in trees:
            step["fromVersion"] = at[oid, k - 1]
        if k in trees:
            step["toVersion"] = at[oid, k]
        if k - 1 not in trees:
            step.update(type="new", evidence="not on the map of {}, on the map of {}".format(a, b))
        elif k not in trees:
            step.update(type="demolished", evidence="on the map of {}, not on the map of {}"
                        .format(a, b))
        elif all(at.get((m, k - 1)) == at.get((m, k)) for m in members):
            step.update(type="kept", evidence="the same geometry, to the millimetre, on the "
                        "maps of {} and {}".format(a, b))
        else:
            step.update(type="changed", evidence="another geometry on the map of {} than on "
                        "the map of {}".format(b, a))
        out.append(step)
    return out


def versioning(years, objects, present, count):
    """The root's ``+versioning``: the city's versions (one per map) and the transitions
    between consecutive ones with their counts of buildings kept, changed, new and
    demolished."""
    steps = {}
    for oid in present:
        for t in objects[oid]["attributes"][versions.TRANSITIONS]:
            tally = steps.setdefault(t["to"], dict.fromkeys(("kept", "changed", "new",
                                                             "demolished"), 0))
            tally[t["type"]] += 1
    return {"versions": [{"id": str(y), "year": y, "buildings": count.get(k, 0)}
                         for k, y in enumerate(years)],
            "transitions": [{"from": str(a), "to": str(b), "type": "historicalSuccession",
                             **steps.get(b, dict.fromkeys(("kept", "changed", "new",
                                                           "demolished"), 0))}
                            for a, b in zip(years, years[1:])]}
