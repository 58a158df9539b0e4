"""A map series: many sheets of one town or country, one process chain each (issue 30).

- ``manifest``: the series as a user describes it (a JSON or CSV file: each
  sheet's map, training points, footprints, extent, year and options), read
  into :class:`Series` and :class:`Sheet`, each error an :class:`InputError`;
- ``chain``: the process chain of one sheet (actinia's process chain
  format, version 1) filled in from a template, and its steps as plain
  command lines for the local fallback;
- ``edges``: which sheet builds a plot that a sheet edge cuts (the sheet
  that holds its larger part) and the grid of sheets the chain needs for it;
- ``merge``: the sheets' models merged into one CityJSONSeq of the series,
  every building once, none overlapping another sheet's;
- ``progress``: what finished, so that a rerun goes on where it stopped;
- ``gate``: what the series service lets through to actinia (routes, process
  chains, file paths in the series' work folder).

``merge`` (and with it the CityJSON writers, orjson, shapely) is imported
when first used (``reconstruction.series.merge``, ``merge_sheets`` and
``MergeReport`` are there all the same, outside ``__all__``): the gate runs
in actinia's own venv, which has not all of them.
"""

import importlib

from . import chain, edges, gate, manifest, progress
from .chain import ProcessChain, Step, process_chain, read_template
from .edges import owner_sheet
from .manifest import Series, Sheet, read_manifest
from .progress import Progress


def __getattr__(name):
    if name == "merge":
        return importlib.import_module(".merge", __name__)
    if name in ("MergeReport", "merge_sheets"):
        return getattr(importlib.import_module(".merge", __name__), name)
    raise AttributeError("module {!r} has no attribute {!r}".format(__name__, name))

__all__ = ["ProcessChain", "Progress", "Series", "Sheet", "Step", "chain", "edges", "gate",
           "manifest", "owner_sheet", "process_chain", "progress", "read_manifest",
           "read_template"]
