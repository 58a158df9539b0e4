"""The height intervals a building is written with hold the building as built
(issue 49, item 5): its ridge interval holds the top of its solid, whatever
roof it got, and a measured building's is its top exactly."""

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from shapely.geometry import Polygon, box

from reconstruction.lod2 import inputs as lod2_inputs
from reconstruction.lod2 import stage as lod2
from reconstruction.lod2.roofs.plan import ROOF_TYPES

X0, Y0 = 85000.0, 446000.0
NAMES = lod2_inputs.INTERVAL_ATTRIBUTES


def footprints(n, rng):
    """n footprints in a row: rectangles, trapezoids, squares and L shapes (concave:
    the straight skeleton's roofs)."""
    out = []
    for i in range(n):
        x, w, d = X0 + 25.0 * i, rng.uniform(5, 9), rng.uniform(10, 18)
        kind = i % 4
        if kind == 0:
            out.append(box(x, Y0, x + w, Y0 + d))
        elif kind == 1:
            out.append(Polygon([(x, Y0), (x + w, Y0 + 0.5), (x + w - 0.4, Y0 + d), (x, Y0 + d)]))
        elif kind == 2:
            out.append(box(x, Y0, x + w, Y0 + w * 1.1))
        else:
            out.append(Polygon([(x, Y0), (x + 2 * w, Y0), (x + 2 * w, Y0 + 6), (x + 6, Y0 + 6),
                                (x + 6, Y0 + d), (x, Y0 + d)]))
    return out


def build(types, eaves, attic, interval, ground, seed, source="measured"):
    """The Lod2Result of len(types) footprints of the heights and intervals given."""
    n = len(types)
    geoms = footprints(n, np.random.default_rng(seed))
    heights = lod2.Heights(np.asarray(eaves, float), np.asarray(attic, float),
                           np.asarray(ground, float))
    requests = lod2.RoofRequests(np.asarray(types, dtype=object), np.full(n, 1700.0))
    config = lod2.Lod2Config(seed=seed, nprocs=1)
    prepared = lod2.prepare(lod2.Footprints(geoms), heights, requests, config)
    prepared = lod2_inputs.with_height_source(prepared, np.full(n, source, dtype=object),
                                              interval)
    return lod2.build(prepared, config)


def tops(result):
    """The top of every built solid above its written ground (m), from its vertices."""
    return np.array([result.solids.solid(s)[0][:, 2].max() for s in range(len(result.solids))]) \
        - np.asarray(result.attributes["ground_height"], dtype=float)


def ends(result):
    return np.column_stack([np.asarray(result.attributes[k], dtype=float) for k in NAMES])


KINDS = ("measured", "inferred", "drawn")


@pytest.mark.parametrize("family", ROOF_TYPES + ("auto",))
@settings(max_examples=6, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(seed=st.integers(0, 2 ** 16), kind=st.sampled_from(KINDS),
       ground=st.floats(-5.0, 120.0), spread=st.floats(0.0, 4.0))
def test_the_ridge_interval_holds_the_built_top_of_every_roof_family(seed, kind, family,
                                                                     ground, spread):
    """Every family on rectangles, trapezoids, squares and L shapes, with
    measured heights (an interval of no width), inferred ones (an interval
    around them) or drawn ones (the ranges): the top of each solid lies in its
    ridge interval, the eaves in its eaves interval; a measured building's
    intervals are its heights as built, to the millimetre. Before, a flat roof
    on a measured building (top 8.875 m) kept the ridge interval of the roof
    it did not get (13.28-13.28 m), and a bell or neck gable's crown stood
    above its ridge interval."""
    rng = np.random.default_rng(seed)
    n = 8
    eaves = rng.uniform(3.0, 18.0, n)
    attic = np.where(rng.random(n) < 0.15, rng.uniform(0.0, 0.9, n), rng.uniform(1.0, 8.0, n))
    if kind == "measured":
        interval = np.column_stack([eaves, eaves, eaves + attic, eaves + attic])
    elif kind == "inferred":
        below, above = rng.uniform(0, spread, (n, 2)), rng.uniform(0, spread, (n, 2))
        interval = np.column_stack([eaves - below[:, 0], eaves + above[:, 0],
                                    eaves + attic - below[:, 1], eaves + attic + above[:, 1]])
    else:
        interval = np.tile([3.0, 18.0, 3.0, 26.0], (n, 1))
    result = build([family] * n, eaves, attic, interval, np.full(n, ground), seed)
    assert len(result.ids) == n
    got, top = ends(result), tops(result)
    built_eaves = np.asarray(result.attributes["eaves_height"], dtype=float)
    # to the millimetre of the solids' grid, and of floating point's subtraction
    assert np.all(got[:, 2] <= top + 1e-9) and np.all(top <= got[:, 3] + 1e-9), \
        (list(result.roof_types), got[:, 2:].tolist(), top.tolist())
    assert np.all(got[:, 0] <= built_eaves) and np.all(built_eaves <= got[:, 1])
    if kind == "measured":
        assert got[:, 2].tolist() == got[:, 3].tolist()
        assert got[:, 2] == pytest.approx(top, abs=1e-9)
        assert got[:, 0].tolist() == got[:, 1].tolist() == built_eaves.tolist()


def test_a_flat_roof_on_a_measured_building_has_the_ridge_of_its_eaves():
    """The issue's building: measured eaves 8.875 m and ridge 13.28 m, a flat
    roof drawn; its top is its eaves, and so is its ridge interval."""
    eaves, attic = np.array([8.875, 8.875]), np.array([4.405, 4.405])
    interval = np.column_stack([eaves, eaves, eaves + attic, eaves + attic])
    result = build(["flat", "gable"], eaves, attic, interval, np.array([1.2, 1.2]), 0)
    got = ends(result)
    assert got[0].tolist() == [8.875, 8.875, 8.875, 8.875]
    assert got[1].tolist() == [8.875, 8.875, 13.28, 13.28]
    assert tops(result) == pytest.approx([8.875, 13.28], abs=1e-6)


@pytest.mark.parametrize("family", ["neck", "bell", "spout", "stepped", "cornice"])
def test_a_gable_facade_above_its_ridge_raises_the_ridge_interval_by_its_crown(family):
    n = 4
    eaves, attic = np.full(n, 9.0), np.full(n, 4.0)
    interval = np.column_stack([eaves - 1, eaves + 1, eaves + attic - 1.5, eaves + attic + 0.5])
    result = build([family] * n, eaves, attic, interval, np.zeros(n), 3, source="neighbours")
    got, top = ends(result), tops(result)
    crown = top - np.where(result.roof_types == "flat", 9.0, 13.0)
    assert np.all(crown >= -1e-6)
    if family in ("neck", "bell"):
        assert crown.max() > 0.1          # the crown stands above the ridge
    assert got[:, 2] == pytest.approx(11.5 + crown, abs=6e-4)
    assert got[:, 3] == pytest.approx(np.maximum(13.5 + crown, top), abs=6e-4)


def test_built_intervals_keep_unknown_ends_unknown_and_round_outwards():
    interval = np.array([[np.nan, np.nan, np.nan, np.nan], [8.0, 9.0, 11.0, 12.0],
                         [8.0, 9.0, 11.0, 12.0]])
    got = lod2.built_intervals(interval, [8.5, 8.5, 8.5], [0.0, 3.0, 3.0],
                               [8.5, 11.5004, 13.2])
    assert np.isnan(got[0]).all()
    assert got[1].tolist() == [8.0, 9.0, 11.0, 12.0]
    assert lod2.built_intervals([[8.0, 9.0, 11.0, 11.5]], [8.5], [3.0], [11.5004])[0, 3] == 11.5004
    # a top 1.7 m above the ridge asked for (a crown): the interval moves with it
    assert got[2].tolist() == [8.0, 9.0, 12.7, 13.7]
