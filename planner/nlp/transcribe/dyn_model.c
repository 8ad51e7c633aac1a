/* The reduced dynamic model of a plan that arrives at rest (docs/planner.md, "Arriving at
 * rest"), after its table (dyn_rows.c: ea__plan_dyn_build, with the rows that hold the model in
 * the transcription): the modal states of a guess integrated along its (L_c, alpha), a cold
 * guess stretched in time, the predicted residual and modal figures of a plan, the model's
 * accessors. */
#include "ea_simulate.h"
#include "dyn_impl.h"
#include "plan_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Hermite value, rate, acceleration of coordinate c over interval k at fraction u. */
static void ea__herm(const ea_planner_t *pl, const double *x, int k, int c, double u, double *q,
                     double *v, double *a) {
  const double tf = ea__plan_tf(pl, x), h = tf * (pl->s[k + 1] - pl->s[k]);
  const double y0 = x[EA__IQ(pl, k, c)], y1 = x[EA__IQ(pl, k + 1, c)];
  const double m0 = x[EA__IV(pl, k, c)] * h, m1 = x[EA__IV(pl, k + 1, c)] * h;
  const double u2 = u * u, u3 = u2 * u;
  *q = (2 * u3 - 3 * u2 + 1) * y0 + (u3 - 2 * u2 + u) * m0 + (-2 * u3 + 3 * u2) * y1 +
       (u3 - u2) * m1;
  *v = ((6 * u2 - 6 * u) * y0 + (3 * u2 - 4 * u + 1) * m0 + (-6 * u2 + 6 * u) * y1 +
        (3 * u2 - 2 * u) * m1) /
       h;
  *a = ((12 * u - 6) * y0 + (6 * u - 4) * m0 + (-12 * u + 6) * y1 + (6 * u - 2) * m1) / (h * h);
}

static void ea__dyn_rhs(const ea_planner_t *pl, const double *x, int k, double u, const double *z,
                        double *dz) {
  double q[2], v[2], a[2];
  for (int c = 0; c < 2; ++c)
    ea__herm(pl, x, k, c, u, &q[c], &v[c], &a[c]);
  for (int j = 0; j < pl->M; ++j) {
    ea_rom_point_t p;
    ea_rom_table_eval(pl->roms[j], q[0], q[1], &p, NULL, NULL);
    for (int mi = 0; mi < pl->Kper; ++mi) {
      const int i = j * pl->Kper + mi;
      const double F =
          -(p.B[mi][0] * a[0] + p.B[mi][1] * a[1]) -
          (p.C[mi][0] * v[0] * v[0] + 2 * p.C[mi][1] * v[0] * v[1] + p.C[mi][2] * v[1] * v[1]);
      dz[2 * i] = z[2 * i + 1];
      dz[2 * i + 1] =
          -p.omega2[mi] * z[2 * i] - 2 * pl->zeta[i] * sqrt(p.omega2[mi]) * z[2 * i + 1] + F;
    }
  }
}

void ea__plan_dyn_fill(const ea_planner_t *pl, double *x) {
  if (!pl->rom) return;
  const int K = pl->K, N = pl->N;
  double z[2 * EA__DYN_MAX] = {0}, k1[2 * EA__DYN_MAX], k2[2 * EA__DYN_MAX], k3[2 * EA__DYN_MAX],
               k4[2 * EA__DYN_MAX], zt[2 * EA__DYN_MAX];
  const double tf = ea__plan_tf(pl, x);
  for (int i = 0; i < K; ++i)
    x[EA__IE(pl, 0, i)] = x[EA__IED(pl, 0, i)] = 0.0;
  for (int k = 0; k + 1 < N; ++k) {
    const double h = tf * (pl->s[k + 1] - pl->s[k]);
    /* RK4 substeps of at most a twentieth of the highest mode's period */
    double wmax = 0.0;
    for (int j = 0; j < pl->M; ++j) {
      ea_rom_point_t p;
      ea_rom_table_eval(pl->roms[j], x[EA__IQ(pl, k, 0)], x[EA__IQ(pl, k, 1)], &p, NULL, NULL);
      wmax = fmax(wmax, sqrt(p.omega2[pl->Kper - 1]));
    }
    const int ns = (int)ceil(h * wmax / (2 * M_PI) * 20) + 1;
    const double du = 1.0 / ns, dt = h * du;
    for (int s = 0; s < ns; ++s) {
      const double u = s * du;
      ea__dyn_rhs(pl, x, k, u, z, k1);
      for (int j = 0; j < 2 * K; ++j)
        zt[j] = z[j] + 0.5 * dt * k1[j];
      ea__dyn_rhs(pl, x, k, u + 0.5 * du, zt, k2);
      for (int j = 0; j < 2 * K; ++j)
        zt[j] = z[j] + 0.5 * dt * k2[j];
      ea__dyn_rhs(pl, x, k, u + 0.5 * du, zt, k3);
      for (int j = 0; j < 2 * K; ++j)
        zt[j] = z[j] + dt * k3[j];
      ea__dyn_rhs(pl, x, k, u + du, zt, k4);
      for (int j = 0; j < 2 * K; ++j)
        z[j] += dt / 6 * (k1[j] + 2 * k2[j] + 2 * k3[j] + k4[j]);
    }
    for (int i = 0; i < K; ++i) {
      x[EA__IE(pl, k + 1, i)] = z[2 * i];
      x[EA__IED(pl, k + 1, i)] = z[2 * i + 1];
    }
  }
}

/* The cold guess of a minimum-time task with dynamics is stretched in time by this factor
 * (t_f x 1.1, every rate / 1.1, accelerations / 1.21) before its modal states are filled:
 * the quasi-static guess sits on its speed and acceleration limits, and Ipopt's steps toward
 * the terminal rest rows were cut short by the fraction-to-boundary rule (bench_dyn: the
 * at-rest paper line 65 -> 34 iterations, payload 0.5 44 -> 34, robust 57 -> 41, the same
 * durations to 1e-10; 1.03 / 1.06 / 1.15 / 1.2 measured 40 / 38 / 39 / 38 on the paper line).
 * A stretch chosen to minimise the goal's modal energy did not help: a uniform stretch barely
 * changes it. */
#define EA__DYN_GUESS_STRETCH 1.1

void ea__plan_dyn_guess(const ea_planner_t *pl, double *x) {
  if (pl->rom && pl->has_tf && pl->task.objective == EA_TASK_MIN_TIME) {
    const double c = EA__DYN_GUESS_STRETCH;
    x[EA__ITF(pl)] *= c;
    for (int k = 0; k < pl->N; ++k) {
      for (int q = 0; q < pl->nq; ++q)
        x[EA__IV(pl, k, q)] /= c;
      x[EA__IW(pl, k)] /= c;
    }
  }
  ea__plan_dyn_fill(pl, x);
}

/* "at rest": the tip within 1 mm of the final equilibrium (ea_sim_settings_t's default) */
#define EA__REST_TOL 1e-3

/* First time after which sum_i A_i e^{-d_i t} <= tol (a bound of the model's tip residual):
 * 0 when it starts below, INFINITY when an undamped mode keeps it above, else by bisection
 * (the bound decreases monotonically). */
static double ea__rest_time(const double *A, const double *d, int n, double tol) {
  double a0 = 0.0, ainf = 0.0, tmax = 0.0;
  for (int i = 0; i < n; ++i) {
    a0 += A[i];
    if (!(d[i] > 0))
      ainf += A[i];
    else if (A[i] > 0)
      tmax = fmax(tmax, log(n * A[i] / tol) / d[i]);
  }
  if (a0 <= tol) return 0.0;
  if (ainf > tol) return INFINITY;
  double lo = 0.0, hi = fmax(tmax, 0.0);
  for (int it = 0; it < 200 && hi - lo > 1e-9 * (1.0 + hi); ++it) {
    const double mid = 0.5 * (lo + hi);
    double s = 0.0;
    for (int i = 0; i < n; ++i)
      s += A[i] * exp(-d[i] * mid);
    if (s > tol)
      lo = mid;
    else
      hi = mid;
  }
  return hi;
}

void ea__plan_dyn_stats(const ea_planner_t *pl, const double *x, ea_plan_info_t *info) {
  info->predicted_time_to_rest_s = NAN;
  info->predicted_residual_m = info->max_modal_deviation_m = NAN;
  info->predicted_residual_worst_m = info->min_dynamic_tension_margin_N = NAN;
  for (int i = 0; i < EA_ROM_MAX_MODES; ++i)
    info->predicted_amplitude_m[i] = NAN;
  info->time_dyn_model_s = pl->rom ? pl->dyn_info.time_s : 0.0;
  if (!pl->rom) return;
  const int N = pl->N, Kp = pl->Kper;
  double dev = 0.0, tm = INFINITY, worst = 0.0;
  double amp[EA_ROM_MAX_MODES], decay[EA_ROM_MAX_MODES]; /* nominal: envelope A e^{-decay t} */
  for (int j = 0; j < pl->M; ++j) {
    ea_rom_point_t p;
    double res = 0.0;
    ea_rom_table_eval(pl->roms[j], x[EA__IQ(pl, N - 1, 0)], x[EA__IQ(pl, N - 1, 1)], &p, NULL,
                      NULL);
    for (int mi = 0; mi < Kp; ++mi) {
      const int i = j * Kp + mi;
      const double w = sqrt(p.omega2[mi]);
      const double a = hypot(x[EA__IE(pl, N - 1, i)], x[EA__IED(pl, N - 1, i)] / w) *
                       hypot(p.tip[mi][0], p.tip[mi][1]);
      if (j == 0) {
        info->predicted_amplitude_m[mi] = a;
        /* damped free vibration eta = e^{-z w t} (c cos w_d t + s sin w_d t): its envelope */
        const double z = pl->zeta[i], wd = w * sqrt(1.0 - z * z);
        const double e0 = x[EA__IE(pl, N - 1, i)], ed0 = x[EA__IED(pl, N - 1, i)];
        amp[mi] = hypot(e0, (ed0 + z * w * e0) / wd) * hypot(p.tip[mi][0], p.tip[mi][1]);
        decay[mi] = z * w;
      }
      res += a;
    }
    if (j == 0) {
      info->predicted_residual_m = res;
      info->predicted_time_to_rest_s = ea__rest_time(amp, decay, Kp, EA__REST_TOL);
    }
    worst = fmax(worst, res);
    for (int k = 0; k < N; ++k) {
      ea_rom_table_eval(pl->roms[j], x[EA__IQ(pl, k, 0)], x[EA__IQ(pl, k, 1)], &p, NULL, NULL);
      double dx = 0, dy = 0, dT = 0;
      for (int mi = 0; mi < Kp; ++mi) {
        const double e = x[EA__IE(pl, k, j * Kp + mi)];
        dx += p.tip[mi][0] * e;
        dy += p.tip[mi][1] * e;
        dT += p.dtension[mi] * e;
      }
      dev = fmax(dev, hypot(dx, dy));
      tm = fmin(tm, x[EA__IP(pl, k, 0)] + dT - pl->task.limits.tension_min);
    }
  }
  info->predicted_residual_worst_m = worst;
  info->max_modal_deviation_m = dev;
  info->min_dynamic_tension_margin_N = tm;
}

ea_status_t ea_planner_dyn_model(const ea_planner_t *pl, ea_plan_dyn_info_t *info) {
  if (!pl || !info) return EA_ERR_ARG;
  *info = pl->dyn_info;
  return EA_OK;
}

const ea_rom_table_t *ea_planner_rom_table(const ea_planner_t *pl) {
  return pl ? pl->rom : NULL;
}

const ea_rom_table_t *ea__plan_rom_model(const ea_planner_t *pl, int j) {
  return pl && j >= 0 && j < pl->M ? pl->roms[j] : NULL;
}

int ea__plan_dyn_terminal(const ea_planner_t *pl, int j, double *eta, double *eta_rate) {
  if (!pl || !pl->rom || !pl->have_solution || j < 0 || j >= pl->M) return 1;
  for (int mi = 0; mi < pl->Kper; ++mi) {
    eta[mi] = pl->x_sol[EA__IE(pl, pl->N - 1, j * pl->Kper + mi)];
    eta_rate[mi] = pl->x_sol[EA__IED(pl, pl->N - 1, j * pl->Kper + mi)];
  }
  return 0;
}
