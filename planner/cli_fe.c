/* CLI: frequencies (paper sec. 3.3, Fig. 5) and simulate (FE transient of a
 * trajectory). The FE model itself lives in model/fe_*.c (docs/fe.md); this
 * file only wires statics -> FE and writes tables, JSON, CSV and figures. */
#include "cli_impl.h"
#include "sim_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* ------------------------------------------------------------------------ */
/* Shared pieces                                                             */
/* ------------------------------------------------------------------------ */

static int ea__fe_help_requested(int argc, char **argv) {
  for (int i = 1; i < argc; ++i)
    if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) return 1;
  return 0;
}

static double ea__fe_wall(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Figure path must end in .svg, .png or .pdf: checked before any work. */
static int ea__fe_check_figure(const char *cmd, const char *path) {
  if (!path) return 0;
  const char *ext = strrchr(path, '.');
  if (!ext || (strcmp(ext, ".svg") && strcmp(ext, ".png") && strcmp(ext, ".pdf")))
    return ea__cli_usage_error(cmd, "--figure: '%s' must end in .svg, .png or .pdf", path);
  return 0;
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

/* One configuration: ODE statics (warm-started if guess), FE static solve,
 * natural frequencies. */
typedef struct {
  double cable_length, alpha; /**< requested [m], [rad] */
  ea_statics_solution_t ode;
  ea_fe_static_info_t fe;
  ea_fe_modes_info_t modes;
  ea_status_t status;
  ea_error_t err;
  const char *stage; /**< where it failed: "statics", "fe-static", "modes" */
} ea__fe_point_t;

static ea_status_t ea__fe_point(ea_fe_model_t *m, ea_shooter_t *sh, double Lc, double alpha,
                                const double *guess, ea__fe_point_t *pt) {
  memset(pt, 0, sizeof *pt);
  pt->cable_length = Lc;
  pt->alpha = alpha;
  pt->fe.residual = pt->fe.tension = pt->fe.theta0 = NAN;
  for (int k = 0; k < EA_FE_MAX_MODES; ++k)
    pt->modes.freq_hz[k] = NAN;
  ea_statics_problem_t pr = ea_statics_problem_cable(Lc, alpha);
  pt->stage = "statics";
  pt->status = ea_statics_solve(sh, &pr, NULL, guess, &pt->ode, &pt->err);
  if (pt->status) return pt->status;
  pt->stage = "fe-static";
  pt->status = ea_fe_static_solve(m, sh, &pt->ode, &pt->fe, &pt->err);
  if (pt->status) return pt->status;
  pt->stage = "modes";
  pt->status = ea_fe_modes(m, &pt->modes, &pt->err);
  if (pt->status) return pt->status;
  pt->stage = "";
  return EA_OK;
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
         "  --arm FILE             arm parameters (default data/elasticarm.yaml)\n"
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
  ea__fe_point_t pt;
  ea__fe_point(m, sh, o->Lc, o->adeg * EA__DEG, NULL, &pt);
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
          "set title 'FE static shape and mode shapes (tip amplitude %.0f mm), L_c = %.3f m, "
          "{/Symbol a} = %.1f deg, T = %.2f N, %s'",
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

static int ea__freq_sweep(const char *cmd, const ea__freq_opts_t *o, const ea_arm_t *arm,
                          ea_shooter_t *sh, ea_fe_model_t *m) {
  const int n = o->nL, nm = (int)o->modes;
  ea__fe_point_t *pts = calloc((size_t)n, sizeof *pts);
  if (!pts) return ea__cli_usage_error(cmd, "out of memory");
  const double alpha = o->adeg * EA__DEG;
  double guess[EA_NP];
  int have = 0, nfail = 0, nunstable = 0;
  const double t0 = ea__fe_wall();
  for (int k = 0; k < n; ++k) {
    ea__fe_point(m, sh, o->Ls[k], alpha, have ? guess : NULL, &pts[k]);
    if (pts[k].status && have) /* warm start failed: retry from the T = 0 edge */
      ea__fe_point(m, sh, o->Ls[k], alpha, NULL, &pts[k]);
    if (pts[k].ode.status == EA_OK) {
      memcpy(guess, pts[k].ode.p, sizeof guess);
      have = 1;
    }
    nfail += pts[k].status != EA_OK;
    nunstable += pts[k].status == EA_OK && !pts[k].modes.stable;
  }
  const double wall = ea__fe_wall() - t0;
  /* relative changes between the shortest and the longest cable */
  int ks = -1, kl = -1;
  for (int k = 0; k < n; ++k)
    if (pts[k].status == EA_OK) {
      if (ks < 0 || o->Ls[k] < o->Ls[ks]) ks = k;
      if (kl < 0 || o->Ls[k] > o->Ls[kl]) kl = k;
    }
  double shorten[EA_FE_MAX_MODES], lengthen[EA_FE_MAX_MODES];
  for (int i = 0; i < nm; ++i) {
    shorten[i] = lengthen[i] = NAN;
    if (ks >= 0 && kl >= 0 && ks != kl) {
      const double fs = pts[ks].modes.freq_hz[i], fl = pts[kl].modes.freq_hz[i];
      shorten[i] = (fs - fl) / fl;
      lengthen[i] = (fl - fs) / fs;
    }
  }
  static const double paper[3] = {0.55, 0.38, 0.12};
  int rc = EA_EXIT_OK;
  if (o->csv) {
    ea_afile_t f;
    ea_error_t err = {0};
    if (ea_afile_open(&f, o->csv, &err)) {
      rc = ea__cli_fail(cmd, err.status, &err);
    } else {
      fprintf(f.fp, "cable_length_m");
      for (int i = 0; i < nm; ++i)
        fprintf(f.fp, ",f%d_Hz", i + 1);
      fprintf(f.fp, ",stable,tension_N,theta0_rad,fe_iterations,fe_residual,status\n");
      for (int k = 0; k < n; ++k) {
        const ea__fe_point_t *p = &pts[k];
        const int ok = p->status == EA_OK;
        fprintf(f.fp, "%.9g", p->cable_length);
        for (int i = 0; i < nm; ++i)
          fprintf(f.fp, ",%.12g", ok ? p->modes.freq_hz[i] : NAN);
        fprintf(f.fp, ",%d,%.12g,%.12g,%d,%.3g,%s\n", ok ? p->modes.stable : 0, p->fe.tension,
                p->fe.theta0, p->fe.iterations, p->fe.residual, ea_status_name(p->status));
      }
      if (ea_afile_commit(&f, &err)) rc = ea__cli_fail(cmd, err.status, &err);
    }
  }
  const int csv_stdout = o->csv && !strcmp(o->csv, "-");
  if (o->json) {
    ea_json_t j;
    ea_json_init(&j, stdout, 1);
    ea_json_obj_begin(&j, NULL);
    ea_json_str(&j, "status", nfail ? "EA_ERR_NOCONV" : "EA_OK");
    ea_json_num(&j, "cable_angle_rad", alpha);
    ea_json_num(&j, "tip_mass_kg", ea_shooter_load(sh)->tip_mass);
    ea_json_int(&j, "elements", o->elements);
    ea_json_str(&j, "fe_hold", o->hold == EA__FE_HOLD_TIP ? "tip" : "tension");
    ea_json_int(&j, "points", n);
    ea_json_int(&j, "failed_points", nfail);
    ea_json_int(&j, "unstable_points", nunstable);
    ea_json_num(&j, "time_s", wall);
    ea_json_vec(&j, "relative_change_shortening", shorten, nm);
    ea_json_vec(&j, "relative_change_lengthening", lengthen, nm);
    ea_json_arr_begin(&j, "sweep");
    for (int k = 0; k < n; ++k) {
      const ea__fe_point_t *p = &pts[k];
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
  } else if (!csv_stdout) {
    printf("Fig. 5 sweep: %d cable lengths %.4f..%.4f m, alpha = %.2f deg, tip mass %.4g kg, "
           "%ld elements\n",
           n, o->Ls[0], o->Ls[n - 1], o->adeg, ea_shooter_load(sh)->tip_mass, o->elements);
    printf("%10s", "L_c [m]");
    for (int i = 0; i < nm; ++i)
      printf("   f%-2d [Hz]", i + 1);
    printf(" %7s %10s %10s\n", "stable", "T [N]", "th0 [deg]");
    const int every = n > 25 ? (n + 19) / 20 : 1;
    for (int k = 0; k < n; ++k) {
      if (k % every && k != n - 1 && pts[k].status == EA_OK) continue;
      const ea__fe_point_t *p = &pts[k];
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
    if (ks >= 0 && kl >= 0 && ks != kl) {
      printf("relative change between L_c = %.4f m and %.4f m:\n", o->Ls[ks], o->Ls[kl]);
      for (int i = 0; i < nm; ++i) {
        printf("  mode %d: %.4f -> %.4f Hz: %+6.1f %% as the cable shortens, %+6.1f %% as it "
               "lengthens",
               i + 1, pts[kl].modes.freq_hz[i], pts[ks].modes.freq_hz[i], 100 * shorten[i],
               100 * lengthen[i]);
        if (i < 3)
          printf("   (paper: %s %.0f %%)", i == 0 ? "shortening" : "lengthening", 100 * paper[i]);
        printf("\n");
      }
    }
    printf("%d points, %d failed, %d unstable, %.1f ms (%.2f ms per point)\n", n, nfail, nunstable,
           1e3 * wall, 1e3 * wall / n);
  }
  if (o->figure && !rc) {
    ea_plot_t *pl;
    ea_error_t fe = {0};
    if (ea_plot_open(&pl, o->figure, 1300, 600, &fe) == EA_OK) {
      ea_plot_data_begin(pl, "freq");
      for (int k = 0; k < n; ++k) {
        double row[1 + EA_FE_MAX_MODES];
        row[0] = pts[k].cable_length * 100.0;
        for (int i = 0; i < nm; ++i)
          row[1 + i] = pts[k].status == EA_OK ? pts[k].modes.freq_hz[i] : NAN;
        ea_plot_data_row(pl, 1 + nm, row);
      }
      ea_plot_data_end(pl);
      /* typical mode shapes: at the middle of the sweep */
      int kmid = n / 2, nshape = 0;
      ea__fe_point_t mid;
      mid.status = EA_ERR_ARG;
      for (int d = 0; d <= n / 2 && mid.status; ++d)
        for (int sgn = -1; sgn <= 1 && mid.status; sgn += 2) {
          const int k = n / 2 + sgn * d;
          if (k < 0 || k >= n || pts[k].status) continue;
          kmid = k;
          ea__fe_point(m, sh, o->Ls[k], alpha, pts[k].ode.p, &mid);
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
        ea_plot_cmd(pl, "set title 'typical mode shapes (60 mm), L_c = %.1f cm'",
                    100 * o->Ls[kmid]);
        ea__fe_plot_modes_cmd(pl, nshape, mid.modes.freq_hz);
      } else {
        ea_plot_cmd(pl, "set title 'no converged configuration'\nplot NaN notitle");
      }
      ea_plot_cmd(pl, "unset multiplot");
      fe.status = ea_plot_close(pl, &fe);
    }
    if (fe.status) {
      fprintf(stderr, "elasticarm %s: figure: %s\n", cmd, fe.msg);
      rc = EA_EXIT_FAIL;
    }
  }
  if (nfail && !rc) {
    for (int k = 0; k < n; ++k)
      if (pts[k].status) {
        fprintf(stderr, "elasticarm %s: L_c = %.5f m: %s failed: %s\n", cmd, pts[k].cable_length,
                pts[k].stage, pts[k].err.msg);
        break;
      }
    fprintf(stderr, "elasticarm %s: %d of %d sweep points failed\n", cmd, nfail, n);
    rc = EA_EXIT_FAIL;
  }
  free(pts);
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
  for (int i = 1; i < argc; ++i) {
    const char *a = argv[i], *v;
    int bad = 0;
    if (!strcmp(a, "--json")) {
      o.json = 1;
      continue;
    }
    if (!strcmp(a, "--sweep")) {
      o.sweep = 1;
      continue;
    }
    if (!(v = ea__cli_value(cmd, argc, argv, &i))) goto done;
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
    else {
      bad = ea__cli_usage_error(cmd, "unknown option '%s'", a);
    }
    if (bad) goto done;
  }
  if (o.sweep) {
    if (isfinite(o.Lc)) {
      ea__cli_usage_error(cmd, "--sweep takes --cable-lengths, not --cable-length");
      goto done;
    }
    if (!isfinite(o.adeg)) o.adeg = 0.0;
    if (!o.Ls && ea__cli_list(cmd, "--cable-lengths", "0.254:0.00381:0.635", &o.Ls, &o.nL))
      goto done;
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
  if (ea__fe_check_figure(cmd, o.figure)) goto done;
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
  printf(
      "usage: elasticarm simulate TRAJ [options]\n\n"
      "FE transient (docs/fe.md) of a trajectory: the statics at the start, the FE static\n"
      "equilibrium, then the nonlinear dynamics driven by the shoulder angle theta0(t) and\n"
      "the cable (passive: moving rest length L0(t) = L_c(t) / (1 + T(t) / EA_c); active:\n"
      "tension T(t)), to the end of the motion plus a settling time. Reports the tip\n"
      "history, the tracking error against the plan's (quasi-static) tip during the motion\n"
      "and the residual vibration after it.\n\n"
      "TRAJ: a trajectory file (docs/trajectory-format.md, written by 'elasticarm plan'),\n"
      "or a simple CSV with the header 't_s,cable_length_m,cable_angle_rad' (one row per\n"
      "sample; T, theta0 and kappa0 come from the statics, warm-started along the rows).\n\n"
      "  --elements N              FE elements (default %d)\n"
      "  --dt S                    time step [s] (default 1e-3)\n"
      "  --settle S                simulated time after the motion [s] (default 1)\n"
      "  --damping-ratio Z         damping ratio Z at the first mode at the start, by strain-\n"
      "                            rate (Kelvin-Voigt) damping of the beam: zero for rigid\n"
      "                            motion; higher modes get more (reported)\n"
      "  --rayleigh A,B            mass damping A M v [1/s] plus strain-rate damping B [s]:\n"
      "                            sectional forces += B (EA, GA, EI) x strain rates; default\n"
      "                            none. A also brakes rigid rotations of the arm\n"
      "  --scheme energy|genalpha  time integrator (default energy: energy-conserving midpoint;\n"
      "                            genalpha: generalized-alpha, Chung-Hulbert)\n"
      "  --rho-inf R               genalpha spectral radius at infinite frequency, [0, 1]\n"
      "                            (default 0.9; 1 = no numerical dissipation)\n"
      "  --cable passive|active    cable phase during the motion (default passive)\n"
      "  --drive plan|fe           theta0(t) and T(t): the trajectory's columns (default), or\n"
      "                            re-solved by FE statics holding the planned tip at every\n"
      "                            sample (removes the ODE-vs-FE static offset)\n"
      "  --payload-factor G | --payload-kg M   tip load (default: the trajectory's tip mass)\n"
      "  --arm FILE                arm parameters (default data/elasticarm.yaml)\n"
      "  -o FILE                   tip history CSV: t_s, tip_x_m, tip_y_m, tip_theta_rad,\n"
      "                            planned_tip_x_m, planned_tip_y_m ('-' = stdout)\n"
      "  --json                    JSON summary on stdout\n"
      "  --figure OUT              planned vs simulated tip path, tip error vs time\n\n"
      "exit: 0 ok, 1 start outside the workspace / FE not converged,\n"
      "      2 usage or input error (missing or malformed trajectory)\n",
      EA_FE_DEFAULT_ELEMENTS);
}

/* Read the simple CSV form; rows of (t, L_c, alpha) into tr (other columns 0). */
static ea_status_t ea__sim_read_simple(const char *path, ea_traj_t *tr, ea_error_t *err) {
  memset(tr, 0, sizeof *tr);
  FILE *fp = fopen(path, "r");
  if (!fp) return ea_error_set(err, EA_ERR_IO, "%s: cannot open", path);
  char line[4096];
  long lineno = 0;
  int cap = 0, n = 0;
  double *rows = NULL;
  ea_status_t st = EA_OK;
  while (fgets(line, sizeof line, fp)) {
    ++lineno;
    line[strcspn(line, "\r\n")] = '\0';
    if (lineno == 1) {
      if (strcmp(line, "t_s,cable_length_m,cable_angle_rad")) {
        st = ea_error_set(err, EA_ERR_PARSE,
                          "%s:1:1: header must be 't_s,cable_length_m,cable_angle_rad' (or a "
                          "trajectory file starting with '# elasticarm-trajectory 1')",
                          path);
        break;
      }
      continue;
    }
    if (!line[0]) continue;
    double v[3];
    const char *s = line;
    for (int c = 0; c < 3; ++c) {
      char *end;
      v[c] = strtod(s, &end);
      const int sep_ok = c < 2 ? *end == ',' : *end == '\0';
      if (end == s || !isfinite(v[c]) || !sep_ok) {
        st = ea_error_set(err, EA_ERR_PARSE, "%s:%ld:%ld: expected a finite number%s", path, lineno,
                          (long)(s - line) + 1, c < 2 ? " followed by ','" : " at the end");
        break;
      }
      s = end + 1;
    }
    if (st) break;
    if (n && !(v[0] > rows[3 * (n - 1)])) {
      st = ea_error_set(err, EA_ERR_INPUT, "%s:%ld:1: time %g does not increase", path, lineno,
                        v[0]);
      break;
    }
    if (!(v[1] > 0)) {
      st = ea_error_set(err, EA_ERR_INPUT, "%s:%ld: cable length %g <= 0", path, lineno, v[1]);
      break;
    }
    if (n == cap) {
      cap = cap ? 2 * cap : 64;
      double *r = realloc(rows, sizeof(double) * 3 * (size_t)cap);
      if (!r) {
        st = ea_error_set(err, EA_ERR_NOMEM, "out of memory");
        break;
      }
      rows = r;
    }
    memcpy(rows + 3 * n++, v, sizeof v);
  }
  fclose(fp);
  if (!st && n < 2)
    st = ea_error_set(err, EA_ERR_INPUT, "%s: needs at least 2 samples, has %d", path, n);
  if (!st && (st = ea_traj_alloc(tr, n))) ea_error_set(err, st, "out of memory");
  if (!st) {
    for (int i = 0; i < n; ++i) {
      EA_TRAJ_AT(tr, i, EA_TRAJ_t) = rows[3 * i];
      EA_TRAJ_AT(tr, i, EA_TRAJ_cable_length) = rows[3 * i + 1];
      EA_TRAJ_AT(tr, i, EA_TRAJ_cable_angle) = rows[3 * i + 2];
    }
    for (int i = 0; i < n; ++i) { /* rates by centred (end: one-sided) differences */
      const int a = i ? i - 1 : 0, b = i < n - 1 ? i + 1 : n - 1;
      const double dt = rows[3 * b] - rows[3 * a];
      EA_TRAJ_AT(tr, i, EA_TRAJ_cable_length_rate) = (rows[3 * b + 1] - rows[3 * a + 1]) / dt;
      EA_TRAJ_AT(tr, i, EA_TRAJ_cable_angle_rate) = (rows[3 * b + 2] - rows[3 * a + 2]) / dt;
    }
    snprintf(tr->status, sizeof tr->status, "simple-csv");
  }
  free(rows);
  return st;
}

/* Is the file the simple CSV form (first line is not a '#' comment)? */
static int ea__sim_is_simple(const char *path) {
  FILE *fp = fopen(path, "r");
  if (!fp) return 0;
  const int c = fgetc(fp);
  fclose(fp);
  return c != '#' && c != EOF;
}

/* Planned (quasi-static) tip at trajectory time t: cubic Hermite of L_c and
 * alpha with their rates, tip = root + L_c (cos alpha, sin alpha). */
static void ea__sim_plan_tip(const ea_traj_t *tr, const ea_arm_t *arm, double t, double xy[2]) {
  const int n = tr->n;
  double L, a;
  if (t <= EA_TRAJ_AT(tr, 0, EA_TRAJ_t) || n == 1) {
    L = EA_TRAJ_AT(tr, 0, EA_TRAJ_cable_length);
    a = EA_TRAJ_AT(tr, 0, EA_TRAJ_cable_angle);
  } else if (t >= EA_TRAJ_AT(tr, n - 1, EA_TRAJ_t)) {
    L = EA_TRAJ_AT(tr, n - 1, EA_TRAJ_cable_length);
    a = EA_TRAJ_AT(tr, n - 1, EA_TRAJ_cable_angle);
  } else {
    int lo = 0, hi = n - 1;
    while (hi - lo > 1) {
      const int mid = (lo + hi) / 2;
      if (EA_TRAJ_AT(tr, mid, EA_TRAJ_t) <= t)
        lo = mid;
      else
        hi = mid;
    }
    const double t0 = EA_TRAJ_AT(tr, lo, EA_TRAJ_t), h = EA_TRAJ_AT(tr, hi, EA_TRAJ_t) - t0;
    const double s = (t - t0) / h, s2 = s * s, s3 = s2 * s;
    const double h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2,
                 h11 = s3 - s2;
    L = h00 * EA_TRAJ_AT(tr, lo, EA_TRAJ_cable_length) +
        h10 * h * EA_TRAJ_AT(tr, lo, EA_TRAJ_cable_length_rate) +
        h01 * EA_TRAJ_AT(tr, hi, EA_TRAJ_cable_length) +
        h11 * h * EA_TRAJ_AT(tr, hi, EA_TRAJ_cable_length_rate);
    a = h00 * EA_TRAJ_AT(tr, lo, EA_TRAJ_cable_angle) +
        h10 * h * EA_TRAJ_AT(tr, lo, EA_TRAJ_cable_angle_rate) +
        h01 * EA_TRAJ_AT(tr, hi, EA_TRAJ_cable_angle) +
        h11 * h * EA_TRAJ_AT(tr, hi, EA_TRAJ_cable_angle_rate);
  }
  xy[0] = arm->x_c + L * cos(a);
  xy[1] = arm->y_c + L * sin(a);
}

typedef struct {
  const char *traj_path, *arm_file, *out, *figure;
  ea__cli_payload_t payload;
  int json, active, drive_fe, damping; /* damping: 0 none, 1 ratio, 2 rayleigh */
  ea_fe_scheme_t scheme;
  long elements;
  double dt, settle, zeta, rayleigh[2], rho_inf;
  int rho_given;
} ea__sim_opts_t;

static int ea__sim_parse(const char *cmd, int argc, char **argv, ea__sim_opts_t *o) {
  memset(o, 0, sizeof *o);
  o->elements = EA_FE_DEFAULT_ELEMENTS;
  o->dt = 1e-3;
  o->settle = 1.0;
  o->scheme = EA_FE_SCHEME_ENERGY;
  o->rho_inf = 0.9;
  for (int i = 1; i < argc; ++i) {
    const char *a = argv[i], *v;
    int bad = 0;
    if (!strcmp(a, "--json")) {
      o->json = 1;
      continue;
    }
    if (a[0] != '-' || !strcmp(a, "-")) {
      if (o->traj_path)
        return ea__cli_usage_error(cmd, "more than one trajectory ('%s', '%s')", o->traj_path, a);
      o->traj_path = a;
      continue;
    }
    if (!(v = ea__cli_value(cmd, argc, argv, &i))) return EA_EXIT_USAGE;
    if (!strcmp(a, "--elements"))
      bad = ea__cli_int(cmd, a, v, 1, 512, &o->elements);
    else if (!strcmp(a, "--dt"))
      bad = ea__cli_double(cmd, a, v, 1e-6, 0.1, &o->dt);
    else if (!strcmp(a, "--settle"))
      bad = ea__cli_double(cmd, a, v, 0.0, 1e4, &o->settle);
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
    else
      bad = ea__cli_usage_error(cmd, "unknown option '%s'", a);
    if (bad) return EA_EXIT_USAGE;
  }
  if (!o->traj_path) return ea__cli_usage_error(cmd, "give a trajectory file");
  if (o->rho_given && o->scheme != EA_FE_SCHEME_GENALPHA)
    return ea__cli_usage_error(cmd, "--rho-inf needs --scheme genalpha");
  if (o->json && o->out && !strcmp(o->out, "-"))
    return ea__cli_usage_error(cmd, "--json and -o - both want stdout");
  return ea__fe_check_figure(cmd, o->figure);
}

/* Statics along the rows of tr (warm-started), filling T, theta0, kappa0,
 * torque and tip; used for the simple CSV form. */
static int ea__sim_fill_statics(const char *cmd, const char *path, ea_traj_t *tr,
                                ea_shooter_t *sh) {
  double guess[EA_NP];
  const ea_arm_t *arm = ea_shooter_arm(sh);
  for (int i = 0; i < tr->n; ++i) {
    const double L = EA_TRAJ_AT(tr, i, EA_TRAJ_cable_length),
                 a = EA_TRAJ_AT(tr, i, EA_TRAJ_cable_angle);
    ea_statics_problem_t pr = ea_statics_problem_cable(L, a);
    ea_statics_solution_t sol;
    ea_error_t err = {0};
    ea_status_t st = ea_statics_solve(sh, &pr, NULL, i ? guess : NULL, &sol, &err);
    if (st && i) st = ea_statics_solve(sh, &pr, NULL, NULL, &sol, &err);
    if (st) {
      fprintf(stderr,
              "elasticarm %s: error: %s: sample %d (t = %g s, L_c = %g m, alpha = %g deg): no "
              "static solution: %s\n",
              cmd, path, i + 1, EA_TRAJ_AT(tr, i, EA_TRAJ_t), L, a / EA__DEG, err.msg);
      return EA_EXIT_FAIL;
    }
    memcpy(guess, sol.p, sizeof guess);
    ea_traj_set_statics(tr, i, sol.p, sol.tip, arm->EI);
  }
  return 0;
}

int ea__cli_simulate(int argc, char **argv) {
  const char *cmd = "simulate";
  if (ea__fe_help_requested(argc, argv)) {
    ea__sim_help();
    return EA_EXIT_OK;
  }
  ea__sim_opts_t o;
  int rc = ea__sim_parse(cmd, argc, argv, &o);
  if (rc) return rc;
  ea_arm_t arm;
  if ((rc = ea__cli_load_arm(cmd, o.arm_file, &arm))) return rc;
  ea_traj_t tr = {0};
  ea_error_t err = {0};
  const int simple = ea__sim_is_simple(o.traj_path);
  ea_status_t st =
      simple ? ea__sim_read_simple(o.traj_path, &tr, &err) : ea_traj_read(&tr, o.traj_path, &err);
  if (st) {
    ea_traj_free(&tr);
    return ea__cli_fail(cmd, st, &err) == EA_EXIT_FAIL ? EA_EXIT_FAIL : EA_EXIT_USAGE;
  }
  if (tr.n < 1) {
    ea_traj_free(&tr);
    return ea__cli_usage_error(cmd, "%s: no samples", o.traj_path);
  }
  const int n = tr.n;
  const double t_first = EA_TRAJ_AT(&tr, 0, EA_TRAJ_t);
  const double duration = EA_TRAJ_AT(&tr, n - 1, EA_TRAJ_t) - t_first;
  const double t_end = duration + o.settle;
  if (!(t_end > 0)) {
    ea_traj_free(&tr);
    return ea__cli_usage_error(cmd, "nothing to simulate: trajectory of one sample and "
                                    "--settle 0");
  }
  if (t_end / o.dt > 2e7) {
    ea_traj_free(&tr);
    return ea__cli_usage_error(cmd, "%.3g s at --dt %g is more than 2e7 steps", t_end, o.dt);
  }
  double tip_mass = tr.tip_mass_kg > 0 ? tr.tip_mass_kg : arm.m_hand;
  if (o.payload.given) tip_mass = ea__cli_tip_mass(&arm, &o.payload);

  ea_shooter_t *sh = NULL;
  ea_fe_model_t *m = NULL, *mh = NULL;
  double *tip = NULL, *qstart = NULL;
  ea__sim_drive_t drv = {0};
  ea_afile_t af = {0};
  const int rows_cap = (int)ceil(t_end / o.dt - 1e-9) + 2;
  if ((rc = ea__fe_make(cmd, &arm, tip_mass, o.elements, 3, EA__FE_HOLD_TENSION, &sh, &m)))
    goto done;
  if (simple && (rc = ea__sim_fill_statics(cmd, o.traj_path, &tr, sh))) goto done;

  /* 1. statics at the start, warm-started from the trajectory's row 0 */
  const double L_0 = EA_TRAJ_AT(&tr, 0, EA_TRAJ_cable_length),
               a_0 = EA_TRAJ_AT(&tr, 0, EA_TRAJ_cable_angle);
  ea_statics_problem_t pr = ea_statics_problem_cable(L_0, a_0);
  ea_statics_solution_t ode;
  const double g0[EA_NP] = {a_0, EA_TRAJ_AT(&tr, 0, EA_TRAJ_tension),
                            EA_TRAJ_AT(&tr, 0, EA_TRAJ_theta0), EA_TRAJ_AT(&tr, 0, EA_TRAJ_kappa0)};
  st = ea_statics_solve(sh, &pr, NULL, g0, &ode, &err);
  if (st) st = ea_statics_solve(sh, &pr, NULL, NULL, &ode, &err);
  if (st) {
    fprintf(stderr,
            "elasticarm %s: error: %s: the start (L_c = %g m, alpha = %g deg) has no static "
            "solution (outside the workspace?): %s\n",
            cmd, o.traj_path, L_0, a_0 / EA__DEG, err.msg);
    rc = EA_EXIT_FAIL;
    goto done;
  }
  const double dT0 = fabs(ode.p[EA_P_TENSION] - g0[1]), dth0 = fabs(ode.p[EA_P_THETA0] - g0[2]);
  if (!simple && (dT0 > 1e-4 * fmax(1.0, fabs(g0[1])) || dth0 > 1e-4))
    fprintf(stderr,
            "elasticarm %s: warning: at the start the statics give T = %.6g N, theta0 = %.6g "
            "rad, the trajectory T = %.6g N, theta0 = %.6g rad (another arm file or payload?)\n",
            cmd, ode.p[EA_P_TENSION], ode.p[EA_P_THETA0], g0[1], g0[2]);

  /* 2. drive samples: theta0(t) and the cable parameter (L0 or T) */
  tip = malloc(sizeof(double) * 4 * (size_t)rows_cap);
  if (!tip || ea__sim_drive_alloc(&drv, n, o.active, &err)) {
    rc = ea__cli_usage_error(cmd, "out of memory");
    goto done;
  }
  if (o.drive_fe) {
    if ((rc = ea__fe_model_make(cmd, &arm, tip_mass, o.elements, 3, EA__FE_HOLD_TIP, &mh)))
      goto done;
  }
  {
    double guess[EA_NP];
    memcpy(guess, ode.p, sizeof guess);
    for (int i = 0; i < n; ++i) {
      const double ti = EA_TRAJ_AT(&tr, i, EA_TRAJ_t) - t_first;
      double T = EA_TRAJ_AT(&tr, i, EA_TRAJ_tension), theta0 = EA_TRAJ_AT(&tr, i, EA_TRAJ_theta0);
      const double L = EA_TRAJ_AT(&tr, i, EA_TRAJ_cable_length);
      if (o.drive_fe) {
        ea__fe_point_t pt;
        ea_statics_problem_t pi =
            ea_statics_problem_cable(L, EA_TRAJ_AT(&tr, i, EA_TRAJ_cable_angle));
        pt.status = ea_statics_solve(sh, &pi, NULL, guess, &pt.ode, &pt.err);
        if (pt.status) pt.status = ea_statics_solve(sh, &pi, NULL, NULL, &pt.ode, &pt.err);
        if (!pt.status) {
          memcpy(guess, pt.ode.p, sizeof guess);
          pt.status = ea_fe_static_solve(mh, sh, &pt.ode, &pt.fe, &pt.err);
        }
        if (pt.status) {
          fprintf(stderr, "elasticarm %s: error: --drive fe: sample %d (t = %g s): %s\n", cmd,
                  i + 1, ti + t_first, pt.err.msg);
          rc = EA_EXIT_FAIL;
          goto done;
        }
        T = pt.fe.tension;
        theta0 = pt.fe.theta0;
        if (i == 0) {
          qstart = malloc(sizeof(double) * 3 * (size_t)ea_fe_model_nodes(mh));
          if (!qstart || ea_fe_get_state(mh, qstart, NULL)) {
            rc = ea__cli_usage_error(cmd, "out of memory");
            goto done;
          }
        }
      }
      if (ea__sim_drive_set(&drv, &arm, i, ti, L, T, theta0, &err)) {
        fprintf(stderr, "elasticarm %s: error: %s: sample %d (t = %g s): %s\n", cmd, o.traj_path,
                i + 1, ti + t_first, err.msg);
        rc = EA_EXIT_FAIL;
        goto done;
      }
    }
    ea__sim_drive_finish(&drv);
  }

  /* 3. FE static equilibrium under the drive values at t = 0 */
  ea_fe_static_info_t fsi;
  const double t_wall0 = ea__fe_wall();
  if ((st = ea_fe_static_solve(m, sh, &ode, &fsi, &err))) {
    fprintf(stderr, "elasticarm %s: error: FE static solve at the start: %s\n", cmd, err.msg);
    rc = EA_EXIT_FAIL;
    goto done;
  }
  {
    st = ea__sim_drive_start(m, &drv, qstart, &fsi, &err);
    if (st) {
      fprintf(stderr, "elasticarm %s: error: FE equilibrium under the start drive: %s\n", cmd,
              err.msg[0] ? err.msg : ea_strerror(st));
      rc = EA_EXIT_FAIL;
      goto done;
    }
  }
  double plan0[2], tip0[3];
  ea__sim_plan_tip(&tr, &arm, t_first, plan0);
  ea_fe_tip(m, tip0);
  const double offset_start = hypot(tip0[0] - plan0[0], tip0[1] - plan0[1]);

  /* 4. damping */
  ea_fe_sim_settings_t ss;
  ea_fe_sim_settings_default(&ss);
  ss.scheme = o.scheme;
  ss.rho_inf = o.rho_inf;
  ss.dt = o.dt;
  ss.t_end = t_end;
  ss.t_motion_end = o.settle > 0 ? duration : -1.0;
  double f12[2] = {NAN, NAN}, zeta_modes[EA_FE_MAX_MODES];
  int nzeta = 0;
  if (o.damping == 2) {
    ss.rayleigh_mass = o.rayleigh[0];
    ss.rayleigh_stiffness = o.rayleigh[1];
  } else if (o.damping == 1 && o.zeta > 0) {
    ea_fe_modes_info_t mi;
    if ((st = ea_fe_modes(m, &mi, &err)) || mi.modes < 1 || !(mi.lambda[0] > 0)) {
      fprintf(stderr,
              "elasticarm %s: error: --damping-ratio needs a stable first mode at the "
              "start: %s\n",
              cmd, st ? err.msg : "not stable");
      rc = EA_EXIT_FAIL;
      goto done;
    }
    /* strain-rate (Kelvin-Voigt) damping only, b from ratio Z at mode 1 of the start
     * state (ea_fe_strain_damping). Not mass-proportional: a M v acts on absolute
     * velocities and so brakes the commanded rigid rotation of the whole arm (a drag
     * that shows up as tracking error), which no physical mechanism of the arm does;
     * the strain rates are zero for rigid motion. The higher modes get the ratios
     * that material damping gives them (rising with frequency), reported. */
    f12[0] = mi.freq_hz[0];
    f12[1] = mi.freq_hz[1];
    if ((st = ea_fe_strain_damping(m, 0, o.zeta, &ss.rayleigh_stiffness, zeta_modes)) != EA_OK) {
      fprintf(stderr, "elasticarm %s: error: --damping-ratio: %s\n", cmd, ea_strerror(st));
      rc = EA_EXIT_FAIL;
      goto done;
    }
    nzeta = mi.modes < 3 ? mi.modes : 3;
    ss.rayleigh_mass = 0.0;
  }

  /* 5. transient */
  ea_fe_sim_info_t si;
  st = ea_fe_simulate(m, &drv.drive, &ss, tip, rows_cap, &si, &err);
  const double wall = ea__fe_wall() - t_wall0;
  if (st) {
    fprintf(stderr, "elasticarm %s: error: %s\n", cmd, err.msg[0] ? err.msg : ea_strerror(st));
    rc = st == EA_ERR_ARG ? EA_EXIT_USAGE : EA_EXIT_FAIL;
    goto done;
  }
  /* 6. tracking error during the motion, final offset */
  double track = 0.0, track_t = 0.0;
  for (int r = 0; r < si.rows; ++r) {
    const double t = tip[4 * r];
    if (t > duration + 1e-9) break;
    double p[2];
    ea__sim_plan_tip(&tr, &arm, t + t_first, p);
    const double e = hypot(tip[4 * r + 1] - p[0], tip[4 * r + 2] - p[1]);
    if (e > track) {
      track = e;
      track_t = t + t_first;
    }
  }
  double plan_end[2];
  ea__sim_plan_tip(&tr, &arm, t_first + duration, plan_end);
  const double offset_end =
      o.settle > 0 ? hypot(si.tip_static[0] - plan_end[0], si.tip_static[1] - plan_end[1]) : NAN;
  if (o.out) {
    if (ea_afile_open(&af, o.out, &err)) {
      rc = ea__cli_fail(cmd, err.status, &err);
      goto done;
    }
    fprintf(af.fp, "t_s,tip_x_m,tip_y_m,tip_theta_rad,planned_tip_x_m,planned_tip_y_m\n");
    for (int r = 0; r < si.rows; ++r) {
      double p[2];
      ea__sim_plan_tip(&tr, &arm, tip[4 * r] + t_first, p);
      fprintf(af.fp, "%.9g,%.12g,%.12g,%.12g,%.12g,%.12g\n", tip[4 * r] + t_first, tip[4 * r + 1],
              tip[4 * r + 2], tip[4 * r + 3], p[0], p[1]);
    }
    if (ea_afile_commit(&af, &err)) {
      rc = ea__cli_fail(cmd, err.status, &err);
      goto done;
    }
  }
  const double sim_time = si.steps * o.dt;
  if (o.json) {
    ea_json_t j;
    ea_json_init(&j, stdout, 1);
    ea_json_obj_begin(&j, NULL);
    ea_json_str(&j, "status", ea_status_name(si.status));
    ea_json_str(&j, "trajectory", o.traj_path);
    ea_json_str(&j, "trajectory_format", simple ? "simple-csv" : "trajectory-v1");
    ea_json_int(&j, "samples", n);
    ea_json_num(&j, "tip_mass_kg", tip_mass);
    ea_json_int(&j, "elements", o.elements);
    ea_json_num(&j, "dt_s", o.dt);
    ea_json_str(&j, "scheme", o.scheme == EA_FE_SCHEME_ENERGY ? "energy" : "genalpha");
    if (o.scheme == EA_FE_SCHEME_GENALPHA) ea_json_num(&j, "rho_inf", o.rho_inf);
    ea_json_str(&j, "cable", o.active ? "active" : "passive");
    ea_json_str(&j, "drive", o.drive_fe ? "fe" : "plan");
    ea_json_num(&j, "rayleigh_mass_per_s", ss.rayleigh_mass);
    ea_json_num(&j, "rayleigh_stiffness_s", ss.rayleigh_stiffness); /* strain-rate b */
    if (o.damping == 1) {
      ea_json_num(&j, "damping_ratio", o.zeta);
      ea_json_vec(&j, "start_frequencies_Hz", f12, 2);
      ea_json_vec(&j, "modal_damping_ratios", zeta_modes, nzeta);
    }
    ea_json_num(&j, "motion_duration_s", duration);
    ea_json_num(&j, "settle_s", o.settle);
    ea_json_num(&j, "simulated_time_s", sim_time);
    ea_json_int(&j, "steps", si.steps);
    ea_json_int(&j, "newton_iterations", si.newton_iterations);
    ea_json_int(&j, "max_step_iterations", si.max_step_iterations);
    ea_json_num(&j, "wall_time_s", wall);
    ea_json_num(&j, "realtime_factor", wall > 0 ? sim_time / wall : NAN);
    ea_json_num(&j, "residual_vibration_rms_m", o.settle > 0 ? si.residual_rms : NAN);
    ea_json_num(&j, "residual_vibration_peak_m", o.settle > 0 ? si.residual_peak : NAN);
    ea_json_num(&j, "max_tracking_error_m", track);
    ea_json_num(&j, "max_tracking_error_time_s", track_t);
    ea_json_num(&j, "static_offset_start_m", offset_start);
    ea_json_num(&j, "static_offset_end_m", offset_end);
    ea_json_vec(&j, "final_static_tip_m", si.tip_static, o.settle > 0 ? 2 : 0);
    ea_json_num(&j, "energy_start_J", si.energy_start);
    ea_json_num(&j, "energy_end_J", si.energy_end);
    ea_json_num(&j, "energy_drift_J", si.energy_drift_max);
    ea_json_num(&j, "kinetic_max_J", si.kinetic_max);
    ea_json_obj_end(&j);
    ea_json_end(&j);
  } else if (!o.out || strcmp(o.out, "-")) {
    printf("trajectory   %s (%s, %d samples, %.4g s), tip mass %.4g kg\n", o.traj_path,
           simple ? "simple CSV" : "format 1", n, duration, tip_mass);
    char scheme[64];
    if (o.scheme == EA_FE_SCHEME_ENERGY)
      snprintf(scheme, sizeof scheme, "energy");
    else
      snprintf(scheme, sizeof scheme, "genalpha (rho_inf %.3g)", o.rho_inf);
    printf("FE           %ld elements, dt %.3g s, %s scheme, %s cable, drive from the %s\n",
           o.elements, o.dt, scheme, o.active ? "active" : "passive",
           o.drive_fe ? "FE statics" : "trajectory");
    if (o.damping)
      printf("damping      mass a = %.4g 1/s, strain-rate b = %.4g s%s\n", ss.rayleigh_mass,
             ss.rayleigh_stiffness, o.damping == 1 ? " (ratio at mode 1)" : "");
    if (nzeta > 0)
      printf("             modal damping ratios at the start: %.4f %.4f %.4f\n", zeta_modes[0],
             nzeta > 1 ? zeta_modes[1] : NAN, nzeta > 2 ? zeta_modes[2] : NAN);
    printf("simulated    %.4g s in %d steps, %d Newton iterations (max %d per step), wall "
           "%.3f s (%.1fx real time)\n",
           sim_time, si.steps, si.newton_iterations, si.max_step_iterations, wall,
           wall > 0 ? sim_time / wall : NAN);
    printf("tracking     max |tip - planned tip| during the motion %.4f mm (t = %.4g s); "
           "static offset at start %.4f mm\n",
           1e3 * track, track_t, 1e3 * offset_start);
    if (o.settle > 0)
      printf("residual     vibration after the motion: rms %.4f mm, peak %.4f mm (about the "
             "final equilibrium, %.4f mm from the planned end)\n",
             1e3 * si.residual_rms, 1e3 * si.residual_peak, 1e3 * offset_end);
    printf("energy       start %.6g J, end %.6g J, max |E - E0| %.3g J (drives do work)\n",
           si.energy_start, si.energy_end, si.energy_drift_max);
  }
  if (o.figure) {
    ea_plot_t *pl;
    ea_error_t fe = {0};
    if (ea_plot_open(&pl, o.figure, 1300, 600, &fe) == EA_OK) {
      ea_plot_data_begin(pl, "sim");
      for (int r = 0; r < si.rows; ++r) {
        double p[2];
        const double t = tip[4 * r] + t_first;
        ea__sim_plan_tip(&tr, &arm, t, p);
        ea_plot_data_row(pl, 6,
                         (double[]){t, tip[4 * r + 1], tip[4 * r + 2], p[0], p[1],
                                    1e3 * hypot(tip[4 * r + 1] - p[0], tip[4 * r + 2] - p[1])});
      }
      ea_plot_data_end(pl);
      ea_plot_cmd(pl, "set multiplot layout 1,2 title 'FE transient of %s (%s cable, dt = %g s)'",
                  o.traj_path, o.active ? "active" : "passive", o.dt);
      ea_plot_cmd(pl, "set size ratio -1\nset xlabel 'x [m]'\nset ylabel 'y [m]'\nset grid\n"
                      "set key top left\nset title 'tip path'");
      ea_plot_cmd(pl, "plot $sim u 4:5 w l lw 3 lc rgb '#999999' t 'planned (quasi-static)', "
                      "$sim u 2:3 w l lw 1.5 lc rgb '#1f77b4' t 'FE simulation'");
      ea_plot_cmd(pl,
                  "set size noratio\nset xlabel 't [s]'\nset ylabel '|tip - planned| [mm]'\n"
                  "set key top right\nset title 'tip error (motion ends at %.3g s)'\n"
                  "set arrow from %.9g, graph 0 to %.9g, graph 1 nohead dt 2 lc rgb 'black'",
                  t_first + duration, t_first + duration, t_first + duration);
      ea_plot_cmd(pl, "plot $sim u 1:6 w l lw 1.5 lc rgb '#d62728' t 'FE - plan'");
      ea_plot_cmd(pl, "unset multiplot");
      fe.status = ea_plot_close(pl, &fe);
    }
    if (fe.status) {
      fprintf(stderr, "elasticarm %s: figure: %s\n", cmd, fe.msg);
      rc = EA_EXIT_FAIL;
    }
  }
done:
  ea_afile_abort(&af);
  free(qstart);
  ea__sim_drive_free(&drv);
  free(tip);
  ea_fe_model_free(mh);
  ea_fe_model_free(m);
  ea_shooter_free(sh);
  ea_traj_free(&tr);
  return rc;
}
