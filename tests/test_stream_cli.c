/* The stream and controller-sim subcommands as processes: a clean session
 * with a log, SIGINT to the streamer mid-stream (controlled stop, exit 1,
 * the simulator's log ends at rest), a dry run to a file, a too-fast
 * trajectory refused before anything is sent, and controller-sim --simulate
 * (FE transient of the accepted setpoints) for a complete and a SIGINT-stopped
 * stream, checked against the ODE statics. Loopback only, bounded. */
#include "ea_test.h"
#include "ea_test_proc.h"
#include "stream_impl.h"
#include "test_stream_fixture.h"

#include <math.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

static const char *bin;

static pid_t start_sim(const char *log, int *port) {
  remove("cli_sim.port");
  char *argv[] = {
      (char *)bin, "controller-sim", "--listen",  "127.0.0.1:0", "--port-file", "cli_sim.port",
      "--log",     (char *)log,      "--timeout", "5",           NULL};
  const pid_t pid = ea_test_spawn(argv, "cli_sim.out", "cli_sim.err");
  *port = ea_test_read_port("cli_sim.port", 300);
  return pid;
}

/* controller-sim with --simulate TIP --settle 0.5 --json (summary to json). */
static pid_t start_sim_fe(const char *log, const char *tipf, const char *json, int *port) {
  remove("cli_sim.port");
  remove(tipf);
  char *argv[] = {(char *)bin,   "controller-sim",
                  "--listen",    "127.0.0.1:0",
                  "--port-file", "cli_sim.port",
                  "--log",       (char *)log,
                  "--timeout",   "5",
                  "--simulate",  (char *)tipf,
                  "--settle",    "0.5",
                  "--json",      NULL};
  const pid_t pid = ea_test_spawn(argv, json, "cli_sim.err");
  *port = ea_test_read_port("cli_sim.port", 300);
  return pid;
}

/* Number after "key": in a JSON text; the first two of an array for vec. NAN if absent. */
static double json_num(const char *buf, const char *key, int idx) {
  char pat[96];
  snprintf(pat, sizeof pat, "\"%s\":", key);
  const char *p = strstr(buf, pat);
  if (!p) return NAN;
  p += strlen(pat);
  while (*p == ' ' || *p == '[')
    ++p;
  for (int k = 0; k < idx; ++k) {
    p = strchr(p, ',');
    if (!p) return NAN;
    ++p;
  }
  char *end;
  const double v = strtod(p, &end);
  return end == p ? NAN : v;
}

/* A physically consistent move (every sample an ODE statics solution): cable length
 * L0 -> L0 + dL and cable angle a0 -> a0 + da along the septic smoothstep in Tm s,
 * sampled every 10 ms; theta0 rates by centred differences (0 at the rest ends). */
static int make_phys_traj(const ea_arm_t *arm, const char *arm_file, double Tm, double L0,
                          double dL, double a0, double da, const char *path) {
  const int n = (int)(Tm / 0.01 + 0.5) + 1;
  ea_traj_t tr = {0};
  ea_shooter_t *sh = NULL;
  if (ea_traj_alloc(&tr, n) || ea_shooter_alloc(arm, NULL, &sh, NULL)) return 1;
  ea_load_t load = {arm->m_hand};
  ea_shooter_set_load(sh, &load);
  tr.payload_kg = 0;
  tr.tip_mass_kg = arm->m_hand;
  snprintf(tr.arm_file, sizeof tr.arm_file, "%s", arm_file);
  snprintf(tr.task, sizeof tr.task, "%s", "test: statics along a septic smoothstep");
  snprintf(tr.status, sizeof tr.status, "%s", "EA_OK");
  double guess[EA_NP];
  int rc = 0;
  for (int i = 0; i < n && !rc; ++i) {
    const double t = (i == n - 1) ? Tm : i * 0.01;
    double u, ud, udd;
    fx_step(Tm, t, &u, &ud, &udd);
    const double L = L0 + dL * u, a = a0 + da * u;
    ea_statics_problem_t pr = ea_statics_problem_cable(L, a);
    ea_statics_solution_t sol;
    if (ea_statics_solve(sh, &pr, NULL, i ? guess : NULL, &sol, NULL)) rc = 1;
    memcpy(guess, sol.p, sizeof guess);
    EA_TRAJ_AT(&tr, i, EA_TRAJ_t) = t;
    EA_TRAJ_AT(&tr, i, EA_TRAJ_cable_length) = L;
    EA_TRAJ_AT(&tr, i, EA_TRAJ_cable_angle) = a;
    EA_TRAJ_AT(&tr, i, EA_TRAJ_cable_length_rate) = dL * ud;
    EA_TRAJ_AT(&tr, i, EA_TRAJ_cable_angle_rate) = da * ud;
    EA_TRAJ_AT(&tr, i, EA_TRAJ_cable_length_acc) = dL * udd;
    EA_TRAJ_AT(&tr, i, EA_TRAJ_cable_angle_acc) = da * udd;
    ea_traj_set_statics(&tr, i, sol.p, sol.tip, arm->EI);
  }
  for (int i = 1; i < n - 1 && !rc; ++i)
    EA_TRAJ_AT(&tr, i, EA_TRAJ_theta0_rate) =
        (EA_TRAJ_AT(&tr, i + 1, EA_TRAJ_theta0) - EA_TRAJ_AT(&tr, i - 1, EA_TRAJ_theta0)) /
        (EA_TRAJ_AT(&tr, i + 1, EA_TRAJ_t) - EA_TRAJ_AT(&tr, i - 1, EA_TRAJ_t));
  if (!rc && ea_traj_write(&tr, path, NULL)) rc = 1;
  ea_traj_free(&tr);
  ea_shooter_free(sh);
  return rc;
}

/* Tip history: rows, first and last time, last tip (x, y). */
static int tip_rows(const char *path, double *t_first, double *t_last, double last[2]) {
  FILE *fp = fopen(path, "r");
  if (!fp) return -1;
  char line[512];
  int n = 0, header = 0;
  while (fgets(line, sizeof line, fp)) {
    if (!strncmp(line, "t_s,tip_x_m,tip_y_m,tip_theta_rad", 33)) {
      header = 1;
      continue;
    }
    double t, x, y, th;
    if (sscanf(line, "%lf,%lf,%lf,%lf", &t, &x, &y, &th) != 4) continue;
    if (!n) *t_first = t;
    *t_last = t;
    last[0] = x;
    last[1] = y;
    ++n;
  }
  fclose(fp);
  return header ? n : -1;
}

/* RMS and peak of |tip(t) - c| over the tip file's rows with t >= t_from
 * (the residual vibration recomputed from the raw history); returns the
 * number of rows used (-1 if unreadable). */
static int tip_residual(const char *path, double t_from, const double c[2], double *rms,
                        double *peak) {
  FILE *fp = fopen(path, "r");
  if (!fp) return -1;
  char line[512];
  int n = 0;
  double s2 = 0;
  *peak = 0;
  while (fgets(line, sizeof line, fp)) {
    double t, x, y, th;
    if (sscanf(line, "%lf,%lf,%lf,%lf", &t, &x, &y, &th) != 4 || t < t_from) continue;
    const double d = hypot(x - c[0], y - c[1]);
    s2 += d * d;
    if (!(d <= *peak)) *peak = d; /* NaN propagates */
    ++n;
  }
  fclose(fp);
  *rms = n ? sqrt(s2 / n) : NAN;
  return n;
}

/* Last row of a controller log: time, cable length, theta0. */
static int log_last(const char *path, double *t, double *L, double *theta0) {
  FILE *fp = fopen(path, "r");
  if (!fp) return 1;
  char line[4096];
  int ok = 0;
  while (fgets(line, sizeof line, fp)) {
    if (line[0] == '#' || !strncmp(line, "seq,", 4)) continue;
    double c[17];
    char *p = line;
    int k = 0;
    for (; k < 17; ++k) {
      char *end;
      c[k] = strtod(p, &end);
      if (end == p) break;
      p = *end == ',' ? end + 1 : end;
    }
    if (k == 17) {
      *t = c[2];
      *theta0 = c[8];
      *L = c[16];
      ok = 1;
    }
  }
  fclose(fp);
  return !ok;
}

/* Rows of a log (non-comment, non-header) and the velocities of the last. */
static int log_rows(const char *path, double *v_last) {
  FILE *fp = fopen(path, "r");
  if (!fp) return -1;
  char line[4096];
  int n = 0;
  while (fgets(line, sizeof line, fp)) {
    if (line[0] == '#' || !strncmp(line, "seq,", 4)) continue;
    ++n;
    /* seq,source,time,recv,spool0,spool1,spool_vel,spool_acc,sh,sh_vel,sh_acc,base,base_vel */
    double c[13];
    if (sscanf(line, "%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf", &c[0], &c[1], &c[2],
               &c[3], &c[4], &c[5], &c[6], &c[7], &c[8], &c[9], &c[10], &c[11], &c[12]) == 13)
      *v_last = fabs(c[6]) + fabs(c[9]) + fabs(c[12]);
  }
  fclose(fp);
  return n;
}

static void slurp(const char *path, char *buf, size_t cap) {
  buf[0] = 0;
  FILE *fp = fopen(path, "r");
  if (!fp) return;
  const size_t k = fread(buf, 1, cap - 1, fp);
  buf[k] = 0;
  fclose(fp);
}

/* First setpoint frame of a dry-run file: 0 if found. */
static int first_setpoint(const char *path, ea_setpoint_t *sp) {
  FILE *fp = fopen(path, "rb");
  if (!fp) return 1;
  ea_frame_parser_t p;
  ea_frame_parser_init(&p);
  uint8_t buf[4096];
  size_t k;
  int found = 0;
  while (!found && (k = fread(buf, 1, sizeof buf, fp)) > 0) {
    size_t off = 0;
    while (off < k && !found) {
      off += ea_frame_parser_feed(&p, buf + off, k - off);
      ea_frame_t f;
      int r;
      while (!found && (r = ea_frame_parser_next(&p, &f)) != 0)
        if (r > 0 && f.type == EA_FRAME_SETPOINT) {
          *sp = f.sp;
          found = 1;
        }
    }
  }
  fclose(fp);
  return !found;
}

/* The arm file with the spool radius replaced (the rest as in src). */
static int write_arm_spool(const char *src, const char *dst, double radius) {
  FILE *in = fopen(src, "r"), *out = fopen(dst, "w");
  char line[1024];
  int done = 0;
  while (in && out && fgets(line, sizeof line, in)) {
    if (strstr(line, "radius_m:")) {
      fprintf(out, "    radius_m: %.17g\n", radius);
      ++done;
    } else {
      fputs(line, out);
    }
  }
  if (in) fclose(in);
  if (out) fclose(out);
  return done == 1 ? 0 : 1;
}

/* stream takes the arm a trajectory was planned for (its '# arm_file:'):
 * the spool positions follow that arm's spool radius, and a different
 * --arm is refused. Reference: the spool map of docs/protocol.md,
 * (L_c - zero_length) / radius * gear, at the fixture's start L0. */
static void test_recorded_arm(const char *arm_src, const fx_move_t *m) {
  const double r30 = 0.030;
  ea_test_true(write_arm_spool(arm_src, "cli_arm30.yaml", r30) == 0,
               "arm file with a 30 mm spool written");
  ea_arm_t a30, a15;
  const int ok = ea_arm_load("cli_arm30.yaml", &a30, NULL) == EA_OK &&
                 ea_arm_load(arm_src, &a15, NULL) == EA_OK;
  ea_test_true(ok && a30.act.spool_radius == r30 && a15.act.spool_radius != r30,
               "the two arm files differ in the spool radius only");
  if (!ok) return;
  ea_traj_t tr = {0};
  fx_make_traj(m, &a30, 0.02, &tr);
  snprintf(tr.arm_file, sizeof tr.arm_file, "%s", "cli_arm30.yaml");
  ea_traj_write(&tr, "cli_move30.csv", NULL);
  ea_traj_free(&tr);
  const double want = (m->L0 - a30.act.spool_zero_length) / r30 * a30.act.spool_gear_ratio;
  {
    remove("cli_arm30.bin");
    char *argv[] = {(char *)bin, "stream", "cli_move30.csv", "--to", "file:cli_arm30.bin", NULL};
    const int rc = ea_test_wait_for(ea_test_spawn(argv, "cli_arm30.out", "cli_arm30.err"), 5000);
    char err[2048];
    slurp("cli_arm30.err", err, sizeof err);
    ea_setpoint_t sp;
    memset(&sp, 0, sizeof sp);
    const int bad = first_setpoint("cli_arm30.bin", &sp);
    printf("recorded arm: exit %d, first spool position %.12g rad (30 mm spool: %.12g); %s", rc,
           sp.spool_pos[0], want, err);
    ea_test_true(rc == 0 && strstr(err, "cli_arm30.yaml") != NULL,
                 "stream: no --arm: the trajectory's arm file, said on stderr");
    ea_test_true(!bad && fabs(sp.spool_pos[0] - want) <= 1e-9 * fabs(want) &&
                     fabs(sp.spool_pos[1] - want) <= 1e-9 * fabs(want),
                 "stream: spool positions from the recorded arm's 30 mm spool (rel 1e-9)");
  }
  {
    remove("cli_arm15.bin");
    char *argv[] = {(char *)bin,          "stream", "cli_move30.csv", "--to",
                    "file:cli_arm15.bin", "--arm",  (char *)arm_src,  NULL};
    const int rc = ea_test_wait_for(ea_test_spawn(argv, "cli_arm15.out", "cli_arm15.err"), 5000);
    char err[2048];
    slurp("cli_arm15.err", err, sizeof err);
    printf("mismatched --arm: exit %d: %s", rc, err);
    ea_test_true(rc == 2 && strstr(err, "spool_radius") && access("cli_arm15.bin", F_OK) != 0,
                 "stream: --arm differing from the trajectory's arm refused (exit 2), nothing "
                 "sent");
  }
  {
    char *argv[] = {(char *)bin,           "stream", "cli_move30.csv", "--to",
                    "file:cli_arm30b.bin", "--arm",  "cli_arm30.yaml", NULL};
    const int rc = ea_test_wait_for(ea_test_spawn(argv, "cli_arm30.out", "cli_arm30.err"), 5000);
    ea_test_true(rc == 0, "stream: --arm equal to the trajectory's arm accepted");
  }
  /* A recorded arm file that cannot be read, no --arm: refused. */
  ea_traj_read(&tr, "cli_move30.csv", NULL);
  snprintf(tr.arm_file, sizeof tr.arm_file, "%s", "cli_no_such_arm.yaml");
  ea_traj_write(&tr, "cli_move_noarm.csv", NULL);
  ea_traj_free(&tr);
  {
    char *argv[] = {(char *)bin,          "stream", "cli_move_noarm.csv", "--to",
                    "file:cli_noarm.bin", NULL};
    const int rc = ea_test_wait_for(ea_test_spawn(argv, "cli_arm30.out", "cli_arm30.err"), 5000);
    char err[2048];
    slurp("cli_arm30.err", err, sizeof err);
    ea_test_true(rc == 2 && strstr(err, "cli_no_such_arm.yaml") &&
                     access("cli_noarm.bin", F_OK) != 0,
                 "stream: unreadable recorded arm file and no --arm: refused (exit 2)");
  }
  const char *tmp[] = {"cli_arm30.yaml", "cli_move30.csv", "cli_arm30.bin",     "cli_arm30b.bin",
                       "cli_arm30.out",  "cli_arm30.err",  "cli_arm15.out",     "cli_arm15.err",
                       "cli_arm15.bin",  "cli_noarm.bin",  "cli_move_noarm.csv"};
  for (size_t i = 0; i < sizeof tmp / sizeof *tmp; ++i)
    remove(tmp[i]);
}

/* Edited trajectories the outside review streamed as "complete" (two plans joined, a row
 * 1e-7 s after another with a 3 rad base step after it, a plan cut short): refused with
 * exit 1 and a message naming what is wrong, nothing written. */
static void test_refused_edits(const ea_arm_t *arm, const char *arm_src, const fx_move_t *m) {
  ea_traj_t a = {0}, b = {0};
  fx_make_traj(m, arm, 0.02, &a);
  snprintf(a.arm_file, sizeof a.arm_file, "%s", arm_src);
  const int n = a.n;
  const double T = EA_TRAJ_AT(&a, n - 1, EA_TRAJ_t);
  struct {
    const char *name, *want;
  } c[3] = {{"joined", "between rows"}, {"row 1e-7 s after", "apart"}, {"cut", "end at rest"}};
  for (int k = 0; k < 3; ++k) {
    if (k == 0) { /* a second copy starting 1 ms after the first ends, base + 1 rad */
      ea_traj_alloc(&b, 2 * n);
      for (int i = 0; i < 2 * n; ++i)
        memcpy(&EA_TRAJ_AT(&b, i, 0), &EA_TRAJ_AT(&a, i % n, 0), EA_TRAJ_NCOL * sizeof(double));
      for (int i = n; i < 2 * n; ++i) {
        EA_TRAJ_AT(&b, i, EA_TRAJ_t) += T + 1e-3;
        EA_TRAJ_AT(&b, i, EA_TRAJ_base_angle) += 1.0;
      }
    } else if (k == 1) { /* row 10 repeated 1e-7 s later, base + 3 rad from there on */
      ea_traj_alloc(&b, n + 1);
      for (int i = 0; i <= n; ++i)
        memcpy(&EA_TRAJ_AT(&b, i, 0), &EA_TRAJ_AT(&a, i <= 10 ? i : i - 1, 0),
               EA_TRAJ_NCOL * sizeof(double));
      for (int i = 11; i <= n; ++i) {
        EA_TRAJ_AT(&b, i, EA_TRAJ_t) += 1e-7;
        EA_TRAJ_AT(&b, i, EA_TRAJ_base_angle) += 3.0;
      }
    } else { /* cut at its middle, still moving */
      ea_traj_alloc(&b, n / 2);
      memcpy(b.data, a.data, (size_t)(n / 2) * EA_TRAJ_NCOL * sizeof(double));
    }
    snprintf(b.arm_file, sizeof b.arm_file, "%s", arm_src);
    ea_traj_write(&b, "cli_edit.csv", NULL);
    remove("cli_edit.bin");
    char *argv[] = {(char *)bin, "stream", "cli_edit.csv", "--to", "file:cli_edit.bin", NULL};
    const int rc = ea_test_wait_for(ea_test_spawn(argv, "cli_edit.out", "cli_edit.err"), 10000);
    char err[4096];
    slurp("cli_edit.err", err, sizeof err);
    char what[200];
    snprintf(what, sizeof what, "%s trajectory: refused (exit %d), nothing written, says '%s'",
             c[k].name, rc, c[k].want);
    ea_test_true(rc == 1 && access("cli_edit.bin", F_OK) != 0 && strstr(err, c[k].want), what);
    if (rc != 1 || !strstr(err, c[k].want)) printf("  stderr: %s\n", err);
  }
  ea_traj_free(&a);
  ea_traj_free(&b);
  remove("cli_edit.csv");
  remove("cli_edit.out");
  remove("cli_edit.err");
}

/* A copy of the arm file src with the spool's gear ratio replaced. */
static int write_arm_gear(const char *src, const char *dst, double gear) {
  FILE *in = fopen(src, "r"), *out = fopen(dst, "w");
  char line[1024];
  int done = 0;
  while (in && out && fgets(line, sizeof line, in)) {
    if (strstr(line, "gear_ratio:")) {
      fprintf(out, "    gear_ratio: %.17g\n", gear);
      ++done;
    } else {
      fputs(line, out);
    }
  }
  if (in) fclose(in);
  if (out) fclose(out);
  return done == 1 ? 0 : 1;
}

/* Copy a file; 0 on success. */
static int copy_file(const char *src, const char *dst) {
  FILE *in = fopen(src, "rb"), *out = fopen(dst, "wb");
  char buf[4096];
  size_t k;
  int ok = in && out;
  while (ok && (k = fread(buf, 1, sizeof buf, in)) > 0)
    ok = fwrite(buf, 1, k, out) == k;
  if (in) fclose(in);
  if (out && fclose(out)) ok = 0;
  return !ok;
}

/* Run argv in folder dir (stdout and stderr to files there); the exit code, stderr in err. */
static int run_in(const char *dir, char *const argv[], char *err, size_t len) {
  char here[4096];
  if (!getcwd(here, sizeof here) || chdir(dir)) return -2;
  const int rc = ea_test_wait_for(ea_test_spawn(argv, "run.out", "run.err"), 20000);
  slurp("run.err", err, len);
  if (chdir(here)) return -2;
  return rc;
}

/* A plan names its arm unambiguously: `plan` run in folder A records A's arm file by its
 * absolute path and the arm's hash. Run from folder B, which has another arm (gear ratio 2)
 * at the relative path the task names, stream uses A's arm (spool positions of gear 1:
 * the spool map of docs/protocol.md, (L_c - zero_length) / radius * gear, at the
 * trajectory's first cable length); an older file (relative arm_file, no hash) is read
 * relative to its own folder. When A's arm file is replaced, stream, simulate and figure
 * refuse, naming both hashes; --arm overrides (stream: only with the planned arm). */
static void test_arm_moved(const char *src) {
  char D[] = "/tmp/ea_test_armhash_XXXXXX";
  if (!mkdtemp(D)) {
    ea_test_true(0, "temp dir");
    return;
  }
  char a[600], b[600], p[900], q[900], arm_a[900], arm_b[900], good[900], err[8192];
  snprintf(a, sizeof a, "%s/a", D);
  snprintf(b, sizeof b, "%s/b", D);
  const char *sub[] = {"a", "a/problems", "a/problems/examples", "a/data",
                       "b", "b/problems", "b/problems/examples", "b/data"};
  for (size_t i = 0; i < sizeof sub / sizeof *sub; ++i) {
    snprintf(p, sizeof p, "%s/%s", D, sub[i]);
    mkdir(p, 0700);
  }
  snprintf(arm_a, sizeof arm_a, "%s/data/elasticarm.yaml", a);
  snprintf(arm_b, sizeof arm_b, "%s/data/elasticarm.yaml", b);
  snprintf(good, sizeof good, "%s/good.yaml", D);
  char arm_src[700], task_src[700], task_a[900];
  snprintf(arm_src, sizeof arm_src, "%s/data/elasticarm.yaml", src);
  snprintf(task_src, sizeof task_src, "%s/problems/examples/paper-line-smooth.yaml", src);
  snprintf(task_a, sizeof task_a, "%s/problems/examples/paper-line-smooth.yaml", a);
  int ok = write_arm_gear(arm_src, arm_a, 1.0) == 0 && write_arm_gear(arm_src, good, 1.0) == 0 &&
           write_arm_gear(arm_src, arm_b, 2.0) == 0 && copy_file(task_src, task_a) == 0;
  ea_arm_t g1, g2;
  ok = ok && ea_arm_load(arm_a, &g1, NULL) == EA_OK && ea_arm_load(arm_b, &g2, NULL) == EA_OK &&
       g1.act.spool_gear_ratio == 1.0 && g2.act.spool_gear_ratio == 2.0;
  ea_test_true(ok, "arm files of gear ratio 1 (folder a) and 2 (folder b), the task in a");
  if (!ok) return;
  {
    char *argv[] = {(char *)bin, "plan",     "problems/examples/paper-line-smooth.yaml",
                    "-o",        "plan.csv", NULL};
    ea_test_true(run_in(a, argv, err, sizeof err) == 0, "plan in folder a: exit 0");
  }
  snprintf(p, sizeof p, "%s/plan.csv", a);
  ea_traj_t tr = {0};
  ok = ea_traj_read(&tr, p, NULL) == EA_OK;
  printf("plan in a: arm_file '%s', arm hash %s %016llx (ea_arm_hash of gear 1: %016llx)\n",
         tr.arm_file, tr.has_arm_hash ? "yes" : "no", (unsigned long long)tr.arm_hash,
         (unsigned long long)ea_arm_hash(&g1));
  ea_test_true(ok && tr.arm_file[0] == '/' && tr.has_arm_hash && tr.arm_hash == ea_arm_hash(&g1),
               "the plan records an absolute arm_file and the hash of the arm it was planned for");
  if (!ok) return;
  const double L0 = EA_TRAJ_AT(&tr, 0, EA_TRAJ_cable_length);
  const double want = (L0 - g1.act.spool_zero_length) / g1.act.spool_radius;
  /* the same file in folder b; and an older file (relative arm_file, no hash) in a */
  char *line = NULL;
  size_t cap = 0;
  FILE *in = fopen(p, "r");
  snprintf(q, sizeof q, "%s/old.csv", a);
  FILE *o = fopen(q, "w");
  while (in && o && getline(&line, &cap, in) > 0) {
    if (!strncmp(line, "# arm_hash:", 11)) continue;
    if (!strncmp(line, "# arm_file:", 11))
      fputs("# arm_file: problems/examples/../../data/elasticarm.yaml\n", o);
    else
      fputs(line, o);
  }
  free(line);
  if (in) fclose(in);
  if (o) fclose(o);
  ea_traj_free(&tr);
  /* the planned file, copied to b (its absolute path kept): b's arm is not taken */
  snprintf(q, sizeof q, "%s/plan.csv", b);
  ok = ok && copy_file(p, q) == 0;
  struct {
    const char *traj, *what;
  } runs[] = {{"plan.csv", "a plan copied to folder b"},
              {"../a/old.csv", "an older file (relative arm_file, no hash) in folder a"}};
  for (int k = 0; k < 2; ++k) {
    char *argv[] = {(char *)bin, "stream", (char *)runs[k].traj, "--to", "file:sp.bin", NULL};
    const int rc = run_in(b, argv, err, sizeof err);
    snprintf(q, sizeof q, "%s/sp.bin", b);
    ea_setpoint_t sp;
    memset(&sp, 0, sizeof sp);
    const int bad = first_setpoint(q, &sp);
    remove(q);
    printf("stream %s from b: exit %d, first spool position %.12g rad (gear 1: %.12g)\n%s",
           runs[k].traj, rc, sp.spool_pos[0], want, err);
    char msg[200];
    snprintf(msg, sizeof msg, "stream of %s from folder b: folder a's arm (gear 1), rel 1e-9",
             runs[k].what);
    ea_test_true(rc == 0 && !bad && fabs(sp.spool_pos[0] - want) <= 1e-9 * fabs(want), msg);
    if (k == 1)
      ea_test_true(strstr(err, "no '# arm_hash:'") != NULL, "older file: a note says unchecked");
  }
  /* folder a's arm file replaced by the gear-2 arm: refused, both hashes and the path named */
  ok = write_arm_gear(arm_src, arm_a, 2.0) == 0;
  char hx[17], hy[17];
  snprintf(hx, sizeof hx, "%016llx", (unsigned long long)ea_arm_hash(&g1));
  snprintf(hy, sizeof hy, "%016llx", (unsigned long long)ea_arm_hash(&g2));
  const char *cmds[][6] = {{"stream", "plan.csv", "--to", "file:sp.bin", NULL, NULL},
                           {"simulate", "plan.csv", NULL, NULL, NULL, NULL},
                           {"figure", "plan.csv", "-o", "fig.svg", NULL, NULL}};
  for (int k = 0; k < 3; ++k) {
    char *argv[8] = {(char *)bin};
    for (int j = 0; j < 5 && cmds[k][j]; ++j)
      argv[j + 1] = (char *)cmds[k][j];
    const int rc = run_in(b, argv, err, sizeof err);
    snprintf(q, sizeof q, "%s/sp.bin", b);
    const int sent = access(q, F_OK) == 0;
    printf("%s with a's arm file changed: exit %d: %s", cmds[k][0], rc, err);
    char msg[200];
    snprintf(msg, sizeof msg,
             "%s: the arm file changed since the plan: exit 2 naming both hashes and the path",
             cmds[k][0]);
    ea_test_true(ok && rc == 2 && strstr(err, hx) && strstr(err, hy) && strstr(err, arm_a) && !sent,
                 msg);
  }
  {
    char *argv[] = {(char *)bin, "stream", "plan.csv", "--to", "file:sp.bin", "--arm", good, NULL};
    const int rc = run_in(b, argv, err, sizeof err);
    snprintf(q, sizeof q, "%s/sp.bin", b);
    ea_setpoint_t sp;
    memset(&sp, 0, sizeof sp);
    const int bad = first_setpoint(q, &sp);
    remove(q);
    ea_test_true(rc == 0 && !bad && fabs(sp.spool_pos[0] - want) <= 1e-9 * fabs(want) &&
                     strstr(err, hx),
                 "stream --arm (the planned arm): accepted, a note names its hash");
  }
  {
    char *argv[] = {(char *)bin, "simulate", "plan.csv", "--arm", arm_b, NULL};
    const int rc = run_in(b, argv, err, sizeof err);
    ea_test_true(rc == 0 && strstr(err, hx) && strstr(err, hy),
                 "simulate --arm (another arm): overrides, a note names both hashes");
  }
  const char *files[] = {"a/plan.csv",
                         "a/plan.json",
                         "a/old.csv",
                         "a/run.out",
                         "a/run.err",
                         "b/plan.csv",
                         "b/run.out",
                         "b/run.err",
                         "b/fig.svg",
                         "good.yaml",
                         "a/problems/examples/paper-line-smooth.yaml",
                         "a/data/elasticarm.yaml",
                         "b/data/elasticarm.yaml"};
  for (size_t i = 0; i < sizeof files / sizeof *files; ++i) {
    snprintf(p, sizeof p, "%s/%s", D, files[i]);
    remove(p);
  }
  for (size_t i = sizeof sub / sizeof *sub; i-- > 0;) {
    snprintf(p, sizeof p, "%s/%s", D, sub[i]);
    rmdir(p);
  }
  rmdir(D);
}

int main(void) {
  /* Run outside CTest this test cannot work: a failure, not a silent pass. */
  bin = getenv("EA_BINARY");
  const char *src = getenv("EA_SOURCE_DIR");
  if (!bin || access(bin, X_OK) || !src) {
    printf("FAIL: EA_BINARY / EA_SOURCE_DIR not set or not executable (run through ctest)\n");
    return 1;
  }
  char arm_src[480];
  if (strlen(src) + 24 >= sizeof arm_src) {
    printf("FAIL: EA_SOURCE_DIR too long\n");
    return 1;
  }
  snprintf(arm_src, sizeof arm_src, "%s/data/elasticarm.yaml", src);
  signal(SIGPIPE, SIG_IGN);
  ea_arm_t arm;
  ea_arm_default(&arm);
  fx_move_t m = fx_default_move();
  ea_traj_t tr = {0};
  /* The trajectories name the arm file they are streamed with. */
  fx_make_traj(&m, &arm, 0.02, &tr);
  snprintf(tr.arm_file, sizeof tr.arm_file, "%s", arm_src);
  ea_test_true(ea_traj_write(&tr, "cli_move.csv", NULL) == EA_OK, "fixture trajectory written");
  fx_move_t fast = m;
  fast.dL = 0.3;
  fx_make_traj(&fast, &arm, 0.02, &tr);
  snprintf(tr.arm_file, sizeof tr.arm_file, "%s", arm_src);
  ea_traj_write(&tr, "cli_fast.csv", NULL);
  ea_traj_free(&tr);
  test_recorded_arm(arm_src, &m);
  test_refused_edits(&arm, arm_src, &m);
  test_arm_moved(src);

  /* 1. Clean session. */
  int port = 0;
  pid_t sim = start_sim("cli_sim_log.csv", &port);
  ea_test_true(port > 0, "controller-sim wrote its port");
  char url[64];
  snprintf(url, sizeof url, "tcp://127.0.0.1:%d", port);
  {
    char *argv[] = {(char *)bin, "stream", "cli_move.csv", "--to", url, "--json", NULL};
    const int rc = ea_test_wait_for(ea_test_spawn(argv, "cli_stream.json", "cli_stream.err"), 5000);
    ea_test_true(rc == 0, "stream: exit 0 for a complete session");
  }
  ea_test_true(ea_test_wait_for(sim, 5000) == 0, "controller-sim: exit 0 after a clean session");
  double v = -1;
  int rows = log_rows("cli_sim_log.csv", &v);
  printf("log rows %d\n", rows);
  ea_test_true(rows == 601, "controller-sim log holds the 601 setpoints");

  /* 2. SIGINT to the streamer mid-stream. */
  sim = start_sim("cli_sim_log2.csv", &port);
  snprintf(url, sizeof url, "tcp://127.0.0.1:%d", port);
  {
    char *argv[] = {(char *)bin, "stream", "cli_move.csv", "--to", url, "--json", NULL};
    const pid_t st = ea_test_spawn(argv, "cli_stream2.json", "cli_stream2.err");
    ea_test_msleep(300);
    kill(st, SIGINT);
    const int rc = ea_test_wait_for(st, 5000);
    ea_test_true(rc == 1, "stream: SIGINT -> controlled stop, exit 1");
    FILE *fp = fopen("cli_stream2.json", "r");
    char buf[4096] = {0};
    if (fp) {
      if (!fread(buf, 1, sizeof buf - 1, fp)) buf[0] = 0;
      fclose(fp);
    }
    ea_test_true(strstr(buf, "\"stop-interrupt\"") != NULL, "JSON summary says stop-interrupt");
  }
  ea_test_wait_for(sim, 5000);
  v = -1;
  rows = log_rows("cli_sim_log2.csv", &v);
  printf("log rows %d, |v| at the end %g\n", rows, v);
  ea_test_true(rows > 0 && v == 0.0, "after SIGINT the controller log ends at rest");

  /* 3. Dry run to a file. */
  {
    char *argv[] = {(char *)bin, "stream", "cli_move.csv", "--to", "file:cli_dry.bin", NULL};
    const int rc = ea_test_wait_for(ea_test_spawn(argv, "cli_dry.out", "cli_dry.err"), 5000);
    struct stat sb;
    const int ok = stat("cli_dry.bin", &sb) == 0 && sb.st_size == 152 + 601 * 140 + 32;
    ea_test_true(rc == 0 && ok, "file: dry run writes HELLO + 601 setpoints + END");
  }

  /* 4. Too fast: refused before anything is sent. */
  {
    char *argv[] = {(char *)bin, "stream", "cli_fast.csv", "--to", "file:cli_fast.bin", NULL};
    remove("cli_fast.bin");
    const int rc = ea_test_wait_for(ea_test_spawn(argv, "cli_fast.out", "cli_fast.err"), 5000);
    ea_test_true(rc == 1 && access("cli_fast.bin", F_OK) != 0,
                 "too fast a trajectory: exit 1, nothing written");
  }
  /* 5. controller-sim --simulate after a complete stream of a physical move: the tip
   * history spans the setpoints plus the settling time, and its final static tip is
   * the ODE statics tip of the trajectory's last sample (independent: the shooting
   * solution at the planned cable length and angle). */
  const double Tm = 0.5, Lp = 0.40, dLp = 0.02, ap = -0.7, dap = 0.05;
  ea_test_true(make_phys_traj(&arm, arm_src, Tm, Lp, dLp, ap, dap, "cli_phys.csv") == 0,
               "physical move: statics at every sample, trajectory written");
  ea_shooter_t *sh = NULL;
  ea_shooter_alloc(&arm, NULL, &sh, NULL);
  ea_load_t load = {arm.m_hand};
  ea_shooter_set_load(sh, &load);
  char js[8192];
  sim = start_sim_fe("cli_sim_log3.csv", "cli_tip.csv", "cli_sim3.json", &port);
  snprintf(url, sizeof url, "tcp://127.0.0.1:%d", port);
  {
    char *argv[] = {(char *)bin, "stream", "cli_phys.csv", "--to", url, "--json", NULL};
    const int rc =
        ea_test_wait_for(ea_test_spawn(argv, "cli_stream3.json", "cli_stream3.err"), 5000);
    ea_test_true(rc == 0, "--simulate session: stream complete");
  }
  ea_test_true(ea_test_wait_for(sim, 10000) == 0, "controller-sim --simulate: exit 0");
  slurp("cli_sim3.json", js, sizeof js);
  {
    double t0 = NAN, t1 = NAN, last[2] = {NAN, NAN};
    const int n = tip_rows("cli_tip.csv", &t0, &t1, last);
    printf("tip rows %d, t %g .. %g s\n", n, t0, t1);
    ea_test_true(strstr(js, "\"sim_status\": \"EA_OK\"") != NULL, "JSON: sim_status EA_OK");
    ea_test_true(strstr(js, "\"sim_elements\":") && strstr(js, "\"sim_payload_kg\":") &&
                     !strstr(js, "o->"),
                 "JSON: the keys sim_elements and sim_payload_kg (no C expressions as keys)");
    ea_test_true(strstr(js, "\"end_reason_name\": \"complete\"") != NULL,
                 "JSON: end_reason_name says what END reason 0 is (docs/protocol.md)");
    ea_test_true(n == 1001 && fabs(t0) < 1e-9 && fabs(t1 - (Tm + 0.5)) < 1e-6,
                 "tip file: 1001 rows over the 0.5 s of setpoints + 0.5 s settling");
    ea_statics_problem_t pr = ea_statics_problem_cable(Lp + dLp, ap + dap);
    ea_statics_solution_t sol;
    const int ok = ea_statics_solve(sh, &pr, NULL, NULL, &sol, NULL) == EA_OK;
    const double fx = json_num(js, "sim_final_static_tip_m", 0),
                 fy = json_num(js, "sim_final_static_tip_m", 1),
                 rms = json_num(js, "residual_vibration_rms_m", 0),
                 peak = json_num(js, "residual_vibration_peak_m", 0);
    const double d = hypot(fx - sol.tip[EA_X_X], fy - sol.tip[EA_X_Y]);
    const double dl = hypot(last[0] - fx, last[1] - fy);
    printf("final static tip (%.9f, %.9f) vs ODE statics (%.9f, %.9f): %.3f um; residual "
           "vibration rms %.4f mm, peak %.4f mm; last tip row %.4f mm from it\n",
           fx, fy, sol.tip[EA_X_X], sol.tip[EA_X_Y], 1e6 * d, 1e3 * rms, 1e3 * peak, 1e3 * dl);
    ea_test_true(ok && d < 5e-6, "final static tip = ODE statics tip of the last sample (5 um)");
    /* The residual vibration recomputed from the tip history after the last
     * setpoint (t >= Tm: 501 rows at 1 ms), about the ODE statics tip instead
     * of the FE one: per row the two distances differ by at most d (triangle
     * inequality), so the RMS and the peak agree to d (3.1 um measured, vs
     * 9.5 mm RMS) plus the file's 12 digits. */
    double rrms = NAN, rpeak = NAN;
    const double c[2] = {sol.tip[EA_X_X], sol.tip[EA_X_Y]};
    const int nr = tip_residual("cli_tip.csv", Tm - 1e-7, c, &rrms, &rpeak);
    printf("residual vibration recomputed from %d tip rows about the ODE statics tip: rms %.6f "
           "mm (reported %.6f), peak %.6f mm (reported %.6f)\n",
           nr, 1e3 * rrms, 1e3 * rms, 1e3 * rpeak, 1e3 * peak);
    ea_test_true(nr == 501 && fabs(rrms - rms) <= d + 1e-9 && fabs(rpeak - peak) <= d + 1e-9,
                 "residual vibration RMS and peak = recomputed from the tip history about the "
                 "ODE statics tip (to the FE-ODE static tip distance)");
    ea_test_true(rrms > 1e-4, "the move leaves a residual vibration to measure (> 0.1 mm RMS)");
  }

  /* 6. SIGINT to the streamer: the tip history follows the stop ramp the controller
   * accepted and settles at the statics of the log's last (rest) setpoint. */
  sim = start_sim_fe("cli_sim_log4.csv", "cli_tip4.csv", "cli_sim4.json", &port);
  snprintf(url, sizeof url, "tcp://127.0.0.1:%d", port);
  {
    char *argv[] = {(char *)bin,    "stream", "cli_phys.csv", "--to", url,
                    "--time-scale", "3",      "--json",       NULL};
    const pid_t stp = ea_test_spawn(argv, "cli_stream4.json", "cli_stream4.err");
    ea_test_msleep(600);
    kill(stp, SIGINT);
    ea_test_true(ea_test_wait_for(stp, 5000) == 1,
                 "--simulate, SIGINT: streamer's controlled stop");
  }
  ea_test_wait_for(sim, 10000);
  slurp("cli_sim4.json", js, sizeof js);
  {
    double tl = NAN, Ll = NAN, thl = NAN, t0 = NAN, t1 = NAN, last[2] = {NAN, NAN};
    const int bad = log_last("cli_sim_log4.csv", &tl, &Ll, &thl);
    const int n = tip_rows("cli_tip4.csv", &t0, &t1, last);
    const double dur = json_num(js, "sim_motion_duration_s", 0);
    printf("stopped: log ends at t = %.4f s (L_c %.6f m, theta0 %.6f rad); tip rows %d, "
           "t %g .. %g s\n",
           tl, Ll, thl, n, t0, t1);
    ea_test_true(!bad && strstr(js, "\"sim_status\": \"EA_OK\"") != NULL && tl < 3 * Tm - 0.1,
                 "stopped stream simulated; the log ends before the plan's end");
    ea_test_true(n > 0 && fabs(t1 - (tl + 0.5)) < 1e-6 && fabs(dur - tl) < 1e-9,
                 "tip file spans the accepted setpoints (stop ramp included) + 0.5 s");
    ea_statics_problem_t pr = {{EA_GIVEN_CABLE_LENGTH, EA_GIVEN_THETA0}, {Ll, thl}};
    ea_statics_solution_t sol;
    const int ok = ea_statics_solve(sh, &pr, NULL, NULL, &sol, NULL) == EA_OK;
    const double fx = json_num(js, "sim_final_static_tip_m", 0),
                 fy = json_num(js, "sim_final_static_tip_m", 1),
                 peak = json_num(js, "residual_vibration_peak_m", 0);
    const double d = hypot(fx - sol.tip[EA_X_X], fy - sol.tip[EA_X_Y]);
    const double dl = hypot(last[0] - sol.tip[EA_X_X], last[1] - sol.tip[EA_X_Y]);
    printf("stop: final static tip %.3f um from the statics of the last setpoint; last tip row "
           "%.4f mm from it (residual peak %.4f mm)\n",
           1e6 * d, 1e3 * dl, 1e3 * peak);
    ea_test_true(ok && d < 5e-6, "stopped: final static tip = statics of the stop configuration");
    ea_test_true(dl <= peak + 5e-6, "stopped: the tip history ends near the stop configuration");
  }
  ea_shooter_free(sh);

  const char *tmp[] = {
      "cli_phys.csv",     "cli_tip.csv",      "cli_tip4.csv",     "cli_sim3.json",
      "cli_sim4.json",    "cli_sim_log3.csv", "cli_sim_log4.csv", "cli_stream3.json",
      "cli_stream3.err",  "cli_stream4.json", "cli_stream4.err",  "cli_move.csv",
      "cli_fast.csv",     "cli_sim.port",     "cli_sim.out",      "cli_sim.err",
      "cli_sim_log.csv",  "cli_sim_log2.csv", "cli_stream.json",  "cli_stream.err",
      "cli_stream2.json", "cli_stream2.err",  "cli_dry.bin",      "cli_dry.out",
      "cli_dry.err",      "cli_fast.out",     "cli_fast.err"};
  for (size_t i = 0; i < sizeof tmp / sizeof *tmp; ++i)
    remove(tmp[i]);
  return ea_test_summary("test_stream_cli");
}
