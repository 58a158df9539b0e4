"""Whether an EPSG code names a reference system (issue 12, item 7).

PROJ's own database (``proj.db``, which GRASS, GDAL and PROJ install: no
extra dependency) is asked through Python's sqlite3. Where it cannot be
found, a plausibility check stands in: EPSG codes lie between 1024 and
999999 (the dataset uses 2000 to 32767, and 900913).
"""

import os
import sqlite3
import sys

#: plausible EPSG codes when proj.db is not found
PLAUSIBLE = (1024, 999999)


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


def known(code, database=None):
    """True when EPSG ``code`` (an int) names a reference system in proj.db;
    without proj.db (``database`` None and none found), whether it is plausible."""
    database = database or proj_db()
    if database:
        try:
            db = sqlite3.connect("file:{}?mode=ro".format(database), uri=True)
            try:
                row = db.execute("SELECT 1 FROM crs_view WHERE auth_name = 'EPSG' AND code = ?",
                                 (str(int(code)),)).fetchone()
            finally:
                db.close()
            return row is not None
        except sqlite3.Error:
            pass
    return PLAUSIBLE[0] <= int(code) <= PLAUSIBLE[1]
