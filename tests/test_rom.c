/* The reduced dynamic model (model/fe_rom.c) against answers from outside it:
 *  - its frequencies against the FE eigen-solver at the same state (direct), and the table's
 *    bicubic interpolation against direct evaluations at the cell centres (the farthest from
 *    the grid);
 *  - the modal forcing (central differences of FE static states): converged in the step
 *    (halving it moves B and C by little, at the rate of a second-order difference), and
 *    B = Phi^T M du_s/dq, C = Phi^T M d2u_s/dq2 of modes 1..4 against the same computed in
 *    the test from the public FE API alone (static states at q +- h, q +- 2h differenced with
 *    Richardson's extrapolation, ea_fe_modes, M from the kinetic energy ea_fe_energy), at two
 *    configurations and tip masses;
 *  - its static tension against the ODE statics;
 *  - what it predicts for a trajectory (modal states integrated along the plan) against the
 *    nonlinear FE transient: the residual vibration of the minimum-time paper line, the
 *    min_vibration paper line, and a small cable-length cycloid (linear regime). */
#include "ea_planner.h"
#include "ea_problems.h"
#include "ea_simulate.h"
#include "ea_test.h"

#include <gsl/gsl_errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

/* the modal forcing against FE static states differenced in the test (test_forcing_independent):
 * measured, worst of the two configurations and the components, relative to each mode's largest
 * entry: B 1.9e-6 (modes 1, 2), 1.0e-5 (3, 4); C 6.0e-6, 9.1e-6 (the reduced model's own
 * O(h^2) truncation: the test's Richardson correction of its h-difference is 3e-6 / 5e-6);
 * tolerances 3x */
#define TOL_B 6e-6
#define TOL_B34 3e-5
#define TOL_C 2e-5
#define TOL_C34 3e-5

static const char *src;

static int plan_example(const char *name, ea_traj_t *tr, ea_arm_t *arm) {
  char path[1024];
  snprintf(path, sizeof path, "%s/problems/examples/%s", src, name);
  ea_task_t task;
  ea_error_t e;
  ea_planner_t *pl = NULL;
  ea_plan_info_t info;
  int rc = 1;
  if (ea_task_load(path, NULL, &task, &e) || ea_planner_alloc(&task, &pl, &e) ||
      ea_planner_solve(pl, EA_PLAN_COLD, NULL, &info, &e) || ea_planner_trajectory(pl, tr, &e))
    printf("%s: %s\n", name, e.msg);
  else
    rc = 0;
  *arm = task.arm;
  ea_planner_free(pl);
  return rc;
}

/* The (L_c, alpha) box of a trajectory with a margin. */
static void traj_box(const ea_traj_t *tr, double box[4]) {
  box[0] = box[2] = INFINITY;
  box[1] = box[3] = -INFINITY;
  for (int i = 0; i < tr->n; ++i) {
    box[0] = fmin(box[0], EA_TRAJ_AT(tr, i, EA_TRAJ_cable_length));
    box[1] = fmax(box[1], EA_TRAJ_AT(tr, i, EA_TRAJ_cable_length));
    box[2] = fmin(box[2], EA_TRAJ_AT(tr, i, EA_TRAJ_cable_angle));
    box[3] = fmax(box[3], EA_TRAJ_AT(tr, i, EA_TRAJ_cable_angle));
  }
  box[0] -= 0.02;
  box[1] += 0.02;
  box[2] -= 0.04;
  box[3] += 0.04;
}

static double rel(double a, double b, double scale) {
  return fabs(a - b) / scale;
}

static void test_point_and_table(void) {
  ea_arm_t arm;
  ea_arm_default(&arm);
  ea_error_t e;
  ea_rom_t *r = NULL, *r2 = NULL;
  ea_rom_settings_t s;
  ea_rom_settings_default(&s);
  if (ea_rom_alloc(&arm, arm.m_hand, &s, &r, &e)) {
    ea_test_true(0, e.msg);
    return;
  }
  /* frequencies against the FE eigen-solver at the state ea_fe_static_solve gives */
  const double Lc = 0.45, al = -0.3;
  ea_rom_point_t p, ph;
  ea_test_true(ea_rom_point(r, Lc, al, 0, &p, &e) == EA_OK, "reduced model at (0.45 m, -0.3)");
  {
    ea_shooter_t *sh = NULL;
    ea_fe_model_t *m = NULL;
    ea_fe_settings_t fs;
    ea_fe_settings_default(&fs);
    fs.static_hold_tip = 1;
    const ea_load_t load = {arm.m_hand};
    ea_statics_problem_t pr = ea_statics_problem_cable(Lc, al);
    ea_statics_solution_t sol;
    ea_fe_modes_info_t mi;
    if (ea_shooter_alloc(&arm, NULL, &sh, NULL) || ea_fe_model_alloc(&arm, &fs, &m, NULL)) return;
    ea_shooter_set_load(sh, &load);
    ea_fe_model_set_load(m, &load);
    if (!ea_statics_solve(sh, &pr, NULL, NULL, &sol, NULL) &&
        !ea_fe_static_solve(m, sh, &sol, NULL, NULL) && !ea_fe_modes(m, &mi, NULL)) {
      ea_test_rel(sqrt(p.omega2[0]) / (2 * M_PI), mi.freq_hz[0], 1e-9, "f1: reduced model = FE");
      ea_test_rel(sqrt(p.omega2[1]) / (2 * M_PI), mi.freq_hz[1], 1e-9, "f2: reduced model = FE");
      /* the FE static tension against the ODE statics: FE and ODE differ by extensibility
       * (~1e-5 N, README) */
      ea_test_abs(p.tension, sol.p[EA_P_TENSION], 1e-4, "static tension vs the ODE statics");
    } else {
      ea_test_true(0, "direct FE");
    }
    ea_fe_model_free(m);
    ea_shooter_free(sh);
  }
  /* the difference step: halved */
  s.step_length /= 2;
  s.step_angle /= 2;
  if (!ea_rom_alloc(&arm, arm.m_hand, &s, &r2, &e) && !ea_rom_point(r2, Lc, al, 0, &ph, &e)) {
    double dB = 0, dC = 0, Bs = 0, Cs = 0;
    for (int k = 0; k < 2; ++k)
      for (int c = 0; c < 3; ++c) {
        if (c < 2) {
          dB = fmax(dB, fabs(p.B[k][c] - ph.B[k][c]));
          Bs = fmax(Bs, fabs(p.B[k][c]));
        }
        dC = fmax(dC, fabs(p.C[k][c] - ph.C[k][c]));
        Cs = fmax(Cs, fabs(p.C[k][c]));
      }
    printf("difference step halved: B moves %.2e, C %.2e (of their largest entries)\n", dB / Bs,
           dC / Cs);
    /* measured 2.5e-6 (B) and 3e-5 (C); tolerances 10x */
    ea_test_true(dB / Bs < 2.5e-5, "modal forcing B converged in the difference step");
    ea_test_true(dC / Cs < 3e-4, "velocity term C converged in the difference step");
  } else {
    ea_test_true(0, e.msg);
  }
  ea_rom_free(r2);
  /* the table over the paper line's box vs direct values at the cell centres */
  const double box[4] = {0.254, 0.55, -0.75, 0.0}; /* from the inner edge */
  ea_rom_table_t *tb = NULL;
  const int nL = 12, na = 12;
  if (ea_rom_table_build(r, box, nL, na, &tb, &e)) {
    ea_test_true(0, e.msg);
    ea_rom_free(r);
    return;
  }
  ea_rom_table_info_t ti;
  ea_rom_table_info(tb, &ti);
  double ew = 0, eB = 0, eC = 0, et = 0, eT = 0, emax = 0;
  int npts = 0;
  for (int j = 0; j + 1 < na; j += 2)
    for (int i = 0; i + 1 < nL; i += 2) {
      const double L = box[0] + (box[1] - box[0]) * (i + 0.5) / (nL - 1);
      const double a = box[2] + (box[3] - box[2]) * (j + 0.5) / (na - 1);
      ea_rom_point_t d, v;
      if (ea_rom_point(r, L, a, 0, &d, NULL)) continue; /* outside the workspace */
      ea_rom_table_eval(tb, L, a, &v, NULL, NULL);
      ++npts;
      for (int k = 0; k < 2; ++k) {
        const double sg = (d.B[k][0] * v.B[k][0] + d.B[k][1] * v.B[k][1]) < 0 ? -1 : 1;
        ew = fmax(ew, rel(v.omega2[k], d.omega2[k], d.omega2[k]));
        const double Bs = hypot(d.B[k][0], d.B[k][1]), Cs = fmax(fabs(d.C[k][0]), fabs(d.C[k][2]));
        for (int c = 0; c < 2; ++c) {
          eB = fmax(eB, rel(sg * v.B[k][c], d.B[k][c], Bs));
          et = fmax(et, rel(sg * v.tip[k][c], d.tip[k][c], hypot(d.tip[k][0], d.tip[k][1])));
        }
        for (int c = 0; c < 3; ++c)
          eC = fmax(eC, rel(sg * v.C[k][c], d.C[k][c], Cs));
        eT = fmax(eT, rel(sg * v.dtension[k], d.dtension[k], hypot(d.B[k][0], d.B[k][1]) * 1e3));
      }
      if (getenv("EA_ROM_DEBUG"))
        printf("  L %.3f a %.3f: w2 %.5g/%.5g B %.4g,%.4g/%.4g,%.4g tip %.4g,%.4g/%.4g,%.4g\n", L,
               a, v.omega2[1], d.omega2[1], v.B[1][0], v.B[1][1], d.B[1][0], d.B[1][1], v.tip[1][0],
               v.tip[1][1], d.tip[1][0], d.tip[1][1]);
      emax = fmax(emax, fmax(fmax(ew, eB), et));
    }
  printf("table %d x %d over L_c [%.2f, %.2f] m, alpha [%.2f, %.2f] rad (%d extrapolated, built "
         "in %.3f s) vs direct at %d cell centres: omega^2 %.1e, B %.1e, C %.1e, tip %.1e, "
         "dT %.1e\n",
         nL, na, box[0], box[1], box[2], box[3], ti.n_extrapolated, ti.time_s, npts, ew, eB, eC, et,
         eT);
  ea_test_true(npts >= 10, "cell centres inside the workspace");
  /* measured (12 x 12; worst near the inner edge, where f1 changes fastest): omega^2 1.3e-3,
   * B 5.0e-4, C 2.0e-3, tip 4.6e-3, tension per mode 1.8e-3; tolerances 3x */
  ea_test_true(ew < 4e-3, "table: omega^2 at the cell centres within 4e-3");
  ea_test_true(eB < 1.5e-3, "table: modal forcing B at the cell centres within 1.5e-3");
  ea_test_true(eC < 6e-3, "table: velocity term C at the cell centres within 6e-3");
  ea_test_true(et < 1.5e-2, "table: modal tip displacement at the cell centres within 1.5e-2");
  ea_test_true(eT < 6e-3, "table: tension per mode at the cell centres within 6e-3");
  /* the interpolant's derivative against a central difference of it */
  {
    ea_rom_point_t v0, dL, da, vp, vm;
    const double L = 0.41, a = -0.33, h = 1e-6;
    ea_rom_table_eval(tb, L, a, &v0, &dL, &da);
    ea_rom_table_eval(tb, L + h, a, &vp, NULL, NULL);
    ea_rom_table_eval(tb, L - h, a, &vm, NULL, NULL);
    const double gL = (vp.B[0][0] - vm.B[0][0]) / (2 * h);
    ea_rom_table_eval(tb, L, a + h, &vp, NULL, NULL);
    ea_rom_table_eval(tb, L, a - h, &vm, NULL, NULL);
    const double ga = (vp.omega2[0] - vm.omega2[0]) / (2 * h);
    ea_test_rel(dL.B[0][0], gL, 1e-6, "table: exact d B / d L_c of the interpolant");
    ea_test_rel(da.omega2[0], ga, 1e-6, "table: exact d omega^2 / d alpha of the interpolant");
    /* its second derivatives (ea_rom_table_eval2) against central differences of the exact
     * first ones, inside one cell */
    ea_rom_point_t v2, dL2, da2, dLL, dLa, daa, pL, pa, mL, ma;
    ea_rom_table_eval2(tb, L, a, &v2, &dL2, &da2, &dLL, &dLa, &daa);
    ea_test_true(
        v2.omega2[0] == v0.omega2[0] && dL2.B[0][0] == dL.B[0][0] &&
            da2.dtension[1] == da.dtension[1],
        "table: ea_rom_table_eval2's values and first derivatives are ea_rom_table_eval's");
    ea_rom_table_eval(tb, L + h, a, NULL, &pL, &pa);
    ea_rom_table_eval(tb, L - h, a, NULL, &mL, &ma);
    ea_test_rel(dLL.dtension[0], (pL.dtension[0] - mL.dtension[0]) / (2 * h), 1e-5,
                "table: exact d2 (tension per mode) / d L_c^2 of the interpolant");
    ea_test_rel(dLa.dtorque[1], (pa.dtorque[1] - ma.dtorque[1]) / (2 * h), 1e-5,
                "table: exact d2 (torque per mode) / d L_c d alpha of the interpolant");
    ea_rom_table_eval(tb, L, a + h, NULL, &pL, &pa);
    ea_rom_table_eval(tb, L, a - h, NULL, &mL, &ma);
    ea_test_rel(daa.dtension[1], (pa.dtension[1] - ma.dtension[1]) / (2 * h), 1e-5,
                "table: exact d2 (tension per mode) / d alpha^2 of the interpolant");
    ea_test_rel(dLa.omega2[0], (pL.omega2[0] - mL.omega2[0]) / (2 * h), 1e-5,
                "table: exact d2 omega^2 / d alpha d L_c of the interpolant");
  }
  ea_rom_table_free(tb);
  ea_rom_free(r);
}

/* ---- the modal forcing against FE static states differenced here ------------------------
 * Everything through the public FE API, nothing of model/fe_rom.c: static states holding the
 * tip (ea_statics_solve + ea_fe_static_solve) on a 5 x 5 stencil of steps h and 2h, the
 * derivatives du_s/dq and d2u_s/dq2 by central differences at both steps and Richardson's
 * extrapolation (4 D_h - D_2h) / 3 (truncation O(h^4)); the modes by ea_fe_modes at the centre
 * (ea_fe_mode_shape, sign: tip y >= 0, as ea_rom_point with align 0); the mass inner product
 * from the kinetic energy, a^T M b = (E(u, s (a + b)) - E(u, s (a - b))) / (2 s^2) with
 * ea_fe_energy at the same positions (the potential cancels). */
typedef struct fd_model {
  ea_shooter_t *sh;
  ea_fe_model_t *m;
  int nd;
  double guess[EA_NP];
  int have_guess;
} fd_model_t;

static int fd_static(fd_model_t *f, double Lc, double al, double *u) {
  ea_statics_problem_t pr = ea_statics_problem_cable(Lc, al);
  ea_statics_solution_t sol;
  if (ea_statics_solve(f->sh, &pr, NULL, f->have_guess ? f->guess : NULL, &sol, NULL) ||
      ea_fe_static_solve(f->m, f->sh, &sol, NULL, NULL))
    return 1;
  memcpy(f->guess, sol.p, sizeof f->guess);
  f->have_guess = 1;
  return ea_fe_get_state(f->m, u, NULL) != EA_OK;
}

/* a^T M b at the model's current positions u, by polarisation of the kinetic energy */
static double fd_dotM(fd_model_t *f, const double *u, const double *a, const double *b, double *w) {
  const double s = 30.0;
  for (int i = 0; i < f->nd; ++i)
    w[i] = s * (a[i] + b[i]);
  ea_fe_set_state(f->m, u, w);
  const double ep = ea_fe_energy(f->m);
  for (int i = 0; i < f->nd; ++i)
    w[i] = s * (a[i] - b[i]);
  ea_fe_set_state(f->m, u, w);
  const double em = ea_fe_energy(f->m);
  ea_fe_set_state(f->m, u, NULL);
  return (ep - em) / (2 * s * s);
}

/* B and C of the first K modes at (Lc, al) for tip mass tm; 0 on success. err_rich: the largest
 * |Richardson - central difference at h| relative to the largest entry, for B and for C (how
 * far the h-difference alone is from converged). */
static int fd_forcing(const ea_arm_t *arm, double tm, double Lc, double al, int K, double B[][2],
                      double C[][3], double err_rich[2]) {
  fd_model_t f = {0};
  ea_fe_settings_t fs;
  ea_fe_settings_default(&fs);
  fs.static_hold_tip = 1;
  fs.newton_tol = 1e-13;
  fs.modes = K;
  const ea_load_t load = {tm};
  int rc = 1;
  double *u[5][5] = {{0}}, *J[2], *H[3], *phi, *w;
  if (ea_shooter_alloc(arm, NULL, &f.sh, NULL) || ea_fe_model_alloc(arm, &fs, &f.m, NULL))
    goto done;
  ea_shooter_set_load(f.sh, &load);
  ea_fe_model_set_load(f.m, &load);
  f.nd = 3 * ea_fe_model_nodes(f.m);
  const size_t nd = (size_t)f.nd;
  double *buf = calloc(nd * (32 + (size_t)K), sizeof(double));
  if (!buf) goto done;
  for (int a = 0; a < 5; ++a)
    for (int b = 0; b < 5; ++b)
      u[a][b] = buf + nd * (size_t)(5 * a + b);
  J[0] = buf + 25 * nd, J[1] = J[0] + nd, H[0] = J[1] + nd, H[1] = H[0] + nd, H[2] = H[1] + nd;
  phi = H[2] + nd, w = phi + nd;
  /* steps other than the reduced model's (2 mm, 4 mrad) */
  const double hL = 2.5e-3, ha = 5e-3;
  /* u[2 + i][2 + j] at (Lc + i hL, al + j ha); the points needed, from the centre outwards */
  static const int pts[17][2] = {{0, 0},   {1, 0}, {-1, 0}, {0, 1},  {0, -1}, {2, 0},
                                 {-2, 0},  {0, 2}, {0, -2}, {1, 1},  {1, -1}, {-1, 1},
                                 {-1, -1}, {2, 2}, {2, -2}, {-2, 2}, {-2, -2}};
  for (int k = 1; k <= 17; ++k) { /* the centre last: the model holds its state */
    const int i = pts[k % 17][0], j = pts[k % 17][1];
    if (fd_static(&f, Lc + i * hL, al + j * ha, u[2 + i][2 + j])) goto freebuf;
  }
  double eB = 0, eC = 0, sB = 0, sC = 0;
  for (int n = 0; n < f.nd; ++n) {
    const double c = u[2][2][n];
    const double dL1 = (u[3][2][n] - u[1][2][n]) / (2 * hL),
                 dL2 = (u[4][2][n] - u[0][2][n]) / (4 * hL);
    const double da1 = (u[2][3][n] - u[2][1][n]) / (2 * ha),
                 da2 = (u[2][4][n] - u[2][0][n]) / (4 * ha);
    const double LL1 = (u[3][2][n] - 2 * c + u[1][2][n]) / (hL * hL);
    const double LL2 = (u[4][2][n] - 2 * c + u[0][2][n]) / (4 * hL * hL);
    const double aa1 = (u[2][3][n] - 2 * c + u[2][1][n]) / (ha * ha);
    const double aa2 = (u[2][4][n] - 2 * c + u[2][0][n]) / (4 * ha * ha);
    const double La1 = (u[3][3][n] - u[3][1][n] - u[1][3][n] + u[1][1][n]) / (4 * hL * ha);
    const double La2 = (u[4][4][n] - u[4][0][n] - u[0][4][n] + u[0][0][n]) / (16 * hL * ha);
    J[0][n] = (4 * dL1 - dL2) / 3;
    J[1][n] = (4 * da1 - da2) / 3;
    H[0][n] = (4 * LL1 - LL2) / 3;
    H[1][n] = (4 * La1 - La2) / 3;
    H[2][n] = (4 * aa1 - aa2) / 3;
    /* kept for the Richardson correction's size, in the mode projections below */
    u[0][1][n] = dL1, u[0][3][n] = da1, u[1][0][n] = LL1, u[3][0][n] = La1, u[4][1][n] = aa1;
  }
  ea_fe_set_state(f.m, u[2][2], NULL);
  ea_fe_modes_info_t mi;
  if (ea_fe_modes(f.m, &mi, NULL) || !mi.stable || mi.modes < K) goto freebuf;
  const double *h1[5] = {u[0][1], u[0][3], u[1][0], u[3][0], u[4][1]};
  double *shapes = w + nd; /* ea_fe_set_state (in fd_dotM) forgets the modes: copy them first */
  for (int k = 0; k < K; ++k)
    if (ea_fe_mode_shape(f.m, k, shapes + nd * (size_t)k)) goto freebuf;
  for (int k = 0; k < K; ++k) {
    memcpy(phi, shapes + nd * (size_t)k, sizeof(double) * nd);
    if (phi[f.nd - 2] < 0) /* the tip's y component >= 0 */
      for (int n = 0; n < f.nd; ++n)
        phi[n] = -phi[n];
    const double nrm = sqrt(fd_dotM(&f, u[2][2], phi, phi, w));
    for (int n = 0; n < f.nd; ++n)
      phi[n] /= nrm;
    double h[5];
    for (int c = 0; c < 2; ++c)
      B[k][c] = fd_dotM(&f, u[2][2], phi, J[c], w);
    for (int c = 0; c < 3; ++c)
      C[k][c] = fd_dotM(&f, u[2][2], phi, H[c], w);
    for (int c = 0; c < 5; ++c)
      h[c] = fd_dotM(&f, u[2][2], phi, h1[c], w);
    for (int c = 0; c < 2; ++c) {
      eB = fmax(eB, fabs(h[c] - B[k][c]));
      sB = fmax(sB, fabs(B[k][c]));
    }
    for (int c = 0; c < 3; ++c) {
      eC = fmax(eC, fabs(h[2 + c] - C[k][c]));
      sC = fmax(sC, fabs(C[k][c]));
    }
  }
  err_rich[0] = eB / sB;
  err_rich[1] = eC / sC;
  rc = 0;
freebuf:
  free(buf);
done:
  ea_fe_model_free(f.m);
  ea_shooter_free(f.sh);
  return rc;
}

static void test_forcing_independent(void) {
  ea_arm_t arm;
  ea_arm_default(&arm);
  /* the paper line's middle without payload, and the payload-0.5 line's goal (0.5, -0.2) */
  const double tm[2] = {arm.m_hand, ea_arm_tip_mass(&arm, ea_arm_payload_from_factor(&arm, 0.5))};
  const double q[2][2] = {{0.45, -0.3}, {0.0, 0.0}};
  for (int c = 0; c < 2; ++c) {
    double Lc = q[c][0], al = q[c][1];
    if (c == 1) { /* the cable length and angle of the tip (0.5, -0.2) */
      Lc = hypot(0.5 - arm.x_c, -0.2 - arm.y_c);
      al = atan2(-0.2 - arm.y_c, 0.5 - arm.x_c);
    }
    const int K = 4;
    ea_rom_settings_t s;
    ea_rom_settings_default(&s);
    s.modes = K;
    ea_rom_t *r = NULL;
    ea_rom_point_t p;
    double B[4][2], C[4][3], er[2];
    ea_error_t e;
    if (ea_rom_alloc(&arm, tm[c], &s, &r, &e) || ea_rom_point(r, Lc, al, 0, &p, &e) ||
        fd_forcing(&arm, tm[c], Lc, al, K, B, C, er)) {
      ea_test_true(0, "modal forcing vs FE differences: the FE states");
      ea_rom_free(r);
      continue;
    }
    ea_rom_free(r);
    double dB[4] = {0}, dC[4] = {0};
    for (int k = 0; k < K; ++k) {
      const double sb = hypot(B[k][0], B[k][1]);
      const double sc = fmax(fabs(C[k][0]), fmax(fabs(C[k][1]), fabs(C[k][2])));
      for (int j = 0; j < 2; ++j)
        dB[k] = fmax(dB[k], fabs(p.B[k][j] - B[k][j]) / sb);
      for (int j = 0; j < 3; ++j)
        dC[k] = fmax(dC[k], fabs(p.C[k][j] - C[k][j]) / sc);
    }
    printf("modal forcing vs FE static states differenced in the test (tip mass %.3f kg, L_c "
           "%.4f m, alpha %.4f rad): B %.1e %.1e %.1e %.1e, C %.1e %.1e %.1e %.1e (modes 1..4, "
           "of each mode's largest entry; Richardson correction B %.1e, C %.1e)\n",
           tm[c], Lc, al, dB[0], dB[1], dB[2], dB[3], dC[0], dC[1], dC[2], dC[3], er[0], er[1]);
    if (getenv("EA_ROM_DEBUG"))
      for (int k = 0; k < K; ++k)
        printf("  mode %d: B %.9g %.9g / %.9g %.9g, C %.6g %.6g %.6g / %.6g %.6g %.6g\n", k + 1,
               p.B[k][0], p.B[k][1], B[k][0], B[k][1], p.C[k][0], p.C[k][1], p.C[k][2], C[k][0],
               C[k][1], C[k][2]);
    char w[200];
    snprintf(w, sizeof w, "tip mass %.3f kg: modal forcing B of modes 1, 2 = FE differences (%g)",
             tm[c], TOL_B);
    ea_test_true(fmax(dB[0], dB[1]) < TOL_B, w);
    snprintf(w, sizeof w, "tip mass %.3f kg: modal forcing B of modes 3, 4 = FE differences (%g)",
             tm[c], TOL_B34);
    ea_test_true(fmax(dB[2], dB[3]) < TOL_B34, w);
    snprintf(w, sizeof w, "tip mass %.3f kg: velocity term C of modes 1, 2 = FE differences (%g)",
             tm[c], TOL_C);
    ea_test_true(fmax(dC[0], dC[1]) < TOL_C, w);
    snprintf(w, sizeof w, "tip mass %.3f kg: velocity term C of modes 3, 4 = FE differences (%g)",
             tm[c], TOL_C34);
    ea_test_true(fmax(dC[2], dC[3]) < TOL_C34, w);
  }
}

/* The model's prediction along a trajectory vs the FE transient. */
static void compare_with_fe(const char *what, const ea_arm_t *arm, const ea_traj_t *tr,
                            double tol) {
  double box[4];
  traj_box(tr, box);
  ea_rom_t *r = NULL;
  ea_rom_table_t *tb = NULL;
  ea_error_t e;
  ea_rom_prediction_t pr;
  ea_sim_settings_t s;
  ea_sim_settings_default(&s);
  ea_sim_info_t si;
  if (ea_rom_alloc(arm, ea_arm_tip_mass(arm, tr->payload_kg), NULL, &r, &e) ||
      ea_rom_table_build(r, box, 12, 12, &tb, &e) ||
      ea_traj_rom_predict(tb, tr, 1e-4, s.settle, &pr, &e) ||
      ea_traj_simulate(arm, tr, 0.0, &s, NULL, &si, &e)) {
    ea_test_true(0, e.msg);
  } else {
    printf("%s: reduced model residual peak %.4f mm (modes %.4f, %.4f mm), FE transient %.4f "
           "mm\n",
           what, 1e3 * pr.residual_peak, 1e3 * pr.amplitude_m[0], 1e3 * pr.amplitude_m[1],
           1e3 * si.residual_peak);
    char w[160];
    snprintf(w, sizeof w, "%s: reduced-model residual vs the FE transient", what);
    ea_test_rel(pr.residual_peak, si.residual_peak, tol, w);
  }
  ea_rom_table_free(tb);
  ea_rom_free(r);
}

static void test_prediction(void) {
  ea_traj_t tr = {0};
  ea_arm_t arm;
  /* measured: 0.8 % (min time), 0.6 % (min_vibration); tolerance 2 % */
  if (!plan_example("paper-line.yaml", &tr, &arm))
    compare_with_fe("paper line, min time", &arm, &tr, 0.02);
  ea_traj_free(&tr);
  if (!plan_example("paper-line-smooth.yaml", &tr, &arm))
    compare_with_fe("paper line, min_vibration 3 s", &arm, &tr, 0.02);
  ea_traj_free(&tr);
  /* a small cable-length cycloid at a fixed angle, 1.5 periods of f1 (linear regime) */
  ea_arm_default(&arm);
  const double L0 = 0.40, dL = 0.01, al = -0.3, T = 1.5 / 1.066;
  const int n = 301;
  if (ea_traj_alloc(&tr, n)) return;
  tr.tip_mass_kg = arm.m_hand;
  for (int i = 0; i < n; ++i) {
    const double t = T * i / (n - 1), w = 2 * M_PI / T;
    EA_TRAJ_AT(&tr, i, EA_TRAJ_t) = t;
    EA_TRAJ_AT(&tr, i, EA_TRAJ_cable_length) = L0 + dL * (t / T - sin(w * t) / (2 * M_PI));
    EA_TRAJ_AT(&tr, i, EA_TRAJ_cable_length_rate) = dL * (1 - cos(w * t)) / T;
    EA_TRAJ_AT(&tr, i, EA_TRAJ_cable_angle) = al;
  }
  ea_shooter_t *sh = NULL;
  const ea_load_t load = {arm.m_hand};
  if (!ea_shooter_alloc(&arm, NULL, &sh, NULL)) {
    ea_shooter_set_load(sh, &load);
    if (!ea_traj_fill_statics(&tr, sh, NULL)) {
      for (int i = 1; i < n - 1; ++i)
        EA_TRAJ_AT(&tr, i, EA_TRAJ_theta0_rate) =
            (EA_TRAJ_AT(&tr, i + 1, EA_TRAJ_theta0) - EA_TRAJ_AT(&tr, i - 1, EA_TRAJ_theta0)) /
            (EA_TRAJ_AT(&tr, i + 1, EA_TRAJ_t) - EA_TRAJ_AT(&tr, i - 1, EA_TRAJ_t));
      /* measured 0.3 %; tolerance 1 % */
      compare_with_fe("1 cm cable cycloid, 1.5 periods", &arm, &tr, 0.01);
    }
    ea_shooter_free(sh);
  }
  ea_traj_free(&tr);
}

/* Flip bit `bit` of byte 7 (sign and high exponent bits) of n stored values, counted from the
 * last value before the file's 4-byte checksum; the key is left intact. 0 on success. */
static int flip_values(const char *path, int n, int bit) {
  FILE *f = fopen(path, "r+b");
  if (!f || fseek(f, 0, SEEK_END)) {
    if (f) fclose(f);
    return 1;
  }
  const long len = ftell(f);
  int bad = 0;
  for (int k = 1; k <= n && !bad; ++k) {
    const long off = len - 4 - 8L * k + 7;
    int c;
    bad = fseek(f, off, SEEK_SET) || (c = fgetc(f)) == EOF || fseek(f, off, SEEK_SET) ||
          fputc(c ^ (1 << bit), f) == EOF;
  }
  return fclose(f) || bad;
}

/* The table cache: built once, then loaded bit for bit; other inputs are another file. A file
 * with flipped bits in its values (key intact), of another format, or a FIFO at the path is
 * not used: the table is rebuilt (bit-equal to a fresh build) and the info says why; a cache
 * that cannot be written is reported. */
static void test_cache(void) {
  ea_arm_t arm;
  ea_arm_default(&arm);
  char dir[] = "/tmp/ea_test_rom_XXXXXX";
  if (!mkdtemp(dir)) {
    ea_test_true(0, "temp dir");
    return;
  }
  ea_rom_settings_t s;
  ea_rom_settings_default(&s);
  const double box[4] = {0.3, 0.45, -0.4, -0.2};
  ea_rom_table_t *a = NULL, *b = NULL, *c = NULL, *d = NULL;
  ea_rom_cache_info_t ia, ib, ic, id;
  ea_error_t e;
  int ok = !ea_rom_table_cached(&arm, arm.m_hand, &s, box, 5, 5, dir, &a, &ia, &e) &&
           !ea_rom_table_cached(&arm, arm.m_hand, &s, box, 5, 5, dir, &b, &ib, &e);
  ea_test_true(ok && ia.built && ia.saved && !ia.loaded && ib.loaded && !ib.built &&
                   !ia.message[0] && !ib.message[0],
               "cache: built and saved once, then loaded, nothing to report");
  size_t na = 0;
  const double *va = ok ? ea_rom_table_values(a, &na) : NULL;
  if (ok) {
    size_t nb = 0;
    const double *vb = ea_rom_table_values(b, &nb);
    ea_test_true(na == nb && !memcmp(va, vb, na * sizeof *va), "cache: loaded values bit-exact");
  }
  /* another tip mass: another file, built */
  ok = !ea_rom_table_cached(&arm, arm.m_hand + 0.05, &s, box, 5, 5, dir, &c, &ic, &e);
  ea_test_true(ok && ic.built && strcmp(ic.path, ia.path), "cache: another payload is rebuilt");
  /* damaged values, the key intact: one exponent bit of each of 140 values (as in the outside
   * review), then a single flip of the lowest exponent bit of one value */
  const int flips[2] = {140, 1}, bits[2] = {6, 4};
  for (int k = 0; k < 2; ++k) {
    ok = flip_values(ia.path, flips[k], bits[k]) == 0 &&
         !ea_rom_table_cached(&arm, arm.m_hand, &s, box, 5, 5, dir, &d, &id, &e);
    size_t nd = 0;
    const double *vd = ok ? ea_rom_table_values(d, &nd) : NULL;
    printf("  %d flipped value(s): %s\n", flips[k], id.message);
    char what[160];
    snprintf(what, sizeof what,
             "cache: %d value(s) with a flipped exponent bit: detected (CRC-32), rebuilt and "
             "saved, said so; the table = a fresh build, bit for bit",
             flips[k]);
    ea_test_true(ok && id.rejected && id.built && id.saved && !id.loaded &&
                     strstr(id.message, "CRC-32") && strstr(id.message, ia.path) && vd &&
                     nd == na && !memcmp(vd, va, na * sizeof *va),
                 what);
    ea_rom_table_free(d);
    d = NULL;
  }
  /* the repaired file loads again */
  ok = !ea_rom_table_cached(&arm, arm.m_hand, &s, box, 5, 5, dir, &d, &id, &e);
  ea_test_true(ok && id.loaded && !id.message[0], "cache: the rewritten file loads");
  ea_rom_table_free(d);
  d = NULL;
  /* a file of the previous format (no checksum, no version in the key): not used */
  FILE *f = fopen(ia.path, "r+b");
  if (f) {
    fputs("elasticarm-rom-table 1\n", f);
    fclose(f);
  }
  ok = !ea_rom_table_cached(&arm, arm.m_hand, &s, box, 5, 5, dir, &d, &id, &e);
  printf("  previous format: %s\n", id.message);
  ea_test_true(ok && id.rejected && id.built && id.saved && strstr(id.message, "format"),
               "cache: a file of another format is rebuilt, said so");
  ea_rom_table_free(d);
  d = NULL;
  /* a FIFO at the cache path: in a child under a 20 s limit (a plain open blocks for good) */
  remove(ia.path);
  if (mkfifo(ia.path, 0600) == 0) {
    int pfd[2];
    const int piped = pipe(pfd) == 0;
    const pid_t pid = piped ? fork() : -1;
    if (pid == 0) {
      close(pfd[0]);
      ea_rom_table_t *t = NULL;
      ea_rom_cache_info_t ii;
      const int r = ea_rom_table_cached(&arm, arm.m_hand, &s, box, 5, 5, dir, &t, &ii, NULL);
      char msg[sizeof ii.message + 8];
      snprintf(msg, sizeof msg, "%d%d%d%d %s", r == EA_OK && t, ii.rejected, ii.built,
               ii.save_failed, ii.message);
      if (write(pfd[1], msg, strlen(msg) + 1) < 0) _exit(2);
      _exit(0);
    }
    int status = -1, waited = 0;
    for (; pid > 0 && waited < 2000; ++waited) {
      if (waitpid(pid, &status, WNOHANG) == pid) break;
      usleep(10000);
    }
    if (pid > 0 && waited == 2000) {
      kill(pid, SIGKILL);
      waitpid(pid, &status, 0);
    }
    char got[2100] = "";
    if (piped) {
      close(pfd[1]);
      const ssize_t r = read(pfd[0], got, sizeof got - 1);
      got[r > 0 ? r : 0] = '\0';
      close(pfd[0]);
    }
    struct stat sb;
    printf("  FIFO: %s after %.2f s: %s\n", waited < 2000 ? "returned" : "KILLED", waited * 0.01,
           got);
    ea_test_true(waited < 2000 && !strncmp(got, "1111", 4) && strstr(got, "FIFO") &&
                     stat(ia.path, &sb) == 0 && S_ISFIFO(sb.st_mode),
                 "cache: a FIFO at the path: no hang; the table built, said so, the FIFO left");
    remove(ia.path);
  } else {
    ea_test_true(0, "mkfifo");
  }
  /* a cache folder that cannot be made (under a regular file; as root too): reported */
  char file[64], under[96];
  snprintf(file, sizeof file, "%s/plain", dir);
  f = fopen(file, "w");
  if (f) fclose(f);
  snprintf(under, sizeof under, "%s/cache", file);
  ok = !ea_rom_table_cached(&arm, arm.m_hand, &s, box, 5, 5, under, &d, &id, &e);
  printf("  unwritable: %s\n", id.message);
  ea_test_true(ok && d && id.built && id.save_failed && !id.saved &&
                   strstr(id.message, "not saved"),
               "cache: an unwritable cache folder: the table built, the failed write reported");
  remove(file);
  remove(ic.path);
  rmdir(dir);
  ea_rom_table_free(a);
  ea_rom_table_free(b);
  ea_rom_table_free(c);
  ea_rom_table_free(d);
}

int main(void) {
  gsl_set_error_handler_off();
  src = getenv("EA_SOURCE_DIR");
  if (!src) {
    printf("EA_SOURCE_DIR not set (run through ctest)\n");
    return EXIT_FAILURE;
  }
  test_point_and_table();
  test_forcing_independent();
  test_cache();
  test_prediction();
  return ea_test_summary("test_rom");
}
