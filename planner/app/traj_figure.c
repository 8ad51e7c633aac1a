/* Figure of a trajectory (through the project's gnuplot module, figure.c):
 * (a) the tip path and a few beam shapes in the workspace of its load (outer
 * edge T = 0, eq. 16; inner edge L_c = L_c,min), (b) actuator coordinates,
 * (c) tension and shoulder torque, (d) rates, over time. Used for plans
 * (ea_plan_figure) and for any trajectory file (elasticarm figure). */
#include "figure_impl.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

ea_status_t ea_traj_figure(const ea_traj_t *tr, ea_shooter_t *sh, double cable_length_min,
                           double tension_min, const char *title, const char *path,
                           ea_error_t *err) {
  if (!tr || !sh || !path || tr->n < 2)
    return ea_error_set(err, EA_ERR_ARG, "ea_traj_figure: NULL argument or empty trajectory");
  const ea_arm_t *arm = ea_shooter_arm(sh);
  ea_plot_t *p = NULL;
  ea_status_t st = ea_plot_open(&p, path, 1200, 900, err);
  if (st) return st;
  /* Workspace edges for this payload. */
  ea_plot_data_begin(p, "edge");
  ea_statics_solution_t sol;
  const double *guess = NULL;
  double prev[EA_NP];
  for (double a = -60.0; a <= 10.0 + 1e-9; a += 2.0) {
    if (ea_statics_edge(sh, a * M_PI / 180.0, NULL, guess, &sol, NULL) == EA_OK) {
      const double row[2] = {sol.tip[EA_X_X], sol.tip[EA_X_Y]};
      ea_plot_data_row(p, 2, row);
      memcpy(prev, sol.p, sizeof prev);
      guess = prev;
    }
  }
  ea_plot_data_end(p);
  ea_plot_data_begin(p, "inner");
  for (double a = -60.0; a <= 10.0 + 1e-9; a += 2.0) {
    const double r = cable_length_min, aa = a * M_PI / 180.0;
    const double row[2] = {arm->x_c + r * cos(aa), arm->y_c + r * sin(aa)};
    ea_plot_data_row(p, 2, row);
  }
  ea_plot_data_end(p);
  /* Tip path in the arm's plane and beam shapes at 6 knots. */
  ea_plot_data_begin(p, "tip");
  for (int k = 0; k < tr->n; ++k) {
    const double row[2] = {
        hypot(EA_TRAJ_AT(tr, k, EA_TRAJ_tip_x), EA_TRAJ_AT(tr, k, EA_TRAJ_tip_y)),
        EA_TRAJ_AT(tr, k, EA_TRAJ_tip_z)};
    ea_plot_data_row(p, 2, row);
  }
  ea_plot_data_end(p);
  ea_plot_data_begin(p, "beams");
  double xs[41], ys[41];
  for (int i = 0; i < 6; ++i) {
    const int k = (int)lround(i * (tr->n - 1) / 5.0);
    const double pp[EA_NP] = {EA_TRAJ_AT(tr, k, EA_TRAJ_cable_angle),
                              EA_TRAJ_AT(tr, k, EA_TRAJ_tension), EA_TRAJ_AT(tr, k, EA_TRAJ_theta0),
                              EA_TRAJ_AT(tr, k, EA_TRAJ_kappa0)};
    if (ea_shoot_shape(sh, pp, 41, NULL, NULL, NULL, xs, ys) != EA_OK) continue;
    for (int j = 0; j < 41; ++j) {
      const double row[2] = {xs[j], ys[j]};
      ea_plot_data_row(p, 2, row);
    }
    const double cab[2][2] = {{xs[40], ys[40]}, {arm->x_c, arm->y_c}};
    const double brk[2] = {NAN, NAN};
    ea_plot_data_row(p, 2, brk);
    ea_plot_data_row(p, 2, cab[0]);
    ea_plot_data_row(p, 2, cab[1]);
    ea_plot_data_row(p, 2, brk);
  }
  ea_plot_data_end(p);
  ea_plot_data_begin(p, "hist");
  for (int k = 0; k < tr->n; ++k)
    ea_plot_data_row(p, EA_TRAJ_NCOL, &EA_TRAJ_AT(tr, k, 0));
  ea_plot_data_end(p);
  char head[1100], quoted[2300];
  snprintf(head, sizeof head, "%.1000s  (duration %.4g s)", title ? title : "trajectory",
           EA_TRAJ_AT(tr, tr->n - 1, EA_TRAJ_t) - EA_TRAJ_AT(tr, 0, EA_TRAJ_t));
  ea_plot_cmd(p, "set multiplot layout 2,2 title %s noenhanced",
              ea_plot_quote(head, quoted, sizeof quoted));
  ea_plot_cmd(p, "set size ratio -1\nset xlabel 'reach x_L [m]'\nset ylabel 'height y_L [m]'");
  ea_plot_cmd(p, "set key below maxrows 3");
  ea_plot_cmd(p,
              "plot $edge w l lw 2 lc rgb '#888888' t 'outer edge (T = 0)', "
              "$inner w l dt 2 lc rgb '#888888' t 'inner edge (L_c min)', "
              "$beams w l lc rgb '#1f77b4' t 'beam and cable', "
              "$tip w lp pt 7 ps 0.3 lc rgb '#d62728' t 'tip path', "
              "'+' using (%.17g):(%.17g) every ::0::0 w p pt 5 ps 1.2 lc rgb 'black' "
              "t 'cable root'",
              arm->x_c, arm->y_c);
  ea_plot_cmd(
      p,
      "set size noratio\nset xlabel 't [s]'\nset key default\nset key inside top right box opaque");
  ea_plot_cmd(p, "set ylabel 'L_c [m], alpha, base [rad]'");
  ea_plot_cmd(p, "plot $hist u 1:2 w l lw 2 t 'L_c', '' u 1:3 w l lw 2 t 'alpha', "
                 "'' u 1:4 w l lw 2 t 'base'");
  ea_plot_cmd(p, "set ylabel 'T [N], EI kappa_0 [N m]'");
  ea_plot_cmd(p,
              "plot $hist u 1:11 w l lw 2 t 'tension T', '' u 1:15 w l lw 2 t 'shoulder "
              "torque', %.17g w l dt 2 lc rgb 'black' t 'T_{min}'",
              tension_min);
  ea_plot_cmd(p, "set ylabel 'rates [m/s, rad/s]'");
  ea_plot_cmd(p, "plot $hist u 1:5 w l lw 2 t 'dL_c/dt', '' u 1:6 w l lw 2 t 'dalpha/dt', "
                 "'' u 1:7 w l lw 2 t 'dbase/dt', '' u 1:13 w l lw 2 t 'dtheta_0/dt'");
  ea_plot_cmd(p, "unset multiplot");
  return ea_plot_close(p, err);
}
