#!/usr/bin/env python3
"""Vertical stress on the floor against the distance from the pile's axis, from the floor's
contacts in a run's contact CSVs (output.contacts + output.contacts_csv): the vertical force of
the plane contacts whose contact point lies in an annulus, over the annulus's area, averaged over
the last FRAMES contact frames; the axis is the mean (x, y) of those contact points weighted by
force. One curve per output folder.

  floor_stress.py OUT.png LABEL=DIR [LABEL=DIR ...] [--frames 3] [--bin 0.01] [--csv OUT.csv]
"""
import csv
import glob
import math
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def profile(d, frames, dr):
    files = sorted(glob.glob(os.path.join(d, "frames", "contacts_*.csv")))[-frames:]
    pts = []
    for fn in files:
        for r in csv.DictReader(open(fn)):
            if r["kind"] != "plane":
                continue
            pts.append((float(r["xb_m"]), float(r["yb_m"]), float(r["fz_N"]) / len(files)))
    w = sum(p[2] for p in pts)
    cx = sum(p[0] * p[2] for p in pts) / w
    cy = sum(p[1] * p[2] for p in pts) / w
    rmax = max(math.hypot(p[0] - cx, p[1] - cy) for p in pts)
    nb = int(rmax / dr) + 1
    f = [0.0] * nb
    for x, y, fz in pts:
        f[int(math.hypot(x - cx, y - cy) / dr)] += fz
    r = [(k + 0.5) * dr for k in range(nb)]
    s = [f[k] / (math.pi * dr * dr * ((k + 1) ** 2 - k ** 2)) for k in range(nb)]
    return r, s, w, (cx, cy), len(files)


def main(argv):
    if len(argv) < 3:
        print(__doc__)
        return 2
    out, runs, frames, dr, csv_out = argv[1], [], 3, 0.01, None
    i = 2
    while i < len(argv):
        a = argv[i]
        if a == "--frames":
            frames, i = int(argv[i + 1]), i + 2
        elif a == "--bin":
            dr, i = float(argv[i + 1]), i + 2
        elif a == "--csv":
            csv_out, i = argv[i + 1], i + 2
        else:
            label, d = a.split("=", 1)
            runs.append((label, d))
            i += 1
    fig, ax = plt.subplots(figsize=(8, 5))
    rows = []
    for label, d in runs:
        r, s, w, c, nf = profile(d, frames, dr)
        ax.plot(r, s, "o-", label="%s (floor load %.3g N, %d frames)" % (label, w, nf))
        print("%s: floor load %.4g N, axis (%.4f, %.4f) m" % (label, w, c[0], c[1]))
        for rr, ss in zip(r, s):
            print("  r = %.3f m  sigma_zz = %.1f Pa" % (rr, ss))
            rows.append((label, rr, ss))
    ax.set_xlabel("distance from the axis (m)")
    ax.set_ylabel("vertical stress on the floor (Pa)")
    ax.grid(True, alpha=0.4)
    ax.legend()
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    if csv_out:
        with open(csv_out, "w") as f:
            f.write("run,r_m,sigma_zz_Pa\n")
            for row in rows:
                f.write("%s,%.6g,%.6g\n" % row)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
