#!/usr/bin/env bash
# Lint and format checks of the whole tree: ruff (lint + format, configured in
# pyproject.toml) on the Python, fprettify on the Fortran.
#
#   tools/lint.sh          check only: exit 1 when something would change or a lint rule fails
#   tools/lint.sh --fix    apply: ruff's safe fixes, ruff format, fprettify in place
#
# Run from anywhere; tools come from PATH or the repository's .venv.
# (docs/contributing.md says which rules and why.)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"

fix=0
case "${1:-}" in
  --fix) fix=1 ;;
  "") ;;
  -h|--help) sed -n '2,9p' "$0"; exit 0 ;;
  *) echo "usage: tools/lint.sh [--fix]" >&2; exit 2 ;;
esac

tool() {   # the tool from PATH, else from .venv/bin
  if command -v "$1" >/dev/null 2>&1; then command -v "$1"
  elif [ -x "$root/.venv/bin/$1" ]; then echo "$root/.venv/bin/$1"
  else echo "tools/lint.sh: $1 is not installed (pip install -r requirements-dev.txt)" >&2; exit 2
  fi
}
ruff="$(tool ruff)"
fprettify="$(tool fprettify)"

# The Fortran style: 2-space indents; fprettify changes whitespace only (no case
# changes, no operator replacements) and leaves a line alone that would exceed
# 132 characters (gfortran's free-form limit) once indented.
fortran_dirs=(src tests/fortran examples/fortran python/f2py)
fprettify_opts=(--indent 2 --line-length 132 --whitespace 2 --silent)
fortran_files() {
  git ls-files -- "${fortran_dirs[@]}" | grep -E '\.(f90|F90)$' || true   # not the .inc fragments: no context
}

status=0
if [ "$fix" = 1 ]; then
  "$ruff" check --fix --quiet . || status=1     # what cannot be fixed automatically is still reported
  "$ruff" format --quiet .
  fortran_files | xargs -r "$fprettify" "${fprettify_opts[@]}"
else
  "$ruff" check --quiet . || status=1
  "$ruff" format --check --quiet . || { echo "tools/lint.sh: ruff format would reformat the files above (tools/lint.sh --fix)" >&2; status=1; }
  diff="$(fortran_files | xargs -r "$fprettify" "${fprettify_opts[@]}" --diff)"
  if [ -n "$diff" ]; then
    printf '%s\n' "$diff"
    echo "tools/lint.sh: fprettify would reformat the Fortran above (tools/lint.sh --fix)" >&2
    status=1
  fi
fi
exit $status
