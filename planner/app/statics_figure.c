/* Figures of the statics commands: the workspace regions (Fig. 3) and the
 * shoulder-torque map, through the project's gnuplot module (figure.c). */
#include "ea_util.h"
#include "figure_impl.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

ea_status_t ea_workspace_figure(const ea_arm_t *arm, ea_shooter_t *sh, const double *gam, int ng,
                                const ea_config_point_t *outer, int n, double inner_length,
                                int limits, const char *path, ea_error_t *err) {
  if (!arm || !sh || !gam || !outer || ng < 1 || n < 2 || !path)
    return ea_error_set(err, EA_ERR_ARG, "ea_workspace_figure: bad argument");
  ea_plot_t *pl;
  ea_status_t st = ea_plot_open(&pl, path, 900, 700, err);
  if (st) return st;
  char plot[8192], style[96];
  int used = snprintf(plot, sizeof plot, "plot ");
  /* T = 0 shapes of the first payload, under everything */
  ea_plot_data_begin(pl, "beams");
  ea_load_t load0 = {ea_arm_tip_mass(arm, ea_arm_payload_from_factor(arm, gam[0]))};
  ea_shooter_set_load(sh, &load0);
  const int step = (n - 1) / 3 > 0 ? (n - 1) / 3 : 1;
  for (int k = 0; k < n; k += step) {
    const ea_config_point_t *o = outer + k;
    if (o->status) continue;
    ea_plot_beam(pl, sh, (double[]){o->alpha, o->tension, o->theta0, o->kappa0}, 61);
  }
  ea_plot_data_end(pl);
  used += snprintf(plot + used, sizeof plot - (size_t)used,
                   "$beams w l lc rgb '#bbbbbb' t 'T = 0 shapes ({/Symbol g} = %g)'", gam[0]);
  int marked = 0;
  for (int g = 0; g < ng && used < (int)sizeof plot - 400; ++g) {
    char name[32];
    snprintf(name, sizeof name, "region%d", g);
    if (!ea_plot_region(pl, name, arm, outer + (size_t)g * n, n, inner_length)) continue;
    ea_plot_style(g, 0, style, sizeof style);
    used += snprintf(plot + used, sizeof plot - (size_t)used,
                     ", $%s w l lw 2 %s t '{/Symbol g} = %g'", name, style, gam[g]);
    if (!limits) continue;
    int past = 0;
    for (int k = 0; k < n; ++k)
      past += outer[(size_t)g * n + k].status == EA_OK && !outer[(size_t)g * n + k].admissible;
    if (!past) continue;
    snprintf(name, sizeof name, "past%d", g);
    ea_plot_data_begin(pl, name);
    for (int k = 0; k < n; ++k) {
      const ea_config_point_t *o = outer + (size_t)g * n + k;
      if (o->status == EA_OK && !o->admissible) ea_plot_data_row(pl, 2, (double[]){o->x, o->y});
    }
    ea_plot_data_end(pl);
    used += snprintf(plot + used, sizeof plot - (size_t)used,
                     ", $%s w p pt 2 ps 0.7 lc rgb '%s' %s", name, ea_plot_colour(g), "notitle");
    ++marked;
  }
  ea_plot_data_begin(pl, "root");
  ea_plot_data_row(pl, 2, (double[]){arm->x_c, arm->y_c});
  ea_plot_data_end(pl);
  snprintf(plot + used, sizeof plot - (size_t)used,
           ", $root w p pt 7 ps 1.5 lc rgb '#c0392b' t 'cable root'%s",
           marked ? ", NaN w p pt 2 lc rgb 'black' t 'outer edge past an arm limit (x)'" : "");
  double amin = INFINITY, amax = -INFINITY;
  for (int k = 0; k < n; ++k)
    if (isfinite(outer[k].alpha)) {
      amin = fmin(amin, outer[k].alpha);
      amax = fmax(amax, outer[k].alpha);
    }
  ea_plot_cmd(pl, "set size ratio -1\nset xlabel 'x [m]'\nset ylabel 'y [m]'\nset key outside "
                  "right top");
  ea_plot_cmd(pl,
              "set title \"Workspace regions for payload factors {/Symbol g} (Fig. 3)\\n"
              "T >= 0, L_c >= %.3f m, {/Symbol a} from %.0f to %.0f deg\\n%s\"",
              inner_length, amin / EA__DEG, amax / EA__DEG,
              !limits  ? "without the arm's actuator limits"
              : marked ? "the arm's limits cut a region where its outer edge is marked x"
                       : "the arm's limits hold on the whole outer edge");
  ea_plot_cmd(pl, "%s", plot);
  return ea_plot_close(pl, err);
}

/* Edges of cell j of a grid v[0..n-1] (midpoints to the neighbours; the ends mirrored). */
static void ea__cell_edges(const double *v, int n, int j, double *lo, double *hi) {
  if (n < 2) {
    *lo = v[j] - 0.5;
    *hi = v[j] + 0.5;
    return;
  }
  const double dl = j > 0 ? 0.5 * (v[j] - v[j - 1]) : 0.5 * (v[1] - v[0]);
  const double dh = j < n - 1 ? 0.5 * (v[j + 1] - v[j]) : 0.5 * (v[n - 1] - v[n - 2]);
  *lo = v[j] - dl;
  *hi = v[j] + dh;
}

ea_status_t ea_torque_map_figure(const double *Ls, int nL, const double *As, int nA,
                                 const ea_config_point_t *cells, const ea_actuators_t *lim,
                                 double tip_mass, const char *path, ea_error_t *err) {
  if (!Ls || !As || !cells || !lim || nL < 1 || nA < 1 || !path)
    return ea_error_set(err, EA_ERR_ARG, "ea_torque_map_figure: bad argument");
  ea_plot_t *pl;
  ea_status_t st = ea_plot_open(&pl, path, 900, 650, err);
  if (st) return st;
  ea_plot_data_begin(pl, "map");
  for (int i = 0; i < nA; ++i) {
    for (int j = 0; j < nL; ++j) {
      const ea_config_point_t *p = &cells[(size_t)i * nL + j];
      if (p->status == EA_OK)
        ea_plot_cmd(pl, "%.9g %.9g %.9g", Ls[j], As[i] / EA__DEG, p->shoulder_torque);
      else
        ea_plot_cmd(pl, "%.9g %.9g NaN", Ls[j], As[i] / EA__DEG);
    }
    ea_plot_cmd(pl, "%s", "");
  }
  ea_plot_data_end(pl);
  /* cells past a limit: the torque limit (hatched), any other (crossed) */
  const double tmax = lim->shoulder_torque_max;
  int n_torque = 0, n_other = 0;
  for (int pass = 0; pass < 2; ++pass) {
    ea_plot_data_begin(pl, pass ? "other" : "torque");
    for (int i = 0; i < nA; ++i)
      for (int j = 0; j < nL; ++j) {
        const ea_config_point_t *p = &cells[(size_t)i * nL + j];
        if (p->status != EA_OK) continue;
        const int over = fabs(p->shoulder_torque) > tmax;
        if (pass ? (over || p->admissible) : !over) continue;
        double x0, x1, y0, y1;
        ea__cell_edges(Ls, nL, j, &x0, &x1);
        ea__cell_edges(As, nA, i, &y0, &y1);
        ea_plot_data_row(pl, 6,
                         (double[]){Ls[j], As[i] / EA__DEG, x0, x1, y0 / EA__DEG, y1 / EA__DEG});
        ++*(pass ? &n_other : &n_torque);
      }
    ea_plot_data_end(pl);
  }
  ea_plot_palette_viridis(pl);
  ea_plot_cmd(pl, "set xlabel 'cable length L_c [m]'\nset ylabel 'cable angle {/Symbol a} [deg]'\n"
                  "set cblabel 'shoulder torque EI {/Symbol k}_0 [N m]'\nset key below box opaque");
  ea_plot_cmd(pl,
              "set title \"Shoulder torque map, tip mass %.3g kg (white: outside the workspace, "
              "T < 0)\\nlimits of the arm file: |EI {/Symbol k}_0| <= %g N m%s\"",
              tip_mass, tmax,
              n_torque  ? ""
              : n_other ? " (no cell past it)"
                        : "; no cell past a limit");
  char plot[1024];
  int used = snprintf(plot, sizeof plot, "plot $map u 1:2:3 w image notitle");
  if (n_torque)
    used += snprintf(plot + used, sizeof plot - (size_t)used,
                     ", $torque u 1:2:3:4:5:6 w boxxyerror fs transparent pattern 5 noborder "
                     "lc rgb '#e41a1c' t 'hatched: past the shoulder torque limit "
                     "(|EI {/Symbol k}_0| > %g N m)'",
                     tmax);
  if (n_other) {
    /* which other limits the crossed cells are past */
    int tlo = 0, thi = 0, len = 0, sh = 0;
    for (size_t k = 0; k < (size_t)nL * nA; ++k) {
      const ea_config_point_t *c = &cells[k];
      if (c->status != EA_OK || c->admissible || fabs(c->shoulder_torque) > tmax) continue;
      tlo |= c->tension < lim->tension_min;
      thi |= c->tension > lim->tension_max;
      len |= c->cable_length < lim->cable_length_min || c->cable_length > lim->cable_length_max;
      sh |= c->theta0 < lim->shoulder_angle_min || c->theta0 > lim->shoulder_angle_max;
    }
    char what[256];
    snprintf(what, sizeof what, "%s%s%s%s", tlo ? ", T < T_{min}" : "", thi ? ", T > T_{max}" : "",
             len ? ", cable length out of range" : "", sh ? ", shoulder angle out of range" : "");
    snprintf(plot + used, sizeof plot - (size_t)used,
             ", $other u 1:2 w p pt 2 ps 1.5 lw 2 lc rgb '#e41a1c' t 'x: past another limit "
             "(%s)'",
             what[0] ? what + 2 : "tension, cable length or shoulder angle");
  }
  ea_plot_cmd(pl, "%s", plot);
  return ea_plot_close(pl, err);
}
