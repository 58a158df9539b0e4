"""Untrusted JSON: every way Python's json fails on a file is one InputError."""

import json

import pytest

from reconstruction.core import jsontext
from reconstruction.core.errors import InputError


def test_a_good_document_is_read(tmp_path):
    path = tmp_path / "a.json"
    path.write_text('{"a": [1, 2, {"b": "\\ud83d\\ude00"}]}', encoding="utf-8")
    assert jsontext.load(str(path), "model") == {"a": [1, 2, {"b": "\U0001F600"}]}


@pytest.mark.parametrize("text, said", [
    ("[" * 100000 + "]" * 100000, "nested too deeply"),
    ('{"a": ' * 5000 + "1" + "}" * 5000, "nested too deeply"),
    ('{"a": "\\ud800"}', "lone UTF-16 surrogate"),
    ('{"\\udc00": 1}', "lone UTF-16 surrogate"),
    ('{"a": ["x", "\\uDBFF"]}', "lone UTF-16 surrogate"),
    ("{'a': 1}", "is not JSON"),
    ("", "is not JSON"),
])
def test_bad_text_is_one_input_error(text, said):
    with pytest.raises(InputError, match=said) as e:
        jsontext.loads(text, "rules file", "r.json")
    assert "'r.json'" in str(e.value) and "rules file" in str(e.value)


def test_nesting_that_json_reads_is_kept():
    doc = jsontext.loads("[" * 200 + "]" * 200, "model", "m.json")
    assert json.dumps(doc).count("[") == 200


def test_latin1_and_missing_files(tmp_path):
    path = tmp_path / "latin.json"
    path.write_bytes('{"name": "Li\u00e8ge"}'.encode("latin-1"))
    with pytest.raises(InputError, match=r"not UTF-8 text \(byte 0xe8 at offset 12\)"):
        jsontext.load(str(path), "manifest")
    with pytest.raises(InputError, match="Cannot read the manifest"):
        jsontext.load(str(tmp_path / "none.json"), "manifest")
