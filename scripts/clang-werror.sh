#!/usr/bin/env bash
# Every C file of the build (library, command, tests, benchmarks, examples) through clang with
# -Wall -Wextra -Werror (CI: .ci/run; gcc's -Werror build is scripts/setup.sh test's). clang's
# warnings all come from its front end, so each file is checked with -fsyntax-only, its own
# flags taken from build-clang/compile_commands.json: 75 s on 2 loaded cores where building
# everything takes 581 s. The one generated file (the embedded cases) is compiled for real.
# Exits non-zero on the first file with a warning, printing it. JOBS=N checks N files at a time
# (default: every core).
set -euo pipefail
cd "$(dirname "$0")/.."

missing=()
for p in clang libomp-dev cmake pkg-config libyaml-dev libcmocka-dev python3; do
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
CC=clang cmake -S . -B build-clang -DCMAKE_BUILD_TYPE=Release -DADEM_WERROR=ON \
  -DCMAKE_EXPORT_COMPILE_COMMANDS=ON >/dev/null
cmake --build build-clang --target generated/embedded_cases.o >/dev/null
/usr/bin/python3 - build-clang/compile_commands.json "$jobs" <<'EOF'
import concurrent.futures, json, shlex, subprocess, sys

entries = [e for e in json.load(open(sys.argv[1])) if "/generated/" not in e["file"]]


def check(e):
    args, skip = [], False
    for a in shlex.split(e["command"]):
        if skip or a == "-c":
            skip = False
            continue
        if a == "-o":
            skip = True
            continue
        args.append(a)
    r = subprocess.run(args + ["-fsyntax-only"], cwd=e["directory"], capture_output=True, text=True)
    return e["file"], r.returncode, r.stderr


with concurrent.futures.ThreadPoolExecutor(int(sys.argv[2])) as pool:
    results = list(pool.map(check, entries))
bad = [r for r in results if r[1] or r[2]]
for f, rc, err in bad:
    print(err, end="", file=sys.stderr)
print("clang-werror.sh: %d files, %d with a warning or an error" % (len(results), len(bad)), file=sys.stderr)
sys.exit(1 if bad else 0)
EOF
echo "clang-werror.sh: clang $(clang -dumpversion), -Wall -Wextra -Werror: no warning" >&2
