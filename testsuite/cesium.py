"""CesiumJS in headless chromium, offline, for the tests of the 3D Tiles (issue 52, item 2).

CesiumJS (npm's ``cesium``, pinned in the Makefile and installed by ``make
deps`` into the node folder beside Khronos's glTF validator) loads its
workers and assets by URL, which file:// pages cannot: :func:`serve` starts
a web server of the test's own on 127.0.0.1 (a free port; stopped when the
block ends, also on failure) that serves the page :data:`PAGE`, CesiumJS's
built files under ``/cesium/`` and the tileset under ``/tiles/``. The page is
opened in :mod:`browser`'s offline chromium with that one origin allowed
(:meth:`browser.BrowserPage.allow`): every other request is aborted and
recorded, so a test asserts that nothing left the machine.

The viewer has no base-map imagery (``baseLayer: false``), the ellipsoid as
terrain, no Cesium ion (no token, no geocoder, no ion imagery), no sky box
(whose pictures are CesiumJS's own assets anyway). The page sets
``window.tiles``: ``ready`` once every tile in view is loaded and drawn,
``features`` (the tileset's features loaded), ``setYear(year)`` (shows only
the features standing in it, by a 3D Tiles style on the metadata), ``shown()``
(the features shown), ``toWindow(x,
y, z)`` (the window position of an ECEF point, or null) and, after a click,
``picked``: the clicked feature's metadata (id, first_year, last_year, years),
or null when the click hit no feature.
"""

import contextlib
import functools
import http.server
import os
import threading

import numpy as np

NODE_DIR = os.environ.get("HISTO_NODE", os.path.expanduser("~/.local/share/histo/node"))
CESIUM = os.path.join(NODE_DIR, "node_modules", "cesium", "Build", "Cesium")

PAGE = """<!DOCTYPE html>
<html><head><meta charset="utf-8"><title>histo 3D Tiles</title>
<link rel="stylesheet" href="/cesium/Widgets/widgets.css">
<style>html, body, #globe { margin: 0; width: 100%; height: 100%; overflow: hidden; }</style>
<script>window.CESIUM_BASE_URL = "/cesium/";</script>
<script src="/cesium/Cesium.js"></script>
</head><body><div id="globe"></div>
<script>
"use strict";
window.tiles = {ready: false, picked: undefined, features: 0, error: null};
Cesium.Ion.defaultAccessToken = "";
const viewer = new Cesium.Viewer("globe", {
  baseLayer: false, baseLayerPicker: false, geocoder: false, homeButton: false,
  sceneModePicker: false, navigationHelpButton: false, animation: false, timeline: false,
  fullscreenButton: false, infoBox: false, selectionIndicator: false,
  globe: false, skyBox: false,
  skyAtmosphere: false, requestRenderMode: false});
viewer.scene.backgroundColor = Cesium.Color.GRAY;
const names = ["id", "first_year", "last_year", "years", "certainty"];
tiles.toWindow = (x, y, z) => {
  const p = Cesium.SceneTransforms.worldToWindowCoordinates(
    viewer.scene, new Cesium.Cartesian3(x, y, z));
  return p ? [p.x, p.y] : null;
};
tiles.shown = () => {
  let count = 0;
  const walk = (tile) => {
    if (tile.contentReady) {
      for (let i = 0; i < tile.content.featuresLength; i++) {
        count += tile.content.getFeature(i).show ? 1 : 0;
      }
    }
    tile.children.forEach(walk);
  };
  walk(tileset.root);
  return count;
};
tiles.setYear = (year) => {
  tileset.style = new Cesium.Cesium3DTileStyle({
    show: "${first_year} <= " + year + " && ${last_year} >= " + year});
};
let tileset;
new Cesium.ScreenSpaceEventHandler(viewer.scene.canvas).setInputAction((click) => {
  const feature = viewer.scene.pick(click.position);
  tiles.picked = feature instanceof Cesium.Cesium3DTileFeature ?
    Object.fromEntries(names.map((n) => [n, feature.getProperty(n)])) : null;
}, Cesium.ScreenSpaceEventType.LEFT_CLICK);
Cesium.Cesium3DTileset.fromUrl("/tiles/tileset.json").then((loaded) => {
  tileset = loaded;
  tileset.tileFailed.addEventListener((e) => {
    tiles.error = "tile failed: " + e.url + " " + e.message;
  });
  viewer.scene.primitives.add(tileset);
  tileset.tileLoad.addEventListener((tile) => { tiles.features += tile.content.featuresLength; });
  tileset.allTilesLoaded.addEventListener(() => {
    viewer.scene.requestRender();
    requestAnimationFrame(() => requestAnimationFrame(() => { tiles.ready = true; }));
  });
  const sphere = tileset.boundingSphere;
  viewer.camera.viewBoundingSphere(sphere, new Cesium.HeadingPitchRange(
    0, -Cesium.Math.PI_OVER_TWO + 0.35, sphere.radius * 2.2));
  viewer.camera.lookAtTransform(Cesium.Matrix4.IDENTITY);
}).catch((e) => { tiles.error = String(e); });
</script></body></html>
"""


def missing():
    """What is missing to run the CesiumJS tests, as a sentence for pytest.skip, or None."""
    if not os.path.isfile(os.path.join(CESIUM, "Cesium.js")):
        return ("CesiumJS is not installed in {} (`make deps` installs npm's cesium there "
                "when npm is present)".format(os.path.dirname(os.path.dirname(CESIUM))))
    return None


class _Handler(http.server.SimpleHTTPRequestHandler):
    """The page at /, CesiumJS's files under /cesium/, the tileset under /tiles/."""

    def __init__(self, *args, tiles, **kwargs):
        self.tiles = tiles
        super().__init__(*args, directory=CESIUM, **kwargs)

    def do_GET(self):
        if self.path in ("/", "/index.html"):
            body = PAGE.encode("utf-8")
            self.send_response(200)
            self.send_header("Content-Type", "text/html; charset=utf-8")
            self.send_header("Content-Length", str(len(body)))
            self.end_headers()
            self.wfile.write(body)
            return
        super().do_GET()

    def translate_path(self, path):
        for prefix, root in (("/cesium/", CESIUM), ("/tiles/", self.tiles)):
            if path.startswith(prefix):
                self.directory = root
                return super().translate_path("/" + path[len(prefix):])
        return os.path.join(self.tiles, "no such file")

    def log_message(self, *args):
        pass


@contextlib.contextmanager
def serve(tiles):
    """A web server on 127.0.0.1 (a free port) of the page, CesiumJS and the tileset in
    the directory ``tiles``; yields its origin (``http://127.0.0.1:PORT``); stopped
    when the block ends."""
    server = http.server.ThreadingHTTPServer(
        ("127.0.0.1", 0), functools.partial(_Handler, tiles=str(tiles)))
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        yield "http://127.0.0.1:{}".format(server.server_address[1])
    finally:
        server.shutdown()
        server.server_close()
        thread.join(timeout=10)


def corners(document, oid):
    """The lowest and highest corners (model coordinates) of city object ``oid`` of a
    CityJSON ``document``."""
    from reconstruction.cityjson.geometry import indices

    geometry = document["CityObjects"][oid]["geometry"]
    rows = np.array([document["vertices"][i] for i in
                     np.unique(indices(geometry, [0] * len(geometry))).tolist()])
    t = document.get("transform") or {"scale": [1, 1, 1], "translate": [0, 0, 0]}
    xyz = rows * t["scale"] + t["translate"]
    return xyz.min(axis=0), xyz.max(axis=0)


def largest(document, ids):
    """The one of ``ids`` whose box covers the most ground."""
    return max(ids, key=lambda o: float(np.prod(np.subtract(*corners(document, o)[::-1])[:2])))


def middle_ecef(document, oid):
    """The middle of the box of city object ``oid`` of a CityJSON ``document`` in ECEF
    (x, y, z): a point inside a building, to click (PROJ, from the model's CRS)."""
    from pyproj import Transformer

    from reconstruction.core.crs import epsg_code

    middle = np.add(*corners(document, oid)) / 2
    crs = epsg_code(document["metadata"]["referenceSystem"])
    return Transformer.from_crs(crs, 4978, always_xy=True).transform(*middle)


def load_and_click(browser_page, tiles, ecef, year=None, shown=None, timeout_ms=90_000):
    """Open the tileset in the directory ``tiles`` in CesiumJS (:func:`serve`, the page in
    ``browser_page``, a :class:`browser.BrowserPage`), show ``year``'s features (None:
    all; ``shown``: how many it must show) and click at the ECEF point ``ecef``.
    Returns the features loaded, the seconds until every tile in view was drawn and
    the clicked feature's metadata (None: the click hit none)."""
    with serve(tiles) as origin:
        browser_page.allow(origin)
        page = browser_page.page
        page.goto(origin + "/")
        waited = browser_page.wait_ready(
            "window.tiles && (tiles.ready === true || tiles.error !== null)",
            timeout_ms=timeout_ms)
        assert page.evaluate("tiles.error") is None
        if year is not None:
            page.evaluate("tiles.setYear({})".format(int(year)))
            browser_page.wait_ready("tiles.shown() === {}".format(int(shown)))
        x, y = page.evaluate("tiles.toWindow({}, {}, {})".format(*ecef))
        page.mouse.click(x, y)
        browser_page.wait_ready("tiles.picked !== undefined")
        return page.evaluate("tiles.features"), waited, page.evaluate("tiles.picked")
