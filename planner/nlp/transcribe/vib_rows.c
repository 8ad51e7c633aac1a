/* Vibration-aware planning (docs/planner.md, "Vibration"): the FE model of
 * the first natural frequency f1(L_c, alpha) for the task's payload, and
 * the rows and objective pieces that use it:
 *  - EA__ROW_FREQ_MIN:   f1(q_k) >= limits.min_first_frequency_hz;
 *  - EA__ROW_DEFL_*:     |s_c acc_c| / omega1(q)^2 <= limits.max_modal_deflection_m
 *                        at both ends of every interval, s = (1, L_c);
 *  - EA__ROW_OBJ_VIB:    per interval, the integral of
 *                        sum_c (acc_c / aref_c)^2 (f_ref / f1(q(t)))^4
 *                        with (f_ref / f1)^4 linear between the knots (exact
 *                        for the Hermite's linear acceleration).
 * The model: FE frequencies (ea_fe_static_solve holding the tip at the
 * requested cable length and angle, ea_fe_modes, passive cable) on a grid
 * over the box of (L_c, alpha) the task's path covers, with a margin; grid
 * points without a valid FE state are filled by linear extrapolation from
 * their neighbours; GSL's bicubic spline (gsl_spline2d, gsl_interp2d_bicubic)
 * gives f1 and its exact gradient. Built once in ea_planner_alloc; the
 * callbacks only evaluate the spline (no allocation). */
#include "plan_impl.h"
#include "vib_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void ea__plan_freq_free(ea__freq_model_t *fm) {
  if (!fm) return;
  if (fm->sp) gsl_spline2d_free(fm->sp);
  if (fm->xa) gsl_interp_accel_free(fm->xa);
  if (fm->ya) gsl_interp_accel_free(fm->ya);
  free(fm->Lg);
  free(fm->ag);
  free(fm->f);
  free(fm);
}

static int ea__needs_model(const ea_task_t *t) {
  return (t->objective == EA_TASK_MIN_VIBRATION && t->dynamics.modes == 0) ||
         t->limits.min_first_frequency_hz > 0.0 || isfinite(t->limits.max_modal_deflection_m);
}

static int ea__clampi(int v, int lo, int hi) {
  return v < lo ? lo : v > hi ? hi : v;
}

/* Fill invalid grid values (ok[i] = 0) by linear extrapolation from valid
 * neighbours (averaged over the directions that have two valid points), or
 * the mean of the valid direct neighbours; repeated until all are filled. */
static int ea__fill(int nL, int na, double *f, unsigned char *ok) {
  for (int pass = 0; pass < nL + na; ++pass) {
    int missing = 0, filled = 0;
    for (int j = 0; j < na; ++j)
      for (int i = 0; i < nL; ++i) {
        if (ok[j * nL + i]) continue;
        ++missing;
        static const int di[4] = {1, -1, 0, 0}, dj[4] = {0, 0, 1, -1};
        double sx = 0.0, s1 = 0.0;
        int nx = 0, n1 = 0;
        for (int d = 0; d < 4; ++d) {
          const int i1 = i + di[d], j1 = j + dj[d], i2 = i + 2 * di[d], j2 = j + 2 * dj[d];
          if (i1 < 0 || i1 >= nL || j1 < 0 || j1 >= na || ok[j1 * nL + i1] != 1) continue;
          s1 += f[j1 * nL + i1];
          ++n1;
          if (i2 < 0 || i2 >= nL || j2 < 0 || j2 >= na || ok[j2 * nL + i2] != 1) continue;
          sx += 2.0 * f[j1 * nL + i1] - f[j2 * nL + i2];
          ++nx;
        }
        if (nx) {
          f[j * nL + i] = sx / nx;
        } else if (n1) {
          f[j * nL + i] = s1 / n1;
        } else {
          continue;
        }
        ok[j * nL + i] = 2; /* filled in this pass: usable from the next one */
        ++filled;
      }
    for (int q = 0; q < nL * na; ++q)
      if (ok[q] == 2) ok[q] = 1;
    if (!missing) return 0;
    if (!filled) return -1;
  }
  return 0;
}

/* (Just over 100 lines: the grid, the FE sweep over it and the spline in order, one FE model.) */
ea_status_t ea__plan_freq_build(ea_planner_t *pl, ea_error_t *err) {
  pl->fm = NULL;
  if (!ea__needs_model(&pl->task)) return EA_OK;
  const double t0 = ea__mono_s();
  const ea_task_t *t = &pl->task;
  ea__freq_model_t *fm = calloc(1, sizeof *fm);
  if (!fm) return ea_error_set(err, EA_ERR_NOMEM, "out of memory (frequency model)");
  pl->fm = fm;
  double box[4];
  ea__plan_box(pl, box);
  fm->nL = ea__clampi((int)ceil((box[1] - box[0]) / 0.04) + 1, 5, 15);
  fm->na = ea__clampi((int)ceil((box[3] - box[2]) / 0.06) + 1, 5, 15);
  const int nL = fm->nL, na = fm->na, n = nL * na;
  fm->Lg = calloc((size_t)nL, sizeof *fm->Lg);
  fm->ag = calloc((size_t)na, sizeof *fm->ag);
  fm->f = calloc((size_t)n, sizeof *fm->f);
  unsigned char *ok = calloc((size_t)n, 1);
  if (!fm->Lg || !fm->ag || !fm->f || !ok) {
    free(ok);
    return ea_error_set(err, EA_ERR_NOMEM, "out of memory (frequency model)");
  }
  for (int i = 0; i < nL; ++i)
    fm->Lg[i] = box[0] + (box[1] - box[0]) * i / (nL - 1);
  for (int j = 0; j < na; ++j)
    fm->ag[j] = box[2] + (box[3] - box[2]) * j / (na - 1);

  ea_fe_settings_t fs;
  ea_fe_settings_default(&fs);
  fs.static_hold_tip = 1; /* the FE state has exactly the grid's (L_c, alpha) */
  fs.modes = 2;
  ea_fe_model_t *m = NULL;
  ea_error_t e2;
  ea_status_t st = ea_fe_model_alloc(&t->arm, &fs, &m, &e2);
  ea_load_t load = {pl->tip_mass};
  if (!st) st = ea_fe_model_set_load(m, &load);
  if (st) {
    ea_fe_model_free(m);
    free(ok);
    return ea_error_set(err, st, "frequency model: FE model: %s", e2.msg);
  }
  double f_lo = INFINITY, f_hi = -INFINITY;
  int nvalid = 0;
  double row_guess[EA_NP] = {0}, guess[EA_NP];
  int have_row = 0;
  for (int j = 0; j < na; ++j) {
    int have = have_row;
    memcpy(guess, row_guess, sizeof guess);
    for (int i = 0; i < nL; ++i) {
      ea_statics_problem_t pr = ea_statics_problem_cable(fm->Lg[i], fm->ag[j]);
      ea_statics_solution_t sol;
      if (have) guess[0] = fm->ag[j];
      st = ea_statics_solve(pl->sh, &pr, NULL, have ? guess : NULL, &sol, &e2);
      if (st && have) st = ea_statics_solve(pl->sh, &pr, NULL, NULL, &sol, &e2);
      if (st || !(sol.p[EA_P_TENSION] > 0.0)) continue;
      memcpy(guess, sol.p, sizeof guess);
      have = 1;
      if (i == 0 || !have_row) {
        memcpy(row_guess, sol.p, sizeof row_guess);
        have_row = 1;
      }
      ea_fe_static_info_t fi;
      ea_fe_modes_info_t mi;
      if (ea_fe_static_solve(m, pl->sh, &sol, &fi, &e2) || ea_fe_modes(m, &mi, &e2) || !mi.stable ||
          !(mi.freq_hz[0] > 0.0))
        continue;
      fm->f[j * nL + i] = mi.freq_hz[0];
      ok[j * nL + i] = 1;
      f_lo = fmin(f_lo, mi.freq_hz[0]);
      f_hi = fmax(f_hi, mi.freq_hz[0]);
      ++nvalid;
    }
  }
  ea_fe_model_free(m);
  /* the shooter's state is shared with the callbacks: nothing to restore
   * (ea_shoot is stateless apart from its load). */
  if (nvalid < 4 || ea__fill(nL, na, fm->f, ok)) {
    free(ok);
    return ea_error_set(err, EA_ERR_INFEASIBLE,
                        "frequency model: only %d of %d grid points (L_c %.4g..%.4g m, alpha "
                        "%.4g..%.4g rad) have a static FE state for payload %.4g kg",
                        nvalid, n, box[0], box[1], box[2], box[3], t->payload_kg);
  }
  free(ok);
  fm->sp = gsl_spline2d_alloc(gsl_interp2d_bicubic, (size_t)nL, (size_t)na);
  fm->xa = gsl_interp_accel_alloc();
  fm->ya = gsl_interp_accel_alloc();
  if (!fm->sp || !fm->xa || !fm->ya)
    return ea_error_set(err, EA_ERR_NOMEM, "out of memory (frequency spline)");
  if (gsl_spline2d_init(fm->sp, fm->Lg, fm->ag, fm->f, (size_t)nL, (size_t)na))
    return ea_error_set(err, EA_ERR_BACKEND, "frequency model: gsl_spline2d_init failed");
  ea_plan_freq_model_info_t *in = &fm->info;
  in->built = 1;
  in->n_cable_length = nL;
  in->n_cable_angle = na;
  in->cable_length_range[0] = box[0];
  in->cable_length_range[1] = box[1];
  in->cable_angle_range[0] = box[2];
  in->cable_angle_range[1] = box[3];
  in->n_extrapolated = n - nvalid;
  in->f1_min_hz = f_lo;
  in->f1_max_hz = f_hi;
  in->f_ref_hz = ea__plan_freq(pl, t->start.cable_length, t->start.cable_angle, NULL);
  in->time_s = ea__mono_s() - t0;
  return EA_OK;
}

double ea__plan_freq(const ea_planner_t *pl, double Lc, double al, double grad[2]) {
  const ea__freq_model_t *fm = pl->fm;
  const double L = fmin(fmax(Lc, fm->Lg[0]), fm->Lg[fm->nL - 1]);
  const double a = fmin(fmax(al, fm->ag[0]), fm->ag[fm->na - 1]);
  double f = 0.0;
  gsl_spline2d_eval_e(fm->sp, L, a, fm->xa, fm->ya, &f);
  if (grad) {
    gsl_spline2d_eval_deriv_x_e(fm->sp, L, a, fm->xa, fm->ya, &grad[0]);
    gsl_spline2d_eval_deriv_y_e(fm->sp, L, a, fm->xa, fm->ya, &grad[1]);
  }
  return f;
}

/* ---------------------------------------------------------------------- */
/* Rows                                                                     */
/* ---------------------------------------------------------------------- */

#define EA__TWO_PI_SQ (4.0 * M_PI * M_PI)

/* (Over 100 lines: one case per vibration row kind, the rows' definitions side by side.) */
int ea__plan_vib_row(const ea_planner_t *pl, const double *x, const ea__row_t *r, double *value,
                     int *cols, double *vals) {
  const int k = r->knot, c = r->coord;
  int n = 0;
  int cl[EA__ROW_MAX];
  double gv[EA__ROW_MAX];
  switch ((ea__row_kind_t)r->kind) {
  case EA__ROW_FREQ_MIN: {
    double g[2];
    const double f = ea__plan_freq(pl, x[EA__IQ(pl, k, 0)], x[EA__IQ(pl, k, 1)], g);
    if (value) *value = f;
    cl[0] = EA__IQ(pl, k, 0);
    cl[1] = EA__IQ(pl, k, 1);
    gv[0] = g[0];
    gv[1] = g[1];
    n = 2;
    break;
  }
  case EA__ROW_DEFL_START:
  case EA__ROW_DEFL_END: {
    const int e = r->kind == EA__ROW_DEFL_END, ke = k + e;
    const double ds = pl->s[k + 1] - pl->s[k], h = ea__plan_tf(pl, x) * ds;
    double a[2], ga[2][5], g[2];
    ea__plan_hermite_acc(x[EA__IQ(pl, k, c)], x[EA__IQ(pl, k + 1, c)], x[EA__IV(pl, k, c)],
                         x[EA__IV(pl, k + 1, c)], h, a, ga);
    const double Lc = x[EA__IQ(pl, ke, 0)], al = x[EA__IQ(pl, ke, 1)];
    const double f = ea__plan_freq(pl, Lc, al, g);
    const double s = c == 0 ? 1.0 : Lc, iw2 = 1.0 / (EA__TWO_PI_SQ * f * f);
    const double d = s * a[e] * iw2, dd_da = s * iw2, dd_df = -2.0 * d / f;
    if (value) *value = d;
    cl[0] = EA__IQ(pl, k, c);
    cl[1] = EA__IQ(pl, k + 1, c);
    cl[2] = EA__IV(pl, k, c);
    cl[3] = EA__IV(pl, k + 1, c);
    for (int i = 0; i < 4; ++i)
      gv[i] = dd_da * ga[e][i];
    n = 4;
    /* frequency (and s) through the coordinates at knot ke */
    const int other = c == 0 ? 1 : 0;
    gv[e] += dd_df * g[c];
    cl[n] = EA__IQ(pl, ke, other);
    gv[n++] = dd_df * g[other] + (c == 1 ? a[e] * iw2 : 0.0);
    if (pl->has_tf) {
      cl[n] = EA__ITF(pl);
      gv[n++] = dd_da * ga[e][4] * ds;
    }
    break;
  }
  case EA__ROW_OBJ_VIB: {
    const double ds = pl->s[k + 1] - pl->s[k], h = ea__plan_tf(pl, x) * ds;
    const double fr = pl->fm->info.f_ref_hz;
    double W[2], dW[2][2];
    for (int e = 0; e < 2; ++e) {
      double g[2];
      const double f = ea__plan_freq(pl, x[EA__IQ(pl, k + e, 0)], x[EA__IQ(pl, k + e, 1)], g);
      const double q = fr / f, q2 = q * q;
      W[e] = q2 * q2;
      dW[e][0] = -4.0 * W[e] / f * g[0];
      dW[e][1] = -4.0 * W[e] / f * g[1];
    }
    double val = 0.0, gtf = 0.0, sw[2] = {0.0, 0.0};
    for (int cc = 0; cc < pl->nq; ++cc) {
      double a[2], ga[2][5];
      ea__plan_hermite_acc(x[EA__IQ(pl, k, cc)], x[EA__IQ(pl, k + 1, cc)], x[EA__IV(pl, k, cc)],
                           x[EA__IV(pl, k + 1, cc)], h, a, ga);
      const double is = 1.0 / (pl->aref[cc] * pl->aref[cc]);
      const double e0 = a[0] * a[0] / 4.0 + a[0] * a[1] / 6.0 + a[1] * a[1] / 12.0;
      const double e1 = a[0] * a[0] / 12.0 + a[0] * a[1] / 6.0 + a[1] * a[1] / 4.0;
      const double P = is * h * (W[0] * e0 + W[1] * e1);
      const double pa0 = is * h * (W[0] * (a[0] / 2.0 + a[1] / 6.0) + W[1] * (a[0] + a[1]) / 6.0);
      const double pa1 = is * h * (W[0] * (a[0] + a[1]) / 6.0 + W[1] * (a[0] / 6.0 + a[1] / 2.0));
      val += P;
      const int b = 4 * cc;
      cl[b + 0] = EA__IQ(pl, k, cc);
      cl[b + 1] = EA__IQ(pl, k + 1, cc);
      cl[b + 2] = EA__IV(pl, k, cc);
      cl[b + 3] = EA__IV(pl, k + 1, cc);
      for (int i = 0; i < 4; ++i)
        gv[b + i] = pa0 * ga[0][i] + pa1 * ga[1][i];
      gtf += (pa0 * ga[0][4] + pa1 * ga[1][4] + P / h) * ds;
      sw[0] += is * h * e0; /* d val / d W_e */
      sw[1] += is * h * e1;
    }
    /* the weights through (L_c, alpha) at both knots: slots 0/1 (L_c), 4/5 (alpha) */
    for (int e = 0; e < 2; ++e) {
      gv[0 + e] += sw[e] * dW[e][0]; /* L_c at knot k + e */
      gv[4 + e] += sw[e] * dW[e][1]; /* alpha at knot k + e */
    }
    n = 4 * pl->nq;
    if (pl->has_tf) {
      cl[n] = EA__ITF(pl);
      gv[n++] = gtf;
    }
    if (value) *value = val;
    break;
  }
  default:
    return 0;
  }
  for (int i = 0; i < n; ++i) {
    if (cols) cols[i] = cl[i];
    if (vals) vals[i] = gv[i];
  }
  return n;
}

/* ---------------------------------------------------------------------- */
/* Reports and public API                                                   */
/* ---------------------------------------------------------------------- */

void ea__plan_vib_stats(const ea_planner_t *pl, const double *x, ea_plan_info_t *info) {
  info->min_first_frequency_hz = NAN;
  info->max_modal_deflection_m = NAN;
  if (!pl->fm) return;
  double f_lo = INFINITY, dmax = 0.0;
  for (int k = 0; k < pl->N; ++k)
    f_lo = fmin(f_lo, ea__plan_freq(pl, x[EA__IQ(pl, k, 0)], x[EA__IQ(pl, k, 1)], NULL));
  for (int k = 0; k + 1 < pl->N; ++k)
    for (int c = 0; c < 2; ++c)
      for (int e = 0; e < 2; ++e) {
        const ea__row_t r = {(unsigned char)(e ? EA__ROW_DEFL_END : EA__ROW_DEFL_START),
                             (unsigned char)c, k};
        double d;
        ea__plan_vib_row(pl, x, &r, &d, NULL, NULL);
        dmax = fmax(dmax, fabs(d));
      }
  info->min_first_frequency_hz = f_lo;
  info->max_modal_deflection_m = dmax;
}

ea_status_t ea_planner_freq_model(const ea_planner_t *pl, ea_plan_freq_model_info_t *info) {
  if (!pl || !info) return EA_ERR_ARG;
  if (pl->fm)
    *info = pl->fm->info;
  else
    memset(info, 0, sizeof *info);
  return EA_OK;
}

ea_status_t ea_planner_first_frequency(const ea_planner_t *pl, double cable_length,
                                       double cable_angle, double *f1_hz, double grad[2],
                                       ea_error_t *err) {
  if (!pl || !f1_hz)
    return ea_error_set(err, EA_ERR_ARG, "ea_planner_first_frequency: NULL argument");
  if (!pl->fm)
    return ea_error_set(err, EA_ERR_ARG,
                        "ea_planner_first_frequency: the task needs no frequency model "
                        "(min_vibration, min_first_frequency_Hz or max_modal_deflection_m)");
  if (!isfinite(cable_length) || !isfinite(cable_angle))
    return ea_error_set(err, EA_ERR_ARG, "ea_planner_first_frequency: non-finite argument");
  *f1_hz = ea__plan_freq(pl, cable_length, cable_angle, grad);
  return ea_error_set(err, EA_OK, "ok");
}
