"""Buildings that still stand, copied from a current 3D city model (issue 17).

On the 3D BAG excerpt of ../shared/data/3dbag_sample (two Delft buildings,
CityJSON 2.0 and CityJSONSeq): aligned footprints made from the ground
surfaces of their solids, plus generated footprints around them, built with
the current library as v.histo.lod2 builds them.
"""

import copy
import io
import json
import os

import numpy as np
import pytest
import shapely

from reconstruction.core import crs
from reconstruction.cityjson import geometry as citygeometry
from reconstruction.cityjson import copied as citycopy
from reconstruction.cityjson import merge as citymerge
from reconstruction.cityjson import model as cityjson
from reconstruction.cityjson import seq as cityjsonseq
from reconstruction.cityjson import existing
from reconstruction.lod2 import stage as lod2
from reconstruction.lod2.solids import build as solids
from reconstruction.geom.solidset import semantics
from reconstruction.core.errors import InputError

BAG = ("NL.IMBAG.Pand.0503100000028341", "NL.IMBAG.Pand.0503100000031927")
FORMS = ("3dbag_b2.city.json", "3dbag_b2.city.jsonl")
BOXES = [shapely.box(84970, 446530, 84985, 446545), shapely.box(85030, 446540, 85040, 446560),
         shapely.box(84990, 446570, 85000, 446580)]


@pytest.fixture(scope="module")
def sample(bag_sample):
    return bag_sample


@pytest.fixture(scope="module")
def schema_dir(schemas):
    return os.path.join(schemas, "cityjson-2.0.2")


def generated(polygons, first_id=1, crs=28992):
    """The CityJSON text of gable-roofed buildings on ``polygons``, as v.histo.lod2 makes it."""
    n = len(polygons)
    if n == 0:  # build refuses to build nothing; the solids of no footprint
        ss = solids.build_solids(solids.Buildings(
            [], np.zeros(0), np.zeros(0), np.zeros(0), np.zeros(0, dtype=object), np.zeros((0, 3)))).solids
        sem = semantics(ss)
        return ss, sem, [], {}, cityjson.citymodel_text(ss, sem, [], {}, crs, title="test")
    result = lod2.build(lod2.prepare(
        lod2.Footprints(list(polygons), cats=list(range(first_id, first_id + n)),
                        source=["2pm"] * n),
        lod2.Heights(eaves=np.full(n, 6.0), attic=np.full(n, 3.0)),
        lod2.RoofRequests(types=np.full(n, "gable", dtype=object), years=np.full(n, np.nan))))
    attributes = {"roof_type": list(result.roof_types), "source": ["2pm"] * len(result.ids)}
    ss, sem = result.solids, result.semantics
    return ss, sem, result.ids, attributes, cityjson.citymodel_text(
        ss, sem, result.ids, attributes, crs, title="test")


def aligned_and_merged(path, ids=None, lods=None):
    """Read the model, match its own footprints plus BOXES, copy and merge."""
    model = existing.read_model(path)
    fps = existing.footprints(model)
    order = [model.buildings.index(b) for b in BAG]
    polygons = [fps.geometry(b) for b in order] + BOXES
    matches = existing.match(model, polygons, ids=ids)
    todo = np.nonzero(matches.building < 0)[0]
    ss, sem, gids, attrs, text = generated([polygons[i] for i in todo], first_id=3)
    copied = citycopy.copy_buildings(model, matches.building[matches.matched], lods=lods)
    return model, matches, copied, (ss, sem, gids, attrs, text), citymerge.merge(text, copied)


@pytest.mark.parametrize("form", FORMS)
def test_both_copied_buildings_keep_parts_lod22_and_vertices(sample, schema_dir, form):
    path = os.path.join(sample, form)
    ids = ["0503100000028341", 503100000031927, None, "", None]
    model, matches, copied, gen, text = aligned_and_merged(path, ids=ids)
    assert matches.report == existing.MatchReport(5, 2, 0, 3, 0)
    doc = json.loads(text)
    assert cityjson.schema_errors(doc, schema_dir) == []
    assert cityjson.consistency_errors(doc) == []
    objects = doc["CityObjects"]
    assert len(objects) == 3 + 4
    for oid in BAG:
        part = oid + "-0"
        assert objects[oid]["children"] == [part]
        assert objects[part]["parents"] == [oid]
        assert objects[part]["type"] == "BuildingPart"
        assert [(g["type"], g["lod"]) for g in objects[part]["geometry"]] == [("Solid", "2.2")]
        assert objects[oid]["attributes"]["identificatie"] == oid
    generated_lods = {g["lod"] for o in objects.values() if o["type"] == "Building"
                      for g in o.get("geometry", ())}
    assert generated_lods == {"2.0"}
    assert doc["metadata"]["referenceSystem"].endswith("/7415")
    # every copied coordinate within 1 mm of the input, vertex by vertex
    with open(os.path.join(sample, FORMS[0])) as f:
        original = citygeometry.resolved(json.load(f))
    merged = citygeometry.resolved(doc)
    for oid in BAG:
        a = np.array(citygeometry.parts(original[oid + "-0"]["geometry"][0]["boundaries"], 3))
        b = np.array(citygeometry.parts(merged[oid + "-0"]["geometry"][0]["boundaries"], 3))
        assert a.shape == b.shape
        assert np.abs(a - b).max() <= 0.001
    # the same document from the dict as from the text
    assert citymerge.merge(json.loads(gen[4]), copied) == doc


def test_json_and_jsonl_inputs_give_the_same_model(sample):
    docs = [json.loads(aligned_and_merged(os.path.join(sample, form))[4]) for form in FORMS]
    assert citygeometry.resolved(docs[0]) == citygeometry.resolved(docs[1])


def test_ids_that_match_nothing_merge_by_geometry(sample):
    ids = ["999", "NL.IMBAG.Pand.0000000000000001", "7", None, None]
    _, matches, copied, _, text = aligned_and_merged(os.path.join(sample, FORMS[0]), ids=ids)
    assert matches.report == existing.MatchReport(5, 0, 2, 3, 3)
    assert matches.overlap[:2].min() > 0.99
    assert sorted(copied.ids) == sorted(BAG)
    assert cityjson.consistency_errors(json.loads(text)) == []


def near(model):
    """A footprint over the whole model: any id match is near its building."""
    place = model.place()
    return shapely.box(place.x0, place.y0, place.x1, place.y1)


def test_id_rules(sample):
    model = existing.read_model(os.path.join(sample, FORMS[0]))
    polygons = [near(model)] * 4
    full = ["NL.IMBAG.Pand.0503100000028341", "0503100000028341", 503100000031927.0,
            "503100000031927"]
    got = existing.match(model, polygons, ids=full)
    assert [model.buildings[b] if b >= 0 else None for b in got.building] == \
        [BAG[0], None, BAG[1], None]                      # one footprint per building
    prefixed = existing.match(model, polygons[:2], ids=["0503100000028341", "503100000031927"],
                              prefix="NL.IMBAG.Pand.")
    assert prefixed.report.by_id == 1 and prefixed.report.ids_not_found == 1


def test_an_id_match_far_from_its_footprint_is_not_taken(sample):
    """Issue 33, item 8: a model in longitude and latitude that says it is in
    EPSG:7415 would be copied 85 km away; the match by id is refused, counted,
    and the footprint tried by geometry."""
    model = existing.read_model(os.path.join(sample, FORMS[0]))
    fps = existing.footprints(model)
    own = fps.geometry(0)
    width = own.bounds[2] - own.bounds[0]
    ids = [model.buildings[0]]
    for gap, building in ((existing.FAR_ID_MATCH + 1, -1), (existing.FAR_ID_MATCH - 1, 0)):
        moved = shapely.affinity.translate(own, xoff=width + gap)
        got = existing.match(model, [moved], ids=ids)
        assert got.building.tolist() == [building]
        assert got.report.far_ids == (building < 0) and got.report.unmatched == (building < 0)
    assert got.report.far_example == ()
    got = existing.match(model, [shapely.affinity.translate(own, xoff=width + 2e5)], ids=ids)
    assert got.report.far_example == (ids[0], pytest.approx(2e5))
    # the same footprint far from its building matches by geometry where it overlaps one
    assert existing.match(model, [own], ids=["NL.IMBAG.Pand.elsewhere"]).building.tolist() == [0]


def test_two_footprints_with_one_id_report_the_second_as_a_duplicate(sample):
    """The second footprint of a pand_id was counted as "matched no building"
    (issue 33, item 8): it is a duplicate id, reported as such."""
    model = existing.read_model(os.path.join(sample, FORMS[0]))
    fps = existing.footprints(model)
    foot = fps.geometry(model.buildings.index(BAG[0]))
    got = existing.match(model, [foot, foot, BOXES[0]], ids=[BAG[0], BAG[0], None])
    assert got.building.tolist() == [model.buildings.index(BAG[0]), -1, -1]
    assert (got.report.by_id, got.report.unmatched, got.report.ids_not_found) == (1, 1, 0)
    assert (got.report.duplicate_ids, got.report.duplicates_unmatched,
            got.report.duplicate_examples) == (1, 1, (BAG[0],))


def test_a_footprint_that_overlaps_too_little_is_generated(sample):
    model = existing.read_model(os.path.join(sample, FORMS[0]))
    fps = existing.footprints(model)
    b = model.buildings.index(BAG[0])
    foot = fps.geometry(b)
    w = foot.bounds[2] - foot.bounds[0]
    moved = shapely.affinity.translate(foot, xoff=0.6 * w)
    got = existing.match(model, [moved, foot], min_overlap=0.5)
    assert got.building.tolist() == [-1, b]
    assert got.report.unmatched == 1 and got.report.by_geometry == 1


def test_measured_heights_of_the_matched_buildings(sample):
    model = existing.read_model(os.path.join(sample, FORMS[0]))
    got = existing.match(model, [near(model)] * 2, ids=[BAG[1], None])
    h = got.heights
    assert h.ground[0] == pytest.approx(-0.077) and np.isnan(h.ground[1])
    assert (h.roof_50p[0], h.roof_70p[0], h.roof_max[0]) == (9.3, 10.49, 13.44)
    assert h.above_ground("roof_70p")[0] == pytest.approx(10.49 + 0.077)
    # the 2025 names come first
    model.objects[BAG[1]]["attributes"].update(b3_h_70p=11.0, b3_h_nok=12.5)
    h = existing.measured_heights(model, got.building)
    assert (h.roof_70p[0], h.ridge[0]) == (11.0, 12.5)


def with_two_lods(sample):
    with open(os.path.join(sample, FORMS[0])) as f:
        doc = json.load(f)
    for oid in BAG:
        part = doc["CityObjects"][oid + "-0"]
        lod12 = copy.deepcopy(part["geometry"][0])
        lod12["lod"] = "1.2"
        part["geometry"].insert(0, lod12)
    return existing.model_of(doc)


@pytest.mark.parametrize("lods,expected,fallback", [
    (None, ["2.2"], 0), (["1.2"], ["1.2"], 0), ("all", ["1.2", "2.2"], 0), (["1.3"], ["2.2"], 2)])
def test_existing_lod_chooses_the_geometries(sample, lods, expected, fallback):
    model = with_two_lods(sample)
    copied = citycopy.copy_buildings(model, [0, 1], lods=lods)
    for objs in copied.objects():
        part = [o for o in objs.values() if o["type"] == "BuildingPart"][0]
        assert [g["lod"] for g in part["geometry"]] == expected
    assert copied.report.lod_fallback == fallback
    doc = citymerge.merge(json.loads(generated(BOXES)[4]), copied)
    assert cityjson.consistency_errors(doc) == []


def test_cityjson_11_is_upgraded_on_read(sample, tmp_path):
    with open(os.path.join(sample, FORMS[0])) as f:
        doc = json.load(f)
    doc["version"] = "1.1"
    doc["metadata"]["pointOfContact"] = {"contactName": "x", "emailAddress": "x@example.org",
                                         "address": "Julianalaan 134, Delft"}
    doc["extensions"] = {"Generic": {
        "url": "https://cityjson.org/extensions/download/generic.ext.json", "version": "1.0"}}
    doc["CityObjects"]["thing"] = {"type": "+GenericCityObject"}
    path = tmp_path / "old.city.json"
    path.write_text(json.dumps(doc))
    model = existing.read_model(str(path))
    assert json.dumps(1e-7) == "1e-07"            # (cjio's import would make it 0.000000)
    assert model.version == "1.1"
    assert model.objects["thing"]["type"] == "GenericCityObject"
    assert not model.extensions
    assert model.metadata["pointOfContact"]["address"] == {"address": "Julianalaan 134, Delft"}
    assert set(model.buildings) == set(BAG)


@pytest.mark.parametrize("content,message", [
    ('{"type": "FeatureCollection", "features": []}', "type is \"FeatureCollection\""),
    ("not json at all\n", "not JSON"),
    ('{"type": "CityJSON", "version": "1.0", "CityObjects": {}, "vertices": []}', "CityJSON 1.0"),
    ('{"type":"CityJSON","version":"2.0","transform":{"scale":[1,1,1],"translate":[0,0,0]},'
     '"CityObjects":{},"vertices":[]}\n{"type":"Feature"}\n', "line 2: not a CityJSONFeature"),
])
def test_a_file_that_is_not_cityjson_is_an_input_error(tmp_path, content, message):
    path = tmp_path / "x.city.json"
    path.write_text(content)
    with pytest.raises(InputError, match=message):
        existing.read_model(str(path))


def test_missing_and_binary_files_are_input_errors(tmp_path):
    with pytest.raises(InputError, match="Cannot read"):
        existing.read_model(str(tmp_path / "none.city.json"))
    path = tmp_path / "b.city.json"
    path.write_bytes(bytes(range(128, 256)))
    with pytest.raises(InputError, match="not a text file"):
        existing.read_model(str(path))


def test_reference_systems_must_agree(sample):
    model = existing.read_model(os.path.join(sample, FORMS[0]))
    existing.check_reference_system(model, 28992)          # RD New + NAP on RD New
    existing.check_reference_system(model, 7415)
    with pytest.raises(InputError, match="EPSG:7415.*EPSG:31370"):
        existing.check_reference_system(model, 31370)
    copied = citycopy.copy_buildings(model, [0])
    with pytest.raises(InputError, match="reference system"):
        citymerge.merge(generated(BOXES, crs=31370)[4], copied)
    assert crs.horizontal_epsg(7415) == 28992 and crs.horizontal_epsg(28992) == 28992



@pytest.mark.parametrize("spelling", ["urn:ogc:def:crs:EPSG::7415", "EPSG:7415", "7415"])
def test_an_existing_models_epsg_code_is_written_as_its_ogc_url(sample, tmp_path, spelling):
    """Issue 33, item 5: a model that names its reference system otherwise
    than by an OGC URL gives a merged model (one file or CityJSONSeq) whose
    referenceSystem is that URL, as CityJSON 2.0's schema wants it."""
    with open(os.path.join(sample, FORMS[0])) as f:
        doc = json.load(f)
    doc["metadata"]["referenceSystem"] = spelling
    path = tmp_path / "urn.city.json"
    path.write_text(json.dumps(doc))
    copied = citycopy.copy_buildings(existing.read_model(str(path)), [0])
    url = "https://www.opengis.net/def/crs/EPSG/0/7415"
    merged = json.loads(citymerge.merge(generated(BOXES)[4], copied))
    assert merged["metadata"]["referenceSystem"] == url
    assert citymerge.output_reference_system(None, spelling) == url
    assert crs.as_ogc_url(url) == url and crs.as_ogc_url(None) is None
    assert crs.as_ogc_url("RD New") == "RD New"

def test_a_finer_grid_collapses_to_valid_rings(sample):
    """A model on a 0.1 mm grid: vertices closer than the output's millimetre meet."""
    with open(os.path.join(sample, FORMS[0])) as f:
        doc = json.load(f)
    doc["transform"]["scale"] = [0.0001] * 3
    doc["vertices"] = [[x * 10, y * 10, z * 10] for x, y, z in doc["vertices"]]
    part = doc["CityObjects"][BAG[0] + "-0"]["geometry"][0]
    ring = part["boundaries"][0][1][0]
    # a vertex 0.3 mm beside the ring's first one, put in after it
    x, y, z = doc["vertices"][ring[0]]
    doc["vertices"].append([x + 3, y, z])
    ring.insert(1, len(doc["vertices"]) - 1)
    model = existing.model_of(doc)
    copied = citycopy.copy_buildings(model, [0, 1])
    assert copied.report.collapsed_surfaces == 0
    merged = citymerge.merge(json.loads(generated(BOXES)[4]), copied)
    assert cityjson.consistency_errors(merged) == []
    shell = merged["CityObjects"][BAG[0] + "-0"]["geometry"][0]["boundaries"][0]
    assert len(shell) == len(part["boundaries"][0])
    assert len(shell[1][0]) == len(ring) - 1          # the vertex that met its neighbour is gone


def test_copied_attributes_are_added_without_overwriting(sample):
    model = existing.read_model(os.path.join(sample, FORMS[0]))
    copied = citycopy.copy_buildings(model, [0, 1], attributes={
        "plot": [7, None], "status": ["historic", "historic"]})
    tops = [objs[i]["attributes"] for objs, i in zip(copied.trees, copied.ids)]
    assert tops[0]["plot"] == 7 and "plot" not in tops[1]
    assert tops[0]["status"] == "Pand in gebruik"
    # the model read is not changed by copying
    assert "plot" not in model.objects[copied.ids[0]]["attributes"]


def test_a_copied_id_that_a_generated_building_has_is_refused(sample):
    model = existing.read_model(os.path.join(sample, FORMS[0]))
    copied = citycopy.copy_buildings(model, [0])
    ss, sem, ids, attrs, _ = generated(BOXES[:1])
    text = cityjson.citymodel_text(ss, sem, [copied.ids[0]], attrs, 28992)
    with pytest.raises(InputError, match="id of a generated building"):
        citymerge.merge(text, copied)
    with pytest.raises(InputError, match="id of a generated building"):
        cityjsonseq.write(io.StringIO(), ss, sem, [copied.ids[0]], attrs, 28992, copied=copied)


# ---------------------------------------------------------------------------
# CityJSONSeq
# ---------------------------------------------------------------------------

def sequence_of(gen, copied, **kwargs):
    ss, sem, ids, attrs, _ = gen
    f = io.StringIO()
    count = cityjsonseq.write(f, ss, sem, ids, attrs, 28992, "test", copied=copied, **kwargs)
    f.seek(0)
    return count, f


@pytest.mark.parametrize("chunk", [20000, 2])
@pytest.mark.parametrize("form", FORMS)
def test_cityjsonseq_collected_equals_the_single_file(sample, schema_dir, chunk, form):
    """Also: a CityJSONSeq input's features are written as they were read
    (every vertex copied), a single file's renumbered per feature."""
    _, _, copied, gen, text = aligned_and_merged(os.path.join(sample, form))
    assert copied.stored_local == (form == FORMS[1])
    count, f = sequence_of(gen, copied, chunk=chunk)
    if form == FORMS[1]:
        with open(os.path.join(sample, form)) as g:
            read = {o: obj for line in g.readlines()[1:]
                    for o, obj in json.loads(line)["CityObjects"].items()}
        written = {o: obj for line in f.getvalue().splitlines()[1:]
                   for o, obj in json.loads(line)["CityObjects"].items() if o in read}
        assert {o: [g["boundaries"] for g in obj.get("geometry", ())]
                for o, obj in written.items()} == {
                    o: [g["boundaries"] for g in obj.get("geometry", ())]
                    for o, obj in read.items()}
    lines = f.getvalue().splitlines()
    assert count == len(lines) - 1 == 5
    head = json.loads(lines[0])
    assert head["CityObjects"] == {} and head["vertices"] == []
    assert cityjson.schema_errors(head, schema_dir) == []
    feature_schema = cityjson.schema_validator(schema_dir, "cityjsonfeature.schema.json")
    for line in lines[1:]:
        feature = json.loads(line)
        assert list(feature_schema.iter_errors(feature)) == []
        assert feature["id"] in feature["CityObjects"]
        used = citygeometry.indices(
            [g for o in feature["CityObjects"].values() for g in o.get("geometry", ())])
        assert set(used.tolist()) == set(range(len(feature["vertices"])))
    back = cityjsonseq.collect(io.StringIO(f.getvalue()))
    single = json.loads(text)
    assert cityjson.consistency_errors(back) == []
    assert citygeometry.resolved(back) == citygeometry.resolved(single)
    assert back["metadata"] == single["metadata"]


@pytest.mark.parametrize("keep_numbering", [True, False])
def test_an_attribute_like_a_placeholder_is_written_as_it_is(sample, keep_numbering):
    """The bulk writers once put boundaries where json.dumps wrote a NUL
    string; the boundaries are orjson fragments now, and a NUL attribute
    (or one that looks like boundaries) is written as it is."""
    model = existing.read_model(os.path.join(sample, FORMS[0]))
    gen = generated(BOXES)
    odd = {"nul": ["\x00"] * 2, "boundaries": [[[0, 1, 2]]] * 2}
    plain, with_odd = (citycopy.copy_buildings(model, [0, 1], attributes=a,
                                                keep_numbering=keep_numbering)
                       for a in (None, odd))
    single, merged = (json.loads(citymerge.merge(gen[4], c)) for c in (plain, with_odd))
    for oid in BAG:
        attributes = merged["CityObjects"][oid]["attributes"]
        assert (attributes.pop("nul"), attributes.pop("boundaries")) == ("\x00", [[0, 1, 2]])
    assert citygeometry.resolved(merged) == citygeometry.resolved(single)
    back = cityjsonseq.collect(sequence_of(gen, with_odd)[1])
    assert citygeometry.resolved(back)[BAG[0]]["attributes"]["nul"] == "\x00"
    assert cityjson.consistency_errors(back) == []


def test_a_model_read_is_kept_out_of_later_garbage_collections(sample):
    """The parsed model's millions of lists are frozen (gc.freeze) once read,
    not walked again by every later collection of an older generation."""
    import gc

    before = gc.get_freeze_count()
    model = existing.read_model(os.path.join(sample, FORMS[0]))
    lists = sum(len(g["boundaries"]) for o in model.objects.values() for g in o.get("geometry", ()))
    assert gc.isenabled()
    assert gc.get_freeze_count() - before >= lists


def test_copied_attributes_that_json_dumps_and_orjson_write_differently(sample):
    """The copied objects are written by orjson: non-ASCII text stays text,
    NaN becomes null (valid JSON), numpy numbers are numbers; a model with a string
    orjson refuses (a lone surrogate) is written by json.dumps instead (NaN
    then as NaN), in both the single file and the sequence (which the reader then
    refuses: core.jsontext)."""
    model = existing.read_model(os.path.join(sample, FORMS[0]))
    gen = generated(BOXES)
    extra = {"straat": ["Oude Delft éè", "字"], "gauge": [[float("nan"), 1.0], 2.5],
             "count": list(np.array([7, 8], dtype=np.int64))}
    for odd, expected in ((None, ["Oude Delft éè", "字"]),
                          ("\ud800", ["\ud800", "\ud800"])):
        attributes = dict(extra, **({"straat": [odd] * 2} if odd else {}))
        copied = citycopy.copy_buildings(model, [0, 1], attributes=attributes)
        text = citymerge.merge(gen[4], copied)
        merged = json.loads(text)
        assert not odd or "\\ud800" in text
        stream = sequence_of(gen, copied)[1]
        if odd:     # written, but not read back: a lone surrogate is refused on reading
            with pytest.raises(InputError, match="lone UTF-16 surrogate"):
                cityjsonseq.collect(stream)
        back = None if odd else cityjsonseq.collect(stream)
        for doc in (merged, back) if back else (merged,):
            got = [doc["CityObjects"][model.buildings[b]]["attributes"] for b in (0, 1)]
            assert [a["straat"] for a in got] == expected
            assert [a["count"] for a in got] == [7, 8]
            assert got[1]["gauge"] == 2.5
            nan = got[0]["gauge"][0]                # orjson writes null, json.dumps NaN
            assert (nan != nan) if odd else (nan is None)
        assert cityjson.consistency_errors(merged) == []


def test_cityjsonseq_of_generated_buildings_only(schema_dir):
    gen = generated(BOXES + [shapely.box(85100, 446500, 85112, 446509)])
    count, f = sequence_of(gen, None)
    assert count == 4
    back = cityjsonseq.collect(f)
    assert citygeometry.resolved(back) == citygeometry.resolved(json.loads(gen[4]))
    assert cityjson.consistency_errors(back) == []


def test_a_written_sequence_reads_back_as_an_existing_model(sample, tmp_path):
    _, _, copied, gen, text = aligned_and_merged(os.path.join(sample, FORMS[0]))
    path = tmp_path / "out.city.jsonl"
    with open(path, "w") as f:
        cityjsonseq.write(f, *gen[:4], 28992, copied=copied)
    model = existing.read_model(str(path))
    assert model.sequence and len(model.buildings) == 5
    assert sorted(model.tree(BAG[0])) == [BAG[0], BAG[0] + "-0"]
    area = existing.footprints(model).area
    assert np.all(area >= 100 - 1e-6)


def test_every_footprint_copied_leaves_no_generated_building(sample, schema_dir):
    model = existing.read_model(os.path.join(sample, FORMS[0]))
    copied = citycopy.copy_buildings(model, [0, 1])
    ss, sem, ids, attrs, text = generated([])
    assert len(ss) == 0
    doc = json.loads(citymerge.merge(text, copied))
    assert sorted(doc["CityObjects"]) == sorted([b for b in BAG] + [b + "-0" for b in BAG])
    assert cityjson.schema_errors(doc, schema_dir) == []
    assert cityjson.consistency_errors(doc) == []
    back = cityjsonseq.collect(sequence_of((ss, sem, ids, attrs, text), copied)[1])
    assert citygeometry.resolved(back) == citygeometry.resolved(doc)


@pytest.mark.parametrize("far", [0, 2 ** 40])
def test_copied_vertices_equal_to_others_are_shared_in_first_use_order(far):
    """A copied vertex equal to a generated one takes its index, copied
    duplicates become one new vertex, numbered in the order first used
    (``far``: an extent too large to pack into one integer key)."""
    from types import SimpleNamespace

    generated = np.array([[0, 0, 0], [1, 1, 1], [far, 0, 0]])
    copied = SimpleNamespace(vertices=np.array([[5, 5, 5], [1, 1, 1], [7, 7, 7], [5, 5, 5],
                                                [far, 0, 0], [6, 6, 6]]))
    to_out, rows = citymerge._placement(generated, copied)
    assert to_out.tolist() == [3, 1, 4, 3, 2, 5]
    assert rows.tolist() == [[5, 5, 5], [7, 7, 7], [6, 6, 6]]
    alone, rows = citymerge._placement(np.zeros((0, 3), dtype=np.int64), copied)
    assert alone.tolist() == [0, 1, 2, 0, 3, 4] and len(rows) == 5
    distinct = SimpleNamespace(vertices=np.array([[9, 9, 9], [8, 8, 8]]))
    to_out, rows = citymerge._placement(generated, distinct)
    assert to_out.tolist() == [3, 4] and rows.tolist() == [[9, 9, 9], [8, 8, 8]]


def test_copied_rows_in_first_use_order_and_per_building_when_shared():
    source, owner, rows = citycopy._rows(np.array([5, 3, 5, 2]), np.array([0, 0, 0, 1]), 8)
    assert (source.tolist(), owner.tolist(), rows.tolist()) == ([5, 3, 2], [0, 0, 1],
                                                                [0, 1, 0, 2])
    # a model vertex used by two buildings: a row in each, by model vertex
    source, owner, rows = citycopy._rows(np.array([5, 3, 5, 3]), np.array([0, 0, 1, 1]), 8)
    assert (source.tolist(), owner.tolist(), rows.tolist()) == ([3, 5, 3, 5], [0, 0, 1, 1],
                                                                [1, 0, 3, 2])


# ---------------------------------------------------------------------------
# A whole model copied keeps its numbering
# ---------------------------------------------------------------------------

def stored_boundaries(doc):
    return {o: [g["boundaries"] for g in obj.get("geometry", ())]
            for o, obj in doc["CityObjects"].items()}


def test_a_whole_model_keeps_its_numbering_and_its_objects_as_read(sample, schema_dir):
    """Every building of a single file copied (each vertex used): its vertices
    come first in the model's order, its boundaries are written as they were
    read, the generated buildings' indices follow; the same model (objects
    and coordinates) as a copy numbered anew, by text and by dict."""
    path = os.path.join(sample, FORMS[0])
    with open(path) as f:
        read = json.load(f)
    model = existing.read_model(path)
    kept = citycopy.copy_buildings(model, [1, 0])
    anew = citycopy.copy_buildings(model, [1, 0], keep_numbering=False)
    assert kept.model_numbered and not anew.model_numbered
    gen = generated(BOXES)
    docs = [json.loads(citymerge.merge(gen[4], c)) for c in (kept, anew)]
    for doc in docs:
        assert cityjson.schema_errors(doc, schema_dir) == []
        assert cityjson.consistency_errors(doc) == []
    assert citygeometry.resolved(docs[0]) == citygeometry.resolved(docs[1])
    assert {o: b for o, b in stored_boundaries(docs[0]).items()
            if o in read["CityObjects"]} == stored_boundaries(read)
    n = len(read["vertices"])
    shift = np.rint(np.subtract(read["transform"]["translate"],
                                docs[0]["transform"]["translate"]) / 0.001).astype(int)
    assert (np.array(docs[0]["vertices"][:n]) == np.array(read["vertices"]) + shift).all()
    generated_used = citygeometry.indices([g for o, obj in docs[0]["CityObjects"].items()
                                           if o not in read["CityObjects"]
                                           for g in obj["geometry"]])
    assert generated_used.min() == n
    assert citymerge.merge(json.loads(gen[4]), kept) == docs[0]


def test_part_of_a_model_is_numbered_anew(sample):
    """One building of two, a LoD left out, an unused vertex or a CityJSONSeq
    input: the copy's rows are numbered anew (the model's numbering would
    leave vertices unused)."""
    path = os.path.join(sample, FORMS[0])
    model = existing.read_model(path)
    assert not citycopy.copy_buildings(model, [0]).model_numbered
    assert not citycopy.copy_buildings(with_two_lods(sample), [0, 1]).model_numbered
    assert citycopy.copy_buildings(with_two_lods(sample), [0, 1], lods="all").model_numbered
    assert not citycopy.copy_buildings(existing.read_model(os.path.join(sample, FORMS[1])),
                                        [0, 1]).model_numbered
    with open(path) as f:
        doc = json.load(f)
    doc["vertices"].append([1, 2, 3])
    orphan = citycopy.copy_buildings(existing.model_of(doc), [0, 1])
    assert not orphan.model_numbered
    merged = json.loads(citymerge.merge(generated(BOXES)[4], orphan))
    assert cityjson.consistency_errors(merged) == []


def test_a_generated_vertex_equal_to_a_copied_one_is_shared(sample):
    """Where a generated vertex equals a copied one, the copy's own numbering
    cannot hold every vertex once: the vertices are placed one by one and
    the two share one index, by text and by dict alike."""
    model = existing.read_model(os.path.join(sample, FORMS[0]))
    copied = citycopy.copy_buildings(model, [0, 1])
    assert copied.model_numbered
    gen = json.loads(generated(BOXES)[4])
    t = np.rint(np.asarray(gen["transform"]["translate"]) / 0.001).astype(int)
    gen["vertices"][0] = (copied.vertices[5] - t).tolist()
    for doc in (citymerge.merge(gen, copied),
                json.loads(citymerge.merge(json.dumps(gen, separators=(",", ":")), copied))):
        assert cityjson.consistency_errors(doc) == []
        assert len(doc["vertices"]) == len(gen["vertices"]) + len(copied.vertices) - 1


def test_a_copy_numbered_as_its_model_numbered_by_building_as_anew(sample):
    """by_building gives the rows, their start per building and the
    boundaries' texts of the copy numbered anew (as CityJSONSeq features
    want them); a CityJSONSeq written from either is the same."""
    model = existing.read_model(os.path.join(sample, FORMS[0]))
    kept = citycopy.copy_buildings(model, [1, 0])
    anew = citycopy.copy_buildings(model, [1, 0], keep_numbering=False)
    by = citycopy.by_building(kept)
    assert not by.model_numbered and kept.model_numbered
    assert np.array_equal(by.vertices, anew.vertices)
    assert np.array_equal(by.vertex_start, anew.vertex_start)
    assert by.boundary_texts() == anew.boundary_texts() == kept.boundary_texts()
    assert by.stored_local == anew.stored_local
    assert citycopy.by_building(anew) is anew
    with pytest.raises(ValueError, match="numbered as its model"):
        kept.local_index()
    gen = generated(BOXES)
    assert sequence_of(gen, kept)[1].getvalue() == sequence_of(gen, anew)[1].getvalue()


def test_a_sequence_written_to_a_binary_file_is_the_text_files_in_utf8(sample):
    """v.histo.lod2 writes CityJSONSeq to a binary file: the same lines, as UTF-8."""
    _, _, copied, gen, _ = aligned_and_merged(os.path.join(sample, FORMS[0]))
    copied.trees[0][copied.ids[0]]["attributes"]["straat"] = "Oude Delft éè"
    binary = io.BytesIO()
    assert cityjsonseq.write(binary, *gen[:4], 28992, "test", copied=copied) == 5
    assert binary.getvalue().decode("utf-8") == sequence_of(gen, copied)[1].getvalue()


def test_ground_surfaces_by_their_semantic_type():
    """The footprint's surfaces: those whose semantic value names a
    GroundSurface (two entries may), none where the values are null or
    miscounted, or no surface is one."""
    ring = [[[0, 1, 2]], [[3, 4, 5]], [[6, 7, 8]], [[9, 10, 11]]]
    surfaces = [{"type": "GroundSurface"}, {"type": "WallSurface"},
                {"type": "GroundSurface", "kind": "under the passage"}]
    solid = {"type": "Solid", "boundaries": [ring],
             "semantics": {"surfaces": surfaces, "values": [[0, 1, None, 2]]}}
    assert citygeometry.surfaces_of_type(solid, "GroundSurface") == [ring[0], ring[3]]
    assert citygeometry.surfaces_of_type(solid, "RoofSurface") == []
    miscounted = dict(solid, semantics={"surfaces": surfaces, "values": [[0, 1]]})
    assert citygeometry.surfaces_of_type(miscounted, "GroundSurface") == []
    multi = {"type": "MultiSurface", "boundaries": ring,
             "semantics": {"surfaces": surfaces, "values": [2, None, 1, 0]}}
    assert citygeometry.surfaces_of_type(multi, "GroundSurface") == [ring[0], ring[3]]
    assert citygeometry.surfaces_of_type({"type": "Solid", "boundaries": [ring]},
                                         "GroundSurface") == []


@pytest.mark.parametrize("text, message", [
    ("[" * 100000 + "]" * 100000, "nested too deeply"),
    ('{"type": "CityJSON", "version": "2.0", "CityObjects": {}, "vertices": [],\n'
     '"metadata": {"title": "\\udc00"}}', "lone UTF-16 surrogate"),
    ('{"type": "CityJSON", "version": "2.0", "CityObjects": {}, "vertices": []}\n'
     '{"type": "CityJSONFeature", "CityObjects": {}, "vertices": ' + "[" * 5000 + "]" * 5000
     + "}\n", "nested too deeply"),
], ids=["deep", "surrogate", "deep CityJSONSeq line"])
def test_an_existing_model_nested_too_deeply_or_with_a_lone_surrogate_is_one_input_error(
        tmp_path, text, message):
    """Issue 49, item 10: a RecursionError or a write failure later, before jsontext."""
    path = tmp_path / "bad.city.json"
    path.write_text(text)
    with pytest.raises(InputError, match=message):
        existing.read_model(str(path))
