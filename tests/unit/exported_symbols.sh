#!/bin/sh
# libadem.so exports the public API and nothing else: every defined dynamic symbol starts with
# adem_ and is a function the public headers (include/adem/*.h) declare, and the library's
# internal functions (e.g. adem_particles_kick, adem_soa_grow) are not among them.
#   exported_symbols.sh LIBADEM_SO INCLUDE_DIR
set -eu
lib=$1 inc=$2
syms=$(nm -D --defined-only "$lib" | awk '{print $3}' | sed 's/@.*//')
count=$(printf '%s\n' "$syms" | grep -c . || true)
[ "$count" -gt 100 ] || { echo "only $count symbols exported by $lib" >&2; exit 1; }
bad=0
for s in $syms; do
  case $s in
    adem_*) ;;
    *) echo "exported symbol without the adem_ prefix: $s" >&2; bad=1; continue ;;
  esac
  grep -qE "\\b$s[ ]*\\(" "$inc"/*.h || { echo "exported but not in the public headers: $s" >&2; bad=1; }
done
for s in adem_particles_kick adem_soa_grow adem_world_build_neighbors adem_force_pass_run; do
  if printf '%s\n' "$syms" | grep -qx "$s"; then echo "internal function exported: $s" >&2; bad=1; fi
done
[ $bad -eq 0 ] && echo "$count symbols exported, all public (adem_*)"
exit $bad
