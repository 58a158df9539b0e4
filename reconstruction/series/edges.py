"""Sheet edges: which sheet builds a plot that an edge cuts.

The rule: **a plot belongs to the sheet whose own area (its extent in the
manifest) holds the larger part of the plot's area; on a tie, to the sheet
listed first in the manifest.** Each sheet's chain reads a margin of its
neighbours' maps (``margin`` metres around its own area, where a
neighbour's map is), so a plot cut by its edge is whole in its chain; it
keeps the plots it owns by this rule and leaves the others to their
neighbours. The chain does so with GRASS's own modules (the plots cut by
the grid of :func:`grid_geojson`, the pieces' areas, one SQL query:
:func:`owner_query`); :func:`owner_sheet` is the same rule in Python, which
the merge of the series applies to the buildings where two sheets' plots
disagree.
"""

from ..core.errors import InputError


def sheet_index(series, sheet):
    """The sheet's number in the grid (1, 2, ... in manifest order)."""
    for k, s in enumerate(series.sheets):
        if s.name == sheet.name:
            return k + 1
    raise InputError("The series has no sheet <{}>".format(sheet.name))


def chain_region(series, sheet):
    """The region of a sheet's chain: its own area grown by the margin, as
    far as the maps of the sheet and its neighbours reach (west, south,
    east, north)."""
    d = series.margin
    west, south, east, north = sheet.extent
    grown = [west - d, south - d, east + d, north + d]
    near = (sheet,) + series.neighbours(sheet)
    reach = (min(s.extent[0] for s in near), min(s.extent[1] for s in near),
             max(s.extent[2] for s in near), max(s.extent[3] for s in near))
    return (max(grown[0], reach[0]), max(grown[1], reach[1]),
            min(grown[2], reach[2]), min(grown[3], reach[3]))


def grid_geojson(series, near=None):
    """The sheets' own areas as GeoJSON polygons with their number ``sheet``
    (what the chains read to apply the rule): of every sheet, or of those
    of ``near`` (sheets of the series: a sheet and its neighbours, all a
    sheet's chain can see), still numbered in the series."""
    features = []
    names = None if near is None else {s.name for s in near}
    for k, s in enumerate(series.sheets):
        if names is not None and s.name not in names:
            continue
        w, so, e, n = s.extent
        ring = [[w, so], [e, so], [e, n], [w, n], [w, so]]
        features.append({"type": "Feature", "properties": {"sheet": k + 1, "name": s.name},
                         "geometry": {"type": "Polygon", "coordinates": [ring]}})
    return {"type": "FeatureCollection", "features": features}


def owner_query(index, pieces="pieces"):
    """The SQL ``where`` that keeps the plots owned by sheet ``index``: the
    plots (``cat``) whose piece on that sheet (table ``pieces`` of the plots
    cut by the grid, with ``a_cat`` the plot, ``b_sheet`` the sheet and
    ``area``) is larger than on every other sheet, or as large and the
    other sheet comes later."""
    return ("cat IN (SELECT p.a_cat FROM {t} p WHERE p.b_sheet = {i} AND NOT EXISTS "
            "(SELECT 1 FROM {t} q WHERE q.a_cat = p.a_cat AND q.b_sheet <> p.b_sheet AND "
            "(q.area > p.area OR (q.area = p.area AND q.b_sheet < p.b_sheet))))").format(
                t=pieces, i=int(index))


def owner_sheet(areas):
    """The owner by the rule: ``areas`` is a sequence of (sheet number, area
    of the part on that sheet); the number of the sheet with the largest
    part, the smallest number among equal ones (None for no part)."""
    best = None
    for sheet, area in areas:
        if area <= 0:
            continue
        if best is None or area > best[1] or (area == best[1] and sheet < best[0]):
            best = (sheet, area)
    return None if best is None else best[0]
