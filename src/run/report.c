/* `adem check`: what a loaded and prepared case will do, as text. */
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "adem/adem.h"
#include "insert.h"
#include "log.h"
#include "schedule.h"
#include "stages.h"
#include "world.h"

static double mib(double bytes) { return bytes / (1024.0 * 1024.0); }


/* What a JKR pair implies, at its smallest spheres (notes sections 1, 5, 6; H section 6.2). */
static void print_jkr(FILE *f, const adem_world *w, int a, int b, bool wall, const double *rmin,
                      double v_ref) {
  const adem_interaction *it = adem_world_interaction(w, a, b);
  if (it->normal != ADEM_NORMAL_JKR) return;
  const char *pad = "";
  if (!(it->pp.gamma_real > 0.0)) {
    fprintf(f, "  %-26s jkr without surface energy: the contact is Hertz\n", pad);
    return;
  }
  double ra = rmin[a], ma = w->mat.m[a].def.density * (4.0 / 3.0) * ADEM_PI * ra * ra * ra;
  double R = ra, mstar = ma;
  if (!wall) {
    double rb = rmin[b], mb = w->mat.m[b].def.density * (4.0 / 3.0) * ADEM_PI * rb * rb * rb;
    R = ra * rb / (ra + rb);
    mstar = ma * mb / (ma + mb);
  }
  adem_jkr_pair_summary s =
      adem_jkr_pair_summarize(it->pp.E_real, it->pp.E, it->pp.gamma_real, it->pp.gamma, R, mstar, v_ref);
  char mod[64];
  snprintf(mod, sizeof mod, "modified (E_mod/E = %.3g)", it->pp.E / it->pp.E_real);
  fprintf(f, "  %-26s simplified JKR (H7-H10) for the smallest spheres: R* = %.4g m, m* = %.4g kg\n",
         pad, R, mstar);
  fprintf(f, "  %-26s   %-36s %-12s %s\n", pad, "", "real", mod);
  const struct {
    const char *label;
    double real, modified;
  } rows[] = {
      {"E* (Pa)", s.E, s.E_mod},
      {"gamma (J/m^2)", s.gamma, s.gamma_mod},
      {"a0 = (9 pi gamma R^2/E)^(1/3) (m)", s.a0, s.a0_mod},
      {"delta_eq = a0^2/(3R) (m)", s.delta_eq, s.delta_eq_mod},
      {"F_C = 3 pi gamma R (N)", s.f_c, s.f_c_mod},
      {"pull-off force (8/9) F_C (N)", s.pull_off, s.pull_off_mod},
      {"Hertz t_c at v_ref (s)", s.t_c, s.t_c_mod},
      {"time step t_c/50 (s)", s.dt, s.dt_mod},
  };
  for (size_t k = 0; k < sizeof rows / sizeof rows[0]; ++k)
    fprintf(f, "  %-26s   %-36s %-12.4g %.4g\n", pad, rows[k].label, rows[k].real, rows[k].modified);
  fprintf(f, "  %-26s   step speed-up (E/E_mod)^(2/5) = %.4g\n", pad, s.speedup);
  fprintf(f, "  %-26s   Tabor parameter lambda_T = %.3g (real material, D_min = 1.65e-10 m)%s\n", pad,
         s.tabor, s.tabor < 3.0 ? ": below 3, JKR is outside its range (H1)" : ", JKR valid (> 3)");
  fprintf(f, "  %-26s   external forces pulling these spheres apart must stay below %.3g N (%.0f%% "
         "of the modified pull-off force)\n",
         pad, s.f_ext_max, 100.0 * ADEM_PULLOFF_SAFETY);
  if (s.tabor < 3.0) {
    fflush(f);
    adem_log(ADEM_LOG_WARN,
             "%s-%s%s: Tabor parameter %.3g is below 3: the JKR model is outside its range (H1); "
             "the contact is closer to DMT/Maugis",
             w->mat.m[a].def.name, w->mat.m[b].def.name, wall ? " (wall)" : "", s.tabor);
  }
}

/* The rolling friction eta_r a pair's rolling law uses (the rule of the rolling_friction row in
 * adem/laws.h): BROF's e_c = min(eta_i r_i, eta_j r_j), models A and C the mean eta_r with
 * R_r = r_i r_j/(r_i + r_j); on a wall the particle's eta_r with r_i, the wall material's unused;
 * an interaction entry's value replaces both sides'. */
static void print_rolling_friction(FILE *f, const adem_world *w, int a, int b, bool wall) {
  const adem_interaction *it = adem_world_interaction(w, a, b);
  const adem_law *law = adem_law_get(ADEM_SLOT_ROLLING, (int)it->rolling);
  if (!law || !adem_law_reads(law, "rolling_friction")) return;
  const int k = ADEM_PARAM_ROLLING_FRICTION;
  double ea = it->pp.param_a[k], eb = it->pp.param_b[k];
  const char *na = w->mat.m[a].def.name, *nb = w->mat.m[b].def.name;
  bool brof = it->rolling == ADEM_ROLLING_BROF;
  char from[2 * ADEM_NAME_MAX + 96];
  if (it->set_param[k])
    snprintf(from, sizeof from, "the interaction entry's value, for both sides");
  else if (wall)
    snprintf(from, sizeof from, "`%s`'s value; the wall material `%s`'s (%g) is not used", na, nb,
             w->mat.m[b].def.param[k]);
  else if (a == b)
    snprintf(from, sizeof from, "`%s`'s value", na);
  else
    snprintf(from, sizeof from, "`%s`'s and `%s`'s values", na, nb);
  if (wall)
    fprintf(f, "  %-26s rolling friction eta_r = %g, e_c = %g r_i (%s)\n", "", ea, ea, from);
  else if (brof)
    fprintf(f, "  %-26s rolling friction e_c = min(%g r_i, %g r_j) (BROF, I9: %s)\n", "", ea, eb,
            from);
  else
    fprintf(f, "  %-26s rolling friction eta_r = %g%s, R_r = r_i r_j/(r_i + r_j) (%s)\n", "",
            0.5 * (ea + eb), ea == eb ? "" : " (the mean)", from);
}

static void print_pair(FILE *f, const adem_world *w, int a, int b, bool wall, const double *rmin,
                       const double *rmax, double v_ref) {
  const adem_interaction *it = adem_world_interaction(w, a, b);
  double Rlo, Rhi;
  if (wall) {
    Rlo = rmin[a];
    Rhi = rmax[a];
  } else {
    Rlo = rmin[a] * rmin[b] / (rmin[a] + rmin[b]);
    Rhi = rmax[a] * rmax[b] / (rmax[a] + rmax[b]);
  }
  char name[2 * ADEM_NAME_MAX + 16];
  snprintf(name, sizeof name, "%s-%s%s", w->mat.m[a].def.name, w->mat.m[b].def.name,
           wall ? " (wall)" : "");
  char R[64];
  if (Rlo == Rhi) snprintf(R, sizeof R, "%.4g", Rlo);
  else snprintf(R, sizeof R, "%.4g..%.4g", Rlo, Rhi);
  fprintf(f, "  %-26s %-11.4g %-11.4g %-21s %-6.3g %-9.4g %-6.3g %-6s %s\n", name, it->pp.E, it->pp.G, R,
         it->pp.restitution, it->pp.beta, it->pp.friction, adem_law_get(ADEM_SLOT_NORMAL, (int)it->normal)->name,
         adem_law_get(ADEM_SLOT_ROLLING, (int)it->rolling)->name);
  if (it->pp.E != it->pp.E_real)
    fprintf(f, "  %-26s real material: E* = %.4g Pa, G* = %.4g Pa (stiffness reduced, H24)\n", "",
           it->pp.E_real, it->pp.G_real);
  print_rolling_friction(f, w, a, b, wall);
  if (it->set_restitution || it->set_friction)
    fprintf(f, "  %-26s %s from the interaction entry (not the materials' mean)\n", "",
            !it->set_friction ? "e" : !it->set_restitution ? "mu" : "e and mu");
  print_jkr(f, w, a, b, wall, rmin, v_ref);
}

adem_status adem_case_report(const adem_case *c, FILE *f, adem_error *err) {
  const adem_world *w = c->world;
  const adem_particles *p = &w->p;
  int nm = w->mat.n;
  double *rmin = malloc((size_t)(nm > 0 ? nm : 1) * sizeof *rmin);
  double *rmax = malloc((size_t)(nm > 0 ? nm : 1) * sizeof *rmax);
  bool *wallmat = calloc((size_t)(nm > 0 ? nm : 1), sizeof *wallmat);
  if (!rmin || !rmax || !wallmat) {
    free(rmin);
    free(rmax);
    free(wallmat);
    return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  }
  for (int k = 0; k < nm; ++k) {
    rmin[k] = INFINITY;
    rmax[k] = 0.0;
  }
  double rlo = INFINITY, rhi = 0.0, mass = 0.0;
  for (size_t i = 0; i < p->n; ++i) {
    int m = p->material[i];
    rmin[m] = fmin(rmin[m], p->radius[i]);
    rmax[m] = fmax(rmax[m], p->radius[i]);
    rlo = fmin(rlo, p->radius[i]);
    rhi = fmax(rhi, p->radius[i]);
    mass += 1.0 / p->inv_mass[i];
  }
  for (int k = 0; c->pours && k < c->pours->n; ++k) { /* poured spheres meet them too */
    const adem_pour *q = &c->pours->p[k];
    rmin[q->def.material] = fmin(rmin[q->def.material], adem_insert_dist_smallest(&q->def.dist));
    rmax[q->def.material] = fmax(rmax[q->def.material], adem_insert_dist_largest(&q->def.dist));
  }
  for (int k = 0; k < w->walls.nplanes; ++k) wallmat[w->walls.planes[k].def.material] = true;
  for (int k = 0; k < w->walls.mesh.ngroups; ++k) wallmat[w->walls.mesh.groups[k].material] = true;

  fprintf(f, "case        %s (%s)\n", c->name, c->path);
  if (p->n)
    fprintf(f, "particles   %zu, radius %.4g..%.4g m, total mass %.4g kg\n", p->n, rlo, rhi, mass);
  else
    fprintf(f, "particles   none at the start\n");
  fprintf(f, "walls       %d plane%s", w->walls.nplanes, w->walls.nplanes == 1 ? "" : "s");
  for (int k = 0; k < w->walls.nplanes && k < 12; ++k)
    fprintf(f, "%s%s", k ? ", " : ": ", w->walls.planes[k].def.name);
  fprintf(f, "%s\n", w->walls.nplanes > 12 ? ", ..." : "");
  if (w->walls.mesh.ngroups > 0) {
    fprintf(f, "meshes      %zu triangles in %d group%s", w->walls.mesh.ntris, w->walls.mesh.ngroups,
           w->walls.mesh.ngroups == 1 ? "" : "s");
    for (int k = 0; k < w->walls.mesh.ngroups && k < 12; ++k)
      fprintf(f, "%s%s", k ? ", " : ": ", w->walls.mesh.groups[k].name);
    fprintf(f, "%s\n", w->walls.mesh.ngroups > 12 ? ", ..." : "");
  }
  for (int k = 0; c->pours && k < c->pours->n; ++k) {
    const adem_pour *q = &c->pours->p[k];
    static const char *const shapes[] = {"box", "cylinder", "mesh"};
    fprintf(f, "pour        %s: %.6g %s from t = %g to %g s into a %s, radius %.4g..%.4g m\n",
           q->def.name, adem_pour_total(q), q->def.rate > 0.0 ? "particles" : "kg", q->def.start,
           q->def.end, shapes[q->def.region.kind], adem_insert_dist_smallest(&q->def.dist),
           adem_insert_dist_largest(&q->def.dist));
  }
  for (int k = 0; c->stages && k < c->stages->n; ++k) {
    const adem_stage *g = &c->stages->s[k];
    double t0 = (double)adem_stages_start_step(c, k) * w->dt;
    fprintf(f, "stage %-5d %s: from t = %.6g s, %d change%s\n", k + 1, g->name, t0, g->nsets,
           g->nsets == 1 ? "" : "s");
  }
  fprintf(f, "gravity     (%g, %g, %g) m/s^2\n", w->gravity.x, w->gravity.y, w->gravity.z);
  fprintf(f, "contacts    %zu particle pairs and %zu wall pairs within reach at the start\n",
         w->pp.n, w->pw.n);

  fprintf(f, "\nmaterial pairs (effective values: E*, G* from H2 and H15, R* = r_i r_j/(r_i+r_j), "
         "beta from H12)\n");
  fprintf(f, "  %-26s %-11s %-11s %-21s %-6s %-9s %-6s %-6s %s\n", "pair", "E* (Pa)", "G* (Pa)",
         "R* (m)", "e", "beta", "mu", "normal", "rolling");
  for (int a = 0; a < nm; ++a) {
    if (!(rmax[a] > 0.0)) continue;
    for (int b = a; b < nm; ++b)
      if (rmax[b] > 0.0) print_pair(f, w, a, b, false, rmin, rmax, c->estimate.v_ref);
    for (int b = 0; b < nm; ++b)
      if (wallmat[b]) print_pair(f, w, a, b, true, rmin, rmax, c->estimate.v_ref);
  }

  const adem_step_estimate *e = &c->estimate;
  double dt = w->dt;
  uint64_t total = adem_schedule_total_steps(c->end_time, dt);
  fprintf(f, "\ntime step (notes section 6)\n");
  fprintf(f, "  reference speed v_ref     %.4g m/s\n", e->v_ref);
  fprintf(f, "  Hertz collision time t_c  %.4g s\n", e->t_collision);
  fprintf(f, "  Rayleigh time t_R         %.4g s\n", e->t_rayleigh);
  fprintf(f, "  proposed step             %.4g s = min(t_c/50, 0.2 t_R)\n", e->dt);
  if (c->dt_auto)
    fprintf(f, "  chosen step               %.4g s (auto)\n", dt);
  else
    fprintf(f, "  chosen step               %.4g s (time.step: %.3g times the proposed one)%s\n", dt,
           c->dt_user_ratio, c->dt_user_ratio > 1.0 ? " -- larger than proposed" : "");
  fprintf(f, "  end time                  %.6g s: %llu steps\n", c->end_time, (unsigned long long)total);

  const adem_output_settings *os = &c->output;
  uint64_t kf = adem_schedule_period(os->frame_interval, dt);
  uint64_t kc = adem_schedule_period(os->csv_interval, dt);
  uint64_t kk = adem_schedule_period(os->checkpoint_interval, dt);
  uint64_t nframes = adem_schedule_count(kf, total), nrows = adem_schedule_count(kc, total);
  fprintf(f, "\noutput in %s\n", os->dir);
  if (kf) fprintf(f, "  frames       every %.4g s (%llu steps): %llu frames\n", os->frame_interval,
                 (unsigned long long)kf, (unsigned long long)nframes);
  else fprintf(f, "  frames       off\n");
  if (kc) fprintf(f, "  CSV rows     every %.4g s (%llu steps): %llu rows\n", os->csv_interval,
                 (unsigned long long)kc, (unsigned long long)nrows);
  else fprintf(f, "  CSV rows     off\n");
  if (kk) fprintf(f, "  checkpoints  every %.4g s (%llu steps), on Ctrl-C and at the end\n",
                 os->checkpoint_interval, (unsigned long long)kk);
  else fprintf(f, "  checkpoints  on Ctrl-C and at the end\n");
  fprintf(f, "  energy plot  %s\n", os->plot ? "yes (gnuplot)" : "no");

  /* Bytes per particle and per candidate pair, from the field tables (particles.h, pairs.h). */
  double per_particle = (double)adem_world_bytes_per_particle();
  double per_pair = (double)adem_world_bytes_per_pair();
  double memory = (double)p->n * per_particle + (double)(w->pp.n + w->pw.n) * per_pair + (double)w->nb.ncells * sizeof(size_t);
  double frame = 1500.0 + (double)p->n * (8 + 8 + 4 + 4 * 24 + 8 + 8 + 1);
  double row = (9.0 + 3.0 * w->walls.nplanes) * 24.0;
  double ckpt = (double)strlen(c->source) + (double)p->n * (6 * 24 + 3 * 8 + 8 + 4) +
                (double)(w->pp.n + w->pw.n) * per_pair;
  fprintf(f, "\nestimates\n");
  fprintf(f, "  memory       %.1f MiB at the start (%zu particles, %zu candidate pairs; grows with "
         "the number of contacts)\n", mib(memory), p->n, w->pp.n + w->pw.n);
  fprintf(f, "  disk         %.1f MiB: frames %llu x %.2f MiB, CSV %.2f MiB, checkpoint %.2f MiB\n",
         mib((double)nframes * frame + (double)nrows * row + ckpt), (unsigned long long)nframes,
         mib(frame), mib((double)nrows * row), mib(ckpt));
  free(rmin);
  free(rmax);
  free(wallmat);
  return ADEM_OK;
}
