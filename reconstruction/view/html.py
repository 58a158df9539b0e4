"""One self-contained HTML file that shows a city model in a browser (issue 29).

The file holds everything it needs: three.js (Debian's ``libjs-three``,
r111, MIT licence, its notice kept in the file) and its OrbitControls, the
viewer's script and style sheet (``viewer.js``, ``viewer.css`` beside this
module), the model's typed arrays (a :class:`~reconstruction.view.scene.Scene`,
gzip-compressed and base64-encoded; the browser's DecompressionStream
unpacks them) and, with a map, the map as a PNG to drape on the ground. It
opens from ``file://`` with no network: nothing is ever fetched.

The same scene gives the same bytes: the arrays are written in a fixed
order, gzip without a time stamp. The page is written piece by piece
(:func:`write_viewer`): a city's page is never held whole in memory.
"""

import base64
import hashlib
import io
import json
import os
import zlib

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
#: bytes of the model's arrays compressed, or encoded, at a time
PIECE = 1 << 22
#: the years of a chunk always drawn (one list for all)
NONE = []


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


def _layout(arrays):
    """Where each array (name, numpy array) lies in the uncompressed buffer (offsets
    aligned to 4 bytes for the typed arrays)."""
    layout, at = [], 0
    for name, array in arrays:
        layout.append({"name": name, "dtype": str(array.dtype), "offset": at,
                       "length": int(array.size)})
        at += array.nbytes + (-array.nbytes) % 4
    return layout


def _write_packed(f, arrays):
    """Write the arrays, one after the other (each padded to 4 bytes), gzip-compressed
    and base64-encoded, to the text file ``f``, :data:`PIECE` bytes at a time: the text
    of ``gzip.compress(..., compresslevel=9, mtime=0)`` of their whole, which is never
    held (issue 49, item 14)."""
    packer = zlib.compressobj(9, zlib.DEFLATED, 31)
    held = bytearray()
    for _name, array in arrays:
        data = memoryview(np.ascontiguousarray(array)).cast("B")
        for a in range(0, len(data), PIECE):
            held += packer.compress(data[a:a + PIECE])
            held = _write_base64(f, held)
        held += packer.compress(b"\0" * ((-len(data)) % 4))
    held += packer.flush()
    f.write(base64.b64encode(held).decode("ascii"))


def _write_base64(f, held):
    """Write the base64 text of the bytes ``held`` but the last few (not a multiple of
    3) to the text file ``f``; returns those left."""
    cut = len(held) - len(held) % 3
    f.write(base64.b64encode(held[:cut]).decode("ascii"))
    return held[cut:]


def _local_triangles(scene):
    """The scene's triangles with each chunk's indices counted from its first vertex, as
    uint16 when every chunk has fewer than 65,536 vertices (and True), else the
    scene's own (uint32, and False); worked out :data:`PIECE` bytes at a time."""
    triangles = np.asarray(scene.triangles, dtype=np.uint32)
    step = PIECE // 12
    pieces = range(0, len(triangles), step)

    def local(a):
        b = min(len(triangles), a + step)
        chunk = np.searchsorted(scene.chunk_start, np.arange(a, b), side="right") - 1
        return triangles[a:b].astype(np.int64) - scene.chunk_vertex[chunk][:, None]

    if not all(local(a).max() < 2 ** 16 for a in pieces):
        return triangles, False
    out = np.empty(triangles.shape, dtype=np.uint16)
    for a in pieces:
        out[a:a + step] = local(a)
    return out, True


def _arrays(scene):
    """The scene's arrays as the viewer reads them; a chunk's triangles index its own
    vertices (uint16) when every chunk has fewer than 65,536 of them."""
    triangles, small = _local_triangles(scene)
    return [("positions", np.asarray(scene.positions, dtype=np.float32)),
            ("kinds", np.asarray(scene.kinds, dtype=np.uint8)),
            ("triangles", triangles.ravel()),
            ("chunkStart", np.asarray(scene.chunk_start, dtype=np.uint32)),
            ("chunkVertex", np.asarray(scene.chunk_vertex, dtype=np.uint32)),
            ("chunkBuilding", np.asarray(scene.chunk_building, dtype=np.uint32))], small


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


#: the characters of JSON text written as escapes inside a <script> element: with no
#: "<" there is no "</script" to close it early and no "<!--" followed by "<script" to put
#: the HTML parser in its double-escaped state (issue 49, item 4), which would swallow
#: the rest of the page; ">" and "&" for good measure, U+2028 and U+2029 for older
#: JavaScript parsers. JSON only holds them inside strings, where the escape is the same
#: character. A UTF-16 surrogate in a Python text is always a lone one (a title given on
#: the command line in another encoding, an attribute column's bytes): UTF-8 cannot
#: hold it, JSON's escape can.
SCRIPT_ESCAPES = {c: "\\u{:04x}".format(c) for c in list(map(ord, "<>&\u2028\u2029"))
                  + list(range(0xD800, 0xE000))}


def _json(value):
    """JSON text safe inside a <script> element (:data:`SCRIPT_ESCAPES`)."""
    return json.dumps(value, ensure_ascii=False, separators=(",", ":")).translate(SCRIPT_ESCAPES)


#: the page's Content Security Policy (issue 49, item 3): nothing but its own inline
#: scripts and style sheet, named by their SHA-256 (:func:`_csp`), so that a script or
#: style smuggled into the page, an event handler attribute (onerror=) or a style
#: attribute is refused by the browser even if escaping ever failed; no request
#: anywhere (default-src 'none'), images and the model's data only from data: and blob:
CSP = ("default-src 'none'; script-src {scripts}; style-src {styles}; img-src data: blob:; "
       "connect-src data: blob:; base-uri 'none'; form-action 'none'")

PAGE = """<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<meta http-equiv="Content-Security-Policy" content="{csp}">
<title>{title}</title>
<style>{css}</style>
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
<script>{three}</script>
<script>{controls}</script>
<script>{viewer}</script>
</body>
</html>
"""


def _inline(text, what):
    """``text`` as the content of an inline <script> or <style> element: its own lines
    between two line breaks, as the browser reads it back (line ends as LF, the text its
    hash is computed on). InputError for text that would end the element early or that
    the HTML parser would change."""
    text = text.replace("\r\n", "\n").replace("\r", "\n")
    lower = text.lower()
    if "</script" in lower or "</style" in lower or "<!--" in lower or "\0" in text:
        raise InputError("{} cannot be written inline in the viewer's page".format(what))
    return "\n" + text + "\n"


def _source(text):
    """The CSP source naming an inline element's content ``text`` by its SHA-256."""
    digest = hashlib.sha256(text.encode("utf-8")).digest()
    return "'sha256-{}'".format(base64.b64encode(digest).decode("ascii"))


def _csp(scripts, styles):
    """The page's policy (:data:`CSP`) allowing the inline ``scripts`` and ``styles``."""
    return CSP.format(scripts=" ".join(map(_source, scripts)),
                      styles=" ".join(map(_source, styles)))


def viewer_html(scene, title, map_image=None, three_root=THREE):
    """The HTML page (str) that shows ``scene`` (a :class:`~reconstruction.view.scene.Scene`)
    titled ``title``, with ``map_image`` draped on the ground when given."""
    out = io.StringIO()
    write_viewer(out, scene, title, map_image, three_root)
    return out.getvalue()


def write_viewer(f, scene, title, map_image=None, three_root=THREE):
    """Write the page of :func:`viewer_html` to the text file ``f``, piece by piece: the
    buildings' attributes a block at a time, the arrays compressed and encoded a few
    MB at a time, so that a large model's page is never held whole (issue 49, item 14)."""
    (three, controls), notice = _three(three_root)
    arrays, local = _arrays(scene)
    layout = _layout(arrays)
    head = {"title": title, "ids": list(scene.ids)}
    tail = {"copied": [bool(c) for c in scene.copied],
            "chunkYears": [[list(s) for s in spans] if spans else NONE for spans in
                           scene.chunk_years],
            "years": list(scene.years), "origin": [float(v) for v in scene.origin],
            "crs": scene.crs, "localIndices": local, "arrays": layout,
            "colours": COLOURS.tolist(), "copiedColours": COPIED_COLOURS.tolist(),
            "background": list(BACKGROUND), "certainty": CERTAINTY_CLASSES,
            "map": _map_png(map_image, scene.origin) if map_image is not None else None}
    with open(os.path.join(HERE, "viewer.css"), encoding="utf-8") as css_file:
        css = _inline(css_file.read() + _swatch_css(), "viewer.css")
    with open(os.path.join(HERE, "viewer.js"), encoding="utf-8") as js_file:
        viewer = _inline(js_file.read(), "viewer.js")
    three = _inline(three, "three.js")
    controls = _inline(controls, "three.js's OrbitControls")
    fields = dict(csp=_csp((three, controls, viewer), (css,)), title=_escape(title), css=css,
                  notice=notice.replace("--", "- -"), three=three, controls=controls,
                  viewer=viewer, legend=_legend(scene.copied.any()))
    before, rest = PAGE.split("{meta}")
    between, after = rest.split("{data}")
    f.write(before.format(**fields))
    # the meta's JSON text: the object of head, attributes and tail, in this order
    f.write(_json(head)[:-1] + ',"attributes":[')
    for k, texts in enumerate(scene.attribute_texts()):
        f.write(("," if k else "") + texts.translate(SCRIPT_ESCAPES))
    f.write("]," + _json(tail)[1:])
    f.write(between.format(**fields))
    _write_packed(f, arrays)
    f.write(after.format(**fields))


#: the legend's swatches: (name, colour) in the palette's colours
SWATCHES = (("roof", COLOURS[ROOF]), ("wall", COLOURS[WALL]), ("ground", COLOURS[GROUND]),
            ("copied", COPIED_COLOURS[ROOF]))


def _swatch_css():
    """The swatches' colours as rules of the style sheet (a style attribute would need
    'unsafe-inline' in the policy)."""
    return "".join("\n.swatch.{} {{ background: #{:02x}{:02x}{:02x}; }}".format(
        name, *(int(v) for v in rgb)) for name, rgb in SWATCHES)


def _legend(copied):
    """The legend's swatches (copied buildings' roofs with ``copied``)."""
    return "".join('<span class="swatch {0}"></span>{0}'.format(name)
                   for name, _rgb in SWATCHES[:4 if copied else 3])


_SURROGATES = dict.fromkeys(range(0xD800, 0xE000), "\ufffd")


def _escape(text):
    """``text`` as HTML text; a lone surrogate (which UTF-8 cannot hold) as U+FFFD."""
    return (str(text).translate(_SURROGATES).replace("&", "&amp;")
            .replace("<", "&lt;").replace(">", "&gt;").replace('"', "&quot;"))
