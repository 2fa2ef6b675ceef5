#!/usr/bin/env python3
"""Meshes for the ballast lateral-resistance case (Irazabal et al. 2017, section 4.3, Figs 16-17).

One concrete monoblock sleeper in a slice of ballast bed one sleeper spacing long, between two
frictionless walls that stand for the mirror planes halfway to the neighbouring sleepers.

Coordinates (metres):
  x  along the sleeper's length = the lateral push direction. +x points to the shoulder the
     sleeper is pushed into; the sleeper's centre is at x = 0.
  y  along the track (rail direction). The slice is -s/2 <= y <= s/2; the frictionless side
     walls are the planes y = +-s/2. The sleeper is centred at y = 0.
  z  up. z = 0 is the floor (top of the formation, bottom of the ballast layer). The sleeper's
     base is at z = D (ballast depth under the sleeper), its top at z = D + h.

Cross-section of the bed in the x-z plane (the same for every y):

        z_fill ......|=========================================|....  riser (vertical) up to z_fill
                     |                 aux sleeper             |
        z_top  ______|__________ ___________ ___________________|______  crib / shoulder top
              /      <-- w -->  |  sleeper  |            <-- w -->     \\   slope 1:n (V:H)
             /                  |___________|                           \\
            /                  z = D                                     \\
   z = 0  --------------------------------------------------------------------  floor
        -x_end   -x_toe                                         x_toe     x_end

Files written to --out (default: meshes/ beside this script), all ASCII STL with named solids
(each `solid NAME` becomes mesh group FILE.NAME in adem, with its own CSV force/torque columns):

  sleeper.stl      the real sleeper, a closed trapezoidal prism; solids base, top, crib_front
                   (face towards +y), crib_back (towards -y), shoulder_end (x = +L/2, faces the
                   shoulder it is pushed into), far_end (x = -L/2). Normals point out, i.e. into
                   the ballast.
  aux_sleeper.stl  the taller auxiliary sleeper used while packing: the same base and crib faces
                   as the real one up to its top, then vertical faces of the top width up to the
                   container's top. One solid, aux_sleeper. Closed, normals out.
  aux_slopes.stl   the auxiliary surfaces that hold the embankment while the ballast packs
                   without friction: slope_pos / slope_neg (the 1:n slopes from the toe to the
                   shoulder edge) and riser_pos / riser_neg (vertical continuations up to z_fill).
                   Normals towards the ballast. A separate file so it can be switched off.
  aux_lid.stl      a lid at the crib/shoulder top level with a hole for the aux sleeper:
                   lid_shoulder_pos, lid_shoulder_neg, lid_crib_front, lid_crib_back. Normals
                   down (towards the ballast). Optional: lowered onto the bed at the end of
                   packing, its vertical load is the paper's "force on the upper part of the
                   auxiliary surfaces" (zero = not over-compacted).
  container.stl    floor, end_pos, end_neg (open box). Normals towards the ballast. Load the
                   auxiliary files with own_vertices: true: their edges then join nothing (a
                   slope toe lying on the floor would otherwise be a non-manifold edge).
  sides.stl        side_front (y = +s/2) and side_back (y = -s/2): the frictionless mirror walls.
                   Separate from container.stl because a mesh file has one material.
  fill_region.stl  closed surface of the volume the loose spheres are placed in before packing:
                   the bed's profile below z_top, the strip between the risers up to z_fill,
                   minus a slot where the aux sleeper stands (adem may place random spheres
                   inside a closed mesh wall, since it could be a container).

Run:  python3 make_geometry.py                   # write the meshes, check them, print the estimate
      python3 make_geometry.py --preset quick    # the reduced-scale variant into meshes/quick/
      python3 make_geometry.py --set ballast_depth=0.3 --no-write   # estimate another geometry
      python3 make_geometry.py --solve-depth 21700                    # depth for a sphere count
"""

import argparse
import math
import os
import sys

# ----------------------------------------------------------------------------- parameters
# Every length in metres. Sources and reasons: DESIGN.md, section "Dimensions".
DEFAULTS = {
    # sleeper: concrete monoblock, B70-like (DB standard sleeper, EN 13230), simplified to a prism
    "sleeper_length": 2.60,      # L
    "sleeper_base_width": 0.30,  # b, width of the base (along y)
    "sleeper_top_width": 0.22,   # t, width of the top
    "sleeper_height": 0.21,      # h, between the rail-seat (0.214) and centre (0.175) heights
    # bed
    "slice_length": 0.60,        # s = sleeper spacing
    "ballast_depth": 0.69,       # D, ballast under the sleeper's base (sets the count; DESIGN.md)
    "crib_height": 0.21,         # c, crib and shoulder top above the sleeper base (c = h: full crib)
    "shoulder_width": 0.50,      # w, from the sleeper end to the slope's upper edge
    "shoulder_slope": 1.5,       # n, horizontal run per unit rise (1:1.5)
    # container and packing
    "margin_end": 0.30,          # end walls this far beyond the slope toes
    "margin_top": 0.10,          # container and aux sleeper this far above z_fill
    "fill_fraction": 0.30,       # solid fraction of the loose random fill before packing
    # spheres
    "d_min": 0.037,              # diameters uniform in number between d_min and d_max
    "d_max": 0.063,              # (mean 0.050 m, inside the EN 13450 31.5-63 mm grading)
    "packing_fraction": 0.60,    # solid fraction of the packed bed
    "target_count": 23000,       # spheres poured: ~6% over the 21,708 of the paper, so the packed
                                 # bed stands above the crib level and pack.yaml's import trims it
}


# A reduced-scale variant for quick checks: spheres twice as large (8x fewer), same geometry; the
# count over-fills the bed by about one sphere diameter (2,550 fill it to the crib level: measured
# with a lid probe), and the push case trims it at the crib level.
PRESETS = {
    "quick": {"d_min": 0.074, "d_max": 0.126, "target_count": 2700},
}


def lid_probe(p, q, fast=1.25, slow=0.25, slow_travel=0.15, start=0.1, clearance=0.05, ramp=1e-4):
    """Motion of aux_lid.stl as an over-compaction probe: the lid starts `clearance` above z_fill
    (translate it up by the returned lift), waits until `start`, comes down at `fast` m/s, then
    at `slow` m/s for the last `slow_travel` metres, and stops at the crib level. Returns
    (lift, table) with table rows [t, vx, vy, vz] for `motion.table` (piecewise-linear velocity,
    switches spread over `ramp` seconds); the table's travel equals the lift to round-off."""
    lift = q["z_fill"] - q["z_top"] + clearance
    ta = start + ramp + (lift - slow_travel) / fast

    def rows(tb):
        return [[start, 0, 0, 0], [start + ramp, 0, 0, -fast], [ta, 0, 0, -fast],
                [ta + ramp, 0, 0, -slow], [tb, 0, 0, -slow], [tb + ramp, 0, 0, 0]]

    tb = ta + ramp + slow_travel / slow
    tb += (lift + table_travel(rows(tb))) / slow     # travel is negative (downwards)
    return lift, rows(tb)


def table_travel(table):
    """Distance travelled under a piecewise-linear velocity table (z component)."""
    d = 0.0
    for (t0, *_, v0), (t1, *_, v1) in zip(table, table[1:]):
        d += 0.5 * (v0 + v1) * (t1 - t0)
    return d


def derived(p):
    """Positions that follow from the parameters."""
    L, h, D, c = p["sleeper_length"], p["sleeper_height"], p["ballast_depth"], p["crib_height"]
    w, n = p["shoulder_width"], p["shoulder_slope"]
    q = {}
    q["z_base"] = D
    q["z_sleeper_top"] = D + h
    q["z_top"] = D + c                        # crib / shoulder top
    q["x_edge"] = L / 2 + w                   # upper edge of the slope
    q["x_toe"] = q["x_edge"] + n * q["z_top"]  # toe of the slope on the floor
    q["x_end"] = q["x_toe"] + p["margin_end"]
    return q


# ----------------------------------------------------------------------------- volumes
def sleeper_section_area(p, z0, z1):
    """Area (in the y-z plane) of the sleeper's trapezoid between heights z0 and z1 (z from its base)."""
    b, t, h = p["sleeper_base_width"], p["sleeper_top_width"], p["sleeper_height"]
    z0, z1 = max(0.0, z0), min(h, z1)
    if z1 <= z0:
        return 0.0
    width = lambda z: b + (t - b) * z / h
    return 0.5 * (width(z0) + width(z1)) * (z1 - z0)


def bed_volume(p):
    """Bulk volume of the ballast in the slice: the embankment profile minus the sleeper."""
    q = derived(p)
    H = q["z_top"]
    section = 2 * q["x_edge"] * H + p["shoulder_slope"] * H * H   # trapezoid, top 2 x_edge
    sleeper = p["sleeper_length"] * sleeper_section_area(p, 0.0, p["crib_height"])
    return section * p["slice_length"] - sleeper


def mean_sphere_volume(p):
    """<pi d^3 / 6> for diameters uniform in number on [d_min, d_max]."""
    a, b = p["d_min"], p["d_max"]
    if b - a < 1e-15:
        return math.pi / 6 * a ** 3
    mean_d3 = (b ** 4 - a ** 4) / (4 * (b - a))
    return math.pi / 6 * mean_d3


def sphere_count(p):
    return p["packing_fraction"] * bed_volume(p) / mean_sphere_volume(p)


def fill_top(p, count):
    """Height z_fill of the loose-fill region that holds `count` spheres at fill_fraction.

    The region is the bed profile below z_top plus the strip between the risers above it, minus
    the aux sleeper (vertical faces of the top width above the sleeper top)."""
    q = derived(p)
    need = count * mean_sphere_volume(p) / p["fill_fraction"]
    below = bed_volume(p)
    strip = (2 * q["x_edge"] * p["slice_length"]
             - p["sleeper_length"] * p["sleeper_top_width"])   # area per metre of height
    if p["crib_height"] < p["sleeper_height"]:
        # between z_top and the sleeper top the aux sleeper is still the trapezoid
        raise ValueError("crib_height below sleeper_height is not supported by fill_top")
    return q["z_top"] + max(0.0, need - below) / strip


def solve_depth(p, count):
    """Ballast depth D that gives `count` spheres with the other parameters fixed (bisection)."""
    lo, hi = 0.01, 5.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if sphere_count(dict(p, ballast_depth=mid)) < count:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


# ----------------------------------------------------------------------------- mesh building
class Solid:
    def __init__(self, name):
        self.name = name
        self.tris = []   # [(a, b, c)], counter-clockwise seen from the side the normal points to

    def tri(self, a, b, c):
        self.tris.append((tuple(a), tuple(b), tuple(c)))

    def quad(self, a, b, c, d):
        """Planar quad a-b-c-d (counter-clockwise seen from the normal side) as two triangles."""
        self.tri(a, b, c)
        self.tri(a, c, d)

    def polygon(self, pts):
        """Convex planar polygon (counter-clockwise seen from the normal side), fanned from pts[0],
        or from the first vertex whose fan has no triangle of area 0: a polygon with a straight
        corner (three points on a line, as a prismatic sleeper's fill region has) keeps every
        vertex, so that the faces meeting it there still close the surface."""
        k = len(pts)

        def flat(a, b, c):
            n = cross(sub(b, a), sub(c, a))
            return dot(n, n) == 0.0

        s = next((s for s in range(k)
                  if not any(flat(pts[s], pts[(s + i) % k], pts[(s + i + 1) % k]) for i in range(1, k - 1))), 0)
        for i in range(1, k - 1):
            self.tri(pts[s], pts[(s + i) % k], pts[(s + i + 1) % k])


def face(solid, pts, outward):
    """Add the convex planar polygon pts to solid, ordered so that its right-hand normal points
    along `outward` (fanned from its first point)."""
    n = (0.0, 0.0, 0.0)
    for i in range(1, len(pts) - 1):
        c = cross(sub(pts[i], pts[0]), sub(pts[i + 1], pts[0]))
        n = (n[0] + c[0], n[1] + c[1], n[2] + c[2])
    if dot(n, outward) < 0:
        pts = list(reversed(pts))
    solid.polygon(pts)


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def unit_normal(t):
    n = cross(sub(t[1], t[0]), sub(t[2], t[0]))
    ln = math.sqrt(dot(n, n))
    return (n[0] / ln, n[1] / ln, n[2] / ln), 0.5 * ln


def prism_x(solid_names, x0, x1, section):
    """A closed prism along x between x0 < x1 whose y-z cross-section is the convex polygon
    `section` [(y, z), ...] given counter-clockwise seen from +x. Faces go to named solids:
    solid_names maps 'x0', 'x1' and the index i of the edge section[i] -> section[i+1] to a
    solid name. Returns {name: Solid}."""
    solids = {}

    def get(key):
        name = solid_names[key]
        if name not in solids:
            solids[name] = Solid(name)
        return solids[name]

    k = len(section)
    # end at x1: normal +x, so counter-clockwise seen from +x = the section's own order
    get("x1").polygon([(x1, y, z) for (y, z) in section])
    # end at x0: normal -x, reverse order
    get("x0").polygon([(x0, y, z) for (y, z) in reversed(section)])
    for i in range(k):
        (ya, za), (yb, zb) = section[i], section[(i + 1) % k]
        # side face between edge a->b at x0 and x1; outward = to the right of a->b seen from +x
        get(i).quad((x0, ya, za), (x0, yb, zb), (x1, yb, zb), (x1, ya, za))
    return solids


def build(p):
    q = derived(p)
    L, b, t, h = p["sleeper_length"], p["sleeper_base_width"], p["sleeper_top_width"], p["sleeper_height"]
    s, D, n = p["slice_length"], p["ballast_depth"], p["shoulder_slope"]
    zb, zs, zt = q["z_base"], q["z_sleeper_top"], q["z_top"]
    xe, xt, xend = q["x_edge"], q["x_toe"], q["x_end"]
    zfill = fill_top(p, p["target_count"])
    zbox = zfill + p["margin_top"]
    q["z_fill"], q["z_box"] = zfill, zbox
    files = {}

    # -- real sleeper: section counter-clockwise seen from +x (y to the right, z up):
    #    base (-b/2, zb) -> (b/2, zb) -> top (t/2, zs) -> (-t/2, zs)
    sec = [(-b / 2, zb), (b / 2, zb), (t / 2, zs), (-t / 2, zs)]
    names = {"x0": "far_end", "x1": "shoulder_end", 0: "base", 1: "crib_front", 2: "top", 3: "crib_back"}
    sl = prism_x(names, -L / 2, L / 2, sec)
    files["sleeper.stl"] = [sl[k] for k in ("base", "top", "crib_front", "crib_back", "shoulder_end", "far_end")]

    # -- aux sleeper: same base and crib faces up to the sleeper top, then vertical to z_box
    sec_aux = [(-b / 2, zb), (b / 2, zb), (t / 2, zs), (t / 2, zbox), (-t / 2, zbox), (-t / 2, zs)]
    names_aux = {key: "aux_sleeper" for key in ("x0", "x1", 0, 1, 2, 3, 4, 5)}
    files["aux_sleeper.stl"] = list(prism_x(names_aux, -L / 2, L / 2, sec_aux).values())

    # -- aux slopes: quads counter-clockwise seen from the ballast side
    y0, y1 = -s / 2, s / 2
    sp = Solid("slope_pos")   # from the toe (xt, 0) up to the edge (xe, zt); ballast at smaller x
    sp.quad((xt, y0, 0.0), (xe, y0, zt), (xe, y1, zt), (xt, y1, 0.0))
    rp = Solid("riser_pos")
    rp.quad((xe, y0, zt), (xe, y0, zfill), (xe, y1, zfill), (xe, y1, zt))
    sn = Solid("slope_neg")
    sn.quad((-xt, y0, 0.0), (-xt, y1, 0.0), (-xe, y1, zt), (-xe, y0, zt))
    rn = Solid("riser_neg")
    rn.quad((-xe, y0, zt), (-xe, y1, zt), (-xe, y1, zfill), (-xe, y0, zfill))
    files["aux_slopes.stl"] = [sp, sn, rp, rn]

    # -- lid at z_top, normal -z (counter-clockwise seen from below), hole |x| < L/2, |y| < t/2
    def down_rect(solid, xa, xb, ya, yb):
        solid.quad((xa, ya, zt), (xa, yb, zt), (xb, yb, zt), (xb, ya, zt))

    lsp, lsn = Solid("lid_shoulder_pos"), Solid("lid_shoulder_neg")
    lcf, lcb = Solid("lid_crib_front"), Solid("lid_crib_back")
    down_rect(lsp, L / 2, xe, y0, y1)
    down_rect(lsn, -xe, -L / 2, y0, y1)
    down_rect(lcf, -L / 2, L / 2, t / 2, y1)
    down_rect(lcb, -L / 2, L / 2, y0, -t / 2)
    # shared vertices at the shoulder/crib seams: split the shoulder plates at y = +-t/2
    lsp.tris, lsn.tris = [], []
    for (ya, yb) in ((y0, -t / 2), (-t / 2, t / 2), (t / 2, y1)):
        down_rect(lsp, L / 2, xe, ya, yb)
        down_rect(lsn, -xe, -L / 2, ya, yb)
    files["aux_lid.stl"] = [lsp, lsn, lcf, lcb]

    # -- container: floor (normal +z, counter-clockwise seen from above). One rectangle: the slopes
    #    stand on it along the toe lines, which would make those edges non-manifold if the floor
    #    had vertices there (load aux_slopes.stl with own_vertices: true so nothing is joined).
    fl = Solid("floor")
    fl.quad((-xend, y0, 0.0), (xend, y0, 0.0), (xend, y1, 0.0), (-xend, y1, 0.0))
    ep = Solid("end_pos")   # x = +x_end, normal -x
    ep.quad((xend, y0, 0.0), (xend, y0, zbox), (xend, y1, zbox), (xend, y1, 0.0))
    en = Solid("end_neg")   # x = -x_end, normal +x
    en.quad((-xend, y0, 0.0), (-xend, y1, 0.0), (-xend, y1, zbox), (-xend, y0, zbox))
    files["container.stl"] = [fl, ep, en]

    # -- frictionless side walls
    sf = Solid("side_front")  # y = +s/2, normal -y
    sf.quad((-xend, y1, 0.0), (xend, y1, 0.0), (xend, y1, zbox), (-xend, y1, zbox))
    sb = Solid("side_back")   # y = -s/2, normal +y
    sb.quad((-xend, y0, 0.0), (-xend, y0, zbox), (xend, y0, zbox), (xend, y0, 0.0))
    files["sides.stl"] = [sf, sb]

    # -- fill region: the bed's profile up to z_fill with a slot where the aux sleeper stands.
    #    adem may place random spheres inside a closed mesh wall (it could be a container), so the
    #    region itself must leave the aux sleeper out. To keep the surface closed, faces that meet
    #    are split at the same points: x at -x_edge, -L/2, L/2, x_edge and y at -s/2, -t/2, t/2, s/2.
    fr = Solid("fill_region")
    X = [-xe, -L / 2, L / 2, xe]
    Y = [y0, -t / 2, t / 2, y1]
    zf = zfill
    for i in range(3):                       # top plate at z_fill, a 3x3 grid without the centre
        for j in range(3):
            if (i, j) != (1, 1):
                face(fr, [(X[i], Y[j], zf), (X[i + 1], Y[j], zf), (X[i + 1], Y[j + 1], zf),
                          (X[i], Y[j + 1], zf)], (0, 0, 1))
    for j in range(3):                       # strips along y so that all seams share vertices
        ya, yb = Y[j], Y[j + 1]
        for sx in (1, -1):
            face(fr, [(sx * xe, ya, zt), (sx * xe, yb, zt), (sx * xe, yb, zf), (sx * xe, ya, zf)],
                 (sx, 0, 0))                                               # riser
            face(fr, [(sx * xt, ya, 0.0), (sx * xt, yb, 0.0), (sx * xe, yb, zt), (sx * xe, ya, zt)],
                 (sx, 0, n))                                               # slope
        face(fr, [(-xt, ya, 0.0), (xt, ya, 0.0), (xt, yb, 0.0), (-xt, yb, 0.0)], (0, 0, -1))  # floor
    cap = [(-xt, 0.0), (xt, 0.0), (xe, zt), (xe, zf), (L / 2, zf), (-L / 2, zf), (-xe, zf), (-xe, zt)]
    for yc, sy in ((y0, -1), (y1, 1)):       # the two ends of the slice
        face(fr, [(x, yc, z) for (x, z) in cap], (0, sy, 0))
    # the slot: the aux sleeper's faces between its base and z_fill, normals into the sleeper
    face(fr, [(-L / 2, -b / 2, zb), (L / 2, -b / 2, zb), (L / 2, b / 2, zb), (-L / 2, b / 2, zb)], (0, 0, 1))
    for sy in (1, -1):
        face(fr, [(-L / 2, sy * b / 2, zb), (L / 2, sy * b / 2, zb), (L / 2, sy * t / 2, zs),
                  (-L / 2, sy * t / 2, zs)], (0, -sy, 0))                  # crib face
        face(fr, [(-L / 2, sy * t / 2, zs), (L / 2, sy * t / 2, zs), (L / 2, sy * t / 2, zf),
                  (-L / 2, sy * t / 2, zf)], (0, -sy, 0))                  # vertical part
    end = [(-b / 2, zb), (b / 2, zb), (t / 2, zs), (t / 2, zf), (-t / 2, zf), (-t / 2, zs)]
    for sx in (1, -1):
        face(fr, [(sx * L / 2, y, z) for (y, z) in end], (-sx, 0, 0))
    files["fill_region.stl"] = [fr]
    return files, q


# ----------------------------------------------------------------------------- checks
def edge_use(solids):
    """Directed edge counts over all triangles of a list of solids (vertices compared exactly)."""
    use = {}
    for sol in solids:
        for tri in sol.tris:
            for k in range(3):
                e = (tri[k], tri[(k + 1) % 3])
                use[e] = use.get(e, 0) + 1
    return use


def closed(solids):
    """True when every edge is used exactly once in each direction (a closed, consistently
    oriented surface)."""
    use = edge_use(solids)
    return all(cnt == 1 and use.get((e[1], e[0]), 0) == 1 for e, cnt in use.items())


def signed_volume(solids):
    v = 0.0
    for sol in solids:
        for a, b_, c in sol.tris:
            v += dot(a, cross(b_, c)) / 6.0
    return v


def check(files, q, p):
    """Closedness, orientation and normals; returns a list of (ok, message)."""
    out = []
    # closed solids with outward normals (positive signed volume): the sleepers and fill region
    L, b, t, h = p["sleeper_length"], p["sleeper_base_width"], p["sleeper_top_width"], p["sleeper_height"]
    expect = {
        "sleeper.stl": L * 0.5 * (b + t) * h,
        "aux_sleeper.stl": L * (0.5 * (b + t) * h + t * (q["z_box"] - q["z_sleeper_top"])),
        "fill_region.stl": None,
    }
    for name, vol in expect.items():
        sols = files[name]
        c = closed(sols)
        v = signed_volume(sols)
        ok = c and v > 0 and (vol is None or abs(v - vol) < 1e-9 * max(1.0, vol))
        msg = f"{name}: closed={c}, signed volume {v:.6f} m^3"
        if vol is not None:
            msg += f" (expected {vol:.6f})"
        out.append((ok, msg))
    # fill region volume = bed volume + sleeper section below z_top + strip above it
    zt, zf = q["z_top"], q["z_fill"]
    s = p["slice_length"]
    vr = (2 * q["x_edge"] * zt + p["shoulder_slope"] * zt * zt) * s + 2 * q["x_edge"] * s * (zf - zt)
    vr -= L * (0.5 * (b + t) * h + t * (zf - q["z_sleeper_top"]))    # the aux sleeper's slot
    v = signed_volume(files["fill_region.stl"])
    out.append((abs(v - vr) < 1e-9 * vr, f"fill_region.stl: volume {v:.6f} m^3, profile minus the "
                                         f"aux sleeper gives {vr:.6f}"))

    # every face of a wall points towards the ballast: a probe point inside the bed
    probe_bed = (0.0, 0.0, 0.5 * q["z_base"])               # under the sleeper, mid-depth
    for name in ("aux_slopes.stl", "aux_lid.stl", "container.stl", "sides.stl"):
        for sol in files[name]:
            bad = 0
            for tri in sol.tris:
                nrm, _ = unit_normal(tri)
                cen = tuple(sum(v[i] for v in tri) / 3 for i in range(3))
                probe = probe_bed
                if sol.name.startswith("riser"):
                    probe = (0.0, 0.0, 0.5 * (q["z_top"] + q["z_fill"]))
                if sol.name.startswith("end"):
                    probe = (0.0, 0.0, 0.5 * q["z_box"])
                if sol.name.startswith("side"):
                    probe = (cen[0], 0.0, cen[2])
                if dot(nrm, sub(probe, cen)) <= 0:
                    bad += 1
            out.append((bad == 0, f"{name}:{sol.name}: {len(sol.tris)} triangles, "
                                  f"{bad} facing away from the ballast"))
    # sleeper faces: outward normals along the expected directions
    want = {"base": (0, 0, -1), "top": (0, 0, 1), "shoulder_end": (1, 0, 0), "far_end": (-1, 0, 0),
            "crib_front": (0, 1, 0), "crib_back": (0, -1, 0)}
    for sol in files["sleeper.stl"]:
        okf = all(dot(unit_normal(tri)[0], want[sol.name]) > 0.9 for tri in sol.tris)
        area = sum(unit_normal(tri)[1] for tri in sol.tris)
        out.append((okf, f"sleeper.stl:{sol.name}: {len(sol.tris)} triangles, area {area:.4f} m^2, "
                         f"normals {'outward' if okf else 'WRONG'}"))
    return out


# ----------------------------------------------------------------------------- output
def fmt(v):
    """Shortest text that reads back as the same double (so equal vertices stay equal)."""
    r = repr(float(v))
    return "0" if r in ("0.0", "-0.0") else r


def write_stl(path, solids):
    lines = []
    for sol in solids:
        lines.append(f"solid {sol.name}")
        for tri in sol.tris:
            nrm, _ = unit_normal(tri)
            lines.append("  facet normal " + " ".join(fmt(round(c, 12)) for c in nrm))
            lines.append("    outer loop")
            for v in tri:
                lines.append("      vertex " + " ".join(fmt(c) for c in v))
            lines.append("    endloop")
            lines.append("  endfacet")
        lines.append(f"endsolid {sol.name}")
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write("\n".join(lines) + "\n")
    os.replace(tmp, path)


def parse_set(items):
    out = {}
    for it in items:
        if "=" not in it:
            raise SystemExit(f"--set wants name=value, got '{it}'")
        k, v = it.split("=", 1)
        if k not in DEFAULTS:
            raise SystemExit(f"unknown parameter '{k}'; known: {', '.join(DEFAULTS)}")
        out[k] = float(v)
    return out


def report(p, q):
    vb = bed_volume(p)
    vs = mean_sphere_volume(p)
    n = sphere_count(p)
    dmean = 0.5 * (p["d_min"] + p["d_max"])
    lines = [
        "parameters: " + ", ".join(f"{k}={v:g}" for k, v in p.items()),
        f"levels: sleeper base z={q['z_base']:.3f}, sleeper top z={q['z_sleeper_top']:.3f}, "
        f"crib/shoulder top z={q['z_top']:.3f} m",
        f"slope edge x=+-{q['x_edge']:.3f}, toe x=+-{q['x_toe']:.3f}, end walls x=+-{q['x_end']:.3f} m",
        f"bed bulk volume in the slice: {vb:.4f} m^3 (sleeper volume "
        f"{p['sleeper_length'] * sleeper_section_area(p, 0, p['sleeper_height']):.4f} m^3)",
        f"spheres: d uniform {p['d_min']:g}-{p['d_max']:g} m (number mean {dmean:.4f} m), "
        f"<v> = {vs:.4e} m^3 (a {dmean:g} m sphere: {math.pi / 6 * dmean ** 3:.4e})",
        f"estimated count at packing fraction {p['packing_fraction']:g}: {n:.0f} "
        f"(target {p['target_count']:.0f}; {p['packing_fraction'] * vb / (math.pi / 6 * dmean ** 3):.0f} "
        f"if all were {dmean:g} m)",
    ]
    if "z_fill" in q:
        lines.append(f"loose fill of {p['target_count']:.0f} spheres at solid fraction "
                     f"{p['fill_fraction']:g}: up to z_fill={q['z_fill']:.3f} m; container top "
                     f"z={q['z_box']:.3f} m")
    return "\n".join(lines)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", help="output folder (default: meshes/ beside this script, "
                                   "meshes/PRESET/ with --preset)")
    ap.add_argument("--preset", choices=sorted(PRESETS), help="start from a named variant")
    ap.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                    help="change a parameter (repeatable); names: " + ", ".join(DEFAULTS))
    ap.add_argument("--no-write", action="store_true", help="estimate and check only")
    ap.add_argument("--solve-depth", type=float, metavar="COUNT",
                    help="print the ballast depth that gives COUNT spheres, then exit")
    a = ap.parse_args(argv)
    p = dict(DEFAULTS)
    if a.preset:
        p.update(PRESETS[a.preset])
    p.update(parse_set(a.set))
    here = os.path.dirname(os.path.abspath(__file__))
    out = a.out or os.path.join(here, "meshes", a.preset or "")
    if a.solve_depth:
        d = solve_depth(p, a.solve_depth)
        print(f"ballast_depth={d:.4f} m gives {sphere_count(dict(p, ballast_depth=d)):.0f} spheres")
        return 0
    files, q = build(p)
    print(report(p, q))
    lift, table = lid_probe(p, q)
    print(f"lid probe (aux_lid.stl): translate [0, 0, {lift!r}], motion table {table!r} "
          f"(travel {-table_travel(table):.6f} m)")
    results = check(files, q, p)
    for ok, msg in results:
        print(("ok   " if ok else "FAIL ") + msg)
    if not all(ok for ok, _ in results):
        print("mesh checks failed; nothing written", file=sys.stderr)
        return 1
    if not a.no_write:
        os.makedirs(out, exist_ok=True)
        for name, sols in files.items():
            write_stl(os.path.join(out, name), sols)
        print(f"wrote {len(files)} files to {os.path.relpath(out)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
