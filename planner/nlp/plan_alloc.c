/* The planner's lifecycle: ea_planner_alloc builds the transcriptions a task needs,
 * ea_planner_free releases them. Everything is allocated here; the callbacks do not
 * allocate. */
#include "ipopt_impl.h"
#include "dyn_impl.h"
#include "guess_impl.h"
#include "hess_impl.h"
#include "knot_impl.h"
#include "path_entry_impl.h"
#include "vib_impl.h"
#include "plan_impl.h"
#include "plan_ipm_impl.h"
#include "plan_screen_impl.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const ea_task_t *ea_planner_task(const ea_planner_t *pl) {
  return &pl->task;
}

void ea_planner_free(ea_planner_t *pl) {
  if (!pl) return;
  ea__ipopt_free(pl->ip);
  ea__screen_free(pl->scr);
  ea__kkt_free(pl->kkt);
  free(pl->rfam);
  free(pl->xstart);
  ea__plan_hess_free(pl);
  ea__plan_freq_free(pl->fm);
  for (int j = 0; j < EA__DYN_MAX_MODELS; ++j)
    ea_rom_table_free(pl->roms[j]);
  ea__plan_dyn_cache_free(pl->dync);
  ea__pp_free(pl->pp);
  ea_shooter_free(pl->sh);
  free(pl->s);
  free(pl->seg_of_knot);
  free(pl->x);
  free(pl->xl);
  free(pl->xu);
  free(pl->gl);
  free(pl->gu);
  free(pl->g);
  free(pl->mult_g);
  free(pl->mult_xl);
  free(pl->mult_xu);
  free(pl->rows);
  free(pl->irow);
  free(pl->jcol);
  free(pl->xL);
  free(pl->S);
  free(pl->pkey);
  free(pl->gscr);
  free(pl->wscr);
  free(pl->kkt_r);
  free(pl->x0);
  free(pl->jval);
  free(pl->kvalid);
  free(pl->x_sol);
  free(pl->mult_g_sol);
  free(pl->mult_xl_sol);
  free(pl->mult_xu_sol);
  free(pl);
}

/* What the planner takes from the task besides the structure: tip mass
 * (the shooter's load), knot and variable counts, the fixed duration and
 * base angle, the speed and acceleration limits (at alloc and at every
 * ea_planner_update). */
void ea__plan_derive(ea_planner_t *pl) {
  const ea_task_t *t = &pl->task;
  const ea_task_limits_t *l = &t->limits;
  pl->tip_mass = ea_arm_tip_mass(&t->arm, t->payload_kg);
  const ea_load_t load = {pl->tip_mass};
  ea_shooter_set_load(pl->sh, &load);
  pl->N = t->knots;
  pl->nq = t->base_moves ? 3 : 2;
  pl->nb = 2 * pl->nq + 3;
  pl->has_tf = t->objective == EA_TASK_MIN_TIME ||
               (t->objective == EA_TASK_MIN_VIBRATION && isnan(t->duration_s));
  pl->tf_fixed = pl->has_tf ? NAN : t->duration_s;
  pl->zero_end_acc = t->objective == EA_TASK_MIN_VIBRATION;
  pl->base_fixed = t->start.base_angle;
  /* Planned 1 + margin tighter: the streamer's quintic resampling overshoots
   * the cubic's knot values slightly (docs/planner.md). */
  const double rm = 1.0 + (l->resample_margin >= 0.0 ? l->resample_margin : 0.0);
  pl->vmax[0] = l->cable_speed_max / rm;
  pl->amax[0] = l->cable_accel_max / rm;
  pl->vmax[1] = l->cable_angle_speed_max / rm;
  pl->amax[1] = l->cable_angle_accel_max / rm;
  pl->vmax[2] = l->base_speed_max / rm;
  pl->amax[2] = l->base_accel_max / rm;
  /* theta0: the task's speed limit, the arm's acceleration limit */
  pl->vmax[EA__C_TH] = l->shoulder_speed_max / rm;
  pl->amax[EA__C_TH] = t->arm.act.shoulder_accel_max / rm;
  pl->aref[0] = pl->amax[0];
  pl->aref[1] = isfinite(pl->amax[1])
                    ? pl->amax[1]
                    : pl->amax[0] / fmax(t->start.cable_length, t->goal.cable_length);
  pl->aref[2] = pl->amax[2];
}

/* Scale of the acceleration rows (plan_impl.h): their tolerance is at
 * least 60 x the rounding floor of a Hermite acceleration 6 eps |q|max /
 * h^2 on the shortest interval, with h from a short duration estimate. */
static void ea__acc_scale(ea_planner_t *pl) {
  const ea_task_t *t = &pl->task;
  double ds = 1.0, qmax = fmax(M_PI, fmax(t->limits.cable_length_max,
                                          fmax(fabs(t->arm.act.shoulder_angle_min),
                                               fabs(t->arm.act.shoulder_angle_max))));
  for (int k = 0; k + 1 < pl->N; ++k)
    ds = fmin(ds, pl->s[k + 1] - pl->s[k]);
  const double h = ea__plan_duration_low(pl) * ds;
  const double floor_a = 60.0 * 6.0 * DBL_EPSILON * qmax / (h * h);
  const double ct = t->solver.constr_tol;
  pl->acc_tol = fmax(ct, floor_a);
  pl->acc_scale = ct / pl->acc_tol;
}

ea_status_t ea_planner_alloc(const ea_task_t *task, ea_planner_t **out, ea_error_t *err) {
  if (!task || !out) return ea_error_set(err, EA_ERR_ARG, "ea_planner_alloc: NULL argument");
  return ea_planner_alloc_with(task, &task->solver, out, err);
}

/* The knot transcription's arrays of pl->n variables and pl->m rows, the statics cache and the
 * guess's scratch (calloc'd). 0, or -1 (out of memory). */
static int ea__plan_arrays(ea_planner_t *pl) {
  const int N = pl->N;
  const size_t n = (size_t)pl->n, m = (size_t)pl->m;
  pl->rows = calloc(m, sizeof *pl->rows);
  pl->gl = calloc(m, sizeof *pl->gl);
  pl->gu = calloc(m, sizeof *pl->gu);
  pl->g = calloc(m, sizeof *pl->g);
  pl->mult_g = calloc(m, sizeof *pl->mult_g);
  pl->mult_g_sol = calloc(m, sizeof *pl->mult_g);
  pl->x = calloc(n, sizeof *pl->x);
  pl->xl = calloc(n, sizeof *pl->x);
  pl->xu = calloc(n, sizeof *pl->x);
  pl->mult_xl = calloc(n, sizeof *pl->x);
  pl->mult_xu = calloc(n, sizeof *pl->x);
  pl->x_sol = calloc(n, sizeof *pl->x);
  pl->mult_xl_sol = calloc(n, sizeof *pl->x);
  pl->mult_xu_sol = calloc(n, sizeof *pl->x);
  pl->xL = calloc((size_t)N * 4, sizeof *pl->xL);
  pl->S = calloc((size_t)N * 16, sizeof *pl->S);
  pl->pkey = calloc((size_t)N * 4, sizeof *pl->pkey);
  pl->kvalid = calloc((size_t)N, sizeof *pl->kvalid);
  pl->gscr = calloc((size_t)N * 5, sizeof *pl->gscr);
  pl->wscr = calloc((size_t)N * 2, sizeof *pl->wscr);
  if (!pl->rows || !pl->gl || !pl->gu || !pl->g || !pl->mult_g || !pl->mult_g_sol || !pl->x ||
      !pl->xl || !pl->xu || !pl->mult_xl || !pl->mult_xu || !pl->x_sol || !pl->mult_xl_sol ||
      !pl->mult_xu_sol || !pl->xL || !pl->S || !pl->pkey || !pl->kvalid || !pl->gscr || !pl->wscr)
    return -1;
  return 0;
}

ea_status_t ea_planner_alloc_with(const ea_task_t *task, const ea_planner_settings_t *settings,
                                  ea_planner_t **out, ea_error_t *err) {
  if (!task || !settings || !out)
    return ea_error_set(err, EA_ERR_ARG, "ea_planner_alloc_with: NULL argument");
  *out = NULL;
  ea_planner_t *pl = calloc(1, sizeof *pl);
  if (!pl) return ea_error_set(err, EA_ERR_NOMEM, "out of memory");
  pl->task = *task;
  pl->task.solver = *settings; /* the planner's settings: read as pl->task.solver below */
  const ea_task_t *t = &pl->task;
  if (t->knots < 3 || t->knots > 4000 || t->n_via < 0 || t->n_via > EA_TASK_MAX_VIA ||
      t->n_via + 2 > t->knots || !(t->start.cable_length > 0)) {
    const int kn = t->knots;
    free(pl);
    return ea_error_set(err, EA_ERR_ARG,
                        "ea_planner_alloc: the task is not checked (ea_task_check) or has a "
                        "bad knot count %d",
                        kn);
  }
  ea_status_t st = ea_planner_settings_validate(settings, err);
  if (st) {
    free(pl);
    return st;
  }
  st = ea_shooter_alloc(&t->arm, NULL, &pl->sh, err);
  if (st) {
    ea_planner_free(pl);
    return st;
  }
  ea__plan_derive(pl);
  const int N = pl->N;
  if ((st = ea__plan_dyn_build(pl, err))) {
    ea_planner_free(pl);
    return st;
  }
  /* knot blocks, t_f, theta0 rates, modal states */
  pl->ie0 = N * pl->nb + pl->has_tf + N;
  pl->n = pl->ie0 + 2 * pl->K * N;
  pl->s = calloc((size_t)N, sizeof *pl->s);
  pl->seg_of_knot = calloc((size_t)N, sizeof *pl->seg_of_knot);
  if (!pl->s || !pl->seg_of_knot) goto nomem;
  ea__plan_knot_times(pl);
  ea__plan_layout(pl);
  ea__acc_scale(pl);
  if ((st = ea__plan_freq_build(pl, err))) {
    ea_planner_free(pl);
    return st;
  }
  pl->m = ea__knot_rows(pl);
  if (ea__plan_arrays(pl)) goto nomem;
  ea__knot_rows(pl);
  ea__knot_bounds(pl);
  ea__plan_terms_setup(pl);
  pl->nnz = ea__plan_jac(pl, pl->x, NULL, NULL, NULL);
  pl->irow = calloc((size_t)pl->nnz, sizeof *pl->irow);
  pl->jcol = calloc((size_t)pl->nnz, sizeof *pl->jcol);
  if (!pl->irow || !pl->jcol) goto nomem;
  ea__plan_jac(pl, pl->x, pl->irow, pl->jcol, NULL);
  pl->kkt_r = calloc((size_t)pl->n, sizeof *pl->kkt_r);
  pl->x0 = calloc((size_t)pl->n, sizeof *pl->x0);
  pl->xstart = calloc((size_t)pl->n, sizeof *pl->xstart);
  pl->jval = calloc((size_t)pl->nnz, sizeof *pl->jval);
  if (!pl->kkt_r || !pl->jval || !pl->x0 || !pl->xstart) goto nomem;
  if (!(pl->rfam = malloc(sizeof(int) * (size_t)(pl->m + 1)))) goto nomem;
  pl->nfam = ea__plan_row_families(pl->rows, pl->m, pl->rfam);
  pl->hess_exact = t->solver.hessian_exact;
  if (pl->hess_exact && ea__plan_hess_setup(pl)) goto nomem;
  if (pl->hess_exact && ea__pp_supported(pl) && (st = ea__pp_alloc(pl, err))) {
    ea_planner_free(pl);
    return st;
  }
  if ((st = ea__ipopt_create(pl))) {
    ea_planner_free(pl);
    return st == EA_ERR_NOMEM ? ea_error_set(err, st, "out of memory building the transcription")
                              : ea_error_set(err, st, "Ipopt: cannot create the problem");
  }
  *out = pl;
  return ea_error_set(err, EA_OK, "ok");
nomem:
  ea_planner_free(pl);
  return ea_error_set(err, EA_ERR_NOMEM, "out of memory building the transcription");
}
