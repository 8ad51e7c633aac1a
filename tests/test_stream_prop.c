/* Property test of the path to the motors (docs/streaming.md, "What is refused"):
 * random edits of valid trajectories (two plans joined, sub-millisecond intervals with
 * everything after them offset, truncations at either end, steps in each column, rows
 * swapped, single values scaled, and pairs of these) never yield a frame sequence that
 * the controller's own checker rejects or that leaves an arm-file limit at 1 kHz: each
 * edited file is refused (by the reader, the resampler or the streamer's checks) or
 * streams as frames the controller simulator accepts, every one, and ends at rest
 * without its own stop.
 *
 * The valid trajectories are plans of problems/examples (the paper line in minimum time
 * and at rest, the 3-D pick and place, which turns the base) and the closed-form septic
 * move of test_stream_fixture.h. The frames are the exact bytes `stream --to file:`
 * writes, run through the controller simulator's frame handler (ea__ctrl_feed_bytes:
 * CRC, sequence, limits, continuity).
 *
 * Usage: test_stream_prop [EDITS] (default 10000; label slow). */
#include "ea_test.h"
#include "ea_test_task.h"
#include "stream_impl.h"
#include "test_stream_fixture.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* xorshift64*: the edits are reproducible from the seed. */
static uint64_t g_rng = 0x9E3779B97F4A7C15ULL;
static uint64_t rnd_u64(void) {
  g_rng ^= g_rng >> 12;
  g_rng ^= g_rng << 25;
  g_rng ^= g_rng >> 27;
  return g_rng * 2685821657736338717ULL;
}
static double rnd_unit(void) { /* [0, 1) */
  return (double)(rnd_u64() >> 11) * 0x1.0p-53;
}
static int rnd_int(int n) { /* [0, n) */
  return (int)(rnd_u64() % (uint64_t)n);
}
/* A step size log-uniform in [lo, hi], random sign. */
static double rnd_step(double lo, double hi) {
  const double v = exp(log(lo) + rnd_unit() * (log(hi) - log(lo)));
  return rnd_u64() & 1 ? v : -v;
}

/* The columns the streamer reads (the rest are not streamed). */
static const int g_cols[] = {EA_TRAJ_cable_length,     EA_TRAJ_base_angle,
                             EA_TRAJ_theta0,           EA_TRAJ_tension,
                             EA_TRAJ_kappa0,           EA_TRAJ_cable_length_rate,
                             EA_TRAJ_base_angle_rate,  EA_TRAJ_theta0_rate,
                             EA_TRAJ_cable_length_acc, EA_TRAJ_base_angle_acc};
enum { NCOLS = sizeof g_cols / sizeof *g_cols };

/* dst := n rows (allocated), the first of them src's rows from..from+n-1 as far as src has
 * them (the rest zero, for the caller to fill). */
static int copy_rows(ea_traj_t *dst, const ea_traj_t *src, int from, int n) {
  if (ea_traj_alloc(dst, n)) return -1;
  const int have = src->n - from < n ? src->n - from : n;
  if (have > 0)
    memcpy(dst->data, src->data + (size_t)from * EA_TRAJ_NCOL,
           (size_t)have * EA_TRAJ_NCOL * sizeof *dst->data);
  dst->payload_kg = src->payload_kg;
  dst->tip_mass_kg = src->tip_mass_kg;
  snprintf(dst->arm_file, sizeof dst->arm_file, "%s", src->arm_file);
  snprintf(dst->task, sizeof dst->task, "%s", src->task);
  snprintf(dst->status, sizeof dst->status, "%s", src->status);
  dst->has_arm_hash = src->has_arm_hash;
  dst->arm_hash = src->arm_hash;
  return 0;
}

/* One random edit of a (in place: a is replaced); what describes it. */
static void edit_once(ea_traj_t *a, char *what, size_t wlen) {
  const int n = a->n;
  ea_traj_t b = {0};
  switch (rnd_int(7)) {
  case 0: { /* join a copy after it, shifted in time, one column offset */
    const double gaps[] = {0.0, 1e-7, 1e-5, 1e-4, 1e-3, 0.01, 0.3};
    const double gap = gaps[rnd_int(7)];
    const int c = g_cols[rnd_int(NCOLS)];
    const double off = rnd_unit() < 0.2 ? 0.0 : rnd_step(1e-6, 1.5);
    copy_rows(&b, a, 0, 2 * n);
    memcpy(b.data + (size_t)n * EA_TRAJ_NCOL, a->data, (size_t)n * EA_TRAJ_NCOL * sizeof *b.data);
    const double shift = EA_TRAJ_AT(a, n - 1, EA_TRAJ_t) - EA_TRAJ_AT(a, 0, EA_TRAJ_t) + gap;
    for (int i = n; i < 2 * n; ++i) {
      EA_TRAJ_AT(&b, i, EA_TRAJ_t) += shift;
      EA_TRAJ_AT(&b, i, c) += off;
    }
    snprintf(what, wlen, "join after %g s, column %d %+g", gap, c, off);
    break;
  }
  case 1: { /* a row inserted dt after row i, everything after it offset in a column */
    const int i = rnd_int(n - 1);
    const double dts[] = {1e-9, 1e-7, 1e-5, 1e-4, 5e-4, 9.99e-4};
    const double dt = dts[rnd_int(6)];
    const int c = g_cols[rnd_int(NCOLS)];
    const double off = rnd_unit() < 0.2 ? 0.0 : rnd_step(1e-6, 3.0);
    copy_rows(&b, a, 0, n + 1);
    memcpy(b.data + (size_t)(i + 1) * EA_TRAJ_NCOL, a->data + (size_t)i * EA_TRAJ_NCOL,
           (size_t)(n - i) * EA_TRAJ_NCOL * sizeof *b.data);
    for (int r = i + 1; r <= n; ++r) {
      EA_TRAJ_AT(&b, r, EA_TRAJ_t) += dt;
      EA_TRAJ_AT(&b, r, c) += off;
    }
    snprintf(what, wlen, "row %d + %g s inserted, column %d %+g after", i, dt, c, off);
    break;
  }
  case 2: { /* truncated at the start, the end or both */
    const int k0 = rnd_int(3) ? rnd_int(n / 2) : 0, k1 = rnd_int(3) ? rnd_int(n / 2) : 0;
    const int m = n - k0 - k1 < 1 ? 1 : n - k0 - k1;
    copy_rows(&b, a, k0, m);
    snprintf(what, wlen, "first %d and last %d rows removed", k0, k1);
    break;
  }
  case 3: { /* a step in one column from row i on */
    const int i = rnd_int(n), c = g_cols[rnd_int(NCOLS)];
    const double off = rnd_step(1e-7, 3.0);
    copy_rows(&b, a, 0, n);
    for (int r = i; r < n; ++r)
      EA_TRAJ_AT(&b, r, c) += off;
    snprintf(what, wlen, "column %d %+g from row %d", c, off, i);
    break;
  }
  case 4: { /* two rows swapped (with or without their times) */
    const int i = rnd_int(n), j = rnd_int(n), keep_t = rnd_int(2);
    copy_rows(&b, a, 0, n);
    for (int c = keep_t ? 1 : 0; c < EA_TRAJ_NCOL; ++c) {
      const double v = EA_TRAJ_AT(&b, i, c);
      EA_TRAJ_AT(&b, i, c) = EA_TRAJ_AT(&b, j, c);
      EA_TRAJ_AT(&b, j, c) = v;
    }
    snprintf(what, wlen, "rows %d and %d swapped%s", i, j, keep_t ? " (times kept)" : "");
    break;
  }
  case 5: { /* one value scaled */
    const int i = rnd_int(n), c = g_cols[rnd_int(NCOLS)];
    const double f = 1.0 + rnd_step(1e-6, 10.0);
    copy_rows(&b, a, 0, n);
    EA_TRAJ_AT(&b, i, c) *= f;
    snprintf(what, wlen, "row %d column %d x %g", i, c, f);
    break;
  }
  default: { /* the time column stretched or squeezed from row i on */
    const int i = 1 + rnd_int(n - 1);
    const double f = exp(rnd_step(1e-4, 2.0));
    copy_rows(&b, a, 0, n);
    const double ti = EA_TRAJ_AT(a, i - 1, EA_TRAJ_t);
    for (int r = i; r < n; ++r)
      EA_TRAJ_AT(&b, r, EA_TRAJ_t) = ti + (EA_TRAJ_AT(a, r, EA_TRAJ_t) - ti) * f;
    snprintf(what, wlen, "times from row %d x %g", i, f);
    break;
  }
  }
  ea_traj_free(a);
  *a = b;
}

typedef struct {
  int refused_read, refused_resample, refused_stream, streamed, bad;
} tally_t;

/* Read a whole file into a malloc'd buffer. */
static uint8_t *slurp(const char *path, size_t *len) {
  FILE *f = fopen(path, "rb");
  if (!f) return NULL;
  fseek(f, 0, SEEK_END);
  const long n = ftell(f);
  fseek(f, 0, SEEK_SET);
  uint8_t *b = malloc(n > 0 ? (size_t)n : 1);
  *len = b ? fread(b, 1, (size_t)n, f) : 0;
  fclose(f);
  return b;
}

/* The edited trajectory through the real path: file, reader, resampler, streamer (dry run
 * to a file), then the frames through the controller's checker. */
static void one_case(const ea_arm_t *arm, ea_ctrl_t *ctrl, const ea_traj_t *ed, const char *csv,
                     const char *bin, const char *what, tally_t *t) {
  ea_error_t e = {0};
  ea_traj_t rd = {0};
  if (ea_traj_write(ed, csv, &e) || ea_traj_read(&rd, csv, &e)) {
    ++t->refused_read;
    ea_traj_free(&rd);
    return;
  }
  ea_setpoint_t *sp = NULL;
  int n = 0;
  if (ea_stream_resample(&rd, arm, 1000.0, 1e-6, &sp, &n, &e)) {
    ++t->refused_resample;
    ea_traj_free(&rd);
    return;
  }
  ea_traj_free(&rd);
  char url[600];
  snprintf(url, sizeof url, "file:%s", bin);
  ea_stream_settings_t ss;
  ea_stream_settings_default(&ss);
  ss.realtime = 0;
  ss.wait_acks = 0;
  ea_stream_info_t info;
  remove(bin);
  const ea_status_t st = ea_stream_run(arm, sp, n, url, &ss, &info, &e);
  free(sp);
  if (st) {
    ++t->refused_stream;
    if (access(bin, F_OK) == 0) { /* a refusal writes nothing */
      ++t->bad;
      printf("BAD (%s): refused (%s) but a frame file was written\n", what, e.msg);
    }
    return;
  }
  ++t->streamed;
  size_t len = 0;
  uint8_t *b = slurp(bin, &len);
  ea__ctrl_reset(ctrl);
  const int done = b ? ea__ctrl_feed_bytes(ctrl, b, len) : 0;
  free(b);
  const ea_ctrl_info_t *ci = ea__ctrl_info(ctrl);
  if (!done || ci->rejected || ci->own_stop_frames || ci->accepted != info.frames_sent) {
    if (t->bad++ < 20)
      printf("BAD (%s): streamed %d frames; the controller accepted %d, rejected %d (limit %d, "
             "continuity %d), own stop %d, END %s\n",
             what, info.frames_sent, ci->accepted, ci->rejected, ci->rejected_limit,
             ci->rejected_continuity, ci->own_stop_frames, done ? "handled" : "missing");
  }
}

/* A plan of an example task (a valid trajectory); 0 on success. */
static int plan_example(const char *src, const char *name, ea_traj_t *tr, ea_arm_t *arm) {
  ea_task_t t;
  if (ea_test_load_example(src, name, &t)) return 1;
  ea_error_t e = {0};
  ea_planner_t *pl = NULL;
  ea_plan_info_t info;
  ea_status_t st = ea_planner_alloc(&t, &pl, &e);
  if (!st) st = ea_planner_solve(pl, EA_PLAN_COLD, NULL, &info, &e);
  if (!st) st = ea_planner_trajectory(pl, tr, &e);
  ea_planner_free(pl);
  if (st) printf("plan %s: %s\n", name, e.msg);
  *arm = t.arm;
  return st != EA_OK;
}

int main(int argc, char **argv) {
  const long edits = argc > 1 ? strtol(argv[1], NULL, 10) : 10000;
  const char *src = getenv("EA_SOURCE_DIR");
  if (!src) src = "..";
  /* scratch files on a RAM disk when there is one: thousands of atomic writes */
  const char *dir = access("/dev/shm", W_OK) == 0 ? "/dev/shm" : ".";
  char csv[512], bin[512];
  snprintf(csv, sizeof csv, "%s/ea_stream_prop_%d.csv", dir, (int)getpid());
  snprintf(bin, sizeof bin, "%s/ea_stream_prop_%d.bin", dir, (int)getpid());

  enum { NBASE = 4 };
  ea_traj_t base[NBASE] = {{0}};
  ea_arm_t arms[NBASE];
  const char *names[NBASE] = {"paper-line.yaml", "paper-line-rest.yaml", "pick-place-3d.yaml",
                              "septic move (closed form)"};
  int nb = 0;
  for (int i = 0; i < 3; ++i)
    if (!plan_example(src, names[i], &base[nb], &arms[nb])) ++nb;
  ea_test_true(nb == 3, "the example plans (valid trajectories to edit)");
  if (nb == 3) {
    const fx_move_t m = fx_default_move();
    arms[3] = arms[0];
    if (!fx_make_traj(&m, &arms[3], 0.02, &base[3])) nb = 4;
  }

  ea_ctrl_settings_t cs;
  ea_ctrl_settings_default(&cs);
  cs.buffer_capacity = 1 << 30; /* frames arrive faster than real time */
  ea_ctrl_t *ctrl[NBASE] = {0};
  for (int i = 0; i < nb; ++i)
    ea__ctrl_open_mem(&arms[i], &cs, &ctrl[i], NULL);

  /* the unedited trajectories stream, every frame accepted */
  tally_t t0 = {0};
  for (int i = 0; i < nb; ++i)
    one_case(&arms[i], ctrl[i], &base[i], csv, bin, names[i], &t0);
  char what[300];
  snprintf(what, sizeof what, "the %d unedited trajectories stream and every frame is accepted",
           nb);
  ea_test_true(t0.streamed == nb && t0.bad == 0, what);

  tally_t t = {0};
  for (long k = 0; k < edits && nb > 0; ++k) {
    const int i = rnd_int(nb);
    ea_traj_t ed = {0};
    copy_rows(&ed, &base[i], 0, base[i].n);
    char desc[400], d2[200];
    edit_once(&ed, d2, sizeof d2);
    snprintf(desc, sizeof desc, "edit %ld of %s: %s", k, names[i], d2);
    if (rnd_int(4) == 0) { /* a second edit on top */
      edit_once(&ed, d2, sizeof d2);
      snprintf(desc + strlen(desc), sizeof desc - strlen(desc), "; %s", d2);
    }
    one_case(&arms[i], ctrl[i], &ed, csv, bin, desc, &t);
    ea_traj_free(&ed);
  }
  printf("%ld random edits: refused by the reader %d, by the resampler %d, by the streamer's "
         "checks %d; streamed %d, of which the controller rejected a frame or stopped on its "
         "own in %d\n",
         edits, t.refused_read, t.refused_resample, t.refused_stream, t.streamed, t.bad);
  snprintf(what, sizeof what,
           "%ld random edits: each refused or streamed as frames the controller accepts, "
           "every one (%d streamed)",
           edits, t.streamed);
  ea_test_true(t.bad == 0, what);
  /* the edits reach every stage: a test whose edits are all refused by the reader proves
   * nothing about the streamer */
  ea_test_true(t.refused_resample > 0 && t.refused_stream > 0 && t.streamed > 0,
               "the edits reach the resampler's and the streamer's checks, and some stream");
  for (int i = 0; i < NBASE; ++i) {
    ea_traj_free(&base[i]);
    ea_ctrl_free(ctrl[i]);
  }
  remove(csv);
  remove(bin);
  return ea_test_summary("test_stream_prop");
}
