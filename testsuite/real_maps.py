"""Training points for the real maps of other styles (../shared/data/maps, issue 50).

The repository holds no point placed on a real map (nor anything else derived
from ../shared/data). The acceptance and the benchmark derive their training
points at run time instead, seeded, by rules written here: **a stand-in for
the points a user places by eye**, not a user's points. Where the map comes
with published ground truth (Venice 1808, its parcels), the rules read the
truth and the scan's colour; where it has none (the Sanborn sheet), colour
rules alone. Pure functions over numpy arrays (no GRASS); the harness
(testsuite/maps_chain.py) turns the cells into map coordinates and writes them
as the points r.histo.classify reads (integer ``label``, text ``class``).

Classes (labels as the Delft chain numbers them: the text and the drawn
outline are 2 and 6, the classes ``remove=2,6`` takes out):

==  ==========  ==============================================================
1   building    Venice: parcel interiors (the ground truth's white, eroded 3
                cells), not ink. Sanborn: the coloured fills (yellow frame,
                pink brick, blue stone: saturation >= 30, not dark).
2   text        Venice: dark cells (mean RGB < 120) inside the parcels (eroded
                2 cells): the parcel numbers. Sanborn: none (ink is one class).
3   water       Venice: outside the blocks (3 cells away), blue-ish (blue - red
                > 15), not ink. Sanborn: none.
4   street      Venice: outside the blocks (3 cells away), not blue, not ink.
                Sanborn: white paper (saturation < 20, mean >= 200).
5   courtyard   Venice: not parcel, enclosed by the blocks (their holes, 3
                cells away), not ink. Sanborn: none.
6   outline     Venice: the ground truth's black within 2 cells of a parcel or
                inside a block (the lines between parcels and around blocks),
                dark in the scan (mean < 150). Sanborn: black ink (mean < 100):
                outlines and text alike.
==  ==========  ==============================================================

Blocks are the parcels' union closed by 0.6 m
(:func:`reconstruction.generalize.assessment.blocks_from_parcels`).
"""

from dataclasses import dataclass

import numpy as np
from scipy import ndimage

from reconstruction.generalize.assessment import blocks_from_parcels, parcels_from_mask

CLASSES = {1: "building", 2: "text", 3: "water", 4: "street", 5: "courtyard", 6: "outline"}
BUILDING, TEXT, WATER, STREET, COURTYARD, OUTLINE = 1, 2, 3, 4, 5, 6


@dataclass(frozen=True)
class TrainingCells:
    """Training points as grid cells: ``rows``, ``cols`` and ``labels`` (int arrays)."""

    rows: np.ndarray
    cols: np.ndarray
    labels: np.ndarray

    def classes(self):
        """The class name of each point."""
        return [CLASSES[int(v)] for v in self.labels]

    def xy(self, west, north, ewres, nsres):
        """The points' coordinates (cell centres) on a grid with that corner and cell size."""
        return np.column_stack([west + (self.cols + 0.5) * ewres,
                                north - (self.rows + 0.5) * nsres])


def draw_cells(masks, per_class, seed):
    """``per_class`` cells drawn at random (``seed``) from each mask of {label: mask}.

    A mask with fewer cells gives all of them; an empty one none. Returns
    :class:`TrainingCells`, by label.
    """
    rng = np.random.default_rng(seed)
    rows, cols, labels = [], [], []
    for label in sorted(masks):
        cells = np.flatnonzero(masks[label])
        if len(cells) > per_class:
            cells = np.sort(rng.choice(cells, per_class, replace=False))
        r, c = np.unravel_index(cells, masks[label].shape)
        rows.append(r)
        cols.append(c)
        labels.append(np.full(len(cells), label))
    return TrainingCells(*(np.concatenate(v).astype(int) for v in (rows, cols, labels)))


def _away(mask, cells):
    """Cells more than ``cells`` (4-connected steps) away from ``mask``."""
    return ~ndimage.binary_dilation(mask, iterations=cells)


def venice_masks(rgb, truth, close=6, margin=3):
    """Where each class's training points may fall on the Venice 1808 cadaster.

    ``rgb``: the scan (rows, cols, 3); ``truth``: the published parcels'
    mask on the same grid (rows, cols), white = parcel; ``close``: the
    blocks' closing radius in cells (0.6 m); ``margin``: cells kept away
    from the parcels' and blocks' edges. Returns {label: boolean mask} (the
    module docstring's rules).
    """
    rgb = np.asarray(rgb, dtype=float)
    mean = rgb.mean(axis=-1)
    parcels = parcels_from_mask(truth) > 0
    blocks = blocks_from_parcels(parcels, close) > 0
    enclosed = ndimage.binary_fill_holes(blocks)
    blue = rgb[..., 2] - rgb[..., 0] > 15
    clear = mean >= 170
    away = _away(blocks, margin)
    return {
        BUILDING: ndimage.binary_erosion(parcels, iterations=margin) & clear,
        TEXT: ndimage.binary_erosion(parcels, iterations=2) & (mean < 120),
        WATER: ~enclosed & away & blue & clear,
        STREET: ~enclosed & away & ~blue & clear,
        COURTYARD: enclosed & ~blocks & away & clear,
        OUTLINE: ~parcels & (blocks | ndimage.binary_dilation(parcels, iterations=2))
        & (mean < 150),
    }


def venice_training_cells(rgb, truth, seed=1, per_class=15):
    """Training points on the Venice 1808 cadaster from its published parcels.

    ``per_class`` cells of each class drawn at random (``seed``) from
    :func:`venice_masks`. A stand-in for a user's points by eye. Returns
    :class:`TrainingCells`.
    """
    return draw_cells(venice_masks(rgb, truth), per_class, seed)


def sanborn_masks(rgba):
    """Where each class's training points may fall on a Sanborn sheet, by colour.

    ``rgba``: the scan (rows, cols, 3 or 4; the alpha band, when there, is 0
    outside the map). Fills (saturation, max - min of RGB, >= 30, mean >= 120)
    are buildings whatever their colour; white paper (saturation < 20, mean
    >= 200) is street; black ink (mean < 100) is the outline class. Cells
    within 3 cells of the map's edge (alpha) are left out. Returns {label:
    boolean mask}. Blue fills stand for stone buildings: keep water out of
    the window.
    """
    rgba = np.asarray(rgba, dtype=float)
    rgb = rgba[..., :3]
    inside = np.ones(rgb.shape[:2], dtype=bool)
    if rgba.shape[-1] == 4:
        inside = ndimage.binary_erosion(rgba[..., 3] > 0, iterations=3)
    mean = rgb.mean(axis=-1)
    saturation = rgb.max(axis=-1) - rgb.min(axis=-1)
    return {
        BUILDING: inside & (saturation >= 30) & (mean >= 120),
        STREET: inside & (saturation < 20) & (mean >= 200),
        OUTLINE: inside & (mean < 100),
    }


def sanborn_training_cells(rgba, seed=1, per_class=15):
    """Training points on a Sanborn sheet by colour rules (:func:`sanborn_masks`),
    ``per_class`` per class drawn at random (``seed``). Returns :class:`TrainingCells`."""
    return draw_cells(sanborn_masks(rgba), per_class, seed)
