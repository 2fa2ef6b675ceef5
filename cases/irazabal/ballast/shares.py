#!/usr/bin/python3
"""Fig. 17's shares read from one push's time series, as `adem validate irazabal-fig17` reads them.

    cases/irazabal/ballast/shares.py PUSH_DIR [--out PREFIX]

PUSH_DIR holds a push's timeseries.csv (e.g. out/vertical-crib/push-E17.7). The rows after the
settle stage (t >= 0.19 s, push.yaml) are binned by the sleeper's displacement u in 0.1 mm bins;
in each bin the lateral resistance R = -F_x of the particles on the sleeper is averaged, and each
face group's share is its mean -F_x over the mean R: base, cribs (front + back), shoulder end and
far end (src/studies/validate_ballast.c, measure_push). Printed: the shares at 0-0.3 mm, 1, 3
and 6 mm (means over the bins whose centre lies within 0.2 mm of the value, as the C measure
takes 2.8-3.2 mm for 3 mm), and the crossing: the displacement from which the shoulder's share
is the largest of base, cribs and shoulder in every later bin. Written: PREFIX.csv (the binned
shares) and PREFIX.png (matplotlib); PREFIX defaults to PUSH_DIR/shares.
"""
import argparse
import csv
import math
import sys

SETTLE_END = 0.19  # s: push.yaml's push stage begins here
BIN = 1e-4  # m
NBIN = 70  # 0 .. 7 mm
GROUPS = ("base", "top", "crib_front", "crib_back", "shoulder_end", "far_end")


def read_bins(path):
    with open(path, newline="") as f:
        rows = csv.reader(f)
        names = next(rows)
        col = {n: k for k, n in enumerate(names)}
        need = ["sleeper_ux_m", "sleeper_fx_N"] + ["sleeper__%s_fx_N" % g for g in GROUPS]
        missing = [n for n in need if n not in col]
        if missing:
            sys.exit("shares.py: %s lacks the columns %s" % (path, ", ".join(missing)))
        cu, cfx = col["sleeper_ux_m"], col["sleeper_fx_N"]
        cg = [col["sleeper__%s_fx_N" % g] for g in GROUPS]
        R = [0.0] * NBIN
        part = [[0.0] * 4 for _ in range(NBIN)]
        count = [0] * NBIN
        for row in rows:
            t = float(row[0])
            if t < SETTLE_END - 1e-12:
                continue
            u = float(row[cu])
            b = math.floor(u / BIN)
            if b < 0 or b >= NBIN:
                continue
            g = [float(row[c]) for c in cg]
            R[b] += -float(row[cfx])
            for q, v in enumerate((-g[0], -(g[2] + g[3]), -g[4], -g[5])):
                part[b][q] += v
            count[b] += 1
    bins = []
    for b in range(NBIN):
        if count[b] == 0:
            continue
        r = R[b] / count[b]
        bins.append(((b + 0.5) * BIN, r, [p / count[b] / r for p in part[b]], b))
    return bins


def mean_over(bins, q, u0, u1):
    v = [s[q] for u, _, s, _ in bins if u0 <= u <= u1 and math.isfinite(s[q])]
    return sum(v) / len(v) if v else float("nan")


def crossing(bins):
    """The displacement (m) from which the shoulder's share is the largest in every later bin."""
    cross = float("nan")
    for u, _, s, b in reversed(bins):
        if s[2] >= s[0] and s[2] >= s[1]:
            cross = b * BIN
        else:
            break
    return cross


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("push_dir")
    ap.add_argument("--out", help="prefix of the CSV and PNG (default PUSH_DIR/shares)")
    a = ap.parse_args()
    prefix = a.out or a.push_dir.rstrip("/") + "/shares"
    bins = read_bins(a.push_dir.rstrip("/") + "/timeseries.csv")
    if not bins:
        sys.exit("shares.py: no row of the push (t >= %.2f s) in %s" % (SETTLE_END, a.push_dir))
    with open(prefix + ".csv.part", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["u_mm", "R_kN", "share_base", "share_cribs", "share_shoulder", "share_far_end"])
        for u, r, s, _ in bins:
            w.writerow(["%.2f" % (u * 1e3), "%.6g" % (r * 1e-3)] + ["%.6g" % x for x in s])
    import os
    os.replace(prefix + ".csv.part", prefix + ".csv")
    names = ("base", "cribs", "shoulder", "far end")
    print("push: %s (to u = %.2f mm)" % (a.push_dir, bins[-1][0] * 1e3))
    print("%-12s %8s %8s %8s %8s" % ("u", *names))
    for label, u0, u1 in (("0-0.3 mm", 0.0, 3e-4), ("1 mm", 0.8e-3, 1.2e-3),
                          ("3 mm", 2.8e-3, 3.2e-3), ("6 mm", 5.8e-3, 6.2e-3)):
        print("%-12s" % label + "".join(" %7.1f%%" % (100 * mean_over(bins, q, u0, u1)) for q in range(4)))
    c = crossing(bins)
    print("the shoulder carries the most from u = %s" % ("%.1f mm" % (c * 1e3) if math.isfinite(c) else "nowhere"))
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    u = [x[0] * 1e3 for x in bins]
    for q, n in enumerate(names):
        ax.plot(u, [100 * x[2][q] for x in bins], label=n, lw=2 if q == 2 else 1)
    if math.isfinite(c):
        ax.axvline(c * 1e3, color="grey", ls=":", label="shoulder largest from %.1f mm" % (c * 1e3))
    ax.set_xlabel("sleeper displacement (mm)")
    ax.set_ylabel("share of the lateral force (%)")
    ax.grid(True)
    ax.legend()
    fig.tight_layout()
    fig.savefig(prefix + ".png.part.png", dpi=110)
    os.replace(prefix + ".png.part.png", prefix + ".png")


if __name__ == "__main__":
    main()
