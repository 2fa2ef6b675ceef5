/* Fields of a run's output folder: the particle frames of particles.pvd in a time window, each
 * with its contact frame of contacts.pvd (the same frame index), averaged (adem/fields.h). */
#include <math.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "adem/fields.h"
#include "adem/frames.h"
#include "adem/world.h"
#include "adem/files.h"

adem_fields_run_options adem_fields_default_run_options(void) {
  adem_fields_run_options o;
  memset(&o, 0, sizeof o);
  o.grid = adem_fields_default_options();
  o.width_diameters = 1.0;
  o.t0 = 0.0;
  o.t1 = -1.0;
  return o;
}

/* A collection's entries: frame index (from the file name) and time. */
typedef struct entry {
  long index;
  double time;
  char file[96];
} entry;

/* Reads the DataSet lines of DIR/NAME whose file is frames/PREFIX_NNNNNN.EXT. */
static adem_status read_pvd(const char *dir, const char *name, const char *prefix, entry **out,
                            size_t *n, adem_error *err) {
  *out = NULL;
  *n = 0;
  char *path = adem_file_join(dir, name);
  if (!path) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  char *text = NULL;
  size_t len = 0;
  adem_status st = adem_file_read_all(path, &text, &len, err);
  if (st) {
    st = adem_error_set(err, ADEM_ERR_INPUT, "cannot read %s%s", path,
                        strcmp(name, "contacts.pvd") ? "" : " (run the case with output.contacts: true)");
    free(path);
    return st;
  }
  free(path);
  size_t cap = 0;
  entry *e = NULL;
  char want[64];
  snprintf(want, sizeof want, "file=\"frames/%s_", prefix);
  for (char *line = text; line && *line;) {
    char *next = strchr(line, '\n');
    if (next) *next++ = '\0';
    const char *ts = strstr(line, "timestep=\""), *fl = strstr(line, want);
    if (ts && fl) {
      if (*n == cap) {
        cap = cap ? 2 * cap : 64;
        entry *q = realloc(e, cap * sizeof *q);
        if (!q) {
          free(e);
          free(text);
          return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
        }
        e = q;
      }
      entry *x = &e[*n];
      x->time = strtod(ts + 10, NULL);
      x->index = strtol(fl + strlen(want), NULL, 10);
      size_t nl = strcspn(fl + 6, "\"");
      if (nl < sizeof x->file) {
        memcpy(x->file, fl + 6, nl);
        x->file[nl] = '\0';
        (*n)++;
      }
    }
    line = next;
  }
  free(text);
  *out = e;
  return ADEM_OK;
}

/* The frames of the window: particle entry k and its contact entry. */
typedef struct pick {
  const entry *p, *c;
} pick;

static adem_status load(const char *dir, const pick *pk, adem_vtu_frame *fr,
                        adem_contact_frame *cf, adem_error *err) {
  char *pp = adem_file_join(dir, pk->p->file), *cp = adem_file_join(dir, pk->c->file);
  adem_status st = pp && cp ? ADEM_OK : adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  if (!st && strstr(pk->p->file, ".pvtu"))
    st = adem_error_set(err, ADEM_ERR_INPUT, "%s: frames in pieces (output.pieces) are not read; run "
                                             "without output.pieces for the fields",
                        pp);
  if (!st) st = adem_vtu_read_file(pp, fr, err);
  if (!st && !fr->mass)
    st = adem_error_set(err, ADEM_ERR_INPUT, "%s has no mass array (written by an adem older than the "
                                             "fields): run the case again",
                        pp);
  if (!st && !fr->id) st = adem_error_set(err, ADEM_ERR_INPUT, "%s has no id array", pp);
  if (!st) st = adem_contact_frame_read_file(cp, cf, err);
  free(pp);
  free(cp);
  return st;
}

adem_status adem_fields_run(const char *dir, const adem_fields_run_options *opt_in,
                            adem_fields **out, adem_fields_run_info *info, adem_error *err) {
  *out = NULL;
  adem_fields_run_options opt = *opt_in;
  memset(info, 0, sizeof *info);
  entry *pe = NULL, *ce = NULL;
  size_t np = 0, nc = 0;
  adem_status st = read_pvd(dir, "particles.pvd", "particles", &pe, &np, err);
  if (!st) st = read_pvd(dir, "contacts.pvd", "contacts", &ce, &nc, err);
  pick *pk = st ? NULL : malloc((np ? np : 1) * sizeof *pk);
  if (!st && !pk) st = adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  size_t m = 0;
  bool all = opt.t1 < opt.t0;
  for (size_t k = 0; !st && k < np; ++k) {
    if (!all && !(pe[k].time >= opt.t0 && pe[k].time <= opt.t1)) continue;
    const entry *c = NULL;
    for (size_t q = 0; q < nc && !c; ++q)
      if (ce[q].index == pe[k].index) c = &ce[q];
    if (!c) continue; /* a particle frame without contacts (output.contacts_every) */
    pk[m++] = (pick){&pe[k], c};
  }
  if (!st && m == 0)
    st = adem_error_set(err, ADEM_ERR_INPUT, "%s: no particle frame with a contact frame %s%.6g .. %.6g s "
                                             "(%zu particle frames, %zu contact frames)",
                        dir, all ? "(any time) " : "in ",
                        all ? 0.0 : opt.t0, all ? 0.0 : opt.t1, np, nc);
  if (!st && opt.last_only) {
    pk[0] = pk[m - 1];
    m = 1;
  }
  /* pass 1: the width from the mean diameter and the grid's extent */
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  double elo[3] = {INFINITY, INFINITY, INFINITY}, ehi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (size_t k = 0; k < m && !st; ++k) {
    adem_vtu_frame fr;
    adem_contact_frame cf;
    st = load(dir, &pk[k], &fr, &cf, err);
    if (st) break;
    if (k == 0) {
      double s = 0.0;
      for (size_t i = 0; i < fr.n; ++i) s += 2.0 * fr.radius[i];
      info->mean_diameter = fr.n ? s / (double)fr.n : 0.0;
    }
    for (size_t i = 0; i < fr.n; ++i) {
      double x[3] = {fr.pos[i].x, fr.pos[i].y, fr.pos[i].z};
      for (int a = 0; a < 3; ++a) {
        lo[a] = fmin(lo[a], x[a]);
        hi[a] = fmax(hi[a], x[a]);
        elo[a] = fmin(elo[a], x[a] - fr.radius[i]);
        ehi[a] = fmax(ehi[a], x[a] + fr.radius[i]);
      }
    }
    adem_vtu_frame_free(&fr);
    adem_contact_frame_free(&cf);
  }
  if (!st && opt.width_diameters > 0.0) {
    if (!(info->mean_diameter > 0.0))
      st = adem_error_set(err, ADEM_ERR_INPUT, "the first frame has no particle to take a diameter from");
    opt.grid.width = opt.width_diameters * info->mean_diameter;
  }
  if (!st && opt.cell_diameters > 0.0) opt.grid.cell = opt.cell_diameters * info->mean_diameter;
  else if (!st && !(opt.grid.cell > 0.0)) opt.grid.cell = 0.5 * opt.grid.width;
  if (!st && !opt.box_given) {
    double reach = (opt.grid.kernel == ADEM_KERNEL_LUCY ? sqrt(12.0) : opt.grid.cutoff) *
                   opt.grid.width;
    for (int a = 0; a < 3; ++a) {
      if (!(lo[a] <= hi[a])) {
        st = adem_error_set(err, ADEM_ERR_INPUT, "no particle in the frames used");
        break;
      }
      if (opt.grid.average[a]) {
        opt.grid.lo[a] = elo[a];
        opt.grid.hi[a] = ehi[a];
      } else { /* a reach and a cell beyond the centres, on cells from the lowest */
        opt.grid.lo[a] = lo[a] - reach - opt.grid.cell;
        opt.grid.hi[a] = hi[a] + reach + opt.grid.cell;
      }
    }
  }
  adem_fields *f = NULL;
  if (!st) st = adem_fields_create(&opt.grid, &f, err);
  /* pass 2: the fields */
  for (size_t k = 0; k < m && !st; ++k) {
    adem_vtu_frame fr;
    adem_contact_frame cf;
    st = load(dir, &pk[k], &fr, &cf, err);
    if (st) break;
    adem_fields_particles P = {fr.n, (const double *)fr.pos, (const double *)fr.velocity, fr.mass,
                               fr.radius, fr.id};
    adem_fields_contacts C = {cf.n, (const double *)cf.p0, (const double *)cf.p1,
                              (const double *)cf.force, cf.kind, cf.id_a, cf.id_b};
    st = adem_fields_add(f, &P, &C, err);
    if (!st) {
      if (k == 0) info->t_first = pk[k].p->time;
      info->t_last = pk[k].p->time;
      info->particles = fr.n;
      info->contacts = cf.n;
      info->mass = 0.0;
      for (size_t i = 0; i < fr.n; ++i) info->mass += fr.mass[i];
      info->frames++;
    }
    adem_vtu_frame_free(&fr);
    adem_contact_frame_free(&cf);
  }
  if (!st) info->width = opt.grid.width;
  free(pe);
  free(ce);
  free(pk);
  if (st) {
    adem_fields_free(f);
    return st;
  }
  *out = f;
  return ADEM_OK;
}

/* ---------------------------------------------------------------- a live world */

adem_status adem_fields_add_world(adem_fields *f, const adem_world *w, adem_error *err) {
  size_t n = adem_world_particle_count(w);
  size_t cap = n ? n : 1;
  double *pos = malloc(3 * cap * sizeof *pos), *vel = malloc(3 * cap * sizeof *vel);
  double *mass = malloc(cap * sizeof *mass), *radius = malloc(cap * sizeof *radius);
  uint64_t *uid = malloc(cap * sizeof *uid);
  int64_t *id = malloc(cap * sizeof *id);
  adem_status st = ADEM_OK;
  if (!pos || !vel || !mass || !radius || !uid || !id)
    st = adem_error_set(err, ADEM_ERR_NOMEM, "out of memory for %zu particles", n);
  if (!st) st = adem_world_get_particles(w, ADEM_FIELD_POSITION, pos, 3 * n, err);
  if (!st) st = adem_world_get_particles(w, ADEM_FIELD_VELOCITY, vel, 3 * n, err);
  if (!st) st = adem_world_get_particles(w, ADEM_FIELD_MASS, mass, n, err);
  if (!st) st = adem_world_get_particles(w, ADEM_FIELD_RADIUS, radius, n, err);
  if (!st) st = adem_world_get_ids(w, uid, n, err);
  for (size_t i = 0; !st && i < n; ++i) id[i] = (int64_t)uid[i];
  adem_contact_frame cf = {0};
  if (!st) st = adem_world_contact_frame(w, &cf, err);
  if (!st) {
    adem_fields_particles P = {n, pos, vel, mass, radius, id};
    adem_fields_contacts C = {cf.n, (const double *)cf.p0, (const double *)cf.p1,
                              (const double *)cf.force, cf.kind, cf.id_a, cf.id_b};
    st = adem_fields_add(f, &P, &C, err);
  }
  adem_contact_frame_free(&cf);
  free(pos), free(vel), free(mass), free(radius), free(uid), free(id);
  return st;
}

size_t adem_fields_abi_sizeof(const char *type) {
  if (!strcmp(type, "adem_fields_options")) return sizeof(adem_fields_options);
  if (!strcmp(type, "adem_fields_run_options")) return sizeof(adem_fields_run_options);
  if (!strcmp(type, "adem_fields_run_info")) return sizeof(adem_fields_run_info);
  return 0;
}
