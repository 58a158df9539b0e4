"""The process chain of one sheet, filled in from a template.

The template (``demo/series/sheet_chain.json``) is a process chain in
actinia's format (version 1: a list of steps, each a GRASS module with its
``inputs``, ``outputs`` and ``flags``) whose texts hold placeholders
``{{name}}``; its ``defaults`` give the options a manifest may change.
:func:`process_chain` fills it in for one sheet: the chain actinia runs.
A step with ``"for_each": "neighbour"`` is repeated for every neighbouring
sheet (``{{neighbour.map}}``, ``{{neighbour.index}}``). The same filled-in
chain is what the local fallback runs (:meth:`ProcessChain.steps`: each
step as a command line), so both run the same modules with the same
parameters.

Outputs marked ``export`` are what a sheet gives back: vector maps (as
GeoJSON) and files written by a module (``$file::name``, actinia's
placeholder for a file of the job).
"""

import copy
import json
import re
from dataclasses import dataclass

from ..core import jsontext
from ..core.errors import InputError
from . import edges

_PLACEHOLDER = re.compile(r"\{\{([A-Za-z_][A-Za-z0-9_.]*)\}\}")
#: actinia's placeholder of a file a step writes: ``$file::name``
FILE = "$file::"


@dataclass(frozen=True)
class Step:
    """One step as a command line: the module, its ``key=value`` parameters
    (files still as ``$file::name``) and its flags."""
    id: str
    module: str
    params: tuple
    flags: str = ""

    def command(self, files):
        """The command line, with the files of ``files`` (name -> path)."""
        args = [self.module]
        for key, value in self.params:
            if value.startswith(FILE):
                value = files[value[len(FILE):]]
            args.append("{}={}".format(key, value))
        if self.flags:
            args.append("-" + self.flags)
        return args


@dataclass(frozen=True)
class Export:
    """What a sheet gives back: a vector map (``kind`` "vector", written as
    GeoJSON) or a file a module wrote (``kind`` "file")."""
    name: str
    kind: str
    file_name: str


@dataclass(frozen=True)
class ProcessChain:
    """The filled-in chain of one sheet: the actinia document and what it exports."""
    sheet: str
    document: dict

    def steps(self):
        """Every step as a :class:`Step`, in order."""
        out = []
        for entry in self.document["list"]:
            params = [(i["param"], str(i["value"])) for i in entry.get("inputs", ())]
            params += [(o["param"], str(o["value"])) for o in entry.get("outputs", ())]
            out.append(Step(entry["id"], entry["module"], tuple(params), entry.get("flags", "")))
        return out

    def exports(self):
        """What the chain exports (:class:`Export`), in order."""
        out = []
        for entry in self.document["list"]:
            for o in entry.get("outputs", ()):
                if "export" not in o:
                    continue
                value = str(o["value"])
                if o["export"]["type"] == "file":
                    name = value[len(FILE):]
                    out.append(Export(name, "file", name))
                else:
                    out.append(Export(value, "vector", value + ".geojson"))
        return out


def read_template(path):
    """The template (a dict) of a JSON file; InputError when it is not one."""
    doc = jsontext.load(path, "chain template")
    if not isinstance(doc, dict) or not isinstance(doc.get("list"), list) \
            or not isinstance(doc.get("defaults", {}), dict):
        raise InputError("The chain template '{}' has no list of steps".format(path))
    return doc


def sheet_grid(series, sheet):
    """The grid a sheet's chain reads (:func:`.edges.grid_geojson` of the
    sheet and its neighbours) as compact GeoJSON text: the chain carries it
    itself (``v.in.ogr`` reads GeoJSON text as a data source), so a job
    needs no file of the driver's, and its size grows with the neighbours,
    not with the series."""
    near = (sheet,) + series.neighbours(sheet)
    return json.dumps(edges.grid_geojson(series, near), separators=(",", ":"))


def values(series, sheet):
    """The placeholders' values of one sheet: the template's defaults are
    filled in by :func:`process_chain`, these come from the manifest.
    ``patch`` is the module that puts each band of the sheet's map and its
    neighbours' into one map of the chain's region: ``r.patch``, or with no
    neighbour (one sheet, ``"margin": 0``) ``r.resample``, as r.patch needs
    two maps."""
    west, south, east, north = edges.chain_region(series, sheet)
    out = {"name": sheet.name, "map": sheet.map, "training": sheet.training,
           "footprints": sheet.footprints, "year": str(sheet.year), "seed": str(series.seed),
           "grid": sheet_grid(series, sheet),
           "owner_query": edges.owner_query(edges.sheet_index(series, sheet)),
           "west": _text(west), "south": _text(south), "east": _text(east),
           "north": _text(north)}
    bands = ["sheet"] + ["n{}".format(k) for k in range(len(series.neighbours(sheet)))]
    out["patch"] = "r.patch" if len(bands) > 1 else "r.resample"
    for b in (1, 2, 3):
        out["patch_{}".format(b)] = ",".join("{}.{}".format(m, b) for m in bands)
    return out


def _text(v):
    return repr(float(v)).rstrip("0").rstrip(".") if float(v) != int(v) else str(int(v))


def _fill(obj, known, where):
    if isinstance(obj, str):
        def one(m):
            if m.group(1) not in known:
                raise InputError("{}: unknown placeholder {{{{{}}}}}".format(where, m.group(1)))
            return known[m.group(1)]
        return _PLACEHOLDER.sub(one, obj)
    if isinstance(obj, list):
        return [_fill(v, known, where) for v in obj]
    if isinstance(obj, dict):
        return {k: _fill(v, known, where) for k, v in obj.items()}
    return obj


def sheet_options(known, series, sheet):
    """The options the manifest sets for ``sheet`` (name -> text): the
    series' options, then the sheet's own (the last wins), each one of
    ``known`` (the names of the chain's options: the template's
    ``defaults``); an unknown one is an InputError."""
    options = {}
    for key, value in series.options + sheet.options:
        if key not in known:
            raise InputError("sheet <{}>: unknown option <{}> (the chain's options: {})".format(
                sheet.name, key, ", ".join(sorted(known))))
        options[key] = value
    return options


def shell_settings(known, series, sheet, grid_file):
    """What ``demo/chain.sh`` needs to run ``sheet`` as its own chain, as
    (shell variable, text or tuple of texts): the sheet's files, its
    neighbours' maps (``SHEET_NEIGHBOURS``), the region of its chain
    (``SHEET_REGION``: west, south, east, north), the query of the plots it
    owns, its year and seed, and each option the manifest sets, as the
    upper-case variable of chain.sh's own parameter (``min_area`` ->
    ``MIN_AREA``); the options it does not set keep chain.sh's values."""
    v = values(series, sheet)
    out = [("SHEET_NAME", sheet.name), ("SHEET_MAP", v["map"]),
           ("SHEET_NEIGHBOURS", tuple(s.map for s in series.neighbours(sheet))),
           ("SHEET_PATCH", v["patch"]),
           ("SHEET_REGION", tuple(v[k] for k in ("west", "south", "east", "north"))),
           ("SHEET_TRAINING", v["training"]), ("SHEET_FOOTPRINTS", v["footprints"]),
           ("SHEET_GRID", grid_file), ("SHEET_OWNER", v["owner_query"]),
           ("YEAR", v["year"]), ("SEED", v["seed"])]
    out += [(k.upper(), value) for k, value in sorted(sheet_options(known, series,
                                                                    sheet).items())]
    return out


def process_chain(template, series, sheet):
    """The :class:`ProcessChain` of ``sheet``: ``template`` (a dict, as
    :func:`read_template` gives it) filled in with the sheet's values, the
    template's defaults, the series' options and the sheet's own (the last
    wins). An option the template does not know is an InputError."""
    where = "sheet <{}>".format(sheet.name)
    defaults = {k: str(v) for k, v in template.get("defaults", {}).items()}
    known = dict(defaults)
    known.update(sheet_options(defaults, series, sheet))
    known.update(values(series, sheet))
    steps = []
    for entry in template["list"]:
        if entry.get("for_each") == "neighbour":
            for k, other in enumerate(series.neighbours(sheet)):
                here = dict(known, **{"neighbour.map": other.map, "neighbour.index": str(k)})
                step = {key: v for key, v in entry.items() if key != "for_each"}
                steps.append(_fill(step, here, where))
        elif "for_each" in entry:
            raise InputError("{}: a template step repeats for each {}: only 'neighbour' is "
                             "known".format(where, json.dumps(entry["for_each"])))
        else:
            steps.append(_fill(entry, known, where))
    return ProcessChain(sheet.name, {"version": "1", "list": copy.deepcopy(steps)})
