"""The README tutorial's pictures (docs/img/) from the outputs of `make demo`.

    make demo && python3 docs/img/update.py demo-output

The demo writes one picture per stage of the synthetic map (demo/pictures.sh,
600 x 600 pixels, and v.histo.lod2's 3D view model.png, 1600 x 1200); this
copies them here made small: 32 colours (the map's scan noise otherwise
weighs 700 kB a picture), the 3D view cropped to the model and scaled to
600 pixels wide; and the web page city.html (v.histo.lod2 viewer=) as
headless chromium shows it, a house clicked (city.png; testsuite/browser.py,
which `make build` sets up). Only pictures of the synthetic map belong here,
never of the shared real maps.
"""

import io
import os
import sys

import numpy as np
from PIL import Image

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "testsuite"))
STAGES = ("map.png", "classes.png", "plots.png", "aligned.png", "footprints.png")
WIDTH = 600
COLOURS = 32


def small(image):
    """The picture in at most COLOURS colours, without dithering."""
    return image.convert("RGB").quantize(colors=COLOURS, method=Image.Quantize.MEDIANCUT,
                                         dither=Image.Dither.NONE)


def crop_to_content(image, margin=10):
    """The picture cut to what differs from its background (the corner's colour)."""
    pixels = np.asarray(image.convert("RGB")).astype(int)
    rows, cols = np.nonzero(np.abs(pixels - pixels[0, 0]).sum(axis=2) > 12)
    box = (max(cols.min() - margin, 0), max(rows.min() - margin, 0),
           min(cols.max() + margin + 1, pixels.shape[1]),
           min(rows.max() + margin + 1, pixels.shape[0]))
    return image.crop(box)


def main(demo_dir):
    for name in STAGES:
        small(Image.open(os.path.join(demo_dir, name))).save(os.path.join(HERE, name),
                                                             optimize=True)
    model = crop_to_content(Image.open(os.path.join(demo_dir, "model.png")))
    height = round(model.height * WIDTH / model.width)
    model = model.convert("RGB").resize((WIDTH, height), Image.Resampling.LANCZOS)
    small(model).save(os.path.join(HERE, "model.png"), optimize=True)
    viewer(os.path.join(demo_dir, "city.html"), os.path.join(HERE, "city.png"))
    for name in STAGES + ("model.png", "city.png"):
        print("{}: {} bytes".format(os.path.join(HERE, name),
                                    os.path.getsize(os.path.join(HERE, name))))


def viewer(page_path, png_path, width=800, height=560):
    """The viewer's page as a browser shows it, the tallest building clicked."""
    import json

    from browser import headless_page

    with headless_page({"width": width, "height": height}) as view:
        view.open(page_path)
        view.wait_ready("window.histo && window.histo.ready === true")
        page = view.page
        ids = page.evaluate("Object.keys(histo)") and page.evaluate(
            "JSON.parse(document.getElementById('histo-meta').textContent).ids")
        attributes = page.evaluate(
            "JSON.parse(document.getElementById('histo-meta').textContent).attributes")
        tallest = max(range(len(ids)), key=lambda i: attributes[i].get("eaves_height", 0))
        x, y = page.evaluate("histo.screenPosition({})".format(json.dumps(ids[tallest])))
        page.mouse.click(x, y)
        image = Image.open(io.BytesIO(view.screenshot()))
    small(image).save(png_path, optimize=True)


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else "demo-output"))
