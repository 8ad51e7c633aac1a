/* FE-in-the-loop refinement of at-rest plans (docs/planner.md, "Refinement against the FE
 * transient"; planner/nlp/plan_refine.c). References are outside the refinement:
 *  - the residual vibration of the returned plan is measured again by an independent FE
 *    transient at a 16x finer step (dt 0.25 ms instead of the loop's 4 ms; 12 elements,
 *    undamped, 3 s after the motion, the measurement);
 *  - every limit of the task and arm is re-checked from the written trajectory file at 1 kHz
 *    (tests/ea_plan_check.h: the statics solved at every sample), the tension margin too;
 *  - two refinements from two fresh planners give bit-identical evaluations and plans
 *    (Newton, and NLopt BOBYQA run to its evaluation budget);
 *  - bad settings are refused with the key and the bound;
 *  - the CLI's plan --refine writes every evaluation into the JSON summary. */
#include "ea_plan_check.h"
#include "ea_planner.h"
#include "ea_problems.h"
#include "ea_refine.h"
#include "ea_test.h"
#include "ea_test_cli.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static char src[1024];

/* The shipped example: the paper line at rest (payload 0, min_time, 2 modes, 100 knots). */
static int load_rest(ea_task_t *t) {
  char path[1200];
  ea_error_t e = {0};
  snprintf(path, sizeof path, "%s/problems/examples/paper-line-rest.yaml", src);
  const ea_status_t st = ea_task_load(path, NULL, t, &e);
  if (st) printf("load %s: %s\n", path, e.msg);
  return st != EA_OK;
}

/* Independent FE residual peak of the planner's plan: dt 0.25 ms, 12 elements, undamped,
 * genalpha, 3 s after the motion. Also checks that the FE cable tension, which carries every
 * mode the reduced model leaves out, stays within the task's tension limits over the motion
 * and the settle (the plan claims them with two modes at the knots). */
static double fe_peak_dt(const ea_task_t *t, const ea_traj_t *tr, double dt) {
  ea_sim_settings_t s;
  ea_sim_settings_default(&s);
  s.elements = 12;
  s.dt = dt;
  s.settle = 3.0;
  s.damping_ratio = 0.0;
  ea_sim_info_t si;
  ea_error_t e = {0};
  if (ea_traj_simulate(&t->arm, tr, -1.0, &s, NULL, &si, &e)) {
    printf("fine FE: %s\n", e.msg);
    return NAN;
  }
  char what[300];
  snprintf(what, sizeof what,
           "%s: FE cable tension %.4f N (t = %.3f s) .. %.4f N within the task's [%.3g, %.3g] N",
           t->name, si.tension_min, si.tension_min_time, si.tension_max, t->limits.tension_min,
           t->limits.tension_max);
  ea_test_true(si.tension_min >= t->limits.tension_min && si.tension_max <= t->limits.tension_max,
               what);
  return si.residual_peak;
}

static double fe_peak_fine(const ea_task_t *t, const ea_traj_t *tr) {
  return fe_peak_dt(t, tr, 2.5e-4);
}

/* Write the plan's trajectory, read it back and re-check every limit at 1 kHz. Returns the
 * worst relative excess (<= 0: held). */
static double recheck_file(const ea_task_t *t, const ea_traj_t *tr, const char *name) {
  char path[] = "/tmp/ea_test_refine_XXXXXX";
  ea_traj_t back;
  memset(&back, 0, sizeof back);
  ea_error_t e = {0};
  const int fd = mkstemp(path);
  if (fd < 0) return INFINITY;
  close(fd);
  double w = INFINITY;
  if (!ea_traj_write(tr, path, &e) && !ea_traj_read(&back, path, &e)) {
    ea_chk_t c;
    w = ea_chk_traj(t, &back, 1000.0, &c);
    ea_chk_print(name, &c);
  } else {
    printf("%s: %s\n", name, e.msg);
  }
  remove(path);
  ea_traj_free(&back);
  return w;
}

static void print_evals(const ea_refine_info_t *r) {
  for (int i = 0; i < r->n_evals; ++i) {
    const ea_refine_eval_t *e = &r->evals[i];
    printf("  eval %2d: params (%+.4e, %+.4e) m, plan %s (%d it), t_f %.6f s, FE peak %.4f mm, "
           "fitted mode 1 (%+.4f, %+.4f) mm, %.2f s%s\n",
           i, e->params_m[0], e->params_m[1], ea_status_name(e->plan_status), e->plan_iterations,
           e->duration_s, 1e3 * e->residual_peak_m, 1e3 * e->fitted_m[0], 1e3 * e->fitted_m[1],
           e->elapsed_s, e->final_resolve ? " (final re-plan)" : "");
  }
  printf("  %s\n", r->message);
}

/* Cold plan + refinement with s; the refined trajectory in tr. */
static ea_status_t plan_refine(const ea_task_t *t, const ea_task_refine_t *s, ea_planner_t **pl,
                               ea_plan_info_t *pi, ea_refine_info_t *ri, ea_traj_t *tr) {
  ea_error_t e = {0};
  ea_status_t st = ea_planner_alloc(t, pl, &e);
  if (!st) st = ea_planner_solve(*pl, EA_PLAN_COLD, NULL, pi, &e);
  if (!st) st = ea_plan_refine(*pl, s, pi, ri, &e);
  if (!st) st = ea_planner_trajectory(*pl, tr, &e);
  if (st) printf("plan_refine: %s\n", e.msg);
  return st;
}

/* The refined plan of task t meets the tolerance by the fine FE, holds every limit on the
 * file, keeps its duration; returns the fine residual. */
static double check_refined(const char *name, const ea_task_t *t, const ea_plan_info_t *pi,
                            const ea_refine_info_t *ri, const ea_traj_t *tr) {
  char what[600];
  print_evals(ri);
  snprintf(what, sizeof what, "%s: refinement converged (%s, %d evaluations, %.2f s)", name,
           ri->stop_reason, ri->n_evals, ri->time_s);
  ea_test_true(ri->status == EA_OK && ri->converged, what);
  const double fine = fe_peak_fine(t, tr);
  /* measured: 0.0071 mm (payload 0), 0.0186 mm (payload 0.5) at dt 0.25 ms against 0.0076 and
   * 0.0177 mm at the loop's 2 ms; at its 4 ms and 1.5 s settle 0.0061 / 0.0061 mm, 0.0140 /
   * 0.0097 mm, 0.0290 / 0.0264 mm on the random line: the loop's error is <= 5 um */
  snprintf(what, sizeof what,
           "%s: FE residual peak of the refined plan at dt 0.25 ms %.4f mm <= tolerance %.4f mm "
           "(loop, dt 4 ms: %.4f mm; unrefined %.4f mm)",
           name, 1e3 * fine, 1e3 * ri->settings.tolerance_m, 1e3 * ri->residual_peak_m,
           1e3 * ri->residual_peak_before_m);
  ea_test_true(fine <= ri->settings.tolerance_m, what);
  /* measured -0.13 % and -0.08 % on the paper lines, +2.4 % on the random line; the setting
   * allows 10 % */
  const double dd = ri->duration_s / ri->duration_before_s - 1.0;
  snprintf(what, sizeof what, "%s: duration %.6f s within %g %% of the unrefined %.6f s (%+.3f %%)",
           name, ri->duration_s, 100.0 * ri->settings.max_duration_change, ri->duration_before_s,
           100.0 * dd);
  ea_test_true(fabs(dd) <= ri->settings.max_duration_change &&
                   fabs(pi->duration_s - ri->duration_s) == 0.0,
               what);
  const double w = recheck_file(t, tr, name);
  snprintf(what, sizeof what,
           "%s: every limit held by the written refined trajectory at 1 kHz (worst relative "
           "excess %.3g, tolerance 0)",
           name, w);
  ea_test_true(w <= 0.0, what);
  snprintf(what, sizeof what,
           "%s: tension margins of the refined plan: quasi-static %.4g N, with the modal part "
           "%.4g N (>= 0)",
           name, pi->min_tension_margin_N, pi->min_dynamic_tension_margin_N);
  ea_test_true(pi->min_tension_margin_N >= 0.0 && pi->min_dynamic_tension_margin_N >= -1e-9, what);
  return fine;
}

static int same_evals(const ea_refine_info_t *a, const ea_refine_info_t *b) {
  if (a->n_evals != b->n_evals) return 0;
  for (int i = 0; i < a->n_evals; ++i) {
    const ea_refine_eval_t *x = &a->evals[i], *y = &b->evals[i];
    if (memcmp(x->params_m, y->params_m, sizeof x->params_m) ||
        memcmp(x->fitted_m, y->fitted_m, sizeof x->fitted_m) ||
        memcmp(&x->residual_peak_m, &y->residual_peak_m, sizeof(double)) ||
        memcmp(&x->duration_s, &y->duration_s, sizeof(double)))
      return 0;
  }
  return 1;
}

static int same_traj(const ea_traj_t *a, const ea_traj_t *b) {
  return a->n == b->n && !memcmp(a->data, b->data, (size_t)a->n * EA_TRAJ_NCOL * sizeof(double));
}

/* Input checks: fast, no planning. */
static void test_inputs(void) {
  ea_task_t t;
  ea_error_t e = {0};
  if (load_rest(&t)) {
    ea_test_true(0, "load paper-line-rest.yaml");
    return;
  }
  ea_test_true(!t.dynamics.refine.enabled && t.dynamics.refine.tolerance_m == 5e-5 &&
                   t.dynamics.refine.method == EA_TASK_REFINE_NEWTON,
               "refinement off by default; defaults newton, tolerance 5e-5 m");
  ea_task_t u = t;
  u.dynamics.refine.enabled = 1;
  u.dynamics.modes = 0;
  ea_status_t st = ea_task_check(&u, &e);
  printf("  %s\n", e.msg);
  ea_test_true(st == EA_ERR_INPUT && strstr(e.msg, "dynamics.modes"),
               "refine without dynamics: EA_ERR_INPUT naming dynamics.modes");
  u = t;
  u.dynamics.refine.enabled = 1;
  u.dynamics.refine.modes = 3;
  st = ea_task_check(&u, &e);
  printf("  %s\n", e.msg);
  ea_test_true(st == EA_ERR_INPUT && strstr(e.msg, "refine.modes = 3"),
               "refine.modes 3 > dynamics.modes 2: EA_ERR_INPUT with the value");
  u = t;
  u.dynamics.refine.enabled = 1;
  u.dynamics.refine.fe_dt_s = 0.1;
  st = ea_task_check(&u, &e);
  printf("  %s\n", e.msg);
  ea_test_true(st == EA_ERR_INPUT && strstr(e.msg, "fe_dt_s = 0.1") && strstr(e.msg, "1e-2"),
               "refine.fe_dt_s 0.1: EA_ERR_INPUT with the value and the bound");
  /* YAML: position of the refine key */
  char path[] = "/tmp/ea_test_refine_task_XXXXXX";
  const int fd = mkstemp(path);
  if (fd >= 0) {
    FILE *fp = fdopen(fd, "w");
    fprintf(fp,
            "arm_file: %s/data/elasticarm.yaml\nstart:\n  tip: [0.3, -0.2]\ngoal:\n  tip: [0.6, "
            "-0.2]\npath: line\ndynamics:\n  modes: 2\n  residual_m: 0.001\n  refine: {}\n",
            src);
    fclose(fp);
    st = ea_task_load(path, NULL, &u, &e);
    printf("  %s\n", e.msg);
    ea_test_true(st == EA_ERR_INPUT && strstr(e.msg, ":10:11:") && strstr(e.msg, "residual_m"),
                 "YAML refine with residual_m > 0: EA_ERR_INPUT at file:10:11 naming residual_m");
    fp = fopen(path, "w");
    fprintf(fp,
            "arm_file: %s/data/elasticarm.yaml\nstart:\n  tip: [0.3, -0.2]\ngoal:\n  tip: [0.6, "
            "-0.2]\npath: line\ndynamics:\n  modes: 2\n  refine:\n    method: simplex\n",
            src);
    fclose(fp);
    st = ea_task_load(path, NULL, &u, &e);
    printf("  %s\n", e.msg);
    ea_test_true(st == EA_ERR_INPUT && strstr(e.msg, ":10:13:") && strstr(e.msg, "method"),
                 "YAML refine.method simplex: EA_ERR_INPUT at file:10:13 naming the key");
    fp = fopen(path, "w");
    fprintf(fp,
            "arm_file: %s/data/elasticarm.yaml\nstart:\n  tip: [0.3, -0.2]\ngoal:\n  tip: [0.6, "
            "-0.2]\npath: line\ndynamics:\n  modes: 2\n  refine:\n    tolerance_m: 1e-4\n    "
            "method: bobyqa\n    max_evaluations: 8\n",
            src);
    fclose(fp);
    st = ea_task_load(path, NULL, &u, &e);
    ea_test_true(st == EA_OK && u.dynamics.refine.enabled &&
                     u.dynamics.refine.method == EA_TASK_REFINE_BOBYQA &&
                     u.dynamics.refine.tolerance_m == 1e-4 &&
                     u.dynamics.refine.max_evaluations == 8 && u.dynamics.refine.modes == 0,
                 "YAML refine mapping read (method, tolerance, evaluations; modes default 0: "
                 "every mode)");
    remove(path);
  }
  /* a planner without dynamics: EA_ERR_ARG, nothing planned */
  char lp[1200];
  snprintf(lp, sizeof lp, "%s/problems/examples/paper-line.yaml", src);
  ea_planner_t *pl = NULL;
  ea_refine_info_t *ri = calloc(1, sizeof *ri);
  if (!ea_task_load(lp, NULL, &u, &e) && !ea_planner_alloc(&u, &pl, &e) && ri) {
    st = ea_plan_refine(pl, NULL, NULL, ri, &e);
    printf("  %s\n", e.msg);
    ea_test_true(st == EA_ERR_ARG && strstr(e.msg, "dynamics"),
                 "ea_plan_refine on a quasi-static task: EA_ERR_ARG");
  } else {
    ea_test_true(0, "quasi-static planner for the argument check");
  }
  ea_planner_free(pl);
  free(ri);
}

/* Write the random line's task (issue 33: payload factor 0.26, (0.6246, 0.0676) -> (0.5868,
 * -0.1509), 2 modes, at rest) with extra dynamics lines into path. */
static void write_random_line(const char *path, const char *extra) {
  FILE *fp = fopen(path, "w");
  if (!fp) return;
  fprintf(fp,
          "name: random-line\narm_file: %s/data/elasticarm.yaml\npayload_factor: 0.26\nstart:\n"
          "  tip: [0.6246, 0.0676]\ngoal:\n  tip: [0.5868, -0.1509]\npath: line\n"
          "dynamics:\n  modes: 2\n  residual_m: 0\n%s",
          src, extra);
  fclose(fp);
}

/* The FE residual at converged settings (genalpha, dt 0.5 ms, 3 s settle, undamped) of a
 * written trajectory file. */
static double file_fe_peak(const ea_task_t *t, const char *csv) {
  ea_traj_t ft;
  memset(&ft, 0, sizeof ft);
  ea_error_t fe = {0};
  double peak = NAN;
  if (!ea_traj_read(&ft, csv, &fe))
    peak = fe_peak_dt(t, &ft, 5e-4);
  else
    printf("%s\n", fe.msg);
  ea_traj_free(&ft);
  return peak;
}

/* Plans keep their promise of rest by default (issue 33, item 2): the CLI's default FE check,
 * its switches, and exit 3 with what was reached when the bound is not met. */
static void test_cli_promise(void) {
  char arm[1100], args[4000], what[600];
  if (cli_setup(arm, sizeof arm)) {
    ea_test_true(0, "CLI run through ctest");
    return;
  }
  const char *task = "/tmp/ea_test_refine_promise.yaml", *csv = "/tmp/ea_test_refine_promise.csv";
  ea_task_t t;
  ea_error_t e = {0};
  write_random_line(task, "");
  if (ea_task_load(task, NULL, &t, &e)) {
    ea_test_true(0, e.msg);
    return;
  }
  /* default: checked by the FE and refined within 0.5 mm; converged FE <= 1 mm */
  snprintf(args, sizeof args, "plan %s -o %s", task, csv);
  int rc = run(args);
  printf("%s", out);
  ea_test_true(rc == 0 && strstr(out, "plan found") &&
                   strstr(out, "checked by the FE (dt 4 ms, 1.5 s after the motion)") &&
                   strstr(out, "within bound 0.5 mm") && !strstr(out, "NOT"),
               "plan (default): exit 0, 'checked by the FE: ... within bound 0.5 mm'");
  double peak = file_fe_peak(&t, csv);
  snprintf(what, sizeof what,
           "plan (default): the written plan's FE residual at dt 0.5 ms %.4f mm <= 1 mm",
           1e3 * peak);
  ea_test_true(peak <= 1e-3, what);
  snprintf(args, sizeof args, "plan %s -o %s --json", task, csv);
  rc = run(args);
  ea_test_true(rc == 0 && strstr(out, "\"fe_check\": {") && strstr(out, "\"checked\": true") &&
                   strstr(out, "\"within\": true") && json_num("bound_m") == 5e-4,
               "plan --json: fe_check {checked: true, within: true, bound_m: 5e-4}");
  /* --no-verify: not checked, and the plan as planned rings (5.9 mm) */
  snprintf(args, sizeof args, "plan %s -o %s --no-verify", task, csv);
  rc = run(args);
  printf("%s", out);
  peak = file_fe_peak(&t, csv);
  snprintf(what, sizeof what,
           "plan --no-verify: exit 0, 'not checked by the FE (plan --no-verify)', FE residual "
           "%.3f mm > 1 mm (what the check removes)",
           1e3 * peak);
  ea_test_true(rc == 0 && strstr(out, "not checked by the FE (plan --no-verify)") && peak > 1e-3,
               what);
  write_random_line(task, "  verify: false\n");
  snprintf(args, sizeof args, "plan %s -o %s", task, csv);
  rc = run(args);
  ea_test_true(rc == 0 && strstr(out, "not checked by the FE (dynamics.verify: false)"),
               "dynamics.verify: false: exit 0, 'not checked by the FE (dynamics.verify: false)'");
  snprintf(args, sizeof args, "plan %s -o %s --json", task, csv);
  rc = run(args);
  ea_test_true(rc == 0 && strstr(out, "\"checked\": false") &&
                   strstr(out, "\"reason\": \"dynamics.verify: false (or plan --no-verify)\""),
               "dynamics.verify: false, --json: fe_check {checked: false, reason: ...}");
  /* a bound not reached: exit 3, files written, the message says what was reached */
  write_random_line(task, "  refine:\n    max_evaluations: 2\n");
  snprintf(args, sizeof args, "plan %s -o %s", task, csv);
  remove(csv);
  rc = run(args);
  printf("%s", out);
  ea_test_true(rc == 3 && !strstr(out, "plan found") && strstr(out, "NOT at rest") &&
                   strstr(out, "exceeds the bound 0.05 mm") && access(csv, F_OK) == 0,
               "refine.max_evaluations 2: exit 3, 'NOT at rest ... exceeds the bound 0.05 mm', no "
               "'plan found', the plan written");
  /* a residual bound: the payload-0.5 line allowed 1 mm rings with 2.5 mm in the FE; the
   * default check refines it to the bound, then --verify's FE transient (dt 1 ms, 3 s)
   * judges it. Unrefined (--no-verify) with --verify: exit 3, what it reached. */
  FILE *fp = fopen(task, "w");
  if (fp) {
    fprintf(fp,
            "name: bound\narm_file: %s/data/elasticarm.yaml\npayload_factor: 0.5\nstart:\n"
            "  tip: [0.3, -0.2]\ngoal:\n  tip: [0.5, -0.2]\npath: line\n"
            "dynamics:\n  modes: 2\n  residual_m: 0.001\n",
            src);
    fclose(fp);
  }
  rc = run(args);
  printf("%s", out);
  double before = NAN, after = NAN, verdict = NAN;
  /* the summary line (a run over a second also prints "FE residual peak" progress lines) */
  const char *p = strstr(out, "refinement (newton): FE residual peak ");
  if (p) sscanf(p, "refinement (newton): FE residual peak %lf mm -> %lf mm", &before, &after);
  p = strstr(out, "checked by the FE (dt 1 ms, 3 s after the motion): residual peak ");
  if (p)
    sscanf(p, "checked by the FE (dt 1 ms, 3 s after the motion): residual peak %lf", &verdict);
  snprintf(what, sizeof what,
           "residual_m 1 mm on the payload-0.5 line: exit 0 (%d); refined %.4g mm -> %.4g mm, "
           "checked at dt 1 ms: %.4g mm within bound 1 mm",
           rc, before, after, verdict);
  ea_test_true(rc == 0 && before > 2.0 && after <= 1.0 && verdict <= 1.0 &&
                   strstr(out, "within bound 1 mm") && strstr(out, "plan found"),
               what);
  snprintf(args, sizeof args, "plan %s -o %s --json", task, csv);
  rc = run(args);
  ea_test_true(rc == 0 && strstr(out, "\"by\": \"verify\"") && strstr(out, "\"dt_s\": 0.001") &&
                   strstr(out, "\"bound_m\": 0.001") && strstr(out, "\"within\": true") &&
                   strstr(out, "\"evaluations\": "),
               "residual_m 1 mm, --json: fe_check by the verdict (verify, dt 1 ms, bound 1 mm, "
               "within, with the refinement's evaluations)");
  snprintf(args, sizeof args, "plan %s -o %s --no-verify --verify", task, csv);
  rc = run(args);
  printf("%s", out);
  ea_test_true(rc == 3 && strstr(out, "--verify failed") && strstr(out, "exceeds the bound 1 mm"),
               "the same unrefined (--no-verify) with --verify: exit 3, the FE check failed (what "
               "it reached)");
  remove(task);
  remove(csv);
  snprintf(args, sizeof args, "%s.lock", csv);
  remove(args);
  remove("/tmp/ea_test_refine_promise.json");
}

int main(void) {
  const char *s = getenv("EA_SOURCE_DIR");
  snprintf(src, sizeof src, "%s", s ? s : ".");
  test_inputs();
  test_cli_promise();

  ea_task_t t;
  if (load_rest(&t)) {
    ea_test_true(0, "load paper-line-rest.yaml");
    return ea_test_summary("test_refine");
  }
  ea_refine_info_t *ra = calloc(1, sizeof *ra), *rb = calloc(1, sizeof *rb);
  if (!ra || !rb) return EXIT_FAILURE;
  ea_task_refine_t set;
  ea_task_refine_default(&set);

  /* paper line, payload 0: twice from fresh planners (determinism), Newton then BOBYQA */
  ea_planner_t *pa = NULL, *pb = NULL;
  ea_plan_info_t ia, ib;
  ea_traj_t ta, tb;
  memset(&ta, 0, sizeof ta);
  memset(&tb, 0, sizeof tb);
  ea_status_t sa = plan_refine(&t, &set, &pa, &ia, ra, &ta);
  ea_test_true(sa == EA_OK, "paper line at rest, payload 0: planned and refined (Newton)");
  if (!sa) {
    const double fine = check_refined("paper line, payload 0", &t, &ia, ra, &ta);
    /* the bound: <= 0.3 mm after refinement (measured 0.0071 mm; unrefined 0.2300) */
    char what[300];
    snprintf(what, sizeof what,
             "paper line, payload 0: refined FE residual %.4f mm <= 0.3 mm and below a tenth of "
             "the unrefined %.4f mm",
             1e3 * fine, 1e3 * ra->residual_peak_before_m);
    ea_test_true(fine <= 3e-4 && fine < 0.1 * ra->residual_peak_before_m, what);
  }
  ea_status_t sb = plan_refine(&t, &set, &pb, &ib, rb, &tb);
  ea_test_true(sa == EA_OK && sb == EA_OK && same_evals(ra, rb) && same_traj(&ta, &tb),
               "Newton: two refinements from fresh planners give identical evaluations and plans");
  /* NLopt BOBYQA past its tolerance: the budget of 6 evaluations is spent */
  ea_task_refine_t nb = set;
  nb.method = EA_TASK_REFINE_BOBYQA;
  nb.tolerance_m = 1e-7;
  nb.max_evaluations = 6;
  ea_error_t e = {0};
  sa = sa ? sa : ea_plan_refine(pa, &nb, &ia, ra, &e);
  if (!sa) sa = ea_planner_trajectory(pa, &ta, &e);
  sb = sb ? sb : ea_plan_refine(pb, &nb, &ib, rb, &e);
  if (!sb) sb = ea_planner_trajectory(pb, &tb, &e);
  if (!sa) print_evals(ra);
  ea_test_true(sa == EA_OK && !ra->converged && !strcmp(ra->stop_reason, "max_evaluations") &&
                   ra->n_evals >= 6,
               "BOBYQA with an unreachable tolerance stops at its evaluation budget, not "
               "converged");
  ea_test_true(sa == EA_OK && sb == EA_OK && same_evals(ra, rb) && same_traj(&ta, &tb),
               "BOBYQA (seed 1): two refinements give identical evaluations and plans");
  if (!sa) {
    /* the plan it returns is the best evaluated one, still admissible */
    double best = INFINITY;
    for (int i = 0; i < ra->n_evals; ++i)
      if (ra->evals[i].accepted && !ra->evals[i].final_resolve)
        best = fmin(best, ra->evals[i].residual_peak_m);
    char what[300];
    snprintf(what, sizeof what,
             "BOBYQA: the returned plan is the best evaluated (%.4f mm) re-measured %.4f mm",
             1e3 * best, 1e3 * ra->residual_peak_m);
    ea_test_true(fabs(ra->residual_peak_m - best) <= 1e-6, what);
    const double w = recheck_file(&t, &ta, "BOBYQA budget");
    ea_test_true(w <= 0.0, "BOBYQA budget: every limit held by the written trajectory");
  }
  ea_planner_free(pa);
  ea_planner_free(pb);

  /* payload factor 0.5, goal (0.5, -0.2): the model misses 2.1 mm */
  ea_task_t h = t;
  h.payload_factor = 0.5;
  h.payload_kg = ea_arm_payload_from_factor(&h.arm, 0.5);
  h.goal = ea_task_point_planar(0.5, -0.2, 0.0);
  if (ea_task_check(&h, &e)) {
    ea_test_true(0, e.msg);
  } else {
    pa = NULL;
    sa = plan_refine(&h, &set, &pa, &ia, ra, &ta);
    ea_test_true(sa == EA_OK, "payload 0.5, goal (0.5, -0.2): planned and refined");
    if (!sa) {
      /* measured: 2.10 mm unrefined -> 0.0186 mm (dt 0.25 ms) in 3 evaluations */
      const double fine = check_refined("payload 0.5", &h, &ia, ra, &ta);
      char what[300];
      snprintf(what, sizeof what,
               "payload 0.5: unrefined FE residual %.3f mm > 1 mm brought down to %.4f mm",
               1e3 * ra->residual_peak_before_m, 1e3 * fine);
      ea_test_true(ra->residual_peak_before_m > 1e-3 && fine < 0.05 * ra->residual_peak_before_m,
                   what);
    }
    ea_planner_free(pa);
  }

  /* an arm with measured damping (damping.modal_ratios [0.03]): the loop's FE transients damp
   * as the arm does, so the refined plan is at rest by an independent FE with the arm's
   * damping (dt 0.25 ms); refined undamped it kept 0.88 mm there */
  ea_task_t dm = t;
  dm.arm.n_damping = 1;
  dm.arm.damping_ratio[0] = 0.03;
  if (ea_task_check(&dm, &e)) {
    ea_test_true(0, e.msg);
  } else {
    pa = NULL;
    sa = plan_refine(&dm, &set, &pa, &ia, ra, &ta);
    ea_test_true(sa == EA_OK, "damping 0.03: planned and refined");
    if (!sa) {
      print_evals(ra);
      ea_sim_settings_t fs;
      ea_sim_settings_default(&fs); /* damping_ratio NAN: the arm file's */
      fs.elements = 12;
      fs.dt = 2.5e-4;
      fs.settle = 3.0;
      ea_sim_info_t fi;
      const double fine =
          ea_traj_simulate(&dm.arm, &ta, -1.0, &fs, NULL, &fi, &e) ? NAN : fi.residual_peak;
      char what[300];
      snprintf(what, sizeof what,
               "damping 0.03: FE residual with the arm's damping at dt 0.25 ms %.4f mm <= 2 x "
               "tolerance %.4f mm (loop: %.4f mm)",
               1e3 * fine, 2e3 * ra->settings.tolerance_m, 1e3 * ra->residual_peak_m);
      ea_test_true(fine <= 2 * ra->settings.tolerance_m, what);
    }
    ea_planner_free(pa);
  }

  /* A random line (issue 33, item 3): payload factor 0.26, (0.6246, 0.0676) -> (0.5868,
   * -0.1509). The model misses 5.9 mm; Broyden from J = I on mode 1 alone, its candidates
   * capped at +2 % of duration, stopped at 1.11 mm after 20 evaluations (the converged plan
   * is 2.4 % longer). Default settings: every mode, globalised Newton, 25 % duration. */
  h = t;
  h.payload_factor = 0.26;
  h.payload_kg = ea_arm_payload_from_factor(&h.arm, 0.26);
  h.start = ea_task_point_planar(0.6246, 0.0676, 0.0);
  h.goal = ea_task_point_planar(0.5868, -0.1509, 0.0);
  if (ea_task_check(&h, &e)) {
    ea_test_true(0, e.msg);
  } else {
    pa = NULL;
    sa = plan_refine(&h, &set, &pa, &ia, ra, &ta);
    ea_test_true(sa == EA_OK, "random line, payload 0.26: planned and refined");
    if (!sa) {
      const double fine = check_refined("random line, payload 0.26", &h, &ia, ra, &ta);
      char what[300];
      snprintf(what, sizeof what,
               "random line: unrefined %.3f mm brought down to %.4f mm (dt 0.25 ms) within %d "
               "evaluations",
               1e3 * ra->residual_peak_before_m, 1e3 * fine, ra->n_evals);
      ea_test_true(ra->residual_peak_before_m > 1e-3 && fine <= set.tolerance_m, what);
    }
    ea_planner_free(pa);
  }
  ea_traj_free(&ta);
  ea_traj_free(&tb);
  free(ra);
  free(rb);

  /* CLI: plan --refine writes the refined plan and every evaluation into the summary */
  char arm[1100], args[4000], csv[] = "/tmp/ea_test_refine_cli_XXXXXX";
  if (cli_setup(arm, sizeof arm)) {
    ea_test_true(0, "CLI run through ctest");
  } else {
    const int fd = mkstemp(csv);
    if (fd >= 0) close(fd);
    snprintf(args, sizeof args,
             "plan %s/problems/examples/paper-line-rest.yaml --refine -o %s --summary %s.json "
             "--json",
             src, csv, csv);
    int rc = run(args);
    ea_test_true(rc == 0 && strstr(out, "\"refine\": {") && strstr(out, "\"evaluation_log\"") &&
                     strstr(out, "\"converged\": true"),
                 "plan --refine: exit 0, summary with the refine object and its evaluations");
    const double ev = json_num("evaluations"), peak = json_num("residual_peak_m");
    char what[300];
    snprintf(what, sizeof what,
             "plan --refine: %g evaluations logged, residual_peak_m %.4g m <= tolerance 5e-5 m", ev,
             peak);
    ea_test_true(ev >= 1 && peak <= 5e-5, what);
    ea_traj_t ft;
    memset(&ft, 0, sizeof ft);
    ea_error_t fe = {0};
    if (!ea_traj_read(&ft, csv, &fe)) {
      const double w = recheck_file(&t, &ft, "plan --refine file");
      ea_test_true(w <= 0.0, "plan --refine: every limit held by the written file at 1 kHz");
      const double fine = fe_peak_fine(&t, &ft);
      snprintf(what, sizeof what, "plan --refine: file's FE residual at dt 0.25 ms %.4f mm",
               1e3 * fine);
      ea_test_true(fine <= 5e-5, what);
    } else {
      ea_test_true(0, fe.msg);
    }
    ea_traj_free(&ft);
    remove(csv);
    snprintf(args, sizeof args, "%s.json", csv);
    remove(args);
    snprintf(args, sizeof args,
             "plan %s/problems/examples/paper-line.yaml --refine -o /tmp/ea_test_refine_none.csv",
             src);
    rc = run(args);
    printf("  %s", out);
    ea_test_true(rc == 2 && strstr(out, "dynamics.modes") &&
                     access("/tmp/ea_test_refine_none.csv", F_OK) != 0,
                 "plan --refine on a task without dynamics: exit 2 naming dynamics.modes, nothing "
                 "written");
  }
  return ea_test_summary("test_refine");
}
