"""Lifespans from the maps and today's register (reconstruction.epochs.lifespans)."""

import pytest
from hypothesis import given
from hypothesis import strategies as st

from reconstruction.epochs.lifespans import lifespan

YEARS = (1880, 1915, 1961)


def test_a_building_of_the_middle_map_only():
    span = lifespan(YEARS, [False, True, False])
    assert span.construction == (1881, 1915) and span.demolition == (1916, 1961)
    assert span.attributes() == {"epochs": [1915], "dateOfConstructionEarliest": 1881,
                                 "dateOfConstructionLatest": 1915,
                                 "dateOfDemolitionEarliest": 1916,
                                 "dateOfDemolitionLatest": 1961, "standing": False}


def test_on_every_map_not_standing_today_was_demolished_after_the_last():
    span = lifespan(YEARS, [True, True, True])
    assert span.construction == (None, 1880) and span.demolition == (1962, None)
    assert "dateOfConstructionEarliest" not in span.attributes()
    assert "dateOfDemolitionLatest" not in span.attributes()


def test_a_standing_building_has_its_register_year_and_no_demolition():
    span = lifespan(YEARS, [False, True, True], built=1902, standing=True)
    assert span.construction == (1902, 1902) and span.demolition is None
    assert span.conflict is None and span.attributes()["dateOfConstruction"] == 1902


@pytest.mark.parametrize("present, built, conflict", [
    ([False, True, True], 1700, "built 1700 (register) but not on the 1880 map"),
    ([True, True, True], 1950, "built 1950 (register) but on the 1880 map"),
    ([True, False, True], None, "not on the 1915 map between maps that show it"),
])
def test_conflicting_evidence_is_said_and_the_maps_bound_the_dates(present, built, conflict):
    span = lifespan(YEARS, present, built=built, standing=built is not None)
    assert span.conflict == conflict
    assert "dateOfConstruction" not in span.attributes()
    assert span.attributes()["conflict"] == conflict


@given(present=st.lists(st.booleans(), min_size=4, max_size=4).filter(any),
       true_year=st.integers(1801, 2000))
def test_the_intervals_hold_the_true_dates(present, true_year):
    """Property: maps that show a building exactly while it stood bound its true
    construction and demolition years."""
    years = (1800, 1850, 1900, 1950)
    # a building that stood from just after one map to just before another
    first = present.index(True)
    last = len(present) - 1 - present[::-1].index(True)
    present = [first <= k <= last for k in range(4)]
    span = lifespan(years, present)
    built = years[first] - 1 if first > 0 else None
    gone = years[last] + 1
    lo, hi = span.construction
    if built is not None:
        assert lo <= built <= hi
    dlo, dhi = span.demolition
    assert dlo <= gone and (dhi is None or gone <= dhi)
    assert span.conflict is None and span.epochs == tuple(y for y, p in zip(years, present) if p)


def test_a_standing_building_left_out_by_the_later_maps_is_a_conflict():
    """On the 1880 map, not on the 1915 and 1961 ones, yet in today's register: the maps
    and the register disagree (issue 49, item 9), not silently standing."""
    span = lifespan(YEARS, [True, False, False], built=1850, standing=True)
    assert span.conflict == "in today's register but not on the 1915, 1961 maps after 1880"
    assert span.standing and span.demolition == (1881, 1915)
    a = span.attributes()
    assert a["conflict"] == span.conflict and "dateOfConstruction" not in a
    assert (a["dateOfDemolitionEarliest"], a["dateOfDemolitionLatest"]) == (1881, 1915)
    # shown on the last map: no conflict
    assert lifespan(YEARS, [True, True, True], standing=True).conflict is None


def test_the_merge_flags_a_register_building_the_next_map_leaves_out():
    """A small synthetic case: a building of the 1880 map, not on the 1915 one (which
    covers its place), and in the register: a conflict of the merge, counted in its
    report."""
    from reconstruction.epochs.dynamic import Epoch, merge_epochs
    from reconstruction.testsuite.epochs.test_dynamic import model

    a = model(1880, {"NL.IMBAG.Pand.0503100000000009": (84000, 446000, 8, 1),
                     "b": (84020, 446000, 9, 2)})
    b = model(1915, {"b": (84020, 446000, 9, 2), "w": (83980, 446000, 9, 3)})
    m = merge_epochs([Epoch(1880, a), Epoch(1915, b)], register={"0503100000000009": 1700})
    assert m.report.conflicts == {"NL.IMBAG.Pand.0503100000000009":
                                  "in today's register but not on the 1915 map after 1880"}
    attributes = m.document["CityObjects"]["NL.IMBAG.Pand.0503100000000009"]["attributes"]
    assert attributes["standing"] and attributes["conflict"]


def test_a_later_map_of_another_part_of_the_town_says_nothing_of_a_building():
    """A map that does not cover a register building's place (the Delft 1961 subset)
    is no evidence that it was gone."""
    span = lifespan(YEARS, [True, False, False], standing=True,
                    covered=[True, False, True])
    assert span.conflict == "in today's register but not on the 1961 map after 1880"
    assert span.demolition == (1881, 1961)
    span = lifespan(YEARS, [True, False, False], standing=True, covered=[True, False, False])
    assert span.conflict is None and span.demolition is None


def test_the_merge_asks_only_the_maps_that_cover_the_building():
    from reconstruction.epochs.dynamic import Epoch, merge_epochs
    from reconstruction.testsuite.epochs.test_dynamic import model

    a = model(1880, {"NL.IMBAG.Pand.0503100000000009": (84000, 446000, 8, 1),
                     "b": (84200, 446000, 9, 2)})
    b = model(1915, {"b": (84200, 446000, 9, 2), "c": (84220, 446000, 9, 2)})
    m = merge_epochs([Epoch(1880, a), Epoch(1915, b)], register={"0503100000000009": 1700})
    assert m.report.conflicts == {}
    assert m.document["CityObjects"]["NL.IMBAG.Pand.0503100000000009"]["attributes"][
        "standing"]
