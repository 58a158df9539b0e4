"""Today's building register (the BAG) in a map's attribute table: construction years
and building ids, read the same way by every module that uses them.

Pure: the table is a {column: values} dict, as grassio reads it.
"""

import datetime
import math

import numpy as np

from .contract import BAG_ID_COLUMNS
from .errors import InputError

#: the BAG register writes 9999 for "construction year unknown"; any year
#: after the current one is a placeholder too
PLACEHOLDER_YEAR = 9999
#: the 3D BAG's year column, taken when the default bouwjaar is absent
FALLBACK_YEAR_COLUMN = "oorspronkelijkbouwjaar"


def construction_years(values, column="year", ids=None, today=None):
    """Construction years as floats, NaN where there is none.

    No year: None (NULL), empty text, zero or less, and placeholders (9999,
    or any year after the current one). Numbers written as text are read;
    any other text raises :class:`InputError` naming the column (and the
    footprint, from ``ids``).
    """
    latest = min(PLACEHOLDER_YEAR - 1, (today or datetime.date.today()).year)
    years = np.full(len(values), np.nan)
    for i, value in enumerate(values):
        if value is None:
            continue
        if isinstance(value, str):
            if not value.strip():
                continue
            try:
                value = float(value)
            except ValueError:
                where = " (footprint {})".format(ids[i]) if ids is not None else ""
                raise InputError("Year column <{}> is not numeric: <{}>{} is not a year".format(
                    column, value.strip(), where)) from None
        value = float(value)
        if math.isfinite(value) and 0 < value <= latest:
            years[i] = value
    return years


def column_named(columns, name):
    """The column of ``columns`` called ``name`` in any case (its values), or None."""
    names = {k.lower(): k for k in columns}
    return columns[names[name.lower()]] if name.lower() in names else None


def bag_ids(columns, name, map_name):
    """The BAG ids of a footprints map's table (as text, None where empty): column
    ``name`` (InputError when missing), or the first of
    :data:`~reconstruction.core.BAG_ID_COLUMNS` present; None for none."""
    if name:
        values = column_named(columns, name)
        if values is None:
            raise InputError("Column <{}> (id_column=) not found in vector map <{}>".format(
                name, map_name))
    else:
        values = next((v for v in (column_named(columns, c) for c in BAG_ID_COLUMNS)
                       if v is not None), None)
    if values is None:
        return None
    return [None if v is None or str(v).strip() == "" else str(v).strip() for v in values]


def year_column(columns, wanted, given, name):
    """The footprints' year column: ``wanted`` (any case), or the 3D BAG's name for the default."""
    names = {c.lower(): c for c in columns if c != "cat"}
    for candidate in [wanted] + ([] if given else [FALLBACK_YEAR_COLUMN]):
        if candidate.lower() in names:
            return names[candidate.lower()]
    raise InputError("Footprints <{}> have no year column <{}>{}; columns: {}".format(
        name, wanted, "" if given else " (nor <{}>)".format(FALLBACK_YEAR_COLUMN),
        ", ".join(sorted(names.values())) or "none (no attribute table)"))
