#!/usr/bin/env python3
"""Force chains of a contact frame (output.contacts) drawn with matplotlib, for where ParaView is
not at hand: each contact a line from a's centre to b's centre (or to a wall's contact point),
its width and darkness scaled by |F_n|, projected on the x-z plane; a slab |y - y0| < half
thickness only (default: the middle fifth of the particles' y range).

  plot_force_chains.py frames/contacts_NNNNNN.csv OUT.png [--slab Y0 HALF] [--title T]

The CSV is the one output.contacts_csv writes (docs/fields.md)."""
import csv
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.collections import LineCollection  # noqa: E402


def main(argv):
    if len(argv) < 3:
        print(__doc__)
        return 2
    src, out = argv[1], argv[2]
    slab = None
    title = src
    i = 3
    while i < len(argv):
        if argv[i] == "--slab":
            slab = (float(argv[i + 1]), float(argv[i + 2]))
            i += 3
        elif argv[i] == "--title":
            title = argv[i + 1]
            i += 2
        else:
            print("unknown option", argv[i])
            return 2
    rows = list(csv.DictReader(open(src)))
    if not rows:
        print("no contacts in", src)
        return 2
    ys = [float(r["ya_m"]) for r in rows]
    if slab is None:
        lo, hi = min(ys), max(ys)
        slab = (0.5 * (lo + hi), 0.1 * (hi - lo))
    segs, fn = [], []
    for r in rows:
        ya, yb = float(r["ya_m"]), float(r["yb_m"])
        if abs(0.5 * (ya + yb) - slab[0]) > slab[1]:
            continue
        segs.append([(float(r["xa_m"]), float(r["za_m"])), (float(r["xb_m"]), float(r["zb_m"]))])
        fn.append(float(r["fn_N"]))
    fmax = max(fn) if fn else 1.0
    widths = [0.3 + 4.0 * f / fmax for f in fn]
    colors = [plt.cm.inferno_r(0.15 + 0.85 * f / fmax) for f in fn]
    fig, ax = plt.subplots(figsize=(7, 7))
    ax.add_collection(LineCollection(segs, linewidths=widths, colors=colors, capstyle="round"))
    ax.autoscale()
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("z (m)")
    ax.set_title("%s\n%d contacts with |y - %.4g| < %.3g m; width and colour ~ |F_n| (max %.3g N)"
                 % (title, len(segs), slab[0], slab[1], fmax), fontsize=9)
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    print("wrote", out, len(segs), "contacts")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
