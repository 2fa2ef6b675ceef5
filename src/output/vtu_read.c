/* Particle-frame reader: a small tag scanner over the XML header, then bounds-checked copies of
 * the raw appended blocks (each an 8-byte size, then the data). See vtu_read.h. */
#include "adem/frames.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static adem_status fail(adem_error *err, adem_status st, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

static adem_status fail(adem_error *err, adem_status st, const char *fmt, ...) {
  if (err) {
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err->message, sizeof err->message, fmt, ap);
    va_end(ap);
    err->status = st;
  }
  return st;
}

/* A piece of the input text (not NUL-terminated). */
typedef struct slice {
  const char *p;
  size_t n;
} slice;

static int slice_is(slice s, const char *lit) {
  size_t k = strlen(lit);
  return s.n == k && memcmp(s.p, lit, k) == 0;
}

/* One XML tag of the header: <name attrs>, </name> or <name attrs/>. */
typedef struct tag {
  slice name, attrs;
  int closing, self_closing;
  size_t at, end; /* byte offsets of '<' and one past '>' */
} tag;

static int is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }
static int is_name_char(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
         c == ':' || c == '-' || c == '.';
}

/* Finds the tag at or after *pos in s[0..len). Returns 1 with *t filled, 0 when there is no
 * further '<', -1 when a tag is malformed (*pos is then the offset of the problem). Comments,
 * <?...?> and <!...> are skipped. */
static int next_tag(const char *s, size_t len, size_t *pos, tag *t) {
  size_t i = *pos;
  for (;;) {
    while (i < len && s[i] != '<') ++i;
    if (i >= len) return 0;
    if (i + 3 < len && memcmp(s + i, "<!--", 4) == 0) {
      size_t j = i + 4;
      while (j + 2 < len && memcmp(s + j, "-->", 3) != 0) ++j;
      if (j + 2 >= len) {
        *pos = i;
        return -1;
      }
      i = j + 3;
      continue;
    }
    if (i + 1 < len && (s[i + 1] == '?' || s[i + 1] == '!')) {
      size_t j = i + 2;
      while (j < len && s[j] != '>') ++j;
      if (j >= len) {
        *pos = i;
        return -1;
      }
      i = j + 1;
      continue;
    }
    break;
  }
  memset(t, 0, sizeof *t);
  t->at = i;
  size_t j = i + 1;
  if (j < len && s[j] == '/') {
    t->closing = 1;
    ++j;
  }
  size_t name0 = j;
  while (j < len && is_name_char(s[j])) ++j;
  if (j == name0) {
    *pos = i;
    return -1;
  }
  t->name = (slice){s + name0, j - name0};
  size_t attr0 = j;
  char quote = 0;
  while (j < len && (quote || s[j] != '>')) {
    if (quote) {
      if (s[j] == quote) quote = 0;
    } else if (s[j] == '"' || s[j] == '\'') {
      quote = s[j];
    } else if (s[j] == '<') {
      *pos = j;
      return -1;
    }
    ++j;
  }
  if (j >= len) {
    *pos = i;
    return -1;
  }
  size_t attr1 = j;
  if (attr1 > attr0 && s[attr1 - 1] == '/') {
    t->self_closing = 1;
    --attr1;
  }
  t->attrs = (slice){s + attr0, attr1 - attr0};
  t->end = j + 1;
  *pos = j + 1;
  return 1;
}

/* Value of attribute KEY of tag T: 1 found, 0 absent, -1 malformed attribute list. KEY NULL
 * checks the whole list (0 when well-formed). */
static int tag_attr(const tag *t, const char *key, slice *value) {
  const char *s = t->attrs.p;
  size_t n = t->attrs.n, i = 0;
  for (;;) {
    while (i < n && is_space(s[i])) ++i;
    if (i >= n) return 0;
    size_t k0 = i;
    while (i < n && is_name_char(s[i])) ++i;
    if (i == k0) return -1;
    slice k = {s + k0, i - k0};
    while (i < n && is_space(s[i])) ++i;
    if (i >= n || s[i] != '=') return -1;
    ++i;
    while (i < n && is_space(s[i])) ++i;
    if (i >= n || (s[i] != '"' && s[i] != '\'')) return -1;
    char q = s[i++];
    size_t v0 = i;
    while (i < n && s[i] != q) ++i;
    if (i >= n) return -1;
    if (key && slice_is(k, key)) {
      *value = (slice){s + v0, i - v0};
      return 1;
    }
    ++i;
  }
}

/* A decimal integer without sign or spaces, at most MAX. */
static int parse_u64(slice v, uint64_t max, uint64_t *out) {
  if (v.n == 0 || v.n > 20) return 0;
  uint64_t x = 0;
  for (size_t i = 0; i < v.n; ++i) {
    if (v.p[i] < '0' || v.p[i] > '9') return 0;
    uint64_t d = (uint64_t)(v.p[i] - '0');
    if (x > (max - d) / 10) return 0;
    x = 10 * x + d;
  }
  *out = x;
  return 1;
}

/* A number in text (surrounding blanks allowed), finite. */
static int parse_double(slice v, double *out) {
  char buf[64];
  size_t a = 0, b = v.n;
  while (a < b && is_space(v.p[a])) ++a;
  while (b > a && is_space(v.p[b - 1])) --b;
  if (b == a || b - a >= sizeof buf) return 0;
  memcpy(buf, v.p + a, b - a);
  buf[b - a] = '\0';
  char *end;
  errno = 0;
  double x = strtod(buf, &end);
  if (*end != '\0' || errno == ERANGE || !isfinite(x)) return 0;
  *out = x;
  return 1;
}

static const char *machine_order(void) {
  const uint16_t one = 1;
  unsigned char b;
  memcpy(&b, &one, 1);
  return b == 1 ? "LittleEndian" : "BigEndian";
}

/* An appended array named in the header. */
typedef struct array_ref {
  int found;
  slice type;
  uint64_t ncomp, offset;
  size_t tag_at; /* byte offset of its tag, for messages */
} array_ref;

enum { MAX_ARRAYS = 64 };

typedef struct header {
  uint64_t npoints;
  uint64_t offsets[MAX_ARRAYS]; /* of every appended DataArray, to check that each block fits */
  size_t noffsets;
  int have_piece;
  array_ref radius, position, id, velocity, mass; /* a particle frame's */
  array_ref force, kind, id_a, id_b;              /* a contact frame's cell data */
  int poly;                                       /* a contact frame: PolyData of lines */
  uint64_t nlines;                                /* its NumberOfLines */
  double time;
  int64_t step;
  size_t data; /* offset of the first byte after '_' */
} header;

#define NAME_OF(name) ((name) ? (name) : "VTU data")

/* Records a DataArray of the piece. */
static adem_status read_array_tag(const tag *t, const char *name, array_ref *a, adem_error *err) {
  slice v;
  if (a->found)
    return fail(err, ADEM_ERR_INPUT, "%s: byte %zu: a second DataArray of the same name",
                NAME_OF(name), t->at);
  a->found = 1;
  a->tag_at = t->at;
  if (tag_attr(t, "type", &a->type) != 1)
    return fail(err, ADEM_ERR_INPUT, "%s: byte %zu: DataArray without a type", NAME_OF(name), t->at);
  int r = tag_attr(t, "format", &v);
  if (r != 1 || !slice_is(v, "appended"))
    return fail(err, ADEM_ERR_INPUT, "%s: byte %zu: DataArray format is not \"appended\"",
                NAME_OF(name), t->at);
  r = tag_attr(t, "NumberOfComponents", &v);
  a->ncomp = 1;
  if (r < 0 || (r == 1 && (!parse_u64(v, 64, &a->ncomp) || a->ncomp == 0)))
    return fail(err, ADEM_ERR_INPUT, "%s: byte %zu: bad NumberOfComponents", NAME_OF(name), t->at);
  if (tag_attr(t, "offset", &v) != 1 || !parse_u64(v, UINT64_MAX, &a->offset))
    return fail(err, ADEM_ERR_INPUT, "%s: byte %zu: DataArray without a valid offset",
                NAME_OF(name), t->at);
  return ADEM_OK;
}

/* The text between a FieldData DataArray's start tag and the next '<'. */
static slice text_after(const char *s, size_t len, const tag *t) {
  size_t i = t->end;
  while (i < len && s[i] != '<') ++i;
  return (slice){s + t->end, i - t->end};
}

/* Offset of the first occurrence of LIT in s[0..len), or len. */
static size_t find(const char *s, size_t len, size_t from, const char *lit) {
  size_t k = strlen(lit);
  for (size_t i = from; i + k <= len; ++i)
    if (s[i] == lit[0] && memcmp(s + i, lit, k) == 0) return i;
  return len;
}

/* Every attribute of T is name="value" or name='value'. */
static int attrs_ok(const tag *t) {
  slice v;
  return tag_attr(t, NULL, &v) == 0;
}

static adem_status parse_header(const char *s, size_t total, const char *name, int poly,
                                header *h, adem_error *err) {
  size_t len = total;
  memset(h, 0, sizeof *h);
  h->poly = poly;
  const char *grid = poly ? "PolyData" : "UnstructuredGrid";
  /* The XML ends with the <AppendedData ...> start tag; what follows is binary and is never
   * scanned for tags. */
  size_t xml_end = find(s, len, 0, "<AppendedData");
  if (xml_end == len)
    return fail(err, ADEM_ERR_INPUT, "%s: no <AppendedData> section: not an adem particle frame",
                NAME_OF(name));
  {
    size_t j = xml_end;
    while (j < len && s[j] != '>') ++j;
    if (j >= len)
      return fail(err, ADEM_ERR_INPUT, "%s: byte %zu: unterminated <AppendedData> tag",
                  NAME_OF(name), xml_end);
    len = j + 1; /* the scan below stops after this tag */
  }
  h->time = NAN;
  h->step = -1;
  int in_vtk = 0, in_grid = 0, in_field = 0, in_piece = 0, in_pdata = 0, in_points = 0;
  int in_cdata = 0;
  int seen_vtk = 0;
  size_t pos = 0;
  tag t;
  for (;;) {
    int r = next_tag(s, len, &pos, &t);
    if (r < 0)
      return fail(err, ADEM_ERR_INPUT, "%s: byte %zu: malformed XML tag", NAME_OF(name), pos);
    if (r == 0)
      return fail(err, ADEM_ERR_INPUT, "%s: byte %zu: <AppendedData> is not a tag of its own",
                  NAME_OF(name), xml_end);
    if (!attrs_ok(&t))
      return fail(err, ADEM_ERR_INPUT, "%s: byte %zu: malformed attributes in <%.*s> (expected "
                                       "name=\"value\")",
                  NAME_OF(name), t.at, (int)(t.name.n > 40 ? 40 : t.name.n),
                  t.name.p);
    slice v;
    if (slice_is(t.name, "VTKFile")) {
      if (t.closing) {
        in_vtk = 0;
        continue;
      }
      if (seen_vtk)
        return fail(err, ADEM_ERR_INPUT, "%s: byte %zu: a second <VTKFile>", NAME_OF(name), t.at);
      seen_vtk = in_vtk = 1;
      if (tag_attr(&t, "type", &v) != 1 || !slice_is(v, grid))
        return fail(err, ADEM_ERR_INPUT, "%s: VTKFile type is not \"%s\"", NAME_OF(name), grid);
      if (tag_attr(&t, "byte_order", &v) != 1 || !slice_is(v, machine_order()))
        return fail(err, ADEM_ERR_INPUT, "%s: byte_order is not \"%s\" (this machine's; files are "
                                         "read without swapping)",
                    NAME_OF(name), machine_order());
      if (tag_attr(&t, "header_type", &v) != 1 || !slice_is(v, "UInt64"))
        return fail(err, ADEM_ERR_INPUT, "%s: header_type is not \"UInt64\" (adem writes UInt64 "
                                         "block headers)",
                    NAME_OF(name));
      continue;
    }
    if (!in_vtk)
      return fail(err, ADEM_ERR_INPUT, "%s: byte %zu: <%.*s> outside <VTKFile>", NAME_OF(name),
                  t.at, (int)(t.name.n > 40 ? 40 : t.name.n), t.name.p);
    if (slice_is(t.name, "AppendedData")) {
      if (t.closing || t.self_closing || t.at != xml_end)
        return fail(err, ADEM_ERR_INPUT, "%s: byte %zu: empty <AppendedData>", NAME_OF(name), t.at);
      if (tag_attr(&t, "encoding", &v) != 1 || !slice_is(v, "raw"))
        return fail(err, ADEM_ERR_INPUT, "%s: AppendedData encoding is not \"raw\"", NAME_OF(name));
      size_t i = t.end;
      while (i < total && is_space(s[i])) ++i;
      if (i >= total || s[i] != '_')
        return fail(err, ADEM_ERR_INPUT, "%s: byte %zu: the appended data does not start with '_'",
                    NAME_OF(name), i);
      h->data = i + 1;
      break;
    }
    if (slice_is(t.name, grid)) {
      in_grid = !t.closing;
    } else if (slice_is(t.name, "FieldData")) {
      in_field = !t.closing && !t.self_closing;
    } else if (slice_is(t.name, "Piece")) {
      if (t.closing) {
        in_piece = 0;
        continue;
      }
      if (!in_grid)
        return fail(err, ADEM_ERR_INPUT, "%s: byte %zu: <Piece> outside <%s>", NAME_OF(name),
                    t.at, grid);
      if (h->have_piece)
        return fail(err, ADEM_ERR_INPUT, "%s: byte %zu: more than one <Piece> (adem writes one)",
                    NAME_OF(name), t.at);
      h->have_piece = in_piece = 1;
      if (tag_attr(&t, "NumberOfPoints", &v) != 1 || !parse_u64(v, UINT64_MAX, &h->npoints))
        return fail(err, ADEM_ERR_INPUT, "%s: byte %zu: Piece without a valid NumberOfPoints",
                    NAME_OF(name), t.at);
      if (poly && (tag_attr(&t, "NumberOfLines", &v) != 1 ||
                   !parse_u64(v, UINT64_MAX, &h->nlines) || h->npoints != 2 * h->nlines))
        return fail(err, ADEM_ERR_INPUT, "%s: byte %zu: Piece without a valid NumberOfLines (two "
                                         "points per line)",
                    NAME_OF(name), t.at);
    } else if (slice_is(t.name, "PointData")) {
      in_pdata = in_piece && !t.closing && !t.self_closing;
    } else if (slice_is(t.name, "CellData")) {
      in_cdata = in_piece && !t.closing && !t.self_closing;
    } else if (slice_is(t.name, "Points")) {
      in_points = in_piece && !t.closing && !t.self_closing;
    } else if (slice_is(t.name, "DataArray") && !t.closing) {
      slice nm = {0}, fmt, off;
      if (tag_attr(&t, "format", &fmt) == 1 && slice_is(fmt, "appended")) {
        if (h->noffsets == MAX_ARRAYS)
          return fail(err, ADEM_ERR_INPUT, "%s: byte %zu: more than %d appended DataArrays",
                      NAME_OF(name), t.at, MAX_ARRAYS);
        if (tag_attr(&t, "offset", &off) != 1 || !parse_u64(off, UINT64_MAX, &h->offsets[h->noffsets]))
          return fail(err, ADEM_ERR_INPUT, "%s: byte %zu: DataArray without a valid offset",
                      NAME_OF(name), t.at);
        h->noffsets++;
      }
      if (tag_attr(&t, "Name", &nm) < 0)
        return fail(err, ADEM_ERR_INPUT, "%s: byte %zu: malformed DataArray attributes",
                    NAME_OF(name), t.at);
      if (in_field && !in_piece && !t.self_closing) {
        slice text = text_after(s, len, &t);
        if (slice_is(nm, "TimeValue")) {
          if (!parse_double(text, &h->time))
            return fail(err, ADEM_ERR_INPUT, "%s: byte %zu: TimeValue is not a finite number",
                        NAME_OF(name), t.end);
        } else if (slice_is(nm, "Step")) {
          uint64_t st;
          size_t a = 0, b = text.n;
          while (a < b && is_space(text.p[a])) ++a;
          while (b > a && is_space(text.p[b - 1])) --b;
          if (!parse_u64((slice){text.p + a, b - a}, INT64_MAX, &st))
            return fail(err, ADEM_ERR_INPUT, "%s: byte %zu: Step is not a non-negative integer",
                        NAME_OF(name), t.end);
          h->step = (int64_t)st;
        }
      } else if (in_points) {
        adem_status e = read_array_tag(&t, name, &h->position, err);
        if (e) return e;
      } else if (in_pdata || in_cdata) {
        static const char *const pnames[] = {"radius", "id", "velocity", "mass"};
        static const char *const cnames[] = {"force", "kind", "id_a", "id_b"};
        array_ref *pref[] = {&h->radius, &h->id, &h->velocity, &h->mass};
        array_ref *cref[] = {&h->force, &h->kind, &h->id_a, &h->id_b};
        for (int q = 0; q < 4; ++q) {
          if (in_pdata ? !slice_is(nm, pnames[q]) : !slice_is(nm, cnames[q])) continue;
          adem_status e = read_array_tag(&t, name, in_pdata ? pref[q] : cref[q], err);
          if (e) return e;
        }
      }
    }
  }
  if (!h->have_piece)
    return fail(err, ADEM_ERR_INPUT, "%s: no <Piece>", NAME_OF(name));
  if (!h->position.found)
    return fail(err, ADEM_ERR_INPUT, "%s: no <Points> DataArray (the centres)", NAME_OF(name));
  if (poly) {
    const array_ref *need[] = {&h->force, &h->kind, &h->id_a, &h->id_b};
    const char *names[] = {"force", "kind", "id_a", "id_b"};
    for (int q = 0; q < 4; ++q)
      if (!need[q]->found)
        return fail(err, ADEM_ERR_INPUT, "%s: no CellData DataArray \"%s\"", NAME_OF(name),
                    names[q]);
    return ADEM_OK;
  }
  if (!h->radius.found)
    return fail(err, ADEM_ERR_INPUT, "%s: no PointData DataArray \"radius\"", NAME_OF(name));
  return ADEM_OK;
}

/* Checks that array A (of element type TYPE, NCOMP components of SIZE bytes) has one block of
 * exactly n * ncomp * size bytes inside the data, and returns a pointer to its first byte. */
static adem_status locate_block(const unsigned char *base, size_t len, const header *h,
                                const array_ref *a, const char *what, const char *type,
                                uint64_t ncomp, size_t size, const char *name,
                                const unsigned char **out, adem_error *err) {
  uint64_t count = h->poly && a != &h->position ? h->nlines : h->npoints;
  if (!slice_is(a->type, type))
    return fail(err, ADEM_ERR_INPUT, "%s: byte %zu: DataArray \"%s\" has type \"%.*s\", not %s",
                NAME_OF(name), a->tag_at, what, (int)(a->type.n > 32 ? 32 : a->type.n), a->type.p,
                type);
  if (a->ncomp != ncomp)
    return fail(err, ADEM_ERR_INPUT,
                "%s: byte %zu: DataArray \"%s\" has %llu components, not %llu", NAME_OF(name),
                a->tag_at, what, (unsigned long long)a->ncomp, (unsigned long long)ncomp);
  size_t avail = len - h->data; /* bytes from the '_' marker to the end of the file */
  if (a->offset > avail || avail - a->offset < 8)
    return fail(err, ADEM_ERR_INPUT,
                "%s: DataArray \"%s\": offset %llu is past the end of the appended data (%zu bytes)",
                NAME_OF(name), what, (unsigned long long)a->offset, avail);
  uint64_t nbytes;
  memcpy(&nbytes, base + h->data + a->offset, 8);
  /* n * ncomp * size without overflow: n was bounded by the file size before. */
  uint64_t want = count * ncomp * (uint64_t)size;
  if (nbytes != want)
    return fail(err, ADEM_ERR_INPUT,
                "%s: DataArray \"%s\": block of %llu bytes, expected %llu (%llu tuples x %llu x %zu)",
                NAME_OF(name), what, (unsigned long long)nbytes, (unsigned long long)want,
                (unsigned long long)count, (unsigned long long)ncomp, size);
  if (nbytes > avail - a->offset - 8)
    return fail(err, ADEM_ERR_INPUT,
                "%s: DataArray \"%s\": block at offset %llu of %llu bytes runs past the end of "
                "the file (truncated?)",
                NAME_OF(name), what, (unsigned long long)a->offset, (unsigned long long)nbytes);
  *out = base + h->data + a->offset + 8;
  return ADEM_OK;
}

void adem_vtu_frame_free(adem_vtu_frame *frame) {
  if (!frame) return;
  free(frame->pos);
  free(frame->radius);
  free(frame->id);
  free(frame->velocity);
  free(frame->mass);
  memset(frame, 0, sizeof *frame);
}

/* Every appended block (the ones not read too) lies inside the data, and the data section is
 * closed after the last one: a file cut anywhere is refused. */
static adem_status check_blocks(const unsigned char *base, size_t len, const header *h,
                                const char *name, adem_error *err) {
  size_t avail = len - h->data, last = 0;
  for (size_t k = 0; k < h->noffsets; ++k) {
    uint64_t off = h->offsets[k], nbytes;
    if (off > avail || avail - off < 8)
      return fail(err, ADEM_ERR_INPUT,
                  "%s: an appended block at offset %llu starts past the end of the data (%zu "
                  "bytes; truncated?)",
                  NAME_OF(name), (unsigned long long)off, avail);
    memcpy(&nbytes, base + h->data + off, 8);
    if (nbytes > avail - off - 8)
      return fail(err, ADEM_ERR_INPUT,
                  "%s: the appended block at offset %llu (%llu bytes) runs past the end of the "
                  "file (truncated?)",
                  NAME_OF(name), (unsigned long long)off,
                  (unsigned long long)nbytes);
    if (off + 8 + nbytes > last) last = (size_t)(off + 8 + nbytes);
  }
  if (find((const char *)base, len, h->data + last, "</AppendedData>") == len)
    return fail(err, ADEM_ERR_INPUT, "%s: no </AppendedData> after the last block (truncated?)",
                NAME_OF(name));
  return ADEM_OK;
}

adem_status adem_vtu_read_memory(const void *data, size_t len, const char *name,
                                 adem_vtu_frame *frame, adem_error *err) {
  memset(frame, 0, sizeof *frame);
  if (!data && len) return fail(err, ADEM_ERR_INPUT, "%s: no data", NAME_OF(name));
  const unsigned char *base = data;
  header h;
  adem_status st = parse_header((const char *)data, len, name, 0, &h, err);
  if (st) return st;
  /* Every point needs at least 32 bytes (radius + centre): bounds n before any product. */
  if (h.npoints > (len - h.data) / 32)
    return fail(err, ADEM_ERR_INPUT,
                "%s: NumberOfPoints %llu does not fit in the %zu bytes of appended data",
                NAME_OF(name), (unsigned long long)h.npoints, len - h.data);
  st = check_blocks(base, len, &h, name, err);
  if (st) return st;
  const unsigned char *rb, *pb, *ib = NULL, *vb = NULL, *mb = NULL;
  st = locate_block(base, len, &h, &h.radius, "radius", "Float64", 1, 8, name, &rb, err);
  if (!st) st = locate_block(base, len, &h, &h.position, "position", "Float64", 3, 8, name, &pb, err);
  if (!st && h.id.found)
    st = locate_block(base, len, &h, &h.id, "id", "Int64", 1, 8, name, &ib, err);
  if (!st && h.velocity.found)
    st = locate_block(base, len, &h, &h.velocity, "velocity", "Float64", 3, 8, name, &vb, err);
  if (!st && h.mass.found)
    st = locate_block(base, len, &h, &h.mass, "mass", "Float64", 1, 8, name, &mb, err);
  if (st) return st;

  size_t n = (size_t)h.npoints;
  adem_vtu_frame f = {.n = n, .time = h.time, .step = h.step};
  size_t cap = n ? n : 1;
  f.pos = malloc(cap * sizeof *f.pos);
  f.radius = malloc(cap * sizeof *f.radius);
  if (ib) f.id = malloc(cap * sizeof *f.id);
  if (vb) f.velocity = malloc(cap * sizeof *f.velocity);
  if (mb) f.mass = malloc(cap * sizeof *f.mass);
  if (!f.pos || !f.radius || (ib && !f.id) || (vb && !f.velocity) || (mb && !f.mass)) {
    adem_vtu_frame_free(&f);
    return fail(err, ADEM_ERR_NOMEM, "%s: out of memory for %zu particles", NAME_OF(name), n);
  }
  for (size_t i = 0; i < n; ++i) {
    double r, x[3];
    memcpy(&r, rb + 8 * i, 8);
    memcpy(x, pb + 24 * i, 24);
    if (!(isfinite(r) && r > 0.0)) {
      adem_vtu_frame_free(&f);
      return fail(err, ADEM_ERR_INPUT, "%s: particle %zu: radius %g is not a finite number > 0",
                  NAME_OF(name), i, r);
    }
    if (!(isfinite(x[0]) && isfinite(x[1]) && isfinite(x[2]))) {
      adem_vtu_frame_free(&f);
      return fail(err, ADEM_ERR_INPUT, "%s: particle %zu: centre (%g, %g, %g) is not finite",
                  NAME_OF(name), i, x[0], x[1], x[2]);
    }
    f.radius[i] = r;
    f.pos[i] = (adem_vec3){x[0], x[1], x[2]};
    if (ib) memcpy(&f.id[i], ib + 8 * i, 8);
    if (vb) {
      memcpy(x, vb + 24 * i, 24);
      f.velocity[i] = (adem_vec3){x[0], x[1], x[2]};
    }
    if (mb) {
      memcpy(&r, mb + 8 * i, 8);
      if (!(isfinite(r) && r > 0.0)) {
        adem_vtu_frame_free(&f);
        return fail(err, ADEM_ERR_INPUT, "%s: particle %zu: mass %g is not a finite number > 0",
                    NAME_OF(name), i, r);
      }
      f.mass[i] = r;
    }
  }
  *frame = f;
  return ADEM_OK;
}

void adem_contact_frame_free(adem_contact_frame *frame) {
  if (!frame) return;
  free(frame->p0);
  free(frame->p1);
  free(frame->force);
  free(frame->kind);
  free(frame->id_a);
  free(frame->id_b);
  memset(frame, 0, sizeof *frame);
}

adem_status adem_contact_frame_read_memory(const void *data, size_t len, const char *name,
                                           adem_contact_frame *frame, adem_error *err) {
  memset(frame, 0, sizeof *frame);
  if (!data && len) return fail(err, ADEM_ERR_INPUT, "%s: no data", NAME_OF(name));
  const unsigned char *base = data;
  header h;
  adem_status st = parse_header((const char *)data, len, name, 1, &h, err);
  if (st) return st;
  /* every line needs at least 92 bytes (two points, a force, kind and two ids) */
  if (h.nlines > (len - h.data) / 92)
    return fail(err, ADEM_ERR_INPUT,
                "%s: NumberOfLines %llu does not fit in the %zu bytes of appended data",
                NAME_OF(name), (unsigned long long)h.nlines, len - h.data);
  st = check_blocks(base, len, &h, name, err);
  const unsigned char *pb, *fb, *kb, *ab, *bb;
  if (!st) st = locate_block(base, len, &h, &h.position, "position", "Float64", 3, 8, name, &pb, err);
  if (!st) st = locate_block(base, len, &h, &h.force, "force", "Float64", 3, 8, name, &fb, err);
  if (!st) st = locate_block(base, len, &h, &h.kind, "kind", "Int32", 1, 4, name, &kb, err);
  if (!st) st = locate_block(base, len, &h, &h.id_a, "id_a", "Int64", 1, 8, name, &ab, err);
  if (!st) st = locate_block(base, len, &h, &h.id_b, "id_b", "Int64", 1, 8, name, &bb, err);
  if (st) return st;
  size_t n = (size_t)h.nlines, cap = n ? n : 1;
  adem_contact_frame f = {.n = n, .time = h.time, .step = h.step};
  f.p0 = malloc(cap * sizeof *f.p0);
  f.p1 = malloc(cap * sizeof *f.p1);
  f.force = malloc(cap * sizeof *f.force);
  f.kind = malloc(cap * sizeof *f.kind);
  f.id_a = malloc(cap * sizeof *f.id_a);
  f.id_b = malloc(cap * sizeof *f.id_b);
  if (!f.p0 || !f.p1 || !f.force || !f.kind || !f.id_a || !f.id_b) {
    adem_contact_frame_free(&f);
    return fail(err, ADEM_ERR_NOMEM, "%s: out of memory for %zu contacts", NAME_OF(name), n);
  }
  for (size_t i = 0; i < n; ++i) {
    double x[9];
    memcpy(x, pb + 48 * i, 48);
    memcpy(x + 6, fb + 24 * i, 24);
    for (int q = 0; q < 9; ++q)
      if (!isfinite(x[q])) {
        adem_contact_frame_free(&f);
        return fail(err, ADEM_ERR_INPUT, "%s: contact %zu: a point or the force is not finite",
                    NAME_OF(name), i);
      }
    f.p0[i] = (adem_vec3){x[0], x[1], x[2]};
    f.p1[i] = (adem_vec3){x[3], x[4], x[5]};
    f.force[i] = (adem_vec3){x[6], x[7], x[8]};
    memcpy(&f.kind[i], kb + 4 * i, 4);
    memcpy(&f.id_a[i], ab + 8 * i, 8);
    memcpy(&f.id_b[i], bb + 8 * i, 8);
    if (f.kind[i] < 0 || f.kind[i] > 2) {
      adem_contact_frame_free(&f);
      return fail(err, ADEM_ERR_INPUT, "%s: contact %zu: kind %d is not 0, 1 or 2",
                  NAME_OF(name), i, (int)f.kind[i]);
    }
  }
  *frame = f;
  return ADEM_OK;
}

/* The whole file in a fresh buffer (at most ADEM_VTU_READ_MAX_BYTES). */
static adem_status slurp(const char *path, unsigned char **out, size_t *out_len, adem_error *err) {
  *out = NULL;
  *out_len = 0;
  FILE *fp = fopen(path, "rb");
  if (!fp) return fail(err, ADEM_ERR_INPUT, "cannot open %s: %s", path, strerror(errno));
  unsigned char *buf = NULL;
  size_t len = 0, cap = 0;
  for (;;) {
    if (len == cap) {
      if (cap >= ADEM_VTU_READ_MAX_BYTES) {
        fclose(fp);
        free(buf);
        return fail(err, ADEM_ERR_INPUT, "%s: larger than %zu bytes", path,
                    (size_t)ADEM_VTU_READ_MAX_BYTES);
      }
      size_t ncap = cap ? 2 * cap : (size_t)1 << 16;
      if (ncap > ADEM_VTU_READ_MAX_BYTES) ncap = ADEM_VTU_READ_MAX_BYTES;
      unsigned char *nb = realloc(buf, ncap);
      if (!nb) {
        fclose(fp);
        free(buf);
        return fail(err, ADEM_ERR_NOMEM, "%s: out of memory reading the file", path);
      }
      buf = nb;
      cap = ncap;
    }
    size_t got = fread(buf + len, 1, cap - len, fp);
    len += got;
    if (got == 0) break;
  }
  int bad = ferror(fp);
  int e = errno;
  fclose(fp);
  if (bad) {
    free(buf);
    return fail(err, ADEM_ERR_INPUT, "cannot read %s: %s", path, strerror(e ? e : EIO));
  }
  *out = buf;
  *out_len = len;
  return ADEM_OK;
}

adem_status adem_vtu_read_file(const char *path, adem_vtu_frame *frame, adem_error *err) {
  memset(frame, 0, sizeof *frame);
  unsigned char *buf;
  size_t len;
  adem_status st = slurp(path, &buf, &len, err);
  if (st) return st;
  st = adem_vtu_read_memory(buf, len, path, frame, err);
  free(buf);
  return st;
}

adem_status adem_contact_frame_read_file(const char *path, adem_contact_frame *frame,
                                         adem_error *err) {
  memset(frame, 0, sizeof *frame);
  unsigned char *buf;
  size_t len;
  adem_status st = slurp(path, &buf, &len, err);
  if (st) return st;
  st = adem_contact_frame_read_memory(buf, len, path, frame, err);
  free(buf);
  return st;
}
