/* Private: what the calibration's fits share (problems/calib_*.c). */
#ifndef EA_CALIB_IMPL_H
#define EA_CALIB_IMPL_H

#include <gsl/gsl_multifit_nlinear.h>

#include <stddef.h>

/** Did gsl_multifit_nlinear_driver's run end at a minimum? status is the driver's return:
 *  GSL_SUCCESS; or a step GSL refuses to take (GSL_ENOPROG, or GSL_EMAXITER before
 *  max_iter iterations: too many rejected steps) at a point where a Gauss-Newton step
 *  predicts no decrease of |f|^2 (g' (J'J)^-1 g <= 1e-6 max(1, |f|^2), g = J' f): the
 *  minimum to rounding, as a fit started at its own solution ends. */
int ea__nls_converged(gsl_multifit_nlinear_workspace *w, int status, size_t max_iter);

#endif
