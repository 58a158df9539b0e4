"""When a building stood: its lifespan from the maps that show it and today's register.

A map of year *y* that shows a building says it stood in *y*; one that does
not show it says it did not (as far as the map goes). So a building first
shown on the map of year *b*, and absent from the one before (year *a*),
was built in ``[a + 1, b]``; last shown in *c* and absent from the next map
(year *d*), it was demolished in ``[c + 1, d]``; still shown on the last
map and not in today's register, it was demolished after that map, when is
unknown. A building in today's register (the BAG) still stands: no
demolition, and its register year (``bouwjaar``) is its construction year
when the maps agree. Where they do not (the register says it was built
before a map that does not show it, or after one that does; a map
between two that show it leaves it out; or it stands in the register but
the maps after the last one that shows it, where they cover its place, do
not) the :class:`Lifespan` says so in ``conflict``; the intervals are then the maps' evidence (a
building in the register that the later maps leave out keeps ``standing``
and gets the demolition interval those maps give).

The attribute names follow CityGML 3.0's ``dateOfConstruction`` and
``dateOfDemolition`` (:meth:`Lifespan.attributes`).
"""

from dataclasses import dataclass
from typing import Optional


@dataclass(frozen=True)
class Lifespan:
    """A building's epochs and dates (years).

    ``epochs``: the map years it is shown in; ``construction`` and
    ``demolition``: ``(earliest, latest)`` years, either bound None where
    unknown (built before the first map; demolished some time after the
    last); ``demolition`` None for a building still standing that the maps
    do not contradict; ``built``: the
    register's construction year (None: not in the register or none given);
    ``standing``: in today's register; ``conflict``: what contradicts what
    (None: nothing).
    """

    epochs: tuple
    construction: tuple
    demolition: Optional[tuple]
    built: Optional[int] = None
    standing: bool = False
    conflict: Optional[str] = None

    def attributes(self):
        """The CityJSON attributes of the lifespan (see the module doc); a bound that
        is unknown is left out."""
        out = {"epochs": list(self.epochs)}
        if self.built is not None and self.conflict is None:
            out["dateOfConstruction"] = self.built
        earliest, latest = self.construction
        if earliest is not None:
            out["dateOfConstructionEarliest"] = earliest
        if latest is not None:
            out["dateOfConstructionLatest"] = latest
        if self.demolition is not None:
            earliest, latest = self.demolition
            out["dateOfDemolitionEarliest"] = earliest
            if latest is not None:
                out["dateOfDemolitionLatest"] = latest
        out["standing"] = self.standing
        if self.conflict is not None:
            out["conflict"] = self.conflict
        return out


def lifespan(years, present, built=None, standing=False, covered=None):
    """The :class:`Lifespan` of a building shown on the maps of ``years`` (ascending)
    where ``present`` (one bool per map); ``built``: its register construction year,
    ``standing``: in today's register; ``covered``: per map, whether it covers the
    building's place (None: every map does), for the maps after its last one: a map
    of another part of the town says nothing of it."""
    shown = [y for y, p in zip(years, present) if p]
    if not shown:
        raise ValueError("a building shown on no map")
    first = list(present).index(True)
    last = len(present) - 1 - list(reversed(present)).index(True)
    conflicts = []
    gaps = [y for y, p in zip(years[first:last + 1], present[first:last + 1]) if not p]
    if gaps:
        conflicts.append("not on the {} map{} between maps that show it".format(
            ", ".join(map(str, gaps)), "s" if len(gaps) > 1 else ""))
    construction = (years[first - 1] + 1 if first > 0 else None, years[first])
    if built is not None:
        if first > 0 and built <= years[first - 1]:
            conflicts.append("built {} (register) but not on the {} map".format(
                built, years[first - 1]))
        elif built > years[first]:
            conflicts.append("built {} (register) but on the {} map".format(built, years[first]))
        else:
            construction = (built, built)
    covered = [True] * len(years) if covered is None else list(covered)
    after = [y for y, c in zip(years[last + 1:], covered[last + 1:]) if c]
    if standing and after:
        # the register says it stands, the later maps that do not show it say it was gone
        conflicts.append("in today's register but not on the {} map{} after {}".format(
            ", ".join(map(str, after)), "s" if len(after) > 1 else "", years[last]))
    if standing and not after:
        demolition = None
    elif standing:
        demolition = (years[last] + 1, after[0])
    elif last == len(years) - 1:
        demolition = (years[last] + 1, None)
    else:
        demolition = (years[last] + 1, years[last + 1])
    return Lifespan(tuple(shown), construction, demolition, built, standing,
                    "; ".join(conflicts) or None)
