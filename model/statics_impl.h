/* Private: the shooter's workspace (statics_shoot.c, statics_solve.c). */
#ifndef EA_STATICS_IMPL_H
#define EA_STATICS_IMPL_H

#include "ea_model.h"

#include <gsl/gsl_odeiv2.h>

/** Default fixed step count of rk8pd over [0, L], chosen by bench_statics. */
#define EA__DEFAULT_STEPS 24

struct ea_shooter {
  ea_arm_t arm;
  ea_shoot_settings_t set;
  ea_load_t load;
  double g;         /* gravity in use (continuation scales it) */
  double p[EA_NP];  /* arguments of the current integration */
  gsl_odeiv2_system sys4, sys20;
  gsl_odeiv2_step *step4, *step20;     /* fixed-step schemes */
  gsl_odeiv2_driver *drv4, *drv20;     /* adaptive schemes */
  gsl_odeiv2_driver *drv_shape;        /* dense sampling of the centreline */
  double yerr[20], dydt0[20], dydt1[20];
};

/** Scale gravity by scale in [0, 1] (gravity continuation); 1 restores it. */
void ea__shooter_set_gscale(ea_shooter_t *sh, double scale);

#endif
