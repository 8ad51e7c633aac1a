/* CLI: frequencies (paper sec. 3.3, Fig. 5) and simulate (FE transient of a
 * trajectory). The computations are library calls (ea_freq_point, ea_freq_sweep:
 * problems/frequencies.c; ea_traj_read_any, ea_traj_fill_statics, ea_traj_simulate:
 * planner/traj/); this file parses the options and writes the tables, JSON, CSV
 * and figures. */
#include "cli_impl.h"
#include "ea_simulate.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* ------------------------------------------------------------------------ */
/* Shared pieces                                                             */
/* ------------------------------------------------------------------------ */

static int ea__fe_help_requested(int argc, char **argv) {
  return ea__cli_help_asked(argc, argv);
}

/* How the FE static state is tied to the ODE solution. */
enum { EA__FE_HOLD_TIP = 0, EA__FE_HOLD_TENSION = 1 };

static int ea__fe_model_make(const char *cmd, const ea_arm_t *arm, double tip_mass, long elements,
                             long modes, int hold, ea_fe_model_t **m) {
  ea_error_t err = {0};
  ea_fe_settings_t s;
  ea_fe_settings_default(&s);
  s.elements = (int)elements;
  if (modes > 0) s.modes = (int)modes;
  s.static_hold_tip = hold == EA__FE_HOLD_TIP;
  ea_load_t load = {tip_mass};
  ea_status_t st = ea_fe_model_alloc(arm, &s, m, &err);
  if (!st) st = ea_fe_model_set_load(*m, &load);
  if (st) {
    ea_fe_model_free(*m);
    *m = NULL;
    return ea__cli_fail(cmd, st, &err);
  }
  return 0;
}

static int ea__fe_make(const char *cmd, const ea_arm_t *arm, double tip_mass, long elements,
                       long modes, int hold, ea_shooter_t **sh, ea_fe_model_t **m) {
  ea_error_t err = {0};
  ea_status_t st = ea_shooter_alloc(arm, NULL, sh, &err);
  if (st) return ea__cli_fail(cmd, st, &err);
  ea_load_t load = {tip_mass};
  ea_shooter_set_load(*sh, &load);
  int rc = ea__fe_model_make(cmd, arm, tip_mass, elements, modes, hold, m);
  if (rc) {
    ea_shooter_free(*sh);
    *sh = NULL;
  }
  return rc;
}

/* Current FE nodal positions (x, y per node) into a data block, then a blank line. */
static void ea__fe_plot_state(ea_plot_t *pl, const double *q, const double *phi, double scale,
                              int nodes) {
  for (int i = 0; i < nodes; ++i) {
    double x = q[3 * i], y = q[3 * i + 1];
    if (phi) {
      x += scale * phi[3 * i];
      y += scale * phi[3 * i + 1];
    }
    ea_plot_data_row(pl, 2, (double[]){x, y});
  }
  ea_plot_data_row(pl, 1, (double[]){NAN});
}

static const char *ea__fe_colors[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd",
                                      "#ff7f0e", "#8c564b", "#e377c2", "#7f7f7f"};

/* Static shape and mode shapes of the model's current state into blocks
 * $static and $mode<k>; returns the number of mode blocks written. */
static int ea__fe_plot_modes(ea_plot_t *pl, ea_fe_model_t *m, int nmodes, double scale) {
  const int nodes = ea_fe_model_nodes(m), nd = 3 * nodes;
  double *q = malloc(sizeof(double) * (size_t)nd), *phi = malloc(sizeof(double) * (size_t)nd);
  int written = 0;
  if (q && phi && ea_fe_get_state(m, q, NULL) == EA_OK) {
    ea_plot_data_begin(pl, "static");
    ea__fe_plot_state(pl, q, NULL, 0.0, nodes);
    ea_plot_data_end(pl);
    for (int k = 0; k < nmodes; ++k) {
      char name[32];
      snprintf(name, sizeof name, "mode%d", k);
      ea_plot_data_begin(pl, name);
      if (ea_fe_mode_shape(m, k, phi) == EA_OK) {
        ea__fe_plot_state(pl, q, phi, scale, nodes);
      } else {
        ea_plot_data_row(pl, 2, (double[]){NAN, NAN});
      }
      ea_plot_data_end(pl);
      ++written;
    }
  }
  free(q);
  free(phi);
  return written;
}

static void ea__fe_plot_cable_block(ea_plot_t *pl, const ea_arm_t *arm, double tx, double ty) {
  ea_plot_data_begin(pl, "cable");
  ea_plot_data_row(pl, 2, (double[]){arm->x_c, arm->y_c});
  ea_plot_data_row(pl, 2, (double[]){tx, ty});
  ea_plot_data_end(pl);
}

/* Plot command of the mode-shape panel (blocks from ea__fe_plot_modes). */
static void ea__fe_plot_modes_cmd(ea_plot_t *pl, int nmodes, const double *freq) {
  char plot[2048];
  int used = snprintf(plot, sizeof plot,
                      "plot $cable w l dt 2 lc rgb '#777777' t 'cable', $static w lp lw 3 pt 7 "
                      "ps 0.5 lc rgb 'black' t 'static'");
  for (int k = 0; k < nmodes && used < (int)sizeof plot - 200; ++k)
    used += snprintf(plot + used, sizeof plot - (size_t)used,
                     ", $mode%d w l lw 1.5 lc rgb '%s' t 'mode %d, %.3f Hz'", k,
                     ea__fe_colors[k % 8], k + 1, freq[k]);
  ea_plot_cmd(pl, "%s", plot);
}

/* ------------------------------------------------------------------------ */
/* frequencies                                                               */
/* ------------------------------------------------------------------------ */

static void ea__freq_help(void) {
  printf("usage: elasticarm frequencies --cable-length M --cable-angle-deg A [options]\n"
         "       elasticarm frequencies --sweep [--cable-lengths LIST] [--cable-angle-deg A] "
         "[options]\n\n"
         "Natural frequencies of the FE model (paper sec. 3.3, eq. 24) about a static\n"
         "configuration: ODE statics (cable length and angle) -> FE static Newton (eq. 21-23)\n"
         "-> passive-cable eigenproblem. The sweep form reproduces Fig. 5 (first modes vs\n"
         "cable length at alpha = 0, statics warm-started along the sweep).\n\n"
         "  --cable-length M       cable length [m]\n"
         "  --cable-angle-deg A    cable angle [deg] (sweep default 0)\n"
         "  --sweep                frequencies vs cable length\n"
         "  --cable-lengths LIST   sweep lengths: a,b,c or start:step:stop [m]\n"
         "                         (default 0.254:0.00381:0.635, the paper's range)\n"
         "  --modes K              number of modes, 1..%d (default 3)\n"
         "  --elements N           FE elements (default %d; the paper used %d)\n"
         "  --fe-hold tip|tension  FE static state: tip = hold the ODE tip, i.e. the exact\n"
         "                         cable length and angle, solving for T and theta0 (default);\n"
         "                         tension = hold the ODE tension and theta0 (the tip moves by\n"
         "                         tip_shift_m)\n"
         "  --payload-factor G     payload m_p = G (m_h + rho L) (eq. 17)\n"
         "  --payload-kg M         payload mass [kg]\n"
         "  --arm FILE             arm parameters (default: see elasticarm --help)\n"
         "  --csv FILE             sweep table as CSV ('-' = stdout)\n"
         "  --json                 JSON on stdout\n"
         "  --figure OUT           static shape and mode shapes; sweep: Fig. 5 with mode\n"
         "                         shapes (.svg, .png or .pdf)\n\n"
         "exit: 0 ok, 1 no static solution / FE not converged (or a sweep point failed),\n"
         "      2 usage or input error\n",
         EA_FE_MAX_MODES, EA_FE_DEFAULT_ELEMENTS, EA_FE_PAPER_ELEMENTS);
}

typedef struct {
  const char *arm_file, *figure, *csv;
  ea__cli_payload_t payload;
  int json, sweep, hold;
  long modes, elements;
  double Lc, adeg;
  double *Ls;
  int nL;
} ea__freq_opts_t;

static int ea__freq_single(const char *cmd, const ea__freq_opts_t *o, const ea_arm_t *arm,
                           ea_shooter_t *sh, ea_fe_model_t *m) {
  ea_freq_point_t pt;
  ea_freq_point(sh, m, o->Lc, o->adeg * EA__DEG, NULL, &pt);
  const int ok = pt.status == EA_OK;
  const int nm = ok ? pt.modes.modes : 0;
  if (o->json) {
    ea_json_t j;
    ea_json_init(&j, stdout, 1);
    ea_json_obj_begin(&j, NULL);
    ea_json_str(&j, "status", ea_status_name(pt.status));
    ea_json_str(&j, "message", ok ? "ok" : pt.err.msg);
    if (!ok) ea_json_str(&j, "failed_stage", pt.stage);
    ea_json_num(&j, "cable_length_m", o->Lc);
    ea_json_num(&j, "cable_angle_rad", o->adeg * EA__DEG);
    ea_json_num(&j, "tip_mass_kg", ea_shooter_load(sh)->tip_mass);
    ea_json_int(&j, "elements", o->elements);
    ea_json_str(&j, "fe_hold", o->hold == EA__FE_HOLD_TIP ? "tip" : "tension");
    ea_json_vec(&j, "frequencies_Hz", pt.modes.freq_hz, nm);
    ea_json_vec(&j, "eigenvalues_rad2_per_s2", pt.modes.lambda, nm);
    if (ok)
      ea_json_bool(&j, "stable", pt.modes.stable);
    else
      ea_json_null(&j, "stable");
    ea_json_int(&j, "fe_iterations", pt.fe.iterations);
    ea_json_num(&j, "fe_residual", pt.fe.residual);
    ea_json_num(&j, "tension_N", pt.fe.tension);
    ea_json_num(&j, "theta0_rad", pt.fe.theta0);
    ea_json_num(&j, "fe_cable_length_m", ok ? pt.fe.cable_length : NAN);
    ea_json_num(&j, "fe_cable_angle_rad", ok ? pt.fe.cable_angle : NAN);
    ea_json_vec(&j, "fe_tip_m", pt.fe.tip, ok ? 2 : 0);
    ea_json_num(&j, "tip_shift_m", ok ? pt.fe.tip_shift : NAN);
    ea_json_num(&j, "ode_tension_N", pt.ode.status == EA_OK ? pt.ode.p[EA_P_TENSION] : NAN);
    ea_json_num(&j, "ode_theta0_rad", pt.ode.status == EA_OK ? pt.ode.p[EA_P_THETA0] : NAN);
    ea_json_num(&j, "ode_residual", pt.ode.residual);
    ea_json_num(&j, "time_fe_static_s", pt.fe.time_s);
    ea_json_num(&j, "time_eigen_s", pt.modes.time_assembly_s + pt.modes.time_eigen_s);
    ea_json_obj_end(&j);
    ea_json_end(&j);
  } else if (ok) {
    printf("cable length %.4f m, cable angle %.2f deg, tip mass %.4g kg, %ld elements (FE "
           "holds the %s)\n",
           o->Lc, o->adeg, ea_shooter_load(sh)->tip_mass, o->elements,
           o->hold == EA__FE_HOLD_TIP ? "tip" : "ODE tension");
    printf("ODE statics   T = %.6f N, theta0 = %.6f deg (residual %.1e)\n", pt.ode.p[EA_P_TENSION],
           pt.ode.p[EA_P_THETA0] / EA__DEG, pt.ode.residual);
    printf("FE statics    T = %.6f N, theta0 = %.6f deg, eps = %.2e in %d iterations, "
           "tip shift %.3e m\n",
           pt.fe.tension, pt.fe.theta0 / EA__DEG, pt.fe.residual, pt.fe.iterations,
           pt.fe.tip_shift);
    printf("stability     %s\n", pt.modes.stable ? "stable (passive stiffness positive definite)"
                                                 : "UNSTABLE (passive stiffness indefinite)");
    printf("%6s %14s %18s\n", "mode", "frequency [Hz]", "omega^2 [rad2/s2]");
    for (int k = 0; k < nm; ++k)
      printf("%6d %14.6f %18.6g\n", k + 1, pt.modes.freq_hz[k], pt.modes.lambda[k]);
  }
  if (!ok) { /* no static solution (outside the workspace) or FE failure: exit 1 */
    fprintf(stderr, "elasticarm %s: error: %s failed: %s\n", cmd, pt.stage,
            pt.err.msg[0] ? pt.err.msg : ea_strerror(pt.status));
    return EA_EXIT_FAIL;
  }
  if (o->figure) {
    ea_plot_t *pl;
    ea_error_t fe = {0};
    if (ea_plot_open(&pl, o->figure, 800, 700, &fe) == EA_OK) {
      const int nplot = nm < 4 ? nm : 4;
      const double scale = 0.06;
      ea__fe_plot_cable_block(pl, arm, pt.fe.tip[0], pt.fe.tip[1]);
      ea__fe_plot_modes(pl, m, nplot, scale);
      ea_plot_cmd(pl, "set size ratio -1\nset xlabel 'x [m]'\nset ylabel 'y [m]'\n"
                      "set key outside bottom center horizontal\nset grid");
      ea_plot_cmd(
          pl,
          "set title \"FE static shape and mode shapes (tip amplitude %.0f mm)\\nL_c = %.3f m, "
          "{/Symbol a} = %.1f deg, T = %.2f N, %s\"",
          scale * 1e3, o->Lc, o->adeg, pt.fe.tension, pt.modes.stable ? "stable" : "UNSTABLE");
      ea__fe_plot_modes_cmd(pl, nplot, pt.modes.freq_hz);
      fe.status = ea_plot_close(pl, &fe);
    }
    if (fe.status) {
      fprintf(stderr, "elasticarm %s: figure: %s\n", cmd, fe.msg);
      return EA_EXIT_FAIL;
    }
  }
  return EA_EXIT_OK;
}

/* A computed sweep and its summary: relative changes between the shortest and the
 * longest converged cable. */
typedef struct {
  ea_freq_point_t *pts;
  int n, nm, nfail, nunstable;
  int ks, kl; /* shortest and longest converged lengths (-1: none) */
  double shorten[EA_FE_MAX_MODES], lengthen[EA_FE_MAX_MODES];
  double wall; /* [s] */
} ea__sweep_t;

static void ea__sweep_summarise(const ea__freq_opts_t *o, ea__sweep_t *w) {
  w->ks = w->kl = -1;
  w->nfail = w->nunstable = 0;
  for (int k = 0; k < w->n; ++k) {
    const ea_freq_point_t *p = &w->pts[k];
    w->nfail += p->status != EA_OK;
    if (p->status != EA_OK) continue;
    w->nunstable += !p->modes.stable;
    if (w->ks < 0 || o->Ls[k] < o->Ls[w->ks]) w->ks = k;
    if (w->kl < 0 || o->Ls[k] > o->Ls[w->kl]) w->kl = k;
  }
  for (int i = 0; i < w->nm; ++i) {
    w->shorten[i] = w->lengthen[i] = NAN;
    if (w->ks >= 0 && w->kl >= 0 && w->ks != w->kl) {
      const double fs = w->pts[w->ks].modes.freq_hz[i], fl = w->pts[w->kl].modes.freq_hz[i];
      w->shorten[i] = (fs - fl) / fl;
      w->lengthen[i] = (fl - fs) / fs;
    }
  }
}

static int ea__sweep_csv(const char *cmd, const char *path, const ea__sweep_t *w) {
  ea_afile_t f;
  ea_error_t err = {0};
  if (ea_afile_open(&f, path, &err)) return ea__cli_fail(cmd, err.status, &err);
  fprintf(f.fp, "cable_length_m");
  for (int i = 0; i < w->nm; ++i)
    fprintf(f.fp, ",f%d_Hz", i + 1);
  fprintf(f.fp, ",stable,tension_N,theta0_rad,fe_iterations,fe_residual,status\n");
  for (int k = 0; k < w->n; ++k) {
    const ea_freq_point_t *p = &w->pts[k];
    const int ok = p->status == EA_OK;
    fprintf(f.fp, "%.9g", p->cable_length);
    for (int i = 0; i < w->nm; ++i)
      fprintf(f.fp, ",%.12g", ok ? p->modes.freq_hz[i] : NAN);
    fprintf(f.fp, ",%d,%.12g,%.12g,%d,%.3g,%s\n", ok ? p->modes.stable : 0, p->fe.tension,
            p->fe.theta0, p->fe.iterations, p->fe.residual, ea_status_name(p->status));
  }
  if (ea_afile_commit(&f, &err)) return ea__cli_fail(cmd, err.status, &err);
  return 0;
}

static void ea__sweep_json(const ea__freq_opts_t *o, double tip_mass, const ea__sweep_t *w) {
  ea_json_t j;
  ea_json_init(&j, stdout, 1);
  ea_json_obj_begin(&j, NULL);
  ea_json_str(&j, "status", w->nfail ? "EA_ERR_NOCONV" : "EA_OK");
  ea_json_num(&j, "cable_angle_rad", o->adeg * EA__DEG);
  ea_json_num(&j, "tip_mass_kg", tip_mass);
  ea_json_int(&j, "elements", o->elements);
  ea_json_str(&j, "fe_hold", o->hold == EA__FE_HOLD_TIP ? "tip" : "tension");
  ea_json_int(&j, "points", w->n);
  ea_json_int(&j, "failed_points", w->nfail);
  ea_json_int(&j, "unstable_points", w->nunstable);
  ea_json_num(&j, "time_s", w->wall);
  ea_json_vec(&j, "relative_change_shortening", w->shorten, w->nm);
  ea_json_vec(&j, "relative_change_lengthening", w->lengthen, w->nm);
  ea_json_arr_begin(&j, "sweep");
  for (int k = 0; k < w->n; ++k) {
    const ea_freq_point_t *p = &w->pts[k];
    const int ok = p->status == EA_OK;
    ea_json_obj_begin(&j, NULL);
    ea_json_num(&j, "cable_length_m", p->cable_length);
    ea_json_vec(&j, "frequencies_Hz", p->modes.freq_hz, ok ? p->modes.modes : 0);
    if (ok)
      ea_json_bool(&j, "stable", p->modes.stable);
    else
      ea_json_null(&j, "stable");
    ea_json_num(&j, "tension_N", p->fe.tension);
    ea_json_num(&j, "theta0_rad", p->fe.theta0);
    ea_json_int(&j, "fe_iterations", p->fe.iterations);
    ea_json_num(&j, "fe_residual", p->fe.residual);
    ea_json_num(&j, "tip_shift_m", ok ? p->fe.tip_shift : NAN);
    ea_json_str(&j, "status", ea_status_name(p->status));
    if (!ok) ea_json_str(&j, "message", p->err.msg);
    ea_json_obj_end(&j);
  }
  ea_json_arr_end(&j);
  ea_json_obj_end(&j);
  ea_json_end(&j);
}

static void ea__sweep_text(const ea__freq_opts_t *o, double tip_mass, const ea__sweep_t *w) {
  static const double paper[3] = {0.55, 0.38, 0.12};
  const int n = w->n, nm = w->nm;
  printf("Fig. 5 sweep: %d cable lengths %.4f..%.4f m, alpha = %.2f deg, tip mass %.4g kg, "
         "%ld elements\n",
         n, o->Ls[0], o->Ls[n - 1], o->adeg, tip_mass, o->elements);
  printf("%10s", "L_c [m]");
  for (int i = 0; i < nm; ++i)
    printf("   f%-2d [Hz]", i + 1);
  printf(" %7s %10s %10s\n", "stable", "T [N]", "th0 [deg]");
  const int every = n > 25 ? (n + 19) / 20 : 1;
  for (int k = 0; k < n; ++k) {
    if (k % every && k != n - 1 && w->pts[k].status == EA_OK) continue;
    const ea_freq_point_t *p = &w->pts[k];
    printf("%10.5f", p->cable_length);
    if (p->status) {
      printf("  %s: %s\n", p->stage, p->err.msg);
      continue;
    }
    for (int i = 0; i < nm; ++i)
      printf(" %10.5f", p->modes.freq_hz[i]);
    printf(" %7s %10.4f %10.4f\n", p->modes.stable ? "yes" : "NO", p->fe.tension,
           p->fe.theta0 / EA__DEG);
  }
  if (n > 25) printf("(every %d-th length shown; --csv for all)\n", every);
  if (w->ks >= 0 && w->kl >= 0 && w->ks != w->kl) {
    printf("relative change between L_c = %.4f m and %.4f m:\n", o->Ls[w->ks], o->Ls[w->kl]);
    for (int i = 0; i < nm; ++i) {
      printf("  mode %d: %.4f -> %.4f Hz: %+6.1f %% as the cable shortens, %+6.1f %% as it "
             "lengthens",
             i + 1, w->pts[w->kl].modes.freq_hz[i], w->pts[w->ks].modes.freq_hz[i],
             100 * w->shorten[i], 100 * w->lengthen[i]);
      if (i < 3)
        printf("   (paper: %s %.0f %%)", i == 0 ? "shortening" : "lengthening", 100 * paper[i]);
      printf("\n");
    }
  }
  printf("%d points, %d failed, %d unstable, %.1f ms (%.2f ms per point)\n", n, w->nfail,
         w->nunstable, 1e3 * w->wall, 1e3 * w->wall / n);
}

/* Fig. 5: frequencies against cable length, and typical mode shapes at the converged
 * point nearest the middle of the sweep (recomputed there, so m holds its modes). */
static int ea__sweep_figure(const char *cmd, const ea__freq_opts_t *o, const ea_arm_t *arm,
                            ea_shooter_t *sh, ea_fe_model_t *m, const ea__sweep_t *w) {
  const int n = w->n, nm = w->nm;
  const double alpha = o->adeg * EA__DEG;
  ea_plot_t *pl;
  ea_error_t fe = {0};
  if (ea_plot_open(&pl, o->figure, 1300, 600, &fe) == EA_OK) {
    ea_plot_data_begin(pl, "freq");
    for (int k = 0; k < n; ++k) {
      double row[1 + EA_FE_MAX_MODES];
      row[0] = w->pts[k].cable_length * 100.0;
      for (int i = 0; i < nm; ++i)
        row[1 + i] = w->pts[k].status == EA_OK ? w->pts[k].modes.freq_hz[i] : NAN;
      ea_plot_data_row(pl, 1 + nm, row);
    }
    ea_plot_data_end(pl);
    int kmid = n / 2, nshape = 0;
    ea_freq_point_t mid;
    mid.status = EA_ERR_ARG;
    for (int d = 0; d <= n / 2 && mid.status; ++d)
      for (int sgn = -1; sgn <= 1 && mid.status; sgn += 2) {
        const int k = n / 2 + sgn * d;
        if (k < 0 || k >= n || w->pts[k].status) continue;
        kmid = k;
        ea_freq_point(sh, m, o->Ls[k], alpha, w->pts[k].ode.p, &mid);
      }
    if (mid.status == EA_OK) {
      ea__fe_plot_cable_block(pl, arm, mid.fe.tip[0], mid.fe.tip[1]);
      nshape = ea__fe_plot_modes(pl, m, nm < 3 ? nm : 3, 0.06);
    }
    ea_plot_cmd(pl,
                "set multiplot layout 1,2 title 'Natural frequencies vs cable length, "
                "{/Symbol a} = %.1f deg (paper Fig. 5), %ld elements'",
                o->adeg, o->elements);
    ea_plot_cmd(pl,
                "set xlabel 'cable length L_c [cm]'\nset ylabel 'frequency [Hz]'\n"
                "set grid\nset key top center\nset logscale y\nset title 'first %d modes'",
                nm);
    char plot[2048];
    int used = snprintf(plot, sizeof plot, "plot");
    for (int i = 0; i < nm && used < (int)sizeof plot - 200; ++i)
      used += snprintf(plot + used, sizeof plot - (size_t)used,
                       "%s $freq u 1:%d w lp lw 2 pt 7 ps 0.4 lc rgb '%s' t 'mode %d'",
                       i ? "," : "", i + 2, ea__fe_colors[i % 8], i + 1);
    ea_plot_cmd(pl, "%s", plot);
    ea_plot_cmd(pl, "unset logscale y\nset size ratio -1\nset xlabel 'x [m]'\n"
                    "set ylabel 'y [m]'\nset key outside bottom center horizontal");
    if (nshape > 0) {
      ea_plot_cmd(pl, "set title 'typical mode shapes (60 mm), L_c = %.1f cm'", 100 * o->Ls[kmid]);
      ea__fe_plot_modes_cmd(pl, nshape, mid.modes.freq_hz);
    } else {
      ea_plot_cmd(pl, "set title 'no converged configuration'\nplot NaN notitle");
    }
    ea_plot_cmd(pl, "unset multiplot");
    fe.status = ea_plot_close(pl, &fe);
  }
  if (fe.status) {
    fprintf(stderr, "elasticarm %s: figure: %s\n", cmd, fe.msg);
    return EA_EXIT_FAIL;
  }
  return 0;
}

/* The sweep: compute (ea_freq_sweep), then the outputs asked for, then the first
 * failed point, if any, on stderr (exit 1). */
static int ea__freq_sweep(const char *cmd, const ea__freq_opts_t *o, const ea_arm_t *arm,
                          ea_shooter_t *sh, ea_fe_model_t *m) {
  ea__sweep_t w = {.n = o->nL, .nm = (int)o->modes};
  if (!(w.pts = calloc((size_t)w.n, sizeof *w.pts))) {
    fprintf(stderr, "elasticarm %s: error: out of memory (%d sweep points)\n", cmd, w.n);
    return EA_EXIT_FAIL;
  }
  const double t0 = ea__mono_s();
  ea_freq_sweep(sh, m, o->Ls, w.n, o->adeg * EA__DEG, w.pts);
  w.wall = ea__mono_s() - t0;
  ea__sweep_summarise(o, &w);
  const double tip_mass = ea_shooter_load(sh)->tip_mass;
  int rc = o->csv ? ea__sweep_csv(cmd, o->csv, &w) : 0;
  if (o->json)
    ea__sweep_json(o, tip_mass, &w);
  else if (!(o->csv && !strcmp(o->csv, "-")))
    ea__sweep_text(o, tip_mass, &w);
  if (o->figure && !rc) rc = ea__sweep_figure(cmd, o, arm, sh, m, &w);
  if (w.nfail && !rc) {
    for (int k = 0; k < w.n; ++k)
      if (w.pts[k].status) {
        fprintf(stderr, "elasticarm %s: L_c = %.5f m: %s failed: %s\n", cmd, w.pts[k].cable_length,
                w.pts[k].stage, w.pts[k].err.msg);
        break;
      }
    fprintf(stderr, "elasticarm %s: %d of %d sweep points failed\n", cmd, w.nfail, w.n);
    rc = EA_EXIT_FAIL;
  }
  free(w.pts);
  return rc;
}

int ea__cli_frequencies(int argc, char **argv) {
  const char *cmd = "frequencies";
  if (ea__fe_help_requested(argc, argv)) {
    ea__freq_help();
    return EA_EXIT_OK;
  }
  ea__freq_opts_t o = {0};
  o.Lc = o.adeg = NAN;
  o.modes = 3;
  o.elements = EA_FE_DEFAULT_ELEMENTS;
  o.hold = EA__FE_HOLD_TIP;
  int rc = EA_EXIT_USAGE;
  static const ea__cli_opt_t opts[] = {{"help", 0, 'h'},
                                       {"json", 0, 0},
                                       {"sweep", 0, 0},
                                       {"cable-length", 1, 0},
                                       {"cable-angle-deg", 1, 0},
                                       {"cable-lengths", 1, 0},
                                       {"modes", 1, 0},
                                       {"elements", 1, 0},
                                       {"fe-hold", 1, 0},
                                       {"payload-factor", 1, 0},
                                       {"payload-kg", 1, 0},
                                       {"arm", 1, 0},
                                       {"figure", 1, 0},
                                       {"csv", 1, 0},
                                       {NULL, 0, 0}};
  ea__cli_args_t g;
  ea__cli_args_init(&g, cmd, argc, argv, opts);
  int r;
  while ((r = ea__cli_args_next(&g)) > 0) {
    const char *a = g.opt, *v = g.arg;
    int bad = 0;
    if (!a) {
      ea__cli_usage_error(cmd, "unexpected argument '%s'", v);
      goto done;
    }
    if (!strcmp(a, "--json")) {
      o.json = 1;
      continue;
    }
    if (!strcmp(a, "--sweep")) {
      o.sweep = 1;
      continue;
    }
    if (!strcmp(a, "--cable-length"))
      bad = ea__cli_double(cmd, a, v, 1e-6, 100.0, &o.Lc);
    else if (!strcmp(a, "--cable-angle-deg"))
      bad = ea__cli_double(cmd, a, v, -180.0, 180.0, &o.adeg);
    else if (!strcmp(a, "--cable-lengths")) {
      free(o.Ls);
      bad = ea__cli_list(cmd, a, v, &o.Ls, &o.nL);
      for (int k = 0; !bad && k < o.nL; ++k)
        if (!(o.Ls[k] > 0 && o.Ls[k] <= 100))
          bad = ea__cli_usage_error(cmd, "%s: %g is not in (0, 100] m", a, o.Ls[k]);
      if (!bad && o.nL > 100000) bad = ea__cli_usage_error(cmd, "%s: too many lengths", a);
    } else if (!strcmp(a, "--modes"))
      bad = ea__cli_int(cmd, a, v, 1, EA_FE_MAX_MODES, &o.modes);
    else if (!strcmp(a, "--elements"))
      bad = ea__cli_int(cmd, a, v, 1, 512, &o.elements);
    else if (!strcmp(a, "--fe-hold")) {
      if (!strcmp(v, "tip"))
        o.hold = EA__FE_HOLD_TIP;
      else if (!strcmp(v, "tension"))
        o.hold = EA__FE_HOLD_TENSION;
      else
        bad = ea__cli_usage_error(cmd, "--fe-hold: '%s' is not 'tip' or 'tension'", v);
    } else if (!strcmp(a, "--payload-factor") || !strcmp(a, "--payload-kg")) {
      if (o.payload.given)
        bad = ea__cli_usage_error(cmd, "give --payload-factor or --payload-kg once");
      else {
        o.payload.given = !strcmp(a, "--payload-factor") ? 1 : 2;
        bad = ea__cli_double(cmd, a, v, 0.0, 1e3, &o.payload.value);
      }
    } else if (!strcmp(a, "--arm"))
      o.arm_file = v;
    else if (!strcmp(a, "--figure"))
      o.figure = v;
    else if (!strcmp(a, "--csv"))
      o.csv = v;
    if (bad) {
      rc = bad;
      goto done;
    }
  }
  if (r < 0) goto done;
  if (o.sweep) {
    if (isfinite(o.Lc)) {
      ea__cli_usage_error(cmd, "--sweep takes --cable-lengths, not --cable-length");
      goto done;
    }
    if (!isfinite(o.adeg)) o.adeg = 0.0;
    if (!o.Ls && (rc = ea__cli_list(cmd, "--cable-lengths", "0.254:0.00381:0.635", &o.Ls, &o.nL)))
      goto done;
    rc = EA_EXIT_USAGE;
  } else {
    if (o.Ls || o.csv) {
      ea__cli_usage_error(cmd, "%s needs --sweep", o.Ls ? "--cable-lengths" : "--csv");
      goto done;
    }
    if (!isfinite(o.Lc) || !isfinite(o.adeg)) {
      ea__cli_usage_error(cmd, "give --cable-length and --cable-angle-deg (or --sweep)");
      goto done;
    }
  }
  if (o.json && o.csv && !strcmp(o.csv, "-")) {
    ea__cli_usage_error(cmd, "--json and --csv - both want stdout");
    goto done;
  }
  if (o.figure && ea__cli_check_figure(cmd, o.figure)) goto done;
  ea_arm_t arm;
  if ((rc = ea__cli_load_arm(cmd, o.arm_file, &arm))) goto done;
  ea_shooter_t *sh = NULL;
  ea_fe_model_t *m = NULL;
  if ((rc = ea__fe_make(cmd, &arm, ea__cli_tip_mass(&arm, &o.payload), o.elements, o.modes, o.hold,
                        &sh, &m)))
    goto done;
  rc = o.sweep ? ea__freq_sweep(cmd, &o, &arm, sh, m) : ea__freq_single(cmd, &o, &arm, sh, m);
  ea_fe_model_free(m);
  ea_shooter_free(sh);
done:
  free(o.Ls);
  return rc;
}

/* ------------------------------------------------------------------------ */
/* simulate                                                                  */
/* ------------------------------------------------------------------------ */

static void ea__sim_help(void) {
  printf("usage: elasticarm simulate TRAJ [options]\n\n"
         "FE transient (docs/fe.md) of a trajectory: the statics at the start, the FE static\n"
         "equilibrium, then the nonlinear dynamics driven by the shoulder angle theta0(t) and\n"
         "the cable (passive: moving rest length L0(t) = L_c(t) / (1 + T(t) / EA_c); active:\n"
         "tension T(t)), following the cubic Hermite of the file's values and rates, to the\n"
         "end of the motion plus a settling time. Reports the tip history, the tracking error\n"
         "against the plan's (quasi-static) tip during the motion, the residual vibration\n"
         "after it and the time to rest (the tip within --tolerance of its final equilibrium\n"
         "from then on).\n\n"
         "TRAJ: a trajectory file (docs/trajectory-format.md, written by 'elasticarm plan'),\n"
         "or a simple CSV with the header 't_s,cable_length_m,cable_angle_rad' (one row per\n"
         "sample; T, theta0 and kappa0 come from the statics, warm-started along the rows).\n\n"
         "  --elements N              FE elements (default %d)\n"
         "  --dt S                    time step [s] (default 1e-3)\n"
         "  --settle S                simulated time after the motion [s] (default 3)\n"
         "  --tolerance M             time to rest: |tip - final equilibrium| <= M [m] from then\n"
         "                            on (default 1e-3)\n"
         "  --damping-ratio Z         damping ratio Z at the first mode at the start, by strain-\n"
         "                            rate (Kelvin-Voigt) damping of the beam: zero for rigid\n"
         "                            motion; higher modes get more (reported)\n"
         "  --rayleigh A,B            mass damping A M v [1/s] plus strain-rate damping B [s]:\n"
         "                            sectional forces += B (EA, GA, EI) x strain rates; default\n"
         "                            none. A also brakes rigid rotations of the arm\n"
         "  --scheme genalpha|energy  time integrator (default genalpha: generalized-alpha,\n"
         "                            Chung-Hulbert; energy: energy-conserving midpoint). Both\n"
         "                            give the residual within 1e-4 of the dt -> 0 limit at the\n"
         "                            default dt (bench/bench_sim); genalpha is 2-10x more\n"
         "                            accurate at coarse steps and ~15 %% faster\n"
         "  --rho-inf R               genalpha spectral radius at infinite frequency, [0, 1]\n"
         "                            (default 0.9; 1 = no numerical dissipation)\n"
         "  --cable passive|active    cable phase during the motion (default passive)\n"
         "  --drive plan|fe           theta0(t) and T(t): the trajectory's columns (default), or\n"
         "                            re-solved by FE statics holding the planned tip at every\n"
         "                            sample (removes the ODE-vs-FE static offset)\n"
         "  --payload-factor G | --payload-kg M   payload (default: the trajectory's payload);\n"
         "                            the tip mass is the arm's hand mass plus the payload\n"
         "  --arm FILE                arm parameters (default: the arm file the trajectory\n"
         "                            records, else the default arm file); a plan run on another\n"
         "                            arm (heavier hand, stiffer beam) is the what-if: the arm\n"
         "                            starts from its own equilibrium under the plan's inputs\n"
         "  -o FILE                   tip history CSV: t_s, tip_x_m, tip_y_m, tip_theta_rad,\n"
         "                            planned_tip_x_m, planned_tip_y_m ('-' = stdout)\n"
         "  --json                    JSON summary on stdout\n"
         "  --quiet                   no progress lines on stderr (a transient that runs\n"
         "                            longer than a second says how far it is)\n"
         "  --figure OUT              planned vs simulated tip path, deviation from the planned\n"
         "                            tip and approach to rest over time\n\n"
         "exit: 0 ok, 1 start outside the workspace / FE not converged,\n"
         "      2 usage or input error (missing or malformed trajectory)\n",
         EA_FE_DEFAULT_ELEMENTS);
}

typedef struct {
  const char *traj_path, *arm_file, *out, *figure;
  ea__cli_payload_t payload;
  int json, quiet, active, drive_fe, damping; /* damping: 0 none, 1 ratio, 2 rayleigh */
  ea_fe_scheme_t scheme;
  long elements;
  double dt, settle, zeta, rayleigh[2], rho_inf, tolerance;
  int rho_given;
} ea__sim_opts_t;

static int ea__sim_parse(const char *cmd, int argc, char **argv, ea__sim_opts_t *o) {
  memset(o, 0, sizeof *o);
  o->elements = EA_FE_DEFAULT_ELEMENTS;
  o->dt = 1e-3;
  o->settle = 3.0;
  o->scheme = EA_FE_SCHEME_GENALPHA;
  o->rho_inf = 0.9;
  o->tolerance = 1e-3;
  static const ea__cli_opt_t opts[] = {{"help", 0, 'h'},
                                       {"json", 0, 0},
                                       {"elements", 1, 0},
                                       {"dt", 1, 0},
                                       {"settle", 1, 0},
                                       {"tolerance", 1, 0},
                                       {"damping-ratio", 1, 0},
                                       {"rayleigh", 1, 0},
                                       {"scheme", 1, 0},
                                       {"rho-inf", 1, 0},
                                       {"cable", 1, 0},
                                       {"drive", 1, 0},
                                       {"payload-factor", 1, 0},
                                       {"payload-kg", 1, 0},
                                       {"arm", 1, 0},
                                       {"output", 1, 'o'},
                                       {"figure", 1, 0},
                                       {"quiet", 0, 0},
                                       {NULL, 0, 0}};
  ea__cli_args_t g;
  ea__cli_args_init(&g, cmd, argc, argv, opts);
  int r;
  while ((r = ea__cli_args_next(&g)) > 0) {
    const char *a = g.opt, *v = g.arg;
    int bad = 0;
    if (a && !strcmp(a, "--quiet")) {
      o->quiet = 1;
      continue;
    }
    if (!a) {
      if (o->traj_path)
        return ea__cli_usage_error(cmd, "more than one trajectory ('%s', '%s')", o->traj_path, v);
      o->traj_path = v;
      continue;
    }
    if (!strcmp(a, "--json")) {
      o->json = 1;
      continue;
    }
    if (!strcmp(a, "--elements"))
      bad = ea__cli_int(cmd, a, v, 1, 512, &o->elements);
    else if (!strcmp(a, "--dt"))
      bad = ea__cli_double(cmd, a, v, 1e-6, 0.1, &o->dt);
    else if (!strcmp(a, "--settle"))
      bad = ea__cli_double(cmd, a, v, 0.0, 1e4, &o->settle);
    else if (!strcmp(a, "--tolerance"))
      bad = ea__cli_double(cmd, a, v, 1e-9, 1.0, &o->tolerance);
    else if (!strcmp(a, "--damping-ratio")) {
      if (o->damping)
        bad = ea__cli_usage_error(cmd, "give --damping-ratio or --rayleigh once");
      else {
        o->damping = 1;
        bad = ea__cli_double(cmd, a, v, 0.0, 1.0, &o->zeta);
      }
    } else if (!strcmp(a, "--rayleigh")) {
      if (o->damping)
        bad = ea__cli_usage_error(cmd, "give --damping-ratio or --rayleigh once");
      else {
        o->damping = 2;
        bad = ea__cli_pair(cmd, a, v, o->rayleigh);
        if (!bad && (o->rayleigh[0] < 0 || o->rayleigh[1] < 0))
          bad = ea__cli_usage_error(cmd, "--rayleigh: '%s': A and B must be >= 0", v);
      }
    } else if (!strcmp(a, "--scheme")) {
      if (!strcmp(v, "energy"))
        o->scheme = EA_FE_SCHEME_ENERGY;
      else if (!strcmp(v, "genalpha"))
        o->scheme = EA_FE_SCHEME_GENALPHA;
      else
        bad = ea__cli_usage_error(cmd, "--scheme: '%s' is not 'energy' or 'genalpha'", v);
    } else if (!strcmp(a, "--rho-inf")) {
      o->rho_given = 1;
      bad = ea__cli_double(cmd, a, v, 0.0, 1.0, &o->rho_inf);
    } else if (!strcmp(a, "--cable")) {
      if (!strcmp(v, "passive") || !strcmp(v, "active"))
        o->active = !strcmp(v, "active");
      else
        bad = ea__cli_usage_error(cmd, "--cable: '%s' is not 'passive' or 'active'", v);
    } else if (!strcmp(a, "--drive")) {
      if (!strcmp(v, "plan") || !strcmp(v, "fe"))
        o->drive_fe = !strcmp(v, "fe");
      else
        bad = ea__cli_usage_error(cmd, "--drive: '%s' is not 'plan' or 'fe'", v);
    } else if (!strcmp(a, "--payload-factor") || !strcmp(a, "--payload-kg")) {
      if (o->payload.given)
        bad = ea__cli_usage_error(cmd, "give --payload-factor or --payload-kg once");
      else {
        o->payload.given = !strcmp(a, "--payload-factor") ? 1 : 2;
        bad = ea__cli_double(cmd, a, v, 0.0, 1e3, &o->payload.value);
      }
    } else if (!strcmp(a, "--arm"))
      o->arm_file = v;
    else if (!strcmp(a, "-o") || !strcmp(a, "--output"))
      o->out = v;
    else if (!strcmp(a, "--figure"))
      o->figure = v;
    if (bad) return bad;
  }
  if (r < 0) return EA_EXIT_USAGE;
  if (!o->traj_path) return ea__cli_usage_error(cmd, "give a trajectory file");
  if (o->rho_given && o->scheme != EA_FE_SCHEME_GENALPHA)
    return ea__cli_usage_error(cmd, "--rho-inf needs --scheme genalpha");
  if (o->json && o->out && !strcmp(o->out, "-"))
    return ea__cli_usage_error(cmd, "--json and -o - both want stdout");
  if (o->figure && ea__cli_check_figure(cmd, o->figure)) return EA_EXIT_USAGE;
  if (o->out && strcmp(o->out, "-") && ea__cli_check_output(cmd, o->out)) return EA_EXIT_USAGE;
  return 0;
}

/* [rad] the base angle's range over the trajectory (0: a planar motion). */
static double ea__base_travel(const ea_traj_t *tr) {
  double lo = INFINITY, hi = -INFINITY;
  for (int k = 0; k < tr->n; ++k) {
    lo = fmin(lo, EA_TRAJ_AT(tr, k, EA_TRAJ_base_angle));
    hi = fmax(hi, EA_TRAJ_AT(tr, k, EA_TRAJ_base_angle));
  }
  return hi >= lo ? hi - lo : 0.0;
}

static void ea__sim_json(const ea__sim_opts_t *o, const ea_sim_settings_t *s, int simple, int n,
                         double base_travel, const char *arm_path, const ea_sim_info_t *si) {
  ea_json_t j;
  ea_json_init(&j, stdout, 1);
  ea_json_obj_begin(&j, NULL);
  ea_json_str(&j, "status", ea_status_name(si->status));
  ea_json_str(&j, "trajectory", o->traj_path);
  ea_json_str(&j, "trajectory_format", simple ? "simple-csv" : "trajectory-v1");
  ea_json_str(&j, "arm_file", arm_path);
  ea_json_int(&j, "samples", n);
  ea_json_num(&j, "tip_mass_kg", si->tip_mass);
  ea_json_str(&j, "transient",
              "planar: in the arm's plane; the base rotation's loads are not in it");
  ea_json_num(&j, "base_travel_rad", base_travel);
  ea_json_int(&j, "elements", s->elements);
  ea_json_num(&j, "dt_s", s->dt);
  ea_json_str(&j, "scheme", s->scheme == EA_FE_SCHEME_ENERGY ? "energy" : "genalpha");
  if (s->scheme == EA_FE_SCHEME_GENALPHA) ea_json_num(&j, "rho_inf", s->rho_inf);
  ea_json_str(&j, "cable", s->cable_active ? "active" : "passive");
  ea_json_str(&j, "drive", s->drive_fe ? "fe" : "plan");
  ea_json_num(&j, "rayleigh_mass_per_s", si->rayleigh_mass);
  ea_json_num(&j, "rayleigh_stiffness_s", si->rayleigh_stiffness); /* strain-rate b */
  if (si->damping_ratio > 0) {
    ea_json_num(&j, "damping_ratio", si->damping_ratio);
    ea_json_vec(&j, "start_frequencies_Hz", si->start_freq_hz, 2);
    ea_json_vec(&j, "modal_damping_ratios", si->modal_damping,
                si->n_modal_damping < 3 ? si->n_modal_damping : 3);
  }
  ea_json_num(&j, "motion_duration_s", si->duration);
  ea_json_num(&j, "settle_s", s->settle);
  ea_json_num(&j, "simulated_time_s", si->simulated_time);
  ea_json_int(&j, "steps", si->steps);
  ea_json_int(&j, "newton_iterations", si->newton_iterations);
  ea_json_int(&j, "max_step_iterations", si->max_step_iterations);
  ea_json_int(&j, "start_newton_iterations", si->start_newton_iterations);
  ea_json_num(&j, "start_tension_N", si->start_tension);
  ea_json_num(&j, "wall_time_s", si->wall_time_s);
  ea_json_num(&j, "realtime_factor",
              si->wall_time_s > 0 ? si->simulated_time / si->wall_time_s : NAN);
  ea_json_num(&j, "residual_vibration_rms_m", si->residual_rms);
  ea_json_num(&j, "residual_vibration_peak_m", si->residual_peak);
  ea_json_num(&j, "rest_tolerance_m", s->rest_tolerance);
  ea_json_num(&j, "time_to_rest_s", si->time_to_rest);
  ea_json_num(&j, "max_tracking_error_m", si->max_tracking_error);
  ea_json_num(&j, "max_tracking_error_time_s", si->max_tracking_error_time);
  ea_json_num(&j, "static_offset_start_m", si->static_offset_start);
  ea_json_num(&j, "static_offset_end_m", si->static_offset_end);
  ea_json_vec(&j, "final_static_tip_m", si->final_static_tip, s->settle > 0 ? 2 : 0);
  ea_json_num(&j, "energy_start_J", si->energy_start);
  ea_json_num(&j, "energy_end_J", si->energy_end);
  ea_json_num(&j, "energy_drift_J", si->energy_drift_max);
  ea_json_num(&j, "kinetic_max_J", si->kinetic_max);
  ea_json_num(&j, "fe_tension_min_N", si->tension_min);
  ea_json_num(&j, "fe_tension_min_time_s", si->tension_min_time);
  ea_json_num(&j, "fe_tension_max_N", si->tension_max);
  ea_json_num(&j, "fe_tension_max_time_s", si->tension_max_time);
  ea_json_obj_end(&j);
  ea_json_end(&j);
}

static void ea__sim_text(const ea__sim_opts_t *o, const ea_sim_settings_t *s, int simple, int n,
                         double base_travel, const char *arm_path, const char *arm_which,
                         const ea_sim_info_t *si) {
  printf("trajectory   %s (%s, %d samples, %.4g s), tip mass %.4g kg\n", o->traj_path,
         simple ? "simple CSV" : "format 1", n, si->duration, si->tip_mass);
  printf("arm          %s (%s)\n", arm_path, arm_which);
  char scheme[64];
  if (s->scheme == EA_FE_SCHEME_ENERGY)
    snprintf(scheme, sizeof scheme, "energy");
  else
    snprintf(scheme, sizeof scheme, "genalpha (rho_inf %.3g)", s->rho_inf);
  printf("FE           %d elements, dt %.3g s, %s scheme, %s cable, drive from the %s\n",
         s->elements, s->dt, scheme, s->cable_active ? "active" : "passive",
         s->drive_fe ? "FE statics" : "trajectory");
  if (base_travel > 0)
    printf("planar       the transient is in the arm's plane: the base turns %.4g deg in this "
           "trajectory and the rotation's loads (out-of-plane bending from its angular "
           "acceleration, centrifugal and Coriolis forces) are not in the results below\n",
           base_travel / EA__DEG);
  if (si->rayleigh_mass > 0 || si->rayleigh_stiffness > 0)
    printf("damping      mass a = %.4g 1/s, strain-rate b = %.4g s%s\n", si->rayleigh_mass,
           si->rayleigh_stiffness, si->damping_ratio > 0 ? " (ratio at mode 1)" : "");
  if (si->n_modal_damping > 0)
    printf("             modal damping ratios at the start: %.4f %.4f %.4f\n", si->modal_damping[0],
           si->n_modal_damping > 1 ? si->modal_damping[1] : NAN,
           si->n_modal_damping > 2 ? si->modal_damping[2] : NAN);
  printf("simulated    %.4g s in %d steps, %d Newton iterations (max %d per step), wall "
         "%.3f s (%.1fx real time)\n",
         si->simulated_time, si->steps, si->newton_iterations, si->max_step_iterations,
         si->wall_time_s, si->wall_time_s > 0 ? si->simulated_time / si->wall_time_s : NAN);
  printf("tracking     max |tip - planned tip| during the motion %.4f mm (t = %.4g s); "
         "static offset at start %.4f mm\n",
         1e3 * si->max_tracking_error, si->max_tracking_error_time, 1e3 * si->static_offset_start);
  if (s->settle > 0) {
    printf("residual     vibration after the motion: rms %.4f mm, peak %.4f mm (about the "
           "final equilibrium, %.4f mm from the planned end)\n",
           1e3 * si->residual_rms, 1e3 * si->residual_peak, 1e3 * si->static_offset_end);
    if (isfinite(si->time_to_rest)) /* t may fall before the motion's end: say so */
      printf("rest         within %.3g mm of the final equilibrium from t = %.4g s on (%.4g s "
             "%s the motion ends)\n",
             1e3 * s->rest_tolerance, si->time_to_rest, fabs(si->time_to_rest - si->duration),
             si->time_to_rest < si->duration ? "before" : "after");
    else
      printf("rest         not within %.3g mm of the final equilibrium by the end (t = %.4g "
             "s): simulate longer (--settle) or add damping\n",
             1e3 * s->rest_tolerance, si->simulated_time);
  }
  printf("tension      FE cable tension %.4f N (t = %.4g s) to %.4f N (t = %.4g s)%s\n",
         si->tension_min, si->tension_min_time, si->tension_max, si->tension_max_time,
         si->tension_min > 0 ? "" : ": the cable went slack");
  printf("energy       start %.6g J, end %.6g J, max |E - E0| %.3g J (drives do work)\n",
         si->energy_start, si->energy_end, si->energy_drift_max);
}

static int ea__sim_figure(const char *cmd, const ea__sim_opts_t *o, const ea_sim_settings_t *s,
                          const ea_sim_info_t *si, const ea_sim_history_t *h) {
  ea_error_t fe = {0};
  if (ea_sim_figure(h, si, s, o->figure, &fe)) { /* sim_figure.c */
    fprintf(stderr, "elasticarm %s: figure: %s\n", cmd, fe.msg);
    return EA_EXIT_FAIL;
  }
  return 0;
}

static void ea__sim_settings(const ea__sim_opts_t *o, ea_sim_settings_t *s) {
  ea_sim_settings_default(s);
  s->elements = (int)o->elements;
  s->dt = o->dt;
  s->settle = o->settle;
  s->scheme = o->scheme;
  s->rho_inf = o->rho_inf;
  s->cable_active = o->active;
  s->drive_fe = o->drive_fe;
  s->rest_tolerance = o->tolerance;
  s->keep_history = o->out || o->figure;
  if (o->damping == 1) s->damping_ratio = o->zeta;
  if (o->damping == 2) {
    s->rayleigh_mass = o->rayleigh[0];
    s->rayleigh_stiffness = o->rayleigh[1];
  }
}

/* A simple CSV has only (t, L_c, alpha): its statics columns from the statics of
 * this arm and tip mass (<= 0: the hand's). Returns 0 or the exit code. */
static int ea__sim_fill_simple(const char *cmd, const ea_arm_t *arm, double tip_mass,
                               ea_traj_t *tr) {
  ea_error_t err = {0};
  ea_shooter_t *sh = NULL;
  const ea_load_t load = {tip_mass > 0 ? tip_mass : arm->m_hand};
  ea_status_t st = ea_shooter_alloc(arm, NULL, &sh, &err);
  if (!st) {
    ea_shooter_set_load(sh, &load);
    st = ea_traj_fill_statics(tr, sh, &err);
  }
  ea_shooter_free(sh);
  return st ? ea__cli_fail(cmd, st == EA_ERR_NOMEM ? st : EA_ERR_INADMISSIBLE, &err) : 0;
}

/* Another arm or tip mass than the plan's: say that its start differs. */
static void ea__sim_note_mismatch(const char *cmd, const ea_traj_t *tr, const ea_sim_info_t *si) {
  if (si->start_tension_mismatch > 1e-4 * fmax(1.0, EA_TRAJ_AT(tr, 0, EA_TRAJ_tension)) ||
      si->start_theta0_mismatch > 1e-4)
    fprintf(stderr,
            "elasticarm %s: note: this arm and tip mass (%.4g kg) are not the plan's: at the "
            "start its statics differ from the trajectory's by %.3g N in T and %.3g rad in "
            "theta0; the drive is the trajectory's, the arm settles where its own equilibrium "
            "is\n",
            cmd, si->tip_mass, si->start_tension_mismatch, si->start_theta0_mismatch);
}

/* The tip history as CSV, atomically ("-" = stdout). Returns 0 or the exit code. */
static int ea__sim_write_history(const char *cmd, const char *path, const ea_sim_history_t *h) {
  ea_afile_t af = {0};
  ea_error_t err = {0};
  if (ea_afile_open(&af, path, &err)) return ea__cli_fail(cmd, err.status, &err);
  fprintf(af.fp, "t_s,tip_x_m,tip_y_m,tip_theta_rad,planned_tip_x_m,planned_tip_y_m\n");
  for (int r = 0; r < h->rows; ++r) {
    const double *v = h->data + 6 * r;
    fprintf(af.fp, "%.9g,%.12g,%.12g,%.12g,%.12g,%.12g\n", v[0], v[1], v[2], v[3], v[4], v[5]);
  }
  if (ea_afile_commit(&af, &err)) return ea__cli_fail(cmd, err.status, &err);
  return 0;
}

/* simulate: read (a trajectory file or a simple CSV), the arm, the statics of a simple
 * CSV, the library's simulation (ea_traj_simulate), then the outputs asked for. */
int ea__cli_simulate(int argc, char **argv) {
  const char *cmd = "simulate";
  if (ea__fe_help_requested(argc, argv)) {
    ea__sim_help();
    return EA_EXIT_OK;
  }
  ea__sim_opts_t o;
  int rc = ea__sim_parse(cmd, argc, argv, &o);
  if (rc) return rc;
  ea_traj_t tr = {0};
  ea_error_t err = {0};
  int simple = 0;
  if ((rc = ea__cli_check_plan_pair(cmd, o.traj_path))) return rc;
  ea_status_t st = ea_traj_read_any(&tr, o.traj_path, &simple, &err);
  if (st) {
    ea_traj_free(&tr);
    return ea__cli_fail(cmd, st, &err) == EA_EXIT_FAIL ? EA_EXIT_FAIL : EA_EXIT_USAGE;
  }
  ea_arm_t arm;
  const char *arm_which = "";
  ea_sim_history_t h = {0};
  /* --arm, else the arm file the trajectory records (checked against its arm hash), else
   * the default */
  char arm_used[sizeof tr.arm_file];
  if ((rc = ea__cli_arm_for_traj(cmd, o.traj_path, o.arm_file, &tr, EA__ARM_QUIET, &arm, arm_used,
                                 sizeof arm_used)))
    goto done;
  arm_which = o.arm_file ? "--arm" : tr.arm_file[0] ? "recorded in the trajectory" : "default";
  const char *arm_path = arm_used[0] ? arm_used : ea__cli_default_arm();
  ea_sim_settings_t s;
  ea__sim_settings(&o, &s);
  ea__cli_progress_t prog;
  ea__cli_progress_init(&prog, cmd, !o.quiet);
  s.progress = ea__cli_progress_fe;
  s.progress_data = &prog;
  /* the tip mass: the arm's hand plus the trajectory's payload, or the flags' payload */
  const double tip_mass = o.payload.given ? ea__cli_tip_mass(&arm, &o.payload) : 0.0;
  if (simple && (rc = ea__sim_fill_simple(cmd, &arm, tip_mass, &tr))) goto done;
  ea_sim_info_t si;
  st = ea_traj_simulate(&arm, &tr, tip_mass, &s, &h, &si, &err);
  ea__cli_progress_end(&prog);
  if (st) {
    fprintf(stderr, "elasticarm %s: error: %s: %s\n", cmd, o.traj_path,
            err.msg[0] ? err.msg : ea_strerror(st));
    rc = (st == EA_ERR_ARG || st == EA_ERR_INPUT) ? EA_EXIT_USAGE : EA_EXIT_FAIL;
    goto done;
  }
  if (!simple) ea__sim_note_mismatch(cmd, &tr, &si);
  if (o.out && (rc = ea__sim_write_history(cmd, o.out, &h))) goto done;
  if (o.json)
    ea__sim_json(&o, &s, simple, tr.n, ea__base_travel(&tr), arm_path, &si);
  else if (!o.out || strcmp(o.out, "-"))
    ea__sim_text(&o, &s, simple, tr.n, ea__base_travel(&tr), arm_path, arm_which, &si);
  if (o.figure) rc = ea__sim_figure(cmd, &o, &s, &si, &h);
done:
  ea_sim_history_free(&h);
  ea_traj_free(&tr);
  return rc;
}
