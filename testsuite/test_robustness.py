"""Bad input and interruptions across the five modules (issue 12, items 3 to 7).

Module runs in a temporary location: core GRASS tools work on every vector
output (no SQL keyword among the columns), output names and paths are
checked before any work, files are replaced whole (through a symbolic link,
never over a device), wrong column values and options fail clearly, and an
interrupted run (SIGINT, SIGTERM) leaves no output and no ``tmp_histo_*``
map, with one ``ERROR:`` line and no traceback.
"""

import contextlib
import json
import os
import shutil
import signal
import subprocess
import time

import pytest
from shapely.geometry import box

from histo_testing import run_module

from reconstruction.core import contract
from reconstruction.core import names

pytestmark = pytest.mark.grass

X0, Y0 = 84000.0, 446000.0


def plots(n, columns=10):
    """``n`` plots of 55 x 35 m in rows (each gives about 20 footprints)."""
    return [box(X0 + (i % columns) * 60, Y0 + (i // columns) * 40,
                X0 + (i % columns) * 60 + 55, Y0 + (i // columns) * 40 + 35) for i in range(n)]


@pytest.fixture
def small(mapset):
    """Six plots, a current footprint (built 1900) in each of the first four and one
    outside them, and
    footprints with heights for v.histo.lod2."""
    import grass.script as gs

    from reconstruction import grassio

    gs.run_command("g.region", n=Y0 + 100, s=Y0 - 10, e=X0 + 400, w=X0 - 10, res=1)
    grassio.write_features("plots", plots(6))
    current = [box(X0 + i * 60 + 2, Y0 + 2, X0 + i * 60 + 14, Y0 + 14) for i in range(4)]
    grassio.write_features("current", current + [box(X0 + 370, Y0 + 50, X0 + 385, Y0 + 65)],
                           {"bouwjaar": [1900] * 5})     # the last one on no plot
    grassio.write_features("houses", current, {"h_building": [6.0] * 4, "h_attic": [3.0] * 4})
    return gs, grassio


def error_lines(err):
    return [ln for ln in err.splitlines() if ln.startswith("ERROR:")]


def fails(module, message, **options):
    """Run ``module``: it fails with one ERROR: line holding ``message``."""
    code, _, err = run_module(module, quiet=True, **options)
    assert code == 1, err
    assert "Traceback" not in err
    lines = error_lines(err)
    assert len(lines) == 1 and message in " ".join(err.split()), err
    return err


# ---------------------------------------------------------------------------
# Item 3: core GRASS tools on every vector output
# ---------------------------------------------------------------------------

def test_core_grass_tools_work_on_every_vector_output(small, tmp_path):
    gs, grassio = small
    for module, options in [
            ("v.histo.generalize", dict(input="plots", output="generalized")),
            ("v.histo.align", dict(input="plots", footprints="current", year=1950,
                                   output="aligned", unmatched="unmatched")),
            ("v.histo.subdivide", dict(input="plots", aligned="aligned", output="footprints"))]:
        code, _, err = run_module(module, quiet=True, **options)
        assert code == 0, err
    for name in ("generalized", "aligned", "unmatched", "footprints"):
        columns = grassio.column_names(name)
        assert all(names.column_name_problem(c) is None for c in columns), (name, columns)
        rows = len(grassio.read_table(name)["cat"])
        assert rows > 0, name
        first = min(grassio.read_table(name)["cat"])
        gs.run_command("g.copy", vector="{},{}_copy".format(name, name), quiet=True)
        assert grassio.column_names(name + "_copy") == columns
        assert len(grassio.read_table(name + "_copy")["cat"]) == rows
        gs.run_command("v.extract", input=name, output=name + "_one", quiet=True,
                       where="cat = {}".format(first))
        assert grassio.column_names(name + "_one") == columns
        column = [c for c in columns if c != "cat"][0]
        gs.run_command("v.db.renamecolumn", map=name + "_copy",
                       column="{},{}_new".format(column, column), quiet=True)
        assert column + "_new" in grassio.column_names(name + "_copy")
        path = str(tmp_path / (name + ".gpkg"))
        gs.run_command("v.out.ogr", input=name, output=path, format="GPKG", quiet=True,
                       stderr=subprocess.DEVNULL)
        assert os.path.getsize(path) > 0
    assert contract.CASE in grassio.column_names("footprints")


def test_an_old_case_column_is_read_and_kept_usable(small, tmp_path):
    """Maps of earlier runs have a column ``case``: read (and passed on) without a crash."""
    gs, grassio = small
    old = [box(X0 + 2, Y0 + 2, X0 + 14, Y0 + 14)]
    grassio.write_features("old", old, {"case": [2], contract.PLOT: [1], "h_building": [6.0],
                                        "h_attic": [3.0]})
    code, _, err = run_module("v.histo.lod2", input="old", output=str(tmp_path / "old.json"),
                              quiet=True)
    assert code == 0, err
    code, _, err = run_module("v.histo.subdivide", input="plots", aligned="old", output="fp",
                              quiet=True)
    assert code == 0, err
    assert "case" in grassio.column_names("fp") and contract.CASE in grassio.column_names("fp")
    assert grassio.read_table("fp")["case"].count(2) == 1


# ---------------------------------------------------------------------------
# Item 4: names and paths checked before any work
# ---------------------------------------------------------------------------

@pytest.mark.parametrize("module, options, message", [
    ("v.histo.subdivide", dict(input="plots", output="a.b"), "cannot name a vector map"),
    ("v.histo.subdivide", dict(input="plots", output="select"), "SQL keyword"),
    ("v.histo.generalize", dict(input="plots", output="g1", report="/nonexistent/r.json"),
     "directory '/nonexistent' does not exist"),
    ("v.histo.generalize", dict(input="plots", output="g2", metrics="/dev/full", overwrite=True),
     "is not a regular file"),
    ("v.histo.align", dict(input="plots", footprints="current", year=1950, output="same",
                           unmatched="same"), "name the same output"),
    ("v.histo.align", dict(input="plots", footprints="current", year=1950, output="1961"),
     "cannot name a vector map"),
    ("r.histo.classify", dict(input="r,g,b", training="t", output="a/b"),
     "cannot name a raster map"),
    ("v.histo.lod2", dict(input="houses", output="/nonexistent/x.json"),
     "directory '/nonexistent' does not exist"),
])
def test_outputs_are_checked_before_any_work(small, module, options, message):
    gs, grassio = small
    fails(module, message, **options)
    assert not gs.list_strings("vector", pattern="g[12]")
    assert not gs.list_strings("vector", pattern="tmp_histo_*")


# ---------------------------------------------------------------------------
# Item 6: file outputs
# ---------------------------------------------------------------------------

def test_file_outputs_go_through_links_never_over_devices(small, tmp_path):
    gs, grassio = small
    target = tmp_path / "model.json"
    target.write_text("old")
    link = tmp_path / "link.json"
    link.symlink_to(target)
    part = tmp_path / "model.json.part"
    part.write_text("someone's file")
    code, _, err = run_module("v.histo.lod2", input="houses", output=str(link), overwrite=True,
                              quiet=True)
    assert code == 0, err
    assert link.is_symlink() and target.read_text().startswith("{")
    assert part.read_text() == "someone's file"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["link.json", "model.json",
                                                         "model.json.part"]
    fails("v.histo.lod2", "is not a regular file", input="houses", output="/dev/full",
          overwrite=True)
    fails("v.histo.lod2", "exists", input="houses", output=str(link))


# ---------------------------------------------------------------------------
# Item 7: wrong input
# ---------------------------------------------------------------------------

@pytest.mark.parametrize("value", [1.5, "two"])
def test_a_plot_column_holding_no_whole_number_fails(small, value):
    gs, grassio = small
    grassio.write_features("odd", [box(X0 + 2, Y0 + 2, X0 + 14, Y0 + 14)],
                           {contract.PLOT: [value]})
    fails("v.histo.subdivide", "Column <plot> of vector map <odd> must hold whole numbers",
          input="plots", aligned="odd", output="fp")


def test_column_options_name_existing_columns_when_given(small):
    fails("v.histo.lod2", "Column <nothere> given as plot_column= is not in vector map <houses>",
          input="houses", output="/tmp/never_written.json", plot_column="nothere")
    fails("v.histo.lod2", "given as source_c", input="houses",
          output="/tmp/never_written.json", source_c="nothere")
    assert not os.path.exists("/tmp/never_written.json")


def test_unknown_epsg_code_fails(small, tmp_path):
    fails("v.histo.lod2", "Option crs= must be an EPSG code", input="houses",
          output=str(tmp_path / "x.json"), crs="999999999")
    code, _, err = run_module("v.histo.lod2", input="houses", output=str(tmp_path / "x.json"),
                              crs="7415", quiet=True)
    assert code == 0, err


def test_an_empty_training_map_gives_one_error_line(small):
    gs, grassio = small
    for band in "rgb":
        gs.mapcalc("{} = 100".format(band), quiet=True)
    gs.run_command("v.edit", map="empty", tool="create", quiet=True)
    fails("r.histo.classify", "Training map <empty> has no", input="r,g,b", training="empty",
          output="cls")


# ---------------------------------------------------------------------------
# Item 5: interruptions
# ---------------------------------------------------------------------------

def _wait_for(condition, proc, timeout=120):
    """Wait until ``condition()`` holds (True), or the run ends."""
    end = time.time() + timeout
    while time.time() < end and proc.poll() is None:
        if condition():
            return True
        time.sleep(0.05)
    return False


def _signal_when(gs, command, options, signum, message=None, pattern=None, tmp=None):
    """Run ``command``, send ``signum`` when it has printed ``message`` or when a
    vector map ``pattern`` exists; check that it ends as interrupted, leaving no
    output, no ``tmp_histo_*`` map and no temporary directory (in ``tmp``)."""
    import threading

    env = dict(os.environ, TMPDIR=str(tmp))
    proc = gs.start_command(command, stderr=subprocess.PIPE, env=env, **options)
    err = []
    reader = threading.Thread(target=lambda: err.extend(gs.decode(ln) for ln in proc.stderr))
    reader.start()
    if message:
        started = _wait_for(lambda: any(message in ln for ln in err), proc)
    else:
        started = _wait_for(lambda: gs.list_strings("vector", pattern=pattern), proc)
    assert started and proc.poll() is None, "the module ended before the signal"
    time.sleep(0.2)
    proc.send_signal(signum)
    proc.wait(timeout=60)
    reader.join()
    err = "".join(err)
    assert proc.returncode != 0, err
    assert "Traceback" not in err
    assert len(error_lines(err)) == 1, err
    assert ("Terminated" if signum == signal.SIGTERM else "Interrupted") in err
    for kind in ("vector", "raster"):
        assert gs.list_strings(kind, pattern=options["output"]) == []
        assert gs.list_strings(kind, pattern="tmp_histo_*") == []
    assert os.listdir(str(tmp)) == []


@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM])
@pytest.mark.parametrize("moment", ["computing", "writing"])
def test_an_interrupted_run_leaves_nothing_behind(mapset, tmp_path, signum, moment):
    """Signals while v.histo.subdivide computes (its message says so) and while it
    writes (its temporary output exists)."""
    import grass.script as gs

    from reconstruction import grassio

    gs.run_command("g.region", n=Y0 + 1700, s=Y0, e=X0 + 1200, w=X0, res=1)
    grassio.write_features("many", plots(400, columns=20))
    _signal_when(gs, "v.histo.subdivide", dict(input="many", output="fp"), signum,
                 message="Subdividing" if moment == "computing" else None,
                 pattern="tmp_histo_out*", tmp=tmp_path)


def test_sigterm_removes_generalize_temporary_maps(mapset, tmp_path):
    """v.histo.generalize on a raster makes tmp_histo_* maps: SIGTERM removes them."""
    import grass.script as gs

    gs.run_command("g.region", n=Y0 + 800, s=Y0, e=X0 + 1200, w=X0, res=1)
    gs.mapcalc("cls = if(row() % 40 < 30 && col() % 60 < 50, 1, 2)", quiet=True)
    _signal_when(gs, "v.histo.generalize", dict(raster="cls", **{"class": 1}, output="gen"),
                 signal.SIGTERM, message="Generalising", tmp=tmp_path)


MODULES = ("r.histo.classify", "v.histo.generalize", "v.histo.align", "v.histo.subdivide",
           "v.histo.lod2")


@pytest.mark.parametrize("module", MODULES)
def test_ctrl_c_while_grass_parses_the_options_is_one_error_line(mapset, tmp_path, module):
    """SIGINT while the module waits for g.parser (made slow here by a g.parser
    that sleeps first, and says when it started): one ERROR line, no traceback."""
    import shutil

    started = tmp_path / "started"
    slow = tmp_path / "g.parser"
    slow.write_text("#!/bin/sh\ntouch '{}'\nsleep 30\nexec '{}' \"$@\"\n".format(
        started, shutil.which("g.parser")))
    slow.chmod(0o755)
    env = dict(os.environ, PATH="{}:{}".format(tmp_path, os.environ["PATH"]))
    proc = subprocess.Popen([module, "--quiet"], env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, start_new_session=True)
    try:
        _wait_for(started.exists, proc, timeout=60)
        assert proc.poll() is None, "the module ended before g.parser started"
        proc.send_signal(signal.SIGINT)
        proc.wait(timeout=60)
    finally:
        with contextlib.suppress(ProcessLookupError):
            os.killpg(proc.pid, signal.SIGKILL)    # the sleeping g.parser, which holds stderr
    err = proc.stderr.read().decode()
    assert proc.returncode == 1, err
    assert "Traceback" not in err and "KeyboardInterrupt" not in err, err
    assert error_lines(err) == ["ERROR: Interrupted while starting"], err


# ---------------------------------------------------------------------------
# Issue 33, item 3: the file outputs of a run appear together or not at all
# ---------------------------------------------------------------------------

def _part_file_written(directory, name):
    """Whether the temporary file of output ``name`` exists in ``directory``
    and holds something (the model is being written)."""
    def written():
        return any(p.name.startswith("." + name + ".") and p.stat().st_size > 0
                   for p in directory.iterdir())
    return written


@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM])
@pytest.mark.parametrize("moment", ["building", "writing", "drawing"])
def test_an_interrupted_lod2_run_keeps_the_old_model_and_picture(mapset, tmp_path, signum,
                                                                  moment):
    """v.histo.lod2 ... render=x.png --overwrite, interrupted while it builds
    (its message says so), while the model is being written (its temporary
    file grows) and while the picture is drawn (its message): both old files
    stay as they were, and nothing else is left beside them."""
    import threading

    import grass.script as gs

    from reconstruction import grassio

    outputs = tmp_path / "out"
    outputs.mkdir()
    model, picture = outputs / "m.json", outputs / "m.png"
    model.write_text("the old model")
    picture.write_bytes(b"the old picture")
    houses = [box(X0 + (i % 60) * 15, Y0 + (i // 60) * 20, X0 + (i % 60) * 15 + 9,
                  Y0 + (i // 60) * 20 + 14) for i in range(3000)]
    grassio.write_features("many_houses", houses, {"h_building": [9.0] * len(houses),
                                                   "h_attic": [4.0] * len(houses)})
    proc = gs.start_command("v.histo.lod2", input="many_houses", output=str(model),
                            render=str(picture), roof="hip", overwrite=True, verbose=True,
                            stderr=subprocess.PIPE, env=dict(os.environ, TMPDIR=str(tmp_path)))
    err = []
    reader = threading.Thread(target=lambda: err.extend(gs.decode(ln) for ln in proc.stderr))
    reader.start()
    condition = {"building": lambda: any("Building" in ln for ln in err),
                 "writing": _part_file_written(outputs, "m.json"),
                 "drawing": lambda: any("Drawing the picture" in ln for ln in err)}[moment]
    started = _wait_for(condition, proc)
    assert started and proc.poll() is None, "the module ended before the signal: " + "".join(err)
    proc.send_signal(signum)
    proc.wait(timeout=60)
    reader.join()
    err = "".join(err)
    assert proc.returncode != 0 and "Traceback" not in err, err
    assert len(error_lines(err)) == 1, err
    assert ("Terminated" if signum == signal.SIGTERM else "Interrupted") in err
    assert model.read_text() == "the old model" and picture.read_bytes() == b"the old picture"
    assert sorted(p.name for p in outputs.iterdir()) == ["m.json", "m.png"]


def test_a_picture_that_cannot_be_written_fails_before_the_model_is_written(small, tmp_path):
    model = tmp_path / "m.json"
    model.write_text("the old model")
    fails("v.histo.lod2", "Cannot write '/proc/m.png'", input="houses", output=str(model),
          render="/proc/m.png", overwrite=True)
    assert model.read_text() == "the old model" and os.listdir(str(tmp_path)) == ["m.json"]


# ---------------------------------------------------------------------------
# Issue 33, item 4: an output never replaces an input
# ---------------------------------------------------------------------------

def test_no_file_output_replaces_a_file_input(small, tmp_path):
    existing = tmp_path / "bag.city.json"
    code, _, err = run_module("v.histo.lod2", input="houses", output=str(existing), quiet=True)
    assert code == 0, err
    before = existing.read_bytes()
    rules = tmp_path / "rules.csv"
    rules.write_text("roof,weight\nhip,1\n")
    link = tmp_path / "link.json"
    link.symlink_to(existing)
    for options, given in (
            (dict(output=str(tmp_path / "m.json"), render=str(existing)), "render"),
            (dict(output=str(link), existing=str(existing)), "output"),
            (dict(output=str(rules), rules=str(rules)), "output")):
        fails("v.histo.lod2", "Option {}= names the input".format(given), input="houses",
              overwrite=True, **dict(dict(existing=str(existing)), **options))
    assert existing.read_bytes() == before and rules.read_text() == "roof,weight\nhip,1\n"
    assert sorted(os.listdir(str(tmp_path))) == ["bag.city.json", "link.json", "rules.csv"]


@pytest.mark.parametrize("module, options", [
    ("v.histo.subdivide", dict(input="plots", output="plots")),
    ("v.histo.subdivide", dict(input="plots", aligned="houses", output="houses")),
    ("v.histo.align", dict(input="plots", footprints="houses", year=1950, output="houses")),
    ("v.histo.generalize", dict(input="plots", output="plots")),
])
def test_no_map_output_replaces_an_input_map(small, module, options):
    gs, grassio = small
    before = {name: grassio.vector_counts(name) for name in ("plots", "houses")}
    output = options["output"]
    fails(module, "Option output= names the input <{}>".format(output), overwrite=True,
          **options)
    assert {name: grassio.vector_counts(name) for name in ("plots", "houses")} == before


def test_an_input_of_another_mapset_may_share_its_output_name(small):
    """An output of the input's name replaces nothing when the input is
    read from another mapset (as GRASS's own modules allow)."""
    gs, grassio = small
    mapset = gs.gisenv()["MAPSET"]
    code, _, err = run_module("v.histo.subdivide", input="plots@" + mapset, output="fp1",
                              quiet=True)
    assert code == 0, err
    other = mapset + "_other"
    gs.run_command("g.mapset", mapset=other, flags="c", quiet=True)
    try:
        code, _, err = run_module("v.histo.subdivide", input="fp1@" + mapset,
                                  output="fp1", quiet=True)
        assert code == 0, err
        assert grassio.vector_counts("fp1@" + other)["areas"] > 0
    finally:
        gs.run_command("g.mapset", mapset=mapset, quiet=True)
        env = gs.gisenv()
        shutil.rmtree(os.path.join(env["GISDBASE"], env["LOCATION_NAME"], other),
                      ignore_errors=True)


# ---------------------------------------------------------------------------
# Issue 33, items 1 and 2: a broken existing model
# ---------------------------------------------------------------------------

def house_model(broken=None, sequence=False, transform=None):
    """The existing model of the first three ``houses`` of ``small`` (12 x 12 m
    cubes in BuildingParts, as the 3D BAG has them): house k is building
    "h<k>"; ``broken``: house -> function changing its objects (ids, objects,
    its vertices' count) in place."""
    faces = [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]]
    semantics = {"surfaces": [{"type": "GroundSurface"}, {"type": "RoofSurface"},
                              {"type": "WallSurface"}], "values": [[0, 1, 2, 2, 2, 2]]}
    head = {"type": "CityJSON", "version": "2.0",
            "transform": transform or {"scale": [0.001] * 3, "translate": [X0, Y0, 0.0]},
            "CityObjects": {}, "vertices": []}
    features = []
    for k in range(3):
        x, y = (k * 60 + 2) * 1000, 2000
        vertices = [[x + dx, y + dy, z] for z in (0, 6000)
                    for dx, dy in ((0, 0), (12000, 0), (12000, 12000), (0, 12000))]
        shift = 0 if sequence else 8 * k
        objects = {"h{}".format(k): {"type": "Building", "children": ["h{}-0".format(k)]},
                   "h{}-0".format(k): {"type": "BuildingPart", "parents": ["h{}".format(k)],
                                       "geometry": [{"type": "Solid", "lod": "2.2",
                                                     "boundaries": [[[[i + shift for i in f]]
                                                                     for f in faces]],
                                                     "semantics": semantics}]}}
        if broken and k in broken:
            broken[k](objects)
        features.append((objects, vertices))
    if sequence:
        lines = [head] + [{"type": "CityJSONFeature", "id": "h{}".format(k), "CityObjects": o,
                           "vertices": v} for k, (o, v) in enumerate(features)]
        return "\n".join(json.dumps(line) for line in lines) + "\n"
    for objects, vertices in features:
        head["CityObjects"].update(objects)
        head["vertices"].extend(vertices)
    return json.dumps(head)


def _index(value):
    def change(objects):
        part = [o for o in objects.values() if o["type"] == "BuildingPart"][0]
        part["geometry"][0]["boundaries"][0][1][0][0] = value
    return change


def _no_child(objects):
    del objects[[k for k in objects if k.endswith("-0")][0]]


@pytest.mark.parametrize("sequence", [False, True])
def test_a_broken_building_of_the_existing_model_is_left_out_and_named(small, tmp_path,
                                                                       sequence):
    """House 1's roof points past its vertices (in a sequence: at the next
    feature's), house 2 has lost its part: both are named, their footprints
    generated; house 0 is copied and checked (-v counts it)."""
    path = tmp_path / ("bag.city.jsonl" if sequence else "bag.city.json")
    path.write_text(house_model({1: _index(8 if sequence else 24), 2: _no_child}, sequence))
    out = tmp_path / "m.json"
    code, stdout, err = run_module("v.histo.lod2", flags="v", input="houses", output=str(out),
                                   existing=str(path))
    assert code == 0, err
    assert "Traceback" not in err
    said = " ".join(err.split())
    assert "2 buildings of the existing model" in said and "broken and left out" in said
    assert "<h1>: <h1-0>, geometry 0 (Solid, lod 2.2): vertex index {} is past its {} " \
           "vertices".format(8 if sequence else 24, 8 if sequence else 24) in said
    assert "<h2>: its child \"h2-0\" is not in the model" in said
    assert "1 of 4 aligned footprints copied" in said
    rep = dict(line.split("=", 1) for line in stdout.splitlines() if "=" in line)
    assert (rep["solids"], rep["valid"], rep["copied_solids"], rep["copied_valid"]) == \
        ("4", "4", "1", "1")
    doc = json.loads(out.read_text())
    buildings = [k for k, o in doc["CityObjects"].items() if o["type"] == "Building"]
    assert len(buildings) == 4 and "h0" in buildings and "h1" not in buildings


def test_an_existing_model_of_scale_zero_is_refused(small, tmp_path):
    path = tmp_path / "bag.city.json"
    path.write_text(house_model(transform={"scale": [0, 0, 0], "translate": [X0, Y0, 0]}))
    fails("v.histo.lod2", "the scale of its transform must be three positive numbers",
          input="houses", output=str(tmp_path / "m.json"), existing=str(path))
    assert os.listdir(str(tmp_path)) == ["bag.city.json"]


# ---------------------------------------------------------------------------
# Issue 33, items 5 and 8: reference systems that cannot be the location's
# ---------------------------------------------------------------------------

def test_a_geographic_crs_is_refused_and_another_place_warned_about(small, tmp_path):
    fails("v.histo.lod2", "crs=EPSG:4326 is a geographic reference system", input="houses",
          output=str(tmp_path / "m.json"), crs=4326)
    assert os.listdir(str(tmp_path)) == []
    code, _, err = run_module("v.histo.lod2", input="houses", output=str(tmp_path / "m.json"),
                              crs=3857)
    assert code == 0 and "crs=EPSG:3857 is not the location's EPSG:28992" in " ".join(
        err.split()), err


def test_a_model_in_longitude_and_latitude_that_claims_rd_is_refused(small, tmp_path):
    path = tmp_path / "bag.city.json"
    doc = json.loads(house_model(transform={"scale": [1e-7, 1e-7, 0.001],
                                            "translate": [4.36, 52.01, 0.0]}))
    doc["metadata"] = {"referenceSystem": "https://www.opengis.net/def/crs/EPSG/0/7415"}
    path.write_text(json.dumps(doc))
    gs, grassio = small
    houses, _ = grassio.read_features("houses", "area")
    grassio.write_features("bag_houses", houses, {"pand_id": ["h0", "h1", "h2", "h3"]})
    fails("v.histo.lod2", "look like longitude and latitude", input="bag_houses",
          output=str(tmp_path / "m.json"), existing=str(path), id_column="pand_id")
    assert os.listdir(str(tmp_path)) == ["bag.city.json"]
