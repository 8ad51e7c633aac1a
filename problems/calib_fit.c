/* The calibration fit (docs/calibration.md, "How the fit works").
 *
 * Unknowns u: the arm's free parameters, log(v / v_prior) for the positive ones (EI, rho,
 * m_hand, EA_c, I_L) and (v - v_prior) / L for the cable root. Each static row i also has its
 * cable angle alpha_i (a nuisance parameter: the row's configuration is its commanded cable
 * length and this angle), eliminated by variable projection: at every u each alpha_i is the
 * best for its row, and the Jacobian's rows are projected off the alpha_i column.
 *
 * Residuals, each divided by its noise: per static row and measured channel, model - measured;
 * per ring-down mode matched to an FE mode, FE frequency - measured frequency.
 *
 * Statics sensitivities: the row's state p = (alpha, T, theta0, kappa0) solves g(p; u) = 0 with
 *   g0 = kappa(L), g1 = (y_L - y_c) cos a - (x_L - x_c) sin a,
 *   g2 = (x_L - x_c) cos a + (y_L - y_c) sin a - L_c (1 + T / EA_c)   (the cable stretches),
 *   g3 = a - alpha_i,
 * so dp/du = -(dg/dp)^-1 dg/du (implicit functions). dg/dp and the tip's dependence on T and
 * alpha come from the shooting map's variational equations (ea_shoot). The tip mass enters the
 * ODE only through the tip force (T cos a, m_L g + T sin a), so d x(L)/d m_L = g (sin a d/dT +
 * cos a / T d/da) x(L), exact; the ODE depends on EI only through W / EI and T / EI, so
 * d/d log EI = -(m_L d/dm_L + rho d/drho + T d/dT), exact but for d/drho, which is a central
 * difference of the fixed-step shooting map (smooth in rho). The FE frequencies' derivatives
 * are central differences. */
#include "calib_impl.h"
#include "ea_calib.h"
#include "ea_util.h"

#include <gsl/gsl_blas.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_linalg.h>
#include <gsl/gsl_multifit_nlinear.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static const char *const ea__pname[EA_CALIB_NP] = {"EI",  "rho",  "m_hand", "x_c",
                                                   "y_c", "EA_c", "I_L",    "payload"};
/* the payload is not an arm-file key: its records' header key */
static const char *const ea__pkey[EA_CALIB_NP] = {
    "beam.EI_Nm2",    "beam.rho_kg_per_m", "hand.mass_kg",   "cable.root_x_m",
    "cable.root_y_m", "cable.EA_N",        "hand.Izz_kg_m2", "payload_kg"};

int ea_calib_param_is_arm(int k) {
  return k >= 0 && k < EA_CALIB_NP && k != EA_CALIB_P_PAYLOAD;
}

const char *ea_calib_param_name(int k) {
  return (k >= 0 && k < EA_CALIB_NP) ? ea__pname[k] : "unknown";
}
const char *ea_calib_param_key(int k) {
  return (k >= 0 && k < EA_CALIB_NP) ? ea__pkey[k] : "unknown";
}
ea_status_t ea_calib_param_parse(const char *name, int *k) {
  if (!name || !k) return EA_ERR_ARG;
  for (int j = 0; j < EA_CALIB_NP; ++j)
    if (!strcmp(name, ea__pname[j]) || !strcmp(name, ea__pkey[j])) {
      *k = j;
      return EA_OK;
    }
  return EA_ERR_ARG;
}

double ea_calib_param_get(const ea_arm_t *arm, int k) {
  switch (k) {
  case EA_CALIB_P_EI:
    return arm->EI;
  case EA_CALIB_P_RHO:
    return arm->rho;
  case EA_CALIB_P_M_HAND:
    return arm->m_hand;
  case EA_CALIB_P_X_C:
    return arm->x_c;
  case EA_CALIB_P_Y_C:
    return arm->y_c;
  case EA_CALIB_P_EA_CABLE:
    return arm->EA_cable;
  case EA_CALIB_P_I_HAND:
    return arm->I_hand;
  default:
    return NAN;
  }
}

void ea_calib_param_set(ea_arm_t *arm, int k, double v) {
  switch (k) {
  case EA_CALIB_P_EI:
    arm->EI = v;
    break;
  case EA_CALIB_P_RHO:
    arm->rho = v;
    break;
  case EA_CALIB_P_M_HAND:
    arm->m_hand = v;
    break;
  case EA_CALIB_P_X_C:
    arm->x_c = v;
    break;
  case EA_CALIB_P_Y_C:
    arm->y_c = v;
    break;
  case EA_CALIB_P_EA_CABLE:
    arm->EA_cable = v;
    break;
  case EA_CALIB_P_I_HAND:
    arm->I_hand = v;
    break;
  default:
    break;
  }
}

void ea_calib_settings_default(ea_calib_settings_t *s) {
  memset(s, 0, sizeof *s);
  s->fix_mask = 0;
  s->fix_damping = 0;
  s->damping_at_start = 1;
  s->max_iter = 100;
  s->ident_se = 0.5;
  s->modes = 3;
  s->fe_elements = EA_FE_DEFAULT_ELEMENTS;
  s->freq_floor = 1e-3;
  s->payload_start = 0.0;
  s->payload_scale = 0.0;
}

/* Noise used when a record does not give it, before the fit's residual replaces it. */
static const double ea__noise_default[EA_CALIB_NCH] = {1e-3, 1e-2, 5e-2, 1e-3, 1e-3, 1e-3};

/* ------------------------------------------------------------------------ */
/* Workspace                                                                 */
/* ------------------------------------------------------------------------ */

typedef struct {
  int rec, row;
  int unknown; /* 1: the payload is the fitted one (its record is marked payload_unknown) */
  double L, payload;
  double p[EA_NP]; /* warm start and last state */
} ea__row_t;

/* Records whose mode-1 damping ratio is carried to the records' start (the rest: as fitted). */
#define EA_CALIB_MAX_RECORDS_SCALE 256

typedef struct {
  int rec;
  int unknown; /* 1: the payload is the fitted one */
  double L, theta0, payload;
  int nm;                           /* matched modes */
  int mode[EA_CALIB_MAX_MODES];     /* FE mode index */
  double f[EA_CALIB_MAX_MODES];     /* measured [Hz] */
  double sf[EA_CALIB_MAX_MODES];    /* its standard error with the floor [Hz] */
  double model[EA_CALIB_MAX_MODES]; /* last model values [Hz] */
  double p[EA_NP];                  /* statics warm start */
  int have_p;
} ea__ring_t;

typedef struct {
  const ea_arm_t *prior;
  const ea_calib_record_t *recs;
  int nrec;
  const ea_calib_settings_t *set;
  int nfree, free_idx[EA_CALIB_NP]; /* free parameters (indices into EA_CALIB_P_*) */
  int is_log[EA_CALIB_NP];
  double pay0, pay_scale; /* unknown payload = pay0 + u pay_scale [kg] */
  double pay;             /* the unknown payload of the current evaluation [kg] */
  int nrow;
  ea__row_t *rows;
  int nring;
  ea__ring_t *rings;
  double (*noise)[EA_CALIB_NCH]; /* per record, per channel */
  int m;                         /* residuals */
  int nz;                        /* nfree + nrow */
  /* cache of the last evaluation */
  double *zc;
  int have_cache, have_jac;
  double *fc, *Jc; /* m, m x nz row-major */
  ea_error_t err;  /* the last failure */
  int failed;
} ea__ws_t;

/* The unknown payload for u [kg] (pay0 unless fitted). */
static double ea__pay_of(const ea__ws_t *w, const double *u) {
  for (int j = 0; j < w->nfree; ++j)
    if (w->free_idx[j] == EA_CALIB_P_PAYLOAD) return w->pay0 + u[j] * w->pay_scale;
  return w->pay0;
}

/* Arm for u (free parameters only; the others at the prior). */
static void ea__arm_of(const ea__ws_t *w, const double *u, ea_arm_t *arm) {
  *arm = *w->prior;
  for (int j = 0; j < w->nfree; ++j) {
    const int k = w->free_idx[j];
    if (!ea_calib_param_is_arm(k)) continue;
    const double v0 = ea_calib_param_get(w->prior, k);
    ea_calib_param_set(arm, k, w->is_log[k] ? v0 * exp(u[j]) : v0 + u[j] * w->prior->length);
  }
}

/* Scale of d/du for parameter k at arm: d/du = scale * d/dv. */
static double ea__du_scale(const ea__ws_t *w, const ea_arm_t *arm, int k) {
  if (k == EA_CALIB_P_PAYLOAD) return w->pay_scale;
  return w->is_log[k] ? ea_calib_param_get(arm, k) : w->prior->length;
}

/* The static state of a row: cable length L (commanded, unstretched) and cable angle alpha;
 * the geometric length L (1 + T / EA_c) is iterated to consistency. */
static ea_status_t ea__row_solve(ea_shooter_t *sh, const ea_arm_t *arm, double L, double alpha,
                                 double p[EA_NP], int have_guess, ea_error_t *err) {
  ea_statics_solution_t sol;
  double T = have_guess ? p[EA_P_TENSION] : 0.0;
  ea_status_t st = EA_OK;
  ea_statics_settings_t ss;
  ea_statics_settings_default(&ss);
  ss.allow_negative_tension = 1; /* a trial arm of the fit may push a row past the edge */
  for (int it = 0; it < 6; ++it) {
    const double l = L * (1.0 + fmax(T, 0.0) / arm->EA_cable);
    ea_statics_problem_t pr = ea_statics_problem_cable(l, alpha);
    st = ea_statics_solve(sh, &pr, &ss, have_guess ? p : NULL, &sol, err);
    if (st && have_guess) st = ea_statics_solve(sh, &pr, &ss, NULL, &sol, err);
    if (st) return st;
    memcpy(p, sol.p, sizeof sol.p);
    have_guess = 1;
    const double dT = fabs(sol.p[EA_P_TENSION] - T);
    T = sol.p[EA_P_TENSION];
    if (L * dT / arm->EA_cable < 1e-14) break;
  }
  return EA_OK;
}

/* The same for a hold given by its cable length and shoulder angle. */
static ea_status_t ea__hold_solve(ea_shooter_t *sh, const ea_arm_t *arm, double L, double theta0,
                                  double p[EA_NP], int have_guess, ea_statics_solution_t *sol,
                                  ea_error_t *err) {
  double T = have_guess ? p[EA_P_TENSION] : 0.0;
  ea_status_t st = EA_OK;
  ea_statics_settings_t ss;
  ea_statics_settings_default(&ss);
  ss.allow_negative_tension = 1;
  for (int it = 0; it < 6; ++it) {
    const double l = L * (1.0 + fmax(T, 0.0) / arm->EA_cable);
    ea_statics_problem_t pr = {{EA_GIVEN_CABLE_LENGTH, EA_GIVEN_THETA0}, {l, theta0}};
    st = ea_statics_solve(sh, &pr, &ss, have_guess ? p : NULL, sol, err);
    if (st && have_guess) st = ea_statics_solve(sh, &pr, &ss, NULL, sol, err);
    if (st) return st;
    memcpy(p, sol->p, sizeof sol->p);
    have_guess = 1;
    const double dT = fabs(sol->p[EA_P_TENSION] - T);
    T = sol->p[EA_P_TENSION];
    if (L * dT / arm->EA_cable < 1e-14) break;
  }
  return EA_OK;
}

/* The starting state of a static row without a sensed cable angle: the cable angle whose
 * configuration at cable length L on arm has the measured shoulder angle theta0, each angle's
 * configuration on the branch the statics reach from the T = 0 edge (the planner's, and so the
 * experiment's): a scan of the angle from -80 to 80 degrees, then bisection in the bracket
 * nearest to a root. */
static ea_status_t ea__angle_init(ea_shooter_t *sh, const ea_arm_t *arm, double L, double theta0,
                                  double p[EA_NP], ea_error_t *err) {
  const int n = 17;
  double a[17], d[17], ps[17][EA_NP];
  int ok[17];
  for (int k = 0; k < n; ++k) {
    a[k] = (-80.0 + 10.0 * k) * M_PI / 180.0;
    ok[k] = !ea__row_solve(sh, arm, L, a[k], ps[k], 0, NULL);
    d[k] = ok[k] ? ps[k][EA_P_THETA0] - theta0 : NAN;
  }
  int best = -1;
  double bd = INFINITY;
  for (int k = 0; k + 1 < n; ++k)
    if (ok[k] && ok[k + 1] && d[k] * d[k + 1] <= 0) {
      const double m = fmin(fabs(d[k]), fabs(d[k + 1]));
      if (m < bd) bd = m, best = k;
    }
  if (best < 0) { /* no bracket: the closest angle, then Newton on the hold */
    for (int k = 0; k < n; ++k)
      if (ok[k] && fabs(d[k]) < bd) bd = fabs(d[k]), best = k;
    if (best < 0)
      return ea_error_set(err, EA_ERR_INPUT, "no static configuration at this cable length");
    memcpy(p, ps[best], sizeof ps[best]);
    ea_statics_solution_t sol;
    return ea__hold_solve(sh, arm, L, theta0, p, 1, &sol, err);
  }
  double lo = a[best], hi = a[best + 1], dlo = d[best];
  double plo[EA_NP];
  memcpy(plo, ps[best], sizeof plo);
  for (int it = 0; it < 40 && hi - lo > 1e-10; ++it) {
    const double mid = 0.5 * (lo + hi);
    double pm[EA_NP];
    memcpy(pm, plo, sizeof pm);
    if (ea__row_solve(sh, arm, L, mid, pm, 1, NULL)) break;
    const double dm = pm[EA_P_THETA0] - theta0;
    if (dm * dlo <= 0) {
      hi = mid;
    } else {
      lo = mid;
      dlo = dm;
      memcpy(plo, pm, sizeof plo);
    }
  }
  memcpy(p, plo, sizeof plo);
  return ea__row_solve(sh, arm, L, 0.5 * (lo + hi), p, 1, err);
}

/* FE natural frequencies (eq. 24) at a hold for arm: modes 0..nmodes-1 into f; with g1, mode
 * 1's damping ratio per unit strain-rate coefficient b there (zeta_1 = b g1, ea_fe_strain_damping).
 */
static ea_status_t ea__hold_fe(const ea__ws_t *w, const ea_arm_t *arm, double pay, ea__ring_t *rg,
                               int nmodes, double *f, double *g1, ea_error_t *err) {
  ea_shooter_t *sh = NULL;
  ea_fe_model_t *m = NULL;
  ea_status_t st = ea_shooter_alloc(arm, NULL, &sh, err);
  if (st) return st;
  ea_load_t load = {arm->m_hand + (rg->unknown ? pay : rg->payload)};
  ea_shooter_set_load(sh, &load);
  ea_statics_solution_t sol;
  double p[EA_NP];
  memcpy(p, rg->p, sizeof p);
  st = ea__hold_solve(sh, arm, rg->L, rg->theta0, p, rg->have_p, &sol, err);
  if (!st) {
    ea_fe_settings_t fs;
    ea_fe_settings_default(&fs);
    fs.elements = w->set->fe_elements;
    fs.modes = nmodes;
    st = ea_fe_model_alloc(arm, &fs, &m, err);
  }
  if (!st) st = ea_fe_model_set_load(m, &load);
  ea_fe_static_info_t fi;
  if (!st) st = ea_fe_static_solve(m, sh, &sol, &fi, err);
  ea_fe_modes_info_t mi;
  if (!st) st = ea_fe_modes(m, &mi, err);
  if (!st && mi.modes < nmodes)
    st = ea_error_set(err, EA_ERR_BACKEND, "FE gave %d modes", mi.modes);
  if (!st)
    for (int k = 0; k < nmodes; ++k)
      f[k] = mi.freq_hz[k];
  double b1 = NAN;
  if (!st && g1 && ea_fe_strain_damping(m, 0, 1.0, &b1, NULL) == EA_OK && b1 > 0) *g1 = 1.0 / b1;
  ea_fe_model_free(m);
  ea_shooter_free(sh);
  return st;
}

static ea_status_t ea__hold_freq(const ea__ws_t *w, const ea_arm_t *arm, double pay, ea__ring_t *rg,
                                 int nmodes, double *f, ea_error_t *err) {
  return ea__hold_fe(w, arm, pay, rg, nmodes, f, NULL, err);
}

/* One static row at cable angle alpha on arm: the predicted channels pred[] and, per column j
 * (the free parameters j < nf when with_params, and alpha as column nf), their derivatives
 * dpred[j][c]. sh is arm's shooter; shp, shm arm's with rho +- hr (with_params only). */
static ea_status_t ea__row_eval(ea__ws_t *w, const ea_arm_t *arm, ea_shooter_t *sh,
                                ea_shooter_t *shp, ea_shooter_t *shm, double hr, ea__row_t *row,
                                double alpha, int with_params, double pred[EA_CALIB_NCH],
                                double dpred[EA_CALIB_NP + 1][EA_CALIB_NCH]) {
  const ea_calib_record_t *rec = &w->recs[row->rec];
  const int nf = w->nfree;
  const ea_load_t load = {arm->m_hand + (row->unknown ? w->pay : row->payload)};
  ea_shooter_set_load(sh, &load);
  double p[EA_NP];
  memcpy(p, row->p, sizeof p);
  ea_status_t st = ea__row_solve(sh, arm, row->L, alpha, p, 1, &w->err);
  if (st) {
    ea_error_t e = w->err;
    return ea_error_set(&w->err, st, "%s:%d: no static solution for this arm (%s)", rec->path,
                        rec->line[row->row], e.msg);
  }
  memcpy(row->p, p, sizeof p);
  double xL[EA_NX], S[EA_NX * EA_NP];
  if ((st = ea_shoot(sh, p, xL, S))) return st;
  const double a = p[EA_P_ALPHA], T = p[EA_P_TENSION], ca = cos(a), sa = sin(a);
  pred[EA_CALIB_CH_THETA0] = p[EA_P_THETA0];
  pred[EA_CALIB_CH_TORQUE] = arm->EI * p[EA_P_KAPPA0];
  pred[EA_CALIB_CH_TENSION] = T;
  pred[EA_CALIB_CH_TIP_X] = xL[EA_X_X];
  pred[EA_CALIB_CH_TIP_Y] = xL[EA_X_Y];
  pred[EA_CALIB_CH_CABLE_ANGLE] = a;
  double Jp[16], rr[4];
  ea_statics_problem_t pr = ea_statics_problem_cable(row->L * (1.0 + T / arm->EA_cable), a);
  if ((st = ea_statics_residual(sh, &pr, p, rr, Jp))) return st;
  Jp[2 * 4 + EA_P_TENSION] -= row->L / arm->EA_cable;
  gsl_matrix_view Am = gsl_matrix_view_array(Jp, 4, 4);
  gsl_permutation *perm = gsl_permutation_alloc(4);
  int sg;
  if (!perm || gsl_linalg_LU_decomp(&Am.matrix, perm, &sg) != GSL_SUCCESS) {
    gsl_permutation_free(perm);
    return ea_error_set(&w->err, EA_ERR_SINGULAR, "%s:%d: singular statics Jacobian", rec->path,
                        rec->line[row->row]);
  }
  /* direct ODE derivatives of x(L) wrt the tip mass and rho */
  double dx_m[EA_NX] = {0}, dx_r[EA_NX] = {0};
  if (with_params) {
    if (T > 1e-3) {
      for (int q = 0; q < EA_NX; ++q)
        dx_m[q] = arm->g * (sa * S[q * EA_NP + EA_P_TENSION] + ca / T * S[q * EA_NP + EA_P_ALPHA]);
    } else { /* slack cable: a central difference in the tip mass */
      double xp[EA_NX], xm[EA_NX];
      const double h = 1e-6 * fmax(load.tip_mass, 1e-3);
      ea_load_t lp = {load.tip_mass + h}, lm = {load.tip_mass - h};
      ea_shooter_set_load(sh, &lp);
      st = ea_shoot(sh, p, xp, NULL);
      ea_shooter_set_load(sh, &lm);
      if (!st) st = ea_shoot(sh, p, xm, NULL);
      ea_shooter_set_load(sh, &load);
      for (int q = 0; q < EA_NX; ++q)
        dx_m[q] = (xp[q] - xm[q]) / (2 * h);
    }
    if (!st) {
      double xp[EA_NX], xm[EA_NX];
      ea_shooter_set_load(shp, &load);
      st = ea_shoot(shp, p, xp, NULL);
      if (!st && shm) {
        ea_shooter_set_load(shm, &load);
        st = ea_shoot(shm, p, xm, NULL);
      } else
        memcpy(xm, xL, sizeof xm);
      for (int q = 0; q < EA_NX; ++q)
        dx_r[q] = (xp[q] - xm[q]) / (shm ? 2 * hr : hr);
    }
  }
  for (int j = with_params ? 0 : nf; !st && j <= nf; ++j) {
    double dg[4] = {0, 0, 0, 0};
    double dx[EA_NX] = {0, 0, 0, 0};
    int k = -1;
    if (j < nf) {
      k = w->free_idx[j];
      const double sc = ea__du_scale(w, arm, k);
      switch (k) {
      case EA_CALIB_P_EI: /* per log EI */
        for (int q = 0; q < EA_NX; ++q)
          dx[q] = -(load.tip_mass * dx_m[q] + arm->rho * dx_r[q] + T * S[q * EA_NP + EA_P_TENSION]);
        break;
      case EA_CALIB_P_RHO:
        for (int q = 0; q < EA_NX; ++q)
          dx[q] = sc * dx_r[q];
        break;
      case EA_CALIB_P_M_HAND:
        for (int q = 0; q < EA_NX; ++q)
          dx[q] = sc * dx_m[q];
        break;
      case EA_CALIB_P_PAYLOAD: /* the tip mass of the marked rows only */
        for (int q = 0; q < EA_NX; ++q)
          dx[q] = row->unknown ? sc * dx_m[q] : 0.0;
        break;
      case EA_CALIB_P_X_C:
        dg[1] += sc * sa;
        dg[2] += -sc * ca;
        break;
      case EA_CALIB_P_Y_C:
        dg[1] += -sc * ca;
        dg[2] += -sc * sa;
        break;
      case EA_CALIB_P_EA_CABLE: /* per log EA_c */
        dg[2] += row->L * T / arm->EA_cable;
        break;
      default:
        break;
      }
      dg[0] += dx[EA_X_KAPPA];
      dg[1] += ca * dx[EA_X_Y] - sa * dx[EA_X_X];
      dg[2] += ca * dx[EA_X_X] + sa * dx[EA_X_Y];
    } else {
      dg[3] = -1.0; /* g3 = a - alpha */
    }
    double b[4], dp[4];
    for (int q = 0; q < 4; ++q)
      b[q] = -dg[q];
    gsl_vector_view bv = gsl_vector_view_array(b, 4), xv = gsl_vector_view_array(dp, 4);
    if (gsl_linalg_LU_solve(&Am.matrix, perm, &bv.vector, &xv.vector) != GSL_SUCCESS) {
      st = ea_error_set(&w->err, EA_ERR_SINGULAR, "%s:%d: singular statics Jacobian", rec->path,
                        rec->line[row->row]);
      break;
    }
    dpred[j][EA_CALIB_CH_THETA0] = dp[EA_P_THETA0];
    dpred[j][EA_CALIB_CH_TORQUE] =
        arm->EI * dp[EA_P_KAPPA0] + (k == EA_CALIB_P_EI ? arm->EI * p[EA_P_KAPPA0] : 0.0);
    dpred[j][EA_CALIB_CH_TENSION] = dp[EA_P_TENSION];
    for (int c = EA_CALIB_CH_TIP_X; c <= EA_CALIB_CH_TIP_Y; ++c) {
      const int q = c == EA_CALIB_CH_TIP_X ? EA_X_X : EA_X_Y;
      double d = dx[q];
      for (int m = 0; m < EA_NP; ++m)
        d += S[q * EA_NP + m] * dp[m];
      dpred[j][c] = d;
    }
    dpred[j][EA_CALIB_CH_CABLE_ANGLE] = dp[EA_P_ALPHA];
  }
  gsl_permutation_free(perm);
  return st;
}

/* Evaluate residuals f (m) and, if J != NULL, the Jacobian (m x nz, row-major).
 * Variable projection: each row's cable angle is the best for the row's measurements at these
 * parameters (Gauss-Newton in the one angle), and the parameter columns of its rows are
 * projected off the angle's column, so J is the Jacobian of the residual with the angles
 * eliminated (Golub and Pereyra; Kaufman's form). */
static int ea__eval(ea__ws_t *w, const double *z, double *f, double *J) {
  ea_arm_t arm;
  ea__arm_of(w, z, &arm);
  w->pay = ea__pay_of(w, z);
  const int nz = w->nz, nf = w->nfree;
  if (J) memset(J, 0, sizeof *J * (size_t)w->m * (size_t)nz);
  ea_shooter_t *sh = NULL, *shp = NULL, *shm = NULL;
  ea_status_t st = ea_arm_validate(&arm, NULL);
  if (st) ea_error_set(&w->err, st, "a trial arm is not physical");
  const double hr = 1e-5 * arm.rho;
  if (!st) st = ea_shooter_alloc(&arm, NULL, &sh, &w->err);
  if (!st && J) {
    ea_arm_t ap = arm, am = arm;
    ap.rho += hr;
    am.rho -= hr;
    st = ea_shooter_alloc(&ap, NULL, &shp, &w->err);
    if (!st && am.rho > 0) st = ea_shooter_alloc(&am, NULL, &shm, &w->err);
  }
  int r = 0;
  for (int i = 0; !st && i < w->nrow; ++i) {
    ea__row_t *row = &w->rows[i];
    const ea_calib_record_t *rec = &w->recs[row->rec];
    const double *sig = w->noise[row->rec];
    double pred[EA_CALIB_NCH], dpred[EA_CALIB_NP + 1][EA_CALIB_NCH];
    double alpha = row->p[EA_P_ALPHA];
    /* the row's angle: Gauss-Newton on its weighted residuals */
    for (int it = 0; it < 20; ++it) {
      if ((st = ea__row_eval(w, &arm, sh, NULL, NULL, 0, row, alpha, 0, pred, dpred))) break;
      double g = 0, h = 0;
      for (int c = 0; c < EA_CALIB_NCH; ++c)
        if (rec->has[c]) {
          const double rc = (pred[c] - rec->ch[c][row->row]) / sig[c], dc = dpred[nf][c] / sig[c];
          g += dc * rc;
          h += dc * dc;
        }
      if (!(h > 0)) break;
      double da = -g / h;
      if (fabs(da) > 0.1) da = copysign(0.1, da);
      alpha += da;
      if (fabs(da) < 1e-12) break;
    }
    if (st) break;
    if ((st = ea__row_eval(w, &arm, sh, shp, shm, hr, row, alpha, J != NULL, pred, dpred))) break;
    /* the angle's column, to project the parameter columns off */
    double ja[EA_CALIB_NCH], jj = 0;
    int nr = 0;
    for (int c = 0; c < EA_CALIB_NCH; ++c)
      if (rec->has[c]) {
        ja[nr] = dpred[nf][c] / sig[c];
        jj += ja[nr] * ja[nr];
        f[r + nr] = (pred[c] - rec->ch[c][row->row]) / sig[c];
        ++nr;
      }
    if (J)
      for (int j = 0; j < nf; ++j) {
        double col[EA_CALIB_NCH], dot = 0;
        int q = 0;
        for (int c = 0; c < EA_CALIB_NCH; ++c)
          if (rec->has[c]) {
            col[q] = dpred[j][c] / sig[c];
            dot += col[q] * ja[q];
            ++q;
          }
        for (q = 0; q < nr; ++q)
          J[(size_t)(r + q) * nz + j] = col[q] - (jj > 0 ? dot / jj * ja[q] : 0.0);
      }
    r += nr;
  }
  ea_shooter_free(shp);
  ea_shooter_free(shm);
  ea_shooter_free(sh);
  /* ring-down frequencies */
  for (int g = 0; !st && g < w->nring; ++g) {
    ea__ring_t *rg = &w->rings[g];
    int nmodes = 0;
    for (int k = 0; k < rg->nm; ++k)
      if (rg->mode[k] + 1 > nmodes) nmodes = rg->mode[k] + 1;
    double fm[EA_FE_MAX_MODES];
    st = ea__hold_freq(w, &arm, w->pay, rg, nmodes, fm, &w->err);
    if (st) {
      ea_error_t e = w->err;
      ea_error_set(&w->err, st, "%s: FE frequencies at the hold: %s", w->recs[rg->rec].path, e.msg);
      break;
    }
    for (int k = 0; k < rg->nm; ++k) {
      rg->model[k] = fm[rg->mode[k]];
      f[r + k] = (rg->model[k] - rg->f[k]) / rg->sf[k];
    }
    if (J) {
      double *u = malloc(sizeof *u * (size_t)nz);
      if (!u) {
        st = EA_ERR_NOMEM;
        break;
      }
      for (int j = 0; !st && j < nf; ++j) {
        const double h = 1e-4;
        double fp_[EA_FE_MAX_MODES], fm_[EA_FE_MAX_MODES];
        ea_arm_t ap, am;
        memcpy(u, z, sizeof *u * (size_t)nz);
        u[j] = z[j] + h;
        ea__arm_of(w, u, &ap);
        const double pp = ea__pay_of(w, u);
        u[j] = z[j] - h;
        ea__arm_of(w, u, &am);
        const double pm = ea__pay_of(w, u);
        st = ea__hold_freq(w, &ap, pp, rg, nmodes, fp_, &w->err);
        if (!st) st = ea__hold_freq(w, &am, pm, rg, nmodes, fm_, &w->err);
        if (st) break;
        for (int k = 0; k < rg->nm; ++k)
          J[(size_t)(r + k) * nz + j] = (fp_[rg->mode[k]] - fm_[rg->mode[k]]) / (2 * h) / rg->sf[k];
      }
      free(u);
    }
    r += rg->nm;
  }
  if (st) {
    w->failed = 1;
    return st;
  }
  return EA_OK;
}

/* GSL callbacks with a cache: the Jacobian comes with the residual of the same z. */
static int ea__cache(ea__ws_t *w, const gsl_vector *x, int need_jac) {
  const int nz = w->nz;
  int same = w->have_cache;
  for (int j = 0; same && j < nz; ++j)
    if (gsl_vector_get(x, (size_t)j) != w->zc[j]) same = 0;
  if (same && (!need_jac || w->have_jac)) return 0;
  for (int j = 0; j < nz; ++j)
    w->zc[j] = gsl_vector_get(x, (size_t)j);
  w->have_cache = w->have_jac = 0;
  ea_status_t st = ea__eval(w, w->zc, w->fc, need_jac ? w->Jc : NULL);
  if (st) return -1;
  w->have_cache = 1;
  w->have_jac = need_jac;
  return 0;
}

static int ea__gsl_f(const gsl_vector *x, void *data, gsl_vector *f) {
  ea__ws_t *w = data;
  if (ea__cache(w, x, 0)) {
    /* no static solution at this trial point: a large residual, the step is refused */
    for (int i = 0; i < w->m; ++i)
      gsl_vector_set(f, (size_t)i, 1e6);
    return GSL_SUCCESS;
  }
  for (int i = 0; i < w->m; ++i)
    gsl_vector_set(f, (size_t)i, w->fc[i]);
  return GSL_SUCCESS;
}

static int ea__gsl_df(const gsl_vector *x, void *data, gsl_matrix *J) {
  ea__ws_t *w = data;
  if (ea__cache(w, x, 1)) return GSL_EDOM;
  for (int i = 0; i < w->m; ++i)
    for (int j = 0; j < w->nz; ++j)
      gsl_matrix_set(J, (size_t)i, (size_t)j, w->Jc[(size_t)i * w->nz + j]);
  return GSL_SUCCESS;
}

/* ------------------------------------------------------------------------ */
/* Identifiability                                                           */
/* ------------------------------------------------------------------------ */

/* The columns cols of J (whose angles the variable projection eliminated already) reduced to
 * the triangle R (nc x nc) with R' R = J_c' J_c. Returns the number of rows written to R. */
static int ea__profile(const ea__ws_t *w, const double *J, const int *cols, int nc, double *R) {
  const int m = w->m, nz = w->nz, nf = 0, na = 0;
  gsl_matrix *A = gsl_matrix_alloc((size_t)m, (size_t)(na + nc));
  if (!A) return -1;
  for (int i = 0; i < m; ++i) {
    for (int j = 0; j < na; ++j)
      gsl_matrix_set(A, (size_t)i, (size_t)j, J[(size_t)i * nz + nf + j]); /* none */
    for (int j = 0; j < nc; ++j)
      gsl_matrix_set(A, (size_t)i, (size_t)(na + j), J[(size_t)i * nz + cols[j]]);
  }
  const size_t nt = (size_t)(na + nc) < (size_t)m ? (size_t)(na + nc) : (size_t)m;
  gsl_vector *tau = gsl_vector_alloc(nt);
  if (!tau || gsl_linalg_QR_decomp(A, tau) != GSL_SUCCESS) {
    gsl_vector_free(tau);
    gsl_matrix_free(A);
    return -1;
  }
  int rows = 0;
  for (int i = na; i < na + nc && i < m; ++i, ++rows)
    for (int j = 0; j < nc; ++j)
      R[rows * nc + j] = (na + j >= i) ? gsl_matrix_get(A, (size_t)i, (size_t)(na + j)) : 0.0;
  gsl_vector_free(tau);
  gsl_matrix_free(A);
  return rows;
}

/* SVD of R (rows x nc): singular values s (nc, descending) and right vectors V (nc x nc). */
static int ea__svd(const double *R, int rows, int nc, double *s, double *V) {
  const int mm = rows > nc ? rows : nc;
  gsl_matrix *A = gsl_matrix_calloc((size_t)mm, (size_t)nc);
  gsl_matrix *Vm = gsl_matrix_alloc((size_t)nc, (size_t)nc);
  gsl_vector *sv = gsl_vector_alloc((size_t)nc), *wk = gsl_vector_alloc((size_t)nc);
  int rc = -1;
  if (A && Vm && sv && wk) {
    for (int i = 0; i < rows; ++i)
      for (int j = 0; j < nc; ++j)
        gsl_matrix_set(A, (size_t)i, (size_t)j, R[i * nc + j]);
    if (gsl_linalg_SV_decomp(A, Vm, sv, wk) == GSL_SUCCESS) {
      for (int j = 0; j < nc; ++j) {
        s[j] = gsl_vector_get(sv, (size_t)j);
        for (int i = 0; i < nc; ++i)
          V[i * nc + j] = gsl_matrix_get(Vm, (size_t)i, (size_t)j);
      }
      rc = 0;
    }
  }
  gsl_matrix_free(A);
  gsl_matrix_free(Vm);
  gsl_vector_free(sv);
  gsl_vector_free(wk);
  return rc;
}

/* Words for a direction v (over the parameters cols[0..nc-1]) the records cannot fix. Picks
 * the parameter to hold (*hold, an index into cols). */
static void ea__describe(const ea__ws_t *w, const int *cols, int nc, const double *v, double se,
                         int have_torque_or_tension, int have_ring, int n_payloads, char *buf,
                         size_t len, int *hold) {
  double a[EA_CALIB_NP] = {0};
  int big = 0, best = 0;
  for (int j = 0; j < nc; ++j) {
    const int k = w->free_idx[cols[j]];
    a[k] = v[j];
    if (fabs(v[j]) > fabs(v[best])) best = j;
  }
  for (int k = 0; k < EA_CALIB_NP; ++k)
    big += fabs(a[k]) > 0.25;
  *hold = best;
  const int kb = w->free_idx[cols[best]];
  const double aEI = a[EA_CALIB_P_EI], ar = a[EA_CALIB_P_RHO], am = a[EA_CALIB_P_M_HAND];
  char comb[200] = "";
  size_t o = 0;
  for (int k = 0; k < EA_CALIB_NP && o < sizeof comb; ++k)
    if (fabs(a[k]) > 0.05)
      o += (size_t)snprintf(comb + o, sizeof comb - o, "%s%+.2f %s%s%s", o ? " " : "", a[k],
                            w->is_log[k] ? "log " : "", ea__pname[k],
                            k == EA_CALIB_P_PAYLOAD ? "/scale"
                            : w->is_log[k]          ? ""
                                                    : "/L");
  /* the unknown payload against the hand mass: the marked rows see only their sum */
  const double ap = a[EA_CALIB_P_PAYLOAD];
  if (fabs(ap) > 0.25 && fabs(am) > 0.25 && ap * am < 0) {
    for (int j = 0; j < nc; ++j)
      if (w->free_idx[cols[j]] == EA_CALIB_P_M_HAND) *hold = j;
    snprintf(buf, len,
             "payload against m_hand (%s; standard error %.3g): a payload known on no record "
             "cannot be separated from the hand mass; the records fix only the tip mass m_hand + "
             "payload. m_hand is held at the prior and the payload fitted relative to it (its "
             "value stands for the tip mass minus the prior's hand mass). Records at a known "
             "payload (e.g. without it) separate them.",
             comb, se);
    return;
  }
  /* the scale of the statics: EI, rho and m_hand together */
  if (fabs(aEI) > 0.25 && fabs(ar) > 0.25 && fabs(am) > 0.25 && aEI * ar > 0 && aEI * am > 0) {
    for (int j = 0; j < nc; ++j)
      if (w->free_idx[cols[j]] == EA_CALIB_P_EI) *hold = j;
    snprintf(buf, len,
             "EI, rho and m_hand together (%s; standard error %.3g): shoulder angles, cable "
             "angles and tip positions depend on them only through the weight-to-stiffness "
             "ratios rho g / EI and m_L g / EI%s, so these records fix the ratios, not the "
             "scale. "
             "%s EI is held at the prior; rho and m_hand are fitted relative to it (their values "
             "stand for rho/EI and m_hand/EI). A shoulder torque, a tension, a ring-down "
             "frequency or records at a second, known payload fix the scale.",
             comb, se,
             fabs(a[EA_CALIB_P_EA_CABLE]) > 0.25 ? " (and the cable's stretch T / EA_c)" : "",
             have_torque_or_tension || have_ring
                 ? "The torques, tensions or frequencies given are too few or too noisy to fix it:"
                 : "No record has a shoulder torque, a tension or a ring-down:");
    return;
  }
  if ((fabs(ar) > 0.25 || fabs(am) > 0.25) && big <= 3 && ar * am < 0 &&
      (kb == EA_CALIB_P_RHO || kb == EA_CALIB_P_M_HAND)) {
    snprintf(buf, len,
             "rho against m_hand (%s; standard error %.3g): the beam's weight and the hand's "
             "act alike in these configurations (%d payload%s); %s is held at the prior. "
             "Records at another known payload, or over a wider range of cable angles and "
             "lengths, separate them.",
             comb, se, n_payloads, n_payloads == 1 ? "" : "s", ea__pname[kb]);
    return;
  }
  if (kb == EA_CALIB_P_I_HAND && big == 1) {
    snprintf(buf, len,
             "I_L (standard error %.3g, relative): the hand's rotary inertia enters only the "
             "dynamics, %s; held at the prior.",
             se,
             have_ring ? "and the ring-downs' modes barely feel it (a ring-down that rocks the "
                         "hand, its second or third mode, would tell it)"
                       : "and no record is a ring-down");
    return;
  }
  if (kb == EA_CALIB_P_EA_CABLE && big == 1) {
    snprintf(buf, len,
             "EA_c (standard error %.3g, relative): the cable's stretch T / EA_c (about %.1g) is "
             "far below what the records resolve; held at the prior.",
             se, w->prior->act.tension_max / w->prior->EA_cable);
    return;
  }
  if (kb == EA_CALIB_P_X_C || kb == EA_CALIB_P_Y_C) {
    snprintf(buf, len,
             "the cable root (%s; standard error %.3g in units of the beam length): the records "
             "do not fix %s; held at the prior. Records with the cable angle or the tip "
             "position, or over a wider range of cable angles, fix it.",
             comb, se, ea__pname[kb]);
    return;
  }
  snprintf(buf, len,
           "the combination %s (standard error %.3g) is not fixed by the records; %s is held "
           "at the prior.",
           comb, se, ea__pname[kb]);
}

/* ------------------------------------------------------------------------ */
/* The fit                                                                   */
/* ------------------------------------------------------------------------ */

void ea_calib_result_free(ea_calib_result_t *res) {
  if (!res) return;
  if (res->rec)
    for (int r = 0; r < res->nrec; ++r) {
      free(res->rec[r].alpha);
      for (int c = 0; c < EA_CALIB_NCH; ++c)
        free(res->rec[r].pred[c]);
    }
  free(res->rec);
  res->rec = NULL;
  res->nrec = 0;
}

static void ea__ws_free(ea__ws_t *w) {
  free(w->rows);
  free(w->rings);
  free(w->noise);
  free(w->zc);
  free(w->fc);
  free(w->Jc);
}

/* Count residuals. */
static int ea__count(const ea__ws_t *w) {
  int m = 0;
  for (int i = 0; i < w->nrow; ++i)
    for (int c = 0; c < EA_CALIB_NCH; ++c)
      m += w->recs[w->rows[i].rec].has[c];
  for (int g = 0; g < w->nring; ++g)
    m += w->rings[g].nm;
  return m;
}

static ea_status_t ea__ws_resize(ea__ws_t *w, ea_error_t *err) {
  w->nz = w->nfree; /* the rows' angles are eliminated (variable projection) */
  w->m = ea__count(w);
  free(w->zc);
  free(w->fc);
  free(w->Jc);
  w->zc = calloc((size_t)w->nz + 1, sizeof *w->zc);
  w->fc = calloc((size_t)w->m + 1, sizeof *w->fc);
  w->Jc = calloc((size_t)w->m * (size_t)w->nz + 1, sizeof *w->Jc);
  w->have_cache = w->have_jac = 0;
  if (!w->zc || !w->fc || !w->Jc)
    return ea_error_set(err, EA_ERR_NOMEM, "out of memory (%d residuals x %d unknowns)", w->m,
                        w->nz);
  return EA_OK;
}

/* Per record and channel: chi^2 contributions and RMS, from residuals f (noise-weighted). */
static void ea__record_stats(const ea__ws_t *w, const double *f, ea_calib_result_t *res) {
  for (int rr = 0; rr < w->nrec; ++rr) {
    ea_calib_record_fit_t *rf = &res->rec[rr];
    rf->n = 0;
    rf->chi2 = 0;
    for (int c = 0; c < EA_CALIB_NCH; ++c)
      if (w->recs[rr].kind == EA_CALIB_STATIC) rf->rms[c] = NAN;
  }
  double ss[64][EA_CALIB_NCH];
  int cnt[64][EA_CALIB_NCH];
  memset(ss, 0, sizeof ss);
  memset(cnt, 0, sizeof cnt);
  int r = 0;
  for (int i = 0; i < w->nrow; ++i) {
    const int rr = w->rows[i].rec;
    const ea_calib_record_t *rec = &w->recs[rr];
    for (int c = 0; c < EA_CALIB_NCH; ++c) {
      if (!rec->has[c]) continue;
      res->rec[rr].chi2 += f[r] * f[r];
      res->rec[rr].n++;
      if (rr < 64) {
        const double d = f[r] * w->noise[rr][c];
        ss[rr][c] += d * d;
        cnt[rr][c]++;
      }
      ++r;
    }
  }
  for (int g = 0; g < w->nring; ++g) {
    const ea__ring_t *rg = &w->rings[g];
    for (int k = 0; k < rg->nm; ++k, ++r) {
      res->rec[rg->rec].chi2 += f[r] * f[r];
      res->rec[rg->rec].n++;
    }
  }
  for (int rr = 0; rr < w->nrec && rr < 64; ++rr)
    for (int c = 0; c < EA_CALIB_NCH; ++c)
      if (cnt[rr][c]) res->rec[rr].rms[c] = sqrt(ss[rr][c] / cnt[rr][c]);
}

ea_status_t ea_calib_fit(const ea_arm_t *prior, const ea_calib_record_t *recs, int nrec,
                         const ea_calib_settings_t *s, ea_calib_result_t *res, ea_error_t *err) {
  if (!res) return ea_error_set(err, EA_ERR_ARG, "ea_calib_fit: NULL result");
  memset(res, 0, sizeof *res);
  res->status = EA_ERR_ARG;
  if (!prior || !recs || nrec < 1) return ea_error_set(err, EA_ERR_ARG, "ea_calib_fit: no records");
  if (nrec > 64)
    return ea_error_set(err, EA_ERR_ARG, "ea_calib_fit: %d records (at most 64)", nrec);
  ea_calib_settings_t set;
  if (s)
    set = *s;
  else
    ea_calib_settings_default(&set);
  if (set.modes < 1 || set.modes > EA_CALIB_MAX_MODES || set.fe_elements < 1 ||
      !(set.ident_se > 0) || set.max_iter < 1 || !(set.freq_floor >= 0))
    return ea_error_set(err, EA_ERR_ARG, "ea_calib_fit: invalid settings");
  ea_status_t st = ea_arm_validate(prior, err);
  if (st) return st;
  const double t0 = ea__mono_s();
  res->prior = *prior;
  res->arm = *prior;
  res->nrec = nrec;
  res->rec = calloc((size_t)nrec, sizeof *res->rec);
  if (!res->rec) return ea_error_set(err, EA_ERR_NOMEM, "out of memory");
  ea__ws_t w = {0};
  w.prior = prior;
  w.recs = recs;
  w.nrec = nrec;
  w.set = &set;
  int any_unknown = 0;
  for (int r = 0; r < nrec; ++r)
    any_unknown |= recs[r].payload_unknown;
  w.pay0 = w.pay = set.payload_start;
  w.pay_scale = set.payload_scale > 0 ? set.payload_scale : prior->m_hand;
  if (!(w.pay_scale > 0)) w.pay_scale = 0.1;
  for (int k = 0; k < EA_CALIB_NP; ++k) {
    w.is_log[k] = ea_calib_param_is_arm(k) && (k != EA_CALIB_P_X_C && k != EA_CALIB_P_Y_C) &&
                  ea_calib_param_get(prior, k) > 0;
    res->value[k] = ea_calib_param_get(prior, k);
    res->se[k] = NAN;
    res->state[k] = (set.fix_mask >> k) & 1u ? EA_CALIB_FIXED : EA_CALIB_FITTED;
  }
  /* the unknown payload: a parameter only when a record is marked */
  res->value[EA_CALIB_P_PAYLOAD] = any_unknown ? set.payload_start : NAN;
  if (!any_unknown) res->state[EA_CALIB_P_PAYLOAD] = EA_CALIB_UNUSED;
  w.noise = calloc((size_t)nrec, sizeof *w.noise);
  int nrows_total = 0, nring = 0;
  for (int r = 0; r < nrec; ++r) {
    res->rec[r].kind = recs[r].kind;
    for (int c = 0; c < EA_CALIB_NCH; ++c) {
      res->rec[r].noise[c] = res->rec[r].rms[c] = NAN;
      if (!recs[r].has[c]) continue;
      const int given = recs[r].noise[c] > 0;
      if (w.noise) w.noise[r][c] = given ? recs[r].noise[c] : ea__noise_default[c];
      res->rec[r].noise_estimated[c] = !given;
    }
    if (recs[r].kind == EA_CALIB_STATIC)
      nrows_total += recs[r].rows;
    else
      ++nring;
  }
  w.rows = calloc((size_t)nrows_total + 1, sizeof *w.rows);
  w.rings = calloc((size_t)nring + 1, sizeof *w.rings);
  if (!w.noise || !w.rows || !w.rings) {
    st = ea_error_set(err, EA_ERR_NOMEM, "out of memory");
    goto done;
  }
  /* payloads seen (for the words) */
  double payloads[64];
  int npay = 0;
  int have_tt = 0;
  /* 1. Static rows: starting cable angles on the prior. */
  {
    ea_shooter_t *sh = NULL;
    if ((st = ea_shooter_alloc(prior, NULL, &sh, err))) goto done;
    for (int r = 0; r < nrec; ++r) {
      const ea_calib_record_t *rec = &recs[r];
      if (rec->kind != EA_CALIB_STATIC) continue;
      have_tt |= rec->has[EA_CALIB_CH_TORQUE] || rec->has[EA_CALIB_CH_TENSION];
      res->rec[r].alpha = calloc((size_t)rec->rows, sizeof(double));
      for (int c = 0; c < EA_CALIB_NCH; ++c)
        if (rec->has[c]) res->rec[r].pred[c] = calloc((size_t)rec->rows, sizeof(double));
      double prev[EA_NP];
      int have_prev = 0;
      for (int i = 0; i < rec->rows; ++i) {
        ea__row_t *row = &w.rows[w.nrow];
        row->rec = r;
        row->row = i;
        row->L = rec->cable_length[i];
        row->unknown = rec->payload_unknown;
        row->payload = row->unknown ? set.payload_start : rec->payload[i];
        int seen = 0;
        for (int q = 0; q < npay; ++q)
          seen |= fabs(payloads[q] - row->payload) < 1e-9;
        if (!row->unknown && !seen && npay < 64) payloads[npay++] = row->payload;
        ea_load_t load = {prior->m_hand + row->payload};
        ea_shooter_set_load(sh, &load);
        ea_statics_solution_t sol;
        ea_error_t e = {0};
        double p[EA_NP];
        if (have_prev) memcpy(p, prev, sizeof p);
        if (rec->has[EA_CALIB_CH_CABLE_ANGLE]) {
          st = ea__row_solve(sh, prior, row->L, rec->ch[EA_CALIB_CH_CABLE_ANGLE][i], p, have_prev,
                             &e);
        } else {
          (void)sol;
          st = ea__angle_init(sh, prior, row->L, rec->ch[EA_CALIB_CH_THETA0][i], p, &e);
        }
        if (st) {
          ea_shooter_free(sh);
          st = ea_error_set(err, EA_ERR_INPUT,
                            "%s:%d: the prior arm has no static configuration with cable length "
                            "%.6g m and %s %.6g rad (%s): is it the record's arm?",
                            rec->path, rec->line[i], row->L,
                            rec->has[EA_CALIB_CH_CABLE_ANGLE] ? "cable angle" : "shoulder angle",
                            rec->has[EA_CALIB_CH_CABLE_ANGLE] ? rec->ch[EA_CALIB_CH_CABLE_ANGLE][i]
                                                              : rec->ch[EA_CALIB_CH_THETA0][i],
                            e.msg);
          goto done;
        }
        memcpy(row->p, p, sizeof p);
        memcpy(prev, p, sizeof p);
        have_prev = 1;
        ++w.nrow;
      }
    }
    ea_shooter_free(sh);
  }
  /* 2. Ring-downs: damped sinusoids, matched to the prior's FE modes. */
  for (int r = 0; r < nrec; ++r) {
    const ea_calib_record_t *rec = &recs[r];
    if (rec->kind != EA_CALIB_RINGDOWN) continue;
    ea_calib_record_fit_t *rf = &res->rec[r];
    ea__ring_t *rg = &w.rings[w.nring];
    rg->rec = r;
    rg->L = rec->hold_cable_length;
    rg->theta0 = rec->hold_theta0;
    rg->unknown = rec->payload_unknown;
    rg->payload = rg->unknown ? set.payload_start : rec->payload_kg;
    int seen = 0;
    for (int q = 0; q < npay; ++q)
      seen |= fabs(payloads[q] - rg->payload) < 1e-9;
    if (!rg->unknown && !seen && npay < 64) payloads[npay++] = rg->payload;
    double fe[EA_FE_MAX_MODES];
    const int nfe = set.modes;
    ea_error_t e = {0};
    if ((st = ea__hold_freq(&w, prior, w.pay0, rg, nfe, fe, &e))) {
      st = ea_error_set(err, EA_ERR_INPUT,
                        "%s: the prior arm has no FE equilibrium at the hold (cable length %.6g "
                        "m, shoulder angle %.6g rad): %s",
                        rec->path, rg->L, rg->theta0, e.msg);
      goto done;
    }
    /* sinusoids sought up to twice the highest FE mode matched (the axial and cable modes far
     * above are not of interest) */
    if ((st = ea_ringdown_fit(rec, EA_CALIB_MAX_MODES, 2.0 * fe[nfe - 1], &rf->ring, err)))
      goto done;
    for (int c = 0; c < EA_CALIB_NCH; ++c)
      if (rec->has[c]) {
        rf->noise[c] = rf->ring.noise[c];
        rf->rms[c] = rf->ring.rms[c];
      }
    /* each FE mode to the nearest fitted sinusoid in log frequency (a factor 1.6 at most);
     * sinusoids left over (harmonics of a large motion) are not used */
    for (int q = 0; q < nfe; ++q) {
      int best = -1;
      double bd = log(1.6);
      for (int k = 0; k < rf->ring.modes; ++k) {
        const double dd = fabs(log(rf->ring.freq_hz[k] / fe[q]));
        if (rf->ring.mode_index[k] < 0 && dd < bd) bd = dd, best = k;
      }
      if (best >= 0) rf->ring.mode_index[best] = q;
    }
    for (int k = 0; k < rf->ring.modes; ++k) {
      if (rf->ring.mode_index[k] < 0) continue;
      rg->mode[rg->nm] = rf->ring.mode_index[k];
      rg->f[rg->nm] = rf->ring.freq_hz[k];
      rg->sf[rg->nm] = hypot(rf->ring.freq_se_hz[k], set.freq_floor * rf->ring.freq_hz[k]);
      rg->nm++;
    }
    /* statics warm start at the hold */
    {
      ea_shooter_t *sh = NULL;
      if (!ea_shooter_alloc(prior, NULL, &sh, NULL)) {
        ea_load_t load = {prior->m_hand + rg->payload};
        ea_shooter_set_load(sh, &load);
        ea_statics_solution_t sol;
        if (!ea__hold_solve(sh, prior, rg->L, rg->theta0, rg->p, 0, &sol, NULL)) rg->have_p = 1;
        ea_shooter_free(sh);
      }
    }
    ++w.nring;
  }
  /* a row with a shoulder angle alone tells nothing: its cable angle, not sensed, takes it up */
  for (int r = 0; r < nrec; ++r) {
    int others = 0;
    for (int c = 0; c < EA_CALIB_NCH; ++c)
      others += c != EA_CALIB_CH_THETA0 && recs[r].has[c];
    if (recs[r].kind == EA_CALIB_STATIC && !others && res->n_notes < EA_CALIB_MAX_NOTES)
      snprintf(res->notes[res->n_notes++], sizeof res->notes[0],
               "%s has only shoulder angles: the cable angle of each row is not sensed, so "
               "fitting it takes up the row's one value and the record tells nothing about the "
               "arm. A cable angle or tip position column (shoulder angles then fix the "
               "weight-to-EI ratios), or a torque or tension column, makes it count.",
               recs[r].path);
  }
  /* 3. Free parameters: all not fixed; identifiability at the prior removes some. */
  w.nfree = 0;
  for (int k = 0; k < EA_CALIB_NP; ++k)
    if (res->state[k] == EA_CALIB_FITTED) w.free_idx[w.nfree++] = k;
  if ((st = ea__ws_resize(&w, err))) goto done;
  if (w.m < 1) {
    st = ea_error_set(err, EA_ERR_INPUT, "the records hold no measured values to fit");
    goto done;
  }
  {
    double *z = calloc((size_t)w.nz + 1, sizeof *z);
    if (!z) {
      st = ea_error_set(err, EA_ERR_NOMEM, "out of memory");
      goto done;
    }
    if ((st = ea__eval(&w, z, w.fc, w.Jc))) {
      free(z);
      st = ea_error_set(err, st, "%s", w.err.msg);
      goto done;
    }
    free(z);
    const int have_ring = w.nring > 0;
    int cols[EA_CALIB_NP], nc = 0;
    for (int j = 0; j < w.nfree; ++j)
      cols[nc++] = j;
    double R[64 * EA_CALIB_NP], sv[EA_CALIB_NP], V[EA_CALIB_NP * EA_CALIB_NP];
    while (nc > 0) {
      const int rows = ea__profile(&w, w.Jc, cols, nc, R);
      if (rows < 0 || ea__svd(R, rows, nc, sv, V)) {
        st = ea_error_set(err, EA_ERR_BACKEND, "SVD of the fit's Jacobian failed");
        goto done;
      }
      const double smin = sv[nc - 1];
      const double se = smin > 0 ? 1.0 / smin : INFINITY;
      if (se <= set.ident_se) break;
      double v[EA_CALIB_NP];
      for (int j = 0; j < nc; ++j)
        v[j] = V[j * nc + nc - 1];
      int hold = 0;
      char words[1024];
      ea__describe(&w, cols, nc, v, se, have_tt, have_ring, npay, words, sizeof words, &hold);
      const int k = w.free_idx[cols[hold]];
      res->state[k] = EA_CALIB_UNIDENTIFIABLE;
      if (res->n_notes < EA_CALIB_MAX_NOTES)
        snprintf(res->notes[res->n_notes++], sizeof res->notes[0], "%s", words);
      for (int j = hold; j + 1 < nc; ++j)
        cols[j] = cols[j + 1];
      --nc;
    }
    /* which records inform which parameter (column norms per record) */
    for (int j = 0; j < w.nfree; ++j) {
      int r = 0;
      double tot = 0, per[64] = {0};
      for (int i = 0; i < w.nrow; ++i)
        for (int c = 0; c < EA_CALIB_NCH; ++c)
          if (recs[w.rows[i].rec].has[c]) {
            const double v = w.Jc[(size_t)r * w.nz + j];
            per[w.rows[i].rec] += v * v;
            tot += v * v;
            ++r;
          }
      for (int g = 0; g < w.nring; ++g)
        for (int k = 0; k < w.rings[g].nm; ++k, ++r) {
          const double v = w.Jc[(size_t)r * w.nz + j];
          per[w.rings[g].rec] += v * v;
          tot += v * v;
        }
      for (int q = 0; q < nrec && q < 32; ++q)
        if (per[q] > 1e-6 * tot && per[q] > 0) res->contributes[w.free_idx[j]] |= 1 << q;
    }
  }
  /* 4. Fit the identifiable parameters and the angles. */
  w.nfree = 0;
  for (int k = 0; k < EA_CALIB_NP; ++k)
    if (res->state[k] == EA_CALIB_FITTED) w.free_idx[w.nfree++] = k;
  if ((st = ea__ws_resize(&w, err))) goto done;
  int any_est = 0;
  for (int r = 0; r < nrec; ++r)
    for (int c = 0; c < EA_CALIB_NCH; ++c)
      any_est |= recs[r].kind == EA_CALIB_STATIC && recs[r].has[c] && !(recs[r].noise[c] > 0);
  gsl_vector *x = gsl_vector_calloc((size_t)w.nz + (w.nz == 0));
  gsl_multifit_nlinear_workspace *nw = NULL;
  gsl_matrix *cov = gsl_matrix_alloc((size_t)w.nz + (w.nz == 0), (size_t)w.nz + (w.nz == 0));
  if (!x || !cov) {
    gsl_vector_free(x);
    gsl_matrix_free(cov);
    st = ea_error_set(err, EA_ERR_NOMEM, "out of memory");
    goto done;
  }
  gsl_multifit_nlinear_parameters fp = gsl_multifit_nlinear_default_parameters();
  fp.trs = gsl_multifit_nlinear_trs_lm;
  fp.scale = gsl_multifit_nlinear_scale_more;
  gsl_multifit_nlinear_fdf fdf = {ea__gsl_f, ea__gsl_df, NULL, (size_t)w.m, (size_t)w.nz, &w,
                                  0,         0,          0};
  if (w.m < w.nz + w.nrow) {
    gsl_vector_free(x);
    gsl_matrix_free(cov);
    st = ea_error_set(err, EA_ERR_INPUT,
                      "%d measured values for %d unknowns (%d parameters, %d cable angles): the "
                      "records are too few",
                      w.m, w.nz + w.nrow, w.nfree, w.nrow);
    goto done;
  }
  if (w.nz)
    nw = gsl_multifit_nlinear_alloc(gsl_multifit_nlinear_trust, &fp, (size_t)w.m, (size_t)w.nz);
  if (w.nz && !nw) {
    gsl_vector_free(x);
    gsl_matrix_free(cov);
    st = ea_error_set(err, EA_ERR_NOMEM, "out of memory (fit workspace)");
    goto done;
  }
  for (int pass = 0; w.nz && pass < (any_est ? 2 : 1); ++pass) {
    int info = 0;
    w.failed = 0;
    if (gsl_multifit_nlinear_init(x, &fdf, nw) != GSL_SUCCESS || w.failed) {
      st = ea_error_set(err, EA_ERR_INPUT, "the fit cannot start: %s", w.err.msg);
      break;
    }
    const int gs =
        gsl_multifit_nlinear_driver((size_t)set.max_iter, 1e-9, 1e-9, 1e-12, NULL, NULL, &info, nw);
    res->iterations += (int)gsl_multifit_nlinear_niter(nw);
    /* a second pass starts at the first one's solution: ea__nls_converged accepts that */
    if (!ea__nls_converged(nw, gs, (size_t)set.max_iter)) {
      st = ea_error_set(
          err, EA_ERR_NOCONV, "the fit did not converge (%s after %zu iterations%s%s)",
          gs == GSL_EMAXITER ? "iteration limit" : gsl_strerror(gs), gsl_multifit_nlinear_niter(nw),
          w.failed ? "; last failure: " : "", w.failed ? w.err.msg : "");
      break;
    }
    gsl_vector_memcpy(x, gsl_multifit_nlinear_position(nw));
    if (!any_est || pass == 1) break;
    /* noise not given: the residual's RMS per record and channel, then fit again */
    if (ea__cache(&w, x, 0)) {
      st = ea_error_set(err, EA_ERR_NOCONV, "the fit's solution failed: %s", w.err.msg);
      break;
    }
    ea__record_stats(&w, w.fc, res);
    const double dofc = (double)w.m / fmax(w.m - w.nz - w.nrow, 1);
    for (int r = 0; r < nrec; ++r)
      for (int c = 0; c < EA_CALIB_NCH; ++c)
        if (recs[r].kind == EA_CALIB_STATIC && recs[r].has[c] && !(recs[r].noise[c] > 0) &&
            res->rec[r].rms[c] > 0)
          w.noise[r][c] = res->rec[r].rms[c] * sqrt(dofc);
    w.have_cache = w.have_jac = 0;
  }
  if (!st) {
    /* the solution: residuals, Jacobian and covariance (nothing to fit: the residuals) */
    if (!w.nz) {
      double zz[1] = {0};
      if (ea__eval(&w, zz, w.fc, NULL))
        st = ea_error_set(err, EA_ERR_INPUT, "the records do not fit the prior: %s", w.err.msg);
    } else if (ea__cache(&w, x, 1)) {
      st = ea_error_set(err, EA_ERR_NOCONV, "the fit's solution failed: %s", w.err.msg);
    } else {
      gsl_matrix_view Jv = gsl_matrix_view_array(w.Jc, (size_t)w.m, (size_t)w.nz);
      if (gsl_multifit_nlinear_covar(&Jv.matrix, 0.0, cov) != GSL_SUCCESS)
        st = ea_error_set(err, EA_ERR_SINGULAR, "the covariance of the fit is singular");
    }
  }
  if (!st) {
    double z[EA_CALIB_NP];
    for (int j = 0; j < w.nfree; ++j)
      z[j] = gsl_vector_get(x, (size_t)j);
    ea__arm_of(&w, z, &res->arm);
    w.pay = ea__pay_of(&w, z);
    for (int j = 0; j < w.nfree; ++j) {
      const int k = w.free_idx[j];
      const double v = k == EA_CALIB_P_PAYLOAD ? w.pay : ea_calib_param_get(&res->arm, k);
      res->value[k] = v;
      const double su = sqrt(fmax(gsl_matrix_get(cov, (size_t)j, (size_t)j), 0.0));
      res->se[k] = k == EA_CALIB_P_PAYLOAD ? su * w.pay_scale
                   : w.is_log[k]           ? v * su
                                           : su * prior->length;
      for (int q = 0; q < w.nfree; ++q) {
        const int k2 = w.free_idx[q];
        const double c = gsl_matrix_get(cov, (size_t)j, (size_t)q);
        const double dd = sqrt(gsl_matrix_get(cov, (size_t)j, (size_t)j) *
                               gsl_matrix_get(cov, (size_t)q, (size_t)q));
        res->corr[k * EA_CALIB_NP + k2] = dd > 0 ? c / dd : 0.0;
      }
    }
    for (int k = 0; k < EA_CALIB_NP; ++k)
      if (res->state[k] != EA_CALIB_FITTED) res->corr[k * EA_CALIB_NP + k] = NAN;
    /* singular values at the solution (profiled) */
    int cols[EA_CALIB_NP];
    for (int j = 0; j < w.nfree; ++j)
      cols[j] = j;
    double R[64 * EA_CALIB_NP], V[EA_CALIB_NP * EA_CALIB_NP];
    const int rows = w.nfree ? ea__profile(&w, w.Jc, cols, w.nfree, R) : 0;
    if (w.nfree && rows >= 0 && !ea__svd(R, rows, w.nfree, res->sv, V)) res->n_sv = w.nfree;
    /* statistics and per-row values */
    ea__record_stats(&w, w.fc, res);
    res->chi2 = 0;
    for (int i = 0; i < w.m; ++i)
      res->chi2 += w.fc[i] * w.fc[i];
    res->n_residuals = w.m;
    res->dof = w.m - w.nz - w.nrow;
    for (int r = 0; r < nrec; ++r)
      for (int c = 0; c < EA_CALIB_NCH; ++c)
        if (recs[r].kind == EA_CALIB_STATIC && recs[r].has[c]) res->rec[r].noise[c] = w.noise[r][c];
    for (int i = 0; i < w.nrow; ++i) {
      const ea__row_t *row = &w.rows[i];
      ea_calib_record_fit_t *rf = &res->rec[row->rec];
      if (rf->alpha) rf->alpha[row->row] = row->p[EA_P_ALPHA];
      const double pv[EA_CALIB_NCH] = {
          row->p[EA_P_THETA0], res->arm.EI * row->p[EA_P_KAPPA0], row->p[EA_P_TENSION], NAN, NAN,
          row->p[EA_P_ALPHA]};
      for (int c = 0; c < EA_CALIB_NCH; ++c)
        if (rf->pred[c]) rf->pred[c][row->row] = pv[c];
    }
    /* tip predictions need a shot */
    {
      ea_shooter_t *sh = NULL;
      if (!ea_shooter_alloc(&res->arm, NULL, &sh, NULL)) {
        for (int i = 0; i < w.nrow; ++i) {
          const ea__row_t *row = &w.rows[i];
          ea_calib_record_fit_t *rf = &res->rec[row->rec];
          if (!rf->pred[EA_CALIB_CH_TIP_X] && !rf->pred[EA_CALIB_CH_TIP_Y]) continue;
          ea_load_t load = {res->arm.m_hand + (row->unknown ? w.pay : row->payload)};
          ea_shooter_set_load(sh, &load);
          double xL[EA_NX];
          if (ea_shoot(sh, row->p, xL, NULL)) continue;
          if (rf->pred[EA_CALIB_CH_TIP_X]) rf->pred[EA_CALIB_CH_TIP_X][row->row] = xL[EA_X_X];
          if (rf->pred[EA_CALIB_CH_TIP_Y]) rf->pred[EA_CALIB_CH_TIP_Y][row->row] = xL[EA_X_Y];
        }
        ea_shooter_free(sh);
      }
    }
    for (int g = 0; g < w.nring; ++g) {
      const ea__ring_t *rg = &w.rings[g];
      ea_calib_record_fit_t *rf = &res->rec[rg->rec];
      for (int k = 0; k < EA_CALIB_MAX_MODES; ++k)
        rf->model_freq_hz[k] = NAN;
      int q = 0;
      for (int k = 0; k < rf->ring.modes; ++k)
        if (rf->ring.mode_index[k] >= 0) rf->model_freq_hz[k] = rg->model[q++];
    }
  }
  if (nw) gsl_multifit_nlinear_free(nw);
  gsl_vector_free(x);
  gsl_matrix_free(cov);
  if (st) goto done;
  /* 5. Damping ratios: weighted means over the ring-downs, per FE mode. Mode 1's ratio of the
   * arm file is the one at the records' start (the first static row: where a recorded session
   * starts), as ea_traj_simulate reads it (strain-rate damping of one coefficient b, set by
   * zeta_1 at a simulation's start): each ring-down's zeta_1 is carried there as b = zeta_1 /
   * g1 (g1: the FE's ratio per unit b at the hold) times g1 at the start. */
  if (!set.fix_damping) {
    double to_start[EA_CALIB_MAX_RECORDS_SCALE];
    for (int r = 0; r < nrec && r < EA_CALIB_MAX_RECORDS_SCALE; ++r)
      to_start[r] = 1.0;
    int r0 = 0;
    while (r0 < nrec && !(recs[r0].kind == EA_CALIB_STATIC && recs[r0].rows > 0))
      ++r0;
    if (set.damping_at_start && r0 < nrec) {
      ea__ring_t ref = {0};
      ref.L = recs[r0].cable_length[0];
      ref.theta0 = recs[r0].ch[EA_CALIB_CH_THETA0][0];
      ref.unknown = recs[r0].payload_unknown;
      ref.payload = recs[r0].payload ? recs[r0].payload[0] : recs[r0].payload_kg;
      double f1, g_ref = NAN;
      ea_error_t e2 = {0};
      if (ea__hold_fe(&w, &res->arm, w.pay, &ref, 1, &f1, &g_ref, &e2) == EA_OK && g_ref > 0)
        for (int g = 0; g < w.nring; ++g) {
          double fg[EA_CALIB_MAX_MODES], g1 = NAN;
          const int r = w.rings[g].rec;
          if (r < EA_CALIB_MAX_RECORDS_SCALE &&
              ea__hold_fe(&w, &res->arm, w.pay, &w.rings[g], 1, fg, &g1, &e2) == EA_OK && g1 > 0)
            to_start[r] = g_ref / g1;
        }
    }
    double sw[EA_ARM_MAX_DAMPED_MODES] = {0}, swz[EA_ARM_MAX_DAMPED_MODES] = {0},
           swzz[EA_ARM_MAX_DAMPED_MODES] = {0};
    int cnt[EA_ARM_MAX_DAMPED_MODES] = {0};
    for (int r = 0; r < nrec; ++r) {
      if (recs[r].kind != EA_CALIB_RINGDOWN) continue;
      const ea_ringdown_fit_t *rf = &res->rec[r].ring;
      for (int k = 0; k < rf->modes; ++k) {
        const int q = rf->mode_index[k];
        if (q < 0 || q >= EA_ARM_MAX_DAMPED_MODES) continue;
        const double sc = (q == 0 && r < EA_CALIB_MAX_RECORDS_SCALE) ? to_start[r] : 1.0;
        const double z = sc * rf->zeta[k], se = fmax(sc * rf->zeta_se[k], 1e-6);
        const double wt = 1.0 / (se * se);
        sw[q] += wt;
        swz[q] += wt * z;
        swzz[q] += wt * z * z;
        cnt[q]++;
      }
    }
    int n = 0;
    while (n < EA_ARM_MAX_DAMPED_MODES && cnt[n] > 0 && swz[n] / sw[n] >= 0 && swz[n] / sw[n] < 1) {
      const double mean = swz[n] / sw[n];
      /* the spread over the ring-downs (the configurations differ) counts when it exceeds
       * the fits' own errors: Birge ratio */
      double se = 1.0 / sqrt(sw[n]);
      if (cnt[n] > 1) {
        const double chi2 = swzz[n] - sw[n] * mean * mean;
        const double birge = chi2 / (cnt[n] - 1);
        if (birge > 1) se *= sqrt(birge);
      }
      res->zeta[n] = mean;
      res->zeta_se[n] = se;
      res->zeta_count[n] = cnt[n];
      ++n;
    }
    res->n_zeta = n;
    if (n > 0) {
      /* modes the prior had beyond the measured ones are kept */
      const int keep = prior->n_damping > n ? prior->n_damping : n;
      res->arm.n_damping = keep;
      for (int q = 0; q < n; ++q)
        res->arm.damping_ratio[q] = res->zeta[q];
    }
  }
  if ((st = ea_arm_validate(&res->arm, err))) goto done;
  res->time_s = ea__mono_s() - t0;
  res->status = EA_OK;
done:
  ea__ws_free(&w);
  if (st) res->status = st;
  res->time_s = ea__mono_s() - t0;
  return st;
}
