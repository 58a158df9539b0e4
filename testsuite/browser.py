"""A real headless browser for the tests of the HTML 3D viewer (issue 29).

The viewer is one self-contained HTML file (three.js inlined) that a user
opens from file:// without a network, so its tests open it the same way in
Debian's chromium, driven through Playwright's sync API. Playwright never
downloads a browser here: ``make build`` installs ``chromium`` (Debian) and
``playwright`` (the venv), and :data:`CHROMIUM` is the browser launched.

WebGL is drawn by SwiftShader, chromium's software renderer, through ANGLE
(:data:`SOFTWARE_WEBGL`): it needs no GPU and no display, and a developer's
machine with a GPU draws with the same renderer as the 2-core CI machine.

The network is off: every request that is not file:, data: or blob: is
aborted and its URL recorded (:attr:`BrowserPage.blocked`), so that a test
can assert that the page never tried to reach the network; host names do
not resolve either (:data:`OFFLINE`), for what a page route does not see.

Use :func:`headless_page` (a context manager), or the fixtures
``browser_page`` (a :class:`BrowserPage` per test) and ``chromium`` (the
browser, once per test file) of the root conftest.py, which skip the test with
what is missing when chromium or Playwright is not installed.
"""

import contextlib
import importlib.util
import io
import os
import pathlib
import time

CHROMIUM = "/usr/bin/chromium"
THREE_JS = "/usr/share/javascript/three/three.min.js"
ORBIT_CONTROLS_JS = "/usr/share/javascript/three/examples/js/controls/OrbitControls.js"
VIEWPORT = {"width": 1024, "height": 768}
# WebGL through ANGLE on SwiftShader. Chromium 156 headless picked it by itself
# on this machine without a GPU, but would draw with a GPU where there is one;
# these flags make SwiftShader the renderer everywhere, and
# --enable-unsafe-swiftshader allows it for WebGL, which chromium no longer
# promises to do without the flag (it deprecated the automatic fallback).
SOFTWARE_WEBGL = ("--use-gl=angle", "--use-angle=swiftshader", "--enable-unsafe-swiftshader")
# No host name resolves, for the requests a page route never sees (the
# browser's own, a service worker's); but 127.0.0.1, where a test may serve
# pages of its own (testsuite/cesium.py), which the route still guards.
OFFLINE = ("--host-resolver-rules=MAP * ~NOTFOUND, EXCLUDE 127.0.0.1",)
LOCAL_SCHEMES = ("file", "data", "blob")
# Long enough for a first frame drawn in software on a busy 2-core machine,
# short enough that a page that never gets ready fails the test quickly.
TIMEOUT_MS = 15_000


def missing():
    """What is missing to run the browser tests, as a sentence for pytest.skip, or None."""
    if importlib.util.find_spec("playwright") is None:
        return ("Playwright is not installed in this Python (`make build` installs it in "
                "the virtual environment; run the tests through `make test`)")
    if not os.access(CHROMIUM, os.X_OK):
        return ("chromium is not installed at {} (`make build` installs Debian's chromium)"
                .format(CHROMIUM))
    return None


def three_js(orbit_controls=False):
    """The text of Debian's three.min.js (three.js r111, global ``THREE``), to inline.

    ``orbit_controls``: followed by OrbitControls.js, which adds
    ``THREE.OrbitControls`` (put both in one <script>, or this one after
    three.js); neither file holds "</script", so both inline as they are.
    Skips the test when libjs-three is not installed: a page without
    three.js would only show the missing package as a JavaScript error.
    """
    import pytest

    paths = [THREE_JS] + ([ORBIT_CONTROLS_JS] if orbit_controls else [])
    texts = []
    for path in paths:
        if not os.path.isfile(path):
            pytest.skip("three.js is not installed at {} (`make build` installs Debian's "
                        "libjs-three)".format(path))
        with open(path, encoding="utf-8") as f:
            texts.append(f.read())
    return "\n;\n".join(texts)


class BrowserPage:
    """The page of a fresh browser ``context``, offline, with what went wrong in it.

    ``page``: the Playwright page (its whole API); ``errors``: the console
    messages of type error and the uncaught exceptions (``pageerror``) as
    text, in order; ``blocked``: the URLs of the requests and WebSockets the
    network guard aborted.
    """

    def __init__(self, context):
        self.errors = []
        self.blocked = []
        self.allowed = []        # origins let through besides the local schemes (allow)
        # the guard first: not even the page's first request passes before it
        context.route("**/*", self.guard)
        context.route_web_socket("**/*", self.guard_web_socket)
        self.page = page = context.new_page()
        page.on("console", self._console)
        page.on("pageerror", lambda error: self.errors.append("page error: {}".format(error)))
        page.on("crash", lambda _: self.errors.append("the page crashed"))

    def _console(self, message):
        if message.type == "error":
            where = message.location
            self.errors.append("console error: {} ({}:{})".format(
                message.text, where.get("url", ""), where.get("lineNumber", "")))

    def allow(self, origin):
        """Let the requests to ``origin`` through too: a server of the test's own on
        127.0.0.1 (e.g. ``http://127.0.0.1:8123``), never another host."""
        if not origin.startswith("http://127.0.0.1:"):
            raise ValueError("only a server on 127.0.0.1 may be allowed, not " + origin)
        self.allowed.append(origin + "/")

    def guard(self, route):
        """Let local requests through, abort and record any other."""
        url = route.request.url
        if url.split(":", 1)[0] in LOCAL_SCHEMES or url.startswith(tuple(self.allowed)):
            route.continue_()
        else:
            self.blocked.append(route.request.url)
            route.abort("blockedbyclient")

    def guard_web_socket(self, socket):
        """Record a WebSocket and close it without connecting (page routes miss them)."""
        self.blocked.append(socket.url)
        socket.close(code=1008, reason="no network in the tests")

    def open(self, path):
        """Open a local file as a user would (file://); return the Playwright response."""
        return self.page.goto(pathlib.Path(path).resolve().as_uri())

    def wait_ready(self, hook="window.ready === true", timeout_ms=TIMEOUT_MS, every_ms=50):
        """Wait until the page says it has drawn (``hook`` true); return the seconds waited.

        Polled with ``page.evaluate`` (DevTools' own evaluation), not
        ``wait_for_function``, whose predicate Playwright compiles with eval in
        the page: a page whose Content Security Policy forbids eval (the
        viewer's does) would refuse it. On a timeout the error names the
        errors the page had, which are usually why it never got ready.
        """
        start = time.perf_counter()
        while True:
            try:
                if self.page.evaluate("Boolean({})".format(hook)):
                    return time.perf_counter() - start
                failure = None
            except Exception as error:          # e.g. the page crashed or navigated
                failure = error
            if (time.perf_counter() - start) * 1000 > timeout_ms:
                raise AssertionError("the page never got ready ({}{}); its errors: {}".format(
                    hook, ": {}".format(str(failure).splitlines()[0]) if failure else "",
                    self.errors or "none"))
            self.page.wait_for_timeout(every_ms)

    def screenshot(self):
        """The viewport as PNG bytes."""
        return self.page.screenshot()


@contextlib.contextmanager
def launch(playwright=None):
    """Debian's chromium, headless with software WebGL and offline; always closed.

    Starts Playwright too unless one is given (its sync API allows one per
    thread).
    """
    if playwright is None:
        from playwright.sync_api import sync_playwright

        with sync_playwright() as started, launch(started) as browser:
            yield browser
        return
    browser = playwright.chromium.launch(
        executable_path=CHROMIUM, headless=True, args=list(SOFTWARE_WEBGL + OFFLINE))
    try:
        yield browser
    finally:
        browser.close()


@contextlib.contextmanager
def open_page(browser, viewport=VIEWPORT):
    """A :class:`BrowserPage` in a fresh context of ``browser``; the context is always closed.

    A fresh context per page: no cache, storage or route of an earlier test
    leaks into this one. Service workers are blocked, as they could fetch
    past the page's routes.
    """
    context = browser.new_context(viewport=dict(viewport), service_workers="block")
    try:
        context.set_default_timeout(TIMEOUT_MS)
        yield BrowserPage(context)
    finally:
        context.close()


@contextlib.contextmanager
def headless_page(viewport=VIEWPORT):
    """A :class:`BrowserPage` in a browser of its own, for use outside pytest's fixtures."""
    with launch() as browser, open_page(browser, viewport) as result:
        yield result


def pixel_variance(png_bytes):
    """The variance of a picture's pixel values (0-255, mean over R, G, B).

    0 for a blank page; a drawn scene has shades and edges, so a test can
    tell a picture that shows something from one that shows nothing.
    """
    import numpy as np
    from PIL import Image

    with Image.open(io.BytesIO(png_bytes)) as image:
        pixels = np.asarray(image.convert("RGB"), dtype=np.float64)
    return float(pixels.reshape(-1, 3).var(axis=0).mean())
