#!/usr/bin/env python3
"""A pour driven step by step from Python, with the packing fraction plotted against time.

500 glass spheres (radius 2 mm +- 10 %) fall from a loose lattice into a 4 x 4 cm box. Every
5 ms the script reads the positions and radii as arrays and computes the solid fraction of the
bed: the spheres' volume below z_top over the box's volume below it, z_top the height under
which 90 % of the spheres' centres lie, minus a radius (a layer that excludes the loose top).
Writes packing.png and packing.csv.

    python3 examples/python/pour_packing.py [OUT_DIR]
"""
import os
import sys

import numpy as np

import adem


def build():
    w = adem.World()
    glass = w.add_material("glass", density=2500, young=5e6, poisson=0.25, restitution=0.4,
                           friction=0.5, rolling_friction=0.05)
    wall = w.add_material("wall", density=7800, young=5e6, poisson=0.25, restitution=0.4,
                          friction=0.5)
    w.set_interaction(glass, glass, rolling="model_c")
    w.add_box("box", (0, 0, 0), (0.04, 0.04, 0.3), material=wall)
    rng = np.random.default_rng(3)
    i, j, k = np.meshgrid(np.arange(8), np.arange(8), np.arange(8), indexing="ij")
    pos = np.stack([0.0025 + 0.005 * i, 0.0025 + 0.005 * j, 0.01 + 0.0055 * k], -1).reshape(-1, 3)
    pos = pos[:500] + rng.uniform(-2e-4, 2e-4, size=(500, 3))
    radius = rng.uniform(0.0018, 0.0022, size=500) * 0.999
    w.add_particles(pos, radius=radius, material=glass, velocity=(0, 0, -0.2))
    w.dt = w.estimate_step(1.0)["dt"]
    return w


def packing_fraction(x, r, area):
    z_top = np.quantile(x[:, 2], 0.9) - np.mean(r)
    below = x[:, 2] < z_top
    return np.sum(4.0 / 3.0 * np.pi * r[below] ** 3) / (area * z_top)


def main(out, end=0.5):
    w = build()
    r = w.particles("radius")
    t, phi, ke = [], [], []
    while w.time < end:
        w.run_to(w.time + 0.005)
        t.append(w.time)
        phi.append(packing_fraction(w.particles("position"), r, 0.04 * 0.04))
        ke.append(w.diagnostics()["kinetic"])
    os.makedirs(out, exist_ok=True)
    np.savetxt(os.path.join(out, "packing.csv"), np.c_[t, phi, ke], delimiter=",",
               header="time_s,packing_fraction,kinetic_J", comments="")
    print("t = %.3f s: packing fraction %.3f, kinetic energy %.3g J" % (t[-1], phi[-1], ke[-1]))
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot(t, phi)
    ax.set_xlabel("time, s")
    ax.set_ylabel("packing fraction of the bed")
    ax.set_ylim(0, 0.7)
    fig.savefig(os.path.join(out, "packing.png"), dpi=100)
    print("plot in %s" % os.path.join(out, "packing.png"))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else "out/python-pour"))
