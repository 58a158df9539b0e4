"""Stage 4, v.histo.subdivide: plots -> individual building footprints.

The thesis's Section 3.3 (2D procedural modelling): every plot is repaired
and made disjoint from its neighbours, the aligned footprints keep their
place, and the rest is cut into buildings along the street by five cases
(rows of facades, corner buildings, courtyards, convex parts of concave
plots); the footprints share vertices and never overlap.

The module's sequence, in three calls: :func:`read_config` (g.parser's
options -> :class:`SubdivisionConfig`), :func:`run` (:class:`SubdivisionInputs`,
made by :func:`read_inputs` from the maps read -> :class:`SubdivisionResult`:
the footprints and their table) and :func:`report` (the messages;
:func:`announce`: those before the work).

- ``config``: :class:`SubdivisionConfig` and :func:`read_config`;
- ``pipeline``: :func:`run`, its inputs and result;
- ``report``: :func:`report` and :func:`announce`, the messages of a run;
- ``stage``: the subdivision itself (:func:`subdivide`);
- ``plots``: plots repaired and disjoint, their street edges;
- ``cases``: the five cases on one plot; ``decomposition``: convex parts;
- ``aligned_footprints``: aligned footprints placed in their plots;
- ``convex_rings``: small convex geometry; ``noding``: shared vertices;
- ``invariants``: the guarantees of the footprints, as a check;
- ``previous``: a dynamic chain's earlier epoch, its footprints kept where
  the plots did not change;
- ``drawn``: the units a map draws inside its plots (parcels, buildings),
  read from its lines (map=).
"""

from . import aligned_footprints, cases, config, convex_rings, decomposition, drawn, invariants
from . import noding
from . import pipeline, plots, previous, stage
from .config import SubdivisionConfig, read_config
from .invariants import invariant_violations
from .pipeline import (SubdivisionInputs, SubdivisionResult, plots_with_category, read_inputs,
                       read_previous, run)
from .previous import PreviousEpoch
from .report import announce, report
from .stage import Subdivision, subdivide

__all__ = ["PreviousEpoch", "Subdivision", "SubdivisionConfig", "SubdivisionInputs", "SubdivisionResult",
           "aligned_footprints", "announce", "cases", "config", "convex_rings", "decomposition", "drawn",
           "invariant_violations", "invariants", "noding", "pipeline", "plots",
           "plots_with_category", "previous", "read_config", "read_inputs", "read_previous",
           "report", "run", "stage",
           "subdivide"]
