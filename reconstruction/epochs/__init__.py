"""Map epochs: several dated maps of one town as one city over time.

The layer under the stages that know about time (issue 28): which plot of a
later map is which of an earlier one (:mod:`~reconstruction.epochs.plots`).
Pure: shapely 2 and numpy, no GRASS.
"""

from . import plots
from .plots import KINDS, PlotMatches, estimate_offset, match_plots

__all__ = ["KINDS", "PlotMatches", "estimate_offset", "match_plots", "plots"]
