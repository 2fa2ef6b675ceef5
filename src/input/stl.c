/* STL files (ASCII and binary) read into triangle soups, then appended to a mesh by the core's
 * topology builder (core/mesh.h). */
#include "stl.h"

#include <inttypes.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "adem/vec3.h"
#include "adem/files.h"
#include "log.h"
#include "world_internal.h"

/* ---------------------------------------------------------------- ASCII STL */

typedef struct lexer {
  const char *p, *end;
  size_t line;
  size_t last_line; /* of the last token: where "the end of the file" is reported */
  const char *path;
} lexer;

typedef struct token {
  const char *s;
  size_t len, line;
} token;

static int is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v'; }

/* Next whitespace-separated token; 0 at the end of the text. */
static int lex_next(lexer *lx, token *t) {
  while (lx->p < lx->end && is_space(*lx->p)) {
    if (*lx->p == '\n') lx->line++;
    lx->p++;
  }
  t->line = lx->line;
  t->s = lx->p;
  while (lx->p < lx->end && !is_space(*lx->p)) lx->p++;
  t->len = (size_t)(lx->p - t->s);
  if (t->len == 0) t->line = lx->last_line;
  lx->last_line = t->line;
  return t->len > 0;
}

/* The rest of the current line, trimmed (the solid's name). */
static void lex_rest_of_line(lexer *lx, char *out, size_t cap) {
  while (lx->p < lx->end && (*lx->p == ' ' || *lx->p == '\t')) lx->p++;
  const char *s = lx->p;
  while (lx->p < lx->end && *lx->p != '\n') lx->p++;
  const char *e = lx->p;
  while (e > s && is_space(e[-1])) --e;
  size_t n = (size_t)(e - s);
  if (n >= cap) n = cap - 1; /* long CAD names are cut: the name is only a label */
  memcpy(out, s, n);
  out[n] = '\0';
}

static int tok_is(const token *t, const char *word) {
  size_t n = strlen(word);
  if (t->len != n) return 0;
  for (size_t i = 0; i < n; ++i) {
    char c = t->s[i];
    if (c >= 'A' && c <= 'Z') c = (char)(c - 'A' + 'a');
    if (c != word[i]) return 0;
  }
  return 1;
}

/* Quotes a token for a message: at most 40 characters. */
static int tok_shown(const token *t) { return t->len > 40 ? 40 : (int)t->len; }

static adem_status expect_word(lexer *lx, const char *word, adem_error *err) {
  token t;
  if (!lex_next(lx, &t))
    return adem_error_set(err, ADEM_ERR_INPUT, "%s:%zu: expected '%s', found the end of the file",
                          lx->path, t.line, word);
  if (!tok_is(&t, word))
    return adem_error_set(err, ADEM_ERR_INPUT, "%s:%zu: expected '%s', found '%.*s'", lx->path,
                          t.line, word, tok_shown(&t), t.s);
  return ADEM_OK;
}

/* A number token; coordinates must be finite, a stored normal that is not becomes zero. */
static adem_status lex_number(lexer *lx, double *x, int coordinate, adem_error *err) {
  token t;
  if (!lex_next(lx, &t))
    return adem_error_set(err, ADEM_ERR_INPUT, "%s:%zu: expected a number, found the end of the file",
                          lx->path, t.line);
  char buf[128];
  char *end = buf;
  if (t.len < sizeof buf) {
    memcpy(buf, t.s, t.len);
    buf[t.len] = '\0';
    *x = strtod(buf, &end);
  }
  if (t.len >= sizeof buf || end != buf + t.len)
    return adem_error_set(err, ADEM_ERR_INPUT, "%s:%zu: bad number '%.*s'", lx->path, t.line,
                          tok_shown(&t), t.s);
  if (!isfinite(*x)) {
    if (coordinate)
      return adem_error_set(err, ADEM_ERR_INPUT, "%s:%zu: non-finite coordinate '%.*s'", lx->path,
                            t.line, tok_shown(&t), t.s);
    *x = 0.0;
  }
  return ADEM_OK;
}

static adem_status lex_vec3(lexer *lx, adem_vec3 *v, int coordinate, adem_error *err) {
  adem_status st = lex_number(lx, &v->x, coordinate, err);
  if (!st) st = lex_number(lx, &v->y, coordinate, err);
  if (!st) st = lex_number(lx, &v->z, coordinate, err);
  return st;
}

static adem_status oom(adem_error *err, const char *path) {
  return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory reading %s", path);
}

/* solid NAME (facet normal n n n / outer loop / vertex x y z (3x) / endloop / endfacet)* endsolid,
 * one or more times. Keywords in any case. */
static adem_status parse_ascii(const char *path, const char *text, size_t n, adem_mesh_soup *s,
                               adem_error *err) {
  lexer lx = {text, text + n, 1, 1, path};
  token t;
  if (!lex_next(&lx, &t) || !tok_is(&t, "solid"))
    return adem_error_set(err, ADEM_ERR_INPUT, "%s:%zu: expected 'solid'", path, t.line);
  for (;;) {
    /* inside a solid, just after the keyword */
    char name[ADEM_NAME_MAX];
    size_t solid_line = t.line;
    lex_rest_of_line(&lx, name, sizeof name);
    adem_mesh_soup_block *b = adem_mesh_soup_block_open(s, name, solid_line);
    if (!b) return oom(err, path);
    for (;;) {
      if (!lex_next(&lx, &t))
        return adem_error_set(err, ADEM_ERR_INPUT,
                              "%s:%zu: the file ends inside solid '%s' (line %zu): 'endsolid' is missing",
                              path, t.line, name, solid_line);
      if (tok_is(&t, "endsolid")) {
        char ignored[ADEM_NAME_MAX];
        lex_rest_of_line(&lx, ignored, sizeof ignored);
        break;
      }
      if (!tok_is(&t, "facet"))
        return adem_error_set(err, ADEM_ERR_INPUT, "%s:%zu: expected 'facet' or 'endsolid', found '%.*s'",
                              path, t.line, tok_shown(&t), t.s);
      size_t facet_line = t.line;
      adem_vec3 normal, c[3];
      adem_status st = expect_word(&lx, "normal", err);
      if (!st) st = lex_vec3(&lx, &normal, 0, err);
      if (!st) st = expect_word(&lx, "outer", err);
      if (!st) st = expect_word(&lx, "loop", err);
      if (st) return st;
      int nv = 0;
      for (;;) {
        if (!lex_next(&lx, &t))
          return adem_error_set(err, ADEM_ERR_INPUT,
                                "%s:%zu: expected 'vertex' or 'endloop', found the end of the file",
                                path, t.line);
        if (!tok_is(&t, "vertex")) break;
        if (nv == 3)
          return adem_error_set(err, ADEM_ERR_INPUT,
                                "%s:%zu: facet (line %zu) has more than 3 vertices", path, t.line,
                                facet_line);
        st = lex_vec3(&lx, &c[nv++], 1, err);
        if (st) return st;
      }
      if (!tok_is(&t, "endloop"))
        return adem_error_set(err, ADEM_ERR_INPUT, "%s:%zu: expected 'vertex' or 'endloop', found '%.*s'",
                              path, t.line, tok_shown(&t), t.s);
      if (nv != 3)
        return adem_error_set(err, ADEM_ERR_INPUT, "%s:%zu: facet (line %zu) has %d vertices, expected 3",
                              path, t.line, facet_line, nv);
      st = expect_word(&lx, "endfacet", err);
      if (st) return st;
      if (!adem_mesh_soup_push(s, c, normal, facet_line)) return oom(err, path);
      s->blocks[s->nblocks - 1].count++;
    }
    if (!lex_next(&lx, &t)) return ADEM_OK;
    if (!tok_is(&t, "solid"))
      return adem_error_set(err, ADEM_ERR_INPUT, "%s:%zu: expected 'solid' or the end of the file, found '%.*s'",
                            path, t.line, tok_shown(&t), t.s);
  }
}

/* ---------------------------------------------------------------- binary STL */

static uint32_t get_u32le(const unsigned char *b) {
  return (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24;
}

static float get_f32le(const unsigned char *b) {
  uint32_t u = get_u32le(b);
  float f;
  memcpy(&f, &u, sizeof f);
  return f;
}

/* 80-byte header, UInt32 count, then per triangle 12 float32 (normal, 3 vertices) and a UInt16. */
static adem_status parse_binary(const char *path, const unsigned char *data, size_t size, adem_mesh_soup *s,
                                adem_error *err) {
  uint32_t n = get_u32le(data + 80);
  uint64_t expected = 84 + 50 * (uint64_t)n;
  if ((uint64_t)size < expected) {
    uint64_t k = (size - 84) / 50;
    return adem_error_set(err, ADEM_ERR_INPUT,
                          "%s: binary STL truncated: the header announces %" PRIu32
                          " triangles (%" PRIu64 " bytes) but the file has %zu bytes; triangle %" PRIu64
                          " (byte offset %" PRIu64 ") is incomplete",
                          path, n, expected, size, k, 84 + 50 * k);
  }
  if ((uint64_t)size > expected)
    return adem_error_set(err, ADEM_ERR_INPUT,
                          "%s: binary STL size mismatch: the header announces %" PRIu32
                          " triangles (%" PRIu64 " bytes) but the file has %zu bytes (extra data at byte offset %" PRIu64 ")",
                          path, n, expected, size, expected);
  if (!adem_mesh_soup_block_open(s, "", 0)) return oom(err, path);
  for (uint32_t i = 0; i < n; ++i) {
    const unsigned char *t = data + 84 + 50 * (size_t)i;
    double v[12];
    for (int k = 0; k < 12; ++k) {
      v[k] = (double)get_f32le(t + 4 * k);
      if (k >= 3 && !isfinite(v[k]))
        return adem_error_set(err, ADEM_ERR_INPUT,
                              "%s: triangle %" PRIu32 " (byte offset %zu): non-finite coordinate %g",
                              path, i, (size_t)(t - data) + 4 * (size_t)k, v[k]);
    }
    adem_vec3 normal = v3(v[0], v[1], v[2]);
    if (!v3_isfinite(normal)) normal = v3_zero();
    adem_vec3 c[3] = {v3(v[3], v[4], v[5]), v3(v[6], v[7], v[8]), v3(v[9], v[10], v[11])};
    if (!adem_mesh_soup_push(s, c, normal, i)) return oom(err, path);
    s->blocks[0].count++;
  }
  return ADEM_OK;
}

/* ASCII if it starts with `solid`, has no NUL byte and has the keywords early on. A binary header
 * may also start with "solid" (some exporters write it), but its count and floats bring NULs. */
/* Whether word occurs in the size bytes at data (no terminating NUL needed). */
static int contains(const char *data, size_t size, const char *word) {
  size_t n = strlen(word);
  for (size_t i = 0; i + n <= size; ++i)
    if (data[i] == word[0] && memcmp(data + i, word, n) == 0) return 1;
  return 0;
}

static int looks_ascii(const char *data, size_t size) {
  size_t i = 0;
  while (i < size && is_space(data[i])) ++i;
  if (size - i < 5 || strncmp(data + i, "solid", 5) != 0) return 0;
  size_t probe = size < 4096 ? size : 4096;
  if (memchr(data, '\0', probe)) return 0;
  return contains(data, size, "facet") || contains(data, size, "endsolid");
}

/* The file name without folders and its last extension. */
static void file_stem(const char *path, char *out, size_t cap) {
  const char *slash = strrchr(path, '/');
  const char *base = slash ? slash + 1 : path;
  const char *dot = strrchr(base, '.');
  size_t n = dot && dot != base ? (size_t)(dot - base) : strlen(base);
  if (n >= cap) n = cap - 1;
  memcpy(out, base, n);
  out[n] = '\0';
}

/* Group names: the given one, else the solid's, else the stem; PREFIX.SOLID for several blocks.
 * A name already in the mesh or in this file is an error. */
static adem_status name_blocks(const adem_mesh *mesh, adem_mesh_soup *s, const char *path,
                               const char *group_name, int ascii, adem_error *err) {
  char stem[ADEM_NAME_MAX];
  file_stem(path, stem, sizeof stem);
  const char *prefix = group_name && *group_name ? group_name : stem;
  for (size_t b = 0; b < s->nblocks; ++b) {
    adem_mesh_soup_block *bl = &s->blocks[b];
    char solid[ADEM_NAME_MAX];
    memcpy(solid, bl->name, sizeof solid);
    /* Composed at full length, then cut: a long name only labels output. */
    char full[2 * ADEM_NAME_MAX + 24];
    if (s->nblocks == 1)
      snprintf(full, sizeof full, "%s", group_name && *group_name ? group_name : *solid ? solid
                                                                                        : stem);
    else if (*solid)
      snprintf(full, sizeof full, "%s.%s", prefix, solid);
    else
      snprintf(full, sizeof full, "%s.%zu", prefix, b + 1);
    size_t len = strlen(full);
    if (len >= sizeof bl->name) len = sizeof bl->name - 1;
    memcpy(bl->name, full, len);
    bl->name[len] = '\0';
    int dup = adem_mesh_find_group(mesh, bl->name) >= 0;
    for (size_t c = 0; c < b && !dup; ++c) dup = strcmp(s->blocks[c].name, bl->name) == 0;
    if (dup) {
      if (ascii)
        return adem_error_set(err, ADEM_ERR_INPUT,
                              "%s:%zu: mesh group name '%s' is already used; give each file or solid a distinct name",
                              path, bl->line, bl->name);
      return adem_error_set(err, ADEM_ERR_INPUT,
                            "%s: mesh group name '%s' is already used; give each file a distinct name",
                            path, bl->name);
    }
  }
  return ADEM_OK;
}

adem_status adem_stl_parse(const char *data, size_t size, const char *path,
                           const adem_mesh *mesh, const char *group_name, adem_mesh_soup *s,
                           int *ascii, adem_error *err) {
  memset(s, 0, sizeof *s);
  *ascii = 0;
  adem_status st;
  /* An ASCII file cannot pass the size test by accident: text bytes at 80..83 announce at least
   * 0x09090909 triangles, a file of 7.5 GB. */
  if (size >= 84 && (uint64_t)size == 84 + 50 * (uint64_t)get_u32le((const unsigned char *)data + 80))
    st = parse_binary(path, (const unsigned char *)data, size, s, err);
  else if (looks_ascii(data, size)) {
    *ascii = 1;
    st = parse_ascii(path, data, size, s, err);
  } else if (size >= 84)
    st = parse_binary(path, (const unsigned char *)data, size, s, err);
  else
    st = adem_error_set(err, ADEM_ERR_INPUT,
                        "%s: not an STL file: %zu bytes is too short for a binary STL (84-byte "
                        "header) and the text is not 'solid ... facet ... endsolid'",
                        path, size);
  if (!st) st = name_blocks(mesh, s, path, group_name, *ascii, err);
  if (st) adem_mesh_soup_free(s);
  return st;
}

adem_status adem_stl_read(const char *path, const adem_mesh *mesh, const char *group_name,
                          adem_mesh_soup *s, int *ascii, adem_error *err) {
  char *data = NULL;
  size_t size = 0;
  memset(s, 0, sizeof *s);
  *ascii = 0;
  adem_status st = adem_file_read_all(path, &data, &size, err);
  if (st) return st;
  st = adem_stl_parse(data, size, path, mesh, group_name, s, ascii, err);
  free(data);
  return st;
}

adem_status adem_mesh_load_stl_bytes(const char *data, size_t size, const char *path,
                                     const adem_mesh_transform *tf, const char *group_name,
                                     adem_mesh *mesh, adem_error *err) {
  adem_mesh_transform def = adem_default_mesh_transform();
  if (!tf) tf = &def;
  adem_status st = adem_mesh_check_transform(tf, path, err);
  if (st) return st;
  adem_mesh_soup s;
  int ascii;
  st = adem_stl_parse(data, size, path, mesh, group_name, &s, &ascii, err);
  if (st) return st;
  st = adem_mesh_append_soup(mesh, &s, tf, path, ascii, err);
  adem_mesh_soup_free(&s);
  return st;
}

adem_status adem_mesh_load_stl(const char *path, const adem_mesh_transform *tf,
                               const char *group_name, adem_mesh *mesh, adem_error *err) {
  adem_mesh_transform def = adem_default_mesh_transform();
  if (!tf) tf = &def;
  adem_status st = adem_mesh_check_transform(tf, path, err);
  if (st) return st;
  adem_mesh_soup s;
  int ascii;
  st = adem_stl_read(path, mesh, group_name, &s, &ascii, err);
  if (st) return st;
  st = adem_mesh_append_soup(mesh, &s, tf, path, ascii, err);
  adem_mesh_soup_free(&s);
  return st;
}

adem_status adem_world_add_stl(adem_world *w, const char *path, const adem_mesh_transform *tf,
                               const char *name, adem_vec3 velocity, adem_error *err) {
  adem_mesh_transform def = adem_default_mesh_transform();
  if (!tf) tf = &def;
  adem_status st = adem_world_check_mesh(w, path, tf, velocity, err);
  if (!st) st = adem_mesh_check_transform(tf, path, err);
  if (st) return st;
  adem_mesh_soup s;
  int ascii;
  st = adem_stl_read(path, &w->walls.mesh, name, &s, &ascii, err);
  if (st) return st;
  st = adem_world_add_mesh_soup(w, &s, tf, path, ascii, name, velocity, err);
  adem_mesh_soup_free(&s);
  return st;
}
