"""No generated footprint has a corner under 20 degrees where its plot has
none (the "wedge" invariant, issue 33, item 6), on the plot shapes that make
them: thin triangles, plots with a sharp corner, plots cut near a vertex,
and generated footprints clipped by an aligned footprint at a shallow angle."""

import math

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from shapely import affinity
from shapely.geometry import Polygon, box

from reconstruction.core.contract import SOURCE_PROCEDURAL
from reconstruction.subdivide import stage as sd
from reconstruction.subdivide.convex_rings import MIN_ANGLE, ccw_ring, corner_angles


def violations(plots, seed, aligned=None, decompose=True):
    """The invariant violations of the subdivision of ``plots`` (the concave
    ones only with ``decompose``)."""
    res = sd.subdivide(plots, seed=seed, decompose=decompose, aligned=aligned,
                       area_threshold=100, length=(5, 9), depth=(10, 15))
    cats, prepared, _ = sd.prepare_plots(plots, list(range(1, len(plots) + 1)))
    bad = sd.invariant_violations(res.geometries, res.plot, res.source,
                                  dict(zip(cats, prepared)), res.case)
    if not decompose:
        bad.pop("concave", None)
    return res, bad


def test_a_footprint_clipped_at_a_shallow_angle_is_cut_square():
    """A row of a 52 x 13.6 m plot crossed by an aligned building turned by
    18.6 degrees to its cuts: the clipped footprint was a right triangle with
    an 18.6 degree corner (found by the search below)."""
    plot = box(0, 0, 52.03087029155016, 13.560232226989688)
    aligned = Polygon([(32.94881492301026, 0.1731398729611385),
                       (26.97346512633157, 17.906267381244266),
                       (-0.9831848663174925, 8.486002243503412),
                       (4.9921649303611995, -9.247125264779717)])
    res, bad = violations([plot], 23, [aligned])
    assert bad == {}
    assert res.report.generated_clipped >= 1
    for g, source in zip(res.geometries, res.source):
        if source == SOURCE_PROCEDURAL:
            assert min(corner_angles(ccw_ring(g.exterior.coords))) >= MIN_ANGLE - 1e-6


def turned(polygon, angle, x=100.0, y=100.0):
    """``polygon`` turned by ``angle`` degrees and moved to (x, y)."""
    return affinity.translate(affinity.rotate(polygon, angle, origin=(0, 0)), x, y)



def test_an_aligned_corner_on_a_footprints_edge_leaves_no_notch():
    """An aligned building whose corner lies on the street edge of a
    generated footprint, its side crossing the plot's corner 5 cm from it
    (found by the search below): the clipped footprint kept a 5 cm notch
    whose tip touched that edge, which the convex decomposition could not
    cut, and was concave."""
    plot = turned(box(0, 0, 30, 10), 1.0)
    aligned = turned(Polygon([(1.314, 5.992), (-1.682, 6.149), (-1.996, 0.157), (1, 0)]), 1.0)
    res, bad = violations([plot], 0, [aligned])
    assert bad == {}
    assert res.report.generated_clipped >= 1

@st.composite
def thin_triangle(draw):
    """A triangular plot with a corner of 5 to 40 degrees, 20 to 150 m long."""
    length = draw(st.floats(20, 150))
    corner = math.radians(draw(st.floats(5, 40)))
    apex = draw(st.floats(0.0, 1.2))
    height = length * math.tan(corner) * draw(st.floats(0.3, 1.0))
    return Polygon([(0, 0), (length, 0), (apex * length, height)])


@st.composite
def sharp_cornered(draw):
    """A quadrilateral plot, one corner of 5 to 35 degrees, 8 to 40 m deep."""
    length, deep = draw(st.floats(30, 150)), draw(st.floats(8, 40))
    corner = math.radians(draw(st.floats(5, 35)))
    return Polygon([(0, 0), (length, 0), (length + draw(st.floats(-10, 10)), deep),
                    (deep / math.tan(corner), deep)])


@st.composite
def cut_near_a_vertex(draw):
    """A rectangular plot with a corner cut off a few centimetres to 3 m from it."""
    length, deep = draw(st.floats(30, 120)), draw(st.floats(15, 60))
    cut = draw(st.floats(0.05, 3.0))
    return Polygon([(0, 0), (length, 0), (length, deep - cut),
                    (length - cut * draw(st.floats(0.5, 5.0)), deep), (0, deep)])


@st.composite
def shallow_aligned(draw):
    """A row plot with 1 to 3 aligned buildings whose sides cross the row at
    3 to 25 degrees off its cuts or its street."""
    length, deep = draw(st.floats(30, 80)), draw(st.floats(10, 15))
    aligned = []
    for _ in range(draw(st.integers(1, 3))):
        x = draw(st.floats(0, length))
        width, below, top = draw(st.floats(6, 30)), draw(st.floats(3, 15)), draw(st.floats(0, deep))
        angle = draw(st.floats(3, 25)) * draw(st.sampled_from([-1, 1])) + draw(
            st.sampled_from([0, 90]))
        aligned.append(affinity.rotate(box(x, top - below, x + width, top), angle, origin=(x, 0)))
    return box(0, 0, length, deep), aligned


sharp_plots = st.one_of(thin_triangle(), sharp_cornered(), cut_near_a_vertex())


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(plot=sharp_plots, angle=st.floats(0, 360), seed=st.integers(0, 1000),
       decompose=st.booleans())
def test_no_wedges_on_sharp_plots(plot, angle, seed, decompose):
    plots = [turned(plot, angle)]
    if not plots[0].is_valid or plots[0].area < 1:
        return
    _, bad = violations(plots, seed, decompose=decompose)
    assert bad == {}


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(row=shallow_aligned(), angle=st.floats(0, 360), seed=st.integers(0, 1000))
def test_no_wedges_where_aligned_footprints_clip_generated_ones(row, angle, seed):
    plot, aligned = row
    _, bad = violations([turned(plot, angle)], seed, [turned(a, angle) for a in aligned])
    assert bad == {}
