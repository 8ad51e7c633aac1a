/* Arm files: YAML -> ea_arm_t with positions in every error. */
#include "ea_arm_file.h"
#include "yaml_impl.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define EA__INF INFINITY

typedef struct {
  const char *key;
  double lo, hi;
  size_t off; /* offset of the double in ea_arm_t */
} ea__field_t;

#define EA__F(key, lo, hi, member)                                                                 \
  { key, lo, hi, offsetof(ea_arm_t, member) }

static ea_status_t ea__read_fields(ea__ydoc_t *d, yaml_node_t *map, const char *ctx,
                                   const ea__field_t *f, size_t n, ea_arm_t *arm, ea_error_t *err) {
  const char *allowed[16];
  for (size_t i = 0; i < n && i < 15; ++i)
    allowed[i] = f[i].key;
  allowed[n < 15 ? n : 15] = NULL;
  ea_status_t st = ea__ymap_check_keys(d, map, allowed, ctx, err);
  if (st) return st;
  for (size_t i = 0; i < n; ++i) {
    double *dst = (double *)((char *)arm + f[i].off);
    st = ea__ymap_double(d, map, f[i].key, 1, f[i].lo, f[i].hi, dst, err);
    if (st) return st;
  }
  return EA_OK;
}

/* Optional damping: {modal_ratios: [zeta_1, ...]}: measured modal damping ratios, mode 1 first,
 * each in [0, 1). */
static ea_status_t ea__read_damping(ea__ydoc_t *d, yaml_node_t *root, ea_arm_t *arm,
                                    ea_error_t *err) {
  yaml_node_t *dm = NULL;
  ea_status_t st = ea__ymap_map(d, root, "damping", 0, &dm, err);
  if (st || !dm) return st;
  static const char *const keys[] = {"modal_ratios", NULL};
  if ((st = ea__ymap_check_keys(d, dm, keys, "damping", err))) return st;
  int n = 0;
  if ((st = ea__ymap_vec(d, dm, "modal_ratios", 1, -EA_ARM_MAX_DAMPED_MODES, arm->damping_ratio, &n,
                         err)))
    return st;
  yaml_node_t *seq = ea__ymap_get(d, dm, "modal_ratios");
  for (int i = 0; i < n; ++i)
    if (!(arm->damping_ratio[i] >= 0.0 && arm->damping_ratio[i] < 1.0))
      return ea__yerr(d, yaml_document_get_node(&d->doc, seq->data.sequence.items.start[i]), err,
                      EA_ERR_INPUT,
                      "damping.modal_ratios[%d] = %g: must be in [0, 1) (an underdamped mode: "
                      "0.02 is 2 %% of critical)",
                      i, arm->damping_ratio[i]);
  arm->n_damping = n;
  return EA_OK;
}

/* Plausibility of the beam against its load (a warning: such a beam exists, not for this
 * design). Two dimensionless numbers: the beam's own weight against its stiffness,
 * G = rho g L^3 / EI (the tip of a horizontal cantilever sags G/8 of its length in the linear
 * theory), and the cable's largest bending, B = T_max L^2 / EI (about the bending angle, in
 * rad, that the largest tension pulling at the tip gives). An elastic arm bends under both:
 * the paper's arm has G = 5.3 and, with data/elasticarm.yaml's 60 N, B = 71. G outside
 * [0.05, 500] (a hundred times either way) blames EI (or its unit); B < 1 with G plausible
 * (the cable cannot bend the beam by a radian) blames the tension limit. warning gets "" or
 * the message with file:line:column. */
static void ea__arm_plausibility(ea__ydoc_t *d, yaml_node_t *beam, yaml_node_t *ten,
                                 const ea_arm_t *arm, char *warning, size_t wlen) {
  warning[0] = '\0';
  const double L = arm->length, EI = arm->EI;
  const double G = arm->rho * arm->g * L * L * L / EI, B = arm->act.tension_max * L * L / EI;
  ea_error_t w = {0};
  if (arm->rho > 0 && arm->g > 0 && (G < 0.05 || G > 500))
    ea__yerr(d, ea__ymap_get(d, beam, "EI_Nm2"), &w, EA_ERR_INPUT,
             "beam.EI_Nm2 = %g N m^2 looks %s for this beam: its own weight against its "
             "stiffness, rho g L^3 / EI = %.3g (plausible 0.05 .. 500; the paper's arm 5.3), "
             "the tip of the horizontal beam sagging about %.3g mm under its weight, and the "
             "cable at max_N = %g N bending it by about T L^2 / EI = %.3g rad; check the value "
             "and its unit (N m^2)",
             EI, G < 0.05 ? "too large" : "too small", G, 1e3 * G * L / 8, arm->act.tension_max, B);
  else if (B < 1.0)
    ea__yerr(d, ea__ymap_get(d, ten, "max_N"), &w, EA_ERR_INPUT,
             "actuators.tension.max_N = %g N looks too low for this beam: at that tension the "
             "cable bends it by about T L^2 / EI = %.3g rad (data/elasticarm.yaml: 71), so most "
             "tip positions need more tension than allowed; check max_N or beam.EI_Nm2",
             arm->act.tension_max, B);
  snprintf(warning, wlen, "%s", w.msg);
}

static ea_status_t ea__arm_from_doc(ea__ydoc_t *d, ea_arm_t *arm, char *warning, size_t wlen,
                                    ea_error_t *err) {
  if (warning && wlen) warning[0] = '\0';
  yaml_node_t *root, *beam, *hand, *cable, *act, *spool, *ten, *sho, *base;
  ea_status_t st = ea__ydoc_root_map(d, &root, err);
  if (st) return st;
  static const char *const top[] = {"beam",      "hand",    "cable", "gravity_m_per_s2",
                                    "actuators", "damping", NULL};
  if ((st = ea__ymap_check_keys(d, root, top, "the arm file", err))) return st;
  ea_arm_default(arm);
  if ((st = ea__ymap_map(d, root, "beam", 1, &beam, err))) return st;
  if ((st = ea__ymap_map(d, root, "hand", 1, &hand, err))) return st;
  if ((st = ea__ymap_map(d, root, "cable", 1, &cable, err))) return st;
  if ((st = ea__ymap_map(d, root, "actuators", 1, &act, err))) return st;
  /* Physical ranges: generous for any arm of this kind (a beam of metres, not kilometres; a
   * spool of millimetres to a metre), finite, so that a slip of the exponent or the unit is
   * caught here and not as a spool position of 1e-309 rad on the wire. */
  static const ea__field_t fb[] = {
      EA__F("rho_kg_per_m", 0, 1e3, rho), EA__F("length_m", 1e-3, 100, length),
      EA__F("EI_Nm2", 1e-9, 1e9, EI),     EA__F("EA_N", 1e-3, 1e13, EA),
      EA__F("GA_N", 1e-3, 1e13, GA_s),    EA__F("Izz_kg_m", 0, 1e3, I_zz)};
  static const ea__field_t fh[] = {EA__F("mass_kg", 0, 1e4, m_hand),
                                   EA__F("Izz_kg_m2", 0, 1e4, I_hand)};
  static const ea__field_t fc[] = {EA__F("root_x_m", -100, 100, x_c),
                                   EA__F("root_y_m", -100, 100, y_c),
                                   EA__F("EA_N", 1e-3, 1e13, EA_cable)};
  if ((st = ea__read_fields(d, beam, "beam", fb, sizeof fb / sizeof *fb, arm, err))) return st;
  if ((st = ea__read_fields(d, hand, "hand", fh, sizeof fh / sizeof *fh, arm, err))) return st;
  if ((st = ea__read_fields(d, cable, "cable", fc, sizeof fc / sizeof *fc, arm, err))) return st;
  if ((st = ea__ymap_double(d, root, "gravity_m_per_s2", 1, 0, 1e3, &arm->g, err))) return st;

  static const char *const acts[] = {"spool", "tension", "shoulder", "base", NULL};
  if ((st = ea__ymap_check_keys(d, act, acts, "actuators", err))) return st;
  if ((st = ea__ymap_map(d, act, "spool", 1, &spool, err))) return st;
  if ((st = ea__ymap_map(d, act, "tension", 1, &ten, err))) return st;
  if ((st = ea__ymap_map(d, act, "shoulder", 1, &sho, err))) return st;
  if ((st = ea__ymap_map(d, act, "base", 1, &base, err))) return st;
  /* angles within one turn either way; the rest within what a motor and a spool can do */
  const double turn = 6.2832; /* 2 pi, rounded up */
  const ea__field_t fs[] = {EA__F("radius_m", 1e-4, 1.0, act.spool_radius),
                            EA__F("gear_ratio", 1e-3, 1e3, act.spool_gear_ratio),
                            EA__F("zero_length_m", 0.0, 100.0, act.spool_zero_length),
                            EA__F("cable_length_min_m", 1e-3, 100.0, act.cable_length_min),
                            EA__F("cable_length_max_m", 1e-3, 100.0, act.cable_length_max),
                            EA__F("speed_max_m_per_s", 1e-6, 100.0, act.cable_speed_max),
                            EA__F("accel_max_m_per_s2", 1e-6, 1e4, act.cable_accel_max)};
  static const ea__field_t ft[] = {EA__F("min_N", 1e-6, 1e5, act.tension_min),
                                   EA__F("max_N", 1e-6, 1e5, act.tension_max)};
  const ea__field_t fsh[] = {EA__F("torque_max_Nm", 1e-6, 1e4, act.shoulder_torque_max),
                             EA__F("speed_max_rad_per_s", 1e-6, 1e3, act.shoulder_speed_max),
                             EA__F("accel_max_rad_per_s2", 1e-6, 1e5, act.shoulder_accel_max),
                             EA__F("angle_min_rad", -turn, turn, act.shoulder_angle_min),
                             EA__F("angle_max_rad", -turn, turn, act.shoulder_angle_max)};
  const ea__field_t fba[] = {EA__F("speed_max_rad_per_s", 1e-6, 1e3, act.base_speed_max),
                             EA__F("accel_max_rad_per_s2", 1e-6, 1e5, act.base_accel_max),
                             EA__F("angle_min_rad", -turn, turn, act.base_angle_min),
                             EA__F("angle_max_rad", -turn, turn, act.base_angle_max)};
  if ((st = ea__read_fields(d, spool, "actuators.spool", fs, sizeof fs / sizeof *fs, arm, err)))
    return st;
  if ((st = ea__read_fields(d, ten, "actuators.tension", ft, sizeof ft / sizeof *ft, arm, err)))
    return st;
  if ((st = ea__read_fields(d, sho, "actuators.shoulder", fsh, sizeof fsh / sizeof *fsh, arm, err)))
    return st;
  if ((st = ea__read_fields(d, base, "actuators.base", fba, sizeof fba / sizeof *fba, arm, err)))
    return st;
  /* Cross-field consistency, reported at the mapping that holds the pair. */
  struct {
    yaml_node_t *map;
    const char *ctx, *lo_key, *hi_key;
    double lo, hi;
  } pairs[] = {
      {spool, "actuators.spool", "cable_length_min_m", "cable_length_max_m",
       arm->act.cable_length_min, arm->act.cable_length_max},
      {ten, "actuators.tension", "min_N", "max_N", arm->act.tension_min, arm->act.tension_max},
      {sho, "actuators.shoulder", "angle_min_rad", "angle_max_rad", arm->act.shoulder_angle_min,
       arm->act.shoulder_angle_max},
      {base, "actuators.base", "angle_min_rad", "angle_max_rad", arm->act.base_angle_min,
       arm->act.base_angle_max},
  };
  for (size_t i = 0; i < sizeof pairs / sizeof *pairs; ++i)
    if (!(pairs[i].lo < pairs[i].hi))
      return ea__yerr(d, ea__ymap_get(d, pairs[i].map, pairs[i].hi_key), err, EA_ERR_INPUT,
                      "%s: %s = %g must be below %s = %g (contradictory limits)", pairs[i].ctx,
                      pairs[i].lo_key, pairs[i].lo, pairs[i].hi_key, pairs[i].hi);
  if ((st = ea__read_damping(d, root, arm, err))) return st;
  ea_error_t e2 = {0};
  if ((st = ea_arm_validate(arm, &e2)))
    return ea__yerr(d, act, err, st, "inconsistent arm data: %s", e2.msg);
  /* No configuration has a cable longer than the farthest the tip can be from the cable
   * root (beam length plus the root's distance from the shoulder): no static solution. */
  const double reach = arm->length + hypot(arm->x_c, arm->y_c);
  if (arm->act.cable_length_min >= reach)
    return ea__yerr(d, ea__ymap_get(d, spool, "cable_length_min_m"), err, EA_ERR_INPUT,
                    "actuators.spool: cable_length_min_m = %g m: no configuration has a cable "
                    "this long (the tip is at most beam.length_m + |cable root| = %g m from the "
                    "cable root): no static solution exists",
                    arm->act.cable_length_min, reach);
  if (warning) ea__arm_plausibility(d, beam, ten, arm, warning, wlen);
  return EA_OK;
}

ea_status_t ea_arm_load_string(const char *name, const char *text, size_t len, ea_arm_t *arm,
                               ea_error_t *err) {
  return ea_arm_load_string_warn(name, text, len, arm, NULL, 0, err);
}

ea_status_t ea_arm_load_string_warn(const char *name, const char *text, size_t len, ea_arm_t *arm,
                                    char *warning, size_t wlen, ea_error_t *err) {
  if (!text || !arm) return ea_error_set(err, EA_ERR_ARG, "ea_arm_load_string: NULL argument");
  ea__ydoc_t d;
  ea_status_t st = ea__ydoc_load(&d, name, text, len, err);
  if (!st) st = ea__arm_from_doc(&d, arm, wlen ? warning : NULL, wlen, err);
  ea__ydoc_free(&d);
  return st;
}

ea_status_t ea_arm_load(const char *path, ea_arm_t *arm, ea_error_t *err) {
  return ea_arm_load_warn(path, arm, NULL, 0, err);
}

ea_status_t ea_arm_load_warn(const char *path, ea_arm_t *arm, char *warning, size_t wlen,
                             ea_error_t *err) {
  if (!path || !arm) return ea_error_set(err, EA_ERR_ARG, "ea_arm_load: NULL argument");
  ea__ydoc_t d;
  ea_status_t st = ea__ydoc_load(&d, path, NULL, 0, err);
  if (!st) st = ea__arm_from_doc(&d, arm, wlen ? warning : NULL, wlen, err);
  ea__ydoc_free(&d);
  return st;
}
