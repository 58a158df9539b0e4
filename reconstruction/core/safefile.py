"""Output files written whole or not at all (issue 12, items 5 and 6).

:func:`replacing` writes a file under a unique temporary name
(``tempfile.mkstemp``) in the directory of its target and renames it into
place (``os.replace``) only once it is complete: a failure or an interruption
leaves the target as it was and no temporary file, and no existing file is
ever taken for a temporary one. A symbolic link is written through: its
target gets the new content and the link stays. Something that is not a
regular file (a directory, a device such as ``/dev/full``, a named pipe) is
never replaced.

:func:`together` does the same for the several files of one run (issue 33,
item 3: a model and its picture): each is written under a temporary name,
and only when all are complete are they renamed into place, one after the
other with Ctrl-C and SIGTERM held back until the last rename is done. A
failure or an interruption at any moment before leaves every target as it
was. An output directory (3D Tiles, issue 52, item 2) is written the same
way, as a temporary directory beside it (:meth:`OutputFiles.reserve_dir`);
the directory it replaces is removed after the renames. Pure Python, no GRASS.
"""

import contextlib
import os
import shutil
import signal
import stat
import tempfile
import threading

from .errors import InputError


def target_of(path):
    """The file that writing ``path`` replaces: ``path`` itself, or the target of
    a symbolic link. Raises :class:`InputError` when that exists and is not a
    regular file."""
    target = os.path.realpath(path)
    if os.path.exists(target) and not os.path.isfile(target):
        raise InputError("'{}' exists and is not a regular file; it is not replaced".format(path))
    return target


def _mode(target):
    """The permissions of the new file: the replaced file's, else as ``open`` gives."""
    try:
        return stat.S_IMODE(os.stat(target).st_mode)
    except FileNotFoundError:
        umask = os.umask(0)
        os.umask(umask)
        return 0o666 & ~umask


class OutputFiles:
    """The files of one :func:`together` block: :meth:`reserve` gives the
    temporary name to write each target under."""

    def __init__(self):
        self._files = []         # (temporary name, target)
        self._replaced = []      # directories replaced, removed once all are in place

    def reserve(self, path, suffix=""):
        """A unique temporary file name beside ``path``'s target (ending in
        ``suffix``, e.g. ``".png"`` for a writer that goes by the extension),
        renamed over the target when the block ends. Raises :class:`InputError`
        naming ``path`` when its directory cannot hold it."""
        target = target_of(path)
        directory, name = os.path.split(target)
        if any(t == target for _tmp, t in self._files):
            raise InputError("'{}' is given twice as an output".format(path))
        try:
            fd, tmp = tempfile.mkstemp(prefix=".{}.".format(name), suffix=".part" + suffix,
                                       dir=directory)
        except OSError as error:
            raise InputError("Cannot write '{}': {}".format(
                path, error.strerror or error)) from None
        os.close(fd)
        self._files.append((tmp, target))
        return tmp

    def reserve_dir(self, path):
        """A new empty temporary directory beside ``path``, renamed to ``path`` when
        the block ends (a directory there is replaced, then removed). Raises
        :class:`InputError` when ``path`` is something else than a directory or
        its parent cannot hold it."""
        target = os.path.realpath(path)
        if os.path.exists(target) and not os.path.isdir(target):
            raise InputError("'{}' exists and is not a directory; it is not replaced".format(path))
        directory, name = os.path.split(target)
        if any(t == target for _tmp, t in self._files):
            raise InputError("'{}' is given twice as an output".format(path))
        try:
            tmp = tempfile.mkdtemp(prefix=".{}.".format(name), suffix=".part", dir=directory)
        except OSError as error:
            raise InputError("Cannot write '{}': {}".format(
                path, error.strerror or error)) from None
        self._files.append((tmp, target))
        return tmp

    def open(self, path, mode="w", encoding="utf-8", newline=None):
        """The file object of :meth:`reserve`'s temporary file of ``path``
        (``mode`` ``"w"`` or ``"wb"``; ``encoding`` and ``newline`` as for ``open``,
        text only): close it, e.g. in a ``with`` block, before the set ends."""
        text = {} if "b" in mode else {"encoding": encoding, "newline": newline}
        return open(self.reserve(path), mode, **text)

    def _commit(self):
        """Every file renamed into place, interruptions held back meanwhile."""
        with _signals_held():
            for tmp, target in self._files:
                os.chmod(tmp, _mode(target) | (0o111 if os.path.isdir(tmp) else 0))
                if os.path.isdir(tmp) and os.path.isdir(target):
                    # a directory is renamed over an empty one only: the old one aside first
                    old = tempfile.mkdtemp(prefix=".{}.".format(os.path.basename(target)),
                                           suffix=".old", dir=os.path.dirname(target))
                    os.replace(target, old)
                    self._replaced.append(old)
                os.replace(tmp, target)
            self._files = []
        for old in self._replaced:
            shutil.rmtree(old, ignore_errors=True)
        self._replaced = []

    def _discard(self):
        for tmp, _target in self._files:
            if os.path.isdir(tmp):
                shutil.rmtree(tmp, ignore_errors=True)
            with contextlib.suppress(FileNotFoundError):
                os.remove(tmp)
        self._files = []


@contextlib.contextmanager
def _signals_held():
    """Ctrl-C and SIGTERM received in the block take effect when it ends (in
    the main thread; elsewhere Python runs no signal handler anyway)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    received = []
    kept = {}
    for number in (signal.SIGINT, signal.SIGTERM):
        kept[number] = signal.signal(number, lambda n, frame: received.append(n))
    try:
        yield
    finally:
        for number, handler in kept.items():
            signal.signal(number, signal.SIG_DFL if handler is None else handler)
        if received:
            signal.raise_signal(received[0])


@contextlib.contextmanager
def together():
    """``with together() as files: write(files.reserve(a)); write(files.reserve(b))``:
    the files appear together when the block ends without an exception, or
    not at all (their temporary files removed, the targets untouched)."""
    files = OutputFiles()
    try:
        yield files
    except BaseException:
        files._discard()
        raise
    try:
        files._commit()
    except BaseException:
        files._discard()
        raise


@contextlib.contextmanager
def replacing_path(path, suffix=""):
    """``with replacing_path(path) as tmp: writer(tmp)``: :func:`together` for
    one file: a temporary name beside ``path``'s target, renamed over it when
    the block ends without an exception (removed otherwise)."""
    with together() as files:
        yield files.reserve(path, suffix)


@contextlib.contextmanager
def replacing(path, mode="w", encoding="utf-8", newline=None):
    """``with replacing(path) as f: f.write(...)``: the file object of a temporary
    file beside ``path``'s target, renamed over it when the block ends without
    an exception (removed otherwise). ``mode``: ``"w"`` (text) or ``"wb"``;
    ``encoding`` and ``newline`` as for ``open`` (text only)."""
    with together() as files, files.open(path, mode, encoding, newline) as f:
        yield f


def write_text(path, text):
    """Write ``text`` (a str, or a list of them written one after the
    other) to ``path`` as :func:`replacing` does."""
    with replacing(path) as f:
        if isinstance(text, str):
            f.write(text)
        else:
            f.writelines(text)
