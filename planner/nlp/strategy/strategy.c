/* Which engine solves a plan's NLP and the fallback chain (strategy_impl.h has the table). */
#include "strategy_impl.h"

#include "ipopt_impl.h"

#include <stdio.h>

void ea__plan_strategy(const ea__solve_case_t *c, ea__strategy_t *s) {
  const int own = !c->derivative_test && !c->ipopt_only; /* the own engines may run */
  /* Ipopt's monotone barrier from a near-optimal start: with dynamics (knots) any cold start,
   * else a plan file or a cold guess timed along its path; the path transcription only
   * without dynamics */
  const int near_opt =
      c->start == EA_PLAN_FROM_TRAJ || (c->start == EA_PLAN_COLD && c->guess_timed);
  const int mono = !c->warm && (c->path ? !c->dynamics && near_opt
                                        : (c->dynamics ? c->start == EA_PLAN_COLD : near_opt));
  s->kkt_start = c->warm && !c->derivative_test;
  s->asn = c->path && c->warm && !c->dynamics && !c->derivative_test;
  s->ipopt_monotone = mono;
  s->why = "";
  if (c->path) {
    /* a cold solve, a plan file, or a replan the active-set Newton gave up: from the cold
     * guess (a replan's predicted point took more iterations) */
    s->ipm = own && (!c->warm || c->replan);
    s->ipm_from_cold = s->ipm && c->replan;
    if (!own)
      s->why = c->derivative_test ? "derivative test" : "solver.nlp: ipopt";
    else if (!s->ipm)
      s->why = "a warm start without a change";
    return;
  }
  /* the knots: where Ipopt would start its monotone barrier, or a replan with dynamics from
   * the cold guess (Ipopt took more iterations from the shifted plan) */
  const int from_cold = c->warm && c->replan && c->dynamics;
  s->ipm = own && c->hess_exact && !c->free_path && c->models <= 1 && (from_cold || mono);
  s->ipm_from_cold = s->ipm && from_cold;
  if (!own)
    s->why = c->derivative_test ? "derivative test" : "solver.nlp: ipopt";
  else if (!c->hess_exact)
    s->why = "limited-memory Hessian";
  else if (c->free_path)
    s->why = "free path";
  else if (c->models > 1)
    s->why = "robust corner models";
  else if (!s->ipm)
    s->why = "not a monotone start";
}

void ea__engine_result_fill(const ea__engine_result_t *r, ea_plan_info_t *info) {
  /* Ipopt's code and name only where Ipopt gave the result */
  const int ipopt = r->engine == EA__ENGINE_IPOPT;
  info->ipopt_status = ipopt ? r->ipopt_status : EA_PLAN_NO_IPOPT;
  snprintf(info->ipopt_status_name, sizeof info->ipopt_status_name, "%s",
           ipopt ? ea__ipopt_name(r->ipopt_status) : "");
  info->iterations = r->iterations;
  info->newton_steps = r->newton_steps;
  info->ipm_iterations = r->ipm_iterations;
  info->ipm_fallback = r->ipm_fallback;
}
