/**
 * @file ea_model.h
 * @brief elasticarm physics: arm parameters, elastica statics (paper sec. 2),
 *        finite element model (paper sec. 3).
 *
 * The model knows nothing of files, tasks or solvers of the planner. It never
 * prints and never aborts: every call returns an ::ea_status_t and, where
 * useful, a message in the caller's ::ea_error_t.
 *
 * Units: SI everywhere, angles in radians. The plane of the arm has x
 * horizontal (away from the base axis) and y vertical (up); gravity is -y.
 */
#ifndef EA_MODEL_H
#define EA_MODEL_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------------------ */
/* Status codes and error context                                           */
/* ------------------------------------------------------------------------ */

/** X-macro list of every status: name, message. 0 = OK. "Call was wrong"
 *  codes (bad argument, bad input) are kept apart from "solver did not
 *  converge" and "the answer is physically inadmissible". */
#define EA_STATUS_LIST(X)                                                     \
  X(EA_OK, "ok")                                                              \
  X(EA_ERR_ARG, "invalid argument")                                          \
  X(EA_ERR_NOMEM, "out of memory")                                           \
  X(EA_ERR_IO, "input/output error")                                         \
  X(EA_ERR_PARSE, "syntax error in input")                                   \
  X(EA_ERR_INPUT, "invalid value in input")                                  \
  X(EA_ERR_NOCONV, "solver did not converge")                                \
  X(EA_ERR_MAXITER, "iteration limit reached")                               \
  X(EA_ERR_SINGULAR, "singular Jacobian")                                    \
  X(EA_ERR_INTEGRATION, "ODE integration failed")                            \
  X(EA_ERR_INADMISSIBLE, "configuration is not admissible")                  \
  X(EA_ERR_INFEASIBLE, "problem is infeasible")                              \
  X(EA_ERR_UNSTABLE, "configuration is unstable")                            \
  X(EA_ERR_BACKEND, "numerical backend failed")                              \
  X(EA_ERR_NET, "network or device error")                                   \
  X(EA_ERR_PROTOCOL, "protocol violation")                                   \
  X(EA_ERR_INTERRUPTED, "interrupted")                                       \
  X(EA_ERR_NOTIMPL, "not implemented")

#define EA__STATUS_ENUM(name, msg) name,
/** Status of every library call. */
typedef enum ea_status { EA_STATUS_LIST(EA__STATUS_ENUM) EA_STATUS_COUNT } ea_status_t;
#undef EA__STATUS_ENUM

/** Static message for a status (never NULL). */
const char *ea_strerror(ea_status_t status);
/** Symbolic name of a status ("EA_ERR_NOCONV"); never NULL. */
const char *ea_status_name(ea_status_t status);

/** Error context filled by calls that can say more than a status code.
 *  Always optional: pass NULL when not wanted. */
typedef struct ea_error {
  ea_status_t status; /**< same as the return value of the call */
  char msg[512];      /**< human-readable, with file:line:column where known */
} ea_error_t;

/** Set err (if not NULL) to status and a printf-style message; returns status. */
ea_status_t ea_error_set(ea_error_t *err, ea_status_t status, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/* ------------------------------------------------------------------------ */
/* Arm parameters (paper Tables 1 and 2, plus actuator data)                 */
/* ------------------------------------------------------------------------ */

/** Actuator limits and geometry. Values not in the paper are assumptions,
 *  marked as such in data/elasticarm.yaml. */
typedef struct ea_actuators {
  double spool_radius;       /**< [m] effective cable spool radius */
  double spool_gear_ratio;   /**< [-] motor turns per spool turn */
  double spool_zero_length;  /**< [m] cable length at spool motor position 0 */
  double cable_length_min;   /**< [m] shortest cable (inner workspace edge) */
  double cable_length_max;   /**< [m] longest cable the spool holds */
  double cable_speed_max;    /**< [m/s] |dL_c/dt| limit */
  double cable_accel_max;    /**< [m/s^2] |d2L_c/dt2| limit */
  double tension_max;        /**< [N] cable tension limit */
  double tension_min;        /**< [N] default minimum tension margin (> 0) */
  double shoulder_torque_max;/**< [N m] |EI kappa0| limit */
  double shoulder_speed_max; /**< [rad/s] |dtheta0/dt| limit */
  double shoulder_angle_min; /**< [rad] shoulder range */
  double shoulder_angle_max; /**< [rad] */
  double shoulder_accel_max; /**< [rad/s^2] |d2theta0/dt2| limit */
  double base_speed_max;     /**< [rad/s] base motor speed limit */
  double base_accel_max;     /**< [rad/s^2] base motor acceleration limit */
  double base_angle_min;     /**< [rad] base range */
  double base_angle_max;     /**< [rad] */
} ea_actuators_t;

/** Arm parameters. Tables 1 and 2 of the paper. */
typedef struct ea_arm {
  /* Table 1 */
  double rho;      /**< [kg/m] beam mass per unit length */
  double m_hand;   /**< [kg] hand (gripper) mass m_h */
  double length;   /**< [m] beam length L */
  double EI;       /**< [N m^2] flexural rigidity */
  double x_c;      /**< [m] cable root x */
  double y_c;      /**< [m] cable root y */
  double g;        /**< [m/s^2] gravitational acceleration */
  /* Table 2 (FE model) */
  double EA;       /**< [N] axial rigidity */
  double GA_s;     /**< [N] shear rigidity (beta G A) */
  double EA_cable; /**< [N] cable axial rigidity EA_c */
  double I_zz;     /**< [kg m] rotary inertia per unit length */
  double I_hand;   /**< [kg m^2] rotary inertia I_L of hand (+ payload) */
  ea_actuators_t act; /**< actuator data */
} ea_arm_t;

/** Fill arm with the paper's values (Tables 1, 2) and the assumed actuator
 *  data documented in data/elasticarm.yaml. */
void ea_arm_default(ea_arm_t *arm);
/** Check every field: finite, right sign, consistent ranges. On failure,
 *  err->msg names the field, its value and the bound. */
ea_status_t ea_arm_validate(const ea_arm_t *arm, ea_error_t *err);
/** Payload mass from the payload factor gamma (eq. 17): gamma (m_h + rho L). */
double ea_arm_payload_from_factor(const ea_arm_t *arm, double gamma);
/** Tip mass m_L = m_h + m_p (eq. 1). */
double ea_arm_tip_mass(const ea_arm_t *arm, double payload_kg);

/* ------------------------------------------------------------------------ */
/* Statics: the shooting map h (eq. 11, 13) and its exact sensitivities      */
/* ------------------------------------------------------------------------ */

/** Integrator of the shooting map. */
typedef enum ea_integrator {
  EA_INT_RK8PD_FIXED = 0, /**< GSL rk8pd, fixed step count (default) */
  EA_INT_RK8PD_ADAPTIVE,  /**< GSL rk8pd with error control */
  EA_INT_RKF45_ADAPTIVE,  /**< GSL rkf45 with error control */
  EA_INT_RK4_FIXED,       /**< GSL rk4, fixed step count */
  EA_INT_COUNT
} ea_integrator_t;

/** Name of an integrator ("rk8pd-fixed", ...). */
const char *ea_integrator_name(ea_integrator_t it);
/** Parse a name as printed by ea_integrator_name(); returns EA_ERR_ARG if unknown. */
ea_status_t ea_integrator_parse(const char *name, ea_integrator_t *it);

/** Settings of the shooting integrator. */
typedef struct ea_shoot_settings {
  ea_integrator_t integrator; /**< which scheme */
  int steps;                  /**< fixed-step schemes: number of steps over [0, L] */
  double rtol;                /**< adaptive schemes: relative tolerance */
  double atol;                /**< adaptive schemes: absolute tolerance */
} ea_shoot_settings_t;

/** Defaults chosen by bench/bench_statics (see README): rk8pd, 24 fixed steps. */
void ea_shoot_settings_default(ea_shoot_settings_t *s);

/** Indices of the shooting arguments p = (alpha, T, theta0, kappa0). */
enum { EA_P_ALPHA = 0, EA_P_TENSION = 1, EA_P_THETA0 = 2, EA_P_KAPPA0 = 3, EA_NP = 4 };
/** Indices of the tip state x(L) = (theta, kappa, x, y). */
enum { EA_X_THETA = 0, EA_X_KAPPA = 1, EA_X_X = 2, EA_X_Y = 3, EA_NX = 4 };

/** Load case of the statics: the tip mass m_L (hand + payload). */
typedef struct ea_load {
  double tip_mass; /**< [kg] m_L = m_h + m_p */
} ea_load_t;

/** Shooting workspace (opaque): preallocated integrator, no malloc per call. */
typedef struct ea_shooter ea_shooter_t;

/** Allocate a shooter for arm (copied) and settings (copied; NULL = default). */
ea_status_t ea_shooter_alloc(const ea_arm_t *arm, const ea_shoot_settings_t *s,
                             ea_shooter_t **out, ea_error_t *err);
void ea_shooter_free(ea_shooter_t *sh);
/** Change the load (tip mass) without reallocating. */
void ea_shooter_set_load(ea_shooter_t *sh, const ea_load_t *load);
/** Arm the shooter was made for. */
const ea_arm_t *ea_shooter_arm(const ea_shooter_t *sh);
/** Current load. */
const ea_load_t *ea_shooter_load(const ea_shooter_t *sh);

/** The shooting map h (eq. 13): tip state x(L) for p = (alpha, T, theta0, kappa0).
 * @param[in]  p     shooting arguments, EA_NP values
 * @param[out] xL    tip state, EA_NX values
 * @param[out] dxdp  if not NULL: row-major EA_NX x EA_NP exact sensitivities
 *                   d x(L) / d p from the variational equations.
 */
ea_status_t ea_shoot(ea_shooter_t *sh, const double p[EA_NP], double xL[EA_NX],
                     double *dxdp);

/** Centreline samples of the beam for p: n points at s = i L/(n-1):
 *  theta, kappa, x, y each n long (any may be NULL). Uses a tight adaptive
 *  integration with dense output. */
ea_status_t ea_shoot_shape(ea_shooter_t *sh, const double p[EA_NP], int n,
                           double *s, double *theta, double *kappa, double *x,
                           double *y);

/** Tip state on the exact ODE at a tight tolerance, by a different scheme and
 *  code path than ea_shoot() (GSL rkf45, adaptive, atol = rtol = 1e-13, no
 *  sensitivities): an independent re-integration used to check answers. */
ea_status_t ea_shoot_reference(const ea_arm_t *arm, const ea_load_t *load,
                               const double p[EA_NP], double xL[EA_NX]);

/* ------------------------------------------------------------------------ */
/* Statics: the general problem g*(alpha, T, theta0, kappa0) = 0 (eq. 14-16) */
/* ------------------------------------------------------------------------ */

/** Quantities a problem statement may fix ("given"). The unknowns are always
 *  p = (alpha, T, theta0, kappa0); the equations are always kappa(L) = 0 and
 *  the tip lying on the cable ray from the root at angle alpha, plus two
 *  given quantities. */
typedef enum ea_given {
  EA_GIVEN_ALPHA = 0,    /**< cable angle alpha [rad] */
  EA_GIVEN_TENSION,      /**< cable tension T [N] */
  EA_GIVEN_THETA0,       /**< shoulder angle theta0 [rad] */
  EA_GIVEN_KAPPA0,       /**< shoulder curvature kappa0 [1/m] */
  EA_GIVEN_CABLE_LENGTH, /**< cable length L_c [m] */
  EA_GIVEN_TIP_X,        /**< tip x [m] */
  EA_GIVEN_TIP_Y,        /**< tip y [m] */
  EA_GIVEN_COUNT
} ea_given_t;

/** A statics problem statement: two given quantities. */
typedef struct ea_statics_problem {
  ea_given_t given[2]; /**< which quantities are fixed */
  double value[2];     /**< their values (SI, rad) */
} ea_statics_problem_t;

/** Convenience constructors of the paper's problem statements. */
ea_statics_problem_t ea_statics_problem_cable(double cable_length, double alpha);
ea_statics_problem_t ea_statics_problem_tip(double x, double y);
ea_statics_problem_t ea_statics_problem_tension_theta0(double T, double theta0);
ea_statics_problem_t ea_statics_problem_tension_alpha(double T, double alpha);

/** Settings of the statics solver. */
typedef struct ea_statics_settings {
  double tol;          /**< residual tolerance (max-norm, [m] / [1/m]) */
  int max_iter;        /**< Newton iterations per solve */
  int max_cont_steps;  /**< continuation steps before giving up */
  int allow_negative_tension; /**< 0: T < 0 is reported as inadmissible */
} ea_statics_settings_t;

void ea_statics_settings_default(ea_statics_settings_t *s);

/** How the solution's branch was reached. */
typedef enum ea_branch {
  EA_BRANCH_NONE = 0,   /**< no solution */
  EA_BRANCH_WARM,       /**< Newton from the caller's guess */
  EA_BRANCH_EDGE,       /**< continuation from the T = 0 outer edge (physical) */
} ea_branch_t;

/** Result of a statics solve. */
typedef struct ea_statics_solution {
  double p[EA_NP];        /**< (alpha [rad], T [N], theta0 [rad], kappa0 [1/m]) */
  double tip[EA_NX];      /**< tip state (theta_L, kappa_L, x_L, y_L) */
  double cable_length;    /**< [m] distance cable root -> tip */
  double shoulder_torque; /**< [N m] EI kappa0 */
  double residual;        /**< max-norm of g* at the solution */
  int iterations;         /**< Newton iterations, all continuation steps included */
  int cont_steps;         /**< continuation steps used (0 = direct Newton) */
  ea_branch_t branch;     /**< how the branch was reached */
  double winding;         /**< [rad] theta_L - theta0: identifies the branch */
  ea_status_t status;     /**< EA_OK, EA_ERR_NOCONV, EA_ERR_INADMISSIBLE (T < 0) */
} ea_statics_solution_t;

/** Solve a statics problem.
 * @param[in]     sh    shooter (arm and load)
 * @param[in]     prob  problem statement
 * @param[in]     s     settings (NULL = default)
 * @param[in]     guess optional warm start p (NULL: continuation from the
 *                      T = 0 outer edge, which selects the physical branch)
 * @param[out]    sol   solution with status, residual, iterations, branch
 * @return EA_OK, or the status also stored in sol->status. A non-converged or
 *         T < 0 configuration is never returned as EA_OK.
 */
ea_status_t ea_statics_solve(ea_shooter_t *sh, const ea_statics_problem_t *prob,
                             const ea_statics_settings_t *s, const double *guess,
                             ea_statics_solution_t *sol, ea_error_t *err);

/** The residual g*(p) of a problem and (optionally) its 4x4 row-major
 *  Jacobian, from the shooting map's exact sensitivities. */
ea_status_t ea_statics_residual(ea_shooter_t *sh, const ea_statics_problem_t *prob,
                                const double p[EA_NP], double r[4], double *J);

/** Outer workspace edge point (T = 0, eq. 16) at cable angle alpha. */
ea_status_t ea_statics_edge(ea_shooter_t *sh, double alpha,
                            const ea_statics_settings_t *s, const double *guess,
                            ea_statics_solution_t *sol, ea_error_t *err);

/* ------------------------------------------------------------------------ */
/* Finite element model (paper sec. 3): see the FE section below             */
/* ------------------------------------------------------------------------ */
/* EA_FE_SECTION_BEGIN (owned by model/fe_*.c) */
/* EA_FE_SECTION_END */

#ifdef __cplusplus
}
#endif
#endif /* EA_MODEL_H */
