"""A map series through actinia and through the local fallback (issue 30).

Starts Redis and actinia on 127.0.0.1 on free ports (tools/actinia/service.sh,
stopped again whatever happens), writes four adjacent sheets of one
synthetic town (testsuite/synthetic_sheets.py; the fourth has no training
map) and runs them with tools/histo_series.py: as jobs on actinia, and
locally, where the driver is killed after its first sheet and run again;
and runs each good sheet through demo/chain.sh (``chain.sh OUT
MANIFEST:SHEET``) in a temporary GRASS location.
Checks: each sheet's model from actinia is byte-identical to the one
demo/chain.sh makes of that sheet with its own stage functions (two
descriptions of one chain: a drift between the template and chain.sh
changes the bytes) and to the local fallback's (the same process chain run
in a local GRASS session); the bad sheet fails alone with its module's
ERROR: line; the rerun runs only the sheets that had not finished; the
merged series builds every plot once and no two of its buildings overlap.
"""

import concurrent.futures
import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import time

import pytest

import synthetic_map
import synthetic_sheets

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DIST = os.environ.get("HISTO_DIST", os.path.join(ROOT, "dist"))
ACTINIA_VENV = os.environ.get("ACTINIA_VENV", os.path.expanduser(
    "~/.local/share/histo/actinia-venv"))
SERVICE = os.path.join(ROOT, "tools", "actinia", "service.sh")
DRIVER = os.path.join(ROOT, "tools", "histo_series.py")
CHAIN = os.path.join(ROOT, "demo", "chain.sh")
GOOD = ("sheet_0_0", "sheet_1_0", "sheet_0_1")

pytestmark = pytest.mark.grass


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.fixture(scope="module")
def actinia(tmp_path_factory):
    missing = [what for what, ok in (
        ("actinia-core (make actinia)", os.path.exists(os.path.join(ACTINIA_VENV, "bin",
                                                                    "gunicorn"))),
        ("redis-server (Debian redis-server)", shutil.which("redis-server")),
        ("the staged suite (make build)", os.path.exists(os.path.join(DIST, "scripts",
                                                                      "v.histo.lod2"))),
        ("GRASS", shutil.which("grass"))) if not ok]
    if missing:
        pytest.skip("not installed: " + ", ".join(missing))
    folder = str(tmp_path_factory.mktemp("actinia"))
    port, redis_port = free_port(), free_port()
    env = dict(os.environ, DIST=DIST, ACTINIA_VENV=ACTINIA_VENV)
    try:
        subprocess.run(["bash", SERVICE, "start", folder, str(port), str(redis_port)],
                       check=True, env=env, capture_output=True, text=True, timeout=180)
        yield "http://127.0.0.1:{}".format(port)
    finally:
        subprocess.run(["bash", SERVICE, "stop", folder], env=env, capture_output=True)


@pytest.fixture(scope="module")
def sheets(tmp_path_factory):
    out = str(tmp_path_factory.mktemp("sheets"))
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
    proc = drive(sheets, out, "--server", actinia, "--jobs", "2")
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


@pytest.fixture(scope="module")
def on_chain_sh(sheets, tmp_path_factory):
    """demo/chain.sh run on each good sheet, each in a mapset of its own of a
    temporary location in the series' EPSG code, two at a time: its output
    folder per sheet."""
    from reconstruction.series import manifest

    out = str(tmp_path_factory.mktemp("chain_sh"))
    location = os.path.join(out, "grassdb", "series")
    subprocess.run(["grass", "-c", "EPSG:{}".format(manifest.read_manifest(sheets).epsg),
                    location, "-e"], check=True, capture_output=True)
    env = dict(os.environ, GRASS_ADDON_BASE=DIST, PATH=os.pathsep.join(
        [os.path.join(DIST, "scripts"), os.path.join(DIST, "bin"), os.environ["PATH"]]))
    for name in ("GISRC", "GISBASE", "GRASS_OVERWRITE"):
        env.pop(name, None)

    def one(name):
        return subprocess.run(["grass", "-c", os.path.join(location, name), "--exec", "bash",
                               CHAIN, os.path.join(out, name), "{}:{}".format(sheets, name)],
                              capture_output=True, text=True, env=env, timeout=600)

    with concurrent.futures.ThreadPoolExecutor(max_workers=2) as pool:
        runs = dict(zip(GOOD, pool.map(one, GOOD)))
    for name, proc in runs.items():
        assert proc.returncode == 0, (name, proc.stdout[-2000:] + proc.stderr[-3000:])
    return out


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
