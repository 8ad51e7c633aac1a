/**
 * @file ea_model.h
 * @brief elasticarm physics, one include: status codes (ea_status.h), arm
 *        parameters (ea_arm.h), elastica statics (ea_statics.h, paper sec. 2),
 *        the finite element and reduced models (ea_fe.h, paper sec. 3).
 *
 * The model knows nothing of files, tasks or solvers of the planner. It never
 * prints and never aborts: every call returns an ::ea_status_t and, where
 * useful and only on failure, a message in the caller's ::ea_error_t.
 *
 * Units: SI everywhere, angles in radians. The plane of the arm has x
 * horizontal (away from the base axis) and y vertical (up); gravity is -y.
 */
#ifndef EA_MODEL_H
#define EA_MODEL_H

#include "ea_arm.h"
#include "ea_fe.h"
#include "ea_statics.h"
#include "ea_status.h"

#endif /* EA_MODEL_H */
