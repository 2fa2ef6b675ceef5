#!/bin/sh
# For each public header: the errors of a file that includes only it, and the public headers it
# pulls in (cc -MM). The structure of include/adem at a glance (docs/architecture.md).
#   scripts/public-headers.sh [SOURCE_ROOT]    (default: this checkout; another tree, e.g. one
#   made by `git archive OLDCOMMIT include | tar -x -C DIR`, shows how it was)
root=${1:-$(dirname "$0")/..}
for f in $root/include/adem/*.h; do
  b=$(basename $f)
  e=$(echo "#include \"adem/$b\"" | cc -std=c17 -fsyntax-only -I$root/include -x c - 2>&1 | grep -c 'error:')
  deps=$(echo "#include \"adem/$b\"" | cc -std=c17 -MM -I$root/include -x c - 2>/dev/null | tr ' \\' '\n\n' | grep 'include/adem/' | sed 's|.*include/adem/||' | grep -vx "$b" | sort | tr '\n' ' ')
  n=$(echo "$deps" | wc -w)
  printf '%-12s errors %2s  pulls %2s: %s\n' "$b" "$e" "$n" "$deps"
done
