"""One self-contained HTML file that shows a city model in a browser (issue 29).

The file holds everything it needs: three.js (Debian's ``libjs-three``,
r111, MIT licence, its notice kept in the file) and its OrbitControls, the
viewer's script and style sheet (``viewer.js``, ``viewer.css`` beside this
module), the model's typed arrays (a :class:`~reconstruction.view.scene.Scene`,
gzip-compressed and base64-encoded; the browser's DecompressionStream
unpacks them) and, with a map, the map as a PNG to drape on the ground. It
opens from ``file://`` with no network: nothing is ever fetched.

The same scene gives the same bytes: the arrays are written in a fixed
order, gzip without a time stamp.
"""

import base64
import gzip
import io
import json
import os

import numpy as np

from ..core.contract import CERTAINTY_CLASSES
from ..core.errors import InputError
from .scene import BACKGROUND, COLOURS, COPIED_COLOURS, GROUND, ROOF, WALL

HERE = os.path.dirname(os.path.abspath(__file__))
#: where Debian's libjs-three puts three.js and the notice of its licence
THREE = "/usr/share/javascript/three"
THREE_FILES = ("three.min.js", "examples/js/controls/OrbitControls.js")
THREE_COPYRIGHT = "/usr/share/doc/libjs-three/copyright"
#: the longest side of the map draped on the ground (pixels): a larger scan is scaled down
MAP_PIXELS = 2048


def _three(root=THREE):
    """The text of three.js and its OrbitControls, and of its licence notice."""
    texts = []
    for name in THREE_FILES:
        path = os.path.join(root, name)
        if not os.path.isfile(path):
            raise InputError("The viewer needs three.js ({} is missing): install Debian's "
                             "package libjs-three (make deps does)".format(path))
        with open(path, encoding="utf-8") as f:
            texts.append(f.read())
    notice = ""
    if os.path.isfile(THREE_COPYRIGHT):
        with open(THREE_COPYRIGHT, encoding="utf-8") as f:
            notice = f.read()
    return texts, notice


def _packed(arrays):
    """The arrays (name, numpy array) as one gzip-compressed buffer, and where each lies
    in the uncompressed one (offsets aligned to 4 bytes for the typed arrays)."""
    out, layout, at = io.BytesIO(), [], 0
    for name, array in arrays:
        data = np.ascontiguousarray(array).tobytes()
        layout.append({"name": name, "dtype": str(array.dtype), "offset": at,
                       "length": int(array.size)})
        pad = (-len(data)) % 4
        out.write(data + b"\0" * pad)
        at += len(data) + pad
    return gzip.compress(out.getvalue(), compresslevel=9, mtime=0), layout


def _arrays(scene):
    """The scene's arrays as the viewer reads them; a chunk's triangles index its own
    vertices (uint16) when every chunk has fewer than 65,536 of them."""
    per_triangle = np.repeat(np.arange(len(scene.chunk_start) - 1),
                             np.diff(scene.chunk_start.astype(np.int64)))
    local = scene.triangles.astype(np.int64) - scene.chunk_vertex[per_triangle][:, None]
    small = bool(not len(local) or local.max() < 2 ** 16)
    triangles = local.astype(np.uint16) if small else scene.triangles.astype(np.uint32)
    return [("positions", scene.positions.astype(np.float32)),
            ("kinds", scene.kinds.astype(np.uint8)),
            ("triangles", triangles.ravel()),
            ("chunkStart", scene.chunk_start.astype(np.uint32)),
            ("chunkVertex", scene.chunk_vertex.astype(np.uint32)),
            ("chunkBuilding", scene.chunk_building.astype(np.uint32))], small


def _map_png(map_image, origin):
    """The map (a :class:`~reconstruction.geom.grid.MapImage`) as a PNG data URL at most
    :data:`MAP_PIXELS` on its longer side, and its extent from the scene's origin."""
    from PIL import Image

    image = Image.fromarray(np.ascontiguousarray(map_image.rgb, dtype=np.uint8))
    scale = MAP_PIXELS / max(image.size)
    if scale < 1:
        image = image.resize((max(1, round(image.width * scale)),
                              max(1, round(image.height * scale))), Image.BILINEAR)
    data = io.BytesIO()
    image.save(data, format="PNG", optimize=True)
    west, east, south, north = (float(v) for v in map_image.extent)
    return {"png": "data:image/png;base64," + base64.b64encode(data.getvalue()).decode("ascii"),
            "extent": [west - origin[0], east - origin[0], south - origin[1], north - origin[1]]}


def _json(value):
    """JSON safe inside a <script> element (no "</" closes it early)."""
    return json.dumps(value, ensure_ascii=False, separators=(",", ":")).replace("</", "<\\/")


PAGE = """<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<meta http-equiv="Content-Security-Policy" content="default-src 'none'; script-src 'unsafe-inline'; style-src 'unsafe-inline'; img-src data: blob:; connect-src data: blob:">
<title>{title}</title>
<style>
{css}
</style>
</head>
<body>
<canvas id="view"></canvas>
<div id="panel">
  <div id="title"></div>
  <div>{legend}</div>
  <div id="map-row"><label><input type="checkbox" id="map-toggle" checked> historical map</label></div>
  <input id="search" type="search" placeholder="building id" aria-label="find a building by its id">
  <div id="time"><label>year <input id="year" type="range" step="1"> <b id="year-label"></b></label></div>
  <div id="info"></div>
</div>
<div id="credits">histo viewer; three.js r111 (MIT licence, below in this file)</div>
<script id="histo-meta" type="application/json">{meta}</script>
<script id="histo-data" type="application/octet-stream">{data}</script>
<!-- three.js, https://threejs.org, licence:
{notice}
-->
<script>
{three}
</script>
<script>
{controls}
</script>
<script>
{viewer}
</script>
</body>
</html>
"""


def viewer_html(scene, title, map_image=None, three_root=THREE):
    """The HTML page (str) that shows ``scene`` (a :class:`~reconstruction.view.scene.Scene`)
    titled ``title``, with ``map_image`` draped on the ground when given."""
    (three, controls), notice = _three(three_root)
    arrays, local = _arrays(scene)
    packed, layout = _packed(arrays)
    meta = {"title": title, "ids": list(scene.ids), "attributes": list(scene.attributes),
            "copied": [bool(c) for c in scene.copied],
            "chunkYears": [[list(s) for s in spans] for spans in scene.chunk_years],
            "years": list(scene.years), "origin": [float(v) for v in scene.origin],
            "crs": scene.crs, "localIndices": local, "arrays": layout,
            "colours": COLOURS.tolist(), "copiedColours": COPIED_COLOURS.tolist(),
            "background": list(BACKGROUND), "certainty": CERTAINTY_CLASSES,
            "map": _map_png(map_image, scene.origin) if map_image is not None else None}
    with open(os.path.join(HERE, "viewer.css"), encoding="utf-8") as f:
        css = f.read()
    with open(os.path.join(HERE, "viewer.js"), encoding="utf-8") as f:
        viewer = f.read()
    return PAGE.format(title=_escape(title), css=css, meta=_json(meta),
                       data=base64.b64encode(packed).decode("ascii"),
                       notice=notice.replace("--", "- -"), three=three, controls=controls,
                       viewer=viewer, legend=_legend(scene.copied.any()))


def _legend(copied):
    """The legend's swatches in the palette's colours (copied buildings' roofs with
    ``copied``)."""
    entries = [(COLOURS[ROOF], "roof"), (COLOURS[WALL], "wall"), (COLOURS[GROUND], "ground")]
    if copied:
        entries.append((COPIED_COLOURS[ROOF], "copied"))
    return "".join('<span class="swatch" style="background:#{:02x}{:02x}{:02x}"></span>{}'
                   .format(*(int(v) for v in rgb), name) for rgb, name in entries)


def _escape(text):
    return (str(text).replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")
            .replace('"', "&quot;"))
