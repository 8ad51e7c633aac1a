/* Private: the reduced dynamic model in the transcription: its table and rows
 * (transcribe/dyn_rows.c: the modal states, their defects, the tension and torque with the
 * modal parts, the terminal and rest rows) and its guesses and figures
 * (transcribe/dyn_model.c). */
#ifndef EA_DYN_IMPL_H
#define EA_DYN_IMPL_H

#include "plan_impl.h"

/** The closed-form Hessians of one interval's modal defect rows (a group of
 *  ea__plan_hess_group_len: rows[0..g-1], weights w; ea__plan_hess_fd_local's outputs). */
void ea__plan_dyn_defect_hess(const ea_planner_t *pl, const double *x, const ea__row_t *rows,
                              const double *w, int g, int cols[][EA__ROW_MAX], int *nc,
                              double Hl[][EA__ROW_MAX][EA__ROW_MAX]);
/** The path layout's local variables of a mode's defect rows over an interval
 * (transcribe/path_*.c): eta_k, eta'_k, eta_k+1, eta'_k+1, sigma_k, sigma_k+1, the rates of L_c and
 * alpha at k and k + 1, t_f (the order of the rows' entries in that layout; t_f dropped if fixed).
 */
#define EA__PP_DKEY 11
/** The closed-form Hessians of interval k's modal defect rows (rows[0..g-1], weights w: those
 *  with w = 0 skipped) in the path layout: second-order forward mode over the interval's path
 *  variables (sigma_k, sigma_k+1: sig; (L_c, alpha) at the ends functions of them with slopes
 *  dq[P] and curvatures d2q[P]), no chain rule. Hl[r]'s lower triangle over the row's
 *  EA__PP_DKEY entries (returned: their count), unweighted. x: the knot-layout expansion.
 *  Each mode's values and path gradients are kept for ea__plan_dyn_defect_pp_cached. */
int ea__plan_dyn_defect_hess_pp(const ea_planner_t *pl, const double *x, const double sig[2],
                                const double *dq[2], const double *d2q[2], const ea__row_t *rows,
                                const double *w, int g, double Hl[][EA__ROW_MAX][EA__ROW_MAX]);
/** Mode i's pos (vel 0) or vel defect over interval k at the path values key (the order of
 *  EA__PP_DKEY, t_f 0 if fixed) when ea__plan_dyn_defect_hess_pp left them: its value and
 *  gradient (either may be NULL); returns the entry count, 0 if not kept. */
int ea__plan_dyn_defect_pp_cached(const ea_planner_t *pl, int k, int i, int vel,
                                  const double key[EA__PP_DKEY], double *value, double *vals);
/** Forget what ea__plan_dyn_defect_hess_pp kept (the path's statics or geometry changed). */
void ea__plan_dyn_pp_forget(const ea_planner_t *pl);
/** Make the tables at knot k's (L_c, alpha) in x current (the knot's cache, which the rows of
 *  the intervals on both sides of it read: at the knot where transcribe/path_*.c splits its rows in
 * two parts, before their evaluation in parallel). */
void ea__plan_dyn_warm(const ea_planner_t *pl, const double *x, int k);
/** The same for the tension and torque rows with the modal parts (dyn_rows.c: the table's
 *  exact second derivatives); -1 for any other kind. */
int ea__plan_dyn_row_hess(const ea_planner_t *pl, const double *x, const ea__row_t *r, int *cols,
                          double H[][EA__ROW_MAX]);
/** The reduced dynamic model for a task with dynamics (pl->rom; NULL otherwise): the box of
 *  the task, the table from the cache or built (dyn_rows.c). */
ea_status_t ea__plan_dyn_build(ea_planner_t *pl, ea_error_t *err);
void ea__plan_dyn_cache_free(struct ea__dyn_cache *c);
/** Rows of the dynamic kinds; same contract as ea__plan_row_eval. */
int ea__plan_dyn_row(const ea_planner_t *pl, const double *x, const ea__row_t *r, double *value,
                     int *cols, double *vals);
/** Modal states of x integrated along its (L_c, alpha) from rest (a guess). */
void ea__plan_dyn_fill(const ea_planner_t *pl, double *x);
/* A cold guess with dynamics: stretched in time inside its limits (minimum time), then its
 * modal states filled (dyn_model.c). */
void ea__plan_dyn_guess(const ea_planner_t *pl, double *x);
/** For the refinement (plan_refine.c): model j's table (0 the nominal, 1..4 the robust
 *  corners; NULL: none) and the held plan's modal state of model j at the goal (Kper values
 *  each; 1: no held plan). */
const ea_rom_table_t *ea__plan_rom_model(const ea_planner_t *pl, int j);
int ea__plan_dyn_terminal(const ea_planner_t *pl, int j, double *eta, double *eta_rate);
/** The model's predicted residual and modal figures of a plan x into info. */
void ea__plan_dyn_stats(const ea_planner_t *pl, const double *x, ea_plan_info_t *info);

#endif
