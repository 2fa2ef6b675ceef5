#!/bin/bash
# hashes.sh: the state-hash matrix that a change of the force pass must reproduce bit for bit
# (issue 24's oracle; bench/hashes.expected holds main's before the redesign).
#
#   bench/hashes.sh [BUILD_DIR] > out.txt && diff bench/hashes.expected out.txt
#
# Rows: a dense block of 4,096 spheres (bench/dense_bed.awk: every neighbour overlaps from the
# start, so 200 steps load, slide, roll, open and rebuild) under Hertz and JKR x every rolling
# law bench_bed takes (DTK only with JKR) x energy balance off and on x 1 and 2 threads;
# bench_bed's own 10,000-sphere bed (dropped and settled for 0.25 s, then 200 steps on 1 and
# 200 on 2 threads: one hash); and the same matrix on the LAMMPS-settled peer beds of 10,000 and
# 100,000 spheres when they exist (bench/peers/make_bed.sh; fewer steps).
# Each hash is FNV-1a over every position, velocity and spin by id (bench_bed.c, state_hash).
#
# Environment: HASHES_BEDS_DIR [bench/peers/beds] (bed10000.data), HASHES_BIG_BED
# [/work/beds/bed100000.data], HASHES_NICE [10], HASHES_OWN [1] (0: skip the own bed, a few
# minutes of one core), HASHES_PEERS [1] (0: skip the peer beds).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
build=${1:-$here/../build}
bench=$build/bench/bench_bed
[ -x "$bench" ] || { echo "hashes.sh: no $bench (cmake --build $build first)" >&2; exit 2; }
beds=${HASHES_BEDS_DIR:-$here/peers/beds}
big=${HASHES_BIG_BED:-/work/beds/bed100000.data}
nice=${HASHES_NICE:-10}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
awk -v side=16 -v d=0.005 -v rho=2500 -f "$here/dense_bed.awk" > "$tmp/dense.data"

# one line per run: bed normal rolling balance threads hash
matrix() {
  local data=$1 label=$2 relax=$3 steps=$4
  for normal in hertz jkr; do
    rollings="none model_a model_c model_c_capped brof brof_objective"
    [ "$normal" = jkr ] && rollings="$rollings dtk"
    for rolling in $rollings; do
      for balance in 0 1; do
        for threads in 1 2; do
          h=$(nice -n "$nice" "$bench" --data "$data" --normal "$normal" --rolling "$rolling" \
                --energy-balance "$balance" --threads "$threads" --relax "$relax" --steps "$steps" |
              awk '$2 == "state_hash" { print $3 }')
          printf '%s %-6s %-15s balance=%s threads=%s %s\n' "$label" "$normal" "$rolling" \
            "$balance" "$threads" "${h:-FAILED}"
        done
      done
    done
  done
}

matrix "$tmp/dense.data" dense4k 10 190
if [ "${HASHES_OWN:-1}" = 1 ]; then
  # bench_bed's own bed: 0.25 s of falling and settling, then 200 steps on 1 and 2 threads
  h=$(ADEM_BENCH_STEPS=200 nice -n "$nice" "$bench" 10000 | awk '/state hash/ { print $NF }')
  printf 'own10k hertz  %-15s balance=1 threads=1,2 %s\n' default "${h:-FAILED}"
fi
if [ "${HASHES_PEERS:-1}" = 1 ] && [ -f "$beds/bed10000.data" ]; then
  matrix "$beds/bed10000.data" bed10k 20 180
fi
if [ "${HASHES_PEERS:-1}" = 1 ] && [ -f "$big" ]; then
  matrix "$big" bed100k 10 40
fi
