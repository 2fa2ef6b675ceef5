#!/bin/sh
# A contact law lives in one place: no law id (ADEM_NORMAL_HERTZ, ADEM_ROLLING_BROF ... the
# first column of the rows in include/adem/laws.h) appears in the library or the command outside
# the laws' folder (src/laws/) and the studies (src/studies/, which set up a paper's laws).
# What the rest needs of a law comes from its row: descriptive columns and cold-path hooks
# (src/laws/law_hooks.h). The one exception is the force pass's hot path: its block kernels
# are compiled for named law combinations (src/core/pair_block_laws.h, the list; pair_blocks.c,
# which picks a kernel for a pair's laws) and its per-particle sums single out BROF's objective
# form (src/core/force_sums.c).
#   check_law_ids.sh SOURCE_DIR
# First checks itself: an id planted in a scratch copy of a file must be reported.
set -eu
root=$1
ids=$(sed -n 's/^ *X(\(ADEM_\(NORMAL\|DAMPING\|TANGENTIAL\|ROLLING\)_[A-Z0-9_]*\),.*/\1/p' \
  "$root/include/adem/laws.h" | sort -u)
count=$(printf '%s\n' "$ids" | grep -c . || true)
[ "$count" -ge 10 ] || { echo "only $count law ids read from include/adem/laws.h" >&2; exit 1; }
pattern=$(printf '%s\n' "$ids" | paste -sd'|' -)

# Files that name a law id, outside the allowed places; $1 the tree to look in.
offenders() {
  find "$1/src" "$1/app" -name '*.[ch]' 2>/dev/null |
    grep -v -e "^$1/src/laws/" -e "^$1/src/studies/" -e "^$1/src/core/pair_block_laws.h$" \
      -e "^$1/src/core/pair_blocks.c$" -e "^$1/src/core/force_sums.c$" |
    xargs grep -lwE "$pattern" 2>/dev/null || true
}

scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
mkdir -p "$scratch/src/run" "$scratch/app"
printf 'static int x(int r) { return r == %s; }\n' "$(printf '%s\n' "$ids" | head -n 1)" \
  > "$scratch/src/run/planted.c"
[ -n "$(offenders "$scratch")" ] || { echo "the check misses a planted law id" >&2; exit 1; }

bad=$(offenders "$root")
if [ -n "$bad" ]; then
  echo "law ids outside src/laws/ and src/studies/ (use the row's columns or hooks):" >&2
  for f in $bad; do grep -nwE "$pattern" "$f" | sed "s|^|${f#$root/}:|" >&2; done
  exit 1
fi
echo "$count law ids; none outside src/laws/, src/studies/ (and the force pass's block kernels and sums)"
