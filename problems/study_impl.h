/* Private: batch studies (problems/study_*.c). */
#ifndef EA_STUDY_IMPL_H
#define EA_STUDY_IMPL_H

#include "ea_arm_file.h"
#include "ea_study.h"
#include "ea_workspace.h"
#include "ea_util.h"

#include <stdint.h>

/** Canonical description of everything that changes the rows (name, arm,
 *  axes, metric settings, the min_time task's name and content key, the CSV
 *  header); its CRC is the study key (ea_study_key). */
void ea__study_describe(const ea_study_t *s, const ea_study_settings_t *set, ea__sbuf_t *b);

/** Compute every row of one case into b (appended); ident is the
 *  "study,study_key" pair every row carries. Returns the number of non-ok
 *  rows, or -1 when out of memory. */
int ea__study_case_eval(const ea_study_t *s, long case_id, const ea_study_settings_t *set,
                        const char *ident, ea__sbuf_t *b);

/** One failed row (metric "case", status st, message msg) for case_id into b, as
 *  when a worker process died computing the case. Returns 1, or -1 when out of
 *  memory. */
int ea__study_case_fail(const ea_study_t *s, long case_id, const char *ident, ea_status_t st,
                        const char *msg, ea__sbuf_t *b);

/** Parse the leading case_id of a CSV row; -1 if it has none. */
long ea__study_row_case(const char *row, size_t len);

#endif
