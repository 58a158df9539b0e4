"""demo/brussels_1924.sh end to end: the shortened chain on Brussels 1924 (issue 18).

The map's raster did not survive, so the chain starts from the thesis's 616
final plots: v.histo.subdivide and v.histo.lod2 with the thesis's parameters
(eaves 6.7-17 m, attic 2.6-6 m), in a fresh EPSG:3857 location (the plots'
reference system). Prints the report's table and asserts: every plot holds
footprints, no overlapping footprints, 100 % valid solids, the CityJSON valid
by the 2.0.2 schema (the document and its first 1,000 buildings) in the
location's EPSG:3857. Skipped without ../shared/data/bxls_1924.
"""

import json
import os

import pytest

from chain_testing import run_chain
from test_demo import need_grass_and_suite

pytestmark = [pytest.mark.grass, pytest.mark.acceptance]


@pytest.fixture(scope="module")
def chain(shared_data, tmp_path_factory):
    folder = os.path.join(shared_data, "bxls_1924")
    if not os.path.isdir(folder):
        pytest.skip("the Brussels 1924 data is not at '{}'".format(folder))
    need_grass_and_suite()
    folder = tmp_path_factory.mktemp("brussels")
    run_chain("brussels_1924.sh", 3857, folder, shared_data)
    out = folder / "out"
    print("\nBrussels 1924 chain (demo/brussels_1924.sh), report.txt:\n" +
          (out / "report.txt").read_text())
    return {"out": out, "report": json.loads((out / "report.json").read_text())}


def test_every_stage_ran_and_was_timed(chain):
    seconds = chain["report"]["seconds"]
    assert set(seconds) == {"import", "subdivide", "lod2"}
    assert all(s > 0 for s in seconds.values())


def test_every_plot_has_footprints_none_overlapping(chain):
    report = chain["report"]
    footprints = report["subdivide"]
    assert report["plots"] == 616
    assert footprints["plots_with_footprints"] == 616
    assert footprints["by_source"]["2pm"] == footprints["footprints"] > 616
    assert footprints["overlapping_pairs"] == 0


def test_solids_all_valid(chain):
    lod2 = chain["report"]["lod2"]
    assert lod2["solids"] == chain["report"]["subdivide"]["footprints"]
    assert lod2["percent_valid"] == 100.0 and lod2["valid"] == lod2["solids"]
    assert lod2["buildings"] == lod2["solids"]
    assert set(lod2["height_source"]) == {"range"}
    assert (chain["out"] / "model.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_cityjson_valid_by_the_2_0_2_schema_in_the_location_crs(chain, schemas):
    report = chain["report"]
    figures = report["cityjson"]
    assert figures["objects_checked"] == min(1000, figures["objects"])
    assert figures["valid"] is True, figures["first_errors"]
    assert report["lod2"]["crs"].endswith("/EPSG/0/3857")
