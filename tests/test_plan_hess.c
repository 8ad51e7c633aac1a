/* The Lagrangian Hessian of the at-rest plan's dynamics rows (planner/nlp/plan_hess.c,
 * plan_dyn.c) against an independent reference: for every modal defect, tension, torque,
 * tip-deviation and terminal row, the Hessian the planner hands Ipopt for that row alone
 * (lambda = e_r, no objective) against central differences of the row's exact gradient over
 * every one of its variables, Richardson-extrapolated from steps h and h/2 (h = 1e-4 relative),
 * at a generic point (the 8-knot plan's solution, every variable moved by a pseudo-random
 * 1e-4 relative). The reference perturbs the modal states too, which the planner does not
 * (the rows are affine in them): its modal-modal blocks must vanish, and the planner's
 * symmetric fill of the modal-trajectory entries must match it. Two tasks: the paper line at
 * payload factor 0.25 with 2 modes, a tip-deviation bound and a 1 mm residual (every row
 * kind), the same damped (2 % and 5 %), and the robust paper line (nominal and four corner
 * models, 1 mode each). Also the
 * closed-form Hessians of the kinematic rows and objective pieces (acceleration, continuity,
 * speed, effort, jerk: ea__plan_row_hess) against the same reference, with t_f free (the
 * at-rest line) and fixed (polyline-effort with min_effort and min_jerk). And the path
 * transcription's whole Lagrangian Hessian with dynamics (the modal defects' in the path
 * variables directly, the rest through the chain rule) against the same differences of its
 * Lagrangian's gradient, and the defects' values and gradients it keeps against the knot
 * layout's through the chain rule. */
#include "ea_planner.h"
#include "dyn_impl.h"
#include "hess_impl.h"
#include "knot_impl.h"
#include "path_entry_impl.h"
#include "ea_problems.h"
#include "ea_test.h"
#include "ea_test_task.h"
#include "plan_impl.h"

#include <gsl/gsl_errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* stated: the planner's entries within 1e-8 of the row's largest reference entry (closed forms
 * for the defects, tension and torque rows; central differences of the exact gradients, step
 * 1e-6, for the deviation and terminal rows; 1e-5 when the defects took forward differences) */
#define HESS_TOL 1e-8
/* the reference's modal-modal blocks: rounding of its differences only */
#define AFFINE_TOL 1e-8
/* closed forms (ea__plan_row_hess) against the reference: its truncation (h^4) and rounding */
#define KIN_TOL 1e-6
/* the path transcription's whole Hessian against the same reference */
#define PATH_TOL 1e-7
#define EA__PATH_TEST_MAXN 512

static const char *src;

static int is_dyn(int kind) {
  return kind == EA__ROW_DYN_DEF_POS || kind == EA__ROW_DYN_DEF_VEL ||
         kind == EA__ROW_DYN_TENSION || kind == EA__ROW_DYN_TORQUE ||
         kind == EA__ROW_DYN_DEVIATION || kind == EA__ROW_DYN_TERMINAL;
}

static int is_modal(const ea_planner_t *pl, int v) {
  return v >= pl->ie0 && v < pl->ie0 + 2 * pl->K * pl->N;
}

/* Central difference of row r's gradient in its local variable a, step h: D[b]. */
static void grad_diff(ea_planner_t *pl, const ea__row_t *row, double *xx, int v, double h, int nc,
                      double *D) {
  double gp[EA__ROW_MAX], gm[EA__ROW_MAX];
  const double x0 = xx[v];
  xx[v] = x0 + h;
  ea__plan_row_eval(pl, xx, row, NULL, NULL, gp);
  xx[v] = x0 - h;
  ea__plan_row_eval(pl, xx, row, NULL, NULL, gm);
  xx[v] = x0;
  for (int b = 0; b < nc; ++b)
    D[b] = (gp[b] - gm[b]) / (2.0 * h);
}

/* Row row's reference Hessian at x (xx: a scratch copy of x): central differences of its
 * exact gradient, Richardson-extrapolated from steps h and h/2 (h = 1e-4 relative), in the
 * order of its entries cols; *big: its largest entry. Returns the entry count. */
static int reference(ea_planner_t *pl, const ea__row_t *row, const double *x, double *xx, int *cols,
                     double R[][EA__ROW_MAX], double *big) {
  const int nc = ea__plan_row_eval(pl, x, row, NULL, cols, NULL);
  *big = 0.0;
  for (int a = 0; a < nc; ++a) {
    const double h = 1e-4 * fmax(1.0, fabs(x[cols[a]]));
    double D1[EA__ROW_MAX], D2[EA__ROW_MAX];
    grad_diff(pl, row, xx, cols[a], h, nc, D1);
    grad_diff(pl, row, xx, cols[a], 0.5 * h, nc, D2);
    for (int b = 0; b < nc; ++b) {
      R[a][b] = (4.0 * D2[b] - D1[b]) / 3.0;
      *big = fmax(*big, fabs(R[a][b]));
    }
  }
  return nc;
}

/* The task planned cold at 8 knots in the knot transcription (NULL, reported, when it fails). */
static ea_planner_t *plan8(ea_task_t *t, const char *name, const char *what) {
  ea_error_t e = {0};
  ea_planner_t *pl = NULL;
  ea_plan_info_t info;
  t->knots = 8;
  t->solver.transcription = EA_TASK_TRANSCRIPTION_KNOTS;
  ea_status_t st = ea_task_check(t, &e);
  if (!st) st = ea_planner_alloc(t, &pl, &e);
  if (!st) st = ea_planner_solve(pl, EA_PLAN_COLD, NULL, &info, &e);
  char w[240];
  snprintf(w, sizeof w, "%s: 8-knot %s (%.160s)", name, what, st ? e.msg : "ok");
  ea_test_true(!st, w);
  if (st) {
    ea_planner_free(pl);
    return NULL;
  }
  return pl;
}

/* A generic point near the solution: every variable moved by a pseudo-random 1e-4 relative
 * (an LCG: the same point every run). */
static void generic_point(const ea_planner_t *pl, unsigned long long s, double *x) {
  for (int i = 0; i < pl->n; ++i) {
    s = s * 6364136223846793005ULL + 1442695040888963407ULL;
    const double u = (double)(s >> 11) / 9007199254740992.0 * 2.0 - 1.0;
    x[i] = pl->x_sol[i] + 1e-4 * u * fmax(fabs(pl->x_sol[i]), 1e-2);
  }
}

static void check_task(ea_task_t *t, const char *name) {
  ea_planner_t *pl = plan8(t, name, "at-rest plan");
  if (!pl) return;
  char w[240];
  ea_status_t st = EA_OK;
  snprintf(w, sizeof w, "%s: the plan has dynamics and an exact Hessian", name);
  ea_test_true(pl->hpos && pl->K > 0, w);
  if (!pl->hpos || pl->K == 0) {
    ea_planner_free(pl);
    return;
  }
  const int n = pl->n;
  double *x = malloc((size_t)n * sizeof *x), *xx = malloc((size_t)n * sizeof *xx);
  double *lam = calloc((size_t)pl->m, sizeof *lam);
  double *values = malloc((size_t)(pl->nnz_h + 1) * sizeof *values);
  if (!x || !xx || !lam || !values) {
    ea_test_true(0, "allocation");
    goto out;
  }
  generic_point(pl, 12345, x);
  memcpy(xx, x, (size_t)n * sizeof *x);
  int nrows = 0, kinds[EA__ROW_DYN_TERMINAL + 1] = {0};
  double worst = 0.0, worst_affine = 0.0, worst_sym = 0.0, worst_tt = 0.0, worst_vg = 0.0;
  int worst_row = -1;
  for (int r = 0; r < pl->m; ++r) {
    const ea__row_t *row = &pl->rows[r];
    if (!is_dyn(row->kind)) continue;
    int cols[EA__ROW_MAX];
    double R[EA__ROW_MAX][EA__ROW_MAX], big;
    const int nc = reference(pl, row, x, xx, cols, R, &big);
    /* the row at x by its dual numbers (the differences above left its cache elsewhere) */
    double v1, g1[EA__ROW_MAX], v2, g2[EA__ROW_MAX];
    ea__plan_row_eval(pl, x, row, &v1, NULL, g1);
    /* the planner's, for this row alone */
    lam[r] = 1.0;
    st = ea__plan_hess_values(pl, x, 0.0, lam, values);
    lam[r] = 0.0;
    if (st) {
      ea_test_true(0, "ea__plan_hess_values");
      goto out;
    }
    /* a defect's value and gradient as the Hessian's closed form leaves them in its cache */
    ea__plan_row_eval(pl, x, row, &v2, NULL, g2);
    double gbig = fabs(v1);
    for (int b = 0; b < nc; ++b)
      gbig = fmax(gbig, fabs(g1[b]));
    worst_vg = fmax(worst_vg, fabs(v2 - v1) / fmax(gbig, 1e-300));
    for (int b = 0; b < nc; ++b)
      worst_vg = fmax(worst_vg, fabs(g2[b] - g1[b]) / fmax(gbig, 1e-300));
    for (int a = 0; a < nc; ++a)
      for (int b = 0; b < nc; ++b) {
        const double ref = 0.5 * (R[a][b] + R[b][a]);
        worst_sym = fmax(worst_sym, fabs(R[a][b] - R[b][a]) / fmax(big, 1e-300));
        if (is_modal(pl, cols[a]) && is_modal(pl, cols[b]) && row->kind != EA__ROW_DYN_DEVIATION &&
            row->kind != EA__ROW_DYN_TERMINAL)
          worst_affine = fmax(worst_affine, fabs(ref) / fmax(big, 1e-300));
        if (b > a) continue;
        /* the planner's entry at (max, min) of the pair */
        const int i = cols[a] > cols[b] ? cols[a] : cols[b],
                  j = cols[a] > cols[b] ? cols[b] : cols[a];
        double got = 0.0;
        for (int q = 0; q < pl->nnz_h; ++q)
          if (pl->hirow[q] == i && pl->hjcol[q] == j) got = values[q];
        const double err = fabs(got - ref) / fmax(big, 1e-300);
        if (row->kind == EA__ROW_DYN_TENSION || row->kind == EA__ROW_DYN_TORQUE)
          worst_tt = fmax(worst_tt, err);
        if (err > worst) {
          worst = err;
          worst_row = r;
        }
      }
    ++nrows;
    ++kinds[row->kind];
  }
  char rn[96] = "-";
  if (worst_row >= 0) ea__plan_row_name(pl, &pl->rows[worst_row], rn, sizeof rn);
  printf("  %s: %d dynamics rows (defects %d, tension %d, torque %d, deviation %d, terminal %d)\n",
         name, nrows, kinds[EA__ROW_DYN_DEF_POS] + kinds[EA__ROW_DYN_DEF_VEL],
         kinds[EA__ROW_DYN_TENSION], kinds[EA__ROW_DYN_TORQUE], kinds[EA__ROW_DYN_DEVIATION],
         kinds[EA__ROW_DYN_TERMINAL]);
  printf("  %s: worst entry %.2e of the row's largest (%s); tension and torque rows (closed "
         "form) %.2e; reference asymmetry %.1e; modal-modal %.1e\n",
         name, worst, rn, worst_tt, worst_sym, worst_affine);
  snprintf(w, sizeof w, "%s: every dynamics row's Hessian within %.0e (worst %.2e, %s)", name,
           HESS_TOL, worst, rn);
  ea_test_true(nrows > 0 && worst <= HESS_TOL, w);
  snprintf(w, sizeof w,
           "%s: every dynamics row's value and gradient after the Hessian (the defects' from its "
           "closed form) as its dual numbers give them: within %.1e (1e-12)",
           name, worst_vg);
  ea_test_true(worst_vg <= 1e-12, w);
  snprintf(w, sizeof w, "%s: defects, tension and torque affine in the modal states (%.1e)", name,
           worst_affine);
  ea_test_true(worst_affine <= AFFINE_TOL, w);
out:
  free(x);
  free(xx);
  free(lam);
  free(values);
  ea_planner_free(pl);
}

static int is_kin(int kind) {
  return kind == EA__ROW_ACC_START || kind == EA__ROW_ACC_END || kind == EA__ROW_ACC_CONT ||
         kind == EA__ROW_SPEED_CTRL || kind == EA__ROW_OBJ_ACC || kind == EA__ROW_OBJ_JERK;
}

/* The closed-form Hessians of the kinematic rows and objective pieces (ea__plan_row_hess,
 * what ea__plan_hess_fd_local hands the Hessian for them) against the same Richardson
 * reference, at a generic point near an 8-knot plan's solution. */
static void check_kin(ea_task_t *t, const char *name) {
  ea_planner_t *pl = plan8(t, name, "plan");
  if (!pl) return;
  char w[240];
  const int n = pl->n;
  double *x = malloc((size_t)n * sizeof *x), *xx = malloc((size_t)n * sizeof *xx);
  if (!x || !xx) {
    ea_test_true(0, "allocation");
    free(x);
    free(xx);
    ea_planner_free(pl);
    return;
  }
  generic_point(pl, 54321, x);
  memcpy(xx, x, (size_t)n * sizeof *x);
  int nrows = 0, kinds[EA__ROW_KIND_COUNT] = {0};
  double worst = 0.0;
  int worst_kind = -1, misplaced = 0;
  for (int r = 0; r < pl->m + pl->n_orows; ++r) {
    const ea__row_t *row = r < pl->m ? &pl->rows[r] : &pl->orows[r - pl->m];
    if (!is_kin(row->kind)) continue;
    int cols[EA__ROW_MAX];
    double R[EA__ROW_MAX][EA__ROW_MAX], big;
    const int nc = reference(pl, row, x, xx, cols, R, &big);
    int hc[1][EA__ROW_MAX], hn[1];
    double Hl[1][EA__ROW_MAX][EA__ROW_MAX];
    const double one = 1.0;
    ea__plan_hess_fd_local(pl, ea__plan_row_eval, x, xx, row, &one, 1, hc, hn, Hl, NULL);
    int same = hn[0] == nc;
    for (int a = 0; a < nc && same; ++a)
      same = hc[0][a] == cols[a];
    if (!same) {
      ++misplaced;
      continue;
    }
    for (int a = 0; a < nc; ++a)
      for (int b = 0; b < nc; ++b) {
        const double err = fabs(Hl[0][a][b] - 0.5 * (R[a][b] + R[b][a])) / fmax(big, 1e-300);
        if (err > worst) worst = err, worst_kind = row->kind;
      }
    ++nrows;
    ++kinds[row->kind];
  }
  printf("  %s: %d kinematic rows and objective pieces (acceleration %d, continuity %d, speed "
         "%d, effort %d, jerk %d); worst entry %.2e of the row's largest (kind %d)\n",
         name, nrows, kinds[EA__ROW_ACC_START] + kinds[EA__ROW_ACC_END], kinds[EA__ROW_ACC_CONT],
         kinds[EA__ROW_SPEED_CTRL], kinds[EA__ROW_OBJ_ACC], kinds[EA__ROW_OBJ_JERK], worst,
         worst_kind);
  snprintf(w, sizeof w,
           "%s: closed-form Hessians of %d kinematic rows within %.0e (worst %.2e), %d with "
           "other entries than the row's",
           name, nrows, KIN_TOL, worst, misplaced);
  ea_test_true(nrows > 0 && worst <= KIN_TOL && !misplaced, w);
  free(x);
  free(xx);
  ea_planner_free(pl);
}

/* The Lagrangian gradient of the path layout at xs, sum_r lambda_r grad row_r, into G (n). */
static void pp_lagrangian_grad(ea_planner_t *pl, const double *xs, int n, int m, const double *lam,
                               double *G) {
  memset(G, 0, (size_t)n * sizeof *G);
  int cols[EA__ROW_MAX];
  double v, g[EA__ROW_MAX];
  for (int r = 0; r < m; ++r) {
    const int nc = ea__pp_test_row(pl, xs, r, &v, cols, g);
    for (int a = 0; a < nc; ++a)
      G[cols[a]] += lam[r] * g[a];
  }
}

/* The path transcription with dynamics (plan_path.c): its Hessian is the modal defects' in the
 * path variables directly (ea__plan_dyn_defect_hess_pp), every other row's the knot row's
 * through the chain rule. The whole Lagrangian Hessian
 * (pseudo-random multipliers in [-1, 1] on every row, no objective) at a generic point near
 * the 8-knot plan's solution against central differences of the Lagrangian's exact gradient
 * (every path row's ea__pp_row), Richardson-extrapolated from steps h and h/2 (h = 1e-4
 * relative); each entry against the largest reference entry of its Hessian row. */
static void check_path(ea_task_t *t, const char *name) {
  t->knots = 8;
  t->solver.transcription = EA_TASK_TRANSCRIPTION_PATH;
  ea_error_t e = {0};
  ea_planner_t *pl = NULL;
  ea_plan_info_t info;
  ea_status_t st = ea_task_check(t, &e);
  if (!st) st = ea_planner_alloc(t, &pl, &e);
  if (!st) st = ea_planner_solve(pl, EA_PLAN_COLD, NULL, &info, &e);
  int n = 0, m = 0, nnz = 0;
  const double *xsol = NULL;
  const int *hr = NULL, *hc = NULL;
  char w[300];
  snprintf(w, sizeof w, "%s: 8-knot plan in the path transcription with dynamics (%.160s)", name,
           st ? e.msg : "ok");
  ea_test_true(!st && !ea__pp_test_dims(pl, &n, &m, &xsol, &nnz, &hr, &hc) && pl->K > 0, w);
  if (st || !n) {
    ea_planner_free(pl);
    return;
  }
  double *xs = malloc((size_t)n * sizeof *xs), *lam = malloc((size_t)m * sizeof *lam);
  double *vals = malloc((size_t)(nnz + 1) * sizeof *vals);
  double *H = calloc((size_t)n * n, sizeof *H), *R = calloc((size_t)n * n, sizeof *R);
  double *Gp = malloc((size_t)n * sizeof *Gp), *Gm = malloc((size_t)n * sizeof *Gm);
  if (!xs || !lam || !vals || !H || !R || !Gp || !Gm) {
    ea_test_true(0, "allocation");
    goto out;
  }
  unsigned long long sd = 777;
  for (int i = 0; i < n; ++i) {
    sd = sd * 6364136223846793005ULL + 1442695040888963407ULL;
    const double u = (double)(sd >> 11) / 9007199254740992.0 * 2.0 - 1.0;
    xs[i] = xsol[i] + 1e-4 * u * fmax(fabs(xsol[i]), 1e-2);
  }
  for (int r = 0; r < m; ++r) {
    sd = sd * 6364136223846793005ULL + 1442695040888963407ULL;
    lam[r] = (double)(sd >> 11) / 9007199254740992.0 * 2.0 - 1.0;
  }
  ea__pp_test_hess(pl, xs, 0.0, lam, vals);
  {
    /* the defects' values and gradients the Hessian kept in the path layout
     * (ea__plan_dyn_defect_hess_pp) against the knot layout's through the chain rule (what
     * the rows give once they are forgotten); each row against its largest entry */
    int cols[2][EA__ROW_MAX], nc[2];
    double v[2], g[2][EA__ROW_MAX];
    double gap = 0.0;
    int same_cols = 1;
    for (int r = 0; r < m; ++r) {
      nc[0] = ea__pp_test_row(pl, xs, r, &v[0], cols[0], g[0]);
      ea__plan_dyn_pp_forget(pl);
      nc[1] = ea__pp_test_row(pl, xs, r, &v[1], cols[1], g[1]);
      ea__pp_test_hess(pl, xs, 0.0, lam, vals); /* kept again for the next row */
      same_cols =
          same_cols && nc[0] == nc[1] && !memcmp(cols[0], cols[1], sizeof(int) * (size_t)nc[0]);
      double big = fabs(v[1]);
      for (int a = 0; a < nc[1]; ++a)
        big = fmax(big, fabs(g[1][a]));
      double d = fabs(v[0] - v[1]);
      for (int a = 0; a < nc[0] && a < nc[1]; ++a)
        d = fmax(d, fabs(g[0][a] - g[1][a]));
      gap = fmax(gap, d / fmax(big, 1e-300));
    }
    printf("  %s: path-layout defects (direct %d) against the knot layout's: %.2e of the row's "
           "largest entry\n",
           name, ea__pp_test_direct(pl), gap);
    snprintf(w, sizeof w,
             "%s: the defects' values and gradients kept in the path layout equal the knot "
             "layout's through the chain rule (1e-12 of the row's largest entry)",
             name);
    ea_test_true(ea__pp_test_direct(pl) && same_cols && gap <= 1e-12, w);
  }
  for (int q = 0; q < nnz; ++q) {
    H[(size_t)hr[q] * n + hc[q]] += vals[q];
    if (hr[q] != hc[q]) H[(size_t)hc[q] * n + hr[q]] += vals[q];
  }
  for (int v = 0; v < n; ++v) {
    const double h0 = 1e-4 * fmax(1.0, fabs(xs[v])), x0 = xs[v];
    double D[2][EA__PATH_TEST_MAXN];
    for (int s2 = 0; s2 < 2; ++s2) {
      const double h = s2 ? 0.5 * h0 : h0;
      xs[v] = x0 + h;
      pp_lagrangian_grad(pl, xs, n, m, lam, Gp);
      xs[v] = x0 - h;
      pp_lagrangian_grad(pl, xs, n, m, lam, Gm);
      xs[v] = x0;
      for (int b = 0; b < n && b < EA__PATH_TEST_MAXN; ++b)
        D[s2][b] = (Gp[b] - Gm[b]) / (2.0 * h);
    }
    for (int b = 0; b < n && b < EA__PATH_TEST_MAXN; ++b)
      R[(size_t)v * n + b] = (4.0 * D[1][b] - D[0][b]) / 3.0;
  }
  pp_lagrangian_grad(pl, xs, n, m, lam, Gp); /* the rows' expansion back at xs */
  double worst = 0.0, biggest = 0.0;
  int wi = -1, wj = -1, nonzero = 0;
  for (int i = 0; i < n; ++i) {
    double big = 0.0;
    for (int j = 0; j < n; ++j)
      big = fmax(big, fabs(0.5 * (R[(size_t)i * n + j] + R[(size_t)j * n + i])));
    biggest = fmax(biggest, big);
    for (int j = 0; j < n; ++j) {
      const double ref = 0.5 * (R[(size_t)i * n + j] + R[(size_t)j * n + i]);
      const double err = fabs(H[(size_t)i * n + j] - ref) / fmax(big, 1e-300);
      nonzero += H[(size_t)i * n + j] != 0.0;
      if (big > 0 && err > worst) worst = err, wi = i, wj = j;
    }
  }
  printf("  %s: path layout %d variables, %d rows, %d Hessian entries (%d nonzero in the full "
         "matrix); worst entry %.2e of its Hessian row's largest reference entry (%d, %d), largest "
         "entry %.3g\n",
         name, n, m, nnz, nonzero, worst, wi, wj, biggest);
  snprintf(w, sizeof w,
           "%s: the path transcription's Lagrangian Hessian within %.0e of the differences of its "
           "gradient (worst %.2e)",
           name, PATH_TOL, worst);
  ea_test_true(n <= EA__PATH_TEST_MAXN && nonzero > 0 && worst <= PATH_TOL, w);
out:
  free(xs);
  free(lam);
  free(vals);
  free(H);
  free(R);
  free(Gp);
  free(Gm);
  ea_planner_free(pl);
}

int main(void) {
  gsl_set_error_handler_off();
  src = getenv("EA_SOURCE_DIR");
  if (!src) {
    printf("EA_SOURCE_DIR not set (run through ctest)\n");
    return EXIT_FAILURE;
  }
  ea_task_t t;
  if (!ea_test_load_example(src, "paper-line-rest.yaml", &t)) {
    t.payload_factor = 0.25;
    t.payload_kg = ea_arm_payload_from_factor(&t.arm, 0.25);
    t.dynamics.residual_m = 1e-3;
    t.dynamics.max_tip_deviation_m = 2e-3;
    check_task(&t, "paper line, payload 0.25, 2 modes");
    /* damped modes (arm-file damping.modal_ratios): the c = 2 zeta omega terms */
    t.arm.n_damping = 2;
    t.arm.damping_ratio[0] = 0.02;
    t.arm.damping_ratio[1] = 0.05;
    check_task(&t, "paper line, payload 0.25, 2 modes, damped 2 % and 5 %");
  } else {
    ea_test_true(0, "paper-line-rest.yaml");
  }
  if (!ea_test_load_example(src, "paper-line-rest.yaml", &t)) check_kin(&t, "paper line at rest");
  if (!ea_test_load_example(src, "paper-line-rest.yaml", &t)) {
    t.arm.n_damping = 2;
    t.arm.damping_ratio[0] = 0.02;
    t.arm.damping_ratio[1] = 0.05;
    check_path(&t, "paper line at rest, damped 2 % and 5 %");
  }
  if (!ea_test_load_example(src, "polyline-effort.yaml", &t)) {
    check_kin(&t, "polyline-effort (min_effort)");
    t.objective = EA_TASK_MIN_JERK;
    check_kin(&t, "polyline-effort (min_jerk)");
  }
  if (!ea_test_load_example(src, "paper-line-robust.yaml", &t))
    check_task(&t, "robust paper line");
  else
    ea_test_true(0, "paper-line-robust.yaml");
  return ea_test_summary("test_plan_hess");
}
