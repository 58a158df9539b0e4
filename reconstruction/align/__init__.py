"""Stage 3, v.histo.align: the current footprints that already stood at the map's date.

The thesis's Section 3.3.1: today's footprints built before the map's year
(``bouwjaar``) are matched one-to-many with the historical plots they lie
in, optionally after correcting the map's offset; each kept footprint gets
its ``plot`` and ``similarity``.

The module's sequence, in three calls: :func:`read_config` (g.parser's
options -> :class:`AlignmentConfig`), :func:`run` (:class:`AlignmentInputs`
-> :class:`AlignmentResult`: the maps to write, the JSON report) and
:func:`report` (the messages; :func:`shell_counts`: the -g lines).

- ``config``: :class:`AlignmentConfig` and :func:`read_config`;
- ``pipeline``: :func:`run`, its inputs and result (the year column, the
  candidates read, the output tables);
- ``stage``: the matching itself (:func:`align`, the offset correction) and
  its records;
- ``report``: :func:`report`, the messages of a run.
"""

from . import config, pipeline, stage
from .config import AlignmentConfig, read_config
from .pipeline import AlignmentInputs, AlignmentResult, FootprintMap, run
from .report import report, shell_counts
from .stage import Alignment, align

__all__ = ["Alignment", "AlignmentConfig", "AlignmentInputs", "AlignmentResult", "FootprintMap",
           "align", "config", "pipeline", "read_config", "report", "run", "shell_counts",
           "stage"]
