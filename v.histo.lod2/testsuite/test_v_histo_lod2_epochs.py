"""v.histo.lod2 in a dynamic chain (previous=): the buildings of a block the two maps show
unchanged are kept as they were (solid, roof, heights), the others built anew, every
building named by its identity; a temporary GRASS location, the town of epoch_testing."""

import json
import os

import numpy as np
import pytest

from epoch_testing import HOUSE, UNCHANGED, subdivide_town, write_town
from histo_testing import run_module
from reconstruction.cityjson import geometry as citygeometry
from reconstruction.cityjson import model as cityjson
from reconstruction.core.contract import BUILDING, PLOT

pytestmark = pytest.mark.grass

HEIGHTS = {"height": "7,12", "attic": "3,5"}


@pytest.fixture
def town(mapset):
    import grass.script as gs

    from reconstruction import grassio

    write_town(grassio, gs)
    subdivide_town(gs)
    return gs, grassio


def load(path):
    with open(path) as f:
        return json.load(f)


def coordinates(doc, oid):
    """The absolute coordinates of every vertex of a building's geometries, in order."""
    resolved = citygeometry.resolved(doc)
    return np.array(citygeometry.parts(resolved[oid]["geometry"][0]["boundaries"], 3))


def test_unchanged_blocks_keep_their_buildings_and_the_rest_is_built_anew(town, tmp_path,
                                                                          schemas):
    gs, grassio = town
    m1880, m1915 = str(tmp_path / "m1880.city.json"), str(tmp_path / "m1915.city.json")
    rc, _, err = run_module("v.histo.lod2", input="fp_1880", output=m1880, year=1880, seed=3,
                            **HEIGHTS)
    assert rc == 0, err
    rc, _, err = run_module("v.histo.lod2", input="fp_1915", output=m1915, previous=m1880,
                            year=1915, seed=4, **HEIGHTS)
    assert rc == 0, err
    said = " ".join(err.split())
    a, b = load(m1880), load(m1915)
    for doc in (a, b):
        assert cityjson.schema_errors(doc, os.path.join(schemas, "cityjson-2.0.2")) == []
        assert cityjson.consistency_errors(doc) == []
    _, c1 = grassio.read_features("fp_1880")
    _, c2 = grassio.read_features("fp_1915")
    # every building is named by its identity
    assert set(a["CityObjects"]) == set(c1[BUILDING])
    assert set(b["CityObjects"]) == set(c2[BUILDING])
    unchanged = {i for i, p in zip(c2[BUILDING], c2[PLOT]) if p in UNCHANGED}
    assert HOUSE in unchanged
    assert unchanged <= set(a["CityObjects"])
    kept = set(c2[BUILDING]) & set(a["CityObjects"])     # the split block's too
    for oid in kept:
        old, new = a["CityObjects"][oid], b["CityObjects"][oid]
        assert np.array_equal(coordinates(a, oid), coordinates(b, oid)), oid
        for name in ("roof_type", "eaves_height", "roof_height", "ground_height"):
            assert old["attributes"][name] == new["attributes"][name]
        assert new["attributes"]["map_year"] == 1915
        assert new["attributes"][PLOT] == c2[PLOT][c2[BUILDING].index(oid)]
    assert "{} of {} footprints with a building identity keep their building".format(
        len(kept), len(c2[BUILDING])) in said
    # the buildings of the split block that stayed clear of the passage keep their
    # footprint and building too; the new block's are new
    split_kept = [i for i, p in zip(c2[BUILDING], c2[PLOT]) if p in (2, 3)
                  and i in a["CityObjects"]]
    assert split_kept
    new = [i for i, p in zip(c2[BUILDING], c2[PLOT]) if p == 5]
    assert new and not set(new) & set(a["CityObjects"])


def test_without_previous_the_same_footprints_give_the_same_model_as_before(town, tmp_path):
    gs, _ = town
    out = str(tmp_path / "plain.city.json")
    rc, _, err = run_module("v.histo.lod2", input="fp_1880", output=out, year=1880, seed=3,
                            **HEIGHTS)
    assert rc == 0, err
    doc = load(out)
    assert all(not oid.startswith("building_1880_") or oid.count("_") == 2
               for oid in doc["CityObjects"])


def test_previous_needs_the_building_column(town, tmp_path):
    gs, grassio = town
    m1880 = str(tmp_path / "m1880.city.json")
    assert run_module("v.histo.lod2", input="fp_1880", output=m1880, **HEIGHTS)[0] == 0
    gs.run_command("v.histo.subdivide", input="plots_1915", output="plain", quiet=True)
    out = str(tmp_path / "x.city.json")
    rc, _, err = run_module("v.histo.lod2", input="plain", output=out, previous=m1880,
                            year=1915, **HEIGHTS)
    assert rc != 0 and "building column" in " ".join(err.split())
    assert "Traceback" not in err and not os.path.exists(out)


def test_previous_of_a_later_map_is_refused_with_one_error_line(town, tmp_path):
    """Issue 49, item 7: 235 buildings were "kept" from 1961 into 1915."""
    m1915 = str(tmp_path / "m1915.city.json")
    assert run_module("v.histo.lod2", input="fp_1915", output=m1915, year=1915,
                      **HEIGHTS)[0] == 0
    out = str(tmp_path / "x.city.json")
    rc, _, err = run_module("v.histo.lod2", input="fp_1880", output=out, previous=m1915,
                            year=1880, **HEIGHTS)
    text = " ".join(err.split())
    assert rc != 0 and text.count("ERROR:") == 1 and "is of the map of 1915" in text
    assert "Traceback" not in err and not os.path.exists(out)


def test_a_broken_building_of_previous_gives_the_counted_warning_existing_gives(town,
                                                                               tmp_path):
    """Issue 49, item 7: it was left out without a word (existing= warns)."""
    m1880 = str(tmp_path / "m1880.city.json")
    assert run_module("v.histo.lod2", input="fp_1880", output=m1880, year=1880, seed=3,
                      **HEIGHTS)[0] == 0
    doc = load(m1880)
    broken = sorted(doc["CityObjects"])[0]
    doc["CityObjects"][broken]["geometry"][0]["boundaries"][0][0][0][0] = -1
    with open(m1880, "w") as f:
        json.dump(doc, f)
    out = str(tmp_path / "m1915.city.json")
    rc, _, err = run_module("v.histo.lod2", input="fp_1915", output=out, previous=m1880,
                            year=1915, seed=4, **HEIGHTS)
    assert rc == 0, err
    text = " ".join(err.split())
    assert "1 buildings of the earlier epoch's model '{}' are broken and left out".format(
        m1880) in text
    assert "<{}>: ".format(broken) in text and "vertex index -1 is negative" in text
