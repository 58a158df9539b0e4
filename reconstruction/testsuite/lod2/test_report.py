"""lod2/report.py: v.histo.lod2's messages of made-up results, without GRASS (issue 27)."""

from dataclasses import replace
from types import SimpleNamespace

import numpy as np
import pytest

from reconstruction.cityjson.copied import CopyReport
from reconstruction.cityjson.existing import MatchReport
from reconstruction.core.messages import Message
from reconstruction.lod2 import report as lod2_report
from reconstruction.lod2 import validity_lines
from reconstruction.lod2.roofs import ROOF_TYPES
from reconstruction.lod2.config import (ExistingRequest, HeightConfig, Lod2Config, OutputRequest,
                                        StreetConfig)
from reconstruction.lod2.inputs import HeightReport
from reconstruction.lod2.output import OutputReport
from reconstruction.lod2.pipeline import Lod2Run
from reconstruction.lod2.solids.vertex_budget import MAX_ROOF_VERTICES
from reconstruction.lod2.stage import Lod2Report, Lod2Result, RoofFallback
from reconstruction.lod2.report import (build_messages, built_messages, config_messages,
                                        existing_messages, footprint_messages,
                                        ground_points_messages, height_messages,
                                        matched_heights_messages, plots_messages,
                                        street_edge_messages, street_messages)

OUTPUT = OutputRequest("out.city.json", reference_system="https://x/7415")
CONFIG = Lod2Config(output=OUTPUT)
NONE = Lod2Report(0, 0, 0, 0, 0, {}, 3)


def W(text):
    return Message(text, "warning")


def N(text):
    return Message(text, "message")


def V(text):
    return Message(text, "verbose")


def test_config_messages():
    assert config_messages(CONFIG) == []
    assert config_messages(replace(CONFIG, output=OutputRequest("o"), map_ignored=True)) == [
        W("The location has no EPSG code and crs= is not given: the CityJSON file has no "
          "reference system"),
        W("map= is drawn only in the picture of render= and the page of viewer=: ignored")]


@pytest.mark.parametrize("path,fmt,ending,named", [
    ("x.json", "cityjsonseq", ".json", "cityjson"),
    ("x.city.jsonl", "cityjson", ".jsonl", "cityjsonseq"),
])
def test_an_output_named_like_the_other_format_is_written_with_a_warning(path, fmt, ending,
                                                                         named):
    """format=cityjsonseq output=x.json, or the default format with
    output=x.city.jsonl, were written without a word (issue 33, item 8)."""
    from reconstruction.lod2.report import FORMAT_NAMES

    got = config_messages(replace(CONFIG, output=replace(OUTPUT, path=path, format=fmt)))
    assert len(got) == 1 and got[0].level == "warning"
    assert got[0].text.startswith("output= '{}' ends in {} but format={} writes ".format(
        path, ending, fmt))
    assert got[0].text.endswith("written as asked (give format={} for {})".format(
        named, FORMAT_NAMES[named]))


@pytest.mark.parametrize("path,fmt", [("x.city.json", "cityjson"), ("x.JSONL", "cityjsonseq"),
                                      ("x.cj", "cityjsonseq"), ("x", "cityjson")])
def test_an_output_named_like_its_format_or_neither_gets_no_warning(path, fmt):
    assert config_messages(replace(CONFIG, output=replace(OUTPUT, path=path, format=fmt))) == []


def test_a_map_picture_far_from_the_footprints_warns_with_both_boxes():
    """map= far from the model was drawn apart without a word (issue 33, item 7)."""
    from reconstruction.geom.grid import Extent, MapImage
    from reconstruction.lod2.report import map_messages

    image = MapImage(np.zeros((2, 2, 3), dtype=np.uint8), (185000, 185400, 446000, 446300))
    assert map_messages(image, Extent(85000, 446000, 85300, 446200)) == [
        W("The map of map= (x 185000..185400, y 446000..446300) does not overlap the footprints "
          "(x 85000..85300, y 446000..446200): the picture draws them apart (a map of another "
          "area or reference system?)")]
    assert map_messages(image, Extent(185300, 446200, 185600, 446500)) == []
    assert map_messages(image, None) == []


def test_building_points_low_on_most_footprints_warn_they_may_be_ground_points():
    """Issue 33, item 8: more than half the footprints with points under 2 m."""
    config = replace(CONFIG, heights=HeightConfig(building_points="bpts"))
    low = HeightReport("points", with_points=5, points_low=3, points_measured=5,
                       points_median_top=0.84, sources={"points": 5})
    assert height_messages(low, config)[1:3] == [
        N("5 footprints have building points"),
        W("The building points of <bpts> stand less than 2 m above the ground on 3 of 5 "
          "footprints (median 0.84 m): are they ground points?")]
    half = replace(low, points_low=2, points_measured=4)
    assert [m.level for m in height_messages(half, config)] == ["message", "message", "verbose"]


def test_existing_and_height_input_messages():
    assert existing_messages(ExistingRequest("m.city.json")) == [
        N("Reading the existing model 'm.city.json'...")]
    assert ground_points_messages(CONFIG) == []
    assert ground_points_messages(replace(CONFIG, heights=HeightConfig(elevation="dtm"))) == [
        W("Both ground_points= and elevation= given: the ground comes from the points")]
    assert matched_heights_messages(4) == [
        N("The 4 footprints matched in the existing model take its measured heights")]
    assert plots_messages(measured=True) == []
    assert plots_messages(measured=False) == [
        W("plots= is used only with aligned= or building_points=")]


def test_height_messages():
    report = HeightReport("column", sources={"column": 5})
    assert height_messages(report, CONFIG) == [V("Height sources: 5 column")]
    config = replace(CONFIG, heights=HeightConfig(ground_points="gp", aligned="al",
                                                  building_points="bp", percentile_text="25"))
    report = HeightReport("points", ground_missing=2, ground_grown=3, matched=4,
                          aligned_measured=5, aligned_unmeasured=6, with_points=7,
                          sources={"measured": 4, "neighbours": 1})
    assert height_messages(report, config) == [
        N("Ground from <gp> (percentile 25): 3 footprints with the buffer grown over a hole"),
        W("2 footprints have no ground point or cell within 50 m"),
        N("4 of the footprints are aligned footprints with measured heights; 5 aligned "
          "footprints measured"),
        W("6 aligned footprints have no measured heights (NULL)"),
        N("7 footprints have building points"),
        V("Height sources: 4 measured, 1 neighbours")]
    elevation = replace(config, heights=HeightConfig(elevation="dtm"))
    assert height_messages(HeightReport("elevation", sources={}), elevation)[0] == N(
        "Ground from <dtm> (percentile 20): 0 footprints with the buffer grown over a hole")


def test_street_messages():
    assert street_messages(StreetConfig()) == []
    assert street_messages(StreetConfig(classes_ignored=True)) == [
        W("street_classes= is used only with streets=")]
    edges = SimpleNamespace(case=np.array([0, 1, 1, 2, 3, 3, 3, 4, 5]))
    assert street_edge_messages(edges) == [
        N("Street edges: 2 one unshared edge, 1 from a neighbour, 3 by vote, 1 shortest, 1 "
          "facing the streets map; 1 enclosed (no street edge)")]


def test_footprint_messages():
    assert footprint_messages(NONE, CONFIG) == []
    config = replace(CONFIG, heights=HeightConfig(ground_text="2.5"))
    report = Lod2Report(1, 2, 3, 4, 5, {"too small": 5}, 10)
    assert footprint_messages(report, config) == [
        W("1 footprints with NULL, zero or negative eaves height are left out"),
        W("2 footprints with NULL or negative roof height get a flat roof"),
        W("3 footprints with NULL ground elevation are set on ground=2.5"),
        W("4 holes (inner courtyards) in footprints are filled"),
        W("5 footprints or parts of footprints are left out (empty or degenerate: 5 too "
          "small)")]
    assert footprint_messages(Lod2Report(0, 0, 0, 0, 1, {}, 1), CONFIG) == [
        W("1 footprints or parts of footprints are left out (empty or degenerate: no "
          "geometry)")]


def test_build_messages():
    assert build_messages(0) == [] and build_messages(3) == [N("Building 3 solids...")]
    assert built_messages(NONE) == []
    report = replace(NONE, dropped=1, fell_back=2, by_rule=3, simplified=4)
    assert built_messages(report) == [
        W("1 footprints gave no valid solid, even flat, and are left out"),
        W("2 roofs fell back to a simpler type to stay valid"),
        V("3 roofs changed type by the roof rules (no free street end for a stepped facade or "
          "a gable)"),
        N("4 footprints of more than {} vertices got their pitched roof on a simplified "
          "outline".format(MAX_ROOF_VERTICES))]


def _run(written, invalid=None, fallbacks=()):
    model = Lod2Result(None, np.zeros(0), ["a", "b", "c"],
                       np.array(["gable", "gable", "hip"], dtype=object), np.arange(3), {},
                       replace(NONE, fallbacks=list(fallbacks), dropped=1, simplified=2))
    return Lod2Run(model, written, invalid)


def test_report_of_a_run():
    assert lod2_report(_run(OutputReport(generated=3)), CONFIG) == [
        N("3 buildings written to 'out.city.json': 1 hip, 2 gable")]
    written = OutputReport(generated=3, copied=2, candidates=4,
                           copy=CopyReport(lod_fallback=1, skipped_geometries=2),
                           match=MatchReport(4, 1, 1, 2, 3), rendered="m.png")
    assert lod2_report(_run(written), CONFIG) == [
        N("5 buildings written to 'out.city.json': 1 hip, 2 gable"),
        N("2 of 4 aligned footprints copied from the existing model (1 matched by id, 1 by "
          "geometry)"),
        W("3 building ids matched no object of the existing model (tried by geometry)"),
        W("2 aligned footprints matched no building of the existing model and are generated"),
        W("1 copied buildings have none of the LoDs of existing_lod= and are copied at their "
          "highest"),
        W("2 geometries of copied buildings (templates or unknown types) are left out"),
        N("Picture written to 'm.png'")]
    quiet = OutputReport(generated=1, copied=0, candidates=1, copy=CopyReport(),
                         match=MatchReport(1, 0, 0, 0, 0))
    assert [m.level for m in lod2_report(_run(quiet), CONFIG)] == ["message", "message"]


def test_footprints_with_the_id_of_an_earlier_one_are_reported_as_duplicates():
    """Issue 33, item 8: not as "matched no building"."""
    written = OutputReport(generated=2, copied=1, candidates=3, copy=CopyReport(),
                           match=MatchReport(3, 1, 0, 0, 0, duplicate_ids=2,
                                             duplicates_unmatched=2,
                                             duplicate_examples=("NL.1",)))
    assert lod2_report(_run(written), CONFIG)[2:] == [
        W("2 aligned footprints have the building id of an earlier footprint (e.g. NL.1): "
          "the building is copied once, for the first; 2 of them are generated")]


def test_the_validity_report():
    assert validity_lines(_run(OutputReport(generated=3))) == []
    run = _run(OutputReport(generated=3), invalid=[None, "104 (shell not closed)", None],
               fallbacks=[RoofFallback(7, "stepped", "self-intersection")])
    assert lod2_report(run, CONFIG)[1:] == [
        N("Footprint cat 7: stepped roof invalid (self-intersection), fell back"),
        N("Invalid solid: 104 (shell not closed)")]
    assert validity_lines(run) == [
        "solids=3", "valid=2", "percent_valid=66.67", "fallbacks=1", "dropped=1",
        "simplified=2", "copied_solids=0", "copied_valid=0"] + [
        "roof_{}={}".format(k, {"hip": 1, "gable": 2}.get(k, 0)) for k in ROOF_TYPES]
    empty = replace(run, model=replace(run.model, report=replace(run.model.report, rings=0)),
                    invalid=[])
    assert validity_lines(empty)[:3] == ["solids=0", "valid=0", "percent_valid=100.00"]


def test_copied_solids_are_counted_with_the_generated():
    """-v counts the copied Solids checked with the generated ones (issue 33, item 1)."""
    written = OutputReport(generated=3, copied=2, copy=CopyReport(), copied_unchecked=1,
                           copied_checked=(("<a-0> (lod 2.2)", None),
                                           ("<b-0> (lod 2.2)", "non-planar face (> 1 mm)")))
    run = _run(written, invalid=[None, None, None])
    lines = validity_lines(run)
    assert lines[:3] == ["solids=5", "valid=4", "percent_valid=80.00"]
    assert "copied_solids=2" in lines and "copied_valid=1" in lines
    said = lod2_report(run, CONFIG)
    assert N("Invalid copied solid <b-0> (lod 2.2): non-planar face (> 1 mm)") in said
    assert N("1 copied solids have inner shells or faces with holes and are not "
             "checked") in said


def test_id_matches_far_from_their_footprints_are_warned_about():
    written = OutputReport(generated=2, copied=0, candidates=2, copy=CopyReport(),
                           match=MatchReport(2, 0, 0, 2, 0, far_ids=2,
                                             far_example=("NL.1", 85123.4)))
    assert W("2 building ids name buildings of the existing model more than 100 m from their "
             "footprints (e.g. NL.1, 85123 m away): not copied, tried by geometry") in \
        lod2_report(_run(written), CONFIG)
