/* flow.png: the outlets' and mass flows' CSV columns against time (output.plot with outlets or
 * output.mass_flow): the rates (kg/s) above, the masses removed and through the planes below. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "adem/case.h"
#include "adem/files.h"
#include "adem/internal/plot.h"
#include "flow_plot.h"

/* The 1-based column of `name` in the CSV header line, 0 if absent. */
static int header_column(const char *header, const char *name) {
  size_t len = strlen(name);
  int k = 1;
  for (const char *s = header; *s && *s != '\n'; ++k) {
    size_t w = strcspn(s, ",\n");
    if (w == len && !strncmp(s, name, len)) return k;
    s += w;
    if (*s == ',') ++s;
  }
  return 0;
}

static void append(char **b, size_t *n, size_t *cap, const char *text) {
  size_t t = strlen(text);
  if (!*b) return;
  if (*n + t + 1 > *cap) {
    size_t c = 2 * (*n + t + 1);
    char *q = realloc(*b, c);
    if (!q) {
      free(*b);
      *b = NULL;
      return;
    }
    *b = q;
    *cap = c;
  }
  memcpy(*b + *n, text, t + 1);
  *n += t;
}

adem_status adem_run_plot_flow(const adem_case *c, const char *csv, const char *png,
                               adem_error *err) {
  int ncol = adem_outlets_columns(c->outlets);
  if (ncol == 0) return ADEM_OK;
  char *text = NULL;
  size_t len = 0;
  adem_status st = adem_file_read_all(csv, &text, &len, err);
  if (st) return st;
  size_t cap = 4096, n = 0;
  char *b = malloc(cap), line[1024], q[1200], name[ADEM_NAME_MAX + 32];
  if (b) b[0] = '\0';
  snprintf(line, sizeof line, "%s: mass flows", c->name[0] ? c->name : "adem");
  append(&b, &n, &cap, "set multiplot layout 2,1\nset grid\nset key outside right\n");
  snprintf(line + 512, 500, "set title %s\n", adem_plot_quote(line, q, sizeof q));
  append(&b, &n, &cap, line + 512);
  snprintf(line, sizeof line, "f = %s\n", adem_plot_quote(csv, q, sizeof q));
  append(&b, &n, &cap, line);
  for (int pass = 0; pass < 2; ++pass) {
    append(&b, &n, &cap, pass == 0 ? "set ylabel 'mass flow (kg/s)'\nplot " : "set title\nset xlabel 'time (s)'\nset ylabel 'mass (kg)'\nplot ");
    int drawn = 0;
    for (int k = 0; k < ncol; ++k) {
      adem_outlets_column_name(c->outlets, k, name, sizeof name);
      bool rate = strstr(name, "_flow_kg_s") != NULL;
      bool mass = strstr(name, "_deleted_mass_kg") || strstr(name, "_through_kg");
      if (pass == 0 ? !rate : !mass) continue;
      int col = header_column(text, name);
      if (!col) continue;
      snprintf(line, sizeof line, "%sf skip 1 using 1:%d with lines title %s", drawn ? ", \\\n     " : "",
               col, adem_plot_quote(name, q, sizeof q));
      append(&b, &n, &cap, line);
      drawn++;
    }
    if (!drawn) append(&b, &n, &cap, "f skip 1 using 1:(NaN) notitle");
    append(&b, &n, &cap, "\n");
  }
  append(&b, &n, &cap, "unset multiplot\n");
  free(text);
  if (!b) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  st = adem_plot_png(png, 1000, 800, b, err);
  free(b);
  return st;
}
