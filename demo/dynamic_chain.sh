#!/usr/bin/env bash
# The dynamic chain: one town drawn on three map sheets (1880, 1915, 1961) into
# one city over time. Each epoch runs the chain of demo/chain.sh; from the
# second on, v.histo.subdivide and v.histo.lod2 get the earlier epoch
# (previous=): a block the maps show unchanged keeps its buildings.
#
# Run it inside a GRASS session, in a mapset of an EPSG:28992 location:
#
#   grass --tmp-location EPSG:28992 --exec bash demo/dynamic_chain.sh demo-output/dynamic
#
# It uses the suite's synthetic town over time (testsuite/synthetic_epochs.py),
# whose true history it writes beside the models (OUT/truth.json).

set -e

OUT=${1:-demo-output/dynamic}
SEED=${SEED:-1}
SIZE=${SIZE:-600}
YEARS=${YEARS:-1880,1915,1961}
TOWN=town
HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
mkdir -p "$OUT"
OUT=$(cd "$OUT" && pwd)

echo "--- synthetic town over time (seed $SEED, $SIZE x $SIZE m, $YEARS)"
python3 "$HERE/../testsuite/synthetic_epochs.py" --seed $SEED --size $SIZE --years $YEARS \
    --prefix $TOWN --truth "$OUT/truth.json"

previous=
for year in ${YEARS//,/ }; do
    echo "--- epoch $year (at ${SECONDS} s)"
    g.region raster=${TOWN}_$year.red
    r.histo.classify input=${TOWN}_$year.red,${TOWN}_$year.green,${TOWN}_$year.blue \
        training=${TOWN}_${year}_training output=classes_$year remove=2,6 min_area=50 \
        min_width=3 separate=1 outline=inside nprocs=2 seed=$SEED --quiet
    # min_area as demo/chain.sh's MIN_AREA: the classification's minimum mapping unit;
    # the edges fitted to the outline strokes the map draws inside its plots
    v.histo.generalize raster=classes_$year class=1 output=plots_$year alpha=12 distance=5 tolerance=1 \
        angle=180 min_area=50 method=alpha,lines,fit \
        map=${TOWN}_$year.red,${TOWN}_$year.green,${TOWN}_$year.blue outline=inside --quiet
    v.histo.align input=plots_$year footprints=${TOWN}_current year=$year \
        output=aligned_$year unmatched=unmatched_$year --quiet
    earlier=
    if [ -n "$previous" ]; then
        # tolerance: the buffered lines (distance 5) may draw one unchanged row's end up
        # to their distance apart on two maps (a row end 4.03 m apart in 1880 and 1915)
        earlier="previous=footprints_$previous previous_plots=plots_$previous tolerance=5"
    fi
    v.histo.subdivide input=plots_$year aligned=aligned_$year output=footprints_$year \
        year=$year seed=$SEED $earlier
    earlier=
    if [ -n "$previous" ]; then earlier="previous=$OUT/model_$previous.city.json"; fi
    v.histo.lod2 input=footprints_$year output="$OUT/model_$year.city.json" \
        aligned=aligned_$year plots=plots_$year year=$year seed=$SEED $earlier
    previous=$year
done
echo "--- dynamic chain done in ${SECONDS} s"
