/* Benchmark: a dense bed of 5 mm spheres resting on the floor of an open box, timed over a fixed
 * number of steps (docs/performance.md). Two ways to get the bed:
 *
 *   bench_bed [N ...]            makes its own: a jittered lattice settled for 0.25 s, then
 *                                1000 steps (ADEM_BENCH_STEPS) timed with 1 and 2 threads;
 *   bench_bed --data FILE ...    reads a bed settled by bench/peers/make_bed.sh (a LAMMPS data
 *                                file, atom_style sphere), so that adem, LAMMPS and LIGGGHTS time
 *                                the same positions with the same physics (bench/peers/).
 *
 * --data options (bench/peers/run_peers.sh passes them):
 *   --normal hertz|jkr  --gamma G  --rolling LAW  --rolling-friction ETA  --skin METRES
 *   --dt SECONDS  --relax STEPS (untimed)  --steps STEPS (timed)  --threads N
 *   --young E --poisson NU --restitution E --friction MU (defaults: the peers' params.sh)
 *   --energy-balance 1|0 (default 1: adem's per-contact energy bookkeeping; 0: off, as the
 *   peers' runs, which keep none)
 * and prints "PEERS key value" lines: timed, particles, loop_seconds, rebuilds,
 * contacts_per_particle, kinetic_energy_per_particle, peak_rss_bytes.
 * Uses only the public headers. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>

#include "adem/adem.h"
#include "adem/vec3.h"

/* A uniform number in [0, 1) (splitmix64): the bed's jitter, the same on every platform. */
static double uniform(uint64_t *s) {
  uint64_t z = (*s += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  z ^= z >> 31;
  return (double)(z >> 11) * (1.0 / 9007199254740992.0);
}

static double now(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static void die(const char *what, const adem_error *err) {
  fprintf(stderr, "bench_bed: %s: %s\n", what, err ? err->message : strerror(errno));
  exit(1);
}

static double peak_rss_bytes(void) {
  struct rusage ru;
  getrusage(RUSAGE_SELF, &ru);
  return (double)ru.ru_maxrss * 1024.0;
}

/* ---- the bed made here ---------------------------------------------------------------------- */

/* Spheres on a loose jittered lattice in a square box, dropped and settled. */
static adem_world *settled_bed(int n, double *settle_seconds) {
  adem_world *w = adem_world_create();
  adem_material_def m = adem_default_material_def();
  snprintf(m.name, sizeof m.name, "glass");
  m.density = 2500.0;
  m.young = 1e7;
  m.poisson = 0.25;
  m.restitution = 0.3;
  m.friction = 0.5;
  adem_error err;
  int glass = 0;
  if (adem_world_add_material(w, &m, &glass, &err)) die("material", &err);
  double r = 2.5e-3, h = 2.2 * r;
  int side = (int)ceil(sqrt(n / 20.0)); /* about 20 layers high */
  double L = side * h;
  if (adem_world_add_box(w, "box", v3(0, 0, 0), v3(L, L, 100.0 * L), glass, NULL, &err))
    die("box", &err);
  uint64_t rng = 1;
  for (int k = 0; k < n; ++k) {
    int ix = k % side, iy = (k / side) % side, iz = k / (side * side);
    adem_particle_def p = adem_default_particle_def();
    p.material = glass;
    p.radius = r;
    p.position = v3((ix + 0.5) * h + 0.1 * r * (uniform(&rng) - 0.5),
                    (iy + 0.5) * h + 0.1 * r * (uniform(&rng) - 0.5), (iz + 0.5) * h);
    if (adem_world_add_particle(w, &p, NULL, &err)) die("particle", &err);
  }
  adem_step_estimate est = adem_world_estimate_step(w, 1.0);
  adem_world_set_dt(w, est.dt);
  double t0 = now();
  if (adem_world_prepare(w, &err) != ADEM_OK) die("prepare", &err);
  /* fall through a few diameters and come to rest: 0.25 s of simulated time */
  if (adem_world_step(w, (uint64_t)(0.25 / est.dt), &err) != ADEM_OK) die("settle", &err);
  *settle_seconds = now() - t0;
  return w;
}

static uint64_t state_hash(const adem_world *w);

static int own_beds(int argc, char **argv) {
  int sizes[8] = {10000, 100000};
  int nsizes = 2;
  if (argc > 1) {
    nsizes = 0;
    for (int k = 1; k < argc && nsizes < 8; ++k) sizes[nsizes++] = atoi(argv[k]);
  }
  const char *s = getenv("ADEM_BENCH_STEPS");
  uint64_t steps = s ? (uint64_t)atoll(s) : 1000;
  printf("# adem %s bench_bed: settled bed, 5 mm spheres, E = 1e7 Pa, mu = 0.5, %llu steps timed\n",
         ADEM_VERSION_STRING, (unsigned long long)steps);
  printf("%9s %8s %14s %16s %12s %14s\n", "N", "threads", "settle_s", "particle-steps/s",
         "contacts/p", "peak_B/particle");
  for (int k = 0; k < nsizes; ++k) {
    double settle;
    adem_world *w = settled_bed(sizes[k], &settle);
    for (int threads = 1; threads <= 2; ++threads) {
      adem_world_set_threads(w, threads);
      adem_error err;
      double t0 = now();
      if (adem_world_step(w, steps, &err) != ADEM_OK) die("step", &err);
      double elapsed = now() - t0;
      adem_diagnostics d = adem_world_diagnostics(w);
      double n = (double)adem_world_particle_count(w);
      printf("%9d %8d %14.1f %16.3e %12.2f %14.0f\n", sizes[k], threads, settle,
             n * (double)steps / elapsed, 2.0 * (double)d.contacts_pp / n + (double)d.contacts_pw / n,
             peak_rss_bytes() / n);
      fflush(stdout);
    }
    /* equal on every host (docs/reliability.md#what-bitwise-covers) */
    printf("# N = %d: state hash %016llx\n", sizes[k], (unsigned long long)state_hash(w));
    adem_world_free(w);
  }
  return 0;
}

/* ---- the peers' bed ------------------------------------------------------------------------- */

typedef struct peer_options {
  const char *data;
  const char *normal, *rolling;
  double gamma, rolling_friction, skin, dt;
  double young, poisson, restitution, friction, gravity;
  long relax, steps;
  int threads;
  int energy_balance; /* 1 (adem's default) or 0: the peers keep no energy balance */
} peer_options;

static double number(const char *opt, const char *text) {
  char *end;
  errno = 0;
  double v = strtod(text, &end);
  if (errno || end == text || *end) {
    fprintf(stderr, "bench_bed: %s wants a number, not '%s'\n", opt, text);
    exit(2);
  }
  return v;
}

static peer_options parse_peer_options(int argc, char **argv) {
  /* defaults: bench/peers/params.sh */
  peer_options o = {NULL, "hertz", "model_c", 0.2, 0.1, 0.0005, 1e-5, 1e7, 0.3, 0.5, 0.5, 9.81,
                    1000, 1000, 1, 1};
  for (int k = 1; k < argc; ++k) {
    const char *a = argv[k];
    if (k + 1 >= argc) {
      fprintf(stderr, "bench_bed: %s wants a value\n", a);
      exit(2);
    }
    const char *v = argv[++k];
    if (!strcmp(a, "--data")) o.data = v;
    else if (!strcmp(a, "--normal")) o.normal = v;
    else if (!strcmp(a, "--rolling")) o.rolling = v;
    else if (!strcmp(a, "--gamma")) o.gamma = number(a, v);
    else if (!strcmp(a, "--rolling-friction")) o.rolling_friction = number(a, v);
    else if (!strcmp(a, "--skin")) o.skin = number(a, v);
    else if (!strcmp(a, "--dt")) o.dt = number(a, v);
    else if (!strcmp(a, "--young")) o.young = number(a, v);
    else if (!strcmp(a, "--poisson")) o.poisson = number(a, v);
    else if (!strcmp(a, "--restitution")) o.restitution = number(a, v);
    else if (!strcmp(a, "--friction")) o.friction = number(a, v);
    else if (!strcmp(a, "--gravity")) o.gravity = number(a, v);
    else if (!strcmp(a, "--relax")) o.relax = (long)number(a, v);
    else if (!strcmp(a, "--steps")) o.steps = (long)number(a, v);
    else if (!strcmp(a, "--threads")) o.threads = (int)number(a, v);
    else if (!strcmp(a, "--energy-balance")) o.energy_balance = (int)number(a, v);
    else {
      fprintf(stderr, "bench_bed: unknown option %s (see the comment at the top of bench_bed.c)\n", a);
      exit(2);
    }
  }
  if (!adem_law_find(ADEM_SLOT_NORMAL, o.normal) || !adem_law_find(ADEM_SLOT_ROLLING, o.rolling)) {
    fprintf(stderr, "bench_bed: --normal must be one of %s, --rolling one of %s\n",
            adem_law_choices(ADEM_SLOT_NORMAL), adem_law_choices(ADEM_SLOT_ROLLING));
    exit(2);
  }
  if (o.relax < 0 || o.steps < 1 || o.threads < 1 || !(o.dt > 0) || !(o.skin > 0)) {
    fprintf(stderr, "bench_bed: --relax >= 0, --steps >= 1, --threads >= 1, --dt > 0, --skin > 0\n");
    exit(2);
  }
  return o;
}

/* A LAMMPS data file of atom_style sphere: the box from "xlo xhi" ... lines, then the
 * "Atoms # sphere" lines "id type diameter density x y z". The box's 5 lower and side faces become
 * walls (the peers' runs have walls at x, y = 0 and L and a floor at z = 0). */
typedef struct peer_bed {
  double lo[3], hi[3];
  adem_vec3 *pos;
  double *diameter;
  double density;
  size_t n, cap;
} peer_bed;

static void read_data_file(const char *path, peer_bed *b) {
  FILE *f = fopen(path, "r");
  if (!f) die(path, NULL);
  memset(b, 0, sizeof *b);
  char line[512];
  int in_atoms = 0;
  while (fgets(line, sizeof line, f)) {
    double a, c;
    char axis[2];
    if (!in_atoms) {
      if (sscanf(line, "%lf %lf %1[xyz]lo", &a, &c, axis) == 3) {
        b->lo[axis[0] - 'x'] = a;
        b->hi[axis[0] - 'x'] = c;
      } else if (!strncmp(line, "Atoms", 5)) {
        in_atoms = 1;
      }
      continue;
    }
    long id, type;
    double d, rho;
    adem_vec3 x;
    int got = sscanf(line, "%ld %ld %lf %lf %lf %lf %lf", &id, &type, &d, &rho, &x.x, &x.y, &x.z);
    if (got <= 0) {
      if (b->n) break; /* the blank line after the last atom */
      continue;
    }
    if (got != 7 || !(d > 0) || !(rho > 0) || (b->n && rho != b->density)) {
      fprintf(stderr, "bench_bed: %s: atom line '%s' is not 'id type diameter density x y z' "
                      "with one density for all\n",
              path, line);
      exit(1);
    }
    if (b->n == b->cap) {
      b->cap = b->cap ? 2 * b->cap : 1024;
      b->pos = realloc(b->pos, b->cap * sizeof *b->pos);
      b->diameter = realloc(b->diameter, b->cap * sizeof *b->diameter);
      if (!b->pos || !b->diameter) die("memory", NULL);
    }
    b->density = rho;
    b->pos[b->n] = x;
    b->diameter[b->n++] = d;
  }
  fclose(f);
  if (!b->n) {
    fprintf(stderr, "bench_bed: %s: no atoms\n", path);
    exit(1);
  }
}

/* The bed of a LAMMPS data file of atom_style sphere (box from the "xlo xhi" lines, atoms from
 * "Atoms # sphere"), in an open box: walls at x, y = lo and hi and a floor at z = lo, as the
 * peers' runs have. */
static adem_world *build_peer_world(const peer_options *o) {
  peer_bed b;
  read_data_file(o->data, &b);
  adem_world *w = adem_world_create();
  adem_world_set_energy_balance(w, o->energy_balance != 0);
  adem_error err;
  adem_material_def m = adem_default_material_def();
  snprintf(m.name, sizeof m.name, "spheres");
  m.density = b.density;
  m.young = o->young;
  m.poisson = o->poisson;
  m.restitution = o->restitution;
  m.friction = o->friction;
  m.param[ADEM_PARAM_ROLLING_FRICTION] = o->rolling_friction;
  m.param[ADEM_PARAM_ROLLING_DAMPING] = 0.0;
  m.param[ADEM_PARAM_SURFACE_ENERGY] = o->gamma;
  int spheres = 0, walls = 1;
  adem_material_def mw = m;
  snprintf(mw.name, sizeof mw.name, "walls");
  if (adem_world_add_material(w, &m, &spheres, &err)) die("material", &err);
  if (adem_world_add_material(w, &mw, &walls, &err)) die("material", &err);
  adem_interaction_def pair = adem_default_interaction_def();
  pair.material_a = pair.material_b = spheres;
  pair.normal = (adem_normal_model)adem_law_find(ADEM_SLOT_NORMAL, o->normal)->id;
  pair.rolling = (adem_rolling_model)adem_law_find(ADEM_SLOT_ROLLING, o->rolling)->id;
  if (adem_world_set_interaction(w, &pair, &err)) die("interaction", &err);
  /* Walls stay Hertz in the JKR bed, as in the peers' inputs (bench/peers/lmp_physics.lmp). */
  adem_interaction_def wall = pair;
  wall.material_b = walls;
  wall.normal = ADEM_NORMAL_HERTZ;
  if (wall.rolling == ADEM_ROLLING_DTK) wall.rolling = ADEM_ROLLING_NONE; /* DTK needs JKR */
  if (adem_world_set_interaction(w, &wall, &err)) die("interaction", &err);

  double dmax = 0.0;
  for (size_t i = 0; i < b.n; ++i) {
    adem_particle_def p = adem_default_particle_def();
    p.material = spheres;
    p.radius = 0.5 * b.diameter[i];
    p.position = b.pos[i];
    if (adem_world_add_particle(w, &p, NULL, &err)) die("particle", &err);
    dmax = fmax(dmax, b.diameter[i]);
  }
  free(b.pos);
  free(b.diameter);
  const adem_vec3 points[5] = {{b.lo[0], 0, 0}, {b.hi[0], 0, 0}, {0, b.lo[1], 0}, {0, b.hi[1], 0}, {0, 0, b.lo[2]}};
  const adem_vec3 normals[5] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
  const char *names[5] = {"xmin", "xmax", "ymin", "ymax", "floor"};
  for (int k = 0; k < 5; ++k) {
    adem_plane_def pl = adem_default_plane_def();
    snprintf(pl.name, sizeof pl.name, "%s", names[k]);
    pl.point = points[k];
    pl.normal = normals[k];
    pl.material = walls;
    if (adem_world_add_plane(w, &pl, NULL, &err)) die("plane", &err);
  }
  adem_world_set_gravity(w, v3(0, 0, -o->gravity));
  adem_world_set_dt(w, o->dt);
  adem_world_set_skin(w, o->skin / dmax);
  adem_world_set_threads(w, o->threads);
  /* the bed rests with overlaps of ~2% of a diameter, as LAMMPS settled it */
  adem_world_set_initial_overlap(w, 0.2);
  return w;
}

static double contacts_per_particle(const adem_world *w) {
  adem_diagnostics d = adem_world_diagnostics(w);
  double n = (double)adem_world_particle_count(w);
  return (2.0 * (double)d.contacts_pp + (double)d.contacts_pw) / n;
}

/* FNV-1a over the positions, velocities and spins: equal hashes mean bitwise equal states
 * (thread counts, code changes that must not change results). */
static uint64_t state_hash(const adem_world *w) {
  size_t n = adem_world_particle_count(w);
  double *buf = malloc(3 * n * sizeof *buf + 1);
  adem_error err;
  uint64_t h = 1469598103934665603ull;
  adem_particle_field fields[] = {ADEM_FIELD_POSITION, ADEM_FIELD_VELOCITY, ADEM_FIELD_ANGULAR_VELOCITY};
  for (int f = 0; f < 3 && buf; ++f) {
    if (adem_world_get_particles(w, fields[f], buf, 3 * n, &err)) die("read back", &err);
    const unsigned char *c = (const unsigned char *)buf;
    for (size_t k = 0; k < 3 * n * sizeof *buf; ++k) h = (h ^ c[k]) * 1099511628211ull;
  }
  free(buf);
  return h;
}

static int run_peer_bed(int argc, char **argv) {
  peer_options o = parse_peer_options(argc, argv);
  adem_world *w = build_peer_world(&o);
  adem_error err;
  double t0 = now();
  if (adem_world_prepare(w, &err)) die("prepare", &err);
  if (o.relax && adem_world_step(w, (uint64_t)o.relax, &err)) die("relax", &err);
  printf("PEERS setup_and_relax_seconds %.6f\n", now() - t0);
  uint64_t builds0 = adem_world_neighbor_builds(w);
  printf("PEERS timed %ld\n", o.steps);
  fflush(stdout);
  t0 = now();
  if (adem_world_step(w, (uint64_t)o.steps, &err)) die("step", &err);
  double loop = now() - t0;
  size_t n = adem_world_particle_count(w);
  adem_diagnostics d = adem_world_diagnostics(w);
  printf("PEERS particles %zu\n", n);
  printf("PEERS loop_seconds %.6f\n", loop);
  printf("PEERS particle_steps_per_second %.6e\n", (double)n * (double)o.steps / loop);
  printf("PEERS rebuilds %llu\n", (unsigned long long)(adem_world_neighbor_builds(w) - builds0));
  printf("PEERS contacts_per_particle %.4f\n", contacts_per_particle(w));
  printf("PEERS pair_contacts %zu\n", d.contacts_pp);
  printf("PEERS wall_contacts %zu\n", d.contacts_pw);
  printf("PEERS kinetic_energy_per_particle %.6e\n", (d.kinetic + d.rotational) / (double)n);
  printf("PEERS max_overlap_ratio %.6f\n", d.max_overlap_ratio);
  printf("PEERS elastic_energy %.17g\n", d.elastic);
  printf("PEERS state_hash %016llx\n", (unsigned long long)state_hash(w));
  printf("PEERS peak_rss_bytes %.0f\n", peak_rss_bytes());
  printf("PEERS bytes_per_particle_model %zu\n", adem_world_bytes_per_particle());
  adem_world_free(w);
  return 0;
}

int main(int argc, char **argv) {
  for (int k = 1; k < argc; ++k)
    if (!strcmp(argv[k], "--data")) return run_peer_bed(argc, argv);
  return own_beds(argc, argv);
}
