#!/usr/bin/env bash
# One-step set-up on a fresh Debian 12 machine (as root):
#   scripts/setup.sh demo   install what is missing, build (Release), run the flagship example
#   scripts/setup.sh test   install what is missing, build (Release, warnings are errors), run the
#                           whole test suite
#   scripts/setup.sh mpi-test   the same with Open MPI: the MPI build (build-mpi, ADEM_MPI=ON)
#                               and its tests under mpirun (ctest -L mpi; docs/parallel.md)
# Settings (environment): JOBS=N compiles and tests N at a time (default: every core);
# THREADS=N runs the flagship example on N threads (default: OMP_NUM_THREADS or every core).
set -euo pipefail
cd "$(dirname "$0")/.."

what=${1:-demo}
packages=(build-essential cmake pkg-config libyaml-dev libcmocka-dev libomp-dev gnuplot-nox
          python3 python3-numpy python3-pytest python3-matplotlib)
[ "$what" = mpi-test ] && packages+=(libopenmpi-dev openmpi-bin)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "adem setup: installing ${missing[*]}"
  sudo_cmd=""
  [ "$(id -u)" -ne 0 ] && sudo_cmd="sudo"
  $sudo_cmd apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

jobs=${JOBS:-$(nproc 2>/dev/null || echo 2)}
case "$jobs" in '' | *[!0-9]* | 0) echo "adem setup: JOBS must be a positive whole number, not '$jobs'" >&2; exit 2 ;; esac
threads=()
if [ -n "${THREADS:-}" ]; then
  case "$THREADS" in *[!0-9]* | 0) echo "adem setup: THREADS must be a positive whole number, not '$THREADS'" >&2; exit 2 ;; esac
  threads=(--threads "$THREADS")
fi
if [ "$what" = mpi-test ]; then
  cmake -S . -B build-mpi -DCMAKE_BUILD_TYPE=Release -DADEM_MPI=ON >/dev/null
  cmake --build build-mpi -j"$jobs"
  ctest --test-dir build-mpi --output-on-failure -L mpi # under mpirun: one test at a time
  exit 0
fi
# The test build treats every warning as an error (ADEM_WERROR); the demo's does not.
werror=OFF
[ "$what" = test ] && werror=ON
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DADEM_WERROR=$werror >/dev/null
cmake --build build -j"$jobs"

# `import adem` in Debian's python3: a .pth file in the user's site-packages names this
# checkout's python/ folder (the module loads build/libadem.so.0 next to it), as an editable
# install would; rm it to undo. `cmake --install build` installs the module for good instead.
site=$(/usr/bin/python3 -c 'import site; print(site.getusersitepackages())')
mkdir -p "$site"
echo "$(pwd)/python" > "$site/adem.pth"
/usr/bin/python3 -c 'import adem; print("adem setup: import adem works (python3, module in %s, library %s)" % (adem.__path__[0], adem.library_path()))'

case "$what" in
  demo)
    ./build/adem run cases/hopper.yaml --out out/hopper "${threads[@]}"
    echo "adem setup: frames in out/hopper/particles.pvd and out/hopper/mesh.pvd (open in ParaView), plot in out/hopper/loads.png"
    ;;
  test)
    ctest --test-dir build --output-on-failure -j"$jobs"
    ;;
  *)
    echo "usage: scripts/setup.sh demo|test|mpi-test" >&2
    exit 2
    ;;
esac
