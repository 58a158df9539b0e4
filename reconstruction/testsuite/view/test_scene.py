"""A city model as a viewer draws it (reconstruction.view): triangles by building and
version, the years each version stands, and the self-contained HTML page."""

import base64
import gzip
import json
import re

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from reconstruction.epochs.dynamic import Epoch, merge_epochs, snapshot
from reconstruction.testsuite.view.models import L_SHAPE, ORIGIN, SQUARE, document
from reconstruction.view import build_scene
from reconstruction.view.html import viewer_html

def triangle_areas(scene, kind=None):
    p = scene.positions.astype(float)[scene.triangles]
    area = np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1) / 2
    if kind is not None:
        area = area[scene.kinds[scene.triangles[:, 0]] == kind]
    return area


def test_a_concave_building_is_cut_into_triangles_that_cover_its_faces():
    scene = build_scene(document({"L": (L_SHAPE, 9.0), "box": (SQUARE, 6.0)}), copied=["box"])
    assert scene.ids == ("L", "box") and list(scene.copied) == [False, True]
    assert scene.chunk_building.tolist() == [0, 1] and scene.chunk_years == ((), ())
    # an L of 85 m²: ground and roof 85 m² each, walls its 44 m perimeter x 9 m
    chunk = scene.chunk_start
    l_area = triangle_areas(scene)[chunk[0]:chunk[1]]
    kinds = scene.kinds[scene.triangles[chunk[0]:chunk[1], 0]]
    assert l_area[kinds == 0].sum() == pytest.approx(85)
    assert l_area[kinds == 2].sum() == pytest.approx(85)
    assert l_area[kinds == 1].sum() == pytest.approx(44 * 9)
    # every triangle's three corners are of one kind and one chunk
    corner_kinds = scene.kinds[scene.triangles]
    assert (corner_kinds == corner_kinds[:, :1]).all()
    for k in range(2):
        t = scene.triangles[chunk[k]:chunk[k + 1]]
        assert t.min() >= scene.chunk_vertex[k] and t.max() < scene.chunk_vertex[k + 1]
    # local coordinates from the model's lowest corner, float32
    assert scene.positions.dtype == np.float32
    assert tuple(scene.origin) == pytest.approx(ORIGIN)


@settings(max_examples=25, deadline=None)
@given(st.floats(3, 40), st.floats(3, 40), st.floats(2.5, 30))
def test_property_triangles_have_the_solid_s_surface_area(width, depth, height):
    outline = [(0, 0), (width, 0), (width, depth), (0, depth)]
    scene = build_scene(document({"b": (outline, height)}))
    w, d, h = round(width, 3), round(depth, 3), round(height, 3)   # the millimetre grid
    assert triangle_areas(scene).sum() == pytest.approx(2 * w * d + 2 * (w + d) * h, rel=1e-5)


def test_each_version_stands_in_the_years_of_its_snapshot():
    # "kept" stands unchanged, "gone" is demolished after 1880, "raised" gets a
    # second storey in 1915, "new" is built in 1915
    early = document({"kept": (SQUARE, 8.0), "gone": (L_SHAPE, 9.0),
                      "raised": ([(40, 0), (48, 0), (48, 8), (40, 8)], 6.0)})
    late = document({"kept": (SQUARE, 8.0), "raised": ([(40, 0), (48, 0), (48, 8), (40, 8)], 9.0),
                     "new": ([(60, 0), (66, 0), (66, 9), (60, 9)], 7.0)})
    merged = merge_epochs([Epoch(1880, early), Epoch(1915, late)]).document
    scene = build_scene(merged)
    assert scene.years == (1880, 1915)
    versions = {(scene.ids[b], spans) for b, spans in zip(scene.chunk_building,
                                                            scene.chunk_years)}
    assert versions == {("kept", ((1880, 1915),)), ("gone", ((1880, 1914),)),
                        ("raised", ((1880, 1914),)), ("raised", ((1915, 1915),)),
                        ("new", ((1915, 1915),))}
    for year in (1880, 1900, 1915):
        drawn = sorted(scene.ids[b] for b in scene.chunk_building[scene.standing(year)])
        assert drawn == sorted(o for o, v in snapshot(merged, year)["CityObjects"].items()
                               if not v.get("parents"))


def test_a_version_is_drawn_in_its_validity_interval_with_its_building_s_attributes():
    # issue 52: the versions are +BuildingVersion city objects (the suite's Extension);
    # the scene keeps its interface: a chunk per version, in the years the version says
    early = document({"raised": ([(40, 0), (48, 0), (48, 8), (40, 8)], 6.0)})
    late = document({"raised": ([(40, 0), (48, 0), (48, 8), (40, 8)], 9.0)})
    merged = merge_epochs([Epoch(1880, early), Epoch(1915, late)]).document
    scene = build_scene(merged)
    valid = sorted((v["validFrom"], v.get("validTo", 1915))
                   for v in merged["CityObjects"].values() if v["type"] == "+BuildingVersion")
    assert scene.ids == ("raised",) and sorted(s for (s,) in scene.chunk_years) == valid
    assert valid == [(1880, 1914), (1915, 1915)]
    shown = scene.attributes[0]
    assert shown["epochs"] == [1880, 1915] and "+transitions" not in shown
    assert shown == {**merged["CityObjects"]["raised~1880"]["attributes"],
                     **{n: v for n, v in merged["CityObjects"]["raised"]["attributes"].items()
                        if n != "+transitions"}}


def unpacked(page):
    """The arrays a viewer page carries, decoded as the browser does."""
    meta = json.loads(re.search(r'<script id="histo-meta" type="application/json">(.*?)</script>',
                                page, re.S).group(1))
    data = re.search(r'<script id="histo-data" type="application/octet-stream">(.*?)</script>',
                     page, re.S).group(1)
    raw = gzip.decompress(base64.b64decode(data))
    types = {"float32": np.float32, "uint8": np.uint8, "uint16": np.uint16, "uint32": np.uint32}
    return meta, {a["name"]: np.frombuffer(raw, types[a["dtype"]], a["length"], a["offset"])
                  for a in meta["arrays"]}


def test_the_page_carries_the_scene_and_fetches_nothing():
    scene = build_scene(document({"L": (L_SHAPE, 9.0), "box": (SQUARE, 6.0)}))
    page = viewer_html(scene, "Two <houses>")
    meta, arrays = unpacked(page)
    assert meta["ids"] == ["L", "box"] and meta["attributes"][0]["eaves_height"] == 9.0
    assert np.array_equal(arrays["positions"].reshape(-1, 3), scene.positions)
    local = arrays["triangles"].reshape(-1, 3).astype(np.int64)
    per_triangle = np.repeat([0, 1], np.diff(scene.chunk_start))
    assert np.array_equal(local + arrays["chunkVertex"][per_triangle][:, None], scene.triangles)
    assert "<title>Two &lt;houses&gt;</title>" in page
    # no address outside the file: no src= or href= attributes, no remote URL in a script
    assert not re.search(r"\b(src|href)\s*=", page.split("<script>", 1)[0])
    assert "default-src 'none'" in page
    # the same scene, the same bytes
    assert viewer_html(scene, "Two <houses>") == page


def test_a_lone_surrogate_in_the_title_or_an_attribute_is_written_not_a_traceback(tmp_path):
    # a title given on the command line in another encoding, or an attribute column's
    # bytes, arrive as a text with a lone surrogate, which UTF-8 cannot hold: the page is
    # written, the title shows U+FFFD and the data keeps the JSON escape (issue 49, item 10)
    from reconstruction.view import build_scene, viewer_html

    model = document({"a": ([(0, 0), (8, 0), (8, 8), (0, 8)], 6.0)})
    model["CityObjects"]["a"]["attributes"]["note"] = "caf\udce9"
    page = viewer_html(build_scene(model), "Li\udce8ge")
    path = tmp_path / "page.html"
    path.write_text(page, encoding="utf-8")
    text = path.read_text(encoding="utf-8")
    assert "<title>Li\ufffdge</title>" in text
    assert "caf\\udce9" in text and "Li\\udce8ge" in text
    assert '"title":"Li\\udce8ge"' in text
