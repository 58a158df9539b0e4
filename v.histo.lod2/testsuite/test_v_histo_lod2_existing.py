"""v.histo.lod2 with an existing city model, CityJSONSeq output and pictures (issue 17).

Acceptance on ../shared/data/3dbag_sample (two real Delft buildings of the 3D
BAG, CityJSON 2.0 and CityJSONSeq): aligned footprints made from the ground
surfaces of their solids, plus generated footprints around them.
"""

import io
import json
import os

import numpy as np
import pytest
import shapely
from shapely.geometry import mapping

from histo_testing import run_module
from reconstruction.cityjson import geometry as citygeometry
from reconstruction.cityjson import model as cityjson
from reconstruction.cityjson import seq as cityjsonseq
from reconstruction.cityjson import existing

pytestmark = pytest.mark.grass

MODULE = "v.histo.lod2"
BAG = ("NL.IMBAG.Pand.0503100000028341", "NL.IMBAG.Pand.0503100000031927")
FORMS = ("3dbag_b2.city.json", "3dbag_b2.city.jsonl")
#: generated footprints around the two buildings; the last one is "aligned"
#: but matches nothing (it is generated, with a warning)
BOXES = [shapely.box(84970, 446530, 84985, 446545), shapely.box(85030, 446540, 85040, 446560),
         shapely.box(84990, 446570, 85000, 446580)]


def run(flags="", **kwargs):
    """Run the module; its error output with GRASS's line wrapping undone."""
    rc, out, err = run_module(MODULE, flags, **kwargs)
    return rc, out, " ".join(err.split())


@pytest.fixture(scope="module")
def sample(bag_sample):
    return bag_sample


def sample_footprints(sample):
    """The ground surfaces of the sample's two buildings (in BAG order)."""
    model = existing.read_model(os.path.join(sample, FORMS[0]))
    fps = existing.footprints(model)
    return [fps.geometry(model.buildings.index(b)) for b in BAG]


def footprint_sets(sample):
    """The footprints of the acceptance tests, {map name: (polygons, attributes)}:
    ``fp`` (the :func:`aligned` fixture's), ``only`` (the two BAG buildings
    alone) and ``fp_noh`` (``fp`` without height columns). tools/output_checksums.py
    writes the same."""
    polygons = sample_footprints(sample) + BOXES
    props = [{"h_building": 6.0 + k, "h_attic": 3.0, "plot": 10 + k,
              "source": "aligned" if k in (0, 1, 4) else "2pm",
              "pand_id": BAG[k].rsplit(".", 1)[1] if k < 2 else "",
              "wrong_id": "12345{}".format(k)} for k in range(len(polygons))]
    return {"fp": (polygons, props),
            "only": (polygons[:2], [{"h_building": 6.0, "h_attic": 3.0, "source": "aligned"}] * 2),
            "fp_noh": (polygons, [{"source": "aligned" if k < 2 else "2pm"}
                                  for k in range(len(polygons))])}


def import_footprints(name, tmp_path, polygons, props):
    import grass.script as gs

    feats = [{"type": "Feature", "properties": p, "geometry": mapping(g)}
             for g, p in zip(polygons, props)]
    path = str(tmp_path / (name + ".geojson"))
    with open(path, "w") as f:
        json.dump({"type": "FeatureCollection", "features": feats}, f)
    gs.run_command("v.in.ogr", input=path, output=name, flags="o", quiet=True)
    return name


@pytest.fixture
def aligned(mapset, sample, tmp_path):
    """Vector map ``fp``: the two BAG footprints (aligned, with their pand_id),
    two generated boxes (2pm) and one aligned box that matches nothing."""
    return import_footprints("fp", tmp_path, *footprint_sets(sample)["fp"])


def load(path):
    with open(path) as f:
        return json.load(f)


def check_merged(doc, sample, schemas, generated=3):
    """Both copied buildings with their parts, LoD 2.2 and their vertices
    within 1 mm; the generated ones lod 2.0; schema-valid and consistent."""
    assert cityjson.schema_errors(doc, os.path.join(schemas, "cityjson-2.0.2")) == []
    assert cityjson.consistency_errors(doc) == []
    objects = doc["CityObjects"]
    tops = [o for o, obj in objects.items() if not obj.get("parents")]
    assert len(tops) == 2 + generated
    for oid in BAG:
        part = oid + "-0"
        assert objects[oid]["children"] == [part] and objects[part]["parents"] == [oid]
        assert objects[part]["type"] == "BuildingPart"
        assert [(g["type"], g["lod"]) for g in objects[part]["geometry"]] == [("Solid", "2.2")]
        assert objects[oid]["attributes"]["identificatie"] == oid
        assert objects[oid]["attributes"]["source"] == "aligned"
        # the paradata of a copied building (issue 31): the surest class
        assert objects[oid]["attributes"]["certainty"] == 5
        assert objects[oid]["attributes"]["height_source"] == "copied"
        assert objects[oid]["attributes"]["roof_source"] == "copied"
    gen = [obj for oid, obj in objects.items() if oid not in BAG and not obj.get("parents")]
    assert {g["lod"] for obj in gen for g in obj["geometry"]} == ({"2.0"} if generated else set())
    assert doc["metadata"]["referenceSystem"].endswith("/7415")
    original = citygeometry.resolved(load(os.path.join(sample, FORMS[0])))
    merged = citygeometry.resolved(doc)
    for oid in BAG:
        a = np.array(citygeometry.parts(original[oid + "-0"]["geometry"][0]["boundaries"], 3))
        b = np.array(citygeometry.parts(merged[oid + "-0"]["geometry"][0]["boundaries"], 3))
        assert a.shape == b.shape and np.abs(a - b).max() <= 0.001


@pytest.mark.acceptance
@pytest.mark.parametrize("form", FORMS)
def test_acceptance_copies_both_bag_buildings(aligned, sample, schemas, tmp_path, form):
    out = str(tmp_path / "merged.city.json")
    rc, stdout, err = run(flags="v", input=aligned, output=out,
                          existing=os.path.join(sample, form), id_column="pand_id", crs=7415,
                          roof="gable")
    assert rc == 0, err
    assert "percent_valid=100.00" in stdout
    assert "2 of 3 aligned footprints copied from the existing model (2 matched by id, " \
           "0 by geometry)" in err
    assert "1 aligned footprints matched no building of the existing model and are " \
           "generated" in err
    check_merged(load(out), sample, schemas)


@pytest.mark.acceptance
def test_ids_that_match_nothing_merge_by_geometry_with_counts(aligned, sample, schemas,
                                                               tmp_path):
    out = str(tmp_path / "geom.city.json")
    rc, _, err = run(input=aligned, output=out, existing=os.path.join(sample, FORMS[1]),
                     id_column="wrong_id")
    assert rc == 0, err
    assert "(0 matched by id, 2 by geometry)" in err
    assert "3 building ids matched no object of the existing model" in err
    assert "1 aligned footprints matched no building" in err
    check_merged(load(out), sample, schemas)


@pytest.mark.acceptance
def test_no_id_column_matches_by_geometry_and_prefix_matches_by_id(aligned, sample, tmp_path):
    out = str(tmp_path / "g.city.json")
    rc, _, err = run(input=aligned, output=out, existing=os.path.join(sample, FORMS[0]))
    assert rc == 0, err
    assert "(0 matched by id, 2 by geometry)" in err
    out2 = str(tmp_path / "p.city.json")
    rc, _, err = run(input=aligned, output=out2, existing=os.path.join(sample, FORMS[0]),
                     id_column="pand_id", id_prefix="NL.IMBAG.Pand.")
    assert rc == 0, err
    assert "(2 matched by id, 0 by geometry)" in err
    # a prefix that makes no object id: the ids match nothing, geometry does
    rc, _, err = run(input=aligned, output=out2, existing=os.path.join(sample, FORMS[0]),
                     id_column="pand_id", id_prefix="NL.BAG.", overwrite=True)
    assert rc == 0, err
    assert "(0 matched by id, 2 by geometry)" in err and "2 building ids matched no" in err


@pytest.mark.acceptance
def test_overlap_threshold(aligned, sample, tmp_path):
    out = str(tmp_path / "o.city.json")
    rc, _, err = run(input=aligned, output=out, existing=os.path.join(sample, FORMS[0]),
                     overlap=1)
    assert rc == 0, err
    # the aligned footprints are the model's own: an intersection over union of 1
    assert "(0 matched by id, 2 by geometry)" in err


@pytest.mark.acceptance
def test_existing_lod_not_in_the_model_copies_the_highest(aligned, sample, tmp_path):
    out = str(tmp_path / "l.city.json")
    rc, _, err = run(input=aligned, output=out, existing=os.path.join(sample, FORMS[0]),
                     existing_lod="1.2")
    assert rc == 0, err
    assert "2 copied buildings have none of the LoDs of existing_lod=" in err
    parts = [load(out)["CityObjects"][b + "-0"] for b in BAG]
    assert all([g["lod"] for g in p["geometry"]] == ["2.2"] for p in parts)


@pytest.mark.acceptance
def test_cityjsonseq_collected_equals_the_single_file(aligned, sample, schemas, tmp_path):
    single, seq = str(tmp_path / "m.city.json"), str(tmp_path / "m.city.jsonl")
    for path, fmt in ((single, "cityjson"), (seq, "cityjsonseq")):
        rc, _, err = run(input=aligned, output=path, existing=os.path.join(sample, FORMS[0]),
                         id_column="pand_id", format=fmt)
        assert rc == 0, err
    with open(seq) as f:
        lines = f.read().splitlines()
    assert len(lines) == 1 + 5
    feature_schema = cityjson.schema_validator(os.path.join(schemas, "cityjson-2.0.2"),
                                               "cityjsonfeature.schema.json")
    for line in lines[1:]:
        assert list(feature_schema.iter_errors(json.loads(line))) == []
    back = cityjsonseq.collect(io.StringIO("\n".join(lines)))
    doc = load(single)
    assert citygeometry.resolved(back) == citygeometry.resolved(doc)
    assert back["metadata"] == doc["metadata"]
    check_merged(back, sample, schemas)


def test_cityjsonseq_without_existing_model(mapset, tmp_path):
    name = import_footprints("gen", tmp_path, BOXES, [{"h_building": 6.0, "h_attic": 3.0}] * 3)
    single, seq = str(tmp_path / "m.city.json"), str(tmp_path / "m.city.jsonl")
    for path, fmt in ((single, "cityjson"), (seq, "cityjsonseq")):
        rc, _, err = run(input=name, output=path, format=fmt)
        assert rc == 0, err
    with open(seq) as f:
        back = cityjsonseq.collect(f)
    assert citygeometry.resolved(back) == citygeometry.resolved(load(single))
    assert not os.path.exists(seq + ".part")


def png_pixels(path):
    from PIL import Image

    with Image.open(path) as image:
        return np.asarray(image.convert("RGB")).reshape(-1, 3).astype(int)


def test_render_writes_a_picture_without_display(mapset, tmp_path):
    name = import_footprints("gen", tmp_path, BOXES, [{"h_building": 6.0, "h_attic": 3.0}] * 3)
    out, png = str(tmp_path / "m.city.json"), str(tmp_path / "m.png")
    env = dict(os.environ)
    env.pop("DISPLAY", None)
    env.pop("WAYLAND_DISPLAY", None)
    rc, _, err = run(input=name, output=out, render=png, view="120,40", roof="hip", env=env)
    assert rc == 0, err
    p = png_pixels(png)
    assert len(np.unique(p, axis=0)) > 20
    assert ((p[:, 0] > 150) & (p[:, 1] < 70) & (p[:, 2] < 70)).sum() > 100       # roofs red
    assert ((p >= 230).all(axis=1) & (np.ptp(p, axis=1) < 12)).sum() > 100      # walls white
    assert not [f for f in os.listdir(tmp_path) if ".part" in f]


def test_a_map_far_away_and_an_output_named_as_the_other_format_warn(mapset, tmp_path):
    """map= 100 km from the footprints was drawn apart, and output=x.city.jsonl
    written as CityJSON, without a word (issue 33, items 7 and 8)."""
    import grass.script as gs

    name = import_footprints("gen", tmp_path, BOXES, [{"h_building": 6.0, "h_attic": 3.0}] * 3)
    gs.run_command("g.region", n=446600, s=446510, e=185060, w=184950, res=1)
    for band in ("red", "green", "blue"):
        gs.run_command("r.mapcalc", expression="far.{} = 100".format(band), quiet=True)
    out, png = str(tmp_path / "m.city.jsonl"), str(tmp_path / "m.png")
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    rc, _, err = run(input=name, output=out, render=png, map="far.red,far.green,far.blue",
                     env=env)
    assert rc == 0, err
    text = " ".join(err.split())
    assert "WARNING: output= '{}' ends in .jsonl but format=cityjson writes".format(out) in text
    assert "WARNING: The map of map= (x 184950..185060, y 446510..446600) does not overlap " \
        "the footprints" in text, err
    assert "Traceback" not in err
    assert load(out)["type"] == "CityJSON"


@pytest.mark.acceptance
def test_render_with_copied_buildings_and_the_map(aligned, sample, tmp_path):
    import grass.script as gs

    gs.run_command("g.region", n=446600, s=446510, e=85060, w=84950, res=1)
    for band, value in (("red", 20), ("green", 200), ("blue", 20)):
        gs.run_command("r.mapcalc", expression="m.{} = {}".format(band, value), quiet=True)
    out, png = str(tmp_path / "m.city.json"), str(tmp_path / "m.png")
    env = {k: v for k, v in os.environ.items() if k != "DISPLAY"}
    rc, _, err = run(input=aligned, output=out, existing=os.path.join(sample, FORMS[0]),
                     render=png, map="m.red,m.green,m.blue", view="120,50", env=env)
    assert rc == 0, err
    p = png_pixels(png)
    blue_roof = (p[:, 2] > 130) & (p[:, 0] < 80) & (p[:, 1] < 130)
    map_green = (p[:, 1] > 120) & (p[:, 0] < 60) & (p[:, 2] < 60)
    red_roof = (p[:, 0] > 150) & (p[:, 1] < 70) & (p[:, 2] < 70)
    assert blue_roof.sum() > 50 and red_roof.sum() > 50 and map_green.sum() > 1000


def with_reference_system(sample, tmp_path, code):
    doc = load(os.path.join(sample, FORMS[0]))
    doc["metadata"]["referenceSystem"] = "https://www.opengis.net/def/crs/EPSG/0/{}".format(code)
    path = str(tmp_path / "other.city.json")
    with open(path, "w") as f:
        json.dump(doc, f)
    return path


@pytest.mark.parametrize("case,message", [
    ("not_cityjson", "is not a CityJSON file or CityJSONSeq file"),
    ("missing_file", "Cannot read the existing model"),
    ("other_crs", "EPSG:31370) does not agree with the location's (EPSG:28992)"),
    ("crs_option", "does not agree with the generated model's"),
    ("missing_id_column", "Column <no_such_id> given as id_column="),
    ("prefix_without_existing", "Option id_prefix= needs existing="),
    ("bad_lod", "Option existing_lod= must be LoDs"),
    ("bad_overlap", "Option overlap= must be at most 1"),
    ("bad_view", "Option view= must be azimuth,elevation"),
    ("two_rasters", "Option map= needs one raster map (a greyscale scan) or three"),
    ("render_exists", "exists. To overwrite, use the --overwrite flag"),
])
def test_bad_inputs_fail_cleanly(aligned, sample, tmp_path, case, message):
    out, png = str(tmp_path / "bad.city.json"), str(tmp_path / "bad.png")
    kwargs = {"input": aligned, "output": out, "existing": os.path.join(sample, FORMS[0])}
    if case == "not_cityjson":
        path = tmp_path / "fp.geojson"          # the GeoJSON the footprints came from
        kwargs["existing"] = str(path)
    elif case == "missing_file":
        kwargs["existing"] = str(tmp_path / "none.city.json")
    elif case == "other_crs":
        kwargs["existing"] = with_reference_system(sample, tmp_path, 31370)
    elif case == "crs_option":
        kwargs["crs"] = 31370
    elif case == "missing_id_column":
        kwargs["id_column"] = "no_such_id"
    elif case == "prefix_without_existing":
        del kwargs["existing"]
        kwargs["id_prefix"] = "NL.IMBAG.Pand."
    elif case == "bad_lod":
        kwargs["existing_lod"] = "two"
    elif case == "bad_overlap":
        kwargs["overlap"] = 1.5
    elif case == "bad_view":
        kwargs.update(render=png, view="30,100")
    elif case == "two_rasters":
        kwargs.update(render=png, map="a,b")
    elif case == "render_exists":
        with open(png, "w") as f:
            f.write("keep")
        kwargs["render"] = png
    rc, _, err = run(**kwargs)
    assert rc != 0
    assert "ERROR" in err and message in err, err
    assert "Traceback" not in err
    assert not os.path.exists(out) and not os.path.exists(out + ".part")
    if case == "render_exists":
        with open(png) as f:
            assert f.read() == "keep"
    else:
        assert not os.path.exists(png)


@pytest.mark.acceptance
def test_copied_footprints_are_not_built_even_all_of_them(mapset, sample, schemas, tmp_path):
    name = import_footprints("only", tmp_path, *footprint_sets(sample)["only"])
    out = str(tmp_path / "only.city.json")
    rc, stdout, err = run(flags="v", input=name, output=out,
                          existing=os.path.join(sample, FORMS[1]))
    assert rc == 0, err
    assert "Building" not in err and "2 buildings written" in err
    assert "percent_valid=100.00" in stdout
    check_merged(load(out), sample, schemas, generated=0)


@pytest.mark.acceptance
def test_copied_buildings_give_measured_heights_to_the_generated(mapset, sample, tmp_path):
    # footprints without height columns: the matched 3D BAG buildings' heights
    # (b3_h_maaiveld, b3_h_dak_*) are the measured heights of the
    # neighbourhood analysis, which gives the generated footprints theirs
    from reconstruction.lod2 import heights

    name = import_footprints("fp_noh", tmp_path, *footprint_sets(sample)["fp_noh"])
    out = str(tmp_path / "h.city.json")
    rc, _, err = run(input=name, output=out, existing=os.path.join(sample, FORMS[0]),
                     roof="flat")
    assert rc == 0, err
    assert "The 2 footprints matched in the existing model take its measured heights" in err
    model = existing.read_model(os.path.join(sample, FORMS[0]))
    attrs = [model.objects[b]["attributes"] for b in BAG]
    m = heights.measured_heights({k: [a[k] for a in attrs] for k in attrs[0]})
    generated = [o["attributes"] for oid, o in load(out)["CityObjects"].items()
                 if oid not in BAG and not o.get("parents")]
    assert len(generated) == 3
    for a in generated:
        assert a["height_source"] == "neighbours"
        assert m.eaves.min() - 1e-3 <= a["eaves_height"] <= m.eaves.max() + 1e-3
