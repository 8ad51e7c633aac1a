/* The FE commands as a user runs them: `frequencies` (single and the Fig. 5
 * sweep) and `simulate`. Frequencies are checked against an independent
 * library computation (statics + FE static solve + a different eigen
 * backend, dense LAPACK dsygv, than the CLI's banded dsbgvx); the sweep
 * against the paper's Fig. 5 trend; bad input against exit codes, messages
 * and leftover files; simulate against a held trajectory (no vibration) and
 * a fast move (vibration). */
#include "ea_planner.h"
#include "ea_problems.h"
#include "ea_simulate.h"
#include "ea_test.h"
#include "ea_test_cli.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>

static int exists(const char *path) {
  struct stat st;
  return stat(path, &st) == 0;
}

static void expect_rc(const char *args, int want_rc, const char *want, const char *what) {
  int rc = run(args);
  ea_test_true(rc == want_rc && strstr(out, want) != NULL, what);
  printf("  $ elasticarm %.160s -> exit %d: %.240s\n", args, rc, out);
}

/* A smooth quintic motion of (L_c, alpha) from a to b over T seconds (0 = held),
 * written as a trajectory file with T, theta0, kappa0 from the statics. */
static int write_traj(const char *path, const ea_arm_t *arm, double T, const double a[2],
                      const double b[2]) {
  ea_shooter_t *sh = NULL;
  if (ea_shooter_alloc(arm, NULL, &sh, NULL)) return 1;
  ea_load_t load = {arm->m_hand};
  ea_shooter_set_load(sh, &load);
  const int n = 41;
  const double dur = T > 0 ? T : 0.5;
  ea_traj_t tr = {0};
  if (ea_traj_alloc(&tr, n)) return 1;
  tr.tip_mass_kg = arm->m_hand;
  snprintf(tr.status, sizeof tr.status, "EA_OK");
  snprintf(tr.task, sizeof tr.task, "test_cli_fe quintic");
  double guess[EA_NP];
  int rc = 0;
  for (int i = 0; i < n && !rc; ++i) {
    const double t = dur * i / (n - 1), s = t / dur;
    const double h = T > 0 ? s * s * s * (10 - 15 * s + 6 * s * s) : 0.0;
    const double hd = T > 0 ? 30 * s * s * (1 - s) * (1 - s) / dur : 0.0;
    const double L = a[0] + (b[0] - a[0]) * h, al = a[1] + (b[1] - a[1]) * h;
    ea_statics_problem_t pr = ea_statics_problem_cable(L, al);
    ea_statics_solution_t sol;
    if (ea_statics_solve(sh, &pr, NULL, i ? guess : NULL, &sol, NULL)) {
      rc = 1;
      break;
    }
    memcpy(guess, sol.p, sizeof guess);
    EA_TRAJ_AT(&tr, i, EA_TRAJ_t) = t;
    EA_TRAJ_AT(&tr, i, EA_TRAJ_cable_length) = L;
    EA_TRAJ_AT(&tr, i, EA_TRAJ_cable_angle) = al;
    EA_TRAJ_AT(&tr, i, EA_TRAJ_cable_length_rate) = (b[0] - a[0]) * hd;
    EA_TRAJ_AT(&tr, i, EA_TRAJ_cable_angle_rate) = (b[1] - a[1]) * hd;
    ea_traj_set_statics(&tr, i, sol.p, sol.tip, arm->EI);
  }
  if (!rc) rc = ea_traj_write(&tr, path, NULL) != EA_OK;
  ea_traj_free(&tr);
  ea_shooter_free(sh);
  return rc;
}

static void write_text(const char *path, const char *text) {
  FILE *f = fopen(path, "w");
  if (f) {
    fputs(text, f);
    fclose(f);
  }
}

/* Out of memory is a failure (exit 1, "out of memory"), not a usage error: a
 * sweep of 99,976 points (about 140 MB of results) under a 120 MB address-space
 * limit. Skipped where the executable does not start under that limit (ASan). */
static void test_out_of_memory(void) {
  char cmd[4096];
  snprintf(cmd, sizeof cmd, "ulimit -v 120000 && %s --version 2>&1", bin);
  FILE *p = popen(cmd, "r");
  char line[256] = "";
  const int got = p && fgets(line, sizeof line, p) != NULL;
  const int rc0 = p ? pclose(p) : -1;
  if (!got || rc0 != 0 || !strstr(line, "elasticarm")) {
    printf("(the executable does not start under a 120 MB limit here: out-of-memory check "
           "skipped)\n");
    return;
  }
  snprintf(cmd, sizeof cmd,
           "ulimit -v 120000 && %s frequencies --sweep --cable-lengths 0.3:0.000004001:0.7 "
           "--modes 1 2>&1",
           bin);
  p = popen(cmd, "r");
  const size_t n = p ? fread(out, 1, sizeof out - 1, p) : 0;
  out[n] = '\0';
  const int st = p ? pclose(p) : -1;
  const int rc = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  printf("  120 MB limit, 99976-point sweep -> exit %d: %.200s\n", rc, out);
  ea_test_true(rc == 1 && strstr(out, "error: out of memory") != NULL,
               "out of memory: exit 1 and said, not a usage error");
}

int main(void) {
  char arm_path[1024], args[3072];
  if (cli_setup(arm_path, sizeof arm_path)) return 1;
  test_out_of_memory();
  ea_arm_t arm;
  if (ea_arm_load(arm_path, &arm, NULL)) {
    printf("cannot load %s\n", arm_path);
    return 1;
  }

  /* ---- frequencies --json: keys, and values vs the library ---------------- */
  snprintf(args, sizeof args,
           "frequencies --cable-length 0.45 --cable-angle-deg -20 --payload-factor 0.1 "
           "--modes 4 --elements 8 --arm %s --json",
           arm_path);
  int rc = run(args);
  ea_test_true(rc == 0, "frequencies --json exits 0");
  const char *keys[] = {"fe_iterations", "fe_residual",    "tension_N",
                        "theta0_rad",    "cable_length_m", "cable_angle_rad",
                        "tip_mass_kg",   "elements",       "tip_shift_m"};
  for (size_t k = 0; k < sizeof keys / sizeof *keys; ++k) {
    char w[96];
    snprintf(w, sizeof w, "JSON has numeric key %s", keys[k]);
    ea_test_true(isfinite(json_num(keys[k])), w);
  }
  ea_test_true(strstr(out, "\"stable\": true") != NULL, "JSON stable: true");
  ea_test_true(strstr(out, "\"status\": \"EA_OK\"") != NULL, "JSON status EA_OK");
  ea_test_true(isfinite(json_list("frequencies_Hz", 3)) && isnan(json_list("frequencies_Hz", 4)),
               "frequencies_Hz lists exactly 4 modes");
  {
    double cli_f[4], cli_T = json_num("tension_N"), cli_th = json_num("theta0_rad");
    for (int k = 0; k < 4; ++k)
      cli_f[k] = json_list("frequencies_Hz", k);
    ea_shooter_t *sh = NULL;
    ea_shooter_alloc(&arm, NULL, &sh, NULL);
    ea_load_t load = {ea_arm_tip_mass(&arm, ea_arm_payload_from_factor(&arm, 0.1))};
    ea_shooter_set_load(sh, &load);
    ea_statics_problem_t pr = ea_statics_problem_cable(0.45, -20.0 * M_PI / 180);
    ea_statics_solution_t sol;
    ea_fe_settings_t fs;
    ea_fe_settings_default(&fs);
    fs.elements = 8;
    fs.modes = 4;
    fs.static_hold_tip = 1;
    fs.eig_backend = EA_FE_EIG_DSYGV; /* a different eigen-solver than the CLI's */
    ea_fe_model_t *m = NULL;
    ea_fe_static_info_t fi;
    ea_fe_modes_info_t mi;
    int ok = ea_statics_solve(sh, &pr, NULL, NULL, &sol, NULL) == EA_OK &&
             ea_fe_model_alloc(&arm, &fs, &m, NULL) == EA_OK &&
             ea_fe_static_solve(m, sh, &sol, &fi, NULL) == EA_OK &&
             ea_fe_modes(m, &mi, NULL) == EA_OK;
    ea_test_true(ok, "library: statics, FE static solve and modes succeed");
    for (int k = 0; ok && k < 4; ++k) {
      char w[96];
      snprintf(w, sizeof w, "CLI f%d vs library (dense dsygv)", k + 1);
      ea_test_rel(cli_f[k], mi.freq_hz[k], 1e-7, w);
    }
    if (ok) {
      ea_test_rel(cli_T, fi.tension, 1e-9, "CLI tension_N = FE equilibrium tension");
      ea_test_rel(cli_th, fi.theta0, 1e-9, "CLI theta0_rad = FE equilibrium theta0");
    }
    ea_fe_model_free(m);
    ea_shooter_free(sh);
  }
  /* text form and a figure */
  const char *fig1 = "test_cli_fe_modes.svg";
  remove(fig1);
  snprintf(args, sizeof args,
           "frequencies --cable-length 0.4 --cable-angle-deg 0 --arm %s --figure %s", arm_path,
           fig1);
  rc = run(args);
  struct stat stt;
  ea_test_true(rc == 0 && strstr(out, "frequency [Hz]") && stat(fig1, &stt) == 0 &&
                   stt.st_size > 2000,
               "frequencies text table and mode-shape figure");

  /* ---- Fig. 5 sweep: CSV shape and trend ---------------------------------- */
  const char *csv = "test_cli_fe_sweep.csv", *fig5 = "test_cli_fe_fig5.svg";
  remove(csv);
  remove(fig5);
  snprintf(args, sizeof args,
           "frequencies --sweep --cable-lengths 0.254:0.0381:0.635 --arm %s --csv %s --figure %s",
           arm_path, csv, fig5);
  rc = run(args);
  ea_test_true(rc == 0 && strstr(out, "as the cable shortens"), "sweep exits 0, prints changes");
  printf("%s", out);
  ea_test_true(stat(fig5, &stt) == 0 && stt.st_size > 5000, "Fig. 5 figure written");
  {
    FILE *f = fopen(csv, "r");
    char line[1024];
    int rows = 0, header_ok = 0, cols_ok = 1, stable_all = 1;
    double L[32], f1[32], f2[32], f3[32];
    if (f && fgets(line, sizeof line, f))
      header_ok = !strcmp(line, "cable_length_m,f1_Hz,f2_Hz,f3_Hz,stable,tension_N,theta0_rad,"
                                "fe_iterations,fe_residual,status\n");
    while (f && fgets(line, sizeof line, f) && rows < 32) {
      int commas = 0;
      for (char *c = line; *c; ++c)
        commas += *c == ',';
      cols_ok = cols_ok && commas == 9 && strstr(line, ",EA_OK");
      int stable = 0;
      if (sscanf(line, "%lf,%lf,%lf,%lf,%d", &L[rows], &f1[rows], &f2[rows], &f3[rows], &stable) !=
          5)
        cols_ok = 0;
      stable_all = stable_all && stable == 1;
      ++rows;
    }
    if (f) fclose(f);
    ea_test_true(header_ok, "sweep CSV header with units");
    ea_test_true(rows == 11 && cols_ok, "sweep CSV: 11 rows of 10 columns, all EA_OK");
    ea_test_true(stable_all, "sweep: every configuration stable");
    if (rows == 11 && cols_ok) {
      int mono1 = 1, mono2 = 1, mono3 = 1;
      for (int k = 1; k < rows; ++k) {
        mono1 = mono1 && f1[k] < f1[k - 1];
        mono2 = mono2 && f2[k] > f2[k - 1];
        mono3 = mono3 && f3[k] > f3[k - 1];
      }
      ea_test_true(mono1, "Fig. 5: f1 rises as the cable shortens (monotone)");
      ea_test_true(mono2 && mono3, "Fig. 5: f2 and f3 rise as the cable lengthens (monotone)");
      const double c1 = (f1[0] - f1[rows - 1]) / f1[rows - 1];
      ea_test_abs(c1, 0.55, 0.05, "Fig. 5: f1 +55 % as the cable shortens 0.635 -> 0.254 m");
      printf("  f2 change %.1f %% (paper 38 %%), f3 change %.1f %% (paper 12 %%)\n",
             100 * (f2[rows - 1] - f2[0]) / f2[0], 100 * (f3[rows - 1] - f3[0]) / f3[0]);
    }
  }

  /* ---- frequencies: bad input -------------------------------------------- */
  expect_rc("frequencies --cable-length 0.4", 2, "give --cable-length and --cable-angle-deg",
            "frequencies without an angle: exit 2");
  expect_rc("frequencies --cable-length 0.4 --cable-angle-deg 0 --modes 0", 2,
            "--modes: value 0 is outside", "zero modes: exit 2");
  expect_rc("frequencies --cable-length x --cable-angle-deg 0", 2, "--cable-length: 'x'",
            "non-numeric length: exit 2");
  expect_rc("frequencies --sweep --cable-lengths 0.3:-1:0.5", 2, "--cable-lengths",
            "bad sweep range: exit 2");
  expect_rc("frequencies --cable-length 0.4 --cable-angle-deg 0 --figure x.gif", 2,
            "must end in .svg", "bad figure extension: exit 2");
  expect_rc("frequencies --cable-length 0.4 --cable-angle-deg 0 --fe-hold tip2", 2,
            "--fe-hold: 'tip2'", "bad --fe-hold: exit 2");
  snprintf(args, sizeof args,
           "frequencies --cable-length 0.95 --cable-angle-deg -20 --arm %s --figure "
           "test_cli_fe_out.svg",
           arm_path);
  remove("test_cli_fe_out.svg");
  expect_rc(args, 1, "error", "configuration outside the workspace: exit 1");
  ea_test_true(!exists("test_cli_fe_out.svg"), "outside the workspace: no figure left behind");

  /* ---- simulate ----------------------------------------------------------- */
  const char *held = "test_cli_fe_held.csv", *fast = "test_cli_fe_fast.csv";
  const double p0[2] = {0.40, -0.30}, p1[2] = {0.55, -0.10};
  ea_test_true(write_traj(held, &arm, 0.0, p0, p0) == 0, "held trajectory written");
  ea_test_true(write_traj(fast, &arm, 0.6, p0, p1) == 0, "fast trajectory written");
  const char *tip = "test_cli_fe_tip.csv";
  /* held: the arm sits in its static equilibrium, nothing should move */
  snprintf(args, sizeof args, "simulate %s --arm %s --json", held, arm_path);
  rc = run(args);
  ea_test_true(rc == 0, "simulate held: exit 0");
  if (rc) printf("  -> %.400s\n", out);
  const double held_rms = json_num("residual_vibration_rms_m");
  ea_test_true(held_rms < 1e-6, "held: residual vibration rms < 1 um");
  ea_test_true(json_num("max_tracking_error_m") < 1e-4, "held: tip stays within 0.1 mm of plan");
  /* fast move: JSON keys, tip CSV, vibration */
  remove(tip);
  snprintf(args, sizeof args, "simulate %s --arm %s -o %s --json", fast, arm_path, tip);
  rc = run(args);
  ea_test_true(rc == 0, "simulate fast: exit 0");
  if (rc) printf("  -> %.400s\n", out);
  const char *skeys[] = {"residual_vibration_rms_m",
                         "residual_vibration_peak_m",
                         "max_tracking_error_m",
                         "energy_drift_J",
                         "steps",
                         "newton_iterations",
                         "wall_time_s",
                         "simulated_time_s"};
  for (size_t k = 0; k < sizeof skeys / sizeof *skeys; ++k) {
    char w[96];
    snprintf(w, sizeof w, "simulate JSON has key %s", skeys[k]);
    ea_test_true(isfinite(json_num(skeys[k])), w);
  }
  {
    FILE *f = fopen(tip, "r");
    char line[512];
    int rows = 0, header_ok = 0;
    if (f && fgets(line, sizeof line, f))
      header_ok = !strcmp(line, "t_s,tip_x_m,tip_y_m,tip_theta_rad,planned_tip_x_m,"
                                "planned_tip_y_m\n");
    while (f && fgets(line, sizeof line, f))
      ++rows;
    if (f) fclose(f);
    ea_test_true(header_ok && rows == (int)json_num("steps") + 1,
                 "tip CSV: header and one row per step + 1");
  }
  const double fast_rms = json_num("residual_vibration_rms_m");
  ea_test_true(fast_rms > 1e-4, "fast move: residual vibration > 0.1 mm");
  ea_test_true(fast_rms > 1e3 * (isfinite(held_rms) ? fmax(held_rms, 1e-12) : INFINITY),
               "fast move: residual vibration >> held");
  printf("  held rms %.3g m, fast rms %.3g m, fast peak %.3g m, tracking %.3g m\n", held_rms,
         fast_rms, json_num("residual_vibration_peak_m"), json_num("max_tracking_error_m"));
  /* damping reduces it */
  snprintf(args, sizeof args, "simulate %s --arm %s --json --damping-ratio 0.1", fast, arm_path);
  rc = run(args);
  ea_test_true(rc == 0 && json_num("residual_vibration_rms_m") < fast_rms,
               "fast move with --damping-ratio 0.1: less residual vibration");
  /* strain-rate damping: ratio 0.1 at mode 1, more above, no mass part */
  ea_test_rel(json_list("modal_damping_ratios", 0), 0.1, 1e-9, "modal damping ratio 1 = 0.1");
  ea_test_true(json_list("modal_damping_ratios", 1) > 0.1 && json_num("rayleigh_mass_per_s") == 0,
               "--damping-ratio: strain-rate only, mode 2 damped more");
  printf("  --damping-ratio 0.1: b = %.4g s, ratios %.4f %.4f %.4f, residual rms %.4g m, "
         "tracking %.4g m\n",
         json_num("rayleigh_stiffness_s"), json_list("modal_damping_ratios", 0),
         json_list("modal_damping_ratios", 1), json_list("modal_damping_ratios", 2),
         json_num("residual_vibration_rms_m"), json_num("max_tracking_error_m"));
  /* the simple CSV form gives the same result as the trajectory file */
  {
    FILE *f = fopen("test_cli_fe_simple.csv", "w");
    ea_traj_t tr = {0};
    if (f && ea_traj_read(&tr, fast, NULL) == EA_OK) {
      fprintf(f, "t_s,cable_length_m,cable_angle_rad\n");
      for (int i = 0; i < tr.n; ++i)
        fprintf(f, "%.17g,%.17g,%.17g\n", EA_TRAJ_AT(&tr, i, EA_TRAJ_t),
                EA_TRAJ_AT(&tr, i, EA_TRAJ_cable_length), EA_TRAJ_AT(&tr, i, EA_TRAJ_cable_angle));
    }
    if (f) fclose(f);
    ea_traj_free(&tr);
    snprintf(args, sizeof args, "simulate test_cli_fe_simple.csv --arm %s --json", arm_path);
    rc = run(args);
    ea_test_true(rc == 0 && strstr(out, "\"trajectory_format\": \"simple-csv\""),
                 "simple CSV accepted");
    /* the file's exact rates vs centred differences of the samples: measured 3.3e-4 */
    ea_test_rel(json_num("residual_vibration_rms_m"), fast_rms, 1e-3,
                "simple CSV (centred-difference rates) ~ trajectory file (exact rates)");
    ea_test_true(json_num("residual_vibration_rms_m") != fast_rms,
                 "simulate uses the trajectory's rate columns (differs from differences)");
  }

  /* ---- simulate: the arm file's hand mass, the trajectory's recorded arm -------- */
  {
    /* an arm file with the hand 0.230 -> 0.300 kg (nothing else changed) */
    const char *heavy = "test_cli_fe_heavy.yaml", *rec = "test_cli_fe_rec.csv",
               *lost = "test_cli_fe_lost.csv";
    FILE *fi = fopen(arm_path, "r"), *fo = fopen(heavy, "w");
    char line[1024];
    int replaced = 0;
    while (fi && fo && fgets(line, sizeof line, fi)) {
      char *at = strstr(line, "mass_kg: 0.230 ");
      if (at && !replaced) {
        memcpy(at, "mass_kg: 0.300 ", 15);
        replaced = 1;
      }
      fputs(line, fo);
    }
    if (fi) fclose(fi);
    if (fo) fclose(fo);
    ea_test_true(replaced == 1, "arm file with the hand mass changed written");
    snprintf(args, sizeof args, "simulate %s --arm %s --json", fast, heavy);
    rc = run(args);
    const double heavy_rms = json_num("residual_vibration_rms_m");
    ea_test_true(rc == 0 && fabs(json_num("tip_mass_kg") - 0.300) < 1e-12,
                 "simulate --arm (hand 0.3 kg): exit 0, tip_mass_kg 0.3");
    /* measured: 35.27 mm nominal, 35.96 mm with the 0.3 kg hand (+1.9 %) */
    ea_test_true(fabs(heavy_rms / fast_rms - 1) > 1e-2,
                 "simulate --arm: the hand mass changes the residual (> 1 %)");
    /* independent: the library on the nominal arm with the tip mass given explicitly */
    ea_traj_t tr = {0};
    ea_sim_settings_t ss;
    ea_sim_settings_default(&ss);
    ea_sim_info_t si;
    ea_error_t e;
    double lib_rms = NAN;
    if (ea_traj_read(&tr, fast, NULL) == EA_OK &&
        ea_traj_simulate(&arm, &tr, 0.300, &ss, NULL, &si, &e) == EA_OK)
      lib_rms = si.residual_rms;
    printf("  hand 0.3 kg: residual rms %.9g m (CLI, arm file), %.9g m (library, nominal arm, tip "
           "mass 0.3 kg); nominal %.9g m\n",
           heavy_rms, lib_rms, fast_rms);
    ea_test_rel(heavy_rms, lib_rms, 1e-9,
                "simulate --arm: = library run with that tip mass on the nominal arm");
    /* the trajectory records the heavy arm file: simulate takes it without --arm */
    snprintf(tr.arm_file, sizeof tr.arm_file, "%s", heavy);
    ea_test_true(ea_traj_write(&tr, rec, NULL) == EA_OK, "trajectory recording the arm written");
    snprintf(args, sizeof args, "simulate %s --json", rec);
    rc = run(args);
    ea_test_true(rc == 0 && strstr(out, "\"arm_file\": \"/") &&
                     strstr(out, "/test_cli_fe_heavy.yaml\""),
                 "simulate without --arm: the recorded arm file (absolute), named in the JSON");
    ea_test_rel(json_num("residual_vibration_rms_m"), heavy_rms, 1e-12,
                "simulate without --arm: = the run with --arm of the recorded file");
    snprintf(args, sizeof args, "simulate %s --arm %s --json", rec, arm_path);
    rc = run(args);
    ea_test_rel(json_num("residual_vibration_rms_m"), fast_rms, 1e-12,
                "simulate --arm overrides the recorded arm file");
    /* a recorded arm file that is not there: refused, never the default arm silently */
    snprintf(tr.arm_file, sizeof tr.arm_file, "%s", "test_cli_fe_no_such_arm.yaml");
    ea_traj_write(&tr, lost, NULL);
    snprintf(args, sizeof args, "simulate %s --json", lost);
    expect_rc(args, 2, "records the arm file 'test_cli_fe_no_such_arm.yaml'",
              "recorded arm file missing: exit 2 naming it");
    ea_traj_free(&tr);
  }

  /* ---- simulate: bad input, nothing left behind ----------------------------- */
  remove(tip);
  snprintf(args, sizeof args, "simulate /nonexistent/traj.csv --arm %s -o %s", arm_path, tip);
  expect_rc(args, 2, "/nonexistent/traj.csv", "missing trajectory: exit 2 naming it");
  ea_test_true(!exists(tip), "missing trajectory: no tip file");
  write_text("test_cli_fe_bad.csv", "# elasticarm-trajectory 1\nt_s,cable_length_m\n0,0.4\n");
  snprintf(args, sizeof args, "simulate test_cli_fe_bad.csv --arm %s -o %s", arm_path, tip);
  expect_rc(args, 2, "test_cli_fe_bad.csv:", "malformed trajectory: exit 2 with file:line");
  ea_test_true(!exists(tip), "malformed trajectory: no tip file");
  write_text("test_cli_fe_bad2.csv",
             "t_s,cable_length_m,cable_angle_rad\n0,0.4,-0.3\n0.5,0.4x,-0.3\n");
  snprintf(args, sizeof args, "simulate test_cli_fe_bad2.csv --arm %s -o %s", arm_path, tip);
  expect_rc(args, 2, "test_cli_fe_bad2.csv:3:", "malformed simple CSV: exit 2 with file:line:col");
  write_text("test_cli_fe_out.csv",
             "t_s,cable_length_m,cable_angle_rad\n0,0.95,-0.35\n1,0.95,-0.35\n");
  snprintf(args, sizeof args, "simulate test_cli_fe_out.csv --arm %s -o %s --figure %s.svg",
           arm_path, tip, tip);
  expect_rc(args, 1, "no static solution", "trajectory outside the workspace: exit 1");
  ea_test_true(!exists(tip), "outside the workspace: no tip file");
  snprintf(args, sizeof args, "simulate %s --dt 0", held);
  expect_rc(args, 2, "--dt: value 0 is outside", "zero time step: exit 2");
  snprintf(args, sizeof args, "simulate %s --scheme rk4", held);
  expect_rc(args, 2, "--scheme: 'rk4'", "unknown scheme: exit 2");
  snprintf(args, sizeof args, "simulate %s --damping-ratio 0.1 --rayleigh 1,0", held);
  expect_rc(args, 2, "give --damping-ratio or --rayleigh once", "two damping models: exit 2");
  expect_rc("simulate", 2, "give a trajectory file", "no trajectory: exit 2");
  snprintf(args, sizeof args, "simulate %s --scheme energy --rho-inf 0.5", held);
  expect_rc(args, 2, "--rho-inf needs --scheme genalpha", "--rho-inf without genalpha: exit 2");
  snprintf(args, sizeof args, "simulate %s --scheme genalpha --rho-inf 1.5", held);
  expect_rc(args, 2, "--rho-inf: value 1.5 is outside", "--rho-inf 1.5: exit 2");
  /* generalized-alpha: held arm stays put; the fast move vibrates like with the energy
   * scheme (the low modes, omega dt << 1, carry next to no numerical damping) */
  snprintf(args, sizeof args, "simulate %s --arm %s --scheme genalpha --json", held, arm_path);
  rc = run(args);
  ea_test_true(rc == 0 && json_num("residual_vibration_rms_m") < 1e-6 && json_num("rho_inf") == 0.9,
               "genalpha held: exit 0, residual rms < 1 um, rho_inf 0.9 reported");
  remove(tip);
  snprintf(args, sizeof args, "simulate %s --arm %s --scheme genalpha --rho-inf 0.7 -o %s --json",
           fast, arm_path, tip);
  rc = run(args);
  const double ga_rms = json_num("residual_vibration_rms_m");
  ea_test_true(rc == 0 && exists(tip), "genalpha fast move: exit 0, tip file");
  /* reference: the other scheme (energy) at dt / 4; measured 3.3e-5 apart, tolerance 3e-4 */
  snprintf(args, sizeof args, "simulate %s --arm %s --scheme energy --dt 2.5e-4 --json", fast,
           arm_path);
  rc = run(args);
  const double fine_rms = json_num("residual_vibration_rms_m");
  ea_test_rel(ga_rms, fine_rms, 3e-4, "genalpha fast move: residual rms ~ energy scheme at dt / 4");
  /* the energy scheme at the default dt against itself at dt / 4 (this cable-length drive
   * moves the rest length by more than the cable's stretch per step: before the mid-step
   * rest-length fix the two were 2.4 % apart); measured 3.4e-5, tolerance 3e-4 */
  snprintf(args, sizeof args, "simulate %s --arm %s --scheme energy --json", fast, arm_path);
  rc = run(args);
  const double en_rms = json_num("residual_vibration_rms_m");
  ea_test_rel(en_rms, fine_rms, 3e-4, "energy scheme fast move: dt 1 ms ~ dt 0.25 ms");
  snprintf(args, sizeof args, "simulate %s --arm %s --scheme genalpha --rho-inf 1 --json", fast,
           arm_path);
  rc = run(args);
  const double ga1_rms = json_num("residual_vibration_rms_m");
  snprintf(args, sizeof args, "simulate %s --arm %s --scheme genalpha --dt 2.5e-4 --json", fast,
           arm_path);
  rc = run(args);
  const double ga_fine_rms = json_num("residual_vibration_rms_m");
  /* rho_inf 0.7 and 1 at dt 1 ms: measured 1.5e-7 apart, tolerance 1.5e-6; the schemes at
   * dt 0.25 ms: measured 5.5e-7, tolerance 5e-6 */
  ea_test_rel(ga1_rms, ga_rms, 1.5e-6, "genalpha fast move: rho_inf 1 ~ rho_inf 0.7");
  ea_test_rel(ga_fine_rms, fine_rms, 5e-6, "fast move at dt 0.25 ms: genalpha ~ energy");
  /* docs/fe.md quotes this line (docs/regenerate.sh) */
  printf("fast move residual rms [m]: default (genalpha 0.9, dt 1 ms) %.10f, genalpha 0.7 %.10f, "
         "genalpha 1 %.10f, energy dt 1 ms %.10f, energy dt 0.25 ms %.10f, genalpha dt 0.25 ms "
         "%.10f\n",
         fast_rms, ga_rms, ga1_rms, en_rms, fine_rms, ga_fine_rms);
  return ea_test_summary("test_cli_fe");
}
