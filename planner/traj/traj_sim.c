/* The FE transient of a trajectory (planner/ea_simulate.h): statics of the start,
 * FE equilibrium, continuation to the file's inputs, the driven transient, and the
 * residual vibration, tracking error and time to rest from the tip history. */
#include "ea_simulate.h"
#include "sim_impl.h"
#include "ea_util.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void ea_sim_settings_default(ea_sim_settings_t *s) {
  if (!s) return;
  memset(s, 0, sizeof *s);
  s->elements = EA_FE_DEFAULT_ELEMENTS;
  s->scheme = EA_FE_SCHEME_GENALPHA;
  s->dt = 1e-3;
  s->rho_inf = 0.9;
  s->settle = 3.0;
  s->damping_ratio = NAN; /* the arm's measured ratio of mode 1 (undamped without one) */
  s->rest_tolerance = 1e-3;
}

ea_status_t ea_sim_settings_validate(const ea_sim_settings_t *s, ea_error_t *err) {
  if (!s) return ea_error_set(err, EA_ERR_ARG, "simulate settings are NULL");
  if (s->elements < 1 || s->elements > 512)
    return ea_error_set(err, EA_ERR_ARG, "simulate: elements = %d: must be in [1, 512]",
                        s->elements);
  if (!(s->dt >= 1e-6 && s->dt <= 0.1))
    return ea_error_set(err, EA_ERR_ARG, "simulate: dt = %g s: must be in [1e-6, 0.1]", s->dt);
  if (!(s->settle >= 0.0 && s->settle <= 1e4))
    return ea_error_set(err, EA_ERR_ARG, "simulate: settle = %g s: must be in [0, 1e4]", s->settle);
  if (!isnan(s->damping_ratio) && !(s->damping_ratio >= 0.0 && s->damping_ratio <= 1.0))
    return ea_error_set(err, EA_ERR_ARG, "simulate: damping ratio = %g: must be in [0, 1]",
                        s->damping_ratio);
  if (!(s->rayleigh_mass >= 0.0) || !(s->rayleigh_stiffness >= 0.0) ||
      !isfinite(s->rayleigh_mass) || !isfinite(s->rayleigh_stiffness))
    return ea_error_set(err, EA_ERR_ARG, "simulate: Rayleigh coefficients must be finite, >= 0");
  if (s->damping_ratio > 0 && (s->rayleigh_mass > 0 || s->rayleigh_stiffness > 0))
    return ea_error_set(err, EA_ERR_ARG,
                        "simulate: give a damping ratio or Rayleigh "
                        "coefficients, not both");
  if (!(s->rest_tolerance > 0.0) || !isfinite(s->rest_tolerance))
    return ea_error_set(err, EA_ERR_ARG, "simulate: rest tolerance = %g m: must be > 0",
                        s->rest_tolerance);
  if (!(s->rho_inf >= 0.0 && s->rho_inf <= 1.0))
    return ea_error_set(err, EA_ERR_ARG, "simulate: rho_inf = %g: must be in [0, 1]", s->rho_inf);
  if ((int)s->scheme < 0 || s->scheme >= EA_FE_SCHEME_COUNT)
    return ea_error_set(err, EA_ERR_ARG, "simulate: unknown scheme %d", (int)s->scheme);
  if (!(s->max_wall_s >= 0.0) || !isfinite(s->max_wall_s))
    return ea_error_set(err, EA_ERR_ARG, "simulate: max_wall_s = %g s: must be finite, >= 0",
                        s->max_wall_s);
  return EA_OK;
}

void ea_sim_history_free(ea_sim_history_t *h) {
  if (!h) return;
  free(h->data);
  free(h->loads);
  h->data = h->loads = NULL;
  h->rows = 0;
}

/* The interval [lo, lo + 1] of samples holding t (t strictly inside the trajectory's span). */
static int ea__traj_interval(const ea_traj_t *tr, double t) {
  int lo = 0, hi = tr->n - 1;
  while (hi - lo > 1) {
    const int mid = (lo + hi) / 2;
    if (EA_TRAJ_AT(tr, mid, EA_TRAJ_t) <= t)
      lo = mid;
    else
      hi = mid;
  }
  return lo;
}

void ea_traj_planned_tip(const ea_traj_t *tr, const ea_arm_t *arm, double t, double xy[2]) {
  const int n = tr->n;
  double L, a;
  if (n == 1 || t <= EA_TRAJ_AT(tr, 0, EA_TRAJ_t)) {
    L = EA_TRAJ_AT(tr, 0, EA_TRAJ_cable_length);
    a = EA_TRAJ_AT(tr, 0, EA_TRAJ_cable_angle);
  } else if (t >= EA_TRAJ_AT(tr, n - 1, EA_TRAJ_t)) {
    L = EA_TRAJ_AT(tr, n - 1, EA_TRAJ_cable_length);
    a = EA_TRAJ_AT(tr, n - 1, EA_TRAJ_cable_angle);
  } else {
    const int lo = ea__traj_interval(tr, t), hi = lo + 1;
    const double t0 = EA_TRAJ_AT(tr, lo, EA_TRAJ_t), h = EA_TRAJ_AT(tr, hi, EA_TRAJ_t) - t0;
    const double s = (t - t0) / h, s2 = s * s, s3 = s2 * s;
    const double h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2,
                 h11 = s3 - s2;
    L = h00 * EA_TRAJ_AT(tr, lo, EA_TRAJ_cable_length) +
        h10 * h * EA_TRAJ_AT(tr, lo, EA_TRAJ_cable_length_rate) +
        h01 * EA_TRAJ_AT(tr, hi, EA_TRAJ_cable_length) +
        h11 * h * EA_TRAJ_AT(tr, hi, EA_TRAJ_cable_length_rate);
    a = h00 * EA_TRAJ_AT(tr, lo, EA_TRAJ_cable_angle) +
        h10 * h * EA_TRAJ_AT(tr, lo, EA_TRAJ_cable_angle_rate) +
        h01 * EA_TRAJ_AT(tr, hi, EA_TRAJ_cable_angle) +
        h11 * h * EA_TRAJ_AT(tr, hi, EA_TRAJ_cable_angle_rate);
  }
  xy[0] = arm->x_c + L * cos(a);
  xy[1] = arm->y_c + L * sin(a);
}

ea_status_t ea_traj_fill_statics(ea_traj_t *tr, ea_shooter_t *sh, ea_error_t *err) {
  if (!tr || !sh) return ea_error_set(err, EA_ERR_ARG, "fill statics: NULL argument");
  double guess[EA_NP];
  const ea_arm_t *arm = ea_shooter_arm(sh);
  for (int i = 0; i < tr->n; ++i) {
    const double L = EA_TRAJ_AT(tr, i, EA_TRAJ_cable_length),
                 a = EA_TRAJ_AT(tr, i, EA_TRAJ_cable_angle);
    ea_statics_problem_t pr = ea_statics_problem_cable(L, a);
    ea_statics_solution_t sol;
    ea_error_t e = {0};
    ea_status_t st = ea_statics_solve(sh, &pr, NULL, i ? guess : NULL, &sol, &e);
    if (st && i) st = ea_statics_solve(sh, &pr, NULL, NULL, &sol, &e);
    if (st)
      return ea_error_set(err, st,
                          "sample %d (t = %g s, L_c = %g m, alpha = %g rad): no static "
                          "solution: %s",
                          i + 1, EA_TRAJ_AT(tr, i, EA_TRAJ_t), L, a, e.msg);
    memcpy(guess, sol.p, sizeof guess);
    ea_traj_set_statics(tr, i, sol.p, sol.tip, arm->EI);
    EA_TRAJ_AT(tr, i, EA_TRAJ_theta0_rate) = NAN; /* not known: differences (the drive) */
  }
  return EA_OK;
}

/* Drive samples: theta0(t) and the cable parameter, from the file's columns (with their
 * rates) or, with drive_fe, re-solved by FE statics holding the planned tip (mh), in which
 * case the first sample's FE state is copied to qstart. */
static ea_status_t ea__sim_drive_fill(const ea_arm_t *arm, const ea_traj_t *tr,
                                      const ea_sim_settings_t *s, ea_shooter_t *sh,
                                      ea_fe_model_t *mh, const double *p0, double *qstart,
                                      ea__sim_drive_t *drv, ea_error_t *err) {
  const int n = tr->n;
  const double t_first = EA_TRAJ_AT(tr, 0, EA_TRAJ_t);
  double guess[EA_NP];
  memcpy(guess, p0, sizeof guess);
  for (int i = 0; i < n; ++i) {
    const double ti = EA_TRAJ_AT(tr, i, EA_TRAJ_t) - t_first;
    double T = EA_TRAJ_AT(tr, i, EA_TRAJ_tension), theta0 = EA_TRAJ_AT(tr, i, EA_TRAJ_theta0);
    double theta0_rate = EA_TRAJ_AT(tr, i, EA_TRAJ_theta0_rate);
    const double L = EA_TRAJ_AT(tr, i, EA_TRAJ_cable_length);
    if (s->drive_fe) {
      ea_statics_problem_t pi = ea_statics_problem_cable(L, EA_TRAJ_AT(tr, i, EA_TRAJ_cable_angle));
      ea_statics_solution_t ode;
      ea_fe_static_info_t fe;
      ea_error_t e = {0};
      ea_status_t st = ea_statics_solve(sh, &pi, NULL, guess, &ode, &e);
      if (st) st = ea_statics_solve(sh, &pi, NULL, NULL, &ode, &e);
      if (!st) {
        memcpy(guess, ode.p, sizeof guess);
        st = ea_fe_static_solve(mh, sh, &ode, &fe, &e);
      }
      if (st)
        return ea_error_set(err, st, "FE drive: sample %d (t = %g s): %s", i + 1, ti + t_first,
                            e.msg);
      T = fe.tension;
      theta0 = fe.theta0;
      theta0_rate = NAN; /* re-solved values: their rates by differences */
      if (i == 0 && (st = ea_fe_get_state(mh, qstart, NULL)))
        return ea_error_set(err, st, "FE drive: state");
    }
    ea_status_t st = ea__sim_drive_set(drv, arm, i, ti, L, T, theta0, err);
    if (st) return ea_error_set(err, st, "sample %d: %s", i + 1, err ? err->msg : "");
    ea__sim_drive_set_rates(drv, i, EA_TRAJ_AT(tr, i, EA_TRAJ_cable_length_rate), theta0_rate);
  }
  ea__sim_drive_finish(drv);
  return EA_OK;
}

/* Damping of the transient: explicit Rayleigh coefficients, or strain-rate damping
 * giving ratio zeta to the first mode of the start state (m at its start equilibrium). */
static ea_status_t ea__sim_damping(ea_fe_model_t *m, const ea_sim_settings_t *s,
                                   ea_fe_sim_settings_t *ss, ea_sim_info_t *info, ea_error_t *err) {
  ss->rayleigh_mass = s->rayleigh_mass;
  ss->rayleigh_stiffness = s->rayleigh_stiffness;
  if (!(s->damping_ratio > 0)) return EA_OK;
  /* strain-rate (Kelvin-Voigt) damping only: mass-proportional a M v acts on absolute
   * velocities and so brakes the commanded rigid rotation of the whole arm, which no
   * physical mechanism of the arm does; the strain rates are zero for rigid motion. The
   * higher modes get the ratios that material damping gives them (reported). */
  ea_fe_modes_info_t mi;
  ea_status_t st = ea_fe_modes(m, &mi, err);
  if (st || mi.modes < 1 || !(mi.lambda[0] > 0))
    return ea_error_set(err, st ? st : EA_ERR_UNSTABLE,
                        "a damping ratio needs a stable first mode at the start");
  info->start_freq_hz[0] = mi.freq_hz[0];
  info->start_freq_hz[1] = mi.modes > 1 ? mi.freq_hz[1] : NAN;
  if ((st = ea_fe_strain_damping(m, 0, s->damping_ratio, &ss->rayleigh_stiffness,
                                 info->modal_damping)) != EA_OK)
    return ea_error_set(err, st, "damping ratio: %s", ea_strerror(st));
  info->n_modal_damping = mi.modes;
  ss->rayleigh_mass = 0.0;
  return EA_OK;
}

/* Tracking error during the motion and the time to rest, from the tip rows (t from 0). */
static void ea__sim_measure(const ea_traj_t *tr, const ea_arm_t *arm, const double *tip, int cols,
                            int rows, double t_first, double tol, int have_static,
                            ea_sim_info_t *info) {
  info->max_tracking_error = 0.0;
  info->max_tracking_error_time = t_first;
  for (int r = 0; r < rows; ++r) {
    const double t = tip[cols * r];
    if (t > info->duration + 1e-9) break;
    double p[2];
    ea_traj_planned_tip(tr, arm, t + t_first, p);
    const double e = hypot(tip[cols * r + 1] - p[0], tip[cols * r + 2] - p[1]);
    if (e > info->max_tracking_error) {
      info->max_tracking_error = e;
      info->max_tracking_error_time = t + t_first;
    }
  }
  info->time_to_rest = NAN;
  if (!have_static || rows < 1) return;
  const double *xs = info->final_static_tip;
  int last_out = -1; /* last row outside the tolerance */
  for (int r = rows - 1; r >= 0; --r)
    if (hypot(tip[cols * r + 1] - xs[0], tip[cols * r + 2] - xs[1]) > tol) {
      last_out = r;
      break;
    }
  if (last_out < 0)
    info->time_to_rest = 0.0;
  else if (last_out < rows - 1)
    info->time_to_rest = tip[cols * (last_out + 1)];
}

static ea_status_t ea__traj_simulate(const ea_arm_t *arm, const ea_traj_t *tr, double tip_mass,
                                     const ea_sim_settings_t *s, ea_sim_history_t *hist,
                                     ea_sim_info_t *info, ea_error_t *err);

ea_status_t ea_traj_simulate(const ea_arm_t *arm, const ea_traj_t *tr, double tip_mass,
                             const ea_sim_settings_t *s, ea_sim_history_t *hist,
                             ea_sim_info_t *info, ea_error_t *err) {
  if (!arm || !s || !isnan(s->damping_ratio))
    return ea__traj_simulate(arm, tr, tip_mass, s, hist, info, err);
  /* damping ratio NAN: the arm file's measured ratio of mode 1, unless Rayleigh coefficients
   * are given */
  ea_sim_settings_t r = *s;
  r.damping_ratio = 0.0;
  if (arm->n_damping > 0 && !(s->rayleigh_mass > 0) && !(s->rayleigh_stiffness > 0))
    r.damping_ratio = arm->damping_ratio[0];
  return ea__traj_simulate(arm, tr, tip_mass, &r, hist, info, err);
}

/* What one trajectory simulation holds. */
typedef struct {
  const ea_arm_t *arm;
  const ea_traj_t *tr;
  const ea_sim_settings_t *s;
  double t_first, t_end;
  int rows_cap;
  int cols; /* doubles per tip row: 4, or 6 with the loads (history kept) */
  ea_shooter_t *sh;
  ea_fe_model_t *m, *mh; /* the transient's model; the tip-holding one of drive_fe */
  double *tip, *qstart;
  ea__sim_drive_t drv;
  double deadline; /* [s] monotonic clock at which the transient stops (INFINITY: never) */
} ea__sim_t;

/* Check the inputs; info's duration, tip mass and damping ratio. */
static ea_status_t ea__sim_check(const ea_arm_t *arm, const ea_traj_t *tr, double tip_mass,
                                 const ea_sim_settings_t *s, ea_sim_info_t *info, ea_error_t *err) {
  ea_status_t st = ea_sim_settings_validate(s, err);
  if (!st) st = ea_arm_validate(arm, err);
  if (st) return st;
  if (tr->n < 1 || !tr->data) return ea_error_set(err, EA_ERR_INPUT, "simulate: no samples");
  info->duration = EA_TRAJ_AT(tr, tr->n - 1, EA_TRAJ_t) - EA_TRAJ_AT(tr, 0, EA_TRAJ_t);
  const double t_end = info->duration + s->settle;
  if (!(t_end > 0))
    return ea_error_set(err, EA_ERR_ARG,
                        "simulate: nothing to simulate (one sample and no settling time)");
  if (t_end / s->dt > 2e7)
    return ea_error_set(err, EA_ERR_ARG, "simulate: %.3g s at dt %g s is more than 2e7 steps",
                        t_end, s->dt);
  info->tip_mass = tip_mass > 0 ? tip_mass : ea_arm_tip_mass(arm, fmax(tr->payload_kg, 0.0));
  info->damping_ratio = s->damping_ratio;
  return EA_OK;
}

/* The shooter and FE models for this arm and tip mass, and the tip rows. */
static ea_status_t ea__sim_alloc(ea__sim_t *c, double tip_mass, ea_error_t *err) {
  ea_fe_settings_t fs;
  ea_fe_settings_default(&fs);
  fs.elements = c->s->elements;
  fs.modes = 3;
  const ea_load_t load = {tip_mass};
  ea_status_t st;
  if ((st = ea_shooter_alloc(c->arm, NULL, &c->sh, err))) return st;
  ea_shooter_set_load(c->sh, &load);
  if ((st = ea_fe_model_alloc(c->arm, &fs, &c->m, err)) || (st = ea_fe_model_set_load(c->m, &load)))
    return st;
  if (c->s->drive_fe) {
    fs.static_hold_tip = 1;
    if ((st = ea_fe_model_alloc(c->arm, &fs, &c->mh, err)) ||
        (st = ea_fe_model_set_load(c->mh, &load)))
      return st;
  }
  c->tip = malloc(sizeof(double) * (size_t)c->cols * (size_t)c->rows_cap);
  c->qstart = malloc(sizeof(double) * 3 * (size_t)ea_fe_model_nodes(c->m));
  if (!c->tip || !c->qstart)
    return ea_error_set(err, EA_ERR_NOMEM, "simulate: %d rows", c->rows_cap);
  return EA_OK;
}

/* 1. Statics of the start for this arm and load, warm-started from row 0. */
static ea_status_t ea__sim_start_statics(ea__sim_t *c, ea_statics_solution_t *ode,
                                         ea_sim_info_t *info, ea_error_t *err) {
  const ea_traj_t *tr = c->tr;
  const double L_0 = EA_TRAJ_AT(tr, 0, EA_TRAJ_cable_length),
               a_0 = EA_TRAJ_AT(tr, 0, EA_TRAJ_cable_angle);
  ea_statics_problem_t pr = ea_statics_problem_cable(L_0, a_0);
  const double g0[EA_NP] = {a_0, EA_TRAJ_AT(tr, 0, EA_TRAJ_tension),
                            EA_TRAJ_AT(tr, 0, EA_TRAJ_theta0), EA_TRAJ_AT(tr, 0, EA_TRAJ_kappa0)};
  ea_error_t e = {0};
  ea_status_t st = ea_statics_solve(c->sh, &pr, NULL, g0, ode, &e);
  if (st) st = ea_statics_solve(c->sh, &pr, NULL, NULL, ode, &e);
  if (st)
    return ea_error_set(err, EA_ERR_INADMISSIBLE,
                        "the start (L_c = %g m, alpha = %g rad) has no static solution for this "
                        "arm and tip mass %g kg: %s",
                        L_0, a_0, info->tip_mass, e.msg);
  info->start_tension_mismatch = fabs(ode->p[EA_P_TENSION] - g0[1]);
  info->start_theta0_mismatch = fabs(ode->p[EA_P_THETA0] - g0[2]);
  return EA_OK;
}

/* 3a. The final equilibrium's tip: the goal's statics for this arm and load, continued to the
 * drive's held inputs (a Newton from the vibrating state at the end of the motion can miss it
 * with a stiff cable). */
static ea_status_t ea__sim_final_eq(ea__sim_t *c, double tip_end[2], ea_error_t *err) {
  const ea_traj_t *tr = c->tr;
  const int l = tr->n - 1;
  ea_statics_problem_t pe = ea_statics_problem_cable(EA_TRAJ_AT(tr, l, EA_TRAJ_cable_length),
                                                     EA_TRAJ_AT(tr, l, EA_TRAJ_cable_angle));
  const double ge[EA_NP] = {EA_TRAJ_AT(tr, l, EA_TRAJ_cable_angle),
                            EA_TRAJ_AT(tr, l, EA_TRAJ_tension), EA_TRAJ_AT(tr, l, EA_TRAJ_theta0),
                            EA_TRAJ_AT(tr, l, EA_TRAJ_kappa0)};
  ea_statics_solution_t ode_e;
  ea_fe_static_info_t fei;
  ea_error_t e = {0};
  ea_status_t st = ea_statics_solve(c->sh, &pe, NULL, ge, &ode_e, &e);
  if (st) st = ea_statics_solve(c->sh, &pe, NULL, NULL, &ode_e, &e);
  if (!st) st = ea_fe_static_solve(c->m, c->sh, &ode_e, &fei, &e);
  if (!st)
    st = ea_fe_static_continue(c->m, c->drv.theta0[l],
                               c->s->cable_active ? EA_FE_CABLE_ACTIVE : EA_FE_CABLE_PASSIVE,
                               c->drv.cable[l], &fei, &e);
  if (st) return ea_error_set(err, st, "the final equilibrium (goal of the trajectory): %s", e.msg);
  double te[3];
  ea_fe_tip(c->m, te);
  tip_end[0] = te[0];
  tip_end[1] = te[1];
  return EA_OK;
}

/* 3b. The FE equilibrium of the start, continued to the drive's start inputs. */
static ea_status_t ea__sim_start_eq(ea__sim_t *c, const ea_statics_solution_t *ode,
                                    ea_sim_info_t *info, ea_error_t *err) {
  ea_fe_static_info_t fsi;
  ea_error_t e = {0};
  ea_status_t st = ea_fe_static_solve(c->m, c->sh, ode, &fsi, &e);
  if (st) return ea_error_set(err, st, "FE static solve at the start: %s", e.msg);
  st = ea__sim_drive_start(c->m, &c->drv, c->s->drive_fe ? c->qstart : NULL, &fsi, &e);
  if (st) return ea_error_set(err, st, "FE equilibrium under the start inputs: %s", e.msg);
  info->start_newton_iterations = fsi.iterations;
  info->start_tension = fsi.tension;
  double plan0[2], tip0[3];
  ea_traj_planned_tip(c->tr, c->arm, c->t_first, plan0);
  ea_fe_tip(c->m, tip0);
  info->static_offset_start = hypot(tip0[0] - plan0[0], tip0[1] - plan0[1]);
  return EA_OK;
}

/* The shoulder drive as the transient asks for it (a few times a step): the hooks on its
 * way, the wall-time cap (stop when the monotonic clock passes deadline) and the settings'
 * progress callback (every 1 % of the simulated time). */
typedef struct {
  ea_fe_history_fn fn;
  void *data;
  const ea_sim_settings_t *s;
  double deadline, t; /* [s] the cap (INFINITY: none); the last drive time asked for */
  double t_end, next; /* [s] the simulated span; the next progress report */
  int calls;
} ea__sim_hook_t;

static int ea__sim_hook(double t, double *value, double *rate, void *data) {
  ea__sim_hook_t *h = data;
  h->t = t;
  if (isfinite(h->deadline) && (++h->calls & 15) == 0 && ea__mono_s() > h->deadline) return 1;
  if (h->s->progress && t >= h->next) {
    h->s->progress(h->s->progress_data, t, h->t_end);
    h->next = t + 0.01 * h->t_end;
  }
  return h->fn(t, value, rate, h->data);
}

/* 4. damping, 5. the transient; what it found into info. */
static ea_status_t ea__sim_run(ea__sim_t *c, const double tip_end[2], ea_fe_sim_info_t *si,
                               ea_sim_info_t *info, ea_error_t *err) {
  const ea_sim_settings_t *s = c->s;
  ea_fe_sim_settings_t ss;
  ea_fe_sim_settings_default(&ss);
  ss.scheme = s->scheme;
  ss.rho_inf = s->rho_inf;
  ss.dt = s->dt;
  ss.t_end = c->t_end;
  ss.t_motion_end = s->settle > 0 ? info->duration : -1.0;
  ss.tip_static[0] = tip_end[0];
  ss.tip_static[1] = tip_end[1];
  ss.output_loads = c->cols == 6;
  ea_status_t st = ea__sim_damping(c->m, s, &ss, info, err);
  if (st) return st;
  info->rayleigh_mass = ss.rayleigh_mass;
  info->rayleigh_stiffness = ss.rayleigh_stiffness;
  ea_fe_drive_t drive = c->drv.drive;
  ea__sim_hook_t hk = {drive.theta0, drive.theta0_data, s, c->deadline, 0.0, c->t_end, 0.0, 0};
  if ((isfinite(c->deadline) || s->progress) && drive.theta0) {
    drive.theta0 = ea__sim_hook;
    drive.theta0_data = &hk;
  }
  st = ea_fe_simulate(c->m, &drive, &ss, c->tip, c->rows_cap, si, err);
  if (st == EA_ERR_INTERRUPTED && isfinite(c->deadline) && ea__mono_s() > c->deadline)
    ea_error_set(err, st,
                 "simulate: stopped at its wall-time cap of %g s at t = %.4g s of %.4g s "
                 "(dt %g s, %d steps)",
                 s->max_wall_s, hk.t, c->t_end, s->dt, si->steps);
  if (s->progress && !st) s->progress(s->progress_data, c->t_end, c->t_end);
  info->steps = si->steps;
  info->simulated_time = si->steps * s->dt;
  info->newton_iterations = si->newton_iterations;
  info->max_step_iterations = si->max_step_iterations;
  info->energy_start = si->energy_start;
  info->energy_end = si->energy_end;
  info->energy_drift_max = si->energy_drift_max;
  info->kinetic_max = si->kinetic_max;
  info->tension_min = si->tension_min;
  info->tension_max = si->tension_max;
  info->tension_min_time = si->tension_min_time;
  info->tension_max_time = si->tension_max_time;
  if (st) return st;
  const int have_static = s->settle > 0;
  if (have_static) {
    info->residual_rms = si->residual_rms;
    info->residual_peak = si->residual_peak;
    memcpy(info->final_static_tip, si->tip_static, 2 * sizeof(double));
    double pe[2];
    ea_traj_planned_tip(c->tr, c->arm, c->t_first + info->duration, pe);
    info->static_offset_end = hypot(si->tip_static[0] - pe[0], si->tip_static[1] - pe[1]);
  }
  ea__sim_measure(c->tr, c->arm, c->tip, c->cols, si->rows, c->t_first, s->rest_tolerance,
                  have_static, info);
  return EA_OK;
}

/* The tip history (t, FE tip x, y, theta, planned tip x, y) into hist. */
static ea_status_t ea__sim_history(const ea__sim_t *c, int rows, ea_sim_history_t *hist,
                                   ea_error_t *err) {
  double *h = malloc(sizeof(double) * 6 * (size_t)(rows > 0 ? rows : 1));
  double *ld = malloc(sizeof(double) * 2 * (size_t)(rows > 0 ? rows : 1));
  if (!h || !ld) {
    free(h);
    free(ld);
    return ea_error_set(err, EA_ERR_NOMEM, "simulate: history of %d rows", rows);
  }
  const int cols = c->cols;
  for (int r = 0; r < rows; ++r) {
    double *o = h + 6 * r;
    o[0] = c->tip[cols * r] + c->t_first;
    memcpy(o + 1, c->tip + cols * r + 1, 3 * sizeof(double));
    ea_traj_planned_tip(c->tr, c->arm, o[0], o + 4);
    ld[2 * r] = cols == 6 ? c->tip[cols * r + 4] : NAN;
    ld[2 * r + 1] = cols == 6 ? c->tip[cols * r + 5] : NAN;
  }
  ea_sim_history_free(hist);
  hist->data = h;
  hist->loads = ld;
  hist->rows = rows;
  return EA_OK;
}

static ea_status_t ea__traj_simulate(const ea_arm_t *arm, const ea_traj_t *tr, double tip_mass,
                                     const ea_sim_settings_t *s, ea_sim_history_t *hist,
                                     ea_sim_info_t *info, ea_error_t *err) {
  ea_sim_info_t loc;
  if (!info) info = &loc;
  memset(info, 0, sizeof *info);
  info->time_to_rest = info->residual_rms = info->residual_peak = NAN;
  info->static_offset_end = info->start_freq_hz[0] = info->start_freq_hz[1] = NAN;
  info->tension_min = info->tension_max = NAN;
  if (!arm || !tr || !s) return info->status = ea_error_set(err, EA_ERR_ARG, "simulate: NULL");
  ea_status_t st = ea__sim_check(arm, tr, tip_mass, s, info, err);
  if (st) return info->status = st;
  const double wall0 = ea__mono_s();
  ea__sim_t c = {0};
  c.arm = arm;
  c.tr = tr;
  c.s = s;
  c.t_first = EA_TRAJ_AT(tr, 0, EA_TRAJ_t);
  c.t_end = info->duration + s->settle;
  c.rows_cap = (int)ceil(c.t_end / s->dt - 1e-9) + 2;
  c.cols = (s->keep_history && hist) ? 6 : 4;
  c.deadline = s->max_wall_s > 0 ? wall0 + s->max_wall_s : INFINITY;
  ea_statics_solution_t ode;
  double tip_end[2] = {NAN, NAN};
  ea_fe_sim_info_t si;
  if ((st = ea__sim_alloc(&c, info->tip_mass, err))) goto done;
  if ((st = ea__sim_start_statics(&c, &ode, info, err))) goto done;
  /* 2. drive */
  if ((st = ea__sim_drive_alloc(&c.drv, tr->n, s->cable_active, err))) goto done;
  if ((st = ea__sim_drive_fill(arm, tr, s, c.sh, c.mh, ode.p, c.qstart, &c.drv, err))) goto done;
  /* 3. the final equilibrium, then the FE equilibrium of the start */
  if (s->settle > 0 && (st = ea__sim_final_eq(&c, tip_end, err))) goto done;
  if ((st = ea__sim_start_eq(&c, &ode, info, err))) goto done;
  if ((st = ea__sim_run(&c, tip_end, &si, info, err))) goto done;
  if (s->keep_history && hist) st = ea__sim_history(&c, si.rows, hist, err);
done:
  info->wall_time_s = ea__mono_s() - wall0;
  info->status = st;
  free(c.qstart);
  ea__sim_drive_free(&c.drv);
  free(c.tip);
  ea_fe_model_free(c.mh);
  ea_fe_model_free(c.m);
  ea_shooter_free(c.sh);
  return st;
}

void ea__traj_hermite(const ea_traj_t *tr, int c, int cr, double t, double *q, double *v,
                      double *a) {
  const int n = tr->n;
  if (n == 1 || t <= EA_TRAJ_AT(tr, 0, EA_TRAJ_t) || t >= EA_TRAJ_AT(tr, n - 1, EA_TRAJ_t)) {
    const int i = (n == 1 || t <= EA_TRAJ_AT(tr, 0, EA_TRAJ_t)) ? 0 : n - 1;
    *q = EA_TRAJ_AT(tr, i, c);
    *v = *a = 0.0;
    return;
  }
  const int lo = ea__traj_interval(tr, t), hi = lo + 1;
  const double t0 = EA_TRAJ_AT(tr, lo, EA_TRAJ_t), h = EA_TRAJ_AT(tr, hi, EA_TRAJ_t) - t0;
  const double s = (t - t0) / h, s2 = s * s, s3 = s2 * s;
  const double y0 = EA_TRAJ_AT(tr, lo, c), y1 = EA_TRAJ_AT(tr, hi, c);
  const double m0 = EA_TRAJ_AT(tr, lo, cr) * h, m1 = EA_TRAJ_AT(tr, hi, cr) * h;
  *q = (2 * s3 - 3 * s2 + 1) * y0 + (s3 - 2 * s2 + s) * m0 + (-2 * s3 + 3 * s2) * y1 +
       (s3 - s2) * m1;
  *v = ((6 * s2 - 6 * s) * y0 + (3 * s2 - 4 * s + 1) * m0 + (-6 * s2 + 6 * s) * y1 +
        (3 * s2 - 2 * s) * m1) /
       h;
  *a = ((12 * s - 6) * y0 + (6 * s - 4) * m0 + (-12 * s + 6) * y1 + (6 * s - 2) * m1) / (h * h);
}

void ea__traj_actuators(const ea_traj_t *tr, double t, double q[2], double v[2], double a[2]) {
  const double ta = t + EA_TRAJ_AT(tr, 0, EA_TRAJ_t);
  ea__traj_hermite(tr, EA_TRAJ_cable_length, EA_TRAJ_cable_length_rate, ta, &q[0], &v[0], &a[0]);
  ea__traj_hermite(tr, EA_TRAJ_cable_angle, EA_TRAJ_cable_angle_rate, ta, &q[1], &v[1], &a[1]);
}

/* Modal right-hand side along the trajectory at time t (from the first sample). */
static void ea__rom_rhs(const ea_rom_table_t *tb, const ea_traj_t *tr, int K, double t,
                        const double *z, double *dz, double tip[2], double *dT) {
  double q[2], v[2], a[2];
  ea__traj_actuators(tr, t, q, v, a);
  ea_rom_point_t p;
  ea_rom_table_eval(tb, q[0], q[1], &p, NULL, NULL);
  if (tip) tip[0] = tip[1] = 0.0;
  if (dT) *dT = 0.0;
  for (int k = 0; k < K; ++k) {
    const double F =
        -(p.B[k][0] * a[0] + p.B[k][1] * a[1]) -
        (p.C[k][0] * v[0] * v[0] + 2 * p.C[k][1] * v[0] * v[1] + p.C[k][2] * v[1] * v[1]);
    dz[2 * k] = z[2 * k + 1];
    dz[2 * k + 1] = -p.omega2[k] * z[2 * k] + F;
    if (tip) {
      tip[0] += p.tip[k][0] * z[2 * k];
      tip[1] += p.tip[k][1] * z[2 * k];
    }
    if (dT) *dT += p.dtension[k] * z[2 * k];
  }
}

/* The end of a prediction: the modal state z (2 K) at the end of tr into out, and the peak of
 * its free vibration at the goal over settle [s]: exact superposition of the modes, sampled
 * finely. */
void ea__rom_settle(const ea_rom_table_t *tb, const ea_traj_t *tr, int K, const double *z,
                    double settle, ea_rom_prediction_t *out) {
  ea_rom_point_t p;
  const int last = tr->n - 1;
  ea_rom_table_eval(tb, EA_TRAJ_AT(tr, last, EA_TRAJ_cable_length),
                    EA_TRAJ_AT(tr, last, EA_TRAJ_cable_angle), &p, NULL, NULL);
  for (int k = 0; k < K; ++k) {
    const double w = sqrt(fmax(p.omega2[k], 1e-300));
    out->eta[k] = z[2 * k];
    out->eta_rate[k] = z[2 * k + 1];
    out->amplitude_m[k] = hypot(z[2 * k], z[2 * k + 1] / w) * hypot(p.tip[k][0], p.tip[k][1]);
  }
  const double w1 = sqrt(fmax(p.omega2[K - 1], 1e-300));
  const int ns = (int)ceil(settle * w1 / (2 * M_PI) * 64) + 1;
  for (int i = 0; i <= ns; ++i) {
    const double t = settle * i / (ns > 0 ? ns : 1);
    double dx = 0, dy = 0;
    for (int k = 0; k < K; ++k) {
      const double w = sqrt(fmax(p.omega2[k], 1e-300));
      const double e = z[2 * k] * cos(w * t) + z[2 * k + 1] / w * sin(w * t);
      dx += p.tip[k][0] * e;
      dy += p.tip[k][1] * e;
    }
    out->residual_peak = fmax(out->residual_peak, hypot(dx, dy));
  }
}

ea_status_t ea_traj_rom_predict(const ea_rom_table_t *tb, const ea_traj_t *tr, double dt,
                                double settle, ea_rom_prediction_t *out, ea_error_t *err) {
  if (!tb || !tr || !out || tr->n < 1 || !(dt > 0) || !(settle >= 0))
    return ea_error_set(err, EA_ERR_ARG, "reduced-model prediction: bad argument");
  memset(out, 0, sizeof *out);
  ea_rom_table_info_t ti;
  ea_rom_table_info(tb, &ti);
  const int K = ti.modes;
  out->modes = K;
  const double T = EA_TRAJ_AT(tr, tr->n - 1, EA_TRAJ_t) - EA_TRAJ_AT(tr, 0, EA_TRAJ_t);
  const int n = (int)ceil(T / dt - 1e-9);
  const double h = n > 0 ? T / n : 0.0;
  double z[2 * EA_ROM_MAX_MODES] = {0}, k1[2 * EA_ROM_MAX_MODES], k2[2 * EA_ROM_MAX_MODES],
               k3[2 * EA_ROM_MAX_MODES], k4[2 * EA_ROM_MAX_MODES], zt[2 * EA_ROM_MAX_MODES];
  for (int i = 0; i < n; ++i) {
    const double t = i * h;
    double tip[2], dT;
    ea__rom_rhs(tb, tr, K, t, z, k1, tip, &dT);
    out->max_deviation = fmax(out->max_deviation, hypot(tip[0], tip[1]));
    out->min_tension_change = fmin(out->min_tension_change, dT);
    for (int j = 0; j < 2 * K; ++j)
      zt[j] = z[j] + 0.5 * h * k1[j];
    ea__rom_rhs(tb, tr, K, t + 0.5 * h, zt, k2, NULL, NULL);
    for (int j = 0; j < 2 * K; ++j)
      zt[j] = z[j] + 0.5 * h * k2[j];
    ea__rom_rhs(tb, tr, K, t + 0.5 * h, zt, k3, NULL, NULL);
    for (int j = 0; j < 2 * K; ++j)
      zt[j] = z[j] + h * k3[j];
    ea__rom_rhs(tb, tr, K, t + h, zt, k4, NULL, NULL);
    for (int j = 0; j < 2 * K; ++j)
      z[j] += h / 6 * (k1[j] + 2 * k2[j] + 2 * k3[j] + k4[j]);
  }
  ea__rom_settle(tb, tr, K, z, settle, out);
  return EA_OK;
}
