"""reconstruction.core.options: the one way to read module options (no GRASS needed)."""

import math

import pytest

from reconstruction.core.errors import InputError
from reconstruction.core.options import parse_list, parse_number, parse_range, processes


def test_parse_range():
    assert parse_range("0.07,0.10", "threshold") == (0.07, 0.10)
    assert parse_range(" 5 , 9 ", "minsize", int) == (5, 9)
    assert parse_range("5", "minsize", int) == (5, 5)
    assert parse_range([2, 3], "length") == (2.0, 3.0)
    assert parse_range("", "length") is None and parse_range(None, "length") is None
    for text, message in (("1,2,3", "two numbers"), ("a,b", "must be numbers"),
                          ("3,2", "above the maximum"), ("1,inf", "two numbers"),
                          ("5.5", "must be numbers")):
        with pytest.raises(InputError, match=message):
            parse_range(text, "x", int if text == "5.5" else float)
    with pytest.raises(InputError, match="zero or more"):
        parse_range("-1,2", "x", positive=True)
    with pytest.raises(InputError, match="positive"):
        parse_range("0,2", "x", positive=True, allow_zero=False)


def test_parse_number():
    assert parse_number("12", "alpha") == 12.0
    assert parse_number("3", "window", int) == 3
    assert parse_number(0, "min_area", minimum=0) == 0
    with pytest.raises(InputError, match="alpha= must be above 0"):
        parse_number("0", "alpha", minimum=0, allow_minimum=False)
    with pytest.raises(InputError, match="angle= must be at most 180"):
        parse_number("200", "angle", maximum=180)
    with pytest.raises(InputError, match="finite"):
        parse_number("nan", "alpha")
    with pytest.raises(InputError, match="seed= must be a number"):
        parse_number("1.5", "seed", int)
    assert math.isclose(parse_number("1e-3", "x"), 0.001)


def test_parse_list():
    assert parse_list("rf,knn,,svm") == ["rf", "knn", "svm"]
    assert parse_list("2, 6", int) == [2, 6]
    assert parse_list("") == [] and parse_list(None) == []
    with pytest.raises(InputError, match="Option remove=: <2,x>"):
        parse_list("2,x", int, key="remove")


def test_processes_has_the_grass_meaning():
    assert processes(1, cores=8) == 1
    assert processes("3", cores=8) == 3
    assert processes(0, cores=8) == 8
    assert processes(-2, cores=8) == 6
    assert processes(-20, cores=8) == 1
    assert processes(0, cores=1) == 1
