"""Worker processes end with the module that started them (core.processes)."""

import os
import subprocess
import sys
import time

import pytest

from reconstruction.core.processes import forked_pool

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))


def _square(x):
    return x * x


def test_the_pool_works():
    with forked_pool(2) as pool:
        assert pool.map(_square, range(5)) == [0, 1, 4, 9, 16]


def _alive(pid):
    try:
        with open("/proc/{}/stat".format(pid)) as f:
            return f.read().split()[2] != "Z"
    except FileNotFoundError:
        return False


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="prctl is Linux's")
def test_workers_end_when_the_module_ends_without_closing_its_pool():
    # a module that dies with its pool open while the workers are blocked (an
    # interrupted module whose new worker waits for ever on the lock of the task
    # queue that a killed worker held; here: asleep): its workers must not stay
    script = ("import os, sys, time; sys.path.insert(0, {!r})\n"
              "from reconstruction.core.processes import forked_pool\n"
              "pool = forked_pool(2)\n"
              "pool.map_async(time.sleep, [600, 600], chunksize=1)\n"
              "time.sleep(0.5)\n"
              "print(' '.join(str(p.pid) for p in pool._pool), flush=True)\n"
              "os._exit(0)\n").format(ROOT)
    out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                         timeout=60, check=True).stdout
    workers = [int(p) for p in out.split()]
    assert len(workers) == 2
    deadline = time.time() + 10
    while time.time() < deadline and any(_alive(p) for p in workers):
        time.sleep(0.05)
    assert not any(_alive(p) for p in workers)
