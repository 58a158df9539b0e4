"""Which roof a footprint gets: weights by construction period and footprint shape.

The thesis's Table B.1 (percent):

======================  ====================  ===================  ====================  ===================
roof                    4-sided, before 1915  4-sided, after 1915  n-sided, before 1915  n-sided, after 1915
======================  ====================  ===================  ====================  ===================
flat                    10                    25                   60                    60
hip                     20                    25                   --                    --
gable                   20                    25                   --                    --
mansard                 10                    10                   40                    40
crow-stepped gable      40                    15                   --                    --
======================  ====================  ===================  ====================  ===================

:data:`FIVE_TYPE_RULES` (the suite's
:data:`reconstruction.lod2.roofs.plan.ROOF_PROBABILITIES`, its default until
it had more roof families) keeps the 4-sided columns and changes the
n-sided ones to **flat 15, hip 65, mansard 20 before 1915; flat 40, hip 40,
mansard 20 after**. Why: the thesis gave n-sided footprints only flat and
mansard roofs because its procedural tool (BCGA in Blender) could not build
other roofs on them; its published script carries these "complex hip"
weights for n-sided footprints and overrides them with the table's only for
that reason. Here hip roofs are built on any footprint (the straight
skeleton, CGAL for concave ones), so 60 % flat roofs on the L, T and U
shaped houses of 19th-century blocks would be an artefact of the old tool,
not a finding about the buildings. :data:`THESIS_RULES` is the table as
printed; a ``rules=`` file reproduces it or any other.

The default (:data:`DEFAULT_RULES`, :data:`DEFAULT_TABLE`) extends that to
the roof families of Dutch and Belgian town houses of 1600-1950, by period
and by the footprint's span (the short side of its oriented bounding box):
the crow-stepped gable about 1600-1665, the spout gable 1620-1720, the neck
gable 1640-1780, the bell gable 1740-1780 (most common 1740-1770); wide
footprints (a span of 8 m or more, double-width houses) mostly get the ridge
along the street behind a cornice (dwarskap behind a lijstgevel) from the
later 17th century on; small ones (under 3.5 m: outbuildings, lean-tos) a
shed roof; square ones a pyramid (tent) or hip roof; other shapes the
five-type rules' n-sided weights. The last period (from 1916) is the
thesis's "after 1915" column with a share of every family: a footprint of
unknown construction year on a 20th-century map falls there, and the map
shows the buildings that stand, most of them older. The shares are the
suite's reading of the architectural literature's periods, not measured
frequencies; a ``rules=`` file changes them.

A rules file is UTF-8 text (a byte order mark and CRLF line ends, as Excel
writes "CSV UTF-8", are fine), CSV (``#`` comments allowed) or JSON::

    from,to,shape,flat,hip,gable,mansard,stepped
    ,1915,4,10,20,20,10,40
    1916,,4,25,25,25,10,15
    ,1915,n,60,0,0,40,0
    1916,,n,60,0,0,40,0

``from``/``to``: the period's first and last year, whole numbers (empty: open); periods
follow each other without gap (``from`` = the previous ``to`` + 1) from an
open start to an open end; a year belongs to the first period whose ``to``
is not below it, an unknown year to the first period. ``shape``: ``square``
(4-sided footprints whose oriented bounding box is at most
:data:`SQUARE_ASPECT` times as long as wide), ``4`` (4-sided footprints),
another vertex count, or ``n`` (every other shape; each period needs one of
any width). Optional columns ``min_width`` and ``max_width`` (m, empty:
open) limit a row to footprints whose span (the short side of their
oriented bounding box, the width the roof spans) is at least ``min_width``
and below ``max_width``. In its period a footprint takes the first row that
fits it: square rows first, then vertex counts, then ``n``, each in the
file's order. Weights in percent, one column per roof type
(:data:`reconstruction.lod2.roofs.plan.ROOF_TYPES`), numbers (not ``true``) summing to 100 in every row. JSON:
``{"rules": [{"from": null, "to": 1915, "shape": "4", "min_width": 8,
"weights": {"flat": 10, ...}}, ...]}``. Roofs lower than 1 m are flat whatever the rules say.
"""

import csv
import functools
import io
import json
import math
import re
from dataclasses import dataclass, field

from typing import Optional

import numpy as np
import shapely

from ...core import jsontext
from ...core.errors import InputError
from . import plan as roofs


#: a 4-sided footprint is "square" when its oriented bounding box's long side
#: is at most this times its short side
SQUARE_ASPECT = 1.25


def footprint_spans(rings):
    """(span, square) of footprints (rings (n, 2)): the short side of each one's
    smallest oriented bounding box (m), the width its roof spans, and
    whether it is a 4-sided footprint within :data:`SQUARE_ASPECT`."""
    rings = list(rings)
    if not rings:
        return np.zeros(0), np.zeros(0, dtype=bool)
    polygons = np.empty(len(rings), dtype=object)
    polygons[:] = [shapely.Polygon(np.asarray(r, dtype=float)) for r in rings]
    boxes = shapely.oriented_envelope(polygons)
    xy, owner = shapely.get_coordinates(boxes, return_index=True)
    first = np.searchsorted(owner, np.arange(len(rings)))
    whole = np.bincount(owner, minlength=len(rings)) >= 4     # a box, not a line or a point
    corners = np.stack([xy[np.minimum(first + k, len(xy) - 1)] for k in range(3)], axis=1)
    sides = np.hypot(*np.diff(corners, axis=1).transpose(2, 0, 1))
    span = np.where(whole, sides.min(axis=1), 0.0)
    long_side = np.where(whole, sides.max(axis=1), 0.0)
    counts = np.array([len(r) for r in rings])
    square = (counts == 4) & (long_side <= SQUARE_ASPECT * span)
    return span, square


@dataclass(frozen=True)
class RoofRule:
    """One row: a period (``first``..``last`` years, None = open), a shape class
    (``"square"``, ``"4"``, another vertex count, or ``"n"``), optionally a
    range of spans (``min_width`` <= span < ``max_width``, m, None = open) and
    the weights (name, percent) in drawing order. ``where`` says where the row
    stands in its file (``"line 7"``), for the messages; not compared."""

    first: float
    last: float
    shape: str
    weights: tuple
    min_width: Optional[float] = None
    max_width: Optional[float] = None
    where: str = field(default="", compare=False)

    @property
    def rank(self):
        """The order rows of one period are tried in: square, a vertex count, n."""
        return 0 if self.shape == "square" else 2 if self.shape == "n" else 1

    def matches(self, n_vertices, spans=None, square=None):
        """(F,) True for the footprints of this row's shape and span."""
        n_vertices = np.asarray(n_vertices)
        if self.shape == "n":
            ok = np.ones(n_vertices.shape, dtype=bool)
        elif self.shape == "square":
            ok = np.zeros(n_vertices.shape, dtype=bool) if square is None else \
                np.asarray(square, dtype=bool).copy()
        else:
            ok = n_vertices == int(self.shape)
        if self.min_width is not None or self.max_width is not None:
            span = np.full(n_vertices.shape, np.nan) if spans is None else np.asarray(spans, float)
            with np.errstate(invalid="ignore"):
                if self.min_width is not None:
                    ok &= span >= self.min_width
                if self.max_width is not None:
                    ok &= span < self.max_width
        return ok


@dataclass(frozen=True)
class RoofRules:
    """A table of :class:`RoofRule` rows; :meth:`draw` picks a roof per footprint."""

    rules: tuple

    def __post_init__(self):
        _check(self.rules)

    @functools.cached_property
    def periods(self):
        """The periods ``(first, last)`` in order."""
        return _periods(self.rules)

    @functools.cached_property
    def period_rows(self):
        """For each of :attr:`periods`, the indices into ``rules`` of its rows in
        the order they are tried (square rows first, then vertex counts, then
        ``n``; each in table order). Grouped once: a table of thousands of
        periods is read and drawn from in time linear in its rows."""
        index = {p: k for k, p in enumerate(self.periods)}
        rows = [[] for _ in self.periods]
        for k, r in enumerate(self.rules):
            rows[index[(r.first, r.last)]].append(k)
        return tuple(tuple(sorted(here, key=lambda k: self.rules[k].rank)) for here in rows)

    def row_of(self, n_vertices, years, spans=None, square=None):
        """(F,) index into ``rules`` of the row of every footprint: in its
        period, the first row (square rows first, then vertex counts, then
        ``n``; each in table order) whose shape and span it has."""
        n_vertices = np.asarray(n_vertices)
        years = np.asarray([np.nan if y is None else y for y in np.broadcast_to(
            np.asarray(years, dtype=object), n_vertices.shape)], dtype=float)
        period = self.period_of(years)
        row = np.full(n_vertices.shape, -1, dtype=np.int64)
        for p in np.unique(period):
            here = period == p
            for k in self.period_rows[p]:
                sel = here & (row < 0) & self.rules[k].matches(n_vertices, spans, square)
                row[sel] = k
        return row

    def draw(self, n_vertices, years, attic, uniforms, spans=None, square=None):
        """A roof type per footprint (object array) from one uniform number in
        [0, 1) per footprint (as :func:`reconstruction.lod2.roofs.plan.draw_roof_types`,
        which :data:`FIVE_TYPE_RULES` reproduce exactly); ``spans`` and
        ``square`` (:func:`footprint_spans`) for rows by span and square shape."""
        n_vertices = np.asarray(n_vertices)
        u = np.asarray(uniforms, dtype=float).reshape(n_vertices.shape)
        row = self.row_of(n_vertices, years, spans, square)
        out = np.empty(n_vertices.shape, dtype=object)
        for k, rule in enumerate(self.rules):
            sel = row == k
            if not sel.any():
                continue
            out[sel] = roofs.weighted_pick(rule.weights, u[sel])
        out[np.asarray(attic, dtype=float) < roofs.MIN_PITCHED_HEIGHT] = "flat"
        return out

    def period_of(self, years):
        """The index into :attr:`periods` of each of ``years`` (floats; NaN,
        an unknown year: the first period)."""
        years = np.asarray(years, dtype=float)
        ends = np.array([np.inf if last is None else last for _, last in self.periods])
        return np.where(np.isnan(years), 0, np.searchsorted(ends, years, side="left"))

    def types_in(self, year):
        """The roof types with a share in some row of ``year``'s period (None: the first)."""
        p = int(self.period_of(np.nan if year is None else year))
        return {k for r in self.period_rows[p] for k, w in self.rules[r].weights if w > 0}

    def table(self):
        """The rules as CSV text (the rules-file format)."""
        names = list(roofs.ROOF_TYPES)
        lines = ["from,to,shape,min_width,max_width," + ",".join(names)]
        for r in self.rules:
            w = dict(r.weights)
            lines.append(",".join([_number_text(r.first), _number_text(r.last), r.shape,
                                   _number_text(r.min_width), _number_text(r.max_width)]
                                  + ["{:g}".format(w.get(n, 0)) for n in names]))
        return "\n".join(lines) + "\n"


def _number_text(value):
    return "" if value is None else "{:g}".format(value)


def _periods(rules):
    """The distinct periods ``(first, last)`` of ``rules``, by first year (open first)."""
    return sorted(dict.fromkeys((r.first, r.last) for r in rules),
                  key=lambda p: -math.inf if p[0] is None else p[0])


#: a shape that is a vertex count: ASCII digits (``int`` takes other digits,
#: "²".isdigit() is true and ``int`` refuses it), few enough for any footprint
_VERTEX_COUNT = re.compile(r"[0-9]{1,9}")


def _check(rules, where="rules"):
    if not rules:
        raise InputError("The roof {} have no rows".format(where))
    seen = set()
    for k, r in enumerate(rules):
        what = "{} ({}, {}-sided)".format(r.where or "row {}".format(k + 1),
                                         _period_text(r.first, r.last), r.shape)
        if r.shape not in ("n", "square") and not (_VERTEX_COUNT.fullmatch(r.shape)
                                                    and int(r.shape) >= 3):
            raise InputError("Roof rules {}: shape must be n, square or a vertex count of 3 or "
                             "more, not <{}>".format(what, r.shape))
        if r.first is not None and r.last is not None and r.first > r.last:
            raise InputError("Roof rules {}: the period starts after it ends (from {:g}, to "
                             "{:g}): from is its first year, to its last".format(
                                 what, r.first, r.last))
        for bound in (r.min_width, r.max_width):
            if bound is not None and not (math.isfinite(bound) and bound >= 0):
                raise InputError("Roof rules {}: a width must be a number of metres, 0 or "
                                 "more, not {}".format(what, bound))
        if r.min_width is not None and r.max_width is not None and r.max_width <= r.min_width:
            raise InputError("Roof rules {}: max_width {:g} is not above min_width {:g}".format(
                what, r.max_width, r.min_width))
        names = set()
        for name, w in r.weights:
            if name not in roofs.ROOF_TYPES:
                raise InputError("Roof rules {}: unknown roof type <{}> (known: {})".format(
                    what, name, ", ".join(roofs.ROOF_TYPES)))
            if name in names:
                raise InputError("Roof rules {}: two weights for {}".format(what, name))
            names.add(name)
            if not (w >= 0 and math.isfinite(w)):
                raise InputError("Roof rules {}: weight of {} must be 0 or more, not {}".format(
                    what, name, w))
        total = sum(w for _, w in r.weights)
        if abs(total - 100.0) > 1e-6:
            raise InputError("Roof rules {}: the weights sum to {:g}, not 100".format(what, total))
        key = (r.first, r.last, r.shape, r.min_width, r.max_width)
        if key in seen:
            raise InputError("Roof rules {}: a second row for the same period, shape and "
                             "widths".format(what))
        seen.add(key)
    periods = _periods(rules)
    if periods[0][0] is not None or periods[-1][1] is not None:
        raise InputError("Roof rules: the first period must have no start and the last no end "
                         "(every year needs a row), not {}".format(
                             _periods_text(periods)))
    for (f0, l0), (f1, l1) in zip(periods, periods[1:]):
        if l0 is None or f1 is None or f1 != l0 + 1:
            raise InputError("Roof rules: periods {} and {} do not follow each other (the "
                             "next starts the year after the last ends)".format(
                                 _period_text(f0, l0), _period_text(f1, l1)))
    covered = {(r.first, r.last) for r in rules
               if r.shape == "n" and r.min_width is None and r.max_width is None}
    for p in periods:
        if p not in covered:
            raise InputError("Roof rules: period {} has no row for n-sided footprints "
                             "(shape n, every other shape, of any width: min_width and "
                             "max_width empty)".format(_period_text(*p)))


def _periods_text(periods):
    """The periods as text, the first three and the last of a long list."""
    shown = [_period_text(*p) for p in (periods if len(periods) <= 4 else
                                        periods[:3] + periods[-1:])]
    return ", ".join(shown if len(periods) <= 4 else shown[:3] + ["..."] + shown[-1:])


def _period_text(first, last):
    return "{}-{}".format("" if first is None else "{:g}".format(first),
                          "" if last is None else "{:g}".format(last))


def _rules_from_probabilities(probabilities, split):
    bounds = {"before": (None, float(split)), "after": (float(split) + 1, None)}
    return RoofRules(tuple(RoofRule(*bounds[period], str(shape), tuple(weights.items()))
                           for (period, shape), weights in probabilities.items()))


#: the suite's rules with the thesis's five roof types
#: (:data:`reconstruction.lod2.roofs.plan.ROOF_PROBABILITIES`, see the module doc)
FIVE_TYPE_RULES = _rules_from_probabilities(roofs.ROOF_PROBABILITIES, roofs.SPLIT_YEAR)
#: the thesis's Table B.1 as printed
THESIS_RULES = _rules_from_probabilities({
    ("before", 4): {"flat": 10, "hip": 20, "gable": 20, "mansard": 10, "stepped": 40},
    ("after", 4): {"flat": 25, "hip": 25, "gable": 25, "mansard": 10, "stepped": 15},
    ("before", "n"): {"flat": 60, "mansard": 40},
    ("after", "n"): {"flat": 60, "mansard": 40},
}, 1915)


# ---------------------------------------------------------------------------
# Rules files
# ---------------------------------------------------------------------------

def _year(text, what):
    """A period's first or last year: a whole number, or None (empty: open).
    A fraction or a JSON boolean is refused: periods are whole years, and a
    year of 1849.5 would only surface later as periods that "do not follow
    each other"."""
    if text is None or (isinstance(text, str) and not text.strip()):
        return None
    if isinstance(text, bool):
        raise InputError("Roof rules {}: a year must be a number, not {}".format(
            what, json.dumps(text)))
    try:
        value = float(text)
    except (TypeError, ValueError, OverflowError):
        raise InputError("Roof rules {}: a year must be a number, not <{}>".format(
            what, text)) from None
    if not math.isfinite(value):
        raise InputError("Roof rules {}: a year must be finite, not <{}>".format(what, text))
    if not value.is_integer():
        raise InputError("Roof rules {}: a year must be a whole number, not <{}> (a period "
                         "runs from its first year to its last, both included)".format(
                             what, text))
    return value


def _weight(text, what):
    """A weight in percent (empty: 0). A JSON boolean is refused, not taken as 1 or 0."""
    if text is None or (isinstance(text, str) and not text.strip()):
        return 0.0
    if isinstance(text, bool):
        raise InputError("Roof rules {}: a weight must be a number of percent, not {}".format(
            what, json.dumps(text)))
    try:
        return float(text)
    except (TypeError, ValueError, OverflowError):
        raise InputError("Roof rules {}: a weight must be a number, not <{}>".format(
            what, text)) from None


#: the optional columns (keys) of a span range: min_width <= span < max_width (m)
WIDTH_COLUMNS = ("min_width", "max_width")


def _width(text, column, what):
    """A span bound in metres (empty or None: open). A JSON boolean is refused."""
    if text is None or (isinstance(text, str) and not text.strip()):
        return None
    if isinstance(text, bool):
        raise InputError("Roof rules {}: {} must be a number of metres, not {}".format(
            what, column, json.dumps(text)))
    try:
        return float(text)
    except (TypeError, ValueError, OverflowError):
        raise InputError("Roof rules {}: {} must be a number of metres, not <{}>".format(
            what, column, text)) from None


def _csv_records(text):
    """(line, cells) of each record of CSV ``text`` but blank lines and ``#``
    comments, ``line`` the number of its first line in the file (1: the
    first line; comments and blank lines counted), the number an editor shows."""
    numbers = []

    def lines():
        for number, line in enumerate(io.StringIO(text, newline=""), start=1):
            if line.strip() and not line.lstrip().startswith("#"):
                numbers.append(number)
                yield line

    reader = csv.reader(lines())
    while True:
        try:
            cells = next(reader, None)
        except csv.Error as error:
            raise InputError("Roof rules line {}: not CSV ({})".format(
                numbers[0] if numbers else 1, error)) from None
        if cells is None:
            return
        yield numbers[0], cells
        numbers.clear()


def _from_csv(text):
    records = _csv_records(text)
    line, cells = next(records, (1, []))
    header = [h.strip().lower() for h in cells]
    for need in ("from", "to", "shape"):
        if need not in header:
            raise InputError("Roof rules: the CSV header needs columns from, to, shape and one "
                             "per roof type (got {})".format(", ".join(header) or "nothing"))
    for k, name in enumerate(header):
        if name in header[:k]:
            raise InputError("Roof rules line {}: the column <{}> appears twice in the header "
                             "(columns {} and {}): one column per roof type".format(
                                 line, name, header.index(name) + 1, k + 1))
    names = [h for h in header if h not in ("from", "to", "shape") + WIDTH_COLUMNS]
    rows = []
    for line, cells in records:
        what = "line {}".format(line)
        if len(cells) != len(header):
            raise InputError("Roof rules {}: {} values for {} columns".format(
                what, len(cells), len(header)))
        cell = dict(zip(header, (c.strip() for c in cells)))
        rows.append(RoofRule(_year(cell["from"], what), _year(cell["to"], what),
                             cell["shape"].lower(),
                             tuple((n, _weight(cell[n], what)) for n in names),
                             *(_width(cell.get(c), c, what) for c in WIDTH_COLUMNS),
                             where=what))
    return tuple(rows)


def _from_json(text, path):
    data = jsontext.loads(text, RULES_FILE, path)
    items = data.get("rules") if isinstance(data, dict) else data
    if not isinstance(items, list):
        raise InputError('Roof rules: the JSON must be {"rules": [...]} or a list of rows')
    rows = []
    for k, item in enumerate(items, start=1):
        what = "row {}".format(k)
        if not isinstance(item, dict) or not isinstance(item.get("weights"), dict):
            raise InputError("Roof rules {}: needs from, to, shape and weights".format(what))
        rows.append(RoofRule(_year(item.get("from"), what), _year(item.get("to"), what),
                             str(item.get("shape", "")).strip().lower(),
                             tuple((str(n).strip().lower(), _weight(w, what))
                                   for n, w in item["weights"].items()),
                             *(_width(item.get(c), c, what) for c in WIDTH_COLUMNS),
                             where=what))
    return tuple(rows)


#: what a rules file is called in the messages of :mod:`reconstruction.core.jsontext`
RULES_FILE = "roof rules file"


def parse_rules(text, path="(text)"):
    """:class:`RoofRules` from the text of a rules file (JSON when it starts
    with ``{`` or ``[``, else CSV; ``path`` names it in the messages). A byte
    order mark and CRLF line ends (Excel's CSV) are accepted. Raises
    InputError on any mistake."""
    text = text[1:] if text.startswith(BOM) else text
    stripped = text.lstrip()
    rows = _from_json(text, path) if stripped[:1] in ("{", "[") else _from_csv(text)
    return RoofRules(rows)


#: the byte order mark Excel and Notepad put at the start of a UTF-8 file
BOM = "\ufeff"


def read_rules(path):
    """:class:`RoofRules` from a rules file (see the module doc), UTF-8 text
    (with or without a byte order mark). A file of another encoding
    (Latin-1) or a binary file is refused with one InputError naming it."""
    text = jsontext.read_text(path, RULES_FILE)
    if "\x00" in text:
        raise InputError("The roof rules file '{}' is a binary file, not UTF-8 text: save it "
                         "as CSV UTF-8 or JSON".format(path))
    return parse_rules(text, path)


#: the default rules as a rules file (see the module doc); percent per row
DEFAULT_TABLE = """\
from,to,shape,min_width,max_width,flat,hip,gable,mansard,stepped,neck,bell,spout,half_hip,pyramid,gambrel,shed,cornice
# before 1600: gables, hipped and half-hipped roofs
,1599,4,,3.5,30,0,20,0,0,0,0,0,0,0,0,50,0
,1599,4,3.5,8,5,10,60,0,15,0,0,0,10,0,0,0,0
,1599,4,8,,10,30,40,0,0,0,0,0,20,0,0,0,0
,1599,square,,,10,40,0,10,0,0,0,0,0,40,0,0,0
,1599,n,,,15,65,0,20,0,0,0,0,0,0,0,0,0
# 1600-1639: the crow-stepped gable, the first spout gables
1600,1639,4,,3.5,30,0,20,0,0,0,0,0,0,0,0,50,0
1600,1639,4,3.5,8,5,5,25,0,45,0,0,15,5,0,0,0,0
1600,1639,4,8,,10,25,20,0,25,0,0,0,0,0,0,0,20
1600,1639,square,,,10,40,0,10,0,0,0,0,0,40,0,0,0
1600,1639,n,,,15,65,0,20,0,0,0,0,0,0,0,0,0
# 1640-1665: crow-stepped, spout and the first neck gables
1640,1665,4,,3.5,30,0,20,0,0,0,0,0,0,0,0,50,0
1640,1665,4,3.5,8,5,5,20,0,35,20,0,15,0,0,0,0,0
1640,1665,4,8,,10,25,20,0,25,0,0,0,0,0,0,0,20
1640,1665,square,,,10,40,0,10,0,0,0,0,0,40,0,0,0
1640,1665,n,,,15,65,0,20,0,0,0,0,0,0,0,0,0
# 1666-1739: the neck gable; wide houses with the ridge along the street
1666,1739,4,,3.5,30,0,20,0,0,0,0,0,0,0,0,50,0
1666,1739,4,3.5,8,5,10,30,0,5,35,0,10,5,0,0,0,0
1666,1739,4,8,,10,25,15,10,0,0,0,0,0,0,0,0,40
1666,1739,square,,,10,40,0,10,0,0,0,0,0,40,0,0,0
1666,1739,n,,,15,65,0,20,0,0,0,0,0,0,0,0,0
# 1740-1780: bell and neck gables
1740,1780,4,,3.5,30,0,20,0,0,0,0,0,0,0,0,50,0
1740,1780,4,3.5,8,5,10,20,5,0,25,30,0,0,0,5,0,0
1740,1780,4,8,,10,20,5,20,0,0,0,0,0,0,0,0,45
1740,1780,square,,,10,40,0,10,0,0,0,0,0,40,0,0,0
1740,1780,n,,,15,65,0,20,0,0,0,0,0,0,0,0,0
# 1781-1915: straight cornice facades, mansard and gambrel roofs
1781,1915,4,,3.5,30,0,20,0,0,0,0,0,0,0,0,50,0
1781,1915,4,3.5,8,15,15,35,15,0,5,5,0,5,0,5,0,0
1781,1915,4,8,,20,20,0,20,0,0,0,0,0,0,0,0,40
1781,1915,square,,,10,40,0,10,0,0,0,0,0,40,0,0,0
1781,1915,n,,,15,65,0,20,0,0,0,0,0,0,0,0,0
# from 1916 (and a 20th-century map's footprints of unknown year): the thesis's
# "after 1915" column with a share of the older families
1916,,4,,3.5,30,0,20,0,0,0,0,0,0,0,0,50,0
1916,,4,3.5,8,25,20,20,10,10,3,2,0,5,0,5,0,0
1916,,4,8,,30,25,10,10,0,0,0,0,0,0,5,0,20
1916,,square,,,30,30,0,10,0,0,0,0,0,30,0,0,0
1916,,n,,,40,40,0,20,0,0,0,0,0,0,0,0,0
"""
#: the suite's default rules (:data:`DEFAULT_TABLE`, see the module doc)
DEFAULT_RULES = parse_rules(DEFAULT_TABLE)

