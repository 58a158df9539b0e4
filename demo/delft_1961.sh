#!/usr/bin/env bash
# The complete histo chain on the real Delft 1961 subset (the thesis's worked
# example, its Table B.3 parameters), from the scanned map to an LoD2 CityJSON
# model and a picture of it, with one report (JSON and a text table) of every
# figure issue 18 accepts the chain by, ours and the thesis's beside.
#
# Run it inside a GRASS session in a fresh mapset of an EPSG:28992 location,
# with the suite on the module path (as run_demo.sh sets it up), e.g.:
#
#   grass -c EPSG:28992 /tmp/grassdata/delft -e
#   grass /tmp/grassdata/delft/PERMANENT --exec bash demo/delft_1961.sh OUT ../shared/data
#
# OUT (default delft-output) gets: report.json and report.txt (demo/
# delft_report.py: each stage's figures and wall time), times.txt,
# import.json, generalize.json, generalize_metrics.csv, align.json, lod2.txt,
# model.city.json, model.png, city.html. Those are derived from the shared data: keep
# them out of the repository. DATA (default ../shared/data) is the shared data
# folder; the CityJSON schemas are read from DATA/../schemas.

set -e

OUT=${1:-delft-output}
DATA=${2:-../shared/data}
SEED=1
YEAR=1961               # the map's year
REMOVE=2,6              # text and symbols, printed over the map
BUILDING=1              # building class in the training points
STREET_CLASSES=3,4      # water and streets in the training points

HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
# implemented, have, timed and the stage functions *_stage (the same steps as demo/chain.sh)
source "$HERE/steps.sh"
start_run               # OUT made absolute, its times.txt (TIMES) emptied

echo "--- import of $DATA/delft_1961_subset"
timed "$TIMES" import python3 "$HERE/delft_import.py" "$DATA" "$OUT/import.json"
g.region raster=delft.red

classify_stage delft.red,delft.green,delft.blue delft_training delft_classes remove=$REMOVE \
    separate=$BUILDING
# the thesis's minimum area, in m² (the module's default follows the cell size)
generalize_stage delft_classes $BUILDING min_area=20 gt_points=delft_gt_points \
    gt_polygons=delft_gt_polygons
align_stage current $YEAR buffer=10 overlap=0.6
subdivide_stage length=5,5 depth=12,16 area_threshold=100
# the ranges are not used: the heights come from the aligned footprints
lod2_stage 6.7,17 2.6,6 delft_classes $STREET_CLASSES year=$YEAR crs=7415 \
    render="$OUT/model.png" viewer="$OUT/city.html" map=delft.red,delft.green,delft.blue

python3 "$HERE/delft_report.py" "$OUT" "$DATA"
echo "--- chain done in ${SECONDS} s; report: $OUT/report.json, $OUT/report.txt"
