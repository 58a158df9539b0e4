#!/usr/bin/env python3
"""Pictures of the man page: synthetic plots of each case and their footprints.

Run inside a GRASS session with the suite on the module path, e.g.:

    grass --tmp-location EPSG:28992 --exec python3 v.histo.subdivide/make_pictures.py

Writes ``v_histo_subdivide_case<N>.png`` (N = 1..5) and
``v_histo_subdivide_aligned.png`` next to this script. The plots are made up
here (no reference data).
"""

import os
import sys

import grass.script as gs
from shapely import affinity
from shapely.geometry import Polygon, box

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
X0, Y0 = 84000.0, 446000.0

CASES = {
    1: Polygon([(0, 0), (10, 0), (10, 5), (5, 5), (5, 9), (0, 9)]),
    2: box(20, 0, 110, 11),
    3: box(20, 30, 110, 58),
    4: Polygon([(140, 0), (230, 0), (230, 55), (190, 72), (140, 60)]),
    5: Polygon([(0, 80), (95, 80), (95, 110), (32, 110), (32, 175), (0, 175)]),
}
ALIGNED_PLOT = box(120, 90, 230, 104)
ALIGNED = [box(150, 90, 157, 103), box(157, 90, 163.5, 104), box(190, 90, 199, 102)]


def render(name, bounds, layers, width=480):
    w, s, e, n = bounds
    margin = 0.08 * max(e - w, n - s)
    height = int(min(360, max(150, width * (n - s + 3.5 * margin) / (e - w + 2 * margin))))
    for kwargs in layers:
        if kwargs.get("module") == "d.text":
            kwargs["size"] = kwargs["size"] * 300.0 / height
    gs.run_command("g.region", w=w - margin, e=e + margin, s=s - margin, n=n + 2.5 * margin,
                   res=0.5)
    env = dict(os.environ, GRASS_RENDER_IMMEDIATE="cairo", GRASS_RENDER_WIDTH=str(width),
               GRASS_RENDER_HEIGHT=str(height), GRASS_RENDER_FILE=os.path.join(HERE, name),
               GRASS_RENDER_TRANSPARENT="FALSE", GRASS_RENDER_FILE_READ="TRUE")
    if os.path.exists(env["GRASS_RENDER_FILE"]):
        os.remove(env["GRASS_RENDER_FILE"])
    gs.run_command("d.erase", bgcolor="white", env=env)
    for kwargs in layers:
        module = kwargs.pop("module", "d.vect")
        gs.run_command(module, env=env, quiet=True, **kwargs)


def main():
    from reconstruction import grassio

    gs.run_command("g.region", n=Y0 + 200, s=Y0 - 10, e=X0 + 250, w=X0 - 10, res=1)
    plots = [affinity.translate(p, X0, Y0) for p in CASES.values()]
    grassio.write_features("plots", plots, cats=list(CASES))
    gs.run_command("v.histo.subdivide", input="plots", output="footprints", seed=1,
                   overwrite=True, quiet=True)
    for case, plot in CASES.items():
        b = affinity.translate(plot, X0, Y0).bounds
        render("v_histo_subdivide_case{}.png".format(case), (b[0], b[1], b[2], b[3]), [
            dict(map="footprints", type="area", flags="c", width=1, color="black",
                 where="plot = {}".format(case)),
            dict(map="plots", type="area", fill_color="none", color="black", width=3,
                 where="cat = {}".format(case)),
            dict(module="d.text", text="case {}".format(case), at="2,93", size=6, color="black"),
        ])
    aligned_plot = affinity.translate(ALIGNED_PLOT, X0, Y0)
    grassio.write_features("row", [aligned_plot], cats=[1])
    grassio.write_features("aligned", [affinity.translate(a, X0, Y0) for a in ALIGNED],
                           {"plot": [1, 1, 1]})
    gs.run_command("v.histo.subdivide", input="row", aligned="aligned", output="row_fp",
                   area_threshold=100, seed=1, overwrite=True, quiet=True)
    render("v_histo_subdivide_aligned.png", aligned_plot.bounds, [
        dict(map="row_fp", type="area", flags="c", width=1, color="black",
             where="source = '2pm'"),
        dict(map="row_fp", type="area", fill_color="40:40:40", color="black", width=2,
             where="source = 'aligned'"),
        dict(map="row", type="area", fill_color="none", color="black", width=3),
        dict(module="d.text", text="aligned footprints (black) kept", at="2,85", size=7,
             color="black"),
    ], width=560)


if __name__ == "__main__":
    main()
