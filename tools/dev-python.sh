#!/usr/bin/env bash
# Developer helper: build pendula in BUILD_DIR (default: build/dev) and stage the
# Python package there, without pip.  Prints the directory to put on PYTHONPATH:
#   PYTHONPATH=$(tools/dev-python.sh build/dev) python -m pytest tests/python
# Extra arguments go to `meson setup` on first configuration.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
bdir=${1:-build/dev}
shift || true
case "$bdir" in /*) ;; *) bdir="$here/$bdir" ;; esac
mkdir -p "$(dirname "$bdir")"
if [ ! -f "$bdir/build.ninja" ]; then
  meson setup "$bdir" "$here" -Dpython=enabled "$@" >"$bdir.setup.log" 2>&1 || { cat "$bdir.setup.log" >&2; exit 1; }
fi
ninja -C "$bdir" >"$bdir.ninja.log" 2>&1 || { grep -v '^\[' "$bdir.ninja.log" | tail -40 >&2; exit 1; }
stage="$bdir/stage"
rm -rf "$stage"
meson install -C "$bdir" --destdir "$stage" --tags python-runtime --quiet >/dev/null 2>&1 \
  || { echo "dev-python.sh: meson install failed" >&2; exit 1; }
init=$(find "$stage" -path '*/pendula/__init__.py' | head -n 1)
dirname "$(dirname "$init")"
