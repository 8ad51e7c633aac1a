/* The planner's setup and its Ipopt glue: bounds, rows, callbacks, solve,
 * and the report of a failed plan (which constraint, which knot, by how
 * much). Everything is allocated in ea_planner_alloc; the callbacks do not
 * allocate. */
#include "plan_impl.h"
#include "plan_ipm_impl.h"
#include "plan_screen_impl.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

const ea_task_t *ea_planner_task(const ea_planner_t *pl) {
  return &pl->task;
}

void ea_planner_free(ea_planner_t *pl) {
  if (!pl) return;
  if (pl->ip) FreeIpoptProblem(pl->ip);
  ea__screen_free(pl->scr);
  ea__asn_free(pl->asn);
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

/* ---------------------------------------------------------------------- */
/* Ipopt callbacks                                                          */
/* ---------------------------------------------------------------------- */

static void ea__touch(ea_planner_t *pl, Bool new_x) {
  if (new_x) pl->cache_val = pl->cache_sens = 0;
}

static Bool ea__cb_f(Index n, Number *x, Bool new_x, Number *f, UserDataPtr ud) {
  ea_planner_t *pl = ud;
  (void)n;
  const double t0 = ea__mono_s();
  ea__touch(pl, new_x);
  double v = 0.0;
  for (int i = 0; i < pl->n_terms; ++i)
    v += pl->terms[i].weight * pl->terms[i].value(pl, x);
  *f = v;
  pl->t_callbacks += ea__mono_s() - t0;
  return isfinite(v);
}

static Bool ea__cb_grad_f(Index n, Number *x, Bool new_x, Number *g, UserDataPtr ud) {
  ea_planner_t *pl = ud;
  const double t0 = ea__mono_s();
  ea__touch(pl, new_x);
  memset(g, 0, (size_t)n * sizeof *g);
  for (int i = 0; i < pl->n_terms; ++i)
    pl->terms[i].grad(pl, x, pl->terms[i].weight, g);
  pl->t_callbacks += ea__mono_s() - t0;
  return TRUE;
}

static Bool ea__cb_g(Index n, Number *x, Bool new_x, Index m, Number *g, UserDataPtr ud) {
  ea_planner_t *pl = ud;
  (void)n;
  (void)m;
  const double t0 = ea__mono_s();
  ea__touch(pl, new_x);
  const ea_status_t st = ea__plan_eval_g(pl, x, g);
  if (pl->info) pl->info->evals_g++;
  pl->t_callbacks += ea__mono_s() - t0;
  return st == EA_OK;
}

static Bool ea__cb_jac(Index n, Number *x, Bool new_x, Index m, Index nele, Index *iRow,
                       Index *jCol, Number *values, UserDataPtr ud) {
  ea_planner_t *pl = ud;
  (void)n;
  (void)m;
  (void)nele;
  if (!values) {
    memcpy(iRow, pl->irow, (size_t)pl->nnz * sizeof *iRow);
    memcpy(jCol, pl->jcol, (size_t)pl->nnz * sizeof *jCol);
    return TRUE;
  }
  const double t0 = ea__mono_s();
  ea__touch(pl, new_x);
  if (ea__plan_shoot_all(pl, x, 1)) return FALSE;
  ea__plan_jac(pl, x, NULL, NULL, values);
  if (pl->info) pl->info->evals_jac++;
  pl->t_callbacks += ea__mono_s() - t0;
  return TRUE;
}

static Bool ea__cb_h(Index n, Number *x, Bool new_x, Number of, Index m, Number *lambda,
                     Bool new_lambda, Index nele, Index *iRow, Index *jCol, Number *values,
                     UserDataPtr ud) {
  ea_planner_t *pl = ud;
  (void)n, (void)m, (void)new_lambda, (void)nele;
  if (!pl->hess_exact) return FALSE; /* limited-memory quasi-Newton */
  if (!values) {
    memcpy(iRow, pl->hirow, (size_t)pl->nnz_h * sizeof *iRow);
    memcpy(jCol, pl->hjcol, (size_t)pl->nnz_h * sizeof *jCol);
    return TRUE;
  }
  const double t0 = ea__mono_s();
  ea__touch(pl, new_x);
  const ea_status_t st = ea__plan_hess_values(pl, x, of, lambda, values);
  pl->t_callbacks += ea__mono_s() - t0;
  return st == EA_OK;
}

int ea__plan_time_up(void *ud) {
  const ea_planner_t *pl = ud;
  return !(ea__mono_s() - pl->t_start < pl->max_time);
}

static Bool ea__cb_iter(Index alg_mod, Index iter, Number obj, Number inf_pr, Number inf_du,
                        Number mu, Number d_norm, Number reg, Number alpha_du, Number alpha_pr,
                        Index ls, UserDataPtr ud) {
  ea_planner_t *pl = ud;
  (void)alg_mod, (void)obj, (void)inf_pr, (void)inf_du, (void)mu, (void)d_norm, (void)reg;
  (void)alpha_du, (void)alpha_pr, (void)ls;
  pl->iter = iter;
  return ea__mono_s() - pl->t_start < pl->max_time ? TRUE : FALSE;
}

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

static int ea__build_rows(ea_planner_t *pl) {
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
  if (pl->rom) { /* the reduced dynamic model (plan_dyn.c) */
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

static void ea__bounds(ea_planner_t *pl) {
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

/* What the planner takes from the task besides the structure: tip mass
 * (the shooter's load), knot and variable counts, the fixed duration and
 * base angle, the speed and acceleration limits (at alloc and at every
 * ea_planner_update). */
static void ea__derive(ea_planner_t *pl) {
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

/* The Ipopt problem with the planner's bounds, its rows of the next solve (plan_screen.c) and
 * the options. Every Ipopt solve creates it (ea__solve_ipopt: the rows it sees change from
 * solve to solve, and Ipopt's C interface copies the bounds at creation; every IpoptSolve sets
 * up its algorithm objects and the MUMPS analysis anew anyway), so a change of the task needs
 * no call here; ea_planner_alloc creates one to report a backend that cannot. A planner that
 * solves in the path coordinate (plan_path.c, its own problem per solve) has none. */
static ea_status_t ea__ipopt_create(ea_planner_t *pl) {
  const ea_task_t *t = &pl->task;
  if (pl->ip) FreeIpoptProblem(pl->ip);
  pl->ip = NULL;
  if (pl->pp && !pl->pp_off) return EA_OK;
  if (pl->hess_exact && ea__plan_hess_pattern(pl)) return EA_ERR_NOMEM;
  /* the rows of the next solve (plan_screen.c; every row until a solve selects them) */
  if (!pl->scr) {
    const ea__screen_nlp_t nlp = {.n = pl->n,
                                  .m = pl->m,
                                  .nnz_j = pl->nnz,
                                  .nnz_h = pl->hess_exact ? pl->nnz_h : 0,
                                  .gl = pl->gl,
                                  .gu = pl->gu,
                                  .jrow = pl->irow,
                                  .jcol = pl->jcol,
                                  .f = ea__cb_f,
                                  .g = ea__cb_g,
                                  .grad_f = ea__cb_grad_f,
                                  .jac = ea__cb_jac,
                                  .h = ea__cb_h,
                                  .iter = ea__cb_iter,
                                  .ud = pl};
    if (!(pl->scr = ea__screen_alloc(&nlp))) return EA_ERR_NOMEM;
  }
  pl->ip = ea__screen_problem(pl->scr, pl->xl, pl->xu);
  if (!pl->ip) return EA_ERR_BACKEND;
  AddIpoptStrOption(pl->ip, "sb", "yes");
  AddIpoptIntOption(pl->ip, "print_level", t->solver.print_level);
  AddIpoptStrOption(pl->ip, "linear_solver", "mumps");
  /* The max-transversal permutation only costs MUMPS analysis time on these
   * KKT systems (8 -> 2 ms at 100 knots); the ordering is chosen per solve
   * (ea__plan_solve_once). */
  AddIpoptIntOption(pl->ip, "mumps_permuting_scaling", 0);
  /* Iterative refinement only when a solve's residual asks for it (Ipopt's default forces
   * one step per solve: a back solve and a residual each): the same iterations on
   * bench_plan, bench_dyn and every test, plans equal to 1e-9 relative; the paper line's
   * cold solve 28.4 -> 24.7 ms (bench_plan, medians of 7), the at-rest one ~3 % */
  AddIpoptIntOption(pl->ip, "min_refinement_steps", 0);
  AddIpoptStrOption(pl->ip, "hessian_approximation", pl->hess_exact ? "exact" : "limited-memory");
  AddIpoptNumOption(pl->ip, "tol", t->solver.tol);
  AddIpoptNumOption(pl->ip, "constr_viol_tol", t->solver.constr_tol);
  /* L-BFGS stalls at a dual infeasibility of ~1e-5 on these problems: accept
   * a plan whose objective no longer moves, primal feasibility kept strict. */
  AddIpoptNumOption(pl->ip, "acceptable_tol", fmax(1e-4, t->solver.tol));
  AddIpoptIntOption(pl->ip, "acceptable_iter", 8);
  AddIpoptNumOption(pl->ip, "acceptable_constr_viol_tol", fmax(1e-9, t->solver.constr_tol));
  AddIpoptNumOption(pl->ip, "acceptable_obj_change_tol", 1e-8);
  AddIpoptIntOption(pl->ip, "max_iter", t->solver.max_iter);
  /* Ipopt relaxes bounds in its scaled space; the acceleration rows are
   * scaled down by ~1/h^2, so the default 1e-8 became ~1e-6 of a limit. A
   * plan must hold its limits: no relaxation. */
  AddIpoptNumOption(pl->ip, "bound_relax_factor", 0.0);
  return EA_OK;
}

ea_status_t ea_planner_alloc(const ea_task_t *task, ea_planner_t **out, ea_error_t *err) {
  if (!task || !out) return ea_error_set(err, EA_ERR_ARG, "ea_planner_alloc: NULL argument");
  *out = NULL;
  ea_planner_t *pl = calloc(1, sizeof *pl);
  if (!pl) return ea_error_set(err, EA_ERR_NOMEM, "out of memory");
  pl->task = *task;
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
  ea_status_t st = ea_shooter_alloc(&t->arm, NULL, &pl->sh, err);
  if (st) {
    ea_planner_free(pl);
    return st;
  }
  ea__derive(pl);
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
  ea__plan_schedule(pl, 0.0);
  ea__plan_layout(pl);
  ea__acc_scale(pl);
  if ((st = ea__plan_freq_build(pl, err))) {
    ea_planner_free(pl);
    return st;
  }
  pl->m = ea__build_rows(pl);
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
    goto nomem;
  ea__build_rows(pl);
  ea__bounds(pl);
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

/* ---------------------------------------------------------------------- */
/* Updates of a live planner (replanning)                                   */
/* ---------------------------------------------------------------------- */

/* Why task t cannot be solved by pl's transcription (NULL: it can). */
static const char *ea__struct_differs(const ea_planner_t *pl, const ea_task_t *t) {
  const ea_task_t *o = &pl->task;
  const ea_task_limits_t *a = &o->limits, *b = &t->limits;
  const double la[7] = {a->cable_speed_max,       a->cable_accel_max, a->cable_angle_speed_max,
                        a->cable_angle_accel_max, a->base_speed_max,  a->base_accel_max,
                        a->shoulder_speed_max};
  const double lb[7] = {b->cable_speed_max,       b->cable_accel_max, b->cable_angle_speed_max,
                        b->cable_angle_accel_max, b->base_speed_max,  b->base_accel_max,
                        b->shoulder_speed_max};
  if (!(t->start.cable_length > 0) || !(t->goal.cable_length > 0))
    return "task is not checked (ea_task_check)";
  if (t->knots != o->knots) return "knot count";
  if (t->n_via != o->n_via) return "number of via points";
  if (t->path != o->path) return "path kind";
  if (t->objective != o->objective) return "objective";
  if (t->dynamics.modes != o->dynamics.modes || t->dynamics.grid[0] != o->dynamics.grid[0] ||
      t->dynamics.grid[1] != o->dynamics.grid[1] ||
      (t->dynamics.residual_m > 0) != (o->dynamics.residual_m > 0) ||
      isfinite(t->dynamics.max_tip_deviation_m) != isfinite(o->dynamics.max_tip_deviation_m) ||
      t->dynamics.robust_tip_mass != o->dynamics.robust_tip_mass ||
      t->dynamics.robust_EI != o->dynamics.robust_EI ||
      (t->dynamics.modes && t->payload_kg != o->payload_kg))
    return "dynamics (modes, grid, residual or deviation limit, robust models, payload)";
  if (t->base_moves != o->base_moves) return "base motion (base variables)";
  if (isnan(t->duration_s) != isnan(o->duration_s)) return "free/fixed duration";
  if (t->limits.continuous_acceleration != o->limits.continuous_acceleration)
    return "acceleration continuity";
  if (t->solver.hessian_exact != o->solver.hessian_exact) return "Hessian mode";
  if ((t->solver.regularization > 0.0) != (o->solver.regularization > 0.0))
    return "regularization term";
  for (int i = 0; i < 7; ++i)
    if (isfinite(la[i]) != isfinite(lb[i])) return "set of finite speed/acceleration limits";
  if (!ea_arm_equal(&t->arm, &o->arm)) return "arm";
  if (pl->fm) return "task with a frequency model (built for the old task's region)";
  return NULL;
}

ea_status_t ea_planner_update(ea_planner_t *pl, const ea_task_t *task, ea_error_t *err) {
  if (!pl || !task) return ea_error_set(err, EA_ERR_ARG, "ea_planner_update: NULL argument");
  const char *why = ea__struct_differs(pl, task);
  if (why)
    return ea_error_set(err, EA_ERR_ARG,
                        "ea_planner_update: %s differs from the planner's; the transcription "
                        "would change: build a new planner (ea_planner_alloc)",
                        why);
  /* A segment that becomes (or stops being) a point changes the path rows. */
  unsigned char deg[EA_TASK_MAX_VIA + 1];
  for (int j = 0; j < pl->n_seg; ++j)
    deg[j] = pl->segLen[j] > 1e-9;
  const double tip_mass = pl->tip_mass;
  const ea_task_t old = pl->task;
  int vk_old[EA_TASK_MAX_VIA + 2];
  memcpy(vk_old, pl->via_knot, sizeof vk_old);
  pl->task = *task;
  ea__derive(pl);
  /* The path transcription places the via knots as a cold planner of the new task would (its
   * rows and their structure do not depend on them): a kept via knot fixes the time at which
   * the plan passes the via to the old task's fraction of t_f (a via moved 10 mm replanned
   * 1.1-3.3 % slower than a cold plan). The knot transcription keeps them: its path rows
   * (lines with dynamics) follow the knots, and its predictor shifts the old plan along the old
   * via knots (a free path with its via moved 10 mm replanned 2.9 % faster than cold, whose
   * estimate placed the via knot worse). */
  if (pl->pp)
    ea__plan_layout(pl);
  else
    ea__plan_segments(pl);
  for (int j = 0; j < pl->n_seg; ++j)
    if (deg[j] != (pl->segLen[j] > 1e-9) && pl->task.path != EA_TASK_PATH_FREE) {
      pl->task = old;
      ea__derive(pl);
      memcpy(pl->via_knot, vk_old, sizeof vk_old);
      ea__plan_segments(pl);
      return ea_error_set(err, EA_ERR_ARG,
                          "ea_planner_update: path segment %d %s a point: the path rows would "
                          "change; build a new planner",
                          j, deg[j] ? "becomes" : "stops being");
    }
  ea__build_rows(pl);
  ea__bounds(pl);
  ea__plan_terms_setup(pl);
  if (pl->hess_exact)
    for (int i = 0; i < pl->n_orows; ++i)
      if (pl->task.objective == EA_TASK_MIN_TIME) pl->oweight[i] = pl->task.solver.regularization;
  if (pl->tip_mass != tip_mass) memset(pl->kvalid, 0, (size_t)pl->N);
  pl->cache_val = pl->cache_sens = 0;
  ea_status_t st = ea__pp_update(pl, err);
  if (st) return st;
  if (pl->have_solution) pl->updated = 1;
  return ea_error_set(err, EA_OK, "ok");
}

/* Copy of the planner's task with one change, checked, then the update. */
static ea_status_t ea__update_checked(ea_planner_t *pl, ea_task_t *t, ea_error_t *err) {
  const ea_status_t st = ea_task_check(t, err);
  if (st) return st;
  return ea_planner_update(pl, t, err);
}

ea_status_t ea_planner_update_goal(ea_planner_t *pl, const ea_task_point_t *goal, ea_error_t *err) {
  if (!pl || !goal) return ea_error_set(err, EA_ERR_ARG, "ea_planner_update_goal: NULL argument");
  ea_task_t t = pl->task;
  t.goal = *goal;
  return ea__update_checked(pl, &t, err);
}

ea_status_t ea_planner_update_start(ea_planner_t *pl, const ea_task_point_t *start,
                                    ea_error_t *err) {
  if (!pl || !start) return ea_error_set(err, EA_ERR_ARG, "ea_planner_update_start: NULL argument");
  ea_task_t t = pl->task;
  t.start = *start;
  return ea__update_checked(pl, &t, err);
}

ea_status_t ea_planner_update_payload(ea_planner_t *pl, double payload_kg, ea_error_t *err) {
  if (!pl) return ea_error_set(err, EA_ERR_ARG, "ea_planner_update_payload: NULL planner");
  ea_task_t t = pl->task;
  t.payload_kg = payload_kg;
  t.payload_factor = NAN;
  return ea__update_checked(pl, &t, err);
}

ea_status_t ea_planner_update_limits(ea_planner_t *pl, const ea_task_limits_t *limits,
                                     ea_error_t *err) {
  if (!pl || !limits)
    return ea_error_set(err, EA_ERR_ARG, "ea_planner_update_limits: NULL argument");
  ea_task_t t = pl->task;
  t.limits = *limits;
  return ea__update_checked(pl, &t, err);
}

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

static void ea__stats(ea_planner_t *pl, const double *x, ea_plan_info_t *info) {
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

static const char *ea__ipopt_name(int s) {
  switch (s) {
  case Solve_Succeeded:
    return "Solve_Succeeded";
  case Solved_To_Acceptable_Level:
    return "Solved_To_Acceptable_Level";
  case Infeasible_Problem_Detected:
    return "Infeasible_Problem_Detected";
  case Search_Direction_Becomes_Too_Small:
    return "Search_Direction_Becomes_Too_Small";
  case Diverging_Iterates:
    return "Diverging_Iterates";
  case User_Requested_Stop:
    return "User_Requested_Stop (time limit)";
  case Feasible_Point_Found:
    return "Feasible_Point_Found";
  case Maximum_Iterations_Exceeded:
    return "Maximum_Iterations_Exceeded";
  case Restoration_Failed:
    return "Restoration_Failed";
  case Error_In_Step_Computation:
    return "Error_In_Step_Computation";
  case Maximum_CpuTime_Exceeded:
    return "Maximum_CpuTime_Exceeded";
  case Not_Enough_Degrees_Of_Freedom:
    return "Not_Enough_Degrees_Of_Freedom";
  case Invalid_Problem_Definition:
    return "Invalid_Problem_Definition";
  case Invalid_Option:
    return "Invalid_Option";
  case Invalid_Number_Detected:
    return "Invalid_Number_Detected";
  default:
    return "Ipopt_Internal_Error";
  }
}

/* Polish the statics of every knot (Newton on T, theta0, kappa0 at the
 * plan's L_c, alpha) so that each knot holds to the statics tolerance
 * whatever Ipopt's; the bounds are kept (a polished value outside them is
 * caught by the final check). */
static void ea__polish(ea_planner_t *pl, double *x) {
  ea_statics_settings_t set;
  ea_statics_settings_default(&set);
  set.allow_negative_tension = 1;
  set.max_cont_steps = 0;
  for (int k = 0; k < pl->N; ++k) {
    const double *gk = pl->g + 3 * k; /* Ipopt's constraint values at x */
    /* only where the final check (1e-9) needs it: a polished theta0 moves
     * the theta0 spline's accelerations by 6 dtheta0 / h^2 */
    if (fmax(fabs(gk[0]), fmax(fabs(gk[1]), fabs(gk[2]))) <= 5e-10) continue;
    const double guess[EA_NP] = {x[EA__IQ(pl, k, 1)], x[EA__IP(pl, k, 0)], x[EA__IP(pl, k, 1)],
                                 x[EA__IP(pl, k, 2)]};
    ea_statics_problem_t prob = ea_statics_problem_cable(x[EA__IQ(pl, k, 0)], guess[0]);
    ea_statics_solution_t sol;
    if (ea_statics_solve(pl->sh, &prob, &set, guess, &sol, NULL) != EA_OK ||
        sol.branch != EA_BRANCH_WARM)
      continue;
    double d = 0.0;
    for (int j = 1; j < EA_NP; ++j)
      d = fmax(d, fabs(sol.p[j] - guess[j]));
    if (d > 1e-6) continue; /* not a polish: keep Ipopt's point */
    for (int j = 1; j < EA_NP; ++j)
      x[EA__IP(pl, k, j - 1)] = sol.p[j];
  }
}

/* Is x (with the multipliers in pl->mult_*) already a KKT point to the
 * solver's tolerances (unscaled, so at least as strict as Ipopt's own test
 * at its first iterate)? A warm start from the planner's own solution of
 * the unchanged problem then needs no Ipopt solve: Ipopt would only push
 * the point into the interior and walk back. Primal: rows and bounds within
 * max(constr_viol_tol, 1e-9) (Ipopt's acceptable level, which the plan's
 * final check also uses); dual: |grad f + J' lambda - z_L + z_U| <= tol;
 * complementarity of every bound and inequality row <= tol. */
static int ea__kkt_ok_tol(ea_planner_t *pl, const double *x, double dtol) {
  const ea_task_t *t = &pl->task;
  const double ptol = fmax(1e-9, t->solver.constr_tol);
  pl->cache_val = pl->cache_sens = 0;
  if (ea__plan_eval_g(pl, x, pl->g)) return 0;
  for (int i = 0; i < pl->m; ++i) {
    if (pl->g[i] < pl->gl[i] - ptol || pl->g[i] > pl->gu[i] + ptol) return 0;
    if (pl->gl[i] == pl->gu[i]) continue;
    /* Ipopt's sign: lambda > 0 at the upper bound, < 0 at the lower */
    const double lam = pl->mult_g[i];
    const double gap = lam > 0 ? pl->gu[i] - pl->g[i] : pl->g[i] - pl->gl[i];
    if (fabs(lam) * fmin(gap, 1e19) > dtol) return 0;
  }
  double *r = pl->kkt_r;
  memset(r, 0, (size_t)pl->n * sizeof *r);
  for (int i = 0; i < pl->n_terms; ++i)
    pl->terms[i].grad(pl, x, pl->terms[i].weight, r);
  ea__plan_jac(pl, x, NULL, NULL, pl->jval);
  for (int e = 0; e < pl->nnz; ++e)
    r[pl->jcol[e]] += pl->jval[e] * pl->mult_g[pl->irow[e]];
  for (int i = 0; i < pl->n; ++i) {
    if (x[i] < pl->xl[i] - ptol || x[i] > pl->xu[i] + ptol) return 0;
    if (pl->xl[i] == pl->xu[i]) continue; /* fixed: Ipopt removes it */
    if (fabs(r[i] - pl->mult_xl[i] + pl->mult_xu[i]) > dtol) return 0;
    if (pl->mult_xl[i] * fmin(x[i] - pl->xl[i], 1e19) > dtol ||
        pl->mult_xu[i] * fmin(pl->xu[i] - x[i], 1e19) > dtol)
      return 0;
  }
  return 1;
}

static int ea__kkt_ok(ea_planner_t *pl, const double *x) {
  return ea__kkt_ok_tol(pl, x, pl->task.solver.tol);
}

/* ---------------------------------------------------------------------- */
/* Solve                                                                    */
/* ---------------------------------------------------------------------- */

ea_status_t ea__plan_solve_once(ea_planner_t *pl, ea_plan_start_t start, const ea_traj_t *prev,
                                ea_plan_info_t *info_out, ea_error_t *err);

static ea_status_t ea__duration_probe(ea_planner_t *pl, ea_plan_info_t *info, ea_error_t *err);

/* Most re-solves with tightened knot bounds for limits between the knots. */
#define EA__BW_PASSES 4

/* A solve, then the limits between the knots (ea__plan_between): where one
 * is exceeded, the bounds at that interval's knots are tightened by 1.5 x
 * the excess and the plan is re-solved from itself, until every limit
 * holds (docs/planner.md, "Limits between the knots"). */
static ea_status_t ea__solve_checked(ea_planner_t *pl, ea_plan_start_t start, const ea_traj_t *prev,
                                     ea_plan_info_t *info_out, ea_error_t *err) {
  ea_plan_info_t local, *info = info_out ? info_out : &local;
  ea_status_t st = ea__plan_solve_once(pl, start, prev, info, err);
  if (st && !pl->has_tf && !pl->task.solver.derivative_test &&
      (info->ipopt_status == Infeasible_Problem_Detected ||
       info->ipopt_status == Restoration_Failed))
    return ea__duration_probe(pl, info, err);
  if (st || pl->task.solver.derivative_test) return st;
  int iters = info->iterations, newton = info->newton_steps, pass = 0;
  int resolves = info->screen_resolves;
  double tt = info->time_total_s, worst = -INFINITY;
  char msg[160] = "";
  for (;; ++pass) {
    const double t0 = ea__mono_s();
    const int n = ea__plan_between(pl, pl->x_sol, &worst, msg, sizeof msg);
    tt += ea__mono_s() - t0;
    if (!(worst > 0.0)) break;
    if (!n || pass == EA__BW_PASSES) {
      pl->have_solution = 0;
      info->status = EA_ERR_NOCONV;
      info->iterations = iters;
      info->newton_steps = newton;
      info->screen_resolves = resolves;
      info->time_total_s = tt;
      info->between_passes = pass;
      snprintf(info->message, sizeof info->message,
               "the planner did not converge: %s (relative %.3g) after %d re-solves with the "
               "knot bounds tightened%s",
               msg, worst, pass, n ? "; use more knots" : " (at pinned knots)");
      return ea_error_set(err, info->status, "%s", info->message);
    }
    pl->refining = 1;
    st = ea__plan_solve_once(pl, EA_PLAN_WARM, NULL, info, err);
    iters += info->iterations;
    newton += info->newton_steps;
    resolves += info->screen_resolves;
    tt += info->time_total_s;
    if (st) { /* from the tightened problem's cold guess */
      st = ea__plan_solve_once(pl, EA_PLAN_COLD, NULL, info, err);
      iters += info->iterations;
      resolves += info->screen_resolves;
      tt += info->time_total_s;
    }
    pl->refining = 0;
    if (st) {
      info->iterations = iters;
      info->newton_steps = newton;
      info->screen_resolves = resolves;
      info->time_total_s = tt;
      info->between_passes = pass + 1;
      return st;
    }
  }
  info->iterations = iters;
  info->newton_steps = newton;
  info->screen_resolves = resolves;
  info->time_total_s = tt;
  info->between_passes = pass;
  if (pass)
    snprintf(info->message, sizeof info->message,
             "plan found: duration %.6g s, %d iterations (%d re-solves for limits between the "
             "knots), min tension margin %.4g N, peak shoulder torque %.4g N m",
             info->duration_s, info->iterations, pass, info->min_tension_margin_N,
             info->peak_shoulder_torque_Nm);
  return ea_error_set(err, EA_OK, "%s", info->message);
}

/* A fixed-duration task Ipopt found (locally) infeasible: the real
 * shortfall is the duration. The same task as min_time gives the shortest
 * admissible duration under the same limits: longer than the task's ->
 * infeasible by that much; not longer -> the task is feasible and the solver
 * failed (EA_ERR_NOCONV). */
static ea_status_t ea__duration_probe(ea_planner_t *pl, ea_plan_info_t *info, ea_error_t *err) {
  ea_task_t t = pl->task;
  const double want = t.duration_s;
  t.objective = EA_TASK_MIN_TIME;
  t.duration_s = NAN;
  t.time_weight = NAN;
  ea_planner_t *pr = NULL;
  ea_plan_info_t pi;
  ea_error_t e2 = {0};
  ea_status_t st = ea_task_check(&t, &e2);
  if (!st) st = ea_planner_alloc(&t, &pr, &e2);
  if (!st) st = ea_planner_solve(pr, EA_PLAN_COLD, NULL, &pi, &e2);
  ea_planner_free(pr);
  info->time_total_s += st ? 0.0 : pi.time_total_s;
  if (st == EA_ERR_INFEASIBLE) {
    snprintf(info->message, sizeof info->message,
             "the task is infeasible for any duration: the same task in minimum time: %.400s",
             e2.msg);
    info->status = EA_ERR_INFEASIBLE;
  } else if (st) {
    return ea_error_set(err, info->status, "%s", info->message); /* keep the first verdict */
  } else if (pi.duration_s > want) {
    snprintf(info->message, sizeof info->message,
             "the task is infeasible: duration_s %.6g s is %.4g s shorter than the shortest "
             "admissible duration %.6g s under the same limits (minimum-time plan, %d knots)",
             want, pi.duration_s - want, pi.duration_s, pl->N);
    info->status = EA_ERR_INFEASIBLE;
  } else {
    snprintf(info->message, sizeof info->message,
             "the planner did not converge (Ipopt: %s after %d iterations); the task is "
             "feasible: a minimum-time plan under the same limits takes %.6g s <= duration_s "
             "%.6g s",
             info->ipopt_status_name, info->iterations, pi.duration_s, want);
    info->status = EA_ERR_NOCONV;
  }
  return ea_error_set(err, info->status, "%s", info->message);
}

ea_status_t ea_planner_solve(ea_planner_t *pl, ea_plan_start_t start, const ea_traj_t *prev,
                             ea_plan_info_t *info_out, ea_error_t *err) {
  if (!pl) return ea_error_set(err, EA_ERR_ARG, "ea_planner_solve: NULL planner");
  return ea__solve_checked(pl, start, prev, info_out, err);
}

/* The phases of one solve (ea__plan_solve_once): the info's defaults, the start point
 * (knot transcription), Ipopt's options for that start, Ipopt itself, and the outcome:
 * the plan accepted and kept, or the failure classified. */

/* The info's defaults and the planner's per-solve counters; returns the solve's start time. */
static double ea__solve_begin(ea_planner_t *pl, ea_plan_info_t *info) {
  memset(info, 0, sizeof *info);
  info->deriv_errors = -1;
  info->min_first_frequency_hz = info->max_modal_deflection_m = NAN;
  info->time_freq_model_s = pl->fm ? pl->fm->info.time_s : 0.0;
  info->n_var = pl->n;
  info->n_con = pl->m;
  info->nnz_jac = pl->nnz;
  info->threads = ea__pp_threads(pl);
  info->status = EA_ERR_NOCONV;
  const double t0 = ea__mono_s();
  pl->t_start = t0;
  pl->max_time = pl->task.solver.max_time_s;
  pl->t_statics = pl->t_callbacks = 0.0;
  pl->iter = 0;
  pl->info = info;
  pl->cache_val = pl->cache_sens = 0;
  return t0;
}

/* A solve that stops before its outcome (no start point, a failed path solve). */
static ea_status_t ea__solve_abort(ea_planner_t *pl, ea_plan_info_t *info, ea_status_t st,
                                   double t0, const ea_error_t *err) {
  info->status = st;
  snprintf(info->message, sizeof info->message, "%s", err ? err->msg : ea_strerror(st));
  info->time_total_s = ea__mono_s() - t0;
  pl->info = NULL;
  return st;
}

/* The start point in pl->x (knot transcription), inside the bounds. */
/* The last plan's multipliers as the current ones (a warm start's). */
static void ea__mult_from_sol(ea_planner_t *pl) {
  memcpy(pl->mult_g, pl->mult_g_sol, (size_t)pl->m * sizeof *pl->x);
  memcpy(pl->mult_xl, pl->mult_xl_sol, (size_t)pl->n * sizeof *pl->x);
  memcpy(pl->mult_xu, pl->mult_xu_sol, (size_t)pl->n * sizeof *pl->x);
}

static ea_status_t ea__solve_start_point(ea_planner_t *pl, ea_plan_start_t start,
                                         const ea_traj_t *prev, int warm, int replan,
                                         ea_plan_info_t *info, ea_error_t *err) {
  ea_status_t st = EA_OK;
  if (warm) {
    memcpy(pl->x, pl->x_sol, (size_t)pl->n * sizeof *pl->x);
    ea__mult_from_sol(pl);
    /* the task changed (ea_planner_update): shift the solution along */
    /* A prescribed path: the cold guess (statics along the straight
     * interpolation) proves infeasibility when the new path leaves the
     * workspace; the shifted plan alone would not (its knots can step over
     * the inadmissible part of the line). */
    if (replan && pl->task.path != EA_TASK_PATH_FREE) st = ea__plan_guess(pl, pl->x0, info, err);
    if (replan && !st) st = ea__plan_predict(pl, &pl->task_sol, pl->x, 1);
  } else if (start == EA_PLAN_FROM_TRAJ) {
    st = ea__plan_guess_traj(pl, prev, pl->x, err);
  } else {
    st = ea__plan_guess(pl, pl->x, info, err);
  }
  if (!st && !warm && start == EA_PLAN_COLD)
    ea__plan_dyn_guess(pl, pl->x); /* stretched inside its limits, modal states along it */
  else if (!st && (!warm || replan))
    ea__plan_dyn_fill(pl, pl->x); /* modal states along the guess */
  if (st) return st;
  for (int i = 0; i < pl->n; ++i)
    pl->x[i] = fmax(pl->xl[i], fmin(pl->xu[i], pl->x[i]));
  return EA_OK;
}

/* Ipopt's options for this start; with the derivative test, its output file's name in
 * tmpl ("" when none could be made). */
static void ea__solve_options(ea_planner_t *pl, int warm, int replan, char tmpl[64]) {
  AddIpoptStrOption(pl->ip, "warm_start_init_point", warm ? "yes" : "no");
  /* MUMPS ordering: AMD for every solve. SCOTCH gave fewer, larger fronts (numeric
   * factorization 1.6 instead of 2.5 ms at 100 knots) but draws on a process-global random
   * state: a plan depended on what the process had solved before (a study's CSV changed with
   * the order of its cases, 1e-8 in durations, one Ipopt iteration more or less). AMD, AMF,
   * PORD and METIS are deterministic; the whole cold solve took the same time with each. */
  AddIpoptIntOption(pl->ip, "mumps_pivot_order", 0);
  ea__ipopt_start_options(pl->ip, warm, replan || pl->refining);
  if (!pl->task.solver.derivative_test) return;
  ea__deriv_test_options(pl->ip, pl->task.solver.derivative_test == 2 && pl->hess_exact == 1, tmpl);
}

static enum ApplicationReturnStatus ea__solve_ipopt_run(ea_planner_t *pl, ea_plan_start_t start,
                                                        int warm, double mono_mu, double *obj,
                                                        int *iters);

/* A start from which the barrier decreases monotonically (near-optimal: a cold guess timed
 * along the path, a plan file; with dynamics any cold start; ea__solve_ipopt). */
static int ea__mono_start(const ea_planner_t *pl, ea_plan_start_t start, int warm) {
  return !warm &&
         (pl->rom ? start == EA_PLAN_COLD
                  : start == EA_PLAN_FROM_TRAJ || (start == EA_PLAN_COLD && pl->guess_timed));
}

/* A cold start of the knot transcription solved by the own interior point (plan_ipm.c) where
 * Ipopt would start its monotone barrier (a cold guess timed along the path, a plan file; with
 * dynamics any cold start) from the same mu_init, taken when it passes the KKT test of the
 * whole problem (ea__kkt_ok). 1: pl->x, pl->mult_* and *obj are the plan's (*iters its
 * iterations); 0: pl->x is the start again (info->ipm_fallback when it ran). */
static int ea__solve_ipm(ea_planner_t *pl, ea_plan_start_t start, int warm, int replan,
                         double mono_mu, ea_plan_info_t *info, double *obj, int *iters) {
  const ea_task_t *t = &pl->task;
  /* a replan with dynamics from the cold guess: bench_dyn's at-rest paper line with its goal
   * moved 5 mm took Ipopt 14 iterations from the shifted plan, and more time than the cold
   * plan by the own interior point */
  const int from_cold = warm && replan && pl->rom;
  if (!(from_cold || ea__mono_start(pl, start, warm)) || t->solver.nlp_ipopt ||
      t->solver.derivative_test || !pl->hess_exact)
    return 0;
  /* not on free paths, nor with the corner models of robust rest: there its candidates failed
   * the KKT test often enough to cost more than they saved (test_plan_sweep's free paths: 27
   * of 98 after 40 iterations; the pick-place-3d example 229 ms against Ipopt's 55, the robust
   * paper line 1.9 s against 1.2 s; the partial Hessian lacks the statics rows' curvature and
   * the own interior point has no line search or second-order correction to make up for it) */
  if (t->path == EA_TASK_PATH_FREE || pl->M > 1 || ea__plan_hess_pattern(pl)) return 0;
  if (!pl->asn) {
    const ea__asn_nlp_t nlp = {.n = pl->n,
                               .m = pl->m,
                               .nnz_j = pl->nnz,
                               .nnz_h = pl->nnz_h,
                               .xl = pl->xl,
                               .xu = pl->xu,
                               .gl = pl->gl,
                               .gu = pl->gu,
                               .jrow = pl->irow,
                               .jcol = pl->jcol,
                               .hrow = pl->hirow,
                               .hcol = pl->hjcol,
                               .f = ea__cb_f,
                               .grad_f = ea__cb_grad_f,
                               .g = ea__cb_g,
                               .jac = ea__cb_jac,
                               .h = ea__cb_h,
                               .ud = pl,
                               .hess_last = pl->K == 0};
    if (!(pl->asn = ea__asn_alloc(&nlp))) return 0;
  }
  /* with Ipopt's acceptable termination (the partial Hessian lacks the statics rows'
   * curvature: on a third of test_plan_sweep's free paths the iterates stalled with the
   * stationarity near 3e-7, where Ipopt stops by this rule), its candidate verified to
   * acc_tol; the slacks pushed as the path transcription's (plan_path.c) */
  ea__ipm_opt_t o;
  ea__plan_ipm_opt(pl, mono_mu, 1e-2, &o);
  memcpy(pl->xstart, pl->x, (size_t)pl->n * sizeof *pl->x);
  ea_error_t e = {0};
  if (from_cold && ea__solve_start_point(pl, EA_PLAN_COLD, NULL, 0, 0, info, &e)) {
    memcpy(pl->x, pl->xstart, (size_t)pl->n * sizeof *pl->x); /* no cold guess: Ipopt's start */
    return 0;
  }
  const int rc = ea__ipm_solve(pl->asn, &o, pl->x, pl->mult_g, pl->mult_xl, pl->mult_xu,
                               &info->ipm_iterations);
  const int ok = rc >= 0 && ea__kkt_ok_tol(pl, pl->x, rc ? o.acc_tol : t->solver.tol);
  info->ipm_fallback = !ok;
  if (!ok) { /* Ipopt's start again */
    memcpy(pl->x, pl->xstart, (size_t)pl->n * sizeof *pl->x);
    if (warm) ea__mult_from_sol(pl);
    return 0;
  }
  *iters = info->ipm_iterations;
  ea__cb_f(pl->n, pl->x, FALSE, obj, pl);
  return 1;
}

/* Ipopt from pl->x (knot transcription); a warm start that already is the solution takes
 * no iteration. Ipopt sees the rows that can matter (plan_screen.c): selected at the start,
 * and if a row left out reaches its limit at the solution, solved again from the start with
 * it (info->screen_resolves). Returns Ipopt's status; *obj, *iters (every attempt) and
 * *t_ipopt [s]. */
static enum ApplicationReturnStatus ea__solve_ipopt(ea_planner_t *pl, ea_plan_start_t start,
                                                    int warm, int replan, char tmpl[64],
                                                    ea_plan_info_t *info, double *obj, int *iters,
                                                    double *t_ipopt) {
  /* Barrier strategy: from a near-optimal start (a cold guess timed along
   * its path, or a previous plan) the monotone strategy with mu_init 1e-4
   * needs about one linear solve per iteration instead of the adaptive
   * strategy's three, in as many or fewer iterations (docs/planner.md). If
   * it fails, the solve is repeated from the same start with the adaptive
   * strategy, the default for every other start. With dynamics (knot transcription) from a
   * cold start, monotone from mu_init 1e-3 (bench_dyn, at-rest paper line: 66 instead of 89
   * iterations at 100 knots; at 200 knots the adaptive strategy failed after 500, monotone
   * converged in 111; 1e-2: 196 and 130; pick-place-3d 19 vs 20; measured with central-difference
   * defect Hessians, now forward: 79 and 96). */
  const double mono_mu = pl->rom ? 1e-3 : 1e-4;
  enum ApplicationReturnStatus rs = Internal_Error;
  const double ti = ea__mono_s();
  if (warm && !pl->task.solver.derivative_test && ea__kkt_ok(pl, pl->x)) {
    rs = Solve_Succeeded; /* the start is the solution: no Ipopt iteration */
    for (int i = 0; i < pl->n_terms; ++i)
      *obj += pl->terms[i].weight * pl->terms[i].value(pl, pl->x);
    pl->t_callbacks = ea__mono_s() - ti; /* not Ipopt's time */
  } else if (ea__solve_ipm(pl, start, warm, replan, mono_mu, info, obj, iters)) {
    rs = Solve_Succeeded; /* the own interior point's plan passed the KKT test */
  } else {
    /* not with dynamics: the at-rest paper line keeps every row anyway (each family has a row
     * near its limit at the cold guess), and test_rom_modes' plans took 1-2 iterations more */
    if (pl->task.solver.derivative_test || !pl->task.solver.screen_rows || pl->rom ||
        ea__plan_eval_g(pl, pl->x, pl->g))
      ea__screen_all(pl->scr);
    else
      ea__screen_select(pl->scr, pl->g, EA__SCREEN_BAND, pl->rfam, pl->nfam);
    memcpy(pl->xstart, pl->x, (size_t)pl->n * sizeof *pl->x);
    for (int round = 0;; ++round) {
      if (round) {
        memcpy(pl->x, pl->xstart, (size_t)pl->n * sizeof *pl->x);
        if (warm) {
          ea__mult_from_sol(pl);
        }
      }
      if (ea__ipopt_create(pl)) break;
      ea__solve_options(pl, warm, replan, tmpl);
      info->ipopt_rows = ea__screen_rows(pl->scr);
      rs = ea__solve_ipopt_run(pl, start, warm, mono_mu, obj, iters);
      if (!(rs == Solve_Succeeded || rs == Solved_To_Acceptable_Level) ||
          !ea__screen_grow(pl->scr, pl->g, EA__SCREEN_HOLD))
        break;
      info->screen_resolves++;
    }
  }
  *t_ipopt = ea__mono_s() - ti;
  return rs;
}

/* One Ipopt solve of pl->ip from pl->x: the monotone barrier from a near-optimal start, and if
 * it fails the adaptive one from the same start. */
static enum ApplicationReturnStatus ea__solve_ipopt_run(ea_planner_t *pl, ea_plan_start_t start,
                                                        int warm, double mono_mu, double *obj,
                                                        int *iters) {
  enum ApplicationReturnStatus rs = Internal_Error;
  int mono = ea__mono_start(pl, start, warm);
  if (mono) memcpy(pl->x0, pl->x, (size_t)pl->n * sizeof *pl->x);
  {
    for (;;) {
      AddIpoptStrOption(pl->ip, "mu_strategy", mono ? "monotone" : "adaptive");
      if (mono) AddIpoptNumOption(pl->ip, "mu_init", mono_mu);
      /* With dynamics from a cold start and one model the bound multipliers start at
       * mu_init / slack instead of 1 (at mu_init 1e-3 the constant 1 is far off the central
       * path): the at-rest paper line 28 -> 21 iterations, 200 knots 33 -> 24, payload 0.25
       * 27 -> 20, payload 0.5 27 -> 19, pick-place-3d 19 -> 18, the same durations. The
       * robust plans (corner models) keep 1: their first barrier phase backtracked with it
       * (up to 7 line-search trials, a regularised KKT system), 43 -> 47 iterations and 29 %
       * more time. Every dynamics cold start solves each barrier subproblem to 100 mu
       * instead of 10 mu: 1-2 iterations fewer (robust 43 -> 42), durations within 2e-7
       * (docs/planner.md). */
      AddIpoptStrOption(pl->ip, "bound_mult_init_method",
                        mono && pl->rom && pl->M == 1 ? "mu-based" : "constant");
      AddIpoptNumOption(pl->ip, "barrier_tol_factor", mono && pl->rom ? 100.0 : 10.0);
      pl->iter = 0;
      rs = ea__screen_solve(pl->scr, pl->ip, pl->x, pl->g, obj, pl->mult_g, pl->mult_xl,
                            pl->mult_xu);
      *iters += pl->iter;
      if (!mono || rs == Solve_Succeeded || rs == Solved_To_Acceptable_Level ||
          rs == User_Requested_Stop || pl->task.solver.derivative_test)
        break;
      mono = 0;
      memcpy(pl->x, pl->x0, (size_t)pl->n * sizeof *pl->x);
      AddIpoptNumOption(pl->ip, "mu_init", 0.1);
    }
  }
  return rs;
}

/* A solve that did not give an admissible plan: info's status and message. Only Ipopt's
 * converged restoration phase (a local minimum of the constraint violation that is not
 * zero) says "infeasible", and only with a violation well above the solver's tolerance; a
 * failed restoration phase proves nothing (docs/planner.md). */
static void ea__solve_failure(ea_plan_info_t *info, enum ApplicationReturnStatus rs,
                              double tol_viol) {
  const int infeasible = rs == Infeasible_Problem_Detected && info->max_violation > tol_viol;
  if (infeasible)
    info->status = EA_ERR_INFEASIBLE;
  else if (rs == Maximum_Iterations_Exceeded)
    info->status = EA_ERR_MAXITER;
  else if (rs == Invalid_Problem_Definition || rs == Invalid_Option || rs == Insufficient_Memory ||
           rs < -100)
    info->status = EA_ERR_BACKEND;
  else
    info->status = EA_ERR_NOCONV;
  if (infeasible)
    snprintf(info->message, sizeof info->message,
             "the task is locally infeasible (Ipopt: %s after %d iterations); at the point of "
             "least violation Ipopt found: %s",
             info->ipopt_status_name, info->iterations, info->worst);
  else
    snprintf(info->message, sizeof info->message,
             "the planner did not converge (Ipopt: %s after %d iterations%s); worst constraint "
             "at the last iterate: %s",
             info->ipopt_status_name, info->iterations,
             rs == Restoration_Failed || rs == Infeasible_Problem_Detected
                 ? "; not a proof that the task is infeasible"
                 : "",
             info->worst[0] ? info->worst : "none violated");
}

/* The outcome of Ipopt's run: the iterate polished and measured; an admissible plan becomes
 * the planner's solution, anything else a classified failure (info->status). */
static void ea__solve_outcome(ea_planner_t *pl, ea_plan_info_t *info,
                              enum ApplicationReturnStatus rs, double obj, int iters,
                              int path_mode) {
  info->ipopt_status = (int)rs;
  snprintf(info->ipopt_status_name, sizeof info->ipopt_status_name, "%s", ea__ipopt_name(rs));
  info->iterations = iters;
  info->objective = obj;
  const int solved = rs == Solve_Succeeded || rs == Solved_To_Acceptable_Level;
  if (solved) {
    if (!path_mode) { /* path mode: theta0 and its rates are the path spline's (1e-10) */
      ea__polish(pl, pl->x);
      ea__plan_theta0_rates(pl, pl->x); /* the spline of the polished theta0 */
    }
  }
  ea__stats(pl, pl->x, info);
  ea__plan_vib_stats(pl, pl->x, info);
  ea__plan_dyn_stats(pl, pl->x, info);
  info->time_freq_model_s = pl->fm ? pl->fm->info.time_s : 0.0;
  const double tol_viol = 1e-6;
  if (!(solved && info->max_violation <= tol_viol && info->max_statics_residual <= 1e-9)) {
    ea__solve_failure(info, rs, tol_viol);
    return;
  }
  info->status = EA_OK;
  memcpy(pl->x_sol, pl->x, (size_t)pl->n * sizeof *pl->x);
  memcpy(pl->mult_g_sol, pl->mult_g, (size_t)pl->m * sizeof *pl->x);
  memcpy(pl->mult_xl_sol, pl->mult_xl, (size_t)pl->n * sizeof *pl->x);
  memcpy(pl->mult_xu_sol, pl->mult_xu, (size_t)pl->n * sizeof *pl->x);
  pl->have_solution = 1;
  pl->updated = 0;
  pl->task_sol = pl->task;
  snprintf(info->message, sizeof info->message,
           "plan found: duration %.6g s, %d iterations, min tension margin %.4g N, peak "
           "shoulder torque %.4g N m",
           info->duration_s, info->iterations, info->min_tension_margin_N,
           info->peak_shoulder_torque_Nm);
}

ea_status_t ea__plan_solve_once(ea_planner_t *pl, ea_plan_start_t start, const ea_traj_t *prev,
                                ea_plan_info_t *info_out, ea_error_t *err) {
  ea_plan_info_t local, *info = info_out ? info_out : &local;
  const double t0 = ea__solve_begin(pl, info);
  ea_status_t st = EA_OK;
  const int path_mode = pl->pp && !pl->pp_off;
  const int warm = start == EA_PLAN_WARM && pl->have_solution;
  const int replan = warm && pl->updated;
  double obj = 0.0, t_ipopt = 0.0;
  int iters = 0;
  enum ApplicationReturnStatus rs = Internal_Error;
  if (path_mode) {
    /* the prescribed path in the path coordinate (plan_path.c): its own guess and Ipopt
     * problem; pl->x gets the plan in the knot layout */
    const double ti = ea__mono_s();
    st = ea__pp_solve(pl, start, prev, info, &rs, &obj, &iters, err);
    t_ipopt = ea__mono_s() - ti - info->time_guess_s; /* its guess is timed apart */
    if (st) return ea__solve_abort(pl, info, st, t0, err);
  } else {
    st = ea__solve_start_point(pl, start, prev, warm, replan, info, err);
    info->time_guess_s = ea__mono_s() - t0;
    if (st) return ea__solve_abort(pl, info, st, t0, err);
    char tmpl[64] = "";
    rs = ea__solve_ipopt(pl, start, warm, replan, tmpl, info, &obj, &iters, &t_ipopt);
    if (tmpl[0]) {
      info->deriv_errors = ea__deriv_errors(tmpl);
      remove(tmpl);
    }
  }
  ea__solve_outcome(pl, info, rs, obj, iters, path_mode);
  pl->cache_val = pl->cache_sens = 0;
  info->time_total_s = ea__mono_s() - t0;
  info->time_statics_s = pl->t_statics;
  info->time_ipopt_s = t_ipopt - pl->t_callbacks;
  info->time_rest_s =
      info->time_total_s - info->time_guess_s - info->time_statics_s - info->time_ipopt_s;
  pl->info = NULL;
  if (replan && info->status) {
    /* the shifted plan led nowhere: solve the changed task cold (its guess
     * also proves a prescribed path infeasible); both solves are counted */
    const int it = info->iterations;
    const double tw = info->time_total_s;
    st = ea__plan_solve_once(pl, EA_PLAN_COLD, NULL, info, err);
    info->iterations += it;
    info->time_total_s += tw;
    return st;
  }
  if (info->status) return ea_error_set(err, info->status, "%s", info->message);
  return ea_error_set(err, EA_OK, "%s", info->message);
}

ea_status_t ea_planner_set_terminal_modes(ea_planner_t *pl, const double *eta,
                                          const double *eta_rate, ea_error_t *err) {
  return ea_planner_set_terminal_modes_model(pl, 0, eta, eta_rate, err);
}

ea_status_t ea_planner_set_terminal_modes_model(ea_planner_t *pl, int model, const double *eta,
                                                const double *eta_rate, ea_error_t *err) {
  if (!pl) return ea_error_set(err, EA_ERR_ARG, "ea_planner_set_terminal_modes: NULL planner");
  if (model == 0 &&
      (!pl->rom || pl->task.dynamics.residual_m > 0 || pl->task.objective == EA_TASK_MIN_VIBRATION))
    return ea_error_set(err, EA_ERR_ARG,
                        "terminal modal targets need a task with dynamics that ends at rest "
                        "(residual_m 0, not min_vibration)");
  if (model != 0 &&
      (!pl->rom || model < 1 || model >= pl->M || pl->task.objective == EA_TASK_MIN_VIBRATION))
    return ea_error_set(err, EA_ERR_ARG,
                        "terminal target of model %d: the task has %d model%s (robust corners "
                        "1..4 need dynamics.robust, not min_vibration)",
                        model, pl->M, pl->M == 1 ? "" : "s");
  for (int i = 0; i < pl->Kper; ++i) { /* the model's modes */
    const double e = eta ? eta[i] : 0.0, ed = eta_rate ? eta_rate[i] : 0.0;
    if (!isfinite(e) || !isfinite(ed))
      return ea_error_set(err, EA_ERR_ARG,
                          "terminal modal target of mode %d (model %d) is not "
                          "finite",
                          i + 1, model);
  }
  for (int i = 0; i < pl->Kper; ++i) {
    const int c = model * pl->Kper + i;
    pl->dyn_target[c] = eta ? eta[i] : 0.0;
    pl->dyn_target[EA__DYN_MAX + c] = eta_rate ? eta_rate[i] : 0.0;
  }
  if (model > 0) return EA_OK; /* a corner's centre is in its row's value only */
  ea__bounds(pl);
  return EA_OK;
}
