"""The LoD2 stage without GRASS: heights and roof requests, what is left out and why, ids, seeds."""

import json

import numpy as np
import pytest
from shapely.geometry import MultiPolygon, Polygon, box

from reconstruction.lod2 import stage as lod2
from reconstruction.core.errors import InputError
from reconstruction.lod2.roofs.plan import ROOF_TYPES

X0, Y0 = 85000.0, 446000.0


def row(n, seed=0):
    """n rectangles and trapezoids in a row (RD New coordinates)."""
    rng = np.random.default_rng(seed)
    out = []
    for i in range(n):
        x, w, d = X0 + 20.0 * i, rng.uniform(5, 9), rng.uniform(10, 18)
        if i % 2:
            out.append(Polygon([(x, Y0), (x + w, Y0 + 0.5), (x + w - 0.4, Y0 + d), (x, Y0 + d)]))
        else:
            out.append(box(x, Y0, x + w, Y0 + d))
    return out


def model(geoms, eaves=9.0, attic=4.0, ground=1.0, types="auto", years=np.nan, seed=1, **kw):
    n = len(geoms)
    heights = lod2.Heights(np.broadcast_to(np.asarray(eaves, dtype=float), (n,)).copy(),
                           np.broadcast_to(np.asarray(attic, dtype=float), (n,)).copy(),
                           ground, ground_default=kw.pop("ground_default", 0.0))
    requests = lod2.RoofRequests(np.broadcast_to(np.asarray(types, dtype=object), (n,)).copy(),
                                 np.full(n, years, dtype=float))
    footprints = lod2.Footprints(geoms, kw.pop("cats", None), kw.pop("plot", None),
                                 kw.pop("source", None))
    config = lod2.Lod2Config(seed=seed, **kw)
    return lod2.build(lod2.prepare(footprints, heights, requests, config), config)


def test_bad_eaves_are_left_out_and_counted():
    eaves = np.array([9.0, np.nan, -2.0, 0.0, 7.5, 8.0])
    result = model(row(6), eaves=eaves)
    assert result.report.bad_eaves == 3
    assert result.ids == ["building_1", "building_5", "building_6"]
    assert list(result.attributes["eaves_height"]) == [9.0, 7.5, 8.0]
    assert result.report.rings == 3 and result.report.dropped == 0


def test_bad_roof_heights_give_flat_roofs_and_bad_ground_the_default():
    attic = np.array([4.0, np.nan, -1.0, 4.0])
    ground = np.array([2.0, 2.0, np.nan, 2.0])
    result = model(row(4), attic=attic, ground=ground, types="gable", ground_default=-3.0)
    assert result.report.bad_attic == 2 and result.report.bad_ground == 1
    assert list(result.roof_types) == ["gable", "flat", "flat", "gable"]
    assert list(result.attributes["roof_height"]) == [4.0, 0.0, 0.0, 4.0]
    assert list(result.attributes["ground_height"]) == [2.0, 2.0, -3.0, 2.0]
    z = result.solids.vertices[:, 2] / 1000.0
    assert z.min() == pytest.approx(-3.0)


def test_parts_holes_empties_and_bowties_are_bookkept():
    courtyard = Polygon([(X0, Y0), (X0 + 20, Y0), (X0 + 20, Y0 + 20), (X0, Y0 + 20)],
                        [[(X0 + 5, Y0 + 5), (X0 + 9, Y0 + 5), (X0 + 9, Y0 + 9), (X0 + 5, Y0 + 9)]])
    two = MultiPolygon([box(X0 + 30, Y0, X0 + 36, Y0 + 12), box(X0 + 40, Y0, X0 + 46, Y0 + 12)])
    bowtie = Polygon([(X0 + 50, Y0), (X0 + 60, Y0 + 10), (X0 + 60, Y0), (X0 + 50, Y0 + 6)])
    line = Polygon([(X0 + 70, Y0), (X0 + 75, Y0), (X0 + 80, Y0)])
    geoms = [courtyard, two, None, bowtie, line, Polygon()]
    result = model(geoms, cats=[10, 20, 30, 40, 50, 60], plot=[1, 2, 3, 4, 5, 6])
    rep = result.report
    assert rep.holes_filled == 1
    assert result.ids == ["building_10", "building_20_1", "building_20_2"]
    assert result.attributes["footprint"] == [10, 20, 20]
    assert result.attributes["plot"] == [1, 2, 2]
    assert list(result.footprint) == [0, 1, 1]
    # two missing or empty geometries, a bowtie and a line
    assert rep.left_out == 4
    assert rep.left_out_reasons == {"self-intersecting outline": 1,
                                    "fewer than 3 distinct vertices": 1}
    assert rep.rings == 3 and len(result.solids) == 3


def test_same_seed_same_buildings_other_seed_other_roofs():
    a, b, c = (model(row(60), seed=s) for s in (4, 4, 5))
    assert a.ids == b.ids and list(a.roof_types) == list(b.roof_types)
    assert np.array_equal(a.solids.vertices, b.solids.vertices)
    assert lod2.citymodel_text(a) == lod2.citymodel_text(b)
    assert list(a.roof_types) != list(c.roof_types)


def test_a_building_does_not_depend_on_which_others_are_left_out():
    geoms = row(30, seed=3)
    eaves = np.full(30, 9.0)
    eaves[[0, 7, 8]] = np.nan
    full, some = model(geoms, seed=2), model(geoms, eaves=eaves, seed=2)
    keep = [i for i in range(30) if i not in (0, 7, 8)]
    assert some.ids == [full.ids[i] for i in keep]
    assert list(some.roof_types) == [full.roof_types[i] for i in keep]


def test_requested_types_override_auto_and_stepped_on_concave_is_gable():
    ell = Polygon([(X0, Y0 + 40), (X0 + 14, Y0 + 40), (X0 + 14, Y0 + 46), (X0 + 6, Y0 + 46),
                   (X0 + 6, Y0 + 56), (X0, Y0 + 56)])
    n = len(ROOF_TYPES)
    geoms = row(n) + [ell]
    types = np.array(list(ROOF_TYPES) + ["stepped"], dtype=object)
    result = model(geoms, types=types)
    want = list(ROOF_TYPES) + ["gable"]
    got = list(result.roof_types)
    assert got[:n] == want[:n]
    # concave: a gable through the skeleton, or flat when pySVCGAL is missing
    assert got[n] in ("gable", "flat")
    assert result.roof_counts()["stepped"] == 1


def test_roof_column_overrides_roof_option_where_set():
    columns = {"roof": ["Gable", None, " flat", "", "auto"]}
    req = lod2.requests_from_columns(columns, 5, roof="hip", roof_column="roof")
    assert list(req.types) == ["gable", "hip", "flat", "hip", "auto"]
    assert np.isnan(req.years).all()
    with pytest.raises(InputError, match="onion_dome"):
        lod2.requests_from_columns({"roof": ["hip", "onion_dome"]}, 2, roof_column="roof")
    with pytest.raises(InputError, match="not found"):
        lod2.requests_from_columns({}, 2, roof_column="roof")


def test_construction_years_after_the_map_are_unknown():
    columns = {"built": [1890, None, 9999, 0, "1950"]}
    req = lod2.requests_from_columns(columns, 5, map_year=1961, year_column="built")
    assert list(req.years) == [1890.0, 1961.0, 1961.0, 1961.0, 1950.0]
    req = lod2.requests_from_columns(columns, 5, year_column="built")
    assert req.years[2] == 9999.0 and np.isnan(req.years[1])


def test_heights_from_columns_and_ranges():
    columns = {"h": [9.0, None, "7.5"], "a": [3, 3, 3], "g": [1.0, None, 2.0]}
    h = lod2.heights_from_columns(columns, 3, "h", "a", "g", ground=-1.0)
    assert np.isnan(h.eaves[1]) and h.eaves[2] == 7.5 and h.ground_default == -1.0
    h = lod2.heights_from_columns(columns, 3, "missing", "also_missing", eaves_range=(6.0, 8.0),
                                  attic_range=(2.0, 2.0), ground=4.0)
    assert h.eaves == lod2.Uniform(6.0, 8.0) and list(h.ground) == [4.0] * 3
    with pytest.raises(InputError, match="missing"):
        lod2.heights_from_columns(columns, 3, "missing", "a")
    with pytest.raises(InputError, match="not numeric"):
        lod2.heights_from_columns({"h": ["tall"], "a": [1]}, 1, "h", "a")


def test_ranges_are_drawn_per_footprint_within_bounds():
    n = 40
    heights = lod2.Heights(lod2.Uniform(6.7, 17.0), lod2.Uniform(2.6, 6.0), 0.0)
    requests = lod2.RoofRequests(np.full(n, "auto", dtype=object), np.full(n, 1900.0))
    result = lod2.build(lod2.prepare(lod2.Footprints(row(n)), heights, requests))
    eaves = result.attributes["eaves_height"]
    assert eaves.min() >= 6.7 and eaves.max() <= 17.0 and np.std(eaves) > 1.0
    assert result.attributes["map_year"] == [None] * n


def test_nothing_left_to_build_is_an_input_error():
    with pytest.raises(InputError, match="No footprint left"):
        model(row(3), eaves=np.full(3, np.nan))


def test_model_text_carries_ids_attributes_and_reference_system():
    result = model(row(4), plot=[7, 7, 8, 8], source=["2pm", "aligned", "2pm", None], map_year=1924)
    doc = json.loads(lod2.citymodel_text(result, 28992, title="t"))
    assert list(doc["CityObjects"]) == result.ids
    assert doc["metadata"]["referenceSystem"].endswith("/EPSG/0/28992")
    attrs = doc["CityObjects"]["building_4"]["attributes"]
    assert attrs["plot"] == 8 and attrs["map_year"] == 1924 and "source" not in attrs
    assert attrs["footprint"] == 4 and attrs["roof_type"] in ROOF_TYPES
