/* Output of a plan: the trajectory (every column filled) and the JSON summary. The figure is
 * drawn by the CLI (planner/app). */
#include "ea_refine.h"
#include "ea_simulate.h"
#include "ipopt_impl.h"
#include "plan_impl.h"
#include "vib_impl.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

ea_status_t ea_planner_trajectory(const ea_planner_t *pl, ea_traj_t *tr, ea_error_t *err) {
  if (!pl || !tr) return ea_error_set(err, EA_ERR_ARG, "ea_planner_trajectory: NULL argument");
  if (!pl->have_solution)
    return ea_error_set(err, EA_ERR_ARG, "ea_planner_trajectory: no converged plan");
  if (pl->updated)
    return ea_error_set(err, EA_ERR_ARG,
                        "ea_planner_trajectory: the task changed (ea_planner_update) since the "
                        "last converged plan: no plan of the new task yet");
  const ea_task_t *t = &pl->task;
  const double *x = pl->x_sol;
  const int N = pl->N;
  ea_status_t st = ea_traj_alloc(tr, N);
  if (st) return ea_error_set(err, st, "out of memory");
  tr->payload_kg = t->payload_kg;
  tr->tip_mass_kg = pl->tip_mass;
  snprintf(tr->arm_file, sizeof tr->arm_file, "%s", t->arm_file);
  tr->arm_hash = ea_arm_hash(&t->arm);
  tr->has_arm_hash = 1;
  snprintf(tr->task, sizeof tr->task, "%s", t->file[0] ? t->file : t->name);
  snprintf(tr->status, sizeof tr->status, "EA_OK");
  const double tf = ea__plan_tf(pl, x);
  static const int qc[3] = {EA_TRAJ_cable_length, EA_TRAJ_cable_angle, EA_TRAJ_base_angle};
  static const int vc[3] = {EA_TRAJ_cable_length_rate, EA_TRAJ_cable_angle_rate,
                            EA_TRAJ_base_angle_rate};
  static const int ac[3] = {EA_TRAJ_cable_length_acc, EA_TRAJ_cable_angle_acc,
                            EA_TRAJ_base_angle_acc};
  for (int k = 0; k < N; ++k) {
    EA_TRAJ_AT(tr, k, EA_TRAJ_t) = tf * pl->s[k];
    for (int c = 0; c < 3; ++c) {
      if (c >= pl->nq) {
        EA_TRAJ_AT(tr, k, qc[c]) = pl->base_fixed;
        continue;
      }
      EA_TRAJ_AT(tr, k, qc[c]) = x[EA__IQ(pl, k, c)];
      EA_TRAJ_AT(tr, k, vc[c]) = x[EA__IV(pl, k, c)];
      double acc = 0.0;
      int na = 0;
      for (int i = k - 1; i <= k; ++i) {
        if (i < 0 || i + 1 >= N) continue;
        double a[2];
        const double h = tf * (pl->s[i + 1] - pl->s[i]);
        ea__plan_hermite_acc(x[EA__IQ(pl, i, c)], x[EA__IQ(pl, i + 1, c)], x[EA__IV(pl, i, c)],
                             x[EA__IV(pl, i + 1, c)], h, a, NULL);
        acc += i == k ? a[0] : a[1];
        ++na;
      }
      EA_TRAJ_AT(tr, k, ac[c]) = na ? acc / na : 0.0;
    }
    const double p[EA_NP] = {x[EA__IQ(pl, k, 1)], x[EA__IP(pl, k, 0)], x[EA__IP(pl, k, 1)],
                             x[EA__IP(pl, k, 2)]};
    double xL[EA_NX], S[EA_NX * EA_NP];
    if ((st = ea_shoot(pl->sh, p, xL, S)))
      return ea_error_set(err, st, "trajectory: shooting failed at knot %d", k);
    ea_traj_set_statics(tr, k, p, xL, t->arm.EI);
    /* theta0 rate: the C2 spline's (docs/trajectory-format.md) */
    EA_TRAJ_AT(tr, k, EA_TRAJ_theta0_rate) = x[EA__IW(pl, k)];
  }
  return ea_error_set(err, EA_OK, "ok");
}

/* The "refine" object: settings, outcome and every evaluation. */
static void ea__refine_json(ea_json_t *j, const ea_refine_info_t *r) {
  const ea_task_refine_t *s = &r->settings;
  ea_json_obj_begin(j, "refine");
  ea_json_str(j, "status", ea_status_name(r->status));
  ea_json_str(j, "message", r->message);
  ea_json_str(j, "method", ea_task_refine_method_name(s->method));
  ea_json_str(j, "by", ea_task_refine_by_name(s->by));
  ea_json_bool(j, "converged", r->converged);
  ea_json_str(j, "stop_reason", r->stop_reason);
  ea_json_num(j, "tolerance_m", s->tolerance_m);
  ea_json_int(j, "max_evaluations", s->max_evaluations);
  ea_json_num(j, "max_time_s", s->max_time_s);
  ea_json_int(j, "modes_adjusted", s->modes);
  ea_json_int(j, "model_modes", r->model_modes);
  ea_json_num(j, "max_duration_change", s->max_duration_change);
  ea_json_int(j, "seed", (long)s->seed);
  ea_json_obj_begin(j, "fe");
  ea_json_int(j, "elements", r->fe.elements);
  ea_json_str(j, "scheme", r->fe.scheme == EA_FE_SCHEME_GENALPHA ? "genalpha" : "energy");
  ea_json_num(j, "rho_inf", r->fe.rho_inf);
  ea_json_num(j, "dt_s", r->fe.dt);
  ea_json_num(j, "settle_s", r->fe.settle);
  ea_json_num(j, "damping_ratio", r->fe.damping_ratio);
  ea_json_obj_end(j);
  ea_json_int(j, "evaluations", r->n_evals);
  ea_json_int(j, "returned_evaluation", r->returned);
  ea_json_num(j, "duration_before_s", r->duration_before_s);
  ea_json_num(j, "residual_peak_before_m", r->residual_peak_before_m);
  ea_json_num(j, "residual_rms_before_m", r->residual_rms_before_m);
  ea_json_num(j, "duration_s", r->duration_s);
  ea_json_num(j, "residual_peak_m", r->residual_peak_m);
  ea_json_num(j, "residual_rms_m", r->residual_rms_m);
  ea_json_vec(j, "terminal_eta_sqrtkg_m", r->eta, r->model_modes * r->models);
  ea_json_vec(j, "terminal_eta_rate_sqrtkg_m_per_s", r->eta_rate, r->model_modes * r->models);
  /* per model: 0 the nominal, 1..4 the robust corners (FE at each model's arm) */
  ea_json_int(j, "models", r->models);
  ea_json_vec(j, "model_tip_mass_kg", r->model_tip_mass_kg, r->models);
  ea_json_vec(j, "model_EI_Nm2", r->model_EI_Nm2, r->models);
  ea_json_vec(j, "model_allowed_residual_peak_m", r->allowed_m, r->models);
  ea_json_vec(j, "model_residual_peak_before_m", r->model_residual_peak_before_m, r->models);
  ea_json_vec(j, "model_residual_peak_m", r->model_residual_peak_m, r->models);
  ea_json_num(j, "score_before", r->score_before);
  ea_json_num(j, "score", r->score);
  ea_json_num(j, "time_s", r->time_s);
  ea_json_num(j, "time_plan_s", r->time_plan_s);
  ea_json_num(j, "time_fe_s", r->time_fe_s);
  if (s->by != EA_TASK_REFINE_BY_FE) {
    ea_json_int(j, "model_evaluations", r->model_evals);
    ea_json_num(j, "time_model_s", r->time_model_s);
    ea_json_num(j, "model_only_residual_peak_m", r->model_only_peak_m);
  }
  if (s->method != EA_TASK_REFINE_NEWTON) ea_json_int(j, "nlopt_result", r->nlopt_result);
  ea_json_arr_begin(j, "evaluation_log");
  for (int i = 0; i < r->n_evals; ++i) {
    const ea_refine_eval_t *e = &r->evals[i];
    ea_json_obj_begin(j, NULL);
    ea_json_int(j, "index", i);
    ea_json_vec(j, "params_m", e->params_m, r->n_params);
    ea_json_vec(j, "eta_sqrtkg_m", e->eta, r->model_modes * r->models);
    ea_json_vec(j, "eta_rate_sqrtkg_m_per_s", e->eta_rate, r->model_modes * r->models);
    ea_json_str(j, "plan_status", ea_status_name(e->plan_status));
    ea_json_int(j, "plan_iterations", e->plan_iterations);
    if (s->by != EA_TASK_REFINE_BY_FE) ea_json_bool(j, "by_model", e->by_model);
    ea_json_num(j, "plan_time_s", e->plan_time_s);
    ea_json_num(j, "duration_s", e->duration_s);
    ea_json_str(j, "fe_status", ea_status_name(e->fe_status));
    ea_json_num(j, "residual_peak_m", e->residual_peak_m);
    ea_json_num(j, "residual_rms_m", e->residual_rms_m);
    ea_json_vec(j, "model_residual_peak_m", e->model_residual_peak_m, r->models);
    ea_json_vec(j, "model_residual_rms_m", e->model_residual_rms_m, r->models);
    ea_json_num(j, "score", e->score);
    ea_json_vec(j, "fitted_m", e->fitted_m, 2 * r->model_modes * r->models);
    ea_json_vec(j, "predicted_m", e->predicted_m, 2 * r->model_modes * r->models);
    ea_json_num(j, "fe_time_s", e->fe_time_s);
    ea_json_num(j, "elapsed_s", e->elapsed_s);
    ea_json_bool(j, "accepted", e->accepted);
    ea_json_bool(j, "final_replan", e->final_resolve);
    ea_json_obj_end(j);
  }
  ea_json_arr_end(j);
  ea_json_obj_end(j);
}

/* The reduced dynamic model and what it predicts (task key dynamics). */
static void ea__summary_dynamics(ea_json_t *j, const ea_planner_t *pl, const ea_plan_info_t *info) {
  const ea_task_t *t = &pl->task;
  ea_plan_dyn_info_t di;
  if (ea_planner_dyn_model(pl, &di) != EA_OK || !di.built) return;
  ea_json_obj_begin(j, "dynamics");
  ea_json_int(j, "modes", t->dynamics.modes);
  ea_json_int(j, "models", di.models);
  ea_json_vec(j, "model_tip_mass_kg", di.model_tip_mass, di.models);
  ea_json_vec(j, "model_EI_Nm2", di.model_EI, di.models);
  ea_json_vec(j, "damping_ratios", t->arm.damping_ratio, t->arm.n_damping);
  ea_json_num(j, "residual_bound_m", t->dynamics.residual_m);
  ea_json_num(j, "predicted_residual_m", info->predicted_residual_m);
  ea_json_vec(j, "predicted_amplitude_m", info->predicted_amplitude_m, t->dynamics.modes);
  ea_json_num(j, "predicted_residual_worst_m", info->predicted_residual_worst_m);
  if (isfinite(info->predicted_time_to_rest_s))
    ea_json_num(j, "predicted_time_to_rest_s", info->predicted_time_to_rest_s);
  else
    ea_json_null(j, "predicted_time_to_rest_s");
  ea_json_num(j, "max_modal_deviation_m", info->max_modal_deviation_m);
  ea_json_num(j, "min_dynamic_tension_margin_N", info->min_dynamic_tension_margin_N);
  ea_json_arr_begin(j, "grid");
  ea_json_int(j, NULL, di.table.n_cable_length);
  ea_json_int(j, NULL, di.table.n_cable_angle);
  ea_json_arr_end(j);
  ea_json_int(j, "grid_extrapolated_points", di.table.n_extrapolated);
  ea_json_bool(j, "model_from_cache", di.cache_loaded);
  if (di.cache_message[0]) ea_json_str(j, "model_cache_warning", di.cache_message);
  ea_json_num(j, "model_time_s", di.time_s);
  ea_json_obj_end(j);
}

/* A number, or null when it is not finite. */
static void ea__num_or_null(ea_json_t *j, const char *key, double v) {
  if (isfinite(v))
    ea_json_num(j, key, v);
  else
    ea_json_null(j, key);
}

/* The "shape" object: the ZV shaping of the written trajectory and its limits check. */
static void ea__shape_json(ea_json_t *j, const ea_shape_info_t *s) {
  ea_json_obj_begin(j, "shape");
  ea_json_str(j, "method", "zv");
  ea_json_str(j, "status", ea_status_name(s->status));
  ea_json_str(j, "message", s->message);
  ea_json_num(j, "damping_ratio", s->damping_ratio);
  ea_json_vec(j, "amplitudes", s->amplitude, 2);
  ea__num_or_null(j, "f1_start_Hz", s->f1_start_hz);
  ea__num_or_null(j, "f1_goal_Hz", s->f1_goal_hz);
  ea__num_or_null(j, "f1_min_Hz", s->f1_min_hz);
  ea__num_or_null(j, "f1_max_Hz", s->f1_max_hz);
  ea__num_or_null(j, "half_period_start_s", s->delay_start_s);
  ea__num_or_null(j, "half_period_goal_s", s->delay_goal_s);
  ea_json_num(j, "duration_before_s", s->duration_in_s);
  ea__num_or_null(j, "duration_s", s->status == EA_OK ? s->duration_s : NAN);
  ea_json_int(j, "samples_before", s->samples_in);
  ea_json_int(j, "samples", s->samples);
  ea_json_int(j, "echo_samples_merged", s->echo_samples_merged);
  ea_json_num(j, "max_merge_s", s->max_merge_s);
  ea__num_or_null(j, "max_path_deviation_m", s->max_path_deviation_m);
  const ea_traj_limits_check_t *c = &s->check;
  ea_json_obj_begin(j, "limits_check");
  ea_json_int(j, "points", c->samples);
  ea_json_int(j, "statics_failures", c->statics_failures);
  ea__num_or_null(j, "min_tension_margin_N", c->min_tension_margin_N);
  ea_json_num(j, "peak_shoulder_torque_Nm", c->peak_shoulder_torque_Nm);
  ea_json_num(j, "max_theta0_deviation_rad", c->max_theta0_deviation_rad);
  ea_json_arr_begin(j, "limits");
  for (int i = 0; i < EA_TRAJ_LIMIT_COUNT; ++i) {
    if (!isfinite(c->excess[i])) continue;
    ea_json_obj_begin(j, NULL);
    ea_json_str(j, "limit", ea_traj_limit_name((ea_traj_limit_t)i));
    ea_json_num(j, "worst_relative_excess", c->excess[i]);
    ea_json_num(j, "value", c->value[i]);
    ea_json_num(j, "bound", c->bound[i]);
    ea_json_num(j, "time_s", c->time_s[i]);
    ea_json_obj_end(j);
  }
  ea_json_arr_end(j);
  ea_json_obj_end(j);
  ea_json_num(j, "time_s", s->time_s);
  ea_json_obj_end(j);
}

/* The "verify" object: the FE transient of the written trajectory beside the model. */
static void ea__verify_json(ea_json_t *j, const ea_plan_verify_t *v) {
  const ea_sim_settings_t *s = &v->settings;
  const ea_sim_info_t *si = &v->sim;
  const int ok = v->status == EA_OK;
  ea_json_obj_begin(j, "verify");
  ea_json_str(j, "status", ea_status_name(v->status));
  ea_json_str(j, "message", v->message);
  ea_json_bool(j, "passed", v->passed);
  ea_json_str(j, "failure", v->failure);
  ea__num_or_null(j, "residual_bound_m", v->residual_bound_m);
  ea_json_num(j, "tension_bound_N", v->tension_bound_N);
  ea_json_int(j, "elements", s->elements);
  ea_json_str(j, "scheme", s->scheme == EA_FE_SCHEME_ENERGY ? "energy" : "genalpha");
  ea_json_num(j, "rho_inf", s->rho_inf);
  ea_json_num(j, "dt_s", s->dt);
  ea_json_num(j, "settle_s", s->settle);
  ea_json_str(j, "cable", s->cable_active ? "active" : "passive");
  ea__num_or_null(j, "damping_ratio", si->damping_ratio);
  ea__num_or_null(j, "tip_mass_kg", si->tip_mass);
  ea__num_or_null(j, "motion_duration_s", ok ? si->duration : NAN);
  ea__num_or_null(j, "measured_residual_peak_m", ok ? si->residual_peak : NAN);
  ea__num_or_null(j, "measured_residual_rms_m", ok ? si->residual_rms : NAN);
  ea_json_num(j, "rest_tolerance_m", s->rest_tolerance);
  /* after the motion (0: within the tolerance when the motion ends); null: not within it by
   * the end of the settling time */
  const double rest = si->time_to_rest - si->duration; /* NAN stays NAN (fmax would drop it) */
  ea__num_or_null(j, "measured_time_to_rest_s", ok && isfinite(rest) ? (rest > 0 ? rest : 0) : NAN);
  ea__num_or_null(j, "predicted_residual_m", v->predicted_residual_m);
  ea__num_or_null(j, "predicted_time_to_rest_s", v->predicted_time_to_rest_s);
  ea__num_or_null(j, "predicted_nonlinear_residual_m", v->predicted_nonlinear_residual_m);
  ea__num_or_null(j, "measured_tension_min_N", ok ? si->tension_min : NAN);
  ea__num_or_null(j, "measured_tension_min_time_s", ok ? si->tension_min_time : NAN);
  ea__num_or_null(j, "measured_tension_max_N", ok ? si->tension_max : NAN);
  ea__num_or_null(j, "max_tracking_error_m", ok ? si->max_tracking_error : NAN);
  ea__num_or_null(j, "static_offset_end_m", ok ? si->static_offset_end : NAN);
  ea_json_num(j, "wall_time_s", si->wall_time_s);
  ea_json_str(j, "transient",
              "planar: in the arm's plane; the base rotation's loads are not in it");
  ea_json_num(j, "base_travel_rad", v->base_travel_rad);
  ea_json_obj_end(j);
}

ea_status_t ea_plan_summary_write(const ea_planner_t *pl, const ea_plan_info_t *info,
                                  const char *path, ea_error_t *err) {
  return ea_plan_summary_write_ex(pl, info, NULL, NULL, NULL, NULL, path, err);
}

ea_status_t ea_plan_summary_write_refined(const ea_planner_t *pl, const ea_plan_info_t *info,
                                          const ea_refine_info_t *refine, const char *path,
                                          ea_error_t *err) {
  return ea_plan_summary_write_ex(pl, info, refine, NULL, NULL, NULL, path, err);
}

/* The engine that gave the plan, read off the info the strategy's result filled
 * (strategy/strategy_impl.h): the own interior point's plan when it passed the KKT test, else
 * Ipopt's iterations, else a replan's active-set Newton, else a warm start that passed the KKT
 * test as it was. */
const char *ea_plan_engine_name(const ea_plan_info_t *info) {
  if (!info) return "none";
  if (info->ipm_iterations > 0 && !info->ipm_fallback) return "interior-point-ldl";
  if (info->iterations > 0) return "ipopt";
  if (info->newton_steps > 0) return "active-set-newton";
  if (!info->ipopt_status_name[0] && info->ipopt_status != EA_PLAN_NO_IPOPT)
    return "none"; /* stopped before any engine ran */
  return "kkt-test";
}

const char *ea_plan_engine_status(const ea_plan_info_t *info) {
  const char *e = ea_plan_engine_name(info);
  if (!strcmp(e, "none")) return "none";
  if (strcmp(e, "ipopt")) return "converged"; /* the own engines hand over KKT-tested points */
  switch (info->ipopt_status) {
  case EA__IPOPT_SOLVE_SUCCEEDED:
    return "converged";
  case EA__IPOPT_ACCEPTABLE:
    return "converged-acceptable";
  case EA__IPOPT_MAX_ITER:
    return "max-iterations";
  case EA__IPOPT_MAX_CPU_TIME:
  case EA__IPOPT_USER_STOP: /* the planner's wall-time limit (solver.max_time_s) */
    return "max-time";
  case EA__IPOPT_INFEASIBLE:
    return "infeasible";
  default:
    return "failed";
  }
}

void ea_plan_verify_judge(ea_plan_verify_t *v) {
  if (!v) return;
  v->passed = 0;
  v->failure[0] = '\0';
  const ea_sim_info_t *si = &v->sim;
  if (v->status) {
    snprintf(v->failure, sizeof v->failure, "the FE transient failed (%s): %.400s",
             ea_status_name(v->status), v->message);
    return;
  }
  char *p = v->failure;
  size_t left = sizeof v->failure;
  if (!(si->tension_min >= v->tension_bound_N)) {
    const int n = snprintf(p, left,
                           "the FE cable tension fell to %.4g N at t = %.4g s, below the tension "
                           "limit %.4g N%s",
                           si->tension_min, si->tension_min_time, v->tension_bound_N,
                           si->tension_min > 0 ? "" : " (the cable went slack)");
    if (n > 0 && (size_t)n < left) p += n, left -= (size_t)n;
  }
  if (isfinite(v->residual_bound_m) && !(si->residual_peak <= v->residual_bound_m))
    snprintf(p, left, "%sthe FE residual vibration peak %.4g mm exceeds the bound %.4g mm",
             p == v->failure ? "" : "; ", 1e3 * si->residual_peak, 1e3 * v->residual_bound_m);
  v->passed = !v->failure[0];
}

/* "fe_check": whether an FE transient checked the written plan's promise and what it
 * measured: with a residual bound (or --verify and a bound) the transient at --verify's
 * settings, else the refinement's last one; within only when every check that ran holds
 * (the exit status's rule). */
static void ea__fe_check_json(ea_json_t *j, const ea_task_t *task, const ea_plan_info_t *info,
                              const ea_refine_info_t *refine, const ea_shape_info_t *shape,
                              const ea_plan_verify_t *verify) {
  if (info->status != EA_OK) return;
  ea_json_obj_begin(j, "fe_check");
  const int model_only = refine && refine->settings.by == EA_TASK_REFINE_BY_MODEL_ONLY;
  const int refined = refine && refine->status == EA_OK && !model_only;
  const int by_verify = verify && isfinite(verify->residual_bound_m);
  const int by_refine = !by_verify && refined;
  ea_json_bool(j, "checked", by_refine || by_verify);
  if (by_refine) {
    ea_json_str(j, "by", "refinement");
    ea_json_num(j, "dt_s", refine->fe.dt);
    ea_json_num(j, "residual_peak_m", refine->residual_peak_m);
    ea_json_num(j, "bound_m", refine->settings.tolerance_m);
    ea_json_bool(j, "within", refine->converged);
    ea_json_int(j, "evaluations", refine->n_evals);
  } else if (by_verify) {
    ea_json_str(j, "by", "verify");
    ea_json_num(j, "dt_s", verify->settings.dt);
    if (verify->status == EA_OK)
      ea_json_num(j, "residual_peak_m", verify->sim.residual_peak);
    else
      ea_json_null(j, "residual_peak_m");
    ea_json_num(j, "bound_m", verify->residual_bound_m);
    ea_json_bool(j, "within", verify->passed && (!refined || refine->converged));
    if (refined) ea_json_int(j, "evaluations", refine->n_evals);
  } else { /* why not: as the text summary says it */
    ea_json_str(j, "reason",
                model_only ? "dynamics.refine.by: model_only: corrected by the nonlinear reduced "
                             "model alone (refine.residual_peak_m is its prediction)"
                : refine && refine->message[0]      ? refine->message
                : refine                            ? "the refinement failed"
                : !task || task->dynamics.modes < 1 ? "no dynamics: the task promises no rest"
                : shape                             ? "a ZV-shaped plan: plan --verify checks it"
                : task->objective == EA_TASK_MIN_VIBRATION
                    ? "min_vibration promises no rest"
                    : "dynamics.verify: false (or plan --no-verify)");
  }
  ea_json_obj_end(j);
}

ea_status_t ea_plan_summary_write_ex(const ea_planner_t *pl, const ea_plan_info_t *info,
                                     const ea_refine_info_t *refine, const ea_shape_info_t *shape,
                                     const ea_plan_verify_t *verify, const char *run_id,
                                     const char *path, ea_error_t *err) {
  if (!pl || !info || !path) return ea_error_set(err, EA_ERR_ARG, "summary: NULL argument");
  const ea_task_t *t = &pl->task;
  ea_afile_t f;
  ea_status_t st = ea_afile_open(&f, path, err);
  if (st) return st;
  ea_json_t j;
  ea_json_init(&j, f.fp, 1);
  ea_json_obj_begin(&j, NULL);
  if (run_id) ea_json_str(&j, "run_id", run_id);
  ea_json_str(&j, "status", ea_status_name(info->status));
  ea_json_str(&j, "message", info->message);
  ea_json_str(&j, "task", t->file[0] ? t->file : t->name);
  ea_json_str(&j, "arm_file", t->arm_file);
  ea_json_str(&j, "objective", ea_task_objective_name(t->objective));
  ea_json_str(&j, "path", ea_task_path_name(t->path));
  ea_json_num(&j, "payload_kg", t->payload_kg);
  ea_json_int(&j, "knots", pl->N);
  ea_json_bool(&j, "base_moves", pl->nq == 3);
  if (info->status == EA_OK)
    ea_json_num(&j, "duration_s", info->duration_s);
  else
    ea_json_null(&j, "duration_s");
  ea_json_int(&j, "iterations", info->iterations);
  /* which engine gave the plan and its outcome in neutral words; Ipopt's own status only
   * when Ipopt ran */
  const char *engine = ea_plan_engine_name(info);
  ea_json_str(&j, "engine", engine);
  ea_json_str(&j, "engine_status", ea_plan_engine_status(info));
  if (!strcmp(engine, "ipopt")) {
    ea_json_str(&j, "ipopt_status", info->ipopt_status_name);
    ea_json_int(&j, "ipopt_status_code", info->ipopt_status);
  }
  ea_json_int(&j, "threads", info->threads);
  ea_json_num(&j, "objective_value", info->objective);
  ea_json_num(&j, "solve_time_s", info->time_total_s);
  ea_json_num(&j, "min_tension_margin_N", info->min_tension_margin_N);
  ea_json_num(&j, "peak_shoulder_torque_Nm", info->peak_shoulder_torque_Nm);
  ea_json_num(&j, "max_statics_residual", info->max_statics_residual);
  ea_json_num(&j, "max_violation", info->max_violation);
  ea_json_int(&j, "between_knots_resolves", info->between_passes);
  if (pl->fm) {
    const ea_plan_freq_model_info_t *fi = &pl->fm->info;
    ea_json_obj_begin(&j, "vibration");
    ea_json_num(&j, "min_first_frequency_Hz", info->min_first_frequency_hz);
    ea_json_num(&j, "max_modal_deflection_m", info->max_modal_deflection_m);
    ea_json_num(&j, "f_ref_Hz", fi->f_ref_hz);
    ea_json_int(&j, "grid_cable_length", fi->n_cable_length);
    ea_json_int(&j, "grid_cable_angle", fi->n_cable_angle);
    ea_json_int(&j, "grid_extrapolated", fi->n_extrapolated);
    ea_json_num(&j, "model_time_s", fi->time_s);
    ea_json_obj_end(&j);
  }
  if (info->status != EA_OK) ea_json_str(&j, "worst_constraint", info->worst);
  if (isfinite(info->predicted_residual_m)) ea__summary_dynamics(&j, pl, info);
  ea_json_obj_begin(&j, "problem");
  ea_json_int(&j, "variables", info->n_var);
  ea_json_int(&j, "constraints", info->n_con);
  ea_json_int(&j, "jacobian_nonzeros", info->nnz_jac);
  ea_json_int(&j, "evals_g", info->evals_g);
  ea_json_int(&j, "evals_jacobian", info->evals_jac);
  ea_json_obj_end(&j);
  ea_json_arr_begin(&j, "active_limits");
  for (int i = 0; i < info->n_active; ++i) {
    ea_json_obj_begin(&j, NULL);
    ea_json_str(&j, "limit", info->active[i]);
    ea_json_int(&j, "knots", info->active_knots[i]);
    ea_json_obj_end(&j);
  }
  ea_json_arr_end(&j);
  ea_json_obj_begin(&j, "phase_times_s");
  ea_json_num(&j, "initial_guess", info->time_guess_s);
  ea_json_num(&j, "statics_jacobians", info->time_statics_s);
  ea_json_num(&j, "solve", info->time_ipopt_s); /* the engine's own work, callbacks excluded */
  ea_json_num(&j, "rest", info->time_rest_s);
  ea_json_obj_end(&j);
  if (refine) ea__refine_json(&j, refine);
  if (shape) ea__shape_json(&j, shape);
  if (verify) ea__verify_json(&j, verify);
  ea__fe_check_json(&j, ea_planner_task(pl), info, refine, shape, verify);
  ea_json_obj_end(&j);
  ea_json_end(&j);
  return ea_afile_commit(&f, err);
}
