"""v.histo.timeline in a temporary GRASS location: the epochs' models merged with today's
register (a vector map's table), a snapshot, and one ERROR line for bad options with
nothing written."""

import json
import pathlib

import pytest

from histo_testing import key_values, run_module
from reconstruction.epochs.dynamic import snapshot
from reconstruction.testsuite.view.test_tiles import features_of, read_glb
from reconstruction.testsuite.timeline.test_timeline import write_epochs

pytestmark = pytest.mark.grass


@pytest.fixture
def epochs(mapset, tmp_path):
    import grass.script as gs

    from reconstruction import grassio
    from shapely.geometry import box

    gs.run_command("g.region", n=446020, s=445990, e=84080, w=83990, res=1)
    grassio.write_features("bag", [box(84060, 446000, 84070, 446010)], cats=[1],
                           columns={"identificatie": ["0503100000000007"], "bouwjaar": [1902]})
    return write_epochs(tmp_path)


def test_the_epochs_merge_into_one_model_and_a_year_is_its_snapshot(epochs, tmp_path):
    out = str(tmp_path / "town.city.json")
    rc, stdout, err = run_module("v.histo.timeline", flags="g", models="{},{}".format(
        epochs[1880], epochs[1915]), years="1880,1915", register="bag", output=out)
    assert rc == 0, err
    counts = key_values(stdout)
    assert counts["buildings"] == "4" and counts["standing"] == "1"
    assert counts["buildings_1880"] == "3" and counts["buildings_1915"] == "3"
    with open(out) as f:
        objects = json.load(f)["CityObjects"]
    assert objects["NL.IMBAG.Pand.0503100000000007"]["attributes"]["dateOfConstruction"] == 1902
    assert objects["gone"]["attributes"]["dateOfDemolitionLatest"] == 1915
    rc, stdout, err = run_module("v.histo.timeline", flags="g", input=out, snapshot=1880,
                                 output=str(tmp_path / "y.city.jsonl"), format="cityjsonseq")
    assert rc == 0, err
    assert key_values(stdout)["buildings"] == "3"


def test_bad_years_end_in_one_error_line_and_nothing_written(epochs, tmp_path):
    out = tmp_path / "town.city.json"
    rc, _out, err = run_module("v.histo.timeline", models=epochs[1880], years="1880,1915",
                               output=str(out))
    assert rc != 0 and not out.exists()
    text = " ".join(err.split())
    assert text.count("ERROR:") == 1 and "one year per model" in text
    assert "Traceback" not in err


def rewritten(path, change, tmp_path, name):
    with open(path) as f:
        doc = json.load(f)
    change(doc)
    out = str(tmp_path / name)
    with open(out, "w") as f:
        json.dump(doc, f)
    return out


def set_crs(code):
    def change(doc):
        doc["metadata"]["referenceSystem"] = "https://www.opengis.net/def/crs/EPSG/0/{}".format(
            code)
    return change


def negative_index(doc):
    doc["CityObjects"]["kept"]["geometry"][0]["boundaries"][0][0][0][0] = -1


@pytest.mark.parametrize("case, message", [
    ("mixed", "different reference systems"),
    ("geographic", "EPSG:4326, whose units are not metres"),
    ("swapped", "is of the map of 1915"),
    ("negative", "vertex index -1 is negative"),
    ("nested", "nested too deeply"),
])
def test_bad_epoch_models_end_in_one_error_line_and_nothing_written(epochs, tmp_path, case,
                                                                     message):
    """Issue 49, items 6 and 10: each of these was merged (the output in the last epoch's
    system, a spike where an index wrapped round) or ended in a traceback."""
    first, second = epochs[1880], epochs[1915]
    years = "1880,1915"
    if case == "mixed":
        first = rewritten(first, set_crs(31370), tmp_path, "a.city.json")
        second = rewritten(second, set_crs(28992), tmp_path, "b.city.json")
    elif case == "geographic":
        first = rewritten(first, set_crs(4326), tmp_path, "a.city.json")
    elif case == "swapped":
        years = "1915,1880"
    elif case == "negative":
        first = rewritten(first, negative_index, tmp_path, "a.city.json")
    else:
        (tmp_path / "deep.city.json").write_text("[" * 100000 + "]" * 100000)
        first = str(tmp_path / "deep.city.json")
    out = tmp_path / "town.city.json"
    rc, _out, err = run_module("v.histo.timeline", models="{},{}".format(first, second),
                               years=years, output=str(out))
    assert rc != 0 and not out.exists()
    text = " ".join(err.split())
    assert text.count("ERROR:") == 1 and message in text, text
    assert "Traceback" not in err


def test_tiles_give_each_year_s_buildings_and_gltf_the_last_year(epochs, tmp_path):
    out, tiles, glb = tmp_path / "town.city.json", tmp_path / "tiles", tmp_path / "town.glb"
    rc, _out, err = run_module("v.histo.timeline", models="{},{}".format(
        epochs[1880], epochs[1915]), years="1880,1915", register="bag", output=str(out),
        tiles=str(tiles), gltf=str(glb))
    assert rc == 0, err
    document = json.loads(out.read_text())
    tileset, features = features_of(tiles)
    assert tileset["extras"]["years"] == [1880, 1915]
    for year in (1880, 1901, 1902, 1914, 1915):
        standing = {f[1] for f in features if f[2] <= year <= f[3]}
        expected = {o for o, obj in snapshot(document, year)["CityObjects"].items()
                    if not obj.get("parents")}
        assert standing == expected, year
    gltf, _binary = read_glb(glb)
    last = {o for o, obj in snapshot(document, 1915)["CityObjects"].items()
            if not obj.get("parents")}
    assert {n["name"] for n in gltf["nodes"]} == last
    assert gltf["scenes"][0]["extras"]["year"] == 1915
    # a second run: the directory exists, --overwrite needed, nothing written
    rc, _out, err = run_module("v.histo.timeline", models="{},{}".format(
        epochs[1880], epochs[1915]), years="1880,1915", output=str(tmp_path / "b.city.json"),
        tiles=str(tiles))
    assert rc != 0 and "use --overwrite" in err and err.count("ERROR") == 1
    assert not pathlib.Path(tmp_path / "b.city.json").exists()
