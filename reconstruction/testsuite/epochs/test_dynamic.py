"""One model of several epochs and its snapshots (reconstruction.epochs.dynamic)."""

import copy
import json
import os
import re
import shutil
import subprocess
import sys

import pytest

from reconstruction.cityjson import geometry as citygeometry
from reconstruction.cityjson import model as cityjson
from reconstruction.core.errors import InputError
from reconstruction.cityjson import versions
from reconstruction.epochs.dynamic import (Epoch, buildings, check_merged, epoch_years,
                                           merge_epochs, snapshot, version_index)

SCHEMAS = os.path.join(os.path.dirname(__file__), "..", "..", "..", "..", "shared", "schemas",
                       "cityjson-2.0.2")


def box_solid(x0, y0, height):
    """A 10 x 10 m box's vertices (absolute, m) and its Solid (indices from 0)."""
    v = [(x0, y0, 0), (x0 + 10, y0, 0), (x0 + 10, y0 + 10, 0), (x0, y0 + 10, 0)]
    v += [(x, y, height) for x, y, _ in v]
    shell = [[[0, 3, 2, 1]], [[4, 5, 6, 7]], [[0, 1, 5, 4]], [[1, 2, 6, 5]], [[2, 3, 7, 6]],
             [[3, 0, 4, 7]]]
    return v, {"type": "Solid", "lod": "2.0", "boundaries": [shell]}


def model(year, buildings, translate=(84000.0, 446000.0, 0.0)):
    """An epoch's model: {id: (x0, y0, height, plot)}; millimetres, its own translate."""
    vertices, objects = [], {}
    for oid, (x0, y0, h, plot) in buildings.items():
        v, solid = box_solid(x0, y0, h)
        start = len(vertices)
        vertices += v
        solid["boundaries"] = [[[[i + start for i in ring] for ring in face]
                                for face in solid["boundaries"][0]]]
        objects[oid] = {"type": "Building", "geometry": [solid],
                        "attributes": {"roof_type": "flat", "eaves_height": h, "plot": plot,
                                       "map_year": year}}
    scaled = [[round((c - t) / 0.001) for c, t in zip(p, translate)] for p in vertices]
    return {"type": "CityJSON", "version": "2.0",
            "transform": {"scale": [0.001] * 3, "translate": list(translate)},
            "metadata": {"referenceSystem": "https://www.opengis.net/def/crs/EPSG/0/7415"},
            "CityObjects": objects, "vertices": scaled}


def town():
    a = model(1880, {"kept": (84000, 446000, 8, 1), "gone": (84020, 446000, 9, 2),
                     "raised": (84040, 446000, 7, 3)})
    b = model(1915, {"kept": (84000, 446000, 8, 5), "raised": (84040, 446000, 11, 6),
                     "NL.IMBAG.Pand.0503100000000007": (84060, 446000, 12, 7)},
              translate=(83990.0, 445995.0, 0.0))
    return [Epoch(1915, b), Epoch(1880, a)]


def test_every_building_once_a_kept_one_with_one_version():
    # issue 52 item 1: each version is a +BuildingVersion city object of its own, a
    # child of its building, with its epochs, validity interval and the transitions
    m = merge_epochs(town(), register={"0503100000000007": 1902})
    objects = m.document["CityObjects"]
    buildings = {o for o, v in objects.items() if v["type"] == "Building"}
    assert buildings == {"kept", "gone", "raised", "NL.IMBAG.Pand.0503100000000007"}
    assert all("geometry" not in objects[b] and "children" not in objects[b] for b in buildings)
    of = version_index(objects)
    kept = of["kept"]
    assert len(kept) == 1 and kept[0]["type"] == "+BuildingVersion"
    assert kept[0]["versionOf"] == "kept" and kept[0]["epochs"] == [1880, 1915]
    assert (kept[0]["validFrom"], "validTo" in kept[0]) == (1880, False)
    assert kept[0]["epochAttributes"] == {"1915": {"plot": 5, "map_year": 1915}}
    raised = of["raised"]
    assert [(v["epochs"], v["validFrom"], v.get("validTo")) for v in raised] == [
        ([1880], 1880, 1914), ([1915], 1915, None)]
    assert [v["attributes"]["eaves_height"] for v in raised] == [7, 11]
    assert [(t["type"], t["from"], t["to"]) for t in objects["raised"]["attributes"][
        "+transitions"]] == [("changed", 1880, 1915)]
    assert objects["kept"]["attributes"]["+transitions"][0]["type"] == "kept"
    gone = objects["gone"]["attributes"]
    assert (gone["dateOfDemolitionEarliest"], gone["dateOfDemolitionLatest"]) == (1881, 1915)
    assert [t["type"] for t in gone["+transitions"]] == ["demolished"]
    new = objects["NL.IMBAG.Pand.0503100000000007"]
    assert new["attributes"]["standing"] and new["attributes"]["dateOfConstruction"] == 1902
    assert "conflict" not in new["attributes"]
    assert [t["type"] for t in new["attributes"]["+transitions"]] == ["new"]
    assert of["NL.IMBAG.Pand.0503100000000007"][0]["validFrom"] == 1902    # the register's
    assert m.report.versions == 5 and m.report.standing == 1
    assert m.report.per_epoch == {1880: 3, 1915: 3}
    assert m.document["+versioning"]["transitions"] == [
        {"from": "1880", "to": "1915", "type": "historicalSuccession", "kept": 1,
         "changed": 1, "new": 1, "demolished": 1}]
    assert cityjson.consistency_errors(m.document) == []
    assert epoch_years(m.document) == [1880, 1915]


def test_the_merged_model_is_schema_valid_with_the_shipped_extension(schemas):
    doc = merge_epochs(town()).document
    ext = versions.extension()
    assert doc["extensions"] == {"HistoVersions": {"url": ext["url"], "version": ext["version"]}}
    given = {"HistoVersions": ext}
    folder = os.path.join(schemas, "cityjson-2.0.2")
    assert cityjson.schema_errors(doc, folder, extensions=given) == []
    # the Extension's definitions are checked, not merely allowed
    broken = copy.deepcopy(doc)
    broken["CityObjects"]["raised"]["attributes"]["+transitions"][0]["type"] = "moved"
    del broken["CityObjects"]["raised~1880"]["epochs"]
    errors = cityjson.schema_errors(broken, folder, extensions=given)
    assert any(e.startswith("raised: +transitions: 'moved'") for e in errors), errors
    assert any(e.startswith("raised~1880: 'epochs' is a required") for e in errors), errors
    assert any("not given" in e for e in cityjson.schema_errors(doc, folder))


def test_no_version_overlaps_another_for_val3dity(tmp_path):
    # a building's versions were extra solids of one Building: val3dity's 601
    # (overlapping parts); as city objects of their own each is checked alone
    from val3dity import require_val3dity, val3dity_report

    require_val3dity()
    path = tmp_path / "merged.city.json"
    path.write_text(json.dumps(merge_epochs(town()).document))
    report = val3dity_report(str(path))
    assert report.codes.get(601, 0) == 0 and report.invalid == [], str(report)
    assert report.objects >= 5


def test_cjio_reads_the_versions_and_names_the_extension(tmp_path):
    # cjio (pinned in requirements.txt) beside the interpreter; its validate needs
    # cjvalpy, which has no wheel here: the schema test above validates instead
    cjio = shutil.which("cjio", path=os.path.dirname(sys.executable)) or shutil.which("cjio")
    if cjio is None:
        pytest.skip("cjio is not installed (make deps installs it in the venv)")
    path = tmp_path / "merged.city.json"
    path.write_text(json.dumps(merge_epochs(town()).document))
    proc = subprocess.run([cjio, str(path), "info"], capture_output=True, text=True,
                          timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert "Extensions = ['HistoVersions']" in proc.stdout
    assert "Building (4)" in proc.stdout and "+BuildingVersion (5)" in proc.stdout


def test_paradata_of_heights_and_roof_type():
    epochs = town()
    attributes = epochs[1].document["CityObjects"]["kept"]["attributes"]      # 1880
    attributes.update(height_source="neighbours", roof_source="earlier epoch",
                      eaves_height_low=6.5, eaves_height_high=9.0, ridge_height_low=8.0,
                      ridge_height_high=10.0)
    objects = merge_epochs(epochs).document["CityObjects"]
    told = objects["kept~1880"]["paradata"]
    assert told["eaves_height"] == {"source": "neighbours", "method": "inferred",
                                    "uncertainty": [6.5, 9.0]}
    assert told["roof_height"]["uncertainty"] == [0.0, 2.0]
    assert told["roof_type"] == {"source": "earlier epoch", "method": "copied"}
    assert "paradata" not in objects["raised~1880"]          # nothing said, nothing made up


def test_a_model_of_the_form_before_the_extension_is_told_how_to_convert():
    early = {"type": "CityJSON", "version": "2.0", "CityObjects": {"a": {
        "type": "Building", "attributes": {"epochs": [1880], "geometry_epochs": []}}},
        "vertices": []}
    for call in (lambda: check_merged(early, "old.city.json"), lambda: snapshot(early, 1880)):
        with pytest.raises(InputError, match="earlier v.histo.timeline .* make it again from the "
                                             "epochs' models"):
            call()


@pytest.mark.parametrize("k", [0, 1])
def test_a_snapshot_of_an_epoch_is_that_epochs_model(k):
    epochs = sorted(town(), key=lambda e: e.year)
    m = merge_epochs(epochs, register={"0503100000000007": 1902})
    snap = snapshot(m.document, epochs[k].year)
    assert citygeometry.resolved(snap) == citygeometry.resolved(epochs[k].document)
    assert cityjson.consistency_errors(snap) == []


def test_a_year_between_epochs_shows_the_earlier_and_what_the_register_dates_by_then():
    m = merge_epochs(town(), register={"0503100000000007": 1902})
    assert set(snapshot(m.document, 1901)["CityObjects"]) == {"kept", "gone", "raised"}
    later = snapshot(m.document, 1902)["CityObjects"]
    assert set(later) == {"kept", "gone", "raised", "NL.IMBAG.Pand.0503100000000007"}
    assert later["raised"]["attributes"]["eaves_height"] == 7       # still the 1880 one
    with pytest.raises(InputError, match="before the model's first epoch"):
        snapshot(m.document, 1870)


def test_a_register_year_before_a_map_without_the_building_is_a_conflict():
    m = merge_epochs(town(), register={"0503100000000007": 1850})
    assert m.report.conflicts == {
        "NL.IMBAG.Pand.0503100000000007": "built 1850 (register) but not on the 1880 map"}


def test_two_epochs_of_one_year_are_refused():
    a, b = town()
    with pytest.raises(InputError, match="same year"):
        merge_epochs([a, Epoch(a.year, b.document)])


def with_crs(doc, code):
    doc["metadata"]["referenceSystem"] = "https://www.opengis.net/def/crs/EPSG/0/{}".format(code)
    return doc


@pytest.mark.parametrize("codes, message", [
    ((31370, 28992), "different reference systems"),
    ((4326, 4326), "EPSG:4326, whose units are not metres on the ground (degrees"),
    ((3857, 3857), "EPSG:3857, whose units are not metres on the ground (Web Mercator"),
])
def test_models_in_other_or_unmetric_reference_systems_are_refused(codes, message):
    b, a = town()
    epochs = [Epoch(1880, with_crs(a.document, codes[0])), Epoch(1915, with_crs(b.document,
                                                                                codes[1]))]
    with pytest.raises(InputError, match=re.escape(message)):
        merge_epochs(epochs)


def test_a_compound_system_and_its_horizontal_part_merge_in_the_models_system():
    b, a = town()
    m = merge_epochs([Epoch(1880, with_crs(a.document, 7415)),
                      Epoch(1915, with_crs(b.document, 28992))])
    assert m.document["metadata"]["referenceSystem"].endswith("/7415")


def test_years_are_checked_against_the_models_map_year():
    b, a = town()
    with pytest.raises(InputError, match="is of the map of 1915 .* not of 1880"):
        merge_epochs([Epoch(1880, b.document, "b.json"), Epoch(1915, a.document, "a.json")])
    with pytest.raises(InputError, match="is of the map of 1880 .* not of 1915"):
        merge_epochs([Epoch(1880, a.document), Epoch(1915, a.document)])


def test_one_model_under_two_years_is_refused_without_map_years_too():
    _, a = town()
    for obj in a.document["CityObjects"].values():
        del obj["attributes"]["map_year"]
    with pytest.raises(InputError, match="one and the same"):
        merge_epochs([Epoch(1880, a.document), Epoch(1915, copy.deepcopy(a.document))])


def test_a_merged_model_or_an_empty_one_is_no_epoch():
    b, a = town()
    merged = merge_epochs([a, b]).document
    with pytest.raises(InputError, match="model over several epochs"):
        merge_epochs([a, Epoch(1961, merged)])
    empty = model(1900, {})
    with pytest.raises(InputError, match="model of 1900 '<model>' has no buildings"):
        merge_epochs([a, Epoch(1900, empty), b])


def test_an_id_of_unrelated_buildings_on_two_maps_names_two_buildings():
    """Two runs that each named their buildings building_1, building_2...: the same id
    far apart is two buildings, each with its own lifespan; one drawn a metre off is one."""
    a = model(1880, {"building_1": (84000, 446000, 8, 1), "building_2": (84020, 446000, 9, 2)})
    b = model(1915, {"building_1": (84200, 446000, 8, 1), "building_2": (84021, 446001, 9, 2)})
    m = merge_epochs([Epoch(1880, a), Epoch(1915, b)])
    objects = m.document["CityObjects"]
    assert set(buildings(objects)) == {"building_1", "building_1@1915", "building_2"}
    assert m.report.apart == {"building_1": ["building_1@1915"]}
    old, new = objects["building_1"]["attributes"], objects["building_1@1915"]["attributes"]
    assert old["epochs"] == [1880] and old["dateOfDemolitionLatest"] == 1915
    assert new["epochs"] == [1915] and new["dateOfConstructionEarliest"] == 1881
    assert objects["building_2"]["attributes"]["epochs"] == [1880, 1915]
    assert cityjson.consistency_errors(m.document) == []
    for year, shown in ((1880, {"building_1", "building_2"}),
                        (1915, {"building_1@1915", "building_2"})):
        assert set(snapshot(m.document, year)["CityObjects"]) == shown


def test_a_model_over_time_is_refused_as_an_existing_model(tmp_path):
    """v.histo.lod2 existing= reads buildings to copy; a merged model's
    versions are no buildings: one error saying how to take an epoch."""
    import json

    import pytest

    from reconstruction.core.errors import InputError
    from reconstruction.lod2 import output as lod2_output

    path = tmp_path / "merged.city.json"
    path.write_text(json.dumps(merge_epochs(town()).document))
    with pytest.raises(InputError, match="snapshot="):
        lod2_output.read_existing(lod2_output.ExistingRequest(str(path)))
