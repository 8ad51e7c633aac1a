/**
 * @file ea_workspace.h
 * @brief Questions over the configurations of an arm: workspace edges and
 *        region metrics (Fig. 3), torque maps, limits and stability checks,
 *        straight-path admissibility (Fig. 4) (problems/statics_problems.c,
 *        problems/workspace_region.c).
 */
#ifndef EA_WORKSPACE_H
#define EA_WORKSPACE_H

#include "ea_fe.h"

#ifdef __cplusplus
extern "C" {
#endif

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

/** Natural frequencies at one configuration (paper sec. 3.3): the statics of the
 *  cable length and angle, the FE static equilibrium from it (ea_fe_static_solve;
 *  the model's settings say whether the tip or the tension is held) and the modes
 *  (ea_fe_modes). */
typedef struct ea_freq_point {
  double cable_length;       /**< [m] requested */
  double alpha;              /**< [rad] requested cable angle */
  ea_statics_solution_t ode; /**< the statics */
  ea_fe_static_info_t fe;    /**< the FE static equilibrium (NAN fields before it) */
  ea_fe_modes_info_t modes;  /**< frequencies (NAN before the modes) and stability */
  ea_status_t status;        /**< EA_OK or the failed stage's status */
  const char *stage;         /**< where it failed: "statics", "fe-static", "modes"; "" */
  ea_error_t err;            /**< the failed stage's message */
} ea_freq_point_t;

/** One configuration: statics (warm start guess, NULL: continuation from the T = 0
 *  edge), FE statics, modes. m and sh are made for the same arm and load; m holds
 *  the FE state and its mode shapes afterwards. */
ea_status_t ea_freq_point(ea_shooter_t *sh, ea_fe_model_t *m, double cable_length, double alpha,
                          const double *guess, ea_freq_point_t *pt);

/** Frequencies against cable length at one cable angle (the paper's Fig. 5): n points,
 *  each warm-started from the previous converged statics (retried from the edge when
 *  that fails). EA_OK when every point converged, else EA_ERR_NOCONV (the points say
 *  which and why). */
ea_status_t ea_freq_sweep(ea_shooter_t *sh, ea_fe_model_t *m, const double *cable_length, int n,
                          double alpha, ea_freq_point_t *pts);

#ifdef __cplusplus
}
#endif
#endif /* EA_WORKSPACE_H */
