#!/usr/bin/env python3
"""Times reading and setting particle arrays of 1,000,000 particles through the Python module.

    PYTHONPATH=python python3 bench/python_bulk.py [N] [REPEATS]

Prints the median and minimum of REPEATS (default 21) of: w.particles("position"),
w.particles("radius"), w.set_positions(x), w.set_velocities(v), w.set_external_force(f),
w.ids(). The world is built with N particles on a lattice (not stepped). A benchmark, not a
test: run it on a quiet machine (issue 26 asks for < 50 ms each at N = 1e6)."""
import statistics
import sys
import time

import numpy as np

import adem


def timed(fn, repeats):
    out = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        out.append(time.perf_counter() - t0)
    return statistics.median(out), min(out)


def main(n=1_000_000, repeats=21):
    w = adem.World()
    g = w.add_material("glass")
    side = int(round(n ** (1 / 3))) + 1
    i = np.arange(n)
    x = np.stack([i % side, (i // side) % side, i // (side * side)], 1) * 0.003
    t0 = time.perf_counter()
    w.add_particles(x, radius=0.001, material=g)
    print("adem %s, %d particles (built in %.1f s), %d repeats" %
          (adem.library_path(), len(w), time.perf_counter() - t0, repeats))
    v = np.random.default_rng(0).normal(size=(n, 3))
    cases = [("particles('position')", lambda: w.particles("position")),
             ("particles('radius')", lambda: w.particles("radius")),
             ("ids()", w.ids),
             ("set_positions(x)", lambda: w.set_positions(x)),
             ("set_velocities(v)", lambda: w.set_velocities(v)),
             ("set_external_force(f)", lambda: w.set_external_force(v))]
    for name, fn in cases:
        med, best = timed(fn, repeats)
        print("%-24s median %7.2f ms   min %7.2f ms" % (name, 1e3 * med, 1e3 * best))


if __name__ == "__main__":
    a = sys.argv[1:]
    main(int(float(a[0])) if a else 1_000_000, int(a[1]) if len(a) > 1 else 21)
