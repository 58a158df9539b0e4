#!/usr/bin/env python3
"""Checksums of every output of the histo chains, to prove a refactor changes none.

    python3 tools/output_checksums.py --dist DIST --shared SHARED --work WORKDIR
                                      [--only NAME,...] [--no-dumps]

Run from a checkout (the scripts of its demo/ folder and its testsuite/ are
the ones run) with the venv's python3 (~/.local/share/histo/venv/bin/python3),
DIST the suite staged by `make build` from that checkout, SHARED the folder
holding data/ and schemas/ (../shared beside the checkout). Each set runs in a
fresh GRASS location under WORKDIR/NAME (removed first), with the suite of
DIST on the module path as the project's tests put it there
(GRASS_ADDON_BASE=DIST, DIST/scripts and DIST/bin first on PATH, the venv's
bin/ next, no GRASS session of the caller):

- ``demo``: the synthetic demo, ``bash demo/run_demo.sh WORKDIR/demo/out``
  with HISTO_DIST=DIST, as ``make demo`` runs it;
- ``delft1961``: demo/delft_1961.sh in a new EPSG:28992 location, as
  testsuite/test_delft_chain.py starts it (testsuite/chain_testing.run_chain);
- ``brussels1924``: demo/brussels_1924.sh in a new EPSG:3857 location
  (testsuite/test_brussels_chain.py);
- ``lod2``: the v.histo.lod2 invocations of its acceptance tests, with the
  same inputs and options, one fresh mapset per test (as the ``mapset``
  fixture of conftest.py) of one EPSG:28992 location; see LOD2_CASES.

It then prints one line per output, sorted, and writes them to
WORKDIR/checksums.txt:

    <set>/<relative name> <sha256>[ [png]]

- every file a set writes (CityJSON, CityJSONSeq, JSON, CSV and text reports,
  the -v report v.histo.lod2 prints, PNG pictures), named by its path in the
  set's output folder. PNG lines end in " [png]": the pictures are rendered
  (cairo, VTK/OSMesa off screen) and may change with the renderer and its
  libraries, not only with the suite;
- every raster and vector map the set leaves in its GRASS location (every
  mapset), as ``<set>/grass/<mapset>/raster/<map>``,
  ``<set>/grass/<mapset>/vector/<map>/geometry`` and ``.../<map>/table``: the
  hash of a deterministic text dump (dump_raster, dump_vector_geometry,
  dump_vector_table), written to WORKDIR/NAME/dumps/ too (unless
  --no-dumps), so that two runs' dumps can be diffed where a checksum
  differs.

What varies from run to run, legitimately, is left out or normalised (see
NORMALISE and the dump functions): wall times (times.txt, the "seconds" keys
and "time" rows of the chain reports), absolute paths (the schemas folder in
report.json, the database path of a vector map), dates and the user's name in
GRASS headers, the random part of the layer names the modules leave in the
database links (TEMP_LAYER_NAME). Everything else is hashed byte for byte.
Not hashed: the maps' history (r.info -h, v.info -h: dates, command lines
with paths), the region left in each mapset, the modules' messages.

The ``lod2`` set leaves out the v.histo.lod2 tests that are not acceptance
tests (synthetic footprints, bad inputs) and the checks of the acceptance
tests themselves (val3dity, schemas, figures): only their outputs are hashed.

The tool itself uses Python's standard library only; it talks to GRASS by
running its modules. The inputs that the v.histo.lod2 acceptance tests make
with numpy, shapely or the library come from the tests' own functions
(``footprint_sets``, ``tower_district``, imported from their modules) or,
for the cross-validation folds, the test's few lines of numpy, run in a
child python3, the venv's (INPUT_HELPERS).

WORKDIR/summary.txt gets each set's wall time and its number of outputs.
"""

import argparse
import hashlib
import json
import os
import re
import shutil
import sqlite3
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SETS = ("demo", "delft1961", "brussels1924", "lod2")
PNG_MARK = "[png]"

#: rasters with more cells than this are dumped by r.stats -c (their values
#: and counts) instead of r.out.ascii (every cell)
HUGE_RASTER_CELLS = 20_000_000


# ---------------------------------------------------------------------------
# Small helpers
# ---------------------------------------------------------------------------

def log(message):
    """Progress on standard error (standard output is for the checksum lines)."""
    print(message, file=sys.stderr, flush=True)


def sha256_bytes(data):
    return hashlib.sha256(data).hexdigest()


def sha256_file(path):
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for chunk in iter(lambda: f.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()


def run_logged(command, log_path, **kwargs):
    """Run a command, its output appended to log_path; raise with the log's end when it fails."""
    with open(log_path, "ab") as out:
        out.write(("\n$ " + " ".join(command) + "\n").encode())
        out.flush()
        proc = subprocess.run(command, stdout=out, stderr=subprocess.STDOUT, **kwargs)
    if proc.returncode != 0:
        with open(log_path, "rb") as f:
            tail = f.read()[-4000:].decode(errors="replace")
        raise RuntimeError("{} failed (exit {}); the end of {}:\n{}".format(
            " ".join(command), proc.returncode, log_path, tail))


# ---------------------------------------------------------------------------
# The environment of the runs: as the tests set it up
# ---------------------------------------------------------------------------

def clean_env(dist, venv_bin):
    """The caller's environment without any GRASS session (testsuite/test_demo.py's
    _clean_env), HISTO_DIST=DIST and the venv's bin/ first on PATH (the modules run
    as `#!/usr/bin/env python3`: conftest.py and `make demo` do the same)."""
    env = {k: v for k, v in os.environ.items()
           if not (k.startswith("GRASS_") or k in ("GISRC", "GISBASE", "GIS_LOCK"))}
    env["HISTO_DIST"] = dist
    path = env.get("PATH", "").split(os.pathsep)
    if path[0] != venv_bin:
        env["PATH"] = os.pathsep.join([venv_bin] + path)
    return env


def suite_env(env, dist):
    """``env`` with the staged suite on the module path, ahead of any installed
    copy (chain_testing.run_chain, conftest.py's grass_session, the README)."""
    env = dict(env)
    env["GRASS_ADDON_BASE"] = dist
    env["PATH"] = os.pathsep.join([os.path.join(dist, "scripts"), os.path.join(dist, "bin"),
                                   env["PATH"]])
    return env


def new_location(path, epsg, env, log_path):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    run_logged(["grass", "-c", "EPSG:{}".format(epsg), path, "-e"], log_path, env=env)


# ---------------------------------------------------------------------------
# The sets: each runs in WORKDIR/NAME and returns (output folder, GRASS location)
# ---------------------------------------------------------------------------

def run_demo(ctx, folder):
    """`make demo`: bash demo/run_demo.sh DEMO_DIR (it makes its own location
    DEMO_DIR/grassdata/histo_demo and puts DIST on the module path itself)."""
    out = os.path.join(folder, "out")
    run_logged(["bash", os.path.join(ROOT, "demo", "run_demo.sh"), out],
               os.path.join(folder, "log.txt"), cwd=ROOT, env=ctx.env)
    return out, os.path.join(out, "grassdata", "histo_demo")


def run_chain(ctx, folder, script, epsg):
    """testsuite/chain_testing.run_chain: demo/SCRIPT in a new EPSG location
    FOLDER/grassdata/chain, outputs in FOLDER/out."""
    log_path = os.path.join(folder, "log.txt")
    location = os.path.join(folder, "grassdata", "chain")
    new_location(location, epsg, ctx.env, log_path)
    out = os.path.join(folder, "out")
    run_logged(["grass", os.path.join(location, "PERMANENT"), "--exec", "bash",
                os.path.join(ROOT, "demo", script), out, ctx.data],
               log_path, cwd=ROOT, env=suite_env(ctx.env, ctx.dist))
    return out, location


def run_delft1961(ctx, folder):
    return run_chain(ctx, folder, "delft_1961.sh", 28992)


def run_brussels1924(ctx, folder):
    return run_chain(ctx, folder, "brussels_1924.sh", 3857)


def run_lod2(ctx, folder):
    """The v.histo.lod2 acceptance runs (LOD2_CASES), in one GRASS session of a
    new EPSG:28992 location (conftest.py's grass_session), this script's
    --inner-lod2 mode doing the work inside it."""
    log_path = os.path.join(folder, "log.txt")
    location = os.path.join(folder, "grassdata", "lod2")
    new_location(location, 28992, ctx.env, log_path)
    out = os.path.join(folder, "out")
    os.makedirs(out)
    run_logged(["grass", os.path.join(location, "PERMANENT"), "--exec", sys.executable,
                os.path.abspath(__file__), "--inner-lod2", out, ctx.data],
               log_path, cwd=ROOT, env=suite_env(ctx.env, ctx.dist))
    return out, location


RUNNERS = {"demo": run_demo, "delft1961": run_delft1961, "brussels1924": run_brussels1924,
           "lod2": run_lod2}


# ---------------------------------------------------------------------------
# Output files: hashed as they are, except what varies run to run
# ---------------------------------------------------------------------------

def _json_without(path, removals):
    """The JSON document at ``path`` without the keys ``removals`` (paths of keys,
    e.g. ("cityjson", "schema")), re-serialised in its own key order."""
    with open(path) as f:
        doc = json.load(f)
    for keys in removals:
        node = doc
        for key in keys[:-1]:
            node = node.get(key, {}) if isinstance(node, dict) else {}
        if isinstance(node, dict):
            node.pop(keys[-1], None)
    return json.dumps(doc, indent=1, ensure_ascii=False).encode()


def _text_without_lines(path, prefix):
    with open(path, "rb") as f:
        return b"".join(line for line in f if not line.startswith(prefix))


#: file name -> (what is done, why); None: excluded. Every other file is hashed byte for byte.
NORMALISE = {
    # steps.sh's `timed`: one line "STAGE MILLISECONDS" per stage, nothing else
    "times.txt": (None, "wall times of the stages only"),
    # demo/chain_report.write (delft_report.py, brussels_report.py): the stages'
    # wall times, and the absolute path of the schemas folder (--shared)
    "report.json": (lambda p: _json_without(p, [("seconds",), ("total_seconds",),
                                                ("cityjson", "schema")]),
                    "keys seconds, total_seconds (wall times) and cityjson.schema "
                    "(absolute path of the schemas folder) removed"),
    # its text table: the rows "time STAGE (s)" and "time total (s)"
    "report.txt": (lambda p: _text_without_lines(p, b"time "),
                   "rows starting with 'time ' (wall times) removed"),
}


def hash_files(set_name, out, dumps):
    """{line name: checksum line} of every file under ``out`` (not the GRASS
    location out/grassdata, not hidden files), and the notes of what was
    excluded or normalised."""
    lines, notes = {}, []
    for base, dirs, files in os.walk(out):
        dirs[:] = sorted(d for d in dirs if not d.startswith(".") and
                         not (base == out and d == "grassdata"))
        for name in sorted(files):
            if name.startswith("."):
                continue
            path = os.path.join(base, name)
            rel = os.path.relpath(path, out).replace(os.sep, "/")
            key = "{}/{}".format(set_name, rel)
            rule = NORMALISE.get(name)
            if rule is not None and rule[0] is None:
                notes.append("{}: excluded ({})".format(key, rule[1]))
                continue
            if rule is not None:
                data = rule[0](path)
                digest = sha256_bytes(data)
                notes.append("{}: normalised ({})".format(key, rule[1]))
                if dumps:
                    target = os.path.join(dumps, "files", rel)
                    os.makedirs(os.path.dirname(target), exist_ok=True)
                    with open(target, "wb") as f:
                        f.write(data)
            else:
                digest = sha256_file(path)
            mark = " " + PNG_MARK if name.lower().endswith(".png") else ""
            lines[key] = "{} {}{}".format(key, digest, mark)
    return lines, notes


# ---------------------------------------------------------------------------
# GRASS maps: a text dump of each, made inside a GRASS session of the location
# (this script's --inner-dump mode)
# ---------------------------------------------------------------------------

def grass_text(*command, env=None):
    """Standard output of a GRASS module (text); raises with its error output when it fails."""
    proc = subprocess.run(list(command), capture_output=True, env=env)
    if proc.returncode != 0:
        raise RuntimeError("{} failed: {}".format(" ".join(command),
                                                  proc.stderr.decode(errors="replace")))
    return proc.stdout.decode()


class Dump:
    """The sha256 of a text dump, written to a file too when ``path`` is given."""

    def __init__(self, path):
        self.hash = hashlib.sha256()
        self.file = None
        if path:
            os.makedirs(os.path.dirname(path), exist_ok=True)
            self.file = open(path, "wb")

    def write(self, data):
        if isinstance(data, str):
            data = data.encode()
        self.hash.update(data)
        if self.file:
            self.file.write(data)

    def section(self, title):
        self.write("### {}\n".format(title))

    def stream(self, command, env=None, skip_header=None):
        """Write a module's standard output as it comes (big maps). ``skip_header``:
        a function telling which lines of the output's header to leave out, the
        header ending at the first line it returns "end" for."""
        proc = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                env=env)
        if skip_header:
            for line in proc.stdout:
                verdict = skip_header(line)
                if verdict != "skip":
                    self.write(line)
                if verdict == "end":
                    break
        for chunk in iter(lambda: proc.stdout.read(1 << 20), b""):
            self.write(chunk)
        err = proc.stderr.read()
        if proc.wait() != 0:
            raise RuntimeError("{} failed: {}".format(" ".join(command),
                                                      err.decode(errors="replace")))

    def hexdigest(self):
        if self.file:
            self.file.close()
        return self.hash.hexdigest()


REGION = "histo_output_checksums"


def dump_raster(name, path):
    """A raster: r.info -g (extent, resolution, cell type, number of categories),
    its category labels (r.category), colour table (r.colors.out) and every cell
    (r.out.ascii, floating-point cells with 17 significant digits, i.e. exactly),
    all in the raster's own region (a saved region, through WIND_OVERRIDE: the
    region the chain left does not matter and is not changed). Rasters of more
    than HUGE_RASTER_CELLS cells: r.stats -c (values and counts) instead of
    every cell. Not in the dump: r.info's history and dates."""
    grass_text("g.region", "-u", "raster=" + name, "save=" + REGION, "--overwrite", "--quiet")
    env = dict(os.environ, WIND_OVERRIDE=REGION)
    try:
        dump = Dump(path)
        info = grass_text("r.info", "-g", name, env=env)
        dump.section("r.info -g")
        dump.write(info)
        dump.section("r.category")
        dump.write(grass_text("r.category", "map=" + name, env=env))
        dump.section("r.colors.out")
        dump.write(grass_text("r.colors.out", "map=" + name, env=env))
        cells = int(dict(line.split("=", 1) for line in info.split())["cells"])
        if cells > HUGE_RASTER_CELLS:
            dump.section("r.stats -c")
            dump.stream(["r.stats", "-c", "input=" + name, "--quiet"], env=env)
        else:
            dump.section("r.out.ascii precision=17")
            dump.stream(["r.out.ascii", "input=" + name, "precision=17", "--quiet"], env=env)
        return dump.hexdigest()
    finally:
        grass_text("g.remove", "-f", "type=region", "name=" + REGION, "--quiet")


#: lines of v.out.ascii's header that say when and by whom the map was made
VECTOR_HEADER_SKIPPED = (b"MAP DATE:", b"DIGIT DATE:", b"DIGIT NAME:")


def _vector_header(line):
    if line.startswith(b"VERTI:"):
        return "end"
    return "skip" if line.startswith(VECTOR_HEADER_SKIPPED) else "keep"


def dump_vector_geometry(name, path):
    """A vector map's geometry: v.out.ascii format=standard layer=-1 (every
    feature, with or without categories), coordinates with 16 decimals (exactly),
    its header without MAP DATE, DIGIT DATE and DIGIT NAME (the date of the run
    and the user's name)."""
    dump = Dump(path)
    dump.stream(["v.out.ascii", "input=" + name, "format=standard", "layer=-1",
                 "precision=16", "--quiet"], skip_header=_vector_header)
    return dump.hexdigest()


#: the modules write a map under a temporary name (grassio's tmp_histo_out_ and 32 random
#: hex digits) and rename it: its database link keeps that name as the layer's name
TEMP_LAYER_NAME = re.compile(r"(tmp_histo_[a-z_]*?)[0-9a-f]{32}")


def dump_vector_table(name, path):
    """A vector map's attribute tables, every layer: the layer, table and key
    column, the column types (v.info -c), v.db.select of the table with its rows
    sorted by the key column (cat), and, for SQLite tables, the rows read with
    Python's sqlite3 in key order with repr() of every value (v.db.select writes
    doubles with 15 significant digits; repr is exact). Not in the dump: the
    database's path (absolute, under WORKDIR), and the random part of a layer
    name that is a temporary map's name (TEMP_LAYER_NAME)."""
    dump = Dump(path)
    links = [line.split("|") for line in
             grass_text("v.db.connect", "-g", "map=" + name, "separator=|").splitlines()
             if line.strip()]
    if not links:
        dump.write("(no attribute table)\n")
    for layer, table, key, database, driver in links:
        dump.section("layer {} table {} key {} driver {}".format(
            TEMP_LAYER_NAME.sub(r"\1<random>", layer), table, key, driver))
        number = layer.split("/")[0]
        dump.section("v.info -c")
        dump.write(grass_text("v.info", "-c", "map=" + name, "layer=" + number))
        rows = grass_text("v.db.select", "map=" + name, "layer=" + number, "separator=|",
                          "null_value=NULL").splitlines()
        header, rows = rows[0], rows[1:]
        at = header.split("|").index(key)
        rows.sort(key=lambda row: int(row.split("|")[at]))
        dump.section("v.db.select, sorted by {}".format(key))
        dump.write("\n".join([header] + rows) + "\n")
        if driver == "sqlite":
            dump.section("sqlite3, repr, ordered by {}".format(key))
            db = sqlite3.connect("file:{}?mode=ro".format(database), uri=True)
            try:
                for row in db.execute('SELECT * FROM "{}" ORDER BY "{}"'.format(table, key)):
                    dump.write(repr(row) + "\n")
            finally:
                db.close()
    return dump.hexdigest()


def inner_dump(result_path, dumps):
    """(Inside a GRASS session of the location) {name: sha256} of every map of
    every mapset, written as JSON to ``result_path``."""
    mapsets = sorted(grass_text("g.mapsets", "-l", "separator=newline").split())
    start = grass_text("g.gisenv", "get=MAPSET").strip()
    result = {}

    def dump_path(*parts):
        return os.path.join(dumps, *parts) + ".txt" if dumps else None

    for mapset in mapsets:
        grass_text("g.mapset", "mapset=" + mapset, "--quiet")
        for name in sorted(grass_text("g.list", "type=raster", "mapset=.").split()):
            key = "grass/{}/raster/{}".format(mapset, name)
            result[key] = dump_raster(name, dump_path(mapset, "raster", name))
        for name in sorted(grass_text("g.list", "type=vector", "mapset=.").split()):
            key = "grass/{}/vector/{}/".format(mapset, name)
            result[key + "geometry"] = dump_vector_geometry(
                name, dump_path(mapset, "vector", name + ".geometry"))
            result[key + "table"] = dump_vector_table(
                name, dump_path(mapset, "vector", name + ".table"))
    grass_text("g.mapset", "mapset=" + start, "--quiet")
    with open(result_path, "w") as f:
        json.dump(result, f, indent=1, sort_keys=True)


def hash_location(ctx, set_name, location, folder, dumps):
    """{line name: checksum line} of every map of the location (inner_dump in a
    GRASS session of it)."""
    result_path = os.path.join(folder, "maps.json")
    command = ["grass", os.path.join(location, "PERMANENT"), "--exec", sys.executable,
               os.path.abspath(__file__), "--inner-dump", result_path]
    if dumps:
        command.append(os.path.join(dumps, "grass"))
    run_logged(command, os.path.join(folder, "dump-log.txt"), cwd=ROOT, env=ctx.env)
    with open(result_path) as f:
        result = json.load(f)
    return {"{}/{}".format(set_name, k): "{}/{} {}".format(set_name, k, v)
            for k, v in result.items()}


# ---------------------------------------------------------------------------
# The v.histo.lod2 acceptance runs (inside a GRASS session: --inner-lod2)
# ---------------------------------------------------------------------------

#: the inputs some tests make with numpy, shapely or the library: run by a child
#: python3 (the venv's), with the tests' own functions where they have them
INPUT_HELPERS = {
    # test_v_histo_lod2_existing.py: the fixture `aligned` (map fp), and the
    # footprints of test_copied_footprints_are_not_built_even_all_of_them
    # (only) and test_copied_buildings_give_measured_heights_to_the_generated
    # (fp_noh); written as their import_footprints writes them
    "bag": r'''
import json, os, sys
root, sample, out = sys.argv[1:4]
sys.path[:0] = [root, os.path.join(root, "testsuite"), os.path.join(root, "v.histo.lod2", "testsuite")]
from shapely.geometry import mapping
from test_v_histo_lod2_existing import footprint_sets

for name, (polygons, props) in footprint_sets(sample).items():
    feats = [{"type": "Feature", "properties": p, "geometry": mapping(g)}
             for g, p in zip(polygons, props)]
    with open(os.path.join(out, name + ".geojson"), "w") as f:
        json.dump({"type": "FeatureCollection", "features": feats}, f)
''',
    # test_v_histo_lod2_heights_acceptance.py: tower_district(), written as
    # histo_testing.import_features writes features
    "tower": r'''
import json, os, sys
out, root = sys.argv[1:3]
sys.path[:0] = [root, os.path.join(root, "testsuite"), os.path.join(root, "v.histo.lod2", "testsuite")]
from test_v_histo_lod2_heights_acceptance import tower_district

feats, aligned = tower_district()
for name, features in (("district", feats), ("district_al", aligned)):
    with open(os.path.join(out, name + ".geojson"), "w") as f:
        json.dump({"type": "FeatureCollection", "features": features}, f)
''',
    # test_height_cross_validation_on_delft_1880_through_the_module: the 5
    # folds (seed 0) of the 674 aligned footprints with known heights, from
    # its v.db.select rows on standard input; prints the categories kept in
    # aligned= for each fold (JSON)
    "folds": r'''
import json, sys
import numpy as np
rows = sys.stdin.read().split()
table = np.array([[float(v) if v else np.nan for i, v in enumerate(r.split("|")) if i != 1]
                  for r in rows])
cat, r25, r99, g = table.T
known = (r25 - g > 0) & np.isfinite(r99)
cat = cat[known].astype(int)
assert len(cat) == 674, len(cat)
rng = np.random.default_rng(0)
fold = np.empty(len(cat), dtype=int)
fold[rng.permutation(len(cat))] = np.arange(len(cat)) % 5
print(json.dumps([",".join(str(c) for c in cat[fold != f]) for f in range(5)]))
''',
}


def helper(name, *args, stdin=None):
    """Run INPUT_HELPERS[name] in a child python3; its standard output."""
    proc = subprocess.run([sys.executable, "-c", INPUT_HELPERS[name]] + list(args),
                          input=stdin, capture_output=True, text=True, cwd=ROOT)
    if proc.returncode != 0:
        raise RuntimeError("input helper {} failed:\n{}".format(name, proc.stderr))
    return proc.stdout


def module_args(module, flags="", overwrite=False, **options):
    """A GRASS command line as grass.script builds it from keywords."""
    command = [module] + (["-" + flags] if flags else [])
    command += ["{}={}".format(k, v) for k, v in options.items()]
    return command + (["--overwrite"] if overwrite else [])


def gmod(module, flags="", **options):
    """Run a GRASS module quietly (as the tests' gs.run_command(..., quiet=True))."""
    return grass_text(*module_args(module, flags, **options), "--quiet")


class Lod2Runs:
    """The acceptance tests' runs of v.histo.lod2, one mapset each (LOD2_CASES)."""

    #: the footprint tables' columns as the tests rename them for GRASS
    DELFT_COLUMNS = ("cat,idx,feaid,bouwjaar,g00,g01,g02,g03,g04,g05,buffer_val,nr_ground,"
                     "h_building,h_attic,roof_025,roof_099")
    BXL_COLUMNS = ("cat,idx,feaid,g00,g01,g02,g03,g04,g05,buffer_val,nr_ground,h_building,"
                   "h_attic,roof_025,roof_099,bouwjaar")
    DELFT_1880_COLUMNS = ("cat,idx,feaid,bouwjaar,pand_id,roof_025,roof_075,roof_099,g00,g01,"
                          "g02,g03,g04,g05,nr_ground")
    D1880_COLUMNS = ("cat,idx,feaid,bouwjaar,pand_id,roof_0_25,roof_0_75,roof_0_99,ground_0_0,"
                     "ground_0_1,ground_0_2,ground_0_3,ground_0_4,ground_0_5,nr_ground")
    BAG_FORMS = ("3dbag_b2.city.json", "3dbag_b2.city.jsonl")

    def __init__(self, out, data):
        self.out, self.data = out, data
        self.bag = os.path.join(data, "3dbag_sample")
        self.inputs = os.path.join(out, ".inputs")  # hidden: inputs, not outputs
        os.makedirs(self.inputs)
        self.case = None

    # -- the test fixtures' work ------------------------------------------------
    def mapset(self, case):
        """A fresh mapset for one test (conftest.py's ``mapset``); its files go to OUT/CASE."""
        self.case = case
        gmod("g.mapset", flags="c", mapset=case)
        os.makedirs(os.path.join(self.out, case))

    def path(self, name):
        return os.path.join(self.out, self.case, name)

    def shp(self, *parts):
        path = os.path.join(self.data, *parts)
        if not os.path.exists(path):
            raise RuntimeError("{} not found".format(path))
        return path

    def import_shp(self, path, name, columns=None):
        kw = {"columns": columns} if columns else {}
        gmod("v.in.ogr", flags="o", input=path, output=name, **kw)
        return name

    def import_geojson(self, name, map_name=None):
        return self.import_shp(os.path.join(self.inputs, name + ".geojson"), map_name or name)

    def lod2(self, output, flags="", env=None, **options):
        """v.histo.lod2 ... output=OUT/CASE/OUTPUT; with -v its report (standard
        output) goes to OUT/CASE/OUTPUT.stdout.txt."""
        command = module_args("v.histo.lod2", flags, output=self.path(output), **options)
        proc = subprocess.run(command, capture_output=True, env=env)
        if proc.returncode != 0:
            raise RuntimeError("{} failed:\n{}".format(" ".join(command),
                                                       proc.stderr.decode(errors="replace")))
        if "v" in flags:
            with open(self.path(output + ".stdout.txt"), "wb") as f:
                f.write(proc.stdout)

    # -- test_v_histo_lod2.py ---------------------------------------------------
    def thesis_footprints(self, case, folder, columns, year, crs):
        """test_acceptance_thesis_footprints[CASE]."""
        self.mapset("thesis_" + case)
        self.import_shp(self.shp(folder, "thesis_output", "final_all_footprints.shp"), case,
                        columns)
        self.lod2(case + ".city.json", flags="v", input=case, ground_column="g02", year=year,
                  crs=crs, seed=1)

    def delft_1880_val3dity(self):
        """test_acceptance_delft_1880_val3dity (val3dity itself is a check, not an output)."""
        self.mapset("delft_1880_val3dity")
        self.import_shp(self.shp("delft_1880", "final_all_footprints.shp"), "d1880",
                        self.DELFT_1880_COLUMNS)
        for column, value in (("h_building", "roof_025 - g02"),
                              ("h_attic", "roof_099 - roof_025")):
            gmod("v.db.addcolumn", map="d1880", columns=column + " double precision")
            gmod("v.db.update", map="d1880", column=column, query_column=value)
        self.lod2("d1880.city.json", flags="v", input="d1880", ground_column="g02", year=1900,
                  crs=7415, seed=1)

    # -- test_v_histo_lod2_existing.py (acceptance) -------------------------------
    def existing(self, case):
        """A mapset with the fixture ``aligned``: the map fp."""
        self.mapset("existing_" + case)
        return self.import_geojson("fp")

    def form(self, k):
        return os.path.join(self.bag, self.BAG_FORMS[k])

    def existing_runs(self):
        for k, form in enumerate(self.BAG_FORMS):
            # test_acceptance_copies_both_bag_buildings[FORM]
            fp = self.existing("copies_" + form.rsplit(".", 1)[1])
            self.lod2("merged.city.json", flags="v", input=fp, existing=self.form(k),
                      id_column="pand_id", crs=7415, roof="gable")
        # test_ids_that_match_nothing_merge_by_geometry_with_counts
        fp = self.existing("wrong_id")
        self.lod2("geom.city.json", input=fp, existing=self.form(1), id_column="wrong_id")
        # test_no_id_column_matches_by_geometry_and_prefix_matches_by_id: the
        # test's third run overwrites p.city.json; here it has a file of its own
        fp = self.existing("id_prefix")
        self.lod2("g.city.json", input=fp, existing=self.form(0))
        self.lod2("p.city.json", input=fp, existing=self.form(0), id_column="pand_id",
                  id_prefix="NL.IMBAG.Pand.")
        self.lod2("p_nl_bag.city.json", input=fp, existing=self.form(0), id_column="pand_id",
                  id_prefix="NL.BAG.")
        # test_overlap_threshold
        fp = self.existing("overlap")
        self.lod2("o.city.json", input=fp, existing=self.form(0), overlap=1)
        # test_existing_lod_not_in_the_model_copies_the_highest
        fp = self.existing("lod")
        self.lod2("l.city.json", input=fp, existing=self.form(0), existing_lod="1.2")
        # test_cityjsonseq_collected_equals_the_single_file
        fp = self.existing("cityjsonseq")
        for name, fmt in (("m.city.json", "cityjson"), ("m.city.jsonl", "cityjsonseq")):
            self.lod2(name, input=fp, existing=self.form(0), id_column="pand_id", format=fmt)
        # test_render_with_copied_buildings_and_the_map
        fp = self.existing("render")
        gmod("g.region", n=446600, s=446510, e=85060, w=84950, res=1)
        for band, value in (("red", 20), ("green", 200), ("blue", 20)):
            gmod("r.mapcalc", expression="m.{} = {}".format(band, value))
        env = {k: v for k, v in os.environ.items() if k != "DISPLAY"}
        self.lod2("m.city.json", input=fp, existing=self.form(0), render=self.path("m.png"),
                  map="m.red,m.green,m.blue", view="120,50", env=env)
        # test_copied_footprints_are_not_built_even_all_of_them
        self.mapset("existing_only")
        self.import_geojson("only")
        self.lod2("only.city.json", flags="v", input="only", existing=self.form(1))
        # test_copied_buildings_give_measured_heights_to_the_generated
        self.mapset("existing_heights")
        self.import_geojson("fp_noh")
        self.lod2("h.city.json", input="fp_noh", existing=self.form(0), roof="flat")

    # -- test_v_histo_lod2_heights_acceptance.py ----------------------------------
    def height_cross_validation(self):
        """test_height_cross_validation_on_delft_1880_through_the_module: 2 rules x 5 folds."""
        self.mapset("heights_cross_validation")
        folder = "delft_1880"
        self.import_shp(self.shp(folder, "final_all_footprints.shp"), "d1880",
                        self.D1880_COLUMNS)
        self.import_shp(self.shp(folder, "final_plots_delft_1880.shp"), "p1880", "cat,feaid")
        rows = grass_text("v.db.select", "map=d1880",
                          "columns=cat,pand_id,roof_0_25,roof_0_99,ground_0_2",
                          "where=pand_id IS NOT NULL", "-c", "separator=|")
        keep = json.loads(helper("folds", stdin=rows))
        for rule in ("plot", "robust"):
            for f in range(5):
                gmod("v.extract", input="d1880", output="al", cats=keep[f], overwrite=True)
                self.lod2("cv_{}_{}.json".format(rule, f), flags="s", input="d1880",
                          aligned="al", plots="p1880", plot_column="feaid", height_rule=rule,
                          ground_column="ground_0_2", roof="hip", year=1880)

    def outlier_guard(self):
        """test_outlier_guard_a_tower_does_not_spread_its_height."""
        self.mapset("heights_outlier_guard")
        fp, al = self.import_geojson("district"), self.import_geojson("district_al")
        for rule in ("robust", "plot"):
            self.lod2("{}.json".format(rule), input=fp, aligned=al, height_rule=rule,
                      ground=1.0, roof="gable")

    def street_edges(self, case, folder, columns, year):
        """test_street_edges_on_the_thesis_footprints[CASE]."""
        self.mapset("street_edges_" + case)
        name = self.import_shp(self.shp(folder, "thesis_output", "final_all_footprints.shp"),
                               case, columns)
        for flags in ("", "s"):
            self.lod2("{}{}.json".format(case, flags), flags=flags, input=name,
                      ground_column="g02", year=year, seed=1)

    def streets_classified(self):
        """test_streets_from_the_classified_delft_1961_map: r.histo.classify's
        classes (a map of this mapset, hashed too) as streets=."""
        self.mapset("streets_classified")
        folder = "delft_1961_subset"
        gmod("r.in.gdal", flags="o", input=self.shp(folder, "input", "delft_1961.tif"),
             output="delft")
        bands = sorted(grass_text("g.list", "type=raster", "pattern=delft.*",
                                  "mapset=.").split(),
                       key=lambda n: (0 if ".red" in n or n.endswith(".1") else
                                      1 if ".green" in n or n.endswith(".2") else 2))
        red, green, blue = bands
        gmod("g.region", raster=red)
        self.import_shp(self.shp(folder, "input", "training_points_delft_1961.shp"), "training")
        gmod("r.histo.classify", input="{},{},{}".format(red, green, blue), training="training",
             output="cls", remove="2,6", min_area=200, separate=1, nprocs=2, seed=1)
        name = self.import_shp(self.shp(folder, "thesis_output", "final_all_footprints.shp"),
                               "delft", self.DELFT_COLUMNS)
        for extra in ({}, {"streets": "cls", "street_classes": "3,4"}):
            self.lod2("st{}.json".format(len(extra)), input=name, ground_column="g02",
                      year=1961, seed=1, **extra)

    def all(self):
        helper("bag", ROOT, self.bag, self.inputs)
        helper("tower", self.inputs, ROOT)
        for step, run in LOD2_CASES:
            start = time.time()
            run(self)
            log("  lod2: {} done in {:.0f} s".format(step, time.time() - start))


#: (test, run) in the order they run; every mapset is named after its test
LOD2_CASES = [
    ("test_acceptance_thesis_footprints[delft]", lambda r: r.thesis_footprints(
        "delft", "delft_1961_subset", Lod2Runs.DELFT_COLUMNS, 1961, 7415)),
    ("test_acceptance_thesis_footprints[brussels]", lambda r: r.thesis_footprints(
        "brussels", "bxls_1924", Lod2Runs.BXL_COLUMNS, 1924, 31370)),
    ("test_acceptance_delft_1880_val3dity", Lod2Runs.delft_1880_val3dity),
    ("test_v_histo_lod2_existing.py, acceptance tests", Lod2Runs.existing_runs),
    ("test_height_cross_validation_on_delft_1880_through_the_module",
     Lod2Runs.height_cross_validation),
    ("test_outlier_guard_a_tower_does_not_spread_its_height", Lod2Runs.outlier_guard),
    ("test_street_edges_on_the_thesis_footprints[delft]", lambda r: r.street_edges(
        "delft", "delft_1961_subset", Lod2Runs.DELFT_COLUMNS, 1961)),
    ("test_street_edges_on_the_thesis_footprints[brussels]", lambda r: r.street_edges(
        "brussels", "bxls_1924", Lod2Runs.BXL_COLUMNS, 1924)),
    ("test_streets_from_the_classified_delft_1961_map", Lod2Runs.streets_classified),
]


# ---------------------------------------------------------------------------
# Main
# ---------------------------------------------------------------------------

class Context:
    def __init__(self, args):
        self.dist = os.path.abspath(args.dist)
        self.shared = os.path.abspath(args.shared)
        self.data = os.path.join(self.shared, "data")
        self.work = os.path.abspath(args.work)
        venv_bin = os.path.join(os.path.abspath(args.venv), "bin")
        self.env = clean_env(self.dist, venv_bin)


def default_venv():
    """The venv this script runs with, else the project's default one (Makefile's VENV)."""
    if sys.prefix != sys.base_prefix:
        return sys.prefix
    return os.path.expanduser("~/.local/share/histo/venv")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--dist", required=True, help="the staged suite (make build's dist/)")
    parser.add_argument("--shared", required=True, help="the shared folder (data/, schemas/)")
    parser.add_argument("--work", required=True, help="scratch folder for the runs")
    parser.add_argument("--only", help="comma-separated sets, of: " + ",".join(SETS))
    parser.add_argument("--venv", default=default_venv(),
                        help="the venv the modules run with (default: %(default)s)")
    parser.add_argument("--no-dumps", action="store_true",
                        help="do not keep the text dumps of the maps in WORKDIR/NAME/dumps")
    args = parser.parse_args()
    sets = SETS if not args.only else [s.strip() for s in args.only.split(",") if s.strip()]
    unknown = [s for s in sets if s not in SETS]
    if unknown:
        parser.error("unknown set(s) {}; the sets are {}".format(",".join(unknown),
                                                                ",".join(SETS)))
    ctx = Context(args)
    if not os.path.isdir(os.path.join(ctx.dist, "scripts")):
        parser.error("no suite staged in '{}' (make build)".format(ctx.dist))
    if not os.path.isdir(ctx.data):
        parser.error("no data/ folder in '{}'".format(ctx.shared))
    if not shutil.which("grass"):
        parser.error("GRASS GIS (grass) is not on the PATH")
    os.makedirs(ctx.work, exist_ok=True)

    lines, notes, summary = {}, [], []
    for name in sets:
        folder = os.path.join(ctx.work, name)
        shutil.rmtree(folder, ignore_errors=True)      # a fresh location every time
        os.makedirs(folder)
        dumps = None if args.no_dumps else os.path.join(folder, "dumps")
        log("--- {}: running (log: {})".format(name, os.path.join(folder, "log.txt")))
        start = time.time()
        out, location = RUNNERS[name](ctx, folder)
        ran = time.time() - start
        log("--- {}: ran in {:.0f} s; hashing".format(name, ran))
        files, set_notes = hash_files(name, out, dumps)
        maps = hash_location(ctx, name, location, folder, dumps)
        total = time.time() - start
        lines.update(files)
        lines.update(maps)
        notes += set_notes
        summary.append("{}: run {:.0f} s, hashing {:.0f} s, {} files + {} map dumps = {} "
                       "outputs".format(name, ran, total - ran, len(files), len(maps),
                                        len(files) + len(maps)))
        log("--- " + summary[-1])

    text = "".join(lines[k] + "\n" for k in sorted(lines))
    sys.stdout.write(text)
    with open(os.path.join(ctx.work, "checksums.txt"), "w") as f:
        f.write(text)
    with open(os.path.join(ctx.work, "summary.txt"), "w") as f:
        f.write("\n".join(summary + [""] + notes) + "\n")
    for line in notes:
        log(line)


if __name__ == "__main__":
    if len(sys.argv) > 1 and sys.argv[1] == "--inner-dump":
        inner_dump(sys.argv[2], sys.argv[3] if len(sys.argv) > 3 else None)
    elif len(sys.argv) > 1 and sys.argv[1] == "--inner-lod2":
        Lod2Runs(sys.argv[2], sys.argv[3]).all()
    else:
        main()
