/* Minimal test helpers in the style of gsl_test_rel: every check prints a
 * line and counts; main returns ea_test_summary(). */
#ifndef EA_TEST_H
#define EA_TEST_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

static int ea_test_fails = 0, ea_test_count = 0;

static inline void ea_test_rel(double got, double want, double relerr, const char *what) {
  ++ea_test_count;
  const double d = (want == 0.0) ? fabs(got) : fabs(got - want) / fabs(want);
  const int ok = isfinite(got) && d <= relerr;
  if (!ok) ++ea_test_fails;
  printf("%s: %s: got %.15g want %.15g (rel err %.3g, tol %.3g)\n", ok ? "PASS" : "FAIL", what, got,
         want, d, relerr);
}

static inline void ea_test_abs(double got, double want, double abserr, const char *what) {
  ++ea_test_count;
  const double d = fabs(got - want);
  const int ok = isfinite(got) && d <= abserr;
  if (!ok) ++ea_test_fails;
  printf("%s: %s: got %.15g want %.15g (abs err %.3g, tol %.3g)\n", ok ? "PASS" : "FAIL", what, got,
         want, d, abserr);
}

static inline void ea_test_true(int cond, const char *what) {
  ++ea_test_count;
  if (!cond) ++ea_test_fails;
  printf("%s: %s\n", cond ? "PASS" : "FAIL", what);
}

/* Larger of a and b, NaN if either is NaN. fmax() drops a NaN, so a
 * "worst error" tallied with it would pass over a NaN; this one keeps it
 * and the check on the tally (which wants a finite value) fails. */
static inline double ea_test_max(double a, double b) {
  if (isnan(a) || isnan(b)) return NAN;
  return a > b ? a : b;
}

static inline int ea_test_summary(const char *name) {
  printf("%s: %d checks, %d failed\n", name, ea_test_count, ea_test_fails);
  return ea_test_fails ? EXIT_FAILURE : EXIT_SUCCESS;
}

#endif
