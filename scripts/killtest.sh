#!/usr/bin/env bash
# Crash safety of adem's output, shown by killing runs (see docs/reliability.md):
#   scripts/killtest.sh [KILLS [SEED]]     default: 20 kills, seed 1
# 1. Runs a shortened hopper (mesh walls, a moving gate, frames, PVDs, CSV, checkpoints) once to a
#    reference folder.
# 2. KILLS times: starts it again and kills it with SIGKILL: the first third of the kills from
#    inside a chosen write (the shim tests/tools/adem_ioshim.c, at a seeded random call on a
#    frame, the PVD, the CSV or the checkpoint), the rest from outside at a seeded random moment
#    while the shim slows every write under the output folder so that kills land inside them.
#    After each kill every file of the folder must be complete (tests/tools/check_output.py);
#    then `adem run --resume` finishes the run and every file must equal the reference's bit
#    for bit.
# 3. Full disk: a small tmpfs (when a mount namespace can be had) and the shim's ENOSPC after N
#    bytes: the run must exit with 4, name the file in its message, and leave every file whole.
# Exit 0 when all of it holds. ADEM_KILLTEST_BUILD names the build folder (default build),
# ADEM_KILLTEST_KEEP=1 keeps the work folder.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD

kills=${1:-20}
seed=${2:-1}
build=${ADEM_KILLTEST_BUILD:-build}
adem=$root/$build/adem
if [ ! -x "$adem" ]; then
  cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
  nice -n 15 cmake --build "$build" -j"$(nproc)" --target adem_cli >/dev/null
fi
work=$(mktemp -d "${TMPDIR:-/tmp}/adem-killtest.XXXXXX")
[ "${ADEM_KILLTEST_KEEP:-0}" = 1 ] || trap 'rm -rf "$work"' EXIT
shim=$work/adem_ioshim.so
cc -shared -fPIC -O2 -o "$shim" tests/tools/adem_ioshim.c -ldl
# The checker uses VTK's readers too when a python with VTK is there (Debian's python3-vtk9 is for
# /usr/bin/python3); it is not needed.
py=python3
for cand in /usr/bin/python3 python3; do
  if "$cand" -c 'import vtk' 2>/dev/null; then py=$cand; break; fi
done
check=("$py" "$root/tests/tools/check_output.py")

# Every run writes to the same folder: the checkpoint stores its path, so the files of runs in
# one folder can be compared byte for byte.
run=$work/run
case_args=(run cases/hopper.yaml --set time.end=0.28 --set particles.0.count=400
           --set output.frame_interval=0.01 --set output.csv_interval=0.001
           --set output.checkpoint_interval=0.02 --set output.plot=false
           --set output.plot_loads=false --threads 1 --quiet)
delay_us=1000
RANDOM=$seed
rnd() { echo $(((RANDOM << 15 | RANDOM) % $1)); } # 0 .. $1 - 1

t0=$SECONDS
nice -n 15 "$adem" "${case_args[@]}" --out "$run"
mv "$run" "$work/ref"
"${check[@]}" "$work/ref" >/dev/null
echo "killtest: reference run: $(ls "$work/ref/frames" | wc -l) frame files, $(($(wc -l <"$work/ref/timeseries.csv") - 1)) CSV rows ($((SECONDS - t0)) s)"

# Calibration with the shim: the order of output calls (the same in every run) and their times.
t1=$(date +%s%N)
ADEM_SHIM_DIR=$run ADEM_SHIM_DELAY_US=$delay_us ADEM_SHIM_LOG=$work/calib.log LD_PRELOAD=$shim \
  nice -n 15 "$adem" "${case_args[@]}" --out "$run"
total_ms=$((($(date +%s%N) - t1) / 1000000))
rm -rf "$run"
# Calls after the first checkpoint is in place (a kill before it has nothing to resume from).
first_ckpt_us=$(awk '$2 == "+rename" && $3 == "checkpoint" {print $1; exit}' "$work/calib.log")
echo "killtest: slowed run takes $total_ms ms; first checkpoint at $((first_ckpt_us / 1000)) ms"

compare() { # files of $run against the reference: 0 when every one is equal
  local f bad=0
  while IFS= read -r f; do
    cmp -s "$work/ref/$f" "$run/$f" || { echo "    differs: $f"; bad=1; }
  done < <(cd "$work/ref" && find . -type f ! -name '.*' | sort)
  while IFS= read -r f; do
    [ -e "$work/ref/$f" ] || { echo "    extra file: $f"; bad=1; }
  done < <(cd "$run" && find . -type f ! -name '.*' | sort)
  return $bad
}

kinds=(frame pvd csv checkpoint)
targeted=$(((kills + 2) / 3))
corrupt_total=0
equal=0
declare -A landed=()
temps_total=0
printf 'killtest: %-4s %-34s %-52s %-7s %-5s %s\n' kill how "landed in" corrupt temps resume
for i in $(seq 1 "$kills"); do
  rm -rf "$run"
  if [ "$i" -le "$targeted" ]; then
    kind=${kinds[$(((i - 1) % 4))]}
    # The n-th shim call on a file of this kind, among those after the first checkpoint.
    count=$(awk -v k="$kind" -v t="$first_ckpt_us" '$3 == k && $2 !~ /^\+/ {n++; if ($1 > t) m++} END {print n " " m}' "$work/calib.log")
    read -r n_all n_after <<<"$count"
    nth=$((n_all - n_after + 1 + $(rnd "$n_after")))
    how="inside call $nth on a $kind file"
    set +e
    # (in a subshell, so that the shell's "Killed" notice goes nowhere)
    (ADEM_SHIM_DIR=$run ADEM_SHIM_KILL=$kind:$nth ADEM_SHIM_LOG=$work/kill.log LD_PRELOAD=$shim \
      nice -n 15 "$adem" "${case_args[@]}" --out "$run" 2>/dev/null; exit $?) 2>/dev/null
    rc=$?
    set -e
  else
    span=$((total_ms - first_ckpt_us / 1000))
    at=$((first_ckpt_us / 1000 + span * 5 / 100 + $(rnd $((span * 90 / 100)))))
    how="outside after $at ms"
    ADEM_SHIM_DIR=$run ADEM_SHIM_DELAY_US=$delay_us ADEM_SHIM_LOG=$work/kill.log LD_PRELOAD=$shim \
      nice -n 15 "$adem" "${case_args[@]}" --out "$run" 2>/dev/null &
    pid=$!
    sleep "$(awk -v ms="$at" 'BEGIN {printf "%.3f", ms / 1000}')"
    kill -KILL "$pid" 2>/dev/null || true
    set +e
    wait "$pid" 2>/dev/null
    rc=$?
    set -e
  fi
  # Where it landed: the last call the shim saw start and not return, else "between writes".
  last=$(grep -v 'SIGKILL-in' "$work/kill.log" | tail -1 || true)
  rm -f "$work/kill.log"
  if [ "$rc" -ne 137 ]; then
    where="(not killed: exit $rc)"
  elif [[ $(awk '{print $2}' <<<"$last") == +* ]]; then
    where="between writes (after $(awk '{print substr($2, 2) " " $3}' <<<"$last"))"
    landed[between]=$((${landed[between]:-0} + 1))
  else
    where="$(awk '{print $2 " of " $3}' <<<"$last") ($(basename "$(awk '{print $4}' <<<"$last")"))"
    k=$(awk '{print $3}' <<<"$last")
    landed[$k]=$((${landed[$k]:-0} + 1))
  fi
  verdict=$("${check[@]}" "$run" || true)
  ncorrupt=$(sed -n 's/.*; \([0-9]*\) corrupt;.*/\1/p' <<<"$verdict")
  corrupt_total=$((corrupt_total + ${ncorrupt:-1}))
  ntemps=$(sed -n 's/.*corrupt; \([0-9]*\) hidden.*/\1/p' <<<"$verdict")
  temps_total=$((temps_total + ${ntemps:-0}))
  [ "${ncorrupt:-1}" = 0 ] || grep '^corrupt:' <<<"$verdict" | sed 's/^/    /'
  if [ -f "$run/checkpoint" ]; then
    nice -n 15 "$adem" run --resume "$run/checkpoint" --threads 1 --quiet
    resumed="resumed"
  else
    nice -n 15 "$adem" "${case_args[@]}" --out "$run"
    resumed="restarted (no checkpoint yet)"
  fi
  if compare; then
    equal=$((equal + 1))
    resumed="$resumed, bitwise equal"
  else
    resumed="$resumed, DIFFERENT"
  fi
  printf 'killtest: %-4s %-34s %-52s %-7s %-5s %s\n' "$i" "$how" "$where" "${ncorrupt:-?}" "${ntemps:-?}" "$resumed"
done
summary=""
for k in "${!landed[@]}"; do summary+="$k ${landed[$k]}, "; done
echo "killtest: $kills kills (landed in: ${summary%, }); $corrupt_total corrupt files; $temps_total hidden temporary files left by the killed processes (never read); $equal of $kills resumes bitwise equal"
ok=1
[ "$corrupt_total" -eq 0 ] && [ "$equal" -eq "$kills" ] || ok=0

# ---- full disk
ref_bytes=$(du -sb "$work/ref" | cut -f1)
# disk_check RC STDERR_FILE: exit 4, a message naming a file of the folder, whole files only,
# no temporary file left behind.
disk_check() {
  local rc=$1 msg verdict
  msg=$(grep 'adem: error:' "$2" | head -1 || true)
  verdict=$("${check[@]}" "$run" || true)
  local temps
  temps=$(sed -n 's/.*corrupt; \([0-9]*\) hidden.*/\1/p' <<<"$verdict")
  local fine=1
  [ "$rc" -eq 4 ] || fine=0
  grep -q "$run/" <<<"$msg" || fine=0
  grep -q 'No space left on device' <<<"$msg" || fine=0
  grep -q '; 0 corrupt; ' <<<"$verdict" || fine=0
  [ "${temps:-1}" = 0 ] || fine=0
  echo "    exit $rc; ${msg:-no message}"
  echo "    ${verdict##*$'\n'}"
  return $((1 - fine))
}

disk_ok=0
disk_runs=0
# Real full disk: a tmpfs of a fraction of the output's size, mounted in a private mount
# namespace (root, or an unprivileged user namespace). The run and the checks happen inside.
if unshare -rm true 2>/dev/null || { [ "$(id -u)" -eq 0 ] && unshare -m true 2>/dev/null; }; then
  ns=(unshare -m)
  [ "$(id -u)" -eq 0 ] || ns=(unshare -rm)
  for pct in 20 50 80; do
    size_k=$((ref_bytes * pct / 100 / 1024))
    rm -rf "$run"
    mkdir -p "$run"
    set +e
    out=$("${ns[@]}" bash -c '
      mount -t tmpfs -o size='"$size_k"'k tmpfs "$1" || exit 99
      shift
      run=$1; shift
      nice -n 15 "$@" --out "$run" 2>"$run/../disk.err"; rc=$?
      echo "rc=$rc"
      '"$py"' '"$root"'/tests/tools/check_output.py "$run"
      ' _ "$run" "$run" "$adem" "${case_args[@]}")
    set -e
    rc=$(sed -n 's/^rc=//p' <<<"$out")
    disk_runs=$((disk_runs + 1))
    echo "killtest: full tmpfs of ${size_k} KiB ($pct% of the output):"
    # The checks ran inside the namespace; judge from their output.
    msg=$(grep 'adem: error:' "$work/disk.err" | head -1 || true)
    verdict=$(grep '^checked\|^corrupt' <<<"$out" || true)
    echo "    exit ${rc:-?}; ${msg:-no message}"
    echo "    $(tail -1 <<<"$verdict")"
    if [ "${rc:-0}" = 4 ] && grep -q "$run/" <<<"$msg" && grep -q 'No space left on device' <<<"$msg" &&
       grep -q '; 0 corrupt; 0 hidden' <<<"$verdict"; then
      disk_ok=$((disk_ok + 1))
    fi
  done
else
  echo "killtest: no mount namespace here: the tmpfs test is left out (the shim's ENOSPC stands in)"
fi
# The shim's ENOSPC: writes under the folder fail once a byte budget is used up.
for pct in 10 35 60 85; do
  budget=$((ref_bytes * pct / 100))
  rm -rf "$run"
  set +e
  ADEM_SHIM_DIR=$run ADEM_SHIM_ENOSPC=$budget LD_PRELOAD=$shim \
    nice -n 15 "$adem" "${case_args[@]}" --out "$run" 2>"$work/disk.err"
  rc=$?
  set -e
  disk_runs=$((disk_runs + 1))
  echo "killtest: ENOSPC from the shim after $budget bytes ($pct% of the output):"
  if disk_check "$rc" "$work/disk.err"; then disk_ok=$((disk_ok + 1)); fi
done
# A full disk inside a CSV row: only the CSV's writes count, and the budget ends mid-row.
csv_bytes=$(wc -c <"$work/ref/timeseries.csv")
rm -rf "$run"
set +e
ADEM_SHIM_DIR=$run ADEM_SHIM_ENOSPC=$((csv_bytes / 2)) ADEM_SHIM_ENOSPC_KIND=csv LD_PRELOAD=$shim \
  nice -n 15 "$adem" "${case_args[@]}" --out "$run" 2>"$work/disk.err"
rc=$?
set -e
disk_runs=$((disk_runs + 1))
echo "killtest: ENOSPC from the shim in the middle of a CSV row (after $((csv_bytes / 2)) CSV bytes):"
if disk_check "$rc" "$work/disk.err"; then disk_ok=$((disk_ok + 1)); fi
echo "killtest: full disk: $disk_ok of $disk_runs runs exit 4 with the file named and no file half-written"
[ "$disk_ok" -eq "$disk_runs" ] || ok=0
echo "killtest: took $((SECONDS - t0)) s"
[ "$ok" = 1 ] && echo "killtest: passed" || { echo "killtest: FAILED"; exit 1; }
