/*
 * ident_consistent.c - the physically consistent fit on a stacked
 * regressor: each body's pseudo-inertia by its Cholesky factor, first
 * log-Cholesky (Rucker & Wensing 2022: the logarithms of the diagonal,
 * friction by its logarithm), then plain (the diagonal itself, friction
 * by its square root), which reaches an optimum on the boundary of the
 * cone; solved with GSL's nonlinear least squares and an analytic
 * Jacobian to a KKT optimality test; the eigenvalues are checked after
 * the fit.
 *
 * Run once per data set, not per point: it allocates its GSL workspaces
 * and frees them before returning.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_blas.h>
#include <gsl/gsl_eigen.h>
#include <gsl/gsl_linalg.h>
#include <gsl/gsl_multifit_nlinear.h>
#include <gsl/gsl_sort_vector.h>

#include "ident_int.h"
#include "internal.h"

#define M4C(A) ((const double(*)[4])(A))

/* ------------------------------------------------ consistent fit */

/* the ten entries of a body's upper-triangular 4 x 4 factor U, in the
   order of its variables; the diagonal ones are exp(variable) */
static const int UA[10] = {0, 0, 0, 0, 1, 1, 1, 2, 2, 3};
static const int UB[10] = {0, 1, 2, 3, 1, 2, 3, 2, 3, 3};

/* the standard parameters (m, mcx, mcy, mcz, Ixx, Ixy, Ixz, Iyy, Iyz,
   Izz) of a pseudo-inertia J = [[Sigma, h], [h^T, m]], I = tr(Sigma) 1 -
   Sigma; linear, so also of a derivative of J */
static void std_of(const double J[4][4], double s[10]) {
  s[0] = J[3][3];
  s[1] = J[0][3];
  s[2] = J[1][3];
  s[3] = J[2][3];
  s[4] = J[1][1] + J[2][2];
  s[5] = -J[0][1];
  s[6] = -J[0][2];
  s[7] = J[0][0] + J[2][2];
  s[8] = -J[1][2];
  s[9] = J[0][0] + J[1][1];
}

/* and back: Sigma = tr(I)/2 1 - I */
static void pseudo_of(const double s[10], double J[4][4]) {
  double tr = 0.5 * (s[4] + s[7] + s[9]);
  J[0][0] = tr - s[4];
  J[1][1] = tr - s[7];
  J[2][2] = tr - s[9];
  J[0][1] = J[1][0] = -s[5];
  J[0][2] = J[2][0] = -s[6];
  J[1][2] = J[2][1] = -s[8];
  J[0][3] = J[3][0] = s[1];
  J[1][3] = J[3][1] = s[2];
  J[2][3] = J[3][2] = s[3];
  J[3][3] = s[0];
}

/* the gradient G = d phi / d J of phi through the standard parameters s
   = std_of(J) (g their gradient): the adjoint of std_of, <G, dJ> = g .
   std_of(dJ) for every symmetric dJ */
static void grad_of(const double g[10], double G[4][4]) {
  G[3][3] = g[0];
  G[0][3] = G[3][0] = 0.5 * g[1];
  G[1][3] = G[3][1] = 0.5 * g[2];
  G[2][3] = G[3][2] = 0.5 * g[3];
  G[0][0] = g[7] + g[9];
  G[1][1] = g[4] + g[9];
  G[2][2] = g[4] + g[7];
  G[0][1] = G[1][0] = -0.5 * g[5];
  G[0][2] = G[2][0] = -0.5 * g[6];
  G[1][2] = G[2][1] = -0.5 * g[8];
}

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
  double *work;    /* 2 p scratch for the curvature rows */
  gsl_eigen_symmv_workspace *ew; /* and their 4 x 4 eigenproblem */
  gsl_matrix *E, *Q;
  gsl_vector *lam;
} cfit;

/* a diagonal entry of U of its variable, and its derivative */
static double diag_of(const cfit *c, double v) { return c->plain ? v : exp(v); }
static double ddiag(const cfit *c, double v) { return c->plain ? 1.0 : exp(v); }

/* a >= 0 column of its variable, and its derivative */
static double nonneg_of(const cfit *c, double v) {
  return c->plain ? v * v : exp(v);
}
static double dnonneg(const cfit *c, double v) {
  return c->plain ? 2.0 * v : exp(v);
}

static int is_nonneg(const cfit *c, size_t j) {
  return c->lay->kind && c->lay->kind[j] == RPS3_IDENT_NONNEG;
}

static void factor_of(const cfit *c, const double *x, double U[4][4]) {
  int v;
  memset(U, 0, 16 * sizeof(double));
  for (v = 0; v < 10; v++)
    U[UA[v]][UB[v]] = UA[v] == UB[v] ? diag_of(c, x[v]) : x[v];
}

/* pi of the variables x */
static void pi_of(const cfit *c, const double *x, double *pi, double *body) {
  size_t b, j;
  for (b = 0; b < c->nb; b++) {
    double U[4][4], J[4][4], s[10];
    int i, k, q;
    factor_of(c, x + 10 * b, U);
    for (i = 0; i < 4; i++)
      for (k = 0; k < 4; k++) {
        J[i][k] = 0.0;
        for (q = 0; q < 4; q++) J[i][k] += U[i][q] * U[k][q];
      }
    std_of(M4C(J), s);
    if (body) memcpy(body + 10 * b, s, sizeof(s));
    for (k = 0; k < 10; k++)
      if (c->lay->col[b][k] >= 0) pi[c->lay->col[b][k]] = s[k];
  }
  for (j = 0; j < c->p; j++) {
    double v;
    if (c->owner[j] >= 0) continue;
    v = x[c->slot[j]];
    pi[j] = is_nonneg(c, j) ? nonneg_of(c, v) : v;
  }
}

static int cfit_f(const gsl_vector *xv, void *params, gsl_vector *f) {
  const cfit *c = params;
  double pi[256], *pp = pi, *heap = NULL;
  size_t i, j, b;
  int v;
  if (c->p > 256) {
    heap = malloc(c->p * sizeof(double));
    if (heap == NULL) return GSL_ENOMEM;
    pp = heap;
  }
  pi_of(c, xv->data, pp, NULL);
  if (!rps3_all_finite(pp, (int)c->p)) {
    free(heap);
    return GSL_EDOM; /* a step overflowed exp: the solver stops, ENOCONV */
  }
  for (i = 0; i < c->p; i++) {
    double s = -c->R[i * (c->p + 1) + c->p];
    for (j = i; j < c->p; j++) s += c->R[i * (c->p + 1) + j] * pp[j];
    gsl_vector_set(f, i, s);
  }
  for (b = 0; b < c->nb; b++)
    for (v = 0; v < 10; v++) {
      double xb = gsl_vector_get(xv, 10 * b + (size_t)v);
      gsl_vector_set(f, c->p + 10 * b + (size_t)v,
                     c->sreg * (UA[v] == UB[v] ? diag_of(c, xb) : xb));
    }
  /* the curvature rows: 0 here, their Jacobian in cfit_df */
  for (i = c->p + 10 * c->nb; i < c->nf; i++) gsl_vector_set(f, i, 0.0);
  free(heap);
  return GSL_SUCCESS;
}

/*
 * The plain Cholesky variables' second-order term that Gauss-Newton
 * leaves out, as rows of the Jacobian whose residuals are 0.  With f the
 * p reduced residuals, 1/2 |f|^2 has, beyond 1/2 |J s|^2, the curvature
 * f^T R11 pi(D D^T) = tr(D^T G D) along a step D of a body's U (G =
 * grad_of(R11^T f), the gradient of 1/2 |f|^2 in J_b), and g_j ds^2 along
 * a >= 0 column's s (g = R11^T f).  Near the boundary of the cone this
 * is the whole curvature of a vanishing diagonal (J U_ii^2 terms vanish
 * with U_ii) and Gauss-Newton without it overshoots and crawls; with the
 * rows sqrt(2 lambda) q^T D[:, k] for each eigenpair of G's positive part
 * (and sqrt(2 g_j) for a >= 0 column with g_j > 0) the trust region's
 * model is Newton's wherever the gradient is dual feasible (G positive
 * semidefinite, g_j >= 0: near the optimum).
 */
static void curvature_rows(const cfit *c, const double *x, gsl_matrix *Jm) {
  const size_t p = c->p, P1 = c->p + 1, base = c->p + 10 * c->nb;
  double *pi = c->work, *gr = c->work + p;
  size_t i, j, b, row = base + 16 * c->nb;
  pi_of(c, x, pi, NULL);
  for (j = 0; j < p; j++) gr[j] = 0.0;
  for (i = 0; i < p; i++) {
    double f = -c->R[i * P1 + p];
    for (j = i; j < p; j++) f += c->R[i * P1 + j] * pi[j];
    for (j = i; j < p; j++) gr[j] += c->R[i * P1 + j] * f;
  }
  for (b = 0; b < c->nb; b++) {
    double gs[10], G[4][4];
    int k, q, m, v;
    for (k = 0; k < 10; k++)
      gs[k] = c->lay->col[b][k] >= 0 ? gr[c->lay->col[b][k]] : 0.0;
    grad_of(gs, G);
    for (k = 0; k < 4; k++)
      for (q = 0; q < 4; q++) gsl_matrix_set(c->E, k, q, G[k][q]);
    gsl_eigen_symmv(c->E, c->lam, c->Q, c->ew);
    for (m = 0; m < 4; m++) {
      double l = gsl_vector_get(c->lam, m), w;
      if (!(l > 0.0)) continue;
      w = sqrt(2.0 * l);
      for (v = 0; v < 10; v++)
        gsl_matrix_set(Jm, base + 16 * b + 4 * (size_t)m + (size_t)UB[v],
                       10 * b + (size_t)v,
                       w * gsl_matrix_get(c->Q, UA[v], m));
    }
  }
  for (j = 0; j < p; j++)
    if (c->owner[j] < 0 && is_nonneg(c, j)) {
      if (gr[j] > 0.0)
        gsl_matrix_set(Jm, row, (size_t)c->slot[j], sqrt(2.0 * gr[j]));
      row++;
    }
}

static int cfit_df(const gsl_vector *xv, void *params, gsl_matrix *Jm) {
  const cfit *c = params;
  size_t i, j, b;
  int v, k, q;
  gsl_matrix_set_zero(Jm);
  /* d pi / d x, one variable at a time, pushed through R */
  for (b = 0; b < c->nb; b++) {
    double U[4][4];
    factor_of(c, xv->data + 10 * b, U);
    for (v = 0; v < 10; v++) {
      /* J = U U^T: dJ = e (E U^T + U E^T) for E the unit entry (a, b), e
         the derivative of U_ab by its variable */
      double dJ[4][4], ds[10],
          e = UA[v] == UB[v] ? ddiag(c, xv->data[10 * b + (size_t)v]) : 1.0;
      size_t col = 10 * b + (size_t)v;
      for (k = 0; k < 4; k++)
        for (q = 0; q < 4; q++)
          dJ[k][q] = e * ((k == UA[v] ? U[q][UB[v]] : 0.0) +
                          (q == UA[v] ? U[k][UB[v]] : 0.0));
      std_of(M4C(dJ), ds);
      for (k = 0; k < 10; k++) {
        int pj = c->lay->col[b][k];
        if (pj < 0 || ds[k] == 0.0) continue;
        for (i = 0; i <= (size_t)pj; i++)
          Jm->data[i * Jm->tda + col] += c->R[i * (c->p + 1) + pj] * ds[k];
      }
      gsl_matrix_set(Jm, c->p + col, col, c->sreg * e);
    }
  }
  for (j = 0; j < c->p; j++) {
    double dp;
    size_t col;
    if (c->owner[j] >= 0) continue;
    col = (size_t)c->slot[j];
    dp = is_nonneg(c, j) ? dnonneg(c, gsl_vector_get(xv, col)) : 1.0;
    for (i = 0; i <= j; i++)
      gsl_matrix_set(Jm, i, col, c->R[i * (c->p + 1) + j] * dp);
  }
  if (c->plain) curvature_rows(c, xv->data, Jm);
  return GSL_SUCCESS;
}

/* the layout's checks; owner and slot of every column */
static int check_layout(const rps3_ident_layout *lay, size_t p, int *owner,
                        int *slot, size_t *nx, char *err, size_t errsz) {
  size_t b, j;
  int k;
  if (lay == NULL)
    return rps3_ident_fail(err, errsz, RPS3_EINVAL, "layout is NULL");
  if (lay->nbody > 0 && lay->col == NULL)
    return rps3_ident_fail(err, errsz, RPS3_EINVAL, "layout.col is NULL");
  if (lay->nbody > p)
    return rps3_ident_fail(err, errsz, RPS3_EINVAL,
                           "layout: %lu bodies for %lu columns",
                           (unsigned long)lay->nbody, (unsigned long)p);
  for (j = 0; j < p; j++) owner[j] = -1;
  for (b = 0; b < lay->nbody; b++)
    for (k = 0; k < 10; k++) {
      int c = lay->col[b][k];
      if (c < -1 || c >= (int)p)
        return rps3_ident_fail(
            err, errsz, RPS3_EINVAL,
            "layout.col[%lu][%d] = %d: not a column (0..%lu) or -1",
            (unsigned long)b, k, c, (unsigned long)p - 1);
      if (c < 0) continue;
      if (owner[c] >= 0)
        return rps3_ident_fail(
            err, errsz, RPS3_EINVAL,
            "layout.col[%lu][%d] = %d: column %d is already body "
            "%d's parameter %d",
            (unsigned long)b, k, c, c, owner[c], slot[c]);
      owner[c] = (int)b;
      slot[c] = k;
    }
  *nx = 10 * lay->nbody;
  for (j = 0; j < p; j++) {
    if (lay->kind && lay->kind[j] != RPS3_IDENT_FREE &&
        lay->kind[j] != RPS3_IDENT_NONNEG)
      return rps3_ident_fail(
          err, errsz, RPS3_EINVAL,
          "layout.kind[%lu] = %d: must be 0 (free) or 1 (>= 0)",
          (unsigned long)j, lay->kind[j]);
    if (owner[j] >= 0) continue;
    slot[j] = (int)(*nx)++;
  }
  return RPS3_OK;
}

/*
 * The start: the minimum-norm least-squares pi (singular values of the
 * column-scaled R below START_TOL of the largest dropped: a start needs
 * no more, and a near-dependence kept would throw it far), each body's
 * pseudo-inertia of it (its parameters not in pi 0) with its eigenvalues raised
 * to at least 1e-3 of the largest, factored J = U U^T (a Cholesky of the
 * reversed matrix); a >= 0 column, pi = exp(x), from the logarithm of its value
 * (1e-3 of its magnitude when it is negative).
 */
#define START_TOL 1e-6
static int start_point(const cfit *c, double *x) {
  const double tol = START_TOL;
  double dmax;
  size_t p = c->p, i, j, b;
  int status = RPS3_ENOMEM;
  gsl_matrix *A = gsl_matrix_alloc(p, p), *V = gsl_matrix_alloc(p, p);
  gsl_vector *S = gsl_vector_alloc(p), *wk = gsl_vector_alloc(p);
  gsl_vector *D = gsl_vector_alloc(p), *pi = gsl_vector_alloc(p);
  gsl_eigen_symmv_workspace *ew = gsl_eigen_symmv_alloc(4);
  gsl_matrix *E = gsl_matrix_alloc(4, 4), *Q = gsl_matrix_alloc(4, 4);
  gsl_vector *lam = gsl_vector_alloc(4);
  if (!A || !V || !S || !wk || !D || !pi || !ew || !E || !Q || !lam) goto out;
  dmax = 0.0;
  for (j = 0; j < p; j++) {
    double s = 0.0;
    for (i = 0; i <= j; i++) s += c->R[i * (p + 1) + j] * c->R[i * (p + 1) + j];
    gsl_vector_set(D, j, sqrt(s));
    if (sqrt(s) > dmax) dmax = sqrt(s);
  }
  /* a column below tol times the largest: left out (pi 0) */
  for (j = 0; j < p; j++)
    if (!(gsl_vector_get(D, j) > tol * dmax)) gsl_vector_set(D, j, HUGE_VAL);
  for (i = 0; i < p; i++)
    for (j = 0; j < p; j++)
      gsl_matrix_set(
          A, i, j, j >= i ? c->R[i * (p + 1) + j] / gsl_vector_get(D, j) : 0.0);
  gsl_linalg_SV_decomp(A, V, S, wk);
  /* pi = D^-1 V S^+ U^T z */
  for (j = 0; j < p; j++) gsl_vector_set(pi, j, 0.0);
  for (i = 0; i < p; i++) {
    double s = gsl_vector_get(S, i), u = 0.0;
    if (!(s > tol * gsl_vector_get(S, 0))) continue;
    for (j = 0; j < p; j++)
      u += gsl_matrix_get(A, j, i) * c->R[j * (p + 1) + p];
    for (j = 0; j < p; j++) pi->data[j] += gsl_matrix_get(V, j, i) * u / s;
  }
  for (j = 0; j < p; j++) pi->data[j] /= gsl_vector_get(D, j);

  for (b = 0; b < c->nb; b++) {
    double s[10], J[4][4], lmax, U[4][4];
    int k, q, r;
    for (k = 0; k < 10; k++) {
      int pj = c->lay->col[b][k];
      s[k] = pj >= 0 ? gsl_vector_get(pi, (size_t)pj) : 0.0;
    }
    pseudo_of(s, J);
    /* a start that overflowed: a unit body (the solver moves it) */
    if (!rps3_all_finite(&J[0][0], 16))
      for (k = 0; k < 4; k++)
        for (q = 0; q < 4; q++) J[k][q] = k == q;
    for (k = 0; k < 4; k++)
      for (q = 0; q < 4; q++) gsl_matrix_set(E, k, q, J[k][q]);
    gsl_eigen_symmv(E, lam, Q, ew);
    lmax = 0.0;
    for (k = 0; k < 4; k++)
      if (gsl_vector_get(lam, k) > lmax) lmax = gsl_vector_get(lam, k);
    if (!(lmax > 0.0) || !isfinite(lmax)) lmax = 1.0;
    /* raised to 1e-3 of the largest: positive definite with a condition
       number of at most 1e3, so that the Cholesky factorization below
       cannot fail (GSL would raise its error handler) */
    for (k = 0; k < 4; k++)
      if (!(gsl_vector_get(lam, k) >= 1e-3 * lmax))
        gsl_vector_set(lam, k, 1e-3 * lmax);
    /* the reversed matrix P J P, P the reversal, for a lower Cholesky
       factor L: J = (P L P)(P L P)^T, P L P upper triangular */
    for (k = 0; k < 4; k++)
      for (q = 0; q < 4; q++) {
        double v = 0.0;
        for (r = 0; r < 4; r++)
          v += gsl_matrix_get(Q, k, r) * gsl_vector_get(lam, r) *
               gsl_matrix_get(Q, q, r);
        gsl_matrix_set(E, 3 - k, 3 - q, v);
      }
    if (gsl_linalg_cholesky_decomp1(E) != GSL_SUCCESS) {
      status = RPS3_ENOCONV;
      goto out;
    }
    for (k = 0; k < 4; k++)
      for (q = 0; q < 4; q++)
        U[k][q] = q >= k ? gsl_matrix_get(E, 3 - k, 3 - q) : 0.0;
    for (k = 0; k < 10; k++) {
      double u = U[UA[k]][UB[k]];
      x[10 * b + (size_t)k] = UA[k] == UB[k] ? log(fabs(u)) : u;
    }
  }
  for (j = 0; j < p; j++) {
    double v = gsl_vector_get(pi, j);
    if (c->owner[j] >= 0) continue;
    if (c->lay->kind && c->lay->kind[j] == RPS3_IDENT_NONNEG)
      v = log(fmax(fmax(v, 1e-3 * fabs(v)), 1e-300));
    x[c->slot[j]] = v;
  }
  status = RPS3_OK;
out:
  gsl_matrix_free(A);
  gsl_matrix_free(V);
  gsl_vector_free(S);
  gsl_vector_free(wk);
  gsl_vector_free(D);
  gsl_vector_free(pi);
  if (ew) gsl_eigen_symmv_free(ew);
  gsl_matrix_free(E);
  gsl_matrix_free(Q);
  gsl_vector_free(lam);
  return status;
}

static const int paper_col[2][10] = {
    /* a link about its pin, x along the link, z the pin axis */
    {-1, 1, -1, -1, -1, -1, -1, -1, -1, 2},
    /* the payload about the platform centre, platform axes */
    {3, 4, 5, 6, 7, -1, -1, 8, -1, 9}};
static const int paper_kind[RPS3_NPAPER] = {
    RPS3_IDENT_NONNEG, 0, 0, 0, 0, 0, 0, 0, 0, 0, RPS3_IDENT_NONNEG,
    RPS3_IDENT_NONNEG};
static const rps3_ident_layout paper_layout = {2, paper_col, paper_kind};

const rps3_ident_layout *rps3_ident_paper_layout(void) { return &paper_layout; }

/* R of the QR of [W^1/2 Y, W^1/2 F], (p + 1)^2 row-major, divided by
   |W^1/2 F| (1 when F = 0): |W^1/2 (Y pi - F)|^2 = |R11 pi - r|^2 +
   rho^2, p rows instead of n.  NULL: out of memory */
static double *reduced(const rps3_ident_data *dt, double *scale) {
  size_t n = dt->n, p = dt->p, i, j;
  gsl_matrix *A = gsl_matrix_alloc(n, p + 1);
  gsl_vector *tau = gsl_vector_alloc(p + 1);
  double *R = calloc((p + 1) * (p + 1), sizeof(double)), sc = 0.0;
  if (!A || !tau || !R) {
    free(R);
    R = NULL;
    goto out;
  }
  for (i = 0; i < n; i++) {
    double sw = sqrt(dt->weight ? dt->weight[i] : 1.0);
    for (j = 0; j < p; j++) gsl_matrix_set(A, i, j, sw * dt->Y[i * p + j]);
    gsl_matrix_set(A, i, p, sw * dt->F[i]);
    sc += sw * dt->F[i] * sw * dt->F[i];
  }
  sc = sqrt(sc);
  if (!(sc > 0.0)) sc = 1.0;
  gsl_linalg_QR_decomp(A, tau);
  for (i = 0; i <= p; i++)
    for (j = i; j <= p; j++) R[i * (p + 1) + j] = gsl_matrix_get(A, i, j) / sc;
  *scale = sc;
out:
  gsl_matrix_free(A);
  gsl_vector_free(tau);
  return R;
}

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
  double dec;  /* the quadratic model's decrease along the step */
  long b, j;   /* the step's body or column (-1 none) */
  double t;    /* its length: J_b += t u u^T, or pi_j += t */
  double u[4];
} descent;

static double optimality(const cfit *c, const double *theta,
                         const double *body, double reg, descent *best) {
  const size_t p = c->p, P1 = c->p + 1;
  const double *R = c->R;
  double *g = c->work, *d = c->work + p, est = 0.0;
  gsl_matrix *E = c->E, *Q = c->Q;
  gsl_vector *lam = c->lam;
  size_t i, j, b;
  if (best) {
    best->dec = 0.0;
    best->b = best->j = -1;
  }
  for (j = 0; j < p; j++) g[j] = 0.0;
  for (i = 0; i < p; i++) {
    double s = -R[i * P1 + p];
    for (j = i; j < p; j++) s += R[i * P1 + j] * theta[j];
    for (j = i; j < p; j++) g[j] += 2.0 * R[i * P1 + j] * s;
  }
  for (b = 0; b < c->nb; b++) {
    double gs[10], G[4][4], J[4][4], U[4][4], ds[10], e, h = 0.0, cg = 0.0,
        dec;
    int k, q;
    for (k = 0; k < 10; k++)
      gs[k] = c->lay->col[b][k] >= 0 ? g[c->lay->col[b][k]] : 0.0;
    grad_of(gs, G);
    pseudo_of(body + 10 * b, J);
    for (k = 0; k < 4; k++) {
      G[k][k] += reg;
      for (q = 0; q < 4; q++) {
        cg += G[k][q] * J[k][q];
        gsl_matrix_set(E, k, q, G[k][q]);
      }
    }
    est += fabs(cg);
    gsl_eigen_symmv(E, lam, Q, c->ew);
    gsl_eigen_symmv_sort(lam, Q, GSL_EIGEN_SORT_VAL_ASC);
    e = -gsl_vector_get(lam, 0);
    if (!(e > 0.0)) continue;
    /* the step u u^T in pi, and its curvature */
    for (k = 0; k < 4; k++)
      for (q = 0; q < 4; q++)
        U[k][q] = gsl_matrix_get(Q, k, 0) * gsl_matrix_get(Q, q, 0);
    std_of(M4C(U), ds);
    for (j = 0; j < p; j++) d[j] = 0.0;
    for (k = 0; k < 10; k++)
      if (c->lay->col[b][k] >= 0) d[c->lay->col[b][k]] = ds[k];
    for (i = 0; i < p; i++) {
      double s = 0.0;
      for (j = i; j < p; j++) s += R[i * P1 + j] * d[j];
      h += s * s;
    }
    dec = h > 0.0 ? e * e / (4.0 * h) : HUGE_VAL;
    est += dec;
    if (best && h > 0.0 && dec > best->dec) {
      best->dec = dec;
      best->b = (long)b;
      best->j = -1;
      best->t = e / (2.0 * h);
      for (k = 0; k < 4; k++) best->u[k] = gsl_matrix_get(Q, k, 0);
    }
  }
  for (j = 0; j < p; j++) {
    double e, h = 0.0, dec;
    if (c->owner[j] >= 0) continue;
    est += fabs(g[j] * theta[j]);
    e = is_nonneg(c, j) ? -g[j] : fabs(g[j]);
    if (!(e > 0.0)) continue;
    for (i = 0; i <= j; i++) h += R[i * P1 + j] * R[i * P1 + j];
    dec = h > 0.0 ? e * e / (4.0 * h) : HUGE_VAL;
    est += dec;
    if (best && h > 0.0 && dec > best->dec) {
      best->dec = dec;
      best->b = -1;
      best->j = (long)j;
      best->t = -g[j] / (2.0 * h);
    }
  }
  return est;
}

/* upper triangular U with U U^T = J for a positive semidefinite J (the
   Cholesky factor of the reversed matrix; a pivot at or below 1e-14 of
   the largest diagonal entry: its column 0) */
static void psd_factor(const double J[4][4], double U[4][4]) {
  double tol = 0.0;
  int i, k, q;
  for (k = 0; k < 4; k++) tol = fmax(tol, J[k][k]);
  tol *= 1e-14;
  memset(U, 0, 16 * sizeof(double));
  for (k = 3; k >= 0; k--) {
    double d = J[k][k];
    for (q = k + 1; q < 4; q++) d -= U[k][q] * U[k][q];
    if (!(d > tol)) continue;
    U[k][k] = sqrt(d);
    for (i = 0; i < k; i++) {
      double s = J[i][k];
      for (q = k + 1; q < 4; q++) s -= U[i][q] * U[k][q];
      U[i][k] = s / U[k][k];
    }
  }
}

/*
 * The step out of a stationary point of the plain variables that is not
 * the optimum: U_ii = 0 (or s_j = 0) with the gradient asking for more
 * (a negative eigenvalue of G_b, g_j < 0), where the gradient in U is 0
 * and no trust-region step sees the way.  The step is optimality()'s
 * best, taken in pi: J_b + t u u^T refactored, or pi_j + t.  0 when
 * there is none.
 */
static int escape(const cfit *c, double *x, const descent *d,
                  const double *body) {
  if (d->b >= 0) {
    double J[4][4], U[4][4];
    int k, q;
    pseudo_of(body + 10 * d->b, J);
    for (k = 0; k < 4; k++)
      for (q = 0; q < 4; q++) J[k][q] += d->t * d->u[k] * d->u[q];
    psd_factor(M4C(J), U);
    for (k = 0; k < 10; k++) x[10 * d->b + k] = U[UA[k]][UB[k]];
    return 1;
  }
  if (d->j >= 0) {
    size_t sl = (size_t)c->slot[d->j];
    if (is_nonneg(c, (size_t)d->j))
      x[sl] = sqrt(fmax(x[sl] * x[sl] + d->t, 0.0));
    else
      x[sl] += d->t;
    return 1;
  }
  return 0;
}

/* the optimality measure's floor, in units of |W^1/2 F|^2: its terms
   are products of the gradient 2 R11^T (R11 pi - r), formed from numbers
   near 1 to about 1e-16, with the bodies; 1e-14 is above that rounding
   and far below what any noise gives (1 % noise: a cost of 1e-4) */
#define GAP_FLOOR 1e-14

/* converged: the measure within opt_tol of the cost, or at its floor */
static int optimal(double gap, double cost, const rps3_ident_opts *o) {
  return gap <= o->opt_tol * cost + GAP_FLOOR;
}

/* the log-Cholesky stage's iterations: it reaches an interior optimum's
   neighbourhood in a few (the paper model's fits take 6 to 10) and only
   crawls towards a boundary one after; the plain stage takes over */
#define LOG_ITER 30

/*
 * The trust-region solve in c's variables from x with the analytic
 * Jacobian, at most max_iter iterations (added to *niter), its last
 * iterate back into x and GSL's status into *gst; RPS3_OK or
 * RPS3_ENOMEM.  theta NULL: GSL's driver and its tests (xtol, gtol,
 * ftol).  Otherwise the iterations are ours and stop on optimality: the
 * measure *gap (of theta and body, the last iterate's) at most opt_tol
 * times the cost.  GSL's gtol test is scaled by max(|f|^2, 1), and the
 * normalised cost is below 1: on nearly exact data, where the cost is the
 * reg term's 1e-10, it stops while the bodies the data do not see are
 * still far from their lightest.
 */
static int solve(cfit *c, double *x, const rps3_ident_opts *o, size_t max_iter,
                 int *niter, int *gst, double *theta, double *body,
                 double *gap) {
  const double rho2 = c->R[c->p * (c->p + 1) + c->p] * c->R[c->p * (c->p + 1) + c->p];
  gsl_multifit_nlinear_fdf fdf;
  gsl_multifit_nlinear_parameters fp =
      gsl_multifit_nlinear_default_parameters();
  gsl_multifit_nlinear_workspace *w;
  gsl_vector_view xv = gsl_vector_view_array(x, c->nx);
  int info = 0;
  size_t it;
  /* Powell's dogleg: Levenberg-Marquardt's steps creep along a
     log-Cholesky diagonal that heads for a singular pseudo-inertia (a
     body the data see only in part), thousands of iterations where the
     dogleg takes tens.  Levenberg's scaling (J^T J's diagonal at each
     step) rather than More's (the largest seen): a variable whose
     influence fades as it heads for a boundary (exp of it towards 0)
     keeps a step it can still take */
  fp.trs = gsl_multifit_nlinear_trs_dogleg;
  fp.scale = gsl_multifit_nlinear_scale_levenberg;
  fdf.f = cfit_f;
  fdf.df = cfit_df;
  fdf.fvv = NULL;
  fdf.n = c->nf;
  fdf.p = c->nx;
  fdf.params = c;
  w = gsl_multifit_nlinear_alloc(gsl_multifit_nlinear_trust, &fp, c->nf, c->nx);
  if (w == NULL) return RPS3_ENOMEM;
  *gst = gsl_multifit_nlinear_init(&xv.vector, &fdf, w);
  if (*gst == GSL_SUCCESS && theta == NULL && max_iter > 0)
    *gst = gsl_multifit_nlinear_driver(max_iter, o->xtol, o->gtol, o->ftol,
                                       NULL, NULL, &info, w);
  for (it = 0; theta != NULL && *gst == GSL_SUCCESS; it++) {
    double fn = gsl_blas_dnrm2(gsl_multifit_nlinear_residual(w));
    pi_of(c, gsl_multifit_nlinear_position(w)->data, theta, body);
    *gap = optimality(c, theta, body, c->sreg * c->sreg, NULL);
    if (optimal(*gap, rho2 + fn * fn, o)) break;
    if (it == max_iter) {
      *gst = GSL_EMAXITER;
      break;
    }
    *gst = gsl_multifit_nlinear_iterate(w);
  }
  *niter += (int)gsl_multifit_nlinear_niter(w);
  memcpy(x, gsl_multifit_nlinear_position(w)->data, c->nx * sizeof(double));
  if (theta != NULL) {
    pi_of(c, x, theta, body);
    *gap = optimality(c, theta, body, c->sreg * c->sreg, NULL);
  }
  gsl_multifit_nlinear_free(w);
  return RPS3_OK;
}

/* the log-Cholesky iterate x in the plain Cholesky variables: the same
   J_b and pi */
static void to_plain(cfit *c, double *x) {
  size_t b, j;
  int v;
  for (b = 0; b < c->nb; b++)
    for (v = 0; v < 10; v++)
      if (UA[v] == UB[v]) x[10 * b + (size_t)v] = exp(x[10 * b + (size_t)v]);
  for (j = 0; j < c->p; j++)
    if (c->owner[j] < 0 && is_nonneg(c, j))
      x[c->slot[j]] = exp(0.5 * x[c->slot[j]]);
  c->plain = 1;
  c->ncurv = 16 * c->nb;
  for (j = 0; j < c->p; j++) c->ncurv += c->owner[j] < 0 && is_nonneg(c, j);
  c->nf = c->p + 10 * c->nb + c->ncurv;
}

/* what was reached, checked whatever the solver said (gst, reported):
   the residual, the cost, every pseudo-inertia's eigenvalues and the >= 0
   columns (fit->consistent), then the optimality measure fit->gap against
   opt_tol; the status.  RPS3_ENOMEM when the eigen workspace cannot be
   had */
static int check_fit(const cfit *c, const rps3_ident_opts *o, double scale,
                     const double *body, int gst, rps3_ident_fit *fit,
                     char *err, size_t errsz) {
  const size_t p = c->p;
  const double *R = c->R;
  gsl_eigen_symm_workspace *ew = gsl_eigen_symm_alloc(4);
  gsl_matrix *E = gsl_matrix_alloc(4, 4);
  gsl_vector *lam = gsl_vector_alloc(4);
  double rss = R[p * (p + 1) + p] * R[p * (p + 1) + p], trsum = 0.0;
  size_t i, j, b;
  int status = RPS3_OK, eig_ok = 1;
  if (!ew || !E || !lam) {
    status =
        rps3_ident_fail(err, errsz, RPS3_ENOMEM, "consistent: out of memory");
    goto out;
  }
  for (i = 0; i < p; i++) {
    double s = -R[i * (p + 1) + p];
    for (j = i; j < p; j++) s += R[i * (p + 1) + j] * fit->theta[j];
    rss += s * s;
  }
  fit->rss = rss * scale * scale;
  for (b = 0; b < c->nb; b++) {
    double J[4][4], lmax = 0.0;
    int k, q;
    pseudo_of(body + 10 * b, J);
    trsum += J[0][0] + J[1][1] + J[2][2] + J[3][3];
    for (k = 0; k < 4; k++)
      for (q = 0; q < 4; q++) gsl_matrix_set(E, k, q, J[k][q]);
    gsl_eigen_symm(E, lam, ew);
    gsl_sort_vector(lam);
    for (k = 0; k < 4; k++) {
      if (fit->eig) fit->eig[4 * b + (size_t)k] = gsl_vector_get(lam, k);
      if (fabs(gsl_vector_get(lam, k)) > lmax)
        lmax = fabs(gsl_vector_get(lam, k));
    }
    if (gsl_vector_get(lam, 0) >= -o->eig_tol * lmax) continue;
    if (eig_ok)
      status = rps3_ident_fail(
          err, errsz, RPS3_ENOCONV,
          "consistent: body %lu's pseudo-inertia has eigenvalue %.3g "
          "below -%.3g times its largest %.3g: not consistent",
          (unsigned long)b, gsl_vector_get(lam, 0), o->eig_tol, lmax);
    eig_ok = 0;
  }
  if (fit->body) memcpy(fit->body, body, 10 * c->nb * sizeof(double));
  fit->cost = rss + o->reg * trsum;
  for (j = 0; j < p && status == RPS3_OK; j++) {
    if (!isfinite(fit->theta[j]))
      status = rps3_ident_fail(err, errsz, RPS3_ENOCONV,
                               "consistent: parameter %lu is not finite",
                               (unsigned long)j);
    else if (c->owner[j] < 0 && c->lay->kind &&
             c->lay->kind[j] == RPS3_IDENT_NONNEG && fit->theta[j] < 0.0)
      status = rps3_ident_fail(err, errsz, RPS3_ENOCONV,
                               "consistent: parameter %lu = %g < 0",
                               (unsigned long)j, fit->theta[j]);
  }
  /* consistent means checked, converged or not: the last iterate of a
     stopped solve is a consistent body set too */
  fit->consistent = status == RPS3_OK;
  /* converged means optimal: the KKT measure, whatever GSL's tests said
     (they stop on a small step, which a stalled iterate also takes) */
  if (status == RPS3_OK && !optimal(fit->gap, fit->cost, o))
    status = rps3_ident_fail(
        err, errsz, RPS3_ENOCONV,
        "consistent: not converged after %d iterations (GSL: %s): the "
        "optimality measure %.3g is above opt_tol = %g times the cost "
        "%.6g (+ %g); the last iterate is returned",
        fit->niter, gsl_strerror(gst), fit->gap, o->opt_tol, fit->cost,
        GAP_FLOOR);
out:
  if (ew) gsl_eigen_symm_free(ew);
  gsl_matrix_free(E);
  gsl_vector_free(lam);
  return status;
}

int rps3_ident_consistent(const rps3_ident_data *dt,
                          const rps3_ident_layout *lay,
                          const rps3_ident_opts *o, rps3_ident_fit *fit,
                          rps3_check *chk) {
  char *err = chk != NULL ? chk->msg : NULL;
  size_t errsz = chk != NULL ? sizeof chk->msg : 0;
  rps3_ident_opts def;
  cfit c;
  size_t p, j, nx = 0;
  int status, *owner = NULL, *slot = NULL, gst = GSL_SUCCESS;
  double *R = NULL, *x0 = NULL, *body = NULL, scale = 1.0;
  rps3_check_clear(chk);
  memset(&c, 0, sizeof c);
  if (o == NULL) {
    rps3_ident_opts_default(&def);
    o = &def;
  }
  if (fit == NULL || fit->theta == NULL)
    return rps3_ident_fail(err, errsz, RPS3_EINVAL,
                           "fit or fit->theta is NULL");
  fit->consistent = 0;
  fit->niter = 0;
  fit->gap = (double)NAN;
  status = rps3_ident_check_data(dt, o, 0, err, errsz);
  if (status != RPS3_OK) return status;
  p = dt->p;
  for (j = 0; j < p; j++) fit->theta[j] = (double)NAN;
  owner = malloc(p * sizeof(int));
  slot = malloc(p * sizeof(int));
  if (owner == NULL || slot == NULL) {
    status =
        rps3_ident_fail(err, errsz, RPS3_ENOMEM, "consistent: out of memory");
    goto out;
  }
  status = check_layout(lay, p, owner, slot, &nx, err, errsz);
  if (status != RPS3_OK) goto out;
  R = reduced(dt, &scale);
  x0 = calloc(nx, sizeof(double));
  body = calloc(10 * lay->nbody + 1, sizeof(double));
  if (!R || !x0 || !body) {
    status =
        rps3_ident_fail(err, errsz, RPS3_ENOMEM, "consistent: out of memory");
    goto out;
  }
  c.p = p;
  c.nb = lay->nbody;
  c.nx = nx;
  c.nf = p + 10 * lay->nbody;
  c.lay = lay;
  c.R = R;
  c.owner = owner;
  c.slot = slot;
  c.sreg = sqrt(o->reg);
  c.plain = 0;
  c.ncurv = 0;
  c.work = malloc(2 * p * sizeof(double));
  c.ew = gsl_eigen_symmv_alloc(4);
  c.E = gsl_matrix_alloc(4, 4);
  c.Q = gsl_matrix_alloc(4, 4);
  c.lam = gsl_vector_alloc(4);
  if (!c.work || !c.ew || !c.E || !c.Q || !c.lam) {
    status =
        rps3_ident_fail(err, errsz, RPS3_ENOMEM, "consistent: out of memory");
    goto out;
  }
  status = start_point(&c, x0);
  if (status == RPS3_OK) {
    /* from the interior in the log-Cholesky variables, where Gauss-Newton
       is at its best, then on in the plain ones, which reach the boundary
       of the cone at finite values, with the curvature rows, to the
       optimality test */
    size_t budget = (size_t)o->max_iter;
    status = solve(&c, x0, o, budget < LOG_ITER ? budget : LOG_ITER,
                   &fit->niter, &gst, NULL, NULL, NULL);
    if (status == RPS3_OK) to_plain(&c, x0);
    while (status == RPS3_OK) {
      descent d;
      status = solve(&c, x0, o, budget - (size_t)fit->niter, &fit->niter,
                     &gst, fit->theta, body, &fit->gap);
      if (status != RPS3_OK || gst == GSL_SUCCESS || gst == GSL_EMAXITER ||
          fit->niter >= o->max_iter)
        break;
      /* stopped short of optimality: out of the stationary point along
         the best descent step of the convex problem, and on (an
         iteration of the budget, so that this ends) */
      optimality(&c, fit->theta, body, o->reg, &d);
      if (!escape(&c, x0, &d, body)) break;
      fit->niter++;
    }
  }
  if (status != RPS3_OK) {
    status = rps3_ident_fail(err, errsz, status,
                             status == RPS3_ENOMEM
                                 ? "consistent: out of memory"
                                 : "consistent: no consistent start");
    goto out;
  }
  status = check_fit(&c, o, scale, body, gst, fit, err, errsz);
out:
  free(c.work);
  if (c.ew) gsl_eigen_symmv_free(c.ew);
  gsl_matrix_free(c.E);
  gsl_matrix_free(c.Q);
  gsl_vector_free(c.lam);
  free(R);
  free(x0);
  free(body);
  free(owner);
  free(slot);
  return status;
}
