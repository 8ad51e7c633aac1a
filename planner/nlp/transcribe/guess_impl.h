/* Private: the knot transcription's start (transcribe/knot_guess.c): the path over the knots,
 * the initial guesses, a replan's prediction. */
#ifndef EA_GUESS_IMPL_H
#define EA_GUESS_IMPL_H

#include "plan_impl.h"

/** theta0 rates of x: the C2 cubic spline through the knots' theta0 with
 *  rest at the start and the goal (what the theta0 rows hold). */
void ea__plan_theta0_rates(const ea_planner_t *pl, double *x);
/** A short estimate of the duration [s] (the fixed one, else half the sum of
 *  the segments' rest-to-rest estimates), for tolerances set at alloc. */
double ea__plan_duration_low(const ea_planner_t *pl);
/** Initial guess (statics continuation along the straight interpolation). */
ea_status_t ea__plan_guess(ea_planner_t *pl, double *x, ea_plan_info_t *info, ea_error_t *err);
/** Initial guess from a previous trajectory. */
ea_status_t ea__plan_guess_traj(ea_planner_t *pl, const ea_traj_t *tr, double *x, ea_error_t *err);
/** Via knots, segments and the knot-to-segment map (at alloc). */
void ea__plan_layout(ea_planner_t *pl);
/** Path segments (ends, directions, normals) and the knot-to-segment map
 *  for the task's points at the planner's via knots (part of the layout;
 *  again at ea_planner_update, which keeps the via knots). */
void ea__plan_segments(ea_planner_t *pl);
/** Shift the previous solution x (of task prev) along a change of the task
 *  (ea_planner_update): points moved -> each coordinate moved by the blend
 *  of its segment's end shifts, min_time re-timed within the limits, every
 *  knot's statics re-solved (payload; statics 0: not, for the path transcription). */
ea_status_t ea__plan_predict(ea_planner_t *pl, const ea_task_t *prev, double *x, int statics);
double ea__plan_retime(const ea_planner_t *pl, double *x);
/** Uniform knot-time fractions s_k = k / (N - 1). */
void ea__plan_knot_times(ea_planner_t *pl);

#endif
