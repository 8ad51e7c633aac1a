/* Drive of an FE transient from sampled joint commands (planner/traj/sim_impl.h). */
#include "sim_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

ea_status_t ea__sim_drive_alloc(ea__sim_drive_t *d, int n, int active, ea_error_t *err) {
  if (!d) return ea_error_set(err, EA_ERR_ARG, "sim drive: NULL");
  memset(d, 0, sizeof *d);
  if (n < 1) return ea_error_set(err, EA_ERR_ARG, "sim drive: %d samples", n);
  d->t = malloc(sizeof(double) * 8 * (size_t)n);
  if (!d->t) return ea_error_set(err, EA_ERR_NOMEM, "sim drive: %d samples", n);
  d->n = n;
  d->active = active != 0;
  double *p = d->t + n;
  double **cols[] = {&d->theta0, &d->cable, &d->theta0_rate, &d->cable_rate, &d->L,
                     &d->L_rate, &d->T};
  for (size_t c = 0; c < sizeof cols / sizeof *cols; ++c, p += n)
    *cols[c] = p;
  for (int i = 0; i < n; ++i)
    d->theta0_rate[i] = d->L_rate[i] = NAN;
  return EA_OK;
}

void ea__sim_drive_free(ea__sim_drive_t *d) {
  if (!d) return;
  free(d->t);
  memset(d, 0, sizeof *d);
}

ea_status_t ea__sim_drive_set(ea__sim_drive_t *d, const ea_arm_t *arm, int i, double t, double L,
                              double T, double theta0, ea_error_t *err) {
  if (!d || !arm || i < 0 || i >= d->n)
    return ea_error_set(err, EA_ERR_ARG, "sim drive: sample %d", i);
  if (!isfinite(t) || !isfinite(L) || !isfinite(T) || !isfinite(theta0))
    return ea_error_set(err, EA_ERR_INPUT, "t = %g s: a value is not finite", t);
  if (!(T >= 0)) return ea_error_set(err, EA_ERR_INPUT, "t = %g s: tension %g N < 0", t, T);
  if (!d->active && !(L > 0))
    return ea_error_set(err, EA_ERR_INPUT, "t = %g s: cable length %g m <= 0", t, L);
  d->EA_cable = arm->EA_cable;
  d->t[i] = t;
  d->theta0[i] = theta0;
  d->L[i] = L;
  d->T[i] = T;
  d->cable[i] = d->active ? T : ea_fe_cable_rest_length(L, T, arm->EA_cable);
  return EA_OK;
}

void ea__sim_drive_set_rates(ea__sim_drive_t *d, int i, double L_rate, double theta0_rate) {
  if (!d || i < 0 || i >= d->n) return;
  d->L_rate[i] = L_rate;
  d->theta0_rate[i] = theta0_rate;
}

/* Centred difference of y at sample i (zero at the ends), as ea_fe_samples_eval
 * takes slopes when it has no rates. */
static double ea__sim_diff(const ea__sim_drive_t *d, const double *y, int i) {
  if (i <= 0 || i >= d->n - 1) return 0.0;
  return (y[i + 1] - y[i - 1]) / (d->t[i + 1] - d->t[i - 1]);
}

void ea__sim_drive_finish(ea__sim_drive_t *d) {
  for (int i = 0; i < d->n; ++i) {
    if (!isfinite(d->theta0_rate[i])) d->theta0_rate[i] = ea__sim_diff(d, d->theta0, i);
    if (d->active || !isfinite(d->L_rate[i])) {
      d->cable_rate[i] = ea__sim_diff(d, d->cable, i);
    } else {
      /* L0 = L / (1 + T / EA_c): the exact rate of L from the file, T' (a 1e-4 relative
       * correction here) by differences */
      const double r = 1.0 + d->T[i] / d->EA_cable;
      d->cable_rate[i] =
          d->L_rate[i] / r - d->L[i] * ea__sim_diff(d, d->T, i) / (d->EA_cable * r * r);
    }
  }
  d->s_theta0 = (ea_fe_samples_t){d->n, d->t, d->theta0, d->theta0_rate};
  d->s_cable = (ea_fe_samples_t){d->n, d->t, d->cable, d->cable_rate};
  d->drive = (ea_fe_drive_t){ea_fe_samples_eval, &d->s_theta0, ea_fe_samples_eval, &d->s_cable};
}

ea_status_t ea__sim_drive_start(ea_fe_model_t *m, const ea__sim_drive_t *d, const double *q,
                                ea_fe_static_info_t *info, ea_error_t *err) {
  if (!m || !d || d->n < 1) return ea_error_set(err, EA_ERR_ARG, "sim drive start: NULL");
  ea_status_t st = EA_OK;
  if (q) {
    st = ea_fe_set_state(m, q, NULL);
    if (!st) st = ea_fe_newton(m, NULL, err);
    if (st) return ea_error_set(err, st, "sim drive start: the given state: %s", err->msg);
  }
  /* from the equilibrium the model holds (e.g. an FE static solve of the start for this arm
   * and load) to the drive's inputs at t = 0 by continuation: a plan made for another tip
   * mass or stiffness gives inputs whose equilibrium is millimetres away, too far for one
   * Newton from a stiff cable's state */
  return ea_fe_static_continue(m, d->theta0[0],
                               d->active ? EA_FE_CABLE_ACTIVE : EA_FE_CABLE_PASSIVE, d->cable[0],
                               info, err);
}
