/* The knot transcription's rows and bounds. */
#include "plan_impl.h"
#include "knot_impl.h"
#include "vib_impl.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---------------------------------------------------------------------- */
/* Setup                                                                    */
/* ---------------------------------------------------------------------- */

static void ea__add_row(ea_planner_t *pl, int *i, ea__row_kind_t kind, int knot, int coord,
                        double lo, double hi) {
  if (pl->rows) {
    pl->rows[*i] = (ea__row_t){(unsigned char)kind, (unsigned char)coord, knot};
    pl->gl[*i] = lo;
    pl->gu[*i] = hi;
  }
  ++*i;
}

int ea__knot_rows(ea_planner_t *pl) {
  const int N = pl->N;
  int i = 0;
  for (int k = 0; k < N; ++k) {
    ea__add_row(pl, &i, EA__ROW_STATICS_KAPPA, k, 0, 0.0, 0.0);
    ea__add_row(pl, &i, EA__ROW_STATICS_X, k, 0, 0.0, 0.0);
    ea__add_row(pl, &i, EA__ROW_STATICS_Y, k, 0, 0.0, 0.0);
  }
  /* The actuator coordinates and theta0 (EA__C_TH): every limit holds on
   * the whole cubic Hermite of each interval (docs/planner.md, "Limits
   * between the knots"). theta0 is always a C2 spline (its rates are fixed
   * by these rows and rest at both ends). */
  const double ct = pl->task.solver.constr_tol;
  int cs[4], ncs = 0;
  for (int c = 0; c < pl->nq; ++c)
    cs[ncs++] = c;
  cs[ncs++] = EA__C_TH;
  for (int j = 0; j < ncs; ++j) {
    const int c = cs[j];
    for (int k = 0; k + 1 < N; ++k) {
      /* min_vibration: no acceleration step at the start and the goal (rest) */
      const int z0 = pl->zero_end_acc && c < pl->nq && k == 0;
      const int z1 = pl->zero_end_acc && c < pl->nq && k + 2 == N;
      /* limits kept their tolerance inside (the row holds to it) */
      const double a = pl->acc_scale * (pl->amax[c] - pl->acc_tol);
      const double v = pl->vmax[c] - ct;
      if (isfinite(pl->amax[c]) || z0)
        ea__add_row(pl, &i, EA__ROW_ACC_START, k, c, z0 ? 0.0 : -a, z0 ? 0.0 : a);
      /* where the acceleration is continuous (ACC_CONT, itself within acc_tol) an interior
       * interval's end acceleration is the next one's start: its row would repeat that
       * row (linearly dependent when active), so only the last interval has one */
      const int cont = pl->task.limits.continuous_acceleration || c == EA__C_TH;
      if ((isfinite(pl->amax[c]) && (!cont || k + 2 == N)) || z1)
        ea__add_row(pl, &i, EA__ROW_ACC_END, k, c, z1 ? 0.0 : -a, z1 ? 0.0 : a);
      if (isfinite(pl->vmax[c])) ea__add_row(pl, &i, EA__ROW_SPEED_CTRL, k, c, -v, v);
    }
  }
  for (int j = 0; j < ncs; ++j)
    if (pl->task.limits.continuous_acceleration || cs[j] == EA__C_TH)
      for (int k = 1; k + 1 < N; ++k)
        ea__add_row(pl, &i, EA__ROW_ACC_CONT, k, cs[j], 0.0, 0.0);
  for (int k = 0; k < N; ++k) {
    const int sg = pl->seg_of_knot[k];
    if (sg < 0) continue;
    for (int j = 0; j < pl->n_normals; ++j)
      ea__add_row(pl, &i, EA__ROW_PATH_NORMAL, k, j, 0, 0);
    ea__add_row(pl, &i, EA__ROW_PATH_PROGRESS, k, 0, 0.0, pl->segLen[sg]);
  }
  const double fmin = pl->task.limits.min_first_frequency_hz;
  if (pl->fm && fmin > 0.0)
    for (int k = 0; k < N; ++k)
      ea__add_row(pl, &i, EA__ROW_FREQ_MIN, k, 0, fmin + ct, EA__IPINF);
  const double dmax = pl->task.limits.max_modal_deflection_m;
  if (pl->fm && isfinite(dmax))
    for (int c = 0; c < 2; ++c)
      for (int k = 0; k + 1 < N; ++k) {
        ea__add_row(pl, &i, EA__ROW_DEFL_START, k, c, -(dmax - ct), dmax - ct);
        ea__add_row(pl, &i, EA__ROW_DEFL_END, k, c, -(dmax - ct), dmax - ct);
      }
  if (pl->rom) { /* the reduced dynamic model (dyn_rows.c) */
    const ea_task_t *t = &pl->task;
    for (int k = 0; k + 1 < N; ++k)
      for (int m = 0; m < pl->K; ++m) {
        ea__add_row(pl, &i, EA__ROW_DYN_DEF_POS, k, m, 0.0, 0.0);
        ea__add_row(pl, &i, EA__ROW_DYN_DEF_VEL, k, m, 0.0, 0.0);
      }
    for (int j = 0; j < pl->M; ++j) /* each model: tension, torque, deviation */
      for (int k = 1; k + 1 < N; ++k) {
        ea__add_row(pl, &i, EA__ROW_DYN_TENSION, k, j, t->limits.tension_min + ct,
                    t->limits.tension_max - ct);
        const double tq = t->limits.shoulder_torque_max - ct;
        ea__add_row(pl, &i, EA__ROW_DYN_TORQUE, k, j, -tq, tq);
        const double d = t->dynamics.max_tip_deviation_m;
        if (isfinite(d)) ea__add_row(pl, &i, EA__ROW_DYN_DEVIATION, k, j, -EA__IPINF, d * d);
      }
    /* at the goal: the nominal model at rest (or within residual_m); the robust corners
     * within robust_residual_m */
    const double r = t->dynamics.residual_m, rr = t->dynamics.robust_residual_m;
    if (t->objective != EA_TASK_MIN_VIBRATION) {
      if (r > 0)
        ea__add_row(pl, &i, EA__ROW_DYN_TERMINAL, N - 1, 0, -EA__IPINF,
                    pl->dyn_term_scale * r * r / pl->Kper);
      else
        for (int m = 0; m < pl->Kper; ++m) {
          ea__add_row(pl, &i, EA__ROW_DYN_REST, N - 1, m, 0.0, 0.0);
          ea__add_row(pl, &i, EA__ROW_DYN_REST, N - 1, pl->K + m, 0.0, 0.0);
        }
      for (int j = 1; j < pl->M; ++j)
        ea__add_row(pl, &i, EA__ROW_DYN_TERMINAL, N - 1, j, -EA__IPINF,
                    pl->dyn_term_scale * rr * rr / pl->Kper);
    }
  }
  return i;
}

static const ea_task_point_t *ea__pt(const ea_task_t *t, int j) {
  return j == 0 ? &t->start : j <= t->n_via ? &t->via[j - 1] : &t->goal;
}

void ea__knot_bounds(ea_planner_t *pl) {
  const ea_task_t *t = &pl->task;
  const ea_task_limits_t *l = &t->limits;
  const ea_actuators_t *a = &t->arm.act;
  const double qlo[3] = {l->cable_length_min, -M_PI, a->base_angle_min};
  const double qhi[3] = {l->cable_length_max, M_PI, a->base_angle_max};
  for (int k = 0; k < pl->N; ++k) {
    for (int c = 0; c < pl->nq; ++c) {
      pl->xl[EA__IQ(pl, k, c)] = qlo[c];
      pl->xu[EA__IQ(pl, k, c)] = qhi[c];
      const double v = isfinite(pl->vmax[c]) ? pl->vmax[c] : EA__IPINF;
      pl->xl[EA__IV(pl, k, c)] = -v;
      pl->xu[EA__IV(pl, k, c)] = v;
    }
    pl->xl[EA__IP(pl, k, 0)] = l->tension_min;
    pl->xu[EA__IP(pl, k, 0)] = l->tension_max;
    pl->xl[EA__IP(pl, k, 1)] = a->shoulder_angle_min;
    pl->xu[EA__IP(pl, k, 1)] = a->shoulder_angle_max;
    const double w = isfinite(pl->vmax[EA__C_TH]) ? pl->vmax[EA__C_TH] : EA__IPINF;
    pl->xl[EA__IW(pl, k)] = -w;
    pl->xu[EA__IW(pl, k)] = w;
    const double km = l->shoulder_torque_max / t->arm.EI;
    pl->xl[EA__IP(pl, k, 2)] = -km;
    pl->xu[EA__IP(pl, k, 2)] = km;
    if (pl->fm) { /* stay on the frequency model's grid */
      const ea_plan_freq_model_info_t *fi = &pl->fm->info;
      pl->xl[EA__IQ(pl, k, 0)] = fmax(pl->xl[EA__IQ(pl, k, 0)], fi->cable_length_range[0]);
      pl->xu[EA__IQ(pl, k, 0)] = fmin(pl->xu[EA__IQ(pl, k, 0)], fi->cable_length_range[1]);
      pl->xl[EA__IQ(pl, k, 1)] = fmax(pl->xl[EA__IQ(pl, k, 1)], fi->cable_angle_range[0]);
      pl->xu[EA__IQ(pl, k, 1)] = fmin(pl->xu[EA__IQ(pl, k, 1)], fi->cable_angle_range[1]);
    }
  }
  /* Pins: the points at their knots; rest at start and goal. */
  for (int j = 0; j < t->n_via + 2; ++j) {
    const ea_task_point_t *p = ea__pt(t, j);
    const int k = pl->via_knot[j];
    const double q[3] = {p->cable_length, p->cable_angle, p->base_angle};
    for (int c = 0; c < pl->nq; ++c)
      pl->xl[EA__IQ(pl, k, c)] = pl->xu[EA__IQ(pl, k, c)] = q[c];
  }
  for (int c = 0; c < pl->nq; ++c) {
    pl->xl[EA__IV(pl, 0, c)] = pl->xu[EA__IV(pl, 0, c)] = 0.0;
    pl->xl[EA__IV(pl, pl->N - 1, c)] = pl->xu[EA__IV(pl, pl->N - 1, c)] = 0.0;
  }
  pl->xl[EA__IW(pl, 0)] = pl->xu[EA__IW(pl, 0)] = 0.0;
  pl->xl[EA__IW(pl, pl->N - 1)] = pl->xu[EA__IW(pl, pl->N - 1)] = 0.0;
  if (pl->has_tf) {
    pl->xl[EA__ITF(pl)] = 1e-3;
    pl->xu[EA__ITF(pl)] = 1e5;
  }
  if (pl->rom) { /* modal states: rest at the start; at the goal unless a residual is allowed */
    const ea_plan_dyn_info_t *di = &pl->dyn_info;
    const int rest_end = !(t->dynamics.residual_m > 0) && t->objective != EA_TASK_MIN_VIBRATION;
    for (int k = 0; k < pl->N; ++k) {
      /* rest at the start (bounds); at the goal the rows EA__ROW_DYN_REST hold the target */
      const int fix = k == 0;
      (void)rest_end;
      for (int i = 0; i < pl->K; ++i) {
        pl->xl[EA__IE(pl, k, i)] = pl->xl[EA__IED(pl, k, i)] = fix ? 0.0 : -EA__IPINF;
        pl->xu[EA__IE(pl, k, i)] = pl->xu[EA__IED(pl, k, i)] = fix ? 0.0 : EA__IPINF;
      }
      /* stay on the model's table */
      pl->xl[EA__IQ(pl, k, 0)] = fmax(pl->xl[EA__IQ(pl, k, 0)], di->table.box[0]);
      pl->xu[EA__IQ(pl, k, 0)] = fmin(pl->xu[EA__IQ(pl, k, 0)], di->table.box[1]);
      pl->xl[EA__IQ(pl, k, 1)] = fmax(pl->xl[EA__IQ(pl, k, 1)], di->table.box[2]);
      pl->xu[EA__IQ(pl, k, 1)] = fmin(pl->xu[EA__IQ(pl, k, 1)], di->table.box[3]);
    }
  }
}
