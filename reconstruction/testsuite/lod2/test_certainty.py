"""The certainty class of a building from where its footprint and heights came from
(reconstruction.lod2.certainty, issue 31)."""

from reconstruction.lod2.certainty import ALIGNED, CLASSES, DRAWN, GENERATED, MEASURED, certainty


def test_the_classes_go_from_measured_to_drawn():
    footprints = ["aligned", "aligned", "2pm", "2pm", "aligned", "2pm", None, "2pm"]
    heights = ["measured", "neighbours", "neighbours", "plot", "range", "points", "column", ""]
    assert certainty(footprints, heights).tolist() == [
        MEASURED, ALIGNED, GENERATED, GENERATED, DRAWN, ALIGNED, GENERATED, DRAWN]
    assert list(CLASSES) == sorted(CLASSES, reverse=True)


def test_without_a_footprint_source_every_footprint_counts_as_generated():
    assert certainty(None, ["measured", "neighbours"]).tolist() == [ALIGNED, GENERATED]
