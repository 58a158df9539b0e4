"""Core of r.histo.classify: criteria, features, ensemble, removal (no GRASS needed)."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from reconstruction.classify import removal
from reconstruction.classify import segments as cl

# ---------------------------------------------------------------------------
# Parameters and segmentation criteria
# ---------------------------------------------------------------------------


def test_parameter_values_are_inclusive_and_without_float_drift():
    assert cl.parameter_values(0.07, 0.10, 0.01) == [0.07, 0.08, 0.09, 0.1]
    assert cl.parameter_values(7, 10, 1, 0) == [7, 8, 9, 10]
    assert cl.parameter_values(5, 5, 1) == [5]
    with pytest.raises(ValueError):
        cl.parameter_values(1, 2, 0)
    with pytest.raises(ValueError):
        cl.parameter_values(2, 1, 1)


def test_relabel_makes_ids_consecutive_and_keeps_no_data():
    index, n = cl.relabel(np.array([[5, 5, 0], [9, 2, 9]]))
    assert n == 3
    assert index.tolist() == [[1, 1, -1], [2, 0, 2]]


def test_criteria_of_homogeneous_segments_and_a_checkerboard():
    # two homogeneous halves: no variance inside; two segments of opposite
    # means next to each other: Moran's I = n / |pairs| * z1 z2 / (z1^2 + z2^2) = -1
    segments = np.array([[1, 1, 2, 2]] * 4)
    band = np.where(segments == 1, 10.0, 30.0)
    vw, moran = cl.segmentation_criteria(segments, [band, band * 2])
    assert vw == pytest.approx(0.0)
    assert moran == pytest.approx(-1.0)


def test_area_weighted_variance_by_hand():
    segments = np.array([[1, 1, 1, 2]])
    band = np.array([[0.0, 2.0, 4.0, 7.0]])  # segment 1: var 8/3, segment 2: var 0
    vw, _ = cl.segmentation_criteria(segments, [band])
    assert vw == pytest.approx((3 * 8 / 3 + 1 * 0) / 4)


def test_morans_i_matches_the_textbook_formula():
    rng = np.random.default_rng(3)
    segments = np.repeat(np.repeat(np.arange(1, 10).reshape(3, 3), 4, axis=0), 4, axis=1)
    band = rng.normal(size=segments.shape) + segments * 0.5
    _, moran = cl.segmentation_criteria(segments, [band])
    means = np.array([band[segments == s].mean() for s in range(1, 10)])
    w = np.zeros((9, 9))
    for i in range(9):
        for j in range(9):
            ri, ci, rj, cj = i // 3, i % 3, j // 3, j % 3
            w[i, j] = abs(ri - rj) + abs(ci - cj) == 1
    z = means - means.mean()
    expected = 9 / w.sum() * (w * np.outer(z, z)).sum() / (z ** 2).sum()
    assert moran == pytest.approx(expected)


def test_normalise_f_function_and_tuning_choice():
    assert cl.normalise([1.0, 3.0, 2.0]).tolist() == [1.0, 0.0, 0.5]
    assert cl.normalise([4.0, 4.0]).tolist() == [1.0, 1.0]
    assert cl.f_function(1.0, 1.0, 1.0) == pytest.approx(1.0)
    assert cl.f_function(0.0, 0.0) == 0.0
    # alpha weighs the criteria: F = (1 + a^2) SA VW / (a^2 SA + VW)
    assert cl.f_function(0.5, 1.0, 2.0) == pytest.approx(5 * 0.5 / (4 * 0.5 + 1))
    # pair 1 has the lowest VW and the lowest Moran's I: best in both
    result = cl.tune([(5.0, 0.3), (1.0, -0.2), (3.0, 0.1)])
    assert result.best == 1
    assert result.f[1] == pytest.approx(1.0)
    assert result.vw_norm.tolist() == [0.0, 1.0, 0.5]


# ---------------------------------------------------------------------------
# Object features
# ---------------------------------------------------------------------------


def test_features_match_a_per_segment_loop():
    rng = np.random.default_rng(7)
    segments = rng.integers(1, 6, size=(20, 30))
    segments[0, :5] = 0  # no data
    bands = [rng.normal(100, 20, size=segments.shape) for _ in range(3)]
    bands[1][3, 3] = np.nan  # a no-data cell of one band
    ids, features = cl.segment_features(segments, bands)
    assert ids.tolist() == [1, 2, 3, 4, 5]
    assert features.shape == (5, 20)
    names = cl.feature_names(3)
    assert names[:5] == ["b1_mean", "b1_median", "b1_variance", "b1_q1", "b1_q3"]
    for row, sid in enumerate(ids):
        for b, band in enumerate(bands):
            values = band[(segments == sid) & np.isfinite(band)]
            got = features[row, 5 * b:5 * b + 5]
            expected = [values.mean(), np.median(values), values.var(),
                        np.percentile(values, 25), np.percentile(values, 75)]
            assert got == pytest.approx(expected)
        assert features[row, 15] == (segments == sid).sum()


def test_shape_features_of_a_square_and_a_line():
    segments = np.zeros((12, 12), dtype=int)
    segments[1:5, 1:5] = 1   # 4 x 4 square: area 16, perimeter 16
    segments[8, 1:11] = 2    # 1 x 10 line: area 10, perimeter 22
    band = np.ones(segments.shape)
    _, features = cl.segment_features(segments, [band])
    area, perimeter, square, circle, fractal = features[:, 5:].T
    assert area.tolist() == [16, 10]
    # the background (id 0) is no data, and its edges count as perimeter
    assert perimeter.tolist() == [16, 22]
    assert square[0] == pytest.approx(1.0)
    assert square[1] == pytest.approx(4 * np.sqrt(10) / 22)
    assert circle[0] == pytest.approx(16 / (2 * np.sqrt(np.pi * 16)))
    assert fractal[0] == pytest.approx(2 * np.log(16) / np.log(16.0001))


def test_select_features_takes_groups_and_logs_sizes():
    features = np.arange(1, 21, dtype=float).reshape(1, 20)
    spectral = cl.select_features(features, 3, ("spectral",))
    assert spectral.shape == (1, 15)
    size = cl.select_features(features, 3, ("size",))
    assert size.tolist() == [[np.log(16), np.log(17)]]
    assert cl.select_features(features, 3, ("spectral", "size", "shape")).shape == (1, 20)
    with pytest.raises(ValueError):
        cl.select_features(features, 3, ("colour",))


def test_cielab_of_known_colours():
    # reference values of the CIE formulas (D65): white, black, sRGB red and a grey
    red, green, blue = (np.array(v, dtype=float) for v in zip(
        (255, 255, 255), (0, 0, 0), (255, 0, 0), (119, 119, 119)))
    lightness, a, b = cl.cielab(red, green, blue)
    assert lightness == pytest.approx([100.0, 0.0, 53.24, 50.0], abs=0.05)
    assert a == pytest.approx([0.0, 0.0, 80.09, 0.0], abs=0.05)
    assert b == pytest.approx([0.0, 0.0, 67.20, 0.0], abs=0.05)


def test_lab_features_tell_a_pale_wash_from_white_paper_where_rgb_distances_do_not():
    # the colours of Venice 1808 (medians of regions): pink parcels, a very pale pink
    # parcel, a white courtyard
    pink, pale, white = (251, 226, 236), (254, 240, 249), (253, 250, 250)
    rgb = np.array([pink, pale, white], dtype=float)
    assert np.linalg.norm(rgb[1] - rgb[2]) < np.linalg.norm(rgb[1] - rgb[0])
    lightness, a, b = cl.cielab(*rgb.T)
    assert a[1] - a[2] > 4 and a[0] > a[1] > a[2]
    # a classifier's colour feature: a* puts the pale parcel with the pink ones
    # relative to white, lightness puts it with white
    assert abs(lightness[1] - lightness[2]) < abs(lightness[1] - lightness[0])


def test_object_features_with_lab_add_the_colour_statistics_to_the_bands():
    rng = np.random.default_rng(3)
    segments = rng.integers(1, 4, size=(10, 12))
    bands = [rng.uniform(0, 255, size=segments.shape) for _ in range(3)]
    ids, plain = cl.object_features(segments, bands, ("spectral", "size"))
    _, with_lab = cl.object_features(segments, bands, ("spectral", "lab", "size"))
    _, lab_only = cl.object_features(segments, bands, ("lab",))
    assert ids.tolist() == [1, 2, 3]
    assert plain.shape == (3, 17) and with_lab.shape == (3, 32) and lab_only.shape == (3, 15)
    np.testing.assert_array_equal(with_lab[:, :15], plain[:, :15])
    np.testing.assert_array_equal(with_lab[:, 15:30], lab_only)
    np.testing.assert_array_equal(with_lab[:, 30:], plain[:, 15:])
    lightness = cl.cielab(*bands)[0]
    assert lab_only[0, 0] == pytest.approx(lightness[segments == 1].mean())


def test_finite_features_replaces_nan_and_inf_by_column_median():
    out = cl.finite_features([[1.0, np.inf], [3.0, 2.0], [np.nan, 4.0]])
    assert out.tolist() == [[1.0, 3.0], [3.0, 2.0], [2.0, 4.0]]


# ---------------------------------------------------------------------------
# Classifiers
# ---------------------------------------------------------------------------


def test_majority_vote_with_ties_to_the_first_classifier():
    predictions = np.array([[1, 1, 1, 2, 3],
                            [1, 2, 2, 4, 4],
                            [1, 2, 3, 2, 5]])
    assert cl.majority_vote(predictions).tolist() == [1, 2, 1, 2, 3]
    assert cl.majority_vote(np.array([[4, 5], [6, 5]])).tolist() == [4, 5]


def test_points_to_cells_and_outside_points():
    from reconstruction.geom.grid import Grid

    grid = Grid(None, north=10, west=0, nsres=1, ewres=1, size=(10, 10))
    xy = np.array([[0.5, 9.5], [9.9, 0.1], [10.5, 5], [5, -1]])
    rows, cols = grid.cells(xy[:, 0], xy[:, 1])
    assert rows.tolist() == [0, 9, -1, -1]
    assert cols.tolist() == [0, 9, -1, -1]


def _blobs(seed=0):
    rng = np.random.default_rng(seed)
    centres = np.array([[0, 0, 0], [10, 0, 0], [0, 10, 0]], dtype=float)
    labels = np.repeat([1, 3, 4], 40)
    features = centres[np.repeat([0, 1, 2], 40)] + rng.normal(0, 1, size=(120, 3))
    return features, labels


def test_ensemble_separates_clear_classes_and_is_seeded():
    features, labels = _blobs()
    train = np.arange(0, 120, 8)  # 15 training segments, 5 per class
    voted, predictions = cl.classify_segments(features, train, labels[train], seed=4)
    assert set(predictions) == {"rf", "knn", "svm"}
    assert (voted == labels).mean() > 0.95
    again, _ = cl.classify_segments(features, train, labels[train], seed=4)
    assert np.array_equal(voted, again)
    rf_only, _ = cl.classify_segments(features, train, labels[train], classifiers=("rf",), seed=4)
    assert (rf_only == labels).mean() > 0.95


def test_ensemble_refuses_a_single_class_and_unknown_classifiers():
    features, labels = _blobs()
    with pytest.raises(ValueError):
        cl.classify_segments(features, [0, 1, 2], [1, 1, 1])
    with pytest.raises(ValueError):
        cl.make_classifiers(("rf", "boost"))


# ---------------------------------------------------------------------------
# Removal of text and symbols
# ---------------------------------------------------------------------------


def test_thickness_and_window():
    mask = np.zeros((20, 20), dtype=bool)
    mask[5:8, 2:18] = True  # a stroke 3 cells thick
    assert removal.object_thickness(mask) == 3
    assert removal.removal_window(mask) == 3
    mask[10:19, 2:11] = True  # a 9 x 9 symbol
    assert removal.object_thickness(mask) == 9
    assert removal.removal_window(mask) == 5  # 9 / 2 + 1 = 5.5 -> 5, odd
    assert removal.object_thickness(np.zeros((3, 3), bool)) == 0


def test_fill_takes_the_modal_class_of_the_surroundings():
    classes = np.full((9, 9), 4)
    classes[:, 5:] = 1
    classes[3:6, 3:6] = 2  # text mostly on class 4
    holes = classes == 2
    filled, left = removal.fill_from_surroundings(classes, holes, window=3)
    assert not left.any()
    assert not (filled == 2).any()
    assert (filled[3:6, 3:5] == 4).all()
    assert (filled[:, 6:] == 1).all()


def test_fill_respects_iterations_exclusions_and_no_data():
    classes = np.full((11, 11), 1)
    classes[1:10, 1:10] = 2
    holes = classes == 2
    _, left = removal.fill_from_surroundings(classes, holes, window=3, iterations=1)
    assert left.sum() == 7 * 7
    filled, left = removal.fill_from_surroundings(classes, holes, window=3, exclude=(1,))
    assert np.array_equal(left, holes) and (filled[holes] == 2).all()
    empty = np.zeros((5, 5), dtype=int)
    filled, left = removal.fill_from_surroundings(empty, empty == 0, window=3)
    assert left.all()
    with pytest.raises(ValueError):
        removal.fill_from_surroundings(classes, holes, window=4)


def test_nearest_fill_meets_halfway_where_the_modal_window_favours_the_solid_class():
    # a plot (1) beside a street (4) whose name covers columns 20-29: only
    # specks of the street show between the letters (columns 23 and 26)
    classes = np.full((30, 40), 4)
    classes[:, :20] = 1
    holes = np.zeros(classes.shape, bool)
    holes[:, 20:30] = True
    holes[::3, 23] = False
    holes[1::3, 26] = False
    inner = slice(5, 25)  # away from the map's edge
    modal, _ = removal.fill_from_surroundings(classes, holes, window=9)
    nearest, left = removal.fill_from_nearest(classes, holes)
    assert not left.any()
    # the midline between the plot (column 19) and the first street cells (23)
    # is column 21: the nearest fill stops there, the modal one goes past it
    assert (nearest[inner, 20:22] == 1).all() and not (nearest[inner, 22:] == 1).any()
    assert (modal[inner, 22] == 1).all()
    # no class is invented, known cells keep theirs, ties go to the 3 x 3 majority
    assert np.array_equal(nearest[~holes], classes[~holes])
    assert set(np.unique(nearest)) == {1, 4}


def test_nearest_fill_respects_reach_exclusions_and_no_data():
    classes = np.full((11, 11), 1)
    classes[1:10, 1:10] = 2
    holes = classes == 2
    _, left = removal.fill_from_nearest(classes, holes, reach=1)
    assert left.sum() == 7 * 7
    filled, left = removal.fill_from_nearest(classes, holes, exclude=(1,))
    assert np.array_equal(left, holes) and (filled[holes] == 2).all()
    empty = np.zeros((5, 5), dtype=int)
    filled, left = removal.fill_from_nearest(empty, empty == 0)
    assert left.all()


def test_small_regions_and_thin_parts():
    classes = np.full((12, 12), 4)
    classes[2:8, 2:8] = 1
    classes[10, 10] = 1          # a single building cell
    classes[2:8, 9] = 5          # a one-cell wide line
    small = removal.small_regions(classes, 4)
    assert small[10, 10] and small.sum() == 1
    thin = removal.thin_parts(classes, 3)
    assert thin[2:8, 9].all() and thin[10, 10]
    assert not thin[2:8, 2:8].any()


def _two_plots_and_a_street_name():
    """Two plots 6 cells apart; a street name fills the street between them."""
    classes = np.full((30, 40), 4)          # street
    classes[2:12, 5:35] = 1                 # plot north of the street
    classes[18:28, 5:35] = 1                # plot south of the street
    classes[12:18, 10:30] = 2               # street name, touching both plots
    return classes


def test_removed_name_does_not_join_separated_plots():
    from scipy import ndimage

    classes = _two_plots_and_a_street_name()
    plain, _ = removal.remove_classes(classes, [2], window=7)
    assert ndimage.label(plain == 1)[1] == 1  # the modal fill bridges the street
    kept, _ = removal.remove_classes(classes, [2], window=7, separate=[1])
    assert ndimage.label(kept == 1)[1] == 2
    assert (kept[13:17, 10:30] == 4).all()  # each plot keeps the cells beside it


def test_a_name_along_most_of_two_facing_plots_does_not_join_them():
    from scipy import ndimage

    classes = np.full((30, 40), 4)
    classes[2:12, 5:35] = 1
    classes[18:28, 5:35] = 1
    classes[12:18, 7:33] = 2                # the name covers 26 of the 30 m they face
    out, _ = removal.remove_classes(classes, [2], window=7, separate=[1])
    assert ndimage.label(out == 1)[1] == 2


def test_removed_symbol_rejoins_the_plot_it_covered():
    from scipy import ndimage

    classes = np.full((30, 40), 4)
    classes[5:25, 10:20] = 1                # one narrow plot
    classes[12:17, 8:22] = 6                # a symbol printed across it
    out, window = removal.remove_classes(classes, [6], separate=[1])
    assert window == 3
    assert ndimage.label(out == 1)[1] == 1
    assert (out[12:17, 10:20] == 1).all()


def test_minimum_mapping_unit_and_thin_parts_are_refilled():
    classes = np.full((30, 30), 4)
    classes[5:20, 5:20] = 1
    classes[25:27, 25:27] = 1               # a 4-cell building fragment
    classes[5:20, 22] = 1                   # a one-cell colour fringe
    out, _ = removal.remove_classes(classes, [], min_cells=10, min_width=3)
    assert (out[5:20, 5:20] == 1).all()
    assert (out[25:27, 25:27] == 4).all()
    assert (out[5:20, 22] == 4).all()


def test_street_beside_a_label_is_neither_thin_nor_small_where_the_label_joins_it():
    classes = np.full((30, 40), 4)          # street
    classes[2:12, 5:35] = 1                 # plot north of the street
    classes[18:28, 5:35] = 1                # plot south of the street
    classes[13:17, 2:38] = 2                # a street name along the street ...
    classes[14:16, 10:12] = 4               # ... with street between two letters
    hidden = classes == 2
    base = np.where(hidden, 0, classes)
    # the one-cell strips between the letters and the plots are thin on their own
    assert removal.thin_parts(base, 3)[12, 10:30].all()
    thin = removal.thin_parts(base, 3, hidden=hidden, exact=(1,))
    assert not thin[12, 10:30].any() and not thin[17, 10:30].any()
    # what the letters enclose stays small
    assert removal.small_regions(base, 10, hidden=hidden, exact=(1,))[14:16, 10:12].all()
    # the street between two letters, from plot to plot, reaches the street around
    # the name through them
    classes[12, :] = 1
    classes[17, :] = 1
    classes[12:18, 0:4] = 4
    classes[12:18, 36:] = 4
    classes[13:17, 10:12] = 4
    hidden = classes == 2
    base = np.where(hidden, 0, classes)
    assert removal.small_regions(base, 10)[13:17, 10:12].all()
    assert not removal.small_regions(base, 10, hidden=hidden, exact=(1,))[13:17, 10:12].any()
    # a building speck reaching a plot through the letters stays small: exact
    base[15, 20] = 1
    assert removal.small_regions(base, 10, hidden=hidden, exact=(1,))[15, 20]


def test_what_a_symbol_encloses_stays_small():
    classes = np.full((30, 30), 1)          # a plot ...
    classes[10:18, 10:18] = 6               # ... a symbol printed on it ...
    classes[12:16, 12:16] = 4               # ... its digits in the paper's colour
    classes[:, 25:] = 4                     # the street beside the plot
    classes[10:18, 18:25] = 6               # the symbol reaching the street
    hidden = classes == 6
    small = removal.small_regions(np.where(hidden, 0, classes), 20, hidden=hidden, exact=(1,))
    assert small[12:16, 12:16].all()
    out, _ = removal.remove_classes(classes, [6], min_cells=20, min_width=3, separate=[1])
    assert (out[12:16, 12:16] == 1).all()


def test_a_name_filling_the_street_does_not_join_the_plots_across_it():
    from scipy import ndimage

    classes = np.full((30, 40), 4)
    classes[2:12, 5:35] = 1
    classes[18:28, 5:35] = 1
    classes[13:17, 3:37] = 2                # letters all along the facing plots, one
    classes[14:16, 12:14] = 4               # cell of street either side, a gap between two
    classes[14:16, 24:25] = 4
    out, _ = removal.remove_classes(classes, [2], window=5, min_cells=10, min_width=3,
                                    separate=[1])
    assert ndimage.label(out == 1)[1] == 2
    assert (out[13:17, 5:35] == 4).all()


PAPER, FILL, INK = (238.0, 231.0, 212.0), (236.0, 183.0, 166.0), (60.0, 58.0, 50.0)


def _name_in_a_narrow_street():
    """Two plots either side of a 5-cell street whose name covers all of it
    where they face each other; the paper between the letters (rows of cells
    across the street, a little ink in them) classified as the plots' class.
    Returns (classes, image)."""
    classes = np.full((40, 30), 4)          # street
    classes[5:35, 2:12] = 1                 # plot west of the street
    classes[5:35, 17:28] = 1                # plot east of the street
    image = np.where((classes == 1)[..., None], FILL, PAPER)
    classes[2:38, 12:17] = 2                # the name, letters 3 cells tall ...
    classes[4:38:4, 12:17] = 1              # ... the paper between them classified as plot
    image[classes == 2] = INK
    gaps = (classes == 1) & (np.arange(30)[None, :] >= 12) & (np.arange(30)[None, :] < 17)
    image[gaps] = 0.8 * np.array(PAPER) + 0.2 * np.array(INK)
    return classes, image


def test_the_paper_between_letters_keeps_two_plots_apart():
    from scipy import ndimage

    classes, image = _name_in_a_narrow_street()
    joined, _ = removal.remove_classes(classes, [2], window=5, min_cells=10, min_width=3,
                                       separate=[1])
    assert ndimage.label(joined == 1)[1] == 1          # by the classes alone
    out, _ = removal.remove_classes(classes, [2], window=5, min_cells=10, min_width=3,
                                    separate=[1], image=image)
    assert ndimage.label(out == 1)[1] == 2
    assert (out[5:35, 14] == 4).all()          # the street goes on between them


def test_letter_gaps_go_to_the_class_of_their_colour():
    classes, image = _name_in_a_narrow_street()
    removed = classes == 2
    out = removal.letter_gaps(classes, image, removed, (1,), 3)
    assert (out[4:38:4, 12:17] == 4).all()
    assert (out[:, :12] == classes[:, :12]).all() and (out[:, 17:] == classes[:, 17:]).all()
    image[classes == 1] = FILL              # between letters printed over a plot: its fill
    assert (removal.letter_gaps(classes, image, removed, (1,), 3) == classes).all()


@settings(max_examples=30, deadline=None)
@given(st.integers(0, 10_000), st.integers(1, 3))
def test_fill_leaves_no_hole_and_invents_no_class(seed, half):
    rng = np.random.default_rng(seed)
    classes = rng.choice([1, 3, 4], size=(25, 25))
    holes = rng.random((25, 25)) < 0.4
    holes[0, 0] = False
    for filled, left in (removal.fill_from_surroundings(classes, holes, window=2 * half + 1),
                         removal.fill_from_nearest(classes, holes, window=2 * half + 1)):
        assert not left.any()
        assert np.array_equal(filled[~holes], classes[~holes])
        assert set(np.unique(filled)) <= {1, 3, 4}


def test_class_raster_maps_segment_labels_back():
    index, _ = cl.relabel(np.array([[3, 3, 0], [7, 3, 7]]))
    out = cl.class_raster(index, np.array([1, 4]))
    assert out.tolist() == [[1, 1, 0], [4, 1, 4]]


def test_label_across_a_courtyard_plot_is_filled_when_nothing_gets_joined():
    from scipy import ndimage

    classes = np.full((60, 60), 4)
    classes[10:50, 25:55] = 1               # courtyard plot ...
    classes[18:42, 33:47] = 4               # ... around its yard
    classes[10:50, 5:16] = 1                # a second plot across a 9-cell street
    classes[28:33, 13:37] = 2               # a label across the street and the west wing
    out, _ = removal.remove_classes(classes, [2], window=5, separate=[1])
    assert ndimage.label(out == 1)[1] == 2  # the two plots stay apart ...
    assert (out[28:33, 25:33] == 1).all()   # ... the wing is whole again ...
    assert (out[28:33, 14:16] == 1).all()   # ... and so is the other plot's edge
    assert (out[28:33, 17:24] == 4).all()


def _label_across_a_block_and_its_streets(strokes):
    """A block between two plots across 9-cell streets, a label printed across all
    three: it cuts the block in two, covers both streets and the plots' edges; with
    ``strokes``, the plots' outlines along the streets classified as text too (a
    scan's dark outline strokes), which join the label into one hole the streets
    long."""
    classes = np.full((60, 60), 4)
    classes[5:55, 2:12] = 1                 # west plot
    classes[5:55, 21:35] = 1                # the block
    classes[5:55, 44:56] = 1                # east plot
    if strokes:
        for col in (12, 20, 35, 43):
            classes[5:55, col] = 2
    classes[28:33, 9:47] = 2                # the label, 5 cells tall
    return classes


@pytest.mark.parametrize("window", [7, 9])
@pytest.mark.parametrize("strokes", [False, True])
def test_a_label_across_a_block_and_its_streets_rejoins_the_block_only(window, strokes):
    # the block's two pieces meet only through the label: it cut one plot in two, so
    # the fill restores it; the streets beside it stay streets between separate plots
    # (the label of the synthetic town's 1915 map, "MUSEUM", cut a row of houses in two:
    # the lens of cells beside both pieces' corners, within the window of both, counted
    # as a street between two plots, and the whole hole's building cells were refused)
    from scipy import ndimage

    out, _ = removal.remove_classes(_label_across_a_block_and_its_streets(strokes), [2],
                               window=window, separate=[1])
    regions, n = ndimage.label(out == 1)
    assert n == 3
    assert (out[28:33, 23:33] == 1).all()               # the block whole again
    assert (out[5:55, 15:18] == 4).all() and (out[5:55, 38:41] == 4).all()  # streets
    assert (out[28:33, 9:12] == 1).all() and (out[28:33, 44:47] == 1).all()   # plots' edges


def _a_name_beside_a_plot():
    """A plot (rows 5-24, columns 5-24) with a street name printed beside it in the
    street, against its east outline: three letters 8 cells tall and 4 wide, a cell
    apart, joined by a bar along their top."""
    classes = np.full((30, 50), 4)
    classes[5:25, 5:25] = 1
    for col in (25, 30, 35):
        classes[8:16, col:col + 4] = 2
    classes[8:10, 25:39] = 2
    return classes


def test_a_name_printed_beside_a_plot_goes_back_to_the_street():
    # the nearest fill grows the plot into the letters that touch it (their cells lie
    # nearer the plot than the street beyond them): the Delft 1961 plot along
    # "PEPERSTR." came out almost 2 m too wide; the plot on one side only is no reason
    classes = _a_name_beside_a_plot()
    plain, _ = removal.remove_classes(classes, [2], window=3)
    assert (plain[10:15, 26] == 1).all()    # the plain fill: the plot grows out
    out, _ = removal.remove_classes(classes, [2], window=3, separate=[1])
    assert (out[5:25, 26:] == 4).all()      # one cell beside the outline at most
    assert (out[5:25, 5:25] == 1).all() and (out[:5] == 4).all()


def test_outgrowths_keep_labels_over_and_across_a_plot():
    classes = np.full((40, 40), 4)
    classes[5:35, 5:30] = 1
    classes[12:16, 10:20] = 2               # a label inside the plot
    classes[22:26, 25:36] = 2               # a label across its east edge
    out, _ = removal.remove_classes(classes, [2], window=3, separate=[1])
    assert (out[5:35, 5:30] == 1).all()     # the plot whole again, its edge straight
    assert (out[:, 30:] == 4).all()


@settings(max_examples=30, deadline=None)
@given(st.integers(0, 10_000))
def test_outgrowths_are_filled_cells_of_the_class_away_from_it(seed):
    rng = np.random.default_rng(seed)
    classes = rng.choice([1, 4], size=(20, 20), p=[0.4, 0.6])
    holes = rng.random((20, 20)) < 0.3
    before = np.where(holes, 0, classes)
    after, _ = removal.fill_from_nearest(classes, holes)
    grown = removal.outgrowths(before, after, holes, 1)
    assert not (grown & ~holes).any() and (after[grown] == 1).all()
    # no grown cell touches a known cell of its class
    from scipy import ndimage
    own = ~holes & (classes == 1)
    assert not (grown & ndimage.binary_dilation(own)).any()


def _outlined_blocks_and_a_street_name():
    """Two building blocks (1) 3 cells apart across a street (4), each outlined
    by a 2-cell stroke of a removed outline class (6), and the street's name
    (2; the paper between its letters read as ink) printed across the street
    from stroke to stroke."""
    classes = np.full((40, 53), 4)
    for c0 in (5, 28):                      # the blocks' outer columns
        classes[5:35, c0:c0 + 20] = 6
        classes[7:33, c0 + 2:c0 + 18] = 1
    classes[16:25, 25:28] = 2               # the name, over the whole street
    return classes


def test_a_removed_outline_class_does_not_join_the_blocks_across_a_street():
    """Issue 50, item 2: with the blocks' outline strokes removed too, the
    name's nearest known cells are the blocks', and its refill joined them."""
    from scipy import ndimage

    classes = _outlined_blocks_and_a_street_name()
    assert removal.line_classes(classes, [2, 6]) == (6,)
    for remove in ([2, 6], [6, 2]):
        out, _ = removal.remove_classes(classes, remove, min_width=3)
        assert ndimage.label(out == 1, removal.FOUR)[1] == 2
        assert (out[:, 26] == 4).all()      # the street's middle stays street
        # each stroke split along its middle: the inner half to the block
        assert (out[7:33, 6] == 1).all() and (out[7:33, 5] == 4).all()
    # a block's text alone (no outline removed) is refilled as before
    only_name, _ = removal.remove_classes(np.where(classes == 6, 4, classes), [2])
    assert not removal.line_classes(classes, [2])
    assert (only_name[16:25, 25:28] == 4).all()


def test_a_knot_of_removed_outline_strokes_does_not_set_the_window():
    """Issue 50, item 3: the window and minimum mapping unit follow the
    removed letters' thickness; where the outline strokes (removed too) meet
    in a knot, its thickness made them larger (a 0.1 m map: 18 cells)."""
    classes = _outlined_blocks_and_a_street_name()
    classes[16:25, 25:28] = 4               # no name across the street
    classes[14:23, 1:10] = 6                # a knot where the strokes meet, 9 cells thick
    classes[20:23, 10:19] = 2               # a name 3 cells thick over the block
    assert removal.object_thickness(np.isin(classes, [2, 6])) == 9
    assert removal.removed_thickness(classes, [2, 6]) == 3
    out, window = removal.remove_classes(classes, [2, 6])
    assert window == 3
    assert (out[20:23, 10:19] == 1).all()   # the name over the block refilled by it


def test_which_removed_classes_are_lines_is_decided_for_the_whole_map_not_per_tile():
    """Issue 51, item 4: a tile that sees only the letters of the outline class
    (the other tile its long strokes) decided alone that it is no line class,
    and refilled its blocks otherwise than the next tile: a seam. Counted in
    the tiles' cores and added up, the decision is the whole map's."""
    from reconstruction.classify.tiling import plan_tiles

    classes = np.full((100, 200), 4, dtype=np.int32)
    classes[10:90, 110:190] = 6                     # a block's outline stroke, 2 cells
    classes[12:88, 112:188] = 1
    for k in range(30):                             # 3 x 3 blots of the same class
        r, c = 10 + 10 * (k // 6), 10 + 15 * (k % 6)
        classes[r:r + 3, c:c + 3] = 6
    classes[62:80, 20:47] = classes[62:80, 50:77] = 1   # two blocks, a street between
    classes[70:73, 47:50] = 6                           # a blot over the street
    assert removal.line_classes(classes, [6]) == (6,)
    tiles = plan_tiles(100, 200, 140, 20)
    assert len(tiles) == 2
    left = tiles[0]
    assert removal.line_classes(classes[left.outer], [6]) == ()      # alone: not lines
    counts = {6: (0, 0)}
    for tile in tiles:
        long, cells = removal.line_counts(classes[tile.outer], [6], tile.core_in_outer)[6]
        counts = {6: (counts[6][0] + long, counts[6][1] + cells)}
    assert counts[6][1] == (classes == 6).sum()
    assert removal.line_classes(None, [6], counts) == (6,)
    whole, _ = removal.remove_classes(classes, [6], window=3)
    assert (whole[70:73, 48] == 4).all()             # the blocks not joined across the street
    alone, _ = removal.remove_classes(classes[left.outer], [6], window=3)
    assert (alone[70:73, 48] == 1).any()             # the tile alone joined them
    tiled, _ = removal.remove_classes(classes[left.outer], [6], window=3, lines=(6,))
    assert (tiled[left.core_in_outer] == whole[left.core]).all()
