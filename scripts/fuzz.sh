#!/usr/bin/env bash
# Fuzzing adem's readers of outside data with libFuzzer (clang, ASan + UBSan); see fuzz/ and
# docs/reliability.md.
#   scripts/fuzz.sh TARGET SECONDS [LIBFUZZER_OPTION ...]
#                         fuzz one target (case, stl, checkpoint, resume) for SECONDS
#   scripts/fuzz.sh --ci [SECONDS]
#                         each target for SECONDS (default 20), then every regression input
#   scripts/fuzz.sh --replay   replay fuzz/regressions/TARGET/* through the fuzz build
#   scripts/fuzz.sh --dict     regenerate fuzz/case.dict from the schema table
# The build goes to build-fuzz (ADEM_FUZZ_BUILD overrides), the growing corpus to
# build-fuzz/corpus/TARGET, crashing inputs to build-fuzz/artifacts/TARGET/ and one line of
# figures per run to build-fuzz/fuzz-stats.txt. An input that crashes belongs in
# fuzz/regressions/TARGET/ once fixed: the test fuzz_replay_TARGET replays it in every build.
set -euo pipefail
cd "$(dirname "$0")/.."

build=${ADEM_FUZZ_BUILD:-build-fuzz}
targets=(case stl checkpoint resume)

usage() {
  sed -n '2,14p' "$0" | sed 's/^# \{0,1\}//' >&2
  exit 2
}

install_missing() {
  local missing=()
  for p in clang libclang-rt-14-dev cmake pkg-config libyaml-dev libcmocka-dev; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  if [ ${#missing[@]} -gt 0 ]; then
    echo "fuzz.sh: installing ${missing[*]}" >&2
    local sudo_cmd=""
    [ "$(id -u)" -ne 0 ] && sudo_cmd="sudo"
    $sudo_cmd apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq --no-install-recommends \
      "${missing[@]}" >/dev/null
  fi
}

build_fuzzers() {
  install_missing
  if [ ! -f "$build/CMakeCache.txt" ]; then
    CC=clang cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DADEM_FUZZ=ON \
      -DADEM_TESTS=OFF -DADEM_OPENMP=OFF -DADEM_SANITIZE=address,undefined >/dev/null
  fi
  local t names=(adem_fuzz_dict)
  for t in "${targets[@]}"; do names+=("fuzz_$t"); done
  nice -n 15 cmake --build "$build" -j"$(nproc)" --target "${names[@]}" >/dev/null
}

# Huge allocations (a count of 10^12 particles) return NULL and take adem's out-of-memory path
# instead of ending the fuzzer; leaks are findings.
export ASAN_OPTIONS=${ASAN_OPTIONS:-allocator_may_return_null=1:max_allocation_size_mb=1024:detect_leaks=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}

# Seed corpora: the case files and test inputs of the repository, and checkpoints and output
# folders the targets generate from fuzz/seeds (ADEM_FUZZ_SEEDS).
make_seeds() {
  local t=$1 dir=$build/seeds/$1
  rm -rf "$dir"
  mkdir -p "$dir"
  case $t in
    case)
      cp cases/*.yaml cases/irazabal/*.yaml tests/cli/data/*.yaml fuzz/seeds/case/*.yaml "$dir/"
      # --set strings follow the case text, each after a NUL byte.
      printf '%s\0time.end=0.01\0particles.0.count=20\0output.track=[0, 3]' "$(cat cases/pour.yaml)" \
        >"$dir/pour_sets"
      printf '%s\0stages.test.set={walls.pusher.active: false}\0walls.floor.point=[0, 0, -1e-3]' \
        "$(cat fuzz/seeds/case/stages_pour.yaml)" >"$dir/stages_sets"
      printf '%s\0walls.gate.motion.table=[[0, 0, 0, 0]]\0materials.steel.rigid=true' \
        "$(cat cases/hopper.yaml)" >"$dir/hopper_sets"
      ;;
    stl) cp tests/data/*.stl cases/meshes/*.stl "$dir/" ;;
    checkpoint | resume) ADEM_FUZZ_SEEDS=$dir "$build/fuzz/fuzz_$t" >/dev/null 2>&1 ;;
  esac
}

# run_target TARGET SECONDS [OPTIONS]: fuzz, and record executions and findings.
run_target() {
  local t=$1 secs=$2
  shift 2
  local corpus=$build/corpus/$t artifacts=$build/artifacts/$t log=$build/logs/fuzz_$t.log
  mkdir -p "$corpus" "$artifacts" "$build/logs"
  make_seeds "$t"
  # Fork mode (one job at a time) goes on past slow inputs and out-of-memory ones: a case may
  # legitimately ask for a million particles (guards against those are a later step). They are
  # counted and kept in the artifacts folder; a crash still stops the run.
  local opts=(-fork=1 -ignore_timeouts=1 -ignore_ooms=1 -max_total_time="$secs" -timeout=5
              -rss_limit_mb=2048 -artifact_prefix="$artifacts/")
  [ "$t" = case ] && opts+=(-dict=fuzz/case.dict -max_len=8192)
  [ "$t" = stl ] && opts+=(-max_len=16384)
  [ "$t" = checkpoint ] && opts+=(-max_len=32768)
  echo "fuzz.sh: fuzzing $t for $secs s (log: $log)" >&2
  local rc=0 start=$SECONDS marker=$build/logs/.start_$t
  touch "$marker"
  nice -n 15 timeout -k 10 $((secs + 120)) "$build/fuzz/fuzz_$t" "${opts[@]}" "$@" \
    "$corpus" "$build/seeds/$t" >"$log" 2>&1 || rc=$?
  # The last progress line of fork mode: "#EXECS: cov: N ft: N corp: N exec/s N
  # oom/timeout/crash: A/B/C time: Ss job: J dft_time: 0".
  local last execs cov slow
  last=$(grep -E '^#[0-9]+: cov:' "$log" | tail -1 || true)
  execs=$(sed -E 's/^#([0-9]+):.*/\1/' <<<"$last")
  cov=$(sed -E 's/.* cov: ([0-9]+) .*/\1/' <<<"$last")
  slow=$(sed -E 's/.*oom\/timeout\/crash: ([0-9]+\/[0-9]+\/[0-9]+).*/\1/' <<<"$last")
  printf '%s target=%s seconds=%s wall=%s execs=%s cov=%s oom/timeout/crash=%s corpus=%s exit=%s\n' \
    "$(date -u +%FT%TZ)" "$t" "$secs" $((SECONDS - start)) "${execs:-0}" "${cov:-?}" "${slow:-?}" \
    "$(find "$corpus" -type f | wc -l)" "$rc" | tee -a "$build/fuzz-stats.txt" >&2
  # A hang is a timeout too: every slow input of this run must be looked at.
  local slow_files
  slow_files=$(find "$artifacts" -newer "$marker" \( -name 'timeout-*' -o -name 'oom-*' -o -name 'slow-unit-*' \) | sort)
  [ -z "$slow_files" ] || printf 'fuzz.sh: slow inputs of this run (look at each; a hang is one too):\n%s\n' "$slow_files" >&2
  if [ "$rc" -ne 0 ]; then
    grep -E 'ERROR|runtime error|SUMMARY|Test unit written' "$log" | head -20 >&2
    echo "fuzz.sh: $t failed; fix it and keep the input in fuzz/regressions/$t/" >&2
  fi
  return "$rc"
}

replay() {
  local t rc=0 files
  for t in "${targets[@]}"; do
    mapfile -t files < <(find "fuzz/regressions/$t" -type f ! -name 'README*' | sort)
    [ ${#files[@]} -eq 0 ] && continue
    if "$build/fuzz/fuzz_$t" -runs=1 "${files[@]}" >"$build/logs/replay_$t.log" 2>&1; then
      echo "fuzz.sh: replayed ${#files[@]} regression input(s) of $t" >&2
    else
      echo "fuzz.sh: a regression input of $t fails again: see $build/logs/replay_$t.log" >&2
      rc=1
    fi
  done
  return "$rc"
}

[ $# -ge 1 ] || usage
case $1 in
  --dict)
    build_fuzzers
    "$build/fuzz/adem_fuzz_dict" >fuzz/case.dict
    echo "fuzz.sh: wrote fuzz/case.dict" >&2
    ;;
  --replay)
    build_fuzzers
    mkdir -p "$build/logs"
    replay
    ;;
  --ci)
    secs=${2:-20}
    build_fuzzers
    rc=0
    for t in "${targets[@]}"; do run_target "$t" "$secs" || rc=1; done
    replay || rc=1
    exit "$rc"
    ;;
  -h | --help) usage ;;
  *)
    [ $# -ge 2 ] || usage
    t=$1
    secs=$2
    shift 2
    [[ " ${targets[*]} " == *" $t "* ]] || { echo "fuzz.sh: no target $t (${targets[*]})" >&2; exit 2; }
    build_fuzzers
    run_target "$t" "$secs" "$@"
    ;;
esac
