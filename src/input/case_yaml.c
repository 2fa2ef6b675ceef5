/* Reading a case's YAML (case_yaml.h). */
#include "case_yaml.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "adem/vec3.h"


/* ---- messages ---- */

void adem_yaml_where(const case_ctx *ctx, const yaml_node_t *node, char *buf, size_t n) {
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
void adem_yaml_where_short(const case_ctx *ctx, const yaml_node_t *node, char *buf, size_t n) {
  int id = node ? (int)(node - ctx->doc.nodes.start) + 1 : 0;
  if (node && id <= ctx->nbase)
    snprintf(buf, n, "line %zu:%zu", (size_t)node->start_mark.line + 1,
             (size_t)node->start_mark.column + 1);
  else
    adem_yaml_where(ctx, node, buf, n);
}

adem_status adem_yaml_fail(case_ctx *ctx, const yaml_node_t *node, const char *path, const char *fmt,
                           ...) {
  char loc[LOC_MAX], msg[ADEM_MSG_MAX];
  adem_yaml_where(ctx, node, loc, sizeof loc);
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(msg, sizeof msg, fmt, ap);
  va_end(ap);
  if (path && *path) return adem_error_set(ctx->err, ADEM_ERR_INPUT, "%s: %s: %s", loc, path, msg);
  return adem_error_set(ctx->err, ADEM_ERR_INPUT, "%s: %s", loc, msg);
}

adem_status adem_yaml_nomem(case_ctx *ctx) {
  return adem_error_set(ctx->err, ADEM_ERR_NOMEM, "%s: out of memory while loading the case",
                        ctx->file);
}

/* ---- suggestions ---- */

/* Optimal string alignment distance (an adjacent swap costs 1), case-insensitive. */
size_t adem_yaml_edit_distance(const char *a, const char *b) {
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


void adem_yaml_suggest_try(suggestion *s, const char *cand) {
  size_t d = adem_yaml_edit_distance(s->word, cand);
  size_t len = strlen(cand);
  size_t limit = 1 + len / 4;
  bool prefix = strlen(s->word) >= 3 && strncmp(cand, s->word, strlen(s->word)) == 0;
  if (prefix && d > limit) d = limit; /* "young" for "youngs_modulus" */
  if (d <= limit && d < s->dist) {
    s->best = cand;
    s->dist = d;
  }
}

/* Names other DEM codes and papers use for a key of ours, where edit distance does not reach
 * it: `rolling_resistance` is 7 edits from `rolling_friction`. Offered only when the key it
 * names is allowed where the unknown one was written. */
static const char *const synonyms[][2] = {
    {"rolling_resistance", "rolling_friction"},
    {"rolling_resistance_coefficient", "rolling_friction"},
    {"rolling_friction_coefficient", "rolling_friction"},
    {"coefficient_of_rolling_friction", "rolling_friction"},
    {"eta_r", "rolling_friction"},
    {"coefficient_of_restitution", "restitution"},
    {"restitution_coefficient", "restitution"},
    {"cor", "restitution"},
    {"e", "restitution"},
    {"coefficient_of_friction", "friction"},
    {"friction_coefficient", "friction"},
    {"sliding_friction", "friction"},
    {"static_friction", "friction"},
    {"mu", "friction"},
    {"youngs", "youngs_modulus"},
    {"young", "youngs_modulus"},
    {"elastic_modulus", "youngs_modulus"},
    {"modulus", "youngs_modulus"},
    {"E", "youngs_modulus"},
    {"poisson", "poisson_ratio"},
    {"poissons_ratio", "poisson_ratio"},
    {"nu", "poisson_ratio"},
    {"rho", "density"},
    {"mass_density", "density"},
    {"gamma", "surface_energy"},
    {"surface_tension", "surface_energy"},
    {"stiffness_reduction", "stiffness_factor"},
    {"dt", "step"},
    {"timestep", "step"},
    {"time_step", "step"},
    {"t_end", "end"},
    {"end_time", "end"},
    {"duration", "end"},
    {"radius_distribution", "radius"},
    {"diameter", "radius"},
    {"number", "count"},
};

const char *adem_yaml_synonym(const char *word) {
  for (size_t k = 0; k < sizeof synonyms / sizeof synonyms[0]; ++k)
    if (!strcmp(word, synonyms[k][0])) return synonyms[k][1];
  return NULL;
}

/* Appends ", item" to a list being written into buf. */
void adem_yaml_list_append(char *buf, size_t n, const char *item) {
  size_t k = strlen(buf);
  if (k + 1 >= n) return;
  snprintf(buf + k, n - k, "%s%s", k ? ", " : "", item);
}

/* ---- scalars ---- */

yaml_node_t *adem_yaml_node_at(case_ctx *ctx, int id) { return yaml_document_get_node(&ctx->doc, id); }
const char *adem_yaml_sval(const yaml_node_t *v) { return (const char *)v->data.scalar.value; }
bool adem_yaml_is_plain(const yaml_node_t *v) {
  return v->type == YAML_SCALAR_NODE && v->data.scalar.style == YAML_PLAIN_SCALAR_STYLE;
}
bool adem_yaml_is_null(const yaml_node_t *v) {
  if (!adem_yaml_is_plain(v)) return false;
  const char *s = adem_yaml_sval(v);
  return !*s || !strcmp(s, "~") || !strcmp(s, "null") || !strcmp(s, "Null") || !strcmp(s, "NULL");
}

/* How a value was written, for "got ..." in messages. */
void adem_yaml_node_text(const yaml_node_t *v, char *buf, size_t n) {
  if (v->type == YAML_SEQUENCE_NODE) {
    size_t k = (size_t)(v->data.sequence.items.top - v->data.sequence.items.start);
    snprintf(buf, n, "a list of %zu item%s", k, k == 1 ? "" : "s");
  } else if (v->type == YAML_MAPPING_NODE)
    snprintf(buf, n, "a mapping");
  else if (adem_yaml_is_null(v))
    snprintf(buf, n, "no value");
  else if (adem_yaml_is_plain(v))
    snprintf(buf, n, "`%.80s`", adem_yaml_sval(v));
  else
    snprintf(buf, n, "the quoted string \"%.80s\"", adem_yaml_sval(v));
}

/* Numbers are plain scalars read by strtod; quoted text is a string, not a number. */
bool adem_yaml_parse_number(const yaml_node_t *v, double *x) {
  if (!adem_yaml_is_plain(v) || adem_yaml_is_null(v)) return false;
  const char *s = adem_yaml_sval(v);
  char *end;
  double d = strtod(s, &end);
  if (end == s || *end != '\0' || !isfinite(d)) return false;
  *x = d;
  return true;
}

bool adem_yaml_parse_uint(const yaml_node_t *v, uint64_t *x) {
  if (!adem_yaml_is_plain(v) || adem_yaml_is_null(v)) return false;
  const char *s = adem_yaml_sval(v);
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
  if (!adem_yaml_parse_number(v, &d) || d < 0 || d != floor(d) || d > 9007199254740992.0) return false;
  *x = (uint64_t)d;
  return true;
}

bool adem_yaml_parse_bool(const yaml_node_t *v, bool *b) {
  if (!adem_yaml_is_plain(v)) return false;
  const char *s = adem_yaml_sval(v);
  if (!strcmp(s, "true") || !strcmp(s, "True") || !strcmp(s, "TRUE")) *b = true;
  else if (!strcmp(s, "false") || !strcmp(s, "False") || !strcmp(s, "FALSE")) *b = false;
  else return false;
  return true;
}

bool adem_yaml_valid_name(const char *s) {
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

adem_status adem_yaml_wrong_type(case_ctx *ctx, const adem_schema_entry *e, const yaml_node_t *v,
                                 const char *path) {
  char d[256], t[128];
  adem_schema_describe(e, d, sizeof d);
  adem_yaml_node_text(v, t, sizeof t);
  return adem_yaml_fail(ctx, v, path, "expected %s, got %s", d, t);
}

adem_status adem_yaml_check_range(case_ctx *ctx, const adem_schema_entry *e, const yaml_node_t *v,
                                  const char *path, double x) {
  if (adem_schema_in_range(e, x)) return ADEM_OK;
  char r[64], unit[48] = "";
  adem_schema_describe_range(e, r, sizeof r);
  if (e->unit && *e->unit) snprintf(unit, sizeof unit, " (%s)", e->unit);
  return adem_yaml_fail(ctx, v, path, "%s is out of range: it must be %s%s", adem_yaml_sval(v), r, unit);
}

adem_status adem_yaml_read_number(case_ctx *ctx, const adem_schema_entry *e, const yaml_node_t *v,
                                  const char *path, double *x) {
  if (!adem_yaml_parse_number(v, x)) return adem_yaml_wrong_type(ctx, e, v, path);
  return adem_yaml_check_range(ctx, e, v, path, *x);
}

adem_status adem_yaml_read_uint(case_ctx *ctx, const adem_schema_entry *e, const yaml_node_t *v,
                                const char *path, uint64_t *x) {
  if (!adem_yaml_parse_uint(v, x)) return adem_yaml_wrong_type(ctx, e, v, path);
  return adem_yaml_check_range(ctx, e, v, path, (double)*x);
}

adem_status adem_yaml_read_string(case_ctx *ctx, const adem_schema_entry *e, const yaml_node_t *v,
                                  const char *path, char *buf, size_t n) {
  if (v->type != YAML_SCALAR_NODE || adem_yaml_is_null(v)) return adem_yaml_wrong_type(ctx, e, v, path);
  if (e->type == ADEM_SCHEMA_NAME && !adem_yaml_valid_name(adem_yaml_sval(v))) return adem_yaml_wrong_type(ctx, e, v, path);
  if (v->data.scalar.length >= n || strlen(adem_yaml_sval(v)) != v->data.scalar.length)
    return adem_yaml_fail(ctx, v, path, "the text is too long (at most %zu characters) or holds a NUL", n - 1);
  memcpy(buf, adem_yaml_sval(v), v->data.scalar.length + 1);
  return ADEM_OK;
}

adem_status adem_yaml_read_vec3(case_ctx *ctx, const adem_schema_entry *e, yaml_node_t *v,
                                const char *path, adem_vec3 *out) {
  if (v->type != YAML_SEQUENCE_NODE || v->data.sequence.items.top - v->data.sequence.items.start != 3)
    return adem_yaml_wrong_type(ctx, e, v, path);
  double x[3];
  for (int k = 0; k < 3; ++k) {
    yaml_node_t *item = adem_yaml_node_at(ctx, v->data.sequence.items.start[k]);
    if (!adem_yaml_parse_number(item, &x[k])) {
      char p[KEY_PATH_MAX + 8], t[128];
      snprintf(p, sizeof p, "%s[%d]", path, k);
      adem_yaml_node_text(item, t, sizeof t);
      return adem_yaml_fail(ctx, item, p, "expected a number, got %s", t);
    }
  }
  *out = v3(x[0], x[1], x[2]);
  return ADEM_OK;
}

adem_status adem_yaml_read_enum(case_ctx *ctx, const adem_schema_entry *e, const yaml_node_t *v,
                                const char *path, int *index) {
  if (v->type != YAML_SCALAR_NODE || adem_yaml_is_null(v)) return adem_yaml_wrong_type(ctx, e, v, path);
  *index = adem_schema_choice(e, adem_yaml_sval(v));
  if (*index >= 0) return ADEM_OK;
  char list[256], word[ADEM_NAME_MAX];
  adem_schema_list_choices(e->choices, list, sizeof list);
  suggestion s = {adem_yaml_sval(v), NULL, (size_t)-1};
  for (const char *c = e->choices; *c;) {
    const char *bar = strchr(c, '|');
    size_t len = bar ? (size_t)(bar - c) : strlen(c);
    snprintf(word, sizeof word, "%.*s", (int)len, c);
    adem_yaml_suggest_try(&s, word);
    if (s.best == word) s.best = c; /* keep a pointer that outlives word */
    c += len + (bar != NULL);
  }
  if (s.best) {
    size_t len = strcspn(s.best, "|");
    return adem_yaml_fail(ctx, v, path, "`%.80s` is not one of: %s; did you mean `%.*s`?", adem_yaml_sval(v), list,
                          (int)len, s.best);
  }
  return adem_yaml_fail(ctx, v, path, "`%.80s` is not one of: %s", adem_yaml_sval(v), list);
}

/* ---- mappings and lists ---- */

void adem_yaml_join(char *out, size_t n, const char *parent, const char *key) {
  if (parent && *parent)
    snprintf(out, n, "%.200s.%.50s", parent, key);
  else
    snprintf(out, n, "%.50s", key);
}

yaml_node_t *adem_yaml_map_get(case_ctx *ctx, yaml_node_t *map, const char *key) {
  if (!map) return NULL;
  for (yaml_node_pair_t *p = map->data.mapping.pairs.start; p < map->data.mapping.pairs.top; ++p) {
    yaml_node_t *k = adem_yaml_node_at(ctx, p->key);
    if (k->type == YAML_SCALAR_NODE && strcmp(adem_yaml_sval(k), key) == 0) return adem_yaml_node_at(ctx, p->value);
  }
  return NULL;
}

adem_status adem_yaml_unknown_key(case_ctx *ctx, const map_cursor *m, const yaml_node_t *k) {
  const char *key = adem_yaml_sval(k);
  char path[KEY_PATH_MAX], allowed[600] = "";
  adem_yaml_join(path, sizeof path, m->path, key);
  suggestion s = {key, NULL, (size_t)-1};
  const char *synonym = adem_yaml_synonym(key);
  for (size_t i = 0; i < adem_schema_count(); ++i) {
    const adem_schema_entry *e = adem_schema_at(i);
    if (!adem_schema_is_child(e, m->schema, m->variant)) continue;
    adem_yaml_list_append(allowed, sizeof allowed, adem_schema_key(e));
    adem_yaml_suggest_try(&s, adem_schema_key(e));
  }
  /* A known other name of an allowed key beats a near spelling. */
  const adem_schema_entry *syn = synonym ? adem_schema_find(m->schema, synonym, m->variant) : NULL;
  if (syn) s.best = adem_schema_key(syn);
  const adem_schema_entry *other = adem_schema_find_any(m->schema, key);
  if (other && other->variant) {
    char vs[128];
    adem_schema_list_choices(other->variant, vs, sizeof vs);
    return adem_yaml_fail(ctx, k, path, "`%s` does not apply to %s `%s` (only to %s: %s); allowed here: %s",
                          key, m->discriminator, m->variant, m->discriminator, vs, allowed);
  }
  if (s.best)
    return adem_yaml_fail(ctx, k, path, "unknown key; did you mean `%s`? Allowed here: %s", s.best, allowed);
  return adem_yaml_fail(ctx, k, path, "unknown key; allowed here: %s", allowed);
}

/* Checks a mapping's keys (duplicates, unknown keys) and reads its discriminator. node NULL or
 * null: the mapping is absent and every key takes its default. */
adem_status adem_yaml_map_open(case_ctx *ctx, yaml_node_t *node, yaml_node_t *parent, const char *path,
                               const char *schema_prefix, const char *discriminator, map_cursor *m) {
  memset(m, 0, sizeof *m);
  m->at = node ? node : parent;
  snprintf(m->schema, sizeof m->schema, "%s", schema_prefix);
  snprintf(m->path, sizeof m->path, "%s", path);
  m->discriminator = discriminator;
  if (!node || adem_yaml_is_null(node)) {
    if (discriminator) {
      char p[KEY_PATH_MAX], d[256];
      adem_yaml_join(p, sizeof p, path, discriminator);
      adem_schema_describe(adem_schema_find(schema_prefix, discriminator, NULL), d, sizeof d);
      return adem_yaml_fail(ctx, m->at, p, "required value is missing: expected %s", d);
    }
    return ADEM_OK;
  }
  if (node->type != YAML_MAPPING_NODE) {
    char t[128];
    adem_yaml_node_text(node, t, sizeof t);
    return adem_yaml_fail(ctx, node, path, "expected a mapping (key: value), got %s", t);
  }
  m->node = node;
  yaml_node_pair_t *start = node->data.mapping.pairs.start, *top = node->data.mapping.pairs.top;
  for (yaml_node_pair_t *p = start; p < top; ++p) {
    yaml_node_t *k = adem_yaml_node_at(ctx, p->key);
    if (k->type != YAML_SCALAR_NODE || adem_yaml_is_null(k))
      return adem_yaml_fail(ctx, k, path, "a key must be a plain word");
    for (yaml_node_pair_t *q = start; q < p; ++q) {
      yaml_node_t *kq = adem_yaml_node_at(ctx, q->key);
      if (kq->type == YAML_SCALAR_NODE && strcmp(adem_yaml_sval(kq), adem_yaml_sval(k)) == 0) {
        char kp[KEY_PATH_MAX], first[LOC_MAX];
        adem_yaml_join(kp, sizeof kp, path, adem_yaml_sval(k));
        adem_yaml_where_short(ctx, kq, first, sizeof first);
        return adem_yaml_fail(ctx, k, kp, "duplicate key (first given at %s)", first);
      }
    }
  }
  if (discriminator) {
    const adem_schema_entry *e = adem_schema_find(schema_prefix, discriminator, NULL);
    yaml_node_t *v = adem_yaml_map_get(ctx, node, discriminator);
    char p[KEY_PATH_MAX];
    adem_yaml_join(p, sizeof p, path, discriminator);
    if (!v) {
      char d[256];
      adem_schema_describe(e, d, sizeof d);
      return adem_yaml_fail(ctx, node, p, "required value is missing: expected %s", d);
    }
    int index;
    adem_status st = adem_yaml_read_enum(ctx, e, v, p, &index);
    if (st) return st;
    snprintf(m->variant, sizeof m->variant, "%s", adem_yaml_sval(v));
  }
  for (yaml_node_pair_t *p = start; p < top; ++p) {
    yaml_node_t *k = adem_yaml_node_at(ctx, p->key);
    if (!adem_schema_find(m->schema, adem_yaml_sval(k), m->variant)) return adem_yaml_unknown_key(ctx, m, k);
  }
  return ADEM_OK;
}

adem_status adem_yaml_missing(case_ctx *ctx, const map_cursor *m, const adem_schema_entry *e,
                              const char *path) {
  char d[256];
  adem_schema_describe(e, d, sizeof d);
  if (e->need == ADEM_SCHEMA_REQUIRED_IF)
    return adem_yaml_fail(ctx, m->at, path, "required value is missing (required %s): expected %s",
                          e->need_doc, d);
  return adem_yaml_fail(ctx, m->at, path, "required value is missing: expected %s", d);
}

/* The schema entry and value node of key in m; fails when a required key is missing. */
adem_status adem_yaml_lookup(case_ctx *ctx, const map_cursor *m, const char *key,
                             const adem_schema_entry **e, yaml_node_t **v, char *path) {
  adem_yaml_join(path, KEY_PATH_MAX, m->path, key);
  *e = adem_schema_find(m->schema, key, m->variant);
  if (!*e)
    return adem_error_set(ctx->err, ADEM_ERR_INPUT, "internal error: `%s` is not in the case schema",
                          path);
  *v = adem_yaml_map_get(ctx, m->node, key);
  if (!*v && (*e)->need == ADEM_SCHEMA_REQUIRED) return adem_yaml_missing(ctx, m, *e, path);
  return ADEM_OK;
}

/* The get_* functions read key from m, or its default when absent; *node (if not NULL) is the
 * value node, NULL when the key was not given. */
adem_status adem_yaml_get_number(case_ctx *ctx, const map_cursor *m, const char *key, double *x,
                                 yaml_node_t **node) {
  const adem_schema_entry *e;
  yaml_node_t *v;
  char path[KEY_PATH_MAX];
  adem_status st = adem_yaml_lookup(ctx, m, key, &e, &v, path);
  if (node) *node = v;
  if (st) return st;
  if (!v) {
    if (e->def) *x = strtod(e->def, NULL);
    return ADEM_OK;
  }
  return adem_yaml_read_number(ctx, e, v, path, x);
}

adem_status adem_yaml_get_uint(case_ctx *ctx, const map_cursor *m, const char *key, uint64_t *x,
                               yaml_node_t **node) {
  const adem_schema_entry *e;
  yaml_node_t *v;
  char path[KEY_PATH_MAX];
  adem_status st = adem_yaml_lookup(ctx, m, key, &e, &v, path);
  if (node) *node = v;
  if (st) return st;
  if (!v) {
    if (e->def) *x = strtoull(e->def, NULL, 10);
    return ADEM_OK;
  }
  return adem_yaml_read_uint(ctx, e, v, path, x);
}

adem_status adem_yaml_get_bool(case_ctx *ctx, const map_cursor *m, const char *key, bool *b) {
  const adem_schema_entry *e;
  yaml_node_t *v;
  char path[KEY_PATH_MAX];
  adem_status st = adem_yaml_lookup(ctx, m, key, &e, &v, path);
  if (st) return st;
  if (!v) {
    *b = e->def && strcmp(e->def, "true") == 0;
    return ADEM_OK;
  }
  if (!adem_yaml_parse_bool(v, b)) return adem_yaml_wrong_type(ctx, e, v, path);
  return ADEM_OK;
}

adem_status adem_yaml_get_bool3(case_ctx *ctx, const map_cursor *m, const char *key, bool b[3],
                                yaml_node_t *items[3]) {
  const adem_schema_entry *e;
  yaml_node_t *v;
  char path[KEY_PATH_MAX];
  adem_status st = adem_yaml_lookup(ctx, m, key, &e, &v, path);
  if (st) return st;
  for (int k = 0; k < 3; ++k) {
    if (items) items[k] = NULL;
    b[k] = false;
  }
  if (!v) { /* the default: "[false, false, false]" or with `true` items */
    const char *s = e->def ? e->def : "";
    for (int k = 0; k < 3 && (s = strpbrk(s, "tf")); ++k, s += 4) b[k] = *s == 't';
    return ADEM_OK;
  }
  if (v->type != YAML_SEQUENCE_NODE || v->data.sequence.items.top - v->data.sequence.items.start != 3)
    return adem_yaml_wrong_type(ctx, e, v, path);
  for (int k = 0; k < 3; ++k) {
    yaml_node_t *item = adem_yaml_node_at(ctx, v->data.sequence.items.start[k]);
    if (items) items[k] = item;
    if (!adem_yaml_parse_bool(item, &b[k])) {
      char p[KEY_PATH_MAX + 8], t[128];
      snprintf(p, sizeof p, "%s[%d]", path, k);
      adem_yaml_node_text(item, t, sizeof t);
      return adem_yaml_fail(ctx, item, p, "expected true or false (is the %c axis periodic?), got %s",
                            "xyz"[k], t);
    }
  }
  return ADEM_OK;
}

adem_status adem_yaml_get_string(case_ctx *ctx, const map_cursor *m, const char *key, char *buf,
                                 size_t n, yaml_node_t **node) {
  const adem_schema_entry *e;
  yaml_node_t *v;
  char path[KEY_PATH_MAX];
  adem_status st = adem_yaml_lookup(ctx, m, key, &e, &v, path);
  if (node) *node = v;
  if (st) return st;
  if (!v) {
    if (e->def) snprintf(buf, n, "%s", e->def);
    return ADEM_OK;
  }
  return adem_yaml_read_string(ctx, e, v, path, buf, n);
}

adem_status adem_yaml_get_vec3(case_ctx *ctx, const map_cursor *m, const char *key, adem_vec3 *x,
                               yaml_node_t **node) {
  const adem_schema_entry *e;
  yaml_node_t *v;
  char path[KEY_PATH_MAX];
  *x = v3_zero(); /* defined on every path, also for keys without a default */
  adem_status st = adem_yaml_lookup(ctx, m, key, &e, &v, path);
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
  return adem_yaml_read_vec3(ctx, e, v, path, x);
}

adem_status adem_yaml_get_enum(case_ctx *ctx, const map_cursor *m, const char *key, int *index) {
  const adem_schema_entry *e;
  yaml_node_t *v;
  char path[KEY_PATH_MAX];
  adem_status st = adem_yaml_lookup(ctx, m, key, &e, &v, path);
  if (st) return st;
  if (!v) {
    *index = e->def ? adem_schema_choice(e, e->def) : -1;
    return ADEM_OK;
  }
  return adem_yaml_read_enum(ctx, e, v, path, index);
}

/* `auto` or a number: *is_auto tells which. */
adem_status adem_yaml_get_auto(case_ctx *ctx, const map_cursor *m, const char *key, bool *is_auto,
                               double *x, yaml_node_t **node) {
  const adem_schema_entry *e;
  yaml_node_t *v;
  char path[KEY_PATH_MAX];
  adem_status st = adem_yaml_lookup(ctx, m, key, &e, &v, path);
  if (node) *node = v;
  if (st) return st;
  if (!v || (adem_yaml_is_plain(v) && strcmp(adem_yaml_sval(v), "auto") == 0)) {
    *is_auto = !v ? (e->def && strcmp(e->def, "auto") == 0) : true;
    if (!*is_auto && e->def) *x = strtod(e->def, NULL);
    return ADEM_OK;
  }
  *is_auto = false;
  return adem_yaml_read_number(ctx, e, v, path, x);
}

/* [name, name]: the names and their nodes (for messages about unknown names). */
adem_status adem_yaml_get_pair(case_ctx *ctx, const map_cursor *m, const char *key,
                               char names[2][ADEM_NAME_MAX], yaml_node_t *nodes[2], char paths[2][KEY_PATH_MAX]) {
  const adem_schema_entry *e;
  yaml_node_t *v;
  char path[KEY_PATH_MAX];
  adem_status st = adem_yaml_lookup(ctx, m, key, &e, &v, path);
  if (st) return st;
  if (v->type != YAML_SEQUENCE_NODE || v->data.sequence.items.top - v->data.sequence.items.start != 2)
    return adem_yaml_wrong_type(ctx, e, v, path);
  for (int k = 0; k < 2; ++k) {
    nodes[k] = adem_yaml_node_at(ctx, v->data.sequence.items.start[k]);
    snprintf(paths[k], KEY_PATH_MAX, "%.240s[%d]", path, k);
    if (nodes[k]->type != YAML_SCALAR_NODE || adem_yaml_is_null(nodes[k]) || !adem_yaml_valid_name(adem_yaml_sval(nodes[k]))) {
      char t[128];
      adem_yaml_node_text(nodes[k], t, sizeof t);
      return adem_yaml_fail(ctx, nodes[k], paths[k], "expected a material name, got %s", t);
    }
    snprintf(names[k], ADEM_NAME_MAX, "%s", adem_yaml_sval(nodes[k]));
  }
  return ADEM_OK;
}

adem_status adem_yaml_get_map(case_ctx *ctx, const map_cursor *m, const char *key, map_cursor *sub) {
  const adem_schema_entry *e;
  yaml_node_t *v;
  char path[KEY_PATH_MAX];
  memset(sub, 0, sizeof *sub);
  adem_status st = adem_yaml_lookup(ctx, m, key, &e, &v, path);
  if (st) return st;
  if (v && adem_yaml_is_null(v) && e->need == ADEM_SCHEMA_REQUIRED) return adem_yaml_missing(ctx, m, e, path);
  return adem_yaml_map_open(ctx, v, m->at, path, e->path, e->discriminator, sub);
}

adem_status adem_yaml_get_list(case_ctx *ctx, const map_cursor *m, const char *key, list_cursor *l) {
  yaml_node_t *v;
  memset(l, 0, sizeof *l);
  adem_status st = adem_yaml_lookup(ctx, m, key, &l->e, &v, l->path);
  if (st) return st;
  if (v && !adem_yaml_is_null(v)) {
    if (v->type != YAML_SEQUENCE_NODE) return adem_yaml_wrong_type(ctx, l->e, v, l->path);
    l->node = v;
    l->n = (size_t)(v->data.sequence.items.top - v->data.sequence.items.start);
  }
  if ((l->e->range & ADEM_RANGE_MIN) && (double)l->n < l->e->lo) {
    if (!v) return adem_yaml_missing(ctx, m, l->e, l->path);
    return adem_yaml_fail(ctx, v, l->path, "needs at least %g item%s", l->e->lo, l->e->lo == 1 ? "" : "s");
  }
  return ADEM_OK;
}

adem_status adem_yaml_list_item(case_ctx *ctx, const list_cursor *l, size_t i, map_cursor *item) {
  char path[KEY_PATH_MAX], schema[96];
  snprintf(path, sizeof path, "%.240s[%zu]", l->path, i);
  snprintf(schema, sizeof schema, "%s[]", l->e->path);
  yaml_node_t *v = adem_yaml_node_at(ctx, l->node->data.sequence.items.start[i]);
  if (adem_yaml_is_null(v)) return adem_yaml_fail(ctx, v, path, "empty list item; expected a mapping (key: value)");
  return adem_yaml_map_open(ctx, v, l->node, path, schema, l->e->discriminator, item);
}

/* ---- --set overrides ---- */

adem_status adem_yaml_load_yaml(const char *text, size_t len, yaml_document_t *doc, const char *file,
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
