"""How a module script runs: the one error convention of the suite.

The library raises :class:`~reconstruction.core.errors.InputError` with the message
a user should read; a GRASS tool that fails raises ``CalledModuleError``. A
module script ends with ``sys.exit(grassio.run_main(main, options, flags))``:
:func:`run_main` turns these, an interruption (Ctrl-C or SIGTERM) and running
out of memory into one ``ERROR:`` line (:func:`failure_message`) and exit
code 1, never a traceback. ``with grassio.doing("reading the plots <p>"):``
says what the module was doing when a tool failed. :func:`say` prints a
stage's report (:class:`~reconstruction.core.messages.Message` lines).
"""

import os
import signal
import sys
import threading

import grass.script as gs
from grass.exceptions import CalledModuleError

from ..core.errors import InputError


class doing:
    """Context manager naming what the module is doing, for the ``ERROR:`` line of a failure.

    ``with grassio.doing("reading the footprints <fp>"): ...`` -- a GRASS tool
    that fails inside ends the module with "ERROR: GRASS tool ... failed while
    reading the footprints <fp>" (see :func:`run_main`). The innermost context
    names the failure: the exception leaving it carries its text (attribute
    ``histo_doing``), so a failure caught and handled inside leaves no trace.
    """

    def __init__(self, what):
        self.what = what

    def __enter__(self):
        return self

    def __exit__(self, kind, error, traceback):
        if error is not None and not hasattr(error, "histo_doing"):
            try:
                error.histo_doing = self.what
            except AttributeError:  # an exception type without attributes
                pass
        return False


#: non-empty while :func:`run_main` runs a module (the clean-up at exit then also
#: stops the tools the module started, see reconstruction.grassio.temp)
RUNNING = []


class Terminated(KeyboardInterrupt):
    """SIGTERM, raised in the main thread by :func:`run_main`'s handler, so that
    the module ends and cleans up as after Ctrl-C."""


#: the process that runs the module (its forked workers inherit the handler)
_MODULE_PID = []


def _terminate(signum, frame):
    if _MODULE_PID and os.getpid() != _MODULE_PID[-1]:
        # a worker process (e.g. of a multiprocessing pool, which the pool ends
        # with SIGTERM): end quietly, as without the handler
        signal.signal(signal.SIGTERM, signal.SIG_DFL)
        os.kill(os.getpid(), signal.SIGTERM)
        return
    # a second SIGTERM must not interrupt the clean-up of the first
    signal.signal(signal.SIGTERM, signal.SIG_IGN)
    raise Terminated()


def _tool_errors(text):
    """A child tool's error output on one line, without its own ``ERROR:`` prefixes."""
    lines = [ln.strip() for ln in text.splitlines() if ln.strip()]
    return " ".join(ln[len("ERROR:"):].strip() if ln.startswith("ERROR:") else ln for ln in lines)


def failure_message(error):
    """One line for an exception that ends a module: what failed, and while doing what.

    None for an exception that is not a user-facing failure (a bug).
    """
    what = getattr(error, "histo_doing", None)
    while_doing = " while {}".format(what) if what else ""
    if isinstance(error, InputError):
        return str(error)
    if isinstance(error, CalledModuleError):
        tool = error.cmd if isinstance(error.cmd, str) and error.cmd else "a GRASS tool"
        detail = ""
        errors = getattr(error, "msg", "")
        if "See the following errors:" in errors:
            detail = _tool_errors(errors.split("See the following errors:", 1)[1])
        return "GRASS tool {} failed (return code {}){}{}".format(
            tool, error.returncode, while_doing, ": " + detail if detail else "")
    if isinstance(error, Terminated):
        return "Terminated (SIGTERM){}".format(while_doing)
    if isinstance(error, KeyboardInterrupt):
        return "Interrupted{}".format(while_doing)
    if isinstance(error, MemoryError):
        return "Out of memory{}".format(while_doing)
    if isinstance(error, OSError):
        return "{}{}".format(error, while_doing)
    return None


def _unheard(unraisable):
    """Drop an exception raised where it cannot propagate (a ``__del__``)."""


#: an interruption swallowed where exceptions cannot propagate, to raise again
_PENDING = []


def _raise_pending(signum, frame):
    """SIGALRM handler put in place by :func:`_redeliver`: raise the swallowed
    interruption."""
    signal.signal(signal.SIGALRM, signal.SIG_DFL)
    raise _PENDING.pop()


def _redeliver(unraisable, previous):
    """``sys.unraisablehook`` while a module runs: an interruption (Ctrl-C,
    SIGTERM) that arrived where Python can only print an exception, such as
    the callbacks that run after a fork (``logging``'s lock release when a
    process pool starts its workers), is raised again in the main thread at
    the next instruction that can raise it, instead of being lost with the
    module running on to the end. Anything else goes to ``previous``."""
    interrupted = isinstance(unraisable.exc_value, KeyboardInterrupt)
    if interrupted and _MODULE_PID and os.getpid() == _MODULE_PID[-1] and not _PENDING:
        _PENDING.append(unraisable.exc_value)
        signal.signal(signal.SIGALRM, _raise_pending)
        signal.setitimer(signal.ITIMER_REAL, 0.001)
        return
    previous(unraisable)


def run_main(main, *args):
    """Run a module's ``main(*args)``: the one place where failures become ``gs.fatal``.

    A module script ends with ``sys.exit(grassio.run_main(main, options, flags))``.
    :class:`~reconstruction.core.errors.InputError` (bad input), a failing child
    GRASS tool (``CalledModuleError``), an interruption (Ctrl-C, and SIGTERM,
    which this installs a handler for), an ``OSError`` (e.g. an output file
    that cannot be written) and running out of memory end in one ``ERROR:``
    line (:func:`failure_message`) and exit code 1, never a traceback;
    temporary maps and files are removed (atexit). Any other exception is a
    bug and keeps its traceback.

    Standard output is flushed line by line: what a module prints there
    (``-g`` figures, ``-v`` counts, ``-p`` tables) comes out where it is
    printed among its messages (standard error, unbuffered) also when both
    go to one log file, not only on a terminal.
    """
    if hasattr(sys.stdout, "reconfigure"):
        sys.stdout.reconfigure(line_buffering=True)
    if threading.current_thread() is threading.main_thread():
        _MODULE_PID.append(os.getpid())
        signal.signal(signal.SIGTERM, _terminate)
        # Ctrl-C is a KeyboardInterrupt again (the script's start-up handler exits at once)
        signal.signal(signal.SIGINT, signal.default_int_handler)
        previous = sys.unraisablehook
        sys.unraisablehook = lambda unraisable: _redeliver(unraisable, previous)
    RUNNING.append(main)
    try:
        return main(*args)
    except (InputError, CalledModuleError, KeyboardInterrupt, MemoryError, OSError) as error:
        message = failure_message(error)
        if isinstance(error, KeyboardInterrupt):
            # an object the interruption caught half made (grass.script.array's
            # temporary file, without its name yet) fails in __del__ when the
            # traceback releases it: noise after the one ERROR: line's cause
            sys.unraisablehook = _unheard
    # outside the except clause: the traceback (and the frames it holds, such
    # as generators of running tools) is released before the exit
    gs.fatal(message)


def finish_tool(proc, module, what=None):
    """Wait for a GRASS tool started with ``gs.start_command(..., stderr=gs.PIPE)``;
    raise ``CalledModuleError`` (with its error output) when it failed.

    Returns its standard output (bytes, or None when not piped).
    """
    out, err = proc.communicate()
    if proc.returncode != 0:
        raise CalledModuleError(module, what or module, proc.returncode,
                                errors=gs.decode(err or b"").strip() or None)
    return out


#: GRASS's printer of each message level
_PRINTERS = {"message": gs.message, "warning": gs.warning, "verbose": gs.verbose, "info": gs.info}


def say(messages):
    """Print a stage's report: each :class:`~reconstruction.core.messages.Message`
    with GRASS's printer of its level."""
    for m in messages:
        _PRINTERS[m.level](m.text)
