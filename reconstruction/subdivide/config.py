"""v.histo.subdivide's options as one record: :class:`SubdivisionConfig` and :func:`read_config`."""

from dataclasses import dataclass
from typing import Optional, Tuple

from ..core.errors import InputError
from ..core.options import parse_bands, parse_number, parse_range
from ..epochs.plots import TOLERANCE


@dataclass(frozen=True)
class SubdivisionConfig:
    """How plots are cut into footprints (lengths in map units).

    ``plots``: the plots map (input=); ``aligned``: the aligned footprints
    map (empty: none); ``output``: the footprints map. ``length``,
    ``depth``: (min, max) ranges of the facade length and the building
    depth; ``area_threshold``: plots smaller than it are one footprint
    (None: the mean area of the aligned footprints, else 100); ``seed``;
    ``decompose``: concave plots cut into convex parts (no -c);
    ``calibrate``: length and depth learnt from the aligned footprints (-a).

    A dynamic chain (issue 28): ``year``, the map's year (None: a single
    map; with it the footprints get a building identity);
    ``previous`` and ``previous_plots``: the earlier epoch's footprints and
    plots maps (empty: none), kept where the plots did not change;
    ``tolerance``: the largest distance between the outlines of a plot
    drawn twice unchanged (map units); ``id_column``: the aligned
    footprints' BAG id column (empty: the first of
    :data:`~reconstruction.core.contract.BAG_ID_COLUMNS` present).

    Units the map draws (issue 50): ``maps``, the scanned map's red, green and
    blue rasters (map=; empty: every plot is subdivided as before); ``stroke``
    the width of its lines and ``min_parcel`` the least unit it draws (map
    units; None: from the stroke width measured on the map); ``whole``: the map
    draws every unit, a plot it does not divide is one footprint (-d).
    """

    plots: str
    output: str
    aligned: str = ""
    length: Tuple[float, float] = (5.0, 8.0)
    depth: Tuple[float, float] = (12.0, 16.0)
    area_threshold: Optional[float] = None
    seed: int = 1
    decompose: bool = True
    calibrate: bool = False
    year: Optional[int] = None
    previous: str = ""
    previous_plots: str = ""
    tolerance: float = TOLERANCE
    id_column: str = ""
    maps: tuple = ()
    stroke: Optional[float] = None
    min_parcel: Optional[float] = None
    whole: bool = False


def _range(text, key):
    """A (min, max) pair of positive numbers (InputError naming ``key``)."""
    pair = parse_range(text, key, positive=True, allow_zero=False)
    if pair is None:
        raise InputError("Option {}= must be two numbers min,max".format(key))
    return pair


def _positive(options, key):
    """The positive number of option ``key``, None when it is not given."""
    if not options.get(key):
        return None
    return parse_number(options[key], key, minimum=0, allow_minimum=False)


def read_config(options, flags):
    """The :class:`SubdivisionConfig` of g.parser's ``options`` and ``flags``
    (:class:`~reconstruction.core.errors.InputError` naming a bad one)."""
    area_threshold = None
    if options["area_threshold"]:
        area_threshold = parse_number(options["area_threshold"], "area_threshold", minimum=0)
    year = None
    if options.get("year"):
        year = parse_number(options["year"], "year", cast=int, minimum=1)
    if options.get("previous") and year is None:
        raise InputError("Option previous= needs year=, the year of this map (the identity of "
                         "its new buildings)")
    if bool(options.get("previous")) != bool(options.get("previous_plots")):
        raise InputError("Options previous= and previous_plots= go together: the earlier "
                         "epoch's footprints and its plots")
    maps = parse_bands(options["map"], "map") if options.get("map") else ()
    return SubdivisionConfig(
        plots=options["input"], output=options["output"], aligned=options["aligned"] or "",
        length=_range(options["length"], "length"), depth=_range(options["depth"], "depth"),
        area_threshold=area_threshold,
        seed=parse_number(options["seed"] or 1, "seed", cast=int),
        decompose=not flags["c"], calibrate=flags["a"], year=year,
        previous=options.get("previous") or "", previous_plots=options.get("previous_plots") or "",
        tolerance=parse_number(options.get("tolerance") or TOLERANCE, "tolerance", minimum=0),
        id_column=options.get("id_column") or "",
        maps=maps,
        stroke=_positive(options, "stroke"), min_parcel=_positive(options, "min_parcel"),
        whole=bool(flags.get("d")))
