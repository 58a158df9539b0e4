"""v.histo.generalize's options as one record: :class:`GeneralizeConfig`, read
by :func:`read_config` from the texts g.parser gives (no GRASS needed).

Every option text becomes a value here, through
:mod:`reconstruction.core.options`; a bad one raises
:class:`~reconstruction.core.errors.InputError` naming the option.
"""

from dataclasses import dataclass
from typing import Optional

from ..core.errors import InputError
from ..core.options import parse_bands, parse_list, parse_number
from .fitting import OUTLINES


@dataclass(frozen=True)
class GeneralizeConfig:
    """The steps of v.histo.generalize and their parameters (map units, degrees).

    ``category``: the building class of raster= (class=; None for input=);
    ``shell``: flag -g, the figures printed as key=value; ``outline``: how
    the map draws the plots' outlines, for the fit step (map=), and
    ``stroke`` the width of an outline drawn inside them (None: measured);
    ``maps``: the scanned map's red, green and blue rasters (map=);
    ``reach``: how far from an edge (cells) the fit step looks for the
    drawn line. ``alpha``, ``distance``, ``tolerance``, ``min_area`` and
    ``reach`` are None when read from options not given: the module derives
    them from the map's scale (:mod:`~reconstruction.generalize.scale`); a
    record made in code has the thesis's values (those on 1 m cells) and
    the fit's :data:`~reconstruction.generalize.fitting.REACH`.
    ``register``: flag -b, they are registered to each other before the
    fit reads them (:mod:`~reconstruction.geom.registration`). ``drawn``:
    flag -d, the raw plots are the regions the outlines drawn on map= close,
    the classified areas deciding which are built
    (:mod:`~reconstruction.generalize.drawn`).
    """

    methods: tuple = ("alpha", "lines")
    alpha: Optional[float] = 12.0
    distance: Optional[float] = 5.0
    angle: float = 180.0
    orthogonal: bool = False
    tolerance: Optional[float] = 1.0
    min_area: Optional[float] = 20.0
    gt_buffer: float = 2.0
    seed: int = 1
    category: Optional[int] = None
    shell: bool = False
    outline: str = "centre"
    stroke: Optional[float] = None
    maps: tuple = ()
    register: bool = False
    reach: Optional[float] = None
    drawn: bool = False


def read_config(options, flags):
    """The options and flags of v.histo.generalize (dicts of texts and
    booleans, as g.parser gives them) as a :class:`GeneralizeConfig`."""
    def positive(key, allow_zero=False):
        return parse_number(options[key], key, minimum=0, allow_minimum=allow_zero)

    def scaled(key, allow_zero=False):
        """None when not given: derived from the map's scale."""
        return positive(key, allow_zero) if options.get(key) not in (None, "") else None

    methods = tuple(parse_list(options["method"]))
    scan = bool(options.get("map"))
    drawn = bool(flags.get("d"))
    if ("fit" in methods or drawn) != scan:
        raise InputError("method=fit moves the plots' edges onto the lines of the scanned map "
                         "and -d reads the plots from them: give map= with one of them, or "
                         "none (method={}, -d {}, map={})".format(
                             options["method"], "given" if drawn else "not given",
                             options.get("map") or "not given"))
    outline = options.get("outline") or "centre"
    if outline not in OUTLINES:
        raise InputError("Option outline= must be one of {}, not '{}'".format(
            ", ".join(OUTLINES), outline))
    return GeneralizeConfig(
        methods=methods, reach=None,
        alpha=scaled("alpha"), distance=scaled("distance"),
        angle=parse_number(options["angle"], "angle", minimum=0, maximum=180),
        orthogonal=bool(flags["r"]), tolerance=scaled("tolerance"),
        min_area=scaled("min_area", allow_zero=True), gt_buffer=positive("gt_buffer"),
        seed=parse_number(options["seed"], "seed", int),
        category=(parse_number(options["class"], "class", int) if options.get("raster")
                  else None),
        shell=bool(flags.get("g")), outline=outline,
        stroke=positive("stroke") if options.get("stroke") else None,
        maps=parse_bands(options["map"], "map") if scan else (), register=bool(flags.get("b")),
        drawn=drawn)
