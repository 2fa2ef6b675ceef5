#!/usr/bin/env bash
# Builds everything (library, command, tests, benchmarks, examples) with clang and -Werror in
# build-clang (CI: .ci/run). gcc's -Werror build is scripts/setup.sh test's. Exits non-zero on
# the first warning. JOBS=N compiles N at a time (default: every core).
set -euo pipefail
cd "$(dirname "$0")/.."

missing=()
for p in clang libomp-dev cmake pkg-config libyaml-dev libcmocka-dev; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "clang-werror.sh: installing ${missing[*]}" >&2
  sudo_cmd=""
  [ "$(id -u)" -ne 0 ] && sudo_cmd="sudo"
  $sudo_cmd apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
jobs=${JOBS:-$(nproc 2>/dev/null || echo 2)}
CC=clang cmake -S . -B build-clang -DCMAKE_BUILD_TYPE=Release -DADEM_WERROR=ON >/dev/null
cmake --build build-clang -j"$jobs"
echo "clang-werror.sh: clang $(clang -dumpversion), -Wall -Wextra -Werror: no warning" >&2
