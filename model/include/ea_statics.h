/**
 * @file ea_statics.h
 * @brief Elastica statics (paper sec. 2): the shooting map with exact
 *        sensitivities and the general problem g* = 0 (model/statics_*.c).
 *
 * Never prints, never aborts: every call returns an ::ea_status_t and, on
 * failure only, a message in the caller's optional ::ea_error_t.
 * Units: SI, angles in radians. The arm's plane has x horizontal (away from
 * the base axis) and y vertical (up); gravity is -y.
 */
#ifndef EA_STATICS_H
#define EA_STATICS_H

#include "ea_arm.h"

#ifdef __cplusplus
extern "C" {
#endif

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

/** Defaults chosen by bench/bench_statics (see README): rk8pd, 12 fixed steps. */
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
ea_status_t ea_shooter_alloc(const ea_arm_t *arm, const ea_shoot_settings_t *s, ea_shooter_t **out,
                             ea_error_t *err);
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
ea_status_t ea_shoot(ea_shooter_t *sh, const double p[EA_NP], double xL[EA_NX], double *dxdp);

/** Centreline samples of the beam for p: n points at s = i L/(n-1):
 *  theta, kappa, x, y each n long (any may be NULL). Uses a tight adaptive
 *  integration with dense output. */
ea_status_t ea_shoot_shape(ea_shooter_t *sh, const double p[EA_NP], int n, double *s, double *theta,
                           double *kappa, double *x, double *y);

/** Tip state on the exact ODE at a tight tolerance, by a different scheme and
 *  code path than ea_shoot() (GSL rkf45, adaptive, atol = rtol = 1e-13, no
 *  sensitivities): an independent re-integration used to check answers. */
ea_status_t ea_shoot_reference(const ea_arm_t *arm, const ea_load_t *load, const double p[EA_NP],
                               double xL[EA_NX]);

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
  double tol;                 /**< residual tolerance (max-norm, [m] / [1/m]) */
  int max_iter;               /**< Newton iterations per solve */
  int max_cont_steps;         /**< continuation steps before giving up */
  int allow_negative_tension; /**< 0: T < 0 is reported as inadmissible */
} ea_statics_settings_t;

void ea_statics_settings_default(ea_statics_settings_t *s);

/** How the solution's branch was reached. */
typedef enum ea_branch {
  EA_BRANCH_NONE = 0, /**< no solution */
  EA_BRANCH_WARM,     /**< Newton from the caller's guess */
  EA_BRANCH_EDGE,     /**< continuation from the T = 0 outer edge (physical) */
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
ea_status_t ea_statics_edge(ea_shooter_t *sh, double alpha, const ea_statics_settings_t *s,
                            const double *guess, ea_statics_solution_t *sol, ea_error_t *err);

#ifdef __cplusplus
}
#endif
#endif /* EA_STATICS_H */
