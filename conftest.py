"""pytest set-up shared by every test of the suite.

Fixtures:
- ``shared_data``: the reference data folder ``../shared/data`` (skips with a
  clear message where it is absent, as in a user's clone);
- ``grass_session``: a GRASS session in a fresh temporary location
  (EPSG:28992) with the suite staged in ``dist/`` on the module path, for
  module tests; skips when GRASS is not installed.
- ``mapset``: a fresh mapset in that location for one test, made current.
- ``browser_page``: a page of Debian's headless chromium, offline, for the
  HTML viewer's tests (``testsuite/browser.py``; ``chromium``: the browser,
  started once per test file); skips when chromium or Playwright is missing.
"""

import os
import shutil
import subprocess
import sys
import uuid

import pytest
from hypothesis import settings

# Property tests draw the same examples on every run of `make test` (CI): a
# failure there is reproducible, not luck. Draw new ones while developing with
# `python3 -m pytest --hypothesis-profile=explore` (docs/developing.md).
settings.register_profile("ci", derandomize=True)
settings.register_profile("explore", derandomize=False)
settings.load_profile("ci")

ROOT = os.path.dirname(os.path.abspath(__file__))
DIST = os.environ.get("HISTO_DIST", os.path.join(ROOT, "dist"))
SHARED_DATA = os.path.abspath(os.path.join(ROOT, "..", "shared", "data"))
SCHEMAS = os.path.abspath(os.path.join(ROOT, "..", "shared", "schemas"))

# Modules run as `#!/usr/bin/env python3`: when the tests run in a virtual
# environment (`make test`: the checkout's .venv), the modules they start run
# with it too.
if sys.prefix != sys.base_prefix:
    _VENV_BIN = os.path.join(sys.prefix, "bin")
    if os.environ.get("PATH", "").split(os.pathsep)[0] != _VENV_BIN:
        os.environ["PATH"] = _VENV_BIN + os.pathsep + os.environ.get("PATH", "")

if ROOT not in sys.path:
    sys.path.insert(0, ROOT)
TESTSUITE = os.path.join(ROOT, "testsuite")
if TESTSUITE not in sys.path:
    sys.path.insert(0, TESTSUITE)


def pytest_configure(config):
    config.addinivalue_line("markers", "grass: needs GRASS GIS and the staged suite")
    config.addinivalue_line("markers", "acceptance: runs on the reference data in ../shared/data")
    config.addinivalue_line("markers", "browser: drives Debian's headless chromium (Playwright)")


def _need(path, what):
    if not os.path.exists(path):
        pytest.skip("{} not found at '{}': reference data is only beside the project "
                    "checkout (README.md, \"The two commands\", says how to lay it out)"
                    .format(what, path))
    return path


@pytest.fixture(scope="session")
def shared_data():
    return _need(SHARED_DATA, "reference data folder")


@pytest.fixture(scope="session")
def bag_sample(shared_data):
    """The real 3D BAG excerpt (../shared/data/3dbag_sample), or the test is skipped."""
    path = os.path.join(shared_data, "3dbag_sample")
    if not os.path.isdir(path):
        pytest.skip("the 3D BAG sample is not in '{}'".format(path))
    return path


@pytest.fixture(scope="session")
def schemas():
    return _need(SCHEMAS, "CityJSON schemas")


def _grass_gisbase():
    grass = shutil.which("grass")
    if not grass:
        return None
    out = subprocess.run([grass, "--config", "path"], capture_output=True, text=True)
    return out.stdout.strip() or None


@pytest.fixture(scope="session")
def grass_session(tmp_path_factory):
    """A GRASS session in a temporary EPSG:28992 location with the staged suite."""
    gisbase = _grass_gisbase()
    if not gisbase:
        pytest.skip("GRASS GIS is not installed (run the tests through `make test`)")
    if not os.path.isdir(os.path.join(DIST, "scripts")):
        pytest.skip("the suite is not built in dist/ (run the tests through `make test`)")
    dbase = str(tmp_path_factory.mktemp("grassdata"))
    location = "histo_test"
    subprocess.run(["grass", "-c", "EPSG:28992", os.path.join(dbase, location), "-e"],
                   check=True, capture_output=True)
    python_path = os.path.join(gisbase, "etc", "python")
    if python_path not in sys.path:
        sys.path.insert(0, python_path)
    os.environ["GRASS_ADDON_BASE"] = DIST
    os.environ["PATH"] = os.pathsep.join(
        [os.path.join(DIST, "scripts"), os.path.join(DIST, "bin"), os.environ["PATH"]])
    os.environ.pop("GRASS_OVERWRITE", None)
    import grass.script as gs
    import grass.script.setup  # noqa: F401  (8.2 needs the explicit import)

    gs.setup.init(dbase, location, "PERMANENT", grass_path=gisbase)
    yield {"gisbase": gisbase, "dbase": dbase, "location": location}
    gs.setup.finish()


@pytest.fixture
def mapset(grass_session):
    """A fresh mapset, current for the duration of one test."""
    import grass.script as gs

    name = "t_" + uuid.uuid4().hex[:8]
    gs.run_command("g.mapset", flags="c", mapset=name, quiet=True)
    yield name
    gs.run_command("g.mapset", mapset="PERMANENT", quiet=True)
    shutil.rmtree(os.path.join(grass_session["dbase"], grass_session["location"], name),
                  ignore_errors=True)


@pytest.fixture(scope="session")
def synthetic(grass_session):
    """The default synthetic historical map (seed 1, 600 x 600 px at 1 m) in PERMANENT.

    Written once per test session. Returns a namespace with the full names
    ``red``, ``green``, ``blue`` (``map.red@PERMANENT`` ...), ``training``,
    ``gt_points``, ``plots``, ``region`` (g.region keywords) and ``smap``, the
    :class:`synthetic_map.SyntheticMap` itself (arrays, plots, points). The map's
    region is also saved as the location's default region, so every fresh
    mapset (fixture ``mapset``) starts on it.
    """
    import types

    import grass.script as gs

    from synthetic_map import generate, write_to_grass

    current = gs.gisenv()["MAPSET"]
    if current != "PERMANENT":
        gs.run_command("g.mapset", mapset="PERMANENT", quiet=True)
    smap = generate(seed=1, size=600)
    names = write_to_grass(smap, "map")
    gs.run_command("g.region", flags="s", quiet=True, **smap.region())
    if current != "PERMANENT":
        gs.run_command("g.mapset", mapset=current, quiet=True)
    full = {key: name + "@PERMANENT" for key, name in names.items()}
    return types.SimpleNamespace(smap=smap, region=smap.region(), **full)


@pytest.fixture(scope="module")
def chromium():
    """Debian's chromium, headless and offline, shared by a test file's tests.

    Once per file, not per session: a start costs 0.3 s, and the browser
    should not hold its memory through the rest of a `make test` run.
    """
    import browser

    problem = browser.missing()
    if problem:
        pytest.skip(problem)
    with browser.launch() as started:
        yield started


@pytest.fixture
def browser_page(chromium):
    """A :class:`browser.BrowserPage` in a fresh context of ``chromium``, closed after the test."""
    import browser

    with browser.open_page(chromium) as page:
        yield page


# ---------------------------------------------------------------------------
# What was skipped, and why (issue 49, item 13)
# ---------------------------------------------------------------------------
# A skipped test is a defect unless the data it reads is truly absent: a
# fresh machine once skipped the map series' test because the Makefile never
# installed Redis, and CI passed. Every run prints what it skipped; with
# HISTO_STRICT_SKIPS=1 (`make test` sets it) a skip fails the run unless its
# reason names a path of the reference data (under ../shared) that does not
# exist. The reasons come from pytest.skip() calls, so a skip for absent data
# names the missing path (as conftest's own `_need` does).
_SKIPS = []
_SHARED = os.path.dirname(SHARED_DATA)


def _shared_paths(reason):
    """The paths under ../shared that a skip's reason names."""
    import re

    return re.findall(re.escape(_SHARED) + r"[^'\"\s,;:)]*", reason)


def skip_is_justified(reason):
    """True when ``reason`` names a path of the reference data that does not exist."""
    return any(not os.path.exists(p) for p in _shared_paths(reason))


def pytest_runtest_logreport(report):
    if report.skipped and not hasattr(report, "wasxfail"):
        reason = report.longrepr[2] if isinstance(report.longrepr, tuple) else str(report.longrepr)
        _SKIPS.append((report.nodeid, reason.replace("Skipped: ", "", 1)))


def _unjustified():
    return [(node, reason) for node, reason in _SKIPS if not skip_is_justified(reason)]


@pytest.hookimpl(tryfirst=True)
def pytest_sessionfinish(session, exitstatus):
    if os.environ.get("HISTO_STRICT_SKIPS") == "1" and _unjustified() and exitstatus == 0:
        session.exitstatus = 1


def pytest_terminal_summary(terminalreporter, exitstatus, config):
    write = terminalreporter.write_line
    terminalreporter.section("what was skipped ({} tests)".format(len(_SKIPS)))
    for node, reason in _SKIPS:
        write("{} {}: {}".format("data absent" if skip_is_justified(reason) else "SKIPPED",
                                 node, reason))
    bad = _unjustified()
    if bad and os.environ.get("HISTO_STRICT_SKIPS") == "1":
        write("{} tests skipped while what they need should be there (HISTO_STRICT_SKIPS=1: "
              "the run fails): install it or mend the test".format(len(bad)), red=True)
