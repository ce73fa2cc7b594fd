#!/usr/bin/env bash
# Meson subproject route: a user's project (tests/consumer/subproject) in a
# temporary folder with this source tree as subprojects/pendula (a symlink),
# forced to the fallback, built and its program run.
# Usage: run_subproject_consumer.sh SOURCE_ROOT
set -euo pipefail
root=$(cd "$1" && pwd)
here=$(cd "$(dirname "$0")" && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/subprojects"
cp "$here/subproject/meson.build" "$here/consumer.f90" "$tmp/"
ln -s "$root" "$tmp/subprojects/pendula"
cd "$tmp"
echo "meson setup --wrap-mode=forcefallback (dependency('pendula', fallback: ['pendula', 'pendula_dep']))"
meson setup build --wrap-mode=forcefallback >setup.log 2>&1 || { cat setup.log; exit 1; }
grep -E 'CVODE|SUNDIALS ' setup.log || true
ninja -C build >build.log 2>&1 || { tail -40 build.log; exit 1; }
unset LD_LIBRARY_PATH
./build/consumer
