#!/usr/bin/env bash
# pendula quick start.  Installs what is missing, then:
#   ./quickstart.sh run    the main job: example drivers, the text's figures and the
#                          speed/accuracy report, all written to out/ (or $PENDULA_OUT)
#   ./quickstart.sh test   every test: Fortran tests (meson test), the pkg-config
#                          consumer test, then pytest on the installed package
# Both are idempotent: a second run installs nothing and rebuilds only what changed.
#
# What "install what is missing" means:
#   Debian packages  gfortran, pkg-config, libsundials-dev, libsundials-fortran-dev
#                    (and valgrind for `test`), via apt-get (root, or sudo);
#   Python           a virtual environment .venv with requirements-dev.txt, and the
#                    pendula package built from this tree with pip (meson-python).
# Set PENDULA_SUNDIALS=disabled to build without SUNDIALS (CVODE then reports that it
# was not built and its tests skip).
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
cd "$here"
mode=${1:-}
case "$mode" in
  run|test) ;;
  *) echo "usage: $0 run|test   (run: main job into out/; test: all tests)" >&2; exit 2 ;;
esac
sundials=${PENDULA_SUNDIALS:-enabled}
venv="$here/.venv"
py="$venv/bin/python"

say() { printf '==> %s\n' "$*"; }

# ---- 1. Debian packages ---------------------------------------------------------
need_pkgs=(gfortran pkg-config)
[ "$sundials" != disabled ] && need_pkgs+=(libsundials-dev libsundials-fortran-dev)
[ "$mode" = test ] && need_pkgs+=(valgrind)
missing=()
for p in "${need_pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  say "installing Debian packages: ${missing[*]}"
  sudo=""
  [ "$(id -u)" -ne 0 ] && sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

# ---- 2. Python environment --------------------------------------------------------
if [ ! -x "$py" ]; then
  say "creating virtual environment .venv"
  python3 -m venv "$venv"
fi
req_hash=$(sha256sum requirements-dev.txt | cut -c1-16)
if [ "$(cat "$venv/.req-hash" 2>/dev/null)" != "$req_hash" ]; then
  say "installing Python requirements (requirements-dev.txt)"
  "$py" -m pip install -q --upgrade pip
  "$py" -m pip install -q -r requirements-dev.txt
  echo "$req_hash" >"$venv/.req-hash"
fi

# ---- 3. Build and install pendula into .venv (only when the sources changed) ----
src_hash=$( { echo "sundials=$sundials";
              find meson.build meson_options.txt pyproject.toml src python -type f \
                   -not -path '*/__pycache__/*' -print0 | sort -z | xargs -0 sha256sum; } \
            | sha256sum | cut -c1-16)
if [ "$(cat "$venv/.pendula-hash" 2>/dev/null)" != "$src_hash" ]; then
  say "building and installing pendula into .venv (meson-python)"
  "$py" -m pip install -q --no-build-isolation --no-deps \
    -Cbuild-dir="$here/build/pip" -Csetup-args="-Dsundials=$sundials" . \
    || { echo "pip install failed; see the output above" >&2; exit 1; }
  echo "$src_hash" >"$venv/.pendula-hash"
fi

# ---- 4. The job ---------------------------------------------------------------------
if [ "$mode" = run ]; then
  out=${PENDULA_OUT:-$here/out}
  say "main job: writing figures, tables and the speed/accuracy report to $out"
  mkdir -p "$out"
  # Fortran example drivers: build and run them, keeping their output.
  if [ ! -f build/main/build.ninja ]; then
    meson setup build/main -Dpython=disabled -Dinstall_fortran=false -Dsundials="$sundials" >/dev/null
  fi
  ninja -C build/main >/dev/null
  "$py" tools/run_fortran_examples.py build/main "$out/fortran"
  (cd /tmp && MPLBACKEND=Agg "$py" "$here/examples/python/run_all.py" --out "$out")
  exit 0
fi

# mode = test
say "Fortran tests (meson test)"
if [ ! -f build/test/build.ninja ]; then
  meson setup build/test -Dpython=disabled -Dsundials="$sundials" >/dev/null
fi
ninja -C build/test >/dev/null
meson test -C build/test --print-errorlogs --num-processes 2
say "pytest on the installed package"
cd /tmp
PENDULA_BUILD_DIR="$here/build/test" MPLBACKEND=Agg "$py" -m pytest -c "$here/pytest.ini" \
  --rootdir "$here" "$here/tests/python" -q
