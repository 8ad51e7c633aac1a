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
#define EA_STATUS_LIST(X)                                                                          \
  X(EA_OK, "ok")                                                                                   \
  X(EA_ERR_ARG, "invalid argument")                                                                \
  X(EA_ERR_NOMEM, "out of memory")                                                                 \
  X(EA_ERR_IO, "input/output error")                                                               \
  X(EA_ERR_PARSE, "syntax error in input")                                                         \
  X(EA_ERR_INPUT, "invalid value in input")                                                        \
  X(EA_ERR_NOCONV, "solver did not converge")                                                      \
  X(EA_ERR_MAXITER, "iteration limit reached")                                                     \
  X(EA_ERR_SINGULAR, "singular Jacobian")                                                          \
  X(EA_ERR_INTEGRATION, "ODE integration failed")                                                  \
  X(EA_ERR_INADMISSIBLE, "configuration is not admissible")                                        \
  X(EA_ERR_INFEASIBLE, "problem is infeasible")                                                    \
  X(EA_ERR_UNSTABLE, "configuration is unstable")                                                  \
  X(EA_ERR_BACKEND, "numerical backend failed")                                                    \
  X(EA_ERR_NET, "network or device error")                                                         \
  X(EA_ERR_PROTOCOL, "protocol violation")                                                         \
  X(EA_ERR_INTERRUPTED, "interrupted")                                                             \
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
  double spool_radius;        /**< [m] effective cable spool radius */
  double spool_gear_ratio;    /**< [-] motor turns per spool turn */
  double spool_zero_length;   /**< [m] cable length at spool motor position 0 */
  double cable_length_min;    /**< [m] shortest cable (inner workspace edge) */
  double cable_length_max;    /**< [m] longest cable the spool holds */
  double cable_speed_max;     /**< [m/s] |dL_c/dt| limit */
  double cable_accel_max;     /**< [m/s^2] |d2L_c/dt2| limit */
  double tension_max;         /**< [N] cable tension limit */
  double tension_min;         /**< [N] default minimum tension margin (> 0) */
  double shoulder_torque_max; /**< [N m] |EI kappa0| limit */
  double shoulder_speed_max;  /**< [rad/s] |dtheta0/dt| limit */
  double shoulder_angle_min;  /**< [rad] shoulder range */
  double shoulder_angle_max;  /**< [rad] */
  double shoulder_accel_max;  /**< [rad/s^2] |d2theta0/dt2| limit */
  double base_speed_max;      /**< [rad/s] base motor speed limit */
  double base_accel_max;      /**< [rad/s^2] base motor acceleration limit */
  double base_angle_min;      /**< [rad] base range */
  double base_angle_max;      /**< [rad] */
} ea_actuators_t;

/** Arm parameters. Tables 1 and 2 of the paper. */
/** Most measured modal damping ratios an arm file may give. */
#define EA_ARM_MAX_DAMPED_MODES 6

typedef struct ea_arm {
  /* Table 1 */
  double rho;    /**< [kg/m] beam mass per unit length */
  double m_hand; /**< [kg] hand (gripper) mass m_h */
  double length; /**< [m] beam length L */
  double EI;     /**< [N m^2] flexural rigidity */
  double x_c;    /**< [m] cable root x */
  double y_c;    /**< [m] cable root y */
  double g;      /**< [m/s^2] gravitational acceleration */
  /* Table 2 (FE model) */
  double EA;          /**< [N] axial rigidity */
  double GA_s;        /**< [N] shear rigidity (beta G A) */
  double EA_cable;    /**< [N] cable axial rigidity EA_c */
  double I_zz;        /**< [kg m] rotary inertia per unit length */
  double I_hand;      /**< [kg m^2] rotary inertia I_L of hand (+ payload) */
  ea_actuators_t act; /**< actuator data */
  /* Damping (optional arm-file key damping.modal_ratios; not in the paper) */
  int n_damping; /**< measured modal damping ratios given (0: undamped, the default) */
  double damping_ratio[EA_ARM_MAX_DAMPED_MODES]; /**< zeta of modes 1..n_damping at rest, in
                                                      [0, 1); modes beyond: undamped */
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

/* ------------------------------------------------------------------------ */
/* Finite element model (paper sec. 3): see the FE section below             */
/* ------------------------------------------------------------------------ */
/* EA_FE_SECTION_BEGIN (owned by model/fe_*.c) */

/** Finite element model of the planar arm (paper sec. 3, docs/fe.md).
 *
 * Geometrically exact (Reissner / Simo-Vu-Quoc) planar beam with axial,
 * shear and bending strains; 3-node quadratic elements, reduced 2-point Gauss
 * integration of the stiffness, consistent mass (rho, I_zz), tip mass m_L and
 * rotary inertia I_hand; clamped at the origin with prescribed shoulder angle
 * theta0; cable from the tip to the root (x_c, y_c) in one of three phases.
 *
 * DOFs: node i (i = 0 .. 2 elements) carries (x_i, y_i, theta_i); "full"
 * vectors have 3 * nodes entries in that order; node 0 is the clamp (x = y = 0,
 * theta = theta0), the other nodes are free. Reference configuration:
 * straight, stress-free, node i at arclength s_i = i L / (nodes - 1). */

/** Phase of the cable element (paper sec. 3.1). */
typedef enum ea_fe_cable_phase {
  EA_FE_CABLE_NONE = 0, /**< no cable (free cantilever) */
  EA_FE_CABLE_ACTIVE,   /**< prescribed tension T [N] directed at the cable root */
  EA_FE_CABLE_PASSIVE   /**< elastic cable of rest (unstretched) length L0 [m]:
                             T = EA_c (l - L0) / L0 for l > L0, else 0 (slack) */
} ea_fe_cable_phase_t;

/** Backend of the generalized symmetric eigenproblem (eq. 24). */
typedef enum ea_fe_eig_backend {
  EA_FE_EIG_DSBGVX = 0, /**< LAPACK banded dsbgvx, selected eigenvalues only, then band
                             inverse iteration per mode shape */
  EA_FE_EIG_DSYGV,      /**< LAPACK dense dsygv, all modes */
  EA_FE_EIG_GSL,        /**< GSL gsl_eigen_gensymmv, all modes */
  EA_FE_EIG_LANCZOS,    /**< Lanczos with full reorthogonalisation on U^-T M U^-1, U the
                             band Cholesky factor of K (+ sigma M) from the stability check:
                             the wanted modes are the largest eigenvalues of the inverted
                             pencil (default, fastest; falls back to dsbgvx if it does not
                             converge, see ea_fe_modes_info_t.fallback) */
  EA_FE_EIG_COUNT
} ea_fe_eig_backend_t;

/** Most modes an ::ea_fe_modes_info_t holds. */
#define EA_FE_MAX_MODES 16
/** Default number of elements, chosen by bench/bench_fe (docs/fe.md). */
#define EA_FE_DEFAULT_ELEMENTS 12
/** The paper's mesh (sec. 3.3). */
#define EA_FE_PAPER_ELEMENTS 6

/** Model settings (plain data; ea_fe_settings_default() fills them). */
typedef struct ea_fe_settings {
  int elements;        /**< number of 3-node elements, >= 1 (default EA_FE_DEFAULT_ELEMENTS) */
  int modes;           /**< modes computed by ea_fe_modes(), 1..EA_FE_MAX_MODES (default 3) */
  double newton_tol;   /**< static Newton: stop at eps <= tol, eps of eq. 23 (default 1e-6) */
  int newton_max_iter; /**< static Newton iteration limit (default 50) */
  ea_fe_eig_backend_t eig_backend; /**< eigen-solver (default EA_FE_EIG_LANCZOS) */
  int static_hold_tip;             /**< ea_fe_static_solve: 0 = hold the ODE tension T and theta0
                                        (paper sec. 3.2; the tip moves by the extensibility
                                        effects); 1 = hold the ODE tip position (cable length
                                        and angle), solving for T and theta0 too (default 0) */
} ea_fe_settings_t;

/** Fill s with the defaults. */
void ea_fe_settings_default(ea_fe_settings_t *s);
/** Check s; err->msg names the bad field. */
ea_status_t ea_fe_settings_validate(const ea_fe_settings_t *s, ea_error_t *err);

/** The FE model workspace (opaque): all storage allocated in ea_fe_model_alloc. */
typedef struct ea_fe_model ea_fe_model_t;

/** Allocate a model for arm (copied; must satisfy ea_arm_validate and
 *  I_zz >= 0; M may be singular) with settings s (copied; NULL = default). The tip mass starts at
 *  arm->m_hand, the state is the straight beam at theta0 = 0, cable NONE. */
ea_status_t ea_fe_model_alloc(const ea_arm_t *arm, const ea_fe_settings_t *s, ea_fe_model_t **out,
                              ea_error_t *err);
/** Free the model; NULL is a no-op. */
void ea_fe_model_free(ea_fe_model_t *m);
/** Set the tip mass m_L [kg] (hand + payload); I_hand stays arm->I_hand. */
ea_status_t ea_fe_model_set_load(ea_fe_model_t *m, const ea_load_t *load);
/** Number of nodes (2 elements + 1); full vectors have 3 * nodes entries. */
int ea_fe_model_nodes(const ea_fe_model_t *m);
/** Arm and settings the model was made with. */
const ea_arm_t *ea_fe_model_arm(const ea_fe_model_t *m);
const ea_fe_settings_t *ea_fe_model_settings(const ea_fe_model_t *m);

/** Set the state to the straight, unstrained beam at shoulder angle theta0
 *  [rad], at rest, with the cable in phase NONE. */
ea_status_t ea_fe_set_straight(ea_fe_model_t *m, double theta0);
/** Set the cable phase and its parameter: ACTIVE: tension T [N] (>= 0);
 *  PASSIVE: rest length L0 [m] (> 0); NONE: value ignored. */
ea_status_t ea_fe_set_cable(ea_fe_model_t *m, ea_fe_cable_phase_t phase, double value);
/** Switch an ACTIVE cable to PASSIVE keeping its current tension: L0 is set
 *  so that T(l) = current T at the current tip (paper sec. 3.3). No-op for
 *  PASSIVE or NONE. */
ea_status_t ea_fe_cable_make_passive(ea_fe_model_t *m);
/** Current cable phase, its parameter (T or L0), tension [N] and length
 *  l = |tip - root| [m] at the current state (any pointer may be NULL). */
void ea_fe_cable_get(const ea_fe_model_t *m, ea_fe_cable_phase_t *phase, double *value,
                     double *tension, double *length);
/** Rest length of a cable of axial rigidity EA_c that has length l [m] at
 *  tension T [N]: l / (1 + T / EA_c). */
double ea_fe_cable_rest_length(double length, double tension, double EA_cable);

/** Copy the state out: q, v full vectors (3 * nodes each; either may be NULL). */
ea_status_t ea_fe_get_state(const ea_fe_model_t *m, double *q, double *v);
/** Set the state: q full vector (its node-0 entries set theta0), v full
 *  vector or NULL (= at rest). */
ea_status_t ea_fe_set_state(ea_fe_model_t *m, const double *q, const double *v);
/** Tip (x [m], y [m], theta [rad]) of the current state. */
void ea_fe_tip(const ea_fe_model_t *m, double tip[3]);
/** Total mechanical energy [J] of the current state: kinetic + strain +
 *  gravity (datum y = 0) + cable (ACTIVE: T l, PASSIVE: elastic). */
double ea_fe_energy(const ea_fe_model_t *m);

/** Result of a static solve. */
typedef struct ea_fe_static_info {
  ea_status_t status;  /**< EA_OK, EA_ERR_MAXITER, EA_ERR_SINGULAR, ... */
  int iterations;      /**< Newton iterations */
  double residual;     /**< eps of eq. 23: |P - F| / |F| (absolute if F = 0) */
  double tip[3];       /**< tip (x [m], y [m], theta [rad]) at the solution */
  double tension;      /**< [N] cable tension at the solution */
  double cable_length; /**< [m] |tip - root| at the solution */
  double cable_angle;  /**< [rad] alpha = atan2(y_L - y_c, x_L - x_c) */
  double theta0;       /**< [rad] shoulder angle */
  double tip_shift;    /**< [m] |tip_FE - tip_ODE| (ea_fe_static_solve only, else 0) */
  double time_s;       /**< [s] wall time */
} ea_fe_static_info_t;

/** Static equilibrium (eq. 21-23) in the active phase started from the ODE
 *  solution ode (p = alpha, T, theta0, kappa0): the centreline is sampled at
 *  the nodes with ea_shoot_shape(sh, ...), the cable is set ACTIVE with
 *  T = ode->p[EA_P_TENSION], the tip mass is taken from sh's load, and
 *  Newton-Raphson runs until eps <= settings.newton_tol (or the Newton
 *  residual stagnates with a correction below 1e-10 L: the attainable eps
 *  is ~1e-8 to 1e-6 (finer meshes: higher), set by EA / h). With settings.static_hold_tip, T and
 * theta0 are unknowns too and the tip is held at the ODE tip (bordered Newton).
 * @param[in,out] m    model; on success holds the FE equilibrium
 * @param[in]     sh   shooter of the same arm (only used to sample the shape)
 * @param[in]     ode  converged statics solution
 * @param[out]    info iterations, residual, tip; may be NULL */
ea_status_t ea_fe_static_solve(ea_fe_model_t *m, ea_shooter_t *sh, const ea_statics_solution_t *ode,
                               ea_fe_static_info_t *info, ea_error_t *err);
/** Make the positions consistent with the rotations: with every nodal theta
 *  held, move the nodes so that the axial and shear strains balance the
 *  loads (a linear solve). Use it after displacing a state by hand (e.g. a
 *  static state plus a mode shape): a linear mode carries second-order axial
 *  strains that, times EA, would start a transient with a violent axial
 *  impulse. */
ea_status_t ea_fe_relax_positions(ea_fe_model_t *m, ea_error_t *err);
/** Newton-Raphson from the current state, in the current cable phase, with
 *  theta0 held. The velocity is set to zero. */
ea_status_t ea_fe_newton(ea_fe_model_t *m, ea_fe_static_info_t *info, ea_error_t *err);
/** Static equilibrium at shoulder angle theta0 [rad] and cable parameter value (ACTIVE:
 *  T [N]; PASSIVE: rest length L0 [m]) by continuation from the current equilibrium:
 *  theta0 and the cable value move along a straight path from the current state's to the
 *  targets, each step solved by Newton from the previous one (secant predictor), the step
 *  halved on failure (down to 1/4096 of the way) and doubled after easy steps. Use it
 *  where a single Newton from the current state may fail: an arm heavier or stiffer than
 *  the state was made for, a large change of the inputs. An ACTIVE state may be continued
 *  to a PASSIVE target (made passive at its current tension first). On success m holds the
 *  equilibrium at rest; on failure m is unchanged and err says how far it got.
 *  info->iterations counts the Newton iterations of all steps. */
ea_status_t ea_fe_static_continue(ea_fe_model_t *m, double theta0, ea_fe_cable_phase_t phase,
                                  double value, ea_fe_static_info_t *info, ea_error_t *err);

/** Result of ea_fe_modes(). */
typedef struct ea_fe_modes_info {
  ea_status_t status;                   /**< EA_OK or backend failure */
  int modes;                            /**< number of modes filled */
  double freq_hz[EA_FE_MAX_MODES];      /**< [Hz] sign(l) sqrt(|l|) / (2 pi), ascending */
  double lambda[EA_FE_MAX_MODES];       /**< [rad^2/s^2] generalized eigenvalues omega^2 */
  int stable;                           /**< 1: passive stiffness positive definite (Cholesky) */
  double time_assembly_s, time_eigen_s; /**< [s] wall times */
  int backend_info;                     /**< raw LAPACK info / GSL status */
  int iterations; /**< Lanczos steps (Krylov dimension); 0 for the other backends */
  int fallback;   /**< 1: Lanczos did not converge and dsbgvx gave the modes */
} ea_fe_modes_info_t;

/** Natural frequencies and mode shapes (eq. 24) about the current state:
 *  passive-phase stiffness K (an ACTIVE cable is treated as PASSIVE with the
 *  rest length that keeps its current tension, without changing the model's
 *  phase), consistent mass M, (K - omega^2 M) v = 0 on the free DOFs. Also
 *  reports stability (K positive definite). The mode shapes are kept in m. */
ea_status_t ea_fe_modes(ea_fe_model_t *m, ea_fe_modes_info_t *info, ea_error_t *err);
/** Mode k (0-based) of the last ea_fe_modes() call as a full vector
 *  (3 * nodes, clamp entries 0), scaled so max |x_i|, |y_i| = 1 with the tip
 *  y component >= 0. */
ea_status_t ea_fe_mode_shape(const ea_fe_model_t *m, int k, double *phi);
/** Strain-rate damping coefficient b [s] (ea_fe_sim_settings_t.rayleigh_stiffness)
 *  that gives mode k (0-based) of the last ea_fe_modes() call the damping ratio
 *  zeta: b = 2 zeta omega_k (phi' M phi) / (phi' K_mat phi), K_mat = int B^T D B
 *  at the current state (phi' K_mat phi < phi' K phi when the cable and the
 *  geometric stiffness carry part of the mode's stiffness). The damping matrix
 *  b K_mat is not proportional, so this is the first-order (modal) ratio.
 * @param[out] b            coefficient [s]
 * @param[out] zeta_modes   if not NULL: the resulting ratios of all computed modes
 *                          (ea_fe_modes_info_t.modes entries)
 * @return EA_ERR_ARG without valid modes, k out of range, zeta < 0 or an unstable mode */
ea_status_t ea_fe_strain_damping(ea_fe_model_t *m, int k, double zeta, double *b,
                                 double *zeta_modes);
/** Stability only: is the passive-phase stiffness at the current state
 *  positive definite? stable = 1/0. */
ea_status_t ea_fe_stability(ea_fe_model_t *m, int *stable, ea_error_t *err);

/** A time history: value(t) and its rate d/dt at t. Return 0 on success,
 *  nonzero to abort the simulation (EA_ERR_INTERRUPTED). */
typedef int (*ea_fe_history_fn)(double t, double *value, double *rate, void *data);

/** A sampled history: n >= 1 points (t[i] strictly increasing, value[i], and
 *  optionally the rate at each point); ea_fe_samples_eval interpolates with the
 *  C1 cubic Hermite spline of the values and the rates (rate NULL: slopes by
 *  centred differences, zero slope at the ends) and holds the end values
 *  outside [t[0], t[n-1]]. Pass ea_fe_samples_eval with a pointer to an
 *  ea_fe_samples_t as its data. */
typedef struct ea_fe_samples {
  int n;
  const double *t;     /**< [s] sample times */
  const double *value; /**< samples (rad, N or m) */
  const double *rate;  /**< rates d value / dt at the samples, or NULL */
} ea_fe_samples_t;
int ea_fe_samples_eval(double t, double *value, double *rate, void *data);

/** What drives a transient: shoulder angle theta0(t) [rad] and the cable's
 *  parameter in the model's current phase (ACTIVE: tension T(t) [N];
 *  PASSIVE: rest length L0(t) [m], a moving reference length). A NULL
 *  function holds the value of the initial state. */
typedef struct ea_fe_drive {
  ea_fe_history_fn theta0;
  void *theta0_data;
  ea_fe_history_fn cable;
  void *cable_data;
} ea_fe_drive_t;

/** Time integrators. */
typedef enum ea_fe_scheme {
  EA_FE_SCHEME_ENERGY = 0, /**< implicit midpoint with the discrete gradient of the
                                potential (Gonzalez / Simo-Tarnow): conserves the
                                energy of the undriven, undamped system exactly,
                                second order, no numerical dissipation */
  EA_FE_SCHEME_GENALPHA,   /**< generalized-alpha (Chung-Hulbert), second order,
                                spectral radius rho_inf at infinite frequency:
                                M a_{n+1-am} + C v_{n+1-af} + f(q_{n+1-af}, t_{n+1-af}) = 0
                                with Newmark updates, am = (2 rho_inf - 1)/(rho_inf + 1),
                                af = rho_inf/(rho_inf + 1), gamma = 1/2 - am + af,
                                beta = (1 - am + af)^2/4; consistent initial acceleration
                                (needs a nonsingular mass matrix, i.e. I_zz > 0) */
  EA_FE_SCHEME_COUNT
} ea_fe_scheme_t;

/** Transient settings. */
typedef struct ea_fe_sim_settings {
  ea_fe_scheme_t scheme;     /**< default EA_FE_SCHEME_ENERGY */
  double dt;                 /**< [s] time step (default 1e-3) */
  double t_end;              /**< [s] end time (default 1) */
  double t_motion_end;       /**< [s] when the drive stops; the residual vibration is
                                  measured on [t_motion_end, t_end]; < 0: not measured
                                  (default -1) */
  double rho_inf;            /**< generalized-alpha spectral radius in [0, 1] (default 0.9;
                                  1 = no numerical dissipation) */
  double rayleigh_mass;      /**< [1/s] a: mass-proportional damping force a M v
                                  (drags rigid motion too; default 0) */
  double rayleigh_stiffness; /**< [s] b: strain-rate (Kelvin-Voigt) damping: the sectional
                                  forces gain b (EA dGamma1/dt, GA dGamma2/dt, EI dK/dt),
                                  i.e. the force b int B^T D B v at the current
                                  configuration. About an unstressed state and for small
                                  motions this is b K_material (the former Rayleigh
                                  b K0 without its geometric and cable parts); unlike
                                  b K0 it is zero for rigid motions of any size.
                                  ea_fe_strain_damping() sets b from a modal damping
                                  ratio (default 0) */
  double tol;                /**< Newton: max |dq| of free DOFs [m, rad] (default 1e-11);
                                  corrections that stagnate below 1e3 tol (rounding) stop too */
  int max_iter;              /**< Newton iterations per step (default 25) */
  int output_every;          /**< write a tip row every this many steps (default 1) */
  double tip_static[2];      /**< [m] the final static equilibrium's tip (x, y) for the residual,
                                  when the caller knows it (e.g. by ea_fe_static_continue);
                                  NAN (default): Newton from the state at t_motion_end */
} ea_fe_sim_settings_t;

void ea_fe_sim_settings_default(ea_fe_sim_settings_t *s);
ea_status_t ea_fe_sim_settings_validate(const ea_fe_sim_settings_t *s, ea_error_t *err);

/** Result of a transient. */
typedef struct ea_fe_sim_info {
  ea_status_t status;
  int steps;                       /**< time steps taken */
  int rows;                        /**< tip rows written */
  int newton_iterations;           /**< total */
  int max_step_iterations;         /**< worst step */
  double energy_start, energy_end; /**< [J] ea_fe_energy at t = 0 and t_end */
  double energy_drift_max;         /**< [J] max_n |E_n - E_0| */
  double damping_work;             /**< [J] work done by the damping forces, sum over the steps
                                        of (q_{n+1} - q_n) . f_damp at the scheme's evaluation
                                        point (energy scheme, undriven: E_n + W_n = E_0) */
  double kinetic_max;              /**< [J] max kinetic energy */
  double residual_rms;  /**< [m] RMS of |tip_xy(t) - tip_xy_static| on [t_motion_end, t_end] */
  double residual_peak; /**< [m] peak of the same */
  double tip_static[3]; /**< final static equilibrium tip (x, y, theta) */
  double time_s;        /**< [s] wall time */
} ea_fe_sim_info_t;

/** Integrate the nonlinear FE model from the current state (q, v) over
 *  [0, t_end] driven by drive (NULL = undriven).
 * @param[in,out] m    model; ends in the state at t_end
 * @param[out]    tip  if not NULL: rows of 4 doubles (t [s], x [m], y [m],
 *                     theta [rad]), the first at t = 0, then every
 *                     output_every steps; at most tip_rows rows are written
 * @param[out]    info may be NULL */
ea_status_t ea_fe_simulate(ea_fe_model_t *m, const ea_fe_drive_t *drive,
                           const ea_fe_sim_settings_t *s, double *tip, int tip_rows,
                           ea_fe_sim_info_t *info, ea_error_t *err);

/* ------------------------------------------------------------------------ */
/* Reduced dynamic model along the quasi-static manifold (model/fe_rom.c)     */
/* ------------------------------------------------------------------------ */

/** Most modes of the reduced model. */
#define EA_ROM_MAX_MODES 4

/** Settings of the reduced model. */
typedef struct ea_rom_settings {
  int modes;          /**< K modes kept (default 2) */
  int elements;       /**< FE elements (default EA_FE_DEFAULT_ELEMENTS) */
  double step_length; /**< [m] central-difference step in L_c for du_s/dq (default 2e-3) */
  double step_angle;  /**< [rad] the same in alpha (default 4e-3) */
} ea_rom_settings_t;

void ea_rom_settings_default(ea_rom_settings_t *s);
ea_status_t ea_rom_settings_validate(const ea_rom_settings_t *s, ea_error_t *err);

/** The reduced model at one configuration q = (L_c, alpha): with u = u_s(q) + sum Phi_i eta_i
 *  (mass-normalised modes about the static state, passive cable),
 *    eta_i'' + omega_i^2 eta_i = -B_i . q'' - q'^T C_i q'
 *  Units: eta_i [sqrt(kg) m]. Index 0 of a pair is L_c, 1 is alpha; C_i = (LL, La, aa). */
typedef struct ea_rom_point {
  int modes;
  double omega2[EA_ROM_MAX_MODES];   /**< [rad^2/s^2] omega_i^2 */
  double B[EA_ROM_MAX_MODES][2];     /**< Phi_i^T M du_s/dq */
  double C[EA_ROM_MAX_MODES][3];     /**< Phi_i^T M d2u_s/dq2 (LL, La, aa) */
  double tip[EA_ROM_MAX_MODES][2];   /**< tip (x, y) displacement per unit eta_i */
  double dtension[EA_ROM_MAX_MODES]; /**< cable tension per unit eta_i (cable rest length held) */
  double
      dtorque[EA_ROM_MAX_MODES]; /**< shoulder torque EI kappa0 per unit eta_i: -(K Phi_i)_theta0 */
  double tension;                /**< [N] FE static tension */
  double theta0;                 /**< [rad] FE static shoulder angle */
  double rest_length;            /**< [m] passive cable rest length (ea_rom_point only) */
  double p_centre[EA_NP];        /**< ODE statics p at q (ea_rom_point only) */
} ea_rom_point_t;

/** Workspace to compute the reduced model (opaque). */
typedef struct ea_rom ea_rom_t;

/** Allocate for arm (copied) and tip mass [kg]; s NULL = defaults. */
ea_status_t ea_rom_alloc(const ea_arm_t *arm, double tip_mass, const ea_rom_settings_t *s,
                         ea_rom_t **out, ea_error_t *err);
void ea_rom_free(ea_rom_t *r);
const ea_rom_settings_t *ea_rom_settings(const ea_rom_t *r);
/** The reduced model at (L_c [m], alpha [rad]) directly from the FE model (9 static solves and
 *  one eigen-solve). align = 1: the mode signs continue those of the previous successful call
 *  (give nearby points in sequence); 0: the tip's y component >= 0.
 *  EA_ERR_UNSTABLE when the configuration is not stable; statics/FE failures as they come. */
ea_status_t ea_rom_point(ea_rom_t *r, double cable_length, double cable_angle, int align,
                         ea_rom_point_t *out, ea_error_t *err);

/** The reduced model tabulated over a box of (L_c, alpha) (opaque). */
typedef struct ea_rom_table ea_rom_table_t;

typedef struct ea_rom_table_info {
  int modes;
  int n_cable_length, n_cable_angle; /**< grid points */
  double box[4];                     /**< [m, m, rad, rad] L_c min, max, alpha min, max */
  int n_extrapolated;                /**< grid points without a stable state, extrapolated */
  double time_s;                     /**< [s] wall time of the build (0: loaded) */
} ea_rom_table_info_t;

/** Build the table on an nL x na grid over box (L_c min, max, alpha min, max): ea_rom_point at
 *  every grid point, mode signs continuous over the grid, points without a stable state
 *  filled by linear extrapolation from their neighbours. */
ea_status_t ea_rom_table_build(ea_rom_t *r, const double box[4], int nL, int na,
                               ea_rom_table_t **out, ea_error_t *err);
/** The table from its grid values (as ea_rom_table_values gives them): for a cache. */
ea_status_t ea_rom_table_from_values(int modes, int nL, int na, const double box[4],
                                     const double *values, ea_rom_table_t **out, ea_error_t *err);
/** The grid values (count of them in *count); owned by the table. */
const double *ea_rom_table_values(const ea_rom_table_t *tb, size_t *count);
void ea_rom_table_info(const ea_rom_table_t *tb, ea_rom_table_info_t *info);
void ea_rom_table_free(ea_rom_table_t *tb);
/** Values (v) and exact derivatives of the bicubic interpolant wrt L_c (dL) and alpha (da) at
 *  (L_c, alpha), clamped to the box (derivatives 0 outside); any output may be NULL. The
 *  p_centre and rest_length fields are not tabulated (0). No allocation. */
void ea_rom_table_eval(const ea_rom_table_t *tb, double cable_length, double cable_angle,
                       ea_rom_point_t *v, ea_rom_point_t *dL, ea_rom_point_t *da);

/* EA_FE_SECTION_END */

#ifdef __cplusplus
}
#endif
#endif /* EA_MODEL_H */
