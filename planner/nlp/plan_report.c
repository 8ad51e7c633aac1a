/* What a plan or a failed solve reports: the worst violated row or bound, the active
 * limits, the plan's margins. */
#include "plan_impl.h"
#include "knot_impl.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---------------------------------------------------------------------- */
/* Reports                                                                  */
/* ---------------------------------------------------------------------- */

static const char *ea__var_name(const ea_planner_t *pl, int i, int upper, int *knot,
                                double *scale) {
  static const char *const qn[2][3] = {{"cable_length_min", "cable angle range", "base range"},
                                       {"cable_length_max", "cable angle range", "base range"}};
  static const char *const vn[3] = {"cable speed limit", "cable angle speed limit",
                                    "base speed limit"};
  *scale = 1.0;
  if (pl->has_tf && i == EA__ITF(pl)) {
    *knot = -1;
    return "duration range";
  }
  if (i >= EA__IW(pl, 0)) {
    *knot = i - EA__IW(pl, 0);
    return "shoulder speed limit";
  }
  *knot = i / pl->nb;
  const int r = i % pl->nb;
  if (r < pl->nq) return qn[upper][r];
  if (r < 2 * pl->nq) return vn[r - pl->nq];
  switch (r - 2 * pl->nq) {
  case 0:
    return upper ? "tension <= tension_max" : "tension >= tension_min";
  case 1:
    return "shoulder angle range";
  default:
    *scale = pl->task.arm.EI;
    return "shoulder torque limit";
  }
}

/* Largest violation of the bounds and rows at x (g filled). */
static double ea__worst(ea_planner_t *pl, const double *x, const double *g, char *buf, size_t len) {
  double worst = 0.0;
  buf[0] = '\0';
  for (int i = 0; i < pl->m; ++i) {
    const double v = fmax(pl->gl[i] - g[i], g[i] - pl->gu[i]) * ea__plan_row_unit(pl, &pl->rows[i]);
    if (v > worst) {
      worst = v;
      char nm[80];
      const ea__row_t *r = &pl->rows[i];
      const int is_statics = r->kind <= EA__ROW_STATICS_Y;
      snprintf(buf, len, "'%s' at %s %d violated by %.3g%s",
               ea__plan_row_name(pl, r, nm, sizeof nm),
               r->kind == EA__ROW_ACC_START || r->kind == EA__ROW_ACC_END ||
                       r->kind == EA__ROW_SPEED_CTRL
                   ? "interval"
                   : "knot",
               r->knot, v, is_statics ? " (no static equilibrium there within the limits)" : "");
    }
  }
  for (int i = 0; i < pl->n; ++i) {
    const double lo = pl->xl[i] - x[i], hi = x[i] - pl->xu[i];
    const double v = fmax(lo, hi);
    if (v > worst) {
      worst = v;
      int k;
      double sc;
      const char *nm = ea__var_name(pl, i, hi > lo, &k, &sc);
      snprintf(buf, len, "'%s' at knot %d violated by %.3g", nm, k, v * sc);
    }
  }
  return worst;
}

static void ea__add_active(ea_plan_info_t *info, const char *name) {
  for (int i = 0; i < info->n_active; ++i)
    if (!strncmp(info->active[i], name, sizeof info->active[0] - 1)) {
      info->active_knots[i]++;
      return;
    }
  if (info->n_active >= EA_PLAN_MAX_ACTIVE) return;
  snprintf(info->active[info->n_active], sizeof info->active[0], "%s", name);
  info->active_knots[info->n_active++] = 1;
}

static int ea__near(double v, double b) {
  return fabs(v - b) <= 1e-5 * fmax(1.0, fabs(b));
}

void ea__plan_stats(ea_planner_t *pl, const double *x, ea_plan_info_t *info) {
  const ea_task_t *t = &pl->task;
  info->duration_s = ea__plan_tf(pl, x);
  info->min_tension_margin_N = INFINITY;
  info->peak_shoulder_torque_Nm = 0.0;
  for (int k = 0; k < pl->N; ++k) {
    info->min_tension_margin_N =
        fmin(info->min_tension_margin_N, x[EA__IP(pl, k, 0)] - t->limits.tension_min);
    info->peak_shoulder_torque_Nm =
        fmax(info->peak_shoulder_torque_Nm, fabs(t->arm.EI * x[EA__IP(pl, k, 2)]));
  }
  pl->cache_val = pl->cache_sens = 0;
  ea__plan_eval_g_values(pl, x, pl->g);
  info->max_statics_residual = 0.0;
  for (int i = 0; i < 3 * pl->N; ++i)
    info->max_statics_residual = fmax(info->max_statics_residual, fabs(pl->g[i]));
  info->max_violation = ea__worst(pl, x, pl->g, info->worst, sizeof info->worst);
  info->n_active = 0;
  for (int i = 3 * pl->N; i < pl->m; ++i) {
    if (pl->gl[i] == pl->gu[i]) continue;
    const ea__row_t *r = &pl->rows[i];
    if (r->kind == EA__ROW_PATH_PROGRESS) continue;
    if (ea__near(pl->g[i], pl->gl[i]) || ea__near(pl->g[i], pl->gu[i])) {
      char nm[80];
      ea__add_active(info, ea__plan_row_name(pl, r, nm, sizeof nm));
    }
  }
  for (int i = 0; i < pl->n; ++i) {
    if (pl->xl[i] == pl->xu[i]) continue;
    int lo = ea__near(x[i], pl->xl[i]), hi = ea__near(x[i], pl->xu[i]);
    if (lo || hi) {
      int k;
      double sc;
      ea__add_active(info, ea__var_name(pl, i, hi, &k, &sc));
    }
  }
}
