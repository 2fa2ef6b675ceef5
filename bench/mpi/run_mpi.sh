#!/usr/bin/env bash
# adem on the peer bed with 1 and 2 MPI processes x 1 and 2 OpenMP threads (issue 15, docs/parallel.md):
# the time of a step from two runs of the same case with STEPS1 and STEPS2 steps, (T2 - T1) /
# (STEPS2 - STEPS1), so that reading the case, the set-up and the final output cancel; runs
# interleaved, REPS repetitions, medians. Needs an MPI build (cmake -DADEM_MPI=ON) and the bed
# (bench/peers/make_bed.sh N).
#   MPI_ADEM=build-mpi/adem MPI_N=100000 MPI_REPS=3 bench/mpi/run_mpi.sh
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
adem=$(realpath "${MPI_ADEM:-$here/../../build-mpi/adem}")
n=${MPI_N:-100000}
reps=${MPI_REPS:-3}
s1=${MPI_STEPS1:-100}
s2=${MPI_STEPS2:-300}
layouts=${MPI_LAYOUTS:-"1x1 1x2 2x1 2x2"} # processes x threads
data=${MPI_BED:-$here/../peers/beds/bed$n.data}
out=${MPI_OUT:-$here/runs/$(date +%Y%m%d-%H%M%S)}
root=$([ "$(id -u)" = 0 ] && echo --allow-run-as-root || true)
mkdir -p "$out"
[ -f "$data" ] || { echo "run_mpi.sh: no bed $data (bench/peers/make_bed.sh $n)" >&2; exit 1; }
"$here/bed_case.sh" "$data" "$out/bed-$s1.yaml" "$s1"
"$here/bed_case.sh" "$data" "$out/bed-$s2.yaml" "$s2"
echo "layout rep steps seconds" > "$out/times.txt"
for r in $(seq "$reps"); do
  for l in $layouts; do
    np=${l%x*} nt=${l#*x}
    for s in "$s1" "$s2"; do
      rm -rf "$out/run"
      t0=$(date +%s.%N)
      # Open MPI binds each process to one core by default: right for processes of one thread;
      # a process's second thread would share its core, so with threads, no binding
      bind=$([ "$nt" = 1 ] && echo core || echo none)
      OMP_NUM_THREADS=$nt mpirun $root --oversubscribe --bind-to "$bind" -np "$np" "$adem" run "$out/bed-$s.yaml" \
        --out "$out/run" --threads "$nt" > "$out/log-$l-$s-$r.txt" 2>&1
      t1=$(date +%s.%N)
      echo "$l $r $s $(echo "$t1 - $t0" | bc)" | tee -a "$out/times.txt"
    done
  done
done
# per layout: median over repetitions of (T2 - T1)/(S2 - S1), particle-steps per second
awk -v n="$n" -v s1="$s1" -v s2="$s2" '
  NR > 1 { t[$1 " " $2 " " $3] = $4; L[$1] = 1; R[$2] = 1 }
  END {
    for (l in L) {
      m = 0
      for (r in R) { v[++m] = (t[l " " r " " s2] - t[l " " r " " s1]) / (s2 - s1) }
      for (i = 2; i <= m; i++) for (j = i; j > 1 && v[j - 1] > v[j]; j--) { x = v[j]; v[j] = v[j - 1]; v[j - 1] = x }
      med = (m % 2) ? v[(m + 1) / 2] : (v[m / 2] + v[m / 2 + 1]) / 2
      printf "%s %.6f %.3f\n", l, med, n / med / 1e6
      delete v
    }
  }' "$out/times.txt" | sort > "$out/step.txt"
base=$(awk '$1 == "1x1" { print $2 }' "$out/step.txt")
echo
# efficiency: the speed-up over the cores the layout can use (processes x threads, at most the
# machine's cores; a layout with more is oversubscribed)
echo "| processes x threads | s per step | M particle-steps/s | speed-up over 1 x 1 | efficiency |"
echo "|---|---|---|---|---|"
awk -v b="$base" -v cores="$(nproc)" '{ split($1, a, "x"); p = a[1] * a[2]; if (p > cores) p = cores
  printf "| %s | %.5f | %.3f | %.2f | %.0f %% |\n", $1, $2, $3, b / $2, 100 * b / $2 / p }' "$out/step.txt"
# the exchanges of the longer runs, as adem reports them (one line per 2-process layout)
for l in $layouts; do
  f="$out/log-$l-$s2-1.txt"
  grep -h "split over" "$f" 2> /dev/null | sed "s/^/$l: /" || true
done
echo "run_mpi: logs in $out"
