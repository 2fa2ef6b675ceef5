# Writes the starting lattice of the peer bed as a LAMMPS data file (atom_style sphere).
# The layout is bench/bench_bed.c's: side = ceil(sqrt(N/20)) columns a side, pitch 2.2 r, about
# 20 layers; x and y jittered by up to +-0.05 r so the bed does not crystallise. The jitter comes
# from a Park-Miller generator (exact in double arithmetic), so any awk gives the same file.
#   awk -v n=N -v d=DIAMETER -v rho=DENSITY [-v seed=1] -f lattice.awk > lattice.data
function uniform() { state = (16807 * state) % 2147483647; return state / 2147483647 }
BEGIN {
  if (n < 1 || d <= 0 || rho <= 0) { print "lattice.awk: need -v n= -v d= -v rho=" > "/dev/stderr"; exit 1 }
  state = (seed > 0) ? seed : 1
  r = d / 2; h = 2.2 * r
  side = int(sqrt(n / 20)); if (side * side * 20 < n) side++
  layers = int((n + side * side - 1) / (side * side))
  L = side * h
  top = layers * h + 2 * d          # room above the lattice while it falls
  printf "LAMMPS data file: adem peer bed, starting lattice of %d spheres, d = %g m (bench/peers/lattice.awk)\n\n", n, d
  printf "%d atoms\n1 atom types\n\n", n
  printf "0 %.17g xlo xhi\n0 %.17g ylo yhi\n0 %.17g zlo zhi\n\n", L, L, top
  printf "Atoms # sphere\n\n"
  for (k = 0; k < n; k++) {
    ix = k % side; iy = int(k / side) % side; iz = int(k / (side * side))
    x = (ix + 0.5) * h + 0.1 * r * (uniform() - 0.5)
    y = (iy + 0.5) * h + 0.1 * r * (uniform() - 0.5)
    z = (iz + 0.5) * h
    printf "%d 1 %.15g %.15g %.17g %.17g %.17g\n", k + 1, d, rho, x, y, z
  }
}
