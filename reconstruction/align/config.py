"""v.histo.align's options as one record: :class:`AlignmentConfig` and :func:`read_config`.

The matching parameters (year, buffer, overlap, offset correction) are the
ones the JSON report lists under ``options``; the map names and the year
column asked for follow them (:data:`MATCHING` holds the former).
"""

import math
from dataclasses import dataclass, field, fields

from ..core.contract import ALIGN_BUFFER
from ..core.errors import InputError
from ..core.options import parse_list, parse_number

#: the year column asked for by default (BAG); the 3D BAG's name is taken when it is absent
DEFAULT_YEAR_COLUMN = "bouwjaar"
#: a field of the map names and texts of the module, not of the matching itself
_NAME = {"matching": False}


@dataclass(frozen=True)
class AlignmentConfig:
    """How current footprints are matched with plots (lengths in map units).

    ``year``: the map's year; footprints built strictly before it are
    candidates (also those built in it with ``include_year``, as the thesis
    did). ``buffer``: distance each plot grows by before matching.
    ``overlap``: the similarity threshold, in (0, 1]. ``shift``: largest
    offset the local offset correction searches (0: off); ``shift_window``:
    margin around a plot whose plots and footprints estimate its offset;
    ``shift_cell``: raster cell of that estimate; ``min_gain``: share by
    which the overlap must grow for a shift to be applied.

    The module's names, not part of the matching: ``plots``, ``footprints``
    (input maps), ``output``, ``unmatched`` (output maps, ``unmatched`` empty
    when not asked for), ``report_file`` (JSON file, empty: none),
    ``year_column`` (the column asked for; ``year_column_given``: not the
    default, so no fallback to the 3D BAG's column), ``year_text`` (year= as
    written, for the messages) and ``shell`` (-g: the counts as key=value).
    """

    year: float
    buffer: float = ALIGN_BUFFER
    overlap: float = 0.6
    include_year: bool = False
    shift: float = 0.0
    shift_window: float = 150.0
    shift_cell: float = 1.0
    min_gain: float = 0.02
    plots: str = field(default="", metadata=_NAME)
    footprints: str = field(default="", metadata=_NAME)
    output: str = field(default="", metadata=_NAME)
    unmatched: str = field(default="", metadata=_NAME)
    report_file: str = field(default="", metadata=_NAME)
    year_column: str = field(default=DEFAULT_YEAR_COLUMN, metadata=_NAME)
    year_column_given: bool = field(default=False, metadata=_NAME)
    year_text: str = field(default="", metadata=_NAME)
    shell: bool = field(default=False, metadata=_NAME)

    def __post_init__(self):
        if not math.isfinite(self.year):
            raise InputError("The map's year must be a number, not {}".format(self.year))
        if not (math.isfinite(self.buffer) and self.buffer > 0):
            raise InputError("The buffer must be positive (map units), not {:g}".format(
                self.buffer))
        if not (0 < self.overlap <= 1):
            raise InputError("The overlap threshold must be in (0, 1], not {:g}".format(
                self.overlap))
        if not (math.isfinite(self.shift) and self.shift >= 0):
            raise InputError("The shift search radius must be zero (off) or positive, "
                             "not {:g}".format(self.shift))
        if self.shift_window < 0 or self.shift_cell <= 0:
            raise InputError("The shift window must be >= 0 and its cell > 0")

    @property
    def map_year(self):
        """The map's year as the messages write it (year= as given)."""
        return self.year_text or "{:g}".format(self.year)


#: the matching parameters, in their order (the JSON report's ``options``)
MATCHING = tuple(f.name for f in fields(AlignmentConfig) if f.metadata.get("matching", True))


def matching_options(config):
    """The matching parameters of ``config`` as a dict (the JSON report's ``options``)."""
    return {name: getattr(config, name) for name in MATCHING}


def buffer_from_resolution(resolution, k):
    """Ying et al.'s (2011) buffer ``k * sqrt(SR_a**2 + SR_b**2)``.

    ``resolution`` holds the two maps' pixel sizes (map units; one value
    is used for both), ``k`` the factor.
    """
    values = [float(v) for v in resolution]
    if len(values) == 1:
        values = values * 2
    if len(values) != 2 or not all(math.isfinite(v) and v > 0 for v in values):
        raise InputError("The resolutions must be two positive pixel sizes, not {}".format(
            ",".join("{:g}".format(v) for v in values)))
    if not (math.isfinite(k) and k > 0):
        raise InputError("The factor k must be positive, not {:g}".format(k))
    return k * math.hypot(*values)


def read_config(options, flags):
    """The :class:`AlignmentConfig` of g.parser's ``options`` and ``flags``
    (:class:`~reconstruction.core.errors.InputError` naming a bad one)."""
    if options["resolution"]:
        buffer = buffer_from_resolution(
            parse_list(options["resolution"], float), parse_number(options["k"], "k"))
    else:
        buffer = parse_number(options["buffer"] or ALIGN_BUFFER, "buffer")
    wanted = options["year_column"]
    return AlignmentConfig(
        year=parse_number(options["year"], "year", cast=int), buffer=buffer,
        overlap=parse_number(options["overlap"], "overlap"), include_year=flags["i"],
        shift=parse_number(options["shift"] or 0, "shift"),
        shift_window=parse_number(options["shift_window"], "shift_window", minimum=0),
        plots=options["input"], footprints=options["footprints"], output=options["output"],
        unmatched=options["unmatched"] or "", report_file=options["report"] or "",
        year_column=wanted, year_column_given=wanted != DEFAULT_YEAR_COLUMN,
        year_text=options["year"], shell=flags["g"])
