/* Ipopt: the problem of the knot transcription, its options, the names of its statuses. */
#include "plan_impl.h"
#include "plan_screen_impl.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The Ipopt problem with the planner's bounds, its rows of the next solve (engine/ipopt_screen.c) and
 * the options. Every Ipopt solve creates it (ea__solve_ipopt: the rows it sees change from
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
    const ea__screen_nlp_t nlp = {.n = pl->n,
                                  .m = pl->m,
                                  .nnz_j = pl->nnz,
                                  .nnz_h = pl->hess_exact ? pl->nnz_h : 0,
                                  .gl = pl->gl,
                                  .gu = pl->gu,
                                  .jrow = pl->irow,
                                  .jcol = pl->jcol,
                                  .f = ea__knot_cb_f,
                                  .g = ea__knot_cb_g,
                                  .grad_f = ea__knot_cb_grad_f,
                                  .jac = ea__knot_cb_jac,
                                  .h = ea__knot_cb_h,
                                  .iter = ea__knot_cb_iter,
                                  .ud = pl};
    if (!(pl->scr = ea__screen_alloc(&nlp))) return EA_ERR_NOMEM;
  }
  pl->ip = ea__screen_problem(pl->scr, pl->xl, pl->xu);
  if (!pl->ip) return EA_ERR_BACKEND;
  AddIpoptStrOption(pl->ip, "sb", "yes");
  AddIpoptIntOption(pl->ip, "print_level", t->solver.print_level);
  AddIpoptStrOption(pl->ip, "linear_solver", "mumps");
  /* The max-transversal permutation only costs MUMPS analysis time on these
   * KKT systems (8 -> 2 ms at 100 knots); the ordering is chosen per solve
   * (ea__plan_solve_once). */
  AddIpoptIntOption(pl->ip, "mumps_permuting_scaling", 0);
  /* Iterative refinement only when a solve's residual asks for it (Ipopt's default forces
   * one step per solve: a back solve and a residual each): the same iterations on
   * bench_plan, bench_dyn and every test, plans equal to 1e-9 relative; the paper line's
   * cold solve 28.4 -> 24.7 ms (bench_plan, medians of 7), the at-rest one ~3 % */
  AddIpoptIntOption(pl->ip, "min_refinement_steps", 0);
  AddIpoptStrOption(pl->ip, "hessian_approximation", pl->hess_exact ? "exact" : "limited-memory");
  AddIpoptNumOption(pl->ip, "tol", t->solver.tol);
  AddIpoptNumOption(pl->ip, "constr_viol_tol", t->solver.constr_tol);
  /* L-BFGS stalls at a dual infeasibility of ~1e-5 on these problems: accept
   * a plan whose objective no longer moves, primal feasibility kept strict. */
  AddIpoptNumOption(pl->ip, "acceptable_tol", fmax(1e-4, t->solver.tol));
  AddIpoptIntOption(pl->ip, "acceptable_iter", 8);
  AddIpoptNumOption(pl->ip, "acceptable_constr_viol_tol", fmax(1e-9, t->solver.constr_tol));
  AddIpoptNumOption(pl->ip, "acceptable_obj_change_tol", 1e-8);
  AddIpoptIntOption(pl->ip, "max_iter", t->solver.max_iter);
  /* Ipopt relaxes bounds in its scaled space; the acceleration rows are
   * scaled down by ~1/h^2, so the default 1e-8 became ~1e-6 of a limit. A
   * plan must hold its limits: no relaxation. */
  AddIpoptNumOption(pl->ip, "bound_relax_factor", 0.0);
  return EA_OK;
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
