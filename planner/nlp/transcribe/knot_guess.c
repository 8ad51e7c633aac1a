/* Layout of the knots (via knots, path segments, time schedule) and the
 * initial guess: the straight interpolation of the tip between the points,
 * each knot's statics solved by continuation from the previous knot
 * (ea_statics_solve with a warm start), so Ipopt starts feasible or nearly
 * so; or a previous plan resampled onto the knots (replanning). */
#include "plan_impl.h"
#include "guess_impl.h"
#include "vib_impl.h"

#include <math.h>
#include <string.h>

void ea__plan_knot_times(ea_planner_t *pl) {
  const int N = pl->N;
  for (int k = 0; k < N; ++k)
    pl->s[k] = (double)k / (N - 1);
  pl->s[0] = 0.0;
  pl->s[N - 1] = 1.0;
}

static const ea_task_point_t *ea__point(const ea_task_t *t, int j) {
  if (j == 0) return &t->start;
  if (j <= t->n_via) return &t->via[j - 1];
  return &t->goal;
}

static void ea__unit(double v[3]) {
  const double n = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  if (n > 0) v[0] /= n, v[1] /= n, v[2] /= n;
}
static void ea__cross(const double a[3], const double b[3], double c[3]) {
  c[0] = a[1] * b[2] - a[2] * b[1];
  c[1] = a[2] * b[0] - a[0] * b[2];
  c[2] = a[0] * b[1] - a[1] * b[0];
}

/* Time estimate of a rest-to-rest smoothstep move of every coordinate. */
static double ea__seg_time(const ea_planner_t *pl, const ea_task_point_t *a,
                           const ea_task_point_t *b) {
  const double dq[3] = {fabs(b->cable_length - a->cable_length),
                        fabs(b->cable_angle - a->cable_angle), fabs(b->base_angle - a->base_angle)};
  double T = 1e-3;
  for (int c = 0; c < 3; ++c) {
    if (isfinite(pl->vmax[c])) T = fmax(T, 1.5 * dq[c] / pl->vmax[c]);
    if (isfinite(pl->amax[c])) T = fmax(T, sqrt(6.0 * dq[c] / pl->amax[c]));
  }
  const double sm = pl->task.limits.shoulder_speed_max;
  if (isfinite(sm)) T = fmax(T, 1.5 * fabs(b->p[EA_P_THETA0] - a->p[EA_P_THETA0]) / sm);
  return T;
}

double ea__plan_duration_low(const ea_planner_t *pl) {
  if (!pl->has_tf) return pl->tf_fixed;
  double T = 0.0;
  for (int j = 0; j < pl->task.n_via + 1; ++j)
    T += ea__seg_time(pl, ea__point(&pl->task, j), ea__point(&pl->task, j + 1));
  return 0.5 * T;
}

void ea__plan_layout(ea_planner_t *pl) {
  const ea_task_t *t = &pl->task;
  const int np = t->n_via + 2, N = pl->N;
  pl->n_seg = np - 1;
  double Tseg[EA_TASK_MAX_VIA + 1], Tsum = 0.0;
  for (int j = 0; j < pl->n_seg; ++j) {
    Tseg[j] = ea__seg_time(pl, ea__point(t, j), ea__point(t, j + 1));
    Tsum += Tseg[j];
  }
  pl->via_knot[0] = 0;
  double acc = 0.0;
  for (int j = 1; j < np - 1; ++j) {
    acc += Tseg[j - 1];
    int k = (int)lround(acc / Tsum * (N - 1));
    if (k <= pl->via_knot[j - 1]) k = pl->via_knot[j - 1] + 1;
    if (k > N - 1 - (np - 1 - j)) k = N - 1 - (np - 1 - j);
    pl->via_knot[j] = k;
  }
  pl->via_knot[np - 1] = N - 1;
  ea__plan_segments(pl);
}

void ea__plan_segments(ea_planner_t *pl) {
  const ea_task_t *t = &pl->task;
  const int N = pl->N;
  /* Segments in 3-D (base frame). */
  pl->n_normals = pl->nq == 3 ? 2 : 1;
  for (int j = 0; j < pl->n_seg; ++j) {
    const ea_task_point_t *a = ea__point(t, j), *b = ea__point(t, j + 1);
    double B[3];
    ea__plan_tip3(pl, a->cable_length, a->cable_angle, a->base_angle, pl->segA[j], NULL);
    ea__plan_tip3(pl, b->cable_length, b->cable_angle, b->base_angle, B, NULL);
    double *D = pl->segD[j];
    for (int i = 0; i < 3; ++i)
      D[i] = B[i] - pl->segA[j][i];
    pl->segLen[j] = sqrt(D[0] * D[0] + D[1] * D[1] + D[2] * D[2]);
    ea__unit(D);
    if (pl->nq == 3) {
      const double z[3] = {0, 0, 1}, xx[3] = {1, 0, 0};
      ea__cross(D, fabs(D[2]) < 0.9 ? z : xx, pl->segN[j][0]);
      ea__unit(pl->segN[j][0]);
      ea__cross(D, pl->segN[j][0], pl->segN[j][1]);
      ea__unit(pl->segN[j][1]);
    } else {
      const double m[3] = {-sin(pl->base_fixed), cos(pl->base_fixed), 0.0};
      ea__cross(D, m, pl->segN[j][0]);
      ea__unit(pl->segN[j][0]);
    }
  }
  for (int k = 0; k < N; ++k)
    pl->seg_of_knot[k] = -1;
  if (t->path != EA_TASK_PATH_FREE)
    for (int j = 0; j < pl->n_seg; ++j)
      if (pl->segLen[j] > 1e-9)
        for (int k = pl->via_knot[j] + 1; k < pl->via_knot[j + 1]; ++k)
          pl->seg_of_knot[k] = j;
}

/* Tip (reach, height, base) at fraction sig of segment j. */
static void ea__seg_point(const ea_planner_t *pl, int j, double sig, double prev_base,
                          double *reach, double *height, double *base) {
  const ea_task_t *t = &pl->task;
  const ea_task_point_t *a = ea__point(t, j), *b = ea__point(t, j + 1);
  if (pl->nq == 3 && t->path != EA_TASK_PATH_FREE) {
    double P[3];
    for (int i = 0; i < 3; ++i)
      P[i] = pl->segA[j][i] + sig * pl->segLen[j] * pl->segD[j][i];
    *reach = hypot(P[0], P[1]);
    *height = P[2];
    double bb = *reach > 1e-12 ? atan2(P[1], P[0]) : prev_base;
    while (bb - prev_base > M_PI)
      bb -= 2 * M_PI;
    while (bb - prev_base < -M_PI)
      bb += 2 * M_PI;
    *base = bb;
  } else {
    *reach = (1 - sig) * a->reach + sig * b->reach;
    *height = (1 - sig) * a->height + sig * b->height;
    *base = pl->nq == 3 ? (1 - sig) * a->base_angle + sig * b->base_angle : pl->base_fixed;
  }
}

/* Actuator coordinates (L_c, alpha, base) at fraction sig of segment j. */
static void ea__seg_q(const ea_planner_t *pl, int j, double sig, double *prev_base, double q[3]) {
  const ea_arm_t *arm = &pl->task.arm;
  double R, H, B;
  ea__seg_point(pl, j, sig, *prev_base, &R, &H, &B);
  q[0] = hypot(R - arm->x_c, H - arm->y_c);
  q[1] = atan2(H - arm->y_c, R - arm->x_c);
  q[2] = B;
  *prev_base = B;
}

/* Time-optimal timing of segment j along the guess's path q(sig), rest to
 * rest, under the speed and acceleration limits of the actuator coordinates
 * (phase-plane reachability on a grid of sig: b = sig_dot^2, constant
 * sig_ddot per cell, forward and backward passes). Fills the knot fractions
 * sig_k and normalised rates dsig/dt at the segment's time fractions u_k
 * (u in [0, 1] of the returned duration). Returns the duration (0 when
 * no limit is finite: the caller keeps its smoothstep). */
#define EA__TOPP_M 400
/* (Just over 100 lines: the passes of one parametrisation share its stack grids.) */
static double ea__topp(const ea_planner_t *pl, int j, int nk, const double *u, double *sig,
                       double *sigdot, const double *th_sig, const double *th, double th_vmax,
                       double th_amax) {
  const int M = EA__TOPP_M, nq = pl->nq, nc = nq + (th != NULL);
  double q[EA__TOPP_M + 1][4], b[EA__TOPP_M + 1], bf[EA__TOPP_M + 1], t[EA__TOPP_M + 1];
  double vm[4], am[4];
  for (int c = 0; c < nq; ++c)
    vm[c] = pl->vmax[c], am[c] = pl->amax[c];
  vm[3] = th_vmax, am[3] = th_amax;
  double pb = pl->nq == 3 ? ea__point(&pl->task, j)->base_angle : pl->base_fixed;
  const double ds = 1.0 / M;
  int any = 0;
  for (int c = 0; c < nq; ++c)
    any |= isfinite(pl->vmax[c]) || isfinite(pl->amax[c]);
  if (!any) return 0.0;
  for (int i = 0; i <= M; ++i)
    ea__seg_q(pl, j, i * ds, &pb, q[i]);
  if (th) {
    /* theta0 at the segment's knots (th_sig increasing from 0 to 1) as a
     * 4th coordinate: the natural cubic spline through them in sig */
    double *m2 = pl->wscr, *cp = pl->wscr + nk;
    m2[0] = m2[nk - 1] = 0.0;
    for (int k = 1; k + 1 < nk; ++k) {
      const double h0 = th_sig[k] - th_sig[k - 1], h1 = th_sig[k + 1] - th_sig[k];
      const double r = 6.0 * ((th[k + 1] - th[k]) / h1 - (th[k] - th[k - 1]) / h0);
      const double den = 2.0 * (h0 + h1) - (k > 1 ? h0 * cp[k - 1] : 0.0);
      cp[k] = h1 / den;
      m2[k] = (r - (k > 1 ? h0 * m2[k - 1] : 0.0)) / den;
    }
    for (int k = nk - 3; k >= 1; --k)
      m2[k] -= cp[k] * m2[k + 1];
    for (int i = 0, k = 0; i <= M; ++i) {
      const double sg = i * ds;
      while (k + 2 < nk && th_sig[k + 1] < sg)
        ++k;
      const double h = th_sig[k + 1] - th_sig[k];
      if (!(h > 0.0)) return 0.0;
      const double a = (th_sig[k + 1] - sg) / h, bb = 1.0 - a;
      q[i][3] = a * th[k] + bb * th[k + 1] +
                ((a * a * a - a) * m2[k] + (bb * bb * bb - bb) * m2[k + 1]) * h * h / 6.0;
    }
  }
  /* first and second derivatives wrt sig on the grid */
  double d1[EA__TOPP_M + 1][4], d2[EA__TOPP_M + 1][4], cap[EA__TOPP_M + 1];
  for (int i = 0; i <= M; ++i) {
    const int a = i > 0 ? i - 1 : 0, z = i < M ? i + 1 : M, m = i == 0 ? 1 : i == M ? M - 1 : i;
    cap[i] = 1e30;
    for (int cc = 0; cc < nc; ++cc) {
      const int c = cc < nq ? cc : 3;
      d1[i][c] = (q[z][c] - q[a][c]) / ((z - a) * ds);
      d2[i][c] = (q[m + 1][c] - 2.0 * q[m][c] + q[m - 1][c]) / (ds * ds);
      const double v = vm[c], A = am[c];
      if (isfinite(v) && fabs(d1[i][c]) > 0.0) cap[i] = fmin(cap[i], v * v / (d1[i][c] * d1[i][c]));
      if (isfinite(A) && fabs(d1[i][c]) < 1e-9 && fabs(d2[i][c]) > 0.0)
        cap[i] = fmin(cap[i], A / fabs(d2[i][c]));
    }
  }
  /* admissible sig_ddot at (i, b): [lo, hi] */
#define EA__ACC_RANGE(i, bb, lo, hi)                                                               \
  do {                                                                                             \
    lo = -1e30, hi = 1e30;                                                                         \
    for (int cc = 0; cc < nc; ++cc) {                                                              \
      const int c = cc < nq ? cc : 3;                                                              \
      const double A = am[c], g1 = d1[i][c];                                                       \
      if (!isfinite(A) || fabs(g1) < 1e-9) continue;                                               \
      double r0 = (-A - d2[i][c] * (bb)) / g1, r1 = (A - d2[i][c] * (bb)) / g1;                    \
      if (r0 > r1) {                                                                               \
        const double tt = r0;                                                                      \
        r0 = r1;                                                                                   \
        r1 = tt;                                                                                   \
      }                                                                                            \
      lo = fmax(lo, r0), hi = fmin(hi, r1);                                                        \
    }                                                                                              \
  } while (0)
  bf[0] = 0.0;
  for (int i = 0; i < M; ++i) {
    double lo, hi;
    EA__ACC_RANGE(i, bf[i], lo, hi);
    const double nb = hi < lo ? bf[i] : bf[i] + 2.0 * ds * fmax(hi, 0.0);
    bf[i + 1] = fmin(cap[i + 1], fmax(0.0, nb));
  }
  b[M] = 0.0;
  for (int i = M - 1; i >= 0; --i) {
    double lo, hi;
    EA__ACC_RANGE(i + 1, b[i + 1], lo, hi);
    const double nb = hi < lo ? b[i + 1] : b[i + 1] - 2.0 * ds * fmin(lo, 0.0);
    b[i] = fmin(bf[i], fmax(0.0, nb));
  }
#undef EA__ACC_RANGE
  if (!(b[M / 2] > 0.0) || b[M / 2] >= 1e29) return 0.0;
  t[0] = 0.0;
  for (int i = 0; i < M; ++i) {
    const double den = sqrt(b[i]) + sqrt(b[i + 1]);
    if (!(den > 0.0)) return 0.0;
    t[i + 1] = t[i] + 2.0 * ds / den;
  }
  const double T = t[M];
  int i = 0;
  for (int k = 0; k < nk; ++k) {
    const double tau = u[k] * T;
    while (i + 1 < M && t[i + 1] < tau)
      ++i;
    const double dt = t[i + 1] - t[i], w0 = sqrt(b[i]), w1 = sqrt(b[i + 1]);
    const double acc = (w1 - w0) / dt, e = fmax(0.0, fmin(dt, tau - t[i]));
    sig[k] = fmin(1.0, i * ds + w0 * e + 0.5 * acc * e * e);
    sigdot[k] = w0 + acc * e;
  }
  sig[0] = 0.0, sig[nk - 1] = 1.0, sigdot[0] = sigdot[nk - 1] = 0.0;
  return T;
}

void ea__plan_theta0_rates(const ea_planner_t *pl, double *x) {
  /* C2 cubic spline slopes through theta0 at the knots, clamped to rest at
   * both ends (Thomas algorithm on the continuity rows). */
  const int N = pl->N;
  const double tf = ea__plan_tf(pl, x);
  double *cp = pl->wscr, *dp = pl->wscr + N;
  for (int k = 1; k + 1 < N; ++k) {
    const double h0 = tf * (pl->s[k] - pl->s[k - 1]), h1 = tf * (pl->s[k + 1] - pl->s[k]);
    const double a = 1.0 / h0, b = 2.0 * (1.0 / h0 + 1.0 / h1), c = 1.0 / h1;
    const double r = 3.0 * ((x[EA__IP(pl, k, 1)] - x[EA__IP(pl, k - 1, 1)]) / (h0 * h0) +
                            (x[EA__IP(pl, k + 1, 1)] - x[EA__IP(pl, k, 1)]) / (h1 * h1));
    const double den = b - (k > 1 ? a * cp[k - 1] : 0.0);
    cp[k] = c / den;
    dp[k] = (r - (k > 1 ? a * dp[k - 1] : 0.0)) / den;
  }
  double w = 0.0;
  x[EA__IW(pl, N - 1)] = 0.0;
  for (int k = N - 2; k > 0; --k) {
    w = dp[k] - cp[k] * w;
    x[EA__IW(pl, k)] = w;
  }
  x[EA__IW(pl, 0)] = 0.0;
}

/* The phases of the cold guess (ea__plan_guess). Scratch: pl->gscr holds sig at the knots
 * (N), d sig / d u (N; -1: no timed path, centred differences), the time fractions of a
 * segment (N) and theta0 as a coordinate of the timing (its sig and values, N each). */

/* Minimum time: each segment timed time-optimally along the guess's path (ea__topp; with
 * with_theta0, theta0 of the last knots a coordinate under 90 % of its limits); returns the
 * largest of the segments' durations over their knot spans. *topp = 0 when a segment cannot
 * be timed. */
static double ea__guess_time_segments(ea_planner_t *pl, int with_theta0, int *topp) {
  const int N = pl->N;
  double *sigk = pl->gscr, *sdn = pl->gscr + N, tf_topp = 0.0;
  double *th_sig = pl->gscr + 3 * N, *th = pl->gscr + 4 * N; /* theta0 at the knots */
  for (int j = 0; j < pl->n_seg && *topp; ++j) {
    const int k0 = pl->via_knot[j], k1 = pl->via_knot[j + 1], nk = k1 - k0 + 1;
    double *u = pl->gscr + 2 * N; /* nk time fractions of the segment */
    for (int k = k0; k <= k1; ++k)
      u[k - k0] = (pl->s[k] - pl->s[k0]) / (pl->s[k1] - pl->s[k0]);
    const double Tj =
        ea__topp(pl, j, nk, u, sigk + k0, sdn + k0, th_sig + k0, with_theta0 ? th + k0 : NULL,
                 0.9 * pl->vmax[EA__C_TH], 0.9 * pl->amax[EA__C_TH]);
    if (!(Tj > 0.0)) {
      *topp = 0;
      break;
    }
    for (int k = k0; k <= k1; ++k)
      sdn[k] *= Tj; /* d sig / d u */
    tf_topp = fmax(tf_topp, Tj / (pl->s[k1] - pl->s[k0]));
  }
  return tf_topp;
}

/* Otherwise a smoothstep in time along each segment. */
static void ea__guess_smoothstep(ea_planner_t *pl) {
  double *sigk = pl->gscr, *sdn = pl->gscr + pl->N;
  for (int j = 0; j < pl->n_seg; ++j) {
    const int k0 = pl->via_knot[j], k1 = pl->via_knot[j + 1];
    for (int k = k0; k <= k1; ++k) {
      const double uu = (double)(k - k0) / (k1 - k0);
      sigk[k] = uu * uu * (3.0 - 2.0 * uu);
      sdn[k] = -1.0; /* centred differences below */
    }
  }
}

/* A prescribed path: the statics sol at knot k (not a pinned one) against the limits; the
 * first one broken refuses the path (EA_ERR_INFEASIBLE: which, where, by how much). */
static ea_status_t ea__guess_path_check(const ea_planner_t *pl, int k, double R, double H,
                                        double Lc, double al, const ea_statics_solution_t *sol,
                                        ea_error_t *err) {
  const ea_task_t *t = &pl->task;
  const ea_arm_t *arm = &t->arm;
  const ea_task_limits_t *l = &t->limits;
  const double T = sol->p[EA_P_TENSION], tau = fabs(arm->EI * sol->p[EA_P_KAPPA0]);
  const char *what = NULL;
  double by = 0.0;
  if (T < l->tension_min)
    what = "tension >= tension_min", by = l->tension_min - T;
  else if (T > l->tension_max)
    what = "tension <= tension_max", by = T - l->tension_max;
  else if (tau > l->shoulder_torque_max)
    what = "shoulder torque limit", by = tau - l->shoulder_torque_max;
  else if (Lc < l->cable_length_min)
    what = "cable_length_min", by = l->cable_length_min - Lc;
  else if (Lc > l->cable_length_max)
    what = "cable_length_max", by = Lc - l->cable_length_max;
  else if (sol->p[EA_P_THETA0] < arm->act.shoulder_angle_min ||
           sol->p[EA_P_THETA0] > arm->act.shoulder_angle_max)
    what = "shoulder angle range",
    by = fmax(arm->act.shoulder_angle_min - sol->p[2], sol->p[2] - arm->act.shoulder_angle_max);
  else if (pl->fm && l->min_first_frequency_hz > 0.0 &&
           ea__plan_freq(pl, Lc, al, NULL) < l->min_first_frequency_hz)
    what = "min_first_frequency_Hz",
    by = l->min_first_frequency_hz - ea__plan_freq(pl, Lc, al, NULL);
  if (!what) return EA_OK;
  return ea_error_set(err, EA_ERR_INFEASIBLE,
                      "the prescribed path leaves the workspace for payload %.4g kg: "
                      "constraint '%s' violated at knot %d by %.4g (tip reach %.4g m, "
                      "height %.4g m, tension %.4g N, shoulder torque %.4g N m)",
                      t->payload_kg, what, k, by, R, H, T, tau);
}

/* The actuator coordinates at sig of every knot along the path and the statics there
 * (continuation from the previous knot), pinned knots at their points. */
static ea_status_t ea__guess_knots(ea_planner_t *pl, double *x, ea_error_t *err) {
  const ea_task_t *t = &pl->task;
  const ea_arm_t *arm = &t->arm;
  const int nq = pl->nq;
  const double *sigk = pl->gscr;
  const int fixed_path = t->path != EA_TASK_PATH_FREE;
  ea_statics_settings_t set;
  ea_statics_settings_default(&set);
  set.allow_negative_tension = 1;
  double pprev[EA_NP], prev_base = t->start.base_angle;
  memcpy(pprev, t->start.p, sizeof pprev);
  for (int j = 0; j < pl->n_seg; ++j) {
    const int k0 = pl->via_knot[j], k1 = pl->via_knot[j + 1];
    for (int k = (j == 0 ? k0 : k0 + 1); k <= k1; ++k) {
      const double sig = sigk[k];
      double R, H, B;
      ea__seg_point(pl, j, sig, prev_base, &R, &H, &B);
      const ea_task_point_t *pin = k == k0 ? ea__point(t, j) : k == k1 ? ea__point(t, j + 1) : NULL;
      double Lc = hypot(R - arm->x_c, H - arm->y_c), al = atan2(H - arm->y_c, R - arm->x_c);
      if (pin) Lc = pin->cable_length, al = pin->cable_angle, B = pin->base_angle;
      prev_base = B;
      x[EA__IQ(pl, k, 0)] = Lc;
      x[EA__IQ(pl, k, 1)] = al;
      if (nq == 3) x[EA__IQ(pl, k, 2)] = B;
      ea_statics_problem_t prob = ea_statics_problem_cable(Lc, al);
      ea_statics_solution_t sol;
      ea_error_t e2;
      ea_status_t st = EA_OK;
      /* a prescribed path with its statics splines (transcribe/path_*.c): the knot's statics from
       * them (1e-10), no Newton; the pinned points keep their own */
      double ps[3];
      if (!pin && pl->guess_statics && pl->guess_statics(pl, j, sig, ps)) {
        sol.p[EA_P_ALPHA] = al;
        for (int i = 0; i < 3; ++i)
          sol.p[1 + i] = ps[i];
      } else {
        st = ea_statics_solve(pl->sh, &prob, &set, pprev, &sol, &e2);
        if (st) st = ea_statics_solve(pl->sh, &prob, &set, NULL, &sol, &e2);
      }
      if (st)
        return ea_error_set(err, EA_ERR_INFEASIBLE,
                            "initial guess: no static equilibrium at knot %d (tip reach %.4g m, "
                            "height %.4g m; cable length %.4g m, angle %.4g rad): the %s leaves "
                            "the workspace for payload %.4g kg (%s)",
                            k, R, H, Lc, al, fixed_path ? "path" : "straight interpolation",
                            t->payload_kg, e2.msg);
      if (fixed_path && !pin && (st = ea__guess_path_check(pl, k, R, H, Lc, al, &sol, err)))
        return st;
      memcpy(pprev, sol.p, sizeof pprev);
      for (int i = 0; i < 3; ++i)
        x[EA__IP(pl, k, i)] = sol.p[1 + i];
    }
  }
  return EA_OK;
}

/* Duration (a free one): the segment estimates (topp: 1 % above the timed tf_topp), then
 * stretched until the guess keeps the shoulder speed limit, in *tf. Returns 1 when a timed
 * guess breaks the shoulder speed or acceleration limit (by more than 5 %): time it again. */
static int ea__guess_duration(ea_planner_t *pl, double *x, int topp, double tf_topp,
                              double *tf_out) {
  const ea_task_t *t = &pl->task;
  const int N = pl->N;
  double tf = 0.0;
  for (int j = 0; j < pl->n_seg; ++j)
    tf += ea__seg_time(pl, ea__point(t, j), ea__point(t, j + 1));
  tf *= 1.2;
  if (topp) tf = 1.01 * tf_topp; /* 1 % inside the limits */
  const double sm = t->limits.shoulder_speed_max, tf0 = tf;
  if (isfinite(sm))
    for (int k = 0; k + 1 < N; ++k) {
      const double h = tf * (pl->s[k + 1] - pl->s[k]);
      const double d = fabs(x[EA__IP(pl, k + 1, 1)] - x[EA__IP(pl, k, 1)]);
      if (d / h > 0.9 * sm) tf *= d / h / (0.9 * sm);
    }
  /* the shoulder acceleration of the guess's theta0 spline at this timing */
  double th_acc = 0.0;
  if (topp && isfinite(pl->amax[EA__C_TH])) {
    x[EA__ITF(pl)] = tf0;
    ea__plan_theta0_rates(pl, x);
    for (int k = 0; k + 1 < N; ++k) {
      double a[2];
      ea__plan_hermite_acc(x[EA__IP(pl, k, 1)], x[EA__IP(pl, k + 1, 1)], x[EA__IW(pl, k)],
                           x[EA__IW(pl, k + 1)], tf0 * (pl->s[k + 1] - pl->s[k]), a, NULL);
      th_acc = fmax(th_acc, fmax(fabs(a[0]), fabs(a[1])) / pl->amax[EA__C_TH]);
    }
  }
  *tf_out = tf;
  return topp && (tf > 1.05 * tf0 || th_acc > 1.05);
}

/* Rates: along the timed path (dq/dsig dsig/dt), else centred differences; rest at the
 * pinned knots. */
static void ea__guess_rates(ea_planner_t *pl, double *x, double tf) {
  const int N = pl->N, nq = pl->nq;
  const double *sigk = pl->gscr, *sdn = pl->gscr + N;
  int jv = 0;
  for (int k = 0; k < N; ++k) {
    while (jv < pl->n_seg + 1 && pl->via_knot[jv] < k)
      ++jv;
    const int pinned = jv <= pl->n_seg && pl->via_knot[jv] == k;
    double dqds[3] = {0.0, 0.0, 0.0}, sdot = 0.0;
    if (!pinned && sdn[k] >= 0.0) {
      const int j = jv - 1, k0 = pl->via_knot[j], k1 = pl->via_knot[j + 1];
      const double e = 1e-6, sa = fmax(0.0, sigk[k] - e), sb = fmin(1.0, sigk[k] + e);
      double qa[3], qb[3], pb = nq == 3 ? x[EA__IQ(pl, k, 2)] : pl->base_fixed;
      ea__seg_q(pl, j, sa, &pb, qa);
      ea__seg_q(pl, j, sb, &pb, qb);
      for (int c = 0; c < nq; ++c)
        dqds[c] = (qb[c] - qa[c]) / (sb - sa);
      sdot = sdn[k] / (tf * (pl->s[k1] - pl->s[k0]));
    }
    for (int c = 0; c < nq; ++c) {
      double v = 0.0;
      if (!pinned && sdn[k] >= 0.0) {
        v = dqds[c] * sdot;
        if (isfinite(pl->vmax[c])) v = fmax(-pl->vmax[c], fmin(pl->vmax[c], v));
      } else if (!pinned) {
        const double dt = tf * (pl->s[k + 1] - pl->s[k - 1]);
        v = (x[EA__IQ(pl, k + 1, c)] - x[EA__IQ(pl, k - 1, c)]) / dt;
        if (isfinite(pl->vmax[c])) v = fmax(-pl->vmax[c], fmin(pl->vmax[c], v));
      }
      x[EA__IV(pl, k, c)] = v;
    }
  }
}

/* Minimum time: the rates of the C2 cubic spline through the knots (rest at the pinned
 * knots), so the acceleration continuity rows hold at the start and the rates agree with
 * the positions. */
static void ea__guess_spline_rates(ea_planner_t *pl, double *x, double tf) {
  const int N = pl->N, nq = pl->nq;
  for (int j = 0; j < pl->n_seg; ++j) {
    const int k0 = pl->via_knot[j], k1 = pl->via_knot[j + 1];
    double *cp = pl->gscr + 3 * N, *dp = pl->gscr + 4 * N;
    for (int c = 0; c < nq; ++c) {
      /* C2 cubic spline slopes, clamped to rest at k0 and k1 (Thomas). */
      for (int k = k0 + 1; k < k1; ++k) {
        const double h0 = tf * (pl->s[k] - pl->s[k - 1]), h1 = tf * (pl->s[k + 1] - pl->s[k]);
        const double a = 1.0 / h0, b = 2.0 * (1.0 / h0 + 1.0 / h1), cc = 1.0 / h1;
        const double r = 3.0 * ((x[EA__IQ(pl, k, c)] - x[EA__IQ(pl, k - 1, c)]) / (h0 * h0) +
                                (x[EA__IQ(pl, k + 1, c)] - x[EA__IQ(pl, k, c)]) / (h1 * h1));
        const double den = b - (k > k0 + 1 ? a * cp[k - 1] : 0.0);
        cp[k] = cc / den;
        dp[k] = (r - (k > k0 + 1 ? a * dp[k - 1] : 0.0)) / den;
      }
      double vn = 0.0;
      for (int k = k1 - 1; k > k0; --k) {
        vn = dp[k] - cp[k] * vn;
        const double vm = isfinite(pl->vmax[c]) ? pl->vmax[c] : INFINITY;
        x[EA__IV(pl, k, c)] = fmax(-vm, fmin(vm, vn));
      }
    }
  }
}

ea_status_t ea__plan_guess(ea_planner_t *pl, double *x, ea_plan_info_t *info, ea_error_t *err) {
  const int N = pl->N;
  (void)info;
  /* Minimum time: each segment timed time-optimally along the guess's path
   * (ea__topp), t_f the largest of the segments' durations over their knot
   * spans. Otherwise, when a segment cannot be timed, or when the timed
   * guess breaks the shoulder speed limit (ea__topp does not see theta0):
   * a smoothstep in time with the old duration estimate. */
  const double *sigk = pl->gscr;
  double *th_sig = pl->gscr + 3 * N, *th = pl->gscr + 4 * N; /* theta0 at the knots */
  int topp = pl->task.objective == EA_TASK_MIN_TIME && pl->has_tf, with_theta0 = 0;
  double tf = pl->tf_fixed;
  for (;;) {
    const double tf_topp = topp ? ea__guess_time_segments(pl, with_theta0, &topp) : 0.0;
    if (!topp) ea__guess_smoothstep(pl);
    const ea_status_t st = ea__guess_knots(pl, x, err);
    if (st) return st;
    if (!pl->has_tf) break;
    if (!ea__guess_duration(pl, x, topp, tf_topp, &tf)) {
      x[EA__ITF(pl)] = tf;
      break;
    }
    /* the timed guess breaks the shoulder speed or acceleration limit: time it again with
     * theta0 of these knots (a spline in sig) as a coordinate under 90 % of its limits; if
     * that is not enough either, the smoothstep */
    if (!with_theta0) {
      for (int k = 0; k < N; ++k)
        th_sig[k] = sigk[k], th[k] = x[EA__IP(pl, k, 1)];
      with_theta0 = 1;
    } else {
      topp = 0;
    }
  }
  pl->guess_timed = topp;
  ea__guess_rates(pl, x, tf);
  if (topp) ea__guess_spline_rates(pl, x, tf);
  ea__plan_theta0_rates(pl, x);
  return EA_OK;
}

/* Linear interpolation of column c of tr at time tt. */
static double ea__traj_at(const ea_traj_t *tr, int c, double tt) {
  int i = 0;
  while (i + 2 < tr->n && EA_TRAJ_AT(tr, i + 1, EA_TRAJ_t) < tt)
    ++i;
  const double t0 = EA_TRAJ_AT(tr, i, EA_TRAJ_t), t1 = EA_TRAJ_AT(tr, i + 1, EA_TRAJ_t);
  double w = (tt - t0) / (t1 - t0);
  w = fmax(0.0, fmin(1.0, w));
  return (1 - w) * EA_TRAJ_AT(tr, i, c) + w * EA_TRAJ_AT(tr, i + 1, c);
}

ea_status_t ea__plan_guess_traj(ea_planner_t *pl, const ea_traj_t *tr, double *x, ea_error_t *err) {
  if (!tr || tr->n < 2 || !tr->data)
    return ea_error_set(err, EA_ERR_ARG, "warm start: the previous plan has fewer than 2 rows");
  const double t0 = EA_TRAJ_AT(tr, 0, EA_TRAJ_t),
               tf_prev = EA_TRAJ_AT(tr, tr->n - 1, EA_TRAJ_t) - t0;
  if (!(tf_prev > 0.0)) return ea_error_set(err, EA_ERR_ARG, "warm start: zero-length plan");
  const double tf = pl->has_tf ? tf_prev : pl->tf_fixed;
  static const int qc[3] = {EA_TRAJ_cable_length, EA_TRAJ_cable_angle, EA_TRAJ_base_angle};
  static const int vc[3] = {EA_TRAJ_cable_length_rate, EA_TRAJ_cable_angle_rate,
                            EA_TRAJ_base_angle_rate};
  for (int k = 0; k < pl->N; ++k) {
    const double tt = t0 + pl->s[k] * tf_prev;
    for (int c = 0; c < pl->nq; ++c) {
      x[EA__IQ(pl, k, c)] = ea__traj_at(tr, qc[c], tt);
      x[EA__IV(pl, k, c)] = ea__traj_at(tr, vc[c], tt) * tf_prev / tf;
    }
    x[EA__IP(pl, k, 0)] = ea__traj_at(tr, EA_TRAJ_tension, tt);
    x[EA__IP(pl, k, 1)] = ea__traj_at(tr, EA_TRAJ_theta0, tt);
    x[EA__IP(pl, k, 2)] = ea__traj_at(tr, EA_TRAJ_kappa0, tt);
  }
  if (pl->has_tf) x[EA__ITF(pl)] = tf;
  ea__plan_theta0_rates(pl, x);
  return EA_OK;
}

/* Step 3 of the predictor (min_time): x (knot layout, the new task's knots) re-timed by lam =
 * the largest usage of a time-scaled limit at its knots over the same at the old plan
 * (pl->x_sol), speeds linear, accelerations square-rooted; t_f times lam, rates over lam
 * (clamped to 0.5..2). Returns lam (1: nothing to compare). */
double ea__plan_retime(const ea_planner_t *pl, double *x) {
  const ea_task_t *t = &pl->task;
  const int N = pl->N, nq = pl->nq;
  const double tf = x[EA__ITF(pl)];
  /* (a finer rule, only the limits the old plan had active, predicted t_f no better and
   * cost iterations) */
  const double *xo = pl->x_sol;
  double un_max = 0.0, uo_max = 0.0;
  for (int k = 0; k + 1 < N; ++k) {
    const double ds = pl->s[k + 1] - pl->s[k];
    for (int c = 0; c < nq; ++c) {
      double un[4], uo[4];
      for (int o = 0; o < 2; ++o) {
        const double *y = o ? xo : x, h = ds * tf;
        double *u = o ? uo : un;
        const double q0 = y[EA__IQ(pl, k, c)], q1 = y[EA__IQ(pl, k + 1, c)];
        const double v0 = y[EA__IV(pl, k, c)], v1 = y[EA__IV(pl, k + 1, c)];
        double a[2], ga[2][5];
        ea__plan_hermite_acc(q0, q1, v0, v1, h, a, ga);
        u[0] = fabs(v0) / pl->vmax[c];
        u[1] = fabs(1.5 * (q1 - q0) / h - 0.25 * (v0 + v1)) / pl->vmax[c];
        u[2] = sqrt(fabs(a[0]) / pl->amax[c]);
        u[3] = sqrt(fabs(a[1]) / pl->amax[c]);
      }
      for (int i = 0; i < 4; ++i)
        if (isfinite(uo[i]) && isfinite(un[i]))
          un_max = fmax(un_max, un[i]), uo_max = fmax(uo_max, uo[i]);
    }
    const double ws = t->limits.shoulder_speed_max;
    if (isfinite(ws)) {
      const double h = ds * tf;
      const double un = fabs(x[EA__IP(pl, k + 1, 1)] - x[EA__IP(pl, k, 1)]) / h / ws;
      const double uo = fabs(xo[EA__IP(pl, k + 1, 1)] - xo[EA__IP(pl, k, 1)]) / h / ws;
      un_max = fmax(un_max, un);
      uo_max = fmax(uo_max, uo);
    }
  }
  if (!(uo_max > 0.0 && un_max > 0.0)) return 1.0;
  const double lam = fmax(0.5, fmin(2.0, un_max / uo_max));
  x[EA__ITF(pl)] = tf * lam;
  for (int k = 0; k < N; ++k)
    for (int c = 0; c < nq; ++c)
      x[EA__IV(pl, k, c)] /= lam;
  return lam;
}

/* Replanning predictor (ea_planner_update, then EA_PLAN_WARM). x holds the
 * solution of task prev; the structure (knots, via knots, rows) is the
 * same. Three steps, each cheap next to an Ipopt iteration:
 * 1. points moved: on each segment, every knot's progress sigma along the
 *    segment (from its dominant coordinate) is kept and each coordinate is
 *    moved by (1 - sigma) dA + sigma dB (dA, dB: the shifts of the
 *    segment's ends), rates by sigma_dot (dB - dA): exact for the
 *    dominant coordinate's affine stretch;
 * 2. every free knot's statics re-solved by Newton at its new (L_c, alpha)
 *    from its old (T, theta0, kappa0) (also for a changed payload);
 * 3. min_time: the plan re-timed by lambda = the largest ratio of a speed
 *    limit (or the square root of an acceleration limit) used at the new
 *    knots to that of the old plan, so the limits the old plan held hold
 *    again (a uniform time scaling keeps the path). */
ea_status_t ea__plan_predict(ea_planner_t *pl, const ea_task_t *prev, double *x, int statics) {
  const ea_task_t *t = &pl->task;
  const int N = pl->N, nq = pl->nq;
  const double w[3] = {1.0, t->arm.length, t->arm.length}; /* [m], [m/rad] */
  double tf =
      pl->has_tf ? x[EA__ITF(pl)] : (isnan(prev->duration_s) ? pl->tf_fixed : prev->duration_s);
  const int retime = pl->has_tf && t->objective == EA_TASK_MIN_TIME;
  /* 1. shift the coordinates along the moved points */
  for (int j = 0; j < pl->n_seg; ++j) {
    const ea_task_point_t *ao = ea__point(prev, j), *bo = ea__point(prev, j + 1);
    const ea_task_point_t *an = ea__point(t, j), *bn = ea__point(t, j + 1);
    const double qao[3] = {ao->cable_length, ao->cable_angle, ao->base_angle};
    const double qbo[3] = {bo->cable_length, bo->cable_angle, bo->base_angle};
    const double qan[3] = {an->cable_length, an->cable_angle, an->base_angle};
    const double qbn[3] = {bn->cable_length, bn->cable_angle, bn->base_angle};
    double dA[3], dB[3], moved = 0.0;
    int cs = 0;
    for (int c = 0; c < nq; ++c) {
      dA[c] = qan[c] - qao[c];
      dB[c] = qbn[c] - qbo[c];
      moved = fmax(moved, fabs(dA[c]) + fabs(dB[c]));
      if (w[c] * fabs(qbo[c] - qao[c]) > w[cs] * fabs(qbo[cs] - qao[cs])) cs = c;
    }
    if (moved == 0.0) continue;
    const int k0 = pl->via_knot[j], k1 = pl->via_knot[j + 1];
    const double D = qbo[cs] - qao[cs];
    for (int k = k0 + (j > 0); k <= k1; ++k) {
      double sg, sgd;
      if (w[cs] * fabs(D) > 1e-9) {
        sg = (x[EA__IQ(pl, k, cs)] - qao[cs]) / D;
        sgd = x[EA__IV(pl, k, cs)] / D;
      } else {
        sg = (pl->s[k] - pl->s[k0]) / (pl->s[k1] - pl->s[k0]);
        sgd = 1.0 / ((pl->s[k1] - pl->s[k0]) * tf);
      }
      sg = fmax(0.0, fmin(1.0, sg));
      for (int c = 0; c < nq; ++c) {
        x[EA__IQ(pl, k, c)] += (1.0 - sg) * dA[c] + sg * dB[c];
        x[EA__IV(pl, k, c)] += sgd * (dB[c] - dA[c]);
      }
    }
  }
  /* 2. statics of every knot at its new (L_c, alpha) (not for the path transcription,
   * whose statics are its splines') */
  if (statics) {
    ea_statics_settings_t set;
    ea_statics_settings_default(&set);
    set.allow_negative_tension = 1;
    set.max_cont_steps = 0;
    int jv = 0;
    for (int k = 0; k < N; ++k) {
      while (jv < pl->n_seg + 1 && pl->via_knot[jv] < k)
        ++jv;
      if (jv <= pl->n_seg && pl->via_knot[jv] == k) { /* pinned: the point's statics */
        const ea_task_point_t *p = ea__point(t, jv);
        for (int i = 0; i < 3; ++i)
          x[EA__IP(pl, k, i)] = p->p[i + 1];
        continue;
      }
      const double guess[EA_NP] = {x[EA__IQ(pl, k, 1)], x[EA__IP(pl, k, 0)], x[EA__IP(pl, k, 1)],
                                   x[EA__IP(pl, k, 2)]};
      ea_statics_problem_t prob = ea_statics_problem_cable(x[EA__IQ(pl, k, 0)], guess[0]);
      ea_statics_solution_t sol;
      if (ea_statics_solve(pl->sh, &prob, &set, guess, &sol, NULL) != EA_OK ||
          sol.branch != EA_BRANCH_WARM)
        continue; /* Ipopt starts from the old values there */
      for (int i = 0; i < 3; ++i)
        x[EA__IP(pl, k, i)] = sol.p[i + 1];
    }
  }
  if (retime) ea__plan_retime(pl, x);
  ea__plan_theta0_rates(pl, x);
  return EA_OK;
}
