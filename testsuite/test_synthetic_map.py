"""The synthetic historical map: content, truth, points, determinism, GRASS output."""

import itertools
import math
import os
import subprocess
import sys

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
import shapely
from shapely.geometry import Point

import synthetic_map as sm
from synthetic_map import BUILDING, STREET, SYMBOL, TEXT, VEGETATION, WATER

HERE = os.path.dirname(os.path.abspath(__file__))


@pytest.fixture(scope="module")
def smap():
    return sm.generate(seed=1)


def _edge_angles(poly):
    """Directions (degrees modulo 90) of all edges of a polygon, holes included."""
    angles = []
    for ring in [poly.exterior, *poly.interiors]:
        xy = np.asarray(ring.coords)
        d = np.diff(xy, axis=0)
        d = d[np.hypot(d[:, 0], d[:, 1]) > 1.0]
        angles.extend(np.degrees(np.arctan2(d[:, 1], d[:, 0])) % 90.0)
    a = np.array(angles)
    return np.minimum(a, 90.0 - a)  # 0 = axis-aligned


def test_same_seed_gives_identical_map_and_other_seed_another(smap):
    again = sm.generate(seed=1)
    assert np.array_equal(again.rgb, smap.rgb)
    assert np.array_equal(again.truth, smap.truth)
    assert np.array_equal(again.drawn, smap.drawn)
    assert [p.wkb for p in again.plots] == [p.wkb for p in smap.plots]
    assert again.plot_kinds == smap.plot_kinds
    assert np.array_equal(again.training["xy"], smap.training["xy"])
    assert np.array_equal(again.training["label"], smap.training["label"])
    assert again.training["class"] == smap.training["class"]
    assert np.array_equal(again.gt_points, smap.gt_points)
    other = sm.generate(seed=2)
    assert np.mean(other.truth != smap.truth) > 0.2
    assert np.mean(np.abs(other.rgb.astype(int) - smap.rgb.astype(int))) > 10
    assert [p.wkb for p in other.plots] != [p.wkb for p in smap.plots]


def test_shapes_region_and_classes(smap):
    assert smap.rgb.shape == (600, 600, 3) and smap.rgb.dtype == np.uint8
    assert smap.truth.shape == smap.drawn.shape == (600, 600)
    assert (smap.west, smap.south, smap.east, smap.north, smap.res) == (
        84000.0, 446000.0, 84600.0, 446600.0, 1.0)
    assert smap.region() == {"n": 446600.0, "s": 446000.0, "e": 84600.0, "w": 84000.0,
                             "res": 1.0}
    assert smap.classes == {1: "building", 2: "text", 3: "water", 4: "street",
                            5: "vegetation", 6: "symbol"}
    assert set(np.unique(smap.truth)) == {BUILDING, WATER, STREET, VEGETATION}
    assert set(np.unique(smap.drawn)) == set(smap.classes)
    # text and symbols only replace what is under them
    plain = ~np.isin(smap.drawn, (TEXT, SYMBOL))
    assert np.array_equal(smap.drawn[plain], smap.truth[plain])


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_class_shares_are_plausible(seed, smap):
    m = smap if seed == 1 else sm.generate(seed=seed)
    share = {label: m.class_share(label, visible=label in (TEXT, SYMBOL)) for label in m.classes}
    assert 0.25 <= share[BUILDING] <= 0.50
    assert 0.15 <= share[STREET] <= 0.50  # streets, quays and unbuilt yards
    assert 0.01 <= share[WATER] <= 0.10
    assert 0.05 <= share[VEGETATION] <= 0.30
    assert 0.003 <= share[TEXT] <= 0.03
    assert 0.001 <= share[SYMBOL] <= 0.01
    assert 30 <= len(m.plots) <= 70


def test_every_plot_kind_with_holed_courtyards_and_concave_blocks(smap):
    kinds = smap.plot_kinds
    assert len(kinds) == len(smap.plots)
    assert set(kinds) == set(sm.PLOT_KINDS)
    for poly, kind in zip(smap.plots, kinds):
        solidity = poly.area / poly.convex_hull.area
        if kind == "courtyard":
            assert len(poly.interiors) == 1
        else:
            assert len(poly.interiors) == 0
        if kind in ("L", "U"):
            assert solidity < 0.9, (kind, solidity)
        elif kind != "courtyard":
            assert solidity > 0.99, (kind, solidity)
    assert sum(len(p.interiors) == 1 for p in smap.plots) >= 2


def test_some_plots_rotated_and_some_slanted(smap):
    rotated = slanted = 0
    for poly in smap.plots:
        skew = _edge_angles(poly)
        if np.all(skew > 5):
            rotated += 1
            assert np.all((skew > 9) & (skew < 31))  # rotated by 10-30 degrees
        elif np.any(skew > 3):
            slanted += 1
    assert rotated >= 1
    assert slanted >= 2
    assert rotated + slanted <= len(smap.plots) / 2  # mostly axis-aligned


def test_plots_valid_inside_the_map_and_apart(smap):
    frame = shapely.box(smap.west, smap.south, smap.east, smap.north)
    for poly in smap.plots:
        assert poly.geom_type == "Polygon" and poly.is_valid
        assert poly.area >= 90
        assert frame.buffer(-2).contains(poly)
    for a, b in itertools.combinations(smap.plots, 2):
        assert a.distance(b) >= 6.0  # a street, a quay or a yard between any two plots


def test_one_ground_truth_point_inside_each_plot(smap):
    assert smap.gt_points.shape == (len(smap.plots), 2)
    for i, (x, y) in enumerate(smap.gt_points):
        inside = [j for j, poly in enumerate(smap.plots) if poly.contains(Point(x, y))]
        assert inside == [i]
    rows, cols = smap.to_pixel(smap.gt_points)
    assert np.all(smap.truth[rows, cols] == BUILDING)


def test_truth_raster_matches_the_plot_polygons(smap):
    rows, cols, in_plot = sm.plots_sampled(smap, 7)
    assert np.array_equal(in_plot, smap.truth[rows, cols] == BUILDING)


def test_training_points_on_pixels_of_their_class(smap):
    tr = smap.training
    assert tr["xy"].shape == (len(tr["label"]), 2)
    assert tr["class"] == [smap.classes[int(v)] for v in tr["label"]]
    counts = np.bincount(tr["label"], minlength=7)[1:]
    assert np.all((counts >= 3) & (counts <= 8)), counts
    rows, cols = smap.to_pixel(tr["xy"])
    assert np.array_equal(smap.drawn[rows, cols], tr["label"])
    # pixel centres
    assert np.allclose((tr["xy"][:, 0] - smap.west) % smap.res, smap.res / 2)
    # text and symbol points lie on black ink (green and blue planes are not shifted)
    ink = np.isin(tr["label"], (TEXT, SYMBOL))
    assert np.all(smap.ink_cover[rows[ink], cols[ink]] >= 0.7)
    assert np.all(smap.rgb[rows[ink], cols[ink], 1:] < 140)
    assert np.all(smap.rgb[rows[~ink], cols[~ink], 1] > 140)


def test_text_and_symbols_printed_over_plots_and_streets(smap):
    for label in (TEXT, SYMBOL):
        under = smap.truth[smap.drawn == label]
        assert np.sum(under == BUILDING) >= 30, label
        assert np.sum(under == STREET) >= 30, label
    # text is thin, anti-aliased ink: many pixels partly covered
    partial = (smap.ink_cover > 0.1) & (smap.ink_cover < 0.9)
    assert partial.sum() > 0.5 * (smap.ink_cover >= 0.9).sum()
    # rotated street names: vertical labels exist (long thin ink runs along columns)
    text = smap.drawn == TEXT
    from scipy import ndimage

    labelled, n = ndimage.label(ndimage.binary_dilation(text, iterations=3))
    boxes = ndimage.find_objects(labelled)
    tall = [b for b in boxes if (b[0].stop - b[0].start) > 3 * (b[1].stop - b[1].start)]
    wide = [b for b in boxes if (b[1].stop - b[1].start) > 3 * (b[0].stop - b[0].start)]
    assert tall and wide


def test_one_plane_misregistered_by_one_pixel(smap):
    assert smap.misregistration == {"band": "red", "shift": (0, 1)}
    rgb = smap.rgb.astype(float)

    def best_shift(a, b, axis):
        """Shift of b (pixels along axis) that best matches a's edges."""
        ga = np.diff(a, axis=axis)[5:-5, 5:-5]
        scores = {}
        for d in (-2, -1, 0, 1, 2):
            gb = np.roll(np.diff(b, axis=axis), d, axis=axis)[5:-5, 5:-5]
            scores[d] = np.corrcoef(ga.ravel(), gb.ravel())[0, 1]
        return max(scores, key=scores.get), scores

    shift, scores = best_shift(rgb[..., 0], rgb[..., 1], axis=1)
    assert shift == 1, scores
    assert best_shift(rgb[..., 0], rgb[..., 1], axis=0)[0] == 0
    assert best_shift(rgb[..., 2], rgb[..., 1], axis=1)[0] == 0
    # false colour: a red fringe east of every dark glyph
    ink = smap.ink_cover >= 0.9
    east = np.roll(ink, 1, axis=1) & (smap.ink_cover == 0)
    assert rgb[..., 0][east].mean() < rgb[..., 1][east].mean() - 40


def test_scan_defects_noise_and_bleaching(smap):
    from scipy import ndimage

    rgb = smap.rgb.astype(float)
    street = ndimage.binary_erosion(smap.drawn == STREET, iterations=2)
    # colour noise inside one class
    assert 3.0 < rgb[..., 1][street].std() < 25.0
    # bleaching: smooth differences between tiles of one class, far beyond the noise
    building = ndimage.binary_erosion(smap.truth == BUILDING, iterations=3)

    def tile_means(mask):
        tiles = []
        for r in range(0, 600, 150):
            for c in range(0, 600, 150):
                part = mask[r:r + 150, c:c + 150]
                if part.sum() > 500:
                    tiles.append(rgb[r:r + 150, c:c + 150][part].mean(axis=0))
        return np.array(tiles)

    assert np.ptp(tile_means(building)[:, 1]) > 5.0  # faded pink
    streets = tile_means(street)
    assert np.ptp(streets[:, 2]) > 5.0  # yellowed paper: blue falls, red and green stay
    assert np.ptp(streets[:, 2]) > 2 * np.ptp(streets[:, 1])
    # mixed pixels on plot edges: values between the fill and the street
    green = rgb[..., 1]
    assert green[building].mean() < green[street].mean() - 30


def test_size_resolution_and_origin():
    m = sm.generate(seed=5, size=240, res=2.0, origin=(1000.0, 2000.0))
    assert m.rgb.shape == (240, 240, 3)
    assert (m.west, m.south, m.east, m.north) == (1000.0, 2000.0, 1480.0, 2480.0)
    frame = shapely.box(m.west, m.south, m.east, m.north)
    assert all(frame.contains(p) for p in m.plots) and len(m.plots) >= 5
    rows, cols = m.to_pixel(m.gt_points)
    assert np.all(m.truth[rows, cols] == BUILDING)
    with pytest.raises(ValueError):
        sm.generate(size=199)


def test_png_picture(tmp_path, smap):
    path = tmp_path / "x.png"
    sm.write_png(str(path), sm.outline_plots(smap), colours=48)
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    width, height = int.from_bytes(data[16:20], "big"), int.from_bytes(data[20:24], "big")
    assert (width, height) == (600, 600)
    assert len(data) < 200_000


# ---------------------------------------------------------------------------
# Today's footprints (v.histo.align's fixture)
# ---------------------------------------------------------------------------

def test_current_footprints_are_valid_and_apart_with_every_kind(smap):
    c = smap.current
    n = len(c.polygons)
    assert n > 300 and len(c.years) == len(c.plot) == len(c.kind) == len(c.ids) == n
    assert len(set(c.ids)) == n
    geoms = np.array(c.polygons, dtype=object)
    assert shapely.is_valid(geoms).all() and set(shapely.get_type_id(geoms)) == {3}
    a, b = shapely.STRtree(geoms).query(geoms, predicate="intersects")
    keep = a < b
    assert shapely.area(shapely.intersection(geoms[a[keep]], geoms[b[keep]])).max() < 1e-6
    counts = {k: c.kind.count(k) for k in sm.CURRENT_KINDS}
    assert counts["standing"] > 300 and counts["offset"] == 4
    assert counts["straddling"] >= 2 and counts["rebuilt"] >= 3 and counts["outside"] == 8
    # some plots keep buildings and some do not
    assert 0.5 * len(smap.plots) < len({p for p, k in zip(c.plot, c.kind) if k == "standing"}) \
        < len(smap.plots)


def test_current_footprints_years_before_and_after_the_map_and_unknown(smap):
    c = smap.current
    known = [y for y in c.years if y is not None and y != 9999]
    before = c.built_before()
    assert c.map_year == sm.MAP_YEAR == 1900
    assert 0.55 < len(before) / len(c.years) < 0.85
    assert sum(y > 1900 for y in known) > 50
    assert c.years.count(None) >= 3 and c.years.count(9999) >= 3
    assert 1900 not in c.years
    for k in ("straddling", "offset"):
        assert all(c.years[i] < 1900 for i in range(len(c.years)) if c.kind[i] == k)
    assert all(c.years[i] > 1900 for i in range(len(c.years)) if c.kind[i] == "rebuilt")


def test_current_footprints_stand_where_their_kind_says(smap):
    c = smap.current
    plots = smap.plots
    union = shapely.union_all(plots)
    for poly, plot, kind in zip(c.polygons, c.plot, c.kind):
        if kind in ("standing", "rebuilt"):
            assert plots[plot - 1].buffer(0.01).contains(poly), kind  # 1 cm grid
        elif kind == "offset":
            inside = poly.intersection(plots[plot - 1]).area / poly.area
            assert 0.6 < inside <= 1.0  # moved outwards or along the row
        elif kind == "straddling":
            shares = sorted((poly.intersection(p).area for p in plots), reverse=True)
            assert shares[1] > 0 and shares[0] >= 2 * shares[1]
            assert poly.intersection(plots[plot - 1]).area == shares[0]
        else:
            assert plot == 0 and poly.distance(union) > 20
            rows, cols = smap.to_pixel(np.asarray(poly.exterior.coords))
            assert not np.any(smap.truth[rows, cols] == WATER)


def test_current_footprints_are_seeded_and_do_not_change_the_map():
    a, b = sm.generate(seed=3, size=260), sm.generate(seed=3, size=260)
    rgb = a.rgb.copy()
    assert [p.wkb for p in a.current.polygons] == [p.wkb for p in b.current.polygons]
    assert a.current.years == b.current.years
    assert np.array_equal(a.rgb, rgb)
    assert [p.wkb for p in sm.generate(seed=4, size=260).current.polygons] != \
        [p.wkb for p in a.current.polygons]


# ---------------------------------------------------------------------------
# In GRASS
# ---------------------------------------------------------------------------

@pytest.mark.grass
def test_write_to_grass_maps_and_counts(synthetic):
    import grass.script as gs

    from reconstruction import grassio

    m = synthetic.smap
    assert synthetic.red == "map.red@PERMANENT"
    for i, name in enumerate((synthetic.red, synthetic.green, synthetic.blue)):
        info = gs.raster_info(name)
        assert info["datatype"] == "CELL"
        assert (int(info["rows"]), int(info["cols"])) == (600, 600)
        assert tuple(float(info[k]) for k in ("north", "south", "east", "west")) == (
            m.north, m.south, m.east, m.west)
        univar = gs.parse_command("r.univar", map=name, flags="g")
        assert int(univar["n"]) == 360000 and int(univar["null_cells"]) == 0
        assert int(univar["min"]) == m.rgb[..., i].min()
        assert int(univar["max"]) == m.rgb[..., i].max() <= 255
        assert float(univar["mean"]) == pytest.approx(m.rgb[..., i].mean(), abs=1e-6)
        colours = gs.read_command("r.colors.out", map=name).split()
        assert "0" in colours and colours[colours.index("0") + 1] == "0:0:0"
    n_plots = len(m.plots)
    holes = sum(len(p.interiors) for p in m.plots)
    assert grassio.vector_counts(synthetic.training)["points"] == len(m.training["label"])
    assert grassio.vector_counts(synthetic.gt_points)["points"] == n_plots
    plots_topo = grassio.vector_counts(synthetic.plots)
    assert plots_topo["centroids"] == n_plots
    assert plots_topo["areas"] == n_plots + holes
    xy, columns = grassio.read_points(synthetic.training)
    order = np.argsort(columns["cat"])
    assert np.allclose(xy[order], m.training["xy"])
    assert [columns["label"][i] for i in order] == list(m.training["label"])
    assert [columns["class"][i] for i in order] == m.training["class"]
    xy, columns = grassio.read_points(synthetic.gt_points)
    order = np.argsort(columns["plot"])
    assert np.allclose(xy[order], m.gt_points)
    geoms, columns = grassio.read_features(synthetic.plots)
    by_cat = dict(zip(columns["cat"], zip(geoms, columns["kind"])))
    for cat, (poly, kind) in enumerate(zip(m.plots, m.plot_kinds), start=1):
        back, back_kind = by_cat[cat]
        assert back_kind == kind
        assert back.symmetric_difference(poly).area < 1e-3
    geoms, columns = grassio.read_areas(synthetic.current)
    assert columns["cat"] == list(range(1, len(m.current.polygons) + 1))
    assert columns["bouwjaar"] == m.current.years
    assert columns["identificatie"] == m.current.ids
    assert max(g.symmetric_difference(p).area for g, p in zip(geoms, m.current.polygons)) < 1e-3
    # the bands read back equal the arrays
    gs.run_command("g.region", raster=synthetic.red)
    assert np.array_equal(grassio.read_raster(synthetic.green, dtype=np.int32), m.rgb[..., 1])


@pytest.mark.grass
def test_new_mapsets_start_on_the_map_region(synthetic, mapset):
    import grass.script as gs

    region = gs.region()
    assert (int(region["rows"]), int(region["cols"])) == (600, 600)
    assert float(region["n"]) == synthetic.smap.north
    assert float(region["w"]) == synthetic.smap.west


@pytest.mark.grass
def test_command_line_writes_a_map_from_anywhere(grass_session, mapset, tmp_path):
    import grass.script as gs

    script = os.path.join(HERE, "synthetic_map.py")
    run = subprocess.run([sys.executable, script, "--seed", "4", "--size", "200",
                          "--prefix", "small"], cwd=str(tmp_path), capture_output=True,
                         text=True)
    assert run.returncode == 0, run.stderr
    m = sm.generate(seed=4, size=200)
    assert "{} plots".format(len(m.plots)) in run.stdout
    info = gs.raster_info("small.blue@" + mapset)
    assert (int(info["rows"]), int(info["cols"])) == (200, 200)
    univar = gs.parse_command("r.univar", map="small.blue", flags="g")
    assert float(univar["mean"]) == pytest.approx(m.rgb[..., 2].mean(), abs=1e-6)
    assert gs.vector_info_topo("small_plots")["centroids"] == len(m.plots)
    # existing maps are kept unless --overwrite is given
    again = subprocess.run([sys.executable, script, "--seed", "4", "--size", "200",
                            "--prefix", "small"], capture_output=True, text=True)
    assert again.returncode != 0
    again = subprocess.run([sys.executable, script, "--seed", "5", "--size", "200",
                            "--prefix", "small", "--overwrite"], capture_output=True, text=True)
    assert again.returncode == 0, again.stderr
    univar = gs.parse_command("r.univar", map="small.blue", flags="g")
    assert float(univar["mean"]) == pytest.approx(
        sm.generate(seed=5, size=200).rgb[..., 2].mean(), abs=1e-6)


def test_command_line_outside_grass_refuses(tmp_path):
    env = {k: v for k, v in os.environ.items() if k != "GISRC"}
    run = subprocess.run([sys.executable, os.path.join(HERE, "synthetic_map.py"), "--size",
                          "200"], env=env, capture_output=True, text=True)
    assert run.returncode != 0 and "GRASS session" in run.stderr
    png = tmp_path / "m.png"
    run = subprocess.run([sys.executable, os.path.join(HERE, "synthetic_map.py"), "--size",
                          "200", "--png", str(png)], env=env, capture_output=True, text=True)
    assert run.returncode == 0 and png.read_bytes()[:4] == b"\x89PNG"
    assert math.isclose(int.from_bytes(png.read_bytes()[16:20], "big"), 200)


@settings(max_examples=6, deadline=None, derandomize=True)
@given(seed=st.integers(0, 10**6), size=st.sampled_from([200, 260, 320]))
def test_any_seed_and_size_keeps_the_invariants(seed, size):
    m = sm.generate(seed=seed, size=size)
    frame = shapely.box(m.west, m.south, m.east, m.north).buffer(-2)
    assert m.plots and len(m.plots) == len(m.plot_kinds) == len(m.gt_points)
    for poly, (x, y) in zip(m.plots, m.gt_points):
        assert poly.geom_type == "Polygon" and poly.is_valid and frame.contains(poly)
        assert poly.contains(Point(x, y))
    for a, b in itertools.combinations(m.plots, 2):
        assert a.distance(b) >= 6.0
    rows, cols = m.to_pixel(m.training["xy"])
    assert np.array_equal(m.drawn[rows, cols], m.training["label"])
    counts = np.bincount(m.training["label"], minlength=7)[1:]
    assert np.all((counts >= 3) & (counts <= 8)), counts
