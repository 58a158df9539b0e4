"""v.histo.generalize's parameters in the map's own scale: :func:`derive`.

The thesis's values (alpha 12, distance 5, tolerance 1, minimum area 20, in
metres; Morlighem 2021, Table B.3) were chosen on the Delft 1961 map, whose
cells are 0.9 m, and are this suite's defaults on its synthetic maps (1 m
cells). On a map scanned at 0.1 m the same metres are ten times as many
cells: an alpha of 12 m fills every courtyard narrower than about 24 m. So
when the user gives no value, each follows the map:

- alpha, distance and tolerance: a number of cells (:data:`ALPHA_CELLS`,
  :data:`DISTANCE_CELLS`, :data:`TOLERANCE_CELLS`), the thesis's values on
  1 m cells: the staircase of a plot's cells and the noise of their edges
  are a cell or two whatever the map;
- the minimum area: :data:`MIN_AREA_CELLS` cells, and no less than a square
  :data:`MIN_SIDE_STROKES` stroke widths wide when the width of the lines the
  map draws is known (a plot narrower than that cannot be drawn with an
  outline around a fill: it is a piece of a letter or a stroke);
- the fit's reach (how far from an edge the drawn line is looked for):
  :data:`~reconstruction.generalize.fitting.REACH` cells, and no less than
  :data:`REACH_STROKES` stroke widths: on a map drawing lines several cells
  wide the classified edge may lie on either side of the stroke.

The stroke width is the ``stroke=`` the user gave, or the typical width of
the dark lines of the scanned map (:func:`line_width`). Pure functions; the
module reads the facts (:class:`MapFacts`) from GRASS.
"""

from dataclasses import dataclass, replace
from typing import Optional

import numpy as np

from ..core.messages import note
from ..geom.strokes import typical_thickness
from .fitting import REACH, _bands

#: alpha radius, buffered-lines distance and simplification tolerance, in cells
ALPHA_CELLS, DISTANCE_CELLS, TOLERANCE_CELLS = 12.0, 5.0, 1.0
#: the smallest raw plot kept, in cells
MIN_AREA_CELLS = 20.0
#: ... and in stroke widths (the side of a square)
MIN_SIDE_STROKES = 4.0
#: the fit looks for the line at least this many stroke widths from an edge
REACH_STROKES = 1.5
#: a cell of the scanned map is ink when its brightness lies within this share
#: of the way from the darkest (1st percentile) to the paper (99th)
INK_SHARE = 0.35


@dataclass(frozen=True)
class Scaled:
    """A derived parameter: its ``value`` and why (``reason``)."""

    value: float
    reason: str


@dataclass(frozen=True)
class ScaledParameters:
    """The parameters :func:`derive` derived (None: the user gave it), in map
    units; ``reach`` in cells (None also when there is no fit step)."""

    alpha: Optional[Scaled] = None
    distance: Optional[Scaled] = None
    tolerance: Optional[Scaled] = None
    min_area: Optional[Scaled] = None
    reach: Optional[Scaled] = None

    def apply(self, config):
        """``config`` (a :class:`~reconstruction.generalize.config.GeneralizeConfig`)
        with the derived values."""
        return replace(config, **{name: value.value for name, value in self._derived()})

    def messages(self):
        """One note saying what was derived and why (none when nothing was)."""
        parts = ["{} {}".format(name.replace("_", " "), value.reason)
                 for name, value in self._derived()]
        return [note("From the map's scale: " + "; ".join(parts))] if parts else []

    def _derived(self):
        return [(name, getattr(self, name))
                for name in ("alpha", "distance", "tolerance", "min_area", "reach")
                if getattr(self, name) is not None]


@dataclass(frozen=True)
class MapFacts:
    """What the map says about its scale, read from GRASS by the module.

    ``cell``: its cell size (map units); ``stroke``: the width of the lines
    it draws (map units; None: unknown, e.g. without map= and stroke=).
    """

    cell: float
    stroke: Optional[float] = None


def _number(value):
    return "{:g}".format(round(value, 3))


def _exact(value):
    """``value`` without the binary fraction's last digits (12 x 0.1 is 1.2)."""
    return float("{:.12g}".format(value))


def derive(config, facts):
    """The parameters of ``config`` it leaves None, from the map's ``facts``
    (a :class:`MapFacts`): a :class:`ScaledParameters`."""
    cell = facts.cell
    cells = "cells of {} map units".format(_number(cell))

    def in_cells(count):
        return Scaled(_exact(count * cell), "{} ({} {})".format(
            _number(count * cell), _number(count), cells.replace("cells", "cell")
            if count == 1 else cells))

    derived = {}
    if config.alpha is None:
        derived["alpha"] = in_cells(ALPHA_CELLS)
    if config.distance is None:
        derived["distance"] = in_cells(DISTANCE_CELLS)
    if config.tolerance is None:
        derived["tolerance"] = in_cells(TOLERANCE_CELLS)
    stroke = facts.stroke
    if config.min_area is None:
        by_cells = MIN_AREA_CELLS * cell * cell
        by_stroke = (MIN_SIDE_STROKES * stroke) ** 2 if stroke else 0.0
        if by_stroke > by_cells:
            derived["min_area"] = Scaled(_exact(by_stroke), "{} square map units (a square {} stroke "
                                         "widths of {} wide)".format(
                                             _number(by_stroke), _number(MIN_SIDE_STROKES),
                                             _number(stroke)))
        else:
            derived["min_area"] = Scaled(_exact(by_cells), "{} square map units ({} {})".format(
                _number(by_cells), _number(MIN_AREA_CELLS), cells))
    if "fit" in config.methods and config.reach is None:
        base = REACH[config.outline]
        # to a tenth of a cell: the profiles are sampled from -reach, and a
        # reach a hair off REACH would move every sample
        by_stroke = round(REACH_STROKES * stroke / cell, 1) if stroke else 0.0
        if by_stroke > base:
            derived["reach"] = Scaled(_exact(by_stroke), "{} cells ({} stroke widths of {})".format(
                _number(by_stroke), _number(REACH_STROKES), _number(stroke)))
        else:
            derived["reach"] = Scaled(base, "{} cells (outline={}{})".format(
                _number(base), config.outline,
                "; the lines are {} wide".format(_number(stroke)) if stroke else ""))
    return ScaledParameters(**derived)


def line_width(image):
    """The typical width (map units) of the dark lines the scanned map
    ``image`` draws (a :class:`~reconstruction.geom.grid.MapImage`), or None
    when it has none: the cells within :data:`INK_SHARE` of the way from its
    darkest to its paper's brightness (the mean of the bands), their
    :func:`~reconstruction.geom.strokes.typical_thickness`."""
    rgb = np.asarray(image.rgb, dtype=float)
    brightness = rgb.mean(axis=-1) if rgb.ndim == 3 else rgb
    valid = np.isfinite(brightness)
    if not valid.any():
        return None
    dark, paper = np.percentile(brightness[valid], [1, 99])
    if paper - dark <= 0:
        return None
    ink = valid & (brightness <= dark + INK_SHARE * (paper - dark))
    width = typical_thickness(ink)
    return width * _bands(image)[2] if width > 0 else None
