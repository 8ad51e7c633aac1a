/* Drive of an FE transient from sampled joint commands (planner/sim_impl.h). */
#include "sim_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

ea_status_t ea__sim_drive_alloc(ea__sim_drive_t *d, int n, int active, ea_error_t *err) {
  if (!d) return ea_error_set(err, EA_ERR_ARG, "sim drive: NULL");
  memset(d, 0, sizeof *d);
  if (n < 1) return ea_error_set(err, EA_ERR_ARG, "sim drive: %d samples", n);
  d->t = malloc(sizeof(double) * 3 * (size_t)n);
  if (!d->t) return ea_error_set(err, EA_ERR_NOMEM, "sim drive: %d samples", n);
  d->n = n;
  d->active = active != 0;
  d->theta0 = d->t + n;
  d->cable = d->t + 2 * (size_t)n;
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
  d->t[i] = t;
  d->theta0[i] = theta0;
  d->cable[i] = d->active ? T : ea_fe_cable_rest_length(L, T, arm->EA_cable);
  return EA_OK;
}

void ea__sim_drive_finish(ea__sim_drive_t *d) {
  d->s_theta0 = (ea_fe_samples_t){d->n, d->t, d->theta0};
  d->s_cable = (ea_fe_samples_t){d->n, d->t, d->cable};
  d->drive = (ea_fe_drive_t){ea_fe_samples_eval, &d->s_theta0, ea_fe_samples_eval, &d->s_cable};
}

ea_status_t ea__sim_drive_start(ea_fe_model_t *m, const ea__sim_drive_t *d, const double *q,
                                ea_fe_static_info_t *info, ea_error_t *err) {
  if (!m || !d || d->n < 1) return ea_error_set(err, EA_ERR_ARG, "sim drive start: NULL");
  const int nd = 3 * ea_fe_model_nodes(m);
  double *w = malloc(sizeof(double) * (size_t)nd);
  if (!w) return ea_error_set(err, EA_ERR_NOMEM, "sim drive start");
  if (q)
    memcpy(w, q, sizeof(double) * (size_t)nd);
  else
    ea_fe_get_state(m, w, NULL);
  w[2] = d->theta0[0];
  ea_status_t st = ea_fe_set_state(m, w, NULL);
  free(w);
  if (!st)
    st = ea_fe_set_cable(m, d->active ? EA_FE_CABLE_ACTIVE : EA_FE_CABLE_PASSIVE, d->cable[0]);
  if (st) return ea_error_set(err, st, "sim drive start: %s", ea_strerror(st));
  return ea_fe_newton(m, info, err);
}
