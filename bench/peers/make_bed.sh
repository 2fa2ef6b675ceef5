#!/bin/sh
# make_bed.sh N [BEDS_DIR]
# Makes the settled peer bed of N spheres once: BEDS_DIR/bedN.data (LAMMPS data file,
# atom_style sphere: id type diameter density x y z) and BEDS_DIR/emptyN.data (the same box with
# one sphere, for the "empty" runs that measure each code's baseline memory). Default BEDS_DIR:
# bench/peers/beds (ignored by git: rerun this script instead of committing beds).
#   1. lattice.awk: bench_bed.c's jittered lattice, deterministic;
#   2. settle.lmp: LAMMPS drops it under gravity with the Hertz bed's physics until the mean
#      translational kinetic energy per sphere is below PEERS_KE_STOP (default 1e-10 J);
#   3. optionally PEERS_SETTLE_ROUNDS times (default 0): velocities and every contact history
#      reset, then PEERS_SETTLE_ROUND_STEPS steps (default 5000), meant to leave a bed that also
#      rests when a code restarts it from positions alone (see settle.lmp; on the 1,000-sphere bed
#      three rounds did not calm LAMMPS' restart, so it is off);
#   4. the positions go to the data file at full precision; the box top is the highest centre
#      plus 3 diameters.
# Environment: PEERS_LMP (default lmp), PEERS_SETTLE_NP (MPI ranks for settling, default 1: the
# bed then does not depend on the machine's core count), PEERS_NICE (default 10).
set -eu
here=$(cd "$(dirname "$0")" && pwd)
. "$here/params.sh"
[ $# -ge 1 ] || { echo "usage: $0 N [BEDS_DIR]" >&2; exit 2; }
n=$1
beds=${2:-$here/beds}
lmp=${PEERS_LMP:-lmp}
np=${PEERS_SETTLE_NP:-1}
mkdir -p "$beds"
work="$beds/settle$n"
mkdir -p "$work"
write_params "$work/params.in"
awk -v n="$n" -v d="$PEERS_DIAMETER" -v rho="$PEERS_DENSITY" -f "$here/lattice.awk" > "$work/lattice.data"

mpi="mpirun -np $np"
[ "$(id -u)" = 0 ] && mpi="$mpi --allow-run-as-root"
echo "make_bed: settling $n spheres with $lmp on $np rank(s); log in $work/settle.log" >&2
start=$(date +%s)
OMP_NUM_THREADS=1 nice -n "${PEERS_NICE:-10}" $mpi "$lmp" -in "$here/settle.lmp" -log "$work/settle.log" \
  -screen none -var params "$work/params.in" -var lattice "$work/lattice.data" \
  -var dump "$work/settled.dump" -var peers "$here" -var ke_stop "${PEERS_KE_STOP:-1e-10}" \
  -var rounds "${PEERS_SETTLE_ROUNDS:-0}" -var round_steps "${PEERS_SETTLE_ROUND_STEPS:-5000}"
grep -h '^SETTLED\|^ROUND' "$work/settle.log" >&2
echo "make_bed: $(($(date +%s) - start)) s" >&2

# dump (ITEM: ATOMS id type diameter x y z) -> data file
awk -v n="$n" -v rho="$PEERS_DENSITY" -v d="$PEERS_DIAMETER" -v src="$work/settle.log" '
  /^ITEM: BOX BOUNDS/ { box = 1; next }
  box && NF == 2 { b[++nb] = $2; if (nb == 3) box = 0; next }
  /^ITEM: ATOMS/ { atoms = 1; next }
  atoms { id[++m] = $1; dia[m] = $3; x[m] = $4; y[m] = $5; z[m] = $6; if ($6 > zmax) zmax = $6 }
  END {
    if (m != n) { printf "make_bed: %d spheres in the dump, expected %d\n", m, n > "/dev/stderr"; exit 1 }
    printf "LAMMPS data file: adem peer bed, %d spheres of d = %g m settled under gravity (bench/peers/make_bed.sh)\n\n", n, d
    printf "%d atoms\n1 atom types\n\n", n
    printf "0 %s xlo xhi\n0 %s ylo yhi\n0 %.6g zlo zhi\n\n", b[1], b[2], zmax + 3 * d
    printf "Atoms # sphere\n\n"
    for (k = 1; k <= m; k++) printf "%d 1 %.15g %.15g %s %s %s\n", id[k], dia[k], rho, x[k], y[k], z[k]
  }' "$work/settled.dump" > "$beds/bed$n.data.tmp"
mv "$beds/bed$n.data.tmp" "$beds/bed$n.data"
# the "empty" box: same header and the bed's first sphere only (it rests on the floor in a
# corner); LIGGGHTS 3.8 refuses to run with no atoms at all
awk '/^Atoms/ { atoms = 1; print; next } atoms && NF == 7 { print; exit } / atoms$/ { print "1 atoms"; next }
     NR == 1 { print "LAMMPS data file: the box of the peer bed with its first sphere only (bench/peers/make_bed.sh)"; next }
     { print }' "$beds/bed$n.data" > "$beds/empty$n.data"
echo "make_bed: wrote $beds/bed$n.data and $beds/empty$n.data" >&2
