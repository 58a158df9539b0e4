"""Stage 4, v.histo.subdivide: plots -> individual building footprints.

The thesis's Section 3.3 (2D procedural modelling): every plot is repaired
and made disjoint from its neighbours, the aligned footprints keep their
place, and the rest is cut into buildings along the street by five cases
(rows of facades, corner buildings, courtyards, convex parts of concave
plots); the footprints share vertices and never overlap.

- ``stage``: the stage's entry point (:func:`subdivide`);
- ``plots``: plots repaired and disjoint, their street edges;
- ``cases``: the five cases on one plot; ``decomposition``: convex parts;
- ``aligned_footprints``: aligned footprints placed in their plots;
- ``convex_rings``: small convex geometry; ``noding``: shared vertices;
- ``invariants``: the guarantees of the footprints, as a check.
"""

from . import aligned_footprints, cases, convex_rings, decomposition, invariants, noding, plots
from . import stage
from .invariants import invariant_violations
from .stage import Subdivision, subdivide

__all__ = ["Subdivision", "aligned_footprints", "cases", "convex_rings", "decomposition",
           "invariant_violations", "invariants", "noding", "plots", "stage", "subdivide"]
