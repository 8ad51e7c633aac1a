/* CLI: figure -- draw any trajectory file (a plan, a replan, a recorded
 * stream) in the workspace of its load, with its time histories. */
#include "cli_impl.h"

#include <string.h>

int ea__cli_figure(int argc, char **argv) {
  const char *cmd = "figure";
  const char *traj = NULL, *out = NULL, *arm_file = NULL;
  for (int i = 1; i < argc; ++i) {
    const char *a = argv[i];
    if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
      printf("usage: elasticarm figure TRAJ.csv -o OUT.(svg|png|pdf) [--arm FILE]\n"
             "Draws a trajectory file (docs/trajectory-format.md): tip path and beam shapes\n"
             "in the workspace region of its load; cable length, angles, tension, shoulder\n"
             "torque, cable speed, angular rates and cable acceleration over time, with the\n"
             "arm file's limits near the data dashed.\n"
             "The arm is --arm, else the file's '# arm_file:' (refused when its parameters no\n"
             "longer match the file's '# arm_hash:'), else the default.\n");
      return EA_EXIT_OK;
    }
    if (!strcmp(a, "-o") || !strcmp(a, "--arm")) {
      const char *v = ea__cli_value(cmd, argc, argv, &i);
      if (!v) return EA_EXIT_USAGE;
      if (!strcmp(a, "-o"))
        out = v;
      else
        arm_file = v;
    } else if (a[0] == '-' && a[1]) {
      return ea__cli_usage_error(cmd, "unknown option '%s'", a);
    } else if (!traj) {
      traj = a;
    } else {
      return ea__cli_usage_error(cmd, "one trajectory file only ('%s' is extra)", a);
    }
  }
  if (!traj || !out) return ea__cli_usage_error(cmd, "needs TRAJ.csv and -o OUT");
  int rc = ea__cli_check_figure(cmd, out); /* extension and folder, before the work */
  if (rc) return rc;
  if ((rc = ea__cli_check_plan_pair(cmd, traj))) return rc;
  ea_traj_t tr = {0};
  ea_error_t err = {0};
  ea_status_t st = ea_traj_read(&tr, traj, &err);
  if (st) return ea__cli_fail(cmd, st, &err);
  ea_arm_t arm;
  rc = ea__cli_arm_for_traj(cmd, traj, arm_file, &tr, EA__ARM_QUIET, &arm, NULL, 0);
  ea_shooter_t *sh = NULL;
  if (!rc && (st = ea_shooter_alloc(&arm, NULL, &sh, &err))) rc = ea__cli_fail(cmd, st, &err);
  if (!rc) {
    ea_load_t load = {tr.tip_mass_kg > 0 ? tr.tip_mass_kg : arm.m_hand};
    ea_shooter_set_load(sh, &load);
    char title[700];
    snprintf(title, sizeof title, "%s (tip mass %.3g kg)", tr.task[0] ? tr.task : traj,
             load.tip_mass);
    ea_traj_figure_opts_t fo;
    ea_traj_figure_opts_default(&fo, &arm); /* the arm file's limits */
    fo.title = title;
    st = ea_traj_figure(&tr, sh, &fo, out, &err);
    if (st)
      rc = ea__cli_fail(cmd, st, &err);
    else
      printf("wrote %s\n", out);
  }
  ea_shooter_free(sh);
  ea_traj_free(&tr);
  return rc;
}
