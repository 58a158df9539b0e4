"""The suite installs with one offline g.extension call and its modules then run.

This is what a GRASS user does (README, "Install"): it must work from a
checkout with no network, put every module, its manual and the shared core
library in place, and the installed modules must find that library.
"""

import os
import shutil
import subprocess

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MODULES = ["r.histo.classify", "v.histo.generalize", "v.histo.subdivide", "v.histo.lod2"]


def _grass(args, env, **kwargs):
    return subprocess.run(["grass"] + args, env=env, capture_output=True, text=True, **kwargs)


@pytest.fixture(scope="module")
def installed(tmp_path_factory):
    if not shutil.which("grass"):
        pytest.skip("GRASS GIS is not installed (run the tests through `make test`)")
    tmp = tmp_path_factory.mktemp("gext")
    addons = tmp / "addons"
    env = dict(os.environ, GRASS_ADDON_BASE=str(addons))
    env.pop("GISRC", None)
    # the suite's own scripts must not come from the staged dist/ on PATH
    env["PATH"] = os.pathsep.join(p for p in env["PATH"].split(os.pathsep) if "dist" not in p)
    out = subprocess.run(["bash", os.path.join(ROOT, "tools", "g_extension_install.sh"), ROOT],
                         env=env, capture_output=True, text=True)
    assert out.returncode == 0, out.stderr[-3000:]
    location = tmp / "loc"
    made = _grass(["-c", "EPSG:28992", str(location), "-e"], env)
    assert made.returncode == 0, made.stderr
    return {"addons": addons, "env": env, "mapset": str(location / "PERMANENT")}


def test_every_module_script_and_manual_installed(installed):
    addons = installed["addons"]
    for module in MODULES:
        assert os.access(addons / "scripts" / module, os.X_OK), module
        page = (addons / "docs" / "html" / (module + ".html")).read_text()
        assert module in page and "DESCRIPTION" in page
    assert (addons / "etc" / "histo" / "reconstruction" / "grassio.py").is_file()
    assert (addons / "docs" / "html" / "histo.html").is_file()


def test_g_extension_lists_the_modules(installed):
    out = _grass([installed["mapset"], "--exec", "g.extension", "-a"], installed["env"])
    assert out.returncode == 0, out.stderr
    listed = set(out.stdout.split())
    assert set(MODULES) <= listed


def test_installed_module_finds_the_core_library(installed):
    """Each installed module resolves `reconstruction` from etc/histo, not the checkout."""
    code = ("import runpy, sys; sys.argv=['{m}']; g = runpy.run_path('{p}', run_name='x'); "
            "g['find_core'](); import reconstruction; print(reconstruction.__file__)")
    for module in MODULES:
        script = installed["addons"] / "scripts" / module
        out = _grass([installed["mapset"], "--exec", "python3", "-c",
                      code.format(m=module, p=script)], installed["env"], cwd="/")
        assert out.returncode == 0, out.stderr[-2000:]
        path = out.stdout.strip().splitlines()[-1]
        assert path.startswith(str(installed["addons"] / "etc" / "histo")), path
