"""Reference systems: EPSG codes, their CityJSON URLs, compound systems.

- :func:`known`: whether an EPSG code names a reference system (issue 12,
  item 7);
- :func:`epsg_code`: the code of a CityJSON ``referenceSystem`` (URL, URN,
  ``EPSG:7415``), :func:`crs_url` the URL of a code;
- :func:`horizontal_epsg` and :func:`same_place`: a compound system (7415,
  RD New + NAP heights) and its horizontal part (28992) locate points alike;
- :func:`geographic`: a system in degrees (4326), which a location in
  metres cannot be written in; :func:`looks_geographic`: a box that could
  be longitude and latitude.

PROJ's own database (``proj.db``, which GRASS, GDAL and PROJ install: no
extra dependency) is asked through Python's sqlite3. Where it cannot be
found, a plausibility check stands in: EPSG codes lie between 1024 and
999999 (the dataset uses 2000 to 32767, and 900913).
"""

import functools
import os
import re
import sqlite3
import sys

#: plausible EPSG codes when proj.db is not found
PLAUSIBLE = (1024, 999999)
#: compound reference systems -> their horizontal part, where PROJ's database is absent
COMPOUND = {7415: 28992, 6190: 31370, 8370: 3812, 7405: 27700, 5555: 25832, 5556: 25833}


def proj_db():
    """The path of PROJ's ``proj.db``, or None."""
    dirs = [os.environ.get(k) for k in ("PROJ_DATA", "PROJ_LIB")]
    dirs += [os.path.join(sys.prefix, "share", "proj"), "/usr/share/proj", "/usr/local/share/proj"]
    for directory in dirs:
        for part in (directory or "").split(os.pathsep):
            path = os.path.join(part, "proj.db")
            if part and os.path.isfile(path):
                return path
    return None


#: what :func:`_ask` gives where PROJ's database is absent or cannot be read
_UNKNOWN = object()


def _ask(query, code, database=None):
    """The first row of ``query`` (one ``?``: the EPSG code) in PROJ's
    database (``database``, else the one found), None when it has no row,
    :data:`_UNKNOWN` where there is no database to ask."""
    database = database or proj_db()
    if not database:
        return _UNKNOWN
    try:
        db = sqlite3.connect("file:{}?mode=ro".format(database), uri=True)
        try:
            return db.execute(query, (str(int(code)),)).fetchone()
        finally:
            db.close()
    except sqlite3.Error:
        return _UNKNOWN


def known(code, database=None):
    """True when EPSG ``code`` (an int) names a reference system in proj.db;
    without proj.db (``database`` None and none found), whether it is plausible."""
    row = _ask("SELECT 1 FROM crs_view WHERE auth_name = 'EPSG' AND code = ?", code, database)
    if row is _UNKNOWN:
        return PLAUSIBLE[0] <= int(code) <= PLAUSIBLE[1]
    return row is not None


def crs_url(epsg):
    """The OGC URL of an EPSG code (``28992`` -> https://www.opengis.net/def/crs/EPSG/0/28992).

    A string that already is such a URL is returned as is; ``EPSG:7415`` works too.
    A code that names no reference system (:func:`known`)
    raises ValueError.
    """
    text = str(epsg).strip()
    if text.startswith("http://") or text.startswith("https://"):
        return text
    if ":" in text:
        text = text.split(":")[-1]
    code = int(text)
    if not known(code):
        raise ValueError("EPSG:{} is not a known reference system".format(code))
    return "https://www.opengis.net/def/crs/EPSG/0/{}".format(code)


def epsg_code(reference_system):
    """EPSG code of a CityJSON ``referenceSystem`` (OGC URL or URN, ``EPSG:7415``, 7415)."""
    if reference_system is None or reference_system == "":
        return None
    text = str(reference_system).strip()
    if "EPSG" not in text.upper() and not text.isdigit():
        return None
    code = text.replace("::", ":").replace("/", ":").split(":")[-1]
    try:
        return int(code)
    except ValueError:
        return None


@functools.lru_cache(maxsize=64)
def horizontal_epsg(code):
    """The horizontal CRS of a compound EPSG CRS (7415 -> 28992), else the code itself.

    Asks PROJ's database (``proj.db``, installed with GRASS) and falls back to
    a short table of common compound systems.
    """
    if code is None:
        return None
    row = _ask("SELECT horiz_crs_auth_name, horiz_crs_code FROM compound_crs WHERE "
               "auth_name = 'EPSG' AND code = ?", code)
    if row is not _UNKNOWN and row is not None and row[0] == "EPSG":
        try:
            return int(row[1])
        except ValueError:
            pass
    return COMPOUND.get(int(code), int(code))


def same_place(a, b):
    """True when two EPSG codes locate points the same way horizontally
    (equal, or one is a compound CRS of the other: 7415 and 28992)."""
    if a is None or b is None:
        return True
    return horizontal_epsg(a) == horizontal_epsg(b)


#: geographic reference systems (degrees), where PROJ's database is absent
GEOGRAPHIC = frozenset({4326, 4258, 4269, 4230, 4289, 4313, 4979, 4937, 4171, 4283})


@functools.lru_cache(maxsize=64)
def geographic(code):
    """True when EPSG ``code`` (or the horizontal part of a compound system)
    is geographic: its coordinates are degrees of longitude and latitude,
    not metres (PROJ's database, else :data:`GEOGRAPHIC`)."""
    if code is None:
        return False
    code = horizontal_epsg(int(code))
    row = _ask("SELECT type FROM geodetic_crs WHERE auth_name = 'EPSG' AND code = ?", code)
    if row is _UNKNOWN:
        return code in GEOGRAPHIC
    return row is not None and str(row[0]).startswith("geographic")


def looks_geographic(extent):
    """Whether coordinates of the box ``extent`` (an object with x0, y0, x1,
    y1) could be longitude and latitude: within +-180 and +-90."""
    return (extent is not None and -180 <= extent.x0 <= extent.x1 <= 180
            and -90 <= extent.y0 <= extent.y1 <= 90)


#: what CityJSON 2.0 wants of a ``referenceSystem`` (metadata.schema.json)
OGC_URL = re.compile(r"^(http|https)://www.opengis.net/def/crs/")


def as_ogc_url(reference_system):
    """A ``referenceSystem`` as CityJSON 2.0 wants it: an EPSG code in any
    spelling (``urn:ogc:def:crs:EPSG::7415``, ``EPSG:7415``, ``7415``) as its
    OGC URL; an OGC URL, None or a text that names no EPSG code as it is."""
    if reference_system is None or OGC_URL.match(str(reference_system).strip()):
        return reference_system
    code = epsg_code(reference_system)
    if code is None:
        return reference_system
    return "https://www.opengis.net/def/crs/EPSG/0/{}".format(code)
