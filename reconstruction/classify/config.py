"""r.histo.classify's options as one record: :class:`ClassifyConfig`, read by
:func:`read_config` from the texts g.parser gives (no GRASS needed).

Every option text becomes a value here, through
:mod:`reconstruction.core.options`; a bad one raises
:class:`~reconstruction.core.errors.InputError` naming the option.
"""

from dataclasses import dataclass
from typing import Optional

from ..core.errors import InputError
from ..core.options import parse_bands, parse_list, parse_number, parse_range, processes
from ..core.work_limits import check_segmentations
from . import segments as cl
from .outlines import OUTLINES


@dataclass(frozen=True)
class ClassifyConfig:
    """What r.histo.classify does: parameter pairs to try, classifiers, removal.

    Sizes: ``min_area`` in square map units, ``min_width`` in map units,
    ``window`` in cells (odd). None for ``window``, ``min_area`` or
    ``min_width``: derived from the data when something is removed
    (:func:`~reconstruction.classify.stage.removal_rule`).

    ``bands``: the raster maps of the scan (input=): three, red, green and
    blue, or one, a greyscale scan (features ``lab`` and flag -b need three);
    ``label_column``, ``class_column``: the training points' columns;
    ``outline``: where the map draws the outline of the ``separate`` classes'
    areas (:data:`~reconstruction.classify.outlines.OUTLINES`);
    ``segmentation``: what the segments are (:data:`SEGMENTATIONS`):
    ``superpixels``, i.segment's regions of like colour, tuned over the
    parameter pairs; ``lines``, the shapes the map's line work closes and
    the lines themselves (:mod:`~reconstruction.classify.lines`: a monochrome
    map's blocks and hatched buildings);
    ``keep_segments``: segments= is given; ``exhaustive``: flag -e (a full
    i.segment run per pair); ``print_table``: flag -p; ``register``: flag
    -b, the bands are registered to each other first
    (:mod:`~reconstruction.geom.registration`); ``in_register``: the bands
    classified are in register (none found off, or registered), which the
    module sets from its estimate: only then are the outermost cells of an
    ``outline=inside`` area unmixed into three colours
    (:func:`~reconstruction.classify.outlines.inside_outlines`) and the
    cells next to removed letters decided by colour
    (:func:`~reconstruction.classify.removal.letter_gaps`): the colours of
    planes out of register are no mixes of their neighbours'.
    """

    thresholds: tuple
    minsizes: tuple
    alpha: float = 1.0
    classifiers: tuple = cl.CLASSIFIERS
    features: tuple = ("spectral", "size")
    remove: tuple = ()
    window: Optional[int] = None
    iterations: Optional[int] = None
    min_area: Optional[float] = None
    min_width: Optional[float] = None
    separate: tuple = ()
    outline: str = "centre"
    seed: int = 1
    nprocs: int = 1
    memory: int = 300
    bands: tuple = ()
    segmentation: str = "superpixels"
    label_column: str = "label"
    class_column: str = "class"
    keep_segments: bool = False
    exhaustive: bool = False
    print_table: bool = False
    register: bool = False
    in_register: bool = True

    @property
    def pairs(self):
        """The (threshold, minsize) pairs to try, thresholds first."""
        return [(t, m) for t in self.thresholds for m in self.minsizes]


#: what r.histo.classify's segments can be (option segmentation=)
SEGMENTATIONS = ("superpixels", "lines")


def read_config(options, flags=None):
    """The options and flags of r.histo.classify (dicts of texts and booleans,
    as g.parser gives them; no flag set when ``flags`` is None) as a
    :class:`ClassifyConfig`."""
    flags = flags or {}
    bands = parse_bands(options.get("input"), "input")
    features = tuple(parse_list(options["features"]))
    if "lab" in features and len(bands) != 3:
        raise InputError("Option features=lab needs the red, green and blue bands of a colour "
                         "scan: input= has one band (a greyscale scan; leave lab out)")
    segmentation = options.get("segmentation") or "superpixels"
    if segmentation not in SEGMENTATIONS:
        raise InputError("Option segmentation= must be one of {}, got '{}'".format(
            ", ".join(SEGMENTATIONS), segmentation))
    if "fill" in features and segmentation != "lines":
        raise InputError("Option features=fill describes the shapes a map's lines close: it "
                         "needs segmentation=lines")
    if flags.get("b") and len(bands) != 3:
        raise InputError("Flag -b registers the colour bands to each other: input= has one band "
                         "(a greyscale scan has nothing to register; leave -b out)")
    low_t, high_t = parse_range(options["threshold"], "threshold", float)
    low_m, high_m = parse_range(options["minsize"], "minsize", int)
    t_step = parse_number(options["threshold_step"], "threshold_step", float, minimum=0,
                          allow_minimum=False)
    m_step = parse_number(options["minsize_step"], "minsize_step", int, minimum=0,
                          allow_minimum=False)
    if not (0 < low_t and high_t < 1):
        raise InputError("Thresholds must lie between 0 and 1, got {}-{}".format(low_t, high_t))
    if low_m < 1:
        raise InputError("Minimum sizes must be at least 1 cell, got {}".format(low_m))
    check_segmentations((low_t, high_t), t_step, (low_m, high_m), m_step)
    thresholds = cl.parameter_values(low_t, high_t, t_step)
    minsizes = [int(v) for v in cl.parameter_values(low_m, high_m, m_step, 0)]
    classifiers = parse_list(options["classifiers"])
    if len(set(classifiers)) != len(classifiers):
        raise InputError("Option classifiers= lists a classifier twice")
    window = None
    if options["window"]:
        window = parse_number(options["window"], "window", int)
        if window < 1 or window % 2 == 0:
            raise InputError("Option window= must be a positive odd number, got {}".format(window))
    iterations = None
    if options["iterations"]:
        iterations = parse_number(options["iterations"], "iterations", int, minimum=1)
    separate = tuple(parse_list(options["separate"], int, key="separate"))
    outline = options.get("outline") or "centre"
    if outline not in OUTLINES:
        raise InputError("Option outline= must be one of {}, got '{}'".format(
            ", ".join(OUTLINES), outline))
    if outline != "centre" and not separate:
        raise InputError("Option outline={} needs separate= (the classes whose outline the "
                         "map draws inside them)".format(outline))
    return ClassifyConfig(
        thresholds=tuple(thresholds), minsizes=tuple(minsizes),
        alpha=parse_number(options["alpha"], "alpha"),
        classifiers=tuple(classifiers), features=features,
        remove=tuple(parse_list(options["remove"], int, key="remove")),
        window=window, iterations=iterations,
        min_area=_optional_number(options["min_area"], "min_area"),
        min_width=_optional_number(options["min_width"], "min_width"),
        separate=separate, outline=outline,
        seed=parse_number(options["seed"], "seed", int),
        nprocs=processes(options["nprocs"]),
        memory=parse_number(options.get("memory") or 300, "memory", int, minimum=1),
        bands=tuple(bands), segmentation=segmentation,
        label_column=options.get("label_column", "label"),
        class_column=options.get("class_column", "class"),
        keep_segments=bool(options.get("segments")), exhaustive=bool(flags.get("e")),
        print_table=bool(flags.get("p")), register=bool(flags.get("b")))


def _optional_number(text, key):
    """A non-negative number, or None when the option is not given."""
    if text in (None, ""):
        return None
    return parse_number(text, key, minimum=0)
