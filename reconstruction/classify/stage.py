"""The r.histo.classify stage as one entry point: from map bands and training
points to a classified raster.

- the options are read by :func:`reconstruction.classify.config.read_config`
  (a :class:`~reconstruction.classify.config.ClassifyConfig`), the whole
  sequence run by :func:`reconstruction.classify.pipeline.run`;
- :func:`read_training`: the training points checked and located on the
  grid (:class:`Training`);
- :func:`classify_map`: chooses the segmentation among the tried parameter
  pairs, classifies its segments and removes classes such as text, with the
  algorithms of :mod:`reconstruction.classify.segments`. The segmentations
  themselves come from the caller (the module runs i.segment), so that this
  stays pure: an iterable of finished runs and a function that reads one;
- :func:`category_rules`, :func:`colour_rules`, :func:`tuning_table`: the
  texts the module writes and prints (its messages:
  :mod:`reconstruction.classify.report`).

Bad input raises :class:`~reconstruction.core.errors.InputError` with the message
a user should read.
"""

import time
from dataclasses import dataclass, field, replace
from typing import Optional, Union

import numpy as np

from ..core.errors import InputError
from ..geom.grid import Grid
from . import lines, outlines, removal
from . import segments as cl

# Colours of the classes: by class name where it is a usual one, otherwise
# distinct colours in the order of the labels.
NAMED_COLOURS = {
    "building": "230:80:80", "buildings": "230:80:80", "text": "40:40:40", "water": "60:120:220",
    "street": "235:235:225", "streets": "235:235:225", "road": "235:235:225",
    "vegetation": "90:170:80", "park": "90:170:80", "garden": "90:170:80",
    "symbol": "150:60:170", "church": "240:160:40", "railway": "120:120:120",
}
PALETTE = ("230:80:80", "40:40:40", "60:120:220", "235:235:225", "240:160:40", "150:60:170",
           "90:170:80", "200:200:60", "120:200:220", "170:110:70")


@dataclass(frozen=True)
class Training:
    """Training points: label of each point, class names, cell of each point."""

    labels: np.ndarray
    names: dict
    rows: np.ndarray
    cols: np.ndarray

    @property
    def classes(self):
        """The labels present, sorted."""
        return sorted(set(self.labels.tolist()))


@dataclass(frozen=True)
class ClassifyResult:
    """Result of :func:`classify_map`.

    classes: the class raster (labels of the training points, 0 = no data);
    pairs, criteria: the tried (threshold, minsize) pairs and their (VW, Moran's I);
    tuning: the :class:`~reconstruction.classify.segments.TuningResult` of the pairs;
    chosen: the chosen segmentation: the caller's id of it (the others are the
    caller's to drop), or its segment array of the whole map (tiled), or None
    (tiled, segments not kept); segments: the number of segments of the chosen
    one; window: the refill window used (None when nothing was removed);
    present: the labels kept; rule: the :class:`RemovalRule` applied (None when
    nothing was cleaned); timing: (step, seconds) pairs; names: the class names
    of the training points by label; grid: the grid classified.
    """

    classes: np.ndarray
    pairs: list
    criteria: Optional[list]
    tuning: cl.TuningResult
    chosen: Union[str, np.ndarray, None]
    segments: int
    window: Optional[int]
    present: list
    rule: Optional["RemovalRule"] = None
    timing: list = field(default_factory=list)
    names: dict = field(default_factory=dict)
    grid: Optional[Grid] = None

    @property
    def best_pair(self):
        return self.pairs[self.tuning.best]

    def timed(self, step, seconds):
        """This result with ``(step, seconds)`` added to its timing."""
        return replace(self, timing=self.timing + [(step, seconds)])


def segmentation_chains(pairs, exhaustive=False):
    """The i.segment runs for ``pairs`` as chains of ``(pair index, seed pair index or None)``.

    One chain per threshold, its minimum sizes ascending: the first run grows
    the segments, each next one starts from the previous result (seeds) and
    only merges what its larger minimum size asks for. ``exhaustive``: one
    chain per pair, every run from scratch.
    """
    if exhaustive:
        return [[(i, None)] for i in range(len(pairs))]
    chains = {}
    for i, (threshold, minsize) in enumerate(pairs):
        chains.setdefault(threshold, []).append((minsize, i))
    out = []
    for threshold in sorted(chains):
        members = [i for _m, i in sorted(chains[threshold])]
        out.append([(i, None if k == 0 else members[k - 1]) for k, i in enumerate(members)])
    return out


def integer_labels(values, column):
    """Class labels of the training points as positive ints."""
    labels = []
    for value in values:
        if value is None or value == "":
            raise InputError("Training point without a value in column <{}>".format(column))
        try:
            number = float(value)
        except (TypeError, ValueError):
            raise InputError("Column <{}> must hold integer class labels, found <{}>".format(
                column, value)) from None
        if number != int(number) or number <= 0:
            raise InputError("Column <{}> must hold positive integer class labels, found <{}>".format(
                column, value))
        labels.append(int(number))
    return labels


def read_training(xy, columns, label_column, class_column, config, grid, name="training"):
    """The training points (coordinates ``xy`` and attribute ``columns`` of map
    ``name``) checked against ``config`` and located on ``grid``."""
    if label_column not in columns:
        raise InputError("Training map <{}> has no column <{}> (columns: {})".format(
            name, label_column, ", ".join(columns) or "none"))
    if not len(xy):
        raise InputError("Training map <{}> has no points".format(name))
    labels = np.array(integer_labels(columns[label_column], label_column))
    names = {}
    if class_column and class_column in columns:
        for label, text in zip(labels, columns[class_column]):
            if text not in (None, ""):
                names.setdefault(int(label), str(text))
    classes = sorted(set(labels.tolist()))
    if len(classes) < 2:
        raise InputError("Training points hold {} class(es) in column <{}>: at least two are "
                         "needed".format(len(classes), label_column))
    missing = [r for r in config.remove if r not in classes]
    if missing:
        raise InputError("No training point has the label(s) {} given in remove= (labels: {})".format(
            ",".join(map(str, missing)), ",".join(map(str, classes))))
    missing = [r for r in config.separate if r not in classes or r in config.remove]
    if missing:
        raise InputError("Label(s) {} in separate= are not kept classes of the training "
                         "points".format(",".join(map(str, missing))))
    if len(set(classes) - set(config.remove)) < 1:
        raise InputError("remove= lists every class: nothing would be left")
    xy = np.asarray(xy, dtype=float).reshape(-1, 2)
    rows, cols = grid.cells(xy[:, 0], xy[:, 1])
    outside = int((rows < 0).sum())
    if outside:
        raise InputError("{} of {} training points lie outside the computational region".format(
            outside, len(xy)))
    return Training(labels, names, rows, cols)


def _ignore(text):
    pass


def _no_percent(done, total):
    pass


def classify_map(bands, segmentations, read_segments, training, config, grid,
                 message=_ignore, verbose=_ignore, percent=_no_percent, reading=None):
    """Classify a scanned map: tuned segmentation, ensemble vote, removal.

    ``bands``: the map's bands (arrays on ``grid``, nan = no data);
    ``segmentations``: an iterable of ``(k, id)`` as the segmentation of
    ``config.pairs[k]`` is ready, ``read_segments(id)`` its segment array.
    ``message`` and ``verbose`` receive progress texts, ``percent(done,
    total)`` the segmentations done of all the pairs' (the longest wait of
    the module, silent otherwise but with -v); ``reading``: the map's
    :class:`~reconstruction.classify.lines.InkReading` (read here when the
    ``fill`` features need it and it is not given). Returns a
    :class:`ClassifyResult`.
    """
    start = time.perf_counter()
    if not all(np.isfinite(b[training.rows, training.cols]).all() for b in bands):
        raise InputError("Some training points lie on no-data cells of the input maps")
    pairs = config.pairs
    criteria = [None] * len(pairs)
    ids = [None] * len(pairs)
    for done, (k, segmentation) in enumerate(segmentations, 1):
        criteria[k] = cl.segmentation_criteria(read_segments(segmentation), bands)
        ids[k] = segmentation
        if len(pairs) > 1:
            verbose("threshold={} minsize={}: VW={:.4f} Moran's I={:.4f}".format(
                pairs[k][0], pairs[k][1], *criteria[k]))
            percent(done, len(pairs))
    tuning = cl.tune(criteria, config.alpha)
    best = tuning.best
    message("Chosen segmentation: threshold={} minsize={} (F={:.3f})".format(
        pairs[best][0], pairs[best][1], tuning.f[best]))
    timing = [("segmentation", time.perf_counter() - start)]
    start = time.perf_counter()

    segments = read_segments(ids[best])
    index, n_segments = cl.relabel(segments)
    fill = None
    if "fill" in config.features:
        reading = reading or lines.read_ink(bands, grid.ewres)
        fill = lines.fill_features(index + 1, reading)
    _ids, model_features = cl.object_features(segments, bands, config.features, fill)
    train_rows = index[training.rows, training.cols]
    if (train_rows < 0).any():
        raise InputError("Some training points lie outside every segment")
    message("Classifying {} segments with {}...".format(n_segments, ",".join(config.classifiers)))
    voted, _predictions = cl.classify_segments(model_features, train_rows, training.labels,
                                               config.classifiers, config.seed, config.nprocs)
    classes = cl.class_raster(index, voted.astype(np.int32))
    timing.append(("classification", time.perf_counter() - start))
    start = time.perf_counter()

    printed = outlines.printed_cells(classes, config)
    classes, rule = _remove(classes, config, grid,
                            np.stack(bands, axis=-1) if config.in_register else None)
    if printed is not None:
        classes = outlines.inside_outlines(classes, bands, config.separate, printed=printed,
                                           unmix=config.in_register)
    timing.append(("removal", time.perf_counter() - start))
    return ClassifyResult(
        classes=classes, pairs=pairs, criteria=criteria, tuning=tuning, chosen=ids[best],
        segments=n_segments, window=rule.window if rule else None, rule=rule,
        present=[c for c in training.classes if c not in config.remove], timing=timing,
        names=training.names, grid=grid)


#: Width (cells) below which parts of a class are refilled by default: the mixed
#: pixels along every edge of a scan and the fringes of a misregistered colour
#: plane are one or two cells wide, whatever the map.
FRINGE_CELLS = 3


@dataclass(frozen=True)
class RemovalRule:
    """How the classes are cleaned, in cells (see :func:`removal_rule`).

    window: refill window (odd); min_cells: minimum mapping unit (0: none);
    width_cells: parts narrower than this are refilled (0: none);
    thickness: of the thickest removed letter or symbol (cells); derived: the names of
    the values derived from the data rather than given.
    """

    window: int
    min_cells: int
    width_cells: int
    thickness: float
    derived: tuple = ()

    def active(self, remove):
        return bool(remove) or self.min_cells > 1 or self.width_cells > 1


def removal_rule(thickness, config, grid):
    """The cleaning rule for removed objects ``thickness`` cells thick (the
    thickest letter or symbol of the ``remove`` classes,
    :func:`~reconstruction.classify.removal.removed_thickness`).

    Explicit options win. When something is removed, what is not given is
    derived from the data: the refill window from the thickness (thickness / 2 + 1,
    odd); a minimum mapping unit of thickness x thickness cells (no object the
    map draws is smaller than a square as thick as its thickest letter or
    symbol: smaller regions are pieces that the letters and symbols left, of
    the classes under them or misclassified beside them); and a minimum width
    of :data:`FRINGE_CELLS` cells (the scan's mixed-pixel edges and colour
    fringes). Without ``remove=``, only the given values apply.
    """
    derived = []
    resolution = min(grid.nsres, grid.ewres)
    window = config.window
    if window is None:
        window = removal.window_for_thickness(thickness)
        derived.append("window")
    if config.min_area is not None:
        min_cells = int(np.ceil(config.min_area / (grid.nsres * grid.ewres))) if config.min_area else 0
    elif config.remove:
        min_cells = int(np.ceil(thickness * thickness))
        derived.append("min_area")
    else:
        min_cells = 0
    if config.min_width is not None:
        width_cells = int(round(config.min_width / resolution)) if config.min_width else 0
    elif config.remove:
        width_cells = FRINGE_CELLS
        derived.append("min_width")
    else:
        width_cells = 0
    return RemovalRule(window, min_cells, width_cells, float(thickness), tuple(derived))


def _remove(classes, config, grid, image=None):
    """Removal of text, symbols, thin parts and small regions: ``(classes,
    RemovalRule or None)``; with the map's ``image`` (rows, cols, bands), the
    cells between the removed letters are first given the class of their
    colour (:func:`~reconstruction.classify.removal.letter_gaps`)."""
    thickness = removal.removed_thickness(classes, config.remove) if config.remove else 0.0
    rule = removal_rule(thickness, config, grid)
    if not rule.active(config.remove):
        return classes, None
    out, _window = removal.remove_classes(classes, config.remove, rule.window, config.iterations,
                                     rule.min_cells, rule.width_cells, config.separate,
                                     image=image)
    return out, rule


def tuning_table(result):
    """The lines that flag -p prints: the tuning table (CSV) and the chosen pair."""
    t = result.tuning
    lines = ["threshold,minsize,vw,moran,vw_norm,moran_norm,f"]
    for k, (threshold, minsize) in enumerate(result.pairs):
        lines.append("{},{},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f}".format(
            threshold, minsize, t.vw[k], t.moran[k], t.vw_norm[k], t.moran_norm[k], t.f[k]))
    lines.append("best: threshold={} minsize={}".format(*result.best_pair))
    return lines


def category_rules(labels, names):
    """r.category rules (label:name) for the labels, "class <label>" where unnamed."""
    return "\n".join("{}:{}".format(c, names.get(c, "class {}".format(c))) for c in labels)


def colour_rules(labels, names):
    """r.colors rules (label r:g:b) for the labels, by class name where known."""
    rules = []
    for i, label in enumerate(labels):
        name = names.get(label, "").strip().lower()
        rules.append("{} {}".format(label, NAMED_COLOURS.get(name, PALETTE[i % len(PALETTE)])))
    return "\n".join(rules)
