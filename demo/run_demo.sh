#!/usr/bin/env bash
# make demo: a fresh GRASS location with the synthetic historical map, and
# the chain of histo modules run in it (demo/chain.sh).
#
#   bash demo/run_demo.sh [DIR]      (default DIR: demo-output)
#
# The suite is taken from $HISTO_DIST (default: the checkout's dist/, staged
# by `make build`); `python3` must be the one with the suite's packages (make
# demo puts the checkout's .venv first on the PATH). Outputs: DIR/grassdata/
# histo_demo (the location) and the files the chain writes into DIR.
#
# A run builds everything in DIR/.demo-next first and only then replaces the
# previous run's outputs, one by one; when it fails, the previous outputs
# are left as they were.

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

# What a run leaves in DIR, besides the location.
FILES="generalize.json generalize_metrics.csv align.json model.city.json city.html model.png map.png classes.png plots.png aligned.png footprints.png"

NEXT=$OUT/.demo-next
rm -rf "$NEXT"
trap 'rm -rf "$NEXT"' EXIT
fail() {
    echo "$1" >&2
    echo "the previous outputs in '$OUT' are left as they were" >&2
    exit 1
}

mkdir -p "$NEXT/grassdata"
grass -c EPSG:28992 "$NEXT/grassdata/histo_demo" -e > /dev/null 2>&1 \
    || fail "cannot create a GRASS location in '$NEXT/grassdata'"

# the staged suite on the module path, ahead of any installed copy
export GRASS_ADDON_BASE=$DIST
export PATH=$DIST/scripts:$DIST/bin:$PATH
unset GRASS_OVERWRITE GISRC

cd "$ROOT"
grass "$NEXT/grassdata/histo_demo/PERMANENT" --exec bash "$HERE/chain.sh" "$NEXT" \
    || fail "the demo chain failed"

# Complete: the new outputs replace the previous ones (a file the new run did
# not make, e.g. of a stage skipped this time, goes too).
LOCATION=$OUT/grassdata/histo_demo
mkdir -p "$OUT/grassdata"
rm -rf "$LOCATION"
mv "$NEXT/grassdata/histo_demo" "$LOCATION"
for f in $FILES; do
    if [ -e "$NEXT/$f" ]; then mv -f "$NEXT/$f" "$OUT/$f"; else rm -f "$OUT/$f"; fi
done

echo
echo "histo demo done. Outputs:"
echo "  GRASS location: $LOCATION (mapset PERMANENT)"
grass "$LOCATION/PERMANENT" --exec bash -c \
    'echo "    rasters: $(g.list type=raster separator=comma)"; echo "    vectors: $(g.list type=vector separator=comma)"' \
    2> /dev/null
for f in $FILES; do
    if [ -e "$OUT/$f" ]; then echo "  $OUT/$f"; fi
done
echo "  open it with: grass $LOCATION/PERMANENT"
