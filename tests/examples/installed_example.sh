#!/bin/sh
# The example builds against the installed library alone: `cmake --install` to a temporary
# prefix, then the example compiled with that prefix's include and lib folders (no source tree
# on the include path), run, and its exit status checked (settled pour, bitwise restart).
#   installed_example.sh BUILD_DIR SOURCE_DIR C_COMPILER
set -eu
build=$1 src=$2 cc=$3
prefix=$(mktemp -d)
trap 'rm -rf "$prefix"' EXIT
cmake --install "$build" --prefix "$prefix" >/dev/null
test -f "$prefix/include/adem/adem.h"
test -f "$prefix/lib/libadem.a"
# the public headers must not name any internal header
if grep -l '#include "' "$prefix"/include/adem/*.h | xargs -r grep -h '#include "' | grep -v '"adem/'; then
  echo "a public header includes an internal one" >&2
  exit 1
fi
libs=$(PKG_CONFIG_PATH="$prefix/lib/pkgconfig" pkg-config --cflags --libs adem)
"$cc" -std=c17 -O2 -Wall -Wextra -Werror "$src/examples/pour.c" $libs -o "$prefix/pour"
cd "$prefix" && "$prefix/pour" "$prefix"
