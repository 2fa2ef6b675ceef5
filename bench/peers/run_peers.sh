#!/bin/bash
# run_peers.sh: the peer side of issue 10's benchmark (docs/performance.md, "Peers").
#
# Runs LAMMPS and LIGGGHTS (Debian's packages) on the same settled bed, Hertz and JKR, on 1 and 2
# MPI ranks, interleaved (every repetition runs every case of every code before the next
# repetition starts), and prints medians: million particle-steps per second, contacts per
# particle, neighbour-list builds and net bytes per particle = (sum over ranks of the peak RSS -
# the same for an "empty" run: same input, same box, one sphere) / (N - 1). adem runs
# bench/bench_bed.c on the same data file with OpenMP threads instead of ranks.
#
#   bench/peers/run_peers.sh                  # the full comparison (100,000 spheres)
#   PEERS_N=10000 PEERS_REPS=1 bench/peers/run_peers.sh     # a small correctness run
#   PEERS_CHECK=1 PEERS_N=10000 bench/peers/run_peers.sh    # verification: loads, overlaps
#
# Environment (defaults in brackets):
#   PEERS_N [100000]          spheres in the bed; made once by make_bed.sh if missing
#   PEERS_BEDS_DIR [bench/peers/beds]  where the beds are (bedN.data, emptyN.data)
#   PEERS_REPS [3]            repetitions (medians over them)
#   PEERS_RELAX [2000]        relaxation steps, not timed, before the timed run
#   PEERS_STEPS [1000]        timed steps
#   PEERS_NP ["1 2"]          MPI ranks (LAMMPS and LIGGGHTS) / OpenMP threads (adem)
#   PEERS_BEDS ["hertz jkr"]  which beds
#   PEERS_CODES ["adem lammps liggghts"]
#   PEERS_ADEM_BENCH [build/bench/bench_bed]  adem's bench_bed (cmake --build build first)
#   PEERS_ADEM_BASE []        a second bench_bed (say, main's before a change) timed as code
#                             "adem_base" in the same interleaved rounds: add adem_base to
#                             PEERS_CODES; the table gives both adem rows and both ratios
#   PEERS_ADEM_BALANCE [0]    1: adem with its energy balance on (the peers keep none)
#   PEERS_CHECK [0]           1: verification runs (walls record forces; never use for timing)
#   PEERS_COUNT_REP [1]       the repetition whose runs count contacts (the count allocates a
#                             neighbour list, so the other repetitions give the memory figures)
#   PEERS_NICE [10]           nice level of every run (0 on a quiet machine)
#   PEERS_MPIRUN_ARGS []      extra mpirun arguments, e.g. "--bind-to core"
#   PEERS_LIGGGHTS_ROLLING [epsd2]   LIGGGHTS rolling model: epsd2, epsd (Ai et al., as adem's
#                             model C but with the secant k_n), cdt (adem's model A)
#   PEERS_LAMMPS_KROLL [model_c]     LAMMPS' constant rolling stiffness: model_c or epsd2 (params.sh)
#   PEERS_OUT [bench/peers/runs/DATE]  logs, GNU time reports, records.tsv, table.md
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
. "$here/params.sh"

N=${PEERS_N:-100000}
REPS=${PEERS_REPS:-3}
RELAX=${PEERS_RELAX:-2000}
STEPS=${PEERS_STEPS:-1000}
NPS=${PEERS_NP:-1 2}
BEDS=${PEERS_BEDS:-hertz jkr}
CODES=${PEERS_CODES:-adem lammps liggghts}
CHECK=${PEERS_CHECK:-0}
NICE=${PEERS_NICE:-10}
OUT=${PEERS_OUT:-$here/runs/$(date +%Y%m%d-%H%M%S)}
LMP=${PEERS_LMP:-lmp}
LIGGGHTS=${PEERS_LIGGGHTS:-liggghts}
ADEM_BENCH=${PEERS_ADEM_BENCH:-$here/../../build/bench/bench_bed}
# adem's energy balance (per-contact dissipation and wall work): off by default here, as the
# peers keep none; PEERS_ADEM_BALANCE=1 times adem with it (its default in a case)
ADEM_BALANCE=${PEERS_ADEM_BALANCE:-0}

# --- 1. the codes: Debian's lammps (lmp, 29Sep2021 in bookworm) and liggghts (3.8.0) ---------
need=""
command -v "$LMP" > /dev/null || need="$need lammps"
command -v "$LIGGGHTS" > /dev/null || need="$need liggghts"
command -v mpirun > /dev/null || need="$need openmpi-bin"
[ -x /usr/bin/time ] || need="$need time"
if [ -n "$need" ]; then
  echo "run_peers: installing$need" >&2
  sudo=""; [ "$(id -u)" = 0 ] || sudo=sudo
  $sudo apt-get update
  $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y $need
fi

# --- 2. the bed -----------------------------------------------------------------------------
BEDS_DIR=${PEERS_BEDS_DIR:-$here/beds}
data=$BEDS_DIR/bed$N.data
empty=$BEDS_DIR/empty$N.data
[ -f "$data" ] && [ -f "$empty" ] || PEERS_LMP=$LMP "$here/make_bed.sh" "$N" "$BEDS_DIR"

mkdir -p "$OUT/logs"
write_params "$OUT/params.in"
records=$OUT/records.tsv
: > "$records"
{
  echo "date: $(date -Is)"
  echo "host: $(uname -nrm); $(nproc) cores; $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')"
  echo "load average at start: $(cut -d' ' -f1-3 /proc/loadavg)"
  echo "packages: $(dpkg-query -W -f '${Package} ${Version}; ' lammps liggghts openmpi-bin 2> /dev/null)"
  echo "lammps: $("$LMP" -h | sed -n 2p | sed 's/^ *//')"
  echo "liggghts: $(echo | "$LIGGGHTS" -echo none -log none 2>&1 | head -1)"
  echo "bed: $data ($N spheres); relax $RELAX steps, timed $STEPS steps; ranks/threads: $NPS; repetitions: $REPS; check: $CHECK; nice: $NICE"
} > "$OUT/about.txt"
cat "$OUT/about.txt" >&2

mpi=(mpirun --oversubscribe)
[ "$(id -u)" = 0 ] && mpi+=(--allow-run-as-root)
# shellcheck disable=SC2206
[ -n "${PEERS_MPIRUN_ARGS:-}" ] && mpi+=(${PEERS_MPIRUN_ARGS})

# --- 3. one run of one code -------------------------------------------------------------------
# run_code CODE BED NP PREFIX DATAFILE: leaves PREFIX.log (the code's log, with "PEERS ..." lines),
# PREFIX.out (its screen) and PREFIX.rss.RANK (GNU time reports).
run_code() {
  local code=$1 bed=$2 np=$3 prefix=$4 file=$5 jkr=0
  [ "$bed" = jkr ] && jkr=1
  case $code in
    lammps)
      OMP_NUM_THREADS=1 nice -n "$NICE" "${mpi[@]}" -np "$np" "$here/rss.sh" "$prefix.rss" \
        "$LMP" -in "$here/bed.lmp" -log "$prefix.log" -nocite -var params "$OUT/params.in" \
        -var data "$file" -var jkr "$jkr" -var relax "$RELAX" -var steps "$STEPS" \
        -var check "$CHECK" -var count "$count" -var peers "$here" > "$prefix.out" 2>&1 ;;
    liggghts)
      OMP_NUM_THREADS=1 nice -n "$NICE" "${mpi[@]}" -np "$np" "$here/rss.sh" "$prefix.rss" \
        "$LIGGGHTS" -in "$here/bed.liggghts" -log "$prefix.log" -nocite -var params "$OUT/params.in" \
        -var data "$file" -var jkr "$jkr" -var relax "$RELAX" -var steps "$STEPS" \
        -var check "$CHECK" -var count "$count" -var peers "$here" -var rolling_model "${PEERS_LIGGGHTS_ROLLING:-epsd2}" \
        > "$prefix.out" 2>&1 ;;
    adem)
      run_adem "$bed" "$np" "$prefix" "$file" ;;
    adem_base)
      ADEM_BENCH=${PEERS_ADEM_BASE:?PEERS_ADEM_BASE: the base bench_bed} run_adem "$bed" "$np" "$prefix" "$file" ;;
  esac
}

# ---- adem -----------------------------------------------------------------------------------
# bench/bench_bed.c --data: one process with NP OpenMP threads under rss.sh; relaxes RELAX steps
# untimed, times STEPS steps and writes "PEERS key value" lines (timed, particles, loop_seconds,
# rebuilds, contacts_per_particle, ...) to PREFIX.log. Physics as the peers' (docs/performance.md):
# Hertz or simplified JKR (gamma = PEERS_GAMMA) between spheres, Hertz walls, COR, friction,
# rolling model C with eta_r = PEERS_ROLLING and no rolling damping, skin PEERS_SKIN, dt PEERS_DT.
run_adem() {
  local bed=$1 np=$2 prefix=$3 file=$4
  [ -x "$ADEM_BENCH" ] || return 3
  OMP_NUM_THREADS=$np nice -n "$NICE" "$here/rss.sh" "$prefix.rss" "$ADEM_BENCH" \
    --data "$file" --normal "$bed" --gamma "$PEERS_GAMMA" --rolling model_c \
    --rolling-friction "$PEERS_ROLLING" --skin "$PEERS_SKIN" --dt "$PEERS_DT" \
    --young "$PEERS_YOUNG" --poisson "$PEERS_POISSON" --restitution "$PEERS_COR" \
    --friction "$PEERS_FRICTION" --gravity "$PEERS_GRAVITY" \
    --relax "$RELAX" --steps "$STEPS" --threads "$np" --energy-balance "$ADEM_BALANCE" \
    > "$prefix.log" 2> "$prefix.out"
}
# ---- end of the adem hook ---------------------------------------------------------------------

# parse PREFIX KIND CODE BED NP REP: one line of records.tsv:
# code bed np rep kind atoms steps loop_s builds dangerous contacts_pp code_mem_MB rss_kB(sum)
parse() {
  local prefix=$1 kind=$2 code=$3 bed=$4 np=$5 rep=$6 rss
  rss=$(cat "$prefix".rss.* 2> /dev/null | awk -F': ' '/Maximum resident set size/ { s += $2 } END { print s + 0 }')
  awk -v code="$code" -v bed="$bed" -v np="$np" -v rep="$rep" -v kind="$kind" -v rss="$rss" '
    /^PEERS timed/ { timed = 1 }
    timed && /^Loop time of/ && !loop { loop = $4; steps = $9; atoms = $12 }
    timed && /^Neighbor list builds/ && builds == "" { builds = $5 }
    timed && /^Dangerous builds/ && danger == "" { danger = $4 }
    timed && /^Per MPI rank memory allocation/ && mem == "" { mem = $(NF - 3) }   # avg
    timed && /^Memory usage per processor/ && mem == "" { mem = $(NF - 1) }
    /^PEERS particles/ { atoms = $3 }
    /^PEERS loop_seconds/ { loop = $3 }
    /^PEERS timed/ { steps = $3 }
    /^PEERS rebuilds/ { builds = $3 }
    /^PEERS contacts_per_particle/ { cpp = $3 }
    END {
      if (loop == "") { print "parse: no timed run in " FILENAME > "/dev/stderr"; exit 1 }
      printf "%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n", code, bed, np, rep, kind,
        atoms, steps, loop, (builds == "" ? "-" : builds), (danger == "" ? "-" : danger),
        (cpp == "" ? "-" : cpp), (mem == "" ? "-" : mem), rss
    }' "$prefix.log"
}

# --- 4. interleaved repetitions ---------------------------------------------------------------
for rep in $(seq 1 "$REPS"); do
  count=0
  { [ "$rep" = "${PEERS_COUNT_REP:-1}" ] || [ "$CHECK" = 1 ] || [ "$REPS" = 1 ]; } && count=1
  for bed in $BEDS; do
    for np in $NPS; do
      for code in $CODES; do
        if [ "$code" = adem ] && [ ! -x "$ADEM_BENCH" ]; then
          echo "run_peers: no $ADEM_BENCH (cmake --build build): adem skipped" >&2; continue
        fi
        tag=$code-$bed-np$np-r$rep
        echo "run_peers: $tag (load $(cut -d' ' -f1 /proc/loadavg))" >&2
        run_code "$code" "$bed" "$np" "$OUT/logs/$tag" "$data" || { echo "run_peers: $tag failed, see $OUT/logs/$tag.out" >&2; exit 1; }
        parse "$OUT/logs/$tag" bed "$code" "$bed" "$np" "$rep" >> "$records"
        run_code "$code" "$bed" "$np" "$OUT/logs/$tag-empty" "$empty" || { echo "run_peers: $tag-empty failed" >&2; exit 1; }
        parse "$OUT/logs/$tag-empty" empty "$code" "$bed" "$np" "$rep" >> "$records"
        if [ "$CHECK" = 1 ]; then grep -h '^PEERS check' "$OUT/logs/$tag.log" | sed "s/^/  $tag: /" >&2; fi
      done
    done
  done
done

# --- 5. the table -----------------------------------------------------------------------------
"$here/table.sh" "$records" "$OUT/about.txt" | tee "$OUT/table.md"
echo "run_peers: logs and records in $OUT" >&2
