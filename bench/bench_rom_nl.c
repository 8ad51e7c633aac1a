/* bench_rom_nl: where the reduced model (model/fe_rom.c) stops holding at large modal
 * deflection, measured against the nonlinear FE transient (ea_traj_simulate: generalized-alpha,
 * dt 0.5 ms, undamped, 3 s after the motion).
 *  1. lines: on the large-motion lines, the paper line and seeded random lines (payload
 *     factor 0..0.5), three plans each: quasi-static, allowed a 5 mm residual (dynamics
 *     residual_m 0.005) and at rest (residual_m 0), 2 modes. Per plan: the model's largest modal
 *     tip deviation during the motion and its predicted residual, the FE's largest tracking
 *     error and its residual; the ratio FE / predicted (the target: within 20 % or
 *     0.2 mm on plans not at rest) and, at rest, FE residual / deflection^2.
 *  2. the modal state at fixed configuration: free vibration of the FE from the static state
 *     at a line's goal displaced along mode 1 (positions relaxed to the rotations) to a tip
 *     amplitude A = 10..135 mm, against the linear model's A cos(omega_1 t): the largest tip
 *     difference within the first 1.5 s (a motion's length) and its frequency shift. What the
 *     linear modal stiffness and output map miss, with the configuration held.
 *  3. candidate terms added to the model's modal equations along each plan (columns of table 1):
 *     the moving mode shapes (M: Phi_i^T M dPhi_j/dq, Phi_i^T M d2Phi_j/dq2 from FE modes at
 *     q +- h), the Galerkin quadratic stiffness (Q) and the quadratic manifold's curvature (E,
 *     static modal derivatives Theta M-orthogonal to the modes), the modal force with every other
 *     DOF condensed statically to all orders (C, a Newton solve at every right-hand side); then
 *     the inertia of the condensed motion y, which C leaves out: on the quadratic manifold
 *     y = Theta e e / 2 (CMI: modal mass I + V^T M V and convective force, V = dy/de = Theta e),
 *     exactly from the condensation's tangent (CMX), and with the manifold's motion with the
 *     modes (CMIM: Phi^T M y'' = -Phi''^T M y - 2 Phi'^T M y' by the gauge Phi^T M y = 0, and
 *     dy/de against Phi'' e + 2 Phi' e'); CMIP is CMIM with the static condensed force fitted
 *     by polynomials in e1 at each sample: the library's nonlinear reduced model
 *     (model/fe_romnl.c, ea_traj_romnl_*; 41 samples, RK4 dt 0.1 ms; BENCH_ROM_NL_POLY=1);
 *  4. at-rest plans corrected by a candidate without touching the transcription: the goal's 4
 *     modal targets moved (warm re-plans) by a globalised Newton until the candidate ends at rest
 *     (residual peak < 0.01 mm, at most 15 evaluations), then the FE; the time of one candidate
 *     integration next to the FE transient's. The candidate: CM, or BENCH_ROM_NL_CMI=1 CMI,
 *     BENCH_ROM_NL_CMIX=1 CMX, BENCH_ROM_NL_CMIM=1 CMIM, BENCH_ROM_NL_POLY=1 CMIP.
 * Section 2b: free vibration from the quadratic manifold against the second-order model.
 * BENCH_ROM_NL_LINE=i: only line i of section 1; BENCH_ROM_NL_ONLY_FREE=1: only section 2;
 * BENCH_ROM_NL_ONLY_CORR=1: sections 1 (at-rest plans only, no candidate terms) and 4 alone;
 * BENCH_ROM_NL_CRUDE=1: section 4 also with the loop target -= z_end (J = I, full steps);
 * BENCH_ROM_NL_FDJ=1: the Newton's first Jacobian by forward differences instead of I;
 * BENCH_ROM_NL_NO_CMX=1, BENCH_ROM_NL_NO_CMIM=1: leave out those columns (each integration
 * takes seconds); BENCH_ROM_NL_XLINE=x0,y0,x1,y1,payload_factor: that line alone.
 * usage: bench_rom_nl [RANDOM_LINES] (default 8) */
#include "bench_util.h"
#include "ea_fe.h"
#include "fe_impl.h"  /* white-box: internal forces and the tangent for the modal derivatives */
#include "sim_impl.h" /* the trajectory's Hermite, as ea_traj_rom_predict integrates it */
#include "ea_planner.h"
#include "ea_problems.h"
#include "ea_simulate.h"
#include "ea_statics.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
  const char *name;
  double x0, y0, x1, y1, gamma;
} line_t;

static int load_line(const line_t *L, ea_task_t *t) {
  char path[1024];
  snprintf(path, sizeof path, "%s/problems/examples/paper-line.yaml", EA_SOURCE_DIR);
  ea_error_t e;
  if (ea_task_load(path, NULL, t, &e)) {
    fprintf(stderr, "bench_rom_nl: %s\n", e.msg);
    return 1;
  }
  t->start = ea_task_point_planar(L->x0, L->y0, 0.0);
  t->goal = ea_task_point_planar(L->x1, L->y1, 0.0);
  t->payload_factor = L->gamma;
  t->payload_kg = ea_arm_payload_from_factor(&t->arm, L->gamma);
  return 0;
}

typedef struct {
  int ok;
  double dur, pred, dev_model, fe, dev_fe;
} plan_res_t;

static void fe_run(const ea_task_t *t, const ea_traj_t *tr, plan_res_t *r) {
  ea_sim_settings_t s;
  ea_sim_settings_default(&s);
  s.scheme = EA_FE_SCHEME_GENALPHA;
  s.dt = 5e-4;
  s.settle = 3.0;
  s.damping_ratio = 0.0;
  ea_sim_info_t si;
  ea_error_t e;
  if (ea_traj_simulate(&t->arm, tr, 0.0, &s, NULL, &si, &e)) {
    fprintf(stderr, "bench_rom_nl: simulate: %s\n", e.msg);
    r->ok = 0;
    return;
  }
  r->fe = si.residual_peak;
  r->dev_fe = si.max_tracking_error;
}

/* Plan t with modes K and residual_m res; the trajectory into tr; the planner kept in *keep
 * when keep is not NULL. */
static int plan(ea_task_t *t, int K, double res, ea_traj_t *tr, ea_planner_t **keep,
                plan_res_t *r) {
  t->dynamics.modes = K;
  t->dynamics.residual_m = res;
  ea_error_t e = {0};
  ea_planner_t *pl = NULL;
  ea_plan_info_t info;
  memset(r, 0, sizeof *r);
  if (ea_task_check(t, &e) || ea_planner_alloc(t, &pl, &e) ||
      ea_planner_solve(pl, EA_PLAN_COLD, NULL, &info, &e) || ea_planner_trajectory(pl, tr, &e)) {
    fprintf(stderr, "bench_rom_nl: plan (modes %d, residual %g m): %s\n", K, res, e.msg);
    ea_planner_free(pl);
    return 1;
  }
  r->ok = 1;
  r->dur = info.duration_s;
  if (keep)
    *keep = pl;
  else
    ea_planner_free(pl);
  return 0;
}

static void predict(const ea_rom_table_t *tb, const ea_traj_t *tr, plan_res_t *r) {
  ea_rom_prediction_t pr;
  ea_error_t e;
  if (ea_traj_rom_predict(tb, tr, 1e-4, 3.0, &pr, &e)) {
    fprintf(stderr, "bench_rom_nl: predict: %s\n", e.msg);
    r->pred = r->dev_model = NAN;
    return;
  }
  r->pred = pr.residual_peak;
  r->dev_model = pr.max_deviation;
}

/* ---- 3. the moving mode shapes ---------------------------------------------------------- */

/* FE static state holding the tip at (L_c, alpha) with its first K mass-normalised modes
 * (full vectors, signs aligned with ref when given); m is left at that state, passive cable. */
typedef struct {
  ea_fe_model_t *m;
  ea_shooter_t *sh;
  int nd, K;
  double guess[EA_NP];
  int have_guess;
  double *w, *w2; /* nd work */
} fe_ctx_t;

/* a^T M b by polarisation of the kinetic energy at the model's current positions u */
static double dotM(fe_ctx_t *c, const double *u, const double *a, const double *b) {
  double ep, em;
  for (int i = 0; i < c->nd; ++i)
    c->w[i] = a[i] + b[i];
  ea_fe_set_state(c->m, u, c->w);
  ep = ea_fe_energy(c->m);
  for (int i = 0; i < c->nd; ++i)
    c->w[i] = a[i] - b[i];
  ea_fe_set_state(c->m, u, c->w);
  em = ea_fe_energy(c->m);
  ea_fe_set_state(c->m, u, NULL);
  return 0.5 * (ep - em); /* (1/2)(a+b)M(a+b) - (1/2)(a-b)M(a-b) = 2 a M b; halved */
}

static int fe_point(fe_ctx_t *c, double Lc, double al, double *u, double *phi, const double *ref,
                    double *omega2) {
  ea_statics_problem_t pr = ea_statics_problem_cable(Lc, al);
  ea_statics_solution_t sol;
  if (ea_statics_solve(c->sh, &pr, NULL, c->have_guess ? c->guess : NULL, &sol, NULL) &&
      ea_statics_solve(c->sh, &pr, NULL, NULL, &sol, NULL))
    return 1;
  memcpy(c->guess, sol.p, sizeof c->guess);
  c->have_guess = 1;
  if (ea_fe_static_solve(c->m, c->sh, &sol, NULL, NULL)) return 1;
  ea_fe_get_state(c->m, u, NULL);
  ea_fe_modes_info_t mi;
  if (ea_fe_modes(c->m, &mi, NULL) || mi.modes < c->K) return 1;
  for (int k = 0; k < c->K; ++k) {
    double *p = phi + (size_t)k * c->nd;
    if (ea_fe_mode_shape(c->m, k, p)) return 1;
    if (omega2) omega2[k] = mi.lambda[k];
  }
  for (int k = 0; k < c->K; ++k) {
    double *p = phi + (size_t)k * c->nd;
    double s = 1.0 / sqrt(dotM(c, u, p, p));
    if (ref && dotM(c, u, p, ref + (size_t)k * c->nd) < 0) s = -s;
    for (int i = 0; i < c->nd; ++i)
      p[i] *= s;
  }
  return 0;
}

enum { KM = 2, NS_MAX = 161 };

/* The moving-shape coefficients sampled along a trajectory: G[i][j][a] = Phi_i^T M dPhi_j/dq_a,
 * D[i][j][ab] = Phi_i^T M d2Phi_j/dq_a dq_b (ab: LL, La, aa). */
typedef struct {
  int ns;
  double t[NS_MAX];
  double G[NS_MAX][KM][KM][2], D[NS_MAX][KM][KM][3];
  double E[NS_MAX][3][5]; /* Theta_ik^T M (du_s/dL, du_s/da, d2u_s/dL2, d2u_s/dLda, d2u_s/da2), ik:
                             11, 12, 22; Theta the static modal derivatives M-orthogonal to the
                             modes */
  double c3[NS_MAX][4];   /* third derivatives of the potential in the modal coordinates (positions
                             relaxed to the rotations): c111, c112, c122, c222 */
  double R[NS_MAX][3][KM][5]; /* Theta_p^T M (dPhi_j/dL, dPhi_j/da, d2Phi_j/dL2, d2Phi_j/dLda,
                                 d2Phi_j/da2): the manifold and the moving modes */
  double W[NS_MAX][3][3];     /* Theta_p^T M Theta_q (p, q: 11, 12, 22): the kinetic energy of the
                                 quadratic manifold's motion y = Theta_jk e_j e_k / 2 */
  double L0[NS_MAX];          /* [m] passive cable rest length at the sample */
  double *vec;                /* per sample 8 full vectors: u_s, Phi_1, Phi_2, du_s/dL, du_s/da,
                                 d2u_s/dL2, d2u_s/dLda, d2u_s/da2 */
  int nd;
} moving_t;

/* [m] the largest modal tip amplitude met by the candidates with the condensed manifold */
static double emax_tip[KM];

/* check of the moving-shape coefficients: Phi^T M Phi = I makes G antisymmetric */
static double g_max, g_asym;

/* The potential on the modal plane about static state u (passive cable at its static rest
 * length): V(e1, e2) of u + Phi_1 e1 + Phi_2 e2, on the linear modes (relax = 0: the Galerkin
 * projection's quadratic modal force, which a quadratic manifold of static modal derivatives
 * M-orthogonal to the modes leaves as it is at second order) or with the positions relaxed to
 * the rotations (relax = 1); its third derivatives by differences of a step that moves mode 1's
 * tip by htip into c3. */
static int relax_mode = 0;
static double htip_mode = 0.002;

static int modal_cubic(fe_ctx_t *c, const double *u, const double *phi, double c3[4]) {
  const int nd = c->nd;
  const double h = htip_mode / hypot(phi[nd - 3], phi[nd - 2]);
  static const int pts[12][2] = {{1, 0}, {-1, 0}, {2, 0}, {-2, 0}, {0, 1},  {0, -1},
                                 {0, 2}, {0, -2}, {1, 1}, {-1, 1}, {1, -1}, {-1, -1}};
  double V[12], V0;
  ea_fe_set_state(c->m, u, NULL);
  if (ea_fe_cable_make_passive(c->m)) return 1;
  V0 = ea_fe_energy(c->m);
  for (int p = 0; p < 12; ++p) {
    for (int i = 0; i < nd; ++i)
      c->w2[i] = u[i] + h * (pts[p][0] * phi[i] + pts[p][1] * phi[nd + i]);
    ea_fe_set_state(c->m, c->w2, NULL);
    if (relax_mode && ea_fe_relax_positions(c->m, NULL)) return 1;
    V[p] = ea_fe_energy(c->m) - V0;
  }
  const double h3 = 2 * h * h * h;
  c3[0] = (V[2] - 2 * V[0] + 2 * V[1] - V[3]) / h3;
  c3[3] = (V[6] - 2 * V[4] + 2 * V[5] - V[7]) / h3;
  c3[1] = (V[8] - 2 * V[4] + V[9] - V[10] + 2 * V[5] - V[11]) / h3;
  c3[2] = (V[8] - 2 * V[0] + V[10] - V[9] + 2 * V[1] - V[11]) / h3;
  return 0;
}

/* check of the modal derivatives: Phi_i^T d2f/de_j de_k (forces) against the energy's c_ijk */
static double c3_max, c3_diff;

/* Static modal derivatives at static state u (the model holds it, cable made passive by
 * modal_cubic): K Theta_jk = -d2f/de_j de_k (f = f_int - f_cable, central differences of step h),
 * theta0 held, then M-orthogonalised to the modes; into th (3 x nd: jk = 11, 12, 22). */
static int modal_derivatives(fe_ctx_t *c, const double *u, const double *phi, double *th,
                             const double c3[4]) {
  ea_fe_model_t *m = c->m;
  const int nd = c->nd, nf = nd - 3;
  ea_fe_cable_phase_t ph;
  double L0, T, len;
  ea_fe_cable_get(m, &ph, &L0, &T, &len);
  if (ph != EA_FE_CABLE_PASSIVE) return 1;
  const double h = 0.002 / hypot(phi[nd - 3], phi[nd - 2]);
  double *Kb = malloc(sizeof(double) * (size_t)nd * (EA__FE_LDS + 3)), *f = Kb + EA__FE_LDS * nd;
  double *x = f + nd, *b = malloc(sizeof(double) * 3 * (size_t)nf);
  double *d2 = x + nd;
  if (!Kb || !b) {
    free(Kb);
    free(b);
    return 1;
  }
  memset(Kb, 0, sizeof(double) * (size_t)nd * EA__FE_LDS);
  ea__fe_assemble(m, u, EA_FE_CABLE_PASSIVE, L0, f, Kb);
  static const int pr[3][2] = {{0, 0}, {0, 1}, {1, 1}};
  for (int p = 0; p < 3; ++p) {
    const double *pj = phi + (size_t)pr[p][0] * nd, *pk = phi + (size_t)pr[p][1] * nd;
    memset(d2, 0, sizeof(double) * (size_t)nd);
    static const int sg[4][3] = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
    for (int q = 0; q < 4; ++q) {
      for (int i = 0; i < nd; ++i)
        x[i] = u[i] + h * (sg[q][0] * pj[i] + sg[q][1] * pk[i]);
      ea__fe_assemble(m, x, EA_FE_CABLE_PASSIVE, L0, f, NULL);
      for (int i = 0; i < nd; ++i)
        d2[i] += sg[q][2] * f[i] / (4 * h * h);
    }
    for (int i = 0; i < nf; ++i)
      b[(size_t)p * nf + i] = -d2[3 + i];
    /* the Galerkin quadratic coefficients from the forces: Phi_i^T d2f_jk */
    for (int i = 0; i < KM; ++i) {
      double sdot = 0;
      for (int r = 3; r < nd; ++r)
        sdot += phi[(size_t)i * nd + r] * d2[r];
      const int idx = i + pr[p][0] + pr[p][1]; /* c111, c112, c122, c222 */
      c3_max = fmax(c3_max, fabs(c3[idx]));
      c3_diff = fmax(c3_diff, fabs(sdot - c3[idx]));
    }
  }
  int rc = ea__fe_factor_free(m, Kb) || ea__fe_solve_factored(m, b, 3);
  for (int p = 0; p < 3 && !rc; ++p) {
    double *t = th + (size_t)p * nd;
    t[0] = t[1] = t[2] = 0;
    memcpy(t + 3, b + (size_t)p * nf, sizeof(double) * (size_t)nf);
    for (int i = 0; i < KM; ++i) {
      const double pm = dotM(c, u, phi + (size_t)i * nd, t);
      for (int r = 0; r < nd; ++r)
        t[r] -= pm * phi[(size_t)i * nd + r];
    }
  }
  free(Kb);
  free(b);
  return rc;
}

/* The planner's table, whose mode signs the FE modes of moving_sample take: the targets and
 * the output map are the table's, so a mode of the other sign would have the augmented model's
 * modal state, and the correction, of the wrong sign. */
static const ea_rom_table_t *sign_tb;
static double sign_cos_min = 1.0,
              sign_norm_dev; /* check: the FE tip per unit eta against the table's */
static int sign_flips, sign_checks;

static void align_to_table(double *phi, int nd, const double q[2]) {
  ea_rom_point_t p;
  ea_rom_table_eval(sign_tb, q[0], q[1], &p, NULL, NULL);
  for (int k = 0; k < KM; ++k) {
    double *f = phi + (size_t)k * nd;
    const double d = f[nd - 3] * p.tip[k][0] + f[nd - 2] * p.tip[k][1];
    const double nf = hypot(f[nd - 3], f[nd - 2]), nt = hypot(p.tip[k][0], p.tip[k][1]);
    sign_cos_min = fmin(sign_cos_min, fabs(d) / (nf * nt));
    sign_norm_dev = fmax(sign_norm_dev, fabs(nf / nt - 1));
    ++sign_checks;
    if (d < 0) {
      ++sign_flips;
      for (int i = 0; i < nd; ++i)
        f[i] = -f[i];
    }
  }
}

static int condensed_force(const moving_t *mv, double t, const double q2[2], const double q1[2],
                           const double *e, double *lam);
static int want_poly; /* BENCH_ROM_NL_POLY: the library's nonlinear reduced model (CMIP) */

/* The coefficients at ns samples of tr (t: time since the start). */
static int moving_sample(fe_ctx_t *c, const ea_traj_t *tr, int ns, moving_t *mv) {
  const int nd = c->nd;
  const double hL = 2e-3, ha = 4e-3;
  double *buf = malloc(sizeof(double) * (size_t)nd * (10 + 9 * KM));
  if (!buf) return 1;
  double *u = buf, *ref = buf + nd, *ph = buf + (size_t)nd * (1 + KM);
  double *u9 = malloc(sizeof(double) * (size_t)nd * 13), *th = u9 + 9 * nd, *jh = th + 3 * nd;
  if (!u9) {
    free(buf);
    return 1;
  }
  const double t0 = EA_TRAJ_AT(tr, 0, EA_TRAJ_t), T = EA_TRAJ_AT(tr, tr->n - 1, EA_TRAJ_t) - t0;
  mv->ns = ns;
  if (!mv->vec) mv->vec = malloc(sizeof(double) * (size_t)nd * 8 * NS_MAX);
  mv->nd = nd;
  if (!mv->vec) {
    free(buf);
    free(u9);
    return 1;
  }
  int have_ref = 0, rc = 0;
  static const int order[9] = {4, 3, 5, 1, 7, 0, 2, 6, 8};
  for (int s = 0; s < ns && !rc; ++s) {
    const double t = t0 + T * s / (ns - 1);
    double q[2], v[2], a[2];
    ea__traj_actuators(tr, t - t0, q, v, a);
    mv->t[s] = t - t0;
    for (int o = 0; o < 9 && !rc; ++o) {
      const int k = order[o], di = k % 3 - 1, dj = k / 3 - 1;
      double *p = ph + (size_t)k * KM * nd;
      rc = fe_point(c, q[0] + di * hL, q[1] + dj * ha, k == 4 ? u : u9 + (size_t)k * nd, p,
                    k == 4 ? (have_ref ? ref : NULL) : ph + (size_t)4 * KM * nd, NULL);
      if (k == 4 && !rc && !have_ref && sign_tb) /* the first sample: the table's mode signs */
        align_to_table(p, nd, q);
      if (k == 4 && !rc) {
        memcpy(ref, p, sizeof(double) * (size_t)nd * KM);
        have_ref = 1;
        rc = modal_cubic(c, u, p, mv->c3[s]) || modal_derivatives(c, u, p, th, mv->c3[s]);
        for (int pa = 0; pa < 3 && !rc; ++pa)
          for (int b2 = 0; b2 < 3; ++b2)
            mv->W[s][pa][b2] = dotM(c, u, th + (size_t)pa * nd, th + (size_t)b2 * nd);
        ea_fe_cable_get(c->m, NULL, &mv->L0[s], NULL, NULL);
        memcpy(mv->vec + (size_t)s * 8 * nd, u, sizeof(double) * (size_t)nd);
        memcpy(mv->vec + ((size_t)s * 8 + 1) * nd, p, sizeof(double) * (size_t)nd * KM);
      }
    }
    if (rc) break;
    memcpy(u9 + 4 * nd, u, sizeof(double) * (size_t)nd);
    for (int comp = 0; comp < 5; ++comp) {
      for (int x = 0; x < nd; ++x) {
        const double c0 = u9[4 * nd + x];
#define U9(k) u9[(size_t)(k)*nd + x]
        switch (comp) {
        case 0:
          jh[x] = (U9(5) - U9(3)) / (2 * hL);
          break;
        case 1:
          jh[x] = (U9(7) - U9(1)) / (2 * ha);
          break;
        case 2:
          jh[x] = (U9(5) - 2 * c0 + U9(3)) / (hL * hL);
          break;
        case 3:
          jh[x] = (U9(8) - U9(6) - U9(2) + U9(0)) / (4 * hL * ha);
          break;
        default:
          jh[x] = (U9(7) - 2 * c0 + U9(1)) / (ha * ha);
          break;
        }
#undef U9
      }
      for (int p = 0; p < 3; ++p)
        mv->E[s][p][comp] = dotM(c, u, th + (size_t)p * nd, jh);
      memcpy(mv->vec + ((size_t)s * 8 + 3 + comp) * nd, jh, sizeof(double) * (size_t)nd);
    }
    const double *P[9];
    for (int k = 0; k < 9; ++k)
      P[k] = ph + (size_t)k * KM * nd;
    double *d1 = buf + (size_t)nd * (1 + KM + 9 * KM); /* nd work */
    for (int j = 0; j < KM; ++j)
      for (int comp = 0; comp < 5; ++comp) {
        for (int x = 0; x < nd; ++x) {
          const size_t o = (size_t)j * nd + (size_t)x;
          const double c0 = P[4][o];
          switch (comp) {
          case 0:
            d1[x] = (P[5][o] - P[3][o]) / (2 * hL);
            break;
          case 1:
            d1[x] = (P[7][o] - P[1][o]) / (2 * ha);
            break;
          case 2:
            d1[x] = (P[5][o] - 2 * c0 + P[3][o]) / (hL * hL);
            break;
          case 3:
            d1[x] = (P[8][o] - P[6][o] - P[2][o] + P[0][o]) / (4 * hL * ha);
            break;
          default:
            d1[x] = (P[7][o] - 2 * c0 + P[1][o]) / (ha * ha);
            break;
          }
        }
        for (int pp = 0; pp < 3; ++pp)
          mv->R[s][pp][j][comp] = dotM(c, u, th + (size_t)pp * nd, d1);
        for (int i = 0; i < KM; ++i) {
          const double g = dotM(c, u, P[4] + (size_t)i * nd, d1);
          if (comp < 2)
            mv->G[s][i][j][comp] = g;
          else
            mv->D[s][i][j][comp - 2] = g;
        }
      }
  }
  for (int s = 0; s < mv->ns && !rc; ++s)
    for (int a = 0; a < 2; ++a) {
      g_max = fmax(g_max, fabs(mv->G[s][0][1][a]));
      g_asym = fmax(g_asym, fmax(fabs(mv->G[s][0][1][a] + mv->G[s][1][0][a]),
                                 fmax(fabs(mv->G[s][0][0][a]), fabs(mv->G[s][1][1][a]))));
    }
  free(buf);
  free(u9);
  return rc;
}

/* 5. the modal force with every other degree of freedom condensed statically, exactly (no
 * expansion in e): at time t of the sampled path (u_s, Phi, J, H, L0 interpolated by Catmull-Rom
 * splines over the samples), y with Phi^T M y = 0 and lambda solve
 *   f(u_s + Phi e + y) - f(u_s) + M (J q'' + H q' q') = M Phi lambda   (free rows)
 * by Newton (warm-started); lambda is the modal force (omega^2 e + B q'' + C q'q' + all orders
 * of e). */
static fe_ctx_t *cond_ctx;
static double *cond_w; /* work */
static int cond_fail;
static double cond_r0;           /* [N] the static state's residual at the last call */
static double cond_prev[3 * 64]; /* the last call's static state */
static int cond_have_prev;
static double cond_T[KM][3 * 64]; /* the condensed manifold's tangent dx/de_k at the last call */
static double cond_dlam[KM][KM];  /* dlambda_i/de_k at the last call: A^-1 */

/* The condensation's warm start in cond_w (after its work vectors, the layout of
 * condensed_force): y (nd), then lambda (KM). */
static double *cond_state(void) {
  const int nd = cond_ctx->nd;
  return cond_w + (size_t)(5 + 2 * KM + EA__FE_LDS) * nd + (size_t)(KM + 1) * (nd - 3);
}
static size_t cond_state_size(void) {
  return sizeof(double) * ((size_t)cond_ctx->nd + KM);
}
/* the next condensation starts from the static state */
static void cond_restart(void) {
  cond_have_prev = 0;
  memset(cond_state(), 0, cond_state_size());
}

static int condensed_force(const moving_t *mv, double t, const double q2[2], const double q1[2],
                           const double *e, double *lam) {
  fe_ctx_t *c = cond_ctx;
  ea_fe_model_t *m = c->m;
  const int nd = c->nd, nf = nd - 3;
  /* work layout */
  double *us = cond_w, *ph = us + nd, *aq = ph + KM * nd, *x = aq + nd, *f = x + nd, *f0 = f + nd;
  double *Mph = f0 + nd, *Kb = Mph + KM * nd, *b = Kb + EA__FE_LDS * nd, *y = cond_state();
  double *lam0 = y + nd; /* persistent: y and lambda of the last call */
  double fs = t / mv->t[mv->ns - 1] * (mv->ns - 1);
  int s = (int)floor(fs);
  s = s < 0 ? 0 : s > mv->ns - 2 ? mv->ns - 2 : s;
  const double w = fmin(fmax(fs - s, 0.0), 1.0), w2 = w * w, w3 = w2 * w;
  const double cw[4] = {-0.5 * w3 + w2 - 0.5 * w, 1.5 * w3 - 2.5 * w2 + 1,
                        -1.5 * w3 + 2 * w2 + 0.5 * w, 0.5 * w3 - 0.5 * w2};
  int idx[4];
  for (int k = 0; k < 4; ++k) {
    int j = s - 1 + k;
    idx[k] = j < 0 ? 0 : j > mv->ns - 1 ? mv->ns - 1 : j;
  }
  double L0 = 0;
  for (int k = 0; k < 4; ++k)
    L0 += cw[k] * mv->L0[idx[k]];
  for (int v = 0; v < 8; ++v) {
    double *dst = v == 0 ? us : v < 3 ? ph + (size_t)(v - 1) * nd : NULL;
    const double coef[5] = {q2[0], q2[1], q1[0] * q1[0], 2 * q1[0] * q1[1], q1[1] * q1[1]};
    if (v == 3) memset(aq, 0, sizeof(double) * (size_t)nd);
    for (int i = 0; i < nd; ++i) {
      double sum = 0;
      for (int k = 0; k < 4; ++k)
        sum += cw[k] * mv->vec[((size_t)idx[k] * 8 + (size_t)v) * nd + (size_t)i];
      if (dst)
        dst[i] = sum;
      else
        aq[i] += coef[v - 3] * sum;
    }
  }
  /* the interpolated static state back onto equilibrium (theta0 and L0 as interpolated): an
   * axial strain error times EA would act as a large spurious prestress on the modes */
  double r0 = 0;
  /* from the last call's equilibrium (a neighbouring time) with the interpolated clamp: the
   * interpolated state itself can be too far off for Newton */
  if (cond_have_prev) memcpy(us + 3, cond_prev + 3, sizeof(double) * (size_t)(nd - 3));
  int ok = 0;
  for (int it = 0; it < 40 && !ok; ++it) {
    memset(Kb, 0, sizeof(double) * (size_t)nd * EA__FE_LDS);
    ea__fe_assemble(m, us, EA_FE_CABLE_PASSIVE, L0, f, Kb);
    r0 = 0;
    for (int i = 3; i < nd; ++i) {
      b[i - 3] = f[i]; /* ea__fe_assemble includes the gravity load */
      r0 = fmax(r0, fabs(b[i - 3]));
    }
    if (ea__fe_factor_free(m, Kb) || ea__fe_solve_factored(m, b, 1)) return 1;
    double dmax = 0;
    for (int i = 3; i < nd; ++i)
      dmax = fmax(dmax, fabs(b[i - 3]));
    const double sc = dmax > 5e-3 ? 5e-3 / dmax : 1.0;
    for (int i = 3; i < nd; ++i)
      us[i] -= sc * b[i - 3];
    ok = sc == 1.0 && dmax < 1e-12;
  }
  if (!ok) {
    cond_r0 = r0;
    cond_have_prev = 0;
    return 1;
  }
  memcpy(cond_prev, us, sizeof(double) * (size_t)nd);
  cond_have_prev = 1;
  cond_r0 = r0;
  for (int k = 0; k < KM; ++k) {
    memset(Mph + (size_t)k * nd, 0, sizeof(double) * (size_t)nd);
    ea__fe_band_gemv(m, 1.0, m->Mb, ph + (size_t)k * nd, Mph + (size_t)k * nd);
  }
  double *Ma = x; /* M a_qs, kept in f0 after the baseline */
  memset(Ma, 0, sizeof(double) * (size_t)nd);
  ea__fe_band_gemv(m, 1.0, m->Mb, aq, Ma);
  ea__fe_assemble(m, us, EA_FE_CABLE_PASSIVE, L0, f0, NULL);
  for (int i = 0; i < nd; ++i)
    f0[i] -= Ma[i]; /* r = f(x) - f0 */
  for (int k = 0; k < KM; ++k)
    lam[k] = lam0[k];
  int conv = 0;
  double last_dmax = 0;
  for (int it = 0; it < 80 && !conv; ++it) {
    for (int i = 0; i < nd; ++i) {
      x[i] = us[i] + y[i];
      for (int k = 0; k < KM; ++k)
        x[i] += ph[(size_t)k * nd + i] * e[k];
    }
    memset(Kb, 0, sizeof(double) * (size_t)nd * EA__FE_LDS);
    ea__fe_assemble(m, x, EA_FE_CABLE_PASSIVE, L0, f, Kb);
    for (int i = 3; i < nd; ++i) {
      double R = f[i] - f0[i];
      for (int k = 0; k < KM; ++k)
        R -= Mph[(size_t)k * nd + i] * lam[k];
      b[i - 3] = R;
      for (int k = 0; k < KM; ++k)
        b[(size_t)(k + 1) * nf + (i - 3)] = Mph[(size_t)k * nd + i];
    }
    double rn = 0;
    for (int i = 0; i < nf; ++i)
      rn = fmax(rn, fabs(b[i]));
    if (ea__fe_factor_free(m, Kb) || ea__fe_solve_factored(m, b, KM + 1)) {
      return 1;
    }
    /* dy = -z + W dl; Phi^T M W dl = Phi^T M (z - y) */
    double A[KM][KM], rhs[KM];
    for (int i = 0; i < KM; ++i) {
      rhs[i] = 0;
      for (int r = 3; r < nd; ++r)
        rhs[i] += Mph[(size_t)i * nd + r] * (b[r - 3] - y[r]);
      for (int j = 0; j < KM; ++j) {
        A[i][j] = 0;
        for (int r = 3; r < nd; ++r)
          A[i][j] += Mph[(size_t)i * nd + r] * b[(size_t)(j + 1) * nf + (r - 3)];
      }
    }
    const double det = A[0][0] * A[1][1] - A[0][1] * A[1][0];
    const double dl[2] = {(rhs[0] * A[1][1] - rhs[1] * A[0][1]) / det,
                          (A[0][0] * rhs[1] - A[1][0] * rhs[0]) / det};
    double dmax = 0;
    for (int r = 3; r < nd; ++r) {
      double dy = -b[r - 3];
      for (int j = 0; j < KM; ++j)
        dy += b[(size_t)(j + 1) * nf + (r - 3)] * dl[j];
      dmax = fmax(dmax, fabs(dy));
    }
    /* steps limited to 5 mm / 5 mrad (a full Newton step can leave the cable's side) */
    const double sc = dmax > 5e-3 ? 5e-3 / dmax : 1.0;
    for (int r = 3; r < nd; ++r) {
      double dy = -b[r - 3];
      for (int j = 0; j < KM; ++j)
        dy += b[(size_t)(j + 1) * nf + (r - 3)] * dl[j];
      y[r] += sc * dy;
    }
    for (int k = 0; k < KM; ++k)
      lam[k] += sc * dl[k];
    (void)rn;
    conv = sc == 1.0 && dmax < 1e-10;
    last_dmax = dmax;
  }
  if (!conv || !isfinite(lam[0]) || !isfinite(lam[1])) { /* start over from the static state */
    if (cond_fail < 5)
      fprintf(stderr,
              "bench_rom_nl: condensation at t %.4f s, e (%.4g, %.4g) did not converge (last step "
              "%.3g, static residual %.3g N)\n",
              t, e[0], e[1], last_dmax, cond_r0);
    ++cond_fail;
    memset(y, 0, sizeof(double) * (size_t)nd);
    lam0[0] = lam0[1] = 0;
    return 1;
  }
  for (int k = 0; k < KM; ++k)
    lam0[k] = lam[k];
  /* the tangent: d/de_k of (free rows) f(x) - f0 - M Phi lambda = 0, Phi^T M y = 0 gives
   * dx/de_k = W A^-1 e_k with W = K^-1 M Phi and A = Phi^T M W (the last Newton step's, taken at
   * the converged state to within the step) */
  {
    double A[KM][KM] = {{0}};
    for (int i = 0; i < KM; ++i)
      for (int j = 0; j < KM; ++j)
        for (int r = 3; r < nd; ++r)
          A[i][j] += Mph[(size_t)i * nd + r] * b[(size_t)(j + 1) * nf + (r - 3)];
    const double det = A[0][0] * A[1][1] - A[0][1] * A[1][0];
    const double Ai[KM][KM] = {{A[1][1] / det, -A[0][1] / det}, {-A[1][0] / det, A[0][0] / det}};
    memcpy(cond_dlam, Ai, sizeof cond_dlam);
    for (int k = 0; k < KM; ++k) {
      cond_T[k][0] = cond_T[k][1] = cond_T[k][2] = 0;
      for (int r = 3; r < nd; ++r)
        cond_T[k][r] =
            b[(size_t)1 * nf + (r - 3)] * Ai[0][k] + b[(size_t)2 * nf + (r - 3)] * Ai[1][k];
    }
  }
  return 0;
}

/* The condensed force with the manifold's exact inertia (CMI exact): lambda at e, the modal mass
 * Mt = T^T M T of the tangent T = dx/de and the convective force c = T^T M d2y/de2[e', e'], the
 * latter by central differences of T along e' (two more condensations). The condensation's warm
 * start is the call at e. */
static int condensed_inertia(const moving_t *mv, double t, const double q2[2], const double q1[2],
                             const double *e, const double *ed, double *lam, double Mt[KM][KM],
                             double cv[KM]) {
  fe_ctx_t *c = cond_ctx;
  const int nd = c->nd;
  double *y = cond_state();
  if (condensed_force(mv, t, q2, q1, e, lam)) return 1;
  static double T0[KM][3 * 64], Tp[KM][3 * 64], Tm[KM][3 * 64], MT[KM][3 * 64], ys[3 * 64 + KM];
  memcpy(T0, cond_T, sizeof T0);
  for (int k = 0; k < KM; ++k) {
    memset(MT[k], 0, sizeof(double) * (size_t)nd);
    ea__fe_band_gemv(c->m, 1.0, c->m->Mb, T0[k], MT[k]);
  }
  for (int i = 0; i < KM; ++i)
    for (int j = 0; j < KM; ++j) {
      double d = 0;
      for (int r = 0; r < nd; ++r)
        d += T0[i][r] * MT[j][r];
      Mt[i][j] = d;
    }
  cv[0] = cv[1] = 0;
  const double sp = hypot(ed[0], ed[1]);
  if (!(sp > 0)) return 0;
  memcpy(ys, y, cond_state_size());
  const double *ph = cond_w + nd; /* Phi_1 at t, as condensed_force interpolated it */
  const double h = 0.002 / hypot(ph[nd - 3], ph[nd - 2]);
  double ep[KM], em[KM], lp[KM];
  for (int k = 0; k < KM; ++k) {
    ep[k] = e[k] + h * ed[k] / sp;
    em[k] = e[k] - h * ed[k] / sp;
  }
  int rc = condensed_force(mv, t, q2, q1, ep, lp);
  if (!rc) memcpy(Tp, cond_T, sizeof Tp);
  memcpy(y, ys, cond_state_size());
  rc = rc || condensed_force(mv, t, q2, q1, em, lp);
  if (!rc) memcpy(Tm, cond_T, sizeof Tm);
  memcpy(y, ys, cond_state_size());
  if (rc) return 1;
  /* d2y/de2[e', e'] = |e'|^2 (T(e + h d) - T(e - h d)) d / (2 h), d = e' / |e'| */
  for (int i = 0; i < KM; ++i) {
    double s = 0;
    for (int r = 0; r < nd; ++r) {
      double a = 0;
      for (int k = 0; k < KM; ++k)
        a += (Tp[k][r] - Tm[k][r]) * ed[k] / sp;
      s += MT[i][r] * a;
    }
    cv[i] = sp * sp * s / (2 * h);
  }
  return 0;
}

/* The model's modal equations along tr (RK4, dt 1e-4) as ea_traj_rom_predict integrates them,
 * with the moving-shape terms of mv added when mv is not NULL (scaled by w: 1 both, bit 1 G
 * only, bit 2 D only); the residual peak of the free vibration at the goal over 3 s. */
static void ea_rhs(const ea_rom_table_t *tb, const ea_traj_t *tr, const moving_t *mv, int terms,
                   double t, const double *z, double *dz) {
  double q[2], v[2], a[2];
  ea__traj_actuators(tr, t, q, v, a);
  ea_rom_point_t p;
  ea_rom_table_eval(tb, q[0], q[1], &p, NULL, NULL);
  double G[KM][KM][2] = {{{0}}}, D[KM][KM][3] = {{{0}}}, c3[4] = {0}, E[3][5] = {{0}},
         W[3][3] = {{0}}, R[3][KM][5] = {{{0}}};
  if (mv) {
    double f = t / mv->t[mv->ns - 1] * (mv->ns - 1);
    int s = (int)floor(f);
    s = s < 0 ? 0 : s > mv->ns - 2 ? mv->ns - 2 : s;
    f = fmin(fmax(f - s, 0.0), 1.0);
    for (int i = 0; i < KM; ++i)
      for (int j = 0; j < KM; ++j) {
        for (int c = 0; c < 2; ++c)
          G[i][j][c] = (1 - f) * mv->G[s][i][j][c] + f * mv->G[s + 1][i][j][c];
        for (int c = 0; c < 3; ++c)
          D[i][j][c] = (1 - f) * mv->D[s][i][j][c] + f * mv->D[s + 1][i][j][c];
      }
    for (int pp = 0; pp < 3; ++pp)
      for (int c = 0; c < 5; ++c)
        E[pp][c] = (1 - f) * mv->E[s][pp][c] + f * mv->E[s + 1][pp][c];
    for (int pp = 0; pp < 3; ++pp)
      for (int c = 0; c < 3; ++c)
        W[pp][c] = (1 - f) * mv->W[s][pp][c] + f * mv->W[s + 1][pp][c];
    for (int pp = 0; pp < 3; ++pp)
      for (int j = 0; j < KM; ++j)
        for (int c = 0; c < 5; ++c)
          R[pp][j][c] = (1 - f) * mv->R[s][pp][j][c] + f * mv->R[s + 1][pp][j][c];
    for (int c = 0; c < ((terms & 8) ? 1 : 4); ++c) /* bit 8: mode 1's own c111 alone */
      c3[c] = (1 - f) * mv->c3[s][c] + f * mv->c3[s + 1][c];
  }
  double lam[KM] = {0}, Mt[KM][KM] = {{1, 0}, {0, 1}}, cv[KM] = {0};
  if (mv && (terms & 128 || terms & 256)) {
    const double *ph0 = mv->vec + (size_t)mv->nd;
    const int nd = mv->nd;
    emax_tip[0] = fmax(emax_tip[0], fabs(z[0]) * hypot(ph0[nd - 3], ph0[nd - 2]));
    emax_tip[1] = fmax(emax_tip[1], fabs(z[2]) * hypot(ph0[2 * nd - 3], ph0[2 * nd - 2]));
  }
  if (terms & 128) {
    const double e[KM] = {z[0], z[2]}, ed[KM] = {z[1], z[3]};
    if (condensed_inertia(mv, t, a, v, e, ed, lam, Mt, cv)) lam[0] = lam[1] = NAN;
  } else if (terms & 32) {
    const double e[KM] = {z[0], z[2]};
    if (condensed_force(mv, t, a, v, e, lam)) lam[0] = lam[1] = NAN;
  }
  for (int i = 0; i < KM; ++i) {
    double F = -(p.B[i][0] * a[0] + p.B[i][1] * a[1]) -
               (p.C[i][0] * v[0] * v[0] + 2 * p.C[i][1] * v[0] * v[1] + p.C[i][2] * v[1] * v[1]);
    if (terms & 160) F = -lam[i] + p.omega2[i] * z[2 * i]; /* the whole force condensed */
    for (int j = 0; j < KM; ++j) {
      const double e = z[2 * j], ed = z[2 * j + 1];
      if (terms & 1)
        F -= 2 * (G[i][j][0] * v[0] + G[i][j][1] * v[1]) * ed +
             (G[i][j][0] * a[0] + G[i][j][1] * a[1]) * e;
      if (terms & 2)
        F -= (D[i][j][0] * v[0] * v[0] + 2 * D[i][j][1] * v[0] * v[1] + D[i][j][2] * v[1] * v[1]) *
             e;
    }
    if (terms & 12) /* the quadratic modal force dV3/de_i = c_ijk e_j e_k / 2 */
      F -= 0.5 * (c3[i] * z[0] * z[0] + 2 * c3[i + 1] * z[0] * z[2] + c3[i + 2] * z[2] * z[2]);
    if (terms & 16) /* the manifold's curvature in the test function: e_k Theta_ik^T M u_s'' */
      for (int k = 0; k < KM; ++k) {
        const double *Ek = E[i + k];
        F -= z[2 * k] * (Ek[0] * a[0] + Ek[1] * a[1] + Ek[2] * v[0] * v[0] +
                         2 * Ek[3] * v[0] * v[1] + Ek[4] * v[1] * v[1]);
      }
    if (terms & 256) {
      /* the manifold y = Theta e e / 2 and the moving modes, second order: the gauge
       * Phi^T M y = 0 gives Phi_i^T M y'' = -Phi_i''^T M y - 2 Phi_i'^T M y', and the test
       * function's dy/de = Theta e meets the modes' motion 2 Phi' e' + Phi'' e. R[p][j][c] =
       * Theta_p^T M (dPhi_j/dq_c, d2Phi_j/dq_cq_d); a time derivative of Phi_j is
       * dPhi_j/dq_a q_a' (Rd1), its second dPhi_j/dq_a q_a'' + d2Phi_j/dq_aq_b q_a' q_b' (Rd2). */
      double Rd1[3][KM], Rd2[3][KM];
      for (int pp = 0; pp < 3; ++pp)
        for (int j = 0; j < KM; ++j) {
          Rd1[pp][j] = R[pp][j][0] * v[0] + R[pp][j][1] * v[1];
          Rd2[pp][j] = R[pp][j][0] * a[0] + R[pp][j][1] * a[1] + R[pp][j][2] * v[0] * v[0] +
                       2 * R[pp][j][3] * v[0] * v[1] + R[pp][j][4] * v[1] * v[1];
        }
      double x = 0;
      for (int k = 0; k < KM; ++k)
        for (int j = 0; j < KM; ++j) {
          const double ek = z[2 * k], ej = z[2 * j], edj = z[2 * j + 1];
          x += ek * (2 * edj * Rd1[i + k][j] + ej * Rd2[i + k][j]); /* (Theta e)^T M Phi'' */
          x -= 0.5 * ek * ej * Rd2[k + j][i];                       /* Phi_i''^T M y */
          x -= 2 * ek * edj * Rd1[k + j][i];                        /* 2 Phi_i'^T M y' */
        }
      F -= x;
    }
    dz[2 * i] = z[2 * i + 1];
    dz[2 * i + 1] = -p.omega2[i] * z[2 * i] + F;
  }
  if (terms & 64) {
    /* the inertia of the manifold's motion: y = Theta_jk e_j e_k / 2 moves with e, so
     * y'' = V e'' + Theta_jk e_j' e_k' with V_k = dy/de_k = Theta_jk e_j; projected on V
     * (Phi^T M V = 0): (I + V^T M V) e'' = (the force above) - V^T M Theta_jk e_j' e_k'. Theta_jk
     * is W's index j + k. */
    const double e[KM] = {z[0], z[2]}, ed[KM] = {z[1], z[3]};
    double A[KM][KM], r[KM];
    for (int i = 0; i < KM; ++i) {
      double ci = 0;
      for (int k = 0; k < KM; ++k)
        for (int j = 0; j < KM; ++j)
          for (int l = 0; l < KM; ++l)
            ci += e[k] * ed[j] * ed[l] * W[i + k][j + l];
      r[i] = dz[2 * i + 1] - ci;
      for (int l = 0; l < KM; ++l) {
        double m = i == l ? 1.0 : 0.0;
        for (int k = 0; k < KM; ++k)
          for (int n = 0; n < KM; ++n)
            m += e[k] * e[n] * W[i + k][l + n];
        A[i][l] = m;
      }
    }
    const double det = A[0][0] * A[1][1] - A[0][1] * A[1][0];
    dz[1] = (r[0] * A[1][1] - r[1] * A[0][1]) / det;
    dz[3] = (A[0][0] * r[1] - A[1][0] * r[0]) / det;
  }
  if (terms & 128) { /* Mt e'' = (the force above) - cv */
    const double r[KM] = {dz[1] - cv[0], dz[3] - cv[1]};
    const double det = Mt[0][0] * Mt[1][1] - Mt[0][1] * Mt[1][0];
    dz[1] = (r[0] * Mt[1][1] - r[1] * Mt[0][1]) / det;
    dz[3] = (Mt[0][0] * r[1] - Mt[1][0] * r[0]) / det;
  }
}

static double cm_dt = 2e-4; /* [s] RK4 step with the condensed force (a Newton solve per stage) */

static double integrate_z(const ea_rom_table_t *tb, const ea_traj_t *tr, const moving_t *mv,
                          int terms, double *zout) {
  const double T = EA_TRAJ_AT(tr, tr->n - 1, EA_TRAJ_t) - EA_TRAJ_AT(tr, 0, EA_TRAJ_t);
  const double dt = (terms & 160) ? cm_dt : 1e-4; /* 512: tabulated, the default step */
  const int n = (int)ceil(T / dt - 1e-9);
  if (terms & 160) /* the condensation starts from the static state */
    cond_restart();
  const double h = T / n;
  double z[2 * KM] = {0}, k1[2 * KM], k2[2 * KM], k3[2 * KM], k4[2 * KM], zt[2 * KM];
  for (int i = 0; i < n; ++i) {
    const double t = i * h;
    ea_rhs(tb, tr, mv, terms, t, z, k1);
    for (int j = 0; j < 2 * KM; ++j)
      zt[j] = z[j] + 0.5 * h * k1[j];
    ea_rhs(tb, tr, mv, terms, t + 0.5 * h, zt, k2);
    for (int j = 0; j < 2 * KM; ++j)
      zt[j] = z[j] + 0.5 * h * k2[j];
    ea_rhs(tb, tr, mv, terms, t + 0.5 * h, zt, k3);
    for (int j = 0; j < 2 * KM; ++j)
      zt[j] = z[j] + h * k3[j];
    ea_rhs(tb, tr, mv, terms, t + h, zt, k4);
    for (int j = 0; j < 2 * KM; ++j)
      z[j] += h / 6 * (k1[j] + 2 * k2[j] + 2 * k3[j] + k4[j]);
  }
  ea_rom_point_t p;
  ea_rom_table_eval(tb, EA_TRAJ_AT(tr, tr->n - 1, EA_TRAJ_cable_length),
                    EA_TRAJ_AT(tr, tr->n - 1, EA_TRAJ_cable_angle), &p, NULL, NULL);
  double peak = 0;
  const int ns = 3 * 64 * 4;
  for (int i = 0; i <= ns; ++i) {
    const double t = 3.0 * i / ns;
    double dx = 0, dy = 0;
    for (int k = 0; k < KM; ++k) {
      const double w = sqrt(fmax(p.omega2[k], 1e-300));
      const double e = z[2 * k] * cos(w * t) + z[2 * k + 1] / w * sin(w * t);
      dx += p.tip[k][0] * e;
      dy += p.tip[k][1] * e;
    }
    peak = fmax(peak, hypot(dx, dy));
  }
  if (!isfinite(z[0]) || !isfinite(z[2])) peak = NAN;
  if (zout) memcpy(zout, z, sizeof z);
  return peak;
}

static double integrate(const ea_rom_table_t *tb, const ea_traj_t *tr, const moving_t *mv,
                        int terms) {
  return integrate_z(tb, tr, mv, terms, NULL);
}

/* CMIP: the library's nonlinear reduced model (model/fe_romnl.c), sampled on tr's path (41
 * points) and integrated along it (RK4, dt 0.1 ms); its end state into z (NULL: not wanted), the
 * sampling's wall time into *t_sample. */
static ea_romnl_t *nlm; /* for the line's arm and tip mass */
static double nl_fit_err, nl_time;
static int nl_dropped, nl_samples;
static double integrate_nl(const ea_rom_table_t *tb, const ea_traj_t *tr, double *z,
                           double *t_sample) {
  ea_rom_prediction_t pr;
  ea_error_t e = {0};
  if (!nlm || ea_traj_romnl_sample(nlm, tb, tr, 41, &e) ||
      ea_traj_romnl_predict(tb, nlm, tr, 1e-4, 3.0, &pr, NULL, &e)) {
    fprintf(stderr, "bench_rom_nl: CMIP: %s\n", e.msg);
    return NAN;
  }
  ea_romnl_info_t ri;
  ea_romnl_info(nlm, &ri);
  nl_fit_err = fmax(nl_fit_err, ri.fit_error);
  nl_dropped += ri.nodes_dropped;
  nl_time += ri.time_s;
  ++nl_samples;
  if (t_sample) *t_sample = ri.time_s;
  for (int k = 0; z && k < KM; ++k) {
    z[2 * k] = pr.eta[k];
    z[2 * k + 1] = pr.eta_rate[k];
  }
  return pr.residual_peak;
}

/* 4. the at-rest plan corrected for the neglected terms without touching the transcription: the
 * goal's modal targets (eta_i, eta_i') moved until the model with those terms (integrated along
 * the re-planned trajectory) ends at rest. The unknowns and residuals are tip amplitudes at the
 * goal, so that the four are comparable (as planner/nlp/plan_refine.c scales them): x = (eta_i
 * |tip_i|, eta_i' |tip_i| / omega_i), F(x) = the augmented model's end state z in the same
 * scaling. The planner holds the linear model's end state at the target, so the model says
 * dF/dx = I; the neglected terms change that by the nonlinearity. */

typedef struct {
  int evals;     /* model integrations (each but the first after a warm re-plan) */
  int failed;    /* evaluations that failed (re-plan or integration) */
  int fd;        /* Jacobians rebuilt by forward differences */
  int converged; /* the model's residual peak < CORR_TOL */
  double pred;   /* [m] the model's residual peak at the returned plan */
  double t_int;  /* [s] wall time in the model's integrations */
  double t_mv;   /* [s] in the moving-shape sampling */
  double t_plan; /* [s] in the re-plans */
} corr_info_t;

enum { CORR_MAX_EVALS = 15, CORR_HALVINGS = 4 };
static const double CORR_TOL = 1e-5;  /* [m] the model's residual peak that ends the search */
static const double CORR_FD_H = 2e-4; /* [m] forward-difference step of the tip amplitudes */
static const double CORR_ARMIJO = 1e-4;
static int corr_verbose; /* BENCH_ROM_NL_VERBOSE: every evaluation on stderr */

static int traj_copy(ea_traj_t *dst, const ea_traj_t *src) {
  if (ea_traj_alloc(dst, src->n)) return 1;
  double *d = dst->data;
  *dst = *src;
  dst->data = d;
  memcpy(d, src->data, sizeof(double) * (size_t)src->n * EA_TRAJ_NCOL);
  return 0;
}

/* One evaluation at tip amplitudes x (replan = 0: tr is already the plan for x): F (4 values,
 * [m]) and the model's residual peak. 0 on success. */
static int corr_eval(ea_planner_t *pl, fe_ctx_t *c, const double sc[2 * KM], const double *x,
                     int replan, ea_traj_t *tr, int terms, double *F, double *peak,
                     corr_info_t *ci) {
  static moving_t mv;
  const ea_rom_table_t *tb = ea_planner_rom_table(pl);
  ++ci->evals;
  double t0 = ea_bench_now();
  if (replan) {
    double eta[KM], rate[KM];
    for (int k = 0; k < KM; ++k) {
      eta[k] = x[2 * k] / sc[2 * k];
      rate[k] = x[2 * k + 1] / sc[2 * k + 1];
    }
    ea_error_t e;
    ea_plan_info_t info;
    if (ea_planner_set_terminal_modes(pl, eta, rate, &e) ||
        (ea_planner_solve(pl, EA_PLAN_WARM, NULL, &info, &e) &&
         ea_planner_solve(pl, EA_PLAN_COLD, NULL, &info, &e)) ||
        ea_planner_trajectory(pl, tr, &e)) {
      ci->t_plan += ea_bench_now() - t0;
      ++ci->failed;
      if (corr_verbose)
        fprintf(stderr, "  eval %d x [mm] (%.3f %.3f %.3f %.3f): re-plan failed: %s\n", ci->evals,
                1e3 * x[0], 1e3 * x[1], 1e3 * x[2], 1e3 * x[3], e.msg);
      return 1;
    }
  }
  double t1 = ea_bench_now();
  ci->t_plan += t1 - t0;
  double z[2 * KM];
  if (want_poly) { /* the library's model: its own sampling, then its integration */
    double ts = 0;
    *peak = integrate_nl(tb, tr, z, &ts);
    ci->t_mv += ts;
    ci->t_int += ea_bench_now() - t1 - ts;
  } else {
    if (moving_sample(c, tr, 41, &mv)) {
      ++ci->failed;
      return 1;
    }
    double t2 = ea_bench_now();
    ci->t_mv += t2 - t1;
    *peak = integrate_z(tb, tr, &mv, terms, z);
    ci->t_int += ea_bench_now() - t2;
  }
  for (int j = 0; j < 2 * KM; ++j)
    F[j] = z[j] * sc[j];
  if (corr_verbose)
    fprintf(stderr,
            "  eval %d x [mm] (%.3f %.3f %.3f %.3f) F [mm] (%.3f %.3f %.3f %.3f) peak %.4f mm\n",
            ci->evals, 1e3 * x[0], 1e3 * x[1], 1e3 * x[2], 1e3 * x[3], 1e3 * F[0], 1e3 * F[1],
            1e3 * F[2], 1e3 * F[3], 1e3 * *peak);
  if (!isfinite(*peak)) {
    ++ci->failed;
    return 1;
  }
  return 0;
}

static double norm4(const double *v) {
  double s = 0;
  for (int j = 0; j < 2 * KM; ++j)
    s += v[j] * v[j];
  return sqrt(s);
}

/* Solve the 4 x 4 system J p = b (J kept) by Gaussian elimination with partial pivoting. */
static int solve4(const double J[2 * KM][2 * KM], const double *b, double *p) {
  enum { N = 2 * KM };
  double A[N][N + 1];
  for (int r = 0; r < N; ++r) {
    for (int j = 0; j < N; ++j)
      A[r][j] = J[r][j];
    A[r][N] = b[r];
  }
  for (int col = 0; col < N; ++col) {
    int pv = col;
    for (int r = col + 1; r < N; ++r)
      if (fabs(A[r][col]) > fabs(A[pv][col])) pv = r;
    if (!(fabs(A[pv][col]) > 1e-12)) return 1;
    for (int j = 0; j <= N; ++j) {
      const double tmp = A[col][j];
      A[col][j] = A[pv][j];
      A[pv][j] = tmp;
    }
    for (int r = col + 1; r < N; ++r) {
      const double f = A[r][col] / A[col][col];
      for (int j = col; j <= N; ++j)
        A[r][j] -= f * A[col][j];
    }
  }
  for (int r = N - 1; r >= 0; --r) {
    double v = A[r][N];
    for (int j = r + 1; j < N; ++j)
      v -= A[r][j] * p[j];
    p[r] = v / A[r][r];
  }
  return 0;
}

/* The globalised Newton on F(x) = 0 from x = 0 (tr: the at-rest plan, targets zero): J = I (or
 * by forward differences with fd_first), Broyden updates on accepted steps; a step is accepted
 * when |F| falls by the Armijo fraction of the predicted decrease, else it is halved (at most
 * CORR_HALVINGS times; a failed re-plan or integration counts as not accepted); when no step
 * length is accepted J is rebuilt by forward differences (and the search stops when a fresh
 * Jacobian's step fails). Stops when the model's residual peak < CORR_TOL or after
 * CORR_MAX_EVALS evaluations. The plan of least |F| into tr. Returns 0, or 1 when even the
 * first evaluation failed. */
static int corrected_plan(ea_planner_t *pl, fe_ctx_t *c, ea_traj_t *tr, int terms, int fd_first,
                          corr_info_t *ci) {
  enum { N = 2 * KM };
  memset(ci, 0, sizeof *ci);
  const ea_rom_table_t *tb = ea_planner_rom_table(pl);
  ea_rom_point_t p;
  ea_rom_table_eval(tb, EA_TRAJ_AT(tr, tr->n - 1, EA_TRAJ_cable_length),
                    EA_TRAJ_AT(tr, tr->n - 1, EA_TRAJ_cable_angle), &p, NULL, NULL);
  double sc[N];
  for (int k = 0; k < KM; ++k) {
    sc[2 * k] = hypot(p.tip[k][0], p.tip[k][1]);
    sc[2 * k + 1] = sc[2 * k] / sqrt(fmax(p.omega2[k], 1e-300));
  }
  double x[N] = {0}, F[N], peak, xt[N], Ft[N], pt, J[N][N] = {{0}};
  ea_traj_t best = {0};
  if (corr_eval(pl, c, sc, x, 0, tr, terms, F, &peak, ci) || traj_copy(&best, tr)) {
    ea_traj_free(&best);
    ci->pred = NAN;
    return 1;
  }
  for (int j = 0; j < N; ++j)
    J[j][j] = 1.0;
  int fresh = 0, need_fd = fd_first;
  while (peak >= CORR_TOL && ci->evals < CORR_MAX_EVALS) {
    if (need_fd) { /* J by forward differences about x */
      if (ci->evals + N > CORR_MAX_EVALS) break;
      int bad = 0;
      for (int j = 0; j < N && !bad; ++j) {
        memcpy(xt, x, sizeof x);
        double h = CORR_FD_H;
        xt[j] += h;
        bad = corr_eval(pl, c, sc, xt, 1, tr, terms, Ft, &pt, ci);
        if (bad && ci->evals < CORR_MAX_EVALS) { /* the backward difference */
          h = -h;
          xt[j] = x[j] + h;
          bad = corr_eval(pl, c, sc, xt, 1, tr, terms, Ft, &pt, ci);
        }
        for (int r = 0; r < N && !bad; ++r)
          J[r][j] = (Ft[r] - F[r]) / h;
      }
      if (bad) break;
      ++ci->fd;
      fresh = 1;
      need_fd = 0;
    }
    double step[N], mF[N];
    for (int j = 0; j < N; ++j)
      mF[j] = -F[j];
    if (solve4((const double(*)[N])J, mF, step)) {
      if (fresh) break;
      need_fd = 1;
      continue;
    }
    const double f0 = norm4(F);
    double lam = 1.0;
    int acc = 0;
    for (int h = 0; h <= CORR_HALVINGS && ci->evals < CORR_MAX_EVALS; ++h, lam *= 0.5) {
      for (int j = 0; j < N; ++j)
        xt[j] = x[j] + lam * step[j];
      if (corr_eval(pl, c, sc, xt, 1, tr, terms, Ft, &pt, ci)) continue;
      if (norm4(Ft) <= (1.0 - CORR_ARMIJO * lam) * f0) {
        acc = 1;
        break;
      }
    }
    if (!acc) {
      if (fresh || ci->evals >= CORR_MAX_EVALS) break; /* a fresh Jacobian's step failed */
      need_fd = 1;
      continue;
    }
    /* Broyden: J += (dF - J s) s^T / s^T s */
    double s[N], ss = 0;
    for (int j = 0; j < N; ++j) {
      s[j] = xt[j] - x[j];
      ss += s[j] * s[j];
    }
    for (int r = 0; r < N; ++r) {
      double u = Ft[r] - F[r];
      for (int j = 0; j < N; ++j)
        u -= J[r][j] * s[j];
      for (int j = 0; j < N; ++j)
        J[r][j] += u * s[j] / ss;
    }
    memcpy(x, xt, sizeof x);
    memcpy(F, Ft, sizeof F);
    peak = pt;
    fresh = 0;
    if (traj_copy(&best, tr)) break;
  }
  ci->pred = peak;
  ci->converged = peak < CORR_TOL;
  const int rc = traj_copy(tr, &best);
  ea_traj_free(&best);
  return rc;
}

/* The crude loop it replaces, for comparison: target <- target - z_end (J = I, full steps, no
 * globalisation), 6 iterations. */
static int crude_plan(ea_planner_t *pl, fe_ctx_t *c, ea_traj_t *tr, int terms, corr_info_t *ci) {
  enum { N = 2 * KM };
  memset(ci, 0, sizeof *ci);
  const double sc[N] = {1, 1, 1, 1};
  double x[N] = {0}, F[N], peak = NAN;
  for (int it = 0; it <= 6; ++it) {
    if (corr_eval(pl, c, sc, x, it > 0, tr, terms, F, &peak, ci)) {
      ci->pred = NAN;
      return 1;
    }
    if (peak < CORR_TOL || it == 6) break;
    for (int j = 0; j < N; ++j)
      x[j] -= F[j];
  }
  ci->pred = peak;
  ci->converged = peak < CORR_TOL;
  return 0;
}

static int ctx_alloc(const ea_arm_t *arm, double tip_mass, fe_ctx_t *c) {
  memset(c, 0, sizeof *c);
  ea_fe_settings_t fs;
  ea_fe_settings_default(&fs);
  fs.modes = KM + 1;
  fs.static_hold_tip = 1;
  fs.newton_tol = 1e-13;
  const ea_load_t load = {tip_mass};
  if (ea_shooter_alloc(arm, NULL, &c->sh, NULL)) return 1;
  ea_shooter_set_load(c->sh, &load);
  if (ea_fe_model_alloc(arm, &fs, &c->m, NULL) || ea_fe_model_set_load(c->m, &load)) return 1;
  c->nd = 3 * ea_fe_model_nodes(c->m);
  c->K = KM;
  c->w = malloc(sizeof(double) * 2 * (size_t)c->nd);
  c->w2 = c->w + c->nd;
  return c->w == NULL;
}

static void ctx_free(fe_ctx_t *c) {
  ea_fe_model_free(c->m);
  ea_shooter_free(c->sh);
  free(c->w);
}

/* ---- 2. free vibration at fixed configuration ------------------------------------------- */

static void free_vibration(const ea_task_t *t, const char *name) {
  fe_ctx_t c;
  const double tm = ea_arm_tip_mass(&t->arm, t->payload_kg);
  if (ctx_alloc(&t->arm, tm, &c)) {
    fprintf(stderr, "bench_rom_nl: FE model\n");
    ctx_free(&c);
    return;
  }
  const int nd = c.nd;
  double *u = malloc(sizeof(double) * (size_t)nd * (2 + KM)), *phi = u + nd, *x = phi + KM * nd;
  const double Lc = t->goal.cable_length, al = t->goal.cable_angle;
  double om2[KM];
  if (!u || fe_point(&c, Lc, al, u, phi, NULL, om2)) {
    fprintf(stderr, "bench_rom_nl: FE point at the goal\n");
    free(u);
    ctx_free(&c);
    return;
  }
  const double w1 = sqrt(om2[0]);
  const double tx = phi[nd - 3], ty = phi[nd - 2], tn = hypot(tx, ty);
  printf("\n2. free vibration along mode 1 at %s's goal (L_c %.4f m, alpha %.4f rad, f1 %.4f Hz), "
         "FE genalpha dt 0.5 ms rho_inf 1, 1.5 s, against the linear model A cos(omega_1 t):\n",
         name, Lc, al, w1 / (2 * M_PI));
  printf("| A [mm] | max |tip_FE - tip_linear| [mm] | / A | / A^2 [1/m] | f_FE / f_1 - 1 |\n"
         "|---|---|---|---|---|\n");
  static const double amps[] = {-0.135, -0.075, -0.030, -0.010, 0.010, 0.030, 0.075, 0.135};
  for (int ia = 0; ia < 8; ++ia) {
    const double A = amps[ia], s = A / tn;
    ea_fe_set_state(c.m, u, NULL);
    ea_fe_cable_make_passive(c.m);
    double tip0[3];
    ea_fe_tip(c.m, tip0);
    for (int i = 0; i < nd; ++i)
      x[i] = u[i] + s * phi[i];
    ea_fe_set_state(c.m, x, NULL);
    ea_error_t e;
    if (ea_fe_relax_positions(c.m, &e)) {
      printf("| %.0f | relax: %s |\n", 1e3 * A, e.msg);
      continue;
    }
    ea_fe_sim_settings_t ss;
    ea_fe_sim_settings_default(&ss);
    ss.scheme = EA_FE_SCHEME_GENALPHA;
    ss.rho_inf = 1.0;
    ss.dt = 5e-4;
    ss.t_end = 2.0; /* the difference over 1.5 s, the frequency from 2 s */
    const int rows = (int)(ss.t_end / ss.dt) + 2;
    double *tip = malloc(sizeof(double) * 4 * (size_t)rows);
    ea_fe_sim_info_t si;
    e.msg[0] = 0;
    if (!tip || ea_fe_simulate(c.m, NULL, &ss, tip, rows, &si, &e)) {
      printf("| %.0f | simulate failed: %s |\n", 1e3 * A, tip ? e.msg : "memory");
      free(tip);
      continue;
    }
    double err = 0, tz[4];
    int nz = 0;
    double prev = 0;
    for (int r = 0; r < si.rows; ++r) {
      const double tt = tip[4 * r], dx = tip[4 * r + 1] - tip0[0], dy = tip[4 * r + 2] - tip0[1];
      const double cw = cos(w1 * tt);
      if (tt <= 1.5) err = fmax(err, hypot(dx - s * tx * cw, dy - s * ty * cw));
      const double pr = (dx * tx + dy * ty) / tn; /* along the mode's tip direction */
      if (r > 0 && nz < 4 && ((prev > 0) != (pr > 0))) {
        const double t0 = tip[4 * (r - 1)];
        tz[nz++] = t0 + (tt - t0) * prev / (prev - pr);
      }
      prev = pr;
    }
    const double f = nz >= 3 ? 1.0 / (tz[2] - tz[0]) : NAN;
    printf("| %.0f | %.3f | %.4f | %.2f | %+.4f |\n", 1e3 * A, 1e3 * err, err / fabs(A),
           err / (A * A), f / (w1 / (2 * M_PI)) - 1);
    free(tip);
  }
  free(u);
  ctx_free(&c);
}

/* 2b. the second-order model at fixed configuration: the FE released from the quadratic
 * manifold's point u_s + Phi_1 e0 + Theta_11 e0^2 / 2 against e'' + omega^2 e + c e e / 2 = 0
 * (2 modes) with the tip from the manifold (Phi e + Theta e e / 2), and against the linear
 * model. */
static void qm_free_vibration(const ea_task_t *t, const char *name) {
  fe_ctx_t c;
  if (ctx_alloc(&t->arm, ea_arm_tip_mass(&t->arm, t->payload_kg), &c)) {
    ctx_free(&c);
    return;
  }
  const int nd = c.nd;
  double *u = malloc(sizeof(double) * (size_t)nd * (3 + KM + 3)), *phi = u + nd;
  double *th = phi + KM * nd, *x = th + 3 * nd;
  double om2[KM], c3[4];
  if (!u || fe_point(&c, t->goal.cable_length, t->goal.cable_angle, u, phi, NULL, om2) ||
      modal_cubic(&c, u, phi, c3) || modal_derivatives(&c, u, phi, th, c3)) {
    fprintf(stderr, "bench_rom_nl: second-order model at the goal\n");
    free(u);
    ctx_free(&c);
    return;
  }
  const double tn = hypot(phi[nd - 3], phi[nd - 2]);
  printf("\n2b. free vibration from the quadratic manifold at %s's goal, 1.5 s: the largest tip "
         "difference FE - model, linear and second-order (Q, the manifold's tip):\n\n| A [mm] | "
         "linear [mm] | second order [mm] | second order / A^3 [1/m^2] |\n|---|---|---|---|\n",
         name);
  static const double amps[] = {-0.075, -0.030, -0.010, 0.010, 0.030, 0.075};
  for (int ia = 0; ia < 6; ++ia) {
    const double A = amps[ia], e0 = A / tn;
    for (int i = 0; i < nd; ++i)
      x[i] = u[i] + phi[i] * e0 + 0.5 * th[i] * e0 * e0;
    ea_fe_set_state(c.m, u, NULL);
    double tip0[3];
    ea_fe_tip(c.m, tip0);
    ea_fe_set_state(c.m, x, NULL); /* the cable stays passive at the static rest length */
    ea_fe_sim_settings_t ss;
    ea_fe_sim_settings_default(&ss);
    ss.scheme = EA_FE_SCHEME_GENALPHA;
    ss.rho_inf = 1.0;
    ss.dt = 5e-4;
    ss.t_end = 1.5;
    const int rows = (int)(ss.t_end / ss.dt) + 2;
    double *tip = malloc(sizeof(double) * 4 * (size_t)rows);
    ea_fe_sim_info_t si;
    ea_error_t e;
    if (!tip || ea_fe_simulate(c.m, NULL, &ss, tip, rows, &si, &e)) {
      printf("| %.0f | simulate failed |\n", 1e3 * A);
      free(tip);
      continue;
    }
    /* the model: RK4 at the FE's output step */
    double z[4] = {e0, 0, 0, 0}, el = 0, eq = 0;
    const double w1 = sqrt(om2[0]);
    for (int r = 0; r < si.rows; ++r) {
      const double tt = tip[4 * r], dx = tip[4 * r + 1] - tip0[0], dy = tip[4 * r + 2] - tip0[1];
      const double cw = cos(w1 * tt);
      el = fmax(el, hypot(dx - e0 * phi[nd - 3] * cw, dy - e0 * phi[nd - 2] * cw));
      double mx = 0, my = 0;
      for (int k = 0; k < KM; ++k) {
        mx += phi[(size_t)k * nd + nd - 3] * z[2 * k];
        my += phi[(size_t)k * nd + nd - 2] * z[2 * k];
      }
      const double q2[3] = {0.5 * z[0] * z[0], z[0] * z[2], 0.5 * z[2] * z[2]};
      for (int p = 0; p < 3; ++p) {
        mx += th[(size_t)p * nd + nd - 3] * q2[p];
        my += th[(size_t)p * nd + nd - 2] * q2[p];
      }
      eq = fmax(eq, hypot(dx - mx, dy - my));
      if (r + 1 < si.rows) { /* advance z to the next row's time */
        const double H = tip[4 * (r + 1)] - tt;
        const int sub = 10;
        for (int q = 0; q < sub; ++q) {
          double k1[4], k2[4], k3[4], k4[4], zt[4];
          double *kk[4] = {k1, k2, k3, k4};
          const double hh = H / sub, cf[4] = {0, 0.5, 0.5, 1};
          for (int st = 0; st < 4; ++st) {
            for (int j = 0; j < 4; ++j)
              zt[j] = st ? z[j] + cf[st] * hh * kk[st - 1][j] : z[j];
            const double e1 = zt[0], e2 = zt[2];
            kk[st][0] = zt[1];
            kk[st][2] = zt[3];
            kk[st][1] =
                -om2[0] * e1 - 0.5 * (c3[0] * e1 * e1 + 2 * c3[1] * e1 * e2 + c3[2] * e2 * e2);
            kk[st][3] =
                -om2[1] * e2 - 0.5 * (c3[1] * e1 * e1 + 2 * c3[2] * e1 * e2 + c3[3] * e2 * e2);
          }
          for (int j = 0; j < 4; ++j)
            z[j] += hh / 6 * (k1[j] + 2 * k2[j] + 2 * k3[j] + k4[j]);
        }
      }
    }
    printf("| %.0f | %.3f | %.3f | %.1f |\n", 1e3 * A, 1e3 * el, 1e3 * eq, eq / fabs(A * A * A));
    free(tip);
  }
  free(u);
  ctx_free(&c);
}

int main(int argc, char **argv) {
  const int nrand = ea_bench_count(argc, argv, 1, 8, 200, "bench_rom_nl [RANDOM_LINES]");
  if (nrand < 0) return 2;
  enum { NFIX = 4 };
  line_t lines[NFIX + 200] = {
      {"paper line", 0.3, -0.2, 0.6, -0.2, 0.0},
      {"diagonal", 0.25, -0.45, 0.6, -0.3, 0.25},
      {"vertical x 0.4", 0.4, -0.3, 0.4, 0.1, 0.0},
      {"refine-stall line", 0.6246, 0.0676, 0.5868, -0.1509, 0.26},
  };
  static char names[200][32];
  unsigned long long seed = 20261205ULL;
  for (int i = 0; i < nrand; ++i) {
    double v[5];
    do { /* lines of at least 0.1 m */
      for (int k = 0; k < 5; ++k) {
        seed = seed * 6364136223846793005ULL + 1442695040888963407ULL;
        v[k] = (double)(seed >> 11) / 9007199254740992.0;
      }
    } while (hypot(0.4 * (v[2] - v[0]), 0.55 * (v[3] - v[1])) < 0.1);
    snprintf(names[i], sizeof names[i], "random %d", i + 1);
    lines[NFIX + i] = (line_t){names[i],          0.25 + 0.4 * v[0],   -0.45 + 0.55 * v[1],
                               0.25 + 0.4 * v[2], -0.45 + 0.55 * v[3], 0.5 * v[4]};
  }
  const int only_corr = getenv("BENCH_ROM_NL_ONLY_CORR") != NULL;
  const int with_crude = getenv("BENCH_ROM_NL_CRUDE") != NULL;
  const int fd_first = getenv("BENCH_ROM_NL_FDJ") != NULL;
  corr_verbose = getenv("BENCH_ROM_NL_VERBOSE") != NULL;
  /* BENCH_ROM_NL_CMI: the correction with the manifold's inertia (CMI) instead of CM */
  want_poly = getenv("BENCH_ROM_NL_POLY") != NULL;
  const char *corr_name = want_poly                     ? "CMIP"
                          : getenv("BENCH_ROM_NL_CMIM") ? "CMIM"
                          : getenv("BENCH_ROM_NL_CMIX") ? "CMX"
                          : getenv("BENCH_ROM_NL_CMI")  ? "CMI"
                                                        : "CM";
  const int corr_terms = want_poly                     ? 835
                         : getenv("BENCH_ROM_NL_CMIM") ? 355
                         : getenv("BENCH_ROM_NL_CMIX") ? 131
                         : getenv("BENCH_ROM_NL_CMI")  ? 99
                                                       : 35;
  int nl = getenv("BENCH_ROM_NL_ONLY_FREE") ? 0 : NFIX + nrand;
  const char *xl = getenv("BENCH_ROM_NL_XLINE"); /* "x0,y0,x1,y1,payload factor": this line alone */
  if (xl) {
    line_t *L = &lines[0];
    if (sscanf(xl, "%lf,%lf,%lf,%lf,%lf", &L->x0, &L->y0, &L->x1, &L->y1, &L->gamma) != 5) {
      fprintf(stderr, "bench_rom_nl: BENCH_ROM_NL_XLINE=x0,y0,x1,y1,payload_factor\n");
      return 2;
    }
    L->name = "BENCH_ROM_NL_XLINE";
    nl = 1;
  }
  printf("1. plans on large-motion lines, 2 modes; model: the planner's table, RK4 dt 0.1 ms; FE: "
         "genalpha dt 0.5 ms, undamped, 3 s after the motion%s\n\n",
         only_corr ? " (BENCH_ROM_NL_ONLY_CORR: the at-rest plans alone, no candidate terms)" : "");
  printf(
      "| line | payload factor | plan | duration [s] | model: max modal tip deviation [mm] | FE: "
      "max tracking error [mm] | model residual [mm] | FE residual [mm] | FE / model | "
      "model + moving shapes M [mm] | M + quadratic stiffness MQ [mm] | MQ + manifold curvature "
      "MQE [mm] | condensed C [mm] | C + moving shapes CM [mm] | CM + manifold inertia CMI [mm] | "
      "CM + exact manifold inertia CMX [mm] | CMI + moving manifold CMIM [mm] | CMIM, static "
      "force fitted CMIP (model/fe_romnl.c) [mm] | FE residual / dev^2 [1/m] |\n"
      "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  static const char *pn[3] = {"quasi-static", "residual 5 mm", "at rest"};
  static char corr[200][600];
  static double fe0[200], fe1[200], ratio[200], t_int[200], t_mv[200], t_plan[200], t_fe4[200],
      t_fe05[200];
  int ncorr = 0, nconv = 0, nratio = 0, nint = 0;
  const char *only = getenv("BENCH_ROM_NL_LINE"); /* one line by index, for diagnosis */
  for (int l = 0; l < nl; ++l) {
    if (only && atoi(only) != l) continue;
    ea_task_t t;
    if (load_line(&lines[l], &t)) return 1;
    ea_error_t e;
    t.dynamics.modes = 0;
    if (ea_task_check(&t, &e)) {
      printf("| %s (%.3f, %.3f) -> (%.3f, %.3f) | %.2f | refused: %s |\n", lines[l].name,
             lines[l].x0, lines[l].y0, lines[l].x1, lines[l].y1, lines[l].gamma, e.msg);
      continue;
    }
    ea_traj_t tr[3] = {{0}};
    plan_res_t r[3];
    ea_planner_t *pl = NULL;
    int ok = !plan(&t, 2, 0.0, &tr[2], &pl, &r[2]);
    ok = ok && (only_corr || !plan(&t, 0, 0.0, &tr[0], NULL, &r[0]));
    ok = ok && (only_corr || !plan(&t, 2, 0.005, &tr[1], NULL, &r[1]));
    if (!ok) {
      printf("| %s | %.2f | not planned |\n", lines[l].name, lines[l].gamma);
      for (int k = 0; k < 3; ++k)
        ea_traj_free(&tr[k]);
      ea_planner_free(pl);
      continue;
    }
    const ea_rom_table_t *tb = ea_planner_rom_table(pl);
    sign_tb = tb;
    fe_ctx_t c;
    const int cok = !ctx_alloc(&t.arm, ea_arm_tip_mass(&t.arm, t.payload_kg), &c);
    cond_ctx = &c;
    free(cond_w);
    cond_w = calloc((size_t)c.nd * 24, sizeof(double));
    ea_romnl_free(nlm);
    nlm = NULL;
    if (want_poly && ea_romnl_alloc(&t.arm, ea_arm_tip_mass(&t.arm, t.payload_kg), 0, &nlm, &e))
      fprintf(stderr, "bench_rom_nl: %s: %s\n", lines[l].name, e.msg);
    for (int k = only_corr ? 2 : 0; k < 3; ++k) {
      predict(tb, &tr[k], &r[k]);
      double t0 = ea_bench_now();
      fe_run(&t, &tr[k], &r[k]);
      if (k == 2) t_fe05[ncorr] = ea_bench_now() - t0;
      static moving_t mv;
      double with = NAN, quad = NAN, both = NAN, cond = NAN, condm = NAN, cmi = NAN, cmix = NAN,
             cmip = NAN, cmim = NAN;
      if (cok && !only_corr && !moving_sample(&c, &tr[k], 41, &mv)) {
        with = integrate(tb, &tr[k], &mv, 3);
        quad = integrate(tb, &tr[k], &mv, 7);
        both = integrate(tb, &tr[k], &mv, 23);
        cond = integrate(tb, &tr[k], &mv, 32);
        condm = integrate(tb, &tr[k], &mv, 35);
        cmi = integrate(tb, &tr[k], &mv, 99);
        cmix = getenv("BENCH_ROM_NL_NO_CMX") ? NAN : integrate(tb, &tr[k], &mv, 131);
        cmim = getenv("BENCH_ROM_NL_NO_CMIM") ? NAN : integrate(tb, &tr[k], &mv, 355);
        cmip = want_poly ? integrate_nl(tb, &tr[k], NULL, NULL) : NAN;
      }
      const double dev = r[k].dev_model;
      printf("| %s (%.3f, %.3f) -> (%.3f, %.3f) | %.2f | %s | %.4f | %.1f | %.1f | %.3f | %.3f | "
             "%.3f | %.3f | %.3f | %.3f | %.3f | %.3f | %.3f | %.3f | %.3f | %.3f | %.2f |\n",
             lines[l].name, lines[l].x0, lines[l].y0, lines[l].x1, lines[l].y1, lines[l].gamma,
             pn[k], r[k].dur, 1e3 * dev, 1e3 * r[k].dev_fe, 1e3 * r[k].pred, 1e3 * r[k].fe,
             r[k].fe / r[k].pred, 1e3 * with, 1e3 * quad, 1e3 * both, 1e3 * cond, 1e3 * condm,
             1e3 * cmi, 1e3 * cmix, 1e3 * cmim, 1e3 * cmip, r[k].fe / (dev * dev));
      fflush(stdout);
    }
    if (cok && ncorr < 200) {
      /* the FE transient at the refinement's settings, for scale */
      ea_sim_settings_t s4;
      ea_sim_settings_default(&s4);
      s4.dt = 4e-3;
      s4.settle = 1.5;
      ea_sim_info_t si4;
      double t0 = ea_bench_now();
      t_fe4[ncorr] =
          ea_traj_simulate(&t.arm, &tr[2], 0.0, &s4, NULL, &si4, NULL) ? NAN : ea_bench_now() - t0;
      const double dur0 = r[2].dur;
      fe0[ncorr] = r[2].fe;
      int n = snprintf(corr[ncorr], sizeof corr[ncorr], "| %s | %.2f | %.4f | %.3f |",
                       lines[l].name, lines[l].gamma, dur0, 1e3 * r[2].fe);
      for (int v = with_crude ? 0 : 1; v < 2; ++v) {
        ea_traj_t tc = {0};
        ea_plan_info_t info;
        corr_info_t ci = {0};
        int rc = 1;
        plan_res_t rr = {0};
        rr.fe = NAN;
        if (!ea_planner_set_terminal_modes(pl, NULL, NULL, NULL) &&
            !ea_planner_solve(pl, EA_PLAN_WARM, NULL, &info, NULL) &&
            !ea_planner_trajectory(pl, &tc, NULL))
          rc = v ? corrected_plan(pl, &c, &tc, corr_terms, fd_first, &ci)
                 : crude_plan(pl, &c, &tc, corr_terms, &ci);
        rr.ok = 1;
        if (!rc) fe_run(&t, &tc, &rr);
        double fine = NAN; /* the CM model's own discretisation: 81 samples, RK4 dt 0.1 ms */
        static moving_t mvf;
        if (!rc && v == 1 && want_poly) {
          ea_rom_prediction_t pr;
          if (!ea_traj_romnl_sample(nlm, tb, &tc, 81, NULL) &&
              !ea_traj_romnl_predict(tb, nlm, &tc, 5e-5, 3.0, &pr, NULL, NULL))
            fine = pr.residual_peak;
        } else if (!rc && v == 1 && !moving_sample(&c, &tc, 81, &mvf)) {
          cm_dt = 1e-4;
          fine = integrate(tb, &tc, &mvf, corr_terms);
          cm_dt = 2e-4;
        }
        const double dur =
            rc ? NAN : EA_TRAJ_AT(&tc, tc.n - 1, EA_TRAJ_t) - EA_TRAJ_AT(&tc, 0, EA_TRAJ_t);
        if (v == 0)
          n += snprintf(corr[ncorr] + n, sizeof corr[ncorr] - (size_t)n, " %d | %.4f | %.3f |",
                        ci.evals, 1e3 * ci.pred, 1e3 * rr.fe);
        else {
          fe1[ncorr] = rr.fe;
          nconv += ci.converged;
          if (ci.converged && rr.fe > 1e-3) ratio[nratio++] = rr.fe / r[2].fe;
          if (ci.evals > 0) {
            t_int[nint] = ci.t_int / ci.evals;
            t_mv[nint] = ci.t_mv / ci.evals;
            t_plan[nint] = ci.evals > 1 ? ci.t_plan / (ci.evals - 1) : NAN;
            ++nint;
          }
          n += snprintf(corr[ncorr] + n, sizeof corr[ncorr] - (size_t)n,
                        " %d | %d | %d | %.4f | %s | %.4f | %.3f | %.2f | %.4f | %+.2f |", ci.evals,
                        ci.fd, ci.failed, 1e3 * ci.pred, ci.converged ? "yes" : "no", 1e3 * fine,
                        1e3 * rr.fe, rr.fe / r[2].fe, dur, 100 * (dur / dur0 - 1));
        }
        ea_traj_free(&tc);
      }
      ++ncorr;
    }
    if (cok) ctx_free(&c);
    for (int k = 0; k < 3; ++k)
      ea_traj_free(&tr[k]);
    ea_planner_free(pl);
  }
  printf("\n4. at-rest plans corrected for a candidate (%s) without touching the transcription: "
         "the goal's modal targets moved (warm re-plans) until the candidate ends at rest "
         "(residual peak < %.3g mm), by a globalised Newton on "
         "the 4 targets as tip amplitudes (J %s, Broyden updates, Armijo %g with at most %d "
         "halvings, J rebuilt by forward differences of %.2g mm when no step is accepted, at most "
         "%d evaluations); FE: genalpha dt 0.5 ms, undamped, 3 s%s\n\n",
         corr_name, 1e3 * CORR_TOL, fd_first ? "by forward differences" : "= I", CORR_ARMIJO,
         CORR_HALVINGS, 1e3 * CORR_FD_H, CORR_MAX_EVALS,
         with_crude ? "; crude: target -= z_end, 6 iterations (the loop it replaces)" : "");
  printf("| line | payload factor | at rest: duration [s] | FE [mm] |%s Newton: evaluations | "
         "J by differences | failed evaluations | candidate's residual [mm] | converged | "
         "%s at 81 samples, "
         "dt 0.1 ms [mm] | FE [mm] | FE / at-rest FE | duration [s] | duration vs at rest [%%] |\n"
         "|---|---|---|---|%s---|---|---|---|---|---|---|---|---|---|\n",
         with_crude ? " crude: evaluations | CM [mm] | FE [mm] |" : "", "the candidate",
         with_crude ? "---|---|---|" : "");
  for (int i = 0; i < ncorr; ++i)
    printf("%s\n", corr[i]);
  if (ncorr > 0) {
    int b1[2] = {0}, b05[2] = {0};
    for (int i = 0; i < ncorr; ++i) {
      b1[0] += fe0[i] <= 1e-3;
      b05[0] += fe0[i] <= 5e-4;
      b1[1] += fe1[i] <= 1e-3;
      b05[1] += fe1[i] <= 5e-4;
    }
    printf("\nFE residual of %d lines: at rest as planned: median %.3f mm, <= 1 mm on %d, <= 0.5 "
           "mm on %d; corrected: median %.3f mm, <= 1 mm on %d, <= 0.5 mm on %d; the loop "
           "converged on %d\n",
           ncorr, 1e3 * ea_bench_median(fe0, ncorr), b1[0], b05[0],
           1e3 * ea_bench_median(fe1, ncorr), b1[1], b05[1], nconv);
    if (nratio > 0) {
      const double med = ea_bench_median(ratio, nratio); /* sorts */
      printf("converged but FE > 1 mm on %d lines: FE corrected / FE at rest median %.2f (%.2f .. "
             "%.2f)\n",
             nratio, med, ratio[0], ratio[nratio - 1]);
    }
    printf("time per evaluation (median over lines): re-plan %.1f ms, moving shapes (41 samples) "
           "%.1f ms, one candidate integration %.1f ms; one FE transient of the at-rest plan: %.1f "
           "ms at "
           "the refinement's settings (ea_sim_settings_default, dt 4 ms, settle 1.5 s), %.1f ms "
           "at genalpha dt 0.5 ms, settle 3 s\n",
           nint ? 1e3 * ea_bench_median(t_plan, nint) : NAN,
           nint ? 1e3 * ea_bench_median(t_mv, nint) : NAN,
           nint ? 1e3 * ea_bench_median(t_int, nint) : NAN, 1e3 * ea_bench_median(t_fe4, ncorr),
           1e3 * ea_bench_median(t_fe05, ncorr));
  }
  printf("\ncondensation: Newton failed (the integration stopped) %d times\n", cond_fail);
  printf("\nthe largest modal tip amplitude met by CMX, CMIM: mode 1 %.1f mm, mode 2 %.1f mm\n",
         1e3 * emax_tip[0], 1e3 * emax_tip[1]);
  if (want_poly)
    printf("\nCMIP (model/fe_romnl.c): the static condensed force's degree-8 fits in e1: worst "
           "residual over the nodes %.2e of the largest |lambda|; nodes not reached (beyond a "
           "fold) %d; sampling 41 points: %.0f ms in the mean over %d samplings\n",
           nl_fit_err, nl_dropped, nl_samples ? 1e3 * nl_time / nl_samples : NAN, nl_samples);
  printf("\nmode signs: the FE modes' tip per unit eta against the table's at %d first samples: "
         "min |cos| %.6f, max | |tip_FE| / |tip_table| - 1 | %.2e; sign taken from the table %d "
         "times\n",
         sign_checks, sign_cos_min, sign_norm_dev, sign_flips);
  printf(
      "\nquadratic modal stiffness: Phi_i^T d2f/de_j de_k (forces) against the potential's third "
      "differences: max difference %.2e of the largest %.3e\n",
      c3_diff / c3_max, c3_max);
  printf("\nmoving-shape coefficients: max |G_12 + G_21|, |G_11|, |G_22| = %.2e of max |G_12| = "
         "%.3e 1/m or 1/rad (Phi^T M Phi = I makes G antisymmetric)\n",
         g_asym / g_max, g_max);
  for (int l = 0; l < (only_corr ? 0 : 3); ++l) {
    ea_task_t t;
    ea_error_t e;
    if (load_line(&lines[l], &t) || ea_task_check(&t, &e)) continue;
    free_vibration(&t, lines[l].name);
    qm_free_vibration(&t, lines[l].name);
  }
  return 0;
}
