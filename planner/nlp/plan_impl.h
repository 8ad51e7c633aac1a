/* Private: the planner's workspace (struct ea_planner), the knot layout's variable indices and
 * the helpers every part shares (plan_shared.c). Each concern has its own header: the knot
 * transcription transcribe/knot_impl.h, its start transcribe/guess_impl.h, its Hessian
 * transcribe/hess_impl.h, the vibration rows transcribe/vib_impl.h, the dynamic rows
 * transcribe/dyn_impl.h, the path transcription transcribe/path_entry_impl.h (its inside
 * transcribe/path_impl.h), the worker thread par_impl.h, the engines their headers in engine/, the
 * strategy strategy/strategy_impl.h. */
#ifndef EA_PLAN_IMPL_H
#define EA_PLAN_IMPL_H

#include "ea_planner.h"
#include "ea_util.h"
#include "strategy_impl.h"

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
  struct ea__freq_model *fm; /* transcribe/vib_impl.h */
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
/** Nonzero when the solve's wall-clock limit (solver.max_time_s) has passed (ud: the
 *  planner; the own interior point's stop, engine/ipm.c). */
int ea__plan_time_up(void *ud);
/** Does the Lagrangian Hessian take the row's curvature? Not the statics rows (their own
 *  blocks, knot_hess.c) nor the linear rest rows. (Without the modal defects' curvature
 *  at-rest plans with a payload no longer converge: docs/planner.md, "Tried, not adopted".) */
static inline int ea__plan_row_curved(const ea__row_t *r) {
  return r->kind > EA__ROW_STATICS_Y && r->kind != EA__ROW_DYN_REST;
}
/** A row evaluation (the knot transcription's ea__plan_row_eval, or the path one's). */
typedef int (*ea__rowfn)(const ea_planner_t *pl, const double *x, const ea__row_t *r, double *value,
                         int *cols, double *vals);
/** Limits between the knots of a converged plan x that no row holds exactly
 *  (ranges of the cubics, tension and torque of the statics at the
 *  interpolated (L_c, alpha), the frequency model's limits, plan_between.c):
 *  tightens the bounds or rows at the knots of every interval where one is
 *  exceeded and returns how many; *worst = the largest relative excess
 *  (<= 0 or -INFINITY: none), msg says which. */
int ea__plan_between(ea_planner_t *pl, const double *x, double *worst, char *msg, size_t len);
/** The (L_c, alpha) box the task's path covers, with a margin (vib_rows.c). */
void ea__plan_box(const ea_planner_t *pl, double box[4]);
struct ea__ipm_opt;
/** The own interior point's settings for both transcriptions (engine/ipm.c): the task's
 *  tolerances, Ipopt's acceptable termination as the planner sets it for Ipopt, at most
 *  min(40, max_iter) iterations, the solve's wall-clock limit; the barrier's start mu_init and
 *  the slacks' push push_s are the caller's. */
void ea__plan_ipm_opt(const ea_planner_t *pl, double mu_init, double push_s, struct ea__ipm_opt *o);
/** Tip in 3-D and its derivatives wrt (L_c, alpha, base). */
void ea__plan_tip3(const ea_planner_t *pl, double Lc, double al, double b, double P[3],
                   double dP[3][3]);
/** What the planner takes from the task besides the structure: tip mass, knot and variable
 *  counts, fixed duration and base angle, speed and acceleration limits (plan_alloc.c). */
void ea__plan_derive(ea_planner_t *pl);
/** Margins, residuals and active limits of a plan x into info. */
void ea__plan_stats(ea_planner_t *pl, const double *x, ea_plan_info_t *info);

#endif
