/* Finite element model: the geometrically exact beam element and the cable
 * element (paper sec. 3, 3.1). Formulas in docs/fe.md. */
#include "fe_impl.h"

#include <math.h>
#include <string.h>

/* Strain-displacement matrix of the element at a Gauss point: rows are the
 * variations of the axial strain G1, the shear strain G2 and the curvature K
 * with respect to the 9 element DOFs (x, y, theta of each node), given
 * cos/sin of the section rotation, the strains and the shape functions N
 * and their arclength derivatives dN. */
static void ea__fe_strain_B(double c, double s, double G1, double G2, const double N[3],
                            const double dN[3], double B[3][9]) {
  for (int a = 0; a < 3; ++a) {
    B[0][3 * a] = c * dN[a];
    B[0][3 * a + 1] = s * dN[a];
    B[0][3 * a + 2] = G2 * N[a];
    B[1][3 * a] = -s * dN[a];
    B[1][3 * a + 1] = c * dN[a];
    B[1][3 * a + 2] = -(1.0 + G1) * N[a];
    B[2][3 * a] = 0.0;
    B[2][3 * a + 1] = 0.0;
    B[2][3 * a + 2] = dN[a];
  }
}

/* Strains of the planar Reissner beam with a straight, unstrained reference:
 *   Gamma1 = x' cos(th) + y' sin(th) - 1   (axial)
 *   Gamma2 = -x' sin(th) + y' cos(th)      (shear)
 *   K      = th'                            (bending)
 * Resultants N = EA Gamma1, Q = GA Gamma2, M = EI K. Virtual work
 *   dW = int (N dGamma1 + Q dGamma2 + M dK) ds
 * gives the internal force; its linearization the material part B^T D B and
 * the geometric part (second variation of the strains times the resultants). */
double ea__fe_beam_element(const ea_fe_model_t *m, const double u[9], double fe[9], double *ke) {
  const double EA = m->arm.EA, GA = m->arm.GA_s, EI = m->arm.EI;
  const ea__fe_quad_t *qd = &m->quad_k;
  double W = 0.0;
  memset(fe, 0, 9 * sizeof(double));
  if (ke) memset(ke, 0, 81 * sizeof(double));
  for (int g = 0; g < qd->n; ++g) {
    const double *N = qd->N[g], *dN = qd->dN[g], w = qd->w[g];
    double xp = 0, yp = 0, th = 0, thp = 0;
    /* positions relative to the element's first node (sum dN = 0): keeps the
     * rounding of x', y' at eps h instead of eps |x|, which EA multiplies */
    for (int a = 1; a < 3; ++a) {
      xp += dN[a] * (u[3 * a] - u[0]);
      yp += dN[a] * (u[3 * a + 1] - u[1]);
    }
    for (int a = 0; a < 3; ++a) {
      th += N[a] * u[3 * a + 2];
      thp += dN[a] * u[3 * a + 2];
    }
    const double c = cos(th), s = sin(th);
    const double G1 = xp * c + yp * s - 1.0, G2 = -xp * s + yp * c, K = thp;
    const double Nf = EA * G1, Qf = GA * G2, Mf = EI * K;
    W += 0.5 * w * (EA * G1 * G1 + GA * G2 * G2 + EI * K * K);
    double B[3][9];
    ea__fe_strain_B(c, s, G1, G2, N, dN, B);
    for (int i = 0; i < 9; ++i)
      fe[i] += w * (B[0][i] * Nf + B[1][i] * Qf + B[2][i] * Mf);
    if (!ke) continue;
    for (int i = 0; i < 9; ++i)
      for (int j = 0; j < 9; ++j)
        ke[9 * i + j] +=
            w * (EA * B[0][i] * B[0][j] + GA * B[1][i] * B[1][j] + EI * B[2][i] * B[2][j]);
    /* geometric part */
    const double gx = -Nf * s - Qf * c, gy = Nf * c - Qf * s;
    const double gt = -Nf * (1.0 + G1) - Qf * G2;
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) {
        const double xa_tb = w * gx * dN[a] * N[b], ya_tb = w * gy * dN[a] * N[b];
        ke[9 * (3 * a) + 3 * b + 2] += xa_tb;
        ke[9 * (3 * b + 2) + 3 * a] += xa_tb;
        ke[9 * (3 * a + 1) + 3 * b + 2] += ya_tb;
        ke[9 * (3 * b + 2) + 3 * a + 1] += ya_tb;
        ke[9 * (3 * a + 2) + 3 * b + 2] += w * gt * N[a] * N[b];
      }
  }
  return W;
}

/* Cable from the tip r to the root c: l = |c - r|, e = (c - r) / l. The force
 * on the tip is T e. ACTIVE: T prescribed, potential T l (a force of fixed
 * magnitude aimed at a fixed point is conservative), load stiffness
 * -d(T e)/dr = T/l (I - e e^T). PASSIVE: T = EA_c (l - L0) / L0 (0 if slack),
 * potential EA_c (l - L0)^2 / (2 L0), stiffness EA_c/L0 e e^T + T/l (I - e e^T). */
double ea__fe_cable(const ea_fe_model_t *m, ea_fe_cable_phase_t phase, double value, double x,
                    double y, double *tension, double *length, double f[2], double kc[4]) {
  const double dx = m->arm.x_c - x, dy = m->arm.y_c - y;
  const double l = hypot(dx, dy);
  double T = 0.0, kt = 0.0, V = 0.0;
  if (phase == EA_FE_CABLE_ACTIVE) {
    T = value;
    V = T * l;
  } else if (phase == EA_FE_CABLE_PASSIVE && l > value) {
    kt = m->arm.EA_cable / value;
    T = kt * (l - value);
    V = 0.5 * kt * (l - value) * (l - value);
  }
  if (tension) *tension = T;
  if (length) *length = l;
  const double ex = (l > 0) ? dx / l : 0.0, ey = (l > 0) ? dy / l : 0.0;
  if (f) {
    f[0] = T * ex;
    f[1] = T * ey;
  }
  if (kc) {
    const double t = (l > 0) ? T / l : 0.0;
    kc[0] = kt * ex * ex + t * (1.0 - ex * ex);
    kc[1] = kc[2] = (kt - t) * ex * ey;
    kc[3] = kt * ey * ey + t * (1.0 - ey * ey);
  }
  return V;
}

/* Kelvin-Voigt (strain-rate) damping of the beam, per unit coefficient b:
 * sectional forces b (EA dGamma1/dt, GA dGamma2/dt, EI dK/dt). The strain
 * rates are B(u) ud (B = d strain / d u, as in the internal force), so the
 * damping force is fd = int B^T D B ud ds and its velocity derivative the
 * symmetric ce = int B^T D B ds (the material stiffness at u). The rates are
 * objective: a rigid motion (ud_x = -w y, ud_y = w x, ud_th = w, plus a
 * translation) gives B ud = 0 exactly, so rigid rotations are not damped.
 * The configuration derivative of fd (order b * strain rate, next to the
 * geometric stiffness) is not returned: see docs/fe.md. */
void ea__fe_beam_rate(const ea_fe_model_t *m, const double u[9], const double ud[9], double fd[9],
                      double *ce) {
  const double EA = m->arm.EA, GA = m->arm.GA_s, EI = m->arm.EI;
  const ea__fe_quad_t *qd = &m->quad_k;
  memset(fd, 0, 9 * sizeof(double));
  if (ce) memset(ce, 0, 81 * sizeof(double));
  for (int g = 0; g < qd->n; ++g) {
    const double *N = qd->N[g], *dN = qd->dN[g], w = qd->w[g];
    double xp = 0, yp = 0, th = 0;
    for (int a = 1; a < 3; ++a) {
      xp += dN[a] * (u[3 * a] - u[0]);
      yp += dN[a] * (u[3 * a + 1] - u[1]);
    }
    for (int a = 0; a < 3; ++a)
      th += N[a] * u[3 * a + 2];
    const double c = cos(th), s = sin(th);
    const double G1 = xp * c + yp * s - 1.0, G2 = -xp * s + yp * c;
    double B[3][9];
    ea__fe_strain_B(c, s, G1, G2, N, dN, B);
    double e1 = 0, e2 = 0, e3 = 0; /* strain rates */
    for (int i = 0; i < 9; ++i) {
      e1 += B[0][i] * ud[i];
      e2 += B[1][i] * ud[i];
      e3 += B[2][i] * ud[i];
    }
    const double n1 = w * EA * e1, n2 = w * GA * e2, n3 = w * EI * e3;
    for (int i = 0; i < 9; ++i)
      fd[i] += B[0][i] * n1 + B[1][i] * n2 + B[2][i] * n3;
    if (!ce) continue;
    for (int i = 0; i < 9; ++i)
      for (int j = 0; j < 9; ++j)
        ce[9 * i + j] +=
            w * (EA * B[0][i] * B[0][j] + GA * B[1][i] * B[1][j] + EI * B[2][i] * B[2][j]);
  }
}
