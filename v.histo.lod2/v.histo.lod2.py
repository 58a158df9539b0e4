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
# % description: Roof type of every footprint; auto draws one per footprint by the roof rules (period, shape and span)
# % options: flat,hip,gable,mansard,stepped,neck,bell,spout,half_hip,pyramid,gambrel,shed,cornice,auto
# % answer: auto
# % guisection: Roofs
# %end

# %option G_OPT_DB_COLUMN
# % key: roof_column
# % description: Column with a roof type per footprint (a roof= value); overrides roof= where not NULL
# % required: no
# % guisection: Roofs
# %end

# %option
# % key: year
# % type: integer
# % description: Year of the map: footprints count as built before it (roof rules differ by period)
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
# % label: Roof rules file (CSV or JSON): weights per period, footprint shape and span
# % description: Rows: from,to,shape[,min_width,max_width],<one column per roof type> in percent, each row summing to 100 (default: the suite's rules, see the manual)
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

# %option G_OPT_F_INPUT
# % key: previous
# % required: no
# % label: Model of the earlier epoch (a dynamic chain: the v.histo.lod2 output of the earlier map)
# % description: Needs year=, later than its map year. A footprint whose building column names one of its buildings, with the same outline, keeps that building (its solid, roof and heights) unless this epoch measures other heights
# % guisection: Epochs
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

# %option G_OPT_F_OUTPUT
# % key: viewer
# % required: no
# % description: HTML page that shows the model in a web browser, offline: orbit, click a building for its facts, search by id
# % guisection: Output
# %end

# %option G_OPT_F_OUTPUT
# % key: gltf
# % required: no
# % description: Binary glTF (.glb) of the model for Blender, CesiumJS and other 3D tools: one node per building, its attributes in extras
# % guisection: Output
# %end

# %option
# % key: tiles
# % type: string
# % key_desc: name
# % gisprompt: new,dir,dir
# % required: no
# % label: Directory of 3D Tiles 1.1 of the model for CesiumJS and other globes
# % description: tileset.json and a glTF per tile; each building's id, attributes and certainty as its metadata; made if missing
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
# % description: Red, green and blue rasters of the historical map (or one, a greyscale scan), draped on the ground of the picture and the viewer
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
    # and the points (a million take seconds)
    points = [grassio.start_read_points(options[k]) for k in ("ground_points", "building_points")]
    from reconstruction import lod2

    grassio.require_projected()      # (a missing input map: when reading it)
    grassio.check_outputs(options, files=("output", "render", "viewer", "gltf"),
                          inputs={"file": ("rules", "existing", "previous")},
                          directories={"tiles": "tileset.json"})
    config = lod2.read_config(options, flags, grassio.location_epsg(), street_labels(options,
                                                                                  flags))

    def footprints():
        with grassio.doing("reading the footprints <{}>".format(options["input"])):
            geoms, columns = grassio.finish_read_areas(reading)
        if geoms:
            keys = [k for k in options if k.endswith("_column")]
            grassio.require_columns(options, columns, keys, options["input"])
        return geoms, columns

    def read_grid(name, bounds, margin):
        grassio.require_raster(name)
        return grassio.read_grid(name, bounds, margin)

    inputs = lod2.Lod2Inputs(
        footprints, points=lambda: tuple(grassio.finish_read_points(p) for p in points),
        read_areas=grassio.read_areas, read_grid=read_grid,
        read_map_image=grassio.read_map_image, say=grassio.say, doing=grassio.doing)
    result = lod2.run(inputs, config)
    grassio.say(lod2.report(result, config))
    for line in lod2.validity_lines(result):
        print(line)
    return 0


def street_labels(options, flags):
    """The category labels of the streets= raster (None without it or with -s)."""
    from reconstruction import grassio

    if not options["streets"] or flags["s"]:
        return None
    grassio.require_raster(options["streets"])
    return grassio.raster_labels(options["streets"])


if __name__ == "__main__":
    options, flags = gs.parser()
    find_core()
    from reconstruction import grassio

    sys.exit(grassio.run_main(main, options, flags))
