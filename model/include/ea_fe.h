/**
 * @file ea_fe.h
 * @brief Finite element model of the arm (paper sec. 3, docs/fe.md):
 *        statics, frequencies, stability, transients (model/fe_*.c), and the
 *        reduced dynamic model along the quasi-static manifold (model/fe_rom.c).
 *
 * Never prints, never aborts: every call returns an ::ea_status_t and, on
 * failure only, a message in the caller's optional ::ea_error_t.
 * Units: SI, angles in radians. The arm's plane has x horizontal (away from
 * the base axis) and y vertical (up); gravity is -y.
 */
#ifndef EA_FE_H
#define EA_FE_H

#include "ea_statics.h"

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

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
  int output_loads;          /**< 1: tip rows carry two more values, the shoulder torque [N m]
                                  (the moment the beam carries at the clamp: minus the clamp
                                  row of the internal and strain-rate damping forces, EI kappa0
                                  at rest; the clamp's own rotary inertia, rho I_zz h theta0'',
                                  is left out) and the cable tension [N] (default 0) */
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
  double tension_min, tension_max; /**< [N] extremes of the cable tension over the steps
                                        (t > 0; PASSIVE: 0 when slack; NONE: 0) */
  double tension_min_time, tension_max_time; /**< [s] when they occur */
  double residual_rms;  /**< [m] RMS of |tip_xy(t) - tip_xy_static| on [t_motion_end, t_end] */
  double residual_peak; /**< [m] peak of the same */
  double tip_static[3]; /**< final static equilibrium tip (x, y, theta) */
  double time_s;        /**< [s] wall time */
} ea_fe_sim_info_t;

/** Integrate the nonlinear FE model from the current state (q, v) over
 *  [0, t_end] driven by drive (NULL = undriven).
 * @param[in,out] m    model; ends in the state at t_end
 * @param[out]    tip  if not NULL: rows of 4 doubles (t [s], x [m], y [m],
 *                     theta [rad]; with s->output_loads 6: + shoulder torque [N m],
 *                     cable tension [N]), the first at t = 0, then every
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
/** What the values of ea_rom_table_values mean (their order, the fields and their sign and
 *  scale conventions): incremented with every change of any of it in model/fe_rom.c, so a
 *  stored table (the planner's cache, ea_simulate.h) of another meaning is never used. */
#define EA_ROM_TABLE_VERSION 2
/** The grid values (count of them in *count); owned by the table. */
const double *ea_rom_table_values(const ea_rom_table_t *tb, size_t *count);
void ea_rom_table_info(const ea_rom_table_t *tb, ea_rom_table_info_t *info);
void ea_rom_table_free(ea_rom_table_t *tb);
/** Values (v) and exact derivatives of the bicubic interpolant wrt L_c (dL) and alpha (da) at
 *  (L_c, alpha), clamped to the box (derivatives 0 outside); any output may be NULL. The
 *  p_centre and rest_length fields are not tabulated (0). No allocation. */
void ea_rom_table_eval(const ea_rom_table_t *tb, double cable_length, double cable_angle,
                       ea_rom_point_t *v, ea_rom_point_t *dL, ea_rom_point_t *da);
/** ea_rom_table_eval plus the interpolant's exact second derivatives (dLL, dLa, daa; 0
 *  outside the box in the coordinate that left it). Piecewise: they jump across the cells'
 *  edges (the bicubic is C1). Any output may be NULL. No allocation. */
void ea_rom_table_eval2(const ea_rom_table_t *tb, double cable_length, double cable_angle,
                        ea_rom_point_t *v, ea_rom_point_t *dL, ea_rom_point_t *da,
                        ea_rom_point_t *dLL, ea_rom_point_t *dLa, ea_rom_point_t *daa);

/** The reduced model at large modal deflection (model/fe_romnl.c; docs/fe.md, "At large modal
 *  deflection"): the linear model's two modes with every other degree of freedom condensed
 *  statically (the modal force to all orders, fitted), the inertia of the condensed motion on the
 *  quadratic manifold of static modal derivatives, and the modes and the manifold moving with
 *  q = (L_c, alpha). Its coefficients are computed at points of a path in q and interpolated
 *  along it; its modal coordinates are those of the linear table it is sampled against. */
#define EA_ROMNL_MODES 2
/** Points at which the planner and plan --verify sample a plan's path (ea_traj_romnl_sample). */
#define EA_ROMNL_SAMPLES 21
typedef struct ea_romnl ea_romnl_t;
typedef struct ea_romnl_info {
  int samples;        /**< points of the path */
  int nodes_dropped;  /**< fit nodes beyond a fold of the condensation (the fit extrapolates) */
  double fit_error;   /**< [-] worst residual of the condensed force's fit, of its largest value */
  double time_s;      /**< [s] wall time of ea_romnl_sample */
  double time_fit_s;  /**< [s] of it in the condensed force's fits (the rest: FE static states,
                           modes and modal derivatives) */
  int condensations;  /**< Newton solves of the condensation (fits) */
  int factorizations; /**< tangent factorizations in them */
} ea_romnl_info_t;
/** Allocate for arm (copied), tip mass [kg] and FE elements (0: the default). */
ea_status_t ea_romnl_alloc(const ea_arm_t *arm, double tip_mass, int elements, ea_romnl_t **out,
                           ea_error_t *err);
void ea_romnl_free(ea_romnl_t *r);
/** The coefficients at n points q = (L_c [m], alpha [rad]) pairs of a path, in order (about 9 FE
 *  static solutions, 9 eigen-solves and 17 condensations each); mode signs those of tb (2 modes).
 *  Replaces the previous samples. EA_ERR_NOCONV when a point has no stable static state or its
 *  condensation fails. */
ea_status_t ea_romnl_sample(ea_romnl_t *r, const ea_rom_table_t *tb, int n, const double *q,
                            ea_error_t *err);
void ea_romnl_info(const ea_romnl_t *r, ea_romnl_info_t *info);
/** The path position (sample index plus fraction) nearest to q, searched from *cursor (a window
 *  of segments after it; NULL: the whole path), *cursor updated; the distance [m, alpha weighted
 *  0.5 m/rad] into *dist. Positions run with time along one motion: start the cursor at 0. */
double ea_romnl_locate(const ea_romnl_t *r, const double q[2], int *cursor, double *dist);
/** The modal accelerations: z = (e_1, e_1', e_2, e_2') [sqrt(kg) m, /s] at path position pos with
 *  the linear table's point p at the same q, actuator rates q1 = q' and accelerations q2 = q'';
 *  dz = z'. */
void ea_romnl_rhs(const ea_romnl_t *r, double pos, const ea_rom_point_t *p, const double q1[2],
                  const double q2[2], const double z[2 * EA_ROMNL_MODES],
                  double dz[2 * EA_ROMNL_MODES]);

#ifdef __cplusplus
}
#endif
#endif /* EA_FE_H */
