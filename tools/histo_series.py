#!/usr/bin/env python3
"""Run a map series: one process chain per sheet, on actinia or locally (issue 30).

    python3 tools/histo_series.py MANIFEST OUT [--server URL ... --credentials FILE] [--jobs N]

Each sheet of the manifest (reconstruction.series.manifest) gets the
process chain of the template (demo/series/sheet_chain.json) filled in
with its files and options. With ``--server`` every chain is sent to that
actinia (``processing_async_export`` in ``--location``, as the user of the
``--credentials`` file that ``tools/actinia/service.sh start DIR`` wrote,
DIR/credentials, readable by its owner only; several ``--server``: to each
in turn, e.g. the REST servers of several machines sharing Redis and the
GRASS database), at most ``--jobs`` at a time; the files the chains read
must lie in the service's work folder (README, "A map series on
actinia"). Without it the same chains run here, ``--jobs`` at a time, each
in a GRASS session of its own in a fresh mapset (the local fallback: the
same modules with the same parameters, the same exports; a mapset left by
a killed run is removed by the next). A failed sheet is tried once more; a
sheet that fails twice is reported with its module's ``ERROR:`` line and
the others go on. What finished is recorded in OUT/progress.jsonl, so a
rerun runs only the sheets that did not finish. Then the sheets' models
are merged into OUT/series.city.jsonl (reconstruction.series.merge).

Output: OUT/<sheet>/model.city.json, plots.geojson, footprints.geojson,
chain.json (the chain as sent); OUT/grid.geojson (the sheets' own areas);
OUT/series.city.jsonl and OUT/report.json. Exit status 0 when every sheet
finished, 1 when some failed (their report says why), 2 on bad input.
The suite is found as GRASS finds addons: ``--dist`` (default: $HISTO_DIST
or ./dist), whose scripts/ go on the PATH of the local runs. The driver
needs the suite's Python packages: started by a python3 without them
(Debian's), it runs itself again with the suite's venv ($HISTO_VENV, by
default ~/.local/share/histo/venv, made by ``make venv``), or says so.

Also: ``histo_series.py --run-steps CHAIN DIR``, inside a GRASS session,
runs one filled-in chain's steps and exports into DIR (what the local
fallback starts for each sheet); ``histo_series.py --sheet-settings
MANIFEST:SHEET GRID`` writes the grid of the sheet and its neighbours to
the file GRID and prints what ``demo/chain.sh OUT MANIFEST:SHEET`` needs to
run that sheet as its own chain, as shell assignments (chain.sh evaluates
them).
"""

import argparse
import base64
import concurrent.futures
import fcntl
import io
import itertools
import json
import os
import shlex
import shutil
import stat
import subprocess
import sys
import threading
import time
import urllib.error
import urllib.request
import zipfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
if ROOT not in sys.path:
    sys.path.insert(0, ROOT)
#: the suite's venv (Makefile: HISTO_VENV)
SUITE_VENV = os.environ.get("HISTO_VENV", os.path.expanduser("~/.local/share/histo/venv"))


def suite_python():
    """Run again with the suite's venv when this python3 lacks the suite's
    packages (Debian's python3: no orjson, or one without orjson.Fragment,
    which the merge writes with); None when this one has them."""
    try:
        import orjson

        from reconstruction.series import merge  # noqa: F401  (numpy, shapely, the writers)
        orjson.Fragment  # noqa: B018
        return None
    except (ImportError, AttributeError) as error:
        problem = "{}: {}".format(type(error).__name__, error)
    python = os.path.join(SUITE_VENV, "bin", "python3")
    if (os.path.exists(python) and not os.environ.get("HISTO_SERIES_RERUN")
            and os.path.realpath(sys.prefix) != os.path.realpath(SUITE_VENV)):
        os.environ["HISTO_SERIES_RERUN"] = "1"
        os.execv(python, [python, os.path.abspath(__file__)] + sys.argv[1:])
    return ("ERROR: {} lacks the suite's packages ({}): run the driver with the suite's venv, "
            "{} (make venv)".format(sys.executable, problem, python))


if __name__ == "__main__":
    _PROBLEM = suite_python()
    if _PROBLEM:
        print(_PROBLEM, file=sys.stderr)
        sys.exit(2)

from reconstruction.core import jsontext  # noqa: E402
from reconstruction.core.errors import InputError  # noqa: E402
from reconstruction.series import chain as series_chain  # noqa: E402
from reconstruction.series import edges, manifest, progress  # noqa: E402

TEMPLATE = os.path.join(ROOT, "demo", "series", "sheet_chain.json")
MODEL = "model.city.json"


class SheetFailed(Exception):
    """A sheet's chain failed: the message is the failing module's ERROR: line."""


def error_line(text, fallback):
    """The last ``ERROR:`` line of a module's messages (else ``fallback``)."""
    lines = (text or "").splitlines()
    starts = [k for k, ln in enumerate(lines) if ln.strip().startswith("ERROR:")]
    if not starts:
        return fallback
    k = starts[-1]
    out = [lines[k].strip()]
    for ln in lines[k + 1:]:         # GRASS wraps a long message on indented lines
        if not ln.startswith("       ") or not ln.strip():
            break
        out.append(ln.strip())
    return " ".join(out)


def write_grid(series, path):
    """The sheets' own areas (edges.grid_geojson) into the file ``path``."""
    with open(path, "w", encoding="utf-8") as f:
        json.dump(edges.grid_geojson(series), f)


def sheet_settings(spec, grid, template=TEMPLATE):
    """``--sheet-settings``: the settings of the sheet ``spec``
    (MANIFEST:SHEET) as shell assignments, the grid written to ``grid``;
    the options the manifest may set are the template's."""
    path, colon, name = spec.rpartition(":")
    if not colon or not path or not name:
        raise InputError("a sheet is given as MANIFEST:SHEET, not '{}'".format(spec))
    series = manifest.read_manifest(path)
    known = series_chain.read_template(template).get("defaults", {})
    grid = os.path.abspath(grid)
    sheet = series.sheet(name)
    with open(grid, "w", encoding="utf-8") as f:
        f.write(series_chain.sheet_grid(series, sheet))
    for key, value in series_chain.shell_settings(known, series, sheet, grid):
        if isinstance(value, tuple):
            print("{}=({})".format(key, " ".join(shlex.quote(v) for v in value)))
        else:
            print("{}={}".format(key, shlex.quote(value)))
    return 0


# ---------------------------------------------------------------------------
# Local fallback
# ---------------------------------------------------------------------------

def run_steps(chain_path, out):
    """Inside a GRASS session: run the steps of one chain and export its outputs into ``out``."""
    with open(chain_path, encoding="utf-8") as f:
        document = json.load(f)
    pc = series_chain.ProcessChain(os.path.basename(out), document)
    os.makedirs(out, exist_ok=True)
    exports = pc.exports()
    files = {e.name: os.path.join(out, e.file_name + ".part") for e in exports if e.kind == "file"}
    for step in pc.steps():
        command = step.command(files)
        proc = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        sys.stdout.write(proc.stdout)
        sys.stderr.write(proc.stderr)
        if proc.returncode:
            print(error_line(proc.stderr, "ERROR: {} failed (exit {})".format(
                step.module, proc.returncode)), file=sys.stderr)
            return 1
    for e in exports:
        if e.kind == "vector":
            subprocess.run(["v.out.ogr", "input=" + e.name, "output=" + os.path.join(
                out, e.file_name), "format=GeoJSON", "--quiet"], check=True)
        else:
            os.replace(files[e.name], os.path.join(out, e.file_name))
    return 0


def remove_left_mapsets(location):
    """Remove the sheets' mapsets a killed run left in ``location`` (every
    mapset but PERMANENT: the caller holds the output folder's lock, so no
    other run is using them). Returns their names."""
    left = sorted(n for n in os.listdir(location) if n != "PERMANENT"
                  and os.path.isdir(os.path.join(location, n)))
    for name in left:
        shutil.rmtree(os.path.join(location, name), ignore_errors=True)
    return left


def run_local(pc, sheet_dir, location, dist):
    """Run one chain in a fresh mapset of ``location`` (removed afterwards)."""
    chain_path = os.path.join(sheet_dir, "chain.json")
    mapset = os.path.join(location, "{}_{}_{}".format(pc.sheet, os.getpid(),
                                                       threading.get_ident()))
    env = dict(os.environ, GRASS_ADDON_BASE=dist,
               PATH=os.path.join(dist, "scripts") + os.pathsep + os.environ.get("PATH", ""))
    env.pop("GISRC", None)
    env.pop("GISBASE", None)
    shutil.rmtree(mapset, ignore_errors=True)
    out = os.path.join(sheet_dir, "local")
    shutil.rmtree(out, ignore_errors=True)
    try:
        proc = subprocess.run(["grass", "-c", mapset, "--exec", sys.executable, __file__,
                               "--run-steps", chain_path, out],
                              stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=env)
    finally:
        shutil.rmtree(mapset, ignore_errors=True)
    with open(os.path.join(sheet_dir, "log.txt"), "w", encoding="utf-8") as f:
        f.write(proc.stdout)
    if proc.returncode or not os.path.exists(os.path.join(out, "model")):
        raise SheetFailed(error_line(proc.stdout, "ERROR: the chain failed (exit {})".format(
            proc.returncode)))
    return {e.file_name: os.path.join(out, e.file_name) for e in pc.exports()}


# ---------------------------------------------------------------------------
# actinia
# ---------------------------------------------------------------------------

def read_credentials(path):
    """(user, password) of the credentials file ``path`` (or of the service
    folder ``path``: its ``credentials``) that ``tools/actinia/service.sh
    start`` wrote: JSON {"user": ..., "password": ...}, readable by its
    owner only (a file others can read is refused: its password is the
    service's)."""
    if os.path.isdir(path):
        path = os.path.join(path, "credentials")
    try:
        mode = os.stat(path).st_mode
    except OSError as e:
        raise InputError("Cannot read the credentials '{}': {}".format(path, e.strerror)) \
            from None
    if mode & (stat.S_IRWXG | stat.S_IRWXO):
        raise InputError("The credentials '{}' can be read by other users (mode {:04o}): "
                         "chmod 600 it".format(path, stat.S_IMODE(mode)))
    doc = jsontext.load(path, "credentials")
    if not isinstance(doc, dict) or not all(isinstance(doc.get(k), str) and doc[k]
                                            for k in ("user", "password")):
        raise InputError("The credentials '{}' hold no user and password".format(path))
    return doc["user"], doc["password"]


class Actinia:
    """A few calls of actinia's REST API (version 3), with basic authentication."""

    def __init__(self, url, user, password, location):
        self.url, self.location = url.rstrip("/"), location
        token = base64.b64encode("{}:{}".format(user, password).encode()).decode()
        self.headers = {"Authorization": "Basic " + token}

    def answer(self, url, data=None):
        """(HTTP status, body bytes) of a GET, or of a POST of the JSON of ``data``."""
        headers = dict(self.headers)
        if data is not None:
            headers["Content-Type"] = "application/json"
            data = json.dumps(data).encode()
        request = urllib.request.Request(url, data=data, headers=headers)
        try:
            with urllib.request.urlopen(request, timeout=120) as r:
                return r.status, r.read()
        except urllib.error.HTTPError as e:
            return e.code, e.read()

    def call(self, url, data=None):
        return self.answer(url, data)[1]

    def run(self, pc, sheet_dir, poll=1.0):
        answer = json.loads(self.call("{}/api/v3/locations/{}/processing_async_export".format(
            self.url, self.location), pc.document))
        status_url = answer.get("urls", {}).get("status")
        if not status_url:
            raise SheetFailed("ERROR: actinia refused the chain: {}".format(
                answer.get("message", answer)))
        while True:
            state = json.loads(self.call(status_url))
            if state.get("status") in ("finished", "error", "terminated"):
                break
            time.sleep(poll)
        with open(os.path.join(sheet_dir, "log.txt"), "w", encoding="utf-8") as f:
            json.dump(state, f, indent=1)
        if state["status"] != "finished":
            logs = state.get("process_log") or []
            text = "\n".join("\n".join(p.get("stderr") or []) for p in logs)
            raise SheetFailed(error_line(text, "ERROR: " + str(state.get("message"))))
        out = os.path.join(sheet_dir, "actinia")
        shutil.rmtree(out, ignore_errors=True)
        os.makedirs(out)
        for url in state["urls"]["resources"]:
            data = self.call(url)
            name = url.rsplit("/", 1)[1]
            if name.endswith(".zip"):
                # one file each, by the resource's name (a file export's
                # member carries the worker's temporary path)
                with zipfile.ZipFile(io.BytesIO(data)) as z:
                    members = [m for m in z.infolist() if not m.is_dir()]
                    if len(members) != 1:
                        raise SheetFailed("ERROR: actinia's <{}> holds {} files, not one".format(
                            name, len(members)))
                    with open(os.path.join(out, name[:-4]), "wb") as f:
                        f.write(z.read(members[0]))
            else:
                with open(os.path.join(out, name), "wb") as f:
                    f.write(data)
        found = {}
        for e in pc.exports():
            stem = e.name
            match = [n for n in os.listdir(out) if n.split(".")[0] == stem]
            if not match:
                raise SheetFailed("ERROR: actinia did not export <{}>".format(e.name))
            found[e.file_name] = os.path.join(out, match[0])
        return found


# ---------------------------------------------------------------------------
# The series
# ---------------------------------------------------------------------------

def make_location(path, epsg):
    if not os.path.isdir(os.path.join(path, "PERMANENT")):
        proc = subprocess.run(["grass", "-c", "EPSG:{}".format(epsg), path, "-e"],
                              stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        if proc.returncode:
            shutil.rmtree(path, ignore_errors=True)
            raise InputError("GRASS cannot make a location in EPSG:{}: {}".format(
                epsg, error_line(proc.stdout, proc.stdout.strip()[-300:])))


def lock_folder(out):
    """An exclusive lock of the output folder ``out`` (held until the
    driver ends): one run at a time, so what a run finds of another's
    (mapsets, .part files) was left by a killed one."""
    f = open(os.path.join(out, ".lock"), "w")
    try:
        fcntl.flock(f, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:
        f.close()
        raise InputError("Another run of the series is writing into '{}'".format(out)) from None
    return f


def merged(series, models, target):
    """Merge ``models`` into ``target`` through ``target``.part, removed
    whatever happens (no .part is left behind)."""
    from reconstruction.series import merge

    part = target + ".part"
    try:
        with open(part, "wb") as f:
            report = merge.merge_sheets(models, series, f)
        os.replace(part, target)
    finally:
        if os.path.exists(part):
            os.remove(part)
    return report


def remove_parts(out, series):
    """Remove the .part files a killed run left in the driver's own places
    of ``out`` (the merged series, the sheets' folders)."""
    folders = [out] + [os.path.join(out, s.name, sub) for s in series.sheets
                       for sub in ("", "local")]
    for folder in folders:
        if os.path.isdir(folder):
            for name in os.listdir(folder):
                if name.endswith(".part") and os.path.isfile(os.path.join(folder, name)):
                    os.remove(os.path.join(folder, name))


def run_series(args):
    series = manifest.read_manifest(args.manifest)
    template = series_chain.read_template(args.template)
    out = os.path.abspath(args.out)
    os.makedirs(out, exist_ok=True)
    held = lock_folder(out)      # noqa: F841  (released when the driver ends)
    remove_parts(out, series)
    write_grid(series, os.path.join(out, "grid.geojson"))
    chains = {s.name: series_chain.process_chain(template, series, s) for s in series.sheets}
    done = progress.Progress(os.path.join(out, "progress.jsonl"))
    todo = [s for s in series.sheets
            if not (done.done(s.name, progress.fingerprint(chains[s.name].document))
                    and os.path.exists(os.path.join(out, s.name, MODEL)))]
    skipped = len(series.sheets) - len(todo)
    if skipped:
        print("{} of {} sheets finished before: running the other {}".format(
            skipped, len(series.sheets), len(todo)), flush=True)
    if args.server:
        if not args.credentials:
            raise InputError("--server needs --credentials FILE: the service folder's "
                             "credentials, which tools/actinia/service.sh start wrote")
        user, password = read_credentials(args.credentials)
        servers = [Actinia(url, user, password, args.location) for url in args.server]
        turns = itertools.count()

        def runner(pc, sheet_dir):
            return servers[next(turns) % len(servers)].run(pc, sheet_dir)
    else:
        location = os.path.join(out, "grassdb", "series")
        make_location(location, series.epsg)
        left = remove_left_mapsets(location)
        if left:
            print("removed {} mapset(s) a killed run left: {}".format(len(left), ", ".join(left)),
                  flush=True)
        dist = os.path.abspath(args.dist)

        def runner(pc, sheet_dir):
            return run_local(pc, sheet_dir, location, dist)

    lock = threading.Lock()
    finished = [skipped]
    failures = {}

    def one(sheet):
        pc = chains[sheet.name]
        sheet_dir = os.path.join(out, sheet.name)
        os.makedirs(sheet_dir, exist_ok=True)
        with open(os.path.join(sheet_dir, "chain.json"), "w", encoding="utf-8") as f:
            json.dump(pc.document, f, indent=1)
        for attempt in (1, 2):
            start = time.time()
            try:
                files = runner(pc, sheet_dir)
            except (SheetFailed, OSError, ValueError) as e:
                message = str(e) if isinstance(e, SheetFailed) else "ERROR: {}".format(e)
                done.record(progress.Attempt(sheet.name, "failed", attempt,
                                             round(time.time() - start, 1),
                                             progress.fingerprint(pc.document), message))
                with lock:
                    print("sheet <{}> failed (attempt {}): {}".format(sheet.name, attempt,
                                                                      message), flush=True)
                continue
            for name, path in files.items():
                final = os.path.join(sheet_dir, MODEL if name == "model" else name)
                shutil.copyfile(path, final + ".part")
                os.replace(final + ".part", final)
            seconds = round(time.time() - start, 1)
            done.record(progress.Attempt(sheet.name, "done", attempt, seconds,
                                         progress.fingerprint(pc.document)))
            with lock:
                finished[0] += 1
                print("[{}/{}] sheet <{}> done in {} s".format(
                    finished[0], len(series.sheets), sheet.name, seconds), flush=True)
            return
        with lock:
            failures[sheet.name] = done.last[sheet.name].error

    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        list(pool.map(one, todo))

    models = [(s.name, os.path.join(out, s.name, MODEL)) for s in series.sheets
              if s.name not in failures and os.path.exists(os.path.join(out, s.name, MODEL))]
    report = {"sheets": len(series.sheets), "finished": len(models), "failed": failures}
    if models:
        target = os.path.join(out, "series.city.jsonl")
        done_merge = merged(series, models, target)
        report.update(buildings=done_merge.buildings, built=done_merge.built,
                      kept=done_merge.kept, dropped=done_merge.dropped,
                      renamed=done_merge.renamed)
        print("{} buildings of {} sheets merged into '{}'{}".format(
            done_merge.buildings, len(models), target,
            "; {} left out, overlapping a neighbour's".format(len(done_merge.dropped))
            if done_merge.dropped else ""), flush=True)
    with open(os.path.join(out, "report.json"), "w", encoding="utf-8") as f:
        json.dump(report, f, indent=1)
    for name, message in sorted(failures.items()):
        print("sheet <{}> failed: {}".format(name, message), flush=True)
    return 1 if failures else 0


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    if argv[:1] == ["--run-steps"]:
        return run_steps(argv[1], argv[2])
    if argv[:1] == ["--sheet-settings"] and len(argv) == 3:
        try:
            return sheet_settings(argv[1], argv[2])
        except InputError as e:
            print("ERROR: {}".format(e), file=sys.stderr)
            return 2
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("manifest", help="the series' manifest (JSON or CSV)")
    parser.add_argument("out", help="output folder")
    parser.add_argument("--server", action="append",
                        help="actinia's URL, or several, one --server each, used in turn "
                             "(default: run the chains here)")
    parser.add_argument("--credentials", metavar="FILE",
                        help="with --server: the service's credentials file (DIR/credentials "
                             "of tools/actinia/service.sh start DIR, or DIR itself)")
    parser.add_argument("--location", default="histo", help="actinia's location for the jobs")
    parser.add_argument("--jobs", type=int, default=2, help="sheets running at a time")
    parser.add_argument("--template", default=TEMPLATE, help="process chain template")
    parser.add_argument("--dist", default=os.environ.get("HISTO_DIST", os.path.join(ROOT, "dist")),
                        help="the staged suite (local runs)")
    args = parser.parse_args(argv)
    try:
        return run_series(args)
    except InputError as e:
        print("ERROR: {}".format(e), file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
