"""Stage 2, v.histo.generalize: the building class -> generalised plot polygons.

The thesis's Sections 3.2.2-3.2.3: the raw plots (areas of the building
class) are generalised by an alpha shape (Arteaga 2013), then by lines
fitted along their edges and joined at right angles (buffered lines,
Commandeur 2012); their shape metrics are measured after each step and
their accuracy against ground truth points and polygons.

- ``stage``: the stage's entry point (:func:`generalize_map`);
- ``operators``: alpha shapes, buffered lines, simplification, overlaps;
- ``shape_metrics``: shape metrics and turning-function distances;
- ``assessment``: precision, recall and F-score against ground truth.
"""

from . import assessment, operators, shape_metrics, stage
from .stage import generalize_map

__all__ = ["assessment", "generalize_map", "operators", "shape_metrics", "stage"]
