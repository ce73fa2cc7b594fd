#!/usr/bin/env bash
# fpm route: a user's fpm project in a temporary folder that depends on this
# source tree by path and runs tests/consumer/consumer.f90 as its program,
# built twice: without SUNDIALS (the default: CVODE reports unavailable) and
# with Debian's SUNDIALS (PENDULA_WITH_SUNDIALS and the libraries as flags).
# Usage: run_fpm_consumer.sh SOURCE_ROOT [FPM]
set -euo pipefail
root=$(cd "$1" && pwd)
fpm=${2:-fpm}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/app"
cp "$root/tests/consumer/consumer.f90" "$tmp/app/main.f90"
# fpm 0.12 takes a path dependency relative to the project
rel=$(python3 -c 'import os, sys; print(os.path.relpath(sys.argv[1], sys.argv[2]))' "$root" "$tmp")
cat >"$tmp/fpm.toml" <<TOML
name = "pendula_consumer"
[dependencies]
pendula = { path = "$rel" }
TOML
cd "$tmp"
echo "fpm run (without SUNDIALS)"
"$fpm" run >run.log 2>&1 || { cat run.log; exit 1; }
grep -v '^\[' run.log | grep '^consumer'
grep -q 'CVODE available: F' run.log || { echo "expected a build without CVODE"; exit 1; }
if [ -d /usr/include/sundials/fortran ]; then
  libs="-Wl,--no-as-needed"
  for l in fcvode_mod cvode fnvecserial_mod nvecserial fsunmatrixdense_mod sunmatrixdense \
           fsunlinsoldense_mod sunlinsoldense; do libs+=" -lsundials_$l"; done
  echo "fpm run --flag '-DPENDULA_WITH_SUNDIALS -I/usr/include/sundials/fortran' --link-flag '$libs'"
  "$fpm" run --flag "-DPENDULA_WITH_SUNDIALS -I/usr/include/sundials/fortran" --link-flag "$libs" \
    >run.log 2>&1 || { cat run.log; exit 1; }
  grep -v '^\[' run.log | grep '^consumer'
  grep -q 'CVODE available: T' run.log || { echo "expected a build with CVODE"; exit 1; }
else
  echo "no /usr/include/sundials/fortran: the SUNDIALS leg is not run"
fi
