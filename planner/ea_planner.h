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
#define EA_TRAJ_COLUMNS(X)                                                                         \
  X(t, "t_s")                                                                                      \
  X(cable_length, "cable_length_m")                                                                \
  X(cable_angle, "cable_angle_rad")                                                                \
  X(base_angle, "base_angle_rad")                                                                  \
  X(cable_length_rate, "cable_length_rate_m_per_s")                                                \
  X(cable_angle_rate, "cable_angle_rate_rad_per_s")                                                \
  X(base_angle_rate, "base_angle_rate_rad_per_s")                                                  \
  X(cable_length_acc, "cable_length_acc_m_per_s2")                                                 \
  X(cable_angle_acc, "cable_angle_acc_rad_per_s2")                                                 \
  X(base_angle_acc, "base_angle_acc_rad_per_s2")                                                   \
  X(tension, "tension_N")                                                                          \
  X(theta0, "theta0_rad")                                                                          \
  X(theta0_rate, "theta0_rate_rad_per_s")                                                          \
  X(kappa0, "kappa0_per_m")                                                                        \
  X(shoulder_torque, "shoulder_torque_Nm")                                                         \
  X(tip_x, "tip_x_m")                                                                              \
  X(tip_y, "tip_y_m")                                                                              \
  X(tip_z, "tip_z_m")

#define EA__TRAJ_ENUM(name, header) EA_TRAJ_##name,
enum { EA_TRAJ_COLUMNS(EA__TRAJ_ENUM) EA_TRAJ_NCOL };
#undef EA__TRAJ_ENUM

/** Header name of column c ("t_s", ...). */
const char *ea_traj_column_name(int c);

/** A trajectory: n samples of EA_TRAJ_NCOL columns, row-major, plus the
 *  metadata the file carries. */
typedef struct ea_traj {
  int n;              /**< number of samples */
  double *data;       /**< n x EA_TRAJ_NCOL, row-major; owned */
  double payload_kg;  /**< [kg] payload m_p */
  double tip_mass_kg; /**< [kg] m_L */
  char arm_file[512]; /**< arm file the plan was made with ("" = defaults) */
  char task[512];     /**< task name or file */
  char status[64];    /**< planner status, e.g. "EA_OK" */
} ea_traj_t;

/** Value at sample i, column c. */
#define EA_TRAJ_AT(tr, i, c) ((tr)->data[(size_t)(i)*EA_TRAJ_NCOL + (c)])

/** Allocate n zeroed samples (frees previous data). */
ea_status_t ea_traj_alloc(ea_traj_t *tr, int n);
void ea_traj_free(ea_traj_t *tr);
/** Fill the statics columns of sample i from a configuration p = (alpha, T,
 *  theta0, kappa0) with tip state xL: tension, theta0, kappa0, shoulder
 *  torque EI kappa0, and the tip in the base frame using the sample's base
 *  angle. (Rates and the actuator columns are left alone.) */
void ea_traj_set_statics(ea_traj_t *tr, int i, const double p[4], const double xL[4], double EI);
/** Write atomically (CSV with '#' metadata lines). */
ea_status_t ea_traj_write(const ea_traj_t *tr, const char *path, ea_error_t *err);
/** Read and validate (header, version, monotonic time, finite values);
 *  errors say file:line:column. */
ea_status_t ea_traj_read(ea_traj_t *tr, const char *path, ea_error_t *err);

/** Figure of a trajectory: tip path and beam shapes (from its alpha, T,
 *  theta0, kappa0 columns, shot with sh, which carries the arm and load) in
 *  the workspace, actuator coordinates, tension and torque, and rates over
 *  time. title may be NULL. (.svg, .png, .pdf) */
ea_status_t ea_traj_figure(const ea_traj_t *tr, ea_shooter_t *sh, double cable_length_min,
                           double tension_min, const char *title, const char *path,
                           ea_error_t *err);

/* EA_PLAN_SECTION_BEGIN (Ipopt/NLopt planner: planner/plan_*.c) */

/** Trajectory planner (docs/planner.md): a direct transcription of a task
 *  (ea_task_t) solved by Ipopt. Knots k = 0..N-1 at t_k = t_f s_k; per knot
 *  the actuator coordinates q = (L_c, alpha[, base]) and their rates (cubic
 *  Hermite between knots, as in the trajectory file), the statics unknowns
 *  (T, theta0, kappa0) tied to q by the shooting residual
 *  (kappa(L), x_L - x_c - L_c cos alpha, y_L - y_c - L_c sin alpha) = 0 with
 *  the exact sensitivities of ea_shoot() in the Jacobian, and theta0's rate
 *  (theta0 a C2 cubic spline). Every limit holds between the knots too
 *  (docs/planner.md, "Limits between the knots"). */
typedef struct ea_planner ea_planner_t;

/** Where a solve starts from. */
typedef enum ea_plan_start {
  EA_PLAN_COLD = 0, /**< statics continuation along the straight interpolation */
  EA_PLAN_WARM,     /**< the planner's last converged solution, with multipliers
                         (after ea_planner_update: shifted along the change) */
  EA_PLAN_FROM_TRAJ /**< a previous plan (ea_traj_t) resampled onto the knots */
} ea_plan_start_t;

/** Most distinct active-limit names an info reports. */
#define EA_PLAN_MAX_ACTIVE 16

/** Result of a solve. */
typedef struct ea_plan_info {
  ea_status_t status; /**< EA_OK, EA_ERR_INFEASIBLE, EA_ERR_NOCONV, EA_ERR_MAXITER, ... */
  int ipopt_status;   /**< raw Ipopt ApplicationReturnStatus */
  char ipopt_status_name[48];
  int iterations;                 /**< Ipopt iterations */
  int n_var, n_con, nnz_jac;      /**< problem size */
  double objective;               /**< final objective value */
  double duration_s;              /**< [s] t_f */
  double min_tension_margin_N;    /**< [N] min_k T_k - tension_min */
  double peak_shoulder_torque_Nm; /**< [N m] max_k |EI kappa0_k| */
  double max_statics_residual;    /**< max-norm of the statics residual at the knots */
  double max_violation;           /**< largest bound or constraint violation at the final point */
  char worst[160];                /**< what it was: constraint name, knot, by how much */
  int n_active;                   /**< limits active (within 1e-6 relative) at some knot */
  char active[EA_PLAN_MAX_ACTIVE][40];
  int active_knots[EA_PLAN_MAX_ACTIVE]; /**< at how many knots / intervals */
  int deriv_errors;       /**< errors found by Ipopt's derivative checker (-1 = not run) */
  int evals_g, evals_jac; /**< callback counts */
  double time_total_s;    /**< [s] wall time of ea_planner_solve */
  double time_guess_s;    /**< [s] initial guess (statics continuation) */
  double time_statics_s;  /**< [s] shooting with sensitivities inside Ipopt's callbacks */
  double time_ipopt_s;    /**< [s] Ipopt itself (linear algebra, line search), callbacks excluded */
  double time_rest_s;     /**< [s] other callback work and post-processing */
  int between_passes;     /**< re-solves with knot bounds tightened because a limit was
                               exceeded between the knots (docs/planner.md) */
  double time_freq_model_s;      /**< [s] building the FE frequency model (ea_planner_alloc;
                                      0 when the task needs none) */
  double min_first_frequency_hz; /**< [Hz] min over the knots of the model's f1 (NAN: no model) */
  double max_modal_deflection_m; /**< [m] max over the interval ends of |s_c acc_c| / omega1^2,
                                      s = (1, L_c) (NAN: no model) */
  /* dynamics (task key dynamics; NAN without) */
  double time_dyn_model_s;     /**< [s] reduced-model table: built or loaded */
  double predicted_residual_m; /**< [m] the model's residual tip amplitude after the
                                    motion: sum_i of the modes' amplitudes */
  double predicted_amplitude_m[EA_ROM_MAX_MODES]; /**< [m] per mode (nominal model) */
  double predicted_residual_worst_m;              /**< [m] the largest over the models (robust) */
  double max_modal_deviation_m;                   /**< [m] max over the knots of the modal tip
                                                       deviation from the quasi-static tip */
  double min_dynamic_tension_margin_N; /**< [N] min over the knots of T + modal part - min */
  char message[512];                   /**< human-readable outcome */
} ea_plan_info_t;

/** The reduced dynamic model of a planner (task key dynamics). */
typedef struct ea_plan_dyn_info {
  int built;                 /**< 1 if the task has dynamics */
  int models;                /**< 1, or 5 with dynamics.robust (nominal + four corners) */
  double model_tip_mass[5];  /**< [kg] each model's tip mass */
  double model_EI[5];        /**< [N m^2] each model's EI */
  ea_rom_table_info_t table; /**< grid, box, extrapolated points, build time */
  int cache_loaded;          /**< 1: the table came from the cache */
  int cache_saved;           /**< 1: it was built and saved */
  char cache_path[1200];     /**< the cache file ("" = none) */
  double time_s;             /**< [s] to build or load */
} ea_plan_dyn_info_t;

/** Build the transcription for a checked task (ea_task_check / ea_task_load;
 *  the task is copied). Only what the task uses is built: base variables
 *  only when the base moves, path rows only for line/polyline paths,
 *  acceleration and speed rows only for finite limits, the FE frequency
 *  model only for min_vibration, min_first_frequency_Hz or
 *  max_modal_deflection_m. */
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
/** Replanning: change what a live planner solves without rebuilding it.
 *  task (checked by ea_task_check; copied) may differ from the planner's in
 *  its points (start, goal, vias), payload, limit values, duration, objective
 *  weights and solver settings, but not in anything that shapes the
 *  transcription: knot count, number of vias, path kind, objective, base
 *  motion, free/fixed duration, acceleration continuity, Hessian mode,
 *  which speed/acceleration limits are finite, the arm, nor a task with a
 *  frequency model; then EA_ERR_ARG says what differs (build a new planner).
 *  The next ea_planner_solve(EA_PLAN_WARM) starts from the previous plan and
 *  its multipliers, shifted along the change (docs/planner.md: points
 *  moved, statics re-solved at every knot, min_time re-timed), and falls
 *  back to a cold solve if that does not converge; info->iterations counts
 *  both. Without a previous plan the next solve is cold. */
ea_status_t ea_planner_update(ea_planner_t *pl, const ea_task_t *task, ea_error_t *err);
/** ea_planner_update with the planner's task and another goal (resolved and
 *  checked: EA_ERR_INFEASIBLE when it is outside the workspace). */
ea_status_t ea_planner_update_goal(ea_planner_t *pl, const ea_task_point_t *goal, ea_error_t *err);
/** ... another start point. */
ea_status_t ea_planner_update_start(ea_planner_t *pl, const ea_task_point_t *start,
                                    ea_error_t *err);
/** ... another payload [kg] (every point re-checked against its workspace). */
ea_status_t ea_planner_update_payload(ea_planner_t *pl, double payload_kg, ea_error_t *err);
/** ... other limit values (the same limits finite). */
ea_status_t ea_planner_update_limits(ea_planner_t *pl, const ea_task_limits_t *limits,
                                     ea_error_t *err);
/** The last converged plan, one row per knot, every column filled
 *  (tip from the statics tip and the base angle). tr is (re)allocated.
 *  EA_ERR_ARG when no plan converged since the last ea_planner_update. */
ea_status_t ea_planner_trajectory(const ea_planner_t *pl, ea_traj_t *tr, ea_error_t *err);
/** Write the JSON summary (status, duration, iterations, times, margins,
 *  active limits) atomically. */
ea_status_t ea_plan_summary_write(const ea_planner_t *pl, const ea_plan_info_t *info,
                                  const char *path, ea_error_t *err);
/** Figure of the last converged plan: tip path and beam shapes in the
 *  workspace of the payload, and the time histories (.svg, .png, .pdf). */
ea_status_t ea_plan_figure(ea_planner_t *pl, const char *path, ea_error_t *err);

/** The planner's model of the first natural frequency f1(L_c, alpha): FE
 *  frequencies (ea_fe_static_solve holding the tip + ea_fe_modes, passive
 *  cable, the task's tip mass) on a grid over the task's region of the
 *  (L_c, alpha) plane, interpolated by a GSL bicubic spline (docs/planner.md). */
typedef struct ea_plan_freq_model_info {
  int built;                         /**< 1 if the task needed (and got) the model */
  int n_cable_length, n_cable_angle; /**< grid points */
  double cable_length_range[2];      /**< [m] grid box (also bounds L_c in the plan) */
  double cable_angle_range[2];       /**< [rad] grid box (also bounds alpha in the plan) */
  int n_extrapolated;                /**< grid points without a valid FE state (outside the
                                          workspace or not converged), filled by extrapolation */
  double f1_min_hz, f1_max_hz;       /**< [Hz] over the valid grid points */
  double f_ref_hz;                   /**< [Hz] f1 at the start (scale of the vibration term) */
  double time_s;                     /**< [s] wall time to build it */
} ea_plan_freq_model_info_t;

/** The frequency model's info (built = 0 when the task needs none). */
ea_status_t ea_planner_freq_model(const ea_planner_t *pl, ea_plan_freq_model_info_t *info);
/** f1 [Hz] of the model at (L_c [m], alpha [rad]) (clamped to the grid box)
 *  and its gradient [Hz/m, Hz/rad] (grad may be NULL). EA_ERR_ARG when the
 *  planner has no frequency model. */
ea_status_t ea_planner_first_frequency(const ea_planner_t *pl, double cable_length,
                                       double cable_angle, double *f1_hz, double grad[2],
                                       ea_error_t *err);

/** The reduced dynamic model's info (built = 0 when the task has no dynamics). */
ea_status_t ea_planner_dyn_model(const ea_planner_t *pl, ea_plan_dyn_info_t *info);
/** The planner's reduced-model table (NULL when the task has no dynamics); owned by pl. */
const ea_rom_table_t *ea_planner_rom_table(const ea_planner_t *pl);
/** A task with dynamics that ends at rest: hold the modal state at the goal at (eta_i,
 *  eta_i') [sqrt(kg) m, sqrt(kg) m / s] (K values each; NULL = zeros) instead of zero. An
 *  FE-in-the-loop refinement uses it to cancel what the reduced model misses: the next
 *  ea_planner_solve (EA_PLAN_WARM from the last plan) plans for the new target. */
ea_status_t ea_planner_set_terminal_modes(ea_planner_t *pl, const double *eta,
                                          const double *eta_rate, ea_error_t *err);
/** The same for model `model` of a robust plan (dynamics.robust; 0 = the nominal, as
 *  ea_planner_set_terminal_modes; 1..4 = the corners in ea_plan_dyn_info_t's order): a
 *  corner's terminal row becomes "modal state within robust residual_m of (eta, eta_rate)"
 *  (K values each; NULL = zeros, the default). EA_ERR_ARG for a model the planner does not
 *  have or a target that is not finite. */
ea_status_t ea_planner_set_terminal_modes_model(ea_planner_t *pl, int model, const double *eta,
                                                const double *eta_rate, ea_error_t *err);

/* EA_PLAN_SECTION_END */

/* EA_STREAM_SECTION_BEGIN (command streamer: planner/stream_*.c) */

/* Command streamer (docs/streaming.md) and its wire format (docs/protocol.md):
 * trajectory -> actuator setpoints at the controller rate -> frames -> a
 * transport (tcp, udp, serial, file) -> a controller (or controller-sim). */

#include <signal.h>
#include <stdint.h>

/** Version of the wire format (docs/protocol.md). */
#define EA_PROTO_VERSION 1
/** Frame magic, bytes 'E' 'A' 'S' 'F' on the wire (0x46534145 read as LE u32). */
#define EA_PROTO_MAGIC 0x46534145u
/** Bytes of the fixed header (magic .. timestamp) and of the trailing CRC. */
#define EA_PROTO_HEADER_BYTES 20
#define EA_PROTO_CRC_BYTES 4
/** Largest frame on the wire [bytes]. */
#define EA_PROTO_FRAME_MAX 256

/** One actuator setpoint in motor coordinates (what goes on the wire). */
typedef struct ea_setpoint {
  double spool_pos[2];    /**< [rad] spool motor positions (both spools; equal) */
  double spool_vel[2];    /**< [rad/s] */
  double spool_acc[2];    /**< [rad/s^2] */
  double shoulder_pos;    /**< [rad] shoulder motor = theta0 */
  double shoulder_vel;    /**< [rad/s] */
  double shoulder_acc;    /**< [rad/s^2] */
  double base_pos;        /**< [rad] base motor */
  double base_vel;        /**< [rad/s] */
  double base_acc;        /**< [rad/s^2] */
  double shoulder_torque; /**< [N m] feed-forward EI kappa0 */
  double tension;         /**< [N] cable tension feed-forward */
} ea_setpoint_t;

/** Number of doubles of an ::ea_setpoint_t on the wire. */
#define EA_SETPOINT_DOUBLES 14

/** The same point in the trajectory's (joint) coordinates. */
typedef struct ea_joint_state {
  double cable_length, cable_length_rate, cable_length_acc; /**< [m], [m/s], [m/s^2] */
  double theta0, theta0_rate, theta0_acc;                   /**< [rad], [rad/s], [rad/s^2] */
  double base_angle, base_angle_rate, base_angle_acc;       /**< [rad], [rad/s], [rad/s^2] */
  double tension;                                           /**< [N] */
  double kappa0;                                            /**< [1/m] */
} ea_joint_state_t;

/** Joint state -> motor setpoint: spool = (L_c - zero_length) / radius *
 *  gear_ratio (both spools), shoulder = theta0, base = base angle, torque
 *  feed-forward EI kappa0, tension feed-forward T. */
void ea_stream_map(const ea_arm_t *arm, const ea_joint_state_t *q, ea_setpoint_t *sp);
/** Inverse of ea_stream_map (spool 0 is used for the cable length). */
void ea_stream_unmap(const ea_arm_t *arm, const ea_setpoint_t *sp, ea_joint_state_t *q);

/** Check one setpoint against every limit of the arm file (ranges, speeds,
 *  accelerations, tension, shoulder torque; both spools must agree). tol is a
 *  relative slack (e.g. 1e-9). On failure err->msg names the quantity, its
 *  value and the bound; returns EA_ERR_INADMISSIBLE. */
ea_status_t ea_stream_check_limits(const ea_arm_t *arm, const ea_setpoint_t *sp, double tol,
                                   ea_error_t *err);

/** Evaluate a trajectory at time t [s] (clamped to its span): quintic
 *  Hermite of value, rate and acceleration for cable length and base angle;
 *  theta0 quintic with the accelerations of the cubic Hermite of theta0 and
 *  its rate at the samples (the mean of both sides: equal for a planned,
 *  C2 theta0, so the quintic is that cubic);
 *  tension and kappa0 cubic Hermite with centred-difference slopes. */
ea_status_t ea_stream_traj_eval(const ea_traj_t *tr, double t, ea_joint_state_t *q);

/** Resample tr at rate_hz: n = ceil(duration * rate) + 1 setpoints at
 *  t_k = t_0 + min(k / rate, duration), mapped to motor coordinates and
 *  checked against the arm's limits (tol relative slack). *out is malloc'd
 *  (caller frees); on a limit violation err->msg names the sample and time. */
ea_status_t ea_stream_resample(const ea_traj_t *tr, const ea_arm_t *arm, double rate_hz, double tol,
                               ea_setpoint_t **out, int *n, ea_error_t *err);

/** Same, with the trajectory played time_scale (>= 1) times slower: t_plan =
 *  t / time_scale, rates / time_scale, accelerations / time_scale^2 (a
 *  uniform time scaling keeps the path; the feed-forwards, quasi-static, are
 *  unchanged). time_scale = 1 is ea_stream_resample. */
ea_status_t ea_stream_resample_scaled(const ea_traj_t *tr, const ea_arm_t *arm, double rate_hz,
                                      double time_scale, double tol, ea_setpoint_t **out, int *n,
                                      ea_error_t *err);

/** Smallest time scale s >= 1 for which ea_stream_resample_scaled(tr, arm,
 *  rate_hz, s, tol) passes the limits check: the interpolant between the
 *  plan's samples can exceed a speed or acceleration limit the plan meets
 *  only at its samples (e.g. at bang-bang switches). EA_ERR_INADMISSIBLE if
 *  a limit no time scaling changes fails (range, tension, torque). */
ea_status_t ea_stream_min_time_scale(const ea_traj_t *tr, const ea_arm_t *arm, double rate_hz,
                                     double tol, double *scale, ea_error_t *err);

/** Controlled stop from sp (position, velocity, acceleration of each axis):
 *  every axis follows v(s) = v0 h00(s) + T a0 h10(s) (cubic Hermite in
 *  s = t / T to v = a = 0), all axes with one common duration T, the
 *  shortest multiple of 1/rate_hz that keeps every |acceleration| within
 *  margin * limit. Feed-forwards are held. Writes at most max setpoints
 *  (the last at rest) to out; returns their number (>= 1), or -1 if max is
 *  too small. */
int ea_stream_stop_ramp(const ea_arm_t *arm, const ea_setpoint_t *sp, double rate_hz, double margin,
                        ea_setpoint_t *out, int max);

/* ---- Frames ------------------------------------------------------------ */

/** Frame types (docs/protocol.md). */
typedef enum ea_frame_type {
  EA_FRAME_HELLO = 0x01,     /**< streamer -> controller: session start */
  EA_FRAME_SETPOINT = 0x02,  /**< streamer -> controller: one setpoint */
  EA_FRAME_HEARTBEAT = 0x03, /**< either way: keep-alive, no payload */
  EA_FRAME_END = 0x04,       /**< streamer -> controller: session end */
  EA_FRAME_ACK = 0x81,       /**< controller -> streamer: acknowledgement */
  EA_FRAME_NACK = 0x82       /**< controller -> streamer: rejection */
} ea_frame_type_t;

/** Setpoint flags. */
enum { EA_SP_FLAG_LAST = 1u, EA_SP_FLAG_STOP = 2u };

/** Controller states reported in ACK/NACK. */
typedef enum ea_ctrl_state {
  EA_CTRL_IDLE = 0,     /**< no session */
  EA_CTRL_READY = 1,    /**< session open, holding position */
  EA_CTRL_RUNNING = 2,  /**< executing setpoints */
  EA_CTRL_STOPPING = 3, /**< executing a controlled stop */
  EA_CTRL_DONE = 4,     /**< session ended, at rest */
  EA_CTRL_FAULT = 5     /**< stopped after a fault; needs a new session */
} ea_ctrl_state_t;

/** NACK reasons (also in ACK: 0). */
typedef enum ea_nack_reason {
  EA_NACK_NONE = 0,
  EA_NACK_CRC = 1,        /**< bad CRC or malformed frame */
  EA_NACK_SEQUENCE = 2,   /**< duplicate or out-of-order sequence number */
  EA_NACK_LIMIT = 3,      /**< setpoint beyond the arm's limits */
  EA_NACK_CONTINUITY = 4, /**< jump from the previous setpoint */
  EA_NACK_OVERFLOW = 5,   /**< controller buffer full */
  EA_NACK_STATE = 6,      /**< frame not allowed in this state */
  EA_NACK_VERSION = 7     /**< unsupported protocol version */
} ea_nack_reason_t;

/** END reasons. */
typedef enum ea_end_reason {
  EA_END_COMPLETE = 0, /**< every setpoint sent */
  EA_END_STOPPED = 1,  /**< controlled stop after NACK, timeout or interrupt */
  EA_END_REFUSED = 2   /**< handshake refused by the streamer */
} ea_end_reason_t;

/** Decoded frame (all types share one flat struct; fields per type in
 *  docs/protocol.md). */
typedef struct ea_frame {
  uint8_t version;  /**< EA_PROTO_VERSION */
  uint8_t type;     /**< ::ea_frame_type_t */
  uint32_t seq;     /**< sequence number (streamer: HELLO 0, then +1 per frame) */
  uint64_t time_us; /**< [us] setpoint time since the session start (sender clock) */
  /* SETPOINT, HELLO (the trajectory's start) */
  uint32_t flags; /**< SETPOINT: EA_SP_FLAG_*; END: ::ea_end_reason_t */
  ea_setpoint_t sp;
  /* HELLO */
  uint32_t rate_hz;      /**< setpoint rate */
  uint32_t count;        /**< HELLO: setpoints planned; END: setpoints sent */
  uint32_t heartbeat_ms; /**< HELLO: heartbeat period */
  /* ACK / NACK */
  uint32_t ack_seq;      /**< highest sequence number accepted */
  uint32_t accepted;     /**< setpoints accepted so far */
  uint32_t rejected;     /**< frames rejected so far */
  uint16_t buffer_level; /**< setpoints buffered, not yet executed */
  uint16_t buffer_capacity;
  uint8_t state;    /**< ::ea_ctrl_state_t */
  uint8_t reason;   /**< ::ea_nack_reason_t */
  double actual[4]; /**< controller's positions: spool 0, spool 1, shoulder, base [rad] */
} ea_frame_t;

/** CRC-32 (IEEE 802.3 / zlib: reflected 0xEDB88320, init and xorout
 *  0xFFFFFFFF); crc = 0 to start, pass the previous value to continue. */
uint32_t ea_crc32(uint32_t crc, const void *buf, size_t len);

/** Encode f into buf (cap bytes, >= EA_PROTO_FRAME_MAX is always enough);
 *  returns the frame's length or 0 if f->type is unknown or cap too small. */
size_t ea_frame_encode(const ea_frame_t *f, uint8_t *buf, size_t cap);

/** Decode exactly one frame of len bytes. EA_ERR_PROTOCOL with err->msg if
 *  the magic, version, type, length or CRC is wrong, or a value is not finite. */
ea_status_t ea_frame_decode(const uint8_t *buf, size_t len, ea_frame_t *f, ea_error_t *err);

/** Incremental parser of a byte stream (TCP, serial): feed bytes, take
 *  frames. A bad frame is skipped by resynchronising on the next magic and
 *  counted. No allocation. */
typedef struct ea_frame_parser {
  uint8_t buf[2 * EA_PROTO_FRAME_MAX];
  size_t len;
  uint64_t bad_frames;    /**< frames dropped (CRC, length, version, type, values) */
  uint64_t skipped_bytes; /**< bytes discarded while resynchronising */
} ea_frame_parser_t;

void ea_frame_parser_init(ea_frame_parser_t *p);
/** Append up to len bytes; returns how many were taken (less when full:
 *  call ea_frame_parser_next and feed the rest). */
size_t ea_frame_parser_feed(ea_frame_parser_t *p, const uint8_t *data, size_t len);
/** Next complete frame: 1 = f filled, 0 = need more bytes, -1 = a bad frame
 *  was dropped (call again). */
int ea_frame_parser_next(ea_frame_parser_t *p, ea_frame_t *f);

/* ---- Streamer ---------------------------------------------------------- */

/** Streamer settings (ea_stream_settings_default fills them). */
typedef struct ea_stream_settings {
  double rate_hz;             /**< setpoint rate (default 1000) */
  double limit_tol;           /**< relative slack of the limits check (default 1e-6) */
  double stop_margin;         /**< stop ramp uses at most this fraction of the accel limits (0.9) */
  double ack_timeout_s;       /**< outstanding frames without an ACK this long -> stop (0.1) */
  double handshake_timeout_s; /**< wait for the HELLO answer (1.0) */
  double end_timeout_s;       /**< wait for the END answer (1.0) */
  double heartbeat_s;         /**< heartbeat period when no setpoint is due (0.1) */
  double start_tol_cable;     /**< [m] handshake tolerance on L_c (1e-3) */
  double start_tol_angle;     /**< [rad] handshake tolerance on theta0 and base (0.01) */
  int realtime;               /**< 1: pace at rate_hz (default); 0: as fast as possible */
  int wait_acks;              /**< 1: handshake and ACKs (default); 0: dry run (file:) */
  const volatile sig_atomic_t *stop_request; /**< nonzero -> controlled stop (SIGINT) */
} ea_stream_settings_t;

void ea_stream_settings_default(ea_stream_settings_t *s);
ea_status_t ea_stream_settings_validate(const ea_stream_settings_t *s, ea_error_t *err);

/** Why the stream ended. */
typedef enum ea_stream_end {
  EA_STREAM_COMPLETE = 0,     /**< every setpoint sent and acknowledged */
  EA_STREAM_REFUSED,          /**< handshake: controller not at the trajectory's start */
  EA_STREAM_STOP_NACK,        /**< controller rejected a frame: controlled stop */
  EA_STREAM_STOP_ACK_TIMEOUT, /**< acknowledgements stopped: controlled stop */
  EA_STREAM_STOP_INTERRUPT,   /**< stop requested (SIGINT): controlled stop */
  EA_STREAM_DISCONNECTED,     /**< link lost: the controller's watchdog must stop */
  EA_STREAM_ERROR             /**< could not start (connect, handshake timeout) */
} ea_stream_end_t;

const char *ea_stream_end_name(ea_stream_end_t e);

/** Summary of a stream. */
typedef struct ea_stream_info {
  ea_status_t status; /**< EA_OK only for EA_STREAM_COMPLETE */
  ea_stream_end_t end;
  int setpoints;              /**< setpoints of the resampled trajectory */
  int frames_sent;            /**< setpoint frames written (stop ramp included) */
  int stop_frames;            /**< of which stop ramp */
  int frames_acked;           /**< setpoints the controller reported accepted */
  int frames_late;            /**< sent more than half a period after their deadline */
  int nacks;                  /**< NACK frames received */
  int acks;                   /**< ACK frames received */
  int ctrl_rejected;          /**< frames the controller reported rejected */
  int ctrl_state;             /**< last reported ::ea_ctrl_state_t (-1 none) */
  int nack_reason;            /**< reason of the first NACK */
  int buffer_min, buffer_max; /**< controller buffer level seen in ACKs */
  int ack_bad_frames;         /**< malformed frames received from the controller */
  double jitter_p50_us, jitter_p99_us, jitter_max_us; /**< |send time - deadline| */
  double ack_latency_max_ms; /**< longest wait for an outstanding frame's ACK */
  double duration_s;         /**< wall time of the setpoint phase */
} ea_stream_info_t;

/** Stream setpoints sp[0..n-1] to the transport named by url
 *  ("tcp://HOST:PORT", "udp://HOST:PORT", "serial:DEVICE[@BAUD]",
 *  "file:PATH", "file:-" = stdout): handshake, paced sending, ACKs, and on
 *  NACK / ACK timeout / stop request a controlled stop. Never prints.
 * @param[out] info summary (always filled)
 * @return EA_OK if complete; EA_ERR_INADMISSIBLE refused handshake;
 *         EA_ERR_PROTOCOL NACK; EA_ERR_NET link; EA_ERR_INTERRUPTED stop request */
ea_status_t ea_stream_run(const ea_arm_t *arm, const ea_setpoint_t *sp, int n, const char *url,
                          const ea_stream_settings_t *s, ea_stream_info_t *info, ea_error_t *err);

/* ---- Controller simulator ---------------------------------------------- */

/** Faults the simulator injects. */
typedef enum ea_ctrl_fault {
  EA_FAULT_NONE = 0,
  EA_FAULT_DROP_AFTER,   /**< close the link after N accepted setpoints */
  EA_FAULT_DELAY_ACK,    /**< delay every ACK by N ms */
  EA_FAULT_WITHHOLD_ACK, /**< answer HELLO, never acknowledge setpoints */
  EA_FAULT_CORRUPT_EVERY /**< flip a byte of every N-th received frame */
} ea_ctrl_fault_t;

/** Simulator settings (ea_ctrl_settings_default fills them). */
typedef struct ea_ctrl_settings {
  int udp;               /**< 0: TCP (default), 1: UDP */
  int max_frames;        /**< stop after this many setpoints (0 = no limit) */
  double timeout_s;      /**< give up when no session/frame for this long (10) */
  double watchdog_s;     /**< RUNNING without a frame this long -> own stop (0.1) */
  int buffer_capacity;   /**< simulated setpoint buffer (256) */
  double limit_tol;      /**< relative slack of the limits check (1e-6) */
  double continuity_tol; /**< relative slack of the continuity check (0.05) */
  ea_ctrl_fault_t fault;
  long fault_arg;    /**< N or ms of the fault */
  int has_initial;   /**< 1: report initial[] at HELLO; 0: adopt the HELLO's start */
  double initial[3]; /**< L_c [m], theta0 [rad], base [rad] */
  const volatile sig_atomic_t *stop_request; /**< nonzero -> end */
} ea_ctrl_settings_t;

void ea_ctrl_settings_default(ea_ctrl_settings_t *s);

/** One logged setpoint. */
typedef struct ea_ctrl_log_row {
  uint32_t seq;  /**< sequence number (0 for the simulator's own stop) */
  double time_s; /**< [s] setpoint time from the frame (own stop: extrapolated) */
  double recv_s; /**< [s] receive time since the first setpoint */
  int source;    /**< 0 received, 1 stop ramp received, 2 own stop (watchdog, drop) */
  ea_setpoint_t sp;
} ea_ctrl_log_row_t;

/** Simulator summary. */
typedef struct ea_ctrl_info {
  ea_status_t status;
  int sessions; /**< HELLOs answered */
  int accepted; /**< setpoints accepted */
  int rejected; /**< frames rejected (all reasons) */
  int rejected_crc, rejected_seq, rejected_limit, rejected_continuity;
  int gaps;            /**< setpoints missing between accepted sequence numbers */
  int own_stop_frames; /**< setpoints of the simulator's own stop */
  int end_received;    /**< 1 if END arrived */
  uint32_t end_reason; /**< its reason */
  int final_state;     /**< ::ea_ctrl_state_t at exit */
  int max_buffer;      /**< highest buffer level */
} ea_ctrl_info_t;

typedef struct ea_ctrl ea_ctrl_t;

/** Bind and listen on "HOST:PORT" (PORT 0 = ephemeral; see ea_ctrl_port).
 *  HOST must be a numeric address; loopback unless the caller chose otherwise. */
ea_status_t ea_ctrl_open(const ea_arm_t *arm, const char *listen, const ea_ctrl_settings_t *s,
                         ea_ctrl_t **out, ea_error_t *err);
/** Bound port. */
int ea_ctrl_port(const ea_ctrl_t *c);
/** Serve one session: accept, handshake, check and log setpoints, answer,
 *  until END, the link drops, max_frames, a timeout or a stop request.
 *  Never prints. */
ea_status_t ea_ctrl_run(ea_ctrl_t *c, ea_ctrl_info_t *info, ea_error_t *err);
/** The log: rows in receive order (own stop rows last). Owned by c. */
const ea_ctrl_log_row_t *ea_ctrl_log(const ea_ctrl_t *c, int *n);
/** Write the log as CSV, atomically. */
ea_status_t ea_ctrl_log_write(const ea_ctrl_t *c, const char *path, ea_error_t *err);
void ea_ctrl_free(ea_ctrl_t *c);

/* EA_STREAM_SECTION_END */

#ifdef __cplusplus
}
#endif
#endif
