"""The series service's gate (issue 49, item 2): file paths in process chains
limited to the series' work folder, only the routes and modules a series needs.
No GRASS, no actinia: :func:`reconstruction.series.gate.refusal` on requests."""

import json
import os
import re

import pytest

from reconstruction.series import chain, gate, manifest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(
    __file__)))))
TEMPLATE = os.path.join(ROOT, "demo", "series", "sheet_chain.json")
SERVICE = os.path.join(ROOT, "tools", "actinia", "service.sh")
POST = "/api/v3/locations/histo/processing_async_export"
SUITE = ["r.histo.classify", "v.histo.generalize", "v.histo.align", "v.histo.subdivide",
         "v.histo.lod2", "v.histo.timeline"]


def chain_modules():
    """The chain's modules as service.sh lists them (its chain_modules)."""
    with open(SERVICE) as f:
        return re.search(r'^chain_modules="([^"]+)"', f.read(), re.M).group(1).split()


@pytest.fixture
def work(tmp_path):
    folder = tmp_path / "work"
    folder.mkdir()
    return folder


@pytest.fixture
def policy(work):
    return gate.Policy.of([str(work)], chain_modules() + SUITE, "histo")


def series_in(work, sheets=("a", "b"), margin=80):
    doc = {"margin": margin, "sheets": [
        {"name": n, "map": n + ".bsq", "training": n + ".t.geojson",
         "footprints": n + ".f.geojson", "year": 1900, "extent": [k * 200, 0, (k + 1) * 200, 200]}
        for k, n in enumerate(sheets)]}
    path = work / "series.json"
    path.write_text(json.dumps(doc))
    return manifest.read_manifest(str(path))


def send(document, policy, method="POST", path=POST):
    return gate.refusal(method, path, json.dumps(document).encode(), policy)


def step(module, inputs=(), outputs=(), **more):
    return dict({"id": "s", "module": module,
                 "inputs": [{"param": p, "value": v} for p, v in inputs],
                 "outputs": [{"param": p, "value": v} for p, v in outputs]}, **more)


def one(*steps):
    return {"version": "1", "list": list(steps)}


@pytest.mark.parametrize("sheets, margin", [(("a", "b"), 80), (("a",), 80), (("a", "b"), 0)])
def test_the_series_own_chains_pass(work, policy, sheets, margin):
    series = series_in(work, sheets, margin)
    template = chain.read_template(TEMPLATE)
    for sheet in series.sheets:
        pc = chain.process_chain(template, series, sheet)
        assert send(pc.document, policy) is None
        assert {s["module"] for s in pc.document["list"]} <= policy.modules


@pytest.mark.parametrize("value", [
    "/etc/shadow", "/root/secret.csv", "{work}/../outside.csv", "{work}/./a.csv",
    "{work}//a.csv", "/vsizip/{work}/a.zip", "/vsicurl/http://example.org/a.tif",
    "CSV:/etc/passwd", "GPKG:/root/a.gpkg:layer", "{work}/a.csv,/etc/passwd", "sub/a.csv",
    "{work}/link/passwd", "$HOME/.bashrc", "$GISDBASE/../../x", "\\\\server\\share",
    " /etc/shadow", "PG:dbname=postgres", "CSV:credentials", "a.csv, WFS:x"])
def test_a_path_outside_the_work_folder_is_refused(work, policy, value):
    (work / "link").symlink_to("/etc")
    value = value.replace("{work}", str(work))
    why = send(one(step("v.in.ogr", [("input", value)], [("output", "x")], flags="o")), policy)
    assert why and "v.in.ogr input=" in why, why


def test_a_path_in_the_work_folder_passes_and_an_output_file_of_the_job(work, policy):
    (work / "sheets").mkdir()
    assert send(one(step("v.in.ogr", [("input", str(work / "sheets" / "a.geojson"))],
                         [("output", "x")])), policy) is None
    assert send(one(step("v.histo.lod2", [("input", "fp")], [("output", "$file::model")])),
                policy) is None
    why = send(one(step("v.histo.lod2", [("input", "fp")], [("output", "/root/.bashrc")])),
               policy)
    assert "outside the series' work folder" in why


@pytest.mark.parametrize("document, said", [
    (one(step("v.db.select", [("map", "x")])), "not one of the series' modules"),
    (one(step("r.out.png", [("input", "x")], [("output", "/tmp/x.png")])), "not one of"),
    (one({"id": "e", "exe": "/bin/sh", "params": ["-c", "id"]}), "<exe> is not allowed"),
    (one(step("g.region", overwrite=True)), "<overwrite> is not allowed"),
    (one(step("g.region", stdin="x::stdout")), "<stdin> is not allowed"),
    (one(step("g.region", flags="-overwrite")), "flags must be letters"),
    (dict(one(step("g.region")), webhooks={"finished": "http://x"}), "<webhooks>"),
    (one(dict(step("g.region"), import_descr={"source": "/etc/passwd", "type": "vector"})),
     "<import_descr>"),
    (one(step("db.connect", [("database", "/root/x.db")])), "outside"),
    (one(step("db.connect", [("database", "$HOME/x.db")])), "'\\$' is allowed only"),
    ({"version": "2", "list": []}, "version"),
])
def test_what_a_series_does_not_need_is_refused(policy, document, said):
    why = send(document, policy)
    assert why and re.search(said, why), why


@pytest.mark.parametrize("method, path, allowed", [
    ("GET", "/api/v3/version", True),
    ("GET", "/api/v3/resources/histo/resource_id-8a2c-11", True),
    ("GET", "/api/v3/resources/histo/resource_id-8a2c-11/model.zip", True),
    ("GET", "/api/v3/resources/histo/resource_id-8a2c-11/mapsetsizes", False),
    ("GET", "/api/v3/resources/histo/resource_id-8a2c-11/../../users", False),
    ("GET", "/api/v3/users", False),
    ("POST", "/api/v3/users/eve", False),
    ("POST", "/api/v3/locations/histo/mapsets/PERMANENT/processing_async", False),
    ("POST", "/api/v3/locations/other/processing_async_export", False),
    ("DELETE", "/api/v3/resources/histo/resource_id-1", False),
    ("GET", POST, False),
])
def test_only_the_routes_a_series_needs_pass(policy, method, path, allowed):
    assert (gate.refusal(method, path, json.dumps(one()).encode(), policy) is None) is allowed


@pytest.mark.parametrize("body, said", [(b"\xff\xfe", "not UTF-8"), (b"[" * 100000, "nested"),
                                        (b"{", "not JSON"), (b"[]", "not an object")])
def test_a_body_that_is_not_a_chain_is_one_refusal(policy, body, said):
    assert said in gate.refusal("POST", POST, body, policy)
