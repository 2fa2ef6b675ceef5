/* A case file's text with --set overrides written into it (adem calibrate's best.yaml): the
 * document is read, the sets are grafted as adem run --set grafts them (case_set.c), and the
 * result is written back as YAML. Comments do not survive a YAML round trip; values, keys and
 * order do. */
#include <stdlib.h>
#include <string.h>

#include "case_yaml.h"
#include "insert.h"

typedef struct emit_buf {
  char *s;
  size_t n, cap;
  int nomem;
} emit_buf;

static int emit_write(void *data, unsigned char *buffer, size_t size) {
  emit_buf *b = data;
  if (b->n + size + 1 > b->cap) {
    size_t cap = 2 * (b->n + size + 1) + 256;
    char *s = realloc(b->s, cap);
    if (!s) {
      b->nomem = 1;
      return 0;
    }
    b->s = s;
    b->cap = cap;
  }
  memcpy(b->s + b->n, buffer, size);
  b->n += size;
  b->s[b->n] = '\0';
  return 1;
}

adem_status adem_case_text_with_sets(const char *text, const char *name_for_messages,
                                     const char *const *sets, int nsets, char **out,
                                     adem_error *err) {
  *out = NULL;
  case_ctx ctx;
  memset(&ctx, 0, sizeof ctx);
  ctx.err = err;
  ctx.file = name_for_messages;
  ctx.sets = sets;
  adem_status st = adem_yaml_load_yaml(text, strlen(text), &ctx.doc, name_for_messages, false, err);
  if (st) return st;
  ctx.nbase = (int)(ctx.doc.nodes.top - ctx.doc.nodes.start);
  st = adem_yaml_apply_sets(&ctx, nsets);
  free(ctx.origin);
  if (st) {
    yaml_document_delete(&ctx.doc);
    return st;
  }
  yaml_emitter_t em;
  emit_buf b = {0};
  if (!yaml_emitter_initialize(&em)) {
    yaml_document_delete(&ctx.doc);
    return adem_error_set(err, ADEM_ERR_NOMEM, "out of memory");
  }
  yaml_emitter_set_output(&em, emit_write, &b);
  yaml_emitter_set_unicode(&em, 1);
  yaml_emitter_set_width(&em, 100);
  int ok = yaml_emitter_open(&em) && yaml_emitter_dump(&em, &ctx.doc) && yaml_emitter_close(&em) &&
           yaml_emitter_flush(&em);
  /* yaml_emitter_dump deletes the document, on success and on failure */
  yaml_emitter_delete(&em);
  if (!ok || b.nomem || !b.s) {
    free(b.s);
    return adem_error_set(err, b.nomem ? ADEM_ERR_NOMEM : ADEM_ERR_INPUT,
                          "%s: the case could not be written back as YAML", name_for_messages);
  }
  *out = b.s;
  return ADEM_OK;
}

adem_status adem_case_region_volume(const adem_case *c, const char *name, double *volume,
                                    adem_error *err) {
  *volume = 0.0;
  char names[512] = "";
  for (int k = 0; c->regions && k < c->regions->n; ++k) {
    if (!strcmp(c->regions->r[k].name, name)) {
      *volume = c->regions->r[k].region.volume;
      return ADEM_OK;
    }
    adem_yaml_list_append(names, sizeof names, c->regions->r[k].name);
  }
  return adem_error_set(err, ADEM_ERR_INPUT, "the case has no output.regions region '%s' (%s%s)",
                        name, *names ? "there are: " : "it has none", names);
}
