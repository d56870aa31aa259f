/*
 * ident_cfit.c - the consistent fit's problem: each body's pseudo-inertia
 * by its Cholesky factor (log-Cholesky: the logarithms of the diagonal,
 * a >= 0 column exp of its variable; plain: the diagonal itself, a >= 0
 * column s^2), the residual and its analytic Jacobian with the plain
 * variables' curvature rows, the KKT optimality measure and the step out
 * of a false stationary point.  The driver is src/ident_consistent.c.
 */
#include <float.h>
#include <math.h>
#include <string.h>

#include <gsl/gsl_eigen.h>
#include <gsl/gsl_errno.h>

#include "ident_cfit.h"
#include "ident_int.h"
#include "internal.h"

/* the ten entries of a body's upper-triangular 4 x 4 factor U, in the
   order of its variables; a diagonal one is exp(variable) in the
   log-Cholesky stage, the variable itself in the plain one (diag_of) */
const int rps3_cfit_UA[10] = {0, 0, 0, 0, 1, 1, 1, 2, 2, 3};
const int rps3_cfit_UB[10] = {0, 1, 2, 3, 1, 2, 3, 2, 3, 3};

/* the standard parameters (m, mcx, mcy, mcz, Ixx, Ixy, Ixz, Iyy, Iyz,
   Izz) of a pseudo-inertia J = [[Sigma, h], [h^T, m]], I = tr(Sigma) 1 -
   Sigma; linear, so also of a derivative of J */
void rps3_cfit_std_of(const double J[4][4], double s[10]) {
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
void rps3_cfit_pseudo_of(const double s[10], double J[4][4]) {
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

int rps3_cfit_is_nonneg(const cfit *c, size_t j) {
  return c->lay->kind && c->lay->kind[j] == RPS3_IDENT_NONNEG;
}

static void factor_of(const cfit *c, const double *x, double U[4][4]) {
  int v;
  memset(U, 0, 16 * sizeof(double));
  for (v = 0; v < 10; v++)
    U[rps3_cfit_UA[v]][rps3_cfit_UB[v]] =
        rps3_cfit_UA[v] == rps3_cfit_UB[v] ? diag_of(c, x[v]) : x[v];
}

/* pi of the variables x */
void rps3_cfit_pi_of(const cfit *c, const double *x, double *pi, double *body) {
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
    rps3_cfit_std_of(M4C(J), s);
    if (body) memcpy(body + 10 * b, s, sizeof(s));
    for (k = 0; k < 10; k++)
      if (c->lay->col[b][k] >= 0) pi[c->lay->col[b][k]] = s[k];
  }
  for (j = 0; j < c->p; j++) {
    double v;
    if (c->owner[j] >= 0) continue;
    v = x[c->slot[j]];
    pi[j] = rps3_cfit_is_nonneg(c, j) ? nonneg_of(c, v) : v;
  }
}

int rps3_cfit_f(const gsl_vector *xv, void *params, gsl_vector *f) {
  const cfit *c = params;
  double *pp = c->work + 2 * c->p; /* scratch: no allocation an iteration */
  size_t i, j, b;
  int v;
  rps3_cfit_pi_of(c, xv->data, pp, NULL);
  if (!rps3_all_finite(pp, (int)c->p)) {
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
      gsl_vector_set(
          f, c->p + 10 * b + (size_t)v,
          c->sreg * (rps3_cfit_UA[v] == rps3_cfit_UB[v] ? diag_of(c, xb) : xb));
    }
  /* the curvature rows: 0 here, their Jacobian in cfit_df */
  for (i = c->p + 10 * c->nb; i < c->nf; i++) gsl_vector_set(f, i, 0.0);
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
  rps3_cfit_pi_of(c, x, pi, NULL);
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
        gsl_matrix_set(
            Jm, base + 16 * b + 4 * (size_t)m + (size_t)rps3_cfit_UB[v],
            10 * b + (size_t)v, w * gsl_matrix_get(c->Q, rps3_cfit_UA[v], m));
    }
  }
  for (j = 0; j < p; j++)
    if (c->owner[j] < 0 && rps3_cfit_is_nonneg(c, j)) {
      if (gr[j] > 0.0)
        gsl_matrix_set(Jm, row, (size_t)c->slot[j], sqrt(2.0 * gr[j]));
      row++;
    }
}

int rps3_cfit_df(const gsl_vector *xv, void *params, gsl_matrix *Jm) {
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
          e = rps3_cfit_UA[v] == rps3_cfit_UB[v]
                  ? ddiag(c, xv->data[10 * b + (size_t)v])
                  : 1.0;
      size_t col = 10 * b + (size_t)v;
      for (k = 0; k < 4; k++)
        for (q = 0; q < 4; q++)
          dJ[k][q] = e * ((k == rps3_cfit_UA[v] ? U[q][rps3_cfit_UB[v]] : 0.0) +
                          (q == rps3_cfit_UA[v] ? U[k][rps3_cfit_UB[v]] : 0.0));
      rps3_cfit_std_of(M4C(dJ), ds);
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
    dp = rps3_cfit_is_nonneg(c, j) ? dnonneg(c, gsl_vector_get(xv, col)) : 1.0;
    for (i = 0; i <= j; i++)
      gsl_matrix_set(Jm, i, col, c->R[i * (c->p + 1) + j] * dp);
  }
  if (c->plain) curvature_rows(c, xv->data, Jm);
  return GSL_SUCCESS;
}

/* a dual violation at the rounding of the gradient: each g_j is a sum of
   products of R's entries with the residual's terms, formed to within a
   few eps (p <= 82 terms a sum) of the sum of their magnitudes; a
   violation below OPT_ROUND times that magnitude along its step is not a
   direction to descend.  Along a direction the data see only at rounding
   level (columns that cancel), h is rounding too and e^2 / (4 h), the
   step e / (2 h), would be anything up to infinite: a measure that never
   meets the test at reg 0, an escape step of 1e13 */
#define OPT_ROUND (64.0 * DBL_EPSILON)

double rps3_cfit_optimality(const cfit *c, const double *theta,
                            const double *body, double reg, descent *best) {
  const size_t p = c->p, P1 = c->p + 1;
  const double *R = c->R;
  /* scratch: g, the step d, and ga, the magnitude of g's terms */
  double *g = c->work, *d = c->work + p, *ga = c->work + 2 * p, est = 0.0;
  gsl_matrix *E = c->E, *Q = c->Q;
  gsl_vector *lam = c->lam;
  size_t i, j, b;
  if (best) {
    best->dec = 0.0;
    best->b = best->j = -1;
  }
  for (j = 0; j < p; j++) g[j] = ga[j] = 0.0;
  for (i = 0; i < p; i++) {
    double s = -R[i * P1 + p], sa = fabs(R[i * P1 + p]);
    for (j = i; j < p; j++) {
      s += R[i * P1 + j] * theta[j];
      sa += fabs(R[i * P1 + j] * theta[j]);
    }
    for (j = i; j < p; j++) {
      g[j] += 2.0 * R[i * P1 + j] * s;
      ga[j] += 2.0 * fabs(R[i * P1 + j]) * sa;
    }
  }
  for (b = 0; b < c->nb; b++) {
    double gs[10], G[4][4], J[4][4], U[4][4], ds[10];
    double e, h = 0.0, cg = 0.0, dec, gn = 0.0, er;
    int k, q;
    for (k = 0; k < 10; k++)
      gs[k] = c->lay->col[b][k] >= 0 ? g[c->lay->col[b][k]] : 0.0;
    grad_of(gs, G);
    rps3_cfit_pseudo_of(body + 10 * b, J);
    for (k = 0; k < 4; k++) {
      G[k][k] += reg;
      for (q = 0; q < 4; q++) {
        cg += G[k][q] * J[k][q];
        gn += G[k][q] * G[k][q];
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
    rps3_cfit_std_of(M4C(U), ds);
    for (j = 0; j < p; j++) d[j] = 0.0;
    /* the rounding of e: of g along the step, and of the eigensolver */
    er = sqrt(gn);
    for (k = 0; k < 10; k++)
      if (c->lay->col[b][k] >= 0) {
        d[c->lay->col[b][k]] = ds[k];
        er += fabs(ds[k]) * ga[c->lay->col[b][k]];
      }
    e -= OPT_ROUND * er;
    if (!(e > 0.0)) continue;
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
    e = (rps3_cfit_is_nonneg(c, j) ? -g[j] : fabs(g[j])) - OPT_ROUND * ga[j];
    if (!(e > 0.0)) continue;
    for (i = 0; i <= j; i++) h += R[i * P1 + j] * R[i * P1 + j];
    dec = h > 0.0 ? e * e / (4.0 * h) : HUGE_VAL;
    est += dec;
    if (best && h > 0.0 && dec > best->dec) {
      best->dec = dec;
      best->b = -1;
      best->j = (long)j;
      best->t = (g[j] > 0.0 ? -e : e) / (2.0 * h);
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

void rps3_cfit_plain_of(const cfit *c, const double *body, const double *pi,
                        double *x) {
  size_t b, j;
  for (b = 0; b < c->nb; b++) {
    double J[4][4], U[4][4];
    int k;
    rps3_cfit_pseudo_of(body + 10 * b, J);
    psd_factor(M4C(J), U);
    for (k = 0; k < 10; k++)
      x[10 * b + (size_t)k] = U[rps3_cfit_UA[k]][rps3_cfit_UB[k]];
  }
  for (j = 0; j < c->p; j++)
    if (c->owner[j] < 0)
      x[c->slot[j]] =
          rps3_cfit_is_nonneg(c, j) ? sqrt(fmax(pi[j], 0.0)) : pi[j];
}

/*
 * The step out of a stationary point of the plain variables that is not
 * the optimum: U_ii = 0 (or s_j = 0) with the gradient asking for more
 * (a negative eigenvalue of G_b, g_j < 0), where the gradient in U is 0
 * and no trust-region step sees the way.  The step is rps3_cfit_optimality()'s
 * best, taken in pi: J_b + t u u^T refactored, or pi_j + t.  0 when
 * there is none.
 */
int rps3_cfit_escape(const cfit *c, double *x, const descent *d,
                     const double *body) {
  if (d->b >= 0) {
    double J[4][4], U[4][4];
    int k, q;
    rps3_cfit_pseudo_of(body + 10 * d->b, J);
    for (k = 0; k < 4; k++)
      for (q = 0; q < 4; q++) J[k][q] += d->t * d->u[k] * d->u[q];
    psd_factor(M4C(J), U);
    for (k = 0; k < 10; k++)
      x[10 * d->b + k] = U[rps3_cfit_UA[k]][rps3_cfit_UB[k]];
    return 1;
  }
  if (d->j >= 0) {
    size_t sl = (size_t)c->slot[d->j];
    if (rps3_cfit_is_nonneg(c, (size_t)d->j))
      x[sl] = sqrt(fmax(x[sl] * x[sl] + d->t, 0.0));
    else
      x[sl] += d->t;
    return 1;
  }
  return 0;
}
