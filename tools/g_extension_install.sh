#!/bin/bash
# Install the histo suite for the current user with g.extension, from a local
# checkout and with no network: `bash tools/g_extension_install.sh [CHECKOUT]`.
# Target: $GRASS_ADDON_BASE, else ~/.grass8/addons (GRASS's default).
set -euo pipefail
checkout="$(cd "${1:-$(dirname "$0")/..}" && pwd)"
addons="${GRASS_ADDON_BASE:-$HOME/.grass8/addons}"
mkdir -p "$addons"
# g.extension 8.2 downloads the addons' path list after installing a toolbox;
# offline that fails, so give it an empty list to read.
[ -f "$addons/addons_paths.json" ] || echo '{"tree": []}' > "$addons/addons_paths.json"

# g.extension needs a GRASS session: use a throwaway XY location when not in one.
if [ -n "${GISRC:-}" ]; then
  GRASS_ADDON_BASE="$addons" g.extension extension=histo url="$checkout"
else
  tmp="$(mktemp -d)"
  trap 'rm -rf "$tmp"' EXIT
  grass -c XY "$tmp/xy" -e
  GRASS_ADDON_BASE="$addons" grass "$tmp/xy/PERMANENT" --exec g.extension extension=histo url="$checkout"
fi
echo "histo installed into $addons (modules in $addons/scripts, manuals in $addons/docs/html)"
