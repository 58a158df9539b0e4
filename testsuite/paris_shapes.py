"""The Paris 1925 atlas's ground truth as the ICDAR 2021 MapSeg competition reads it (issue 51).

``../shared/data/maps/paris_1925`` holds the western part of a sheet of the
Atlas municipal (1925), its content mask and the shapes vectorised by hand,
published as an edge image (255 on the 1-pixel boundary of every closed
shape: blocks, hatched buildings, squares, the river...). The competition
read such ground truth as the 4-connected regions of the non-edge cells
inside the content mask, one shape each, the open space of the streets
included, no size filter, and scored a prediction with its panoptic quality
(PQ = SQ * RQ, shapes matched at IoU > 0.5; its best entry reached 0.741).
This edge image comes from the same authors' vectorisation dataset
(soduco/ICDAR-2021-Vectorization), which outlines more kinds of shapes than
the competition's task 1 (building blocks only): the metric is the
competition's, the reference not quite its test set.

Pure functions over numpy arrays (no GRASS); nothing read from the shared
data is kept in the repository:

- :func:`paris_files`: where the three rasters are (:class:`ParisFiles`);
- :func:`read_band`: one band of a TIFF as an array (Pillow);
- :func:`paris_truth`: the ground-truth shapes and the content mask
  (:class:`ParisTruth`), from arrays or read from the files;
- :func:`score_prediction`: the ICDAR panoptic quality of a predicted label
  raster on the same grid
  (:func:`reconstruction.generalize.assessment.icdar_panoptic_quality`).
"""

import os
from dataclasses import dataclass

import numpy as np

from reconstruction.generalize.assessment import icdar_panoptic_quality, shapes_from_edges

#: the folder of the Paris atlas in the shared reference data
PARIS = os.path.join("maps", "paris_1925")


@dataclass(frozen=True)
class ParisFiles:
    """The scan, the published edge image and the content mask (paths)."""

    scan: str
    edges: str
    mask: str

    def missing(self):
        """The paths that do not exist."""
        return [p for p in (self.scan, self.edges, self.mask) if not os.path.exists(p)]


def paris_files(shared_data):
    """The Paris 1925 (western part) rasters under ``shared_data``."""
    folder = os.path.join(shared_data, PARIS)
    return ParisFiles(os.path.join(folder, "paris_1925_west.tif"),
                      os.path.join(folder, "paris_1925_west_edges_gt.tif"),
                      os.path.join(folder, "paris_1925_west_content_mask.tif"))


def read_band(path, band=0):
    """Band ``band`` of an image file as a 2-D array (rows from the north)."""
    from PIL import Image

    with Image.open(path) as image:
        values = np.asarray(image)
    return values if values.ndim == 2 else values[..., band]


@dataclass(frozen=True)
class ParisTruth:
    """The ground-truth shapes (a label raster: 0 on the edges and outside
    the map, 1..``count`` the shapes) and the content mask (True where the
    map is), on the scan's grid."""

    shapes: np.ndarray
    mask: np.ndarray

    @property
    def count(self):
        """How many shapes."""
        return int(self.shapes.max())


def paris_truth(edges, mask):
    """The :class:`ParisTruth` of an edge image and a content mask (arrays,
    non-zero on the edges and where the map is), as the competition reads
    them (:func:`reconstruction.generalize.assessment.shapes_from_edges`)."""
    edges, mask = np.asarray(edges), np.asarray(mask)
    if edges.shape != mask.shape:
        raise ValueError("edge image {} and content mask {} on different grids".format(
            edges.shape, mask.shape))
    return ParisTruth(shapes_from_edges(edges, mask), mask != 0)


def read_paris_truth(files):
    """The :class:`ParisTruth` of the published files (:class:`ParisFiles`)."""
    return paris_truth(read_band(files.edges), read_band(files.mask))


def score_prediction(predicted, truth):
    """The ICDAR 2021 MapSeg panoptic quality of ``predicted`` against the truth.

    ``predicted``: a label raster on the truth's grid (0 = no shape, each
    other value one shape) or a boolean raster (its 4-connected regions are
    the shapes); cells outside the content mask are dropped, as the
    competition masks its inputs. Returns a
    :class:`~reconstruction.generalize.assessment.PanopticQuality`.
    """
    predicted = np.asarray(predicted)
    if predicted.shape != truth.shapes.shape:
        raise ValueError("prediction {} not on the ground truth's grid {}".format(
            predicted.shape, truth.shapes.shape))
    return icdar_panoptic_quality(predicted, truth.shapes, truth.mask)
