"""Stage 1, r.histo.classify: a scanned map's colours -> a classified raster.

The thesis's Section 3.2.1 (after Gobbi et al. 2019): the map is segmented
with i.segment, its parameters tuned on the map itself; each segment gets
object features; a random forest, kNN and SVM vote on its class from the
training points; text and symbols are removed, filled with the classes
around them.

The module script reads its options with :func:`read_config` (a
:class:`ClassifyConfig`), binds what it reads from GRASS into
:class:`ClassifyInputs`, calls :func:`run` (a :class:`ClassifyResult`),
writes the rasters and prints :func:`report`.

- ``config``: the options as a :class:`ClassifyConfig`;
- ``pipeline``: the whole sequence (:func:`run`): the training points
  checked, the whole map or its tiles classified;
- ``stage``: a map classified whole (:func:`classify_map`) and the records
  (:class:`Training`, :class:`ClassifyResult`, the removal's rule);
- ``segments``: the pure steps (tuning criteria, features, classifiers);
- ``removal``: text and symbols removed, thin parts and specks too, and the
  holes refilled from around them;
- ``tiling`` and ``tiled``: a large sheet tuned on a sample of windows and
  classified in tiles, in bounded memory;
- ``report``: the messages after the run (:func:`report`).
"""

from . import config, pipeline, removal, segments, stage, tiled, tiling
from .config import ClassifyConfig, read_config
from .pipeline import ClassifyInputs, run
from .report import report, rule_message
from .stage import ClassifyResult, Training, classify_map

__all__ = ["ClassifyConfig", "ClassifyInputs", "ClassifyResult", "Training", "classify_map",
           "config", "pipeline", "read_config", "removal", "report", "rule_message", "run",
           "segments", "stage", "tiled", "tiling"]
