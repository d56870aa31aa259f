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

int rps3_lu_factor(int n, double *A, int *perm) {
  int k, i, j;
  for (k = 0; k < n; k++) {
    /* partial pivoting: the largest magnitude in column k */
    int p = k;
    double big = fabs(A[k * n + k]);
    for (i = k + 1; i < n; i++) {
      double v = fabs(A[i * n + k]);
      if (v > big) { big = v; p = i; }
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

void rps3_lu_solve(int n, const double *LU, const int *perm, double *x) {
  int k, i;
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

double rps3_lu_cond1(int n, const double *A, const double *LU,
                     const int *perm) {
  /* exact 1-norm condition: ||A||_1 ||A^-1||_1, A^-1 column by column */
  double anorm = 0.0, inorm = 0.0, col[RPS3_LU_NMAX];
  int i, j;
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
