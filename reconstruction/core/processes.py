"""Worker processes that do not outlive the module that started them.

A multiprocessing pool replaces a worker that ended with a new one, forked
from the pool's own handler thread. When a module is interrupted (Ctrl-C,
SIGTERM) while its pool works, a worker forked in that moment waits on the
pool's task queue for ever after the module has gone: it holds the module's
standard error open, so whoever reads it (a shell pipe, a test, actinia)
never sees the module end. :func:`forked_pool` gives each worker the
death signal of its parent (Linux ``prctl(PR_SET_PDEATHSIG)``): it is
killed when the thread that forked it ends, at the latest with the pool.
"""

import ctypes
import ctypes.util
import multiprocessing
import os
import signal

#: prctl option: the signal a process gets when its parent thread ends
PR_SET_PDEATHSIG = 1


def _die_with_parent(parent):
    """Pool initializer: SIGKILL when the forking thread ends; gone already if the
    module (``parent``) has ended before this worker started."""
    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6", use_errno=True)
        libc.prctl(PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)
    except (OSError, AttributeError):  # not Linux: as without it
        return
    if os.getppid() != parent:
        os._exit(1)


def forked_pool(processes):
    """A ``fork`` pool of ``processes`` workers that end with the module."""
    return multiprocessing.get_context("fork").Pool(
        processes, initializer=_die_with_parent, initargs=(os.getpid(),))
