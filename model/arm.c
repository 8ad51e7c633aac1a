/* Arm parameters: the paper's Tables 1 and 2 and assumed actuator data. */
#include "ea_arm.h"
#include "ea_util.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

void ea_arm_default(ea_arm_t *arm) {
  /* Table 1 */
  arm->rho = 0.501;
  arm->m_hand = 0.230;
  arm->length = 0.914;
  arm->EI = 0.705;
  arm->x_c = 0.098;
  arm->y_c = -0.006;
  arm->g = 9.81;
  /* Table 2 */
  arm->EA = 1.28e8;
  arm->GA_s = 3.28e6;
  arm->EA_cable = 1.02e5;
  arm->I_zz = 2.68e-8;
  arm->I_hand = 4.00e-4;
  /* Actuators: assumptions (see data/elasticarm.yaml) */
  ea_actuators_t *a = &arm->act;
  a->spool_radius = 0.015;
  a->spool_gear_ratio = 1.0;
  a->spool_zero_length = 0.254;
  a->cable_length_min = 0.254;
  a->cable_length_max = 1.2;
  a->cable_speed_max = 0.25;
  a->cable_accel_max = 1.0;
  a->tension_max = 60.0;
  a->tension_min = 0.05;
  a->shoulder_torque_max = 4.0;
  a->shoulder_speed_max = 2.0;
  a->shoulder_accel_max = 8.0;
  a->shoulder_angle_min = -30.0 * EA__DEG;
  a->shoulder_angle_max = 210.0 * EA__DEG;
  a->base_speed_max = 1.0;
  a->base_accel_max = 3.0;
  a->base_angle_min = -180.0 * EA__DEG;
  a->base_angle_max = 180.0 * EA__DEG;
  arm->n_damping = 0; /* the paper gives no damping: undamped, the worst case */
  for (int i = 0; i < EA_ARM_MAX_DAMPED_MODES; ++i)
    arm->damping_ratio[i] = 0.0;
}

#define EA__CHECK_POS(field)                                                                       \
  do {                                                                                             \
    if (!isfinite(arm->field) || !(arm->field > 0.0))                                              \
      return ea_error_set(err, EA_ERR_INPUT, "%s = %g: must be finite and > 0", #field,            \
                          arm->field);                                                             \
  } while (0)
#define EA__CHECK_NONNEG(field)                                                                    \
  do {                                                                                             \
    if (!isfinite(arm->field) || !(arm->field >= 0.0))                                             \
      return ea_error_set(err, EA_ERR_INPUT, "%s = %g: must be finite and >= 0", #field,           \
                          arm->field);                                                             \
  } while (0)
#define EA__CHECK_FINITE(field)                                                                    \
  do {                                                                                             \
    if (!isfinite(arm->field))                                                                     \
      return ea_error_set(err, EA_ERR_INPUT, "%s = %g: must be finite", #field, arm->field);       \
  } while (0)
#define EA__CHECK_LT(lo, hi)                                                                       \
  do {                                                                                             \
    if (!(arm->lo < arm->hi))                                                                      \
      return ea_error_set(err, EA_ERR_INPUT, "%s = %g must be below %s = %g", #lo, arm->lo, #hi,   \
                          arm->hi);                                                                \
  } while (0)

ea_status_t ea_arm_validate(const ea_arm_t *arm, ea_error_t *err) {
  if (!arm) return ea_error_set(err, EA_ERR_ARG, "arm is NULL");
  EA__CHECK_NONNEG(rho);
  EA__CHECK_NONNEG(m_hand);
  EA__CHECK_POS(length);
  EA__CHECK_POS(EI);
  EA__CHECK_FINITE(x_c);
  EA__CHECK_FINITE(y_c);
  EA__CHECK_NONNEG(g);
  EA__CHECK_POS(EA);
  EA__CHECK_POS(GA_s);
  EA__CHECK_POS(EA_cable);
  EA__CHECK_NONNEG(I_zz);
  EA__CHECK_NONNEG(I_hand);
  EA__CHECK_POS(act.spool_radius);
  EA__CHECK_POS(act.spool_gear_ratio);
  EA__CHECK_FINITE(act.spool_zero_length);
  EA__CHECK_POS(act.cable_length_min);
  EA__CHECK_POS(act.cable_length_max);
  EA__CHECK_LT(act.cable_length_min, act.cable_length_max);
  EA__CHECK_POS(act.cable_speed_max);
  EA__CHECK_POS(act.cable_accel_max);
  EA__CHECK_POS(act.tension_max);
  EA__CHECK_POS(act.tension_min);
  EA__CHECK_LT(act.tension_min, act.tension_max);
  EA__CHECK_POS(act.shoulder_torque_max);
  EA__CHECK_POS(act.shoulder_speed_max);
  EA__CHECK_POS(act.shoulder_accel_max);
  EA__CHECK_FINITE(act.shoulder_angle_min);
  EA__CHECK_FINITE(act.shoulder_angle_max);
  EA__CHECK_LT(act.shoulder_angle_min, act.shoulder_angle_max);
  EA__CHECK_POS(act.base_speed_max);
  EA__CHECK_POS(act.base_accel_max);
  EA__CHECK_FINITE(act.base_angle_min);
  EA__CHECK_FINITE(act.base_angle_max);
  EA__CHECK_LT(act.base_angle_min, act.base_angle_max);
  if (!(arm->act.cable_length_min > 0.0))
    return ea_error_set(err, EA_ERR_INPUT, "cable_length_min must be > 0");
  if (arm->n_damping < 0 || arm->n_damping > EA_ARM_MAX_DAMPED_MODES)
    return ea_error_set(err, EA_ERR_INPUT, "n_damping = %d: must be in [0, %d]", arm->n_damping,
                        EA_ARM_MAX_DAMPED_MODES);
  for (int i = 0; i < arm->n_damping; ++i)
    if (!(arm->damping_ratio[i] >= 0.0 && arm->damping_ratio[i] < 1.0))
      return ea_error_set(err, EA_ERR_INPUT,
                          "damping_ratio[%d] = %g: must be in [0, 1) (an underdamped mode)", i,
                          arm->damping_ratio[i]);
  return EA_OK;
}

double ea_arm_payload_from_factor(const ea_arm_t *arm, double gamma) {
  return gamma * (arm->m_hand + arm->rho * arm->length);
}

double ea_arm_tip_mass(const ea_arm_t *arm, double payload_kg) {
  return arm->m_hand + payload_kg;
}

int ea_arm_equal(const ea_arm_t *a, const ea_arm_t *b) {
  /* field by field: the struct has padding after n_damping and unused damping slots, which
   * memcmp would compare (a task loaded into an uninitialised struct then differed from
   * itself copied elsewhere) */
  const double fa[] = {a->rho, a->m_hand, a->length, a->EI,       a->x_c,  a->y_c,
                       a->g,   a->EA,     a->GA_s,   a->EA_cable, a->I_zz, a->I_hand};
  const double fb[] = {b->rho, b->m_hand, b->length, b->EI,       b->x_c,  b->y_c,
                       b->g,   b->EA,     b->GA_s,   b->EA_cable, b->I_zz, b->I_hand};
  for (size_t i = 0; i < sizeof fa / sizeof *fa; ++i)
    if (!(fa[i] == fb[i])) return 0;
  _Static_assert(sizeof(ea_actuators_t) == 18 * sizeof(double), "ea_actuators_t: doubles only");
  double xa[18], xb[18];
  memcpy(xa, &a->act, sizeof xa);
  memcpy(xb, &b->act, sizeof xb);
  for (int i = 0; i < 18; ++i)
    if (!(xa[i] == xb[i])) return 0;
  if (a->n_damping != b->n_damping) return 0;
  for (int i = 0; i < a->n_damping && i < EA_ARM_MAX_DAMPED_MODES; ++i)
    if (!(a->damping_ratio[i] == b->damping_ratio[i])) return 0;
  return 1;
}

/* FNV-1a (64 bit) of one value's IEEE-754 bit pattern, least significant byte first (the
 * same bytes on every host); -0 is hashed as +0, as ea_arm_equal compares with ==. */
static uint64_t ea__fnv_double(uint64_t h, double x) {
  if (x == 0.0) x = 0.0;
  uint64_t b;
  memcpy(&b, &x, sizeof b);
  for (int k = 0; k < 8; ++k) {
    h ^= (b >> (8 * k)) & 0xffu;
    h *= 1099511628211u;
  }
  return h;
}

uint64_t ea_arm_hash(const ea_arm_t *arm) {
  /* the parameters ea_arm_equal compares, in the order of ea_arm_t */
  const double f[] = {arm->rho, arm->m_hand, arm->length, arm->EI,       arm->x_c,  arm->y_c,
                      arm->g,   arm->EA,     arm->GA_s,   arm->EA_cable, arm->I_zz, arm->I_hand};
  uint64_t h = 14695981039346656037u;
  for (size_t i = 0; i < sizeof f / sizeof *f; ++i)
    h = ea__fnv_double(h, f[i]);
  double x[18];
  memcpy(x, &arm->act, sizeof x);
  for (int i = 0; i < 18; ++i)
    h = ea__fnv_double(h, x[i]);
  const int nd = arm->n_damping < 0                         ? 0
                 : arm->n_damping > EA_ARM_MAX_DAMPED_MODES ? EA_ARM_MAX_DAMPED_MODES
                                                            : arm->n_damping;
  h = ea__fnv_double(h, (double)arm->n_damping);
  for (int i = 0; i < nd; ++i)
    h = ea__fnv_double(h, arm->damping_ratio[i]);
  return h;
}
