#!/usr/bin/env python3
"""Writes the hopper of the angle-of-repose case (Irazabal et al. 2017, section 4.2, Fig. 10) as
ASCII STL with named solids, for cases/irazabal/repose.yaml.

    python3 cases/irazabal/make_repose_hopper.py            # writes meshes/repose_*.stl here

What the paper fixes: a square aperture of 25 cm side whose outlet is 0.7 m above the floor (layout
after Chen et al. 2014, Soils Found. 54(1) 1-11, which we could not obtain). What we choose (the
parameters below):
- a square pyramidal funnel (four flat walls) under a vertical square bin, both centred on the
  z axis, so the pile forms around the axis the analysis uses;
- walls at 60 degrees from the horizontal: steeper than the spheres' sliding angle
  (atan 0.6 = 31 deg) and far steeper than what BROF holds (atan 0.25 = 14 deg), so nothing
  stays on a wall; it is the usual mass-flow slope of a steep hopper;
- a funnel 0.3 m high (top side 0.25 + 2 * 0.3 / tan 60 = 0.596 m) and a bin 0.3 m high: room for
  a pour region of about 0.5 m x 0.5 m above the funnel, which spreads the feed over the funnel
  walls instead of dropping it straight through the outlet.
- a gate (a separate file): a square plate just under the outlet, for the fill-then-open variant
  (cases/irazabal/repose-gated.yaml) that shows why the main case pours into an open hopper.

Normals point into the hopper (right-hand rule on the vertex order), as in cases/meshes/hopper.stl.
"""
import math
import os

OUTLET_SIDE = 0.25        # m, square aperture side (paper)
OUTLET_Z = 0.70           # m, height of the outlet above the floor z = 0 (paper)
WALL_ANGLE_DEG = 60.0     # funnel walls against the horizontal (chosen)
FUNNEL_HEIGHT = 0.30      # m (chosen)
BIN_HEIGHT = 0.30         # m, vertical walls above the funnel (chosen)
GATE_SIDE = 0.35          # m, square plate under the outlet (fill-then-open variant only)
GATE_GAP = 0.002          # m, between the outlet and the gate's top face

HERE = os.path.dirname(os.path.abspath(__file__))
OUT_DIR = os.path.join(HERE, "meshes")


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def unit(a):
    n = math.sqrt(a[0] ** 2 + a[1] ** 2 + a[2] ** 2)
    return (a[0] / n, a[1] / n, a[2] / n)


def fmt(x):
    s = "%.9g" % x
    return "0" if s == "-0" else s


def solid(name, triangles):
    lines = ["solid %s" % name]
    for t in triangles:
        n = unit(cross(sub(t[1], t[0]), sub(t[2], t[0])))
        lines.append("  facet normal %s %s %s" % tuple(fmt(c) for c in n))
        lines.append("    outer loop")
        for v in t:
            lines.append("      vertex %s %s %s" % tuple(fmt(c) for c in v))
        lines.append("    endloop")
        lines.append("  endfacet")
    lines.append("endsolid %s" % name)
    return "\n".join(lines) + "\n"


def square(half, z):
    """Corners of a square of half-side HALF at height Z, counter-clockwise seen from above."""
    return [(-half, -half, z), (half, -half, z), (half, half, z), (-half, half, z)]


def ring(lower, upper):
    """Four quadrilateral walls between two squares, two triangles each, normals inwards."""
    tris = []
    for k in range(4):
        a, b = lower[k], lower[(k + 1) % 4]
        c, d = upper[(k + 1) % 4], upper[k]
        # the lower edge a->b runs counter-clockwise seen from above: (d - a) x (b - a) points
        # inwards, so the triangles are listed a, d, c and a, c, b
        tris.append((a, d, c))
        tris.append((a, c, b))
    return tris


def hopper_triangles():
    a = 0.5 * OUTLET_SIDE
    top_half = a + FUNNEL_HEIGHT / math.tan(math.radians(WALL_ANGLE_DEG))
    z1 = OUTLET_Z + FUNNEL_HEIGHT
    z2 = z1 + BIN_HEIGHT
    funnel = ring(square(a, OUTLET_Z), square(top_half, z1))
    binwalls = ring(square(top_half, z1), square(top_half, z2))
    return funnel, binwalls, top_half, z1, z2


def gate_triangles():
    h = 0.5 * GATE_SIDE
    z = OUTLET_Z - GATE_GAP
    c = square(h, z)
    return [(c[0], c[1], c[2]), (c[0], c[2], c[3])]  # normal +z: towards the hopper


def inward_check(triangles):
    """Every wall normal must point towards the axis (its horizontal part, against the centroid)."""
    for t in triangles:
        n = cross(sub(t[1], t[0]), sub(t[2], t[0]))
        cx = (t[0][0] + t[1][0] + t[2][0]) / 3.0
        cy = (t[0][1] + t[1][1] + t[2][1]) / 3.0
        if n[0] * cx + n[1] * cy >= 0.0:
            raise SystemExit("a wall normal points outwards: %r" % (t,))


def main():
    funnel, binwalls, top_half, z1, z2 = hopper_triangles()
    inward_check(funnel + binwalls)
    os.makedirs(OUT_DIR, exist_ok=True)
    hopper_path = os.path.join(OUT_DIR, "repose_hopper.stl")
    gate_path = os.path.join(OUT_DIR, "repose_gate.stl")
    with open(hopper_path, "w") as f:
        f.write(solid("funnel", funnel))
        f.write(solid("bin", binwalls))
    with open(gate_path, "w") as f:
        f.write(solid("gate", gate_triangles()))
    print("%s: funnel %.3f m square outlet at z = %.3f m, walls %.1f deg, top %.4f m square at "
          "z = %.3f m; bin to z = %.3f m"
          % (os.path.relpath(hopper_path), OUTLET_SIDE, OUTLET_Z, WALL_ANGLE_DEG, 2 * top_half,
             z1, z2))
    print("%s: %.3f m square plate at z = %.3f m" % (os.path.relpath(gate_path), GATE_SIDE,
                                                      OUTLET_Z - GATE_GAP))


if __name__ == "__main__":
    main()
