/**
 * @file ea_problems.h
 * @brief What a user asks, one include: arm files (ea_arm_file.h),
 *        workspace, torque maps and paths (ea_workspace.h), task specs
 *        (ea_task.h), batch studies (ea_study.h), calibration (ea_calib.h); with the model
 *        (ea_model.h). Knows nothing of Ipopt.
 */
#ifndef EA_PROBLEMS_H
#define EA_PROBLEMS_H

#include "ea_arm_file.h"
#include "ea_calib.h"
#include "ea_model.h"
#include "ea_study.h"
#include "ea_task.h"
#include "ea_workspace.h"

#endif /* EA_PROBLEMS_H */
