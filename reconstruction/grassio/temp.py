"""Temporary maps and files, and outputs written under a temporary name.

Every temporary map (:func:`temp_map`, named ``tmp_histo_*``) and temporary
directory (:func:`temp_file`) is removed at exit, after success, failure,
Ctrl-C and SIGTERM alike (:func:`reconstruction.grassio.run.run_main` turns
SIGTERM into an interruption, so the exit handlers run). An output map is
written under a temporary name and renamed into place only when complete
(:func:`staged`, used by grassio's writers): an interruption or a failure
leaves no partial output, only a temporary map that the clean-up removes
(issue 12, item 5). Before removing anything, the clean-up stops the GRASS
tools the module started that still run (after SIGTERM, or an error while
they ran in the background), so that none of them writes a map after it.
Re-exported by :mod:`reconstruction.grassio.maps`.
"""

import atexit
import contextlib
import os
import shutil
import signal
import subprocess
import tempfile
import threading
import time

import grass.script as gs

from ..core.errors import InputError
from . import run as grassrun
from .run import doing, finish_tool

_TEMP_MAPS = {"raster": set(), "vector": set()}
_TEMP_FILES = set()
_CLEANUP_REGISTERED = []
#: staged temporary map -> the output it becomes (see staged)
_STAGED = {}


def _children(pid):
    """Process ids of the children of ``pid`` (Linux /proc; empty elsewhere)."""
    kids = []
    try:
        for task in os.listdir("/proc/{}/task".format(pid)):
            with open("/proc/{}/task/{}/children".format(pid, task)) as f:
                kids.extend(int(k) for k in f.read().split())
    except OSError:
        pass
    return kids


def _running(pid):
    """True while process ``pid`` runs (not ended, not a zombie)."""
    try:
        with open("/proc/{}/stat".format(pid)) as f:
            return f.read().rsplit(")", 1)[1].split()[0] != "Z"
    except (OSError, IndexError):
        return False


def stop_children(timeout=5.0):
    """Stop (SIGTERM) every process this one started that still runs, with
    their own children, and wait for them (at most ``timeout`` seconds)."""
    found, todo = [], _children(os.getpid())
    while todo:
        pid = todo.pop()
        found.append(pid)
        todo.extend(_children(pid))
    for pid in found:
        with contextlib.suppress(OSError):
            os.kill(pid, signal.SIGTERM)
    end = time.monotonic() + timeout
    for pid in found:
        while time.monotonic() < end:
            with contextlib.suppress(OSError):   # reap our own children
                os.waitpid(pid, os.WNOHANG)
            if not _running(pid):
                break
            time.sleep(0.02)


def _cleanup(at_exit=False):
    """Remove the temporary maps and files. At the exit of a module (run by
    :func:`~reconstruction.grassio.run.run_main`): uninterrupted, and after
    stopping the tools it started."""
    if at_exit and grassrun.RUNNING:
        if threading.current_thread() is threading.main_thread():
            # a second Ctrl-C must not interrupt the clean-up of the first
            signal.signal(signal.SIGINT, signal.SIG_IGN)
            signal.signal(signal.SIGTERM, signal.SIG_IGN)
        stop_children()
    for kind, names in _TEMP_MAPS.items():
        if names and os.environ.get("GISRC"):
            # silent: names of maps never made (a failure came first) only give
            # warnings after the module's ERROR: line
            gs.run_command(
                "g.remove", flags="f", type=kind, name=",".join(sorted(names)),
                quiet=True, errors="ignore", stderr=subprocess.DEVNULL,
            )
            names.clear()
    for path in list(_TEMP_FILES):
        shutil.rmtree(path, ignore_errors=True)
        _TEMP_FILES.discard(path)


def _ensure_cleanup():
    if not _CLEANUP_REGISTERED:
        atexit.register(_cleanup, at_exit=True)
        _CLEANUP_REGISTERED.append(True)


def register_cleanup():
    """Register removal of every temporary map and file at exit.

    Call right after ``gs.parser()``; temporary names made by
    :func:`temp_map` and :func:`temp_file` are then removed on success and on
    failure alike.
    """
    _ensure_cleanup()


def temp_map(kind, prefix):
    """A unique temporary map name of ``kind`` (raster or vector), removed at exit."""
    _ensure_cleanup()
    name = gs.append_uuid("tmp_histo_{}".format(prefix)).replace("-", "_")
    _TEMP_MAPS[kind].add(name)
    return name


def is_temp_map(kind, name):
    """True when ``name`` is a temporary map made by :func:`temp_map`."""
    return name in _TEMP_MAPS[kind]


def temp_file(suffix=""):
    """A path for a temporary file (not created yet), removed at exit."""
    _ensure_cleanup()
    directory = tempfile.mkdtemp(prefix="histo_")
    _TEMP_FILES.add(directory)
    return os.path.join(directory, "data" + suffix)


def forget_temp_map(kind, name):
    """Keep a temporary map (e.g. after renaming it to a real output)."""
    _TEMP_MAPS[kind].discard(name)


@contextlib.contextmanager
def uninterrupted():
    """SIGINT and SIGTERM wait until the block ends (an output renamed into
    place): the module then ends as interrupted, with its output complete.
    The GRASS tools started inside inherit the blocked signals."""
    if threading.current_thread() is not threading.main_thread() or \
            not hasattr(signal, "pthread_sigmask"):
        yield
        return
    old = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT, signal.SIGTERM})
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, old)


def output_name(name):
    """The output that map ``name`` becomes when it is staged, else ``name`` (for messages)."""
    return _STAGED.get(name, name)


def rename_map(kind, temporary, name):
    """Rename temporary map ``temporary`` to ``name`` (replacing it: see
    :func:`staged` for the check of --overwrite), and keep it."""
    with doing("renaming <{}> to the output <{}>".format(temporary, name)):
        finish_tool(gs.start_command("g.rename", quiet=True, overwrite=True, stderr=gs.PIPE,
                                     **{kind: "{},{}".format(temporary, name)}), "g.rename")
    forget_temp_map(kind, name)
    forget_temp_map(kind, temporary)


@contextlib.contextmanager
def staged(kind, name, before=None, after=None):
    """``with staged("vector", output) as tmp:`` write and complete map ``tmp``;
    it becomes ``name`` when the block ends without an exception (a temporary
    map, removed at exit, otherwise). ``name`` already temporary: used as is.
    ``before(tmp)``, ``after(name)``: run just before and after the renaming,
    all three uninterrupted (see :func:`uninterrupted`)."""
    name = name.split("@")[0]
    if is_temp_map(kind, name):
        yield name
        return
    if not gs.overwrite() and gs.find_file(
            name, element="cell" if kind == "raster" else kind, mapset=".")["name"]:
        raise InputError("{} map <{}> exists; use --overwrite to replace it".format(
            kind.capitalize(), name))
    temporary = temp_map(kind, "out")
    _STAGED[temporary] = name
    yield temporary
    with uninterrupted():
        if before:
            before(temporary)
        rename_map(kind, temporary, name)
        if after:
            after(name)
