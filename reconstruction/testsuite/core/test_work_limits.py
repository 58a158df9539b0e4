"""Parameters that ask for unbounded work are refused before any work (issue 12, item 2)."""

import numpy as np
import pytest
from shapely.geometry import box

from reconstruction.align import stage as alignment
from reconstruction.classify import config as classify
from reconstruction import generalize
from reconstruction.lod2.solids import build as solids
from reconstruction.subdivide import stage as subdivision
from reconstruction.core import work_limits
from reconstruction.lod2 import outlines
from reconstruction.core.errors import InputError
from reconstruction.lod2.roofs.model import RoofConfig

PLOTS = [box(0, 0, 100, 100), box(150, 0, 230, 60), box(0, 150, 60, 260)]


def test_alpha_estimate_counts_the_points_the_alpha_shape_samples():
    from reconstruction.generalize import operators as generalization

    plot = box(0, 0, 40, 25)
    for alpha in (2.0, 0.5):
        points = generalization.sample_points(plot, alpha / 4, inner_spacing=alpha / 2)
        estimate = work_limits.alpha_points([plot.area], [plot.length], alpha)
        assert abs(len(points) - estimate) <= 0.02 * estimate


@pytest.mark.parametrize("alpha", [0.001, 0.1])
def test_tiny_alpha_is_refused_with_a_reasonable_value(alpha):
    raw = generalize.RawPlots(PLOTS, None, 3, 0)
    config = generalize.GeneralizeConfig(alpha=alpha)
    with pytest.raises(InputError, match=r"alpha=.* use alpha >= (\S+)") as error:
        generalize.generalize_map(raw, config)
    reasonable = float(str(error.value).split("use alpha >= ")[1].split()[0])
    areas = [p.area for p in PLOTS]
    lengths = [p.length for p in PLOTS]
    assert work_limits.alpha_points(areas, lengths, reasonable) <= work_limits.MAX_ALPHA_POINTS
    assert work_limits.alpha_points(areas, lengths, 0.9 * reasonable) > \
        work_limits.MAX_ALPHA_POINTS


def test_alpha_within_the_budget_and_other_methods_pass():
    work_limits.check_alpha(PLOTS, 12.0)
    raw = generalize.RawPlots(PLOTS, None, 3, 0)
    generalize.generalize_map(raw, generalize.GeneralizeConfig(methods=("lines",), alpha=0.001))


@pytest.mark.parametrize("length,depth,key", [((0.001, 0.002), (12, 16), "length"),
                                              ((5, 8), (0.5, 1.0), "depth")])
def test_facades_narrower_than_slivers_are_refused(length, depth, key):
    with pytest.raises(InputError, match="{}=.*at least 2".format(key)):
        subdivision.subdivide(PLOTS, length=length, depth=depth)


def test_facades_from_the_minimum_width_on_pass():
    subdivision.subdivide(PLOTS[:1], length=(2, 3), depth=(12, 16))


def classify_options(**changes):
    base = {"threshold": "0.07,0.10", "threshold_step": "0.01", "minsize": "7,10",
            "minsize_step": "1", "alpha": "1", "classifiers": "rf,knn,svm",
            "features": "spectral,size", "remove": "", "window": "", "iterations": "",
            "min_area": "0", "min_width": "0", "separate": "", "seed": "1", "nprocs": "1",
            "input": "r,g,b"}
    base.update(changes)
    return base


@pytest.mark.parametrize("changes,hint", [
    ({"threshold_step": "0.000001"}, "threshold_step >= "),
    ({"minsize": "1,100000"}, "minsize_step >= "),
])
def test_segmentation_grids_over_the_budget_are_refused(changes, hint):
    with pytest.raises(InputError, match="segmentations") as error:
        classify.read_config(classify_options(**changes))
    assert hint in str(error.value)


def test_the_hinted_threshold_step_fits_the_budget():
    with pytest.raises(InputError) as error:
        classify.read_config(classify_options(threshold_step="0.0001"))
    step = str(error.value).split("threshold_step >= ")[1].split()[0]
    config = classify.read_config(classify_options(threshold_step=step))
    assert len(config.pairs) <= work_limits.MAX_SEGMENTATIONS


def test_crow_steps_below_ten_centimetres_are_refused():
    xy = outlines.clean_ring(np.array([[0, 0], [12, 0], [12, 6], [0, 6.0]]) + 85000)[0]
    b = solids.Buildings([xy], [0.0], [9.0], [3.0], ["stepped"], np.full((1, 3), 0.5))
    with pytest.raises(InputError, match="step=0.01,0.02.*at least 0.1"):
        solids.build_solids(b, RoofConfig(step=(0.01, 0.02)))
    assert len(solids.build_solids(b, RoofConfig(step=(0.1, 0.2))).kept) == 1


def test_facades_of_many_steps_fall_back_to_a_gable():
    xy = outlines.clean_ring(np.array([[0, 0], [12, 0], [12, 6], [0, 6.0]]) + 85000)[0]
    b = solids.Buildings([xy], [0.0], [9.0], [12.0], ["stepped"], np.full((1, 3), 0.5))
    built = solids.build_solids(b, RoofConfig(step=(0.1, 0.1)))
    assert list(built.types) == ["gable"]


def footprints_and_years():
    fps = [box(x, y, x + 8, y + 10) for x in range(0, 220, 20) for y in range(0, 250, 25)]
    return np.array(fps, dtype=object), np.full(len(fps), 1900.0)


@pytest.mark.parametrize("changes,key", [({"buffer": 1e5}, "buffer"), ({"shift": 1e5}, "shift")])
def test_alignment_buffers_and_shifts_beyond_the_maps_are_refused(changes, key):
    fps, years = footprints_and_years()
    config = alignment.AlignmentConfig(year=1961, **changes)
    with pytest.raises(InputError, match="{}=.*larger than the maps".format(key)):
        alignment.align(np.array(PLOTS, dtype=object), [1, 2, 3], fps, years, config)


def test_alignment_pairs_and_correlations_over_the_budget_are_refused():
    fps, _ = footprints_and_years()
    plots = np.array(PLOTS, dtype=object)
    work_limits.check_alignment(plots, fps, 10.0, shift=5.0)
    with pytest.raises(InputError, match="buffer=200 pairs about .* use buffer <= "):
        work_limits.check_alignment(plots, fps, 200.0, max_pairs=50)
    with pytest.raises(InputError, match="shift=100 .* use shift <= "):
        work_limits.check_alignment(plots, fps, 10.0, shift=100.0, max_cells=100_000)
