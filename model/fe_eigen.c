/* Finite element model: natural frequencies (paper eq. 24) and stability. */
#include "fe_impl.h"

#include <float.h>
#include <math.h>
#include <string.h>

#include <gsl/gsl_errno.h>

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
  for (int i = 0; i < n; ++i)
    z[i] = 1.0 + 0.1 * sin(1.3 * i + 0.7 * j); /* deterministic start */
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
        for (int i = 0; i < n; ++i)
          z[i] -= pz / pp * zp[i];
    }
    double zmax = 0.0;
    for (int i = 0; i < n; ++i)
      zmax = fmax(zmax, fabs(z[i]));
    if (!(zmax > 0.0) || !isfinite(zmax)) return EA_ERR_BACKEND;
    for (int i = 0; i < n; ++i)
      z[i] /= zmax;
  }
  return EA_OK;
}

/* ---- Lanczos on the inverted pencil ----
 * With U the upper band Cholesky factor of K + sigma M (m->Gb, from the
 * stability check), the wanted modes are the largest eigenvalues mu of the
 * symmetric C = U^-T M U^-1 (y = U v). Band helpers on free-size (nf) vectors. */

/* x := U^-1 x (back substitution, U upper band in LAPACK storage). */
static void ea__fe_band_usolve(int n, const double *U, double *x) {
  const int kd = EA__FE_KD, ld = EA__FE_LDS;
  for (int j = n - 1; j >= 0; --j) {
    const double *col = U + (size_t)j * ld + kd - j; /* col[i] = U(i, j) */
    const double xj = (x[j] /= col[j]);
    for (int i = (j > kd ? j - kd : 0); i < j; ++i)
      x[i] -= col[i] * xj;
  }
}

/* x := U^-T x (forward substitution). */
static void ea__fe_band_utsolve(int n, const double *U, double *x) {
  const int kd = EA__FE_KD, ld = EA__FE_LDS;
  for (int j = 0; j < n; ++j) {
    const double *col = U + (size_t)j * ld + kd - j;
    double s = x[j];
    for (int i = (j > kd ? j - kd : 0); i < j; ++i)
      s -= col[i] * x[i];
    x[j] = s / col[j];
  }
}

/* y := A x for a free symmetric upper band A. */
static void ea__fe_band_symv(int n, const double *A, const double *x, double *y) {
  const int kd = EA__FE_KD, ld = EA__FE_LDS;
  for (int j = 0; j < n; ++j) {
    const double *col = A + (size_t)j * ld + kd - j;
    const double xj = x[j];
    double t = col[j] * xj;
    for (int i = (j > kd ? j - kd : 0); i < j; ++i) {
      y[i] += col[i] * xj;
      t += col[i] * x[i];
    }
    y[j] = t;
  }
}

static double ea__fe_dot(int n, const double *a, const double *b) {
  double s = 0.0;
  for (int i = 0; i < n; ++i)
    s += a[i] * b[i];
  return s;
}

/* w := w - Q h, h = Q' w over the first cols columns of Q, twice (CGS2: the
 * second pass removes what rounding left of the first). Returns h_last of the
 * first pass plus the second (the correction to alpha when the last column is
 * the current Lanczos vector). */
static double ea__fe_reorth(int n, const double *Q, int cols, double *w, double *h) {
  double hl = 0.0;
  for (int pass = 0; pass < 2; ++pass) {
    for (int p = 0; p < cols; ++p)
      h[p] = ea__fe_dot(n, Q + (size_t)p * n, w);
    for (int p = 0; p < cols; ++p) {
      const double *qp = Q + (size_t)p * n, hp = h[p];
      for (int i = 0; i < n; ++i)
        w[i] -= hp * qp[i];
    }
    if (cols > 0) hl += h[cols - 1];
  }
  return hl;
}

/* The k largest mu of C by Lanczos with full reorthogonalisation (Krylov
 * basis in m->Qw, nf x nf, so at most nf steps: then the space is all of R^nf
 * and the Ritz pairs are exact). Converged when every wanted Ritz pair
 * (theta_i, y_i) has the residual |C y_i - theta_i y_i| = beta_j |s_ji| below
 * max(1e-10 gap_i, 1e-13 theta_max), gap_i the distance to the nearest other
 * Ritz value (the error of y_i is ~ residual / gap, that of theta_i residual^2
 * / gap). Writes mu[0..k) descending and the mode vectors v_i = U^-1 y_i as
 * columns of m->Z. Work: m->lz, m->qs, m->vs, m->iwork, m->ifail. */
static ea_status_t ea__fe_lanczos(ea_fe_model_t *m, int k, double *mu, int *steps, int *linfo) {
  const int n = m->nf;
  const double *U = m->Gb, *M = m->Bb;
  double *Q = m->Qw, *lz = m->lz;
  double *al = lz, *be = lz + n, *d = lz + 2 * n, *e = lz + 3 * n, *th = lz + 4 * n,
         *h = lz + 5 * n, *wk = lz + 6 * n /* 5 n */, *S = lz + 11 * n /* (k + 1) n */;
  double *w = m->qs, *u = m->vs;          /* nd >= nf */
  const int want = k + 1 < n ? k + 1 : k; /* one more Ritz value for the gap of mode k */
  *steps = 0;
  *linfo = 0;
  /* start: y0 = U^-T M x = C (U x), x a smooth deterministic vector: one step of the
   * operator already damps the high modes */
  for (int i = 0; i < n; ++i)
    u[i] = 1.0 + 0.5 * sin(0.37 * i + 0.3);
  ea__fe_band_symv(n, M, u, w);
  ea__fe_band_utsolve(n, U, w);
  double nw = sqrt(ea__fe_dot(n, w, w));
  if (!(nw > 0.0) || !isfinite(nw)) return EA_ERR_NOCONV;
  for (int i = 0; i < n; ++i)
    Q[i] = w[i] / nw;
  int nr = 0, conv = 0;
  for (int j = 0; j < n; ++j) {
    const double *qj = Q + (size_t)j * n;
    memcpy(u, qj, sizeof(double) * (size_t)n);
    ea__fe_band_usolve(n, U, u);
    ea__fe_band_symv(n, M, u, w);
    ea__fe_band_utsolve(n, U, w); /* w = C q_j */
    double a = ea__fe_dot(n, qj, w);
    for (int i = 0; i < n; ++i)
      w[i] -= a * qj[i];
    if (j > 0)
      for (int i = 0, p = j - 1; i < n; ++i)
        w[i] -= be[p] * Q[i + (size_t)p * n];
    a += ea__fe_reorth(n, Q, j + 1, w, h);
    al[j] = a;
    double b = sqrt(ea__fe_dot(n, w, w));
    const int ms = j + 1;
    *steps = ms;
    /* Ritz values and the last components of their vectors; dstevx costs about as much as
     * two Lanczos steps, so check from 2k + 2 steps on (the paper's arm needs 10 for k = 3)
     * and then every other step */
    if ((ms >= 2 * k + 2 && (ms - 2 * k) % 2 == 0) || ms == n) {
      const int wm = want < ms ? want : ms, il = ms - wm + 1, iu = ms;
      const double vl = 0.0, vu = 0.0, abstol = 2.0 * DBL_MIN;
      memcpy(d, al, sizeof(double) * (size_t)ms);
      memcpy(e, be, sizeof(double) * (size_t)(ms > 1 ? ms - 1 : 1));
      dstevx_("V", "I", &ms, d, e, &vl, &vu, &il, &iu, &abstol, &nr, th, S, &ms, wk, m->iwork,
              m->ifail, linfo, 1, 1);
      if (*linfo != 0 || nr != wm) return EA_ERR_BACKEND;
      /* th ascending: the wanted are th[nr - 1], th[nr - 2], ... th[nr - k] */
      const double tmax = fabs(th[nr - 1]);
      conv = 1;
      for (int i = nr - k; i < nr && conv; ++i) {
        double gap = INFINITY;
        if (i > 0) gap = fmin(gap, th[i] - th[i - 1]);
        if (i < nr - 1) gap = fmin(gap, th[i + 1] - th[i]);
        const double res = b * fabs(S[(size_t)(ms - 1) + (size_t)i * ms]);
        if (!(res <= fmax(1e-10 * gap, 1e-13 * tmax))) conv = 0;
      }
      if (ms == n) conv = 1; /* the whole space: exact */
    }
    if (conv) break;
    if (j + 1 >= n) return EA_ERR_NOCONV;
    double *qn = Q + (size_t)(j + 1) * n;
    if (!(b > 1e-14 * fabs(a)) || !isfinite(b)) {
      /* invariant subspace found: continue with a new direction orthogonal to it */
      for (int i = 0; i < n; ++i)
        w[i] = sin(2.1 * i + 1.7 * j + 0.5);
      ea__fe_reorth(n, Q, j + 1, w, h);
      b = sqrt(ea__fe_dot(n, w, w));
      if (!(b > 0.0) || !isfinite(b)) return EA_ERR_NOCONV;
      for (int i = 0; i < n; ++i)
        qn[i] = w[i] / b;
      be[j] = 0.0;
    } else {
      for (int i = 0; i < n; ++i)
        qn[i] = w[i] / b;
      be[j] = b;
    }
  }
  if (!conv) return EA_ERR_NOCONV;
  /* Ritz vectors y = Q s, mode vectors v = U^-1 y (the K-normalised modes) */
  const int ms = *steps;
  for (int c = 0; c < k; ++c) {
    const int i = nr - 1 - c;
    const double *s = S + (size_t)i * ms;
    double *z = m->Z + (size_t)c * n;
    memset(z, 0, sizeof(double) * (size_t)n);
    for (int p = 0; p < ms; ++p) {
      const double *qp = Q + (size_t)p * n, sp = s[p];
      for (int r = 0; r < n; ++r)
        z[r] += sp * qp[r];
    }
    ea__fe_band_usolve(n, U, z);
    mu[c] = th[i];
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
  const double t0 = ea__mono_s();
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
      for (size_t i = 0; i < nb; ++i)
        m->Ab[i] = K0[i] + sigma * m->Bb[i];
      ok = ea__fe_posdef(m);
      if (ok) break;
    }
    if (!ok) return ea_error_set(err, EA_ERR_BACKEND, "fe modes: no shift makes K + s M definite");
  }
  /* A := M, B := K + sigma M (swap the band arrays' roles) */
  double *A = m->Bb, *B = m->Ab;
  const double t1 = ea__mono_s();
  const int n = m->nf, k = m->set.modes, kd = EA__FE_KD, ld = EA__FE_LDS;
  int info_l = 0, found = 0;
  ea_status_t st = EA_OK;
  double *mu = m->evals; /* mu of mode j (ascending lambda) at mu[j] after the switch */
  ea_fe_eig_backend_t backend = m->set.eig_backend;
  if (backend == EA_FE_EIG_LANCZOS) {
    /* U of K + sigma M is in m->Gb from ea__fe_posdef; A and B are left intact */
    st = ea__fe_lanczos(m, k, mu, &info->iterations, &info_l);
    if (st) { /* not converged (or dstevx failed): the band LAPACK solver instead */
      info->fallback = 1;
      backend = EA_FE_EIG_DSBGVX;
      st = EA_OK;
    }
  }
  switch (backend) {
  case EA_FE_EIG_LANCZOS:
    break;
  case EA_FE_EIG_DSBGVX: {
    /* eigenvalues only (JOBZ = 'N': no n x n reduction matrix Q, no back-transformation,
     * which took ~95 % of the time), the k largest mu; vectors below by band inverse
     * iteration on K - lambda M */
    const double vl = 0.0, vu = 0.0, abstol = 2.0 * DBL_MIN;
    const int il = n - k + 1, iu = n, ld1 = 1;
    dsbgvx_("N", "I", "U", &n, &kd, &kd, A, &ld, B, &ld, m->Qw, &ld1, &vl, &vu, &il, &iu, &abstol,
            &found, m->work, m->Z, &ld1, m->work + n, m->iwork, m->ifail, &info_l, 1, 1, 1);
    if (info_l != 0 || found < k) {
      st = EA_ERR_BACKEND;
      break;
    }
    /* found ascending mu: reverse into ascending lambda */
    for (int j = 0; j < k; ++j)
      mu[j] = m->work[k - 1 - j];
    for (int j = 0; j < k && !st; ++j)
      st = ea__fe_inverse_iteration(m, (mu[j] > 0.0) ? 1.0 / mu[j] - sigma : INFINITY, j);
    break;
  }
  case EA_FE_EIG_DSYGV: {
    const int itype = 1;
    ea__fe_band_dense(m, A, m->Ad);
    ea__fe_band_dense(m, B, m->Bd);
    dsygv_(&itype, "V", "U", &n, m->Ad, &n, m->Bd, &n, m->evals, m->work, &m->lwork, &info_l, 1, 1);
    if (info_l != 0) {
      st = EA_ERR_BACKEND;
      break;
    }
    for (int j = 0; j < k; ++j) {
      memcpy(m->Z + (size_t)j * n, m->Ad + (size_t)(n - 1 - j) * n, sizeof(double) * (size_t)n);
      m->work[j] = m->evals[n - 1 - j];
    }
    for (int j = 0; j < k; ++j)
      mu[j] = m->work[j];
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
  info->time_eigen_s = ea__mono_s() - t1;
  info->backend_info = info_l;
  info->status = st;
  if (st)
    return ea_error_set(err, st, "fe modes: eigen-solver failed (backend %d, info %d)",
                        (int)backend, info_l);
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
      for (int i = 0; i < m->nd; ++i)
        phi[i] *= sgn / amax;
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
    for (int j = 0; j < m->modes_valid; ++j)
      zeta_modes[j] = 0.5 * *b * ratio[j];
  return EA_OK;
}
