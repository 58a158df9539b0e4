"""v.histo.generalize's whole sequence: :func:`run` (``reconstruction.generalize.run``).

The raw areas the module read become single polygons, the small ones
dropped (:func:`~reconstruction.generalize.stage.raw_plots`); they are
generalised, measured and scored against the ground truth
(:func:`~reconstruction.generalize.stage.generalize_map`). The lines printed
before the work (the areas dropped, the plots about to be generalised) go
out through ``say`` as they happen; the rest is :func:`~reconstruction.generalize.report.report`'s.
"""

from dataclasses import dataclass
from typing import Callable, Optional

import numpy as np

from ..core.messages import note, verbose
from ..geom.grid import MapImage
from ..geom.registration import image_shifts, register_image
from .config import GeneralizeConfig
from .drawn import UNIFORM, building_cells, drawn_plots
from .scale import MapFacts, derive, line_width
from .stage import GeneralizedPlots, generalize_map, raw_plots


def _silent(messages):
    pass


@dataclass(frozen=True)
class GeneralizeInputs:
    """What v.histo.generalize read from GRASS.

    ``geometries``: the raw areas of map ``source_map`` (vectorised from
    raster= or given as input=); ``cats``: their categories (input= only,
    None for areas vectorised from a raster); ``gt_points``: (n, 2)
    coordinates of the ground-truth points, ``gt_polygons``: the reference
    plots (None when not given); ``image``: the scanned map for the fit step
    (a :class:`~reconstruction.geom.grid.MapImage`, None without map=);
    ``say(messages)``: prints progress
    :class:`~reconstruction.core.messages.Message` s as they happen;
    ``cell``: the cell size of the map the plots come from (map units; the
    parameters the user did not give follow it,
    :mod:`~reconstruction.generalize.scale`).
    """

    geometries: list
    source_map: str
    cats: Optional[list] = None
    gt_points: Optional[np.ndarray] = None
    gt_polygons: Optional[list] = None
    image: Optional[MapImage] = None
    say: Callable[[list], None] = _silent
    cell: float = 1.0


def _drawn(inputs, config):
    """The plots the outlines drawn on the map close (flag -d), the raw areas
    deciding which are built (:func:`~reconstruction.generalize.drawn.drawn_plots`)."""
    image = inputs.image
    building = building_cells(inputs.geometries, image.extent, image.rgb.shape[:2])
    read = drawn_plots(image.rgb, image.extent, building, config.stroke)
    inputs.say([note("{} plots read from the lines drawn on the map: {} of the {} regions they "
                     "close are built whole ({:.0%} of their cells in the raw areas; "
                     "regions of at least {:g} square map units, strokes {:g} cells "
                     "wide)".format(len(read.polygons), read.built, read.regions, UNIFORM,
                                    read.scale.min_area, read.scale.stroke))])
    return read.polygons


def run(inputs, config: GeneralizeConfig) -> GeneralizedPlots:
    """Generalise the raw areas of ``inputs`` as ``config`` says: a
    :class:`~reconstruction.generalize.stage.GeneralizedPlots`; the
    parameters ``config`` leaves None are derived from the map's scale
    (:func:`~reconstruction.generalize.scale.derive`, said in a note)."""
    stroke = config.stroke
    if stroke is None and inputs.image is not None:
        stroke = line_width(inputs.image)
    scaled = derive(config, MapFacts(inputs.cell, stroke))
    config = scaled.apply(config)
    inputs.say(scaled.messages())
    geometries, cats = inputs.geometries, inputs.cats
    if config.drawn:
        geometries, cats = _drawn(inputs, config), None
    raw = raw_plots(geometries, config.min_area, inputs.source_map, cats=cats)
    if raw.dropped:
        inputs.say([verbose("{} raw areas smaller than {} dropped".format(raw.dropped,
                                                                          config.min_area))])
    inputs.say([note("Generalising {} plots ({})...".format(len(raw.polygons),
                                                            ", ".join(config.methods)))])
    image = inputs.image
    if image is not None:
        shifts = image_shifts(image)
        if config.register:
            image = register_image(image, shifts)
        inputs.say([shifts.message(config.maps, config.register)])
    return generalize_map(raw, config, inputs.gt_points, inputs.gt_polygons, image)
