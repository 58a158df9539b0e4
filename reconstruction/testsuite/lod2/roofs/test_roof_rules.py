"""Roof rules: the thesis's Table B.1 as data, the suite's default, rules files."""

import json
import time

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

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
    ("{not json", "is not JSON"),
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


# ---------------------------------------------------------------------------
# Messages and cost of rules files (issue 49, items 10, 14 and 15)
# ---------------------------------------------------------------------------

def test_an_error_names_the_files_own_line_counting_comments_and_blank_lines():
    """The line an editor shows: THESIS_CSV's row ",1915,n" is line 5 after a
    comment; with two blank lines and a second comment before it, line 8."""
    bad = THESIS_CSV.replace(",1915,n,60,0,0,40,0", ",1915,n,60,0,0,40,1")
    with pytest.raises(InputError, match=r"^Roof rules line 5 \(-1915, n-sided\): the weights "
                                         r"sum to 101"):
        roof_rules.parse_rules(bad)
    spaced = bad.replace("1916,,4", "\n# after the first war\n\n1916,,4")
    with pytest.raises(InputError, match=r"^Roof rules line 8 \("):
        roof_rules.parse_rules(spaced)
    # a value that is not a number, after CRLF line ends and a comment
    text = THESIS_CSV.replace("1916,,n,60,,,40,", "# x\n1916,,n,sixty,,,40,").replace(
        "\n", "\r\n")
    with pytest.raises(InputError, match="^Roof rules line 7: a weight must be a number"):
        roof_rules.parse_rules(text)
    # too few values, line 3 behind a blank line
    with pytest.raises(InputError, match="^Roof rules line 3: 4 values for 8 columns"):
        roof_rules.parse_rules("from,to,shape,flat,hip,gable,mansard,stepped\n\n,,n,100\n")


def test_a_duplicated_column_is_named_not_summed_twice():
    """A header with flat twice (a file edited by hand): its weights summed
    to 100 in the file, and the message said they summed to 110, counting the
    second flat column's 10 twice."""
    text = ("from,to,shape,flat,hip,flat\n"
            ",1915,n,50,40,10\n"
            "1916,,n,50,40,10\n")
    with pytest.raises(InputError) as error:
        roof_rules.parse_rules(text)
    message = str(error.value)
    assert "sum" not in message
    assert message == ("Roof rules line 1: the column <flat> appears twice in the header "
                       "(columns 4 and 6): one column per roof type")
    # the same roof type twice in a JSON row (keys differing in case)
    data = {"rules": [{"from": None, "to": None, "shape": "n",
                       "weights": {"flat": 60, "Flat": 40}}]}
    with pytest.raises(InputError, match=r"^Roof rules row 1 \(-, n-sided\): two weights for flat$"):
        roof_rules.parse_rules(json.dumps(data))


@pytest.mark.parametrize("text, where", [
    (THESIS_CSV.replace(",1915,4,", "1950,1915,4,"), "line 3"),
    ("from,to,shape,flat\n,1899,n,100\n1920,1900,n,100\n1901,,n,100\n", "line 3"),
    ('[{"from": null, "to": 1899, "shape": "n", "weights": {"flat": 100}},'
     ' {"from": 1920, "to": 1900, "shape": "n", "weights": {"flat": 100}},'
     ' {"from": 1901, "to": null, "shape": "n", "weights": {"flat": 100}}]', "row 2"),
])
def test_a_reversed_period_says_it_starts_after_it_ends(text, where):
    with pytest.raises(InputError) as error:
        roof_rules.parse_rules(text)
    message = str(error.value)
    assert message.startswith("Roof rules {} (".format(where))
    assert "the period starts after it ends" in message
    assert "first period" not in message


def many_periods(n):
    """A rules file of ``n`` one-year periods, each with one n-sided row."""
    rows = ["from,to,shape,flat,hip"]
    rows += ["{},{},n,50,50".format("" if k == 0 else 1000 + k, "" if k == n - 1 else 1000 + k)
             for k in range(n)]
    return "\n".join(rows) + "\n"


def test_a_rules_file_of_16000_periods_is_read_and_drawn_from_in_linear_time():
    """Each period was looked up in a list of the periods seen and each
    period's n-sided row in every row: 16,000 periods took 10 s (34 s on a
    busier machine) to read; now 0.2 s. The bound leaves room for a slow CI."""
    text = many_periods(16000)
    start = time.perf_counter()
    rules = roof_rules.parse_rules(text)
    n = np.full(2000, 5)
    years = np.linspace(900, 18000, 2000)
    got = rules.draw(n, years, np.full(2000, 3.0), U(2000, 3))
    seconds = time.perf_counter() - start
    assert len(rules.periods) == 16000
    assert set(got) <= {"flat", "hip"} and len(got) == 2000
    assert rules.types_in(1500) == {"flat", "hip"}
    assert seconds < 4.0, "16,000 periods took {:.1f} s".format(seconds)


def test_rules_json_nested_a_thousand_levels_deep_is_one_input_error(tmp_path):
    """json raised RecursionError, a traceback (issue 49, item 10)."""
    path = tmp_path / "deep.json"
    path.write_text('{"rules": ' + "[" * 1000 + "]" * 1000 + "}")
    with pytest.raises(InputError, match="nested too deeply") as error:
        roof_rules.read_rules(str(path))
    assert str(path) in str(error.value)
    path.write_text('[{"from": null, "to": null, "shape": "\\ud800", "weights": {"flat": 100}}]')
    with pytest.raises(InputError, match="lone UTF-16 surrogate"):
        roof_rules.read_rules(str(path))


# pieces of rules files, right and wrong: what a careless or hostile user types
CELLS = st.sampled_from(["", " ", "0", "3", "4", "5", "n", "N", "square", "100", "50", "-1",
                         "1e400", "-1e400", "nan", "inf", "1915", "1916", "1849.5", "1e20",
                         "9" * 5000, "\u00b2", "\u0664", "true", "#", '"', '"a,b"', "x" * 200,
                         "flat", "hip", "dome", "\x00", "\ud800", "\u2028"])
HEADERS = st.lists(st.sampled_from(["from", "to", "shape", "min_width", "max_width", "flat",
                                    "hip", "gable", "mansard", "stepped", "dome", "", "FLAT"]),
                   max_size=9)
LINES = st.one_of(st.lists(CELLS, max_size=9).map(",".join),
                  st.sampled_from(["", "# comment", "   ", ",1915,n,100", "1916,,n,,100",
                                   ",,n,100,,", ",,square,,,100"]))
CSV_FILES = st.builds(lambda header, lines, end: end.join([",".join(header)] + lines),
                      HEADERS, st.lists(LINES, max_size=8), st.sampled_from(["\n", "\r\n", "\r"]))
JSON_VALUES = st.recursive(
    st.none() | st.booleans() | st.integers(-10 ** 400, 10 ** 400) | st.floats()
    | st.sampled_from(["n", "square", "4", "flat", "hip", "", "1915", "\ud800"]),
    lambda inner: st.lists(inner, max_size=4) | st.dictionaries(
        st.sampled_from(["from", "to", "shape", "weights", "rules", "flat", "hip", "min_width",
                         "max_width", "Flat"]), inner, max_size=5),
    max_leaves=20)
JSON_ROWS = st.fixed_dictionaries(
    {"from": JSON_VALUES, "to": JSON_VALUES, "shape": JSON_VALUES,
     "weights": st.dictionaries(st.sampled_from(["flat", "hip", "Flat", "dome", ""]),
                                JSON_VALUES | st.integers(0, 100), max_size=3)},
    optional={"min_width": JSON_VALUES, "max_width": JSON_VALUES})
JSON_FILES = st.one_of(
    JSON_VALUES.map(lambda v: json.dumps({"rules": v})),
    st.lists(JSON_ROWS, max_size=5).map(json.dumps),
    st.lists(JSON_ROWS, max_size=5).map(lambda rows: json.dumps({"rules": rows})),
    st.integers(1, 3000).map(lambda depth: "[" * depth + "]" * depth))
RULES_TEXT = st.one_of(CSV_FILES, JSON_FILES, st.text(max_size=200),
                       st.sampled_from([THESIS_CSV, WIDTH_RULES, roof_rules.DEFAULT_TABLE]))


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(text=RULES_TEXT, bom=st.booleans())
def test_any_rules_file_is_read_or_refused_with_one_input_error(tmp_path_factory, text, bom):
    """Whatever a rules file holds: parsed rules that give every footprint a
    roof type in every period, or one InputError, never another exception
    (issue 49, item 10)."""
    path = tmp_path_factory.mktemp("rules") / "rules.txt"
    path.write_bytes((roof_rules.BOM if bom else "").encode("utf-8")
                     + text.encode("utf-8", "surrogatepass"))
    try:
        rules = roof_rules.read_rules(str(path))
    except InputError as error:
        assert str(error)
        return
    years = [None] + [p[0] for p in rules.periods if p[0] is not None] + [3000]
    n = np.array([3, 4, 5, 4] * len(years))
    got = rules.draw(n, np.repeat(years, 4), np.full(len(n), 3.0), U(len(n), 0),
                     np.full(len(n), 6.0), np.array([False, True, False, False] * len(years)))
    assert set(got) <= set(roofs.ROOF_TYPES) and None not in set(got)
