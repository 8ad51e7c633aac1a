/* bench_study: batch-study speed. The Fig. 3 study (4 payload factors, the
 * workspace region's metrics from 71 sampled cable angles, without and with
 * the arm's limits; the error column is the largest change of any metric
 * against 141 samples and a 1e-13 area tolerance), a 1000-case study with
 * FE frequencies (payload x EI x hand mass, 2 configurations x 3 modes),
 * the speed-up from 1 to 2 threads and the cost of the fsync'd checkpoint
 * journal; then studies that plan (min_time: 12 shoulder swings; at_rest: 4 payloads on
 * the line to (0.5, -0.2)) on 1 worker, 2 threads (Ipopt calls serialised: MUMPS'
 * sequential build is not thread-safe) and 2 forked worker processes. Medians, as a
 * table.
 * Usage: bench_study [repeats-of-the-1000-case-study (default 3)] [planner-repeats
 *        (default 3)]; bench_study planner [planner-repeats]: the planner rows only */
#include "ea_planner.h"
#include "ea_problems.h"

#include <gsl/gsl_errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bench_util.h"
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

static const char *k_fig3 = "name: fig3\n"
                            "grid: {payload_factor: [0, 0.1, 0.25, 0.5]}\n"
                            "metrics:\n"
                            "  workspace: {alpha_min_deg: -60, alpha_max_deg: 10, points: 71,\n"
                            "              limits: false}\n";

static const char *k_fig3l = "name: fig3l\n"
                             "grid: {payload_factor: [0, 0.1, 0.25, 0.5]}\n"
                             "metrics:\n"
                             "  workspace: {alpha_min_deg: -60, alpha_max_deg: 10, points: 71}\n";

/* Largest change of area [m^2], reach, x_max, y_min [m] over the study's
 * cases when the metrics are computed with 141 samples, 16 cable lengths
 * per angle and an area tolerance of 1e-13 instead of the study's. */
static double metric_error(const ea_study_t *s) {
  double worst = 0;
  for (long c = 0; c < s->n_cases; ++c) {
    ea_arm_t arm;
    double kg, g;
    ea_shooter_t *sh = NULL;
    if (ea_study_case_arm(s, c, &arm, &kg, &g, NULL) || ea_shooter_alloc(&arm, NULL, &sh, NULL))
      return NAN;
    ea_load_t ld = {ea_arm_tip_mass(&arm, kg)};
    ea_shooter_set_load(sh, &ld);
    ea_workspace_settings_t a, b;
    ea_workspace_settings_default(&a);
    a.alpha_min = s->workspace.alpha_min;
    a.alpha_max = s->workspace.alpha_max;
    a.limits = s->workspace.limits;
    a.samples = s->workspace.points;
    b = a;
    b.samples = 141;
    b.depth_samples = 16;
    b.tol = 1e-13;
    ea_workspace_metrics_t ma, mb;
    if (ea_workspace_metrics(sh, &a, &ma, NULL) || ea_workspace_metrics(sh, &b, &mb, NULL)) {
      ea_shooter_free(sh);
      return NAN;
    }
    ea_shooter_free(sh);
    worst = fmax(worst, fabs(ma.area - mb.area));
    worst = fmax(worst, fabs(ma.reach.value - mb.reach.value));
    worst = fmax(worst, fabs(ma.x_max.value - mb.x_max.value));
    worst = fmax(worst, fabs(ma.y_min.value - mb.y_min.value));
  }
  return worst;
}

static const char *k_freq = "name: freq1000\n"
                            "grid:\n"
                            "  payload_factor: 0:0.05:0.45\n"
                            "  EI_Nm2: 0.6:0.025:0.825\n"
                            "  hand_mass_kg: 0.15:0.02:0.33\n"
                            "metrics:\n"
                            "  frequencies:\n"
                            "    modes: 3\n"
                            "    configurations:\n"
                            "      - {cable_length_m: 0.45, cable_angle_deg: -25}\n"
                            "      - {cable_length_m: 0.55, cable_angle_deg: -40}\n";

/* Median wall time [s] of reps runs; *failed = failed cases of the last. */
static double time_study(const ea_study_t *s, int threads, const char *ckpt, int reps, char **keep,
                         long *failed) {
  double *t = malloc((size_t)reps * sizeof *t);
  for (int r = 0; r < reps; ++r) {
    ea_study_settings_t set;
    ea_study_settings_default(&set);
    set.threads = threads;
    set.checkpoint = ckpt;
    if (ckpt) unlink(ckpt);
    char *csv = NULL;
    ea_study_info_t info;
    ea_error_t e = {0};
    const double t0 = ea_bench_now();
    if (ea_study_run(s, &set, &csv, NULL, &info, &e)) {
      fprintf(stderr, "bench_study: %s\n", e.msg);
      exit(1);
    }
    t[r] = ea_bench_now() - t0;
    if (failed) *failed = info.cases_failed;
    if (keep && r == reps - 1)
      *keep = csv;
    else
      free(csv);
  }
  if (ckpt) unlink(ckpt);
  const double m = ea_bench_median(t, reps);
  free(t);
  return m;
}

/* 1- and 2-thread runs interleaved (so that load from other processes
 * hits both alike): medians m1, m2; CSVs compared byte for byte. */
static int pair_times(const ea_study_t *s, int reps, double *m1, double *m2, long *failed,
                      double *cores2) {
  double *t1 = malloc((size_t)reps * sizeof *t1), *t2 = malloc((size_t)reps * sizeof *t2);
  int same = 1;
  double cpu = 0, wall = 0;
  for (int r = 0; r < reps; ++r) {
    char *a = NULL, *b = NULL;
    t1[r] = time_study(s, 1, NULL, 1, &a, failed);
    const double c0 = ea_bench_cpu_now();
    t2[r] = time_study(s, 2, NULL, 1, &b, NULL);
    cpu += ea_bench_cpu_now() - c0;
    wall += t2[r];
    same &= a && b && !strcmp(a, b);
    free(a);
    free(b);
  }
  *cores2 = cpu / wall;
  *m1 = ea_bench_median(t1, reps);
  *m2 = ea_bench_median(t2, reps);
  free(t1);
  free(t2);
  return same;
}

static const char *loadavg(void) {
  static char buf[64] = "n/a";
  FILE *fp = fopen("/proc/loadavg", "r");
  if (fp) {
    if (!fgets(buf, sizeof buf, fp)) snprintf(buf, sizeof buf, "n/a");
    buf[strcspn(buf, " ")] = '\0';
    fclose(fp);
  }
  return buf;
}

/* CPU time [s] of the waited-for children (the worker processes). */
static double children_cpu(void) {
  struct rusage ru;
  getrusage(RUSAGE_CHILDREN, &ru);
  return (double)ru.ru_utime.tv_sec + 1e-6 * (double)ru.ru_utime.tv_usec +
         (double)ru.ru_stime.tv_sec + 1e-6 * (double)ru.ru_stime.tv_usec;
}

/* One run of a study that plans: wall time [s]; *cpu = CPU [s] of this process and its
 * worker processes; *csv kept. */
static double time_plan(const ea_study_t *s, int threads, ea_study_workers_t w, char **csv,
                        double *cpu, int *procs) {
  ea_study_planner_t *p = NULL;
  ea_error_t e = {0};
  ea_study_settings_t set;
  ea_study_settings_default(&set);
  if (ea_study_use_planner(s, NULL, &set, &p, &e)) {
    fprintf(stderr, "bench_study: %s\n", e.msg);
    exit(1);
  }
  set.threads = threads;
  set.workers = w;
  ea_study_info_t info;
  const double c0 = ea_bench_cpu_now() + children_cpu(), t0 = ea_bench_now();
  if (ea_study_run(s, &set, csv, NULL, &info, &e)) {
    fprintf(stderr, "bench_study: %s\n", e.msg);
    exit(1);
  }
  const double t = ea_bench_now() - t0;
  *cpu = ea_bench_cpu_now() + children_cpu() - c0;
  *procs = info.processes;
  ea_study_planner_free(p);
  return t;
}

/* A planner study on 1 worker, 2 threads and 2 worker processes, interleaved (load from
 * other processes hits all three alike); rows of the table. */
static void bench_planner(const char *label, const ea_study_t *s, int reps) {
  double *t[3], cpu[3] = {0}, wall[3] = {0};
  int same = 1, procs_ok = 1;
  char *ref = NULL;
  static const int threads[3] = {1, 2, 2};
  static const ea_study_workers_t mode[3] = {EA_STUDY_WORKERS_THREADS, EA_STUDY_WORKERS_THREADS,
                                             EA_STUDY_WORKERS_PROCESSES};
  for (int m = 0; m < 3; ++m)
    t[m] = malloc((size_t)reps * sizeof *t[m]);
  {
    /* warm-up (reduced-model tables into the cache, pages in), not timed */
    double c;
    int pr;
    char *x = NULL;
    time_plan(s, 2, EA_STUDY_WORKERS_PROCESSES, &x, &c, &pr);
    free(x);
  }
  for (int r = 0; r < reps; ++r)
    for (int m = 0; m < 3; ++m) {
      char *csv = NULL;
      double c;
      int pr;
      t[m][r] = time_plan(s, threads[m], mode[m], &csv, &c, &pr);
      cpu[m] += c;
      wall[m] += t[m][r];
      procs_ok &= pr == (m == 2);
      if (!ref)
        ref = csv;
      else {
        same &= csv && !strcmp(csv, ref);
        free(csv);
      }
    }
  double med[3];
  for (int m = 0; m < 3; ++m) {
    med[m] = ea_bench_median(t[m], reps);
    free(t[m]);
  }
  free(ref);
  printf("| %s | %ld | 1 | %.3f s | %.0f ms | CPU/wall %.2f |\n", label, s->n_cases, med[0],
         1e3 * med[0] / s->n_cases, cpu[0] / wall[0]);
  printf("| %s | %ld | 2 threads | %.3f s | %.0f ms | speed-up %.2fx, CPU/wall %.2f, CSV %s |\n",
         label, s->n_cases, med[1], 1e3 * med[1] / s->n_cases, med[0] / med[1], cpu[1] / wall[1],
         same ? "identical" : "DIFFERS");
  printf("| %s | %ld | 2 processes | %.3f s | %.0f ms | speed-up %.2fx, CPU/wall %.2f, CSV %s%s "
         "|\n",
         label, s->n_cases, med[2], 1e3 * med[2] / s->n_cases, med[0] / med[2], cpu[2] / wall[2],
         same ? "identical" : "DIFFERS", procs_ok ? "" : ", NOT FORKED");
  fflush(stdout);
}

static const char *k_swing =
    "name: swing12\n"
    "arm_file: %s/data/elasticarm.yaml\n"
    "grid:\n"
    "  payload_factor: [0, 0.25, 0.5]\n"
    "  EI_Nm2: [0.6, 0.65, 0.7, 0.75]\n"
    "metrics:\n"
    "  min_time: {task: %s/problems/examples/studies/shoulder-swing.yaml}\n";

static const char *k_rest = "name: rest4\n"
                            "arm_file: %s/data/elasticarm.yaml\n"
                            "grid: {payload_factor: [0, 0.15, 0.3, 0.45]}\n"
                            "metrics:\n"
                            "  at_rest: {task: %s/problems/examples/studies/line-to-0.5.yaml}\n";

/* The machine's own ceiling for 2 workers: the reference kernel of bench_util.h (arithmetic
 * and libm, no memory traffic, nothing shared) as 4 runs in 1 process against 2 forked
 * processes of 2 runs each: a study's speed-up is bounded by it (on a virtual machine whose
 * two cores share the host's, it is below 2). Median over reps; NAN when fork fails. */
static double kernel_ceiling(int reps) {
  double one[64], two[64];
  reps = reps > 64 ? 64 : reps;
  for (int r = 0; r < reps; ++r) {
    double t0 = ea_bench_now();
    for (int i = 0; i < 4; ++i)
      (void)ea_bench_pace_ms();
    one[r] = ea_bench_now() - t0;
    t0 = ea_bench_now();
    pid_t kid[2];
    for (int w = 0; w < 2; ++w) {
      kid[w] = fork();
      if (kid[w] == 0) {
        for (int i = 0; i < 2; ++i)
          (void)ea_bench_pace_ms();
        _exit(0);
      }
      if (kid[w] < 0) {
        if (w) waitpid(kid[0], NULL, 0);
        return NAN;
      }
    }
    for (int w = 0; w < 2; ++w)
      waitpid(kid[w], NULL, 0);
    two[r] = ea_bench_now() - t0;
  }
  return ea_bench_median(one, reps) / ea_bench_median(two, reps);
}

static void planner_rows(int reps) {
  char text[4096];
  ea_study_t sw, re;
  ea_error_t e = {0};
  snprintf(text, sizeof text, k_swing, EA_SOURCE_DIR, EA_SOURCE_DIR);
  if (ea_study_load_string("swing12.yaml", text, strlen(text), NULL, &sw, &e)) {
    fprintf(stderr, "bench_study: %s\n", e.msg);
    exit(1);
  }
  snprintf(text, sizeof text, k_rest, EA_SOURCE_DIR, EA_SOURCE_DIR);
  if (ea_study_load_string("rest4.yaml", text, strlen(text), NULL, &re, &e)) {
    fprintf(stderr, "bench_study: %s\n", e.msg);
    exit(1);
  }
  bench_planner("min_time, 12 shoulder swings (60 knots)", &sw, reps);
  bench_planner("at_rest, 4 payloads (2 plans + 2 FE transients each)", &re, reps);
  ea_study_free(&sw);
  ea_study_free(&re);
}

int main(int argc, char **argv) {
  gsl_set_error_handler_off(); /* every GSL return is checked */
  const long cores = sysconf(_SC_NPROCESSORS_ONLN);
  if (argc > 1 && !strcmp(argv[1], "planner")) {
    const int reps =
        ea_bench_count(argc, argv, 2, 3, 1000, "bench_study planner [repetitions 1..1000]");
    if (reps < 0 || argc > 3) return 2;
    printf("bench_study planner: %ld online cores; medians of %d; load average %s at the start\n\n",
           cores, reps, loadavg());
    printf("| study | cases | workers | median wall | per case | notes |\n");
    printf("|---|---|---|---|---|---|\n");
    planner_rows(reps);
    printf("\nload average %s at the end; CPU/wall = cores the run got (worker processes "
           "included)\n",
           loadavg());
    printf("the machine's ceiling: the reference kernel of bench_util.h, 2 processes against 1: "
           "speed-up %.2fx\n",
           kernel_ceiling(reps));
    return 0;
  }
  const char *usage = "bench_study [repetitions 1..1000 [plan-repetitions 1..1000]] | "
                      "bench_study planner [repetitions]";
  const int reps_big = ea_bench_count(argc, argv, 1, 3, 1000, usage);
  const int reps_plan = ea_bench_count(argc, argv, 2, 3, 1000, usage);
  if (reps_big < 0 || reps_plan < 0 || argc > 3) return 2;
  ea_study_t fig3, fig3l, freq;
  ea_error_t e = {0};
  if (ea_study_load_string("fig3.yaml", k_fig3, strlen(k_fig3), NULL, &fig3, &e) ||
      ea_study_load_string("fig3l.yaml", k_fig3l, strlen(k_fig3l), NULL, &fig3l, &e) ||
      ea_study_load_string("freq1000.yaml", k_freq, strlen(k_freq), NULL, &freq, &e)) {
    fprintf(stderr, "bench_study: %s\n", e.msg);
    return 1;
  }
  char ckpt[] = "/tmp/bench_study.journal";
  printf("bench_study: %ld online cores; medians; no checkpoint unless stated\n\n", cores);
  printf("| study | cases | threads | median wall | per case | notes |\n");
  printf("|---|---|---|---|---|---|\n");
  long failed = 0;
  double f1, f2, g1, g2, fcores, gcores;
  int same = pair_times(&fig3, 21, &f1, &f2, &failed, &fcores);
  const double err3 = metric_error(&fig3);
  printf("| Fig. 3 (workspace, 71 samples, no limits) | %ld | 1 | %.2f ms | %.2f ms | %ld failed, "
         "metrics within %.1e of 141 samples |\n",
         fig3.n_cases, 1e3 * f1, 1e3 * f1 / fig3.n_cases, failed, err3);
  printf("| Fig. 3 (workspace, 71 samples, no limits) | %ld | 2 | %.2f ms | %.2f ms | speed-up "
         "%.2fx, CPU/wall %.2f, CSV %s |\n",
         fig3.n_cases, 1e3 * f2, 1e3 * f2 / fig3.n_cases, f1 / f2, fcores,
         same ? "identical" : "DIFFERS");
  double l1, l2, lcores;
  same = pair_times(&fig3l, 5, &l1, &l2, &failed, &lcores);
  const double err3l = metric_error(&fig3l);
  printf("| Fig. 3 within the arm's limits | %ld | 1 | %.2f ms | %.2f ms | %ld failed, metrics "
         "within %.1e of 141 samples |\n",
         fig3l.n_cases, 1e3 * l1, 1e3 * l1 / fig3l.n_cases, failed, err3l);
  printf("| Fig. 3 within the arm's limits | %ld | 2 | %.2f ms | %.2f ms | speed-up %.2fx, "
         "CPU/wall %.2f, CSV %s |\n",
         fig3l.n_cases, 1e3 * l2, 1e3 * l2 / fig3l.n_cases, l1 / l2, lcores,
         same ? "identical" : "DIFFERS");
  const double fc = time_study(&fig3, 2, ckpt, 21, NULL, NULL);
  printf("| Fig. 3 + fsync'd checkpoint | %ld | 2 | %.2f ms | %.2f ms | journal cost %.2f ms |\n",
         fig3.n_cases, 1e3 * fc, 1e3 * fc / fig3.n_cases, 1e3 * (fc - f2));
  same = pair_times(&freq, reps_big, &g1, &g2, &failed, &gcores);
  printf("| 1000 cases, FE frequencies (2 configs x 3 modes) | %ld | 1 | %.3f s | %.2f ms | %ld "
         "failed |\n",
         freq.n_cases, g1, 1e3 * g1 / freq.n_cases, failed);
  printf("| 1000 cases, FE frequencies (2 configs x 3 modes) | %ld | 2 | %.3f s | %.2f ms | "
         "speed-up %.2fx, CPU/wall %.2f, CSV %s |\n",
         freq.n_cases, g2, 1e3 * g2 / freq.n_cases, g1 / g2, gcores,
         same ? "identical" : "DIFFERS");
  /* checkpoint cost: runs with and without the journal interleaved */
  double *tc = malloc((size_t)reps_big * sizeof *tc), *tn = malloc((size_t)reps_big * sizeof *tn);
  for (int r = 0; r < reps_big; ++r) {
    tn[r] = time_study(&freq, 2, NULL, 1, NULL, NULL);
    tc[r] = time_study(&freq, 2, ckpt, 1, NULL, NULL);
  }
  const double gc = ea_bench_median(tc, reps_big);
  const double gn = ea_bench_median(tn, reps_big);
  free(tc);
  free(tn);
  printf("| 1000 cases + checkpoint (fsync every 0.2 s) | %ld | 2 | %.3f s | %.2f ms | journal "
         "cost %+.1f%% |\n",
         freq.n_cases, gc, 1e3 * gc / freq.n_cases, 100.0 * (gc - gn) / gn);
  planner_rows(reps_plan);
  printf("\nspeed-up 1 -> 2 threads: Fig. 3 %.2fx (4 cases of unequal cost), 1000-case %.2fx "
         "(target >= 1.8x);\nCPU/wall of the 2-thread runs = cores the study actually got "
         "(< 2 when other processes share the machine; load average %s)\n",
         f1 / f2, g1 / g2, loadavg());
  ea_study_free(&fig3);
  ea_study_free(&fig3l);
  ea_study_free(&freq);
  return 0;
}
