/* The seeded random sweep of tasks across the workspace shared by tests/test_rest_sweep.c and
 * bench/bench_rest.c (the bench times the test's tasks): uniform numbers by SplitMix64
 * (Steele, Lea & Flood 2014) from a fixed seed, tip points in the box that holds the arm's
 * planar workspace (the task check refuses what the arm does not reach). */
#ifndef EA_TEST_SWEEP_H
#define EA_TEST_SWEEP_H

#include "ea_problems.h"
#include "ea_simulate.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <time.h>

/** The sweep's seed: the state a sweep starts from. */
#define EA_TS_SEED 0x33c0ffeeULL

/* A uniform number in [0, 1) (53 bits), advancing *state. */
static inline double ea_ts_urand(uint64_t *state) {
  uint64_t z = (*state += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  z ^= z >> 31;
  return (double)(z >> 11) * 0x1.0p-53;
}

/* A tip point [m] in x 0.15..0.70, y -0.55..0.20; y is drawn first, in statements of their own
 * (the order of a call's arguments is unspecified in C: gcc and clang draw differently). */
static inline ea_task_point_t ea_ts_rand_point(uint64_t *state) {
  const double y = -0.55 + 0.75 * ea_ts_urand(state);
  const double x = 0.15 + 0.55 * ea_ts_urand(state);
  return ea_task_point_planar(x, y, 0.0);
}

/* The FE residual peak [m] of a plan at converged settings, the sweep's reference (12 elements,
 * generalized-alpha, dt 0.5 ms, 3 s after the motion, undamped); NAN, said on stdout, when the
 * transient fails. */
static inline double ea_ts_fe_converged(const ea_task_t *t, const ea_traj_t *tr) {
  ea_sim_settings_t s;
  ea_sim_settings_default(&s);
  s.elements = 12;
  s.scheme = EA_FE_SCHEME_GENALPHA;
  s.dt = 5e-4;
  s.settle = 3.0;
  s.damping_ratio = 0.0;
  ea_sim_info_t si;
  ea_error_t e = {0};
  if (ea_traj_simulate(&t->arm, tr, -1.0, &s, NULL, &si, &e)) {
    printf("  FE: %s\n", e.msg);
    return NAN;
  }
  return si.residual_peak;
}

/* Monotonic wall time [s]. */
static inline double ea_ts_mono(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

#endif
