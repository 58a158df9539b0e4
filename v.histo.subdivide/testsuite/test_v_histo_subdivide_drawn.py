"""v.histo.subdivide map= in a temporary GRASS location: footprints that follow the lines
the map draws inside its plots (issue 50), and the errors of a bad map=."""

import numpy as np
import pytest
from shapely.geometry import box

from histo_testing import matched_share, run_module
from reconstruction.core.contract import SOURCE, SOURCE_DRAWN, SOURCE_PROCEDURAL

pytestmark = pytest.mark.grass

X0, Y0, CELL = 84000.0, 446000.0, 0.25
PINK, WHITE, LINE, OUTLINE = (236, 190, 180), (250, 248, 242), (60, 55, 55), (150, 45, 45)


def drawn_block():
    """A 40 x 20 m block outlined thick and cut into five parcels by thin lines (with
    a number over each), and an undivided block beside it, on 0.25 m cells."""
    rows, cols = 120, 280                       # 30 x 70 m
    rgb = np.full((rows, cols, 3), (232, 220, 190), float)
    rgb[20:100, 20:180] = PINK
    rgb[20:100, 100:140] = WHITE
    rgb[20:23, 20:180] = rgb[97:100, 20:180] = OUTLINE
    rgb[20:100, 20:23] = rgb[20:100, 177:180] = OUTLINE
    for c in (52, 100, 140, 160):
        rgb[23:97, c - 1:c + 1] = LINE
    for c in (36, 76, 120, 150, 170):
        rgb[55:63, c - 4:c + 4:2] = LINE        # a number: thin strokes
    rgb[20:100, 200:260] = PINK                # the second block: no inner line
    rgb[20:23, 200:260] = rgb[97:100, 200:260] = OUTLINE
    rgb[20:100, 200:203] = rgb[20:100, 257:260] = OUTLINE
    north = Y0 + rows * CELL

    def plot(c0, c1):
        return box(X0 + c0 * CELL, north - 100 * CELL, X0 + c1 * CELL, north - 20 * CELL)
    truth = [plot(a, b) for a, b in zip((20, 52, 100, 140, 160), (52, 100, 140, 160, 180))]
    return rgb.astype(np.uint8), [plot(20, 180), plot(200, 260)], truth, north


@pytest.fixture
def drawn_map(mapset):
    import grass.script as gs

    from reconstruction import grassio

    rgb, plots, truth, north = drawn_block()
    gs.run_command("g.region", n=north, s=Y0, w=X0, e=X0 + rgb.shape[1] * CELL, res=CELL)
    for i, band in enumerate(("red", "green", "blue")):
        grassio.write_raster("scan." + band, rgb[..., i].astype(np.int32))
    # a greyscale scan of it (issue 51, item 3): the mean of the three
    grassio.write_raster("scan.grey", np.rint(rgb.mean(axis=2)).astype(np.int32))
    grassio.write_features("plots", plots, cats=[1, 2])
    return gs, grassio, truth


@pytest.mark.parametrize("scan", ["scan.red,scan.green,scan.blue", "scan.grey"])
def test_the_drawn_parcels_are_the_footprints_and_say_so(drawn_map, scan):
    gs, grassio, truth = drawn_map
    code, _, err = run_module("v.histo.subdivide", input="plots", output="fp", seed=1, map=scan)
    assert code == 0, err
    assert "1 of 2 plots divided into 5 drawn footprints" in " ".join(err.split())
    geoms, columns = grassio.read_features("fp")
    drawn = [g for g, s in zip(geoms, columns[SOURCE]) if s == SOURCE_DRAWN]
    assert len(drawn) == 5
    for t in truth:
        assert max(g.intersection(t).area / g.union(t).area for g in drawn) > 0.9
    # the undivided block is subdivided as without map=
    generated = [p for p, s in zip(columns["plot"], columns[SOURCE]) if s == SOURCE_PROCEDURAL]
    assert generated and set(generated) == {2}
    assert run_module("v.histo.subdivide", input="plots", output="plain", seed=1)[0] == 0
    plain, plain_columns = grassio.read_features("plain")
    mine = sorted(round(g.area, 3) for g, p in zip(geoms, columns["plot"]) if p == 2)
    theirs = sorted(round(g.area, 3) for g, p in zip(plain, plain_columns["plot"]) if p == 2)
    assert mine == theirs


def test_flag_d_makes_an_undivided_plot_one_footprint(drawn_map):
    gs, grassio, _ = drawn_map
    code, _, err = run_module("v.histo.subdivide", flags="d", input="plots", output="fp",
                              map="scan.red,scan.green,scan.blue")
    assert code == 0, err
    geoms, columns = grassio.read_features("fp")
    assert columns[SOURCE] == [SOURCE_DRAWN] * 6
    assert "1 undivided plots one footprint each (-d)" in " ".join(err.split())


@pytest.mark.parametrize("options, message", [
    ({"map": "scan.red,scan.green"}, "map= needs one raster map (a greyscale scan) or three"),
    ({"map": "scan.red,scan.green,nothere"}, "nothere"),
    ({"map": "scan.red,scan.green,scan.blue", "stroke": "-1"}, "stroke"),
])
def test_a_bad_map_is_one_error_and_leaves_nothing(drawn_map, options, message):
    gs, grassio, _ = drawn_map
    code, _, err = run_module("v.histo.subdivide", input="plots", output="fp", **options)
    assert code != 0
    errors = [line for line in err.splitlines() if line.startswith("ERROR:")]
    assert len(errors) == 1 and message in errors[0] and "Traceback" not in err
    assert not gs.find_file("fp", element="vector")["name"]
    assert not gs.list_grouped("vector", pattern="tmp_histo_*")[gs.gisenv()["MAPSET"]]


@pytest.mark.parametrize("style, least", [("insurance", 0.95), ("cadaster", 0.97)])
def test_the_synthetic_styles_units_read_from_their_lines(mapset, style, least):
    # the chain's last steps on the synthetic styles' true blocks: every drawn
    # building (insurance) one footprint; the cadaster's parcels (whose lines stop
    # short of the outline at a third of their ends, one line in eight broken by a
    # gap) matched at 98 % on seed 1 (80 % before the line ends were drawn on;
    # the goal is 95 %): the test guards what is reached
    import synthetic_map as sm

    from reconstruction import grassio

    smap = sm.generate(seed=1, size=600, style=style)
    names = sm.write_map_to_grass(smap, "syn")
    code, _, err = run_module("v.histo.subdivide", flags="d", input=names["plots"], output="fp",
                              map=",".join(names[b] for b in ("red", "green", "blue")))
    assert code == 0, err
    geoms, columns = grassio.read_features("fp")
    assert set(columns[SOURCE]) == {SOURCE_DRAWN}
    assert matched_share([single(g) for g in geoms], smap.parcels) >= least


def single(geom):
    return geom.geoms[0] if geom.geom_type == "MultiPolygon" and len(geom.geoms) == 1 else geom
