#!/usr/bin/env bash
# pendula quick start.  Installs what is missing, then:
#   ./quickstart.sh run    the main job: example drivers, the text's figures and the
#                          speed/accuracy report, all written to out/ (or $PENDULA_OUT)
#   ./quickstart.sh test   every test: lint and format checks (tools/lint.sh), Fortran
#                          tests (meson test), the consumer
#                          tests of every install route (pkg-config, CMake, meson
#                          subproject, fpm), then pytest on the installed package
#                          (the wheel route included), then the documentation site
#                          with warnings as errors (tools/build_docs.sh)
#   ./quickstart.sh docs   only the documentation site -> docs/_build/html
# Both are idempotent: a second run installs nothing and rebuilds only what changed.
#
# What "install what is missing" means:
#   Debian packages  gfortran, pkg-config, libsundials-dev, libsundials-fortran-dev
#                    (and valgrind and cmake for `test`), via apt-get (root, or sudo);
#   Python           a virtual environment .venv with requirements-dev.txt, and the
#                    pendula package built from this tree with pip (meson-python).
#   SUNDIALS         built once from Debian's source package, optimised, into
#                    .deps/sundials (tools/build_sundials.sh, ~10 s): Debian's packaged
#                    6.4.1 is compiled without optimisation and makes CVODE ~2.7x slower.
#                    If that build fails, the packaged libraries are used (with a warning).
# PENDULA_SUNDIALS=system uses the packaged libraries; PENDULA_SUNDIALS=disabled builds
# without SUNDIALS (CVODE then reports that it was not built and its tests skip).
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
cd "$here"
mode=${1:-}
case "$mode" in
  run|test|docs) ;;
  *) echo "usage: $0 run|test|docs   (run: main job into out/; test: all tests; docs: the site)" >&2; exit 2 ;;
esac
sundials=${PENDULA_SUNDIALS:-enabled}
case "$sundials" in
  enabled|system|disabled) ;;
  *) echo "PENDULA_SUNDIALS must be enabled, system or disabled (got '$sundials')" >&2; exit 2 ;;
esac
venv="$here/.venv"
py="$venv/bin/python"

say() { printf '==> %s\n' "$*"; }

# ---- 1. Debian packages ---------------------------------------------------------
need_pkgs=(gfortran pkg-config)
[ "$sundials" != disabled ] && need_pkgs+=(libsundials-dev libsundials-fortran-dev)
{ [ "$sundials" = enabled ] || [ "$mode" = test ]; } && ! cmake --version >/dev/null 2>&1 && need_pkgs+=(cmake)
[ "$sundials" = enabled ] && ! make --version >/dev/null 2>&1 && need_pkgs+=(make)
[ "$sundials" = enabled ] && ! xz --version >/dev/null 2>&1 && need_pkgs+=(xz-utils)
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
# meson, ninja and fpm (the fpm consumer test) come from the environment
export PATH="$venv/bin:$PATH"
req_hash=$(cat requirements-dev.txt requirements-docs.txt | sha256sum | cut -c1-16)
if [ "$(cat "$venv/.req-hash" 2>/dev/null)" != "$req_hash" ]; then
  say "installing Python requirements (requirements-dev.txt, requirements-docs.txt)"
  "$py" -m pip install -q --upgrade pip
  "$py" -m pip install -q -r requirements-dev.txt -r requirements-docs.txt
  echo "$req_hash" >"$venv/.req-hash"
fi

# ---- 3. SUNDIALS: the optimised build (once) ---------------------------------------
sundials_prefix=""
if [ "$sundials" = enabled ]; then
  if tools/build_sundials.sh "$here/.deps/sundials"; then
    sundials_prefix="$here/.deps/sundials"
  else
    echo "WARNING: the optimised SUNDIALS build failed; using Debian's packaged libraries" \
         "(CVODE about 2.7x slower)" >&2
  fi
fi
meson_sundials=("-Dsundials=$([ "$sundials" = disabled ] && echo disabled || echo enabled)"
                "-Dsundials_prefix=$sundials_prefix")
# Configure a meson build directory, or configure an existing one afresh when
# its options differ from these (recorded beside it; --wipe, because meson
# refuses -D for an option that meson_options.txt gained since the setup).
meson_dir() {
  local dir=$1; shift
  local args="$* ${meson_sundials[*]}"
  if [ ! -f "$dir/build.ninja" ]; then
    meson setup "$dir" "$@" "${meson_sundials[@]}" >/dev/null
  elif [ "$(cat "$dir.pendula-args" 2>/dev/null)" != "$args" ]; then
    meson setup --wipe "$dir" "$@" "${meson_sundials[@]}" >/dev/null
  fi
  echo "$args" >"$dir.pendula-args"
}

# ---- 4. Build and install pendula into .venv (only when the sources changed) ----
src_hash=$( { echo "sundials=$sundials prefix=$sundials_prefix";
              echo "$sundials_prefix"/.pendula-sundials-recipe-*;
              find meson.build meson_options.txt pyproject.toml src python -type f \
                   -not -path '*/__pycache__/*' -print0 | sort -z | xargs -0 sha256sum; } \
            | sha256sum | cut -c1-16)
if [ "$(cat "$venv/.pendula-hash" 2>/dev/null)" != "$src_hash" ]; then
  say "building and installing pendula into .venv (meson-python)"
  # meson-python reconfigures an existing build directory; start it afresh
  # when the SUNDIALS options changed (see meson_dir).
  if [ "$(cat build/pip.pendula-args 2>/dev/null)" != "${meson_sundials[*]}" ]; then
    rm -rf build/pip
  fi
  mkdir -p build
  echo "${meson_sundials[*]}" >build/pip.pendula-args
  "$py" -m pip install -q --no-build-isolation --no-deps \
    -Cbuild-dir="$here/build/pip" -Csetup-args="${meson_sundials[0]}" -Csetup-args="${meson_sundials[1]}" . \
    || { echo "pip install failed; see the output above" >&2; exit 1; }
  echo "$src_hash" >"$venv/.pendula-hash"
fi

# ---- 5. The job ---------------------------------------------------------------------
if [ "$mode" = run ]; then
  out=${PENDULA_OUT:-$here/out}
  say "main job: writing figures, tables and the speed/accuracy report to $out"
  mkdir -p "$out"
  # Fortran example drivers: build and run them, keeping their output.
  meson_dir build/main -Dpython=disabled -Dinstall_fortran=false
  ninja -C build/main >/dev/null
  "$py" tools/run_fortran_examples.py build/main "$out/fortran"
  (cd /tmp && MPLBACKEND=Agg "$py" "$here/examples/python/run_all.py" --out "$out")
  exit 0
fi

# The documentation site (Sphinx -W, FORD), from the package just installed.
build_docs() {
  say "documentation site (warnings are errors) -> docs/_build/html"
  PYTHON="$py" "$here/tools/build_docs.sh"
}
if [ "$mode" = docs ]; then
  build_docs
  exit 0
fi

# mode = test
say "lint and format checks (tools/lint.sh: ruff, fprettify)"
tools/lint.sh
say "Fortran tests (meson test) and the consumer tests of the install routes"
meson_dir build/test -Dpython=disabled
ninja -C build/test >/dev/null
meson test -C build/test --print-errorlogs --num-processes 2 --no-suite consumer
meson test -C build/test --print-errorlogs --suite consumer
# before pytest, so that pytest's summary stays the last line of the run
build_docs
say "pytest on the installed package"
cd /tmp
PENDULA_BUILD_DIR="$here/build/test" MPLBACKEND=Agg "$py" -m pytest -c "$here/pytest.ini" \
  --rootdir "$here" "$here/tests/python" -q
