/* The case-file schema table and what is derived from it: look-ups, range checks, the words of
 * error messages and the Markdown reference. */
#include "schema.h"

#include <math.h>
#include <string.h>

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
#define REQ .need = ADEM_SCHEMA_REQUIRED
#define GT(x) .lo = (x), .range = ADEM_RANGE_MIN_OPEN
#define GE(x) .lo = (x), .range = ADEM_RANGE_MIN
#define GT_LE(a, b) .lo = (a), .hi = (b), .range = ADEM_RANGE_MIN_OPEN | ADEM_RANGE_MAX
#define GT_LT(a, b) .lo = (a), .hi = (b), .range = ADEM_RANGE_MIN_OPEN | ADEM_RANGE_MAX_OPEN

/* Every key of a case file. Order: as the reference lists them. */
static const adem_schema_entry schema[] = {
    {"name", NULL, STR, "", NULL, "file name without directory and extension", .doc = "Case name; the default output directory is `out/<name>`."},
    {"seed", NULL, INT, "", "1", NULL, GE(0), .doc = "Seed of the random fills; the same seed gives the same positions on every platform."},

    {"materials", NULL, LIST, "", NULL, NULL, GE(1), REQ, .doc = "Materials of particles and walls."},
    {"materials[].name", NULL, NAME, "", NULL, NULL, REQ, .doc = "Unique name that particle sets, walls and interactions refer to."},
    {"materials[].density", NULL, NUM, "kg/m^3", NULL, NULL, GT(0), .need = ADEM_SCHEMA_REQUIRED_IF, .need_doc = "for materials that particles use", .doc = "Density rho."},
    {"materials[].youngs_modulus", NULL, NUM, "Pa", NULL, NULL, GT(0), .need = ADEM_SCHEMA_REQUIRED_IF, .need_doc = "unless `rigid: true`", .doc = "Young's modulus E of the real material (see `stiffness_factor`)."},
    {"materials[].poisson_ratio", NULL, NUM, "", NULL, NULL, GT_LT(-1, 0.5), .need = ADEM_SCHEMA_REQUIRED_IF, .need_doc = "unless `rigid: true`", .doc = "Poisson's ratio nu."},
    {"materials[].restitution", NULL, NUM, "", "0.5", NULL, GT_LE(0, 1), .doc = "Coefficient of restitution e of a collision between two spheres of this material."},
    {"materials[].friction", NULL, NUM, "", "0.5", NULL, GE(0), .doc = "Sliding friction coefficient mu_s."},
    {"materials[].surface_energy", NULL, NUM, "J/m^2", "0", NULL, GE(0), .doc = "Surface energy gamma per surface (work of adhesion 2 gamma); used by the `jkr` normal model."},
    {"materials[].adhesion_hysteresis", NULL, NUM, "", "0", NULL, GE(0), .doc = "Adhesion hysteresis delta_gamma/gamma (DTK rolling)."},
    {"materials[].stiffness_factor", NULL, NUM, "", "1", NULL, GT_LE(0, 1), .doc = "Stiffness reduction f = E_mod/E; surface energy is scaled by f^(2/5) to keep the pull-off force."},
    {"materials[].rolling_friction", NULL, NUM, "", "0", NULL, GE(0), .doc = "Rolling friction coefficient eta_r (rolling models `model_a`, `model_c`, `brof`)."},
    {"materials[].rolling_damping", NULL, NUM, "", "0", NULL, GE(0), .doc = "Rolling damping ratio delta_r (rolling model `model_c`)."},
    {"materials[].rigid", NULL, BOOL, "", "false", NULL, .doc = "`true`: infinite Young's modulus; for wall materials only."},

    {"interactions", NULL, LIST, "", NULL, NULL, .doc = "Per-pair overrides of how two materials interact; pairs not listed use the defaults."},
    {"interactions[].materials", NULL, PAIR, "", NULL, NULL, REQ, .doc = "The two materials (may be the same one twice). Each pair may appear once."},
    {"interactions[].restitution", NULL, NUM, "", NULL, "derived from the two materials", GT_LE(0, 1), .doc = "Coefficient of restitution of this pair."},
    {"interactions[].friction", NULL, NUM, "", NULL, "derived from the two materials", GE(0), .doc = "Sliding friction coefficient of this pair."},
    {"interactions[].normal", NULL, ENUM, "", "hertz", NULL, .choices = "hertz|jkr", .doc = "Normal force law: Hertz with damping, or simplified JKR adhesion."},
    {"interactions[].rolling", NULL, ENUM, "", "none", NULL, .choices = "none|dtk|model_a|model_c|brof", .doc = "Rolling resistance law."},

    {"groups", NULL, LIST, "", NULL, NULL, .doc = "Named groups of particles with a constant external force; group `default` always exists (no force unless listed)."},
    {"groups[].name", NULL, NAME, "", NULL, NULL, REQ, .doc = "Unique name; `default` sets the force of the particles without a `group`."},
    {"groups[].external_force", NULL, VEC3, "N", "[0, 0, 0]", NULL, .doc = "Constant force on every particle of the group."},

    {"particles", NULL, LIST, "", NULL, NULL, GE(1), REQ, .discriminator = "type", .doc = "Particle sets, created in order; each has a `type`."},
    {"particles[].type", NULL, ENUM, "", NULL, NULL, REQ, .choices = "list|lattice|random", .doc = "`list`: explicit spheres; `lattice`: simple cubic lattice in a box; `random`: random non-overlapping fill of a box."},
    {"particles[].material", NULL, NAME, "", NULL, NULL, REQ, .doc = "Material of the set's spheres; it needs a `density` and must not be rigid."},
    {"particles[].group", NULL, NAME, "", "default", NULL, .doc = "Group of the set's spheres."},
    {"particles[].spheres", "list", LIST, "", NULL, NULL, GE(1), REQ, .doc = "The spheres; two spheres of the list must not overlap."},
    {"particles[].spheres[].position", NULL, VEC3, "m", NULL, NULL, REQ, .doc = "Centre."},
    {"particles[].spheres[].radius", NULL, NUM, "m", NULL, NULL, GT(0), REQ, .doc = "Radius."},
    {"particles[].spheres[].velocity", NULL, VEC3, "m/s", "[0, 0, 0]", NULL, .doc = "Initial velocity."},
    {"particles[].spheres[].angular_velocity", NULL, VEC3, "rad/s", "[0, 0, 0]", NULL, .doc = "Initial angular velocity."},
    {"particles[].radius", "lattice", NUM, "m", NULL, NULL, GT(0), REQ, .doc = "Radius of every sphere."},
    {"particles[].spacing", "lattice", NUM, "m", NULL, NULL, GT(0), REQ, .doc = "Distance between neighbouring centres; at least 2 radius."},
    {"particles[].radius", "random", MAP, "", NULL, NULL, REQ, .discriminator = "distribution", .doc = "Radius distribution, e.g. `{distribution: uniform, min: 1e-3, max: 2e-3}`."},
    {"particles[].radius.distribution", NULL, ENUM, "", NULL, NULL, REQ, .choices = "constant|uniform|normal|lognormal", .doc = "Shape of the distribution; normal and lognormal are truncated to radii that fit the box (redrawn)."},
    {"particles[].radius.value", "constant", NUM, "m", NULL, NULL, GT(0), REQ, .doc = "The radius."},
    {"particles[].radius.min", "uniform", NUM, "m", NULL, NULL, GT(0), REQ, .doc = "Smallest radius."},
    {"particles[].radius.max", "uniform", NUM, "m", NULL, NULL, GT(0), REQ, .doc = "Largest radius; greater than `min`."},
    {"particles[].radius.mean", "normal|lognormal", NUM, "m", NULL, NULL, GT(0), REQ, .doc = "Mean of the radius."},
    {"particles[].radius.std", "normal|lognormal", NUM, "m", NULL, NULL, GE(0), REQ, .doc = "Standard deviation of the radius (for lognormal: of the radius itself, not of its logarithm)."},
    {"particles[].min", "lattice|random", VEC3, "m", NULL, NULL, REQ, .doc = "Lower corner of the box; whole spheres lie inside it."},
    {"particles[].max", "lattice|random", VEC3, "m", NULL, NULL, REQ, .doc = "Upper corner of the box; greater than `min` in every component."},
    {"particles[].count", "lattice", INT, "", "0", NULL, GE(0), .doc = "Most spheres to create, filling x first, then y, then z; 0 fills the box."},
    {"particles[].count", "random", INT, "", NULL, NULL, GE(1), REQ, .doc = "Number of spheres to place."},
    {"particles[].max_attempts", "random", INT, "", NULL, "max(1000000, 100 count)", GE(1), .doc = "Total number of trial positions; when used up, the fill stops with a warning giving the number placed."},
    {"particles[].velocity", "lattice|random", VEC3, "m/s", "[0, 0, 0]", NULL, .doc = "Initial velocity of every sphere."},
    {"particles[].angular_velocity", "lattice|random", VEC3, "rad/s", "[0, 0, 0]", NULL, .doc = "Initial angular velocity of every sphere."},

    {"walls", NULL, LIST, "", NULL, NULL, .discriminator = "type", .doc = "Walls; each has a `type`."},
    {"walls[].type", NULL, ENUM, "", NULL, NULL, REQ, .choices = "plane|box", .doc = "`plane`: an infinite plane; `box`: six planes facing inwards, named NAME.xmin, NAME.xmax, ..."},
    {"walls[].name", NULL, NAME, "", NULL, "`wall<index>`", .doc = "Unique name (used in output)."},
    {"walls[].material", NULL, NAME, "", NULL, NULL, REQ, .doc = "Material of the wall."},
    {"walls[].point", "plane", VEC3, "m", NULL, NULL, REQ, .doc = "A point of the plane."},
    {"walls[].normal", "plane", VEC3, "", NULL, NULL, REQ, .doc = "Normal pointing to the particles' side; non-zero, normalised by the loader."},
    {"walls[].velocity", "plane", VEC3, "m/s", "[0, 0, 0]", NULL, .doc = "Translation velocity of the plane."},
    {"walls[].min", "box", VEC3, "m", NULL, NULL, REQ, .doc = "Lower corner of the box."},
    {"walls[].max", "box", VEC3, "m", NULL, NULL, REQ, .doc = "Upper corner of the box; greater than `min` in every component."},

    {"gravity", NULL, VEC3, "m/s^2", "[0, 0, -9.81]", NULL, .doc = "Gravitational acceleration."},
    {"domain", NULL, MAP, "", NULL, "derived, see above", .doc = "Box the particles must stay in; a particle leaving it stops the run (escape check)."},
    {"domain.min", NULL, VEC3, "m", NULL, NULL, REQ, .doc = "Lower corner."},
    {"domain.max", NULL, VEC3, "m", NULL, NULL, REQ, .doc = "Upper corner; greater than `min` in every component."},

    {"time", NULL, MAP, "", NULL, NULL, REQ, .doc = "Simulated time and step."},
    {"time.end", NULL, NUM, "s", NULL, NULL, GT(0), REQ, .doc = "End time."},
    {"time.step", NULL, AUTO, "s", "auto", NULL, GT(0), .doc = "Time step; `auto` takes the proposed step min(t_collision/50, 0.2 t_Rayleigh). A larger step is allowed with a warning."},
    {"time.reference_speed", NULL, AUTO, "m/s", "auto", NULL, GT(0), .doc = "Impact speed at which the Hertz collision time is evaluated; `auto`: see above."},

    {"neighbor", NULL, MAP, "", NULL, NULL, .doc = "Neighbour search."},
    {"neighbor.skin", NULL, NUM, "", "0.2", NULL, GT(0), .doc = "Verlet skin as a fraction of the largest particle diameter."},

    {"limits", NULL, MAP, "", NULL, NULL, .doc = "Safety limits that stop a run that has gone wrong."},
    {"limits.max_overlap_ratio", NULL, NUM, "", "0.2", NULL, GT_LE(0, 1), .doc = "Stop the run when a contact's overlap exceeds this fraction of the smaller radius."},

    {"output", NULL, MAP, "", NULL, NULL, .doc = "What a run writes; an interval of 0 switches that output off."},
    {"output.dir", NULL, STR, "", NULL, "`out/<name>`", .doc = "Output directory (created if missing)."},
    {"output.frame_interval", NULL, NUM, "s", NULL, "time.end / 100", GE(0), .doc = "Simulated time between VTU frames."},
    {"output.csv_interval", NULL, NUM, "s", NULL, "time.end / 1000", GE(0), .doc = "Simulated time between rows of the CSV time series."},
    {"output.checkpoint_interval", NULL, NUM, "s", NULL, "time.end / 10", GE(0), .doc = "Simulated time between checkpoint rewrites."},
    {"output.plot", NULL, BOOL, "", "false", NULL, .doc = "Write an energy-time PNG (gnuplot) at the end of the run."},
    {"output.track", NULL, IDS, "", "[]", NULL, .lo = 0, .hi = 32, .range = ADEM_RANGE_MAX, .doc = "Particles (ids: 0, 1, ... in order of creation) that get CSV columns `p<id>_rolling_torque_x_Nm` (and `_y_`, `_z_`: rolling resistance torque), `p<id>_omega_x_rad_s` (and `_y_`, `_z_`) and `p<id>_distance_m`, the path length its centre has travelled."},
};

size_t adem_schema_count(void) { return sizeof schema / sizeof schema[0]; }
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
        "<!-- Generated by adem_case_write_reference() from the schema table in src/schema.c; "
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
        "## Values computed by the loader\n\n"
        "- **Reference speed** (`time.reference_speed: auto`): v_ref = max(v0, sqrt(2 |g| H), "
        "0.1 m/s), where v0 is the largest initial speed of a particle or a plane wall and H is the "
        "extent, along gravity, of the bounding box of the particles and the walls (box corners and "
        "plane points).\n"
        "- **Time step** (`time.step: auto`): dt = min(t_collision/50, 0.2 t_Rayleigh): the "
        "shortest Hertz collision time at v_ref and the shortest Rayleigh time over the material "
        "pairs in use (particle-particle and particle-wall), each for the smallest sphere of its "
        "material. A given `time.step` larger than that is used, with a warning saying by how much "
        "it exceeds the proposal.\n"
        "- **Domain** (no `domain`): the bounding box B of the particles (whole spheres) and the "
        "walls (box corners and plane points), widened on every side by the largest of: the longest "
        "side of B, 10 largest diameters, and v0 t_end + |g| t_end^2 / 2.\n"
        "- **Lattice**: centres at min + radius + i spacing along each axis for as long as the "
        "whole sphere stays inside the box; filled x first, then y, then z.\n"
        "- **Random fill**: radii are drawn first and placed largest first; each sphere is tried at "
        "uniform random positions (whole sphere inside the box) until it overlaps no sphere already "
        "placed by this or an earlier set. Each random set draws from its own stream of `seed`: "
        "the same seed gives the same spheres (bit for bit on every platform for `constant` and "
        "`uniform` radii; `normal` and `lognormal` also use the C library's log, cos and exp). "
        "Normal and lognormal radii outside (0, half the box's smallest side] are redrawn; a lognormal radius with mean m "
        "and standard deviation s has sigma^2 = ln(1 + s^2/m^2), mu = ln m - sigma^2/2.\n"
        "- **Output intervals** default to fractions of `time.end`.\n\n"
        "Spheres of an explicit `list` must not overlap each other (the loader names both). "
        "Overlaps between spheres of different sets, and spheres behind a wall, are reported when "
        "the run starts.\n\n",
        f);

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
