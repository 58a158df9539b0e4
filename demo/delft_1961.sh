#!/usr/bin/env bash
# The complete histo chain on the real Delft 1961 subset (the thesis's worked
# example, its Table B.3 parameters), from the scanned map to an LoD2 CityJSON
# model and a picture of it, with one JSON report of every stage.
#
# Run it inside a GRASS session in a fresh mapset of an EPSG:28992 location,
# with the suite on the module path (as run_demo.sh sets it up), e.g.:
#
#   grass -c EPSG:28992 /tmp/grassdata/delft -e
#   grass /tmp/grassdata/delft/PERMANENT --exec bash demo/delft_1961.sh OUT ../shared/data
#
# OUT (default delft-output) gets: report.json (each stage's figures and wall
# time), generalize.json, generalize_metrics.csv, align.json, lod2.txt,
# model.city.json, model.png. Those are derived from the shared data: keep
# them out of the repository.

set -e

OUT=${1:-delft-output}
DATA=${2:-../shared/data}
SEED=1
YEAR=1961               # the map's year
REMOVE=2,6              # text and symbols, printed over the map
BUILDING=1              # building class in the training points
STREET_CLASSES=3,4      # water and streets in the training points

HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
mkdir -p "$OUT"
OUT=$(cd "$OUT" && pwd)
TIMES=$OUT/times.txt
: > "$TIMES"
# implemented MODULE, have TYPE NAME, timed FILE STAGE COMMAND...
source "$HERE/steps.sh"

echo "--- import of $DATA/delft_1961_subset"
timed "$TIMES" import python3 "$HERE/delft_import.py" "$DATA"
g.region raster=delft.red

implemented r.histo.classify
timed "$TIMES" classify r.histo.classify input=delft.red,delft.green,delft.blue \
    training=delft_training output=delft_classes remove=$REMOVE nprocs=2 seed=$SEED

implemented v.histo.generalize
timed "$TIMES" generalize v.histo.generalize raster=delft_classes class=$BUILDING output=plots \
    alpha=12 distance=5 angle=180 metrics="$OUT/generalize_metrics.csv" \
    gt_points=delft_gt_points gt_polygons=delft_gt_polygons report="$OUT/generalize.json"

implemented v.histo.align
timed "$TIMES" align v.histo.align input=plots footprints=current year=$YEAR buffer=10 \
    overlap=0.6 output=aligned unmatched=unmatched report="$OUT/align.json"

implemented v.histo.subdivide
timed "$TIMES" subdivide v.histo.subdivide input=plots aligned=aligned output=footprints \
    length=5,5 depth=12,16 area_threshold=100 seed=$SEED

implemented v.histo.lod2
timed "$TIMES" lod2 v.histo.lod2 -v input=footprints output="$OUT/model.city.json" \
    aligned=aligned plots=plots streets=delft_classes street_classes=$STREET_CLASSES \
    year=$YEAR seed=$SEED crs=7415 render="$OUT/model.png" map=delft.red,delft.green,delft.blue \
    > "$OUT/lod2.txt"
cat "$OUT/lod2.txt"

python3 "$HERE/delft_report.py" "$OUT"
echo "--- chain done in ${SECONDS} s; report: $OUT/report.json"
