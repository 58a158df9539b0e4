"""lod2_output.py: v.histo.lod2's output side without GRASS (issue 17)."""

import contextlib
from dataclasses import replace
import io
import json
import os

import numpy as np
import pytest
import shapely

from reconstruction.cityjson import geometry as citygeometry
from reconstruction.cityjson import model as cityjson
from reconstruction.cityjson import seq as cityjsonseq
from reconstruction.cityjson import existing
from reconstruction.lod2 import stage as lod2
from reconstruction.lod2 import output as lod2_output
from reconstruction.core.errors import InputError
from reconstruction.testsuite.cityjson.test_existing import BAG, BOXES, FORMS

@pytest.fixture(scope="module")
def sample(bag_sample):
    return bag_sample


def test_candidates():
    assert lod2_output.candidates(["2pm", "aligned", None, " aligned"], 4).tolist() == [1, 3]
    assert lod2_output.candidates(None, 3).tolist() == [0, 1, 2]
    with pytest.raises(InputError, match="id_column"):
        lod2_output.footprint_ids({"cat": [1]}, "pand_id")
    assert lod2_output.footprint_ids({"cat": [1]}, "") is None


def built(polygons, source):
    n = len(polygons)
    footprints = lod2.Footprints(list(polygons), cats=list(range(1, n + 1)),
                                 plot=list(range(100, 100 + n)), source=source)
    result = lod2.build(lod2.prepare(
        footprints, lod2.Heights(eaves=np.full(n, 6.0), attic=np.full(n, 3.0)),
        lod2.RoofRequests(types=np.full(n, "gable", dtype=object), years=np.full(n, np.nan))))
    return footprints, result


def test_without_footprints_leaves_the_others_as_they_were():
    footprints, result = built(BOXES, ["2pm"] * 3)
    less = lod2_output.without_footprints(result, [1])
    assert less.ids == [result.ids[0], result.ids[2]] and len(less.solids) == 2
    assert less.attributes["plot"] == [100, 102]
    doc = json.loads(lod2.citymodel_text(less))
    whole = citygeometry.resolved(json.loads(lod2.citymodel_text(result)))
    assert citygeometry.resolved(doc) == {k: v for k, v in whole.items() if k != result.ids[1]}
    assert lod2_output.without_footprints(result, []) is result


@pytest.mark.parametrize("fmt", lod2_output.FORMATS)
def test_write_model_copies_the_matched_aligned_footprints(sample, tmp_path, fmt):
    model = existing.read_model(os.path.join(sample, FORMS[1]))
    fps = existing.footprints(model)
    polygons = [fps.geometry(model.buildings.index(b)) for b in BAG] + BOXES
    # the second BAG footprint is not aligned: generated, not copied
    footprints, result = built(polygons, ["aligned", "2pm", "aligned", "2pm", "2pm"])
    wanted = lod2_output.ExistingRequest(os.path.join(sample, FORMS[1]))
    match = lod2_output.match_existing(model, wanted, footprints)
    assert match.candidates.tolist() == [0, 2]
    assert match.matches.report == existing.MatchReport(2, 0, 1, 1, 0)
    path = str(tmp_path / "m.city.json")
    request = lod2_output.OutputRequest(path, fmt, 28992, "t")
    report = lod2_output.write_model(result, footprints, request, match)
    assert (report.generated, report.copied, report.replaced) == (4, 1, 1)
    with open(path) as f:
        doc = cityjsonseq.collect(f) if fmt == "cityjsonseq" else json.load(f)
    assert cityjson.consistency_errors(doc) == []
    attrs = doc["CityObjects"][BAG[0]]["attributes"]
    assert (attrs["plot"], attrs["source"], attrs["footprint"]) == (100, "aligned", 1)
    assert "building_1" not in doc["CityObjects"] and "building_2" in doc["CityObjects"]
    assert BAG[1] not in doc["CityObjects"]
    assert not os.path.exists(path + ".part")


def test_a_failing_sequence_leaves_nothing(tmp_path, monkeypatch):
    footprints, result = built(BOXES, None)

    def broken(f, *args, **kwargs):
        f.write(b"half")              # the file is opened binary
        raise OSError("disk full")

    monkeypatch.setattr(lod2_output.cityjsonseq, "write", broken)
    path = str(tmp_path / "m.city.jsonl")
    with pytest.raises(OSError):
        lod2_output.write_model(result, footprints,
                                lod2_output.OutputRequest(path, "cityjsonseq"))
    assert os.listdir(tmp_path) == []


def test_render_of_the_written_model(tmp_path, monkeypatch):
    monkeypatch.delenv("DISPLAY", raising=False)
    footprints, result = built(BOXES + [shapely.box(85000, 446500, 85014, 446508)], None)
    png = str(tmp_path / "m.png")
    request = lod2_output.OutputRequest(str(tmp_path / "m.city.jsonl"), "cityjsonseq",
                                        render=png)
    report = lod2_output.write_model(result, footprints, request)
    assert report.rendered == png and os.path.getsize(png) > 1000
    assert sorted(os.listdir(tmp_path)) == ["m.city.jsonl", "m.png"]
    with open(request.path) as f:
        assert len(cityjsonseq.collect(io.StringIO(f.read()))["CityObjects"]) == 4



@pytest.mark.parametrize("fmt", ["cityjson", "cityjsonseq"])
def test_a_picture_that_fails_leaves_the_old_model_and_no_picture(tmp_path, monkeypatch, fmt):
    """Issue 33, item 3: the model and its picture appear together or not at all."""
    footprints, result = built(BOXES, None)
    model, png = tmp_path / "m.json", tmp_path / "m.png"
    model.write_text("the old model")

    def interrupted(document, path, *args, **kwargs):
        with open(path, "wb") as f:
            f.write(b"half a picture")
        raise KeyboardInterrupt()

    monkeypatch.setattr(lod2_output.render, "render", interrupted)
    steps = []

    @contextlib.contextmanager
    def doing(what):
        steps.append(what)
        yield

    with pytest.raises(KeyboardInterrupt):
        lod2_output.write_model(result, footprints, lod2_output.OutputRequest(
            str(model), fmt, render=str(png)), doing=doing)
    assert model.read_text() == "the old model" and os.listdir(tmp_path) == ["m.json"]
    assert steps == ["writing '{}'".format(model), "drawing the picture '{}'".format(png)]


def test_a_picture_that_cannot_be_written_is_named_and_the_model_is_not_written(tmp_path):
    footprints, result = built(BOXES, None)
    with pytest.raises(InputError, match=r"Cannot write '/proc/m.png'"):
        lod2_output.write_model(result, footprints, lod2_output.OutputRequest(
            str(tmp_path / "m.json"), render="/proc/m.png"))
    assert os.listdir(tmp_path) == []

def test_copied_footprints_are_not_built(sample, tmp_path):
    model = existing.read_model(os.path.join(sample, FORMS[0]))
    fps = existing.footprints(model)
    polygons = [fps.geometry(model.buildings.index(b)) for b in BAG]
    wanted = lod2_output.ExistingRequest("m")
    for extra, built_ids in ((BOXES[:1], ["building_3"]), ([], [])):
        footprints = lod2.Footprints(polygons + extra, source=["aligned"] * (2 + len(extra)))
        prepared = lod2.prepare(footprints, lod2.Heights(eaves=6.0, attic=3.0),
                                lod2.RoofRequests(np.full(len(polygons + extra), "hip"),
                                                  np.full(len(polygons + extra), np.nan)))
        match = lod2_output.match_existing(model, wanted, footprints)
        assert match.matches.report.by_geometry == 2
        less = lod2_output.without_copied(prepared, match)
        assert less.report.rings == len(built_ids) == len(less.buildings)
        result = lod2_output.build(less, lod2.Lod2Config(), match)
        assert result.ids == built_ids
        report = lod2_output.write_model(result, footprints, lod2_output.OutputRequest(
            str(tmp_path / "m.city.json"), reference_system=28992), match)
        assert (report.generated, report.copied, report.replaced) == (len(built_ids), 2, 0)
    assert lod2_output.without_copied(prepared, None) is prepared
    with pytest.raises(InputError, match="No footprint left"):
        lod2_output.build(lod2.prepare(lod2.Footprints([None]), lod2.Heights(6.0, 3.0),
                                       lod2.RoofRequests(np.array(["hip"]), np.array([np.nan]))),
                          lod2.Lod2Config())


def test_the_matched_buildings_heights_are_measured_heights(sample):
    from reconstruction.lod2 import heights

    model = existing.read_model(os.path.join(sample, FORMS[0]))
    fps = existing.footprints(model)
    polygons = [BOXES[0]] + [fps.geometry(model.buildings.index(b)) for b in BAG]
    footprints = lod2.Footprints(polygons, source=["aligned"] * 3)
    match = lod2_output.match_existing(model, lod2_output.ExistingRequest("m"), footprints)
    columns = lod2_output.attribute_columns(match, 3)
    assert columns["b3_h_maaiveld"][0] is None and columns["identificatie"][1:] == list(BAG)
    measured = heights.measured_heights(columns)
    assert np.isnan(measured.eaves[0]) and measured.known[1:].all()
    assert measured.ground[2] == pytest.approx(-0.077)
    assert lod2_output.attribute_columns(match, 3, ["b3_h_dak_max"]) == {
        "b3_h_dak_max": [None] + [model.objects[b]["attributes"]["b3_h_dak_max"] for b in BAG]}


def _prepared(polygons, source=None, roof="gable"):
    n = len(polygons)
    footprints = lod2.Footprints(list(polygons), cats=list(range(1, n + 1)),
                                 plot=list(range(100, 100 + n)), source=source)
    prepared = lod2.prepare(
        footprints, lod2.Heights(eaves=np.full(n, 6.0), attic=np.full(n, 3.0)),
        lod2.RoofRequests(types=np.full(n, roof, dtype=object), years=np.full(n, np.nan)))
    return footprints, prepared


def _row_of_houses(n):
    return [shapely.box(85000 + (i % 40) * 12, 446000 + (i // 40) * 16,
                        85000 + (i % 40) * 12 + 8, 446000 + (i // 40) * 16 + 11)
            for i in range(n)]


def test_a_cityjsonseq_built_and_written_in_steps_is_the_one_written_at_once(
        sample, tmp_path, monkeypatch):
    """Issue 33, item 9: the streamed CityJSONSeq (a step of buildings built,
    written and let go at a time) is byte for byte the one written from
    every solid at once, copied buildings included; -v checks every solid."""
    from reconstruction.lod2.solids import build as solids

    model = existing.read_model(os.path.join(sample, FORMS[1]))
    fps = existing.footprints(model)
    polygons = [fps.geometry(model.buildings.index(b)) for b in BAG] + _row_of_houses(23)
    source = ["aligned"] + ["2pm"] * 24
    footprints, prepared = _prepared(polygons, source, roof="hip")
    match = lod2_output.match_existing(
        model, lod2_output.ExistingRequest(os.path.join(sample, FORMS[1])), footprints)
    request = lod2_output.OutputRequest(str(tmp_path / "at_once.city.jsonl"), "cityjsonseq",
                                        28992, "t")
    config = lod2.Lod2Config()
    monkeypatch.setattr(solids, "STEP", 4)      # (vertex numbering follows the steps)
    result = lod2_output.build(lod2_output.without_copied(prepared, match), config, match)
    at_once = lod2_output.write_model(result, footprints, request, match, validate=True)
    streamed = replace(request, path=str(tmp_path / "steps.city.jsonl"))
    summary, report, invalid = lod2_output.write_in_steps(
        lod2_output.without_copied(prepared, match), config, footprints, streamed, match,
        validate=True)
    with open(request.path, "rb") as a, open(streamed.path, "rb") as b:
        assert a.read() == b.read()
    assert report == at_once and (report.generated, report.copied) == (24, 1)
    assert report.copied_checked == (("<{}-0> (lod 2.2)".format(BAG[0]), None),)
    assert summary.ids == result.ids and list(summary.roof_types) == list(result.roof_types)
    assert summary.report == result.report and summary.roof_counts() == result.roof_counts()
    assert invalid == [None] * 24
    assert sorted(os.listdir(tmp_path)) == ["at_once.city.jsonl", "steps.city.jsonl"]


def test_a_streamed_write_that_fails_leaves_nothing(tmp_path, monkeypatch):
    from reconstruction.lod2.solids import build as solids

    footprints, prepared = _prepared(_row_of_houses(9))
    monkeypatch.setattr(solids, "STEP", 4)
    written = []

    def add_then_fail(self, *args, **kwargs):
        if written:
            raise KeyboardInterrupt()
        written.append(1)
        return add(self, *args, **kwargs)

    add = cityjsonseq.SeqWriter.add
    monkeypatch.setattr(cityjsonseq.SeqWriter, "add", add_then_fail)
    (tmp_path / "m.jsonl").write_text("old")
    with pytest.raises(KeyboardInterrupt):
        lod2_output.write_in_steps(prepared, lod2.Lod2Config(), footprints,
                                   lod2_output.OutputRequest(str(tmp_path / "m.jsonl"),
                                                             "cityjsonseq"))
    assert os.listdir(tmp_path) == ["m.jsonl"] and (tmp_path / "m.jsonl").read_text() == "old"


def test_the_picture_of_a_large_model_draws_the_footprints_nearest_its_middle():
    polygons = _row_of_houses(120)
    mask = lod2_output.drawn_footprints(polygons, most=20)
    assert mask.sum() == 20
    middle = shapely.box(*shapely.total_bounds(polygons)).centroid
    drawn = max(polygons[i].centroid.distance(middle) for i in np.nonzero(mask)[0])
    left = min(polygons[i].centroid.distance(middle) for i in np.nonzero(~mask)[0])
    assert drawn <= left
    assert lod2_output.drawn_footprints(polygons, most=120) is None
    assert lod2_output.drawn_footprints(polygons[:3] + [None], most=2).tolist()[3] is False


@pytest.mark.parametrize("fmt", lod2_output.FORMATS)
def test_render_draws_at_most_max_drawn_buildings_and_says_so(tmp_path, monkeypatch, fmt):
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.setattr(lod2_output.render, "MAX_DRAWN", 5)
    seen = []
    draw = lod2_output.render.render

    def counted(document, *args, **kwargs):
        seen.append(len(document["CityObjects"]))
        return draw(document, *args, **kwargs)

    monkeypatch.setattr(lod2_output.render, "render", counted)
    footprints, prepared = _prepared(_row_of_houses(12))
    request = lod2_output.OutputRequest(str(tmp_path / "m.json"), fmt,
                                        render=str(tmp_path / "m.png"))
    if fmt == "cityjson":
        report = lod2_output.write_model(lod2.build(prepared), footprints, request)
    else:
        report = lod2_output.write_in_steps(prepared, lod2.Lod2Config(), footprints, request)[1]
    assert seen == [5] and report.drawn == 5 and report.generated == 12
    assert os.path.getsize(tmp_path / "m.png") > 1000


def test_a_model_in_longitude_and_latitude_that_claims_rd_is_refused():
    """Issue 33, item 8: every id names a building 85 km away and nothing
    matched by geometry: the model is not where it says; nothing is copied."""
    from reconstruction.testsuite.cityjson.test_checks import single

    doc = single([("a", None), ("b", None)], scale=[1e-6, 1e-6, 0.001],
                 translate=[4.36, 52.01, 0.0])
    doc["metadata"] = {"referenceSystem": "https://www.opengis.net/def/crs/EPSG/0/7415"}
    model = existing.model_of(doc, "lonlat.city.json")
    polygons = [shapely.box(85000, 446000, 85004, 446004), shapely.box(85010, 446000, 85014,
                                                                        446004)]
    footprints = lod2.Footprints(polygons, source=["aligned"] * 2)
    with pytest.raises(InputError) as error:
        lod2_output.match_existing(model, lod2_output.ExistingRequest("m"), footprints,
                                   ids=["a", "b"])
    said = str(error.value)
    assert "lie far from their footprints (2 of them" in said
    assert "look like longitude and latitude" in said and "EPSG:7415" in said
    # one id match near its footprint: the far one is only warned about
    near = [shapely.box(4.36, 52.01, 4.364, 52.014)] + polygons[1:]
    match = lod2_output.match_existing(model, lod2_output.ExistingRequest("m"),
                                       lod2.Footprints(near, source=["aligned"] * 2),
                                       ids=["a", "b"])
    assert match.matches.report.by_id == 1 and match.matches.report.far_ids == 1
