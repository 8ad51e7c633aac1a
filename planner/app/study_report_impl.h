/* Private: the reports of batch studies (planner/app/study_figure.c, used by
 * planner/app/cli_study.c and the tests): parsed result rows, the JSON summary
 * and the figures. */
#ifndef EA_STUDY_REPORT_IMPL_H
#define EA_STUDY_REPORT_IMPL_H

#include "ea_study.h"

/* ---- parsed rows --------------------------------------------------------- */

typedef struct ea__study_row {
  long case_id;
  double param[EA_STUDY_NPARAM]; /**< values of the parameter columns */
  char metric[64];
  double value; /**< NAN when empty */
  char unit[16];
  int ok; /**< status "ok" */
  char status[32];
} ea__study_row_t;

typedef struct ea__study_table {
  char study[128];    /**< study column of the first row ("" if no rows) */
  char study_key[16]; /**< study_key column of the first row */
  int n_params;
  char params[EA_STUDY_NPARAM][32]; /**< parameter column names */
  long n_rows;
  ea__study_row_t *rows; /**< owned */
} ea__study_table_t;

/** Parse a study CSV (as written by ea_study_run / ea_study_merge). */
ea_status_t ea__study_table_parse(const char *text, size_t len, const char *name,
                                  ea__study_table_t *t, ea_error_t *err);
void ea__study_table_free(ea__study_table_t *t);

/** Run facts for the summary (NULL members omitted). spec and csv as they
 *  should appear (relative to the summary's folder). */
typedef struct ea__study_run_facts {
  const char *name, *spec, *csv;
  const ea_study_info_t *info; /**< NULL for a merge */
  int shard_k, shard_n;
  int merged_inputs; /**< > 0 for a merge */
} ea__study_run_facts_t;

/** JSON summary (per metric: unit, rows, ok, failed, min, max; failed
 *  cases; run facts), written atomically. */
ea_status_t ea__study_summary_write(const ea__study_table_t *t, const ea__study_run_facts_t *f,
                                    const char *path, ea_error_t *err);

/** Figures: PREFIX-workspace.EXT (Fig. 3: the closed workspace region of
 *  every case; needs the study) and PREFIX-METRIC.EXT for every scalar metric
 *  against the swept parameter (one curve per combination of the other
 *  parameters, every one drawn, labelled with units). *n_written counts the
 *  figures. */
ea_status_t ea__study_figures(const ea_study_t *s, const ea__study_table_t *t, const char *prefix,
                              const char *ext, int *n_written, ea_error_t *err);

#endif
