/* Finite element model: transient dynamics of the nonlinear model.
 *
 * Energy-consistent implicit midpoint (Gonzalez discrete gradient; Simo and
 * Tarnow's energy-momentum idea): with h = dt, q_m = (q0 + q1)/2,
 *   q1 - q0 = h (v0 + v1) / 2
 *   M (v1 - v0) / h + C (v0 + v1) / 2 + dV(q0, q1) = 0          (free rows)
 *   dV = grad V(q_m) + [V(q1) - V(q0) - grad V(q_m).dq] M dq / (dq' M dq)
 * dV . dq = V(q1) - V(q0) exactly, so without damping and driving the total
 * energy 1/2 v'Mv + V is conserved to the Newton tolerance, for any step and
 * any nonlinearity; second order; no numerical dissipation. The mass matrix
 * of the planar beam is constant. Newton uses 2M/h^2 + C/h + K(q_m)/2 (the
 * rank-one part of the correction term is left out: it is O(dq)). */
#include "fe_impl.h"

#include <math.h>
#include <string.h>

void ea_fe_sim_settings_default(ea_fe_sim_settings_t *s) {
  if (!s) return;
  s->scheme = EA_FE_SCHEME_ENERGY;
  s->dt = 1e-3;
  s->t_end = 1.0;
  s->t_motion_end = -1.0;
  s->rho_inf = 0.9;
  s->rayleigh_mass = 0.0;
  s->rayleigh_stiffness = 0.0;
  s->tol = 1e-11;
  s->max_iter = 25;
  s->output_every = 1;
}

ea_status_t ea_fe_sim_settings_validate(const ea_fe_sim_settings_t *s, ea_error_t *err) {
  if (!s) return ea_error_set(err, EA_ERR_ARG, "sim settings are NULL");
  if ((int)s->scheme < 0 || s->scheme >= EA_FE_SCHEME_COUNT)
    return ea_error_set(err, EA_ERR_ARG, "sim scheme = %d: unknown", (int)s->scheme);
  if (s->scheme != EA_FE_SCHEME_ENERGY)
    return ea_error_set(err, EA_ERR_NOTIMPL, "sim scheme generalized-alpha: not implemented");
  if (!isfinite(s->dt) || !(s->dt > 0.0))
    return ea_error_set(err, EA_ERR_ARG, "sim dt = %g: must be > 0", s->dt);
  if (!isfinite(s->t_end) || !(s->t_end >= 0.0) || s->t_end / s->dt > 1e9)
    return ea_error_set(err, EA_ERR_ARG, "sim t_end = %g: must be >= 0 and < 1e9 dt", s->t_end);
  if (!isfinite(s->t_motion_end))
    return ea_error_set(err, EA_ERR_ARG, "sim t_motion_end = %g: must be finite",
                        s->t_motion_end);
  if (!(s->rho_inf >= 0.0 && s->rho_inf <= 1.0))
    return ea_error_set(err, EA_ERR_ARG, "sim rho_inf = %g: must be in [0, 1]", s->rho_inf);
  if (!(s->rayleigh_mass >= 0.0) || !(s->rayleigh_stiffness >= 0.0) ||
      !isfinite(s->rayleigh_mass) || !isfinite(s->rayleigh_stiffness))
    return ea_error_set(err, EA_ERR_ARG, "sim Rayleigh coefficients must be finite and >= 0");
  if (!(s->tol > 0.0) || s->max_iter < 1 || s->output_every < 1)
    return ea_error_set(err, EA_ERR_ARG, "sim tol > 0, max_iter >= 1, output_every >= 1");
  return EA_OK;
}

int ea_fe_samples_eval(double t, double *value, double *rate, void *data) {
  const ea_fe_samples_t *h = data;
  if (!h || h->n < 1 || !h->t || !h->value || !value || !rate) return 1;
  const int n = h->n;
  if (n == 1 || t <= h->t[0]) {
    *value = h->value[0];
    *rate = 0.0;
    return 0;
  }
  if (t >= h->t[n - 1]) {
    *value = h->value[n - 1];
    *rate = 0.0;
    return 0;
  }
  int lo = 0, hi = n - 1;
  while (hi - lo > 1) {
    const int mid = (lo + hi) / 2;
    if (h->t[mid] <= t) lo = mid;
    else hi = mid;
  }
  const double t0 = h->t[lo], t1 = h->t[hi], dt = t1 - t0;
  if (!(dt > 0.0)) return 1;
  const double y0 = h->value[lo], y1 = h->value[hi];
  const double m0 = (lo > 0) ? (y1 - h->value[lo - 1]) / (t1 - h->t[lo - 1]) : 0.0;
  const double m1 = (hi < n - 1) ? (h->value[hi + 1] - y0) / (h->t[hi + 1] - t0) : 0.0;
  const double u = (t - t0) / dt, u2 = u * u, u3 = u2 * u;
  *value = (2 * u3 - 3 * u2 + 1) * y0 + (u3 - 2 * u2 + u) * dt * m0 + (-2 * u3 + 3 * u2) * y1 +
           (u3 - u2) * dt * m1;
  *rate = ((6 * u2 - 6 * u) * y0 + (3 * u2 - 4 * u + 1) * dt * m0 + (-6 * u2 + 6 * u) * y1 +
           (3 * u2 - 2 * u) * dt * m1) / dt;
  return 0;
}

/* Drive values at t. */
static int ea__fe_drive_at(const ea_fe_drive_t *d, double t, double th0_hold, double cab_hold,
                           double *th0, double *th0_rate, double *cab) {
  double r = 0.0;
  *th0 = th0_hold;
  *th0_rate = 0.0;
  *cab = cab_hold;
  if (!d) return 0;
  if (d->theta0 && d->theta0(t, th0, th0_rate, d->theta0_data)) return 1;
  if (d->cable && d->cable(t, cab, &r, d->cable_data)) return 1;
  return !(isfinite(*th0) && isfinite(*th0_rate) && isfinite(*cab));
}

static double ea__fe_kinetic(const ea_fe_model_t *m, const double *v) {
  memset(m->tmp, 0, sizeof(double) * (size_t)m->nd);
  ea__fe_band_gemv(m, 1.0, m->Mb, v, m->tmp);
  double T = 0.0;
  for (int i = 0; i < m->nd; ++i) T += 0.5 * v[i] * m->tmp[i];
  return T;
}

ea_status_t ea_fe_simulate(ea_fe_model_t *m, const ea_fe_drive_t *drive,
                           const ea_fe_sim_settings_t *s, double *tip, int tip_rows,
                           ea_fe_sim_info_t *info, ea_error_t *err) {
  ea_fe_sim_info_t loc;
  if (!info) info = &loc;
  memset(info, 0, sizeof *info);
  if (!m || !s) return info->status = ea_error_set(err, EA_ERR_ARG, "simulate: NULL argument");
  ea_status_t st = ea_fe_sim_settings_validate(s, err);
  if (st) return info->status = st;
  if (tip && tip_rows < 0) return info->status = ea_error_set(err, EA_ERR_ARG, "tip_rows < 0");
  const double wall0 = ea__fe_now();
  const int nd = m->nd, nf = m->nf;
  const double h = s->dt;
  const int nsteps = (int)ceil(s->t_end / h - 1e-9);
  const ea_fe_cable_phase_t phase = m->phase;
  const double th0_hold = m->q[2], cab_hold = m->cable_value;
  double th0, th0r, cab;
  if (ea__fe_drive_at(drive, 0.0, th0_hold, cab_hold, &th0, &th0r, &cab))
    return info->status = ea_error_set(err, EA_ERR_INTERRUPTED, "simulate: drive failed at t = 0");
  m->q[2] = th0;
  m->v[0] = m->v[1] = 0.0;
  m->v[2] = th0r;
  if (phase != EA_FE_CABLE_NONE) m->cable_value = cab;
  /* Rayleigh damping C = a M + b K0 (passive stiffness at t = 0) */
  const int damped = s->rayleigh_mass > 0.0 || s->rayleigh_stiffness > 0.0;
  memset(m->Cb, 0, sizeof(double) * EA__FE_LDS * (size_t)nd);
  if (damped) {
    ea_fe_cable_phase_t pp;
    double pv;
    ea__fe_passive_equiv(m, m->q, &pp, &pv);
    ea__fe_assemble(m, m->q, pp, pv, m->fi, m->Kt);
    ea__fe_band_axpy(m, s->rayleigh_mass, m->Mb, m->Cb);
    ea__fe_band_axpy(m, s->rayleigh_stiffness, m->Kt, m->Cb);
  }
  const double E0 = ea_fe_energy(m);
  info->energy_start = E0;
  int rows = 0;
  if (tip && rows < tip_rows) {
    double *r = tip + 4 * rows++;
    r[0] = 0.0;
    memcpy(r + 1, m->q + nd - 3, 3 * sizeof(double));
  }
  const int measure = s->t_motion_end >= 0.0 && s->t_motion_end < s->t_end;
  int have_static = 0;
  double sum2 = 0.0, peak = 0.0;
  int nres = 0;
  for (int n = 0; n < nsteps; ++n) {
    const double t0 = n * h, t1 = (n + 1) * h, tm = 0.5 * (t0 + t1);
    double th1, th1r, cm, dum1, dum2;
    if (ea__fe_drive_at(drive, t1, th0_hold, cab_hold, &th1, &th1r, &dum1) ||
        ea__fe_drive_at(drive, tm, th0_hold, cab_hold, &dum1, &dum2, &cm)) {
      st = ea_error_set(err, EA_ERR_INTERRUPTED, "simulate: drive failed at t = %g", t1);
      break;
    }
    if (phase == EA_FE_CABLE_NONE) cm = 0.0;
    if (phase == EA_FE_CABLE_PASSIVE && !(cm > 0.0)) {
      st = ea_error_set(err, EA_ERR_INPUT, "simulate: rest length %g <= 0 at t = %g", cm, tm);
      break;
    }
    if (phase == EA_FE_CABLE_ACTIVE && !(cm >= 0.0)) {
      st = ea_error_set(err, EA_ERR_INPUT, "simulate: tension %g < 0 at t = %g", cm, tm);
      break;
    }
    double *q0 = m->q0, *v0 = m->v0, *q1 = m->q, *v1 = m->v, *qm = m->qm;
    memcpy(q0, m->q, sizeof(double) * (size_t)nd);
    memcpy(v0, m->v, sizeof(double) * (size_t)nd);
    const double V0 = ea__fe_potential(m, q0, phase, cm);
    /* predictor */
    for (int i = 3; i < nd; ++i) q1[i] = q0[i] + h * v0[i];
    q1[0] = q1[1] = 0.0;
    q1[2] = th1;
    v1[0] = v1[1] = 0.0;
    v1[2] = th1r;
    int it = 0, conv = 0;
    double dprev = INFINITY;
    for (; it < s->max_iter; ++it) {
      for (int i = 3; i < nd; ++i) v1[i] = 2.0 * (q1[i] - q0[i]) / h - v0[i];
      for (int i = 0; i < nd; ++i) qm[i] = 0.5 * (q0[i] + q1[i]);
      ea__fe_assemble(m, qm, phase, cm, m->fm, m->Kb);
      /* discrete gradient correction */
      double *dq = m->tmp, *Mdq = m->a0;
      for (int i = 0; i < nd; ++i) dq[i] = q1[i] - q0[i];
      memset(Mdq, 0, sizeof(double) * (size_t)nd);
      ea__fe_band_gemv(m, 1.0, m->Mb, dq, Mdq);
      double dMd = 0.0, fd = 0.0;
      for (int i = 0; i < nd; ++i) {
        dMd += dq[i] * Mdq[i];
        fd += m->fm[i] * dq[i];
      }
      if (dMd > 1e-300) {
        const double V1 = ea__fe_potential(m, q1, phase, cm);
        const double dV = V1 - V0 - fd;
        /* Below the rounding level of V (2e-14 of it, ~90 ulp) the difference is noise; dividing
         * it by a tiny dq' M dq (an arm nearly at rest) would swamp Newton:
         * the midpoint gradient is then exact to rounding already. */
        if (fabs(dV) > 2e-14 * (fabs(V0) + fabs(V1))) {
          const double c = dV / dMd;
          for (int i = 0; i < nd; ++i) m->fm[i] += c * Mdq[i];
        }
      }
      /* residual: M (v1 - v0)/h + C vm + dV */
      for (int i = 0; i < nd; ++i) {
        m->qs[i] = (v1[i] - v0[i]) / h; /* acceleration-like */
        m->vs[i] = 0.5 * (v0[i] + v1[i]);
      }
      ea__fe_band_gemv(m, 1.0, m->Mb, m->qs, m->fm);
      if (damped) ea__fe_band_gemv(m, 1.0, m->Cb, m->vs, m->fm);
      for (int i = 0; i < nf; ++i) m->r[i] = m->fm[i + 3];
      /* Jacobian 2M/h^2 + C/h + K/2 */
      const size_t nb = EA__FE_LDS * (size_t)nd;
      for (size_t i = 0; i < nb; ++i)
        m->Kb[i] = 0.5 * m->Kb[i] + 2.0 / (h * h) * m->Mb[i] + (damped ? m->Cb[i] / h : 0.0);
      if ((st = ea__fe_solve_free(m, m->Kb)) != EA_OK) break;
      double dmax = 0.0;
      int finite = 1;
      for (int i = 0; i < nf; ++i) {
        q1[i + 3] -= m->dq[i];
        dmax = fmax(dmax, fabs(m->dq[i]));
        finite = finite && isfinite(m->dq[i]);
      }
      if (!finite) {
        st = EA_ERR_NOCONV;
        break;
      }
      /* converged, or stagnating at rounding level (EA / h amplifies rounding) */
      if (dmax <= s->tol || (dmax <= 1e3 * s->tol && dmax > 0.5 * dprev)) {
        conv = 1;
        ++it;
        break;
      }
      dprev = dmax;
    }
    for (int i = 3; i < nd; ++i) v1[i] = 2.0 * (q1[i] - q0[i]) / h - v0[i];
    info->newton_iterations += it;
    if (it > info->max_step_iterations) info->max_step_iterations = it;
    if (st || !conv) {
      if (!st) st = EA_ERR_NOCONV;
      ea_error_set(err, st, "simulate: step %d (t = %g) did not converge in %d iterations", n + 1,
                   t1, it);
      break;
    }
    if (phase != EA_FE_CABLE_NONE) m->cable_value = cm;
    info->steps = n + 1;
    const double E = ea_fe_energy(m), K = ea__fe_kinetic(m, m->v);
    if (!isfinite(E)) {
      st = ea_error_set(err, EA_ERR_NOCONV, "simulate: state not finite at t = %g", t1);
      break;
    }
    info->energy_drift_max = fmax(info->energy_drift_max, fabs(E - E0));
    info->kinetic_max = fmax(info->kinetic_max, K);
    if (tip && rows < tip_rows && ((n + 1) % s->output_every == 0 || n + 1 == nsteps)) {
      double *r = tip + 4 * rows++;
      r[0] = t1;
      memcpy(r + 1, m->q + nd - 3, 3 * sizeof(double));
    }
    if (measure && t1 >= s->t_motion_end - 1e-12 * h) {
      if (!have_static) {
        /* final static equilibrium for the inputs held from here on */
        double th_e, th_er, cab_e;
        ea__fe_drive_at(drive, s->t_motion_end, th0_hold, cab_hold, &th_e, &th_er, &cab_e);
        if (phase == EA_FE_CABLE_NONE) cab_e = 0.0;
        memcpy(m->q0, m->q, sizeof(double) * (size_t)nd);
        memcpy(m->v0, m->v, sizeof(double) * (size_t)nd);
        double *qstat = m->qs;
        memcpy(qstat, m->q, sizeof(double) * (size_t)nd);
        qstat[2] = th_e;
        ea_fe_static_info_t si;
        st = ea__fe_newton_q(m, qstat, phase, cab_e, &si, err);
        if (st) break;
        memcpy(info->tip_static, qstat + nd - 3, 3 * sizeof(double));
        memcpy(m->q, m->q0, sizeof(double) * (size_t)nd);
        memcpy(m->v, m->v0, sizeof(double) * (size_t)nd);
        have_static = 1;
      }
      const double d = hypot(m->q[nd - 3] - info->tip_static[0], m->q[nd - 2] - info->tip_static[1]);
      sum2 += d * d;
      peak = fmax(peak, d);
      ++nres;
    }
  }
  info->rows = rows;
  info->energy_end = ea_fe_energy(m);
  if (nres > 0) {
    info->residual_rms = sqrt(sum2 / nres);
    info->residual_peak = peak;
  }
  info->time_s = ea__fe_now() - wall0;
  info->status = st;
  m->modes_valid = 0;
  return st;
}
