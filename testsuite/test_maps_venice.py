"""Issue 50's acceptance on the Venice 1808 cadaster (sample 3, ../shared/data/maps).

Runs testsuite/maps_chain.py in a fresh EPSG:32633 location: training
points derived at run time from the published parcels (testsuite/real_maps.py,
seeded: a stand-in for a user's points by eye, none stored),
r.histo.classify (``remove=2,6 separate=1 features=lab,size``), v.histo.generalize on the
building class, v.histo.subdivide (with ``map=`` the scan when the module
has that option: footprints that follow the lines the map draws). Scored
by reconstruction.generalize.assessment on the scan's grid:

- blocks (the published parcels' union, lines closed by 0.6 m) against the
  plots, matched one-to-one at IoU > 0.5: F-score >= 0.90, panoptic
  quality >= 0.80;
- parcels matched one-to-one by a footprint at IoU >= 0.5: >= 85 % of the
  published ones (this needs footprints read from the drawn lines).

The classification's seconds per megapixel is a benchmark figure
(testsuite/benchmarks/bench_maps.py), printed here, not asserted. Skipped
(naming the path) without ../shared/data/maps/venice_1808.
"""

import json
import os
import sys

import pytest

from chain_testing import run_in_location
from test_demo import ROOT, need_grass_and_suite

pytestmark = [pytest.mark.grass, pytest.mark.acceptance]


@pytest.fixture(scope="module")
def figures(shared_data, tmp_path_factory):
    scan = os.path.join(shared_data, "maps", "venice_1808", "venice_1808_sample3.tif")
    if not os.path.isfile(scan):
        pytest.skip("the Venice 1808 sample is not at '{}'".format(scan))
    need_grass_and_suite()
    folder = tmp_path_factory.mktemp("venice")
    report = folder / "report.json"
    run_in_location(32633, folder, [sys.executable, os.path.join(ROOT, "testsuite",
                                                                 "maps_chain.py"),
                                    "venice", str(report)])
    figures = json.loads(report.read_text())
    print("\nVenice 1808 sample 3: " + json.dumps(figures, sort_keys=True))
    return figures


def test_every_figure_is_there_and_consistent(figures):
    blocks, parcels = figures["blocks"], figures["parcels"]
    assert blocks["true"] > 0 and blocks["predicted"] > 0
    assert 0 <= blocks["matched"] <= min(blocks["true"], blocks["predicted"])
    assert parcels["parcels"] > 0 and 0 <= parcels["matched"] <= parcels["parcels"]
    assert figures["training_points"] == 90
    assert figures["classify_s_per_mp"] > 0


#: issue 50 is open: the thresholds are its acceptance, not yet met (strict: the
#: test fails as soon as they are, to be unmarked)
OPEN = pytest.mark.xfail(strict=True, reason="issue 50 open: white numbered parcels and "
                                             "courts classified courtyard split their "
                                             "blocks (blocks F 0.78, PQ 0.61; parcels "
                                             "84.7 %)")


@OPEN
def test_blocks_f_score_and_panoptic_quality(figures):
    blocks = figures["blocks"]
    assert blocks["f_score"] >= 0.90, blocks
    assert blocks["pq"] >= 0.80, blocks


@OPEN
def test_parcels_matched_by_footprints(figures):
    """Needs footprints from the drawn lines (v.histo.subdivide map=): the
    procedural cases alone match 12-24 % (issue 50); read from the lines within
    the published blocks 93.9 %, within the chain's joined blocks far fewer."""
    parcels = figures["parcels"]
    assert figures["drawn_lines"], "v.histo.subdivide has no map= option (drawn lines)"
    assert parcels["matched_share"] >= 0.85, parcels
