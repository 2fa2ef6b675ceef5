/* --set overrides: each "key.path=value" is parsed as YAML and grafted onto the case's document,
 * so that validation treats it like the file's own text and names the --set in messages. */
#include <stdlib.h>
#include <string.h>

#include "case_yaml.h"

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
  adem_status st = adem_yaml_load_yaml(eq + 1, strlen(eq + 1), &value, label, true, ctx->err);
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
    int target = 0;   /* id of the node the segment names, 0 if missing */
    int *slot = NULL; /* where that id is stored, to replace it */
    size_t slot_index = 0;
    bool in_map = n->type == YAML_MAPPING_NODE;
    if (in_map) {
      yaml_node_pair_t *p = n->data.mapping.pairs.start;
      for (; p < n->data.mapping.pairs.top; ++p) {
        yaml_node_t *k = yaml_document_get_node(doc, p->key);
        if (k->type == YAML_SCALAR_NODE && strcmp(adem_yaml_sval(k), seg) == 0) break;
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
              if (k->type == YAML_SCALAR_NODE && !strcmp(adem_yaml_sval(k), "name"))
                name = yaml_document_get_node(doc, p->value);
            }
          if (name && name->type == YAML_SCALAR_NODE) {
            if (!strcmp(adem_yaml_sval(name), seg)) break;
            adem_yaml_list_append(names, sizeof names, adem_yaml_sval(name));
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
    bool open = !tn || adem_yaml_is_null(tn); /* nothing there yet: walk on through a new mapping */
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
        st = adem_yaml_nomem(ctx);
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
          st = adem_yaml_nomem(ctx);
          break;
        }
      }
      target = replacement;
    }
    char parent[KEY_PATH_MAX];
    snprintf(parent, sizeof parent, "%s", walked);
    adem_yaml_join(walked, sizeof walked, parent, seg);
    if (last) break;
    node = target;
    seg = dot + 1;
  }
  yaml_document_delete(&value);
  return st;
}

adem_status adem_yaml_apply_sets(case_ctx *ctx, int nsets) {
  for (int k = 0; k < nsets; ++k) {
    int before = doc_size(&ctx->doc);
    adem_status st = apply_set(ctx, ctx->sets[k]);
    if (st) return st;
    int after = doc_size(&ctx->doc);
    if (after > before) {
      int *o = realloc(ctx->origin, (size_t)(after - ctx->nbase) * sizeof *o);
      if (!o) return adem_yaml_nomem(ctx);
      ctx->origin = o;
      /* A root mapping made for an empty file stands for the file: -1. */
      for (int id = before + 1; id <= after; ++id) o[id - ctx->nbase - 1] = id == 1 ? -1 : k;
      ctx->norigin = (size_t)(after - ctx->nbase);
    }
  }
  return ADEM_OK;
}

/* ---- spheres ---- */
