/* Timing helpers shared by the benchmarks: monotonic wall clock, process
 * CPU clock, and the median of a sample (which it sorts). */
#ifndef EA_BENCH_UTIL_H
#define EA_BENCH_UTIL_H

#include <errno.h>
#include <math.h>
#include <stdio.h>
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

/* A repetition count from argv[i] (dflt when absent): a whole number in 1..max, else
 * the usage line on stderr and -1 (the caller exits 2; a count of 0 would print medians
 * of nothing). */
static inline int ea_bench_count(int argc, char **argv, int i, int dflt, int max,
                                 const char *usage) {
  if (argc <= i) return dflt;
  char *end = NULL;
  errno = 0;
  const long v = strtol(argv[i], &end, 10);
  if (errno || end == argv[i] || *end || v < 1 || v > max) {
    fprintf(stderr, "%s: argument %d '%s' is not a count in 1..%d\nusage: %s\n", argv[0], i,
            argv[i], max, usage);
    return -1;
  }
  return (int)v;
}

/* The machine's pace, so that timing tables of different machines can be compared: the
 * median wall time [ms] of 5 runs of a fixed floating-point kernel (RK4 of the pendulum
 * theta'' = -sin(theta), 200000 steps: libm and scalar arithmetic, like the shooting and the
 * planner's callbacks); its result goes to a volatile, so the kernel is not optimised away. */
static inline double ea_bench_pace_ms(void) {
  double t[5];
  for (int r = 0; r < 5; ++r) {
    const double t0 = ea_bench_now();
    double th = 1.0, om = 0.0;
    const double h = 1e-4;
    for (int i = 0; i < 200000; ++i) {
      const double k1 = om, l1 = -sin(th);
      const double k2 = om + 0.5 * h * l1, l2 = -sin(th + 0.5 * h * k1);
      const double k3 = om + 0.5 * h * l2, l3 = -sin(th + 0.5 * h * k2);
      const double k4 = om + h * l3, l4 = -sin(th + h * k3);
      th += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
      om += h / 6.0 * (l1 + 2.0 * l2 + 2.0 * l3 + l4);
    }
    t[r] = 1e3 * (ea_bench_now() - t0);
    volatile double keep = th + om;
    (void)keep;
  }
  return ea_bench_median(t, 5);
}

/* The pace as a line of a bench's header. */
static inline void ea_bench_print_pace(void) {
  printf("machine pace: %.2f ms (fixed reference kernel of bench_util.h, median of 5; lower is "
         "faster)\n",
         ea_bench_pace_ms());
}

#endif
