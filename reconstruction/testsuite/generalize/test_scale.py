"""v.histo.generalize's parameters in the map's own scale
(reconstruction.generalize.scale; issue 50, item 3): no GRASS needed."""

import numpy as np
import pytest
import shapely

from reconstruction import generalize
from reconstruction.generalize import scale
from reconstruction.generalize.config import GeneralizeConfig
from reconstruction.geom.grid import MapImage

#: what read_config gives when the sizes are not given
UNSET = dict(alpha=None, distance=None, tolerance=None, min_area=None)


def test_on_1_m_cells_the_thesis_values():
    config = scale.derive(GeneralizeConfig(**UNSET), scale.MapFacts(1.0)).apply(
        GeneralizeConfig(**UNSET))
    assert (config.alpha, config.distance, config.tolerance, config.min_area) == (12, 5, 1, 20)


def test_on_a_0_1_m_map_ten_times_smaller_and_said_why():
    derived = scale.derive(GeneralizeConfig(**UNSET), scale.MapFacts(0.1))
    config = derived.apply(GeneralizeConfig(**UNSET))
    assert (config.alpha, config.distance, config.tolerance, config.min_area) == (
        1.2, 0.5, 0.1, 0.2)
    assert config.reach is None                  # no fit step
    [message] = derived.messages()
    assert message.level == "message"
    assert message.text.startswith("From the map's scale: alpha 1.2 (12 cells of 0.1 map units); "
                                   "distance 0.5 (5 cells of 0.1 map units); tolerance 0.1 "
                                   "(1 cell of 0.1 map units)")


def test_given_values_are_kept_and_not_mentioned():
    config = GeneralizeConfig(alpha=4.0, distance=1.0, tolerance=0.5, min_area=3.0)
    derived = scale.derive(config, scale.MapFacts(0.1))
    assert derived.apply(config) == config and derived.messages() == []


def test_wide_strokes_raise_the_minimum_area_and_the_fit_reach():
    config = GeneralizeConfig(methods=("alpha", "lines", "fit"), **UNSET)
    thin = scale.derive(config, scale.MapFacts(1.0, stroke=0.9)).apply(config)
    assert (thin.min_area, thin.reach) == (20, 1.5)  # the synthetic maps' 0.9 m lines
    # lines a cell wide, measured on a map whose cells are not quite square:
    # REACH itself, not a hair beside it (every profile sample would move)
    delft = scale.derive(config, scale.MapFacts(0.9030, stroke=0.90307)).apply(config)
    assert delft.reach == 1.5
    wide = scale.derive(config, scale.MapFacts(0.1, stroke=0.4)).apply(config)
    assert wide.min_area == pytest.approx(2.56)      # a square 4 strokes wide
    assert wide.reach == pytest.approx(6.0)          # 1.5 strokes of 4 cells


def test_the_width_of_the_drawn_lines():
    rgb = np.full((60, 80, 3), 240, dtype=np.uint8)
    rgb[10:13, 5:75] = 20                        # lines 3 cells wide
    rgb[40:43, 5:75] = 20
    rgb[10:43, 30:33] = 20
    image = MapImage(rgb=rgb, extent=(0.0, 8.0, 0.0, 6.0))   # 0.1 map units a cell
    assert scale.line_width(image) == pytest.approx(0.3)
    assert scale.line_width(MapImage(rgb=np.full((5, 5, 3), 200, np.uint8),
                                     extent=(0, 5, 0, 5))) is None


def test_a_courtyard_of_a_0_1_m_map_stays_open():
    """12 m, the thesis's alpha on Delft's 0.9 m cells, fills a 2 m
    courtyard of a 6 m block; 12 cells of a 0.1 m map keep it."""
    block = shapely.box(0, 0, 6, 6).difference(shapely.box(2, 2, 4.2, 4))
    said = []
    inputs = generalize.GeneralizeInputs([block], "raw", say=said.extend, cell=0.1)
    plot = generalize.run(inputs, GeneralizeConfig(**UNSET)).plots[0]
    assert len(plot.interiors) == 1 and plot.area == pytest.approx(block.area, rel=0.02)
    assert said[0].text.startswith("From the map's scale: alpha 1.2 ")
    thesis = generalize.run(generalize.GeneralizeInputs([block], "raw"),
                            GeneralizeConfig()).plots[0]
    assert len(thesis.interiors) == 0
