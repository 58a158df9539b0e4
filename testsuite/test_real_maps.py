"""Training points derived at run time for the real maps (testsuite/real_maps.py): the
rules on small made-up maps (no GRASS, no shared data)."""

import numpy as np

from real_maps import (BUILDING, COURTYARD, OUTLINE, STREET, TEXT, WATER, draw_cells,
                       sanborn_masks, sanborn_training_cells, venice_masks,
                       venice_training_cells)

PINK, BUFF, BLUE, WHITE, INK, GREY = ((240, 215, 225), (235, 225, 205), (180, 210, 240),
                                      (250, 250, 250), (30, 20, 20), (120, 100, 100))


def made_up_cadaster():
    """A 60 x 100 cadaster: a block of two parcels split by a grey line, a ring
    block around a white courtyard, a buff street between, a blue canal at the
    bottom; a number in ink on the first parcel; its parcel mask."""
    rgb = np.zeros((60, 100, 3), dtype=np.uint8)
    rgb[:] = BUFF
    rgb[45:, :] = BLUE
    truth = np.zeros((60, 100), dtype=np.uint8)
    for r0, r1, c0, c1 in ((5, 35, 5, 24), (5, 35, 26, 45), (5, 35, 60, 95)):
        truth[r0:r1, c0:c1] = 255
        rgb[r0 - 1:r1 + 1, c0 - 1:c1 + 1] = INK          # block and parcel outlines
        rgb[r0:r1, c0:c1] = PINK
    rgb[5:35, 24:26] = GREY                               # the line between the parcels
    truth[11:29, 67:88] = 0                               # the courtyard
    rgb[10:30, 66:89] = INK
    rgb[11:29, 67:88] = WHITE
    rgb[15:19, 10:14] = INK                               # a parcel number
    return rgb, truth


def test_venice_classes_fall_where_the_truth_and_colour_say():
    rgb, truth = made_up_cadaster()
    masks = venice_masks(rgb, truth, close=3, margin=2)
    assert set(masks) == {BUILDING, TEXT, WATER, STREET, COURTYARD, OUTLINE}
    assert all(masks[k].any() for k in masks)
    parcel = truth > 0
    assert not (masks[BUILDING] & ~parcel).any()
    assert not masks[BUILDING][15:19, 10:14].any()            # not on the number
    assert masks[TEXT][15:19, 10:14].all() and masks[TEXT].sum() == 16
    courtyard = np.zeros_like(parcel)
    courtyard[11:29, 67:88] = True
    assert not (masks[COURTYARD] & ~courtyard).any()
    assert (rgb[masks[WATER]] == BLUE).all() and (rgb[masks[STREET]] == BUFF).all()
    # the line between the parcels is an outline, closed into the block; so are the strokes
    assert masks[OUTLINE][5:35, 24:26].all()
    assert not (masks[OUTLINE] & parcel).any()
    assert (rgb[masks[OUTLINE]].mean(axis=-1) < 150).all()


def test_venice_points_drawn_per_class_and_seeded():
    rgb, truth = made_up_cadaster()
    one = venice_training_cells(rgb, truth, seed=3, per_class=5)
    assert np.bincount(one.labels).tolist() == [0, 5, 5, 5, 5, 5, 5]
    again = venice_training_cells(rgb, truth, seed=3, per_class=5)
    other = venice_training_cells(rgb, truth, seed=4, per_class=5)
    assert np.array_equal(one.rows, again.rows) and np.array_equal(one.cols, again.cols)
    assert not (np.array_equal(one.rows, other.rows) and np.array_equal(one.cols, other.cols))
    assert one.classes()[:5] == ["building"] * 5
    xy = one.xy(1000.0, 2000.0, 0.1, 0.1)
    assert np.allclose(xy[:, 0], 1000.0 + (one.cols + 0.5) * 0.1)
    assert np.allclose(xy[:, 1], 2000.0 - (one.rows + 0.5) * 0.1)


def test_draw_takes_what_a_small_class_has():
    mask = np.zeros((4, 4), dtype=bool)
    mask[1, 2] = True
    cells = draw_cells({1: mask, 2: np.zeros_like(mask)}, 5, seed=0)
    assert cells.labels.tolist() == [1] and (cells.rows[0], cells.cols[0]) == (1, 2)


def test_sanborn_colour_rules():
    rgba = np.zeros((30, 40, 4), dtype=np.uint8)
    rgba[..., :3] = (234, 234, 221)                  # paper
    rgba[..., 3] = 255
    rgba[10:20, 5:15, :3] = (240, 220, 150)           # yellow frame
    rgba[10:20, 20:25, :3] = (230, 170, 170)          # pink brick
    rgba[10:20, 27:30, :3] = (148, 184, 172)          # blue stone
    rgba[5, 5:15, :3] = (20, 20, 20)                 # ink
    rgba[:, 35:, 3] = 0                              # outside the sheet
    masks = sanborn_masks(rgba)
    assert set(masks) == {BUILDING, STREET, OUTLINE}
    fills = np.zeros((30, 40), dtype=bool)
    fills[10:20, 5:15] = fills[10:20, 20:25] = fills[10:20, 27:30] = True
    assert np.array_equal(masks[BUILDING], fills)
    assert masks[OUTLINE].sum() == 10 and masks[OUTLINE][5, 5:15].all()
    assert not (masks[STREET] & fills).any() and not masks[STREET][:, 32:].any()
    cells = sanborn_training_cells(rgba, seed=1, per_class=4)
    assert np.bincount(cells.labels).tolist() == [0, 4, 0, 0, 4, 0, 4]
