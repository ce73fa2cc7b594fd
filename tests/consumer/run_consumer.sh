#!/usr/bin/env bash
# Install the built library into a temporary prefix (as a user would, with
# `meson install`), then compile, link and run a program that does `use pendula`
# with exactly `gfortran prog.f90 $(pkg-config --cflags --libs pendula)`.
set -euo pipefail
build=$1
src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
meson install -C "$build" --destdir "$tmp/root" --tags devel,runtime --quiet >/dev/null
prefix=$(meson introspect "$build" --buildoptions | python3 -c \
  "import json,sys; print([o['value'] for o in json.load(sys.stdin) if o['name']=='prefix'][0])")
pcdir=$(dirname "$(find "$tmp/root" -name pendula.pc | head -n 1)")
export PKG_CONFIG_PATH="$pcdir"
# The files sit under DESTDIR; point pkg-config's prefix there (a relocated install).
flags=$(pkg-config --define-variable=prefix="$tmp/root$prefix" --cflags --libs pendula)
cd "$tmp"
echo "gfortran consumer.f90 $flags"
gfortran "$src" $flags -o consumer
libdir=$(pkg-config --define-variable=prefix="$tmp/root$prefix" --variable=libdir pendula)
LD_LIBRARY_PATH="$libdir${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}" ./consumer
