"""The certainty class of a building from where its footprint and heights came from
(reconstruction.lod2.certainty, issue 31)."""

from reconstruction.lod2.certainty import ALIGNED, CLASSES, DRAWN, GENERATED, MEASURED, certainty


def test_the_classes_go_from_measured_to_drawn():
    footprints = ["aligned", "aligned", "2pm", "2pm", "aligned", "2pm", None, "2pm"]
    heights = ["measured", "neighbours", "neighbours", "plot", "range", "points", "column", ""]
    assert certainty(footprints, heights).tolist() == [
        MEASURED, ALIGNED, GENERATED, GENERATED, DRAWN, ALIGNED, GENERATED, DRAWN]
    assert list(CLASSES) == sorted(CLASSES, reverse=True)


def test_a_footprint_the_map_draws_is_surer_than_a_generated_one_not_than_a_measured_one():
    # issue 50: a parcel or building outlined on the map (source drawn)
    drawn = ["drawn"] * 4
    assert certainty(drawn, ["measured", "neighbours", "column", "range"]).tolist() == [
        ALIGNED, ALIGNED, ALIGNED, DRAWN]
    assert certainty(["2pm"], ["neighbours"]).tolist() == [GENERATED]


def test_without_a_footprint_source_every_footprint_counts_as_generated():
    assert certainty(None, ["measured", "neighbours"]).tolist() == [ALIGNED, GENERATED]


def test_each_footprint_says_why_it_has_its_roof():
    # issue 31's roof paradata: drawn by the rules, asked for by roof= or the roof
    # column ("auto" there is the rules' again), kept from the earlier epoch
    from types import SimpleNamespace

    import numpy as np

    from reconstruction.lod2.previous import with_earlier_roofs
    from reconstruction.lod2.stage import requests_from_columns

    columns = {"roof": ["gable", None, "auto", "", "hip"]}
    drawn = requests_from_columns(columns, 5, roof_column="roof", map_year=1900)
    assert drawn.source.tolist() == ["column", "rule", "rule", "rule", "column"]
    forced = requests_from_columns(columns, 5, roof="flat", roof_column="roof")
    assert forced.source.tolist() == ["column", "option", "rule", "option", "column"]
    earlier = SimpleNamespace(building=np.array([-1, -1, 3, -1, -1]),
                              roof_type=[None, "mansard", "hip", "flat", "flat"],
                              roof_source=[None, None, None, "rule", None])
    kept = with_earlier_roofs(drawn, earlier)
    assert kept.types.tolist()[:4] == ["gable", "mansard", "auto", "flat"]
    # the earlier building's own reason where it said one: the rule of its first map
    assert kept.source.tolist() == ["column", "earlier epoch", "rule", "rule", "column"]
