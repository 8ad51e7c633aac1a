/**
 * @file ea_problems.h
 * @brief What a user asks: arm files, task specs, workspace, torque maps,
 *        path admissibility, sweeps and studies. Knows nothing of Ipopt.
 */
#ifndef EA_PROBLEMS_H
#define EA_PROBLEMS_H

#include "ea_model.h"

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

/* EA_STATICS_PROBLEMS_SECTION_BEGIN (workspace, torque map, path: problems/statics_*.c) */
/* EA_STATICS_PROBLEMS_SECTION_END */

/* EA_TASK_SECTION_BEGIN (task specs: problems/task_*.c) */
/* EA_TASK_SECTION_END */

/* EA_STUDY_SECTION_BEGIN (studies: problems/study_*.c) */
/* EA_STUDY_SECTION_END */

#ifdef __cplusplus
}
#endif
#endif
