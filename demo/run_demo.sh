#!/usr/bin/env bash
# make demo: a fresh GRASS location with the synthetic historical map, and
# the chain of histo modules run in it (demo/chain.sh).
#
#   bash demo/run_demo.sh [DIR]      (default DIR: demo-output)
#
# The suite is taken from $HISTO_DIST (default: the checkout's dist/, staged
# by `make build`). Outputs: DIR/grassdata/histo_demo (the location; rebuilt
# on every run) and the files the chain writes into DIR.

set -euo pipefail

HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
ROOT=$(dirname "$HERE")
OUT=${1:-demo-output}
mkdir -p "$OUT"
OUT=$(cd "$OUT" && pwd)
DIST=${HISTO_DIST:-$ROOT/dist}
if [ ! -d "$DIST/scripts" ]; then
    echo "the suite is not built in '$DIST': run 'make build' (or 'make demo') first" >&2
    exit 1
fi

LOCATION=$OUT/grassdata/histo_demo
rm -rf "$LOCATION"
rm -f "$OUT"/generalize.json "$OUT"/align.json "$OUT"/model.city.json "$OUT"/*.png
mkdir -p "$OUT/grassdata"
grass -c EPSG:28992 "$LOCATION" -e > /dev/null 2>&1 || {
    echo "cannot create the GRASS location '$LOCATION'" >&2
    exit 1
}

# the staged suite on the module path, ahead of any installed copy
export GRASS_ADDON_BASE=$DIST
export PATH=$DIST/scripts:$DIST/bin:$PATH
unset GRASS_OVERWRITE GISRC

cd "$ROOT"
grass "$LOCATION/PERMANENT" --exec bash "$HERE/chain.sh" "$OUT"

echo
echo "histo demo done. Outputs:"
echo "  GRASS location: $LOCATION (mapset PERMANENT)"
grass "$LOCATION/PERMANENT" --exec bash -c \
    'echo "    rasters: $(g.list type=raster separator=comma)"; echo "    vectors: $(g.list type=vector separator=comma)"' \
    2> /dev/null
for f in "$OUT"/generalize.json "$OUT"/align.json "$OUT"/model.city.json "$OUT"/*.png; do
    [ -e "$f" ] && echo "  $f"
done
echo "  open it with: grass $LOCATION/PERMANENT"
