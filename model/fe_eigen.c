/* Finite element model: natural frequencies (paper eq. 24) and stability. */
#include "fe_impl.h"

#include <float.h>
#include <math.h>
#include <string.h>

#include <gsl/gsl_errno.h>

#define EA__SB(A, i, j) (A)[(EA__FE_KD + (i) - (j)) + (size_t)(j) * EA__FE_LDS]

/* Free-DOF block of a full symmetric band matrix into a free band (LDS x nf). */
static void ea__fe_band_free(const ea_fe_model_t *m, const double *full, double *fr) {
  memset(fr, 0, sizeof(double) * EA__FE_LDS * (size_t)m->nf);
  for (int j = 0; j < m->nf; ++j)
    for (int i = (j > EA__FE_KD ? j - EA__FE_KD : 0); i <= j; ++i)
      EA__SB(fr, i, j) = EA__SB(full, i + 3, j + 3);
}

/* Dense (column-major, both triangles) copy of a free band. */
static void ea__fe_band_dense(const ea_fe_model_t *m, const double *fr, double *d) {
  const size_t n = (size_t)m->nf;
  memset(d, 0, sizeof(double) * n * n);
  for (size_t j = 0; j < n; ++j)
    for (size_t i = (j > EA__FE_KD ? j - EA__FE_KD : 0); i <= j; ++i)
      d[i + j * n] = d[j + i * n] = EA__SB(fr, i, j);
}

/* Passive stiffness (free band in m->Ab) and mass (m->Bb) at the current state. */
static void ea__fe_passive_free(ea_fe_model_t *m) {
  ea_fe_cable_phase_t ph;
  double val;
  ea__fe_passive_equiv(m, m->q, &ph, &val);
  ea__fe_assemble(m, m->q, ph, val, m->fi, m->Kb);
  ea__fe_band_free(m, m->Kb, m->Ab);
  ea__fe_band_free(m, m->Mb, m->Bb);
}

/* Cholesky of the free stiffness band in m->Ab (copied to m->Gb). */
static int ea__fe_posdef(ea_fe_model_t *m) {
  const int n = m->nf, kd = EA__FE_KD, ld = EA__FE_LDS;
  memcpy(m->Gb, m->Ab, sizeof(double) * EA__FE_LDS * (size_t)n);
  int info = 0;
  dpbtrf_("U", &n, &kd, m->Gb, &ld, &info, 1);
  return info == 0;
}

ea_status_t ea_fe_stability(ea_fe_model_t *m, int *stable, ea_error_t *err) {
  if (!m || !stable) return ea_error_set(err, EA_ERR_ARG, "fe stability: NULL argument");
  ea__fe_passive_free(m);
  *stable = ea__fe_posdef(m);
  return EA_OK;
}

/* Mode shape of the eigenvalue lam (computed already) by inverse iteration on
 * the band pencil: (K - lam M) z_{i+1} = M z_i, M-orthogonalized against the
 * modes 0 .. j-1 already in m->Z, 3 iterations (the shift is the eigenvalue to
 * rounding, so one iteration already gives the vector to rounding; the others
 * guard against an unlucky start). K - lam M is factored by the general band
 * LU of the free block (m->Gb); K is the full passive stiffness in m->Kb.
 * Writes column j of m->Z (length nf). */
static ea_status_t ea__fe_inverse_iteration(ea_fe_model_t *m, double lam, int j) {
  const int n = m->nf, nd = m->nd, kd = EA__FE_KD, ldg = EA__FE_LDG, one = 1;
  memset(m->Gb, 0, sizeof(double) * EA__FE_LDG * (size_t)n);
  for (int c = 0; c < n; ++c)
    for (int i = (c > kd ? c - kd : 0); i <= c; ++i) {
      const double a = EA__SB(m->Kb, i + 3, c + 3) - lam * EA__SB(m->Mb, i + 3, c + 3);
      m->Gb[(2 * kd + i - c) + (size_t)c * ldg] = a;
      m->Gb[(2 * kd + c - i) + (size_t)i * ldg] = a;
    }
  int info = 0;
  dgbtrf_(&n, &n, &kd, &kd, m->Gb, &ldg, m->ipiv, &info);
  if (info < 0) return EA_ERR_BACKEND;
  if (info > 0) { /* exactly singular at this shift: move it by a few ulp of lam */
    const double l2 = lam + 1e-13 * (fabs(lam) + 1.0);
    return l2 != lam ? ea__fe_inverse_iteration(m, l2, j) : EA_ERR_BACKEND;
  }
  double *z = m->Z + (size_t)j * n, *xf = m->qs, *yf = m->vs; /* full-length work */
  for (int i = 0; i < n; ++i) z[i] = 1.0 + 0.1 * sin(1.3 * i + 0.7 * j); /* deterministic start */
  for (int it = 0; it < 3; ++it) {
    memset(xf, 0, sizeof(double) * (size_t)nd);
    memset(yf, 0, sizeof(double) * (size_t)nd);
    memcpy(xf + 3, z, sizeof(double) * (size_t)n);
    ea__fe_band_gemv(m, 1.0, m->Mb, xf, yf); /* M z (clamp entries of z are 0) */
    memcpy(z, yf + 3, sizeof(double) * (size_t)n);
    dgbtrs_("N", &n, &kd, &kd, &one, m->Gb, &ldg, m->ipiv, z, &n, &info, 1);
    if (info != 0) return EA_ERR_BACKEND;
    /* M-orthogonalize against the lower modes, normalize to max |z| = 1 */
    for (int p = 0; p < j; ++p) {
      const double *zp = m->Z + (size_t)p * n;
      memset(xf, 0, sizeof(double) * (size_t)nd);
      memset(yf, 0, sizeof(double) * (size_t)nd);
      memcpy(xf + 3, zp, sizeof(double) * (size_t)n);
      ea__fe_band_gemv(m, 1.0, m->Mb, xf, yf);
      double pz = 0.0, pp = 0.0;
      for (int i = 0; i < n; ++i) {
        pz += yf[i + 3] * z[i];
        pp += yf[i + 3] * zp[i];
      }
      if (pp > 0.0)
        for (int i = 0; i < n; ++i) z[i] -= pz / pp * zp[i];
    }
    double zmax = 0.0;
    for (int i = 0; i < n; ++i) zmax = fmax(zmax, fabs(z[i]));
    if (!(zmax > 0.0) || !isfinite(zmax)) return EA_ERR_BACKEND;
    for (int i = 0; i < n; ++i) z[i] /= zmax;
  }
  return EA_OK;
}

/* The low modes are computed from the inverted pencil
 *   M v = mu (K + sigma M) v,   lambda = omega^2 = 1/mu - sigma,
 * taking the k largest mu. K + sigma M is factored by Cholesky (its errors are
 * eps |K|, which moves the low omega^2 by a relative ~eps cond-free amount),
 * whereas a Cholesky of M (tiny rotary inertia I_zz h ~ 1e-9) would amplify
 * rounding in K by 1/min(M) and destroy the low modes. sigma = 0 when K is
 * positive definite (stable), else the smallest power of 10 >= 1 that makes
 * K + sigma M positive definite. M may be singular (I_zz = 0). */
ea_status_t ea_fe_modes(ea_fe_model_t *m, ea_fe_modes_info_t *info, ea_error_t *err) {
  if (!m) return ea_error_set(err, EA_ERR_ARG, "fe modes: model is NULL");
  ea_fe_modes_info_t loc;
  if (!info) info = &loc;
  memset(info, 0, sizeof *info);
  const double t0 = ea__fe_now();
  m->modes_valid = 0;
  ea__fe_passive_free(m);
  info->stable = ea__fe_posdef(m);
  double sigma = 0.0;
  if (!info->stable) {
    /* shift until K + sigma M is positive definite */
    double *K0 = m->Qw; /* spare: LDS x nf fits in nf x nf for nf >= LDS */
    const size_t nb = EA__FE_LDS * (size_t)m->nf;
    if ((size_t)m->nf * (size_t)m->nf < nb)
      return ea_error_set(err, EA_ERR_ARG, "fe modes: mesh too small to shift");
    memcpy(K0, m->Ab, sizeof(double) * nb);
    int ok = 0;
    for (sigma = 1.0; sigma < 1e12 && !ok; sigma *= 10.0) {
      for (size_t i = 0; i < nb; ++i) m->Ab[i] = K0[i] + sigma * m->Bb[i];
      ok = ea__fe_posdef(m);
      if (ok) break;
    }
    if (!ok) return ea_error_set(err, EA_ERR_BACKEND, "fe modes: no shift makes K + s M definite");
  }
  /* A := M, B := K + sigma M (swap the band arrays' roles) */
  double *A = m->Bb, *B = m->Ab;
  const double t1 = ea__fe_now();
  const int n = m->nf, k = m->set.modes, kd = EA__FE_KD, ld = EA__FE_LDS;
  int info_l = 0, found = 0;
  ea_status_t st = EA_OK;
  double *mu = m->evals; /* mu of mode j (ascending lambda) at mu[j] after the switch */
  switch (m->set.eig_backend) {
  case EA_FE_EIG_DSBGVX: {
    /* eigenvalues only (JOBZ = 'N': no n x n reduction matrix Q, no back-transformation,
     * which took ~95 % of the time), the k largest mu; vectors below by band inverse
     * iteration on K - lambda M */
    const double vl = 0.0, vu = 0.0, abstol = 2.0 * DBL_MIN;
    const int il = n - k + 1, iu = n, ld1 = 1;
    dsbgvx_("N", "I", "U", &n, &kd, &kd, A, &ld, B, &ld, m->Qw, &ld1, &vl, &vu, &il, &iu,
            &abstol, &found, m->work, m->Z, &ld1, m->work + n, m->iwork,
            m->ifail, &info_l, 1, 1, 1);
    if (info_l != 0 || found < k) {
      st = EA_ERR_BACKEND;
      break;
    }
    /* found ascending mu: reverse into ascending lambda */
    for (int j = 0; j < k; ++j) mu[j] = m->work[k - 1 - j];
    for (int j = 0; j < k && !st; ++j)
      st = ea__fe_inverse_iteration(m, (mu[j] > 0.0) ? 1.0 / mu[j] - sigma : INFINITY, j);
    break;
  }
  case EA_FE_EIG_DSYGV: {
    const int itype = 1;
    ea__fe_band_dense(m, A, m->Ad);
    ea__fe_band_dense(m, B, m->Bd);
    dsygv_(&itype, "V", "U", &n, m->Ad, &n, m->Bd, &n, m->evals, m->work, &m->lwork, &info_l,
           1, 1);
    if (info_l != 0) {
      st = EA_ERR_BACKEND;
      break;
    }
    for (int j = 0; j < k; ++j) {
      memcpy(m->Z + (size_t)j * n, m->Ad + (size_t)(n - 1 - j) * n, sizeof(double) * (size_t)n);
      m->work[j] = m->evals[n - 1 - j];
    }
    for (int j = 0; j < k; ++j) mu[j] = m->work[j];
    break;
  }
  case EA_FE_EIG_GSL: {
    ea__fe_band_dense(m, A, m->gA->data);
    ea__fe_band_dense(m, B, m->gB->data);
    gsl_error_handler_t *old = gsl_set_error_handler_off();
    info_l = gsl_eigen_gensymmv(m->gA, m->gB, m->geval, m->gevec, m->gws);
    if (info_l == GSL_SUCCESS)
      info_l = gsl_eigen_gensymmv_sort(m->geval, m->gevec, GSL_EIGEN_SORT_VAL_DESC);
    gsl_set_error_handler(old);
    if (info_l != GSL_SUCCESS) {
      st = EA_ERR_BACKEND;
      break;
    }
    for (int j = 0; j < k; ++j) {
      mu[j] = gsl_vector_get(m->geval, (size_t)j);
      for (int i = 0; i < n; ++i)
        m->Z[i + (size_t)j * n] = gsl_matrix_get(m->gevec, (size_t)i, (size_t)j);
    }
    break;
  }
  default:
    st = EA_ERR_ARG;
  }
  info->time_assembly_s = t1 - t0;
  info->time_eigen_s = ea__fe_now() - t1;
  info->backend_info = info_l;
  info->status = st;
  if (st)
    return ea_error_set(err, st, "fe modes: eigen-solver failed (backend %d, info %d)",
                        (int)m->set.eig_backend, info_l);
  info->modes = k;
  for (int j = 0; j < k; ++j) {
    const double lam = (mu[j] > 0.0) ? 1.0 / mu[j] - sigma : INFINITY;
    info->lambda[j] = lam;
    m->mode_lambda[j] = lam;
    info->freq_hz[j] = (lam >= 0 ? 1.0 : -1.0) * sqrt(fabs(lam)) / (2.0 * M_PI);
    /* full-length, normalized mode shape */
    double *phi = m->phi + (size_t)j * m->nd;
    phi[0] = phi[1] = phi[2] = 0.0;
    memcpy(phi + 3, m->Z + (size_t)j * n, sizeof(double) * (size_t)n);
    double amax = 0.0;
    int imax = 3;
    for (int i = 3; i < m->nd; ++i)
      if (i % 3 != 2 && fabs(phi[i]) > amax) amax = fabs(phi[i]), imax = i;
    const double ty = phi[m->nd - 2];
    const double sgn =
        (fabs(ty) > 1e-6 * amax) ? (ty > 0 ? 1.0 : -1.0) : (phi[imax] > 0 ? 1.0 : -1.0);
    if (amax > 0)
      for (int i = 0; i < m->nd; ++i) phi[i] *= sgn / amax;
  }
  m->modes_valid = k;
  return EA_OK;
}

ea_status_t ea_fe_mode_shape(const ea_fe_model_t *m, int k, double *phi) {
  if (!m || !phi || k < 0 || k >= m->modes_valid) return EA_ERR_ARG;
  memcpy(phi, m->phi + (size_t)k * m->nd, sizeof(double) * (size_t)m->nd);
  return EA_OK;
}

ea_status_t ea_fe_strain_damping(ea_fe_model_t *m, int k, double zeta, double *b,
                                 double *zeta_modes) {
  if (!m || !b || k < 0 || k >= m->modes_valid || !(zeta >= 0.0) || !isfinite(zeta) ||
      !(m->mode_lambda[k] > 0.0))
    return EA_ERR_ARG;
  const int nd = m->nd;
  const size_t nb = EA__FE_LDS * (size_t)nd;
  double ratio[EA_FE_MAX_MODES]; /* phi' K_mat phi / (omega phi' M phi) */
  memset(m->Kt, 0, sizeof(double) * nb);
  memset(m->tmp, 0, sizeof(double) * (size_t)nd);
  ea__fe_assemble_rate(m, m->q, m->v, 1.0, m->tmp, m->Kt); /* K_mat in m->Kt */
  for (int j = 0; j < m->modes_valid; ++j) {
    const double *phi = m->phi + (size_t)j * nd;
    double *Mp = m->qs, *Kp = m->vs, pm = 0.0, pk = 0.0;
    memset(Mp, 0, sizeof(double) * (size_t)nd);
    memset(Kp, 0, sizeof(double) * (size_t)nd);
    ea__fe_band_gemv(m, 1.0, m->Mb, phi, Mp);
    ea__fe_band_gemv(m, 1.0, m->Kt, phi, Kp);
    for (int i = 0; i < nd; ++i) {
      pm += phi[i] * Mp[i];
      pk += phi[i] * Kp[i];
    }
    const double lam = m->mode_lambda[j];
    ratio[j] = (lam > 0.0 && pm > 0.0) ? pk / (sqrt(lam) * pm) : NAN;
  }
  if (!(ratio[k] > 0.0)) return EA_ERR_ARG;
  /* zeta_j = b phi_j' K_mat phi_j / (2 omega_j phi_j' M phi_j) */
  *b = 2.0 * zeta / ratio[k];
  if (zeta_modes)
    for (int j = 0; j < m->modes_valid; ++j) zeta_modes[j] = 0.5 * *b * ratio[j];
  return EA_OK;
}
