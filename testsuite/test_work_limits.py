"""Every module refuses a parameter that asks for unbounded work, at once and
with one ERROR line that names a reasonable value (issue 12, item 2)."""

import json

import numpy as np
import pytest
from shapely.geometry import box

from histo_testing import run_module

pytestmark = pytest.mark.grass

X0, Y0 = 84000.0, 446000.0


def assert_refused(code, err, *words):
    """Exit code 1, one ERROR line holding ``words``, no traceback."""
    assert code == 1, err
    errors = [line for line in err.splitlines() if line.startswith("ERROR:")]
    assert len(errors) == 1 and "Traceback" not in err, err
    text = " ".join(err.split())
    for word in words:
        assert word in text, err


@pytest.fixture
def plots(mapset):
    import grass.script as gs

    from reconstruction import grassio

    gs.run_command("g.region", n=Y0 + 300, s=Y0 - 10, e=X0 + 300, w=X0 - 10, res=1)
    grassio.write_features("plots", [box(X0, Y0, X0 + 100, Y0 + 100),
                                     box(X0 + 150, Y0, X0 + 230, Y0 + 60),
                                     box(X0, Y0 + 150, X0 + 60, Y0 + 260)], cats=[1, 2, 3])
    return "plots"


@pytest.mark.parametrize("alpha", ["0.001", "0.1"])
def test_generalize_refuses_a_tiny_alpha(plots, alpha):
    code, _, err = run_module("v.histo.generalize", input=plots, output="gen", alpha=alpha)
    assert_refused(code, err, "alpha={}".format(alpha), "use alpha >=")


def test_subdivide_refuses_millimetre_facades(plots):
    code, _, err = run_module("v.histo.subdivide", input=plots, output="fp", length="0.001,0.002")
    assert_refused(code, err, "length=0.001,0.002", "at least 2")


def test_subdivide_refuses_a_tiny_depth(plots):
    code, _, err = run_module("v.histo.subdivide", input=plots, output="fp", depth="0.01,0.5")
    assert_refused(code, err, "depth=0.01,0.5", "at least 2")


def test_lod2_refuses_centimetre_crow_steps(mapset, tmp_path):
    import grass.script as gs

    feats = [{"type": "Feature", "properties": {"h_building": 9.0, "h_attic": 4.0},
              "geometry": {"type": "Polygon", "coordinates": [[
                  [X0, Y0], [X0 + 12, Y0], [X0 + 12, Y0 + 7], [X0, Y0 + 7], [X0, Y0]]]}}]
    path = tmp_path / "fp.geojson"
    path.write_text(json.dumps({"type": "FeatureCollection", "features": feats}))
    gs.run_command("v.in.ogr", input=str(path), output="fp", flags="o", quiet=True)
    out = tmp_path / "m.city.json"
    code, _, err = run_module("v.histo.lod2", input="fp", output=str(out), roof="stepped",
                              step="0.01,0.02")
    assert_refused(code, err, "step=0.01,0.02", "at least 0.1 m")
    assert not out.exists()


@pytest.mark.parametrize("options,key", [({"buffer": 1e6}, "buffer="),
                                         ({"resolution": "1000,1000", "k": 1000}, "buffer="),
                                         ({"shift": 1e6}, "shift=")])
def test_align_refuses_buffers_and_shifts_beyond_the_maps(plots, options, key):
    from reconstruction import grassio

    grassio.write_features("current", [box(X0 + 5, Y0 + 5, X0 + 15, Y0 + 20)],
                           {"bouwjaar": [1800]})
    code, _, err = run_module("v.histo.align", input=plots, footprints="current", year=1900,
                              output="al", **options)
    assert_refused(code, err, key, "larger than the maps")


def test_classify_refuses_a_grid_of_too_many_segmentations(mapset):
    import grass.script as gs

    from reconstruction import grassio

    gs.run_command("g.region", n=Y0 + 20, s=Y0, e=X0 + 20, w=X0, res=1)
    for band in ("r", "g", "b"):
        gs.mapcalc("{} = row() + col()".format(band), quiet=True)
    grassio.write_points("train", np.array([[X0 + 5, Y0 + 5], [X0 + 15, Y0 + 15]]),
                         {"label": [1, 2], "class": ["building", "street"]})
    code, _, err = run_module("r.histo.classify", input="r,g,b", training="train", output="cls",
                              threshold_step="0.000001")
    assert_refused(code, err, "segmentations", "threshold_step >=")
