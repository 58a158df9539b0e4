"""Stage 2, v.histo.generalize: the building class -> generalised plot polygons.

The thesis's Sections 3.2.2-3.2.3: the raw plots (areas of the building
class) are generalised by an alpha shape (Arteaga 2013), then by lines
fitted along their edges and joined at right angles (buffered lines,
Commandeur 2012); their shape metrics are measured after each step and
their accuracy against ground truth points and polygons.

The module script reads its options with :func:`read_config` (a
:class:`GeneralizeConfig`), puts the maps it read into
:class:`GeneralizeInputs`, calls :func:`run` (a :class:`GeneralizedPlots`),
writes the plots and files and prints :func:`report`.

- ``config``: the options as a :class:`GeneralizeConfig`;
- ``pipeline``: the whole sequence (:func:`run`);
- ``stage``: raw plots (:func:`raw_plots`), their generalisation, metrics
  and scores (:func:`generalize_map`) and its records;
- ``operators``: alpha shapes, simplification, overlaps, the chain of steps
  (:func:`~.operators.generalize_plots`);
- ``lines``: the buffered lines (:func:`~.lines.buffered_lines`);
- ``shape_metrics``: shape metrics and turning-function distances;
- ``assessment``: precision, recall and F-score against ground truth points;
  objects (blocks, parcels) matched one-to-one by IoU: F-score, panoptic quality;
- ``report``: the messages after the run (:func:`report`, :func:`shell_figures`).
"""

from . import assessment, config, lines, operators, pipeline, scale, shape_metrics, stage
from .config import GeneralizeConfig, read_config
from .pipeline import GeneralizeInputs, run
from .report import report, shell_figures
from .stage import GeneralizedPlots, GeneralizeReport, RawPlots, generalize_map, raw_plots

__all__ = ["GeneralizeConfig", "GeneralizeInputs", "GeneralizeReport", "GeneralizedPlots",
           "RawPlots", "assessment", "config", "generalize_map", "lines", "operators", "pipeline",
           "raw_plots", "read_config", "report", "run", "shape_metrics", "shell_figures",
           "stage"]
