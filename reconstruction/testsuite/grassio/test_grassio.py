"""GRASS I/O of the core library, in a temporary GRASS location."""

import numpy as np
import pytest
from shapely.geometry import Point, Polygon, box

pytestmark = pytest.mark.grass


@pytest.fixture
def io(mapset):
    import grass.script as gs

    from reconstruction import grassio

    gs.run_command("g.region", n=446100, s=446000, e=84100, w=84000, res=1)
    return grassio


def test_areas_round_trip_keeps_cats_holes_shared_edges_and_keyword_columns(io):
    import grass.script as gs

    courtyard = Polygon([(84050, 446050), (84090, 446050), (84090, 446090), (84050, 446090)],
                        [[(84060, 446060), (84080, 446060), (84080, 446080), (84060, 446080)]])
    geoms = [box(84000, 446000, 84010, 446010), box(84010, 446000, 84020, 446010), courtyard]
    io.write_features("plots", geoms, {"case": [1, 2, 3], "eaves": [6.5, None, 9.25],
                                       "source": ["2pm", "aligned", "o'neil"]}, cats=[5, 6, 9])
    topo = gs.vector_info_topo("plots")
    assert topo["areas"] == 4  # three plots and the courtyard hole
    assert topo["centroids"] == 3
    read, columns = io.read_features("plots")
    order = np.argsort(columns["cat"])
    assert [columns["cat"][i] for i in order] == [5, 6, 9]
    assert [columns["case"][i] for i in order] == [1, 2, 3]
    assert [columns["eaves"][i] for i in order] == [6.5, None, 9.25]
    assert [columns["source"][i] for i in order] == ["2pm", "aligned", "o'neil"]
    areas = [read[i].area for i in order]
    assert areas == pytest.approx([100, 100, 1600 - 400])
    assert read[order[0]].intersection(read[order[1]]).area == 0
    assert read[order[0]].touches(read[order[1]])


def test_noded_areas_written_fast_are_the_same_map_as_through_ogr(io):
    import grass.script as gs
    from shapely.geometry import MultiPolygon

    courtyard = Polygon([(84050, 446050), (84090, 446050), (84090, 446090), (84050, 446090)],
                        [[(84060, 446060), (84070, 446060), (84080, 446060), (84080, 446080),
                          (84060, 446080), (84060, 446070)]])
    # three footprints in a row sharing vertices (the middle one with a T-junction
    # vertex), one footprint inside the courtyard, one of two parts
    row = [box(84000, 446000, 84010, 446010),
           Polygon([(84010, 446000), (84020, 446000), (84020, 446010), (84010, 446010),
                    (84010, 446005)]),
           box(84020, 446000, 84030, 446010)]
    row[0] = Polygon([(84000, 446000), (84010, 446000), (84010, 446005), (84010, 446010),
                      (84000, 446010)])
    inner = box(84060, 446060, 84070, 446070)
    two = MultiPolygon([box(84000, 446030, 84005, 446035), box(84010, 446030, 84015, 446035)])
    geoms = row + [courtyard, inner, two]
    assert io.area_boundaries(geoms) is not None
    columns = {"case": [2, 2, 2, 4, 0, 1], "source": ["2pm"] * 4 + ["aligned", "2pm"]}
    io.write_areas("fast", geoms, columns, cats=[1, 2, 3, 4, 5, 6])
    io.write_features("slow", geoms, columns, cats=[1, 2, 3, 4, 5, 6])
    assert gs.vector_info_topo("fast") == gs.vector_info_topo("slow")
    fast, fcols = io.read_features("fast")
    slow, scols = io.read_features("slow")
    assert fcols == scols
    for a, b in zip(fast, slow):
        assert a.symmetric_difference(b).area == 0
    assert fast[fcols["cat"].index(6)].geom_type == "MultiPolygon"


def test_areas_that_are_not_noded_still_written_through_ogr(io):
    import grass.script as gs

    # a T-junction without the shared vertex: the fast path cannot build it
    geoms = [box(84000, 446000, 84010, 446010),
             box(84010, 446000, 84020, 446005), box(84010, 446005, 84020, 446010)]
    assert io.area_boundaries(geoms) is None
    # nor edges that overlap without sharing their ends, or cross
    assert io.area_boundaries([box(84000, 446000, 84010, 446010),
                               box(84010, 446002, 84020, 446008)]) is None
    assert io.area_boundaries([box(84000, 446000, 84010, 446010),
                               box(84005, 446005, 84015, 446015)]) is None
    io.write_areas("mended", geoms, {"case": [1, 2, 3]})
    assert gs.vector_info_topo("mended")["centroids"] == 3
    read, columns = io.read_features("mended")
    assert sorted(round(g.area) for g in read) == [50, 50, 100]


def test_overlapping_areas_keep_their_whole_geometry(io):
    """Footprints that overlap though their edges only meet at shared vertices (as
    neighbouring cadastre footprints do) are not noded: the shared area goes to
    both, not to neither (an area without a centroid)."""
    wedge = Polygon([(84010, 446000), (84020, 446000), (84020, 446010), (84010, 446010),
                     (84009, 446005)])
    geoms = [box(84000, 446000, 84010, 446010), wedge, box(84002, 446002, 84004, 446004)]
    assert io.area_boundaries(geoms[:2]) is None
    assert io.area_boundaries([geoms[0], geoms[2]]) is None
    io.write_areas("overlapping", geoms, {"case": [1, 2, 3]})
    read, columns = io.read_features("overlapping")
    for geom, cat in zip(read, columns["cat"]):
        assert geom.symmetric_difference(geoms[cat - 1]).area < 1e-9


def test_points_round_trip(io):
    io.write_features("pts", [Point(84001.5, 446002.5), Point(84050, 446070)],
                      {"label": [1, 4], "class": ["building", "street"]})
    xy, columns = io.read_points("pts")
    assert xy.shape == (2, 2)
    assert sorted(map(tuple, xy)) == [(84001.5, 446002.5), (84050.0, 446070.0)]
    assert sorted(columns["class"]) == ["building", "street"]


def test_raster_round_trip_with_nulls(io):
    values = np.arange(100 * 100, dtype=np.int32).reshape(100, 100) % 7
    values[0, 0] = -1
    io.write_raster("cls", values, null=-1)
    back = io.read_raster("cls")
    assert np.isnan(back[0, 0])
    assert np.array_equal(back[1:, :], values[1:, :])
    assert back[0, 1] == values[0, 1]


def test_temporary_maps_are_removed_at_cleanup(io):
    import grass.script as gs

    name = io.temp_map("vector", "t")
    io.write_features(name, [box(84000, 446000, 84010, 446010)])
    assert gs.find_file(name, element="vector")["fullname"]
    io.temp._cleanup()
    assert not gs.find_file(name, element="vector")["fullname"]


def test_region_check_and_projection(io):
    io.require_projected()  # EPSG:28992: passes
    io.write_raster("a", np.zeros((100, 100), dtype=np.int32))
    assert io.raster_region_matches(["a", "a"])


def test_table_read_from_sqlite_file_matches_v_db_select(io):
    import grass.script as gs

    io.write_features("tab", [box(84000, 446000, 84010, 446010), box(84010, 446000, 84020, 446010)],
                      {"case": [1, None], "eaves": [6.5, None], "source": ["o'neil", None]},
                      cats=[3, 7])
    link = gs.vector_db("tab")[1]
    assert link["driver"] == "sqlite"
    direct = io.maps._table_sqlite(link["database"], link["table"])
    sep, null = "\x1f", "\x1e"
    table = gs.read_command("v.db.select", map="tab", separator=sep, null_value=null)
    types = gs.read_command("v.info", map="tab", flags="c")
    via_select = io.maps._table_text(table, types, sep, null)
    assert direct[0] == via_select[0] == ["cat", "case", "eaves", "source"]
    kinds = [io.maps._column_kind(t) for t in direct[1]]
    assert kinds == [io.maps._column_kind(t) for t in via_select[1]] == [int, int, float, str]

    def values(rows):
        return sorted([io.maps._column_value(v, k) for v, k in zip(row, kinds)] for row in rows)

    assert values(direct[2]) == values(via_select[2]) == [[3, 1, 6.5, "o'neil"],
                                                          [7, None, None, None]]


def test_standard_format_points_with_categories_of_one_layer(io):
    text = ("ORGANIZATION: \nMAP THRESH:   0.000000\nVERTI:\n"
            "C  1 1\n 84001.5 446002.5\n 1     7         \n"
            "C  1 3\n 84010 446020\n 1     8\n 2     99\n 1     9\n"
            "C  1 0\n 84030 446030\n")
    xy, cats = io.maps._standard_points(text, 1)
    assert xy == [["84001.5", "446002.5"], ["84010", "446020"], ["84030", "446030"]]
    assert cats == [[7], [8, 9], []]
    assert io.maps._standard_points(text, 2)[1] == [[], [99], []]
    assert io.maps._standard_points("", 1) == ([], [])


def test_checks_take_the_answers_of_queries_started_ahead(io):
    io.prefetch_checks()
    io.require_projected()
    assert io.location_epsg() == 28992
    from reconstruction.grassio import checks as grasschecks

    assert not grasschecks._QUERIES


def test_reading_a_missing_map_fails_as_require_vector(io):
    job = io.start_read_areas("not_there")
    with pytest.raises(SystemExit):
        io.finish_read_areas(job)


def test_table_alone_and_areas_of_some_categories(io):
    import grass.script as gs

    geoms = [box(84000 + 12 * i, 446000, 84010 + 12 * i, 446010) for i in range(5)]
    io.write_features("some", geoms, {"year": [1800, None, 1900, 1950, 1700],
                                      "name": ["a", "b", "c", "d", "e"]}, cats=[2, 3, 4, 8, 9])
    table = io.read_table("some")
    assert table == {"cat": [2, 3, 4, 8, 9], "year": [1800, None, 1900, 1950, 1700],
                     "name": ["a", "b", "c", "d", "e"]}
    assert io.cat_ranges([9, 2, 3, 4, 8, 3]) == "2-4,8-9"
    read, columns = io.read_areas("some", cats=[3, 8, 9], table=False)
    assert columns == {"cat": [3, 8, 9]}
    assert [g.bounds[0] for g in read] == [84012, 84036, 84048]
    read, columns = io.read_areas("some", cats=[4])
    assert columns == {"cat": [4], "year": [1900], "name": ["c"]}
    assert io.read_areas("some", cats=[]) == ([], {"cat": [], "year": [], "name": []})
    gs.run_command("v.db.droptable", map="some", flags="f", quiet=True)
    assert io.read_table("some") == {"cat": []}
    with pytest.raises(SystemExit):
        io.read_table("no_such_map")
