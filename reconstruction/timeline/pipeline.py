"""v.histo.timeline's work: read the epochs' models and the register, merge them (or
take a year's snapshot), write the model."""

import os
from dataclasses import dataclass
from typing import Callable, Optional

import numpy as np
import orjson

from ..cityjson import existing
from ..cityjson.geometry import json_bytes
from ..cityjson.seq import document_features
from ..core import register as bag
from ..core.errors import InputError
from ..core.safefile import together
from ..epochs.dynamic import (Epoch, MergeReport, buildings, check_merged, epoch_years,
                              merge_epochs, snapshot)
from .. import view


@dataclass(frozen=True)
class TimelineResult:
    """The ``document`` to write; the :class:`~reconstruction.epochs.dynamic.MergeReport`
    of the merge (``merge``, None when a merged model was read); the model's epoch
    ``years``; the ``snapshot`` year (None: the whole model); the ``buildings``
    written (top-level objects) and the ``register`` size read (None: none)."""

    document: dict
    merge: Optional[MergeReport]
    years: tuple
    snapshot: Optional[int]
    buildings: int
    register: Optional[int] = None


def read_register(table, id_column=None, year_column=None, name="<register>"):
    """{BAG id: construction year or None} of today's footprints' attribute table
    (``table``: {column: values}); the ids from ``id_column`` or the first of the
    usual names, the years from ``year_column`` (default ``bouwjaar``, else
    ``oorspronkelijkbouwjaar``). InputError for a missing column."""
    ids = bag.bag_ids(table, id_column, name)
    if ids is None:
        raise InputError("Vector map <{}> (register=) has no building id column ({}); give "
                         "id_column=".format(name, ", ".join(bag.BAG_ID_COLUMNS)))
    column = bag.year_column(table, year_column or "bouwjaar", bool(year_column), name)
    years = bag.construction_years(table[column], column, ids=ids)
    return {i: (int(y) if np.isfinite(y) else None) for i, y in zip(ids, years)
            if i is not None}


def _title(config):
    if config.title:
        return config.title
    if config.snapshot is not None:
        return "The town in {}".format(config.snapshot)
    return "The town over the map epochs {}".format(", ".join(map(str, sorted(config.years))))


def run(config, read_table, doing):
    """The :class:`TimelineResult` of a :class:`~.config.TimelineConfig`;
    ``read_table(name)``: a vector map's attribute table; ``doing(text)``: a
    context naming what is being done (for the error of a failure)."""
    register = None
    if config.register:
        with doing("reading the register <{}>".format(config.register)):
            register = read_register(read_table(config.register), config.id_column,
                                     config.year_column, config.register)
    merge = None
    if config.input:
        with doing("reading the merged model '{}'".format(config.input)):
            document = existing.read_document(config.input)
            check_merged(document, config.input)
    else:
        epochs = []
        for path, year in zip(config.models, config.years):
            with doing("reading the model of {} '{}'".format(year, path)):
                epochs.append(Epoch(year, existing.read_document(path), path))
        with doing("merging the epochs"):
            merged = merge_epochs(epochs, register, title=_title(config))
        document, merge = merged.document, merged.report
    years = tuple(epoch_years(document))
    if config.snapshot is not None:
        with doing("taking the snapshot of {}".format(config.snapshot)):
            document = snapshot(document, config.snapshot)
        if config.title:
            document.setdefault("metadata", {})["title"] = config.title
    count = len(buildings(document.get("CityObjects", {})))
    return TimelineResult(document, merge, years, config.snapshot, count,
                          None if register is None else len(register))


def _lines(document):
    for feature in document_features(document):
        yield json_bytes(feature) + b"\n"


def write(result, config, report_json=None):
    """Write the model (and the JSON report, the viewer's page, the glTF and the 3D
    Tiles) together: all appear, or none."""
    with together() as files:
        with files.open(config.output, mode="wb", encoding=None) as f:
            if config.format == "cityjsonseq":
                for line in _lines(result.document):
                    f.write(line)
            else:
                f.write(json_bytes(result.document))
        if config.report_file and report_json is not None:
            with files.open(config.report_file) as f:
                f.write(orjson.dumps(report_json, option=orjson.OPT_INDENT_2).decode())
        scene = (view.build_scene(result.document) if config.viewer or config.gltf or
                 config.tiles else None)
        if config.viewer:
            with files.open(config.viewer) as f:
                view.write_viewer(f, scene, _title(config))
        if config.gltf:
            with files.open(config.gltf, mode="wb", encoding=None) as f:
                view.write_glb(f, scene, folder=os.path.dirname(os.path.abspath(config.gltf)))
        if config.tiles:
            view.write_tileset(files.reserve_dir(config.tiles), scene, _title(config))
    return os.path.getsize(config.output)
