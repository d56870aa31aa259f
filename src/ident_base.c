/*
 * ident_base.c - the base parameters of a stacked regressor: which
 * columns are independent, and how the others regroup into them.
 *
 * Y (n x p) has the column geometry of its R factor (Y^T Y = R^T R), so
 * the rows are first reduced to p by a QR when n > p.  The columns, scaled
 * to unit norm, are taken in their order: a column is kept when its part
 * orthogonal to the kept ones (Gram-Schmidt, twice) is above tol, so that
 * a dependent parameter regroups into earlier ones; a column whose norm is
 * at most tol times the largest acts on nothing.  The rank is checked
 * against the singular values of the scaled R (below tol times the
 * largest is zero): a tolerance in no gap of the spectrum is refused.  The
 * grouping coefficients solve Y_ind beta = Y_dep in least squares; K =
 * [1 beta] in the columns' order gives base = K pi, Y pi = Y_ind base.
 *
 * Once per data set: it allocates its GSL workspace and frees it.
 */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_blas.h>
#include <gsl/gsl_linalg.h>

#include "ident_int.h"
#include "internal.h"

/* the columns' geometry: R of Y (p x p) when n > p, else Y itself, into
   A (m x p); m its rows */
static gsl_matrix *geometry(const double *Y, size_t n, size_t p) {
  gsl_matrix *A = gsl_matrix_alloc(n, p);
  gsl_matrix *R;
  gsl_vector *tau;
  size_t i, j;
  if (A == NULL) return NULL;
  memcpy(A->data, Y, n * p * sizeof(double));
  if (n <= p) return A;
  tau = gsl_vector_alloc(p);
  R = gsl_matrix_calloc(p, p);
  if (tau == NULL || R == NULL) {
    gsl_vector_free(tau);
    gsl_matrix_free(R);
    gsl_matrix_free(A);
    return NULL;
  }
  gsl_linalg_QR_decomp(A, tau);
  for (i = 0; i < p; i++)
    for (j = i; j < p; j++) gsl_matrix_set(R, i, j, gsl_matrix_get(A, i, j));
  gsl_vector_free(tau);
  gsl_matrix_free(A);
  return R;
}

/* the numerical rank of the unit-norm columns of A (zero columns
   included as zeros): singular values above tol times the largest */
static int svd_rank(const gsl_matrix *As, double tol, int *rank) {
  const size_t m = As->size1, p = As->size2;
  gsl_matrix *U;
  gsl_matrix *V = gsl_matrix_alloc(p, p);
  gsl_vector *s = gsl_vector_alloc(p), *w = gsl_vector_alloc(p);
  size_t k;
  int r = 0;
  /* SV_decomp needs rows >= columns: pad with zero rows */
  U = gsl_matrix_calloc(m > p ? m : p, p);
  if (U == NULL || V == NULL || s == NULL || w == NULL) {
    gsl_matrix_free(U);
    gsl_matrix_free(V);
    gsl_vector_free(s);
    gsl_vector_free(w);
    return RPS3_ENOMEM;
  }
  for (k = 0; k < m; k++) {
    gsl_vector_const_view row = gsl_matrix_const_row(As, k);
    gsl_matrix_set_row(U, k, &row.vector);
  }
  gsl_linalg_SV_decomp(U, V, s, w);
  for (k = 0; k < p; k++)
    if (gsl_vector_get(s, k) > tol * gsl_vector_get(s, 0)) r++;
  *rank = r;
  gsl_matrix_free(U);
  gsl_matrix_free(V);
  gsl_vector_free(s);
  gsl_vector_free(w);
  return RPS3_OK;
}

/* the greedy choice in the columns' order, on the unit-norm columns of
   As (zero: the columns that act on nothing); Q scratch m x p */
static int greedy(const gsl_matrix *As, const int *zero, double tol,
                  gsl_matrix *Q, int *indep) {
  const size_t m = As->size1, p = As->size2;
  size_t j, k, r, pass;
  int nb = 0;
  double *v = malloc(m * sizeof(double));
  if (v == NULL) return -1;
  for (j = 0; j < p; j++) {
    double nv = 0.0;
    if (zero[j]) continue;
    for (r = 0; r < m; r++) v[r] = gsl_matrix_get(As, r, j);
    for (pass = 0; pass < 2; pass++)
      for (k = 0; k < (size_t)nb; k++) {
        double c = 0.0;
        for (r = 0; r < m; r++) c += gsl_matrix_get(Q, r, k) * v[r];
        for (r = 0; r < m; r++) v[r] -= c * gsl_matrix_get(Q, r, k);
      }
    for (r = 0; r < m; r++) nv += v[r] * v[r];
    nv = sqrt(nv);
    if (nv > tol) {
      for (r = 0; r < m; r++) gsl_matrix_set(Q, r, (size_t)nb, v[r] / nv);
      indep[nb++] = (int)j;
    }
  }
  free(v);
  return nb;
}

/* K: 1 at each kept column, the least-squares grouping of the others
   (zero columns 0), from the unscaled geometry A */
static int grouping(const gsl_matrix *A, const int *zero, const int *indep,
                    int nb, double *K) {
  const size_t m = A->size1, p = A->size2;
  gsl_matrix *Ai = gsl_matrix_alloc(m, (size_t)nb);
  gsl_vector *tau = gsl_vector_alloc((size_t)nb);
  gsl_vector *b = gsl_vector_alloc(m), *x = gsl_vector_alloc((size_t)nb),
             *res = gsl_vector_alloc(m);
  size_t j, r;
  int k, kept;
  if (Ai == NULL || tau == NULL || b == NULL || x == NULL || res == NULL) {
    gsl_matrix_free(Ai);
    gsl_vector_free(tau);
    gsl_vector_free(b);
    gsl_vector_free(x);
    gsl_vector_free(res);
    return RPS3_ENOMEM;
  }
  memset(K, 0, (size_t)nb * p * sizeof(double));
  for (k = 0; k < nb; k++) {
    gsl_vector_const_view c = gsl_matrix_const_column(A, (size_t)indep[k]);
    gsl_matrix_set_col(Ai, (size_t)k, &c.vector);
    K[(size_t)k * p + (size_t)indep[k]] = 1.0;
  }
  gsl_linalg_QR_decomp(Ai, tau);
  for (j = 0, k = 0; j < p; j++) {
    kept = k < nb && indep[k] == (int)j;
    if (kept) k++;
    if (kept || zero[j]) continue;
    for (r = 0; r < m; r++) gsl_vector_set(b, r, gsl_matrix_get(A, r, j));
    gsl_linalg_QR_lssolve(Ai, tau, b, x, res);
    for (r = 0; r < (size_t)nb; r++) K[r * p + j] = gsl_vector_get(x, r);
  }
  gsl_matrix_free(Ai);
  gsl_vector_free(tau);
  gsl_vector_free(b);
  gsl_vector_free(x);
  gsl_vector_free(res);
  return RPS3_OK;
}

/* the most columns: a regressor's parameters, not its rows */
#define MAXP 4096

int rps3_ident_base(const double *Y, size_t n, size_t p, double tol,
                    int *indep, double *K, int *nbase, rps3_check *chk) {
  char *err = chk != NULL ? chk->msg : NULL;
  const size_t errsz = chk != NULL ? sizeof chk->msg : 0;
  gsl_matrix *A = NULL, *As = NULL, *Q = NULL;
  int *zero = NULL, rank = 0, nb, st = RPS3_OK;
  double cmax = 0.0;
  size_t i, j;
  rps3_check_clear(chk);
  if (nbase != NULL) *nbase = 0;
  if (Y == NULL || indep == NULL || K == NULL || nbase == NULL)
    return rps3_ident_fail(err, errsz, RPS3_EINVAL,
                           "Y, independent, K and nbase must not be NULL");
  if (n == 0 || p == 0 || p > MAXP || n > SIZE_MAX / sizeof(double) / p)
    return rps3_ident_fail(err, errsz, RPS3_EINVAL,
                           "n = %lu rows and p = %lu columns: need n >= 1 and "
                           "1 <= p <= %d",
                           (unsigned long)n, (unsigned long)p, MAXP);
  if (!(tol > 0.0 && tol < 1.0))
    return rps3_ident_fail(err, errsz, RPS3_EINVAL,
                           "tol = %g: must be in (0, 1)", tol);
  for (i = 0; i < n * p; i++)
    if (!isfinite(Y[i]))
      return rps3_ident_fail(err, errsz, RPS3_EINVAL,
                             "Y[%lu][%lu] = %g is not finite",
                             (unsigned long)(i / p), (unsigned long)(i % p),
                             Y[i]);
  A = geometry(Y, n, p);
  zero = calloc(p, sizeof(int));
  if (A == NULL || zero == NULL) {
    st = RPS3_ENOMEM;
    goto done;
  }
  As = gsl_matrix_alloc(A->size1, p);
  Q = gsl_matrix_alloc(A->size1, p);
  if (As == NULL || Q == NULL) {
    st = RPS3_ENOMEM;
    goto done;
  }
  /* unit-norm columns; those at most tol of the largest act on nothing */
  for (j = 0; j < p; j++) {
    gsl_vector_const_view c = gsl_matrix_const_column(A, j);
    double s = gsl_blas_dnrm2(&c.vector);
    if (s > cmax) cmax = s;
  }
  for (j = 0; j < p; j++) {
    gsl_vector_const_view c = gsl_matrix_const_column(A, j);
    double s = gsl_blas_dnrm2(&c.vector);
    zero[j] = !(s > tol * cmax);
    for (i = 0; i < A->size1; i++)
      gsl_matrix_set(As, i, j, zero[j] ? 0.0 : gsl_matrix_get(A, i, j) / s);
  }
  if (!(cmax > 0.0)) {
    st = rps3_ident_fail(err, errsz, RPS3_ESING,
                         "every column of Y is zero: the data excite nothing");
    goto done;
  }
  st = svd_rank(As, tol, &rank);
  if (st != RPS3_OK) goto done;
  nb = greedy(As, zero, tol, Q, indep);
  if (nb < 0) {
    st = RPS3_ENOMEM;
    goto done;
  }
  if (nb != rank) {
    st = rps3_ident_fail(err, errsz, RPS3_ESING,
                         "the greedy selection keeps %d columns where the "
                         "singular values give rank %d: tol = %g is in no gap "
                         "of the spectrum (data barely exciting?)",
                         nb, rank, tol);
    goto done;
  }
  st = grouping(A, zero, indep, nb, K);
  if (st == RPS3_OK) *nbase = nb;
done:
  if (st == RPS3_ENOMEM)
    rps3_ident_fail(err, errsz, RPS3_ENOMEM, "out of memory");
  gsl_matrix_free(A);
  gsl_matrix_free(As);
  gsl_matrix_free(Q);
  free(zero);
  return st;
}
