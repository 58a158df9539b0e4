"""geom.grid.Extent: the box an input covers, for the warnings of inputs that do not meet."""

import numpy as np
import shapely

from reconstruction.geom.grid import Extent, MapImage


def test_the_extent_of_geometries_leaves_out_none_and_empty_ones():
    got = Extent.of([None, shapely.box(0, 1, 2, 3), shapely.Polygon(), shapely.box(5, -1, 6, 0)])
    assert got == Extent(0.0, -1.0, 6.0, 3.0)
    assert Extent.of([]) is None and Extent.of([None, shapely.Polygon()]) is None


def test_boxes_meet_when_they_overlap_or_touch_or_come_within_the_margin():
    a = Extent(0, 0, 10, 10)
    assert a.meets(Extent(5, 5, 20, 20)) and a.meets(Extent(10, 0, 12, 10))
    assert not a.meets(Extent(15, 0, 20, 10)) and a.meets(Extent(15, 0, 20, 10), margin=5)
    assert not Extent(15, 0, 20, 10).meets(a) and Extent(15, 0, 20, 10).meets(a, margin=5)
    assert not a.meets(Extent(0, 100010, 10, 100020), margin=10)


def test_a_map_image_is_placed_by_its_west_east_south_north_extent():
    image = MapImage(np.zeros((1, 1, 3), dtype=np.uint8), (100, 200, 10, 20))
    assert image.place == Extent(100, 10, 200, 20)
    assert image.place.text() == "x 100..200, y 10..20"
