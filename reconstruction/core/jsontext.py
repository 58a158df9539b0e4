"""JSON a user gave (a model, a rules file, a manifest), parsed or refused.

Every file the suite reads that a user or another program wrote is untrusted:
:func:`read_text` and :func:`loads` turn what Python's ``json`` would raise
on it (a file that is not UTF-8, text that is not JSON, nesting deep enough
to exhaust the interpreter's stack, a lone UTF-16 surrogate that no output
can encode) into one :class:`~reconstruction.core.errors.InputError` that
names the file, never a traceback.
"""

import json
import re

from .errors import InputError

#: an escaped UTF-16 surrogate in JSON text (``\\ud800``): the only way a
#: lone surrogate gets into a parsed string (UTF-8 text cannot hold one)
_ESCAPED_SURROGATE = re.compile(r"\\u[dD][89a-fA-F][0-9a-fA-F]{2}")


def read_text(path, what):
    """The text of the file ``path`` (UTF-8); ``what`` the file is, for the error."""
    try:
        with open(path, "rb") as f:
            data = f.read()
    except OSError as error:
        raise InputError("Cannot read the {} '{}': {}".format(
            what, path, error.strerror)) from None
    return decode(data, what, path)


def decode(data, what, path):
    """``data`` (bytes) as UTF-8 text, or one InputError naming the byte that is not."""
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as error:
        raise InputError("The {} '{}' is not UTF-8 text (byte {:#04x} at offset {}): save it "
                         "as UTF-8".format(what, path, data[error.start], error.start)) from None


def loads(text, what, path):
    """The document of JSON ``text`` (read from ``path``, which is a ``what``)."""
    try:
        doc = json.loads(text)
    except RecursionError:
        raise InputError("The {} '{}' is nested too deeply to be read".format(
            what, path)) from None
    except ValueError as error:
        raise InputError("The {} '{}' is not JSON ({})".format(what, path, error)) from None
    if _ESCAPED_SURROGATE.search(text):
        check_strings(doc, what, path)
    return doc


def load(path, what):
    """The document of the JSON file ``path`` (:func:`read_text`, :func:`loads`)."""
    return loads(read_text(path, what), what, path)


def check_strings(doc, what, path):
    """InputError where a string (key or value) of ``doc`` cannot be written as UTF-8."""
    stack = [doc]
    while stack:
        value = stack.pop()
        if isinstance(value, dict):
            stack.extend(value.keys())
            stack.extend(value.values())
        elif isinstance(value, list):
            stack.extend(value)
        elif isinstance(value, str):
            try:
                value.encode("utf-8")
            except UnicodeEncodeError:
                raise InputError("The {} '{}' holds a text with a lone UTF-16 surrogate ({}), "
                                 "which no output can hold".format(
                                     what, path, json.dumps(value)[:60])) from None
