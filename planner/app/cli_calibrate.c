/* CLI: calibrate -- fit an arm file's physical parameters to measurement records
 * (docs/calibration.md): the calibrated arm file, a JSON report, figures. */
#include "cli_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const char *const ea__calib_units[EA_CALIB_NP] = {"N m^2", "kg/m", "kg",     "m",
                                                         "m",     "N",    "kg m^2", "kg"};

static void ea__calib_help(void) {
  printf("usage: elasticarm calibrate RECORD... --arm PRIOR.yaml -o ARM.yaml [options]\n"
         "Fits the arm file's physical parameters (EI, rho, hand mass, cable root, EA_c, I_L and\n"
         "the modal damping ratios) to measurement records (docs/calibration.md): static records\n"
         "against the elastica statics, ring-downs by damped sinusoids and the FE frequencies\n"
         "(eq. 24). Trust-region nonlinear least squares; parameters the records cannot tell\n"
         "apart are held at the prior and named in words. Writes the calibrated arm file (each\n"
         "fitted value with its standard error and records in a comment) and a JSON report;\n"
         "a fit that does not converge writes nothing.\n\n"
         "  --arm FILE            the prior arm (default: see elasticarm --help)\n"
         "  -o, --output FILE     the calibrated arm file (required)\n"
         "  --report FILE         the JSON report (default: the output with .json)\n"
         "  --fix LIST            hold these at the prior: EI, rho, m_hand, x_c, y_c, EA_c, I_L,\n"
         "                        payload\n"
         "                        (or their arm-file keys, e.g. beam.EI_Nm2), comma separated\n"
         "  --payload-unknown RECORD  the record's payload is unknown (as its header\n"
         "                        '# payload_kg: unknown'): the fit estimates it, one payload\n"
         "                        shared by every record so marked (repeatable)\n"
         "  --payload-start KG    the unknown payload's starting value (default 0)\n"
         "  --fix-damping         keep the prior's damping ratios\n"
         "  --damping-mean        mode 1's ratio: the ring-downs' weighted mean (modal damping)\n"
         "                        instead of their strain-rate damping at the records' start\n"
         "  --modes K             FE modes matched to the ring-downs, 1..%d (default 3)\n"
         "  --ident-se S          a parameter combination whose standard error exceeds S\n"
         "                        (relative; cable root: in beam lengths) is not identifiable\n"
         "                        (default 0.5)\n"
         "  --figure OUT          measured against model: shoulder angle and torque (and\n"
         "                        tension) against cable length per cable angle, frequencies\n"
         "                        against cable length (.svg, .png or .pdf)\n"
         "  --ringdown-figure OUT each ring-down with its fitted curve\n"
         "  --quiet               no table on stdout\n\n"
         "exit: 0 calibrated; 1 the fit did not converge (nothing written) or an output could\n"
         "      not be written; 2 usage error or a bad record (file:line:column)\n",
         EA_CALIB_MAX_MODES);
}

/* "--fix EI,rho" into a mask. */
static int ea__calib_fix(const char *cmd, const char *text, unsigned *mask) {
  char buf[512];
  snprintf(buf, sizeof buf, "%s", text);
  for (char *tok = strtok(buf, ","); tok; tok = strtok(NULL, ",")) {
    while (*tok == ' ')
      ++tok;
    int k;
    if (ea_calib_param_parse(tok, &k))
      return ea__cli_usage_error(cmd,
                                 "--fix: '%s' is not a parameter (EI, rho, m_hand, x_c, y_c, "
                                 "EA_c, I_L, payload or their arm-file keys)",
                                 tok);
    *mask |= 1u << k;
  }
  return 0;
}

/* Write the arm file text into memory, check that the project's loader reads it back to the
 * same arm, then write it atomically. */
static int ea__calib_write_arm(const char *cmd, const char *path, const ea_calib_result_t *res,
                               const ea_calib_record_t *recs, const char *prior_path) {
  char *text = NULL;
  size_t len = 0;
  FILE *mf = open_memstream(&text, &len);
  if (!mf) return ea__cli_oom(cmd, "arm file text");
  ea_error_t err = {0};
  ea_status_t st = ea_calib_write_arm(mf, res, recs, prior_path, &err);
  fclose(mf);
  if (st) {
    free(text);
    return ea__cli_fail(cmd, st, &err);
  }
  ea_arm_t back;
  st = ea_arm_load_string(path, text, len, &back, &err);
  if (st || !ea_arm_equal(&back, &res->arm)) {
    fprintf(stderr, "elasticarm %s: error: the calibrated arm file does not load back%s%s\n", cmd,
            st ? ": " : " to the same values", st ? err.msg : "");
    free(text);
    return EA_EXIT_FAIL;
  }
  ea_afile_t f;
  if ((st = ea_afile_open(&f, path, &err))) {
    free(text);
    return ea__cli_fail(cmd, st, &err);
  }
  fwrite(text, 1, len, f.fp);
  free(text);
  if ((st = ea_afile_commit(&f, &err))) return ea__cli_fail(cmd, st, &err);
  return 0;
}

static int ea__calib_write_report(const char *cmd, const char *path, const ea_calib_result_t *res,
                                  const ea_calib_record_t *recs, const char *prior_path) {
  ea_afile_t f;
  ea_error_t err = {0};
  ea_status_t st = ea_afile_open(&f, path, &err);
  if (st) return ea__cli_fail(cmd, st, &err);
  if ((st = ea_calib_write_report(f.fp, res, recs, prior_path, &err))) {
    ea_afile_abort(&f);
    return ea__cli_fail(cmd, st, &err);
  }
  if ((st = ea_afile_commit(&f, &err))) return ea__cli_fail(cmd, st, &err);
  return 0;
}

static void ea__calib_table(const ea_calib_result_t *res) {
  printf("%-7s %-18s %14s %12s %14s  %s\n", "param", "key", "estimate", "std error", "prior",
         "state");
  for (int k = 0; k < EA_CALIB_NP; ++k) {
    if (res->state[k] == EA_CALIB_UNUSED) continue; /* the payload, when none is unknown */
    const char *state = res->state[k] == EA_CALIB_FITTED  ? "fitted"
                        : res->state[k] == EA_CALIB_FIXED ? "held (--fix)"
                                                          : "held: not identifiable";
    char se[32] = "-";
    if (res->state[k] == EA_CALIB_FITTED) snprintf(se, sizeof se, "%.3g", res->se[k]);
    char pr[32] = "-"; /* the payload has no prior in the arm */
    if (ea_calib_param_is_arm(k))
      snprintf(pr, sizeof pr, "%.6g", ea_calib_param_get(&res->prior, k));
    printf("%-7s %-18s %14.6g %12s %14s  %s [%s]\n", ea_calib_param_name(k), ea_calib_param_key(k),
           res->value[k], se, pr, state, ea__calib_units[k]);
  }
  for (int k = 0; k < res->n_zeta; ++k)
    printf("zeta_%d  %-18s %14.4g %12.2g %14s  fitted, %d ring-down%s\n", k + 1,
           "damping.modal_ratios", res->zeta[k], res->zeta_se[k], "", res->zeta_count[k],
           res->zeta_count[k] == 1 ? "" : "s");
  printf("chi^2 %.4g for %d residuals, %d degrees of freedom (chi^2/dof %.3g); %d iterations, "
         "%.2f s\n",
         res->chi2, res->n_residuals, res->dof, res->dof > 0 ? res->chi2 / res->dof : NAN,
         res->iterations, res->time_s);
  for (int n = 0; n < res->n_notes; ++n)
    printf("not identifiable: %s\n", res->notes[n]);
}

int ea__cli_calibrate(int argc, char **argv) {
  const char *cmd = "calibrate";
  /* calibrate --plan-experiment SPEC [options]: the experiment (calibrate-experiment) */
  for (int i = 1; i < argc; ++i) {
    if (strncmp(argv[i], "--plan-experiment", 17) || (argv[i][17] && argv[i][17] != '=')) continue;
    char **av = calloc((size_t)argc + 1, sizeof *av);
    if (!av) return ea__cli_oom(cmd, "arguments");
    int n = 0;
    av[n++] = "calibrate-experiment";
    if (argv[i][17] == '=') av[n++] = argv[i] + 18;
    for (int j = 1; j < argc; ++j)
      if (j != i) av[n++] = argv[j];
    const int rc = ea__cli_calibrate_experiment(n, av);
    free(av);
    return rc;
  }
  const char *arm_file = NULL, *out = NULL, *report = NULL, *figure = NULL, *rfigure = NULL;
  int quiet = 0;
  ea_calib_settings_t set;
  ea_calib_settings_default(&set);
  const char **paths = calloc((size_t)argc + 1, sizeof *paths);
  const char **unknown = calloc((size_t)argc + 1, sizeof *unknown);
  if (!paths || !unknown) {
    free(paths);
    free(unknown);
    return ea__cli_oom(cmd, "arguments");
  }
  int npaths = 0, nunknown = 0;
  static const ea__cli_opt_t opts[] = {{"help", 0, 'h'},
                                       {"arm", 1, 0},
                                       {"output", 1, 'o'},
                                       {"report", 1, 0},
                                       {"fix", 1, 0},
                                       {"fix-damping", 0, 0},
                                       {"damping-mean", 0, 0},
                                       {"modes", 1, 0},
                                       {"ident-se", 1, 0},
                                       {"figure", 1, 0},
                                       {"ringdown-figure", 1, 0},
                                       {"quiet", 0, 0},
                                       {"payload-unknown", 1, 0},
                                       {"payload-start", 1, 0},
                                       {NULL, 0, 0}};
  ea__cli_args_t g;
  ea__cli_args_init(&g, cmd, argc, argv, opts);
  int r, rc = 0;
  while (!rc && (r = ea__cli_args_next(&g)) > 0) {
    const char *a = g.opt;
    if (!a) {
      paths[npaths++] = g.arg;
    } else if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
      ea__calib_help();
      free(paths);
      free(unknown);
      return EA_EXIT_OK;
    } else if (!strcmp(a, "--arm")) {
      arm_file = g.arg;
    } else if (!strcmp(a, "--output") || !strcmp(a, "-o")) {
      out = g.arg;
    } else if (!strcmp(a, "--report")) {
      report = g.arg;
    } else if (!strcmp(a, "--fix")) {
      rc = ea__calib_fix(cmd, g.arg, &set.fix_mask);
    } else if (!strcmp(a, "--fix-damping")) {
      set.fix_damping = 1;
    } else if (!strcmp(a, "--damping-mean")) {
      set.damping_at_start = 0;
    } else if (!strcmp(a, "--modes")) {
      long v;
      rc = ea__cli_int(cmd, a, g.arg, 1, EA_CALIB_MAX_MODES, &v);
      set.modes = (int)v;
    } else if (!strcmp(a, "--ident-se")) {
      rc = ea__cli_double(cmd, a, g.arg, 1e-9, 1e9, &set.ident_se);
    } else if (!strcmp(a, "--figure")) {
      figure = g.arg;
    } else if (!strcmp(a, "--ringdown-figure")) {
      rfigure = g.arg;
    } else if (!strcmp(a, "--quiet")) {
      quiet = 1;
    } else if (!strcmp(a, "--payload-unknown")) {
      unknown[nunknown++] = g.arg;
    } else if (!strcmp(a, "--payload-start")) {
      rc = ea__cli_double(cmd, a, g.arg, 0.0, 1e3, &set.payload_start);
    }
  }
  /* each --payload-unknown names a record given */
  for (int u = 0; !rc && u < nunknown; ++u) {
    int found = 0;
    for (int i = 0; i < npaths; ++i)
      found |= !strcmp(paths[i], unknown[u]);
    if (!found)
      rc = ea__cli_usage_error(cmd, "--payload-unknown '%s': not one of the records given",
                               unknown[u]);
  }
  if (rc || r < 0) {
    free(paths);
    free(unknown);
    return rc ? rc : EA_EXIT_USAGE;
  }
  if (!npaths || !out) {
    free(paths);
    free(unknown);
    return ea__cli_usage_error(cmd, "needs RECORD... and -o ARM.yaml");
  }
  char report_buf[1100];
  if (!report) {
    ea__replace_ext(out, ".json", report_buf, sizeof report_buf);
    if (!strcmp(report_buf, out)) snprintf(report_buf, sizeof report_buf, "%s.json", out);
    report = report_buf;
  }
  if (!strcmp(out, "-") || !strcmp(report, "-") || !strcmp(out, report)) {
    free(paths);
    free(unknown);
    return ea__cli_usage_error(cmd, "the arm file and the report need two file paths");
  }
  /* outputs and figures checked before the work */
  if ((rc = ea__cli_check_output(cmd, out)) || (rc = ea__cli_check_output(cmd, report)) ||
      (figure && (rc = ea__cli_check_figure(cmd, figure))) ||
      (rfigure && (rc = ea__cli_check_figure(cmd, rfigure)))) {
    free(paths);
    free(unknown);
    return rc;
  }
  ea_arm_t prior;
  if ((rc = ea__cli_load_arm(cmd, arm_file, &prior))) {
    free(paths);
    free(unknown);
    return rc;
  }
  const char *prior_path = arm_file ? arm_file : ea__cli_default_arm();
  ea_calib_record_t *recs = calloc((size_t)npaths, sizeof *recs);
  if (!recs) {
    free(paths);
    free(unknown);
    return ea__cli_oom(cmd, "records");
  }
  ea_error_t err = {0};
  ea_status_t st = EA_OK;
  int nread = 0;
  for (; nread < npaths; ++nread) {
    if ((st = ea_calib_record_read(paths[nread], &recs[nread], &err))) break;
    for (int u = 0; u < nunknown; ++u)
      if (!strcmp(paths[nread], unknown[u])) recs[nread].payload_unknown = 1;
  }
  ea_calib_result_t res;
  memset(&res, 0, sizeof res);
  if (st) {
    rc = ea__cli_fail(cmd, st, &err);
  } else {
    st = ea_calib_fit(&prior, recs, npaths, &set, &res, &err);
    if (st == EA_ERR_NOCONV) {
      fprintf(stderr, "elasticarm %s: error: %s; nothing written\n", cmd, err.msg);
      rc = EA_EXIT_FAIL;
    } else if (st) {
      rc = ea__cli_fail(cmd, st, &err);
    }
  }
  if (!rc) {
    if (!quiet) ea__calib_table(&res);
    rc = ea__calib_write_arm(cmd, out, &res, recs, prior_path);
    if (!rc) rc = ea__calib_write_report(cmd, report, &res, recs, prior_path);
    if (!rc && !quiet) printf("wrote %s and %s\n", out, report);
    if (!rc && figure) {
      if ((st = ea_calib_figure(&res, recs, npaths, figure, &err)))
        rc = ea__cli_fail(cmd, st, &err);
      else if (!quiet)
        printf("wrote %s\n", figure);
    }
    if (!rc && rfigure) {
      if ((st = ea_calib_ringdown_figure(&res, recs, npaths, rfigure, &err)))
        rc = ea__cli_fail(cmd, st, &err);
      else if (!quiet)
        printf("wrote %s\n", rfigure);
    }
  }
  ea_calib_result_free(&res);
  for (int i = 0; i < npaths; ++i)
    ea_calib_record_free(&recs[i]);
  free(recs);
  free(paths);
  free(unknown);
  return rc;
}
