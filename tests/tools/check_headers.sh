#!/bin/sh
# Every header of include/adem (the public API and include/adem/internal) stands alone: a file
# that includes only it compiles, warning-free, as C17 (and as C++ when a C++ compiler is given),
# and no header but the umbrella includes the umbrella adem/adem.h.
#   check_headers.sh CC INCLUDE_DIR [CXX]
set -eu
cc=$1 inc=$2 cxx=${3:-}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
n=0 bad=0
for h in "$inc"/adem/*.h "$inc"/adem/internal/*.h; do
  name=${h#"$inc"/}
  n=$((n + 1))
  printf '#include "%s"\n' "$name" > "$tmp/one.c"
  if ! "$cc" -std=c17 -Wall -Wextra -Wpedantic -Werror -fsyntax-only -I"$inc" "$tmp/one.c" \
       2> "$tmp/err"; then
    echo "$name does not compile alone ($(grep -c 'error' "$tmp/err") errors):" >&2
    cat "$tmp/err" >&2
    bad=$((bad + 1))
  fi
  if [ -n "$cxx" ] && ! "$cxx" -x c++ -std=c++17 -Wall -Wextra -Werror -fsyntax-only -I"$inc" \
       "$tmp/one.c" 2> "$tmp/err"; then
    echo "$name does not compile alone as C++:" >&2
    cat "$tmp/err" >&2
    bad=$((bad + 1))
  fi
  if [ "$name" != adem/adem.h ] && grep -q '#include *["<]adem/adem\.h[">]' "$h"; then
    echo "$name includes the umbrella adem/adem.h: include what it uses" >&2
    bad=$((bad + 1))
  fi
done
[ "$n" -ge 15 ] || { echo "only $n headers under $inc/adem" >&2; exit 1; }
echo "$n headers, each compiles alone; $bad failures"
[ "$bad" -eq 0 ]
