"""The data-flow contract between the modules, in code.

Column names and values that pass from one module to the next
(``../shared/docs/data-flow.md``). Every module and test uses these names
instead of string literals.
"""

#: category of a plot in the plots map; later maps refer to it in a PLOT column
PLOT = "plot"
#: how a footprint was made: SOURCE_PROCEDURAL (generated), SOURCE_ALIGNED (a current
#: footprint that already stood) or SOURCE_DRAWN (a unit the map draws: a parcel, a building)
SOURCE = "source"
SOURCE_PROCEDURAL = "2pm"
SOURCE_ALIGNED = "aligned"
SOURCE_DRAWN = "drawn"
#: procedural case (0-5) of v.histo.subdivide ("pm_case": 2D procedural modelling's
#: case; not "case", an SQL keyword that core GRASS tools do not quote, issue 12)
CASE = "pm_case"
#: footprint area (m2)
AREA = "area"
#: matching similarity of an aligned footprint (v.histo.align)
SIMILARITY = "similarity"
#: heights: terrain elevation, wall height above ground, roof height above the eaves
GROUND = "ground"
EAVES = "eaves"
ATTIC = "attic"
#: where a footprint's heights come from (v.histo.lod2 writes it as an attribute)
HEIGHT_SOURCE = "height_source"
#: its values: measured (aligned footprint), plot (its plot's aligned footprints),
#: neighbours (aligned footprints around it), points (building points), range
#: (drawn from height=/attic=), column (eaves_column=/attic_column=)
HEIGHTS_MEASURED = "measured"
HEIGHTS_PLOT = "plot"
HEIGHTS_NEIGHBOURS = "neighbours"
HEIGHTS_POINTS = "points"
HEIGHTS_RANGE = "range"
HEIGHTS_COLUMN = "column"
#: a building copied whole from an existing (current) 3D model: its heights,
#: roof and solid are that model's
HEIGHTS_COPIED = "copied"

#: a building's certainty class (v.histo.lod2 writes it as ``certainty``; the
#: web page names it): value -> name, surest first (reconstruction.lod2.certainty)
CERTAINTY_CLASSES = {5: "copied", 4: "measured", 3: "aligned", 2: "generated", 1: "drawn"}

#: how far (map units) a current footprint may lie from a plot and still be aligned
#: with it (v.histo.align buffer=, its default); v.histo.subdivide places an aligned
#: footprint that overlaps no plot in the nearest plot within this distance
ALIGN_BUFFER = 10.0

#: every column name above (the values are not column names): none may be an SQL
#: keyword (reconstruction/core/names.py, tested)
COLUMNS = (PLOT, SOURCE, CASE, AREA, SIMILARITY, GROUND, EAVES, ATTIC, HEIGHT_SOURCE)

# ---------------------------------------------------------------------------
# A dynamic chain: several map epochs of one town (issue 28)
# ---------------------------------------------------------------------------

#: a footprint's building identity over the epochs (v.histo.subdivide year=): kept
#: from the earlier epoch, the BAG id of an aligned footprint, or a new one
BUILDING = "building"
#: how a footprint's plot changed since the earlier epoch (v.histo.subdivide previous=)
PLOT_CHANGE = "plot_change"
#: the BAG id columns of current footprints, as registers and the thesis's data name it
BAG_ID_COLUMNS = ("identificatie", "identifica", "pand_id")
#: the identity of a footprint made in the epoch of ``year``, the ``number``-th footprint
NEW_BUILDING = "building_{year}_{number}"

#: the columns of a dynamic chain, among :data:`COLUMNS` (no SQL keywords either)
EPOCH_COLUMNS = (BUILDING, PLOT_CHANGE)
COLUMNS = COLUMNS + EPOCH_COLUMNS
