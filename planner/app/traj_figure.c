/* Figure of a trajectory (through the project's gnuplot module, figure.c), one
 * unit per axis and the keys below the panels (never over a curve):
 * (a) the tip path and a few beam shapes in the workspace region of its load
 * (outer edge T = 0, eq. 16; inner edge the shortest cable; the sides along
 * the cable), (b) cable length, (c) angles, (d) tension, (e) shoulder torque,
 * (f) cable speed, (g) angular rates, (h) a plan's natural frequencies or the
 * cable acceleration, over time; the limits near the data dashed. Used for
 * plans (ea_plan_figure) and for any trajectory file (elasticarm figure). */
#include "ea_util.h"
#include "figure_impl.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void ea_traj_figure_opts_default(ea_traj_figure_opts_t *o, const ea_arm_t *arm) {
  memset(o, 0, sizeof *o);
  if (arm) o->lim = arm->act;
  o->predicted_residual_m = o->max_modal_deviation_m = o->predicted_time_to_rest_s = NAN;
  o->fe_residual_peak_m = NAN;
}

/* Range of column c (scaled) over the rows. */
static void ea__col_range(const ea_traj_t *tr, int c, double scale, double *lo, double *hi) {
  *lo = INFINITY;
  *hi = -INFINITY;
  for (int k = 0; k < tr->n; ++k) {
    const double v = scale * EA_TRAJ_AT(tr, k, c);
    if (!isfinite(v)) continue;
    *lo = fmin(*lo, v);
    *hi = fmax(*hi, v);
  }
}

/* A limit is drawn when finite and near the data (at most the data's span away, so
 * the axis at most doubles): far limits would squeeze the curves flat. */
static int ea__limit_near(double limit, double lo, double hi) {
  if (!isfinite(limit) || !(lo <= hi)) return 0;
  const double span = fmax(hi - lo, 1e-3 * fmax(fabs(lo), fabs(hi)));
  return limit >= lo - span && limit <= hi + span;
}

/* Appends ", LIMIT w l dt 2 lc rgb 'black' t 'TEXT'" to a plot command when the limit
 * is drawn. */
static int ea__limit_term(char *buf, size_t len, int used, double limit, double lo, double hi,
                          const char *text) {
  if (used < 0 || (size_t)used >= len || !ea__limit_near(limit, lo, hi)) return used;
  return used + snprintf(buf + used, len - (size_t)used,
                         ", %.9g w l dt 2 lw 1.5 lc rgb '#444444' t '%s'", limit, text);
}

/* The workspace panel's data: the closed region of the load (cable angles covering
 * the paper's -60 to 10 deg and the trajectory's), the tip path in the arm's plane,
 * six beam shapes with their cables. */
static void ea__traj_workspace_data(ea_plot_t *p, const ea_traj_t *tr, ea_shooter_t *sh,
                                    double inner_length) {
  const ea_arm_t *arm = ea_shooter_arm(sh);
  double alo, ahi;
  ea__col_range(tr, EA_TRAJ_cable_angle, 1.0, &alo, &ahi);
  alo = fmin(-60.0 * EA__DEG, alo - 5.0 * EA__DEG);
  ahi = fmax(10.0 * EA__DEG, ahi + 5.0 * EA__DEG);
  enum { NA = 61 };
  double alpha[NA];
  ea_config_point_t outer[NA];
  for (int k = 0; k < NA; ++k)
    alpha[k] = alo + (ahi - alo) * k / (NA - 1);
  ea_workspace_outer(sh, alpha, NA, outer);
  if (!ea_plot_region(p, "region", arm, outer, NA, inner_length)) {
    ea_plot_data_begin(p, "region");
    ea_plot_data_row(p, 2, (double[]){NAN, NAN});
    ea_plot_data_end(p);
  }
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
    for (int j = 0; j < 41; ++j)
      ea_plot_data_row(p, 2, (double[]){xs[j], ys[j]});
    const double brk[2] = {NAN, NAN};
    ea_plot_data_row(p, 2, brk);
    ea_plot_data_row(p, 2, (double[]){xs[40], ys[40]});
    ea_plot_data_row(p, 2, (double[]){arm->x_c, arm->y_c});
    ea_plot_data_row(p, 2, brk);
  }
  ea_plot_data_end(p);
}

/* The time histories: every column (NaN where a value is unknown, which gnuplot
 * leaves out) and, with a model, the natural frequencies in the columns after. */
static int ea__traj_hist_data(ea_plot_t *p, const ea_traj_t *tr, const ea_traj_figure_opts_t *o) {
  int nf = 0;
  if (o->f1)
    nf = 1;
  else if (o->rom) {
    ea_rom_table_info_t ti;
    ea_rom_table_info(o->rom, &ti);
    nf = ti.modes;
  }
  ea_plot_data_begin(p, "hist");
  for (int k = 0; k < tr->n; ++k) {
    char line[64 * (EA_TRAJ_NCOL + EA_ROM_MAX_MODES)];
    size_t u = 0;
    double v[EA_TRAJ_NCOL + EA_ROM_MAX_MODES];
    memcpy(v, &EA_TRAJ_AT(tr, k, 0), EA_TRAJ_NCOL * sizeof *v);
    const double L = v[EA_TRAJ_cable_length], a = v[EA_TRAJ_cable_angle];
    if (o->f1) {
      double hz = NAN;
      if (o->f1(o->f1_ctx, L, a, &hz)) hz = NAN;
      v[EA_TRAJ_NCOL] = hz;
    } else if (o->rom) {
      ea_rom_point_t rp;
      ea_rom_table_eval(o->rom, L, a, &rp, NULL, NULL);
      for (int i = 0; i < nf; ++i)
        v[EA_TRAJ_NCOL + i] = rp.omega2[i] > 0 ? sqrt(rp.omega2[i]) / (2.0 * M_PI) : NAN;
    }
    for (int c = 0; c < EA_TRAJ_NCOL + nf && u < sizeof line - 32; ++c) {
      if (isfinite(v[c]))
        u += (size_t)snprintf(line + u, sizeof line - u, "%s%.9g", c ? " " : "", v[c]);
      else
        u += (size_t)snprintf(line + u, sizeof line - u, "%sNaN", c ? " " : "");
    }
    ea_plot_cmd(p, "%s", line);
  }
  ea_plot_data_end(p);
  return nf;
}

#define EA__COL(c) ((c) + 1) /* gnuplot column of trajectory column c */

/* The layout: 3 columns x 4 rows below the title; (a) takes the top left 2 x 2,
 * the time panels one cell each (slot 0, 1 the right column's top two, then the
 * bottom two rows left to right). Each time panel: its key above it (outside: it
 * never hides a curve), its title, y label, the common x label. */
static void ea__time_panel(ea_plot_t *p, int slot, const char *title, const char *ylabel) {
  const double w = 1.0 / 3.0, h = 0.955 / 4.0;
  const int col = slot < 2 ? 2 : (slot - 2) % 3, row = slot < 2 ? slot : 2 + (slot - 2) / 3;
  ea_plot_cmd(p,
              "unset label 1\nset size noratio %.6f,%.6f\nset origin %.6f,%.6f\nset title \"%s\"\n"
              "set ylabel '%s'\nset xlabel 't [s]'\n"
              "set key outside top center horizontal box opaque\n"
              "set offsets 0, 0, graph 0.05, graph 0.05", /* a limit at the data's edge shows */
              w, h, col * w, 0.955 - (row + 1) * h, title, ylabel);
}

/* (a) the workspace with the tip path and beam shapes, and the reduced model's summary. */
static void ea__panel_workspace(ea_plot_t *p, const ea_arm_t *arm, const ea_traj_figure_opts_t *o,
                                int top_view) {
  ea_plot_cmd(p,
              "set size ratio -1 %.6f,%.6f\nset origin 0,%.6f\n"
              "set xlabel 'reach x_L [m]'\nset ylabel 'height y_L [m]'\n"
              "set title '(a) tip path and beam shapes in the workspace region'\n"
              "set key outside right top vertical box opaque",
              2.0 / 3.0, 0.955 / 2.0, 0.955 / 2.0);
  /* what the model predicted and, apart, what an FE transient of this trajectory measured */
  char label[900] = "";
  size_t u = 0;
  if (isfinite(o->fe_residual_peak_m))
    u += (size_t)snprintf(label, sizeof label,
                          "FE transient of this trajectory (%s):\\n"
                          "  measured residual vibration peak: %.3g mm\\n",
                          o->fe_check ? o->fe_check : "measured", 1e3 * o->fe_residual_peak_m);
  if (u < sizeof label &&
      (isfinite(o->predicted_residual_m) || isfinite(o->max_modal_deviation_m))) {
    char rest[120];
    if (isfinite(o->predicted_time_to_rest_s))
      snprintf(rest, sizeof rest, "within 1 mm %.3g s after the motion",
               o->predicted_time_to_rest_s);
    else
      snprintf(rest, sizeof rest, "not within 1 mm (undamped)");
    snprintf(label + u, sizeof label - u,
             "reduced model's prediction (plan summary):\\n"
             "  modal tip deviation during the motion: up to %.3g mm\\n"
             "  model-predicted residual vibration: %.3g mm\\n  %s",
             1e3 * o->max_modal_deviation_m, 1e3 * o->predicted_residual_m, rest);
  }
  if (label[0])
    ea_plot_cmd(p, "set label 1 \"%s\" at screen 0.41, screen %.3f left", label,
                top_view ? 0.84 : 0.72); /* above the top view when there is one */
  ea_plot_cmd(p,
              "plot $region w l lw 2 lc rgb '#888888' t 'workspace (T >= 0, L_c >= %.3g m)', "
              "$beams w l lc rgb '#1f77b4' t 'beam and cable', "
              "$tip w l lw 2.5 lc rgb '#d62728' t 'tip path', "
              "'+' using (%.17g):(%.17g) every ::0::0 w p pt 5 ps 1.2 lc rgb 'black' "
              "t 'cable root'",
              o->lim.cable_length_min, arm->x_c, arm->y_c);
}

/* (a') the tip path seen from above (x, y; the base axis at the origin) with the arm's
 * horizontal projection at the start and the end: the base rotation that (a), drawn in the
 * arm's plane, does not show. In the free space right of (a), below its key. */
static void ea__panel_top(ea_plot_t *p, const ea_traj_t *tr) {
  ea_plot_data_begin(p, "top");
  for (int k = 0; k < tr->n; ++k)
    ea_plot_data_row(
        p, 2, (double[]){EA_TRAJ_AT(tr, k, EA_TRAJ_tip_x), EA_TRAJ_AT(tr, k, EA_TRAJ_tip_y)});
  ea_plot_data_end(p);
  ea_plot_data_begin(p, "toparm");
  const int ends[2] = {0, tr->n - 1};
  for (int e = 0; e < 2; ++e) {
    ea_plot_data_row(p, 2, (double[]){0.0, 0.0});
    ea_plot_data_row(
        p, 2,
        (double[]){EA_TRAJ_AT(tr, ends[e], EA_TRAJ_tip_x), EA_TRAJ_AT(tr, ends[e], EA_TRAJ_tip_y)});
    ea_plot_data_row(p, 2, (double[]){NAN, NAN});
  }
  ea_plot_data_end(p);
  ea_plot_cmd(p, "unset label 1\nset size ratio -1 0.27,0.27\nset origin 0.40,0.47\n"
                 "set title \"(a') top view: tip path as the base turns\"\n"
                 "set xlabel 'x [m]'\nset ylabel 'y [m]'\nunset key\n"
                 "set offsets graph 0.08, graph 0.08, graph 0.08, graph 0.08");
  ea_plot_cmd(p, "plot $toparm w l lw 1.5 dt 2 lc rgb '#1f77b4', "
                 "$top w l lw 2.5 lc rgb '#d62728', "
                 "$top every ::0::0 w p pt 7 ps 1.2 lc rgb '#d62728', "
                 "'+' using (0):(0) every ::0::0 w p pt 5 ps 1.2 lc rgb 'black'");
  ea_plot_cmd(p, "set offsets 0, 0, 0, 0\nset key");
}

/* A time panel of one column (SI units as in the file) with its lower and upper limits. */
typedef struct {
  int slot, col, colour;
  const char *title, *ylabel, *key;
  double lim_lo, lim_hi;
  const char *name_lo, *name_hi;
} ea__col_panel_t;

static void ea__panel_col(ea_plot_t *p, const ea_traj_t *tr, const ea__col_panel_t *c) {
  char plot[2048];
  double lo, hi;
  ea__col_range(tr, c->col, 1.0, &lo, &hi);
  ea__time_panel(p, c->slot, c->title, c->ylabel);
  int u = snprintf(plot, sizeof plot, "plot $hist u 1:%d w l lw 2 lc rgb '%s' t '%s'",
                   EA__COL(c->col), ea_plot_colour(c->colour), c->key);
  u = ea__limit_term(plot, sizeof plot, u, c->lim_lo, lo, hi, c->name_lo);
  ea__limit_term(plot, sizeof plot, u, c->lim_hi, lo, hi, c->name_hi);
  ea_plot_cmd(p, "%s", plot);
}

/* Extends [lo, hi] by column c's range in degrees. */
static void ea__range_deg(const ea_traj_t *tr, int c, double *lo, double *hi) {
  double l2, h2;
  ea__col_range(tr, c, 1.0 / EA__DEG, &l2, &h2);
  *lo = fmin(*lo, l2);
  *hi = fmax(*hi, h2);
}

/* Appends the base coordinate's column c (in degrees) to a plot command of length u. */
static int ea__base_term(char *plot, size_t len, int u, int c, const char *key) {
  return u + snprintf(plot + u, len - (size_t)u, ", '' u 1:($%d*deg) w l lw 2 lc rgb '%s' t '%s'",
                      EA__COL(c), ea_plot_colour(3), key);
}

/* (c) cable, shoulder and (when it moves) base angles. */
static void ea__panel_angles(ea_plot_t *p, const ea_traj_t *tr, const ea_actuators_t *lim,
                             int base) {
  char plot[2048];
  double lo = INFINITY, hi = -INFINITY;
  ea__range_deg(tr, EA_TRAJ_theta0, &lo, &hi);
  ea__range_deg(tr, EA_TRAJ_cable_angle, &lo, &hi);
  if (base) ea__range_deg(tr, EA_TRAJ_base_angle, &lo, &hi);
  ea__time_panel(p, 1, "(c) angles", "angle [deg]");
  int u = snprintf(plot, sizeof plot,
                   "plot $hist u 1:($%d*deg) w l lw 2 lc rgb '%s' t 'cable angle {/Symbol a}', "
                   "'' u 1:($%d*deg) w l lw 2 lc rgb '%s' t 'shoulder angle {/Symbol q}_0'",
                   EA__COL(EA_TRAJ_cable_angle), ea_plot_colour(1), EA__COL(EA_TRAJ_theta0),
                   ea_plot_colour(2));
  if (base) u = ea__base_term(plot, sizeof plot, u, EA_TRAJ_base_angle, "base angle");
  u = ea__limit_term(plot, sizeof plot, u, lim->shoulder_angle_min / EA__DEG, lo, hi,
                     "{/Symbol q}_{0,min}");
  ea__limit_term(plot, sizeof plot, u, lim->shoulder_angle_max / EA__DEG, lo, hi,
                 "{/Symbol q}_{0,max}");
  ea_plot_cmd(p, "%s", plot);
}

/* (g) angular rates with the shoulder (and base) speed limits. */
static void ea__panel_rates(ea_plot_t *p, const ea_traj_t *tr, const ea_actuators_t *lim,
                            int base) {
  char plot[2048];
  double lo = INFINITY, hi = -INFINITY;
  ea__range_deg(tr, EA_TRAJ_theta0_rate, &lo, &hi);
  ea__range_deg(tr, EA_TRAJ_cable_angle_rate, &lo, &hi);
  if (base) ea__range_deg(tr, EA_TRAJ_base_angle_rate, &lo, &hi);
  ea__time_panel(p, 5, "(g) angular rates", "rate [deg/s]");
  int u = snprintf(plot, sizeof plot,
                   "plot $hist u 1:($%d*deg) w l lw 2 lc rgb '%s' t 'd{/Symbol a}/dt', "
                   "'' u 1:($%d*deg) w l lw 2 lc rgb '%s' t 'd{/Symbol q}_0/dt'",
                   EA__COL(EA_TRAJ_cable_angle_rate), ea_plot_colour(1),
                   EA__COL(EA_TRAJ_theta0_rate), ea_plot_colour(2));
  if (base) u = ea__base_term(plot, sizeof plot, u, EA_TRAJ_base_angle_rate, "base rate");
  u = ea__limit_term(plot, sizeof plot, u, -lim->shoulder_speed_max / EA__DEG, lo, hi,
                     "-|d{/Symbol q}_0/dt|_{max}");
  u = ea__limit_term(plot, sizeof plot, u, lim->shoulder_speed_max / EA__DEG, lo, hi,
                     "+|d{/Symbol q}_0/dt|_{max}");
  if (base) {
    u = ea__limit_term(plot, sizeof plot, u, -lim->base_speed_max / EA__DEG, lo, hi,
                       "-base speed_{max}");
    ea__limit_term(plot, sizeof plot, u, lim->base_speed_max / EA__DEG, lo, hi,
                   "+base speed_{max}");
  }
  ea_plot_cmd(p, "%s", plot);
}

/* (i) natural frequencies of a plan's model (nf > 0 columns), else the angular
 * accelerations. */
static void ea__panel_last(ea_plot_t *p, const ea_traj_t *tr, const ea_traj_figure_opts_t *o,
                           int nf, int base) {
  char plot[2048];
  const ea_actuators_t *lim = &o->lim;
  if (nf > 0) {
    char title[400];
    snprintf(title, sizeof title, "(i) natural frequencies (%s)",
             o->f1 ? "FE frequency model" : "reduced model");
    ea__time_panel(p, 7, title, "f [Hz]");
    int u = snprintf(plot, sizeof plot, "plot ");
    for (int i = 0; i < nf; ++i)
      u += snprintf(plot + u, sizeof plot - (size_t)u,
                    "%s$hist u 1:%d w l lw 2 lc rgb '%s' t 'f_%d'", i ? ", " : "",
                    EA_TRAJ_NCOL + 1 + i, ea_plot_colour(i), i + 1);
    if (o->f1_min_hz > 0)
      snprintf(plot + u, sizeof plot - (size_t)u,
               ", %.9g w l dt 2 lw 1.5 lc rgb '#444444' t 'f_{1,min}'", o->f1_min_hz);
  } else {
    double lo, hi;
    ea__col_range(tr, EA_TRAJ_cable_angle_acc, 1.0 / EA__DEG, &lo, &hi);
    if (base) ea__range_deg(tr, EA_TRAJ_base_angle_acc, &lo, &hi);
    ea__time_panel(p, 7, "(i) angular accelerations", "acceleration [deg/s^2]");
    int u = snprintf(plot, sizeof plot,
                     "plot $hist u 1:($%d*deg) w l lw 2 lc rgb '%s' t 'd^2{/Symbol a}/dt^2'",
                     EA__COL(EA_TRAJ_cable_angle_acc), ea_plot_colour(1));
    if (base) {
      u += snprintf(plot + u, sizeof plot - (size_t)u,
                    ", '' u 1:($%d*deg) w l lw 2 lc rgb '%s' t 'base'",
                    EA__COL(EA_TRAJ_base_angle_acc), ea_plot_colour(3));
      u = ea__limit_term(plot, sizeof plot, u, -lim->base_accel_max / EA__DEG, lo, hi,
                         "-base a_{max}");
      ea__limit_term(plot, sizeof plot, u, lim->base_accel_max / EA__DEG, lo, hi, "+base a_{max}");
    }
  }
  ea_plot_cmd(p, "%s", plot);
}

ea_status_t ea_traj_figure(const ea_traj_t *tr, ea_shooter_t *sh, const ea_traj_figure_opts_t *opts,
                           const char *path, ea_error_t *err) {
  if (!tr || !sh || !path || tr->n < 2)
    return ea_error_set(err, EA_ERR_ARG, "ea_traj_figure: NULL argument or empty trajectory");
  const ea_arm_t *arm = ea_shooter_arm(sh);
  ea_traj_figure_opts_t o;
  if (opts)
    o = *opts;
  else
    ea_traj_figure_opts_default(&o, arm);
  const ea_actuators_t *lim = &o.lim;
  ea_plot_t *p = NULL;
  ea_status_t st = ea_plot_open(&p, path, 1500, 1350, err);
  if (st) return st;
  ea__traj_workspace_data(p, tr, sh, lim->cable_length_min);
  const int nf = ea__traj_hist_data(p, tr, &o);
  char head[1100], quoted[2300];
  snprintf(head, sizeof head, "%.1000s  (duration %.4g s)", o.title ? o.title : "trajectory",
           EA_TRAJ_AT(tr, tr->n - 1, EA_TRAJ_t) - EA_TRAJ_AT(tr, 0, EA_TRAJ_t));
  ea_plot_cmd(p, "deg = 180.0 / pi");
  ea_plot_cmd(p, "set multiplot title %s noenhanced", ea_plot_quote(head, quoted, sizeof quoted));
  double blo, bhi;
  ea__col_range(tr, EA_TRAJ_base_angle, 1.0, &blo, &bhi);
  const int base = blo < bhi || fabs(blo) > 0;
  ea__panel_workspace(p, arm, &o, blo < bhi);
  if (blo < bhi) ea__panel_top(p, tr);
  const ea__col_panel_t cols[] = {
      {0, EA_TRAJ_cable_length, 0, "(b) cable length", "L_c [m]", "L_c", lim->cable_length_min,
       lim->cable_length_max, "L_{c,min}", "L_{c,max}"},
      {2, EA_TRAJ_tension, 0, "(d) cable tension", "T [N]", "tension T", lim->tension_min,
       lim->tension_max, "T_{min}", "T_{max}"},
      {3, EA_TRAJ_shoulder_torque, 1, "(e) shoulder torque", "EI {/Symbol k}_0 [N m]",
       "shoulder torque", -lim->shoulder_torque_max, lim->shoulder_torque_max, "-{/Symbol t}_{max}",
       "+{/Symbol t}_{max}"},
      {4, EA_TRAJ_cable_length_rate, 0, "(f) cable speed", "dL_c/dt [m/s]", "dL_c/dt",
       -lim->cable_speed_max, lim->cable_speed_max, "-v_{max}", "+v_{max}"},
      {6, EA_TRAJ_cable_length_acc, 0, "(h) cable acceleration", "d^2L_c/dt^2 [m/s^2]",
       "d^2L_c/dt^2", -lim->cable_accel_max, lim->cable_accel_max, "-a_{max}", "+a_{max}"},
  };
  /* panels in the order (b) .. (i) */
  ea__panel_col(p, tr, &cols[0]);
  ea__panel_angles(p, tr, lim, base);
  ea__panel_col(p, tr, &cols[1]);
  ea__panel_col(p, tr, &cols[2]);
  ea__panel_col(p, tr, &cols[3]);
  ea__panel_rates(p, tr, lim, base);
  ea__panel_col(p, tr, &cols[4]);
  ea__panel_last(p, tr, &o, nf, base);
  ea_plot_cmd(p, "unset multiplot");
  return ea_plot_close(p, err);
}
