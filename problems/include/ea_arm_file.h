/**
 * @file ea_arm_file.h
 * @brief Arm files (data/elasticarm.yaml, YAML): load and validate an arm
 *        with file:line:column errors (problems/arm_file.c).
 */
#ifndef EA_ARM_FILE_H
#define EA_ARM_FILE_H

#include "ea_arm.h"

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------------------ */
/* Arm files (data/elasticarm.yaml)                                          */
/* ------------------------------------------------------------------------ */

/** Load and validate an arm file. Every key is required and within its physical range
 *  (docs/task-format.md, "Arm files"); errors name file:line:column, the key, the value and
 *  the bound.
 * @param[in]  path  YAML file
 * @param[out] arm   filled on success
 */
ea_status_t ea_arm_load(const char *path, ea_arm_t *arm, ea_error_t *err);
/** Same from a string (len bytes); name is used in messages. */
ea_status_t ea_arm_load_string(const char *name, const char *text, size_t len, ea_arm_t *arm,
                               ea_error_t *err);
/** ea_arm_load that also judges the arm's physical plausibility (docs/task-format.md, "Arm
 *  files"): warning (wlen bytes) gets "" or a message with file:line:column naming the value
 *  that looks wrong (the beam's weight against EI, rho g L^3 / EI, outside [0.05, 500]; the
 *  cable's largest bending T_max L^2 / EI below 1). Not an error: the arm loads. */
ea_status_t ea_arm_load_warn(const char *path, ea_arm_t *arm, char *warning, size_t wlen,
                             ea_error_t *err);
/** ea_arm_load_string with the plausibility warning of ea_arm_load_warn. */
ea_status_t ea_arm_load_string_warn(const char *name, const char *text, size_t len, ea_arm_t *arm,
                                    char *warning, size_t wlen, ea_error_t *err);

#ifdef __cplusplus
}
#endif
#endif /* EA_ARM_FILE_H */
