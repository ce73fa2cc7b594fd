#!/usr/bin/env bash
# Rewrite docs/_generated/*.md, the tables of the accuracy and performance pages, by running
# every benchmarks/bench_*.py (speed) and benchmarks/accuracy_*.py (error vs the tests' references) with --out
# (quick mode unless --full is given) and keeping the Markdown tables they write (their CSV
# files and plots stay in a scratch folder).
#   tools/refresh_docs_tables.sh [--full]      (python: $PYTHON, else python3 on PATH)
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
py=${PYTHON:-python3}
quick=--quick
[ "${1:-}" = --full ] && quick=
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
for b in "$here"/benchmarks/bench_*.py "$here"/benchmarks/accuracy_*.py; do
  echo "==> $(basename "$b") $quick"
  (cd "$scratch" && MPLBACKEND=Agg "$py" "$b" $quick --out "$scratch/out" >/dev/null)
done
mkdir -p "$here/docs/_generated"
cp "$scratch"/out/*.md "$here/docs/_generated/"
ls "$here/docs/_generated"
