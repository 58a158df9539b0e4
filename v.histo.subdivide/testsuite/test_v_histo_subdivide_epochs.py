"""v.histo.subdivide in a dynamic chain (year=, previous=, previous_plots=): a temporary
GRASS location, two epochs of one town, the identities and kept footprints as GRASS
stores them."""

import pytest

from epoch_testing import CHANGES, HOUSE, UNCHANGED, write_town
from reconstruction.core.contract import BUILDING, PLOT, PLOT_CHANGE, SOURCE, SOURCE_ALIGNED
from reconstruction.geom.polygons import same_outline

pytestmark = pytest.mark.grass


@pytest.fixture
def town(mapset):
    import grass.script as gs

    from reconstruction import grassio

    write_town(grassio, gs)
    return gs, grassio


def read(grassio, name):
    geoms, cols = grassio.read_features(name)
    single = [g.geoms[0] if g.geom_type == "MultiPolygon" and len(g.geoms) == 1 else g
              for g in geoms]
    return single, cols


def test_two_epochs_keep_unchanged_blocks_and_name_every_building(town):
    gs, grassio = town
    from histo_testing import run_module

    gs.run_command("v.histo.subdivide", input="plots_1880", aligned="aligned_1880",
                   output="fp_1880", year=1880, seed=1, quiet=True)
    g1, c1 = read(grassio, "fp_1880")
    assert HOUSE in c1[BUILDING]
    assert all(b.startswith("building_1880_") for b, s in zip(c1[BUILDING], c1[SOURCE])
               if s != SOURCE_ALIGNED)
    assert len(set(c1[BUILDING])) == len(c1[BUILDING])
    assert PLOT_CHANGE not in c1

    rc, out, err = run_module("v.histo.subdivide", input="plots_1915", output="fp_1915",
                              previous="fp_1880", previous_plots="plots_1880", year=1915,
                              seed=2)
    assert rc == 0, err
    said = " ".join(err.split())
    assert "Plots since <plots_1880>: 4 unchanged, 2 split, 1 new; 1 gone " \
           "(map offset 0.80,-0.60)" in said
    assert "footprints kept from <fp_1880> (" in said
    g2, c2 = read(grassio, "fp_1915")
    old = dict(zip(c1[BUILDING], g1))
    change = dict(zip(c2[PLOT], c2[PLOT_CHANGE]))
    assert change == CHANGES
    # the unchanged blocks keep every footprint, its outline and its identity, the aligned
    # house its BAG id and its columns
    for after_plot, before_plot in UNCHANGED.items():
        before = {b for b, p in zip(c1[BUILDING], c1[PLOT]) if p == before_plot}
        after = {b for b, p in zip(c2[BUILDING], c2[PLOT]) if p == after_plot}
        assert before == after
    for b, g in zip(c2[BUILDING], g2):
        if b in old:
            assert same_outline(old[b], g, 1e-6), b
    k = c2[BUILDING].index(HOUSE)
    assert c2[SOURCE][k] == SOURCE_ALIGNED and c2["bouwjaar"][k] == 1700
    # the gone plot's buildings are gone; the new plot's are new
    gone = {b for b, p in zip(c1[BUILDING], c1[PLOT]) if p == 4}
    assert gone and not gone & set(c2[BUILDING])
    assert all(b.startswith("building_1915_") for b, p in zip(c2[BUILDING], c2[PLOT]) if p == 5)
    assert len(set(c2[BUILDING])) == len(c2[BUILDING])
    topo = grassio.vector_counts("fp_1915")
    assert topo["centroids"] == len(g2)


def test_without_year_the_footprints_are_those_of_a_single_map(town):
    gs, grassio = town
    gs.run_command("v.histo.subdivide", input="plots_1880", output="plain", seed=1, quiet=True)
    gs.run_command("v.histo.subdivide", input="plots_1880", output="dated", seed=1, year=1880,
                   quiet=True)
    plain, pc = read(grassio, "plain")
    dated, dc = read(grassio, "dated")
    assert BUILDING not in pc and BUILDING in dc
    assert [g.wkb for g in plain] == [g.wkb for g in dated]


@pytest.mark.parametrize("options, message", [
    ({"previous": "fp_none"}, "previous_plots"),
    ({"previous_plots": "plots_1880"}, "previous"),
    ({"previous": "plots_1880", "previous_plots": "plots_1880"}, "year"),
    ({"previous": "nowhere", "previous_plots": "plots_1880", "year": "1915"}, "not found"),
    ({"previous": "plots_1880", "previous_plots": "plots_1880", "year": "1915",
      "tolerance": "-1"}, "tolerance"),
    ({"year": "1915", "aligned": "aligned_1880", "id_column": "nothing"}, "id_column"),
    # issue 49, item 7: the plots as previous= became whole footprints; year=0 was taken
    ({"previous": "plots_1880", "previous_plots": "plots_1880", "year": "1915"},
     "has no building column"),
    ({"year": "0"}, "year= must be at least 1"),
])
def test_a_bad_dynamic_chain_fails_clearly_and_leaves_nothing(town, options, message):
    gs, _ = town
    from histo_testing import run_module

    kwargs = {"input": "plots_1915", "output": "fp"}
    kwargs.update(options)
    rc, out, err = run_module("v.histo.subdivide", **kwargs)
    assert rc != 0
    assert message in err and "Traceback" not in err
    assert not gs.find_file("fp", element="vector")["name"]
