/* Command streamer: actuator mapping, resampling at the controller rate
 * (quintic Hermite), the limits check, and the controlled-stop ramp. */
#include "ea_statics.h"
#include "stream_impl.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- Mapping --------------------------------------------------------------- */

void ea_stream_map(const ea_arm_t *arm, const ea_joint_state_t *q, ea_setpoint_t *sp) {
  const ea_actuators_t *a = &arm->act;
  const double k = a->spool_gear_ratio / a->spool_radius; /* [rad/m] motor per cable */
  memset(sp, 0, sizeof *sp);
  for (int i = 0; i < 2; ++i) {
    sp->spool_pos[i] = (q->cable_length - a->spool_zero_length) * k;
    sp->spool_vel[i] = q->cable_length_rate * k;
    sp->spool_acc[i] = q->cable_length_acc * k;
  }
  sp->shoulder_pos = q->theta0;
  sp->shoulder_vel = q->theta0_rate;
  sp->shoulder_acc = q->theta0_acc;
  sp->base_pos = q->base_angle;
  sp->base_vel = q->base_angle_rate;
  sp->base_acc = q->base_angle_acc;
  sp->shoulder_torque = arm->EI * q->kappa0;
  sp->tension = q->tension;
}

void ea_stream_unmap(const ea_arm_t *arm, const ea_setpoint_t *sp, ea_joint_state_t *q) {
  const ea_actuators_t *a = &arm->act;
  const double k = a->spool_radius / a->spool_gear_ratio; /* [m/rad] */
  q->cable_length = a->spool_zero_length + sp->spool_pos[0] * k;
  q->cable_length_rate = sp->spool_vel[0] * k;
  q->cable_length_acc = sp->spool_acc[0] * k;
  q->theta0 = sp->shoulder_pos;
  q->theta0_rate = sp->shoulder_vel;
  q->theta0_acc = sp->shoulder_acc;
  q->base_angle = sp->base_pos;
  q->base_angle_rate = sp->base_vel;
  q->base_angle_acc = sp->base_acc;
  q->tension = sp->tension;
  q->kappa0 = sp->shoulder_torque / arm->EI;
}

ea_status_t ea_stream_setpoints_traj(const ea_arm_t *arm, double tip_mass, const ea_setpoint_t *sp,
                                     const double *t, int n, ea_traj_t *tr, int *skipped,
                                     ea_error_t *err) {
  if (skipped) *skipped = 0;
  if (!arm || !sp || !t || !tr || n < 1)
    return ea_error_set(err, EA_ERR_ARG, "setpoints to a trajectory: no setpoints");
  int m = 1; /* rows kept: times strictly increasing */
  for (int i = 1, last = 0; i < n; ++i)
    if (t[i] > t[last]) last = i, ++m;
  ea_status_t st = ea_traj_alloc(tr, m);
  if (st) return ea_error_set(err, st, "setpoints to a trajectory: %d rows", m);
  ea_shooter_t *sh = NULL;
  if ((st = ea_shooter_alloc(arm, NULL, &sh, err))) return st;
  const ea_load_t load = {tip_mass};
  ea_shooter_set_load(sh, &load);
  double guess[EA_NP];
  for (int i = 0, r = 0, last = -1; i < n && !st; ++i) {
    if (last >= 0 && !(t[i] > t[last])) continue;
    last = i;
    ea_joint_state_t q;
    ea_stream_unmap(arm, &sp[i], &q);
    ea_statics_problem_t pr = {{EA_GIVEN_CABLE_LENGTH, EA_GIVEN_THETA0},
                               {q.cable_length, q.theta0}};
    ea_statics_solution_t sol;
    ea_error_t e = {0};
    st = ea_statics_solve(sh, &pr, NULL, r ? guess : NULL, &sol, &e);
    if (st && r) st = ea_statics_solve(sh, &pr, NULL, NULL, &sol, &e);
    if (st) {
      st = ea_error_set(err, EA_ERR_INADMISSIBLE,
                        "setpoint %d (t = %g s): no static solution at cable length %g m, "
                        "shoulder angle %g rad: %s",
                        i + 1, t[i], q.cable_length, q.theta0, e.msg);
      break;
    }
    memcpy(guess, sol.p, sizeof guess);
    const double v[EA_TRAJ_NCOL] = {
        [EA_TRAJ_t] = t[i],
        [EA_TRAJ_cable_length] = q.cable_length,
        [EA_TRAJ_cable_angle] = sol.p[EA_P_ALPHA],
        [EA_TRAJ_base_angle] = q.base_angle,
        [EA_TRAJ_cable_length_rate] = q.cable_length_rate,
        [EA_TRAJ_base_angle_rate] = q.base_angle_rate,
        [EA_TRAJ_cable_length_acc] = q.cable_length_acc,
        [EA_TRAJ_base_angle_acc] = q.base_angle_acc,
        [EA_TRAJ_theta0_rate] = q.theta0_rate,
    };
    memcpy(&EA_TRAJ_AT(tr, r, 0), v, sizeof v);
    ea_traj_set_statics(tr, r, sol.p, sol.tip, arm->EI);
    /* the drive is what the setpoints command: their feed-forwards */
    EA_TRAJ_AT(tr, r, EA_TRAJ_tension) = q.tension;
    EA_TRAJ_AT(tr, r, EA_TRAJ_theta0) = q.theta0;
    EA_TRAJ_AT(tr, r, EA_TRAJ_kappa0) = q.kappa0;
    EA_TRAJ_AT(tr, r, EA_TRAJ_shoulder_torque) = sp[i].shoulder_torque;
    ++r;
  }
  ea_shooter_free(sh);
  if (st) return st;
  for (int r = 0; r < m; ++r) { /* the cable angle's rate: centred differences */
    const int a = r ? r - 1 : 0, b = r < m - 1 ? r + 1 : m - 1;
    EA_TRAJ_AT(tr, r, EA_TRAJ_cable_angle_rate) =
        b > a ? (EA_TRAJ_AT(tr, b, EA_TRAJ_cable_angle) - EA_TRAJ_AT(tr, a, EA_TRAJ_cable_angle)) /
                    (EA_TRAJ_AT(tr, b, EA_TRAJ_t) - EA_TRAJ_AT(tr, a, EA_TRAJ_t))
              : 0.0;
  }
  if (skipped) *skipped = n - m;
  tr->tip_mass_kg = tip_mass;
  tr->payload_kg = tip_mass - arm->m_hand;
  snprintf(tr->status, sizeof tr->status, "setpoints");
  return EA_OK;
}

/* ---- Limits ---------------------------------------------------------------- */

static int ea__range_ok(double v, double lo, double hi, double tol) {
  const double slack = tol * fmax(1.0, fmax(fabs(lo), fabs(hi)));
  return isfinite(v) && v >= lo - slack && v <= hi + slack;
}

static int ea__abs_ok(double v, double max, double tol) {
  return isfinite(v) && fabs(v) <= max * (1.0 + tol) + tol * 1e-12;
}

ea_status_t ea_stream_check_limits(const ea_arm_t *arm, const ea_setpoint_t *sp, double tol,
                                   ea_error_t *err) {
  const ea_actuators_t *a = &arm->act;
  const double agree = fmax(tol, 1e-12);
  if (fabs(sp->spool_pos[0] - sp->spool_pos[1]) > agree * fmax(1.0, fabs(sp->spool_pos[0])) ||
      fabs(sp->spool_vel[0] - sp->spool_vel[1]) > agree * fmax(1.0, fabs(sp->spool_vel[0])) ||
      fabs(sp->spool_acc[0] - sp->spool_acc[1]) > agree * fmax(1.0, fabs(sp->spool_acc[0])))
    return ea_error_set(err, EA_ERR_INADMISSIBLE,
                        "spools disagree: %.9g vs %.9g rad (both spools move together)",
                        sp->spool_pos[0], sp->spool_pos[1]);
  ea_joint_state_t q;
  ea_stream_unmap(arm, sp, &q);
#define EA__RANGE(v, lo, hi, what, unit)                                                           \
  if (!ea__range_ok(v, lo, hi, tol))                                                               \
    return ea_error_set(err, EA_ERR_INADMISSIBLE, "%s %.9g %s outside [%.9g, %.9g]", what, v,      \
                        unit, lo, hi);
#define EA__ABS(v, max, what, unit)                                                                \
  if (!ea__abs_ok(v, max, tol))                                                                    \
    return ea_error_set(err, EA_ERR_INADMISSIBLE, "|%s| %.9g %s above the limit %.9g", what,       \
                        fabs(v), unit, max);
  EA__RANGE(q.cable_length, a->cable_length_min, a->cable_length_max, "cable length", "m")
  EA__ABS(q.cable_length_rate, a->cable_speed_max, "cable speed", "m/s")
  EA__ABS(q.cable_length_acc, a->cable_accel_max, "cable acceleration", "m/s^2")
  EA__RANGE(q.theta0, a->shoulder_angle_min, a->shoulder_angle_max, "shoulder angle", "rad")
  EA__ABS(q.theta0_rate, a->shoulder_speed_max, "shoulder speed", "rad/s")
  EA__ABS(q.theta0_acc, a->shoulder_accel_max, "shoulder acceleration", "rad/s^2")
  EA__RANGE(q.base_angle, a->base_angle_min, a->base_angle_max, "base angle", "rad")
  EA__ABS(q.base_angle_rate, a->base_speed_max, "base speed", "rad/s")
  EA__ABS(q.base_angle_acc, a->base_accel_max, "base acceleration", "rad/s^2")
  EA__RANGE(q.tension, a->tension_min, a->tension_max, "tension", "N")
  EA__ABS(sp->shoulder_torque, a->shoulder_torque_max, "shoulder torque", "N m")
#undef EA__RANGE
#undef EA__ABS
  return EA_OK;
}

/* The protocol's continuity rule (docs/protocol.md, "What each side checks"): over dt
 * seconds each axis's position change must match the trapezoid of its velocities within
 * tol v_max dt + a_max dt^2, and its velocity change must stay within (1 + tol) a_max dt
 * (1e-9 rad absolute slack on both, as the controller's check). */
ea_status_t ea_stream_check_continuity(const ea_arm_t *arm, const ea_setpoint_t *prev,
                                       const ea_setpoint_t *next, double dt, double tol,
                                       ea_error_t *err) {
  static const char *const axis[3] = {"spool", "shoulder", "base"};
  if (!(dt > 0) || !isfinite(dt))
    return ea_error_set(err, EA_ERR_INADMISSIBLE, "setpoint times do not increase (dt %g s)", dt);
  const ea_actuators_t *a = &arm->act;
  const double ks = a->spool_gear_ratio / a->spool_radius;
  const double p0[3] = {prev->spool_pos[0], prev->shoulder_pos, prev->base_pos};
  const double p1[3] = {next->spool_pos[0], next->shoulder_pos, next->base_pos};
  const double v0[3] = {prev->spool_vel[0], prev->shoulder_vel, prev->base_vel};
  const double v1[3] = {next->spool_vel[0], next->shoulder_vel, next->base_vel};
  const double vmax[3] = {a->cable_speed_max * ks, a->shoulder_speed_max, a->base_speed_max};
  const double amax[3] = {a->cable_accel_max * ks, a->shoulder_accel_max, a->base_accel_max};
  for (int i = 0; i < 3; ++i) {
    const double dp = p1[i] - p0[i] - 0.5 * (v0[i] + v1[i]) * dt;
    const double dp_max = tol * vmax[i] * dt + amax[i] * dt * dt + 1e-9;
    if (!(fabs(dp) <= dp_max))
      return ea_error_set(err, EA_ERR_INADMISSIBLE,
                          "%s motor jumps: moves %.6g rad in %g s where its velocities "
                          "(%.6g, %.6g rad/s) allow %.6g +- %.3g rad",
                          axis[i], p1[i] - p0[i], dt, v0[i], v1[i], 0.5 * (v0[i] + v1[i]) * dt,
                          dp_max);
    const double dv_max = amax[i] * dt * (1 + tol) + 1e-9;
    if (!(fabs(v1[i] - v0[i]) <= dv_max))
      return ea_error_set(err, EA_ERR_INADMISSIBLE,
                          "%s motor velocity jumps from %.6g to %.6g rad/s in %g s (at most "
                          "%.6g rad/s at its acceleration limit)",
                          axis[i], v0[i], v1[i], dt, dv_max);
  }
  return EA_OK;
}

void ea_stream_at_rest(const ea_setpoint_t *sp, ea_setpoint_t *rest) {
  *rest = *sp;
  for (int i = 0; i < 2; ++i)
    rest->spool_vel[i] = rest->spool_acc[i] = 0.0;
  rest->shoulder_vel = rest->shoulder_acc = 0.0;
  rest->base_vel = rest->base_acc = 0.0;
}

/* ---- Interpolation ----------------------------------------------------------- */

/* Quintic Hermite on [0, h]: value, rate and acceleration at both ends. */
static void ea__quintic(double h, double s, double p0, double v0, double a0, double p1, double v1,
                        double a1, double *p, double *v, double *a) {
  const double d = p1 - p0, hv0 = h * v0, hv1 = h * v1, h2a0 = h * h * a0, h2a1 = h * h * a1;
  const double c0 = p0, c1 = hv0, c2 = 0.5 * h2a0;
  const double c3 = 10 * d - 6 * hv0 - 4 * hv1 - 1.5 * h2a0 + 0.5 * h2a1;
  const double c4 = -15 * d + 8 * hv0 + 7 * hv1 + 1.5 * h2a0 - h2a1;
  const double c5 = 6 * d - 3 * hv0 - 3 * hv1 - 0.5 * h2a0 + 0.5 * h2a1;
  *p = c0 + s * (c1 + s * (c2 + s * (c3 + s * (c4 + s * c5))));
  *v = (c1 + s * (2 * c2 + s * (3 * c3 + s * (4 * c4 + s * 5 * c5)))) / h;
  *a = (2 * c2 + s * (6 * c3 + s * (12 * c4 + s * 20 * c5))) / (h * h);
}

/* Cubic Hermite on [0, h]: value and slope at both ends. */
static double ea__cubic(double h, double s, double p0, double m0, double p1, double m1) {
  const double s2 = s * s, s3 = s2 * s;
  return (2 * s3 - 3 * s2 + 1) * p0 + (s3 - 2 * s2 + s) * h * m0 + (-2 * s3 + 3 * s2) * p1 +
         (s3 - s2) * h * m1;
}

/* Derivative estimate of column c at sample i: weighted centred difference
 * (one-sided at the ends). */
static double ea__fd(const ea_traj_t *tr, int i, int c) {
  const int n = tr->n;
  if (n < 2) return 0.0;
  if (n == 2)
    return (EA_TRAJ_AT(tr, 1, c) - EA_TRAJ_AT(tr, 0, c)) /
           (EA_TRAJ_AT(tr, 1, EA_TRAJ_t) - EA_TRAJ_AT(tr, 0, EA_TRAJ_t));
  if (i == 0 || i == n - 1) {
    /* Second-order one-sided difference (derivative at x0 of the parabola
     * through the three end samples). */
    const int a = i == 0 ? 0 : n - 1, b = i == 0 ? 1 : n - 2, d = i == 0 ? 2 : n - 3;
    const double x0 = EA_TRAJ_AT(tr, a, EA_TRAJ_t), x1 = EA_TRAJ_AT(tr, b, EA_TRAJ_t),
                 x2 = EA_TRAJ_AT(tr, d, EA_TRAJ_t);
    const double f0 = EA_TRAJ_AT(tr, a, c), f1 = EA_TRAJ_AT(tr, b, c), f2 = EA_TRAJ_AT(tr, d, c);
    return f0 * (2 * x0 - x1 - x2) / ((x0 - x1) * (x0 - x2)) +
           f1 * (x0 - x2) / ((x1 - x0) * (x1 - x2)) + f2 * (x0 - x1) / ((x2 - x0) * (x2 - x1));
  }
  const double h0 = EA_TRAJ_AT(tr, i, EA_TRAJ_t) - EA_TRAJ_AT(tr, i - 1, EA_TRAJ_t);
  const double h1 = EA_TRAJ_AT(tr, i + 1, EA_TRAJ_t) - EA_TRAJ_AT(tr, i, EA_TRAJ_t);
  const double d0 = (EA_TRAJ_AT(tr, i, c) - EA_TRAJ_AT(tr, i - 1, c)) / h0;
  const double d1 = (EA_TRAJ_AT(tr, i + 1, c) - EA_TRAJ_AT(tr, i, c)) / h1;
  return (d0 * h1 + d1 * h0) / (h0 + h1);
}

/* Acceleration at sample i of the cubic Hermite of columns (c, rate) on the
 * adjacent intervals (docs/trajectory-format.md: theta0 follows the cubic
 * Hermite of theta0 and its rate; a planned theta0 is a C2 spline, so both
 * one-sided values agree and the quintic through them is that cubic). */
static double ea__hermite_acc(const ea_traj_t *tr, int i, int c, int rate) {
  double acc = 0.0;
  int na = 0;
  for (int j = i - 1; j <= i; ++j) {
    if (j < 0 || j + 1 >= tr->n) continue;
    const double h = EA_TRAJ_AT(tr, j + 1, EA_TRAJ_t) - EA_TRAJ_AT(tr, j, EA_TRAJ_t);
    const double d = (EA_TRAJ_AT(tr, j + 1, c) - EA_TRAJ_AT(tr, j, c)) / h;
    const double v0 = EA_TRAJ_AT(tr, j, rate), v1 = EA_TRAJ_AT(tr, j + 1, rate);
    acc += j == i ? (6.0 * d - 4.0 * v0 - 2.0 * v1) / h : (-6.0 * d + 2.0 * v0 + 4.0 * v1) / h;
    ++na;
  }
  return na ? acc / na : 0.0;
}

/* Monotone slope (Fritsch-Butland) of column c at sample i: no overshoot of
 * the samples, so feed-forwards stay within the range of the plan's values. */
static double ea__fd_monotone(const ea_traj_t *tr, int i, int c) {
  const int n = tr->n;
  if (n < 2) return 0.0;
  if (i == 0 || i == n - 1) return ea__fd(tr, i, c); /* end secant */
  const double h0 = EA_TRAJ_AT(tr, i, EA_TRAJ_t) - EA_TRAJ_AT(tr, i - 1, EA_TRAJ_t);
  const double h1 = EA_TRAJ_AT(tr, i + 1, EA_TRAJ_t) - EA_TRAJ_AT(tr, i, EA_TRAJ_t);
  const double d0 = (EA_TRAJ_AT(tr, i, c) - EA_TRAJ_AT(tr, i - 1, c)) / h0;
  const double d1 = (EA_TRAJ_AT(tr, i + 1, c) - EA_TRAJ_AT(tr, i, c)) / h1;
  if (d0 * d1 <= 0.0) return 0.0;
  return 3.0 * (h0 + h1) / ((2 * h1 + h0) / d0 + (h1 + 2 * h0) / d1);
}

ea_status_t ea_stream_traj_eval(const ea_traj_t *tr, double t, ea_joint_state_t *q) {
  if (!tr || !q || tr->n < 1 || !tr->data || !isfinite(t)) return EA_ERR_ARG;
  memset(q, 0, sizeof *q);
  const int n = tr->n;
  if (n == 1 || t <= EA_TRAJ_AT(tr, 0, EA_TRAJ_t) || t >= EA_TRAJ_AT(tr, n - 1, EA_TRAJ_t)) {
    const int i = (n == 1 || t <= EA_TRAJ_AT(tr, 0, EA_TRAJ_t)) ? 0 : n - 1;
    /* At an end sample: its values. Beyond it: the end's rates held, positions moving
     * with them, no acceleration (a hold, for a plan that starts and ends at rest; a
     * consistent continuation otherwise, which the streamer then refuses as not at
     * rest). */
    const double u = t - EA_TRAJ_AT(tr, i, EA_TRAJ_t), at = u == 0.0;
    q->cable_length_rate = EA_TRAJ_AT(tr, i, EA_TRAJ_cable_length_rate);
    q->cable_length = EA_TRAJ_AT(tr, i, EA_TRAJ_cable_length) + u * q->cable_length_rate;
    q->cable_length_acc = at ? EA_TRAJ_AT(tr, i, EA_TRAJ_cable_length_acc) : 0.0;
    q->theta0_rate = EA_TRAJ_AT(tr, i, EA_TRAJ_theta0_rate);
    q->theta0 = EA_TRAJ_AT(tr, i, EA_TRAJ_theta0) + u * q->theta0_rate;
    q->theta0_acc = at ? ea__hermite_acc(tr, i, EA_TRAJ_theta0, EA_TRAJ_theta0_rate) : 0.0;
    q->base_angle_rate = EA_TRAJ_AT(tr, i, EA_TRAJ_base_angle_rate);
    q->base_angle = EA_TRAJ_AT(tr, i, EA_TRAJ_base_angle) + u * q->base_angle_rate;
    q->base_angle_acc = at ? EA_TRAJ_AT(tr, i, EA_TRAJ_base_angle_acc) : 0.0;
    q->tension = EA_TRAJ_AT(tr, i, EA_TRAJ_tension);
    q->kappa0 = EA_TRAJ_AT(tr, i, EA_TRAJ_kappa0);
    return EA_OK;
  }
  int lo = 0, hi = n - 1; /* t in [t_lo, t_hi) */
  while (hi - lo > 1) {
    const int mid = lo + (hi - lo) / 2;
    if (EA_TRAJ_AT(tr, mid, EA_TRAJ_t) <= t)
      lo = mid;
    else
      hi = mid;
  }
  const double t0 = EA_TRAJ_AT(tr, lo, EA_TRAJ_t), h = EA_TRAJ_AT(tr, hi, EA_TRAJ_t) - t0;
  const double s = (t - t0) / h;
#define EA__Q(col, rate, acc, P, V, A)                                                             \
  ea__quintic(h, s, EA_TRAJ_AT(tr, lo, col), EA_TRAJ_AT(tr, lo, rate), EA_TRAJ_AT(tr, lo, acc),    \
              EA_TRAJ_AT(tr, hi, col), EA_TRAJ_AT(tr, hi, rate), EA_TRAJ_AT(tr, hi, acc), P, V, A)
  EA__Q(EA_TRAJ_cable_length, EA_TRAJ_cable_length_rate, EA_TRAJ_cable_length_acc, &q->cable_length,
        &q->cable_length_rate, &q->cable_length_acc);
  EA__Q(EA_TRAJ_base_angle, EA_TRAJ_base_angle_rate, EA_TRAJ_base_angle_acc, &q->base_angle,
        &q->base_angle_rate, &q->base_angle_acc);
#undef EA__Q
  ea__quintic(h, s, EA_TRAJ_AT(tr, lo, EA_TRAJ_theta0), EA_TRAJ_AT(tr, lo, EA_TRAJ_theta0_rate),
              ea__hermite_acc(tr, lo, EA_TRAJ_theta0, EA_TRAJ_theta0_rate),
              EA_TRAJ_AT(tr, hi, EA_TRAJ_theta0), EA_TRAJ_AT(tr, hi, EA_TRAJ_theta0_rate),
              ea__hermite_acc(tr, hi, EA_TRAJ_theta0, EA_TRAJ_theta0_rate), &q->theta0,
              &q->theta0_rate, &q->theta0_acc);
  q->tension =
      ea__cubic(h, s, EA_TRAJ_AT(tr, lo, EA_TRAJ_tension), ea__fd_monotone(tr, lo, EA_TRAJ_tension),
                EA_TRAJ_AT(tr, hi, EA_TRAJ_tension), ea__fd_monotone(tr, hi, EA_TRAJ_tension));
  q->kappa0 =
      ea__cubic(h, s, EA_TRAJ_AT(tr, lo, EA_TRAJ_kappa0), ea__fd_monotone(tr, lo, EA_TRAJ_kappa0),
                EA_TRAJ_AT(tr, hi, EA_TRAJ_kappa0), ea__fd_monotone(tr, hi, EA_TRAJ_kappa0));
  return EA_OK;
}

/* The joint state at plan time tp, played time_scale times slower, as a setpoint. */
static void ea__scaled_setpoint(const ea_traj_t *tr, const ea_arm_t *arm, double tp,
                                double time_scale, ea_setpoint_t *sp) {
  const double is = 1.0 / time_scale, is2 = is * is;
  ea_joint_state_t q;
  ea_stream_traj_eval(tr, tp, &q);
  q.cable_length_rate *= is;
  q.theta0_rate *= is;
  q.base_angle_rate *= is;
  q.cable_length_acc *= is2;
  q.theta0_acc *= is2;
  q.base_angle_acc *= is2;
  ea_stream_map(arm, &q, sp);
}

/* Points per sample interval at which the interpolant is checked besides the grid. */
enum { EA__INTERIOR_CHECKS = 8 };

/* The trajectory between its samples, before any resampling: every interval at least one
 * stream period long (played time_scale slower), so that no motion hides between two
 * setpoints, and the interpolant within the arm's limits at EA__INTERIOR_CHECKS interior
 * points of each interval. Names the rows (1 = the first data row). */
static ea_status_t ea__check_intervals(const ea_traj_t *tr, const ea_arm_t *arm, double rate_hz,
                                       double time_scale, double tol, ea_error_t *err) {
  const double period = 1.0 / rate_hz;
  for (int r = 0; r + 1 < tr->n; ++r) {
    const double ta = EA_TRAJ_AT(tr, r, EA_TRAJ_t), tb = EA_TRAJ_AT(tr, r + 1, EA_TRAJ_t);
    const double h = tb - ta;
    if (!(h * time_scale >= period * (1 - 1e-9)))
      return ea_error_set(err, EA_ERR_INADMISSIBLE,
                          "rows %d and %d (t = %.9g and %.9g s) are %.3g s apart%s, less than "
                          "the stream period %.3g s (%g Hz): a motion between them would not "
                          "be streamed; nothing sent",
                          r + 1, r + 2, ta, tb, h * time_scale,
                          time_scale != 1.0 ? " played slower" : "", period, rate_hz);
  }
  for (int r = 0; r + 1 < tr->n; ++r) { /* then the interpolant, which spans neighbours */
    const double ta = EA_TRAJ_AT(tr, r, EA_TRAJ_t), h = EA_TRAJ_AT(tr, r + 1, EA_TRAJ_t) - ta;
    for (int j = 1; j <= EA__INTERIOR_CHECKS; ++j) {
      const double tp = ta + h * j / (EA__INTERIOR_CHECKS + 1.0);
      ea_setpoint_t sp;
      ea__scaled_setpoint(tr, arm, tp, time_scale, &sp);
      ea_error_t e = {0};
      if (ea_stream_check_limits(arm, &sp, tol, &e))
        return ea_error_set(err, EA_ERR_INADMISSIBLE,
                            "between rows %d and %d, at t = %.6f s of the plan: %s; nothing sent",
                            r + 1, r + 2, tp, e.msg);
    }
  }
  return EA_OK;
}

ea_status_t ea_stream_resample_scaled(const ea_traj_t *tr, const ea_arm_t *arm, double rate_hz,
                                      double time_scale, double tol, ea_setpoint_t **out, int *n,
                                      ea_error_t *err) {
  if (!tr || !arm || !out || !n)
    return ea_error_set(err, EA_ERR_ARG, "stream resample: NULL argument");
  *out = NULL;
  *n = 0;
  if (!(rate_hz > 0) || rate_hz > 1e6 || !isfinite(rate_hz))
    return ea_error_set(err, EA_ERR_ARG, "rate %g Hz outside (0, 1e6]", rate_hz);
  if (!(time_scale >= 1.0) || time_scale > 1e3 || !isfinite(time_scale))
    return ea_error_set(err, EA_ERR_ARG, "time scale %g outside [1, 1000]", time_scale);
  if (tr->n < 1 || !tr->data) return ea_error_set(err, EA_ERR_INPUT, "trajectory has no samples");
  ea_status_t st = ea__check_intervals(tr, arm, rate_hz, time_scale, tol, err);
  if (st) return st;
  const double t0 = EA_TRAJ_AT(tr, 0, EA_TRAJ_t);
  const double dur = (EA_TRAJ_AT(tr, tr->n - 1, EA_TRAJ_t) - t0) * time_scale;
  const double nf = ceil(dur * rate_hz - 1e-9) + 1.0;
  if (!(nf >= 1) || nf > 5e7)
    return ea_error_set(err, EA_ERR_INPUT, "trajectory of %g s at %g Hz: too many setpoints", dur,
                        rate_hz);
  const int m = (int)nf;
  ea_setpoint_t *sp = malloc((size_t)m * sizeof *sp);
  if (!sp) return ea_error_set(err, EA_ERR_NOMEM, "stream resample: %d setpoints", m);
  for (int k = 0; k < m; ++k) {
    /* The k-th setpoint goes on the wire at k / rate (docs/protocol.md); the last one, at
     * or after the end, holds the end at rest. */
    const double t = k / rate_hz;
    ea__scaled_setpoint(tr, arm, t0 + t / time_scale, time_scale, &sp[k]);
    ea_error_t e = {0};
    if (ea_stream_check_limits(arm, &sp[k], tol, &e) != EA_OK) {
      free(sp);
      return ea_error_set(err, EA_ERR_INADMISSIBLE,
                          "setpoint %d at t = %.6f s (resampled at %g Hz%s): %s; nothing sent", k,
                          t, rate_hz, time_scale != 1.0 ? ", time-scaled" : "", e.msg);
    }
  }
  *out = sp;
  *n = m;
  return EA_OK;
}

ea_status_t ea_stream_resample(const ea_traj_t *tr, const ea_arm_t *arm, double rate_hz, double tol,
                               ea_setpoint_t **out, int *n, ea_error_t *err) {
  return ea_stream_resample_scaled(tr, arm, rate_hz, 1.0, tol, out, n, err);
}

ea_status_t ea_stream_min_time_scale(const ea_traj_t *tr, const ea_arm_t *arm, double rate_hz,
                                     double tol, double *scale, ea_error_t *err) {
  if (!tr || !arm || !scale || tr->n < 1 || !tr->data || !(rate_hz > 0))
    return ea_error_set(err, EA_ERR_ARG, "min time scale: bad argument");
  *scale = 1.0;
  /* Worst speed and acceleration ratios on a grid 4x finer than the rate. */
  const ea_actuators_t *a = &arm->act;
  const double t0 = EA_TRAJ_AT(tr, 0, EA_TRAJ_t), dur = EA_TRAJ_AT(tr, tr->n - 1, EA_TRAJ_t) - t0;
  const long m = (long)ceil(dur * rate_hz * 4) + 1;
  const long mi = (long)(tr->n - 1) * EA__INTERIOR_CHECKS; /* inside every interval too */
  double rv = 0, ra = 0, h_min = INFINITY;
  for (int r = 0; r + 1 < tr->n; ++r)
    h_min = fmin(h_min, EA_TRAJ_AT(tr, r + 1, EA_TRAJ_t) - EA_TRAJ_AT(tr, r, EA_TRAJ_t));
  for (long k = 0; k < m + mi && m < 200000000L; ++k) {
    ea_joint_state_t q;
    double t = t0 + fmin(k / (4 * rate_hz), dur);
    if (k >= m) {
      const long r = (k - m) / EA__INTERIOR_CHECKS, j = (k - m) % EA__INTERIOR_CHECKS + 1;
      const double ta = EA_TRAJ_AT(tr, r, EA_TRAJ_t), tb = EA_TRAJ_AT(tr, r + 1, EA_TRAJ_t);
      t = ta + (tb - ta) * j / (EA__INTERIOR_CHECKS + 1.0);
    }
    ea_stream_traj_eval(tr, t, &q);
    rv = fmax(rv, fmax(fabs(q.cable_length_rate) / a->cable_speed_max,
                       fmax(fabs(q.theta0_rate) / a->shoulder_speed_max,
                            fabs(q.base_angle_rate) / a->base_speed_max)));
    ra = fmax(ra, fmax(fabs(q.cable_length_acc) / a->cable_accel_max,
                       fmax(fabs(q.theta0_acc) / a->shoulder_accel_max,
                            fabs(q.base_angle_acc) / a->base_accel_max)));
  }
  /* every interval at least one stream period long once played slower */
  double s = fmax(fmax(1.0, fmax(rv, sqrt(ra))), h_min > 0 ? 1.0 / (rate_hz * h_min) : 1.0);
  if (!(s <= 1e3))
    return ea_error_set(err, EA_ERR_INADMISSIBLE,
                        "no time scale up to 1000 meets the limits (it would take %.3g: speed "
                        "%.3g, acceleration %.3g times its limit between the samples, or "
                        "samples %.3g s apart)",
                        s, rv, ra, h_min);
  /* Confirm on the actual grid; grow by 0.1 % while the check still fails on
   * speed or acceleration (the streamed grid differs from the fine grid). */
  for (int it = 0; it < 50; ++it) {
    ea_setpoint_t *sp = NULL;
    int n = 0;
    ea_error_t e = {0};
    const ea_status_t st = ea_stream_resample_scaled(tr, arm, rate_hz, s, tol, &sp, &n, &e);
    free(sp);
    if (st == EA_OK) {
      *scale = s;
      return EA_OK;
    }
    if (st != EA_ERR_INADMISSIBLE || !(strstr(e.msg, "speed") || strstr(e.msg, "acceleration"))) {
      if (err) *err = e;
      return st;
    }
    s *= 1.001;
  }
  return ea_error_set(err, EA_ERR_INADMISSIBLE, "no time scale up to %g meets the limits", s);
}

/* ---- Controlled stop ---------------------------------------------------------- */

typedef struct {
  double p0, v0, a0, amax;
} ea__axis_t;

/* Peak |acceleration| of the stop profile of one axis over duration T: the acceleration
 * a(s) = A s^2 + B s + C is a quadratic in s, so its extremes on [0, 1] are at the ends
 * and at the vertex (a sampled maximum misses a peak just after s = 0 when the axis
 * already brakes at its limit). */
static double ea__stop_peak_acc(const ea__axis_t *x, double T) {
  const double A = 6 * x->v0 / T + 3 * x->a0, B = -6 * x->v0 / T - 4 * x->a0, C = x->a0;
  double peak = fmax(fabs(C), fabs(A + B + C));
  if (A != 0) {
    const double s = -B / (2 * A);
    if (s > 0 && s < 1) peak = fmax(peak, fabs(C + s * (B + s * A)));
  }
  return peak;
}

static void ea__stop_eval(const ea__axis_t *x, double T, double s, double *p, double *v,
                          double *a) {
  const double s2 = s * s, s3 = s2 * s, s4 = s3 * s;
  *p = x->p0 +
       T * (x->v0 * (0.5 * s4 - s3 + s) + T * x->a0 * (0.25 * s4 - 2.0 / 3.0 * s3 + 0.5 * s2));
  *v = x->v0 * (2 * s3 - 3 * s2 + 1) + T * x->a0 * (s3 - 2 * s2 + s);
  *a = x->v0 * (6 * s2 - 6 * s) / T + x->a0 * (3 * s2 - 4 * s + 1);
}

int ea_stream_stop_ramp(const ea_arm_t *arm, const ea_setpoint_t *sp, double rate_hz, double margin,
                        ea_setpoint_t *out, int max) {
  const ea_actuators_t *ac = &arm->act;
  const double ks = ac->spool_gear_ratio / ac->spool_radius;
  ea__axis_t ax[3] = {
      {sp->spool_pos[0], sp->spool_vel[0], sp->spool_acc[0], ac->cable_accel_max * ks},
      {sp->shoulder_pos, sp->shoulder_vel, sp->shoulder_acc, ac->shoulder_accel_max},
      {sp->base_pos, sp->base_vel, sp->base_acc, ac->base_accel_max}};
  /* An axis still accelerating away from rest starts braking at once (its acceleration
   * steps to the ramp's): the ramp then never speeds an axis up, so it stays within any
   * speed limit the last setpoint met. */
  for (int i = 0; i < 3; ++i)
    if (ax[i].v0 * ax[i].a0 > 0) ax[i].a0 = 0.0;
  const double dt = 1.0 / rate_hz;
  /* Lower bound on T from the velocity term (peak |h00'| = 1.5), then step
   * up one period at a time until every axis is within its budget. */
  double T0 = dt;
  for (int i = 0; i < 3; ++i)
    if (ax[i].amax > 0)
      T0 = fmax(T0, 1.5 * fabs(ax[i].v0) / (margin * ax[i].amax + fabs(ax[i].a0)));
  long k = (long)ceil(T0 * rate_hz - 1e-9);
  if (k < 1) k = 1;
  for (;; ++k) {
    int ok = 1;
    for (int i = 0; i < 3 && ok; ++i) {
      const double budget = fmax(margin * ax[i].amax, fabs(ax[i].a0)) * (1 + 1e-12) + 1e-12;
      ok = ea__stop_peak_acc(&ax[i], k * dt) <= budget;
    }
    if (ok || k > max) break;
  }
  if (k > max) return -1;
  const double T = k * dt;
  for (long j = 1; j <= k; ++j) {
    const double s = (double)j / (double)k;
    ea_setpoint_t *o = &out[j - 1];
    *o = *sp;
    double p, v, a;
    ea__stop_eval(&ax[0], T, s, &p, &v, &a);
    o->spool_pos[0] = o->spool_pos[1] = p;
    o->spool_vel[0] = o->spool_vel[1] = (j == k) ? 0.0 : v;
    o->spool_acc[0] = o->spool_acc[1] = (j == k) ? 0.0 : a;
    ea__stop_eval(&ax[1], T, s, &o->shoulder_pos, &v, &a);
    o->shoulder_vel = (j == k) ? 0.0 : v;
    o->shoulder_acc = (j == k) ? 0.0 : a;
    ea__stop_eval(&ax[2], T, s, &o->base_pos, &v, &a);
    o->base_vel = (j == k) ? 0.0 : v;
    o->base_acc = (j == k) ? 0.0 : a;
  }
  return (int)k;
}
