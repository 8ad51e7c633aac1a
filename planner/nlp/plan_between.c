/* Limits between the knots that no row holds exactly (docs/planner.md,
 * "Limits between the knots"). The rows hold the accelerations (linear on
 * each interval: both ends) and the speeds (Bernstein hull of the quadratic
 * rate) of every cubic Hermite exactly. What is left:
 *  - the ranges of L_c, base and theta0: exact extrema of each interval's
 *    cubic (roots of its quadratic rate);
 *  - tension and shoulder torque: the quasi-static values at the
 *    interpolated (L_c, alpha), screened by the cubic Hermite of each
 *    knot's value and rate (implicit differentiation of the statics, from
 *    the cached sensitivities) and, where that comes within a band of a
 *    limit, sampled by Newton solves at 16 points of the interval (with a
 *    parabola through the largest sample and its neighbours);
 *  - the frequency model's limits (f1 >= min, modal deflection), sampled on
 *    every interval.
 * A limit exceeded between knots k and k+1 tightens the bound (or row) at
 * those of the two knots that are not pinned by 1.5 x the excess; the
 * caller re-solves. */
#include "plan_impl.h"
#include "knot_impl.h"
#include "path_entry_impl.h"
#include "vib_impl.h"

#include <math.h>
#include <string.h>

#define EA__BW_SAMPLES 16

/* Cubic Hermite on [0, h]: value at s in [0, 1]. */
static double ea__cubic_at(double h, double q0, double v0, double q1, double v1, double s) {
  const double d = q1 - q0, c2 = 3.0 * d - h * (2.0 * v0 + v1), c3 = -2.0 * d + h * (v0 + v1);
  return q0 + s * (h * v0 + s * (c2 + s * c3));
}

/* Smallest and largest value of the cubic Hermite inside the interval (at
 * the roots of its rate in (0, 1)); +-INFINITY when it has none there (the
 * ends are knots, held by the bounds). */
static void ea__cubic_extrema(double h, double q0, double v0, double q1, double v1, double *lo,
                              double *hi) {
  const double d = q1 - q0, c2 = 3.0 * d - h * (2.0 * v0 + v1), c3 = -2.0 * d + h * (v0 + v1);
  *lo = INFINITY;
  *hi = -INFINITY;
  /* q'(s) = h v0 + 2 c2 s + 3 c3 s^2 */
  const double A = 3.0 * c3, B = 2.0 * c2, C = h * v0;
  double r[2];
  int nr = 0;
  if (fabs(A) < 1e-300) {
    if (fabs(B) > 0.0) r[nr++] = -C / B;
  } else {
    const double disc = B * B - 4.0 * A * C;
    if (disc >= 0.0) {
      const double sq = sqrt(disc), qq = -0.5 * (B + (B >= 0.0 ? sq : -sq));
      if (qq != 0.0) r[nr++] = C / qq;
      r[nr++] = qq / A;
    }
  }
  for (int i = 0; i < nr; ++i)
    if (r[i] > 0.0 && r[i] < 1.0) {
      const double v = ea__cubic_at(h, q0, v0, q1, v1, r[i]);
      *lo = fmin(*lo, v);
      *hi = fmax(*hi, v);
    }
}

/* Largest value of samples y[0..n] at equal spacing inside the interval,
 * refined by the parabola through the largest sample and its neighbours;
 * -INFINITY when the largest is an end (a knot, held by the bounds). */
static double ea__sample_max(const double *y, int n) {
  int im = 0;
  for (int i = 1; i <= n; ++i)
    if (y[i] > y[im]) im = i;
  if (im == 0 || im == n) return -INFINITY;
  const double a = y[im - 1], b = y[im], c = y[im + 1], den = a - 2.0 * b + c;
  if (!(den < 0.0)) return b;
  const double u = 0.5 * (a - c) / den; /* vertex offset in [-0.5, 0.5] */
  return fmax(b, b - 0.25 * (a - c) * u);
}

/* Rates of (T, theta0, kappa0) at knot k along (dL_c/dt, dalpha/dt): the
 * statics residual's implicit derivative, from the cached sensitivities. */
static void ea__statics_rates(const ea_planner_t *pl, const double *x, int k, double pd[3]) {
  if (pl->pp) { /* the path transcription: the splines' partials (no sensitivities shot) */
    if (ea__pp_statics_rates(pl, x, k, pd)) pd[0] = pd[1] = pd[2] = 0.0;
    return;
  }
  if (ea__plan_statics_slope(pl->S + 16 * k, x[EA__IQ(pl, k, 0)], x[EA__IQ(pl, k, 1)],
                             x[EA__IV(pl, k, 0)], x[EA__IV(pl, k, 1)], pd))
    pd[0] = pd[1] = pd[2] = 0.0;
}

typedef struct {
  double worst; /* largest relative excess found */
  char *msg;
  size_t len;
  int tightened;
} ea__bw_t;

static void ea__bw_note(ea__bw_t *b, double rel, const char *what, int k, double by) {
  if (rel <= b->worst) return;
  b->worst = rel;
  snprintf(b->msg, b->len, "%s exceeded between knots %d and %d by %.3g", what, k, k + 1, by);
}

/* Tighten a variable bound at knot k (not pinned) by amount: side +1 upper,
 * -1 lower. */
static void ea__tighten_var(ea_planner_t *pl, ea__bw_t *b, int var, int side, double amount) {
  if (pl->xl[var] == pl->xu[var]) return;
  if (side > 0)
    pl->xu[var] = fmax(pl->xl[var], pl->xu[var] - amount);
  else
    pl->xl[var] = fmin(pl->xu[var], pl->xl[var] + amount);
  b->tightened++;
}

static int ea__pinned(const ea_planner_t *pl, int k) {
  return pl->xl[EA__IQ(pl, k, 0)] == pl->xu[EA__IQ(pl, k, 0)];
}

/* Row index of (kind, knot, coord) or -1. */
static int ea__find_row(const ea_planner_t *pl, int kind, int knot, int coord) {
  for (int i = 3 * pl->N; i < pl->m; ++i)
    if (pl->rows[i].kind == kind && pl->rows[i].knot == knot && pl->rows[i].coord == coord)
      return i;
  return -1;
}

/* A limit [lo, hi] on a quantity whose extremes inside interval k are [vlo,
 * vhi]: note an excess and tighten variable var0 (knot k) and var1 (knot
 * k + 1), those not pinned, by 1.5 x the excess. */
static void ea__bw_range(ea_planner_t *pl, ea__bw_t *b, int k, double vlo, double vhi, double lo,
                         double hi, double scale, const char *what, int var0, int var1) {
  for (int side = -1; side <= 1; side += 2) {
    const double e = side > 0 ? vhi - hi : lo - vlo;
    if (!(e > 0.0)) continue;
    const double amount = 1.5 * e + 1e-9 * scale;
    ea__bw_note(b, e / scale, what, k, e);
    if (var0 >= 0 && !ea__pinned(pl, k)) ea__tighten_var(pl, b, var0, side, amount);
    if (var1 >= 0 && !ea__pinned(pl, k + 1)) ea__tighten_var(pl, b, var1, side, amount);
  }
}

/* Ranges of the cubics: cable length, base angle and shoulder angle between the knots. */
static void ea__bw_cubics(ea_planner_t *pl, const double *x, double tf, ea__bw_t *b) {
  const ea_task_limits_t *l = &pl->task.limits;
  const ea_actuators_t *act = &pl->task.arm.act;
  const double qlo[3] = {l->cable_length_min, -INFINITY, act->base_angle_min};
  const double qhi[3] = {l->cable_length_max, INFINITY, act->base_angle_max};
  static const char *const qname[3] = {"cable length range", "", "base angle range"};
  for (int k = 0; k + 1 < pl->N; ++k) {
    const double h = tf * (pl->s[k + 1] - pl->s[k]);
    for (int c = 0; c <= EA__C_TH; ++c) {
      if (c == 1 || (c < EA__C_TH && c >= pl->nq)) continue;
      double vlo, vhi;
      ea__cubic_extrema(h, x[EA__IQC(pl, k, c)], x[EA__IVC(pl, k, c)], x[EA__IQC(pl, k + 1, c)],
                        x[EA__IVC(pl, k + 1, c)], &vlo, &vhi);
      const double lo = c == EA__C_TH ? act->shoulder_angle_min : qlo[c];
      const double hi = c == EA__C_TH ? act->shoulder_angle_max : qhi[c];
      ea__bw_range(pl, b, k, vlo, vhi, lo, hi, hi - lo,
                   c == EA__C_TH ? "shoulder angle range" : qname[c], EA__IQC(pl, k, c),
                   EA__IQC(pl, k + 1, c));
    }
  }
}

/* Quasi-static T and kappa0 at EA__BW_SAMPLES + 1 points of interval k of the interpolated
 * (L_c, alpha), in y[T, kappa0][max, -min][sample]; 0 when a statics solve failed. */
static int ea__bw_statics_samples(ea_planner_t *pl, const double *x, int k, double h,
                                  const ea_statics_settings_t *set,
                                  double y[2][2][EA__BW_SAMPLES + 1]) {
  double p[EA_NP] = {x[EA__IQ(pl, k, 1)], x[EA__IP(pl, k, 0)], x[EA__IP(pl, k, 1)],
                     x[EA__IP(pl, k, 2)]};
  for (int j = 0; j <= EA__BW_SAMPLES; ++j) {
    const double s = (double)j / EA__BW_SAMPLES;
    double v[2];
    if (j == 0 || j == EA__BW_SAMPLES) {
      const int kk = j ? k + 1 : k;
      v[0] = x[EA__IP(pl, kk, 0)];
      v[1] = x[EA__IP(pl, kk, 2)];
    } else {
      const double Lc = ea__cubic_at(h, x[EA__IQ(pl, k, 0)], x[EA__IV(pl, k, 0)],
                                     x[EA__IQ(pl, k + 1, 0)], x[EA__IV(pl, k + 1, 0)], s);
      const double al = ea__cubic_at(h, x[EA__IQ(pl, k, 1)], x[EA__IV(pl, k, 1)],
                                     x[EA__IQ(pl, k + 1, 1)], x[EA__IV(pl, k + 1, 1)], s);
      ea_statics_problem_t prob = ea_statics_problem_cable(Lc, al);
      ea_statics_solution_t sol;
      p[0] = al;
      if (ea_statics_solve(pl->sh, &prob, set, p, &sol, NULL) != EA_OK) return 0;
      memcpy(p, sol.p, sizeof p);
      v[0] = sol.p[EA_P_TENSION];
      v[1] = sol.p[EA_P_KAPPA0];
    }
    for (int i = 0; i < 2; ++i) {
      y[i][0][j] = v[i];
      y[i][1][j] = -v[i];
    }
  }
  return 1;
}

/* Tension and torque: quasi-static at the interpolated (L_c, alpha), sampled where the
 * cubic estimate from the knots' statics rates comes near a limit. */
static void ea__bw_statics(ea_planner_t *pl, const double *x, double tf, ea__bw_t *b) {
  const ea_task_t *t = &pl->task;
  const ea_task_limits_t *l = &t->limits;
  if (ea__plan_shoot_all(pl, x, pl->pp == NULL) != EA_OK) {
    ea__bw_note(b, INFINITY, "static equilibrium (shooting failed)", 0, NAN);
    return;
  }
  const double km = l->shoulder_torque_max / t->arm.EI;
  const double plo[2] = {l->tension_min, -km}, phi[2] = {l->tension_max, km};
  const double pscale[2] = {l->tension_max, km};
  static const char *const pname[2] = {"tension limit", "shoulder torque limit"};
  const int pj[2] = {0, 2}; /* T, kappa0 */
  double pd0[3], pd1[3];
  ea__statics_rates(pl, x, 0, pd1);
  ea_statics_settings_t set;
  ea_statics_settings_default(&set);
  set.allow_negative_tension = 1;
  set.max_cont_steps = 0;
  for (int k = 0; k + 1 < pl->N; ++k) {
    memcpy(pd0, pd1, sizeof pd0);
    ea__statics_rates(pl, x, k + 1, pd1);
    const double h = tf * (pl->s[k + 1] - pl->s[k]);
    int sample = 0;
    for (int i = 0; i < 2; ++i) {
      const double p0 = x[EA__IP(pl, k, pj[i])], p1 = x[EA__IP(pl, k + 1, pj[i])];
      double vlo, vhi;
      ea__cubic_extrema(h, p0, pd0[pj[i]], p1, pd1[pj[i]], &vlo, &vhi);
      vlo = fmin(vlo, fmin(p0, p1));
      vhi = fmax(vhi, fmax(p0, p1));
      /* screening band: 1e-3 of the limit plus the estimate's own bulge */
      const double band = 1e-3 * pscale[i] + fmax(vhi - fmax(p0, p1), fmin(p0, p1) - vlo);
      if (vhi > phi[i] - band || vlo < plo[i] + band) sample = 1;
    }
    if (!sample) continue;
    double y[2][2][EA__BW_SAMPLES + 1]; /* [T, kappa0][max, -min][sample] */
    if (!ea__bw_statics_samples(pl, x, k, h, &set, y)) {
      ea__bw_note(b, INFINITY, "static equilibrium (no solution)", k, NAN);
      continue;
    }
    for (int i = 0; i < 2; ++i) {
      const double vhi = ea__sample_max(y[i][0], EA__BW_SAMPLES);
      const double vlo = -ea__sample_max(y[i][1], EA__BW_SAMPLES);
      ea__bw_range(pl, b, k, vlo, vhi, plo[i], phi[i], pscale[i], pname[i], EA__IP(pl, k, pj[i]),
                   EA__IP(pl, k + 1, pj[i]));
    }
  }
}

/* Frequency-model limits (first frequency, modal deflection) between the knots: their rows
 * at the knots tightened by 1.5 x the excess. */
static void ea__bw_freq(ea_planner_t *pl, const double *x, double tf, ea__bw_t *b) {
  const ea_task_limits_t *l = &pl->task.limits;
  const double fmin_ = l->min_first_frequency_hz, dmax = l->max_modal_deflection_m;
  if (!pl->fm || !(fmin_ > 0.0 || isfinite(dmax))) return;
  for (int k = 0; k + 1 < pl->N; ++k) {
    const double h = tf * (pl->s[k + 1] - pl->s[k]);
    double yf[EA__BW_SAMPLES + 1], yd[2][2][EA__BW_SAMPLES + 1];
    for (int j = 0; j <= EA__BW_SAMPLES; ++j) {
      const double s = (double)j / EA__BW_SAMPLES;
      double q[2], a[2];
      for (int c = 0; c < 2; ++c) {
        const double q0 = x[EA__IQ(pl, k, c)], q1 = x[EA__IQ(pl, k + 1, c)];
        const double v0 = x[EA__IV(pl, k, c)], v1 = x[EA__IV(pl, k + 1, c)];
        double ae[2];
        ea__plan_hermite_acc(q0, q1, v0, v1, h, ae, NULL);
        q[c] = ea__cubic_at(h, q0, v0, q1, v1, s);
        a[c] = (1.0 - s) * ae[0] + s * ae[1];
      }
      const double f = ea__plan_freq(pl, q[0], q[1], NULL);
      yf[j] = -f;
      for (int c = 0; c < 2; ++c) {
        const double d = (c == 0 ? 1.0 : q[0]) * a[c] / (4.0 * M_PI * M_PI * f * f);
        yd[c][0][j] = d;
        yd[c][1][j] = -d;
      }
    }
    if (fmin_ > 0.0) {
      const double e = fmin_ - (-ea__sample_max(yf, EA__BW_SAMPLES));
      if (e > 0.0) {
        ea__bw_note(b, e / fmin_, "first natural frequency limit", k, e);
        for (int kk = k; kk <= k + 1; ++kk) {
          const int r = ea__find_row(pl, EA__ROW_FREQ_MIN, kk, 0);
          if (r >= 0 && !ea__pinned(pl, kk)) {
            pl->gl[r] += 1.5 * fmax(e, 0.0) + 2e-9 * fmin_;
            b->tightened++;
          }
        }
      }
    }
    if (!isfinite(dmax)) continue;
    for (int c = 0; c < 2; ++c) {
      const double dm =
          fmax(ea__sample_max(yd[c][0], EA__BW_SAMPLES), ea__sample_max(yd[c][1], EA__BW_SAMPLES));
      const double e = dm - dmax;
      if (!(e > 0.0)) continue;
      ea__bw_note(b, e / dmax, "modal deflection limit", k, e);
      const int kinds[2] = {EA__ROW_DEFL_START, EA__ROW_DEFL_END};
      for (int i = 0; i < 2; ++i) {
        const int r = ea__find_row(pl, kinds[i], k, c);
        if (r < 0) continue;
        const double amount = 1.5 * fmax(e, 0.0) + 2e-9 * dmax;
        pl->gu[r] = fmax(0.0, pl->gu[r] - amount);
        pl->gl[r] = fmin(0.0, pl->gl[r] + amount);
        b->tightened++;
      }
    }
  }
}

int ea__plan_between(ea_planner_t *pl, const double *x, double *worst, char *msg, size_t len) {
  const double tf = ea__plan_tf(pl, x);
  ea__bw_t b = {-INFINITY, msg, len, 0};
  if (msg && len) msg[0] = '\0';
  ea__bw_cubics(pl, x, tf, &b);
  ea__bw_statics(pl, x, tf, &b);
  pl->cache_val = pl->cache_sens = 0;
  ea__bw_freq(pl, x, tf, &b);
  if (worst) *worst = b.worst;
  return b.tightened;
}
