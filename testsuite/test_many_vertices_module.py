"""v.histo.lod2 on footprints of many vertices, as a user runs it (issue 12, item 1)."""

import json

import pytest

from histo_testing import key_values, run_module
from many_vertex_footprints import SHAPES, footprint

pytestmark = pytest.mark.grass

X0, Y0 = 85000.0, 446000.0


def test_lod2_builds_5000_vertex_footprints_and_reports_the_simplified(mapset, tmp_path):
    import grass.script as gs

    feats = []
    for k, shape in enumerate(SHAPES):
        ring = (footprint(shape, 5000) + [X0 + 80.0 * k, Y0]).round(3).tolist()
        feats.append({"type": "Feature", "properties": {"h_building": 9.0, "h_attic": 4.0},
                      "geometry": {"type": "Polygon", "coordinates": [ring + ring[:1]]}})
    feats.append({"type": "Feature", "properties": {"h_building": 9.0, "h_attic": 4.0},
                  "geometry": {"type": "Polygon", "coordinates": [[
                      [X0, Y0 - 40], [X0 + 12, Y0 - 40], [X0 + 12, Y0 - 33], [X0, Y0 - 33],
                      [X0, Y0 - 40]]]}})
    path = tmp_path / "big.geojson"
    path.write_text(json.dumps({"type": "FeatureCollection", "features": feats}))
    gs.run_command("v.in.ogr", input=str(path), output="big", flags="o", quiet=True)
    out = tmp_path / "big.city.json"
    code, stdout, err = run_module("v.histo.lod2", flags="v", input="big", output=str(out),
                                   roof="hip")
    assert code == 0, err
    rep = key_values(stdout)
    assert rep["solids"] == rep["valid"] == "5" and rep["percent_valid"] == "100.00"
    # every 5,000-vertex footprint whose roof stays pitched (hip, or its
    # mansard fallback) stands on its simplified outline; the rectangle not
    simplified = int(rep["simplified"])
    assert 3 <= simplified <= 4
    assert "{} footprints of more than 100 vertices".format(simplified) in " ".join(err.split())
