/* The CLI as a user runs it: exit codes, messages for bad input, JSON keys,
 * figures, atomic outputs. Values are checked against an independent
 * re-solve through the library with a different problem statement. */
#include "ea_planner.h"
#include "ea_test.h"
#include "ea_test_cli.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>

static void expect_usage(const char *args, const char *want, const char *what) {
  int rc = run(args);
  ea_test_true(rc == 2 && strstr(out, want) != NULL, what);
  printf("  $ elasticarm %s -> exit %d: %.200s\n", args, rc, out);
}

int main(void) {
  char arm_path[1024];
  if (cli_setup(arm_path, sizeof arm_path)) return 1;
  const char *src = getenv("EA_SOURCE_DIR");

  /* Usage errors: exit 2, a message naming the flag and the value. */
  expect_usage("", "usage", "no command");
  expect_usage("frobnicate", "unknown command 'frobnicate'", "unknown command");
  expect_usage("statics --cable-length abc --cable-angle-deg 0", "--cable-length: 'abc'",
               "non-numeric value");
  expect_usage("statics --cable-length nan --cable-angle-deg 0", "--cable-length: 'nan'",
               "NaN value");
  expect_usage("statics --cable-length 0.4", "give exactly one of", "incomplete problem statement");
  expect_usage("statics --cable-length 0.4 --cable-angle-deg 0 --tip 0.3,0.2",
               "give exactly one of", "contradictory problem statement");
  expect_usage("statics --tip 0.3", "--tip: '0.3' is not 'X,Y'", "malformed pair");
  expect_usage("statics --cable-length 0.4 --cable-angle-deg 500", "outside [-180, 180]",
               "angle out of range");
  expect_usage("statics --cable-length", "needs a value", "missing value");
  expect_usage("statics --bogus 1", "unknown option '--bogus'", "unknown option");
  expect_usage("statics --cable-length 0.4 --cable-angle-deg 0 --arm /nonexistent.yaml",
               "/nonexistent.yaml: cannot open", "missing arm file");
  expect_usage("workspace --payload-factors 0,x", "--payload-factors", "bad list");
  expect_usage("workspace --alpha-min-deg 10 --alpha-max-deg -10", "must be below",
               "empty angle range");
  expect_usage("path --steps 0", "outside [1, 100000]", "zero steps");

  /* statics --json, checked by an independent library solve from the tip. */
  char args[1400];
  snprintf(args, sizeof args,
           "statics --cable-length 0.45 --cable-angle-deg -25 --payload-factor 0.25 --arm %s "
           "--json",
           arm_path);
  int rc = run(args);
  ea_test_true(rc == 0, "statics --json exits 0");
  const char *keys[] = {"tension_N",       "theta0_rad",     "kappa0_per_m", "shoulder_torque_Nm",
                        "cable_angle_rad", "cable_length_m", "residual",     "iterations"};
  for (size_t k = 0; k < sizeof keys / sizeof *keys; ++k) {
    char w[96];
    snprintf(w, sizeof w, "JSON has key %s", keys[k]);
    ea_test_true(isfinite(json_num(keys[k])), w);
  }
  ea_test_true(strstr(out, "\"tip_m\": [") && strstr(out, "\"status\": \"EA_OK\""),
               "JSON has tip_m and status EA_OK");
  {
    ea_arm_t arm;
    ea_arm_load(arm_path, &arm, NULL);
    ea_shooter_t *sh = NULL;
    ea_shooter_alloc(&arm, NULL, &sh, NULL);
    ea_load_t load = {ea_arm_tip_mass(&arm, ea_arm_payload_from_factor(&arm, 0.25))};
    ea_shooter_set_load(sh, &load);
    const double a = -25.0 * M_PI / 180;
    ea_statics_problem_t pr =
        ea_statics_problem_tip(arm.x_c + 0.45 * cos(a), arm.y_c + 0.45 * sin(a));
    ea_statics_solution_t sol;
    ea_statics_solve(sh, &pr, NULL, NULL, &sol, NULL);
    ea_test_rel(json_num("tension_N"), sol.p[EA_P_TENSION], 1e-8,
                "CLI tension vs library tip solve");
    ea_test_rel(json_num("theta0_rad"), sol.p[EA_P_THETA0], 1e-8,
                "CLI theta0 vs library tip solve");
    ea_test_rel(json_num("shoulder_torque_Nm"), arm.EI * sol.p[EA_P_KAPPA0], 1e-8,
                "CLI torque = EI kappa0");
    ea_shooter_free(sh);
  }

  /* Outside the workspace: exit 1 and says why. */
  snprintf(args, sizeof args, "statics --cable-length 0.95 --cable-angle-deg -20 --arm %s",
           arm_path);
  rc = run(args);
  ea_test_true(rc == 1 && strstr(out, "error"), "outside the workspace: exit 1 with an error");
  printf("  -> %.300s\n", out);

  /* The paper's path: admissible, with a figure. */
  const char *svg = "test_cli_path.svg";
  remove(svg);
  snprintf(args, sizeof args, "path --arm %s --figure %s", arm_path, svg);
  rc = run(args);
  ea_test_true(rc == 0 && strstr(out, "path ADMISSIBLE"), "paper path admissible (exit 0)");
  struct stat stt;
  ea_test_true(stat(svg, &stt) == 0 && stt.st_size > 1000, "path figure written");
  /* A path leaving the workspace: exit 1, reason per step. */
  snprintf(args, sizeof args, "path --arm %s --from 0.3,-0.2 --to 0.95,-0.2 --steps 4", arm_path);
  rc = run(args);
  ea_test_true(rc == 1 && strstr(out, "NOT admissible") && strstr(out, "NO: "),
               "path beyond the edge: exit 1, reasons given");

  /* Atomic output: an unwritable CSV leaves nothing behind. */
  /* a directory that cannot exist: its parent is a regular file */
  FILE *blocker = fopen("test_cli_blocker", "w");
  if (blocker) fclose(blocker);
  snprintf(args, sizeof args, "torque-map --arm %s --csv test_cli_blocker/x.csv", arm_path);
  rc = run(args);
  ea_test_true(rc != 0 && strstr(out, "test_cli_blocker/x.csv"),
               "unwritable output: error names it");
  const char *csv = "test_cli_tm.csv";
  remove(csv);
  snprintf(args, sizeof args,
           "torque-map --arm %s --cable-lengths 0.3,0.5,0.9 --cable-angles-deg -40,0 --csv %s",
           arm_path, csv);
  rc = run(args);
  FILE *f = fopen(csv, "r");
  int lines = 0, outside = 0;
  char line[512];
  while (f && fgets(line, sizeof line, f)) {
    ++lines;
    if (strstr(line, "outside the workspace")) ++outside;
  }
  if (f) fclose(f);
  ea_test_true(rc == 0 && lines == 7, "torque map CSV: header + 6 cells");
  ea_test_true(outside == 2, "torque map marks the 0.9 m cells outside the workspace");
  /* figure: a trajectory file written through the library (statics at three
   * cable lengths), drawn by the CLI; a malformed one is refused with its
   * position. */
  {
    ea_arm_t arm;
    ea_arm_load(arm_path, &arm, NULL);
    ea_shooter_t *sh = NULL;
    ea_shooter_alloc(&arm, NULL, &sh, NULL);
    ea_traj_t tr = {0};
    ea_traj_alloc(&tr, 3);
    tr.tip_mass_kg = arm.m_hand;
    for (int k = 0; k < 3; ++k) {
      ea_statics_problem_t pr = ea_statics_problem_cable(0.3 + 0.1 * k, -0.4);
      ea_statics_solution_t sol;
      ea_statics_solve(sh, &pr, NULL, NULL, &sol, NULL);
      EA_TRAJ_AT(&tr, k, EA_TRAJ_t) = 0.5 * k;
      EA_TRAJ_AT(&tr, k, EA_TRAJ_cable_length) = sol.cable_length;
      EA_TRAJ_AT(&tr, k, EA_TRAJ_cable_angle) = sol.p[EA_P_ALPHA];
      ea_traj_set_statics(&tr, k, sol.p, sol.tip, arm.EI);
    }
    ea_traj_write(&tr, "test_cli_traj.csv", NULL);
    ea_traj_free(&tr);
    ea_shooter_free(sh);
    remove("test_cli_traj.png");
    snprintf(args, sizeof args, "figure test_cli_traj.csv -o test_cli_traj.png --arm %s", arm_path);
    rc = run(args);
    struct stat fs;
    ea_test_true(rc == 0 && stat("test_cli_traj.png", &fs) == 0 && fs.st_size > 1000,
                 "figure draws a trajectory file");
    FILE *bad = fopen("test_cli_bad.csv", "w");
    if (bad) {
      fputs("# elasticarm-trajectory 1\nt_s,cable_length_m\n", bad);
      fclose(bad);
    }
    rc = run("figure test_cli_bad.csv -o test_cli_bad.png");
    ea_test_true(rc == 2 && strstr(out, "test_cli_bad.csv:2:") &&
                     stat("test_cli_bad.png", &fs) != 0,
                 "figure refuses a malformed trajectory with file:line, writes nothing");
    printf("  -> %.200s\n", out);
  }

  /* Golden file with a float-tolerant comparison: the paper's path against
   * data/reference/paper_line_path.csv, generated independently with scipy by
   * tests/gen/gen_paper_line.py. */
  {
    char ref_path[1100];
    snprintf(ref_path, sizeof ref_path, "%s/data/reference/paper_line_path.csv", src);
    FILE *rf = fopen(ref_path, "r");
    snprintf(args, sizeof args, "path --arm %s --no-stability --csv test_cli_path.csv", arm_path);
    rc = run(args);
    FILE *of = fopen("test_cli_path.csv", "r");
    ea_test_true(rf && of && rc == 0, "golden: reference and output readable");
    char rl[1024], ol[2048];
    double worst = 0;
    int rows = 0;
    if (rf && of && fgets(rl, sizeof rl, rf) && fgets(ol, sizeof ol, of)) {
      /* output columns: beta,cable_length_m,cable_angle_rad,tip_x_m,tip_y_m,tension_N,
       * theta0_rad,kappa0_per_m,shoulder_torque_Nm,... ; reference: beta,cable_length_m,
       * cable_angle_rad,tension_N,theta0_rad,kappa0_per_m,shoulder_torque_Nm */
      while (fgets(rl, sizeof rl, rf) && fgets(ol, sizeof ol, of)) {
        double r[7], o[9];
        if (sscanf(rl, "%lf,%lf,%lf,%lf,%lf,%lf,%lf", &r[0], &r[1], &r[2], &r[3], &r[4], &r[5],
                   &r[6]) != 7 ||
            sscanf(ol, "%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf", &o[0], &o[1], &o[2], &o[3], &o[4],
                   &o[5], &o[6], &o[7], &o[8]) != 9)
          break;
        const double pairs[6][2] = {{r[1], o[1]}, {r[2], o[2]}, {r[3], o[5]},
                                    {r[4], o[6]}, {r[5], o[7]}, {r[6], o[8]}};
        for (int q = 0; q < 6; ++q)
          worst = fmax(worst, fabs(pairs[q][0] - pairs[q][1]) / fmax(1.0, fabs(pairs[q][0])));
        ++rows;
      }
    }
    if (rf) fclose(rf);
    if (of) fclose(of);
    ea_test_true(rows == 7, "golden: 7 path steps compared");
    ea_test_abs(worst, 0.0, 1e-8, "golden: path vs independent scipy solution (worst rel.)");
  }
  return ea_test_summary("test_cli");
}
