/* Reduced dynamic model of the arm along its quasi-static manifold (docs/fe.md, "Reduced
 * model"). At a configuration q = (L_c, alpha) the FE static state u_s(q) holds the tip at
 * the cable's end (ea_fe_static_solve, holding the tip); its first K modes Phi_i
 * (mass-normalised) and frequencies omega_i about it, passive cable. With the arm moving
 * along the manifold, u = u_s(q(t)) + sum_i Phi_i(q) eta_i, projected:
 *   eta_i'' + 2 zeta_i omega_i eta_i' + omega_i^2 eta_i = -B_i(q) q'' - q'^T C_i(q) q'
 *   B_i = Phi_i^T M du_s/dq,  C_i = Phi_i^T M d2u_s/dq2   (full M: the clamp's theta0 too)
 * (the terms of the moving mode shapes, O(eta q'), are left out). The tip moves by
 * sum_i tip(Phi_i) eta_i, the cable tension by EA_c / L0 e . tip(Phi_i) eta_i, the shoulder
 * torque EI kappa0 by -(K Phi_i)_theta0 eta_i (the clamp's internal force is -EI kappa0). du_s/dq
 * and d2u_s/dq2 are central differences of static states converged to rounding (3 x 3 stencil).
 *
 * The table: those quantities on a grid over a box of (L_c, alpha), interpolated by a
 * bicubic (values, first derivatives and the cross derivative at the grid points, from
 * not-a-knot-free natural cubic splines along the grid lines), evaluated for every field
 * at once with exact derivatives of the interpolant. */
#include "fe_impl.h"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_spline.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- one configuration ------------------------------------------------- */

void ea_rom_settings_default(ea_rom_settings_t *s) {
  if (!s) return;
  memset(s, 0, sizeof *s);
  s->modes = 2;
  s->elements = EA_FE_DEFAULT_ELEMENTS;
  s->step_length = 2e-3;
  s->step_angle = 4e-3;
}

ea_status_t ea_rom_settings_validate(const ea_rom_settings_t *s, ea_error_t *err) {
  if (!s) return ea_error_set(err, EA_ERR_ARG, "reduced model settings are NULL");
  if (s->modes < 1 || s->modes > EA_ROM_MAX_MODES)
    return ea_error_set(err, EA_ERR_ARG, "reduced model: modes = %d: must be in [1, %d]", s->modes,
                        EA_ROM_MAX_MODES);
  if (s->elements < 2 || s->elements > 256)
    return ea_error_set(err, EA_ERR_ARG, "reduced model: elements = %d: must be in [2, 256]",
                        s->elements);
  if (!(s->step_length > 0 && s->step_length < 0.05) || !(s->step_angle > 0 && s->step_angle < 0.1))
    return ea_error_set(err, EA_ERR_ARG,
                        "reduced model: difference steps %g m, %g rad: must be in (0, 0.05 m), "
                        "(0, 0.1 rad)",
                        s->step_length, s->step_angle);
  return EA_OK;
}

struct ea_rom {
  ea_rom_settings_t set;
  ea_arm_t arm;
  double tip_mass;
  ea_shooter_t *sh;
  ea_fe_model_t *m;
  double *u[9];     /* static states of the 3 x 3 stencil (full) */
  double *Mw;       /* work: M x */
  double *phi_prev; /* K x nd: mass-normalised modes of the last point (sign alignment) */
  int have_prev;
  double have_guess;
  double guess[EA_NP];
};

ea_status_t ea_rom_alloc(const ea_arm_t *arm, double tip_mass, const ea_rom_settings_t *s,
                         ea_rom_t **out, ea_error_t *err) {
  if (!out) return ea_error_set(err, EA_ERR_ARG, "reduced model: NULL out");
  *out = NULL;
  ea_rom_settings_t def;
  if (!s) {
    ea_rom_settings_default(&def);
    s = &def;
  }
  ea_status_t st = ea_rom_settings_validate(s, err);
  if (st) return st;
  if (!arm || !(tip_mass >= 0) || !isfinite(tip_mass))
    return ea_error_set(err, EA_ERR_ARG, "reduced model: arm NULL or tip mass %g", tip_mass);
  ea_rom_t *r = calloc(1, sizeof *r);
  if (!r) return ea_error_set(err, EA_ERR_NOMEM, "reduced model");
  r->set = *s;
  r->arm = *arm;
  r->tip_mass = tip_mass;
  ea_fe_settings_t fs;
  ea_fe_settings_default(&fs);
  fs.elements = s->elements;
  fs.modes = s->modes;
  fs.static_hold_tip = 1;
  fs.newton_tol = 1e-13; /* to rounding: the stencil differences need it (stagnation stops) */
  const ea_load_t load = {tip_mass};
  if ((st = ea_shooter_alloc(arm, NULL, &r->sh, err))) goto fail;
  ea_shooter_set_load(r->sh, &load);
  if ((st = ea_fe_model_alloc(arm, &fs, &r->m, err)) || (st = ea_fe_model_set_load(r->m, &load)))
    goto fail;
  const size_t nd = (size_t)r->m->nd;
  r->u[0] = malloc(sizeof(double) * nd * (10 + (size_t)s->modes));
  if (!r->u[0]) {
    st = ea_error_set(err, EA_ERR_NOMEM, "reduced model");
    goto fail;
  }
  for (int k = 1; k < 9; ++k)
    r->u[k] = r->u[0] + nd * (size_t)k;
  r->Mw = r->u[0] + 9 * nd;
  r->phi_prev = r->u[0] + 10 * nd;
  *out = r;
  return EA_OK;
fail:
  ea_rom_free(r);
  return st;
}

void ea_rom_free(ea_rom_t *r) {
  if (!r) return;
  ea_fe_model_free(r->m);
  ea_shooter_free(r->sh);
  free(r->u[0]);
  free(r);
}

const ea_rom_settings_t *ea_rom_settings(const ea_rom_t *r) {
  return r ? &r->set : NULL;
}

/* FE static state holding the tip at (L_c, alpha) into u (full); T and theta0 out. */
static ea_status_t ea__rom_static(ea_rom_t *r, double Lc, double al, double *u, double *T,
                                  double *th0, ea_error_t *err) {
  ea_statics_problem_t pr = ea_statics_problem_cable(Lc, al);
  ea_statics_solution_t sol;
  ea_error_t e = {0};
  ea_status_t st = ea_statics_solve(r->sh, &pr, NULL, r->have_guess ? r->guess : NULL, &sol, &e);
  if (st && r->have_guess) st = ea_statics_solve(r->sh, &pr, NULL, NULL, &sol, &e);
  if (st)
    return ea_error_set(err, st, "reduced model: statics at L_c = %g m, alpha = %g rad: %s", Lc, al,
                        e.msg);
  memcpy(r->guess, sol.p, sizeof r->guess);
  r->have_guess = 1;
  ea_fe_static_info_t fi;
  st = ea_fe_static_solve(r->m, r->sh, &sol, &fi, &e);
  if (st)
    return ea_error_set(err, st, "reduced model: FE statics at L_c = %g m, alpha = %g rad: %s", Lc,
                        al, e.msg);
  memcpy(u, r->m->q, sizeof(double) * (size_t)r->m->nd);
  if (T) *T = fi.tension;
  if (th0) *th0 = fi.theta0;
  return EA_OK;
}

static double ea__rom_dotM(ea_rom_t *r, const double *a, const double *b) {
  const int nd = r->m->nd;
  memset(r->Mw, 0, sizeof(double) * (size_t)nd);
  ea__fe_band_gemv(r->m, 1.0, r->m->Mb, b, r->Mw);
  double s = 0.0;
  for (int i = 0; i < nd; ++i)
    s += a[i] * r->Mw[i];
  return s;
}

ea_status_t ea_rom_point(ea_rom_t *r, double Lc, double alpha, int align, ea_rom_point_t *out,
                         ea_error_t *err) {
  if (!r || !out) return ea_error_set(err, EA_ERR_ARG, "reduced model point: NULL");
  memset(out, 0, sizeof *out);
  const int nd = r->m->nd, K = r->set.modes;
  const double hL = r->set.step_length, ha = r->set.step_angle;
  ea_status_t st;
  /* the stencil: index 3 (a + 1) + (L + 1), centre 4, solved from the centre outwards */
  static const int order[9] = {4, 3, 5, 1, 7, 0, 2, 6, 8};
  double Tc = 0, thc = 0;
  for (int o = 0; o < 9; ++o) {
    const int k = order[o], di = k % 3 - 1, dj = k / 3 - 1;
    st = ea__rom_static(r, Lc + di * hL, alpha + dj * ha, r->u[k], k == 4 ? &Tc : NULL,
                        k == 4 ? &thc : NULL, err);
    if (st) return st;
    if (k == 4) memcpy(out->p_centre, r->guess, sizeof out->p_centre);
  }
  /* modes about the centre state (ea_fe_static_solve left m at the last stencil point) */
  ea_fe_set_state(r->m, r->u[4], NULL);
  ea_fe_set_cable(r->m, EA_FE_CABLE_ACTIVE, Tc);
  ea_fe_cable_phase_t ph;
  double L0;
  ea__fe_passive_equiv(r->m, r->u[4], &ph, &L0);
  ea_fe_set_cable(r->m, EA_FE_CABLE_PASSIVE, L0);
  ea_fe_modes_info_t mi;
  if ((st = ea_fe_modes(r->m, &mi, err))) return st;
  if (!mi.stable || mi.modes < K || !(mi.lambda[0] > 0))
    return ea_error_set(err, EA_ERR_UNSTABLE,
                        "reduced model: L_c = %g m, alpha = %g rad is not stable", Lc, alpha);
  r->have_prev = 1;
  out->modes = K;
  out->tension = Tc;
  out->theta0 = thc;
  out->rest_length = L0;
  /* du/dq and d2u/dq2 by central differences (full vectors, the clamp's theta0 too) */
  double *J0 = r->m->qs, *J1 = r->m->vs, *H00 = r->m->fm, *H01 = r->m->tmp, *H11 = r->m->a0;
  for (int i = 0; i < nd; ++i) {
    const double c = r->u[4][i];
    J0[i] = (r->u[5][i] - r->u[3][i]) / (2 * hL);
    J1[i] = (r->u[7][i] - r->u[1][i]) / (2 * ha);
    H00[i] = (r->u[5][i] - 2 * c + r->u[3][i]) / (hL * hL);
    H11[i] = (r->u[7][i] - 2 * c + r->u[1][i]) / (ha * ha);
    H01[i] = (r->u[8][i] - r->u[6][i] - r->u[2][i] + r->u[0][i]) / (4 * hL * ha);
  }
  /* passive stiffness at the centre for the torque per mode */
  ea__fe_assemble(r->m, r->u[4], EA_FE_CABLE_PASSIVE, L0, r->m->fi, r->m->Kt);
  const int t = nd - 3;
  const double ex = r->u[4][t] - r->arm.x_c, ey = r->u[4][t + 1] - r->arm.y_c;
  const double l = hypot(ex, ey);
  double *phi = r->m->q0;
  for (int k = 0; k < K; ++k) {
    memcpy(phi, r->m->phi + (size_t)k * nd, sizeof(double) * (size_t)nd);
    const double nrm = sqrt(ea__rom_dotM(r, phi, phi));
    double sg = 1.0 / nrm;
    /* sign: continuous with the previous point's mode (align: M-inner product of the whole
     * shapes; a node of the mode can pass through the tip), else the tip y component >= 0 */
    if (align && r->have_prev) {
      if (ea__rom_dotM(r, phi, r->phi_prev + (size_t)k * nd) < 0) sg = -sg;
    } else if (phi[t + 1] < 0) {
      sg = -sg;
    }
    for (int i = 0; i < nd; ++i)
      phi[i] *= sg;
    memcpy(r->phi_prev + (size_t)k * nd, phi, sizeof(double) * (size_t)nd);
    out->omega2[k] = mi.lambda[k];
    out->B[k][0] = ea__rom_dotM(r, phi, J0);
    out->B[k][1] = ea__rom_dotM(r, phi, J1);
    out->C[k][0] = ea__rom_dotM(r, phi, H00);
    out->C[k][1] = ea__rom_dotM(r, phi, H01);
    out->C[k][2] = ea__rom_dotM(r, phi, H11);
    out->tip[k][0] = phi[t];
    out->tip[k][1] = phi[t + 1];
    out->dtension[k] = r->arm.EA_cable / L0 * (ex * phi[t] + ey * phi[t + 1]) / l;
    double mk = 0.0; /* (K phi)_theta0: row 2 of the symmetric band */
    for (int j = 2; j <= 2 + EA__FE_KD && j < nd; ++j)
      mk += EA__SB(r->m->Kt, 2, j) * phi[j];
    out->dtorque[k] = -mk; /* the clamp's internal force is -EI kappa0 */
  }
  return EA_OK;
}

/* ---- the table ---------------------------------------------------------- */

/* Fields of a point, in table order: per mode omega2, B0, B1, C0, C1, C2, tipx, tipy,
 * dtension, dtorque; then tension, theta0. */
enum { EA__ROM_PER_MODE = 10 };

static int ea__rom_nfields(int K) {
  return EA__ROM_PER_MODE * K + 2;
}

static void ea__rom_pack(const ea_rom_point_t *p, int K, double *f) {
  for (int k = 0; k < K; ++k) {
    double *g = f + EA__ROM_PER_MODE * k;
    g[0] = p->omega2[k];
    g[1] = p->B[k][0];
    g[2] = p->B[k][1];
    g[3] = p->C[k][0];
    g[4] = p->C[k][1];
    g[5] = p->C[k][2];
    g[6] = p->tip[k][0];
    g[7] = p->tip[k][1];
    g[8] = p->dtension[k];
    g[9] = p->dtorque[k];
  }
  f[EA__ROM_PER_MODE * K] = p->tension;
  f[EA__ROM_PER_MODE * K + 1] = p->theta0;
}

static void ea__rom_unpack(const double *f, int K, ea_rom_point_t *p) {
  memset(p, 0, sizeof *p);
  p->modes = K;
  for (int k = 0; k < K; ++k) {
    const double *g = f + EA__ROM_PER_MODE * k;
    p->omega2[k] = g[0];
    p->B[k][0] = g[1];
    p->B[k][1] = g[2];
    p->C[k][0] = g[3];
    p->C[k][1] = g[4];
    p->C[k][2] = g[5];
    p->tip[k][0] = g[6];
    p->tip[k][1] = g[7];
    p->dtension[k] = g[8];
    p->dtorque[k] = g[9];
  }
  p->tension = f[EA__ROM_PER_MODE * K];
  p->theta0 = f[EA__ROM_PER_MODE * K + 1];
}

struct ea_rom_table {
  ea_rom_table_info_t info;
  int K, nf, nL, na;
  double *Lg, *ag; /* grid */
  double *val;     /* nf x (na x nL), L fastest */
  double *coef;    /* per cell (na-1)(nL-1), per field: 16 bicubic coefficients */
};

void ea_rom_table_free(ea_rom_table_t *tb) {
  if (!tb) return;
  free(tb->Lg);
  free(tb->ag);
  free(tb->val);
  free(tb->coef);
  free(tb);
}

/* Natural cubic spline derivatives of y (n points at x) into d. */
static int ea__rom_spline_deriv(const double *x, const double *y, int n, double *d) {
  if (n < 3) {
    const double s = (y[n - 1] - y[0]) / (x[n - 1] - x[0]);
    for (int i = 0; i < n; ++i)
      d[i] = s;
    return 0;
  }
  gsl_spline *sp = gsl_spline_alloc(gsl_interp_cspline, (size_t)n);
  if (!sp) return 1;
  int rc = gsl_spline_init(sp, x, y, (size_t)n) != GSL_SUCCESS;
  for (int i = 0; i < n && !rc; ++i)
    d[i] = gsl_spline_eval_deriv(sp, x[i], NULL);
  gsl_spline_free(sp);
  return rc;
}

/* Bicubic coefficients of every cell and field from the grid values: f, f_L, f_a, f_La at
 * the nodes (splines along the grid lines; the cross derivative from splines of f_L
 * along alpha). */
static ea_status_t ea__rom_coefficients(ea_rom_table_t *tb, ea_error_t *err) {
  const int nL = tb->nL, na = tb->na, nn = nL * na;
  double *fL = malloc(sizeof(double) * 3 * (size_t)nn), *line = malloc(sizeof(double) * 2 * 64);
  free(tb->coef);
  tb->coef = malloc(sizeof(double) * 16 * (size_t)(nL - 1) * (size_t)(na - 1) * (size_t)tb->nf);
  if (!fL || !line || !tb->coef || nL > 64 || na > 64) {
    free(fL);
    free(line);
    return ea_error_set(err, EA_ERR_NOMEM, "reduced model table: coefficients");
  }
  double *fa = fL + nn, *fLa = fa + nn, *ly = line, *ld = line + 64;
  for (int f = 0; f < tb->nf; ++f) {
    const double *v = tb->val + (size_t)f * nn;
    for (int j = 0; j < na; ++j) /* along L */
      if (ea__rom_spline_deriv(tb->Lg, v + j * nL, nL, fL + j * nL)) goto bad;
    for (int i = 0; i < nL; ++i) { /* along alpha: f and f_L */
      for (int j = 0; j < na; ++j)
        ly[j] = v[j * nL + i];
      if (ea__rom_spline_deriv(tb->ag, ly, na, ld)) goto bad;
      for (int j = 0; j < na; ++j)
        fa[j * nL + i] = ld[j];
      for (int j = 0; j < na; ++j)
        ly[j] = fL[j * nL + i];
      if (ea__rom_spline_deriv(tb->ag, ly, na, ld)) goto bad;
      for (int j = 0; j < na; ++j)
        fLa[j * nL + i] = ld[j];
    }
    for (int j = 0; j + 1 < na; ++j)
      for (int i = 0; i + 1 < nL; ++i) {
        const double dx = tb->Lg[i + 1] - tb->Lg[i], dy = tb->ag[j + 1] - tb->ag[j];
        const int c00 = j * nL + i, c10 = c00 + 1, c01 = c00 + nL, c11 = c01 + 1;
        /* node data in unit-cell coordinates */
        const double F[4] = {v[c00], v[c10], v[c01], v[c11]};
        const double X[4] = {fL[c00] * dx, fL[c10] * dx, fL[c01] * dx, fL[c11] * dx};
        const double Y[4] = {fa[c00] * dy, fa[c10] * dy, fa[c01] * dy, fa[c11] * dy};
        const double XY[4] = {fLa[c00] * dx * dy, fLa[c10] * dx * dy, fLa[c01] * dx * dy,
                              fLa[c11] * dx * dy};
        /* 1-D Hermite basis coefficient matrix A (p(t) = sum_m a_m t^m from p0, p1, d0, d1) */
        static const double A[4][4] = {{1, 0, 0, 0}, {0, 0, 1, 0}, {-3, 3, -2, -1}, {2, -2, 1, 1}};
        /* G = [[f00 f01 fy00 fy01], [f10 f11 fy10 fy11], [fx00 fx01 fxy00 fxy01],
         *      [fx10 fx11 fxy10 fxy11]] (rows: x-data, cols: y-data); a = A G A^T */
        const double G[4][4] = {{F[0], F[2], Y[0], Y[2]},
                                {F[1], F[3], Y[1], Y[3]},
                                {X[0], X[2], XY[0], XY[2]},
                                {X[1], X[3], XY[1], XY[3]}};
        double AG[4][4];
        for (int a = 0; a < 4; ++a)
          for (int b = 0; b < 4; ++b) {
            AG[a][b] = 0;
            for (int c = 0; c < 4; ++c)
              AG[a][b] += A[a][c] * G[c][b];
          }
        double *cf = tb->coef + (((size_t)j * (nL - 1) + i) * tb->nf + f) * 16;
        for (int a = 0; a < 4; ++a)
          for (int b = 0; b < 4; ++b) {
            double s = 0;
            for (int c = 0; c < 4; ++c)
              s += AG[a][c] * A[b][c];
            cf[4 * a + b] = s; /* coefficient of x^a y^b */
          }
      }
  }
  free(fL);
  free(line);
  return EA_OK;
bad:
  free(fL);
  free(line);
  return ea_error_set(err, EA_ERR_BACKEND, "reduced model table: spline of the grid failed");
}

static ea_status_t ea__rom_table_new(int K, int nL, int na, const double box[4],
                                     ea_rom_table_t **out, ea_error_t *err) {
  ea_rom_table_t *tb = calloc(1, sizeof *tb);
  if (!tb) return ea_error_set(err, EA_ERR_NOMEM, "reduced model table");
  tb->K = K;
  tb->nf = ea__rom_nfields(K);
  tb->nL = nL;
  tb->na = na;
  tb->Lg = malloc(sizeof(double) * (size_t)nL);
  tb->ag = malloc(sizeof(double) * (size_t)na);
  tb->val = calloc((size_t)tb->nf * (size_t)nL * (size_t)na, sizeof(double));
  if (!tb->Lg || !tb->ag || !tb->val) {
    ea_rom_table_free(tb);
    return ea_error_set(err, EA_ERR_NOMEM, "reduced model table");
  }
  for (int i = 0; i < nL; ++i)
    tb->Lg[i] = box[0] + (box[1] - box[0]) * i / (nL - 1);
  for (int j = 0; j < na; ++j)
    tb->ag[j] = box[2] + (box[3] - box[2]) * j / (na - 1);
  memcpy(tb->info.box, box, sizeof tb->info.box);
  tb->info.modes = K;
  tb->info.n_cable_length = nL;
  tb->info.n_cable_angle = na;
  *out = tb;
  return EA_OK;
}

/* Fill invalid grid values (ok = 0) by linear extrapolation from valid neighbours, as
 * many passes as it takes; -1 if nothing valid. */
static int ea__rom_fill(int nL, int na, int nf, double *val, unsigned char *ok) {
  const int nn = nL * na;
  for (int pass = 0; pass < nL + na; ++pass) {
    int missing = 0, filled = 0;
    for (int j = 0; j < na; ++j)
      for (int i = 0; i < nL; ++i) {
        const int p = j * nL + i;
        if (ok[p]) continue;
        ++missing;
        static const int di[4] = {1, -1, 0, 0}, dj[4] = {0, 0, 1, -1};
        int nx = 0, n1 = 0, dirs2[4], dirs1[4];
        for (int d = 0; d < 4; ++d) {
          const int i1 = i + di[d], j1 = j + dj[d], i2 = i + 2 * di[d], j2 = j + 2 * dj[d];
          if (i1 < 0 || i1 >= nL || j1 < 0 || j1 >= na || ok[j1 * nL + i1] != 1) continue;
          dirs1[n1++] = d;
          if (i2 < 0 || i2 >= nL || j2 < 0 || j2 >= na || ok[j2 * nL + i2] != 1) continue;
          dirs2[nx++] = d;
        }
        if (!n1) continue;
        for (int f = 0; f < nf; ++f) {
          double *v = val + (size_t)f * nn, s = 0;
          if (nx) {
            for (int q = 0; q < nx; ++q) {
              const int d = dirs2[q];
              s += 2 * v[(j + dj[d]) * nL + i + di[d]] - v[(j + 2 * dj[d]) * nL + i + 2 * di[d]];
            }
            v[p] = s / nx;
          } else {
            for (int q = 0; q < n1; ++q) {
              const int d = dirs1[q];
              s += v[(j + dj[d]) * nL + i + di[d]];
            }
            v[p] = s / n1;
          }
        }
        ok[p] = 2;
        ++filled;
      }
    for (int p = 0; p < nn; ++p)
      if (ok[p] == 2) ok[p] = 1;
    if (!missing) return 0;
    if (!filled) return -1;
  }
  return 0;
}

ea_status_t ea_rom_table_build(ea_rom_t *r, const double box[4], int nL, int na,
                               ea_rom_table_t **out, ea_error_t *err) {
  if (!r || !box || !out) return ea_error_set(err, EA_ERR_ARG, "reduced model table: NULL");
  *out = NULL;
  if (nL < 2 || na < 2 || nL > 64 || na > 64 || !(box[1] > box[0]) || !(box[3] > box[2]))
    return ea_error_set(err, EA_ERR_ARG,
                        "reduced model table: grid %d x %d over [%g, %g] x [%g, %g]", nL, na,
                        box[0], box[1], box[2], box[3]);
  const double t0 = ea__mono_s();
  ea_rom_table_t *tb;
  ea_status_t st = ea__rom_table_new(r->set.modes, nL, na, box, &tb, err);
  if (st) return st;
  const int nn = nL * na;
  unsigned char *ok = calloc((size_t)nn, 1);
  ea_rom_point_t *prev = malloc(sizeof(ea_rom_point_t) * (size_t)nn);
  double *f = malloc(sizeof(double) * (size_t)tb->nf);
  if (!ok || !prev || !f) {
    st = ea_error_set(err, EA_ERR_NOMEM, "reduced model table");
    goto done;
  }
  /* serpentine sweep: each point's mode signs aligned with a computed neighbour */
  int nvalid = 0;
  r->have_guess = 0;
  r->have_prev = 0;
  for (int j = 0; j < na; ++j)
    for (int ii = 0; ii < nL; ++ii) {
      const int i = (j % 2) ? nL - 1 - ii : ii, p = j * nL + i;
      ea_error_t e = {0};
      /* the previous successful point is a neighbour along the serpentine (or the nearest
       * one computed before a gap) */
      if (ea_rom_point(r, tb->Lg[i], tb->ag[j], 1, &prev[p], &e) != EA_OK) {
        r->have_guess = 0;
        continue;
      }
      ea__rom_pack(&prev[p], tb->K, f);
      for (int q = 0; q < tb->nf; ++q)
        tb->val[(size_t)q * nn + p] = f[q];
      ok[p] = 1;
      ++nvalid;
    }
  tb->info.n_extrapolated = nn - nvalid;
  if (nvalid == 0 || ea__rom_fill(nL, na, tb->nf, tb->val, ok)) {
    st = ea_error_set(err, EA_ERR_INADMISSIBLE,
                      "reduced model table: no stable configuration in L_c [%g, %g] m, alpha "
                      "[%g, %g] rad",
                      box[0], box[1], box[2], box[3]);
    goto done;
  }
  st = ea__rom_coefficients(tb, err);
done:
  free(ok);
  free(prev);
  free(f);
  if (st) {
    ea_rom_table_free(tb);
    return st;
  }
  tb->info.time_s = ea__mono_s() - t0;
  *out = tb;
  return EA_OK;
}

ea_status_t ea_rom_table_from_values(int modes, int nL, int na, const double box[4],
                                     const double *values, ea_rom_table_t **out, ea_error_t *err) {
  if (!box || !values || !out) return ea_error_set(err, EA_ERR_ARG, "reduced model table: NULL");
  *out = NULL;
  if (modes < 1 || modes > EA_ROM_MAX_MODES || nL < 2 || na < 2 || nL > 64 || na > 64 ||
      !(box[1] > box[0]) || !(box[3] > box[2]))
    return ea_error_set(err, EA_ERR_INPUT, "reduced model table: %d modes, grid %d x %d", modes, nL,
                        na);
  ea_rom_table_t *tb;
  ea_status_t st = ea__rom_table_new(modes, nL, na, box, &tb, err);
  if (st) return st;
  const size_t nv = (size_t)tb->nf * (size_t)nL * (size_t)na;
  for (size_t i = 0; i < nv; ++i)
    if (!isfinite(values[i])) {
      ea_rom_table_free(tb);
      return ea_error_set(err, EA_ERR_INPUT, "reduced model table: value %zu is not finite", i);
    }
  memcpy(tb->val, values, sizeof(double) * nv);
  if ((st = ea__rom_coefficients(tb, err))) {
    ea_rom_table_free(tb);
    return st;
  }
  *out = tb;
  return EA_OK;
}

const double *ea_rom_table_values(const ea_rom_table_t *tb, size_t *count) {
  if (!tb) return NULL;
  if (count) *count = (size_t)tb->nf * (size_t)tb->nL * (size_t)tb->na;
  return tb->val;
}

void ea_rom_table_info(const ea_rom_table_t *tb, ea_rom_table_info_t *info) {
  if (tb && info) *info = tb->info;
}

void ea_rom_table_eval2(const ea_rom_table_t *tb, double Lc, double alpha, ea_rom_point_t *v,
                        ea_rom_point_t *dL, ea_rom_point_t *da, ea_rom_point_t *dLL,
                        ea_rom_point_t *dLa, ea_rom_point_t *daa) {
  const int nL = tb->nL, na = tb->na, nf = tb->nf;
  /* clamp to the box (the planner keeps its knots inside) */
  const double x = fmin(fmax(Lc, tb->Lg[0]), tb->Lg[nL - 1]);
  const double y = fmin(fmax(alpha, tb->ag[0]), tb->ag[na - 1]);
  const double hx = tb->Lg[1] - tb->Lg[0], hy = tb->ag[1] - tb->ag[0];
  int i = (int)floor((x - tb->Lg[0]) / hx), j = (int)floor((y - tb->ag[0]) / hy);
  i = i < 0 ? 0 : i > nL - 2 ? nL - 2 : i;
  j = j < 0 ? 0 : j > na - 2 ? na - 2 : j;
  const double u = (x - tb->Lg[i]) / hx, w = (y - tb->ag[j]) / hy;
  const double U[4] = {1, u, u * u, u * u * u}, W[4] = {1, w, w * w, w * w * w};
  const double dU[4] = {0, 1, 2 * u, 3 * u * u}, dW[4] = {0, 1, 2 * w, 3 * w * w};
  const double d2U[4] = {0, 0, 2, 6 * u}, d2W[4] = {0, 0, 2, 6 * w};
  const int inside_L = Lc >= tb->Lg[0] && Lc <= tb->Lg[nL - 1];
  const int inside_a = alpha >= tb->ag[0] && alpha <= tb->ag[na - 1];
  const int second = dLL || dLa || daa;
  enum { NF = EA__ROM_PER_MODE * EA_ROM_MAX_MODES + 2 };
  double fv[NF], fx[NF], fy[NF], fxx[NF], fxy[NF], fyy[NF];
  const double *cf = tb->coef + ((size_t)j * (nL - 1) + i) * nf * 16;
  for (int f = 0; f < nf; ++f, cf += 16) {
    double s = 0, sx = 0, sy = 0, sxx = 0, sxy = 0, syy = 0;
    for (int a = 0; a < 4; ++a) {
      const double ra =
          cf[4 * a] * W[0] + cf[4 * a + 1] * W[1] + cf[4 * a + 2] * W[2] + cf[4 * a + 3] * W[3];
      const double rb = cf[4 * a + 1] * dW[1] + cf[4 * a + 2] * dW[2] + cf[4 * a + 3] * dW[3];
      s += U[a] * ra;
      sx += dU[a] * ra;
      sy += U[a] * rb;
      if (second) {
        sxx += d2U[a] * ra;
        sxy += dU[a] * rb;
        syy += U[a] * (cf[4 * a + 2] * d2W[2] + cf[4 * a + 3] * d2W[3]);
      }
    }
    fv[f] = s;
    fx[f] = inside_L ? sx / hx : 0.0;
    fy[f] = inside_a ? sy / hy : 0.0;
    if (second) {
      fxx[f] = inside_L ? sxx / (hx * hx) : 0.0;
      fxy[f] = inside_L && inside_a ? sxy / (hx * hy) : 0.0;
      fyy[f] = inside_a ? syy / (hy * hy) : 0.0;
    }
  }
  if (v) ea__rom_unpack(fv, tb->K, v);
  if (dL) ea__rom_unpack(fx, tb->K, dL);
  if (da) ea__rom_unpack(fy, tb->K, da);
  if (dLL) ea__rom_unpack(fxx, tb->K, dLL);
  if (dLa) ea__rom_unpack(fxy, tb->K, dLa);
  if (daa) ea__rom_unpack(fyy, tb->K, daa);
}

void ea_rom_table_eval(const ea_rom_table_t *tb, double Lc, double alpha, ea_rom_point_t *v,
                       ea_rom_point_t *dL, ea_rom_point_t *da) {
  ea_rom_table_eval2(tb, Lc, alpha, v, dL, da, NULL, NULL, NULL);
}
