"""The manifest of a map series: one entry per sheet, read into named types.

A manifest is a JSON file::

    {"epsg": 28992, "margin": 80, "seed": 1,
     "options": {"remove": "2,6"},
     "sheets": [{"name": "sheet_0_0", "map": "sheet_0_0.map.bsq",
                 "training": "sheet_0_0.training.geojson",
                 "footprints": "sheet_0_0.current.geojson",
                 "extent": [84000, 446000, 84200, 446200], "year": 1900,
                 "options": {"min_area": 40}}]}

or a CSV file with the columns ``name,map,training,footprints,west,south,
east,north,year`` and, optionally, ``options`` (``key=value`` pairs
separated by ``;``), one sheet per row, the series' own settings (epsg,
margin, seed) left at their defaults. Relative file paths are taken from
the manifest's folder. The extent is the sheet's own area (its neatline):
sheets of a series share edges and never overlap.
"""

import csv
import io
import json
import math
import os
import re
from dataclasses import dataclass

from ..core import crs, jsontext
from ..core.errors import InputError

#: a sheet's name becomes part of GRASS map names and file names (matched
#: whole: ``$`` would let a name end in a newline)
_NAME = re.compile(r"[A-Za-z][A-Za-z0-9_]*")
#: what a manifest is, for the errors of :mod:`reconstruction.core.jsontext`
WHAT = "manifest"
#: the columns of a CSV manifest
CSV_COLUMNS = ("name", "map", "training", "footprints", "west", "south", "east", "north", "year")


#: the default margin (m) a sheet's chain reads of its neighbours' maps: more
#: than a plot (a town block) reaches across a sheet edge, so that both
#: sheets see it whole and agree on its owner. With 30 m, 8 sheets of the
#: synthetic town (blocks up to about 100 m) built 95 buildings twice (left
#: out by the merge); with 80 m none, for about 25 % more time a sheet.
MARGIN = 80.0


@dataclass(frozen=True)
class Sheet:
    """One sheet: its files (absolute paths), its own area (west, south,
    east, north, metres), the year its map shows and its options (name ->
    text, over the series' and the template's)."""
    name: str
    map: str
    training: str
    footprints: str
    extent: tuple
    year: int
    options: tuple = ()

    @property
    def area(self):
        west, south, east, north = self.extent
        return (east - west) * (north - south)


@dataclass(frozen=True)
class Series:
    """A series of sheets: the EPSG code of their maps, the margin (m) each
    sheet's chain reads from its neighbours, the seed, the series' options."""
    sheets: tuple
    epsg: int = 28992
    margin: float = MARGIN
    seed: int = 1
    options: tuple = ()
    path: str = ""

    def sheet(self, name):
        for s in self.sheets:
            if s.name == name:
                return s
        raise InputError("The series has no sheet <{}>".format(name))

    def neighbours(self, sheet):
        """The other sheets within ``margin`` of ``sheet`` (those whose map
        its chain reads for the margin), in manifest order."""
        return tuple(s for s in self.sheets if s.name != sheet.name
                     and _boxes_meet(_grown(sheet.extent, self.margin), s.extent))


def _grown(extent, d):
    return (extent[0] - d, extent[1] - d, extent[2] + d, extent[3] + d)


def _boxes_meet(a, b):
    return a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3]


def _where(path, sheet=None):
    return "manifest '{}'".format(path) + (", sheet <{}>".format(sheet) if sheet else "")


def _number(value, what, where, kind=float):
    """``value`` (a JSON number or a text) as a finite float, or as an int
    when ``kind`` is int (a whole number: 1900 or "1900", not 1900.5)."""
    if isinstance(value, bool):
        value = None                # true is no number (float(True) would be 1.0)
    try:
        out = float(value)
    except (TypeError, ValueError, OverflowError):
        raise InputError("{}: {} must be a number, not {}".format(
            where, what, json.dumps(value)[:60])) from None
    if not math.isfinite(out):
        raise InputError("{}: {} must be a finite number, not {}".format(where, what, out))
    if kind is float:
        return out
    if isinstance(value, int):
        return value
    if out != int(out) or abs(out) >= 2 ** 53:
        raise InputError("{}: {} must be a whole number, not {}".format(
            where, what, json.dumps(value)[:60]))
    return int(out)


def _options(value, where):
    if value in (None, ""):
        return ()
    if isinstance(value, str):
        pairs = [p.strip() for p in value.split(";") if p.strip()]
        if any("=" not in p for p in pairs):
            raise InputError("{}: options must be key=value pairs separated by ';', not '{}'"
                             .format(where, value))
        value = dict(p.split("=", 1) for p in pairs)
    if not isinstance(value, dict) or any(isinstance(v, (dict, list)) for v in value.values()):
        raise InputError("{}: options must be an object of key: value".format(where))
    return tuple(sorted((str(k).strip(), str(v).strip()) for k, v in value.items()))


def _file(folder, value, what, where):
    if not isinstance(value, str) or not value.strip():
        raise InputError("{}: no {} file given".format(where, what))
    return os.path.normpath(os.path.join(folder, value.strip()))


def sheet_of(entry, folder, where):
    """A :class:`Sheet` of one manifest entry (a dict of its fields)."""
    name = entry.get("name")
    if not isinstance(name, str) or not _NAME.fullmatch(name):
        raise InputError("{}: a sheet's name must start with a letter and hold only letters, "
                         "digits and '_', not {}".format(where, json.dumps(name)[:60]))
    where = "{}, sheet <{}>".format(where, name)
    extent = entry.get("extent")
    if extent is None:
        extent = [entry.get(k) for k in ("west", "south", "east", "north")]
    if not isinstance(extent, (list, tuple)) or len(extent) != 4:
        raise InputError("{}: extent must be [west, south, east, north]".format(where))
    extent = tuple(_number(v, "the extent", where) for v in extent)
    if not (extent[0] < extent[2] and extent[1] < extent[3]):
        raise InputError("{}: extent {} is empty (west < east and south < north wanted)"
                         .format(where, list(extent)))
    year = _number(entry.get("year"), "year", where, int)
    return Sheet(name=name, map=_file(folder, entry.get("map"), "map", where),
                 training=_file(folder, entry.get("training"), "training", where),
                 footprints=_file(folder, entry.get("footprints"), "footprints", where),
                 extent=extent, year=year, options=_options(entry.get("options"), where))


def series_of(doc, path):
    """A :class:`Series` of a manifest's document (a dict as the JSON form holds)."""
    where = _where(path)
    if not isinstance(doc, dict) or not isinstance(doc.get("sheets"), list):
        raise InputError("{}: no list of sheets".format(where))
    if not doc["sheets"]:
        raise InputError("{}: the list of sheets is empty".format(where))
    folder = os.path.dirname(os.path.abspath(path))
    sheets = []
    for k, entry in enumerate(doc["sheets"]):
        if not isinstance(entry, dict):
            raise InputError("{}: sheet {} is not an object".format(where, k + 1))
        sheets.append(sheet_of(entry, folder, where))
    names = [s.name for s in sheets]
    twice = sorted({n for n in names if names.count(n) > 1})
    if twice:
        raise InputError("{}: sheet <{}> is listed twice".format(where, twice[0]))
    for a in range(len(sheets)):
        for b in range(a + 1, len(sheets)):
            if _boxes_meet(sheets[a].extent, sheets[b].extent):
                raise InputError("{}: sheets <{}> and <{}> overlap: a series' sheets share "
                                 "edges, each area on one sheet".format(
                                     where, sheets[a].name, sheets[b].name))
    margin = _number(doc.get("margin", MARGIN), "margin", where)
    if margin < 0:
        raise InputError("{}: margin must be 0 or more metres".format(where))
    epsg = _number(doc.get("epsg", 28992), "epsg", where, int)
    if not 0 < epsg < 2 ** 31 or not crs.known(epsg):
        raise InputError("{}: EPSG:{} is not a reference system PROJ knows".format(where, epsg))
    if crs.geographic(epsg):
        raise InputError("{}: EPSG:{} is geographic (degrees): a series' sheets are in "
                         "metres".format(where, epsg))
    seed = _number(doc.get("seed", 1), "seed", where, int)
    if not 0 <= seed < 2 ** 31:
        raise InputError("{}: seed must be a whole number from 0 to 2147483647".format(where))
    return Series(sheets=tuple(sheets), epsg=epsg, margin=margin, seed=seed,
                  options=_options(doc.get("options"), where), path=os.path.abspath(path))


def read_manifest(path):
    """The :class:`Series` of a manifest file (``.json`` or ``.csv``, UTF-8)."""
    text = jsontext.read_text(path, WHAT)
    if path.lower().endswith(".csv"):
        return series_of({"sheets": csv_rows(text, path)}, path)
    return series_of(jsontext.loads(text, WHAT, path), path)


def csv_rows(text, path):
    """The rows of a CSV manifest as dicts of its columns, or one InputError."""
    reader = csv.DictReader(io.StringIO(text, newline=""))
    rows = []
    try:
        for row in reader:
            if None in row or None in row.values():
                raise InputError("{}: line {} has not as many fields as the header".format(
                    _where(path), reader.line_num))
            rows.append(row)
    except csv.Error as e:
        raise InputError("{}: not CSV ({})".format(_where(path), e)) from None
    missing = [c for c in CSV_COLUMNS if c not in (reader.fieldnames or ())]
    if rows and missing:
        raise InputError("{}: no column {}".format(_where(path), ", ".join(missing)))
    return rows
