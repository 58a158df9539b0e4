"""The options of v.histo.timeline, checked (:func:`read_config`)."""

from dataclasses import dataclass
from typing import Optional

from ..core.errors import InputError
from ..core.options import parse_number

FORMATS = ("cityjson", "cityjsonseq")


@dataclass(frozen=True)
class TimelineConfig:
    """``models`` (paths) of the epochs' ``years``, or ``input``: a merged model;
    ``register``: today's footprints map (ids in ``id_column``, construction years
    in ``year_column``; None: the first of the usual names); ``output`` (a file of
    ``format``), ``snapshot`` (a year, or None for the whole model), ``report_file``,
    ``viewer`` (the HTML page that shows the model in a browser, with a year slider
    for the whole model; None: none), ``gltf`` (a binary glTF of its last year, or of
    the snapshot), ``tiles`` (a directory of 3D Tiles with every version and its
    years) and ``shell`` (-g)."""

    output: str
    models: tuple = ()
    years: tuple = ()
    input: Optional[str] = None
    register: Optional[str] = None
    id_column: Optional[str] = None
    year_column: Optional[str] = None
    format: str = "cityjson"
    snapshot: Optional[int] = None
    report_file: Optional[str] = None
    title: Optional[str] = None
    shell: bool = False
    viewer: Optional[str] = None
    gltf: Optional[str] = None
    tiles: Optional[str] = None


def _list(text):
    return tuple(t.strip() for t in (text or "").split(",") if t.strip())


def _year(text, key):
    # a map's year, as year= of the other modules: 1 or later
    return parse_number(text.strip() if isinstance(text, str) else text, key, cast=int,
                        minimum=1)


def read_config(options, flags):
    """The :class:`TimelineConfig` of g.parser's ``options`` and ``flags``; InputError
    for a bad one."""
    models, input_model = _list(options.get("models")), options.get("input") or None
    if bool(models) == bool(input_model):
        raise InputError("Give either models= (with years=) or input= (a merged model)")
    years = tuple(_year(y, "years") for y in _list(options.get("years")))
    if models and len(years) != len(models):
        raise InputError("Option years= needs one year per model of models= ({} models, {} "
                         "years)".format(len(models), len(years)))
    if len(set(years)) != len(years):
        raise InputError("Option years=: two models of one year ({})".format(
            ", ".join(map(str, years))))
    snapshot = options.get("snapshot") or None
    if input_model and snapshot is None:
        raise InputError("Option input= (a merged model) needs snapshot= (the year to show)")
    fmt = options.get("format") or "cityjson"
    if fmt not in FORMATS:
        raise InputError("Option format=: one of {}, not <{}>".format(", ".join(FORMATS), fmt))
    return TimelineConfig(
        output=options["output"], models=models, years=years, input=input_model,
        register=options.get("register") or None, id_column=options.get("id_column") or None,
        year_column=options.get("year_column") or None, format=fmt,
        snapshot=None if snapshot is None else _year(snapshot, "snapshot"),
        report_file=options.get("report") or None, title=options.get("title") or None,
        shell=bool(flags.get("g")), viewer=options.get("viewer") or None,
        gltf=options.get("gltf") or None, tiles=options.get("tiles") or None)
