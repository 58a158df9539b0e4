"""Names the suite writes: map names GRASS accepts, no SQL keyword as a column (issue 12)."""

import pytest

from reconstruction.core import contract
from reconstruction.core import names


def test_every_contract_column_is_a_plain_sql_name():
    assert contract.CASE in contract.COLUMNS
    for column in contract.COLUMNS:
        assert names.column_name_problem(column) is None, column


@pytest.mark.parametrize("word", ["case", "CASE", "select", "Order", "group", "table", "user"])
def test_sql_keywords(word):
    assert names.is_sql_keyword(word)
    assert "SQL keyword" in names.column_name_problem(word)
    assert "SQL keyword" in names.vector_name_problem(word)


@pytest.mark.parametrize("name", ["footprints", "plots_1961", "a", "Map2"])
def test_good_names(name):
    assert names.vector_name_problem(name) is None
    assert names.raster_name_problem(name) is None
    assert names.column_name_problem(name) is None


@pytest.mark.parametrize("name", ["a.b", "1961", "_x", "a-b", "a b", "é"])
def test_vector_names_grass_rejects(name):
    assert names.vector_name_problem(name)


@pytest.mark.parametrize("name", ["", ".hidden", "a@b", "a,b", "a=b", "a/b", "x" * 256])
def test_raster_names_grass_rejects(name):
    assert names.raster_name_problem(name)
    assert names.vector_name_problem(name)


def test_raster_names_may_hold_dots_and_keywords():
    assert names.raster_name_problem("map.red") is None
    assert names.raster_name_problem("select") is None
