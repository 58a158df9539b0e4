"""make test's rule on skips (conftest.py): a skip is justified only by absent reference data."""

import importlib.util
import os

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def _conftest():
    spec = importlib.util.spec_from_file_location("histo_root_conftest",
                                                  os.path.join(ROOT, "conftest.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_only_a_missing_path_of_the_reference_data_justifies_a_skip(tmp_path):
    c = _conftest()
    missing = os.path.join(c.SHARED_DATA, "no_such_map_{}".format(os.getpid()), "x.tif")
    assert c.skip_is_justified("the map is not at '{}'".format(missing))
    assert c.skip_is_justified("{} not found".format(missing))
    # the reasons of the series test on a machine where make forgot Redis, and
    # of a test whose data is there
    assert not c.skip_is_justified("not installed: redis-server (Debian redis-server)")
    assert not c.skip_is_justified("GRASS GIS is not installed (run the tests through `make test`)")
    assert not c.skip_is_justified("the data is not at '{}'".format(os.path.dirname(c.SHARED_DATA)))


def test_strict_skips_fail_the_session(monkeypatch):
    c = _conftest()
    c._SKIPS.extend([("t.py::a", "not installed: redis-server"),
                     ("t.py::b", "'{}' not found".format(os.path.join(c.SHARED_DATA, "nope.x")))])
    assert c._unjustified() == [("t.py::a", "not installed: redis-server")]

    class Session:
        exitstatus = 0

    monkeypatch.setenv("HISTO_STRICT_SKIPS", "1")
    session = Session()
    c.pytest_sessionfinish(session, 0)
    assert session.exitstatus == 1
    monkeypatch.setenv("HISTO_STRICT_SKIPS", "0")
    session = Session()
    c.pytest_sessionfinish(session, 0)
    assert session.exitstatus == 0
