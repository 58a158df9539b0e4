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
- ``progress``: what finished, so that a rerun goes on where it stopped.
"""

from . import chain, edges, manifest, merge, progress
from .chain import ProcessChain, Step, process_chain, read_template
from .edges import owner_sheet
from .manifest import Series, Sheet, read_manifest
from .merge import MergeReport, merge_sheets
from .progress import Progress

__all__ = ["MergeReport", "ProcessChain", "Progress", "Series", "Sheet", "Step", "chain", "edges",
           "manifest", "merge", "merge_sheets", "owner_sheet", "process_chain", "progress",
           "read_manifest", "read_template"]
