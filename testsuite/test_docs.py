"""The README and the manual pages show what there is.

Every picture they show is in the repository, and the README tutorial's
commands are those demo/chain.sh runs (what the demo prints is checked
against the tutorial by test_demo.py).

The README's tutorial shows one picture per stage of the demo (docs/img/);
each module's manual page shows pictures from its own folder, which GRASS's
Make system installs beside the page (every *.png of the folder), so that
g.manual shows them. No GRASS needed, except for the check of the staged
manuals (skipped when the suite is not built).
"""

import os
import re

import pytest

import readme_tutorial

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DIST = os.environ.get("HISTO_DIST", os.path.join(ROOT, "dist"))
MODULES = ("r.histo.classify", "v.histo.generalize", "v.histo.align", "v.histo.subdivide",
           "v.histo.lod2")
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