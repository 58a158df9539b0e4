"""Checks a module makes before any work: the location, its inputs, its outputs.

Re-exported by :mod:`reconstruction.grassio.maps`, where modules reach them
(``grassio.require_vector``, ``grassio.check_outputs``, ...). Outputs are
checked first (issue 12, item 4): every output map name against GRASS's
rules and SQL keywords, every output file path (its directory exists and is
writable, it is not something else than a regular file), so that a bad name
fails in a second, not after all the computing.
"""

import os
import sys

import grass.script as gs

from ..core import names
from ..core.errors import InputError
from .run import doing

_PROJECTION = []
#: GRASS queries of the checks started ahead (see prefetch_checks).
_QUERIES = {}


def prefetch_checks():
    """Start the GRASS query behind :func:`require_projected` (and
    :func:`location_epsg`) now, so that it runs while the caller imports and
    parses; the checks then take its answer."""
    if not _PROJECTION and "proj" not in _QUERIES:
        _QUERIES["proj"] = gs.start_command("g.proj", flags="g", stdout=gs.PIPE,
                                            stderr=gs.PIPE)


def _answer(key):
    """The parsed output of a query started by :func:`prefetch_checks`, or None."""
    proc = _QUERIES.pop(key, None)
    if proc is None:
        return None
    return gs.parse_key_val(gs.decode(proc.communicate()[0]))


def projection():
    """The current location's projection (g.proj -g) as a dict (asked once)."""
    if not _PROJECTION:
        answer = _answer("proj")
        _PROJECTION.append(answer if answer is not None else
                           gs.parse_command("g.proj", flags="g"))
    return _PROJECTION[0]


def location_epsg():
    """The current location's EPSG code, or None."""
    proj = projection()
    srid = proj.get("srid", "") or proj.get("epsg", "")
    if srid:
        code = srid.split(":")[-1]
        if code.isdigit():
            return int(code)
    return None


def require_projected():
    """Fail unless the current location has a projected CRS in metres."""
    proj = projection()
    name = proj.get("name", "")
    if proj.get("proj", "") in ("ll", "") or "lat" in name.lower() and "long" in name.lower():
        gs.fatal(
            _("Location is not projected: the histo modules need map units in metres "
              "(e.g. EPSG:28992); create a projected location and import the maps there")
        )
    units = proj.get("units", proj.get("unit", "")).lower()
    if units and not units.startswith("met"):
        gs.warning(_("Map units are <{}>, not metres: sizes are taken in map units").format(units))


def require_raster(name):
    if not gs.find_file(name, element="cell")["fullname"]:
        gs.fatal(_("Raster map <{}> not found").format(name))


def require_vector(name):
    if not gs.find_file(name, element="vector")["fullname"]:
        gs.fatal(_("Vector map <{}> not found").format(name))


def require_features(name, kind, key):
    """Fail unless vector map ``name`` (given as ``key``=) holds ``kind`` (areas, points...)."""
    require_vector(name)
    counts = vector_counts(name)
    if counts.get(kind, 0) == 0:
        held = ", ".join("{} {}".format(counts.get(k, 0), k)
                         for k in ("points", "lines", "boundaries", "centroids", "areas"))
        gs.fatal(_("Vector map <{}> given as {}= has no {} (it holds {}): give a map of {}").format(
            name, key, kind, held, kind))


def require_new_file(path, option):
    """Fail if an output file exists and --overwrite was not given, or cannot be
    written (see :func:`check_output_file`)."""
    if path:
        check_output_file(path, option)


def vector_counts(name):
    """Topology counts of a vector map (points, areas, ...) as integers."""
    with doing("reading the topology of vector map <{}>".format(name)):
        info = gs.vector_info_topo(name)
    return {k: int(v) for k, v in info.items() if isinstance(v, (int, float))}


# ---------------------------------------------------------------------------
# Outputs
# ---------------------------------------------------------------------------

def check_outputs(options, rasters=(), vectors=(), files=(), inputs=None, directories=None):
    """Raise :class:`InputError` now when an output named by ``options`` cannot be written.

    ``rasters``, ``vectors``, ``files``: the option keys of the output raster
    maps, vector maps and files (empty options are skipped). A map name must be
    one GRASS accepts (a vector map's also names its table: no SQL keyword);
    ``name@mapset`` only for the current mapset. A file's directory must exist
    and be writable, an existing file needs --overwrite and must be a regular
    file (a symbolic link is followed: its target is checked and written,
    see :mod:`reconstruction.core.safefile`). Two outputs may not have one name.
    ``inputs``: kind (``"raster"``, ``"vector"``, ``"file"``) -> the option
    keys of the inputs of that kind (comma lists allowed): no output may be
    one of them (issue 33, item 4: ``render=`` given the ``existing=`` model
    would replace the user's model with a picture; as GRASS's own modules
    refuse an output map that is their input).
    ``directories``: option key -> the file that marks a directory that output
    wrote (``{"tiles": "tileset.json"}``): as a file, and an existing directory
    is replaced only with --overwrite and when it is empty or holds that file.
    """
    seen = {}
    for kind, keys in (("raster", rasters), ("vector", vectors)):
        for key in keys:
            name = _map_name(options[key], key)
            if not name:
                continue
            problem = (names.vector_name_problem if kind == "vector"
                       else names.raster_name_problem)(name)
            if problem:
                raise InputError("Option {}=: <{}> cannot name a {} map: {}".format(
                    key, name, kind, problem))
            _unique(seen, (kind, name), key)
    for key in files:
        if options[key]:
            _unique(seen, ("file", check_output_file(options[key], key)), key)
    for key, marker in (directories or {}).items():
        if options.get(key):
            _unique(seen, ("file", check_output_directory(options[key], key, marker)), key)
    for kind, keys in (inputs or {}).items():
        for key in keys:
            for given in [v.strip() for v in (options.get(key) or "").split(",") if v.strip()]:
                output = seen.get((kind, _input_identity(kind, given, seen)))
                if output:
                    raise InputError("Option {}= names the input <{}> of {}=: an output never "
                                     "replaces an input".format(output, given, key))


def _input_identity(kind, name, outputs):
    """What an input is, as :func:`check_outputs` keys its ``outputs``: a
    file's real path; a map's name when an output has that name and the map
    is found in the current mapset (else None: no output replaces it)."""
    if kind == "file":
        return os.path.realpath(name)
    bare, _at, mapset = name.partition("@")
    if (kind, bare) not in outputs:
        return None
    current = gs.gisenv()["MAPSET"]
    if mapset and mapset != current:
        return None
    found = gs.find_file(bare, element="cell" if kind == "raster" else "vector", mapset=current)
    return bare if found["fullname"] else None


def _map_name(name, key):
    """An output map name without its ``@mapset`` (which must be the current one)."""
    if name and "@" in name:
        name, mapset = name.split("@", 1)
        if mapset != gs.gisenv()["MAPSET"]:
            raise InputError("Option {}=: outputs go to the current mapset <{}>, not <{}>".format(
                key, gs.gisenv()["MAPSET"], mapset))
    return name


def _unique(seen, what, key):
    if what in seen:
        raise InputError("Options {}= and {}= name the same output <{}>".format(
            seen[what], key, what[1]))
    seen[what] = key


def check_output_file(path, key):
    """The file an output path writes (a symbolic link's target), checked as
    :func:`check_outputs` says; raises :class:`InputError`."""
    return _check_output(path, key)


def check_output_directory(path, key, marker):
    """The directory an output path writes, checked as :func:`check_outputs` says
    (``marker``: the file that shows the directory is one this output wrote);
    raises :class:`InputError`."""
    return _check_output(path, key, marker)


def _check_output(path, key, marker=None):
    """A file (``marker`` None) or directory output, checked; its real path."""
    target = os.path.realpath(path)
    kind, is_kind = ("directory", os.path.isdir) if marker else ("regular file", os.path.isfile)
    if os.path.exists(target):
        if not is_kind(target):
            raise InputError("Option {}=: '{}' exists and is not a {}; "
                             "it is not replaced".format(key, path, kind))
        if not gs.overwrite():
            raise InputError("{} '{}' given as {}= exists; use --overwrite to replace "
                             "it".format("Directory" if marker else "File", path, key))
        if marker and os.listdir(target) and not os.path.isfile(os.path.join(target, marker)):
            raise InputError("Option {}=: directory '{}' holds other files than a {} output "
                             "(no {}); it is not replaced".format(key, path, key, marker))
    directory = os.path.dirname(target)
    if not os.path.isdir(directory):
        raise InputError("Option {}=: directory '{}' does not exist".format(key, directory))
    if not os.access(directory, os.W_OK | os.X_OK):
        raise InputError("Option {}=: directory '{}' is not writable".format(key, directory))
    return target


# ---------------------------------------------------------------------------
# Column options
# ---------------------------------------------------------------------------

def given(options, key):
    """True when option ``key`` is on the module's command line (not its default).

    GRASS takes unambiguous abbreviations of option keys: ``plot_c=`` is
    ``plot_column=`` unless another option is called ``plot_c``.
    """
    for arg in sys.argv[1:]:
        word = arg.split("=", 1)[0]
        if "=" not in arg or not word:
            continue
        if word == key or (key.startswith(word) and word not in options):
            return True
    return False


def require_columns(options, columns, keys, map_name):
    """Raise :class:`InputError` when a column option given on the command line
    (one of ``keys``) names a column that vector map ``map_name`` does not
    have (``columns``: its column names). Defaults that are absent stay
    optional: the module then does without them."""
    for key in keys:
        column = options.get(key)
        if column and column not in columns and given(options, key):
            raise InputError("Column <{}> given as {}= is not in vector map <{}> (its columns: "
                             "{})".format(column, key, map_name,
                                          ", ".join(c for c in columns if c != "cat") or "none"))
