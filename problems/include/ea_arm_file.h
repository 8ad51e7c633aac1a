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

/** Load and validate an arm file. Every key is required; errors name
 *  file:line:column, the key, the value and the bound.
 * @param[in]  path  YAML file
 * @param[out] arm   filled on success
 */
ea_status_t ea_arm_load(const char *path, ea_arm_t *arm, ea_error_t *err);
/** Same from a string (len bytes); name is used in messages. */
ea_status_t ea_arm_load_string(const char *name, const char *text, size_t len, ea_arm_t *arm,
                               ea_error_t *err);

#ifdef __cplusplus
}
#endif
#endif /* EA_ARM_FILE_H */
