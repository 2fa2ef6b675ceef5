#!/usr/bin/env python3
"""One-way coupling: a prescribed air flow drags particles through World.set_external_force.

Stokes drag F = 6 pi mu R (u(x) - v) is set on every particle before every step, from the
velocities adem computes (no Python loop over particles). Two checks:
  1. a single 40 um sphere falling in still air reaches the Stokes terminal velocity
     v_t = m g / (6 pi mu R) = (2/9) rho R^2 g / mu to 1e-3 (after 12 relaxation times);
  2. a cloud in a horizontal wind u = (U, 0, 0) is carried at U (mean |v_x - U| / U < 1e-3).
Writes drag.png (speed against time). Exit status 1 if a check fails.

    python3 examples/python/drag.py [OUT_DIR]
"""
import math
import os
import sys

import numpy as np

import adem

MU = 1.8e-5      # air viscosity, Pa s
RHO = 2500.0     # glass, kg/m^3
G = 9.81
R = 20e-6        # m: Re = rho_air v_t 2R / mu = 0.16, Stokes regime
U = 0.5          # wind, m/s


def stokes_world(positions):
    w = adem.World()
    glass = w.add_material("glass", density=RHO, young=1e7, poisson=0.3, restitution=0.5,
                           friction=0.5)
    w.add_particles(positions, radius=R, material=glass)
    w.set_domain((-100, -100, -100), (100, 100, 100))
    w.gravity = (0, 0, -G)
    return w


def drag_force(w, wind):
    v = w.particles("velocity")
    return 6.0 * math.pi * MU * R * (wind - v)   # (N, 3), one array operation


def main(out):
    m = RHO * 4.0 / 3.0 * math.pi * R ** 3
    tau = m / (6.0 * math.pi * MU * R)            # relaxation time, s
    v_t = m * G / (6.0 * math.pi * MU * R)        # Stokes terminal velocity, m/s
    w = stokes_world([[0.0, 0.0, 0.0]])
    w.dt = tau / 200.0                            # explicit drag: dt << tau
    steps = int(12 * tau / w.dt)
    t, vz = [], []
    for _ in range(steps):
        w.set_external_force(drag_force(w, np.zeros(3)))
        w.step(1)
        t.append(w.time)
        vz.append(-w.particles("velocity")[0, 2])
    err1 = abs(vz[-1] - v_t) / v_t
    print("single sphere: v = %.6g m/s, Stokes v_t = %.6g m/s, relative error %.2e (tau = %.4g s)"
          % (vz[-1], v_t, err1, tau))

    rng = np.random.default_rng(1)
    cloud = stokes_world(rng.uniform(-0.01, 0.01, size=(200, 3)))
    cloud.gravity = (0, 0, 0)
    cloud.dt = w.dt
    wind = np.array([U, 0.0, 0.0])
    for _ in range(steps):
        cloud.set_external_force(drag_force(cloud, wind))
        cloud.step(1)
    vx = cloud.particles("velocity")[:, 0]
    err2 = np.mean(np.abs(vx - U)) / U
    print("cloud of 200 in a %.2g m/s wind: mean |v_x - U| / U = %.2e" % (U, err2))

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot(np.array(t) / tau, vz, label="adem, drag set each step")
    ax.axhline(v_t, color="k", ls="--", label="Stokes terminal velocity")
    ax.set_xlabel("t / tau")
    ax.set_ylabel("falling speed, m/s")
    ax.legend()
    os.makedirs(out, exist_ok=True)
    fig.savefig(os.path.join(out, "drag.png"), dpi=100)
    ok = err1 < 1e-3 and err2 < 1e-3
    print("drag: %s (plot in %s)" % ("ok" if ok else "FAILED", os.path.join(out, "drag.png")))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else "out/python-drag"))
