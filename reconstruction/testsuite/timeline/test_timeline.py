"""v.histo.timeline's library part (reconstruction.timeline): options, the register,
the merge and the snapshot written as CityJSON and CityJSONSeq (no GRASS)."""

import contextlib
import re
import json

import pytest

from reconstruction.cityjson import existing
from reconstruction.core.errors import InputError
from reconstruction.epochs.dynamic import snapshot
from reconstruction.testsuite.epochs.test_dynamic import town
from reconstruction import timeline

REGISTER = {"cat": [1, 2, 3], "identificatie": ["0503100000000007", " ", "0503100000000008"],
            "bouwjaar": [1902, 1700, 9999]}


def options(**kw):
    out = {"models": "", "years": "", "input": "", "output": "out.city.json", "register": "",
           "id_column": "", "year_column": "", "format": "cityjson", "snapshot": "",
           "report": "", "title": ""}
    out.update(kw)
    return out


@pytest.mark.parametrize("given, message", [
    ({}, "either models= (with years=) or input="),
    ({"models": "a.json", "input": "m.json"}, "either models="),
    ({"models": "a.json,b.json", "years": "1880"}, "one year per model"),
    ({"models": "a.json,b.json", "years": "1880,1880"}, "two models of one year"),
    ({"models": "a.json", "years": "1880.5"}, "years= must be a number"),
    ({"input": "m.json"}, "needs snapshot="),
    ({"models": "a.json,b.json", "years": "0,1880"}, "years= must be"),
    ({"input": "m.json", "snapshot": "-5"}, "snapshot= must be"),
    ({"models": "a.json", "years": "1880", "format": "obj"}, "format=: one of"),
])
def test_bad_options_are_refused_with_the_option_named(given, message):
    with pytest.raises(InputError, match=re.escape(message)):
        timeline.read_config(options(**given), {})


def test_the_register_gives_ids_and_years_and_no_year_for_a_placeholder():
    assert timeline.read_register(REGISTER) == {"0503100000000007": 1902,
                                                "0503100000000008": None}
    with pytest.raises(InputError, match="no building id column"):
        timeline.read_register({"cat": [1], "bouwjaar": [1900]}, name="reg")
    with pytest.raises(InputError, match="no year column <bj>"):
        timeline.read_register(REGISTER, year_column="bj", name="reg")


def resolved(doc):
    """{id: (attributes, the coordinates of every geometry in millimetres)}: a document
    as its vertices' order aside."""
    t = doc["transform"]
    vertices = [[round(v * s + o, 3) for v, s, o in zip(row, t["scale"], t["translate"])]
                for row in doc["vertices"]]

    def coords(node):
        return [coords(n) for n in node] if isinstance(node, list) else vertices[node]
    return {oid: (obj.get("attributes"), [coords(g["boundaries"]) for g in obj.get(
        "geometry", ())]) for oid, obj in doc["CityObjects"].items()}


def write_epochs(tmp_path):
    """The epochs of test_dynamic's town as files: {year: path}."""
    paths = {}
    for epoch in town():
        paths[epoch.year] = str(tmp_path / "model_{}.city.json".format(epoch.year))
        with open(paths[epoch.year], "w") as f:
            json.dump(epoch.document, f)
    return paths


def doing(_text):
    return contextlib.nullcontext()


@pytest.mark.parametrize("fmt", ["cityjson", "cityjsonseq"])
def test_the_merged_model_written_and_read_back_gives_each_epoch_its_snapshot(tmp_path, fmt):
    paths = write_epochs(tmp_path)
    out = str(tmp_path / ("town.city.jsonl" if fmt == "cityjsonseq" else "town.city.json"))
    config = timeline.read_config(options(models="{},{}".format(paths[1915], paths[1880]),
                                          years="1915,1880", output=out, register="bag",
                                          format=fmt), {"g": True})
    result = timeline.run(config, lambda name: REGISTER, doing)
    assert result.merge.buildings == 4 and result.merge.standing == 1
    assert result.years == (1880, 1915) and result.register == 2
    timeline.write(result, config)
    back = existing.read_document(out)
    assert resolved(back) == resolved(result.document)
    assert "buildings=4" in timeline.shell_counts(result)
    # the snapshot of the written model equals the one of the merge in memory
    one = timeline.read_config(options(input=out, snapshot="1880", output=str(
        tmp_path / "y1880.city.json")), {})
    taken = timeline.run(one, lambda name: {}, doing)
    assert taken.buildings == 3 and taken.merge is None
    assert resolved(taken.document) == resolved(snapshot(result.document, 1880))


def test_the_report_counts_and_lists_the_conflicts(tmp_path):
    paths = write_epochs(tmp_path)
    config = timeline.read_config(options(models="{},{}".format(paths[1880], paths[1915]),
                                          years="1880,1915", register="bag",
                                          output=str(tmp_path / "t.city.json")), {})
    early = {"cat": [1], "identificatie": ["0503100000000007"], "bouwjaar": [1700]}
    result = timeline.run(config, lambda name: early, doing)
    assert list(result.merge.conflicts) == ["NL.IMBAG.Pand.0503100000000007"]
    text = " ".join(m.text for m in timeline.report(result, config, 1000, 0.1))
    assert "1 buildings where the maps and the register disagree" in text
    assert "<NL.IMBAG.Pand.0503100000000007>" in text
    assert timeline.report_json(result, config)["conflicts"] == dict(result.merge.conflicts)


def test_a_model_that_cannot_be_opened_is_named(tmp_path):
    config = timeline.read_config(options(models=str(tmp_path / "none.city.json"),
                                          years="1880"), {})
    with pytest.raises(InputError, match="Cannot read the model '.*none.city.json'"):
        timeline.run(config, lambda name: {}, doing)


def test_ids_kept_apart_are_counted_in_a_warning_the_report_and_g(tmp_path):
    from reconstruction.testsuite.epochs.test_dynamic import model

    paths = []
    for year, x in ((1880, 84000), (1915, 84300)):
        paths.append(str(tmp_path / "m{}.city.json".format(year)))
        with open(paths[-1], "w") as f:
            json.dump(model(year, {"building_1": (x, 446000, 8, 1)}), f)
    config = timeline.read_config(options(models=",".join(paths), years="1880,1915",
                                          output=str(tmp_path / "t.city.json")), {})
    result = timeline.run(config, lambda name: {}, doing)
    said = [m for m in timeline.report(result, config, 1000, 0.1) if "do not overlap" in m.text]
    assert len(said) == 1 and said[0].level == "warning"
    assert "1 ids name buildings in different places" in said[0].text
    assert "<building_1> also as <building_1@1915>" in said[0].text
    assert timeline.report_json(result, config)["apart"] == {"building_1": ["building_1@1915"]}
    assert "apart=1" in timeline.shell_counts(result)
