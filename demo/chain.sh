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

set -e

# ---------------------------------------------------------------------------
# Parameters
# ---------------------------------------------------------------------------
OUT=${1:-demo-output}   # folder for the files: report, CityJSON, pictures
SEED=1                  # one seed for everything: the same outputs run to run
SIZE=600                # synthetic map: pixels per side (1 m each)
MAP=map                 # prefix of the map: rasters map.red/.green/.blue, vectors map_*
BUILDING=1              # label of the building class in the training points
REMOVE=2,6              # classes printed over the map (text, symbols): filled from around
MIN_AREA=100            # building plots below this (m²) are specks, not plots
HEIGHT=6.7,17           # eaves height range (m above ground), the thesis's values, without
                        # aligned footprints
ATTIC=2.6,6             # roof height range above the eaves (m), without aligned footprints
STREET_CLASSES=3,4      # classes of the water and the streets in the training points
YEAR=1900               # the map's year: older current buildings may still stand; roof odds

HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
mkdir -p "$OUT"

# implemented MODULE, have TYPE NAME
source "$HERE/steps.sh"
# stage_pictures OUT PREFIX WIDTH
source "$HERE/pictures.sh"

# ---------------------------------------------------------------------------
# 1. The map: RGB rasters, training points, ground-truth points, true plots
#    and today's footprints
# ---------------------------------------------------------------------------
echo "--- synthetic historical map (seed $SEED, $SIZE x $SIZE m)"
python3 "$HERE/../testsuite/synthetic_map.py" --seed $SEED --size $SIZE --prefix $MAP
g.region raster=$MAP.red

# ---------------------------------------------------------------------------
# 2. Classify the map's pixels from the training points; text and symbols
#    are removed (replaced by the class around them)
# ---------------------------------------------------------------------------
if implemented r.histo.classify; then
    r.histo.classify input=$MAP.red,$MAP.green,$MAP.blue training=${MAP}_training \
        output=${MAP}_classes remove=$REMOVE min_area=50 min_width=3 separate=$BUILDING \
        nprocs=2 seed=$SEED
fi

# ---------------------------------------------------------------------------
# 3. Generalised building plots from the building class, scored against the
#    ground truth (report with precision, recall, F-score, shape metrics)
# ---------------------------------------------------------------------------
if have raster ${MAP}_classes && implemented v.histo.generalize; then
    v.histo.generalize raster=${MAP}_classes class=$BUILDING output=plots min_area=$MIN_AREA \
        alpha=12 distance=5 angle=180 metrics="$OUT/generalize_metrics.csv" \
        gt_points=${MAP}_gt_points gt_polygons=${MAP}_plots report="$OUT/generalize.json"
fi

# ---------------------------------------------------------------------------
# 4. Today's footprints that already stood at the map's date, each matched
#    with its plot
# ---------------------------------------------------------------------------
if have vector plots && have vector ${MAP}_current && implemented v.histo.align; then
    v.histo.align input=plots footprints=${MAP}_current year=$YEAR output=aligned \
        unmatched=unmatched report="$OUT/align.json"
fi

# ---------------------------------------------------------------------------
# 5. Building footprints inside the plots: the aligned ones as they are, the
#    rest by procedural subdivision
# ---------------------------------------------------------------------------
if have vector plots && implemented v.histo.subdivide; then
    ALIGNED=
    if [ -n "$(g.list type=vector pattern=aligned)" ]; then ALIGNED=aligned=aligned; fi
    v.histo.subdivide input=plots output=footprints seed=$SEED $ALIGNED
fi

# ---------------------------------------------------------------------------
# 6. LoD2 buildings with roofs, written as CityJSON, and a picture of them
#    over the map (model.png, rendered off-screen). Heights: the aligned
#    footprints' measured ones (today's 3D BAG attributes), the others'
#    inferred from them (the robust neighbourhood rule, the plots for the
#    thesis's fallback); without aligned footprints, drawn from the ranges.
#    Gable ends and stepped facades go on the street edge, found with the
#    classified map's streets and water.
# ---------------------------------------------------------------------------
if have vector footprints && implemented v.histo.lod2; then
    HEIGHTS="height=$HEIGHT attic=$ATTIC"
    if [ -n "$(g.list type=vector pattern=aligned)" ]; then
        HEIGHTS="aligned=aligned plots=plots"
    fi
    STREETS=
    if [ -n "$(g.list type=raster pattern=${MAP}_classes)" ]; then
        STREETS="streets=${MAP}_classes street_classes=$STREET_CLASSES"
    fi
    v.histo.lod2 -v input=footprints output="$OUT/model.city.json" $HEIGHTS $STREETS \
        year=$YEAR seed=$SEED render="$OUT/model.png" map=$MAP.red,$MAP.green,$MAP.blue
fi

# ---------------------------------------------------------------------------
# Pictures: one per stage, $SIZE pixels wide (demo/pictures.sh; model.png is
# v.histo.lod2's above)
# ---------------------------------------------------------------------------
stage_pictures "$OUT" $MAP $SIZE
echo "--- chain done in ${SECONDS} s"
