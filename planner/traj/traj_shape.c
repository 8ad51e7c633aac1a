/* Zero-vibration input shaping of a trajectory with a delay that follows the
 * first natural frequency along the motion (ea_traj_shape_zv), and the re-check
 * of a trajectory file against every limit of its task (ea_traj_check_limits);
 * planner/include/ea_simulate.h, docs/planner.md "ZV-shaped plans". */
#include "ea_simulate.h"
#include "ea_util.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ------------------------------------------------------------------------ */
/* Cubic pieces                                                              */
/* ------------------------------------------------------------------------ */

/* Cubic Hermite on [0, h] at s in [0, 1]: value, rate, acceleration. */
static void ea__herm(double h, double s, double q0, double v0, double q1, double v1, double *q,
                     double *v, double *a) {
  const double d = q1 - q0;
  const double c2 = 3.0 * d - h * (2.0 * v0 + v1), c3 = -2.0 * d + h * (v0 + v1);
  *q = q0 + s * (h * v0 + s * (c2 + s * c3));
  *v = (h * v0 + s * (2.0 * c2 + s * 3.0 * c3)) / h;
  *a = (2.0 * c2 + 6.0 * c3 * s) / (h * h);
}

/* Points s in (0, 1) of the cubic Hermite's extrema: of its value (the roots of its
 * quadratic rate, up to 2) and of its rate (the vertex, 1). Returns how many, in out. */
static int ea__herm_extrema(double h, double q0, double v0, double q1, double v1, double out[3]) {
  const double d = q1 - q0, c2 = 3.0 * d - h * (2.0 * v0 + v1), c3 = -2.0 * d + h * (v0 + v1);
  /* h q'(s) = h v0 + 2 c2 s + 3 c3 s^2 */
  const double A = 3.0 * c3, B = 2.0 * c2, C = h * v0;
  double r[3];
  int nr = 0;
  if (fabs(A) > 1e-300) {
    r[nr++] = -B / (2.0 * A); /* vertex of the rate */
    const double disc = B * B - 4.0 * A * C;
    if (disc >= 0.0) {
      const double sq = sqrt(disc), qq = -0.5 * (B + (B >= 0.0 ? sq : -sq));
      if (qq != 0.0) r[nr++] = C / qq;
      r[nr++] = qq / A;
    }
  } else if (fabs(B) > 0.0) {
    r[nr++] = -C / B;
  }
  int n = 0;
  for (int i = 0; i < nr; ++i)
    if (r[i] > 0.0 && r[i] < 1.0) out[n++] = r[i];
  return n;
}

/* Rates of the C2 cubic spline through (x_i, y_i), i < n, with the end rates v0, v1
 * (clamped): m gets n rates. w: scratch of 2 n. */
static void ea__spline_rates(int n, const double *x, const double *y, double v0, double v1,
                             double *m, double *w) {
  m[0] = v0;
  m[n - 1] = v1;
  if (n <= 2) return;
  /* interior i = 1..n-2: a m_{i-1} + b m_i + c m_{i+1} = d; Thomas */
  double *cp = w, *dp = w + n;
  for (int i = 1; i <= n - 2; ++i) {
    const double h0 = x[i] - x[i - 1], h1 = x[i + 1] - x[i];
    const double a = 1.0 / h0, c = 1.0 / h1, b = 2.0 * (a + c);
    double d = 3.0 * ((y[i] - y[i - 1]) / (h0 * h0) + (y[i + 1] - y[i]) / (h1 * h1));
    if (i == 1) d -= a * v0;
    const double cc = (i == n - 2) ? 0.0 : c;
    if (i == n - 2) d -= c * v1;
    const double den = b - (i > 1 ? a * cp[i - 1] : 0.0);
    cp[i] = cc / den;
    dp[i] = (d - (i > 1 ? a * dp[i - 1] : 0.0)) / den;
  }
  m[n - 2] = dp[n - 2];
  for (int i = n - 3; i >= 1; --i)
    m[i] = dp[i] - cp[i] * m[i + 1];
}

/* A piecewise cubic Hermite (x_i, y_i, rate_i), held at its end values outside
 * [x_0, x_{n-1}]: value, rate and acceleration at u, from the interval on side
 * (-1: the one ending at u, +1: the one starting at u) when u is a breakpoint. */
typedef struct {
  int n;
  const double *x, *y, *v;
} ea__pw_t;

static void ea__pw_eval(const ea__pw_t *p, double u, int side, double *q, double *v, double *a) {
  const int n = p->n;
  const double *x = p->x;
  if (u < x[0] || (u == x[0] && side < 0)) {
    *q = p->y[0], *v = 0.0, *a = 0.0;
    return;
  }
  if (u > x[n - 1] || (u == x[n - 1] && side > 0)) {
    *q = p->y[n - 1], *v = 0.0, *a = 0.0;
    return;
  }
  /* interval k: x_k <= u < x_{k+1} (side +1) or x_k < u <= x_{k+1} (side -1) */
  int lo = 0, hi = n - 1;
  while (hi - lo > 1) {
    const int mid = (lo + hi) / 2;
    if (side > 0 ? x[mid] <= u : x[mid] < u)
      lo = mid;
    else
      hi = mid;
  }
  const int k = lo;
  const double h = x[k + 1] - x[k];
  ea__herm(h, (u - x[k]) / h, p->y[k], p->v[k], p->y[k + 1], p->v[k + 1], q, v, a);
}

/* ------------------------------------------------------------------------ */
/* Limits check                                                              */
/* ------------------------------------------------------------------------ */

static const char *const ea__lim_names[EA_TRAJ_LIMIT_COUNT] = {"cable length range",
                                                               "cable speed",
                                                               "cable acceleration",
                                                               "cable angle speed",
                                                               "cable angle acceleration",
                                                               "tension minimum",
                                                               "tension maximum",
                                                               "shoulder torque",
                                                               "shoulder angle range",
                                                               "shoulder speed",
                                                               "shoulder acceleration",
                                                               "base angle range",
                                                               "base speed",
                                                               "base acceleration",
                                                               "first natural frequency",
                                                               "modal deflection"};
static const char *const ea__lim_units[EA_TRAJ_LIMIT_COUNT] = {
    "m",   "m/s",   "m/s^2",   "rad/s", "rad/s^2", "N",       "N",  "N m",
    "rad", "rad/s", "rad/s^2", "rad",   "rad/s",   "rad/s^2", "Hz", "m"};

const char *ea_traj_limit_name(ea_traj_limit_t i) {
  return (int)i >= 0 && i < EA_TRAJ_LIMIT_COUNT ? ea__lim_names[i] : "unknown limit";
}

static void ea__note(ea_traj_limits_check_t *c, int i, double excess, double value, double bound,
                     double t) {
  if (excess > c->excess[i]) {
    c->excess[i] = excess;
    c->value[i] = value;
    c->bound[i] = bound;
    c->time_s[i] = t;
  }
}

/* |v| <= max (max finite) */
static void ea__note_abs(ea_traj_limits_check_t *c, int i, double v, double max, double t) {
  if (isfinite(max)) ea__note(c, i, fabs(v) / max - 1.0, v, max, t);
}

/* v in [lo, hi]: the distance outside over the width */
static void ea__note_range(ea_traj_limits_check_t *c, int i, double v, double lo, double hi,
                           double t) {
  const double e = fmax(lo - v, v - hi) / (hi - lo);
  ea__note(c, i, e, v, v < 0.5 * (lo + hi) ? lo : hi, t);
}

/* One point of interval k at s in [0, 1]: the cubics and the statics (p: warm start
 * in, solution out). */
static void ea__check_point(const ea_task_t *t, const ea_traj_t *tr, ea_shooter_t *sh, int k,
                            double s, double p[EA_NP], ea_traj_limits_check_t *c) {
  const ea_task_limits_t *l = &t->limits;
  const ea_actuators_t *a = &t->arm.act;
  static const int qc[4] = {EA_TRAJ_cable_length, EA_TRAJ_cable_angle, EA_TRAJ_base_angle,
                            EA_TRAJ_theta0};
  static const int vc[4] = {EA_TRAJ_cable_length_rate, EA_TRAJ_cable_angle_rate,
                            EA_TRAJ_base_angle_rate, EA_TRAJ_theta0_rate};
  const double t0 = EA_TRAJ_AT(tr, k, EA_TRAJ_t), h = EA_TRAJ_AT(tr, k + 1, EA_TRAJ_t) - t0;
  const double tt = t0 + s * h;
  double q[4], v[4], acc[4];
  for (int i = 0; i < 4; ++i)
    ea__herm(h, s, EA_TRAJ_AT(tr, k, qc[i]), EA_TRAJ_AT(tr, k, vc[i]), EA_TRAJ_AT(tr, k + 1, qc[i]),
             EA_TRAJ_AT(tr, k + 1, vc[i]), &q[i], &v[i], &acc[i]);
  ea__note_range(c, EA_TRAJ_LIMIT_CABLE_LENGTH, q[0], l->cable_length_min, l->cable_length_max, tt);
  ea__note_abs(c, EA_TRAJ_LIMIT_CABLE_SPEED, v[0], l->cable_speed_max, tt);
  ea__note_abs(c, EA_TRAJ_LIMIT_CABLE_ACCEL, acc[0], l->cable_accel_max, tt);
  ea__note_abs(c, EA_TRAJ_LIMIT_ANGLE_SPEED, v[1], l->cable_angle_speed_max, tt);
  ea__note_abs(c, EA_TRAJ_LIMIT_ANGLE_ACCEL, acc[1], l->cable_angle_accel_max, tt);
  ea__note_range(c, EA_TRAJ_LIMIT_BASE_ANGLE, q[2], a->base_angle_min, a->base_angle_max, tt);
  ea__note_abs(c, EA_TRAJ_LIMIT_BASE_SPEED, v[2], l->base_speed_max, tt);
  ea__note_abs(c, EA_TRAJ_LIMIT_BASE_ACCEL, acc[2], l->base_accel_max, tt);
  ea__note_range(c, EA_TRAJ_LIMIT_SHOULDER_ANGLE, q[3], a->shoulder_angle_min,
                 a->shoulder_angle_max, tt);
  ea__note_abs(c, EA_TRAJ_LIMIT_SHOULDER_SPEED, v[3], l->shoulder_speed_max, tt);
  ea__note_abs(c, EA_TRAJ_LIMIT_SHOULDER_ACCEL, acc[3], a->shoulder_accel_max, tt);
  ++c->samples;
  ea_statics_settings_t set;
  ea_statics_settings_default(&set);
  set.tol = 1e-12;
  p[0] = q[1];
  const ea_statics_problem_t prob = ea_statics_problem_cable(q[0], q[1]);
  ea_statics_solution_t sol;
  if (ea_statics_solve(sh, &prob, &set, p, &sol, NULL) != EA_OK &&
      ea_statics_solve(sh, &prob, &set, NULL, &sol, NULL) != EA_OK) {
    if (!c->statics_failures++) c->first_failure_s = tt;
    return;
  }
  memcpy(p, sol.p, EA_NP * sizeof *p);
  const double T = sol.p[EA_P_TENSION], tau = t->arm.EI * sol.p[EA_P_KAPPA0];
  ea__note(c, EA_TRAJ_LIMIT_TENSION_MIN, (l->tension_min - T) / l->tension_min, T, l->tension_min,
           tt);
  ea__note_abs(c, EA_TRAJ_LIMIT_TENSION_MAX, T, l->tension_max, tt);
  ea__note_abs(c, EA_TRAJ_LIMIT_TORQUE, tau, l->shoulder_torque_max, tt);
  c->min_tension_margin_N = fmin(c->min_tension_margin_N, T - l->tension_min);
  c->peak_shoulder_torque_Nm = fmax(c->peak_shoulder_torque_Nm, fabs(tau));
  c->max_theta0_deviation_rad = fmax(c->max_theta0_deviation_rad, fabs(sol.p[EA_P_THETA0] - q[3]));
}

static void ea__check_init(ea_traj_limits_check_t *c) {
  memset(c, 0, sizeof *c);
  for (int i = 0; i < EA_TRAJ_LIMIT_COUNT; ++i) {
    c->excess[i] = -INFINITY;
    c->value[i] = c->bound[i] = c->time_s[i] = NAN;
  }
  c->first_failure_s = NAN;
  c->min_tension_margin_N = INFINITY;
  c->worst = 0;
}

/* The verdict of a filled check: EA_OK or EA_ERR_INADMISSIBLE naming the worst. */
static ea_status_t ea__check_verdict(ea_traj_limits_check_t *c, double tol, ea_error_t *err) {
  for (int i = 1; i < EA_TRAJ_LIMIT_COUNT; ++i)
    if (c->excess[i] > c->excess[c->worst]) c->worst = i;
  if (c->statics_failures)
    return ea_error_set(err, EA_ERR_INADMISSIBLE,
                        "no static solution with T > 0 at t = %.6g s (%d of %d points): the "
                        "trajectory leaves the workspace",
                        c->first_failure_s, c->statics_failures, c->samples);
  const int w = c->worst;
  if (c->excess[w] > tol) {
    const int range = w == EA_TRAJ_LIMIT_CABLE_LENGTH || w == EA_TRAJ_LIMIT_SHOULDER_ANGLE ||
                      w == EA_TRAJ_LIMIT_BASE_ANGLE;
    const int below = range ? c->value[w] < c->bound[w]
                            : w == EA_TRAJ_LIMIT_TENSION_MIN || w == EA_TRAJ_LIMIT_FIRST_FREQUENCY;
    if (range || below)
      return ea_error_set(err, EA_ERR_INADMISSIBLE,
                          "%s: %.9g %s at t = %.6g s is %s the bound %.9g %s (by %.3g %% of %s)",
                          ea__lim_names[w], c->value[w], ea__lim_units[w], c->time_s[w],
                          below ? "below" : "above", c->bound[w], ea__lim_units[w],
                          100.0 * c->excess[w], range ? "the range" : "the bound");
    return ea_error_set(err, EA_ERR_INADMISSIBLE,
                        "%s: |%.9g| %s at t = %.6g s exceeds the limit %.9g %s by %.3g %%",
                        ea__lim_names[w], c->value[w], ea__lim_units[w], c->time_s[w], c->bound[w],
                        ea__lim_units[w], 100.0 * c->excess[w]);
  }
  return EA_OK;
}

static ea_status_t ea__check_run(const ea_task_t *task, const ea_traj_t *tr, double rate_hz,
                                 ea_traj_limits_check_t *c, ea_error_t *err) {
  ea_shooter_t *sh = NULL;
  ea_status_t st = ea_shooter_alloc(&task->arm, NULL, &sh, err);
  if (st) return st;
  const ea_load_t load = {ea_arm_tip_mass(&task->arm, task->payload_kg)};
  ea_shooter_set_load(sh, &load);
  double p[EA_NP] = {EA_TRAJ_AT(tr, 0, EA_TRAJ_cable_angle), EA_TRAJ_AT(tr, 0, EA_TRAJ_tension),
                     EA_TRAJ_AT(tr, 0, EA_TRAJ_theta0), EA_TRAJ_AT(tr, 0, EA_TRAJ_kappa0)};
  static const int qc[4] = {EA_TRAJ_cable_length, EA_TRAJ_cable_angle, EA_TRAJ_base_angle,
                            EA_TRAJ_theta0};
  static const int vc[4] = {EA_TRAJ_cable_length_rate, EA_TRAJ_cable_angle_rate,
                            EA_TRAJ_base_angle_rate, EA_TRAJ_theta0_rate};
  for (int k = 0; k + 1 < tr->n; ++k) {
    const double h = EA_TRAJ_AT(tr, k + 1, EA_TRAJ_t) - EA_TRAJ_AT(tr, k, EA_TRAJ_t);
    int nsub = (int)ceil(h * rate_hz);
    if (nsub < 4) nsub = 4;
    for (int j = 0; j <= nsub; ++j)
      ea__check_point(task, tr, sh, k, (double)j / nsub, p, c);
    /* the extrema of each coordinate's value and rate inside the interval */
    for (int i = 0; i < 4; ++i) {
      double r[3];
      const int nr =
          ea__herm_extrema(h, EA_TRAJ_AT(tr, k, qc[i]), EA_TRAJ_AT(tr, k, vc[i]),
                           EA_TRAJ_AT(tr, k + 1, qc[i]), EA_TRAJ_AT(tr, k + 1, vc[i]), r);
      double pp[EA_NP];
      for (int e = 0; e < nr; ++e) {
        memcpy(pp, p, sizeof pp);
        ea__check_point(task, tr, sh, k, r[e], pp, c);
      }
    }
  }
  ea_shooter_free(sh);
  return EA_OK;
}

ea_status_t ea_traj_check_limits(const ea_task_t *task, const ea_traj_t *tr, double rate_hz,
                                 double tol, ea_traj_limits_check_t *out, ea_error_t *err) {
  if (!task || !tr || !out)
    return ea_error_set(err, EA_ERR_ARG, "ea_traj_check_limits: NULL argument");
  if (tr->n < 2 || !tr->data)
    return ea_error_set(err, EA_ERR_ARG, "ea_traj_check_limits: %d samples (at least 2)", tr->n);
  if (!(rate_hz > 0.0 && rate_hz <= 1e6) || !(tol >= 0.0))
    return ea_error_set(err, EA_ERR_ARG,
                        "ea_traj_check_limits: rate %g Hz (in (0, 1e6]) or tol %g (>= 0)", rate_hz,
                        tol);
  ea__check_init(out);
  ea_status_t st = ea__check_run(task, tr, rate_hz, out, err);
  if (st) return st;
  return ea__check_verdict(out, tol, err);
}

/* ------------------------------------------------------------------------ */
/* ZV shaping                                                                */
/* ------------------------------------------------------------------------ */

void ea_shape_settings_default(ea_shape_settings_t *s) {
  if (!s) return;
  memset(s, 0, sizeof *s);
  s->damping_ratio = NAN;
  s->elements = EA_FE_DEFAULT_ELEMENTS;
  s->check_rate_hz = 1000.0;
  s->limit_tol = 1e-9;
}

/* The FE first frequency [Hz] at every sample of tr (passive cable, tip held at the
 * sample's (L_c, alpha), the task's tip mass). */
static ea_status_t ea__shape_freqs(const ea_task_t *task, const ea_traj_t *tr, int elements,
                                   double *f, ea_error_t *err) {
  ea_fe_settings_t fs;
  ea_fe_settings_default(&fs);
  fs.static_hold_tip = 1;
  fs.modes = 1;
  fs.elements = elements;
  ea_fe_model_t *m = NULL;
  ea_shooter_t *sh = NULL;
  const ea_load_t load = {ea_arm_tip_mass(&task->arm, task->payload_kg)};
  ea_status_t st = ea_fe_model_alloc(&task->arm, &fs, &m, err);
  if (!st) st = ea_fe_model_set_load(m, &load);
  if (!st) st = ea_shooter_alloc(&task->arm, NULL, &sh, err);
  if (st) {
    ea_fe_model_free(m);
    return st;
  }
  ea_shooter_set_load(sh, &load);
  for (int k = 0; k < tr->n && !st; ++k) {
    const double L = EA_TRAJ_AT(tr, k, EA_TRAJ_cable_length);
    const double al = EA_TRAJ_AT(tr, k, EA_TRAJ_cable_angle);
    const double guess[EA_NP] = {al, EA_TRAJ_AT(tr, k, EA_TRAJ_tension),
                                 EA_TRAJ_AT(tr, k, EA_TRAJ_theta0),
                                 EA_TRAJ_AT(tr, k, EA_TRAJ_kappa0)};
    const ea_statics_problem_t pr = ea_statics_problem_cable(L, al);
    ea_statics_solution_t sol;
    ea_error_t e2 = {0};
    ea_fe_static_info_t fi;
    ea_fe_modes_info_t mi;
    st = ea_statics_solve(sh, &pr, NULL, guess, &sol, &e2);
    if (st) st = ea_statics_solve(sh, &pr, NULL, NULL, &sol, &e2);
    if (!st) st = ea_fe_static_solve(m, sh, &sol, &fi, &e2);
    if (!st) st = ea_fe_modes(m, &mi, &e2);
    if (!st && (!mi.stable || !(mi.freq_hz[0] > 0.0))) {
      st = EA_ERR_UNSTABLE;
      snprintf(e2.msg, sizeof e2.msg, "the FE state is not stable");
    }
    if (st)
      ea_error_set(err, st,
                   "ZV shaping: no FE first frequency at sample %d (t = %.6g s, L_c = %.6g m, "
                   "alpha = %.6g rad): %s",
                   k, EA_TRAJ_AT(tr, k, EA_TRAJ_t), L, al, e2.msg);
    else
      f[k] = mi.freq_hz[0];
  }
  ea_shooter_free(sh);
  ea_fe_model_free(m);
  return st;
}

static int ea__cmp_double(const void *a, const void *b) {
  const double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

/* Largest distance [m] of the samples' tips from the task's line or polyline
 * (3-D, base frame); NAN for a free path. */
static double ea__path_deviation(const ea_task_t *t, const ea_traj_t *tr) {
  if (t->path == EA_TASK_PATH_FREE) return NAN;
  const ea_task_point_t *pts[EA_TASK_MAX_VIA + 2];
  int np = 0;
  pts[np++] = &t->start;
  if (t->path == EA_TASK_PATH_POLYLINE)
    for (int i = 0; i < t->n_via; ++i)
      pts[np++] = &t->via[i];
  pts[np++] = &t->goal;
  double P[EA_TASK_MAX_VIA + 2][3];
  for (int i = 0; i < np; ++i) {
    P[i][0] = pts[i]->reach * cos(pts[i]->base_angle);
    P[i][1] = pts[i]->reach * sin(pts[i]->base_angle);
    P[i][2] = pts[i]->height;
  }
  double worst = 0.0;
  for (int k = 0; k < tr->n; ++k) {
    const double x[3] = {EA_TRAJ_AT(tr, k, EA_TRAJ_tip_x), EA_TRAJ_AT(tr, k, EA_TRAJ_tip_y),
                         EA_TRAJ_AT(tr, k, EA_TRAJ_tip_z)};
    double best = INFINITY;
    for (int i = 0; i + 1 < np; ++i) {
      double d[3], w[3], dd = 0.0, dw = 0.0;
      for (int c = 0; c < 3; ++c) {
        d[c] = P[i + 1][c] - P[i][c];
        w[c] = x[c] - P[i][c];
        dd += d[c] * d[c];
        dw += d[c] * w[c];
      }
      const double u = dd > 0.0 ? fmin(1.0, fmax(0.0, dw / dd)) : 0.0;
      double r2 = 0.0;
      for (int c = 0; c < 3; ++c)
        r2 += (w[c] - u * d[c]) * (w[c] - u * d[c]);
      best = fmin(best, sqrt(r2));
    }
    worst = fmax(worst, best);
  }
  return worst;
}

static const int ea__qc[3] = {EA_TRAJ_cable_length, EA_TRAJ_cable_angle, EA_TRAJ_base_angle};
static const int ea__vc[3] = {EA_TRAJ_cable_length_rate, EA_TRAJ_cable_angle_rate,
                              EA_TRAJ_base_angle_rate};
static const int ea__ac[3] = {EA_TRAJ_cable_length_acc, EA_TRAJ_cable_angle_acc,
                              EA_TRAJ_base_angle_acc};

/* Value, rate and acceleration at u of A1 q + A2 D; the acceleration is that of the interval
 * on side (-1 before u, +1 after it; 0: the mean of both, as the planner writes a jump). */
static void ea__shaped_at(const ea__pw_t *in, const ea__pw_t *echo, double A1, double A2, double u,
                          int side, double out[3]) {
  double q1, v1, a1, q2, v2, a2, qm, vm, am, qe, ve, ae;
  ea__pw_eval(in, u, -1, &qm, &vm, &am);
  ea__pw_eval(in, u, +1, &q1, &v1, &a1);
  ea__pw_eval(echo, u, -1, &qe, &ve, &ae);
  ea__pw_eval(echo, u, +1, &q2, &v2, &a2);
  out[0] = A1 * q1 + A2 * q2;
  out[1] = A1 * v1 + A2 * v2;
  const double after = A1 * a1 + A2 * a2, before = A1 * am + A2 * ae;
  out[2] = side > 0 ? after : side < 0 ? before : 0.5 * (after + before);
  (void)qm, (void)vm, (void)qe, (void)ve;
}

/* Scratch of the shaper. */
typedef struct {
  double *tin, *f, *tau, *m; /* n_in each */
  double *yin[3], *vin[3];   /* input values and rates, n_in each */
  double *vecho[3];          /* echo spline rates, n_in each */
  double *u;                 /* output times, up to 2 n_in */
  double *th, *thv, *w;      /* theta0 values, rates, spline scratch (2 x 2 n_in) */
  double *block;
} ea__shape_ws_t;

static ea_status_t ea__shape_ws_alloc(ea__shape_ws_t *w, int n, ea_error_t *err) {
  memset(w, 0, sizeof *w);
  const size_t nn = (size_t)n, total = 13 * nn + 2 * nn + 2 * nn + 2 * nn + 4 * nn;
  w->block = calloc(total, sizeof *w->block);
  if (!w->block)
    return ea_error_set(err, EA_ERR_NOMEM, "ZV shaping: out of memory (%d samples)", n);
  double *b = w->block;
  w->tin = b, b += nn;
  w->f = b, b += nn;
  w->tau = b, b += nn;
  w->m = b, b += nn;
  for (int c = 0; c < 3; ++c) {
    w->yin[c] = b, b += nn;
    w->vin[c] = b, b += nn;
    w->vecho[c] = b, b += nn;
  }
  w->u = b, b += 2 * nn;
  w->th = b, b += 2 * nn;
  w->thv = b, b += 2 * nn;
  w->w = b;
  return EA_OK;
}

/* Statics columns of every output row (warm-started along the rows), theta0's rates
 * from the C2 spline through its values with rest at both ends. */
static ea_status_t ea__shape_statics(const ea_task_t *task, ea_traj_t *out, const ea_traj_t *in,
                                     ea__shape_ws_t *w, ea_error_t *err) {
  ea_shooter_t *sh = NULL;
  ea_status_t st = ea_shooter_alloc(&task->arm, NULL, &sh, err);
  if (st) return st;
  const ea_load_t load = {ea_arm_tip_mass(&task->arm, task->payload_kg)};
  ea_shooter_set_load(sh, &load);
  ea_statics_settings_t set;
  ea_statics_settings_default(&set);
  set.tol = 1e-12;
  double p[EA_NP] = {EA_TRAJ_AT(in, 0, EA_TRAJ_cable_angle), EA_TRAJ_AT(in, 0, EA_TRAJ_tension),
                     EA_TRAJ_AT(in, 0, EA_TRAJ_theta0), EA_TRAJ_AT(in, 0, EA_TRAJ_kappa0)};
  for (int k = 0; k < out->n && !st; ++k) {
    const double L = EA_TRAJ_AT(out, k, EA_TRAJ_cable_length);
    const double al = EA_TRAJ_AT(out, k, EA_TRAJ_cable_angle);
    const ea_statics_problem_t pr = ea_statics_problem_cable(L, al);
    ea_statics_solution_t sol;
    p[0] = al;
    st = ea_statics_solve(sh, &pr, &set, p, &sol, NULL);
    if (st) st = ea_statics_solve(sh, &pr, &set, NULL, &sol, NULL);
    if (st) {
      st = ea_error_set(err, EA_ERR_INADMISSIBLE,
                        "ZV shaping: the shaped command leaves the workspace: no static "
                        "solution with T > 0 at t = %.6g s (L_c = %.6g m, alpha = %.6g rad)",
                        EA_TRAJ_AT(out, k, EA_TRAJ_t), L, al);
      break;
    }
    memcpy(p, sol.p, sizeof p);
    ea_traj_set_statics(out, k, sol.p, sol.tip, task->arm.EI);
    w->th[k] = sol.p[EA_P_THETA0];
  }
  ea_shooter_free(sh);
  if (st) return st;
  ea__spline_rates(out->n, w->u, w->th, 0.0, 0.0, w->thv, w->w);
  for (int k = 0; k < out->n; ++k)
    EA_TRAJ_AT(out, k, EA_TRAJ_theta0_rate) = w->thv[k];
  return EA_OK;
}

/* The output times: the t_k and the m_k, sorted; an m_k closer than merge to some t_j is
 * left out (the t_j stands for both: a breakpoint of the echo that close cannot be kept
 * without the file's cubic on the tiny interval between them amplifying the rounding of
 * the stored values, 6 eps |q| / h^2 in the acceleration). Returns their count. */
static int ea__shape_times(ea__shape_ws_t *w, int n, double merge, ea_shape_info_t *info) {
  int nu = 0;
  memcpy(w->u, w->tin, (size_t)n * sizeof *w->u);
  nu = n;
  for (int k = 0; k < n; ++k) {
    /* nearest t_j (tin is increasing) */
    int lo = 0, hi = n - 1;
    while (hi - lo > 1) {
      const int mid = (lo + hi) / 2;
      if (w->tin[mid] <= w->m[k])
        lo = mid;
      else
        hi = mid;
    }
    const double d = fmin(fabs(w->tin[lo] - w->m[k]), fabs(w->tin[hi] - w->m[k]));
    if (d < merge) {
      ++info->echo_samples_merged;
      info->max_merge_s = fmax(info->max_merge_s, d);
      continue;
    }
    w->u[nu++] = w->m[k];
  }
  qsort(w->u, (size_t)nu, sizeof *w->u, ea__cmp_double);
  return nu;
}

/* Check the input: at rest at both ends, the task's payload. */
static ea_status_t ea__shape_check_input(const ea_task_t *task, const ea_traj_t *in,
                                         ea_error_t *err) {
  if (in->n < 2 || !in->data)
    return ea_error_set(err, EA_ERR_ARG, "ZV shaping: the trajectory has %d samples (at least 2)",
                        in->n);
  for (int c = 0; c < 3; ++c)
    for (int e = 0; e < 2; ++e) {
      const int k = e ? in->n - 1 : 0;
      if (EA_TRAJ_AT(in, k, ea__vc[c]) != 0.0)
        return ea_error_set(err, EA_ERR_ARG,
                            "ZV shaping: the trajectory is not at rest at its %s (%s = %g): "
                            "only rest-to-rest motions are shaped",
                            e ? "end" : "start", ea_traj_column_name(ea__vc[c]),
                            EA_TRAJ_AT(in, k, ea__vc[c]));
    }
  if (fabs(in->payload_kg - task->payload_kg) > 1e-12 * fmax(1.0, task->payload_kg))
    return ea_error_set(err, EA_ERR_ARG,
                        "ZV shaping: the trajectory's payload %.9g kg is not the task's %.9g kg",
                        in->payload_kg, task->payload_kg);
  return EA_OK;
}

/* The shaper's damping ratio: the setting, else the arm's zeta_1, else 0. */
static ea_status_t ea__shape_zeta(const ea_task_t *task, const ea_shape_settings_t *s, double *z,
                                  ea_error_t *err) {
  *z = s->damping_ratio;
  if (isnan(*z)) *z = task->arm.n_damping > 0 ? task->arm.damping_ratio[0] : 0.0;
  if (!(*z >= 0.0 && *z < 1.0))
    return ea_error_set(err, EA_ERR_ARG, "ZV shaping: damping ratio %g: must be in [0, 1)", *z);
  if (s->elements < 1 || s->elements > 512)
    return ea_error_set(err, EA_ERR_ARG, "ZV shaping: elements = %d: must be in [1, 512]",
                        s->elements);
  if (!(s->check_rate_hz > 0.0 && s->check_rate_hz <= 1e6) || !(s->limit_tol >= 0.0))
    return ea_error_set(err, EA_ERR_ARG,
                        "ZV shaping: check rate %g Hz (in (0, 1e6]) or limit tolerance %g (>= 0)",
                        s->check_rate_hz, s->limit_tol);
  return EA_OK;
}

/* The frequency limits of the task at the output's samples. */
static ea_status_t ea__shape_freq_limits(const ea_task_t *task, const ea_traj_t *out,
                                         const ea_shape_settings_t *s, ea_traj_limits_check_t *c,
                                         ea_error_t *err) {
  const ea_task_limits_t *l = &task->limits;
  const int fmin_on = l->min_first_frequency_hz > 0.0,
            defl_on = isfinite(l->max_modal_deflection_m);
  if (!fmin_on && !defl_on) return EA_OK;
  double *f = calloc((size_t)out->n, sizeof *f);
  if (!f) return ea_error_set(err, EA_ERR_NOMEM, "ZV shaping: out of memory");
  ea_status_t st = ea__shape_freqs(task, out, s->elements, f, err);
  for (int k = 0; k < out->n && !st; ++k) {
    const double t = EA_TRAJ_AT(out, k, EA_TRAJ_t);
    if (fmin_on)
      ea__note(c, EA_TRAJ_LIMIT_FIRST_FREQUENCY,
               (l->min_first_frequency_hz - f[k]) / l->min_first_frequency_hz, f[k],
               l->min_first_frequency_hz, t);
    if (defl_on) {
      const double w2 = pow(2.0 * M_PI * f[k], 2);
      const double dL = EA_TRAJ_AT(out, k, EA_TRAJ_cable_length_acc) / w2;
      const double da = EA_TRAJ_AT(out, k, EA_TRAJ_cable_length) *
                        EA_TRAJ_AT(out, k, EA_TRAJ_cable_angle_acc) / w2;
      ea__note_abs(c, EA_TRAJ_LIMIT_MODAL_DEFLECTION, fabs(dL) > fabs(da) ? dL : da,
                   l->max_modal_deflection_m, t);
    }
  }
  free(f);
  return st;
}

/* Fill the output rows: times, the shaped L_c, alpha and base, the metadata. */
static ea_status_t ea__shape_rows(const ea_traj_t *in, ea__shape_ws_t *w, int nu, double A1,
                                  double A2, ea_traj_t *out, ea_error_t *err) {
  const int n = in->n;
  ea_status_t st = ea_traj_alloc(out, nu);
  if (st) return ea_error_set(err, st, "ZV shaping: out of memory (%d samples)", nu);
  out->payload_kg = in->payload_kg;
  out->tip_mass_kg = in->tip_mass_kg;
  snprintf(out->arm_file, sizeof out->arm_file, "%s", in->arm_file);
  out->arm_hash = in->arm_hash;
  out->has_arm_hash = in->has_arm_hash;
  snprintf(out->task, sizeof out->task, "%s", in->task);
  snprintf(out->status, sizeof out->status, "%s", in->status);
  for (int c = 0; c < 3; ++c) {
    const ea__pw_t pin = {n, w->tin, w->yin[c], w->vin[c]};
    ea__spline_rates(n, w->m, w->yin[c], 0.0, 0.0, w->vecho[c], w->w);
    const ea__pw_t pecho = {n, w->m, w->yin[c], w->vecho[c]};
    for (int k = 0; k < nu; ++k) {
      double r[3];
      ea__shaped_at(&pin, &pecho, A1, A2, w->u[k], k == 0 ? 1 : k == nu - 1 ? -1 : 0, r);
      EA_TRAJ_AT(out, k, ea__qc[c]) = r[0];
      EA_TRAJ_AT(out, k, ea__vc[c]) = r[1];
      EA_TRAJ_AT(out, k, ea__ac[c]) = r[2];
    }
  }
  for (int k = 0; k < nu; ++k)
    EA_TRAJ_AT(out, k, EA_TRAJ_t) = w->u[k];
  return EA_OK;
}

ea_status_t ea_traj_shape_zv(const ea_task_t *task, const ea_traj_t *in,
                             const ea_shape_settings_t *s, ea_traj_t *out, ea_shape_info_t *info,
                             ea_error_t *err_out) {
  ea_error_t e = {0}, *err = &e;
  ea_shape_info_t local;
  if (!info) info = &local;
  memset(info, 0, sizeof *info);
  ea__check_init(&info->check);
  info->max_path_deviation_m = NAN;
  const double t_start = ea__mono_s();
  if (!task || !in || !out)
    return info->status = ea_error_set(err_out, EA_ERR_ARG, "ea_traj_shape_zv: NULL argument");
  ea_shape_settings_t def;
  if (!s) {
    ea_shape_settings_default(&def);
    s = &def;
  }
  double zeta = 0.0;
  ea_status_t st = ea__shape_zeta(task, s, &zeta, err);
  if (!st) st = ea__shape_check_input(task, in, err);
  if (st) {
    snprintf(info->message, sizeof info->message, "%s", e.msg);
    return info->status = ea_error_set(err_out, st, "%s", e.msg);
  }
  const int n = in->n;
  ea__shape_ws_t w;
  if ((st = ea__shape_ws_alloc(&w, n, err))) {
    snprintf(info->message, sizeof info->message, "%s", e.msg);
    return info->status = ea_error_set(err_out, st, "%s", e.msg);
  }
  const double K = exp(-zeta * M_PI / sqrt(1.0 - zeta * zeta));
  const double A1 = 1.0 / (1.0 + K), A2 = K / (1.0 + K);
  info->damping_ratio = zeta;
  info->amplitude[0] = A1;
  info->amplitude[1] = A2;
  info->samples_in = n;
  for (int k = 0; k < n; ++k) {
    w.tin[k] = EA_TRAJ_AT(in, k, EA_TRAJ_t);
    for (int c = 0; c < 3; ++c) {
      w.yin[c][k] = EA_TRAJ_AT(in, k, ea__qc[c]);
      w.vin[c][k] = EA_TRAJ_AT(in, k, ea__vc[c]);
    }
  }
  info->duration_in_s = w.tin[n - 1] - w.tin[0];
  st = ea__shape_freqs(task, in, s->elements, w.f, err);
  double hmin = INFINITY;
  if (!st) {
    info->f1_min_hz = INFINITY, info->f1_max_hz = -INFINITY;
    info->delay_min_s = INFINITY, info->delay_max_s = -INFINITY;
    for (int k = 0; k < n; ++k) {
      w.tau[k] = 1.0 / (2.0 * w.f[k] * sqrt(1.0 - zeta * zeta));
      w.m[k] = w.tin[k] + w.tau[k];
      info->f1_min_hz = fmin(info->f1_min_hz, w.f[k]);
      info->f1_max_hz = fmax(info->f1_max_hz, w.f[k]);
      info->delay_min_s = fmin(info->delay_min_s, w.tau[k]);
      info->delay_max_s = fmax(info->delay_max_s, w.tau[k]);
      if (k) hmin = fmin(hmin, w.tin[k] - w.tin[k - 1]);
    }
    info->f1_start_hz = w.f[0], info->f1_goal_hz = w.f[n - 1];
    info->delay_start_s = w.tau[0], info->delay_goal_s = w.tau[n - 1];
    /* the echo times must keep the samples' order, with room to spare */
    for (int k = 1; k < n && !st; ++k)
      if (!(w.m[k] - w.m[k - 1] > 0.5 * (w.tin[k] - w.tin[k - 1])))
        st = ea_error_set(err, EA_ERR_INADMISSIBLE,
                          "ZV shaping: the half period falls by %.6g s between t = %.6g s and "
                          "%.6g s, more than half the interval: the first frequency changes too "
                          "fast along the motion for a ZV shaper",
                          w.tau[k - 1] - w.tau[k], w.tin[k - 1], w.tin[k]);
  }
  int nu = 0;
  if (!st) {
    nu = ea__shape_times(&w, n, 1e-3 * hmin, info);
    st = ea__shape_rows(in, &w, nu, A1, A2, out, err);
  }
  if (!st) st = ea__shape_statics(task, out, in, &w, err);
  if (!st) {
    info->samples = out->n;
    info->duration_s = EA_TRAJ_AT(out, out->n - 1, EA_TRAJ_t) - EA_TRAJ_AT(out, 0, EA_TRAJ_t);
    info->max_path_deviation_m = ea__path_deviation(task, out);
    st = ea__check_run(task, out, s->check_rate_hz, &info->check, err);
    if (!st) st = ea__shape_freq_limits(task, out, s, &info->check, err);
    if (!st) {
      st = ea__check_verdict(&info->check, s->limit_tol, err);
      if (st) {
        char why[sizeof e.msg];
        snprintf(why, sizeof why, "%s", e.msg);
        double drop = 0.0; /* the largest fall of the half period between two samples */
        for (int k = 1; k < n; ++k)
          drop = fmax(drop, w.tau[k - 1] - w.tau[k]);
        ea_error_set(err, st, "ZV shaping: the shaped trajectory breaks a limit: %.300s%s", why,
                     drop > 1e-6 ? " (the half period shrinks along this motion, which speeds "
                                   "the echo up)"
                                 : "");
      }
    }
  }
  free(w.block);
  info->time_s = ea__mono_s() - t_start;
  info->status = st;
  if (st) {
    ea_traj_free(out);
    snprintf(info->message, sizeof info->message, "%s", e.msg);
    return ea_error_set(err_out, st, "%s", e.msg);
  }
  snprintf(info->message, sizeof info->message,
           "ZV-shaped: duration %.6g s (input %.6g s + %.6g s), half period %.4g s at the start, "
           "%.4g s at the goal",
           info->duration_s, info->duration_in_s, info->duration_s - info->duration_in_s,
           info->delay_start_s, info->delay_goal_s);
  return EA_OK;
}
