/* Private: the Lagrangian's Hessian of the knot transcription (transcribe/knot_hess.c): its
 * pattern and its values from the rows' closed forms or differences of exact gradients. */
#ifndef EA_HESS_IMPL_H
#define EA_HESS_IMPL_H

#include "plan_impl.h"

#include <stdint.h>

/** Most rows the Hessian differences together (an interval's modal defects). */
#define EA__HGROUP_MAX (2 * EA__DYN_MAX)
/** Rows r.. that the Hessian differences together (>= 1). */
int ea__plan_hess_group_len(const ea__row_t *rows, int r, int nr);
/** The Hessians of ea__plan_hess_fd_group as local matrices: row r's entries cols[r]
 *  (nc[r] of them; 0 where w[r] = 0) and Hl[r][a][b] = d grad_b / d x_cols[r][a] (closed forms
 *  where a row kind has one, with fn = ea__plan_row_eval: ea__plan_row_hess,
 *  ea__plan_dyn_defect_hess; else central differences of the exact gradients); g0 (NULL: not
 *  wanted) the rows' gradients at x in the same order; xx a scratch copy of x (one per
 *  thread). */
void ea__plan_hess_fd_local(const ea_planner_t *pl, ea__rowfn fn, const double *x, double *xx,
                            const ea__row_t *rows, const double *w, int g, int cols[][EA__ROW_MAX],
                            int *nc, double Hl[][EA__ROW_MAX][EA__ROW_MAX],
                            double g0[][EA__ROW_MAX]);
/** The Hessians of g rows (rows[0..g-1], weights w; ea__plan_hess_fd_local: closed forms or
 *  central differences over the union of their variables, xx a scratch copy of x), added as
 *  w 0.5 (H + H^T) at each row's Hessian positions hpos[r]. */
void ea__plan_hess_fd_group(const ea_planner_t *pl, ea__rowfn fn, const double *x, double *xx,
                            const ea__row_t *rows, const double *w, int g, const int *const *hpos,
                            double *values);
/** Hessian setup (structure, positions) and values (lower triangle). */
ea_status_t ea__plan_hess_setup(ea_planner_t *pl);
ea_status_t ea__plan_hess_pattern(ea_planner_t *pl);
ea_status_t ea__plan_hess_values(ea_planner_t *pl, const double *x, double obj_factor,
                                 const double *lambda, double *values);
void ea__plan_hess_free(ea_planner_t *pl);
/** Hessian sparsity (knot_hess.c): the key of entry (max(i, j), min(i, j)) of an n-column
 *  matrix. */
int64_t ea__hkey(int n, int i, int j);
/* The pattern of nk keys (ea__hkey of an n-column matrix, repeats allowed; keys is scratch):
 * its sorted unique entries as triplets (irow, jcol malloc'd, *nnz of them) and pos[q] = the
 * entry of keys[q]. */
ea_status_t ea__hpattern(int64_t *keys, size_t nk, int n, int *nnz, int **irow, int **jcol,
                         int *pos);

#endif
