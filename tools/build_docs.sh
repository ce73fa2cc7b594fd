#!/usr/bin/env bash
# Build the documentation site into docs/_build/html: the Sphinx site (guides, methods,
# accuracy and performance pages, the Python API from the docstrings, the example gallery)
# with the FORD Fortran API under fortran/.  Warnings are errors (Sphinx -W --keep-going;
# FORD's warnings are turned into a failure here).
#   tools/build_docs.sh            build (needs pendula importable and requirements-docs.txt)
#   PENDULA_DOCS_GALLERY=skip ...  skip running the examples (no gallery pages)
# The python used is $PYTHON, else the one on PATH.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
py=${PYTHON:-python3}
out="$here/docs/_build/html"
log=$(mktemp)
trap 'rm -f "$log"' EXIT

start=$(date +%s)
"$py" -m sphinx -E -W --keep-going -q -b html "$here/docs" "$out"

# FORD writes into docs/_build/html/fortran (output_dir of docs/fortran/pendula.md).
ford_bin=$(dirname "$("$py" -c 'import sys; print(sys.executable)')")/ford
[ -x "$ford_bin" ] || ford_bin=ford
(cd "$here/docs/fortran" && "$ford_bin" pendula.md) >"$log" 2>&1 || { cat "$log" >&2; exit 1; }
if grep -i -E "warning|error" "$log" >&2; then
  echo "FORD reported warnings (above): failing the docs build" >&2
  exit 1
fi
test -f "$out/fortran/index.html"
echo "docs built into $out in $(( $(date +%s) - start )) s"
