/* Reading a case's YAML: the document, cursors over its mappings and lists, typed getters checked
 * against the schema table, and messages that name file:line:column (or the --set that made a
 * value). Shared by the case loader (case.c) and the --set grafting (case_set.c). */
#ifndef ADEM_CASE_YAML_H
#define ADEM_CASE_YAML_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <yaml.h>

#include "adem/case.h"
#include "adem/world.h"
#include "log.h"
#include "schema.h"
#include "world_internal.h"

#define KEY_PATH_MAX 256
#define LOC_MAX 640

/* Where the loader is: the YAML document and what has been built so far. */
typedef struct case_ctx {
  yaml_document_t doc;
  bool have_doc;
  const char *file;        /* name used in messages */
  const char *stem_of;     /* file whose stem is the default case name */
  const char *base_dir;    /* folder relative file paths of the case start from */
  const char *const *sets; /* the --set strings */
  int nbase;               /* node ids 1..nbase come from the text, later ones from --set */
  int *origin;             /* origin[id - nbase - 1]: the --set that made node id (-1: none) */
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
  double rmax;  /* largest radius */
  double vmax;  /* largest initial speed of a particle or a plane wall */
  bool has_box; /* bounding box of particles and walls */
  adem_vec3 box_lo, box_hi;
  double initial_overlap; /* limits.initial_overlap, read before the particles */
  bool memory_auto;       /* limits.max_memory: auto (what the machine has) */
  double max_memory;      /* limits.max_memory in bytes, when not auto */
  double poured;          /* particles the pours read so far insert in all */
  bool allow_large_step;  /* limits.allow_large_step */
} case_ctx;

/* A mapping being read: its node (NULL when the section is absent) and where it sits. */
typedef struct map_cursor {
  yaml_node_t *node;
  yaml_node_t *at;           /* node messages point at: the mapping, or its parent */
  char schema[96];           /* prefix of its keys in the schema table */
  const char *discriminator; /* key choosing the variant, or NULL */
  char variant[32];          /* value of the discriminator */
  char path[KEY_PATH_MAX];   /* key path for messages, "materials[0]" */
} map_cursor;

typedef struct list_cursor {
  yaml_node_t *node; /* sequence, NULL when absent or empty */
  const adem_schema_entry *e;
  size_t n;
  char path[KEY_PATH_MAX];
} list_cursor;
/* Keeps the closest candidate that is plausibly a misspelling of word. */
typedef struct suggestion {
  const char *word;
  const char *best;
  size_t dist;
} suggestion;

/* ---- messages ---- */
void adem_yaml_where(const case_ctx *ctx, const yaml_node_t *node, char *buf, size_t n);
void adem_yaml_where_short(const case_ctx *ctx, const yaml_node_t *node, char *buf, size_t n);
adem_status adem_yaml_fail(case_ctx *ctx, const yaml_node_t *node, const char *path, const char *fmt, ...);
adem_status adem_yaml_nomem(case_ctx *ctx);

/* ---- suggestions ---- */
size_t adem_yaml_edit_distance(const char *a, const char *b);
void adem_yaml_suggest_try(suggestion *s, const char *cand);
/* The key of ours that another DEM name stands for (`rolling_resistance` -> `rolling_friction`),
 * or NULL. */
const char *adem_yaml_synonym(const char *word);
void adem_yaml_list_append(char *buf, size_t n, const char *item);

/* ---- scalars ---- */
yaml_node_t *adem_yaml_node_at(case_ctx *ctx, int id);
const char *adem_yaml_sval(const yaml_node_t *v);
bool adem_yaml_is_plain(const yaml_node_t *v);
bool adem_yaml_is_null(const yaml_node_t *v);
void adem_yaml_node_text(const yaml_node_t *v, char *buf, size_t n);
bool adem_yaml_parse_number(const yaml_node_t *v, double *x);
bool adem_yaml_parse_uint(const yaml_node_t *v, uint64_t *x);
bool adem_yaml_parse_bool(const yaml_node_t *v, bool *b);
bool adem_yaml_valid_name(const char *s);
adem_status adem_yaml_wrong_type(case_ctx *ctx, const adem_schema_entry *e, const yaml_node_t *v, const char *path);
adem_status adem_yaml_check_range(case_ctx *ctx, const adem_schema_entry *e, const yaml_node_t *v, const char *path, double x);
adem_status adem_yaml_read_number(case_ctx *ctx, const adem_schema_entry *e, const yaml_node_t *v, const char *path, double *x);
adem_status adem_yaml_read_uint(case_ctx *ctx, const adem_schema_entry *e, const yaml_node_t *v, const char *path, uint64_t *x);
adem_status adem_yaml_read_string(case_ctx *ctx, const adem_schema_entry *e, const yaml_node_t *v, const char *path, char *buf, size_t n);
adem_status adem_yaml_read_vec3(case_ctx *ctx, const adem_schema_entry *e, yaml_node_t *v, const char *path, adem_vec3 *out);
adem_status adem_yaml_read_enum(case_ctx *ctx, const adem_schema_entry *e, const yaml_node_t *v, const char *path, int *index);

/* ---- mappings and lists ---- */
void adem_yaml_join(char *out, size_t n, const char *parent, const char *key);
yaml_node_t *adem_yaml_map_get(case_ctx *ctx, yaml_node_t *map, const char *key);
adem_status adem_yaml_unknown_key(case_ctx *ctx, const map_cursor *m, const yaml_node_t *k);
adem_status adem_yaml_map_open(case_ctx *ctx, yaml_node_t *node, yaml_node_t *parent, const char *path, const char *schema_prefix, const char *discriminator, map_cursor *m);
adem_status adem_yaml_missing(case_ctx *ctx, const map_cursor *m, const adem_schema_entry *e, const char *path);
adem_status adem_yaml_lookup(case_ctx *ctx, const map_cursor *m, const char *key, const adem_schema_entry **e, yaml_node_t **v, char *path);
adem_status adem_yaml_get_number(case_ctx *ctx, const map_cursor *m, const char *key, double *x, yaml_node_t **node);
adem_status adem_yaml_get_uint(case_ctx *ctx, const map_cursor *m, const char *key, uint64_t *x, yaml_node_t **node);
adem_status adem_yaml_get_bool(case_ctx *ctx, const map_cursor *m, const char *key, bool *b);
/* [bool, bool, bool]; items[k] (if not NULL) the item nodes, NULL when the key was not given. */
adem_status adem_yaml_get_bool3(case_ctx *ctx, const map_cursor *m, const char *key, bool b[3],
                                yaml_node_t *items[3]);
adem_status adem_yaml_get_string(case_ctx *ctx, const map_cursor *m, const char *key, char *buf, size_t n, yaml_node_t **node);
adem_status adem_yaml_get_vec3(case_ctx *ctx, const map_cursor *m, const char *key, adem_vec3 *x, yaml_node_t **node);
adem_status adem_yaml_get_enum(case_ctx *ctx, const map_cursor *m, const char *key, int *index);
adem_status adem_yaml_get_auto(case_ctx *ctx, const map_cursor *m, const char *key, bool *is_auto, double *x, yaml_node_t **node);
adem_status adem_yaml_get_pair(case_ctx *ctx, const map_cursor *m, const char *key, char names[2][ADEM_NAME_MAX], yaml_node_t *nodes[2], char paths[2][KEY_PATH_MAX]);
adem_status adem_yaml_get_map(case_ctx *ctx, const map_cursor *m, const char *key, map_cursor *sub);
adem_status adem_yaml_get_list(case_ctx *ctx, const map_cursor *m, const char *key, list_cursor *l);
adem_status adem_yaml_list_item(case_ctx *ctx, const list_cursor *l, size_t i, map_cursor *item);

/* ---- documents ---- */
adem_status adem_yaml_load_yaml(const char *text, size_t len, yaml_document_t *doc, const char *file, bool is_set, adem_error *err);
/* Grafts the --set overrides ctx->sets[0..nsets) onto the document (case_set.c). */
adem_status adem_yaml_apply_sets(case_ctx *ctx, int nsets);

#endif
