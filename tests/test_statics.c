#include "ea_model.h"
#include "ea_test.h"
int main(void) {
  ea_arm_t arm; ea_arm_default(&arm);
  ea_shooter_t *sh; ea_error_t e;
  if (ea_shooter_alloc(&arm, NULL, &sh, &e)) { printf("%s\n", e.msg); return 1; }
  for (double a = -60; a <= 10; a += 10) {
    ea_statics_solution_t sol;
    ea_status_t st = ea_statics_edge(sh, a*M_PI/180, NULL, NULL, &sol, &e);
    printf("alpha %g st %d %s T %g th0 %g k0 %g tip %g %g Lc %g it %d steps %d res %g wind %g\n", a, st, e.msg,
      sol.p[1], sol.p[2]*180/M_PI, sol.p[3], sol.tip[2], sol.tip[3], sol.cable_length, sol.iterations, sol.cont_steps, sol.residual, sol.winding);
  }
  for (int i = 0; i <= 6; ++i) {
    double b = i/6.0; double x = 0.3*b+0.3, y=-0.2;
    ea_statics_problem_t pr = ea_statics_problem_tip(x,y);
    ea_statics_solution_t sol;
    ea_status_t st = ea_statics_solve(sh, &pr, NULL, NULL, &sol, &e);
    printf("beta %g st %d T %g th0 %g k0 %g Lc %g alpha %g it %d steps %d\n", b, st, sol.p[1], sol.p[2]*180/M_PI, sol.p[3], sol.cable_length, sol.p[0]*180/M_PI, sol.iterations, sol.cont_steps);
  }
  ea_shooter_free(sh);
  return 0;
}
