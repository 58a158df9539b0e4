"""Generalised plots read back valid through GRASS and v.out.ogr (issue 13), in a GRASS location."""

import itertools
import json
import os
import subprocess

import numpy as np
import pytest
import shapely
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from shapely import affinity
from shapely.geometry import Polygon, box, shape

from reconstruction.generalize.operators import generalize_plots

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


# ---------------------------------------------------------------------------
# The round trip as a property: random plots whose holes and neighbours touch
# ---------------------------------------------------------------------------

def _inward_triangle(apex, inward, depth, spread):
    """A triangle with one vertex at ``apex``, pointing into the plot along ``inward``."""
    inward = np.asarray(inward, dtype=float) / np.hypot(*inward)
    across = np.array([-inward[1], inward[0]])
    base = np.asarray(apex) + depth * inward
    return [tuple(apex), tuple(base + spread * across), tuple(base - spread * across)]


def _through(ring, point):
    """The ring with ``point`` inserted as a vertex on the edge it lies on: rotated, a
    vertex on an edge would move off it by rounding, a shared vertex stays shared."""
    ring = [tuple(map(float, c)) for c in ring]
    p = shapely.Point(point)
    for k in range(len(ring)):
        a, b = ring[k], ring[(k + 1) % len(ring)]
        if p.distance(shapely.LineString([a, b])) < 1e-9 and p.distance(shapely.Point(a)) > 1e-9 \
                and p.distance(shapely.Point(b)) > 1e-9:
            return ring[:k + 1] + [tuple(map(float, point))] + ring[k + 1:]
    return ring


@st.composite
def hole_on_outline(draw, shared):
    """A plot with a hole touching its outline at one point: on an edge or at a corner
    (``shared``: the point a vertex of the outline too)."""
    w, h = draw(st.floats(25, 60)), draw(st.floats(25, 60))
    side, t = draw(st.integers(0, 3)), draw(st.sampled_from([0.0, 0.3, 0.5, 0.77]))
    corners = [(0, 0), (w, 0), (w, h), (0, h)]
    a, b = np.array(corners[side], float), np.array(corners[(side + 1) % 4], float)
    apex = a + t * (b - a)
    # into the plot: perpendicular to the edge, or halving the corner's right angle
    inward = np.sign(np.array([w / 2, h / 2]) - apex) if t == 0.0 else \
        np.array([-(b - a)[1], (b - a)[0]])
    depth = draw(st.floats(4, min(w, h) / 2 - 2))
    spread = draw(st.floats(1.5, 6))
    if t == 0.0:  # inside the corner's right angle
        spread = min(spread, 0.7 * depth)
    else:  # off the edge's ends
        spread = min(spread, 0.8 * min(t, 1 - t) * np.hypot(*(b - a)))
    hole = _inward_triangle(apex, inward, depth, spread)
    return Polygon(_through(corners, apex) if shared else corners, [hole])


@st.composite
def holes_touching(draw, shared):
    """A plot with two holes touching at one point: vertex to vertex, or a vertex of one
    on an edge of the other (``shared``: a vertex of both)."""
    w, h = draw(st.floats(30, 60)), draw(st.floats(30, 60))
    q = np.array([draw(st.floats(0.4, 0.6)) * w, draw(st.floats(0.4, 0.6)) * h])
    # a vertex exactly on an edge that is not shared: an axis-parallel edge
    angle = draw(st.floats(0, 180) if shared else st.sampled_from([0.0, 90.0, 180.0]))
    d = np.array([np.cos(np.radians(angle)), np.sin(np.radians(angle))])
    room = min(w, h) * 0.15  # two holes one behind the other stay inside
    first = _inward_triangle(q, -d, draw(st.floats(3, room)), draw(st.floats(1.5, room / 2)))
    if draw(st.booleans()):
        second = _inward_triangle(q, d, draw(st.floats(3, room)), draw(st.floats(1.5, room / 2)))
    else:
        far = (np.asarray(first[1]) + np.asarray(first[2])) / 2
        second = _inward_triangle(far, -d, draw(st.floats(3, room)),
                                  draw(st.floats(1.5, room / 2)))
        if shared:
            first = _through(first, far)
    return Polygon([(0, 0), (w, 0), (w, h), (0, h)], [first, second])


@st.composite
def plots_touching(draw, shared):
    """Two plots touching at one point: corner to corner, or a corner on an edge."""
    x1, y1 = draw(st.floats(15, 40)), draw(st.floats(15, 40))
    a = [(0, 0), (x1, 0), (x1, y1), (0, y1)]
    w, h = draw(st.floats(15, 40)), draw(st.floats(15, 40))
    if draw(st.booleans()):
        b = box(x1, y1, x1 + w, y1 + h)
    else:
        # a square standing on one corner on a's top edge
        cx, r = draw(st.floats(0.3, 0.7)) * x1, w / 2
        b = Polygon([(cx, y1), (cx + r, y1 + r), (cx, y1 + 2 * r), (cx - r, y1 + r)])
        if shared:
            a = _through(a, (cx, y1))
    return [Polygon(a), b]


@st.composite
def touching_scenes(draw):
    """The three kinds side by side, maybe rotated, placed in the location."""
    angle = draw(st.sampled_from([0.0, 17.0, 45.0, 90.0]))
    shared = angle != 0 or draw(st.booleans())
    plots = [draw(hole_on_outline(shared)), draw(holes_touching(shared)),
             *draw(plots_touching(shared))]
    placed = [affinity.translate(p, dx) for p, dx in zip(plots, (0, 100, 200, 200))]
    return [affinity.translate(affinity.rotate(p, angle, origin=(0, 0)), X + 150, Y + 150)
            for p in placed]


_names = itertools.count()


@settings(max_examples=6, deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])
@given(scene=touching_scenes(), methods=st.sampled_from([("simplify",), ("douglas",)]))
def test_round_trip_property_every_plot_valid_after_v_out_ogr(mapset, tmp_path, scene,
                                                                methods):
    """Issue 13 item 1: whatever the holes and neighbours touch, every plot that
    v.histo.generalize writes (its library call, then grassio.write_features as in its
    main()) reads back valid through v.out.ogr and through grassio."""
    import grass.script as gs

    from reconstruction import generalize
    from reconstruction import grassio

    assert all(p.is_valid for p in scene)
    gs.run_command("g.region", n=Y + 500, s=Y - 200, e=X + 600, w=X - 200, res=1)
    config = generalize.GeneralizeConfig(methods=methods, tolerance=0.01, min_area=1)
    raw = generalize.raw_plots(scene, config.min_area, "scene")
    result = generalize.generalize_map(raw, config)
    name = "plots_{}".format(next(_names))
    grassio.write_features(name, result.plots, result.columns)
    path = str(tmp_path / "{}.geojson".format(name))
    gs.run_command("v.out.ogr", input=name, output=path, format="GeoJSON", quiet=True,
                   stderr=subprocess.DEVNULL)  # "features without category": the holes
    exported = [shape(f["geometry"]) for f in json.load(open(path))["features"]]
    os.remove(path)
    assert len(exported) == len(scene)
    assert [shapely.is_valid_reason(g) for g in exported] == ["Valid Geometry"] * len(scene)
    read, _ = grassio.read_features(name)
    assert len(read) == len(scene) and all(g.is_valid for g in read)
    gs.run_command("g.remove", type="vector", name=name, flags="f", quiet=True)
