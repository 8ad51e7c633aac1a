/* The CLI as a user runs it: exit codes, messages for bad input, JSON keys,
 * figures, atomic outputs. Values are checked against an independent
 * re-solve through the library with a different problem statement. */
#include "ea_planner.h"
#include "ea_problems.h"
#include "figure_impl.h"
#include "ea_test.h"
#include "ea_test_cli.h"

#include <dirent.h>
#include <fcntl.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

static void expect_usage(const char *args, const char *want, const char *what) {
  int rc = run(args);
  ea_test_true(rc == 2 && strstr(out, want) != NULL, what);
  printf("  $ elasticarm %s -> exit %d: %.200s\n", args, rc, out);
}

static int exists(const char *path) {
  struct stat sb;
  return stat(path, &sb) == 0;
}

/* The whole of a small file into buf ("" if unreadable). */
static void slurp(const char *path, char *buf, size_t cap) {
  buf[0] = '\0';
  FILE *fp = fopen(path, "r");
  if (!fp) return;
  const size_t k = fread(buf, 1, cap - 1, fp);
  buf[k] = '\0';
  fclose(fp);
}

static void touch(const char *path, const char *text) {
  FILE *fp = fopen(path, "w");
  if (!fp) return;
  fputs(text, fp);
  fclose(fp);
}

/* A pid that no longer runs: a child that exited and was reaped. */
static pid_t dead_pid(void) {
  const pid_t pid = fork();
  if (pid == 0) _exit(0);
  waitpid(pid, NULL, 0);
  return pid;
}

/* Figures: checked before the work, never drawn on stdout (issue: a figure
 * that could not be written made gnuplot dump the SVG into --json output,
 * exit 0). */
static void test_figures(const char *arm_path) {
  char args[1400];
  touch("test_cli_blocker", "");
  snprintf(args, sizeof args,
           "statics --cable-length 0.45 --cable-angle-deg -25 --no-stability --arm %s --json "
           "--figure test_cli_blocker/x.svg",
           arm_path);
  int rc = run(args);
  ea_test_true(rc == 2 && !strstr(out, "<svg") && !strstr(out, "\"status\"") &&
                   strstr(out, "test_cli_blocker/x.svg"),
               "statics: unwritable figure refused before the work (exit 2, no SVG on stdout)");
  printf("  -> %.300s\n", out);
  snprintf(args, sizeof args,
           "statics --cable-length 0.45 --cable-angle-deg -25 --no-stability --arm %s "
           "--figure test_cli_fig.txt",
           arm_path);
  rc = run(args);
  ea_test_true(rc == 2 && strstr(out, "test_cli_fig.txt: figure must end in"),
               "statics: unknown figure extension refused before the work (exit 2)");
  snprintf(args, sizeof args,
           "torque-map --arm %s --cable-lengths 0.3 --cable-angles-deg 0 --csv test_cli_tm1.csv "
           "--figure test_cli_blocker/tm.png",
           arm_path);
  remove("test_cli_tm1.csv");
  rc = run(args);
  ea_test_true(rc == 2 && !exists("test_cli_tm1.csv"),
               "torque-map: unwritable figure refused before anything is written");
  snprintf(args, sizeof args,
           "statics --cable-length 0.45 --cable-angle-deg -25 --no-stability --arm %s --json "
           "--figure test_cli_fig/st.svg",
           arm_path);
  remove("test_cli_fig/st.svg");
  rc = run(args);
  struct stat sb;
  ea_test_true(
      rc == 0 && !strstr(out, "<svg") && stat("test_cli_fig/st.svg", &sb) == 0 && sb.st_size > 1000,
      "statics --json --figure: figure in its file (folder created), JSON alone on stdout");

  /* gnuplot failing after the check (its temporary replaced by a folder):
   * an error, and nothing on our stdout. */
  ea_plot_t *pl = NULL;
  ea_error_t err = {0};
  mkdir("test_cli_gp", 0777);
  ea_status_t st = ea_plot_open(&pl, "test_cli_gp/f.svg", 0, 0, &err);
  char tmpdir[600] = "";
  DIR *d = opendir("test_cli_gp");
  struct dirent *e;
  while (d && (e = readdir(d)) != NULL)
    if (!strncmp(e->d_name, "f.svg.tmp", 9))
      snprintf(tmpdir, sizeof tmpdir, "test_cli_gp/%.500s", e->d_name);
  if (d) closedir(d);
  ea_test_true(st == EA_OK && tmpdir[0], "ea_plot_open makes its temporary beside the target");
  if (st == EA_OK) {
    if (tmpdir[0]) {
      unlink(tmpdir);
      mkdir(tmpdir, 0777);
    }
    ea_plot_cmd(pl, "plot x");
    fflush(stdout);
    const int saved = dup(STDOUT_FILENO);
    const int fd = open("test_cli_gp_stdout.txt", O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(fd, STDOUT_FILENO);
    close(fd);
    st = ea_plot_close(pl, &err);
    fflush(stdout);
    dup2(saved, STDOUT_FILENO);
    close(saved);
    const int quiet = stat("test_cli_gp_stdout.txt", &sb) == 0 && sb.st_size == 0;
    printf("  gnuplot failure: %s; %lld bytes on stdout\n", err.msg, (long long)sb.st_size);
    ea_test_true(st == EA_ERR_IO && quiet && !exists("test_cli_gp/f.svg") &&
                     strstr(err.msg, "gnuplot failed"),
                 "gnuplot failure: EA_ERR_IO with gnuplot's message, stdout untouched");
  }
  if (tmpdir[0]) rmdir(tmpdir);
  remove("test_cli_gp_stdout.txt");
  remove("test_cli_fig/st.svg");
  rmdir("test_cli_fig");
  rmdir("test_cli_gp");
}

/* statics: --guess-deg (listed in --help) works; the arm's limits are
 * checked; a tip at the cable root is refused. */
static void test_statics_checks(const char *arm_path) {
  ea_arm_t arm;
  ea_status_t ast = ea_arm_load(arm_path, &arm, NULL);
  ea_test_true(ast == EA_OK, "arm file loads");
  if (ast) return;
  char args[1400];
  /* Warm start from a guess near the answer: the library's tip solve. */
  ea_shooter_t *sh = NULL;
  ea_shooter_alloc(&arm, NULL, &sh, NULL);
  ea_load_t load = {arm.m_hand};
  ea_shooter_set_load(sh, &load);
  const double a = -25.0 * M_PI / 180;
  ea_statics_problem_t pr =
      ea_statics_problem_tip(arm.x_c + 0.45 * cos(a), arm.y_c + 0.45 * sin(a));
  ea_statics_solution_t sol;
  const ea_status_t sst = ea_statics_solve(sh, &pr, NULL, NULL, &sol, NULL);
  ea_shooter_free(sh);
  ea_test_true(sst == EA_OK, "library tip solve");
  snprintf(args, sizeof args,
           "statics --cable-length 0.45 --cable-angle-deg -25 --no-stability --arm %s --json "
           "--guess-deg %.3f,%.3f,%.3f,%.3f",
           arm_path, sol.p[EA_P_ALPHA] * 180 / M_PI + 1, sol.p[EA_P_TENSION] * 1.05,
           sol.p[EA_P_THETA0] * 180 / M_PI + 2, sol.p[EA_P_KAPPA0] * 0.95);
  int rc = run(args);
  ea_test_true(rc == 0 && strstr(out, "\"branch\": \"warm start\""),
               "statics --guess-deg accepted: warm start");
  ea_test_rel(json_num("tension_N"), sol.p[EA_P_TENSION], 1e-8,
              "--guess-deg: tension vs library tip solve");
  ea_test_rel(json_num("theta0_rad"), sol.p[EA_P_THETA0], 1e-8,
              "--guess-deg: theta0 vs library tip solve");
  run("statics --help");
  ea_test_true(strstr(out, "--guess-deg") != NULL, "statics --help lists --guess-deg");

  /* Below the spool's minimum cable length (the arm file's value). */
  const double Lshort = 0.8 * arm.act.cable_length_min;
  snprintf(args, sizeof args,
           "statics --cable-length %.6f --cable-angle-deg -20 --no-stability --arm %s --json",
           Lshort, arm_path);
  rc = run(args);
  ea_test_true(rc == 1 && strstr(out, "\"admissible\": false") &&
                   strstr(out, "below the minimum") && strstr(out, "\"status\": \"EA_OK\""),
               "statics below the spool minimum: solved, flagged inadmissible, exit 1");
  printf("  -> %.200s\n", strstr(out, "\"admissible\"") ? strstr(out, "\"admissible\"") : out);
  snprintf(args, sizeof args,
           "statics --cable-length %.6f --cable-angle-deg -20 --no-stability --arm %s", Lshort,
           arm_path);
  rc = run(args);
  ea_test_true(rc == 1 && strstr(out, "admissible        NO: cable length"),
               "statics text output says why it is not admissible");
  snprintf(args, sizeof args,
           "statics --cable-length 0.45 --cable-angle-deg -25 --no-stability --arm %s --json",
           arm_path);
  rc = run(args);
  ea_test_true(rc == 0 && strstr(out, "\"admissible\": true"),
               "statics inside the limits: admissible, exit 0");

  /* A tip at the cable root: no cable, no angle. */
  snprintf(args, sizeof args, "statics --tip %.17g,%.17g --no-stability --arm %s --json", arm.x_c,
           arm.y_c, arm_path);
  rc = run(args);
  ea_test_true(rc == 2 && strstr(out, "cable root") && !strstr(out, "EA_OK"),
               "statics --tip at the cable root refused (exit 2)");
  printf("  -> %.200s\n", out);
}

/* A paper-line task with the given name (YAML-quoted), knots 20. */
static void write_task(const char *path, const char *name, const char *arm_path, int feasible) {
  FILE *fp = fopen(path, "w");
  if (!fp) return;
  fprintf(fp, "name: \"%s\"\narm_file: %s\npayload_factor: 0.0\n", name, arm_path);
  if (feasible)
    fputs("start:\n  tip: [0.3, -0.2]\ngoal:\n  tip: [0.6, -0.2]\n", fp);
  else /* the line passes closer to the cable root than the shortest cable */
    fputs("start:\n  tip: [0.34, 0.08]\ngoal:\n  tip: [0.34, -0.30]\n", fp);
  fputs("path: line\nobjective: min_time\nknots: 20\n", fp);
  fclose(fp);
}

/* plan: outputs written so that a summary never sits beside a trajectory it
 * does not describe; killed runs' temporaries cleaned; names made safe. */
static void test_plan_outputs(const char *arm_path) {
  char buf[8192];
  write_task("test_cli_ok.yaml", "ok", arm_path, 1);
  write_task("test_cli_inf.yaml", "inf", arm_path, 0);
  const char *o[] = {"test_cli_p.csv", "test_cli_p.json", "test_cli_p.svg"};
  for (int i = 0; i < 3; ++i)
    remove(o[i]);
  int rc = run("plan test_cli_ok.yaml -o test_cli_p.csv --figure test_cli_p.svg --quiet");
  ea_test_true(rc == 0 && exists(o[0]) && exists(o[1]) && exists(o[2]),
               "plan: trajectory, summary, figure written");
  /* The same outputs, a failing plan: the earlier trajectory and figure go. */
  rc = run("plan test_cli_inf.yaml -o test_cli_p.csv --figure test_cli_p.svg --quiet --json");
  slurp(o[1], buf, sizeof buf);
  ea_test_true(rc == 1 && !exists(o[0]) && !exists(o[2]) &&
                   strstr(buf, "\"status\": \"EA_ERR_INFEASIBLE\"") &&
                   strstr(out, "\"status\": \"EA_ERR_INFEASIBLE\""),
               "failed plan: failure summary (also on --json), earlier trajectory and figure "
               "removed");

  /* The trajectory cannot be written (its name is a folder): no EA_OK summary. */
  mkdir("test_cli_dir.csv", 0777);
  touch("test_cli_dir.csv/keep", "x");
  remove("test_cli_dir.json");
  rc = run("plan test_cli_ok.yaml -o test_cli_dir.csv --quiet");
  slurp("test_cli_dir.json", buf, sizeof buf);
  ea_test_true(rc == 1 && !strstr(buf, "\"EA_OK\"") && strstr(buf, "\"status\": \"EA_ERR_IO\"") &&
                   strstr(buf, "could not be written"),
               "trajectory not written: the summary says so (EA_ERR_IO), never EA_OK");
  printf("  -> %.300s\n", out);
  remove("test_cli_dir.csv/keep");
  rmdir("test_cli_dir.csv");
  remove("test_cli_dir.json");
  DIR *d = opendir(".");
  struct dirent *e;
  int left = 0;
  while (d && (e = readdir(d)) != NULL)
    if (strstr(e->d_name, "test_cli_dir.") && strstr(e->d_name, ".tmp")) ++left;
  if (d) closedir(d);
  ea_test_true(left == 0, "no temporaries left after the failed write");

  /* Temporaries of a killed run (dead pid) are removed, a live one's kept. */
  char stale1[128], stale2[128], live[128];
  const long dp = (long)dead_pid();
  snprintf(stale1, sizeof stale1, "test_cli_k.csv.tmp%ld.traj", dp);
  snprintf(stale2, sizeof stale2, "test_cli_k.json.tmp%ld.json.tmp%ld.Ab12Cd", dp, dp);
  snprintf(live, sizeof live, "test_cli_k.csv.tmp%ld.Xy34Zw", (long)getpid());
  touch(stale1, "x");
  touch(stale2, "x");
  touch(live, "x");
  rc = run("plan test_cli_ok.yaml -o test_cli_k.csv --quiet");
  ea_test_true(rc == 0 && !exists(stale1) && !exists(stale2) && exists(live),
               "plan: a killed run's temporaries removed, a live process's kept");
  remove(live);
  remove("test_cli_k.csv");
  remove("test_cli_k.json");

  /* The task's name is free text, not a path. */
  write_task("test_cli_name.yaml", "../test_cli_evil", arm_path, 1);
  remove("../test_cli_evil.csv");
  remove("../test_cli_evil.json");
  rc = run("plan test_cli_name.yaml --quiet");
  ea_test_true(rc == 0 && !exists("../test_cli_evil.csv") && exists("test_cli_evil.csv") &&
                   exists("test_cli_evil.json"),
               "name '../test_cli_evil': default outputs in the current folder, not above");
  remove("../test_cli_evil.csv");
  remove("../test_cli_evil.json");
  remove("test_cli_evil.csv");
  remove("test_cli_evil.json");
  write_task("test_cli_name.yaml", "", arm_path, 1);
  remove(".csv");
  remove(".json");
  rc = run("plan test_cli_name.yaml --quiet");
  ea_test_true(rc == 0 && !exists(".csv") && exists("plan.csv"),
               "empty name: 'plan.csv', not the hidden '.csv'");
  remove(".csv");
  remove(".json");
  remove("plan.csv");
  remove("plan.json");

  /* An unwritable figure: refused before the solve, nothing written. */
  remove(o[0]);
  remove(o[1]);
  rc = run("plan test_cli_ok.yaml -o test_cli_p.csv --figure test_cli_blocker/p.svg --quiet");
  ea_test_true(rc == 2 && !exists(o[0]) && !exists(o[1]),
               "plan: unwritable figure refused before the solve, nothing written");
  for (int i = 0; i < 3; ++i)
    remove(o[i]);
  remove("test_cli_ok.yaml");
  remove("test_cli_inf.yaml");
  remove("test_cli_name.yaml");
}

/* Text from a user goes into gnuplot scripts quoted: a trajectory whose task
 * name holds both quotes and a backslash, drawn to a path with a quote (before:
 * the title's double quote ended gnuplot's string, exit 1, no figure). */
static void test_figure_quotes(void) {
  const char *src = getenv("EA_SOURCE_DIR");
  char args[2048], line[512];
  snprintf(args, sizeof args,
           "plan %s/problems/examples/paper-line.yaml -o test_cli_q.csv --summary test_cli_q.json",
           src);
  int rc = run(args);
  FILE *in = fopen("test_cli_q.csv", "r"), *o = fopen("test_cli_q2.csv", "w");
  while (in && o && fgets(line, sizeof line, in))
    fputs(!strncmp(line, "# task:", 7) ? "# task: it's a \"quoted\" task \\ name\n" : line, o);
  if (in) fclose(in);
  if (o) fclose(o);
  remove("test_cli_q'.svg");
  rc = rc ? rc : run("figure test_cli_q2.csv -o \"test_cli_q'.svg\"");
  char svg[1 << 16];
  slurp("test_cli_q'.svg", svg, sizeof svg);
  ea_test_true(rc == 0 && strstr(svg, "quoted") != NULL,
               "figure: a task name with quotes and a backslash, a path with a quote");
  printf("  exit %d: %.300s\n", rc, out);
  remove("test_cli_q.csv");
  remove("test_cli_q2.csv");
  remove("test_cli_q.json");
  remove("test_cli_q'.svg");
}

/* A shell command line (its output in out); the exit code. */
static int sh(const char *line) {
  char cmd[4096];
  snprintf(cmd, sizeof cmd, "%s 2>&1", line);
  FILE *p = popen(cmd, "r");
  if (!p) return -1;
  const size_t n = fread(out, 1, sizeof out - 1, p);
  out[n] = '\0';
  const int rc = pclose(p);
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

/* The default arm file: looked up in the documented order and named, with how it
 * was found, by elasticarm --help (only the CLI knows it). */
static void test_default_arm(const char *arm_path) {
  char dir[] = "/tmp/ea_test_arm_lookup_XXXXXX", line[3000], want[PATH_MAX + 100],
       real_arm[PATH_MAX];
  if (!mkdtemp(dir) || !realpath(arm_path, real_arm)) {
    ea_test_true(0, "default arm: temporary folder");
    return;
  }
  /* 1. $EA_ARM_FILE first; a missing file is then an error naming it */
  snprintf(line, sizeof line, "cd %s && EA_ARM_FILE=/nonexistent/arm.yaml %s --help", dir, bin);
  int rc = sh(line);
  ea_test_true(rc == 0 && strstr(out, "  /nonexistent/arm.yaml\n  found as: $EA_ARM_FILE"),
               "default arm: $EA_ARM_FILE first, said by --help");
  snprintf(line, sizeof line,
           "cd %s && EA_ARM_FILE=/nonexistent/arm.yaml %s statics --cable-length 0.45 "
           "--cable-angle-deg -25",
           dir, bin);
  rc = sh(line);
  ea_test_true(rc == 2 && strstr(out, "/nonexistent/arm.yaml"),
               "default arm: an unreadable $EA_ARM_FILE is a usage error naming it");
  /* 2. the build tree: <folder of the executable>/../data (this build is inside the
   * source tree when that file is the source's arm file) */
  char bdir[PATH_MAX], cand[PATH_MAX + 64], real_cand[PATH_MAX];
  snprintf(bdir, sizeof bdir, "%s", bin);
  char *slash = strrchr(bdir, '/');
  if (slash) *slash = '\0';
  snprintf(cand, sizeof cand, "%s/../data/elasticarm.yaml", slash ? bdir : ".");
  if (realpath(cand, real_cand) && !strcmp(real_cand, real_arm)) {
    snprintf(line, sizeof line, "cd %s && env -u EA_ARM_FILE %s --help", dir, bin);
    rc = sh(line);
    snprintf(want, sizeof want, "  %s\n  found as: data/ beside the folder of the executable",
             real_arm);
    ea_test_true(rc == 0 && strstr(out, want) != NULL,
                 "default arm: a build tree finds the source's data/ (no ./data here)");
  } else {
    printf("(build folder not directly inside the source tree: build-tree lookup not tested)\n");
  }
  /* 3. ./data/elasticarm.yaml of the working directory before the executable's */
  snprintf(line, sizeof line,
           "mkdir -p %s/data && cp %s %s/data/ && cd %s && env -u EA_ARM_FILE %s --help", dir,
           arm_path, dir, dir, bin);
  rc = sh(line);
  ea_test_true(rc == 0 && strstr(out, "  data/elasticarm.yaml\n  found as: ./data/ of the working "
                                      "directory"),
               "default arm: ./data/elasticarm.yaml of the working directory");
  /* 4. an installed layout: PREFIX/bin/elasticarm finds PREFIX/share/elasticarm/ */
  snprintf(line, sizeof line,
           "mkdir -p %s/inst/bin %s/inst/share/elasticarm && cp %s %s/inst/bin/elasticarm && cp "
           "%s %s/inst/share/elasticarm/ && cd %s/inst && env -u EA_ARM_FILE ./bin/elasticarm "
           "--help",
           dir, dir, bin, dir, arm_path, dir, dir);
  rc = sh(line);
  ea_test_true(rc == 0 && strstr(out, "/inst/share/elasticarm/elasticarm.yaml\n  found as: "
                                      "share/elasticarm/ beside the folder of the executable"),
               "default arm: an installed executable finds ../share/elasticarm/");
  snprintf(line, sizeof line,
           "cd %s/inst && env -u EA_ARM_FILE ./bin/elasticarm statics --cable-length 0.45 "
           "--cable-angle-deg -25 --json",
           dir);
  rc = sh(line);
  ea_test_true(rc == 0 && strstr(out, "\"status\": \"EA_OK\""),
               "default arm: the installed executable solves with it");
  snprintf(line, sizeof line, "rm -rf %s", dir);
  sh(line);
}

/* The cache file in dir (the one rom-*.bin), in path; 0 if found. */
static int find_rom(const char *dir, char *path, size_t len) {
  DIR *d = opendir(dir);
  struct dirent *de;
  int found = 1;
  while (d && (de = readdir(d)))
    if (!strncmp(de->d_name, "rom-", 4) && strstr(de->d_name, ".bin")) {
      snprintf(path, len, "%s/%s", dir, de->d_name);
      found = 0;
    }
  if (d) closedir(d);
  return found;
}

/* The reduced-model cache seen from `plan --verify` of the at-rest paper line ($EA_CACHE_DIR
 * in a temp folder): one exponent bit flipped in each of 140 stored values (the key intact)
 * is detected, the table rebuilt and a warning printed, and the plan and its FE check are
 * those of a fresh cache (duration and measured residual equal); a FIFO at the cache path
 * does not hang the plan (run under timeout 120); a cache that cannot be written is a
 * warning, exit 0. */
static void test_rom_cache(const char *src) {
  char dir[] = "/tmp/ea_test_cli_cache_XXXXXX", args[1400], rom[600], plain[600], cache2[700];
  if (!mkdtemp(dir)) {
    ea_test_true(0, "temp dir");
    return;
  }
  const char *old = getenv("EA_CACHE_DIR");
  char saved[1024] = "";
  if (old) snprintf(saved, sizeof saved, "%s", old);
  setenv("EA_CACHE_DIR", dir, 1);
  snprintf(args, sizeof args,
           "plan %s/problems/examples/paper-line-rest.yaml -o %s/p.csv --verify --json", src, dir);
  int rc = run(args);
  const double d0 = json_num("duration_s"), m0 = json_num("measured_residual_peak_m");
  ea_test_true(rc == 0 && strstr(out, "\"model_from_cache\": false") && !strstr(out, "warning") &&
                   d0 > 0 && m0 > 0 && find_rom(dir, rom, sizeof rom) == 0,
               "plan --verify, empty cache: exit 0, the table built and saved, no warning");
  FILE *f = fopen(rom, "r+b");
  long len = -1;
  if (f && !fseek(f, 0, SEEK_END)) len = ftell(f);
  for (int k = 1; f && len > 0 && k <= 140; ++k) { /* bit 4 of byte 7: an exponent bit */
    const long off = len - 4 - 8L * k + 7;
    int c = EOF;
    if (fseek(f, off, SEEK_SET) || (c = fgetc(f)) == EOF || fseek(f, off, SEEK_SET) ||
        fputc(c ^ 0x10, f) == EOF)
      break;
  }
  if (f) fclose(f);
  rc = run(args);
  printf("  damaged cache: exit %d, duration %.17g s (fresh %.17g), measured %.6g mm (fresh "
         "%.6g)\n%.600s\n",
         rc, json_num("duration_s"), d0, 1e3 * json_num("measured_residual_peak_m"), 1e3 * m0, out);
  ea_test_true(
      rc == 0 && strstr(out, "warning: reduced-model cache") && strstr(out, "CRC-32") &&
          strstr(out, "\"model_cache_warning\"") && strstr(out, "\"model_from_cache\": false"),
      "plan, 140 flipped values in the cache: detected, rebuilt, a warning (stderr, JSON)");
  ea_test_true(json_num("duration_s") == d0 && json_num("measured_residual_peak_m") == m0,
               "plan, damaged cache: the same plan and FE check as with a fresh cache");
  rc = run(args);
  ea_test_true(rc == 0 && strstr(out, "\"model_from_cache\": true") && !strstr(out, "warning") &&
                   json_num("duration_s") == d0,
               "plan after the rebuild: loaded from the cache, no warning, the same plan");
  /* a FIFO at the cache path */
  remove(rom);
  const char *b0 = bin;
  char tb[1200];
  snprintf(tb, sizeof tb, "timeout 120 %s", b0);
  if (mkfifo(rom, 0600) == 0) {
    bin = tb;
    rc = run(args);
    bin = b0;
    printf("  FIFO at the cache path: exit %d\n%.400s\n", rc, out);
    ea_test_true(rc == 0 && strstr(out, "FIFO") && json_num("duration_s") == d0,
                 "plan, a FIFO at the cache path: no hang, a warning, the same plan");
  } else {
    ea_test_true(0, "mkfifo");
  }
  remove(rom);
  /* a cache folder that cannot be made: under a regular file (root too) */
  snprintf(plain, sizeof plain, "%s/plain", dir);
  touch(plain, "x");
  snprintf(cache2, sizeof cache2, "%s/cache", plain);
  setenv("EA_CACHE_DIR", cache2, 1);
  rc = run(args);
  printf("  unwritable cache: exit %d\n%.400s\n", rc, out);
  ea_test_true(rc == 0 && strstr(out, "warning: reduced-model cache") && strstr(out, "not saved") &&
                   json_num("duration_s") == d0,
               "plan, a cache that cannot be written: a warning, exit 0, the same plan");
  if (old)
    setenv("EA_CACHE_DIR", saved, 1);
  else
    unsetenv("EA_CACHE_DIR");
  remove(plain);
  snprintf(args, sizeof args, "%s/p.csv", dir);
  remove(args);
  snprintf(args, sizeof args, "%s/p.json", dir);
  remove(args);
  rmdir(dir);
}

int main(void) {
  char arm_path[1024];
  if (cli_setup(arm_path, sizeof arm_path)) return 1;
  const char *src = getenv("EA_SOURCE_DIR");
  test_rom_cache(src);

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
  test_default_arm(arm_path);
  test_figure_quotes();
  test_figures(arm_path);
  test_statics_checks(arm_path);
  test_plan_outputs(arm_path);
  remove("test_cli_blocker");
  return ea_test_summary("test_cli");
}
