/* The calibrated arm file (data/elasticarm.yaml's structure, ea_arm_load reads it back) and
 * the JSON report of a calibration. Both go to a stream the caller opened (the CLI writes
 * them atomically). */
#include "ea_arm_file.h"
#include "ea_calib.h"
#include "ea_util.h"

#include <math.h>
#include <string.h>

static const char *ea__units[EA_CALIB_NP] = {"N m^2", "kg/m", "kg", "m", "m", "N", "kg m^2", "kg"};

static void ea__c(FILE *fp, const char *const comment[EA_CALIB_NP], int k) {
  if (comment && comment[k] && comment[k][0]) fprintf(fp, "  # %s", comment[k]);
  fputc('\n', fp);
}

ea_status_t ea_arm_write_yaml(FILE *fp, const ea_arm_t *arm, const char *header,
                              const char *const comment[EA_CALIB_NP], const char *damping_comment,
                              ea_error_t *err) {
  if (!fp || !arm) return ea_error_set(err, EA_ERR_ARG, "ea_arm_write_yaml: NULL argument");
  ea_status_t st = ea_arm_validate(arm, err);
  if (st) return st;
  if (header && header[0]) {
    /* every line of the header as a comment */
    const char *s = header;
    while (*s) {
      const char *nl = strchr(s, '\n');
      const int n = nl ? (int)(nl - s) : (int)strlen(s);
      fprintf(fp, "# %.*s\n", n, s);
      s += n + (nl ? 1 : 0);
    }
  }
  const ea_actuators_t *a = &arm->act;
  fprintf(fp, "beam:\n");
  fprintf(fp, "  rho_kg_per_m: %.17g", arm->rho);
  ea__c(fp, comment, EA_CALIB_P_RHO);
  fprintf(fp, "  length_m: %.17g\n", arm->length);
  fprintf(fp, "  EI_Nm2: %.17g", arm->EI);
  ea__c(fp, comment, EA_CALIB_P_EI);
  fprintf(fp, "  EA_N: %.17g\n", arm->EA);
  fprintf(fp, "  GA_N: %.17g\n", arm->GA_s);
  fprintf(fp, "  Izz_kg_m: %.17g\n", arm->I_zz);
  fprintf(fp, "hand:\n");
  fprintf(fp, "  mass_kg: %.17g", arm->m_hand);
  ea__c(fp, comment, EA_CALIB_P_M_HAND);
  fprintf(fp, "  Izz_kg_m2: %.17g", arm->I_hand);
  ea__c(fp, comment, EA_CALIB_P_I_HAND);
  fprintf(fp, "cable:\n");
  fprintf(fp, "  root_x_m: %.17g", arm->x_c);
  ea__c(fp, comment, EA_CALIB_P_X_C);
  fprintf(fp, "  root_y_m: %.17g", arm->y_c);
  ea__c(fp, comment, EA_CALIB_P_Y_C);
  fprintf(fp, "  EA_N: %.17g", arm->EA_cable);
  ea__c(fp, comment, EA_CALIB_P_EA_CABLE);
  fprintf(fp, "gravity_m_per_s2: %.17g\n", arm->g);
  fprintf(fp, "actuators:\n  spool:\n");
  fprintf(fp, "    radius_m: %.17g\n    gear_ratio: %.17g\n    zero_length_m: %.17g\n",
          a->spool_radius, a->spool_gear_ratio, a->spool_zero_length);
  fprintf(fp, "    cable_length_min_m: %.17g\n    cable_length_max_m: %.17g\n", a->cable_length_min,
          a->cable_length_max);
  fprintf(fp, "    speed_max_m_per_s: %.17g\n    accel_max_m_per_s2: %.17g\n", a->cable_speed_max,
          a->cable_accel_max);
  fprintf(fp, "  tension:\n    min_N: %.17g\n    max_N: %.17g\n", a->tension_min, a->tension_max);
  fprintf(fp, "  shoulder:\n    torque_max_Nm: %.17g\n    speed_max_rad_per_s: %.17g\n",
          a->shoulder_torque_max, a->shoulder_speed_max);
  fprintf(fp,
          "    accel_max_rad_per_s2: %.17g\n    angle_min_rad: %.17g\n    angle_max_rad: %.17g\n",
          a->shoulder_accel_max, a->shoulder_angle_min, a->shoulder_angle_max);
  fprintf(fp, "  base:\n    speed_max_rad_per_s: %.17g\n    accel_max_rad_per_s2: %.17g\n",
          a->base_speed_max, a->base_accel_max);
  fprintf(fp, "    angle_min_rad: %.17g\n    angle_max_rad: %.17g\n", a->base_angle_min,
          a->base_angle_max);
  if (arm->n_damping > 0) {
    if (damping_comment && damping_comment[0]) {
      const char *s = damping_comment;
      while (*s) {
        const char *nl = strchr(s, '\n');
        const int n = nl ? (int)(nl - s) : (int)strlen(s);
        fprintf(fp, "# %.*s\n", n, s);
        s += n + (nl ? 1 : 0);
      }
    }
    fprintf(fp, "damping:\n  modal_ratios: [");
    for (int i = 0; i < arm->n_damping; ++i)
      fprintf(fp, "%s%.17g", i ? ", " : "", arm->damping_ratio[i]);
    fprintf(fp, "]\n");
  }
  if (ferror(fp)) return ea_error_set(err, EA_ERR_IO, "writing the arm file failed");
  return EA_OK;
}

/* "a.csv, b.csv" of the records in mask (at most len bytes). */
static void ea__rec_list(const ea_calib_record_t *recs, int nrec, int mask, char *buf, size_t len) {
  size_t o = 0;
  buf[0] = '\0';
  for (int r = 0; r < nrec && r < 32 && o < len; ++r)
    if (mask & (1 << r))
      o += (size_t)snprintf(buf + o, len - o, "%s%s", o ? ", " : "", recs[r].path);
}

ea_status_t ea_calib_write_arm(FILE *fp, const ea_calib_result_t *res,
                               const ea_calib_record_t *recs, const char *prior_path,
                               ea_error_t *err) {
  if (!fp || !res || !recs) return ea_error_set(err, EA_ERR_ARG, "ea_calib_write_arm: NULL");
  char cm[EA_CALIB_NP][700];
  const char *cp[EA_CALIB_NP];
  int scale_held = res->state[EA_CALIB_P_EI] == EA_CALIB_UNIDENTIFIABLE ||
                   res->state[EA_CALIB_P_EI] == EA_CALIB_FIXED;
  for (int k = 0; k < EA_CALIB_NP; ++k) {
    cp[k] = cm[k];
    cm[k][0] = '\0';
    if (!ea_calib_param_is_arm(k)) continue; /* the payload: the records', not the arm's */
    char from[400];
    ea__rec_list(recs, res->nrec, res->contributes[k], from, sizeof from);
    switch (res->state[k]) {
    case EA_CALIB_FITTED:
      snprintf(cm[k], sizeof cm[k], "calibrated: %.6g +- %.2g %s (1 standard error), from %s%s",
               res->value[k], res->se[k], ea__units[k], from[0] ? from : "the records",
               scale_held && (k == EA_CALIB_P_RHO || k == EA_CALIB_P_M_HAND)
                   ? "; measured relative to EI, which is held"
                   : "");
      break;
    case EA_CALIB_FIXED:
      snprintf(cm[k], sizeof cm[k], "the prior's value, held (--fix)");
      break;
    case EA_CALIB_UNIDENTIFIABLE:
      snprintf(cm[k], sizeof cm[k],
               "the prior's value, held: the records cannot identify it (see the report)");
      break;
    case EA_CALIB_UNUSED:
      break;
    }
  }
  char header[8192];
  size_t o = 0;
  o += (size_t)snprintf(header + o, sizeof header - o,
                        "Calibrated by elasticarm calibrate %s from %d record%s (prior: %s).\n"
                        "Values without a comment are the prior's. chi^2 = %.4g for %d "
                        "residuals, %d degrees of freedom.",
                        EA_VERSION_STRING, res->nrec, res->nrec == 1 ? "" : "s",
                        prior_path && prior_path[0] ? prior_path : "built-in arm", res->chi2,
                        res->n_residuals, res->dof);
  if (res->state[EA_CALIB_P_PAYLOAD] == EA_CALIB_FITTED && o < sizeof header)
    o += (size_t)snprintf(header + o, sizeof header - o,
                          "\nThe records' unknown payload, %.6g +- %.2g kg, is not a parameter "
                          "of the arm: it is in the report, not in this file.",
                          res->value[EA_CALIB_P_PAYLOAD], res->se[EA_CALIB_P_PAYLOAD]);
  for (int n = 0; n < res->n_notes && o < sizeof header; ++n)
    o += (size_t)snprintf(header + o, sizeof header - o, "\nnot identifiable: %s", res->notes[n]);
  char dc[600] = "";
  if (res->n_zeta > 0) {
    size_t q = (size_t)snprintf(dc, sizeof dc, "damping: calibrated from the ring-downs:");
    for (int k = 0; k < res->n_zeta && q < sizeof dc; ++k)
      q += (size_t)snprintf(dc + q, sizeof dc - q, " mode %d %.4g +- %.2g (%d ring-down%s);", k + 1,
                            res->zeta[k], res->zeta_se[k], res->zeta_count[k],
                            res->zeta_count[k] == 1 ? "" : "s");
    if (res->arm.n_damping > res->n_zeta && q < sizeof dc)
      snprintf(dc + q, sizeof dc - q, " modes %d..%d: the prior's", res->n_zeta + 1,
               res->arm.n_damping);
  }
  return ea_arm_write_yaml(fp, &res->arm, header, cp, dc, err);
}

ea_status_t ea_calib_write_report(FILE *fp, const ea_calib_result_t *res,
                                  const ea_calib_record_t *recs, const char *prior_path,
                                  ea_error_t *err) {
  if (!fp || !res || !recs) return ea_error_set(err, EA_ERR_ARG, "ea_calib_write_report: NULL");
  static const char *const states[] = {"fitted", "fixed", "not_identifiable", "unused"};
  ea_json_t j;
  ea_json_init(&j, fp, 1);
  ea_json_obj_begin(&j, NULL);
  ea_json_str(&j, "elasticarm_calibration", "1");
  ea_json_str(&j, "version", EA_VERSION_STRING);
  ea_json_str(&j, "prior_arm_file", prior_path ? prior_path : "");
  ea_json_str(&j, "status", ea_status_name(res->status));
  ea_json_int(&j, "iterations", res->iterations);
  ea_json_num(&j, "chi2", res->chi2);
  ea_json_int(&j, "residuals", res->n_residuals);
  ea_json_int(&j, "dof", res->dof);
  ea_json_num(&j, "chi2_per_dof", res->dof > 0 ? res->chi2 / res->dof : NAN);
  ea_json_num(&j, "time_s", res->time_s);
  ea_json_arr_begin(&j, "parameters");
  for (int k = 0; k < EA_CALIB_NP; ++k) {
    ea_json_obj_begin(&j, NULL);
    ea_json_str(&j, "name", ea_calib_param_name(k));
    ea_json_str(&j, "key", ea_calib_param_key(k));
    ea_json_str(&j, "unit", ea__units[k]);
    ea_json_str(&j, "state", states[res->state[k]]);
    ea_json_num(&j, "prior", ea_calib_param_get(&res->prior, k)); /* payload: null, no prior */
    ea_json_num(&j, "estimate", res->value[k]);
    ea_json_num(&j, "standard_error", res->se[k]);
    ea_json_arr_begin(&j, "records");
    for (int r = 0; r < res->nrec && r < 32; ++r)
      if (res->state[k] == EA_CALIB_FITTED && (res->contributes[k] & (1 << r)))
        ea_json_str(&j, NULL, recs[r].path);
    ea_json_arr_end(&j);
    ea_json_obj_end(&j);
  }
  ea_json_arr_end(&j);
  /* correlations of the fitted parameters: names, then the matrix */
  ea_json_obj_begin(&j, "correlations");
  ea_json_arr_begin(&j, "names");
  for (int k = 0; k < EA_CALIB_NP; ++k)
    if (res->state[k] == EA_CALIB_FITTED) ea_json_str(&j, NULL, ea_calib_param_name(k));
  ea_json_arr_end(&j);
  ea_json_arr_begin(&j, "matrix");
  for (int k = 0; k < EA_CALIB_NP; ++k) {
    if (res->state[k] != EA_CALIB_FITTED) continue;
    double row[EA_CALIB_NP];
    int n = 0;
    for (int q = 0; q < EA_CALIB_NP; ++q)
      if (res->state[q] == EA_CALIB_FITTED) row[n++] = res->corr[k * EA_CALIB_NP + q];
    ea_json_vec(&j, NULL, row, n);
  }
  ea_json_arr_end(&j);
  ea_json_obj_end(&j);
  ea_json_obj_begin(&j, "identifiability");
  ea_json_vec(&j, "singular_values", res->sv, res->n_sv);
  ea_json_arr_begin(&j, "not_identifiable");
  for (int k = 0; k < EA_CALIB_NP; ++k)
    if (res->state[k] == EA_CALIB_UNIDENTIFIABLE) ea_json_str(&j, NULL, ea_calib_param_name(k));
  ea_json_arr_end(&j);
  ea_json_arr_begin(&j, "notes");
  for (int n = 0; n < res->n_notes; ++n)
    ea_json_str(&j, NULL, res->notes[n]);
  ea_json_arr_end(&j);
  ea_json_obj_end(&j);
  ea_json_arr_begin(&j, "damping");
  for (int k = 0; k < res->n_zeta; ++k) {
    ea_json_obj_begin(&j, NULL);
    ea_json_int(&j, "mode", k + 1);
    ea_json_num(&j, "ratio", res->zeta[k]);
    ea_json_num(&j, "standard_error", res->zeta_se[k]);
    ea_json_int(&j, "ringdowns", res->zeta_count[k]);
    ea_json_obj_end(&j);
  }
  ea_json_arr_end(&j);
  ea_json_arr_begin(&j, "records");
  for (int r = 0; r < res->nrec; ++r) {
    const ea_calib_record_fit_t *rf = &res->rec[r];
    ea_json_obj_begin(&j, NULL);
    ea_json_str(&j, "path", recs[r].path);
    ea_json_str(&j, "kind", recs[r].kind == EA_CALIB_STATIC ? "static" : "ringdown");
    ea_json_int(&j, "rows", recs[r].rows);
    ea_json_int(&j, "residuals", rf->n);
    ea_json_num(&j, "chi2", rf->chi2);
    ea_json_num(&j, "rms_residual_over_noise", rf->n ? sqrt(rf->chi2 / rf->n) : NAN);
    ea_json_arr_begin(&j, "channels");
    for (int c = 0; c < EA_CALIB_NCH; ++c) {
      if (!recs[r].has[c]) continue;
      ea_json_obj_begin(&j, NULL);
      ea_json_str(&j, "column", ea_calib_channel_column(c));
      ea_json_num(&j, "noise", rf->noise[c]);
      ea_json_bool(&j, "noise_estimated", rf->noise_estimated[c]);
      ea_json_num(&j, "rms_residual", rf->rms[c]);
      ea_json_num(&j, "rms_over_noise", rf->noise[c] > 0 ? rf->rms[c] / rf->noise[c] : NAN);
      ea_json_obj_end(&j);
    }
    ea_json_arr_end(&j);
    if (recs[r].kind == EA_CALIB_RINGDOWN) {
      ea_json_num(&j, "cable_length_m", recs[r].hold_cable_length);
      ea_json_num(&j, "theta0_rad", recs[r].hold_theta0);
      ea_json_num(&j, "payload_kg", recs[r].payload_kg);
      ea_json_arr_begin(&j, "modes");
      for (int k = 0; k < rf->ring.modes; ++k) {
        ea_json_obj_begin(&j, NULL);
        ea_json_int(&j, "fe_mode", rf->ring.mode_index[k] + 1);
        ea_json_num(&j, "frequency_hz", rf->ring.freq_hz[k]);
        ea_json_num(&j, "frequency_se_hz", rf->ring.freq_se_hz[k]);
        ea_json_num(&j, "model_frequency_hz", rf->model_freq_hz[k]);
        ea_json_num(&j, "damping_ratio", rf->ring.zeta[k]);
        ea_json_num(&j, "damping_ratio_se", rf->ring.zeta_se[k]);
        ea_json_num(&j, "spectrum_peak_hz", rf->ring.spectrum_hz[k]);
        ea_json_obj_end(&j);
      }
      ea_json_arr_end(&j);
    }
    ea_json_obj_end(&j);
  }
  ea_json_arr_end(&j);
  ea_json_obj_end(&j);
  ea_json_end(&j);
  if (ferror(fp)) return ea_error_set(err, EA_ERR_IO, "writing the report failed");
  return EA_OK;
}
