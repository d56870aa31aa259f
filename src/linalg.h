/* linalg.h - small dense LU with partial pivoting (n <= RPS3_LU_NMAX). */
#ifndef RPS3_LINALG_H
#define RPS3_LINALG_H

#define RPS3_LU_NMAX 6

/* Factor the row-major n x n matrix A in place (L unit lower, U upper) with
   row swaps perm.  Returns 0, or -1 on a zero or non-finite pivot. */
int rps3_lu_factor(int n, double *A, int *perm);

/* Solve with a factorization from rps3_lu_factor; x holds b on entry. */
void rps3_lu_solve(int n, const double *LU, const int *perm, double *x);

/* Solve the 3 x 3 system of rps3_lu_factor for nrhs right-hand sides at
   once: column c of the 3 x nrhs row-major X (row stride ldx) holds b_c on
   entry and x_c on return.  As rps3_lu_solve column by column, but dividing
   once per pivot (products by the reciprocals): within an ulp of it. */
void rps3_lu3_solve_multi(const double *LU, const int *perm, double *X, int ldx,
                          int nrhs);

/* The inverse of the 3 x 3 A (row-major into X) from its factorization,
   and its 1-norm condition number, rps3_lu_cond1's for n = 3 bitwise. */
double rps3_lu3_inverse_cond1(const double *A, const double *LU,
                              const int *perm, double X[9]);

/* 1-norm condition number of A, given A and its factorization. */
double rps3_lu_cond1(int n, const double *A, const double *LU, const int *perm);

/* The inverse of the 6 x 6 A (row-major into X) from its factorization by
   rps3_lu_factor: column j is rps3_lu_solve's for e_j to an ulp or two
   (a product by the pivot's reciprocal where it divides). */
void rps3_lu6_inverse(const double *restrict LU, const int *restrict perm,
                      double *restrict X);

#endif
