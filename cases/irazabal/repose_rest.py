#!/usr/bin/env python3
"""When is the repose pile at rest? Reads OUTDIR/timeseries.csv of a run of repose.yaml.

    python3 cases/irazabal/repose_rest.py OUTDIR [--threshold 1e-7] [--after 20]

Rest: the kinetic plus rotational energy per particle stays below THRESHOLD (J) from some time on
until the end of the run; the script prints that time, counted from AFTER (the end of the pour),
and the largest overlap, the floor's load against the particles' weight and the number of
particles (from the last frame's header). Standard library only.
"""
import argparse
import csv
import glob
import os
import re
import sys


def last_frame_count(outdir):
    frames = sorted(glob.glob(os.path.join(outdir, "frames", "particles_*.vtu")))
    if not frames:
        return None
    with open(frames[-1], "rb") as f:
        head = f.read(4096).decode("latin-1")
    m = re.search(r'NumberOfPoints="(\d+)"', head)
    return int(m.group(1)) if m else None


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("outdir")
    ap.add_argument("--threshold", type=float, default=1e-7,
                    help="J per particle (1e-7 J: rms speed about 1 mm/s for 0.18 kg)")
    ap.add_argument("--after", type=float, default=20.0, help="end of the pour, s")
    ap.add_argument("--particles", type=int, default=0, help="default: the last frame's count")
    a = ap.parse_args()
    n = a.particles or last_frame_count(a.outdir)
    if not n:
        sys.exit("cannot tell the number of particles: give --particles")
    rows = []
    with open(os.path.join(a.outdir, "timeseries.csv")) as f:
        for r in csv.DictReader(f):
            rows.append(r)
    if not rows:
        sys.exit("empty timeseries.csv")
    t = [float(r["time_s"]) for r in rows]
    e = [(float(r["kinetic_J"]) + float(r["rotational_J"])) / n for r in rows]
    ov = max(float(r["max_overlap_ratio"]) for r in rows)
    rest = None
    for i in range(len(rows) - 1, -1, -1):
        if e[i] >= a.threshold:
            break
        if t[i] >= a.after:
            rest = t[i]
    print("particles           %d" % n)
    print("end of run          %.3f s, energy per particle %.3e J" % (t[-1], e[-1]))
    if rest is None:
        print("at rest             no: energy per particle is above %.1e J at the end" % a.threshold)
    else:
        print("at rest             from %.3f s (%.3f s after %.3f s): energy per particle below "
              "%.1e J to the end" % (rest, rest - a.after, a.after, a.threshold))
    print("largest overlap     %.4f of the smaller radius" % ov)
    if "floor_fz_N" in rows[-1]:
        print("floor load at end   %.2f N" % -float(rows[-1]["floor_fz_N"]))


if __name__ == "__main__":
    main()
