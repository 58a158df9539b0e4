"""v.histo.align in a temporary GRASS location: the synthetic map, an offset map, bad input."""

import json
import os

import numpy as np
import pytest
from shapely.geometry import Point, box

from histo_testing import key_values, run_in_latlong, run_module

pytestmark = pytest.mark.grass

MODULE = "v.histo.align"
X0, Y0 = 84000.0, 446000.0


def counts(stdout):
    return {k: int(v) for k, v in key_values(stdout).items()}


def by_cat(grassio, name, **kw):
    """{cat: (geometry, {column: value})} of a map of areas."""
    geoms, columns = grassio.read_areas(name, **kw)
    return {c: (g, {k: v[i] for k, v in columns.items()})
            for i, (g, c) in enumerate(zip(geoms, columns["cat"]))}


@pytest.fixture
def tools(mapset, synthetic):
    import grass.script as gs

    from reconstruction import grassio

    return gs, grassio, synthetic


def test_synthetic_map_aligns_the_old_buildings_with_their_plots(tools):
    gs, grassio, synthetic = tools
    current = synthetic.smap.current
    code, out, err = run_module(MODULE, flags="g", input=synthetic.plots,
                                footprints=synthetic.current, year=1900, output="aligned",
                                unmatched="unmatched")
    assert code == 0, err
    n = counts(out)
    without = sum(y is None or y == 9999 for y in current.years)
    assert n["footprints"] == len(current.polygons) and n["without_year"] == without
    assert "{} of {} footprints have no year in <bouwjaar>".format(without, n["footprints"]) in \
        " ".join(err.split())
    assert n["candidates"] == len(current.built_before())
    assert n["aligned"] + n["unmatched"] == n["candidates"]
    aligned = by_cat(grassio, "aligned")
    # the footprints' own columns (the synthetic map's include measured heights) + plot, similarity
    assert set(next(iter(aligned.values()))[1]) == {
        "cat", "bouwjaar", "identificatie", "plot", "similarity", "b3_h_maaiveld", "b3_h_50p",
        "b3_h_70p", "b3_h_nok"}
    assert len(aligned) == n["aligned"] and n["plots_matched"] == len(
        {row["plot"] for _, row in aligned.values()})
    for cat, (geom, row) in aligned.items():
        k = cat - 1                        # the footprint keeps its own category
        assert row["bouwjaar"] == current.years[k] < 1900
        assert row["identificatie"] == current.ids[k]
        # as GRASS keeps it: neighbours crossing by millimetres lose a sliver
        assert geom.symmetric_difference(current.polygons[k]).area < 1e-3 * geom.area
        assert row["plot"] == current.plot[k], current.kind[k]
        assert 0.6 <= row["similarity"] <= 1
    # every old building on a plot is found, straddling and offset ones included
    old_on_plots = {k + 1 for k in current.built_before() if current.kind[k] != "outside"}
    assert set(aligned) == old_on_plots
    assert {current.kind[c - 1] for c in aligned} == {"standing", "offset", "straddling"}
    unmatched = by_cat(grassio, "unmatched")
    assert set(unmatched) == {k + 1 for k in current.built_before()} - old_on_plots
    assert {current.kind[c - 1] for c in unmatched} == {"outside"}
    assert all(row["similarity"] == 0 for _, row in unmatched.values())
    # straddling buildings went to the plot holding most of them
    straddling = [c for c in aligned if current.kind[c - 1] == "straddling"]
    assert straddling and all(aligned[c][1]["plot"] == current.plot[c - 1] for c in straddling)


def test_subdivide_takes_the_aligned_footprints_as_they_are(tools):
    gs, grassio, synthetic = tools
    gs.run_command(MODULE, input=synthetic.plots, footprints=synthetic.current, year=1900,
                   output="aligned", quiet=True)
    gs.run_command("v.histo.subdivide", input=synthetic.plots, aligned="aligned",
                   output="footprints", seed=1, quiet=True)
    aligned = by_cat(grassio, "aligned")
    geoms, columns = grassio.read_areas("footprints")
    source = np.array(columns["source"])
    assert (source == "aligned").sum() == len(aligned)
    mine = {i: row for i, row in enumerate(columns["identificatie"]) if row is not None}
    ids = {row["identificatie"]: row for _, row in aligned.values()}
    assert set(mine.values()) == set(ids)
    for i, ident in mine.items():
        assert columns["plot"][i] == ids[ident]["plot"]
        assert columns["bouwjaar"][i] == ids[ident]["bouwjaar"]
    assert (source == "2pm").sum() > 50


def test_an_offset_map_is_matched_again_with_the_offset_correction(tools, tmp_path):
    gs, grassio, synthetic = tools
    gs.run_command("v.transform", input=synthetic.current, output="current_off", xshift=6,
                   yshift=-4, quiet=True)
    tight = dict(input=synthetic.plots, year=1900, buffer=3, overlap=0.9)
    _, base, _ = run_module(MODULE, flags="g", footprints=synthetic.current, output="a0", **tight)
    _, off, _ = run_module(MODULE, flags="g", footprints="current_off", output="a1", **tight)
    report = tmp_path / "shifts.json"
    code, fixed, err = run_module(MODULE, flags="g", footprints="current_off", output="a2",
                                  shift=10, report=str(report), **tight)
    assert code == 0, err
    base, off, fixed = counts(base), counts(off), counts(fixed)
    assert off["aligned"] < 0.75 * base["aligned"]
    assert fixed["aligned"] == base["aligned"]
    assert fixed["plots_matched"] == base["plots_matched"]
    assert fixed["shifted_plots"] >= 0.9 * fixed["plots_matched"]
    data = json.loads(report.read_text())
    assert data["counts"] == fixed and data["options"]["shift"] == 10
    moved = [row for row in data["plots"] if row["shifted"]]
    assert len(moved) == fixed["shifted_plots"]
    assert max(np.hypot(row["dx"] + 6, row["dy"] - 4) for row in moved) < 1.0
    # the footprints keep their geometry; dx, dy are their plot's shift
    a0, a2 = by_cat(grassio, "a0"), by_cat(grassio, "a2")
    assert set(a0) == set(a2)
    shifted = {row["plot"] for row in moved}
    for cat, (geom, row) in a2.items():
        assert row["plot"] == a0[cat][1]["plot"]
        if row["plot"] in shifted:
            assert abs(row["dx"] + 6) < 1 and abs(row["dy"] - 4) < 1
        else:
            assert row["dx"] == row["dy"] == 0
        assert geom.centroid.distance(a0[cat][0].centroid) == pytest.approx(np.hypot(6, 4),
                                                                             abs=0.01)


@pytest.fixture
def small(mapset):
    """Two plots and footprints around them, made up (cats 1-4)."""
    import grass.script as gs

    from reconstruction import grassio

    gs.run_command("g.region", n=Y0 + 100, s=Y0 - 20, e=X0 + 120, w=X0 - 20, res=1)
    plots = [box(X0, Y0, X0 + 30, Y0 + 12), box(X0, Y0 + 40, X0 + 30, Y0 + 52)]
    grassio.write_features("plots", plots, cats=[10, 20])
    footprints = [box(X0 + 1, Y0 + 1, X0 + 8, Y0 + 10),
                  box(X0 + 32, Y0 + 2, X0 + 34.5, Y0 + 10),   # 2-4.5 m east of plot 10
                  box(X0 + 1, Y0 + 41, X0 + 8, Y0 + 50),
                  box(X0 + 80, Y0, X0 + 90, Y0 + 10)]
    grassio.write_features("fp", footprints, {"bouwjaar": [1800, 1810, "1960", None],
                                              "name": ["a", "b", "c", "d"]})
    return gs, grassio


def test_buffer_from_resolution_and_k_and_the_inclusive_year(small):
    gs, grassio = small
    code, out, err = run_module(MODULE, flags="g", input="plots", footprints="fp", year=1900,
                                resolution="0.9,0.3", k=3, overlap=0.3, output="al")
    assert code == 0, err
    got = by_cat(grassio, "al")
    assert sorted(got) == [1, 2]            # the text years are read; 1960 is after 1900
    assert got[2][1]["similarity"] == pytest.approx(0.85 / 2.5, abs=2e-3)  # buffer 2.85
    assert got[1][1]["name"] == "a" and got[1][1]["plot"] == 10
    _, out, _ = run_module(MODULE, flags="gi", input="plots", footprints="fp", year=1960,
                           output="al2", overwrite=True)
    assert counts(out)["aligned"] == 3 and counts(out)["after_year"] == 0


def test_the_3d_bag_year_column_is_taken_when_there_is_no_bouwjaar(small):
    gs, grassio = small
    gs.run_command("v.db.renamecolumn", map="fp", column="bouwjaar,oorspronkelijkbouwjaar",
                   quiet=True)
    code, out, err = run_module(MODULE, flags="g", input="plots", footprints="fp", year=1900,
                                output="al")
    assert code == 0, err
    assert counts(out)["aligned"] == 2
    assert "oorspronkelijkbouwjaar" in grassio.column_names("al")


def test_nothing_built_before_the_year_gives_an_empty_map_and_a_warning(small):
    gs, grassio = small
    code, out, err = run_module(MODULE, flags="g", input="plots", footprints="fp", year=1500,
                                output="al", unmatched="un")
    assert code == 0, err
    assert "No footprint of <fp> was built before 1500" in err
    assert counts(out)["aligned"] == 0
    assert grassio.vector_counts("al").get("areas", 0) == 0
    assert grassio.read_table("al") == {"cat": [], "bouwjaar": [], "name": [], "plot": [],
                                        "similarity": []}
    assert grassio.read_table("un")["cat"] == []


def test_footprints_far_from_the_plots_give_a_warning_naming_both_boxes(small):
    """Footprints 100 km from the plots ended rc 0 with an empty map and no
    word (issue 33, item 7)."""
    gs, grassio = small
    far = [box(X0 + 100001, Y0 + 1, X0 + 100008, Y0 + 10),
           box(X0 + 100001, Y0 + 41, X0 + 100008, Y0 + 50)]
    grassio.write_features("far", far, {"bouwjaar": [1800, 1810]})
    code, out, err = run_module(MODULE, flags="g", input="plots", footprints="far", year=1900,
                                output="al")
    assert code == 0, err
    assert counts(out)["aligned"] == 0
    text = " ".join(err.split())
    assert ("WARNING: The 2 candidate footprints of <far> (x 184001..184008, y 446001..446050) "
            "do not overlap the plots of <plots> (x 84000..84030, y 446000..446052)") in text, err
    assert "Traceback" not in err


def test_outputs_are_not_overwritten_without_overwrite(small):
    gs, _ = small
    args = dict(input="plots", footprints="fp", year=1900)
    assert run_module(MODULE, output="al", **args)[0] == 0
    code, _, err = run_module(MODULE, output="al", **args)
    assert code != 0 and "exists" in err
    assert run_module(MODULE, output="al", overwrite=True, **args)[0] == 0


@pytest.mark.parametrize("options, message", [
    ({"year_column": "jaar"}, "have no year column <jaar>; columns: bouwjaar, name"),
    ({"year_column": "name"}, "Year column <name> is not numeric: <a> (footprint 1)"),
    ({"buffer": "0"}, "buffer must be positive"),
    ({"buffer": "-2"}, "buffer must be positive"),
    ({"overlap": "0"}, "overlap threshold must be in (0, 1]"),
    ({"overlap": "1.5"}, "overlap threshold must be in (0, 1]"),
    ({"shift": "-3"}, "shift search radius"),
    ({"resolution": "0.9,0"}, "k"),
    ({"resolution": "0.9,0", "k": "2"}, "two positive pixel sizes"),
    ({"buffer": "5", "resolution": "1,1", "k": "2"}, "mutually exclusive"),
    ({"footprints": "pts"}, "has no areas (it holds 1 points"),
    ({"input": "pts"}, "has no areas (it holds 1 points"),
    ({"footprints": "nowhere"}, "not found"),
    ({"input": "nowhere"}, "not found"),
])
def test_bad_input_fails_clearly_and_leaves_nothing(small, options, message, tmp_path):
    gs, grassio = small
    grassio.write_features("pts", [Point(X0 + 5, Y0 + 5)], {"bouwjaar": [1800]})
    kwargs = dict(input="plots", footprints="fp", year=1900, output="al", unmatched="un",
                  report=str(tmp_path / "r.json"))
    kwargs.update(options)
    code, _, err = run_module(MODULE, **kwargs)
    assert code != 0
    assert message in " ".join(err.split()), err
    assert "Traceback" not in err
    for name in ("al", "un"):
        assert not gs.find_file(name, element="vector", mapset=".")["name"]
    assert not os.path.exists(tmp_path / "r.json")
    assert not gs.list_grouped("vector", pattern="tmp_histo_*")[gs.gisenv()["MAPSET"]]


def test_an_existing_report_file_is_kept(small, tmp_path):
    report = tmp_path / "r.json"
    report.write_text("keep")
    code, _, err = run_module(MODULE, input="plots", footprints="fp", year=1900, output="al",
                              report=str(report))
    assert code != 0 and "exists" in err
    assert report.read_text() == "keep"


def test_unprojected_location_is_refused(grass_session):
    script = ("echo '1|1' | v.in.ascii input=- output=pts --q && "
              "{} input=pts footprints=pts year=1900 output=al".format(MODULE))
    loc, proc = run_in_latlong(grass_session["dbase"], "latlong_align", "bash", "-c", script)
    assert proc.returncode != 0
    assert "not projected" in proc.stderr
    assert not os.path.isdir(os.path.join(loc, "PERMANENT", "vector", "al"))


# ---------------------------------------------------------------------------
# Acceptance on the thesis's data: Delft 1961 and Delft 1880
# ---------------------------------------------------------------------------

@pytest.fixture(scope="module")
def delft(grass_session, shared_data):
    """The Delft current footprints with the thesis's years, in a mapset of its own
    (:func:`histo_testing.import_delft_alignment`)."""
    import shutil
    import uuid

    import grass.script as gs

    from histo_testing import import_delft_alignment

    name = "delft_" + uuid.uuid4().hex[:6]
    gs.run_command("g.mapset", flags="c", mapset=name, quiet=True)
    found = import_delft_alignment(shared_data)
    found["mapset"] = name
    yield found
    gs.run_command("g.mapset", mapset="PERMANENT", quiet=True)
    shutil.rmtree(os.path.join(grass_session["dbase"], grass_session["location"], name),
                  ignore_errors=True)


def _align_delft(gs, grassio, delft, year, flags="g", **options):
    """Run the module on the Delft fixture: its counts, {cat: plot} aligned, {cat: best
    similarity} unmatched."""
    if gs.gisenv()["MAPSET"] != delft["mapset"]:
        gs.run_command("g.mapset", mapset=delft["mapset"], quiet=True)
    code, out, err = run_module(MODULE, flags=flags, input="plots{}".format(year),
                                footprints="current", year=year, output="aligned",
                                unmatched="unmatched", overwrite=True, **options)
    assert code == 0, err
    aligned = grassio.read_table("aligned")
    unmatched = grassio.read_table("unmatched")
    return (counts(out), dict(zip(aligned["cat"], aligned["plot"])),
            dict(zip(unmatched["cat"], unmatched["similarity"])))


def _why_missed(delft, thesis, aligned, unmatched, year):
    """Why each of the thesis's aligned footprints is not aligned here: {cat: reason}."""
    reasons = {}
    for cat in sorted(thesis - set(aligned)):
        built = delft["years"][cat]
        if built >= year:
            reasons[cat] = "built in {}".format(built)
        else:
            reasons[cat] = "similarity {:.3f} below the threshold".format(unmatched[cat])
    return reasons


@pytest.mark.acceptance
@pytest.mark.parametrize("year, buffer, overlap, thesis_count, of_the_year", [
    (1961, 10, 0.6, 651, 3),      # the thesis's Table B.3
    (1880, 6, 0.9, 674, 43),
])
def test_acceptance_delft(delft, year, buffer, overlap, thesis_count, of_the_year):
    """At least 95 % of the thesis's aligned footprints aligned (with -i, the thesis's rule
    year <= map year: its own aligned footprints include some of the map's year)."""
    import grass.script as gs

    from reconstruction import grassio

    thesis = delft["thesis{}".format(year)]
    assert len(thesis) == thesis_count
    options = dict(buffer=buffer, overlap=overlap)
    runs = {}
    for flags, extra in (("g", {}), ("gi", {}), ("gi", {"shift": 10})):
        n, aligned, unmatched = _align_delft(gs, grassio, delft, year, flags=flags, **options,
                                             **extra)
        found = thesis & set(aligned)
        missed = _why_missed(delft, thesis, aligned, unmatched, year + ("i" in flags))
        key = ("-i " if "i" in flags else "") + ("shift=10" if extra else "")
        runs[key or "strict"] = found
        print("\nDelft {} {}: {} aligned, {} of the thesis's {} ({:.1%}), {} more, {} plots "
              "shifted; missed: {}".format(
                  year, key or "(strictly before)", n["aligned"], len(found), len(thesis),
                  len(found) / len(thesis), len(set(aligned) - thesis), n["shifted_plots"],
                  missed))
        if flags == "g":
            assert n["footprints"] == 12567
            # strictly before the map's year: missed first of all those of the year itself
            assert sum(r == "built in {}".format(year) for r in missed.values()) == of_the_year
    assert len(runs["-i "]) >= 0.95 * len(thesis)
    assert runs["strict"] <= runs["-i "]
    assert len(runs["-i shift=10"]) >= len(runs["-i "]) - 5
