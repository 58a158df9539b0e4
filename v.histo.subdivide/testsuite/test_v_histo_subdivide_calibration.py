"""Acceptance of v.histo.subdivide's calibration flag -a on Delft 1961 (issue 14).

The chain as a user runs it: today's footprints with their construction years
(built here, :func:`histo_testing.import_delft_alignment`), v.histo.align on the
thesis's 1961 plots, its output straight into v.histo.subdivide aligned= -a.
The footprints are compared with the 651 footprints the thesis aligned (the
real ones) by the issue's measure (:func:`histo_testing.plausibility`).
"""

import re

import pytest

from reconstruction.core.contract import CASE, PLOT, SOURCE, SOURCE_ALIGNED, SOURCE_PROCEDURAL

pytestmark = [pytest.mark.grass, pytest.mark.acceptance]


@pytest.fixture
def delft(mapset, shared_data):
    """Plots, today's footprints with years, and v.histo.align's output for 1961."""
    import grass.script as gs

    from histo_testing import import_delft_alignment, key_values, run_module
    from reconstruction import grassio
    from reconstruction.subdivide import stage as subdivision

    import_delft_alignment(shared_data)
    code, out, err = run_module("v.histo.align", flags="g", input="plots1961",
                                footprints="current", year=1961, buffer=10, overlap=0.6,
                                output="aligned")
    assert code == 0, err
    plots, columns = grassio.read_features("plots1961", "area")
    real, _ = grassio.read_features("thesis61", "area")
    assert len(plots) == 33 and len(real) == 651
    return gs, grassio, subdivision, plots, columns["cat"], real, key_values(out)


def subdivide(gs, grassio, subdivision, output, **options):
    """Run the module on the 1961 plots; its footprints, columns and messages, with every
    invariant checked on what GRASS stored (counts printed)."""
    from histo_testing import invariant_counts

    err = gs.read_command("v.histo.subdivide", input="plots1961", output=output,
                          area_threshold=100, seed=1, stderr=gs.STDOUT, **options)
    geoms, cols = grassio.read_features(output, "area")
    # read back as multipolygons: one part is one polygon
    geoms = [g.geoms[0] if g.geom_type == "MultiPolygon" and len(g.geoms) == 1 else g
             for g in geoms]
    plots, columns = grassio.read_features("plots1961", "area")
    cats, prepared, _ = subdivision.prepare_plots(plots, columns["cat"])
    bad = subdivision.invariant_violations(geoms, cols[PLOT], cols[SOURCE],
                                           dict(zip(cats, prepared)), cols[CASE])
    print("{}: {} footprints ({} aligned); invariant violations: {}".format(
        output, len(geoms), cols[SOURCE].count(SOURCE_ALIGNED), invariant_counts(bad)))
    assert bad == {}
    return geoms, cols, " ".join(err.split())


def test_calibration_makes_footprints_like_the_real_ones(delft):
    from histo_testing import plausibility

    gs, grassio, subdivision, plots, cats, real, aligned = delft
    print("\nv.histo.align: {} of {} candidates aligned".format(aligned["aligned"],
                                                              aligned["candidates"]))
    run = dict(gs=gs, grassio=grassio, subdivision=subdivision)
    figures = {}

    def measure(name, geoms):
        figures[name] = plausibility(plots, cats, real, geoms)
        print("  {}: {} plots >= half covered, median count ratio {:.2f}, median area "
              "ratio {:.2f}".format(name, *figures[name]))

    # without -a: the thesis's Delft ranges, without and with the aligned footprints
    geoms, _, _ = subdivide(output="thesis", length="5,5", depth="12,16", **run)
    measure("no -a, thesis ranges", geoms)
    geoms, _, _ = subdivide(output="kept", aligned="aligned", length="5,5", depth="12,16",
                            **run)
    measure("no -a, thesis ranges, aligned kept", geoms)
    # with -a: the module's output (aligned footprints kept, the rest generated)
    geoms, cols, err = subdivide(output="calibrated", aligned="aligned", flags="a", **run)
    found = re.search(r"Calibrated from (\d+) aligned footprints: "
                      r"length=([\d.]+,[\d.]+) depth=([\d.]+,[\d.]+)", err)
    assert found, err
    print("  -a: from {} street-fronting row buildings, length={} depth={}".format(
        *found.groups()))
    measure("-a, aligned kept", geoms)
    assert cols[SOURCE].count(SOURCE_PROCEDURAL) > 50
    # what the learnt ranges make alone: every footprint generated
    geoms, _, _ = subdivide(output="ranges", length=found.group(2), depth=found.group(3), **run)
    measure("-a ranges, all generated", geoms)

    used = {n for n, _, _ in figures.values()}
    assert used == {15}
    for name in ("-a, aligned kept", "-a ranges, all generated"):
        _, count, area = figures[name]
        assert 0.8 <= count <= 1.25, name
        assert 0.8 <= area <= 1.25, name
    # the learnt ranges make footprints more like the real ones than the thesis's: the
    # area ratio rises towards 1 (the old calibration lowered it, to 0.65)
    assert figures["-a ranges, all generated"][2] > figures["no -a, thesis ranges"][2] + 0.1
    length = [float(v) for v in found.group(2).split(",")]
    depth = [float(v) for v in found.group(3).split(",")]
    assert 4 <= length[0] <= length[1] <= 9 and 10 <= depth[0] <= depth[1] <= 20
