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
# % description: Range of the mansard inset (m), kept below half the shortest edge
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
import sys

import grass.script as gs


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
    from reconstruction import cityjson, lod2, validation
    from reconstruction.errors import InputError
    from reconstruction.options import parse_number, parse_range, processes
    from reconstruction.roof_model import RoofConfig

    grassio.require_projected()      # (a missing input map: when reading it)
    output = options["output"]
    grassio.require_new_file(output, "output")
    outdir = os.path.dirname(os.path.abspath(output))
    if not os.path.isdir(outdir):
        raise InputError("Directory of the output file '{}' does not exist".format(outdir))
    roof = RoofConfig(pitch_min=parse_number(options["pitch_min"], "pitch_min"),
                      inset=parse_range(options["inset"], "inset", positive=True),
                      step=parse_range(options["step"], "step", positive=True, allow_zero=False),
                      thickness=parse_number(options["thickness"], "thickness", minimum=0,
                                             allow_minimum=False))
    height_range = parse_range(options["height"], "height", positive=True)
    attic_range = parse_range(options["attic"], "attic", positive=True)
    map_year = int(options["year"]) if options["year"] else None
    config = lod2.Lod2Config(roof, seed=int(options["seed"]), map_year=map_year,
                             nprocs=processes(options["nprocs"]))
    crs = options["crs"] or grassio.location_epsg()
    if crs is None:
        gs.warning(_("The location has no EPSG code and crs= is not given: the CityJSON "
                     "file has no reference system"))
    else:
        try:
            crs = cityjson.crs_url(crs)
        except ValueError:
            raise InputError("Option crs= must be an EPSG code (e.g. 7415, EPSG:7415) or an OGC "
                             "URL, not <{}>".format(options["crs"])) from None

    with grassio.doing("reading the footprints <{}>".format(options["input"])):
        geoms, columns = grassio.finish_read_areas(reading)
    if not geoms:
        raise InputError("Vector map <{}> has no areas".format(options["input"]))
    heights = lod2.heights_from_columns(
        columns, len(geoms), options["eaves_column"], options["attic_column"],
        options["ground_column"], float(options["ground"]), height_range, attic_range)
    requests = lod2.requests_from_columns(columns, len(geoms), options["roof"],
                                          options["roof_column"], map_year, options["year_column"])
    footprints = lod2.Footprints(geoms, columns.get("cat"), _column(columns, options["plot_column"]),
                                 _column(columns, options["source_column"]))

    prepared = lod2.prepare(footprints, heights, requests, config)
    report_footprints(prepared.report, options["ground"])
    if prepared.report.rings:
        gs.message(_("Building {} solids...").format(prepared.report.rings))
    result = lod2.build(prepared, config)
    report_build(result.report)
    text = lod2.citymodel_text(result, crs, title="LoD2 model from <{}>".format(options["input"]))
    with grassio.doing("writing '{}'".format(output)):
        cityjson.write_text(output, text)

    counts = result.roof_counts()
    gs.message(_("{} buildings written to '{}': {}").format(
        len(result.ids), output, ", ".join("{} {}".format(v, k) for k, v in counts.items() if v)))
    if flags["v"]:
        report_validity(result, validation.validate(result.solids), counts)
    return 0


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
    if report.simplified:
        from reconstruction.vertex_budget import MAX_ROOF_VERTICES

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
