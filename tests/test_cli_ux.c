/* The CLI's usability as an outside review asked for it: options read by getopt_long
 * ("--opt=value", abbreviations, negative values), one spelling per meaning, what the
 * printed numbers are, progress of long jobs. Values are checked against what was asked
 * (the tip given), against the arm file read through the library, or against the
 * documented protocol. */
#include "ea_problems.h"
#include "ea_test.h"
#include "ea_test_cli.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
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

int main(void) {
  char arm[1024];
  if (cli_setup(arm, sizeof arm)) return 1;
  snprintf(dir, sizeof dir, "/tmp/ea_cli_ux.%ld", (long)getpid());
  mkdir(dir, 0700);
  test_options(arm);
  test_spellings(arm);
  test_workspace_payload(arm);
  char cmd[700];
  snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
  if (system(cmd)) printf("could not remove %s\n", dir);
  return ea_test_summary("test_cli_ux");
}
