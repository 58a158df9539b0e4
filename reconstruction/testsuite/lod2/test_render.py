"""render.py: a PNG of a city model with no display (issue 17)."""

import json
import os

import numpy as np
import pytest
import shapely

from reconstruction.geom.grid import MapImage
from reconstruction.cityjson import copied as citycopy
from reconstruction.cityjson import merge as citymerge
from reconstruction.cityjson import existing
from reconstruction.lod2 import render
from reconstruction.core.errors import InputError
from reconstruction.testsuite.cityjson.test_existing import BAG, BOXES, generated


def png_pixels(path):
    from PIL import Image

    with Image.open(path) as image:
        return np.asarray(image.convert("RGB")).reshape(-1, 3).astype(int)


def roof_red(p):
    return (p[:, 0] > 150) & (p[:, 1] < 70) & (p[:, 2] < 70)


def wall_white(p):
    return (p >= 230).all(axis=1) & (np.ptp(p, axis=1) < 12)


def test_a_png_without_display_has_red_roofs_and_white_walls(tmp_path, monkeypatch):
    monkeypatch.delenv("DISPLAY", raising=False)
    doc = json.loads(generated(BOXES + [shapely.box(85000, 446500, 85014, 446508)])[4])
    path = str(tmp_path / "model.png")
    image = render.render(doc, path, render.View(210, 35), size=(480, 360))
    assert os.path.getsize(path) > 0 and image.shape == (360, 480, 3)
    p = png_pixels(path)
    assert len(np.unique(p, axis=0)) > 20                   # not blank
    assert roof_red(p).sum() > 100
    assert wall_white(p).sum() > 100
    assert (p == render.BACKGROUND).all(axis=1).mean() < 0.95


def test_copied_buildings_and_the_map_show_in_their_colours(tmp_path, shared_data):
    path = os.path.join(shared_data, "3dbag_sample", "3dbag_b2.city.json")
    if not os.path.exists(path):
        pytest.skip("the 3D BAG sample is not in '{}'".format(path))
    model = existing.read_model(path)
    copied = citycopy.copy_buildings(model, [0, 1])
    doc = citymerge.merge(json.loads(generated(BOXES)[4]), copied)
    green = np.zeros((40, 60, 3), dtype=np.uint8)
    green[..., 1] = 200
    out = str(tmp_path / "copied.png")
    render.render(doc, out, render.View(120, 50), size=(480, 360), copied=BAG,
                  map_image=MapImage(green, (84950, 85060, 446510, 446600)))
    p = png_pixels(out)
    blue_roof = (p[:, 2] > 130) & (p[:, 0] < 80) & (p[:, 1] < 130)
    map_green = (p[:, 1] > 120) & (p[:, 0] < 60) & (p[:, 2] < 60)
    assert blue_roof.sum() > 50 and roof_red(p).sum() > 50 and map_green.sum() > 1000


def test_a_model_without_surfaces_is_an_input_error(tmp_path):
    doc = {"type": "CityJSON", "version": "2.0", "CityObjects": {}, "vertices": []}
    with pytest.raises(InputError, match="no surfaces"):
        render.render(doc, str(tmp_path / "x.png"))
