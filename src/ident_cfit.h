/*
 * ident_cfit.h - the consistent fit's problem (src/ident_cfit.c: the
 * Cholesky variables, the residual and its Jacobian, the optimality
 * measure and the step out of a false stationary point; src/ident_cbar.c:
 * the barrier stage) as its driver (src/ident_consistent.c) uses it.  Not
 * installed.
 */
#ifndef RPS3_IDENT_CFIT_H
#define RPS3_IDENT_CFIT_H

#include <stddef.h>

#include <gsl/gsl_eigen.h>
#include <gsl/gsl_matrix.h>
#include <gsl/gsl_permutation.h>
#include <gsl/gsl_vector.h>

#include "rps3.h"

#define M4C(A) ((const double(*)[4])(A))

/* the ten entries of a body's upper-triangular 4 x 4 factor U, in the
   order of its variables */
extern const int rps3_cfit_UA[10], rps3_cfit_UB[10];

/* the problem gsl_multifit_nlinear sees */
typedef struct {
  size_t p, nb, nx, nf;
  const rps3_ident_layout *lay;
  const double *R; /* (p + 1) x (p + 1) R factor of [W^1/2 Y, W^1/2 F],
                      row-major, divided by |W^1/2 F| */
  int *owner;      /* p: body of column j, -1 none */
  int *slot;       /* p: its parameter in the body, or its variable */
  double sreg;     /* sqrt(reg) */
  int plain;       /* the variables: 0 log-Cholesky (U's diagonal and a
                      >= 0 column exp of theirs), 1 plain Cholesky (the
                      diagonal itself, free in sign; a >= 0 column s^2) */
  size_t ncurv;    /* plain: the curvature rows after the p + 10 nb */
  double *work;    /* 3 p scratch: the curvature rows and the
                      optimality measure (2 p), the residual's pi (p) */
  gsl_eigen_symmv_workspace *ew; /* and their 4 x 4 eigenproblem */
  gsl_matrix *E, *Q;
  gsl_vector *lam;
} cfit;

/*
 * How far theta (its bodies in body) may be from the optimum, in units
 * of the normalised objective phi.  phi is convex; its KKT conditions,
 * with g = 2 R11^T (R11 pi - r) the residual term's gradient and G_b =
 * d phi / d J_b (grad_of, plus reg 1 from the trace), are: every G_b
 * positive semidefinite, <G_b, J_b> = 0, g_j = 0 on a free column, g_j
 * >= 0 and g_j pi_j = 0 on a >= 0 one.  The measure adds the
 * complementarity terms |<G_b, J_b>| and |g_j pi_j| (together the duality
 * gap <grad phi, pi> when the gradient is dual feasible) and, for each
 * violated dual condition, the decrease of phi's quadratic model along
 * the step it points to, e^2 / (4 h): e the violation (-lambda_min(G_b),
 * step u u^T along its eigenvector u; |g_j| or -g_j, step along column j)
 * and h = |R11 d|^2 the curvature of the step d in pi.  Scratch: c's.
 */
typedef struct {
  double dec; /* the quadratic model's decrease along the step */
  long b, j;  /* the step's body or column (-1 none) */
  double t;   /* its length: J_b += t u u^T, or pi_j += t */
  double u[4];
} descent;

/* the optimality measure's floor, in units of |W^1/2 F|^2: its terms
   are products of the gradient 2 R11^T (R11 pi - r), formed from numbers
   near 1 to about 1e-16, with the bodies; 1e-14 is above that rounding
   and far below what any noise gives (1 % noise: a cost of 1e-4) */
#define RPS3_CFIT_GAP_FLOOR 1e-14

/* converged: the measure within opt_tol of the cost, or at its floor */
static inline int rps3_cfit_optimal(double gap, double cost, double opt_tol) {
  return gap <= opt_tol * cost + RPS3_CFIT_GAP_FLOOR;
}

/* a body's 4 x 4 pseudo-inertia of its ten standard parameters, and
   back */
void rps3_cfit_pseudo_of(const double s[10], double J[4][4]);
void rps3_cfit_std_of(const double J[4][4], double s[10]);
/* column j is >= 0 in the layout */
int rps3_cfit_is_nonneg(const cfit *c, size_t j);
/* pi (p) and the bodies' ten parameters (10 nb) of the variables x */
void rps3_cfit_pi_of(const cfit *c, const double *x, double *pi, double *body);
/* the residual and its Jacobian, for gsl_multifit_nlinear */
int rps3_cfit_f(const gsl_vector *xv, void *params, gsl_vector *f);
int rps3_cfit_df(const gsl_vector *xv, void *params, gsl_matrix *Jm);
/* the optimality measure of theta (best: the step it points to) */
double rps3_cfit_optimality(const cfit *c, const double *theta,
                            const double *body, double reg, descent *best);
/* the step out of a false stationary point into x; 0 when none */
int rps3_cfit_escape(const cfit *c, double *x, const descent *d,
                     const double *body);

/* the plain Cholesky variables x of the bodies' standard parameters
   (body, 10 nb, each pseudo-inertia positive semidefinite) and pi (the
   columns of no body, a >= 0 one >= 0) */
void rps3_cfit_plain_of(const cfit *c, const double *body, const double *pi,
                        double *x);

/*
 * The barrier stage (src/ident_cbar.c): the convex problem in the
 * bodies' standard parameters and the columns of no body, y (nx; body
 * b's ten at 10 b, column j at slot[j] as the Cholesky variables),
 * minimised with the log-barrier of the constraints by Newton's method
 * on a decreasing path.  Its workspace, allocated once a fit.
 */
typedef struct {
  gsl_matrix *M;          /* p x p: R11^T R11 */
  gsl_matrix *H;          /* nx x nx: the Newton matrix, then its factor */
  gsl_vector *g, *dy, *D; /* nx: gradient, step, the scaling of H */
  gsl_vector *yt;         /* nx: a trial point */
  gsl_permutation *perm;  /* nx: the factor's pivots */
  double *res;            /* p: R11 pi - r */
  double *Ji;             /* 16 nb: the inverse pseudo-inertias */
  double *cw;             /* nb + p: the barrier's linear terms, a body's
                             on its trace, a >= 0 column's on it */
} cbar;

/* the workspace for c (its p, nb, nx); RPS3_OK or RPS3_ENOMEM (then
   partly allocated: free it) */
int rps3_cbar_alloc(cbar *w, const cfit *c);
void rps3_cbar_free(cbar *w);

/*
 * From y (moved inside first where it is not: every pseudo-inertia
 * positive definite, a >= 0 column > 0), at most max_iter Newton steps
 * (added to *niter); theta, body, *gap (the optimality measure) and
 * *cost (of theta, rho^2 = R's last diagonal squared included) of the
 * last iterate, y.  1 when the optimality test with opt_tol is met; 0
 * when not: the budget is spent, reg is 0 (the barrier's minimiser need
 * not exist: no step is taken), or Newton's step stalled.
 */
int rps3_cbar_solve(const cfit *c, cbar *w, double *y, double reg,
                    double opt_tol, size_t max_iter, int *niter, double *theta,
                    double *body, double *gap, double *cost);

#endif /* RPS3_IDENT_CFIT_H */
