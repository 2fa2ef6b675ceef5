/* Output: the run's CSV, a row per interval of the energies, wall loads and motions, tracked
 * particles and regions (output.h), and its plots. */
#include "output.h"
#include "adem/internal/plot.h"
#include "vtu.h"

#include <errno.h>
#include <fcntl.h>
#include <inttypes.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "log.h"
#include "world_internal.h"
#include "cylinder.h"

/* ---------------------------------------------------------------- CSV */

/* Growing string for rows and headers. */
typedef struct strbuf {
  char *s;
  size_t n, cap;
  int failed;
} strbuf;

static void sb_printf(strbuf *b, const char *fmt, ...) ADEM_PRINTF(2, 3);
static void sb_printf(strbuf *b, const char *fmt, ...) {
  if (b->failed) return;
  for (;;) {
    va_list ap;
    va_start(ap, fmt);
    int m = vsnprintf(b->s ? b->s + b->n : NULL, b->s ? b->cap - b->n : 0, fmt, ap);
    va_end(ap);
    if (m < 0) {
      b->failed = 1;
      return;
    }
    if (b->s && b->n + (size_t)m < b->cap) {
      b->n += (size_t)m;
      return;
    }
    size_t cap = b->cap ? b->cap : 256;
    while (cap <= b->n + (size_t)m) cap *= 2;
    char *s = realloc(b->s, cap);
    if (!s) {
      b->failed = 1;
      return;
    }
    b->s = s;
    b->cap = cap;
  }
}

static char *sb_finish(strbuf *b) {
  if (b->failed) {
    free(b->s);
    return NULL;
  }
  return b->s;
}

/* A wall's name as the start of CSV column names: one CSV field per column, and names that
 * numpy's genfromtxt(names=True) keeps (it drops every character but letters, digits and `_`):
 * the dot of a mesh group or a box's plane (`hopper.funnel`, `box.xmin`) becomes `__`. */
static void csv_field_name(char *buf, size_t n, const char *name) {
  size_t k = 0;
  for (const char *c = name; *c && k + 2 < n; ++c) {
    if (*c == '.') {
      buf[k++] = '_';
      buf[k++] = '_';
    } else {
      buf[k++] = (*c == ',' || *c == '"' || *c == '\n' || *c == '\r' || *c == ' ') ? '_' : *c;
    }
  }
  if (n) buf[k < n ? k : n - 1] = '\0';
}

/* Mesh loads: force and torque on every group, then on every file with several groups (a file
 * of one group would repeat its columns). */

static void mesh_csv_header(strbuf *b, const adem_world *w) {
  char name[2 * ADEM_NAME_MAX];
  for (int g = 0; g < w->walls.mesh.ngroups + w->walls.nmesh_walls; ++g) {
    bool group = g < w->walls.mesh.ngroups;
    const adem_mesh_wall *mw = group ? NULL : &w->walls.mesh_walls[g - w->walls.mesh.ngroups];
    if (mw && mw->count < 2) continue;
    csv_field_name(name, sizeof name, group ? w->walls.mesh.groups[g].name : mw->name);
    sb_printf(b, ",%s_fx_N,%s_fy_N,%s_fz_N,%s_tx_Nm,%s_ty_Nm,%s_tz_Nm", name, name, name, name,
              name, name);
  }
}

static void mesh_csv_row(strbuf *b, const adem_world *w) {
  size_t ng = (size_t)w->walls.mesh.ngroups, nw = (size_t)w->walls.nmesh_walls;
  if (ng == 0) return;
  adem_vec3 *f = malloc(2 * (ng + nw) * sizeof *f);
  if (!f) {
    b->failed = 1;
    return;
  }
  adem_vec3 *t = f + ng + nw;
  adem_world_mesh_loads(w, f, t, f + ng, t + ng);
  for (size_t k = 0; k < ng + nw; ++k) {
    if (k >= ng && w->walls.mesh_walls[k - ng].count < 2) continue;
    sb_printf(b, ",%.17g,%.17g,%.17g,%.17g,%.17g,%.17g", f[k].x, f[k].y, f[k].z, t[k].x, t[k].y,
              t[k].z);
  }
  free(f);
}

/* Walls that move or have a servo in some configuration of the run (ADEM_WALL_CSV_*): the
 * displacement of their reference point since their motion began, and the servo's displacement
 * and measured force. After the loads, so that the loads' columns keep their places. */
static void motion_csv_header(strbuf *b, const adem_world *w) {
  char name[2 * ADEM_NAME_MAX];
  int np = w->walls.nplanes;
  for (int k = 0; k < np + w->walls.nmesh_walls; ++k) {
    uint8_t csv = k < np ? w->walls.planes[k].csv : w->walls.mesh_walls[k - np].csv;
    if (!csv) continue;
    csv_field_name(name, sizeof name,
                   k < np ? w->walls.planes[k].def.name : w->walls.mesh_walls[k - np].name);
    if (!name[0]) snprintf(name, sizeof name, "plane%d", k);
    sb_printf(b, ",%s_ux_m,%s_uy_m,%s_uz_m", name, name, name);
    if (csv & ADEM_WALL_CSV_SERVO) sb_printf(b, ",%s_servo_u_m,%s_servo_F_N", name, name);
    sb_printf(b, ",%s_drive_power_W", name);
    if (k >= np) sb_printf(b, ",%s_axis_torque_Nm", name);
  }
}

/* What driving a moving wall costs: the power its motion puts into the particles,
 * -(F . v_ref + T_ref . omega), F and T_ref the particles' force and torque on it (a mesh wall:
 * summed over its groups, each about its reference point), and the particles' torque about its
 * rotation axis through the axis's point now (0 while it does not turn); a drive holds the wall
 * on its path against them. A plane's torque is not summed: its power is that of its
 * translation, and NaN while it turns. */
static void drive_load(const adem_world *w, int k, const adem_vec3 *gf, const adem_vec3 *gt,
                       const adem_vec3 *pf, double *power, double *axis_torque) {
  const adem_walls *wl = &w->walls;
  int np = wl->nplanes;
  *power = *axis_torque = 0.0;
  if (k < np) {
    const adem_motion *m = &wl->planes[k].motion;
    *power = m->omega != 0.0 ? NAN : -v3_dot(pf[k], adem_motion_velocity(m, wl->time));
    return;
  }
  const adem_mesh_wall *mw = &wl->mesh_walls[k - np];
  for (int g = mw->first; g < mw->first + mw->count; ++g) {
    const adem_motion *m = &wl->mesh_motion[g];
    adem_vec3 spin = v3_scale(m->axis, m->omega);
    *power -= v3_dot(gf[g], adem_motion_point_velocity(m, wl->time, wl->mesh_ref[g])) +
              v3_dot(gt[g], spin);
    if (m->omega == 0.0) continue;
    adem_vec3 c = v3_add(m->center, adem_motion_displacement(m, wl->time));
    *axis_torque += v3_dot(v3_add(gt[g], v3_cross(v3_sub(wl->mesh_ref[g], c), gf[g])), m->axis);
  }
}

static void motion_csv_row(strbuf *b, const adem_world *w) {
  int np = w->walls.nplanes;
  size_t ng = (size_t)w->walls.mesh.ngroups;
  adem_vec3 *gf = malloc((2 * ng + (size_t)np + 1) * sizeof *gf);
  if (!gf) {
    b->failed = 1;
    return;
  }
  adem_vec3 *gt = gf + ng, *pf = gf + 2 * ng;
  if (ng) adem_world_mesh_loads(w, gf, gt, NULL, NULL);
  if (np) adem_world_plane_forces(w, pf);
  for (int k = 0; k < np + w->walls.nmesh_walls; ++k) {
    uint8_t csv = k < np ? w->walls.planes[k].csv : w->walls.mesh_walls[k - np].csv;
    if (!csv) continue;
    adem_vec3 u = k < np ? adem_walls_plane_displacement(&w->walls, k)
                         : adem_walls_mesh_wall_displacement(&w->walls, k - np);
    sb_printf(b, ",%.17g,%.17g,%.17g", u.x, u.y, u.z);
    if (csv & ADEM_WALL_CSV_SERVO) {
      const adem_motion *m = k < np ? adem_walls_plane_servo(&w->walls, k)
                                    : adem_walls_mesh_wall_servo(&w->walls, k - np);
      /* a stage without the servo: no servo displacement, no measurement */
      if (m)
        sb_printf(b, ",%.17g,%.17g", m->servo_u, m->servo_force);
      else
        sb_printf(b, ",0,nan");
    }
    double power, torque;
    drive_load(w, k, gf, gt, pf, &power, &torque);
    sb_printf(b, ",%.17g", power);
    if (k >= np) sb_printf(b, ",%.17g", torque);
  }
  free(gf);
}

/* Cylinders and plates (core/cylinder.h): the torque of the particles on each about its point (a
 * cylinder: its axis point) and, for a cylinder, its component along the axis. After the motion
 * columns, so that the columns before keep their places. */
static void shape_csv_header(strbuf *b, const adem_world *w) {
  char name[2 * ADEM_NAME_MAX];
  for (int k = 0; k < w->walls.nplanes; ++k) {
    const adem_plane_def *d = &w->walls.planes[k].def;
    if (d->shape == ADEM_WALL_PLANE) continue;
    csv_field_name(name, sizeof name, d->name);
    if (!name[0]) snprintf(name, sizeof name, "plane%d", k);
    sb_printf(b, ",%s_tx_Nm,%s_ty_Nm,%s_tz_Nm", name, name, name);
    if (d->shape == ADEM_WALL_CYLINDER) sb_printf(b, ",%s_t_axis_Nm", name);
  }
}

static void shape_csv_row(strbuf *b, const adem_world *w, const adem_vec3 *t) {
  for (int k = 0; k < w->walls.nplanes; ++k) {
    const adem_plane_def *d = &w->walls.planes[k].def;
    if (d->shape == ADEM_WALL_PLANE) continue;
    sb_printf(b, ",%.17g,%.17g,%.17g", t[k].x, t[k].y, t[k].z);
    if (d->shape == ADEM_WALL_CYLINDER) sb_printf(b, ",%.17g", v3_dot(t[k], d->normal));
  }
}

char *adem_output_csv_header(const adem_world *w, const adem_output_track *track,
                             const adem_output_extra *extra) {
  strbuf b = {0};
  sb_printf(&b, "time_s,kinetic_J,rotational_J,potential_J,elastic_J,dissipated_J,wall_work_J,"
                "contacts_pp,contacts_pw,max_overlap_ratio");
  for (int k = 0; k < w->walls.nplanes; ++k) {
    /* Plane names come from the case file: keep the header one CSV field per column. */
    char name[2 * ADEM_NAME_MAX];
    csv_field_name(name, sizeof name, w->walls.planes[k].def.name);
    if (!name[0]) snprintf(name, sizeof name, "plane%d", k);
    sb_printf(&b, ",%s_fx_N,%s_fy_N,%s_fz_N", name, name, name);
  }
  mesh_csv_header(&b, w);
  motion_csv_header(&b, w);
  shape_csv_header(&b, w);
  for (int k = 0; track && k < track->n; ++k) {
    unsigned long long id = (unsigned long long)track->id[k];
    sb_printf(&b, ",p%llu_rolling_torque_x_Nm,p%llu_rolling_torque_y_Nm,p%llu_rolling_torque_z_Nm", id,
              id, id);
    sb_printf(&b, ",p%llu_omega_x_rad_s,p%llu_omega_y_rad_s,p%llu_omega_z_rad_s,p%llu_distance_m", id,
              id, id, id);
  }
  for (int k = 0; extra && k < extra->n; ++k) {
    char name[2 * ADEM_NAME_MAX + 16];
    csv_field_name(name, sizeof name, extra->name[k]);
    sb_printf(&b, ",%s", name);
  }
  sb_printf(&b, "\n");
  return sb_finish(&b);
}

char *adem_output_csv_row(const adem_world *w, const adem_output_track *track,
                          const adem_output_extra *extra) {
  adem_diagnostics d = adem_world_diagnostics(w);
  strbuf b = {0};
  /* %.17g: the times read back on resume compare exactly with the checkpoint's. */
  sb_printf(&b, "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%zu,%zu,%.17g", w->time, d.kinetic,
            d.rotational, d.potential, d.elastic, d.dissipated, d.wall_work, d.contacts_pp,
            d.contacts_pw, d.max_overlap_ratio);
  adem_vec3 *f = malloc((size_t)(w->walls.nplanes > 0 ? w->walls.nplanes : 1) * sizeof *f);
  if (!f) {
    free(b.s);
    return NULL;
  }
  adem_world_plane_forces(w, f);
  for (int k = 0; k < w->walls.nplanes; ++k) sb_printf(&b, ",%.17g,%.17g,%.17g", f[k].x, f[k].y, f[k].z);
  mesh_csv_row(&b, w);
  motion_csv_row(&b, w);
  adem_world_plane_torques(w, f); /* cylinders' and plates' torques */
  shape_csv_row(&b, w, f);
  free(f);
  const adem_particles *p = &w->p;
  for (int k = 0; track && k < track->n; ++k) {
    size_t i = 0; /* particles are reordered by cell: find the id (a few per row) */
    while (i < p->n && p->id[i] != track->id[k]) ++i;
    if (i == p->n) {
      sb_printf(&b, ",nan,nan,nan,nan,nan,nan,nan");
      continue;
    }
    adem_vec3 t = p->rolling_torque[i], o = p->omega[i];
    sb_printf(&b, ",%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g", t.x, t.y, t.z, o.x, o.y, o.z,
              p->path_length[i]);
  }
  for (int k = 0; extra && k < extra->n; ++k) sb_printf(&b, ",%.17g", extra->value[k]);
  sb_printf(&b, "\n");
  return sb_finish(&b);
}

/* ---------------------------------------------------------------- plot */

adem_status adem_output_plot_energy(const char *csv_path, const char *png_path, const char *title,
                                    adem_error *err) {
  size_t qn = 2 * (strlen(csv_path) + strlen(title)) + 8;
  char *qcsv = malloc(qn), *qtitle = malloc(qn);
  if (!qcsv || !qtitle) {
    free(qcsv);
    free(qtitle);
    return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  }
  strbuf b = {0};
  sb_printf(&b, "set title %s\nset xlabel 'time (s)'\nset ylabel 'energy (J)'\n"
                "set key outside right\nset grid\nf = %s\n",
            adem_plot_quote(title, qtitle, qn), adem_plot_quote(csv_path, qcsv, qn));
  /* The total goes down by what is dissipated and up by what moving walls give: the total plus
   * the dissipated energy less the wall work is the balance, flat but for the integration
   * error (and the work of a stage's change of gravity or group forces). */
  sb_printf(&b, "plot f skip 1 using 1:2 with lines title 'kinetic', \\\n"
                "     f skip 1 using 1:3 with lines title 'rotational', \\\n"
                "     f skip 1 using 1:4 with lines title 'potential', \\\n"
                "     f skip 1 using 1:5 with lines title 'elastic', \\\n"
                "     f skip 1 using 1:6 with lines title 'dissipated', \\\n"
                "     f skip 1 using 1:7 with lines title 'wall work', \\\n"
                "     f skip 1 using 1:($2+$3+$4+$5) with lines lw 2 title 'total', \\\n"
                "     f skip 1 using 1:($2+$3+$4+$5+$6-$7) with lines lw 2 dt 2 "
                "title 'total + dissipated - wall work'\n");
  free(qcsv);
  free(qtitle);
  char *body = sb_finish(&b);
  if (!body) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  adem_status st = adem_plot_png(png_path, 1000, 600, body, err);
  free(body);
  return st;
}

/* Wall loads from the CSV: for every mesh group and plane, its force along gravity (what a load
 * cell under it would read), and the particles' weight for reference. Columns as the header
 * writes them: 9, then 3 per plane, then 6 per mesh group. */
adem_status adem_output_plot_loads(const adem_world *w, const char *csv_path, const char *png_path,
                                   const char *title, adem_error *err) {
  double gn = v3_norm(w->gravity);
  adem_vec3 down = gn > 0.0 ? v3_scale(w->gravity, 1.0 / gn) : v3(0.0, 0.0, -1.0);
  double weight = 0.0;
  uint32_t *order = adem_world_id_order(w); /* summed by id, as every sum over particles */
  if (!order) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  for (size_t k = 0; k < w->p.n; ++k) weight += gn / w->p.inv_mass[order[k]];
  free(order);
  size_t qn = 2 * (strlen(csv_path) + strlen(title) + ADEM_NAME_MAX) + 8;
  char *qcsv = malloc(qn), *qname = malloc(qn);
  strbuf b = {0};
  bool ok = qcsv && qname;
  if (ok) {
    sb_printf(&b, "set title %s\nset xlabel 'time (s)'\nset ylabel 'load along gravity (N)'\n"
                  "set key outside right\nset grid\nset autoscale xfix\nset datafile separator ','\n"
                  "f = %s\n",
              adem_plot_quote(title, qname, qn), adem_plot_quote(csv_path, qcsv, qn));
    sb_printf(&b, "plot %.17g with lines dt 2 lc rgb 'black' title 'weight of the particles'", weight);
    for (int k = 0; k < w->walls.mesh.ngroups + w->walls.nplanes; ++k) {
      bool mesh = k < w->walls.mesh.ngroups;
      int col = mesh ? 11 + 3 * w->walls.nplanes + 6 * k : 11 + 3 * (k - w->walls.mesh.ngroups);
      const char *name = mesh ? w->walls.mesh.groups[k].name : w->walls.planes[k - w->walls.mesh.ngroups].def.name;
      sb_printf(&b, ", \\\n     f skip 1 using 1:(%.17g*column(%d)+%.17g*column(%d)+%.17g*column(%d)) "
                    "with lines lw 2 title %s",
                down.x, col, down.y, col + 1, down.z, col + 2, adem_plot_quote(name, qname, qn));
    }
    sb_printf(&b, "\n");
    /* Moving walls: a second panel with the power their drives put into the particles. */
    char *head = adem_output_csv_header(w, NULL, NULL);
    int nmoving = 0;
    for (char *tok = head ? strstr(head, "_drive_power_W") : NULL; tok; tok = strstr(tok + 1, "_drive_power_W"))
      ++nmoving;
    if (nmoving > 0) {
      char *body0 = sb_finish(&b);
      memset(&b, 0, sizeof b);
      sb_printf(&b, "set multiplot layout 2,1\n%s", body0 ? body0 : "");
      free(body0);
      sb_printf(&b, "set ylabel 'drive power (W)'\nset title 'power the moving walls put into the "
                    "particles (integral: wall work)'\nplot 0 with lines lc rgb 'black' notitle");
      int col = 0;
      for (char *tok = strtok(head, ",\n"); tok; tok = strtok(NULL, ",\n")) {
        ++col;
        size_t n = strlen(tok), sfx = strlen("_drive_power_W");
        if (n <= sfx || strcmp(tok + n - sfx, "_drive_power_W")) continue;
        tok[n - sfx] = '\0';
        sb_printf(&b, ", \\\n     f skip 1 using 1:%d with lines lw 2 title %s", col,
                  adem_plot_quote(tok, qname, qn));
      }
      sb_printf(&b, "\nunset multiplot\n");
    }
    free(head);
  }
  free(qcsv);
  free(qname);
  char *body = ok ? sb_finish(&b) : NULL;
  if (!body) {
    free(b.s);
    return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  }
  adem_status st = adem_plot_png(png_path, 1000, 600, body, err);
  free(body);
  return st;
}
