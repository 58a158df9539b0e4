"""The synthetic map's other styles (synthetic_styles.py): a colour-washed cadaster and a
fire-insurance map, their parcels' truth; and the Delft map left as it was."""

import hashlib
import itertools
import math
import os
import subprocess
import sys

import numpy as np
import pytest
import shapely
from scipy import ndimage

import synthetic_map as sm
import synthetic_styles as ss
from synthetic_map import BLOCK, BUILDING, COURTYARD, DISTRICT, OUTLINE, STREET, TEXT, WATER

HERE = os.path.dirname(os.path.abspath(__file__))

#: sha256 of the Delft map's arrays, plots and points (see _digest), taken on c8c018b,
#: before the styles were added: the default map must stay byte-identical
DELFT_DIGESTS = {
    (1, 300): "95944791bd04214f28b40b473537701db3e19ed3f989393e1be10ff330f68b12",
    (2, 300): "f143e14bb1d0b29139665bc4df20160328c1b97b472b8d5e5680bd7ce13956bb",
}


def _digest(m):
    h = hashlib.sha256()
    for a in (m.rgb, m.truth, m.drawn, m.gt_points, m.training["xy"], m.training["label"]):
        h.update(np.ascontiguousarray(a).tobytes())
    for p in m.plots:
        h.update(p.wkb)
    h.update("|".join(m.plot_kinds).encode())
    return h.hexdigest()


@pytest.fixture(scope="module")
def cadaster():
    return sm.generate(seed=1, size=400, style="cadaster")


@pytest.fixture(scope="module")
def insurance():
    return sm.generate(seed=1, size=400, style="insurance")


def _pixel_centres(m):
    rows, cols = np.mgrid[0:m.shape[0], 0:m.shape[1]]
    return m.west + (cols + 0.5) * m.res, m.north - (rows + 0.5) * m.res


def _at(m, xy):
    """The pixel (row, col) of a point."""
    rows, cols = m.to_pixel(np.asarray(xy, dtype=float).reshape(1, 2))
    return int(rows[0]), int(cols[0])


@pytest.mark.parametrize("seed", [1, 2])
def test_delft_map_is_unchanged(seed):
    m = sm.generate(seed=seed, size=300)
    assert _digest(m) == DELFT_DIGESTS[(seed, 300)]
    assert m.style == "delft" and m.parcels == [] and m.courtyards == []
    assert m.classes == sm.CLASSES


@pytest.mark.parametrize("style", ["cadaster", "insurance"])
def test_same_seed_same_map_other_seed_another(style):
    a, b = (sm.generate(seed=3, size=240, style=style) for _ in range(2))
    for key in ("rgb", "truth", "drawn", "gt_points"):
        assert np.array_equal(getattr(a, key), getattr(b, key)), key
    assert [p.wkb for p in a.parcels] == [p.wkb for p in b.parcels]
    assert [p.wkb for p in a.plots] == [p.wkb for p in b.plots]
    assert a.parcel_info == b.parcel_info
    assert np.array_equal(a.training["xy"], b.training["xy"])
    other = sm.generate(seed=4, size=240, style=style)
    assert [p.wkb for p in other.parcels] != [p.wkb for p in a.parcels]
    assert np.mean(np.abs(other.rgb.astype(int) - a.rgb.astype(int))) > 5


def test_styles_have_their_resolution_classes_and_refuse_unknown_ones(cadaster, insurance):
    assert (cadaster.style, cadaster.res, insurance.style, insurance.res) == (
        "cadaster", 0.2, "insurance", 0.3)
    assert cadaster.classes == {1: "building", 2: "text", 3: "water", 4: "street",
                                7: "courtyard", 8: "outline"}
    assert insurance.classes == {1: "building", 2: "text", 4: "street", 8: "outline"}
    assert set(np.unique(cadaster.drawn)) == set(cadaster.classes)
    assert set(np.unique(insurance.drawn)) == set(insurance.classes)
    assert (cadaster.east - cadaster.west) == pytest.approx(80.0)
    assert sm.generate(seed=1, size=200, res=0.1, style="cadaster").res == 0.1
    with pytest.raises(ValueError, match="style"):
        sm.generate(seed=1, size=200, style="portolan")


@pytest.mark.parametrize("style", ["cadaster", "insurance"])
def test_parcels_valid_disjoint_and_inside_their_plot(style, cadaster, insurance):
    m = cadaster if style == "cadaster" else insurance
    frame = shapely.box(m.west, m.south, m.east, m.north)
    assert len(m.parcels) == len(m.parcel_info) >= 20
    tree = shapely.STRtree(m.parcels)
    for i, (p, info) in enumerate(zip(m.parcels, m.parcel_info)):
        assert p.geom_type == "Polygon" and p.is_valid and frame.contains(p)
        assert 1 <= info.plot <= len(m.plots)
        assert p.difference(m.plots[info.plot - 1]).area < 1e-6
        for j in tree.query(p):
            if j != i:
                assert p.intersection(m.parcels[j]).area < 1e-6, (i, j)
    for k, plot in enumerate(m.plots, start=1):
        mine = [p for p, info in zip(m.parcels, m.parcel_info) if info.plot == k]
        assert mine and plot.geom_type == "Polygon" and plot.is_valid
        courts = sum(c.area for c in m.courtyards if plot.contains(c.centroid))
        # the parcels cover their plot but its courtyards
        assert sum(p.area for p in mine) == pytest.approx(plot.area - courts, rel=1e-6)


@pytest.mark.parametrize("style", ["cadaster", "insurance"])
def test_pixel_classes_follow_the_truth(style, cadaster, insurance):
    m = cadaster if style == "cadaster" else insurance
    x, y = _pixel_centres(m)
    parcels = shapely.union_all(m.parcels)
    in_parcel = shapely.contains_xy(parcels, x, y)
    in_court = shapely.contains_xy(shapely.union_all(m.courtyards), x, y) \
        if m.courtyards else np.zeros(x.shape, bool)
    assert np.all(m.truth[in_parcel] == BUILDING)
    assert np.all(m.truth[in_court] == COURTYARD)
    # (a pixel centre on a parcel's edge may be either)
    assert not np.any(m.truth[~shapely.intersects_xy(parcels, x, y)] == BUILDING)
    assert not np.any(np.isin(m.truth, (TEXT, OUTLINE)))
    # what is drawn over the truth: lines and ink only
    over = m.drawn != m.truth
    assert set(np.unique(m.drawn[over])) <= {TEXT, OUTLINE}
    # training points on their class, 3-8 per fill of the buildings
    rows, cols = m.to_pixel(m.training["xy"])
    assert np.array_equal(m.drawn[rows, cols], m.training["label"])
    assert set(m.training["label"]) == set(m.classes)
    fills = {}
    for xy, label in zip(m.training["xy"], m.training["label"]):
        if label == BUILDING:
            owner = [info.fill for p, info in zip(m.parcels, m.parcel_info)
                     if p.contains(shapely.Point(xy))]
            fills[owner[0]] = fills.get(owner[0], 0) + 1
    wanted = ss.CADASTER_FILLS if style == "cadaster" else ss.MATERIALS
    assert set(fills) == set(wanted) and all(3 <= n <= 8 for n in fills.values()), fills


def _line_pixels(m, ring_or_line, step):
    """Pixels along a line every ``step`` metres, away from its ends."""
    n = int(ring_or_line.length / step)
    out = []
    for k in range(1, n):
        p = ring_or_line.interpolate(k * step)
        out.append(_at(m, (p.x, p.y)))
    return out


def test_cadaster_lines_darker_than_the_fills_where_parcels_meet(cadaster):
    m = cadaster
    grey = m.rgb.astype(float).mean(axis=2)
    on_line, beside, reds, ends = [], [], [], []
    for k, plot in enumerate(m.plots, start=1):
        mine = [p for p, info in zip(m.parcels, m.parcel_info) if info.plot == k]
        for line in ss._inner_lines(mine, plot):
            for r, c in _line_pixels(m, line, 0.5):
                if m.drawn[r, c] != TEXT:
                    on_line.append((r, c))
            # where it meets the block's outline: half a pixel inside the thick line
            for end in (0, 1):
                if plot.exterior.distance(shapely.Point(line.coords[-end])) < 0.05 and \
                        line.length > 2:
                    d = m.strokes.outline / 2 + 0.5 * m.res
                    p = line.interpolate(d if end == 0 else line.length - d)
                    ends.append(m.drawn[_at(m, (p.x, p.y))])
        for r, c in _line_pixels(m, plot.exterior, 0.5):
            reds.append(m.rgb[r, c].astype(int))
        for p in mine:  # the fill, 1 m inside the parcel, off the ink
            inner = p.buffer(-1.0)
            if not inner.is_empty:
                for r, c in _line_pixels(m, inner.exterior if inner.geom_type == "Polygon"
                                         else max(inner.geoms, key=lambda g: g.area).exterior,
                                         1.0):
                    if m.drawn[r, c] == BUILDING:
                        beside.append((r, c))
    assert len(on_line) > 200 and len(beside) > 200
    line_rows, line_cols = np.array(on_line).T
    fill_rows, fill_cols = np.array(beside).T
    # thin grey lines: nearly every pixel under a parcels' common edge is drawn as one
    # (some stop short of the outline, a few have gaps) and darker than every fill
    assert np.mean(m.drawn[line_rows, line_cols] == OUTLINE) > 0.9
    assert np.median(grey[line_rows, line_cols]) < np.percentile(grey[fill_rows, fill_cols], 1) - 40
    # some lines stop short of the block's outline (1-3 pixels), most meet it
    assert 0.15 < np.mean(np.array(ends) != OUTLINE) < 0.6
    # the blocks' outline is thick and dark red
    reds = np.array(reds)
    assert np.median(reds[:, 0] - reds[:, 1]) > 50 and np.median(reds.mean(axis=1)) < 140
    assert m.strokes.outline >= 1.8 * m.strokes.line and m.strokes.line >= m.res


def test_cadaster_numbers_over_nearly_every_parcel_some_across_a_line(cadaster):
    m = cadaster
    numbered = [(p, info) for p, info in zip(m.parcels, m.parcel_info) if info.number]
    assert len(numbered) >= 0.9 * len(m.parcels)
    values = [int(info.number) for _, info in numbered]
    assert values == list(range(values[0], values[0] + len(values)))
    across = 0
    for p, info in numbered:
        point = shapely.Point(info.number_xy)
        assert p.contains(point) or p.exterior.distance(point) < 1e-6
        r, c = _at(m, info.number_xy)
        window = m.drawn[max(r - 5, 0):r + 6, max(c - 5, 0):c + 6]
        assert np.any(window == TEXT)
        across += info.across
        if info.across:  # written across one of its own lines
            assert p.exterior.distance(point) < 1.0
    assert 1 <= across <= 0.3 * len(numbered)


def test_cadaster_fills_courtyards_streets_and_canal(cadaster):
    m = cadaster
    fills = [info.fill for info in m.parcel_info]
    assert set(fills) == set(ss.CADASTER_FILLS) and fills.count("pink") > len(fills) / 3
    colour = {}
    for p, info in zip(m.parcels, m.parcel_info):
        inner = p.buffer(-0.8)
        if inner.is_empty:
            continue
        r, c = _at(m, inner.representative_point().coords[0])
        if m.drawn[r, c] == BUILDING:
            colour.setdefault(info.fill, []).append(m.rgb[r, c].astype(float))
    mean = {k: np.mean(v, axis=0) for k, v in colour.items()}
    assert mean["pink"][0] - mean["pink"][2] > 50            # pink
    assert mean["yellow"][1] - mean["yellow"][2] > 50        # yellow
    assert mean["pale"].mean() > mean["pink"].mean() + 25    # nearly white
    assert mean["white"].mean() > 230
    # courtyards: white like the white parcels, unnumbered, not parcels
    assert m.courtyards
    for court in m.courtyards:
        r, c = _at(m, court.centroid.coords[0])
        assert m.drawn[r, c] == COURTYARD
        assert np.abs(m.rgb[r, c].astype(float) - mean["white"]).max() < 20
        assert not any(p.intersection(court).area > 1e-6 for p in m.parcels)
        assert not any(court.contains(shapely.Point(i.number_xy)) for i in m.parcel_info
                       if i.number)
    # buff streets, pinkish-buff squares with names; a blue canal
    street = m.rgb[m.drawn == STREET].astype(float).mean(axis=0)
    assert street[0] > street[2] + 30 and street.mean() > 180
    water = m.rgb[m.drawn == WATER].astype(float).mean(axis=0)
    assert water[2] > water[0] + 40
    assert np.any((m.drawn == TEXT) & (m.truth == STREET))


def test_insurance_buildings_one_each_by_material_outbuildings_crossed(insurance):
    m = insurance
    materials = [info.fill for info in m.parcel_info]
    assert set(materials) == set(ss.MATERIALS)
    kinds = dict(zip(*np.unique(m.plot_kinds, return_counts=True)))
    assert kinds.get("row", 0) >= 2 and kinds.get("single", 0) >= 2
    assert kinds.get("outbuilding", 0) >= 2
    counts = np.bincount([info.plot for info in m.parcel_info], minlength=len(m.plots) + 1)
    for k, kind in enumerate(m.plot_kinds, start=1):
        assert (counts[k] >= 2) == (kind == "row")
    colour = {}
    for p, info in zip(m.parcels, m.parcel_info):
        r, c = _at(m, p.centroid.coords[0])
        if info.crossed:
            # an X: both diagonals drawn, through the centre
            assert info.fill == "frame" and p.area < 25
            minx, miny, maxx, maxy = p.bounds
            for fx, fy in ((0.25, 0.25), (0.75, 0.75), (0.25, 0.75), (0.75, 0.25)):
                rr, cc = _at(m, (minx + fx * (maxx - minx), miny + fy * (maxy - miny)))
                assert OUTLINE in m.drawn[rr - 1:rr + 2, cc - 1:cc + 2], info
        else:  # its fill (off the D or S written in its middle)
            assert m.drawn[r, c] in (BUILDING, TEXT)
            minx, miny, maxx, maxy = p.bounds
            rr, cc = _at(m, (0.75 * minx + 0.25 * maxx, 0.75 * miny + 0.25 * maxy))
            assert m.drawn[rr, cc] == BUILDING
            colour.setdefault(info.fill, []).append(m.rgb[rr, cc].astype(float))
        if info.number:  # its house number, in the street in front of it
            point = shapely.Point(info.number_xy)
            assert p.distance(point) < 6.0  # (detached houses stand back 2-4 m)
            assert not any(q.contains(point) for q in m.parcels)
            rr, cc = _at(m, info.number_xy)
            assert TEXT in m.drawn[rr - 3:rr + 4, cc - 3:cc + 4]
        # its own black outline all round
        ring = _line_pixels(m, p.exterior, 0.5)
        rows, cols = np.array(ring).T
        assert np.mean(m.drawn[rows, cols] == OUTLINE) > 0.9
    mean = {k: np.mean(v, axis=0) for k, v in colour.items()}
    assert mean["frame"][1] - mean["frame"][2] > 60
    assert mean["brick"][0] - mean["brick"][1] > 45
    assert mean["stone"][2] - mean["stone"][0] > 40
    # touching buildings: a line between them; white paper around; street names and numbers
    touching = sum(1 for a, b in itertools.combinations(m.parcels, 2)
                   if a.intersection(b).length > 1.0)
    assert touching >= 5
    paper = m.rgb[m.drawn == STREET].astype(float).mean(axis=0)
    assert paper.min() > 225
    assert np.sum((m.drawn == TEXT) & (m.truth == STREET)) > 500
    assert np.sum((m.drawn == TEXT) & (m.truth == BUILDING)) > 100  # D and S
    assert sum(1 for info in m.parcel_info if info.number) > 0.5 * len(m.parcels)


@pytest.mark.parametrize("style,size,res,seed", [
    ("cadaster", 200, 0.1, 5), ("cadaster", 260, 0.25, 6), ("cadaster", 200, None, 7),
    ("insurance", 200, None, 5), ("insurance", 300, 0.5, 6)])
def test_any_seed_size_and_resolution(style, size, res, seed):
    m = sm.generate(seed=seed, size=size, res=res, style=style)
    assert m.parcels and m.plots and len(m.gt_points) == len(m.plots)
    for plot, (x, y) in zip(m.plots, m.gt_points):
        assert plot.is_valid and plot.contains(shapely.Point(x, y))
    assert sum(p.area for p in m.parcels) + sum(c.area for c in m.courtyards) == \
        pytest.approx(sum(p.area for p in m.plots), rel=1e-6)
    assert m.strokes.line >= m.res


@pytest.mark.parametrize("style", ["cadaster", "monochrome"])
def test_png_of_a_style_outside_grass(style, tmp_path):
    env = {k: v for k, v in os.environ.items() if k != "GISRC"}
    png = tmp_path / "c.png"
    run = subprocess.run([sys.executable, os.path.join(HERE, "synthetic_map.py"), "--style",
                          style, "--size", "200", "--png", str(png)], env=env,
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    assert png.read_bytes()[:4] == b"\x89PNG"
    run = subprocess.run([sys.executable, os.path.join(HERE, "synthetic_map.py"), "--style",
                          "portolan", "--png", str(png)], env=env, capture_output=True,
                         text=True)
    assert run.returncode != 0 and "invalid choice" in run.stderr
    run = subprocess.run([sys.executable, os.path.join(HERE, "synthetic_map.py"), "--help"],
                         env=env, capture_output=True, text=True)
    assert style in run.stdout


def test_outline_of_the_parcels_drawn_on_the_picture(cadaster):
    m = cadaster
    picture = sm.outline_plots(m, polygons=m.parcels, width=m.res, colour=(0, 255, 0))
    marked = np.all(picture == (0, 255, 0), axis=2)
    x, y = _pixel_centres(m)
    inside = np.zeros(m.shape, bool)
    for p in m.parcels:
        inside |= shapely.contains_xy(p.difference(p.buffer(-m.res)), x, y)
    assert marked.sum() > 0.8 * inside.sum()


@pytest.mark.grass
@pytest.mark.parametrize("style", ["cadaster", "insurance"])
def test_write_to_grass_writes_the_parcels(style, mapset):
    import grass.script as gs

    from reconstruction import grassio

    m = sm.generate(seed=2, size=200 if style == "cadaster" else 300, style=style)
    names = sm.write_map_to_grass(m, "cad")
    assert names["parcels"] == "cad_parcels"
    topo = grassio.vector_counts("cad_parcels")
    holes = sum(len(p.interiors) for p in m.parcels)
    # one area per parcel (touching parcels share their boundary: no slivers)
    assert topo["centroids"] == len(m.parcels)
    assert topo["areas"] == len(m.parcels) + holes
    geoms, columns = grassio.read_features("cad_parcels")
    by_cat = dict(zip(columns["cat"], zip(geoms, columns["plot"], columns["fill"],
                                          columns["number"])))
    for cat, (p, info) in enumerate(zip(m.parcels, m.parcel_info), start=1):
        back, plot, fill, number = by_cat[cat]
        assert (plot, fill, number) == (info.plot, info.fill, info.number)
        assert back.symmetric_difference(p).area < 1e-3
    delft = sm.generate(seed=2, size=200)
    assert "parcels" not in sm.write_map_to_grass(delft, "delft")
    assert not gs.list_strings("vector", pattern="delft_parcels")


# ---------------------------------------------------------------------------
# The monochrome map (issue 51: outlined blocks, hatched buildings and water)
# ---------------------------------------------------------------------------

#: the drawn classes that are ink lines (the hatching keeps its area's class)
_INK = (OUTLINE, TEXT, DISTRICT)


@pytest.fixture(scope="module")
def mono():
    return sm.generate(seed=1, size=600, style="monochrome")


def _hatching_fit(m, area, hatching):
    """On the pixels of ``area`` (bool raster): the share of ink, the angle (degrees,
    0-180) at which the ink pixels line up best with lines ``hatching.spacing``
    apart, the coherence (0-1) of the grey's gradients (1: all one direction) and
    how much the ink pixels keep to the drawn lines' phase (0-1: the mean resultant
    length of their positions across the lines, in periods of the spacing)."""
    grey = m.grey.astype(float)
    paper, ink = np.percentile(grey[m.drawn == STREET], 50), 50.0
    dark = area & (grey < (paper + ink) / 2)
    gy, gx = np.gradient(grey)
    gy = -gy  # rows go south: y up
    jxx, jyy, jxy = (np.sum(v[area]) for v in (gx * gx, gy * gy, gx * gy))
    coherence = math.hypot(jxx - jyy, 2 * jxy) / (jxx + jyy)
    x, y = _pixel_centres(m)
    x, y = x[dark] - x[dark].mean(), y[dark] - y[dark].mean()

    def lined_up(angle):
        turn = math.radians(angle)
        across = -x * math.sin(turn) + y * math.cos(turn)
        return float(abs(np.exp(2j * math.pi * across / hatching.spacing).mean()))

    angles = np.arange(0.0, 180.0, 0.5)
    best = angles[int(np.argmax([lined_up(a) for a in angles]))]
    return dark.sum() / area.sum(), best, coherence, lined_up(hatching.angle)


def _angle_gap(a, b):
    d = abs(a - b) % 180
    return min(d, 180 - d)


def _mask(m, geom):
    x, y = _pixel_centres(m)
    return shapely.contains_xy(geom, x, y)


def test_monochrome_style_its_resolution_classes_and_truth_fields(mono):
    m = mono
    assert (m.style, m.res, m.shape) == ("monochrome", 0.5, (600, 600))
    assert m.classes == {1: "building", 2: "text", 3: "water", 4: "street", 8: "outline",
                         9: "block", 10: "district"}
    assert set(np.unique(m.drawn)) == set(m.classes)
    assert set(np.unique(m.truth)) == {BUILDING, WATER, STREET, BLOCK}
    assert m.parcels == [] and m.courtyards == []
    kinds = set(m.plot_kinds)
    assert kinds == {"block", "building"} and len(m.plots) >= 10
    assert len(m.hatched) == len(m.hatching) >= 5 and m.water and m.water_hatching
    frame = shapely.box(m.west, m.south, m.east, m.north)
    for p in m.plots + m.hatched + m.water:
        assert p.geom_type == "Polygon" and p.is_valid and frame.buffer(1e-6).contains(p)
    # blocks apart (streets between), each hatched building inside its block
    for a, b in itertools.combinations(m.plots, 2):
        assert a.distance(b) > 1.0
    for p, h in zip(m.hatched, m.hatching):
        # (within a centimetre: a cut's corner a few mm from the block's slanted edge may
        # round onto it)
        assert m.plots[h.plot - 1].buffer(0.01).contains(p)
        assert h.spacing >= 4 * m.res and h.width >= m.res and 0 <= h.angle < 180
    for k, (plot, kind) in enumerate(zip(m.plots, m.plot_kinds), start=1):
        mine = [p for p, h in zip(m.hatched, m.hatching) if h.plot == k]
        if kind == "building":  # the whole block is one hatched building
            assert len(mine) == 1 and mine[0].symmetric_difference(plot).area < 1e-6
    inside = [p for p, kind in zip(m.plots, m.plot_kinds) if kind == "block"]
    assert sum(1 for p in m.hatched if any(p.symmetric_difference(q).area > 1 and
                                           q.contains(p.centroid) for q in inside)) >= 3
    assert {h.angle for h in m.hatching} >= {45.0, 135.0}
    assert m.water_hatching.angle == 0 and m.water_hatching.spacing > \
        1.4 * max(h.spacing for h in m.hatching)
    for plot, (x, y) in zip(m.plots, m.gt_points):
        assert plot.contains(shapely.Point(x, y))
    with pytest.raises(ValueError, match="80 m across"):
        sm.generate(seed=1, size=300, res=0.25, style="monochrome")


def test_monochrome_pixel_classes_follow_the_truth(mono):
    m = mono
    hatched = shapely.union_all(m.hatched)
    blocks = shapely.union_all(m.plots)
    water = shapely.union_all(m.water)
    assert np.all(m.truth[_mask(m, hatched)] == BUILDING)
    assert np.all(m.truth[_mask(m, blocks) & ~_mask(m, hatched.buffer(1e-6))] == BLOCK)
    assert np.all(m.truth[_mask(m, water)] == WATER)
    x, y = _pixel_centres(m)
    off = ~shapely.intersects_xy(blocks.buffer(0.01), x, y) & ~shapely.intersects_xy(water, x, y)
    assert np.all(m.truth[off] == STREET)
    # drawn over the truth: ink lines and letters only
    over = m.drawn != m.truth
    assert set(np.unique(m.drawn[over])) == set(_INK)
    # training points on their class, 3-8 per class, every class
    rows, cols = m.to_pixel(m.training["xy"])
    assert np.array_equal(m.drawn[rows, cols], m.training["label"])
    labels, counts = np.unique(m.training["label"], return_counts=True)
    assert set(labels) == set(m.classes) and all(3 <= n <= 8 for n in counts)
    assert [m.classes[int(v)] for v in m.training["label"]] == list(m.training["class"])


def test_monochrome_hatched_buildings_and_water_are_hatched_at_their_angle(mono):
    m = mono
    stroke = m.strokes.outline
    for p, h in zip(m.hatched, m.hatching):
        area = _mask(m, p.buffer(-stroke - m.res, join_style="mitre")) & (m.drawn == BUILDING)
        if area.sum() < 150:
            continue
        share, angle, coherence, phase = _hatching_fit(m, area, h)
        # parallel thin lines at the drawn angle and spacing (as much ink as width/spacing)
        assert 0.5 * h.width / h.spacing < share < 2.5 * h.width / h.spacing, (h, share)
        assert _angle_gap(angle, h.angle) <= 2 and coherence > 0.5, (h, angle, coherence)
        assert phase > 0.5, (h, phase)
    area = _mask(m, shapely.union_all(m.water).buffer(-stroke - m.res)) & (m.drawn == WATER)
    share, angle, coherence, phase = _hatching_fit(m, area, m.water_hatching)
    assert _angle_gap(angle, 0.0) <= 1 and coherence > 0.5 and phase > 0.5
    assert 0.5 * m.strokes.line / m.water_hatching.spacing < share < 0.4
    # the blocks' own paper (off letters and lines) holds no ink
    grey = m.grey.astype(float)
    paper = ndimage.binary_erosion(m.drawn == BLOCK, iterations=2)
    street = ndimage.binary_erosion(m.drawn == STREET, iterations=2)
    assert paper.sum() > 20000 and np.mean(grey[paper] < 150) < 0.002


def test_monochrome_blocks_and_streets_one_paper_ink_black_district_red(mono):
    m = mono
    paper = ndimage.binary_erosion(m.drawn == BLOCK, iterations=2)
    street = ndimage.binary_erosion(m.drawn == STREET, iterations=2)
    for band in range(3):
        a, b = m.rgb[..., band][paper].astype(float), m.rgb[..., band][street].astype(float)
        # the same colour: medians and spreads agree within a few levels (a stain may
        # lie on more of one than of the other)
        gap = np.abs(np.percentile(a, [10, 50, 90]) - np.percentile(b, [10, 50, 90]))
        assert gap[1] <= 2 and gap.max() <= 5, (band, gap)
    cream = np.median(m.rgb[street].astype(float), axis=0)
    assert cream.mean() > 190 and cream[0] - cream[2] > 25
    full = m.ink_cover  # black ink (letters) covering the pixel wholly
    black = m.rgb[(m.drawn == TEXT) & (full >= 1)].astype(float)
    assert len(black) > 50 and np.median(black.mean(axis=1)) < 90
    assert np.median(black.max(axis=1) - black.min(axis=1)) < 40  # (a brownish black)
    red = m.rgb[m.drawn == DISTRICT].astype(float)
    assert len(red) > 300
    assert np.median(red[:, 0] - red[:, 1]) > 60 and np.median(red[:, 0] - red[:, 2]) > 60
    assert m.grey.dtype == np.uint8 and m.grey.shape == m.shape
    assert np.array_equal(m.grey, np.rint(m.rgb.astype(float).mean(axis=2)).astype(np.uint8))


def test_monochrome_blocks_closed_by_ink_all_round(mono):
    m = mono
    grey = m.grey.astype(float)
    # along every block's edge: a drawn line (or letters crossing it), dark on the scan
    ring = [rc for p in m.plots for rc in _line_pixels(m, p.exterior, 0.5)]
    rows, cols = np.array(ring).T
    assert np.all(np.isin(m.drawn[rows, cols], _INK))
    assert np.mean(grey[rows, cols] < 150) > 0.95
    # no gap: no 4-connected stretch of paper joins a block's inside to a street or the water
    parts, n = ndimage.label(~np.isin(m.drawn, _INK))
    inside = np.isin(m.truth, (BLOCK, BUILDING))
    within = np.unique(parts[inside & (parts > 0)])
    outside = np.unique(parts[~inside & (parts > 0)])
    assert n > len(m.plots) and not set(within) & set(outside)
    # the dotted lines and letters inside blocks close nothing: one piece of paper per block
    # (besides its hatched buildings' lines)
    for plot, kind in zip(m.plots, m.plot_kinds):
        if kind == "block":
            own = _mask(m, plot) & (m.truth == BLOCK)
            labels = np.unique(parts[own & (parts > 0)])
            big = [k for k in labels if np.sum(parts == k) > 200]
            assert len(big) <= 3, len(big)
    # text crosses some outlines: letters touch the blocks' edges
    assert np.sum(m.drawn[rows, cols] == TEXT) >= 5


def test_monochrome_fold_and_stains_darken_or_lighten_the_paper(mono):
    m = mono
    paper = ndimage.binary_erosion(np.isin(m.drawn, (STREET, BLOCK)), iterations=2)
    grey = m.grey.astype(float)[paper]
    median = np.median(grey)
    # a stain: somewhere the paper is much darker than its median, the fold lighter
    assert np.percentile(grey, 0.1) < median - 15
    assert np.percentile(grey, 99.9) > median + 15


@pytest.mark.parametrize("size,res,seed", [(600, None, 2), (200, None, 5), (320, 0.25, 6),
                                           (200, 0.4, 8), (400, 1.0, 7)])
def test_monochrome_same_seed_same_map_any_size(size, res, seed):
    a, b = (sm.generate(seed=seed, size=size, res=res, style="monochrome") for _ in range(2))
    for key in ("rgb", "truth", "drawn", "gt_points", "ink_cover"):
        assert np.array_equal(getattr(a, key), getattr(b, key)), key
    for key in ("plots", "hatched", "water"):
        assert [p.wkb for p in getattr(a, key)] == [p.wkb for p in getattr(b, key)], key
    assert a.hatching == b.hatching and a.plot_kinds == b.plot_kinds
    assert np.array_equal(a.training["xy"], b.training["xy"])
    assert set(a.training["label"]) == set(a.classes)
    assert a.hatched and a.water and "building" in a.plot_kinds
    other = sm.generate(seed=seed + 100, size=size, res=res, style="monochrome")
    assert [p.wkb for p in other.plots] != [p.wkb for p in a.plots]


def test_monochrome_is_quick():
    import time

    start = time.process_time()
    sm.generate(seed=3, size=600, style="monochrome")
    assert time.process_time() - start < 4.0  # about 1.8 s on the development machine


@pytest.mark.grass
def test_write_to_grass_writes_the_hatched_buildings_and_water(mapset):
    from reconstruction import grassio

    m = sm.generate(seed=2, size=300, style="monochrome")
    names = sm.write_map_to_grass(m, "mono")
    assert (names["hatched"], names["water"]) == ("mono_hatched", "mono_water")
    assert "parcels" not in names
    geoms, columns = grassio.read_features("mono_hatched")
    by_cat = dict(zip(columns["cat"], zip(geoms, columns["plot"], columns["angle"],
                                          columns["spacing"])))
    assert len(by_cat) == len(m.hatched)
    for cat, (p, h) in enumerate(zip(m.hatched, m.hatching), start=1):
        back, plot, angle, spacing = by_cat[cat]
        assert (plot, angle, spacing) == pytest.approx((h.plot, h.angle, h.spacing))
        assert back.symmetric_difference(p).area < 1e-2
    geoms, columns = grassio.read_features("mono_water")
    assert len(geoms) == len(m.water) and set(columns["angle"]) == {0}
    assert sum(g.area for g in geoms) == pytest.approx(sum(p.area for p in m.water), rel=1e-4)
    geoms, columns = grassio.read_features("mono_plots")
    assert sorted(columns["kind"]) == sorted(m.plot_kinds)
