#!/usr/bin/env bash
# Long-run checks of adem's memory (see docs/reliability.md, "Soak"):
#   scripts/soak.sh [STEPS]      soak: cases/packing.yaml with smaller spheres (a pour of 2400
#                                spheres of 8 to 12 mm, two stages, a lid that comes down) run
#                                for STEPS steps (default 1000000, about 12 s simulated, 40 min), its
#                                resident memory (VmRSS of
#                                /proc/PID/status) sampled every ADEM_SOAK_EVERY seconds (default
#                                5) into build-soak/rss.csv; then whether it grew after warm-up
#   scripts/soak.sh --valgrind   valgrind memcheck of short runs (fuzz/seeds/case/stages_pour.yaml:
#                                pours, stages, a moving plane, JKR, rolling, checkpoints, and
#                                its resume; the hopper: mesh walls, a moving gate, a stage): no
#                                error and no leak expected
# Warm-up: everything up to the last change of the case (the pour ends at 0.8 s, the lid stops
# at 1.51 s) and at least the first tenth of the run; after it the RSS must not grow by more
# than 1 MiB (the pair lists settle with the bed; any leak per step or per rebuild shows as a
# steady rise). Exit 0 when it holds (or memcheck is clean), 1 when not. ADEM_SOAK_BUILD names
# the build folder (default build-soak, Release).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD

build=${ADEM_SOAK_BUILD:-build-soak}
every=${ADEM_SOAK_EVERY:-5}

build_adem() {
  if [ ! -f "$build/CMakeCache.txt" ]; then
    cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=${ADEM_SOAK_TYPE:-Release} -DADEM_TESTS=OFF >/dev/null
  fi
  nice -n 15 cmake --build "$build" -j"$(nproc)" --target adem_cli >/dev/null
}

install_valgrind() {
  command -v valgrind >/dev/null && return
  echo "soak.sh: installing valgrind" >&2
  local sudo_cmd=""
  [ "$(id -u)" -ne 0 ] && sudo_cmd="sudo"
  $sudo_cmd apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq --no-install-recommends valgrind >/dev/null
}

# memcheck NAME ARGS...: one run under valgrind; 0 when it reports no error and no leak.
memcheck() {
  local name=$1 log=$build/valgrind-$1.log
  shift
  local t0=$SECONDS rc=0
  # one thread: libgomp's thread pool is kept alive at exit on purpose and would show as
  # "possibly lost"; the threaded code paths are the sanitizers' (scripts/sanitize.sh).
  nice -n 15 valgrind --tool=memcheck --error-exitcode=99 --leak-check=full \
    --show-leak-kinds=definite,indirect,possible --errors-for-leak-kinds=definite,indirect,possible \
    --track-origins=yes --log-file="$log" "$root/$build/adem" "$@" --threads 1 --quiet || rc=$?
  local errors
  errors=$(grep -E 'ERROR SUMMARY' "$log" | tail -1 | sed -E 's/.*ERROR SUMMARY: ([0-9]+) errors.*/\1/')
  printf 'soak.sh: memcheck %-8s exit %s, %s errors, %s (%d s; log %s)\n' "$name" "$rc" "${errors:-?}" \
    "$(grep -E 'definitely lost|All heap blocks were freed' "$log" | tail -1 | sed 's/^==[0-9]*== *//')" \
    $((SECONDS - t0)) "$log" >&2
  [ "$rc" -eq 0 ] && [ "${errors:-1}" = 0 ]
}

run_valgrind() {
  install_valgrind
  build_adem
  local out=$build/valgrind-out rc=0
  rm -rf "$out"
  # pours, stages, a plane wall switched on by a stage and moved by a table, JKR and rolling
  # resistance, tracked particles, frames, CSV rows, checkpoints (the fuzzers' seed case); then a
  # resume from its checkpoint to a later end
  memcheck stages run fuzz/seeds/case/stages_pour.yaml --out "$out/stages" || rc=1
  memcheck resume run --resume "$out/stages/checkpoint" --set time.end=0.007 || rc=1
  # hopper: mesh walls (hopper and gate), the gate's motion table, the stage that removes it
  memcheck hopper run cases/hopper.yaml --out "$out/hopper" --set time.end=0.02 \
    --set particles.0.count=100 --set stages.0.duration=0.01 --set output.frame_interval=0.005 \
    --set output.csv_interval=0.001 --set output.checkpoint_interval=0.005 \
    --set output.plot=false --set output.plot_loads=false || rc=1
  [ "$rc" -eq 0 ] && echo "soak.sh: memcheck clean" >&2 || echo "soak.sh: memcheck found errors" >&2
  return "$rc"
}

run_soak() {
  local steps=$1
  build_adem
  local out=$build/soak-out csv=$build/rss.csv
  rm -rf "$out"
  # the proposed step of the case, to turn steps into a simulated end time
  local dt size=(--set pours.0.rate=3000 --set 'pours.0.radius.values=[0.008, 0.01, 0.012]')
  dt=$("$build/adem" check cases/packing.yaml "${size[@]}" | awk '/chosen step/ {print $3; exit}')
  local end
  end=$(awk -v n="$steps" -v dt="$dt" 'BEGIN {printf "%.9g", n * dt}')
  echo "soak.sh: cases/packing.yaml for $steps steps of $dt s (time.end = $end s), RSS every $every s into $csv" >&2
  nice -n 10 "$build/adem" run cases/packing.yaml "${size[@]}" --out "$out" --set time.end="$end" \
    --set output.frame_interval="$(awk -v e="$end" 'BEGIN {printf "%.9g", e / 20}')" \
    --set output.checkpoint_interval="$(awk -v e="$end" 'BEGIN {printf "%.9g", e / 10}')" \
    --set output.csv_interval=0.01 --set output.plot=false --threads 1 --quiet &
  local pid=$! t0=$SECONDS
  echo "wall_s,sim_time_s,rss_kib,hwm_kib" >"$csv"
  while kill -0 "$pid" 2>/dev/null; do
    local rss hwm sim
    rss=$(awk '/^VmRSS:/ {print $2}' "/proc/$pid/status" 2>/dev/null || true)
    hwm=$(awk '/^VmHWM:/ {print $2}' "/proc/$pid/status" 2>/dev/null || true)
    sim=$(tail -n 1 "$out/timeseries.csv" 2>/dev/null | cut -d, -f1 || true)
    [[ $sim =~ ^[0-9.e+-]+$ ]] || sim=0
    [ -n "$rss" ] && echo "$((SECONDS - t0)),$sim,$rss,$hwm" >>"$csv"
    sleep "$every"
  done
  local rc=0
  wait "$pid" || rc=$?
  [ "$rc" -eq 0 ] || { echo "soak.sh: the run failed (exit $rc)" >&2; return 1; }
  # Warm-up: up to 1.6 s simulated (the pour and both stages' changes are over) and the first
  # tenth of the samples; after it the RSS may not rise by more than 1 MiB.
  awk -F, -v warm_sim=1.6 'NR > 1 { t[++n] = $2; r[n] = $3; w[n] = $1 }
    END {
      if (n < 3) { print "soak.sh: too few samples"; exit 1 }
      k = int(n / 10); if (k < 1) k = 1
      while (k < n && t[k] < warm_sim) k++
      base = r[k]; top = base; last = r[n]
      for (i = k; i <= n; i++) if (r[i] > top) top = r[i]
      printf "soak.sh: %d samples over %d s; RSS %d KiB at the end of warm-up (t = %s s, sample %d), at most %d KiB after it, %d KiB at the end: growth %d KiB\n", n, w[n], base, t[k], k, top, last, top - base
      if (top - base > 1024) { print "soak.sh: memory grows after warm-up"; exit 1 }
      print "soak.sh: no growth after warm-up"
    }' "$csv" >&2
}

case ${1:-} in
  --valgrind) run_valgrind ;;
  -h | --help) sed -n '2,17p' "$0" | sed 's/^# \{0,1\}//' >&2 ;;
  *) run_soak "${1:-1000000}" ;;
esac
