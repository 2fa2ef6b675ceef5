#!/usr/bin/env python3
"""Writes rough-floor.yaml: cases/irazabal/repose.yaml with a rough floor of fixed spheres.

    /usr/bin/python3 cases/irazabal/repose-study/make_rough_floor.py   # writes rough-floor.yaml here

Issue 30's point `rough-floor` of the screen (run.sh). The floor is one layer of ballast spheres
(radii uniform 0.02-0.03 m, the pile's own grading) that never move (`frozen: true`), placed by
random sequential addition (ATTEMPTS trials) in a disc of radius R_FLOOR about the hopper's
axis, and half sunk in the plane floor: their centres lie at
z = Z_CENTRE, just under the floor, so that
- they stand 0.019-0.029 m above the plane: a roughness of half a stone, the bumps a free sphere
  rests between (the plane still carries a free sphere that falls into a gap);
- the pile measure (`adem analyze repose`, centres above the floor) never counts them as pile,
  and the laboratory measure's skirt level h_e keeps its meaning above a floor of bumps;
- they touch no wall (frozen spheres never do) and no other frozen sphere.
The layer is the same for every seed (its own RNG seed below): the floor is part of the set-up.
Random sequential addition of discs jams at a covered fraction of about 0.547; the layer written
here covers what it reaches after ATTEMPTS trials (printed).
"""
import math
import os
import random

R_FLOOR = 0.70        # m: beyond the 400-sphere piles' footprint (about 0.5 m); plane floor outside
R_MIN, R_MAX = 0.02, 0.03
Z_CENTRE = -0.001     # m: centres just under the plane z = 0
GAP = 1e-4            # m: clearance between neighbouring frozen spheres
ATTEMPTS = 400000
SEED = 30

here = os.path.dirname(os.path.abspath(__file__))
rng = random.Random(SEED)
cell = 2 * R_MAX + GAP
grid = {}
spheres = []
for _ in range(ATTEMPTS):
    r = rng.uniform(R_MIN, R_MAX)
    rho = (R_FLOOR - r) * math.sqrt(rng.random())
    phi = rng.uniform(0.0, 2.0 * math.pi)
    x, y = rho * math.cos(phi), rho * math.sin(phi)
    gx, gy = int(math.floor(x / cell)), int(math.floor(y / cell))
    ok = True
    for ix in (gx - 1, gx, gx + 1):
        for iy in (gy - 1, gy, gy + 1):
            for (xo, yo, ro) in grid.get((ix, iy), ()):
                if (x - xo) ** 2 + (y - yo) ** 2 < (r + ro + GAP) ** 2:
                    ok = False
                    break
            if not ok: break
        if not ok: break
    if ok:
        grid.setdefault((gx, gy), []).append((x, y, r))
        spheres.append((x, y, r))

covered = sum(math.pi * r * r for (_, _, r) in spheres) / (math.pi * R_FLOOR ** 2)
with open(os.path.join(here, "..", "repose.yaml")) as f:
    case = f.read()
case = case.replace("name: irazabal-repose\n", "name: irazabal-repose-rough-floor\n", 1)
case = case.replace("file: meshes/repose_hopper.stl", "file: ../meshes/repose_hopper.stl", 1)
assert "../meshes/repose_hopper.stl" in case and "particles:" not in case
head = ("# Written by make_rough_floor.py (issue 30's screen point rough-floor): repose.yaml with a\n"
        "# rough floor of %d fixed ballast spheres half sunk in the plane, covering %.3f of a disc\n"
        "# of radius %.2f m. Do not edit; edit the script.\n" % (len(spheres), covered, R_FLOOR))
lines = ["", "particles:",
         "  - type: list",
         "    material: ballast",
         "    frozen: true",
         "    spheres:"]
for (x, y, r) in spheres:
    lines.append("      - {position: [%.6f, %.6f, %.4f], radius: %.6f}" % (x, y, Z_CENTRE, r))
with open(os.path.join(here, "rough-floor.yaml"), "w") as f:
    f.write(head + case + "\n".join(lines) + "\n")
print("rough-floor.yaml: %d spheres, covered fraction %.3f" % (len(spheres), covered))
