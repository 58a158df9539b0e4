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


def parse_range(text, key, positive=True):
    """A min,max option as two floats (a single value gives min = max)."""
    if not text:
        return None
    try:
        values = [float(v) for v in text.split(",") if v.strip()]
    except ValueError:
        gs.fatal(_("Option {}= must be two numbers min,max, not <{}>").format(key, text))
    if len(values) == 1:
        values = values * 2
    if len(values) != 2 or values[0] > values[1]:
        gs.fatal(_("Option {}= must be min,max with min <= max, not <{}>").format(key, text))
    if positive and values[0] < 0:
        gs.fatal(_("Option {}= must not be negative").format(key))
    return values


def numeric_column(columns, name, label):
    """Values of a numeric column as floats (None -> nan); fatal if missing or not numeric."""
    import numpy as np

    if name not in columns:
        gs.fatal(_("Column <{}> ({}) not found in the input map; available: {}").format(
            name, label, ", ".join(sorted(columns))))
    out = []
    for v in columns[name]:
        if v is None or v == "":
            out.append(np.nan)
            continue
        try:
            out.append(float(v))
        except (TypeError, ValueError):
            gs.fatal(_("Column <{}> ({}) is not numeric: value <{}>").format(name, label, v))
    return np.asarray(out, dtype=float)


def main():
    options, flags = OPTIONS, FLAGS
    from reconstruction import grassio

    grassio.register_cleanup()
    # GRASS exports the footprints while the inputs are checked
    reading = grassio.start_read_areas(options["input"], layer=options["layer"])
    grassio.prefetch_checks()
    import numpy as np

    from reconstruction import cityjson, roofs, solids

    grassio.require_projected()      # (a missing input map: when reading it)
    output = options["output"]
    grassio.require_new_file(output, "output")
    outdir = os.path.dirname(os.path.abspath(output))
    if not os.path.isdir(outdir):
        gs.fatal(_("Directory of the output file '{}' does not exist").format(outdir))

    height_range = parse_range(options["height"], "height")
    attic_range = parse_range(options["attic"], "attic")
    inset_range = parse_range(options["inset"], "inset")
    step_range = parse_range(options["step"], "step")
    if step_range[0] <= 0:
        gs.fatal(_("Option step= must be positive"))
    thickness = float(options["thickness"])
    if thickness <= 0:
        gs.fatal(_("Option thickness= must be positive"))
    pitch_min = float(options["pitch_min"])
    seed = int(options["seed"])
    nprocs = int(options["nprocs"])
    if nprocs <= 0:
        nprocs = max(1, (os.cpu_count() or 1) + nprocs)
    map_year = int(options["year"]) if options["year"] else None
    crs = options["crs"] or grassio.location_epsg()
    if crs is None:
        gs.warning(_("The location has no EPSG code and crs= is not given: the CityJSON "
                     "file has no reference system"))
    else:
        try:
            crs = cityjson.crs_url(crs)
        except ValueError:
            gs.fatal(_("Option crs= must be an EPSG code (e.g. 7415, EPSG:7415) or an OGC URL, "
                       "not <{}>").format(options["crs"]))

    geoms, columns = grassio.finish_read_areas(reading)
    if not geoms:
        gs.fatal(_("Vector map <{}> has no areas").format(options["input"]))
    n_feat = len(geoms)

    # per-feature values -------------------------------------------------
    if height_range is None:
        eaves = numeric_column(columns, options["eaves_column"], "eaves height")
    if attic_range is None:
        attic = numeric_column(columns, options["attic_column"], "roof height")
    if options["ground_column"]:
        ground = numeric_column(columns, options["ground_column"], "ground elevation")
    else:
        ground = np.full(n_feat, float(options["ground"]))
    requested = np.full(n_feat, options["roof"], dtype=object)
    if options["roof_column"]:
        if options["roof_column"] not in columns:
            gs.fatal(_("Column <{}> (roof type) not found in the input map").format(
                options["roof_column"]))
        values = [None if v is None else str(v).strip().lower() for v in columns[options["roof_column"]]]
        unknown = sorted({v for v in values if v not in (None, "") and v not in roofs.ROOF_TYPES + ("auto",)})
        if unknown:
            gs.fatal(_("Unknown roof types in column <{}>: {} (known: {})").format(
                options["roof_column"], ", ".join(unknown), ", ".join(roofs.ROOF_TYPES)))
        requested = np.array([v if v not in (None, "") else options["roof"] for v in values],
                             dtype=object)
    years = np.full(n_feat, np.nan if map_year is None else float(map_year))
    if options["year_column"]:
        built = numeric_column(columns, options["year_column"], "construction year")
        known = ~np.isnan(built) & (built > 0)
        if map_year is not None:
            known &= built <= map_year
        years = np.where(known, built, years)

    rng = np.random.default_rng(seed)
    u_type = rng.random(n_feat)
    u_shape = rng.random((n_feat, 3))
    u_height = rng.random((n_feat, 2))
    if height_range is not None:
        eaves = height_range[0] + (height_range[1] - height_range[0]) * u_height[:, 0]
    if attic_range is not None:
        attic = attic_range[0] + (attic_range[1] - attic_range[0]) * u_height[:, 1]

    # bad heights ---------------------------------------------------------
    bad_eaves = np.isnan(eaves) | (eaves <= 0)
    if bad_eaves.any():
        gs.warning(_("{} footprints with NULL, zero or negative eaves height are left out").format(
            int(bad_eaves.sum())))
    bad_attic = np.isnan(attic) | (attic < 0)
    if bad_attic.any():
        gs.warning(_("{} footprints with NULL or negative roof height get a flat roof").format(
            int(bad_attic.sum())))
        attic = np.where(bad_attic, 0.0, attic)
        requested = np.where(bad_attic, "flat", requested)
    bad_ground = np.isnan(ground)
    if bad_ground.any():
        gs.warning(_("{} footprints with NULL ground elevation are set on ground={}").format(
            int(bad_ground.sum()), options["ground"]))
        ground = np.where(bad_ground, float(options["ground"]), ground)

    # footprints: one ring per polygon part -------------------------------
    polys, src, part, n_holes, n_bad = solids.footprint_polygons(geoms, skip=bad_eaves)
    reasons = {}
    cleaned, why = solids.clean_rings(polys)
    ok = np.array([r is not None for r in cleaned], dtype=bool)
    for w in why:
        if w is not None:
            n_bad += 1
            reasons[w] = reasons.get(w, 0) + 1
    rings = [r for r, good in zip(cleaned, ok) if good]
    src, part = src[ok], part[ok]
    simple = solids.rings_are_simple(rings)
    if not simple.all():
        n_bad += int((~simple).sum())
        reasons["self-intersecting outline"] = int((~simple).sum())
        rings = [r for r, good in zip(rings, simple) if good]
        src, part = src[simple], part[simple]
    if n_holes:
        gs.warning(_("{} holes (inner courtyards) in footprints are filled").format(n_holes))
    if n_bad:
        gs.warning(_("{} footprints or parts of footprints are left out (empty or degenerate: {})").format(
            n_bad, ", ".join("{} {}".format(v, k) for k, v in reasons.items()) or "no geometry"))
    if not rings:
        gs.fatal(_("No footprint left to build"))

    # roof types ------------------------------------------------------------
    nverts = np.array([len(r) for r in rings])
    drawn = roofs.draw_roof_types(nverts, years[src], attic[src], _Uniform(u_type[src]))
    types = np.where(requested[src] == "auto", drawn, requested[src])

    gs.message(_("Building {} solids...").format(len(rings)))
    ss, kept, got, log = solids.build_solids_parallel(
        rings, ground[src], eaves[src], attic[src], types, u_shape[src], nprocs=nprocs,
        pitch_min=pitch_min, inset=tuple(inset_range), step=tuple(step_range),
        thickness=thickness)
    dropped = len(rings) - len(kept)
    if dropped:
        gs.warning(_("{} footprints gave no valid solid, even flat, and are left out").format(dropped))
    fell = int(np.sum(got != types[kept]))
    if fell:
        gs.warning(_("{} roofs fell back to a simpler type to stay valid").format(fell))

    # CityJSON ---------------------------------------------------------------
    fsrc = src[kept]
    cats = columns.get("cat", list(range(1, n_feat + 1)))
    ids = []
    for j, i in zip(kept, fsrc):
        base = "building_{}".format(cats[i])
        ids.append(base if part[j] < 0 else "{}_{}".format(base, part[j] + 1))

    def column_or_none(name):
        if name and name in columns:
            return [columns[name][i] for i in fsrc]
        return [None] * len(fsrc)

    attributes = {
        "roof_type": list(got),
        "eaves_height": np.round(eaves[fsrc], 3),
        "roof_height": np.round(np.where(got == "flat", 0.0, attic[fsrc]), 3),
        "ground_height": np.round(ground[fsrc], 3),
        "map_year": [map_year] * len(fsrc),
        "plot": column_or_none(options["plot_column"]),
        "source": column_or_none(options["source_column"]),
        "footprint": [cats[i] for i in fsrc],
    }
    semantic = solids.semantics(ss)
    text = cityjson.citymodel_text(ss, semantic, ids, attributes, crs,
                                   title="LoD2 model from <{}>".format(options["input"]))
    tmp = output + ".part"
    try:
        cityjson.write_text(tmp, text)
        os.replace(tmp, output)
    except OSError as error:
        if os.path.exists(tmp):
            os.remove(tmp)
        gs.fatal(_("Cannot write '{}': {}").format(output, error))

    counts = {k: int(np.sum(got == k)) for k in roofs.ROOF_TYPES}
    gs.message(_("{} buildings written to '{}': {}").format(
        len(kept), output, ", ".join("{} {}".format(v, k) for k, v in counts.items() if v)))
    if flags["v"]:
        check = solids.validate(ss)
        valid = sum(r is None for r in check)
        total = len(rings)
        print("solids={}".format(total))
        print("valid={}".format(valid))
        print("percent_valid={:.2f}".format(100.0 * valid / total if total else 100.0))
        print("fallbacks={}".format(len(log)))
        print("dropped={}".format(dropped))
        for k, v in counts.items():
            print("roof_{}={}".format(k, v))
        for i, kind, why in log:
            gs.message(_("Footprint cat {}: {} roof invalid ({}), fell back").format(
                cats[src[i]], kind, why))
        for r in check:
            if r is not None:
                gs.message(_("Invalid solid: {}").format(r))
    return 0


class _Uniform:
    """A stand-in random generator returning pre-drawn uniforms (so the roof
    types do not depend on which footprints are kept)."""

    def __init__(self, values):
        self.values = values

    def random(self, shape):
        return self.values.reshape(shape)


if __name__ == "__main__":
    OPTIONS, FLAGS = gs.parser()
    find_core()
    sys.exit(main())
