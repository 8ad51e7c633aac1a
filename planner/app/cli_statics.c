/* CLI: statics, workspace, torque-map, path (paper sec. 2). */
#include "cli_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ------------------------------------------------------------------------ */
/* Shared pieces                                                             */
/* ------------------------------------------------------------------------ */

typedef struct {
  int no_stability;
  const char *arm_file;
  ea__cli_payload_t payload;
  int json;
  const char *figure;
  const char *csv;
} ea__common_t;

/* The options shared by the statics commands (in each one's table). */
#define EA__COMMON_OPTS                                                                            \
  {"help", 0, 'h'}, {"arm", 1, 0}, {"payload-factor", 1, 0}, {"payload-kg", 1, 0}, {"json", 0, 0}, \
      {"no-stability", 0, 0}, {"figure", 1, 0}, {                                                  \
    "csv", 1, 0                                                                                    \
  }

/* One option a (value v) shared by the statics commands; returns 1 if consumed,
 * 0 if not ours, -1 on error (message printed). */
static int ea__common_opt(const char *cmd, const char *a, const char *v, ea__common_t *c) {
  if (!strcmp(a, "--arm")) {
    c->arm_file = v;
  } else if (!strcmp(a, "--payload-factor") || !strcmp(a, "--payload-kg")) {
    if (c->payload.given)
      return ea__cli_usage_error(cmd, "give --payload-factor or --payload-kg once"), -1;
    c->payload.given = !strcmp(a, "--payload-factor") ? 1 : 2;
    if (ea__cli_double(cmd, a, v, 0.0, 1e3, &c->payload.value)) return -1;
  } else if (!strcmp(a, "--json")) {
    c->json = 1;
  } else if (!strcmp(a, "--no-stability")) {
    c->no_stability = 1;
  } else if (!strcmp(a, "--figure")) {
    if (ea__cli_check_figure(cmd, v)) return -1; /* before the work */
    c->figure = v;
  } else if (!strcmp(a, "--csv")) {
    c->csv = v;
  } else {
    return 0;
  }
  return 1;
}

static const char *ea__common_help =
    "  --arm FILE            arm parameters (default: see elasticarm --help)\n"
    "  --payload-factor G    payload m_p = G (m_h + rho L) (eq. 17)\n"
    "  --payload-kg M        payload mass [kg]\n"
    "  --json                JSON on stdout\n"
    "  --no-stability        skip the FE stability check (statics, path)\n"
    "  --figure OUT          draw a figure (.svg, .png or .pdf)\n";

static int ea__make_shooter(const char *cmd, const ea_arm_t *arm, double tip_mass,
                            ea_shooter_t **sh) {
  ea_error_t err = {0};
  ea_status_t st = ea_shooter_alloc(arm, NULL, sh, &err);
  if (st) return ea__cli_fail(cmd, st, &err);
  ea_load_t load = {tip_mass};
  ea_shooter_set_load(*sh, &load);
  return 0;
}

static void ea__json_point(ea_json_t *j, const char *key, const ea_config_point_t *p) {
  ea_json_obj_begin(j, key);
  ea_json_num(j, "cable_length_m", p->cable_length);
  ea_json_num(j, "cable_angle_rad", p->alpha);
  ea_json_vec(j, "tip_m", (double[]){p->x, p->y}, 2);
  ea_json_num(j, "tension_N", p->tension);
  ea_json_num(j, "theta0_rad", p->theta0);
  ea_json_num(j, "kappa0_per_m", p->kappa0);
  ea_json_num(j, "shoulder_torque_Nm", p->shoulder_torque);
  ea_json_num(j, "residual", p->residual);
  ea_json_str(j, "status", ea_status_name(p->status));
  ea_json_bool(j, "admissible", p->admissible);
  ea_json_str(j, "reason", p->reason);
  ea_json_obj_end(j);
}

static const char *ea__csv_point_header =
    "cable_length_m,cable_angle_rad,tip_x_m,tip_y_m,tension_N,theta0_rad,kappa0_per_m,"
    "shoulder_torque_Nm,residual,status,admissible,reason";

static void ea__csv_point(FILE *fp, const ea_config_point_t *p) {
  fprintf(fp, "%.12g,%.12g,%.12g,%.12g,%.12g,%.12g,%.12g,%.12g,%.3g,%s,%d,", p->cable_length,
          p->alpha, p->x, p->y, p->tension, p->theta0, p->kappa0, p->shoulder_torque, p->residual,
          ea_status_name(p->status), p->admissible);
  ea__csv_quote(fp, p->reason);
}

/* Leading columns of row k of a points CSV. */
typedef void (*ea__csv_prefix_fn)(FILE *fp, int k, const void *ctx);

/* Write n points as a CSV to path (atomically; "-" = stdout): a header of
 * prefix_header (may be "") and the point columns, then one row per point.
 * point(k, ctx) gives row k's point. Returns 0 or the exit code. */
static int ea__write_points_csv(const char *cmd, const char *path, const char *prefix_header, int n,
                                const ea_config_point_t *(*point)(int k, const void *ctx),
                                ea__csv_prefix_fn prefix, const void *ctx) {
  ea_afile_t f;
  ea_error_t err = {0};
  if (ea_afile_open(&f, path, &err)) return ea__cli_fail(cmd, err.status, &err);
  fprintf(f.fp, "%s%s\n", prefix_header, ea__csv_point_header);
  for (int k = 0; k < n; ++k) {
    if (prefix) prefix(f.fp, k, ctx);
    ea__csv_point(f.fp, point(k, ctx));
    fputc('\n', f.fp);
  }
  if (ea_afile_commit(&f, &err)) return ea__cli_fail(cmd, err.status, &err);
  return 0;
}

/* Points stored contiguously. */
static const ea_config_point_t *ea__point_array(int k, const void *ctx) {
  return (const ea_config_point_t *)ctx + k;
}

static int ea__help_requested(int argc, char **argv) {
  return ea__cli_help_asked(argc, argv);
}

/* ------------------------------------------------------------------------ */
/* statics                                                                   */
/* ------------------------------------------------------------------------ */

static void ea__statics_help(void) {
  printf("usage: elasticarm statics (--cable-length M --cable-angle-deg A | --tip X,Y |\n"
         "                           --tension N --cable-angle-deg A | --tension N "
         "--theta0-deg D) [options]\n"
         "Solves the planar statics (eq. 11, 14-16) on the physical branch, then checks\n"
         "the arm's limits (tension, cable length range, shoulder torque and angle) and,\n"
         "unless --no-stability, FE stability: 'admissible' says whether all hold, and\n"
         "why not.\n"
         "  --shape N             add N centreline points to the output\n"
         "  --guess-deg A,T,TH,K  warm start (alpha deg, T N, theta0 deg, kappa0 1/m)\n%s"
         "exit: 0 solved and admissible, 1 no solution or not admissible (or the figure\n"
         "failed), 2 usage or input error\n",
         ea__common_help);
}

/* The options of `elasticarm statics` and the problem they state. */
typedef struct {
  ea__common_t c;
  double tip[2];
  double guess[EA_NP];
  int has_guess, has_tip;
  long shape;
  ea_statics_problem_t prob;
} ea__statics_opts_t;

/* --guess-deg A,T,TH,K into o->guess. 0 or the exit code. */
static int ea__statics_guess(const char *cmd, const char *a, const char *v, ea__statics_opts_t *o) {
  double *g = NULL;
  int ng = 0;
  int bad = ea__cli_list(cmd, a, v, &g, &ng);
  if (!bad && ng != EA_NP)
    bad = ea__cli_usage_error(cmd, "%s: '%s' is not 4 values alpha_deg,T,theta0_deg,kappa0", a, v);
  if (!bad) {
    o->guess[EA_P_ALPHA] = g[0] * EA__DEG;
    o->guess[EA_P_TENSION] = g[1];
    o->guess[EA_P_THETA0] = g[2] * EA__DEG;
    o->guess[EA_P_KAPPA0] = g[3];
    o->has_guess = 1;
  }
  free(g);
  return bad;
}

/* Parse the options and state the problem. 0 or the exit code. */
static int ea__statics_parse(const char *cmd, int argc, char **argv, ea__statics_opts_t *o) {
  memset(o, 0, sizeof *o);
  double Lc = NAN, adeg = NAN, T = NAN, th0deg = NAN;
  o->tip[0] = o->tip[1] = NAN;
  static const ea__cli_opt_t opts[] = {
      EA__COMMON_OPTS,   {"cable-length", 1, 0}, {"cable-angle-deg", 1, 0},
      {"tension", 1, 0}, {"theta0-deg", 1, 0},   {"tip", 1, 0},
      {"shape", 1, 0},   {"guess-deg", 1, 0},    {NULL, 0, 0}};
  ea__cli_args_t g;
  ea__cli_args_init(&g, cmd, argc, argv, opts);
  int gr;
  while ((gr = ea__cli_args_next(&g)) > 0) {
    const char *a = g.opt, *v = g.arg;
    if (!a) {
      ea__cli_usage_error(cmd, "unexpected argument '%s'", v);
      return EA_EXIT_USAGE;
    }
    int r = ea__common_opt(cmd, a, v, &o->c);
    if (r < 0) return EA_EXIT_USAGE;
    if (r) continue;
    int bad;
    if (!strcmp(a, "--cable-length"))
      bad = ea__cli_double(cmd, a, v, 1e-6, 100.0, &Lc);
    else if (!strcmp(a, "--cable-angle-deg"))
      bad = ea__cli_double(cmd, a, v, -180.0, 180.0, &adeg);
    else if (!strcmp(a, "--tension"))
      bad = ea__cli_double(cmd, a, v, -1e6, 1e6, &T);
    else if (!strcmp(a, "--theta0-deg"))
      bad = ea__cli_double(cmd, a, v, -360.0, 360.0, &th0deg);
    else if (!strcmp(a, "--tip"))
      bad = ea__cli_pair(cmd, a, v, o->tip);
    else if (!strcmp(a, "--shape"))
      bad = ea__cli_int(cmd, a, v, 2, 10000, &o->shape);
    else if (!strcmp(a, "--guess-deg"))
      bad = ea__statics_guess(cmd, a, v, o);
    else
      return ea__cli_usage_error(cmd, "unknown option '%s'", a);
    if (bad) return bad;
  }
  if (gr < 0) return EA_EXIT_USAGE;
  const int has_L = isfinite(Lc), has_a = isfinite(adeg), has_T = isfinite(T),
            has_th = isfinite(th0deg), has_tip = isfinite(o->tip[0]);
  o->has_tip = has_tip;
  if (has_L && has_a && !has_T && !has_th && !has_tip)
    o->prob = ea_statics_problem_cable(Lc, adeg * EA__DEG);
  else if (has_tip && !has_L && !has_a && !has_T && !has_th)
    o->prob = ea_statics_problem_tip(o->tip[0], o->tip[1]);
  else if (has_T && has_a && !has_L && !has_th && !has_tip)
    o->prob = ea_statics_problem_tension_alpha(T, adeg * EA__DEG);
  else if (has_T && has_th && !has_L && !has_a && !has_tip)
    o->prob = ea_statics_problem_tension_theta0(T, th0deg * EA__DEG);
  else
    return ea__cli_usage_error(cmd, "give exactly one of: --cable-length with "
                                    "--cable-angle-deg; --tip; --tension with "
                                    "--cable-angle-deg; --tension with --theta0-deg");
  return 0;
}

/* The solution against the arm's limits, as path and torque-map check them, and FE
 * stability (*stable: 1, 0, or -1 when not checked). */
static void ea__statics_check(const ea_arm_t *arm, ea_shooter_t *sh,
                              const ea_statics_solution_t *sol, ea_status_t st, int no_stability,
                              int *stable, ea_config_point_t *cp) {
  const int solved = st == EA_OK;
  *stable = -1;
  if (solved && !no_stability) {
    ea_fe_model_t *fe = NULL;
    ea_fe_static_info_t fi;
    if (ea_fe_model_alloc(arm, NULL, &fe, NULL) == EA_OK &&
        ea_fe_model_set_load(fe, ea_shooter_load(sh)) == EA_OK &&
        ea_fe_static_solve(fe, sh, sol, &fi, NULL) == EA_OK)
      ea_fe_stability(fe, stable, NULL);
    ea_fe_model_free(fe);
  }
  memset(cp, 0, sizeof *cp);
  cp->cable_length = sol->cable_length;
  cp->alpha = sol->p[EA_P_ALPHA];
  cp->tension = sol->p[EA_P_TENSION];
  cp->theta0 = sol->p[EA_P_THETA0];
  cp->kappa0 = sol->p[EA_P_KAPPA0];
  cp->shoulder_torque = arm->EI * sol->p[EA_P_KAPPA0];
  cp->status = st;
  ea_config_check_limits(cp, &arm->act, 0.0);
  if (solved && cp->admissible && *stable == 0) {
    cp->admissible = 0;
    snprintf(cp->reason, sizeof cp->reason,
             "unstable: the FE passive stiffness is not positive definite");
  }
}

/* What `statics` found, for printing: the solution, its check and the beam's shape. */
typedef struct {
  const ea_arm_t *arm;
  ea_shooter_t *sh;
  const ea_statics_solution_t *sol;
  const ea_error_t *err;
  int solved, stable;
  const ea_config_point_t *cp;
  long shape;
  const double *sx, *sy;
} ea__statics_out_t;

static void ea__statics_json(const ea__statics_out_t *r) {
  const ea_statics_solution_t *sol = r->sol;
  ea_json_t j;
  ea_json_init(&j, stdout, 1);
  ea_json_obj_begin(&j, NULL);
  ea_json_str(&j, "status", ea_status_name(sol->status));
  ea_json_str(&j, "message", r->solved ? "ok" : r->err->msg);
  ea_json_num(&j, "tension_N", sol->p[EA_P_TENSION]);
  ea_json_num(&j, "theta0_rad", sol->p[EA_P_THETA0]);
  ea_json_num(&j, "kappa0_per_m", sol->p[EA_P_KAPPA0]);
  ea_json_num(&j, "shoulder_torque_Nm", r->arm->EI * sol->p[EA_P_KAPPA0]);
  ea_json_num(&j, "cable_angle_rad", sol->p[EA_P_ALPHA]);
  ea_json_num(&j, "cable_length_m", r->solved ? sol->cable_length : NAN);
  ea_json_vec(&j, "tip_m", (double[]){sol->tip[EA_X_X], sol->tip[EA_X_Y]}, 2);
  ea_json_num(&j, "tip_angle_rad", sol->tip[EA_X_THETA]);
  ea_json_num(&j, "tip_mass_kg", ea_shooter_load(r->sh)->tip_mass);
  ea_json_num(&j, "residual", sol->residual);
  ea_json_int(&j, "iterations", sol->iterations);
  ea_json_int(&j, "continuation_steps", sol->cont_steps);
  ea_json_str(&j, "branch",
              sol->branch == EA_BRANCH_EDGE   ? "physical (continued from T = 0 edge)"
              : sol->branch == EA_BRANCH_WARM ? "warm start"
                                              : "none");
  ea_json_num(&j, "winding_rad", sol->winding);
  if (r->stable >= 0)
    ea_json_bool(&j, "stable", r->stable);
  else
    ea_json_null(&j, "stable");
  ea_json_bool(&j, "admissible", r->solved && r->cp->admissible);
  ea_json_str(&j, "reason", r->solved ? r->cp->reason : r->err->msg);
  if (r->solved && r->shape > 0) {
    ea_json_arr_begin(&j, "shape_m");
    for (long k = 0; k < r->shape; ++k)
      ea_json_vec(&j, NULL, (double[]){r->sx[k], r->sy[k]}, 2);
    ea_json_arr_end(&j);
  }
  ea_json_obj_end(&j);
  ea_json_end(&j);
}

static void ea__statics_text(const ea__statics_out_t *r) {
  const ea_statics_solution_t *sol = r->sol;
  printf("status            %s (residual %.2e, %d iterations, %d continuation steps)\n",
         ea_status_name(sol->status), sol->residual, sol->iterations, sol->cont_steps);
  printf("cable length      %.9f m\ncable angle       %.9f deg\ntension           %.9f N\n"
         "theta0            %.9f deg\nkappa0            %.9f 1/m\nshoulder torque   %.9f N m\n"
         "tip               (%.9f, %.9f) m\n",
         sol->cable_length, sol->p[EA_P_ALPHA] / EA__DEG, sol->p[EA_P_TENSION],
         sol->p[EA_P_THETA0] / EA__DEG, sol->p[EA_P_KAPPA0], sol->shoulder_torque, sol->tip[EA_X_X],
         sol->tip[EA_X_Y]);
  printf("stable (FE)       %s\n", r->stable < 0 ? "not checked" : r->stable ? "yes" : "NO");
  printf("admissible        %s%s\n", r->cp->admissible ? "yes" : "NO: ", r->cp->reason);
  for (long k = 0; k < r->shape; ++k)
    printf("shape %ld  %.9f %.9f\n", k, r->sx[k], r->sy[k]);
}

/* The beam and the cable of the solution. 0 or EA_EXIT_FAIL. */
static int ea__statics_figure(const ea__statics_out_t *r, const char *figure) {
  const ea_statics_solution_t *sol = r->sol;
  ea_plot_t *pl;
  ea_error_t fe = {0};
  if (ea_plot_open(&pl, figure, 700, 650, &fe) == EA_OK) {
    ea_plot_data_begin(pl, "beam");
    ea_plot_beam(pl, r->sh, sol->p, 81);
    ea_plot_data_end(pl);
    ea_plot_data_begin(pl, "cable");
    ea_plot_data_row(pl, 2, (double[]){r->arm->x_c, r->arm->y_c});
    ea_plot_data_row(pl, 2, (double[]){sol->tip[EA_X_X], sol->tip[EA_X_Y]});
    ea_plot_data_end(pl);
    ea_plot_cmd(pl, "set size ratio -1\nset xlabel 'x [m]'\nset ylabel 'y [m]'");
    ea_plot_cmd(pl,
                "set title 'L_c = %.3f m, {/Symbol a} = %.1f deg, T = %.2f N, "
                "{/Symbol q}_0 = %.1f deg'",
                sol->cable_length, sol->p[EA_P_ALPHA] / EA__DEG, sol->p[EA_P_TENSION],
                sol->p[EA_P_THETA0] / EA__DEG);
    ea_plot_cmd(pl, "plot $beam w l lw 3 lc rgb '#1f4e9c' t 'beam', $cable w lp lw 1 dt 2 "
                    "pt 7 lc rgb '#c0392b' t 'cable'");
    fe.status = ea_plot_close(pl, &fe);
  }
  if (!fe.status) return 0;
  fprintf(stderr, "elasticarm statics: figure: %s\n", fe.msg);
  return EA_EXIT_FAIL;
}

int ea__cli_statics(int argc, char **argv) {
  const char *cmd = "statics";
  if (ea__help_requested(argc, argv)) {
    ea__statics_help();
    return EA_EXIT_OK;
  }
  ea__statics_opts_t o;
  int rc = ea__statics_parse(cmd, argc, argv, &o);
  if (rc) return rc;
  ea_arm_t arm;
  if ((rc = ea__cli_load_arm(cmd, o.c.arm_file, &arm))) return rc;
  /* The cable angle is undefined for a tip at the cable root; the same
   * bound as --cable-length's. */
  if (o.has_tip && hypot(o.tip[0] - arm.x_c, o.tip[1] - arm.y_c) < 1e-6)
    return ea__cli_usage_error(cmd,
                               "--tip %.9g,%.9g is at the cable root (%.9g, %.9g): no cable, "
                               "its angle is undefined (the tip must be >= 1e-6 m from it)",
                               o.tip[0], o.tip[1], arm.x_c, arm.y_c);
  ea_shooter_t *sh = NULL;
  if ((rc = ea__make_shooter(cmd, &arm, ea__cli_tip_mass(&arm, &o.c.payload), &sh))) return rc;
  ea_statics_solution_t sol;
  ea_error_t err = {0};
  ea_status_t st = ea_statics_solve(sh, &o.prob, NULL, o.has_guess ? o.guess : NULL, &sol, &err);
  if (st == EA_OK && !(sol.cable_length >= 1e-6)) {
    st = ea_error_set(&err, EA_ERR_INADMISSIBLE,
                      "the solution has the tip at the cable root (L_c = %.3g m): no cable",
                      sol.cable_length);
    sol.status = st;
  }
  const int solved = st == EA_OK;
  int stable;
  ea_config_point_t cp;
  ea__statics_check(&arm, sh, &sol, st, o.c.no_stability, &stable, &cp);
  double *sx = NULL, *sy = NULL;
  long shape = o.shape;
  if (solved && shape > 0) {
    sx = malloc((size_t)shape * sizeof *sx);
    sy = malloc((size_t)shape * sizeof *sy);
    if (!sx || !sy || ea_shoot_shape(sh, sol.p, (int)shape, NULL, NULL, NULL, sx, sy)) shape = 0;
  }
  const ea__statics_out_t r = {&arm, sh, &sol, &err, solved, stable, &cp, shape, sx, sy};
  if (o.c.json)
    ea__statics_json(&r);
  else if (solved)
    ea__statics_text(&r);
  if (solved && o.c.figure) rc = ea__statics_figure(&r, o.c.figure);
  free(sx);
  free(sy);
  ea_shooter_free(sh);
  if (!solved) {
    if (!o.c.json) ea__cli_fail(cmd, st, &err);
    return EA_EXIT_FAIL;
  }
  if (!cp.admissible) {
    fprintf(stderr, "elasticarm statics: not admissible: %s\n", cp.reason);
    return EA_EXIT_FAIL;
  }
  return rc;
}

/* ------------------------------------------------------------------------ */
/* workspace                                                                 */
/* ------------------------------------------------------------------------ */

/* Workspace CSV rows: for each payload, the outer then the inner edge. */
struct ea__ws_csv {
  const double *gam;
  const ea_config_point_t *outer, *inner;
  int n;
};
static const ea_config_point_t *ea__ws_point(int k, const void *vctx) {
  const struct ea__ws_csv *c = vctx;
  const int g = k / (2 * c->n), e = (k / c->n) % 2, i = k % c->n;
  return (e ? c->inner : c->outer) + (size_t)g * c->n + i;
}
static void ea__ws_prefix(FILE *fp, int k, const void *vctx) {
  const struct ea__ws_csv *c = vctx;
  fprintf(fp, "%.6g,%s,", c->gam[k / (2 * c->n)], (k / c->n) % 2 ? "inner" : "outer");
}

/* Where a workspace extremum sits, for the table. */
static void ea__ws_where(const ea_workspace_extremum_t *e, char *buf, size_t len) {
  int w = snprintf(buf, len, "alpha %.4g deg, %s", e->alpha / EA__DEG, ea_ws_bound_name(e->bound));
  if (w > 0 && (size_t)w < len && e->bound2)
    w += snprintf(buf + w, len - (size_t)w, " / %s", ea_ws_bound_name(e->bound2));
  if (w > 0 && (size_t)w < len && e->at_end)
    snprintf(buf + w, len - (size_t)w, " [%s: the range bounds it]", ea_ws_bound_name(e->at_end));
}

/* The workspace command: options, then per payload factor the region's metrics and
 * both edges. */
typedef struct {
  ea__common_t c;
  double amin, amax, inner; /* [deg], [deg], [m] */
  long npts;
  int no_limits;
  double *gam; /* payload factors (owned) */
  int ng;
  double *kg; /* --payload-kg: payload masses [kg] (owned), the factors once the arm is known */
  int nkg;
  /* results */
  ea_arm_t arm;
  int n; /* cable angles */
  double *alpha;
  ea_config_point_t *outer, *inn; /* ng x n each */
  ea_workspace_metrics_t *met;    /* ng */
  ea_workspace_settings_t wset;
  ea_shooter_t *sh;
  int failures; /* payloads with outer-edge points without a solution */
} ea__ws_run_t;

/* Options; 0 or the exit code. */
static int ea__ws_parse(const char *cmd, int argc, char **argv, ea__ws_run_t *w) {
  w->amin = -60.0;
  w->amax = 10.0;
  w->inner = NAN;
  w->npts = 71;
  static const ea__cli_opt_t opts[] = {EA__COMMON_OPTS,           {"no-limits", 0, 0},
                                       {"payload-factors", 1, 0}, {"alpha-min-deg", 1, 0},
                                       {"alpha-max-deg", 1, 0},   {"points", 1, 0},
                                       {"inner-length", 1, 0},    {NULL, 0, 0}};
  ea__cli_args_t g;
  ea__cli_args_init(&g, cmd, argc, argv, opts);
  int gr;
  while ((gr = ea__cli_args_next(&g)) > 0) {
    const char *a = g.opt, *v = g.arg;
    if (!a) {
      ea__cli_usage_error(cmd, "unexpected argument '%s'", v);
      return EA_EXIT_USAGE;
    }
    if (!strcmp(a, "--payload-kg")) { /* a list here: factors once the arm is loaded */
      free(w->kg);
      w->kg = NULL;
      if (ea__cli_list(cmd, a, v, &w->kg, &w->nkg)) return EA_EXIT_USAGE;
      for (int k = 0; k < w->nkg; ++k)
        if (!(w->kg[k] >= 0 && w->kg[k] <= 1e3))
          return ea__cli_usage_error(cmd, "%s: payload %g kg is outside [0, 1000]", a, w->kg[k]);
      continue;
    }
    int r = strcmp(a, "--payload-factor") ? ea__common_opt(cmd, a, v, &w->c) : 0;
    if (r < 0) return EA_EXIT_USAGE;
    if (r) continue;
    if (!strcmp(a, "--no-limits")) {
      w->no_limits = 1;
      continue;
    }
    int bad;
    if (!strcmp(a, "--payload-factors") || !strcmp(a, "--payload-factor")) {
      free(w->gam);
      bad = ea__cli_list(cmd, a, v, &w->gam, &w->ng);
      for (int k = 0; !bad && k < w->ng; ++k)
        if (!(w->gam[k] >= 0 && w->gam[k] <= 100))
          bad = ea__cli_usage_error(cmd, "%s: payload factor %g is outside [0, 100]", a, w->gam[k]);
    } else if (!strcmp(a, "--alpha-min-deg"))
      bad = ea__cli_double(cmd, a, v, -180, 180, &w->amin);
    else if (!strcmp(a, "--alpha-max-deg"))
      bad = ea__cli_double(cmd, a, v, -180, 180, &w->amax);
    else if (!strcmp(a, "--points"))
      bad = ea__cli_int(cmd, a, v, 2, 100000, &w->npts);
    else if (!strcmp(a, "--inner-length"))
      bad = ea__cli_double(cmd, a, v, 1e-6, 100, &w->inner);
    else
      bad = ea__cli_usage_error(cmd, "unknown option '%s'", a);
    if (bad) return bad;
  }
  if (gr < 0) return EA_EXIT_USAGE;
  if (!(w->amin < w->amax))
    return ea__cli_usage_error(cmd, "--alpha-min-deg %g must be below --alpha-max-deg %g", w->amin,
                               w->amax);
  if (w->gam && w->kg)
    return ea__cli_usage_error(cmd, "give --payload-factors or --payload-kg, not both");
  if (!w->gam && !w->kg) {
    static const double def[] = {0.0, 0.1, 0.25, 0.5};
    w->ng = 4;
    if (!(w->gam = malloc(sizeof def))) return ea__cli_oom(cmd, "payload factors");
    memcpy(w->gam, def, sizeof def);
  }
  return 0;
}

/* Per payload: the metrics first (a region that is empty or ill-defined is an error
 * before anything is written), then the outer and inner edges. 0 or the exit code. */
static int ea__ws_compute(const char *cmd, ea__ws_run_t *w) {
  int rc = ea__cli_load_arm(cmd, w->c.arm_file, &w->arm);
  if (rc) return rc;
  const ea_arm_t *arm = &w->arm;
  if (w->kg) { /* --payload-kg: the factors of these masses (eq. 17) */
    w->gam = malloc((size_t)w->nkg * sizeof *w->gam);
    if (!w->gam) return ea__cli_oom(cmd, "payload factors");
    for (int k = 0; k < w->nkg; ++k)
      w->gam[k] = w->kg[k] / ea_arm_payload_from_factor(arm, 1.0);
    w->ng = w->nkg;
  }
  if (!isfinite(w->inner)) w->inner = arm->act.cable_length_min;
  const int n = w->n = (int)w->npts, ng = w->ng;
  w->alpha = malloc((size_t)n * sizeof *w->alpha);
  w->outer = calloc((size_t)n * ng, sizeof *w->outer);
  w->inn = calloc((size_t)n * ng, sizeof *w->inn);
  w->met = calloc((size_t)ng, sizeof *w->met);
  if (!w->alpha || !w->outer || !w->inn || !w->met) return ea__cli_oom(cmd, "workspace edges");
  for (int k = 0; k < n; ++k)
    w->alpha[k] = (w->amin + (w->amax - w->amin) * k / (n - 1)) * EA__DEG;
  if ((rc = ea__make_shooter(cmd, arm, arm->m_hand, &w->sh))) return rc;
  ea_workspace_settings_default(&w->wset);
  w->wset.alpha_min = w->amin * EA__DEG;
  w->wset.alpha_max = w->amax * EA__DEG;
  w->wset.inner_cable_length = w->inner;
  w->wset.limits = !w->no_limits;
  w->wset.samples = n;
  for (int g = 0; g < ng; ++g) {
    ea_load_t load = {ea_arm_tip_mass(arm, ea_arm_payload_from_factor(arm, w->gam[g]))};
    ea_shooter_set_load(w->sh, &load);
    ea_error_t me = {0};
    const ea_status_t ms = ea_workspace_metrics(w->sh, &w->wset, &w->met[g], &me);
    if (ms) {
      fprintf(stderr, "elasticarm %s: error: payload factor %g: %s\n", cmd, w->gam[g], me.msg);
      return ms == EA_ERR_INADMISSIBLE || ms == EA_ERR_ARG ? EA_EXIT_USAGE : EA_EXIT_FAIL;
    }
    if (ea_workspace_outer(w->sh, w->alpha, n, w->outer + (size_t)g * n)) ++w->failures;
    ea_workspace_inner(w->sh, w->inner, w->alpha, n, w->inn + (size_t)g * n);
  }
  return 0;
}

static void ea__ws_json(const ea__ws_run_t *w) {
  const int n = w->n;
  ea_json_t j;
  ea_json_init(&j, stdout, 1);
  ea_json_obj_begin(&j, NULL);
  ea_json_num(&j, "inner_cable_length_m", w->inner);
  ea_json_num(&j, "alpha_min_rad", w->wset.alpha_min);
  ea_json_num(&j, "alpha_max_rad", w->wset.alpha_max);
  ea_json_bool(&j, "limits", w->wset.limits);
  ea_json_arr_begin(&j, "payloads");
  for (int g = 0; g < w->ng; ++g) {
    const ea_config_point_t *o = w->outer + (size_t)g * n, *in = w->inn + (size_t)g * n;
    const ea_workspace_metrics_t *m = &w->met[g];
    ea_json_obj_begin(&j, NULL);
    ea_json_num(&j, "payload_factor", w->gam[g]);
    ea_json_num(&j, "payload_kg", ea_arm_payload_from_factor(&w->arm, w->gam[g]));
    ea_json_num(&j, "area_m2", m->area);
    ea_json_num(&j, "area_error_m2", m->area_error);
    const ea_workspace_extremum_t *ex[3] = {&m->reach, &m->x_max, &m->y_min};
    static const char *const names[3] = {"max_reach", "x_max", "y_min"};
    for (int q = 0; q < 3; ++q) {
      ea_json_obj_begin(&j, names[q]);
      ea_json_num(&j, "value_m", ex[q]->value);
      ea_json_num(&j, "cable_angle_rad", ex[q]->alpha);
      ea_json_num(&j, "cable_length_m", ex[q]->cable_length);
      ea_json_vec(&j, "tip_m", (double[]){ex[q]->x, ex[q]->y}, 2);
      ea_json_str(&j, "bound", ea_ws_bound_name(ex[q]->bound));
      if (ex[q]->bound2) ea_json_str(&j, "bound2", ea_ws_bound_name(ex[q]->bound2));
      ea_json_bool(&j, "at_range_end", ex[q]->at_end != EA_WS_NONE);
      ea_json_obj_end(&j);
    }
    ea_json_arr_begin(&j, "region_bounds");
    for (int k = EA_WS_OUTER; k < EA_WS_ALPHA_MIN; ++k)
      if (m->bounds & (1u << k)) ea_json_str(&j, NULL, ea_ws_bound_name((ea_ws_bound_t)k));
    ea_json_arr_end(&j);
    ea_json_arr_begin(&j, "outer");
    for (int k = 0; k < n; ++k)
      ea__json_point(&j, NULL, &o[k]);
    ea_json_arr_end(&j);
    ea_json_arr_begin(&j, "inner");
    for (int k = 0; k < n; ++k)
      ea__json_point(&j, NULL, &in[k]);
    ea_json_arr_end(&j);
    ea_json_obj_end(&j);
  }
  ea_json_arr_end(&j);
  ea_json_obj_end(&j);
  ea_json_end(&j);
}

static void ea__ws_text(const ea__ws_run_t *w) {
  printf("region: cable angle %g to %g deg, inner cable %.4g m, %s\n", w->amin, w->amax, w->inner,
         w->no_limits ? "no actuator limits (--no-limits)" : "within the arm's limits");
  printf("%-7s %-14s %-14s %-14s %-14s\n", "gamma", "area_m2", "max_reach_m", "x_max_m", "y_min_m");
  for (int g = 0; g < w->ng; ++g)
    printf("%-7.4g %-14.10f %-14.10f %-14.10f %-14.10f\n", w->gam[g], w->met[g].area,
           w->met[g].reach.value, w->met[g].x_max.value, w->met[g].y_min.value);
  for (int g = 0; g < w->ng; ++g) {
    char w1[300], w2[300], w3[300];
    ea__ws_where(&w->met[g].reach, w1, sizeof w1);
    ea__ws_where(&w->met[g].x_max, w2, sizeof w2);
    ea__ws_where(&w->met[g].y_min, w3, sizeof w3);
    printf("gamma %g: max_reach at %s\n          x_max at %s\n          y_min at %s\n", w->gam[g],
           w1, w2, w3);
  }
}

/* Fig. 3 (statics_figure.c). 0 or the exit code. */
static int ea__ws_figure(const char *cmd, ea__ws_run_t *w) {
  ea_error_t fe = {0};
  if (ea_workspace_figure(&w->arm, w->sh, w->gam, w->ng, w->outer, w->n, w->inner, !w->no_limits,
                          w->c.figure, &fe)) {
    fprintf(stderr, "elasticarm %s: figure: %s\n", cmd, fe.msg);
    return EA_EXIT_FAIL;
  }
  return 0;
}

int ea__cli_workspace(int argc, char **argv) {
  const char *cmd = "workspace";
  if (ea__help_requested(argc, argv)) {
    printf("usage: elasticarm workspace [--payload-factors LIST | --payload-kg LIST] [options]\n"
           "Outer edge (T = 0, eq. 16) and inner edge (shortest cable) for each payload (Fig. "
           "3),\n"
           "and the region's metrics (docs/statics.md): area, farthest reach from the shoulder,\n"
           "largest x and lowest y of the tip, each to 1e-9, with the boundary that sets it.\n"
           "  --payload-factors L   payload factors G, m_p = G (m_h + rho L) (eq. 17): a list\n"
           "                        a,b,c or a range start:step:stop (default 0,0.1,0.25,0.5);\n"
           "                        --payload-factor is the same option (one value or a list)\n"
           "  --payload-kg L        the payloads as masses [kg] instead (a list or a range)\n"
           "  --alpha-min-deg A     start of the cable-angle range (default -60)\n"
           "  --alpha-max-deg A     end of the cable-angle range (default 10)\n"
           "  --points N            cable angles per edge, and the region's samples (default 71)\n"
           "  --inner-length M      inner edge cable length (default: arm's minimum)\n"
           "  --no-limits           the region without the arm's limits (shoulder angle,\n"
           "                        shoulder torque, tension, cable length): paper Fig. 3\n"
           "  --csv FILE            tidy CSV of every edge point ('-' = stdout)\n"
           "  --arm FILE            arm parameters (default: see elasticarm --help)\n"
           "  --json                JSON on stdout\n"
           "  --figure OUT          draw a figure (.svg, .png or .pdf)\n"
           "exit: 0 ok; 1 an edge point or a metric did not solve; 2 bad options, or an\n"
           "empty or ill-defined region (inner cable beyond the outer edge, cable angles\n"
           "where the outer edge does not bound the region)\n");
    return EA_EXIT_OK;
  }
  ea__ws_run_t w;
  memset(&w, 0, sizeof w);
  int rc = ea__ws_parse(cmd, argc, argv, &w);
  if (!rc) rc = ea__ws_compute(cmd, &w);
  if (!rc && w.c.csv) {
    struct ea__ws_csv ctx = {w.gam, w.outer, w.inn, w.n};
    rc = ea__write_points_csv(cmd, w.c.csv, "payload_factor,edge,", 2 * w.n * w.ng, ea__ws_point,
                              ea__ws_prefix, &ctx);
  }
  if (!rc) {
    if (w.c.json)
      ea__ws_json(&w);
    else if (!w.c.csv || strcmp(w.c.csv, "-"))
      ea__ws_text(&w);
    if (w.c.figure) rc = ea__ws_figure(cmd, &w);
    if (w.failures && !rc) {
      fprintf(stderr, "elasticarm %s: %d payload(s) had edge points without a solution\n", cmd,
              w.failures);
      rc = EA_EXIT_FAIL;
    }
  }
  ea_shooter_free(w.sh);
  free(w.alpha);
  free(w.outer);
  free(w.inn);
  free(w.met);
  free(w.gam);
  free(w.kg);
  return rc;
}

/* ------------------------------------------------------------------------ */
/* torque-map                                                                */
/* ------------------------------------------------------------------------ */

int ea__cli_torque_map(int argc, char **argv) {
  const char *cmd = "torque-map";
  if (ea__help_requested(argc, argv)) {
    printf("usage: elasticarm torque-map [options]\n"
           "Shoulder torque EI kappa0 and tension T over a (L_c, alpha) grid; cells outside\n"
           "the workspace or beyond a limit are marked (admissible = 0, with the reason).\n"
           "  --cable-lengths L      list or start:step:stop [m] (default 0.254:0.01:0.834)\n"
           "  --cable-angles-deg L   list or start:step:stop [deg] (default -60:5:10)\n"
           "  --csv FILE             tidy CSV ('-' = stdout, the default without --json)\n%s",
           ea__common_help);
    return EA_EXIT_OK;
  }
  ea__common_t c = {0};
  double *Ls = NULL, *As = NULL;
  int nL = 0, nA = 0, rc = 0, rc_usage = EA_EXIT_USAGE; /* (or EA_EXIT_FAIL: out of memory) */
  static const ea__cli_opt_t opts[] = {
      EA__COMMON_OPTS, {"cable-lengths", 1, 0}, {"cable-angles-deg", 1, 0}, {NULL, 0, 0}};
  ea__cli_args_t g;
  ea__cli_args_init(&g, cmd, argc, argv, opts);
  int gr;
  while ((gr = ea__cli_args_next(&g)) > 0) {
    const char *a = g.opt, *v = g.arg;
    if (!a) {
      ea__cli_usage_error(cmd, "unexpected argument '%s'", v);
      goto usage;
    }
    int r = ea__common_opt(cmd, a, v, &c);
    if (r < 0) goto usage;
    if (r) continue;
    int bad;
    if (!strcmp(a, "--cable-lengths")) {
      free(Ls);
      bad = ea__cli_list(cmd, a, v, &Ls, &nL);
      for (int k = 0; !bad && k < nL; ++k)
        if (!(Ls[k] > 0)) bad = ea__cli_usage_error(cmd, "%s: %g is not > 0", a, Ls[k]);
    } else if (!strcmp(a, "--cable-angles-deg")) {
      free(As);
      bad = ea__cli_list(cmd, a, v, &As, &nA);
      for (int k = 0; !bad && k < nA; ++k)
        if (!(fabs(As[k]) <= 180))
          bad = ea__cli_usage_error(cmd, "%s: %g is not in [-180, 180]", a, As[k]);
    } else
      bad = ea__cli_usage_error(cmd, "unknown option '%s'", a);
    if (bad) {
      rc_usage = bad;
      goto usage;
    }
  }
  if (gr < 0) goto usage;
  if (!Ls && (rc_usage = ea__cli_list(cmd, "--cable-lengths", "0.254:0.01:0.834", &Ls, &nL)))
    goto usage;
  if (!As && (rc_usage = ea__cli_list(cmd, "--cable-angles-deg", "-60:5:10", &As, &nA))) goto usage;
  rc_usage = EA_EXIT_USAGE;
  if ((size_t)nL * (size_t)nA > 4000000u) {
    ea__cli_usage_error(cmd, "grid of %d x %d cells is too large", nL, nA);
    goto usage;
  }
  for (int k = 0; k < nA; ++k)
    As[k] *= EA__DEG;
  ea_arm_t arm;
  if ((rc = ea__cli_load_arm(cmd, c.arm_file, &arm))) goto done;
  ea_shooter_t *sh = NULL;
  if ((rc = ea__make_shooter(cmd, &arm, ea__cli_tip_mass(&arm, &c.payload), &sh))) goto done;
  ea_config_point_t *cells = calloc((size_t)nL * nA, sizeof *cells);
  if (!cells) {
    ea_shooter_free(sh);
    rc = EA_EXIT_FAIL;
    goto done;
  }
  ea_torque_map(sh, Ls, nL, As, nA, &arm.act, cells);
  int inside = 0;
  double tmin = INFINITY, tmax = -INFINITY, Tmin = INFINITY, Tmax = -INFINITY;
  for (size_t k = 0; k < (size_t)nL * nA; ++k)
    if (cells[k].admissible) {
      ++inside;
      tmin = fmin(tmin, cells[k].shoulder_torque);
      tmax = fmax(tmax, cells[k].shoulder_torque);
      Tmin = fmin(Tmin, cells[k].tension);
      Tmax = fmax(Tmax, cells[k].tension);
    }
  const char *csv = c.csv ? c.csv : (c.json ? NULL : "-");
  if (csv) rc = ea__write_points_csv(cmd, csv, "", nL * nA, ea__point_array, NULL, cells);
  if (c.json && !rc) {
    ea_json_t j;
    ea_json_init(&j, stdout, 1);
    ea_json_obj_begin(&j, NULL);
    ea_json_num(&j, "tip_mass_kg", ea_shooter_load(sh)->tip_mass);
    ea_json_vec(&j, "cable_length_m", Ls, nL);
    ea_json_vec(&j, "cable_angle_rad", As, nA);
    ea_json_int(&j, "cells_admissible", inside);
    ea_json_vec(&j, "shoulder_torque_range_Nm", (double[]){tmin, tmax}, 2);
    ea_json_vec(&j, "tension_range_N", (double[]){Tmin, Tmax}, 2);
    ea_json_arr_begin(&j, "cells");
    for (size_t k = 0; k < (size_t)nL * nA; ++k)
      ea__json_point(&j, NULL, &cells[k]);
    ea_json_arr_end(&j);
    ea_json_obj_end(&j);
    ea_json_end(&j);
  }
  if (c.figure && !rc) {
    ea_error_t fe = {0};
    if (ea_torque_map_figure(Ls, nL, As, nA, cells, &arm.act, ea_shooter_load(sh)->tip_mass,
                             c.figure, &fe)) {
      fprintf(stderr, "elasticarm torque-map: figure: %s\n", fe.msg);
      rc = EA_EXIT_FAIL;
    }
  }
  free(cells);
  ea_shooter_free(sh);
done:
  free(Ls);
  free(As);
  return rc;
usage:
  free(Ls);
  free(As);
  return rc_usage;
}

/* ------------------------------------------------------------------------ */
/* path                                                                      */
/* ------------------------------------------------------------------------ */

/* Path CSV rows start with beta = k / steps. */
struct ea__path_csv {
  const ea_config_point_t *pts;
  long steps;
};
static const ea_config_point_t *ea__path_point(int k, const void *vctx) {
  return ((const struct ea__path_csv *)vctx)->pts + k;
}
static void ea__beta_prefix(FILE *fp, int k, const void *vctx) {
  fprintf(fp, "%.9g,", (double)k / (double)((const struct ea__path_csv *)vctx)->steps);
}

/* path's options into c, the ends and the step count; 0 or an exit code. */
static int ea__path_parse(int argc, char **argv, ea__common_t *c, double p0[2], double p1[2],
                          long *steps) {
  const char *cmd = "path";
  static const ea__cli_opt_t opts[] = {
      EA__COMMON_OPTS, {"from", 1, 0}, {"to", 1, 0}, {"steps", 1, 0}, {NULL, 0, 0}};
  ea__cli_args_t g;
  ea__cli_args_init(&g, cmd, argc, argv, opts);
  int gr;
  while ((gr = ea__cli_args_next(&g)) > 0) {
    const char *a = g.opt, *v = g.arg;
    if (!a) {
      ea__cli_usage_error(cmd, "unexpected argument '%s'", v);
      return EA_EXIT_USAGE;
    }
    int r = ea__common_opt(cmd, a, v, c);
    if (r < 0) return EA_EXIT_USAGE;
    if (r) continue;
    int bad;
    if (!strcmp(a, "--from"))
      bad = ea__cli_pair(cmd, a, v, p0);
    else if (!strcmp(a, "--to"))
      bad = ea__cli_pair(cmd, a, v, p1);
    else if (!strcmp(a, "--steps"))
      bad = ea__cli_int(cmd, a, v, 1, 100000, steps);
    else
      bad = ea__cli_usage_error(cmd, "unknown option '%s'", a);
    if (bad) return bad;
  }
  if (gr < 0) return EA_EXIT_USAGE;
  return 0;
}

static void ea__path_json(const ea_config_point_t *pts, int n, long steps, const double p0[2],
                          const double p1[2], double tip_mass, ea_status_t st, int nbad) {
  ea_json_t j;
  ea_json_init(&j, stdout, 1);
  ea_json_obj_begin(&j, NULL);
  ea_json_vec(&j, "from_m", p0, 2);
  ea_json_vec(&j, "to_m", p1, 2);
  ea_json_num(&j, "tip_mass_kg", tip_mass);
  ea_json_bool(&j, "admissible", st == EA_OK);
  ea_json_int(&j, "inadmissible_steps", nbad);
  ea_json_arr_begin(&j, "steps");
  for (int k = 0; k < n; ++k) {
    ea_json_obj_begin(&j, NULL);
    ea_json_num(&j, "beta", (double)k / (double)steps);
    ea_json_num(&j, "cable_length_m", pts[k].cable_length);
    ea_json_num(&j, "cable_angle_rad", pts[k].alpha);
    ea_json_vec(&j, "tip_m", (double[]){pts[k].x, pts[k].y}, 2);
    ea_json_num(&j, "tension_N", pts[k].tension);
    ea_json_num(&j, "theta0_rad", pts[k].theta0);
    ea_json_num(&j, "kappa0_per_m", pts[k].kappa0);
    ea_json_num(&j, "shoulder_torque_Nm", pts[k].shoulder_torque);
    ea_json_num(&j, "residual", pts[k].residual);
    if (pts[k].stable >= 0)
      ea_json_bool(&j, "stable", pts[k].stable);
    else
      ea_json_null(&j, "stable");
    ea_json_bool(&j, "admissible", pts[k].admissible);
    ea_json_str(&j, "reason", pts[k].reason);
    ea_json_obj_end(&j);
  }
  ea_json_arr_end(&j);
  ea_json_obj_end(&j);
  ea_json_end(&j);
}

static void ea__path_text(const ea_config_point_t *pts, int n, long steps, const double p0[2],
                          const double p1[2], double tip_mass, ea_status_t st) {
  printf("Straight path (%.4g, %.4g) -> (%.4g, %.4g) m, tip mass %.4g kg, %ld steps\n", p0[0],
         p0[1], p1[0], p1[1], tip_mass, steps);
  printf("%6s %10s %10s %10s %10s %11s %7s %s\n", "beta", "L_c [m]", "alpha[deg]", "T [N]",
         "th0 [deg]", "torque[Nm]", "stable", "admissible");
  for (int k = 0; k < n; ++k)
    printf("%6.3f %10.5f %10.3f %10.4f %10.3f %11.5f %7s %s%s\n", (double)k / (double)steps,
           pts[k].cable_length, pts[k].alpha / EA__DEG, pts[k].tension, pts[k].theta0 / EA__DEG,
           pts[k].shoulder_torque,
           pts[k].stable < 0 ? "-"
           : pts[k].stable   ? "yes"
                             : "NO",
           pts[k].admissible ? "yes" : "NO: ", pts[k].reason);
  printf("path %s\n", st == EA_OK ? "ADMISSIBLE" : "NOT admissible");
}

/* Fig. 4: the beams along the path, their cables, the line and the inadmissible steps;
 * 0 or EA_EXIT_FAIL (said on stderr). */
static int ea__path_figure(const char *path, ea_shooter_t *sh, const ea_arm_t *arm,
                           const ea_config_point_t *pts, int n, const double p0[2],
                           const double p1[2], ea_status_t st) {
  ea_plot_t *pl;
  ea_error_t fe = {0};
  if (ea_plot_open(&pl, path, 800, 650, &fe) == EA_OK) {
    ea_plot_data_begin(pl, "beams");
    for (int k = 0; k < n; ++k)
      if (pts[k].status == EA_OK || pts[k].status == EA_ERR_INADMISSIBLE)
        ea_plot_beam(pl, sh, (double[]){pts[k].alpha, pts[k].tension, pts[k].theta0, pts[k].kappa0},
                     61);
    ea_plot_data_end(pl);
    ea_plot_data_begin(pl, "cables");
    for (int k = 0; k < n; ++k) {
      ea_plot_data_row(pl, 2, (double[]){arm->x_c, arm->y_c});
      ea_plot_data_row(pl, 2, (double[]){pts[k].x, pts[k].y});
      ea_plot_data_row(pl, 1, (double[]){NAN});
    }
    ea_plot_data_end(pl);
    ea_plot_data_begin(pl, "line");
    ea_plot_data_row(pl, 2, p0);
    ea_plot_data_row(pl, 2, p1);
    ea_plot_data_end(pl);
    ea_plot_data_begin(pl, "bad");
    for (int k = 0; k < n; ++k)
      if (!pts[k].admissible) ea_plot_data_row(pl, 2, (double[]){pts[k].x, pts[k].y});
    ea_plot_data_row(pl, 2, (double[]){NAN, NAN});
    ea_plot_data_end(pl);
    ea_plot_cmd(pl,
                "set size ratio -1\nset xlabel 'x [m]'\nset ylabel 'y [m]'\nset title "
                "'Straight-line tip path (Fig. 4): %s'",
                st == EA_OK ? "admissible" : "NOT admissible");
    ea_plot_cmd(pl, "plot $beams w l lw 2 lc rgb '#1f4e9c' t 'beam', $cables w l dt 2 lc rgb "
                    "'#c0392b' t 'cable', $line w l lw 2 lc rgb 'black' t 'desired path', $bad "
                    "w p pt 2 ps 2 lc rgb 'red' t 'inadmissible'");
    fe.status = ea_plot_close(pl, &fe);
  }
  if (!fe.status) return 0;
  fprintf(stderr, "elasticarm path: figure: %s\n", fe.msg);
  return EA_EXIT_FAIL;
}

int ea__cli_path(int argc, char **argv) {
  const char *cmd = "path";
  if (ea__help_requested(argc, argv)) {
    printf("usage: elasticarm path [--from X,Y] [--to X,Y] [--steps N] [options]\n"
           "Admissibility of a straight tip path (Fig. 4, eqs. 18-20): per step L_c, alpha,\n"
           "T, theta0, shoulder torque, and whether every limit holds (with the reason).\n"
           "Default: the paper's line x = 0.3 beta + 0.3, y = -0.2, 6 steps.\n"
           "  --csv FILE            per-step table as CSV ('-' = stdout)\n%s",
           ea__common_help);
    return EA_EXIT_OK;
  }
  ea__common_t c = {0};
  double p0[2] = {0.3, -0.2}, p1[2] = {0.6, -0.2};
  long steps = 6;
  int rc = ea__path_parse(argc, argv, &c, p0, p1, &steps);
  if (rc) return rc;
  ea_arm_t arm;
  if ((rc = ea__cli_load_arm(cmd, c.arm_file, &arm))) return rc;
  ea_shooter_t *sh = NULL;
  if ((rc = ea__make_shooter(cmd, &arm, ea__cli_tip_mass(&arm, &c.payload), &sh))) return rc;
  const int n = (int)steps + 1;
  ea_config_point_t *pts = calloc((size_t)n, sizeof *pts);
  if (!pts) {
    ea_shooter_free(sh);
    return EA_EXIT_FAIL;
  }
  ea_fe_model_t *fem = NULL;
  if (!c.no_stability) {
    ea_error_t ferr = {0};
    ea_status_t fst = ea_fe_model_alloc(&arm, NULL, &fem, &ferr);
    if (fst) {
      free(pts);
      ea_shooter_free(sh);
      return ea__cli_fail(cmd, fst, &ferr);
    }
  }
  ea_status_t st = ea_path_check_line_fe(sh, fem, p0, p1, (int)steps, &arm.act, pts);
  ea_fe_model_free(fem);
  int nbad = 0;
  for (int k = 0; k < n; ++k)
    nbad += !pts[k].admissible;
  if (c.csv) {
    struct ea__path_csv ctx = {pts, steps};
    rc = ea__write_points_csv(cmd, c.csv, "beta,", n, ea__path_point, ea__beta_prefix, &ctx);
  }
  const double tip_mass = ea_shooter_load(sh)->tip_mass;
  if (c.json)
    ea__path_json(pts, n, steps, p0, p1, tip_mass, st, nbad);
  else if (!c.csv || strcmp(c.csv, "-"))
    ea__path_text(pts, n, steps, p0, p1, tip_mass, st);
  if (c.figure && ea__path_figure(c.figure, sh, &arm, pts, n, p0, p1, st)) rc = EA_EXIT_FAIL;
  free(pts);
  ea_shooter_free(sh);
  if (rc) return rc;
  return st == EA_OK ? EA_EXIT_OK : EA_EXIT_FAIL;
}
