/* Private to dyn_rows.c: the second-order forward mode of the modal defects over an interval's
 * trajectory variables z, for a number of them set by the includer (the GSL template way):
 * EA__HZ variables, and EA__HZN(name) the name for that number. dyn_rows.c includes it twice:
 * EA__HZ 9 (the knot layout: L_c q0 q1 v0 v1, alpha q0 q1 v0 v1, t_f) and 7 (the path layout:
 * sigma_0, sigma_1, the rates of L_c and alpha at both ends, t_f). Values, gradients and packed
 * lower-triangle Hessians (entry (a, b), b <= a, at a (a + 1) / 2 + b). */

#define EA__HP (EA__HZ * (EA__HZ + 1) / 2)
#define HZ EA__HZN(ea__hz_t)
#define DZ EA__HZN(ea__dz_t)
#define FIELDS EA__HZN(ea__hz_fields_t)
#define KIN EA__HZN(ea__hz_kin_t)
#define FN(name) EA__HZN(name)

/* s1 >= 0: the number depends on variable s1 alone (g and H zero elsewhere), which a product
 * uses (ea__hz_mul: the same sums, without their zero terms) */
typedef struct {
  double v, g[EA__HZ], H[EA__HP];
  int s1;
} HZ;

static void FN(ea__hz_c)(HZ *r, double v) {
  memset(r, 0, sizeof *r);
  r->v = v;
  r->s1 = -1;
}
static void FN(ea__hz_var)(HZ *r, double v, int i) {
  FN(ea__hz_c)(r, v);
  r->g[i] = 1.0;
  r->s1 = i;
}
/* r = a x + b y (r may be x or y) */
static void FN(ea__hz_lin)(HZ *r, double a, const HZ *x, double b, const HZ *y) {
  r->s1 = -1;
  r->v = a * x->v + b * y->v;
  for (int i = 0; i < EA__HZ; ++i)
    r->g[i] = a * x->g[i] + b * y->g[i];
  for (int p = 0; p < EA__HP; ++p)
    r->H[p] = a * x->H[p] + b * y->H[p];
}
static void FN(ea__hz_addc)(HZ *r, double c) {
  r->v += c;
}
/* r = x y where x depends on variable i alone: ea__hz_mul's sums without their zero terms (the
 * same values) */
static void FN(ea__hz_mul1)(HZ *r, const HZ *x, const HZ *y) {
  const int i = x->s1;
  const double xv = x->v, yv = y->v, xg = x->g[i];
  r->s1 = -1;
  r->v = xv * yv;
  for (int j = 0; j < EA__HZ; ++j)
    r->g[j] = xv * y->g[j];
  r->g[i] = xg * yv + xv * y->g[i];
  for (int p = 0; p < EA__HP; ++p)
    r->H[p] = xv * y->H[p];
  const int ii = i * (i + 1) / 2;
  for (int b = 0; b < i; ++b) /* row i: (i, b) */
    r->H[ii + b] += xg * y->g[b];
  for (int a = i + 1; a < EA__HZ; ++a) /* column i: (a, i) */
    r->H[a * (a + 1) / 2 + i] += xg * y->g[a];
  r->H[ii + i] = x->H[ii + i] * yv + xv * y->H[ii + i] + xg * y->g[i] + xg * y->g[i];
}

/* r = x y (r not x or y) */
static void FN(ea__hz_mul)(HZ *r, const HZ *x, const HZ *y) {
  if (x->s1 >= 0) {
    FN(ea__hz_mul1)(r, x, y);
    return;
  }
  if (y->s1 >= 0) {
    FN(ea__hz_mul1)(r, y, x);
    return;
  }
  r->s1 = -1;
  r->v = x->v * y->v;
  for (int i = 0; i < EA__HZ; ++i)
    r->g[i] = x->g[i] * y->v + x->v * y->g[i];
  int p = 0;
  for (int a = 0; a < EA__HZ; ++a)
    for (int b = 0; b <= a; ++b, ++p)
      r->H[p] = x->H[p] * y->v + x->v * y->H[p] + x->g[a] * y->g[b] + x->g[b] * y->g[a];
}
/* r = f(x) from f, f', f'' at x->v (r may be x) */
static void FN(ea__hz_fn)(HZ *r, const HZ *x, double f, double f1, double f2) {
  r->s1 = x->s1;
  int p = 0;
  for (int a = 0; a < EA__HZ; ++a)
    for (int b = 0; b <= a; ++b, ++p)
      r->H[p] = f1 * x->H[p] + f2 * x->g[a] * x->g[b];
  for (int i = 0; i < EA__HZ; ++i)
    r->g[i] = f1 * x->g[i];
  r->v = f;
}
/* The products of the gradients of (L, A) that every field at the same point takes: L L', the
 * symmetrised L A' and A A' (packed lower triangles). */
typedef struct {
  double LL[EA__HP], LA[EA__HP], AA[EA__HP];
} FN(ea__hz_outer_t);

static void FN(ea__hz_outer)(FN(ea__hz_outer_t) * o, const HZ *L, const HZ *A) {
  int p = 0;
  for (int a = 0; a < EA__HZ; ++a)
    for (int b = 0; b <= a; ++b, ++p) {
      o->LL[p] = L->g[a] * L->g[b];
      o->LA[p] = L->g[a] * A->g[b] + A->g[a] * L->g[b];
      o->AA[p] = A->g[a] * A->g[b];
    }
}

/* A tabulated field at (L, a), both functions of z (value f, derivatives fL, fa, fLL, fLa,
 * faa), with the outer products of ea__hz_outer */
static void FN(ea__hz_field_o)(HZ *r, const HZ *L, const HZ *A, const FN(ea__hz_outer_t) * o,
                               const double f[6]) {
  r->s1 = -1;
  r->v = f[0];
  for (int i = 0; i < EA__HZ; ++i)
    r->g[i] = f[1] * L->g[i] + f[2] * A->g[i];
  for (int p = 0; p < EA__HP; ++p)
    r->H[p] = f[1] * L->H[p] + f[2] * A->H[p] + f[3] * o->LL[p] + f[4] * o->LA[p] + f[5] * o->AA[p];
}

/* The same at an interval's end, where (L, a) depends on few variables (ea__hz_end_t). */
static void FN(ea__hz_field_end)(HZ *r, const ea__hz_end_t *e, const double f[6]) {
  FN(ea__hz_c)(r, f[0]);
  if (e->iA >= 0) { /* L and A the variables iL and iA (iA > iL): three Hessian entries */
    r->g[e->iL] = f[1];
    r->g[e->iA] = f[2];
    r->H[e->iL * (e->iL + 1) / 2 + e->iL] = f[3];
    r->H[e->iA * (e->iA + 1) / 2 + e->iL] = f[4];
    r->H[e->iA * (e->iA + 1) / 2 + e->iA] = f[5];
  } else { /* L = L(s), A = A(s) of the one variable s = iL: f(s) to second order */
    r->s1 = e->iL;
    const double L1 = e->d[0], A1 = e->d[1], L2 = e->d2[0], A2 = e->d2[1];
    r->g[e->iL] = f[1] * L1 + f[2] * A1;
    r->H[e->iL * (e->iL + 1) / 2 + e->iL] =
        f[3] * L1 * L1 + 2.0 * f[4] * L1 * A1 + f[5] * A1 * A1 + f[1] * L2 + f[2] * A2;
  }
}

/* The model's fields at one point: omega^2, 2 zeta omega per mode (c), B, C. */
typedef struct {
  HZ W[EA_ROM_MAX_MODES], c[EA_ROM_MAX_MODES], B[EA_ROM_MAX_MODES][2], C[EA_ROM_MAX_MODES][3];
} FIELDS;

/* A field at an end (e not NULL: ea__hz_field_end) or at (L, A) with their outer products op. */
static void FN(ea__hz_field_at)(HZ *r, const ea__hz_end_t *e, const HZ *L, const HZ *A,
                                const FN(ea__hz_outer_t) * op, const double f[6]) {
  if (e)
    FN(ea__hz_field_end)(r, e, f);
  else
    FN(ea__hz_field_o)(r, L, A, op, f);
}

/* The fields of model j at (L, A) (functions of z) from the table's values and derivatives
 * there; at an end (e not NULL) by ea__hz_field_end. */
static void FN(ea__hz_point_from)(const ea_planner_t *pl, int j, const HZ *L, const HZ *A,
                                  const ea_rom_point_t *vp, const ea_rom_point_t *dLp,
                                  const ea_rom_point_t *dap, const ea_rom_point_t *dLLp,
                                  const ea_rom_point_t *dLap, const ea_rom_point_t *daap,
                                  const ea__hz_end_t *e, FIELDS *o) {
  FN(ea__hz_outer_t) op;
  if (!e) FN(ea__hz_outer)(&op, L, A);
  for (int k = 0; k < pl->Kper; ++k) {
    const double w[6] = {vp->omega2[k],   dLp->omega2[k],  dap->omega2[k],
                         dLLp->omega2[k], dLap->omega2[k], daap->omega2[k]};
    FN(ea__hz_field_at)(&o->W[k], e, L, A, &op, w);
    const double zeta = pl->zeta[j * pl->Kper + k];
    if (zeta > 0) { /* 2 zeta sqrt(W) */
      const double sw = sqrt(o->W[k].v);
      FN(ea__hz_fn)(&o->c[k], &o->W[k], 2 * zeta * sw, zeta / sw, -0.5 * zeta / (sw * o->W[k].v));
    } else {
      FN(ea__hz_c)(&o->c[k], 0.0);
    }
    for (int c = 0; c < 2; ++c) {
      const double b[6] = {vp->B[k][c],   dLp->B[k][c],  dap->B[k][c],
                           dLLp->B[k][c], dLap->B[k][c], daap->B[k][c]};
      FN(ea__hz_field_at)(&o->B[k][c], e, L, A, &op, b);
    }
    for (int c = 0; c < 3; ++c) {
      const double f[6] = {vp->C[k][c],   dLp->C[k][c],  dap->C[k][c],
                           dLLp->C[k][c], dLap->C[k][c], daap->C[k][c]};
      FN(ea__hz_field_at)(&o->C[k][c], e, L, A, &op, f);
    }
  }
}

/* The fields of model j at (L, A): at an end (knot not NULL) from the knot's cached table and e,
 * else the table there. */
static void FN(ea__hz_point)(const ea_planner_t *pl, int j, const HZ *L, const HZ *A,
                             const ea__dyn_kcache_t *knot, const ea__hz_end_t *e, FIELDS *o) {
  if (knot) {
    FN(ea__hz_point_from)
    (pl, j, L, A, &knot->v, &knot->dL, &knot->da, &knot->dLL, &knot->dLa, &knot->daa, e, o);
    return;
  }
  ea_rom_point_t v, dL, da, dLL, dLa, daa;
  ea_rom_table_eval2(pl->roms[j], L->v, A->v, &v, &dL, &da, &dLL, &dLa, &daa);
  FN(ea__hz_point_from)(pl, j, L, A, &v, &dL, &da, &dLL, &dLa, &daa, NULL, o);
}

/* F = -(B . a + C0 v0^2 + 2 C1 v0 v1 + C2 v1^2) of mode k; vv = (v0^2, v0 v1, v1^2) */
static void FN(ea__hz_force)(HZ *F, const FIELDS *m, int k, const HZ a[2], const HZ vv[3]) {
  HZ t;
  FN(ea__hz_mul)(F, &m->B[k][0], &a[0]);
  FN(ea__hz_mul)(&t, &m->B[k][1], &a[1]);
  FN(ea__hz_lin)(F, -1.0, F, -1.0, &t);
  for (int c = 0; c < 3; ++c) {
    FN(ea__hz_mul)(&t, &m->C[k][c], &vv[c]);
    FN(ea__hz_lin)(F, 1.0, F, c == 1 ? -2.0 : -1.0, &t);
  }
}

/* The interval's kinematics along the trajectory's Hermite: per point (0, 1, midpoint) its
 * (L_c, alpha), accelerations and velocity products; h. */
typedef struct {
  HZ h, q[3][2], a[3][2], vv[3][3];
} KIN;

/* Interval k's step h = (s_k+1 - s_k) t_f, t_f the variable itf (fixed: a number). */
static void FN(ea__hz_step)(const ea_planner_t *pl, const double *x, int k, int itf, HZ *h) {
  HZ tfz;
  if (pl->has_tf)
    FN(ea__hz_var)(&tfz, x[EA__ITF(pl)], itf);
  else
    FN(ea__hz_c)(&tfz, pl->tf_fixed);
  FN(ea__hz_lin)(h, pl->s[k + 1] - pl->s[k], &tfz, 0.0, &tfz);
}

/* The kinematics from the ends' (L_c, alpha) q[P][c], rates v[P][c] and h, functions of z. */
static void FN(ea__hz_kin_from)(HZ q[2][2], HZ v[3][2], const HZ *h, KIN *o) {
  HZ ih, ih2, t, u;
  o->h = *h;
  const double hv = h->v;
  FN(ea__hz_fn)(&ih, h, 1.0 / hv, -1.0 / (hv * hv), 2.0 / (hv * hv * hv));
  FN(ea__hz_mul)(&ih2, &ih, &ih);
  for (int c = 0; c < 2; ++c) {
    const HZ *q0 = &q[0][c], *q1 = &q[1][c];
    HZ dq, t6;
    o->q[0][c] = *q0;
    o->q[1][c] = *q1;
    FN(ea__hz_lin)(&dq, 1.0, q1, -1.0, q0);
    FN(ea__hz_mul)(&t6, &dq, &ih2); /* dq / h^2 */
    /* a0 = 6 dq / h^2 - (4 v0 + 2 v1) / h, a1 = -6 dq / h^2 + (2 v0 + 4 v1) / h */
    FN(ea__hz_lin)(&t, 4.0, &v[0][c], 2.0, &v[1][c]);
    FN(ea__hz_mul)(&u, &t, &ih);
    FN(ea__hz_lin)(&o->a[0][c], 6.0, &t6, -1.0, &u);
    FN(ea__hz_lin)(&t, 2.0, &v[0][c], 4.0, &v[1][c]);
    FN(ea__hz_mul)(&u, &t, &ih);
    FN(ea__hz_lin)(&o->a[1][c], -6.0, &t6, 1.0, &u);
    /* qm = (q0 + q1)/2 + h (v0 - v1)/8, vm = 3/2 dq / h - (v0 + v1)/4, am = (a0 + a1)/2 */
    FN(ea__hz_lin)(&t, 1.0, &v[0][c], -1.0, &v[1][c]);
    FN(ea__hz_mul)(&u, h, &t);
    FN(ea__hz_lin)(&t, 0.5, q0, 0.5, q1);
    FN(ea__hz_lin)(&o->q[2][c], 1.0, &t, 0.125, &u);
    FN(ea__hz_mul)(&u, &dq, &ih);
    FN(ea__hz_lin)(&t, 1.0, &v[0][c], 1.0, &v[1][c]);
    FN(ea__hz_lin)(&v[2][c], 1.5, &u, -0.25, &t);
    FN(ea__hz_lin)(&o->a[2][c], 0.5, &o->a[0][c], 0.5, &o->a[1][c]);
  }
  for (int P = 0; P < 3; ++P) {
    FN(ea__hz_mul)(&o->vv[P][0], &v[P][0], &v[P][0]);
    FN(ea__hz_mul)(&o->vv[P][1], &v[P][0], &v[P][1]);
    FN(ea__hz_mul)(&o->vv[P][2], &v[P][1], &v[P][1]);
  }
}

/* First order over the same z: value and gradient (the defects' coefficients of the modal
 * states, whose Hessian entries are the z-e ones: gradients only). */
typedef struct {
  double v, g[EA__HZ];
} DZ;

static void FN(ea__dz_of)(DZ *r, const HZ *x) {
  r->v = x->v;
  memcpy(r->g, x->g, sizeof r->g);
}
/* r = a x + b y + c (r may be x or y) */
static void FN(ea__dz_lin)(DZ *r, double a, const DZ *x, double b, const DZ *y, double c) {
  r->v = a * x->v + b * y->v + c;
  for (int i = 0; i < EA__HZ; ++i)
    r->g[i] = a * x->g[i] + b * y->g[i];
}
/* r = x y (r not x or y) */
static void FN(ea__dz_mul)(DZ *r, const DZ *x, const DZ *y) {
  r->v = x->v * y->v;
  for (int i = 0; i < EA__HZ; ++i)
    r->g[i] = x->g[i] * y->v + x->v * y->g[i];
}

/* Mode k's pos (0) and vel (1) defects (unscaled) at the modal states e = (eta_0, eta'_0,
 * eta_1, eta'_1): phi, to second order in z with e fixed (the z-z Hessian entries), and their
 * coefficients of e, C[d][j] = d defect / d e_j, to first order (the z-e entries; e-e: none).
 * The defects evaluated at e as numbers take half the second-order products of their five
 * coefficients each (the at-rest paper line's defect Hessians ~35 % cheaper). */
static void FN(ea__hz_defect)(const KIN *kin, const FIELDS *m[3], int k, const double e[4],
                              HZ phi[2], DZ C[2][4]) {
  HZ F[3], t, u, acc0, acc1, d, em, edm, accm;
  for (int P = 0; P < 3; ++P)
    FN(ea__hz_force)(&F[P], m[P], k, kin->a[P], kin->vv[P]);
  const HZ *h = &kin->h, *W0 = &m[0]->W[k], *W1 = &m[1]->W[k], *c0 = &m[0]->c[k], *c1 = &m[1]->c[k],
           *Wm = &m[2]->W[k], *cm = &m[2]->c[k];
  /* acc_P = F_P - W_P eta_P - c_P eta'_P at the ends, d = acc_0 - acc_1 */
  FN(ea__hz_lin)(&acc0, 1.0, &F[0], -e[0], W0);
  FN(ea__hz_lin)(&acc0, 1.0, &acc0, -e[1], c0);
  FN(ea__hz_lin)(&acc1, 1.0, &F[1], -e[2], W1);
  FN(ea__hz_lin)(&acc1, 1.0, &acc1, -e[3], c1);
  FN(ea__hz_lin)(&d, 1.0, &acc0, -1.0, &acc1);
  /* pos = eta_1 - eta_0 - h/2 (eta'_0 + eta'_1) - h^2/12 d */
  FN(ea__hz_mul)(&t, h, h);
  FN(ea__hz_mul)(&u, &t, &d);
  FN(ea__hz_lin)(&phi[0], -0.5 * (e[1] + e[3]), h, -1.0 / 12.0, &u);
  FN(ea__hz_addc)(&phi[0], e[2] - e[0]);
  /* em = (eta_0 + eta_1)/2 + h/8 (eta'_0 - eta'_1), edm = (eta'_0 + eta'_1)/2 + h/8 d,
   * accm = F_m - W_m em - c_m edm */
  FN(ea__hz_lin)(&em, 0.125 * (e[1] - e[3]), h, 0.0, h);
  FN(ea__hz_addc)(&em, 0.5 * (e[0] + e[2]));
  FN(ea__hz_mul)(&t, h, &d);
  FN(ea__hz_lin)(&edm, 0.125, &t, 0.0, &t);
  FN(ea__hz_addc)(&edm, 0.5 * (e[1] + e[3]));
  FN(ea__hz_mul)(&t, Wm, &em);
  FN(ea__hz_lin)(&accm, 1.0, &F[2], -1.0, &t);
  FN(ea__hz_mul)(&t, cm, &edm);
  FN(ea__hz_lin)(&accm, 1.0, &accm, -1.0, &t);
  /* vel = eta'_1 - eta'_0 - h/6 (acc_0 + acc_1) - 2h/3 accm */
  FN(ea__hz_lin)(&d, 1.0, &acc0, 1.0, &acc1);
  FN(ea__hz_mul)(&t, h, &d);
  FN(ea__hz_mul)(&u, h, &accm);
  FN(ea__hz_lin)(&phi[1], -1.0 / 6.0, &t, -2.0 / 3.0, &u);
  FN(ea__hz_addc)(&phi[1], e[3] - e[1]);
  /* the coefficients: pos -1 + h2 W0, -h/2 + h2 c0, 1 - h2 W1, -h/2 - h2 c1 (h2 = h^2/12);
   * vel h/6 X_j - 2h/3 M_j (-1, +1 at j = 1, 3) with X = (W0, c0, W1, c1),
   * M_j = -W_m E_j - c_m D_j, E = (1/2, h/8, 1/2, -h/8),
   * D = (-h/8 W0, 1/2 - h/8 c0, h/8 W1, 1/2 + h/8 c1) */
  DZ hd, h2, X[4], wm, c, hx, a, b;
  FN(ea__dz_of)(&hd, h);
  FN(ea__dz_mul)(&a, &hd, &hd);
  FN(ea__dz_lin)(&h2, 1.0 / 12.0, &a, 0.0, &a, 0.0);
  FN(ea__dz_of)(&X[0], W0);
  FN(ea__dz_of)(&X[1], c0);
  FN(ea__dz_of)(&X[2], W1);
  FN(ea__dz_of)(&X[3], c1);
  FN(ea__dz_of)(&wm, Wm);
  FN(ea__dz_of)(&c, cm);
  for (int j = 0; j < 4; ++j) {
    const double sg = j < 2 ? 1.0 : -1.0;
    FN(ea__dz_mul)(&a, &h2, &X[j]);
    if (j % 2 == 0)
      FN(ea__dz_lin)(&C[0][j], sg, &a, 0.0, &a, -sg); /* -1 + h2 W0, 1 - h2 W1 */
    else
      FN(ea__dz_lin)(&C[0][j], -0.5, &hd, sg, &a, 0.0);
    FN(ea__dz_mul)(&hx, &hd, &X[j]);
    /* D_j = -/+ h/8 X_j (+ 1/2 for j odd); M_j = -W_m E_j - c_m D_j */
    FN(ea__dz_lin)(&a, -0.125 * sg, &hx, 0.0, &hx, j % 2 ? 0.5 : 0.0);
    FN(ea__dz_mul)(&b, &c, &a);
    if (j % 2 == 0) {
      FN(ea__dz_lin)(&a, -0.5, &wm, -1.0, &b, 0.0);
    } else {
      FN(ea__dz_mul)(&a, &wm, &hd);
      FN(ea__dz_lin)(&a, -0.125 * sg, &a, -1.0, &b, 0.0);
    }
    FN(ea__dz_mul)(&b, &hd, &a);
    FN(ea__dz_lin)(&C[1][j], 1.0 / 6.0, &hx, -2.0 / 3.0, &b, j == 1 ? -1.0 : j == 3 ? 1.0 : 0.0);
  }
}

#undef EA__HP
#undef HZ
#undef DZ
#undef FIELDS
#undef KIN
#undef FN
