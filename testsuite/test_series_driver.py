"""tools/histo_series.py after a kill or a failure, and with Debian's python3 (issue 49, item 12).

Sheets whose models are there and whose attempts progress.jsonl records as
done are not run again: the driver goes straight to the merge, so these
tests need no chain run (a GRASS location is made for the local fallback).
"""

import json
import os
import shutil
import subprocess
import sys

import pytest

from reconstruction.series import chain, manifest, progress
from reconstruction.testsuite.series.test_series import box_model

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DRIVER = os.path.join(ROOT, "tools", "histo_series.py")
TEMPLATE = os.path.join(ROOT, "demo", "series", "sheet_chain.json")
DEBIAN_PYTHON = "/usr/bin/python3"

pytestmark = pytest.mark.grass


@pytest.fixture
def finished(tmp_path):
    """A series of two sheets that finished: (manifest, output folder)."""
    if not shutil.which("grass"):
        pytest.skip("GRASS GIS is not installed")
    doc = {"sheets": [{"name": n, "map": n + ".bsq", "training": n + ".t.geojson",
                       "footprints": n + ".f.geojson", "year": 1900,
                       "extent": [k * 200, 0, (k + 1) * 200, 200]}
                      for k, n in enumerate(("a", "b"))]}
    path = tmp_path / "series.json"
    path.write_text(json.dumps(doc))
    series = manifest.read_manifest(str(path))
    template = chain.read_template(TEMPLATE)
    out = tmp_path / "out"
    done = progress.Progress(str(out / "progress.jsonl"))
    for k, sheet in enumerate(series.sheets):
        (out / sheet.name).mkdir(parents=True)
        box_model(str(out / sheet.name / "model.city.json"),
                  [("building_{}".format(k), k * 200000 + 10000, 10000, k * 200000 + 20000,
                    20000)])
        done.record(progress.Attempt(sheet.name, "done", 1, 1.0, progress.fingerprint(
            chain.process_chain(template, series, sheet).document)))
    return str(path), str(out)


def drive(python, manifest_path, out, env=None):
    return subprocess.run([python, DRIVER, manifest_path, out], capture_output=True, text=True,
                          timeout=300, env=dict(os.environ, **(env or {})))


def parts(out):
    return [os.path.join(d, n) for d, _, files in os.walk(out) for n in files
            if n.endswith(".part")]


@pytest.mark.skipif(not os.path.exists(DEBIAN_PYTHON), reason="no Debian python3")
def test_debians_python3_runs_the_series_with_the_suites_venv(finished):
    manifest_path, out = finished
    proc = drive(DEBIAN_PYTHON, manifest_path, out)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "2 of 2 sheets finished before" in proc.stdout
    with open(os.path.join(out, "series.city.jsonl")) as f:
        assert len(f.read().splitlines()) == 3          # the header and two buildings
    assert parts(out) == []


@pytest.mark.skipif(not os.path.exists(DEBIAN_PYTHON), reason="no Debian python3")
def test_without_the_suites_venv_one_error_line_and_nothing_written(finished, tmp_path):
    manifest_path, out = finished
    proc = drive(DEBIAN_PYTHON, manifest_path, out, {"HISTO_VENV": str(tmp_path / "none")})
    if proc.returncode == 0:
        pytest.skip("{} has the suite's packages".format(DEBIAN_PYTHON))
    assert proc.returncode == 2 and "Traceback" not in proc.stderr, proc.stderr
    assert proc.stderr.startswith("ERROR:") and "make venv" in proc.stderr
    assert not os.path.exists(os.path.join(out, "series.city.jsonl")) and parts(out) == []


def test_a_failed_merge_leaves_no_part_file(finished):
    manifest_path, out = finished
    with open(os.path.join(out, "b", "model.city.json"), "w") as f:
        f.write('{"type": "CityJSON", "CityObjects": ')          # cut short
    proc = drive(sys.executable, manifest_path, out)
    assert proc.returncode == 2 and proc.stderr.startswith("ERROR:"), proc.stderr
    assert "Traceback" not in proc.stderr
    assert parts(out) == []


def test_the_mapsets_and_part_files_a_killed_run_left_are_removed(finished):
    manifest_path, out = finished
    location = os.path.join(out, "grassdb", "series")
    assert drive(sys.executable, manifest_path, out).returncode == 0
    left = os.path.join(location, "a_4242_139861")          # as run_local names them
    os.makedirs(os.path.join(left, "cell"))
    with open(os.path.join(left, "WIND"), "w") as f:
        f.write("north: 1\n")
    for path in (os.path.join(out, "series.city.jsonl.part"),
                 os.path.join(out, "a", "model.city.json.part")):
        with open(path, "w") as f:
            f.write("cut short")
    proc = drive(sys.executable, manifest_path, out)
    assert proc.returncode == 0, proc.stderr
    assert "removed 1 mapset(s) a killed run left: a_4242_139861" in proc.stdout
    assert os.listdir(location) == ["PERMANENT"]
    assert parts(out) == []
