"""The synthetic map's other styles: a colour-washed cadaster, a fire-insurance map and a
monochrome map.

:func:`synthetic_map.generate` draws them with ``style="cadaster"``,
``style="insurance"`` or ``style="monochrome"`` (this module's
:func:`generate`); each comes from its
own random stream of the seed, so the default (Delft) map's draws are not
changed by them. Both draw what the Delft map does not: the divisions inside
the blocks, whose truth is written beside the picture.

``cadaster`` (the Napoleonic cadaster of Venice, 1808; default 0.2 m per
pixel): ragged blocks outlined by a thick dark-red line (``strokes.outline``
= max(0.5 m, 2.5 pixels), centred on the block's edge), each divided into
parcels by thin dark-grey lines (``strokes.line`` = max(0.2 m, 1.3 pixels),
centred on the parcels' common edges; about a third of them stop 1-3 pixels
short of the block's outline, one in eight has a gap of 2-4 pixels); the
parcels washed pink (most), yellow, pale pink (nearly white) or left white;
a black parcel number over nearly every parcel (some written across one of
its lines); small white courtyards, unnumbered and outlined by a thin line,
inside some parcels (holes of the parcel: not parcels); buff streets and
pinkish-buff squares with names along the streets; a blue canal; scan noise
and JPEG compression (8 x 8 blocks, chroma halved).

``insurance`` (a Sanborn fire-insurance map, 1892; default 0.3 m per
pixel): every building drawn on its own with a thin black outline
(``strokes.outline`` = ``strokes.line`` = max(0.15 m, 1.1 pixels), centred
on its edges, so touching buildings share one line) and filled by its
material (yellow frame, pink brick, blue stone); rows of touching buildings
along the streets, detached houses, rear wings touching their house, small
yellow outbuildings at the back of the lots crossed by an X (two diagonal
black lines); a D (dwelling) or S (store) written on most houses; white
paper around; street names; house numbers in the street along the houses'
fronts; scan noise and JPEG compression.

``monochrome`` (the Atlas municipal of Paris, 1925; default 0.5 m per
pixel): black line work on cream paper, blocks and streets the same paper.
Blocks (a street grid cut by a slanted avenue and a river) are outlined
only (``strokes.outline`` = max(0.6 m, 1.8 pixels), centred on their edge);
private buildings are not drawn. Some buildings are drawn in their own
outline (the same stroke) and hatched: parallel lines ``strokes.line`` =
max(0.3 m, 1.2 pixels) wide every max(2.2 m, 4 pixels), at 45 or 135
degrees or another angle per building; most are cut from a corner of their
block (sharing its outline), some stand inside it, and the smallest block
and about one in eight others are a hatched building of their own. The
river is hatched with horizontal lines every max(3.6 m, 6.5 pixels), its two
banks outlined. Street and river names, a few building names over the
blocks, house numbers just inside the blocks' edges (some touching the
outline), dotted lines across some blocks (no outlines: they close
nothing), a district limit as a red dashed line along a street with red
district names either side; a sheet fold (a light crease with a shadow
beside it) and one or two brownish stains, scan noise and JPEG. A
greyscale scan of it is ``SyntheticMap.grey``.

Truth (:class:`synthetic_map.SyntheticMap`, world coordinates):

- ``parcels``: the cadaster's parcels (each the region between the centres of
  its lines, courtyards cut out as holes) or the insurance map's buildings as
  drawn (one polygon each, between the centres of their outlines); they touch
  but never overlap, sharing their vertices where they touch.
- ``parcel_info``: one :class:`ParcelInfo` per parcel (its plot, fill,
  number, whether crossed).
- ``plots``: the cadaster's blocks (the union of their parcels and
  courtyards: up to the centre of the thick outline); on the insurance map
  the groups of touching buildings (the union of each connected group; a
  detached house or outbuilding is a plot of its own). ``plot_kinds``:
  ``block`` (cadaster); ``row`` (two buildings or more), ``single`` or
  ``outbuilding`` (insurance).
- ``courtyards``: the cadaster's courtyards.
- Monochrome: ``plots`` are the blocks, each the region the outline closes
  (up to the centre of its stroke), the hatched buildings in it included;
  ``plot_kinds``: ``block``, or ``building`` for a block that is one hatched
  building. ``hatched``: the hatched buildings as drawn (up to the centre
  of their outline), ``hatching``: their :class:`Hatching` (angle, spacing,
  line width, plot); ``water``: the river in the map (between the centres
  of its banks), ``water_hatching``. ``parcels`` is empty. ``truth``:
  ``building`` in a hatched building (its lines and the paper between),
  ``block`` on the blocks' other paper, ``water``, ``street`` elsewhere;
  ``drawn``: ``outline`` on the blocks', buildings' and banks' outlines and
  the dots, ``text`` on the black letters, ``district`` on the red lines and
  letters, ``truth`` elsewhere (the hatching lines keep their area's class).
  ``training``: 3-8 points per class of :data:`MONOCHROME_CLASSES`.
- ``truth``: the class under each pixel's centre, lines and text left out:
  ``building`` inside a parcel, ``courtyard`` in a courtyard, ``water``,
  ``street`` (streets, squares and, on the insurance map, all the white
  paper around the buildings). ``drawn``: what is visible there: ``outline``
  (label 8) on the drawn lines (thick and thin, the X of outbuildings),
  ``text`` on the ink of numbers and names, ``truth`` elsewhere.
- ``training``: 3-8 points per visible class (:data:`CADASTER_CLASSES`,
  :data:`INSURANCE_CLASSES`), the building points 3-8 on each fill (pink,
  yellow, pale and white parcels; frame, brick and stone buildings).
"""

import math
from dataclasses import dataclass

import numpy as np
import shapely
from scipy import fft
from shapely import affinity
from shapely.geometry import LineString, MultiPoint, Point, box
from shapely.ops import polylabel, split, unary_union

import synthetic_map as sm
from synthetic_map import BLOCK, BUILDING, COURTYARD, DISTRICT, OUTLINE, STREET, TEXT, WATER

CADASTER_CLASSES = {BUILDING: "building", TEXT: "text", WATER: "water", STREET: "street",
                    COURTYARD: "courtyard", OUTLINE: "outline"}
INSURANCE_CLASSES = {BUILDING: "building", TEXT: "text", STREET: "street", OUTLINE: "outline"}
MONOCHROME_CLASSES = {BUILDING: "building", TEXT: "text", WATER: "water", STREET: "street",
                      OUTLINE: "outline", BLOCK: "block", DISTRICT: "district"}
#: the washes of the cadaster's parcels and their shares
CADASTER_FILLS = {"pink": 0.55, "yellow": 0.15, "pale": 0.15, "white": 0.15}
#: the insurance map's building materials (yellow, pink, blue) and their shares
MATERIALS = {"frame": 0.5, "brick": 0.38, "stone": 0.12}

VENICE_STREETS = (
    "CALLE LARGA", "RUGA GIUFFA", "SALIZADA", "CALLE DEI FABBRI", "CALLE DEL FORNO",
    "FONDAMENTA NOVE", "CALLE DEL PISTOR", "RIO TERA", "CALLE DEI PRETI", "CORTE NOVA",
    "CALLE LUNGA", "CALLE DEL MAGAZEN", "RAMO DEL TRAGHETTO", "CALLE DELLE BOTTEGHE",
)
VENICE_CANALS = ("RIO DI SAN LIO", "RIO DEL PALAZZO", "RIO DE LA SENSA", "RIO MARIN")
PARIS_STREETS = (
    "RUE DE VARENNE", "RUE DU BAC", "RUE DE GRENELLE", "RUE VANEAU", "RUE DE BABYLONE",
    "RUE DE LILLE", "RUE DE L UNIVERSITE", "RUE CLER", "RUE DE BOURGOGNE", "RUE DE SEVRES",
    "RUE MONSIEUR", "RUE OUDINOT", "RUE DUROC", "RUE DE BELLECHASSE", "RUE AMELIE",
)
PARIS_BUILDINGS = ("MINISTERE", "ECOLE", "EGLISE", "MAIRIE", "CASERNE", "HOPITAL", "LYCEE")
SANBORN_STREETS = (
    "MAIN ST", "FRONT ST", "WATER ST", "MARKET ST", "CHURCH ST", "ELM ST", "OAK ST",
    "WALNUT ST", "CHESTNUT ST", "MILL ST", "BRIDGE ST", "HIGH ST", "UNION ST", "PINE ST",
)

# Drawing layers of both styles (what colour a sub-pixel gets); each style has its colours.
(_GROUND, _SQUARE, _WATER, _BANK, _PINK, _YELLOW, _PALE, _WHITE, _BLUE, _COURT, _THICK,
 _THIN, _INK, _BLOCK, _HATCHED, _HATCH, _WATER_HATCH, _RED, _DOTS) = range(19)
_FILL_LAYER = {"pink": _PINK, "yellow": _YELLOW, "pale": _PALE, "white": _WHITE,
               "frame": _YELLOW, "brick": _PINK, "stone": _BLUE}
_FILLS = (_PINK, _YELLOW, _PALE, _WHITE, _BLUE)
_LAYER_CLASS = np.array([STREET, STREET, WATER, WATER, BUILDING, BUILDING, BUILDING, BUILDING,
                         BUILDING, COURTYARD, OUTLINE, OUTLINE, TEXT,
                         # the monochrome map's: block paper, a hatched building's paper and
                         # its hatching, the water's hatching, red lines and text, dots
                         BLOCK, BUILDING, BUILDING, WATER, DISTRICT, OUTLINE], dtype=np.int32)
_CADASTER_COLOUR = np.array([
    (222, 204, 172),  # streets: buff
    (228, 192, 168),  # squares: pinkish buff
    (146, 182, 206),  # canal
    (98, 132, 172),   # canal bank line
    (228, 158, 148),  # pink wash
    (234, 212, 138),  # yellow wash
    (242, 222, 214),  # pale pink, nearly white
    (247, 243, 234),  # white (unwashed) parcel
    (150, 182, 214),  # (blue: not on the cadaster)
    (247, 243, 234),  # courtyard: the white parcels' colour
    (136, 40, 34),    # block outline, dark red
    (62, 56, 54),     # parcel lines, dark grey
    (28, 24, 24),     # ink
], dtype=np.float64)
_INSURANCE_COLOUR = np.array([
    (246, 244, 236),  # white paper: streets and yards
    (246, 244, 236),
    (146, 182, 206),
    (98, 132, 172),
    (236, 164, 156),  # brick, pink
    (240, 218, 120),  # frame, yellow
    (242, 222, 214),
    (247, 243, 234),
    (150, 182, 218),  # stone, blue
    (247, 243, 234),
    (30, 28, 28),
    (30, 28, 28),     # building outlines and crosses, black
    (24, 22, 22),     # ink
], dtype=np.float64)

_CREAM, _BLACK = (224, 215, 184), (44, 40, 32)
#: the monochrome map: black line work on cream paper (colours measured on the Paris atlas)
_MONOCHROME_COLOUR = np.array(
    [_CREAM] * 3 + [_BLACK] + [_CREAM] * 6 + [_BLACK] * 3 + [_CREAM] * 2 + [_BLACK] * 2
    + [(204, 44, 40)] + [_BLACK], dtype=np.float64)
_COLOURS = {"cadaster": _CADASTER_COLOUR, "insurance": _INSURANCE_COLOUR,
            "monochrome": _MONOCHROME_COLOUR}
_CLASSES = {"cadaster": CADASTER_CLASSES, "insurance": INSURANCE_CLASSES,
            "monochrome": MONOCHROME_CLASSES}
_JPEG_QUALITY = {"cadaster": 60, "insurance": 70, "monochrome": 65}

# JPEG's quantisation tables (ITU T.81, annex K), quality 50
_JPEG_LUMA = np.array([
    [16, 11, 10, 16, 24, 40, 51, 61], [12, 12, 14, 19, 26, 58, 60, 55],
    [14, 13, 16, 24, 40, 57, 69, 56], [14, 17, 22, 29, 51, 87, 80, 62],
    [18, 22, 37, 56, 68, 109, 103, 77], [24, 35, 55, 64, 81, 104, 113, 92],
    [49, 64, 78, 87, 103, 121, 120, 101], [72, 92, 95, 98, 112, 100, 103, 99]], dtype=float)
_JPEG_CHROMA = np.full((8, 8), 99.0)
_JPEG_CHROMA[:4, :4] = [[17, 18, 24, 47], [18, 21, 26, 66], [24, 26, 56, 99], [47, 66, 99, 99]]


@dataclass(frozen=True)
class ParcelInfo:
    """What the map draws of one parcel (``SyntheticMap.parcel_info``).

    ``plot``: 1-based index of its plot in ``SyntheticMap.plots``; ``fill``:
    one of :data:`CADASTER_FILLS` or :data:`MATERIALS`; ``number``: the
    number written for it, centred at ``number_xy`` (world coordinates), or
    None: the cadaster's parcel number, over the parcel; the insurance map's
    house number, in the street in front of the house (its wings and
    outbuildings have none); ``across``: the number is written across one of
    the parcel's lines (cadaster); ``crossed``: an outbuilding crossed by an
    X (insurance).
    """

    plot: int
    fill: str
    number: str = None
    number_xy: tuple = None
    across: bool = False
    crossed: bool = False


@dataclass(frozen=True)
class Strokes:
    """Widths (m) of the lines a style draws: ``outline`` around the blocks (cadaster)
    or the buildings (insurance), ``line`` between the parcels (cadaster) or the
    buildings (insurance: the same as ``outline``)."""

    outline: float
    line: float


@dataclass(frozen=True)
class Hatching:
    """Parallel thin ink lines filling a shape (monochrome map): ``angle`` of the lines
    (degrees anticlockwise from east, 0-180), ``spacing`` between their centres and
    ``width`` of each (m); ``plot``: 1-based index in ``SyntheticMap.plots`` of the
    block a hatched building stands in (0 for the water)."""

    angle: float
    spacing: float
    width: float
    plot: int = 0


@dataclass(frozen=True)
class _Drawing:
    """What a style draws, in local metres (origin south-west), before the scan."""

    ground: list       # [(polygon, layer)] burnt first (squares, water)
    parcels: list      # polygons, filled by their fill
    info: list         # ParcelInfo per parcel (number_xy local)
    courtyards: list   # polygons (white, not parcels)
    lines: list        # [(polygon, layer)] burnt over the fills, in order (outlines,
    #                    lines, crosses), in small pieces: each is burnt in its own window
    texts: list        # [(text, centre, angle, height, stroke)]
    plots: list
    kinds: list
    strokes: Strokes
    # (monochrome) [(polygon, Hatching, layer)] hatched after the ground, under the lines;
    # the hatched buildings and their Hatching, the water and its Hatching
    hatches: list = ()
    hatched: list = ()
    hatching: list = ()
    water: list = ()
    water_hatching: Hatching = None


def generate(seed, size, res, origin, style):
    """The map of ``style`` (``cadaster``, ``insurance`` or ``monochrome``): a
    SyntheticMap."""
    rng = np.random.default_rng([seed, {"cadaster": 31, "insurance": 32,
                                        "monochrome": 33}[style]])
    extent = size * res
    draw = {"cadaster": _cadaster, "insurance": _insurance, "monochrome": _monochrome}[style]
    drawing = draw(rng, extent, res)
    return _scan(rng, drawing, seed, size, res, origin, style)


# ---------------------------------------------------------------------------
# Shared geometry
# ---------------------------------------------------------------------------

def _parts(geom):
    return [g for g in getattr(geom, "geoms", [geom]) if g.geom_type == "Polygon"
            and not g.is_empty]


def _noded(polygons):
    """The polygons with each other's vertices inserted where they touch (no vertex
    lies on another's edge), on a 1 cm grid: their union has no slivers and GRASS
    builds one area each. (The grid is not kept as the polygons' precision: later
    operations are not snapped to it.)"""
    points = MultiPoint([c for p in polygons for ring in (p.exterior, *p.interiors)
                         for c in ring.coords])
    out = []
    for p in polygons:
        q = shapely.set_precision(shapely.snap(p, points, 1e-6), 0.01)
        out.append(shapely.set_precision(max(_parts(q), key=lambda g: g.area), 0.0))
    return out


def _width(poly):
    """The shorter side of a polygon's oriented envelope."""
    xy = np.asarray(shapely.oriented_envelope(poly).exterior.coords)
    sides = np.hypot(*np.diff(xy[:3], axis=0).T)
    return float(sides.min())


def _band(poly, width):
    """The band ``width`` wide centred on a polygon's rings (buffering a closed ring
    with flat ends may fill it)."""
    return poly.buffer(width / 2, join_style="mitre").difference(
        poly.buffer(-width / 2, join_style="mitre"))


def _strokes(poly, width):
    """The band ``width`` wide centred on a polygon's rings as one rectangle per edge
    (square ends close the corners): small pieces, each burnt in its own window."""
    out = []
    for ring in (poly.exterior, *poly.interiors):
        xy = np.asarray(ring.coords)
        for a, b in zip(xy[:-1], xy[1:]):
            if np.hypot(*(b - a)) > 1e-6:
                out.append(LineString([a, b]).buffer(width / 2, cap_style="square"))
    return out


def _inner_lines(parcels, block):
    """The parcels' common edges inside a block: a list of LineStrings."""
    lines = unary_union([p.exterior for p in parcels]).difference(
        block.boundary.buffer(0.02))
    lines = shapely.line_merge(lines) if not lines.is_empty else lines
    return [g for g in getattr(lines, "geoms", [lines]) if g.geom_type == "LineString"
            and g.length > 1e-3]


def _number(rng, text, parcel, lines, height, res, across_share):
    """Where a parcel's number is written: (centre, across): inside, or with
    ``across_share`` centred just inside one of the parcel's own ``lines`` (so
    that it is written across it)."""
    centre = polylabel(parcel, tolerance=0.05)
    if rng.random() >= across_share:
        return centre, False
    edge = parcel.exterior.buffer(1e-3)
    own = [ln for ln in lines if ln.distance(parcel.exterior) < 1e-3
           and ln.intersection(edge).length > 1.0]
    if own:
        line = own[int(rng.integers(len(own)))]
        q = line.interpolate(line.project(centre))
        d = centre.distance(q)
        if d > 0.6 * height:
            back = 0.3 * height / d
            return Point(q.x + (centre.x - q.x) * back, q.y + (centre.y - q.y) * back), True
    return centre, False


# ---------------------------------------------------------------------------
# Cadaster
# ---------------------------------------------------------------------------

def _ragged(rng, x0, y0, x1, y1, room):
    """A block [x0, x1] x [y0, y1] with stepped edges: notches and bumps of 0.25-1.2 m
    (bumps at most ``room`` (west, south, east, north) m outwards) and a few cut
    corners."""
    poly = sm._rect(x0, y0, x1, y1)
    sides = (("w", y0, y1), ("s", x0, x1), ("e", y0, y1), ("n", x0, x1))
    for (side, a0, a1), out_room in zip(sides, room):
        t = a0 + rng.uniform(1, 6)
        while True:
            w = rng.uniform(2, 7)
            if t + w > a1 - 1:
                break
            d = rng.uniform(0.25, 1.2)
            outward = rng.random() < 0.5 and out_room >= 0.25
            d = min(d, out_room) if outward else d
            lo, hi = (-d, 0.0) if outward else (0.0, d)  # inward depth from the edge
            if side == "w":
                step = sm._rect(x0 + lo, t, x0 + hi, t + w)
            elif side == "e":
                step = sm._rect(x1 - hi, t, x1 - lo, t + w)
            elif side == "s":
                step = sm._rect(t, y0 + lo, t + w, y0 + hi)
            else:
                step = sm._rect(t, y1 - hi, t + w, y1 - lo)
            poly = poly.union(step) if outward else poly.difference(step)
            t += w + rng.uniform(2, 8)
    for cx, cy, sx, sy in ((x0, y0, 1, 1), (x1, y0, -1, 1), (x1, y1, -1, -1), (x0, y1, 1, -1)):
        if rng.random() < 0.3:
            a, b = rng.uniform(1, 3, size=2)
            poly = poly.difference(shapely.Polygon([(cx - sx, cy - sy), (cx + sx * a, cy - sy),
                                                    (cx + sx * a, cy), (cx, cy + sy * b),
                                                    (cx - sx, cy + sy * b)]))
    return max(_parts(poly), key=lambda g: g.area)


def _cut(rng, poly):
    """Two or more pieces of ``poly`` cut across its length (slightly slanted), or
    None if a piece would be too small or too thin for a parcel."""
    xy = np.asarray(shapely.oriented_envelope(poly).exterior.coords)
    e0, e1 = xy[1] - xy[0], xy[2] - xy[1]
    u = e0 if np.hypot(*e0) >= np.hypot(*e1) else e1
    length = float(np.hypot(*u))
    u = u / length
    centre = np.asarray(shapely.oriented_envelope(poly).centroid.coords[0])
    p = centre + u * rng.uniform(-0.2, 0.2) * length
    theta = math.radians(rng.uniform(-7, 7))
    v = np.array([-u[1], u[0]])
    v = v * math.cos(theta) + u * math.sin(theta)
    reach = 2 * length + 10
    pieces = _parts(split(poly, LineString([p - v * reach, p + v * reach])))
    if len(pieces) < 2 or any(g.area < 12 or _width(g) < 2.6 for g in pieces):
        return None
    return pieces


def _split_block(rng, block):
    """The parcels of a block: cut across their length until small enough."""
    target = rng.uniform(30, 90)
    out, todo = [], [block]
    while todo:
        poly = todo.pop()
        pieces = None
        if poly.area > target * rng.uniform(0.8, 1.5):
            for _ in range(6):
                pieces = _cut(rng, poly)
                if pieces:
                    break
        if pieces:
            todo.extend(pieces)
        else:
            out.append(poly)
    return out


def _courtyard(rng, parcel):
    """A small rectangle well inside ``parcel`` (2-4.5 m x 2-5 m, on a 1 cm grid), or None."""
    inner = parcel.buffer(-0.9)
    if inner.is_empty:
        return None
    minx, miny, maxx, maxy = inner.bounds
    for _ in range(15):
        w, h = rng.uniform(2.0, 4.5), rng.uniform(2.0, 5.0)
        x, y = rng.uniform(minx, maxx - w) if maxx - w > minx else minx, \
            rng.uniform(miny, maxy - h) if maxy - h > miny else miny
        rect = box(*np.round([x, y, x + w, y + h], 2))
        if inner.contains(rect):
            return rect
    return None


def _grid_and_water(rng, extent, cuts, slant, middle, width, quay):
    """A street grid and a straight band of water across it from west to east: the
    grid's column and row intervals (:func:`synthetic_map._cuts` with ``cuts``), the
    band's slant (radians, ``slant`` degrees either way), centre line (its middle at
    ``middle`` of the map's height), width (m, drawn in ``width``), the band and its
    quays (``quay`` m more on each side)."""
    cols = sm._cuts(rng, extent, **cuts)
    rows = sm._cuts(rng, extent, **cuts)
    angle = math.radians(rng.uniform(*slant) * rng.choice([-1, 1]))
    y_mid = rng.uniform(*middle) * extent
    half = math.tan(angle) * (extent / 2 + 20)
    line = LineString([(-20, y_mid - half), (extent + 20, y_mid + half)])
    w = rng.uniform(*width)
    band = line.buffer(w / 2, cap_style="flat")
    quays = line.buffer(w / 2 + rng.uniform(*quay), cap_style="flat")
    return cols, rows, angle, line, w, band, quays


def _cadaster_layout(rng, extent):
    """Blocks (ragged), squares and the canal of a cadaster, in local metres."""
    cols, rows, angle, canal_line, width, canal, quays = _grid_and_water(
        rng, extent, dict(block=(16, 40), street=(2.2, 5.5), start=(2, 5), edge=2, last=10),
        slant=(3, 12), middle=(0.3, 0.7), width=(5, 9), quay=(0.3, 2.5))

    def room(intervals, i, end):
        lo = intervals[i][0] - (intervals[i - 1][1] if i else 0.0)
        hi = (intervals[i + 1][0] if i + 1 < len(intervals) else end) - intervals[i][1]
        return max(0.0, lo / 2 - 0.8), max(0.0, hi / 2 - 0.8)

    cells = [(ci, ri) for ri in range(len(rows)) for ci in range(len(cols))]
    dry = [k for k, (ci, ri) in enumerate(cells)
           if not sm._rect(cols[ci][0], rows[ri][0], cols[ci][1], rows[ri][1]).intersects(quays)]
    square = int(rng.choice(dry)) if len(cells) >= 6 and dry else -1
    blocks, squares = [], []
    for k, (ci, ri) in enumerate(cells):
        (x0, x1), (y0, y1) = cols[ci], rows[ri]
        if k == square:
            squares.append(sm._rect(x0, y0, x1, y1))
            continue
        (west, east), (south, north) = room(cols, ci, extent), room(rows, ri, extent)
        block = _ragged(rng, x0, y0, x1, y1, (west, south, east, north))
        for piece in _parts(block.difference(quays)):
            if piece.area >= 40 and _width(piece) >= 4:
                blocks.append(piece)
    anchors = [("h", (a[1] + b[0]) / 2, b[0] - a[1]) for a, b in zip(rows[:-1], rows[1:])]
    anchors += [("v", (a[1] + b[0]) / 2, b[0] - a[1]) for a, b in zip(cols[:-1], cols[1:])]
    return {"blocks": blocks, "squares": squares, "canal": canal, "quays": quays,
            "canal_line": canal_line, "canal_angle": math.degrees(angle),
            "street_anchors": anchors}


def _cadaster(rng, extent, res):
    layout = _cadaster_layout(rng, extent)
    strokes = Strokes(outline=max(0.5, 2.5 * res), line=max(0.2, 1.3 * res))
    fills, shares = list(CADASTER_FILLS), np.array(list(CADASTER_FILLS.values()))
    parcels, owner, courtyards, plots = [], [], [], []
    for block in layout["blocks"]:
        pieces = _noded(_split_block(rng, block))
        courts = []
        if block.area >= 150 and rng.random() < 0.6:
            for i in rng.permutation(len(pieces))[: int(rng.integers(1, 3))]:
                court = _courtyard(rng, pieces[i]) if pieces[i].area >= 40 else None
                if court is not None:
                    pieces[i] = pieces[i].difference(court)
                    courts.append(court)
        plots.append(unary_union(pieces + courts))
        parcels += pieces
        owner += [len(plots)] * len(pieces)
        courtyards += courts
    if not courtyards and parcels:  # every map has one at least
        i = int(np.argmax([p.area for p in parcels]))
        court = _courtyard(rng, parcels[i])
        if court is not None:
            parcels[i] = parcels[i].difference(court)
            courtyards.append(court)

    # lines: the parcels' common edges, some stopping short of the outline, a few with a gap
    lines, texts, info = [], [], []
    thin_lines = []
    number = int(rng.integers(100, 2000))
    per_block = {}
    for b, block in enumerate(plots, start=1):
        mine = [p for p, o in zip(parcels, owner) if o == b]
        inner = _inner_lines(mine, block)
        per_block[b] = inner
        for line in inner:
            for end in (0, 1):
                tip = Point(line.coords[-end])
                if block.exterior.distance(tip) < 0.05 and rng.random() < 0.35 \
                        and line.length > 2 * strokes.outline + 4 * res:
                    short = strokes.outline / 2 + int(rng.integers(1, 4)) * res
                    line = shapely.ops.substring(line, short, line.length) if end == 0 else \
                        shapely.ops.substring(line, 0, line.length - short)
            if line.length > 3 and rng.random() < 0.125:
                gap = int(rng.integers(2, 5)) * res
                at = rng.uniform(1, line.length - 1 - gap)
                thin_lines += [shapely.ops.substring(line, 0, at),
                               shapely.ops.substring(line, at + gap, line.length)]
            else:
                thin_lines.append(line)
    lines += [(ln.buffer(strokes.line / 2, cap_style="flat"), _THIN) for ln in thin_lines]
    lines += [(_band(c, strokes.line), _THIN) for c in courtyards]
    lines += [(g, _THICK) for p in plots for g in _strokes(p, strokes.outline)]
    # names along the streets and the canal, then a number over nearly every parcel
    style = sm.LabelStyle(canal_names=VENICE_CANALS, street_names=VENICE_STREETS,
                          building_names=(), scale=0.25)
    for text, centre, angle, height in sm._labels(rng, layout, extent, style):
        texts.append((text, centre, angle, height, max(0.15 * height, 0.9 * res)))
    for parcel, b in zip(parcels, owner):
        fill = fills[int(rng.choice(len(fills), p=shares))]
        if rng.random() < 0.06:
            info.append(ParcelInfo(plot=b, fill=fill))
            continue
        text = str(number)
        number += 1
        height = max(rng.uniform(1.0, 1.4), 5 * res)
        centre, across = _number(rng, text, parcel, per_block[b], height, res, 0.12)
        angle = rng.uniform(-4, 4)
        texts.append((text, (centre.x, centre.y), angle, height, max(0.14, 0.8 * res)))
        info.append(ParcelInfo(plot=b, fill=fill, number=text, number_xy=(centre.x, centre.y),
                               across=across))
    ground = [(g, _SQUARE) for g in layout["squares"]]
    ground += [(layout["canal"], _WATER),
               (layout["canal"].difference(layout["canal"].buffer(-max(0.25, 1.2 * res))),
                _BANK)]
    return _Drawing(ground=ground, parcels=parcels, info=info, courtyards=courtyards,
                    lines=lines, texts=texts, plots=plots, kinds=["block"] * len(plots),
                    strokes=strokes)


# ---------------------------------------------------------------------------
# Insurance map
# ---------------------------------------------------------------------------

def _insurance(rng, extent, res):
    cols = sm._cuts(rng, extent, block=(40, 75), street=(10, 16), start=(3, 8), edge=3,
                    last=25)
    rows = sm._cuts(rng, extent, block=(40, 75), street=(10, 16), start=(3, 8), edge=3,
                    last=25)
    strokes = Strokes(outline=max(0.15, 1.1 * res), line=max(0.15, 1.1 * res))
    materials, shares = list(MATERIALS), np.array(list(MATERIALS.values()))
    buildings, info, texts = [], [], []
    num_height = max(1.2, 5 * res)
    mark_height = max(1.4, 5 * res)
    for (x0, x1), (y0, y1) in ((c, r) for r in rows for c in cols):
        horizontal = x1 - x0 >= y1 - y0
        a0, a1 = (x0, x1) if horizontal else (y0, y1)
        depth = ((y1 - y0) if horizontal else (x1 - x0)) / 2
        mode = str(rng.choice(["row", "row", "mixed", "detached"]))
        block = []
        for side in (0, 1):
            # (along, in from the street) -> local metres
            if horizontal:
                def at(a, c, side=side):
                    return (a, y0 + c) if side == 0 else (a, y1 - c)
            else:
                def at(a, c, side=side):
                    return (x0 + c, a) if side == 0 else (x1 - c, a)

            def rect(a, b, c, d, at=at):
                return sm._rect(*at(a, c), *at(b, d))

            house = int(rng.integers(5, 60)) * 2 + side
            t = a0
            while t < a1 - 4:
                w = rng.uniform(6, 12)
                if a1 - (t + w) < 5:
                    w = a1 - t
                lot = (t, t + w)
                t += w
                house += 2
                if rng.random() < 0.12:
                    continue  # a vacant lot
                detached = mode == "detached" or (mode == "mixed" and rng.random() < 0.5)
                inset = rng.uniform(1.0, 2.0) if detached else 0.0
                back = rng.uniform(2, 4) if detached else 0.0
                deep = rng.uniform(9, min(18, depth - 5))
                main = rect(lot[0] + inset, lot[1] - inset, back, back + deep)
                material = materials[int(rng.choice(3, p=shares))]
                # the house number in the street, in front of the house
                centre = at((lot[0] + lot[1]) / 2, -(0.6 + num_height / 2))
                angle = 0.0 if horizontal else 90.0
                texts.append((str(house), centre, angle, num_height, max(0.14, 0.8 * res)))
                block.append((main, material, False, str(house), centre))
                if rng.random() < 0.6:  # D (dwelling) or S (store) written on it
                    mark = "S" if not detached and material != "frame" else "D"
                    height = min(mark_height, 0.5 * min(w - 2 * inset, deep))
                    texts.append((mark, (main.centroid.x, main.centroid.y), angle, height,
                                  max(0.14, 0.8 * res)))
                if rng.random() < 0.3 and back + deep + 4 < depth - 5:
                    narrow = rng.uniform(0, 1.5, size=2)
                    wing = rect(lot[0] + inset + narrow[0], lot[1] - inset - narrow[1],
                                back + deep, back + deep + rng.uniform(3, 5))
                    block.append((wing, materials[int(rng.choice(3, p=shares))], False, None,
                                  None))
                if rng.random() < 0.4:
                    s, d = rng.uniform(2.5, 4.0), rng.uniform(2.5, 4.5)
                    c = rng.uniform(lot[0] + 0.8, max(lot[0] + 0.8, lot[1] - 0.8 - s))
                    shed = rect(c, c + s, depth - 1 - d, depth - 1)
                    if all(shed.distance(g[0]) >= 1.0 for g in block):
                        block.append((shed, "frame", True, None, None))
        buildings += [g for g, _, _, _, _ in block]
        info += [ParcelInfo(plot=0, fill=m, number=n, number_xy=xy, crossed=x)
                 for _, m, x, n, xy in block]
    buildings = _noded(buildings)
    # plots: the groups of touching buildings
    groups = _parts(unary_union(buildings))
    tree = shapely.STRtree(groups)
    owner = [int(tree.query(b.representative_point(), predicate="within")[0]) for b in buildings]
    info = [ParcelInfo(plot=o + 1, fill=i.fill, number=i.number, number_xy=i.number_xy,
                       crossed=i.crossed) for o, i in zip(owner, info)]
    counts = np.bincount(owner, minlength=len(groups))
    kinds = []
    for g in range(len(groups)):
        if counts[g] > 1:
            kinds.append("row")
        else:
            kinds.append("outbuilding" if info[owner.index(g)].crossed else "single")
    outlines = [_band(b, strokes.outline) for b in buildings]
    for b, i in zip(buildings, info):
        if i.crossed:
            minx, miny, maxx, maxy = b.bounds
            outlines += [LineString(d).buffer(strokes.outline / 2, cap_style="flat") for d in
                         (((minx, miny), (maxx, maxy)), ((minx, maxy), (maxx, miny)))]
    lines = [(g, _THIN) for g in outlines]
    layout = {"canal_line": None, "quays": None, "street_anchors":
              [("h", (a[1] + b[0]) / 2, b[0] - a[1]) for a, b in zip(rows[:-1], rows[1:])]
              + [("v", (a[1] + b[0]) / 2, b[0] - a[1]) for a, b in zip(cols[:-1], cols[1:])]}
    style = sm.LabelStyle(canal_names=(), street_names=SANBORN_STREETS, building_names=(),
                          scale=0.5)
    texts += [(text, centre, angle, height, max(0.12 * height, 0.9 * res))
              for text, centre, angle, height in sm._labels(rng, layout, extent, style)]
    return _Drawing(ground=[], parcels=buildings, info=info, courtyards=[], lines=lines,
                    texts=texts, plots=groups, kinds=kinds, strokes=strokes)


# ---------------------------------------------------------------------------
# Monochrome map
# ---------------------------------------------------------------------------

def _dashes(line, on, off, width, phase=0.0):
    """A dashed line: pieces ``on`` m long every ``on + off`` m, ``width`` wide."""
    out, t = [], phase
    while t < line.length:
        piece = shapely.ops.substring(line, t, min(t + on, line.length))
        if piece.length > 1e-3:
            out.append(piece.buffer(width / 2, cap_style="flat"))
        t += on + off
    return out


def _hatched_building(rng, block):
    """A building drawn hatched in ``block``: the block cut by a rectangle from one of
    its corners (its own outline then shares the block's) or one standing 3 m or more
    inside it; None if none fits."""
    minx, miny, maxx, maxy = block.bounds
    w, h = rng.uniform(0.25, 0.6) * (maxx - minx), rng.uniform(0.25, 0.6) * (maxy - miny)
    if rng.random() < 0.7:  # from a corner, past the block's edges
        x = minx - 5 if rng.random() < 0.5 else maxx - w
        y = miny - 5 if rng.random() < 0.5 else maxy - h
        cut = block.intersection(box(*np.round([x, y, x + w + 5, y + h + 5], 2)))
    else:
        inner = block.buffer(-3.0, join_style="mitre")
        if inner.is_empty:
            return None
        x0, y0, x1, y1 = inner.bounds
        if x1 - x0 <= w or y1 - y0 <= h:
            return None
        x, y = rng.uniform(x0, x1 - w), rng.uniform(y0, y1 - h)
        cut = inner.intersection(box(*np.round([x, y, x + w, y + h], 2)))
    parts = _parts(cut)
    if not parts:
        return None
    building = max(parts, key=lambda g: g.area)
    return building if building.area >= 60 and _width(building) >= 5 else None


def _monochrome_layout(rng, extent):
    """Blocks, the river and the avenue of a monochrome map, in local metres."""
    cols, rows, angle, river_line, width, river, quays = _grid_and_water(
        rng, extent, dict(block=(min(35, extent / 4), min(85, extent / 2.5)), street=(8, 15),
                          start=(3, 8), edge=3, last=min(20, extent / 5)),
        slant=(2, 8), middle=(0.25, 0.75), width=(0.08 * extent, 0.13 * extent),
        quay=(6, 10))
    # an avenue across the grid, slanted
    a = math.radians(rng.uniform(30, 60) * rng.choice([-1, 1]))
    cx, cy = rng.uniform(0.3, 0.7, size=2) * extent
    reach = 2 * extent
    avenue = LineString([(cx - reach * math.cos(a), cy - reach * math.sin(a)),
                         (cx + reach * math.cos(a), cy + reach * math.sin(a))]).buffer(
        rng.uniform(10, 15) / 2, cap_style="flat")
    blocks = []
    for (x0, x1), (y0, y1) in ((c, r) for r in rows for c in cols):
        cell = sm._rect(x0, y0, x1, y1).difference(quays).difference(avenue)
        for piece in _parts(shapely.set_precision(cell, 0.01)):
            if piece.area >= 150 and _width(piece) >= 8:
                blocks.append(piece)
    anchors = [("h", (a[1] + b[0]) / 2, b[0] - a[1]) for a, b in zip(rows[:-1], rows[1:])]
    anchors += [("v", (a[1] + b[0]) / 2, b[0] - a[1]) for a, b in zip(cols[:-1], cols[1:])]
    return {"blocks": blocks, "river": river, "quays": quays, "canal_line": river_line,
            "canal_angle": math.degrees(angle), "river_width": width,
            "street_anchors": anchors}


def _touching(rng, labels, layout):
    """The labels with about a third of the street names moved across their street
    until their letters overlap a block's outline by 10-50 % of their height (where
    they then stay clear of the other labels and the river)."""
    out = list(labels)
    for i, (text, centre, angle, height) in enumerate(labels):
        if text not in PARIS_STREETS or rng.random() >= 0.35:
            continue
        across = 1 if angle == 0.0 else 0  # the coordinate across the street
        width = [w for d, pos, w in layout["street_anchors"]
                 if (d == "h") == (across == 1) and abs(pos - centre[across]) < 1e-9]
        shift = rng.choice([-1, 1]) * (width[0] / 2 - height / 2 + rng.uniform(0.1, 0.5) *
                                       height) if width else 0.0
        moved = list(centre)
        moved[across] += shift
        footprint = sm._label_box(text, tuple(moved), angle, height)
        if shift and not footprint.intersects(layout["quays"]) and not any(
                footprint.intersects(sm._label_box(*other)) for k, other in enumerate(out)
                if k != i):
            out[i] = (text, tuple(moved), angle, height)
    return out


def _monochrome(rng, extent, res):
    if extent < 80:
        raise ValueError("a monochrome map must be 80 m across at least (a few blocks)")
    layout = _monochrome_layout(rng, extent)
    strokes = Strokes(outline=max(0.6, 1.8 * res), line=max(0.3, 1.2 * res))
    frame = box(0, 0, extent, extent)
    blocks = layout["blocks"]
    hatched, hatching, kinds = [], [], []

    def hatch(plot):
        turn = float(rng.choice([45.0, 135.0, 45.0, 135.0, rng.uniform(20, 70),
                                 rng.uniform(110, 160)]))
        return Hatching(angle=round(turn, 1), spacing=max(2.2, 4.0 * res),
                        width=strokes.line, plot=plot)

    # buildings as blocks of their own: the smallest block and some others
    own = {int(np.argmin([p.area for p in blocks]))} | {
        i for i in range(len(blocks)) if rng.random() < 0.12}
    if len(own) == len(blocks) > 1:  # (a small map) the largest keeps its paper
        own.discard(int(np.argmax([p.area for p in blocks])))
    for b, block in enumerate(blocks, start=1):
        if b - 1 in own:
            kinds.append("building")
            hatched.append(block)
            hatching.append(hatch(b))
            continue
        kinds.append("block")
        if rng.random() < 0.5:
            mine = []
            for _ in range(int(rng.integers(1, 3))):
                building = _hatched_building(rng, block)
                if building is not None and all(building.distance(o) >= 2.0 for o in mine):
                    mine.append(building)
                    hatched.append(building)
                    hatching.append(hatch(b))
    river = layout["river"].intersection(frame)
    water = _parts(river)
    water_hatching = Hatching(angle=0.0, spacing=max(3.6, 6.5 * res), width=strokes.line)
    hatches = [(p, h, _HATCH) for p, h in zip(hatched, hatching)]
    hatches += [(layout["river"], water_hatching, _WATER_HATCH)]

    lines = []
    # dotted lines across some blocks (not outlines: they close nothing), off the hatching
    clear = unary_union(hatched).buffer(1.5) if hatched else None
    for block in blocks:
        if rng.random() < 0.25:
            inner = block.buffer(-2.0)
            inner = inner.difference(clear) if clear is not None else inner
            turn = math.radians(rng.uniform(0, 180))
            c = inner.representative_point() if not inner.is_empty else None
            if c is None:
                continue
            d = (math.cos(turn) * extent, math.sin(turn) * extent)
            cross = inner.intersection(LineString([(c.x - d[0], c.y - d[1]),
                                                   (c.x + d[0], c.y + d[1])]))
            for piece in getattr(cross, "geoms", [cross]):
                if piece.geom_type == "LineString" and piece.length > 5:
                    n = int(piece.length / 1.2)
                    dots = [piece.interpolate((k + 0.5) * piece.length / n).buffer(
                        max(0.25, 0.7 * res), quad_segs=3) for k in range(n)]
                    lines.append((unary_union(dots), _DOTS))
    lines += [(g, _THIN) for p in hatched for g in _strokes(p, strokes.outline)]
    lines += [(g, _THICK) for p in blocks for g in _strokes(p, strokes.outline)]
    # the river's banks: its two long sides
    line, half = layout["canal_line"], layout["river_width"] / 2
    (x0, y0), (x1, y1) = line.coords
    n = np.array([-(y1 - y0), x1 - x0]) / line.length
    lines += [(affinity.translate(line, *(s * half * n)).buffer(strokes.outline / 2,
                                                                 cap_style="flat"), _THICK)
              for s in (-1, 1)]
    # texts: the river's and the streets' names, a few buildings' names, numbers
    style = sm.LabelStyle(canal_names=("LA SEINE",), street_names=PARIS_STREETS,
                          building_names=PARIS_BUILDINGS, scale=0.7)
    layout["plots"] = [(p, "block", 0.0) for p in blocks]
    labels = _touching(rng, sm._labels(rng, layout, extent, style), layout)
    taken = [sm._label_box(*label).buffer(1.0) for label in labels]
    texts = [(text, centre, angle, height, max(0.14 * height, 1.0 * res))
             for text, centre, angle, height in labels]
    num_height = max(2.2, 5 * res)
    number = int(rng.integers(1, 40)) * 2
    for block in blocks:
        for _ in range(int(rng.integers(0, 3))):
            # just inside the block's edge: some touch its outline
            inset = rng.uniform(0.35, 1.0) * num_height
            ring = block.buffer(-inset, join_style="mitre")
            if ring.is_empty or ring.geom_type != "Polygon":
                continue
            p = ring.exterior.interpolate(rng.uniform(0, ring.exterior.length))
            text = str(number)
            number += 2
            footprint = sm._label_box(text, (p.x, p.y), 0.0, num_height)
            if frame.buffer(-2).contains(footprint) and not any(
                    footprint.intersects(t) for t in taken):
                taken.append(footprint.buffer(1.0))
                texts.append((text, (p.x, p.y), 0.0, num_height, max(0.3, 1.0 * res)))
    # a district limit: a red dashed line along a street, red names either side
    dry = [a for a in layout["street_anchors"] if a[0] == "v"] or layout["street_anchors"] \
        or [("v", rng.uniform(0.3, 0.7) * extent, 0.0)]  # (a map of one block's width)
    direction, pos, width = dry[int(rng.integers(len(dry)))]
    limit = LineString([(pos, -1), (pos, extent + 1)] if direction == "v"
                       else [(-1, pos), (extent + 1, pos)])
    red = max(0.8, 2.2 * res)
    lines += [(g, _RED) for g in _dashes(limit, 4.0, 2.0, red, rng.uniform(0, 6))]
    height = max(5.0, 10 * res)
    for name, side in (("7E ARROND", -1), ("6E ARROND", 1)):
        for _ in range(20):
            along = rng.uniform(0.15, 0.85) * extent
            off = side * (width / 2 + rng.uniform(0.6, 1.5) * height)
            centre = (pos + off, along) if direction == "v" else (along, pos + off)
            footprint = sm._label_box(name, centre, 0.0, height)
            if frame.buffer(-2).contains(footprint) and not any(
                    footprint.intersects(t) for t in taken) and not footprint.intersects(
                    layout["quays"]):
                taken.append(footprint.buffer(1.0))
                lines.append((sm._text_geometry(name, height, centre, 0.0,
                                                max(0.16 * height, 1.5 * res)), _RED))
                break
    ground = [(p, _BLOCK) for p in blocks] + [(p, _HATCHED) for p in hatched]
    ground += [(p, _WATER) for p in water]
    return _Drawing(ground=ground, parcels=[], info=[], courtyards=[], lines=lines,
                    texts=texts, plots=blocks, kinds=kinds, strokes=strokes, hatches=hatches,
                    hatched=hatched, hatching=hatching, water=water,
                    water_hatching=water_hatching)


def _burn_hatching(canvas, where, poly, hatching, layer):
    """Burn the lines of ``hatching`` inside ``poly`` into ``canvas`` (its sub-pixels
    within half a line's width of one of the lines); ``where``: a scratch canvas of
    the same size, all 0, left so."""
    window = where.burn(poly, 1)
    if window is None:
        return
    rows, cols = window
    inside = where.layer[rows, cols] == 1
    where.layer[rows, cols] = 0
    xs = (np.arange(cols.start, cols.stop) + 0.5) * canvas.step
    ys = canvas.extent - (np.arange(rows.start, rows.stop) + 0.5) * canvas.step
    turn = math.radians(hatching.angle)
    phase = np.mod(-xs[None, :] * math.sin(turn) + ys[:, None] * math.cos(turn),
                   hatching.spacing)
    on = inside & (np.minimum(phase, hatching.spacing - phase) <= hatching.width / 2)
    canvas.layer[rows, cols][on] = layer


# ---------------------------------------------------------------------------
# Drawing and scanning
# ---------------------------------------------------------------------------

def _jpeg(rgb, quality):
    """``rgb`` (float) compressed as JPEG does: YCbCr, chroma halved, 8 x 8 DCT blocks
    quantised with the standard tables at ``quality``."""
    h, w = rgb.shape[:2]
    ph, pw = -h % 16, -w % 16
    x = np.pad(rgb, ((0, ph), (0, pw), (0, 0)), mode="edge")
    r, g, b = x[..., 0], x[..., 1], x[..., 2]
    y = 0.299 * r + 0.587 * g + 0.114 * b
    cb = 128 - 0.168736 * r - 0.331264 * g + 0.5 * b
    cr = 128 + 0.5 * r - 0.418688 * g - 0.081312 * b
    scale = 5000.0 / quality if quality < 50 else 200.0 - 2 * quality

    def code(plane, table):
        q = np.clip(np.floor((table * scale + 50) / 100), 1, 255)
        n, m = plane.shape
        blocks = (plane - 128).reshape(n // 8, 8, m // 8, 8).transpose(0, 2, 1, 3)
        coef = np.rint(fft.dctn(blocks, axes=(2, 3), norm="ortho") / q) * q
        back = fft.idctn(coef, axes=(2, 3), norm="ortho").transpose(0, 2, 1, 3)
        return back.reshape(n, m) + 128

    def halved(plane):
        n, m = plane.shape
        small = plane.reshape(n // 2, 2, m // 2, 2).mean(axis=(1, 3))
        return np.repeat(np.repeat(code(small, _JPEG_CHROMA), 2, axis=0), 2, axis=1)

    y, cb, cr = code(y, _JPEG_LUMA), halved(cb) - 128, halved(cr) - 128
    out = np.stack([y + 1.402 * cr, y - 0.344136 * cb - 0.714136 * cr, y + 1.772 * cb], axis=2)
    return out[:h, :w]


def _scan(rng, drawing, seed, size, res, origin, style):
    """Draw, print and scan a style's drawing: the SyntheticMap."""
    canvas = sm._Canvas(size, res)
    for geom, layer in drawing.ground:
        canvas.burn(geom, layer)
    ids = sm._Canvas(size, res)
    ids.layer = np.zeros(canvas.layer.shape, dtype=np.int32)
    for i, poly in enumerate(drawing.parcels, start=1):
        # grown by a micrometre: the sub-pixel centres on the edge two parcels share too
        ids.burn(poly.buffer(1e-6, join_style="mitre"), i)
    fill_of = np.array([_GROUND] + [_FILL_LAYER[p.fill] for p in drawing.info], dtype=np.int8)
    on = ids.layer > 0
    canvas.layer[on] = fill_of[ids.layer[on]]
    for court in drawing.courtyards:
        canvas.burn(court, _COURT)
    base = canvas.layer.copy()
    if drawing.hatches:
        scratch = sm._Canvas(size, res)
        for poly, hatching, layer in drawing.hatches:
            _burn_hatching(canvas, scratch, poly, hatching, layer)
    for geom, layer in drawing.lines:
        canvas.burn(geom, layer)
    ink = [sm._text_geometry(t, h, c, a, stroke) for t, c, a, h, stroke in drawing.texts]
    for g in ink:
        canvas.burn(g, _INK)

    colour = _COLOURS[style]
    layer = canvas.layer
    rgb = sm.pixel_colours(lambda a, b: colour[layer[a:b]], size, layer.shape[1])
    # each parcel's wash a little different (pixels whose centre it washes)
    c = sm._SUB // 2
    tint = rng.normal(0, 4, size=(len(drawing.parcels) + 1, 3))
    tint[0] = 0
    washed = np.isin(layer[c::sm._SUB, c::sm._SUB], _FILLS)
    rgb[washed] += tint[ids.layer[c::sm._SUB, c::sm._SUB][washed]]
    # uneven wash and paper, grain, then the JPEG of the scan
    rgb += ((sm._smooth_field(rng, (size, size), size / 10.0) - 0.5) * 10.0)[..., None]
    rgb += rng.normal(0, 2.5, size=(size, size, 1))
    rgb += rng.normal(0, 3.0, size=(size, size, 3))
    if style == "monochrome":
        rgb = _fold_and_stains(rng, rgb)
    rgb = _jpeg(np.clip(rgb, 0, 255), _JPEG_QUALITY[style])
    rgb = np.clip(np.rint(rgb), 0, 255).astype(np.uint8)

    truth = _LAYER_CLASS[base[c::sm._SUB, c::sm._SUB]]
    drawn_layer = layer[c::sm._SUB, c::sm._SUB]
    drawn = _LAYER_CLASS[drawn_layer]
    classes = _CLASSES[style]

    def share(mask):  # (the sum of the sub-pixel grid's strided views: quicker than a
        sub = sm._SUB   # reduction over two axes, the same counts)
        count = np.zeros((size, size), dtype=np.uint8)
        for r in range(sub):
            for c in range(sub):
                count += mask[r::sub, c::sub]
        return count / sub ** 2

    sub_class = _LAYER_CLASS.astype(np.int8)[layer]
    ink_cover = share(layer == _INK)
    # training points: the building points on each fill (pseudo-labels 100 + layer)
    # (every class on a map without fills: the monochrome map's hatched buildings)
    groups = {label: share(sub_class == label) for label in classes
              if label != BUILDING or not drawing.parcels}
    picks = drawn.copy()
    for fill in _FILLS:
        if np.any(drawn_layer == fill):
            groups[100 + fill] = share(layer == fill)
            picks[drawn_layer == fill] = 100 + fill
    x0, y0 = origin
    extent = size * res
    north = y0 + extent

    def xy_of(r, c):
        return (x0 + (c + 0.5) * res, north - (r + 0.5) * res)

    xy, picked = sm._pick_training(rng, picks, groups, xy_of, labels=groups,
                                   thin=(TEXT, OUTLINE, DISTRICT))
    labels = np.where(picked >= 100, BUILDING, picked).astype(np.int32)

    def world(g):
        return affinity.translate(g, x0, y0)

    plots = [world(p) for p in drawing.plots]
    info = [p if p.number_xy is None else ParcelInfo(
        plot=p.plot, fill=p.fill, number=p.number, across=p.across, crossed=p.crossed,
        number_xy=(p.number_xy[0] + x0, p.number_xy[1] + y0)) for p in drawing.info]
    gt = np.array([[q.x, q.y] for q in (p.representative_point() for p in plots)],
                  dtype=float).reshape(-1, 2)
    return sm.SyntheticMap(
        seed=seed, rgb=rgb, truth=truth.astype(np.int32), drawn=drawn.astype(np.int32),
        plots=plots, plot_kinds=list(drawing.kinds),
        training={"xy": xy, "label": labels, "class": [classes[int(v)] for v in labels]},
        gt_points=gt, north=north, south=y0, east=x0 + extent, west=x0, res=res,
        classes=dict(classes), ink_cover=ink_cover, style=style,
        parcels=[world(p) for p in drawing.parcels], parcel_info=info,
        courtyards=[world(c) for c in drawing.courtyards], strokes=drawing.strokes,
        hatched=[world(p) for p in drawing.hatched], hatching=list(drawing.hatching),
        water=[world(p) for p in drawing.water], water_hatching=drawing.water_hatching)


def _fold_and_stains(rng, rgb):
    """A scan's sheet fold (a light crease across, shadowed on one side) and a stain or
    two (smooth brownish blots) over ``rgb`` (float, changed and returned)."""
    size = rgb.shape[0]
    rows, cols = np.mgrid[0:size, 0:size].astype(float)
    turn = math.radians(rng.uniform(-20, 20) + float(rng.choice([0.0, 90.0])))
    at = rng.uniform(0.3, 0.7) * size
    d = (cols - size / 2) * math.sin(turn) + (rows - size / 2) * math.cos(turn) + size / 2 - at
    crease = 28.0 * np.exp(-(d / 1.6) ** 2) - 14.0 * np.exp(-((d - 3.5) / 2.5) ** 2)
    rgb += crease[..., None]
    for _ in range(int(rng.integers(1, 3))):
        r0, c0 = rng.uniform(0.1, 0.9, size=2) * size
        radius = rng.uniform(0.03, 0.08) * size
        blot = np.exp(-(((rows - r0) ** 2 + (cols - c0) ** 2) / radius ** 2) ** 2)
        rgb -= blot[..., None] * np.array([18.0, 30.0, 48.0])
    return rgb
