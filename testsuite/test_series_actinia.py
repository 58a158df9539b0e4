"""A map series through actinia and through the local fallback (issue 30).

Starts Redis and actinia on 127.0.0.1 on free ports (tools/actinia/service.sh,
stopped again whatever happens: testsuite/series_service.py), writes four
adjacent sheets of one synthetic town (testsuite/synthetic_sheets.py; the
fourth has no training map) into the service's work folder and runs them
with tools/histo_series.py (the credentials of the service's folder): as
jobs on actinia, and
locally, where the driver is killed after its first sheet and run again;
and runs each good sheet through demo/chain.sh (``chain.sh OUT
MANIFEST:SHEET``) in a temporary GRASS location.
Checks: each sheet's model from actinia is byte-identical to the one
demo/chain.sh makes of that sheet with its own stage functions (two
descriptions of one chain: a drift between the template and chain.sh
changes the bytes) and to the local fallback's (the same process chain run
in a local GRASS session); the bad sheet fails alone with its module's
ERROR: line; the rerun runs only the sheets that had not finished; the
merged series builds every plot once and no two of its buildings overlap;
the killed run's mapset is gone after the rerun; a series of one sheet with
no margin (no neighbour) runs alike on actinia, locally and in chain.sh.
"""

import concurrent.futures
import json
import os
import signal
import subprocess
import sys
import time

import pytest

import series_service
import synthetic_map
import synthetic_sheets

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DIST = series_service.DIST
DRIVER = os.path.join(ROOT, "tools", "histo_series.py")
CHAIN = os.path.join(ROOT, "demo", "chain.sh")
GOOD = ("sheet_0_0", "sheet_1_0", "sheet_0_1")

pytestmark = pytest.mark.grass


@pytest.fixture(scope="module")
def actinia(tmp_path_factory):
    missing = series_service.missing()
    if missing:
        pytest.skip("not installed: " + ", ".join(missing))
    with series_service.started(str(tmp_path_factory.mktemp("actinia"))) as service:
        yield service


@pytest.fixture(scope="module")
def sheets(actinia):
    """The sheets in the service's work folder (the only place its chains may read)."""
    out = os.path.join(actinia.work, "sheets")
    smap = synthetic_map.generate(seed=1, size=400)
    path = synthetic_sheets.write(out, smap, [(0, 0), (1, 0), (0, 1), (1, 1)], 200.0)
    os.remove(os.path.join(out, "sheet_1_1.training.geojson"))
    return path


def drive(manifest, out, *more, background=False):
    command = [sys.executable, DRIVER, manifest, out, "--dist", DIST] + list(more)
    if background:
        return subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                text=True, start_new_session=True)
    return subprocess.run(command, capture_output=True, text=True, timeout=1200)


def attempts(out):
    with open(os.path.join(out, "progress.jsonl")) as f:
        return [json.loads(line) for line in f if line.strip()]


@pytest.fixture(scope="module")
def on_actinia(actinia, sheets, tmp_path_factory):
    out = str(tmp_path_factory.mktemp("on_actinia"))
    proc = drive(sheets, out, "--server", actinia.url, "--credentials", actinia.credentials,
                 "--jobs", "2")
    return out, proc


@pytest.fixture(scope="module")
def local_resumed(sheets, tmp_path_factory):
    """The local fallback, killed after its first finished sheet, then run again."""
    out = str(tmp_path_factory.mktemp("local"))
    first = drive(sheets, out, "--jobs", "1", background=True)
    try:
        deadline = time.time() + 600
        while time.time() < deadline and first.poll() is None:
            if os.path.exists(os.path.join(out, "progress.jsonl")) and any(
                    a["status"] == "done" for a in attempts(out)):
                break
            time.sleep(0.5)
    finally:
        if first.poll() is None:
            os.killpg(first.pid, signal.SIGKILL)
        first.wait()
    before = attempts(out)
    second = drive(sheets, out, "--jobs", "2")
    return out, before, second


def chain_sh(manifest_path, names, out):
    """demo/chain.sh run on each sheet of ``names``, each in a mapset of its
    own of a temporary location in the series' EPSG code, two at a time:
    their output folders (``out``/sheet) asserted to have finished."""
    from reconstruction.series import manifest

    location = os.path.join(out, "grassdb", "series")
    subprocess.run(["grass", "-c", "EPSG:{}".format(manifest.read_manifest(manifest_path).epsg),
                    location, "-e"], check=True, capture_output=True)
    env = dict(os.environ, GRASS_ADDON_BASE=DIST, PATH=os.pathsep.join(
        [os.path.join(DIST, "scripts"), os.path.join(DIST, "bin"), os.environ["PATH"]]))
    for name in ("GISRC", "GISBASE", "GRASS_OVERWRITE"):
        env.pop(name, None)

    def one(name):
        return subprocess.run(["grass", "-c", os.path.join(location, name), "--exec", "bash",
                               CHAIN, os.path.join(out, name),
                               "{}:{}".format(manifest_path, name)],
                              capture_output=True, text=True, env=env, timeout=600)

    with concurrent.futures.ThreadPoolExecutor(max_workers=2) as pool:
        runs = dict(zip(names, pool.map(one, names)))
    for name, proc in runs.items():
        assert proc.returncode == 0, (name, proc.stdout[-2000:] + proc.stderr[-3000:])
    return out


@pytest.fixture(scope="module")
def on_chain_sh(sheets, tmp_path_factory):
    """demo/chain.sh run on each good sheet: its output folder per sheet."""
    return chain_sh(sheets, GOOD, str(tmp_path_factory.mktemp("chain_sh")))


@pytest.fixture(scope="module")
def single(sheets, actinia, tmp_path_factory):
    """A series of one sheet with "margin": 0 (no neighbour: r.patch, which
    needs two maps, cannot make its map; issue 49, item 11), run on
    actinia, locally and through demo/chain.sh: the three output folders."""
    with open(sheets) as f:
        doc = json.load(f)
    doc.update(margin=0, sheets=[s for s in doc["sheets"] if s["name"] == "sheet_0_0"])
    path = os.path.join(os.path.dirname(sheets), "single.json")
    with open(path, "w") as f:
        json.dump(doc, f)
    runs = {"actinia": str(tmp_path_factory.mktemp("single_actinia")),
            "local": str(tmp_path_factory.mktemp("single_local"))}
    procs = {"actinia": drive(path, runs["actinia"], "--server", actinia.url, "--credentials",
                              actinia.credentials),
             "local": drive(path, runs["local"])}
    for how, proc in procs.items():
        assert proc.returncode == 0, (how, proc.stdout[-2000:] + proc.stderr[-3000:])
    runs["chain.sh"] = os.path.join(chain_sh(path, ["sheet_0_0"], str(
        tmp_path_factory.mktemp("single_chain_sh"))), "sheet_0_0")
    runs["actinia"] = os.path.join(runs["actinia"], "sheet_0_0")
    runs["local"] = os.path.join(runs["local"], "sheet_0_0")
    return runs


def test_actinia_runs_the_good_sheets_and_the_bad_one_fails_alone(on_actinia):
    out, proc = on_actinia
    assert proc.returncode == 1, proc.stdout + proc.stderr
    report = json.load(open(os.path.join(out, "report.json")))
    assert report["finished"] == 3 and list(report["failed"]) == ["sheet_1_1"]
    assert report["failed"]["sheet_1_1"].startswith("ERROR:")
    assert "training" in report["failed"]["sheet_1_1"]
    tries = [a for a in attempts(out) if a["sheet"] == "sheet_1_1"]
    assert [a["attempt"] for a in tries] == [1, 2]          # tried once more
    for name in GOOD:
        assert os.path.getsize(os.path.join(out, name, "model.city.json")) > 1000


def test_a_rerun_after_a_kill_runs_only_the_missing_sheets(local_resumed):
    out, before, second = local_resumed
    assert second.returncode == 1, second.stdout + second.stderr
    done_before = {a["sheet"] for a in before if a["status"] == "done"}
    assert done_before and len(done_before) < 3
    assert "finished before" in second.stdout
    after = attempts(out)[len(before):]
    assert not done_before & {a["sheet"] for a in after}
    assert {a["sheet"] for a in after if a["status"] == "done"} == set(GOOD) - done_before
    # the mapset of the sheet the kill cut short is gone (issue 49, item 12), and no .part
    assert os.listdir(os.path.join(out, "grassdb", "series")) == ["PERMANENT"]
    assert not [n for _, _, files in os.walk(out) for n in files if n.endswith(".part")]


def test_a_sheet_without_neighbours_runs_the_same_on_actinia_locally_and_in_chain_sh(single):
    with open(os.path.join(single["actinia"], "chain.json")) as f:
        modules = [step["module"] for step in json.load(f)["list"]]
    assert "r.patch" not in modules and modules.count("r.resample") == 3
    models = {}
    for how, folder in single.items():
        with open(os.path.join(folder, "model.city.json"), "rb") as f:
            models[how] = f.read()
    assert len(models["actinia"]) > 1000
    assert models["actinia"] == models["local"], first_difference(
        "sheet_0_0", models["actinia"], models["local"])
    assert models["actinia"] == models["chain.sh"], first_difference(
        "sheet_0_0", models["actinia"], models["chain.sh"])


def test_each_sheet_from_actinia_is_byte_identical_to_chain_sh_on_that_sheet(on_actinia,
                                                                             on_chain_sh):
    for name in GOOD:
        with open(os.path.join(on_actinia[0], name, "model.city.json"), "rb") as f:
            a = f.read()
        with open(os.path.join(on_chain_sh, name, "model.city.json"), "rb") as f:
            b = f.read()
        assert a == b, first_difference(name, a, b)


def first_difference(name, a, b):
    """Where two models part: sizes and the bytes around the first difference."""
    k = next((i for i, (x, y) in enumerate(zip(a, b)) if x != y), min(len(a), len(b)))
    return "sheet <{}>: {} and {} bytes, first difference at byte {}: {!r} / {!r}".format(
        name, len(a), len(b), k, a[max(0, k - 60):k + 60], b[max(0, k - 60):k + 60])


def test_each_sheet_from_actinia_is_byte_identical_to_the_local_fallback(on_actinia,
                                                                          local_resumed):
    for name in GOOD:
        with open(os.path.join(on_actinia[0], name, "model.city.json"), "rb") as a, \
                open(os.path.join(local_resumed[0], name, "model.city.json"), "rb") as b:
            assert a.read() == b.read(), name
    with open(os.path.join(on_actinia[0], "series.city.jsonl"), "rb") as a, \
            open(os.path.join(local_resumed[0], "series.city.jsonl"), "rb") as b:
        assert a.read() == b.read()


def test_the_merged_series_builds_every_plot_once_without_overlaps(on_actinia, sheets):
    import shapely
    from shapely.geometry import box, shape

    from reconstruction.cityjson import existing
    from reconstruction.series import manifest

    out = on_actinia[0]
    series = manifest.read_manifest(sheets)
    areas = {s.name: box(*s.extent) for s in series.sheets if s.name in GOOD}
    built = {}
    for name in GOOD:
        with open(os.path.join(out, name, "plots.geojson")) as f:
            built[name] = [shape(ft["geometry"]) for ft in json.load(f)["features"]]
    with open(os.path.join(os.path.dirname(sheets), "plots.geojson")) as f:
        truth = [shape(ft["geometry"]) for ft in json.load(f)["features"]]
    crossing = 0
    for plot in truth:
        on = [n for n, a in areas.items() if plot.intersection(a).area > 1.0]
        if not on or plot.intersection(shapely.union_all(list(areas.values()))).area < \
                0.9 * plot.area:
            continue
        builders = [n for n, ps in built.items()
                    if any(p.intersection(plot).area > 0.3 * plot.area for p in ps)]
        assert len(builders) <= 1, (plot.wkt, builders)
        if len(on) > 1:             # cut by an edge: built, whole, by one sheet
            crossing += 1
            assert len(builders) == 1, (plot.wkt, on)
    assert crossing >= 1            # the test needs plots over the sheets' edges
    model = existing.read_model(os.path.join(out, "series.city.jsonl"))
    fps = existing.footprints(model)
    geoms = [fps.geometry(b) for b in range(len(model.buildings))]
    assert len(geoms) == json.load(open(os.path.join(out, "report.json")))["buildings"]
    tree = shapely.STRtree(geoms)
    i, j = tree.query(geoms, predicate="intersects")
    overlaps = [(model.buildings[a], model.buildings[b]) for a, b in zip(i, j)
                if a < b and geoms[a].intersection(geoms[b]).area > 0.01]
    assert overlaps == []
    # and the sheets' chains built every building once: the merge had none to leave out
    assert json.load(open(os.path.join(out, "report.json")))["dropped"] == []
