/* The case-file schema table and what is derived from it: look-ups, range checks, the words of
 * error messages and the Markdown reference. */
#include "schema.h"

#include <math.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "adem/laws.h"

#define NUM ADEM_SCHEMA_NUMBER
#define INT ADEM_SCHEMA_INT
#define BOOL ADEM_SCHEMA_BOOL
#define STR ADEM_SCHEMA_STRING
#define NAME ADEM_SCHEMA_NAME
#define VEC3 ADEM_SCHEMA_VEC3
#define ENUM ADEM_SCHEMA_ENUM
#define AUTO ADEM_SCHEMA_AUTO
#define PAIR ADEM_SCHEMA_NAME_PAIR
#define MAP ADEM_SCHEMA_MAP
#define LIST ADEM_SCHEMA_LIST
#define IDS ADEM_SCHEMA_ID_LIST
#define TABLE ADEM_SCHEMA_TABLE
#define NUMS ADEM_SCHEMA_NUMBER_LIST
#define SETS ADEM_SCHEMA_SETTINGS
#define BOOL3 ADEM_SCHEMA_BOOL3
#define REQ .need = ADEM_SCHEMA_REQUIRED
#define GT(x) .lo = (x), .range = ADEM_RANGE_MIN_OPEN
#define GE(x) .lo = (x), .range = ADEM_RANGE_MIN
#define GT_LE(a, b) .lo = (a), .hi = (b), .range = ADEM_RANGE_MIN_OPEN | ADEM_RANGE_MAX
#define GT_LT(a, b) .lo = (a), .hi = (b), .range = ADEM_RANGE_MIN_OPEN | ADEM_RANGE_MAX_OPEN

/* The keys of a run-until condition under prefix P ("time.until", "stages[].until"). */
// clang-format off
#define UNTIL_ENTRIES(P, WHAT)                                                                     \
  {P, NULL, MAP, "", NULL, NULL, .doc = "End " WHAT " early, at the first check where every condition given has held for `for` seconds (docs/insertion-and-stages.md). Give `kinetic_energy_per_particle`, `kinetic_energy_ratio`, `wall_load` or more than one; the progress line shows each against its threshold."}, \
  {P ".kinetic_energy_per_particle", NULL, NUM, "J", NULL, NULL, GT(0), .doc = "Translational plus rotational kinetic energy per particle below this (1e-7 J: an rms speed of about 1 mm/s for 5 cm stones). Not while a pour still has particles to insert. A bed without rolling resistance keeps rocking: its value can swing over more than a decade (4e-11 to 1.1e-9 J for 5 mm glass) and never stay below a threshold inside that band; watch the progress line and set it above the band, or use `kinetic_energy_ratio`."}, \
  {P ".kinetic_energy_ratio", NULL, NUM, "", NULL, NULL, GT(0), .doc = "Relative form: the total kinetic energy below this fraction of sum m |g| d, the energy that would lift every particle by its diameter (independent of size and density; 1e-4: an rms speed of about 1.4 % of sqrt(g d)). Needs gravity."}, \
  {P ".wall_load", NULL, MAP, "", NULL, NULL, .doc = "A wall's load steady: its largest and smallest value since the streak began differ by at most `tolerance` times the larger magnitude (a wall that carries nothing is not steady)."}, \
  {P ".wall_load.wall", NULL, STR, "", NULL, NULL, REQ, .doc = "A plane (a box's: `NAME.xmin` ...), a mesh group or a mesh file of several groups (their total), as named in the CSV."}, \
  {P ".wall_load.direction", NULL, VEC3, "", NULL, "along gravity", .doc = "The load is the force of the particles on the wall along this direction (any length > 0)."}, \
  {P ".wall_load.tolerance", NULL, NUM, "", "0.01", NULL, GT(0), .doc = "Relative spread allowed."}, \
  {P ".for", NULL, NUM, "s", "0", NULL, GE(0), .doc = "How long every condition must hold, measured between checks."}, \
  {P ".interval", NULL, NUM, "s", NULL, "`for` / 10, or every step when `for` is 0", GT(0), .doc = "Simulated time between checks (rounded to whole steps): the run ends on a check."}
// clang-format on

/* Every key of a case file. Order: as the reference lists them. */
// clang-format off
static const adem_schema_entry base_schema[] = {
    {"name", NULL, STR, "", NULL, "file name without directory and extension", .doc = "Case name; the default output directory is `out/<name>`."},
    {"seed", NULL, INT, "", "1", NULL, GE(0), .doc = "Seed of the random fills; the same seed gives the same positions on every platform."},

    {"materials", NULL, LIST, "", NULL, NULL, GE(1), REQ, .doc = "Materials of particles and walls."},
    {"materials[].name", NULL, NAME, "", NULL, NULL, REQ, .doc = "Unique name that particle sets, walls and interactions refer to."},
    {"materials[].density", NULL, NUM, "kg/m^3", NULL, NULL, GT(0), .need = ADEM_SCHEMA_REQUIRED_IF, .need_doc = "for materials that particles use", .doc = "Density rho."},
    {"materials[].youngs_modulus", NULL, NUM, "Pa", NULL, NULL, GT(0), .need = ADEM_SCHEMA_REQUIRED_IF, .need_doc = "unless `rigid: true`", .doc = "Young's modulus E of the real material (see `stiffness_factor`)."},
    {"materials[].poisson_ratio", NULL, NUM, "", NULL, NULL, GT_LT(-1, 0.5), .need = ADEM_SCHEMA_REQUIRED_IF, .need_doc = "unless `rigid: true`", .doc = "Poisson's ratio nu."},
    {"materials[].restitution", NULL, NUM, "", "0.5", NULL, GT_LE(0, 1), .doc = "Coefficient of restitution e of a collision between two spheres of this material."},
    {"materials[].friction", NULL, NUM, "", "0.5", NULL, GE(0), .doc = "Sliding friction coefficient mu_s."},
    {"materials[].stiffness_factor", NULL, NUM, "", "1", NULL, GT_LE(0, 1), .doc = "Stiffness reduction f = E_mod/E; surface energy is scaled by f^(2/5) to keep the pull-off force. Without adhesion (Hertz, no surface energy) it is the same as giving `youngs_modulus` f E."},
    {"materials[]", NULL, ADEM_SCHEMA_LAW_PARAMS, .doc = "(one entry per contact-law parameter)"},
    {"materials[].rigid", NULL, BOOL, "", "false", NULL, .doc = "`true`: infinite Young's modulus; for wall materials only."},

    {"interactions", NULL, LIST, "", NULL, NULL, .doc = "Per-pair overrides of how two materials interact; pairs not listed use the defaults."},
    {"interactions[].name", NULL, NAME, "", NULL, NULL, .doc = "Optional unique name, so that `--set interactions.NAME.friction=0.3` and a stage's `set` find the entry however the list is ordered (an index works too)."},
    {"interactions[].materials", NULL, PAIR, "", NULL, NULL, REQ, .doc = "The two materials (may be the same one twice). Each pair may appear once."},
    {"interactions[].restitution", NULL, NUM, "", NULL, "derived from the two materials", GT_LE(0, 1), .doc = "Coefficient of restitution of this pair."},
    {"interactions[].friction", NULL, NUM, "", NULL, "derived from the two materials", GE(0), .doc = "Sliding friction coefficient of this pair."},
    {"interactions[].normal", NULL, ENUM, "", "hertz", NULL, .choices = "@normal", .doc = "Normal force law (see Contact laws)."},
    {"interactions[].damping", NULL, ENUM, "", "viscoelastic", NULL, .choices = "@damping", .doc = "Damping law of the normal and tangential dashpots."},
    {"interactions[].tangential", NULL, ENUM, "", "incremental", NULL, .choices = "@tangential", .doc = "Tangential force law: incremental (Mindlin-Deresiewicz, cannot create energy) or total (H14 as written)."},
    {"interactions[].rolling", NULL, ENUM, "", "none", NULL, .choices = "@rolling", .doc = "Rolling resistance law."},
    {"interactions[]", NULL, ADEM_SCHEMA_LAW_PARAMS, .doc = "(one entry per contact-law parameter)"},

    {"groups", NULL, LIST, "", NULL, NULL, .doc = "Named groups of particles with a constant external force; group `default` always exists (no force unless listed)."},
    {"groups[].name", NULL, NAME, "", NULL, NULL, REQ, .doc = "Unique name; `default` sets the force of the particles without a `group`."},
    {"groups[].external_force", NULL, VEC3, "N", "[0, 0, 0]", NULL, .doc = "Constant force on every particle of the group."},

    {"particles", NULL, LIST, "", NULL, NULL, .need = ADEM_SCHEMA_REQUIRED_IF, .need_doc = "unless there are `pours`", .discriminator = "type", .doc = "Particle sets, created in order; each has a `type`."},
    {"particles[].type", NULL, ENUM, "", NULL, NULL, REQ, .choices = "list|lattice|random|state", .doc = "`list`: explicit spheres; `lattice`: simple cubic lattice in a box; `random`: random non-overlapping fill of a box, a cylinder or a closed STL volume (docs/insertion-and-stages.md); `state`: the particles of another run's checkpoint."},
    {"particles[].file", "state", STR, "", NULL, NULL, REQ, .doc = "A checkpoint written by adem (`OUT/checkpoint`), relative to the case file's folder: its particles' positions, velocities, spins and radii, their materials by name (this case must have them; their properties are this case's) and their ids (the same when this set comes first). Contact history is not carried over; a settled bed overlaps, so set `limits.initial_overlap`."},
    {"particles[].keep_inside", "state", MAP, "", NULL, NULL, .doc = "Keep only the checkpoint's particles whose centre lies in this box, e.g. to trim a packed bed to its final height (as a track bed is levelled at the sleepers' top); the kept particles get ids 0, 1, ... in the order of their old ids."},
    {"particles[].keep_inside.min", NULL, VEC3, "m", NULL, NULL, REQ, .doc = "Lower corner of the box."},
    {"particles[].keep_inside.max", NULL, VEC3, "m", NULL, NULL, REQ, .doc = "Upper corner; greater than `min` in every component."},
    {"particles[].material", "list|lattice|random", NAME, "", NULL, NULL, REQ, .doc = "Material of the set's spheres; it needs a `density` and must not be rigid."},
    {"particles[].group", NULL, NAME, "", "default", NULL, .doc = "Group of the set's spheres."},
    {"particles[].frozen", "list|lattice|random", BOOL, "", "false", NULL, .doc = "`true`: the set's spheres are fixed (a rough wall or floor, docs/outlets-and-flow.md): never integrated, they move with the wall named by `attach` (or stay where they are), touch no wall and no other frozen sphere, and the forces on them are that wall's load."},
    {"particles[].attach", "list|lattice|random", NAME, "", NULL, "none: fixed in space", .doc = "A plane or mesh group (as named in the CSV) whose prescribed motion the frozen spheres follow and whose load includes the forces on them; implies `frozen: true`. Not a servo wall."},
    {"particles[].spheres", "list", LIST, "", NULL, NULL, GE(1), REQ, .doc = "The spheres; two spheres of the list must not overlap."},
    {"particles[].spheres[].position", NULL, VEC3, "m", NULL, NULL, REQ, .doc = "Centre."},
    {"particles[].spheres[].radius", NULL, NUM, "m", NULL, NULL, GT(0), REQ, .doc = "Radius."},
    {"particles[].spheres[].velocity", NULL, VEC3, "m/s", "[0, 0, 0]", NULL, .doc = "Initial velocity."},
    {"particles[].spheres[].angular_velocity", NULL, VEC3, "rad/s", "[0, 0, 0]", NULL, .doc = "Initial angular velocity."},
    {"particles[].radius", "lattice", NUM, "m", NULL, NULL, GT(0), REQ, .doc = "Radius of every sphere."},
    {"particles[].spacing", "lattice", NUM, "m", NULL, NULL, GT(0), REQ, .doc = "Distance between neighbouring centres; at least 2 radius."},
    {"particles[].radius", "random", MAP, "", NULL, NULL, REQ, .discriminator = "distribution", .doc = "Radius distribution, e.g. `{distribution: uniform, min: 1e-3, max: 2e-3}`."},
    {"particles[].radius.distribution", NULL, ENUM, "", NULL, NULL, REQ, .choices = "constant|uniform|normal|lognormal|discrete", .doc = "Shape of the distribution; normal and lognormal are truncated to radii that fit the region (drawn again)."},
    {"particles[].radius.value", "constant", NUM, "m", NULL, NULL, GT(0), REQ, .doc = "The radius."},
    {"particles[].radius.min", "uniform", NUM, "m", NULL, NULL, GT(0), REQ, .doc = "Smallest radius."},
    {"particles[].radius.max", "uniform", NUM, "m", NULL, NULL, GT(0), REQ, .doc = "Largest radius; greater than `min`."},
    {"particles[].radius.mean", "normal|lognormal", NUM, "m", NULL, NULL, GT(0), REQ, .doc = "Mean of the radius."},
    {"particles[].radius.std", "normal|lognormal", NUM, "m", NULL, NULL, GE(0), REQ, .doc = "Standard deviation of the radius (for lognormal: of the radius itself, not of its logarithm)."},
    {"particles[].radius.values", "discrete", NUMS, "m", NULL, NULL, GT(0), REQ, .doc = "The radii, e.g. `[0.01, 0.015, 0.02]`."},
    {"particles[].radius.weights", "discrete", NUMS, "", NULL, "all equal", GE(0), .doc = "Relative number frequency of each radius (same length as `values`, not all 0)."},
    {"particles[].min", "lattice", VEC3, "m", NULL, NULL, REQ, .doc = "Lower corner of the box; whole spheres lie inside it."},
    {"particles[].max", "lattice", VEC3, "m", NULL, NULL, REQ, .doc = "Upper corner of the box; greater than `min` in every component."},
    {"particles[].min", "random", VEC3, "m", NULL, NULL, .need = ADEM_SCHEMA_REQUIRED_IF, .need_doc = "unless `region` is given", .doc = "Lower corner of the box to fill; whole spheres lie inside it."},
    {"particles[].max", "random", VEC3, "m", NULL, NULL, .need = ADEM_SCHEMA_REQUIRED_IF, .need_doc = "unless `region` is given", .doc = "Upper corner of the box; greater than `min` in every component."},
    {"particles[].region", "random", MAP, "", NULL, NULL, .discriminator = "shape", .doc = "Region to fill instead of the box `min`/`max`: `{shape: box, min, max}`, `{shape: cylinder, start, end, radius}` or `{shape: mesh, file}` (a closed STL surface)."},
    {"particles[].region.shape", NULL, ENUM, "", NULL, NULL, REQ, .choices = "box|cylinder|mesh", .doc = "`box`: axis-aligned box; `cylinder`: any axis; `mesh`: the inside of a closed STL surface (ray parity), whole spheres at least a radius from it."},
    {"particles[].region.min", "box", VEC3, "m", NULL, NULL, REQ, .doc = "Lower corner of the box."},
    {"particles[].region.max", "box", VEC3, "m", NULL, NULL, REQ, .doc = "Upper corner; greater than `min` in every component."},
    {"particles[].region.start", "cylinder", VEC3, "m", NULL, NULL, REQ, .doc = "Centre of one end disc."},
    {"particles[].region.end", "cylinder", VEC3, "m", NULL, NULL, REQ, .doc = "Centre of the other end disc; the axis runs from `start` to `end`."},
    {"particles[].region.radius", "cylinder", NUM, "m", NULL, NULL, GT(0), REQ, .doc = "Radius of the cylinder."},
    {"particles[].region.file", "mesh", STR, "", NULL, NULL, REQ, .doc = "Closed STL surface (every edge shared by two triangles); a relative path is taken from the folder of the case file."},
    {"particles[].region.scale", "mesh", NUM, "", "1", NULL, GT(0), .doc = "Factor from file units to metres, applied first."},
    {"particles[].region.translate", "mesh", VEC3, "m", "[0, 0, 0]", NULL, .doc = "Translation applied after the scale."},
    {"particles[].count", "lattice", INT, "", "0", NULL, GE(0), .doc = "Most spheres to create, filling x first, then y, then z; 0 fills the box."},
    {"particles[].count", "random", INT, "", NULL, NULL, GE(1), .need = ADEM_SCHEMA_REQUIRED_IF, .need_doc = "unless `solid_fraction` or `fill_level` is given", .doc = "Number of spheres to place."},
    {"particles[].solid_fraction", "random", NUM, "", NULL, NULL, GT_LT(0, 1), .doc = "Instead of `count`: radii are drawn until their volume is closest to this fraction of the region's volume (within half the largest sphere's volume); random packing jams near 0.3-0.4."},
    {"particles[].fill_level", "random", MAP, "", NULL, NULL, .doc = "Instead of `count` or `solid_fraction`: as many spheres as make a settled bed of `packing` up to a height `level` of the region (a container's inside, e.g. a drum's: `region: {shape: cylinder, ...}`), or filling a `fraction` of its volume (a drum 36 % full); they are placed at random in the whole region and settle to it."},
    {"particles[].fill_level.level", NULL, NUM, "m", NULL, NULL, .doc = "Height (z) of the bed's top: the bulk volume is the region's volume below it."},
    {"particles[].fill_level.fraction", NULL, NUM, "", NULL, NULL, GT_LE(0, 1), .doc = "Instead of `level`: the bulk volume is this fraction of the region's volume."},
    {"particles[].fill_level.packing", NULL, NUM, "", "0.6", NULL, GT_LT(0, 1), .doc = "Solid fraction of the settled bed (0.6: random packing of spheres); the set's solid fraction is packing x bulk volume / region volume, at most 0.45."},
    {"particles[].max_attempts", "random", INT, "", NULL, "max(1000000, 100 count)", GE(1), .doc = "Total number of trial positions; when used up, the fill stops with a warning giving the number placed."},
    {"particles[].velocity", "lattice|random", VEC3, "m/s", "[0, 0, 0]", NULL, .doc = "Initial velocity of every sphere."},
    {"particles[].angular_velocity", "lattice|random", VEC3, "rad/s", "[0, 0, 0]", NULL, .doc = "Initial angular velocity of every sphere."},

    {"walls", NULL, LIST, "", NULL, NULL, .discriminator = "type", .doc = "Walls; each has a `type`."},
    {"walls[].type", NULL, ENUM, "", NULL, NULL, REQ, .choices = "plane|box|mesh|cylinder|plate", .doc = "`plane`: an infinite plane; `box`: six planes facing inwards, named NAME.xmin, NAME.xmax, ...; `mesh`: the triangles of an STL file (docs/meshes.md), one group per file or per `solid` of an ASCII file; `cylinder`: an analytic cylinder (a drum, a pipe), touched inside or outside, with optional end caps NAME.cap0 and NAME.cap1 (docs/walls.md); `plate`: a flat two-sided plate, optionally a disc, with an optional circular hole (an orifice)."},
    {"walls[].name", NULL, NAME, "", NULL, "`wall<index>`; a mesh: the solid's name, else the file's stem", .doc = "Unique name (used in output). A mesh file with several solids makes groups NAME.SOLID."},
    {"walls[].material", NULL, NAME, "", NULL, NULL, REQ, .doc = "Material of the wall."},
    {"walls[].active", NULL, BOOL, "", "true", NULL, .doc = "`false`: the wall is there but switched off (no contacts) until a stage sets `walls.NAME.active: true`."},
    {"walls[].point", "plane|cylinder|plate", VEC3, "m", NULL, NULL, REQ, .doc = "A point of the plane; a cylinder: a point of its axis, its first end when it has a `length`; a plate: its centre (the hole's)."},
    {"walls[].normal", "plane|plate", VEC3, "", NULL, NULL, REQ, .doc = "Normal pointing to the particles' side; non-zero, normalised by the loader. A plate is touched from both sides."},
    {"walls[].axis", "cylinder", VEC3, "", NULL, NULL, REQ, .doc = "Direction of the cylinder's axis (any length > 0); with a `length` the cylinder runs from `point` along it."},
    {"walls[].radius", "cylinder|plate", NUM, "m", NULL, NULL, GE(0), .need = ADEM_SCHEMA_REQUIRED_IF, .need_doc = "for a cylinder (> 0)", .doc = "A cylinder's radius; a plate's outer radius (a disc; omitted or 0: unbounded)."},
    {"walls[].length", "cylinder", NUM, "m", "0", NULL, GE(0), .doc = "Length from `point` along `axis`; 0: infinite (a drum or pipe periodic along its axis). An open end is a rim a sphere can roll over."},
    {"walls[].caps", "cylinder", BOOL, "", "false", NULL, .doc = "Close both ends of a finite cylinder with flat discs, walls NAME.cap0 (at `point`) and NAME.cap1, moving with it, each with its own CSV columns."},
    {"walls[].contact", "cylinder", ENUM, "", "inside", NULL, .choices = "inside|outside", .doc = "`inside`: the particles are within the cylinder (a drum); `outside`: around it (a rod, an obstacle)."},
    {"walls[].hole_radius", "plate", NUM, "m", "0", NULL, GE(0), .doc = "Radius of a circular hole about `point` (an orifice); 0: none. Its rim is a circle a sphere rolls over without a jump."},
    {"walls[].velocity", "plane", VEC3, "m/s", "[0, 0, 0]", NULL, .doc = "Translation velocity of the plane."},
    {"walls[].motion", "plane|mesh|cylinder|plate", MAP, "", NULL, NULL, .doc = "Prescribed motion, an exact function of time: a translation (`velocity`, `table` or `positions`) and a `rotation`. A mesh that moves needs its own vertices. The CSV gives a moving wall its displacement (`WALL_ux_m` ...), the power its drive puts into the particles, -(F . v + T . omega) (`WALL_drive_power_W`, whose time integral is the wall work of the energy balance; a rotating plane's is NaN: its torque is not summed) and, for a mesh, the particles' torque about its rotation axis (`WALL_axis_torque_Nm`; the drive holds it with the opposite torque)."},
    {"walls[].motion.velocity", NULL, VEC3, "m/s", NULL, NULL, .doc = "Constant translation velocity; not with `table` or `positions`."},
    {"walls[].motion.table", NULL, TABLE, "s, m/s", NULL, NULL, GE(1), .doc = "Piecewise-linear translation velocity: rows [t, vx, vy, vz], t strictly increasing; constant before the first row and after the last; not with `velocity` or `positions`."},
    {"walls[].motion.positions", NULL, TABLE, "s, m", NULL, NULL, GE(1), .doc = "Piecewise-linear translation: rows [t, x, y, z], the displacement from where the wall is placed (by the case, or where a stage's new motion finds it), t strictly increasing; the wall is exactly there at each row's time, moves at the constant velocity of each segment, and holds the first row's displacement before it and the last row's after it (it stops). E.g. a gate that opens: `[[0.2, 0, 0, 0], [0.25, 0.06, 0, 0]]`. Not with `velocity` or `table`."},
    {"walls[].motion.rotation", NULL, MAP, "", NULL, NULL, .doc = "Rotation at a constant rate about an axis through `center`; the axis travels with the translation."},
    {"walls[].motion.rotation.axis", NULL, VEC3, "", NULL, NULL, REQ, .doc = "Axis direction (any length > 0); the rotation is right-handed about it."},
    {"walls[].motion.rotation.center", NULL, VEC3, "m", NULL, NULL, REQ, .doc = "A point of the axis at t = 0."},
    {"walls[].motion.rotation.speed", NULL, NUM, "rad/s", NULL, NULL, REQ, .doc = "Angular speed."},
    /* ---- servo (force-controlled) wall motion ---- */
    {"walls[].motion.servo", NULL, MAP, "", NULL, NULL, .doc = "Force control along `axis`: the wall's velocity along it is clamp(gain (F - target_force), +-max_speed), F the particles' force on the wall (a mesh: on its whole file, or on `groups`) along `axis` in the last force pass; this replaces the translation's component along `axis` (the others and the rotation are kept) and the displacement is integrated step by step (in checkpoints). Stable for gain K dt < 1, K the stiffness of what the wall presses on (adem warns above 0.5 from its contacts); a time constant 1/(gain K) of many collision times is a good choice. CSV columns `WALL_servo_u_m` and `WALL_servo_F_N` (the measured, filtered force)."},
    {"walls[].motion.servo.axis", NULL, VEC3, "", NULL, NULL, REQ, .doc = "Direction the servo acts along (any length > 0): the wall moves along +axis when the particles push on it along +axis harder than `target_force`."},
    {"walls[].motion.servo.target_force", NULL, NUM, "N", NULL, NULL, REQ, .doc = "Wanted force of the particles on the wall along `axis` (e.g. a sleeper's weight W on the ballast under it: axis [0, 0, 1], target W)."},
    {"walls[].motion.servo.gain", NULL, NUM, "m/(N s)", NULL, NULL, GT(0), REQ, .doc = "Speed per newton of force error."},
    {"walls[].motion.servo.max_speed", NULL, NUM, "m/s", NULL, NULL, GT(0), REQ, .doc = "Largest speed along `axis`; it also bounds the servo's travel the neighbour skin must cover."},
    {"walls[].motion.servo.filter", NULL, NUM, "s", "0", NULL, GE(0), .doc = "Time constant of a first-order low-pass on the measured force; 0: none."},
    {"walls[].motion.servo.travel", NULL, NUMS, "m", NULL, "no limits", .doc = "`[min, max]`, min <= 0 <= max: limits of the servo displacement from where the motion began; the wall stops at them."},
    {"walls[].motion.servo.groups", NULL, STR, "", NULL, "every group of the file", .doc = "Mesh walls: the group (or list of groups), by solid name or full group name, whose load is measured; the whole file moves."},
    /* ---- end of servo ---- */
    {"walls[].min", "box", VEC3, "m", NULL, NULL, REQ, .doc = "Lower corner of the box."},
    {"walls[].max", "box", VEC3, "m", NULL, NULL, REQ, .doc = "Upper corner of the box; greater than `min` in every component."},
    {"walls[].file", "mesh", STR, "", NULL, NULL, REQ, .doc = "STL file, ASCII or binary; a relative path is taken from the folder of the case file."},
    {"walls[].scale", "mesh", NUM, "", "1", NULL, GT(0), .doc = "Factor from file units to metres (0.001 for a file in mm), applied first."},
    {"walls[].rotate", "mesh", LIST, "", NULL, NULL, .doc = "Rotation applied after the scale: `{axis: [x, y, z], angle: degrees}`, or a list of them applied in order. Multiples of 90 degrees about a coordinate axis are exact."},
    {"walls[].rotate[].axis", NULL, VEC3, "", NULL, NULL, REQ, .doc = "Axis direction (any length > 0); right-handed."},
    {"walls[].rotate[].angle", NULL, NUM, "deg", NULL, NULL, REQ, .doc = "Angle."},
    {"walls[].translate", "mesh", VEC3, "m", "[0, 0, 0]", NULL, .doc = "Translation applied last: x' = R (scale x) + translate."},
    {"walls[].own_vertices", "mesh", BOOL, "", NULL, "`true` if the mesh has a `motion`, else `false`", .doc = "`true`: share no vertex with other meshes (needed to move); `false`: points equal to another mesh's are joined, so a seam is an ordinary edge."},
    {"walls[].torque_about", "mesh", VEC3, "m", NULL, "each group's area centroid (and the file's)", .doc = "Point at t = 0, carried with the wall's motion, that the CSV torques of the mesh's groups and of the whole file are taken about."},

    {"pours", NULL, LIST, "", NULL, NULL, .doc = "Particles inserted while the run goes on: in a region, at a rate, during a time window, overlapping nothing already there (docs/insertion-and-stages.md)."},
    {"pours[].name", NULL, NAME, "", NULL, "`pour<index>`", .doc = "Unique name (for messages)."},
    {"pours[].material", NULL, NAME, "", NULL, NULL, REQ, .doc = "Material of the poured spheres; it needs a `density` and must not be rigid."},
    {"pours[].group", NULL, NAME, "", "default", NULL, .doc = "Group of the poured spheres."},
    {"pours[].radius", NULL, MAP, "", NULL, NULL, REQ, .discriminator = "distribution", .doc = "Radius distribution, as for a random particle set."},
    {"pours[].radius.distribution", NULL, ENUM, "", NULL, NULL, REQ, .choices = "constant|uniform|normal|lognormal|discrete", .doc = "Shape of the distribution; normal and lognormal are truncated to radii that fit the region (drawn again)."},
    {"pours[].radius.value", "constant", NUM, "m", NULL, NULL, GT(0), REQ, .doc = "The radius."},
    {"pours[].radius.min", "uniform", NUM, "m", NULL, NULL, GT(0), REQ, .doc = "Smallest radius."},
    {"pours[].radius.max", "uniform", NUM, "m", NULL, NULL, GT(0), REQ, .doc = "Largest radius; greater than `min`."},
    {"pours[].radius.mean", "normal|lognormal", NUM, "m", NULL, NULL, GT(0), REQ, .doc = "Mean of the radius."},
    {"pours[].radius.std", "normal|lognormal", NUM, "m", NULL, NULL, GE(0), REQ, .doc = "Standard deviation of the radius (for lognormal: of the radius itself, not of its logarithm)."},
    {"pours[].radius.values", "discrete", NUMS, "m", NULL, NULL, GT(0), REQ, .doc = "The radii, e.g. `[0.01, 0.015, 0.02]`."},
    {"pours[].radius.weights", "discrete", NUMS, "", NULL, "all equal", GE(0), .doc = "Relative number frequency of each radius (same length as `values`, not all 0)."},
    {"pours[].region", NULL, MAP, "", NULL, NULL, REQ, .discriminator = "shape", .doc = "Region the particles are put in: `{shape: box, min, max}`, `{shape: cylinder, start, end, radius}` or `{shape: mesh, file}` (a closed STL surface)."},
    {"pours[].region.shape", NULL, ENUM, "", NULL, NULL, REQ, .choices = "box|cylinder|mesh", .doc = "`box`: axis-aligned box; `cylinder`: any axis; `mesh`: the inside of a closed STL surface (ray parity), whole spheres at least a radius from it."},
    {"pours[].region.min", "box", VEC3, "m", NULL, NULL, REQ, .doc = "Lower corner of the box."},
    {"pours[].region.max", "box", VEC3, "m", NULL, NULL, REQ, .doc = "Upper corner; greater than `min` in every component."},
    {"pours[].region.start", "cylinder", VEC3, "m", NULL, NULL, REQ, .doc = "Centre of one end disc."},
    {"pours[].region.end", "cylinder", VEC3, "m", NULL, NULL, REQ, .doc = "Centre of the other end disc; the axis runs from `start` to `end`."},
    {"pours[].region.radius", "cylinder", NUM, "m", NULL, NULL, GT(0), REQ, .doc = "Radius of the cylinder."},
    {"pours[].region.file", "mesh", STR, "", NULL, NULL, REQ, .doc = "Closed STL surface (every edge shared by two triangles); a relative path is taken from the folder of the case file."},
    {"pours[].region.scale", "mesh", NUM, "", "1", NULL, GT(0), .doc = "Factor from file units to metres, applied first."},
    {"pours[].region.translate", "mesh", VEC3, "m", "[0, 0, 0]", NULL, .doc = "Translation applied after the scale."},
    {"pours[].rate", NULL, NUM, "1/s", NULL, NULL, GT(0), .need = ADEM_SCHEMA_REQUIRED_IF, .need_doc = "unless `mass_rate` is given", .doc = "Particles per second; the pour inserts round(rate (end - start)) in all."},
    {"pours[].mass_rate", NULL, NUM, "kg/s", NULL, NULL, GT(0), .need = ADEM_SCHEMA_REQUIRED_IF, .need_doc = "unless `rate` is given", .doc = "Instead of `rate`: kilograms per second (the total is met to within half a particle)."},
    {"pours[].start", NULL, NUM, "s", "0", NULL, GE(0), .doc = "Start of the window."},
    {"pours[].end", NULL, NUM, "s", NULL, NULL, GT(0), REQ, .doc = "End of the window; after `start`."},
    {"pours[].interval", NULL, NUM, "s", NULL, "(end - start) / 20", GT(0), .doc = "Time between batches; each batch brings the total up to the rate times the time elapsed at the end of its interval."},
    {"pours[].velocity", NULL, VEC3, "m/s", "[0, 0, 0]", NULL, .doc = "Initial velocity of every poured sphere."},
    {"pours[].angular_velocity", NULL, VEC3, "rad/s", "[0, 0, 0]", NULL, .doc = "Initial angular velocity."},
    {"pours[].max_attempts", NULL, INT, "", "1000", NULL, GE(1), .doc = "Trial positions per particle; a particle that finds no room is left for the next batch, and a pour that ends short says how many it inserted."},

    {"stages", NULL, LIST, "", NULL, NULL, .doc = "Consecutive stages of the run, each with a duration and the case-file values it changes (docs/insertion-and-stages.md)."},
    {"stages[].name", NULL, NAME, "", NULL, "`stage<index>`", .doc = "Unique name (for messages)."},
    {"stages[].duration", NULL, NUM, "s", NULL, NULL, GT(0), .need = ADEM_SCHEMA_REQUIRED_IF, .need_doc = "except for the last stage", .doc = "Length of the stage; the last stage without one runs until `time.end`."},
    UNTIL_ENTRIES("stages[].until", "the stage (the next one begins then; `duration` is then the most it lasts; the last stage's ends the run)"),
    {"stages[].set", NULL, SETS, "", NULL, NULL, .doc = "Values that change when the stage begins, as `--set` paths: `{materials.ballast.friction: 0, walls.aux.active: false}`. They stay until a later stage changes them. Allowed: materials, interactions, groups, walls, gravity, limits, neighbor, output.frame_interval, output.csv_interval, output.checkpoint_interval."},

    {"gravity", NULL, VEC3, "m/s^2", "[0, 0, -9.81]", NULL, .doc = "Gravitational acceleration."},
    {"domain", NULL, MAP, "", NULL, "derived, see above", .doc = "Box the particles must stay in; a particle leaving it stops the run (escape check), except through a periodic face."},
    {"domain.min", NULL, VEC3, "m", NULL, NULL, REQ, .doc = "Lower corner."},
    {"domain.max", NULL, VEC3, "m", NULL, NULL, REQ, .doc = "Upper corner; greater than `min` in every component."},
    {"domain.periodic", NULL, BOOL3, "", "[false, false, false]", NULL, .doc = "Periodic axes x, y, z: a particle leaving through a face of the box comes in through the opposite one, and pairs touch through the faces (minimum image; docs/architecture.md). A periodic length must be at least 2 (largest diameter + skin); a plane wall must be parallel to every periodic axis (a `box` wall cannot be used); walls are not imaged across the faces: an infinite cylinder along a periodic axis, and a mesh shell the same along it that reaches past both faces by the largest radius and the skin, need no image; other meshes, cylinders and plates within that reach of a face are refused (docs/walls.md). Random fills and pours do not look through the faces: keep their regions a diameter inside them."},

    {"time", NULL, MAP, "", NULL, NULL, REQ, .doc = "Simulated time and step."},
    {"time.end", NULL, NUM, "s", NULL, NULL, GT(0), REQ, .doc = "End time."},
    {"time.step", NULL, AUTO, "s", "auto", NULL, GT(0), .doc = "Time step; `auto` takes the proposed step min(t_collision/50, 0.2 t_Rayleigh, a fifth of the contacts' stability limit). A larger step is allowed with a warning up to min(t_collision/5, the stability limit of the contacts' modes with their damping: docs/models.md, \"Time step\"); beyond it the case is refused unless `limits.allow_large_step: true`."},
    UNTIL_ENTRIES("time.until", "the run (`end` is then the most it lasts)"),
    {"time.reference_speed", NULL, AUTO, "m/s", "auto", NULL, GT(0), .doc = "Impact speed at which the Hertz collision time is evaluated; `auto`: see above."},

    {"neighbor", NULL, MAP, "", NULL, NULL, .doc = "Neighbour search."},
    {"neighbor.skin", NULL, NUM, "", "0.2", NULL, GT(0), .doc = "Verlet skin as a fraction of the largest particle diameter."},

    {"limits", NULL, MAP, "", NULL, NULL, .doc = "Safety limits that stop a run that has gone wrong."},
    {"limits.max_overlap_ratio", NULL, NUM, "", "0.2", NULL, GT_LE(0, 1), .doc = "Stop the run when a contact's overlap exceeds this fraction of the smaller radius."},
    {"limits.initial_overlap", NULL, NUM, "", "0", NULL, .lo = 0, .hi = 0.5, .range = ADEM_RANGE_MIN | ADEM_RANGE_MAX, .doc = "Overlaps allowed between particles (and with mesh walls) at the start, as a fraction of the smaller radius: for a bed settled by another run or code. 0 refuses any."},
    {"limits.max_memory", NULL, AUTO, "B", "auto", NULL, GT(0), .doc = "Memory the run may use, bytes; `auto`: what the machine has available (MemAvailable in /proc/meminfo). A case whose estimate (every particle, the pours' totals included, their candidate pairs and the neighbour grid; `adem check` prints it) is larger is refused before anything is allocated."},
    {"limits.allow_large_step", NULL, BOOL, "", "false", NULL, .doc = "`true`: run with a time.step above min(t_collision/5, the contacts' stability limit) (refused otherwise: on a two-sphere collision the restitution is off by up to 1.6 % at t_collision/5, 3 % at /4, 6.5 % at /3, 15 % at /2.5 with energy created, a factor 2.3 at /2; above the stability limit, t_collision/7.3 at e = 0.1 and /6.1 at e = 0.2, a contact rings from step to step)."},

    {"output", NULL, MAP, "", NULL, NULL, .doc = "What a run writes; an interval of 0 switches that output off."},
    {"output.dir", NULL, STR, "", NULL, "`out/<name>`", .doc = "Output directory (created if missing)."},
    {"output.frame_interval", NULL, NUM, "s", NULL, "time.end / 100", GE(0), .doc = "Simulated time between VTU frames."},
    {"output.csv_interval", NULL, NUM, "s", NULL, "time.end / 1000", GE(0), .doc = "Simulated time between rows of the CSV time series."},
    {"output.checkpoint_interval", NULL, NUM, "s", NULL, "time.end / 10", GE(0), .doc = "Simulated time between checkpoint rewrites."},
    {"output.plot", NULL, BOOL, "", "false", NULL, .doc = "Write an energy-time PNG (gnuplot) at the end of the run, however it ends (done, stopped by Ctrl-C or SIGTERM, failed, or resumed to its end): each energy, the dissipated energy, the moving walls' work, the total and the balance (total + dissipated - wall work, flat but for the integration error)."},
    {"output.energy_balance", NULL, BOOL, "", "true", NULL, .doc = "Keep the energy balance: every step each contact's dissipation and each moving wall's work are accumulated, so that with the CSV's energies its `dissipated_J` and `wall_work_J` close the balance (docs/models.md). It changes no force or motion; `false` makes a step cheaper and each candidate pair 96 bytes smaller (docs/performance.md) and writes those two columns as `nan`."},
    {"output.plot_loads", NULL, BOOL, "", "false", NULL, .doc = "Write `loads.png` (gnuplot) at the end of the run, however it ends: the load along gravity on every mesh group and plane against time, with the particles' weight, and below it the power each moving wall's drive puts into the particles (its `WALL_drive_power_W` column)."},
    {"output.pieces", NULL, BOOL, "", "false", NULL, .doc = "A run split over MPI processes (`mpirun -np N`, docs/parallel.md) writes each frame as a ParaView `frames/particles_NNNNNN.pvtu` of one piece per process (`particles_NNNNNN_pK.vtu`: the particles process K owns, by id), each written by its process, instead of one `.vtu` of every particle gathered to rank 0; `particles.pvd` lists the `.pvtu` files. One process: no change."},
    {"output.contacts", NULL, BOOL, "", "false", NULL, .doc = "Write the touching contacts with the particle frames: `frames/contacts_NNNNNN.vtp` (VTK PolyData, one line per contact from particle a's centre to b's, or to the contact point of a wall; cell data force, normal_force, normal_force_magnitude, tangential_force, rolling_torque, overlap, kind 0 particle / 1 plane / 2 mesh, id_a, id_b, branch) listed in `contacts.pvd`: ParaView's Tube filter scaled by normal_force_magnitude shows the force chains; `adem analyze fields` reads them (docs/fields.md)."},
    {"output.contacts_every", NULL, INT, "", "1", NULL, GE(1), .doc = "With `output.contacts`: contact frames with every N-th particle frame only (frame index a multiple of N)."},
    {"output.contacts_csv", NULL, BOOL, "", "false", NULL, .doc = "With `output.contacts`: each contact frame also as `frames/contacts_NNNNNN.csv`, one row per contact (columns in docs/fields.md)."},
    {"output.regions", NULL, LIST, "", NULL, NULL, .discriminator = "shape", .doc = "Named regions whose particles are counted in every CSV row: columns `NAME_count` (particles whose centre is inside) and `NAME_mass_kg` (their mass). E.g. the hopper above its outlet and the space under it make a discharge rate and a jam plain to see (docs/insertion-and-stages.md)."},
    {"output.regions[].name", NULL, NAME, "", NULL, NULL, REQ, .doc = "Unique name; the start of the region's CSV columns."},
    {"output.regions[].shape", NULL, ENUM, "", NULL, NULL, REQ, .choices = "box|cylinder|mesh", .doc = "`box`: axis-aligned box; `cylinder`: any axis; `mesh`: the inside of a closed STL surface (ray parity)."},
    {"output.regions[].min", "box", VEC3, "m", NULL, NULL, REQ, .doc = "Lower corner of the box."},
    {"output.regions[].max", "box", VEC3, "m", NULL, NULL, REQ, .doc = "Upper corner; greater than `min` in every component."},
    {"output.regions[].start", "cylinder", VEC3, "m", NULL, NULL, REQ, .doc = "Centre of one end disc."},
    {"output.regions[].end", "cylinder", VEC3, "m", NULL, NULL, REQ, .doc = "Centre of the other end disc."},
    {"output.regions[].radius", "cylinder", NUM, "m", NULL, NULL, GT(0), REQ, .doc = "Radius of the cylinder."},
    {"output.regions[].file", "mesh", STR, "", NULL, NULL, REQ, .doc = "Closed STL surface; a relative path is taken from the folder of the case file."},
    {"output.regions[].scale", "mesh", NUM, "", "1", NULL, GT(0), .doc = "Factor from file units to metres, applied first."},
    {"output.regions[].translate", "mesh", VEC3, "m", "[0, 0, 0]", NULL, .doc = "Translation applied after the scale."},
    {"output.mass_flow", NULL, LIST, "", NULL, NULL, .doc = "Mass flows in the CSV (docs/outlets-and-flow.md): through a plane (`point`, `normal`: columns `NAME_through_kg`, the mass that has crossed along the normal since the start, and `NAME_flow_kg_s`, its rate) or the rate of change of a region's mass (`region`: column `NAME_flow_kg_s`, negative while it empties). A rate is over `window` (the last CSV interval by default)."},
    {"output.mass_flow[].name", NULL, NAME, "", NULL, NULL, REQ, .doc = "Unique name (among regions, outlets and flows); the start of its CSV columns."},
    {"output.mass_flow[].region", NULL, NAME, "", NULL, NULL, .need = ADEM_SCHEMA_REQUIRED_IF, .need_doc = "unless `point` and `normal` are given", .doc = "A region of `output.regions`: the flow is the rate of change of its mass."},
    {"output.mass_flow[].point", NULL, VEC3, "m", NULL, NULL, .need = ADEM_SCHEMA_REQUIRED_IF, .need_doc = "unless `region` is given", .doc = "A point of the plane (an infinite plane: put it where only the flow to measure crosses, e.g. an orifice's plane)."},
    {"output.mass_flow[].normal", NULL, VEC3, "m", NULL, NULL, .need = ADEM_SCHEMA_REQUIRED_IF, .need_doc = "with `point`", .doc = "Normal of the plane (any length > 0): mass crossing along it counts positive, against it negative. A particle's crossing is seen from its side at the previous CSV row or outlet check (the net flow is exact; one that crosses and comes back in between is not counted)."},
    {"output.mass_flow[].window", NULL, NUM, "s", "0", NULL, GE(0), .doc = "The rate is (Q(t) - Q(t - window)) / window from the CSV rows (Q: the mass through, or the region's mass), the oldest row at least `window` before; 0: the last CSV interval."},
    {"outlets", NULL, LIST, "", NULL, NULL, .doc = "Where particles leave the run (docs/outlets-and-flow.md): every `interval` the particles whose centre is inside `region` or beyond the domain's `face` are removed; CSV columns `NAME_deleted_count` and `NAME_deleted_mass_kg` (since the start) and a log line at the end. Split over MPI processes, each check gathers the whole system (as a pour batch does)."},
    {"outlets[].name", NULL, NAME, "", NULL, NULL, REQ, .doc = "Unique name (among regions, outlets and flows); the start of its CSV columns."},
    {"outlets[].region", NULL, NAME, "", NULL, NULL, .need = ADEM_SCHEMA_REQUIRED_IF, .need_doc = "unless `face` is given", .doc = "A region of `output.regions`: particles whose centre is inside it are removed."},
    {"outlets[].face", NULL, ENUM, "", NULL, NULL, .choices = "x_min|x_max|y_min|y_max|z_min|z_max", .need = ADEM_SCHEMA_REQUIRED_IF, .need_doc = "unless `region` is given", .doc = "A face of `domain` (which must be given; not a periodic axis): particles leaving through it are no escape; those beyond it are removed."},
    {"outlets[].interval", NULL, NUM, "s", NULL, "100 time steps", GT(0), .doc = "Simulated time between two checks (rounded to whole steps). A removed particle's last push on its neighbours acts for half a step: put an outlet where particles fly free."},
    {"output.track", NULL, IDS, "", "[]", NULL, .lo = 0, .hi = 32, .range = ADEM_RANGE_MAX, .doc = "Particles (ids: 0, 1, ... in order of creation) that get CSV columns `p<id>_rolling_torque_x_Nm` (and `_y_`, `_z_`: rolling resistance torque), `p<id>_omega_x_rad_s` (and `_y_`, `_z_`) and `p<id>_distance_m`, the path length its centre has travelled."},
};
// clang-format on

/* The table: base_schema with its ADEM_SCHEMA_LAW_PARAMS markers replaced by one entry per
 * contact-law parameter and its law choices ("@rolling") by the names of the laws' rows
 * (adem/laws.h), built once. */
static adem_schema_entry *built;
static size_t nbuilt;

static char *dup_printf(const char *fmt, ...) ADEM_SCHEMA_PRINTF(1, 2);
static char *dup_printf(const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  int n = vsnprintf(NULL, 0, fmt, ap);
  va_end(ap);
  char *s = malloc((size_t)(n > 0 ? n : 0) + 1);
  if (!s) abort(); /* a few hundred bytes at start-up */
  va_start(ap, fmt);
  vsnprintf(s, (size_t)n + 1, fmt, ap);
  va_end(ap);
  return s;
}

static void build_table(void) {
  size_t nbase = sizeof base_schema / sizeof base_schema[0];
  adem_schema_entry *t = calloc(nbase + 2 * ADEM_PARAM_COUNT + 1, sizeof *t);
  if (!t) abort();
  size_t n = 0;
  for (size_t i = 0; i < nbase; ++i) {
    const adem_schema_entry *e = &base_schema[i];
    if (e->type != ADEM_SCHEMA_LAW_PARAMS) {
      t[n] = *e;
      if (e->choices && e->choices[0] == '@') {
        static const char *const slots[] = {"@normal", "@damping", "@tangential", "@rolling"};
        for (int s = 0; s < 4; ++s)
          if (!strcmp(e->choices, slots[s])) t[n].choices = adem_law_choices((adem_law_slot)s);
      }
      ++n;
      continue;
    }
    bool material = !strcmp(e->path, "materials[]");
    for (int k = 0; k < ADEM_PARAM_COUNT; ++k) {
      const adem_law_param *p = adem_law_param_get((adem_law_param_id)k);
      adem_schema_entry *x = &t[n++];
      x->path = dup_printf("%s.%s", e->path, p->key);
      x->type = ADEM_SCHEMA_NUMBER;
      x->unit = p->unit;
      x->lo = p->lo;
      x->range = ADEM_RANGE_MIN;
      if (material) {
        x->def = dup_printf("%g", p->def);
        x->doc = p->doc;
      } else {
        x->def_doc = "the two materials' values";
        x->doc = dup_printf("This pair's value, replacing the materials': %s", p->doc);
      }
    }
  }
  nbuilt = n;
  built = t;
}

#define schema (built ? built : (build_table(), built))

size_t adem_schema_count(void) {
  if (!built) build_table();
  return nbuilt;
}
const adem_schema_entry *adem_schema_at(size_t i) { return i < adem_schema_count() ? &schema[i] : NULL; }

const char *adem_schema_key(const adem_schema_entry *e) {
  const char *dot = strrchr(e->path, '.');
  return dot ? dot + 1 : e->path;
}

/* True if "a|b|c" contains v as a whole word. */
static bool variant_has(const char *variants, const char *v) {
  if (!variants) return true;
  if (!v || !*v) return false;
  size_t n = strlen(v);
  for (const char *s = variants; *s;) {
    const char *bar = strchr(s, '|');
    size_t len = bar ? (size_t)(bar - s) : strlen(s);
    if (len == n && strncmp(s, v, n) == 0) return true;
    if (!bar) break;
    s = bar + 1;
  }
  return false;
}

/* True if path is prefix + "." + key (or just key at the top). */
static bool path_is(const char *path, const char *prefix, const char *key, size_t keylen) {
  size_t np = strlen(prefix);
  if (np) {
    if (strncmp(path, prefix, np) != 0 || path[np] != '.') return false;
    path += np + 1;
  }
  return strncmp(path, key, keylen) == 0 && path[keylen] == '\0';
}

const adem_schema_entry *adem_schema_find(const char *prefix, const char *key, const char *variant) {
  size_t n = strlen(key);
  for (size_t i = 0; i < adem_schema_count(); ++i)
    if (path_is(schema[i].path, prefix, key, n) && variant_has(schema[i].variant, variant))
      return &schema[i];
  return NULL;
}

const adem_schema_entry *adem_schema_find_any(const char *prefix, const char *key) {
  size_t n = strlen(key);
  for (size_t i = 0; i < adem_schema_count(); ++i)
    if (path_is(schema[i].path, prefix, key, n)) return &schema[i];
  return NULL;
}

bool adem_schema_is_child(const adem_schema_entry *e, const char *prefix, const char *variant) {
  const char *key = adem_schema_key(e);
  size_t np = strlen(prefix);
  if (np == 0) {
    if (key != e->path) return false;
  } else if ((size_t)(key - e->path) != np + 1 || strncmp(e->path, prefix, np) != 0) {
    return false;
  }
  return variant_has(e->variant, variant);
}

bool adem_schema_in_range(const adem_schema_entry *e, double x) {
  if ((e->range & ADEM_RANGE_MIN) && !(x >= e->lo)) return false;
  if ((e->range & ADEM_RANGE_MIN_OPEN) && !(x > e->lo)) return false;
  if ((e->range & ADEM_RANGE_MAX) && !(x <= e->hi)) return false;
  if ((e->range & ADEM_RANGE_MAX_OPEN) && !(x < e->hi)) return false;
  return true;
}

void adem_schema_describe_range(const adem_schema_entry *e, char *buf, size_t n) {
  unsigned lo = e->range & (ADEM_RANGE_MIN | ADEM_RANGE_MIN_OPEN);
  unsigned hi = e->range & (ADEM_RANGE_MAX | ADEM_RANGE_MAX_OPEN);
  if (lo && hi)
    snprintf(buf, n, "in %c%g, %g%c", (lo & ADEM_RANGE_MIN_OPEN) ? '(' : '[', e->lo, e->hi,
             (hi & ADEM_RANGE_MAX_OPEN) ? ')' : ']');
  else if (lo)
    snprintf(buf, n, "%s %g", (lo & ADEM_RANGE_MIN_OPEN) ? ">" : ">=", e->lo);
  else if (hi)
    snprintf(buf, n, "%s %g", (hi & ADEM_RANGE_MAX_OPEN) ? "<" : "<=", e->hi);
  else if (n)
    buf[0] = '\0';
}

void adem_schema_list_choices(const char *choices, char *buf, size_t n) {
  size_t k = 0;
  for (const char *s = choices; *s && k + 3 < n; ++s) {
    if (*s == '|') {
      buf[k++] = ',';
      buf[k++] = ' ';
    } else {
      buf[k++] = *s;
    }
  }
  if (n) buf[k < n ? k : n - 1] = '\0';
}

int adem_schema_choice(const adem_schema_entry *e, const char *s) {
  if (!e->choices) return -1;
  size_t n = strlen(s);
  int index = 0;
  for (const char *c = e->choices;; ++index) {
    const char *bar = strchr(c, '|');
    size_t len = bar ? (size_t)(bar - c) : strlen(c);
    if (len == n && strncmp(c, s, n) == 0) return index;
    if (!bar) return -1;
    c = bar + 1;
  }
}

void adem_schema_describe(const adem_schema_entry *e, char *buf, size_t n) {
  char range[64], choices[256], unit[48] = "";
  adem_schema_describe_range(e, range, sizeof range);
  if (e->unit && *e->unit) snprintf(unit, sizeof unit, " (%s)", e->unit);
  const char *sp = *range ? " " : "";
  switch (e->type) {
    case ADEM_SCHEMA_NUMBER: snprintf(buf, n, "a number%s%s%s", sp, range, unit); break;
    case ADEM_SCHEMA_INT: snprintf(buf, n, "an integer%s%s", sp, range); break;
    case ADEM_SCHEMA_BOOL: snprintf(buf, n, "true or false"); break;
    case ADEM_SCHEMA_STRING: snprintf(buf, n, "a string"); break;
    case ADEM_SCHEMA_NAME:
      snprintf(buf, n, "a name (a letter or _, then letters, digits, _ or -; at most 63 characters)");
      break;
    case ADEM_SCHEMA_VEC3: snprintf(buf, n, "a list [x, y, z] of 3 numbers%s", unit); break;
    case ADEM_SCHEMA_ENUM:
      adem_schema_list_choices(e->choices, choices, sizeof choices);
      snprintf(buf, n, "one of: %s", choices);
      break;
    case ADEM_SCHEMA_AUTO: snprintf(buf, n, "`auto` or a number%s%s%s", sp, range, unit); break;
    case ADEM_SCHEMA_NAME_PAIR: snprintf(buf, n, "a list [name, name] of 2 names"); break;
    case ADEM_SCHEMA_MAP: snprintf(buf, n, "a mapping (key: value)"); break;
    case ADEM_SCHEMA_LIST:
      if (e->range & ADEM_RANGE_MIN)
        snprintf(buf, n, "a list of mappings (at least %g)", e->lo);
      else
        snprintf(buf, n, "a list of mappings");
      break;
    case ADEM_SCHEMA_ID_LIST: snprintf(buf, n, "a list [id, ...] of particle ids (at most %g)", e->hi); break;
    case ADEM_SCHEMA_TABLE: snprintf(buf, n, "a list of rows [t, x, y, z] of 4 numbers%s", unit); break;
    case ADEM_SCHEMA_NUMBER_LIST:
      snprintf(buf, n, "a list [a, b, ...] of numbers%s%s%s", sp, range, unit);
      break;
    case ADEM_SCHEMA_SETTINGS: snprintf(buf, n, "a mapping of key paths to values (key.path: value)"); break;
    case ADEM_SCHEMA_LAW_PARAMS: snprintf(buf, n, "contact-law parameters"); break;
    case ADEM_SCHEMA_BOOL3: snprintf(buf, n, "a list [x, y, z] of 3 booleans (true or false)"); break;
  }
}

/* ---- Markdown reference ---- */

static void md_type(FILE *f, const adem_schema_entry *e) {
  switch (e->type) {
    case ADEM_SCHEMA_NUMBER: fputs("number", f); break;
    case ADEM_SCHEMA_INT: fputs("integer", f); break;
    case ADEM_SCHEMA_BOOL: fputs("bool", f); break;
    case ADEM_SCHEMA_STRING: fputs("string", f); break;
    case ADEM_SCHEMA_NAME: fputs("name", f); break;
    case ADEM_SCHEMA_VEC3: fputs("[x, y, z]", f); break;
    case ADEM_SCHEMA_ENUM:
      fputc('`', f);
      for (const char *s = e->choices; *s; ++s) {
        if (*s == '|')
          fputs("` \\| `", f);
        else
          fputc(*s, f);
      }
      fputc('`', f);
      break;
    case ADEM_SCHEMA_AUTO: fputs("`auto` or number", f); break;
    case ADEM_SCHEMA_NAME_PAIR: fputs("[name, name]", f); break;
    case ADEM_SCHEMA_MAP: fputs("mapping", f); break;
    case ADEM_SCHEMA_LIST: fputs("list", f); break;
    case ADEM_SCHEMA_ID_LIST: fputs("[id, ...]", f); break;
    case ADEM_SCHEMA_TABLE: fputs("[[t, x, y, z], ...]", f); break;
    case ADEM_SCHEMA_NUMBER_LIST: fputs("[number, ...]", f); break;
    case ADEM_SCHEMA_SETTINGS: fputs("{key.path: value, ...}", f); break;
    case ADEM_SCHEMA_BOOL3: fputs("[bool, bool, bool]", f); break;
    default: break;
  }
}

/* The entry of the mapping or list that holds e (for its discriminator's name). */
static const adem_schema_entry *parent_of(const adem_schema_entry *e) {
  const char *key = adem_schema_key(e);
  if (key == e->path) return NULL;
  size_t n = (size_t)(key - e->path) - 1;
  if (n >= 2 && strncmp(e->path + n - 2, "[]", 2) == 0) n -= 2;
  for (size_t i = 0; i < adem_schema_count(); ++i)
    if (schema[i].discriminator && strlen(schema[i].path) == n &&
        strncmp(schema[i].path, e->path, n) == 0)
      return &schema[i];
  return NULL;
}

static void md_row(FILE *f, const adem_schema_entry *e) {
  fprintf(f, "| `%s` | ", e->path);
  md_type(f, e);
  fprintf(f, " | %s | ", e->unit && *e->unit ? e->unit : "");
  if (e->need == ADEM_SCHEMA_REQUIRED)
    fputs("**required**", f);
  else if (e->need == ADEM_SCHEMA_REQUIRED_IF)
    fprintf(f, "required %s", e->need_doc);
  else if (e->def)
    fprintf(f, "`%s`", e->def);
  else if (e->def_doc)
    fputs(e->def_doc, f);
  else if (e->type == ADEM_SCHEMA_MAP || e->type == ADEM_SCHEMA_LIST)
    fputs("optional", f);
  else
    fputs("none", f);
  char range[64];
  if (e->type == ADEM_SCHEMA_LIST && (e->range & ADEM_RANGE_MIN))
    snprintf(range, sizeof range, "at least %g item%s", e->lo, e->lo == 1 ? "" : "s");
  else if (e->type == ADEM_SCHEMA_ID_LIST)
    snprintf(range, sizeof range, "at most %g existing ids", e->hi);
  else
    adem_schema_describe_range(e, range, sizeof range);
  fprintf(f, " | %s | ", range);
  if (e->variant) {
    const adem_schema_entry *p = parent_of(e);
    fputs("*(", f);
    fputs(p ? p->discriminator : "variant", f);
    fputs(": ", f);
    for (const char *s = e->variant; *s; ++s) {
      if (*s == '|')
        fputs(", ", f);
      else
        fputc(*s, f);
    }
    fputs(")* ", f);
  }
  fprintf(f, "%s |\n", e->doc);
}

static void md_header(FILE *f) {
  fputs("| Key | Type | Unit | Default | Allowed | Description |\n", f);
  fputs("|-----|------|------|---------|---------|-------------|\n", f);
}

void adem_schema_write_markdown(FILE *f) {
  fputs("# Case-file reference\n\n"
        "<!-- Generated by adem_case_write_reference() from the schema table in src/input/schema.c; "
        "do not edit by hand. -->\n\n"
        "A case is a YAML file. Every key is checked: an unknown key, a value of the wrong type, a "
        "missing required value or a value out of range stops the loading with a message that names "
        "`file:line:column`, the key path (e.g. `materials[0].poisson_ratio`) and what is allowed.\n\n"
        "Conventions:\n\n"
        "- `materials[].density` is the key `density` of an item of the list `materials`; error "
        "messages give the item's index (`materials[0].density`).\n"
        "- Units are SI. A range `(a, b]` excludes a and includes b.\n"
        "- A *name* starts with a letter or `_` followed by letters, digits, `_` or `-` (at most "
        "63 characters); names of materials, groups and walls are unique within their list.\n"
        "- Numbers are plain YAML scalars (`2500`, `1.0e7`, `1e-6`); a quoted `\"2500\"` is a "
        "string and is refused. Integers may be written `1000000` or `1e6`.\n"
        "- Keys marked with *(type: ...)* apply only to items of that type.\n\n"
        "## Command-line overrides\n\n"
        "`adem run case.yaml --set key.path=value` changes the case before it is validated, so "
        "an override is checked like the file. The path is a dot-separated list of mapping keys; an "
        "item of a list is chosen by its index or by its `name` (`time.end=2`, "
        "`materials.glass.friction=0.3`, `materials.0.friction=0.3`, `output.dir=/tmp/x`, "
        "`gravity=[0,0,-1]`). Setting a key that a mapping lacks adds it; a path that does not "
        "resolve is an error naming the failing segment. The value is read as YAML.\n\n"
        "`adem run --resume DIR --set time.end=T` takes a run (finished or stopped) on to a later "
        "end, bit for bit as a run that had that end from the start: the state, and the frames and "
        "CSV rows on the same steps (a frame or row written only because the shorter run ended "
        "there is replaced). On resume `--set` may change only `time.end` and "
        "`output.frame_interval`, `output.csv_interval`, `output.checkpoint_interval` (from the "
        "resume on); output intervals left to their defaults keep the values of the first run's "
        "end time.\n\n"
        "## Values computed by the loader\n\n"
        "- **Reference speed** (`time.reference_speed: auto`): v_ref = max(v0, sqrt(2 |g| H), "
        "0.1 m/s), where v0 is the largest initial speed of a particle or a plane wall and H is the "
        "extent, along gravity, of the bounding box of the particles and the walls (box corners, "
        "plane points and mesh vertices); v0 includes the speeds of moving walls.\n"
        "- **Time step** (`time.step: auto`): dt = min(t_collision/50, 0.2 t_Rayleigh): the "
        "shortest Hertz collision time at v_ref and the shortest Rayleigh time over the material "
        "pairs in use (particle-particle and particle-wall), each for the smallest sphere of its "
        "material. A simplified JKR pair takes its collision time at sqrt(v_ref^2 + 2|U_min|/m*), "
        "the speed its adhesion brings the spheres to (U_min the JKR energy at equilibrium), or "
        "half its period of small oscillations about the equilibrium, 2 pi sqrt(m*/(1.2 E a0)), "
        "if that is shorter. A given `time.step` larger than that is used, with a warning saying by how much "
        "it exceeds the proposal.\n"
        "- **Domain** (no `domain`): the bounding box B of the particles (whole spheres) and the "
        "walls (box corners, plane points and mesh vertices), widened on every side by the largest of: the longest "
        "side of B, 10 largest diameters, and v0 t_end + |g| t_end^2 / 2.\n"
        "- **Lattice**: centres at min + radius + i spacing along each axis for as long as the "
        "whole sphere stays inside the box; filled x first, then y, then z.\n"
        "- **Random fill**: radii are drawn first (`count` of them, or, for `solid_fraction`, while "
        "their volume plus half the next one stays within the fraction of the region's volume) and "
        "placed largest first; each sphere is tried at uniform random positions (whole sphere inside "
        "the region: the box, the cylinder, or inside a closed STL surface by ray parity and at least "
        "its radius from every triangle) until it overlaps no sphere already placed by this or an "
        "earlier set and clears every active wall built so far. Each random set draws from its own "
        "stream of `seed`: "
        "the same seed gives the same spheres, bit for bit on every platform (`normal` and "
        "`lognormal` radii use adem's own log, cos and exp, not the C library's). Normal and lognormal radii outside (0, r_fit] are redrawn, r_fit the largest "
        "sphere the region holds (half a box's smallest side; a cylinder's radius or half its "
        "length; half the smallest side of a mesh's bounding box); a lognormal radius with mean m "
        "and standard deviation s has sigma^2 = ln(1 + s^2/m^2), mu = ln m - sigma^2/2.\n"
        "- **Pours**: batches at fixed steps, every round(interval/dt) steps from round(start/dt); "
        "batch j brings the number poured to round(N min(1, (j+1) interval / (end - start))), N = "
        "round(rate (end - start)), placed as a random fill among the particles and walls already "
        "there; with `mass_rate`, radii are drawn while the mass stays within half a particle of the "
        "target. `time.step: auto` counts poured particles at the 0.1 % quantile of their radius "
        "(the smallest value of constant, uniform and discrete; max(mean - 3.09 std, mean / 10) for "
        "normal; exp(mu - 3.09 sigma) for lognormal), and the domain includes the pour regions.\n"
        "- **Stages**: stage k begins at step round((sum of the earlier durations) / dt); its `set` "
        "entries are applied, after those of the stages before it, to the case as written (with "
        "`--set`), and the result is loaded and validated like a case. `time.step: auto` takes the "
        "smallest step any stage proposes.\n"
        "- **Output intervals** default to fractions of `time.end`.\n"
        "- **Mesh walls** (`type: mesh`): `file` is read relative to the case file's folder (a "
        "checkpoint keeps that folder as an absolute path, so `adem run --resume` works from "
        "anywhere). The transform is x' = R (scale x) + translate, R the `rotate` entries in order. "
        "Each group (the file, or each `solid` of an ASCII file with several) gets CSV columns "
        "`GROUP_fx_N` ... and `GROUP_tx_Nm` ... (a dot of a group's or a box plane's name is "
        "written `__`: `hopper.funnel` gives `hopper__funnel_fz_N`, a name numpy's "
        "`genfromtxt(names=True)` keeps; it drops a `-`, so prefer `_` in names): the force of the particles on it and its torque "
        "about `torque_about` (default: the group's area centroid), the point carried with the "
        "wall's motion; a file with several groups also gets the columns of its total, its torque "
        "about the file's centroid. A particle cutting into a mesh face at the start is an "
        "error.\n\n"
        "Spheres of an explicit `list` must not overlap each other (the loader names both). "
        "Overlaps between spheres of different sets, and spheres behind a wall, are reported when "
        "the run starts.\n\n",
        f);

  fputs("## Contact laws\n\n"
        "Each material pair composes its contact from one law per slot, chosen in `interactions` "
        "(pairs not listed: the first law of each slot). The table is the engine's own registry "
        "(include/adem/laws.h). Parameters come from the materials (mixed per pair) or from the "
        "interaction entry.\n\n"
        "| slot | law | equations | parameters | needs | acts | what it is |\n"
        "|---|---|---|---|---|---|---|\n",
        f);
  for (int sl = 0; sl < ADEM_SLOT_COUNT; ++sl)
    for (size_t k = 0; k < adem_law_count((adem_law_slot)sl); ++k) {
      const adem_law *lw = adem_law_get((adem_law_slot)sl, (int)k);
      fprintf(f, "| %s | `%s` | %s | %s | %s | %s | %s |\n", adem_law_slot_name((adem_law_slot)sl),
              lw->name, lw->equations[0] ? lw->equations : "-", lw->params[0] ? lw->params : "-",
              lw->requires[0] ? lw->requires : "-", lw->per_particle ? "per particle" : "per contact",
              lw->doc);
    }
  fputs("\n", f);
  /* The rule lives in the parameter's row; `adem check` prints what each pair uses by it. */
  fprintf(f, "**Which values a pair uses.** Restitution and friction: the mean of the two "
             "materials', or the interaction entry's. `rolling_friction`: %s `adem check` prints "
             "the e_c or eta_r of every pair and where it comes from.\n\n",
          adem_law_param_get(ADEM_PARAM_ROLLING_FRICTION)->doc);

  fputs("## Top-level keys\n\n", f);
  md_header(f);
  for (size_t i = 0; i < adem_schema_count(); ++i)
    if (adem_schema_is_child(&schema[i], "", NULL)) md_row(f, &schema[i]);
  fputc('\n', f);

  for (size_t i = 0; i < adem_schema_count(); ++i) {
    const adem_schema_entry *top = &schema[i];
    if (!adem_schema_is_child(top, "", NULL)) continue;
    if (top->type != ADEM_SCHEMA_MAP && top->type != ADEM_SCHEMA_LIST) continue;
    fprintf(f, "## `%s`\n\n%s\n\n", top->path, top->doc);
    md_header(f);
    size_t n = strlen(top->path);
    for (size_t k = 0; k < adem_schema_count(); ++k) {
      const char *p = schema[k].path;
      if (strncmp(p, top->path, n) == 0 && (p[n] == '.' || p[n] == '[')) md_row(f, &schema[k]);
    }
    fputc('\n', f);
  }
}
