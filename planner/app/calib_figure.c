/* Figures of a calibration (elasticarm calibrate --figure, --ringdown-figure), through the
 * project's gnuplot module (figure.c): the static records against the calibrated model per
 * cable angle, the ring-downs' frequencies against the FE frequencies over cable length (as
 * the paper's Fig. 5 shows its experimental points), each ring-down with its fitted curve. */
#include "ea_util.h"
#include "figure_impl.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* A group of static rows: one cable angle (within half a degree) and one payload. */
typedef struct {
  double alpha, payload, Lmin, Lmax;
  int n;
} ea__cgroup_t;

#define EA__MAX_GROUPS 12

static int ea__groups(const ea_calib_result_t *res, const ea_calib_record_t *recs, int nrec,
                      ea__cgroup_t *g) {
  int ng = 0;
  for (int r = 0; r < nrec; ++r) {
    if (recs[r].kind != EA_CALIB_STATIC || !res->rec[r].alpha) continue;
    for (int i = 0; i < recs[r].rows; ++i) {
      const double a = res->rec[r].alpha[i], L = recs[r].cable_length[i];
      const double p =
          recs[r].payload_unknown ? res->value[EA_CALIB_P_PAYLOAD] : recs[r].payload[i];
      int k = 0;
      for (; k < ng; ++k)
        if (fabs(g[k].alpha - a) < 0.5 * EA__DEG && fabs(g[k].payload - p) < 1e-9) break;
      if (k == ng) {
        if (ng == EA__MAX_GROUPS) continue;
        g[ng++] = (ea__cgroup_t){a, p, L, L, 0};
      }
      g[k].alpha = (g[k].alpha * g[k].n + a) / (g[k].n + 1);
      g[k].Lmin = fmin(g[k].Lmin, L);
      g[k].Lmax = fmax(g[k].Lmax, L);
      g[k].n++;
    }
  }
  return ng;
}

/* Statics of the calibrated arm at commanded cable length L (stretched by T / EA_c) and cable
 * angle alpha, warm-started from p (have: p holds a guess). */
static ea_status_t ea__cal_statics(ea_shooter_t *sh, const ea_arm_t *arm, double L, double alpha,
                                   double p[EA_NP], int have, ea_statics_solution_t *sol) {
  ea_statics_settings_t ss;
  ea_statics_settings_default(&ss);
  ss.allow_negative_tension = 1;
  double T = have ? p[EA_P_TENSION] : 0.0;
  for (int it = 0; it < 4; ++it) {
    ea_statics_problem_t pr = ea_statics_problem_cable(L * (1 + fmax(T, 0) / arm->EA_cable), alpha);
    ea_status_t st = ea_statics_solve(sh, &pr, &ss, have ? p : NULL, sol, NULL);
    if (st && have) st = ea_statics_solve(sh, &pr, &ss, NULL, sol, NULL);
    if (st) return st;
    memcpy(p, sol->p, sizeof sol->p);
    have = 1;
    T = sol->p[EA_P_TENSION];
  }
  return EA_OK;
}

ea_status_t ea_calib_figure(const ea_calib_result_t *res, const ea_calib_record_t *recs, int nrec,
                            const char *path, ea_error_t *err) {
  if (!res || !recs || !path) return ea_error_set(err, EA_ERR_ARG, "ea_calib_figure: NULL");
  ea__cgroup_t grp[EA__MAX_GROUPS];
  const int ng = ea__groups(res, recs, nrec, grp);
  int have[EA_CALIB_NCH] = {0}, nring = 0;
  for (int r = 0; r < nrec; ++r) {
    if (recs[r].kind == EA_CALIB_STATIC)
      for (int c = 0; c < EA_CALIB_NCH; ++c)
        have[c] |= recs[r].has[c];
    else
      nring += res->rec[r].ring.modes > 0;
  }
  /* panels: theta0, torque, tension (those measured), frequencies (with ring-downs) */
  int panel[4], np = 0;
  if (ng) panel[np++] = EA_CALIB_CH_THETA0;
  if (ng && have[EA_CALIB_CH_TORQUE]) panel[np++] = EA_CALIB_CH_TORQUE;
  if (ng && have[EA_CALIB_CH_TENSION]) panel[np++] = EA_CALIB_CH_TENSION;
  if (nring) panel[np++] = -1;
  if (!np) return ea_error_set(err, EA_ERR_INPUT, "no record to draw");
  const ea_arm_t *arm = &res->arm;
  ea_shooter_t *sh = NULL;
  ea_status_t st = ea_shooter_alloc(arm, NULL, &sh, err);
  if (st) return st;
  ea_plot_t *pl;
  if ((st = ea_plot_open(&pl, path, 650 * (np > 2 ? 2 : np), np > 2 ? 1000 : 520, err))) {
    ea_shooter_free(sh);
    return st;
  }
  /* model curves per group: L, theta0 [deg], torque, tension */
  for (int k = 0; k < ng; ++k) {
    char name[32];
    snprintf(name, sizeof name, "model%d", k);
    ea_plot_data_begin(pl, name);
    ea_load_t load = {arm->m_hand + grp[k].payload};
    ea_shooter_set_load(sh, &load);
    double p[EA_NP];
    int hv = 0;
    const double L0 = grp[k].Lmin - 0.02, L1 = grp[k].Lmax + 0.02;
    for (int i = 0; i <= 60; ++i) {
      const double L = L0 + (L1 - L0) * i / 60.0;
      ea_statics_solution_t sol;
      if (ea__cal_statics(sh, arm, L, grp[k].alpha, p, hv, &sol)) {
        hv = 0;
        ea_plot_data_row(pl, 1, (double[]){NAN});
        continue;
      }
      hv = 1;
      ea_plot_data_row(pl, 4,
                       (double[]){L, sol.p[EA_P_THETA0] / EA__DEG, arm->EI * sol.p[EA_P_KAPPA0],
                                  sol.p[EA_P_TENSION]});
    }
    ea_plot_data_end(pl);
    /* measured rows of the group: L, theta0 [deg], torque, tension (NaN-free: absent = far) */
    snprintf(name, sizeof name, "meas%d", k);
    ea_plot_data_begin(pl, name);
    for (int r = 0; r < nrec; ++r) {
      if (recs[r].kind != EA_CALIB_STATIC || !res->rec[r].alpha) continue;
      for (int i = 0; i < recs[r].rows; ++i) {
        if (fabs(res->rec[r].alpha[i] - grp[k].alpha) >= 0.5 * EA__DEG ||
            fabs((recs[r].payload_unknown ? res->value[EA_CALIB_P_PAYLOAD] : recs[r].payload[i]) -
                 grp[k].payload) >= 1e-9)
          continue;
        const double v[4] = {
            recs[r].cable_length[i], recs[r].ch[EA_CALIB_CH_THETA0][i] / EA__DEG,
            recs[r].has[EA_CALIB_CH_TORQUE] ? recs[r].ch[EA_CALIB_CH_TORQUE][i] : 1e30,
            recs[r].has[EA_CALIB_CH_TENSION] ? recs[r].ch[EA_CALIB_CH_TENSION][i] : 1e30};
        ea_plot_data_row(pl, 4, v);
      }
    }
    ea_plot_data_end(pl);
  }
  ea_plot_cmd(pl,
              "set multiplot layout %d,%d title 'calibrated arm against the records (lines: "
              "model, points: measured)'",
              np > 2 ? 2 : 1, np > 2 ? 2 : np);
  ea_plot_cmd(pl, "set key top right box opaque font ',8'\nset grid\nset xlabel 'cable length L_c "
                  "[m]'");
  for (int q = 0; q < np; ++q) {
    if (panel[q] >= 0) {
      const int col = panel[q] == EA_CALIB_CH_THETA0 ? 2 : panel[q] == EA_CALIB_CH_TORQUE ? 3 : 4;
      const char *yl = panel[q] == EA_CALIB_CH_THETA0   ? "shoulder angle {/Symbol q}_0 [deg]"
                       : panel[q] == EA_CALIB_CH_TORQUE ? "shoulder torque [N m]"
                                                        : "cable tension [N]";
      ea_plot_cmd(pl, "set ylabel '%s'\nset yrange [*:*]\nset title '(%c) %s'", yl, 'a' + q,
                  panel[q] == EA_CALIB_CH_THETA0   ? "shoulder angle"
                  : panel[q] == EA_CALIB_CH_TORQUE ? "shoulder torque"
                                                   : "tension");
      char plot[8192];
      int used = snprintf(plot, sizeof plot, "plot ");
      for (int k = 0; k < ng && used < (int)sizeof plot - 300; ++k) {
        used += snprintf(plot + used, sizeof plot - (size_t)used,
                         "%s$model%d u 1:%d w l lw 1.5 lc rgb '%s' t '{/Symbol a} = %.1f deg%s', "
                         "$meas%d u 1:(($%d) < 1e29 ? ($%d) : 1/0) w p pt 7 ps 0.6 lc rgb '%s' "
                         "notitle",
                         k ? ", " : "", k, col, ea_plot_colour(k), grp[k].alpha / EA__DEG,
                         grp[k].payload > 0 ? ", payload" : "", k, col, col, ea_plot_colour(k));
      }
      ea_plot_cmd(pl, "%s", plot);
    } else {
      /* frequencies: FE along cable length at each ring-down's cable angle, measured points */
      ea_fe_settings_t fs;
      ea_fe_settings_default(&fs);
      fs.modes = 3;
      ea_fe_model_t *m = NULL;
      ea_plot_cmd(pl,
                  "set ylabel 'natural frequency [Hz]'\nset logscale y\nset title '(%c) "
                  "frequencies (Fig. 5 style)'",
                  'a' + q);
      char plot[8192];
      int used = snprintf(plot, sizeof plot, "plot ");
      int nc = 0;
      for (int r = 0; r < nrec; ++r) {
        if (recs[r].kind != EA_CALIB_RINGDOWN || res->rec[r].ring.modes < 1) continue;
        /* the hold's cable angle */
        ea_load_t load = {arm->m_hand + (recs[r].payload_unknown ? res->value[EA_CALIB_P_PAYLOAD]
                                                                 : recs[r].payload_kg)};
        ea_shooter_set_load(sh, &load);
        ea_statics_problem_t pr = {{EA_GIVEN_CABLE_LENGTH, EA_GIVEN_THETA0},
                                   {recs[r].hold_cable_length, recs[r].hold_theta0}};
        ea_statics_solution_t sol;
        if (ea_statics_solve(sh, &pr, NULL, NULL, &sol, NULL)) continue;
        char name[32];
        snprintf(name, sizeof name, "fe%d", r);
        if (!m && ea_fe_model_alloc(arm, &fs, &m, NULL)) break;
        ea_fe_model_set_load(m, &load);
        double Ls[41];
        ea_freq_point_t pts[41];
        for (int i = 0; i <= 40; ++i)
          Ls[i] = arm->act.cable_length_min +
                  (0.9 * arm->length - arm->act.cable_length_min) * i / 40.0;
        ea_freq_sweep(sh, m, Ls, 41, sol.p[EA_P_ALPHA], pts);
        ea_plot_data_begin(pl, name);
        for (int i = 0; i <= 40; ++i)
          if (pts[i].status == EA_OK)
            ea_plot_data_row(pl, 4,
                             (double[]){Ls[i], pts[i].modes.freq_hz[0], pts[i].modes.freq_hz[1],
                                        pts[i].modes.freq_hz[2]});
          else
            ea_plot_data_row(pl, 1, (double[]){NAN});
        ea_plot_data_end(pl);
        snprintf(name, sizeof name, "fm%d", r);
        ea_plot_data_begin(pl, name);
        for (int k = 0; k < res->rec[r].ring.modes; ++k)
          if (res->rec[r].ring.mode_index[k] >= 0)
            ea_plot_data_row(pl, 3,
                             (double[]){recs[r].hold_cable_length, res->rec[r].ring.freq_hz[k],
                                        res->rec[r].ring.freq_se_hz[k]});
        ea_plot_data_end(pl);
        char ttl[96];
        snprintf(ttl, sizeof ttl, "t 'FE modes 1-3, {/Symbol a} = %.1f deg'",
                 sol.p[EA_P_ALPHA] / EA__DEG);
        for (int mm = 0; mm < 3 && used < (int)sizeof plot - 300; ++mm)
          used +=
              snprintf(plot + used, sizeof plot - (size_t)used, "%s$fe%d u 1:%d w l lc rgb '%s' %s",
                       nc || mm ? ", " : "", r, mm + 2, ea_plot_colour(nc), mm ? "notitle" : ttl);
        if (used < (int)sizeof plot - 300) {
          used += snprintf(plot + used, sizeof plot - (size_t)used,
                           ", $fm%d u 1:2:3 w yerrorbars pt 7 ps 0.8 lc rgb '%s' t "
                           "'ring-down {/Symbol a} = %.1f deg'",
                           r, ea_plot_colour(nc), sol.p[EA_P_ALPHA] / EA__DEG);
        }
        ++nc;
      }
      ea_fe_model_free(m);
      if (!nc) used += snprintf(plot + used, sizeof plot - (size_t)used, "1/0 notitle");
      ea_plot_cmd(pl, "%s\nunset logscale y", plot);
    }
  }
  ea_plot_cmd(pl, "unset multiplot");
  ea_shooter_free(sh);
  return ea_plot_close(pl, err);
}

ea_status_t ea_calib_ringdown_figure(const ea_calib_result_t *res, const ea_calib_record_t *recs,
                                     int nrec, const char *path, ea_error_t *err) {
  if (!res || !recs || !path)
    return ea_error_set(err, EA_ERR_ARG, "ea_calib_ringdown_figure: NULL");
  int idx[6], n = 0;
  for (int r = 0; r < nrec && n < 6; ++r)
    if (recs[r].kind == EA_CALIB_RINGDOWN && res->rec[r].ring.modes > 0) idx[n++] = r;
  if (!n) return ea_error_set(err, EA_ERR_INPUT, "--ringdown-figure: no ring-down record fitted");
  ea_plot_t *pl;
  ea_status_t st = ea_plot_open(&pl, path, 1100, 330 * n, err);
  if (st) return st;
  ea_plot_cmd(pl, "set multiplot layout %d,1 title 'ring-downs and their damped-sinusoid fits'", n);
  ea_plot_cmd(pl, "set key top right box opaque font ',8'\nset grid\nset xlabel 't [s]'");
  for (int q = 0; q < n; ++q) {
    const int r = idx[q];
    const ea_calib_record_t *rec = &recs[r];
    const ea_ringdown_fit_t *f = &res->rec[r].ring;
    /* the channel with the most signal against its noise */
    int best = -1;
    double bs = -1;
    for (int c = 0; c < EA_CALIB_NCH; ++c) {
      if (!rec->has[c]) continue;
      double a = 0;
      for (int k = 0; k < f->modes; ++k)
        a += hypot(f->amp[c][k][0], f->amp[c][k][1]);
      const double snr = a / fmax(f->noise[c], 1e-300);
      if (snr > bs) bs = snr, best = c;
    }
    char name[32];
    snprintf(name, sizeof name, "rd%d", q);
    ea_plot_data_begin(pl, name);
    const int stride = rec->rows > 4000 ? rec->rows / 4000 : 1;
    for (int i = 0; i < rec->rows; i += stride)
      ea_plot_data_row(pl, 3,
                       (double[]){rec->t[i], rec->ch[best][i],
                                  ea_ringdown_eval(f, best, rec->t[i] - rec->t[0])});
    ea_plot_data_end(pl);
    char modes[600];
    size_t o = 0;
    modes[0] = '\0';
    for (int k = 0; k < f->modes && o < sizeof modes; ++k)
      o += (size_t)snprintf(modes + o, sizeof modes - o, "%s%.4g Hz {/Symbol z} %.3g%s",
                            k ? ", " : "", f->freq_hz[k], f->zeta[k],
                            f->mode_index[k] >= 0 ? "" : " (unmatched)");
    char qpath[300], title[1200];
    ea_plot_enh(rec->path, qpath, sizeof qpath);
    snprintf(title, sizeof title, "(%c) %s: %s", 'a' + q, qpath, modes);
    char tq[1300];
    char yl[64];
    ea_plot_cmd(
        pl, "set title %s font ',9'\nset ylabel '%s [%s]'", ea_plot_quote(title, tq, sizeof tq),
        ea_plot_enh(ea_calib_channel_column(best), yl, sizeof yl), ea_calib_channel_unit(best));
    ea_plot_cmd(pl,
                "plot $%s u 1:2 w l lw 0.5 lc rgb '#999999' t 'measured', $%s u 1:3 w l lw 1.2 lc "
                "rgb '%s' t 'fit'",
                name, name, ea_plot_colour(0));
  }
  ea_plot_cmd(pl, "unset multiplot");
  return ea_plot_close(pl, err);
}
