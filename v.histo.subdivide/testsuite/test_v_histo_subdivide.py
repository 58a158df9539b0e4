"""v.histo.subdivide in a temporary GRASS location: options, round trip, bad input, acceptance."""

import os
import re

import numpy as np
import pytest
import shapely
from shapely.geometry import Polygon, box

from reconstruction.core.contract import AREA, CASE, PLOT, SOURCE, SOURCE_ALIGNED, SOURCE_PROCEDURAL

pytestmark = pytest.mark.grass

X0, Y0 = 84000.0, 446000.0


def synthetic_plots():
    """One plot per case, in RD New metres (case 5: an L; plus two overlapping plots)."""
    plots = [
        box(0, 0, 9, 9),  # case 1
        box(20, 0, 120, 11),  # case 2
        box(20, 30, 120, 58),  # case 3
        box(140, 0, 220, 60),  # case 4
        Polygon([(0, 80), (90, 80), (90, 110), (30, 110), (30, 170), (0, 170)]),  # case 5
        box(140, 80, 200, 112),  # overlaps the next one
        box(195, 80, 240, 112),
    ]
    return [shapely.affinity.translate(p, X0, Y0) for p in plots]


@pytest.fixture
def tools(mapset):
    import grass.script as gs

    from reconstruction import grassio
    from reconstruction.subdivide import stage as subdivision

    gs.run_command("g.region", n=Y0 + 200, s=Y0 - 10, e=X0 + 250, w=X0 - 10, res=1)
    grassio.write_features("plots", synthetic_plots(), cats=[11, 12, 13, 14, 15, 16, 17])
    return gs, grassio, subdivision


def single(geom):
    """v.out.ogr -m writes multipolygons: one part is one polygon."""
    if geom is not None and geom.geom_type == "MultiPolygon" and len(geom.geoms) == 1:
        return geom.geoms[0]
    return geom


def read_output(grassio, name):
    geoms, columns = grassio.read_features(name)
    order = np.argsort(columns["cat"])
    return [single(geoms[i]) for i in order], {k: [v[i] for i in order] for k, v in columns.items()}


def check_round_trip(gs, grassio, subdivision, output, plots_name):
    """Invariants on the footprints as GRASS stored them (after v.in.ogr cleaning)."""
    from histo_testing import invariant_counts

    geoms, cols = read_output(grassio, output)
    plots, pcols = grassio.read_features(plots_name)
    cats, prepared, _ = subdivision.prepare_plots(plots, pcols["cat"])
    bad = subdivision.invariant_violations(geoms, cols[PLOT], cols[SOURCE],
                                           dict(zip(cats, prepared)), cols[CASE])
    print("\n{}: {} footprints, invariant violations by kind: {}".format(
        output, len(geoms), invariant_counts(bad)))
    assert bad == {}
    # GRASS kept every footprint as one area with its whole geometry: no piece of a
    # footprint cut off into an area of its own by unshared edges or overlaps
    topo = grassio.vector_counts(output)
    assert topo["centroids"] == len(geoms)
    for g, area in zip(geoms, cols[AREA]):
        assert area == pytest.approx(g.area, abs=0.01)
    return geoms, cols


def test_every_case_round_trip_columns_and_invariants(tools):
    gs, grassio, subdivision = tools
    gs.run_command("v.histo.subdivide", input="plots", output="fp", seed=3, quiet=True)
    geoms, cols = check_round_trip(gs, grassio, subdivision, "fp", "plots")
    assert set(cols) >= {"cat", PLOT, CASE, SOURCE, AREA}
    assert set(cols[SOURCE]) == {SOURCE_PROCEDURAL}
    case_of_plot = {}
    for p, c in zip(cols[PLOT], cols[CASE]):
        case_of_plot.setdefault(p, set()).add(c)
    assert case_of_plot[11] == {1}
    assert case_of_plot[12] == {2}
    assert case_of_plot[13] == {3}
    assert case_of_plot[14] == {4}
    assert case_of_plot[15] == {5}
    assert len(geoms) > 40
    assert gs.find_file("fp", element="vector")["name"] == "fp"
    # shared edges stay shared: neighbours touch without gaps along their common cut
    row = [g for g, p in zip(geoms, cols[PLOT]) if p == 12]
    assert shapely.union_all(row).area == pytest.approx(100 * 11, abs=0.01)


def test_seed_repeats_and_changes_facades_and_overwrite_is_respected(tools):
    gs, grassio, _ = tools
    from grass.exceptions import CalledModuleError

    gs.run_command("v.histo.subdivide", input="plots", output="a", seed=5, quiet=True)
    gs.run_command("v.histo.subdivide", input="plots", output="b", seed=5, quiet=True)
    gs.run_command("v.histo.subdivide", input="plots", output="c", seed=6, quiet=True)
    a, b, c = (read_output(grassio, n)[0] for n in "abc")
    assert [g.wkb for g in a] == [g.wkb for g in b]
    assert sorted(round(g.area, 3) for g in a) != sorted(round(g.area, 3) for g in c)
    with pytest.raises(CalledModuleError):
        gs.run_command("v.histo.subdivide", input="plots", output="a", seed=6, quiet=True)
    assert [g.wkb for g in read_output(grassio, "a")[0]] == [g.wkb for g in b]
    gs.run_command("v.histo.subdivide", input="plots", output="a", seed=6, quiet=True,
                   overwrite=True)
    assert [g.wkb for g in read_output(grassio, "a")[0]] == [g.wkb for g in c]


def test_overlapping_plots_warned_and_aligned_footprints_kept(tools):
    gs, grassio, subdivision = tools
    aligned = [shapely.affinity.translate(box(40, 0, 47, 11), X0, Y0),
               shapely.affinity.translate(box(60, 0, 66.5, 11), X0, Y0)]
    grassio.write_features("al", aligned, {PLOT: [12, None], "bouwjaar": ["1900", "1850"]})
    err = gs.read_command("v.histo.subdivide", input="plots", output="fp", aligned="al",
                          area_threshold=100, flags="a", seed=1, stderr=gs.STDOUT)
    assert "1 pairs of overlapping plots" in err
    assert "Too few aligned footprints" in err  # two are not enough to calibrate
    geoms, cols = check_round_trip(gs, grassio, subdivision, "fp", "plots")
    kept = [i for i, s in enumerate(cols[SOURCE]) if s == SOURCE_ALIGNED]
    assert len(kept) == 2
    assert sorted(cols["bouwjaar"][i] for i in kept) == ["1850", "1900"]
    assert {cols[PLOT][i] for i in kept} == {12}
    assert all(cols[CASE][i] == 0 for i in kept)
    assert all(v is None for i, v in enumerate(cols["bouwjaar"]) if i not in kept)


def test_multipart_and_holed_plots(tools):
    # GRASS's topology cannot hold a self-intersecting area (v.in.ogr splits it), so
    # repair is tested in the core; here: one plot of two areas and a plot with a hole
    gs, grassio, subdivision = tools
    two = shapely.MultiPolygon([box(0, 0, 50, 12), box(0, 30, 50, 42)])
    holed = Polygon([(100, 0), (180, 0), (180, 70), (100, 70)],
                    [[(120, 20), (160, 20), (160, 50), (120, 50)]])
    grassio.write_features("odd", [shapely.affinity.translate(g, X0, Y0) for g in (two, holed)],
                           cats=[1, 2])
    gs.run_command("v.histo.subdivide", input="odd", output="fp", quiet=True)
    geoms, cols = check_round_trip(gs, grassio, subdivision, "fp", "odd")
    assert set(cols[PLOT]) == {1, 2}
    hole = shapely.affinity.translate(Polygon(holed.interiors[0]), X0, Y0)
    assert all(g.intersection(hole).area < 1e-6 for g in geoms)
    first = [g for g, p in zip(geoms, cols[PLOT]) if p == 1]
    assert any(g.centroid.y < Y0 + 12 for g in first) and any(g.centroid.y > Y0 + 30 for g in first)


@pytest.mark.parametrize("options, message", [
    ({"length": "8,5"}, "above the maximum"),
    ({"depth": "0,12"}, "positive"),
    ({"depth": "-3,-1"}, "positive"),
    ({"area_threshold": "-5"}, "at least 0"),
    ({"input": "nowhere"}, "not found"),
    ({"aligned": "nowhere"}, "not found"),
])
def test_bad_input_fails_clearly_and_leaves_nothing(tools, options, message):
    gs, _, _ = tools
    from grass.exceptions import CalledModuleError

    kwargs = {"input": "plots", "output": "fp"}
    kwargs.update(options)
    proc = gs.start_command("v.histo.subdivide", stderr=gs.PIPE, **kwargs)
    _, err = proc.communicate()
    assert proc.returncode != 0
    assert message in gs.decode(err)
    assert "Traceback" not in gs.decode(err)
    assert not gs.find_file("fp", element="vector")["name"]
    assert not gs.list_grouped("vector", pattern="tmp_histo_*")[gs.gisenv()["MAPSET"]]
    with pytest.raises(CalledModuleError):
        gs.run_command("v.histo.subdivide", quiet=True, stderr=open(os.devnull, "w"), **kwargs)


def test_without_decomposition_flag(tools):
    gs, grassio, subdivision = tools
    gs.run_command("v.histo.subdivide", input="plots", output="fp", flags="c", seed=3, quiet=True)
    geoms, cols = read_output(grassio, "fp")
    assert 5 not in cols[CASE]
    l_shaped = [g for g, p in zip(geoms, cols[PLOT]) if p == 15]
    assert l_shaped
    plots, pcols = grassio.read_features("plots")
    cats, prepared, _ = subdivision.prepare_plots(plots, pcols["cat"])
    bad = subdivision.invariant_violations(geoms, cols[PLOT], cols[SOURCE],
                                           dict(zip(cats, prepared)), cols[CASE])
    bad.pop("concave", None)  # -c: footprints of a concave plot may be concave
    assert bad == {}


def test_points_are_no_plots(tools):
    gs, grassio, _ = tools
    grassio.write_features("pts", [shapely.Point(X0 + 5, Y0 + 5)])
    proc = gs.start_command("v.histo.subdivide", input="pts", output="fp", stderr=gs.PIPE)
    _, err = proc.communicate()
    assert proc.returncode != 0
    assert "has no areas" in gs.decode(err)
    assert not gs.find_file("fp", element="vector")["name"]


def test_calibration_flag_needs_aligned(tools):
    gs, _, _ = tools
    proc = gs.start_command("v.histo.subdivide", input="plots", output="fp", flags="a",
                            stderr=gs.PIPE)
    _, err = proc.communicate()
    assert proc.returncode != 0
    assert "aligned" in gs.decode(err)


# ---------------------------------------------------------------------------
# Acceptance on the thesis's data
# ---------------------------------------------------------------------------

def plausibility(subdivision, plots, pcats, real, gen_geoms, gen_plot):
    """Median count and area ratios over plots at least half covered by the real footprints
    (real footprints in the plot they overlap most, generated ones in their own)."""
    from histo_testing import plausibility as ratios

    return ratios(plots, pcats, real, gen_geoms, subdivision.assign_plots(real, plots, pcats),
                  gen_plot)


@pytest.mark.acceptance
def test_acceptance_delft_1961(tools, shared_data):
    gs, grassio, subdivision = tools
    base = os.path.join(shared_data, "delft_1961_subset", "thesis_output")
    gs.run_command("v.in.ogr", input=os.path.join(base, "final_plots_delft_1961.shp"),
                   output="delft", quiet=True)
    # no .prj beside this one: -o (it is RD New too)
    gs.run_command("v.in.ogr", input=os.path.join(base, "aligned_entities_current_dataset.shp"),
                   output="real", flags="o", quiet=True)
    err = gs.read_command("v.histo.subdivide", input="delft", output="fp", length="5,5",
                          depth="12,16", area_threshold=100, seed=1, stderr=gs.STDOUT)
    assert "1 pairs of overlapping plots" in err
    geoms, cols = check_round_trip(gs, grassio, subdivision, "fp", "delft")
    assert set(cols[CASE]) <= {1, 2, 3, 4, 5}
    plots, pcols = grassio.read_features("delft")
    assert len(plots) == 33
    assert set(cols[PLOT]) == set(pcols["cat"])
    real, _ = grassio.read_features("real")
    used, count_ratio, area_ratio = plausibility(subdivision, plots, pcols["cat"], real,
                                                 geoms, cols[PLOT])
    print("\nDelft 1961: {} footprints; {} plots >= half covered; median count ratio {:.2f}, "
          "median area ratio {:.2f}".format(len(geoms), used, count_ratio, area_ratio))
    assert used >= 10
    assert 0.8 <= count_ratio <= 1.25  # the thesis's code: 1.00
    assert 0.8 <= area_ratio <= 1.25  # the thesis's code: 0.62

    # with the real footprints as aligned ones, calibrated ranges
    err = gs.read_command("v.histo.subdivide", input="delft", output="fpa", aligned="real",
                          flags="a", area_threshold=100, seed=1, stderr=gs.STDOUT)
    assert "Calibrated from" in err
    geoms_a, cols_a = check_round_trip(gs, grassio, subdivision, "fpa", "delft")
    assert cols_a[SOURCE].count(SOURCE_ALIGNED) > 600
    assert cols_a[SOURCE].count(SOURCE_PROCEDURAL) > 50
    # how much the calibrated ranges help: generate with them, without the aligned ones
    ranges = re.search(r"length=([\d.]+,[\d.]+) depth=([\d.]+,[\d.]+)", " ".join(err.split()))
    gs.run_command("v.histo.subdivide", input="delft", output="fpc", length=ranges.group(1),
                   depth=ranges.group(2), area_threshold=100, seed=1, quiet=True)
    geoms_c, cols_c = check_round_trip(gs, grassio, subdivision, "fpc", "delft")
    _, count_c, area_c = plausibility(subdivision, plots, pcols["cat"], real, geoms_c,
                                      cols_c[PLOT])
    print("Delft 1961 calibrated (length={} depth={}): {} footprints; median count ratio "
          "{:.2f}, median area ratio {:.2f}".format(ranges.group(1), ranges.group(2),
                                                    len(geoms_c), count_c, area_c))
    # reported, not a goal: real footprints include annexes a street row cannot make
    assert 0.5 <= area_c <= 1.5 and count_c >= 0.4


@pytest.mark.acceptance
def test_acceptance_brussels_1924(tools, shared_data):
    gs, grassio, subdivision = tools
    path = os.path.join(shared_data, "bxls_1924", "thesis_output", "final_plots_bxls_1924.shp")
    gs.run_command("v.in.ogr", input=path, output="bxls", flags="o", quiet=True)
    err = gs.read_command("v.histo.subdivide", input="bxls", output="fp", length="8,15",
                          depth="23,30", area_threshold=300, seed=1, stderr=gs.STDOUT)
    assert "11 pairs of overlapping plots" in err
    geoms, cols = check_round_trip(gs, grassio, subdivision, "fp", "bxls")
    print("\nBrussels 1924: {} footprints (thesis 15015)".format(len(geoms)))
    assert abs(len(geoms) - 15015) <= 0.2 * 15015
    assert len(set(cols[PLOT])) == 616
