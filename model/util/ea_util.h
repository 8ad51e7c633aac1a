/* Private: the utility layer under model/, problems/ and planner/ (one copy
 * each; not part of the public API, not installed): angles, the monotonic
 * clock, CRC-32, a string buffer, CSV quoting, file name extensions, atomic
 * output files, regular input files and a JSON writer. Status codes and the error context are
 * public: ea_status.h. */
#ifndef EA_UTIL_H
#define EA_UTIL_H

#include "ea_status.h"

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

/** Radians per degree (degrees only at the CLI and in files that say _deg). */
#define EA__DEG (M_PI / 180.0)

/* ------------------------------------------------------------------------ */
/* Monotonic clock (clock.c)                                                 */
/* ------------------------------------------------------------------------ */

/** CLOCK_MONOTONIC [ns]. */
int64_t ea__mono_ns(void);
/** CLOCK_MONOTONIC [s] (wall times of solves). */
double ea__mono_s(void);

/* ------------------------------------------------------------------------ */
/* CRC-32 (crc32.c)                                                          */
/* ------------------------------------------------------------------------ */

/** CRC-32 (IEEE 802.3 / zlib: reflected 0xEDB88320, init and xorout
 *  0xFFFFFFFF); crc = 0 to start, pass the previous value to continue. */
uint32_t ea_crc32(uint32_t crc, const void *buf, size_t len);

/* ------------------------------------------------------------------------ */
/* Text (text.c)                                                             */
/* ------------------------------------------------------------------------ */

/** A growable text buffer (never fails silently: oom sticks). Zero-initialise. */
typedef struct ea__sbuf {
  char *s;
  size_t len, cap;
  int oom;
} ea__sbuf_t;

void ea__sbuf_printf(ea__sbuf_t *b, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;
void ea__sbuf_put(ea__sbuf_t *b, const char *text, size_t len);
void ea__sbuf_free(ea__sbuf_t *b);

/** text as one quoted CSV field (RFC 4180): '"' doubled, line breaks as
 *  spaces so that a row stays one line; NULL is "". */
void ea__csv_quote(FILE *fp, const char *text);
void ea__sbuf_csv_quote(ea__sbuf_t *b, const char *text);

/** in with its extension (after the last '.' of the last path component)
 *  replaced by ext ("" removes it) into out (len bytes). */
void ea__replace_ext(const char *in, const char *ext, char *out, size_t len);

/* ------------------------------------------------------------------------ */
/* Atomic output files: write to a temporary beside the target, rename on    */
/* commit; an abort (or a crash) never leaves a half-written target.         */
/* ------------------------------------------------------------------------ */

typedef struct ea_afile {
  FILE *fp;        /**< write here */
  char path[1024]; /**< final path */
  char tmp[1040];  /**< temporary path */
} ea_afile_t;

/** Create the missing parent directories of path (like mkdir -p dirname). */
ea_status_t ea_mkdir_parents(const char *path, ea_error_t *err);
/** Open a temporary file next to path ("-" means stdout, written directly). */
ea_status_t ea_afile_open(ea_afile_t *f, const char *path, ea_error_t *err);
/** Flush, fsync and rename onto the target. Closes f. */
ea_status_t ea_afile_commit(ea_afile_t *f, ea_error_t *err);
/** Close and remove the temporary. Safe on a closed or zeroed f. */
void ea_afile_abort(ea_afile_t *f);

/* ------------------------------------------------------------------------ */
/* Minimal JSON emitter (numbers with 17 significant digits, NaN -> null)    */
/* ------------------------------------------------------------------------ */

typedef struct ea_json {
  FILE *fp;
  int depth;
  int first[32]; /**< first element at this depth? */
  int pretty;
} ea_json_t;

void ea_json_init(ea_json_t *j, FILE *fp, int pretty);
void ea_json_obj_begin(ea_json_t *j, const char *key); /**< key NULL inside arrays / top */
void ea_json_obj_end(ea_json_t *j);
void ea_json_arr_begin(ea_json_t *j, const char *key);
void ea_json_arr_end(ea_json_t *j);
void ea_json_num(ea_json_t *j, const char *key, double v);
void ea_json_int(ea_json_t *j, const char *key, long v);
void ea_json_bool(ea_json_t *j, const char *key, int v);
void ea_json_str(ea_json_t *j, const char *key, const char *v);
void ea_json_null(ea_json_t *j, const char *key);
/** Array of n numbers. */
void ea_json_vec(ea_json_t *j, const char *key, const double *v, int n);
/** Finish (newline). */
void ea_json_end(ea_json_t *j);

/* ------------------------------------------------------------------------ */
/* Input files (read_file.c)                                                 */
/* ------------------------------------------------------------------------ */

/** Open path for reading if it is a regular file: the open does not block (a FIFO without
 *  a writer would) and a directory, FIFO or device is refused with "NAME: is a directory,
 *  not a regular file" (name NULL: the path). */
ea_status_t ea__file_open_regular(const char *path, const char *name, FILE **fp, ea_error_t *err);
/** The whole of the regular file path in *buf (malloc'd, NUL-terminated, *len bytes); the
 *  same refusals as ea__file_open_regular. */
ea_status_t ea__file_read_regular(const char *path, const char *name, char **buf, size_t *len,
                                  ea_error_t *err);

/** Remove the temporaries of path ("<path>.tmp<pid>.*", regular files owned
 *  by this user) whose process no longer runs: what a killed run (kill -9,
 *  power loss) left behind. Temporaries of live processes are kept. */
void ea__afile_clean_stale(const char *path);

#endif /* EA_UTIL_H */
