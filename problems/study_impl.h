/* Private: batch studies (problems/study_*.c). */
#ifndef EA_STUDY_IMPL_H
#define EA_STUDY_IMPL_H

#include "ea_problems.h"

#include <stdint.h>

/** A growable text buffer (never fails silently: oom sticks). */
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

/** CRC-32 (IEEE, zlib's): crc = 0 to start. */
uint32_t ea__study_crc32(uint32_t crc, const void *buf, size_t len);

/** Canonical description of everything that changes the rows (name, arm,
 *  axes, metric settings, the min_time task's name and content key, the CSV
 *  header); its CRC is the study key (ea_study_key). */
void ea__study_describe(const ea_study_t *s, const ea_study_settings_t *set, ea__sbuf_t *b);

/** Compute every row of one case into b (appended); ident is the
 *  "study,study_key" pair every row carries. Returns the number of non-ok
 *  rows, or -1 when out of memory. */
int ea__study_case_eval(const ea_study_t *s, long case_id, const ea_study_settings_t *set,
                        const char *ident, ea__sbuf_t *b);

/** Parse the leading case_id of a CSV row; -1 if it has none. */
long ea__study_row_case(const char *row, size_t len);

#endif
