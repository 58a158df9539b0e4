#!/bin/bash
# Install the histo suite for the current user with g.extension, from a local
# checkout and with no network: `bash tools/g_extension_install.sh [CHECKOUT]`
# (`make install` runs it). Target: $GRASS_ADDON_BASE, else ~/.grass8/addons
# (GRASS's default).
#
# With HISTO_VENV set (make install sets it to the venv of `make deps`), it also
# tells every later GRASS session of this user to run the modules with that
# venv's python3: ~/.grass8/bashrc gets the venv first on the PATH (GRASS
# reads its `export` lines at start-up, for the shell, --exec and the GUI) and
# GRASS_PYTHON pinned to the python GRASS itself runs with, so that the GUI,
# which starts with $GRASS_PYTHON, keeps Debian's python3 and its wxPython.
set -euo pipefail
checkout="$(cd "${1:-$(dirname "$0")/..}" && pwd)"
addons="${GRASS_ADDON_BASE:-$HOME/.grass8/addons}"
mkdir -p "$addons"
# g.extension 8.2 reads the official addons' path list after building a
# toolbox and downloads it when missing; offline that fails and the suite is
# left half-installed (nothing listed by g.extension -a), so give it an empty
# list to read. An existing list (from an online install) is kept.
[ -e "$addons/addons_paths.json" ] || echo '{"tree": []}' > "$addons/addons_paths.json"

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

if [ -n "${HISTO_VENV:-}" ]; then
  rc="$HOME/.grass8/bashrc"
  grass_python="$(sed -n '1s/^#! *//p' "$(command -v grass)")"
  mkdir -p "$(dirname "$rc")"
  touch "$rc"
  # replace the lines of an earlier install, keep everything else
  begin="# >>> histo: modules run with the packages of $HISTO_VENV"
  end="# <<< histo"
  sed -i '/^# >>> histo:/,/^# <<< histo$/d' "$rc"
  {
    echo "$begin"
    echo "export PATH=$HISTO_VENV/bin:\$PATH"
    echo "export GRASS_PYTHON=${grass_python:-python3}"
    echo "$end"
  } >> "$rc"
  echo "GRASS sessions started from now on run the modules with $HISTO_VENV/bin/python3 (set in $rc)"
fi
