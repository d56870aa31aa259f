/*
 * linalg.c - small dense solves for the per-point path.
 *
 * The systems here are 3x3 (the lambda system) and 6x6 (Newton-Euler).
 * Gaussian elimination with partial pivoting on the stack is several times
 * faster than going through gsl_matrix views at these sizes and needs no
 * workspace; tests/test_linalg.c checks it against gsl_linalg_LU_solve.
 */
#include "linalg.h"

#include <math.h>
#include <string.h>

/*
 * n = 3, the lambda system, is factored once and solved several times per
 * point: it has unrolled versions of the general loops below, with the same
 * operations in the same order, so that their results are bitwise those of
 * the general code (tests/test_linalg.c checks both against GSL).
 */
static void swap3(double *a, double *b) {
  int j;
  for (j = 0; j < 3; j++) {
    double t = a[j];
    a[j] = b[j];
    b[j] = t;
  }
}

static int lu_factor3(double *A, int *perm) {
  double big, v, f;
  int p;
  /* column 0: pivot, swap, eliminate rows 1 and 2 */
  p = 0;
  big = fabs(A[0]);
  v = fabs(A[3]);
  if (v > big) {
    big = v;
    p = 1;
  }
  v = fabs(A[6]);
  if (v > big) {
    big = v;
    p = 2;
  }
  perm[0] = p;
  if (!(big > 0.0)) return -1;
  if (p != 0) swap3(A, A + 3 * p);
  f = A[3] / A[0];
  A[3] = f;
  A[4] -= f * A[1];
  A[5] -= f * A[2];
  f = A[6] / A[0];
  A[6] = f;
  A[7] -= f * A[1];
  A[8] -= f * A[2];
  /* column 1 */
  p = 1;
  big = fabs(A[4]);
  v = fabs(A[7]);
  if (v > big) {
    big = v;
    p = 2;
  }
  perm[1] = p;
  if (!(big > 0.0)) return -1;
  if (p != 1) swap3(A + 3, A + 6);
  f = A[7] / A[4];
  A[7] = f;
  A[8] -= f * A[5];
  /* column 2 */
  perm[2] = 2;
  if (!(fabs(A[8]) > 0.0)) return -1;
  return 0;
}

static void lu_solve3(const double *LU, const int *perm, double *x) {
  double x0, x1, x2, t;
  int k;
  for (k = 0; k < 3; k++)
    if (perm[k] != k) {
      t = x[k];
      x[k] = x[perm[k]];
      x[perm[k]] = t;
    }
  x0 = x[0];
  x1 = x[1] - LU[3] * x0;
  x2 = x[2] - LU[6] * x0;
  x2 -= LU[7] * x1;
  x2 /= LU[8];
  x1 -= LU[5] * x2;
  x1 /= LU[4];
  x0 -= LU[1] * x1;
  x0 -= LU[2] * x2;
  x0 /= LU[0];
  x[0] = x0;
  x[1] = x1;
  x[2] = x2;
}

void rps3_lu3_solve_multi(const double *LU, const int *perm, double *X, int ldx,
                          int nrhs) {
  double *x0 = X, *x1 = X + ldx, *x2 = X + 2 * ldx;
  /* one division per pivot, then products: the columns share them */
  const double r0 = 1.0 / LU[0], r4 = 1.0 / LU[4], r8 = 1.0 / LU[8];
  int k, c;
  /* the steps of lu_solve3 on every column, with the pivots' reciprocals:
     within an ulp of it, and checked against GSL in tests/test_linalg.c */
  for (k = 0; k < 3; k++)
    if (perm[k] != k)
      for (c = 0; c < nrhs; c++) {
        double t = X[k * ldx + c];
        X[k * ldx + c] = X[perm[k] * ldx + c];
        X[perm[k] * ldx + c] = t;
      }
  for (c = 0; c < nrhs; c++) {
    double a = x0[c], b, e;
    b = x1[c] - LU[3] * a;
    e = x2[c] - LU[6] * a;
    e -= LU[7] * b;
    e *= r8;
    b -= LU[5] * e;
    b *= r4;
    a -= LU[1] * b;
    a -= LU[2] * e;
    a *= r0;
    x0[c] = a;
    x1[c] = b;
    x2[c] = e;
  }
}

static inline int lu_factor_n(int n, double *A, int *perm) {
  int k, i, j;
  for (k = 0; k < n; k++) {
    /* partial pivoting: the largest magnitude in column k */
    int p = k;
    double big = fabs(A[k * n + k]);
    for (i = k + 1; i < n; i++) {
      double v = fabs(A[i * n + k]);
      if (v > big) {
        big = v;
        p = i;
      }
    }
    perm[k] = p;
    if (!(big > 0.0)) return -1; /* zero (or NaN) pivot: singular */
    if (p != k)
      for (j = 0; j < n; j++) {
        double t = A[k * n + j];
        A[k * n + j] = A[p * n + j];
        A[p * n + j] = t;
      }
    for (i = k + 1; i < n; i++) {
      double f = A[i * n + k] / A[k * n + k];
      A[i * n + k] = f;
      for (j = k + 1; j < n; j++) A[i * n + j] -= f * A[k * n + j];
    }
  }
  return 0;
}

int rps3_lu_factor(int n, double *A, int *perm) {
  if (n == 3) return lu_factor3(A, perm);
  /* n = 6 (Newton-Euler, the design's wrench system) with the size known
     to the compiler: the same operations, unrolled */
  if (n == 6) return lu_factor_n(6, A, perm);
  return lu_factor_n(n, A, perm);
}

void rps3_lu_solve(int n, const double *LU, const int *perm, double *x) {
  int k, i;
  if (n == 3) {
    lu_solve3(LU, perm, x);
    return;
  }
  /* apply the row swaps, then forward and back substitution */
  for (k = 0; k < n; k++)
    if (perm[k] != k) {
      double t = x[k];
      x[k] = x[perm[k]];
      x[perm[k]] = t;
    }
  for (i = 1; i < n; i++)
    for (k = 0; k < i; k++) x[i] -= LU[i * n + k] * x[k];
  for (i = n - 1; i >= 0; i--) {
    for (k = i + 1; k < n; k++) x[i] -= LU[i * n + k] * x[k];
    x[i] /= LU[i * n + i];
  }
}

double rps3_lu3_inverse_cond1(const double *A, const double *LU,
                              const int *perm, double X[9]) {
  static const double I3[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  double anorm = 0.0, inorm = 0.0;
  int j;
  for (j = 0; j < 3; j++) {
    double s = fabs(A[j]) + fabs(A[3 + j]) + fabs(A[6 + j]);
    if (s > anorm) anorm = s;
  }
  /* the three columns of A^-1 in one multi-column solve */
  memcpy(X, I3, sizeof(I3));
  rps3_lu3_solve_multi(LU, perm, X, 3, 3);
  for (j = 0; j < 3; j++) {
    double s = fabs(X[j]) + fabs(X[3 + j]) + fabs(X[6 + j]);
    if (s > inorm) inorm = s;
  }
  return anorm * inorm;
}

double rps3_lu_cond1(int n, const double *A, const double *LU,
                     const int *perm) {
  /* exact 1-norm condition: ||A||_1 ||A^-1||_1, A^-1 column by column */
  double anorm = 0.0, inorm = 0.0, col[RPS3_LU_NMAX];
  int i, j;
  if (n == 3) {
    double X[9];
    return rps3_lu3_inverse_cond1(A, LU, perm, X);
  }
  for (j = 0; j < n; j++) {
    double s = 0.0;
    for (i = 0; i < n; i++) s += fabs(A[i * n + j]);
    if (s > anorm) anorm = s;
  }
  for (j = 0; j < n; j++) {
    double s = 0.0;
    for (i = 0; i < n; i++) col[i] = (i == j) ? 1.0 : 0.0;
    rps3_lu_solve(n, LU, perm, col);
    for (i = 0; i < n; i++) s += fabs(col[i]);
    if (s > inorm) inorm = s;
  }
  return anorm * inorm;
}

void rps3_lu6_inverse(const double *restrict LU, const int *restrict perm,
                      double *restrict X) {
  /* the columns of A^-1 as rps3_lu_solve computes each, all six at once,
     row by row so that a row's six entries go together; the division by
     a pivot as a product by its reciprocal (within an ulp) */
  int i, k, j;
  memset(X, 0, 36 * sizeof(double));
  for (i = 0; i < 6; i++) X[7 * i] = 1.0;
  for (k = 0; k < 6; k++)
    if (perm[k] != k)
      for (j = 0; j < 6; j++) {
        double t = X[6 * k + j];
        X[6 * k + j] = X[6 * perm[k] + j];
        X[6 * perm[k] + j] = t;
      }
  for (i = 1; i < 6; i++)
    for (k = 0; k < i; k++) {
      double f = LU[6 * i + k];
      for (j = 0; j < 6; j++) X[6 * i + j] -= f * X[6 * k + j];
    }
  for (i = 5; i >= 0; i--) {
    for (k = i + 1; k < 6; k++) {
      double f = LU[6 * i + k];
      for (j = 0; j < 6; j++) X[6 * i + j] -= f * X[6 * k + j];
    }
    {
      double p = 1.0 / LU[7 * i];
      for (j = 0; j < 6; j++) X[6 * i + j] *= p;
    }
  }
}
