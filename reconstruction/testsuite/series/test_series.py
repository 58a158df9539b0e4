"""The map series' library (issue 30): manifest, chain, sheet edges, progress, merge. No GRASS."""

import io
import json
import os

import pytest

from reconstruction.core.errors import InputError
from reconstruction.series import chain, edges, manifest, merge, progress

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(
    __file__)))))
TEMPLATE = os.path.join(ROOT, "demo", "series", "sheet_chain.json")


def sheet(label, column, row, side=200.0, **more):
    entry = {"name": label, "map": label + ".bsq", "training": label + ".t.geojson",
             "footprints": label + ".f.geojson", "year": 1900,
             "extent": [column * side, row * side, (column + 1) * side, (row + 1) * side]}
    entry.update(more)
    return entry


def write_manifest(tmp_path, doc, name="series.json"):
    path = tmp_path / name
    path.write_text(json.dumps(doc) if isinstance(doc, dict) else doc)
    return str(path)


def three(tmp_path, **more):
    doc = {"margin": 30, "sheets": [sheet("a", 0, 0), sheet("b", 1, 0), sheet("c", 0, 1)]}
    doc.update(more)
    return manifest.read_manifest(write_manifest(tmp_path, doc))


def test_a_json_manifest_gives_sheets_with_absolute_files(tmp_path):
    series = three(tmp_path)
    assert [s.name for s in series.sheets] == ["a", "b", "c"]
    assert series.sheets[0].map == str(tmp_path / "a.bsq")
    assert series.sheets[1].extent == (200.0, 0.0, 400.0, 200.0)


def test_a_csv_manifest_reads_as_the_json_one(tmp_path):
    text = ("name,map,training,footprints,west,south,east,north,year,options\n"
            "a,a.bsq,a.t.geojson,a.f.geojson,0,0,200,200,1900,min_area=40;remove=2\n")
    series = manifest.read_manifest(write_manifest(tmp_path, text, "series.csv"))
    assert series.sheets[0].options == (("min_area", "40"), ("remove", "2"))
    assert series.sheets[0].year == 1900


@pytest.mark.parametrize("change, message", [
    ({"name": "1a"}, "name must start with a letter"),
    ({"extent": [0, 0, 0, 200]}, "is empty"),
    ({"extent": [0, 0, 200]}, "extent must be"),
    ({"year": "soon"}, "year must be a number"),
    ({"map": ""}, "no map file"),
    ({"options": "min_area"}, "key=value"),
])
def test_a_bad_sheet_is_named_in_the_error(tmp_path, change, message):
    doc = {"sheets": [sheet("a", 0, 0, **change)]}
    with pytest.raises(InputError, match=message):
        manifest.read_manifest(write_manifest(tmp_path, doc))


def test_overlapping_or_repeated_sheets_are_refused(tmp_path):
    with pytest.raises(InputError, match="overlap"):
        manifest.read_manifest(write_manifest(tmp_path, {"sheets": [
            sheet("a", 0, 0), sheet("b", 0.5, 0)]}))
    with pytest.raises(InputError, match="listed twice"):
        manifest.read_manifest(write_manifest(tmp_path, {"sheets": [
            sheet("a", 0, 0), sheet("a", 1, 0)]}))
    with pytest.raises(InputError, match="Cannot read"):
        manifest.read_manifest(str(tmp_path / "none.json"))


def test_neighbours_are_the_sheets_within_the_margin(tmp_path):
    series = three(tmp_path)
    a, b, c = series.sheets
    assert series.neighbours(a) == (b, c)
    assert series.neighbours(b) == (a, c)       # c touches b's margin at the corner


def test_the_chain_region_grows_only_where_a_neighbour_has_a_map(tmp_path):
    series = three(tmp_path)
    a, b, c = series.sheets
    assert edges.chain_region(series, a) == (0.0, 0.0, 230.0, 230.0)
    assert edges.chain_region(series, b) == (170.0, 0.0, 400.0, 230.0)


def test_the_owner_holds_the_larger_part_and_the_earlier_sheet_wins_a_tie():
    assert edges.owner_sheet([(1, 30.0), (2, 70.0)]) == 2
    assert edges.owner_sheet([(2, 50.0), (1, 50.0)]) == 1
    assert edges.owner_sheet([(3, 0.0)]) is None


def test_the_owner_query_names_the_sheet():
    where = edges.owner_query(3)
    assert "p.b_sheet = 3" in where and "q.b_sheet < p.b_sheet" in where


def test_the_chain_is_filled_in_for_each_sheet_with_its_neighbours(tmp_path):
    series = three(tmp_path, options={"min_area": "40"})
    template = chain.read_template(TEMPLATE)
    pc = chain.process_chain(template, series, series.sheets[0])
    text = json.dumps(pc.document)
    assert "{{" not in text
    steps = pc.steps()
    modules = [s.module for s in steps]
    assert modules.count("r.in.gdal") == 3   # the sheet and its two neighbours
    assert modules[-1] == "v.histo.lod2"
    generalize = dict(next(s for s in steps if s.module == "v.histo.generalize").params)
    assert generalize["min_area"] == "40"
    lod2 = steps[-1].command({"model": "/out/model"})
    assert "output=/out/model" in lod2
    assert [e.file_name for e in pc.exports()] == ["plots.geojson", "footprints.geojson", "model"]


def test_an_unknown_option_is_refused(tmp_path):
    series = three(tmp_path, options={"colour": "red"})
    template = chain.read_template(TEMPLATE)
    with pytest.raises(InputError, match="unknown option <colour>"):
        chain.process_chain(template, series, series.sheets[0])
    with pytest.raises(InputError, match="unknown option <colour>"):
        chain.shell_settings(template["defaults"], series, series.sheets[0], "g")


def test_chain_sh_gets_a_sheets_files_region_owner_and_the_options_set(tmp_path):
    """What demo/chain.sh runs a sheet with: the manifest's values, the
    options the manifest sets (the sheet's over the series'), not the
    template's defaults (chain.sh has its own, compared by the bytes of the
    models in testsuite/test_series_actinia.py)."""
    doc = {"margin": 30, "options": {"min_area": "40", "remove": "2"}, "seed": 3,
           "sheets": [sheet("a", 0, 0), sheet("b", 1, 0, options={"remove": "6"}),
                      sheet("c", 0, 1)]}
    series = manifest.read_manifest(write_manifest(tmp_path, doc))
    known = chain.read_template(TEMPLATE)["defaults"]
    settings = dict(chain.shell_settings(known, series, series.sheets[1], "/g.geojson"))
    assert settings["SHEET_MAP"] == str(tmp_path / "b.bsq")
    assert settings["SHEET_NEIGHBOURS"] == (str(tmp_path / "a.bsq"), str(tmp_path / "c.bsq"))
    assert settings["SHEET_REGION"] == ("170", "0", "400", "230")
    assert settings["SHEET_OWNER"] == edges.owner_query(2)
    assert settings["SHEET_GRID"] == "/g.geojson"
    assert (settings["YEAR"], settings["SEED"]) == ("1900", "3")
    assert (settings["MIN_AREA"], settings["REMOVE"]) == ("40", "6")
    assert "ALPHA" not in settings and "BUILDING" not in settings


def test_chain_sh_has_a_parameter_for_every_option_of_the_template():
    """Every option a manifest may set (the template's defaults) reaches
    demo/chain.sh as its upper-case variable: set in its parameters, or read
    by the stage functions of demo/steps.sh."""
    import re

    texts = ""
    for name in ("chain.sh", "steps.sh"):
        with open(os.path.join(ROOT, "demo", name), encoding="utf-8") as f:
            texts += f.read()
    for key in chain.read_template(TEMPLATE)["defaults"]:
        var = key.upper()
        assert re.search(r"^{0}=|\$\{{{0}:-".format(var), texts, re.M), var


def test_progress_survives_a_cut_last_line(tmp_path):
    path = str(tmp_path / "progress.jsonl")
    p = progress.Progress(path)
    p.record(progress.Attempt("a", "done", 1, 2.0, "f1"))
    p.record(progress.Attempt("b", "failed", 1, 1.0, "f2", "ERROR: no"))
    with open(path, "a") as f:
        f.write('{"sheet": "c", "sta')
    again = progress.Progress(path)
    assert again.done("a", "f1") and not again.done("a", "other chain")
    assert not again.done("b", "f2") and not again.done("c", "f3")


def test_a_changed_chain_has_another_fingerprint():
    assert progress.fingerprint({"a": 1}) != progress.fingerprint({"a": 2})


def box_model(path, boxes):
    """A CityJSON file with one box building per (id, x0, y0, x1, y1)."""
    vertices, objects = [], {}
    for oid, x0, y0, x1, y1 in boxes:
        n = len(vertices)
        for z in (0, 3000):
            vertices += [[x0, y0, z], [x1, y0, z], [x1, y1, z], [x0, y1, z]]
        shell = [[[n + 3, n + 2, n + 1, n]], [[n + 4, n + 5, n + 6, n + 7]]] + [
            [[n + i, n + (i + 1) % 4, n + 4 + (i + 1) % 4, n + 4 + i]] for i in range(4)]
        objects[oid] = {"type": "Building", "geometry": [{
            "type": "Solid", "lod": "2.2", "boundaries": [shell],
            "semantics": {"surfaces": [{"type": "GroundSurface"}, {"type": "RoofSurface"},
                                       {"type": "WallSurface"}],
                          "values": [[0, 1, 2, 2, 2, 2]]}}]}
    doc = {"type": "CityJSON", "version": "2.0",
           "transform": {"scale": [0.001] * 3, "translate": [0, 0, 0]},
           "metadata": {"referenceSystem": "https://www.opengis.net/def/crs/EPSG/0/28992"},
           "CityObjects": objects, "vertices": vertices}
    with open(path, "w") as f:
        json.dump(doc, f)
    return path


def test_the_merge_keeps_every_building_once_and_the_owner_of_an_overlap(tmp_path):
    series = manifest.read_manifest(write_manifest(tmp_path, {"sheets": [
        sheet("a", 0, 0), sheet("b", 1, 0)]}))
    # both sheets built the plot over their edge x = 200 m, most of it on b
    a = box_model(str(tmp_path / "a.json"), [("building_1", 10000, 10000, 20000, 20000),
                                              ("building_2", 190000, 10000, 230000, 20000)])
    b = box_model(str(tmp_path / "b.json"), [("building_1", 191000, 10000, 231000, 20000),
                                              ("building_9", 300000, 10000, 310000, 20000)])
    out = io.BytesIO()
    report = merge.merge_sheets([("b", b), ("a", a)], series, out)
    lines = out.getvalue().decode().splitlines()
    assert json.loads(lines[0])["type"] == "CityJSON"
    ids = [json.loads(line)["id"] for line in lines[1:]]
    assert sorted(ids) == ["a/building_1", "b/building_1", "building_9"]
    assert report.dropped == [("a", "building_2", "b")]
    assert report.built == {"a": 2, "b": 2} and report.kept == {"a": 1, "b": 2}


@pytest.mark.parametrize("sheets, margin", [(["a"], 80), (["a", "b", "c"], 0)])
def test_a_sheet_without_neighbours_gets_its_map_through_r_resample(tmp_path, sheets, margin):
    """r.patch needs two maps: a one-sheet series or "margin": 0 (issue 49, item 11)."""
    places = {"a": (0, 0), "b": (1, 0), "c": (0, 1)}
    series = manifest.read_manifest(write_manifest(tmp_path, {"margin": margin, "sheets": [
        sheet(n, *places[n]) for n in sheets]}))
    template = chain.read_template(TEMPLATE)
    for s in series.sheets:
        steps = chain.process_chain(template, series, s).steps()
        patches = [dict(step.params)["input"] for step in steps if step.id.startswith("patch_")]
        assert [step.module for step in steps if step.id.startswith("patch_")] == \
            ["r.resample"] * 3
        assert patches == ["sheet.1", "sheet.2", "sheet.3"]
        settings = dict(chain.shell_settings(template["defaults"], series, s, "/g.geojson"))
        assert settings["SHEET_PATCH"] == "r.resample" and settings["SHEET_NEIGHBOURS"] == ()
    two = manifest.read_manifest(write_manifest(tmp_path, {"sheets": [sheet("a", 0, 0),
                                                                      sheet("b", 1, 0)]}))
    steps = chain.process_chain(template, two, two.sheets[0]).steps()
    assert {step.module for step in steps if step.id.startswith("patch_")} == {"r.patch"}


def test_the_chain_carries_the_grid_of_the_sheet_and_its_neighbours(tmp_path):
    """No file of the driver's in a job (issue 49: paths limited to the work folder)."""
    doc = {"margin": 30, "sheets": [sheet("a", 0, 0), sheet("b", 1, 0), sheet("c", 0, 1),
                                    sheet("d", 5, 5)]}
    series = manifest.read_manifest(write_manifest(tmp_path, doc))
    step = next(s for s in chain.process_chain(chain.read_template(TEMPLATE), series,
                                               series.sheets[1]).steps() if s.id == "import_grid")
    grid = json.loads(dict(step.params)["input"])
    assert [(f["properties"]["name"], f["properties"]["sheet"]) for f in grid["features"]] == \
        [("a", 1), ("b", 2), ("c", 3)]


@pytest.mark.parametrize("text, said", [("[1]", "has no list of steps"),
                                        ('{"list": 1}', "has no list of steps"),
                                        ("nope", "is not JSON"),
                                        ("[" * 5000 + "]" * 5000, "nested too deeply")])
def test_a_bad_chain_template_is_one_input_error(tmp_path, text, said):
    path = tmp_path / "template.json"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(InputError, match=said):
        chain.read_template(str(path))
