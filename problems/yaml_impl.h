/* Private: a thin typed reader over libyaml's document API. Every error says
 * file:line:column, the key and the value. libcyaml was considered: its
 * schema loader reports errors only through a log callback without the
 * node's position, and we want positions in the returned message. */
#ifndef EA_YAML_IMPL_H
#define EA_YAML_IMPL_H

#include "ea_arm.h"
#include "ea_status.h"

#include <yaml.h>

typedef struct ea__ydoc {
  yaml_document_t doc;
  int loaded;
  char file[256];
} ea__ydoc_t;

/** Deepest nesting of mappings and sequences a loaded document may have. */
#define EA__YDOC_MAX_DEPTH 64

/** Parse path (or, if text != NULL, the len bytes of text named path).
 *  A path must name a regular file (a FIFO or directory is refused without
 *  blocking); nesting deeper than EA__YDOC_MAX_DEPTH is an error. */
ea_status_t ea__ydoc_load(ea__ydoc_t *d, const char *path, const char *text, size_t len,
                          ea_error_t *err);
void ea__ydoc_free(ea__ydoc_t *d);
/** Root node, required to be a mapping. */
ea_status_t ea__ydoc_root_map(ea__ydoc_t *d, yaml_node_t **root, ea_error_t *err);

/** Position of a node as "file:line:col". */
void ea__ynode_where(const ea__ydoc_t *d, const yaml_node_t *n, char *buf, size_t len);
/** Error at node n: "file:line:col: " followed by the message. */
ea_status_t ea__yerr(ea__ydoc_t *d, const yaml_node_t *n, ea_error_t *err, ea_status_t st,
                     const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 5, 6)))
#endif
    ;

/** Value node of key in mapping map, or NULL. */
yaml_node_t *ea__ymap_get(ea__ydoc_t *d, yaml_node_t *map, const char *key);
/** Every key of map must be in the NULL-terminated list allowed; duplicate
 *  keys are errors too. ctx names the mapping in the message. */
ea_status_t ea__ymap_check_keys(ea__ydoc_t *d, yaml_node_t *map, const char *const *allowed,
                                const char *ctx, ea_error_t *err);
/** Required (or optional: *out left unchanged when absent) sub-mapping. */
ea_status_t ea__ymap_map(ea__ydoc_t *d, yaml_node_t *map, const char *key, int required,
                         yaml_node_t **out, ea_error_t *err);
/** Sequence node of key (required or optional; *out = NULL when absent). */
ea_status_t ea__ymap_seq(ea__ydoc_t *d, yaml_node_t *map, const char *key, int required,
                         yaml_node_t **out, ea_error_t *err);
/** A finite number in [lo, hi] (pass -INFINITY / INFINITY for none). */
ea_status_t ea__ymap_double(ea__ydoc_t *d, yaml_node_t *map, const char *key, int required,
                            double lo, double hi, double *out, ea_error_t *err);
/** A scalar node as a finite double; key used in messages. */
ea_status_t ea__ynode_double(ea__ydoc_t *d, yaml_node_t *n, const char *key, double lo, double hi,
                             double *out, ea_error_t *err);
/** An integer in [lo, hi]. */
ea_status_t ea__ymap_int(ea__ydoc_t *d, yaml_node_t *map, const char *key, int required, long lo,
                         long hi, long *out, ea_error_t *err);
/** A boolean (true/false/yes/no). */
ea_status_t ea__ymap_bool(ea__ydoc_t *d, yaml_node_t *map, const char *key, int required, int *out,
                          ea_error_t *err);
/** A string copied into buf (len bytes incl. NUL); too long is an error. */
ea_status_t ea__ymap_string(ea__ydoc_t *d, yaml_node_t *map, const char *key, int required,
                            char *buf, size_t len, ea_error_t *err);
/** One of the NULL-terminated names; *out = its index. */
ea_status_t ea__ymap_enum(ea__ydoc_t *d, yaml_node_t *map, const char *key, int required,
                          const char *const *names, int *out, ea_error_t *err);
/** A sequence of exactly n numbers (n > 0) or, with n < 0, 1..-n numbers
 *  (*count set). */
ea_status_t ea__ymap_vec(ea__ydoc_t *d, yaml_node_t *map, const char *key, int required, int n,
                         double *out, int *count, ea_error_t *err);
/** Scalar text of a node (NULL if not a scalar). */
const char *ea__ynode_text(const yaml_node_t *n);

/** rel as named from the file base_file: prefixed with base_file's folder unless it is
 *  absolute, empty, or base_file has no folder (NULL: as given); kept as given when the
 *  result would not fit in len bytes. */
void ea__path_beside(const char *base_file, const char *rel, char *out, size_t len);

/** A spec's optional `arm_file:` key (a study's, an experiment's): the file relative to
 *  base_file (ea__path_beside) loaded into *arm, its path in path; without the key,
 *  default_arm's (none either: arm and path untouched). A file that does not load is
 *  an error at the key's line and column. */
ea_status_t ea__ymap_arm_file(ea__ydoc_t *d, yaml_node_t *root, const char *base_file,
                              const char *default_arm, char *path, size_t len, ea_arm_t *arm,
                              ea_error_t *err);

#endif
