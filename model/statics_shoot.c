/* The shooting map h (eq. 11, 13) and its variational equations.
 *
 * State y = (theta, kappa, x, y) over s in [0, L]:
 *   theta' = kappa
 *   kappa' = W(s) cos(theta) - T sin(theta - alpha),  W(s) = (m_L + rho (L - s)) g
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

static const char *const ea__int_names[EA_INT_COUNT] = {
    "rk8pd-fixed", "rk8pd-adaptive", "rkf45-adaptive", "rk4-fixed"};

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

/* Right-hand side; params is the shooter. dim 4 or 20. No allocation. */
static int ea__rhs(double s, const double y[], double f[], void *params, int with_sens) {
  const ea_shooter_t *sh = params;
  const double th = y[0], ka = y[1];
  const double W = (sh->load.tip_mass + sh->arm.rho * (sh->arm.length - s)) * sh->g;
  const double c = cos(th), sn = sin(th);
  const double alpha = sh->p[EA_P_ALPHA], T = sh->p[EA_P_TENSION];
  const double d = th - alpha, sd = sin(d), cd = cos(d);
  f[0] = ka;
  f[1] = W * c - T * sd;
  f[2] = c;
  f[3] = sn;
  if (with_sens) {
    const double a10 = -W * sn - T * cd;
    const double *S = y + 4; /* S[i*4 + j] = d y_i / d p_j */
    double *F = f + 4;
    for (int j = 0; j < EA_NP; ++j) {
      const double dth = S[j], dka = S[4 + j];
      F[j] = dka;
      F[4 + j] = a10 * dth;
      F[8 + j] = -sn * dth;
      F[12 + j] = c * dth;
    }
    F[4 + EA_P_ALPHA] += T * cd;
    F[4 + EA_P_TENSION] -= sd;
  }
  return GSL_SUCCESS;
}

static int ea__rhs4(double s, const double y[], double f[], void *params) {
  return ea__rhs(s, y, f, params, 0);
}
static int ea__rhs20(double s, const double y[], double f[], void *params) {
  return ea__rhs(s, y, f, params, 1);
}

static const gsl_odeiv2_step_type *ea__step_type(ea_integrator_t it) {
  switch (it) {
  case EA_INT_RK8PD_FIXED:
  case EA_INT_RK8PD_ADAPTIVE: return gsl_odeiv2_step_rk8pd;
  case EA_INT_RKF45_ADAPTIVE: return gsl_odeiv2_step_rkf45;
  case EA_INT_RK4_FIXED: return gsl_odeiv2_step_rk4;
  default: return NULL;
  }
}

static int ea__is_fixed(ea_integrator_t it) {
  return it == EA_INT_RK8PD_FIXED || it == EA_INT_RK4_FIXED;
}

ea_status_t ea_shooter_alloc(const ea_arm_t *arm, const ea_shoot_settings_t *s,
                             ea_shooter_t **out, ea_error_t *err) {
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
  sh->load.tip_mass = arm->m_hand;
  sh->sys4 = (gsl_odeiv2_system){ea__rhs4, NULL, 4, sh};
  sh->sys20 = (gsl_odeiv2_system){ea__rhs20, NULL, 20, sh};
  const gsl_odeiv2_step_type *T = ea__step_type(set.integrator);
  if (ea__is_fixed(set.integrator)) {
    sh->step4 = gsl_odeiv2_step_alloc(T, 4);
    sh->step20 = gsl_odeiv2_step_alloc(T, 20);
    if (!sh->step4 || !sh->step20) goto nomem;
  } else {
    const double h0 = arm->length / 16.0;
    sh->drv4 = gsl_odeiv2_driver_alloc_y_new(&sh->sys4, T, h0, set.atol, set.rtol);
    sh->drv20 = gsl_odeiv2_driver_alloc_y_new(&sh->sys20, T, h0, set.atol, set.rtol);
    if (!sh->drv4 || !sh->drv20) goto nomem;
  }
  *out = sh;
  return ea_error_set(err, EA_OK, "ok");
nomem:
  ea_shooter_free(sh);
  return ea_error_set(err, EA_ERR_NOMEM, "out of memory allocating the integrator");
}

void ea_shooter_free(ea_shooter_t *sh) {
  if (!sh) return;
  if (sh->step4) gsl_odeiv2_step_free(sh->step4);
  if (sh->step20) gsl_odeiv2_step_free(sh->step20);
  if (sh->drv4) gsl_odeiv2_driver_free(sh->drv4);
  if (sh->drv20) gsl_odeiv2_driver_free(sh->drv20);
  if (sh->drv_shape) gsl_odeiv2_driver_free(sh->drv_shape);
  free(sh);
}

void ea_shooter_set_load(ea_shooter_t *sh, const ea_load_t *load) { sh->load = *load; }
const ea_arm_t *ea_shooter_arm(const ea_shooter_t *sh) { return &sh->arm; }
const ea_load_t *ea_shooter_load(const ea_shooter_t *sh) { return &sh->load; }
void ea__shooter_set_gscale(ea_shooter_t *sh, double scale) { sh->g = sh->arm.g * scale; }

static void ea__initial(const double p[EA_NP], double *y, int dim) {
  memset(y, 0, (size_t)dim * sizeof *y);
  y[0] = p[EA_P_THETA0];
  y[1] = p[EA_P_KAPPA0];
  if (dim == 20) {
    y[4 + 0 * 4 + EA_P_THETA0] = 1.0;
    y[4 + 1 * 4 + EA_P_KAPPA0] = 1.0;
  }
}

static ea_status_t ea__integrate(ea_shooter_t *sh, double *y, int dim) {
  const double L = sh->arm.length;
  if (ea__is_fixed(sh->set.integrator)) {
    gsl_odeiv2_step *st = dim == 20 ? sh->step20 : sh->step4;
    gsl_odeiv2_system *sys = dim == 20 ? &sh->sys20 : &sh->sys4;
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
    gsl_odeiv2_driver *d = dim == 20 ? sh->drv20 : sh->drv4;
    gsl_odeiv2_driver_reset(d);
    double s = 0.0;
    if (gsl_odeiv2_driver_apply(d, &s, L, y) != GSL_SUCCESS) return EA_ERR_INTEGRATION;
  }
  for (int i = 0; i < dim; ++i)
    if (!isfinite(y[i])) return EA_ERR_INTEGRATION;
  return EA_OK;
}

ea_status_t ea_shoot(ea_shooter_t *sh, const double p[EA_NP], double xL[EA_NX],
                     double *dxdp) {
  if (!sh || !p || !xL) return EA_ERR_ARG;
  for (int i = 0; i < EA_NP; ++i)
    if (!isfinite(p[i])) return EA_ERR_ARG;
  memcpy(sh->p, p, sizeof sh->p);
  const int dim = dxdp ? 20 : 4;
  double y[20];
  ea__initial(p, y, dim);
  ea_status_t st = ea__integrate(sh, y, dim);
  if (st) return st;
  memcpy(xL, y, EA_NX * sizeof *xL);
  if (dxdp) memcpy(dxdp, y + 4, EA_NX * EA_NP * sizeof *dxdp);
  return EA_OK;
}

ea_status_t ea_shoot_shape(ea_shooter_t *sh, const double p[EA_NP], int n, double *s,
                           double *theta, double *kappa, double *x, double *y) {
  if (!sh || !p || n < 2) return EA_ERR_ARG;
  for (int i = 0; i < EA_NP; ++i)
    if (!isfinite(p[i])) return EA_ERR_ARG;
  if (!sh->drv_shape) {
    sh->drv_shape = gsl_odeiv2_driver_alloc_y_new(&sh->sys4, gsl_odeiv2_step_rk8pd,
                                                  sh->arm.length / 32.0, 1e-12, 1e-12);
    if (!sh->drv_shape) return EA_ERR_NOMEM;
  }
  memcpy(sh->p, p, sizeof sh->p);
  double st[4];
  ea__initial(p, st, 4);
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

ea_status_t ea_shoot_reference(const ea_arm_t *arm, const ea_load_t *load,
                               const double p[EA_NP], double xL[EA_NX]) {
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
