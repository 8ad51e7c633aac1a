/* Figure of a simulated trajectory (elasticarm simulate --figure), through the
 * project's gnuplot module (figure.c): the tip paths at equal scale in a window
 * that never collapses into a strip, the deviation from the planned tip in mm
 * (where a small deviation is seen), and the approach to rest on a log scale. */
#include "figure_impl.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* Range [lo, hi] widened about its centre to at least min_span. */
static void ea__widen(double *lo, double *hi, double min_span) {
  if (*hi - *lo >= min_span) return;
  const double c = 0.5 * (*lo + *hi);
  *lo = c - 0.5 * min_span;
  *hi = c + 0.5 * min_span;
}

ea_status_t ea_sim_figure(const ea_sim_history_t *h, const ea_sim_info_t *si,
                          const ea_sim_settings_t *s, const char *path, ea_error_t *err) {
  if (!h || !si || !s || !path || h->rows < 1)
    return ea_error_set(err, EA_ERR_ARG, "ea_sim_figure: no history to draw");
  const double *fin = si->final_static_tip;
  const int settle = s->settle > 0 && isfinite(fin[0]) && isfinite(fin[1]);
  ea_plot_t *pl;
  ea_status_t st = ea_plot_open(&pl, path, settle ? 1600 : 1150, 560, err);
  if (st) return st;
  double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
  double rmin = INFINITY, rmax = 0.0;
  ea_plot_data_begin(pl, "sim");
  for (int r = 0; r < h->rows; ++r) {
    const double *v = h->data + 6 * r;
    const double dx = 1e3 * (v[1] - v[4]), dy = 1e3 * (v[2] - v[5]);
    const double rest = settle ? 1e3 * hypot(v[1] - fin[0], v[2] - fin[1]) : NAN;
    /* (a NaN would blank the row: the rest column only when there is one) */
    ea_plot_data_row(pl, settle ? 9 : 8,
                     (double[]){v[0], v[1], v[2], v[4], v[5], dx, dy, hypot(dx, dy), rest});
    for (int c = 1; c < 5; c += 3) {
      x0 = fmin(x0, v[c]);
      x1 = fmax(x1, v[c]);
      y0 = fmin(y0, v[c + 1]);
      y1 = fmax(y1, v[c + 1]);
    }
    if (settle && v[0] >= h->data[0] + si->duration && rest > 0) {
      rmin = fmin(rmin, rest);
      rmax = fmax(rmax, rest);
    }
  }
  ea_plot_data_end(pl);
  /* (a): equal scale; the window at least 0.4 times as tall as wide (and as wide
   * as tall), at least 10 mm, with a 5 % margin */
  const double w = x1 - x0, ht = y1 - y0, big = fmax(fmax(w, ht), 0.01);
  ea__widen(&x0, &x1, fmax(w, w >= ht ? big : 0.4 * big));
  ea__widen(&y0, &y1, fmax(ht, w >= ht ? 0.4 * big : big));
  const double mx = 0.05 * (x1 - x0), my = 0.05 * (y1 - y0);
  const double t_end_motion = h->data[0] + si->duration;
  const double pw = settle ? 1.0 / 3.0 : 0.5; /* panel width; 0.9 high under the title */
  ea_plot_cmd(pl,
              "set multiplot title 'FE transient of the trajectory (%s cable, "
              "dt = %g s, tip mass %.3g kg)'",
              s->cable_active ? "active" : "passive", s->dt, si->tip_mass);
  ea_plot_cmd(
      pl,
      "set size ratio -1 %.6f,0.9\nset origin 0,0\nset xrange [%.9g:%.9g]\nset yrange [%.9g:%.9g]\n"
      "set xlabel 'x [m]'\nset ylabel 'y [m]'\nset key outside top center horizontal box opaque\n"
      "set title '(a) tip path (equal scale)'",
      pw, x0 - mx, x1 + mx, y0 - my, y1 + my);
  char fin_term[200] = "";
  if (settle)
    snprintf(fin_term, sizeof fin_term,
             ", '+' u (%.17g):(%.17g) every ::0::0 w p pt 6 ps 1.5 lc rgb 'black' "
             "t 'final equilibrium'",
             fin[0], fin[1]);
  ea_plot_cmd(pl,
              "plot $sim u 4:5 w l lw 4 lc rgb '#999999' t 'planned (quasi-static)', "
              "$sim u 2:3 w l lw 1.5 lc rgb '%s' t 'FE simulation'%s",
              ea_plot_colour(0), fin_term);
  ea_plot_cmd(pl,
              "set size noratio %.6f,0.9\nset origin %.6f,0\nset autoscale xy\nset xlabel 't [s]'\n"
              "set ylabel 'tip - planned tip [mm]'\n"
              "set title \"(b) deviation from the planned tip\\nmax %.3g mm during the motion\"\n"
              "set arrow 1 from %.9g, graph 0 to %.9g, graph 1 nohead dt 2 lc rgb 'black'",
              pw, pw, 1e3 * si->max_tracking_error, t_end_motion, t_end_motion);
  ea_plot_cmd(pl,
              "plot $sim u 1:8 w l lw 2 lc rgb 'black' t '|tip - planned|', "
              "'' u 1:6 w l lw 1 lc rgb '%s' t 'x part', '' u 1:7 w l lw 1 lc rgb '%s' t 'y part', "
              "NaN w l dt 2 lc rgb 'black' t 'end of the motion (%.3g s)'",
              ea_plot_colour(0), ea_plot_colour(1), t_end_motion);
  if (settle) {
    const double tol = 1e3 * s->rest_tolerance;
    double lo = isfinite(rmin) ? fmin(rmin, tol) : 1e-3 * tol;
    double hi = fmax(isfinite(rmax) ? rmax : tol, tol);
    lo = fmax(lo, 1e-6 * hi); /* a decade range gnuplot can draw */
    char rest[160];
    const int rest_after = isfinite(si->time_to_rest) && si->time_to_rest > t_end_motion;
    if (isfinite(si->time_to_rest))
      snprintf(rest, sizeof rest, "at rest from t = %.4g s%s", si->time_to_rest,
               rest_after ? "" : ", before the motion ends");
    else
      snprintf(rest, sizeof rest, "not at rest by t = %.4g s", si->simulated_time);
    ea_plot_cmd(pl,
                "set origin %.6f,0\nunset arrow 1\nset logscale y\nset yrange [%.9g:%.9g]\nset "
                "xrange [%.9g:*]\n"
                "set ylabel '|tip - final equilibrium| [mm]'\n"
                "set title \"(c) approach to rest after the motion\\n%s\"",
                2 * pw, lo / 2, hi * 2, t_end_motion, rest);
    char rest_term[200] = "";
    if (rest_after) {
      ea_plot_cmd(pl,
                  "set arrow 2 from %.9g, graph 0 to %.9g, graph 1 nohead dt 3 lw 1.5 "
                  "lc rgb '%s'",
                  si->time_to_rest, si->time_to_rest, ea_plot_colour(2));
      snprintf(rest_term, sizeof rest_term, ", NaN w l dt 3 lw 1.5 lc rgb '%s' t 'at rest from'",
               ea_plot_colour(2));
    }
    ea_plot_cmd(pl,
                "plot $sim u 1:($9 > 0 ? $9 : NaN) w l lw 1.5 lc rgb '%s' t 'distance', "
                "%.9g w l dt 2 lw 1.5 lc rgb '#444444' t 'rest tolerance %.3g mm'%s",
                ea_plot_colour(0), tol, tol, rest_term);
  }
  ea_plot_cmd(pl, "unset multiplot");
  return ea_plot_close(pl, err);
}
