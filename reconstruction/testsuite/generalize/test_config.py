"""v.histo.generalize's options read into a GeneralizeConfig
(reconstruction.generalize.config): no GRASS needed."""

import pytest

from reconstruction.core.errors import InputError
from reconstruction.generalize.config import GeneralizeConfig, read_config

#: every option of the module's g.parser header with its default (input= given)
DEFAULTS = {"input": "raw", "raster": "", "class": "", "output": "plots",
            "method": "alpha,lines", "alpha": "", "distance": "", "angle": "180",
            "tolerance": "", "min_area": "", "seed": "1", "metrics": "", "gt_points": "",
            "gt_polygons": "", "gt_buffer": "2", "report": ""}
FLAGS = {"r": False, "g": False}


def options(**changes):
    return dict(DEFAULTS, **changes)


def test_default_options_give_the_default_config():
    # the sizes not given are derived from the map's scale (generalize.scale)
    assert read_config(options(), FLAGS) == GeneralizeConfig(alpha=None, distance=None,
                                                             tolerance=None, min_area=None)
    config = read_config(options(method="douglas", min_area="0"), {"r": True, "g": True})
    assert config.methods == ("douglas",) and config.min_area == 0 and config.orthogonal
    assert config.shell and config.category is None


def test_values_read_into_the_config():
    config = read_config(options(method="alpha,douglas", alpha="6.5", distance="2", angle="15",
                                 tolerance="0.5", seed="4", gt_buffer="1"), FLAGS)
    assert (config.methods, config.alpha, config.distance, config.angle) == (
        ("alpha", "douglas"), 6.5, 2.0, 15.0)
    assert (config.tolerance, config.seed, config.gt_buffer) == (0.5, 4, 1.0)


def test_the_class_of_a_raster_is_read_with_raster_only():
    assert read_config(options(input="", raster="classes", **{"class": "3"}), FLAGS).category == 3
    assert read_config(options(**{"class": "3"}), FLAGS).category is None


@pytest.mark.parametrize("key,value", [("alpha", "0"), ("distance", "-1"), ("tolerance", "0"),
                                       ("min_area", "-1"), ("gt_buffer", "0"), ("angle", "200"),
                                       ("angle", "-1"), ("alpha", "x"), ("seed", "1.5")])
def test_bad_options_are_refused_with_the_option_named(key, value):
    with pytest.raises(InputError, match="{}=".format(key)):
        read_config(options(**{key: value}), FLAGS)


def test_a_bad_class_is_refused_with_the_option_named():
    with pytest.raises(InputError, match="class="):
        read_config(options(input="", raster="classes", **{"class": "x"}), FLAGS)


@pytest.mark.parametrize("maps", ["grey", "red,green,blue"])
def test_map_is_one_band_or_three(maps):
    """Issue 51, item 3: map= of the fit and of -d may be a greyscale scan."""
    config = read_config(options(method="fit", map=maps), FLAGS)
    assert config.maps == tuple(maps.split(","))
    assert read_config(options(map=maps), dict(FLAGS, d=True)).maps == tuple(maps.split(","))
    with pytest.raises(InputError, match=r"map= needs one raster map \(a greyscale scan\) or "
                                         "three"):
        read_config(options(method="fit", map="red,green"), FLAGS)
