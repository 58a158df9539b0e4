#!/usr/bin/env bash
# The shortened histo chain on Brussels 1924 (issue 18): the map's raster did
# not survive, so the chain starts from the thesis's 616 final building plots
# (../shared/data/bxls_1924/thesis_output/final_plots_bxls_1924) and runs
# v.histo.subdivide and v.histo.lod2 with the thesis's parameters for this map
# (facade length 8-15, depth 23-30, area threshold 300; eaves height
# 6.7-17 m, attic 2.6-6 m), with the same stage functions as demo/chain.sh and
# demo/delft_1961.sh (demo/steps.sh).
#
# The plots are in EPSG:3857 (Web Mercator: metric, but stretched by about
# 1.6 at Brussels' latitude), as the thesis used them and its parameters are
# in these map units: run it in a fresh mapset of an EPSG:3857 location, with
# the suite on the module path, e.g.:
#
#   grass -c EPSG:3857 /tmp/grassdata/brussels -e
#   grass /tmp/grassdata/brussels/PERMANENT --exec bash demo/brussels_1924.sh OUT ../shared/data
#
# No 3D reference system for Belgium fits these coordinates (EPSG:3857 has no
# vertical part; a Belgian one, e.g. Lambert 72 + Ostend heights, would need
# the plots reprojected and the parameters converted), so the CityJSON keeps
# v.histo.lod2's default crs, the location's EPSG:3857.
#
# OUT (default brussels-output) gets: report.json and report.txt (demo/
# brussels_report.py), times.txt, lod2.txt, model.city.json, model.png, city.html.
# Derived from the shared data: keep them out of the repository.

set -e

OUT=${1:-brussels-output}
DATA=${2:-../shared/data}
SEED=1
YEAR=1924               # the map's year (roof odds)

HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
# implemented, have, timed and the stage functions *_stage (the same steps as demo/chain.sh)
source "$HERE/steps.sh"
start_run               # OUT made absolute, its times.txt (TIMES) emptied

echo "--- import of $DATA/bxls_1924: the thesis's final plots"
timed "$TIMES" import v.in.ogr -o input="$DATA/bxls_1924/thesis_output/final_plots_bxls_1924.shp" \
    output=plots --quiet
g.region vector=plots

subdivide_stage length=8,15 depth=23,30 area_threshold=300
lod2_stage 6.7,17 2.6,6 - - year=$YEAR render="$OUT/model.png" viewer="$OUT/city.html"

python3 "$HERE/brussels_report.py" "$OUT" "$DATA"
echo "--- chain done in ${SECONDS} s; report: $OUT/report.json, $OUT/report.txt"
