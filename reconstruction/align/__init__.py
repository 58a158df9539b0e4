"""Stage 3, v.histo.align: the current footprints that already stood at the map's date.

The thesis's Section 3.3.1: today's footprints built before the map's year
(``bouwjaar``) are matched one-to-many with the historical plots they lie
in, optionally after correcting the map's offset; each kept footprint gets
its ``plot`` and ``similarity``.

- ``stage``: the stage's entry point (:func:`align`) and its records.
"""

from . import stage
from .stage import Alignment, AlignmentConfig, align

__all__ = ["Alignment", "AlignmentConfig", "align", "stage"]
