/* Case files: YAML read with libyaml, --set overrides grafted onto the document, every key checked
 * against the schema table (schema.c), then the world built from it. */
#include "adem/adem.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <yaml.h>

#include "collide.h"
#include "log.h"
#include "rng.h"
#include "schema.h"
#include "vec3.h"
#include "world.h"

#define KEY_PATH_MAX 256
#define LOC_MAX 640
/* Sets larger than this are surely a typo and would only exhaust memory. */
#define MAX_SET_SPHERES 100000000.0

/* Where the loader is: the YAML document and what has been built so far. */
typedef struct case_ctx {
  yaml_document_t doc;
  bool have_doc;
  const char *file;          /* name used in messages */
  const char *stem_of;       /* file whose stem is the default case name */
  const char *const *sets;   /* the --set strings */
  int nbase;                 /* node ids 1..nbase come from the text, later ones from --set */
  int *origin;               /* origin[id - nbase - 1]: the --set that made node id (-1: none) */
  size_t norigin;
  adem_error *err;
  adem_case *c;
  adem_world *w;

  /* materials, groups and walls by position, for messages and name checks */
  char (*mat_name)[ADEM_NAME_MAX];
  yaml_node_t **mat_node;
  bool *mat_density, *mat_rigid;
  int nmat;
  char (*group_name)[ADEM_NAME_MAX];
  yaml_node_t **group_node;
  int ngroup;

  /* every sphere made so far, in order of creation */
  adem_vec3 *pos, *vel, *omega;
  double *rad;
  size_t n, cap;
  double rmax;      /* largest radius */
  double vmax;      /* largest initial speed of a particle or a plane wall */
  bool has_box;     /* bounding box of particles and walls */
  adem_vec3 box_lo, box_hi;
} case_ctx;

/* A mapping being read: its node (NULL when the section is absent) and where it sits. */
typedef struct map_cursor {
  yaml_node_t *node;
  yaml_node_t *at;                  /* node messages point at: the mapping, or its parent */
  char schema[96];                  /* prefix of its keys in the schema table */
  const char *discriminator;        /* key choosing the variant, or NULL */
  char variant[32];                 /* value of the discriminator */
  char path[KEY_PATH_MAX];          /* key path for messages, "materials[0]" */
} map_cursor;

typedef struct list_cursor {
  yaml_node_t *node; /* sequence, NULL when absent or empty */
  const adem_schema_entry *e;
  size_t n;
  char path[KEY_PATH_MAX];
} list_cursor;

/* ---- messages ---- */

static void where(const case_ctx *ctx, const yaml_node_t *node, char *buf, size_t n) {
  if (node && ctx->have_doc) {
    int id = (int)(node - ctx->doc.nodes.start) + 1;
    if (id > ctx->nbase && (size_t)(id - ctx->nbase - 1) < ctx->norigin &&
        ctx->origin[id - ctx->nbase - 1] >= 0) {
      snprintf(buf, n, "--set %.500s", ctx->sets[ctx->origin[id - ctx->nbase - 1]]);
      return;
    }
    snprintf(buf, n, "%.500s:%zu:%zu", ctx->file, (size_t)node->start_mark.line + 1,
             (size_t)node->start_mark.column + 1);
  } else {
    snprintf(buf, n, "%.500s:1:1", ctx->file);
  }
}

/* "line:column" of a node, or the --set that made it, for "first defined at ...". */
static void where_short(const case_ctx *ctx, const yaml_node_t *node, char *buf, size_t n) {
  int id = node ? (int)(node - ctx->doc.nodes.start) + 1 : 0;
  if (node && id <= ctx->nbase)
    snprintf(buf, n, "line %zu:%zu", (size_t)node->start_mark.line + 1,
             (size_t)node->start_mark.column + 1);
  else
    where(ctx, node, buf, n);
}

static adem_status fail(case_ctx *ctx, const yaml_node_t *node, const char *path, const char *fmt,
                        ...) ADEM_PRINTF(4, 5);
static adem_status fail(case_ctx *ctx, const yaml_node_t *node, const char *path, const char *fmt,
                        ...) {
  char loc[LOC_MAX], msg[ADEM_MSG_MAX];
  where(ctx, node, loc, sizeof loc);
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(msg, sizeof msg, fmt, ap);
  va_end(ap);
  if (path && *path) return adem_error_set(ctx->err, ADEM_ERR_INPUT, "%s: %s: %s", loc, path, msg);
  return adem_error_set(ctx->err, ADEM_ERR_INPUT, "%s: %s", loc, msg);
}

static adem_status nomem(case_ctx *ctx) {
  return adem_error_set(ctx->err, ADEM_ERR_NOMEM, "%s: out of memory while loading the case",
                        ctx->file);
}

/* ---- suggestions ---- */

/* Optimal string alignment distance (an adjacent swap costs 1), case-insensitive. */
static size_t edit_distance(const char *a, const char *b) {
  enum { N = 64 };
  size_t na = strlen(a), nb = strlen(b);
  if (na >= N || nb >= N) return (size_t)-1;
  size_t d[N + 1][N + 1];
  for (size_t i = 0; i <= na; ++i) d[i][0] = i;
  for (size_t j = 0; j <= nb; ++j) d[0][j] = j;
  for (size_t i = 1; i <= na; ++i) {
    for (size_t j = 1; j <= nb; ++j) {
      int ca = a[i - 1] | 0x20, cb = b[j - 1] | 0x20; /* ASCII letters to lower case */
      size_t best = d[i - 1][j - 1] + (ca != cb);
      if (d[i - 1][j] + 1 < best) best = d[i - 1][j] + 1;
      if (d[i][j - 1] + 1 < best) best = d[i][j - 1] + 1;
      if (i > 1 && j > 1 && ca == (b[j - 2] | 0x20) && (a[i - 2] | 0x20) == cb &&
          d[i - 2][j - 2] + 1 < best)
        best = d[i - 2][j - 2] + 1;
      d[i][j] = best;
    }
  }
  return d[na][nb];
}

/* Keeps the closest candidate that is plausibly a misspelling of word. */
typedef struct suggestion {
  const char *word;
  const char *best;
  size_t dist;
} suggestion;

static void suggest_try(suggestion *s, const char *cand) {
  size_t d = edit_distance(s->word, cand);
  size_t len = strlen(cand);
  size_t limit = 1 + len / 4;
  bool prefix = strlen(s->word) >= 3 && strncmp(cand, s->word, strlen(s->word)) == 0;
  if (prefix && d > limit) d = limit; /* "young" for "youngs_modulus" */
  if (d <= limit && d < s->dist) {
    s->best = cand;
    s->dist = d;
  }
}

/* Appends ", item" to a list being written into buf. */
static void list_append(char *buf, size_t n, const char *item) {
  size_t k = strlen(buf);
  if (k + 1 >= n) return;
  snprintf(buf + k, n - k, "%s%s", k ? ", " : "", item);
}

/* ---- scalars ---- */

static yaml_node_t *node_at(case_ctx *ctx, int id) { return yaml_document_get_node(&ctx->doc, id); }
static const char *sval(const yaml_node_t *v) { return (const char *)v->data.scalar.value; }
static bool is_plain(const yaml_node_t *v) {
  return v->type == YAML_SCALAR_NODE && v->data.scalar.style == YAML_PLAIN_SCALAR_STYLE;
}
static bool is_null(const yaml_node_t *v) {
  if (!is_plain(v)) return false;
  const char *s = sval(v);
  return !*s || !strcmp(s, "~") || !strcmp(s, "null") || !strcmp(s, "Null") || !strcmp(s, "NULL");
}

/* How a value was written, for "got ..." in messages. */
static void node_text(const yaml_node_t *v, char *buf, size_t n) {
  if (v->type == YAML_SEQUENCE_NODE) {
    size_t k = (size_t)(v->data.sequence.items.top - v->data.sequence.items.start);
    snprintf(buf, n, "a list of %zu item%s", k, k == 1 ? "" : "s");
  } else if (v->type == YAML_MAPPING_NODE)
    snprintf(buf, n, "a mapping");
  else if (is_null(v))
    snprintf(buf, n, "no value");
  else if (is_plain(v))
    snprintf(buf, n, "`%.80s`", sval(v));
  else
    snprintf(buf, n, "the quoted string \"%.80s\"", sval(v));
}

/* Numbers are plain scalars read by strtod; quoted text is a string, not a number. */
static bool parse_number(const yaml_node_t *v, double *x) {
  if (!is_plain(v) || is_null(v)) return false;
  const char *s = sval(v);
  char *end;
  double d = strtod(s, &end);
  if (end == s || *end != '\0' || !isfinite(d)) return false;
  *x = d;
  return true;
}

static bool parse_uint(const yaml_node_t *v, uint64_t *x) {
  if (!is_plain(v) || is_null(v)) return false;
  const char *s = sval(v);
  bool digits = true;
  for (const char *p = s; *p; ++p)
    if (*p < '0' || *p > '9') digits = false;
  if (digits) {
    errno = 0;
    unsigned long long u = strtoull(s, NULL, 10);
    if (errno == ERANGE) return false;
    *x = (uint64_t)u;
    return true;
  }
  double d; /* 1e6 and 2.0 are integers too */
  if (!parse_number(v, &d) || d < 0 || d != floor(d) || d > 9007199254740992.0) return false;
  *x = (uint64_t)d;
  return true;
}

static bool parse_bool(const yaml_node_t *v, bool *b) {
  if (!is_plain(v)) return false;
  const char *s = sval(v);
  if (!strcmp(s, "true") || !strcmp(s, "True") || !strcmp(s, "TRUE")) *b = true;
  else if (!strcmp(s, "false") || !strcmp(s, "False") || !strcmp(s, "FALSE")) *b = false;
  else return false;
  return true;
}

static bool valid_name(const char *s) {
  size_t n = strlen(s);
  if (n == 0 || n >= ADEM_NAME_MAX) return false;
  if (!((s[0] >= 'a' && s[0] <= 'z') || (s[0] >= 'A' && s[0] <= 'Z') || s[0] == '_')) return false;
  for (const char *p = s; *p; ++p)
    if (!((*p >= 'a' && *p <= 'z') || (*p >= 'A' && *p <= 'Z') || (*p >= '0' && *p <= '9') ||
          *p == '_' || *p == '-'))
      return false;
  return true;
}

/* ---- typed readers of a present value ---- */

static adem_status wrong_type(case_ctx *ctx, const adem_schema_entry *e, const yaml_node_t *v,
                              const char *path) {
  char d[256], t[128];
  adem_schema_describe(e, d, sizeof d);
  node_text(v, t, sizeof t);
  return fail(ctx, v, path, "expected %s, got %s", d, t);
}

static adem_status check_range(case_ctx *ctx, const adem_schema_entry *e, const yaml_node_t *v,
                               const char *path, double x) {
  if (adem_schema_in_range(e, x)) return ADEM_OK;
  char r[64], unit[48] = "";
  adem_schema_describe_range(e, r, sizeof r);
  if (e->unit && *e->unit) snprintf(unit, sizeof unit, " (%s)", e->unit);
  return fail(ctx, v, path, "%s is out of range: it must be %s%s", sval(v), r, unit);
}

static adem_status read_number(case_ctx *ctx, const adem_schema_entry *e, const yaml_node_t *v,
                               const char *path, double *x) {
  if (!parse_number(v, x)) return wrong_type(ctx, e, v, path);
  return check_range(ctx, e, v, path, *x);
}

static adem_status read_uint(case_ctx *ctx, const adem_schema_entry *e, const yaml_node_t *v,
                             const char *path, uint64_t *x) {
  if (!parse_uint(v, x)) return wrong_type(ctx, e, v, path);
  return check_range(ctx, e, v, path, (double)*x);
}

static adem_status read_string(case_ctx *ctx, const adem_schema_entry *e, const yaml_node_t *v,
                               const char *path, char *buf, size_t n) {
  if (v->type != YAML_SCALAR_NODE || is_null(v)) return wrong_type(ctx, e, v, path);
  if (e->type == ADEM_SCHEMA_NAME && !valid_name(sval(v))) return wrong_type(ctx, e, v, path);
  if (v->data.scalar.length >= n || strlen(sval(v)) != v->data.scalar.length)
    return fail(ctx, v, path, "the text is too long (at most %zu characters) or holds a NUL", n - 1);
  memcpy(buf, sval(v), v->data.scalar.length + 1);
  return ADEM_OK;
}

static adem_status read_vec3(case_ctx *ctx, const adem_schema_entry *e, yaml_node_t *v,
                             const char *path, adem_vec3 *out) {
  if (v->type != YAML_SEQUENCE_NODE || v->data.sequence.items.top - v->data.sequence.items.start != 3)
    return wrong_type(ctx, e, v, path);
  double x[3];
  for (int k = 0; k < 3; ++k) {
    yaml_node_t *item = node_at(ctx, v->data.sequence.items.start[k]);
    if (!parse_number(item, &x[k])) {
      char p[KEY_PATH_MAX + 8], t[128];
      snprintf(p, sizeof p, "%s[%d]", path, k);
      node_text(item, t, sizeof t);
      return fail(ctx, item, p, "expected a number, got %s", t);
    }
  }
  *out = v3(x[0], x[1], x[2]);
  return ADEM_OK;
}

static adem_status read_enum(case_ctx *ctx, const adem_schema_entry *e, const yaml_node_t *v,
                             const char *path, int *index) {
  if (v->type != YAML_SCALAR_NODE || is_null(v)) return wrong_type(ctx, e, v, path);
  *index = adem_schema_choice(e, sval(v));
  if (*index >= 0) return ADEM_OK;
  char list[256], word[ADEM_NAME_MAX];
  adem_schema_list_choices(e->choices, list, sizeof list);
  suggestion s = {sval(v), NULL, (size_t)-1};
  for (const char *c = e->choices; *c;) {
    const char *bar = strchr(c, '|');
    size_t len = bar ? (size_t)(bar - c) : strlen(c);
    snprintf(word, sizeof word, "%.*s", (int)len, c);
    suggest_try(&s, word);
    if (s.best == word) s.best = c; /* keep a pointer that outlives word */
    c += len + (bar != NULL);
  }
  if (s.best) {
    size_t len = strcspn(s.best, "|");
    return fail(ctx, v, path, "`%.80s` is not one of: %s; did you mean `%.*s`?", sval(v), list,
                (int)len, s.best);
  }
  return fail(ctx, v, path, "`%.80s` is not one of: %s", sval(v), list);
}

/* ---- mappings and lists ---- */

static void join(char *out, size_t n, const char *parent, const char *key) {
  if (parent && *parent)
    snprintf(out, n, "%.200s.%.50s", parent, key);
  else
    snprintf(out, n, "%.50s", key);
}

static yaml_node_t *map_get(case_ctx *ctx, yaml_node_t *map, const char *key) {
  if (!map) return NULL;
  for (yaml_node_pair_t *p = map->data.mapping.pairs.start; p < map->data.mapping.pairs.top; ++p) {
    yaml_node_t *k = node_at(ctx, p->key);
    if (k->type == YAML_SCALAR_NODE && strcmp(sval(k), key) == 0) return node_at(ctx, p->value);
  }
  return NULL;
}

static adem_status unknown_key(case_ctx *ctx, const map_cursor *m, const yaml_node_t *k) {
  const char *key = sval(k);
  char path[KEY_PATH_MAX], allowed[600] = "";
  join(path, sizeof path, m->path, key);
  suggestion s = {key, NULL, (size_t)-1};
  for (size_t i = 0; i < adem_schema_count(); ++i) {
    const adem_schema_entry *e = adem_schema_at(i);
    if (!adem_schema_is_child(e, m->schema, m->variant)) continue;
    list_append(allowed, sizeof allowed, adem_schema_key(e));
    suggest_try(&s, adem_schema_key(e));
  }
  const adem_schema_entry *other = adem_schema_find_any(m->schema, key);
  if (other && other->variant) {
    char vs[128];
    adem_schema_list_choices(other->variant, vs, sizeof vs);
    return fail(ctx, k, path, "`%s` does not apply to %s `%s` (only to %s: %s); allowed here: %s",
                key, m->discriminator, m->variant, m->discriminator, vs, allowed);
  }
  if (s.best)
    return fail(ctx, k, path, "unknown key; did you mean `%s`? Allowed here: %s", s.best, allowed);
  return fail(ctx, k, path, "unknown key; allowed here: %s", allowed);
}

/* Checks a mapping's keys (duplicates, unknown keys) and reads its discriminator. node NULL or
 * null: the mapping is absent and every key takes its default. */
static adem_status map_open(case_ctx *ctx, yaml_node_t *node, yaml_node_t *parent, const char *path,
                            const char *schema_prefix, const char *discriminator, map_cursor *m) {
  memset(m, 0, sizeof *m);
  m->at = node ? node : parent;
  snprintf(m->schema, sizeof m->schema, "%s", schema_prefix);
  snprintf(m->path, sizeof m->path, "%s", path);
  m->discriminator = discriminator;
  if (!node || is_null(node)) {
    if (discriminator) {
      char p[KEY_PATH_MAX], d[256];
      join(p, sizeof p, path, discriminator);
      adem_schema_describe(adem_schema_find(schema_prefix, discriminator, NULL), d, sizeof d);
      return fail(ctx, m->at, p, "required value is missing: expected %s", d);
    }
    return ADEM_OK;
  }
  if (node->type != YAML_MAPPING_NODE) {
    char t[128];
    node_text(node, t, sizeof t);
    return fail(ctx, node, path, "expected a mapping (key: value), got %s", t);
  }
  m->node = node;
  yaml_node_pair_t *start = node->data.mapping.pairs.start, *top = node->data.mapping.pairs.top;
  for (yaml_node_pair_t *p = start; p < top; ++p) {
    yaml_node_t *k = node_at(ctx, p->key);
    if (k->type != YAML_SCALAR_NODE || is_null(k))
      return fail(ctx, k, path, "a key must be a plain word");
    for (yaml_node_pair_t *q = start; q < p; ++q) {
      yaml_node_t *kq = node_at(ctx, q->key);
      if (kq->type == YAML_SCALAR_NODE && strcmp(sval(kq), sval(k)) == 0) {
        char kp[KEY_PATH_MAX], first[LOC_MAX];
        join(kp, sizeof kp, path, sval(k));
        where_short(ctx, kq, first, sizeof first);
        return fail(ctx, k, kp, "duplicate key (first given at %s)", first);
      }
    }
  }
  if (discriminator) {
    const adem_schema_entry *e = adem_schema_find(schema_prefix, discriminator, NULL);
    yaml_node_t *v = map_get(ctx, node, discriminator);
    char p[KEY_PATH_MAX];
    join(p, sizeof p, path, discriminator);
    if (!v) {
      char d[256];
      adem_schema_describe(e, d, sizeof d);
      return fail(ctx, node, p, "required value is missing: expected %s", d);
    }
    int index;
    adem_status st = read_enum(ctx, e, v, p, &index);
    if (st) return st;
    snprintf(m->variant, sizeof m->variant, "%s", sval(v));
  }
  for (yaml_node_pair_t *p = start; p < top; ++p) {
    yaml_node_t *k = node_at(ctx, p->key);
    if (!adem_schema_find(m->schema, sval(k), m->variant)) return unknown_key(ctx, m, k);
  }
  return ADEM_OK;
}

static adem_status missing(case_ctx *ctx, const map_cursor *m, const adem_schema_entry *e,
                           const char *path) {
  char d[256];
  adem_schema_describe(e, d, sizeof d);
  if (e->need == ADEM_SCHEMA_REQUIRED_IF)
    return fail(ctx, m->at, path, "required value is missing (required %s): expected %s",
                e->need_doc, d);
  return fail(ctx, m->at, path, "required value is missing: expected %s", d);
}

/* The schema entry and value node of key in m; fails when a required key is missing. */
static adem_status lookup(case_ctx *ctx, const map_cursor *m, const char *key,
                          const adem_schema_entry **e, yaml_node_t **v, char *path) {
  join(path, KEY_PATH_MAX, m->path, key);
  *e = adem_schema_find(m->schema, key, m->variant);
  if (!*e)
    return adem_error_set(ctx->err, ADEM_ERR_INPUT, "internal error: `%s` is not in the case schema",
                          path);
  *v = map_get(ctx, m->node, key);
  if (!*v && (*e)->need == ADEM_SCHEMA_REQUIRED) return missing(ctx, m, *e, path);
  return ADEM_OK;
}

/* The get_* functions read key from m, or its default when absent; *node (if not NULL) is the
 * value node, NULL when the key was not given. */
static adem_status get_number(case_ctx *ctx, const map_cursor *m, const char *key, double *x,
                              yaml_node_t **node) {
  const adem_schema_entry *e;
  yaml_node_t *v;
  char path[KEY_PATH_MAX];
  adem_status st = lookup(ctx, m, key, &e, &v, path);
  if (node) *node = v;
  if (st) return st;
  if (!v) {
    if (e->def) *x = strtod(e->def, NULL);
    return ADEM_OK;
  }
  return read_number(ctx, e, v, path, x);
}

static adem_status get_uint(case_ctx *ctx, const map_cursor *m, const char *key, uint64_t *x,
                            yaml_node_t **node) {
  const adem_schema_entry *e;
  yaml_node_t *v;
  char path[KEY_PATH_MAX];
  adem_status st = lookup(ctx, m, key, &e, &v, path);
  if (node) *node = v;
  if (st) return st;
  if (!v) {
    if (e->def) *x = strtoull(e->def, NULL, 10);
    return ADEM_OK;
  }
  return read_uint(ctx, e, v, path, x);
}

static adem_status get_bool(case_ctx *ctx, const map_cursor *m, const char *key, bool *b) {
  const adem_schema_entry *e;
  yaml_node_t *v;
  char path[KEY_PATH_MAX];
  adem_status st = lookup(ctx, m, key, &e, &v, path);
  if (st) return st;
  if (!v) {
    *b = e->def && strcmp(e->def, "true") == 0;
    return ADEM_OK;
  }
  if (!parse_bool(v, b)) return wrong_type(ctx, e, v, path);
  return ADEM_OK;
}

static adem_status get_string(case_ctx *ctx, const map_cursor *m, const char *key, char *buf,
                              size_t n, yaml_node_t **node) {
  const adem_schema_entry *e;
  yaml_node_t *v;
  char path[KEY_PATH_MAX];
  adem_status st = lookup(ctx, m, key, &e, &v, path);
  if (node) *node = v;
  if (st) return st;
  if (!v) {
    if (e->def) snprintf(buf, n, "%s", e->def);
    return ADEM_OK;
  }
  return read_string(ctx, e, v, path, buf, n);
}

static adem_status get_vec3(case_ctx *ctx, const map_cursor *m, const char *key, adem_vec3 *x,
                            yaml_node_t **node) {
  const adem_schema_entry *e;
  yaml_node_t *v;
  char path[KEY_PATH_MAX];
  adem_status st = lookup(ctx, m, key, &e, &v, path);
  if (node) *node = v;
  if (st) return st;
  if (!v) {
    if (e->def) {
      double a = 0, b = 0, c = 0;
      sscanf(e->def, "[%lf, %lf, %lf]", &a, &b, &c); /* the table's own literal */
      *x = v3(a, b, c);
    }
    return ADEM_OK;
  }
  return read_vec3(ctx, e, v, path, x);
}

static adem_status get_enum(case_ctx *ctx, const map_cursor *m, const char *key, int *index) {
  const adem_schema_entry *e;
  yaml_node_t *v;
  char path[KEY_PATH_MAX];
  adem_status st = lookup(ctx, m, key, &e, &v, path);
  if (st) return st;
  if (!v) {
    *index = e->def ? adem_schema_choice(e, e->def) : -1;
    return ADEM_OK;
  }
  return read_enum(ctx, e, v, path, index);
}

/* `auto` or a number: *is_auto tells which. */
static adem_status get_auto(case_ctx *ctx, const map_cursor *m, const char *key, bool *is_auto,
                            double *x, yaml_node_t **node) {
  const adem_schema_entry *e;
  yaml_node_t *v;
  char path[KEY_PATH_MAX];
  adem_status st = lookup(ctx, m, key, &e, &v, path);
  if (node) *node = v;
  if (st) return st;
  if (!v || (is_plain(v) && strcmp(sval(v), "auto") == 0)) {
    *is_auto = !v ? (e->def && strcmp(e->def, "auto") == 0) : true;
    if (!*is_auto && e->def) *x = strtod(e->def, NULL);
    return ADEM_OK;
  }
  *is_auto = false;
  return read_number(ctx, e, v, path, x);
}

/* [name, name]: the names and their nodes (for messages about unknown names). */
static adem_status get_pair(case_ctx *ctx, const map_cursor *m, const char *key,
                            char names[2][ADEM_NAME_MAX], yaml_node_t *nodes[2], char paths[2][KEY_PATH_MAX]) {
  const adem_schema_entry *e;
  yaml_node_t *v;
  char path[KEY_PATH_MAX];
  adem_status st = lookup(ctx, m, key, &e, &v, path);
  if (st) return st;
  if (v->type != YAML_SEQUENCE_NODE || v->data.sequence.items.top - v->data.sequence.items.start != 2)
    return wrong_type(ctx, e, v, path);
  for (int k = 0; k < 2; ++k) {
    nodes[k] = node_at(ctx, v->data.sequence.items.start[k]);
    snprintf(paths[k], KEY_PATH_MAX, "%.240s[%d]", path, k);
    if (nodes[k]->type != YAML_SCALAR_NODE || is_null(nodes[k]) || !valid_name(sval(nodes[k]))) {
      char t[128];
      node_text(nodes[k], t, sizeof t);
      return fail(ctx, nodes[k], paths[k], "expected a material name, got %s", t);
    }
    snprintf(names[k], ADEM_NAME_MAX, "%s", sval(nodes[k]));
  }
  return ADEM_OK;
}

static adem_status get_map(case_ctx *ctx, const map_cursor *m, const char *key, map_cursor *sub) {
  const adem_schema_entry *e;
  yaml_node_t *v;
  char path[KEY_PATH_MAX];
  memset(sub, 0, sizeof *sub);
  adem_status st = lookup(ctx, m, key, &e, &v, path);
  if (st) return st;
  if (v && is_null(v) && e->need == ADEM_SCHEMA_REQUIRED) return missing(ctx, m, e, path);
  return map_open(ctx, v, m->at, path, e->path, e->discriminator, sub);
}

static adem_status get_list(case_ctx *ctx, const map_cursor *m, const char *key, list_cursor *l) {
  yaml_node_t *v;
  memset(l, 0, sizeof *l);
  adem_status st = lookup(ctx, m, key, &l->e, &v, l->path);
  if (st) return st;
  if (v && !is_null(v)) {
    if (v->type != YAML_SEQUENCE_NODE) return wrong_type(ctx, l->e, v, l->path);
    l->node = v;
    l->n = (size_t)(v->data.sequence.items.top - v->data.sequence.items.start);
  }
  if ((l->e->range & ADEM_RANGE_MIN) && (double)l->n < l->e->lo) {
    if (!v) return missing(ctx, m, l->e, l->path);
    return fail(ctx, v, l->path, "needs at least %g item%s", l->e->lo, l->e->lo == 1 ? "" : "s");
  }
  return ADEM_OK;
}

static adem_status list_item(case_ctx *ctx, const list_cursor *l, size_t i, map_cursor *item) {
  char path[KEY_PATH_MAX], schema[96];
  snprintf(path, sizeof path, "%.240s[%zu]", l->path, i);
  snprintf(schema, sizeof schema, "%s[]", l->e->path);
  yaml_node_t *v = node_at(ctx, l->node->data.sequence.items.start[i]);
  if (is_null(v)) return fail(ctx, v, path, "empty list item; expected a mapping (key: value)");
  return map_open(ctx, v, l->node, path, schema, l->e->discriminator, item);
}

/* ---- --set overrides ---- */

static adem_status load_yaml(const char *text, size_t len, yaml_document_t *doc, const char *file,
                             bool is_set, adem_error *err) {
  yaml_parser_t parser;
  if (!yaml_parser_initialize(&parser))
    return adem_error_set(err, ADEM_ERR_NOMEM, "%s: out of memory", file);
  yaml_parser_set_input_string(&parser, (const unsigned char *)text, len);
  adem_status st = ADEM_OK;
  bool loaded = yaml_parser_load(&parser, doc);
  if (loaded) {
    /* A case is one document: a second one is almost surely a mistake. */
    yaml_document_t extra;
    if (yaml_parser_load(&parser, &extra)) {
      yaml_node_t *root = yaml_document_get_root_node(&extra);
      if (root)
        st = adem_error_set(err, ADEM_ERR_INPUT, "%s:%zu:%zu: a second YAML document; a case %s one",
                            file, (size_t)root->start_mark.line + 1,
                            (size_t)root->start_mark.column + 1, is_set ? "value is" : "file holds");
      yaml_document_delete(&extra);
    } else {
      loaded = false;
    }
    if (!loaded || st) yaml_document_delete(doc);
  }
  if (!loaded && !st) {
    if (parser.error == YAML_MEMORY_ERROR) {
      st = adem_error_set(err, ADEM_ERR_NOMEM, "%s: out of memory reading YAML", file);
    } else if (parser.error == YAML_READER_ERROR) {
      st = adem_error_set(err, ADEM_ERR_INPUT, "%s: YAML error: %s at byte %zu", file,
                          parser.problem ? parser.problem : "unreadable input",
                          (size_t)parser.problem_offset);
    } else if (is_set) {
      st = adem_error_set(err, ADEM_ERR_INPUT, "%s: the value is not valid YAML: %s", file,
                          parser.problem ? parser.problem : "syntax error");
    } else {
      char context[200] = "";
      if (parser.context)
        snprintf(context, sizeof context, " (%s at line %zu:%zu)", parser.context,
                 (size_t)parser.context_mark.line + 1, (size_t)parser.context_mark.column + 1);
      st = adem_error_set(err, ADEM_ERR_INPUT, "%s:%zu:%zu: YAML syntax error: %s%s", file,
                          (size_t)parser.problem_mark.line + 1, (size_t)parser.problem_mark.column + 1,
                          parser.problem ? parser.problem : "syntax error", context);
    }
  }
  yaml_parser_delete(&parser);
  return st;
}

static int doc_size(const yaml_document_t *d) { return (int)(d->nodes.top - d->nodes.start); }

/* Copies node id of src (with everything under it) into dst; returns the new id or 0. */
static int graft(yaml_document_t *dst, yaml_document_t *src, int id, int depth) {
  yaml_node_t *n = yaml_document_get_node(src, id);
  if (!n || depth > 64) return 0;
  if (n->type == YAML_SCALAR_NODE)
    return yaml_document_add_scalar(dst, NULL, n->data.scalar.value, (int)n->data.scalar.length,
                                    n->data.scalar.style);
  if (n->type == YAML_SEQUENCE_NODE) {
    int s = yaml_document_add_sequence(dst, NULL, YAML_FLOW_SEQUENCE_STYLE);
    size_t count = (size_t)(n->data.sequence.items.top - n->data.sequence.items.start);
    for (size_t k = 0; s && k < count; ++k) {
      int c = graft(dst, src, n->data.sequence.items.start[k], depth + 1);
      if (!c || !yaml_document_append_sequence_item(dst, s, c)) return 0;
    }
    return s;
  }
  int m = yaml_document_add_mapping(dst, NULL, YAML_FLOW_MAPPING_STYLE);
  size_t count = (size_t)(n->data.mapping.pairs.top - n->data.mapping.pairs.start);
  for (size_t k = 0; m && k < count; ++k) {
    yaml_node_pair_t p = n->data.mapping.pairs.start[k];
    int a = graft(dst, src, p.key, depth + 1);
    int b = a ? graft(dst, src, p.value, depth + 1) : 0;
    if (!b || !yaml_document_append_mapping_pair(dst, m, a, b)) return 0;
  }
  return m;
}

static bool all_digits(const char *s) {
  if (!*s) return false;
  for (; *s; ++s)
    if (*s < '0' || *s > '9') return false;
  return true;
}

/* Applies one "key.path=value": walks the path from the root (adding missing mapping keys) and
 * replaces the target with the value parsed as YAML. Node pointers move when nodes are added,
 * so the walk holds ids. */
static adem_status apply_set(case_ctx *ctx, const char *text) {
  yaml_document_t *doc = &ctx->doc;
  const char *eq = strchr(text, '=');
  if (!eq || eq == text)
    return adem_error_set(ctx->err, ADEM_ERR_INPUT, "--set %s: expected key.path=value", text);
  char path[KEY_PATH_MAX];
  if ((size_t)(eq - text) >= sizeof path)
    return adem_error_set(ctx->err, ADEM_ERR_INPUT, "--set %.200s...: the key path is too long", text);
  memcpy(path, text, (size_t)(eq - text));
  path[eq - text] = '\0';

  char label[LOC_MAX];
  snprintf(label, sizeof label, "--set %.500s", text);
  yaml_document_t value;
  adem_status st = load_yaml(eq + 1, strlen(eq + 1), &value, label, true, ctx->err);
  if (st) return st;

  int node = yaml_document_get_root_node(doc) ? 1 : 0;
  if (!node) node = yaml_document_add_mapping(doc, NULL, YAML_BLOCK_MAPPING_STYLE);
  char walked[KEY_PATH_MAX] = "";
  char *seg = path;
  while (node && !st) {
    char *dot = strchr(seg, '.');
    if (dot) *dot = '\0';
    bool last = dot == NULL;
    if (!*seg) {
      st = adem_error_set(ctx->err, ADEM_ERR_INPUT, "--set %s: empty segment in the key path", text);
      break;
    }
    yaml_node_t *n = yaml_document_get_node(doc, node);
    int target = 0;  /* id of the node the segment names, 0 if missing */
    int *slot = NULL; /* where that id is stored, to replace it */
    size_t slot_index = 0;
    bool in_map = n->type == YAML_MAPPING_NODE;
    if (in_map) {
      yaml_node_pair_t *p = n->data.mapping.pairs.start;
      for (; p < n->data.mapping.pairs.top; ++p) {
        yaml_node_t *k = yaml_document_get_node(doc, p->key);
        if (k->type == YAML_SCALAR_NODE && strcmp(sval(k), seg) == 0) break;
      }
      if (p < n->data.mapping.pairs.top) {
        target = p->value;
        slot_index = (size_t)(p - n->data.mapping.pairs.start);
        slot = &p->value;
      }
    } else if (n->type == YAML_SEQUENCE_NODE) {
      size_t count = (size_t)(n->data.sequence.items.top - n->data.sequence.items.start);
      char names[400] = "";
      size_t i = 0;
      if (all_digits(seg)) {
        i = strtoul(seg, NULL, 10);
        if (i >= count) {
          st = adem_error_set(ctx->err, ADEM_ERR_INPUT,
                              "--set %s: `%s`: index out of range; `%s` has %zu item%s", text, seg,
                              walked, count, count == 1 ? "" : "s");
          break;
        }
      } else {
        for (i = 0; i < count; ++i) {
          yaml_node_t *item = yaml_document_get_node(doc, n->data.sequence.items.start[i]);
          yaml_node_t *name = NULL;
          if (item->type == YAML_MAPPING_NODE)
            for (yaml_node_pair_t *p = item->data.mapping.pairs.start;
                 p < item->data.mapping.pairs.top; ++p) {
              yaml_node_t *k = yaml_document_get_node(doc, p->key);
              if (k->type == YAML_SCALAR_NODE && !strcmp(sval(k), "name"))
                name = yaml_document_get_node(doc, p->value);
            }
          if (name && name->type == YAML_SCALAR_NODE) {
            if (!strcmp(sval(name), seg)) break;
            list_append(names, sizeof names, sval(name));
          }
        }
        if (i == count) {
          st = adem_error_set(ctx->err, ADEM_ERR_INPUT,
                              "--set %s: `%s`: no item of `%s` has that name or index (names: %s)",
                              text, seg, walked, *names ? names : "none");
          break;
        }
      }
      target = n->data.sequence.items.start[i];
      slot_index = i;
      slot = &n->data.sequence.items.start[i];
    } else {
      st = adem_error_set(ctx->err, ADEM_ERR_INPUT,
                          "--set %s: `%s`: `%s` is a single value, it has no keys", text, seg,
                          walked);
      break;
    }
    yaml_node_t *tn = target ? yaml_document_get_node(doc, target) : NULL;
    bool open = !tn || is_null(tn); /* nothing there yet: walk on through a new mapping */
    int replacement = 0;
    if (last && yaml_document_get_root_node(&value))
      replacement = graft(doc, &value, 1, 0);
    else if (last) /* "key=": no value, which validation then names */
      replacement = yaml_document_add_scalar(doc, NULL, (const yaml_char_t *)"", 0,
                                             YAML_PLAIN_SCALAR_STYLE);
    else if (open)
      replacement = yaml_document_add_mapping(doc, NULL, YAML_BLOCK_MAPPING_STYLE);
    if (last || open) {
      if (!replacement) {
        st = nomem(ctx);
        break;
      }
      n = yaml_document_get_node(doc, node); /* may have moved */
      if (slot) {
        if (in_map)
          n->data.mapping.pairs.start[slot_index].value = replacement;
        else
          n->data.sequence.items.start[slot_index] = replacement;
      } else {
        int key = yaml_document_add_scalar(doc, NULL, (const yaml_char_t *)seg, -1,
                                           YAML_PLAIN_SCALAR_STYLE);
        if (!key || !yaml_document_append_mapping_pair(doc, node, key, replacement)) {
          st = nomem(ctx);
          break;
        }
      }
      target = replacement;
    }
    char parent[KEY_PATH_MAX];
    snprintf(parent, sizeof parent, "%s", walked);
    join(walked, sizeof walked, parent, seg);
    if (last) break;
    node = target;
    seg = dot + 1;
  }
  yaml_document_delete(&value);
  return st;
}

static adem_status apply_sets(case_ctx *ctx, int nsets) {
  for (int k = 0; k < nsets; ++k) {
    int before = doc_size(&ctx->doc);
    adem_status st = apply_set(ctx, ctx->sets[k]);
    if (st) return st;
    int after = doc_size(&ctx->doc);
    if (after > before) {
      int *o = realloc(ctx->origin, (size_t)(after - ctx->nbase) * sizeof *o);
      if (!o) return nomem(ctx);
      ctx->origin = o;
      /* A root mapping made for an empty file stands for the file: -1. */
      for (int id = before + 1; id <= after; ++id) o[id - ctx->nbase - 1] = id == 1 ? -1 : k;
      ctx->norigin = (size_t)(after - ctx->nbase);
    }
  }
  return ADEM_OK;
}

/* ---- spheres ---- */

static void box_include(case_ctx *ctx, adem_vec3 lo, adem_vec3 hi) {
  if (!ctx->has_box) {
    ctx->box_lo = lo;
    ctx->box_hi = hi;
    ctx->has_box = true;
    return;
  }
  ctx->box_lo = v3(fmin(ctx->box_lo.x, lo.x), fmin(ctx->box_lo.y, lo.y), fmin(ctx->box_lo.z, lo.z));
  ctx->box_hi = v3(fmax(ctx->box_hi.x, hi.x), fmax(ctx->box_hi.y, hi.y), fmax(ctx->box_hi.z, hi.z));
}

static adem_status push_sphere(case_ctx *ctx, adem_vec3 x, double r, adem_vec3 v, adem_vec3 w) {
  if (ctx->n == ctx->cap) {
    size_t cap = ctx->cap ? 2 * ctx->cap : 256;
    adem_vec3 *pos = realloc(ctx->pos, cap * sizeof *pos);
    if (pos) ctx->pos = pos;
    adem_vec3 *vel = realloc(ctx->vel, cap * sizeof *vel);
    if (vel) ctx->vel = vel;
    adem_vec3 *omega = realloc(ctx->omega, cap * sizeof *omega);
    if (omega) ctx->omega = omega;
    double *rad = realloc(ctx->rad, cap * sizeof *rad);
    if (rad) ctx->rad = rad;
    if (!pos || !vel || !omega || !rad) return nomem(ctx);
    ctx->cap = cap;
  }
  ctx->pos[ctx->n] = x;
  ctx->rad[ctx->n] = r;
  ctx->vel[ctx->n] = v;
  ctx->omega[ctx->n] = w;
  ctx->n++;
  return ADEM_OK;
}

/* Adds spheres [first, ctx->n) to the world. */
static adem_status flush_spheres(case_ctx *ctx, size_t first, int material, int group,
                                 const yaml_node_t *at, const char *path) {
  for (size_t i = first; i < ctx->n; ++i) {
    adem_particle_def d = adem_default_particle_def();
    d.position = ctx->pos[i];
    d.velocity = ctx->vel[i];
    d.angular_velocity = ctx->omega[i];
    d.radius = ctx->rad[i];
    d.material = material;
    d.group = group;
    adem_error werr = {ADEM_OK, ""};
    if (adem_world_add_particle(ctx->w, &d, &werr) < 0) {
      if (werr.status == ADEM_ERR_NOMEM) return nomem(ctx);
      return fail(ctx, at, path, "%s", werr.message);
    }
    double r = ctx->rad[i];
    box_include(ctx, v3_sub(d.position, v3(r, r, r)), v3_add(d.position, v3(r, r, r)));
    ctx->rmax = fmax(ctx->rmax, r);
    ctx->vmax = fmax(ctx->vmax, v3_norm(d.velocity));
  }
  return ADEM_OK;
}

/* Uniform cell grid over spheres of ctx, for overlap queries in O(1). Queries are spheres of
 * radius <= reach; cells are at least 2 reach wide. A sphere of radius R is filed in every cell
 * its box widened by max(0, R + reach - h) touches (one cell unless it is large), so a sphere
 * that overlaps a query always sits in the query's cell or a neighbouring one. Centres outside
 * the grid are clamped to its border cells, which keeps that true. */
typedef struct sphere_grid {
  adem_vec3 lo;
  double h, inv_h, reach;
  int dims[3];
  int64_t *head; /* per cell: first entry or -1 */
  int64_t *next; /* per entry */
  size_t *sphere;
  size_t n, cap;
} sphere_grid;

static adem_status grid_init(sphere_grid *g, adem_vec3 lo, adem_vec3 hi, double h, double reach,
                             size_t expected) {
  memset(g, 0, sizeof *g);
  double ext[3] = {hi.x - lo.x, hi.y - lo.y, hi.z - lo.z};
  double limit = 8.0 * (double)expected + 4096.0; /* cells: about one per sphere */
  double cells;
  for (;;) {
    cells = 1.0;
    for (int k = 0; k < 3; ++k) cells *= floor(fmax(ext[k], 0.0) / h) + 1.0;
    if (cells <= limit) break;
    h *= 1.5;
  }
  for (int k = 0; k < 3; ++k) g->dims[k] = (int)(floor(fmax(ext[k], 0.0) / h) + 1.0);
  g->lo = lo;
  g->h = h;
  g->inv_h = 1.0 / h;
  g->reach = reach;
  size_t ncells = (size_t)cells;
  g->head = malloc(ncells * sizeof *g->head);
  if (!g->head) return ADEM_ERR_NOMEM;
  for (size_t c = 0; c < ncells; ++c) g->head[c] = -1;
  return ADEM_OK;
}

static void grid_free(sphere_grid *g) {
  free(g->head);
  free(g->next);
  free(g->sphere);
}

static int grid_coord(const sphere_grid *g, double x, double lo, int k) {
  double c = floor((x - lo) * g->inv_h);
  if (!(c > 0)) return 0; /* also NaN */
  if (c >= g->dims[k]) return g->dims[k] - 1;
  return (int)c;
}

static void grid_cell(const sphere_grid *g, adem_vec3 p, int c[3]) {
  c[0] = grid_coord(g, p.x, g->lo.x, 0);
  c[1] = grid_coord(g, p.y, g->lo.y, 1);
  c[2] = grid_coord(g, p.z, g->lo.z, 2);
}

static size_t grid_index(const sphere_grid *g, const int c[3]) {
  return ((size_t)c[2] * (size_t)g->dims[1] + (size_t)c[1]) * (size_t)g->dims[0] + (size_t)c[0];
}

static adem_status grid_insert(sphere_grid *g, const case_ctx *ctx, size_t i) {
  double e = fmax(0.0, ctx->rad[i] + g->reach - g->h);
  int a[3], b[3];
  grid_cell(g, v3_sub(ctx->pos[i], v3(e, e, e)), a);
  grid_cell(g, v3_add(ctx->pos[i], v3(e, e, e)), b);
  for (int z = a[2]; z <= b[2]; ++z)
    for (int y = a[1]; y <= b[1]; ++y)
      for (int x = a[0]; x <= b[0]; ++x) {
        if (g->n == g->cap) {
          size_t cap = g->cap ? 2 * g->cap : 1024;
          int64_t *next = realloc(g->next, cap * sizeof *next);
          if (next) g->next = next;
          size_t *sphere = realloc(g->sphere, cap * sizeof *sphere);
          if (sphere) g->sphere = sphere;
          if (!next || !sphere) return ADEM_ERR_NOMEM;
          g->cap = cap;
        }
        int c[3] = {x, y, z};
        size_t cell = grid_index(g, c);
        g->sphere[g->n] = i;
        g->next[g->n] = g->head[cell];
        g->head[cell] = (int64_t)g->n;
        g->n++;
      }
  return ADEM_OK;
}

/* Index (in ctx) of a sphere overlapping the sphere (p, r), or -1. Touching is not overlapping.
 * The query's own cell first: that is where a rejected try usually finds its overlap. */
static int64_t grid_overlap(const sphere_grid *g, const case_ctx *ctx, adem_vec3 p, double r) {
  static const int order[27][3] = {
      {0, 0, 0},   {-1, 0, 0},  {1, 0, 0},   {0, -1, 0},  {0, 1, 0},   {0, 0, -1},  {0, 0, 1},
      {-1, -1, 0}, {1, -1, 0},  {-1, 1, 0},  {1, 1, 0},   {-1, 0, -1}, {1, 0, -1},  {0, -1, -1},
      {0, 1, -1},  {-1, 0, 1},  {1, 0, 1},   {0, -1, 1},  {0, 1, 1},   {-1, -1, -1}, {1, -1, -1},
      {-1, 1, -1}, {1, 1, -1},  {-1, -1, 1}, {1, -1, 1},  {-1, 1, 1},  {1, 1, 1}};
  int c[3];
  grid_cell(g, p, c);
  for (int k = 0; k < 27; ++k) {
    int q[3] = {c[0] + order[k][0], c[1] + order[k][1], c[2] + order[k][2]};
    if (q[0] < 0 || q[1] < 0 || q[2] < 0 || q[0] >= g->dims[0] || q[1] >= g->dims[1] ||
        q[2] >= g->dims[2])
      continue;
    for (int64_t e = g->head[grid_index(g, q)]; e >= 0; e = g->next[e]) {
      size_t j = g->sphere[e];
      double s = r + ctx->rad[j];
      adem_vec3 d = v3_sub(p, ctx->pos[j]);
      if (d.x * d.x + d.y * d.y + d.z * d.z < s * s) return (int64_t)j;
    }
  }
  return -1;
}

/* ---- sections ---- */

static adem_status check_box(case_ctx *ctx, adem_vec3 lo, adem_vec3 hi, const yaml_node_t *hi_node,
                             const map_cursor *m) {
  const double a[3] = {lo.x, lo.y, lo.z}, b[3] = {hi.x, hi.y, hi.z};
  for (int k = 0; k < 3; ++k)
    if (!(a[k] < b[k])) {
      char path[KEY_PATH_MAX];
      join(path, sizeof path, m->path, "max");
      return fail(ctx, hi_node ? hi_node : m->at, path,
                  "must be greater than `min` in every component (%c: max %g <= min %g)", "xyz"[k],
                  b[k], a[k]);
    }
  return ADEM_OK;
}

/* Index of the material called name (given at node), or an error naming the known ones. */
static adem_status find_material(case_ctx *ctx, const char *name, const yaml_node_t *node,
                                 const char *path, int *index) {
  char known[600] = "";
  suggestion s = {name, NULL, (size_t)-1};
  for (int k = 0; k < ctx->nmat; ++k) {
    if (!strcmp(ctx->mat_name[k], name)) {
      *index = k;
      return ADEM_OK;
    }
    list_append(known, sizeof known, ctx->mat_name[k]);
    suggest_try(&s, ctx->mat_name[k]);
  }
  if (s.best)
    return fail(ctx, node, path, "unknown material `%s`; did you mean `%s`? Defined: %s", name,
                s.best, known);
  return fail(ctx, node, path, "unknown material `%s`; defined: %s", name, known);
}

static adem_status find_group(case_ctx *ctx, const char *name, const yaml_node_t *node,
                              const char *path, int *index) {
  *index = adem_world_find_group(ctx->w, name);
  if (*index >= 0) return ADEM_OK;
  char known[600] = "default";
  suggestion s = {name, NULL, (size_t)-1};
  suggest_try(&s, "default");
  for (int k = 0; k < ctx->ngroup; ++k) {
    list_append(known, sizeof known, ctx->group_name[k]);
    suggest_try(&s, ctx->group_name[k]);
  }
  if (s.best)
    return fail(ctx, node, path, "unknown group `%s`; did you mean `%s`? Defined: %s", name, s.best,
                known);
  return fail(ctx, node, path, "unknown group `%s`; defined: %s", name, known);
}

static adem_status build_materials(case_ctx *ctx, const map_cursor *root) {
  list_cursor l;
  adem_status st = get_list(ctx, root, "materials", &l);
  if (st) return st;
  ctx->mat_name = calloc(l.n, sizeof *ctx->mat_name);
  ctx->mat_node = calloc(l.n, sizeof *ctx->mat_node);
  ctx->mat_density = calloc(l.n, sizeof *ctx->mat_density);
  ctx->mat_rigid = calloc(l.n, sizeof *ctx->mat_rigid);
  if (!ctx->mat_name || !ctx->mat_node || !ctx->mat_density || !ctx->mat_rigid) return nomem(ctx);
  for (size_t i = 0; i < l.n; ++i) {
    map_cursor m;
    if ((st = list_item(ctx, &l, i, &m))) return st;
    adem_material_def d = adem_default_material_def();
    yaml_node_t *name_node, *density, *young, *poisson;
    bool rigid;
    if ((st = get_string(ctx, &m, "name", d.name, sizeof d.name, &name_node))) return st;
    for (int k = 0; k < ctx->nmat; ++k)
      if (!strcmp(ctx->mat_name[k], d.name)) {
        char first[LOC_MAX], path[KEY_PATH_MAX];
        where_short(ctx, ctx->mat_node[k], first, sizeof first);
        join(path, sizeof path, m.path, "name");
        return fail(ctx, name_node, path, "duplicate material name `%s` (first defined at %s)",
                    d.name, first);
      }
    if ((st = get_bool(ctx, &m, "rigid", &rigid))) return st;
    d.rigid = rigid;
    if ((st = get_number(ctx, &m, "density", &d.density, &density))) return st;
    if ((st = get_number(ctx, &m, "youngs_modulus", &d.young, &young))) return st;
    if ((st = get_number(ctx, &m, "poisson_ratio", &d.poisson, &poisson))) return st;
    char path[KEY_PATH_MAX];
    if (!rigid && !young) {
      join(path, sizeof path, m.path, "youngs_modulus");
      return missing(ctx, &m, adem_schema_find("materials[]", "youngs_modulus", NULL), path);
    }
    if (!rigid && !poisson) {
      join(path, sizeof path, m.path, "poisson_ratio");
      return missing(ctx, &m, adem_schema_find("materials[]", "poisson_ratio", NULL), path);
    }
    if ((st = get_number(ctx, &m, "restitution", &d.restitution, NULL))) return st;
    if ((st = get_number(ctx, &m, "friction", &d.friction, NULL))) return st;
    if ((st = get_number(ctx, &m, "surface_energy", &d.surface_energy, NULL))) return st;
    if ((st = get_number(ctx, &m, "adhesion_hysteresis", &d.hysteresis, NULL))) return st;
    if ((st = get_number(ctx, &m, "stiffness_factor", &d.stiffness_factor, NULL))) return st;
    if ((st = get_number(ctx, &m, "rolling_friction", &d.rolling_friction, NULL))) return st;
    if ((st = get_number(ctx, &m, "rolling_damping", &d.rolling_damping, NULL))) return st;
    adem_error werr = {ADEM_OK, ""};
    int index = adem_world_add_material(ctx->w, &d, &werr);
    if (index < 0) {
      if (werr.status == ADEM_ERR_NOMEM) return nomem(ctx);
      return fail(ctx, m.node, m.path, "%s", werr.message);
    }
    if (index != ctx->nmat)
      return adem_error_set(ctx->err, ADEM_ERR_INPUT, "internal error: material index %d", index);
    snprintf(ctx->mat_name[index], ADEM_NAME_MAX, "%s", d.name);
    ctx->mat_node[index] = m.node;
    ctx->mat_density[index] = density != NULL;
    ctx->mat_rigid[index] = rigid;
    ctx->nmat++;
  }
  return ADEM_OK;
}

/* JKR adhesion needs a surface energy on both sides: the pair's is the geometric mean of the two
 * (materials.c), so a side without one (typically a wall material) silently makes it Hertz. */
static adem_status check_jkr_pair(case_ctx *ctx, const map_cursor *m, const adem_interaction_def *d,
                                  char names[2][ADEM_NAME_MAX]) {
  const int mats[2] = {d->material_a, d->material_b};
  for (int s = 0; s < 2; ++s) {
    if (ctx->w->materials[mats[s]].def.surface_energy > 0.0) continue;
    char path[KEY_PATH_MAX], at[LOC_MAX];
    join(path, sizeof path, m->path, "normal");
    where_short(ctx, ctx->mat_node[mats[s]], at, sizeof at);
    yaml_node_t *node = map_get(ctx, m->node, "normal");
    return fail(ctx, node ? node : m->node, path,
                "`jkr` between `%s` and `%s` needs a surface energy on both materials, but `%s` "
                "(at %s) has surface_energy 0; give it a `surface_energy` > 0 (for a wall, the "
                "wall material's) or use `normal: hertz`",
                names[0], names[1], ctx->mat_name[mats[s]], at);
  }
  return ADEM_OK;
}

static adem_status build_interactions(case_ctx *ctx, const map_cursor *root) {
  list_cursor l;
  adem_status st = get_list(ctx, root, "interactions", &l);
  if (st || l.n == 0) return st;
  int *pairs = malloc(2 * l.n * sizeof *pairs);
  yaml_node_t **nodes = malloc(l.n * sizeof *nodes);
  if (!pairs || !nodes) {
    free(pairs);
    free(nodes);
    return nomem(ctx);
  }
  for (size_t i = 0; i < l.n && !st; ++i) {
    map_cursor m;
    char names[2][ADEM_NAME_MAX], paths[2][KEY_PATH_MAX];
    yaml_node_t *name_nodes[2];
    adem_interaction_def d = adem_default_interaction_def();
    int normal, rolling;
    yaml_node_t *e_node, *mu_node;
    double e, mu;
    if ((st = list_item(ctx, &l, i, &m))) break;
    if ((st = get_pair(ctx, &m, "materials", names, name_nodes, paths))) break;
    if ((st = find_material(ctx, names[0], name_nodes[0], paths[0], &d.material_a))) break;
    if ((st = find_material(ctx, names[1], name_nodes[1], paths[1], &d.material_b))) break;
    nodes[i] = m.node;
    pairs[2 * i] = d.material_a < d.material_b ? d.material_a : d.material_b;
    pairs[2 * i + 1] = d.material_a < d.material_b ? d.material_b : d.material_a;
    for (size_t k = 0; k < i && !st; ++k)
      if (pairs[2 * k] == pairs[2 * i] && pairs[2 * k + 1] == pairs[2 * i + 1]) {
        char first[LOC_MAX];
        where_short(ctx, nodes[k], first, sizeof first);
        st = fail(ctx, m.node, m.path, "a second interaction of `%s` and `%s` (first at %s)",
                  names[0], names[1], first);
      }
    if (st) break;
    if ((st = get_number(ctx, &m, "restitution", &e, &e_node))) break;
    if ((st = get_number(ctx, &m, "friction", &mu, &mu_node))) break;
    if ((st = get_enum(ctx, &m, "normal", &normal))) break;
    if ((st = get_enum(ctx, &m, "rolling", &rolling))) break;
    if (e_node) d.restitution = e;
    if (mu_node) d.friction = mu;
    /* The schema's choices are listed in the order of the enums. */
    d.normal = (adem_normal_model)normal;
    d.rolling = (adem_rolling_model)rolling;
    if (d.rolling == ADEM_ROLLING_DTK) {
      /* DTK's stiffness and limit come from the JKR pull-off force and contact radius (H18-H22):
       * without JKR adhesion they do not exist. */
      char rpath[KEY_PATH_MAX];
      join(rpath, sizeof rpath, m.path, "rolling");
      yaml_node_t *at = map_get(ctx, m.node, "rolling");
      if (d.normal != ADEM_NORMAL_JKR) {
        st = fail(ctx, at, rpath,
                  "`dtk` rolling needs the JKR pull-off force and contact radius, which the "
                  "`hertz` normal model does not provide; add `normal: jkr` to this interaction or "
                  "choose another rolling model (model_a, model_c, brof)");
        break;
      }
    }
    if (d.normal == ADEM_NORMAL_JKR && (st = check_jkr_pair(ctx, &m, &d, names))) break;
    adem_error werr = {ADEM_OK, ""};
    if (adem_world_set_interaction(ctx->w, &d, &werr) < 0)
      st = werr.status == ADEM_ERR_NOMEM ? nomem(ctx) : fail(ctx, m.node, m.path, "%s", werr.message);
  }
  free(pairs);
  free(nodes);
  return st;
}

static adem_status build_groups(case_ctx *ctx, const map_cursor *root) {
  list_cursor l;
  adem_status st = get_list(ctx, root, "groups", &l);
  if (st || l.n == 0) return st;
  ctx->group_name = calloc(l.n, sizeof *ctx->group_name);
  ctx->group_node = calloc(l.n, sizeof *ctx->group_node);
  if (!ctx->group_name || !ctx->group_node) return nomem(ctx);
  for (size_t i = 0; i < l.n; ++i) {
    map_cursor m;
    char name[ADEM_NAME_MAX];
    yaml_node_t *name_node;
    adem_vec3 force;
    if ((st = list_item(ctx, &l, i, &m))) return st;
    if ((st = get_string(ctx, &m, "name", name, sizeof name, &name_node))) return st;
    for (int k = 0; k < ctx->ngroup; ++k)
      if (!strcmp(ctx->group_name[k], name)) {
        char first[LOC_MAX], path[KEY_PATH_MAX];
        where_short(ctx, ctx->group_node[k], first, sizeof first);
        join(path, sizeof path, m.path, "name");
        return fail(ctx, name_node, path, "duplicate group name `%s` (first defined at %s)", name,
                    first);
      }
    if ((st = get_vec3(ctx, &m, "external_force", &force, NULL))) return st;
    /* Naming `default` sets the force of the group particles without `group` belong to. */
    if (adem_world_add_group(ctx->w, name, force) < 0) return nomem(ctx);
    snprintf(ctx->group_name[ctx->ngroup], ADEM_NAME_MAX, "%s", name);
    ctx->group_node[ctx->ngroup++] = name_node;
  }
  return ADEM_OK;
}

static adem_status build_walls(case_ctx *ctx, const map_cursor *root) {
  list_cursor l;
  adem_status st = get_list(ctx, root, "walls", &l);
  if (st || l.n == 0) return st;
  char(*names)[ADEM_NAME_MAX] = calloc(l.n, sizeof *names);
  yaml_node_t **nodes = calloc(l.n, sizeof *nodes);
  if (!names || !nodes) {
    free(names);
    free(nodes);
    return nomem(ctx);
  }
  for (size_t i = 0; i < l.n && !st; ++i) {
    map_cursor m;
    char material[ADEM_NAME_MAX], path[KEY_PATH_MAX];
    yaml_node_t *name_node, *mat_node;
    int mat;
    if ((st = list_item(ctx, &l, i, &m))) break;
    if ((st = get_string(ctx, &m, "name", names[i], sizeof names[i], &name_node))) break;
    if (!name_node) snprintf(names[i], sizeof names[i], "wall%zu", i);
    nodes[i] = name_node ? name_node : m.node;
    for (size_t k = 0; k < i && !st; ++k)
      if (!strcmp(names[k], names[i])) {
        char first[LOC_MAX];
        where_short(ctx, nodes[k], first, sizeof first);
        join(path, sizeof path, m.path, "name");
        st = fail(ctx, nodes[i], path, "duplicate wall name `%s` (first used at %s)", names[i],
                  first);
      }
    if (st) break;
    if ((st = get_string(ctx, &m, "material", material, sizeof material, &mat_node))) break;
    join(path, sizeof path, m.path, "material");
    if ((st = find_material(ctx, material, mat_node, path, &mat))) break;
    adem_error werr = {ADEM_OK, ""};
    if (!strcmp(m.variant, "plane")) {
      adem_plane_def d = adem_default_plane_def();
      yaml_node_t *normal_node;
      snprintf(d.name, sizeof d.name, "%s", names[i]);
      d.material = mat;
      if ((st = get_vec3(ctx, &m, "point", &d.point, NULL))) break;
      if ((st = get_vec3(ctx, &m, "normal", &d.normal, &normal_node))) break;
      if ((st = get_vec3(ctx, &m, "velocity", &d.velocity, NULL))) break;
      double len = v3_norm(d.normal);
      if (!(len > 0) || !isfinite(len)) {
        join(path, sizeof path, m.path, "normal");
        st = fail(ctx, normal_node, path, "must be a non-zero vector");
        break;
      }
      d.normal = v3_scale(d.normal, 1.0 / len);
      if (adem_world_add_plane(ctx->w, &d, &werr) < 0) {
        st = werr.status == ADEM_ERR_NOMEM ? nomem(ctx) : fail(ctx, m.node, m.path, "%s", werr.message);
        break;
      }
      box_include(ctx, d.point, d.point);
      ctx->vmax = fmax(ctx->vmax, v3_norm(d.velocity));
    } else {
      adem_vec3 lo, hi;
      yaml_node_t *hi_node;
      if ((st = get_vec3(ctx, &m, "min", &lo, NULL))) break;
      if ((st = get_vec3(ctx, &m, "max", &hi, &hi_node))) break;
      if ((st = check_box(ctx, lo, hi, hi_node, &m))) break;
      if (adem_world_add_box(ctx->w, names[i], lo, hi, mat, &werr) < 0) {
        st = werr.status == ADEM_ERR_NOMEM ? nomem(ctx) : fail(ctx, m.node, m.path, "%s", werr.message);
        break;
      }
      box_include(ctx, lo, hi);
    }
  }
  free(names);
  free(nodes);
  return st;
}

/* An explicit list of spheres; none of them may overlap another of the list. */
static adem_status build_list(case_ctx *ctx, const map_cursor *set, int mat, int group) {
  list_cursor l;
  adem_status st = get_list(ctx, set, "spheres", &l);
  if (st) return st;
  size_t first = ctx->n;
  double rmax = 0;
  for (size_t i = 0; i < l.n; ++i) {
    map_cursor m;
    adem_vec3 x, v, w;
    double r = 0.0;
    if ((st = list_item(ctx, &l, i, &m))) return st;
    if ((st = get_vec3(ctx, &m, "position", &x, NULL))) return st;
    if ((st = get_number(ctx, &m, "radius", &r, NULL))) return st;
    if ((st = get_vec3(ctx, &m, "velocity", &v, NULL))) return st;
    if ((st = get_vec3(ctx, &m, "angular_velocity", &w, NULL))) return st;
    if ((st = push_sphere(ctx, x, r, v, w))) return st;
    rmax = fmax(rmax, r);
  }
  if (l.n > 1) {
    adem_vec3 lo = ctx->pos[first], hi = lo;
    for (size_t i = first; i < ctx->n; ++i) {
      adem_vec3 p = ctx->pos[i];
      lo = v3(fmin(lo.x, p.x), fmin(lo.y, p.y), fmin(lo.z, p.z));
      hi = v3(fmax(hi.x, p.x), fmax(hi.y, p.y), fmax(hi.z, p.z));
    }
    sphere_grid g;
    if (grid_init(&g, lo, hi, 2.0 * rmax, rmax, l.n)) return nomem(ctx);
    for (size_t i = first; i < ctx->n && !st; ++i) {
      int64_t j = grid_overlap(&g, ctx, ctx->pos[i], ctx->rad[i]);
      if (j >= 0) {
        size_t a = (size_t)j - first, b = i - first;
        yaml_node_t *na = node_at(ctx, l.node->data.sequence.items.start[a]);
        yaml_node_t *nb = node_at(ctx, l.node->data.sequence.items.start[b]);
        char pa[KEY_PATH_MAX], pb[KEY_PATH_MAX], first_at[LOC_MAX];
        snprintf(pa, sizeof pa, "%.240s[%zu]", l.path, a);
        snprintf(pb, sizeof pb, "%.240s[%zu]", l.path, b);
        where_short(ctx, na, first_at, sizeof first_at);
        st = fail(ctx, nb, pb,
                  "overlaps %s (at %s): centre distance %g m < sum of radii %g m", pa, first_at,
                  v3_norm(v3_sub(ctx->pos[i], ctx->pos[j])), ctx->rad[i] + ctx->rad[j]);
      } else if (grid_insert(&g, ctx, i)) {
        st = nomem(ctx);
      }
    }
    grid_free(&g);
    if (st) return st;
  }
  return flush_spheres(ctx, first, mat, group, set->node, set->path);
}

/* Number of lattice sites along one axis: centres at lo + r + k s up to hi - r. */
static double lattice_sites(double lo, double hi, double r, double s) {
  double room = hi - lo - 2.0 * r;
  if (room < -1e-12 * fabs(hi - lo)) return 0;
  return floor(fmax(room, 0.0) / s * (1.0 + 1e-12)) + 1.0; /* round-off must not lose a layer */
}

static adem_status build_lattice(case_ctx *ctx, const map_cursor *m, int mat, int group) {
  double r = 0.0, s = 0.0;
  adem_vec3 lo, hi, v, w;
  uint64_t count;
  yaml_node_t *s_node, *hi_node, *count_node;
  adem_status st;
  char path[KEY_PATH_MAX];
  if ((st = get_number(ctx, m, "radius", &r, NULL))) return st;
  if ((st = get_number(ctx, m, "spacing", &s, &s_node))) return st;
  if (s < 2.0 * r) {
    join(path, sizeof path, m->path, "spacing");
    return fail(ctx, s_node, path,
                "spacing %g m is less than the diameter 2 radius = %g m; neighbours would overlap", s,
                2.0 * r);
  }
  if ((st = get_vec3(ctx, m, "min", &lo, NULL))) return st;
  if ((st = get_vec3(ctx, m, "max", &hi, &hi_node))) return st;
  if ((st = check_box(ctx, lo, hi, hi_node, m))) return st;
  if ((st = get_uint(ctx, m, "count", &count, &count_node))) return st;
  if ((st = get_vec3(ctx, m, "velocity", &v, NULL))) return st;
  if ((st = get_vec3(ctx, m, "angular_velocity", &w, NULL))) return st;
  double nx = lattice_sites(lo.x, hi.x, r, s), ny = lattice_sites(lo.y, hi.y, r, s),
         nz = lattice_sites(lo.z, hi.z, r, s);
  if (nx < 1 || ny < 1 || nz < 1) {
    join(path, sizeof path, m->path, "max");
    return fail(ctx, hi_node, path, "the box is narrower than one sphere (diameter %g m) along %c",
                2.0 * r, nx < 1 ? 'x' : ny < 1 ? 'y' : 'z');
  }
  double capacity = nx * ny * nz;
  double n = count > 0 ? fmin((double)count, capacity) : capacity;
  if (n > MAX_SET_SPHERES)
    return fail(ctx, m->node, m->path, "would create %.3g spheres (at most %.0g per set)", n,
                MAX_SET_SPHERES);
  if ((double)count > capacity)
    adem_log(ADEM_LOG_WARN, "%s: the lattice box holds %.0f spheres; count asks for %llu", m->path,
             capacity, (unsigned long long)count);
  size_t first = ctx->n, total = (size_t)n, nxy = (size_t)nx * (size_t)ny;
  for (size_t k = 0; k < total; ++k) {
    size_t ix = k % (size_t)nx, iy = (k / (size_t)nx) % (size_t)ny, iz = k / nxy;
    adem_vec3 x = v3(lo.x + r + (double)ix * s, lo.y + r + (double)iy * s, lo.z + r + (double)iz * s);
    if ((st = push_sphere(ctx, x, r, v, w))) return st;
  }
  return flush_spheres(ctx, first, mat, group, m->node, m->path);
}

/* Radii of a random set, drawn before any position so the grid knows the largest. */
static adem_status draw_radii(case_ctx *ctx, const map_cursor *m, adem_rng *rng, double rfit,
                              double *radii, size_t count) {
  map_cursor d;
  adem_status st = get_map(ctx, m, "radius", &d);
  if (st) return st;
  char path[KEY_PATH_MAX];
  yaml_node_t *node;
  if (!strcmp(d.variant, "constant")) {
    double r = 0.0;
    if ((st = get_number(ctx, &d, "value", &r, &node))) return st;
    if (r > rfit) {
      join(path, sizeof path, d.path, "value");
      return fail(ctx, node, path, "radius %g m does not fit the box (half its smallest side is %g m)",
                  r, rfit);
    }
    for (size_t k = 0; k < count; ++k) radii[k] = r;
    return ADEM_OK;
  }
  if (!strcmp(d.variant, "uniform")) {
    double a = 0.0, b = 0.0;
    if ((st = get_number(ctx, &d, "min", &a, NULL))) return st;
    if ((st = get_number(ctx, &d, "max", &b, &node))) return st;
    join(path, sizeof path, d.path, "max");
    if (!(b > a)) return fail(ctx, node, path, "must be greater than `min` (%g m)", a);
    if (b > rfit)
      return fail(ctx, node, path, "radius %g m does not fit the box (half its smallest side is %g m)",
                  b, rfit);
    for (size_t k = 0; k < count; ++k) radii[k] = a + (b - a) * adem_rng_uniform(rng);
    return ADEM_OK;
  }
  double mean, std;
  if ((st = get_number(ctx, &d, "mean", &mean, NULL))) return st;
  if ((st = get_number(ctx, &d, "std", &std, NULL))) return st;
  bool lognormal = !strcmp(d.variant, "lognormal");
  double sigma = 0, mu = 0;
  if (lognormal) {
    double s2 = log1p(std * std / (mean * mean));
    sigma = sqrt(s2);
    mu = log(mean) - 0.5 * s2;
  }
  for (size_t k = 0; k < count; ++k) {
    int tries = 0;
    double r = 0.0;
    do {
      if (++tries > 1000)
        return fail(ctx, d.node, d.path,
                    "could not draw a radius in (0, %g m] (half the box's smallest side) in 1000 "
                    "tries; the distribution does not fit the box",
                    rfit);
      double z = adem_rng_normal(rng);
      r = lognormal ? exp(mu + sigma * z) : mean + std * z;
    } while (!(r > 0 && r <= rfit));
    radii[k] = r;
  }
  return ADEM_OK;
}

static int compare_descending(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x < y) - (x > y);
}

static adem_status build_random(case_ctx *ctx, const map_cursor *m, size_t set_index, int mat,
                                int group) {
  adem_vec3 lo, hi, v, w;
  uint64_t count, max_attempts;
  yaml_node_t *hi_node, *attempts_node;
  adem_status st;
  if ((st = get_vec3(ctx, m, "min", &lo, NULL))) return st;
  if ((st = get_vec3(ctx, m, "max", &hi, &hi_node))) return st;
  if ((st = check_box(ctx, lo, hi, hi_node, m))) return st;
  if ((st = get_uint(ctx, m, "count", &count, NULL))) return st;
  if ((double)count > MAX_SET_SPHERES)
    return fail(ctx, m->node, m->path, "count %llu is more than %.0g spheres per set",
                (unsigned long long)count, MAX_SET_SPHERES);
  if ((st = get_uint(ctx, m, "max_attempts", &max_attempts, &attempts_node))) return st;
  if (!attempts_node) max_attempts = count * 100 > 1000000 ? count * 100 : 1000000;
  if ((st = get_vec3(ctx, m, "velocity", &v, NULL))) return st;
  if ((st = get_vec3(ctx, m, "angular_velocity", &w, NULL))) return st;

  /* Each set draws from its own stream, so editing one set leaves the others' spheres alone. */
  adem_rng rng = adem_rng_seed(ctx->c->seed ^ (0x9e3779b97f4a7c15ULL * (uint64_t)(set_index + 1)));
  adem_vec3 size = v3_sub(hi, lo);
  double rfit = 0.5 * fmin(size.x, fmin(size.y, size.z));
  double *radii = malloc((count ? count : 1) * sizeof *radii);
  if (!radii) return nomem(ctx);
  if ((st = draw_radii(ctx, m, &rng, rfit, radii, count))) {
    free(radii);
    return st;
  }
  /* Largest first: the big spheres find room while the box is empty, the small fill the gaps. */
  qsort(radii, count, sizeof *radii, compare_descending);
  double rnew = count ? radii[0] : 0.0;
  double h = fmax(2.0 * rnew, cbrt(size.x * size.y * size.z / (double)(count ? count : 1)));
  adem_vec3 glo = v3_sub(lo, v3(h, h, h)), ghi = v3_add(hi, v3(h, h, h));
  sphere_grid g;
  if (grid_init(&g, glo, ghi, h, rnew, count)) {
    free(radii);
    return nomem(ctx);
  }
  /* Spheres of earlier sets that reach the box. */
  for (size_t i = 0; i < ctx->n && !st; ++i) {
    adem_vec3 p = ctx->pos[i];
    double e = ctx->rad[i] + rnew;
    if (p.x > lo.x - e && p.y > lo.y - e && p.z > lo.z - e && p.x < hi.x + e && p.y < hi.y + e &&
        p.z < hi.z + e && grid_insert(&g, ctx, i))
      st = nomem(ctx);
  }
  size_t first = ctx->n, placed = 0;
  uint64_t attempts = 0;
  for (size_t k = 0; k < count && !st && attempts < max_attempts; ++k) {
    double r = radii[k];
    while (attempts < max_attempts) {
      ++attempts;
      double ux = adem_rng_uniform(&rng), uy = adem_rng_uniform(&rng), uz = adem_rng_uniform(&rng);
      adem_vec3 p = v3(lo.x + r + ux * (size.x - 2.0 * r), lo.y + r + uy * (size.y - 2.0 * r),
                       lo.z + r + uz * (size.z - 2.0 * r));
      if (grid_overlap(&g, ctx, p, r) >= 0) continue;
      if ((st = push_sphere(ctx, p, r, v, w))) break;
      if (grid_insert(&g, ctx, ctx->n - 1)) st = nomem(ctx);
      ++placed;
      break;
    }
  }
  grid_free(&g);
  free(radii);
  if (st) return st;
  if (placed < count) {
    char loc[LOC_MAX];
    where(ctx, m->node, loc, sizeof loc);
    adem_log(ADEM_LOG_WARN,
             "%s: %s: random fill placed %zu of %llu spheres before max_attempts (%llu) ran out; "
             "the box may be too full",
             loc, m->path, placed, (unsigned long long)count, (unsigned long long)max_attempts);
  }
  return flush_spheres(ctx, first, mat, group, m->node, m->path);
}

static adem_status build_particles(case_ctx *ctx, const map_cursor *root) {
  list_cursor l;
  adem_status st = get_list(ctx, root, "particles", &l);
  if (st) return st;
  for (size_t i = 0; i < l.n; ++i) {
    map_cursor m;
    char material[ADEM_NAME_MAX], group_name[ADEM_NAME_MAX], path[KEY_PATH_MAX];
    yaml_node_t *mat_node, *group_node;
    int mat, group;
    if ((st = list_item(ctx, &l, i, &m))) return st;
    if ((st = get_string(ctx, &m, "material", material, sizeof material, &mat_node))) return st;
    join(path, sizeof path, m.path, "material");
    if ((st = find_material(ctx, material, mat_node, path, &mat))) return st;
    if (ctx->mat_rigid[mat])
      return fail(ctx, mat_node, path, "material `%s` is rigid; rigid materials are for walls only",
                  material);
    if (!ctx->mat_density[mat]) {
      char at[LOC_MAX];
      where_short(ctx, ctx->mat_node[mat], at, sizeof at);
      return fail(ctx, mat_node, path,
                  "material `%s` (at %s) has no `density`; materials of particles need one", material,
                  at);
    }
    if ((st = get_string(ctx, &m, "group", group_name, sizeof group_name, &group_node))) return st;
    join(path, sizeof path, m.path, "group");
    if ((st = find_group(ctx, group_name, group_node ? group_node : m.node, path, &group))) return st;
    if (!strcmp(m.variant, "list"))
      st = build_list(ctx, &m, mat, group);
    else if (!strcmp(m.variant, "lattice"))
      st = build_lattice(ctx, &m, mat, group);
    else
      st = build_random(ctx, &m, i, mat, group);
    if (st) return st;
  }
  return ADEM_OK;
}

/* Case name from a file name: no directory, no extension. */
static void file_stem(const char *file, char *buf, size_t n) {
  const char *base = strrchr(file, '/');
  base = base ? base + 1 : file;
  const char *dot = strrchr(base, '.');
  size_t len = dot && dot != base ? (size_t)(dot - base) : strlen(base);
  if (len >= n) len = n - 1;
  if (len == 0) {
    snprintf(buf, n, "case");
    return;
  }
  memcpy(buf, base, len);
  buf[len] = '\0';
}

/* time.step: the proposal at v_ref (rule in the reference doc), or the user's step checked
 * against it. */
static adem_status choose_step(case_ctx *ctx, const map_cursor *time, adem_vec3 g) {
  adem_case *c = ctx->c;
  bool step_auto, speed_auto;
  double step = 0, v_ref = 0;
  yaml_node_t *step_node;
  adem_status st;
  if ((st = get_auto(ctx, time, "step", &step_auto, &step, &step_node))) return st;
  if ((st = get_auto(ctx, time, "reference_speed", &speed_auto, &v_ref, NULL))) return st;
  if (speed_auto) {
    double gn = v3_norm(g), height = 0;
    if (gn > 0 && ctx->has_box) {
      adem_vec3 ext = v3_sub(ctx->box_hi, ctx->box_lo);
      height = (fabs(g.x) * ext.x + fabs(g.y) * ext.y + fabs(g.z) * ext.z) / gn;
    }
    v_ref = fmax(fmax(ctx->vmax, sqrt(2.0 * gn * height)), 0.1);
  }
  c->estimate = adem_world_estimate_step(ctx->w, v_ref);
  bool proposal = c->estimate.dt > 0 && isfinite(c->estimate.dt);
  if (step_auto) {
    if (!proposal)
      return fail(ctx, time->at, "time.step",
                  "`auto` cannot propose a step (no particles were created); give a number");
    c->dt = c->estimate.dt;
    c->dt_auto = 1;
    c->dt_user_ratio = 1.0;
  } else {
    c->dt = step;
    c->dt_auto = 0;
    c->dt_user_ratio = proposal ? step / c->estimate.dt : 0.0;
    if (c->dt_user_ratio > 1.0) {
      bool collision = c->estimate.t_collision / 50.0 <= 0.2 * c->estimate.t_rayleigh;
      char loc[LOC_MAX];
      where(ctx, step_node, loc, sizeof loc);
      adem_log(ADEM_LOG_WARN, "%s: time.step %g s is %.1fx the proposed %g s (%s)", loc, step,
               c->dt_user_ratio, c->estimate.dt, collision ? "t_collision/50" : "0.2 t_Rayleigh");
    }
  }
  adem_world_set_dt(ctx->w, c->dt);
  return ADEM_OK;
}

/* H section 6.2: with a reduced stiffness the force that breaks a JKR contact drops to
 * (8/9) 3 pi gamma_mod R. The group forces are constant, so one look at load time finds every
 * group whose force pulls hard enough, against any JKR pair its spheres can touch, to break
 * contacts the real material would keep. One warning per group, for its weakest pair. */
static adem_status warn_pulling_forces(case_ctx *ctx) {
  adem_world *w = ctx->w;
  size_t nm = (size_t)w->nmaterials, ng = (size_t)w->ngroups;
  if (!w->interactions || nm == 0) return ADEM_OK;
  double *rmin = malloc((ng + 1) * nm * sizeof *rmin); /* per group and material; last row: all */
  bool *wall = calloc(nm, sizeof *wall);
  if (!rmin || !wall) {
    free(rmin);
    free(wall);
    return nomem(ctx);
  }
  for (size_t k = 0; k < (ng + 1) * nm; ++k) rmin[k] = INFINITY;
  for (size_t i = 0; i < w->p.n; ++i) {
    size_t g = w->p.group[i], m = w->p.material[i];
    rmin[g * nm + m] = fmin(rmin[g * nm + m], w->p.radius[i]);
    rmin[ng * nm + m] = fmin(rmin[ng * nm + m], w->p.radius[i]);
  }
  for (int k = 0; k < w->nplanes; ++k) wall[w->planes[k].def.material] = true;
  for (size_t g = 0; g < ng; ++g) {
    double force = v3_norm(w->groups[g].external_force);
    if (!(force > 0.0)) continue;
    double worst = 0.0, worst_pull = 0.0, worst_R = 0.0;
    size_t wa = 0, wb = 0;
    bool worst_wall = false;
    for (size_t a = 0; a < nm; ++a) {
      double ra = rmin[g * nm + a];
      if (!isfinite(ra)) continue;
      for (size_t b = 0; b < nm; ++b) {
        const adem_interaction *it = adem_world_interaction(w, (int)a, (int)b);
        if (it->normal != ADEM_NORMAL_JKR || !(it->gamma > 0.0)) continue;
        double rb = rmin[ng * nm + b];
        for (int side = 0; side < 2; ++side) { /* 0: a sphere of b, 1: a wall of b */
          if (side == 0 && !isfinite(rb)) continue;
          if (side == 1 && !wall[b]) continue;
          double R = side ? ra : ra * rb / (ra + rb);
          double pull = 8.0 / 9.0 * adem_jkr_pair_summarize(it->E_real, it->E, it->gamma_real,
                                                            it->gamma, R, 1.0, 1.0).f_c_mod;
          if (force / pull > worst) {
            worst = force / pull;
            worst_pull = pull;
            worst_R = R;
            wa = a;
            wb = b;
            worst_wall = side == 1;
          }
        }
      }
    }
    if (worst < ADEM_PULLOFF_SAFETY) continue;
    const adem_interaction *it = adem_world_interaction(w, (int)wa, (int)wb);
    char loc[LOC_MAX] = "";
    for (int k = 0; k < ctx->ngroup; ++k)
      if (!strcmp(ctx->group_name[k], w->groups[g].name)) where(ctx, ctx->group_node[k], loc, sizeof loc);
    if (!loc[0]) snprintf(loc, sizeof loc, "%.500s", ctx->file);
    adem_log(ADEM_LOG_WARN,
             "%s: group `%s`: its external force of %.3g N is %.0f%% of the force that breaks a "
             "`%s`-`%s`%s JKR contact, (8/9) 3 pi gamma_mod R = %.3g N (R = %.3g m, gamma_mod = "
             "%.3g J/m^2%s); such forces can tear apart contacts the real material keeps. Keep "
             "them below %.0f%% of it (%.3g N)%s (Haervig et al. section 6.2)",
             loc, w->groups[g].name, force, 100.0 * worst, w->materials[wa].def.name,
             w->materials[wb].def.name, worst_wall ? " (wall)" : "", worst_pull, worst_R,
             it->gamma, it->E < it->E_real ? ", reduced with the stiffness by H24" : "",
             100.0 * ADEM_PULLOFF_SAFETY, ADEM_PULLOFF_SAFETY * worst_pull,
             it->E < it->E_real ? " or reduce the stiffness less" : "");
  }
  free(rmin);
  free(wall);
  return ADEM_OK;
}

/* output.track: ids of particles already created (ids count from 0 in order of creation, so
 * particle id k was made from ctx->pos[k]), without repeats. */
static adem_status read_track(case_ctx *ctx, const map_cursor *out) {
  const adem_schema_entry *e;
  yaml_node_t *v;
  char path[KEY_PATH_MAX];
  adem_output_settings *o = &ctx->c->output;
  o->ntrack = 0;
  adem_status st = lookup(ctx, out, "track", &e, &v, path);
  if (st || !v || is_null(v)) return st;
  if (v->type != YAML_SEQUENCE_NODE) return wrong_type(ctx, e, v, path);
  size_t n = (size_t)(v->data.sequence.items.top - v->data.sequence.items.start);
  if ((double)n > e->hi)
    return fail(ctx, v, path, "lists %zu particles; at most %g can be tracked", n, e->hi);
  for (size_t k = 0; k < n; ++k) {
    yaml_node_t *item = node_at(ctx, v->data.sequence.items.start[k]);
    char p[KEY_PATH_MAX + 24], t[128];
    snprintf(p, sizeof p, "%s[%zu]", path, k);
    uint64_t id;
    if (!parse_uint(item, &id)) {
      node_text(item, t, sizeof t);
      return fail(ctx, item, p, "expected a particle id (an integer >= 0), got %s", t);
    }
    if (id >= ctx->n)
      return fail(ctx, item, p, "there is no particle %llu: the case creates %zu (ids 0 to %zu)",
                  (unsigned long long)id, ctx->n, ctx->n ? ctx->n - 1 : 0);
    for (int j = 0; j < o->ntrack; ++j)
      if (o->track[j] == id)
        return fail(ctx, item, p, "particle %llu is listed twice", (unsigned long long)id);
    o->track[o->ntrack] = id;
    o->ntrack++;
  }
  return ADEM_OK;
}

static adem_status build(case_ctx *ctx) {
  adem_case *c = ctx->c;
  map_cursor root, time, nb, limits, out, domain;
  yaml_node_t *node;
  adem_status st;
  if ((st = map_open(ctx, yaml_document_get_root_node(&ctx->doc), NULL, "", "", NULL, &root)))
    return st;
  if ((st = get_string(ctx, &root, "name", c->name, sizeof c->name, &node))) return st;
  if (!node) file_stem(ctx->stem_of, c->name, sizeof c->name);
  if ((st = get_uint(ctx, &root, "seed", &c->seed, NULL))) return st;
  if ((st = get_map(ctx, &root, "time", &time))) return st; /* required: report it early */
  if ((st = get_number(ctx, &time, "end", &c->end_time, NULL))) return st;
  if ((st = build_materials(ctx, &root))) return st;
  if ((st = build_interactions(ctx, &root))) return st;
  if ((st = build_groups(ctx, &root))) return st;
  if ((st = build_walls(ctx, &root))) return st;
  if ((st = build_particles(ctx, &root))) return st;

  adem_vec3 g;
  if ((st = get_vec3(ctx, &root, "gravity", &g, NULL))) return st;
  adem_world_set_gravity(ctx->w, g);

  double skin, overlap;
  if ((st = get_map(ctx, &root, "neighbor", &nb))) return st;
  if ((st = get_number(ctx, &nb, "skin", &skin, NULL))) return st;
  adem_world_set_skin(ctx->w, skin);
  if ((st = get_map(ctx, &root, "limits", &limits))) return st;
  if ((st = get_number(ctx, &limits, "max_overlap_ratio", &overlap, NULL))) return st;
  adem_world_set_max_overlap_ratio(ctx->w, overlap);

  adem_output_settings *o = &c->output;
  if ((st = get_map(ctx, &root, "output", &out))) return st;
  if ((st = get_string(ctx, &out, "dir", o->dir, sizeof o->dir, &node))) return st;
  if (!node) snprintf(o->dir, sizeof o->dir, "out/%s", c->name);
  o->frame_interval = c->end_time / 100.0;
  o->csv_interval = c->end_time / 1000.0;
  o->checkpoint_interval = c->end_time / 10.0;
  bool plot;
  if ((st = get_number(ctx, &out, "frame_interval", &o->frame_interval, NULL))) return st;
  if ((st = get_number(ctx, &out, "csv_interval", &o->csv_interval, NULL))) return st;
  if ((st = get_number(ctx, &out, "checkpoint_interval", &o->checkpoint_interval, NULL))) return st;
  if ((st = get_bool(ctx, &out, "plot", &plot))) return st;
  o->plot = plot;
  if ((st = read_track(ctx, &out))) return st;

  if ((st = get_map(ctx, &root, "domain", &domain))) return st;
  if (domain.node) {
    adem_vec3 lo, hi;
    yaml_node_t *hi_node;
    if ((st = get_vec3(ctx, &domain, "min", &lo, NULL))) return st;
    if ((st = get_vec3(ctx, &domain, "max", &hi, &hi_node))) return st;
    if ((st = check_box(ctx, lo, hi, hi_node, &domain))) return st;
    adem_world_set_domain(ctx->w, lo, hi);
  } else if (ctx->has_box) {
    /* Wide enough for free flight over the whole run, so only a blow-up trips it. */
    adem_vec3 ext = v3_sub(ctx->box_hi, ctx->box_lo);
    double t = c->end_time;
    double margin = fmax(fmax(ext.x, fmax(ext.y, ext.z)), 20.0 * ctx->rmax);
    margin = fmax(margin, ctx->vmax * t + 0.5 * v3_norm(g) * t * t);
    adem_world_set_domain(ctx->w, v3_sub(ctx->box_lo, v3(margin, margin, margin)),
                          v3_add(ctx->box_hi, v3(margin, margin, margin)));
  }
  if ((st = choose_step(ctx, &time, g))) return st;
  return warn_pulling_forces(ctx);
}

static void ctx_free(case_ctx *ctx) {
  if (ctx->have_doc) yaml_document_delete(&ctx->doc);
  free(ctx->origin);
  free(ctx->mat_name);
  free(ctx->mat_node);
  free(ctx->mat_density);
  free(ctx->mat_rigid);
  free(ctx->group_name);
  free(ctx->group_node);
  free(ctx->pos);
  free(ctx->vel);
  free(ctx->omega);
  free(ctx->rad);
}

static char *copy_text(const char *s) {
  size_t n = strlen(s) + 1;
  char *t = malloc(n);
  if (t) memcpy(t, s, n);
  return t;
}

adem_status adem_case_load_string(const char *text, const char *name_for_messages,
                                  const char *const *sets, int nsets, adem_case **out,
                                  adem_error *err) {
  if (out) *out = NULL;
  if (!text || !out || nsets < 0 || (nsets > 0 && !sets))
    return adem_error_set(err, ADEM_ERR_INPUT, "adem_case_load_string: no case text");
  adem_case *c = calloc(1, sizeof *c);
  if (!c) return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory loading a case");
  snprintf(c->path, sizeof c->path, "%s", name_for_messages ? name_for_messages : "<case>");
  case_ctx ctx;
  memset(&ctx, 0, sizeof ctx);
  ctx.file = c->path;
  ctx.stem_of = name_for_messages ? c->path : "case";
  ctx.err = err;
  ctx.c = c;
  adem_status st = ADEM_OK;
  c->source = copy_text(text);
  c->sets = calloc((size_t)(nsets > 0 ? nsets : 1), sizeof *c->sets);
  if (!c->source || !c->sets) st = nomem(&ctx);
  for (int k = 0; k < nsets && !st; ++k) {
    if (!sets[k]) {
      st = adem_error_set(err, ADEM_ERR_INPUT, "--set: missing key.path=value");
      break;
    }
    c->sets[k] = copy_text(sets[k]);
    if (!c->sets[k]) st = nomem(&ctx);
    c->nsets = k + 1;
  }
  ctx.sets = (const char *const *)c->sets;
  if (!st) st = load_yaml(text, strlen(text), &ctx.doc, c->path, false, err);
  if (!st) {
    ctx.have_doc = true;
    ctx.nbase = doc_size(&ctx.doc);
    st = apply_sets(&ctx, nsets);
  }
  if (!st) {
    c->world = adem_world_create();
    ctx.w = c->world;
    st = c->world ? build(&ctx) : nomem(&ctx);
  }
  ctx_free(&ctx);
  if (st) {
    adem_case_free(c);
    return st;
  }
  *out = c;
  return ADEM_OK;
}

adem_status adem_case_load_file(const char *path, const char *const *sets, int nsets,
                                adem_case **out, adem_error *err) {
  if (out) *out = NULL;
  if (!path) return adem_error_set(err, ADEM_ERR_INPUT, "no case file given");
  FILE *f = fopen(path, "rb");
  if (!f) return adem_error_set(err, ADEM_ERR_INPUT, "%s: cannot open the case file: %s", path,
                                strerror(errno));
  size_t len = 0, cap = 4096;
  char *text = malloc(cap);
  while (text) {
    len += fread(text + len, 1, cap - 1 - len, f);
    if (len < cap - 1) break;
    char *t = realloc(text, 2 * cap);
    if (!t) {
      free(text);
      text = NULL;
      break;
    }
    text = t;
    cap *= 2;
  }
  int read_errno = errno;
  bool failed = ferror(f);
  fclose(f);
  if (!text) return adem_error_set(err, ADEM_ERR_NOMEM, "%s: out of memory reading the case", path);
  if (failed) {
    free(text);
    return adem_error_set(err, ADEM_ERR_INPUT, "%s: cannot read the case file: %s", path,
                          strerror(read_errno));
  }
  text[len] = '\0';
  if (strlen(text) != len) {
    free(text);
    return adem_error_set(err, ADEM_ERR_INPUT, "%s: the case file holds a NUL byte; is it text?",
                          path);
  }
  adem_status st = adem_case_load_string(text, path, sets, nsets, out, err);
  free(text);
  return st;
}

void adem_case_free(adem_case *c) {
  if (!c) return;
  adem_world_free(c->world);
  free(c->source);
  if (c->sets)
    for (int k = 0; k < c->nsets; ++k) free(c->sets[k]);
  free(c->sets);
  free(c);
}

void adem_case_write_reference(FILE *f) { adem_schema_write_markdown(f); }
