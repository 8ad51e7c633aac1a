/* The reduced model at large modal deflection (docs/fe.md, "At large modal deflection"; the
 * candidate the bench calls CMIP).
 *
 * The linear model (fe_rom.c) moves the arm as u = u_s(q) + Phi e about the static state u_s of
 * the actuator coordinates q = (L_c, alpha). At tens of millimetres of modal tip deflection it
 * misses what the other degrees of freedom do. Here every degree of freedom but the two modes is
 * condensed statically:
 *   u = u_s(q) + Phi(q) e + y,  y = Theta e e / 2 + ...,  Phi^T M y = 0,
 * with Theta the static modal derivatives (Idelsohn & Cardona 1985) M-orthogonal to the modes.
 * The modal equations then hold
 *   - the static condensed force lambda(e) (the modal stiffness to all orders: a Newton solve of
 *     the FE with the modal amplitudes held), fitted at each sample as a polynomial of degree 8
 *     in e1 plus a slope in e2 from the condensation's own tangent (dlambda/de = A^-1);
 *   - the base load on (Phi + Theta e) (the linear table's B, C and E here);
 *   - the inertia of y: modal mass I + V^T M V, V = Theta e, and its convective force;
 *   - the moving modes (G, D) and the manifold moving with them (R: the gauge Phi^T M y = 0 gives
 *     Phi^T M y'' = -Phi''^T M y - 2 Phi'^T M y').
 * Coefficients are computed at points of a path in (L_c, alpha) (a 9-point stencil of FE static
 * solutions and eigen-solves at each, then the condensation walked over 17 Chebyshev nodes) and
 * interpolated linearly along it. The modes take the signs of the linear table's, so that the
 * modal coordinates are the planner's. */
#include "ea_fe.h"
#include "ea_statics.h"
#include "fe_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum {
  NK = EA_ROMNL_MODES,
  PDEG = 8,      /* degree of the condensed force's fit in e1 */
  PN = PDEG + 1, /* its coefficients */
  PG = 17,       /* its Chebyshev nodes */
  NVEC = 1 + NK  /* vectors kept per sample: u_s, Phi_1, Phi_2 */
};

static const double RNL_HL = 2e-3;    /* [m] stencil step in L_c */
static const double RNL_HA = 4e-3;    /* [rad] stencil step in alpha */
static const double RNL_TIP1 = 0.15;  /* [m] mode 1's tip amplitude the fit covers (+-) */
static const double RNL_WALK = 0.03;  /* [m] largest tip step between condensations (each starts
                                         from the last one's tangent) */
static const double RNL_ASCALE = 0.5; /* [m/rad] alpha's weight in the path's distance */

/* The coefficients at one sample. Index p of a pair jk = 11, 12, 22 is j + k. */
typedef struct {
  double G[NK][NK][2];  /* Phi_i^T M dPhi_j/dq_a */
  double D[NK][NK][3];  /* Phi_i^T M d2Phi_j/dq_a dq_b (LL, La, aa) */
  double E[3][5];       /* Theta_p^T M (du_s/dL, du_s/da, d2u_s/dL2, d2u_s/dLda, d2u_s/da2) */
  double R[3][NK][5];   /* Theta_p^T M (the same derivatives of Phi_j) */
  double W[3][3];       /* Theta_p^T M Theta_q */
  double P[2 * NK][PN]; /* lambda_i(e1, 0), dlambda_i/de2(e1, 0): polynomials in e1 / esc */
  double esc;           /* [sqrt(kg) m] the fit's range of e1 */
} rnl_coef_t;

struct ea_romnl {
  ea_fe_model_t *m;
  ea_shooter_t *sh;
  int nd, nf;
  double guess[EA_NP];
  int have_guess;
  /* the samples */
  int ns, cap;
  double *q;     /* 2 ns: (L_c, alpha) */
  rnl_coef_t *c; /* ns */
  double *vec;   /* per sample NVEC vectors of nd */
  double *L0;    /* [m] passive cable rest length at each sample */
  ea_romnl_info_t info;
  /* work: one block (rnl_layout) */
  double *work;
  double *ph9;                  /* 9 stencil points x NK modes x nd */
  double *u9;                   /* 9 x nd static states */
  double *th;                   /* 3 x nd modal derivatives */
  double *d1, *w1;              /* nd each */
  double *Kb;                   /* LDS x nd */
  double *f, *f0, *x, *y, *Mph; /* nd, nd, nd, nd, NK nd */
  double *b;                    /* (NK + 1) nf */
  double lam0[NK];
  double dlam[NK][NK];
  double *yt;        /* NK x nd: dy/de at the last condensation (its predictor) */
  double e_last[NK]; /* the e of the last condensation */
  int have_tan;      /* yt and dlam hold */
};

static double dotM(const ea_romnl_t *r, const double *a, const double *b) {
  double *w = r->w1;
  memset(w, 0, sizeof(double) * (size_t)r->nd);
  ea__fe_band_gemv(r->m, 1.0, r->m->Mb, b, w);
  double s = 0.0;
  for (int i = 0; i < r->nd; ++i)
    s += a[i] * w[i];
  return s;
}

void ea_romnl_free(ea_romnl_t *r) {
  if (!r) return;
  ea_fe_model_free(r->m);
  ea_shooter_free(r->sh);
  free(r->q);
  free(r->c);
  free(r->vec);
  free(r->L0);
  free(r->work);
  free(r);
}

/* The work vectors in one block from base (NULL: only count); returns its length in doubles. */
static size_t rnl_layout(ea_romnl_t *r, double *base) {
  const size_t nd = (size_t)r->nd;
  size_t o = 0;
#define RNL_TAKE(field, count) (r->field = base ? base + o : NULL, o += (count))
  RNL_TAKE(ph9, 9 * NK * nd);
  RNL_TAKE(u9, 9 * nd);
  RNL_TAKE(th, 3 * nd);
  RNL_TAKE(d1, nd);
  RNL_TAKE(w1, nd);
  RNL_TAKE(Kb, EA__FE_LDS * nd);
  RNL_TAKE(f, nd);
  RNL_TAKE(f0, nd);
  RNL_TAKE(x, nd);
  RNL_TAKE(y, nd);
  RNL_TAKE(Mph, NK * nd);
  RNL_TAKE(yt, NK * nd);
  RNL_TAKE(b, (NK + 1) * (size_t)r->nf);
#undef RNL_TAKE
  return o;
}

ea_status_t ea_romnl_alloc(const ea_arm_t *arm, double tip_mass, int elements, ea_romnl_t **out,
                           ea_error_t *err) {
  if (!arm || !out || !(tip_mass >= 0.0))
    return ea_error_set(err, EA_ERR_ARG, "nonlinear reduced model: bad argument");
  *out = NULL;
  ea_romnl_t *r = calloc(1, sizeof *r);
  if (!r) return ea_error_set(err, EA_ERR_NOMEM, "nonlinear reduced model: out of memory");
  ea_fe_settings_t fs;
  ea_fe_settings_default(&fs);
  if (elements > 0) fs.elements = elements;
  fs.modes = NK + 1;
  fs.static_hold_tip = 1;
  fs.newton_tol = 1e-13;
  const ea_load_t load = {tip_mass};
  ea_status_t st = ea_shooter_alloc(arm, NULL, &r->sh, err);
  if (!st) {
    ea_shooter_set_load(r->sh, &load);
    st = ea_fe_model_alloc(arm, &fs, &r->m, err);
  }
  if (!st) st = ea_fe_model_set_load(r->m, &load);
  if (st) {
    ea_romnl_free(r);
    return st;
  }
  const int nd = 3 * ea_fe_model_nodes(r->m);
  r->nd = nd;
  r->nf = nd - 3;
  r->work = calloc(rnl_layout(r, NULL), sizeof(double));
  if (!r->work) {
    ea_romnl_free(r);
    return ea_error_set(err, EA_ERR_NOMEM, "nonlinear reduced model: out of memory");
  }
  rnl_layout(r, r->work);
  *out = r;
  return EA_OK;
}

/* The FE static state u and the NK modes phi (mass-normalised; the sign of ref's modes where ref
 * is given) at (L_c, alpha). 0 on success. */
static int rnl_point(ea_romnl_t *r, double Lc, double al, double *u, double *phi,
                     const double *ref) {
  const ea_statics_problem_t pr = ea_statics_problem_cable(Lc, al);
  ea_statics_solution_t sol;
  if (ea_statics_solve(r->sh, &pr, NULL, r->have_guess ? r->guess : NULL, &sol, NULL) &&
      ea_statics_solve(r->sh, &pr, NULL, NULL, &sol, NULL))
    return 1;
  memcpy(r->guess, sol.p, sizeof r->guess);
  r->have_guess = 1;
  if (ea_fe_static_solve(r->m, r->sh, &sol, NULL, NULL)) return 1;
  ea_fe_get_state(r->m, u, NULL);
  ea_fe_modes_info_t mi;
  if (ea_fe_modes(r->m, &mi, NULL) || mi.modes < NK) return 1;
  const int nd = r->nd;
  for (int k = 0; k < NK; ++k) {
    double *pk = phi + (size_t)k * nd;
    if (ea_fe_mode_shape(r->m, k, pk)) return 1;
    double s = 1.0 / sqrt(dotM(r, pk, pk));
    if (ref && dotM(r, pk, ref + (size_t)k * nd) < 0) s = -s;
    for (int i = 0; i < nd; ++i)
      pk[i] *= s;
  }
  return 0;
}

/* Static modal derivatives at the static state u (passive cable at its rest length L0):
 * K Theta_jk = -d2f/de_j de_k (central differences of a 2 mm tip step), M-orthogonalised to
 * the modes; into r->th (3 x nd). */
static int rnl_modal_derivatives(ea_romnl_t *r, const double *u, const double *phi, double L0) {
  const int nd = r->nd, nf = r->nf;
  const double h = 0.002 / hypot(phi[nd - 3], phi[nd - 2]);
  double *d2 = r->d1, *x = r->x, *f = r->f, *b = r->b;
  memset(r->Kb, 0, sizeof(double) * (size_t)nd * EA__FE_LDS);
  ea__fe_assemble(r->m, u, EA_FE_CABLE_PASSIVE, L0, f, r->Kb);
  static const int pr[3][2] = {{0, 0}, {0, 1}, {1, 1}};
  static const int sg[4][3] = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
  for (int p = 0; p < 3; ++p) {
    const double *pj = phi + (size_t)pr[p][0] * nd, *pk = phi + (size_t)pr[p][1] * nd;
    memset(d2, 0, sizeof(double) * (size_t)nd);
    for (int q = 0; q < 4; ++q) {
      for (int i = 0; i < nd; ++i)
        x[i] = u[i] + h * (sg[q][0] * pj[i] + sg[q][1] * pk[i]);
      ea__fe_assemble(r->m, x, EA_FE_CABLE_PASSIVE, L0, f, NULL);
      for (int i = 0; i < nd; ++i)
        d2[i] += sg[q][2] * f[i] / (4 * h * h);
    }
    for (int i = 0; i < nf; ++i)
      b[(size_t)p * nf + i] = -d2[3 + i];
  }
  if (ea__fe_factor_free(r->m, r->Kb) || ea__fe_solve_factored(r->m, b, 3)) return 1;
  for (int p = 0; p < 3; ++p) {
    double *t = r->th + (size_t)p * nd;
    t[0] = t[1] = t[2] = 0.0;
    memcpy(t + 3, b + (size_t)p * nf, sizeof(double) * (size_t)nf);
    for (int i = 0; i < NK; ++i) {
      const double pm = dotM(r, phi + (size_t)i * nd, t);
      for (int k = 0; k < nd; ++k)
        t[k] -= pm * phi[(size_t)i * nd + k];
    }
  }
  return 0;
}

/* The stencil's derivative comp (dL, da, dLL, dLa, daa) of the field at offset off (stride st
 * doubles between stencil points) into out (nd). Stencil point k: L + (k % 3 - 1) hL,
 * alpha + (k / 3 - 1) ha. */
static void rnl_stencil(const double *f, size_t st, int nd, int comp, double *out) {
#define F9(k) f[(size_t)(k)*st + (size_t)x]
  for (int x = 0; x < nd; ++x) {
    switch (comp) {
    case 0:
      out[x] = (F9(5) - F9(3)) / (2 * RNL_HL);
      break;
    case 1:
      out[x] = (F9(7) - F9(1)) / (2 * RNL_HA);
      break;
    case 2:
      out[x] = (F9(5) - 2 * F9(4) + F9(3)) / (RNL_HL * RNL_HL);
      break;
    case 3:
      out[x] = (F9(8) - F9(6) - F9(2) + F9(0)) / (4 * RNL_HL * RNL_HA);
      break;
    default:
      out[x] = (F9(7) - 2 * F9(4) + F9(1)) / (RNL_HA * RNL_HA);
      break;
    }
  }
#undef F9
}

/* The static condensed force at sample s: y (Phi^T M y = 0) and lambda with
 *   f(u_s + Phi e + y) - f(u_s) = M Phi lambda   (free rows)
 * by Newton from the last call's (y, lambda) (r->y, r->lam0), steps limited to 5 mm / 5 mrad;
 * lambda into lam, dlambda/de = A^-1 into r->dlam. 0 on success. */
static int rnl_condense(ea_romnl_t *r, int s, const double e[NK], double lam[NK]) {
  const int nd = r->nd, nf = r->nf;
  const double *us = r->vec + (size_t)s * NVEC * nd, *ph = us + nd;
  const double L0 = r->L0[s];
  double *x = r->x, *f = r->f, *f0 = r->f0, *y = r->y, *Mph = r->Mph, *b = r->b, *Kb = r->Kb;
  ea__fe_assemble(r->m, us, EA_FE_CABLE_PASSIVE, L0, f0, NULL);
  ++r->info.condensations;
  if (r->have_tan) { /* the tangent's predictor from the last condensation */
    const double de[NK] = {e[0] - r->e_last[0], e[1] - r->e_last[1]};
    for (int k = 3; k < nd; ++k)
      y[k] += r->yt[k] * de[0] + r->yt[(size_t)nd + k] * de[1];
    for (int i = 0; i < NK; ++i)
      r->lam0[i] += r->dlam[i][0] * de[0] + r->dlam[i][1] * de[1];
  }
  for (int k = 0; k < NK; ++k)
    lam[k] = r->lam0[k];
  double A[NK][NK];
  int conv = 0;
  for (int it = 0; it < 80 && !conv; ++it) {
    for (int i = 0; i < nd; ++i) {
      x[i] = us[i] + y[i];
      for (int k = 0; k < NK; ++k)
        x[i] += ph[(size_t)k * nd + i] * e[k];
    }
    memset(Kb, 0, sizeof(double) * (size_t)nd * EA__FE_LDS);
    ea__fe_assemble(r->m, x, EA_FE_CABLE_PASSIVE, L0, f, Kb);
    for (int i = 3; i < nd; ++i) {
      double R = f[i] - f0[i];
      for (int k = 0; k < NK; ++k) {
        R -= Mph[(size_t)k * nd + i] * lam[k];
        b[(size_t)(k + 1) * nf + (i - 3)] = Mph[(size_t)k * nd + i];
      }
      b[i - 3] = R;
    }
    ++r->info.factorizations;
    if (ea__fe_factor_free(r->m, Kb) || ea__fe_solve_factored(r->m, b, NK + 1)) return 1;
    /* dy = -z + Z dl with Z = K^-1 M Phi; Phi^T M dy = -Phi^T M y gives A dl = Phi^T M (z - y) */
    double rhs[NK];
    for (int i = 0; i < NK; ++i) {
      rhs[i] = 0.0;
      for (int k = 3; k < nd; ++k)
        rhs[i] += Mph[(size_t)i * nd + k] * (b[k - 3] - y[k]);
      for (int j = 0; j < NK; ++j) {
        A[i][j] = 0.0;
        for (int k = 3; k < nd; ++k)
          A[i][j] += Mph[(size_t)i * nd + k] * b[(size_t)(j + 1) * nf + (k - 3)];
      }
    }
    const double det = A[0][0] * A[1][1] - A[0][1] * A[1][0];
    if (!(fabs(det) > 0.0)) return 1;
    const double dl[NK] = {(rhs[0] * A[1][1] - rhs[1] * A[0][1]) / det,
                           (A[0][0] * rhs[1] - A[1][0] * rhs[0]) / det};
    double dmax = 0.0;
    for (int k = 3; k < nd; ++k) {
      double dy = -b[k - 3];
      for (int j = 0; j < NK; ++j)
        dy += b[(size_t)(j + 1) * nf + (k - 3)] * dl[j];
      dmax = fmax(dmax, fabs(dy));
    }
    const double sc = dmax > 5e-3 ? 5e-3 / dmax : 1.0;
    for (int k = 3; k < nd; ++k) {
      double dy = -b[k - 3];
      for (int j = 0; j < NK; ++j)
        dy += b[(size_t)(j + 1) * nf + (k - 3)] * dl[j];
      y[k] += sc * dy;
    }
    for (int k = 0; k < NK; ++k)
      lam[k] += sc * dl[k];
    conv = sc == 1.0 && dmax < 1e-10;
  }
  if (!conv || !isfinite(lam[0]) || !isfinite(lam[1])) {
    r->have_tan = 0;
    return 1;
  }
  memcpy(r->lam0, lam, sizeof r->lam0);
  /* the tangent of the condensation (the last Newton step's factors): K (Phi + dy/de) =
   * M Phi dlambda/de and Phi^T M dy/de = 0 give dlambda/de = A^-1 and dy/de = Z A^-1 - Phi,
   * Z = K^-1 M Phi */
  const double det = A[0][0] * A[1][1] - A[0][1] * A[1][0];
  r->dlam[0][0] = A[1][1] / det;
  r->dlam[0][1] = -A[0][1] / det;
  r->dlam[1][0] = -A[1][0] / det;
  r->dlam[1][1] = A[0][0] / det;
  for (int j = 0; j < NK; ++j) {
    double *t = r->yt + (size_t)j * nd;
    t[0] = t[1] = t[2] = 0.0;
    for (int k = 3; k < nd; ++k)
      t[k] = b[(size_t)1 * nf + (k - 3)] * r->dlam[0][j] +
             b[(size_t)2 * nf + (k - 3)] * r->dlam[1][j] - ph[(size_t)j * nd + k];
  }
  r->e_last[0] = e[0];
  r->e_last[1] = e[1];
  r->have_tan = 1;
  return 0;
}

static void rnl_restart(ea_romnl_t *r) {
  memset(r->y, 0, sizeof(double) * (size_t)r->nd);
  r->lam0[0] = r->lam0[1] = 0.0;
  r->have_tan = 0;
}

static void rnl_pbasis(double x, double *b) {
  b[0] = 1.0;
  for (int d = 1; d < PN; ++d)
    b[d] = b[d - 1] * x;
}

/* The condensed force's fit at sample s: lambda_i(e1, 0) and dlambda_i/de2(e1, 0) on PG
 * Chebyshev nodes in [-esc, esc] (esc: RNL_TIP1 of mode 1's tip), walked from the middle out in
 * tip steps of at most RNL_WALK; a node beyond a fold of the condensation ends that side (the fit
 * extrapolates); least squares of degree PDEG by Cholesky of the normal equations. */
static int rnl_fit(ea_romnl_t *r, int s) {
  const int nd = r->nd;
  rnl_coef_t *c = &r->c[s];
  const double *ph = r->vec + ((size_t)s * NVEC + 1) * nd;
  const double tn = hypot(ph[nd - 3], ph[nd - 2]);
  c->esc = RNL_TIP1 / tn;
  double xs[PG], lg[PG][2 * NK];
  int have[PG] = {0}, ng = 0, stop = 0;
  int ord[PG], no = 0;
  for (int i = PG / 2; i < PG; ++i)
    ord[no++] = i;
  for (int i = PG / 2 - 1; i >= 0; --i)
    ord[no++] = i;
  rnl_restart(r);
  double ecur = 0.0;
  for (int oi = 0; oi < no; ++oi) {
    const int i = ord[oi], side = oi < PG / 2 + 1 ? 1 : 2;
    if (stop & side) continue;
    if (oi == PG / 2 + 1) { /* back to the middle from the static state */
      rnl_restart(r);
      ecur = 0.0;
    }
    const double xn = cos(M_PI * (i + 0.5) / PG), e1 = xn * c->esc;
    int nst = (int)ceil(fabs(e1 - ecur) * tn / RNL_WALK);
    nst = nst < 1 ? 1 : nst;
    double lam[NK];
    int bad = 0;
    for (int st = 1; st <= nst && !bad; ++st) {
      const double es[NK] = {ecur + (e1 - ecur) * st / nst, 0.0};
      bad = rnl_condense(r, s, es, lam);
    }
    ecur = e1;
    if (bad) {
      stop |= side;
      ++r->info.nodes_dropped;
      continue;
    }
    have[i] = 1;
    ++ng;
    xs[i] = xn;
    for (int k = 0; k < NK; ++k) {
      lg[i][k] = lam[k];
      lg[i][NK + k] = r->dlam[k][1];
    }
  }
  rnl_restart(r);
  if (ng < PN + 2) return 1;
  double A[PN][PN] = {{0}}, rhs[2 * NK][PN] = {{0}};
  for (int g = 0; g < PG; ++g) {
    if (!have[g]) continue;
    double bb[PN];
    rnl_pbasis(xs[g], bb);
    for (int a = 0; a < PN; ++a) {
      for (int q = 0; q < PN; ++q)
        A[a][q] += bb[a] * bb[q];
      for (int k = 0; k < 2 * NK; ++k)
        rhs[k][a] += bb[a] * lg[g][k];
    }
  }
  double Lc[PN][PN] = {{0}};
  for (int j = 0; j < PN; ++j) {
    double d = A[j][j];
    for (int k = 0; k < j; ++k)
      d -= Lc[j][k] * Lc[j][k];
    if (!(d > 0.0)) return 1;
    Lc[j][j] = sqrt(d);
    for (int i = j + 1; i < PN; ++i) {
      double v = A[i][j];
      for (int k = 0; k < j; ++k)
        v -= Lc[i][k] * Lc[j][k];
      Lc[i][j] = v / Lc[j][j];
    }
  }
  for (int k = 0; k < 2 * NK; ++k) {
    double w[PN];
    for (int i = 0; i < PN; ++i) {
      double v = rhs[k][i];
      for (int q = 0; q < i; ++q)
        v -= Lc[i][q] * w[q];
      w[i] = v / Lc[i][i];
    }
    for (int i = PN - 1; i >= 0; --i) {
      double v = w[i];
      for (int q = i + 1; q < PN; ++q)
        v -= Lc[q][i] * c->P[k][q];
      c->P[k][i] = v / Lc[i][i];
    }
    if (k >= NK) continue;
    double mx = 0.0, er = 0.0;
    for (int g = 0; g < PG; ++g) {
      if (!have[g]) continue;
      double bb[PN], v = 0.0;
      rnl_pbasis(xs[g], bb);
      for (int q = 0; q < PN; ++q)
        v += bb[q] * c->P[k][q];
      mx = fmax(mx, fabs(lg[g][k]));
      er = fmax(er, fabs(v - lg[g][k]));
    }
    if (mx > 0.0) r->info.fit_error = fmax(r->info.fit_error, er / mx);
  }
  return 0;
}

/* The coefficients at sample s, configuration q; ref: the modes of the previous sample (NULL: the
 * signs of tb's). */
static int rnl_sample(ea_romnl_t *r, const ea_rom_table_t *tb, int s, const double q[2],
                      const double *ref) {
  const int nd = r->nd;
  rnl_coef_t *c = &r->c[s];
  double *us = r->vec + (size_t)s * NVEC * nd, *phs = us + nd;
  /* the centre first, then its neighbours (each static solve starts next to the last) */
  static const int order[9] = {4, 3, 5, 1, 7, 0, 2, 6, 8};
  for (int o = 0; o < 9; ++o) {
    const int k = order[o];
    double *ph = r->ph9 + (size_t)k * NK * nd;
    if (rnl_point(r, q[0] + (k % 3 - 1) * RNL_HL, q[1] + (k / 3 - 1) * RNL_HA,
                  r->u9 + (size_t)k * nd, ph, k == 4 ? ref : r->ph9 + (size_t)4 * NK * nd))
      return 1;
    if (k != 4) continue;
    if (!ref) { /* the table's signs: its targets and output map are the planner's */
      ea_rom_point_t p;
      ea_rom_table_eval(tb, q[0], q[1], &p, NULL, NULL);
      for (int j = 0; j < NK; ++j) {
        double *f = ph + (size_t)j * nd;
        if (f[nd - 3] * p.tip[j][0] + f[nd - 2] * p.tip[j][1] < 0)
          for (int i = 0; i < nd; ++i)
            f[i] = -f[i];
      }
    }
    ea_fe_cable_phase_t phase;
    if (ea_fe_cable_make_passive(r->m)) return 1;
    ea_fe_cable_get(r->m, &phase, &r->L0[s], NULL, NULL);
    memcpy(us, r->u9 + (size_t)4 * nd, sizeof(double) * (size_t)nd);
    memcpy(phs, ph, sizeof(double) * (size_t)NK * nd);
    if (rnl_modal_derivatives(r, us, phs, r->L0[s])) return 1;
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b)
        c->W[a][b] = dotM(r, r->th + (size_t)a * nd, r->th + (size_t)b * nd);
  }
  for (int comp = 0; comp < 5; ++comp) {
    rnl_stencil(r->u9, (size_t)nd, nd, comp, r->d1);
    for (int a = 0; a < 3; ++a)
      c->E[a][comp] = dotM(r, r->th + (size_t)a * nd, r->d1);
  }
  for (int j = 0; j < NK; ++j)
    for (int comp = 0; comp < 5; ++comp) {
      rnl_stencil(r->ph9 + (size_t)j * nd, (size_t)NK * nd, nd, comp, r->d1);
      for (int a = 0; a < 3; ++a)
        c->R[a][j][comp] = dotM(r, r->th + (size_t)a * nd, r->d1);
      for (int i = 0; i < NK; ++i) {
        const double g = dotM(r, phs + (size_t)i * nd, r->d1);
        if (comp < 2)
          c->G[i][j][comp] = g;
        else
          c->D[i][j][comp - 2] = g;
      }
    }
  for (int k = 0; k < NK; ++k) {
    memset(r->Mph + (size_t)k * nd, 0, sizeof(double) * (size_t)nd);
    ea__fe_band_gemv(r->m, 1.0, r->m->Mb, phs + (size_t)k * nd, r->Mph + (size_t)k * nd);
  }
  const double tf = ea__mono_s();
  const int rc = rnl_fit(r, s);
  r->info.time_fit_s += ea__mono_s() - tf;
  return rc;
}

ea_status_t ea_romnl_sample(ea_romnl_t *r, const ea_rom_table_t *tb, int n, const double *q,
                            ea_error_t *err) {
  if (!r || !tb || !q || n < 2)
    return ea_error_set(err, EA_ERR_ARG, "nonlinear reduced model: bad argument");
  ea_rom_table_info_t ti;
  ea_rom_table_info(tb, &ti);
  if (ti.modes != NK)
    return ea_error_set(err, EA_ERR_ARG,
                        "the nonlinear reduced model has %d modes; the table has %d (set "
                        "dynamics.modes to %d)",
                        NK, ti.modes, NK);
  const double t0 = ea__mono_s();
  if (n > r->cap) {
    const size_t nd = (size_t)r->nd;
    double *nq = realloc(r->q, sizeof(double) * 2 * (size_t)n);
    if (nq) r->q = nq;
    rnl_coef_t *nc = realloc(r->c, sizeof(rnl_coef_t) * (size_t)n);
    if (nc) r->c = nc;
    double *nv = realloc(r->vec, sizeof(double) * NVEC * nd * (size_t)n);
    if (nv) r->vec = nv;
    double *nl = realloc(r->L0, sizeof(double) * (size_t)n);
    if (nl) r->L0 = nl;
    if (!nq || !nc || !nv || !nl)
      return ea_error_set(err, EA_ERR_NOMEM, "nonlinear reduced model: out of memory");
    r->cap = n;
  }
  memset(&r->info, 0, sizeof r->info);
  r->ns = 0;
  r->have_guess = 0;
  for (int s = 0; s < n; ++s) {
    r->q[2 * s] = q[2 * s];
    r->q[2 * s + 1] = q[2 * s + 1];
    const double *ref = s ? r->vec + ((size_t)(s - 1) * NVEC + 1) * (size_t)r->nd : NULL;
    if (rnl_sample(r, tb, s, q + 2 * s, ref))
      return ea_error_set(err, EA_ERR_NOCONV,
                          "nonlinear reduced model: no stable static state, modes or condensed "
                          "force at L_c %.6g m, alpha %.6g rad (point %d of %d)",
                          q[2 * s], q[2 * s + 1], s + 1, n);
  }
  r->ns = n;
  r->info.samples = n;
  r->info.time_s = ea__mono_s() - t0;
  return EA_OK;
}

void ea_romnl_info(const ea_romnl_t *r, ea_romnl_info_t *info) {
  if (!r || !info) return;
  *info = r->info;
}

double ea_romnl_locate(const ea_romnl_t *r, const double q[2], int *cursor, double *dist) {
  if (!r || r->ns < 2) {
    if (dist) *dist = INFINITY;
    return 0.0;
  }
  const int c0 = cursor ? *cursor : 0;
  const int lo = c0 - 1 < 0 ? 0 : c0 - 1;
  const int hi = cursor ? (c0 + 8 > r->ns - 2 ? r->ns - 2 : c0 + 8) : r->ns - 2;
  double best = INFINITY, pos = 0.0;
  int bj = lo;
  for (int j = lo; j <= hi; ++j) {
    const double ax = r->q[2 * j], ay = RNL_ASCALE * r->q[2 * j + 1];
    const double dx = r->q[2 * j + 2] - ax, dy = RNL_ASCALE * r->q[2 * j + 3] - ay;
    const double px = q[0] - ax, py = RNL_ASCALE * q[1] - ay;
    const double ll = dx * dx + dy * dy;
    double w = ll > 0.0 ? (px * dx + py * dy) / ll : 0.0;
    w = w < 0.0 ? 0.0 : w > 1.0 ? 1.0 : w;
    const double d = hypot(px - w * dx, py - w * dy);
    if (d < best) {
      best = d;
      pos = j + w;
      bj = j;
    }
  }
  if (cursor) *cursor = bj;
  if (dist) *dist = best;
  return pos;
}

void ea_romnl_rhs(const ea_romnl_t *r, double pos, const ea_rom_point_t *p, const double q1[2],
                  const double q2[2], const double z[2 * EA_ROMNL_MODES],
                  double dz[2 * EA_ROMNL_MODES]) {
  int s = (int)floor(pos);
  s = s < 0 ? 0 : s > r->ns - 2 ? r->ns - 2 : s;
  const double f = fmin(fmax(pos - s, 0.0), 1.0);
  const rnl_coef_t *c0 = &r->c[s], *c1 = &r->c[s + 1];
  rnl_coef_t c;
#define RNL_LERP(fld)                                                                              \
  do {                                                                                             \
    const double *a = (const double *)c0->fld, *b = (const double *)c1->fld;                       \
    double *o = (double *)c.fld;                                                                   \
    for (size_t k = 0; k < sizeof c.fld / sizeof(double); ++k)                                     \
      o[k] = (1 - f) * a[k] + f * b[k];                                                            \
  } while (0)
  RNL_LERP(G);
  RNL_LERP(D);
  RNL_LERP(E);
  RNL_LERP(R);
  RNL_LERP(W);
#undef RNL_LERP
  const double *a = q2, *v = q1;
  const double vv[3] = {v[0] * v[0], 2 * v[0] * v[1], v[1] * v[1]};
  /* the static condensed force of each sample, blended */
  double lam[NK];
  {
    double b0[PN], b1[PN];
    rnl_pbasis(z[0] / c0->esc, b0);
    rnl_pbasis(z[0] / c1->esc, b1);
    for (int i = 0; i < NK; ++i) {
      double l0 = 0.0, l1 = 0.0;
      for (int n = 0; n < PN; ++n) {
        l0 += b0[n] * (c0->P[i][n] + z[2] * c0->P[NK + i][n]);
        l1 += b1[n] * (c1->P[i][n] + z[2] * c1->P[NK + i][n]);
      }
      lam[i] = (1 - f) * l0 + f * l1;
    }
  }
  /* the time derivatives of the modes projected on the manifold: Rd1 = R . q',
   * Rd2 = R . q'' + R . q' q' */
  double Rd1[3][NK], Rd2[3][NK];
  for (int pp = 0; pp < 3; ++pp)
    for (int j = 0; j < NK; ++j) {
      const double *Rc = c.R[pp][j];
      Rd1[pp][j] = Rc[0] * v[0] + Rc[1] * v[1];
      Rd2[pp][j] = Rc[0] * a[0] + Rc[1] * a[1] + Rc[2] * vv[0] + Rc[3] * vv[1] + Rc[4] * vv[2];
    }
  double rhs[NK];
  for (int i = 0; i < NK; ++i) {
    /* the base load on (Phi_i + Theta e) */
    double F = -lam[i] - (p->B[i][0] * a[0] + p->B[i][1] * a[1]) -
               (p->C[i][0] * vv[0] + p->C[i][1] * vv[1] + p->C[i][2] * vv[2]);
    for (int k = 0; k < NK; ++k) {
      const double *Ek = c.E[i + k];
      F -= z[2 * k] * (Ek[0] * a[0] + Ek[1] * a[1] + Ek[2] * vv[0] + Ek[3] * vv[1] + Ek[4] * vv[2]);
    }
    /* the moving modes */
    for (int j = 0; j < NK; ++j) {
      const double e = z[2 * j], ed = z[2 * j + 1];
      const double *G = c.G[i][j], *D = c.D[i][j];
      F -= 2 * (G[0] * v[0] + G[1] * v[1]) * ed + (G[0] * a[0] + G[1] * a[1]) * e;
      F -= (D[0] * vv[0] + D[1] * vv[1] + D[2] * vv[2]) * e;
    }
    /* the manifold moving with the modes: (Theta e)^T M (Phi'' e + 2 Phi' e'),
     * Phi_i''^T M y and 2 Phi_i'^T M y' by the gauge */
    double x = 0.0;
    for (int k = 0; k < NK; ++k)
      for (int j = 0; j < NK; ++j) {
        const double ek = z[2 * k], ej = z[2 * j], edj = z[2 * j + 1];
        x += ek * (2 * edj * Rd1[i + k][j] + ej * Rd2[i + k][j]);
        x -= 0.5 * ek * ej * Rd2[k + j][i];
        x -= 2 * ek * edj * Rd1[k + j][i];
      }
    F -= x;
    /* the convective force of the manifold's inertia: V^T M Theta_jl e_j' e_l' */
    for (int k = 0; k < NK; ++k)
      for (int j = 0; j < NK; ++j)
        for (int l = 0; l < NK; ++l)
          F -= z[2 * k] * z[2 * j + 1] * z[2 * l + 1] * c.W[i + k][j + l];
    rhs[i] = F;
  }
  /* the modal mass I + V^T M V, V_l = Theta_lk e_k */
  double A[NK][NK];
  for (int i = 0; i < NK; ++i)
    for (int l = 0; l < NK; ++l) {
      double m = i == l ? 1.0 : 0.0;
      for (int k = 0; k < NK; ++k)
        for (int n = 0; n < NK; ++n)
          m += z[2 * k] * z[2 * n] * c.W[i + k][l + n];
      A[i][l] = m;
    }
  const double det = A[0][0] * A[1][1] - A[0][1] * A[1][0];
  dz[0] = z[1];
  dz[2] = z[3];
  dz[1] = (rhs[0] * A[1][1] - rhs[1] * A[0][1]) / det;
  dz[3] = (A[0][0] * rhs[1] - A[1][0] * rhs[0]) / det;
}
