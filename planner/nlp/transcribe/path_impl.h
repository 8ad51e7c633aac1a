/* Private: the path transcription (docs/planner.md, "Transcriptions"). On a line or polyline
 * the statics along the path do not depend on the timing, so they are computed once along the
 * path coordinate sigma (arc length of the tip path in the base frame) and the NLP keeps per
 * knot only sigma_k and the rates of the cubic Hermites (L_c, alpha[, base], theta0), plus t_f
 * and the modal states of a task with dynamics. No shooting inside the engines.
 *
 * It is a reduced space of the knot transcription (knot_*.c): its knot-layout vector x_k is a
 * function of the path vector x_s (L_c, alpha, base = the path's geometry at sigma_k,
 * (T, theta0, kappa0) = the path's statics tables at sigma_k, everything else copied), and every
 * row but the statics and path rows (which hold identically) is the knot transcription's own
 * row evaluated at x_k, its Jacobian mapped by the chain rule. The feasible set is the knot
 * transcription's (the knots on the path, the C2 splines through them), so the plans agree.
 *
 * Files: path_layout.c (geometry, the map to the knot layout), path_statics.c (the statics
 * tables), path_nlp.c (evaluation, callbacks), path_build.c (setup), path_solve.c (a solve). */
#ifndef EA_PATH_IMPL_H
#define EA_PATH_IMPL_H

#include "plan_asn_impl.h"
#include "dyn_impl.h"
#include "par_impl.h"
#include "path_entry_impl.h"
#include "plan_impl.h"
#include "plan_ipm_impl.h"
#include "plan_screen_impl.h"

#define EA__PP_TOL 1e-10
#define EA__PP_MAXS 4096

struct ea__pp {
  int nc;  /* coordinates with a rate per knot: nq + 1 (theta0 last) */
  int nbp; /* path variables per knot: 1 + nc */
  int n, m, nnz, nnz_h, itf, ie0;
  /* path: cumulative sigma at the segment starts, total */
  double sig0[EA_TASK_MAX_VIA + 2], S;
  double bref[EA_TASK_MAX_VIA + 1]; /* base angle at each segment's start (unwrap reference) */
  /* statics splines: ns samples sorted in sigma; per sample p = (T, theta0, kappa0), dp/dsigma */
  int ns, soff[EA_TASK_MAX_VIA + 2]; /* samples; segment j's are soff[j] .. soff[j + 1] - 1 */
  double *ssig, *sp, *sdp;
  double *spa;       /* per sample dp/dL_c, dp/dalpha (the limits between the knots' rates) */
  double spline_err; /* estimated max error (theta0 [rad]; T relative) */
  /* what the samples were built for (ea__pp_update keeps the segments that did not change):
   * per segment its geometry and estimated error; the arm, tip mass and fixed base angle */
  int key_nseg;
  double key_seg[EA_TASK_MAX_VIA + 1][8], key_err[EA_TASK_MAX_VIA + 1];
  double key_tip_mass, key_base;
  ea_arm_t key_arm;
  double g_first[EA_NP], q_first[2]; /* the first sample's statics (an update's warm start) */
  int have_first;
  ea_status_t path_status; /* the path's statics (EA_ERR_INFEASIBLE: it leaves the workspace) */
  char path_msg[512];
  /* knot-layout map: for index i of x_k: path index (-1: none) and kind */
  int *kidx;
  unsigned char *kkind; /* 0 copy, 1 q (coordinate kc), 2 statics (j) */
  unsigned char *kcoord;
  int *kknot;
  double *xk, *xs_last; /* expanded vector, the path vector it was expanded from */
  double *dq;           /* N x (3 + 3): dq/dsigma (L, alpha, base), dp/dsigma (T, theta0, kappa0) */
  double *dq2;          /* N x (3 + 3): their second derivatives */
  double *xkx;          /* knot-layout scratch (the Hessian's differences) */
  /* NLP */
  ea__row_t *rows;
  int *rmap; /* knot planner's row of each row */
  double *x, *xl, *xu, *gl, *gu, *g, *mult_g, *mult_xl, *mult_xu;
  double *x_sol, *mult_g_sol, *mult_xl_sol, *mult_xu_sol, *x0;
  double *g_sol;     /* the rows at x_sol (the active-set Newton's gaps) */
  ea__kkt_t *kkt;    /* the KKT system of the own engines (NULL until the first) */
  ea__asn_t *asn;    /* the active-set Newton of a warm start, on kkt */
  ea__screen_t *scr; /* Ipopt's rows (engine/ipopt_screen.c; NULL until the first Ipopt solve) */
  int *rfam, nfam;   /* each row's family for it: one limit of one coordinate */
  double *xstart;    /* the start of an Ipopt solve (a screened solve's second round) */
  int have_solution;
  /* per knot of the solution: its speed along the path [m/s] and its slopes dq/dsigma (N x 4);
   * its segments' starts (the replanning predictor, ea__pp_predict) */
  double *sd_sol, sig0_sol[EA_TASK_MAX_VIA + 2];
  int vk_sol[EA_TASK_MAX_VIA + 2]; /* its via knots */
  int *irow, *jcol;
  int *hirow, *hjcol, *hpos_start, *hpos;
  ea__row_t *orows;
  double *oweight;
  int n_orows;
  double *gk, *xx; /* knot-layout gradient scratch; perturbed path vector */
  /* with dynamics the rows, Jacobian and Hessian are evaluated in two parts, the rows of the
   * knots below split and the rest (plan_par.c; par NULL: both parts on the caller) */
  ea__par_t *par;
  int split;
  int *jstart;       /* each row's first Jacobian entry */
  double *xkx1;      /* part 1's knot-layout scratch */
  ea_shooter_t *sh1; /* the worker's shooter (the statics samples; NULL without a worker) */
  int dyn_direct;    /* the modal defects' Hessians and cached gradients in this layout directly
                        (ea__plan_dyn_defect_hess_pp; 0: through the knot layout) */
  double *hv1;       /* part 1's Hessian values */
  /* with dynamics the rows' values come with their Jacobian's (one pass over the rows), kept
   * for the Jacobian at the same x */
  double *jv_keep, *jv_x;
  double *kkt_jv; /* the KKT test's Jacobian values */
  int jv_valid;
  struct IpoptProblemInfo *ip;
  int iter;
};

/* the path layout: knot k's sigma and rates */
#define EA__PS(pp, k) ((k) * (pp)->nbp)
#define EA__PR(pp, k, c) ((k) * (pp)->nbp + 1 + (c)) /* c: 0..nq-1, nq = theta0 */

/* ---- path_layout.c ---- */
int ea__pp_seg(const ea_planner_t *pl, double sig);
void ea__pp_q(const ea_planner_t *pl, int j, double sig, double q[3], double dq[3]);
double ea__pp_sigma_of(const ea_planner_t *pl, int j, const double q[3]);
void ea__pp_expand(const ea_planner_t *pl, const double *xs);
int ea__pp_defect_entries(const ea_planner_t *pl, const double *xs, const ea__row_t *r,
                          int cols[EA__PP_DKEY], double key[EA__PP_DKEY]);
int ea__pp_row(const ea_planner_t *pl, const double *xs, const ea__row_t *r, double *value,
               int *cols, double *vals);

/* ---- path_statics.c ---- */
double ea__herm(double h, double y0, double d0, double y1, double d1, double u, double *dy);
void ea__pp_spline(const ea__pp_t *pp, int j, double sig, double p[3], double dp[3], double d2p[3]);
ea_status_t ea__pp_build_splines(ea_planner_t *pl, ea_error_t *err);

/* ---- path_nlp.c ---- */
/** The path NLP's description (engine/nlp_impl.h). */
void ea__pp_nlp(const ea_planner_t *pl, ea__nlp_t *p);
const ea__row_t *ea__pp_hrow(const ea_planner_t *pl, int r);
int ea__pp_npieces(const ea_planner_t *pl);
ea_status_t ea__pp_hess_setup(ea_planner_t *pl, const int *rc, const int *rn);
int ea__pp_cb_f(int n, double *x, int new_x, double *f, void *ud);
int ea__pp_cb_grad_f(int n, double *x, int new_x, double *g, void *ud);
int ea__pp_cb_g(int n, double *x, int new_x, int m, double *g, void *ud);
int ea__pp_cb_jac(int n, double *x, int new_x, int m, int nele, int *iRow, int *jCol,
                  double *values, void *ud);
int ea__pp_cb_h(int n, double *x, int new_x, double of, int m, double *lambda, int new_lambda,
                int nele, int *iRow, int *jCol, double *values, void *ud);
int ea__pp_cb_iter(int alg_mod, int iter, double obj, double inf_pr, double inf_du, double mu,
                   double d_norm, double reg, double alpha_du, double alpha_pr, int ls, void *ud);

/* ---- path_solve.c ---- */
void ea__pp_predict(ea_planner_t *pl);

/* ---- path_build.c ---- */
void ea__pp_bounds(ea_planner_t *pl);
void ea__pp_path(ea_planner_t *pl);

#endif
