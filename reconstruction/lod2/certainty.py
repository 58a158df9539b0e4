"""How sure a building of the model is: one class on an ordinal scale (issue 31).

Historians working with reconstructions ask for degrees of certainty and
for the provenance (paradata) of every element. Each building says where
its values came from (``source``: an aligned current footprint, a unit the
map draws (``drawn``: a parcel or a building outlined on the map) or one the
plot's subdivision generated; ``height_source``: measured, inferred from
measured neighbours, drawn from a range; the interval of its heights,
:data:`~reconstruction.lod2.inputs.INTERVAL_ATTRIBUTES`; ``roof_source``:
why it has its roof type, :class:`~reconstruction.lod2.stage.RoofRequests`),
and, in
``certainty``, one class that sums them up, from the surest:

==  ============  ==========================================================
5   copied        a building that still stands, copied whole from a current
                  3D model (its solid, roof and heights are that model's)
4   measured      a current footprint that stood at the map's date, with
                  its heights measured (3D BAG, building points)
3   aligned       a current footprint that stood at the map's date, or a
                  footprint the map draws, its heights inferred from
                  measured neighbours or given; or a generated or drawn
                  footprint with measured heights
2   generated     a footprint generated in its plot, its heights inferred
                  from measured neighbours or given in the footprints' columns
1   drawn         heights drawn from ranges, or nothing measured anywhere
==  ============  ==========================================================

The class and the height interval agree: a measured height (class 4, or 3
on a generated footprint) is its own interval, of no width, the building's
eaves and top as built (:func:`~reconstruction.lod2.stage.built_intervals`);
an inferred or drawn one (classes 3 to 1) spans its neighbours' spread or
its range, around the built heights.

A building copied from an existing 3D model keeps that model's attributes
and gets ``certainty`` 5 and ``height_source`` and ``roof_source``
``copied`` where it has none of its own (:data:`COPIED_ATTRIBUTES`).
Pure: numpy.
"""

import numpy as np

from ..core.contract import (CERTAINTY_CLASSES, HEIGHT_SOURCE, HEIGHTS_COLUMN, HEIGHTS_COPIED, HEIGHTS_MEASURED,
                             HEIGHTS_NEIGHBOURS, HEIGHTS_PLOT, HEIGHTS_POINTS, SOURCE_ALIGNED,
                             SOURCE_DRAWN)

COPIED, MEASURED, ALIGNED, GENERATED, DRAWN = 5, 4, 3, 2, 1
#: the classes' names, surest first
CLASSES = CERTAINTY_CLASSES
#: the paradata of a building copied from an existing 3D model (attribute: value)
COPIED_ATTRIBUTES = (("certainty", COPIED), (HEIGHT_SOURCE, HEIGHTS_COPIED),
                     ("roof_source", HEIGHTS_COPIED))


def certainty(footprint_source, height_source):
    """The certainty class (:data:`CLASSES`) of every footprint from its footprint
    source (``aligned``, ``drawn`` or anything else, e.g. ``2pm``; None: unknown,
    counted as generated) and its height source (a ``height_source`` value). A
    footprint the map draws is as sure of its outline as an aligned one, but no
    current building measured it: measured heights make it class 3, not 4."""
    height = np.asarray(height_source, dtype=object)
    sources = footprint_source if footprint_source is not None else [None] * len(height)
    aligned = np.asarray([s == SOURCE_ALIGNED for s in sources], dtype=bool)
    outlined = aligned | np.asarray([s == SOURCE_DRAWN for s in sources], dtype=bool)
    measured = np.isin(height, [HEIGHTS_MEASURED, HEIGHTS_POINTS])
    inferred = np.isin(height, [HEIGHTS_NEIGHBOURS, HEIGHTS_PLOT, HEIGHTS_COLUMN])
    out = np.full(len(height), DRAWN, dtype=np.int64)
    out[inferred] = np.where(outlined[inferred], ALIGNED, GENERATED)
    out[measured] = np.where(aligned[measured], MEASURED, ALIGNED)
    return out
