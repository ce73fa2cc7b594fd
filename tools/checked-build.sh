#!/usr/bin/env bash
# Checked build leg: build the Fortran library and its Fortran tests
# with meson -Dchecked=true, which adds
#   -fcheck=all -ffpe-trap=invalid,zero,overflow -g -fbacktrace
# to every Fortran target, and run `meson test --suite fortran`.
# A bounds error, an invalid/zero-divide/overflow operation or a failed check
# aborts the program with a backtrace, so the leg fails.
#
# Usage: tools/checked-build.sh [BUILD_DIR]      (default: build/checked)
# Environment:
#   CHECKED_BUILDTYPE   meson buildtype (default: debug, i.e. -O0: no
#                       optimiser speculation that could trap on its own)
#   PENDULA_TEST_QUICK  exported as 1 unless already set: Fortran tests that
#                       honour it run a reduced sweep
#   MESON_TEST_ARGS     extra arguments for `meson test`
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
bdir=${1:-build/checked}
case "$bdir" in /*) ;; *) bdir="$here/$bdir" ;; esac
buildtype=${CHECKED_BUILDTYPE:-debug}
export PENDULA_TEST_QUICK=${PENDULA_TEST_QUICK:-1}
mkdir -p "$(dirname "$bdir")"

t0=$(date +%s)
if [ ! -f "$bdir/build.ninja" ]; then
  echo "checked-build: configuring $bdir (buildtype=$buildtype, -Dchecked=true, -Dpython=disabled)"
  meson setup "$bdir" "$here" -Dchecked=true -Dpython=disabled \
      -Dbuildtype="$buildtype" >"$bdir.setup.log" 2>&1 \
    || { cat "$bdir.setup.log" >&2; echo "checked-build: meson setup FAILED" >&2; exit 2; }
else
  # An existing directory must really be a checked one.
  meson configure "$bdir" -Dchecked=true -Dpython=disabled >/dev/null
fi
if ! ninja -C "$bdir" >"$bdir.ninja.log" 2>&1; then
  # The compiler's errors, not the pages of warnings around them.
  grep -E -A6 '^FAILED:|Error:|error:' "$bdir.ninja.log" | head -60 >&2
  echo "checked-build: build FAILED (log: $bdir.ninja.log)" >&2
  exit 2
fi
t1=$(date +%s)
echo "checked-build: built in $((t1 - t0)) s; running the Fortran suite"
# shellcheck disable=SC2086
if meson test -C "$bdir" --suite fortran --no-rebuild --print-errorlogs ${MESON_TEST_ARGS:-}; then
  rc=0
else
  rc=1
fi
t2=$(date +%s)
echo "checked-build: Fortran suite $( [ $rc -eq 0 ] && echo PASSED || echo FAILED ) in $((t2 - t1)) s (log: $bdir/meson-logs/testlog.txt)"
exit $rc
