#!/usr/bin/python3
"""Discharge rates of cases/silo/silo.yaml runs against Beverloo's correlation.

Usage: beverloo.py [--window FROM TO] L1:OUT1 L2:OUT2 ...
  (L: the orifice's side in m, OUT: the run's output folder; the window 0.5 .. 0.8 s by default)

For each run: the packing fraction of the settled bed (centres in a box inside it, from the
frame at the gate's opening), its bulk density rho_b, and the discharge rate W: the slope of a
least-squares line through orifice_through_kg against time over FROM .. TO s (after the start-up,
while the bed is still well above the orifice). Then Beverloo's law for a square orifice of side
L: W = C rho_b sqrt(g) (L - k d)^(5/2), fitted as a line W^(2/5) = (C rho_b sqrt(g))^(2/5) (L - k d)
(C and k from the runs), and C again with k fixed at 1.5.
"""
import csv
import math
import struct
import sys

G = 9.81
D = 0.004          # mean diameter, m
RHO_S = 2500.0     # particle density, kg/m^3
OPEN = 0.4         # the gate's switch-off (stage `discharge`)
FROM, TO = 0.5, 0.8
FRAME = "frames/particles_000004.vtu"  # t = 0.4 s with frame_interval 0.1


def vtu_arrays(path):
    """The appended raw arrays of an adem frame, by name: (type, components, bytes)."""
    data = open(path, "rb").read()
    head, _, tail = data.partition(b'<AppendedData encoding="raw">')
    blob = tail[tail.index(b"_") + 1:]
    out = {}
    for line in head.decode().splitlines():
        if "<DataArray" not in line or 'format="appended"' not in line:
            continue
        attrs = dict(a.split("=", 1) for a in line.strip("<>/ ").split()[1:] if "=" in a)
        name, off = attrs["Name"].strip('"'), int(attrs["offset"].strip('"'))
        n = struct.unpack_from("<Q", blob, off)[0]
        out[name] = (attrs["type"].strip('"'), blob[off + 8: off + 8 + n])
    return out


def packing_fraction(path):
    a = vtu_arrays(path)
    pos = struct.unpack("<%dd" % (len(a["position"][1]) // 8), a["position"][1])
    rad = struct.unpack("<%dd" % (len(a["radius"][1]) // 8), a["radius"][1])
    top = max(pos[3 * i + 2] for i in range(len(rad)))
    lo, hi = (-0.024, -0.024, 0.008), (0.024, 0.024, top - 0.012)
    vol = sum(4.0 / 3.0 * math.pi * r ** 3 for i, r in enumerate(rad)
              if all(lo[k] <= pos[3 * i + k] <= hi[k] for k in range(3)))
    return vol / ((hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2])), top


def rate(path):
    t, m = [], []
    for row in csv.DictReader(open(path)):
        x = float(row["time_s"])
        if FROM <= x <= TO:
            t.append(x)
            m.append(float(row["orifice_through_kg"]))
    n = len(t)
    if n < 3:
        return float("nan"), n
    tm, mm = sum(t) / n, sum(m) / n
    slope = sum((a - tm) * (b - mm) for a, b in zip(t, m)) / sum((a - tm) ** 2 for a in t)
    return slope, n


def main():
    global FROM, TO
    args = sys.argv[1:]
    if args[:1] == ["--window"]:
        FROM, TO = float(args[1]), float(args[2])
        args = args[3:]
    runs = []
    for arg in args:
        side, out = arg.split(":", 1)
        phi, top = packing_fraction(out + "/" + FRAME)
        w, n = rate(out + "/timeseries.csv")
        runs.append((float(side), out, phi, top, w, n))
    rho_b = sum(RHO_S * r[2] for r in runs) / len(runs)
    print("| L (mm) | L/d | bed height (mm) | packing fraction | W (kg/s), %g-%g s |" % (FROM, TO))
    print("|---|---|---|---|---|")
    for side, out, phi, top, w, n in runs:
        print("| %.0f | %.1f | %.0f | %.3f | %.4f (%d rows) |" % (side * 1e3, side / D, top * 1e3, phi, w, n))
    print("\nrho_b = %.0f kg/m^3 (mean packing fraction x %g)" % (rho_b, RHO_S))
    # line through W^(2/5) against L
    xs = [r[0] for r in runs]
    ys = [r[4] ** 0.4 for r in runs]
    n = len(xs)
    if n >= 2:
        xm, ym = sum(xs) / n, sum(ys) / n
        s = sum((x - xm) * (y - ym) for x, y in zip(xs, ys)) / sum((x - xm) ** 2 for x in xs)
        b = ym - s * xm
        C = s ** 2.5 / (rho_b * math.sqrt(G))
        k = -b / (s * D)
        print("fit of W^(2/5) against L: C' = %.3f (a circle's C = C' pi/4 = %.3f), k = %.2f" % (C, C * math.pi / 4, k))
        for side, out, phi, top, w, _ in runs:
            wf = C * rho_b * math.sqrt(G) * max(side - k * D, 0.0) ** 2.5
            print("  L = %.0f mm: W = %.4f kg/s, fit %.4f (%+.1f %%)" % (side * 1e3, w, wf, 100 * (w / wf - 1)))
    for side, out, phi, top, w, _ in runs:
        c15 = w / (rho_b * math.sqrt(G) * (side - 1.5 * D) ** 2.5)
        print("  k = 1.5: L = %.0f mm gives C' = %.3f (a circle's C = C' pi/4 = %.3f)" % (side * 1e3, c15, c15 * math.pi / 4))


if __name__ == "__main__":
    main()
