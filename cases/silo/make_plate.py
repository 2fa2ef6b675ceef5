#!/usr/bin/python3
"""Writes the silo's floor: a square plate with a square hole in its middle, as an ASCII STL
(8 triangles, z = 0). Usage: make_plate.py WIDTH HOLE OUT.stl (metres), e.g.
  cases/silo/make_plate.py 0.064 0.024 cases/silo/plate-24mm.stl
"""
import sys


def plate(width, hole):
    a, b = width / 2.0, hole / 2.0
    outer = [(-a, -a), (a, -a), (a, a), (-a, a)]
    inner = [(-b, -b), (b, -b), (b, b), (-b, b)]
    tris = []
    for k in range(4):  # one trapezoid per side, two triangles each, counter-clockwise from +z
        o0, o1, i0, i1 = outer[k], outer[(k + 1) % 4], inner[k], inner[(k + 1) % 4]
        tris.append((o0, o1, i1))
        tris.append((o0, i1, i0))
    return tris


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    width, hole, out = float(sys.argv[1]), float(sys.argv[2]), sys.argv[3]
    if not 0.0 < hole < width:
        sys.exit("the hole must be narrower than the plate")
    with open(out, "w") as f:
        f.write("solid plate\n")
        for t in plate(width, hole):
            f.write("  facet normal 0 0 1\n    outer loop\n")
            for x, y in t:
                f.write(f"      vertex {x:.9g} {y:.9g} 0\n")
            f.write("    endloop\n  endfacet\n")
        f.write("endsolid plate\n")


if __name__ == "__main__":
    main()
