#!/usr/bin/env bash
# clang-format over the tracked C files (src/, include/, app/, tests/, examples/, bench/, fuzz/,
# python/) with the repository's .clang-format.
#   scripts/format.sh           rewrites the files in place
#   scripts/format.sh --check   changes nothing; lists each file that would change with its count
#                               of changed lines and exits 1 if there is any
# CLANG_FORMAT=clang-format-N picks another clang-format (the figures in .clang-format are
# Debian 12's clang-format 14).
set -euo pipefail
cd "$(dirname "$0")/.."

cf=${CLANG_FORMAT:-clang-format}
command -v "$cf" >/dev/null || { echo "format.sh: $cf not found (apt-get install clang-format)" >&2; exit 2; }
mode=write
case "${1:-}" in
  --check) mode=check ;;
  '') ;;
  *) echo "usage: scripts/format.sh [--check]" >&2; exit 2 ;;
esac

mapfile -t files < <(git ls-files -- '*.c' '*.h' | grep -E '^(src|include|app|tests|examples|bench|fuzz|python)/')
changed=0 lines=0
for f in "${files[@]}"; do
  [ -f "$f" ] || continue
  if [ "$mode" = check ]; then
    n=$("$cf" --style=file "$f" | diff "$f" - | grep -c '^<' || true)
    if [ "$n" -gt 0 ]; then
      echo "$f: $n lines"
      changed=$((changed + 1)) lines=$((lines + n))
    fi
  else
    "$cf" --style=file -i "$f"
  fi
done
if [ "$mode" = check ]; then
  echo "format.sh: ${#files[@]} files, $changed would change ($lines lines)" >&2
  [ "$changed" -eq 0 ]
fi
