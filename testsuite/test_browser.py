"""The browser the HTML 3D viewer's tests run in (issue 29), proven on small pages.

A page with Debian's three.js inlined, opened from file:// as a user opens
the viewer, draws a lit box with WebGL in headless chromium (software
rendering, no GPU, no display): the screenshot shows it, and the page had
no error and asked for nothing on the network. Pages that do reach for the
network, or fail, are caught doing it: the guard and the error lists of
``testsuite/browser.py`` work, so a viewer test that finds them empty can
trust them. No GRASS needed.
"""

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
