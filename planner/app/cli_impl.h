/* Private: the CLI's subcommands and their shared helpers. Each subcommand
 * lives in planner/cli_<name>.c and is listed in main.c's table. */
#ifndef EA_CLI_IMPL_H
#define EA_CLI_IMPL_H

#include "ea_planner.h"
#include "ea_problems.h"
#include "ea_simulate.h"
#include "ea_stream.h"
#include "ea_util.h"
#include "figure_impl.h"

#include <getopt.h>

/** A subcommand: returns the process exit code (0 ok, 1 failure or not
 *  converged / inadmissible, 2 usage error). Prints only to stdout/stderr. */
typedef int (*ea__cli_fn)(int argc, char **argv);

int ea__cli_statics(int argc, char **argv);
int ea__cli_workspace(int argc, char **argv);
int ea__cli_torque_map(int argc, char **argv);
int ea__cli_path(int argc, char **argv);
/* EA_CLI_DECL_BEGIN (other subcommands add their prototypes here) */
int ea__cli_stream(int argc, char **argv);
int ea__cli_controller_sim(int argc, char **argv);
int ea__cli_plan(int argc, char **argv);
int ea__cli_frequencies(int argc, char **argv);
int ea__cli_simulate(int argc, char **argv);
int ea__cli_study(int argc, char **argv);
int ea__cli_figure(int argc, char **argv);
int ea__cli_calibrate_experiment(int argc, char **argv);
int ea__cli_calibrate(int argc, char **argv);
/* EA_CLI_DECL_END */

/** Exit codes: 0 done; 1 failure (not converged, infeasible, inadmissible, an output not
 *  written); 2 usage or input error; 3 `plan --verify`: the plan and its summary were
 *  written but the FE transient of the written trajectory failed the verification (the
 *  transient failed, the cable went slack or below the tension limit, the residual
 *  vibration above the task's bound). */
enum { EA_EXIT_OK = 0, EA_EXIT_FAIL = 1, EA_EXIT_USAGE = 2, EA_EXIT_VERIFY = 3 };

/** Print "elasticarm CMD: message" to stderr; returns EA_EXIT_USAGE. */
int ea__cli_usage_error(const char *cmd, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;
/** Print "elasticarm CMD: error: msg" for a failed call; returns EA_EXIT_FAIL
 *  (EA_EXIT_USAGE for EA_ERR_ARG/EA_ERR_INPUT/EA_ERR_PARSE/EA_ERR_IO). */
int ea__cli_fail(const char *cmd, ea_status_t st, const ea_error_t *err);

/** Print "elasticarm CMD: error: out of memory (what)"; returns EA_EXIT_FAIL (not a
 *  usage error). */
int ea__cli_oom(const char *cmd, const char *what);

/** Parse a finite double option value: "--flag" named in the error. */
int ea__cli_double(const char *cmd, const char *flag, const char *text, double lo, double hi,
                   double *out);
/** Parse an integer option value in [lo, hi]. */
int ea__cli_int(const char *cmd, const char *flag, const char *text, long lo, long hi, long *out);
/** Parse "a,b" (two finite doubles). */
int ea__cli_pair(const char *cmd, const char *flag, const char *text, double out[2]);
/** Parse a list "a,b,c" or a range "start:step:stop" into a malloc'd array. Returns 0,
 *  EA_EXIT_USAGE (bad text) or EA_EXIT_FAIL (out of memory), having said which. */
int ea__cli_list(const char *cmd, const char *flag, const char *text, double **out, int *n);
/** One option of a subcommand for ea__cli_args_next: its long name without the leading
 *  "--", whether it takes a value, and its one-letter form ('o' for -o; 0: none). */
typedef struct ea__cli_opt {
  const char *name;
  int value;
  char letter;
} ea__cli_opt_t;
/** Most options of one subcommand. */
#define EA__CLI_MAX_OPTS 64

/** A subcommand's command line read by getopt_long (the C library's): "--name VALUE",
 *  "--name=VALUE", "-o VALUE", "-oVALUE", unambiguous abbreviations ("--kn" for "--knots"),
 *  "--" before operands; a value may start with '-' ("--tip -0.1,0.3"). Operands come in
 *  order among the options. */
typedef struct ea__cli_args {
  const char *cmd;
  int argc;
  char **argv;
  const ea__cli_opt_t *opts;
  int nopts;
  const char *opt; /**< the option as "--name" (its full name, also when abbreviated) or
                        "-o"; NULL: an operand */
  const char *arg; /**< the option's value (NULL for a flag) or the operand */
  int rest;        /**< 1: past the options ("--" or the end): operands only */
  char buf[80];
} ea__cli_args_t;

/** 1 when argv[1..argc-1] has -h, --help or an abbreviation of it ("--he"), for the
 *  commands that print their help before reading the other options. */
int ea__cli_help_asked(int argc, char **argv);

/** Start reading argv[1..argc-1] with the options opts (ended by a NULL name). */
void ea__cli_args_init(ea__cli_args_t *g, const char *cmd, int argc, char **argv,
                       const ea__cli_opt_t *opts);
/** The next option or operand into g->opt, g->arg: 1; 0 at the end; -1 after a usage
 *  error it printed (an unknown or ambiguous option, a missing value, a value given to a
 *  flag). */
int ea__cli_args_next(ea__cli_args_t *g);

/** Default arm file, the first of: $EA_ARM_FILE; ./data/elasticarm.yaml;
 *  <folder of the executable>/../share/elasticarm/elasticarm.yaml (installed);
 *  <folder of the executable>/../data/elasticarm.yaml (a build tree inside the
 *  source tree); the install location compiled in (EA_INSTALL_DATADIR). Only
 *  the command-line tool knows it: the library takes arm files as arguments. */
const char *ea__cli_default_arm(void);
/** How ea__cli_default_arm() found it ("$EA_ARM_FILE", ...), for --help. */
const char *ea__cli_default_arm_how(void);
/** Load the arm file (path NULL = default). Prints errors; returns exit code. */
int ea__cli_load_arm(const char *cmd, const char *path, ea_arm_t *arm);

/** Check a figure path before the work: known extension (.svg, .png, .pdf)
 *  and a writable directory (a temporary is created there and removed).
 *  Prints the error; returns 0 or the exit code. */
int ea__cli_check_figure(const char *cmd, const char *path);
/** Check an output path before the work (not "-"): its directory can take a
 *  temporary (created and removed). Also removes the temporaries a killed run
 *  left beside it. Prints the error; returns 0 or the exit code. */
int ea__cli_check_output(const char *cmd, const char *path);
/** A safe file name from a free-form name (a task's `name`): one path
 *  component, letters, digits, '-', '_', '.', '+' only (others become '_'),
 *  no leading '.', at most 100 characters; fallback if nothing is left. */
void ea__cli_safe_name(const char *name, const char *fallback, char *buf, size_t len);

/** ea__cli_arm_for_traj flags. */
enum {
  EA__ARM_QUIET = 1, /**< do not say which arm file it took from the trajectory */
  EA__ARM_STRICT = 2 /**< refuse an --arm that differs from the planned arm (stream) */
};
/** The arm for a trajectory file traj_path (stream, figure, simulate). Without arm_opt:
 *  the file's '# arm_file:' (resolved by ea_traj_read), else the default arm; refused
 *  (exit 2, naming the path and both hashes) when its parameters' hash (ea_arm_hash)
 *  differs from the trajectory's '# arm_hash:', or when it cannot be loaded; a trajectory
 *  without '# arm_hash:' (an older file) is used with a note. With arm_opt: that arm;
 *  when it differs from the planned one (by the hash, else by the recorded file's
 *  parameters) EA__ARM_STRICT refuses it (exit 2, naming both hashes and the first
 *  parameter that differs if known), otherwise a note names both hashes. used (may be NULL)
 *  gets the file loaded ("" = the default). Prints errors and notes; returns 0 or the exit
 *  code. */
int ea__cli_arm_for_traj(const char *cmd, const char *traj_path, const char *arm_opt,
                         const ea_traj_t *tr, int flags, ea_arm_t *arm, char *used,
                         size_t used_len);

/** A plan's trajectory and its summary beside it (TRAJ with .json) must come from the same
 *  run: when the trajectory has a '# run_id:' line and the summary exists, the summary's
 *  "run_id" must be the same (read under a shared lock of TRAJ.lock, the lock `plan` holds
 *  while it renames the pair). Prints the error; returns 0 or EA_EXIT_USAGE. */
int ea__cli_check_plan_pair(const char *cmd, const char *traj_path);

/** Progress of a long job on stderr: nothing during its first second, then a line at most
 *  every 0.2 s on a terminal (one line, rewritten) or every 2 s otherwise (a line each). The
 *  library reports through callbacks; only this prints. */
typedef struct ea__cli_progress {
  const char *cmd;
  int on;      /**< 0: --quiet */
  int tty;     /**< stderr is a terminal */
  double t0;   /**< [s] the command's start (ea__mono_s) */
  double last; /**< [s] the last line's time, 0: none yet */
  int open;    /**< a terminal line is open (not ended by a newline) */
} ea__cli_progress_t;
/** Start the clock; on = 0 silences every line. */
void ea__cli_progress_init(ea__cli_progress_t *p, const char *cmd, int on);
/** Say "elasticarm CMD: <fmt>" when due (always when force, once past the first second). */
void ea__cli_progress(ea__cli_progress_t *p, int force, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;
/** End an open terminal line (before other output). */
void ea__cli_progress_end(ea__cli_progress_t *p);
/** [s] since ea__cli_progress_init. */
double ea__cli_progress_elapsed(const ea__cli_progress_t *p);
/** The settings' FE progress callback (data: an ea__cli_progress_t, what: "FE transient"). */
void ea__cli_progress_fe(void *data, double t_s, double t_end_s);

/** Payload options shared by commands: --payload-factor G | --payload-kg M. */
typedef struct ea__cli_payload {
  int given; /**< 0 none, 1 factor, 2 kg */
  double value;
} ea__cli_payload_t;
/** Tip mass m_L for the payload option. */
double ea__cli_tip_mass(const ea_arm_t *arm, const ea__cli_payload_t *p);

#endif
