/* The general statics problem g*(alpha, T, theta0, kappa0) = 0 (eq. 14-16).
 *
 * Unknowns: always p = (alpha, T, theta0, kappa0). Equations:
 *   r0 = kappa(L)                                    (no tip moment)
 *   r1 = (y_L - y_c) cos(alpha) - (x_L - x_c) sin(alpha)  (tip on the cable ray)
 *   r2, r3 = the two given quantities minus their values.
 * Damped Newton with the exact Jacobian from the variational equations; when
 * a direct solve fails, or no guess is given, the solution is reached by
 * continuation from the T = 0 outer edge of the same cable angle, itself
 * reached from the straight, weightless beam by ramping gravity: the arm's
 * physical branch. */
#include "statics_impl.h"

#include <gsl/gsl_linalg.h>
#include <math.h>
#include <string.h>

void ea_statics_settings_default(ea_statics_settings_t *s) {
  s->tol = 1e-10;
  s->max_iter = 30;
  s->max_cont_steps = 400;
  s->allow_negative_tension = 0;
}

static ea_statics_problem_t ea__prob2(ea_given_t a, double va, ea_given_t b, double vb) {
  ea_statics_problem_t p;
  p.given[0] = a;
  p.given[1] = b;
  p.value[0] = va;
  p.value[1] = vb;
  return p;
}

ea_statics_problem_t ea_statics_problem_cable(double cable_length, double alpha) {
  return ea__prob2(EA_GIVEN_CABLE_LENGTH, cable_length, EA_GIVEN_ALPHA, alpha);
}
ea_statics_problem_t ea_statics_problem_tip(double x, double y) {
  return ea__prob2(EA_GIVEN_TIP_X, x, EA_GIVEN_TIP_Y, y);
}
ea_statics_problem_t ea_statics_problem_tension_theta0(double T, double theta0) {
  return ea__prob2(EA_GIVEN_TENSION, T, EA_GIVEN_THETA0, theta0);
}
ea_statics_problem_t ea_statics_problem_tension_alpha(double T, double alpha) {
  return ea__prob2(EA_GIVEN_TENSION, T, EA_GIVEN_ALPHA, alpha);
}

/* Value of a given quantity at (p, xL) and its gradient wrt p. */
static double ea__given_value(const ea_arm_t *arm, ea_given_t g, const double p[EA_NP],
                              const double xL[EA_NX], const double *dxdp, double grad[EA_NP]) {
  const double ca = cos(p[EA_P_ALPHA]), sa = sin(p[EA_P_ALPHA]);
  const double dx = xL[EA_X_X] - arm->x_c, dy = xL[EA_X_Y] - arm->y_c;
  if (grad) memset(grad, 0, EA_NP * sizeof *grad);
  switch (g) {
  case EA_GIVEN_ALPHA:
    if (grad) grad[EA_P_ALPHA] = 1.0;
    return p[EA_P_ALPHA];
  case EA_GIVEN_TENSION:
    if (grad) grad[EA_P_TENSION] = 1.0;
    return p[EA_P_TENSION];
  case EA_GIVEN_THETA0:
    if (grad) grad[EA_P_THETA0] = 1.0;
    return p[EA_P_THETA0];
  case EA_GIVEN_KAPPA0:
    if (grad) grad[EA_P_KAPPA0] = 1.0;
    return p[EA_P_KAPPA0];
  case EA_GIVEN_CABLE_LENGTH:
    if (grad && dxdp) {
      for (int j = 0; j < EA_NP; ++j)
        grad[j] = dxdp[EA_X_X * EA_NP + j] * ca + dxdp[EA_X_Y * EA_NP + j] * sa;
      grad[EA_P_ALPHA] += -dx * sa + dy * ca;
    }
    return dx * ca + dy * sa;
  case EA_GIVEN_TIP_X:
    if (grad && dxdp)
      for (int j = 0; j < EA_NP; ++j)
        grad[j] = dxdp[EA_X_X * EA_NP + j];
    return xL[EA_X_X];
  case EA_GIVEN_TIP_Y:
    if (grad && dxdp)
      for (int j = 0; j < EA_NP; ++j)
        grad[j] = dxdp[EA_X_Y * EA_NP + j];
    return xL[EA_X_Y];
  default:
    return NAN;
  }
}

/* The parameter a given quantity fixes directly, or -1. */
static int ea__direct_param(ea_given_t g) {
  switch (g) {
  case EA_GIVEN_ALPHA:
    return EA_P_ALPHA;
  case EA_GIVEN_TENSION:
    return EA_P_TENSION;
  case EA_GIVEN_THETA0:
    return EA_P_THETA0;
  case EA_GIVEN_KAPPA0:
    return EA_P_KAPPA0;
  default:
    return -1;
  }
}

/* Put directly given parameters at their values (Newton's first step would). */
static void ea__project(const ea_given_t given[2], const double v[2], double p[EA_NP]) {
  for (int k = 0; k < 2; ++k) {
    const int j = ea__direct_param(given[k]);
    if (j >= 0) p[j] = v[k];
  }
}

/* Residual with target values v[2] (continuation moves them). */
static ea_status_t ea__residual(ea_shooter_t *sh, const ea_given_t given[2], const double v[2],
                                const double p[EA_NP], double r[4], double *J,
                                double xL_out[EA_NX]) {
  double xL[EA_NX], S[EA_NX * EA_NP];
  /* Parameters fixed directly by a given quantity need no sensitivity
   * column: Newton keeps them at their values (see ea__project). */
  unsigned mask = (1u << EA_NP) - 1u;
  for (int k = 0; k < 2; ++k) {
    const int j = ea__direct_param(given[k]);
    if (j >= 0 && p[j] == v[k]) mask &= ~(1u << j);
  }
  ea_status_t st = ea__shoot_cols(sh, p, xL, J ? S : NULL, mask);
  if (st) return st;
  const ea_arm_t *arm = &sh->arm;
  const double ca = cos(p[EA_P_ALPHA]), sa = sin(p[EA_P_ALPHA]);
  const double dx = xL[EA_X_X] - arm->x_c, dy = xL[EA_X_Y] - arm->y_c;
  r[0] = xL[EA_X_KAPPA];
  r[1] = dy * ca - dx * sa;
  if (J) {
    for (int j = 0; j < EA_NP; ++j) {
      J[0 * 4 + j] = S[EA_X_KAPPA * EA_NP + j];
      J[1 * 4 + j] = S[EA_X_Y * EA_NP + j] * ca - S[EA_X_X * EA_NP + j] * sa;
    }
    J[1 * 4 + EA_P_ALPHA] += -dy * sa - dx * ca;
  }
  for (int k = 0; k < 2; ++k)
    r[2 + k] =
        ea__given_value(arm, given[k], p, xL, J ? S : NULL, J ? J + (2 + k) * 4 : NULL) - v[k];
  if (xL_out) memcpy(xL_out, xL, sizeof xL);
  return EA_OK;
}

ea_status_t ea_statics_residual(ea_shooter_t *sh, const ea_statics_problem_t *prob,
                                const double p[EA_NP], double r[4], double *J) {
  if (!sh || !prob || !p || !r) return EA_ERR_ARG;
  return ea__residual(sh, prob->given, prob->value, p, r, J, NULL);
}

static double ea__norm(const double r[4]) {
  double m = 0.0;
  for (int i = 0; i < 4; ++i)
    m = fmax(m, fabs(r[i]));
  return m;
}

/* Damped Newton from p (in/out). Returns EA_OK on convergence. */
/* strict: refuse damped steps. A guess that needs damping is far from the
 * solution, and an undamped Newton run from it is how solutions jump to
 * another branch; callers then fall back to continuation. */
static ea_status_t ea__newton(ea_shooter_t *sh, const ea_given_t given[2], const double v[2],
                              double p[EA_NP], double tol, int max_iter, int strict, int *iters,
                              double *res_out) {
  double r[4], J[16], Jt[16], dz[4], pt[EA_NP], rt[4];
  gsl_permutation *perm = sh->perm;
  double nr_prev = INFINITY;
  ea__project(given, v, p);
  ea_status_t st = ea__residual(sh, given, v, p, r, J, NULL);
  double nr = st ? INFINITY : ea__norm(r);
  int it = 0;
  ea_status_t out = EA_ERR_MAXITER;
  if (st) {
    out = st;
    goto done;
  }
  for (;;) {
    if (nr <= tol) {
      out = EA_OK;
      break;
    }
    if (it >= max_iter) break;
    ++it;
    gsl_matrix_view Jm = gsl_matrix_view_array(J, 4, 4);
    gsl_vector_view rv = gsl_vector_view_array(r, 4);
    gsl_vector_view dv = gsl_vector_view_array(dz, 4);
    int sgn;
    if (gsl_linalg_LU_decomp(&Jm.matrix, perm, &sgn) != GSL_SUCCESS ||
        fabs(gsl_linalg_LU_det(&Jm.matrix, sgn)) < 1e-300 ||
        gsl_linalg_LU_solve(&Jm.matrix, perm, &rv.vector, &dv.vector) != GSL_SUCCESS) {
      out = EA_ERR_SINGULAR;
      break;
    }
    /* Limit the angular part of the step: Newton far away overshoots. */
    double lam = 1.0;
    const double amax = fmax(fabs(dz[EA_P_ALPHA]), fabs(dz[EA_P_THETA0]));
    if (amax > 0.5) lam = 0.5 / amax;
    /* Backtracking; the full step is tried with the sensitivities, since it
     * is accepted almost always and then needs no second integration. */
    /* When quadratic convergence predicts the full step ends below tol, it
     * is tried without them. */
    const int last = (isfinite(nr_prev) && nr < nr_prev && (nr / nr_prev) * nr < 0.1 * tol) ||
                     nr * nr < 1e-2 * tol;
    int accepted = 0;
    for (int k = 0; k < 12; ++k) {
      for (int j = 0; j < EA_NP; ++j)
        pt[j] = p[j] - lam * dz[j];
      if (ea__residual(sh, given, v, pt, rt, (k == 0 && !last) ? Jt : NULL, NULL) == EA_OK) {
        const double nt = ea__norm(rt);
        if (nt < (1.0 - 1e-4 * lam) * nr || nt <= tol) {
          accepted = k + 1;
          break;
        }
      }
      lam *= 0.5;
    }
    if (!accepted || (strict && (accepted > 1 || amax > 0.5))) {
      out = EA_ERR_NOCONV;
      break;
    }
    memcpy(p, pt, sizeof pt);
    memcpy(r, rt, sizeof rt);
    nr_prev = nr;
    if (ea__norm(r) <= tol) {
      nr = ea__norm(r);
      continue; /* converged: no Jacobian needed */
    }
    if (accepted == 1 && !last) {
      memcpy(J, Jt, sizeof Jt);
    } else if ((st = ea__residual(sh, given, v, p, r, J, NULL))) {
      out = st;
      break;
    }
    nr = ea__norm(r);
  }
done:
  if (iters) *iters += it;
  if (res_out) *res_out = nr;
  return out;
}

/* Straight, weightless beam with its tip on the ray at alpha: the start of
 * the gravity continuation. */
static void ea__straight_start(const ea_arm_t *arm, double alpha, double p[EA_NP]) {
  double q = (arm->y_c * cos(alpha) - arm->x_c * sin(alpha)) / arm->length;
  q = fmax(-1.0, fmin(1.0, q));
  p[EA_P_ALPHA] = alpha;
  p[EA_P_TENSION] = 0.0;
  p[EA_P_THETA0] = alpha + asin(q);
  p[EA_P_KAPPA0] = 0.0;
}

/* Continuation of a parameter lambda from 0 to 1; set(lambda) updates the
 * problem, p is the solution at lambda = 0 on entry. Secant predictor,
 * adaptive step. */
typedef void (*ea__homotopy_fn)(ea_shooter_t *sh, double lam, void *ctx, double v[2]);

static ea_status_t ea__continue(ea_shooter_t *sh, const ea_given_t given[2], ea__homotopy_fn fn,
                                void *ctx, double p[EA_NP], const ea_statics_settings_t *s,
                                int stop_negative_tension, int *iters, int *steps, double *res) {
  double lam = 0.0, dl = 0.25, pprev[EA_NP], lprev = -1.0;
  double v[2];
  memcpy(pprev, p, sizeof pprev);
  while (lam < 1.0) {
    if (*steps >= s->max_cont_steps || dl < 1e-7) return EA_ERR_NOCONV;
    const double lt = fmin(1.0, lam + dl);
    double pt[EA_NP];
    memcpy(pt, p, sizeof pt);
    if (lprev >= 0.0 && lam > lprev) { /* secant predictor */
      const double f = (lt - lam) / (lam - lprev);
      for (int j = 0; j < EA_NP; ++j)
        pt[j] = p[j] + f * (p[j] - pprev[j]);
    }
    fn(sh, lt, ctx, v);
    ++*steps;
    int it = 0;
    ea_status_t st = ea__newton(sh, given, v, pt, s->tol, 12, 1, &it, res);
    *iters += it;
    if (st == EA_OK) {
      memcpy(pprev, p, sizeof pprev);
      memcpy(p, pt, sizeof pt);
      lprev = lam;
      lam = lt;
      if (it <= 4) dl *= 1.6;
      /* Continuation from the T = 0 edge that makes T negative has left the
       * workspace: the target is outside it, no need to go on. */
      if (stop_negative_tension && p[EA_P_TENSION] < -1e-9) return EA_ERR_INADMISSIBLE;
    } else {
      dl *= 0.4;
    }
  }
  return EA_OK;
}

struct ea__lin_ctx {
  double v0[2], v1[2];
};
static void ea__lin_fn(ea_shooter_t *sh, double lam, void *ctx, double v[2]) {
  (void)sh;
  const struct ea__lin_ctx *c = ctx;
  v[0] = (1.0 - lam) * c->v0[0] + lam * c->v1[0];
  v[1] = (1.0 - lam) * c->v0[1] + lam * c->v1[1];
}
struct ea__grav_ctx {
  double v[2];
};
static void ea__grav_fn(ea_shooter_t *sh, double lam, void *ctx, double v[2]) {
  const struct ea__grav_ctx *c = ctx;
  ea__shooter_set_gscale(sh, lam);
  v[0] = c->v[0];
  v[1] = c->v[1];
}

static void ea__fill_solution(ea_shooter_t *sh, const ea_statics_problem_t *prob,
                              const double p[EA_NP], ea_statics_solution_t *sol) {
  const ea_arm_t *arm = &sh->arm;
  double r[4];
  memcpy(sol->p, p, sizeof sol->p);
  ea__residual(sh, prob->given, prob->value, p, r, NULL, sol->tip);
  sol->residual = ea__norm(r);
  const double dx = sol->tip[EA_X_X] - arm->x_c, dy = sol->tip[EA_X_Y] - arm->y_c;
  sol->cable_length = dx * cos(p[EA_P_ALPHA]) + dy * sin(p[EA_P_ALPHA]);
  sol->shoulder_torque = arm->EI * p[EA_P_KAPPA0];
  sol->winding = sol->tip[EA_X_THETA] - p[EA_P_THETA0];
}

static ea_status_t ea__validate_problem(const ea_statics_problem_t *prob, ea_error_t *err) {
  for (int k = 0; k < 2; ++k) {
    if ((int)prob->given[k] < 0 || prob->given[k] >= EA_GIVEN_COUNT)
      return ea_error_set(err, EA_ERR_ARG, "given quantity %d is unknown", (int)prob->given[k]);
    if (!isfinite(prob->value[k]))
      return ea_error_set(err, EA_ERR_ARG, "given value %d is not finite", k);
  }
  if (prob->given[0] == prob->given[1])
    return ea_error_set(err, EA_ERR_ARG, "the two given quantities are the same");
  return EA_OK;
}

/* Cable angle to start the edge continuation from. */
static double ea__start_alpha(const ea_arm_t *arm, const ea_statics_problem_t *prob) {
  double tx = NAN, ty = NAN;
  for (int k = 0; k < 2; ++k) {
    if (prob->given[k] == EA_GIVEN_ALPHA) return prob->value[k];
    if (prob->given[k] == EA_GIVEN_TIP_X) tx = prob->value[k];
    if (prob->given[k] == EA_GIVEN_TIP_Y) ty = prob->value[k];
  }
  if (isfinite(tx) && isfinite(ty)) return atan2(ty - arm->y_c, tx - arm->x_c);
  return -20.0 * M_PI / 180.0;
}

ea_status_t ea_statics_solve(ea_shooter_t *sh, const ea_statics_problem_t *prob,
                             const ea_statics_settings_t *s, const double *guess,
                             ea_statics_solution_t *sol, ea_error_t *err) {
  if (!sh || !prob || !sol) return ea_error_set(err, EA_ERR_ARG, "ea_statics_solve: NULL argument");
  memset(sol, 0, sizeof *sol);
  sol->status = EA_ERR_NOCONV;
  ea_statics_settings_t set;
  if (s)
    set = *s;
  else
    ea_statics_settings_default(&set);
  ea_status_t st = ea__validate_problem(prob, err);
  if (st) return sol->status = st;
  ea__shooter_set_gscale(sh, 1.0);

  double p[EA_NP];
  int iters = 0, steps = 0;
  double res = INFINITY;
  st = EA_ERR_NOCONV;
  if (guess) {
    memcpy(p, guess, sizeof p);
    st = ea__newton(sh, prob->given, prob->value, p, set.tol, set.max_iter < 8 ? set.max_iter : 8,
                    1, &iters, &res);
    if (st == EA_OK) sol->branch = EA_BRANCH_WARM;
  }
  if (st != EA_OK) {
    /* 1. Edge point at the start angle: gravity continuation, T = 0. */
    const double a0 = ea__start_alpha(&sh->arm, prob);
    const ea_given_t eg[2] = {EA_GIVEN_TENSION, EA_GIVEN_ALPHA};
    struct ea__grav_ctx gc = {{0.0, a0}};
    ea__straight_start(&sh->arm, a0, p);
    st = ea__continue(sh, eg, ea__grav_fn, &gc, p, &set, 0, &iters, &steps, &res);
    ea__shooter_set_gscale(sh, 1.0);
    /* 2. From the edge to the requested values of the given quantities. */
    if (st == EA_OK) {
      double xL[EA_NX], r[4];
      struct ea__lin_ctx lc;
      st = ea__residual(sh, prob->given, prob->value, p, r, NULL, xL);
      if (st == EA_OK) {
        for (int k = 0; k < 2; ++k) {
          lc.v0[k] = ea__given_value(&sh->arm, prob->given[k], p, xL, NULL, NULL);
          lc.v1[k] = prob->value[k];
        }
        st = ea__continue(sh, prob->given, ea__lin_fn, &lc, p, &set, !set.allow_negative_tension,
                          &iters, &steps, &res);
        if (st == EA_OK) /* polish at the exact values */
          st = ea__newton(sh, prob->given, prob->value, p, set.tol, set.max_iter, 0, &iters, &res);
      }
    }
    if (st == EA_OK) sol->branch = EA_BRANCH_EDGE;
  }
  sol->iterations = iters;
  sol->cont_steps = steps;
  if (st != EA_OK) {
    sol->status = st == EA_ERR_MAXITER ? EA_ERR_NOCONV : st;
    memcpy(sol->p, p, sizeof sol->p);
    sol->residual = res;
    sol->branch = EA_BRANCH_NONE;
    if (st == EA_ERR_INADMISSIBLE)
      return ea_error_set(err, st,
                          "no admissible configuration: continuing from the T = 0 outer edge "
                          "toward the request makes the tension negative (T = %.4g N), so it "
                          "lies outside the workspace for this load",
                          p[EA_P_TENSION]);
    return ea_error_set(err, sol->status,
                        "statics did not converge (%s; residual %.3g after %d iterations, %d "
                        "continuation steps)",
                        ea_strerror(st), res, iters, steps);
  }
  ea__fill_solution(sh, prob, p, sol);
  if (!(sol->cable_length > 0.0)) {
    sol->status = EA_ERR_INADMISSIBLE;
    return ea_error_set(err, EA_ERR_INADMISSIBLE,
                        "the tip lies behind the cable root (cable length %.6g m)",
                        sol->cable_length);
  }
  if (!set.allow_negative_tension && sol->p[EA_P_TENSION] < 0.0) {
    sol->status = EA_ERR_INADMISSIBLE;
    return ea_error_set(err, EA_ERR_INADMISSIBLE,
                        "cable tension T = %.6g N < 0: the tip is outside the workspace",
                        sol->p[EA_P_TENSION]);
  }
  sol->status = EA_OK;
  return EA_OK;
}

ea_status_t ea_statics_edge(ea_shooter_t *sh, double alpha, const ea_statics_settings_t *s,
                            const double *guess, ea_statics_solution_t *sol, ea_error_t *err) {
  ea_statics_problem_t prob = ea_statics_problem_tension_alpha(0.0, alpha);
  return ea_statics_solve(sh, &prob, s, guess, sol, err);
}
