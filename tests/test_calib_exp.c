/* The data path of calibration (docs/calibration.md): an identification experiment
 * planned on the default arm streams as planned; the controller simulator playing a
 * "true" arm (EI +10 %, hand mass +20 %, modal damping) records measurement records that
 * parse, whose static rows are the FE static equilibrium of the true arm at each hold
 * within the noise, and whose ring-downs ring at the true arm's FE first frequency and
 * decay at its damping. References: the ODE statics and the FE statics / modes of the
 * true arm at each hold, computed here, not by the recorder.
 *
 * 1. calibrate-experiment on a 2 x 2 spec: every hold, the streamer's file dry run exits 0.
 * 2. controller-sim --record over TCP (real time, ~25 s), true arm with 2 % damping: the
 *    records parse; each ring-down's frequency (zero crossings) within 2 % of the FE's first
 *    frequency at the hold, its decay (log decrement of the peaks) within 20 % of the
 *    modal damping ratio the simulation's strain-rate damping gives that hold.
 * 3. the same session in the library (resampled setpoints -> ea_stream_setpoints_traj ->
 *    ea_traj_simulate -> ea_record_write) on a true arm with 30 % damping, whose ring-downs
 *    are over before each hold's averaging window: every static row within 4 standard
 *    deviations (the header's, a row's) of the ODE torque and the FE tension and tip. */
#include "ea_experiment_plan.h"
#include "ea_planner.h"
#include "ea_problems.h"
#include "ea_simulate.h"
#include "ea_stream.h"
#include "ea_test.h"
#include "ea_test_proc.h"
#include "ea_test_cli.h"
#include "ea_test_record.h"

#include <signal.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

/* ---- a small reader of measurement records (docs/calibration.md) ---------------- */

#define MAXCOL 12
typedef struct {
  char keys[32][64], vals[32][256];
  int nh;
  char cols[MAXCOL][64];
  int nc, rows;
  double *v; /* rows x nc */
} rec_t;

static int rec_read(const char *path, rec_t *r) {
  memset(r, 0, sizeof *r);
  FILE *fp = fopen(path, "r");
  if (!fp) return 1;
  char line[4096];
  int cap = 0, bad = 0;
  while (fgets(line, sizeof line, fp)) {
    line[strcspn(line, "\n")] = '\0';
    if (line[0] == '#') {
      const char *c = strchr(line, ':');
      if (c && r->nh < 32) {
        snprintf(r->keys[r->nh], 64, "%.*s", (int)(c - line - 2), line + 2);
        snprintf(r->vals[r->nh], 256, "%s", c + 2);
        ++r->nh;
      } else if (strcmp(line, "# elasticarm-record 1")) {
        bad = 1;
      }
      continue;
    }
    if (!r->nc) {
      for (char *tok = strtok(line, ","); tok && r->nc < MAXCOL; tok = strtok(NULL, ","))
        snprintf(r->cols[r->nc++], 64, "%s", tok);
      continue;
    }
    if (r->rows == cap) {
      cap = cap ? 2 * cap : 1024;
      r->v = realloc(r->v, sizeof(double) * (size_t)cap * r->nc);
    }
    int k = 0;
    for (char *tok = strtok(line, ","); tok && k < r->nc; tok = strtok(NULL, ","))
      r->v[(size_t)r->rows * r->nc + k++] = strtod(tok, NULL);
    if (k != r->nc) bad = 1;
    ++r->rows;
  }
  fclose(fp);
  return bad;
}

static const char *rec_hdr(const rec_t *r, const char *key) {
  for (int i = 0; i < r->nh; ++i)
    if (!strcmp(r->keys[i], key)) return r->vals[i];
  return NULL;
}

static double rec_num(const rec_t *r, const char *key) {
  const char *v = rec_hdr(r, key);
  return v ? strtod(v, NULL) : NAN;
}

static int rec_col(const rec_t *r, const char *name) {
  for (int i = 0; i < r->nc; ++i)
    if (!strcmp(r->cols[i], name)) return i;
  return -1;
}

static double rec_at(const rec_t *r, int row, int col) {
  return r->v[(size_t)row * r->nc + col];
}

/* ---- references at a hold: the true arm's statics, FE equilibrium and modes -------- */

typedef struct {
  double torque;  /* [N m] ODE EI kappa0 at the FE equilibrium's cable length and angle */
  double tension; /* [N] FE */
  double tip[2];  /* [m] FE */
  double f1;      /* [Hz] FE first frequency about it (passive cable) */
  double b_002;   /* [s] strain-rate coefficient giving mode 1 a ratio of 0.02 here */
} ref_t;

/* The equilibrium the simulation holds at: shoulder angle theta0 and a passive cable of
 * rest length L_c / (1 + T_ff / EA_c) (T_ff the setpoints' tension feed-forward), reached
 * from the ODE statics of (L_c, theta0) on the true arm. */
static int reference(const ea_arm_t *arm, double L, double theta0, double T_ff, ref_t *o) {
  ea_shooter_t *sh = NULL;
  ea_fe_model_t *m = NULL;
  ea_error_t e = {0};
  const ea_load_t load = {arm->m_hand};
  ea_fe_settings_t fs;
  ea_fe_settings_default(&fs);
  int bad = ea_shooter_alloc(arm, NULL, &sh, &e) || ea_fe_model_alloc(arm, &fs, &m, &e) ||
            ea_fe_model_set_load(m, &load);
  if (bad) return 1;
  ea_shooter_set_load(sh, &load);
  ea_statics_problem_t pr = ea_statics_problem_cable(L, 0.0);
  pr.given[1] = EA_GIVEN_THETA0;
  pr.value[1] = theta0;
  ea_statics_solution_t ode;
  ea_fe_static_info_t fi;
  bad = ea_statics_solve(sh, &pr, NULL, NULL, &ode, &e) ||
        ea_fe_static_solve(m, sh, &ode, &fi, &e) ||
        ea_fe_static_continue(m, theta0, EA_FE_CABLE_PASSIVE,
                              ea_fe_cable_rest_length(L, T_ff, arm->EA_cable), &fi, &e);
  if (!bad) {
    o->tension = fi.tension;
    o->tip[0] = fi.tip[0];
    o->tip[1] = fi.tip[1];
    ea_statics_problem_t p2 = ea_statics_problem_cable(fi.cable_length, fi.cable_angle);
    ea_statics_solution_t s2;
    bad = ea_statics_solve(sh, &p2, NULL, ode.p, &s2, &e) != EA_OK;
    o->torque = s2.shoulder_torque;
    ea_fe_modes_info_t mi;
    bad = bad || ea_fe_modes(m, &mi, &e) || ea_fe_strain_damping(m, 0, 0.02, &o->b_002, NULL);
    o->f1 = mi.freq_hz[0];
  }
  if (bad) printf("reference at L_c %g, theta0 %g: %s\n", L, theta0, e.msg);
  ea_fe_model_free(m);
  ea_shooter_free(sh);
  return bad;
}

/* The tension feed-forward of the experiment at the hold of (L_c, theta0). */
static double t_ff(const ea_traj_t *tr, double L, double theta0) {
  for (int i = 0; i < tr->n; ++i)
    if (fabs(EA_TRAJ_AT(tr, i, EA_TRAJ_cable_length) - L) < 1e-9 &&
        fabs(EA_TRAJ_AT(tr, i, EA_TRAJ_theta0) - theta0) < 1e-7)
      return EA_TRAJ_AT(tr, i, EA_TRAJ_tension);
  return NAN;
}

/* Frequency (upward zero crossings) and decay rate (log of the positive peaks against time)
 * of x - x0 from t_skip on, after a 51-sample moving average. */
static void ring(const rec_t *r, int col, double x0, double t_skip, double *f, double *sigma,
                 int *peaks) {
  const int n = r->rows, w = 25;
  double *y = malloc(sizeof(double) * (size_t)n);
  for (int i = 0; i < n; ++i) {
    double s = 0;
    int c = 0;
    for (int j = i - w; j <= i + w; ++j)
      if (j >= 0 && j < n) s += rec_at(r, j, col) - x0, ++c;
    y[i] = s / c;
  }
  double tz[64], tp[64], lp[64];
  int nz = 0, np = 0, in_lobe = 0;
  double best = 0, tbest = 0;
  for (int i = w + 1; i < n - w; ++i) {
    const double t = rec_at(r, i, 0);
    if (t < t_skip) continue;
    if (y[i - 1] < 0 && y[i] >= 0 && nz < 64) {
      tz[nz++] = rec_at(r, i - 1, 0) + (t - rec_at(r, i - 1, 0)) * (-y[i - 1]) / (y[i] - y[i - 1]);
      in_lobe = 1, best = 0;
    }
    if (in_lobe && y[i] > best) best = y[i], tbest = t;
    if (in_lobe && y[i - 1] > 0 && y[i] <= 0 && np < 64) {
      tp[np] = tbest, lp[np++] = log(best);
      in_lobe = 0;
    }
  }
  *f = nz > 1 ? (nz - 1) / (tz[nz - 1] - tz[0]) : NAN;
  double st = 0, sl = 0, stt = 0, stl = 0;
  for (int i = 0; i < np; ++i)
    st += tp[i], sl += lp[i], stt += tp[i] * tp[i], stl += tp[i] * lp[i];
  *sigma = np > 1 ? -(np * stl - st * sl) / (np * stt - st * st) : NAN;
  *peaks = np;
  free(y);
}

static void write_text(const char *path, const char *text) {
  FILE *fp = fopen(path, "w");
  if (fp) {
    fputs(text, fp);
    fclose(fp);
  }
}

/* 2. ring-downs of the CLI session against the FE modes of the true arm */
static void check_ringdowns(const char *dir, const ea_arm_t *arm, const ea_traj_t *tr) {
  rec_t st;
  char sp[256];
  snprintf(sp, sizeof sp, "%s/static.csv", dir);
  const int st_bad = rec_read(sp, &st) != 0 || st.rows != 4;
  ea_test_true(!st_bad, "static record parses: 4 rows");
  if (st_bad) {
    free(st.v);
    return;
  }
  ea_test_true(rec_hdr(&st, "kind") && !strcmp(rec_hdr(&st, "kind"), "static"), "kind: static");
  const double n_avg = rec_num(&st, "averaged_samples");
  ea_test_rel(rec_num(&st, "noise_torque_Nm"), 0.01 / sqrt(n_avg), 1e-6,
              "static noise_torque_Nm = sensor / sqrt(samples averaged)");
  ref_t r1;
  const int cL = rec_col(&st, "cable_length_m");
  /* the simulation's damping: 2 % at mode 1 of its start, the first hold */
  const double L1 = EA_TRAJ_AT(tr, 0, EA_TRAJ_cable_length),
               th1 = EA_TRAJ_AT(tr, 0, EA_TRAJ_theta0);
  const int ok_ref = !reference(arm, L1, th1, t_ff(tr, L1, th1), &r1);
  ea_test_true(ok_ref, "reference at the first hold (the simulation's start)");
  for (int k = 2; k <= 4; ++k) {
    char path[256];
    snprintf(path, sizeof path, "%s/ringdown-%03d.csv", dir, k);
    rec_t r;
    char what[400];
    snprintf(what, sizeof what, "%s parses (kind ringdown, 5 columns, t_s from 0)", path);
    const int bad = rec_read(path, &r);
    ea_test_true(!bad && r.nc == 5 && r.rows > 1000 && rec_at(&r, 0, 0) == 0.0 &&
                     !strcmp(rec_hdr(&r, "kind"), "ringdown"),
                 what);
    if (bad || r.rows < 1000) continue;
    const double L = rec_num(&r, "cable_length_m"), th = rec_num(&r, "theta0_rad");
    ea_test_abs(L, rec_at(&st, k - 1, cL), 1e-9, "ring-down header: the static row's L_c");
    ref_t rf;
    if (reference(arm, L, th, t_ff(tr, L, th), &rf) || !ok_ref) {
      ea_test_true(0, "reference at the hold");
      continue;
    }
    double f, sigma;
    int np;
    ring(&r, rec_col(&r, "tip_y_m"), rf.tip[1], 1.0, &f, &sigma, &np);
    const double zeta_ref = 0.02 * r1.b_002 / rf.b_002;
    const double zeta = sigma / (2 * M_PI * f);
    printf("hold %d: L_c %.3f m, theta0 %.4f rad: ring %.5f Hz (FE %.5f Hz), %d peaks, zeta "
           "%.5f (modal %.5f)\n",
           k, L, th, f, rf.f1, np, zeta, zeta_ref);
    snprintf(what, sizeof what, "hold %d: ring-down frequency = FE first frequency of the true arm",
             k);
    ea_test_rel(f, rf.f1, 0.02, what);
    snprintf(what, sizeof what, "hold %d: ring-down decay = the true arm's modal damping ratio", k);
    ea_test_rel(zeta, zeta_ref, 0.2, what);
    free(r.v);
  }
  free(st.v);
}

/* 3. static rows against the statics of the true arm */
static void check_static(const char *path, const ea_arm_t *arm, const ea_traj_t *tr) {
  rec_t st;
  ea_test_true(rec_read(path, &st) == 0 && st.rows == 4, "library session: static record, 4 rows");
  const double sT = rec_num(&st, "noise_torque_Nm"), sN = rec_num(&st, "noise_tension_N"),
               sX = rec_num(&st, "noise_tip_m"), sA = rec_num(&st, "noise_theta0_rad");
  const int cL = rec_col(&st, "cable_length_m"), cA = rec_col(&st, "theta0_rad"),
            cM = rec_col(&st, "shoulder_torque_Nm"), cN = rec_col(&st, "tension_N"),
            cx = rec_col(&st, "tip_x_m"), cy = rec_col(&st, "tip_y_m");
  ea_test_true(cL >= 0 && cA >= 0 && cM >= 0 && cN >= 0 && cx >= 0 && cy >= 0,
               "static columns: cable_length_m, theta0_rad, shoulder_torque_Nm, tension_N, tip");
  for (int k = 0; k < st.rows; ++k) {
    const double L = rec_at(&st, k, cL);
    /* the commanded theta0: the experiment's hold at this cable length and sensed angle */
    double th = NAN, best = INFINITY;
    for (int i = 0; i < tr->n; ++i) {
      const double d = fabs(EA_TRAJ_AT(tr, i, EA_TRAJ_theta0) - rec_at(&st, k, cA));
      if (fabs(EA_TRAJ_AT(tr, i, EA_TRAJ_cable_length) - L) < 1e-9 && d < best)
        best = d, th = EA_TRAJ_AT(tr, i, EA_TRAJ_theta0);
    }
    ref_t rf;
    if (reference(arm, L, th, t_ff(tr, L, th), &rf)) {
      ea_test_true(0, "reference at the hold");
      continue;
    }
    char what[200];
    snprintf(what, sizeof what, "row %d (L_c %.2f m): sensed theta0 = commanded within 4 sd", k + 1,
             L);
    ea_test_abs(rec_at(&st, k, cA), th, 4 * sA, what);
    snprintf(what, sizeof what, "row %d: shoulder torque = ODE statics of the true arm within 4 sd",
             k + 1);
    ea_test_abs(rec_at(&st, k, cM), rf.torque, 4 * sT, what);
    snprintf(what, sizeof what, "row %d: tension = FE equilibrium of the true arm within 4 sd",
             k + 1);
    ea_test_abs(rec_at(&st, k, cN), rf.tension, 4 * sN, what);
    snprintf(what, sizeof what, "row %d: tip = FE equilibrium within 4 sd", k + 1);
    ea_test_abs(hypot(rec_at(&st, k, cx) - rf.tip[0], rec_at(&st, k, cy) - rf.tip[1]), 0.0, 4 * sX,
                what);
  }
  free(st.v);
}

int main(void) {
  char arm_path[1024];
  if (cli_setup(arm_path, sizeof arm_path)) return 77;
  char spec[2048];
  snprintf(spec, sizeof spec,
           "name: test-experiment\narm_file: %s\ncable_lengths_m: [0.40, 0.50]\n"
           "cable_angles_rad: [-0.6, -0.2]\nhold_s: 6\n",
           arm_path);
  write_text("calib_spec.yaml", spec);

  /* 1. the experiment, and the streamer's own checks */
  int rc = run("calibrate-experiment calib_spec.yaml -o calib_exp.csv --json");
  ea_test_true(rc == 0, "calibrate-experiment: exit 0");
  ea_test_abs(json_num("holds"), 4, 0, "4 holds (2 cable lengths x 2 angles)");
  const double dur = json_num("duration_s");
  ea_test_true(dur > 4 * 6 && dur < 4 * 6 + 5, "duration: 4 holds of 6 s and 3 moves");
  ea_traj_t tr = {0};
  ea_error_t e = {0};
  ea_test_true(ea_traj_read(&tr, "calib_exp.csv", &e) == EA_OK, "the experiment reads back");
  rc = run("stream calib_exp.csv --to file:calib_exp.bin");
  ea_test_true(rc == 0, "stream --to file: the streamer's checks pass (exit 0)");
  rc = run("calibrate --plan-experiment calib_spec.yaml -o calib_exp2.csv --json");
  ea_test_true(rc == 0 && json_num("duration_s") == dur,
               "calibrate --plan-experiment SPEC is calibrate-experiment SPEC");
  remove("calib_exp2.csv");
  remove("calib_exp2.json");
  int rest = tr.n > 1;
  for (int c = EA_TRAJ_cable_length_rate; c <= EA_TRAJ_base_angle_acc; ++c)
    rest = rest && EA_TRAJ_AT(&tr, 0, c) == 0 && EA_TRAJ_AT(&tr, tr.n - 1, c) == 0;
  ea_test_true(rest, "the experiment starts and ends at rest");
  /* an infeasible configuration is skipped with a note */
  write_text("calib_spec_bad.yaml",
             "name: bad\ncable_lengths_m: [0.45, 1.1]\ncable_angles_rad: [-0.5]\nhold_s: 2\n");
  rc = run("calibrate-experiment calib_spec_bad.yaml -o calib_bad.csv");
  ea_test_true(rc == 0 &&
                   strstr(out, "skipped: L_c = 1.1 m, alpha = -0.5 rad: outside the workspace") &&
                   strstr(out, "1 of 2 configurations feasible"),
               "a configuration outside the workspace is skipped with a note");

  /* 2. controller-sim --record on the true arm (2 % damping), streamed over TCP */
  ea_arm_t arm2;
  ea_test_true(ea_tr_true_arm(arm_path, "calib_true2.yaml", 1.1, 1.2, 1.0, 0.02, &arm2) == 0,
               "true arm file: EI +10 %, hand +20 %, damping 0.02");
  remove("calib.port");
  char *argv[] = {(char *)bin,     "controller-sim",
                  "--arm",         "calib_true2.yaml",
                  "--port-file",   "calib.port",
                  "--record",      "calib_rec",
                  "--simulate",    "calib_tip.csv",
                  "--settle",      "1",
                  "--timeout",     "20",
                  "--watchdog-ms", "2000",
                  "--json",        NULL};
  const pid_t sim = ea_test_spawn(argv, "calib_sim.json", "calib_sim.err");
  const int port = ea_test_read_port("calib.port", 500);
  char args[512];
  snprintf(args, sizeof args, "stream calib_exp.csv --to tcp://127.0.0.1:%d", port);
  rc = run(args);
  if (rc) printf("%s", out);
  ea_test_true(port > 0 && rc == 0, "stream over TCP to controller-sim: complete");
  ea_test_true(ea_test_wait_for(sim, 120000) == 0, "controller-sim --simulate --record: exit 0");
  check_ringdowns("calib_rec", &arm2, &tr);

  /* 3. the static rows, on a true arm whose ring-downs end before the averaging window */
  ea_arm_t arm3;
  ea_test_true(ea_tr_true_arm(arm_path, "calib_true3.yaml", 1.1, 1.2, 1.0, 0.3, &arm3) == 0,
               "true arm file: EI +10 %, hand +20 %, damping 0.3");
  ea_arm_t def3; /* the experiment was planned on the default arm */
  ea_arm_default(&def3);
  ea_test_true(ea_tr_record_session(&tr, &def3, &arm3, "calib_rec3", "library session") == 0,
               "library session: setpoints -> FE transient -> records");
  check_static("calib_rec3/static.csv", &arm3, &tr);
  ea_traj_free(&tr);
  return ea_test_summary("test_calib_exp");
}
