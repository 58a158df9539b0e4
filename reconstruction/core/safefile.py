"""Output files written whole or not at all (issue 12, items 5 and 6).

:func:`replacing` writes a file under a unique temporary name
(``tempfile.mkstemp``) in the directory of its target and renames it into
place (``os.replace``) only once it is complete: a failure or an interruption
leaves the target as it was and no temporary file, and no existing file is
ever taken for a temporary one. A symbolic link is written through: its
target gets the new content and the link stays. Something that is not a
regular file (a directory, a device such as ``/dev/full``, a named pipe) is
never replaced. Pure Python, no GRASS.
"""

import contextlib
import os
import stat
import tempfile

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


@contextlib.contextmanager
def replacing_path(path, suffix=""):
    """``with replacing_path(path) as tmp: writer(tmp)``: a unique temporary
    file name beside ``path``'s target (ending in ``suffix``, e.g. ``".png"``
    for a writer that goes by the extension), renamed over the target when the
    block ends without an exception (removed otherwise)."""
    target = target_of(path)
    directory, name = os.path.split(target)
    fd, tmp = tempfile.mkstemp(prefix=".{}.".format(name), suffix=".part" + suffix, dir=directory)
    os.close(fd)
    try:
        yield tmp
        os.chmod(tmp, _mode(target))
        os.replace(tmp, target)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            os.remove(tmp)
        raise


@contextlib.contextmanager
def replacing(path, mode="w", encoding="utf-8", newline=None):
    """``with replacing(path) as f: f.write(...)``: the file object of a temporary
    file beside ``path``'s target, renamed over it when the block ends without
    an exception (removed otherwise). ``mode``: ``"w"`` (text) or ``"wb"``;
    ``encoding`` and ``newline`` as for ``open`` (text only)."""
    text = {} if "b" in mode else {"encoding": encoding, "newline": newline}
    with replacing_path(path) as tmp, open(tmp, mode, **text) as f:
        yield f


def write_text(path, text):
    """Write ``text`` (a str, or a list of them written one after the
    other) to ``path`` as :func:`replacing` does."""
    with replacing(path) as f:
        if isinstance(text, str):
            f.write(text)
        else:
            f.writelines(text)
