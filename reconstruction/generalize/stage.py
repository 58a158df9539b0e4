"""The v.histo.generalize stage as one entry point: from raw plot areas to
generalised plots, their attribute columns and the assessment report.

- the options are read by :func:`reconstruction.generalize.config.read_config`
  (a :class:`~reconstruction.generalize.config.GeneralizeConfig`), the whole
  sequence run by :func:`reconstruction.generalize.pipeline.run`;
- :func:`raw_plots`: the raw areas as single polygons, small ones dropped
  (:class:`RawPlots`);
- :func:`generalize_map`: generalises them (:mod:`reconstruction.generalize.operators`),
  measures them (:mod:`reconstruction.generalize.shape_metrics`) and scores them against
  ground truth (:mod:`reconstruction.generalize.assessment`): a :class:`GeneralizedPlots`
  with the plots, the columns of the output map and a :class:`GeneralizeReport`.

Bad input raises :class:`~reconstruction.core.errors.InputError` with the message
a user should read.
"""

import csv
import json
from collections import Counter
from dataclasses import asdict, dataclass, field
from typing import Optional

from ..core import safefile
from ..core.errors import InputError
from ..core.work_limits import check_alpha
from . import assessment
from . import operators as generalization
from . import shape_metrics

#: column of the output plots: the category of the raw area a plot comes from
#: (only for vector input). Not :data:`reconstruction.core.contract.SOURCE` (how a
#: footprint was made): the same word, another meaning, kept for compatibility.
RAW_CATEGORY = "source"
#: column of the output plots: the methods used, joined by "+"
METHOD = "method"


@dataclass(frozen=True)
class RawPlots:
    """Raw plots as single polygons: ``cats`` the category of the area each comes
    from (None for areas vectorised from a raster), ``areas`` how many raw
    polygons there were, ``dropped`` how many of them were below min_area."""

    polygons: list
    cats: Optional[list]
    areas: int
    dropped: int


def raw_plots(geometries, min_area, name, cats=None):
    """The polygons of the raw areas ``geometries`` of map ``name`` (one per part,
    see :func:`~reconstruction.generalize.operators.explode_plots`), those smaller
    than ``min_area`` dropped."""
    polygons, index = generalization.explode_plots(geometries)
    if not polygons:
        raise InputError("No area with a category in <{}>: nothing to generalise".format(name))
    keep = [k for k, p in enumerate(polygons) if p.area >= min_area]
    if not keep:
        raise InputError("All {} raw areas are smaller than min_area={}: nothing to "
                         "generalise".format(len(polygons), min_area))
    return RawPlots(polygons=[polygons[k] for k in keep],
                    cats=None if cats is None else [cats[index[k]] for k in keep],
                    areas=len(polygons), dropped=len(polygons) - len(keep))


@dataclass(frozen=True)
class PointScores:
    """Detection scores against ground-truth points (one in each true plot)."""

    precision: float
    recall: float
    f_score: float
    gt_points: int


@dataclass(frozen=True)
class ShapeScores:
    """Shape agreement with reference plots (None where nothing matched): the
    turning distance and buffer similarity of the matches; the mean outward
    ``outline_offset`` (map units) and ``iou`` of each reference with the plot that
    overlaps it most (:func:`~reconstruction.generalize.shape_metrics.outline_agreement`),
    per reference, and ``outline_by_step``: the same two means after each step of
    the generalisation ({step: {"offset", "iou"}}; ``raw``: the raw areas, for
    raster input the classified cells)."""

    gt_polygons: int
    matched: int
    turning_distance: Optional[float]
    buffer_similarity: Optional[float]
    turning_distances: list
    buffer_similarities: list
    outline_offset: Optional[float] = None
    iou: Optional[float] = None
    outline_offsets: list = field(default_factory=list)
    ious: list = field(default_factory=list)
    outline_by_step: dict = field(default_factory=dict)


@dataclass(frozen=True)
class PanopticScores:
    """Panoptic quality of the plots against the reference plots as the ICDAR
    2021 MapSeg competition computes it
    (:func:`~reconstruction.generalize.assessment.polygon_panoptic_quality`):
    ``pq`` = ``sq`` * ``rq``; ``pq_matched`` plots and references paired at
    IoU > 0.5 out of ``pq_plots`` and ``pq_references``."""

    pq: float
    sq: float
    rq: float
    pq_matched: int
    pq_plots: int
    pq_references: int


@dataclass(frozen=True)
class FitFigures:
    """The fit step's figures: how many edges were long enough to fit
    (``fit_edges``), how many were moved onto a line of the map
    (``fitted_edges``), and the width of the outline stroke (map units) for
    maps that draw it inside the plots (None for outline=centre)."""

    fit_edges: int
    fitted_edges: int
    stroke_width: Optional[float] = None


@dataclass(frozen=True)
class GeneralizeReport:
    """The figures of one run: counts, methods used, metrics per step, scores."""

    plots: int
    raw_areas: int
    dropped_small: int
    methods: dict
    fallbacks: dict
    steps: list
    points: Optional[PointScores] = None
    shapes: Optional[ShapeScores] = None
    fit: Optional[FitFigures] = None
    panoptic: Optional[PanopticScores] = None

    def figures(self):
        """All figures as one dict, the JSON report (scores only when measured)."""
        figures = {"plots": self.plots, "raw_areas": self.raw_areas,
                   "dropped_small": self.dropped_small, "methods": self.methods,
                   "fallbacks": self.fallbacks, "steps": self.steps}
        for scores in (self.fit, self.points, self.shapes, self.panoptic):
            if scores is not None:
                figures.update(asdict(scores))
        return figures

    def scalars(self):
        """The single-number figures (None where not measurable), in report order."""
        return {k: v for k, v in self.figures().items()
                if isinstance(v, (int, float)) or v is None}

    def write_files(self, files, metrics=None, report=None):
        """Write the metrics CSV (summed and averaged after each step, one row
        per step) to ``metrics`` and the JSON report (:meth:`figures`) to
        ``report`` (None: not written) in ``files``, a
        :func:`reconstruction.core.safefile.together` set: they appear
        together with the module's other outputs, or not at all."""
        if metrics:
            with files.open(metrics, newline="") as f:
                writer = csv.DictWriter(f, fieldnames=list(self.steps[0].keys()))
                writer.writeheader()
                for row in self.steps:
                    writer.writerow({k: (round(v, 6) if isinstance(v, float) else v)
                                     for k, v in row.items()})
        if report:
            with files.open(report) as f:
                json.dump(self.figures(), f, indent=2)


@dataclass(frozen=True)
class GeneralizedPlots:
    """Result of :func:`generalize_map`: the plots (one per raw polygon, in order),
    the attribute columns of the output map, and the report."""

    plots: list
    columns: dict
    report: GeneralizeReport


def _step_rows(steps):
    """One row of summary statistics of the Table 3.1 metrics per step."""
    rows = []
    for name, polygons in steps:
        row = {"step": name}
        row.update(shape_metrics.summarise_metrics(shape_metrics.plot_metrics(polygons)))
        rows.append(row)
    return rows


def _point_scores(plots, xy):
    scores = assessment.point_detection_scores(plots, xy)
    return PointScores(scores.precision, scores.recall, scores.f_score, len(xy))


def _shape_scores(plots, references, buffer, steps=()):
    """The :class:`ShapeScores` of ``plots``; ``steps``: the generalisation's (name,
    polygons), the last of them ``plots`` themselves (measured once)."""
    refs, _index = generalization.explode_plots(references)
    scores = shape_metrics.shape_scores(plots, refs, buffer)
    agreements = {name: shape_metrics.outline_agreement(polygons, refs)
                  for name, polygons in steps}
    outline = agreements[steps[-1][0]] if steps else shape_metrics.outline_agreement(plots, refs)
    by_step = {name: {"offset": a.offset, "iou": a.iou} for name, a in agreements.items()}
    return ShapeScores(scores["references"], scores["matched"], scores["turning_distance"],
                       scores["buffer_similarity"], scores["turning_distances"],
                       scores["buffer_similarities"], outline.offset, outline.iou,
                       outline.offsets, outline.ious, by_step)


def _panoptic_scores(plots, references):
    refs, _index = generalization.explode_plots(references)
    q = assessment.polygon_panoptic_quality(plots, refs)
    return PanopticScores(q.pq, q.sq, q.rq, q.matched, q.predicted, q.true)


def generalize_map(raw, config, gt_points=None, gt_polygons=None, image=None):
    """Generalise the raw plots; measure and score the result.

    An alpha that would sample too many points in these plots raises
    :class:`~reconstruction.core.errors.InputError` first
    (:func:`reconstruction.core.work_limits.check_alpha`).

    ``gt_points``: (n, 2) coordinates of ground-truth points, one in each true
    plot; ``gt_polygons``: reference plot geometries; ``image``: the scanned
    map (:class:`~reconstruction.geom.grid.MapImage`) for the fit step.
    Returns a :class:`GeneralizedPlots`.
    """
    if "alpha" in config.methods:
        check_alpha(raw.polygons, config.alpha)
    result = generalization.generalize_plots(
        raw.polygons, config.methods, alpha=config.alpha, distance=config.distance,
        angle=config.angle, orthogonal=config.orthogonal, tolerance=config.tolerance,
        seed=config.seed, image=image, outline=config.outline, stroke=config.stroke,
        reach=config.reach)
    fit = result.outline_fit
    metrics = shape_metrics.plot_metrics(result.plots)
    columns = {RAW_CATEGORY: raw.cats} if raw.cats is not None else {}
    columns[METHOD] = result.methods
    columns.update({k: metrics[k] for k in shape_metrics.METRICS})
    report = GeneralizeReport(
        plots=len(result.plots), raw_areas=raw.areas, dropped_small=raw.dropped,
        methods=dict(Counter(result.methods)), fallbacks=result.fallbacks,
        steps=_step_rows(result.steps),
        points=None if gt_points is None else _point_scores(result.plots, gt_points),
        shapes=None if gt_polygons is None else _shape_scores(result.plots, gt_polygons,
                                                              config.gt_buffer, result.steps),
        fit=None if fit is None else FitFigures(fit.edges, fit.fitted, fit.stroke_width),
        panoptic=None if gt_polygons is None else _panoptic_scores(result.plots, gt_polygons))
    return GeneralizedPlots(result.plots, columns, report)
