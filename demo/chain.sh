#!/usr/bin/env bash
# The histo chain: from a scanned colour city map to an LoD2 CityJSON model.
#
# Run it inside a GRASS session, in a mapset of a projected location in metres
# (here EPSG:28992), e.g. as `make demo` does:
#
#   grass demo-output/grassdata/histo_demo/PERMANENT --exec bash demo/chain.sh demo-output
#
# It uses the project's synthetic historical map (testsuite/synthetic_map.py)
# and today's building footprints over it (map_current, with construction
# years); for a real map, import its red, green and blue bands, your training
# points and current footprints (e.g. the BAG) instead of step 1 and keep the
# rest. A stage whose module is not
# implemented yet in this checkout is skipped with a message.
#
# One sheet of a map series (README, "A map series on actinia"): name the
# series' manifest and the sheet as a second argument,
#
#   grass LOCATION/PERMANENT --exec bash demo/chain.sh OUT series.json:sheet_0_1
#
# (the location in the series' EPSG code). Step 1 then imports the sheet's
# map and the margin of its neighbours' maps, its training points and
# footprints, and sets the region; the sheet's year, seed and the options its
# manifest sets (remove, min_area, ...) replace the parameters below; after
# step 3 the sheet keeps the plots it builds (those whose larger part lies on
# its own area) and writes OUT/model.city.json without pictures. The result is
# byte for byte the model of that sheet's process chain on actinia
# (tools/histo_series.py, demo/series/sheet_chain.json): two descriptions of
# one chain, compared by testsuite/test_series_actinia.py.

set -e

# ---------------------------------------------------------------------------
# Parameters
# ---------------------------------------------------------------------------
OUT=${1:-demo-output}   # folder for the files: report, CityJSON, pictures
SHEET=${2:-}            # MANIFEST:NAME, a sheet of a map series (see above); empty: the synthetic map
SEED=${SEED:-1}          # one seed for everything: the same outputs run to run
SIZE=600                # synthetic map: pixels per side (1 m each)
MAP=map                 # prefix of the map: rasters map.red/.green/.blue, vectors map_*
BUILDING=1              # label of the building class in the training points
REMOVE=2,6              # classes printed over the map (text, symbols): filled from around
MIN_AREA=50             # building plots below this (m²) are specks, not plots: the
                        # classification's minimum mapping unit (the synthetic town over
                        # time has true plots of 98 m², and a thin one of 150 m² that the
                        # classification of its 1915 map shrinks to about 60 m²)
HEIGHT=6.7,17           # eaves height range (m above ground), the thesis's values, without
                        # aligned footprints
ATTIC=2.6,6             # roof height range above the eaves (m), without aligned footprints
STREET_CLASSES=3,4      # classes of the water and the streets in the training points
YEAR=1900               # the map's year: older current buildings may still stand; roof odds
                        # (demo/steps.sh reads ALPHA, DISTANCE, ANGLE of the generalisation
                        # and NPROCS of the classification when they are set, as a sheet's
                        # manifest may set them)

HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
mkdir -p "$OUT"

# implemented, have, and the stage functions *_stage (the same steps as
# demo/delft_1961.sh and demo/brussels_1924.sh)
source "$HERE/steps.sh"
# stage_pictures OUT PREFIX WIDTH
source "$HERE/pictures.sh"

# ---------------------------------------------------------------------------
# 1. The map: RGB rasters, training points, ground-truth points, true plots
#    and today's footprints
# ---------------------------------------------------------------------------
if [ -z "$SHEET" ]; then
    echo "--- synthetic historical map (seed $SEED, $SIZE x $SIZE m)"
    python3 "$HERE/../testsuite/synthetic_map.py" --seed $SEED --size $SIZE --prefix $MAP
    g.region raster=$MAP.red
    truth="gt_points=${MAP}_gt_points gt_polygons=${MAP}_plots"
    pictures=(render="$OUT/model.png" viewer="$OUT/city.html" map=$MAP.red,$MAP.green,$MAP.blue)
else
    # The sheet's files, its neighbours' maps, the region of its chain (its
    # own area and the margin), the query of the plots it owns, its year,
    # seed and options (SHEET_*, YEAR, SEED, REMOVE, ...: from the manifest by
    # reconstruction.series), and the grid of the series' sheets
    echo "--- sheet $SHEET"
    settings=$(python3 "$HERE/../tools/histo_series.py" --sheet-settings "$SHEET" "$OUT/grid.geojson")
    eval "$settings"
    r.in.gdal -o input="$SHEET_MAP" output=sheet
    bands=(sheet)
    for k in "${!SHEET_NEIGHBOURS[@]}"; do
        r.in.gdal -o input="${SHEET_NEIGHBOURS[k]}" output=n$k
        bands+=(n$k)
    done
    g.region w=${SHEET_REGION[0]} s=${SHEET_REGION[1]} e=${SHEET_REGION[2]} \
        n=${SHEET_REGION[3]} align=sheet.1
    band=0
    for colour in red green blue; do  # one band of the sheet and its neighbours in one map
        band=$((band + 1))
        # r.patch, or r.resample for a sheet without neighbours (r.patch needs two maps)
        $SHEET_PATCH input="$(IFS=,; echo "${bands[*]/%/.$band}")" output=$MAP.$colour
    done
    v.in.ogr -o input="$SHEET_TRAINING" output=${MAP}_training
    v.in.ogr -o input="$SHEET_FOOTPRINTS" output=${MAP}_current
    v.in.ogr -o input="$SHEET_GRID" output=sheets
    truth=
    pictures=()
fi

# ---------------------------------------------------------------------------
# 2. Classify the map's pixels from the training points; text and symbols
#    are removed (replaced by the class around them); the synthetic map
#    draws each plot's outline inside the plot (outline=inside), and its
#    scan's red plane lies a cell east of the others (-b registers the bands)
# ---------------------------------------------------------------------------
classify_stage $MAP.red,$MAP.green,$MAP.blue ${MAP}_training ${MAP}_classes \
    remove=$REMOVE min_area=50 min_width=3 separate=$BUILDING outline=inside -b

# ---------------------------------------------------------------------------
# 3. Generalised building plots from the building class, scored against the
#    ground truth (report with precision, recall, F-score, shape metrics);
#    their edges then moved onto the outline strokes the map draws (fit)
# ---------------------------------------------------------------------------
generalize_stage ${MAP}_classes $BUILDING min_area=$MIN_AREA $truth \
    method=alpha,lines,fit map=$MAP.red,$MAP.green,$MAP.blue outline=inside -b

# ---------------------------------------------------------------------------
# 3b. A sheet of a series keeps the plots it builds: those whose larger part
#     lies on its own area (the plots cut by the grid of sheets, their
#     pieces' areas, one query; the others are its neighbours')
# ---------------------------------------------------------------------------
if [ -n "$SHEET" ] && have vector plots; then
    g.rename vector=plots,margin_plots
    v.overlay ainput=margin_plots binput=sheets operator=and output=pieces
    v.to.db map=pieces option=area columns=area
    v.extract input=margin_plots where="$SHEET_OWNER" output=plots
fi

# ---------------------------------------------------------------------------
# 4. Today's footprints that already stood at the map's date, each matched
#    with its plot
# ---------------------------------------------------------------------------
align_stage ${MAP}_current $YEAR

# ---------------------------------------------------------------------------
# 5. Building footprints inside the plots: the aligned ones as they are, the
#    rest by procedural subdivision
# ---------------------------------------------------------------------------
subdivide_stage

# ---------------------------------------------------------------------------
# 6. LoD2 buildings with roofs, written as CityJSON, and a picture of them
#    over the map (model.png, rendered off-screen). Heights: the aligned
#    footprints' measured ones (today's 3D BAG attributes), the others'
#    inferred from them (the robust neighbourhood rule, the plots for the
#    thesis's fallback); without aligned footprints, drawn from the ranges.
#    Gable ends and stepped facades go on the street edge, found with the
#    classified map's streets and water. city.html shows the model in a web
#    browser, offline (orbit, click a house, search by id).
# ---------------------------------------------------------------------------
lod2_stage $HEIGHT $ATTIC ${MAP}_classes $STREET_CLASSES year=$YEAR "${pictures[@]}"

# ---------------------------------------------------------------------------
# Pictures: one per stage, $SIZE pixels wide (demo/pictures.sh; model.png is
# v.histo.lod2's above)
# ---------------------------------------------------------------------------
if [ -z "$SHEET" ]; then
    stage_pictures "$OUT" $MAP $SIZE
fi
echo "--- chain done in ${SECONDS} s"
