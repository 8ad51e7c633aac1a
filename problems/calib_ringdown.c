/* Ring-downs: damped sinusoids started from a spectrum (GSL's real FFT), refined by
 * trust-region nonlinear least squares (gsl_multifit_nlinear).
 *
 * Model of channel c (every channel present in the record):
 *   y_c(t) = o_c + sum_k exp(-sigma_k t) (a_ck cos w_k t + b_ck sin w_k t),
 * t from the first sample; w_k and sigma_k are shared by the channels (one mode, one
 * frequency and decay everywhere); residuals are weighted by each channel's noise. */
#include "calib_impl.h"
#include "ea_calib.h"
#include "ea_util.h"

#include <gsl/gsl_blas.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_fft_real.h>
#include <gsl/gsl_linalg.h>
#include <gsl/gsl_multifit_nlinear.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
  int N, K, C;
  int ch[EA_CALIB_NCH]; /* channel index of column c */
  const double *y[EA_CALIB_NCH];
  double w[EA_CALIB_NCH]; /* 1 / noise */
  double *t;              /* relative time */
} ea__rd_t;

/* Parameter layout: [w_0 s_0 ... w_K-1 s_K-1 | per channel: o, a_0, b_0, ..., a_K-1, b_K-1]. */
static int ea__np(const ea__rd_t *d) {
  return 2 * d->K + d->C * (1 + 2 * d->K);
}

static int ea__rd_f(const gsl_vector *x, void *data, gsl_vector *f) {
  const ea__rd_t *d = data;
  const int K = d->K, base = 2 * K;
  for (int c = 0; c < d->C; ++c) {
    const int o = base + c * (1 + 2 * K);
    for (int i = 0; i < d->N; ++i) {
      const double t = d->t[i];
      double m = gsl_vector_get(x, (size_t)o);
      for (int k = 0; k < K; ++k) {
        const double wk = gsl_vector_get(x, (size_t)(2 * k)),
                     sk = gsl_vector_get(x, (size_t)(2 * k + 1));
        const double e = exp(-sk * t);
        m += e * (gsl_vector_get(x, (size_t)(o + 1 + 2 * k)) * cos(wk * t) +
                  gsl_vector_get(x, (size_t)(o + 2 + 2 * k)) * sin(wk * t));
      }
      gsl_vector_set(f, (size_t)(c * d->N + i), (m - d->y[c][i]) * d->w[c]);
    }
  }
  return GSL_SUCCESS;
}

static int ea__rd_df(const gsl_vector *x, void *data, gsl_matrix *J) {
  const ea__rd_t *d = data;
  const int K = d->K, base = 2 * K;
  gsl_matrix_set_zero(J);
  for (int c = 0; c < d->C; ++c) {
    const int o = base + c * (1 + 2 * K);
    for (int i = 0; i < d->N; ++i) {
      const size_t r = (size_t)(c * d->N + i);
      const double t = d->t[i], w = d->w[c];
      gsl_matrix_set(J, r, (size_t)o, w);
      for (int k = 0; k < K; ++k) {
        const double wk = gsl_vector_get(x, (size_t)(2 * k)),
                     sk = gsl_vector_get(x, (size_t)(2 * k + 1));
        const double a = gsl_vector_get(x, (size_t)(o + 1 + 2 * k)),
                     b = gsl_vector_get(x, (size_t)(o + 2 + 2 * k));
        const double e = exp(-sk * t), cs = cos(wk * t), sn = sin(wk * t);
        gsl_matrix_set(J, r, (size_t)(2 * k), w * e * t * (-a * sn + b * cs));
        gsl_matrix_set(J, r, (size_t)(2 * k + 1), -w * t * e * (a * cs + b * sn));
        gsl_matrix_set(J, r, (size_t)(o + 1 + 2 * k), w * e * cs);
        gsl_matrix_set(J, r, (size_t)(o + 2 + 2 * k), w * e * sn);
      }
    }
  }
  return GSL_SUCCESS;
}

/* Amplitudes and offsets by linear least squares (normal equations, Cholesky: the basis is
 * small and well conditioned for distinct frequencies) for the frequencies and decays in x;
 * returns the weighted sum of squares (INFINITY on failure). */
static double ea__rd_linear(const ea__rd_t *d, gsl_vector *x) {
  const int K = d->K, P = 1 + 2 * K, base = 2 * K;
  double *X = malloc(sizeof *X * (size_t)d->N * (size_t)P);
  gsl_matrix *A = gsl_matrix_calloc((size_t)P, (size_t)P);
  gsl_vector *rhs = gsl_vector_alloc((size_t)P), *c = gsl_vector_alloc((size_t)P);
  double total = INFINITY;
  if (!X || !A || !rhs || !c) goto done;
  for (int i = 0; i < d->N; ++i) {
    const double t = d->t[i];
    double *row = X + (size_t)i * P;
    row[0] = 1.0;
    for (int k = 0; k < K; ++k) {
      const double e = exp(-gsl_vector_get(x, (size_t)(2 * k + 1)) * t);
      const double wk = gsl_vector_get(x, (size_t)(2 * k));
      row[1 + 2 * k] = e * cos(wk * t);
      row[2 + 2 * k] = e * sin(wk * t);
    }
    for (int a = 0; a < P; ++a)
      for (int b = 0; b <= a; ++b)
        *gsl_matrix_ptr(A, (size_t)a, (size_t)b) += row[a] * row[b];
  }
  for (int a = 0; a < P; ++a) {
    for (int b = 0; b < a; ++b)
      gsl_matrix_set(A, (size_t)b, (size_t)a, gsl_matrix_get(A, (size_t)a, (size_t)b));
    *gsl_matrix_ptr(A, (size_t)a, (size_t)a) *= 1.0 + 1e-12;
  }
  if (gsl_linalg_cholesky_decomp1(A) != GSL_SUCCESS) goto done;
  total = 0.0;
  for (int ch = 0; ch < d->C; ++ch) {
    gsl_vector_set_zero(rhs);
    for (int i = 0; i < d->N; ++i)
      for (int a = 0; a < P; ++a)
        *gsl_vector_ptr(rhs, (size_t)a) += X[(size_t)i * P + a] * d->y[ch][i];
    if (gsl_linalg_cholesky_solve(A, rhs, c) != GSL_SUCCESS) {
      total = INFINITY;
      goto done;
    }
    double ss = 0;
    for (int i = 0; i < d->N; ++i) {
      double m = 0;
      for (int a = 0; a < P; ++a)
        m += X[(size_t)i * P + a] * gsl_vector_get(c, (size_t)a);
      ss += (m - d->y[ch][i]) * (m - d->y[ch][i]);
    }
    for (int j = 0; j < P; ++j)
      gsl_vector_set(x, (size_t)(base + ch * P + j), gsl_vector_get(c, (size_t)j));
    total += ss * d->w[ch] * d->w[ch];
  }
done:
  free(X);
  gsl_matrix_free(A);
  gsl_vector_free(rhs);
  gsl_vector_free(c);
  return total;
}

static int ea__cmp_dbl(const void *a, const void *b) {
  const double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

/* Noise of a channel from its second differences (a smooth signal sampled finely has
 * second differences far below the noise's): MAD / 0.6745 / sqrt(6). */
static double ea__noise_guess(const double *y, int n) {
  double *d = malloc(sizeof *d * (size_t)n);
  if (!d) return NAN;
  int m = 0;
  for (int i = 1; i + 1 < n; ++i)
    d[m++] = fabs(y[i + 1] - 2 * y[i] + y[i - 1]);
  qsort(d, (size_t)m, sizeof *d, ea__cmp_dbl);
  const double med = m ? d[m / 2] : 0.0;
  free(d);
  return med / 0.6745 / sqrt(6.0);
}

double ea_ringdown_eval(const ea_ringdown_fit_t *fit, int ch, double t) {
  if (!fit || ch < 0 || ch >= EA_CALIB_NCH) return NAN;
  double m = fit->offset[ch];
  for (int k = 0; k < fit->modes; ++k) {
    const double e = exp(-fit->sigma[k] * t);
    m += e * (fit->amp[ch][k][0] * cos(fit->omega_d[k] * t) +
              fit->amp[ch][k][1] * sin(fit->omega_d[k] * t));
  }
  return m;
}

/* Weighted power spectrum of the residuals of the model x (K modes) summed over the channels,
 * into spec (M / 2 + 1 bins of 1 / (M dt) Hz). */
static ea_status_t ea__rd_spectrum(const ea__rd_t *d, const gsl_vector *x, size_t M, double *buf,
                                   double *spec) {
  const int K = d->K, P = 1 + 2 * K;
  memset(spec, 0, sizeof *spec * (M / 2 + 1));
  for (int c = 0; c < d->C; ++c) {
    double mean = 0;
    for (size_t i = 0; i < M; ++i) {
      if (i >= (size_t)d->N) {
        buf[i] = 0.0;
        continue;
      }
      const double t = d->t[i];
      double m = 0;
      if (x) {
        const int o = 2 * K + c * P;
        m = gsl_vector_get(x, (size_t)o);
        for (int k = 0; k < K; ++k) {
          const double e = exp(-gsl_vector_get(x, (size_t)(2 * k + 1)) * t);
          const double wk = gsl_vector_get(x, (size_t)(2 * k));
          m += e * (gsl_vector_get(x, (size_t)(o + 1 + 2 * k)) * cos(wk * t) +
                    gsl_vector_get(x, (size_t)(o + 2 + 2 * k)) * sin(wk * t));
        }
      }
      buf[i] = d->y[c][i] - m;
      mean += buf[i];
    }
    mean /= d->N;
    /* the falling half of a Hann window: a ring-down is strongest at its start, where a full
     * window would hide its quickly decaying modes */
    for (int i = 0; i < d->N; ++i)
      buf[i] = (buf[i] - mean) * d->w[c] * (0.5 + 0.5 * cos(M_PI * (double)i / (d->N - 1)));
    if (gsl_fft_real_radix2_transform(buf, 1, M) != GSL_SUCCESS) return EA_ERR_BACKEND;
    /* half-complex storage: buf[k] real, buf[M - k] imaginary */
    spec[0] += buf[0] * buf[0];
    for (size_t k = 1; k < M / 2; ++k)
      spec[k] += buf[k] * buf[k] + buf[M - k] * buf[M - k];
    spec[M / 2] += buf[M / 2] * buf[M / 2];
  }
  return EA_OK;
}

/* 2 x the cost: |f|^2 at the workspace's point. */
static double ea__cost(gsl_multifit_nlinear_workspace *w) {
  double r;
  gsl_blas_ddot(gsl_multifit_nlinear_residual(w), gsl_multifit_nlinear_residual(w), &r);
  return r;
}

/* The decrease of |f|^2 a Gauss-Newton step predicts at the workspace's point: g' (J'J)^-1 g,
 * g = J' f (infinite when J'J is singular). */
static double ea__gn_decrease(gsl_multifit_nlinear_workspace *w) {
  const gsl_matrix *J = gsl_multifit_nlinear_jac(w);
  const size_t p = J->size2;
  gsl_vector *g = gsl_vector_alloc(p), *h = gsl_vector_alloc(p);
  gsl_matrix *A = gsl_matrix_alloc(p, p);
  double dec = INFINITY;
  if (g && h && A) {
    gsl_blas_dgemv(CblasTrans, 1.0, J, gsl_multifit_nlinear_residual(w), 0.0, g);
    gsl_blas_dgemm(CblasTrans, CblasNoTrans, 1.0, J, J, 0.0, A);
    if (gsl_linalg_cholesky_decomp1(A) == GSL_SUCCESS &&
        gsl_linalg_cholesky_solve(A, g, h) == GSL_SUCCESS)
      gsl_blas_ddot(g, h, &dec);
  }
  gsl_vector_free(g);
  gsl_vector_free(h);
  gsl_matrix_free(A);
  return dec;
}

int ea__nls_converged(gsl_multifit_nlinear_workspace *w, int status, size_t max_iter) {
  if (status == GSL_SUCCESS) return 1;
  const int refused =
      status == GSL_ENOPROG || (status == GSL_EMAXITER && gsl_multifit_nlinear_niter(w) < max_iter);
  return refused && ea__gn_decrease(w) <= 1e-6 * fmax(1.0, ea__cost(w));
}

/* Nonlinear least squares of all of x (K modes); info->iterations accumulated. */
static ea_status_t ea__rd_nls(ea__rd_t *d, gsl_vector *x, int *iters, gsl_matrix *cov) {
  const int P = ea__np(d);
  gsl_multifit_nlinear_fdf fdf = {ea__rd_f, ea__rd_df, NULL, (size_t)(d->N * d->C), (size_t)P, d,
                                  0,        0,         0};
  gsl_multifit_nlinear_parameters fp = gsl_multifit_nlinear_default_parameters();
  fp.trs = gsl_multifit_nlinear_trs_lm;
  fp.scale = gsl_multifit_nlinear_scale_more;
  fp.solver = gsl_multifit_nlinear_solver_cholesky; /* tall and thin: normal equations */
  gsl_multifit_nlinear_workspace *w =
      gsl_multifit_nlinear_alloc(gsl_multifit_nlinear_trust, &fp, (size_t)(d->N * d->C), (size_t)P);
  if (!w) return EA_ERR_NOMEM;
  ea_status_t st = EA_OK;
  int info = 0;
  if (gsl_multifit_nlinear_init(x, &fdf, w) != GSL_SUCCESS) {
    st = EA_ERR_BACKEND;
  } else {
    const int gs = gsl_multifit_nlinear_driver(200, 1e-10, 1e-10, 0.0, NULL, NULL, &info, w);
    *iters += (int)gsl_multifit_nlinear_niter(w);
    if (!ea__nls_converged(w, gs, 200)) st = EA_ERR_NOCONV;
    gsl_vector_memcpy(x, gsl_multifit_nlinear_position(w));
    if (!st && cov && gsl_multifit_nlinear_covar(gsl_multifit_nlinear_jac(w), 0.0, cov))
      st = EA_ERR_BACKEND;
  }
  gsl_multifit_nlinear_free(w);
  return st;
}

/* x for K + 1 modes from x for K: the new mode (w, s) appended, amplitudes zero. */
static gsl_vector *ea__rd_grow(const ea__rd_t *d, const gsl_vector *x, double w, double s) {
  const int K = d->K, P = 1 + 2 * K, P1 = P + 2;
  gsl_vector *y = gsl_vector_calloc((size_t)(2 * (K + 1) + d->C * P1));
  if (!y) return NULL;
  for (int k = 0; k < K; ++k) {
    gsl_vector_set(y, (size_t)(2 * k), gsl_vector_get(x, (size_t)(2 * k)));
    gsl_vector_set(y, (size_t)(2 * k + 1), gsl_vector_get(x, (size_t)(2 * k + 1)));
  }
  gsl_vector_set(y, (size_t)(2 * K), w);
  gsl_vector_set(y, (size_t)(2 * K + 1), s);
  for (int c = 0; c < d->C; ++c)
    for (int j = 0; j < P; ++j)
      gsl_vector_set(y, (size_t)(2 * (K + 1) + c * P1 + j),
                     gsl_vector_get(x, (size_t)(2 * K + c * P + j)));
  return y;
}

ea_status_t ea_ringdown_fit(const ea_calib_record_t *rec, int max_modes, double max_hz,
                            ea_ringdown_fit_t *fit, ea_error_t *err) {
  if (!rec || !fit) return ea_error_set(err, EA_ERR_ARG, "ea_ringdown_fit: NULL argument");
  memset(fit, 0, sizeof *fit);
  for (int c = 0; c < EA_CALIB_NCH; ++c)
    fit->noise[c] = fit->rms[c] = NAN;
  for (int k = 0; k < EA_CALIB_MAX_MODES; ++k)
    fit->mode_index[k] = -1;
  fit->status = EA_ERR_INPUT;
  if (rec->kind != EA_CALIB_RINGDOWN || rec->rows < 16 || !(rec->dt > 0))
    return ea_error_set(err, EA_ERR_ARG, "%s: not a ring-down record", rec->path);
  if (max_modes < 1) max_modes = 1;
  if (max_modes > EA_CALIB_MAX_MODES) max_modes = EA_CALIB_MAX_MODES;
  ea__rd_t d = {0};
  d.N = rec->rows < EA_CALIB_RINGDOWN_MAX_SAMPLES ? rec->rows : EA_CALIB_RINGDOWN_MAX_SAMPLES;
  for (int c = 0; c < EA_CALIB_NCH; ++c)
    if (rec->has[c] && rec->ch[c]) {
      d.ch[d.C] = c;
      d.y[d.C] = rec->ch[c];
      double s = rec->noise[c];
      if (!(s > 0)) s = ea__noise_guess(rec->ch[c], d.N);
      if (!(s > 0)) s = 1e-12; /* a noiseless channel: any positive weight */
      d.w[d.C] = 1.0 / s;
      ++d.C;
    }
  if (!d.C) return ea_error_set(err, EA_ERR_INPUT, "%s: no measured channel", rec->path);
  ea_status_t st = EA_OK;
  double *spec = NULL, *buf = NULL, *sorted = NULL;
  gsl_vector *x = NULL;
  gsl_matrix *cov = NULL;
  d.t = malloc(sizeof *d.t * (size_t)d.N);
  if (!d.t) return ea_error_set(err, EA_ERR_NOMEM, "out of memory");
  for (int i = 0; i < d.N; ++i)
    d.t[i] = rec->t[i] - rec->t[0];
  size_t M = 1;
  while (M < 4 * (size_t)d.N)
    M <<= 1;
  spec = malloc(sizeof *spec * (M / 2 + 1));
  sorted = malloc(sizeof *sorted * (M / 2 + 1));
  buf = malloc(sizeof *buf * M);
  x = gsl_vector_calloc((size_t)d.C); /* K = 0: the offsets */
  if (!spec || !buf || !sorted || !x) {
    st = ea_error_set(err, EA_ERR_NOMEM, "out of memory (spectrum of %zu points)", M);
    goto done;
  }
  ea__rd_linear(&d, x);
  /* Modes one at a time, each from the spectrum of what the modes found so far leave
   * (the leakage of a strong mode hides no weaker one), then all refitted together. */
  const double df = 1.0 / (M * rec->dt);
  const double pad = (double)M / d.N;        /* padded bins per unpadded bin */
  const size_t kmin = (size_t)ceil(3 * pad); /* at least ~1.5 cycles in the record */
  size_t kmax = (size_t)floor(0.4 * M);
  if (max_hz > 0 && max_hz / df < (double)kmax) kmax = (size_t)floor(max_hz / df);
  while (d.K < max_modes) {
    if (ea__rd_spectrum(&d, x, M, buf, spec)) {
      st = ea_error_set(err, EA_ERR_BACKEND, "%s: FFT failed", rec->path);
      goto done;
    }
    memcpy(sorted, spec, sizeof *sorted * (M / 2 + 1));
    qsort(sorted, M / 2 + 1, sizeof *sorted, ea__cmp_dbl);
    const double floor_ = sorted[(M / 2 + 1) / 2];
    size_t best = 0;
    double bp = 0;
    for (size_t k = kmin > 1 ? kmin : 1; k < kmax && k + 1 < M / 2; ++k) {
      if (!(spec[k] > spec[k - 1] && spec[k] >= spec[k + 1]) || spec[k] <= bp) continue;
      int near = 0;
      for (int j = 0; j < d.K; ++j)
        near |=
            fabs((double)k * df - gsl_vector_get(x, (size_t)(2 * j)) / (2 * M_PI)) < 2 * pad * df;
      if (near) continue;
      best = k;
      bp = spec[k];
    }
    /* noise alone: exponentially distributed power, its largest of ~M/2 bins about 15 times
     * the median */
    if (!best || !(bp > 40 * floor_)) break;
    const double a = log(spec[best - 1]), b = log(spec[best]), c = log(spec[best + 1]);
    const double den = a - 2 * b + c;
    const double delta = (den < 0) ? 0.5 * (a - c) / den : 0.0;
    const double f0 = ((double)best + delta) * df;
    gsl_vector *y = ea__rd_grow(&d, x, 2 * M_PI * f0, 0.01 * 2 * M_PI * f0);
    if (!y) {
      st = ea_error_set(err, EA_ERR_NOMEM, "out of memory");
      goto done;
    }
    d.K++;
    /* its decay: the best of a few damping ratios, amplitudes linear */
    static const double zg[] = {0.002, 0.005, 0.01, 0.02, 0.04, 0.08, 0.16};
    double bres = INFINITY, bz = 0.01;
    for (size_t g = 0; g < sizeof zg / sizeof *zg; ++g) {
      gsl_vector_set(y, (size_t)(2 * d.K - 1), zg[g] * 2 * M_PI * f0);
      const double r = ea__rd_linear(&d, y);
      if (r < bres) bres = r, bz = zg[g];
    }
    gsl_vector_set(y, (size_t)(2 * d.K - 1), bz * 2 * M_PI * f0);
    ea__rd_linear(&d, y);
    gsl_vector *keep = x;
    x = y;
    const ea_status_t s2 = ea__rd_nls(&d, x, &fit->iterations, NULL);
    const double wk = fabs(gsl_vector_get(x, (size_t)(2 * d.K - 2)));
    const double sk = gsl_vector_get(x, (size_t)(2 * d.K - 1));
    /* a new sinusoid that does not settle to a resolved, underdamped mode is noise */
    int dup = 0;
    for (int j = 0; j + 1 < d.K; ++j)
      dup |= fabs(fabs(gsl_vector_get(x, (size_t)(2 * j))) - wk) < pad * 2 * M_PI * df;
    if (s2 || !(sk > 0) || !(sk < 0.5 * wk) || dup || wk < kmin * 2 * M_PI * df) {
      gsl_vector_free(x);
      x = keep;
      d.K--;
      if (s2 == EA_ERR_NOMEM) {
        st = ea_error_set(err, EA_ERR_NOMEM, "out of memory (ring-down fit)");
        goto done;
      }
      break;
    }
    fit->spectrum_hz[d.K - 1] = f0;
    gsl_vector_free(keep);
  }
  if (!d.K) {
    st = ea_error_set(err, EA_ERR_INPUT,
                      "%s: no vibration stands out of the noise in the spectrum of the "
                      "ring-down (%d samples at %g s)",
                      rec->path, d.N, rec->dt);
    goto done;
  }
  const int P = ea__np(&d);
  cov = gsl_matrix_alloc((size_t)P, (size_t)P);
  if (!cov) {
    st = ea_error_set(err, EA_ERR_NOMEM, "out of memory");
    goto done;
  }
  /* the noise: the header's, or the residual's when larger (unmodelled motion; a channel
   * without a header noise); once more with those weights when they changed */
  for (int pass = 0; pass < 2; ++pass) {
    double w_before[EA_CALIB_NCH];
    memcpy(w_before, d.w, sizeof w_before);
    st = ea__rd_nls(&d, x, &fit->iterations, cov);
    if (st) {
      st = ea_error_set(err, st == EA_ERR_NOCONV ? EA_ERR_NOCONV : EA_ERR_BACKEND,
                        "%s: the damped-sinusoid fit of %d modes did not converge", rec->path, d.K);
      goto done;
    }
    gsl_vector *f = gsl_vector_alloc((size_t)(d.N * d.C));
    if (!f) {
      st = ea_error_set(err, EA_ERR_NOMEM, "out of memory");
      goto done;
    }
    ea__rd_f(x, &d, f);
    for (int c = 0; c < d.C; ++c) {
      double ss = 0;
      for (int i = 0; i < d.N; ++i) {
        const double r = gsl_vector_get(f, (size_t)(c * d.N + i)) / d.w[c];
        ss += r * r;
      }
      const double dof = d.N - (1 + 2 * d.K) - 2.0 * d.K / d.C;
      fit->rms[d.ch[c]] = sqrt(ss / d.N);
      const double s =
          fmax(rec->noise[d.ch[c]] > 0 ? rec->noise[d.ch[c]] : 0.0, sqrt(ss / fmax(dof, 1.0)));
      fit->noise[d.ch[c]] = s;
      d.w[c] = 1.0 / fmax(s, 1e-300);
    }
    gsl_vector_free(f);
    int changed = 0;
    for (int c = 0; c < d.C; ++c)
      changed |= fabs(d.w[c] / w_before[c] - 1.0) > 0.01;
    if (!changed) break;
  }
  /* Results, modes ascending (sorted by an index permutation). */
  int idx[EA_CALIB_MAX_MODES];
  for (int k = 0; k < d.K; ++k)
    idx[k] = k;
  for (int a = 0; a < d.K; ++a)
    for (int b = a + 1; b < d.K; ++b)
      if (fabs(gsl_vector_get(x, (size_t)(2 * idx[b]))) <
          fabs(gsl_vector_get(x, (size_t)(2 * idx[a])))) {
        const int t = idx[a];
        idx[a] = idx[b];
        idx[b] = t;
      }
  double sp[EA_CALIB_MAX_MODES];
  fit->modes = d.K;
  for (int c = 0; c < d.C; ++c)
    fit->offset[d.ch[c]] = gsl_vector_get(x, (size_t)(2 * d.K + c * (1 + 2 * d.K)));
  for (int kk = 0; kk < d.K; ++kk) {
    const int k = idx[kk];
    sp[kk] = fit->spectrum_hz[k];
    double wk = gsl_vector_get(x, (size_t)(2 * k)), sk = gsl_vector_get(x, (size_t)(2 * k + 1));
    double sgn = 1.0;
    if (wk < 0) wk = -wk, sgn = -1.0; /* sin(-w t) = -sin(w t) */
    const double wn = hypot(wk, sk);
    fit->omega_d[kk] = wk;
    fit->sigma[kk] = sk;
    fit->freq_hz[kk] = wn / (2 * M_PI);
    fit->zeta[kk] = sk / wn;
    const double vww = gsl_matrix_get(cov, (size_t)(2 * k), (size_t)(2 * k));
    const double vss = gsl_matrix_get(cov, (size_t)(2 * k + 1), (size_t)(2 * k + 1));
    const double vws = gsl_matrix_get(cov, (size_t)(2 * k), (size_t)(2 * k + 1)) * sgn;
    /* delta method: d wn = (w dw + s ds) / wn; d zeta = (w^2 ds - s w dw) / wn^3 */
    const double gw = wk / wn, gs_ = sk / wn;
    fit->freq_se_hz[kk] =
        sqrt(fmax(gw * gw * vww + 2 * gw * gs_ * vws + gs_ * gs_ * vss, 0.0)) / (2 * M_PI);
    const double zw = -sk * wk / (wn * wn * wn), zs = wk * wk / (wn * wn * wn);
    fit->zeta_se[kk] = sqrt(fmax(zw * zw * vww + 2 * zw * zs * vws + zs * zs * vss, 0.0));
    for (int c = 0; c < d.C; ++c) {
      const int o = 2 * d.K + c * (1 + 2 * d.K);
      fit->amp[d.ch[c]][kk][0] = gsl_vector_get(x, (size_t)(o + 1 + 2 * k));
      fit->amp[d.ch[c]][kk][1] = sgn * gsl_vector_get(x, (size_t)(o + 2 + 2 * k));
    }
  }
  memcpy(fit->spectrum_hz, sp, sizeof(double) * (size_t)d.K);
  fit->status = EA_OK;
done:
  gsl_matrix_free(cov);
  gsl_vector_free(x);
  free(spec);
  free(sorted);
  free(buf);
  free(d.t);
  if (st) fit->status = st;
  return st;
}
