"""v.histo.lod2's options as one frozen :class:`Lod2Config` (:func:`read_config`).

The one place where the module's option texts become values (issue 27):
:func:`read_config` turns g.parser's ``options`` and ``flags`` dicts, with
the facts the script got from GRASS (the location's EPSG code, the streets
raster's category labels), into a :class:`Lod2Config`, raising
:class:`~reconstruction.core.errors.InputError` naming the option. The
config holds sub-configs: the roof parameters
(:class:`~reconstruction.lod2.roofs.model.RoofConfig`), where the heights
come from (:class:`HeightConfig`), how street edges are found
(:class:`StreetConfig`), the output (:class:`OutputRequest`) and the
existing model to copy from (:class:`ExistingRequest`).
"""

from dataclasses import dataclass, field, fields
from typing import Optional, Union

from ..cityjson import geometry as citygeometry
from ..core.crs import crs_url, epsg_code, geographic
from ..core.errors import InputError
from ..core.options import parse_list, parse_number, parse_range, processes
from ..geom.grid import MapImage
from .heights import GROUND_RANGE, MAX_HEIGHT
from .neighbourhood import HeightRule
from .render import View
from .roofs.model import RoofConfig
from .roofs.rules import RoofRules, read_rules

#: the output formats (``format=``)
FORMATS = ("cityjson", "cityjsonseq")
#: the file name endings of each format: a name ending in the other format's
#: is written as asked, with a warning (:func:`format_of_name`)
EXTENSIONS = {"cityjson": ".json", "cityjsonseq": ".jsonl"}
#: what a roof column or ``roof=`` may ask for besides a roof type
AUTO = "auto"


@dataclass(frozen=True)
class ExistingRequest:
    """What to copy from an existing model: ``path``; ``prefix`` put before
    a footprint's id to make an object id (None: the automatic rule of
    :mod:`reconstruction.cityjson.existing`); ``min_overlap``: least intersection over
    union of a match by geometry; ``lods``: None (each building's highest),
    "all" or a list of LoD strings."""
    path: str
    prefix: Optional[str] = None
    min_overlap: float = 0.5
    lods: Union[None, str, list] = None


@dataclass(frozen=True)
class OutputRequest:
    """Where and how the model is written: ``path``, ``format`` (one of
    :data:`FORMATS`), ``reference_system`` (EPSG code or URL, or None),
    ``title``; ``render``: path of a PNG picture (None: none), its ``view``
    (:class:`~reconstruction.lod2.render.View`) and ``map_image``
    (:class:`~reconstruction.geom.grid.MapImage` or None); ``viewer``: path
    of the HTML page that shows the model in a browser, ``gltf`` of its
    binary glTF and ``tiles`` the directory of its 3D Tiles (None: none;
    :mod:`reconstruction.view`); ``maps``: the red, green and blue rasters of
    ``map_image`` (read by the script), draped in the picture and the page."""
    path: str
    format: str = "cityjson"
    reference_system: Union[str, int, None] = None
    title: Optional[str] = None
    render: Optional[str] = None
    view: Optional[View] = None
    map_image: Optional[MapImage] = None
    maps: tuple = ()
    viewer: Optional[str] = None
    gltf: Optional[str] = None
    tiles: Optional[str] = None


@dataclass(frozen=True)
class HeightColumns:
    """The heights given with the footprints: their columns, ranges ``(low,
    high)`` drawn at random, a constant ground and the percentile of the
    ground measured around each footprint. Shared by the options as read
    (:class:`HeightConfig`) and as used
    (:class:`~reconstruction.lod2.inputs.HeightOptions`)."""

    eaves_column: Optional[str] = "h_building"
    attic_column: Optional[str] = "h_attic"
    ground_column: Optional[str] = None
    ground: float = 0.0
    eaves_range: Optional[tuple] = None
    attic_range: Optional[tuple] = None
    ground_percentile: float = 20.0

    def columns(self):
        """These fields alone, as keywords (to make another record of them)."""
        return {f.name: getattr(self, f.name) for f in fields(HeightColumns)}


@dataclass(frozen=True)
class HeightConfig(HeightColumns):
    """Where the heights come from (the options of the Heights section):
    columns of the footprints, ranges ``(low, high)`` drawn at random, and
    the names of the maps measuring them (None: not given)."""

    #: 3D ground points (vector map) and the DTM (raster)
    ground_points: Optional[str] = None
    elevation: Optional[str] = None
    #: aligned footprints with measured heights, and which height columns they have
    aligned: Optional[str] = None
    height_columns: str = "auto"
    #: building plots and 3D building points (vector maps)
    plots: Optional[str] = None
    building_points: Optional[str] = None
    rule: HeightRule = field(default_factory=HeightRule)
    #: ``ground=`` and ``ground_percentile=`` as given (the messages repeat them)
    ground_text: str = "0"
    percentile_text: str = "20"


@dataclass(frozen=True)
class StreetConfig:
    """How street edges are found: a classified raster ``streets`` with its
    street and water ``classes``, or street polygons ``areas`` (a vector
    map), or neither (the four cases alone)."""

    streets: Optional[str] = None
    classes: Optional[tuple] = None
    areas: Optional[str] = None
    #: ``street_classes=`` given without ``streets=`` (ignored, with a warning)
    classes_ignored: bool = False


@dataclass(frozen=True)
class Lod2Config:
    """Everything v.histo.lod2's options ask for; the first five fields are
    the parameters of the build that are the same for every footprint."""

    roof: RoofConfig = field(default_factory=RoofConfig)
    #: seed of every random draw
    seed: int = 1
    #: processes building the solids (the result does not depend on it)
    nprocs: int = 1
    #: year of the map, written as attribute ``map_year``
    map_year: Optional[int] = None
    #: the roof choice; None: the default
    rules: Optional[RoofRules] = None
    #: the footprints (vector map)
    input: str = ""
    #: the roof type of every footprint, or "auto"; the columns of the roof
    #: type and construction year per footprint ("" or None: none)
    roof_type: str = AUTO
    roof_column: Optional[str] = None
    year_column: Optional[str] = None
    #: columns of the plot, the source and the building id of each footprint
    plot_column: Optional[str] = "plot"
    source_column: Optional[str] = "source"
    id_column: Optional[str] = None
    heights: HeightConfig = field(default_factory=HeightConfig)
    #: None: no street edges (flag -s)
    streets: Optional[StreetConfig] = field(default_factory=StreetConfig)
    output: Optional[OutputRequest] = None
    #: None: no existing model
    existing: Optional[ExistingRequest] = None
    #: the earlier epoch's model (previous=, a dynamic chain: issue 28), None: none
    previous: Optional[str] = None
    #: map= given without render= or viewer= (ignored, with a warning)
    map_ignored: bool = False
    #: the location's EPSG code (the existing model's must agree)
    location_epsg: Optional[int] = None
    #: validate every solid and print the -v report
    validate: bool = False


def check_crs(code, location_epsg):
    """InputError unless the EPSG ``code`` of crs= can label the location's
    coordinates, which are written as they are, in metres (v.histo.lod2
    needs a projected location): a geographic system cannot. (Another
    projected system than the location's is only warned about:
    :func:`reconstruction.lod2.report.config_messages`.)"""
    if code is not None and geographic(code):
        raise InputError("Option crs=EPSG:{} is a geographic reference system (degrees of "
                         "longitude and latitude), but the model's coordinates are the "
                         "location's, in metres: give the location's system{}".format(
                             code, " (EPSG:{})".format(location_epsg) if location_epsg else ""))


def read_config(options, flags, location_epsg=None, street_labels=None):
    """The :class:`Lod2Config` of v.histo.lod2's ``options`` and ``flags``
    (g.parser's dicts); ``location_epsg``: the location's EPSG code (None:
    none); ``street_labels``: the category labels of the ``streets=`` raster
    (label -> value). Raises :class:`InputError` naming a bad option."""
    roof = RoofConfig(pitch_min=parse_number(options["pitch_min"], "pitch_min"),
                      inset=parse_range(options["inset"], "inset", positive=True),
                      step=parse_range(options["step"], "step", positive=True, allow_zero=False),
                      thickness=parse_number(options["thickness"], "thickness", minimum=0,
                                             allow_minimum=False))
    height_range = _height_range(options["height"], "height")
    attic_range = _height_range(options["attic"], "attic")
    map_year = parse_number(options["year"], "year", cast=int, minimum=1) if options["year"] \
        else None
    if options.get("previous") and map_year is None:
        raise InputError("Option previous= needs year=, the year of this map (the earlier "
                         "epoch's model must be of an earlier map)")
    seed = parse_number(options["seed"], "seed", cast=int)
    nprocs = processes(options["nprocs"])
    rules = read_rules(options["rules"]) if options["rules"] else None
    crs = options["crs"] or location_epsg
    if crs is not None:
        try:
            crs = crs_url(crs)
        except ValueError:
            raise InputError("Option crs= must be an EPSG code (e.g. 7415, EPSG:7415) or an OGC "
                             "URL, not <{}>".format(options["crs"])) from None
        if options["crs"]:
            check_crs(epsg_code(crs), location_epsg)
    elif options.get("tiles"):
        raise InputError("Option tiles= needs the model's reference system to put it on the "
                         "globe: give crs= (an EPSG code) or use a location with an EPSG code")
    output, existing = _requests(options, crs, title="LoD2 model from <{}>".format(
        options["input"]))
    heights = HeightConfig(
        eaves_column=options["eaves_column"], attic_column=options["attic_column"],
        ground_column=options["ground_column"],
        ground=parse_number(options["ground"], "ground", minimum=GROUND_RANGE[0],
                            maximum=GROUND_RANGE[1]),
        eaves_range=height_range, attic_range=attic_range,
        ground_percentile=parse_number(options["ground_percentile"], "ground_percentile",
                                       minimum=0),
        ground_points=options["ground_points"] or None, elevation=options["elevation"] or None,
        aligned=options["aligned"] or None, height_columns=options["height_columns"],
        plots=options["plots"] or None, building_points=options["building_points"] or None,
        rule=HeightRule(method=options["height_rule"]),
        ground_text=options["ground"], percentile_text=options["ground_percentile"])
    return Lod2Config(
        roof, seed=seed, nprocs=nprocs, map_year=map_year, rules=rules, input=options["input"],
        roof_type=options["roof"], roof_column=options["roof_column"],
        year_column=options["year_column"], plot_column=options["plot_column"],
        source_column=options["source_column"], id_column=options["id_column"],
        heights=heights, streets=None if flags["s"] else _streets(options, street_labels),
        output=output, existing=existing,
        map_ignored=bool(options["map"] and not (output.render or output.viewer)),
        location_epsg=location_epsg, validate=bool(flags["v"]),
        previous=options.get("previous") or None)


def _height_range(text, key):
    """A ``min,max`` range of heights (m): 0 or more, at most
    :data:`~reconstruction.lod2.heights.MAX_HEIGHT` (a building's plausible height)."""
    bounds = parse_range(text, key, positive=True)
    if bounds is not None and bounds[1] > MAX_HEIGHT:
        raise InputError("Option {}=: the maximum {:g} m is not a plausible height (at most "
                         "{:g} m)".format(key, bounds[1], MAX_HEIGHT))
    return bounds


def _streets(options, labels):
    """The :class:`StreetConfig` of the options."""
    if options["streets"]:
        return StreetConfig(options["streets"], parse_classes(options["street_classes"], labels))
    return StreetConfig(areas=options["street_areas"] or None,
                        classes_ignored=bool(options["street_classes"]))


def _requests(options, reference_system=None, title=None):
    """The :class:`OutputRequest` and :class:`ExistingRequest` (None without
    ``existing=``) of the options."""
    render, viewer = options.get("render") or None, options.get("viewer") or None
    maps = tuple(options["map"].split(",")) if options.get("map") and (render or viewer) else ()
    request = OutputRequest(path=options["output"], format=parse_format(options.get("format")),
                            reference_system=reference_system, title=title, render=render,
                            view=parse_view(options.get("view")), maps=maps, viewer=viewer,
                            gltf=options.get("gltf") or None,
                            tiles=options.get("tiles") or None)
    if not options.get("existing"):
        for key in ("id_column", "id_prefix", "existing_lod"):
            if options.get(key):
                raise InputError("Option {}= needs existing= (the model to copy buildings "
                                 "from)".format(key))
        return request, None
    overlap = parse_number(options.get("overlap") or "0.5", "overlap", minimum=0,
                           allow_minimum=False, maximum=1)
    return request, ExistingRequest(path=options["existing"],
                                    prefix=options.get("id_prefix") or None,
                                    min_overlap=overlap, lods=parse_lods(options.get("existing_lod")))


def parse_lods(text):
    """The ``existing_lod=`` option: None (empty: each building's highest), "all",
    or a list of LoD strings ("1.2", "2.2")."""
    if text is None or not str(text).strip():
        return None
    values = [v.strip() for v in str(text).split(",") if v.strip()]
    if [v.lower() for v in values] == ["all"]:
        return "all"
    bad = [v for v in values if citygeometry.lod_value(v) < 0]
    if bad:
        raise InputError("Option existing_lod= must be LoDs such as 2.2 or 1.2,2.2, or all, "
                         "not <{}>".format(text))
    return values


def parse_format(text):
    """The ``format=`` option (default cityjson)."""
    value = (text or FORMATS[0]).strip().lower()
    if value not in FORMATS:
        raise InputError("Option format= must be one of {}, not <{}>".format(
            ", ".join(FORMATS), text))
    return value


def format_of_name(path):
    """The format an output file name suggests by its ending (``x.city.json``:
    cityjson, ``x.jsonl``: cityjsonseq), None for any other name. Only a
    warning comes of it: a user may name a file as they like."""
    name = str(path or "").lower()
    for value, ending in EXTENSIONS.items():
        if name.endswith(ending):
            return value
    return None


def parse_view(text):
    """A ``view=azimuth,elevation`` option as a :class:`~reconstruction.lod2.render.View`
    (empty: the default)."""
    if text is None or not str(text).strip():
        return View()
    values = parse_list(str(text), float, key="view")
    if len(values) != 2 or not 0 <= values[1] <= 90:
        raise InputError("Option view= must be azimuth,elevation in degrees (elevation 0-90), "
                         "not <{}>".format(text))
    return View(values[0] % 360.0, values[1])


def parse_classes(text, categories=None):
    """Street and water classes from ``street_classes=`` text: integers or
    category labels of the raster (``categories``: label -> value)."""
    out = []
    labels = {str(k).strip().lower(): v for k, v in (categories or {}).items()}
    for item in [t.strip() for t in str(text or "").split(",") if t.strip()]:
        try:
            out.append(int(item))
        except ValueError:
            if item.lower() not in labels:
                raise InputError("Street class <{}> is neither a number nor a category label "
                                 "of the streets raster (labels: {})".format(
                                     item, ", ".join(sorted(labels)) or "none")) from None
            out.append(int(labels[item.lower()]))
    if not out:
        raise InputError("Give street_classes=, the street and water classes of the streets "
                         "raster")
    return tuple(out)
