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
 * rank-one part of the correction term is left out: it is O(dq)).
 *
 * Generalized-alpha (Chung and Hulbert 1993): see ea__fe_step_galpha; numerical
 * dissipation of the high modes set by rho_inf, second order, no exact energy
 * statement for the nonlinear model. */
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
  s->output_loads = 0;
  s->tip_static[0] = s->tip_static[1] = NAN;
}

ea_status_t ea_fe_sim_settings_validate(const ea_fe_sim_settings_t *s, ea_error_t *err) {
  if (!s) return ea_error_set(err, EA_ERR_ARG, "sim settings are NULL");
  if ((int)s->scheme < 0 || s->scheme >= EA_FE_SCHEME_COUNT)
    return ea_error_set(err, EA_ERR_ARG, "sim scheme = %d: unknown", (int)s->scheme);
  if (!isfinite(s->dt) || !(s->dt > 0.0))
    return ea_error_set(err, EA_ERR_ARG, "sim dt = %g: must be > 0", s->dt);
  if (!isfinite(s->t_end) || !(s->t_end >= 0.0) || s->t_end / s->dt > 1e9)
    return ea_error_set(err, EA_ERR_ARG, "sim t_end = %g: must be >= 0 and < 1e9 dt", s->t_end);
  if (!isfinite(s->t_motion_end))
    return ea_error_set(err, EA_ERR_ARG, "sim t_motion_end = %g: must be finite", s->t_motion_end);
  if (!(s->rho_inf >= 0.0 && s->rho_inf <= 1.0))
    return ea_error_set(err, EA_ERR_ARG, "sim rho_inf = %g: must be in [0, 1]", s->rho_inf);
  if (!(s->rayleigh_mass >= 0.0) || !(s->rayleigh_stiffness >= 0.0) ||
      !isfinite(s->rayleigh_mass) || !isfinite(s->rayleigh_stiffness))
    return ea_error_set(err, EA_ERR_ARG, "sim Rayleigh coefficients must be finite and >= 0");
  if (!(s->tol > 0.0) || s->max_iter < 1 || s->output_every < 1)
    return ea_error_set(err, EA_ERR_ARG, "sim tol > 0, max_iter >= 1, output_every >= 1");
  if (s->output_loads != 0 && s->output_loads != 1)
    return ea_error_set(err, EA_ERR_ARG, "sim output_loads = %d: must be 0 or 1", s->output_loads);
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
    if (h->t[mid] <= t)
      lo = mid;
    else
      hi = mid;
  }
  const double t0 = h->t[lo], t1 = h->t[hi], dt = t1 - t0;
  if (!(dt > 0.0)) return 1;
  const double y0 = h->value[lo], y1 = h->value[hi];
  double m0, m1;
  if (h->rate) {
    m0 = h->rate[lo];
    m1 = h->rate[hi];
  } else {
    m0 = (lo > 0) ? (y1 - h->value[lo - 1]) / (t1 - h->t[lo - 1]) : 0.0;
    m1 = (hi < n - 1) ? (h->value[hi + 1] - y0) / (h->t[hi + 1] - t0) : 0.0;
  }
  const double u = (t - t0) / dt, u2 = u * u, u3 = u2 * u;
  *value = (2 * u3 - 3 * u2 + 1) * y0 + (u3 - 2 * u2 + u) * dt * m0 + (-2 * u3 + 3 * u2) * y1 +
           (u3 - u2) * dt * m1;
  *rate = ((6 * u2 - 6 * u) * y0 + (3 * u2 - 4 * u + 1) * dt * m0 + (-6 * u2 + 6 * u) * y1 +
           (3 * u2 - 2 * u) * dt * m1) /
          dt;
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
  for (int i = 0; i < m->nd; ++i)
    T += 0.5 * v[i] * m->tmp[i];
  return T;
}

/* Clamp angular acceleration [rad/s^2] at t: centred difference of the drive's
 * rate over +-h/2 (second order; the drives give value and rate only). */
static int ea__fe_drive_acc(const ea_fe_drive_t *d, double t, double h, double th0_hold,
                            double cab_hold, double *acc) {
  double v, rp, rm, c;
  *acc = 0.0;
  if (!d || !d->theta0) return 0;
  if (ea__fe_drive_at(d, t + 0.5 * h, th0_hold, cab_hold, &v, &rp, &c) ||
      ea__fe_drive_at(d, t - 0.5 * h, th0_hold, cab_hold, &v, &rm, &c))
    return 1;
  *acc = (rp - rm) / h;
  return 0;
}

/* Converged, or stagnating at rounding level (EA / h amplifies rounding). */
static int ea__fe_newton_done(const ea_fe_sim_settings_t *s, double dmax, double dprev) {
  return dmax <= s->tol || (dmax <= 1e3 * s->tol && dmax > 0.5 * dprev);
}

/* Apply the Newton correction m->dq to the free rows of q; max |dq| in *dmax.
 * Returns 0 if the correction is not finite. */
static int ea__fe_apply_dq(ea_fe_model_t *m, double *q, double *dmax) {
  int finite = 1;
  *dmax = 0.0;
  for (int i = 0; i < m->nf; ++i) {
    q[i + 3] -= m->dq[i];
    *dmax = fmax(*dmax, fabs(m->dq[i]));
    finite = finite && isfinite(m->dq[i]);
  }
  return finite;
}

/* The common end of a Newton iteration of both time schemes, once m->fm holds
 * the residual (inertia and Rayleigh terms included) and m->Kb the tangent K
 * at the evaluation point qe: adds the strain-rate damping at (qe, ve), forms
 * the iteration matrix ck K + ca M + cv (C + K_damping), solves for the free
 * DOFs and updates q1. *conv is set when the correction meets the stopping
 * rule; *dprev carries the previous correction. */
static ea_status_t ea__fe_newton_correct(ea_fe_model_t *m, const ea_fe_sim_settings_t *s,
                                         double *q1, const double *qe, const double *ve, int damped,
                                         double bkv, double ck, double ca, double cv, double *dprev,
                                         int *conv) {
  const int nd = m->nd, nf = m->nf;
  const size_t nb = EA__FE_LDS * (size_t)nd;
  if (bkv > 0.0) {
    memset(m->Kt, 0, sizeof(double) * nb);
    ea__fe_assemble_rate(m, qe, ve, bkv, m->fm, m->Kt);
  }
  for (int i = 0; i < nf; ++i)
    m->r[i] = m->fm[i + 3];
  for (size_t i = 0; i < nb; ++i)
    m->Kb[i] = ck * m->Kb[i] + ca * m->Mb[i] + (damped ? cv * m->Cb[i] : 0.0) +
               (bkv > 0.0 ? cv * m->Kt[i] : 0.0);
  ea_status_t st = ea__fe_solve_free(m, m->Kb);
  if (st) return st;
  double dmax;
  if (!ea__fe_apply_dq(m, q1, &dmax)) return EA_ERR_NOCONV;
  *conv = ea__fe_newton_done(s, dmax, *dprev);
  *dprev = dmax;
  return EA_OK;
}

/* Cable force of the energy scheme over a step: the discrete gradient of the cable
 * potential taken in the cable's own strain, e = l - L0 (PASSIVE) with the rest
 * length at each end of the step, e0 = l(q0) - L0(t0), e1 = l(q1) - L0(t1):
 *   T_sec = [W(e1) - W(e0)] / (e1 - e0),  W(e) = EA_c max(e, 0)^2 / (2 L0(t_m)),
 * applied along u = (d0 + d1) / (l0 + l1), d = root - tip, so that the work the cable
 * does on the tip over the step is exactly -T_sec (l1 - l0) (l1^2 - l0^2 = (d1 + d0).
 * (d1 - d0)). Undriven (L0 fixed) this is Gonzalez's discrete gradient of a spring:
 * energy is conserved exactly. Driven, the reel's work is -T_sec (L0(t1) - L0(t0)),
 * and the tension is the secant over the strains the cable really has at the two ends
 * (both ~ T L0 / EA_c), not over a frozen rest length that the moving cable crosses
 * within the step (|dL0| per step can exceed the stretch: with L0 frozen at its mid-step
 * value the cable is slack at one end and overstretched at the other, and the global
 * correction turned that into a spurious force of newtons). ACTIVE: T_sec = T(t_m).
 * Adds -T_sec u to the tip rows of f (f = f_int - f_ext) and the midpoint cable
 * stiffness (Newton matrix) to Kb; returns T_sec. */
static double ea__fe_cable_secant(ea_fe_model_t *m, const double *q0, const double *q1,
                                  ea_fe_cable_phase_t phase, double c0, double cm, double c1,
                                  double *f, double *Kb) {
  const int t = m->nd - 3;
  if (phase == EA_FE_CABLE_NONE) return 0.0;
  const double xc = m->arm.x_c, yc = m->arm.y_c;
  const double d0x = xc - q0[t], d0y = yc - q0[t + 1], d1x = xc - q1[t], d1y = yc - q1[t + 1];
  const double l0 = hypot(d0x, d0y), l1 = hypot(d1x, d1y);
  double Tsec;
  if (phase == EA_FE_CABLE_ACTIVE) {
    Tsec = cm;
  } else {
    const double kt = m->arm.EA_cable / cm;
    const double e0 = fmax(l0 - c0, 0.0), e1 = fmax(l1 - c1, 0.0);
    const double de = (l1 - c1) - (l0 - c0);
    /* secant of W' = kt max(e, 0); where the difference is at rounding level, the
     * tangent at the mean strain (the limit of the secant) */
    if (fabs(de) > 1e-9 * (fabs(l0 - c0) + fabs(l1 - c1)) + 1e-300)
      Tsec = 0.5 * kt * (e1 * e1 - e0 * e0) / de;
    else
      Tsec = kt * fmax(0.5 * ((l0 - c0) + (l1 - c1)), 0.0);
  }
  const double ls = l0 + l1;
  const double ux = ls > 0 ? (d0x + d1x) / ls : 0.0, uy = ls > 0 ? (d0y + d1y) / ls : 0.0;
  f[t] -= Tsec * ux;
  f[t + 1] -= Tsec * uy;
  if (Kb) {
    double kc[4], fc[2];
    ea__fe_cable(m, phase, cm, 0.5 * (q0[t] + q1[t]), 0.5 * (q0[t + 1] + q1[t + 1]), NULL, NULL, fc,
                 kc);
    EA__SB(Kb, t, t) += kc[0];
    EA__SB(Kb, t, t + 1) += kc[1];
    EA__SB(Kb, t + 1, t + 1) += kc[3];
  }
  return Tsec;
}

/* One step of the energy-consistent midpoint scheme from (m->q0, m->v0) to
 * (m->q, m->v); clamp angle/rate th1, th1r at t1; cable value (T or L0) c0, cm, c1 at
 * t0, the midpoint and t1. The potential is partitioned: beam strain + gravity get the
 * global (mass-weighted) discrete-gradient correction, the cable its own discrete
 * gradient in its strain (ea__fe_cable_secant). *iters: Newton iterations. */
static ea_status_t ea__fe_step_energy(ea_fe_model_t *m, const ea_fe_sim_settings_t *s, int damped,
                                      double bkv, ea_fe_cable_phase_t phase, double c0, double cm,
                                      double c1, double th1, double th1r, int *iters) {
  const int nd = m->nd;
  const double h = s->dt;
  double *q0 = m->q0, *v0 = m->v0, *q1 = m->q, *v1 = m->v, *qm = m->qm;
  const double V0 = ea__fe_potential(m, q0, EA_FE_CABLE_NONE, 0.0);
  ea_status_t st = EA_OK;
  /* predictor */
  for (int i = 3; i < nd; ++i)
    q1[i] = q0[i] + h * v0[i];
  q1[0] = q1[1] = 0.0;
  q1[2] = th1;
  v1[0] = v1[1] = 0.0;
  v1[2] = th1r;
  int it = 0, conv = 0;
  double dprev = INFINITY;
  for (; it < s->max_iter; ++it) {
    for (int i = 3; i < nd; ++i)
      v1[i] = 2.0 * (q1[i] - q0[i]) / h - v0[i];
    for (int i = 0; i < nd; ++i)
      qm[i] = 0.5 * (q0[i] + q1[i]);
    ea__fe_assemble(m, qm, EA_FE_CABLE_NONE, 0.0, m->fm, m->Kb);
    /* discrete gradient correction of the beam + gravity potential */
    double *dq = m->tmp, *Mdq = m->a0;
    for (int i = 0; i < nd; ++i)
      dq[i] = q1[i] - q0[i];
    memset(Mdq, 0, sizeof(double) * (size_t)nd);
    ea__fe_band_gemv(m, 1.0, m->Mb, dq, Mdq);
    double dMd = 0.0, fd = 0.0;
    for (int i = 0; i < nd; ++i) {
      dMd += dq[i] * Mdq[i];
      fd += m->fm[i] * dq[i];
    }
    if (dMd > 1e-300) {
      const double V1 = ea__fe_potential(m, q1, EA_FE_CABLE_NONE, 0.0);
      const double dV = V1 - V0 - fd;
      /* Below the rounding level of V (2e-14 of it, ~90 ulp) the difference is noise; dividing
       * it by a tiny dq' M dq (an arm nearly at rest) would swamp Newton:
       * the midpoint gradient is then exact to rounding already. */
      if (fabs(dV) > 2e-14 * (fabs(V0) + fabs(V1))) {
        const double c = dV / dMd;
        for (int i = 0; i < nd; ++i)
          m->fm[i] += c * Mdq[i];
      }
    }
    ea__fe_cable_secant(m, q0, q1, phase, c0, cm, c1, m->fm, m->Kb);
    /* residual: M (v1 - v0)/h + C vm + dV */
    for (int i = 0; i < nd; ++i) {
      m->qs[i] = (v1[i] - v0[i]) / h; /* acceleration-like */
      m->vs[i] = 0.5 * (v0[i] + v1[i]);
    }
    ea__fe_band_gemv(m, 1.0, m->Mb, m->qs, m->fm);
    if (damped) ea__fe_band_gemv(m, 1.0, m->Cb, m->vs, m->fm);
    /* strain-rate damping at (q_m, v_m); d v_m / d q1 = 1/h.
     * Jacobian 2M/h^2 + C/h + K/2 */
    if ((st = ea__fe_newton_correct(m, s, q1, qm, m->vs, damped, bkv, 0.5, 2.0 / (h * h), 1.0 / h,
                                    &dprev, &conv)) != EA_OK)
      break;
    if (conv) {
      ++it;
      break;
    }
  }
  for (int i = 3; i < nd; ++i)
    v1[i] = 2.0 * (q1[i] - q0[i]) / h - v0[i];
  *iters = it;
  if (!st && !conv) st = EA_ERR_NOCONV;
  return st;
}

/* Generalized-alpha parameters (Chung and Hulbert 1993) for rho_inf. */
typedef struct ea__fe_galpha {
  double am, af, gamma, beta;
} ea__fe_galpha_t;

static ea__fe_galpha_t ea__fe_galpha(double rho_inf) {
  ea__fe_galpha_t g;
  g.am = (2.0 * rho_inf - 1.0) / (rho_inf + 1.0);
  g.af = rho_inf / (rho_inf + 1.0);
  g.gamma = 0.5 - g.am + g.af;
  g.beta = 0.25 * (1.0 - g.am + g.af) * (1.0 - g.am + g.af);
  return g;
}

/* One generalized-alpha step from (m->q0, m->v0, m->acc0) to (m->q, m->v,
 * m->acc): Newmark updates
 *   q1 = q0 + h v0 + h^2 ((1/2 - beta) a0 + beta a1),  v1 = v0 + h ((1 - gamma) a0 + gamma a1)
 * and, on the free rows,
 *   M a_{1-am} + C v_{1-af} + f(q_{1-af}; cable value at t_{n+1-af}) = 0,
 *   x_{1-a} = (1 - a) x1 + a x0.
 * Unknown: the free rows of q1; Newton matrix
 *   (1-am)/(beta h^2) M + (1-af) gamma/(beta h) C + (1-af) K(q_{1-af}).
 * Clamp: angle, rate and acceleration th1, th1r, th1a at t1 (prescribed).
 * first: no previous step (m->qprev not set). */
static ea_status_t ea__fe_step_galpha(ea_fe_model_t *m, const ea_fe_sim_settings_t *s,
                                      const ea__fe_galpha_t *g, int damped, double bkv,
                                      ea_fe_cable_phase_t phase, double caf, double th1,
                                      double th1r, double th1a, int first, int *iters) {
  const int nd = m->nd;
  const double h = s->dt, am = g->am, af = g->af, ga = g->gamma, be = g->beta;
  double *q0 = m->q0, *v0 = m->v0, *a0 = m->acc0, *q1 = m->q, *v1 = m->v, *a1 = m->acc;
  double *qf = m->qm, *vf = m->vs, *amv = m->qs;
  ea_status_t st = EA_OK;
  /* predictor: linear extrapolation of the last two positions (first step: q0 + h v0). Not
   * q0 + h v0 (+ h^2/2 a0): in the stiff modes (rotary inertia I_zz h ~ 1e-9 against
   * shear GA / h, omega h >> 1) a start slightly off equilibrium gives accelerations
   * ~ omega^2 x and, for rho_inf < 1, velocities h v ~ (omega h)^2 x while the
   * positions stay ~ x: extrapolating with v or a throws Newton out of its basin. */
  for (int i = 3; i < nd; ++i)
    q1[i] = first ? q0[i] + h * v0[i] : 2.0 * q0[i] - m->qprev[i];
  q1[0] = q1[1] = 0.0;
  q1[2] = th1;
  v1[0] = v1[1] = 0.0;
  v1[2] = th1r;
  a1[0] = a1[1] = 0.0;
  a1[2] = th1a;
  const double ca = (1.0 - am) / (be * h * h), cv = (1.0 - af) * ga / (be * h), ck = 1.0 - af;
  int it = 0, conv = 0;
  double dprev = INFINITY;
  for (; it < s->max_iter; ++it) {
    for (int i = 3; i < nd; ++i) {
      a1[i] = (q1[i] - q0[i] - h * v0[i]) / (be * h * h) - (0.5 / be - 1.0) * a0[i];
      v1[i] = v0[i] + h * ((1.0 - ga) * a0[i] + ga * a1[i]);
    }
    for (int i = 0; i < nd; ++i) {
      qf[i] = (1.0 - af) * q1[i] + af * q0[i];
      vf[i] = (1.0 - af) * v1[i] + af * v0[i];
      amv[i] = (1.0 - am) * a1[i] + am * a0[i];
    }
    ea__fe_assemble(m, qf, phase, caf, m->fm, m->Kb);
    ea__fe_band_gemv(m, 1.0, m->Mb, amv, m->fm);
    if (damped) ea__fe_band_gemv(m, 1.0, m->Cb, vf, m->fm);
    /* strain-rate damping at (q_{1-af}, v_{1-af}) */
    if ((st = ea__fe_newton_correct(m, s, q1, qf, vf, damped, bkv, ck, ca, cv, &dprev, &conv)) !=
        EA_OK)
      break;
    if (conv) {
      ++it;
      break;
    }
  }
  for (int i = 3; i < nd; ++i) {
    a1[i] = (q1[i] - q0[i] - h * v0[i]) / (be * h * h) - (0.5 / be - 1.0) * a0[i];
    v1[i] = v0[i] + h * ((1.0 - ga) * a0[i] + ga * a1[i]);
  }
  *iters = it;
  if (!st && !conv) st = EA_ERR_NOCONV;
  return st;
}

/* Consistent initial acceleration: M a = -(f(q) + C v) on the free rows, the
 * clamp acceleration a[2] = th0a given (its inertia coupling moved right). */
static ea_status_t ea__fe_initial_acc(ea_fe_model_t *m, int damped, double bkv, double th0a,
                                      double *a) {
  const int nd = m->nd, nf = m->nf;
  ea__fe_assemble(m, m->q, m->phase, m->cable_value, m->fm, NULL);
  memset(a, 0, sizeof(double) * (size_t)nd);
  a[2] = th0a;
  ea__fe_band_gemv(m, 1.0, m->Mb, a, m->fm);
  if (damped) ea__fe_band_gemv(m, 1.0, m->Cb, m->v, m->fm);
  ea__fe_assemble_rate(m, m->q, m->v, bkv, m->fm, NULL);
  for (int i = 0; i < nf; ++i)
    m->r[i] = -m->fm[i + 3];
  ea_status_t st = ea__fe_solve_free(m, m->Mb);
  if (st) return st;
  for (int i = 0; i < nf; ++i)
    a[i + 3] = m->dq[i];
  return EA_OK;
}

/* The state at t = 0: the drive's theta0 and cable value, the damping matrices, and for
 * generalized-alpha the consistent initial acceleration. */
static ea_status_t ea__fe_sim_start(ea_fe_model_t *m, const ea_fe_drive_t *drive,
                                    const ea_fe_sim_settings_t *s, double th0_hold, double cab_hold,
                                    ea_error_t *err) {
  const int nd = m->nd;
  double th0, th0r, cab;
  if (ea__fe_drive_at(drive, 0.0, th0_hold, cab_hold, &th0, &th0r, &cab))
    return ea_error_set(err, EA_ERR_INTERRUPTED, "simulate: drive failed at t = 0");
  m->q[2] = th0;
  m->v[0] = m->v[1] = 0.0;
  m->v[2] = th0r;
  if (m->phase != EA_FE_CABLE_NONE) m->cable_value = cab;
  /* damping: mass-proportional a M (constant, in m->Cb) and strain-rate (Kelvin-Voigt)
   * b int B^T D B v at the current configuration */
  const int damped = s->rayleigh_mass > 0.0;
  memset(m->Cb, 0, sizeof(double) * EA__FE_LDS * (size_t)nd);
  if (damped) ea__fe_band_axpy(m, s->rayleigh_mass, m->Mb, m->Cb);
  if (s->scheme != EA_FE_SCHEME_GENALPHA) return EA_OK;
  double th0a;
  if (ea__fe_drive_acc(drive, 0.0, s->dt, th0_hold, cab_hold, &th0a))
    return ea_error_set(err, EA_ERR_INTERRUPTED, "simulate: drive failed at t = 0");
  const ea_status_t st = ea__fe_initial_acc(m, damped, s->rayleigh_stiffness, th0a, m->acc);
  if (st)
    return ea_error_set(err, st,
                        "simulate: generalized-alpha initial acceleration: singular mass "
                        "matrix (I_zz = 0 with I_hand = 0?)");
  return EA_OK;
}

/* Work of the damping forces over the step just taken: (q1 - q0) . f_d(q_e, v_e) at the
 * scheme's evaluation point (midpoint, or n+1-af). */
static void ea__fe_damping_work(ea_fe_model_t *m, const ea_fe_sim_settings_t *s, double w1,
                                double *work) {
  const int nd = m->nd;
  double *qe = m->qm, *ve = m->vs, *fd = m->tmp;
  for (int i = 0; i < nd; ++i) {
    qe[i] = w1 * m->q[i] + (1.0 - w1) * m->q0[i];
    ve[i] = w1 * m->v[i] + (1.0 - w1) * m->v0[i];
  }
  memset(fd, 0, sizeof(double) * (size_t)nd);
  if (s->rayleigh_mass > 0.0) ea__fe_band_gemv(m, 1.0, m->Cb, ve, fd);
  ea__fe_assemble_rate(m, qe, ve, s->rayleigh_stiffness, fd, NULL);
  for (int i = 0; i < nd; ++i)
    *work += (m->q[i] - m->q0[i]) * fd[i];
}

/* The final static equilibrium for the inputs held from t_motion_end on (the residual's
 * reference), unless the caller gave it; the transient's state is kept. */
static ea_status_t ea__fe_sim_final_static(ea_fe_model_t *m, const ea_fe_drive_t *drive,
                                           const ea_fe_sim_settings_t *s, double th0_hold,
                                           double cab_hold, ea_fe_sim_info_t *info,
                                           ea_error_t *err) {
  const int nd = m->nd;
  if (isfinite(s->tip_static[0]) && isfinite(s->tip_static[1])) {
    info->tip_static[0] = s->tip_static[0];
    info->tip_static[1] = s->tip_static[1];
    info->tip_static[2] = NAN;
    return EA_OK;
  }
  double th_e, th_er, cab_e;
  ea__fe_drive_at(drive, s->t_motion_end, th0_hold, cab_hold, &th_e, &th_er, &cab_e);
  if (m->phase == EA_FE_CABLE_NONE) cab_e = 0.0;
  memcpy(m->q0, m->q, sizeof(double) * (size_t)nd);
  memcpy(m->v0, m->v, sizeof(double) * (size_t)nd);
  double *qstat = m->qs;
  memcpy(qstat, m->q, sizeof(double) * (size_t)nd);
  qstat[2] = th_e;
  ea_fe_static_info_t si;
  const ea_status_t st = ea__fe_newton_q(m, qstat, m->phase, cab_e, &si, err);
  if (st) return st;
  memcpy(info->tip_static, qstat + nd - 3, 3 * sizeof(double));
  memcpy(m->q, m->q0, sizeof(double) * (size_t)nd);
  memcpy(m->v, m->v0, sizeof(double) * (size_t)nd);
  return EA_OK;
}

/* The drive's values for the step t0 -> t1: theta0 and its rate at t1 (and its acceleration
 * for generalized-alpha), the cable value where the scheme evaluates the forces (cm) and at
 * t1 (cab1), checked. */
static ea_status_t ea__fe_step_drive(const ea_fe_model_t *m, const ea_fe_drive_t *drive,
                                     const ea_fe_sim_settings_t *s, const ea__fe_galpha_t *g,
                                     double t0, double t1, double th0_hold, double cab_hold,
                                     double v[5], ea_error_t *err) {
  const int galpha = s->scheme == EA_FE_SCHEME_GENALPHA;
  /* cable value where the scheme evaluates the forces: the midpoint, or t_{n+1-af} */
  const double tc = galpha ? t0 + (1.0 - g->af) * s->dt : 0.5 * (t0 + t1);
  double dum;
  v[2] = 0.0;
  if (ea__fe_drive_at(drive, t1, th0_hold, cab_hold, &v[0], &v[1], &v[4]) ||
      ea__fe_drive_at(drive, tc, th0_hold, cab_hold, &dum, &dum, &v[3]) ||
      (galpha && ea__fe_drive_acc(drive, t1, s->dt, th0_hold, cab_hold, &v[2])))
    return ea_error_set(err, EA_ERR_INTERRUPTED, "simulate: drive failed at t = %g", t1);
  if (m->phase == EA_FE_CABLE_NONE) v[3] = v[4] = 0.0;
  if (m->phase == EA_FE_CABLE_PASSIVE && !(v[3] > 0.0))
    return ea_error_set(err, EA_ERR_INPUT, "simulate: rest length %g <= 0 at t = %g", v[3], tc);
  if (m->phase == EA_FE_CABLE_ACTIVE && !(v[3] >= 0.0))
    return ea_error_set(err, EA_ERR_INPUT, "simulate: tension %g < 0 at t = %g", v[3], tc);
  return EA_OK;
}

/* One output row at time t: the tip (x, y, theta) and, with output_loads, the shoulder
 * torque (minus the clamp's theta row of the internal force plus the strain-rate damping
 * force: the moment the beam carries at the clamp, EI kappa0 at rest) and the cable
 * tension. m->fm is the steps' scratch vector: free between steps. */
static void ea__fe_sim_row(ea_fe_model_t *m, const ea_fe_sim_settings_t *s, double t, double *r) {
  const int nd = m->nd;
  r[0] = t;
  memcpy(r + 1, m->q + nd - 3, 3 * sizeof(double));
  if (!s->output_loads) return;
  ea__fe_assemble(m, m->q, m->phase, m->cable_value, m->fm, NULL);
  ea__fe_assemble_rate(m, m->q, m->v, s->rayleigh_stiffness, m->fm, NULL);
  r[4] = -m->fm[2];
  double T = 0.0;
  ea__fe_cable(m, m->phase, m->cable_value, m->q[nd - 3], m->q[nd - 2], &T, NULL, NULL, NULL);
  r[5] = T;
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
  const double wall0 = ea__mono_s();
  const int nd = m->nd;
  const double h = s->dt;
  const int nsteps = (int)ceil(s->t_end / h - 1e-9);
  const ea_fe_cable_phase_t phase = m->phase;
  const double th0_hold = m->q[2], cab_hold = m->cable_value;
  const int galpha = s->scheme == EA_FE_SCHEME_GENALPHA;
  const ea__fe_galpha_t g = ea__fe_galpha(s->rho_inf);
  if ((st = ea__fe_sim_start(m, drive, s, th0_hold, cab_hold, err))) return info->status = st;
  const int damped = s->rayleigh_mass > 0.0;
  const double bkv = s->rayleigh_stiffness;
  const double E0 = ea_fe_energy(m);
  info->energy_start = E0;
  int rows = 0;
  const int cols = s->output_loads ? 6 : 4;
  if (tip && rows < tip_rows) ea__fe_sim_row(m, s, 0.0, tip + cols * rows++);
  const int measure = s->t_motion_end >= 0.0 && s->t_motion_end < s->t_end;
  int have_static = 0;
  info->tension_min = INFINITY;
  info->tension_max = -INFINITY;
  double sum2 = 0.0, peak = 0.0;
  int nres = 0;
  for (int n = 0; n < nsteps; ++n) {
    const double t0 = n * h, t1 = (n + 1) * h;
    double dv[5]; /* theta0, its rate and acceleration at t1; cable value at tc and t1 */
    if ((st = ea__fe_step_drive(m, drive, s, &g, t0, t1, th0_hold, cab_hold, dv, err))) break;
    memcpy(m->q0, m->q, sizeof(double) * (size_t)nd);
    memcpy(m->v0, m->v, sizeof(double) * (size_t)nd);
    int it = 0;
    if (galpha) {
      memcpy(m->acc0, m->acc, sizeof(double) * (size_t)nd);
      st =
          ea__fe_step_galpha(m, s, &g, damped, bkv, phase, dv[3], dv[0], dv[1], dv[2], n == 0, &it);
      memcpy(m->qprev, m->q0, sizeof(double) * (size_t)nd);
    } else {
      st = ea__fe_step_energy(m, s, damped, bkv, phase, m->cable_value, dv[3], dv[4], dv[0], dv[1],
                              &it);
    }
    info->newton_iterations += it;
    if (it > info->max_step_iterations) info->max_step_iterations = it;
    if (st) {
      ea_error_set(err, st, "simulate: step %d (t = %g) did not converge in %d iterations", n + 1,
                   t1, it);
      break;
    }
    /* the state at t1 goes with the cable value at t1 (both schemes) */
    if (phase != EA_FE_CABLE_NONE) m->cable_value = dv[4];
    info->steps = n + 1;
    if (damped || bkv > 0.0)
      ea__fe_damping_work(m, s, galpha ? 1.0 - g.af : 0.5, &info->damping_work);
    const double E = ea_fe_energy(m), K = ea__fe_kinetic(m, m->v);
    if (!isfinite(E)) {
      st = ea_error_set(err, EA_ERR_NOCONV, "simulate: state not finite at t = %g", t1);
      break;
    }
    info->energy_drift_max = fmax(info->energy_drift_max, fabs(E - E0));
    info->kinetic_max = fmax(info->kinetic_max, K);
    {
      double T = 0.0;
      ea__fe_cable(m, phase, m->cable_value, m->q[nd - 3], m->q[nd - 2], &T, NULL, NULL, NULL);
      if (T < info->tension_min) info->tension_min = T, info->tension_min_time = t1;
      if (T > info->tension_max) info->tension_max = T, info->tension_max_time = t1;
    }
    if (tip && rows < tip_rows && ((n + 1) % s->output_every == 0 || n + 1 == nsteps))
      ea__fe_sim_row(m, s, t1, tip + cols * rows++);
    if (measure && t1 >= s->t_motion_end - 1e-12 * h) {
      if (!have_static) {
        if ((st = ea__fe_sim_final_static(m, drive, s, th0_hold, cab_hold, info, err))) break;
        have_static = 1;
      }
      const double d =
          hypot(m->q[nd - 3] - info->tip_static[0], m->q[nd - 2] - info->tip_static[1]);
      sum2 += d * d;
      peak = fmax(peak, d);
      ++nres;
    }
  }
  info->rows = rows;
  if (info->steps == 0) info->tension_min = info->tension_max = NAN;
  info->energy_end = ea_fe_energy(m);
  if (nres > 0) {
    info->residual_rms = sqrt(sum2 / nres);
    info->residual_peak = peak;
  }
  info->time_s = ea__mono_s() - wall0;
  info->status = st;
  m->modes_valid = 0;
  return st;
}
