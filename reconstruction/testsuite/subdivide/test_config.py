"""v.histo.subdivide's options -> SubdivisionConfig (read_config), without GRASS."""

import pytest

from reconstruction.core.errors import InputError
from reconstruction.subdivide import SubdivisionConfig, read_config

# what g.parser gives for `v.histo.subdivide input=plots output=fp`
OPTIONS = {"input": "plots", "output": "fp", "aligned": "", "length": "5,8", "depth": "12,16",
           "area_threshold": "", "seed": "1"}
FLAGS = {"c": False, "a": False}


def config(flags=None, **changes):
    return read_config(dict(OPTIONS, **changes), dict(FLAGS, **(flags or {})))


def test_the_defaults():
    assert config() == SubdivisionConfig(plots="plots", output="fp", aligned="",
                                          length=(5.0, 8.0), depth=(12.0, 16.0),
                                          area_threshold=None, seed=1, decompose=True,
                                          calibrate=False)
    assert config(seed="").seed == 1           # no seed: 1
    assert isinstance(config().seed, int)


def test_good_values():
    c = config(flags={"c": True, "a": True}, aligned="al", length="6", depth="10,14.5",
               area_threshold="80", seed="7")
    assert (c.aligned, c.length, c.depth, c.area_threshold, c.seed) == (
        "al", (6.0, 6.0), (10.0, 14.5), 80.0, 7)
    assert not c.decompose and c.calibrate
    assert config(area_threshold="0").area_threshold == 0


@pytest.mark.parametrize("changes, message", [
    ({"length": "8,5"}, "Option length=: the minimum 8 is above the maximum 5"),
    ({"length": "0,5"}, "Option length= must be positive, not <0,5>"),
    ({"length": ""}, "Option length= must be two numbers min,max"),
    ({"length": "a,b"}, "Option length= must be numbers min,max, not <a,b>"),
    ({"depth": "-3,-1"}, "Option depth= must be positive, not <-3,-1>"),
    ({"depth": "1,2,3"}, "Option depth= must be two numbers min,max, not <1,2,3>"),
    ({"area_threshold": "-5"}, "Option area_threshold= must be at least 0 (got -5)"),
    ({"area_threshold": "big"}, "Option area_threshold= must be a number, not <big>"),
    ({"seed": "x"}, "Option seed= must be a number, not <x>"),
])
def test_each_bad_value_names_its_option(changes, message):
    with pytest.raises(InputError) as caught:
        config(**changes)
    assert str(caught.value) == message
    assert "Option {}=".format(next(iter(changes))) in str(caught.value)


@pytest.mark.parametrize("year", ["0", "-5"])
def test_a_year_before_1_is_refused(year):
    """Issue 49, item 7: year=0 dropped the aligned footprints' BAG ids."""
    with pytest.raises(InputError, match="year= must be at least 1"):
        config(year=year)


def test_the_map_whose_lines_divide_the_plots():
    c = config(map="scan.red,scan.green,scan.blue", stroke="0.3", min_parcel="2.5")
    assert (c.maps, c.stroke, c.min_parcel) == (("scan.red", "scan.green", "scan.blue"), 0.3, 2.5)
    assert (config().maps, config().stroke, config().min_parcel) == ((), None, None)
    with pytest.raises(InputError, match=r"map= needs one raster map \(a greyscale scan\) or "
                                         "three"):
        config(map="scan.red,scan.green")
    assert config(map="scan.grey").maps == ("scan.grey",)   # issue 51, item 3
    for key in ("stroke", "min_parcel"):
        with pytest.raises(InputError, match=key):
            config(map="r,g,b", **{key: "0"})
        with pytest.raises(InputError, match=key):
            config(map="r,g,b", **{key: "wide"})
