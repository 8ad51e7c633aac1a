/* Typed reading of YAML documents with positions in every error. */
#include "ea_util.h"
#include "yaml_impl.h"
#include "ea_arm_file.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static ea_status_t ea__syntax_error(const ea__ydoc_t *d, const yaml_parser_t *p, ea_error_t *err) {
  return ea_error_set(err, EA_ERR_PARSE, "%s:%lu:%lu: YAML syntax error: %s %s", d->file,
                      (unsigned long)p->problem_mark.line + 1,
                      (unsigned long)p->problem_mark.column + 1, p->problem ? p->problem : "",
                      p->context ? p->context : "");
}

/* Walk the events of the first document and refuse nesting deeper than
 * EA__YDOC_MAX_DEPTH before libyaml builds the tree: its scanner takes time
 * quadratic in the depth of flow collections (measured, 100k levels: 23 s
 * for [[[...]]], 46 s for {a: {a: ...}}), and no input of ours needs more
 * than a few levels. Stops at the first
 * over-deep collection, so the cost is bounded by the cap. */
static ea_status_t ea__ydoc_depth(const ea__ydoc_t *d, const char *text, size_t len,
                                  ea_error_t *err) {
  yaml_parser_t p;
  if (!yaml_parser_initialize(&p))
    return ea_error_set(err, EA_ERR_NOMEM, "%s: cannot initialise the YAML parser", d->file);
  yaml_parser_set_input_string(&p, (const unsigned char *)text, len);
  ea_status_t st = EA_OK;
  int depth = 0, done = 0;
  while (!st && !done) {
    yaml_event_t ev;
    if (!yaml_parser_parse(&p, &ev)) {
      st = ea__syntax_error(d, &p, err);
      break;
    }
    switch (ev.type) {
    case YAML_SEQUENCE_START_EVENT:
    case YAML_MAPPING_START_EVENT:
      if (++depth > EA__YDOC_MAX_DEPTH)
        st = ea_error_set(err, EA_ERR_PARSE,
                          "%s:%lu:%lu: YAML nesting deeper than the limit of %d levels (mappings "
                          "and sequences inside each other)",
                          d->file, (unsigned long)ev.start_mark.line + 1,
                          (unsigned long)ev.start_mark.column + 1, EA__YDOC_MAX_DEPTH);
      break;
    case YAML_SEQUENCE_END_EVENT:
    case YAML_MAPPING_END_EVENT:
      --depth;
      break;
    case YAML_DOCUMENT_END_EVENT:
    case YAML_STREAM_END_EVENT:
      done = 1;
      break;
    default:
      break;
    }
    yaml_event_delete(&ev);
  }
  yaml_parser_delete(&p);
  return st;
}

ea_status_t ea__ydoc_load(ea__ydoc_t *d, const char *path, const char *text, size_t len,
                          ea_error_t *err) {
  memset(d, 0, sizeof *d);
  snprintf(d->file, sizeof d->file, "%s", path ? path : "<input>");
  char *buf = NULL;
  if (!text) {
    if (!path) return ea_error_set(err, EA_ERR_ARG, "YAML load: no path and no text");
    ea_status_t st = ea__file_read_regular(path, d->file, &buf, &len, err);
    if (st) return st;
    text = buf;
  }
  ea_status_t st = ea__ydoc_depth(d, text, len, err);
  yaml_parser_t parser;
  if (!st && !yaml_parser_initialize(&parser))
    st = ea_error_set(err, EA_ERR_NOMEM, "%s: cannot initialise the YAML parser", d->file);
  if (!st) {
    yaml_parser_set_input_string(&parser, (const unsigned char *)text, len);
    if (!yaml_parser_load(&parser, &d->doc))
      st = ea__syntax_error(d, &parser, err);
    else
      d->loaded = 1;
    yaml_parser_delete(&parser);
  }
  free(buf);
  return st;
}

void ea__ydoc_free(ea__ydoc_t *d) {
  if (d && d->loaded) {
    yaml_document_delete(&d->doc);
    d->loaded = 0;
  }
}

void ea__ynode_where(const ea__ydoc_t *d, const yaml_node_t *n, char *buf, size_t len) {
  if (n)
    snprintf(buf, len, "%s:%lu:%lu", d->file, (unsigned long)n->start_mark.line + 1,
             (unsigned long)n->start_mark.column + 1);
  else
    snprintf(buf, len, "%s", d->file);
}

ea_status_t ea__yerr(ea__ydoc_t *d, const yaml_node_t *n, ea_error_t *err, ea_status_t st,
                     const char *fmt, ...) {
  if (!err) return st;
  char where[300], msg[400];
  ea__ynode_where(d, n, where, sizeof where);
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(msg, sizeof msg, fmt, ap);
  va_end(ap);
  return ea_error_set(err, st, "%s: %s", where, msg);
}

ea_status_t ea__ydoc_root_map(ea__ydoc_t *d, yaml_node_t **root, ea_error_t *err) {
  yaml_node_t *r = yaml_document_get_root_node(&d->doc);
  if (!r) return ea_error_set(err, EA_ERR_INPUT, "%s: the document is empty", d->file);
  if (r->type != YAML_MAPPING_NODE)
    return ea__yerr(d, r, err, EA_ERR_INPUT, "the top level must be a mapping of keys");
  *root = r;
  return EA_OK;
}

const char *ea__ynode_text(const yaml_node_t *n) {
  if (!n || n->type != YAML_SCALAR_NODE) return NULL;
  return (const char *)n->data.scalar.value;
}

yaml_node_t *ea__ymap_get(ea__ydoc_t *d, yaml_node_t *map, const char *key) {
  if (!map || map->type != YAML_MAPPING_NODE) return NULL;
  for (yaml_node_pair_t *p = map->data.mapping.pairs.start; p < map->data.mapping.pairs.top; ++p) {
    const char *k = ea__ynode_text(yaml_document_get_node(&d->doc, p->key));
    if (k && strcmp(k, key) == 0) return yaml_document_get_node(&d->doc, p->value);
  }
  return NULL;
}

ea_status_t ea__ymap_check_keys(ea__ydoc_t *d, yaml_node_t *map, const char *const *allowed,
                                const char *ctx, ea_error_t *err) {
  for (yaml_node_pair_t *p = map->data.mapping.pairs.start; p < map->data.mapping.pairs.top; ++p) {
    yaml_node_t *kn = yaml_document_get_node(&d->doc, p->key);
    const char *k = ea__ynode_text(kn);
    if (!k) return ea__yerr(d, kn, err, EA_ERR_INPUT, "%s: keys must be plain strings", ctx);
    int ok = 0;
    for (const char *const *a = allowed; *a; ++a)
      if (strcmp(*a, k) == 0) ok = 1;
    if (!ok) {
      char list[300] = "";
      size_t used = 0;
      for (const char *const *a = allowed; *a && used + 1 < sizeof list; ++a) {
        int w = snprintf(list + used, sizeof list - used, "%s%s", used ? ", " : "", *a);
        if (w < 0) break;
        used += (size_t)w;
      }
      return ea__yerr(d, kn, err, EA_ERR_INPUT, "unknown key '%s' in %s (allowed: %s)", k, ctx,
                      list);
    }
    for (yaml_node_pair_t *q = map->data.mapping.pairs.start; q < p; ++q) {
      const char *k2 = ea__ynode_text(yaml_document_get_node(&d->doc, q->key));
      if (k2 && strcmp(k2, k) == 0)
        return ea__yerr(d, kn, err, EA_ERR_INPUT, "duplicate key '%s' in %s", k, ctx);
    }
  }
  return EA_OK;
}

static ea_status_t ea__ymap_node(ea__ydoc_t *d, yaml_node_t *map, const char *key, int required,
                                 yaml_node_t **out, ea_error_t *err) {
  *out = ea__ymap_get(d, map, key);
  if (!*out && required)
    return ea__yerr(d, map, err, EA_ERR_INPUT, "missing required key '%s'", key);
  return EA_OK;
}

ea_status_t ea__ymap_map(ea__ydoc_t *d, yaml_node_t *map, const char *key, int required,
                         yaml_node_t **out, ea_error_t *err) {
  yaml_node_t *n;
  ea_status_t st = ea__ymap_node(d, map, key, required, &n, err);
  if (st) return st;
  if (!n) {
    *out = NULL;
    return EA_OK;
  }
  if (n->type != YAML_MAPPING_NODE)
    return ea__yerr(d, n, err, EA_ERR_INPUT, "key '%s' must be a mapping", key);
  *out = n;
  return EA_OK;
}

ea_status_t ea__ymap_seq(ea__ydoc_t *d, yaml_node_t *map, const char *key, int required,
                         yaml_node_t **out, ea_error_t *err) {
  yaml_node_t *n;
  ea_status_t st = ea__ymap_node(d, map, key, required, &n, err);
  *out = NULL;
  if (st || !n) return st;
  if (n->type != YAML_SEQUENCE_NODE)
    return ea__yerr(d, n, err, EA_ERR_INPUT, "key '%s' must be a sequence [ ... ]", key);
  *out = n;
  return EA_OK;
}

ea_status_t ea__ynode_double(ea__ydoc_t *d, yaml_node_t *n, const char *key, double lo, double hi,
                             double *out, ea_error_t *err) {
  const char *t = ea__ynode_text(n);
  if (!t) return ea__yerr(d, n, err, EA_ERR_INPUT, "key '%s' must be a number", key);
  char *end = NULL;
  errno = 0;
  const double v = strtod(t, &end);
  if (end == t || *end != '\0' || errno == ERANGE)
    return ea__yerr(d, n, err, EA_ERR_INPUT, "key '%s': '%s' is not a number", key, t);
  if (!isfinite(v))
    return ea__yerr(d, n, err, EA_ERR_INPUT, "key '%s': '%s' is not finite", key, t);
  if (v < lo)
    return ea__yerr(d, n, err, EA_ERR_INPUT, "key '%s': value %s is below the bound %g", key, t,
                    lo);
  if (v > hi)
    return ea__yerr(d, n, err, EA_ERR_INPUT, "key '%s': value %s is above the bound %g", key, t,
                    hi);
  *out = v;
  return EA_OK;
}

ea_status_t ea__ymap_double(ea__ydoc_t *d, yaml_node_t *map, const char *key, int required,
                            double lo, double hi, double *out, ea_error_t *err) {
  yaml_node_t *n;
  ea_status_t st = ea__ymap_node(d, map, key, required, &n, err);
  if (st || !n) return st;
  return ea__ynode_double(d, n, key, lo, hi, out, err);
}

ea_status_t ea__ymap_int(ea__ydoc_t *d, yaml_node_t *map, const char *key, int required, long lo,
                         long hi, long *out, ea_error_t *err) {
  yaml_node_t *n;
  ea_status_t st = ea__ymap_node(d, map, key, required, &n, err);
  if (st || !n) return st;
  const char *t = ea__ynode_text(n);
  if (!t) return ea__yerr(d, n, err, EA_ERR_INPUT, "key '%s' must be an integer", key);
  char *end = NULL;
  errno = 0;
  const long v = strtol(t, &end, 10);
  if (end == t || *end != '\0' || errno == ERANGE)
    return ea__yerr(d, n, err, EA_ERR_INPUT, "key '%s': '%s' is not an integer", key, t);
  if (v < lo || v > hi)
    return ea__yerr(d, n, err, EA_ERR_INPUT, "key '%s': value %ld is outside [%ld, %ld]", key, v,
                    lo, hi);
  *out = v;
  return EA_OK;
}

ea_status_t ea__ymap_bool(ea__ydoc_t *d, yaml_node_t *map, const char *key, int required, int *out,
                          ea_error_t *err) {
  yaml_node_t *n;
  ea_status_t st = ea__ymap_node(d, map, key, required, &n, err);
  if (st || !n) return st;
  const char *t = ea__ynode_text(n);
  if (t && (!strcmp(t, "true") || !strcmp(t, "yes") || !strcmp(t, "on"))) {
    *out = 1;
    return EA_OK;
  }
  if (t && (!strcmp(t, "false") || !strcmp(t, "no") || !strcmp(t, "off"))) {
    *out = 0;
    return EA_OK;
  }
  return ea__yerr(d, n, err, EA_ERR_INPUT, "key '%s' must be true or false", key);
}

ea_status_t ea__ymap_string(ea__ydoc_t *d, yaml_node_t *map, const char *key, int required,
                            char *buf, size_t len, ea_error_t *err) {
  yaml_node_t *n;
  ea_status_t st = ea__ymap_node(d, map, key, required, &n, err);
  if (st || !n) return st;
  const char *t = ea__ynode_text(n);
  if (!t) return ea__yerr(d, n, err, EA_ERR_INPUT, "key '%s' must be a string", key);
  if (strlen(t) + 1 > len)
    return ea__yerr(d, n, err, EA_ERR_INPUT, "key '%s': value is longer than %zu characters", key,
                    len - 1);
  memcpy(buf, t, strlen(t) + 1);
  return EA_OK;
}

ea_status_t ea__ymap_enum(ea__ydoc_t *d, yaml_node_t *map, const char *key, int required,
                          const char *const *names, int *out, ea_error_t *err) {
  yaml_node_t *n;
  ea_status_t st = ea__ymap_node(d, map, key, required, &n, err);
  if (st || !n) return st;
  const char *t = ea__ynode_text(n);
  if (t)
    for (int i = 0; names[i]; ++i)
      if (!strcmp(names[i], t)) {
        *out = i;
        return EA_OK;
      }
  char list[256] = "";
  size_t used = 0;
  for (int i = 0; names[i] && used + 1 < sizeof list; ++i) {
    int w = snprintf(list + used, sizeof list - used, "%s%s", i ? ", " : "", names[i]);
    if (w < 0) break;
    used += (size_t)w;
  }
  return ea__yerr(d, n, err, EA_ERR_INPUT, "key '%s': '%s' is not one of: %s", key,
                  t ? t : "(not a scalar)", list);
}

ea_status_t ea__ymap_vec(ea__ydoc_t *d, yaml_node_t *map, const char *key, int required, int n,
                         double *out, int *count, ea_error_t *err) {
  yaml_node_t *s;
  ea_status_t st = ea__ymap_seq(d, map, key, required, &s, err);
  if (st || !s) return st;
  const int have = (int)(s->data.sequence.items.top - s->data.sequence.items.start);
  if ((n > 0 && have != n) || (n < 0 && (have < 1 || have > -n)))
    return ea__yerr(d, s, err, EA_ERR_INPUT, "key '%s' must have %s%d numbers, not %d", key,
                    n > 0 ? "" : "1 to ", n > 0 ? n : -n, have);
  for (int i = 0; i < have; ++i) {
    yaml_node_t *it = yaml_document_get_node(&d->doc, s->data.sequence.items.start[i]);
    st = ea__ynode_double(d, it, key, -INFINITY, INFINITY, &out[i], err);
    if (st) return st;
  }
  if (count) *count = have;
  return EA_OK;
}

void ea__path_beside(const char *base_file, const char *rel, char *out, size_t len) {
  const char *slash = base_file ? strrchr(base_file, '/') : NULL;
  if (!rel[0] || rel[0] == '/' || !slash) {
    snprintf(out, len, "%s", rel);
    return;
  }
  const int w = snprintf(out, len, "%.*s/%s", (int)(slash - base_file), base_file, rel);
  if (w < 0 || (size_t)w >= len) snprintf(out, len, "%s", rel); /* too long: keep it relative */
}

ea_status_t ea__ymap_arm_file(ea__ydoc_t *d, yaml_node_t *root, const char *base_file,
                              const char *default_arm, char *path, size_t len, ea_arm_t *arm,
                              ea_error_t *err) {
  char rel[512] = "";
  ea_status_t st = ea__ymap_string(d, root, "arm_file", 0, rel, sizeof rel, err);
  if (st) return st;
  if (rel[0]) {
    ea__path_beside(base_file, rel, path, len);
    ea_error_t e = {0};
    if ((st = ea_arm_load(path, arm, &e)))
      return ea__yerr(d, ea__ymap_get(d, root, "arm_file"), err, st, "key 'arm_file': %s", e.msg);
  } else if (default_arm) {
    snprintf(path, len, "%s", default_arm);
    return ea_arm_load(default_arm, arm, err);
  }
  return EA_OK;
}
