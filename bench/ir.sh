#!/bin/bash
# ir.sh: instructions per particle-step of the force pass's bed, counted by callgrind
# (deterministic, so it measures a change on a shared machine where times do not).
#
#   bench/ir.sh [BUILD_DIR] [bench_bed options...]
#
# Runs bench_bed on a bed (IR_BED: a LAMMPS data file, e.g. a peer bed of bench/peers/make_bed.sh;
# default: the dense block of 8,000 spheres of bench/dense_bed.awk) twice under
# valgrind --tool=callgrind, with IR_SHORT and IR_LONG timed steps (defaults 5 and 25) after one
# relaxation step, 1 thread, the energy balance off, Hertz with rolling model C unless the
# options say otherwise; the difference of the two totals over (IR_LONG - IR_SHORT) x N is the
# cost of a step without the setup. Then the long run's functions with their share of it.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
build=${1:-$here/../build}
[ $# -gt 0 ] && shift
bench=$build/bench/bench_bed
short=${IR_SHORT:-5}
long=${IR_LONG:-25}
out=${IR_OUT:-$(mktemp -d)}
data=${IR_BED:-$out/dense.data}
[ -n "${IR_BED:-}" ] || awk -v side=20 -v d=0.005 -v rho=2500 -f "$here/dense_bed.awk" > "$data"
n=$(awk '/ atoms$/ { print $1; exit }' "$data")
total() {
  local steps=$1
  shift
  nice -n "${IR_NICE:-10}" valgrind --tool=callgrind --callgrind-out-file="$out/cg.$steps" "$bench" \
    --data "$data" --normal hertz --rolling model_c --energy-balance 0 --threads 1 --relax 1 \
    --steps "$steps" "$@" > "$out/log.$steps" 2>&1
  callgrind_annotate "$out/cg.$steps" 2>/dev/null | awk '/PROGRAM TOTALS/ { gsub(",", "", $1); print $1 }'
}
a=$(total "$short" "$@")
b=$(total "$long" "$@")
awk -v a="$a" -v b="$b" -v s="$short" -v l="$long" -v n="$n" \
  'BEGIN { printf "instructions per particle-step: %.0f  (%d particles, %d - %d steps)\n", (b - a) / ((l - s) * n), n, l, s }'
callgrind_annotate --threshold=97 "$out/cg.$long" 2>/dev/null | sed -n '/file:function/,$p' | head -25
