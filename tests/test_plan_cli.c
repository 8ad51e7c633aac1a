/* `elasticarm plan` as a script uses it (issue 31): a refused flag combination, the exit code
 * of a failed --verify, the trajectory and summary of one run under concurrent runs and a
 * reader that refuses a mixed pair, the engine named in the summary, the refinement's time
 * cap inside its first FE transient, and an implausible arm file named in a warning. Each
 * check is against what the user asked for or an independent command, not saved output. */
#include "ea_test.h"
#include "ea_test_cli.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

static int exists(const char *path) {
  struct stat sb;
  return stat(path, &sb) == 0;
}

static void slurp(const char *path, char *buf, size_t cap) {
  buf[0] = '\0';
  FILE *fp = fopen(path, "r");
  if (!fp) return;
  const size_t k = fread(buf, 1, cap - 1, fp);
  buf[k] = '\0';
  fclose(fp);
}

/* The text after `key` up to the end of its line (or a closing quote) into val. */
static void value_after(const char *text, const char *key, char *val, size_t len) {
  val[0] = '\0';
  const char *p = strstr(text, key);
  if (!p) return;
  p += strlen(key);
  snprintf(val, len, "%.*s", (int)strcspn(p, "\"\r\n"), p);
}

/* A paper-line task (arm data/elasticarm.yaml) ending at (gx, -0.2) with extra YAML. */
static void write_task(const char *path, const char *arm, double gx, const char *extra) {
  FILE *fp = fopen(path, "w");
  if (!fp) return;
  fprintf(fp,
          "name: pc\narm_file: %s\npayload_factor: 0.0\nstart:\n  tip: [0.3, -0.2]\n"
          "goal:\n  tip: [%.17g, -0.2]\npath: line\nobjective: min_time\nknots: 40\n%s",
          arm, gx, extra ? extra : "");
  fclose(fp);
}

static double now_s(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Item 6: --shape zv with --refine (or the task's dynamics.refine) is a usage error naming
 * both; nothing is written. */
static void test_shape_refine(const char *arm) {
  write_task("tpc_rest.yaml", arm, 0.6, "dynamics:\n  modes: 2\n  residual_m: 0\n");
  remove("tpc_sr.csv");
  remove("tpc_sr.json");
  int rc = run("plan tpc_rest.yaml --shape zv --refine -o tpc_sr.csv");
  ea_test_true(rc == 2 && strstr(out, "--shape zv") && strstr(out, "--refine") &&
                   !exists("tpc_sr.csv") && !exists("tpc_sr.json"),
               "plan --shape zv --refine: usage error naming both flags, exit 2, nothing written");
  printf("  -> %.300s\n", out);
  write_task("tpc_rest_ref.yaml", arm, 0.6,
             "dynamics:\n  modes: 2\n  residual_m: 0\n  refine: true\n");
  rc = run("plan tpc_rest_ref.yaml --shape zv -o tpc_sr.csv");
  ea_test_true(rc == 2 && strstr(out, "--shape zv") && strstr(out, "dynamics.refine"),
               "plan --shape zv on a task with dynamics.refine: usage error naming both");
  remove("tpc_rest_ref.yaml");
}

/* Item 7: a failed verification exits 3 with the plan and summary written and says what was
 * reached; a passed one exits 0. */
static void test_verify(const char *arm) {
  char buf[1 << 16], args[512];
  /* the goal at 0.76 m: the refined plan's FE cable goes slack after the motion */
  write_task("tpc_far.yaml", arm, 0.76, "dynamics:\n  modes: 2\n  residual_m: 0\n");
  remove("tpc_far.csv");
  remove("tpc_far.json");
  int rc = run("plan tpc_far.yaml --refine --verify -o tpc_far.csv --quiet");
  slurp("tpc_far.json", buf, sizeof buf);
  ea_test_true(rc == 3 && exists("tpc_far.csv") && strstr(buf, "\"passed\": false") &&
                   strstr(out, "--verify failed") && strstr(out, "went slack"),
               "plan --refine --verify, slack FE cable: exit 3, plan and summary written, "
               "stderr says the cable went slack");
  printf("  -> %.400s\n", out);
  /* an independent run of the FE transient of the written file agrees that the tension
   * fell below the arm's 0.05 N */
  snprintf(args, sizeof args, "simulate tpc_far.csv --json");
  rc = run(args);
  const double tmin = json_num("fe_tension_min_N");
  ea_test_true(rc == 0 && tmin < 0.05,
               "simulate of the written file: FE tension below the 0.05 N limit too");
  printf("  simulate: fe_tension_min_N %g\n", tmin);

  /* residual above the bound: a refinement that cannot reach 1 um in one evaluation */
  write_task("tpc_tol.yaml", arm, 0.6,
             "dynamics:\n  modes: 2\n  residual_m: 0\n  refine:\n    tolerance_m: 1e-6\n"
             "    max_evaluations: 1\n");
  rc = run("plan tpc_tol.yaml --verify -o tpc_tol.csv --quiet --json");
  const double peak = json_num("measured_residual_peak_m");
  ea_test_true(rc == 3 && peak > 1e-6 && strstr(out, "exceeds the bound 0.001 mm"),
               "refined to 1 um and not there: --verify exits 3 naming the residual and bound");
  printf("  measured residual peak %g m\n", peak);

  rc = run("plan tpc_rest.yaml --verify -o tpc_ok.csv --quiet --json");
  ea_test_true(rc == 0 && strstr(out, "\"passed\": true"),
               "at-rest plan, taut cable, no residual bound: --verify passes, exit 0");
  remove("tpc_far.yaml");
  remove("tpc_tol.yaml");
}

/* Item 8: concurrent runs writing the same outputs leave one run's pair; readers refuse a
 * trajectory whose summary is another run's. */
static void test_pair(const char *arm) {
  char csv[1 << 16], json[1 << 16], tid[128], sid[128], ttask[256], stask[256];
  write_task("tpc_a.yaml", arm, 0.6, NULL);
  write_task("tpc_b.yaml", arm, 0.5, NULL);
  int bad = 0, rounds = 0;
  for (int round = 0; round < 4; ++round) {
    enum { NP = 6 };
    pid_t pids[NP];
    for (int i = 0; i < NP; ++i) {
      pids[i] = fork();
      if (pids[i] == 0) {
        execl(bin, bin, "plan", i % 2 ? "tpc_b.yaml" : "tpc_a.yaml", "-o", "tpc_same.csv",
              "--quiet", (char *)NULL);
        _exit(127);
      }
    }
    int ok = 1;
    for (int i = 0; i < NP; ++i) {
      int ws = 0;
      waitpid(pids[i], &ws, 0);
      ok = ok && WIFEXITED(ws) && WEXITSTATUS(ws) == 0;
    }
    slurp("tpc_same.csv", csv, sizeof csv);
    slurp("tpc_same.json", json, sizeof json);
    value_after(csv, "# run_id: ", tid, sizeof tid);
    value_after(json, "\"run_id\": \"", sid, sizeof sid);
    value_after(csv, "# task: ", ttask, sizeof ttask);
    value_after(json, "\"task\": \"", stask, sizeof stask);
    if (!ok || !tid[0] || strcmp(tid, sid) || strcmp(ttask, stask)) ++bad;
    ++rounds;
    printf("  round %d: csv run_id %s task %s | json run_id %s task %s\n", round, tid, ttask, sid,
           stask);
  }
  ea_test_true(bad == 0, "6 concurrent plans with the same -o, 4 rounds: every final pair has "
                         "one run id and one task");
  /* a reader: figure and simulate accept the matched pair, refuse a mixed one */
  int rc = run("figure tpc_same.csv -o tpc_same.svg");
  ea_test_true(rc == 0, "figure of a matched pair: drawn");
  rc = run("plan tpc_b.yaml -o tpc_other.csv --quiet");
  /* a new trajectory beside the old summary (a run killed between its renames) */
  FILE *src = fopen("tpc_other.csv", "r"), *dst = fopen("tpc_same.csv", "w");
  size_t n;
  while (src && dst && (n = fread(csv, 1, sizeof csv, src)) > 0)
    fwrite(csv, 1, n, dst);
  if (src) fclose(src);
  if (dst) fclose(dst);
  rc = run("figure tpc_same.csv -o tpc_mixed.svg");
  ea_test_true(rc == 2 && strstr(out, "different plan runs") && !exists("tpc_mixed.svg"),
               "figure refuses a trajectory beside another run's summary (exit 2)");
  printf("  -> %.300s\n", out);
  rc = run("simulate tpc_same.csv");
  ea_test_true(rc == 2 && strstr(out, "different plan runs"),
               "simulate refuses the mixed pair (exit 2)");
  rc = run("stream tpc_same.csv --to file:tpc_mixed.bin");
  ea_test_true(rc == 2 && strstr(out, "different plan runs") && !exists("tpc_mixed.bin"),
               "stream refuses the mixed pair (exit 2), nothing written");
  /* a summary without a run id (an older plan's) is not this trajectory's either */
  FILE *fp = fopen("tpc_same.json", "w");
  if (fp) {
    fputs("{\n  \"status\": \"EA_OK\",\n  \"refine\": {\"run_id\": \"x\"}\n}\n", fp);
    fclose(fp);
  }
  slurp("tpc_same.csv", csv, sizeof csv);
  rc = run("figure tpc_same.csv -o tpc_mixed.svg");
  ea_test_true(rc == 2 && strstr(out, "no run_id"),
               "figure refuses a summary with no top-level run_id beside a plan's trajectory");
  const char *rm[] = {"tpc_a.yaml",    "tpc_b.yaml",         "tpc_same.csv",   "tpc_same.json",
                      "tpc_same.svg",  "tpc_other.csv",      "tpc_other.json", "tpc_same.csv.lock",
                      "tpc_mixed.svg", "tpc_other.csv.lock", "tpc_mixed.bin"};
  for (size_t i = 0; i < sizeof rm / sizeof *rm; ++i)
    remove(rm[i]);
  printf("  %d rounds\n", rounds);
}

/* Item 9: the summary names the engine that ran, with neutral keys; --print-level says when
 * it was not Ipopt; the refinement's first FE transient is inside its time cap. */
static void test_engine(const char *arm) {
  int rc = run("plan tpc_rest.yaml -o tpc_e.csv --quiet --json --print-level 5");
  ea_test_true(rc == 0 && strstr(out, "\"engine\": \"interior-point-ldl\"") &&
                   strstr(out, "\"engine_status\": \"converged\"") &&
                   !strstr(out, "ipopt_status") && !strstr(out, "\"solver\"") &&
                   !strstr(out, "interior-point-klu") && isfinite(json_num("solve")) &&
                   !strstr(out, "\"ipopt\": "),
               "own interior point (solver.nlp auto): engine interior-point-ldl, no Ipopt keys, "
               "phase_times_s.solve");
  ea_test_true(strstr(out, "--print-level applies to Ipopt only") != NULL,
               "--print-level on a plan Ipopt did not make: stderr says so");
  write_task("tpc_ipopt.yaml", arm, 0.6,
             "dynamics:\n  modes: 2\n  residual_m: 0\nsolver:\n  nlp: ipopt\n");
  rc = run("plan tpc_ipopt.yaml -o tpc_e.csv --quiet --json");
  ea_test_true(rc == 0 && strstr(out, "\"engine\": \"ipopt\"") &&
                   strstr(out, "\"ipopt_status\": \"Solve_Succeeded\"") &&
                   json_num("ipopt_status_code") == 0.0,
               "solver.nlp: ipopt: engine ipopt with Ipopt's own status and code");
  rc = run("plan tpc_rest.yaml -o tpc_e.csv --quiet --json --refine");
  ea_test_true(rc == 0 && strstr(out, "\"engine\": \"interior-point-ldl\""),
               "refined plan: the engine of its iterations (the at-rest plan's), not 'ipopt'");
  remove("tpc_ipopt.yaml");
  remove("tpc_e.csv");
  remove("tpc_e.json");

  /* refine.fe_dt_s 1e-5: one FE transient takes ~20 s here; max_time_s 1 must hold */
  write_task("tpc_dt.yaml", arm, 0.6,
             "dynamics:\n  modes: 2\n  residual_m: 0\n  refine:\n    fe_dt_s: 1e-5\n"
             "    max_time_s: 1\n");
  const double t0 = now_s();
  rc = run("plan tpc_dt.yaml -o tpc_dt.csv --quiet");
  const double wall = now_s() - t0;
  ea_test_true(rc == 1 && wall < 5.0 && strstr(out, "max_time_s = 1 s") && strstr(out, "fe_dt_s"),
               "refine.fe_dt_s 1e-5 with max_time_s 1: stops inside the first transient, says "
               "why (exit 1)");
  printf("  wall %.2f s -> %.300s\n", wall, out);
  remove("tpc_dt.yaml");
  remove("tpc_dt.json");
  remove("tpc_dt.csv.lock");
}

/* Item 14: an arm file with EI 1000x too large: the warning names EI_Nm2 at its position. */
static void test_implausible_arm(const char *arm) {
  char text[8192];
  slurp(arm, text, sizeof text);
  char *at = strstr(text, "EI_Nm2: 0.705");
  if (!at) {
    ea_test_true(0, "arm file has EI_Nm2: 0.705");
    return;
  }
  memcpy(at, "EI_Nm2: 705  ", 13);
  FILE *fp = fopen("tpc_stiff_arm.yaml", "w");
  if (fp) {
    fputs(text, fp);
    fclose(fp);
  }
  int line = 1;
  const char *q = text;
  for (const char *c = text; c < at; ++c)
    if (*c == '\n') ++line, q = c + 1;
  char want[96];
  snprintf(want, sizeof want, "tpc_stiff_arm.yaml:%d:%d: beam.EI_Nm2 = 705", line,
           (int)(at - q) + 9);
  write_task("tpc_stiff.yaml", "tpc_stiff_arm.yaml", 0.6, NULL);
  const int rc = run("plan tpc_stiff.yaml -o tpc_stiff.csv --quiet");
  ea_test_true(rc == 1 && strstr(out, "warning") && strstr(out, want),
               "plan with EI_Nm2 705: a warning at the key's line:column names the value");
  printf("  want '%s' -> %.500s\n", want, out);
  remove("tpc_stiff_arm.yaml");
  remove("tpc_stiff.yaml");
  remove("tpc_stiff.json");
  remove("tpc_stiff.csv.lock");
}

/* dynamics.refine.by: model_only says the FE did not check the plan (text and fe_check), model
 * runs the FE verdict after the model's evaluations; a bad value or a model the nonlinear
 * reduced model cannot be is an input error naming the key. */
static void test_refine_by(const char *arm) {
  char js[1 << 16];
  write_task("tpc_by.yaml", arm, 0.6,
             "dynamics:\n  modes: 2\n  residual_m: 0\n  refine:\n    by: model_only\n");
  int rc = run("plan tpc_by.yaml -o tpc_by.csv");
  slurp("tpc_by.json", js, sizeof js);
  ea_test_true(rc == 0 && strstr(out, "not checked by the FE (dynamics.refine.by: model_only)") &&
                   strstr(js, "\"by\": \"model_only\"") && strstr(js, "\"checked\": false"),
               "refine.by model_only: exit 0, the text and fe_check say the FE did not check it");
  write_task("tpc_by.yaml", arm, 0.6,
             "dynamics:\n  modes: 2\n  residual_m: 0\n  refine:\n    by: model\n");
  rc = run("plan tpc_by.yaml -o tpc_by.csv");
  slurp("tpc_by.json", js, sizeof js);
  ea_test_true(rc == 0 && strstr(out, "checked by the FE") && strstr(js, "\"by_model\": true") &&
                   strstr(js, "\"by_model\": false") && strstr(js, "\"checked\": true"),
               "refine.by model: the model's evaluations, then an FE verdict that checks it");
  write_task("tpc_by.yaml", arm, 0.6,
             "dynamics:\n  modes: 2\n  residual_m: 0\n  refine:\n    by: exact\n");
  rc = run("plan tpc_by.yaml -o tpc_by.csv");
  ea_test_true(rc == 2 && strstr(out, "tpc_by.yaml:15:9: key 'by'") && strstr(out, "model_only"),
               "refine.by exact: input error at the key's line:column listing the values");
  printf("  -> %.300s\n", out);
  write_task("tpc_by.yaml", arm, 0.6,
             "dynamics:\n  modes: 1\n  residual_m: 0\n  refine:\n    by: model\n");
  rc = run("plan tpc_by.yaml -o tpc_by.csv");
  ea_test_true(rc == 2 && strstr(out, "dynamics.refine.by = model") &&
                   strstr(out, "dynamics.modes = 1"),
               "refine.by model with 1 mode: input error naming the key and the modes");
  printf("  -> %.300s\n", out);
  /* the flag as the key; a value it does not know is a usage error */
  write_task("tpc_by.yaml", arm, 0.6, "dynamics:\n  modes: 2\n  residual_m: 0\n");
  rc = run("plan tpc_by.yaml -o tpc_by.csv --refine-by model_only");
  ea_test_true(rc == 0 && strstr(out, "not checked by the FE (dynamics.refine.by: model_only)"),
               "plan --refine-by model_only: the default check by the model alone, so said");
  rc = run("plan tpc_by.yaml -o tpc_by.csv --refine-by exact");
  ea_test_true(rc == 2 && strstr(out, "--refine-by: 'exact'"),
               "plan --refine-by exact: usage error naming the flag and the value");
  /* --verify beside the FE: the nonlinear reduced model's prediction within 20 % of the FE's
   * measure on the diagonal allowed 5 mm (the linear model's: 3.7 mm, the FE's 9.8 mm) */
  FILE *fp = fopen("tpc_by.yaml", "w");
  if (fp) {
    fprintf(fp,
            "name: diag\narm_file: %s\npayload_factor: 0.25\nstart:\n  tip: [0.25, -0.45]\n"
            "goal:\n  tip: [0.6, -0.3]\npath: line\nobjective: min_time\ndynamics:\n  modes: 2\n"
            "  residual_m: 0.005\n  verify: false\n",
            arm);
    fclose(fp);
  }
  rc = run("plan tpc_by.yaml -o tpc_by.csv --verify");
  slurp("tpc_by.json", js, sizeof js);
  char v1[64], v2[64];
  value_after(js, "\"predicted_nonlinear_residual_m\": ", v1, sizeof v1);
  value_after(js, "\"measured_residual_peak_m\": ", v2, sizeof v2);
  const double pn = atof(v1), fe = atof(v2);
  printf("  --verify on the diagonal: nonlinear model %.4f mm, FE %.4f mm (exit %d)\n", 1e3 * pn,
         1e3 * fe, rc);
  ea_test_true(rc == 3 && strstr(out, "the nonlinear reduced model") && fe > 0.005 &&
                   fabs(pn - fe) <= 0.2 * fe,
               "--verify: the nonlinear reduced model's prediction within 20 % of the FE's "
               "residual (over the 5 mm bound: exit 3)");
  const char *rm[] = {"tpc_by.yaml", "tpc_by.csv", "tpc_by.json", "tpc_by.csv.lock"};
  for (size_t i = 0; i < sizeof rm / sizeof *rm; ++i)
    remove(rm[i]);
}

int main(void) {
  char arm[1024];
  if (cli_setup(arm, sizeof arm)) return 1;
  test_shape_refine(arm);
  test_verify(arm);
  test_pair(arm);
  test_engine(arm);
  test_implausible_arm(arm);
  test_refine_by(arm);
  const char *rm[] = {"tpc_rest.yaml",    "tpc_far.csv",     "tpc_far.json",  "tpc_tol.csv",
                      "tpc_tol.json",     "tpc_ok.csv",      "tpc_ok.json",   "tpc_far.csv.lock",
                      "tpc_tol.csv.lock", "tpc_ok.csv.lock", "tpc_e.csv.lock"};
  for (size_t i = 0; i < sizeof rm / sizeof *rm; ++i)
    remove(rm[i]);
  return ea_test_summary("test_plan_cli");
}
