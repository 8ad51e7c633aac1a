/* Ipopt: the problem of the knot transcription, its options, the names of its statuses. */
#include "ipopt_impl.h"
#include "hess_impl.h"
#include "knot_impl.h"
#include "plan_impl.h"
#include "plan_screen_impl.h"

#include <coin/IpStdCInterface.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* The Ipopt problem with the planner's bounds, its rows of the next solve (engine/ipopt_screen.c)
 * and the options. Every Ipopt solve creates it (ea__solve_engines: the rows it sees change from
 * solve to solve, and Ipopt's C interface copies the bounds at creation; every IpoptSolve sets
 * up its algorithm objects and the MUMPS analysis anew anyway), so a change of the task needs
 * no call here; ea_planner_alloc creates one to report a backend that cannot. A planner that
 * solves in the path coordinate (transcribe/path_*.c, its own problem per solve) has none. */
ea_status_t ea__ipopt_create(ea_planner_t *pl) {
  const ea_task_t *t = &pl->task;
  if (pl->ip) FreeIpoptProblem(pl->ip);
  pl->ip = NULL;
  if (pl->pp && !pl->pp_off) return EA_OK;
  if (pl->hess_exact && ea__plan_hess_pattern(pl)) return EA_ERR_NOMEM;
  /* the rows of the next solve (engine/ipopt_screen.c; every row until a solve selects them) */
  if (!pl->scr) {
    ea__nlp_t nlp;
    ea__knot_nlp(pl, &nlp);
    if (!(pl->scr = ea__screen_alloc(&nlp))) return EA_ERR_NOMEM;
  }
  pl->ip = ea__screen_problem(pl->scr, pl->xl, pl->xu);
  if (!pl->ip) return EA_ERR_BACKEND;
  ea__ipopt_options(pl->ip, &t->solver, pl->hess_exact, 0.0);
  return EA_OK;
}

/* the planner's copies of Ipopt's return codes (engine/ipopt_impl.h) */
_Static_assert((int)EA__IPOPT_SOLVE_SUCCEEDED == (int)Solve_Succeeded, "Ipopt's codes");
_Static_assert((int)EA__IPOPT_ACCEPTABLE == (int)Solved_To_Acceptable_Level, "Ipopt's codes");
_Static_assert((int)EA__IPOPT_INFEASIBLE == (int)Infeasible_Problem_Detected, "Ipopt's codes");
_Static_assert((int)EA__IPOPT_USER_STOP == (int)User_Requested_Stop, "Ipopt's codes");
_Static_assert((int)EA__IPOPT_MAX_ITER == (int)Maximum_Iterations_Exceeded, "Ipopt's codes");
_Static_assert((int)EA__IPOPT_RESTORATION_FAILED == (int)Restoration_Failed, "Ipopt's codes");
_Static_assert((int)EA__IPOPT_MAX_CPU_TIME == (int)Maximum_CpuTime_Exceeded, "Ipopt's codes");
_Static_assert((int)EA__IPOPT_INVALID_PROBLEM == (int)Invalid_Problem_Definition, "Ipopt's codes");
_Static_assert((int)EA__IPOPT_INVALID_OPTION == (int)Invalid_Option, "Ipopt's codes");
_Static_assert((int)EA__IPOPT_NO_MEMORY == (int)Insufficient_Memory, "Ipopt's codes");
_Static_assert((int)EA__IPOPT_INTERNAL_ERROR == (int)Internal_Error, "Ipopt's codes");

void ea__ipopt_free(ea__ipopt_problem_t ip) {
  if (ip) FreeIpoptProblem(ip);
}

const char *ea__ipopt_name(int s) {
  switch (s) {
  case Solve_Succeeded:
    return "Solve_Succeeded";
  case Solved_To_Acceptable_Level:
    return "Solved_To_Acceptable_Level";
  case Infeasible_Problem_Detected:
    return "Infeasible_Problem_Detected";
  case Search_Direction_Becomes_Too_Small:
    return "Search_Direction_Becomes_Too_Small";
  case Diverging_Iterates:
    return "Diverging_Iterates";
  case User_Requested_Stop:
    return "User_Requested_Stop (time limit)";
  case Feasible_Point_Found:
    return "Feasible_Point_Found";
  case Maximum_Iterations_Exceeded:
    return "Maximum_Iterations_Exceeded";
  case Restoration_Failed:
    return "Restoration_Failed";
  case Error_In_Step_Computation:
    return "Error_In_Step_Computation";
  case Maximum_CpuTime_Exceeded:
    return "Maximum_CpuTime_Exceeded";
  case Not_Enough_Degrees_Of_Freedom:
    return "Not_Enough_Degrees_Of_Freedom";
  case Invalid_Problem_Definition:
    return "Invalid_Problem_Definition";
  case Invalid_Option:
    return "Invalid_Option";
  case Invalid_Number_Detected:
    return "Invalid_Number_Detected";
  default:
    return "Ipopt_Internal_Error";
  }
}

void ea__ipopt_options(IpoptProblem ip, const ea_planner_settings_t *s, int hess_exact,
                       double bound_push) {
  AddIpoptStrOption(ip, "sb", "yes");
  AddIpoptIntOption(ip, "print_level", s->print_level);
  if (s->print_level >= 5) AddIpoptStrOption(ip, "print_timing_statistics", "yes");
  AddIpoptStrOption(ip, "linear_solver", "mumps");
  /* The max-transversal permutation only costs MUMPS analysis time on these KKT systems. */
  AddIpoptIntOption(ip, "mumps_permuting_scaling", 0);
  /* MUMPS ordering: AMD for every solve. SCOTCH draws on a process-global random state: a
   * plan depended on what the process had solved before (a study's CSV changed with the order
   * of its cases). AMD, AMF, PORD and METIS are deterministic. */
  AddIpoptIntOption(ip, "mumps_pivot_order", 0);
  /* Iterative refinement only when a solve's residual asks for it (Ipopt's default forces one
   * step per solve: a back solve and a residual each, for the same iterations). */
  AddIpoptIntOption(ip, "min_refinement_steps", 0);
  AddIpoptStrOption(ip, "hessian_approximation", hess_exact ? "exact" : "limited-memory");
  AddIpoptNumOption(ip, "tol", s->tol);
  AddIpoptNumOption(ip, "constr_viol_tol", s->constr_tol);
  /* L-BFGS stalls at a dual infeasibility of ~1e-5 on these problems: accept a plan whose
   * objective no longer moves, primal feasibility kept strict. */
  AddIpoptNumOption(ip, "acceptable_tol", fmax(1e-4, s->tol));
  AddIpoptIntOption(ip, "acceptable_iter", 8);
  AddIpoptNumOption(ip, "acceptable_constr_viol_tol", fmax(1e-9, s->constr_tol));
  AddIpoptNumOption(ip, "acceptable_obj_change_tol", 1e-8);
  AddIpoptIntOption(ip, "max_iter", s->max_iter);
  /* Ipopt relaxes bounds in its scaled space; the acceleration rows are scaled down by
   * ~1/h^2, so the default 1e-8 became ~1e-6 of a limit. A plan must hold its limits: no
   * relaxation. */
  AddIpoptNumOption(ip, "bound_relax_factor", 0.0);
  if (bound_push > 0.0) {
    AddIpoptNumOption(ip, "bound_push", bound_push);
    AddIpoptNumOption(ip, "bound_frac", bound_push);
  }
}

/* The barrier's start and the warm-start pushes for both transcriptions. After an update
 * (ea_planner_update, or bounds tightened for limits between knots) the shifted point is
 * near, not at, the new optimum: a barrier and pushes between those of an unchanged task and
 * a cold start (docs/planner.md, "Replanning a live planner"). */
void ea__ipopt_start_options(IpoptProblem ip, int warm, int updated) {
  AddIpoptStrOption(ip, "warm_start_init_point", warm ? "yes" : "no");
  const double mu = updated ? 1e-6 : warm ? 1e-7 : 0.1, push = updated ? 1e-5 : 1e-9;
  AddIpoptNumOption(ip, "mu_init", mu);
  /* no options file: a stray ipopt.opt in the working directory would override these and
   * change the plan */
  AddIpoptStrOption(ip, "option_file_name", "");
  if (!warm && !updated) return;
  AddIpoptNumOption(ip, "warm_start_bound_push", push);
  AddIpoptNumOption(ip, "warm_start_mult_bound_push", push);
  AddIpoptNumOption(ip, "warm_start_slack_bound_push", push);
}

void ea__ipopt_barrier_options(IpoptProblem ip, int mono, double mu_init, int mu_based_mult,
                               double barrier_tol_factor) {
  AddIpoptStrOption(ip, "mu_strategy", mono ? "monotone" : "adaptive");
  if (mu_init > 0.0) AddIpoptNumOption(ip, "mu_init", mu_init);
  AddIpoptStrOption(ip, "bound_mult_init_method", mu_based_mult ? "mu-based" : "constant");
  AddIpoptNumOption(ip, "barrier_tol_factor", barrier_tol_factor);
}

/* Count of derivative checker errors in Ipopt's output file (-1: unknown). */
int ea__deriv_errors(const char *path) {
  FILE *fp = fopen(path, "r");
  if (!fp) return -1;
  char line[512];
  int n = -1;
  while (fgets(line, sizeof line, fp)) {
    int k;
    if (strstr(line, "No errors detected by derivative checker")) n = 0;
    if (sscanf(line, "Derivative checker detected %d error", &k) == 1) n = k;
  }
  fclose(fp);
  return n;
}

void ea__deriv_test_options(IpoptProblem ip, int second, char tmpl[64]) {
  snprintf(tmpl, 64, "/tmp/ea_dercheck_XXXXXX");
  const int fd = mkstemp(tmpl);
  if (fd >= 0) {
    close(fd);
    OpenIpoptOutputFile(ip, tmpl, 5);
  } else {
    tmpl[0] = '\0';
  }
  AddIpoptStrOption(ip, "derivative_test", second ? "second-order" : "first-order");
  AddIpoptNumOption(ip, "derivative_test_perturbation", 1e-7);
  AddIpoptNumOption(ip, "derivative_test_tol", 1e-5);
}
