"""The dynamic chain on the synthetic town over time, against its true history (issue 28).

In a fresh mapset of the temporary GRASS location, demo/dynamic_chain.sh
draws the town of seed 1 at 1880, 1915 and 1961 (testsuite/synthetic_epochs.py,
its truth beside the models) and runs the whole chain per epoch, from the
classification of each map to its model, the later epochs with previous=;
v.histo.timeline merges the three models with today's register
(``town_current``) and extracts the snapshot of each epoch's year.

Measured building by building (testsuite/dynamic_town.py) and printed:
(a) the buildings of truth-unchanged plots kept identically in the next
epoch (same id, geometry to the millimetre, roof and heights); (b) every
building of a truth-demolished plot has a demolition interval holding the
true year; (c) every register building is one building of the merged model,
shown on the maps whose models hold it, and, once shown, on every later map;
(d) each snapshot equals its epoch's model; (e) the merged model is valid by
the CityJSON 2.0.2 schemas, and val3dity finds every solid valid.

The chain's plots of two maps of one unchanged block differ by more than the
drawing: (a) and (c) hold because subdivide keeps a building most of whose
ground the later map still draws, the classification restores a plot a label
cut in two, and no plot above the classification's minimum mapping unit is
dropped (min_area=50 in the chain).
"""

import json
import os
import subprocess

import pytest

from histo_testing import key_values, run_module

pytestmark = [pytest.mark.grass]

HERE = os.path.dirname(os.path.abspath(__file__))
CHAIN = os.path.join(HERE, "..", "demo", "dynamic_chain.sh")
YEARS = (1880, 1915, 1961)


@pytest.fixture(scope="module")
def town(grass_session, tmp_path_factory):
    import grass.script as gs

    from synthetic_epochs import load_truth

    gs.run_command("g.mapset", flags="c", mapset="dynamic_town", quiet=True)
    out = tmp_path_factory.mktemp("dynamic_town")
    proc = subprocess.run(["bash", CHAIN, str(out)], capture_output=True, text=True,
                          env=dict(os.environ, YEARS=",".join(map(str, YEARS))))
    assert proc.returncode == 0, proc.stderr[-3000:]
    models = {y: str(out / "model_{}.city.json".format(y)) for y in YEARS}
    merged = str(out / "merged.city.json")
    rc, stdout, err = run_module("v.histo.timeline", flags="g", models=",".join(
        models[y] for y in YEARS), years=",".join(map(str, YEARS)), register="town_current",
        output=merged, viewer=str(out / "town.html"), tiles=str(out / "tiles"))
    assert rc == 0, err
    snapshots = {}
    for y in YEARS:
        snapshots[y] = str(out / "snapshot_{}.city.json".format(y))
        rc, _out, err = run_module("v.histo.timeline", input=merged, snapshot=y,
                                   output=snapshots[y])
        assert rc == 0, err

    def read(path):
        with open(path) as f:
            return json.load(f)

    sizes = sum(os.path.getsize(p) for p in models.values())
    print("\nmerged: {}; {} bytes against the epochs' {} (ratio {:.2f})".format(
        " ".join(stdout.split()), os.path.getsize(merged), sizes,
        os.path.getsize(merged) / sizes))
    return {"truth": load_truth(str(out / "truth.json")),
            "models": {y: read(p) for y, p in models.items()},
            "merged": read(merged), "merged_path": merged, "counts": key_values(stdout),
            "snapshots": {y: read(p) for y, p in snapshots.items()},
            "snapshot_paths": snapshots, "model_paths": models, "viewer": str(out / "town.html"),
            "tiles": out / "tiles"}


def test_unchanged_plots_keep_their_buildings(town):
    from dynamic_town import unchanged_plots

    u = unchanged_plots(town["truth"], town["models"])
    print("\nbuildings of truth-unchanged plots kept identically: {} of {} ({:.1f} %); plots "
          "whose buildings all are: {} of {}".format(u.kept, u.buildings,
                                                       100.0 * u.kept / u.buildings,
                                                       u.plots_kept, u.plots))
    for year, oid, why in u.lost:
        print("  {}: {}: {}".format(year, oid, why))
    assert u.buildings > 1000
    assert u.kept == u.buildings and u.plots_kept == u.plots


def test_demolished_buildings_are_dated_around_their_true_year(town):
    from dynamic_town import demolitions

    total, right, wrong = demolitions(town["truth"], town["models"], town["merged"])
    print("\nbuildings of demolished plots: {}, demolition interval holds the true year: {}; "
          "others: {}".format(total, right, wrong[:10]))
    assert total > 20 and right == total


def test_register_buildings_are_one_building_over_the_epochs(town):
    from dynamic_town import standing_identities

    objects = town["merged"]["CityObjects"]
    register = {c["identificatie"] for c in town["truth"]["current"]}
    for oid in register:
        shown = [y for y in YEARS if oid in town["models"][y]["CityObjects"]]
        if shown:
            assert objects[oid]["attributes"]["epochs"] == shown, oid
            assert "dateOfDemolitionEarliest" not in objects[oid]["attributes"], oid
    found, good, bad = standing_identities(town["truth"], town["models"], town["merged"])
    print("\nregister buildings on the maps: {}, shown on every map from their first: {}; "
          "others: {}".format(found, good, bad))
    assert found > 100 and good == found


def test_each_snapshot_is_its_epochs_model(town):
    from dynamic_town import same_model

    for y in YEARS:
        differences = same_model(town["snapshots"][y], town["models"][y])
        assert differences == [], (y, differences[:10])


def test_the_merged_model_is_valid_and_its_solids_too(town, schemas):
    from reconstruction.cityjson import model as cityjson
    from reconstruction.cityjson import versions
    from reconstruction.epochs.dynamic import buildings
    from val3dity import val3dity_problem, val3dity_report

    # issue 52: valid with the suite's Extension (HistoVersions), each version a city
    # object of its own that val3dity checks alone: no 601 (overlapping parts)
    doc = town["merged"]
    assert cityjson.schema_errors(doc, os.path.join(schemas, "cityjson-2.0.2"), extensions={
        versions.NAME: versions.extension()}) == []
    assert cityjson.consistency_errors(doc) == []
    assert int(town["counts"]["buildings"]) == len(buildings(doc["CityObjects"]))
    if val3dity_problem():
        pytest.skip(val3dity_problem())
    report = val3dity_report(town["merged_path"])
    several = sum(1 for v in doc["CityObjects"].values() if v["type"] == versions.VERSION) - \
        len(buildings(doc["CityObjects"]))
    print("\nval3dity, merged: {} ({} versions more than buildings)".format(report, several))
    assert report.objects > 0 and report.valid == report.objects and not report.codes
    for y in YEARS:
        r = val3dity_report(town["snapshot_paths"][y])
        print("val3dity, snapshot {}: {}".format(y, r))
        assert r.objects > 0 and r.valid == r.objects


@pytest.mark.browser
def test_the_viewer_s_year_slider_shows_each_year_s_snapshot(town, browser_page):
    # issue 29: v.histo.timeline viewer= in headless chromium, offline; the slider at
    # each epoch and between them draws as many buildings as that year's snapshot
    from reconstruction.epochs.dynamic import buildings, snapshot

    def top_level(document):
        return buildings(document["CityObjects"])

    browser_page.open(town["viewer"])
    waited = browser_page.wait_ready("window.histo && window.histo.ready === true")
    page = browser_page.page
    assert page.evaluate("histo.buildings") == len(top_level(town["merged"]))
    drawn = {}
    for year in (1880, 1900, 1915, 1940, 1961):
        page.evaluate("histo.setYear({})".format(year))
        drawn[year] = page.evaluate("histo.drawn()")
        assert drawn[year] == len(top_level(snapshot(town["merged"], year))), year
    print("\nviewer: first frame after {:.2f} s; buildings drawn by year {}".format(
        waited, drawn))
    assert browser_page.errors == [] and browser_page.blocked == []


@pytest.mark.browser
def test_the_tileset_loads_in_cesium_and_a_click_picks_a_building(town, browser_page):
    # issue 52, item 2: v.histo.timeline tiles= in CesiumJS (npm), headless chromium,
    # served on 127.0.0.1 with no request leaving the machine: every feature loads, the
    # year's style shows as many as the year's snapshot has buildings, and a click on a
    # building standing in 1915 returns its id and the years of its 1915 version
    import cesium
    from reconstruction.epochs.dynamic import snapshot
    from reconstruction.testsuite.view.test_tiles import features_of

    if cesium.missing():
        pytest.skip(cesium.missing())
    _tileset, features = features_of(town["tiles"])
    year = 1915
    standing = snapshot(town["merged"], year)
    buildings = [o for o, v in standing["CityObjects"].items() if not v.get("parents")]
    assert len([f for f in features if f[2] <= year <= f[3]]) == len(buildings)
    # the year's largest building, clicked at its middle
    target = cesium.largest(standing, buildings)
    loaded, waited, picked = cesium.load_and_click(
        browser_page, town["tiles"], cesium.middle_ecef(standing, target), year,
        len(buildings))
    assert loaded == len(features)
    versions = {(f[2], f[3]) for f in features if f[1] == target and f[2] <= year <= f[3]}
    assert picked is not None, "the click at the middle of {} hit nothing".format(target)
    assert picked["id"] == target and {(picked["first_year"], picked["last_year"])} == versions
    print("\nCesiumJS: {} features of {} tiles loaded in {:.1f} s; picked {}".format(
        len(features), len(list(town["tiles"].glob("content/*.glb"))), waited, picked))
    assert browser_page.errors == [] and browser_page.blocked == []

