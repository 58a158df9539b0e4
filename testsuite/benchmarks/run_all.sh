#!/bin/bash
# Run every benchmark (testsuite/benchmarks/bench_*.py) in a temporary GRASS
# location (EPSG:28992) with the suite staged in dist/. `make bench` calls it.
# Benchmarks print their figures (medians of several runs); they are never
# part of `make test`.
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
dist="${HISTO_DIST:-$root/dist}"
export GRASS_ADDON_BASE="$dist"
export PATH="$dist/scripts:$PATH"
export PYTHONPATH="$root:${PYTHONPATH:-}"
status=0
for bench in "$root"/testsuite/benchmarks/bench_*.py; do
  echo "== $(basename "$bench")"
  grass --tmp-location EPSG:28992 --exec python3 "$bench" "$@" || status=1
done
exit $status
