/* CLI: figure -- draw any trajectory file (a plan, a replan, a recorded
 * stream) in the workspace of its load, with its time histories. */
#include "cli_impl.h"

#include <string.h>

int ea__cli_figure(int argc, char **argv) {
  const char *cmd = "figure";
  const char *traj = NULL, *out = NULL, *arm_file = NULL;
  static const ea__cli_opt_t opts[] = {
      {"help", 0, 'h'}, {"output", 1, 'o'}, {"figure", 1, 0}, {"arm", 1, 0}, {NULL, 0, 0}};
  ea__cli_args_t g;
  ea__cli_args_init(&g, cmd, argc, argv, opts);
  int r;
  while ((r = ea__cli_args_next(&g)) > 0) {
    const char *a = g.opt;
    if (!a) {
      if (traj) return ea__cli_usage_error(cmd, "one trajectory file only ('%s' is extra)", g.arg);
      traj = g.arg;
    } else if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
      printf("usage: elasticarm figure TRAJ.csv --figure OUT.(svg|png|pdf) [--arm FILE]\n"
             "Draws a trajectory file (docs/trajectory-format.md): tip path and beam shapes\n"
             "in the workspace region of its load (and, when the base turns, the tip path\n"
             "seen from above); cable length, angles, tension, shoulder torque, cable speed,\n"
             "angular rates and cable acceleration over time, with the arm file's limits near\n"
             "the data dashed.\n"
             "  --figure OUT   the figure (.svg, .png or .pdf); -o OUT and --output OUT\n"
             "                 are the same\n"
             "  --arm FILE     the arm: --arm, else the file's '# arm_file:' (refused when its\n"
             "                 parameters no longer match the file's '# arm_hash:'), else the\n"
             "                 default\n");
      return EA_EXIT_OK;
    } else if (!strcmp(a, "--arm")) {
      arm_file = g.arg;
    } else { /* -o, --output, --figure */
      if (out && strcmp(out, g.arg))
        return ea__cli_usage_error(cmd, "two figure paths ('%s' and '%s')", out, g.arg);
      out = g.arg;
    }
  }
  if (r < 0) return EA_EXIT_USAGE;
  if (!traj || !out) return ea__cli_usage_error(cmd, "needs TRAJ.csv and --figure OUT (or -o OUT)");
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
