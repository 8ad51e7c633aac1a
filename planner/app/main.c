/* elasticarm: the command-line tool. main() owns printing and exit codes;
 * the library never prints or aborts. */
#include "cli_impl.h"

#include <gsl/gsl_errno.h>
#include <stdio.h>
#include <string.h>

typedef struct {
  const char *name;
  ea__cli_fn fn;
  const char *help;
} ea__cmd_t;

static const ea__cmd_t ea__cmds[] = {
    {"statics", ea__cli_statics, "solve one static configuration (paper sec. 2)"},
    {"workspace", ea__cli_workspace, "workspace edges for payload factors (Fig. 3)"},
    {"torque-map", ea__cli_torque_map, "shoulder torque and tension over (L_c, alpha)"},
    {"path", ea__cli_path, "admissibility of a straight tip path (Fig. 4, eqs. 18-20)"},
    /* EA_CLI_TABLE_BEGIN (other subcommands add a line here) */
    {"stream", ea__cli_stream, "send a trajectory to the arm's controller in real time"},
    {"controller-sim", ea__cli_controller_sim, "simulated controller for the streamer's protocol"},
    {"plan", ea__cli_plan, "plan an admissible trajectory for a task spec (YAML)"},
    {"frequencies", ea__cli_frequencies,
     "FE natural frequencies at a configuration, or the Fig. 5 sweep"},
    {"simulate", ea__cli_simulate, "FE transient of a trajectory: tip history, residual vibration"},
    {"study", ea__cli_study, "batch studies of payload and design: grid, threads, shards, resume"},
    {"figure", ea__cli_figure, "draw a trajectory file (plan) to SVG/PNG/PDF"},
    {"calibrate-experiment", ea__cli_calibrate_experiment,
     "identification experiment for calibrate: holds at configurations, joined by moves"},
    {"calibrate", ea__cli_calibrate,
     "fit the arm file to measurement records (docs/calibration.md)"},
    /* EA_CLI_TABLE_END */
};

static void ea__usage(FILE *fp) {
  fprintf(fp, "usage: elasticarm COMMAND [options]   (elasticarm COMMAND --help)\n"
              "       elasticarm --version\n\n"
              "Models a cable-actuated elastica manipulator arm and plans its motions.\n\n"
              "commands:\n");
  for (size_t i = 0; i < sizeof ea__cmds / sizeof *ea__cmds; ++i)
    fprintf(fp, "  %-14s %s\n", ea__cmds[i].name, ea__cmds[i].help);
  fprintf(fp,
          "\ndefault arm file (without --arm or a task's arm_file):\n  %s\n  found as: %s\n"
          "  (looked up in order: $EA_ARM_FILE, ./data/elasticarm.yaml,\n"
          "  <folder of the executable>/../share/elasticarm/elasticarm.yaml,\n"
          "  <folder of the executable>/../data/elasticarm.yaml, %s)\n",
          ea__cli_default_arm(), ea__cli_default_arm_how(),
          EA_INSTALL_DATADIR "/elasticarm/elasticarm.yaml");
}

int main(int argc, char **argv) {
  gsl_set_error_handler_off(); /* every GSL return is checked */
  if (argc < 2) {
    ea__usage(stderr);
    return EA_EXIT_USAGE;
  }
  if (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h") || !strcmp(argv[1], "help")) {
    ea__usage(stdout);
    return EA_EXIT_OK;
  }
  if (!strcmp(argv[1], "--version")) {
    printf("elasticarm %s\n", ea_version()); /* project() in CMakeLists.txt */
    return EA_EXIT_OK;
  }
  for (size_t i = 0; i < sizeof ea__cmds / sizeof *ea__cmds; ++i)
    if (!strcmp(argv[1], ea__cmds[i].name)) return ea__cmds[i].fn(argc - 1, argv + 1);
  fprintf(stderr, "elasticarm: unknown command '%s'\n", argv[1]);
  ea__usage(stderr);
  return EA_EXIT_USAGE;
}
