/* The nonlinear reduced model (model/fe_romnl.c) along a trajectory: its coefficients sampled on
 * the trajectory's path, and its modal equations integrated along the motion as
 * ea_traj_rom_predict integrates the linear model's (docs/fe.md, "At large modal deflection"). */
#include "ea_simulate.h"
#include "sim_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

ea_status_t ea_traj_romnl_sample(ea_romnl_t *r, const ea_rom_table_t *tb, const ea_traj_t *tr,
                                 int n, ea_error_t *err) {
  if (!r || !tb || !tr || tr->n < 2 || n < 2)
    return ea_error_set(err, EA_ERR_ARG, "nonlinear reduced model: bad argument");
  double *q = malloc(sizeof(double) * 2 * (size_t)n);
  if (!q) return ea_error_set(err, EA_ERR_NOMEM, "nonlinear reduced model: out of memory");
  const double t0 = EA_TRAJ_AT(tr, 0, EA_TRAJ_t), T = EA_TRAJ_AT(tr, tr->n - 1, EA_TRAJ_t) - t0;
  for (int s = 0; s < n; ++s) {
    double v[2], a[2];
    ea__traj_actuators(tr, T * s / (n - 1), q + 2 * s, v, a);
  }
  const ea_status_t st = ea_romnl_sample(r, tb, n, q, err);
  free(q);
  return st;
}

/* The right-hand side at time t since the start: the actuators' motion from the trajectory's
 * Hermite, the linear table's point and the path position at q. */
static void ea__romnl_rhs(const ea_rom_table_t *tb, const ea_romnl_t *r, const ea_traj_t *tr,
                          double t, int *cursor, double *dist, const double *z, double *dz,
                          double tip[2], double *dT) {
  double q[2], v[2], a[2];
  ea__traj_actuators(tr, t, q, v, a);
  ea_rom_point_t p;
  ea_rom_table_eval(tb, q[0], q[1], &p, NULL, NULL);
  double d;
  const double pos = ea_romnl_locate(r, q, cursor, &d);
  *dist = fmax(*dist, d);
  ea_romnl_rhs(r, pos, &p, v, a, z, dz);
  if (tip) {
    tip[0] = tip[1] = 0.0;
    *dT = 0.0;
    for (int k = 0; k < EA_ROMNL_MODES; ++k) {
      tip[0] += p.tip[k][0] * z[2 * k];
      tip[1] += p.tip[k][1] * z[2 * k];
      *dT += p.dtension[k] * z[2 * k];
    }
  }
}

ea_status_t ea_traj_romnl_predict(const ea_rom_table_t *tb, const ea_romnl_t *r,
                                  const ea_traj_t *tr, double dt, double settle,
                                  ea_rom_prediction_t *out, double *path_dist, ea_error_t *err) {
  if (!tb || !r || !tr || !out || tr->n < 1 || !(dt > 0) || !(settle >= 0))
    return ea_error_set(err, EA_ERR_ARG, "nonlinear reduced-model prediction: bad argument");
  ea_romnl_info_t ri;
  ea_romnl_info(r, &ri);
  if (ri.samples < 2)
    return ea_error_set(err, EA_ERR_ARG, "nonlinear reduced-model prediction: not sampled");
  memset(out, 0, sizeof *out);
  enum { N = 2 * EA_ROMNL_MODES };
  out->modes = EA_ROMNL_MODES;
  const double T = EA_TRAJ_AT(tr, tr->n - 1, EA_TRAJ_t) - EA_TRAJ_AT(tr, 0, EA_TRAJ_t);
  const int n = (int)ceil(T / dt - 1e-9);
  const double h = n > 0 ? T / n : 0.0;
  double z[N] = {0}, k1[N], k2[N], k3[N], k4[N], zt[N], dist = 0.0;
  int cursor = 0;
  for (int i = 0; i < n; ++i) {
    const double t = i * h;
    double tip[2], dT;
    ea__romnl_rhs(tb, r, tr, t, &cursor, &dist, z, k1, tip, &dT);
    out->max_deviation = fmax(out->max_deviation, hypot(tip[0], tip[1]));
    out->min_tension_change = fmin(out->min_tension_change, dT);
    for (int j = 0; j < N; ++j)
      zt[j] = z[j] + 0.5 * h * k1[j];
    ea__romnl_rhs(tb, r, tr, t + 0.5 * h, &cursor, &dist, zt, k2, NULL, NULL);
    for (int j = 0; j < N; ++j)
      zt[j] = z[j] + 0.5 * h * k2[j];
    ea__romnl_rhs(tb, r, tr, t + 0.5 * h, &cursor, &dist, zt, k3, NULL, NULL);
    for (int j = 0; j < N; ++j)
      zt[j] = z[j] + h * k3[j];
    ea__romnl_rhs(tb, r, tr, t + h, &cursor, &dist, zt, k4, NULL, NULL);
    for (int j = 0; j < N; ++j)
      z[j] += h / 6 * (k1[j] + 2 * k2[j] + 2 * k3[j] + k4[j]);
  }
  if (path_dist) *path_dist = dist;
  for (int j = 0; j < N; ++j)
    if (!isfinite(z[j]))
      return ea_error_set(err, EA_ERR_INTEGRATION,
                          "nonlinear reduced-model prediction: the modal state left the model's "
                          "range (not finite)");
  ea__rom_settle(tb, tr, EA_ROMNL_MODES, z, settle, out);
  return EA_OK;
}
