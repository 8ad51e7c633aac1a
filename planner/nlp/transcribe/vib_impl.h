/* Private: the vibration rows (transcribe/vib_rows.c): the FE first-frequency model, the
 * frequency and modal deflection rows, the vibration objective. */
#ifndef EA_VIB_IMPL_H
#define EA_VIB_IMPL_H

#include "plan_impl.h"

#include <gsl/gsl_interp2d.h>
#include <gsl/gsl_spline2d.h>

/** FE first-frequency model f1(L_c, alpha) (vib_rows.c). */
typedef struct ea__freq_model {
  int nL, na;
  double *Lg, *ag, *f; /* grid (nL, na) and f1 [Hz] (na x nL, x fastest) */
  gsl_spline2d *sp;
  gsl_interp_accel *xa, *ya;
  ea_plan_freq_model_info_t info;
} ea__freq_model_t;

/** Build the frequency model when the task needs it (pl->fm; NULL otherwise). */
ea_status_t ea__plan_freq_build(ea_planner_t *pl, ea_error_t *err);
void ea__plan_freq_free(ea__freq_model_t *fm);
/** f1 [Hz] at (L_c, alpha), clamped to the box, and its gradient (may be NULL). */
double ea__plan_freq(const ea_planner_t *pl, double Lc, double al, double grad[2]);
/** Rows and objective pieces of the vibration kinds (EA__ROW_FREQ_MIN,
 *  EA__ROW_DEFL_*, EA__ROW_OBJ_VIB); same contract as ea__plan_row_eval. */
int ea__plan_vib_row(const ea_planner_t *pl, const double *x, const ea__row_t *r, double *value,
                     int *cols, double *vals);
/** Vibration figures of a plan x into info (min f1, max modal deflection). */
void ea__plan_vib_stats(const ea_planner_t *pl, const double *x, ea_plan_info_t *info);

#endif
