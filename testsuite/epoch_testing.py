"""A small town drawn on two map sheets (1880, 1915), for the module tests of a dynamic
chain (on sys.path through the root conftest.py)."""

import shapely
from shapely.geometry import box

X0, Y0 = 84000.0, 446000.0
#: the 1915 sheet is georeferenced a little off the 1880 one
OFFSET = (0.8, -0.6)
#: the BAG id of the one current house aligned in 1880 (built 1700)
HOUSE = "0503100000000001"


def at(geom, dx=0.0, dy=0.0):
    return shapely.affinity.translate(geom, X0 + dx, Y0 + dy)


def plots_1880():
    return [box(0, 0, 60, 14), box(0, 30, 70, 58), box(100, 0, 160, 60), box(200, 0, 240, 14),
            box(200, 30, 240, 44), box(100, 80, 160, 94)]


def plots_1915():
    """Plot 1 unchanged, plot 2 split by a passage, plots 3, 5 and 6 unchanged, plot 4
    gone, a new plot; all drawn with the sheet's offset."""
    return [box(0, 0, 60, 14), box(0, 30, 33, 58), box(37, 30, 70, 58), box(100, 0, 160, 60),
            box(0, 80, 40, 94), box(200, 30, 240, 44), box(100, 80, 160, 94)]


#: later plot category -> its change since 1880, and the unchanged ones' earlier plot
CHANGES = {1: "unchanged", 2: "split", 3: "split", 4: "unchanged", 5: "new", 6: "unchanged",
           7: "unchanged"}
UNCHANGED = {1: 1, 4: 3, 6: 5, 7: 6}


def write_town(grassio, gs):
    """The region, both sheets' plots and the aligned house in the current mapset."""
    from reconstruction.core.contract import PLOT

    gs.run_command("g.region", n=Y0 + 120, s=Y0 - 10, e=X0 + 260, w=X0 - 10, res=1)
    grassio.write_features("plots_1880", [at(p) for p in plots_1880()], cats=[1, 2, 3, 4, 5, 6])
    grassio.write_features("plots_1915", [at(p, *OFFSET) for p in plots_1915()],
                           cats=[1, 2, 3, 4, 5, 6, 7])
    grassio.write_features("aligned_1880", [at(box(100, 0, 106, 12))],
                           {PLOT: [3], "identificatie": [HOUSE], "bouwjaar": [1700]})


def subdivide_town(gs):
    """The footprints of both sheets: fp_1880 (year=1880) and fp_1915 (previous=)."""
    gs.run_command("v.histo.subdivide", input="plots_1880", aligned="aligned_1880",
                   output="fp_1880", year=1880, seed=1, quiet=True)
    gs.run_command("v.histo.subdivide", input="plots_1915", output="fp_1915",
                   previous="fp_1880", previous_plots="plots_1880", year=1915, seed=2,
                   quiet=True)
