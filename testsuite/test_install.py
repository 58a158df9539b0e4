"""The suite installs with one offline g.extension call and its modules then run.

This is what a GRASS user does (README, "Install in GRASS GIS"): it must work
from a checkout with no network, put every module, its manual and the shared
core library in place, and the installed modules must find that library.
Both ways are tried: `tools/g_extension_install.sh` (`make install`) and the
README's snippet by hand, taken from README.md as it is written, in a new
user's home (no addon folder yet), followed by a new GRASS session in which
the modules run with the checkout's virtual environment.
"""

import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MODULES = ["r.histo.classify", "v.histo.generalize", "v.histo.align", "v.histo.subdivide",
           "v.histo.lod2", "v.histo.timeline"]
PLACEHOLDER = "/path/to/histo-checkout"
# a user's PATH with no python3 but Debian's (no pyenv, no venv, no dist/)
PLAIN_PATH = "/usr/sbin:/usr/bin:/sbin:/bin"


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
    assert (addons / "docs" / "html" / "histo.html").is_file()


def test_every_library_package_installed_without_its_tests(installed):
    """The library's packages and sub-packages (lod2/roofs/, ...) are all
    installed, file for file, and its tests are not."""
    library = Path(ROOT) / "reconstruction"
    wanted = sorted(str(p.relative_to(library)) for p in library.rglob("*.py")
                    if "testsuite" not in p.parts)
    lib = installed["addons"] / "etc" / "histo" / "reconstruction"
    present = sorted(str(p.relative_to(lib)) for p in lib.rglob("*.py"))
    assert "lod2/roofs/skeleton.py" in wanted and "grassio/__init__.py" in wanted
    assert present == wanted


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


def readme_snippet():
    """The shell snippet of the README's "Install in GRASS GIS" that runs g.extension."""
    with open(os.path.join(ROOT, "README.md")) as f:
        text = f.read()
    section = text.split("\n## Install in GRASS GIS\n", 1)[1].split("\n## ", 1)[0]
    blocks = [b for b in re.findall(r"```sh\n(.*?)```", section, re.S) if "g.extension" in b]
    assert len(blocks) == 1, "the README's install section has one g.extension snippet"
    return blocks[0]


def _venv():
    """The virtual environment with the suite's packages that these tests run in."""
    if sys.prefix == sys.base_prefix:
        pytest.skip("not run in the virtual environment of `make deps` (run `make test`)")
    return sys.prefix


def _user_env(home):
    """A new user's environment: only HOME, a plain PATH and a locale."""
    return {"HOME": str(home), "PATH": PLAIN_PATH, "LANG": "C.UTF-8"}


@pytest.fixture(scope="module")
def by_hand(tmp_path_factory):
    """The README's snippet run as written in a GRASS session of a new user."""
    if not shutil.which("grass"):
        pytest.skip("GRASS GIS is not installed (run the tests through `make test`)")
    venv = _venv()
    home = tmp_path_factory.mktemp("home")
    env = _user_env(home)
    made = _grass(["-c", "EPSG:28992", str(home / "grassdata" / "rd"), "-e"], env)
    assert made.returncode == 0, made.stderr
    mapset = str(home / "grassdata" / "rd" / "PERMANENT")
    # the venv where the README says `make deps` makes it, in this user's home
    user_venv = home / ".local" / "share" / "histo" / "venv"
    user_venv.parent.mkdir(parents=True)
    user_venv.symlink_to(venv)
    snippet = readme_snippet()
    assert PLACEHOLDER in snippet
    snippet = snippet.replace(PLACEHOLDER, ROOT)
    run = _grass([mapset, "--exec", "bash", "-e", "-c", snippet], env)
    assert run.returncode == 0, run.stdout[-2000:] + run.stderr[-3000:]
    addons = home / ".grass8" / "addons"
    assert (addons / "scripts" / "v.histo.lod2").is_file()
    return {"home": home, "env": env, "mapset": mapset, "venv": str(user_venv), "addons": addons,
            "install": run}


def test_readme_snippet_lists_the_modules_in_a_new_session(by_hand):
    out = _grass([by_hand["mapset"], "--exec", "g.extension", "-a"], by_hand["env"])
    assert out.returncode == 0, out.stderr
    assert set(MODULES) <= set(out.stdout.split())


def test_readme_snippet_offline_warnings_are_the_ones_it_explains(by_hand):
    """The README says the offline install warns once per module about GitHub."""
    warnings = [line for line in by_hand["install"].stderr.splitlines()
                if line.startswith("WARNING")]
    assert all("Download file from" in line for line in warnings), warnings


def test_new_session_runs_an_installed_module_with_the_venv(by_hand, tmp_path):
    """A new session of that user: python3 is the venv's and a module really runs."""
    env = by_hand["env"]
    where = _grass([by_hand["mapset"], "--exec", "bash", "-c",
                    "command -v python3; command -v v.histo.lod2; echo $GRASS_PYTHON"], env)
    assert where.returncode == 0, where.stderr
    python3, module, grass_python = where.stdout.split()[:3]
    assert python3 == os.path.join(by_hand["venv"], "bin", "python3")
    assert module == str(by_hand["addons"] / "scripts" / "v.histo.lod2")
    assert grass_python == "/usr/bin/python3"
    # an L-shaped footprint: its hip roof needs pySVCGAL, from the venv
    ascii_map = ("B 7\n0 0\n20 0\n20 8\n8 8\n8 20\n0 20\n0 0\nC 1 1\n4 4\n1 1\n")
    model = tmp_path / "l.city.json"
    script = ("v.in.ascii -n format=standard input=- output=l <<'EOF'\n" + ascii_map + "EOF\n"
              "v.histo.lod2 input=l output={} height=8,8 attic=4,4 roof=hip\n").format(model)
    run = _grass([by_hand["mapset"], "--exec", "bash", "-e", "-c", script], env)
    assert run.returncode == 0, run.stderr[-3000:]
    city = json.loads(model.read_text())
    assert len(city["CityObjects"]) >= 1


def test_manual_readable_without_a_browser(by_hand):
    if not shutil.which("man"):
        pytest.skip("man is not installed (make deps installs man-db)")
    env = dict(by_hand["env"], MANPAGER="cat", PAGER="cat", MANWIDTH="80")
    out = _grass([by_hand["mapset"], "--exec", "g.manual", "-m", "v.histo.lod2"], env)
    assert out.returncode == 0, out.stderr
    assert "v.histo.lod2" in out.stdout and "NAME" in out.stdout
    assert "\\x" not in out.stdout  # test_docs.py checks every page's text
    assert (by_hand["addons"] / "docs" / "html" / "v.histo.lod2.html").is_file()


def test_make_install_tells_grass_sessions_about_the_venv_once(tmp_path):
    """tools/g_extension_install.sh with HISTO_VENV (make install) twice: one block."""
    if not shutil.which("grass"):
        pytest.skip("GRASS GIS is not installed (run the tests through `make test`)")
    venv = _venv()
    rc = tmp_path / ".grass8" / "bashrc"
    rc.parent.mkdir()
    rc.write_text("export MY_OWN=1\n")
    env = dict(_user_env(tmp_path), HISTO_VENV=venv)
    for _ in range(2):
        out = subprocess.run(["bash", os.path.join(ROOT, "tools", "g_extension_install.sh"), ROOT],
                             env=env, capture_output=True, text=True)
        assert out.returncode == 0, out.stderr[-3000:]
    lines = rc.read_text().splitlines()
    assert lines[0] == "export MY_OWN=1"
    assert lines.count("export PATH={}/bin:$PATH".format(venv)) == 1
    assert lines.count("export GRASS_PYTHON=/usr/bin/python3") == 1
