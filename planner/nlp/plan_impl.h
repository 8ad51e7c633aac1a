/* Private: the planner's workspace (planner/plan_*.c). */
#ifndef EA_PLAN_IMPL_H
#define EA_PLAN_IMPL_H

#include "ea_planner.h"
#include "ea_util.h"
#include "strategy_impl.h"

#include <gsl/gsl_interp2d.h>
#include <gsl/gsl_spline2d.h>
#include <stdint.h>

/** Kinds of constraint rows (and of the variable bounds, for reports). */
typedef enum ea__row_kind {
  EA__ROW_STATICS_KAPPA = 0, /* kappa(L) = 0 */
  EA__ROW_STATICS_X,         /* x_L - x_c - L_c cos alpha = 0 */
  EA__ROW_STATICS_Y,         /* y_L - y_c - L_c sin alpha = 0 */
  EA__ROW_ACC_START,         /* acceleration at the start of an interval */
  EA__ROW_ACC_END,           /* ... at its end */
  EA__ROW_SPEED_CTRL,        /* middle Bernstein coefficient of an interval's rate */
  EA__ROW_PATH_NORMAL,       /* tip on the segment's line */
  EA__ROW_PATH_PROGRESS,     /* tip between the segment's ends */
  EA__ROW_OBJ_ACC,           /* objective piece: acceleration energy of an interval */
  EA__ROW_OBJ_JERK,          /* objective piece: jerk energy of an interval */
  EA__ROW_FREQ_MIN,          /* f1(L_c, alpha) >= min at a knot */
  EA__ROW_DEFL_START,        /* modal deflection s_c acc / omega1^2 at the start of an interval */
  EA__ROW_DEFL_END,          /* ... at its end */
  EA__ROW_OBJ_VIB,           /* objective piece: vibration integral of an interval (all coords) */
  EA__ROW_ACC_CONT,          /* acceleration continuous at an interior knot */
  EA__ROW_DYN_DEF_POS,       /* modal Hermite-Simpson defect, eta (dyn_rows.c) */
  EA__ROW_DYN_DEF_VEL,       /* ... eta' */
  EA__ROW_DYN_TENSION,       /* tension with the modal part at a knot */
  EA__ROW_DYN_TORQUE,        /* shoulder torque with the modal part at a knot */
  EA__ROW_DYN_DEVIATION,     /* squared modal tip deviation at a knot */
  EA__ROW_DYN_TERMINAL,      /* squared residual amplitude at the goal */
  EA__ROW_DYN_REST, /* the goal's modal state = its target (coord i < K: eta_i, else eta'_i) */
  EA__ROW_OBJ_DYN,  /* objective piece: the same (min_vibration with dynamics) */
  EA__ROW_KIND_COUNT
} ea__row_kind_t;

/** Coordinates with a cubic Hermite per interval: the actuator coordinates
 *  0 L_c, 1 alpha, 2 base, and the shoulder angle theta0 (its values are
 *  statics variables, its rates variables of their own). */
#define EA__C_TH 3

typedef struct ea__pp ea__pp_t;

/** A worker thread for two-part evaluations (plan_par.c). */
typedef struct ea__par ea__par_t;
/** Start the worker (NULL: no thread could be started; ea__par_run then runs both parts). */
ea__par_t *ea__par_new(void);
void ea__par_free(ea__par_t *p);
/** fn(ctx, 1) on the worker while the caller runs fn(ctx, 0); returns when both are done
 *  (p NULL: both on the caller, part 0 first). */
void ea__par_run(ea__par_t *p, void (*fn)(void *ctx, int part), void *ctx);
/** Processors online (>= 1). */
int ea__par_cpus(void);

/** Most models of a robust plan (the nominal arm and four corners), and modal coordinates. */
#define EA__DYN_MAX_MODELS 5
#define EA__DYN_MAX (EA__DYN_MAX_MODELS * EA_ROM_MAX_MODES)

typedef struct ea__row {
  unsigned char kind, coord; /* coord: coordinate (EA__C_TH = theta0) or normal index */
  int knot;                  /* knot (or first knot of the interval) */
} ea__row_t;

/** An objective term (pluggable): value and gradient added with weight w. */
typedef struct ea__plan_term {
  const char *name;
  double weight;
  double (*value)(const struct ea_planner *pl, const double *x);
  void (*grad)(const struct ea_planner *pl, const double *x, double w, double *g);
} ea__plan_term_t;

#define EA__MAX_TERMS 4
/** Most entries of one row or objective piece (ea__plan_row_eval). */
#define EA__ROW_MAX 16

/** FE first-frequency model f1(L_c, alpha) (vib_rows.c). */
typedef struct ea__freq_model {
  int nL, na;
  double *Lg, *ag, *f; /* grid (nL, na) and f1 [Hz] (na x nL, x fastest) */
  gsl_spline2d *sp;
  gsl_interp_accel *xa, *ya;
  ea_plan_freq_model_info_t info;
} ea__freq_model_t;

struct ea_planner {
  ea_task_t task;
  ea_shooter_t *sh;
  double tip_mass;
  int N;      /* knots */
  int nq;     /* actuator coordinates: 2 (L_c, alpha) or 3 (+ base) */
  int nb;     /* variables per knot block: 2 nq + 3 (q, qdot, T, theta0, kappa0) */
  int has_tf; /* 1: t_f is a variable (min_time) */
  int n, m, nnz;
  double tf_fixed;
  double base_fixed;                /* base angle when the base does not move */
  double *s;                        /* N knot time fractions, s_0 = 0, s_{N-1} = 1 */
  double vmax[4], amax[4], aref[3]; /* per coordinate (3: theta0); INFINITY = no limit */
  /* Acceleration rows (ACC_START, ACC_END, ACC_CONT) are multiplied by
   * acc_scale <= 1: Ipopt's absolute tolerance constr_tol on them is then
   * acc_tol = constr_tol / acc_scale in m/s^2 or rad/s^2, at least 60 x the
   * rounding floor 6 eps |q| / h^2 of an acceleration from knot values (at
   * 2000 knots ~3e-9, above the default 1e-10). Every limit row keeps its
   * tolerance inside the limit. */
  double acc_scale, acc_tol;
  /* path */
  int n_seg, n_normals;              /* segments; normals per path knot (1 planar, 2 in 3-D) */
  int via_knot[EA_TASK_MAX_VIA + 2]; /* knot index of start, vias, goal */
  double segA[EA_TASK_MAX_VIA + 1][3], segD[EA_TASK_MAX_VIA + 1][3],
      segN[EA_TASK_MAX_VIA + 1][2][3], segLen[EA_TASK_MAX_VIA + 1];
  int *seg_of_knot; /* N: segment of each knot (-1: pinned or no path) */
  /* Ipopt arrays */
  double *x, *xl, *xu, *gl, *gu, *g, *mult_g, *mult_xl, *mult_xu;
  ea__row_t *rows;
  int *irow, *jcol;
  struct IpoptProblemInfo *ip; /* Ipopt's problem (engine/ipopt_problem.c) */
  struct ea__screen *scr;      /* Ipopt's rows of the next solve (engine/ipopt_screen.c) */
  struct ea__kkt *kkt; /* the own interior point's KKT system (engine/ipm.c; NULL until used) */
  int *rfam, nfam;     /* m: each row's family for it (ea__plan_row_families) */
  double *xstart;      /* n: the start of a solve (a screened solve's second round) */
  /* frequency model (NULL when the task needs none) */
  ea__freq_model_t *fm;
  /* reduced dynamic model (NULL when the task has no dynamics; dyn_rows.c) */
  ea_rom_table_t *rom;                      /* the nominal model's (roms[0]) */
  ea_rom_table_t *roms[EA__DYN_MAX_MODELS]; /* per model: nominal, then the robust corners */
  int M;                                    /* models */
  int Kper;                                 /* modes per model */
  int K;                                    /* modal coordinates: M Kper (model-major) */
  double zeta[EA__DYN_MAX];                 /* modal damping ratios */
  double dyn_scale;                         /* defect rows are multiplied by this */
  double dyn_term_scale;              /* [1/m^2] the terminal amplitude row and objective piece */
  int ie0;                            /* index of the first modal variable */
  double dyn_target[2 * EA__DYN_MAX]; /* terminal (eta, eta') when ending at rest */
  ea_plan_dyn_info_t dyn_info;
  struct ea__dyn_cache *dync; /* the defect rows' work per interval (dyn_rows.c) */
  int zero_end_acc;           /* 1: acceleration 0 at start and goal (min_vibration) */
  /* objective */
  int n_terms;
  ea__plan_term_t terms[EA__MAX_TERMS];
  /* exact Hessian (knot_hess.c) */
  int hess_exact;
  int n_orows; /* objective pieces (rows of kind EA__ROW_OBJ_*) */
  ea__row_t *orows;
  double *oweight; /* weight of each piece */
  int nnz_h;
  int *hirow, *hjcol; /* lower triangle, sorted */
  int *hpos_start;    /* (m + n_orows + 1): offsets into hpos, per row */
  int *hpos;          /* value position of each local pair of a row */
  int *hpos_stat;     /* N x 15: statics block (L_c, alpha, T, theta0, kappa0) */
  double *xx;         /* n scratch */
  double *kkt_r;      /* n scratch: KKT check of a warm start */
  double *x0;         /* n: start point kept for a retry with another barrier strategy */
  double *jval;       /* nnz scratch: Jacobian values (KKT check) */
  int guess_timed;    /* 1: the last cold guess was timed along its path (ea__topp) */
  double *gscr;       /* 5 N scratch of the initial guess */
  double *wscr;       /* 2 N scratch of the theta0 spline */
  /* statics cache, per knot, keyed on the knot's shooting parameters
   * p = (alpha, T, theta0, kappa0): Ipopt evaluates g, its Jacobian and
   * the Hessian at the same x, and a knot is shot (always with
   * sensitivities) only when its p changed. */
  double *xL;            /* N x 4 tip states */
  double *S;             /* N x 16 sensitivities */
  double *pkey;          /* N x 4 p of the cached shot */
  unsigned char *kvalid; /* N: xL (1), xL and S (2) hold the shot at pkey */
  int cache_val, cache_sens;
  /* last converged solution (warm start) */
  int have_solution;
  int updated;        /* the task changed since x_sol (ea_planner_update) */
  ea_task_t task_sol; /* the task x_sol solves */
  double *x_sol, *mult_g_sol, *mult_xl_sol, *mult_xu_sol;
  /* bookkeeping during a solve */
  ea_plan_info_t *info;
  double t_statics, t_callbacks, t_start, max_time;
  int iter;
  int refining; /* 1: re-solve after bounds were tightened for limits between knots */
  /* the prescribed path in the path coordinate (transcribe/path_*.c; NULL: knots only) */
  struct ea__pp *pp;
  int pp_off; /* 1: solve with the knot transcription (a fallback) */
  /* the guess's statics at fraction frac of segment j when a prescribed path has them
   * tabulated (set by the path transcription; NULL, or 0 returned: solve them) */
  int (*guess_statics)(const struct ea_planner *pl, int j, double frac, double p[3]);
};

/** Ipopt's infinity (nlp_lower/upper_bound_inf). */
#define EA__IPINF 1e19

/* Variable indices. */
#define EA__IQ(pl, k, c) ((k) * (pl)->nb + (c))
#define EA__IV(pl, k, c) ((k) * (pl)->nb + (pl)->nq + (c))
#define EA__IP(pl, k, j) ((k) * (pl)->nb + 2 * (pl)->nq + (j)) /* j: 0 T, 1 theta0, 2 kappa0 */
#define EA__ITF(pl) ((pl)->N * (pl)->nb)
/* theta0 rates: one block after the knot blocks and t_f */
#define EA__IW(pl, k) ((pl)->N * (pl)->nb + (pl)->has_tf + (k))
/* Value and rate of coordinate c (< nq, or EA__C_TH) at knot k. */
#define EA__IQC(pl, k, c) ((c) == EA__C_TH ? EA__IP(pl, k, 1) : EA__IQ(pl, k, c))
#define EA__IVC(pl, k, c) ((c) == EA__C_TH ? EA__IW(pl, k) : EA__IV(pl, k, c))
/* modal states: one block after the theta0 rates, 2 K per knot (eta_i, then eta'_i) */
#define EA__IE(pl, k, i) ((pl)->ie0 + 2 * (pl)->K * (k) + (i))
#define EA__IED(pl, k, i) ((pl)->ie0 + 2 * (pl)->K * (k) + (pl)->K + (i))

/** t_f at x. */
double ea__plan_tf(const ea_planner_t *pl, const double *x);
/** x = A^-1 b for 3 x 3 A (Cramer's rule); 0, or -1 when A is singular. */
int ea__plan_solve3(double A[3][3], const double b[3], double x[3]);
/** Derivative of the statics (T, theta0, kappa0) along a move (dL, dalpha) of (L_c, alpha)
 *  at (L, alpha): implicit differentiation of the knot rows (kappa(L), x_L - x_c - L_c cos
 *  alpha, y_L - y_c - L_c sin alpha) = 0, from the shooting sensitivities S (EA_NX x EA_NP,
 *  row-major) at the solution. 0, or -1 when the rows' Jacobian in (T, theta0, kappa0) is
 *  singular. */
int ea__plan_statics_slope(const double *S, double L, double alpha, double dL, double dalpha,
                           double out[3]);
/** Hermite accelerations at both ends of an interval of length h and their
 *  gradients wrt (q0, q1, v0, v1, h). */
void ea__plan_hermite_acc(double q0, double q1, double v0, double v1, double h, double a[2],
                          double ga[2][5]);
/** Shoot every knot at x, with sensitivities when sens (a knot whose p is unchanged and
 *  whose shot has what is asked is not shot again). */
/** Nonzero when the solve's wall-clock limit (solver.max_time_s) has passed (ud: the
 *  planner; the own interior point's stop, engine/ipm.c). */
int ea__plan_time_up(void *ud);
ea_status_t ea__plan_shoot_all(ea_planner_t *pl, const double *x, int sens);
/** The rows' families (m): one limit of one coordinate (an interval's start and end rows of
 *  a limit together), for leaving rows out of Ipopt's problem (engine/ipopt_screen.c); returns the
 *  number of families. */
int ea__plan_row_families(const ea__row_t *rows, int m, int *fam);
/** Constraint values at x into g (m). */
ea_status_t ea__plan_eval_g(ea_planner_t *pl, const double *x, double *g);
/** The same from shots without sensitivities (a check of the rows' values only). */
ea_status_t ea__plan_eval_g_values(ea_planner_t *pl, const double *x, double *g);
/** Jacobian: structure (values NULL) or values (irow/jcol NULL). Returns nnz. */
int ea__plan_jac(ea_planner_t *pl, const double *x, int *irow, int *jcol, double *values);
/** One row (constraint or objective piece): value and entries (col, val);
 *  returns the entry count (<= EA__ROW_MAX). Statics rows read the cached sensitivities. */
int ea__plan_row_eval(const ea_planner_t *pl, const double *x, const ea__row_t *r, double *value,
                      int *cols, double *vals);
/** The closed-form Hessian of a row whose curvature is the Hermite's in t_f (acceleration,
 *  acceleration continuity, the speed rows' middle coefficient, the acceleration and jerk
 *  objective pieces) or the table's (the tension and torque rows with the modal parts): H[a][b]
 * over the row's entries (cols, in ea__plan_row_eval's order); returns their count, or -1 for any
 * other kind. */
int ea__plan_row_hess(const ea_planner_t *pl, const double *x, const ea__row_t *r, int *cols,
                      double H[][EA__ROW_MAX]);
/** The closed-form Hessians of one interval's modal defect rows (a group of
 *  ea__plan_hess_group_len: rows[0..g-1], weights w; ea__plan_hess_fd_local's outputs). */
void ea__plan_dyn_defect_hess(const ea_planner_t *pl, const double *x, const ea__row_t *rows,
                              const double *w, int g, int cols[][EA__ROW_MAX], int *nc,
                              double Hl[][EA__ROW_MAX][EA__ROW_MAX]);
/** The path layout's local variables of a mode's defect rows over an interval
 * (transcribe/path_*.c): eta_k, eta'_k, eta_k+1, eta'_k+1, sigma_k, sigma_k+1, the rates of L_c and
 * alpha at k and k + 1, t_f (the order of the rows' entries in that layout; t_f dropped if fixed).
 */
#define EA__PP_DKEY 11
/** The closed-form Hessians of interval k's modal defect rows (rows[0..g-1], weights w: those
 *  with w = 0 skipped) in the path layout: second-order forward mode over the interval's path
 *  variables (sigma_k, sigma_k+1: sig; (L_c, alpha) at the ends functions of them with slopes
 *  dq[P] and curvatures d2q[P]), no chain rule. Hl[r]'s lower triangle over the row's
 *  EA__PP_DKEY entries (returned: their count), unweighted. x: the knot-layout expansion.
 *  Each mode's values and path gradients are kept for ea__plan_dyn_defect_pp_cached. */
int ea__plan_dyn_defect_hess_pp(const ea_planner_t *pl, const double *x, const double sig[2],
                                const double *dq[2], const double *d2q[2], const ea__row_t *rows,
                                const double *w, int g, double Hl[][EA__ROW_MAX][EA__ROW_MAX]);
/** Mode i's pos (vel 0) or vel defect over interval k at the path values key (the order of
 *  EA__PP_DKEY, t_f 0 if fixed) when ea__plan_dyn_defect_hess_pp left them: its value and
 *  gradient (either may be NULL); returns the entry count, 0 if not kept. */
int ea__plan_dyn_defect_pp_cached(const ea_planner_t *pl, int k, int i, int vel,
                                  const double key[EA__PP_DKEY], double *value, double *vals);
/** Forget what ea__plan_dyn_defect_hess_pp kept (the path's statics or geometry changed). */
void ea__plan_dyn_pp_forget(const ea_planner_t *pl);
/** Make the tables at knot k's (L_c, alpha) in x current (the knot's cache, which the rows of
 *  the intervals on both sides of it read: at the knot where transcribe/path_*.c splits its rows in
 * two parts, before their evaluation in parallel). */
void ea__plan_dyn_warm(const ea_planner_t *pl, const double *x, int k);
/** The same for the tension and torque rows with the modal parts (dyn_rows.c: the table's
 *  exact second derivatives); -1 for any other kind. */
int ea__plan_dyn_row_hess(const ea_planner_t *pl, const double *x, const ea__row_t *r, int *cols,
                          double H[][EA__ROW_MAX]);
/** Does the Lagrangian Hessian take the row's curvature? Not the statics rows (their own
 *  blocks, knot_hess.c) nor the linear rest rows. (Leaving out the modal defects' curvature
 *  was tried: 60 % less work per iteration, but a payload-0.5 at-rest plan no longer
 *  converged in 500 iterations.) */
static inline int ea__plan_row_curved(const ea__row_t *r) {
  return r->kind > EA__ROW_STATICS_Y && r->kind != EA__ROW_DYN_REST;
}
/** A row evaluation (the knot transcription's ea__plan_row_eval, or the path one's). */
typedef int (*ea__rowfn)(const ea_planner_t *pl, const double *x, const ea__row_t *r, double *value,
                         int *cols, double *vals);
/** Most rows the Hessian differences together (an interval's modal defects). */
#define EA__HGROUP_MAX (2 * EA__DYN_MAX)
/** Rows r.. that the Hessian differences together (>= 1). */
int ea__plan_hess_group_len(const ea__row_t *rows, int r, int nr);
/** The Hessians of ea__plan_hess_fd_group as local matrices: row r's entries cols[r]
 *  (nc[r] of them; 0 where w[r] = 0) and Hl[r][a][b] = d grad_b / d x_cols[r][a] (closed forms
 *  where a row kind has one, with fn = ea__plan_row_eval: ea__plan_row_hess,
 *  ea__plan_dyn_defect_hess; else central differences of the exact gradients); g0 (NULL: not
 *  wanted) the rows' gradients at x in the same order; xx a scratch copy of x (one per
 *  thread). */
void ea__plan_hess_fd_local(const ea_planner_t *pl, ea__rowfn fn, const double *x, double *xx,
                            const ea__row_t *rows, const double *w, int g, int cols[][EA__ROW_MAX],
                            int *nc, double Hl[][EA__ROW_MAX][EA__ROW_MAX],
                            double g0[][EA__ROW_MAX]);
/** The Hessians of g rows (rows[0..g-1], weights w; ea__plan_hess_fd_local: closed forms or
 *  central differences over the union of their variables, xx a scratch copy of x), added as
 *  w 0.5 (H + H^T) at each row's Hessian positions hpos[r]. */
void ea__plan_hess_fd_group(const ea_planner_t *pl, ea__rowfn fn, const double *x, double *xx,
                            const ea__row_t *rows, const double *w, int g, const int *const *hpos,
                            double *values);
/** Hessian setup (structure, positions) and values (lower triangle). */
ea_status_t ea__plan_hess_setup(ea_planner_t *pl);
ea_status_t ea__plan_hess_pattern(ea_planner_t *pl);
ea_status_t ea__plan_hess_values(ea_planner_t *pl, const double *x, double obj_factor,
                                 const double *lambda, double *values);
void ea__plan_hess_free(ea_planner_t *pl);
/** Objective terms for the task. */
void ea__plan_terms_setup(ea_planner_t *pl);
/** Name of a row kind ("tension", ...). */
const char *ea__plan_row_name(const ea_planner_t *pl, const ea__row_t *r, char *buf, size_t len);
/** theta0 rates of x: the C2 cubic spline through the knots' theta0 with
 *  rest at the start and the goal (what the theta0 rows hold). */
void ea__plan_theta0_rates(const ea_planner_t *pl, double *x);
/** A short estimate of the duration [s] (the fixed one, else half the sum of
 *  the segments' rest-to-rest estimates), for tolerances set at alloc. */
double ea__plan_duration_low(const ea_planner_t *pl);
/** Physical units per unit of row r's value (1 / acc_scale for the
 *  acceleration rows, else 1). */
double ea__plan_row_unit(const ea_planner_t *pl, const ea__row_t *r);
/** Initial guess (statics continuation along the straight interpolation). */
ea_status_t ea__plan_guess(ea_planner_t *pl, double *x, ea_plan_info_t *info, ea_error_t *err);
/** Initial guess from a previous trajectory. */
ea_status_t ea__plan_guess_traj(ea_planner_t *pl, const ea_traj_t *tr, double *x, ea_error_t *err);
/** Via knots, segments and the knot-to-segment map (at alloc). */
void ea__plan_layout(ea_planner_t *pl);
/** Path segments (ends, directions, normals) and the knot-to-segment map
 *  for the task's points at the planner's via knots (part of the layout;
 *  again at ea_planner_update, which keeps the via knots). */
void ea__plan_segments(ea_planner_t *pl);
/** Shift the previous solution x (of task prev) along a change of the task
 *  (ea_planner_update): points moved -> each coordinate moved by the blend
 *  of its segment's end shifts, min_time re-timed within the limits, every
 *  knot's statics re-solved (payload; statics 0: not, for the path transcription). */
ea_status_t ea__plan_predict(ea_planner_t *pl, const ea_task_t *prev, double *x, int statics);
double ea__plan_retime(const ea_planner_t *pl, double *x);
/** Limits between the knots of a converged plan x that no row holds exactly
 *  (ranges of the cubics, tension and torque of the statics at the
 *  interpolated (L_c, alpha), the frequency model's limits, plan_between.c):
 *  tightens the bounds or rows at the knots of every interval where one is
 *  exceeded and returns how many; *worst = the largest relative excess
 *  (<= 0 or -INFINITY: none), msg says which. */
int ea__plan_between(ea_planner_t *pl, const double *x, double *worst, char *msg, size_t len);
/** The reduced dynamic model for a task with dynamics (pl->rom; NULL otherwise): the box of
 *  the task, the table from the cache or built (dyn_rows.c). */
ea_status_t ea__plan_dyn_build(ea_planner_t *pl, ea_error_t *err);
void ea__plan_dyn_cache_free(struct ea__dyn_cache *c);
/** Rows of the dynamic kinds; same contract as ea__plan_row_eval. */
int ea__plan_dyn_row(const ea_planner_t *pl, const double *x, const ea__row_t *r, double *value,
                     int *cols, double *vals);
/** Modal states of x integrated along its (L_c, alpha) from rest (a guess). */
void ea__plan_dyn_fill(const ea_planner_t *pl, double *x);
/* A cold guess with dynamics: stretched in time inside its limits (minimum time), then its
 * modal states filled (dyn_rows.c). */
void ea__plan_dyn_guess(const ea_planner_t *pl, double *x);
/** For the refinement (plan_refine.c): model j's table (0 the nominal, 1..4 the robust
 *  corners; NULL: none) and the held plan's modal state of model j at the goal (Kper values
 *  each; 1: no held plan). */
const ea_rom_table_t *ea__plan_rom_model(const ea_planner_t *pl, int j);
int ea__plan_dyn_terminal(const ea_planner_t *pl, int j, double *eta, double *eta_rate);
/** The model's predicted residual and modal figures of a plan x into info. */
void ea__plan_dyn_stats(const ea_planner_t *pl, const double *x, ea_plan_info_t *info);
/** The path transcription (transcribe/path_*.c): does the task qualify (line/polyline, no frequency
 *  model, exact Hessian)? */
int ea__pp_supported(const ea_planner_t *pl);
/** Build it (after the knot planner's rows, bounds and Hessian structure). */
ea_status_t ea__pp_alloc(ea_planner_t *pl, ea_error_t *err);
void ea__pp_free(struct ea__pp *pp);
/** The rates of the statics (T, theta0, kappa0) at knot k of the knot-layout plan x along its
 *  (L_c, alpha) rates, from the path's tabulated partial derivatives (the limits between the
 *  knots' screen, plan_between.c); 0, or -1 without a path transcription. */
int ea__pp_statics_rates(const ea_planner_t *pl, const double *x, int k, double pd[3]);
/** After ea_planner_update: the path moved: statics splines and bounds again. */
ea_status_t ea__pp_update(ea_planner_t *pl, ea_error_t *err);
/** A solve in the path coordinate: guess (start), the engines of the strategy
 *  (strategy/strategy_impl.h); pl->x gets the plan in the knot layout (expanded), pl->g its
 *  rows; *res the engines' outcome (its time excepted), *obj the objective. */
ea_status_t ea__pp_solve(ea_planner_t *pl, ea_plan_start_t start, const ea_traj_t *prev,
                         ea_plan_info_t *info, ea__engine_result_t *res, double *obj,
                         ea_error_t *err);
/** For tests (tests/test_plan_hess.c): the path layout's size, its last solution and Hessian
 *  pattern (lower triangle); 0, or -1 without a path transcription. */
int ea__pp_test_dims(const ea_planner_t *pl, int *n, int *m, const double **x_sol, int *nnz_h,
                     const int **hrow, const int **hcol);
/** Path row r at xs: value, entries (cols) and gradient (vals); the entry count. */
int ea__pp_test_row(const ea_planner_t *pl, const double *xs, int r, double *value, int *cols,
                    double *vals);
/** The Lagrangian Hessian of the path layout at xs (objective weight sigma, multipliers lambda)
 *  into values (the pattern's order), as Ipopt and the own interior point get it. */
void ea__pp_test_hess(ea_planner_t *pl, const double *xs, double sigma, const double *lambda,
                      double *values);
/** Threads of the path transcription's evaluations (2 with its worker), 1 without it. */
int ea__pp_threads(const ea_planner_t *pl);
/** Are the modal defects' Hessians and gradients kept in the path layout directly
 *  (ea__plan_dyn_defect_hess_pp)? 1 yes, 0 through the knot layout. */
int ea__pp_test_direct(const ea_planner_t *pl);
/** The (L_c, alpha) box the task's path covers, with a margin (vib_rows.c). */
void ea__plan_box(const ea_planner_t *pl, double box[4]);
/** Uniform knot-time fractions s_k = k / (N - 1). */
void ea__plan_knot_times(ea_planner_t *pl);
/* Hessian sparsity (knot_hess.c): the key of entry (max(i, j), min(i, j)) of an n-column
 * matrix; the sorted unique keys as triplets (irow, jcol calloc'd; keys sorted in place);
 * the position of a key among nnz sorted ones (-1: absent). */
struct ea__ipm_opt;
/** The own interior point's settings for both transcriptions (engine/ipm.c): the task's
 *  tolerances, Ipopt's acceptable termination as the planner sets it for Ipopt, at most
 *  min(40, max_iter) iterations, the solve's wall-clock limit; the barrier's start mu_init and
 *  the slacks' push push_s are the caller's. */
void ea__plan_ipm_opt(const ea_planner_t *pl, double mu_init, double push_s, struct ea__ipm_opt *o);
int64_t ea__hkey(int n, int i, int j);
/* The pattern of nk keys (ea__hkey of an n-column matrix, repeats allowed; keys is scratch):
 * its sorted unique entries as triplets (irow, jcol malloc'd, *nnz of them) and pos[q] = the
 * entry of keys[q]. */
ea_status_t ea__hpattern(int64_t *keys, size_t nk, int n, int *nnz, int **irow, int **jcol,
                         int *pos);
/** Build the frequency model when the task needs it (pl->fm; NULL otherwise). */
ea_status_t ea__plan_freq_build(ea_planner_t *pl, ea_error_t *err);
void ea__plan_freq_free(ea__freq_model_t *fm);
/** f1 [Hz] at (L_c, alpha), clamped to the box, and its gradient (may be NULL). */
double ea__plan_freq(const ea_planner_t *pl, double Lc, double al, double grad[2]);
/** Rows and objective pieces of the vibration kinds (EA__ROW_FREQ_MIN,
 *  EA__ROW_DEFL_*, EA__ROW_OBJ_VIB); same contract as ea__plan_row_eval. */
int ea__plan_vib_row(const ea_planner_t *pl, const double *x, const ea__row_t *r, double *value,
                     int *cols, double *vals);
/** Vibration figures of a plan x into info (min f1, max modal deflection). */
void ea__plan_vib_stats(const ea_planner_t *pl, const double *x, ea_plan_info_t *info);
/** Tip in 3-D and its derivatives wrt (L_c, alpha, base). */
void ea__plan_tip3(const ea_planner_t *pl, double Lc, double al, double b, double P[3],
                   double dP[3][3]);

/* ---- the knot transcription (transcribe/knot_build.c, knot_callbacks.c) ---- */
/** What the planner takes from the task besides the structure: tip mass, knot and variable
 *  counts, fixed duration and base angle, speed and acceleration limits (plan_alloc.c). */
void ea__plan_derive(ea_planner_t *pl);
/** The rows (pl->rows NULL: only counted); returns their count. */
int ea__knot_rows(ea_planner_t *pl);
/** Variable and row bounds from the task. */
void ea__knot_bounds(ea_planner_t *pl);
/* The callbacks of the knot transcription, in Ipopt's C interface's signatures. */
int ea__knot_cb_f(int n, double *x, int new_x, double *f, void *ud);
int ea__knot_cb_grad_f(int n, double *x, int new_x, double *g, void *ud);
int ea__knot_cb_g(int n, double *x, int new_x, int m, double *g, void *ud);
int ea__knot_cb_jac(int n, double *x, int new_x, int m, int nele, int *iRow, int *jCol,
                    double *values, void *ud);
int ea__knot_cb_h(int n, double *x, int new_x, double of, int m, double *lambda, int new_lambda,
                  int nele, int *iRow, int *jCol, double *values, void *ud);
int ea__knot_cb_iter(int alg_mod, int iter, double obj, double inf_pr, double inf_du, double mu,
                     double d_norm, double reg, double alpha_du, double alpha_pr, int ls, void *ud);
/* ---- reports (plan_report.c) ---- */
/** Margins, residuals and active limits of a plan x into info. */
void ea__plan_stats(ea_planner_t *pl, const double *x, ea_plan_info_t *info);
/* ---- the knot transcription's NLP (transcribe/knot_callbacks.c) ---- */
struct ea__nlp;
/** Its description (engine/nlp_impl.h), for the engines. */
void ea__knot_nlp(const ea_planner_t *pl, struct ea__nlp *p);
/** Is x with pl->mult_* a KKT point (engine/kkt_test.c: ea__kkt_accept) to the task's row
 *  tolerance and dual tolerance dtol? 1 yes, 0 no. */
int ea__knot_kkt_ok(ea_planner_t *pl, const double *x, double dtol);

#endif
