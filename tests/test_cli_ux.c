/* The CLI's usability as an outside review asked for it: options read by getopt_long
 * ("--opt=value", abbreviations, negative values), one spelling per meaning, what the
 * printed numbers are, progress of long jobs. Values are checked against what was asked
 * (the tip given), against the arm file read through the library, or against the
 * documented protocol. */
#include "ea_planner.h"
#include "ea_problems.h"
#include "ea_test.h"
#include "ea_test_cli.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

static char dir[512];

static void expect(int want_rc, const char *args, const char *want, const char *what) {
  const int rc = run(args);
  ea_test_true(rc == want_rc && (!want || strstr(out, want) != NULL), what);
  printf("  $ elasticarm %.300s -> exit %d: %.300s\n", args, rc, out);
}

/* Options: --opt=value, abbreviations, negative values, clear errors (getopt_long). */
static void test_options(const char *arm) {
  char a[2048];
  snprintf(a, sizeof a, "statics --arm %s --tip=0.4,-0.2 --json", arm);
  expect(0, a, "\"tip_m\"", "--tip=X,Y is read (it was 'needs a value')");
  ea_test_abs(json_list("tip_m", 0), 0.4, 1e-9, "--tip=0.4,-0.2: the tip asked for (x)");
  ea_test_abs(json_list("tip_m", 1), -0.2, 1e-9, "--tip=0.4,-0.2: the tip asked for (y)");
  snprintf(a, sizeof a, "statics --arm %s --tip 0.4,-0.2 --json", arm);
  expect(0, a, "\"tip_m\"", "--tip X,Y with a negative second value");
  ea_test_abs(json_list("tip_m", 1), -0.2, 1e-9, "--tip 0.4,-0.2: y");
  snprintf(a, sizeof a, "statics --arm %s --tip -0.1,0.3 --json", arm);
  expect(0, a, "\"tip_m\"", "--tip with a value that starts with '-'");
  ea_test_abs(json_list("tip_m", 0), -0.1, 1e-9, "--tip -0.1,0.3: x");
  ea_test_abs(json_list("tip_m", 1), 0.3, 1e-9, "--tip -0.1,0.3: y");
  snprintf(a, sizeof a, "statics --ar=%s --ti 0.45,-0.1 --js", arm);
  expect(0, a, "\"tip_m\"", "unambiguous abbreviations (--ar, --ti, --js)");
  ea_test_abs(json_list("tip_m", 0), 0.45, 1e-9, "--ti 0.45,-0.1: x");
  expect(2, "statics --payload 1 --tip 0.4,-0.2",
         "option '--payload' is ambiguous (--payload-factor, --payload-kg)",
         "an ambiguous abbreviation names the options it could be");
  expect(2, "statics --json=1 --tip 0.4,-0.2", "--json takes no value", "a value given to a flag");
  expect(2, "statics --tip", "--tip needs a value", "a missing value");
  expect(2, "statics --bogus=1", "unknown option '--bogus'", "an unknown option with =value");
  expect(2, "plan x.yaml --knots=2", "--knots: value 2 is outside [3, 4000]",
         "--knots=N is read and checked");
  expect(2, "simulate --dt=-1 x.csv", "--dt: value -1 is outside", "a negative --opt=value");
  expect(2, "stream x.csv --rate-hz=0 --to tcp://127.0.0.1:1", "--rate-hz: value 0",
         "stream reads --opt=value");
  expect(2, "controller-sim --max-fr=0", "--max-frames: value 0", "controller-sim abbreviation");
  expect(2, "study payload --payload-factors 0 --thr=-1", "--threads: value -1 is outside [0,",
         "study reads --opt=value");
  expect(2, "frequencies --cable-length=0.4 --cable-angle-deg=-20 --modes=0",
         "--modes: value 0 is outside", "frequencies reads --opt=value");
}

/* figure takes --figure like every other command (and still -o); study --threads 0 is
 * auto; --figure-format without figures is refused. */
static void test_spellings(const char *arm) {
  (void)arm;
  const char *src = getenv("EA_SOURCE_DIR");
  char a[4096], traj[700], fig[700], fig2[700];
  snprintf(traj, sizeof traj, "%s/line.csv", dir);
  snprintf(fig, sizeof fig, "%s/line.svg", dir);
  snprintf(fig2, sizeof fig2, "%s/line2.svg", dir);
  snprintf(a, sizeof a, "plan %s/problems/examples/paper-line.yaml -o %s --quiet", src, traj);
  expect(0, a, NULL, "a plan to draw");
  snprintf(a, sizeof a, "figure %s --figure %s", traj, fig);
  expect(0, a, "wrote", "figure --figure OUT");
  struct stat sb;
  ea_test_true(stat(fig, &sb) == 0 && sb.st_size > 1000, "figure --figure wrote the figure");
  snprintf(a, sizeof a, "figure %s -o %s", traj, fig2);
  expect(0, a, "wrote", "figure -o OUT still works");
  ea_test_true(stat(fig2, &sb) == 0 && sb.st_size > 1000, "figure -o wrote the figure");
  snprintf(a, sizeof a, "figure %s -o %s --figure %s", traj, fig, fig2);
  expect(2, a, "two figure paths", "two different figure paths are refused");

  snprintf(a, sizeof a,
           "study payload --payload-factors 0,0.1 --points 5 --threads 0 --no-checkpoint -o "
           "%s/ws.csv --summary %s/ws.json",
           dir, dir);
  expect(0, a, "study payload: 2 case(s)", "study --threads 0 = every online core");
  const long cores = sysconf(_SC_NPROCESSORS_ONLN);
  char want[64];
  snprintf(want, sizeof want, ", %d thread(s)", cores < 2 ? 1 : 2); /* 2 cases: at most 2 */
  ea_test_true(strstr(out, want) != NULL, "--threads 0: as many workers as cores (and cases)");
  snprintf(a, sizeof a,
           "study payload --payload-factors 0 --figure-format png --no-checkpoint -o %s/ws2.csv",
           dir);
  expect(2, a, "--figure-format png needs --figures", "--figure-format without --figures");
}

/* workspace: --payload-factor is --payload-factors; --payload-kg gives the same region as
 * the factor m_p / (m_h + rho L) of eq. 17 computed here from the arm file. */
static void test_workspace_payload(const char *arm_path) {
  ea_arm_t arm;
  ea_error_t err = {0};
  ea_test_true(ea_arm_load(arm_path, &arm, &err) == EA_OK, "arm file loads");
  const double mp = 0.05, gamma = mp / (arm.m_hand + arm.rho * arm.length);
  char a[2048];
  snprintf(a, sizeof a, "workspace --arm %s --points 9 --payload-factors %.17g --json", arm_path,
           gamma);
  expect(0, a, "\"area_m2\"", "workspace --payload-factors G");
  const double area = json_num("area_m2");
  snprintf(a, sizeof a, "workspace --arm %s --points 9 --payload-kg %.17g --json", arm_path, mp);
  expect(0, a, "\"area_m2\"", "workspace --payload-kg M (it was ignored)");
  ea_test_rel(json_num("payload_factor"), gamma, 1e-12, "--payload-kg: the factor of eq. 17");
  ea_test_rel(json_num("area_m2"), area, 1e-12, "--payload-kg M: the region of its factor");
  snprintf(a, sizeof a, "workspace --arm %s --points 9 --payload-factor %.17g --json", arm_path,
           gamma);
  expect(0, a, "\"area_m2\"", "workspace --payload-factor G (it was ignored)");
  ea_test_rel(json_num("payload_factor"), gamma, 1e-12, "--payload-factor: that factor");
  ea_test_rel(json_num("area_m2"), area, 1e-12, "--payload-factor G = --payload-factors G");
}

static double now_s(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* The whole text of a file into buf. */
static void slurp(const char *path, char *buf, size_t cap) {
  buf[0] = '\0';
  FILE *fp = fopen(path, "r");
  if (!fp) return;
  const size_t n = fread(buf, 1, cap - 1, fp);
  buf[n] = '\0';
  fclose(fp);
}

/* The number after text in s (NAN if absent). */
static double num_after(const char *s, const char *text) {
  const char *p = strstr(s, text);
  return p ? strtod(p + strlen(text), NULL) : NAN;
}

/* What the printed numbers are: simulate's time to rest before or after the motion's end
 * (the motion's duration read from the file by the library); the plan figure's FE residual,
 * labelled as measured, equal to what `simulate` measures on the written file; END's reason
 * named (docs/protocol.md). */
static void test_numbers(void) {
  const char *src = getenv("EA_SOURCE_DIR");
  char a[4096], traj[700], fig[700], sum[700];
  snprintf(traj, sizeof traj, "%s/rest.csv", dir);
  snprintf(fig, sizeof fig, "%s/rest.svg", dir);
  snprintf(sum, sizeof sum, "%s/rest.json", dir);
  snprintf(a, sizeof a,
           "plan %s/problems/examples/paper-line-rest.yaml --refine --verify -o %s --figure %s "
           "--quiet",
           src, traj, fig);
  expect(0, a, NULL, "an at-rest plan, refined and verified, with its figure");
  ea_traj_t tr = {0};
  ea_error_t err = {0};
  ea_test_true(ea_traj_read(&tr, traj, &err) == EA_OK, "the plan reads back");
  const double duration =
      tr.n > 1 ? EA_TRAJ_AT(&tr, tr.n - 1, EA_TRAJ_t) - EA_TRAJ_AT(&tr, 0, 0) : NAN;
  ea_traj_free(&tr);

  snprintf(a, sizeof a, "simulate %s --json", traj);
  expect(0, a, "\"time_to_rest_s\"", "simulate --json");
  const double t_rest = json_num("time_to_rest_s"), peak = json_num("residual_vibration_peak_m");
  snprintf(a, sizeof a, "simulate %s", traj);
  expect(0, a, "rest         within", "simulate's text");
  ea_test_true(strstr(out, "-0.") == NULL || strstr(out, "s after the motion") == NULL,
               "no negative time 'after the motion'");
  const int before = t_rest < duration;
  char want[200];
  snprintf(want, sizeof want, "(%.4g s %s the motion ends)", fabs(t_rest - duration),
           before ? "before" : "after");
  ea_test_true(strstr(out, want) != NULL,
               "simulate: the time to rest before/after the motion's end");
  printf("  want '%s' (time to rest %.6g s, motion %.6g s)\n", want, t_rest, duration);

  static char svg[1 << 21];
  slurp(fig, svg, sizeof svg);
  ea_test_true(strstr(svg, "FE transient of this trajectory (plan --verify):") != NULL,
               "the figure names the FE check it shows");
  ea_test_rel(num_after(svg, "measured residual vibration peak: "), 1e3 * peak, 6e-3,
              "the figure's measured residual = simulate's on the file [mm]");
  ea_test_true(strstr(svg, "model-predicted residual vibration: ") != NULL,
               "the model's prediction is labelled as the model's");

  snprintf(a, sizeof a,
           "plan %s/problems/examples/paper-line-rest.yaml --refine -o %s --figure %s "
           "--summary %s --quiet",
           src, traj, fig, sum);
  expect(0, a, NULL, "the refined plan without --verify");
  static char js[1 << 20];
  slurp(sum, js, sizeof js);
  const char *ref = strstr(js, "\"returned_evaluation\"");
  const double ref_peak = ref ? num_after(ref, "\"residual_peak_m\": ") : NAN;
  slurp(fig, svg, sizeof svg);
  ea_test_true(strstr(svg, "FE transient of this trajectory (refinement):") != NULL,
               "without --verify: the refinement's FE check, named");
  ea_test_rel(num_after(svg, "measured residual vibration peak: "), 1e3 * ref_peak, 6e-3,
              "the figure's measured residual = the summary's refined FE residual [mm]");

  /* END(refused): a controller away from the trajectory's start */
  char pf[700];
  snprintf(pf, sizeof pf, "%s/port", dir);
  snprintf(a, sizeof a,
           "controller-sim --listen 127.0.0.1:0 --port-file %s --initial 0.6,0.5,0 --timeout 10 "
           "> %s/sim.out 2>&1 & "
           "for i in 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19 20; do "
           "[ -s %s ] && break; sleep 0.1; done; "
           "%s stream %s --to tcp://127.0.0.1:$(cat %s); wait; cat %s/sim.out",
           pf, dir, pf, bin, traj, pf, dir);
  run(a);
  printf("  controller-sim: %.600s\n", out);
  ea_test_true(strstr(out, "END reason 2: refused") != NULL,
               "controller-sim names END reason 2 (refused, docs/protocol.md)");
}

/* 3-D plans: --verify says that the FE transient is planar, in the text and the JSON, with
 * the base's travel (90 deg in the task: its start and goal bearings); the figure has a top
 * view. */
static void test_planar_note(void) {
  const char *src = getenv("EA_SOURCE_DIR");
  char a[4096], traj[700], fig[700];
  snprintf(traj, sizeof traj, "%s/pp3.csv", dir);
  snprintf(fig, sizeof fig, "%s/pp3.svg", dir);
  snprintf(a, sizeof a, "plan %s/problems/examples/pick-place-3d.yaml --verify -o %s --figure %s",
           src, traj, fig);
  expect(0, a, "verify: the FE transient is planar", "plan --verify says the transient is planar");
  ea_test_true(strstr(out, "the base turns 90 deg") != NULL, "... and how far the base turns");
  snprintf(a, sizeof a, "plan %s/problems/examples/pick-place-3d.yaml --verify -o %s --json", src,
           traj);
  expect(0, a, "\"transient\": \"planar", "the summary's verify object says so");
  ea_test_rel(json_num("base_travel_rad"), M_PI / 2, 1e-9, "verify.base_travel_rad: 90 deg");
  static char svg[1 << 21];
  slurp(fig, svg, sizeof svg);
  ea_test_true(strstr(svg, "top view") != NULL, "the 3-D plan's figure has a top view");
  snprintf(a, sizeof a, "simulate %s", traj);
  expect(0, a, "planar       the transient is in the arm's plane", "simulate says it too");
  snprintf(a, sizeof a, "plan %s/problems/examples/paper-line.yaml --verify -o %s", src, traj);
  expect(0, a, "verify: FE residual", "a planar plan");
  ea_test_true(strstr(out, "is planar") == NULL, "no note when the base does not turn");
}

/* Long jobs: the time line counts the whole command with its phases named; progress on
 * stderr after a second (refinement evaluations, study cases with the time left); --quiet
 * silences it. Checked against the wall time measured here. */
static void test_progress(void) {
  const char *src = getenv("EA_SOURCE_DIR");
  char a[4096];
  snprintf(a, sizeof a,
           "plan %s/problems/examples/paper-line-robust.yaml --refine --verify -o %s/rob.csv", src,
           dir);
  double t0 = now_s();
  /* The refinement stops at its wall-time cap (refine.max_time_s) on a slow machine (a
   * sanitizer build): then the plan is written, verify fails its bound and the exit is 3
   * (docs/task-format.md). Either way the command ran long and printed its time line. */
  const int rc = run(a);
  printf("  $ elasticarm %.300s -> exit %d: %.300s\n", a, rc, out);
  ea_test_true((rc == 0 || (rc == 3 && strstr(out, "NOT reached"))) && strstr(out, "time: "),
               "a long plan (refined against five FE arms, verified): done, or its refinement "
               "stopped at the time cap and said so (exit 3)");
  double wall = now_s() - t0;
  const double total = 1e-3 * num_after(out, "time: ");
  printf("  time line %.3f s, wall %.3f s\n", total, wall);
  ea_test_true(total <= wall && total >= 0.8 * wall - 0.1,
               "the time line's total is the command's wall time");
  ea_test_true(strstr(out, "refinement ") && strstr(out, "--verify FE transient ") &&
                   strstr(out, "plan "),
               "the time line names its phases");
  ea_test_true(strstr(out, "elasticarm plan: refinement: evaluation ") != NULL,
               "progress: the refinement's evaluations on stderr");

  snprintf(a, sizeof a,
           "study payload --payload-factors 0:0.02:1 --metrics workspace,frequencies --config "
           "0.4:-20 --threads 1 --no-checkpoint -o %s/st.csv",
           dir);
  t0 = now_s();
  expect(0, a, "study payload: 51 case(s)", "a study of a few seconds");
  wall = now_s() - t0;
  if (wall < 1.3) {
    printf("SKIP: the study ran %.2f s: too fast for a progress line\n", wall);
  } else {
    const char *p = strstr(out, "elasticarm study: ");
    ea_test_true(p && strstr(p, " / 51 cases"), "progress: study cases on stderr");
    const char *l = p ? strstr(p, "s left") : NULL;
    if (l) {
      const double el = num_after(p, "%), "), left = num_after(p, "about ");
      printf("  at %.2f s: about %g s left; the study took %.2f s\n", el, left, wall);
      ea_test_true(el + left > 0.5 * wall && el + left < 2.0 * wall + 1.0,
                   "the time left is about the time the study still took");
    }
  }
  snprintf(a, sizeof a,
           "study payload --payload-factors 0:0.02:1 --metrics workspace,frequencies --config "
           "0.4:-20 --threads 1 --no-checkpoint -o %s/st.csv --quiet",
           dir);
  expect(0, a, NULL, "the study, --quiet");
  ea_test_true(strstr(out, "elasticarm study:") == NULL, "study --quiet: no progress");
}

int main(void) {
  char arm[1024];
  if (cli_setup(arm, sizeof arm)) return 1;
  snprintf(dir, sizeof dir, "/tmp/ea_cli_ux.%ld", (long)getpid());
  mkdir(dir, 0700);
  test_options(arm);
  test_spellings(arm);
  test_workspace_payload(arm);
  test_numbers();
  test_planar_note();
  test_progress();
  char cmd[700];
  snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
  if (system(cmd)) printf("could not remove %s\n", dir);
  return ea_test_summary("test_cli_ux");
}
