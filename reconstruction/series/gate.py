"""What the series service lets through to actinia (issue 49, item 2).

actinia 4.14.1 checks a ``user``'s modules (``accessible_modules``) and
mapsets (``accessible_datasets``) but not the files a module's parameters
name: ``v.in.ogr input=/root/secret.csv`` followed by ``v.db.select``, or
``r.out.png output=/etc/... --o``, read and write wherever the service's
system user may. The service therefore answers through a gate
(``tools/actinia/gate.py``, a WSGI application in front of actinia's) that
lets through only what a series needs, each request checked by
:func:`refusal`:

- the routes of :data:`ROUTES` (the version, a process chain sent to
  ``processing_async_export`` in the service's location, its status and its
  exported files); any other route of actinia's API is refused;
- a process chain (:func:`check_chain`) of version 1 whose steps are GRASS
  modules of the service's list (no executables, no ``stdin``, no imports
  or webhooks of actinia's, no ``overwrite``), with flags of letters only;
- every parameter value: where a comma-separated part of it holds a ``/``
  it must be an absolute, normalised path whose real path (symbolic links
  resolved) lies in the series' work folder, not a GDAL ``/vsi`` path; a
  ``$`` only in actinia's ``$file::name`` (a file of the job) and GRASS's
  default SQLite database of ``db.connect``; no part that names a GDAL/OGR
  data source by its driver (``PG:dbname=...``). A value without ``/`` is
  no path outside: relative names resolve in the job's empty working folder.

What the gate cannot see is inside the files of the work folder (a GDAL
VRT there may name any file): the service should run as an unprivileged
user, and the work folder be writable by that user only.
"""

import os
import re
from dataclasses import dataclass

from ..core import jsontext
from ..core.errors import InputError

#: (method, path) a series needs of actinia's API version 3
ROUTES = (
    ("GET", re.compile(r"/api/v3/version")),
    ("POST", re.compile(r"/api/v3/locations/(?P<location>[A-Za-z0-9_]+)/processing_async_export")),
    ("GET", re.compile(r"/api/v3/resources/[A-Za-z0-9_]+/resource_id-[A-Za-z0-9_-]+")),
    ("GET", re.compile(r"/api/v3/resources/[A-Za-z0-9_]+/resource_id-[A-Za-z0-9_-]+/"
                       r"(?!mapsetsizes)[A-Za-z0-9_-]+(\.[A-Za-z0-9_]+)*")),
)
#: the largest process chain accepted (bytes)
MAX_BODY = 4 * 1024 * 1024
#: the keys of a process chain, of a step, of an input or output, of an export
CHAIN_KEYS = {"version", "list"}
STEP_KEYS = {"id", "module", "inputs", "outputs", "flags"}
PARAMETER_KEYS = {"param", "value"}
EXPORT_KEYS = {"format", "type"}
#: names: a step id, a parameter, a ``$file::`` name
_NAME = re.compile(r"[A-Za-z0-9_.]+")
#: actinia's placeholder of a job's own file
_JOB_FILE = re.compile(r"\$file::[A-Za-z0-9_]+")
#: a GDAL/OGR data source named by its driver (``PG:dbname=...``, ``WFS:``,
#: ``CSV:file``): a database, a service or a file by another name
_SOURCE_PREFIX = re.compile(r"\s*[A-Za-z][A-Za-z0-9_]*:")
#: GRASS's default database of a mapset, which ``db.connect`` expands itself
DEFAULT_SQLITE = "$GISDBASE/$LOCATION_NAME/$MAPSET/sqlite/sqlite.db"
WHAT = "process chain"


@dataclass(frozen=True)
class Policy:
    """What the service allows: the work folders (real absolute paths) that
    file paths may name, the modules, the location."""
    work: tuple
    modules: frozenset
    location: str

    @classmethod
    def of(cls, work, modules, location):
        folders = tuple(os.path.realpath(w) for w in work if w)
        if not folders or not all(os.path.isabs(w) for w in work):
            raise InputError("the series service needs an absolute work folder")
        return cls(folders, frozenset(m for m in modules if m), location)


def refusal(method, path, body, policy):
    """Why the request (``method``, ``path``, ``body`` bytes) is refused, or None."""
    for allowed, pattern in ROUTES:
        match = pattern.fullmatch(path)
        if match and method == allowed:
            break
    else:
        return "{} {} is not offered by the histo series service".format(method, path[:200])
    if method != "POST":
        return None
    if match.group("location") != policy.location:
        return "the series service runs chains in location <{}> only".format(policy.location)
    if len(body) > MAX_BODY:
        return "a process chain of more than {} bytes".format(MAX_BODY)
    try:
        check_chain(jsontext.loads(jsontext.decode(body, WHAT, "request"), WHAT, "request"),
                    policy)
    except InputError as error:
        return str(error)
    return None


def _keys(obj, allowed, where):
    if not isinstance(obj, dict):
        raise InputError("{}: not an object".format(where))
    unknown = sorted(set(obj) - allowed)
    if unknown:
        raise InputError("{}: <{}> is not allowed by the series service".format(
            where, unknown[0][:40]))


def check_chain(document, policy):
    """InputError unless ``document`` is a process chain the policy allows."""
    _keys(document, CHAIN_KEYS, "the process chain")
    if document.get("version") != "1" or not isinstance(document.get("list"), list):
        raise InputError("the process chain must be of version \"1\" with a list of steps")
    for k, step in enumerate(document["list"]):
        where = "step {}".format(k + 1)
        _keys(step, STEP_KEYS, where)
        module = step.get("module")
        if module not in policy.modules:
            raise InputError("{}: module <{}> is not one of the series' modules".format(
                where, str(module)[:40]))
        if not isinstance(step.get("id"), str) or not _NAME.fullmatch(step["id"]):
            raise InputError("{}: its id must be letters, digits, '_' and '.'".format(where))
        flags = step.get("flags", "")
        if not isinstance(flags, str) or not re.fullmatch(r"[A-Za-z]*", flags):
            raise InputError("{}: flags must be letters".format(where))
        for kind in ("inputs", "outputs"):
            entries = step.get(kind, [])
            if not isinstance(entries, list):
                raise InputError("{}: its {} must be a list".format(where, kind))
            for entry in entries:
                check_parameter(entry, kind, module, where, policy)


def check_parameter(entry, kind, module, where, policy):
    """InputError unless one input or output of a step is allowed."""
    _keys(entry, PARAMETER_KEYS | ({"export"} if kind == "outputs" else set()), where)
    param, value = entry.get("param"), entry.get("value")
    if not isinstance(param, str) or not _NAME.fullmatch(param) or not isinstance(value, str):
        raise InputError("{}: a parameter is a name and a text".format(where))
    where = "{} ({} {}=)".format(where, module, param)
    if "export" in entry:
        _keys(entry["export"], EXPORT_KEYS, where)
    if "$" in value and not (kind == "outputs" and _JOB_FILE.fullmatch(value)) and not (
            module == "db.connect" and param == "database" and value == DEFAULT_SQLITE):
        raise InputError("{}: '$' is allowed only in actinia's $file::name".format(where))
    if value == DEFAULT_SQLITE:
        return
    for part in value.split(","):
        if _SOURCE_PREFIX.match(part):
            raise InputError("{}: a GDAL/OGR data source prefix ('{}') is not allowed".format(
                where, part[:40]))
        if "/" in part or "\\" in part:
            check_path(part, where, policy)


def check_path(path, where, policy):
    """InputError unless ``path`` is a file or folder in the policy's work folders."""
    if not path.startswith("/") or os.path.normpath(path) != path or "\\" in path:
        raise InputError("{}: a path must be absolute and normalised, not '{}'".format(
            where, path[:200]))
    if path.startswith("/vsi"):
        raise InputError("{}: GDAL's virtual file systems are not allowed ('{}')".format(
            where, path[:200]))
    real = os.path.realpath(path)
    if not any(os.path.commonpath([real, w]) == w for w in policy.work):
        raise InputError("{}: '{}' is outside the series' work folder '{}'".format(
            where, path[:200], policy.work[0]))
