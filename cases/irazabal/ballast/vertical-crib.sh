#!/usr/bin/env bash
# Issue 30, item 5 (see docs/validation.md): does Fig. 17's shoulder take the most load from about 1 mm
# when the sleeper's crib faces are vertical? The shared packing was made around the trapezoidal
# sleeper (0.30 m base, 0.22 m top), so a sleeper of another section needs its own packing:
# the geometry is made again with a prismatic sleeper 0.30 m wide (make_geometry.py --set
# sleeper_top_width=0.30; the auxiliary sleeper follows it), packed (pack.yaml, 1,269 s on
# one core) and pushed once at 17.7 GPa with the settings irazabal-fig17 uses for that
# modulus (src/studies/validate_ballast.c: E raised in steps of 3, dt 5 us, servo gain
# 1e-6 (1.77e9 / E)^(2/3) 6 = 1.29266e-6, to 0.50 s = 6.1 mm). Resumable: run it again and an
# interrupted step continues from its checkpoint, a finished one is skipped.
#
#   nice -n 19 cases/irazabal/ballast/vertical-crib.sh [OUT]      # default out/vertical-crib
#
# The face groups' forces are the sleeper's columns of OUT/push-E17.7/timeseries.csv
# (sleeper__base_*, sleeper__crib_front_*, ...); `adem analyze push` reads the shares at 1, 3 and 6 mm and
# the displacement where the shoulder overtakes the cribs as irazabal-fig17 reads them.
# Measured on 2026-11-28 (docs/validation.md, "Fig. 17's shoulder with vertical crib faces"):
# the push took about 45 min of one core (two segments); the shoulder never carries the most.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../../.." && pwd)
out=${1:-out/vertical-crib}
adem=${ADEM:-$root/build/adem}
mkdir -p "$out"
if [ ! -f "$out/pack.yaml" ]; then
  cp "$here/pack.yaml" "$here/push.yaml" "$out/"
  /usr/bin/python3 "$here/make_geometry.py" --set sleeper_top_width=0.30 --out "$out/meshes"
fi
step() { # dir end args...
  local dir=$1 end=$2; shift 2
  if [ -f "$dir/finished" ]; then return; fi
  if [ -f "$dir/checkpoint" ]; then "$adem" run --resume "$dir" --threads 1
  else "$adem" run "$@" --out "$dir" --threads 1; fi
  touch "$dir/finished"
}
step "$out/pack" 2.5 "$out/pack.yaml"
E=17700000000  # Pa (bc reads no exponent)
step "$out/push-E17.7" 0.5 "$out/push.yaml" \
  --set particles.0.file=pack/checkpoint \
  --set materials.ballast.youngs_modulus=$(echo "$E / 27" | bc -l) \
  --set "stages.stiffen-e9.set={materials.ballast.youngs_modulus: $(echo "$E / 9" | bc -l)}" \
  --set "stages.stiffen-e3.set={materials.ballast.youngs_modulus: $(echo "$E / 3" | bc -l)}" \
  --set "stages.settle.set={materials.ballast.youngs_modulus: $E}" \
  --set time.step=5e-6 --set time.end=0.5 --set walls.sleeper.motion.servo.gain=1.29266e-6
# Fig. 17's shares and the crossing, as irazabal-fig17 reads them (push-E17.7/shares.csv, .png)
"$adem" analyze push "$out/push-E17.7"
