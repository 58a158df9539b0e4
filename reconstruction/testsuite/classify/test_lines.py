"""The shapes a monochrome map's line work closes (reconstruction.classify.lines), pure.

Made-up maps, drawn here: paper 235, black ink 40, 1 m cells, strokes 2
cells wide (given, so that the tests do not depend on the measured width).
"""

import numpy as np

from reconstruction.classify import lines

PAPER, INK = 235.0, 40.0


def _outline(img, r0, c0, r1, c1, width=2, value=INK):
    img[r0:r1, c0:c0 + width] = value
    img[r0:r1, c1 - width:c1] = value
    img[r0:r0 + width, c0:c1] = value
    img[r1 - width:r1, c0:c1] = value


def _hatch(img, r0, c0, r1, c1, spacing=4, slope=1):
    """Diagonal lines 1-2 cells wide every ``spacing`` cells inside a box."""
    rows, cols = np.mgrid[r0:r1, c0:c1]
    on = ((rows + slope * cols) % spacing) < 2 if slope else (rows % spacing) < 2
    img[r0:r1, c0:c1] = np.where(on, INK, img[r0:r1, c0:c1])


def _map():
    """Two outlined blocks across a street; the left one with a hatched
    building in its corner (its own outline), the right one with a short
    word inside; a lone line in the street, too short to close anything."""
    img = np.full((120, 200), PAPER)
    _outline(img, 10, 10, 110, 90)
    _outline(img, 10, 110, 110, 190)
    _hatch(img, 12, 12, 50, 50)
    _outline(img, 10, 10, 52, 52)
    img[60:68, 130:132] = INK                # a word: L, O, T and a slanted stroke
    img[66:68, 130:135] = INK
    _outline(img, 60, 138, 68, 144)
    img[60:62, 147:153] = INK
    img[60:68, 149:151] = INK
    for k in range(8):
        img[60 + k, 156 + k // 2:158 + k // 2] = INK
    img[60:62, 95:104] = INK                 # a dash in the street
    return img


def _read(img, **kwargs):
    reading = lines.read_ink([img], 1.0, stroke=2.0, min_area=kwargs.pop("min_area", 60.0))
    return reading, lines.line_shapes(reading)


def _shape_at(shapes, row, col):
    return shapes.segments == shapes.segments[row, col]


def test_blocks_and_a_hatched_building_are_shapes_the_street_is_one():
    img = _map()
    reading, shapes = _read(img)
    # the hatched building is hatching, the paper is not, nor is the word
    assert reading.hatched[20:45, 20:45].mean() > 0.9
    assert not reading.hatched[60:100, 60:85].any() and not reading.hatched[55:75, 125:160].any()
    building = _shape_at(shapes, 30, 30)
    block = _shape_at(shapes, 80, 50)
    right = _shape_at(shapes, 80, 150)
    street = _shape_at(shapes, 5, 100)
    assert len({int(shapes.segments[r, c]) for r, c in ((30, 30), (80, 50), (80, 150),
                                                        (5, 100))}) == 4
    # each shape is its own drawn area, between the strokes
    assert abs(building.sum() - 38 * 38) < 0.15 * 38 * 38
    assert abs(right.sum() - 96 * 76) < 0.1 * 96 * 76
    assert not (block & building).any() and block.sum() > 0.8 * (96 * 76 - 40 * 40)
    # the word stays inside its block, the dash in the street: no shapes of their own
    assert right[64, 131] or shapes.lines[64, 131]
    assert street[60, 98] or shapes.lines[60, 98]
    assert shapes.shapes == 4


def test_a_line_of_colour_closes_nothing():
    """A red district limit drawn across a block does not cut it in two."""
    grey = np.full((100, 100), PAPER)
    _outline(grey, 10, 10, 90, 90)
    red, green, blue = grey.copy(), grey.copy(), grey.copy()
    red[48:51, 5:95], green[48:51, 5:95], blue[48:51, 5:95] = 200.0, 40.0, 40.0
    reading = lines.read_ink([red, green, blue], 1.0, stroke=2.0, min_area=60.0)
    shapes = lines.line_shapes(reading)
    assert shapes.segments[30, 50] == shapes.segments[70, 50]
    # in grey, the same line is ink and cuts the block
    reading = lines.read_ink([(red + green + blue) / 3.0], 1.0, stroke=2.0, min_area=60.0)
    shapes = lines.line_shapes(reading)
    assert shapes.segments[30, 50] != shapes.segments[70, 50]


def test_the_fill_tells_hatching_directions_apart():
    """Two hatched squares, one at 45 degrees, one horizontal (water), and a
    plain one: their fill features differ by direction, not by ink."""
    img = np.full((60, 200), PAPER)
    for c0 in (10, 75, 140):
        _outline(img, 5, c0, 55, c0 + 50)
    _hatch(img, 7, 12, 53, 58, slope=1)
    _hatch(img, 7, 77, 53, 123, spacing=5, slope=0)
    reading, shapes = _read(img)
    segments = shapes.segments
    fill = lines.fill_features(segments, reading)
    diagonal, horizontal, plain = (fill[segments[30, c] - 1] for c in (35, 100, 165))
    names = list(lines.FILL_FEATURES)
    ink, hatch = names.index("ink_share"), names.index("hatching_share")
    cos2, sin2 = names.index("orientation_cos"), names.index("orientation_sin")
    assert diagonal[hatch] > 0.8 and horizontal[hatch] > 0.8 and plain[hatch] == 0
    assert plain[ink] < 0.05 < diagonal[ink]
    # horizontal strokes: twice their angle is 0 (cos 1); at 135 degrees: sin -1
    assert horizontal[cos2] > 0.5 and abs(horizontal[sin2]) < 0.2
    assert abs(diagonal[cos2]) < 0.2 and abs(diagonal[sin2]) > 0.5


def test_a_blank_map_is_one_shape_and_no_data_is_no_shape():
    img = np.full((50, 50), PAPER)
    img[:, :5] = np.nan
    reading, shapes = _read(img)
    assert shapes.shapes == 1 and (shapes.segments[:, :5] == 0).all()
    assert (shapes.segments[:, 5:] == 1).all()
