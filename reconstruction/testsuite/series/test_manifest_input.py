"""Hostile or careless manifests (issue 49, items 10 and 15): one InputError, never a traceback.

A manifest that is not UTF-8, an EPSG code PROJ does not know, an extent
with Infinity, JSON nested a thousand levels, a sheet name ending in a
newline; then a fuzz test over JSON and CSV manifests (derandomized in CI
by conftest's profile; more examples with ``--hypothesis-profile=explore``).
"""

import json
import math

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from reconstruction.core.errors import InputError
from reconstruction.series import manifest


def good_sheet(name="a", column=0):
    return {"name": name, "map": name + ".bsq", "training": name + ".t.geojson",
            "footprints": name + ".f.geojson", "year": 1900,
            "extent": [column * 200.0, 0.0, (column + 1) * 200.0, 200.0]}


def write(tmp_path, text, name="series.json"):
    path = tmp_path / name
    path.write_bytes(text if isinstance(text, bytes) else text.encode("utf-8", "surrogatepass"))
    return str(path)


def refused(path, match):
    with pytest.raises(InputError, match=match):
        manifest.read_manifest(path)


def test_a_latin1_manifest_is_one_input_error(tmp_path):
    doc = {"sheets": [dict(good_sheet(), map="carte_\u00e9t\u00e9.bsq")]}
    refused(write(tmp_path, json.dumps(doc, ensure_ascii=False).encode("latin-1")),
            "not UTF-8")
    refused(write(tmp_path, "name,map\n\u00e9,x\n".encode("latin-1"), "series.csv"),
            "not UTF-8")


@pytest.mark.parametrize("epsg, said", [(999999, "EPSG:999999 is not"), (0, "EPSG:0 is not"),
                                        (-28992, "is not"), (4326, "geographic"),
                                        (1e400, "finite number"), (28992.5, "whole number"),
                                        (True, "a number"), ("EPSG:28992", "a number")])
def test_an_epsg_code_proj_does_not_know_is_one_input_error(tmp_path, epsg, said):
    text = json.dumps({"epsg": epsg, "sheets": [good_sheet()]})
    refused(write(tmp_path, text), said)


@pytest.mark.parametrize("where", ["west", "east", "margin", "year", "seed"])
@pytest.mark.parametrize("value", ["Infinity", "-Infinity", "NaN", "1e400"])
def test_an_extent_or_number_that_is_not_finite_is_one_input_error(tmp_path, where, value):
    sheet = good_sheet()
    doc = {"sheets": [sheet]}
    if where in ("west", "east"):
        sheet["extent"][0 if where == "west" else 2] = "@"
    elif where == "year":
        sheet["year"] = "@"
    else:
        doc[where] = "@"
    refused(write(tmp_path, json.dumps(doc).replace('"@"', value)), "finite number|a number")


def test_infinity_in_a_csv_extent_is_refused_too(tmp_path):
    text = ("name,map,training,footprints,west,south,east,north,year\n"
            "a,a.bsq,a.t.geojson,a.f.geojson,-inf,0,inf,200,1900\n")
    refused(write(tmp_path, text, "series.csv"), "finite number")


def test_json_nested_a_thousand_levels_is_one_input_error(tmp_path):
    refused(write(tmp_path, '{"sheets": ' + "[" * 1000 + "]" * 1000 + "}"), "nested too deeply")
    refused(write(tmp_path, "[" * 100000 + "]" * 100000), "nested too deeply")


def test_a_sheet_name_ending_in_a_newline_is_refused(tmp_path):
    doc = {"sheets": [good_sheet("sheet_0_0\n")]}
    refused(write(tmp_path, json.dumps(doc)), "a sheet's name must start with a letter")
    text = ("name,map,training,footprints,west,south,east,north,year\n"
            '"a\n",a.bsq,a.t.geojson,a.f.geojson,0,0,200,200,1900\n')
    refused(write(tmp_path, text, "series.csv"), "a sheet's name")


def test_a_csv_row_with_more_or_fewer_fields_is_refused(tmp_path):
    head = "name,map,training,footprints,west,south,east,north,year\n"
    refused(write(tmp_path, head + "a,a.bsq,a.t,a.f,0,0,200,200,1900,extra\n", "s.csv"),
            "line 2 has not as many fields")
    refused(write(tmp_path, head + "a,a.bsq,a.t,a.f,0,0,200\n", "s.csv"),
            "line 2 has not as many fields")


def test_the_good_manifest_of_these_tests_is_read(tmp_path):
    series = manifest.read_manifest(write(tmp_path, json.dumps(
        {"epsg": 31370, "margin": 0, "sheets": [good_sheet("a", 0), good_sheet("b", 1)]})))
    assert series.epsg == 31370 and series.margin == 0.0
    assert [s.year for s in series.sheets] == [1900, 1900]


# --- fuzz ------------------------------------------------------------------

JSON_VALUES = st.recursive(
    st.none() | st.booleans() | st.integers() | st.floats() | st.text(max_size=12),
    lambda inner: st.lists(inner, max_size=4) | st.dictionaries(st.text(max_size=8), inner,
                                                                max_size=4),
    max_leaves=12)
FIELDS = ("name", "map", "training", "footprints", "extent", "year", "options", "west")


@st.composite
def near_manifests(draw):
    """A good manifest of one to three sheets with some fields replaced by
    anything JSON holds (or left out), so that every check is reached."""
    sheets = [good_sheet(n, k) for k, n in enumerate(draw(st.sampled_from(
        [["a"], ["a", "b"], ["a", "b", "c"]])))]
    for s in sheets:
        for key in draw(st.lists(st.sampled_from(FIELDS), max_size=3)):
            if draw(st.booleans()):
                s.pop(key, None)
            else:
                s[key] = draw(JSON_VALUES)
    doc = {"sheets": sheets}
    for key in draw(st.lists(st.sampled_from(["epsg", "margin", "seed", "options", "sheets"]),
                             max_size=2)):
        doc[key] = draw(JSON_VALUES | st.integers(min_value=-2, max_value=40000))
    return draw(st.sampled_from([doc, sheets, doc["sheets"]]))


def read_or_refused(path):
    try:
        series = manifest.read_manifest(path)
    except InputError as error:
        assert str(error)
        return None
    assert isinstance(series, manifest.Series) and series.sheets
    for s in series.sheets:
        assert manifest._NAME.fullmatch(s.name)
        assert all(math.isfinite(v) for v in s.extent)
    assert math.isfinite(series.margin)
    return series


FUZZ = settings(max_examples=300, deadline=None,
                suppress_health_check=[HealthCheck.function_scoped_fixture])


@FUZZ
@given(doc=near_manifests())
def test_fuzz_json_manifests_give_a_series_or_one_input_error(tmp_path, doc):
    read_or_refused(write(tmp_path, json.dumps(doc)))


@FUZZ
@given(text=st.text(max_size=200) | st.binary(max_size=200))
def test_fuzz_any_text_as_a_json_manifest(tmp_path, text):
    read_or_refused(write(tmp_path, text))


CSV_CELLS = st.sampled_from(["a", "b", "a.bsq", "0", "200", "400", "1900", "inf", "nan", "-1",
                             "1e400", "", "x=1;y", "min_area=40", '"', "a\n", "\x00", ",", "c"])


@FUZZ
@given(header=st.lists(st.sampled_from(manifest.CSV_COLUMNS + ("options", "extent", "")),
                       min_size=0, max_size=11),
       rows=st.lists(st.lists(CSV_CELLS, max_size=11), max_size=4),
       good=st.booleans())
def test_fuzz_csv_manifests_give_a_series_or_one_input_error(tmp_path, header, rows, good):
    if good:
        header = list(manifest.CSV_COLUMNS)
    text = "\n".join(",".join(cells) for cells in [header] + rows) + "\n"
    read_or_refused(write(tmp_path, text, "series.csv"))


@FUZZ
@given(text=st.text(max_size=300))
def test_fuzz_any_text_as_a_csv_manifest(tmp_path, text):
    read_or_refused(write(tmp_path, text, "series.csv"))
