"""A CityJSONSeq model drawn a batch of features at a time (issue 49, item 14): the
scene, the page and the glTF are those of the whole document, and the memory they
take is that of their compact arrays, not of every building's objects."""

import json
import tracemalloc
from contextlib import nullcontext

import numpy as np
import pytest

from reconstruction.cityjson import seq as cityjsonseq
from reconstruction.epochs.dynamic import Epoch, merge_epochs
from reconstruction.lod2 import output
from reconstruction.lod2.config import OutputRequest
from reconstruction.testsuite.view.models import L_SHAPE, SQUARE, document
from reconstruction.view import (build_scene, glb_bytes, gltf, html, scene, scene_of_seq,
                                 viewer_html)

ARRAYS = ("positions", "kinds", "triangles", "chunk_start", "chunk_vertex", "chunk_building",
          "copied", "origin")


def town(count, per_row=50):
    """A model of ``count`` buildings in rows, every tenth an L, heights varying, and
    attributes of all kinds (a hostile string, nested values)."""
    buildings = {}
    for i in range(count):
        x, y = 30 * (i % per_row), 30 * (i // per_row)
        outline = L_SHAPE if i % 10 == 0 else SQUARE
        buildings["b{}".format(i)] = ([(x + a, y + b) for a, b in outline], 6.0 + i % 7)
    model = document(buildings)
    for k, obj in enumerate(model["CityObjects"].values()):
        obj["attributes"].update({"plot": k, "note": "<!--<script> \u2028 é", "nested": [k, {}]})
    return model


def write_seq(path, model):
    with open(path, "w", encoding="utf-8") as f:
        for feature in cityjsonseq.document_features(model):
            f.write(json.dumps(feature, separators=(",", ":")) + "\n")
    return str(path)


def whole_scene(path, copied=()):
    """The scene as v.histo.lod2 made it before: of the whole document collected."""
    with open(path, encoding="utf-8") as f:
        return build_scene(cityjsonseq.collect(f, path), copied)


@pytest.mark.parametrize("step", [1, 3, 7, 1000])
def test_a_seq_drawn_in_batches_is_the_whole_model_s_scene(tmp_path, step):
    path = write_seq(tmp_path / "town.city.jsonl", town(23))
    copied = ["b4", "b11"]
    whole, streamed = whole_scene(path, copied), scene_of_seq(path, copied, step=step)
    for name in ARRAYS:
        a, b = getattr(whole, name), getattr(streamed, name)
        assert a.dtype == b.dtype and np.array_equal(a, b), name
    assert streamed.ids == whole.ids and streamed.chunk_years == whole.chunk_years
    assert streamed.crs == whole.crs and streamed.years == whole.years == ()
    assert list(streamed.attributes) == list(whole.attributes)
    # the page and the glTF, byte for byte
    assert viewer_html(streamed, "town") == viewer_html(whole, "town")
    assert glb_bytes(streamed) == glb_bytes(whole)


def test_a_dynamic_seq_is_drawn_whole(tmp_path):
    early = document({"kept": (SQUARE, 8.0), "gone": (L_SHAPE, 9.0)})
    late = document({"kept": (SQUARE, 9.0)})
    merged = merge_epochs([Epoch(1880, early), Epoch(1915, late)]).document
    path = write_seq(tmp_path / "dynamic.city.jsonl", merged)
    streamed = scene_of_seq(path, step=1)
    assert streamed.years == (1880, 1915)
    assert streamed.chunk_years == whole_scene(path).chunk_years


def test_a_seq_with_nothing_to_draw_is_refused(tmp_path):
    model = document({"a": (SQUARE, 6.0)})
    model["CityObjects"]["a"]["geometry"] = []
    path = write_seq(tmp_path / "empty.city.jsonl", model)
    with pytest.raises(Exception, match="no surfaces to draw"):
        scene_of_seq(path)


def traced_peak(run):
    """The peak of Python's (and numpy's) allocations while ``run()`` runs, in bytes."""
    tracemalloc.start()
    try:
        run()
        return tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


def views_peak(tmp_path, count):
    """The traced peak of v.histo.lod2's page and glTF (output._views) of a CityJSONSeq
    model of ``count`` buildings, in bytes."""
    model_file = write_seq(tmp_path / "town{}.city.jsonl".format(count), town(count))
    request = OutputRequest(path=model_file, format="cityjsonseq", viewer="town.html",
                            gltf="town.glb")
    page, glb = tmp_path / "town.html", tmp_path / "town.glb"
    peak = traced_peak(lambda: output._views(model_file, str(page), str(glb), request, None,
                                             nullcontext))
    assert glb.read_bytes() == glb_bytes(whole_scene(model_file))
    return peak


def test_viewer_and_gltf_of_a_seq_take_memory_by_the_batch(tmp_path, monkeypatch):
    # v.histo.lod2 viewer= gltf= on a CityJSONSeq output: the page and the glTF of a model
    # read a batch at a time into compact arrays, and written a piece at a time; before,
    # the whole document's objects, the page and the glTF were each held at once (1.7 GB
    # for 50,000 footprints against 226 MB without them). With small batches and
    # pieces, the memory that grows with the city is about that of the scene's arrays.
    monkeypatch.setattr(scene, "STEP", 100)
    monkeypatch.setattr(html, "PIECE", 1 << 16)
    monkeypatch.setattr(gltf, "SPOOLED", 1 << 16)
    build_scene(document({"a": (SQUARE, 6.0)}))          # pyvista imported beforehand
    small, large = views_peak(tmp_path, 500), views_peak(tmp_path, 2000)
    per_building = (large - small) / 1500
    arrays = sum(getattr(scene_of_seq(str(tmp_path / "town2000.city.jsonl")), name).nbytes
                 for name in ARRAYS) / 2000
    print("\npeak traced: {:.1f} MB for 500 buildings, {:.1f} MB for 2000: {:.0f} bytes a "
          "building (the scene's arrays {:.0f})".format(small / 1e6, large / 1e6,
                                                       per_building, arrays))
    # 57d2396: 19,500 bytes a building
    assert per_building < 4 * arrays, per_building
