#!/usr/bin/env python3
"""A parameter sweep of the rolling friction eta_r (BROF, Irazabal et al. 2017) on a small pile.

For each eta_r a column of 300 spheres settles in a square tube on a rough floor; the tube is
then switched off and the column collapses into a pile. Its angle is taken as atan(H / R_b),
H the pile's height and R_b the radius holding 95 % of the spheres (a cone's side). A larger
eta_r must give a steeper pile. Small and quick (about a minute on one core); the paper-scale
study is `adem validate irazabal_fig11`. Writes repose_sweep.png and repose_sweep.csv.

    python3 examples/python/repose_sweep.py [OUT_DIR] [ETA_R ...]
"""
import math
import os
import sys

import numpy as np

import adem


def pile_angle(eta_r, settle=0.25, collapse=0.5):
    w = adem.World()
    stone = w.add_material("stone", density=2700, young=1e6, poisson=0.25, restitution=0.3,
                           friction=0.6, rolling_friction=eta_r)
    steel = w.add_material("steel", density=7800, young=1e6, poisson=0.25, restitution=0.3,
                           friction=0.6, rolling_friction=eta_r)
    w.set_interaction(stone, stone, rolling="brof")
    w.set_interaction(stone, steel, rolling="brof")
    w.add_plane((0, 0, 0), (0, 0, 1), material=steel, name="floor")
    w.add_box("tube", (-0.0125, -0.0125, -0.01), (0.0125, 0.0125, 0.2), material=steel)
    w.set_wall_active("tube.zmin", False)
    rng = np.random.default_rng(7)
    i, j, k = np.meshgrid(np.arange(5), np.arange(5), np.arange(12), indexing="ij")
    pos = np.stack([-0.01 + 0.005 * i, -0.01 + 0.005 * j, 0.003 + 0.0055 * k], -1).reshape(-1, 3)
    pos += rng.uniform(-2e-4, 2e-4, size=pos.shape) * [1, 1, 0]
    w.add_particles(pos, radius=rng.uniform(0.0019, 0.0022, size=len(pos)), material=stone)
    w.set_domain((-0.5, -0.5, -0.05), (0.5, 0.5, 0.5))
    w.dt = w.estimate_step(1.0)["dt"]
    w.run_to(settle)
    for face in ("xmin", "xmax", "ymin", "ymax"):
        w.set_wall_active("tube." + face, False)
    w.run_to(settle + collapse)
    x, r = w.particles("position"), w.particles("radius")
    on_floor = x[:, 2] > -0.01
    h = np.max(x[on_floor, 2] + r[on_floor])
    rb = np.quantile(np.hypot(x[on_floor, 0], x[on_floor, 1]), 0.95)
    return math.degrees(math.atan(h / rb)), w.diagnostics()["kinetic"]


def main(out, etas):
    os.makedirs(out, exist_ok=True)
    rows = []
    for eta in etas:
        angle, ke = pile_angle(eta)
        rows.append((eta, angle))
        print("eta_r = %.3f: pile angle %.1f deg (kinetic energy at the end %.2g J)"
              % (eta, angle, ke))
    np.savetxt(os.path.join(out, "repose_sweep.csv"), rows, delimiter=",",
               header="eta_r,angle_deg", comments="")
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(5, 4))
    ax.plot([e for e, _ in rows], [a for _, a in rows], "o-")
    ax.set_xlabel("rolling friction eta_r")
    ax.set_ylabel("pile angle atan(H / R_b), deg")
    fig.savefig(os.path.join(out, "repose_sweep.png"), dpi=100)
    return 0


if __name__ == "__main__":
    args = sys.argv[1:]
    out = args.pop(0) if args else "out/python-repose"
    sys.exit(main(out, [float(a) for a in args] or [0.02, 0.1, 0.3]))
