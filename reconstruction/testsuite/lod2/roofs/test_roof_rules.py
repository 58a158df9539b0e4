"""Roof rules: the thesis's Table B.1 as data, the suite's default, rules files."""

import json

import numpy as np
import pytest

from reconstruction.lod2.roofs import rules as roof_rules
from reconstruction.lod2.roofs import plan as roofs
from reconstruction.core.errors import InputError


def U(n, seed):
    """n uniform numbers in [0, 1) of one seed: what a roof draw takes."""
    return np.random.default_rng(seed).random(n)

THESIS_CSV = """# the thesis's Table B.1
from,to,shape,flat,hip,gable,mansard,stepped
,1915,4,10,20,20,10,40
1916,,4,25,25,25,10,15
,1915,n,60,0,0,40,0
1916,,n,60,,,40,
"""


def weights(rules, first, last, shape):
    row = [r for r in rules.rules if (r.first, r.last, r.shape) == (first, last, shape)][0]
    return {k: v for k, v in row.weights if v}


def test_a_rules_file_reproduces_the_thesis_table_exactly():
    rules = roof_rules.parse_rules(THESIS_CSV)
    for first, last in ((None, 1915.0), (1916.0, None)):
        for shape in ("4", "n"):
            assert weights(rules, first, last, shape) == weights(roof_rules.THESIS_RULES, first,
                                                                 last, shape)
    assert weights(rules, None, 1915.0, "4") == {"flat": 10, "hip": 20, "gable": 20,
                                                 "mansard": 10, "stepped": 40}
    assert weights(rules, 1916.0, None, "n") == {"flat": 60, "mansard": 40}
    # and draws the same roofs
    n = np.array([4, 4, 5, 6, 4, 7] * 50)
    years = np.array([1800, 1950, 1900, 1990, np.nan, 1915] * 50)
    a = rules.draw(n, years, np.full(len(n), 3.0), U(len(n), 4))
    b = roof_rules.THESIS_RULES.draw(n, years, np.full(len(n), 3.0), U(len(n), 4))
    assert list(a) == list(b)


def test_the_default_draws_exactly_what_roofs_draws_today():
    rng = np.random.default_rng(9)
    n = rng.integers(3, 9, 5000)
    years = rng.choice([1700, 1880, 1915, 1915.5, 1916, 1961, np.nan], 5000)
    attic = rng.uniform(0, 5, 5000)
    a = roof_rules.FIVE_TYPE_RULES.draw(n, years, attic, U(len(n), 2))
    b = roofs.draw_roof_types(n, years, attic, U(len(n), 2))
    assert list(a) == list(b)


def test_the_default_table_round_trips_through_a_file(tmp_path):
    path = tmp_path / "rules.csv"
    path.write_text(roof_rules.DEFAULT_RULES.table())
    again = roof_rules.read_rules(str(path))
    n = np.array([4, 5] * 100)
    years = np.array([1900, 1950, 1950, 1900] * 50)
    assert list(again.draw(n, years, np.full(200, 3.0), U(len(n), 1))) == \
        list(roof_rules.DEFAULT_RULES.draw(n, years, np.full(200, 3.0), U(len(n), 1)))


def test_json_rules_with_three_periods_and_a_vertex_count(tmp_path):
    data = {"rules": [
        {"from": None, "to": 1850, "shape": "n", "weights": {"stepped": 100}},
        {"from": 1851, "to": 1930, "shape": "n", "weights": {"gable": 50, "hip": 50}},
        {"from": 1851, "to": 1930, "shape": "3", "weights": {"flat": 100}},
        {"from": 1931, "to": None, "shape": "n", "weights": {"flat": 100}},
    ]}
    path = tmp_path / "rules.json"
    path.write_text(json.dumps(data))
    rules = roof_rules.read_rules(str(path))
    got = rules.draw([4, 4, 3, 5, 4], [1800, 1900, 1900, 2000, None], [3.0] * 5,
                     U(5, 0))
    assert got[0] == "stepped" and got[1] in ("gable", "hip") and got[2] == "flat"
    assert got[3] == "flat" and got[4] == "stepped"       # unknown year: the first period


def test_low_roofs_stay_flat():
    got = roof_rules.THESIS_RULES.draw([4, 4], [1800, 1800], [0.5, 3.0],
                                       U(2, 0))
    assert got[0] == "flat"


@pytest.mark.parametrize("text,message", [
    (THESIS_CSV.replace(",1915,4,10,20,20,10,40", ",1915,4,10,20,20,10,30"),
     "sum to 90, not 100"),
    (THESIS_CSV.replace("flat,hip", "flat,dome"), "unknown roof type <dome>"),
    (THESIS_CSV.replace("1916,,4", "1920,,4").replace("1916,,n", "1920,,n"),
     "do not follow each other"),
    (THESIS_CSV.replace(",1915,n,60,0,0,40,0\n", ""), "no row for n-sided"),
    (THESIS_CSV + ",1915,4,10,20,20,10,40\n", "a second row"),
    (THESIS_CSV.replace("1916,,n", "1916,2000,n").replace("1916,,4", "1916,2000,4"),
     "the last no end"),
    (THESIS_CSV.replace(",1915,4,10", ",1915,4,-10"), "0 or more"),
    ("from,to\n,,\n", "needs columns"),
    ('{"rules": [{"shape": "n"}]}', "needs from, to, shape and weights"),
    ("{not json", "not valid JSON"),
])
def test_bad_rules_are_refused(text, message):
    with pytest.raises(InputError, match=message):
        roof_rules.parse_rules(text)


def test_a_missing_rules_file_is_an_input_error(tmp_path):
    with pytest.raises(InputError, match="Cannot read"):
        roof_rules.read_rules(str(tmp_path / "none.csv"))


def test_an_excel_csv_with_a_byte_order_mark_and_crlf_is_read_silently(tmp_path):
    """Excel's "CSV UTF-8" starts with a BOM and ends lines with CRLF: a normal
    input, read as the plain file (issue 33, item 8)."""
    path = tmp_path / "excel.csv"
    path.write_bytes(b"\xef\xbb\xbf" + THESIS_CSV.replace("\n", "\r\n").encode("utf-8"))
    assert roof_rules.read_rules(str(path)) == roof_rules.parse_rules(THESIS_CSV)
    assert roof_rules.parse_rules("\ufeff" + THESIS_CSV) == roof_rules.parse_rules(THESIS_CSV)


def test_a_json_rules_file_with_a_byte_order_mark_is_read(tmp_path):
    path = tmp_path / "rules.json"
    rows = [{"from": None, "to": None, "shape": "n", "weights": {"flat": 100}}]
    path.write_bytes(b"\xef\xbb\xbf" + json.dumps({"rules": rows}).encode("utf-8"))
    assert roof_rules.read_rules(str(path)).rules[0].weights == (("flat", 100.0),)


@pytest.mark.parametrize("data,message", [
    # Latin-1 (an "é" in a comment): not UTF-8
    (("# période\n" + THESIS_CSV).encode("latin-1"), r"not UTF-8 text \(byte 0xe9"),
    (b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR", "not UTF-8 text"),
    (b"from,to\x00\x00shape\n", "binary file"),
])
def test_a_rules_file_of_another_encoding_is_one_input_error_naming_it(tmp_path, data, message):
    path = tmp_path / "rules.csv"
    path.write_bytes(data)
    with pytest.raises(InputError, match=message) as error:
        roof_rules.read_rules(str(path))
    assert str(path) in str(error.value) and "UTF-8" in str(error.value)


@pytest.mark.parametrize("text,message", [
    (THESIS_CSV.replace(",1915,4,", ",1849.5,4,").replace(",1915,n,", ",1849.5,n,")
     .replace("1916,,", "1850,,"), r"a year must be a whole number, not <1849\.5>"),
    ('{"rules": [{"from": null, "to": null, "shape": "n", '
     '"weights": {"flat": 99, "hip": true}}]}', "a weight must be a number of percent, not true"),
    ('{"rules": [{"from": null, "to": false, "shape": "n", "weights": {"flat": 100}}]}',
     "a year must be a number, not false"),
])
def test_a_fractional_year_or_a_boolean_weight_says_what_is_wrong(text, message):
    with pytest.raises(InputError, match=message):
        roof_rules.parse_rules(text)


WIDTH_RULES = """from,to,shape,min_width,max_width,flat,hip,gable,cornice,pyramid,shed
,,square,,,0,0,0,0,100,0
,,4,,3.5,0,0,0,0,0,100
,,4,8,,0,0,0,100,0,0
,,4,,,0,0,100,0,0,0
,,n,,,0,100,0,0,0,0
"""


def test_rules_by_span_and_square_shape():
    rules = roof_rules.parse_rules(WIDTH_RULES)
    rings = [np.array([[0, 0], [9, 0], [9, 10], [0, 10]]),       # square: pyramid
             np.array([[0, 0], [3, 0], [3, 12], [0, 12]]),        # span 3 m: shed
             np.array([[0, 0], [14, 0], [14, 9], [0, 9]]),        # span 9 m: cornice
             np.array([[0, 0], [6, 0], [6, 15], [0, 15]]),        # span 6 m: gable
             np.array([[0, 0], [9, 0], [9, 9], [4, 12], [0, 9]])]  # 5-sided: hip
    spans, square = roof_rules.footprint_spans(rings)
    assert spans.tolist() == pytest.approx([9, 3, 9, 6, 9])
    got = rules.draw([len(r) for r in rings], [None] * 5, np.full(5, 3.0), np.full(5, 0.5),
                     spans, square)
    assert list(got) == ["pyramid", "shed", "cornice", "gable", "hip"]
    # without spans, only the rows of any width match
    got = rules.draw([4, 4], [None] * 2, np.full(2, 3.0), np.full(2, 0.5))
    assert list(got) == ["gable", "gable"]
    # the table round-trips (with a 0 for every other roof type)
    back = roof_rules.parse_rules(rules.table()).rules
    assert [(r.shape, r.min_width, r.max_width, {k: w for k, w in r.weights if w})
            for r in back] == [(r.shape, r.min_width, r.max_width,
                                {k: w for k, w in r.weights if w}) for r in rules.rules]


@pytest.mark.parametrize("text, message", [
    (WIDTH_RULES.replace(",,4,8,,", ",,4,8,6,"), "max_width 6 is not above min_width 8"),
    (WIDTH_RULES.replace(",,4,8,,", ",,4,-1,,"), "0 or more"),
    (WIDTH_RULES.replace(",,4,8,,", ",,4,wide,,"), "min_width must be a number"),
    (WIDTH_RULES.replace(",,n,,,", ",,n,2,,"), "of any width"),
    (WIDTH_RULES.replace(",,square,", ",,round,"), "shape must be n, square or a vertex count"),
])
def test_bad_widths_are_refused(text, message):
    with pytest.raises(InputError, match=message):
        roof_rules.parse_rules(text)


@pytest.mark.parametrize("year, span, square, family, share", [
    (1650, 6.0, False, "stepped", 0.35), (1650, 6.0, False, "neck", 0.20),
    (1620, 6.0, False, "spout", 0.15), (1760, 6.0, False, "bell", 0.30),
    (1700, 10.0, False, "cornice", 0.40), (1700, 2.5, False, "shed", 0.50),
    (1850, 9.0, True, "pyramid", 0.40), (1961, 6.0, False, "flat", 0.25),
])
def test_the_default_rules_give_each_family_its_period_and_span(year, span, square, family,
                                                                share):
    n = 20000
    got = roof_rules.DEFAULT_RULES.draw(np.full(n, 4), np.full(n, year), np.full(n, 3.0),
                                        U(n, 5), np.full(n, span), np.full(n, square))
    assert np.mean(got == family) == pytest.approx(share, abs=0.015)


def test_every_roof_family_has_a_share_in_the_default_rules():
    shares = {k for r in roof_rules.DEFAULT_RULES.rules for k, w in r.weights if w > 0}
    assert shares == set(roofs.ROOF_TYPES)
