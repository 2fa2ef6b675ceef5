/* The registry of paper reproductions, their summaries, and CSV tables. */
#include "adem/laws.h"
#include "adem/files.h"
#include "adem/internal/plot.h"
#include "adem/studies.h"
#include "adem/vec3.h"
#include "table.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>


size_t adem_validation_count(void) {
  return adem_validations_haervig_count + adem_validations_irazabal_count +
         adem_validations_repose_count + adem_validations_ballast_count;
}

const adem_validation *adem_validation_at(size_t i) {
  if (i < adem_validations_haervig_count) return &adem_validations_haervig[i];
  i -= adem_validations_haervig_count;
  if (i < adem_validations_irazabal_count) return &adem_validations_irazabal[i];
  i -= adem_validations_irazabal_count;
  if (i < adem_validations_repose_count) return &adem_validations_repose[i];
  i -= adem_validations_repose_count;
  if (i < adem_validations_ballast_count) return &adem_validations_ballast[i];
  return NULL;
}

const adem_validation *adem_validation_find(const char *name) {
  for (size_t i = 0; i < adem_validation_count(); ++i)
    if (strcmp(adem_validation_at(i)->name, name) == 0) return adem_validation_at(i);
  return NULL;
}

char *adem_validation_path(const adem_validation_context *ctx, const char *name, const char *ext) {
  size_t n = strlen(ctx->out_dir) + strlen(name) + strlen(ext) + 3;
  char *p = malloc(n);
  if (p) snprintf(p, n, "%s/%s.%s", ctx->out_dir, name, ext);
  return p;
}

adem_status adem_validation_plot(const adem_validation_context *ctx, const char *name, int width,
                                 int height, const char *body, adem_error *err) {
  char *csv = adem_validation_path(ctx, name, "csv");
  char *png = adem_validation_path(ctx, name, "png");
  size_t qn = csv ? 2 * strlen(csv) + 3 : 0, n = strlen(body) + qn + 16;
  char *q = malloc(qn ? qn : 1), *script = malloc(n);
  adem_status st = ADEM_OK;
  if (!csv || !png || !q || !script) {
    st = adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  } else {
    snprintf(script, n, "f = %s\n%s", adem_plot_quote(csv, q, qn), body);
    st = adem_plot_png(png, width, height, script, err);
  }
  free(csv);
  free(png);
  free(q);
  free(script);
  return st;
}

/* ------------------------------------------------------------------ tables */

adem_status adem_table_init(adem_table *t, const char *header) {
  memset(t, 0, sizeof *t);
  t->header = strdup(header);
  if (!t->header) return ADEM_ERR_NOMEM;
  t->ncols = 1;
  for (const char *c = header; *c; ++c) t->ncols += *c == ',';
  return ADEM_OK;
}

adem_status adem_table_add(adem_table *t, const double *row) {
  if (t->nrows == t->cap) {
    size_t cap = t->cap ? 2 * t->cap : 64;
    double *d = realloc(t->data, cap * t->ncols * sizeof *d);
    if (!d) return ADEM_ERR_NOMEM;
    t->data = d;
    t->cap = cap;
  }
  memcpy(&t->data[t->nrows * t->ncols], row, t->ncols * sizeof *row);
  t->nrows++;
  return ADEM_OK;
}

adem_status adem_table_write_csv(const adem_table *t, const char *path, adem_error *err) {
  adem_afile af;
  adem_status st = adem_file_open(&af, path, err);
  if (st) return st;
  fprintf(af.f, "%s\n", t->header);
  for (size_t r = 0; r < t->nrows; ++r)
    for (size_t c = 0; c < t->ncols; ++c)
      fprintf(af.f, "%.10g%c", t->data[r * t->ncols + c], c + 1 == t->ncols ? '\n' : ',');
  return adem_file_commit(&af, err);
}

void adem_table_free(adem_table *t) {
  free(t->header);
  free(t->data);
  memset(t, 0, sizeof *t);
}

/* ---------------------------------------------------------------- summaries */

static void json_string(FILE *f, const char *s) {
  fputc('"', f);
  for (; *s; ++s) {
    unsigned char c = (unsigned char)*s;
    if (c == '"' || c == '\\')
      fprintf(f, "\\%c", c);
    else if (c == '\n')
      fputs("\\n", f);
    else if (c < 0x20)
      fprintf(f, "\\u%04x", c);
    else
      fputc(c, f);
  }
  fputc('"', f);
}

/* Markdown table cell: pipes escaped, newlines as spaces. */
static void md_cell(FILE *f, const char *s) {
  for (; *s; ++s) {
    if (*s == '|')
      fputs("\\|", f);
    else if (*s == '\n')
      fputc(' ', f);
    else
      fputc(*s, f);
  }
}

typedef struct result_entry {
  const adem_validation *v;
  adem_validation_report report;
  adem_status status;
  char error[ADEM_MSG_MAX + 16];
  double seconds;
} result_entry;

static adem_status write_summaries(const adem_validation_context *ctx, const result_entry *r,
                                   size_t n, adem_error *err) {
  char *json_path = adem_file_join(ctx->out_dir, "summary.json");
  char *md_path = adem_file_join(ctx->out_dir, "summary.md");
  if (!json_path || !md_path) {
    free(json_path);
    free(md_path);
    return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  }
  adem_afile af;
  adem_status st = adem_file_open(&af, json_path, err);
  if (!st) {
    fprintf(af.f, "{\n  \"adem\": \"%s\",\n  \"validations\": [\n", ADEM_VERSION_STRING);
    for (size_t k = 0; k < n; ++k) {
      const adem_validation_report *rep = &r[k].report;
      fprintf(af.f, "    {\"name\": ");
      json_string(af.f, r[k].v->name);
      fprintf(af.f, ", \"source\": ");
      json_string(af.f, r[k].v->source);
      fprintf(af.f, ", \"title\": ");
      json_string(af.f, r[k].v->title);
      fprintf(af.f, ",\n     \"claim\": ");
      json_string(af.f, rep->claim);
      fprintf(af.f, ",\n     \"measured\": ");
      json_string(af.f, r[k].status ? r[k].error : rep->measured);
      fprintf(af.f, ",\n     \"notes\": ");
      json_string(af.f, rep->notes);
      fprintf(af.f, ",\n     \"pass\": %s, \"seconds\": %.1f, \"csv\": \"%s.csv\", \"png\": \"%s.png\"}%s\n",
              (!r[k].status && rep->pass) ? "true" : "false", r[k].seconds, r[k].v->name,
              r[k].v->name, k + 1 < n ? "," : "");
    }
    fprintf(af.f, "  ]\n}\n");
    st = adem_file_commit(&af, err);
  }
  if (!st) st = adem_file_open(&af, md_path, err);
  if (!st) {
    fprintf(af.f, "# adem %s: paper reproductions\n\n", ADEM_VERSION_STRING);
    fprintf(af.f, "| name | source | claim | measured | result |\n|---|---|---|---|---|\n");
    for (size_t k = 0; k < n; ++k) {
      const adem_validation_report *rep = &r[k].report;
      fprintf(af.f, "| [%s](%s.png) | ", r[k].v->name, r[k].v->name);
      md_cell(af.f, r[k].v->source);
      fprintf(af.f, " | ");
      md_cell(af.f, rep->claim);
      fprintf(af.f, " | ");
      md_cell(af.f, r[k].status ? r[k].error : rep->measured);
      fprintf(af.f, " | %s |\n", r[k].status ? "error" : rep->pass ? "pass"
                                                                   : "FAIL");
    }
    fprintf(af.f, "\nNotes:\n\n");
    for (size_t k = 0; k < n; ++k)
      if (r[k].report.notes[0]) {
        fprintf(af.f, "- %s: ", r[k].v->name);
        md_cell(af.f, r[k].report.notes);
        fprintf(af.f, "\n");
      }
    st = adem_file_commit(&af, err);
  }
  free(json_path);
  free(md_path);
  return st;
}

static double seconds_now(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

adem_status adem_validation_run(const char *const *names, int n, const adem_validation_context *ctx,
                                int *failed, adem_error *err) {
  *failed = 0;
  size_t count = n > 0 ? (size_t)n : adem_validation_count();
  for (size_t k = 0; k < (size_t)n; ++k)
    if (!adem_validation_find(names[k]))
      return adem_error_set(err, ADEM_ERR_INPUT,
                            "unknown validation '%s' (adem validate --list shows them)", names[k]);
  if (ctx->normal_law && !adem_law_find(ADEM_SLOT_NORMAL, ctx->normal_law))
    return adem_error_set(err, ADEM_ERR_INPUT, "unknown normal law '%s'", ctx->normal_law);
  if (ctx->rolling_law && !adem_law_find(ADEM_SLOT_ROLLING, ctx->rolling_law))
    return adem_error_set(err, ADEM_ERR_INPUT, "unknown rolling law '%s'", ctx->rolling_law);
  adem_status st = adem_file_mkdir_p(ctx->out_dir, err);
  if (!st) st = adem_file_check_writable(ctx->out_dir, err);
  if (st) return st;
  result_entry *r = calloc(count ? count : 1, sizeof *r);
  if (!r) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  for (size_t k = 0; k < count; ++k) {
    r[k].v = n > 0 ? adem_validation_find(names[k]) : adem_validation_at(k);
    adem_log(ADEM_LOG_INFO, "validate %s: %s (%s)", r[k].v->name, r[k].v->title, r[k].v->source);
    double t0 = seconds_now();
    adem_error e;
    memset(&e, 0, sizeof e);
    r[k].status = r[k].v->run(ctx, r[k].v->name, &r[k].report, &e);
    r[k].seconds = seconds_now() - t0;
    if (r[k].status) snprintf(r[k].error, sizeof r[k].error, "error: %.1000s", e.message);
    bool pass = !r[k].status && r[k].report.pass;
    if (!pass) ++*failed;
    adem_log(pass ? ADEM_LOG_INFO : ADEM_LOG_WARN, "validate %s: %s in %.1f s: %s", r[k].v->name,
             r[k].status ? "ERROR" : pass ? "pass"
                                          : "FAIL",
             r[k].seconds,
             r[k].status ? r[k].error : r[k].report.measured);
  }
  st = write_summaries(ctx, r, count, err);
  free(r);
  return st;
}
