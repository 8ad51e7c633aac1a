/**
 * @file ea_problems.h
 * @brief What a user asks: arm files, task specs, workspace, torque maps,
 *        path admissibility, sweeps and studies. Knows nothing of Ipopt.
 */
#ifndef EA_PROBLEMS_H
#define EA_PROBLEMS_H

#include "ea_model.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------------------ */
/* Arm files (data/elasticarm.yaml)                                          */
/* ------------------------------------------------------------------------ */

/** Load and validate an arm file. Every key is required; errors name
 *  file:line:column, the key, the value and the bound.
 * @param[in]  path  YAML file
 * @param[out] arm   filled on success
 */
ea_status_t ea_arm_load(const char *path, ea_arm_t *arm, ea_error_t *err);
/** Same from a string (len bytes); name is used in messages. */
ea_status_t ea_arm_load_string(const char *name, const char *text, size_t len, ea_arm_t *arm,
                               ea_error_t *err);

/* EA_STATICS_PROBLEMS_SECTION_BEGIN (workspace, torque map, path: problems/statics_*.c) */

/** One point of a workspace edge, torque map or path: a statics solution
 *  flattened with the quantities users ask for. */
typedef struct ea_config_point {
  double cable_length;    /**< [m] L_c */
  double alpha;           /**< [rad] cable angle */
  double x, y;            /**< [m] tip */
  double tension;         /**< [N] T */
  double theta0;          /**< [rad] shoulder angle */
  double kappa0;          /**< [1/m] shoulder curvature */
  double shoulder_torque; /**< [N m] EI kappa0 */
  double residual;        /**< statics residual */
  int iterations;         /**< Newton iterations */
  ea_status_t status;     /**< EA_OK or why there is no valid configuration */
  int stable;             /**< FE passive stiffness positive definite: 1, 0, or -1 not checked */
  int admissible;         /**< 1 if every limit holds (path, torque map) */
  char reason[96];        /**< why not admissible ("" if admissible) */
} ea_config_point_t;

/** Outer workspace edge (T = 0, eq. 16) at n cable angles (ascending or
 *  descending), warm-starting each from its neighbour. Points that fail keep
 *  their status; returns EA_OK if all converged. Each solved point is
 *  checked against the arm's limits except the tension margin (T = 0 is the
 *  edge's definition): admissible = 0 with the reason when the shoulder
 *  angle, the shoulder torque or the cable length is out of range. */
ea_status_t ea_workspace_outer(ea_shooter_t *sh, const double *alpha, int n,
                               ea_config_point_t *out);
/** Inner edge: the cable at length cable_length (default: the arm's
 *  cable_length_min) at n cable angles, with its statics, each point checked
 *  against every limit of the arm (ea_config_check_limits). Returns EA_OK if
 *  all converged (EA_ERR_INADMISSIBLE where the cable is longer than the
 *  outer edge). */
ea_status_t ea_workspace_inner(ea_shooter_t *sh, double cable_length, const double *alpha, int n,
                               ea_config_point_t *out);

/** Boundaries of the workspace region (ea_workspace_metrics). */
typedef enum ea_ws_bound {
  EA_WS_NONE = 0,
  EA_WS_OUTER,        /**< outer edge, T = 0 (eq. 16) */
  EA_WS_INNER,        /**< inner edge: the shortest cable */
  EA_WS_CABLE_MAX,    /**< the spool's longest cable */
  EA_WS_SHOULDER_MIN, /**< theta0 = shoulder_angle_min */
  EA_WS_SHOULDER_MAX, /**< theta0 = shoulder_angle_max */
  EA_WS_TORQUE_NEG,   /**< EI kappa0 = -shoulder_torque_max */
  EA_WS_TORQUE_POS,   /**< EI kappa0 = +shoulder_torque_max */
  EA_WS_TENSION_MAX,  /**< T = tension_max */
  EA_WS_ALPHA_MIN,    /**< start of the cable-angle range */
  EA_WS_ALPHA_MAX,    /**< end of the cable-angle range */
  EA_WS_COUNT
} ea_ws_bound_t;

/** Description of a boundary ("outer edge (T = 0)", ...; never NULL). */
const char *ea_ws_bound_name(ea_ws_bound_t b);

/** What ea_workspace_metrics measures (docs/statics.md, "Workspace metrics"). */
typedef struct ea_workspace_settings {
  double alpha_min, alpha_max; /**< [rad] cable-angle range: a bound of the region
                                    (default -60, 10 deg: the paper's Fig. 3) */
  double inner_cable_length;   /**< [m] inner edge (<= 0: the arm's cable_length_min) */
  int limits;                  /**< 1 (default): the arm's limits bound the region too
                                    (shoulder angle range, |EI kappa0| <= torque max,
                                    T <= tension max, cable length range); 0: only
                                    T >= 0 and L_c >= the inner cable length */
  int samples;                 /**< cable angles at which the region's structure (which
                                    boundary bounds it) is sampled (default 71) */
  int depth_samples;           /**< cable lengths sampled per angle for the limits (8) */
  double tol;                  /**< [m^2] area tolerance (default 1e-10); extrema are
                                    located to 1e-10 rad */
} ea_workspace_settings_t;

void ea_workspace_settings_default(ea_workspace_settings_t *s);

/** An extremum of the region and where it is attained. */
typedef struct ea_workspace_extremum {
  double value;         /**< [m] */
  double alpha;         /**< [rad] cable angle */
  double cable_length;  /**< [m] */
  double x, y;          /**< [m] tip */
  ea_ws_bound_t bound;  /**< boundary of the cable-length interval it lies on */
  ea_ws_bound_t bound2; /**< at a corner where two boundaries meet: the other one
                             (bound < bound2); else EA_WS_NONE */
  ea_ws_bound_t at_end; /**< EA_WS_ALPHA_MIN / _MAX when attained at an end of the
                             cable-angle range (the range, not the arm, bounds it);
                             else EA_WS_NONE */
} ea_workspace_extremum_t;

/** Metrics of the workspace region. */
typedef struct ea_workspace_metrics {
  double area;                   /**< [m^2] area of the region */
  double area_error;             /**< [m^2] conservative quadrature error estimate */
  ea_workspace_extremum_t reach; /**< max distance of the tip from the shoulder */
  ea_workspace_extremum_t x_max; /**< largest tip x */
  ea_workspace_extremum_t y_min; /**< lowest tip y */
  unsigned bounds;               /**< bit (1u << ea_ws_bound_t) of every boundary that
                                      bounds the region somewhere */
  int pieces;                    /**< smooth pieces between structure changes */
  long solves;                   /**< statics solves used */
} ea_workspace_metrics_t;

/** Area, reach, largest x and lowest y of the region of tip positions the
 *  arm holds (T >= 0, L_c >= inner, alpha in the range, the arm's limits):
 *  the area by quadrature in polar coordinates about the cable root on the
 *  smooth pieces between structure changes (each located by a root find),
 *  the extrema by Brent's method along the boundary curves. Errors:
 *  EA_ERR_ARG (bad settings), EA_ERR_INADMISSIBLE (the region is empty, e.g.
 *  an inner cable longer than the outer edge), EA_ERR_NOCONV (no statics
 *  solution somewhere in the range, or the quadrature did not converge). */
ea_status_t ea_workspace_metrics(ea_shooter_t *sh, const ea_workspace_settings_t *set,
                                 ea_workspace_metrics_t *m, ea_error_t *err);

/** Torque map: cells[i * n_len + j] at alpha[i], cable_length[j]. A cell
 *  beyond the outer edge (T would be < 0) has status EA_ERR_INADMISSIBLE and
 *  admissible = 0 with the reason. Warm-started sweeps from the edge. */
ea_status_t ea_torque_map(ea_shooter_t *sh, const double *cable_length, int n_len,
                          const double *alpha, int n_alpha, const ea_actuators_t *lim,
                          ea_config_point_t *cells);

/** Check one configuration against the limits (T_min <= T <= T_max,
 *  cable length range, |torque| <= max, shoulder range); sets admissible and
 *  reason. tension_min overrides lim->tension_min when > 0. */
void ea_config_check_limits(ea_config_point_t *pt, const ea_actuators_t *lim, double tension_min);

/** Stability of a solved configuration (paper sec. 3): FE static solve in the
 *  active phase from the statics, then is the passive-phase stiffness
 *  positive definite? Sets pt->stable; an unstable configuration becomes
 *  inadmissible with the reason. fe must be made for the same arm and load
 *  as sh. Returns the FE status (pt->stable = -1 if the FE failed). */
ea_status_t ea_config_check_stability(ea_shooter_t *sh, ea_fe_model_t *fe, ea_config_point_t *pt);

/** Straight tip path from tip0 to tip1 (eqs. 18-20) at steps + 1 points
 *  beta = 0, 1/steps, ..., 1; each solved (warm start along the path, cold
 *  start where that fails) and checked against the limits. out has
 *  steps + 1 entries. Returns EA_OK if every point is admissible,
 *  EA_ERR_INADMISSIBLE otherwise. */
ea_status_t ea_path_check_line(ea_shooter_t *sh, const double tip0[2], const double tip1[2],
                               int steps, const ea_actuators_t *lim, ea_config_point_t *out);
/** As ea_path_check_line, and with fe != NULL every solved step is also
 *  checked for stability (ea_config_check_stability). */
ea_status_t ea_path_check_line_fe(ea_shooter_t *sh, ea_fe_model_t *fe, const double tip0[2],
                                  const double tip1[2], int steps, const ea_actuators_t *lim,
                                  ea_config_point_t *out);
/* EA_STATICS_PROBLEMS_SECTION_END */

/* EA_TASK_SECTION_BEGIN (task specs: problems/task_*.c) */

/** Task specs (docs/task-format.md): what a plan must do. Loaded from YAML
 *  by ea_task_load() or built in C with ea_task_init() + ea_task_set_*() +
 *  ea_task_check(). Points are resolved to actuator coordinates and checked
 *  against the workspace of the task's payload by ea_task_check(). */

/** Most via points a task holds. */
#define EA_TASK_MAX_VIA 16

/** How a point was given. */
typedef enum ea_task_point_kind {
  EA_TASK_TIP_PLANAR = 0, /**< tip (x, y) in the arm's plane (+ optional base angle) */
  EA_TASK_TIP_3D,         /**< tip (x, y, z) in the base frame, z up */
  EA_TASK_ACTUATORS       /**< (cable length, cable angle, base angle) */
} ea_task_point_kind_t;

/** A start, goal or via point. */
typedef struct ea_task_point {
  ea_task_point_kind_t kind;
  double given[3]; /**< as given: planar (x, y, base) [m, m, rad]; 3-D (x, y, z) [m];
                        actuators (L_c [m], alpha [rad], base [rad]) */
  /* resolved by ea_task_check(): */
  double cable_length; /**< [m] L_c (eq. 19) */
  double cable_angle;  /**< [rad] alpha (eq. 20) */
  double base_angle;   /**< [rad] base angle (3-D: atan2(y, x)) */
  double reach;        /**< [m] planar tip x_L (3-D: hypot(x, y)) */
  double height;       /**< [m] planar tip y_L (3-D: z) */
  double p[EA_NP];     /**< statics (alpha, T, theta0, kappa0) at the point */
  char where[300];     /**< "file:line:col" of the point in the task file, or "" */
} ea_task_point_t;

/** Path constraint on the tip between the points. */
typedef enum ea_task_path {
  EA_TASK_PATH_FREE = 0, /**< no path constraint (vias are passed through) */
  EA_TASK_PATH_LINE,     /**< tip on the straight segment start -> goal */
  EA_TASK_PATH_POLYLINE  /**< tip on the segments start -> vias -> goal */
} ea_task_path_t;

/** Objective. */
typedef enum ea_task_objective {
  EA_TASK_MIN_TIME = 0, /**< minimum duration */
  EA_TASK_MIN_EFFORT,   /**< fixed duration, min integral of squared scaled accelerations */
  EA_TASK_MIN_JERK,     /**< fixed duration, min integral of squared scaled jerks */
  EA_TASK_MIN_VIBRATION /**< min integral of the squared quasi-static modal deflection
                             (acceleration / omega1(q)^2, FE frequency model), zero
                             acceleration at start and goal; duration fixed
                             (duration_s) or free with a time weight (time_weight) */
} ea_task_objective_t;

/** Limits of a plan; defaults from the arm file (ea_actuators_t). INFINITY
 *  means "no limit" (only allowed where documented). */
typedef struct ea_task_limits {
  double tension_min;            /**< [N] T >= tension_min > 0 */
  double tension_max;            /**< [N] */
  double cable_length_min;       /**< [m] */
  double cable_length_max;       /**< [m] */
  double cable_speed_max;        /**< [m/s] |dL_c/dt| */
  double cable_accel_max;        /**< [m/s^2] |d2L_c/dt2| */
  double cable_angle_speed_max;  /**< [rad/s] |dalpha/dt| (default INFINITY) */
  double cable_angle_accel_max;  /**< [rad/s^2] (default INFINITY) */
  double shoulder_torque_max;    /**< [N m] |EI kappa0| */
  double shoulder_speed_max;     /**< [rad/s] |dtheta0/dt| (INFINITY = off) */
  double base_speed_max;         /**< [rad/s] */
  double base_accel_max;         /**< [rad/s^2] */
  double min_first_frequency_hz; /**< [Hz] first natural frequency (FE, passive cable) >= this
                                      at every knot (0 = off, default) */
  double max_modal_deflection_m; /**< [m] quasi-static modal deflection |s_c acc_c| / omega1^2
                                      <= this at both ends of every interval, s = (1, L_c)
                                      for (L_c, alpha) (INFINITY = off, default) */
  double resample_margin;        /**< [-] speed and acceleration limits are planned
                                      1 + margin times tighter, so that the streamer's
                                      quintic resampling stays within them (default 0) */
  int continuous_acceleration;   /**< 1 (default): the acceleration is continuous at the
                                      knots (the plan is a C2 cubic spline, which the
                                      streamer's quintic reproduces exactly); 0: the
                                      cubic Hermite's acceleration may jump at the knots */
} ea_task_limits_t;

/** Which transcription plans a task (docs/planner.md, "Transcriptions"). */
typedef enum ea_task_transcription {
  EA_TASK_TRANSCRIPTION_AUTO = 0, /**< the path coordinate for line/polyline paths, else knots */
  EA_TASK_TRANSCRIPTION_KNOTS,    /**< knots with the statics shooting rows (every task) */
  EA_TASK_TRANSCRIPTION_PATH      /**< the path coordinate (line/polyline; else refused) */
} ea_task_transcription_t;

/** Solver options of a task. */
typedef struct ea_task_solver {
  int max_iter;          /**< Ipopt iterations (default 500) */
  double tol;            /**< Ipopt tol (default 1e-8) */
  double constr_tol;     /**< Ipopt constr_viol_tol (default 1e-10) */
  double max_time_s;     /**< wall-clock limit (default 60) */
  int derivative_test;   /**< run Ipopt's derivative checker: 1 first-order, 2 second-order */
  int print_level;       /**< Ipopt print level (default 0 = silent) */
  double regularization; /**< weight of the acceleration-energy term added to min_time
                              (default 1e-4; 0 = pure minimum time) */
  int hessian_exact;     /**< Hessian of the Lagrangian: 2 "partial" (default): exact for
                              every row but without the statics curvature; 1 "exact":
                              with it (second-order statics by differences of the exact
                              sensitivities); 0 "limited-memory": Ipopt's quasi-Newton */
  ea_task_transcription_t transcription; /**< "auto" (default), "knots" or "path" */
} ea_task_solver_t;

/** How ea_plan_refine searches (docs/planner.md, "Refinement against the FE transient"). */
typedef enum ea_task_refine_method {
  EA_TASK_REFINE_NEWTON = 0, /**< Newton steps on the fitted residual modal state (Broyden) */
  EA_TASK_REFINE_BOBYQA,     /**< NLopt BOBYQA on the fitted residual modal energy */
  EA_TASK_REFINE_COBYLA,     /**< NLopt COBYLA, same objective */
  EA_TASK_REFINE_SBPLX       /**< NLopt Sbplx, same objective */
} ea_task_refine_method_t;

/** Most FE transients a refinement may spend. */
#define EA_TASK_REFINE_MAX_EVALUATIONS 100

/** FE-in-the-loop refinement of a plan that arrives at rest (task key dynamics.refine,
 *  docs/task-format.md): the terminal modal targets are adjusted until the residual vibration
 *  measured by the nonlinear FE transient is below tolerance_m. */
typedef struct ea_task_refine {
  int enabled;                    /**< 1: refine after the plan (key present, or plan --refine) */
  ea_task_refine_method_t method; /**< default EA_TASK_REFINE_NEWTON */
  double tolerance_m;  /**< [m] stop when the FE residual peak is at most this (default 5e-5) */
  int max_evaluations; /**< FE transients, the unrefined plan's included (default 20) */
  double max_time_s;   /**< [s] wall-time cap, checked before each evaluation (default 10) */
  int modes;           /**< modes whose terminal targets are adjusted, 1..dynamics.modes
                            (default 1) */
  double fe_dt_s;      /**< [s] FE time step of the evaluations (default 2e-3) */
  double settle_s;     /**< [s] FE time simulated after the motion (default 3) */
  double max_duration_change; /**< [-] a candidate whose duration differs from the unrefined
                                   plan's by more than this fraction is rejected (default 0.02) */
  unsigned long seed;         /**< seed of NLopt's random numbers (default 1) */
} ea_task_refine_t;

/** Defaults of the refinement (disabled). */
void ea_task_refine_default(ea_task_refine_t *r);
/** Name of a refinement method ("newton", "bobyqa", "cobyla", "sbplx"). */
const char *ea_task_refine_method_name(ea_task_refine_method_t m);

/** Dynamics of a plan (docs/task-format.md, "dynamics"): plan with the reduced dynamic model
 *  of the arm (model/fe_rom.c) so that it arrives at rest. */
typedef struct ea_task_dynamics {
  int modes;                  /**< K modes of the reduced model; 0 = quasi-static plan (default) */
  double residual_m;          /**< [m] allowed residual tip amplitude after the motion (model);
                                   0 (default) = the modal state is zero at the goal */
  double max_tip_deviation_m; /**< [m] modal tip deviation from the quasi-static tip during the
                                   motion, at the knots (INFINITY = off, default) */
  int grid[2];                /**< table grid (L_c, alpha) points (0 = from the box, default) */
  double robust_tip_mass;     /**< [-] robust rest: the plan also at rest for the tip mass
                                   m (1 +- this) ... (0 = off, default) */
  double robust_EI;           /**< [-] ... and EI (1 +- this): the four corners as models */
  double robust_residual_m;   /**< [m] allowed residual amplitude at each corner (the
                                   model's; default 5e-4) */
  ea_task_refine_t refine;    /**< FE-in-the-loop refinement (off by default) */
} ea_task_dynamics_t;

/** A task spec. Plain data, no owned memory. */
typedef struct ea_task {
  char name[128];
  char file[512];     /**< task file ("" when built in C) */
  char arm_file[512]; /**< arm file used ("" = built-in defaults) */
  ea_arm_t arm;
  double payload_kg;     /**< [kg] m_p */
  double payload_factor; /**< [-] gamma (eq. 17) if given as factor, else NAN */
  ea_task_point_t start, goal;
  int n_via;
  ea_task_point_t via[EA_TASK_MAX_VIA];
  ea_task_path_t path;
  ea_task_objective_t objective;
  double duration_s;  /**< [s] fixed duration (min_effort, min_jerk, min_vibration);
                           NAN for min_time and a free-time min_vibration */
  double time_weight; /**< [1/s] min_vibration with free duration: weight of t_f
                           added to the vibration integral (NAN otherwise) */
  ea_task_limits_t limits;
  ea_task_dynamics_t dynamics; /**< modes = 0: a quasi-static plan */
  int knots;                   /**< time knots including start and goal (default 100) */
  ea_task_solver_t solver;
  char out_trajectory[512]; /**< outputs (relative to the task file); "" = none */
  char out_summary[512];
  char out_figure[512];
  int base_moves;         /**< set by ea_task_check(): some point has another base angle */
  char where_limits[300]; /**< positions used in messages */
  char where_objective[300];
} ea_task_t;

/** Names: "min_time", "free", "tip-3d", ... (never NULL). */
const char *ea_task_objective_name(ea_task_objective_t o);
const char *ea_task_path_name(ea_task_path_t p);

/** Initialise a task for arm (copied; NULL = ea_arm_default): no payload,
 *  limits from the arm, min_time, 100 knots, free path, default solver
 *  options; start and goal must still be set. */
void ea_task_init(ea_task_t *task, const ea_arm_t *arm);
/** Points: tip in the plane (x, y [m]) at base angle [rad]. */
ea_task_point_t ea_task_point_planar(double x, double y, double base_angle);
/** Tip in 3-D (x, y, z [m]). */
ea_task_point_t ea_task_point_3d(double x, double y, double z);
/** Actuator coordinates (L_c [m], alpha [rad], base [rad]). */
ea_task_point_t ea_task_point_actuators(double cable_length, double cable_angle, double base_angle);
/** Resolve every point and validate the whole task: limits consistent and
 *  within the arm's, objective and duration consistent, every point inside
 *  the workspace for the payload (ea_statics_solve with the cable problem:
 *  converged, T in [tension_min, tension_max], |EI kappa0| <= torque limit,
 *  L_c in range, theta0 and base angle in range). Messages start with the
 *  point's position when it came from a file. */
ea_status_t ea_task_check(ea_task_t *task, ea_error_t *err);
/** Load, resolve and validate a task file. The arm file named in the task
 *  is read relative to the task file's folder; without one, default_arm
 *  (NULL = built-in ea_arm_default values) is used.
 *  Errors: EA_ERR_IO, EA_ERR_PARSE, EA_ERR_INPUT ("file:line:col: key ..."),
 *  EA_ERR_INFEASIBLE (a point outside the workspace). */
ea_status_t ea_task_load(const char *path, const char *default_arm, ea_task_t *task,
                         ea_error_t *err);
/** Same from a string of len bytes named name (arm files relative to cwd). */
ea_status_t ea_task_load_string(const char *name, const char *text, size_t len,
                                const char *default_arm, ea_task_t *task, ea_error_t *err);
/** Output path of an output key resolved against the task file's folder
 *  (buf of len bytes); returns buf, or NULL when rel is empty. */
const char *ea_task_output_path(const ea_task_t *task, const char *rel, char *buf, size_t len);

/* EA_TASK_SECTION_END */

/* EA_STUDY_SECTION_BEGIN (studies: problems/study_*.c) */

/** Batch studies (docs/studies.md): a full-factorial grid of payload and arm
 *  parameters, and per case only the metrics asked for (workspace, torque
 *  and tension ranges, FE natural frequencies, path admissibility, and the
 *  minimum-time duration of a task through a callback the planner
 *  registers). Results are one tidy CSV row per case and metric:
 *  case_id, the parameter columns, metric, value, unit, status, message.
 *  Cases are computed independently (a fresh shooter / FE model per case,
 *  no warm start across cases), so the CSV is byte-identical whatever the
 *  thread count, the sharding, or how often the study was interrupted. */

#include <signal.h>

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
  EA_STUDY_M_MIN_TIME = 16u    /**< minimum-time duration of a task (planner callback) */
};

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

/** Progress callback (from worker threads, serialised): a case finished. */
typedef void (*ea_study_progress_fn)(void *data, long case_id, long done, long todo,
                                     int failed_rows);

/** Run settings. */
typedef struct ea_study_settings {
  int threads;             /**< worker threads (0 = all online cores) */
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
  int threads;                /**< threads used */
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

/** Run (one shard of) a checked study. On EA_OK, *csv (malloc'd, caller
 *  frees; *csv_len bytes) holds the header and the shard's rows in case
 *  order (columns case_id, study, study_key, the parameters, metric, value,
 *  unit, status, message). With a checkpoint journal every finished case is appended (one
 *  write + fsync, CRC-32 per case); a rerun with the same study skips the
 *  cases found there, drops a torn tail, and refuses a journal of another
 *  study (EA_ERR_INPUT). A failed case is recorded in its rows. */
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

/* EA_STUDY_SECTION_END */

#ifdef __cplusplus
}
#endif
#endif
