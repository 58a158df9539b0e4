"""v.histo.lod2, part 2 (issue 16): reference heights, street edges and roof rules,
through the module in a temporary GRASS location: every option and every bad input."""

import json
import os

import numpy as np
import pytest

from histo_testing import import_features, run_module
from lod2_ends import ends_on_shared, model_ends, tops_outside

pytestmark = pytest.mark.grass

MODULE = "v.histo.lod2"
X0, Y0 = 85000.0, 446000.0


def rect(x0, y0, x1, y1):
    return [[x0, y0], [x1, y0], [x1, y1], [x0, y1], [x0, y0]]


def block(n=6, width=6.0, depth=12.0, x0=X0, y0=Y0, rows=2):
    """``rows`` rows of ``n`` houses back to back: row 0 faces the street south
    of it, row 1 the street north of it; their backs are shared."""
    feats = []
    for r in range(rows):
        for i in range(n):
            x, y = x0 + i * width, y0 + r * depth
            feats.append({"type": "Feature",
                          "properties": {"h_building": 9.0 + (i % 3), "h_attic": 4.0,
                                         "plot": 1 + r, "gid": len(feats) + 1},
                          "geometry": {"type": "Polygon",
                                       "coordinates": [rect(x, y, x + width, y + depth)]}})
    return feats


def import_points(xyz, name, tmp_path, z=True):
    import grass.script as gs

    path = str(tmp_path / (name + ".txt"))
    np.savetxt(path, np.asarray(xyz)[:, :3 if z else 2], fmt="%.3f", delimiter="|")
    gs.run_command("v.in.ascii", input=path, output=name, flags="zt" if z else "t", z=3 if z else 0,
                   quiet=True)
    return name


def run(flags="", **kwargs):
    """Run the module: (returncode, stdout, stderr with its lines joined)."""
    rc, stdout, err = run_module(MODULE, flags, **kwargs)
    return rc, stdout, " ".join(err.split())


def load(path):
    with open(path) as f:
        return json.load(f)


def by_footprint(model):
    return {o["attributes"]["footprint"]: o["attributes"] for o in model["CityObjects"].values()}


def plane(x, y):
    return 2.0 + 0.01 * (x - X0) + 0.005 * (y - Y0)


def ground_points(seed=0, hole=None, n=40000):
    """Ground points on a plane over the block's area; none inside ``hole`` (x0, y0, x1, y1)."""
    rng = np.random.default_rng(seed)
    xy = rng.uniform([X0 - 20, Y0 - 20], [X0 + 56, Y0 + 44], (n, 2))
    houses = (xy[:, 0] > X0) & (xy[:, 0] < X0 + 36) & (xy[:, 1] > Y0) & (xy[:, 1] < Y0 + 24)
    xy = xy[~houses]
    if hole is not None:
        x0, y0, x1, y1 = hole
        inside = (xy[:, 0] > x0) & (xy[:, 0] < x1) & (xy[:, 1] > y0) & (xy[:, 1] < y1)
        xy = xy[~inside]
    # inside the footprints there are no ground points (buildings stand there)
    return np.column_stack([xy, plane(xy[:, 0], xy[:, 1])])


@pytest.fixture
def houses(mapset, tmp_path):
    return import_features(block(), "houses", tmp_path)


# ---------------------------------------------------------------------------
# Ground
# ---------------------------------------------------------------------------

def test_ground_points_give_the_plane_under_every_footprint_and_a_hole(houses, tmp_path):
    # a demolished building bigger than house 3 left a hole in the points around it
    hole = (X0 + 10.0, Y0 - 3.0, X0 + 20.0, Y0 + 10.0)
    pts = import_points(ground_points(hole=hole), "gpts", tmp_path)
    out = str(tmp_path / "g.json")
    rc, _, err = run(input=houses, output=out, ground_points=pts, roof="flat")
    assert rc == 0, err
    assert "1 footprints with the buffer grown over a hole" in err
    feats = block()
    for cat, a in by_footprint(load(out)).items():
        ring = np.array(feats[cat - 1]["geometry"]["coordinates"][0])
        cx, cy = ring[:-1].mean(axis=0)
        assert abs(a["ground_height"] - plane(cx, cy)) < 0.1, (cat, a["ground_height"])


def test_a_dtm_gives_the_same_within_a_cell_slope(houses, tmp_path):
    import grass.script as gs

    gs.run_command("g.region", n=Y0 + 44, s=Y0 - 20, e=X0 + 56, w=X0 - 20, res=1.0, quiet=True)
    gs.mapcalc("dtm = 2.0 + 0.01 * (x() - {}) + 0.005 * (y() - {})".format(X0, Y0), quiet=True)
    gs.run_command("g.region", n=Y0 + 5, s=Y0, e=X0 + 5, w=X0, res=5, quiet=True)  # not used
    out = str(tmp_path / "d.json")
    rc, _, err = run(input=houses, output=out, elevation="dtm", roof="flat", ground_percentile=0)
    assert rc == 0, err
    feats = block()
    slope = 1.0 * np.hypot(0.01, 0.005)
    for cat, a in by_footprint(load(out)).items():
        ring = np.array(feats[cat - 1]["geometry"]["coordinates"][0])
        x0, y0 = ring.min(axis=0)
        # percentile 0: the lowest cell centre in the footprint buffered by 0.5 m
        low = plane(x0 - 0.5, y0 - 0.5)
        assert abs(a["ground_height"] - low) < 0.1 + slope, (cat, a["ground_height"], low)


# ---------------------------------------------------------------------------
# Measured heights, plots, building points
# ---------------------------------------------------------------------------

def aligned_features(columns="thesis"):
    """Houses 1, 4, 8 and 11 of the block, measured (absolute heights, ground 2 m)."""
    feats = []
    for f in block():
        gid = f["properties"]["gid"]
        if gid not in (1, 4, 8, 11):
            continue
        eaves, top = 8.0 + gid * 0.25, 12.0 + gid * 0.25
        if columns == "thesis":
            props = {"ground-0.2": 2.0, "roof-0.25": 2.0 + eaves, "roof-0.99": 2.0 + top}
        else:
            # the 3D BAG since 2025: p25 = p50 - 1.25 (p70 - p50)
            props = {"b3_h_maaiveld": 2.0, "b3_h_50p": 2.0 + eaves + 1.25,
                     "b3_h_70p": 2.0 + eaves + 2.25, "b3_h_nok": 2.0 + top}
        feats.append({"type": "Feature", "properties": props, "geometry": f["geometry"]})
    return feats


@pytest.mark.parametrize("columns", ["thesis", "3dbag"])
def test_aligned_footprints_give_measured_heights_and_the_rest_inferred(houses, tmp_path,
                                                                        columns):
    aligned = import_features(aligned_features(columns), "al_" + columns, tmp_path)
    out = str(tmp_path / "a.json")
    # the houses have eaves and roof columns: aligned= takes precedence over them
    rc, _, err = run(input=houses, output=out, aligned=aligned, ground=2.0, roof="gable")
    assert rc == 0, err
    assert "4 of the footprints are aligned footprints" in err
    attrs = by_footprint(load(out))
    for cat, a in attrs.items():
        if cat in (1, 4, 8, 11):
            assert a["height_source"] == "measured"
            assert a["eaves_height"] == pytest.approx(8.0 + cat * 0.25, abs=1e-3)
            assert a["roof_height"] == pytest.approx(4.0, abs=1e-3)
        else:
            assert a["height_source"] == "neighbours"
            assert 8.0 <= a["eaves_height"] <= 11.0


@pytest.mark.parametrize("roof", ["flat", "neck", "bell", "auto"])
def test_every_ridge_interval_holds_its_building_s_top_whatever_its_roof(houses, tmp_path, roof):
    """A flat roof on a measured house kept the ridge interval of the roof it
    did not get (its top 4 m below it), a neck or bell gable's crown stood
    above it (issue 49, item 5). A measured house's intervals are its heights
    as built; an inferred one's hold them."""
    aligned = import_features(aligned_features(), "al", tmp_path)
    out = str(tmp_path / "i.json")
    rc, _, err = run(input=houses, output=out, aligned=aligned, ground=2.0, roof=roof, seed=3)
    assert rc == 0, err
    model = load(out)
    assert tops_outside(model) == []
    attrs = by_footprint(model)
    for cat in (1, 4, 8, 11):
        a = attrs[cat]
        # measured heights on a footprint of unknown source (no source column): class 3
        assert a["certainty"] == 3 and a["height_source"] == "measured"
        assert a["eaves_height_low"] == a["eaves_height_high"] == a["eaves_height"]
        assert a["ridge_height_low"] == a["ridge_height_high"]
        if a["roof_type"] == "flat":
            assert a["ridge_height_low"] == a["eaves_height"]
    assert all(a["ridge_height_low"] < a["ridge_height_high"] for c, a in attrs.items()
               if c not in (1, 4, 8, 11))


def test_implausible_measured_heights_warn_apart_from_nulls_and_lend_nothing(houses, tmp_path):
    """A ground of -1,000 m gave house 2 eaves of 1,010 m, which reached its
    neighbours' intervals; a NULL, a roof top below the eaves and eaves of 1e9
    were all counted as "no measured heights (NULL)" (issue 49, item 8)."""
    feats = aligned_features()
    bad = {2: {"ground-0.2": -1000.0, "roof-0.25": 12.0, "roof-0.99": 16.0},
           3: {"ground-0.2": None, "roof-0.25": 12.0, "roof-0.99": 16.0},
           5: {"ground-0.2": 2.0, "roof-0.25": 12.0, "roof-0.99": 9.0},
           6: {"ground-0.2": 2.0, "roof-0.25": 1e9, "roof-0.99": 1e9}}
    houses_at = {f["properties"]["gid"]: f["geometry"] for f in block()}
    feats += [{"type": "Feature", "properties": props, "geometry": houses_at[gid]}
              for gid, props in bad.items()]
    aligned = import_features(feats, "al_bad", tmp_path)
    out = str(tmp_path / "bad_heights.json")
    rc, _, err = run(input=houses, output=out, aligned=aligned, ground=2.0, roof="gable")
    assert rc == 0, err
    assert "1 aligned footprints have no measured heights (NULL)" in err
    for reason in ("ground outside -450..8850 m", "roof top below the eaves",
                   "taller than 300 m"):
        assert "WARNING: 1 aligned footprints have implausible measured heights ({}): not " \
            "used".format(reason) in err, err
    attrs = by_footprint(load(out))
    assert [attrs[c]["height_source"] for c in (2, 3, 5, 6)] == ["neighbours"] * 4
    assert max(a["ridge_height_high"] for a in attrs.values()) < 20.0
    assert max(a["eaves_height"] for a in attrs.values()) < 12.0


def test_plots_and_the_thesis_rule(houses, tmp_path):
    import grass.script as gs

    aligned = import_features(aligned_features(), "al", tmp_path)
    plots = import_features([{"type": "Feature", "properties": {"plot": r + 1},
                              "geometry": {"type": "Polygon", "coordinates": [
                                  rect(X0, Y0 + 12 * r, X0 + 36, Y0 + 12 * (r + 1))]}}
                             for r in range(2)], "plots", tmp_path)
    gs.run_command("v.db.addcolumn", map=plots, columns="plot integer", quiet=True) \
        if "plot" not in gs.vector_columns(plots) else None
    out = str(tmp_path / "p.json")
    rc, _, err = run(input=houses, output=out, aligned=aligned, plots=plots, height_rule="plot",
                     roof="flat")
    assert rc == 0, err
    attrs = by_footprint(load(out))
    row0 = np.median([8.0 + g * 0.25 for g in (1, 4)])
    for cat, a in attrs.items():
        if cat not in (1, 4, 8, 11):
            assert a["height_source"] == "plot"
            if cat <= 6:
                assert a["eaves_height"] == pytest.approx(row0, abs=1e-3)


def test_building_points_then_neighbours(houses, tmp_path):
    rng = np.random.default_rng(1)
    pts = []
    for f in block()[:4]:                     # houses 5 and on have no points
        ring = np.array(f["geometry"]["coordinates"][0])
        (x0, y0), (x1, y1) = ring.min(axis=0), ring.max(axis=0)
        xy = rng.uniform([x0 + 0.2, y0 + 0.2], [x1 - 0.2, y1 - 0.2], (300, 2))
        z = 2.0 + 9.0 + 4.0 * (1 - np.abs(xy[:, 0] - (x0 + x1) / 2) / ((x1 - x0) / 2))
        pts.append(np.column_stack([xy, z]))
    bp = import_points(np.concatenate(pts), "bpts", tmp_path)
    out = str(tmp_path / "b.json")
    rc, _, err = run(input=houses, output=out, building_points=bp, ground=2.0, roof="flat")
    assert rc == 0, err
    assert "4 footprints have building points" in err
    assert "are they ground points?" not in err
    attrs = by_footprint(load(out))
    assert [attrs[c]["height_source"] for c in range(1, 13)] == ["points"] * 4 + \
        ["neighbours"] * 8
    assert all(9.0 < a["eaves_height"] < 13.0 for a in attrs.values())


def test_ground_points_given_as_building_points_warn(houses, tmp_path):
    """They gave buildings 0.01-1.4 m tall without a word (issue 33, item 8)."""
    rng = np.random.default_rng(3)
    xy = rng.uniform([X0 - 20, Y0 - 20], [X0 + 56, Y0 + 44], (40000, 2))
    ground = np.column_stack([xy, plane(xy[:, 0], xy[:, 1]) + rng.uniform(0, 1.0, len(xy))])
    pts = import_points(ground, "gpts_all", tmp_path)
    out = str(tmp_path / "low.json")
    rc, _, err = run(input=houses, output=out, ground_points=pts, building_points=pts,
                     roof="flat")
    assert rc == 0, err
    assert "WARNING: The building points of <gpts_all> stand less than 2 m above the ground " \
        "on 12 of 12 footprints" in err and "are they ground points?" in err, err
    assert "Traceback" not in err


def test_ranges_and_columns_keep_working_with_their_source(houses, tmp_path):
    out = str(tmp_path / "r.json")
    rc, _, err = run(input=houses, output=out, height="6,7")
    assert rc == 0, err
    assert {a["height_source"] for a in by_footprint(load(out)).values()} == {"range"}
    rc, _, err = run(input=houses, output=out, flags="", overwrite=True)
    assert rc == 0, err
    assert {a["height_source"] for a in by_footprint(load(out)).values()} == {"column"}


# ---------------------------------------------------------------------------
# Street edges and roof rules
# ---------------------------------------------------------------------------

def test_street_edges_written_and_no_end_on_a_shared_edge(houses, tmp_path):
    out = str(tmp_path / "s.json")
    rc, _, err = run(input=houses, output=out, roof="gable")
    assert rc == 0, err
    assert "Street edges:" in err
    model = load(out)
    rows, _ = model_ends(model)
    for oid, ring, ends, shared, a in rows:
        k = a["street_edge"]
        assert 0 <= k < len(ring) and not shared[k]
        a_, b_ = ring[k], ring[(k + 1) % len(ring)]
        cat = a["footprint"]
        # row 0 faces south (y = Y0), row 1 north (y = Y0 + 24)
        assert np.allclose([a_[1], b_[1]], Y0 if cat <= 6 else Y0 + 24), (cat, a_, b_)
        assert k in ends                       # the gable end is on the street edge
    counts = ends_on_shared(model)
    assert counts["on_shared"] == 0, counts
    assert counts["ends"] == 12                # one end each: the back is a hip


def test_flag_s_puts_ends_on_the_shortest_edge(houses, tmp_path):
    out = str(tmp_path / "s.json")
    rc, _, err = run(flags="s", input=houses, output=out, roof="gable")
    assert rc == 0, err
    model = load(out)
    assert all("street_edge" not in o["attributes"] for o in model["CityObjects"].values())
    assert ends_on_shared(model)["on_shared"] > 0      # the thesis's part 1 behaviour


def free_row(name, tmp_path):
    """One row of the block's houses, the k-th moved 2k m along x (apart), as map ``name``."""
    feats = block(rows=1)
    for k, f in enumerate(feats):
        ring = np.array(f["geometry"]["coordinates"][0]) + [k * 2.0, 0]
        f["geometry"]["coordinates"][0] = ring.tolist()
    return import_features(feats, name, tmp_path)


def street_raster(tmp_path):
    """A classified raster: class 4 (street) south of row 0 only, class 1 elsewhere."""
    import grass.script as gs

    gs.run_command("g.region", n=Y0 + 40, s=Y0 - 20, e=X0 + 56, w=X0 - 20, res=0.5, quiet=True)
    gs.mapcalc("cls = if(y() < {}, 4, 1)".format(Y0), quiet=True)
    return "cls"


def test_streets_raster_picks_the_edge_facing_the_street(mapset, tmp_path):
    # one row of free-standing houses: every edge is unshared
    name = free_row("free", tmp_path)
    cls = street_raster(tmp_path)
    out = str(tmp_path / "st.json")
    rc, _, err = run(input=name, output=out, streets=cls, street_classes="3,4", roof="gable")
    assert rc == 0, err
    rows, _ = model_ends(load(out))
    for oid, ring, ends, shared, a in rows:
        k = a["street_edge"]
        assert a["street_case"] == 5
        assert np.allclose([ring[k][1], ring[(k + 1) % len(ring)][1]], Y0)


def test_street_areas_work_as_the_raster(mapset, tmp_path):
    name = free_row("free2", tmp_path)
    street = import_features([{"type": "Feature", "properties": {"n": 1}, "geometry": {
        "type": "Polygon", "coordinates": [rect(X0 - 20, Y0 - 8, X0 + 60, Y0 - 0.01)]}}],
        "street", tmp_path)
    out = str(tmp_path / "sa.json")
    rc, _, err = run(input=name, output=out, street_areas=street, roof="gable")
    assert rc == 0, err
    assert {a["street_case"] for a in by_footprint(load(out)).values()} == {5}


def test_rules_file_decides_the_roofs(houses, tmp_path):
    path = str(tmp_path / "rules.csv")
    with open(path, "w") as f:
        f.write("# every roof flat before 1900, mansard after\nfrom,to,shape,flat,mansard\n"
                ",1900,n,100,0\n1901,,n,0,100\n")
    for year, kind in ((1880, "flat"), (1950, "mansard")):
        out = str(tmp_path / "rules{}.json".format(year))
        rc, _, err = run(input=houses, output=out, rules=path, year=year)
        assert rc == 0, err
        assert {a["roof_type"] for a in by_footprint(load(out)).values()} == {kind}


def test_an_excel_rules_file_is_read_without_a_word(houses, tmp_path):
    """Excel's "CSV UTF-8" (a byte order mark, CRLF) was refused with an
    invisible BOM in the message (issue 33, item 8)."""
    path = tmp_path / "excel.csv"
    path.write_bytes(b"\xef\xbb\xbffrom,to,shape,flat,mansard\r\n,1900,n,100,0\r\n"
                     b"1901,,n,0,100\r\n")
    out = str(tmp_path / "excel.json")
    rc, _, err = run(input=houses, output=out, rules=str(path), year=1950)
    assert rc == 0, err
    assert "WARNING" not in err and "Traceback" not in err
    assert {a["roof_type"] for a in by_footprint(load(out)).values()} == {"mansard"}


# ---------------------------------------------------------------------------
# Bad inputs: a clear error and nothing left behind
# ---------------------------------------------------------------------------

@pytest.mark.parametrize("case,expect", [
    ("points_elsewhere", "another reference system"),
    ("points_2d", "is 2D"),
    ("aligned_no_columns", "no height columns"),
    ("streets_no_classes", "no cells of the classes"),
    ("streets_no_option", "street_classes"),
    ("streets_bad_label", "neither a number nor a category label"),
    ("rules_sum", "sum to 90"),
    ("rules_missing", "Cannot read the roof rules"),
    ("rules_latin1", "is not UTF-8 text (byte 0xe9 at offset 3): save it as UTF-8"),
    ("rules_reversed", "line 3 (1920-1900, n-sided): the period starts after it ends"),
    ("eaves_1e9", "Column <h_building> (eaves height) of feature cat 3: 1e+09 m is not a "
                  "plausible eaves height (at most 300 m)"),
    ("ground_column", "Column <g> (ground elevation) of feature cat 2: -1000 m is not a "
                      "plausible ground elevation"),
    ("dtm_nodata", "from the elevation raster is -9999 m, not a plausible ground"),
    ("height_range", "height=: the maximum 1000 m is not a plausible height"),
    ("rules_fraction", "a year must be a whole number, not <1899.5>"),
    ("streets_elsewhere", "has no data within 10 m of the footprints"),
    ("percentile", "ground_percentile"),
])
def test_bad_inputs_fail_cleanly(houses, tmp_path, case, expect):
    out = str(tmp_path / "bad.json")
    kwargs = {"input": houses, "output": out}
    if case == "points_elsewhere":
        pts = ground_points(n=2000)
        pts[:, 0] += 3.0e6                           # e.g. UTM coordinates in an RD location
        kwargs["ground_points"] = import_points(pts, "far", tmp_path)
    elif case == "points_2d":
        kwargs["ground_points"] = import_points(ground_points(n=200), "flat2d", tmp_path, z=False)
    elif case == "aligned_no_columns":
        kwargs["aligned"] = houses
    elif case == "streets_elsewhere":                # its streets 100 km east
        import grass.script as gs

        gs.run_command("g.region", n=Y0 + 40, s=Y0 - 20, e=X0 + 100056, w=X0 + 99980, res=0.5,
                       quiet=True)
        gs.mapcalc("far_cls = 4", quiet=True)
        gs.run_command("g.region", n=Y0 + 40, s=Y0 - 20, e=X0 + 56, w=X0 - 20, quiet=True)
        kwargs.update(streets="far_cls", street_classes="4")
    elif case.startswith("streets"):
        kwargs["streets"] = street_raster(tmp_path)
        if case == "streets_no_classes":
            kwargs["street_classes"] = "7"
        elif case == "streets_bad_label":
            kwargs["street_classes"] = "canal"
    elif case == "rules_sum":
        path = str(tmp_path / "r.csv")
        with open(path, "w") as f:
            f.write("from,to,shape,flat,hip\n,,n,50,40\n")
        kwargs["rules"] = path
    elif case == "rules_latin1":
        path = tmp_path / "latin1.csv"
        path.write_bytes("# p\u00e9riode\nfrom,to,shape,flat\n,,n,100\n".encode("latin-1"))
        kwargs["rules"] = str(path)
    elif case == "rules_fraction":
        path = tmp_path / "fraction.csv"
        path.write_text("from,to,shape,flat\n,1899.5,n,100\n1900,,n,100\n")
        kwargs["rules"] = str(path)
    elif case == "rules_missing":
        kwargs["rules"] = str(tmp_path / "nothing.csv")
    elif case == "rules_reversed":
        path = tmp_path / "reversed.csv"
        path.write_text("from,to,shape,flat\n,1899,n,100\n1920,1900,n,100\n1901,,n,100\n")
        kwargs["rules"] = str(path)
    elif case in ("eaves_1e9", "ground_column"):
        feats = block()
        if case == "eaves_1e9":
            feats[2]["properties"]["h_building"] = 1e9
        else:
            for f in feats:
                f["properties"]["g"] = -1000.0 if f["properties"]["gid"] == 2 else 2.0
            kwargs["ground_column"] = "g"
        kwargs["input"] = import_features(feats, "bad_" + case, tmp_path)
    elif case == "dtm_nodata":
        import grass.script as gs

        gs.run_command("g.region", n=Y0 + 44, s=Y0 - 20, e=X0 + 56, w=X0 - 20, res=1.0,
                       quiet=True)
        gs.mapcalc("dtm_9999 = -9999", quiet=True)
        kwargs["elevation"] = "dtm_9999"
    elif case == "height_range":
        kwargs["height"] = "5,1000"
    elif case == "percentile":
        kwargs["ground_percentile"] = 70
    rc, _, err = run(**kwargs)
    assert rc != 0
    assert "ERROR" in err and expect in err, err
    assert "Traceback" not in err
    assert not os.path.exists(out)
    assert not os.path.exists(out + ".part")
