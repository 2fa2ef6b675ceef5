/* Running a case: stepping in chunks between output events, progress, stop requests.
 *
 * Output events are scheduled on step counts (every round(interval/dt) steps, and at the last
 * step), never by comparing float times, so a run writes the same files at the same steps
 * whether it was interrupted and resumed or not. After each chunk every event due at the current
 * step is handled before the stop flag is looked at; a checkpoint therefore always follows the
 * events of its own step, and a resumed run knows what was written from the step count alone. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "adem/case.h"
#include "adem/laws.h"
#include "adem/run.h"
#include "adem/world.h"
#include "adem/files.h"
#include "flow_plot.h"
#include "insert.h"
#include "log.h"
#include "outlets.h"
#include "output.h"
#include "schedule.h"
#include "stages.h"
#include "world_internal.h"
#ifdef ADEM_HAVE_MPI
#include "split.h"
#endif

/* Most steps between two looks at the stop flag. */
enum { RUN_MAX_CHUNK = 100 };
/* Wall seconds a chunk should take at most, so that Ctrl-C answers quickly on big systems. */
#define RUN_CHUNK_SECONDS 0.2
#define RUN_PROGRESS_SECONDS 1.0

uint64_t adem_case_total_steps(const adem_case *c) {
  return adem_schedule_total_steps(c->end_time, adem_world_dt(c->world));
}

adem_run_options adem_default_run_options(void) {
  adem_run_options o;
  memset(&o, 0, sizeof o);
  return o;
}

static double wall_now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static bool due(uint64_t step, uint64_t period) { return period > 0 && step % period == 0; }

/* The next step after `step` at which something must be written. */
static uint64_t next_event(uint64_t step, uint64_t total, const uint64_t *periods, int nperiods) {
  uint64_t next = total;
  for (int k = 0; k < nperiods; ++k) {
    if (periods[k] == 0) continue;
    uint64_t e = (step / periods[k] + 1) * periods[k];
    if (e < next) next = e;
  }
  return next;
}

/* Samples the run for its ETA and calls the progress hook. */
static void report(const adem_run_options *opt, const adem_case *c, uint64_t total, double t0,
                   adem_eta *eta, bool final) {
  if (!opt->progress) return;
  const adem_world *w = c->world;
  double end_time = c->end_time;
  adem_progress p;
  memset(&p, 0, sizeof p);
  p.may_end_early = c->until != NULL;
  p.final = final;
  for (int k = 0; c->stages && k < c->stages->n; ++k)
    p.may_end_early |= c->stages->s[k].until != NULL && k + 1 == c->stages->n;
  p.time = w->time;
  p.end_time = end_time;
  p.step = w->step;
  p.total_steps = total;
  p.wall_seconds = wall_now() - t0;
  for (size_t k = 0; k < w->pp.n; ++k) p.contacts += w->pp.touching[k];
  for (size_t k = 0; k < w->pw.n; ++k) p.contacts += w->pw.touching[k];
  for (size_t k = 0; k < w->pm.l.n; ++k) p.contacts += w->pm.l.touching[k];
  p.particles = w->p.n;
  adem_stages_until_status(c, p.until, sizeof p.until);
  adem_eta_add(eta, p.wall_seconds, w->step, p.contacts, p.particles);
  p.steps_per_second = adem_eta_rate(eta);
  p.eta_seconds = adem_eta_seconds(eta, total, &p.eta_rough);
  if (final) { /* done, whatever the end time said */
    p.eta_seconds = 0.0;
    p.eta_rough = ADEM_ETA_STEADY;
    p.may_end_early = 0;
  }
  opt->progress(&p, opt->progress_user);
}

/* Adds what the failed run leaves behind to the world's message. */
static void note_kept(adem_error *err, const char *dir, double t_checkpoint, bool have_checkpoint) {
  if (!err) return;
  size_t len = strlen(err->message);
  if (have_checkpoint)
    snprintf(err->message + len, sizeof err->message - len,
             "; the output written before is kept in %s (last checkpoint at t = %.9g s)", dir,
             t_checkpoint);
  else
    snprintf(err->message + len, sizeof err->message - len,
             "; the output written before is kept in %s", dir);
}

/* output.plot_loads: loads.png from the CSV written by the run. */
static adem_status plot_loads(const adem_case *c, const char *dir, bool have_csv, adem_error *err) {
  if (!have_csv) {
    adem_log(ADEM_LOG_WARN, "output.plot_loads needs the CSV time series, which is off: no plot");
    return ADEM_OK;
  }
  char *csv = adem_file_join(dir, "timeseries.csv");
  char *png = adem_file_join(dir, "loads.png");
  adem_status st;
  if (csv && png) {
    char title[ADEM_NAME_MAX + 32];
    snprintf(title, sizeof title, "%s: wall loads", c->name[0] ? c->name : "adem");
    st = adem_output_plot_loads(c->world, csv, png, title, err);
  } else {
    st = adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  }
  free(csv);
  free(png);
  return st;
}

/* output.plot and output.plot_loads: energy.png and loads.png from the CSV in dir. */
static adem_status write_plots(const adem_case *c, const char *dir, adem_error *err) {
  if (!c->output.plot && !c->output.plot_loads) return ADEM_OK;
  bool have_csv = adem_stages_output_on(c, 1);
  adem_status st = ADEM_OK;
  if (c->output.plot) {
    if (!have_csv) {
      adem_log(ADEM_LOG_WARN, "output.plot needs the CSV time series, which is off: no plot");
    } else {
      char *csv = adem_file_join(dir, "timeseries.csv");
      char *png = adem_file_join(dir, "energy.png");
      if (csv && png) {
        char title[ADEM_NAME_MAX + 32];
        snprintf(title, sizeof title, "%s: energy", c->name[0] ? c->name : "adem");
        st = adem_output_plot_energy(csv, png, title, err);
      } else {
        st = adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
      }
      free(csv);
      free(png);
    }
  }
  if (!st && c->output.plot_loads) st = plot_loads(c, dir, have_csv, err);
  if (!st && c->output.plot && have_csv && adem_outlets_columns(c->outlets) > 0) {
    char *csv = adem_file_join(dir, "timeseries.csv"), *png = adem_file_join(dir, "flow.png");
    st = csv && png ? adem_run_plot_flow(c, csv, png, err)
                    : adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
    free(csv);
    free(png);
  }
  return st;
}

/* output.regions: columns NAME_count and NAME_mass_kg of each region. */
typedef struct region_columns {
  int n;
  int brof; /* the first of BROF's columns (n without them) */
  char (*names)[ADEM_NAME_MAX + 16];
  const char **name;
  double *value, *count, *mass;
} region_columns;

static void region_columns_free(region_columns *rc) {
  free(rc->names);
  free(rc->name);
  free(rc->value);
  free(rc->count);
  free(rc->mass);
  memset(rc, 0, sizeof *rc);
}

/* Whether some configuration of the case (its own, or a stage's) gives a pair BROF: a rolling
 * law that resists absolute spin (its row's .absolute_spin), whose angular impulse the CSV
 * reports. */
static bool case_uses_brof(const adem_case *c) {
  const adem_materials *mt = &c->world->mat;
  for (int j = 0; j < mt->ndefs; ++j)
    if (adem_laws_absolute_spin((int)mt->defs[j].rolling)) return true;
  for (int k = 0; c->stages && k < c->stages->n; ++k)
    for (int j = 0; j < c->stages->s[k].config.ninteractions; ++j)
      if (adem_laws_absolute_spin((int)c->stages->s[k].config.interactions[j].rolling)) return true;
  return false;
}

/* Whether the CSV has a slip column for plane k (k < nplanes) or mesh group k - nplanes: the
 * walls that move (their CSV flag, any stage's motion). */
static bool slip_column(const adem_walls *wl, int k) {
  if (k < wl->nplanes) return (wl->planes[k].csv & ADEM_WALL_CSV_MOVES) != 0;
  int g = k - wl->nplanes;
  for (int j = 0; j < wl->nmesh_walls; ++j)
    if (g >= wl->mesh_walls[j].first && g < wl->mesh_walls[j].first + wl->mesh_walls[j].count)
      return (wl->mesh_walls[j].csv & ADEM_WALL_CSV_MOVES) != 0;
  return false;
}

/* ... then the outlets' and mass flows' columns (outlets.h), then NAME_slip_m_s of each moving
 * wall (adem_world_wall_slip), then, when the case has BROF, the angular impulse BROF's particle
 * contacts have added (brof_impulse_x_Nms ...: no partner takes it back, I9-I10). */
static bool region_columns_make(region_columns *rc, const adem_regions *rs, const adem_outlets *o,
                                const adem_world *w, bool brof) {
  memset(rc, 0, sizeof *rc);
  int nr = rs ? rs->n : 0, no = adem_outlets_columns(o), ns = 0;
  int nw = w->walls.nplanes + w->walls.mesh.ngroups;
  for (int k = 0; k < nw; ++k) ns += slip_column(&w->walls, k);
  rc->brof = 2 * nr + no + ns;
  rc->n = rc->brof + (brof ? 3 : 0);
  size_t m = (size_t)(nr > 0 ? nr : 1), mc = 2 * m + (size_t)no + (size_t)ns + 3;
  rc->names = calloc(mc, sizeof *rc->names);
  rc->name = calloc(mc, sizeof *rc->name);
  rc->value = calloc(mc, sizeof *rc->value);
  rc->count = calloc(m, sizeof *rc->count);
  rc->mass = calloc(m, sizeof *rc->mass);
  if (!rc->names || !rc->name || !rc->value || !rc->count || !rc->mass) {
    region_columns_free(rc);
    return false;
  }
  for (int k = 0; k < nr; ++k) {
    snprintf(rc->names[2 * k], sizeof rc->names[0], "%s_count", rs->r[k].name);
    snprintf(rc->names[2 * k + 1], sizeof rc->names[0], "%s_mass_kg", rs->r[k].name);
    rc->name[2 * k] = rc->names[2 * k];
    rc->name[2 * k + 1] = rc->names[2 * k + 1];
  }
  for (int k = 0; k < no; ++k) {
    adem_outlets_column_name(o, k, rc->names[2 * nr + k], sizeof rc->names[0]);
    rc->name[2 * nr + k] = rc->names[2 * nr + k];
  }
  for (int k = 0, c = 2 * nr + no; k < nw; ++k) {
    if (!slip_column(&w->walls, k)) continue;
    const char *wn = k < w->walls.nplanes ? w->walls.planes[k].def.name
                                          : w->walls.mesh.groups[k - w->walls.nplanes].name;
    snprintf(rc->names[c], sizeof rc->names[0], "%s_slip_m_s", wn);
    rc->name[c] = rc->names[c];
    c++;
  }
  for (int a = 0, c = rc->n - 3; brof && a < 3; ++a) {
    snprintf(rc->names[c + a], sizeof rc->names[0], "brof_impulse_%c_Nms", "xyz"[a]);
    rc->name[c + a] = rc->names[c + a];
  }
  return true;
}

/* A CSV row with the regions' counts and masses now. */
static adem_status csv_row(adem_output *out, adem_case *c, region_columns *rc,
                           adem_error *err) {
  int nr = c->regions ? c->regions->n : 0;
  if (nr > 0) {
    adem_regions_count(c->regions, c->world, rc->count, rc->mass);
    for (int k = 0; k < nr; ++k) {
      rc->value[2 * k] = rc->count[k];
      rc->value[2 * k + 1] = rc->mass[k];
    }
  }
  adem_status st = adem_outlets_sample(c, rc->value + 2 * nr, err);
  const adem_walls *wl = &c->world->walls;
  int nw = wl->nplanes + wl->mesh.ngroups, v = 2 * nr + adem_outlets_columns(c->outlets);
  if (!st && v < rc->brof) {
    double *slip = malloc(((size_t)nw + 1) * sizeof *slip);
    if (!slip) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
    adem_world_wall_slip(c->world, slip, slip + wl->nplanes);
    for (int k = 0; k < nw; ++k)
      if (slip_column(wl, k)) rc->value[v++] = slip[k];
    free(slip);
  }
  if (!st && rc->brof < rc->n) { /* BROF's columns */
    adem_vec3 b = adem_world_diagnostics(c->world).brof_impulse;
    rc->value[rc->brof] = b.x;
    rc->value[rc->brof + 1] = b.y;
    rc->value[rc->brof + 2] = b.z;
  }
  return st ? st : adem_output_csv_append(out, c->world, err);
}

/* The run's processes (src/mpi): one, or a system split over several, each stepping its own
 * part; rank 0 assembles the whole into the case's world for every output and alone writes. */
typedef struct run_split {
#ifdef ADEM_HAVE_MPI
  adem_split *s;
  adem_split_stats stats; /* of the run's splits so far (a stage or a pour splits again) */
#endif
  adem_world *part; /* the world that steps: the case's own, or this process's part */
  bool many;        /* more than one process */
  bool writer;      /* this process writes the output */
} run_split;

/* How many processes run (MPI_Init by the program: the adem command's `run`). */
static int split_size(run_split *rs, adem_case *c) {
  rs->part = c->world;
  rs->writer = true;
  rs->many = false;
  int size = 1;
#ifdef ADEM_HAVE_MPI
  rs->s = NULL;
  memset(&rs->stats, 0, sizeof rs->stats);
  int on = 0, rank = 0;
  MPI_Initialized(&on);
  if (on) {
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  }
  rs->writer = rank == 0;
  rs->many = size > 1;
#endif
  return size;
}

/* Splits the prepared world when more than one process runs. */
static adem_status split_start(adem_case *c, run_split *rs, int size, adem_error *err) {
#ifdef ADEM_HAVE_MPI
  if (size < 2) return ADEM_OK;
  adem_world *w = c->world;
  /* nothing to split yet (every particle comes from a pour): every process steps the same
   * empty world until the first batch, then splits */
  if (w->p.n == 0 && !w->admit_pending) return ADEM_OK;
  if (adem_world_has_frozen(w)) /* their loads are summed on one process (frozen.c) */
    return adem_error_set(err, ADEM_ERR_INPUT,
                          "frozen particles (particles[].frozen, attach) are not supported split "
                          "over MPI processes yet: run with one process");
  if (w->admit_pending) { /* what the serial run's next step begins with */
    w->admit_pending = false;
    adem_status st = adem_world_admit_particles(w, w->admit_from, err);
    if (st) return st;
  }
  return adem_split_create(w, MPI_COMM_WORLD, &rs->s, &rs->part, err);
#else
  (void)c;
  (void)rs;
  (void)size;
  (void)err;
  return ADEM_OK;
#endif
}

/* The whole state in the case's world on the writer, or on every process (everywhere: for the
 * decisions every process takes alike, on the serial state). Collective when split. */
static adem_status split_assemble(adem_case *c, run_split *rs, bool everywhere, adem_error *err) {
#ifdef ADEM_HAVE_MPI
  if (rs->s) return adem_split_assemble(rs->s, rs->part, c->world, everywhere, err);
#endif
  (void)c;
  (void)rs;
  (void)everywhere;
  (void)err;
  return ADEM_OK;
}

static adem_status split_agree(run_split *rs, adem_status st, adem_error *err);

/* A frame: one .vtu of the whole, written by the writer; split and with output.pieces, a piece
 * of its own particles from every process and the .pvtu from the writer (collective then). */
static adem_status write_frame(adem_output *out, adem_case *c, run_split *rs, size_t *frame_no,
                               adem_error *err) {
  adem_status st = ADEM_OK;
  if (!adem_stages_output_on(c, 0)) return ADEM_OK;
#ifdef ADEM_HAVE_MPI
  if (rs->s && c->output.pieces) {
    uint32_t *idx = NULL;
    size_t n = 0;
    if (adem_split_own_by_id(rs->s, rs->part, &idx, &n))
      st = adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
    if (!st && adem_split_break("pieces")) { /* the test's control: the ghosts too */
      n = 0;
      uint32_t *all = realloc(idx, (rs->part->p.n + 1) * sizeof *all);
      if (all)
        for (idx = all; n < rs->part->p.n; ++n) idx[n] = (uint32_t)n;
    }
    const char *dir = c->output.dir[0] ? c->output.dir : ".";
    if (!st)
      st = adem_output_frame_piece(dir, *frame_no, adem_split_rank(rs->s), rs->part, idx, n, err);
    free(idx);
    st = split_agree(rs, st, err); /* every piece is there before the .pvtu names it */
    int size = 1;
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    if (!st && rs->writer) st = adem_output_frame_pvtu(out, c->world, size, err);
    if (!st) (*frame_no)++;
    return st;
  }
#endif
  if (rs->writer) st = adem_output_frame(out, c->world, err);
  if (!st) (*frame_no)++;
  return st;
}

/* After a change to the whole (a stage begun, particles poured), assembled on every process
 * and changed alike on each: the parts are cut from it again, as from a checkpoint. */
static void split_end(adem_case *c, run_split *rs);
static adem_status split_again(adem_case *c, run_split *rs, adem_error *err) {
  int size = rs->many ? 2 : 1;
  split_end(c, rs);
  return split_start(c, rs, size, err);
}

/* A status the same on every process: an error on one is an error on all. */
static adem_status split_agree(run_split *rs, adem_status st, adem_error *err) {
#ifdef ADEM_HAVE_MPI
  if (rs->many) {
    int v = (int)st, r = 0;
    MPI_Allreduce(&v, &r, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    if (r && !st) return adem_error_set(err, (adem_status)r, "another MPI process failed");
  }
#endif
  (void)rs;
  (void)err;
  return st;
}

static bool split_any(run_split *rs, bool yes) {
#ifdef ADEM_HAVE_MPI
  if (rs->many) {
    int v = yes ? 1 : 0, r = 0;
    MPI_Allreduce(&v, &r, 1, MPI_INT, MPI_LOR, MPI_COMM_WORLD);
    return r != 0;
  }
#endif
  (void)rs;
  return yes;
}

static void split_end(adem_case *c, run_split *rs) {
#ifdef ADEM_HAVE_MPI
  if (rs->s) {
    adem_split_stats_add(rs->s, &rs->stats);
    adem_world_free(rs->part);
    adem_split_free(rs->s);
    rs->s = NULL;
  }
#endif
  rs->part = c->world;
}

static adem_status run_case(adem_case *c, const adem_run_options *opt_in, run_split *rs,
                            adem_error *err);

/* What the split run's exchanges cost, per process and step (bench/mpi, docs/parallel.md):
 * every process's figures to rank 0, which logs the mean and the largest. Collective. */
static void split_report(run_split *rs) {
#ifdef ADEM_HAVE_MPI
  if (!rs->many) return;
  int size = 1, rank = 0;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  double *all = malloc((size_t)size * ADEM_SPLIT_STATS_COUNT * sizeof *all);
  double mine[ADEM_SPLIT_STATS_COUNT];
  memcpy(mine, &rs->stats, sizeof mine);
  MPI_Gather(mine, ADEM_SPLIT_STATS_COUNT, MPI_DOUBLE, all, all ? ADEM_SPLIT_STATS_COUNT : 0,
             MPI_DOUBLE, 0, MPI_COMM_WORLD);
  if (rank == 0 && all) {
    adem_split_stats sum, top;
    memset(&sum, 0, sizeof sum);
    memset(&top, 0, sizeof top);
    double *ps = (double *)&sum, *pt = (double *)&top;
    for (int q = 0; q < size; ++q)
      for (int k = 0; k < ADEM_SPLIT_STATS_COUNT; ++k) {
        double v = all[q * ADEM_SPLIT_STATS_COUNT + k];
        ps[k] += v;
        pt[k] = v > pt[k] ? v : pt[k];
      }
    double steps = sum.refreshes / size, n = size;
    if (steps > 0.0) {
      adem_log(ADEM_LOG_INFO,
               "split over %d processes, per process and step (mean, largest): own particles "
               "%.0f, %.0f; ghosts %.0f, %.0f; ghost refresh %.1f, %.1f kB sent in %.1f, %.1f "
               "us (%.4f us per own particle); %.0f builds, per build %.1f kB sent in %.2f ms "
               "(mean); other exchanges %.1f kB per step (outputs, decisions, wall loads)",
               size, sum.owned / n / steps, top.owned / steps, sum.ghosts / n / steps,
               top.ghosts / steps, sum.refresh_bytes / n / steps / 1e3,
               top.refresh_bytes / steps / 1e3, sum.refresh_seconds / n / steps * 1e6,
               top.refresh_seconds / steps * 1e6,
               sum.owned > 0.0 ? sum.refresh_seconds / sum.owned * 1e6 : 0.0,
               sum.builds / n,
               sum.builds > 0.0 ? sum.build_bytes / sum.builds / 1e3 : 0.0,
               sum.builds > 0.0 ? sum.build_seconds / sum.builds * 1e3 : 0.0,
               sum.other_bytes / n / steps / 1e3);
    }
  }
  free(all);
#else
  (void)rs;
#endif
}

adem_status adem_run(adem_case *c, const adem_run_options *opt_in, adem_error *err) {
  run_split rs;
  adem_status st = run_case(c, opt_in, &rs, err);
  split_end(c, &rs);
  if (!st) split_report(&rs); /* collective: only when every process ended well */
  return st;
}

static adem_status run_case(adem_case *c, const adem_run_options *opt_in, run_split *rs,
                            adem_error *err) {
  adem_run_options opt = opt_in ? *opt_in : adem_default_run_options();
  adem_world *w = c->world;
  if (opt.nthreads > 0) adem_world_set_threads(w, opt.nthreads);
  /* A prepared world past step 0 comes from a checkpoint (or an earlier run): continue it. */
  bool resume = w->prepared && w->step > 0;
  const char *dir = c->output.dir[0] ? c->output.dir : ".";
  int nproc = split_size(rs, c);

  /* Fail on an unwritable folder before any expensive set-up. */
  adem_status st = ADEM_OK;
  if (rs->writer) st = adem_file_mkdir_p(dir, err);
  if (!st && rs->writer) st = adem_file_check_writable(dir, err);
  st = split_agree(rs, st, err);
  if (st) return st;
  if (!w->prepared) {
    st = adem_world_prepare(w, err);
    if (st) return st;
  }
  /* each process prepares the whole (the same), then keeps its part */
  st = split_start(c, rs, nproc, err);
  if (st) return st;
  adem_world *ws = rs->part;

  const double dt = w->dt;
  const uint64_t total = adem_schedule_total_steps(c->end_time, dt);
  /* A stage may change the intervals: they are taken again after each stage start. */
  uint64_t k_frame = adem_schedule_period(c->output.frame_interval, dt);
  uint64_t k_csv = adem_schedule_period(c->output.csv_interval, dt);
  uint64_t k_ckpt = adem_schedule_period(c->output.checkpoint_interval, dt);
  uint64_t periods[3] = {k_frame, k_csv, k_ckpt};
  const uint64_t step0 = w->step;
  if (rs->writer && !resume) { /* outputs fall on whole steps: say where, when not on the interval */
    const struct {
      const char *what;
      double interval;
      uint64_t k;
    } every[] = {{"frames", c->output.frame_interval, k_frame}, {"CSV rows", c->output.csv_interval, k_csv}};
    for (int j = 0; j < 2; ++j)
      if (every[j].k && fabs((double)every[j].k * dt - every[j].interval) > 1e-9 * every[j].interval)
        adem_log(ADEM_LOG_INFO, "%s every %llu steps = %.9g s (the interval %g s in whole steps of "
                                "dt = %.9g s): at t = %.9g, %.9g, ... s",
                 every[j].what,
                 (unsigned long long)every[j].k, (double)every[j].k * dt, every[j].interval, dt,
                 (double)every[j].k * dt, 2.0 * (double)every[j].k * dt);
  }
  char why[ADEM_MSG_MAX];
  if (resume && adem_stages_ended(c, why, sizeof why)) {
    adem_log(ADEM_LOG_INFO, "%s", why);
    return rs->writer ? write_plots(c, dir, err) : ADEM_OK;
  }
  if (resume && step0 >= total) {
    adem_log(ADEM_LOG_INFO, "the run has already reached its end time (t = %.9g s)", w->time);
    return rs->writer ? write_plots(c, dir, err) : ADEM_OK;
  }
  /* The frames at t = 0 and at every interval up to this step were written before the
   * checkpoint; a frame and a CSV row written only because an earlier run ended here are
   * replaced by those of the run going on. */
  size_t frames_done = resume ? (size_t)c->frames_written : 0;
  bool drop_row = resume && c->csv_last_extra;

  adem_output out;
  memset(&out, 0, sizeof out);
  adem_output_track track = {c->output.ntrack, c->output.track};
  region_columns rc;
  if (!region_columns_make(&rc, c->regions, c->outlets, w, case_uses_brof(c)))
    return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  adem_output_extra extra = {rc.n, rc.name, rc.value};
  if (rs->writer)
    st = adem_output_open(&out, dir, w, adem_stages_output_on(c, 0), adem_stages_output_on(c, 1),
                          resume, frames_done, (double)k_frame * dt, w->time, drop_row, &track,
                          &extra, err);
  if (!st && rs->writer)
    st = adem_output_contacts_open(&out, c->output.contacts_every, c->output.contacts_csv, resume,
                                   frames_done, err);
  st = split_agree(rs, st, err);
  if (st) {
    region_columns_free(&rc);
    return st;
  }
  char *ckpt_path = adem_file_join(dir, "checkpoint");
  if (!ckpt_path) {
    if (rs->writer) adem_output_close(&out);
    region_columns_free(&rc);
    return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  }
  bool have_ckpt = resume;
  double t_ckpt = w->time;

  bool stale = false;            /* the whole changed: split it again before the next step */
  size_t frame_no = frames_done; /* the next frame's index, on every process */
  if (!st && !resume) st = write_frame(&out, c, rs, &frame_no, err);
  if (!st && !resume && rs->writer) {
    c->frames_written = out.next_frame;
    st = csv_row(&out, c, &rc, err);
  }
  st = split_agree(rs, st, err);
  if (!resume && !st) { /* pour batches due at step 0, on every process's whole alike */
    size_t n_before = w->p.n;
    st = adem_stages_events(c, err);
    stale = rs->many && w->p.n != n_before;
  }
  st = split_agree(rs, st, err);
  const double t0 = wall_now();
  double last_report = t0;
  adem_eta eta;
  adem_eta_init(&eta);
  if (rs->writer) report(&opt, c, total, t0, &eta, false);
  uint64_t chunk_cap = RUN_MAX_CHUNK;

  bool ended = false; /* a run-until condition was met */
  while (!st && ws->step < total && !ended) {
#ifdef ADEM_HAVE_MPI
    if (stale && adem_split_break("resplit")) stale = false; /* the test's control */
#endif
    if (stale) {
      st = split_again(c, rs, err);
      st = split_agree(rs, st, err);
      if (st) break;
      ws = rs->part;
      stale = false;
    }
    uint64_t target = next_event(ws->step, total, periods, 3);
    uint64_t staged = adem_stages_next_step(c, ws->step); /* stage starts, pour batches */
    if (staged < target) target = staged;
    uint64_t check = adem_stages_until_next(c, ws->step); /* run-until conditions */
    if (check < target) target = check;
    uint64_t n = target - ws->step;
    if (n > chunk_cap) n = chunk_cap;
    double tc = wall_now();
    st = adem_world_step(ws, n, err);
    double spent = wall_now() - tc;
    if (st) {
      if (st == ADEM_ERR_RUNTIME) note_kept(err, dir, t_ckpt, have_ckpt);
      break;
    }
    /* Keep a chunk near RUN_CHUNK_SECONDS of wall time; split, the same chunks on every
     * process (the stop flag is agreed on at their ends). */
    if (spent > 0.0 && !rs->many) {
      double fit = RUN_CHUNK_SECONDS * (double)n / spent;
      chunk_cap = fit >= RUN_MAX_CHUNK ? RUN_MAX_CHUNK : (fit < 1.0 ? 1 : (uint64_t)fit);
    }

    uint64_t s = ws->step;
    if (ws != w) { /* the conditions and stages read the whole's clock */
      w->step = ws->step;
      w->time = ws->time;
    }
    /* A run-until check, a stage start or a pour batch here: every process takes the serial
     * decision on the whole (assembled on each), and changes it alike. */
    bool decide = ws != w && (adem_stages_until_next(c, s - 1) == s ||
                              adem_stages_next_step(c, s - 1) == s);
    if (decide) st = split_assemble(c, rs, true, err);
    if (st) break;
    /* Conditions first: a run that ends here writes this step's outputs as its last; a stage
     * that ends lets the next begin here (after the outputs, as any stage start). */
    adem_until_outcome until = adem_stages_until(c, why, sizeof why);
    if (until != ADEM_UNTIL_NOTHING)
      adem_log(ADEM_LOG_INFO, "t = %.9g s (step %llu): %s", w->time, (unsigned long long)s, why);
    ended = until == ADEM_UNTIL_RUN_ENDS;
    bool last = s >= total || ended;
    bool ckpt_due = last || due(s, k_ckpt);
    /* frames in pieces need the whole only for the mesh frame */
    bool frame_whole = due(s, k_frame) && !(c->output.pieces && w->walls.mesh.ntris == 0 &&
                                            !c->output.contacts_every);
    if (ws != w && !decide && (ckpt_due || frame_whole || due(s, k_csv)))
      st = split_assemble(c, rs, false, err);
    if (!st && (last || due(s, k_frame))) st = write_frame(&out, c, rs, &frame_no, err);
    if (!st && rs->writer) {
      if (due(s, k_frame)) c->frames_written = out.next_frame;
      if (last || due(s, k_csv)) st = csv_row(&out, c, &rc, err);
    }
    st = split_agree(rs, st, err);
    c->csv_last_extra = last && !due(s, k_csv);
    /* Stage starts and pour batches follow the outputs of their step and precede its
     * checkpoint, the last step's too: a resumed run, even one given a later end, finds them
     * done. */
    if (!st) {
      int stage_before = adem_stages_current(c);
      size_t n_before = w->p.n;
      st = adem_stages_events(c, err);
      /* (split, they come at `decide` steps only, on the whole assembled everywhere) */
      if (rs->many && (adem_stages_current(c) != stage_before || w->p.n != n_before)) stale = true;
      k_frame = periods[0] = adem_schedule_period(c->output.frame_interval, dt);
      k_csv = periods[1] = adem_schedule_period(c->output.csv_interval, dt);
      k_ckpt = periods[2] = adem_schedule_period(c->output.checkpoint_interval, dt);
    }
    if (!st && ckpt_due) {
      if (rs->writer) st = adem_checkpoint_write(c, ckpt_path, err);
      st = split_agree(rs, st, err);
      if (!st) {
        have_ckpt = true;
        t_ckpt = ws->time;
      }
    }
    if (st) break;

    double now = wall_now();
    if (rs->writer && (now - last_report >= RUN_PROGRESS_SECONDS || last)) {
      report(&opt, c, total, t0, &eta, last);
      last_report = now;
    }
    if (!last && split_any(rs, opt.stop_flag && *opt.stop_flag)) {
      if (!(have_ckpt && t_ckpt == ws->time)) {
        if (ws != w) st = split_assemble(c, rs, false, err);
        if (!st && rs->writer) st = adem_checkpoint_write(c, ckpt_path, err);
        st = split_agree(rs, st, err);
      }
      if (!st)
        st = adem_error_set(err, ADEM_INTERRUPTED,
                            "stopped at t = %.9g s (step %llu of %llu); checkpoint written to %s",
                            ws->time, (unsigned long long)ws->step, (unsigned long long)total,
                            ckpt_path);
      break;
    }
  }
  if (rs->writer) adem_output_close(&out);
  region_columns_free(&rc);
  if (rs->writer && (!st || st == ADEM_INTERRUPTED)) adem_outlets_log(c);
  /* The plots of what the CSV holds, however the run ended: done, stopped by a signal, or
   * failed (they show how it went wrong). A plot that fails then is a warning only. */
  if (rs->writer && (!st || st == ADEM_INTERRUPTED || st == ADEM_ERR_RUNTIME)) {
    adem_error perr = {ADEM_OK, ""};
    adem_status pst = write_plots(c, dir, &perr);
    if (pst && !st) {
      st = pst;
      if (err) *err = perr;
    } else if (pst) {
      adem_log(ADEM_LOG_WARN, "%s", perr.message);
    }
  }
  free(ckpt_path);
  return st;
}
