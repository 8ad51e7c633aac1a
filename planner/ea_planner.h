/**
 * @file ea_planner.h
 * @brief Planning and the outside world: trajectory files, atomic output,
 *        JSON, figures, the Ipopt/NLopt planner, the command streamer.
 */
#ifndef EA_PLANNER_H
#define EA_PLANNER_H

#include "ea_problems.h"

#include <stdio.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------------------ */
/* Atomic output files: write to a temporary beside the target, rename on    */
/* commit; an abort (or a crash) never leaves a half-written target.         */
/* ------------------------------------------------------------------------ */

typedef struct ea_afile {
  FILE *fp;          /**< write here */
  char path[1024];   /**< final path */
  char tmp[1040];    /**< temporary path */
} ea_afile_t;

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
/* Figures: gnuplot driven through a pipe (Debian gnuplot-nox).              */
/* The terminal follows the output's extension: .svg, .png (pngcairo), .pdf  */
/* ------------------------------------------------------------------------ */

typedef struct ea_plot ea_plot_t;

/** Start a figure for out_path (width x height pixels; 0 = 900 x 650). */
ea_status_t ea_plot_open(ea_plot_t **p, const char *out_path, int width, int height,
                         ea_error_t *err);
/** Append a gnuplot command line (printf-style). */
void ea_plot_cmd(ea_plot_t *p, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;
/** Inline data block $name: begin, rows of n numbers (NaN -> blank line,
 *  which breaks a curve), end. */
void ea_plot_data_begin(ea_plot_t *p, const char *name);
void ea_plot_data_row(ea_plot_t *p, int n, const double *v);
void ea_plot_data_end(ea_plot_t *p);
/** Run gnuplot on the script; on success the figure appears atomically at
 *  out_path. Frees p in every case. */
ea_status_t ea_plot_close(ea_plot_t *p, ea_error_t *err);
/** Free without drawing. */
void ea_plot_discard(ea_plot_t *p);

/* ------------------------------------------------------------------------ */
/* Trajectory files (docs/trajectory-format.md), format version 1            */
/* ------------------------------------------------------------------------ */

#define EA_TRAJ_FORMAT_VERSION 1

/** Columns of a trajectory, in file order. */
#define EA_TRAJ_COLUMNS(X)                                      \
  X(t, "t_s")                                                   \
  X(cable_length, "cable_length_m")                             \
  X(cable_angle, "cable_angle_rad")                             \
  X(base_angle, "base_angle_rad")                               \
  X(cable_length_rate, "cable_length_rate_m_per_s")             \
  X(cable_angle_rate, "cable_angle_rate_rad_per_s")             \
  X(base_angle_rate, "base_angle_rate_rad_per_s")               \
  X(cable_length_acc, "cable_length_acc_m_per_s2")              \
  X(cable_angle_acc, "cable_angle_acc_rad_per_s2")              \
  X(base_angle_acc, "base_angle_acc_rad_per_s2")                \
  X(tension, "tension_N")                                       \
  X(theta0, "theta0_rad")                                       \
  X(theta0_rate, "theta0_rate_rad_per_s")                       \
  X(kappa0, "kappa0_per_m")                                     \
  X(shoulder_torque, "shoulder_torque_Nm")                      \
  X(tip_x, "tip_x_m")                                           \
  X(tip_y, "tip_y_m")                                           \
  X(tip_z, "tip_z_m")

#define EA__TRAJ_ENUM(name, header) EA_TRAJ_##name,
enum { EA_TRAJ_COLUMNS(EA__TRAJ_ENUM) EA_TRAJ_NCOL };
#undef EA__TRAJ_ENUM

/** Header name of column c ("t_s", ...). */
const char *ea_traj_column_name(int c);

/** A trajectory: n samples of EA_TRAJ_NCOL columns, row-major, plus the
 *  metadata the file carries. */
typedef struct ea_traj {
  int n;            /**< number of samples */
  double *data;     /**< n x EA_TRAJ_NCOL, row-major; owned */
  double payload_kg;/**< [kg] payload m_p */
  double tip_mass_kg; /**< [kg] m_L */
  char arm_file[512]; /**< arm file the plan was made with ("" = defaults) */
  char task[512];     /**< task name or file */
  char status[64];    /**< planner status, e.g. "EA_OK" */
} ea_traj_t;

/** Value at sample i, column c. */
#define EA_TRAJ_AT(tr, i, c) ((tr)->data[(size_t)(i) * EA_TRAJ_NCOL + (c)])

/** Allocate n zeroed samples (frees previous data). */
ea_status_t ea_traj_alloc(ea_traj_t *tr, int n);
void ea_traj_free(ea_traj_t *tr);
/** Write atomically (CSV with '#' metadata lines). */
ea_status_t ea_traj_write(const ea_traj_t *tr, const char *path, ea_error_t *err);
/** Read and validate (header, version, monotonic time, finite values);
 *  errors say file:line:column. */
ea_status_t ea_traj_read(ea_traj_t *tr, const char *path, ea_error_t *err);

/* EA_PLAN_SECTION_BEGIN (Ipopt/NLopt planner: planner/plan_*.c) */

/** Trajectory planner (docs/planner.md): a direct transcription of a task
 *  (ea_task_t) solved by Ipopt. Knots k = 0..N-1 at t_k = t_f s_k; per knot
 *  the actuator coordinates q = (L_c, alpha[, base]) and their rates (cubic
 *  Hermite between knots, as in the trajectory file) and the statics
 *  unknowns (T, theta0, kappa0) tied to q by the shooting residual
 *  (kappa(L), x_L - x_c - L_c cos alpha, y_L - y_c - L_c sin alpha) = 0 with
 *  the exact sensitivities of ea_shoot() in the Jacobian. */
typedef struct ea_planner ea_planner_t;

/** Where a solve starts from. */
typedef enum ea_plan_start {
  EA_PLAN_COLD = 0,  /**< statics continuation along the straight interpolation */
  EA_PLAN_WARM,      /**< the planner's last converged solution, with multipliers */
  EA_PLAN_FROM_TRAJ  /**< a previous plan (ea_traj_t) resampled onto the knots */
} ea_plan_start_t;

/** Most distinct active-limit names an info reports. */
#define EA_PLAN_MAX_ACTIVE 16

/** Result of a solve. */
typedef struct ea_plan_info {
  ea_status_t status;        /**< EA_OK, EA_ERR_INFEASIBLE, EA_ERR_NOCONV, EA_ERR_MAXITER, ... */
  int ipopt_status;          /**< raw Ipopt ApplicationReturnStatus */
  char ipopt_status_name[48];
  int iterations;            /**< Ipopt iterations */
  int n_var, n_con, nnz_jac; /**< problem size */
  double objective;          /**< final objective value */
  double duration_s;         /**< [s] t_f */
  double min_tension_margin_N;   /**< [N] min_k T_k - tension_min */
  double peak_shoulder_torque_Nm;/**< [N m] max_k |EI kappa0_k| */
  double max_statics_residual;   /**< max-norm of the statics residual at the knots */
  double max_violation;      /**< largest bound or constraint violation at the final point */
  char worst[160];           /**< what it was: constraint name, knot, by how much */
  int n_active;              /**< limits active (within 1e-6 relative) at some knot */
  char active[EA_PLAN_MAX_ACTIVE][40];
  int active_knots[EA_PLAN_MAX_ACTIVE]; /**< at how many knots / intervals */
  int deriv_errors;          /**< errors found by Ipopt's derivative checker (-1 = not run) */
  int evals_g, evals_jac;    /**< callback counts */
  double time_total_s;       /**< [s] wall time of ea_planner_solve */
  double time_guess_s;       /**< [s] initial guess (statics continuation) */
  double time_statics_s;     /**< [s] shooting with sensitivities inside Ipopt's callbacks */
  double time_ipopt_s;       /**< [s] Ipopt itself (linear algebra, line search), callbacks excluded */
  double time_rest_s;        /**< [s] other callback work and post-processing */
  double time_tune_s;        /**< [s] NLopt schedule tuning (0 when off) */
  double schedule_warp;      /**< knot-time warp parameter used (0 = uniform) */
  char message[512];         /**< human-readable outcome */
} ea_plan_info_t;

/** Build the transcription for a checked task (ea_task_check / ea_task_load;
 *  the task is copied). Only what the task uses is built: base variables
 *  only when the base moves, path rows only for line/polyline paths,
 *  acceleration and speed rows only for finite limits. */
ea_status_t ea_planner_alloc(const ea_task_t *task, ea_planner_t **out, ea_error_t *err);
/** Free; NULL is a no-op. */
void ea_planner_free(ea_planner_t *pl);
/** The planner's task. */
const ea_task_t *ea_planner_task(const ea_planner_t *pl);
/** Plan. prev is used with EA_PLAN_FROM_TRAJ only (may be NULL otherwise).
 *  EA_PLAN_WARM without a previous converged solution falls back to cold.
 *  Returns EA_OK only for a converged plan satisfying every limit; then
 *  ea_planner_trajectory() gives it. On failure info->message says which
 *  constraint, at which knot, by how much (EA_ERR_INFEASIBLE when Ipopt
 *  proves local infeasibility or the path leaves the workspace). */
ea_status_t ea_planner_solve(ea_planner_t *pl, ea_plan_start_t start, const ea_traj_t *prev,
                             ea_plan_info_t *info, ea_error_t *err);
/** The last converged plan, one row per knot, every column filled
 *  (tip from the statics tip and the base angle). tr is (re)allocated. */
ea_status_t ea_planner_trajectory(const ea_planner_t *pl, ea_traj_t *tr, ea_error_t *err);
/** Write the JSON summary (status, duration, iterations, times, margins,
 *  active limits) atomically. */
ea_status_t ea_plan_summary_write(const ea_planner_t *pl, const ea_plan_info_t *info,
                                  const char *path, ea_error_t *err);
/** Figure of the last converged plan: tip path and beam shapes in the
 *  workspace of the payload, and the time histories (.svg, .png, .pdf). */
ea_status_t ea_plan_figure(ea_planner_t *pl, const char *path, ea_error_t *err);

/* EA_PLAN_SECTION_END */

/* EA_STREAM_SECTION_BEGIN (command streamer: planner/stream_*.c) */
/* EA_STREAM_SECTION_END */

#ifdef __cplusplus
}
#endif
#endif
