"""The LoD2 stage's whole sequence, :func:`run`: v.histo.lod2's one entry point.

:func:`run` takes a :class:`~reconstruction.lod2.config.Lod2Config` and the
:class:`Lod2Inputs` (how to read what GRASS holds: callables the stage calls
when it needs them, so that the script can start the slow reads, the
footprints and the 3D points, in the background before the options are
checked) and does, in turn:

1. the existing model read (before any footprint is built: a wrong file
   fails fast; :func:`reconstruction.lod2.output.read_existing`), and the
   map's picture rasters;
2. the footprints, matched with the existing model's buildings
   (:func:`reconstruction.lod2.output.match_existing`);
3. their heights (:func:`reconstruction.lod2.inputs.footprint_heights`) and
   roof requests (:func:`reconstruction.lod2.stage.requests_from_columns`);
4. :func:`reconstruction.lod2.stage.prepare`, the height sources and street
   edges added (:mod:`reconstruction.lod2.inputs`), the copied footprints
   left out (:func:`reconstruction.lod2.output.without_copied`);
5. the solids built (:func:`reconstruction.lod2.output.build`) and the model
   written (:func:`reconstruction.lod2.output.write_model`), validated with -v;
   a CityJSONSeq is built and written a step of buildings at a time
   (:func:`reconstruction.lod2.output.write_in_steps`: memory bounded by a
   step, not by the city).

The messages of each step (:mod:`reconstruction.lod2.report`) go to
``inputs.say`` as the step is done; :func:`reconstruction.lod2.report.report`
gives those of the finished run.
"""

from contextlib import nullcontext
from dataclasses import dataclass, replace
from typing import Callable, ContextManager, Optional

import numpy as np

from ..core.contract import BUILDING
from ..core.errors import InputError
from ..geom.grid import Extent, Grid, MapImage
from . import inputs as lod2_inputs
from . import output as lod2_output
from . import previous as lod2_previous
from .certainty import certainty
from .neighbourhood import Plots
from .report import (build_messages, built_messages, config_messages, existing_messages,
                     existing_model_messages, footprint_messages, ground_points_messages, height_messages,
                     map_messages, matched_heights_messages, plots_messages, previous_messages,
                     street_edge_messages, street_messages)
from .solids import validation
from .stage import Footprints, Lod2Result, prepare, requests_from_columns

#: the strip (m) around the footprints read of a streets raster
STREETS_MARGIN = 10.0


def _no_points():
    return None, None


def _ignore(messages):
    return None


def _unread(*args, **kwargs):
    raise InputError("No reader given for this input")


@dataclass(frozen=True)
class Lod2Inputs:
    """How the stage reads what it needs from GRASS (the script's readers)."""

    #: () -> (geometries, columns) of the footprints (``input=``)
    footprints: Callable[[], tuple]
    #: () -> (ground points, building points), each (N, 3) or None (not given)
    points: Callable[[], tuple] = _no_points
    #: (name, table=True) -> (geometries, columns) of a vector map of areas
    read_areas: Callable[..., tuple] = _unread
    #: (name, bounds, margin) -> :class:`~reconstruction.geom.grid.Grid` of a raster
    read_grid: Callable[..., Grid] = _unread
    #: (names) -> :class:`~reconstruction.geom.grid.MapImage` of the map's red, green
    #: and blue rasters
    read_map_image: Callable[[list], MapImage] = _unread
    #: prints a list of :class:`~reconstruction.core.messages.Message` (as each step is done)
    say: Callable[[list], None] = _ignore
    #: (what) -> a context manager naming what is being done, for the error of a failure
    doing: Callable[[str], ContextManager] = nullcontext


@dataclass(frozen=True)
class Lod2Run:
    """What :func:`run` did: the built buildings, what was written, and with
    -v the validation of every solid (None per valid solid, else its error)."""

    model: Lod2Result
    written: lod2_output.OutputReport
    invalid: Optional[list] = None


def run(inputs, config):
    """Build and write the LoD2 model of ``config`` (a
    :class:`~reconstruction.lod2.config.Lod2Config`)
    from ``inputs`` (:class:`Lod2Inputs`); returns the :class:`Lod2Run`."""
    say, doing = inputs.say, inputs.doing
    say(config_messages(config))
    output = config.output
    if output.maps:
        output = replace(output, map_image=inputs.read_map_image(list(output.maps)))
    model = None
    if config.existing is not None:
        say(existing_messages(config.existing))
        with doing("reading the existing model '{}'".format(config.existing.path)):
            model = lod2_output.read_existing(config.existing, config.location_epsg)
        say(existing_model_messages(model))

    geoms, columns = inputs.footprints()
    if not geoms:
        raise InputError("Vector map <{}> has no areas".format(config.input))
    if output.map_image is not None:
        say(map_messages(output.map_image, Extent.of(geoms)))
    plot = _column(columns, config.plot_column)
    footprints = Footprints(geoms, columns.get("cat"), plot,
                            _column(columns, config.source_column), _column(columns, BUILDING))
    match = None if model is None else lod2_output.match_existing(
        model, config.existing, footprints, lod2_output.footprint_ids(columns, config.id_column))
    found = lod2_inputs.footprint_heights(geoms, columns, plot, _height_options(
        inputs, config, geoms, columns, match))
    say(height_messages(found.report, config))
    requests = requests_from_columns(columns, len(geoms), config.roof_type, config.roof_column,
                                     config.map_year, config.year_column)
    if config.previous is not None:
        kept = _previous(config, footprints, found, inputs)
        requests = lod2_previous.with_earlier_roofs(requests, kept)
        match = lod2_previous.with_previous(match, kept, config.existing, len(geoms))

    prepared = prepare(footprints, found.heights, requests, config)
    prepared = lod2_inputs.with_height_source(prepared, found.source, found.interval)
    prepared = lod2_inputs.with_attributes(prepared, certainty=certainty(
        footprints.source, found.source)[prepared.source])
    if requests.source is not None:
        prepared = lod2_inputs.with_attributes(
            prepared, roof_source=np.asarray(requests.source, dtype=object)[prepared.source])
    if config.streets is not None:
        prepared, edges = lod2_inputs.with_street_edges(
            prepared, _street_options(inputs, config.streets, geoms))
        say(street_edge_messages(edges))
    say(footprint_messages(prepared.report, config))
    prepared = lod2_output.without_copied(prepared, match)     # the copied are not built
    say(build_messages(prepared.report.rings))
    if output.format == "cityjsonseq":      # built and written a step at a time
        result, written, invalid = lod2_output.write_in_steps(
            prepared, config, footprints, output, match, doing, say, config.validate)
        say(built_messages(result.report))
        return Lod2Run(result, written, invalid)
    result = lod2_output.build(prepared, config, match)
    say(built_messages(result.report))
    written = lod2_output.write_model(result, footprints, output, match, doing, say,
                                      config.validate)
    return Lod2Run(result, written, validation.validate(result.solids) if config.validate
                   else None)


def _previous(config, footprints, found, inputs):
    """The :class:`~reconstruction.lod2.previous.PreviousMatch` of the footprints with
    the earlier epoch's model (previous=), read and checked as an existing model is."""
    identity = footprints.identity
    if identity is None:
        raise InputError("Option previous= needs the footprints' {} column (v.histo.subdivide "
                         "year=): it names each footprint's building".format(BUILDING))
    with inputs.doing("reading the earlier epoch's model '{}'".format(config.previous)):
        model = lod2_previous.read_previous(config.previous, config.map_year,
                                            config.location_epsg)
    inputs.say(existing_model_messages(model, "earlier epoch's model", "not kept; the "
                                       "footprints of their identity are built anew"))
    heights = found.heights
    kept = lod2_previous.match_previous(model, identity, footprints.geometries, heights.eaves,
                                        heights.attic, found.source, config.map_year)
    inputs.say(previous_messages(config.previous, kept.report))
    return kept


def _height_options(inputs, config, geoms, columns, match=None):
    """The :class:`~reconstruction.lod2.inputs.HeightOptions` of the config,
    with the points, rasters and maps it names read; without aligned= and
    without an eaves column in ``columns``, the buildings ``match`` copies
    from the existing model give the measured heights (their 3D BAG attributes)."""
    h, say, doing = config.heights, inputs.say, inputs.doing
    elevation = aligned = plots = None
    with doing("reading the 3D points"):
        ground_points, building_points = inputs.points()
    if ground_points is not None:
        say(ground_points_messages(config))
    elif h.elevation:
        elevation = inputs.read_grid(h.elevation, _bounds(geoms),
                                     lod2_inputs.MAX_GROUND_BUFFER + 1)
    if h.aligned:
        with doing("reading the aligned footprints <{}>".format(h.aligned)):
            a_geoms, a_columns = inputs.read_areas(h.aligned)
        aligned = lod2_inputs.AlignedFootprints(a_geoms, a_columns, h.height_columns)
    elif match is not None and h.eaves_column not in columns and h.eaves_range is None:
        aligned = lod2_output.matched_heights(match, geoms, h.height_columns)
        if aligned is not None:
            say(matched_heights_messages(len(aligned.geometries)))
    if h.plots:
        with doing("reading the plots <{}>".format(h.plots)):
            p_geoms, p_columns = inputs.read_areas(h.plots)
        key = config.plot_column if config.plot_column in p_columns else "cat"
        plots = Plots(p_geoms, p_columns[key])
        say(plots_messages(measured=aligned is not None or building_points is not None))
    return lod2_inputs.HeightOptions(
        **h.columns(), ground_points=ground_points, elevation=elevation, aligned=aligned,
        building_points=building_points, plots=plots, rule=h.rule)


def _street_options(inputs, streets, geoms):
    """The :class:`~reconstruction.lod2.inputs.StreetOptions` of a
    :class:`~reconstruction.lod2.config.StreetConfig`, its raster or areas read."""
    if streets.streets:
        grid = inputs.read_grid(streets.streets, _bounds(geoms), STREETS_MARGIN)
        lod2_inputs.check_streets_near(grid, streets.classes, streets.streets, STREETS_MARGIN,
                                       Extent.of(geoms))
        return lod2_inputs.StreetOptions(grid, streets.classes)
    inputs.say(street_messages(streets))
    if streets.areas:
        with inputs.doing("reading the street areas <{}>".format(streets.areas)):
            s_geoms, _columns = inputs.read_areas(streets.areas, table=False)
        return lod2_inputs.StreetOptions([g for g in s_geoms if g is not None])
    return lod2_inputs.StreetOptions()


def _bounds(geoms):
    import shapely

    return shapely.total_bounds([g for g in geoms if g is not None])


def _column(columns, name):
    """The values of column ``name``, or None when it is not in the map."""
    return columns[name] if name and name in columns else None
