"""GRASS input and output shared by the histo modules.

This is the only part of the library that talks to GRASS: it moves rasters
into numpy arrays and vector maps into shapely geometries with their
attributes, and back. Everything else in the library is pure.

Vector maps travel through a temporary GeoJSON file (v.out.ogr / v.in.ogr),
which keeps categories, attribute columns and area topology (shared
boundaries, holes) without any extra Python dependency.
"""

import json
import math
import os
import sqlite3
import threading

import numpy as np

import grass.script as gs
from grass.exceptions import CalledModuleError

from ..core.names import is_sql_keyword
from .checks import require_vector, vector_counts
from .run import _tool_errors, doing
from .temp import output_name, staged, temp_file

# ---------------------------------------------------------------------------
# Rasters
# ---------------------------------------------------------------------------

def raster_region_matches(names):
    """True when all rasters share extent and resolution."""
    with doing("reading the extent of raster maps <{}>".format(",".join(names))):
        infos = [gs.raster_info(n) for n in names]
    keys = ("north", "south", "east", "west", "nsres", "ewres")
    first = infos[0]
    return all(all(abs(float(i[k]) - float(first[k])) < 1e-6 for k in keys) for i in infos[1:])


def read_raster(name, dtype=np.float64, env=None):
    """Read a raster in the current region (or the region of ``env``, e.g. a
    ``GRASS_REGION`` window) into a numpy array (NULL -> nan for floats)."""
    from grass.script import array as garray

    null = np.nan if np.dtype(dtype).kind == "f" else None
    with doing("reading raster map <{}>".format(name)):
        arr = garray.array(mapname=name, dtype=dtype, null=null, env=env)
    return np.array(arr)


def write_raster(name, values, title=None, cell=True, null=None):
    """Write a numpy array (current region) as a raster map (under a temporary
    name, renamed when complete: :func:`staged`).

    ``cell=True`` writes a CELL map with ``null`` as the NULL value.
    """
    from grass.script import array as garray

    arr = garray.array(dtype=np.int32 if cell else np.float64)
    arr[...] = values
    with doing("writing raster map <{}>".format(output_name(name))), \
            staged("raster", name) as tmp:
        # grass.script.array swallows r.in.bin's failure into a return code
        if arr.write(tmp, title=title, null=null, overwrite=True) != 0:
            raise CalledModuleError("r.in.bin", "r.in.bin output={}".format(name), 1)


# ---------------------------------------------------------------------------
# Vectors
# ---------------------------------------------------------------------------

def _read_geojson(name, layer, feature_type, where=None):
    path = temp_file(".geojson")
    kwargs = {}
    if where:
        kwargs["where"] = where
    # stderr is kept back: v.out.ogr warns about every unlabelled area (holes)
    proc = gs.start_command(
        "v.out.ogr", input=name, layer=layer, type=feature_type, output=path,
        format="GeoJSON", flags="" if feature_type == "point" else "m",
        overwrite=True, quiet=True,
        stderr=gs.PIPE, **kwargs,
    )
    err = proc.communicate()[1]
    if proc.returncode != 0 or not os.path.exists(path):
        if not where and vector_counts(name).get(feature_type + "s", 1) == 0:
            return []       # v.out.ogr fails on a map without such features
        gs.fatal(_("Cannot read {} features of vector map <{}>: {}").format(
            feature_type, name, _tool_errors(gs.decode(err))))
    with open(path) as f:
        data = json.load(f)
    return data.get("features", [])


def read_features(name, feature_type="area", layer=1, where=None):
    """Read the features of a vector map.

    Returns ``(geometries, attributes)``: a list of shapely geometries (areas of
    one category merged into one (Multi)Polygon) and a dict column -> list of
    values, always with a ``cat`` column.
    """
    from shapely.geometry import shape

    features = _read_geojson(name, layer, feature_type, where)
    geoms = []
    columns = {}
    for i, feature in enumerate(features):
        geoms.append(shape(feature["geometry"]) if feature.get("geometry") else None)
        props = feature.get("properties") or {}
        for key, value in props.items():
            columns.setdefault(key, [None] * i).append(value)
        for key in columns:
            if len(columns[key]) < i + 1:
                columns[key].append(None)
    if "cat" not in columns:
        columns["cat"] = list(range(1, len(geoms) + 1))
    return geoms, columns


def read_points(name, layer=1, where=None):
    """Read points as an (n, 2) array and their attribute columns."""
    geoms, columns = read_features(name, "point", layer, where)
    xy = np.array([[g.x, g.y] for g in geoms], dtype=float).reshape(-1, 2)
    return xy, columns


def _json_value(value):
    if value is None:
        return None
    if isinstance(value, (np.integer,)):
        return int(value)
    if isinstance(value, (np.floating, float)):
        value = float(value)
        return None if math.isnan(value) else value
    if isinstance(value, np.bool_):
        return int(value)
    return value


def write_features(name, geometries, columns=None, snap=-1, feature_type=None,
                   title=None, cats=None, history=False):
    """Write shapely geometries with attribute columns as a new vector map.

    ``columns`` is a dict of column name -> sequence of values (int, float,
    str or None); the map gets a ``cat`` column from ``cats`` (default 1..n).
    Polygons become areas with shared boundaries where they touch. The map is
    written under a temporary name and renamed when complete (:func:`staged`).
    ``history``: record the module's command line in the map's history
    (as ``gs.vector_history``, in the same v.support run as the title).
    """
    from shapely.geometry import mapping

    columns = dict(columns or {})
    n = len(geometries)
    cats = list(cats) if cats is not None else list(range(1, n + 1))
    if n == 0:  # v.in.ogr cannot import nothing: an empty map with its (empty) table
        with staged("vector", name, **_keyword_hooks(columns)) as tmp:
            gs.run_command("v.edit", map=tmp, tool="create", quiet=True, overwrite=True)
            _finish_vector(tmp, cats, columns, title, history)
        return name
    features = []
    for i, geom in enumerate(geometries):
        props = {"cat": int(cats[i])}
        for key, values in columns.items():
            props[key] = _json_value(values[i])
        features.append({"type": "Feature", "geometry": mapping(geom), "properties": props})
    path = temp_file(".geojson")
    with open(path, "w") as f:
        json.dump({"type": "FeatureCollection", "features": features}, f)
    kwargs = {"snap": snap, "key": "cat"}
    if feature_type:
        kwargs["type"] = feature_type
    # Geometry only: the table is written below with quoted column names, since
    # a column (e.g. of a user's map passed through) may be an SQL keyword that
    # v.in.ogr cannot create. Written under a temporary name, renamed when complete.
    with doing("writing vector map <{}>".format(name)), \
            staged("vector", name, **_keyword_hooks(columns)) as tmp:
        gs.run_command(
            "v.in.ogr", input=path, output=tmp, flags="ot", quiet=True,
            overwrite=True, **kwargs,
        )
        _finish_vector(tmp, cats, columns, title, history)
    return name


def _finish_vector(name, cats, columns, title, history=False):
    _write_table(name, cats, columns)
    support = {"comment": title} if title else {}
    if history and os.environ.get("CMDLINE"):
        support["cmdhist"] = os.environ["CMDLINE"]
    if support:
        gs.run_command("v.support", map=name, quiet=True, **support)


def area_boundaries(polygons):
    """Boundaries and inside points of polygons that share exact vertices where
    they touch, as GRASS builds areas from them.

    Returns ``(lines, points, owner)``: the boundary lines (every ring edge
    once, merged between nodes), one point inside every polygon part, and
    the index of the polygon each point belongs to; or None when the edges
    are not noded (two edges cross or overlap), which only a snapping import
    can mend, or when two polygons overlap (e.g. neighbouring cadastre
    footprints whose edges meet only at shared vertices): the shared area
    would be an area without a centroid, lost to both, where an import gives
    it to each of them.
    """
    import shapely

    parts, owner = shapely.get_parts(np.asarray(polygons, dtype=object), return_index=True)
    keep = ~shapely.is_empty(parts)
    parts, owner = parts[keep], owner[keep]
    a, b = shapely.STRtree(parts).query(parts, predicate="intersects")
    pair = (a < b) & (owner[a] != owner[b])
    if shapely.relate_pattern(parts[a[pair]], parts[b[pair]], "T********").any():
        return None  # their interiors meet
    rings = shapely.get_rings(parts)
    coords, ring = shapely.get_coordinates(rings, return_index=True)
    same = ring[1:] == ring[:-1]
    edges = np.hstack([coords[:-1][same], coords[1:][same]])
    flip = (edges[:, 0] > edges[:, 2]) | ((edges[:, 0] == edges[:, 2]) & (edges[:, 1] > edges[:, 3]))
    edges[flip] = edges[flip][:, [2, 3, 0, 1]]
    edges = np.unique(edges, axis=0)
    segments = shapely.multilinestrings(shapely.linestrings(edges.reshape(-1, 2, 2)))
    noded = shapely.node(segments)
    # crossings and T-junctions add pieces; overlaps take length away
    if shapely.get_num_geometries(noded) != len(edges) or \
            not math.isclose(shapely.length(noded), shapely.length(segments), rel_tol=1e-12):
        return None
    lines = shapely.get_parts(shapely.line_merge(segments))
    return lines, shapely.point_on_surface(parts), owner


def write_areas(name, polygons, columns=None, cats=None, title=None, history=False):
    """Write polygons as areas, like :func:`write_features`, but fast when they
    are noded (neighbours share their vertices exactly, no overlaps, as
    v.histo.subdivide's footprints): the boundaries go in as GRASS ASCII
    (v.in.ascii), which needs no snapping or cleaning. Polygons that are not
    noded go through :func:`write_features`.
    """
    columns = dict(columns or {})
    cats = list(cats) if cats is not None else list(range(1, len(polygons) + 1))
    found = area_boundaries(polygons) if len(polygons) else None
    if found is None:
        return write_features(name, polygons, columns, title=title, cats=cats, history=history)
    lines, points, owner = found
    import shapely

    text = []
    coords, line = shapely.get_coordinates(lines, return_index=True)
    starts = np.flatnonzero(np.r_[True, line[1:] != line[:-1]])
    ends = np.r_[starts[1:], len(line)]
    coords = coords.tolist()
    for a, b in zip(starts.tolist(), ends.tolist()):
        text.append("B {} 0\n".format(b - a))
        text.extend(" {!r} {!r}\n".format(x, y) for x, y in coords[a:b])
    for (x, y), i in zip(shapely.get_coordinates(points).tolist(), owner.tolist()):
        text.append("C 1 1\n {!r} {!r}\n 1 {}\n".format(x, y, int(cats[i])))
    path = temp_file(".txt")
    with open(path, "w") as f:
        f.write("".join(text))
    with doing("writing vector map <{}>".format(name)), \
            staged("vector", name, **_keyword_hooks(columns)) as tmp:
        gs.run_command("v.in.ascii", input=path, output=tmp, format="standard", flags="nt",
                       quiet=True, overwrite=True)
        _finish_vector(tmp, cats, columns, title, history)
    return name


def write_points(name, xy, columns=None, cats=None, title=None):
    """Write an (n, 2) array of coordinates as a new vector map of points.

    ``columns`` and ``cats`` as in :func:`write_features`.
    """
    from shapely.geometry import Point

    xy = np.asarray(xy, dtype=float).reshape(-1, 2)
    return write_features(name, [Point(x, y) for x, y in xy], columns, cats=cats, title=title)


def _sql_type(values):
    kinds = {type(_json_value(v)) for v in values if _json_value(v) is not None}
    if kinds and kinds <= {int, bool}:
        return "INTEGER"
    if kinds and kinds <= {int, float, bool}:
        return "DOUBLE PRECISION"
    return "TEXT"


def _sql_value(value, sql_type):
    value = _json_value(value)
    if value is None:
        return None
    if sql_type == "INTEGER":
        return int(value)
    if sql_type == "DOUBLE PRECISION":
        return float(value)
    return str(value)


def _sql_literal(value, sql_type):
    value = _sql_value(value, sql_type)
    if value is None:
        return "NULL"
    if sql_type == "TEXT":
        return "'{}'".format(value.replace("'", "''"))
    return repr(value)


def _sqlite_path(database, map_name):
    """The file of a SQLite database connection of vector map ``map_name``:
    GRASS's variables replaced, ``$MAP`` too (a database per map, as
    actinia's ephemeral mapsets have it: ``.../vector/$MAP/sqlite.db``)."""
    env = gs.gisenv()
    for key in ("GISDBASE", "LOCATION_NAME", "MAPSET"):
        database = database.replace("$" + key, env[key])
    return database.replace("$MAP", map_name.split("@")[0])


def _write_table(name, cats, columns):
    """Create the attribute table of a new map in one transaction and link it.

    Column names are quoted (a user's column passed through may be an SQL keyword).
    With GRASS's default SQLite driver the rows go in through Python's
    sqlite3 (a tenth of the time of db.execute on 17,000 rows); other
    drivers get the same statements through db.execute.
    """
    table = name.split("@")[0]
    types = {key: _sql_type(values) for key, values in columns.items()}
    definition = ", ".join(['"cat" INTEGER PRIMARY KEY'] + [
        '"{}" {}'.format(key, sql_type) for key, sql_type in types.items()])
    head = ['DROP TABLE IF EXISTS "{}"'.format(table),
            'CREATE TABLE "{}" ({})'.format(table, definition)]
    names = ", ".join(['"cat"'] + ['"{}"'.format(k) for k in columns])
    connection = gs.db_connection(force=True)
    if connection["driver"] == "sqlite":
        path = _sqlite_path(connection["database"], name)
        os.makedirs(os.path.dirname(path), exist_ok=True)
        rows = zip([int(c) for c in cats], *[
            [_sql_value(v, t) for v in columns[k]] for k, t in types.items()])
        insert = 'INSERT INTO "{}" ({}) VALUES ({})'.format(
            table, names, ", ".join("?" * (len(types) + 1)))
        db = sqlite3.connect(path)
        try:
            with db:
                for statement in head:
                    db.execute(statement)
                db.executemany(insert, rows)
        finally:
            db.close()
    else:
        lines = [h + ";" for h in head] + ["BEGIN TRANSACTION;"]
        for i, cat in enumerate(cats):
            values = [str(int(cat))] + [_sql_literal(columns[k][i], t) for k, t in types.items()]
            lines.append('INSERT INTO "{}" ({}) VALUES ({});'.format(
                table, names, ", ".join(values)))
        lines.append("COMMIT;")
        sql = temp_file(".sql")
        with open(sql, "w") as f:
            f.write("\n".join(lines) + "\n")
        gs.run_command("db.execute", input=sql, driver=connection["driver"],
                       database=connection["database"], quiet=True)
    _connect(name, table, connection)


def _connect(name, table, connection):
    gs.run_command("v.db.connect", map=name, table=table, key="cat", layer=1, flags="o",
                   driver=connection["driver"], database=connection["database"], quiet=True)


def _keyword_hooks(columns):
    """:func:`staged`'s hooks for a map with a column named by an SQL keyword,
    which g.rename cannot copy (it creates the table unquoted): the table is
    unlinked before the renaming, then renamed (quoted SQL) and linked again."""
    if not any(is_sql_keyword(c) for c in columns):
        return {}
    tables = []

    def before(temporary):
        tables.append(temporary)
        gs.run_command("v.db.connect", map=temporary, layer=1, flags="d", quiet=True)

    def after(name):
        connection = gs.db_connection(force=True)
        statements = ['DROP TABLE IF EXISTS "{}"'.format(name),
                      'ALTER TABLE "{}" RENAME TO "{}"'.format(tables[0], name)]
        if connection["driver"] == "sqlite":
            db = sqlite3.connect(_sqlite_path(connection["database"], name))
            try:
                with db:
                    for statement in statements:
                        db.execute(statement)
            finally:
                db.close()
        else:
            gs.write_command("db.execute", input="-", driver=connection["driver"],
                             database=connection["database"], quiet=True,
                             stdin=";\n".join(statements) + ";\n")
        _connect(name, name, connection)
    return {"before": before, "after": after}


def column_names(name, layer=1):
    """Attribute column names of a vector map (empty when it has no table)."""
    try:
        return list(gs.vector_columns(name, layer=layer).keys())
    except Exception:
        return []


def _column_kind(sql_type):
    """int, float or str: how values of a column of SQL type ``sql_type`` are read."""
    t = (sql_type or "").upper()
    if "INT" in t:
        return int
    if any(k in t for k in ("DOUBLE", "REAL", "FLOA", "NUMERIC", "DECIMAL")):
        return float
    return str


def _column_value(value, kind):
    """A table value as ``kind`` (int, float or str); None when NULL or not convertible."""
    if value is None:
        return None
    if kind is str:
        return value if isinstance(value, str) else str(value)
    try:
        return kind(value)
    except (TypeError, ValueError):
        return None


def _table_sqlite(database, table):
    """Column names, SQL types and rows of a table of a SQLite database, read
    directly (the GRASS database driver hands over rows one by one, which is
    slow for large tables)."""
    connection = sqlite3.connect(database)
    try:
        quoted = '"{}"'.format(table.replace('"', '""'))
        info = connection.execute("PRAGMA table_info({})".format(quoted)).fetchall()
        rows = connection.execute("SELECT * FROM {}".format(quoted)).fetchall()
    finally:
        connection.close()
    return [c[1] for c in info], [c[2] for c in info], rows


def _table_text(table_text, types_text, sep, null):
    """Column names, SQL types and rows of a table from v.db.select text
    (``sep`` between values, ``null`` for NULL) and v.info -c text."""
    types = {}
    for ln in types_text.splitlines():
        if "|" in ln:
            t, col = ln.split("|", 1)
            types[col.strip()] = t.strip().upper()
    lines = table_text.split("\n")      # not splitlines(): it splits at \x1e
    names = lines[0].rstrip("\r").split(sep) if lines else []
    rows = []
    for ln in lines[1:]:
        vals = ln.rstrip("\r").split(sep)
        if len(vals) == len(names):
            rows.append([None if v == null else v for v in vals])
    return names, [types.get(n, "TEXT") for n in names], rows


def _standard_points(text, layer):
    """Coordinates (x, y) and categories in ``layer`` of the points of a
    v.out.ascii standard format export (header, then per feature a line
    ``type coordinates categories``, its coordinate lines and its
    ``layer category`` lines)."""
    lines = text.splitlines()
    i = next((k for k, ln in enumerate(lines) if ln.strip() == "VERTI:"), len(lines)) + 1
    xy, cats = [], []
    while i < len(lines):
        head = lines[i].split()
        i += 1
        if not head:
            continue
        ncoor, ncats = int(head[1]), int(head[2]) if len(head) > 2 else 0
        xy.append(lines[i].split()[:2])
        found = []
        for ln in lines[i + ncoor:i + ncoor + ncats]:
            lay, cat = ln.split()[:2]
            if int(lay) == layer:
                found.append(int(cat))
        cats.append(found)
        i += ncoor + ncats
    return xy, cats


def read_areas(name, layer=1, cats=None, table=True):
    """Read the areas of a vector map fast, with their attribute columns.

    Same result as ``read_features(name, "area", layer)`` (one shapely
    geometry per category, areas of one category merged; a dict column ->
    list of values with ``cat``), but without the per-feature cost of OGR:
    the areas come as WKT from v.out.ascii, each one gets the categories of
    its centroid, and the table comes in one query (straight from the file
    of a SQLite database, else from v.db.select); the GRASS tools run side
    by side, writing to files. Areas shared by several categories
    (overlapping input polygons) belong to each of them. ``cats``: read
    only the areas of these categories (a sequence of integers);
    ``table=False``: no attribute columns (only ``cat``).
    """
    return finish_read_areas(start_read_areas(name, layer, cats, table))


def cat_ranges(cats):
    """Categories as GRASS's cats= text: ``1-3,7,9-10``."""
    values = sorted({int(c) for c in cats})
    ranges = []
    for value in values:
        if ranges and value == ranges[-1][1] + 1:
            ranges[-1][1] = value
        else:
            ranges.append([value, value])
    return ",".join(str(a) if a == b else "{}-{}".format(a, b) for a, b in ranges)


def _start_tools(commands, outdir):
    """Start GRASS tools ``{key: (module, options)}`` writing to files in ``outdir``."""
    procs = {}
    for k, (cmd, kw) in commands.items():
        with open(os.path.join(outdir, k + ".out"), "wb") as out, \
                open(os.path.join(outdir, k + ".err"), "wb") as err:
            procs[k] = gs.start_command(cmd, quiet=True, stdout=out, stderr=err, **kw)
    return procs


def start_read_areas(name, layer=1, cats=None, table=True):
    """Start reading the areas of a vector map (see :func:`read_areas`): the
    GRASS tools export the geometry in the background while the caller does
    other work (e.g. checks its inputs); :func:`finish_read_areas` waits for
    them and returns the result. Errors (e.g. no such map, then as
    :func:`require_vector`) are reported by :func:`finish_read_areas`."""
    only = {} if cats is None else {"cats": cat_ranges(cats) or "0"}
    commands = {
        "wkt": ("v.out.ascii", dict(input=name, layer=layer, type="area", format="wkt", **only)),
        # the centroids with all their categories
        "centroids": ("v.out.ascii", dict(input=name, layer=layer, type="centroid",
                                          format="standard", **only)),
    }
    outdir = os.path.dirname(temp_file())
    os.makedirs(outdir, exist_ok=True)
    job = {"name": name, "layer": layer, "outdir": outdir, "commands": commands,
           "procs": _start_tools(commands, outdir), "table": [],
           "cats": None if cats is None else {int(c) for c in cats}}
    # meanwhile a thread finds the attribute table and reads it if it is SQLite
    job["table_reader"] = threading.Thread(
        target=_find_table if table else lambda job: job["table"].extend([None, None, None]),
        args=(job,), daemon=True)
    job["table_reader"].start()
    return job


def _find_table(job):
    """The attribute table link of a :func:`start_read_areas` job, and the
    table itself when it is a SQLite file (into ``job["table"]``: link,
    table or None, error or None)."""
    try:
        link = gs.vector_db(job["name"], stderr=gs.PIPE).get(int(job["layer"]))
        table = None
        if link is not None and link["driver"] == "sqlite" and os.path.isfile(link["database"]):
            table = _table_sqlite(link["database"], link["table"])
        job["table"][:] = [link, table, None]
    except Exception as error:  # reported by finish_read_areas
        job["table"][:] = [None, None, error]


def finish_read_areas(job):
    """The areas and attribute columns of a :func:`start_read_areas` job."""
    import shapely

    name, layer, outdir = job["name"], job["layer"], job["outdir"]
    commands, procs = dict(job["commands"]), dict(job["procs"])
    sep, null = "\x1f", "\x1e"
    job["table_reader"].join()
    link, table, error = job["table"]
    direct = table is not None
    if link is not None and not direct:
        table_commands = {
            "table": ("v.db.select", dict(map=name, layer=layer, separator=sep, null_value=null)),
            "types": ("v.info", dict(map=name, layer=layer, flags="c"))}
        commands.update(table_commands)
        procs.update(_start_tools(table_commands, outdir))
    text = {}
    for k, proc in procs.items():
        proc.wait()
        if proc.returncode != 0:
            require_vector(name)
            with open(os.path.join(outdir, k + ".err"), "rb") as f:
                err = f.read()
            gs.fatal(_("Cannot read vector map <{}> ({}): {}").format(
                name, commands[k][0], gs.decode(err).strip()))
        with open(os.path.join(outdir, k + ".out"), "rb") as f:
            text[k] = gs.decode(f.read())
    if error is not None:
        raise error
    lines = [ln for ln in text["wkt"].splitlines() if ln.strip()]
    polys = shapely.from_wkt(np.array(lines, dtype=object)) if lines else np.array([])
    try:
        xy, cats = _standard_points(text["centroids"], int(layer))
    except (ValueError, IndexError):
        gs.fatal(_("Cannot read the centroids of vector map <{}>").format(name))
    by_cat = {}
    if len(polys) and xy:
        points = shapely.points(np.array(xy, dtype=float))
        pt, poly = shapely.STRtree(polys).query(points, predicate="within")
        for p, a in zip(pt.tolist(), poly.tolist()):
            for c in cats[p]:
                by_cat.setdefault(c, []).append(polys[a])
    wanted = job.get("cats")
    order = sorted(by_cat if wanted is None else set(by_cat) & wanted)
    geoms = []
    for c in order:
        parts = by_cat[c]
        geoms.append(parts[0] if len(parts) == 1 else shapely.union_all(parts))
    if link is not None and not direct:
        table = _table_text(text["table"], text["types"], sep, null)
    return geoms, _table_columns(link, table, order)


def _table_columns(link, table, order=None):
    """Columns (dict name -> list, ``cat`` first) of a table read by :func:`_table_sqlite`
    or :func:`_table_text`, for the categories ``order`` (default: every row's, ascending)."""
    if link is None:
        return {"cat": list(order or [])}
    names, sql_types, rows = table
    key = link["key"]
    kpos = names.index(key) if key in names else None
    by_key = {}
    for vals in rows:
        if kpos is not None and vals[kpos] is not None:
            by_key[int(vals[kpos])] = vals
    order = sorted(by_key) if order is None else order
    columns = {"cat": list(order)}
    for j, n in enumerate(names):
        if n == key:
            continue
        kind = _column_kind(sql_types[j])
        columns[n] = [_column_value(by_key[c][j], kind) if c in by_key else None for c in order]
    return columns


def read_table(name, layer=1):
    """The attribute table of a vector map: a dict column -> list of values, with ``cat``
    (ascending; empty when the map has no table). Values as in :func:`read_areas`."""
    job = {"name": name, "layer": layer, "table": []}
    _find_table(job)
    link, table, error = job["table"]
    if error is not None:
        require_vector(name)
        raise error
    if link is not None and table is None:
        sep, null = "\x1f", "\x1e"
        table = _table_text(
            gs.read_command("v.db.select", map=name, layer=layer, separator=sep,
                            null_value=null),
            gs.read_command("v.info", map=name, layer=layer, flags="c"), sep, null)
    return _table_columns(link, table)
