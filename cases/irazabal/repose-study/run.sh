#!/usr/bin/env bash
# Issue 30's screen of the angle of repose: how the pile is built, the floor, the pile's size and
# the stiffness, each point a run of cases/irazabal/repose.yaml (or inlet.yaml) with --set
# changes, >= 3 seeds a point, one folder per run. Resumable: a finished run (its folder holds
# `done`) is never run again; an interrupted one continues from its checkpoint (bit for bit the
# run that never stopped). Measures: `adem analyze repose` (docs/validation.md, "The measure").
#
#   cases/irazabal/repose-study/run.sh                      # start (refuses an existing OUT)
#   cases/irazabal/repose-study/run.sh --resume             # go on where it stopped
#   cases/irazabal/repose-study/run.sh --resume --only 'floor-eta'   # only points matching
#   (two instances with disjoint --only patterns or --seeds may run side by side)
#   cases/irazabal/repose-study/run.sh --resume --only '^full-eta0.25$' --seeds 2018  # one seed
#   cases/irazabal/repose-study/run.sh --list               # every run and whether it is done
#   cases/irazabal/repose-study/run.sh --analyze            # measure every finished run again
#                                                           # (with --bin, default build/adem)
#   /usr/bin/python3 cases/irazabal/repose-study/summarize.py OUT   # table: mean, sd per point
#
# Options: --out DIR (default out/repose-study), --bin ADEM (default build/adem, copied into
# OUT/adem once so that a rebuild cannot change a study half way), --threads N (default 1),
# --seeds 'S ...' (only these of the seeds 2017 2018 2019).
# Run it under `nice -n 19` on a shared machine. Each run's wall time (every segment, resumed
# ones added) is in RUN/wall_s; the sum over a run is in the summary.
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../../.." && pwd)
out=out/repose-study
bin=$root/build/adem
resume=0
only=''
list=0
analyze=0
threads=1
seedsel=''
while [ $# -gt 0 ]; do
  case $1 in
    --resume) resume=1 ;;
    --out) out=$2; shift ;;
    --bin) bin=$2; shift ;;
    --only) only=$2; shift ;;
    --list) list=1 ;;
    --analyze) analyze=1 ;;
    --threads) threads=$2; shift ;;
    --seeds) seedsel=$2; shift ;;
    -h|--help) sed -n '2,19p' "$0"; exit 0 ;;
    *) echo "run.sh: unknown option '$1' (see --help)" >&2; exit 2 ;;
  esac
  shift
done

# The quick screen: E/100 with the step that stiffness proposes (issue 12 measured under 0.4 deg
# between E/100 and full stiffness on one seed; point E17.7 measures it again on 3 seeds),
# 400 spheres unless the point says otherwise, the run ending when at rest (time.until) or
# 8 s after the pour.
quick=(materials.ballast.stiffness_factor=0.01 time.step=auto output.frame_interval=0.5
       output.checkpoint_interval=1 output.csv_interval=0.05 output.plot=false output.plot_loads=false)
seeds=(2017 2018 2019)
if [ -n "$seedsel" ]; then read -r -a seeds <<< "$seedsel"; fi

# name | case | --set changes (besides the quick ones, seed and the pour's end). Rate r and count
# n: pours.feed.end = n / r.
# With little rolling friction on the floor a sphere rolls 7 v^2 / (10 eta g) (28 m at 2 m/s and
# eta 0.01) and would leave repose.yaml's 3 m domain (a run stopped so: floor eta 0.05, seed
# 2017, at 3.2 s): those points get a domain of +-40 m (the neighbour grid spans the particles,
# not the domain, so this costs nothing until a sphere is that far).
wide="domain.min=[-40,-40,-0.5] domain.max=[40,40,2]"
# Tier 1 first (every seed of the cheap points), then tier 2, then tier 3, so that a stopped
# screen has whole points rather than one seed of everything.
points=(
  "1|pour100|repose.yaml|rate=100 n=400"
  "1|feed400|repose.yaml|rate=400 n=400"
  "1|feed800|repose.yaml|rate=800 n=400"
  "1|inlet|repose-study/inlet.yaml|rate=100 n=400"
  "1|floor-eta0.05|repose.yaml|rate=100 n=400 interactions.2.rolling_friction=0.05 $wide"
  "1|floor-eta0.01|repose.yaml|rate=100 n=400 interactions.2.rolling_friction=0.01 $wide"
  "1|floor-mu0.3|repose.yaml|rate=100 n=400 interactions.2.friction=0.3"
  "2|n800|repose.yaml|rate=100 n=800"
  "2|E17.7|repose.yaml|rate=100 n=400 full"
  "3|n1600|repose.yaml|rate=100 n=1600"
  # A rough floor of fixed spheres (frozen particles): rough-floor.yaml, written by
  # make_rough_floor.py (the case with a layer of ballast spheres half sunk in the plane floor).
  # Its 476 frozen spheres would count in time.until's energy per particle if the engine counted
  # them: the threshold is scaled by 400 / 876 so that the free spheres meet at least the case's.
  "1|rough-floor|repose-study/rough-floor.yaml|rate=100 n=400 time.until.kinetic_energy_per_particle=4.5e-8"
  # Fig. 11 at paper scale (issue 30, item 3): repose.yaml as it is, 1,600 spheres, full
  # stiffness with Table 2's step for each E (docs/validation.md, "Fig. 11 at paper scale").
  "4|full-eta0.25|repose.yaml|rate=100 n=1600 full"
  "4|full-eta0.20|repose.yaml|rate=100 n=1600 full materials.ballast.rolling_friction=0.2"
  "4|full-eta0.30|repose.yaml|rate=100 n=1600 full materials.ballast.rolling_friction=0.3"
  "4|full-E5.9|repose.yaml|rate=100 n=1600 full materials.ballast.youngs_modulus=5.9e9 time.step=8e-6"
  "4|full-E11.8|repose.yaml|rate=100 n=1600 full materials.ballast.youngs_modulus=11.8e9 time.step=6e-6"
  "4|full-E23.6|repose.yaml|rate=100 n=1600 full materials.ballast.youngs_modulus=23.6e9 time.step=4e-6"
  # The screen's decisive points confirmed at paper scale (issue 30, item 2): no hopper, and the
  # floor's rolling friction at 0.05.
  "5|full-inlet|repose-study/inlet.yaml|rate=100 n=1600 full"
  "5|full-floor-eta0.05|repose.yaml|rate=100 n=1600 full interactions.2.rolling_friction=0.05 $wide"
)

mkdir -p "$out"
if [ $list = 0 ] && [ $analyze = 0 ]; then
  if [ $resume = 0 ] && ls "$out"/*-s* >/dev/null 2>&1; then
    echo "run.sh: $out already holds runs; go on with --resume (or choose another --out)" >&2
    exit 2
  fi
  if [ ! -x "$out/adem" ]; then cp "$bin" "$out/adem"; fi
fi
adem=$out/adem
[ -x "$adem" ] || adem=$bin
# measuring again takes the given (or built) binary: the measures may have changed, not the runs
if [ $analyze = 1 ]; then adem=$bin; fi

measure() { # dir
  "$adem" analyze repose "$1" --zmax 0.65 > "$1/measure.txt" 2>&1 || echo "analyze failed: $1" >&2
}

for tier in 1 2 3 4 5; do
for seed in "${seeds[@]}"; do
  for p in "${points[@]}"; do
    IFS='|' read -r ptier name case spec <<< "$p"
    if [ "$ptier" != $tier ]; then continue; fi
    if [ -n "$only" ] && ! [[ $name =~ $only ]]; then continue; fi
    dir=$out/$name-s$seed
    if [ $list = 1 ]; then
      if [ -f "$dir/done" ]; then echo "done     $name seed $seed ($(cat "$dir/wall_s" | paste -sd+ | bc) s)"
      elif [ -f "$dir/checkpoint" ]; then echo "started  $name seed $seed"
      else echo "to run   $name seed $seed"; fi
      continue
    fi
    if [ $analyze = 1 ]; then
      if [ -f "$dir/done" ]; then measure "$dir"; fi
      continue
    fi
    if [ -f "$dir/done" ]; then continue; fi
    mkdir -p "$dir"
    t0=$(date +%s)
    if [ -f "$dir/checkpoint" ]; then
      echo "$(date -u +%H:%M:%S) resume $name seed $seed"
      rc=0; "$adem" run --resume "$dir" --threads "$threads" --quiet || rc=$?
    else
      rate=100 n=400 full=0 sets=()
      for kv in $spec; do
        case $kv in
          rate=*) rate=${kv#rate=} ;;
          n=*) n=${kv#n=} ;;
          full) full=1 ;;
          *) sets+=(--set "$kv") ;;
        esac
      done
      pend=$(echo "scale=6; $n / $rate" | bc)
      tend=$(echo "scale=6; $pend + 8" | bc)
      if [ $full = 0 ]; then for q in "${quick[@]}"; do sets+=(--set "$q"); done
      else for q in "${quick[@]:2}"; do sets+=(--set "$q"); done; fi
      echo "$(date -u +%H:%M:%S) run $name seed $seed ($n spheres at $rate/s)"
      rc=0
      "$adem" run "$root/cases/irazabal/$case" --out "$dir" --threads "$threads" --quiet \
        --set seed="$seed" --set pours.feed.rate="$rate" --set pours.feed.end="$pend" \
        --set time.end="$tend" "${sets[@]}" || rc=$?
    fi
    echo $(( $(date +%s) - t0 )) >> "$dir/wall_s"
    if [ $rc != 0 ]; then
      echo "run.sh: $name seed $seed stopped with exit $rc; --resume goes on from its checkpoint" >&2
      exit $rc
    fi
    measure "$dir"
    touch "$dir/done"
  done
done
done
