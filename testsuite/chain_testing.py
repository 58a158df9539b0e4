"""Running a chain script of demo/ (delft_1961.sh, brussels_1924.sh), or any
command, in a fresh GRASS location, for the chain tests (and the real maps'
acceptance, testsuite/test_maps_venice.py) and testsuite/benchmarks/bench_chain.py."""

import os
import subprocess

from test_demo import DIST, ROOT, _clean_env


def run_in_location(epsg, folder, command, timeout=1800):
    """Run ``command`` (a list) in a new EPSG:``epsg`` location under ``folder`` with
    the staged suite (DIST) on the module path, from the checkout's root.
    Returns the finished process (text output); raises when it fails."""
    location = os.path.join(str(folder), "grassdata", "chain")
    env = _clean_env()
    subprocess.run(["grass", "-c", "EPSG:{}".format(epsg), location, "-e"], check=True, env=env,
                   capture_output=True)
    env["GRASS_ADDON_BASE"] = DIST
    env["PATH"] = os.pathsep.join([os.path.join(DIST, "scripts"), os.path.join(DIST, "bin"),
                                   env["PATH"]])
    run = subprocess.run(["grass", os.path.join(location, "PERMANENT"), "--exec"] + command,
                         cwd=ROOT, env=env, capture_output=True, text=True, timeout=timeout)
    if run.returncode != 0:
        raise AssertionError("{} failed:\n{}\n{}".format(" ".join(command[:2]),
                                                          run.stdout[-3000:], run.stderr[-3000:]))
    return run


def run_chain(script, epsg, folder, shared_data, timeout=1800):
    """Run demo/``script`` in a new EPSG:``epsg`` location under ``folder`` (as
    :func:`run_in_location`); its outputs go to folder/out."""
    out = os.path.join(str(folder), "out")
    return run_in_location(epsg, folder, ["bash", os.path.join(ROOT, "demo", script), out,
                                          shared_data], timeout)
