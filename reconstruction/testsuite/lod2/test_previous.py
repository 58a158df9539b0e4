"""The earlier epoch's buildings kept or built anew (reconstruction.lod2.previous):
nothing changes where the maps and the measured heights did not."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from shapely.geometry import box

from reconstruction.cityjson import existing
from reconstruction.core.contract import HEIGHTS_MEASURED
from reconstruction.lod2.previous import HEIGHT_TOLERANCE, match_previous
from reconstruction.testsuite.timeline.test_timeline_fuzz import FUZZ, epoch_model, mutated

CUBE = [[[[0, 3, 2, 1]], [[4, 5, 6, 7]], [[0, 1, 5, 4]], [[1, 2, 6, 5]], [[2, 3, 7, 6]],
         [[3, 0, 4, 7]]]]
SEMANTICS = {"surfaces": [{"type": "GroundSurface"}, {"type": "RoofSurface"},
                          {"type": "WallSurface"}], "values": [[0, 1, 2, 2, 2, 2]]}


def earlier_model(roof_type, eaves, roof_height):
    """One earlier building, ``b1``, on the square (0, 0)-(4, 4), with its heights."""
    vertices = [[dx, dy, dz] for dz in (0, int(eaves * 1000)) for dx, dy in
                ((0, 0), (4000, 0), (4000, 4000), (0, 4000))]
    doc = {"type": "CityJSON", "version": "2.0",
           "transform": {"scale": [0.001] * 3, "translate": [0, 0, 0]},
           "CityObjects": {"b1": {"type": "Building", "attributes": {
               "roof_type": roof_type, "eaves_height": eaves, "roof_height": roof_height},
               "geometry": [{"type": "Solid", "lod": "2.2", "boundaries": CUBE,
                             "semantics": SEMANTICS}]}},
           "vertices": vertices}
    return existing.model_of(doc)


def kept(model, eaves, attic, outline=box(0, 0, 4, 4), source=HEIGHTS_MEASURED):
    match = match_previous(model, ["b1"], [outline], np.array([eaves]), np.array([attic]),
                           [source])
    return match.building[0] >= 0, match.report, match.roof_type


def test_the_same_outline_and_heights_keep_the_building():
    model = earlier_model("gable", 9.0, 3.0)
    is_kept, report, roof = kept(model, 9.0, 3.0 + HEIGHT_TOLERANCE / 2)
    assert is_kept and report.kept == 1 and roof == ["gable"]


def test_other_measured_heights_or_another_outline_build_it_anew_with_its_roof():
    model = earlier_model("gable", 9.0, 3.0)
    is_kept, report, roof = kept(model, 9.0, 3.5)
    assert not is_kept and report.measured == 1 and roof == ["gable"]
    is_kept, report, _ = kept(model, 9.5, 3.0)
    assert not is_kept and report.measured == 1
    is_kept, report, _ = kept(model, 9.0, 3.0, outline=box(0, 0, 4, 5))
    assert not is_kept and report.reshaped == 1


def test_a_flat_roof_has_no_roof_height_to_compare():
    """An earlier flat roof stores roof height 0 whatever attic the heights measured:
    the same measured heights keep it, other eaves do not."""
    model = earlier_model("flat", 11.2, 0.0)
    is_kept, report, _ = kept(model, 11.2, 5.49)
    assert is_kept and report.kept == 1
    is_kept, report, _ = kept(model, 12.0, 5.49)
    assert not is_kept and report.measured == 1


def test_heights_not_measured_in_this_epoch_keep_the_building():
    model = earlier_model("hip", 9.0, 3.0)
    assert kept(model, 7.0, 1.0, source="neighbours")[0]


@pytest.mark.parametrize("identity", [None, "b2"])
def test_a_footprint_without_an_earlier_building_is_built(identity):
    model = earlier_model("hip", 9.0, 3.0)
    match = match_previous(model, [identity], [box(0, 0, 4, 4)], np.array([9.0]),
                           np.array([3.0]), [HEIGHTS_MEASURED])
    assert match.building[0] == -1 and match.report.new == (identity is not None)


def written(tmp_path, doc, name="earlier.city.json"):
    import json

    path = str(tmp_path / name)
    with open(path, "w") as f:
        json.dump(doc, f)
    return path


def epoch_doc(map_year):
    from reconstruction.testsuite.epochs.test_dynamic import model

    return model(map_year, {"b1": (84000, 446000, 8, 1), "b2": (84020, 446000, 9, 2)})


@pytest.mark.parametrize("earlier, message", [(1961, "is of the map of 1961"),
                                              (1915, "is of the map of 1915")])
def test_previous_of_a_later_or_the_same_map_is_refused(tmp_path, earlier, message):
    """Issue 49, item 7: 235 buildings were "kept" from 1961 into 1915."""
    from reconstruction.core.errors import InputError
    from reconstruction.lod2.previous import read_previous

    path = written(tmp_path, epoch_doc(earlier))
    with pytest.raises(InputError, match=message + r", not of a map before this one's \(1915"):
        read_previous(path, 1915)
    assert read_previous(written(tmp_path, epoch_doc(1880), "ok.city.json"), 1915).buildings \
        == ["b1", "b2"]


def test_previous_a_merged_model_over_time_is_refused(tmp_path):
    from reconstruction.core.errors import InputError
    from reconstruction.epochs.dynamic import Epoch, merge_epochs
    from reconstruction.lod2.previous import read_previous

    merged = merge_epochs([Epoch(1880, epoch_doc(1880)), Epoch(1900, epoch_doc(1900))])
    with pytest.raises(InputError, match="model over several epochs.*snapshot="):
        read_previous(written(tmp_path, merged.document), 1915)


def test_a_broken_building_of_previous_gives_the_warning_existing_gives(tmp_path):
    from reconstruction.lod2.previous import read_previous
    from reconstruction.lod2.report import existing_model_messages

    doc = epoch_doc(1880)
    doc["CityObjects"]["b2"]["geometry"][0]["boundaries"][0][0][0][0] = -1
    model = read_previous(written(tmp_path, doc), 1915)
    assert model.buildings == ["b1"]
    said = existing_model_messages(model, "earlier epoch's model", "not kept")
    assert len(said) == 1 and said[0].level == "warning"
    assert "1 buildings of the earlier epoch's model" in said[0].text
    assert "<b2>" in said[0].text and "vertex index -1 is negative" in said[0].text


def test_previous_with_attributes_of_the_wrong_kind_leaves_that_building_out(tmp_path):
    from reconstruction.lod2.previous import read_previous

    doc = epoch_doc(1880)
    doc["CityObjects"]["b2"]["attributes"] = ["map_year", 1961]
    model = read_previous(written(tmp_path, doc), 1915)
    assert model.buildings == ["b1"] and "attributes that are not an object" in \
        model.skipped["b2"]


@FUZZ
@given(data=st.data())
def test_a_malformed_previous_model_gives_a_match_or_one_input_error(data):
    """Issue 49, item 10, for previous=: mutations of a small earlier model (the
    timeline's fuzz test's) are read and matched, or refused with one InputError."""
    import json
    import tempfile

    from reconstruction.core.errors import InputError
    from reconstruction.lod2.previous import read_previous

    with tempfile.TemporaryDirectory() as folder:
        path = folder + "/earlier.city.json"
        with open(path, "w") as f:
            json.dump(mutated(data, epoch_model()), f)
        try:
            model = read_previous(path, 1961)
        except InputError as error:
            assert str(error)
            return
        outlines = [box(84000, 446000, 84010, 446010), box(84020, 446000, 84030, 446010)]
        match = match_previous(model, ["a", "b"], outlines, np.array([8.0, 9.0]),
                               np.array([0.0, 0.0]), [HEIGHTS_MEASURED] * 2, 1961)
        assert match.report.footprints == 2
