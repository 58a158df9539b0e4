"""The one error convention (grassio.run_main, doing, failure_message), in a GRASS session."""

import os
import signal
import time

import pytest

pytestmark = pytest.mark.grass


@pytest.fixture
def run(grass_session):
    """grassio, with SIGTERM's handler put back after the test (run_main installs one)."""
    from reconstruction import grassio

    import sys

    handler = signal.getsignal(signal.SIGTERM)
    hook = sys.unraisablehook
    yield grassio
    signal.signal(signal.SIGTERM, handler)
    sys.unraisablehook = hook


def _fails(grassio, capfd, main, *args):
    """Run main through run_main: it must exit 1 with an ERROR: message, no traceback.

    Returns the last message from its ERROR: on, on one line (g.message wraps
    long lines).
    """
    with pytest.raises(SystemExit) as ended:
        grassio.run_main(main, *args)
    assert ended.value.code == 1
    err = capfd.readouterr().err
    assert "Traceback" not in err
    assert "ERROR:" in err, err
    return "ERROR: " + " ".join(err.rsplit("ERROR:", 1)[1].split())


def _run_script(script, grass_session):
    """Run ``script`` in a Python process of its own with the suite and GRASS on
    its path, standard output block-buffered as in a pipe; its output and
    messages together in ``stdout``."""
    import subprocess
    import sys

    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(
        os.path.abspath(__file__)))))
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(
        [root, os.path.join(grass_session["gisbase"], "etc", "python")]))
    env.pop("PYTHONUNBUFFERED", None)
    return subprocess.run([sys.executable, "-c", script], env=env, stdout=subprocess.PIPE,
                          stderr=subprocess.STDOUT, text=True, timeout=60)


def test_run_main_passes_arguments_and_returns_the_result(run):
    assert run.run_main(lambda options, flags: (options["a"], flags["b"]), {"a": 1}, {"b": 2}) == (1, 2)


def test_standard_output_keeps_its_place_among_the_messages_in_a_log(run, grass_session):
    """A module's printed figures and its messages to one pipe, as `make demo
    > log 2>&1` has them: in the order the module wrote them (issue 33, item
    10: block-buffered, the figures came out at the exit, after every later
    message)."""
    script = ("import sys\n"
              "from reconstruction import grassio\n"
              "from reconstruction.core.messages import note\n"
              "def main():\n"
              "    print('figure=1')\n"
              "    grassio.say([note('said after the figure')])\n"
              "    return 0\n"
              "sys.exit(grassio.run_main(main))\n")
    out = _run_script(script, grass_session)
    assert out.returncode == 0, out.stdout
    lines = out.stdout.splitlines()
    assert lines.index("figure=1") < lines.index("said after the figure"), lines


def test_an_object_an_interruption_caught_half_made_prints_nothing(run, grass_session):
    """SIGTERM while grass.script.array made its temporary file: the half-made
    object's __del__ failed as it was released and Python printed its
    traceback beside the ERROR: line (a test of r.histo.classify's clean-up
    failed on it once in CI). In a process of its own: pytest catches such
    exceptions itself."""
    script = ("import sys\n"
              "from reconstruction import grassio\n"
              "class HalfMade:\n"
              "    def __del__(self):\n"
              "        return self.filename\n"
              "def main():\n"
              "    half = HalfMade()\n"
              "    raise KeyboardInterrupt\n"
              "sys.exit(grassio.run_main(main))\n")
    out = _run_script(script, grass_session)
    assert out.returncode == 1, out.stdout
    assert "ERROR: Interrupted" in out.stdout, out.stdout
    assert "Traceback" not in out.stdout and "Exception ignored" not in out.stdout, out.stdout


@pytest.mark.parametrize("interruption, said", [("grassio.run.Terminated", "Terminated"),
                                                  ("KeyboardInterrupt", "Interrupted")])
def test_an_interruption_that_arrives_while_a_process_forks_still_ends_the_module(
        run, grass_session, interruption, said):
    """SIGTERM or Ctrl-C arriving in the callbacks that run after a fork
    (logging's lock release as a process pool starts its workers): Python
    printed "Exception ignored" and v.histo.lod2 ran on to the end, replacing
    the old model (CI, test_robustness). The interruption is raised again:
    the module ends with its one ERROR: line and never reaches its end."""
    script = ("import os, sys, time\n"
              "from reconstruction import grassio\n"
              "def interrupted():\n"
              "    raise {}()\n"
              "def main():\n"
              "    os.register_at_fork(after_in_parent=interrupted)\n"
              "    child = os.fork()\n"
              "    if child == 0:\n"
              "        os._exit(0)\n"
              "    os.waitpid(child, 0)\n"
              "    for _ in range(100):\n"
              "        time.sleep(0.01)\n"
              "    print('ran to the end')\n"
              "    return 0\n"
              "sys.exit(grassio.run_main(main))\n").format(interruption)
    out = _run_script(script, grass_session)
    assert out.returncode == 1, out.stdout
    assert "ERROR: " + said in out.stdout, out.stdout
    assert "ran to the end" not in out.stdout and "Traceback" not in out.stdout, out.stdout


def test_input_error_is_one_error_line(run, capfd):
    from reconstruction.core.errors import InputError

    def main():
        with run.doing("reading the plots"):
            raise InputError("Option alpha= must be above 0 (got -1)")

    assert _fails(run, capfd, main) == "ERROR: Option alpha= must be above 0 (got -1)"


def test_failing_tool_says_what_the_module_was_doing(run, capfd):
    import grass.script as gs

    def main():
        with run.doing("reading the plots <p>"):
            with run.doing("setting the region"):
                gs.run_command("g.region", raster="no_such_map_here", quiet=True)

    line = _fails(run, capfd, main)
    assert line == ("ERROR: GRASS tool g.region failed (return code 1) while setting the region")


def test_failing_started_tool_gives_its_error_output_on_the_line(run, capfd):
    import grass.script as gs

    def main():
        proc = gs.start_command("g.region", raster="no_such_map_here", stderr=gs.PIPE)
        with run.doing("checking the region"):
            run.finish_tool(proc, "g.region")

    line = _fails(run, capfd, main)
    assert line.startswith("ERROR: GRASS tool g.region failed (return code 1) while checking "
                           "the region: ")
    assert "no_such_map_here" in line


def test_failure_handled_inside_leaves_no_stale_context(run):
    from grass.exceptions import CalledModuleError

    try:
        with run.doing("trying something"):
            raise CalledModuleError("g.fake", "g.fake", 1)
    except CalledModuleError:
        pass
    error = CalledModuleError("g.other", "g.other", 2)
    assert run.failure_message(error) == "GRASS tool g.other failed (return code 2)"


def test_failure_messages_of_each_kind(run):
    def marked(error, what):
        try:
            with run.doing(what):
                raise error
        except BaseException as caught:  # noqa: B902 - the point of the test
            return caught

    assert run.failure_message(marked(KeyboardInterrupt(), "writing <x>")) == \
        "Interrupted while writing <x>"
    assert run.failure_message(marked(run.Terminated(), "writing <x>")) == \
        "Terminated (SIGTERM) while writing <x>"
    assert run.failure_message(MemoryError()) == "Out of memory"
    assert run.failure_message(marked(FileNotFoundError(2, "No such file", "/no/x.json"),
                                      "writing the report")) == \
        "[Errno 2] No such file: '/no/x.json' while writing the report"
    assert run.failure_message(RuntimeError("a bug")) is None


def test_other_exceptions_are_bugs_and_keep_their_traceback(run):
    def main():
        raise RuntimeError("a bug")

    with pytest.raises(RuntimeError):
        run.run_main(main)


def test_sigterm_ends_like_an_interruption(run, capfd):
    def main():
        with run.doing("waiting"):
            os.kill(os.getpid(), signal.SIGTERM)
            time.sleep(30)

    start = time.perf_counter()
    assert _fails(run, capfd, main) == "ERROR: Terminated (SIGTERM) while waiting"
    assert time.perf_counter() - start < 10


def _sleep(seconds):
    time.sleep(seconds)
    return seconds


def test_pool_workers_ended_by_the_pool_print_no_traceback(run, capfd):
    # a pool ends its (forked) workers with SIGTERM; they inherit run_main's
    # handler, which must let them end quietly rather than raise Terminated
    import multiprocessing

    def main():
        with multiprocessing.get_context("fork").Pool(2) as pool:
            pool.map_async(_sleep, [5, 5])
            time.sleep(0.5)     # the workers are sleeping when the pool ends them
        return 0

    assert run.run_main(main) == 0
    err = capfd.readouterr().err
    assert "Traceback" not in err and "Terminated" not in err, err
