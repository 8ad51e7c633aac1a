/* Finite element model: static Newton-Raphson (paper eq. 21-23). */
#include "fe_impl.h"

#include <math.h>
#include <string.h>

/* Largest rotation change [rad] accepted in one Newton step; longer steps are
 * scaled back (a guard for starts far from equilibrium; never active near it). */
#define EA__FE_MAX_DTHETA 0.3

/* Newton-Raphson on the free DOFs of q. With tip != NULL (ACTIVE phase only)
 * the tension *value and theta0 = q[2] are unknowns as well and the tip is
 * held at tip[0..1]: the bordered system [K b_T b_th0; C 0 0] is solved by
 * block elimination with three right-hand sides on the band LU of K. */
static ea_status_t ea__fe_newton_core(ea_fe_model_t *m, double *q, ea_fe_cable_phase_t phase,
                                      double *value, const double *tip, ea_fe_static_info_t *info,
                                      ea_error_t *err) {
  const double t0 = ea__mono_s();
  const int nf = m->nf, tx = nf - 3, ty = nf - 2; /* free indices of the tip x, y */
  ea_status_t st = EA_ERR_MAXITER;
  double eps = INFINITY, gtip = 0.0, eps_prev = INFINITY;
  int it = 0;
  for (;; ++it) {
    ea__fe_assemble(m, q, phase, *value, m->fi, m->Kb);
    double r2 = 0.0;
    for (int i = 0; i < nf; ++i) {
      m->r[i] = m->fi[i + 3];
      r2 += m->r[i] * m->r[i];
    }
    eps = (m->fext_norm > 0.0) ? sqrt(r2) / m->fext_norm : sqrt(r2);
    if (tip) gtip = fmax(fabs(q[tx + 3] - tip[0]), fabs(q[ty + 3] - tip[1]));
    if (!isfinite(eps)) {
      st = EA_ERR_NOCONV;
      break;
    }
    if (eps <= m->set.newton_tol && gtip <= 1e-12 * m->arm.length) {
      st = EA_OK;
      break;
    }
    if (it >= m->set.newton_max_iter) break;
    if ((st = ea__fe_factor_free(m, m->Kb)) != EA_OK) break;
    double *X = m->rhs3, dT = 0.0, dth = 0.0;
    memcpy(X, m->r, sizeof(double) * (size_t)nf);
    int nrhs = 1;
    if (tip) {
      double *b1 = X + nf, *b2 = X + 2 * nf;
      memset(b1, 0, sizeof(double) * 2 * (size_t)nf);
      const double dx = m->arm.x_c - q[tx + 3], dy = m->arm.y_c - q[ty + 3];
      const double l = hypot(dx, dy);
      b1[tx] = -dx / l; /* d r / d T = -e at the tip */
      b1[ty] = -dy / l;
      for (int i = 0; i < nf && i + 3 <= 2 + EA__FE_KD; ++i) /* d r / d theta0 = K(:, 2) */
        b2[i] = m->Kb[(EA__FE_KD + 2 - (i + 3)) + (size_t)(i + 3) * EA__FE_LDS];
      nrhs = 3;
    }
    if ((st = ea__fe_solve_factored(m, X, nrhs)) != EA_OK) break;
    if (tip) {
      /* tip rows of Delta = Xr - Xb1 dT - Xb2 dth must equal tip - target */
      const double *Xr = X, *X1 = X + nf, *X2 = X + 2 * nf;
      const double gx = Xr[tx] - (q[tx + 3] - tip[0]), gy = Xr[ty] - (q[ty + 3] - tip[1]);
      const double a11 = X1[tx], a12 = X2[tx], a21 = X1[ty], a22 = X2[ty];
      const double det = a11 * a22 - a12 * a21;
      if (!(fabs(det) > 0.0)) {
        st = EA_ERR_SINGULAR;
        break;
      }
      dT = (gx * a22 - a12 * gy) / det;
      dth = (a11 * gy - a21 * gx) / det;
      for (int i = 0; i < nf; ++i)
        X[i] -= X1[i] * dT + X2[i] * dth;
    }
    st = EA_ERR_MAXITER;
    double dmax = fabs(dth), xmax = 0.0;
    for (int i = 0; i < nf; ++i) {
      if (i % 3 == 2) dmax = fmax(dmax, fabs(X[i]));
      xmax = fmax(xmax, fabs(X[i]));
    }
    const double sc = (dmax > EA__FE_MAX_DTHETA) ? EA__FE_MAX_DTHETA / dmax : 1.0;
    for (int i = 0; i < nf; ++i)
      q[i + 3] -= sc * X[i];
    if (tip) {
      *value -= sc * dT;
      q[2] -= sc * dth;
    }
    /* rounding-level correction: as converged as EA allows */
    /* stagnation at rounding level: eps no longer falls 10x per step and the
     * correction is below 1e-10 L */
    const int stagnant = it > 0 && eps > 0.1 * eps_prev;
    eps_prev = eps;
    if (stagnant && xmax <= 1e-10 * m->arm.length && fabs(sc * dth) <= 1e-10 &&
        fabs(sc * dT) <= 1e-10 * (1.0 + fabs(*value))) {
      ++it;
      st = EA_OK;
      ea__fe_assemble(m, q, phase, *value, m->fi, NULL);
      r2 = 0.0;
      for (int i = 0; i < nf; ++i)
        r2 += m->fi[i + 3] * m->fi[i + 3];
      eps = (m->fext_norm > 0.0) ? sqrt(r2) / m->fext_norm : sqrt(r2);
      if (tip) gtip = fmax(fabs(q[tx + 3] - tip[0]), fabs(q[ty + 3] - tip[1]));
      if (gtip > 1e-12 * m->arm.length) st = EA_ERR_MAXITER;
      break;
    }
    /* after a large step the positions carry spurious strains (x EA): relax */
    if (dmax * sc > 1e-3) ea__fe_relax_positions(m, q, phase, *value, 1);
  }
  if (info) {
    memset(info, 0, sizeof *info);
    info->status = st;
    info->iterations = it;
    info->residual = eps;
    memcpy(info->tip, q + m->nd - 3, 3 * sizeof(double));
    double T = 0.0, l = 0.0;
    ea__fe_cable(m, phase, *value, q[m->nd - 3], q[m->nd - 2], &T, &l, NULL, NULL);
    info->tension = T;
    info->cable_length = l;
    info->cable_angle = atan2(q[m->nd - 2] - m->arm.y_c, q[m->nd - 3] - m->arm.x_c);
    info->theta0 = q[2];
    info->time_s = ea__mono_s() - t0;
  }
  if (st == EA_ERR_SINGULAR)
    return ea_error_set(err, st, "fe Newton: singular tangent at iteration %d", it);
  if (st == EA_ERR_MAXITER)
    return ea_error_set(err, st, "fe Newton: eps = %g > %g after %d iterations", eps,
                        m->set.newton_tol, it);
  if (st) return ea_error_set(err, st, "fe Newton: failed at iteration %d", it);
  return EA_OK;
}

ea_status_t ea__fe_newton_q(ea_fe_model_t *m, double *q, ea_fe_cable_phase_t phase, double value,
                            ea_fe_static_info_t *info, ea_error_t *err) {
  return ea__fe_newton_core(m, q, phase, &value, NULL, info, err);
}

/* Positions compatible with the rotations: with every theta held, the strains
 * are linear in the positions, and with 2 Gauss points per element the 4 new
 * position DOFs of an element can zero its 4 Gauss-point strains. Newton on
 * the position rows alone (theta rows replaced by identity) therefore makes
 * the ODE shape, whose quadratic interpolation carries strains ~h^2 kappa^2
 * (times EA ~ 1e8 N), into a start with the right axial and shear forces;
 * the full Newton then only corrects the moment balance. */
ea_status_t ea__fe_relax_positions(ea_fe_model_t *m, double *q, ea_fe_cable_phase_t phase,
                                   double value, int iters) {
  for (int it = 0; it < iters; ++it) {
    ea__fe_assemble(m, q, phase, value, m->fi, m->Kb);
    for (int i = 0; i < m->nf; ++i)
      m->r[i] = m->fi[i + 3];
    for (int j = 5; j < m->nd; j += 3) { /* full index of each free theta */
      for (int i = (j > EA__FE_KD ? j - EA__FE_KD : 0); i <= j; ++i)
        m->Kb[(EA__FE_KD + i - j) + (size_t)j * EA__FE_LDS] = 0.0;
      for (int k = j + 1; k <= j + EA__FE_KD && k < m->nd; ++k)
        m->Kb[(EA__FE_KD + j - k) + (size_t)k * EA__FE_LDS] = 0.0;
      m->Kb[EA__FE_KD + (size_t)j * EA__FE_LDS] = 1.0;
      m->r[j - 3] = 0.0;
    }
    ea_status_t st = ea__fe_solve_free(m, m->Kb);
    if (st) return st;
    for (int i = 0; i < m->nf; ++i)
      q[i + 3] -= m->dq[i];
  }
  return EA_OK;
}

ea_status_t ea_fe_relax_positions(ea_fe_model_t *m, ea_error_t *err) {
  if (!m) return ea_error_set(err, EA_ERR_ARG, "fe relax: model is NULL");
  memcpy(m->qs, m->q, sizeof(double) * (size_t)m->nd);
  ea_status_t st = ea__fe_relax_positions(m, m->qs, m->phase, m->cable_value, 2);
  if (st) return ea_error_set(err, st, "fe relax: singular position block");
  memcpy(m->q, m->qs, sizeof(double) * (size_t)m->nd);
  m->modes_valid = 0;
  return EA_OK;
}

ea_status_t ea_fe_newton(ea_fe_model_t *m, ea_fe_static_info_t *info, ea_error_t *err) {
  if (!m) return ea_error_set(err, EA_ERR_ARG, "fe model is NULL");
  memcpy(m->qs, m->q, sizeof(double) * (size_t)m->nd);
  ea_status_t st = ea__fe_newton_q(m, m->qs, m->phase, m->cable_value, info, err);
  if (st == EA_OK) {
    memcpy(m->q, m->qs, sizeof(double) * (size_t)m->nd);
    memset(m->v, 0, sizeof(double) * (size_t)m->nd);
    m->modes_valid = 0;
  }
  return st;
}

ea_status_t ea_fe_static_solve(ea_fe_model_t *m, ea_shooter_t *sh, const ea_statics_solution_t *ode,
                               ea_fe_static_info_t *info, ea_error_t *err) {
  if (!m || !sh || !ode) return ea_error_set(err, EA_ERR_ARG, "fe static: NULL argument");
  for (int i = 0; i < EA_NP; ++i)
    if (!isfinite(ode->p[i]))
      return ea_error_set(err, EA_ERR_ARG, "fe static: ODE solution p[%d] = %g", i, ode->p[i]);
  if (ode->p[EA_P_TENSION] < 0.0)
    return ea_error_set(err, EA_ERR_INADMISSIBLE, "fe static: tension %g < 0",
                        ode->p[EA_P_TENSION]);
  const double t0 = ea__mono_s();
  ea_status_t st = ea_fe_model_set_load(m, ea_shooter_load(sh));
  if (st) return ea_error_set(err, st, "fe static: bad tip mass");
  /* sample the ODE centreline at the nodes (uniform in arclength) */
  const int n = m->nn;
  double *th = m->tmp, *x = m->q0, *y = m->v0;
  st = ea_shoot_shape(sh, ode->p, n, NULL, th, NULL, x, y);
  if (st) return ea_error_set(err, st, "fe static: sampling the ODE shape failed");
  for (int i = 0; i < n; ++i) {
    m->qs[3 * i] = x[i];
    m->qs[3 * i + 1] = y[i];
    m->qs[3 * i + 2] = th[i];
  }
  m->qs[0] = m->qs[1] = 0.0;
  m->qs[2] = ode->p[EA_P_THETA0];
  double T = ode->p[EA_P_TENSION];
  st = ea__fe_relax_positions(m, m->qs, EA_FE_CABLE_ACTIVE, T, 2);
  if (st) return ea_error_set(err, st, "fe static: singular position relaxation");
  double target[2] = {x[n - 1], y[n - 1]};
  st = ea__fe_newton_core(m, m->qs, EA_FE_CABLE_ACTIVE, &T, m->set.static_hold_tip ? target : NULL,
                          info, err);
  if (info) {
    info->tip_shift = hypot(info->tip[0] - x[n - 1], info->tip[1] - y[n - 1]);
    info->time_s = ea__mono_s() - t0;
  }
  if (st) return st;
  memcpy(m->q, m->qs, sizeof(double) * (size_t)m->nd);
  memset(m->v, 0, sizeof(double) * (size_t)m->nd);
  m->phase = EA_FE_CABLE_ACTIVE;
  m->cable_value = T;
  m->modes_valid = 0;
  return EA_OK;
}

/* Continuation of an equilibrium in (theta0, cable value): the path
 * lambda -> (theta0_a + lambda (theta0_b - theta0_a), c_a + lambda (c_b - c_a)) from the
 * current equilibrium (lambda = 0) to the target (lambda = 1), Newton at each step from
 * the previous solution extrapolated along the path's secant, the step halved when Newton
 * fails and grown after easy successes. */
ea_status_t ea_fe_static_continue(ea_fe_model_t *m, double theta0, ea_fe_cable_phase_t phase,
                                  double value, ea_fe_static_info_t *info, ea_error_t *err) {
  if (!m) return ea_error_set(err, EA_ERR_ARG, "fe continue: model is NULL");
  if (!isfinite(theta0) || !isfinite(value) || (int)phase < 0 || phase > EA_FE_CABLE_PASSIVE)
    return ea_error_set(err, EA_ERR_ARG, "fe continue: theta0 = %g, cable value = %g", theta0,
                        value);
  if (phase == EA_FE_CABLE_PASSIVE && !(value > 0.0))
    return ea_error_set(err, EA_ERR_ARG, "fe continue: rest length %g <= 0", value);
  if (phase == EA_FE_CABLE_ACTIVE && !(value >= 0.0))
    return ea_error_set(err, EA_ERR_ARG, "fe continue: tension %g < 0", value);
  const double t0 = ea__mono_s();
  const int nd = m->nd;
  /* the start in the target's phase: an ACTIVE cable becomes PASSIVE keeping its tension */
  ea_fe_cable_phase_t ph = m->phase;
  double ca = m->cable_value;
  if (phase == EA_FE_CABLE_PASSIVE && ph == EA_FE_CABLE_ACTIVE)
    ea__fe_passive_equiv(m, m->q, &ph, &ca);
  if (ph != phase)
    return ea_error_set(err, EA_ERR_ARG, "fe continue: cable phase %d cannot become %d", (int)ph,
                        (int)phase);
  const double tha = m->q[2];
  double *qa = m->q0, *qb = m->v0, *qt = m->qs; /* last two accepted states, trial */
  memcpy(qa, m->q, sizeof(double) * (size_t)nd);
  memcpy(qb, m->q, sizeof(double) * (size_t)nd);
  double la = 0.0, lb = 0.0, step = 1.0;
  int steps = 0, newton = 0, easy = 0;
  ea_fe_static_info_t si;
  memset(&si, 0, sizeof si);
  ea_status_t st = EA_OK;
  while (lb < 1.0) {
    const double lt = fmin(1.0, lb + step);
    /* predictor: secant through the last two accepted states */
    const double w = (lb > la) ? (lt - lb) / (lb - la) : 0.0;
    for (int i = 0; i < nd; ++i)
      qt[i] = qb[i] + w * (qb[i] - qa[i]);
    qt[2] = tha + lt * (theta0 - tha);
    const double ct = ca + lt * (value - ca);
    st = ea__fe_newton_core(m, qt, phase, (double[]){ct}, NULL, &si, NULL);
    newton += si.iterations;
    ++steps;
    /* a step must stay on the branch: Newton from a stiff cable's state can land on a
     * distant (axially crushed, unstable) equilibrium; accept only a continuous change
     * (every node within 2 % of L, every rotation within 0.05 rad of the prediction from
     * the last state) */
    if (st == EA_OK) {
      double dx = 0.0, dth = 0.0;
      for (int i = 3; i < nd; ++i) {
        const double d = fabs(qt[i] - qb[i]);
        if (i % 3 == 2)
          dth = fmax(dth, d);
        else
          dx = fmax(dx, d);
      }
      if (dx > 0.02 * m->arm.length || dth > 0.05 + fabs(qt[2] - qb[2])) st = EA_ERR_NOCONV;
    }
    if (st == EA_OK) {
      memcpy(qa, qb, sizeof(double) * (size_t)nd);
      memcpy(qb, qt, sizeof(double) * (size_t)nd);
      la = lb;
      lb = lt;
      if (si.iterations <= 6 && ++easy >= 2) step = fmin(1.0, 2.0 * step);
    } else {
      easy = 0;
      step *= 0.5;
      if (step < 1.0 / 4096) break;
    }
  }
  if (info) {
    *info = si;
    info->iterations = newton;
    info->time_s = ea__mono_s() - t0;
  }
  if (!(lb >= 1.0))
    return ea_error_set(err, st ? st : EA_ERR_NOCONV,
                        "fe continuation to theta0 = %g rad, cable value %g stopped at %.4g of "
                        "the way after %d steps (last Newton eps %g)",
                        theta0, value, lb, steps, si.residual);
  memcpy(m->q, qb, sizeof(double) * (size_t)nd);
  memset(m->v, 0, sizeof(double) * (size_t)nd);
  m->phase = phase;
  m->cable_value = value;
  m->modes_valid = 0;
  if (info) info->status = EA_OK;
  return EA_OK;
}
