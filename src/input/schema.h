/* The case-file schema: one table entry per key. The same table drives the parser (types, defaults,
 * ranges, required keys), its error messages and the Markdown reference. */
#ifndef ADEM_SCHEMA_H
#define ADEM_SCHEMA_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

#if defined(__GNUC__)
#define ADEM_SCHEMA_PRINTF(a, b) __attribute__((format(printf, a, b)))
#else
#define ADEM_SCHEMA_PRINTF(a, b)
#endif

typedef enum adem_schema_type {
  ADEM_SCHEMA_NUMBER,      /* finite real number */
  ADEM_SCHEMA_INT,         /* non-negative integer */
  ADEM_SCHEMA_BOOL,        /* true or false */
  ADEM_SCHEMA_STRING,      /* any text */
  ADEM_SCHEMA_NAME,        /* identifier: a letter or _, then letters, digits, _ or - */
  ADEM_SCHEMA_VEC3,        /* [x, y, z] */
  ADEM_SCHEMA_ENUM,        /* one of `choices` */
  ADEM_SCHEMA_AUTO,        /* `auto` or a number */
  ADEM_SCHEMA_NAME_PAIR,   /* [name, name] */
  ADEM_SCHEMA_MAP,         /* mapping; its keys are entries "path.key" */
  ADEM_SCHEMA_LIST,        /* list of mappings; their keys are entries "path[].key" */
  ADEM_SCHEMA_ID_LIST,     /* list of particle ids [0, 5, ...]; range bounds the item count */
  ADEM_SCHEMA_TABLE,       /* list of rows [t, x, y, z] of 4 numbers; range bounds the row count */
  ADEM_SCHEMA_NUMBER_LIST, /* [a, b, ...] of numbers; range bounds each number */
  ADEM_SCHEMA_SETTINGS,    /* mapping of case-file key paths to values (stages[].set) */
  ADEM_SCHEMA_BOOL3,       /* [bool, bool, bool], one per axis x, y, z */
  ADEM_SCHEMA_LAW_PARAMS   /* in the source table only: one NUMBER per contact-law parameter */
} adem_schema_type;

/* Bounds of a number (for lists: of the item count). */
enum {
  ADEM_RANGE_MIN = 1u,      /* value >= lo */
  ADEM_RANGE_MIN_OPEN = 2u, /* value > lo */
  ADEM_RANGE_MAX = 4u,      /* value <= hi */
  ADEM_RANGE_MAX_OPEN = 8u  /* value < hi */
};

typedef enum adem_schema_need {
  ADEM_SCHEMA_OPTIONAL,
  ADEM_SCHEMA_REQUIRED,
  ADEM_SCHEMA_REQUIRED_IF /* required under the condition in need_doc; the loader checks it */
} adem_schema_need;

typedef struct adem_schema_entry {
  const char *path;    /* "materials[].density": "[]" marks the items of a list */
  const char *variant; /* NULL, or the values of the parent's discriminator it belongs to: "lattice|random" */
  adem_schema_type type;
  const char *unit;    /* SI unit, "" if none */
  const char *def;     /* default as written in a case file; NULL if none */
  const char *def_doc; /* default computed by the loader, in words; NULL if none */
  double lo, hi;       /* bounds, see range */
  unsigned range;      /* ADEM_RANGE_* flags */
  adem_schema_need need;
  const char *need_doc;      /* the condition of ADEM_SCHEMA_REQUIRED_IF */
  const char *choices;       /* ENUM: "hertz|jkr" */
  const char *discriminator; /* MAP/LIST: the key whose value selects which other keys apply */
  const char *doc;           /* one line */
} adem_schema_entry;

/* The entry for key `key` of a mapping whose entries start with `prefix` ("" at the top, "time",
 * "materials[]"), valid for the mapping's variant (NULL or "" if it has none). */
const adem_schema_entry *adem_schema_find(const char *prefix, const char *key, const char *variant);
/* The same ignoring variants: tells "wrong type of set" from "unknown key". */
const adem_schema_entry *adem_schema_find_any(const char *prefix, const char *key);

size_t adem_schema_count(void);
const adem_schema_entry *adem_schema_at(size_t i);
/* True if e is a key of the mapping at prefix with that variant. */
bool adem_schema_is_child(const adem_schema_entry *e, const char *prefix, const char *variant);
/* The last segment of e->path (the key as written in a case file). */
const char *adem_schema_key(const adem_schema_entry *e);

bool adem_schema_in_range(const adem_schema_entry *e, double x);
/* "> 0", "in (-1, 0.5)", ">= 0", or "" when unbounded. */
void adem_schema_describe_range(const adem_schema_entry *e, char *buf, size_t n);
/* What a value must look like: "a number > 0 (kg/m^3)", "one of: hertz, jkr". */
void adem_schema_describe(const adem_schema_entry *e, char *buf, size_t n);
/* Index of s among e->choices, or -1. */
int adem_schema_choice(const adem_schema_entry *e, const char *s);
/* "hertz, jkr" */
void adem_schema_list_choices(const char *choices, char *buf, size_t n);

/* The Markdown reference of every key. */
void adem_schema_write_markdown(FILE *f);

#endif
