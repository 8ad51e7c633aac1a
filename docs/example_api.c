/* The README's C API example, built with the project (target example_api)
 * and, by the test "install", against the installed library with plain
 * `cc -std=c11` through pkg-config and through find_package. The README shows
 * this file from its first include line on (docs/regenerate.sh checks it). */

#include "ea_model.h" /* model/: statics and FE */
#include <math.h>
#include <stdio.h>

int main(void) {
  ea_arm_t arm;
  ea_arm_default(&arm); /* paper, Tables 1 and 2 */
  ea_shooter_t *sh = NULL;
  ea_error_t err;
  if (ea_shooter_alloc(&arm, NULL, &sh, &err)) {
    fprintf(stderr, "%s\n", err.msg);
    return 1;
  }
  ea_load_t load = {ea_arm_tip_mass(&arm, ea_arm_payload_from_factor(&arm, 0.25))};
  ea_shooter_set_load(sh, &load); /* payload factor 0.25 (eq. 17) */

  /* Cable 0.45 m at -25 deg: solve g*(alpha, T, theta0, kappa0) = 0 on the
     physical branch (continued from the T = 0 outer edge). */
  const double deg = acos(-1.0) / 180; /* M_PI is not ISO C */
  ea_statics_problem_t pr = ea_statics_problem_cable(0.45, -25.0 * deg);
  ea_statics_solution_t sol;
  if (ea_statics_solve(sh, &pr, NULL, NULL, &sol, &err) != EA_OK) {
    fprintf(stderr, "%s\n", err.msg); /* not converged, or T < 0 */
    ea_shooter_free(sh);
    return 1;
  }
  printf("T = %.4f N, theta0 = %.4f rad, shoulder torque = %.4f N m (residual %.1e)\n",
         sol.p[EA_P_TENSION], sol.p[EA_P_THETA0], sol.shoulder_torque, sol.residual);

  /* The shooting map h (eq. 13) with exact sensitivities d x(L) / d p:
     the tip lies on the cable, 0.45 m from its root. */
  double xL[EA_NX], dxdp[EA_NX * EA_NP];
  const ea_status_t st = ea_shoot(sh, sol.p, xL, dxdp);
  ea_shooter_free(sh);
  const double Lc = hypot(xL[EA_X_X] - arm.x_c, xL[EA_X_Y] - arm.y_c);
  return st == EA_OK && fabs(Lc - 0.45) < 1e-9 ? 0 : 1;
}
