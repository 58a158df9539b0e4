"""The README and the manual pages show what there is.

Every picture they show is in the repository, and the README tutorial's
commands are those demo/chain.sh runs (what the demo prints is checked
against the tutorial by test_demo.py).

The README's tutorial shows one picture per stage of the demo (docs/img/);
each module's manual page shows pictures from its own folder, which GRASS's
Make system installs beside the page (every *.png of the folder), so that
g.manual shows them. The man versions of the pages that GRASS's Make system
builds into dist/docs/man/man1 are plain ASCII, and `g.manual -m` shows
each as text, without byte escapes, in a GRASS session whose locale is not
generated (GRASS sets LANG=en_US; a Debian minbase has no such locale).
No GRASS needed, except for the checks of the staged manuals (skipped when
the suite is not built).
"""

import html as html_entities
import os
import re
import shutil
import subprocess

import pytest

import readme_tutorial

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DIST = os.environ.get("HISTO_DIST", os.path.join(ROOT, "dist"))
MODULES = ("r.histo.classify", "v.histo.generalize", "v.histo.align", "v.histo.subdivide",
           "v.histo.lod2", "v.histo.timeline")
PAGES = MODULES + ("histo",)
TUTORIAL = ("map.png", "classes.png", "plots.png", "aligned.png", "footprints.png", "model.png")


def _read(*path):
    with open(os.path.join(ROOT, *path), encoding="utf-8") as f:
        return f.read()


def _html_images(text):
    return re.findall(r'<img\s[^>]*src="([^"]+)"', text)


def _markdown_images(text):
    return re.findall(r"!\[[^\]]*\]\(([^)\s]+)\)", text) + _html_images(text)


def test_every_readme_picture_exists():
    images = _markdown_images(_read("README.md"))
    assert images
    missing = [p for p in images if not os.path.isfile(os.path.join(ROOT, p))]
    assert not missing, missing


def test_readme_tutorial_shows_one_picture_per_stage():
    images = _markdown_images(_read("README.md"))
    for name in TUTORIAL:
        assert "docs/img/" + name in images, name
        with open(os.path.join(ROOT, "docs", "img", name), "rb") as f:
            data = f.read()
        assert data[:8] == b"\x89PNG\r\n\x1a\n", name
        assert len(data) < 400_000, name + ": keep the repository's pictures small"


@pytest.mark.parametrize("module", MODULES)
def test_every_manual_picture_exists(module):
    page = _read(module, module + ".html")
    images = _html_images(page)
    assert images, module + ": no picture"
    for src in images:
        # installed beside the page: a plain file name of the module's folder
        assert "/" not in src, src
        assert src.startswith(module.replace(".", "_") + "_") and src.endswith(".png"), src
        assert os.path.isfile(os.path.join(ROOT, module, src)), src
    assert "<h2>EXAMPLES</h2>" in page


@pytest.mark.parametrize("module", MODULES)
def test_manual_pictures_are_installed(module):
    html = os.path.join(DIST, "docs", "html")
    if not os.path.isfile(os.path.join(html, module + ".html")):
        pytest.skip("the suite is not built in dist/ (run `make build`)")
    with open(os.path.join(html, module + ".html"), encoding="utf-8") as f:
        installed = _html_images(f.read())
    # the page's own pictures (the others, e.g. grass_logo.png, are GRASS's)
    for src in _html_images(_read(module, module + ".html")):
        assert src in installed, src
        assert os.path.isfile(os.path.join(html, src)), src


def test_readme_tutorial_commands_are_the_chains():
    """Each command of the tutorial's stages that is not one of the suite's
    modules (those run in demo/steps.sh, and test_demo compares them with
    what the demo ran) is one demo/chain.sh runs, in that order."""
    commands = [c for c in readme_tutorial.stage_commands()
                if not re.match(r"[rv]\.histo\.", c)]
    chain = readme_tutorial.chain_commands()
    assert len(commands) >= 2
    assert len(readme_tutorial.module_commands()) == 5
    missing = [c for c in commands if c not in chain]
    assert not missing, missing
    assert [chain.index(c) for c in commands] == sorted(chain.index(c) for c in commands)
    # and the picture of each stage is drawn by the chain
    assert 'stage_pictures "$OUT" map 600' in chain


def _built_man_page(page):
    path = os.path.join(DIST, "docs", "man", "man1", page + ".1")
    if not os.path.isfile(path):
        pytest.skip("the suite is not built in dist/ (run `make build`)")
    with open(path, "rb") as f:
        return f.read()


@pytest.mark.parametrize("page", PAGES)
def test_built_man_page_is_ascii(page):
    """Every character of the page ASCII, and groff told to draw its own
    hyphens, quotes and bullets in ASCII on a UTF-8 terminal
    (tools/html2man.py): otherwise man, unable to set an ungenerated locale,
    shows them through col as `\\xe2\\x80\\x99`."""
    text = _built_man_page(page).decode("utf-8")
    outside = sorted({c for c in text if not c.isascii()})
    assert not outside, outside
    assert text.startswith(".TH " + page + " 1 ")
    for request in ("char \\[hy] \\N'45'", "shc \\N'45'", "char \\[cq] \\N'39'",
                    "char \\[bu] \\N'42'"):
        assert request in text, request


@pytest.fixture(scope="module")
def unset_locale_session(tmp_path_factory):
    """A new GRASS location and the environment of a fresh Debian minbase's
    root: no LANG, LANGUAGE or LC_* at all, so that GRASS's start-up sets
    its own (LANG=en_US, LC_CTYPE=en_US.UTF-8), generated or not."""
    if not shutil.which("grass"):
        pytest.skip("GRASS GIS is not installed (run the tests through `make test`)")
    if not shutil.which("man"):
        pytest.skip("man is not installed (make deps installs man-db)")
    if not os.path.isdir(os.path.join(DIST, "docs", "man", "man1")):
        pytest.skip("the suite is not built in dist/ (run `make build`)")
    env = {k: v for k, v in os.environ.items()
           if not (k.startswith("LC_") or k in ("LANG", "LANGUAGE", "GISRC"))}
    env.update(GRASS_ADDON_BASE=DIST, MANPAGER="cat", PAGER="cat", MANWIDTH="80")
    location = str(tmp_path_factory.mktemp("manual") / "loc")
    made = subprocess.run(["grass", "-c", "EPSG:28992", location, "-e"], env=env,
                          capture_output=True, text=True)
    assert made.returncode == 0, made.stderr
    return {"env": env, "mapset": os.path.join(location, "PERMANENT")}


def _first_sentence_words(page):
    """The words (letters only, four or more) of the first sentence of the
    page's DESCRIPTION, as a reader sees them."""
    source = _read(page, page + ".html") if page != "histo" else _read("histo.html")
    description = source.split("<h2>DESCRIPTION</h2>", 1)[1]
    text = html_entities.unescape(re.sub(r"<[^>]+>", " ", description))
    sentence = re.split(r"[.:;]\s", " ".join(text.split()), 1)[0]
    return [w for w in re.findall(r"[A-Za-z]+", sentence) if len(w) >= 4]


@pytest.mark.parametrize("page", PAGES)
def test_g_manual_text_readable_in_an_ungenerated_locale(unset_locale_session, page):
    """`g.manual -m` prints the page as ASCII text, no `\\x` escapes; man's
    own warning that it cannot set the locale (stderr, when en_US.UTF-8 is
    not generated) is man's and not the suite's to silence."""
    session = unset_locale_session
    out = subprocess.run(["grass", session["mapset"], "--exec", "g.manual", "-m", page],
                         env=session["env"], capture_output=True)
    assert out.returncode == 0, out.stderr.decode(errors="replace")[-2000:]
    text = out.stdout.decode("utf-8", errors="backslashreplace")
    assert text.isascii(), sorted({c for c in text if not c.isascii()})
    assert "\\x" not in text, [line for line in text.splitlines() if "\\x" in line][:5]
    assert "NAME" in text and page in text
    # the text, not only the heading: the description's first sentence,
    # hyphenated words at line ends joined again
    words = set(re.findall(r"[A-Za-z]+", re.sub(r"-\n\s*", "", text)))
    missing = [w for w in _first_sentence_words(page) if w not in words]
    assert _first_sentence_words(page) and not missing, missing
