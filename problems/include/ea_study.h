/**
 * @file ea_study.h
 * @brief Batch studies (docs/studies.md): grids of payload and arm
 *        parameters, metrics per case, threads, shards, resumable runs, merges
 *        (problems/study_*.c). The minimum-time and at-rest metrics are
 *        callbacks the planner registers, so problems/ does not link Ipopt.
 */
#ifndef EA_STUDY_H
#define EA_STUDY_H

#include "ea_task.h"

#include <signal.h>
#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/** Batch studies (docs/studies.md): a full-factorial grid of payload and arm
 *  parameters, and per case only the metrics asked for (workspace, torque
 *  and tension ranges, FE natural frequencies, path admissibility, and the
 *  minimum-time duration of a task through a callback the planner
 *  registers; the duration of the plan that arrives at rest and the FE residual
 *  vibration it and the minimum-time plan leave, through another). Results are
 *  one tidy CSV row per case and metric:
 *  case_id, the parameter columns, metric, value, unit, status, message.
 *  Cases are computed independently (a fresh shooter / FE model per case,
 *  no warm start across cases), so the CSV is byte-identical whatever the
 *  worker count (threads or forked processes), the sharding, or how often
 *  the study was interrupted. */

/** Parameters a grid may sweep, in CSV column order (payload first). */
typedef enum ea_study_param {
  EA_STUDY_PAYLOAD_FACTOR = 0, /**< [-] gamma (eq. 17), of the case's arm */
  EA_STUDY_PAYLOAD_KG,         /**< [kg] m_p */
  EA_STUDY_EI,                 /**< [N m^2] flexural rigidity */
  EA_STUDY_RHO,                /**< [kg/m] beam mass per unit length */
  EA_STUDY_LENGTH,             /**< [m] beam length L */
  EA_STUDY_HAND_MASS,          /**< [kg] hand mass m_h */
  EA_STUDY_CABLE_ROOT_X,       /**< [m] cable root x_c */
  EA_STUDY_CABLE_ROOT_Y,       /**< [m] cable root y_c */
  EA_STUDY_NPARAM
} ea_study_param_t;

/** Spec key and CSV column of a parameter ("payload_factor", "EI_Nm2", ...). */
const char *ea_study_param_name(ea_study_param_t p);

/** Metrics (bit flags of ea_study_t.metrics). */
enum {
  EA_STUDY_M_WORKSPACE = 1u,   /**< region metrics: area, max_reach, x_max, y_min */
  EA_STUDY_M_TORQUE = 2u,      /**< torque map: shoulder torque and tension ranges */
  EA_STUDY_M_FREQUENCIES = 4u, /**< FE natural frequencies at given configurations */
  EA_STUDY_M_PATH = 8u,        /**< admissibility of a straight tip path */
  EA_STUDY_M_MIN_TIME = 16u,   /**< minimum-time duration of a task (planner callback) */
  EA_STUDY_M_AT_REST = 32u     /**< at-rest duration and FE residuals (planner callback) */
};

/** Metrics that plan (Ipopt): cases with them run in forked worker processes. */
#define EA_STUDY_M_PLANNER (EA_STUDY_M_MIN_TIME | EA_STUDY_M_AT_REST)

/** Most frequency configurations of a study. */
#define EA_STUDY_MAX_CONFIGS 16

/** One axis of the grid: values owned (malloc'd). */
typedef struct ea_study_axis {
  ea_study_param_t param;
  int n;          /**< number of values (>= 1) */
  double *values; /**< owned; freed by ea_study_free */
} ea_study_axis_t;

/** A study spec. Built by ea_study_load() or ea_study_init() +
 *  ea_study_set_axis() + fields + ea_study_check(). Owns the axis values
 *  and the torque-map grids: release with ea_study_free(). */
typedef struct ea_study {
  char name[128];     /**< letters, digits, '.', '_', '-' (a CSV column and file stem) */
  char file[512];     /**< spec file ("" when built in C) */
  char arm_file[512]; /**< arm file used ("" = built-in defaults) */
  ea_arm_t arm;       /**< base arm; grid parameters override it per case */
  int n_axes;         /**< axes in CSV column order (ea_study_param_t order) */
  ea_study_axis_t axis[EA_STUDY_NPARAM];
  long n_cases;     /**< product of the axis sizes (set by ea_study_check) */
  unsigned metrics; /**< EA_STUDY_M_* flags */
  struct {
    double alpha_min, alpha_max; /**< [rad] cable-angle range of the region (-60, 10 deg) */
    int points;                  /**< cable angles sampled (default 71; ea_workspace_metrics'
                                      samples) */
    double inner_cable_length;   /**< [m] inner edge (<= 0: the arm's cable_length_min) */
    int limits;                  /**< the arm's limits bound the region (default 1) */
  } workspace;
  struct {
    int n_len, n_alpha;   /**< grid sizes */
    double *cable_length; /**< [m] owned */
    double *alpha;        /**< [rad] owned */
  } torque;
  struct {
    int modes;    /**< modes per configuration (default 3) */
    int elements; /**< FE elements (default EA_FE_DEFAULT_ELEMENTS) */
    int n_config;
    double cable_length[EA_STUDY_MAX_CONFIGS]; /**< [m] */
    double alpha[EA_STUDY_MAX_CONFIGS];        /**< [rad] */
  } freq;
  struct {
    double start[2], goal[2]; /**< [m] tip (x, y) */
    int steps;                /**< points - 1 (default 20) */
  } path;
  struct {
    char task_file[512]; /**< task spec (resolved against the spec's folder) */
    char task_name[512]; /**< as written in the spec (relative to it): the name used in
                              messages and keys, so rows do not depend on the working
                              directory ("" = task_file) */
  } min_time;
  struct {
    char task_file[512];  /**< min_time task to plan at rest (resolved against the spec) */
    char task_name[512];  /**< as written in the spec ("" = task_file) */
    int modes;            /**< reduced-model modes of the at-rest plan (default 2, 1..4) */
    int elements;         /**< FE elements of the transients (default EA_FE_DEFAULT_ELEMENTS) */
    double dt;            /**< [s] FE time step (default 1e-3) */
    double settle;        /**< [s] FE time simulated after the motion (default 3) */
    double damping_ratio; /**< zeta at the first mode (default 0: undamped, the residual the
                               motion leaves) */
  } at_rest;
  char out_csv[512]; /**< outputs resolved against the spec's folder ("" = none) */
  char out_summary[512];
  char out_figures[512]; /**< figure path prefix */
} ea_study_t;

/** Initialise: base arm (copied; NULL = ea_arm_default), no axes, no
 *  metrics, default metric settings. */
void ea_study_init(ea_study_t *s, const ea_arm_t *arm);
/** Release owned arrays; the struct may be reused after ea_study_init. */
void ea_study_free(ea_study_t *s);
/** Set (or replace) the values of one axis (copied). */
ea_status_t ea_study_set_axis(ea_study_t *s, ea_study_param_t p, const double *values, int n,
                              ea_error_t *err);
/** Validate and count the cases (ea_study_t.n_cases). Every case's arm is
 *  checked with ea_arm_validate. */
ea_status_t ea_study_check(ea_study_t *s, ea_error_t *err);
/** Load and check a study spec (docs/studies.md). Errors say
 *  file:line:column and the key. default_arm: arm file used when the spec
 *  names none (NULL = built-in defaults). */
ea_status_t ea_study_load(const char *path, const char *default_arm, ea_study_t *s,
                          ea_error_t *err);
/** Same from len bytes of text named name (relative paths against cwd). */
ea_status_t ea_study_load_string(const char *name, const char *text, size_t len,
                                 const char *default_arm, ea_study_t *s, ea_error_t *err);

/** Parameter values of case_id (0-based; the first axis varies slowest):
 *  values[n_axes]. */
void ea_study_case_values(const ea_study_t *s, long case_id, double *values);
/** The arm and payload of a case: grid values applied to the base arm;
 *  payload from payload_kg or the factor of the case's arm (eq. 17).
 *  *payload_factor is NAN when the payload is given in kg. */
ea_status_t ea_study_case_arm(const ea_study_t *s, long case_id, ea_arm_t *arm, double *payload_kg,
                              double *payload_factor, ea_error_t *err);

/** Minimum-time duration of the study's task for one case: registered by
 *  the planner (problems/ does not link Ipopt). Returns EA_OK and
 *  *duration_s, or a status and a message in msg. Called from worker
 *  threads; the callee serialises what is not thread-safe. */
typedef ea_status_t (*ea_study_min_time_fn)(void *data, const ea_study_t *s, const ea_arm_t *arm,
                                            double payload_kg, double payload_factor,
                                            double *duration_s, char *msg, size_t msg_len);

/** What the at-rest callback found for one case: the quasi-static minimum-time plan
 *  and the plan that arrives at rest (task key dynamics, residual 0), each with
 *  the FE residual peak after the motion (ea_traj_simulate). A value is NAN when
 *  its status is not EA_OK; msg says why, or how it was obtained. */
typedef struct ea_study_at_rest_result {
  double duration_s;         /**< [s] the at-rest plan */
  double residual_peak_m;    /**< [m] FE residual peak after the at-rest plan */
  double qs_duration_s;      /**< [s] the quasi-static minimum-time plan */
  double qs_residual_peak_m; /**< [m] FE residual peak after the quasi-static plan */
  ea_status_t status[4];     /**< of the four values, in this order */
  char msg[4][400];
} ea_study_at_rest_result_t;

/** At-rest metric of one case: registered by the planner. Returns EA_OK when every
 *  value is EA_OK (else the first failure); fills *out in any case. */
typedef ea_status_t (*ea_study_at_rest_fn)(void *data, const ea_study_t *s, const ea_arm_t *arm,
                                           double payload_kg, double payload_factor,
                                           ea_study_at_rest_result_t *out);

/** Where the cases run. */
typedef enum ea_study_workers {
  EA_STUDY_WORKERS_AUTO = 0, /**< forked processes when the study plans (min_time, at_rest)
                                  and more than one worker runs; else threads */
  EA_STUDY_WORKERS_THREADS,  /**< threads of this process (planner calls serialised) */
  EA_STUDY_WORKERS_PROCESSES /**< forked worker processes, even for one worker */
} ea_study_workers_t;

/** Progress callback (from worker threads, serialised): a case finished. */
typedef void (*ea_study_progress_fn)(void *data, long case_id, long done, long todo,
                                     int failed_rows);

/** Run settings. */
typedef struct ea_study_settings {
  int threads;             /**< workers: threads or processes (0 = all online cores) */
  int shard_k, shard_n;    /**< run the cases with case_id % shard_n == shard_k - 1
                                (1 <= shard_k <= shard_n; 1/1 = all) */
  const char *checkpoint;  /**< journal path for resume (NULL = none) */
  int fsync;               /**< fsync the journal (default 1): power-loss safe up to the
                                last fsync; a killed process loses nothing written */
  double fsync_interval_s; /**< [s] at most one fsync per interval (group commit; default
                              0.2; 0 = after every case); always at the end */
  long stop_after;         /**< test hook: stop after this many newly computed cases (0 = off) */
  const volatile sig_atomic_t *stop_request; /**< nonzero: finish running cases, stop */
  ea_study_min_time_fn min_time;             /**< NULL: min_time rows report EA_ERR_NOTIMPL */
  void *min_time_data;
  const char *min_time_key; /**< content key of the task the callback plans (e.g. from
                                 ea_study_task_load): part of the study key, so rows of
                                 an edited task are never mixed with the old ones */
  ea_study_progress_fn progress;
  void *progress_data;
  ea_study_at_rest_fn at_rest; /**< NULL: at_rest rows report EA_ERR_NOTIMPL */
  void *at_rest_data;
  const char *at_rest_key;    /**< content key of the at_rest task (like min_time_key) */
  ea_study_workers_t workers; /**< threads or forked processes (default auto). Worker
                                   processes are forked from the calling thread: call
                                   ea_study_run with no other thread inside the library */
} ea_study_settings_t;

void ea_study_settings_default(ea_study_settings_t *set);

/** Outcome of a run. */
typedef struct ea_study_info {
  ea_status_t status;         /**< EA_OK: every case of the shard has its rows (some may
                                   record failures); EA_ERR_INTERRUPTED: stopped, resume
                                   later; other: could not run (I/O, bad settings) */
  long cases_total;           /**< cases of the grid */
  long cases_shard;           /**< cases of this shard */
  long cases_skipped;         /**< found finished in the checkpoint (not recomputed) */
  long cases_computed;        /**< computed in this run */
  long cases_failed;          /**< cases with at least one non-ok row */
  long rows_failed;           /**< non-ok rows */
  long journal_dropped_bytes; /**< torn / corrupt tail removed from the journal */
  int threads;                /**< workers used (threads or processes) */
  int processes;              /**< 1: the workers were forked processes */
  long workers_lost;          /**< worker processes that died (killed, crashed) while
                                   computing a case: that case's row says so (failed) */
  double time_s;              /**< [s] wall time */
} ea_study_info_t;

/** Study key: CRC-32 (8 hex digits) of a canonical description of
 *  everything that changes the rows (the arm's values, the grid, the metric
 *  settings, the name, the min_time task's name and set->min_time_key).
 *  Every CSV row carries it (column study_key); it keys the journal. */
void ea_study_key(const ea_study_t *s, const ea_study_settings_t *set, char key[9]);

/** Load the min_time task of a study for planning: relative to the spec,
 *  default arm = the study's arm file (else default_arm), messages naming
 *  the task as written in the spec (s->min_time.task_name). key (>= 32
 *  bytes) receives a content key: CRC-32 and length of the task file and of
 *  the arm file it uses ("task=XXXXXXXX/N arm=XXXXXXXX/N"). */
ea_status_t ea_study_task_load(const ea_study_t *s, const char *default_arm, ea_task_t *task,
                               char *key, size_t key_len, ea_error_t *err);

/** The same for the task of a planner metric: EA_STUDY_M_MIN_TIME (= ea_study_task_load)
 *  or EA_STUDY_M_AT_REST; messages name it "min_time task" or "at_rest task". */
ea_status_t ea_study_metric_task_load(const ea_study_t *s, unsigned metric, const char *default_arm,
                                      ea_task_t *task, char *key, size_t key_len, ea_error_t *err);

/** Run (one shard of) a checked study. On EA_OK, *csv (malloc'd, caller
 *  frees; *csv_len bytes) holds the header and the shard's rows in case
 *  order (columns case_id, study, study_key, the parameters, metric, value,
 *  unit, status, message). With a checkpoint journal every finished case is appended (one
 *  write + fsync, CRC-32 per case); a rerun with the same study skips the
 *  cases found there, drops a torn tail, and refuses a journal of another
 *  study (EA_ERR_INPUT). A failed case is recorded in its rows.
 *  Worker processes (set->workers; by default when the study plans and more
 *  than one worker runs): each is forked, computes the cases the parent hands
 *  it one at a time and sends back their rows (the journal's block format);
 *  the parent alone writes the journal and assembles the CSV, so it is the
 *  same bytes as a one-worker run. A worker that dies while computing a case
 *  (killed, crashed) leaves that case one failed row saying so, and another
 *  worker is started for the remaining cases; every worker is waited for
 *  before the call returns. Workers ignore SIGINT and SIGTERM (the caller's
 *  stop_request decides) and, on Linux, die with the calling thread. */
ea_status_t ea_study_run(const ea_study_t *s, const ea_study_settings_t *set, char **csv,
                         size_t *csv_len, ea_study_info_t *info, ea_error_t *err);

/** CSV header line (with newline) of a study into buf; returns its length. */
size_t ea_study_csv_header(const ea_study_t *s, char *buf, size_t len);

/** Merge shard CSVs (texts[i] of lens[i] bytes, names[i] for messages)
 *  into the single-run CSV: same header and the same study and study_key
 *  in every row required (shards of different specs, or of an edited spec
 *  or task, are refused), rows ordered by case_id, each case from exactly
 *  one shard; case ids must be 0..n-1 without gaps (n = expect_cases when
 *  > 0). *out malloc'd. */
ea_status_t ea_study_merge(const char *const *texts, const size_t *lens, const char *const *names,
                           int n, long expect_cases, char **out, size_t *out_len, ea_error_t *err);

#ifdef __cplusplus
}
#endif
#endif /* EA_STUDY_H */
