/* CLI: calibrate-experiment -- the trajectory of an identification experiment
 * (docs/calibration.md, "The experiment"). */
#include "cli_impl.h"
#include "ea_experiment_plan.h"

#include <stdlib.h>
#include <string.h>

static const char *ea__exp_help =
    "usage: elasticarm calibrate-experiment SPEC.yaml -o EXP.csv [options]\n\n"
    "Plan the trajectory of an identification experiment (docs/calibration.md, \"The\n"
    "experiment\"): a hold at every configuration of the spec (cable lengths x angles)\n"
    "long enough for the ring-down of the move into it, joined by minimum-time moves of\n"
    "the planner; infeasible configurations are skipped with a note. Stream it with\n"
    "`elasticarm stream` while the controller logs its sensors. Every trajectory is\n"
    "checked with the streamer's own checks (limits between samples, continuity, rest at\n"
    "both ends) at --rate-hz before it is written.\n\n"
    "  -o, --output EXP.csv  the trajectory; with several payloads one file each,\n"
    "                        EXP-payload1.csv, EXP-payload2.csv, ... (a payload change\n"
    "                        needs a human between them)\n"
    "  --arm FILE            arm file when the spec names none (default: see\n"
    "                        elasticarm --help)\n"
    "  --rate-hz R           stream rate of the check (default 1000)\n"
    "  --json                summary as JSON on stdout\n"
    "Exit: 0 written; 1 nothing feasible, a check failed or a file not written;\n"
    "2 usage or input error.\n";

/* The output path of payload i of n: out itself, or out with -payload<i+1> before its
 * extension. */
static void ea__exp_path(const char *out, int i, int n, char *buf, size_t len) {
  if (n == 1) {
    snprintf(buf, len, "%s", out);
    return;
  }
  const char *slash = strrchr(out, '/'), *dot = strrchr(out, '.');
  if (!dot || (slash && dot < slash)) dot = out + strlen(out);
  snprintf(buf, len, "%.*s-payload%d%s", (int)(dot - out), out, i + 1, dot);
}

typedef struct {
  char path[1100];
  ea_experiment_plan_info_t info;
  int setpoints;
  ea_status_t st;
  char msg[1024];
} ea__exp_out_t;

static void ea__exp_json(const ea_experiment_spec_t *s, const ea_experiment_config_t *const *cfg,
                         const ea__exp_out_t *o, double rate, double total) {
  ea_json_t j;
  ea_json_init(&j, stdout, 1);
  ea_json_obj_begin(&j, NULL);
  ea_json_str(&j, "spec", s->file);
  ea_json_str(&j, "arm_file", s->arm_file);
  ea_json_num(&j, "rate_hz", rate);
  ea_json_num(&j, "duration_s", total);
  ea_json_arr_begin(&j, "trajectories");
  for (int p = 0; p < s->n_payload; ++p) {
    const ea_experiment_plan_info_t *in = &o[p].info;
    ea_json_obj_begin(&j, NULL);
    ea_json_str(&j, "status", ea_status_name(o[p].st));
    ea_json_str(&j, "message", o[p].msg);
    ea_json_str(&j, "file", o[p].path);
    ea_json_num(&j, "payload_kg", s->payload_kg[p]);
    ea_json_int(&j, "configurations", in->n_configs);
    ea_json_int(&j, "feasible", in->n_feasible);
    ea_json_int(&j, "holds", in->n_holds);
    ea_json_int(&j, "move_failures", in->n_move_failures);
    ea_json_num(&j, "hold_s", in->hold_s);
    ea_json_num(&j, "damping_ratio", in->damping_ratio);
    ea_json_num(&j, "f1_min_Hz", in->f1_min_hz);
    ea_json_num(&j, "f1_max_Hz", in->f1_max_hz);
    ea_json_num(&j, "move_time_s", in->move_time_s);
    ea_json_num(&j, "duration_s", in->duration_s);
    ea_json_int(&j, "rows", in->rows);
    ea_json_int(&j, "setpoints", o[p].setpoints);
    ea_json_num(&j, "wall_time_s", in->time_s);
    ea_json_arr_begin(&j, "holds_list");
    for (int h = 0; h < in->n_holds; ++h) {
      const ea_experiment_config_t *c = &cfg[p][in->holds[h].config];
      ea_json_obj_begin(&j, NULL);
      ea_json_num(&j, "t_start_s", in->holds[h].t_start);
      ea_json_num(&j, "t_end_s", in->holds[h].t_end);
      ea_json_num(&j, "cable_length_m", c->cable_length);
      ea_json_num(&j, "cable_angle_rad", c->cable_angle);
      ea_json_num(&j, "theta0_rad", c->p[EA_P_THETA0]);
      ea_json_num(&j, "tension_N", c->p[EA_P_TENSION]);
      ea_json_num(&j, "shoulder_torque_Nm", c->shoulder_torque);
      ea_json_num(&j, "f1_Hz", c->f1_hz);
      ea_json_obj_end(&j);
    }
    ea_json_arr_end(&j);
    ea_json_arr_begin(&j, "skipped");
    for (int k = 0; k < in->n_configs; ++k)
      if (cfg[p][k].note[0]) ea_json_str(&j, NULL, cfg[p][k].note);
    ea_json_arr_end(&j);
    ea_json_obj_end(&j);
  }
  ea_json_arr_end(&j);
  ea_json_obj_end(&j);
  ea_json_end(&j);
}

/* Plan payload p, check it as the streamer does, write it. */
static void ea__exp_one(const ea_experiment_spec_t *s, int p, double rate,
                        ea_experiment_config_t *cfg, ea__exp_out_t *o) {
  ea_traj_t tr = {0};
  ea_error_t err = {0};
  o->st = ea_experiment_plan(s, p, cfg, &tr, &o->info, &err);
  if (!o->st) {
    ea_stream_settings_t ss;
    ea_stream_settings_default(&ss);
    ea_setpoint_t *sp = NULL;
    o->st = ea_stream_resample(&tr, &s->arm, rate, ss.limit_tol, &sp, &o->setpoints, &err);
    free(sp);
    if (o->st) {
      char m[sizeof err.msg];
      snprintf(m, sizeof m, "%s", err.msg);
      ea_error_set(&err, o->st, "the streamer's check refused it: %s", m);
    }
  }
  if (!o->st) o->st = ea_traj_write(&tr, o->path, &err);
  if (o->st) snprintf(o->msg, sizeof o->msg, "%s", err.msg[0] ? err.msg : ea_strerror(o->st));
  ea_traj_free(&tr);
}

int ea__cli_calibrate_experiment(int argc, char **argv) {
  const char *cmd = "calibrate-experiment";
  const char *spec_path = NULL, *out = NULL, *arm_file = NULL;
  int json = 0;
  double rate = 1000.0;
  static const ea__cli_opt_t opts[] = {{"help", 0, 'h'},  {"output", 1, 'o'}, {"arm", 1, 0},
                                       {"rate-hz", 1, 0}, {"json", 0, 0},     {NULL, 0, 0}};
  ea__cli_args_t g;
  ea__cli_args_init(&g, cmd, argc, argv, opts);
  int r;
  while ((r = ea__cli_args_next(&g)) > 0) {
    const char *a = g.opt, *v = g.arg;
    if (!a) {
      if (spec_path) return ea__cli_usage_error(cmd, "one spec only ('%s' is extra)", v);
      spec_path = v;
    } else if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
      fputs(ea__exp_help, stdout);
      return EA_EXIT_OK;
    } else if (!strcmp(a, "--output") || !strcmp(a, "-o")) {
      out = v;
    } else if (!strcmp(a, "--arm")) {
      arm_file = v;
    } else if (!strcmp(a, "--rate-hz")) {
      if (ea__cli_double(cmd, a, v, 1, 100000, &rate)) return EA_EXIT_USAGE;
    } else if (!strcmp(a, "--json")) {
      json = 1;
    }
  }
  if (r < 0) return EA_EXIT_USAGE;
  if (!spec_path || !out) return ea__cli_usage_error(cmd, "needs SPEC.yaml and -o EXP.csv");
  ea_experiment_spec_t *s = malloc(sizeof *s);
  if (!s) return ea__cli_oom(cmd, "spec");
  ea_error_t err = {0};
  ea_status_t st =
      ea_experiment_spec_load(spec_path, arm_file ? arm_file : ea__cli_default_arm(), s, &err);
  if (st) {
    free(s);
    return ea__cli_fail(cmd, st, &err);
  }
  ea__exp_out_t *o = calloc((size_t)s->n_payload, sizeof *o);
  ea_experiment_config_t **cfg = calloc((size_t)s->n_payload, sizeof *cfg);
  int rc = (o && cfg) ? 0 : ea__cli_oom(cmd, "outputs");
  for (int p = 0; !rc && p < s->n_payload; ++p) {
    ea__exp_path(out, p, s->n_payload, o[p].path, sizeof o[p].path);
    if ((rc = ea__cli_check_output(cmd, o[p].path))) break;
    if (!(cfg[p] = calloc(EA_EXPERIMENT_MAX_CONFIGS, sizeof **cfg))) rc = ea__cli_oom(cmd, "cfg");
  }
  double total = 0.0;
  for (int p = 0; !rc && p < s->n_payload; ++p) {
    ea__exp_one(s, p, rate, cfg[p], &o[p]);
    if (!o[p].st) total += o[p].info.duration_s;
  }
  if (!rc && json) ea__exp_json(s, (const ea_experiment_config_t *const *)cfg, o, rate, total);
  for (int p = 0; !rc && p < s->n_payload; ++p) {
    const ea_experiment_plan_info_t *in = &o[p].info;
    if (!json) {
      printf("experiment %s, payload %g kg: %d of %d configurations feasible, %d held\n", spec_path,
             s->payload_kg[p], in->n_feasible, in->n_configs, in->n_holds);
      if (!o[p].st) {
        printf("  hold %.4g s each (f1 %.4g..%.4g Hz, damping ratio %.4g%s), moves %.4g s\n",
               in->hold_s, in->f1_min_hz, in->f1_max_hz, in->damping_ratio,
               s->arm.n_damping > 0 ? " from the arm file" : " assumed", in->move_time_s);
        printf("  duration %.4f s, %d rows -> %s; streams at %g Hz: %d setpoints, every check "
               "passed\n",
               in->duration_s, in->rows, o[p].path, rate, o[p].setpoints);
      }
      for (int k = 0; k < in->n_configs; ++k)
        if (cfg[p][k].note[0]) printf("  skipped: %s\n", cfg[p][k].note);
    }
    if (o[p].st) {
      fprintf(stderr, "elasticarm %s: payload %g kg: %s\n", cmd, s->payload_kg[p], o[p].msg);
      rc = (o[p].st == EA_ERR_IO) ? EA_EXIT_USAGE : EA_EXIT_FAIL;
    }
  }
  if (!rc && !json && s->n_payload > 1)
    printf("total %.4f s over %d trajectories (payload changes not included)\n", total,
           s->n_payload);
  for (int p = 0; cfg && p < s->n_payload; ++p)
    free(cfg[p]);
  free(cfg);
  free(o);
  free(s);
  return rc;
}
