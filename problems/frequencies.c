/* Natural frequencies at configurations (ea_workspace.h): statics -> FE
 * statics -> modes, one configuration or the Fig. 5 sweep. One copy for the
 * frequencies command and the studies. */
#include "ea_workspace.h"

#include <math.h>
#include <string.h>

ea_status_t ea_freq_point(ea_shooter_t *sh, ea_fe_model_t *m, double cable_length, double alpha,
                          const double *guess, ea_freq_point_t *pt) {
  memset(pt, 0, sizeof *pt);
  pt->cable_length = cable_length;
  pt->alpha = alpha;
  pt->fe.residual = pt->fe.tension = pt->fe.theta0 = NAN;
  for (int k = 0; k < EA_FE_MAX_MODES; ++k)
    pt->modes.freq_hz[k] = NAN;
  ea_statics_problem_t pr = ea_statics_problem_cable(cable_length, alpha);
  pt->stage = "statics";
  pt->status = ea_statics_solve(sh, &pr, NULL, guess, &pt->ode, &pt->err);
  if (pt->status) return pt->status;
  pt->stage = "fe-static";
  pt->status = ea_fe_static_solve(m, sh, &pt->ode, &pt->fe, &pt->err);
  if (pt->status) return pt->status;
  pt->stage = "modes";
  pt->status = ea_fe_modes(m, &pt->modes, &pt->err);
  if (pt->status) return pt->status;
  pt->stage = "";
  return EA_OK;
}

ea_status_t ea_freq_sweep(ea_shooter_t *sh, ea_fe_model_t *m, const double *cable_length, int n,
                          double alpha, ea_freq_point_t *pts) {
  double guess[EA_NP];
  int have = 0, nfail = 0;
  for (int k = 0; k < n; ++k) {
    ea_freq_point(sh, m, cable_length[k], alpha, have ? guess : NULL, &pts[k]);
    if (pts[k].status && have) /* warm start failed: retry from the T = 0 edge */
      ea_freq_point(sh, m, cable_length[k], alpha, NULL, &pts[k]);
    if (pts[k].ode.status == EA_OK) {
      memcpy(guess, pts[k].ode.p, sizeof guess);
      have = 1;
    }
    nfail += pts[k].status != EA_OK;
  }
  return nfail ? EA_ERR_NOCONV : EA_OK;
}
