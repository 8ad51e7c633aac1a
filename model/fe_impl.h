/* Private: finite element model workspace (model/fe_*.c). */
#ifndef EA_FE_IMPL_H
#define EA_FE_IMPL_H

#include "ea_fe.h"
#include "ea_util.h"

#include <gsl/gsl_eigen.h>
#include <gsl/gsl_matrix.h>

/** Half bandwidth of every matrix: a 3-node element couples 9 consecutive DOFs. */
#define EA__FE_KD 8
/** Rows of the symmetric (upper) band storage. */
#define EA__FE_LDS (EA__FE_KD + 1)
/** Rows of the general band storage for LU (2 kl + ku + 1). */
#define EA__FE_LDG (3 * EA__FE_KD + 1)
/** Entry (i, j), i <= j, of a symmetric band matrix in upper storage (LDS x nd). */
#define EA__SB(A, i, j) (A)[(EA__FE_KD + (i) - (j)) + (size_t)(j)*EA__FE_LDS]

/** Precomputed shape functions at the quadrature points of the uniform mesh. */
typedef struct ea__fe_quad {
  int n;           /* points */
  double w[3];     /* weight * ds/dxi */
  double N[3][3];  /* N[g][a] */
  double dN[3][3]; /* dN/ds [g][a] */
} ea__fe_quad_t;

/** The model workspace. */
struct ea_fe_model {
  ea_arm_t arm;
  ea_fe_settings_t set;
  double tip_mass;              /* [kg] m_L */
  int ne, nn, nd, nf;           /* elements, nodes, full DOFs (3 nn), free DOFs (nd - 3) */
  double h;                     /* element length */
  ea__fe_quad_t quad_k, quad_m; /* stiffness (2-pt), mass (3-pt) quadrature */
  /* state */
  double *q, *v; /* full */
  ea_fe_cable_phase_t phase;
  double cable_value; /* T (active) or L0 (passive) */
  /* constant data */
  double *fg; /* full gravity load vector */
  double *Mb; /* full mass, symmetric band (LDS x nd) */
  /* work */
  double *Kb;       /* full tangent, symmetric band (LDS x nd) */
  double *Kt;       /* second band work matrix (LDS x nd) */
  double fext_norm; /* |F| of eq. 23 (free rows) from the last assembly */
  double *fi;       /* full internal + cable force (f_int - f_cable) */
  double *r;        /* free residual */
  double *dq;       /* free increment */
  double *rhs3;     /* 3 x nf right-hand sides (bordered Newton) */
  double *Gb;       /* general band LU (LDG x nf) */
  int *ipiv;        /* nf */
  double *Ab, *Bb;  /* free symmetric band copies for dsbgvx (LDS x nf) */
  double *Ad, *Bd;  /* dense nf x nf for dsygv / GSL */
  double *Z;        /* nf x nf eigenvectors (column-major, only modes used) */
  double *Qw;       /* nf x nf dsbgvx Q */
  double *work;     /* max(7 nf, 3 nf + lwork_dsygv) */
  int lwork;
  int *iwork, *ifail; /* 5 nf, nf */
  double *evals;      /* nf */
  double *lz;         /* Lanczos work: (EA_FE_MAX_MODES + 12) nf (T, Ritz vectors, dstevx) */
  int modes_valid;    /* modes stored in Z */
  double mode_lambda[EA_FE_MAX_MODES]; /* omega^2 of the stored modes */
  double *phi;                         /* full-length mode shapes, settings.modes x nd */
  /* transient work (full vectors) */
  double *q0, *v0, *a0, *qm, *fm, *tmp, *Cb, *qs, *vs;
  double *acc, *acc0;                /* generalized-alpha accelerations a_{n+1}, a_n */
  double *qprev;                     /* generalized-alpha q_{n-1} (predictor) */
  gsl_eigen_gensymmv_workspace *gws; /* GSL backend */
  gsl_matrix *gA, *gB, *gevec;
  gsl_vector *geval;
};

/* fe_element.c: beam element at (x, y, theta) of its 3 nodes. */
/** Internal force fe (9), tangent ke (9 x 9 row-major, may be NULL) and
 *  strain energy (returned) of element with nodal values u (9). */
double ea__fe_beam_element(const ea_fe_model_t *m, const double u[9], double fe[9], double *ke);
/** Kelvin-Voigt damping per unit coefficient: fd = int B^T D B ud (9) and
 *  ce = int B^T D B (9 x 9 row-major, may be NULL) at nodal values u, rates ud. */
void ea__fe_beam_rate(const ea_fe_model_t *m, const double u[9], const double ud[9], double fd[9],
                      double *ce);
/** Cable: tension, length, force on the tip (fx, fy) and 2x2 stiffness
 *  kc (row-major, may be NULL) for phase/value; returns the potential. */
double ea__fe_cable(const ea_fe_model_t *m, ea_fe_cable_phase_t phase, double value, double x,
                    double y, double *tension, double *length, double f[2], double kc[4]);

/* fe_model.c: assembly and band helpers. */
/** Assemble at full state q: fi = f_int - f_cable (full), K (full symmetric
 *  band, if Kb not NULL) with the cable in phase/value; returns the
 *  potential energy (strain + gravity + cable). */
double ea__fe_assemble(ea_fe_model_t *m, const double *q, ea_fe_cable_phase_t phase, double value,
                       double *fi, double *Kb);
/** Add the strain-rate damping force b int B^T D B v (full) to fd and, if Cb
 *  is not NULL, its velocity derivative b int B^T D B to the full band Cb.
 *  No-op for b <= 0. */
void ea__fe_assemble_rate(ea_fe_model_t *m, const double *q, const double *v, double b, double *fd,
                          double *Cb);
/** Potential energy only. */
double ea__fe_potential(const ea_fe_model_t *m, const double *q, ea_fe_cable_phase_t phase,
                        double value);
/** Add s * A (symmetric band) to B (symmetric band), full size. */
void ea__fe_band_axpy(const ea_fe_model_t *m, double s, const double *A, double *B);
/** y += s * A x for a full symmetric band A and full vectors. */
void ea__fe_band_gemv(const ea_fe_model_t *m, double s, const double *A, const double *x,
                      double *y);
/** LU-factor the free block of the full symmetric band Kb (into m->Gb) and
 *  solve for m->dq = Kb_ff^-1 m->r. Returns EA_ERR_SINGULAR on failure. */
ea_status_t ea__fe_solve_free(ea_fe_model_t *m, const double *Kb);
/** LU-factor the free block of Kb into m->Gb. */
ea_status_t ea__fe_factor_free(ea_fe_model_t *m, const double *Kb);
/** Solve with the factors in m->Gb for nrhs columns of length nf in b. */
ea_status_t ea__fe_solve_factored(ea_fe_model_t *m, double *b, int nrhs);
/** Passive-phase parameter equivalent of the current cable (ACTIVE -> L0). */
void ea__fe_passive_equiv(const ea_fe_model_t *m, const double *q, ea_fe_cable_phase_t *phase,
                          double *value);
/** Newton on the free DOFs of q (full, node 0 held) for the given phase. */
ea_status_t ea__fe_newton_q(ea_fe_model_t *m, double *q, ea_fe_cable_phase_t phase, double value,
                            ea_fe_static_info_t *info, ea_error_t *err);
/** Positions relaxed to the rotations (theta held): iters Newton steps on
 *  the position rows only. */
ea_status_t ea__fe_relax_positions(ea_fe_model_t *m, double *q, ea_fe_cable_phase_t phase,
                                   double value, int iters);

/* LAPACK (Fortran symbols; hidden string lengths passed as size_t). */
void dgbtrf_(const int *m, const int *n, const int *kl, const int *ku, double *ab, const int *ldab,
             int *ipiv, int *info);
void dgbtrs_(const char *trans, const int *n, const int *kl, const int *ku, const int *nrhs,
             const double *ab, const int *ldab, const int *ipiv, double *b, const int *ldb,
             int *info, size_t ltrans);
void dpbtrf_(const char *uplo, const int *n, const int *kd, double *ab, const int *ldab, int *info,
             size_t luplo);
void dsbgvx_(const char *jobz, const char *range, const char *uplo, const int *n, const int *ka,
             const int *kb, double *ab, const int *ldab, double *bb, const int *ldbb, double *q,
             const int *ldq, const double *vl, const double *vu, const int *il, const int *iu,
             const double *abstol, int *m, double *w, double *z, const int *ldz, double *work,
             int *iwork, int *ifail, int *info, size_t ljobz, size_t lrange, size_t luplo);
void dstevx_(const char *jobz, const char *range, const int *n, double *d, double *e,
             const double *vl, const double *vu, const int *il, const int *iu, const double *abstol,
             int *m, double *w, double *z, const int *ldz, double *work, int *iwork, int *ifail,
             int *info, size_t ljobz, size_t lrange);
void dsygv_(const int *itype, const char *jobz, const char *uplo, const int *n, double *a,
            const int *lda, double *b, const int *ldb, double *w, double *work, const int *lwork,
            int *info, size_t ljobz, size_t luplo);

#endif
