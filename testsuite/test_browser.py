"""The browser the HTML 3D viewer's tests run in (issue 29), proven on small pages.

A page with Debian's three.js inlined, opened from file:// as a user opens
the viewer, draws a lit box with WebGL in headless chromium (software
rendering, no GPU, no display): the screenshot shows it, and the page had
no error and asked for nothing on the network. Pages that do reach for the
network, or fail, are caught doing it: the guard and the error lists of
``testsuite/browser.py`` work, so a viewer test that finds them empty can
trust them. Then the viewer's own page against hostile data (issue 49, items 3
and 4): text that would break out of its script elements in every field the
page shows, ids that name JavaScript's machinery, and the Content Security
Policy refusing what a copy of the page has injected. No GRASS needed.
"""

import json
import time

import pytest

import browser

pytestmark = pytest.mark.browser

BOX_PAGE = """<!DOCTYPE html>
<html><head><meta charset="utf-8"><title>box</title>
<style>html, body {{ margin: 0; height: 100%; overflow: hidden; background: #fff; }}</style>
<script>{three}</script>
</head><body><script>
const renderer = new THREE.WebGLRenderer({{antialias: true}});
renderer.setSize(window.innerWidth, window.innerHeight);
renderer.setClearColor(0x203040);
document.body.appendChild(renderer.domElement);
const scene = new THREE.Scene();
const camera = new THREE.PerspectiveCamera(45, window.innerWidth / window.innerHeight, 0.1, 100);
camera.position.set(3, 2.5, 4);
camera.lookAt(0, 0, 0);
const box = new THREE.Mesh(new THREE.BoxGeometry(2, 1.5, 1.2),
                           new THREE.MeshPhongMaterial({{color: 0xd08030, flatShading: true}}));
scene.add(box);
scene.add(new THREE.AmbientLight(0xffffff, 0.3));
const sun = new THREE.DirectionalLight(0xffffff, 0.8);
sun.position.set(2, 5, 3);
scene.add(sun);
// the viewer's camera control, from three.js's examples
new THREE.OrbitControls(camera, renderer.domElement);
renderer.render(scene, camera);
window.gl = renderer.getContext();
// ready once the drawn frame has been shown
requestAnimationFrame(() => requestAnimationFrame(() => {{ window.ready = true; }}));
</script></body></html>
"""

BLANK_PAGE = """<!DOCTYPE html>
<html><body style="background: #fff"><script>window.ready = true;</script></body></html>
"""


def _write(tmp_path, name, text):
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def _box_page(tmp_path):
    return _write(tmp_path, "box.html",
                  BOX_PAGE.format(three=browser.three_js(orbit_controls=True)))


def test_three_js_draws_a_lit_box_offline(browser_page, tmp_path):
    page = _box_page(tmp_path)
    blank = _write(tmp_path, "blank.html", BLANK_PAGE)

    start = time.perf_counter()
    browser_page.open(page)
    browser_page.wait_ready()
    first_frame = time.perf_counter() - start
    webgl = browser_page.page.evaluate("""() => {
        const gl = window.gl;
        const info = gl.getExtension('WEBGL_debug_renderer_info');
        return {webgl: gl instanceof WebGLRenderingContext, lost: gl.isContextLost(),
                controls: typeof THREE.OrbitControls === 'function',
                renderer: info ? gl.getParameter(info.UNMASKED_RENDERER_WEBGL) : null,
                revision: THREE.REVISION};
    }""")
    drawn = browser.pixel_variance(browser_page.screenshot())
    browser_page.open(blank)
    browser_page.wait_ready()
    empty = browser.pixel_variance(browser_page.screenshot())
    print("\nthree.js r{revision} on {renderer}: first frame {:.2f} s after opening the page, "
          "pixel variance {:.0f} (blank page {:.0f})".format(first_frame, drawn, empty, **webgl))

    assert webgl["webgl"] and not webgl["lost"] and webgl["controls"], webgl
    # a flat page has none; the box on its background has hundreds
    assert empty == 0
    assert drawn > 100, drawn
    assert browser_page.errors == []
    assert browser_page.blocked == []


def test_the_box_is_shaded_by_the_light(browser_page, tmp_path):
    """Flat shading and a light give the box's visible faces three different shades."""
    import io

    import numpy as np
    from PIL import Image

    browser_page.open(_box_page(tmp_path))
    browser_page.wait_ready()
    with Image.open(io.BytesIO(browser_page.screenshot())) as image:
        pixels = np.asarray(image.convert("RGB")).reshape(-1, 3)
    colours, counts = np.unique(pixels, axis=0, return_counts=True)
    large = colours[counts > 0.01 * len(pixels)]
    # the background and three faces, each a large patch of one colour
    assert len(large) == 4, large
    assert browser_page.errors == []


def test_a_request_to_the_network_is_aborted_and_recorded(browser_page, tmp_path):
    page = _write(tmp_path, "fetch.html", """<!DOCTYPE html><html><body><script>
fetch('http://example.com/model.city.json')
  .then(() => { window.outcome = 'fetched'; }, () => { window.outcome = 'refused'; })
  .finally(() => { window.ready = true; });
</script></body></html>
""")
    browser_page.open(page)
    browser_page.wait_ready()
    assert browser_page.page.evaluate("window.outcome") == "refused"
    assert browser_page.blocked == ["http://example.com/model.city.json"]
    # the browser says so on its console too
    assert any("ERR_BLOCKED_BY_CLIENT" in e for e in browser_page.errors), browser_page.errors


def test_console_errors_and_exceptions_are_collected(browser_page, tmp_path):
    page = _write(tmp_path, "fails.html", """<!DOCTYPE html><html><body><script>
console.error('the model has no buildings');
setTimeout(() => { window.ready = true; undefinedFunction(); });
</script></body></html>
""")
    browser_page.open(page)
    browser_page.wait_ready()
    browser_page.page.wait_for_timeout(50)
    assert len(browser_page.errors) == 2, browser_page.errors
    assert "the model has no buildings" in browser_page.errors[0]
    assert "undefinedFunction is not defined" in browser_page.errors[1]
    assert browser_page.blocked == []


# ---------------------------------------------------------------------------
# The viewer's page against hostile data (issue 49, items 3 and 4)
# ---------------------------------------------------------------------------

#: text that, were it placed in the page as it is, would end the data's <script> element
#: and run scripts of its own (set window.pwned and the page's title, reach the network),
#: or (its "<!--" followed by "<script", with no "-->" after them) put the HTML parser in
#: its double-escaped script state, which swallows the rest of the page; with the line
#: and paragraph separators older JavaScript parsers take for line ends
PAYLOAD = ('<!--<script>\u2028\u2029</script><script>window.pwned = 1; document.title = '
           '"pwned"; fetch("http://evil.example/pwned")</script><img src=x onerror="window.pwned '
           '= 2; document.title = \'pwned\'"> & &amp; "\'')
#: building ids that are the names of a JavaScript object's own machinery
MACHINERY = ("__proto__", "constructor", "toString")


def _model(ids=("a", "b"), name="note", value="a note", epoch=None):
    """A small model of buildings ``ids`` with an attribute ``name`` of ``value`` (and,
    given an ``epoch``, one that differs from epoch to epoch)."""
    from reconstruction.testsuite.view.models import document

    model = document({oid: ([(20 * k, 0), (20 * k + 8, 0), (20 * k + 8, 8), (20 * k, 8)],
                            6.0 + k) for k, oid in enumerate(ids)})
    for obj in model["CityObjects"].values():
        obj["attributes"][name] = value
        if epoch is not None:
            obj["attributes"]["seen"] = "{} {}".format(value, epoch)
    return model


def _viewer_page(tmp_path, model, title, name="hostile.html"):
    from reconstruction.view import build_scene, viewer_html

    return _write(tmp_path, name, viewer_html(build_scene(model), title))


#: records the page's Content Security Policy violations (in window.violations), from
#: before the page's first script: DevTools' init scripts are not subject to the policy
RECORD_VIOLATIONS = """
window.violations = [];
document.addEventListener("securitypolicyviolation", function (e) {
  window.violations.push(e.effectiveDirective + " " + e.blockedURI);
});
"""


def _open_viewer(browser_page, path):
    browser_page.page.add_init_script(RECORD_VIOLATIONS)
    browser_page.open(path)
    browser_page.wait_ready("window.histo && window.histo.ready === true")
    return browser_page.page


def _plain(text):
    """``text`` with its runs of white space (and line separators) as one space."""
    return " ".join(text.replace("\u2028", " ").replace("\u2029", " ").split())


def _nothing_injected_ran(browser_page, page, title):
    assert page.evaluate("window.pwned") is None
    assert _plain(page.title()) == _plain(title)          # the title element's text, as given
    assert browser_page.blocked == []                     # no request left the page
    assert page.evaluate("window.violations") == []       # nothing even tried to run
    assert browser_page.errors == []


def _selected(page, oid):
    """The text of the panel once building ``oid`` is selected (it starts with the id)."""
    assert page.evaluate("histo.select({})".format(json.dumps(oid))) == oid
    info = page.inner_text("#info")
    assert _plain(info).startswith(_plain(oid)), info
    return info


@pytest.mark.parametrize("field", ["title", "building id", "attribute name",
                                   "attribute value"])
def test_hostile_text_in_any_field_reaches_the_page_as_text(browser_page, tmp_path, field):
    # item 4: "<!--" then "<script" in the title, a building id, an attribute's name or
    # value (a footprint column, an existing= or previous= model) no longer swallows the
    # page: it draws, and shows the text as text
    title = PAYLOAD if field == "title" else "Town"
    ids = (PAYLOAD, "b") if field == "building id" else ("a", "b")
    name = PAYLOAD if field == "attribute name" else "note"
    value = PAYLOAD if field == "attribute value" else "a note"
    page = _open_viewer(browser_page, _viewer_page(tmp_path, _model(ids, name, value), title))
    assert page.evaluate("histo.buildings") == page.evaluate("histo.drawn()") == 2
    assert browser.pixel_variance(browser_page.screenshot()) > 100
    assert _plain(page.inner_text("#title")) == _plain(title)
    info = _selected(page, ids[0])
    assert _plain(name) in _plain(info) and _plain(value) in _plain(info)
    _nothing_injected_ran(browser_page, page, title)


def test_ids_naming_javascript_machinery_are_buildings_like_any_other(browser_page, tmp_path):
    # item 4: a building id __proto__ (constructor, toString) is selected and found, with
    # its attributes, one of them named __proto__ too; nothing leaks into Object.prototype
    model = _model(MACHINERY, "__proto__", {"polluted": "yes"})
    page = _open_viewer(browser_page, _viewer_page(tmp_path, model, "machinery"))
    assert page.evaluate("histo.drawn()") == 3
    for oid in MACHINERY:
        info = _selected(page, oid)
        assert "__proto__" in info and '"polluted":"yes"' in info
        assert page.evaluate("histo.find({})".format(json.dumps(oid))) is True
        assert page.evaluate("histo.selected") == oid
    assert page.evaluate("histo.select('hasOwnProperty')") is None     # no such building
    assert page.evaluate("({}).polluted") is None
    _nothing_injected_ran(browser_page, page, "machinery")


def test_hostile_text_in_a_timeline_page(browser_page, tmp_path):
    # item 4 for v.histo.timeline's page: the title, ids and the attributes of two epochs
    # (what one epoch says otherwise is in epoch_attributes), the year slider moved
    from reconstruction.epochs.dynamic import Epoch, merge_epochs
    from reconstruction.view import build_scene, viewer_html

    ids = ("__proto__", "constructor", PAYLOAD)
    early, late = (_model(ids, PAYLOAD, PAYLOAD, epoch) for epoch in (1880, 1915))
    del late["CityObjects"]["constructor"]               # demolished after 1880
    title = PAYLOAD + " 1880-1915"
    merged = merge_epochs([Epoch(1880, early), Epoch(1915, late)], title=title).document
    path = _write(tmp_path, "timeline.html", viewer_html(build_scene(merged), title))
    page = _open_viewer(browser_page, path)
    assert page.evaluate("histo.drawn()") == 3
    page.evaluate("histo.setYear(1915)")
    assert page.evaluate("histo.drawn()") == 2 and page.evaluate("histo.year") == 1915
    for oid in ("__proto__", PAYLOAD):
        info = _selected(page, oid)
        assert "1880" in info and "1915" in info and _plain(PAYLOAD) in _plain(info)
    page.evaluate("histo.setYear(1900)")
    assert page.evaluate("histo.drawn()") == 3
    _selected(page, "constructor")
    _nothing_injected_ran(browser_page, page, title)


def test_the_policy_refuses_a_script_injected_into_a_copy_of_the_page(browser_page, tmp_path):
    # item 3: were escaping ever to fail, the Content Security Policy is the second wall:
    # an inline script, an event handler attribute and a style attribute put into a copy
    # of the page are refused (and reported), and the page still draws
    text = _viewer_page(tmp_path, _model(("a",)), "injected").read_text()
    policy = text.split('http-equiv="Content-Security-Policy" content="', 1)[1].split('"')[0]
    assert "unsafe" not in policy and "default-src 'none'" in policy
    injected = ('<script>window.pwned = 1; document.title = "pwned";</script>'
                '<img src="data:," onerror="window.pwned = 2">'
                '<div id="styled" style="display: none">styled</div>')
    copy = _write(tmp_path, "injected.html", text.replace("<body>", "<body>" + injected, 1))
    page = _open_viewer(browser_page, copy)
    assert page.evaluate("histo.drawn()") == 1
    assert page.evaluate("window.pwned") is None and page.title() == "injected"
    assert page.is_visible("#styled")                     # its style attribute refused
    violations = page.evaluate("window.violations")
    assert sorted(v.split()[0] for v in violations) == [
        "script-src-attr", "script-src-elem", "style-src-attr"], violations
    assert browser_page.blocked == []
    assert all("Content Security Policy" in e for e in browser_page.errors), browser_page.errors


def test_the_page_with_its_map_draws_under_the_policy(browser_page, tmp_path):
    # item 3: what the page needs passes the strict policy: its three scripts and style
    # sheet (by their hashes), the map (a data: PNG) and the model (base64 through a blob)
    import numpy as np

    from reconstruction.geom.grid import MapImage
    from reconstruction.testsuite.view.models import ORIGIN
    from reconstruction.view import build_scene, viewer_html

    rgb = np.zeros((64, 64, 3), dtype=np.uint8)
    rgb[..., 0] = np.arange(64)[:, None] * 4                  # a gradient to see
    west, south = ORIGIN[0] - 10, ORIGIN[1] - 10
    image = MapImage(rgb, (west, west + 60, south, south + 60))
    page_file = _write(tmp_path, "map.html", viewer_html(build_scene(_model()), "map", image))
    page = _open_viewer(browser_page, page_file)
    assert page.evaluate("histo.drawn()") == 2
    assert page.is_visible("#map-toggle")
    assert page.evaluate("window.violations") == []
    assert browser_page.errors == [] and browser_page.blocked == []
