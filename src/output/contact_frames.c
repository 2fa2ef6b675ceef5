/* Contact frames: the contact network of the last force pass as line cells (contact_frames.h). */
#include "contact_frames.h"

#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "adem/files.h"
#include "adem/frames.h"
#include "output.h"
#include "periodic.h"
#include "vtu.h"

/* A contact's place in the fixed order: (kind, id a, b, slot). */
typedef struct rec_key {
  int kind;
  uint64_t a, b;
  size_t slot, k;
} rec_key;

static int key_cmp(const void *x, const void *y) {
  const rec_key *p = x, *q = y;
  if (p->kind != q->kind) return p->kind < q->kind ? -1 : 1;
  if (p->a != q->a) return p->a < q->a ? -1 : 1;
  if (p->b != q->b) return p->b < q->b ? -1 : 1;
  if (p->slot != q->slot) return p->slot < q->slot ? -1 : 1;
  return 0;
}

/* Splits the force on a into its parts along n and across it. */
static void split_force(adem_contact_record *r) {
  adem_vec3 d = v3_sub(r->p1, r->p0);
  double len = v3_norm(d);
  adem_vec3 n = len > 0.0 ? v3_scale(d, 1.0 / len) : v3_zero();
  r->normal_force = v3_scale(n, v3_dot(r->force, n));
  r->tangential_force = v3_sub(r->force, r->normal_force);
}

adem_status adem_contact_records(const adem_world *w, adem_contact_record **out, size_t *count,
                                 adem_error *err) {
  *out = NULL;
  *count = 0;
  const adem_particles *p = &w->p;
  const adem_mesh_pairs *pm = &w->pm;
  size_t m = 0;
  for (size_t k = 0; k < w->pp.n; ++k) m += w->pp.touching[k];
  for (size_t k = 0; k < w->pw.n; ++k) m += w->pw.touching[k];
  for (size_t k = 0; k < pm->l.n; ++k) m += pm->l.touching[k];
  if (m == 0) return ADEM_OK;
  rec_key *keys = malloc(m * sizeof *keys);
  adem_contact_record *rec = malloc(m * sizeof *rec);
  if (!keys || !rec) {
    free(keys);
    free(rec);
    return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory for %zu contacts", m);
  }
  size_t q = 0;
  for (size_t k = 0; k < w->pp.n; ++k)
    if (w->pp.touching[k])
      keys[q++] = (rec_key){0, p->id[w->pp.a[k]], p->id[w->pp.b[k]], 0, k};
  for (size_t k = 0; k < w->pw.n; ++k)
    if (w->pw.touching[k]) keys[q++] = (rec_key){1, p->id[w->pw.a[k]], w->pw.b[k], 0, k};
  /* mesh slots: a particle's slots are its range of pm->start, in key order */
  for (size_t i = 0; pm->start && i < p->n; ++i)
    for (size_t k = pm->start[i]; k < pm->start[i + 1]; ++k)
      if (pm->l.touching[k]) keys[q++] = (rec_key){2, p->id[i], 0, k - pm->start[i], k};
  qsort(keys, q, sizeof *keys, key_cmp);
  for (size_t s = 0; s < q; ++s) {
    adem_contact_record *r = &rec[s];
    size_t k = keys[s].k;
    memset(r, 0, sizeof *r);
    r->kind = keys[s].kind;
    r->a = (int64_t)keys[s].a;
    if (r->kind == 0) {
      uint32_t i = w->pp.a[k], j = w->pp.b[k];
      adem_vec3 d = adem_periodic_min_image(&w->periodic, v3_sub(p->pos[j], p->pos[i]));
      r->b = (int64_t)keys[s].b;
      r->p0 = p->pos[i];
      r->p1 = v3_add(p->pos[i], d);
      r->overlap = p->radius[i] + p->radius[j] - v3_norm(d);
      const adem_pair_result *res = &w->pp.res[adem_pairs_slot(&w->pp, k)];
      r->force = res->force_a;
      r->rolling_torque = res->rolling_a;
    } else if (r->kind == 1) {
      uint32_t i = w->pw.a[k];
      const adem_plane_def *pl = &w->walls.planes[w->pw.b[k]].def;
      double dist = v3_dot(v3_sub(p->pos[i], pl->point), pl->normal);
      r->b = (int64_t)w->pw.b[k];
      r->p0 = p->pos[i];
      r->p1 = v3_axpy(p->pos[i], -dist, pl->normal); /* the foot on the plane */
      r->overlap = p->radius[i] - dist;
      r->force = w->pw.res[k].force_a;
      r->rolling_torque = w->pw.res[k].rolling_a;
    } else {
      uint32_t i = pm->l.a[k], t = pm->owner[k];
      const adem_mesh *mesh = &w->walls.mesh;
      adem_triangle_feature feat;
      /* the contact point is the closest point of the region, which lies on its owner triangle */
      adem_vec3 cp = adem_triangle_closest_point(p->pos[i], mesh->vert[mesh->tri[t][0]],
                                                 mesh->vert[mesh->tri[t][1]],
                                                 mesh->vert[mesh->tri[t][2]], &feat);
      r->b = (int64_t)mesh->group[t];
      r->p0 = p->pos[i];
      r->p1 = cp;
      r->overlap = p->radius[i] - v3_norm(v3_sub(cp, p->pos[i]));
      r->force = pm->l.res[k].force_a;
      r->rolling_torque = pm->l.res[k].rolling_a;
    }
    split_force(r);
  }
  free(keys);
  *out = rec;
  *count = q;
  return ADEM_OK;
}

/* ---------------------------------------------------------------- VTP */

enum { CHUNK = 1024 };

/* Array k of the file, through a small buffer. */
static int put_array(FILE *f, int k, const adem_contact_record *c, size_t n) {
  double d[3 * CHUNK];
  int64_t l[2 * CHUNK];
  int32_t s[CHUNK];
  for (size_t i0 = 0; i0 < n; i0 += CHUNK) {
    size_t m = n - i0 < CHUNK ? n - i0 : CHUNK;
    const adem_contact_record *r = c + i0;
    size_t wrote = 0, want = m;
    switch (k) {
      case 0:
      case 2:
      case 3:
      case 4:
      case 11: { /* 3-vectors */
        for (size_t j = 0; j < m; ++j) {
          adem_vec3 v = k == 0 ? r[j].force : k == 2 ? r[j].normal_force
                                          : k == 3   ? r[j].tangential_force
                                          : k == 4   ? r[j].rolling_torque
                                                     : v3_sub(r[j].p1, r[j].p0);
          d[3 * j] = v.x, d[3 * j + 1] = v.y, d[3 * j + 2] = v.z;
        }
        want = 3 * m;
        wrote = fwrite(d, 8, want, f);
        break;
      }
      case 1:
      case 5: /* scalars */
        for (size_t j = 0; j < m; ++j)
          d[j] = k == 1 ? v3_norm(r[j].normal_force) : r[j].overlap;
        wrote = fwrite(d, 8, m, f);
        break;
      case 6:
        for (size_t j = 0; j < m; ++j) s[j] = r[j].kind;
        wrote = fwrite(s, 4, m, f);
        break;
      case 7:
      case 8:
        for (size_t j = 0; j < m; ++j) l[j] = k == 7 ? r[j].a : r[j].b;
        wrote = fwrite(l, 8, m, f);
        break;
      case 9: /* points: two per contact */
        for (size_t h = 0; h < m; h += CHUNK / 2) {
          size_t mm = m - h < CHUNK / 2 ? m - h : CHUNK / 2;
          for (size_t j = 0; j < mm; ++j) {
            const adem_contact_record *x = &r[h + j];
            double *o = d + 6 * j;
            o[0] = x->p0.x, o[1] = x->p0.y, o[2] = x->p0.z;
            o[3] = x->p1.x, o[4] = x->p1.y, o[5] = x->p1.z;
          }
          if (fwrite(d, 8, 6 * mm, f) != 6 * mm) return 0;
        }
        wrote = want;
        break;
      case 10: /* connectivity */
        for (size_t j = 0; j < m; ++j) {
          l[2 * j] = (int64_t)(2 * (i0 + j));
          l[2 * j + 1] = (int64_t)(2 * (i0 + j) + 1);
        }
        want = 2 * m;
        wrote = fwrite(l, 8, want, f);
        break;
      case 12: /* offsets */
        for (size_t j = 0; j < m; ++j) l[j] = (int64_t)(2 * (i0 + j + 1));
        wrote = fwrite(l, 8, m, f);
        break;
      default:
        return 0;
    }
    if (wrote != want) return 0;
  }
  return 1;
}

adem_status adem_contact_write_vtp(const adem_world *w, const adem_contact_record *c, size_t n,
                                   const char *path, adem_error *err) {
  /* cell arrays 0..8 and 11, then points (9), then lines (10, 12) */
  static const struct {
    const char *name, *type;
    int ncomp, size;
  } def[] = {{"force", "Float64", 3, 8}, {"normal_force_magnitude", "Float64", 1, 8}, {"normal_force", "Float64", 3, 8}, {"tangential_force", "Float64", 3, 8}, {"rolling_torque", "Float64", 3, 8}, {"overlap", "Float64", 1, 8}, {"kind", "Int32", 1, 4}, {"id_a", "Int64", 1, 8}, {"id_b", "Int64", 1, 8}, {"position", "Float64", 3, 8}, {"connectivity", "Int64", 1, 8}, {"branch", "Float64", 3, 8}, {"offsets", "Int64", 1, 8}};
  const int order[] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 11, 9, 10, 12}; /* as appended */
  const int nord = (int)(sizeof order / sizeof order[0]);
  size_t bytes[13];
  for (int k = 0; k < 13; ++k) {
    size_t per = (size_t)def[k].ncomp * (size_t)def[k].size;
    bytes[k] = (k == 9 || k == 10 ? 2 : 1) * n * per;
  }
  adem_afile af;
  adem_status st = adem_file_open(&af, path, err);
  if (st) return st;
  FILE *f = af.f;
  fprintf(f,
          "<?xml version=\"1.0\"?>\n"
          "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"%s\" header_type=\"UInt64\">\n"
          "  <PolyData>\n"
          "    <FieldData>\n"
          "      <DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" "
          "format=\"ascii\">%.17g</DataArray>\n"
          "      <DataArray type=\"Int64\" Name=\"Step\" NumberOfTuples=\"1\" "
          "format=\"ascii\">%" PRIu64 "</DataArray>\n"
          "    </FieldData>\n"
          "    <Piece NumberOfPoints=\"%zu\" NumberOfVerts=\"0\" NumberOfLines=\"%zu\" "
          "NumberOfStrips=\"0\" NumberOfPolys=\"0\">\n"
          "      <CellData Scalars=\"normal_force_magnitude\" Vectors=\"force\">\n",
          adem_vtu_byte_order(), w->time, w->step, 2 * n, n);
  uint64_t offset = 0;
  for (int q = 0; q < nord; ++q) {
    int k = order[q];
    if (k == 9) fprintf(f, "      </CellData>\n      <Points>\n");
    if (k == 10) fprintf(f, "      </Points>\n      <Lines>\n");
    fprintf(f, "        <DataArray type=\"%s\" Name=\"%s\" ", def[k].type, def[k].name);
    if (def[k].ncomp > 1) fprintf(f, "NumberOfComponents=\"%d\" ", def[k].ncomp);
    fprintf(f, "format=\"appended\" offset=\"%" PRIu64 "\"/>\n", offset);
    offset += 8 + (uint64_t)bytes[k];
  }
  fprintf(f, "      </Lines>\n    </Piece>\n  </PolyData>\n  <AppendedData encoding=\"raw\">\n   _");
  int ok = 1;
  for (int q = 0; q < nord && ok; ++q) {
    int k = order[q];
    uint64_t nb = bytes[k];
    ok = fwrite(&nb, 8, 1, f) == 1 && put_array(f, k, c, n);
  }
  fprintf(f, "\n  </AppendedData>\n</VTKFile>\n");
  if (!ok || ferror(f)) {
    int e = errno ? errno : EIO;
    adem_file_abort(&af);
    return adem_error_set(err, ADEM_ERR_IO, "cannot write %s: %s", path, strerror(e));
  }
  return adem_file_commit(&af, err);
}

/* ---------------------------------------------------------------- CSV */

const char adem_contact_csv_header[] =
    "kind,id_a,id_b,xa_m,ya_m,za_m,xb_m,yb_m,zb_m,fx_N,fy_N,fz_N,fnx_N,fny_N,fnz_N,fn_N,"
    "ftx_N,fty_N,ftz_N,mrx_Nm,mry_Nm,mrz_Nm,overlap_m\n";

adem_status adem_contact_write_csv(const adem_contact_record *c, size_t n, const char *path,
                                   adem_error *err) {
  static const char *const kinds[] = {"particle", "plane", "mesh"};
  adem_afile af;
  adem_status st = adem_file_open(&af, path, err);
  if (st) return st;
  FILE *f = af.f;
  fputs(adem_contact_csv_header, f);
  for (size_t k = 0; k < n; ++k) {
    const adem_contact_record *r = &c[k];
    fprintf(f,
            "%s,%" PRId64 ",%" PRId64 ",%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,"
            "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n",
            kinds[r->kind < 0 || r->kind > 2 ? 0 : r->kind], r->a, r->b, r->p0.x, r->p0.y,
            r->p0.z, r->p1.x, r->p1.y, r->p1.z, r->force.x, r->force.y, r->force.z,
            r->normal_force.x, r->normal_force.y, r->normal_force.z, v3_norm(r->normal_force),
            r->tangential_force.x, r->tangential_force.y, r->tangential_force.z,
            r->rolling_torque.x, r->rolling_torque.y, r->rolling_torque.z, r->overlap);
  }
  if (ferror(f)) {
    int e = errno ? errno : EIO;
    adem_file_abort(&af);
    return adem_error_set(err, ADEM_ERR_IO, "cannot write %s: %s", path, strerror(e));
  }
  return adem_file_commit(&af, err);
}

/* ---------------------------------------------------------------- the run's contact frames */

static void contacts_name(char *buf, size_t cap, size_t index, const char *ext) {
  snprintf(buf, cap, "frames/contacts_%06zu.%s", index, ext);
}

/* Keeps the entries of an earlier contacts.pvd whose frame index is below frames_done and whose
 * file is the name adem gives it. */
static adem_status contacts_pvd_reload(adem_pvd *pvd, const char *path, size_t frames_done,
                                       adem_error *err) {
  char *text = NULL;
  size_t len = 0;
  adem_error ignored;
  if (adem_file_read_all(path, &text, &len, &ignored) != ADEM_OK) return ADEM_OK;
  adem_status st = ADEM_OK;
  size_t last = 0;
  bool any = false;
  for (char *line = text; line && *line && !st;) {
    char *next = strchr(line, '\n');
    if (next) *next++ = '\0';
    const char *ts = strstr(line, "timestep=\"");
    const char *fl = strstr(line, "file=\"frames/contacts_");
    if (ts && fl) {
      double t = strtod(ts + 10, NULL);
      unsigned long long k = strtoull(fl + 22, NULL, 10);
      char want[64];
      contacts_name(want, sizeof want, (size_t)k, "vtp");
      size_t nl = strcspn(fl + 6, "\"");
      /* in order, each once, and only earlier frames */
      if (k < frames_done && (!any || k > last) && nl == strlen(want) &&
          !strncmp(fl + 6, want, nl)) {
        st = adem_output_pvd_add(pvd, t, want, err);
        last = (size_t)k;
        any = true;
      }
    }
    line = next;
  }
  free(text);
  return st;
}

adem_status adem_output_contacts_open(adem_output *o, int every, bool csv, bool resume,
                                      size_t frames_done, adem_error *err) {
  o->contacts_every = o->frames && every > 0 ? every : 0;
  o->contacts_csv = csv;
  if (!o->contacts_every) return ADEM_OK;
  char *path = adem_file_join(o->dir, "contacts.pvd");
  if (!path) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  adem_status st = ADEM_OK;
  if (resume) {
    st = contacts_pvd_reload(&o->contacts_pvd, path, frames_done, err);
    /* the list must not name frames the resumed run is about to rewrite */
    if (!st) st = adem_output_pvd_write(&o->contacts_pvd, path, err);
  }
  free(path);
  return st;
}

adem_status adem_output_contacts_frame(adem_output *o, const adem_world *w, adem_error *err) {
  if (!o->contacts_every || o->next_frame % (size_t)o->contacts_every != 0) return ADEM_OK;
  adem_contact_record *rec = NULL;
  size_t n = 0;
  adem_status st = adem_contact_records(w, &rec, &n, err);
  if (st) return st;
  char name[64], csv[64];
  contacts_name(name, sizeof name, o->next_frame, "vtp");
  contacts_name(csv, sizeof csv, o->next_frame, "csv");
  char *path = adem_file_join(o->dir, name);
  char *csv_path = adem_file_join(o->dir, csv);
  char *pvd_path = adem_file_join(o->dir, "contacts.pvd");
  if (!path || !csv_path || !pvd_path) st = adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  if (!st) st = adem_contact_write_vtp(w, rec, n, path, err);
  if (!st && o->contacts_csv) st = adem_contact_write_csv(rec, n, csv_path, err);
  if (!st) st = adem_output_pvd_add(&o->contacts_pvd, w->time, name, err);
  if (!st) st = adem_output_pvd_write(&o->contacts_pvd, pvd_path, err);
  free(path);
  free(csv_path);
  free(pvd_path);
  free(rec);
  return st;
}

adem_status adem_world_contact_frame(const adem_world *w, adem_contact_frame *frame,
                                     adem_error *err) {
  memset(frame, 0, sizeof *frame);
  frame->time = adem_world_time(w);
  frame->step = (int64_t)adem_world_step_count(w);
  adem_contact_record *rec = NULL;
  size_t n = 0;
  adem_status st = adem_contact_records(w, &rec, &n, err);
  if (st) return st;
  size_t cap = n ? n : 1; /* a frame with no contact still owns its (empty) arrays */
  frame->p0 = malloc(cap * sizeof *frame->p0);
  frame->p1 = malloc(cap * sizeof *frame->p1);
  frame->force = malloc(cap * sizeof *frame->force);
  frame->kind = malloc(cap * sizeof *frame->kind);
  frame->id_a = malloc(cap * sizeof *frame->id_a);
  frame->id_b = malloc(cap * sizeof *frame->id_b);
  if (!frame->p0 || !frame->p1 || !frame->force || !frame->kind || !frame->id_a || !frame->id_b) {
    free(rec);
    adem_contact_frame_free(frame);
    return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory for %zu contacts", n);
  }
  for (size_t k = 0; k < n; ++k) {
    frame->p0[k] = rec[k].p0;
    frame->p1[k] = rec[k].p1;
    frame->force[k] = rec[k].force;
    frame->kind[k] = rec[k].kind;
    frame->id_a[k] = rec[k].a;
    frame->id_b[k] = rec[k].b;
  }
  frame->n = n;
  free(rec);
  return ADEM_OK;
}
