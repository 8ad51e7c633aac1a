/* The shooting map h (eq. 11, 13) and its variational equations.
 *
 * State y = (theta, kappa, x, y) over s in [0, L]:
 *   theta' = kappa
 *   kappa' = [W(s) cos(theta) - T sin(theta - alpha)] / EI,  W(s) = (m_L + rho (L - s)) g
 * (eq. 10 solved for theta''; the paper's eq. 11 prints it without the 1/EI)
 *   x'     = cos(theta),   y' = sin(theta)
 * with y(0) = (theta0, kappa0, 0, 0). The sensitivities S = dy/dp for
 * p = (alpha, T, theta0, kappa0) obey S' = A(s) S + B(s), S(0) = [0 0 1 0; 0 0 0 1;
 * 0...], integrated alongside (20 states in all), so d x(L)/d p is exact up to the
 * integrator's truncation error: no finite differences. */
#include "statics_impl.h"

#include <gsl/gsl_errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static const char *const ea__int_names[EA_INT_COUNT] = {"rk8pd-fixed", "rk8pd-adaptive",
                                                        "rkf45-adaptive", "rk4-fixed"};

const char *ea_integrator_name(ea_integrator_t it) {
  if ((int)it < 0 || it >= EA_INT_COUNT) return "unknown";
  return ea__int_names[it];
}

ea_status_t ea_integrator_parse(const char *name, ea_integrator_t *it) {
  if (!name || !it) return EA_ERR_ARG;
  for (int i = 0; i < EA_INT_COUNT; ++i)
    if (strcmp(name, ea__int_names[i]) == 0) {
      *it = (ea_integrator_t)i;
      return EA_OK;
    }
  return EA_ERR_ARG;
}

void ea_shoot_settings_default(ea_shoot_settings_t *s) {
  s->integrator = EA_INT_RK8PD_FIXED;
  s->steps = EA__DEFAULT_STEPS;
  s->rtol = 1e-11;
  s->atol = 1e-12;
}

/* Right-hand side; params is the shooter. dim = 4 + 4 ncols, where the
 * sensitivity columns are those of sh->cols (a subset of the parameters:
 * columns of parameters a problem fixes are not integrated). Column-major
 * within each state row: S[i * ncols + k] = d y_i / d p_{cols[k]}. */
static int ea__rhs(double s, const double y[], double f[], void *params) {
  const ea_shooter_t *sh = params;
  const double th = y[0], ka = y[1];
  const double W = (sh->load.tip_mass + sh->arm.rho * (sh->arm.length - s)) * sh->g;
  const double c = cos(th), sn = sin(th);
  const double T = sh->p[EA_P_TENSION];
  /* sin/cos(theta - alpha) from the angle-difference identities: one
   * sin/cos pair per evaluation (cos/sin alpha are set per shot). */
  const double sd = sn * sh->cos_alpha - c * sh->sin_alpha;
  const double cd = c * sh->cos_alpha + sn * sh->sin_alpha;
  const double iEI = sh->inv_EI;
  f[0] = ka;
  f[1] = (W * c - T * sd) * iEI; /* eq. 10 divided by EI (eq. 11 prints it with EI = 1) */
  f[2] = c;
  f[3] = sn;
  const int nc = sh->ncols_active;
  if (nc) {
    const double a10 = (-W * sn - T * cd) * iEI;
    const double *S = y + 4;
    double *F = f + 4;
    for (int k = 0; k < nc; ++k) {
      const double dth = S[k], dka = S[nc + k];
      F[k] = dka;
      F[nc + k] = a10 * dth;
      F[2 * nc + k] = -sn * dth;
      F[3 * nc + k] = c * dth;
      if (sh->cols_active[k] == EA_P_ALPHA) F[nc + k] += T * cd * iEI;
      if (sh->cols_active[k] == EA_P_TENSION) F[nc + k] -= sd * iEI;
    }
  }
  return GSL_SUCCESS;
}

static const gsl_odeiv2_step_type *ea__step_type(ea_integrator_t it) {
  switch (it) {
  case EA_INT_RK8PD_FIXED:
  case EA_INT_RK8PD_ADAPTIVE:
    return gsl_odeiv2_step_rk8pd;
  case EA_INT_RKF45_ADAPTIVE:
    return gsl_odeiv2_step_rkf45;
  case EA_INT_RK4_FIXED:
    return gsl_odeiv2_step_rk4;
  default:
    return NULL;
  }
}

static int ea__is_fixed(ea_integrator_t it) {
  return it == EA_INT_RK8PD_FIXED || it == EA_INT_RK4_FIXED;
}

ea_status_t ea_shooter_alloc(const ea_arm_t *arm, const ea_shoot_settings_t *s, ea_shooter_t **out,
                             ea_error_t *err) {
  if (!arm || !out) return ea_error_set(err, EA_ERR_ARG, "ea_shooter_alloc: NULL argument");
  *out = NULL;
  ea_status_t st = ea_arm_validate(arm, err);
  if (st) return st;
  ea_shoot_settings_t set;
  if (s)
    set = *s;
  else
    ea_shoot_settings_default(&set);
  if ((int)set.integrator < 0 || set.integrator >= EA_INT_COUNT)
    return ea_error_set(err, EA_ERR_ARG, "unknown integrator %d", (int)set.integrator);
  if (ea__is_fixed(set.integrator) && (set.steps < 1 || set.steps > 100000))
    return ea_error_set(err, EA_ERR_ARG, "integrator steps = %d: must be in [1, 100000]",
                        set.steps);
  if (!ea__is_fixed(set.integrator) &&
      !(set.rtol > 0 && set.atol > 0 && isfinite(set.rtol) && isfinite(set.atol)))
    return ea_error_set(err, EA_ERR_ARG, "integrator tolerances must be finite and > 0");

  ea_shooter_t *sh = calloc(1, sizeof *sh);
  if (!sh) return ea_error_set(err, EA_ERR_NOMEM, "out of memory");
  sh->arm = *arm;
  sh->set = set;
  sh->g = arm->g;
  sh->inv_EI = 1.0 / arm->EI;
  sh->load.tip_mass = arm->m_hand;
  const gsl_odeiv2_step_type *T = ea__step_type(set.integrator);
  sh->perm = gsl_permutation_alloc(4);
  if (!sh->perm) goto nomem;
  for (int nc = 0; nc <= EA_NP; ++nc) {
    const size_t dim = (size_t)(4 + 4 * nc);
    sh->sys[nc] = (gsl_odeiv2_system){ea__rhs, NULL, dim, sh};
    if (ea__is_fixed(set.integrator)) {
      sh->step[nc] = gsl_odeiv2_step_alloc(T, dim);
      if (!sh->step[nc]) goto nomem;
    } else {
      sh->drv[nc] =
          gsl_odeiv2_driver_alloc_y_new(&sh->sys[nc], T, arm->length / 16.0, set.atol, set.rtol);
      if (!sh->drv[nc]) goto nomem;
    }
  }
  *out = sh;
  return EA_OK;
nomem:
  ea_shooter_free(sh);
  return ea_error_set(err, EA_ERR_NOMEM, "out of memory allocating the integrator");
}

void ea_shooter_free(ea_shooter_t *sh) {
  if (!sh) return;
  for (int nc = 0; nc <= EA_NP; ++nc) {
    if (sh->step[nc]) gsl_odeiv2_step_free(sh->step[nc]);
    if (sh->drv[nc]) gsl_odeiv2_driver_free(sh->drv[nc]);
  }
  if (sh->drv_shape) gsl_odeiv2_driver_free(sh->drv_shape);
  if (sh->perm) gsl_permutation_free(sh->perm);
  free(sh);
}

void ea_shooter_set_load(ea_shooter_t *sh, const ea_load_t *load) {
  sh->load = *load;
  sh->cache_valid = 0;
}
const ea_arm_t *ea_shooter_arm(const ea_shooter_t *sh) {
  return &sh->arm;
}
const ea_load_t *ea_shooter_load(const ea_shooter_t *sh) {
  return &sh->load;
}
void ea__shooter_set_gscale(ea_shooter_t *sh, double scale) {
  const double g = sh->arm.g * scale;
  if (g != sh->g) sh->cache_valid = 0;
  sh->g = g;
}

static void ea__initial(const ea_shooter_t *sh, const double p[EA_NP], double *y) {
  const int nc = sh->ncols_active;
  memset(y, 0, (size_t)(4 + 4 * nc) * sizeof *y);
  y[0] = p[EA_P_THETA0];
  y[1] = p[EA_P_KAPPA0];
  for (int k = 0; k < nc; ++k) {
    if (sh->cols_active[k] == EA_P_THETA0) y[4 + k] = 1.0;
    if (sh->cols_active[k] == EA_P_KAPPA0) y[4 + nc + k] = 1.0;
  }
}

static ea_status_t ea__integrate(ea_shooter_t *sh, double *y) {
  const double L = sh->arm.length;
  const int nc = sh->ncols_active, dim = 4 + 4 * nc;
  if (ea__is_fixed(sh->set.integrator)) {
    gsl_odeiv2_step *st = sh->step[nc];
    gsl_odeiv2_system *sys = &sh->sys[nc];
    gsl_odeiv2_step_reset(st);
    const int n = sh->set.steps;
    const double h = L / n;
    double *yerr = sh->yerr, *d0 = sh->dydt0, *d1 = sh->dydt1;
    if (sys->function(0.0, y, d0, sh) != GSL_SUCCESS) return EA_ERR_INTEGRATION;
    for (int i = 0; i < n; ++i) {
      const double s = i * h;
      if (gsl_odeiv2_step_apply(st, s, h, y, yerr, d0, d1, sys) != GSL_SUCCESS)
        return EA_ERR_INTEGRATION;
      double *t = d0;
      d0 = d1;
      d1 = t;
    }
  } else {
    gsl_odeiv2_driver *d = sh->drv[nc];
    gsl_odeiv2_driver_reset(d);
    double s = 0.0;
    if (gsl_odeiv2_driver_apply(d, &s, L, y) != GSL_SUCCESS) return EA_ERR_INTEGRATION;
  }
  for (int i = 0; i < dim; ++i)
    if (!isfinite(y[i])) return EA_ERR_INTEGRATION;
  return EA_OK;
}

ea_status_t ea__shoot_cols(ea_shooter_t *sh, const double p[EA_NP], double xL[EA_NX], double *dxdp,
                           unsigned mask) {
  if (!sh || !p || !xL) return EA_ERR_ARG;
  for (int i = 0; i < EA_NP; ++i)
    if (!isfinite(p[i])) return EA_ERR_ARG;
  if (!dxdp) mask = 0;
  mask &= (1u << EA_NP) - 1u;
  /* The last shot is remembered: solvers often ask again for the point they
   * just accepted. */
  if (sh->cache_valid && memcmp(p, sh->cache_p, sizeof sh->cache_p) == 0 &&
      (mask & ~sh->cache_mask) == 0) {
    memcpy(xL, sh->cache_x, sizeof sh->cache_x);
    if (dxdp) memcpy(dxdp, sh->cache_S, sizeof sh->cache_S);
    return EA_OK;
  }
  memcpy(sh->p, p, sizeof sh->p);
  sh->cos_alpha = cos(p[EA_P_ALPHA]);
  sh->sin_alpha = sin(p[EA_P_ALPHA]);
  int nc = 0;
  for (int j = 0; j < EA_NP; ++j)
    if (mask & (1u << j)) sh->cols_active[nc++] = j;
  sh->ncols_active = nc;
  double y[4 + 4 * EA_NP];
  ea__initial(sh, p, y);
  sh->cache_valid = 0;
  ea_status_t st = ea__integrate(sh, y);
  if (st) return st;
  memcpy(xL, y, EA_NX * sizeof *xL);
  memcpy(sh->cache_x, y, sizeof sh->cache_x);
  memset(sh->cache_S, 0, sizeof sh->cache_S);
  for (int i = 0; i < EA_NX; ++i)
    for (int k = 0; k < nc; ++k)
      sh->cache_S[i * EA_NP + sh->cols_active[k]] = y[4 + i * nc + k];
  if (dxdp) memcpy(dxdp, sh->cache_S, sizeof sh->cache_S);
  memcpy(sh->cache_p, p, sizeof sh->cache_p);
  sh->cache_mask = mask;
  sh->cache_valid = 1;
  return EA_OK;
}

ea_status_t ea_shoot(ea_shooter_t *sh, const double p[EA_NP], double xL[EA_NX], double *dxdp) {
  return ea__shoot_cols(sh, p, xL, dxdp, (1u << EA_NP) - 1u);
}

ea_status_t ea_shoot_shape(ea_shooter_t *sh, const double p[EA_NP], int n, double *s, double *theta,
                           double *kappa, double *x, double *y) {
  if (!sh || !p || n < 2) return EA_ERR_ARG;
  for (int i = 0; i < EA_NP; ++i)
    if (!isfinite(p[i])) return EA_ERR_ARG;
  if (!sh->drv_shape) {
    sh->drv_shape = gsl_odeiv2_driver_alloc_y_new(&sh->sys[0], gsl_odeiv2_step_rk8pd,
                                                  sh->arm.length / 32.0, 1e-12, 1e-12);
    if (!sh->drv_shape) return EA_ERR_NOMEM;
  }
  memcpy(sh->p, p, sizeof sh->p);
  sh->cos_alpha = cos(p[EA_P_ALPHA]);
  sh->sin_alpha = sin(p[EA_P_ALPHA]);
  sh->cache_valid = 0;
  sh->ncols_active = 0;
  double st[4];
  ea__initial(sh, p, st);
  gsl_odeiv2_driver_reset(sh->drv_shape);
  double sc = 0.0;
  for (int i = 0; i < n; ++i) {
    const double si = (i == n - 1) ? sh->arm.length : sh->arm.length * i / (n - 1);
    if (si > sc && gsl_odeiv2_driver_apply(sh->drv_shape, &sc, si, st) != GSL_SUCCESS)
      return EA_ERR_INTEGRATION;
    if (s) s[i] = si;
    if (theta) theta[i] = st[0];
    if (kappa) kappa[i] = st[1];
    if (x) x[i] = st[2];
    if (y) y[i] = st[3];
  }
  return EA_OK;
}

ea_status_t ea_shoot_reference(const ea_arm_t *arm, const ea_load_t *load, const double p[EA_NP],
                               double xL[EA_NX]) {
  ea_shoot_settings_t set;
  ea_shoot_settings_default(&set);
  set.integrator = EA_INT_RKF45_ADAPTIVE;
  set.rtol = 1e-13;
  set.atol = 1e-13;
  ea_shooter_t *sh = NULL;
  ea_status_t st = ea_shooter_alloc(arm, &set, &sh, NULL);
  if (st) return st;
  ea_shooter_set_load(sh, load);
  st = ea_shoot(sh, p, xL, NULL);
  ea_shooter_free(sh);
  return st;
}
