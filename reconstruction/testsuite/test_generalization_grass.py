"""Generalised plots read back valid through GRASS and v.out.ogr (issue 13), in a GRASS location."""

import json
import subprocess

import pytest
import shapely
from shapely.geometry import Polygon, box, shape

from reconstruction.generalization import generalize_plots

pytestmark = pytest.mark.grass

X, Y = 84000.0, 446000.0


def touching_plots():
    """A hole touching the outline at a vertex, two holes touching each other,
    and two plots touching at one corner."""
    hole_on_outline = Polygon([(X, Y), (X + 40, Y), (X + 40, Y + 40), (X, Y + 40)],
                              [[(X + 40, Y + 20), (X + 20, Y + 10), (X + 20, Y + 30)]])
    two_holes = Polygon([(X + 50, Y), (X + 90, Y), (X + 90, Y + 40), (X + 50, Y + 40)],
                        [[(X + 60, Y + 10), (X + 70, Y + 20), (X + 60, Y + 30)],
                         [(X + 70, Y + 20), (X + 80, Y + 10), (X + 80, Y + 30)]])
    return [hole_on_outline, two_holes, box(X, Y + 50, X + 20, Y + 70),
            box(X + 20, Y + 70, X + 40, Y + 90)]


def test_holes_kept_off_the_outline_and_each_other():
    plots = generalize_plots(touching_plots(), methods=("simplify",), tolerance=0.01).plots
    for plot in plots:
        assert plot.is_valid
        rings = [plot.exterior, *plot.interiors]
        for k, hole in enumerate(plot.interiors):
            assert all(Polygon(hole).distance(r) >= 0.0099 for j, r in enumerate(rings)
                       if j != k + 1)
    assert [len(p.interiors) for p in plots] == [1, 2, 0, 0]
    # the hole shrinks by 1 cm all round: its perimeter times 1 cm
    assert plots[0].area == pytest.approx(touching_plots()[0].area, abs=0.7)


def test_generalised_plots_read_back_valid_through_v_out_ogr(mapset, tmp_path):
    import grass.script as gs

    from reconstruction import grassio

    gs.run_command("g.region", n=Y + 100, s=Y, e=X + 100, w=X, res=1)
    plots = generalize_plots(touching_plots(), methods=("simplify",), tolerance=0.01).plots
    grassio.write_features("plots", plots)
    gpkg, geojson = str(tmp_path / "plots.gpkg"), str(tmp_path / "plots.geojson")
    gs.run_command("v.out.ogr", input="plots", output=gpkg, format="GPKG", quiet=True)
    subprocess.run(["ogr2ogr", "-f", "GeoJSON", geojson, gpkg], check=True)
    exported = [shape(f["geometry"]) for f in json.load(open(geojson))["features"]]
    assert len(exported) == 4
    assert [shapely.is_valid_reason(g) for g in exported] == ["Valid Geometry"] * 4
    read, _ = grassio.read_features("plots")
    assert all(g.is_valid for g in read)
    # as written without the 1 cm: GRASS's self-touching rings
    grassio.write_features("raw", touching_plots())
    raw, _ = grassio.read_features("raw")
    assert sum(not g.is_valid for g in raw) == 2
