/* The paper's statics problems: workspace edges (Fig. 3), shoulder torque
 * maps (sec. 2.3.2) and straight-path admissibility (Fig. 4, eqs. 18-20). */
#include "ea_workspace.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static void ea__fill_point(ea_config_point_t *pt, const ea_statics_solution_t *sol) {
  pt->stable = -1;
  pt->cable_length = sol->cable_length;
  pt->alpha = sol->p[EA_P_ALPHA];
  pt->x = sol->tip[EA_X_X];
  pt->y = sol->tip[EA_X_Y];
  pt->tension = sol->p[EA_P_TENSION];
  pt->theta0 = sol->p[EA_P_THETA0];
  pt->kappa0 = sol->p[EA_P_KAPPA0];
  pt->shoulder_torque = sol->shoulder_torque;
  pt->residual = sol->residual;
  pt->iterations = sol->iterations;
  pt->status = sol->status;
}

static void ea__fail_point(ea_config_point_t *pt, ea_status_t st, const char *why) {
  memset(pt, 0, sizeof *pt);
  pt->cable_length = pt->alpha = pt->x = pt->y = NAN;
  pt->tension = pt->theta0 = pt->kappa0 = pt->shoulder_torque = pt->residual = NAN;
  pt->status = st;
  pt->stable = -1;
  pt->admissible = 0;
  snprintf(pt->reason, sizeof pt->reason, "%s", why);
}

/* Solve (given g = v, alpha = alpha[i]) along the angles, each warm-started
 * from its neighbour (cold where that fails). */
static ea_status_t ea__alpha_sweep(ea_shooter_t *sh, ea_given_t g, double v, const double *alpha,
                                   int n, ea_config_point_t *out) {
  if (!sh || !alpha || !out || n < 1) return EA_ERR_ARG;
  ea_status_t all = EA_OK;
  double guess[EA_NP];
  int have = 0;
  for (int i = 0; i < n; ++i) {
    ea_statics_problem_t pr = {{g, EA_GIVEN_ALPHA}, {v, alpha[i]}};
    ea_statics_solution_t sol;
    if (have) guess[EA_P_ALPHA] = alpha[i];
    ea_status_t st = ea_statics_solve(sh, &pr, NULL, have ? guess : NULL, &sol, NULL);
    if (st && have) st = ea_statics_solve(sh, &pr, NULL, NULL, &sol, NULL);
    if (st) {
      ea__fail_point(&out[i], st, st == EA_ERR_INADMISSIBLE ? "T < 0" : "no solution");
      out[i].alpha = alpha[i];
      if (g == EA_GIVEN_CABLE_LENGTH) out[i].cable_length = v;
      all = st;
      have = 0;
      continue;
    }
    ea__fill_point(&out[i], &sol);
    /* the arm's limits; on the outer edge T = 0 by definition, so without
       the tension margin */
    ea_actuators_t lim = ea_shooter_arm(sh)->act;
    if (g == EA_GIVEN_TENSION) lim.tension_min = 0.0;
    ea_config_check_limits(&out[i], &lim, 0.0);
    memcpy(guess, sol.p, sizeof guess);
    have = 1;
  }
  return all;
}

ea_status_t ea_workspace_outer(ea_shooter_t *sh, const double *alpha, int n,
                               ea_config_point_t *out) {
  return ea__alpha_sweep(sh, EA_GIVEN_TENSION, 0.0, alpha, n, out);
}

ea_status_t ea_workspace_inner(ea_shooter_t *sh, double cable_length, const double *alpha, int n,
                               ea_config_point_t *out) {
  if (!sh) return EA_ERR_ARG;
  if (!(cable_length > 0)) cable_length = ea_shooter_arm(sh)->act.cable_length_min;
  return ea__alpha_sweep(sh, EA_GIVEN_CABLE_LENGTH, cable_length, alpha, n, out);
}

void ea_config_check_limits(ea_config_point_t *pt, const ea_actuators_t *lim, double tension_min) {
  const double tmin = tension_min > 0 ? tension_min : lim->tension_min;
  pt->admissible = 0;
  if (pt->status != EA_OK && pt->status != EA_ERR_INADMISSIBLE) {
    snprintf(pt->reason, sizeof pt->reason, "no statics solution (%s)", ea_strerror(pt->status));
    return;
  }
  if (!(pt->tension >= tmin))
    snprintf(pt->reason, sizeof pt->reason, "tension %.4g N below the minimum %.4g N", pt->tension,
             tmin);
  else if (pt->tension > lim->tension_max)
    snprintf(pt->reason, sizeof pt->reason, "tension %.4g N above the maximum %.4g N", pt->tension,
             lim->tension_max);
  else if (pt->cable_length < lim->cable_length_min - 1e-9)
    snprintf(pt->reason, sizeof pt->reason, "cable length %.4g m below the minimum %.4g m",
             pt->cable_length, lim->cable_length_min);
  else if (pt->cable_length > lim->cable_length_max + 1e-9)
    snprintf(pt->reason, sizeof pt->reason, "cable length %.4g m above the maximum %.4g m",
             pt->cable_length, lim->cable_length_max);
  else if (fabs(pt->shoulder_torque) > lim->shoulder_torque_max)
    snprintf(pt->reason, sizeof pt->reason, "shoulder torque %.4g N m beyond the limit %.4g N m",
             pt->shoulder_torque, lim->shoulder_torque_max);
  else if (pt->theta0 < lim->shoulder_angle_min || pt->theta0 > lim->shoulder_angle_max)
    snprintf(pt->reason, sizeof pt->reason, "shoulder angle %.4g rad outside [%.4g, %.4g] rad",
             pt->theta0, lim->shoulder_angle_min, lim->shoulder_angle_max);
  else {
    pt->admissible = 1;
    pt->reason[0] = '\0';
  }
}

ea_status_t ea_torque_map(ea_shooter_t *sh, const double *cable_length, int n_len,
                          const double *alpha, int n_alpha, const ea_actuators_t *lim,
                          ea_config_point_t *cells) {
  if (!sh || !cable_length || !alpha || !cells || n_len < 1 || n_alpha < 1) return EA_ERR_ARG;
  const ea_actuators_t *L = lim ? lim : &ea_shooter_arm(sh)->act;
  ea_statics_settings_t set;
  ea_statics_settings_default(&set);
  set.allow_negative_tension = 1; /* classify by the sign ourselves */
  for (int i = 0; i < n_alpha; ++i) {
    ea_config_point_t *row = cells + (size_t)i * n_len;
    /* The edge first: it bounds the cells and starts the sweep. */
    ea_statics_solution_t edge;
    if (ea_statics_edge(sh, alpha[i], NULL, NULL, &edge, NULL) != EA_OK) {
      for (int j = 0; j < n_len; ++j) {
        ea__fail_point(&row[j], EA_ERR_NOCONV, "no outer edge at this cable angle");
        row[j].alpha = alpha[i];
        row[j].cable_length = cable_length[j];
      }
      continue;
    }
    /* Sweep from the longest cable inward, warm-started. */
    double guess[EA_NP];
    memcpy(guess, edge.p, sizeof guess);
    int order_desc = n_len < 2 || cable_length[0] > cable_length[n_len - 1];
    for (int k = 0; k < n_len; ++k) {
      const int j = order_desc ? k : n_len - 1 - k;
      ea_config_point_t *c = &row[j];
      if (cable_length[j] > edge.cable_length) {
        ea__fail_point(c, EA_ERR_INADMISSIBLE, "outside the workspace (beyond the T = 0 edge)");
        c->alpha = alpha[i];
        c->cable_length = cable_length[j];
        continue;
      }
      ea_statics_problem_t pr = ea_statics_problem_cable(cable_length[j], alpha[i]);
      ea_statics_solution_t sol;
      ea_status_t st = ea_statics_solve(sh, &pr, &set, guess, &sol, NULL);
      if (st) st = ea_statics_solve(sh, &pr, &set, NULL, &sol, NULL);
      if (st) {
        ea__fail_point(c, st, "no statics solution");
        c->alpha = alpha[i];
        c->cable_length = cable_length[j];
        continue;
      }
      ea__fill_point(c, &sol);
      if (sol.p[EA_P_TENSION] < 0) c->status = EA_ERR_INADMISSIBLE;
      ea_config_check_limits(c, L, 0.0);
      memcpy(guess, sol.p, sizeof guess);
    }
  }
  return EA_OK;
}

ea_status_t ea_config_check_stability(ea_shooter_t *sh, ea_fe_model_t *fe, ea_config_point_t *pt) {
  if (!sh || !fe || !pt) return EA_ERR_ARG;
  pt->stable = -1;
  if (pt->status != EA_OK && pt->status != EA_ERR_INADMISSIBLE) return EA_OK;
  ea_statics_solution_t sol;
  memset(&sol, 0, sizeof sol);
  sol.p[EA_P_ALPHA] = pt->alpha;
  sol.p[EA_P_TENSION] = pt->tension;
  sol.p[EA_P_THETA0] = pt->theta0;
  sol.p[EA_P_KAPPA0] = pt->kappa0;
  sol.cable_length = pt->cable_length;
  sol.status = EA_OK;
  ea_status_t st = ea_fe_model_set_load(fe, ea_shooter_load(sh));
  if (!st) st = ea_fe_static_solve(fe, sh, &sol, NULL, NULL);
  int stable = 0;
  if (!st) st = ea_fe_stability(fe, &stable, NULL);
  if (st) return st;
  pt->stable = stable;
  if (!stable) {
    pt->admissible = 0;
    snprintf(pt->reason, sizeof pt->reason,
             "unstable: the FE passive stiffness is not positive definite");
  }
  return EA_OK;
}

ea_status_t ea_path_check_line(ea_shooter_t *sh, const double tip0[2], const double tip1[2],
                               int steps, const ea_actuators_t *lim, ea_config_point_t *out) {
  return ea_path_check_line_fe(sh, NULL, tip0, tip1, steps, lim, out);
}

ea_status_t ea_path_check_line_fe(ea_shooter_t *sh, ea_fe_model_t *fe, const double tip0[2],
                                  const double tip1[2], int steps, const ea_actuators_t *lim,
                                  ea_config_point_t *out) {
  if (!sh || !tip0 || !tip1 || !out || steps < 1) return EA_ERR_ARG;
  const ea_arm_t *arm = ea_shooter_arm(sh);
  const ea_actuators_t *L = lim ? lim : &arm->act;
  ea_statics_settings_t set;
  ea_statics_settings_default(&set);
  set.allow_negative_tension = 1;
  ea_status_t all = EA_OK;
  double guess[EA_NP];
  int have = 0;
  for (int k = 0; k <= steps; ++k) {
    const double b = (double)k / steps;
    const double x = tip0[0] + b * (tip1[0] - tip0[0]), y = tip0[1] + b * (tip1[1] - tip0[1]);
    /* eqs. 19-20 */
    const double Lc = hypot(x - arm->x_c, y - arm->y_c), a = atan2(y - arm->y_c, x - arm->x_c);
    ea_statics_problem_t pr = ea_statics_problem_cable(Lc, a);
    ea_statics_solution_t sol;
    ea_status_t st = ea_statics_solve(sh, &pr, &set, have ? guess : NULL, &sol, NULL);
    if (st && have) st = ea_statics_solve(sh, &pr, &set, NULL, &sol, NULL);
    ea_config_point_t *pt = &out[k];
    if (st) {
      ea__fail_point(pt, st, "");
      pt->x = x;
      pt->y = y;
      pt->cable_length = Lc;
      pt->alpha = a;
      ea_config_check_limits(pt, L, 0.0);
      all = EA_ERR_INADMISSIBLE;
      have = 0;
      continue;
    }
    ea__fill_point(pt, &sol);
    ea_config_check_limits(pt, L, 0.0);
    if (fe && pt->admissible) ea_config_check_stability(sh, fe, pt);
    if (!pt->admissible) all = EA_ERR_INADMISSIBLE;
    memcpy(guess, sol.p, sizeof guess);
    have = 1;
  }
  return all;
}
