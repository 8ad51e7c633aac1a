/**
 * @file ea_arm.h
 * @brief Arm parameters: the paper's Tables 1 and 2 and the actuator data
 *        (model/arm.c; arm files: ea_arm_file.h).
 *
 * Never prints, never aborts: every call returns an ::ea_status_t and, on
 * failure only, a message in the caller's optional ::ea_error_t.
 * Units: SI, angles in radians. The arm's plane has x horizontal (away from
 * the base axis) and y vertical (up); gravity is -y.
 */
#ifndef EA_ARM_H
#define EA_ARM_H

#include "ea_status.h"

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------------------ */
/* Arm parameters (paper Tables 1 and 2, plus actuator data)                 */
/* ------------------------------------------------------------------------ */

/** Actuator limits and geometry. Values not in the paper are assumptions,
 *  marked as such in data/elasticarm.yaml. */
typedef struct ea_actuators {
  double spool_radius;        /**< [m] effective cable spool radius */
  double spool_gear_ratio;    /**< [-] motor turns per spool turn */
  double spool_zero_length;   /**< [m] cable length at spool motor position 0 */
  double cable_length_min;    /**< [m] shortest cable (inner workspace edge) */
  double cable_length_max;    /**< [m] longest cable the spool holds */
  double cable_speed_max;     /**< [m/s] |dL_c/dt| limit */
  double cable_accel_max;     /**< [m/s^2] |d2L_c/dt2| limit */
  double tension_max;         /**< [N] cable tension limit */
  double tension_min;         /**< [N] default minimum tension margin (> 0) */
  double shoulder_torque_max; /**< [N m] |EI kappa0| limit */
  double shoulder_speed_max;  /**< [rad/s] |dtheta0/dt| limit */
  double shoulder_angle_min;  /**< [rad] shoulder range */
  double shoulder_angle_max;  /**< [rad] */
  double shoulder_accel_max;  /**< [rad/s^2] |d2theta0/dt2| limit */
  double base_speed_max;      /**< [rad/s] base motor speed limit */
  double base_accel_max;      /**< [rad/s^2] base motor acceleration limit */
  double base_angle_min;      /**< [rad] base range */
  double base_angle_max;      /**< [rad] */
} ea_actuators_t;

/** Arm parameters. Tables 1 and 2 of the paper. */
/** Most measured modal damping ratios an arm file may give. */
#define EA_ARM_MAX_DAMPED_MODES 6

typedef struct ea_arm {
  /* Table 1 */
  double rho;    /**< [kg/m] beam mass per unit length */
  double m_hand; /**< [kg] hand (gripper) mass m_h */
  double length; /**< [m] beam length L */
  double EI;     /**< [N m^2] flexural rigidity */
  double x_c;    /**< [m] cable root x */
  double y_c;    /**< [m] cable root y */
  double g;      /**< [m/s^2] gravitational acceleration */
  /* Table 2 (FE model) */
  double EA;          /**< [N] axial rigidity */
  double GA_s;        /**< [N] shear rigidity (beta G A) */
  double EA_cable;    /**< [N] cable axial rigidity EA_c */
  double I_zz;        /**< [kg m] rotary inertia per unit length */
  double I_hand;      /**< [kg m^2] rotary inertia I_L of hand (+ payload) */
  ea_actuators_t act; /**< actuator data */
  /* Damping (optional arm-file key damping.modal_ratios; not in the paper) */
  int n_damping; /**< measured modal damping ratios given (0: undamped, the default) */
  double damping_ratio[EA_ARM_MAX_DAMPED_MODES]; /**< zeta of modes 1..n_damping at rest, in
                                                      [0, 1); modes beyond: undamped */
} ea_arm_t;

/** Fill arm with the paper's values (Tables 1, 2) and the assumed actuator
 *  data documented in data/elasticarm.yaml. */
void ea_arm_default(ea_arm_t *arm);
/** Check every field: finite, right sign, consistent ranges. On failure,
 *  err->msg names the field, its value and the bound. */
ea_status_t ea_arm_validate(const ea_arm_t *arm, ea_error_t *err);
/** Payload mass from the payload factor gamma (eq. 17): gamma (m_h + rho L). */
double ea_arm_payload_from_factor(const ea_arm_t *arm, double gamma);
/** Tip mass m_L = m_h + m_p (eq. 1). */
double ea_arm_tip_mass(const ea_arm_t *arm, double payload_kg);
/** 1 when a and b hold the same parameters (the first n_damping damping ratios; the bytes
 *  between and after the fields are not compared), else 0. */
int ea_arm_equal(const ea_arm_t *a, const ea_arm_t *b);
/** A 64-bit fingerprint of the parameters ea_arm_equal compares (equal arms: equal hashes;
 *  an arm file's whitespace, comments and number spelling do not enter): FNV-1a over the
 *  IEEE-754 bit patterns, least significant byte first, of rho, m_hand, length, EI, x_c, y_c,
 *  g, EA, GA_s, EA_cable, I_zz, I_hand, the 18 fields of ea_actuators_t in their order,
 *  n_damping (as a double) and the first n_damping damping ratios; -0 counts as +0.
 *  Trajectory files carry it ('# arm_hash:', docs/trajectory-format.md). */
uint64_t ea_arm_hash(const ea_arm_t *arm);

#ifdef __cplusplus
}
#endif
#endif /* EA_ARM_H */
