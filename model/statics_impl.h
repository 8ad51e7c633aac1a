/* Private: the shooter's workspace (statics_shoot.c, statics_solve.c). */
#ifndef EA_STATICS_IMPL_H
#define EA_STATICS_IMPL_H

#include "ea_statics.h"

#include <gsl/gsl_odeiv2.h>
#include <gsl/gsl_permutation.h>

/** Default fixed step count of rk8pd over [0, L], chosen by bench_statics. */
#define EA__DEFAULT_STEPS 12

struct ea_shooter {
  ea_arm_t arm;
  ea_shoot_settings_t set;
  ea_load_t load;
  double g;                    /* gravity in use (continuation scales it) */
  double inv_EI;               /* 1 / EI */
  double p[EA_NP];             /* arguments of the current integration */
  double cos_alpha, sin_alpha; /* of p[EA_P_ALPHA] */
  /* Index nc = number of sensitivity columns integrated (dim 4 + 4 nc). */
  gsl_odeiv2_system sys[EA_NP + 1];
  gsl_odeiv2_step *step[EA_NP + 1];  /* fixed-step schemes */
  gsl_odeiv2_driver *drv[EA_NP + 1]; /* adaptive schemes */
  int ncols_active, cols_active[EA_NP];
  gsl_odeiv2_driver *drv_shape; /* dense sampling of the centreline */
  double yerr[4 + 4 * EA_NP], dydt0[4 + 4 * EA_NP], dydt1[4 + 4 * EA_NP];
  gsl_permutation *perm; /* Newton's LU pivots */
  int cache_valid;       /* the last shot, remembered */
  unsigned cache_mask;   /* its sensitivity columns */
  double cache_p[EA_NP], cache_x[EA_NX], cache_S[EA_NX * EA_NP];
};

/** ea_shoot() integrating only the sensitivity columns in mask (bit j =
 *  parameter j); the other columns of dxdp are zero. */
ea_status_t ea__shoot_cols(ea_shooter_t *sh, const double p[EA_NP], double xL[EA_NX], double *dxdp,
                           unsigned mask);

/** Scale gravity by scale in [0, 1] (gravity continuation); 1 restores it. */
void ea__shooter_set_gscale(ea_shooter_t *sh, double scale);

#endif
