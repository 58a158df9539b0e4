#!/usr/bin/env python3
"""A synthetic, seeded colour city map: the project's embedded historical map.

No real scanned map may be committed, so histo makes its own. The map looks
and behaves like a 19th-20th century colour city map (the Delft 1961 map of
the thesis is the model): blocks of pale pink building plots with a thin
darker outline, of several shapes (single buildings, rows, two rows back to
back, courtyard blocks with a hole, concave L and U blocks, a few rotated
blocks and some cut slanted by the canal), separated by pale streets; a blue
canal crossing the map; green parks and gardens; black street names along
the streets and black numbered square symbols printed over plots and
streets; and the defects of a scan: mixed pixels on every edge, colour
noise, bleaching (a smooth brightness and yellowing gradient) and one colour
plane misregistered by one pixel (false colour fringes).

Beside the picture it gives what a test needs: the true class of every
pixel, the true building plots as polygons, one ground-truth point inside
each plot and a few training points per class, as the thesis's Delft data;
and today's building footprints over the map (``SyntheticMap.current``:
row houses with construction years before and after the map's year
:data:`MAP_YEAR`, a few offset or straddling two plots, modern blocks,
buildings away from the plots), the fixture of v.histo.align.

Other styles (``generate(style=...)``, ``--style``; synthetic_styles.py
draws them from their own random streams, so this map's draws do not change):
``cadaster``, a colour-washed cadaster like Venice's of 1808 (ragged blocks in
a thick dark-red outline divided into numbered pink, yellow, pale and white
parcels by thin grey lines, white courtyards, buff streets, pinkish squares,
a blue canal, JPEG noise; 0.2 m per pixel) and ``insurance``, a
fire-insurance map like Sanborn's of 1892 (every building outlined in black
and filled by its material, outbuildings crossed, house numbers; 0.3 m per
pixel) and ``monochrome``, black line work on cream paper like the 1925
Atlas municipal of Paris (blocks outlined only, public buildings hatched in
their own outline, the river hatched horizontally, names, numbers, dotted
lines, a red dashed district limit, a fold and stains; 0.5 m per pixel).
Their truth adds ``SyntheticMap.parcels`` (the divisions the map draws
inside its plots), ``parcel_info`` and ``courtyards``, the monochrome map's
``hatched`` buildings (with their ``hatching``) and ``water``, and the
classes ``courtyard`` (7), ``outline`` (8), ``block`` (9, the paper inside
the monochrome map's blocks) and ``district`` (10, its red lines and
names); the Delft map's ``parcels`` are empty (it draws no divisions).
``SyntheticMap.grey`` is the picture as a greyscale scan (the bands' mean).

Two parts:

- :func:`generate` is pure (numpy, scipy, shapely; no GRASS) and returns a
  :class:`SyntheticMap`; the same seed gives identical arrays and vectors.
- :func:`write_to_grass` writes it into the current GRASS mapset (region,
  ``<prefix>.red/.green/.blue`` rasters, ``<prefix>_training``,
  ``<prefix>_gt_points``, ``<prefix>_plots`` and ``<prefix>_current``
  vectors; ``<prefix>_parcels`` too for the cadaster and insurance styles,
  ``<prefix>_hatched`` and ``<prefix>_water`` for the monochrome one). From the
  command line,
  inside a GRASS session::

      python3 testsuite/synthetic_map.py --seed 1 --size 600 --prefix map

Coordinates are EPSG:28992 (RD New) metres, north up: pixel (row 0, col 0)
is the north-west corner, at (origin_x, origin_y + size * res).
"""

import argparse
import math
import os
import struct
import sys
import zlib
from dataclasses import dataclass, field

import numpy as np
import shapely
from scipy import ndimage
from shapely import affinity
from shapely.geometry import LineString, Point, Polygon, box
from shapely.ops import unary_union

CLASSES = {1: "building", 2: "text", 3: "water", 4: "street", 5: "vegetation", 6: "symbol"}
BUILDING, TEXT, WATER, STREET, VEGETATION, SYMBOL = 1, 2, 3, 4, 5, 6
#: classes of the other styles only (synthetic_styles.py): white courtyards, drawn lines;
#: the monochrome map's paper inside the blocks and its red district limits and names
COURTYARD, OUTLINE, BLOCK, DISTRICT = 7, 8, 9, 10
#: the map styles :func:`generate` draws: the Delft 1961 map (the default), a colour-washed
#: cadaster (Venice 1808) and a fire-insurance map (Sanborn 1892); see synthetic_styles.py
STYLES = ("delft", "cadaster", "insurance", "monochrome")
#: metres per pixel of each style when none is given
STYLE_RES = {"delft": 1.0, "cadaster": 0.2, "insurance": 0.3, "monochrome": 0.5}
PLOT_KINDS = ("single", "row", "double_row", "courtyard", "L", "U")
#: the year the map shows (the demo chain's YEAR): current buildings older than it may be on it
MAP_YEAR = 1900
#: what a current footprint is (see :class:`CurrentFootprints`)
CURRENT_KINDS = ("standing", "offset", "straddling", "rebuilt", "outside")

# Drawing layers (finer than classes: what colour a sub-pixel gets).
_PAPER, _FILL, _OUTLINE, _WATER, _BANK, _GREEN, _TREE, _INK, _SYMBOL_INK, _SYMBOL_PAPER = range(10)
_LAYER_CLASS = np.array([STREET, BUILDING, BUILDING, WATER, WATER, VEGETATION, VEGETATION,
                         TEXT, SYMBOL, SYMBOL], dtype=np.int32)
_LAYER_COLOUR = np.array([
    (238, 231, 212),  # paper: streets, yards
    (236, 183, 166),  # plot fill, pale salmon pink
    (176, 100, 92),   # plot outline
    (150, 188, 214),  # water
    (92, 130, 176),   # canal bank line
    (182, 207, 150),  # parks, gardens
    (120, 160, 104),  # trees
    (30, 27, 30),     # text ink
    (24, 24, 28),     # symbol ink
    (236, 230, 214),  # numbers inside symbols
], dtype=np.float64)

_SUB = 3          # sub-pixels per pixel side (anti-aliasing)
_BAND_SUBPIXELS = 1 << 22  # sub-pixels coloured at a time (memory of the rendering)
_MISREGISTERED_BAND = 0  # red
_MISREGISTRATION = (0, 1)  # rows, cols: one pixel to the east

STREET_NAMES = (
    "OUDE DELFT", "KOORNMARKT", "VOLDERSGRACHT", "WIJNHAVEN", "TURFMARKT", "BREESTRAAT",
    "NIEUWSTRAAT", "BEESTENMARKT", "KAPELSTEEG", "HIPPOLYTUSBUURT", "VLAMINGSTRAAT",
    "PAPENSTRAAT", "OOSTSINGEL", "GASTHUISLAAN", "BINNENWATERSLOOT", "LANGE GEER",
    "BRABANTSE TURFMARKT", "PEPERSTRAAT", "HAVERSTRAAT", "MOLENSTRAAT", "ZUIDWAL",
    "NOORDEINDE", "PHOENIXSTRAAT", "HOOGSTRAAT", "VESTSTRAAT", "KERKSTRAAT",
)
CANAL_NAMES = ("NIEUWE DELFT", "BUITENWATERSLOOT", "RIJN SCHIE KANAAL", "OOSTERGRACHT")
BUILDING_NAMES = ("KERK", "SCHOOL", "WAAG", "HOFJE", "STADHUIS", "GASTHUIS", "MUSEUM")

# A small stroke font on a 4 x 6 grid (y up): polylines per glyph.
_O = [(1, 0), (0, 1), (0, 5), (1, 6), (3, 6), (4, 5), (4, 1), (3, 0), (1, 0)]
_P = [(0, 0), (0, 6), (3, 6), (4, 5), (4, 4), (3, 3), (0, 3)]
GLYPHS = {
    "A": [[(0, 0), (0, 4), (2, 6), (4, 4), (4, 0)], [(0, 3), (4, 3)]],
    "B": [[(0, 0), (0, 6), (3, 6), (4, 5), (4, 4), (3, 3), (0, 3)],
          [(3, 3), (4, 2), (4, 1), (3, 0), (0, 0)]],
    "C": [[(4, 5), (3, 6), (1, 6), (0, 5), (0, 1), (1, 0), (3, 0), (4, 1)]],
    "D": [[(0, 0), (0, 6), (2, 6), (4, 4), (4, 2), (2, 0), (0, 0)]],
    "E": [[(4, 6), (0, 6), (0, 0), (4, 0)], [(0, 3), (3, 3)]],
    "F": [[(4, 6), (0, 6), (0, 0)], [(0, 3), (3, 3)]],
    "G": [[(4, 5), (3, 6), (1, 6), (0, 5), (0, 1), (1, 0), (3, 0), (4, 1), (4, 3), (2, 3)]],
    "H": [[(0, 0), (0, 6)], [(4, 0), (4, 6)], [(0, 3), (4, 3)]],
    "I": [[(1, 6), (3, 6)], [(2, 6), (2, 0)], [(1, 0), (3, 0)]],
    "J": [[(4, 6), (4, 1), (3, 0), (1, 0), (0, 1)]],
    "K": [[(0, 0), (0, 6)], [(4, 6), (0, 2)], [(1, 3), (4, 0)]],
    "L": [[(0, 6), (0, 0), (4, 0)]],
    "M": [[(0, 0), (0, 6), (2, 3), (4, 6), (4, 0)]],
    "N": [[(0, 0), (0, 6), (4, 0), (4, 6)]],
    "O": [_O],
    "P": [_P],
    "Q": [_O, [(2, 2), (4, 0)]],
    "R": [_P, [(2, 3), (4, 0)]],
    "S": [[(4, 5), (3, 6), (1, 6), (0, 5), (0, 4), (1, 3), (3, 3), (4, 2), (4, 1), (3, 0),
           (1, 0), (0, 1)]],
    "T": [[(0, 6), (4, 6)], [(2, 6), (2, 0)]],
    "U": [[(0, 6), (0, 1), (1, 0), (3, 0), (4, 1), (4, 6)]],
    "V": [[(0, 6), (2, 0), (4, 6)]],
    "W": [[(0, 6), (1, 0), (2, 3), (3, 0), (4, 6)]],
    "X": [[(0, 0), (4, 6)], [(0, 6), (4, 0)]],
    "Y": [[(0, 6), (2, 3), (4, 6)], [(2, 3), (2, 0)]],
    "Z": [[(0, 6), (4, 6), (0, 0), (4, 0)]],
    "0": [_O],
    "1": [[(1, 5), (2, 6), (2, 0)], [(1, 0), (3, 0)]],
    "2": [[(0, 5), (1, 6), (3, 6), (4, 5), (4, 4), (0, 0), (4, 0)]],
    "3": [[(0, 5), (1, 6), (3, 6), (4, 5), (4, 4), (3, 3), (4, 2), (4, 1), (3, 0), (1, 0),
           (0, 1)], [(1, 3), (3, 3)]],
    "4": [[(3, 0), (3, 6), (0, 2), (4, 2)]],
    "5": [[(4, 6), (0, 6), (0, 3), (3, 3), (4, 2), (4, 1), (3, 0), (1, 0), (0, 1)]],
    "6": [[(4, 5), (3, 6), (1, 6), (0, 5), (0, 1), (1, 0), (3, 0), (4, 1), (4, 2), (3, 3),
           (0, 3)]],
    "7": [[(0, 6), (4, 6), (1, 0)]],
    "8": [[(1, 3), (0, 4), (0, 5), (1, 6), (3, 6), (4, 5), (4, 4), (3, 3), (1, 3), (0, 2),
           (0, 1), (1, 0), (3, 0), (4, 1), (4, 2), (3, 3)]],
    "9": [[(0, 1), (1, 0), (3, 0), (4, 1), (4, 5), (3, 6), (1, 6), (0, 5), (0, 4), (1, 3),
           (4, 3)]],
}
_ADVANCE = 5.6  # glyph advance in font units (glyphs are 4 wide, 6 high)


@dataclass
class SyntheticMap:
    """A generated map: picture, truth, plots, points and its region.

    Arrays are north-up (row 0 is the northern edge); vectors are in map
    coordinates (EPSG:28992 metres).
    """

    seed: int
    rgb: np.ndarray          # uint8 (rows, cols, 3)
    truth: np.ndarray        # int32 (rows, cols): underlying class (no text, no symbols)
    drawn: np.ndarray        # int32 (rows, cols): visible class (text and symbols on top)
    plots: list              # shapely Polygons of the true building plots
    plot_kinds: list         # kind of each plot, one of PLOT_KINDS
    training: dict           # {"xy": (n, 2) float, "label": (n,) int, "class": [str]}
    gt_points: np.ndarray    # (n_plots, 2) float: one point inside each plot, same order
    north: float
    south: float
    east: float
    west: float
    res: float
    classes: dict = field(default_factory=lambda: dict(CLASSES))
    misregistration: dict = field(default_factory=dict)  # {"band": "red", "shift": (rows, cols)}
    ink_cover: np.ndarray = None  # float (rows, cols): share of black ink in each pixel
    _current: object = field(default=None, repr=False, compare=False)
    style: str = "delft"     # one of STYLES
    #: shapely Polygons of the divisions the map draws inside its plots (cadaster: the
    #: parcels; insurance: the buildings); empty on the Delft map, which draws none
    parcels: list = field(default_factory=list)
    #: one synthetic_styles.ParcelInfo per parcel, same order (plot, fill, number...)
    parcel_info: list = field(default_factory=list)
    courtyards: list = field(default_factory=list)  # shapely Polygons (cadaster)
    strokes: object = None   # synthetic_styles.Strokes: the drawn lines' widths (m)
    #: (monochrome) the buildings drawn hatched in their own outline, shapely Polygons, and
    #: one synthetic_styles.Hatching each (angle, spacing, line width, plot), same order
    hatched: list = field(default_factory=list)
    hatching: list = field(default_factory=list)
    #: (monochrome) the water (the river band in the map), shapely Polygons, and its
    #: Hatching (horizontal lines, wider apart than the buildings')
    water: list = field(default_factory=list)
    water_hatching: object = None

    @property
    def shape(self):
        return self.truth.shape

    @property
    def grey(self):
        """The picture as a greyscale scan gives it: the mean of its three bands
        (uint8 (rows, cols))."""
        return np.rint(self.rgb.astype(np.float64).mean(axis=2)).astype(np.uint8)

    @property
    def current(self):
        """Today's building footprints over the map (:class:`CurrentFootprints`), made on
        first use from their own generator (the map itself does not depend on them)."""
        if self._current is None:
            self._current = current_footprints(np.random.default_rng([self.seed, 14]), self)
        return self._current

    def region(self):
        """Keyword arguments of g.region for this map."""
        return {"n": self.north, "s": self.south, "e": self.east, "w": self.west,
                "res": self.res}

    def to_pixel(self, xy):
        """Rows and columns of the pixels holding map coordinates ``xy`` ((n, 2))."""
        xy = np.asarray(xy, dtype=float).reshape(-1, 2)
        cols = np.floor((xy[:, 0] - self.west) / self.res).astype(int)
        rows = np.floor((self.north - xy[:, 1]) / self.res).astype(int)
        return rows, cols

    def class_share(self, label, visible=True):
        """Share of the map's pixels of one class (visible or underlying)."""
        return float(np.mean((self.drawn if visible else self.truth) == label))


# ---------------------------------------------------------------------------
# Layout: streets, canal, blocks and plots (local metres, origin south-west)
# ---------------------------------------------------------------------------

def _cuts(rng, extent, block=(55, 100), street=(8, 17), start=(5, 12), edge=5, last=30):
    """Block intervals [(a, b), ...] along one axis: blocks ``block`` m long separated by
    streets ``street`` m wide (the Delft map's by default), the first ``start`` m from
    the map's edge, none nearer than ``edge`` m to the other edge and the last one at
    least ``last`` m long."""
    intervals = []
    pos = rng.uniform(*start)
    while True:
        width = rng.uniform(*block)
        if pos + width > extent - edge:
            width = extent - edge - pos
            if width >= last:
                intervals.append((pos, pos + width))
            break
        intervals.append((pos, pos + width))
        pos += width + rng.uniform(*street)
    return intervals


def _rect(x0, y0, x1, y1):
    return box(min(x0, x1), min(y0, y1), max(x0, x1), max(y0, y1))


def _block_content(rng, kind, x0, y0, x1, y1):
    """Plots and gardens of one block [x0, x1] x [y0, y1] in local metres.

    Returns (plots as [(polygon, kind)], gardens as [polygon]).
    """
    w, h = x1 - x0, y1 - y0
    horizontal = w >= h  # rows run along the long side
    plots, gardens = [], []
    depth = rng.uniform(15, 25)
    if kind == "single":
        # two to four detached houses in the corners of a garden block
        corners = [(x0, y0, 1, 1), (x1, y0, -1, 1), (x0, y1, 1, -1), (x1, y1, -1, -1)]
        n_houses = rng.integers(1, 4) if min(w, h) >= 50 else 1
        chosen = rng.permutation(4)[:n_houses]
        if rng.random() < 0.8:
            gardens.append(_rect(x0, y0, x1, y1).buffer(-2.0, join_style="mitre"))
        for i in sorted(chosen):
            cx, cy, sx, sy = corners[i]
            # at most half the block less 10 m: houses stay 8 m apart
            bw = rng.uniform(9, max(10, min(22, w / 2 - 10)))
            bh = rng.uniform(9, max(10, min(22, h / 2 - 10)))
            ox, oy = rng.uniform(2, 6), rng.uniform(2, 6)
            plots.append((_rect(cx + sx * ox, cy + sy * oy, cx + sx * (ox + bw),
                                cy + sy * (oy + bh)), "single"))
    elif kind == "row":
        # one row along each long side, gardens or a yard between
        if horizontal:
            plots.append((_rect(x0, y0, x1, y0 + depth), "row"))
            if h - 2 * depth >= 12:
                d2 = rng.uniform(11, min(16, h - depth - 10))
                plots.append((_rect(x0, y1 - d2, x1, y1), "row"))
                inner = _rect(x0 + 2, y0 + depth + 3, x1 - 2, y1 - d2 - 3)
            else:
                inner = _rect(x0 + 2, y0 + depth + 3, x1 - 2, y1 - 2)
        else:
            plots.append((_rect(x0, y0, x0 + depth, y1), "row"))
            if w - 2 * depth >= 12:
                d2 = rng.uniform(11, min(16, w - depth - 10))
                plots.append((_rect(x1 - d2, y0, x1, y1), "row"))
                inner = _rect(x0 + depth + 3, y0 + 2, x1 - d2 - 3, y1 - 2)
            else:
                inner = _rect(x0 + depth + 3, y0 + 2, x1 - 2, y1 - 2)
        if rng.random() < 0.6 and inner.area > 50:
            gardens.append(inner)
    elif kind == "double_row":
        # two rows back to back: one deep plot in the middle of the block
        d = rng.uniform(30, 50)
        if horizontal:
            d = min(d, h - 6)
            c = (y0 + y1) / 2 + rng.uniform(-1, 1) * max(0.0, (h - d) / 2 - 3)
            plots.append((_rect(x0, c - d / 2, x1, c + d / 2), "double_row"))
            for a, b in ((y0 + 2, c - d / 2 - 3), (c + d / 2 + 3, y1 - 2)):
                if b - a > 6:
                    gardens.append(_rect(x0 + 2, a, x1 - 2, b))
        else:
            d = min(d, w - 6)
            c = (x0 + x1) / 2 + rng.uniform(-1, 1) * max(0.0, (w - d) / 2 - 3)
            plots.append((_rect(c - d / 2, y0, c + d / 2, y1), "double_row"))
            for a, b in ((x0 + 2, c - d / 2 - 3), (c + d / 2 + 3, x1 - 2)):
                if b - a > 6:
                    gardens.append(_rect(a, y0 + 2, b, y1 - 2))
    elif kind == "courtyard":
        d = min(depth, w / 2 - 6, h / 2 - 6)
        hole = _rect(x0 + d, y0 + d, x1 - d, y1 - d)
        plots.append((Polygon(_rect(x0, y0, x1, y1).exterior.coords,
                              [hole.exterior.coords]), "courtyard"))
        if rng.random() < 0.6:
            gardens.append(hole.buffer(-3.0, join_style="mitre"))
    elif kind in ("L", "U"):
        outer = _rect(x0, y0, x1, y1)
        d1 = min(depth, w / 2 - 6)
        d2 = min(rng.uniform(11, 16), h / 2 - 6)
        if kind == "L":
            # keep two adjacent sides of the block
            sx, sy = rng.choice([-1, 1]), rng.choice([-1, 1])
            cut = _rect(x0 + d1 if sx > 0 else x0, y0 + d2 if sy > 0 else y0,
                        x1 if sx > 0 else x1 - d1, y1 if sy > 0 else y1 - d2)
        else:
            # keep three sides: open towards one side of the block
            side = rng.integers(4)
            cut = [_rect(x0 + d1, y0 + d2, x1 - d1, y1),
                   _rect(x0 + d1, y0, x1 - d1, y1 - d2),
                   _rect(x0 + d1, y0 + d2, x1, y1 - d2),
                   _rect(x0, y0 + d2, x1 - d1, y1 - d2)][side]
        plots.append((outer.difference(cut), kind))
        if rng.random() < 0.6:
            garden = cut.buffer(-3.0, join_style="mitre")
            if not garden.is_empty:
                gardens.append(garden)
    elif kind == "park":
        gardens.append(_rect(x0, y0, x1, y1))
    return plots, gardens


def _layout(rng, extent):
    """Streets, canal, blocks, plots, gardens and label anchors in local metres."""
    cols = _cuts(rng, extent)
    rows = _cuts(rng, extent)
    # the canal: a band crossing the map from west to east with a slight slant
    angle = math.radians(rng.uniform(6, 16) * rng.choice([-1, 1]))
    y_mid = rng.uniform(0.35, 0.65) * extent
    canal_line = LineString([(-50, y_mid - math.tan(angle) * (extent / 2 + 50)),
                             (extent + 50, y_mid + math.tan(angle) * (extent / 2 + 50))])
    canal_width = rng.uniform(18, 26)
    canal = canal_line.buffer(canal_width / 2, cap_style="flat")
    quays = canal_line.buffer(canal_width / 2 + rng.uniform(6, 9), cap_style="flat")

    cells = [(c, r) for r in rows for c in cols]
    order = rng.permutation(len(cells))
    required = ["courtyard", "courtyard", "L", "U", "U", "L", "double_row", "row",
                "single", "park"]
    weights = {"courtyard": 3, "L": 2, "U": 2, "double_row": 3, "row": 3, "single": 1}
    kinds_pool = list(weights)
    probs = np.array([weights[k] for k in kinds_pool], dtype=float)
    probs /= probs.sum()
    rotated = set()
    plots, gardens, street_anchors = [], [], []
    n_assigned = 0
    n_rotated = 0
    for idx in order:
        (x0, x1), (y0, y1) = cells[idx]
        block = _rect(x0, y0, x1, y1)
        crosses = block.intersects(quays)
        if crosses:
            kind = rng.choice(["row", "double_row", "single", "row"])
        elif n_assigned < len(required):
            kind = required[n_assigned]
            n_assigned += 1
        else:
            kind = str(rng.choice(kinds_pool, p=probs))
        kind = str(kind)
        if kind in ("courtyard", "L", "U", "double_row") and min(x1 - x0, y1 - y0) < 40:
            kind = "row"
        content, green = _block_content(rng, kind, x0, y0, x1, y1)
        angle_deg = 0.0
        if not crosses and kind != "park" and n_rotated < 3 and rng.random() < 0.35:
            # a rotated block, scaled to stay inside its street grid cell
            angle_deg = rng.uniform(10, 30) * rng.choice([-1, 1])
            a = math.radians(abs(angle_deg))
            w, h = x1 - x0, y1 - y0
            scale = min(w / (w * math.cos(a) + h * math.sin(a)),
                        h / (w * math.sin(a) + h * math.cos(a))) * 0.97
            centre = ((x0 + x1) / 2, (y0 + y1) / 2)

            def turn(g):
                g = affinity.rotate(g, angle_deg, origin=centre)
                return affinity.scale(g, scale, scale, origin=centre)

            content = [(turn(p), k) for p, k in content]
            green = [turn(g) for g in green]
            rotated.add(idx)
            n_rotated += 1
        for poly, k in content:
            if crosses:
                poly = poly.difference(quays)
            for piece in getattr(poly, "geoms", [poly]):
                if piece.geom_type == "Polygon" and piece.area >= 90:
                    piece = shapely.set_precision(piece, 0.01)
                    plots.append((piece, k, angle_deg))
        for g in green:
            g = g.difference(quays) if crosses else g
            if not g.is_empty:
                gardens.append(g)
    if not gardens:
        # every map has some green: grass verges along the canal
        verges = quays.difference(canal.buffer(1.5)).difference(
            unary_union([p for p, _, _ in plots]).buffer(2.0))
        gardens.append(verges.intersection(box(0, 0, extent, extent)))
    # street anchors for labels: horizontal streets between block rows, vertical
    # streets between block columns
    for (a0, a1), (b0, b1) in zip(rows[:-1], rows[1:]):
        street_anchors.append(("h", (a1 + b0) / 2, b0 - a1))
    for (a0, a1), (b0, b1) in zip(cols[:-1], cols[1:]):
        street_anchors.append(("v", (a1 + b0) / 2, b0 - a1))
    return {
        "plots": plots, "gardens": gardens, "canal": canal, "quays": quays,
        "canal_line": canal_line, "canal_angle": math.degrees(angle),
        "street_anchors": street_anchors, "cols": cols, "rows": rows,
    }


# ---------------------------------------------------------------------------
# Text and symbols
# ---------------------------------------------------------------------------

def _text_geometry(text, height, centre, angle_deg, stroke):
    """Outline of a text label (stroke font) centred on ``centre``, rotated."""
    scale = height / 6.0
    lines = []
    for i, char in enumerate(text):
        for polyline in GLYPHS.get(char, []):
            lines.append(LineString([(x + i * _ADVANCE, y) for x, y in polyline]))
    if not lines:
        return None
    geom = unary_union([ln.buffer(stroke / 2 / scale, cap_style="round", quad_segs=3)
                        for ln in lines])
    width = (len(text) - 1) * _ADVANCE + 4
    geom = affinity.translate(geom, -width / 2, -3)
    geom = affinity.scale(geom, scale, scale, origin=(0, 0))
    geom = affinity.rotate(geom, angle_deg, origin=(0, 0))
    return affinity.translate(geom, centre[0], centre[1])


def text_length(text, height):
    """Length in metres of a label of ``text`` with letters ``height`` high."""
    return ((len(text) - 1) * _ADVANCE + 4) * height / 6.0


def _label_box(text, centre, angle, height):
    """The rectangle a label covers."""
    length = text_length(text, height)
    rect = box(-length / 2, -height / 2, length / 2, height / 2)
    return affinity.translate(affinity.rotate(rect, angle, origin=(0, 0)), *centre)


@dataclass(frozen=True)
class LabelStyle:
    """What :func:`_labels` writes: the names it draws from and ``scale``, the size of
    the letters and of the room kept around them relative to the Delft map's (1.0:
    canal names 7.5-9 m high, street names 6-9 m, kept 5 m apart)."""

    canal_names: tuple = CANAL_NAMES
    street_names: tuple = STREET_NAMES
    building_names: tuple = BUILDING_NAMES
    scale: float = 1.0


def _labels(rng, layout, extent, style=LabelStyle()):
    """Street names, canal names and building names: [(text, centre, angle, height)].

    Labels never overlap each other nor leave the map; street names stay off
    the canal (a layout without one, ``canal_line`` None, has no canal name).
    """
    labels, taken = [], []
    k = style.scale
    inside = box(4 * k, 4 * k, extent - 4 * k, extent - 4 * k)

    def place(text, centre, angle, height, avoid=None):
        footprint = _label_box(text, centre, angle, height)
        if not inside.contains(footprint) or any(footprint.intersects(t) for t in taken):
            return False
        if avoid is not None and footprint.intersects(avoid):
            return False
        labels.append((text, centre, angle, height))
        taken.append(footprint.buffer(5 * k))
        return True

    # along the canal, first
    line = layout["canal_line"]
    if line is not None:
        name = str(rng.choice(style.canal_names))
        height = rng.uniform(7.5 * k, 9.0 * k)
        for _ in range(20):
            x = rng.uniform(0.2, 0.8) * extent
            p = line.interpolate(line.project(Point(x, line.interpolate(0.5,
                                                                          normalized=True).y)))
            if place(name, (p.x, p.y), layout["canal_angle"], height):
                break
    # street names, along the streets between the blocks
    names = list(rng.permutation(style.street_names))
    anchors = list(layout["street_anchors"])
    for i in rng.permutation(len(anchors)):
        direction, pos, width = anchors[i]
        if not names:
            break
        name = str(names.pop())
        height = float(np.clip(width * rng.uniform(0.55, 0.8), 6.0 * k, 9.0 * k))
        length = text_length(name, height)
        if length > extent - 60 * k:
            continue
        for _ in range(12):
            along = rng.uniform(10 * k + length / 2, extent - 10 * k - length / 2)
            centre, angle = ((along, pos), 0.0) if direction == "h" else ((pos, along), 90.0)
            if place(name, centre, angle, height, avoid=layout["quays"]):
                break
    # names of a few buildings, written on their plots
    if not style.building_names:
        return labels
    plots = layout["plots"]
    big = [i for i, (poly, kind, ang) in enumerate(plots) if poly.area > 900 * k * k]
    for i in rng.permutation(big)[: 4]:
        poly, kind, ang = plots[i]
        name = str(rng.choice(style.building_names))
        p = poly.representative_point()
        place(name, (p.x, p.y), ang, rng.uniform(6.0 * k, 7.5 * k))
    return labels


def _symbols(rng, layout, extent, labels_geom):
    """Numbered square symbols: [(square polygon, number glyphs geometry)]."""
    plots = [p for p, _, _ in layout["plots"]]
    plots_union = unary_union(plots)
    green = unary_union(layout["gardens"]) if layout["gardens"] else Polygon()
    near_plots, inner_plots = plots_union.buffer(12), plots_union.buffer(-2)
    for geom in (plots_union, green, near_plots, inner_plots, layout["canal"]):
        shapely.prepare(geom)
    symbols = []
    wanted = {"plot": int(rng.integers(5, 9)), "street": int(rng.integers(4, 7))}
    tries = 0
    taken = [labels_geom.buffer(3)] if labels_geom is not None else []
    while (wanted["plot"] or wanted["street"]) and tries < 2000:
        tries += 1
        side = rng.uniform(8, 12)
        x, y = rng.uniform(20, extent - 20, size=2)
        square = box(x - side / 2, y - side / 2, x + side / 2, y + side / 2)
        where = "plot" if plots_union.contains(square.centroid) else "street"
        if where == "street" and (square.intersects(layout["canal"]) or square.intersects(green)
                                  or not square.intersects(near_plots)):
            continue
        if where == "plot" and not inner_plots.contains(square.centroid):
            continue
        if not wanted[where] or any(square.intersects(t) for t in taken):
            continue
        number = str(int(rng.integers(1, 100)))
        digits = _text_geometry(number, side * 0.55, (x, y), 0.0, 0.9)
        symbols.append((square, digits, where))
        taken.append(square.buffer(6))
        wanted[where] -= 1
    return symbols


# ---------------------------------------------------------------------------
# Rendering
# ---------------------------------------------------------------------------

class _Canvas:
    """Sub-pixel layer raster: polygons are burnt in by their sub-pixel centres."""

    def __init__(self, size, res, sub=_SUB):
        self.n = size * sub
        self.step = res / sub
        self.extent = size * res
        self.layer = np.full((self.n, self.n), _PAPER, dtype=np.int8)

    def burn(self, geom, value, mask=None):
        """Burn ``geom`` in as ``value``; returns the window (row and column slices) it
        may have changed, or None."""
        if geom is None or geom.is_empty:
            return None
        minx, miny, maxx, maxy = geom.bounds
        c0 = max(int(math.floor(minx / self.step)), 0)
        c1 = min(int(math.ceil(maxx / self.step)) + 1, self.n)
        r0 = max(int(math.floor((self.extent - maxy) / self.step)), 0)
        r1 = min(int(math.ceil((self.extent - miny) / self.step)) + 1, self.n)
        if c0 >= c1 or r0 >= r1:
            return None
        xs = (np.arange(c0, c1) + 0.5) * self.step
        ys = self.extent - (np.arange(r0, r1) + 0.5) * self.step
        gx, gy = np.meshgrid(xs, ys)
        shapely.prepare(geom)
        inside = shapely.contains_xy(geom, gx, gy)
        if mask is not None:
            inside &= mask[r0:r1, c0:c1]
        self.layer[r0:r1, c0:c1][inside] = value
        return slice(r0, r1), slice(c0, c1)


def pixel_colours(colours, size, n_sub, sub=_SUB):
    """The pixels' colours (float (size, size, 3)): the mean of their sub-pixels'
    (mixed edge pixels), ``colours(a, b)`` giving those of sub-pixel rows a to b
    ((b - a, n_sub, 3)); coloured in bands of rows, so the memory stays bounded."""
    rgb = np.empty((size, size, 3))
    band_rows = max(1, _BAND_SUBPIXELS // (n_sub * sub))  # pixel rows per band
    for r0 in range(0, size, band_rows):
        r1 = min(size, r0 + band_rows)
        rgb[r0:r1] = colours(r0 * sub, r1 * sub).reshape(r1 - r0, sub, size, sub, 3).mean(
            axis=(1, 3))
    return rgb


def _smooth_field(rng, shape, sigma):
    field_ = ndimage.gaussian_filter(rng.standard_normal(shape), sigma, mode="reflect")
    field_ -= field_.min()
    peak = field_.max()
    return field_ / peak if peak > 0 else field_


def _render(rng, layer, plot_ids, n_plots, size):
    """Colours of the sub-pixel layers, averaged to pixels, with scan defects."""
    sub = _SUB
    # printing: each plot's pink varies a little
    tint = rng.normal(0, 5, size=(n_plots + 1, 3))
    tint[0] = 0

    def colours(a, b):
        part = layer[a:b]
        out = _LAYER_COLOUR[part]                     # (rows, n, 3)
        on_plot = (part == _FILL)
        out[on_plot] += tint[plot_ids[a:b][on_plot]]
        return out

    rgb = pixel_colours(colours, size, layer.shape[1])
    # bleaching: smooth brightening and yellowing, strongest towards one corner
    yy, xx = np.mgrid[0:size, 0:size] / float(size)
    gx, gy = rng.uniform(-1, 1, size=2)
    ramp = gx * xx + gy * yy
    ramp = (ramp - ramp.min()) / max(ramp.max() - ramp.min(), 1e-9)
    bleach = 0.6 * ramp + 0.4 * _smooth_field(rng, (size, size), size / 8.0)
    rgb += (255.0 - rgb) * (0.28 * bleach)[..., None]
    rgb[..., 2] -= 26.0 * bleach
    rgb[..., 1] -= 6.0 * bleach
    # paper grain, print and scan noise: per pixel, per channel
    rgb += rng.normal(0, 3.5, size=(size, size, 1))
    rgb += rng.normal(0, 4.5, size=(size, size, 3))
    rgb = np.clip(np.rint(rgb), 0, 255).astype(np.uint8)
    # one plane misregistered by one pixel (false colour on every edge)
    band = rgb[..., _MISREGISTERED_BAND]
    dr, dc = _MISREGISTRATION
    shifted = np.roll(band, (dr, dc), axis=(0, 1))
    if dc > 0:
        shifted[:, :dc] = band[:, :dc]
    if dr > 0:
        shifted[:dr, :] = band[:dr, :]
    rgb[..., _MISREGISTERED_BAND] = shifted
    return rgb


def _pick_training(rng, drawn, cover, xy_of, labels=None, thin=(TEXT, SYMBOL)):
    """3-8 training points per class on clean pixels of that class, spread out.

    ``labels``: the values of ``drawn`` to place points on (default: every class of
    :data:`CLASSES`); those of ``thin`` (printed ink, drawn lines) go on pixels that
    their class covers for 7/9 at least, the others on pixels two pixels inside."""
    points, chosen_labels = [], []
    for label in sorted(CLASSES if labels is None else labels):
        if label in thin:
            mask = (drawn == label) & (cover[label] >= 7.0 / 9.0)
            min_dist = 15.0
        else:
            mask = ndimage.binary_erosion(drawn == label, iterations=2) & (cover[label] >= 1.0)
            min_dist = 40.0
        rows, cols = np.nonzero(mask)
        if len(rows) == 0:
            continue
        want = int(rng.integers(3, 9))
        order = rng.permutation(len(rows))
        min_dist = min(min_dist, drawn.shape[0] / 10.0)
        while True:  # spread out; closer together only where the class is scarce
            chosen = []
            for i in order:
                p = np.array([rows[i], cols[i]], dtype=float)
                if all(np.hypot(*(p - q)) >= min_dist for q in chosen):
                    chosen.append(p)
                    if len(chosen) == want:
                        break
            if len(chosen) >= 3 or min_dist < 1:
                break
            min_dist /= 2.0
        for r, c in chosen:
            points.append(xy_of(int(r), int(c)))
            chosen_labels.append(label)
    return (np.array(points, dtype=float).reshape(-1, 2),
            np.array(chosen_labels, dtype=np.int32))


def generate(seed=1, size=600, res=None, origin=(84000.0, 446000.0), style="delft"):
    """Generate the synthetic historical map.

    ``size`` pixels square at ``res`` metres (default: the style's
    :data:`STYLE_RES`); ``origin`` is the south-west corner in EPSG:28992.
    Lengths (streets, plots, letters) are in metres, so they are drawn at
    about 1 pixel per metre with the Delft map's ``res``. ``style`` is one of
    :data:`STYLES`: the other styles are drawn by synthetic_styles.py from
    their own random streams (the Delft map's draws are not changed by them).
    """
    if style not in STYLES:
        raise ValueError("style must be one of {}".format(", ".join(STYLES)))
    if size < 200:
        raise ValueError("size must be at least 200 pixels (a few blocks, every class)")
    res = STYLE_RES[style] if res is None else res
    if style != "delft":
        import synthetic_styles

        return synthetic_styles.generate(seed, size, res, origin, style)
    rng = np.random.default_rng(seed)
    layout = _layout(rng, size * res)
    return render(layout, rng, seed=seed, size=size, res=res, origin=origin)


def render(layout, rng, seed=1, size=600, res=1.0, origin=(84000.0, 446000.0)):
    """Draw a layout (as :func:`_layout` makes it: plots, gardens, canal, label
    anchors, in local metres) as a scanned map: its own trees, labels, symbols,
    print and scan defects and training points all come from ``rng``.

    :func:`generate` is this on the layout drawn from the same ``rng``; a
    layout changed between two map epochs (synthetic_epochs.py) is drawn by it
    as another map of the same region.
    """
    extent = size * res
    canvas = _Canvas(size, res)
    # which plot each sub-pixel's fill belongs to (1-based; 0: none)
    sub_ids = np.zeros((canvas.n, canvas.n),
                       dtype=np.int16 if len(layout["plots"]) < 2 ** 15 else np.int32)

    # ground: gardens and parks, with trees
    for g in layout["gardens"]:
        canvas.burn(g, _GREEN)
        minx, miny, maxx, maxy = g.bounds
        n_trees = int(g.area / 180)
        room = g.buffer(-2.5)  # where a tree's centre may stand
        shapely.prepare(room)
        for _ in range(n_trees):
            p = Point(rng.uniform(minx, maxx), rng.uniform(miny, maxy))
            if room.contains(p):
                canvas.burn(p.buffer(rng.uniform(1.2, 2.2), quad_segs=4), _TREE)
    # canal: water and its darker bank lines
    canvas.burn(layout["canal"], _WATER)
    canvas.burn(layout["canal"].difference(layout["canal"].buffer(-1.0)), _BANK)
    # building plots: fill, then a thin darker outline inside
    plots = [p for p, _, _ in layout["plots"]]
    kinds = [k for _, k, _ in layout["plots"]]
    for i, poly in enumerate(plots):
        window = canvas.burn(poly, _FILL)
        # remember which plot each sub-pixel belongs to (for the print tint): the fill
        # sub-pixels without a plot yet are all in the window this burn changed
        if window is not None:
            ids = sub_ids[window]
            ids[(canvas.layer[window] == _FILL) & (ids == 0)] = i + 1
        canvas.burn(poly.difference(poly.buffer(-0.9, join_style="mitre")), _OUTLINE)
    base = canvas.layer.copy()

    # text and symbols printed on top
    labels = _labels(rng, layout, extent)
    text_geoms = [_text_geometry(t, h, c, a, rng.uniform(1.0, 1.25)) for t, c, a, h in labels]
    text_geoms = [g for g in text_geoms if g is not None]
    for g in text_geoms:
        canvas.burn(g, _INK)
    symbols = _symbols(rng, layout, extent, unary_union(text_geoms) if text_geoms else None)
    for square, digits, _ in symbols:
        canvas.burn(square, _SYMBOL_INK)
        canvas.burn(digits, _SYMBOL_PAPER, mask=canvas.layer == _SYMBOL_INK)

    rgb = _render(rng, canvas.layer, sub_ids, len(plots), size)

    centre = _SUB // 2
    truth = _LAYER_CLASS[base[centre::_SUB, centre::_SUB]]
    drawn = _LAYER_CLASS[canvas.layer[centre::_SUB, centre::_SUB]]
    sub_class = _LAYER_CLASS.astype(np.int8)[canvas.layer]
    cover = {label: (sub_class == label).reshape(size, _SUB, size, _SUB).mean(axis=(1, 3))
             for label in CLASSES}
    ink = np.isin(canvas.layer, (_INK, _SYMBOL_INK)).reshape(size, _SUB, size, _SUB)
    ink_cover = ink.mean(axis=(1, 3))
    # text and symbol training points go on black pixels only
    cover[TEXT] = np.minimum(cover[TEXT], ink_cover)
    cover[SYMBOL] = np.minimum(cover[SYMBOL], ink_cover)

    x0, y0 = origin
    north = y0 + extent

    def xy_of(r, c):
        return (x0 + (c + 0.5) * res, north - (r + 0.5) * res)

    train_xy, train_label = _pick_training(rng, drawn, cover, xy_of)
    world = [affinity.translate(p, x0, y0) for p in plots]
    gt = np.array([[q.x, q.y] for q in (p.representative_point() for p in world)],
                  dtype=float).reshape(-1, 2)
    return SyntheticMap(
        seed=seed, rgb=rgb, truth=truth.astype(np.int32), drawn=drawn.astype(np.int32),
        plots=world, plot_kinds=kinds,
        training={"xy": train_xy, "label": train_label,
                  "class": [CLASSES[int(v)] for v in train_label]},
        gt_points=gt, north=north, south=y0, east=x0 + extent, west=x0, res=res,
        misregistration={"band": ("red", "green", "blue")[_MISREGISTERED_BAND],
                         "shift": _MISREGISTRATION},
        ink_cover=ink_cover,
    )


# ---------------------------------------------------------------------------
# Today's building footprints (the fixture of v.histo.align)
# ---------------------------------------------------------------------------

@dataclass
class CurrentFootprints:
    """Today's building footprints over the map, as a register such as the BAG has them.

    ``years`` are construction years (None: unknown; a few 9999
    placeholders, as the BAG writes); ``plot`` is the 1-based index of the
    true plot a footprint stands in (0: none; a straddling one: the plot
    that holds most of it); ``kind`` one of :data:`CURRENT_KINDS`:
    ``standing`` (a row house along a plot's street edge), ``offset`` (one
    of those, digitised 1-1.5 m off), ``straddling`` (over two plots and
    the street between), ``rebuilt`` (a modern block on a plot whose old
    buildings are gone), ``outside`` (away from every plot).
    """

    polygons: list
    years: list
    plot: list
    kind: list
    ids: list
    map_year: int = MAP_YEAR

    def built_before(self, year=None):
        """Indices of the footprints with a real construction year before ``year``."""
        year = self.map_year if year is None else year
        return [i for i, y in enumerate(self.years) if y is not None and y < min(year, 9999)]


def _draw_year(rng, map_year, old_share=0.7):
    """A construction year: mostly before the map, some after, a few unknown."""
    u = rng.random()
    if u < old_share:
        return int(rng.integers(1550, map_year))
    if u < 0.93:
        return int(rng.integers(map_year + 1, 2023))
    return None if u < 0.965 else 9999


def _edge_buildings(rng, plot, taken):
    """Row houses along the street edges of a plot: [polygon], none overlapping ``taken``."""
    ring = shapely.geometry.polygon.orient(plot, 1.0).exterior.simplify(0.05)
    coords = np.asarray(ring.coords)
    out = []
    for (ax, ay), (bx, by) in zip(coords[:-1], coords[1:]):
        length = math.hypot(bx - ax, by - ay)
        if length < 4:
            continue
        ux, uy = (bx - ax) / length, (by - ay) / length
        nx, ny = -uy, ux  # inward: the exterior runs counter-clockwise
        t = 0.0
        while t < length - 2:
            w = rng.uniform(5, 10)
            if length - (t + w) < 3:
                w = length - t
            d = rng.uniform(9, 15)
            p0 = (ax + ux * t, ay + uy * t)
            p1 = (ax + ux * (t + w), ay + uy * (t + w))
            rect = Polygon([p0, p1, (p1[0] + nx * d, p1[1] + ny * d),
                            (p0[0] + nx * d, p0[1] + ny * d)])
            t += w
            piece = rect.intersection(plot)
            near = [g for g in taken if g.intersects(piece)]
            if near:
                piece = piece.difference(unary_union(near))
            parts = [g for g in getattr(piece, "geoms", [piece]) if g.geom_type == "Polygon"]
            if not parts:
                continue
            piece = max(parts, key=lambda g: g.area)
            if piece.area < 20 or piece.area < 0.5 * min(rect.area, plot.area):
                continue
            piece = shapely.set_precision(piece, 0.01)
            if piece.is_empty or piece.geom_type != "Polygon":
                continue
            taken.append(piece)
            out.append(piece)
    return out


def _straddling(rng, plots, chosen, taken):
    """A few buildings over two close plots and the street between: [(polygon, plot)]."""
    from shapely.ops import nearest_points

    tree = shapely.STRtree(plots)
    out, used = [], set()
    for i in chosen:
        if len(out) == 3:
            break
        for j in tree.query(plots[i].buffer(14)):
            j = int(j)
            if j == i or j in used or i in used or j not in chosen:
                continue
            gap = plots[i].distance(plots[j])
            if not 3 <= gap <= 14:
                continue
            pa, pb = nearest_points(plots[i], plots[j])
            vx, vy = (pb.x - pa.x) / gap, (pb.y - pa.y) / gap
            width = rng.uniform(7, 10) / 2
            a = (pa.x - vx * 9, pa.y - vy * 9)
            b = (pb.x + vx * 3, pb.y + vy * 3)
            rect = Polygon([(a[0] - vy * width, a[1] + vx * width),
                            (b[0] - vy * width, b[1] + vx * width),
                            (b[0] + vy * width, b[1] - vx * width),
                            (a[0] + vy * width, a[1] - vx * width)])
            others = [plots[k] for k in tree.query(rect) if k not in (i, j)]
            if any(rect.intersects(o) for o in others) or \
                    rect.intersection(plots[i]).area < 2 * rect.intersection(plots[j]).area:
                continue
            rect = shapely.set_precision(rect, 0.01)
            out.append((rect, i))
            taken.append(rect)
            used.update((i, j))
            break
    return out


def current_footprints(rng, smap, map_year=MAP_YEAR):
    """Today's footprints over the map's plots (:class:`CurrentFootprints`).

    About two thirds of the plots keep row houses along their street edges
    (each with its own construction year, most before ``map_year``, some
    after, a few unknown; some houses missing); a few are digitised 1-1.5 m
    off, a few straddle two plots; half of the other plots carry one modern
    block; and a few buildings stand away from every plot (not on water).
    """
    plots = list(smap.plots)
    n = len(plots)
    chosen = sorted(int(i) for i in rng.permutation(n)[: int(round(0.7 * n))])
    polygons, years, owner, kind = [], [], [], []
    taken = []

    def add(poly, year, plot, what):
        polygons.append(poly)
        years.append(year)
        owner.append(plot)
        kind.append(what)

    for poly, i in _straddling(rng, plots, set(chosen), taken):
        add(poly, int(rng.integers(1600, map_year)), i + 1, "straddling")
    for i in chosen:
        for poly in _edge_buildings(rng, plots[i], [t for t in taken if t.intersects(plots[i])]):
            if rng.random() < 0.1:
                continue  # demolished: a gap in the row today
            add(poly, _draw_year(rng, map_year), i + 1, "standing")
    # a few old houses digitised a little off their place
    old = [k for k, (y, what) in enumerate(zip(years, kind))
           if what == "standing" and y is not None and y < map_year]
    for k in sorted(int(v) for v in rng.permutation(old)[:4]):
        angle = rng.uniform(0, 2 * math.pi)
        step = rng.uniform(1.0, 1.5)
        moved = affinity.translate(polygons[k], step * math.cos(angle), step * math.sin(angle))
        others = [p for m, p in enumerate(polygons) if m != k and p.intersects(moved)]
        if others:
            moved = moved.difference(unary_union(others))
        parts = [g for g in getattr(moved, "geoms", [moved]) if g.geom_type == "Polygon"]
        if parts:
            polygons[k] = shapely.set_precision(max(parts, key=lambda g: g.area), 0.01)
            kind[k] = "offset"
    for i in sorted(set(range(n)) - set(chosen)):
        if rng.random() < 0.5:
            block = plots[i].buffer(-1.5, join_style="mitre")
            parts = [g for g in getattr(block, "geoms", [block]) if g.geom_type == "Polygon"]
            if parts and max(g.area for g in parts) >= 40:
                add(shapely.set_precision(max(parts, key=lambda g: g.area), 0.01),
                    int(rng.integers(1950, 2023)), i + 1, "rebuilt")
    # away from every plot (and off the water): garden houses, villas, new estates
    away = unary_union(plots).buffer(25)
    shapely.prepare(away)
    minx, miny, maxx, maxy = smap.west, smap.south, smap.east, smap.north
    placed = 0
    for _ in range(400):
        if placed == 8:
            break
        cx, cy = rng.uniform(minx + 15, maxx - 15), rng.uniform(miny + 15, maxy - 15)
        house = affinity.rotate(box(cx - rng.uniform(4, 6), cy - rng.uniform(5, 7),
                                    cx + rng.uniform(4, 6), cy + rng.uniform(5, 7)),
                                rng.uniform(0, 90), origin=(cx, cy))
        if house.intersects(away) or any(house.distance(p) < 8 for p in polygons[-placed:]
                                         if placed):
            continue
        rows, cols = smap.to_pixel(np.asarray(house.exterior.coords))
        rows, cols = np.clip(rows, 0, smap.shape[0] - 1), np.clip(cols, 0, smap.shape[1] - 1)
        if np.any(smap.truth[rows, cols] == WATER):
            continue
        year = int(rng.integers(1600, map_year)) if placed % 2 == 0 else int(
            rng.integers(map_year + 1, 2023))
        add(shapely.set_precision(house, 0.01), year, 0, "outside")
        placed += 1
    ids = ["0503100000{:06d}".format(100000 + 17 * k) for k in range(len(polygons))]
    return CurrentFootprints(polygons, years, owner, kind, ids, map_year)


# ---------------------------------------------------------------------------
# Pictures without GRASS
# ---------------------------------------------------------------------------

def outline_plots(smap, rgb=None, colour=(200, 20, 20), polygons=None, width=1.0):
    """A copy of the picture with the true plots' boundaries (or those of ``polygons``)
    drawn in ``colour``, ``width`` metres inside them."""
    rgb = (smap.rgb if rgb is None else rgb).copy()
    size = rgb.shape[0]
    canvas = _Canvas(size, smap.res, sub=1)
    for poly in smap.plots if polygons is None else polygons:
        local = affinity.translate(poly, -smap.west, -smap.south)
        canvas.burn(local.difference(local.buffer(-width, join_style="mitre")), 1)
    rgb[canvas.layer == 1] = colour
    return rgb


def write_png(path, rgb, colours=None):
    """Write an RGB uint8 image as PNG; ``colours`` (<= 256) makes a palette image."""
    rgb = np.ascontiguousarray(rgb, dtype=np.uint8)
    h, w = rgb.shape[:2]
    if colours:
        from scipy.cluster.vq import kmeans2

        flat = rgb.reshape(-1, 3).astype(float)
        sample = flat[np.random.default_rng(0).choice(len(flat), min(len(flat), 20000),
                                                      replace=False)]
        centres, _ = kmeans2(sample, colours, seed=1, minit="++")
        centres = np.clip(np.rint(centres), 0, 255)
        d = ((flat[:, None, :] - centres[None, :, :]) ** 2).sum(axis=2)
        index = d.argmin(axis=1).astype(np.uint8).reshape(h, w)
        raw = b"".join(b"\x00" + index[r].tobytes() for r in range(h))
        header = struct.pack(">IIBBBBB", w, h, 8, 3, 0, 0, 0)
        chunks = [(b"IHDR", header), (b"PLTE", centres.astype(np.uint8).tobytes())]
    else:
        raw = b"".join(b"\x00" + rgb[r].tobytes() for r in range(h))
        chunks = [(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))]
    chunks.append((b"IDAT", zlib.compress(raw, 9)))
    chunks.append((b"IEND", b""))
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        for tag, data in chunks:
            f.write(struct.pack(">I", len(data)) + tag + data)
            f.write(struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF))


# ---------------------------------------------------------------------------
# GRASS
# ---------------------------------------------------------------------------

def map_names(prefix="map"):
    """Names of the maps :func:`write_to_grass` writes with ``prefix``."""
    return {
        "red": prefix + ".red", "green": prefix + ".green", "blue": prefix + ".blue",
        "training": prefix + "_training", "gt_points": prefix + "_gt_points",
        "plots": prefix + "_plots", "current": prefix + "_current",
    }


def _find_repo_library():
    here = os.path.dirname(os.path.abspath(__file__))
    root = os.path.dirname(here)
    if root not in sys.path:
        sys.path.insert(0, root)


def write_to_grass(smap, prefix="map"):
    """Write the map into the current mapset; returns the names written.

    Sets the region to the map, writes ``<prefix>.red``, ``.green``, ``.blue``
    (CELL 0-255 with grey colour tables) and the vectors ``<prefix>_training``
    (points: ``label``, ``class``), ``<prefix>_gt_points`` (points: ``plot``,
    the category of the plot they lie in), ``<prefix>_plots`` (areas:
    ``kind``) and ``<prefix>_current`` (areas: today's footprints with
    ``bouwjaar``, NULL where unknown, and ``identificatie``); and, for a
    style that draws divisions inside its plots (``smap.parcels``, not the
    Delft map), ``<prefix>_parcels`` (areas, one per parcel: ``plot``, the
    category of its plot, ``fill``, ``number``, the number written over it
    or NULL, ``crossed``, 1 for an outbuilding crossed by an X; its name is
    the ``parcels`` entry of the names returned). Respects
    GRASS_OVERWRITE / --overwrite like any module. The monochrome map adds
    ``<prefix>_hatched`` (areas, its hatched buildings: ``plot``, ``angle``,
    ``spacing``) and ``<prefix>_water`` (areas, its water: ``angle``,
    ``spacing`` of the hatching), the ``hatched`` and ``water`` entries.
    """
    names = write_map_to_grass(smap, prefix)
    write_current_to_grass(names["current"], smap.current, measured_heights(smap))
    return names


def write_map_to_grass(smap, prefix="map"):
    """Write the map without today's footprints (as :func:`write_to_grass` does
    otherwise); returns the names of :func:`map_names`, ``current`` unwritten."""
    _find_repo_library()
    import grass.script as gs

    from reconstruction import grassio

    names = map_names(prefix)
    if smap.parcels:
        names["parcels"] = prefix + "_parcels"
    if smap.hatched:
        names["hatched"], names["water"] = prefix + "_hatched", prefix + "_water"
    gs.run_command("g.region", quiet=True, **smap.region())
    for i, band in enumerate(("red", "green", "blue")):
        grassio.write_raster(names[band], smap.rgb[..., i].astype(np.int32),
                             title="Synthetic historical map (seed {}), {}".format(smap.seed, band))
        gs.run_command("r.colors", map=names[band], color="grey255", quiet=True)
    grassio.write_points(names["training"], smap.training["xy"],
                         {"label": [int(v) for v in smap.training["label"]],
                          "class": list(smap.training["class"])})
    cats = list(range(1, len(smap.plots) + 1))
    grassio.write_points(names["gt_points"], smap.gt_points, {"plot": cats})
    grassio.write_features(names["plots"], smap.plots, {"kind": list(smap.plot_kinds)},
                           cats=cats)
    if smap.parcels:
        info = smap.parcel_info
        grassio.write_features(
            names["parcels"], smap.parcels,
            {"plot": [p.plot for p in info], "fill": [p.fill for p in info],
             "number": [p.number for p in info], "crossed": [int(p.crossed) for p in info]},
            title="Parcels drawn on the synthetic {} map (seed {})".format(smap.style,
                                                                          smap.seed))
    if smap.hatched:
        title = "{{}} drawn on the synthetic monochrome map (seed {})".format(smap.seed)
        grassio.write_features(
            names["hatched"], smap.hatched,
            {"plot": [h.plot for h in smap.hatching], "angle": [h.angle for h in smap.hatching],
             "spacing": [h.spacing for h in smap.hatching]},
            title=title.format("Hatched buildings"))
        grassio.write_features(
            names["water"], smap.water,
            {"angle": [smap.water_hatching.angle] * len(smap.water),
             "spacing": [smap.water_hatching.spacing] * len(smap.water)},
            title=title.format("Water"))
    return names


def write_current_to_grass(name, current, heights):
    """Write today's footprints (:class:`CurrentFootprints`) as areas ``name`` with
    ``bouwjaar`` (NULL where unknown), ``identificatie`` and the ``heights``
    columns (as :func:`measured_heights` gives them)."""
    _find_repo_library()
    from reconstruction import grassio

    grassio.write_features(name, current.polygons,
                           {"bouwjaar": current.years, "identificatie": current.ids,
                            **heights},
                           title="Current building footprints over the synthetic map")
    return name


def measured_heights(smap):
    """Heights measured today on the current footprints, as the 3D BAG (2025)
    publishes them (absolute, m): ``b3_h_maaiveld`` ground, ``b3_h_50p`` and
    ``b3_h_70p`` roof percentiles, ``b3_h_nok`` the ridge. Houses of 6.7-12 m
    eaves and 2.6-6 m roofs (the thesis's ranges), one 30 m tower among
    them; the ground slopes gently. Drawn from their own random stream, so the
    map and the footprints do not change with them."""
    return footprint_heights(smap.current.polygons, smap.seed)


def footprint_heights(polygons, seed):
    """:func:`measured_heights` of any footprints ``polygons``, from the random
    stream of ``seed`` (so a town of several maps gets them as one map does)."""
    rng = np.random.default_rng([seed, 16])
    n = len(polygons)
    centres = np.array([[p.centroid.x, p.centroid.y] for p in polygons]).reshape(-1, 2)
    ground = 0.5 + 0.002 * centres[:, 0] + 0.001 * centres[:, 1] if n else np.zeros(0)
    eaves = rng.uniform(6.7, 12.0, n)
    attic = rng.uniform(2.6, 6.0, n)
    if n:
        eaves[n // 2], attic[n // 2] = 26.0, 4.0          # a church tower
    d = 0.3 * attic                   # so that p50 - 1.25 (p70 - p50) = the eaves
    rows = {"b3_h_maaiveld": ground, "b3_h_50p": ground + eaves + d,
            "b3_h_70p": ground + eaves + 1.8 * d, "b3_h_nok": ground + eaves + attic}
    return {k: [round(float(v), 2) for v in values] for k, values in rows.items()}


def plots_sampled(smap, step):
    """Rows and columns of every ``step``-th pixel, and whether its centre lies in a plot
    (for tests of the truth raster against the plots)."""
    rows, cols = np.mgrid[0:smap.shape[0]:step, 0:smap.shape[1]:step]
    x = smap.west + (cols + 0.5) * smap.res
    y = smap.north - (rows + 0.5) * smap.res
    inside = np.zeros(x.shape, bool)
    for poly in smap.plots:
        inside |= shapely.contains_xy(poly, x, y)
    return rows, cols, inside


def map_arguments(description, res=1.0):
    """The command line parser of a synthetic map's options (seed, size, resolution;
    ``res`` None: the style's, :data:`STYLE_RES`)."""
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--size", type=int, default=600, help="pixels per side")
    parser.add_argument("--res", type=float, default=res, help="metres per pixel" + (
        " (default: the style's, 1 for the Delft map)" if res is None else ""))
    return parser


def main(argv=None):
    parser = map_arguments("Write the synthetic historical map into the current GRASS mapset "
                           "(run inside a GRASS session), or as a PNG picture.", res=None)
    parser.add_argument("--prefix", default="map", help="prefix of the map names")
    parser.add_argument("--png", help="write only a PNG picture (plots outlined) to this path")
    parser.add_argument("--overwrite", action="store_true", help="replace existing maps")
    parser.add_argument("--style", choices=STYLES, default="delft",
                        help="the map's style: Delft 1961 (default), a colour-washed cadaster "
                        "(Venice 1808), a fire-insurance map (Sanborn 1892) or a monochrome "
                        "map (Paris 1925: outlined blocks, hatched buildings and water)")
    args = parser.parse_args(argv)
    smap = generate(seed=args.seed, size=args.size, res=args.res, style=args.style)
    if args.png:
        if smap.parcels:  # the parcels, a thin line inside each
            picture = outline_plots(smap, polygons=smap.parcels, width=smap.res)
        elif smap.hatched:  # the blocks, and the hatched buildings in another colour
            picture = outline_plots(smap, outline_plots(smap, width=smap.res),
                                    colour=(20, 110, 220), polygons=smap.hatched,
                                    width=smap.res)
        else:
            picture = outline_plots(smap)
        write_png(args.png, picture, colours=48)
        print("picture written to '{}'".format(args.png))
        return 0
    if not os.environ.get("GISRC"):
        parser.error("not inside a GRASS session: run it with grass <mapset> --exec")
    if args.overwrite:
        os.environ["GRASS_OVERWRITE"] = "1"
    os.environ.setdefault("GRASS_VERBOSE", "1")  # no progress bars from the raster import
    names = write_to_grass(smap, args.prefix)
    parcels = ", {} ({} parcels)".format(names["parcels"], len(smap.parcels)) \
        if smap.parcels else ""
    if smap.hatched:
        parcels = ", {} ({} hatched buildings), {} ({} water areas)".format(
            names["hatched"], len(smap.hatched), names["water"], len(smap.water))
    print("synthetic map (seed {}, {} x {} px at {} m) written: rasters {}, {}, {}; "
          "vectors {} ({} training points), {} ({} points), {} ({} plots), {} ({} current "
          "footprints){}".format(
              args.seed, args.size, args.size, smap.res, names["red"], names["green"],
              names["blue"], names["training"], len(smap.training["label"]),
              names["gt_points"], len(smap.gt_points), names["plots"], len(smap.plots),
              names["current"], len(smap.current.polygons), parcels))
    return 0


if __name__ == "__main__":
    # synthetic_styles.py imports this file as the module synthetic_map: the same one
    sys.modules.setdefault("synthetic_map", sys.modules[__name__])
    sys.exit(main())
