/**
 * @file ea_traj.h
 * @brief Trajectory files (docs/trajectory-format.md): the columns, the
 *        in-memory trajectory, atomic writing and validated reading
 *        (planner/traj/trajectory.c).
 */
#ifndef EA_TRAJ_H
#define EA_TRAJ_H

#include "ea_status.h"

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------------------ */
/* Trajectory files (docs/trajectory-format.md), format version 1            */
/* ------------------------------------------------------------------------ */

#define EA_TRAJ_FORMAT_VERSION 1

/** Columns of a trajectory, in file order. */
#define EA_TRAJ_COLUMNS(X)                                                                         \
  X(t, "t_s")                                                                                      \
  X(cable_length, "cable_length_m")                                                                \
  X(cable_angle, "cable_angle_rad")                                                                \
  X(base_angle, "base_angle_rad")                                                                  \
  X(cable_length_rate, "cable_length_rate_m_per_s")                                                \
  X(cable_angle_rate, "cable_angle_rate_rad_per_s")                                                \
  X(base_angle_rate, "base_angle_rate_rad_per_s")                                                  \
  X(cable_length_acc, "cable_length_acc_m_per_s2")                                                 \
  X(cable_angle_acc, "cable_angle_acc_rad_per_s2")                                                 \
  X(base_angle_acc, "base_angle_acc_rad_per_s2")                                                   \
  X(tension, "tension_N")                                                                          \
  X(theta0, "theta0_rad")                                                                          \
  X(theta0_rate, "theta0_rate_rad_per_s")                                                          \
  X(kappa0, "kappa0_per_m")                                                                        \
  X(shoulder_torque, "shoulder_torque_Nm")                                                         \
  X(tip_x, "tip_x_m")                                                                              \
  X(tip_y, "tip_y_m")                                                                              \
  X(tip_z, "tip_z_m")

#define EA__TRAJ_ENUM(name, header) EA_TRAJ_##name,
enum { EA_TRAJ_COLUMNS(EA__TRAJ_ENUM) EA_TRAJ_NCOL };
#undef EA__TRAJ_ENUM

/** Header name of column c ("t_s", ...). */
const char *ea_traj_column_name(int c);

/** A trajectory: n samples of EA_TRAJ_NCOL columns, row-major, plus the
 *  metadata the file carries. */
typedef struct ea_traj {
  int n;               /**< number of samples */
  double *data;        /**< n x EA_TRAJ_NCOL, row-major; owned */
  double payload_kg;   /**< [kg] payload m_p */
  double tip_mass_kg;  /**< [kg] m_L */
  char arm_file[4096]; /**< arm file the plan was made with ("" = defaults); relative paths
                            are relative to the current folder (ea_traj_read resolves the
                            file's relative ones against the trajectory's folder) */
  int has_arm_hash;    /**< 1: arm_hash holds the arm's ea_arm_hash ('# arm_hash:') */
  uint64_t arm_hash;   /**< ea_arm_hash of the arm the plan was made with */
  char task[512];      /**< task name or file */
  char run_id[64];     /**< the plan run that wrote it, shared with the run's JSON summary
                            ('# run_id:'; "" none) */
  char status[64];     /**< planner status, e.g. "EA_OK" */
} ea_traj_t;

/** Value at sample i, column c. */
#define EA_TRAJ_AT(tr, i, c) ((tr)->data[(size_t)(i)*EA_TRAJ_NCOL + (c)])

/** Allocate n zeroed samples (frees previous data). Every ea_traj_t handed to
 *  the library starts zeroed (ea_traj_t tr = {0};) and is released with
 *  ea_traj_free; a call that fills it replaces (frees) what it held. */
ea_status_t ea_traj_alloc(ea_traj_t *tr, int n);
void ea_traj_free(ea_traj_t *tr);
/** Fill the statics columns of sample i from a configuration p = (alpha, T,
 *  theta0, kappa0) with tip state xL: tension, theta0, kappa0, shoulder
 *  torque EI kappa0, and the tip in the base frame using the sample's base
 *  angle. (Rates and the actuator columns are left alone.) */
void ea_traj_set_statics(ea_traj_t *tr, int i, const double p[4], const double xL[4], double EI);
/** Write atomically (CSV with '#' metadata lines). arm_file is written as an absolute
 *  path when it names an existing file (realpath), else as given; '# arm_hash:' only
 *  when has_arm_hash. */
ea_status_t ea_traj_write(const ea_traj_t *tr, const char *path, ea_error_t *err);
/** Read and validate (header, version, monotonic time, finite values, a
 *  '# arm_hash:' of 16 hexadecimal digits); errors say file:line:column. A
 *  relative '# arm_file:' is taken relative to the trajectory's folder (tr->arm_file
 *  gets that folder prefixed). tr: zeroed, or a trajectory whose samples are freed
 *  first. */
ea_status_t ea_traj_read(ea_traj_t *tr, const char *path, ea_error_t *err);
/** Read the simple CSV form: the header 't_s,cable_length_m,cable_angle_rad', then one
 *  row per sample (time increasing, cable length > 0, at least 2 rows); the rates of
 *  L_c and alpha by centred differences (one-sided at the ends), every other column 0
 *  (ea_traj_fill_statics, ea_simulate.h, fills the statics). Errors say file:line:column. */
ea_status_t ea_traj_read_simple(ea_traj_t *tr, const char *path, ea_error_t *err);
/** A trajectory file, or the simple CSV form when the first byte is not '#'
 *  (*simple = 1 then; simple may be NULL). */
ea_status_t ea_traj_read_any(ea_traj_t *tr, const char *path, int *simple, ea_error_t *err);

#ifdef __cplusplus
}
#endif
#endif /* EA_TRAJ_H */
