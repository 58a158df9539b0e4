"""lod2/config.py: v.histo.lod2's options as one Lod2Config, without GRASS (issue 27)."""

import dataclasses

import pytest

from reconstruction.core.errors import InputError
from reconstruction.lod2 import config as lod2_config
from reconstruction.lod2.config import read_config
from reconstruction.lod2.render import View

#: the module's options as g.parser gives them with only input= and output= given
DEFAULTS = {
    "input": "fp", "layer": "1", "output": "out.city.json", "ground_column": "", "ground": "0",
    "eaves_column": "h_building", "attic_column": "h_attic", "height": "", "attic": "",
    "ground_points": "", "elevation": "", "ground_percentile": "20", "aligned": "",
    "height_columns": "auto", "plots": "", "building_points": "", "height_rule": "robust",
    "roof": "auto", "roof_column": "", "year": "", "year_column": "", "pitch_min": "60",
    "inset": "1,2", "step": "0.4,0.7", "thickness": "0.5", "streets": "", "street_classes": "",
    "street_areas": "", "rules": "", "seed": "1", "crs": "", "existing": "", "id_column": "",
    "id_prefix": "", "overlap": "0.5", "existing_lod": "", "format": "cityjson", "render": "",
    "view": "210,35", "map": "", "plot_column": "plot", "source_column": "source",
    "nprocs": "0",
}
FLAGS = {"s": False, "v": False}


def config(flags=None, epsg=28992, labels=None, **change):
    return read_config(dict(DEFAULTS, **change), dict(FLAGS, **(flags or {})), epsg, labels)


def test_defaults():
    c = config()
    assert c.roof.pitch_min == 60.0 and c.roof.inset == (1.0, 2.0) and c.roof.step == (0.4, 0.7)
    assert c.roof.thickness == 0.5 and c.seed == 1 and c.nprocs >= 1 and c.map_year is None
    assert c.rules is None and c.roof_type == "auto" and not c.validate and not c.map_ignored
    assert c.output.path == "out.city.json" and c.output.format == "cityjson"
    assert c.output.reference_system == "https://www.opengis.net/def/crs/EPSG/0/28992"
    assert c.output.title == "LoD2 model from <fp>" and c.output.render is None
    assert c.output.view == View(210.0, 35.0) and c.output.maps == () and c.existing is None
    h = c.heights
    assert (h.eaves_column, h.attic_column, h.ground, h.ground_percentile) == (
        "h_building", "h_attic", 0.0, 20.0)
    assert h.eaves_range is None and h.ground_points is None and h.aligned is None
    assert h.rule.method == "robust" and (h.ground_text, h.percentile_text) == ("0", "20")
    assert c.streets == lod2_config.StreetConfig() and c.location_epsg == 28992


def test_the_config_is_frozen():
    with pytest.raises(dataclasses.FrozenInstanceError):
        config().seed = 2
    with pytest.raises(dataclasses.FrozenInstanceError):
        config().output.path = "x"


def test_good_values():
    c = config(flags={"s": True, "v": True}, height="6,9", attic="3", year="1961", seed="7",
               nprocs="2", crs="EPSG:7415", render="m.png", map="r,g,b", view="-90,90",
               existing="m.city.json", id_column="pand_id", id_prefix="NL.IMBAG.Pand.",
               overlap="0.8", existing_lod="1.2, 2.2", format="cityjsonseq",
               ground_points="gp", elevation="dtm", height_rule="plot", ground="1.5")
    assert c.heights.eaves_range == (6.0, 9.0) and c.heights.attic_range == (3.0, 3.0)
    assert c.map_year == 1961 and c.seed == 7 and c.nprocs == 2 and c.validate
    assert c.streets is None
    assert c.output.reference_system.endswith("/7415") and c.output.format == "cityjsonseq"
    assert c.output.render == "m.png" and c.output.maps == ("r", "g", "b")
    assert c.output.view == View(270.0, 90.0)
    assert c.existing == lod2_config.ExistingRequest("m.city.json", "NL.IMBAG.Pand.", 0.8,
                                                     ["1.2", "2.2"])
    assert c.id_column == "pand_id" and c.heights.ground_points == "gp"
    assert c.heights.elevation == "dtm" and c.heights.rule.method == "plot"
    assert c.heights.ground == 1.5 and c.heights.ground_text == "1.5"


def test_existing_lods():
    assert config(existing="m", existing_lod="ALL").existing.lods == "all"
    assert config(existing="m").existing.lods is None


def test_no_epsg_no_crs():
    assert config(epsg=None).output.reference_system is None


def test_map_without_render_is_ignored():
    c = config(map="r,g,b")
    assert c.map_ignored and c.output.maps == ()


def test_street_classes_numbers_or_labels():
    assert config(streets="cl", street_classes="3, 4").streets.classes == (3, 4)
    c = config(streets="cl", street_classes="water,street", labels={"Water": 3, "street": 4})
    assert c.streets == lod2_config.StreetConfig("cl", (3, 4))
    assert config(street_areas="sa").streets == lod2_config.StreetConfig(areas="sa")
    assert config(street_classes="3").streets.classes_ignored
    # -s: no street edges, the classes are not read
    assert config(flags={"s": True}, streets="cl", street_classes="canal").streets is None


@pytest.mark.parametrize("change,message", [
    ({"pitch_min": "steep"}, "pitch_min="), ({"inset": "2,1"}, "inset="),
    ({"step": "0"}, "step="), ({"thickness": "0"}, "thickness="), ({"height": "a"}, "height="),
    ({"attic": "-1,2"}, "attic="), ({"seed": "x"}, "seed="), ({"crs": "RD New"}, "crs="),
    ({"format": "obj"}, "format="), ({"existing_lod": "2.2"}, "needs existing="),
    ({"id_column": "pand_id"}, "needs existing="), ({"id_prefix": "NL."}, "needs existing="),
    ({"existing": "m", "overlap": "0"}, "overlap="), ({"existing": "m", "overlap": "2"}, "at most 1"),
    ({"existing": "m", "existing_lod": "high"}, "existing_lod="), ({"view": "1,2,3"}, "view="),
    ({"view": "45,95"}, "view="), ({"view": "a,b"}, "view="),
    ({"streets": "cl", "street_classes": "canal"}, "Street class <canal>"),
    ({"streets": "cl"}, "street_classes="), ({"ground": "x"}, "ground="),
    ({"rules": "/nonexistent/rules.csv"}, "rules"),
    # implausible heights (issue 49, item 8)
    ({"height": "5,1e9"}, "height=: the maximum 1e.09 m is not a plausible height"),
    ({"attic": "2,400"}, "attic=: the maximum 400 m is not a plausible height"),
    ({"ground": "-1000"}, "ground= must be at least -450"),
])
def test_bad_values_name_the_option(change, message):
    with pytest.raises(InputError, match=message):
        config(**change)


def test_a_rules_file(tmp_path):
    path = tmp_path / "rules.csv"
    path.write_text("from,to,shape,flat,hip,gable,mansard,stepped\n,,n,100,0,0,0,0\n")
    assert config(rules=str(path)).rules is not None


def test_parse_helpers():
    assert lod2_config.parse_lods("") is None and lod2_config.parse_lods("1.2, 2.2") == ["1.2",
                                                                                        "2.2"]
    assert lod2_config.parse_format("") == "cityjson"
    assert lod2_config.parse_format("CityJSONSeq") == "cityjsonseq"
    assert lod2_config.parse_view("") == View()
    assert lod2_config.parse_view("45,30") == View(45.0, 30.0)
    assert lod2_config.parse_classes("water,street", {"Water": 3, "street": 4}) == (3, 4)
    with pytest.raises(InputError, match="canal"):
        lod2_config.parse_classes("canal", {"water": 3})


@pytest.mark.parametrize("crs,epsg,message", [
    ("4326", 28992, "crs=EPSG:4326 is a geographic reference system"),
    ("EPSG:4979", None, "crs=EPSG:4979 is a geographic reference system"),
    ("https://www.opengis.net/def/crs/EPSG/0/4258", 28992, "geographic"),
    ("9705", 28992, "geographic"),              # WGS 84 + MSL height: compound, in degrees
])
def test_a_crs_that_cannot_label_the_locations_coordinates_is_refused(crs, epsg, message):
    """Issue 33, item 5: the coordinates are written as they are; a label in
    degrees, or of another place than the location's, would be wrong."""
    with pytest.raises(InputError, match=message):
        config(epsg=epsg, crs=crs)


@pytest.mark.parametrize("crs,epsg,warned", [
    ("7415", 28992, False), ("28992", 28992, False), ("EPSG:7415", None, False),
    ("3812", None, False), ("31370", 28992, True), ("3857", 28992, True)])
def test_a_projected_crs_is_taken_and_another_than_the_locations_warned_about(crs, epsg,
                                                                               warned):
    from reconstruction.lod2.report import config_messages

    c = config(epsg=epsg, crs=crs)
    assert c.output.reference_system.endswith("/" + crs.split(":")[-1])
    said = [m.text for m in config_messages(c)]
    assert any("is not the location's" in t for t in said) == warned


@pytest.mark.parametrize("change, message", [
    ({"year": "0"}, "year= must be at least 1"),
    ({"year": "-1880"}, "year= must be at least 1"),
    ({"previous": "m1880.city.json"}, "previous= needs year="),
])
def test_a_map_year_before_1_or_previous_without_one_is_refused(change, message):
    """Issue 49, item 7: year=0 is no map's year; previous= must be of an earlier map,
    which needs this map's year."""
    with pytest.raises(InputError, match=message):
        config(**change)
    assert config(year="1915", previous="m1880.city.json").map_year == 1915
