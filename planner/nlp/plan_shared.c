/* What both transcriptions (plan_solve.c: knots, transcribe/path_*.c: the path coordinate) and the
 * row families (knot_rows.c, vib_rows.c, dyn_rows.c) share: the duration variable, the end
 * accelerations of an interval's cubic Hermite, the tip from the actuator coordinates, the
 * (L_c, alpha) box a task covers, the Ipopt barrier start and its derivative checker, the own
 * interior point's settings. Calls nothing above it. */
#include "plan_impl.h"
#include "plan_ipm_impl.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

double ea__plan_tf(const ea_planner_t *pl, const double *x) {
  return pl->has_tf ? x[EA__ITF(pl)] : pl->tf_fixed;
}

int ea__plan_solve3(double A[3][3], const double b[3], double x[3]) {
  const double det = A[0][0] * (A[1][1] * A[2][2] - A[1][2] * A[2][1]) -
                     A[0][1] * (A[1][0] * A[2][2] - A[1][2] * A[2][0]) +
                     A[0][2] * (A[1][0] * A[2][1] - A[1][1] * A[2][0]);
  if (!(fabs(det) > 1e-300)) return -1;
  for (int c = 0; c < 3; ++c) {
    double M[3][3];
    memcpy(M, A, sizeof M);
    for (int r = 0; r < 3; ++r)
      M[r][c] = b[r];
    x[c] = (M[0][0] * (M[1][1] * M[2][2] - M[1][2] * M[2][1]) -
            M[0][1] * (M[1][0] * M[2][2] - M[1][2] * M[2][0]) +
            M[0][2] * (M[1][0] * M[2][1] - M[1][1] * M[2][0])) /
           det;
  }
  return 0;
}

int ea__plan_statics_slope(const double *S, double L, double alpha, double dL, double dalpha,
                           double out[3]) {
  /* G_u du + G_L dL + G_a da = 0, u = (T, theta0, kappa0) */
  const int xi[3] = {EA_X_KAPPA, EA_X_X, EA_X_Y};
  const double ca = cos(alpha), sa = sin(alpha);
  const double gL[3] = {0.0, -ca, -sa};
  const double ga[3] = {S[EA_X_KAPPA * EA_NP + EA_P_ALPHA], S[EA_X_X * EA_NP + EA_P_ALPHA] + L * sa,
                        S[EA_X_Y * EA_NP + EA_P_ALPHA] - L * ca};
  double A[3][3], rhs[3];
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c)
      A[r][c] = S[xi[r] * EA_NP + 1 + c];
    rhs[r] = -(gL[r] * dL + ga[r] * dalpha);
  }
  return ea__plan_solve3(A, rhs, out);
}

void ea__plan_hermite_acc(double q0, double q1, double v0, double v1, double h, double a[2],
                          double ga[2][5]) {
  const double dq = q1 - q0, ih = 1.0 / h, ih2 = ih * ih;
  a[0] = 6.0 * dq * ih2 - (4.0 * v0 + 2.0 * v1) * ih;
  a[1] = -6.0 * dq * ih2 + (2.0 * v0 + 4.0 * v1) * ih;
  if (!ga) return;
  ga[0][0] = -6.0 * ih2;
  ga[0][1] = 6.0 * ih2;
  ga[0][2] = -4.0 * ih;
  ga[0][3] = -2.0 * ih;
  ga[0][4] = -12.0 * dq * ih2 * ih + (4.0 * v0 + 2.0 * v1) * ih2;
  ga[1][0] = 6.0 * ih2;
  ga[1][1] = -6.0 * ih2;
  ga[1][2] = 2.0 * ih;
  ga[1][3] = 4.0 * ih;
  ga[1][4] = 12.0 * dq * ih2 * ih - (2.0 * v0 + 4.0 * v1) * ih2;
}

void ea__plan_tip3(const ea_planner_t *pl, double Lc, double al, double b, double P[3],
                   double dP[3][3]) {
  const ea_arm_t *arm = &pl->task.arm;
  const double ca = cos(al), sa = sin(al), cb = cos(b), sb = sin(b);
  const double X = arm->x_c + Lc * ca, Y = arm->y_c + Lc * sa;
  P[0] = X * cb;
  P[1] = X * sb;
  P[2] = Y;
  if (!dP) return;
  /* dP[i][j]: d P_i / d (L_c, alpha, base)_j */
  dP[0][0] = ca * cb;
  dP[0][1] = -Lc * sa * cb;
  dP[0][2] = -X * sb;
  dP[1][0] = ca * sb;
  dP[1][1] = -Lc * sa * sb;
  dP[1][2] = X * cb;
  dP[2][0] = sa;
  dP[2][1] = Lc * ca;
  dP[2][2] = 0.0;
}

static const ea_task_point_t *ea__vpt(const ea_task_t *t, int j) {
  return j == 0 ? &t->start : j <= t->n_via ? &t->via[j - 1] : &t->goal;
}

void ea__plan_box(const ea_planner_t *pl, double box[4]) {
  const ea_task_t *t = &pl->task;
  const ea_arm_t *arm = &t->arm;
  box[0] = box[2] = INFINITY;
  box[1] = box[3] = -INFINITY;
  const int np = t->n_via + 2, ns = 64;
  for (int j = 0; j + 1 < np; ++j) {
    const ea_task_point_t *a = ea__vpt(t, j), *b = ea__vpt(t, j + 1);
    for (int i = 0; i <= ns; ++i) {
      const double u = (double)i / ns;
      double L, al;
      if (t->path == EA_TASK_PATH_FREE) {
        L = a->cable_length + u * (b->cable_length - a->cable_length);
        al = a->cable_angle + u * (b->cable_angle - a->cable_angle);
      } else {
        double PA[3], PB[3];
        ea__plan_tip3(pl, a->cable_length, a->cable_angle, a->base_angle, PA, NULL);
        ea__plan_tip3(pl, b->cable_length, b->cable_angle, b->base_angle, PB, NULL);
        double P[3];
        for (int c = 0; c < 3; ++c)
          P[c] = PA[c] + u * (PB[c] - PA[c]);
        const double r = hypot(P[0], P[1]) - arm->x_c, z = P[2] - arm->y_c;
        L = hypot(r, z);
        al = atan2(z, r);
      }
      box[0] = fmin(box[0], L);
      box[1] = fmax(box[1], L);
      box[2] = fmin(box[2], al);
      box[3] = fmax(box[3], al);
    }
  }
  const double mL = fmax(0.15 * (box[1] - box[0]), 0.02), ma = fmax(0.15 * (box[3] - box[2]), 0.04);
  box[0] = fmax(box[0] - mL, t->limits.cable_length_min);
  box[1] = fmin(box[1] + mL, t->limits.cable_length_max);
  box[2] = fmax(box[2] - ma, -M_PI);
  box[3] = fmin(box[3] + ma, M_PI);
}

void ea__plan_ipm_opt(const ea_planner_t *pl, double mu_init, double push_s,
                      struct ea__ipm_opt *o) {
  const ea_planner_settings_t *s = &pl->task.solver;
  *o = (ea__ipm_opt_t){.tol = s->tol,
                       .ptol = fmax(1e-9, s->constr_tol),
                       .mu_init = mu_init,
                       .push = 1e-6, /* Ipopt's bound_push and bound_frac as set for it */
                       .push_s = push_s,
                       .max_iter = s->max_iter < 40 ? s->max_iter : 40,
                       .stop = ea__plan_time_up,
                       .acc_tol = fmax(1e-4, s->tol),
                       .acc_obj = 1e-8,
                       .acc_iter = 8};
}
