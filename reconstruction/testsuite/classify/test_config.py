"""r.histo.classify's options read into a ClassifyConfig
(reconstruction.classify.config): no GRASS needed."""

import os

import pytest

from reconstruction.classify import config as classify
from reconstruction.core.errors import InputError

#: every option of the module's g.parser header, with its default (input= and
#: the maps given), as g.parser gives them
DEFAULTS = {"input": "red,green,blue", "training": "points", "label_column": "label",
            "class_column": "class", "output": "classes", "segments": "",
            "threshold": "0.07,0.10", "threshold_step": "0.01", "minsize": "7,10",
            "minsize_step": "1", "alpha": "1", "classifiers": "rf,knn,svm",
            "features": "spectral,size", "remove": "", "window": "", "iterations": "",
            "min_area": "", "min_width": "", "separate": "", "outline": "centre", "seed": "1",
            "nprocs": "1",
            "memory": "300"}
FLAGS = {"e": False, "p": False}


def options(**changes):
    return dict(DEFAULTS, **changes)


def test_default_options_give_the_module_defaults():
    config = classify.read_config(options())
    assert config.thresholds == (0.07, 0.08, 0.09, 0.1)
    assert config.minsizes == (7, 8, 9, 10)
    assert len(config.pairs) == 16 and config.pairs[:2] == [(0.07, 7), (0.07, 8)]
    assert config.classifiers == ("rf", "knn", "svm")
    assert config.features == ("spectral", "size")
    assert config.remove == () and config.window is None and config.iterations is None
    assert config.nprocs == 1 and config.seed == 1


def test_nprocs_has_the_grass_meaning():
    cores = os.cpu_count() or 1
    assert classify.read_config(options(nprocs="2")).nprocs == 2
    assert classify.read_config(options(nprocs="0")).nprocs == cores
    assert classify.read_config(options(nprocs="-1")).nprocs == max(1, cores - 1)


def test_options_read_into_the_config():
    config = classify.read_config(options(threshold="0.05", minsize="5,9", minsize_step="2",
                                          remove="2, 6", separate="1", window="5",
                                          iterations="3", min_area="200", min_width="1.5"))
    assert config.pairs == [(0.05, 5), (0.05, 7), (0.05, 9)]
    assert config.remove == (2, 6) and config.separate == (1,)
    assert (config.window, config.iterations, config.min_area, config.min_width) == (5, 3, 200, 1.5)


@pytest.mark.parametrize("changes,message", [
    ({"threshold": "0.1,0.05"}, "above the maximum"),
    ({"threshold": "0,0.5"}, "between 0 and 1"),
    ({"minsize": "0,3"}, "at least 1 cell"),
    ({"minsize": "a,3"}, "minsize="),
    ({"threshold_step": "0"}, "threshold_step="),
    ({"classifiers": "rf,rf"}, "twice"),
    ({"window": "4"}, "positive odd number"),
    ({"iterations": "0"}, "iterations="),
    ({"min_area": "-1"}, "min_area="),
    ({"min_width": "-1"}, "min_width="),
    ({"remove": "2,x"}, "remove="),
])
def test_bad_options_are_refused_with_the_option_named(changes, message):
    with pytest.raises(InputError, match=message):
        classify.read_config(options(**changes))


def test_maps_columns_and_flags_read_into_the_config():
    config = classify.read_config(options(segments="segs", class_column=""), {"e": True, "p": True})
    assert config.bands == ("red", "green", "blue")
    assert (config.label_column, config.class_column) == ("label", "")
    assert config.keep_segments and config.exhaustive and config.print_table
    config = classify.read_config(options(), FLAGS)
    assert not (config.keep_segments or config.exhaustive or config.print_table)
    assert config.memory == 300 and classify.read_config(options(memory="")).memory == 300
    assert classify.read_config(options()) == config    # no flags: none set


@pytest.mark.parametrize("text", ["red,green", "r,g,b,a", ""])
def test_input_needs_one_or_three_maps(text):
    with pytest.raises(InputError, match=r"Option input= needs one raster map \(a greyscale "
                                         r"scan\) or three \(red, green, blue\), not"):
        classify.read_config(options(input=text), FLAGS)


def test_one_band_is_a_greyscale_scan():
    """Issue 51, item 3: a greyscale scan is one band; CIELAB and the
    registration of the bands need three."""
    config = classify.read_config(options(input="grey"), FLAGS)
    assert config.bands == ("grey",) and config.features == ("spectral", "size")
    with pytest.raises(InputError, match="features=lab needs the red, green and blue"):
        classify.read_config(options(input="grey", features="spectral,lab"), FLAGS)
    with pytest.raises(InputError, match="Flag -b registers the colour bands"):
        classify.read_config(options(input="grey"), dict(FLAGS, b=True))
    assert classify.read_config(options(features="lab"), dict(FLAGS, b=True)).register


@pytest.mark.parametrize("changes,message", [
    ({"alpha": "x"}, "alpha="), ({"seed": "1.5"}, "seed="), ({"memory": "0"}, "memory="),
    ({"separate": "a"}, "separate="), ({"minsize_step": "-1"}, "minsize_step="),
])
def test_other_bad_options_are_refused(changes, message):
    with pytest.raises(InputError, match=message):
        classify.read_config(options(**changes), FLAGS)


def test_outline_is_read_and_inside_needs_the_classes_it_is_drawn_in():
    assert classify.read_config(options()).outline == "centre"
    config = classify.read_config(options(outline="inside", separate="1"))
    assert (config.outline, config.separate) == ("inside", (1,))
    with pytest.raises(InputError, match="outline=inside needs separate="):
        classify.read_config(options(outline="inside"))
    with pytest.raises(InputError, match="outline= must be one of centre, inside"):
        classify.read_config(options(outline="outside", separate="1"))
