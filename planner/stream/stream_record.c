/* Measurement records of a simulated session (ea_stream.h, docs/calibration.md): the holds
 * found in the accepted setpoints, the FE history's loads and tip with sensor noise. */
#include "ea_simulate.h"
#include "ea_stream.h"
#include "ea_util.h"

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

void ea_record_settings_default(ea_record_settings_t *s) {
  memset(s, 0, sizeof *s);
  s->min_hold_s = 1.0;
  s->static_fraction = 1.0 / 3.0;
  s->seed = 1;
  s->noise_theta0_rad = 5e-4;
  s->noise_torque_Nm = 0.01;
  s->noise_tension_N = 0.05;
  s->noise_tip_m = 5e-4;
  snprintf(s->source, sizeof s->source, "controller-sim --simulate");
}

/* At rest and at the position of r: every velocity and acceleration within 1e-9 of 0, every
 * position within 1e-9 rad of r's. */
static int ea__rest_at(const ea_setpoint_t *p, const ea_setpoint_t *r) {
  const double tol = 1e-9;
  const double v[] = {p->spool_vel[0], p->spool_acc[0], p->shoulder_vel,
                      p->shoulder_acc, p->base_vel,     p->base_acc};
  for (size_t i = 0; i < sizeof v / sizeof *v; ++i)
    if (!(fabs(v[i]) <= tol)) return 0;
  return fabs(p->spool_pos[0] - r->spool_pos[0]) <= tol &&
         fabs(p->shoulder_pos - r->shoulder_pos) <= tol && fabs(p->base_pos - r->base_pos) <= tol;
}

ea_status_t ea_record_find_holds(const ea_arm_t *arm, const ea_setpoint_t *sp, const double *t,
                                 int n, double min_hold_s, double t_last, ea_record_hold_t **holds,
                                 int *n_holds, ea_error_t *err) {
  if (!arm || !sp || !t || !holds || !n_holds || n < 0)
    return ea_error_set(err, EA_ERR_ARG, "records: NULL argument");
  *holds = NULL;
  *n_holds = 0;
  int cap = 0, nh = 0;
  ea_record_hold_t *H = NULL;
  int i = 0, prev = -1; /* prev: the last row kept (time increasing) */
  while (i < n) {
    if (prev >= 0 && !(t[i] > t[prev])) { /* left out, as ea_stream_setpoints_traj does */
      ++i;
      continue;
    }
    if (!ea__rest_at(&sp[i], &sp[i])) {
      prev = i++;
      continue;
    }
    const int first = i;
    int last = i;
    prev = i++;
    for (; i < n; ++i) {
      if (!(t[i] > t[prev])) continue;
      if (!ea__rest_at(&sp[i], &sp[first])) break;
      last = prev = i;
    }
    const double t_end = (i >= n && t_last > t[last]) ? t_last : t[last];
    if (t_end - t[first] < min_hold_s) continue;
    if (nh == cap) {
      cap = cap ? 2 * cap : 16;
      ea_record_hold_t *nH = realloc(H, sizeof *H * (size_t)cap);
      if (!nH) {
        free(H);
        return ea_error_set(err, EA_ERR_NOMEM, "records: %d holds", cap);
      }
      H = nH;
    }
    ea_record_hold_t *h = &H[nh++];
    ea_joint_state_t q;
    ea_stream_unmap(arm, &sp[first], &q);
    h->first = first;
    h->last = last;
    h->t_start = t[first];
    h->t_end = t_end;
    h->cable_length = q.cable_length;
    h->theta0 = sp[first].shoulder_pos;
    h->ringdown = first > 0;
  }
  *holds = H;
  *n_holds = nh;
  return EA_OK;
}

/* '# key: value' noise header when the level is positive. */
static void ea__noise_hdr(FILE *fp, const char *key, double v) {
  if (v > 0) fprintf(fp, "# %s: %.9g\n", key, v);
}

static void ea__common_hdr(FILE *fp, const char *kind, const ea_record_settings_t *s) {
  fprintf(fp, "# elasticarm-record 1\n# kind: %s\n", kind);
  if (s->arm_file[0]) fprintf(fp, "# arm_file: %s\n", s->arm_file);
  fprintf(fp, "# source: %s (noise seed %lu)\n", s->source, s->seed);
  fprintf(fp, "# payload_kg: %.9g\n", s->payload_kg);
}

/* The history rows [*r0, *r1) of times within [a - eps, b + eps]. */
static void ea__rows_in(const ea_sim_history_t *h, double a, double b, int *r0, int *r1) {
  const double eps = 1e-9;
  int lo = 0;
  while (lo < h->rows && h->data[6 * lo] < a - eps)
    ++lo;
  int hi = lo;
  while (hi < h->rows && h->data[6 * hi] <= b + eps)
    ++hi;
  *r0 = lo;
  *r1 = hi;
}

/* Sensed values of history row r: theta0, torque, tension, tip x, tip y (noise drawn in this
 * order). */
static void ea__sense(gsl_rng *rng, const ea_record_settings_t *s, const ea_sim_history_t *h, int r,
                      double theta0, double v[5]) {
  const double sd[5] = {s->noise_theta0_rad, s->noise_torque_Nm, s->noise_tension_N, s->noise_tip_m,
                        s->noise_tip_m};
  const double x[5] = {theta0, h->loads[2 * r], h->loads[2 * r + 1], h->data[6 * r + 1],
                       h->data[6 * r + 2]};
  for (int k = 0; k < 5; ++k)
    v[k] = x[k] + (sd[k] > 0 ? gsl_ran_gaussian(rng, sd[k]) : 0.0);
}

/* One hold: its ring-down record (when it has one) and its static row (means into m). */
static ea_status_t ea__record_hold(const char *dir, const ea_record_settings_t *s,
                                   const ea_sim_history_t *h, const ea_record_hold_t *hd, int k,
                                   int n_avg, gsl_rng *rng, double m[5], int *ringdowns,
                                   ea_error_t *err) {
  int r0, r1;
  ea__rows_in(h, hd->t_start, hd->t_end, &r0, &r1);
  if (r1 - r0 < n_avg)
    return ea_error_set(err, EA_ERR_INPUT,
                        "records: hold %d (t = %g..%g s) has %d samples of the FE history, "
                        "fewer than the %d averaged",
                        k + 1, hd->t_start, hd->t_end, r1 - r0, n_avg);
  ea_afile_t af = {0};
  char path[1100];
  ea_status_t st = EA_OK;
  if (hd->ringdown) {
    snprintf(path, sizeof path, "%s/ringdown-%03d.csv", dir, k + 1);
    if ((st = ea_afile_open(&af, path, err))) return st;
    ea__common_hdr(af.fp, "ringdown", s);
    fprintf(af.fp, "# cable_length_m: %.12g\n# theta0_rad: %.12g\n", hd->cable_length, hd->theta0);
    ea__noise_hdr(af.fp, "noise_torque_Nm", s->noise_torque_Nm);
    ea__noise_hdr(af.fp, "noise_tension_N", s->noise_tension_N);
    ea__noise_hdr(af.fp, "noise_tip_m", s->noise_tip_m);
    fprintf(af.fp, "# hold_start_s: %.9g\n", hd->t_start);
    fprintf(af.fp, "t_s,shoulder_torque_Nm,tension_N,tip_x_m,tip_y_m\n");
  }
  for (int k5 = 0; k5 < 5; ++k5)
    m[k5] = 0.0;
  const double dt = h->rows > 1 ? h->data[6] - h->data[0] : 0.0;
  /* the first sample's offset from the hold's start: 0 up to rounding (both on the grid) */
  const double off = round((h->data[6 * r0] - hd->t_start) * 1e9) * 1e-9;
  for (int r = r0; r < r1; ++r) {
    double v[5];
    ea__sense(rng, s, h, r, hd->theta0, v);
    if (hd->ringdown) /* t_s from the sample index: a constant rate without rounding drift */
      fprintf(af.fp, "%.9g,%.10g,%.10g,%.10g,%.10g\n", off + (r - r0) * dt, v[1], v[2], v[3], v[4]);
    if (r >= r1 - n_avg)
      for (int k5 = 0; k5 < 5; ++k5)
        m[k5] += v[k5] / n_avg;
  }
  if (hd->ringdown) {
    st = ea_afile_commit(&af, err);
    ea_afile_abort(&af);
    if (!st) ++*ringdowns;
  }
  return st;
}

ea_status_t ea_record_write(const char *dir, const ea_record_settings_t *s, const ea_arm_t *arm,
                            const ea_setpoint_t *sp, const double *t, int n,
                            const ea_sim_history_t *h, ea_record_info_t *info, ea_error_t *err) {
  ea_record_info_t loc;
  if (!info) info = &loc;
  memset(info, 0, sizeof *info);
  if (!dir || !s || !arm || !sp || !t || !h || !h->data || !h->loads || h->rows < 2)
    return ea_error_set(err, EA_ERR_ARG, "records: NULL argument or no FE history with loads");
  if (!(s->static_fraction > 0 && s->static_fraction <= 1) || !(s->min_hold_s > 0))
    return ea_error_set(err, EA_ERR_ARG,
                        "records: static_fraction %g must be in (0, 1], min_hold_s %g > 0",
                        s->static_fraction, s->min_hold_s);
  const double sd[] = {s->noise_theta0_rad, s->noise_torque_Nm, s->noise_tension_N, s->noise_tip_m};
  for (size_t i = 0; i < sizeof sd / sizeof *sd; ++i)
    if (!(sd[i] >= 0) || !isfinite(sd[i]))
      return ea_error_set(err, EA_ERR_ARG, "records: noise level %g: must be finite, >= 0", sd[i]);
  ea_record_hold_t *holds = NULL;
  int nh = 0;
  ea_status_t st = ea_record_find_holds(arm, sp, t, n, s->min_hold_s, h->data[6 * (h->rows - 1)],
                                        &holds, &nh, err);
  if (st) return st;
  if (nh == 0) {
    free(holds);
    return ea_error_set(err, EA_ERR_INPUT,
                        "records: no hold (setpoints at rest for at least %g s) in the session",
                        s->min_hold_s);
  }
  /* the static window: a fixed number of samples, so every row has the same noise */
  double shortest = INFINITY;
  for (int k = 0; k < nh; ++k)
    shortest = fmin(shortest, holds[k].t_end - holds[k].t_start);
  const double dt = h->data[6] - h->data[0];
  const int n_avg = (int)fmax(1.0, floor(s->static_fraction * shortest / dt + 1e-9));
  info->holds = nh;
  info->averaged_samples = n_avg;
  info->averaged_window_s = n_avg * dt;
  char path[1100];
  snprintf(path, sizeof path, "%s/static.csv", dir);
  double *rows = malloc(sizeof(double) * 5 * (size_t)nh);
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  if (!rows || !rng) st = ea_error_set(err, EA_ERR_NOMEM, "records: %d holds", nh);
  if (!st) {
    gsl_rng_set(rng, s->seed);
    st = ea_mkdir_parents(path, err);
  }
  for (int k = 0; !st && k < nh; ++k)
    st = ea__record_hold(dir, s, h, &holds[k], k, n_avg, rng, rows + 5 * k, &info->ringdowns, err);
  ea_afile_t af = {0};
  if (!st && !(st = ea_afile_open(&af, path, err))) {
    ea__common_hdr(af.fp, "static", s);
    const double rn = 1.0 / sqrt((double)n_avg);
    ea__noise_hdr(af.fp, "noise_theta0_rad", s->noise_theta0_rad * rn);
    ea__noise_hdr(af.fp, "noise_torque_Nm", s->noise_torque_Nm * rn);
    ea__noise_hdr(af.fp, "noise_tension_N", s->noise_tension_N * rn);
    ea__noise_hdr(af.fp, "noise_tip_m", s->noise_tip_m * rn);
    fprintf(af.fp, "# averaged_samples: %d\n# averaged_window_s: %.9g\n", n_avg, n_avg * dt);
    fprintf(af.fp, "cable_length_m,theta0_rad,shoulder_torque_Nm,tension_N,tip_x_m,tip_y_m\n");
    for (int k = 0; k < nh; ++k) {
      const double *v = rows + 5 * k;
      fprintf(af.fp, "%.12g,%.12g,%.12g,%.12g,%.12g,%.12g\n", holds[k].cable_length, v[0], v[1],
              v[2], v[3], v[4]);
    }
    st = ea_afile_commit(&af, err);
    if (!st) snprintf(info->static_path, sizeof info->static_path, "%s", path);
  }
  ea_afile_abort(&af);
  gsl_rng_free(rng);
  free(rows);
  free(holds);
  return st;
}
