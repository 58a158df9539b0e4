"""Stage 1, r.histo.classify: a scanned map's colours -> a classified raster.

The thesis's Section 3.2.1 (after Gobbi et al. 2019): the map is segmented
with i.segment, its parameters tuned on the map itself; each segment gets
object features; a random forest, kNN and SVM vote on its class from the
training points; text and symbols are removed, filled with the classes
around them.

- ``stage``: the stage's entry point (:func:`classify_map`) and its records;
- ``segments``: the pure steps (tuning criteria, features, classifiers,
  removal of classes);
- ``tiling`` and ``tiled``: a large sheet tuned on a sample of windows and
  classified in tiles, in bounded memory.
"""

from . import segments, stage, tiled, tiling
from .stage import ClassifyConfig, ClassifyResult, Training, classify_map

__all__ = ["ClassifyConfig", "ClassifyResult", "Training", "classify_map", "segments", "stage",
           "tiled", "tiling"]
