# Writes a dense block of spheres as a LAMMPS data file (atom_style sphere) for bench/hashes.sh:
# side^3 spheres on a cubic lattice of pitch 0.99 d, each jittered by up to +-0.01 d along every
# axis, in a box whose walls touch the outer spheres. Every neighbour overlaps from the first
# step, so a short run goes through loading, sliding, rolling and opening contacts. The jitter
# comes from a Park-Miller generator (exact in double arithmetic): any awk gives the same file.
#   awk -v side=16 -v d=0.005 -v rho=2500 -f dense_bed.awk > dense.data
function uniform() { state = (16807 * state) % 2147483647; return state / 2147483647 }
BEGIN {
  if (side < 1 || d <= 0 || rho <= 0) { print "dense_bed.awk: need -v side= -v d= -v rho=" > "/dev/stderr"; exit 1 }
  state = 7
  h = 0.99 * d
  n = side * side * side
  L = side * h
  printf "LAMMPS data file: dense block of %d spheres, d = %g m (bench/dense_bed.awk)\n\n", n, d
  printf "%d atoms\n1 atom types\n\n", n
  printf "0 %.17g xlo xhi\n0 %.17g ylo yhi\n0 %.17g zlo zhi\n\n", L, L, L + 3 * d
  printf "Atoms # sphere\n\n"
  for (k = 0; k < n; k++) {
    ix = k % side; iy = int(k / side) % side; iz = int(k / (side * side))
    x = (ix + 0.5) * h + 0.02 * d * (uniform() - 0.5)
    y = (iy + 0.5) * h + 0.02 * d * (uniform() - 0.5)
    z = (iz + 0.5) * h + 0.02 * d * (uniform() - 0.5)
    printf "%d 1 %.15g %.15g %.17g %.17g %.17g\n", k + 1, d, rho, x, y, z
  }
}
