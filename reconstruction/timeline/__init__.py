"""v.histo.timeline: the epochs' models of one town as one city over time.

The chain writes one model per map epoch (v.histo.lod2, ``previous=`` from
the second on); this module merges them into one CityJSON model that holds
every building once, with its lifespan
(:func:`reconstruction.epochs.dynamic.merge_epochs`), or extracts the
snapshot of one year (:func:`reconstruction.epochs.dynamic.snapshot`).

The module's sequence: :func:`read_config` (g.parser's options ->
:class:`TimelineConfig`), :func:`run` (-> :class:`TimelineResult`),
:func:`write` and :func:`report` (the messages; :func:`shell_counts`: -g).
"""

from . import config, pipeline
from .config import TimelineConfig, read_config
from .pipeline import TimelineResult, read_register, run, write
from .report import report, report_json, shell_counts

__all__ = ["TimelineConfig", "TimelineResult", "config", "pipeline", "read_config",
           "read_register", "report", "report_json", "run", "shell_counts",
           "write"]
