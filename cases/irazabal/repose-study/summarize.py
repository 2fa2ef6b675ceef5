#!/usr/bin/python3
"""Tables of issue 30's repose screen: every finished run of run.sh and, per point, the mean and
standard deviation over its seeds of every measure (docs/validation.md, "The measure"). A run
that ended with spheres above the outlet jammed (an arch held in the hopper): it is listed, and
left out of its point's means ("seeds" counts the runs in them).

    /usr/bin/python3 cases/irazabal/repose-study/summarize.py out/repose-study

Writes OUT/runs.csv and OUT/summary.md and prints the summary. Standard library only."""
import csv
import math
import os
import re
import sys

MEASURES = [("angle_lab_deg", "lab (primary)"), ("angle_surface_deg", "surface fit"),
            ("angle_slices_deg", "slices"), ("angle_ringtop_deg", "ring-top line"),
            ("angle_footprint_deg", "H / footprint")]


def mean_sd(xs):
    xs = [x for x in xs if not math.isnan(x)]
    if not xs:
        return float("nan"), float("nan"), 0
    m = sum(xs) / len(xs)
    sd = math.sqrt(sum((x - m) ** 2 for x in xs) / (len(xs) - 1)) if len(xs) > 1 else float("nan")
    return m, sd, len(xs)


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "out/repose-study"
    rows = []
    for name in sorted(os.listdir(out)):
        d = os.path.join(out, name)
        m = re.fullmatch(r"(.+)-s(\d+)", name)
        if not m or not os.path.isfile(os.path.join(d, "done")):
            continue
        mpath = os.path.join(d, "repose_measures.csv")
        if not os.path.isfile(mpath):
            continue
        with open(mpath) as f:
            r = next(csv.DictReader(f))
        wall = 0
        if os.path.isfile(os.path.join(d, "wall_s")):
            wall = sum(int(x) for x in open(os.path.join(d, "wall_s")).read().split())
        # spheres left above the outlet when the run ended: a jammed hopper (an arch), whose pile
        # is not the set-up's and is left out of the means
        in_hopper = 0
        ts = os.path.join(d, "timeseries.csv")
        if os.path.isfile(ts):
            with open(ts) as f:
                last = None
                for last in csv.DictReader(f):
                    pass
            if last and "above_outlet_count" in last:
                in_hopper = int(float(last["above_outlet_count"]))
        row = {"point": m.group(1), "seed": int(m.group(2)), "wall_s": wall, "in_hopper": in_hopper}
        row.update({k: float(v) for k, v in r.items()})
        rows.append(row)
    if not rows:
        print("no finished runs in", out)
        return
    keys = ["point", "seed", "wall_s", "in_hopper"] + [
        k for k in rows[0] if k not in ("point", "seed", "wall_s", "in_hopper")]
    with open(os.path.join(out, "runs.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys)
        w.writeheader()
        w.writerows(rows)
    points = []
    for r in rows:
        if r["point"] not in points:
            points.append(r["point"])
    lines = ["| point | seeds | " + " | ".join(label for _, label in MEASURES) +
             " | height m | R_base m | jammed | wall s (each) |",
             "|---|---|" + "---|" * len(MEASURES) + "---|---|---|---|"]
    for p in points:
        every = [r for r in rows if r["point"] == p]
        rs = [r for r in every if r["in_hopper"] == 0]
        jams = ", ".join(f"s{r['seed']}: {r['in_hopper']} left" for r in every if r["in_hopper"] > 0)
        cells = []
        for k, _ in MEASURES:
            m, sd, n = mean_sd([r[k] for r in rs])
            cells.append(f"{m:.1f} ± {sd:.1f}" if n > 1 else f"{m:.1f}")
        h = mean_sd([r["height_m"] for r in rs])[0]
        rb = mean_sd([r["lab_base_radius_m"] for r in rs])[0]
        walls = ", ".join(str(r["wall_s"]) for r in every)
        lines.append(f"| {p} | {len(rs)} | " + " | ".join(cells) +
                     f" | {h:.3f} | {rb:.3f} | {jams or 'no'} | {walls} |")
    lines.append("")
    lines.append("Each run: " + "; ".join(
        f"{r['point']} s{r['seed']}: lab {r['angle_lab_deg']:.1f}, surface {r['angle_surface_deg']:.1f}, "
        f"slices {r['angle_slices_deg']:.1f}, ring-top {r['angle_ringtop_deg']:.1f}"
        + (f" (jammed: {r['in_hopper']} left in the hopper)" if r["in_hopper"] else "") for r in rows) + ".")
    text = "\n".join(lines) + "\n"
    with open(os.path.join(out, "summary.md"), "w") as f:
        f.write(text)
    print(text)


if __name__ == "__main__":
    main()
