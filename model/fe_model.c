/* Finite element model: settings, allocation, state, assembly, band algebra. */
#include "fe_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void ea_fe_settings_default(ea_fe_settings_t *s) {
  if (!s) return;
  s->elements = EA_FE_DEFAULT_ELEMENTS;
  s->modes = 3;
  s->newton_tol = 1e-6;
  s->newton_max_iter = 50;
  s->eig_backend = EA_FE_EIG_LANCZOS;
  s->static_hold_tip = 0;
}

ea_status_t ea_fe_settings_validate(const ea_fe_settings_t *s, ea_error_t *err) {
  if (!s) return ea_error_set(err, EA_ERR_ARG, "fe settings are NULL");
  if (s->elements < 1 || s->elements > 10000)
    return ea_error_set(err, EA_ERR_ARG, "fe elements = %d: must be in [1, 10000]", s->elements);
  if (s->modes < 1 || s->modes > EA_FE_MAX_MODES || s->modes > 6 * s->elements)
    return ea_error_set(err, EA_ERR_ARG, "fe modes = %d: must be in [1, %d] and <= 6 elements",
                        s->modes, EA_FE_MAX_MODES);
  if (!isfinite(s->newton_tol) || !(s->newton_tol > 0.0))
    return ea_error_set(err, EA_ERR_ARG, "fe newton_tol = %g: must be > 0", s->newton_tol);
  if (s->newton_max_iter < 1)
    return ea_error_set(err, EA_ERR_ARG, "fe newton_max_iter = %d: must be >= 1",
                        s->newton_max_iter);
  if ((int)s->eig_backend < 0 || s->eig_backend >= EA_FE_EIG_COUNT)
    return ea_error_set(err, EA_ERR_ARG, "fe eig_backend = %d: unknown", (int)s->eig_backend);
  return EA_OK;
}

static void ea__fe_quad_fill(ea__fe_quad_t *qd, int n, double h) {
  static const double x2[2] = {-0.57735026918962576451, 0.57735026918962576451};
  static const double w2[2] = {1.0, 1.0};
  static const double x3[3] = {-0.77459666924148337704, 0.0, 0.77459666924148337704};
  static const double w3[3] = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
  qd->n = n;
  for (int g = 0; g < n; ++g) {
    const double xi = (n == 2) ? x2[g] : x3[g];
    qd->w[g] = ((n == 2) ? w2[g] : w3[g]) * 0.5 * h;
    qd->N[g][0] = 0.5 * xi * (xi - 1.0);
    qd->N[g][1] = 1.0 - xi * xi;
    qd->N[g][2] = 0.5 * xi * (xi + 1.0);
    qd->dN[g][0] = (xi - 0.5) * 2.0 / h;
    qd->dN[g][1] = -2.0 * xi * 2.0 / h;
    qd->dN[g][2] = (xi + 0.5) * 2.0 / h;
  }
}

/* Mass matrix (band) and gravity load for the current tip mass. */
static void ea__fe_build_mass(ea_fe_model_t *m) {
  memset(m->Mb, 0, sizeof(double) * EA__FE_LDS * (size_t)m->nd);
  memset(m->fg, 0, sizeof(double) * (size_t)m->nd);
  const ea__fe_quad_t *qd = &m->quad_m;
  for (int e = 0; e < m->ne; ++e) {
    const int o = 6 * e;
    for (int g = 0; g < qd->n; ++g)
      for (int a = 0; a < 3; ++a) {
        m->fg[o + 3 * a + 1] -= m->arm.rho * m->arm.g * qd->w[g] * qd->N[g][a];
        for (int b = a; b < 3; ++b) {
          const double nn = qd->w[g] * qd->N[g][a] * qd->N[g][b];
          EA__SB(m->Mb, o + 3 * a, o + 3 * b) += m->arm.rho * nn;
          EA__SB(m->Mb, o + 3 * a + 1, o + 3 * b + 1) += m->arm.rho * nn;
          EA__SB(m->Mb, o + 3 * a + 2, o + 3 * b + 2) += m->arm.I_zz * nn;
        }
      }
  }
  const int t = m->nd - 3;
  EA__SB(m->Mb, t, t) += m->tip_mass;
  EA__SB(m->Mb, t + 1, t + 1) += m->tip_mass;
  EA__SB(m->Mb, t + 2, t + 2) += m->arm.I_hand;
  m->fg[t + 1] -= m->tip_mass * m->arm.g;
}

void ea_fe_model_free(ea_fe_model_t *m) {
  if (!m) return;
  double *dp[] = {m->q,  m->v,    m->fg,  m->Mb,   m->Kb,    m->fi,  m->r,    m->dq,    m->Gb,
                  m->Ab, m->Bb,   m->Ad,  m->Bd,   m->Z,     m->Qw,  m->work, m->evals, m->phi,
                  m->q0, m->v0,   m->a0,  m->qm,   m->fm,    m->tmp, m->Cb,   m->qs,    m->vs,
                  m->Kt, m->rhs3, m->acc, m->acc0, m->qprev, m->lz};
  for (size_t i = 0; i < sizeof dp / sizeof dp[0]; ++i)
    free(dp[i]);
  free(m->ipiv);
  free(m->iwork);
  free(m->ifail);
  if (m->gws) gsl_eigen_gensymmv_free(m->gws);
  if (m->gA) gsl_matrix_free(m->gA);
  if (m->gB) gsl_matrix_free(m->gB);
  if (m->gevec) gsl_matrix_free(m->gevec);
  if (m->geval) gsl_vector_free(m->geval);
  free(m);
}

ea_status_t ea_fe_model_alloc(const ea_arm_t *arm, const ea_fe_settings_t *s, ea_fe_model_t **out,
                              ea_error_t *err) {
  if (!out) return ea_error_set(err, EA_ERR_ARG, "out is NULL");
  *out = NULL;
  ea_status_t st = ea_arm_validate(arm, err);
  if (st) return st;
  ea_fe_settings_t set;
  if (s)
    set = *s;
  else
    ea_fe_settings_default(&set);
  if ((st = ea_fe_settings_validate(&set, err))) return st;
  ea_fe_model_t *m = calloc(1, sizeof *m);
  if (!m) return ea_error_set(err, EA_ERR_NOMEM, "fe model");
  m->arm = *arm;
  m->set = set;
  m->tip_mass = arm->m_hand;
  m->ne = set.elements;
  m->nn = 2 * m->ne + 1;
  m->nd = 3 * m->nn;
  m->nf = m->nd - 3;
  m->h = arm->length / m->ne;
  ea__fe_quad_fill(&m->quad_k, 2, m->h);
  ea__fe_quad_fill(&m->quad_m, 3, m->h);
  const size_t nd = (size_t)m->nd, nf = (size_t)m->nf;
  /* dsygv workspace query */
  int lw = -1, info = 0, n = m->nf, itype = 1;
  double wq = 0.0, dummy = 0.0;
  dsygv_(&itype, "V", "U", &n, &dummy, &n, &dummy, &n, &dummy, &wq, &lw, &info, 1, 1);
  m->lwork = (info == 0 && wq > 0) ? (int)wq : 64 * n;
  if (m->lwork < 3 * n) m->lwork = 3 * n;
  const size_t lwork = (size_t)m->lwork > 8 * nf ? (size_t)m->lwork : 8 * nf;
  int ok = 1;
#define EA__ALLOC(p, cnt) ok = ok && ((p) = calloc((cnt), sizeof *(p))) != NULL
  EA__ALLOC(m->q, nd);
  EA__ALLOC(m->v, nd);
  EA__ALLOC(m->fg, nd);
  EA__ALLOC(m->Mb, EA__FE_LDS * nd);
  EA__ALLOC(m->Kb, EA__FE_LDS * nd);
  EA__ALLOC(m->Kt, EA__FE_LDS * nd);
  EA__ALLOC(m->Cb, EA__FE_LDS * nd);
  EA__ALLOC(m->fi, nd);
  EA__ALLOC(m->r, nf);
  EA__ALLOC(m->dq, nf);
  EA__ALLOC(m->rhs3, 3 * nf);
  EA__ALLOC(m->Gb, EA__FE_LDG * nf);
  EA__ALLOC(m->ipiv, nf);
  EA__ALLOC(m->Ab, EA__FE_LDS * nf);
  EA__ALLOC(m->Bb, EA__FE_LDS * nf);
  EA__ALLOC(m->Z, nf * nf);
  EA__ALLOC(m->Qw, nf * nf);
  EA__ALLOC(m->work, lwork);
  EA__ALLOC(m->iwork, 5 * nf);
  EA__ALLOC(m->ifail, nf);
  EA__ALLOC(m->evals, nf);
  EA__ALLOC(m->lz, (EA_FE_MAX_MODES + 12) * nf);
  EA__ALLOC(m->phi, (size_t)EA_FE_MAX_MODES * nd);
  EA__ALLOC(m->q0, nd);
  EA__ALLOC(m->v0, nd);
  EA__ALLOC(m->a0, nd);
  EA__ALLOC(m->qm, nd);
  EA__ALLOC(m->fm, nd);
  EA__ALLOC(m->tmp, nd);
  EA__ALLOC(m->qs, nd);
  EA__ALLOC(m->vs, nd);
  EA__ALLOC(m->acc, nd);
  EA__ALLOC(m->acc0, nd);
  EA__ALLOC(m->qprev, nd);
  if (set.eig_backend == EA_FE_EIG_DSYGV || set.eig_backend == EA_FE_EIG_GSL) {
    EA__ALLOC(m->Ad, nf * nf);
    EA__ALLOC(m->Bd, nf * nf);
  }
#undef EA__ALLOC
  if (ok && set.eig_backend == EA_FE_EIG_GSL) {
    m->gws = gsl_eigen_gensymmv_alloc(nf);
    m->gA = gsl_matrix_alloc(nf, nf);
    m->gB = gsl_matrix_alloc(nf, nf);
    m->gevec = gsl_matrix_alloc(nf, nf);
    m->geval = gsl_vector_alloc(nf);
    ok = m->gws && m->gA && m->gB && m->gevec && m->geval;
  }
  if (!ok) {
    ea_fe_model_free(m);
    return ea_error_set(err, EA_ERR_NOMEM, "fe model with %d elements", set.elements);
  }
  ea__fe_build_mass(m);
  ea_fe_set_straight(m, 0.0);
  *out = m;
  return EA_OK;
}

ea_status_t ea_fe_model_set_load(ea_fe_model_t *m, const ea_load_t *load) {
  if (!m || !load) return EA_ERR_ARG;
  if (!isfinite(load->tip_mass) || load->tip_mass < 0.0) return EA_ERR_ARG;
  m->tip_mass = load->tip_mass;
  m->modes_valid = 0;
  ea__fe_build_mass(m);
  return EA_OK;
}

int ea_fe_model_nodes(const ea_fe_model_t *m) {
  return m ? m->nn : 0;
}
const ea_arm_t *ea_fe_model_arm(const ea_fe_model_t *m) {
  return m ? &m->arm : NULL;
}
const ea_fe_settings_t *ea_fe_model_settings(const ea_fe_model_t *m) {
  return m ? &m->set : NULL;
}

ea_status_t ea_fe_set_straight(ea_fe_model_t *m, double theta0) {
  if (!m || !isfinite(theta0)) return EA_ERR_ARG;
  const double c = cos(theta0), s = sin(theta0);
  for (int i = 0; i < m->nn; ++i) {
    const double si = m->arm.length * i / (m->nn - 1);
    m->q[3 * i] = si * c;
    m->q[3 * i + 1] = si * s;
    m->q[3 * i + 2] = theta0;
  }
  memset(m->v, 0, sizeof(double) * (size_t)m->nd);
  m->phase = EA_FE_CABLE_NONE;
  m->cable_value = 0.0;
  m->modes_valid = 0;
  return EA_OK;
}

ea_status_t ea_fe_set_cable(ea_fe_model_t *m, ea_fe_cable_phase_t phase, double value) {
  if (!m) return EA_ERR_ARG;
  if (phase == EA_FE_CABLE_ACTIVE && !(isfinite(value) && value >= 0.0)) return EA_ERR_ARG;
  if (phase == EA_FE_CABLE_PASSIVE && !(isfinite(value) && value > 0.0)) return EA_ERR_ARG;
  if (phase != EA_FE_CABLE_NONE && phase != EA_FE_CABLE_ACTIVE && phase != EA_FE_CABLE_PASSIVE)
    return EA_ERR_ARG;
  m->phase = phase;
  m->cable_value = (phase == EA_FE_CABLE_NONE) ? 0.0 : value;
  m->modes_valid = 0;
  return EA_OK;
}

double ea_fe_cable_rest_length(double length, double tension, double EA_cable) {
  return length / (1.0 + tension / EA_cable);
}

void ea__fe_passive_equiv(const ea_fe_model_t *m, const double *q, ea_fe_cable_phase_t *phase,
                          double *value) {
  *phase = m->phase;
  *value = m->cable_value;
  if (m->phase == EA_FE_CABLE_ACTIVE) {
    const double *t = q + m->nd - 3;
    const double l = hypot(m->arm.x_c - t[0], m->arm.y_c - t[1]);
    *phase = EA_FE_CABLE_PASSIVE;
    *value = ea_fe_cable_rest_length(l, m->cable_value, m->arm.EA_cable);
  }
}

ea_status_t ea_fe_cable_make_passive(ea_fe_model_t *m) {
  if (!m) return EA_ERR_ARG;
  ea__fe_passive_equiv(m, m->q, &m->phase, &m->cable_value);
  return EA_OK;
}

void ea_fe_cable_get(const ea_fe_model_t *m, ea_fe_cable_phase_t *phase, double *value,
                     double *tension, double *length) {
  if (!m) return;
  const double *t = m->q + m->nd - 3;
  double T = 0.0, l = 0.0;
  ea__fe_cable(m, m->phase, m->cable_value, t[0], t[1], &T, &l, NULL, NULL);
  if (phase) *phase = m->phase;
  if (value) *value = m->cable_value;
  if (tension) *tension = T;
  if (length) *length = l;
}

ea_status_t ea_fe_get_state(const ea_fe_model_t *m, double *q, double *v) {
  if (!m) return EA_ERR_ARG;
  if (q) memcpy(q, m->q, sizeof(double) * (size_t)m->nd);
  if (v) memcpy(v, m->v, sizeof(double) * (size_t)m->nd);
  return EA_OK;
}

ea_status_t ea_fe_set_state(ea_fe_model_t *m, const double *q, const double *v) {
  if (!m || !q) return EA_ERR_ARG;
  for (int i = 0; i < m->nd; ++i)
    if (!isfinite(q[i]) || (v && !isfinite(v[i]))) return EA_ERR_ARG;
  memcpy(m->q, q, sizeof(double) * (size_t)m->nd);
  m->q[0] = m->q[1] = 0.0;
  if (v)
    memcpy(m->v, v, sizeof(double) * (size_t)m->nd);
  else
    memset(m->v, 0, sizeof(double) * (size_t)m->nd);
  m->modes_valid = 0;
  return EA_OK;
}

void ea_fe_tip(const ea_fe_model_t *m, double tip[3]) {
  if (!m || !tip) return;
  memcpy(tip, m->q + m->nd - 3, 3 * sizeof(double));
}

/* ---- assembly ---------------------------------------------------------- */

double ea__fe_assemble(ea_fe_model_t *m, const double *q, ea_fe_cable_phase_t phase, double value,
                       double *fi, double *Kb) {
  double V = 0.0, fe[9], ke[81];
  memset(fi, 0, sizeof(double) * (size_t)m->nd);
  if (Kb) memset(Kb, 0, sizeof(double) * EA__FE_LDS * (size_t)m->nd);
  for (int e = 0; e < m->ne; ++e) {
    const int o = 6 * e;
    V += ea__fe_beam_element(m, q + o, fe, Kb ? ke : NULL);
    for (int i = 0; i < 9; ++i)
      fi[o + i] += fe[i];
    if (Kb)
      for (int i = 0; i < 9; ++i)
        for (int j = i; j < 9; ++j)
          EA__SB(Kb, o + i, o + j) += ke[9 * i + j];
  }
  /* gravity: potential -fg . q, gradient -fg */
  for (int i = 0; i < m->nd; ++i) {
    V -= m->fg[i] * q[i];
    fi[i] -= m->fg[i];
  }
  const int t = m->nd - 3;
  double fc[2] = {0, 0}, kc[4];
  V += ea__fe_cable(m, phase, value, q[t], q[t + 1], NULL, NULL, fc, Kb ? kc : NULL);
  fi[t] -= fc[0];
  fi[t + 1] -= fc[1];
  double fe2 = 0.0;
  for (int i = 3; i < m->nd; ++i) {
    double f = m->fg[i];
    if (i == t) f += fc[0];
    if (i == t + 1) f += fc[1];
    fe2 += f * f;
  }
  m->fext_norm = sqrt(fe2);
  if (Kb) {
    EA__SB(Kb, t, t) += kc[0];
    EA__SB(Kb, t, t + 1) += kc[1];
    EA__SB(Kb, t + 1, t + 1) += kc[3];
  }
  return V;
}

double ea__fe_potential(const ea_fe_model_t *m, const double *q, ea_fe_cable_phase_t phase,
                        double value) {
  double V = 0.0, fe[9];
  for (int e = 0; e < m->ne; ++e)
    V += ea__fe_beam_element(m, q + 6 * e, fe, NULL);
  for (int i = 0; i < m->nd; ++i)
    V -= m->fg[i] * q[i];
  const int t = m->nd - 3;
  V += ea__fe_cable(m, phase, value, q[t], q[t + 1], NULL, NULL, NULL, NULL);
  return V;
}

double ea_fe_energy(const ea_fe_model_t *m) {
  if (!m) return NAN;
  double T = 0.0;
  for (int j = 0; j < m->nd; ++j)
    for (int i = (j > EA__FE_KD ? j - EA__FE_KD : 0); i <= j; ++i) {
      const double a = EA__SB(m->Mb, i, j);
      T += (i == j) ? 0.5 * a * m->v[i] * m->v[i] : a * m->v[i] * m->v[j];
    }
  return T + ea__fe_potential(m, m->q, m->phase, m->cable_value);
}

void ea__fe_band_axpy(const ea_fe_model_t *m, double s, const double *A, double *B) {
  const size_t n = EA__FE_LDS * (size_t)m->nd;
  for (size_t i = 0; i < n; ++i)
    B[i] += s * A[i];
}

void ea__fe_band_gemv(const ea_fe_model_t *m, double s, const double *A, const double *x,
                      double *y) {
  for (int j = 0; j < m->nd; ++j)
    for (int i = (j > EA__FE_KD ? j - EA__FE_KD : 0); i <= j; ++i) {
      const double a = s * EA__SB(A, i, j);
      y[i] += a * x[j];
      if (i != j) y[j] += a * x[i];
    }
}

ea_status_t ea__fe_factor_free(ea_fe_model_t *m, const double *Kb) {
  const int n = m->nf, kd = EA__FE_KD, ldg = EA__FE_LDG;
  memset(m->Gb, 0, sizeof(double) * EA__FE_LDG * (size_t)n);
  for (int j = 0; j < n; ++j)
    for (int i = (j > kd ? j - kd : 0); i <= j; ++i) {
      const double a = EA__SB(Kb, i + 3, j + 3);
      m->Gb[(2 * kd + i - j) + (size_t)j * ldg] = a;
      m->Gb[(2 * kd + j - i) + (size_t)i * ldg] = a;
    }
  int info = 0;
  dgbtrf_(&n, &n, &kd, &kd, m->Gb, &ldg, m->ipiv, &info);
  return info == 0 ? EA_OK : EA_ERR_SINGULAR;
}

ea_status_t ea__fe_solve_factored(ea_fe_model_t *m, double *b, int nrhs) {
  const int n = m->nf, kd = EA__FE_KD, ldg = EA__FE_LDG;
  int info = 0;
  dgbtrs_("N", &n, &kd, &kd, &nrhs, m->Gb, &ldg, m->ipiv, b, &n, &info, 1);
  return info == 0 ? EA_OK : EA_ERR_BACKEND;
}

ea_status_t ea__fe_solve_free(ea_fe_model_t *m, const double *Kb) {
  const int n = m->nf, kd = EA__FE_KD, ldg = EA__FE_LDG, one = 1;
  memset(m->Gb, 0, sizeof(double) * EA__FE_LDG * (size_t)n);
  for (int j = 0; j < n; ++j)
    for (int i = (j > kd ? j - kd : 0); i <= j; ++i) {
      const double a = EA__SB(Kb, i + 3, j + 3);
      m->Gb[(2 * kd + i - j) + (size_t)j * ldg] = a; /* upper (i <= j) */
      m->Gb[(2 * kd + j - i) + (size_t)i * ldg] = a; /* lower (j, i) */
    }
  int info = 0;
  dgbtrf_(&n, &n, &kd, &kd, m->Gb, &ldg, m->ipiv, &info);
  if (info != 0) return EA_ERR_SINGULAR;
  memcpy(m->dq, m->r, sizeof(double) * (size_t)n);
  dgbtrs_("N", &n, &kd, &kd, &one, m->Gb, &ldg, m->ipiv, m->dq, &n, &info, 1);
  return info == 0 ? EA_OK : EA_ERR_BACKEND;
}

void ea__fe_assemble_rate(ea_fe_model_t *m, const double *q, const double *v, double b, double *fd,
                          double *Cb) {
  double fe[9], ce[81];
  if (!(b > 0.0)) return;
  for (int e = 0; e < m->ne; ++e) {
    const int o = 6 * e;
    ea__fe_beam_rate(m, q + o, v + o, fe, Cb ? ce : NULL);
    for (int i = 0; i < 9; ++i)
      fd[o + i] += b * fe[i];
    if (Cb)
      for (int i = 0; i < 9; ++i)
        for (int j = i; j < 9; ++j)
          EA__SB(Cb, o + i, o + j) += b * ce[9 * i + j];
  }
}
