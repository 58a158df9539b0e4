#!/usr/bin/env python3
############################################################################
#
# MODULE:       r.histo.classify
# AUTHOR(S):    histo developers
# PURPOSE:      Object-based classification of a scanned historical map with
#               tuned segmentation, an ensemble of classifiers and removal of
#               text and symbols
# COPYRIGHT:    (C) 2026 the histo developers
#
#               This program is free software under the GNU General Public
#               License (>=v2). Read the file COPYING that comes with GRASS
#               for details.
#
############################################################################

# %module
# % description: Classifies a scanned RGB historical map by segments (tuned i.segment, random forest + kNN + SVM vote) and removes text and symbols.
# % keyword: raster
# % keyword: classification
# % keyword: segmentation
# % keyword: historical map
# % keyword: histo
# %end
# %option G_OPT_R_INPUTS
# % description: Red, green and blue raster maps of the scanned map
# % guisection: Input
# %end
# %option G_OPT_V_INPUT
# % key: training
# % label: Training points
# % description: Vector points labelling the classes of the map
# % guisection: Input
# %end
# %option G_OPT_DB_COLUMN
# % key: label_column
# % description: Integer column of the training points with the class label
# % answer: label
# % required: yes
# % guisection: Input
# %end
# %option G_OPT_DB_COLUMN
# % key: class_column
# % description: Text column naming the classes (category labels of the output; ignored when absent)
# % answer: class
# % guisection: Input
# %end
# %option G_OPT_R_OUTPUT
# % description: Classified raster map (categories are the training labels)
# % guisection: Output
# %end
# %option G_OPT_R_OUTPUT
# % key: segments
# % required: no
# % description: Chosen segmentation
# % guisection: Output
# %end
# %option
# % key: threshold
# % type: double
# % multiple: yes
# % key_desc: min,max
# % description: Range of i.segment similarity thresholds to try (0-1)
# % answer: 0.07,0.10
# % guisection: Segmentation
# %end
# %option
# % key: threshold_step
# % type: double
# % description: Step of the threshold range
# % answer: 0.01
# % guisection: Segmentation
# %end
# %option
# % key: minsize
# % type: integer
# % multiple: yes
# % key_desc: min,max
# % description: Range of i.segment minimum segment sizes to try (cells)
# % answer: 7,10
# % guisection: Segmentation
# %end
# %option
# % key: minsize_step
# % type: integer
# % description: Step of the minimum size range
# % answer: 1
# % guisection: Segmentation
# %end
# %option
# % key: alpha
# % type: double
# % description: Weight of the F-function combining normalised Moran's I and intra-segment variance
# % answer: 1
# % guisection: Segmentation
# %end
# %option
# % key: classifiers
# % type: string
# % multiple: yes
# % options: rf,knn,svm
# % description: Classifiers of the ensemble (majority vote, ties go to the first)
# % answer: rf,knn,svm
# % guisection: Classification
# %end
# %option
# % key: features
# % type: string
# % multiple: yes
# % options: spectral,size,shape
# % description: Object features the classifiers use: band statistics, log area and perimeter, shape indices
# % descriptions: spectral;mean, median, variance, first and third quartile of each band;size;logarithm of area and perimeter;shape;compact square, compact circle, fractal dimension
# % answer: spectral,size
# % guisection: Classification
# %end
# %option
# % key: remove
# % type: integer
# % multiple: yes
# % description: Class labels to remove (e.g. text, symbols): refilled from their surroundings
# % guisection: Removal
# %end
# %option
# % key: window
# % type: integer
# % description: Moving window size of the refill (odd; default: from the thickness of the removed objects)
# % guisection: Removal
# %end
# %option
# % key: iterations
# % type: integer
# % description: Maximum number of refill iterations (default: until filled)
# % guisection: Removal
# %end
# %option
# % key: min_area
# % type: double
# % description: Minimum mapping unit: regions of one class smaller than this (square map units) are refilled from their surroundings
# % answer: 0
# % guisection: Removal
# %end
# %option
# % key: min_width
# % type: double
# % description: Parts of a class narrower than this (map units) are refilled from their surroundings (e.g. colour fringes, pieces of letters)
# % answer: 0
# % guisection: Removal
# %end
# %option
# % key: separate
# % type: integer
# % multiple: yes
# % description: Class labels (e.g. buildings) whose separate objects the refill must not join across a removed label
# % guisection: Removal
# %end
# %option
# % key: seed
# % type: integer
# % description: Seed of the random forest
# % answer: 1
# %end
# %option G_OPT_M_NPROCS
# %end
# %flag
# % key: p
# % description: Print the tuning table (threshold, minsize, VW, Moran's I, normalised criteria, F) and the chosen pair
# %end

import os
import sys
import time

import grass.script as gs


def find_core():
    """Put the histo core library on sys.path (installed in etc/histo, or the checkout)."""
    here = os.path.dirname(os.path.realpath(__file__))
    for base in (os.path.join(os.path.dirname(here), "etc", "histo"), os.path.dirname(here)):
        if os.path.isfile(os.path.join(base, "reconstruction", "__init__.py")):
            sys.path.insert(0, base)
            return


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


def class_colours(labels, names):
    """Colour rules (label r:g:b) for the labels, by name where known."""
    rules = []
    for i, label in enumerate(labels):
        name = names.get(label, "").strip().lower()
        rules.append("{} {}".format(label, NAMED_COLOURS.get(name, PALETTE[i % len(PALETTE)])))
    return "\n".join(rules)


def parse_range(options, key, cast):
    values = [v for v in options[key].split(",") if v.strip()]
    if len(values) == 1:
        values = values * 2
    if len(values) != 2:
        gs.fatal(_("Option {}= needs min,max (two values), got <{}>").format(key, options[key]))
    try:
        low, high = (cast(v) for v in values)
    except ValueError:
        gs.fatal(_("Option {}= has values that are not numbers: <{}>").format(key, options[key]))
    if high < low:
        gs.fatal(_("Option {}=: the maximum {} is below the minimum {}").format(key, high, low))
    return low, high


def integer_labels(values, column):
    """Class labels of the training points as ints; fatal on missing or fractional values."""
    labels = []
    for value in values:
        if value is None or value == "":
            gs.fatal(_("Training point without a value in column <{}>").format(column))
        try:
            number = float(value)
        except (TypeError, ValueError):
            gs.fatal(_("Column <{}> must hold integer class labels, found <{}>").format(column, value))
        if number != int(number) or number <= 0:
            gs.fatal(_("Column <{}> must hold positive integer class labels, found <{}>").format(
                column, value))
        labels.append(int(number))
    return labels


def run_segmentations(inputs, pairs, nprocs):
    """i.segment for each (threshold, minsize) pair, nprocs at a time.

    Yields (index in pairs, temporary raster name) as each run finishes.
    """
    from reconstruction import grassio

    names = [grassio.temp_map("raster", "seg") for _ in pairs]
    pending = list(range(len(pairs)))
    running = {}
    while pending or running:
        while pending and len(running) < max(nprocs, 1):
            i = pending.pop(0)
            threshold, minsize = pairs[i]
            running[i] = gs.start_command(
                "i.segment", group=",".join(inputs), output=names[i], threshold=threshold,
                minsize=minsize, memory=300, quiet=True, stderr=gs.PIPE)
        i = next(iter(running))
        proc = running.pop(i)
        err = proc.communicate()[1]
        if proc.returncode != 0:
            gs.fatal(_("i.segment failed (threshold={}, minsize={}): {}").format(
                pairs[i][0], pairs[i][1], gs.decode(err).strip()))
        yield i, names[i]


def main():
    import numpy as np

    from reconstruction import classification as cl
    from reconstruction import grassio

    grassio.register_cleanup()
    grassio.require_projected()

    # --- inputs --------------------------------------------------------------
    inputs = [n.strip() for n in options["input"].split(",") if n.strip()]
    if len(inputs) != 3:
        gs.fatal(_("Option input= needs three raster maps (red,green,blue), got {}").format(len(inputs)))
    for name in inputs:
        grassio.require_raster(name)
    if not grassio.raster_region_matches(inputs):
        gs.fatal(_("Input maps <{}> do not share the same extent and resolution").format(
            ",".join(inputs)))
    training = options["training"]
    grassio.require_vector(training)
    label_column = options["label_column"]
    class_column = options["class_column"]
    columns = grassio.column_names(training)
    if label_column not in columns:
        gs.fatal(_("Training map <{}> has no column <{}> (columns: {})").format(
            training, label_column, ", ".join(columns) or _("none")))

    low_t, high_t = parse_range(options, "threshold", float)
    low_m, high_m = parse_range(options, "minsize", int)
    try:
        thresholds = cl.parameter_values(low_t, high_t, float(options["threshold_step"]))
        minsizes = [int(v) for v in cl.parameter_values(low_m, high_m, int(options["minsize_step"]), 0)]
    except ValueError as error:
        gs.fatal(_("Bad parameter range: {}").format(error))
    if not (0 < low_t and high_t < 1):
        gs.fatal(_("Thresholds must lie between 0 and 1, got {}-{}").format(low_t, high_t))
    if low_m < 1:
        gs.fatal(_("Minimum sizes must be at least 1 cell, got {}").format(low_m))
    alpha = float(options["alpha"])
    feature_groups = [g for g in options["features"].split(",") if g]
    classifiers = [c for c in options["classifiers"].split(",") if c]
    if len(set(classifiers)) != len(classifiers):
        gs.fatal(_("Option classifiers= lists a classifier twice"))
    remove = [int(v) for v in options["remove"].split(",") if v.strip()]
    window = int(options["window"]) if options["window"] else None
    if window is not None and (window < 1 or window % 2 == 0):
        gs.fatal(_("Option window= must be a positive odd number, got {}").format(window))
    iterations = int(options["iterations"]) if options["iterations"] else None
    if iterations is not None and iterations < 1:
        gs.fatal(_("Option iterations= must be at least 1"))
    min_area = float(options["min_area"] or 0)
    if min_area < 0:
        gs.fatal(_("Option min_area= must not be negative"))
    min_width = float(options["min_width"] or 0)
    if min_width < 0:
        gs.fatal(_("Option min_width= must not be negative"))
    separate = [int(v) for v in options["separate"].split(",") if v.strip()]
    seed = int(options["seed"])
    nprocs = max(int(options["nprocs"]), 1)

    xy, attributes = grassio.read_points(training)
    if not len(xy):
        gs.fatal(_("Training map <{}> has no points").format(training))
    labels = np.array(integer_labels(attributes[label_column], label_column))
    names = {}
    if class_column and class_column in attributes:
        for label, name in zip(labels, attributes[class_column]):
            if name not in (None, ""):
                names.setdefault(int(label), str(name))
    classes = sorted(set(labels.tolist()))
    if len(classes) < 2:
        gs.fatal(_("Training points hold {} class(es) in column <{}>: at least two are needed").format(
            len(classes), label_column))
    missing = [r for r in remove if r not in classes]
    if missing:
        gs.fatal(_("No training point has the label(s) {} given in remove= (labels: {})").format(
            ",".join(map(str, missing)), ",".join(map(str, classes))))
    missing = [r for r in separate if r not in classes or r in remove]
    if missing:
        gs.fatal(_("Label(s) {} in separate= are not kept classes of the training points").format(
            ",".join(map(str, missing))))
    if len(set(classes) - set(remove)) < 1:
        gs.fatal(_("remove= lists every class: nothing would be left"))

    region = gs.region()
    rows, cols = int(region["rows"]), int(region["cols"])
    prow, pcol = cl.points_to_cells(xy, region["n"], region["w"], region["nsres"], region["ewres"],
                                    rows, cols)
    outside = int((prow < 0).sum())
    if outside:
        gs.fatal(_("{} of {} training points lie outside the computational region").format(
            outside, len(xy)))

    # --- segmentation with tuned parameters ---------------------------------
    timing = {}
    start = time.perf_counter()
    bands = [grassio.read_raster(name) for name in inputs]
    if not all(np.isfinite(b[prow, pcol]).all() for b in bands):
        gs.fatal(_("Some training points lie on no-data cells of the input maps"))
    pairs = [(t, m) for t in thresholds for m in minsizes]
    gs.message(_("Segmenting with {} parameter pairs...").format(len(pairs)))
    criteria = [None] * len(pairs)
    segmentations = [None] * len(pairs)
    for i, name in run_segmentations(inputs, pairs, nprocs):
        segments = grassio.read_raster(name, dtype=np.int32)
        criteria[i] = cl.segmentation_criteria(segments, bands)
        segmentations[i] = name
        if len(pairs) > 1:
            gs.verbose(_("threshold={} minsize={}: VW={:.4f} Moran's I={:.4f}").format(
                pairs[i][0], pairs[i][1], *criteria[i]))
    tuning = cl.tune(criteria, alpha)
    best = tuning.best
    if flags["p"]:
        print("threshold,minsize,vw,moran,vw_norm,moran_norm,f")
        for i, (t, m) in enumerate(pairs):
            print("{},{},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f}".format(
                t, m, tuning.vw[i], tuning.moran[i], tuning.vw_norm[i], tuning.moran_norm[i], tuning.f[i]))
        print("best: threshold={} minsize={}".format(*pairs[best]))
    gs.message(_("Chosen segmentation: threshold={} minsize={} (F={:.3f})").format(
        pairs[best][0], pairs[best][1], tuning.f[best]))
    chosen = segmentations[best]
    for i, name in enumerate(segmentations):
        if i != best:
            gs.run_command("g.remove", flags="f", type="raster", name=name, quiet=True)
            grassio.forget_temp_map("raster", name)
    timing["segmentation"] = time.perf_counter() - start
    start = time.perf_counter()

    # --- object features and classification ----------------------------------
    segments = grassio.read_raster(chosen, dtype=np.int32)
    index, n_segments = cl.relabel(segments)
    ids, features = cl.segment_features(segments, bands)
    train_rows = index[prow, pcol]
    if (train_rows < 0).any():
        gs.fatal(_("Some training points lie outside every segment"))
    gs.message(_("Classifying {} segments with {}...").format(n_segments, ",".join(classifiers)))
    model_features = cl.select_features(features, len(bands), feature_groups)
    voted, _predictions = cl.classify_segments(model_features, train_rows, labels, classifiers, seed,
                                               nprocs)
    result = cl.class_raster(index, voted.astype(np.int32))
    timing["classification"] = time.perf_counter() - start
    start = time.perf_counter()

    # --- removal of text, symbols and small regions --------------------------
    cell_area = region["nsres"] * region["ewres"]
    min_cells = int(np.ceil(min_area / cell_area)) if min_area > 0 else 0
    width_cells = int(round(min_width / min(region["nsres"], region["ewres"]))) if min_width else 0
    if remove or min_cells > 1 or width_cells > 1:
        result, used = cl.remove_classes(result, remove, window, iterations, min_cells, width_cells,
                                         separate)
        if remove:
            gs.message(_("Removed classes {} with a {}x{} moving window").format(
                ",".join(map(str, remove)), used, used))

    timing["removal"] = time.perf_counter() - start
    start = time.perf_counter()

    # --- outputs ------------------------------------------------------------
    output = options["output"]
    grassio.write_raster(output, result, title="Classified historical map", null=0)
    present = [c for c in classes if c not in remove]
    rules = "\n".join("{}:{}".format(c, names.get(c, "class {}".format(c))) for c in present)
    gs.write_command("r.category", map=output, rules="-", stdin=rules + "\n", separator=":", quiet=True)
    colours = class_colours(present, names)
    gs.write_command("r.colors", map=output, rules="-", stdin=colours + "\nnv 255:255:255\n", quiet=True)
    gs.run_command("r.support", map=output, source1="training points <{}>, inputs <{}>".format(
        training, ",".join(inputs)), description="i.segment threshold={} minsize={}".format(*pairs[best]))
    gs.raster_history(output, overwrite=True)
    if options["segments"]:
        gs.run_command("g.rename", raster="{},{}".format(chosen, options["segments"]), quiet=True)
        grassio.forget_temp_map("raster", chosen)
        gs.raster_history(options["segments"], overwrite=True)
    timing["output"] = time.perf_counter() - start
    gs.verbose(_("Timing (s): {}").format(", ".join("{} {:.1f}".format(k, v) for k, v in timing.items())))
    return 0


if __name__ == "__main__":
    options, flags = gs.parser()
    find_core()
    sys.exit(main())
