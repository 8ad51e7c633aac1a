/* Timing helpers shared by the benchmarks: monotonic wall clock, process
 * CPU clock, and the median of a sample (which it sorts). */
#ifndef EA_BENCH_UTIL_H
#define EA_BENCH_UTIL_H

#include <stdlib.h>
#include <time.h>

static inline double ea_bench_now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static inline double ea_bench_cpu_now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static inline int ea_bench_cmp(const void *a, const void *b) {
  const double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

/* Median of v[0..n-1]; sorts v. */
static inline double ea_bench_median(double *v, int n) {
  qsort(v, (size_t)n, sizeof *v, ea_bench_cmp);
  return (n % 2) ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

#endif
