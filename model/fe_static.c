/* Finite element model: static Newton-Raphson (paper eq. 21-23). */
#include "fe_impl.h"

#include <math.h>
#include <string.h>

/* Largest rotation change [rad] accepted in one Newton step; longer steps are
 * scaled back (a guard for starts far from equilibrium; never active near it). */
#define EA__FE_MAX_DTHETA 0.3

ea_status_t ea__fe_newton_q(ea_fe_model_t *m, double *q, ea_fe_cable_phase_t phase,
                            double value, ea_fe_static_info_t *info, ea_error_t *err) {
  const double t0 = ea__fe_now();
  ea_status_t st = EA_ERR_MAXITER;
  double eps = INFINITY;
  int it = 0;
  for (;; ++it) {
    ea__fe_assemble(m, q, phase, value, m->fi, m->Kb);
    double r2 = 0.0;
    for (int i = 0; i < m->nf; ++i) {
      m->r[i] = m->fi[i + 3];
      r2 += m->r[i] * m->r[i];
    }
    eps = (m->fext_norm > 0.0) ? sqrt(r2) / m->fext_norm : sqrt(r2);
    if (!isfinite(eps)) {
      st = EA_ERR_NOCONV;
      break;
    }
    if (eps <= m->set.newton_tol) {
      st = EA_OK;
      break;
    }
    if (it >= m->set.newton_max_iter) break;
    if ((st = ea__fe_solve_free(m, m->Kb)) != EA_OK) break;
    st = EA_ERR_MAXITER;
    double dmax = 0.0;
    for (int i = 2; i < m->nf; i += 3) dmax = fmax(dmax, fabs(m->dq[i]));
    const double sc = (dmax > EA__FE_MAX_DTHETA) ? EA__FE_MAX_DTHETA / dmax : 1.0;
    for (int i = 0; i < m->nf; ++i) q[i + 3] -= sc * m->dq[i];
  }
  if (info) {
    memset(info, 0, sizeof *info);
    info->status = st;
    info->iterations = it;
    info->residual = eps;
    memcpy(info->tip, q + m->nd - 3, 3 * sizeof(double));
    double T = 0.0, l = 0.0;
    ea__fe_cable(m, phase, value, q[m->nd - 3], q[m->nd - 2], &T, &l, NULL, NULL);
    info->tension = T;
    info->cable_length = l;
    info->cable_angle = atan2(q[m->nd - 2] - m->arm.y_c, q[m->nd - 3] - m->arm.x_c);
    info->theta0 = q[2];
    info->time_s = ea__fe_now() - t0;
  }
  if (st == EA_ERR_SINGULAR)
    return ea_error_set(err, st, "fe Newton: singular tangent at iteration %d", it);
  if (st == EA_ERR_MAXITER)
    return ea_error_set(err, st, "fe Newton: eps = %g > %g after %d iterations", eps,
                        m->set.newton_tol, it);
  if (st) return ea_error_set(err, st, "fe Newton: residual not finite at iteration %d", it);
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

ea_status_t ea_fe_static_solve(ea_fe_model_t *m, ea_shooter_t *sh,
                               const ea_statics_solution_t *ode, ea_fe_static_info_t *info,
                               ea_error_t *err) {
  if (!m || !sh || !ode) return ea_error_set(err, EA_ERR_ARG, "fe static: NULL argument");
  for (int i = 0; i < EA_NP; ++i)
    if (!isfinite(ode->p[i]))
      return ea_error_set(err, EA_ERR_ARG, "fe static: ODE solution p[%d] = %g", i, ode->p[i]);
  if (ode->p[EA_P_TENSION] < 0.0)
    return ea_error_set(err, EA_ERR_INADMISSIBLE, "fe static: tension %g < 0",
                        ode->p[EA_P_TENSION]);
  const double t0 = ea__fe_now();
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
  st = ea__fe_newton_q(m, m->qs, EA_FE_CABLE_ACTIVE, ode->p[EA_P_TENSION], info, err);
  if (info) {
    info->tip_shift = hypot(info->tip[0] - x[n - 1], info->tip[1] - y[n - 1]);
    info->time_s = ea__fe_now() - t0;
  }
  if (st) return st;
  memcpy(m->q, m->qs, sizeof(double) * (size_t)m->nd);
  memset(m->v, 0, sizeof(double) * (size_t)m->nd);
  m->phase = EA_FE_CABLE_ACTIVE;
  m->cable_value = ode->p[EA_P_TENSION];
  m->modes_valid = 0;
  return EA_OK;
}
