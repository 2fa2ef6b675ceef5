#!/usr/bin/env bash
# The instruction mix of one particle-step (docs/performance.md, "Cost model"): callgrind counts
# every instruction adem_world_step executes on the 10,000-sphere peer bed (1 relaxation + 20
# timed steps, 1 thread), instruction_mix.py sorts them by kind. Deterministic: the machine's
# load does not change it. Needs valgrind and a bench_bed built with -g for the disassembly:
#   cmake -S . -B build-g -DCMAKE_BUILD_TYPE=Release -DCMAKE_C_FLAGS=-g
#   cmake --build build-g --target bench_bed
#   bench/cost/cost_model.sh build-g/bench/bench_bed
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
bin=$(realpath "${1:?usage: cost_model.sh BENCH_BED}")
data=${COST_BED:-$here/../peers/beds/bed10000.data}
[ -f "$data" ] || { echo "cost_model.sh: no bed $data (bench/peers/make_bed.sh 10000)" >&2; exit 1; }
n=$(awk '/ atoms$/{print $1}' "$data")
steps=21 # adem_world_step runs 1 relaxation step and 20 timed ones
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
run() { # NAME ARGS...
  local name=$1; shift
  OMP_NUM_THREADS=1 valgrind --tool=callgrind --dump-instr=yes --dump-line=no \
    --toggle-collect=adem_world_step --callgrind-out-file="$tmp/$name.cg" \
    "$bin" --data "$data" --relax 1 --steps 20 --threads 1 "$@" >"$tmp/$name.log" 2>&1
  echo "== $name ($(grep -h contacts_per_particle "$tmp/$name.log" | awk '{print $3}') contacts per particle)"
  python3 "$here/instruction_mix.py" "$tmp/$name.cg" "$bin" "$((n * steps))"
}
run "hertz, balance off" --energy-balance 0
run "hertz, balance on" --energy-balance 1
run "jkr, balance off" --normal jkr --energy-balance 0
