/**
 * @file ea_task.h
 * @brief Task specs (docs/task-format.md): what a plan must do, loaded from
 *        YAML or built in C, resolved and checked against the workspace
 *        (problems/task_*.c). Knows nothing of Ipopt.
 */
#ifndef EA_TASK_H
#define EA_TASK_H

#include "ea_planner_settings.h"
#include "ea_statics.h"

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/** Task specs (docs/task-format.md): what a plan must do. Loaded from YAML
 *  by ea_task_load() or built in C with ea_task_init(), the points
 *  (ea_task_point_*()) and fields set, then ea_task_check(). Points are resolved to actuator
 * coordinates and checked against the workspace of the task's payload by ea_task_check(). */

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

/** How ea_plan_refine searches (docs/planner.md, "Refinement against the FE transient"). */
typedef enum ea_task_refine_method {
  EA_TASK_REFINE_NEWTON = 0, /**< Newton steps on the fitted residual modal state (Broyden) */
  EA_TASK_REFINE_BOBYQA,     /**< NLopt BOBYQA on the fitted residual modal energy */
  EA_TASK_REFINE_COBYLA,     /**< NLopt COBYLA, same objective */
  EA_TASK_REFINE_SBPLX       /**< NLopt Sbplx, same objective */
} ea_task_refine_method_t;

/** [m] Default bound of the FE residual peak of a plan that ends at rest (dynamics.residual_m
 *  0) when the task does not refine explicitly: the planner's FE check (dt 4 ms) refines until
 *  the residual is within it; the FE at converged settings (dt 0.5 ms) then shows <= 1 mm. */
#define EA_TASK_REST_TOLERANCE_M 5e-4

/** What measures a refinement's candidates (docs/planner.md, "Refinement by the reduced model"). */
typedef enum ea_task_refine_by {
  EA_TASK_REFINE_BY_FE = 0,    /**< every candidate by the FE transient (default) */
  EA_TASK_REFINE_BY_MODEL,     /**< first by the nonlinear reduced model (model/fe_romnl.c) until
                                    it predicts rest, then the FE transient of that plan; the FE
                                    refines on where it is not within the tolerance */
  EA_TASK_REFINE_BY_MODEL_ONLY /**< by the nonlinear reduced model alone: no FE transient runs,
                                    the result is the model's prediction */
} ea_task_refine_by_t;
/** Name of a refinement's measure ("fe", "model", "model_only"). */
const char *ea_task_refine_by_name(ea_task_refine_by_t b);
/** The measure of that name into *b; 0, or -1 for a name that is none (*b unchanged). */
int ea_task_refine_by_from_name(const char *name, ea_task_refine_by_t *b);

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
  int modes;           /**< modes whose terminal targets are adjusted, 1..dynamics.modes;
                            0 (default): every mode */
  double fe_dt_s;      /**< [s] FE time step of the evaluations (default 4e-3) */
  double settle_s;     /**< [s] FE time simulated after the motion (default 1.5) */
  double max_duration_change; /**< [-] a candidate whose duration differs from the unrefined
                                   plan's by more than this fraction is rejected (default 0.1) */
  unsigned long seed;         /**< seed of NLopt's random numbers (default 1) */
  /** Progress of a refinement (NULL: none, the default; not a task key): called by
   *  ea_plan_refine from the calling thread after each evaluation with its index
   *  (0: the unrefined plan), max_evaluations, the seconds since the refinement began and
   *  the evaluation's FE residual peak at the nominal arm [m] (NAN: not measured). */
  void (*progress)(void *data, int evaluation, int max_evaluations, double elapsed_s,
                   double residual_peak_m);
  void *progress_data;    /**< passed to progress */
  ea_task_refine_by_t by; /**< what measures the candidates (default EA_TASK_REFINE_BY_FE) */
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
  ea_task_refine_t refine;    /**< FE-in-the-loop refinement (explicit: off by default) */
  int verify; /**< 1 (default): the plan's promise is checked by the FE transient and, at rest,
                   refined until it holds (dynamics.refine's tolerance_m when enabled, else
                   EA_TASK_REST_TOLERANCE_M); with residual_m > 0 checked against it (key
                   dynamics.verify; plan --no-verify sets 0) */
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
  ea_task_dynamics_t dynamics;  /**< modes = 0: a quasi-static plan */
  int knots;                    /**< time knots including start and goal (default 100) */
  ea_planner_settings_t solver; /**< how to plan: the file's solver: keys (ea_planner_alloc
                                     plans with them; ea_planner_alloc_with with others) */
  char out_trajectory[512];     /**< outputs (relative to the task file); "" = none */
  char out_summary[512];
  char out_figure[512];
  int base_moves;         /**< set by ea_task_check(): some point has another base angle */
  char where_limits[300]; /**< positions used in messages */
  char where_objective[300];
  char arm_warning[700]; /**< the arm file's plausibility warning (ea_arm_load_warn), "" none */
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

#ifdef __cplusplus
}
#endif
#endif /* EA_TASK_H */
