#!/usr/bin/env python3
############################################################################
#
# MODULE:       v.histo.lod2
# AUTHOR(S):    histo developers
# PURPOSE:      Builds LoD2 buildings (flat, hip, gable, mansard and
#               crow-stepped gable roofs) on footprints as valid solids and
#               writes them as a CityJSON 2.0 file.
# COPYRIGHT:    (C) 2026 the histo developers
#
#               This program is free software under the GNU General Public
#               License (>=v2). Read the file COPYING that comes with GRASS
#               for details.
#
############################################################################

# %module
# % description: Builds LoD2 buildings with roofs on footprints as valid solids and writes them as CityJSON 2.0.
# % keyword: vector
# % keyword: 3D
# % keyword: CityJSON
# % keyword: LoD2
# % keyword: roof
# % keyword: histo
# %end

# %option G_OPT_V_INPUT
# % description: Footprints (areas), e.g. from v.histo.subdivide
# %end

# %option G_OPT_V_FIELD
# %end

# %option G_OPT_F_OUTPUT
# % description: Name of the CityJSON file to write
# %end

# %option G_OPT_DB_COLUMN
# % key: ground_column
# % description: Column with the ground elevation of each footprint (default: the constant ground=)
# % required: no
# % guisection: Heights
# %end

# %option
# % key: ground
# % type: double
# % description: Ground elevation of every footprint when no ground_column is given
# % answer: 0
# % guisection: Heights
# %end

# %option G_OPT_DB_COLUMN
# % key: eaves_column
# % description: Column with the eaves height (wall height above the ground)
# % answer: h_building
# % required: no
# % guisection: Heights
# %end

# %option G_OPT_DB_COLUMN
# % key: attic_column
# % description: Column with the roof height above the eaves
# % answer: h_attic
# % required: no
# % guisection: Heights
# %end

# %option
# % key: height
# % type: double
# % key_desc: min,max
# % description: Range of eaves heights drawn at random per footprint (takes precedence over eaves_column)
# % required: no
# % guisection: Heights
# %end

# %option
# % key: attic
# % type: double
# % key_desc: min,max
# % description: Range of roof heights drawn at random per footprint (takes precedence over attic_column)
# % required: no
# % guisection: Heights
# %end

# %option G_OPT_V_INPUT
# % key: ground_points
# % label: 3D ground points (e.g. a LiDAR ground class from v.in.pdal or v.in.ascii -z)
# % description: The ground of a footprint is a percentile of the points in it buffered by 0.5 m, the buffer grown where there are none (takes precedence over ground_column)
# % required: no
# % guisection: Heights
# %end

# %option G_OPT_R_ELEV
# % description: Terrain (DTM) raster: the ground of a footprint is a percentile of its cells in it buffered by 0.5 m (used without ground_points)
# % required: no
# % guisection: Heights
# %end

# %option
# % key: ground_percentile
# % type: double
# % description: Percentile of the ground points or cells that is the ground of a footprint
# % options: 0-50
# % answer: 20
# % guisection: Heights
# %end

# %option G_OPT_V_INPUT
# % key: aligned
# % label: Aligned footprints with measured heights (e.g. v.histo.align's output with 3D BAG attributes)
# % description: Footprints that are aligned footprints get their measured heights, the others heights inferred from them by height_rule (takes precedence over eaves_column and attic_column)
# % required: no
# % guisection: Heights
# %end

# %option
# % key: height_columns
# % type: string
# % label: Measured height columns of the aligned footprints
# % description: thesis: roof-0.25, roof-0.99, ground-0.2; 3dbag: b3_h_maaiveld, b3_h_50p, b3_h_70p, b3_h_nok or b3_h_max (2025); 3dbag-2024: b3_h_dak_50p, b3_h_dak_70p, b3_h_dak_max; auto: the first present
# % options: auto,thesis,3dbag,3dbag-2024
# % answer: auto
# % guisection: Heights
# %end

# %option G_OPT_V_INPUT
# % key: plots
# % description: Building plots (areas) for the plot-level neighbourhood analysis; their plot_column (else their category) is the footprints' plot
# % required: no
# % guisection: Heights
# %end

# %option G_OPT_V_INPUT
# % key: building_points
# % label: 3D building (roof) points: eaves and roof top from their 25th and 99th percentiles per footprint
# % description: The shortened version: footprints without points get heights inferred from those with (takes precedence over eaves_column and attic_column)
# % required: no
# % guisection: Heights
# %end

# %option
# % key: height_rule
# % type: string
# % description: How heights are inferred from measured footprints
# % options: robust,plot
# % descriptions: robust;weighted median of the nearby measured footprints without outliers (towers), by size;plot;the thesis's: median of the plot's measured footprints, else of the neighbouring plots'
# % answer: robust
# % guisection: Heights
# %end

# %option
# % key: roof
# % type: string
# % description: Roof type of every footprint; auto draws one per footprint with the thesis's probabilities
# % options: flat,hip,gable,mansard,stepped,auto
# % answer: auto
# % guisection: Roofs
# %end

# %option G_OPT_DB_COLUMN
# % key: roof_column
# % description: Column with a roof type per footprint (flat, hip, gable, mansard, stepped); overrides roof= where not NULL
# % required: no
# % guisection: Roofs
# %end

# %option
# % key: year
# % type: integer
# % description: Year of the map: footprints count as built before it (roof probabilities differ before and after 1915)
# % required: no
# % guisection: Roofs
# %end

# %option G_OPT_DB_COLUMN
# % key: year_column
# % description: Column with a construction year per footprint (values after the map year, e.g. 9999, count as unknown)
# % required: no
# % guisection: Roofs
# %end

# %option
# % key: pitch_min
# % type: double
# % description: Minimum pitch of the hip ends (degrees)
# % answer: 60
# % options: 0-89
# % guisection: Roofs
# %end

# %option
# % key: inset
# % type: double
# % key_desc: min,max
# % description: Range of the mansard inset (m), kept below 0.9 of the footprint's inscribed radius
# % answer: 1,2
# % guisection: Roofs
# %end

# %option
# % key: step
# % type: double
# % key_desc: min,max
# % description: Range of the crow-step height (m)
# % answer: 0.4,0.7
# % guisection: Roofs
# %end

# %option
# % key: thickness
# % type: double
# % description: Thickness of the crow-stepped facade (m)
# % answer: 0.5
# % guisection: Roofs
# %end

# %option G_OPT_R_INPUT
# % key: streets
# % label: Classified map (r.histo.classify's output) showing the streets
# % description: The street edge of a footprint is the unshared edge with most street or water cells in the 3 m in front of it; the thesis's four cases decide where none or several have
# % required: no
# % guisection: Roofs
# %end

# %option
# % key: street_classes
# % type: string
# % description: Street and water classes of the streets map (numbers or category labels)
# % multiple: yes
# % required: no
# % guisection: Roofs
# %end

# %option G_OPT_V_INPUT
# % key: street_areas
# % description: Street areas (polygons; buffer street lines first), used as streets is (without streets)
# % required: no
# % guisection: Roofs
# %end

# %option G_OPT_F_INPUT
# % key: rules
# % label: Roof rules file (CSV or JSON): weights per period and footprint shape
# % description: Rows: from,to,shape,flat,hip,gable,mansard,stepped in percent, each row summing to 100 (default: the thesis's Table B.1 with hip roofs on n-sided footprints)
# % required: no
# % guisection: Roofs
# %end

# %flag
# % key: s
# % description: Do not look for street edges: gable ends and stepped facades on the shortest edge
# % guisection: Roofs
# %end

# %option
# % key: seed
# % type: integer
# % description: Seed of the random draws (roof types, pitches, insets, steps, heights from ranges)
# % answer: 1
# %end

# %option
# % key: crs
# % type: string
# % description: 3D reference system written to the CityJSON metadata (EPSG code or OGC URL; default: the location's EPSG code)
# % required: no
# %end

# %option G_OPT_F_INPUT
# % key: existing
# % required: no
# % description: Existing 3D city model (CityJSON 2.0 or 1.1, or CityJSONSeq .city.jsonl, e.g. the 3D BAG): the aligned footprints that match one of its buildings get that building, copied
# % guisection: Existing model
# %end

# %option G_OPT_DB_COLUMN
# % key: id_column
# % description: Column of the footprints with the building id matched with the existing model's object ids (e.g. pand_id)
# % required: no
# % guisection: Existing model
# %end

# %option
# % key: id_prefix
# % type: string
# % description: Prefix that makes an id of id_column an object id (e.g. NL.IMBAG.Pand.); default: the part of the object id after its last dot, without leading zeros
# % required: no
# % guisection: Existing model
# %end

# %option
# % key: overlap
# % type: double
# % description: Least intersection over union of an aligned footprint and an existing building's footprint to match them by geometry (where ids are absent or match nothing)
# % answer: 0.5
# % guisection: Existing model
# %end

# %option
# % key: existing_lod
# % type: string
# % description: LoDs of the existing buildings to copy (e.g. 2.2, or 1.2,2.2, or all); default: each building's highest
# % required: no
# % multiple: yes
# % guisection: Existing model
# %end

# %option
# % key: format
# % type: string
# % description: Format of the output file: one CityJSON file, or CityJSONSeq (one CityJSONFeature per line, streamed)
# % options: cityjson,cityjsonseq
# % answer: cityjson
# % guisection: Output
# %end

# %option G_OPT_F_OUTPUT
# % key: render
# % required: no
# % description: PNG picture of the model, rendered off-screen (roofs red, walls white; copied buildings blue)
# % guisection: Output
# %end

# %option
# % key: view
# % type: double
# % key_desc: azimuth,elevation
# % description: Where the picture is seen from: azimuth (degrees clockwise from north) and elevation (degrees above the horizon)
# % answer: 210,35
# % guisection: Output
# %end

# %option G_OPT_R_INPUTS
# % key: map
# % required: no
# % description: Red, green and blue rasters of the historical map, draped on the ground of the picture
# % guisection: Output
# %end

# %option G_OPT_DB_COLUMN
# % key: plot_column
# % description: Column with the building plot of each footprint (written as attribute plot)
# % answer: plot
# % required: no
# %end

# %option G_OPT_DB_COLUMN
# % key: source_column
# % description: Column with the source of each footprint, 2pm or aligned (written as attribute source)
# % answer: source
# % required: no
# %end

# %option G_OPT_M_NPROCS
# % description: Number of processes building the solids: 0 = one per core, negative = all cores but that many (the result does not depend on it)
# % answer: 0
# %end

# %flag
# % key: v
# % description: Validate every solid and print counts and percent valid, with the reason for each roof that had to fall back
# %end

import os
import signal
import sys

# Ctrl-C before the module runs (while Python loads it, while GRASS parses its
# options): one error line, as during its work (grassio.run_main takes over)
signal.signal(signal.SIGINT, lambda *_: sys.exit("ERROR: Interrupted while starting"))

import grass.script as gs  # noqa: E402


def find_core():
    """Put the histo core library on sys.path (installed in etc/histo, or the checkout)."""
    here = os.path.dirname(os.path.realpath(__file__))
    for base in (os.path.join(os.path.dirname(here), "etc", "histo"), os.path.dirname(here)):
        if os.path.isfile(os.path.join(base, "reconstruction", "__init__.py")):
            sys.path.insert(0, base)
            return


def main(options, flags):
    from reconstruction import grassio

    grassio.register_cleanup()
    # GRASS exports the footprints while the inputs are checked
    reading = grassio.start_read_areas(options["input"], layer=options["layer"])
    grassio.prefetch_checks()
    from reconstruction.core import crs as crs_codes
    from reconstruction.grassio import points as grassinputs
    from reconstruction.lod2 import stage as lod2
    from reconstruction.lod2 import inputs as lod2_inputs
    from reconstruction.lod2 import output as lod2_output
    from reconstruction.lod2.solids import validation
    # and the points (a million take seconds)
    points = {k: grassinputs.start_read_points(options[k])
              for k in ("ground_points", "building_points")}
    from reconstruction.core.errors import InputError
    from reconstruction.core.options import parse_number, parse_range, processes
    from reconstruction.lod2.roofs.model import RoofConfig
    from reconstruction.lod2.roofs.rules import read_rules

    grassio.require_projected()      # (a missing input map: when reading it)
    output = options["output"]
    grassio.check_outputs(options, files=("output", "render"))
    roof = RoofConfig(pitch_min=parse_number(options["pitch_min"], "pitch_min"),
                      inset=parse_range(options["inset"], "inset", positive=True),
                      step=parse_range(options["step"], "step", positive=True, allow_zero=False),
                      thickness=parse_number(options["thickness"], "thickness", minimum=0,
                                             allow_minimum=False))
    height_range = parse_range(options["height"], "height", positive=True)
    attic_range = parse_range(options["attic"], "attic", positive=True)
    map_year = int(options["year"]) if options["year"] else None
    config = lod2.Lod2Config(roof, seed=int(options["seed"]), map_year=map_year,
                             nprocs=processes(options["nprocs"]),
                             rules=read_rules(options["rules"]) if options["rules"] else None)
    crs = options["crs"] or grassio.location_epsg()
    if crs is None:
        gs.warning(_("The location has no EPSG code and crs= is not given: the CityJSON "
                     "file has no reference system"))
    else:
        try:
            crs = crs_codes.crs_url(crs)
        except ValueError:
            raise InputError("Option crs= must be an EPSG code (e.g. 7415, EPSG:7415) or an OGC "
                             "URL, not <{}>".format(options["crs"])) from None
    request, wanted, model = prepare_output(options, crs)

    with grassio.doing("reading the footprints <{}>".format(options["input"])):
        geoms, columns = grassio.finish_read_areas(reading)
    if not geoms:
        raise InputError("Vector map <{}> has no areas".format(options["input"]))
    grassio.require_columns(options, columns, [k for k in options if k.endswith("_column")],
                            options["input"])
    plot = _column(columns, options["plot_column"])
    footprints = lod2.Footprints(geoms, columns.get("cat"), plot,
                                 _column(columns, options["source_column"]))
    match = None if model is None else lod2_output.match_existing(
        model, wanted, footprints, lod2_output.footprint_ids(columns, options["id_column"]))
    found = lod2_inputs.footprint_heights(geoms, columns, plot, height_options(
        options, points, geoms, columns, height_range, attic_range, match))
    report_heights(found.report, options)
    requests = lod2.requests_from_columns(columns, len(geoms), options["roof"],
                                          options["roof_column"], map_year, options["year_column"])

    prepared = lod2.prepare(footprints, found.heights, requests, config)
    prepared = lod2_inputs.with_height_source(prepared, found.source)
    if not flags["s"]:
        prepared, edges = lod2_inputs.with_street_edges(prepared, street_options(options, geoms))
        report_street_edges(edges)
    report_footprints(prepared.report, options["ground"])
    prepared = lod2_output.without_copied(prepared, match)     # the copied are not built
    if prepared.report.rings:
        gs.message(_("Building {} solids...").format(prepared.report.rings))
    result = lod2_output.build(prepared, config, match)
    report_build(result.report)
    with grassio.doing("writing '{}'".format(output)):
        written = lod2_output.write_model(result, footprints, request, match)
    counts = result.roof_counts()
    report_output(written, counts, output)
    if flags["v"]:
        report_validity(result, validation.validate(result.solids), counts)
    return 0


def prepare_output(options, crs):
    """The output and existing-model requests of the options, with the
    existing model read and the map rasters of the picture (early: a wrong
    file or map fails before the buildings are built)."""
    from reconstruction import grassio
    from reconstruction.grassio import images as grassmaps
    from reconstruction.lod2 import output as lod2_output

    request, wanted = lod2_output.requests_from_options(
        options, crs, title="LoD2 model from <{}>".format(options["input"]))
    if options["map"] and not request.render:
        gs.warning(_("map= is drawn only in the picture of render=: ignored"))
    elif options["map"]:
        request.map_image = grassmaps.read_map_image(options["map"].split(","))
    model = None
    if wanted is not None:
        gs.message(_("Reading the existing model '{}'...").format(wanted.path))
        with grassio.doing("reading the existing model '{}'".format(wanted.path)):
            model = lod2_output.read_existing(wanted, grassio.location_epsg())
    return request, wanted, model


def report_output(written, counts, output):
    """Say what was written: generated buildings (by roof type), copied ones, the picture."""
    gs.message(_("{} buildings written to '{}': {}").format(
        written.generated + written.copied, output,
        ", ".join("{} {}".format(v, k) for k, v in counts.items() if v)))
    if written.match is not None:
        m = written.match
        gs.message(_("{} of {} aligned footprints copied from the existing model ({} matched by "
                     "id, {} by geometry)").format(written.copied, written.candidates, m.by_id,
                                                   m.by_geometry))
        if m.ids_not_found:
            gs.warning(_("{} building ids matched no object of the existing model (tried by "
                         "geometry)").format(m.ids_not_found))
        if m.unmatched:
            gs.warning(_("{} aligned footprints matched no building of the existing model and "
                         "are generated").format(m.unmatched))
        if written.copy.lod_fallback:
            gs.warning(_("{} copied buildings have none of the LoDs of existing_lod= and are "
                         "copied at their highest").format(written.copy.lod_fallback))
        if written.copy.skipped_geometries:
            gs.warning(_("{} geometries of copied buildings (templates or unknown types) are left "
                         "out").format(written.copy.skipped_geometries))
    if written.rendered:
        gs.message(_("Picture written to '{}'").format(written.rendered))


def height_options(options, points, geoms, columns, height_range, attic_range, match=None):
    """The :class:`~reconstruction.lod2.inputs.HeightOptions` of the options,
    with the points (``points``: option -> reading job), rasters and maps they
    name read; without aligned= and without an eaves column in ``columns``,
    the buildings ``match`` copies from the existing model give the measured
    heights (their 3D BAG attributes)."""
    from reconstruction.grassio import points as grassinputs
    from reconstruction import grassio
    from reconstruction.lod2 import inputs as lod2_inputs
    from reconstruction.lod2 import output as lod2_output
    from reconstruction.lod2 import neighbourhood
    from reconstruction.core.options import parse_number

    percentile = parse_number(options["ground_percentile"], "ground_percentile", minimum=0)
    elevation = aligned = plots = None
    with grassio.doing("reading the 3D points"):
        ground_points, building_points = (grassinputs.finish_read_points(points[k])
                                          for k in ("ground_points", "building_points"))
    if ground_points is not None:
        if options["elevation"]:
            gs.warning(_("Both ground_points= and elevation= given: the ground comes from the "
                         "points"))
    elif options["elevation"]:
        grassio.require_raster(options["elevation"])
        elevation = grassinputs.read_grid(options["elevation"], _bounds(geoms),
                                          lod2_inputs.MAX_GROUND_BUFFER + 1)
    if options["aligned"]:
        with grassio.doing("reading the aligned footprints <{}>".format(options["aligned"])):
            a_geoms, a_columns = grassio.read_areas(options["aligned"])
        aligned = lod2_inputs.AlignedFootprints(a_geoms, a_columns, options["height_columns"])
    elif match is not None and options["eaves_column"] not in columns and not height_range:
        aligned = lod2_output.matched_heights(match, geoms, options["height_columns"])
        if aligned is not None:
            gs.message(_("The {} footprints matched in the existing model take its measured "
                         "heights").format(len(aligned.geometries)))
    if options["plots"]:
        with grassio.doing("reading the plots <{}>".format(options["plots"])):
            p_geoms, p_columns = grassio.read_areas(options["plots"])
        key = options["plot_column"] if options["plot_column"] in p_columns else "cat"
        plots = neighbourhood.Plots(p_geoms, p_columns[key])
    if (plots is not None) and aligned is None and building_points is None:
        gs.warning(_("plots= is used only with aligned= or building_points="))
    return lod2_inputs.HeightOptions(
        options["eaves_column"], options["attic_column"], options["ground_column"],
        float(options["ground"]), height_range, attic_range, ground_points, elevation,
        percentile, aligned, building_points, plots,
        neighbourhood.HeightRule(method=options["height_rule"]))


def street_options(options, geoms):
    """The :class:`~reconstruction.lod2.inputs.StreetOptions` of the options."""
    from reconstruction.grassio import points as grassinputs
    from reconstruction import grassio
    from reconstruction.lod2 import inputs as lod2_inputs

    if options["streets"]:
        grassio.require_raster(options["streets"])
        classes = lod2_inputs.parse_classes(options["street_classes"],
                                            grassinputs.raster_labels(options["streets"]))
        grid = grassinputs.read_grid(options["streets"], _bounds(geoms), 10.0)
        return lod2_inputs.StreetOptions(grid, classes)
    if options["street_classes"]:
        gs.warning(_("street_classes= is used only with streets="))
    if options["street_areas"]:
        with grassio.doing("reading the street areas <{}>".format(options["street_areas"])):
            s_geoms, _columns = grassio.read_areas(options["street_areas"], table=False)
        return lod2_inputs.StreetOptions([g for g in s_geoms if g is not None])
    return lod2_inputs.StreetOptions()


def _bounds(geoms):
    import shapely

    return shapely.total_bounds([g for g in geoms if g is not None])


def report_heights(report, options):
    """Say where the heights came from, warn about footprints without ground."""
    if report.ground_from in ("points", "elevation"):
        what = options["ground_points"] if report.ground_from == "points" else options["elevation"]
        gs.message(_("Ground from <{}> (percentile {}): {} footprints with the buffer grown "
                     "over a hole").format(what, options["ground_percentile"],
                                           report.ground_grown))
        if report.ground_missing:
            gs.warning(_("{} footprints have no ground point or cell within {:g} m").format(
                report.ground_missing, 50.0))
    if options["aligned"]:
        gs.message(_("{} of the footprints are aligned footprints with measured heights; {} "
                     "aligned footprints measured").format(report.matched,
                                                           report.aligned_measured))
        if report.aligned_unmeasured:
            gs.warning(_("{} aligned footprints have no measured heights (NULL)").format(
                report.aligned_unmeasured))
    if options["building_points"]:
        gs.message(_("{} footprints have building points").format(report.with_points))
    gs.verbose(_("Height sources: {}").format(
        ", ".join("{} {}".format(v, k) for k, v in report.sources.items())))


def report_street_edges(edges):
    """Say how the street edges were chosen (the cases)."""
    import numpy as np

    from reconstruction.lod2 import street_edges as se

    n = np.bincount(edges.case, minlength=6)
    gs.message(_("Street edges: {} one unshared edge, {} from a neighbour, {} by vote, {} "
                 "shortest, {} facing the streets map; {} enclosed (no street edge)").format(
                     n[se.ONE_FREE], n[se.FROM_NEIGHBOUR], n[se.VOTE], n[se.SHORTEST],
                     n[se.STREETS], n[se.ENCLOSED]))


def _column(columns, name):
    """The values of column ``name``, or None when it is not in the map."""
    return columns[name] if name and name in columns else None


def report_build(report):
    """Warn about the buildings left out or simpler than requested."""
    if report.dropped:
        gs.warning(_("{} footprints gave no valid solid, even flat, and are left out").format(
            report.dropped))
    if report.fell_back:
        gs.warning(_("{} roofs fell back to a simpler type to stay valid").format(report.fell_back))
    if report.by_rule:
        gs.verbose(_("{} roofs changed type by the roof rules (no free street end for a stepped "
                     "facade or a gable)").format(report.by_rule))
    if report.simplified:
        from reconstruction.lod2.solids.vertex_budget import MAX_ROOF_VERTICES

        gs.message(_("{} footprints of more than {} vertices got their pitched roof on a "
                     "simplified outline").format(report.simplified, MAX_ROOF_VERTICES))


def report_validity(result, check, counts):
    """Print the -v report: counts and percent valid, and each fallback and invalid solid."""
    valid = sum(r is None for r in check)
    total = result.report.rings
    print("solids={}".format(total))
    print("valid={}".format(valid))
    print("percent_valid={:.2f}".format(100.0 * valid / total if total else 100.0))
    print("fallbacks={}".format(len(result.report.fallbacks)))
    print("dropped={}".format(result.report.dropped))
    print("simplified={}".format(result.report.simplified))
    for k, v in counts.items():
        print("roof_{}={}".format(k, v))
    for fallback in result.report.fallbacks:
        gs.message(_("Footprint cat {}: {} roof invalid ({}), fell back").format(*fallback))
    for r in check:
        if r is not None:
            gs.message(_("Invalid solid: {}").format(r))


def report_footprints(report, ground):
    """Warn about the footprints left out or changed before building."""
    if report.bad_eaves:
        gs.warning(_("{} footprints with NULL, zero or negative eaves height are left out").format(
            report.bad_eaves))
    if report.bad_attic:
        gs.warning(_("{} footprints with NULL or negative roof height get a flat roof").format(
            report.bad_attic))
    if report.bad_ground:
        gs.warning(_("{} footprints with NULL ground elevation are set on ground={}").format(
            report.bad_ground, ground))
    if report.holes_filled:
        gs.warning(_("{} holes (inner courtyards) in footprints are filled").format(
            report.holes_filled))
    if report.left_out:
        reasons = ", ".join("{} {}".format(v, k) for k, v in report.left_out_reasons.items())
        gs.warning(_("{} footprints or parts of footprints are left out (empty or degenerate: "
                     "{})").format(report.left_out, reasons or "no geometry"))


if __name__ == "__main__":
    options, flags = gs.parser()
    find_core()
    from reconstruction import grassio

    sys.exit(grassio.run_main(main, options, flags))
