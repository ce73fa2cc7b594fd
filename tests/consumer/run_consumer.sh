#!/usr/bin/env bash
# Install the built library into a temporary prefix (as a user would, with
# `meson install`), then build and run tests/consumer/consumer.f90 the way a
# user of that route would, without LD_LIBRARY_PATH:
#   pkgconfig  gfortran consumer.f90 $(pkg-config --cflags --libs pendula)
#   cmake      find_package(pendula) and the target pendula::pendula
# Usage: run_consumer.sh BUILD_DIR pkgconfig|cmake
set -euo pipefail
build=$1
route=$2
here=$(cd "$(dirname "$0")" && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
meson install -C "$build" --destdir "$tmp/root" --tags devel,runtime --quiet >/dev/null
prefix=$(meson introspect "$build" --buildoptions | python3 -c \
  "import json,sys; print([o['value'] for o in json.load(sys.stdin) if o['name']=='prefix'][0])")
# The files sit under DESTDIR: the install as if made with --prefix $tmp/root$prefix.
root="$tmp/root$prefix"
unset LD_LIBRARY_PATH
cd "$tmp"
case "$route" in
  pkgconfig)
    pcdir=$(dirname "$(find "$root" -name pendula.pc | head -n 1)")
    export PKG_CONFIG_PATH="$pcdir"
    # pkg-config's prefix pointed at the relocated install (its libdir and the
    # run path in Libs follow it).
    flags=$(pkg-config --define-variable=prefix="$root" --cflags --libs pendula)
    echo "gfortran consumer.f90 $flags"
    gfortran "$here/consumer.f90" $flags -o consumer
    ;;
  cmake)
    cmake_bin=cmake
    "$cmake_bin" --version >/dev/null 2>&1 || cmake_bin=/usr/bin/cmake
    echo "cmake -S tests/consumer/cmake -DCMAKE_PREFIX_PATH=$root"
    "$cmake_bin" -S "$here/cmake" -B cm -DCMAKE_PREFIX_PATH="$root" -DCMAKE_BUILD_TYPE=Release >cm.log 2>&1 \
      || { cat cm.log; exit 1; }
    "$cmake_bin" --build cm >>cm.log 2>&1 || { cat cm.log; exit 1; }
    cp cm/consumer .
    ;;
  *) echo "run_consumer.sh: unknown route '$route'" >&2; exit 2 ;;
esac
./consumer
