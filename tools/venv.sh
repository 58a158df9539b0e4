#!/bin/bash
# Make or bring up to date the virtual environment with the suite's pinned
# Python packages: `bash tools/venv.sh VENV PYTHON` (`make deps` runs it).
#
# VENV is made from PYTHON (Debian's /usr/bin/python3, the interpreter GRASS
# runs with) when it does not exist yet, with access to that Python's Debian
# packages: GRASS's own tools run with the first python3 on the PATH too
# (its manual-page builder, run by g.extension, needs python3-six), and so
# may a user's other addons. It gets the packages of requirements.txt with
# the versions of constraints.txt, which take precedence over Debian's,
# whenever these two files differ from the ones it was last brought up to
# date with. GRASS's own Python library is not installed in it: a GRASS
# session puts it on PYTHONPATH. Several checkouts may share one VENV: they
# take turns (flock).
set -euo pipefail
venv="$1"
python="$2"
root="$(cd "$(dirname "$0")/.." && pwd)"
mkdir -p "$(dirname "$venv")"
exec 9> "$venv.lock"
flock 9
if [ ! -x "$venv/bin/python3" ] \
    || ! grep -q '^include-system-site-packages = true' "$venv/pyvenv.cfg" 2>/dev/null; then
  echo "making the virtual environment $venv (from $python)"
  rm -rf "$venv"
  "$python" -m venv --system-site-packages "$venv" || { rm -rf "$venv"; exit 1; }
fi
wanted="$(cat "$root/requirements.txt" "$root/constraints.txt")"
if [ "$(cat "$venv/.histo-requirements" 2>/dev/null)" != "$wanted" ]; then
  count() { grep -c '^[A-Za-z0-9]' "$1"; }
  echo "installing the $(count "$root/requirements.txt") Python packages of requirements.txt" \
    "($(count "$root/constraints.txt") more pinned by constraints.txt for their dependencies)" \
    "into $venv: about 1.1 GB once installed (vtk half of it), a few minutes the first time"
  rm -f "$venv/.histo-requirements"
  # pip's own progress (a line per package, download bars) on a terminal; in
  # a log (CI) only these lines and pip's errors
  quiet=-q
  if [ -t 1 ]; then quiet=; fi
  "$venv/bin/python3" -m pip install $quiet --disable-pip-version-check \
    -r "$root/requirements.txt" -c "$root/constraints.txt"
  printf '%s\n' "$wanted" > "$venv/.histo-requirements"
  echo "installed: $venv holds $(du -sh "$venv" | cut -f1)"
fi
