/* Timing helpers shared by the benchmarks: monotonic wall clock, process
 * CPU clock, and the median of a sample (which it sorts). */
#ifndef EA_BENCH_UTIL_H
#define EA_BENCH_UTIL_H

#include <errno.h>
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

#endif
