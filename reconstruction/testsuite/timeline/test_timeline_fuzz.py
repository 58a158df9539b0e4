"""v.histo.timeline on malformed models (issue 49, item 10): every model, an epoch's
(models=) or a merged one (input=), gives a result or one InputError, never another
exception. Property tests over mutations of a small valid epoch model and of a merged
model, derandomized in CI (conftest.py's profile; more examples with
``--hypothesis-profile=explore``), and the cases of the issue by name."""

import copy
import json
import os
import tempfile

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from reconstruction.cityjson import existing
from reconstruction.core.errors import InputError
from reconstruction.epochs.dynamic import check_merged, merge_epochs
from reconstruction.testsuite.epochs.test_dynamic import model, town
from reconstruction.testsuite.timeline.test_timeline import doing, options
from reconstruction import timeline

#: JSON values put in place of a part of a model
LEAVES = (st.none() | st.booleans() | st.integers(-2 ** 70, 2 ** 70) | st.integers(-3, 40)
          | st.floats(allow_nan=True, allow_infinity=True) | st.text(max_size=4)
          | st.sampled_from(["\ud800", "Building", "BuildingPart", "Solid", "MultiSurface",
                             "CityJSON", "2.0", "1.1", "EPSG:4326", "parents", "children"]))
VALUES = st.recursive(LEAVES, lambda inner: st.lists(inner, max_size=3) | st.dictionaries(
    st.text(max_size=4) | st.sampled_from(["type", "geometry", "boundaries", "epochs"]),
    inner, max_size=3), max_leaves=6)


def epoch_model():
    return model(1915, {"a": (84000, 446000, 8, 1), "b": (84020, 446000, 9, 2)})


def merged_model():
    return merge_epochs(town(), register={"0503100000000007": 1902}).document


def mutated(data, doc):
    """``doc`` with one to three of its parts replaced, removed or added to."""
    doc = copy.deepcopy(doc)
    for _ in range(data.draw(st.integers(1, 3))):
        parent, key = None, None
        node = doc
        while isinstance(node, (dict, list)) and node and (
                parent is None or data.draw(st.integers(0, 7)) > 0):
            keys = list(node) if isinstance(node, dict) else list(range(len(node)))
            parent, key = node, data.draw(st.sampled_from(keys))
            node = node[key]
        if parent is None:
            continue
        action = data.draw(st.sampled_from(["replace", "replace", "delete", "add"]))
        if action == "delete":
            del parent[key]
        elif action == "add" and isinstance(parent, list):
            parent.append(data.draw(VALUES))
        else:
            parent[key] = data.draw(VALUES)
    return doc


REGISTER = {"cat": [1], "identificatie": ["0503100000000007"], "bouwjaar": [1902]}


def outcome(folder, fmt, **kw):
    """Run and write v.histo.timeline's library part: the result, or the InputError."""
    out = os.path.join(folder, "out.city.jsonl" if fmt == "cityjsonseq" else "out.city.json")
    try:
        config = timeline.read_config(options(output=out, format=fmt, **kw), {})
        result = timeline.run(config, lambda name: REGISTER, doing)
        timeline.write(result, config, timeline.report_json(result, config))
        timeline.report(result, config, 1, 0.1)
    except InputError as error:
        assert str(error)
        return error
    return result, out


def write(folder, name, doc):
    path = os.path.join(folder, name)
    with open(path, "w") as f:
        json.dump(doc, f)
    return path


#: examples per property: 150, the same ones on every run in CI (conftest.py's
#: derandomized profile), ten times as many new ones with --hypothesis-profile=explore
EXAMPLES = 150 if settings.default.derandomize else 1500
FUZZ = settings(max_examples=EXAMPLES, deadline=None,
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])


@FUZZ
@given(data=st.data(), fmt=st.sampled_from(["cityjson", "cityjsonseq"]),
       register=st.booleans())
def test_a_malformed_epoch_model_gives_a_result_or_one_input_error(data, fmt, register):
    with tempfile.TemporaryDirectory() as folder:
        good = write(folder, "m1880.city.json", town()[1].document)
        bad = write(folder, "m1915.city.json", mutated(data, epoch_model()))
        got = outcome(folder, fmt, models="{},{}".format(good, bad), years="1880,1915",
                      register="bag" if register else "")
        if not isinstance(got, InputError):
            # what was written is a model over time that reads back whole
            check_merged(existing.read_document(got[1]), got[1])


@FUZZ
@given(data=st.data(), fmt=st.sampled_from(["cityjson", "cityjsonseq"]),
       year=st.sampled_from([1880, 1900, 1902, 1915, 2000]))
def test_a_malformed_merged_model_gives_a_result_or_one_input_error(data, fmt, year):
    with tempfile.TemporaryDirectory() as folder:
        bad = write(folder, "town.city.json", mutated(data, merged_model()))
        got = outcome(folder, fmt, input=bad, snapshot=str(year))
        if not isinstance(got, InputError):
            existing.read_document(got[1])


def with_object(doc, oid, change):
    doc = copy.deepcopy(doc)
    change(doc["CityObjects"][oid])
    return doc


def first_index(value):
    def change(obj):
        obj["geometry"][0]["boundaries"][0][0][0][0] = value
    return change


def set_attribute(name, value):
    def change(obj):
        obj.setdefault("attributes", {})[name] = value
    return change


def epoch(change):
    doc = epoch_model()
    change(doc)
    return doc


EPOCH_CASES = {
    "negative index": (with_object(epoch_model(), "a", first_index(-3)), "negative"),
    "index past the vertices": (with_object(epoch_model(), "a", first_index(10 ** 6)),
                                "past its"),
    "null index": (with_object(epoch_model(), "a", first_index(None)), "not an integer"),
    "metadata a string": (epoch(lambda d: d.update(metadata="EPSG:7415")),
                          "metadata is not an object"),
    "attributes a list": (with_object(epoch_model(), "a", lambda o: o.update(attributes=[1])),
                          "attributes that are not an object"),
    "an object a string": (epoch(lambda d: d["CityObjects"].update(c="x")),
                           "not a JSON object"),
}


@pytest.mark.parametrize("case", sorted(EPOCH_CASES))
def test_the_issues_malformed_epoch_models_are_refused_by_name(tmp_path, case):
    doc, message = EPOCH_CASES[case]
    good = write(str(tmp_path), "m1880.city.json", town()[1].document)
    bad = write(str(tmp_path), "m1915.city.json", doc)
    got = outcome(str(tmp_path), "cityjson", models="{},{}".format(good, bad),
                  years="1880,1915")
    assert isinstance(got, InputError) and message in str(got)


def merged_with(change):
    doc = merged_model()
    change(doc)
    return doc


def earlier_form():
    """The merged model as v.histo.timeline wrote it before the Extension (issue 52): a
    building's versions its geometries, ``geometry_epochs`` their epochs."""
    doc = merged_model()
    objects = doc["CityObjects"]
    for oid in [o for o, v in objects.items() if v["type"] == "+BuildingVersion"]:
        version = objects.pop(oid)
        building = objects[version["versionOf"]]
        building.setdefault("geometry", []).extend(version["geometry"])
        building["attributes"].setdefault("geometry_epochs", []).append(version["epochs"])
        building["attributes"].pop("+transitions", None)
    del doc["extensions"], doc["+versioning"]
    return doc


MERGED_CASES = {
    "epochs a number": (with_object(merged_model(), "kept", set_attribute("epochs", 1880)),
                        "no list of epochs"),
    "epochs a text": (with_object(merged_model(), "kept", set_attribute("epochs", "1880")),
                      "no list of epochs"),
    "version epochs a number": (with_object(merged_model(), "kept~1880", lambda o: o.update(
        epochs=1880)), "no list of epochs"),
    "a version of nothing": (with_object(merged_model(), "kept~1880", lambda o: o.update(
        versionOf="nobody")), "<kept>: it has no geometry"),
    "a version of a list": (with_object(merged_model(), "kept~1880", lambda o: o.update(
        versionOf=["kept"])), "<kept>: it has no geometry"),
    "epochAttributes a list": (with_object(merged_model(), "raised~1880", lambda o: o.update(
        epochAttributes=[1])), "epochAttributes that are not"),
    "epochAttributes of numbers": (with_object(merged_model(), "kept~1880", lambda o: o.update(
        epochAttributes={"1915": 3})), "epochAttributes that are not"),
    "a building without the version of an epoch": (merged_with(lambda d: d[
        "CityObjects"].pop("raised~1915")), "has no version of its epoch 1915"),
    "a geometry on a building": (merged_with(lambda d: d["CityObjects"]["kept"].update(
        geometry=d["CityObjects"]["kept~1880"]["geometry"])), "a geometry of its own"),
    "the form before the Extension": (earlier_form(), "earlier v.histo.timeline"),
    "metadata a string": (merged_with(lambda d: d.update(metadata="x")),
                          "metadata is not an object"),
    "an index past the vertices": (with_object(merged_model(), "kept~1880",
                                                first_index(10 ** 6)),
                                   "past its"),
}


@pytest.mark.parametrize("case", sorted(MERGED_CASES))
def test_the_issues_malformed_merged_models_are_refused_by_name(tmp_path, case):
    doc, message = MERGED_CASES[case]
    bad = write(str(tmp_path), "town.city.json", doc)
    got = outcome(str(tmp_path), "cityjson", input=bad, snapshot="1915")
    assert isinstance(got, InputError) and message in str(got)


def test_a_merged_model_without_a_transform_gives_its_snapshot(tmp_path):
    """No ``transform``: the vertices are metres as they stand (CityJSON allows it)."""
    doc = merged_model()
    t = doc.pop("transform")
    doc["vertices"] = [[v * s + o for v, s, o in zip(row, t["scale"], t["translate"])]
                       for row in doc["vertices"]]
    bad = write(str(tmp_path), "town.city.json", doc)
    result, _ = outcome(str(tmp_path), "cityjson", input=bad, snapshot="1915")
    assert result.buildings == 3


@pytest.mark.parametrize("text, message", [
    ("[" * 100000 + "]" * 100000, "nested too deeply"),
    ('{"type": "CityJSON", "version": "2.0", "CityObjects": {"a": {"type": "Building", '
     '"attributes": {"name": "\\ud800"}}}, "vertices": []}', "lone UTF-16 surrogate"),
], ids=["nested 100,000 deep", "a lone surrogate"])
@pytest.mark.parametrize("option", ["models", "input"])
def test_deep_nesting_and_a_lone_surrogate_are_one_input_error(tmp_path, text, message,
                                                                option):
    path = tmp_path / "bad.city.json"
    path.write_text(text)
    kw = {"models": str(path), "years": "1915"} if option == "models" else {
        "input": str(path), "snapshot": "1915"}
    got = outcome(str(tmp_path), "cityjson", **kw)
    assert isinstance(got, InputError) and message in str(got)


def test_a_vertex_beyond_any_town_is_refused_not_wrapped_round(tmp_path):
    doc = epoch_model()
    doc["transform"]["translate"] = [1e300, 0.0, 0.0]
    good = write(str(tmp_path), "m1880.city.json", town()[1].document)
    bad = write(str(tmp_path), "m1915.city.json", doc)
    got = outcome(str(tmp_path), "cityjson", models="{},{}".format(good, bad),
                  years="1880,1915")
    assert isinstance(got, InputError) and "more than 100000 km" in str(got)
