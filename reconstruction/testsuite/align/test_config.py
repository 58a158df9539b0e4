"""v.histo.align's options -> AlignmentConfig (read_config), without GRASS."""

import json
import math

import pytest

from reconstruction.align import config as cf
from reconstruction.align import read_config
from reconstruction.core.errors import InputError

# what g.parser gives for `v.histo.align input=plots footprints=fp year=1900 output=al`
OPTIONS = {"input": "plots", "footprints": "fp", "year_column": "bouwjaar", "year": "1900",
           "buffer": "", "resolution": "", "k": "", "overlap": "0.6", "shift": "",
           "shift_window": "150", "output": "al", "unmatched": "", "report": ""}
FLAGS = {"i": False, "g": False}


def config(flags=None, **changes):
    return read_config(dict(OPTIONS, **changes), dict(FLAGS, **(flags or {})))


def test_the_defaults():
    c = config()
    assert (c.year, c.buffer, c.overlap, c.include_year, c.shift, c.shift_window) == (
        1900, 10, 0.6, False, 0, 150)
    assert isinstance(c.year, int)
    assert (c.plots, c.footprints, c.output, c.unmatched, c.report_file) == (
        "plots", "fp", "al", "", "")
    assert (c.year_column, c.year_column_given, c.map_year, c.shell) == (
        "bouwjaar", False, "1900", False)


def test_good_values():
    c = config(flags={"i": True, "g": True}, buffer="4.5", overlap="0.9", shift="10",
               shift_window="80", unmatched="un", report="/tmp/r.json", year_column="jaar")
    assert (c.buffer, c.overlap, c.shift, c.shift_window) == (4.5, 0.9, 10, 80)
    assert c.include_year and c.shell
    assert (c.unmatched, c.report_file, c.year_column, c.year_column_given) == (
        "un", "/tmp/r.json", "jaar", True)


def test_the_buffer_from_resolution_and_k():
    c = config(resolution="0.9,0.3", k="3")
    assert c.buffer == pytest.approx(3 * math.hypot(0.9, 0.3))
    assert config(resolution="2", k="1").buffer == pytest.approx(2 * math.sqrt(2))


def test_the_year_as_written_is_the_one_the_messages_give():
    assert config(year="1961").map_year == "1961"
    assert cf.AlignmentConfig(year=1961).map_year == "1961"      # without the module


@pytest.mark.parametrize("changes, option, message", [
    ({"year": "19x"}, "year", "Option year= must be a number, not <19x>"),
    ({"buffer": "-2"}, "buffer", "The buffer must be positive (map units), not -2"),
    ({"buffer": "0"}, "buffer", "The buffer must be positive"),
    ({"buffer": "ten"}, "buffer", "Option buffer= must be a number, not <ten>"),
    ({"overlap": "0"}, "overlap", "The overlap threshold must be in (0, 1], not 0"),
    ({"overlap": "1.5"}, "overlap", "The overlap threshold must be in (0, 1], not 1.5"),
    ({"shift": "-3"}, "shift", "The shift search radius must be zero (off) or positive"),
    ({"shift_window": "-1"}, "shift_window", "Option shift_window= must be at least 0"),
    ({"resolution": "0.9,0"}, "k", "Option k= must be a number, not <>"),
    ({"resolution": "0.9,0", "k": "2"}, "resolution",
     "The resolutions must be two positive pixel sizes, not 0.9,0"),
    ({"resolution": "1,2,3", "k": "2"}, "resolution", "two positive pixel sizes"),
    ({"resolution": "1,1", "k": "0"}, "k", "The factor k must be positive, not 0"),
])
def test_each_bad_value_names_its_option(changes, option, message):
    with pytest.raises(InputError) as caught:
        config(**changes)
    text = str(caught.value)
    assert message in text
    # the option, by its key or in words ("the buffer", "the resolutions", ...)
    assert option.split("_")[0] in text.replace("resolutions", "resolution").lower()


def test_the_json_report_lists_the_matching_options_only():
    c = config(unmatched="un", report="r.json")
    assert list(cf.matching_options(c)) == ["year", "buffer", "overlap", "include_year", "shift",
                                            "shift_window", "shift_cell", "min_gain"]
    assert json.dumps(cf.matching_options(c)) == (
        '{"year": 1900, "buffer": 10.0, "overlap": 0.6, "include_year": false, "shift": 0.0, '
        '"shift_window": 150.0, "shift_cell": 1.0, "min_gain": 0.02}')
