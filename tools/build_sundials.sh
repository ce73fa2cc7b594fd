#!/usr/bin/env bash
# Build SUNDIALS 6.4 (CVODE, the serial vector, the dense matrix and linear
# solver, and their Fortran 2003 modules) optimised (-O3), as static PIC
# libraries, into PREFIX; meson then links it into pendula with
# -Dsundials_prefix=PREFIX.
#
# Why: Debian bookworm's libsundials 6.4.1+dfsg1-3 is compiled without
# optimisation -- its debian/rules passes -DCMAKE_C_FLAGS=-fcommon, which
# replaces the -O2 of dpkg's default flags (objdump shows -O0 code: every
# argument spilled to the stack).  For pendula's two equations CVODE's own
# per-step work is the whole cost, and the packaged build makes pendula.cvode
# several times slower (benchmarks/bench_integrators.py measures it).
#
# The source is Debian's own source package of the same release (apt-get
# source with a private sources list and state directory: the system's apt
# configuration is not touched; apt checks the files against the signed
# index).  Needs: apt-get, cmake, gcc, gfortran, make, xz.
#
# Usage: tools/build_sundials.sh PREFIX
# Idempotent: returns at once when PREFIX already holds this build.
set -euo pipefail
prefix=${1:?usage: build_sundials.sh PREFIX}
case "$prefix" in /*) ;; *) prefix="$PWD/$prefix" ;; esac
# Bump when the configuration below changes, so existing builds are redone.
recipe=1
stamp="$prefix/.pendula-sundials-recipe-$recipe"
[ -f "$stamp" ] && exit 0

# A cmake on PATH that does not run (e.g. a pyenv shim without the package)
# is passed over for Debian's.
cmake_bin=cmake
"$cmake_bin" --version >/dev/null 2>&1 || cmake_bin=/usr/bin/cmake
"$cmake_bin" --version >/dev/null 2>&1 || { echo "build_sundials: no working cmake" >&2; exit 1; }

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/apt/lists/partial" "$work/apt/cache/archives/partial" "$work/apt/sources"
cat >"$work/apt/sources/debian-src.sources" <<'EOF'
Types: deb-src
URIs: http://deb.debian.org/debian
Suites: bookworm bookworm-updates
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg
EOF
aptopts=(-o Dir::Etc::SourceList=/dev/null -o "Dir::Etc::SourceParts=$work/apt/sources"
         -o "Dir::State::Lists=$work/apt/lists" -o "Dir::Cache=$work/apt/cache"
         -o APT::Sandbox::User=root)
echo "build_sundials: fetching Debian's SUNDIALS source package"
apt-get "${aptopts[@]}" update -qq
(cd "$work" && apt-get "${aptopts[@]}" source --download-only -qq sundials >/dev/null)
orig=$(ls "$work"/sundials_6.4.*.orig.tar.* 2>/dev/null | head -n 1)
[ -n "$orig" ] || { echo "build_sundials: no SUNDIALS 6.4 source in Debian's index" >&2; exit 1; }
tar -xf "$orig" -C "$work"
src=$(ls -d "$work"/sundials-6.4.* | head -n 1)

echo "build_sundials: building $(basename "$src") (Release, static, PIC) into $prefix"
# -fcommon as Debian uses it (the 6.4 sources define some globals in headers).
"$cmake_bin" -S "$src" -B "$work/build" -DCMAKE_BUILD_TYPE=Release -DCMAKE_C_FLAGS=-fcommon \
  -DCMAKE_INSTALL_PREFIX="$prefix" -DCMAKE_INSTALL_LIBDIR=lib \
  -DBUILD_SHARED_LIBS=OFF -DBUILD_STATIC_LIBS=ON -DCMAKE_POSITION_INDEPENDENT_CODE=ON \
  -DBUILD_FORTRAN_MODULE_INTERFACE=ON -DCMAKE_Fortran_COMPILER=gfortran \
  -DBUILD_ARKODE=OFF -DBUILD_CVODES=OFF -DBUILD_IDA=OFF -DBUILD_IDAS=OFF -DBUILD_KINSOL=OFF \
  -DEXAMPLES_ENABLE_C=OFF -DEXAMPLES_ENABLE_F2003=OFF -DEXAMPLES_INSTALL=OFF \
  -DSUNDIALS_INDEX_SIZE=64 >"$work/configure.log" 2>&1 \
  || { tail -40 "$work/configure.log" >&2; echo "build_sundials: cmake configure FAILED" >&2; exit 1; }
"$cmake_bin" --build "$work/build" -j "$(nproc)" >"$work/build.log" 2>&1 \
  || { grep -E -A5 'error|Error' "$work/build.log" | head -40 >&2; echo "build_sundials: build FAILED" >&2; exit 1; }
rm -rf "$prefix"
"$cmake_bin" --install "$work/build" >/dev/null 2>&1
touch "$stamp"
echo "build_sundials: done"
