/* test_linalg.c - the small pivoted LU of the per-point path against GSL's
   gsl_linalg_LU_decomp / _solve / _invert. */
#include <gsl/gsl_linalg.h>

#include "linalg.h"
#include "testutil.h"

static void compare_with_gsl(int n, uint64_t *seed) {
  double A[36], LU[36], x[6], b[6], inv1 = 0.0, anorm = 0.0, cond;
  int perm[6], i, j, sgn;
  gsl_matrix *G = gsl_matrix_alloc((size_t)n, (size_t)n);
  gsl_matrix *Ginv = gsl_matrix_alloc((size_t)n, (size_t)n);
  gsl_permutation *p = gsl_permutation_alloc((size_t)n);
  gsl_vector *gb = gsl_vector_alloc((size_t)n), *gx = gsl_vector_alloc((size_t)n);
  for (i = 0; i < n * n; i++) A[i] = LU[i] = rnd_uniform(seed, -2.0, 2.0);
  for (i = 0; i < n; i++) x[i] = b[i] = rnd_uniform(seed, -5.0, 5.0);
  for (i = 0; i < n; i++)
    for (j = 0; j < n; j++) gsl_matrix_set(G, (size_t)i, (size_t)j, A[i * n + j]);
  for (i = 0; i < n; i++) gsl_vector_set(gb, (size_t)i, b[i]);
  assert_int_equal(rps3_lu_factor(n, LU, perm), 0);
  rps3_lu_solve(n, LU, perm, x);
  assert_int_equal(gsl_linalg_LU_decomp(G, p, &sgn), 0);
  assert_int_equal(gsl_linalg_LU_solve(G, p, gb, gx), 0);
  assert_int_equal(gsl_linalg_LU_invert(G, p, Ginv), 0);
  for (i = 0; i < n; i++)
    CHECK_REL(x[i], gsl_vector_get(gx, (size_t)i), 1e-11, 1.0, "x%d (n=%d)", i, n);
  /* exact 1-norm condition number from GSL's inverse */
  for (j = 0; j < n; j++) {
    double s = 0.0, t = 0.0;
    for (i = 0; i < n; i++) {
      s += fabs(gsl_matrix_get(Ginv, (size_t)i, (size_t)j));
      t += fabs(A[i * n + j]);
    }
    if (s > inv1) inv1 = s;
    if (t > anorm) anorm = t;
  }
  /* the multi-column 3x3 solve of the lambda system: the same solutions */
  if (n == 3) {
    double X[3 * 4];
    int c;
    for (i = 0; i < 3; i++)
      for (c = 0; c < 4; c++) X[4 * i + c] = (c == 0) ? b[i] : A[3 * i + c - 1];
    rps3_lu3_solve_multi(LU, perm, X, 4, 4);
    for (i = 0; i < 3; i++) {
      CHECK_REL(X[4 * i], gsl_vector_get(gx, (size_t)i), 1e-11, 1.0, "multi x%d", i);
      for (c = 1; c < 4; c++) /* A^-1 A = I, column by column */
        CHECK_REL(X[4 * i + c], i == c - 1 ? 1.0 : 0.0, 1e-11, 1.0, "multi I");
    }
  }
  /* the 6 x 6 inverse: GSL's, and rps3_lu_solve's columns but for the
     rounding of a reciprocal */
  if (n == 6) {
    double X[36], col[6];
    int c;
    rps3_lu6_inverse(LU, perm, X);
    for (c = 0; c < 6; c++) {
      for (i = 0; i < 6; i++) col[i] = i == c ? 1.0 : 0.0;
      rps3_lu_solve(6, LU, perm, col);
      for (i = 0; i < 6; i++) {
        CHECK_REL(X[6 * i + c], col[i], TOL_EXACT, 0.0, "column solve");
        CHECK_REL(X[6 * i + c], gsl_matrix_get(Ginv, (size_t)i, (size_t)c),
                  1e-11, 1.0, "inverse (%d, %d)", i, c);
      }
    }
  }
  cond = rps3_lu_cond1(n, A, LU, perm);
  CHECK_REL(cond, anorm * inv1, 1e-10, 0.0, "cond (n=%d)", n);
  gsl_matrix_free(G);
  gsl_matrix_free(Ginv);
  gsl_permutation_free(p);
  gsl_vector_free(gb);
  gsl_vector_free(gx);
}

static void matches_gsl(void **state) {
  uint64_t seed = 577;
  int k;
  (void)state;
  for (k = 0; k < 200; k++) {
    compare_with_gsl(3, &seed);
    compare_with_gsl(6, &seed);
  }
}

static void singular_is_reported(void **state) {
  double A[9] = {1.5, 2.25, -0.75, 3.0, 4.5, -1.5, 0.3, 0.1, 0.7}; /* row2 = 2 row1 */
  double B[9] = {(double)NAN, 1, 0, 0, 1, 0, 0, 0, 1};
  int perm[3];
  (void)state;
  assert_int_equal(rps3_lu_factor(3, A, perm), -1);
  assert_int_equal(rps3_lu_factor(3, B, perm), -1);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(matches_gsl),
      cmocka_unit_test(singular_is_reported),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
