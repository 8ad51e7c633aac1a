/* Batch studies: the Fig. 3 result (outer edge moves inward with payload),
 * byte-identical CSV for 1, 2, 3 threads, shards merged = single run,
 * interrupted (stop hook, kill -9, torn journal) and resumed = uninterrupted,
 * failed cases recorded, spec errors with file:line:column. */
#include "ea_planner.h"
#include "ea_test.h"
#include "study_plan_impl.h"

#include <fcntl.h>
#include <gsl/gsl_errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

static char g_src[1024] = ".";
static char g_tmp[256];

/* A mixed study: workspace + frequencies (one configuration outside the
 * workspace for the heavier payloads) + path + torque map. */
static const char *k_mixed =
    "name: mixed\n"
    "grid:\n"
    "  payload_factor: 0:0.1:0.5\n"
    "  EI_Nm2: [0.6, 0.705]\n"
    "metrics:\n"
    "  workspace: {points: 21}\n"
    "  torque_map: {cable_lengths_m: '0.3:0.1:0.8', cable_angles_deg: [-50, -20, 0]}\n"
    "  frequencies:\n"
    "    modes: 2\n"
    "    elements: 6\n"
    "    configurations:\n"
    "      - {cable_length_m: 0.45, cable_angle_deg: -25}\n"
    "      - {cable_length_m: 0.85, cable_angle_deg: 0}\n"
    "  path: {start: [0.3, -0.2], goal: [0.6, -0.2], steps: 10}\n";

static int load(const char *text, ea_study_t *s) {
  ea_error_t e = {0};
  ea_status_t st = ea_study_load_string("mixed.yaml", text, strlen(text), NULL, s, &e);
  if (st) printf("load: %s\n", e.msg);
  return st;
}

static char *run(const ea_study_t *s, int threads, int k, int n, const char *ckpt, long stop_after,
                 ea_study_info_t *info, ea_status_t *st_out) {
  ea_study_settings_t set;
  ea_study_settings_default(&set);
  set.threads = threads;
  set.shard_k = k;
  set.shard_n = n;
  set.checkpoint = ckpt;
  set.stop_after = stop_after;
  set.fsync = 0;
  char *csv = NULL;
  size_t len = 0;
  ea_error_t e = {0};
  ea_study_info_t dummy;
  ea_status_t st = ea_study_run(s, &set, &csv, &len, info ? info : &dummy, &e);
  if (st_out) *st_out = st;
  if (st && st != EA_ERR_INTERRUPTED) printf("run: %s\n", e.msg);
  return csv;
}

static double metric(const char *csv, long case_id, const char *name, char *status) {
  ea__study_table_t t;
  ea_error_t e;
  double v = NAN;
  if (ea__study_table_parse(csv, strlen(csv), "csv", &t, &e)) return NAN;
  for (long i = 0; i < t.n_rows; ++i)
    if (t.rows[i].case_id == case_id && !strcmp(t.rows[i].metric, name)) {
      v = t.rows[i].value;
      if (status) strcpy(status, t.rows[i].status);
    }
  ea__study_table_free(&t);
  return v;
}

/* ---- the Fig. 3 study ---------------------------------------------------------- */

static void test_fig3(void) {
  char path[1200];
  snprintf(path, sizeof path, "%s/problems/examples/studies/fig3.yaml", g_src);
  ea_study_t s;
  ea_error_t e = {0};
  ea_status_t st = ea_study_load(path, NULL, &s, &e);
  ea_test_true(st == EA_OK, "fig3.yaml loads");
  if (st) {
    printf("  %s\n", e.msg);
    return;
  }
  ea_test_true(s.n_cases == 4 && s.n_axes == 1 && s.axis[0].param == EA_STUDY_PAYLOAD_FACTOR,
               "fig3: 4 payload factors");
  ea_test_abs(s.workspace.alpha_min * 180 / M_PI, -60, 1e-12, "fig3: alpha from -60 deg");
  ea_test_abs(s.workspace.alpha_max * 180 / M_PI, 10, 1e-12, "fig3: alpha to 10 deg");
  ea_study_info_t info;
  char *csv = run(&s, 0, 1, 1, NULL, 0, &info, &st);
  ea_test_true(csv && st == EA_OK && info.cases_failed == 0, "fig3: every case solved");
  if (!csv) return;
  double reach[4], area[4];
  for (int c = 0; c < 4; ++c) {
    reach[c] = metric(csv, c, "max_reach", NULL);
    area[c] = metric(csv, c, "area", NULL);
    printf("  gamma = %.2f: max reach %.5f m, area %.5f m^2\n", s.axis[0].values[c], reach[c],
           area[c]);
  }
  int dec = 1;
  for (int c = 1; c < 4; ++c)
    dec &= reach[c] < reach[c - 1] && area[c] < area[c - 1];
  ea_test_true(dec, "fig3: reach and area decrease strictly as the payload grows");
  /* Independently of the study code: at every cable angle the outer edge
   * point of gamma = 0.5 lies inside (closer to the cable root than) that
   * of gamma = 0, from separate edge solves. */
  ea_shooter_t *sh = NULL;
  ea_shooter_alloc(&s.arm, NULL, &sh, NULL);
  int inward = sh != NULL;
  for (int k = 0; sh && k <= 14; ++k) {
    const double a = (-60.0 + 5.0 * k) * M_PI / 180;
    double d[2];
    for (int g = 0; g < 2; ++g) {
      ea_load_t ld = {ea_arm_tip_mass(&s.arm, ea_arm_payload_from_factor(&s.arm, g ? 0.5 : 0.0))};
      ea_shooter_set_load(sh, &ld);
      ea_statics_solution_t sol;
      if (ea_statics_edge(sh, a, NULL, NULL, &sol, NULL)) {
        inward = 0;
        d[g] = NAN;
        continue;
      }
      d[g] = sol.cable_length;
    }
    if (!(d[1] < d[0])) inward = 0;
  }
  ea_shooter_free(sh);
  ea_test_true(inward,
               "fig3: outer edge of gamma 0.5 inside gamma 0 at every angle (separate solves)");
  free(csv);
  ea_study_free(&s);
}

/* ---- threads, shards, merge ------------------------------------------------------ */

static void test_threads_shards(void) {
  ea_study_t s;
  if (load(k_mixed, &s)) {
    ea_test_true(0, "mixed study loads");
    return;
  }
  ea_test_true(s.n_cases == 12, "mixed: 6 x 2 = 12 cases");
  char *c1 = run(&s, 1, 1, 1, NULL, 0, NULL, NULL);
  char *c2 = run(&s, 2, 1, 1, NULL, 0, NULL, NULL);
  char *c3 = run(&s, 3, 1, 1, NULL, 0, NULL, NULL);
  ea_test_true(c1 && c2 && c3, "runs with 1, 2, 3 threads");
  if (!c1 || !c2 || !c3) return;
  ea_test_true(!strcmp(c1, c2), "CSV with 2 threads byte-identical to 1 thread");
  ea_test_true(!strcmp(c1, c3), "CSV with 3 threads byte-identical to 1 thread");
  /* order: case ids ascending, first parameter slowest */
  ea_test_true(!strncmp(c1, "case_id,payload_factor,EI_Nm2,metric,value,unit,status,message\n", 62),
               "header: case_id, parameters (payload first), metric, value, unit, status, message");
  ea_test_abs(metric(c1, 3, "area", NULL), metric(c1, 3, "area", NULL), 0, "case 3 has an area");

  for (int n = 2; n <= 5; n += 3) {
    const char *texts[5];
    size_t lens[5];
    static const char *const shard_names[5] = {"s1", "s2", "s3", "s4", "s5"};
    const char *names[5];
    char *sh[5] = {0};
    long total = 0;
    for (int k = 1; k <= n; ++k) {
      ea_study_info_t info;
      sh[k - 1] = run(&s, 2, k, n, NULL, 0, &info, NULL);
      total += info.cases_shard;
      texts[n - k] = sh[k - 1] ? sh[k - 1] : ""; /* reversed order on purpose */
      lens[n - k] = strlen(texts[n - k]);
      names[n - k] = shard_names[k - 1];
    }
    char *m = NULL;
    size_t ml = 0;
    ea_error_t e = {0};
    ea_status_t st = ea_study_merge(texts, lens, names, n, 12, &m, &ml, &e);
    char what[96];
    snprintf(what, sizeof what, "%d shards: %ld cases in all, merged = single run byte for byte", n,
             total);
    ea_test_true(st == EA_OK && total == 12 && m && !strcmp(m, c1), what);
    if (st) printf("  %s\n", e.msg);
    free(m);
    /* merge refuses a missing shard and a duplicated one */
    st = ea_study_merge(texts, lens, names, n - 1, 12, &m, &ml, &e);
    printf("  missing shard: %s\n", e.msg);
    ea_test_true(st == EA_ERR_INPUT && strstr(e.msg, "missing"), "merge: missing cases named");
    const char *dup[2] = {texts[0], texts[0]};
    size_t dl[2] = {lens[0], lens[0]};
    st = ea_study_merge(dup, dl, names, 2, 0, &m, &ml, &e);
    printf("  duplicate shard: %s\n", e.msg);
    ea_test_true(st == EA_ERR_INPUT && strstr(e.msg, "is in"), "merge: duplicated case named");
    for (int k = 0; k < n; ++k)
      free(sh[k]);
  }
  const char *bad[2] = {c1, "case_id,payload_kg,metric,value,unit,status,message\n"};
  size_t bl[2] = {strlen(bad[0]), strlen(bad[1])};
  char *m = NULL;
  ea_error_t e = {0};
  ea_status_t st = ea_study_merge(bad, bl, (const char *[]){"a.csv", "b.csv"}, 2, 0, &m, NULL, &e);
  printf("  other header: %s\n", e.msg);
  ea_test_true(st == EA_ERR_INPUT && strstr(e.msg, "b.csv:1:1"), "merge: header mismatch named");
  free(c1);
  free(c2);
  free(c3);
  ea_study_free(&s);
}

/* ---- failed cases ---------------------------------------------------------------- */

static void test_failed_case(void) {
  ea_study_t s;
  if (load(k_mixed, &s)) return;
  ea_study_info_t info;
  ea_status_t st;
  char *c = run(&s, 2, 1, 1, NULL, 0, &info, &st);
  ea_test_true(c && st == EA_OK, "a study with failing cases completes");
  if (!c) return;
  char s1[32] = "", s2[32] = "";
  int others_ok = 1, all_fail = 1;
  for (long k = 0; k < 12; ++k) {
    metric(c, k, "frequency_c1_mode1", s1);
    const double f2 = metric(c, k, "frequency_c2_mode2", s2);
    others_ok &= !strcmp(s1, "ok") && isfinite(metric(c, k, "max_reach", NULL));
    all_fail &= !strcmp(s2, "EA_ERR_INADMISSIBLE") && isnan(f2);
  }
  ea_test_true(all_fail, "configuration outside the workspace: every case records "
                         "EA_ERR_INADMISSIBLE with an empty value");
  ea_test_true(others_ok, "the other metrics of the failing cases still computed");
  ea_test_true(strstr(c, "configuration 2 (L_c = 0.85 m, alpha = 0 deg)") != NULL,
               "the reason names the configuration");
  ea_test_true(info.cases_failed == 12 && info.rows_failed == 24,
               "info counts 12 failed cases, 24 failed rows");
  /* min_time without the planner callback: recorded as not implemented */
  ea_study_t m;
  const char *mt = "grid: {payload_factor: [0]}\nmetrics: {min_time: {task: x.yaml}}\n";
  ea_error_t e = {0};
  if (ea_study_load_string("mt.yaml", mt, strlen(mt), NULL, &m, &e) == EA_OK) {
    char *r = run(&m, 1, 1, 1, NULL, 0, &info, &st);
    ea_test_true(r && strstr(r, "min_time_duration,,s,EA_ERR_NOTIMPL"),
                 "min_time without the planner: EA_ERR_NOTIMPL row");
    free(r);
    ea_study_free(&m);
  } else {
    ea_test_true(0, e.msg);
  }
  free(c);
  ea_study_free(&s);
}

/* ---- resume ---------------------------------------------------------------------- */

static long journal_cases(const char *path) {
  FILE *fp = fopen(path, "r");
  if (!fp) return 0;
  char line[4096];
  long n = 0;
  while (fgets(line, sizeof line, fp))
    n += !strncmp(line, "#case ", 6);
  fclose(fp);
  return n;
}

static void slow_progress(void *d, long c, long done, long todo, int failed) {
  (void)d, (void)c, (void)done, (void)todo, (void)failed;
  struct timespec ts = {0, 20 * 1000000L};
  nanosleep(&ts, NULL);
}

static void test_resume(void) {
  ea_study_t s;
  if (load(k_mixed, &s)) return;
  char *ref = run(&s, 1, 1, 1, NULL, 0, NULL, NULL);
  char ck[400];
  ea_study_info_t info;
  ea_status_t st;

  /* (a) injected stop after 5 cases, then resume */
  snprintf(ck, sizeof ck, "%s/a.journal", g_tmp);
  unlink(ck);
  char *c = run(&s, 2, 1, 1, ck, 5, &info, &st);
  ea_test_true(st == EA_ERR_INTERRUPTED && !c && info.cases_computed == 5,
               "stop hook: interrupted after 5 cases, no CSV");
  ea_test_true(journal_cases(ck) == 5, "journal holds 5 cases");
  c = run(&s, 3, 1, 1, ck, 0, &info, &st);
  printf("  resume: skipped %ld, computed %ld\n", info.cases_skipped, info.cases_computed);
  ea_test_true(st == EA_OK && info.cases_skipped == 5 && info.cases_computed == 7,
               "resume skips the 5 finished cases and computes 7");
  ea_test_true(c && ref && !strcmp(c, ref), "resumed CSV byte-identical to uninterrupted run");
  free(c);
  /* a finished journal: nothing recomputed */
  c = run(&s, 2, 1, 1, ck, 0, &info, &st);
  ea_test_true(c && !strcmp(c, ref) && info.cases_computed == 0 && info.cases_skipped == 12,
               "rerun on a complete journal recomputes nothing");
  free(c);

  /* (b) torn tail: half a block appended, as a crash mid-write leaves it */
  FILE *fp = fopen(ck, "r+b");
  if (fp) {
    fseek(fp, 0, SEEK_END);
    const long size = ftell(fp);
    /* cut the last block in half: drop its trailer and half its rows */
    fclose(fp);
    if (truncate(ck, size - 200) != 0) printf("  truncate failed\n");
  }
  c = run(&s, 2, 1, 1, ck, 0, &info, &st);
  printf("  torn tail: dropped %ld bytes, recomputed %ld\n", info.journal_dropped_bytes,
         info.cases_computed);
  ea_test_true(c && !strcmp(c, ref) && info.journal_dropped_bytes > 0 && info.cases_computed == 1 &&
                   info.cases_skipped == 11,
               "torn journal tail dropped, that case recomputed, CSV identical");
  free(c);
  /* a corrupted byte inside a block: CRC catches it, the rest is recomputed */
  fp = fopen(ck, "r+b");
  if (fp) {
    fseek(fp, 300, SEEK_SET);
    int ch = fgetc(fp);
    fseek(fp, 300, SEEK_SET);
    fputc(ch == '1' ? '2' : '1', fp);
    fclose(fp);
  }
  c = run(&s, 2, 1, 1, ck, 0, &info, &st);
  ea_test_true(c && !strcmp(c, ref) && info.cases_skipped < 12,
               "corrupted block: CRC mismatch, recomputed, CSV identical");
  free(c);

  /* (c) a journal of another study is refused */
  ea_study_t o;
  if (!load(k_mixed, &o)) {
    o.workspace.points = 22;
    ea_error_t e = {0};
    ea_study_settings_t set;
    ea_study_settings_default(&set);
    set.checkpoint = ck;
    char *x = NULL;
    st = ea_study_run(&o, &set, &x, NULL, &info, &e);
    printf("  other study: %s\n", e.msg);
    ea_test_true(st == EA_ERR_INPUT && strstr(e.msg, "another study"),
                 "journal of another study refused");
    free(x);
    ea_study_free(&o);
  }

  /* (d) kill -9 in the middle of a run (fsync on), then resume */
  snprintf(ck, sizeof ck, "%s/d.journal", g_tmp);
  unlink(ck);
  pid_t pid = fork();
  if (pid == 0) {
    ea_study_settings_t set;
    ea_study_settings_default(&set);
    set.threads = 2;
    set.checkpoint = ck;
    set.progress = slow_progress; /* keep the child alive long enough */
    char *x = NULL;
    ea_study_run(&s, &set, &x, NULL, NULL, NULL);
    _exit(0);
  }
  long seen = 0;
  for (int i = 0; i < 5000 && seen < 4; ++i) {
    struct timespec ts = {0, 1000000L};
    nanosleep(&ts, NULL);
    seen = journal_cases(ck);
  }
  kill(pid, SIGKILL);
  int status = 0;
  waitpid(pid, &status, 0);
  const long at_kill = journal_cases(ck);
  printf("  killed with %ld cases in the journal\n", at_kill);
  ea_test_true(WIFSIGNALED(status) && at_kill >= 4 && at_kill < 12,
               "child killed (SIGKILL) halfway through");
  c = run(&s, 2, 1, 1, ck, 0, &info, &st);
  printf("  after kill -9: skipped %ld, computed %ld\n", info.cases_skipped, info.cases_computed);
  ea_test_true(c && ref && !strcmp(c, ref) && info.cases_skipped == at_kill &&
                   info.cases_computed == 12 - at_kill,
               "resumed after kill -9: finished cases skipped, CSV byte-identical");
  free(c);
  unlink(ck);
  snprintf(ck, sizeof ck, "%s/a.journal", g_tmp);
  unlink(ck);
  free(ref);
  ea_study_free(&s);
}

/* ---- the planner metric ------------------------------------------------------------ */

static void test_min_time(void) {
  char text[1400];
  snprintf(text, sizeof text,
           "grid: {payload_factor: [0, 0.25, 3]}\n"
           "metrics: {min_time: {task: %s/problems/examples/paper-line.yaml}}\n",
           g_src);
  ea_study_t s;
  ea_error_t e = {0};
  if (ea_study_load_string("mt.yaml", text, strlen(text), NULL, &s, &e)) {
    ea_test_true(0, e.msg);
    return;
  }
  ea__study_plan_t *plan = NULL;
  if (ea__study_plan_alloc(&s, NULL, &plan, &e)) {
    ea_test_true(0, e.msg);
    ea_study_free(&s);
    return;
  }
  char *c[2] = {0};
  for (int t = 0; t < 2; ++t) {
    ea_study_settings_t set;
    ea_study_settings_default(&set);
    set.threads = t + 1;
    set.min_time = ea__study_min_time;
    set.min_time_data = plan;
    ea_study_run(&s, &set, &c[t], NULL, NULL, &e);
  }
  ea__study_plan_free(plan);
  ea_test_true(c[0] && c[1] && !strcmp(c[0], c[1]), "min_time: 1 and 2 threads byte-identical");
  if (c[0]) {
    char st0[32] = "", st2[32] = "";
    const double d0 = metric(c[0], 0, "min_time_duration", st0);
    const double d1 = metric(c[0], 1, "min_time_duration", NULL);
    metric(c[0], 2, "min_time_duration", st2);
    printf("  min-time durations: gamma 0: %.6f s, gamma 0.25: %.6f s; gamma 3: %s\n", d0, d1, st2);
    ea_test_true(!strcmp(st0, "ok") && d0 > 0.5 && d0 < 10 && d1 > 0.5 && d1 < 10,
                 "min_time: paper line planned for gamma 0 and 0.25");
    ea_test_true(strcmp(st2, "ok") != 0,
                 "min_time: payload factor 3 (line outside the workspace) recorded as failed");
  }
  free(c[0]);
  free(c[1]);
  ea_study_free(&s);
}

/* ---- spec errors ------------------------------------------------------------------ */

static void test_spec_errors(void) {
  static const struct {
    const char *text, *want;
  } cases[] = {
      {"grid:\n  payload_factr: [0]\nmetrics: {workspace: }\n",
       "spec.yaml:2:3: unknown key 'payload_factr' in grid"},
      {"grid:\n  payload_factor: [0, abc]\nmetrics: {workspace: }\n",
       "spec.yaml:2:23: key 'payload_factor': 'abc' is not a number"},
      {"grid:\n  payload_factor: '0:-0.1:0.5'\nmetrics: {workspace: }\n",
       "spec.yaml:2:19: key 'payload_factor': '0:-0.1:0.5' is not a range"},
      {"grid:\n  payload_factor: [0]\n  payload_kg: [1]\nmetrics: {workspace: }\n",
       "spec.yaml:3:15: key 'payload_kg': give payload_factor or payload_kg, not both"},
      {"grid:\n  payload_factor: [0]\n", "spec.yaml:1:1: missing required key 'metrics'"},
      {"grid:\n  EI_Nm2: [-1]\nmetrics: {workspace: }\n",
       "spec.yaml:2:12: key 'EI_Nm2': value -1 is below the bound"},
      {"grid: {payload_factor: [0]}\nmetrics:\n  frequencies:\n    modes: 99\n"
       "    configurations: [{cable_length_m: 0.4, cable_angle_deg: 0}]\n",
       "spec.yaml:4:12: key 'modes': value 99 is outside [1, 16]"},
      {"grid: {payload_factor: [0]}\nmetrics:\n  workspace: {alpha_min_deg: 10, alpha_max_deg: "
       "-10}\n",
       "spec.yaml:3:49: key 'alpha_max_deg': -10 must be above alpha_min_deg 10"},
      {"grid: {payload_factor: [0]}\nmetrics:\n  frequencies:\n    configurations:\n"
       "      - {cable_length: 0.4}\n",
       "spec.yaml:5:10: unknown key 'cable_length' in a frequencies configuration"},
      {"grid: {payload_factor: [0]}\nmetrics: {}\n",
       "spec.yaml:2:10: key 'metrics': ask for at least one"},
      {"grid: [0\n", "spec.yaml:2:1: YAML syntax error"},
  };
  for (size_t i = 0; i < sizeof cases / sizeof *cases; ++i) {
    ea_study_t s;
    ea_error_t e = {0};
    ea_status_t st =
        ea_study_load_string("spec.yaml", cases[i].text, strlen(cases[i].text), NULL, &s, &e);
    const int ok = st != EA_OK && !strncmp(e.msg, cases[i].want, strlen(cases[i].want));
    char what[300];
    snprintf(what, sizeof what, "spec error %zu: '%s'", i + 1, cases[i].want);
    ea_test_true(ok, what);
    if (!ok) printf("  got (%s): %s\n", ea_status_name(st), e.msg);
    if (!st) ea_study_free(&s);
  }
  ea_study_t s;
  ea_error_t e = {0};
  ea_test_true(ea_study_load("/nonexistent/x.yaml", NULL, &s, &e) == EA_ERR_IO &&
                   strstr(e.msg, "/nonexistent/x.yaml"),
               "missing spec file: EA_ERR_IO naming the file");
}

int main(void) {
  gsl_set_error_handler_off(); /* every GSL return is checked */
  const char *src = getenv("EA_SOURCE_DIR");
  if (src) snprintf(g_src, sizeof g_src, "%s", src);
  snprintf(g_tmp, sizeof g_tmp, "/tmp/ea_test_study.XXXXXX");
  if (!mkdtemp(g_tmp)) snprintf(g_tmp, sizeof g_tmp, "/tmp");
  test_fig3();
  test_threads_shards();
  test_failed_case();
  test_resume();
  test_min_time();
  test_spec_errors();
  rmdir(g_tmp);
  return ea_test_summary("test_study");
}
