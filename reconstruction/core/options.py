"""Pure helpers that turn module option text into values (one way for every module).

Each raises :class:`reconstruction.core.errors.InputError` with the message a user
should read; the module script turns it into ``gs.fatal``.
"""

import math
import os

from .errors import InputError


def parse_range(text, key, cast=float, positive=False, allow_zero=True):
    """A ``min,max`` option as a (low, high) pair; one value means low = high.

    ``text`` may also be a sequence of values. Empty text gives None.
    ``positive`` refuses negative values (and zero unless ``allow_zero``).
    """
    if text is None or (isinstance(text, str) and not text.strip()):
        return None
    values = text
    if isinstance(text, str):
        values = [v for v in text.replace(" ", "").split(",") if v != ""]
    try:
        values = [cast(v) for v in values]
    except (TypeError, ValueError):
        raise InputError("Option {}= must be numbers min,max, not <{}>".format(key, text)) from None
    if len(values) == 1:
        values = values * 2
    if len(values) != 2 or not all(math.isfinite(v) for v in values):
        raise InputError("Option {}= must be two numbers min,max, not <{}>".format(key, text))
    low, high = values
    if positive and (low < 0 or (low == 0 and not allow_zero)):
        raise InputError("Option {}= must be {}, not <{}>".format(
            key, "zero or more" if allow_zero else "positive", text))
    if low > high:
        raise InputError("Option {}=: the minimum {:g} is above the maximum {:g}".format(key, low, high))
    return low, high


def parse_number(text, key, cast=float, minimum=None, allow_minimum=True, maximum=None):
    """One number option, checked against optional bounds."""
    try:
        value = cast(text)
    except (TypeError, ValueError):
        raise InputError("Option {}= must be a number, not <{}>".format(key, text)) from None
    if isinstance(value, float) and not math.isfinite(value):
        raise InputError("Option {}= must be a finite number, not <{}>".format(key, text))
    if minimum is not None and (value < minimum or (value == minimum and not allow_minimum)):
        raise InputError("Option {}= must be {} {:g} (got {})".format(
            key, "at least" if allow_minimum else "above", minimum, text))
    if maximum is not None and value > maximum:
        raise InputError("Option {}= must be at most {:g} (got {})".format(key, maximum, text))
    return value


def parse_list(text, cast=str, key=None):
    """A comma-separated option as a list (empty items dropped).

    ``key`` names the option in the error message.
    """
    if not text:
        return []
    try:
        return [cast(v.strip()) for v in text.split(",") if v.strip()]
    except (TypeError, ValueError):
        raise InputError("{}<{}> must be a comma-separated list of numbers".format(
            "Option {}=: ".format(key) if key else "", text)) from None


def parse_bands(text, key):
    """The raster maps of a scanned map's option ``key`` (comma-separated):
    one (a greyscale scan) or three (red, green, blue), as a tuple; any other
    count raises InputError."""
    names = tuple(parse_list(text))
    if len(names) not in (1, 3):
        raise InputError("Option {}= needs one raster map (a greyscale scan) or three (red, "
                         "green, blue), not {}".format(key, len(names)))
    return names


def processes(nprocs, cores=None):
    """GRASS's nprocs= meaning: positive = that many, 0 = every core, negative = all cores but that many.

    Always at least 1.
    """
    cores = cores if cores is not None else (os.cpu_count() or 1)
    nprocs = int(nprocs)
    if nprocs <= 0:
        nprocs = cores + nprocs
    return max(1, nprocs)


def integer_column(values, column, map_name):
    """The values of attribute column ``column`` of map ``map_name`` as ints
    (None stays None): a value that is not a whole number (``1.5``, text)
    raises InputError instead of being truncated."""
    out = []
    for value in values:
        if value is None or value == "":
            out.append(None)
            continue
        try:
            number = float(value)
            whole = number == int(number)
        except (TypeError, ValueError, OverflowError):
            whole = False
        if not whole:
            raise InputError("Column <{}> of vector map <{}> must hold whole numbers, found "
                             "<{}>".format(column, map_name, value))
        out.append(int(number))
    return out
