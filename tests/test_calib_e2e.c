/* Calibration end to end (docs/calibration.md, "End to end"): an arm that is not the
 * paper's is measured by the project's own loop and the plans made on the calibrated arm
 * arrive at rest on it, where the paper arm's plans do not.
 *
 * The "true" arm: the paper's with EI +12 %, hand mass +20 %, I_L x2.5 and damping 0.05 (its
 * ring-downs decay well inside each 20 s hold, so the static rows, averaged over the hold's
 * last third, are at rest).
 * 1. calibrate-experiment (3 cable lengths x 2 cable angles, holds of 20 s) planned on the
 *    paper's arm.
 * 2. The controller simulator's session in the library (setpoints at 1 kHz ->
 *    ea_stream_setpoints_traj -> FE transient on the true arm -> ea_record_write, the code
 *    of controller-sim --simulate --record): the records, with sensor noise.
 * 3. elasticarm calibrate RECORDS --arm PAPER --fix EA_c -o CAL.yaml (the simulator's
 *    cable_length_m is the cable's length at the planned tension, its stretch already paid
 *    out by the spool, so the records carry no stretch to fit EA_c to).
 * 4. For the paper line and two lines where the paper arm's plan misses: plan (by default
 *    checked by the FE and refined within 0.5 mm) on the paper arm and on the calibrated arm, each
 * simulated by the FE (genalpha, dt 0.5 ms, 3 s settle) on the TRUE arm. The reference is the FE
 * transient of the true arm: the calibrated arm's plans leave at most 1 mm, the paper arm's more
 * than 3 mm on the two lines. */
#include "ea_experiment_plan.h"
#include "ea_planner.h"
#include "ea_problems.h"
#include "ea_simulate.h"
#include "ea_stream.h"
#include "ea_test.h"
#include "ea_test_cli.h"
#include "ea_test_record.h"

#include <glob.h>

static void write_text(const char *path, const char *text) {
  FILE *fp = fopen(path, "w");
  if (fp) {
    fputs(text, fp);
    fclose(fp);
  }
}

/* An at-rest line task on arm_file; plan (refined by default); the FE residual peak [m] of the plan
 * on the true arm (NAN when a step fails). */
static double plan_on(const char *name, const char *arm_file, const double a[2], const double b[2],
                      double payload_factor, const char *true_arm_path) {
  char task[1024], path[256], args[1024];
  snprintf(task, sizeof task,
           "name: %s\narm_file: %s\npayload_factor: %g\nstart:\n  tip: [%.17g, %.17g]\n"
           "goal:\n  tip: [%.17g, %.17g]\npath: line\nobjective: min_time\nknots: 100\n"
           "dynamics:\n  modes: 2\n  residual_m: 0\n"
           /* the default bound (0.5 mm) with a wall-time cap that a slow (sanitizer) build
            * does not reach: the default 10 s decides by the machine's speed */
           "  refine:\n    tolerance_m: 5e-4\n    max_time_s: 300\n",
           name, arm_file, payload_factor, a[0], a[1], b[0], b[1]);
  snprintf(path, sizeof path, "%s.yaml", name);
  write_text(path, task);
  snprintf(args, sizeof args, "plan %s.yaml -o %s.csv --summary %s.json", name, name, name);
  int rc = run(args);
  if (rc) {
    printf("%s: plan exit %d\n%s", name, rc, out);
    return NAN;
  }
  snprintf(args, sizeof args,
           "simulate %s.csv --arm %s --scheme genalpha --dt 0.0005 --settle 3 --json", name,
           true_arm_path);
  rc = run(args);
  if (rc) {
    printf("%s: simulate exit %d\n%s", name, rc, out);
    return NAN;
  }
  return json_num("residual_vibration_peak_m");
}

int main(void) {
  char arm_path[1024];
  if (cli_setup(arm_path, sizeof arm_path)) return 77;
  ea_arm_t paper, truth;
  ea_error_t e = {0};
  ea_test_true(ea_arm_load(arm_path, &paper, &e) == EA_OK, "the paper's arm file loads");
  ea_test_true(ea_tr_true_arm(arm_path, "e2e_true.yaml", 1.12, 1.2, 2.5, 0.05, &truth) == 0,
               "true arm file: EI +12 %, hand mass +20 %, I_L x2.5, damping 0.05");

  /* 1. the experiment, planned on the paper's arm */
  char spec[2048];
  snprintf(spec, sizeof spec,
           "name: e2e-experiment\narm_file: %s\ncable_lengths_m: [0.40, 0.50, 0.60]\n"
           "cable_angles_rad: [-0.5, 0.0]\nhold_s: 20\n",
           arm_path);
  write_text("e2e_spec.yaml", spec);
  int rc = run("calibrate-experiment e2e_spec.yaml -o e2e_exp.csv --json");
  ea_test_true(rc == 0 && json_num("holds") == 6, "calibrate-experiment: exit 0, 6 holds");
  printf("experiment: %g s\n", json_num("duration_s"));
  ea_traj_t tr = {0};
  ea_test_true(ea_traj_read(&tr, "e2e_exp.csv", &e) == EA_OK, "the experiment reads back");

  /* 2. the records, made by the FE transient of the true arm */
  ea_test_true(ea_tr_record_session(&tr, &paper, &truth, "e2e_rec", "record session") == 0,
               "controller simulator session on the true arm: records written");
  ea_traj_free(&tr);

  /* 3. calibrate from the paper's arm */
  char args[4096];
  glob_t g;
  ea_test_true(glob("e2e_rec/ringdown-*.csv", 0, NULL, &g) == 0 && g.gl_pathc == 5,
               "5 ring-downs (every hold after a move)");
  int off = snprintf(args, sizeof args, "calibrate e2e_rec/static.csv");
  for (size_t i = 0; i < g.gl_pathc; ++i)
    off += snprintf(args + off, sizeof args - (size_t)off, " %s", g.gl_pathv[i]);
  globfree(&g);
  snprintf(args + off, sizeof args - (size_t)off,
           " --arm %s --fix EA_c -o e2e_cal.yaml --report e2e_cal.json", arm_path);
  rc = run(args);
  printf("%s", out);
  ea_arm_t cal;
  ea_test_true(rc == 0 && ea_arm_load("e2e_cal.yaml", &cal, &e) == EA_OK,
               "calibrate: exit 0, the calibrated arm file loads");
  printf("calibrated: EI %+.3f %%, m_hand %+.3f %%, I_L %+.2f %% of the true arm\n",
         100 * (cal.EI / truth.EI - 1), 100 * (cal.m_hand / truth.m_hand - 1),
         100 * (cal.I_hand / truth.I_hand - 1));

  /* 4. plans on the paper arm and on the calibrated arm, run on the true arm */
  static const struct {
    const char *name;
    double a[2], b[2], payload_factor;
    int nominal_misses; /* the paper arm's plan leaves > 3 mm on the true arm */
  } lines[] = {
      {"paper", {0.3, -0.2}, {0.6, -0.2}, 0.0, 0},
      {"line_a", {0.68, -0.05}, {0.54, -0.55}, 0.15, 1},
      {"line_b", {0.23, -0.37}, {0.56, 0.00}, 0.08, 1},
  };
  for (size_t i = 0; i < sizeof lines / sizeof lines[0]; ++i) {
    char nom[64], cn[64], what[256];
    snprintf(nom, sizeof nom, "e2e_nominal_%s", lines[i].name);
    snprintf(cn, sizeof cn, "e2e_calibrated_%s", lines[i].name);
    const double r_nom =
        plan_on(nom, arm_path, lines[i].a, lines[i].b, lines[i].payload_factor, "e2e_true.yaml");
    const double r_cal = plan_on(cn, "e2e_cal.yaml", lines[i].a, lines[i].b,
                                 lines[i].payload_factor, "e2e_true.yaml");
    printf("%s: FE residual peak on the true arm: paper arm's plan %.3f mm, calibrated arm's "
           "plan %.3f mm\n",
           lines[i].name, 1e3 * r_nom, 1e3 * r_cal);
    snprintf(what, sizeof what, "%s: the calibrated arm's plan on the true arm: <= 1 mm",
             lines[i].name);
    ea_test_true(r_cal <= 1e-3, what);
    if (lines[i].nominal_misses) {
      snprintf(what, sizeof what, "%s: the paper arm's plan on the true arm: > 3 mm",
               lines[i].name);
      ea_test_true(r_nom > 3e-3, what);
    }
  }
  return ea_test_summary("test_calib_e2e");
}
