/*
 * ident_fit.c - estimators on a stacked regressor: the checks of their
 * data, and weighted least squares with its covariance and intervals
 * (the physically consistent fit is in ident_consistent.c).
 *
 * They run once per data set, not per point: each call allocates its GSL
 * workspaces and frees them before returning.  Every argument is checked
 * before GSL sees it, so GSL's error handler is never reached.
 */
#include <stdarg.h>
#include <stdint.h>
#include <stdlib.h>

#include <gsl/gsl_cdf.h>
#include <gsl/gsl_eigen.h>
#include <gsl/gsl_linalg.h>
#include <gsl/gsl_multifit.h>
#include <gsl/gsl_multifit_nlinear.h>

#include "ident_int.h"
#include "internal.h"

void rps3_ident_opts_default(rps3_ident_opts *o) {
  if (o == NULL) return;
  o->rank_tol = 1e-10;
  o->level = 0.95;
  o->reg = 1e-9;
  o->xtol = 1e-12;
  o->gtol = 1e-12;
  o->ftol = 0.0;
  o->max_iter = 2000;
  o->eig_tol = 1e-10;
  o->opt_tol = 1e-6;
}

/* a message into err (may be NULL), and the status */
int rps3_ident_fail(char *err, size_t errsz, int status, const char *fmt, ...) {
  if (err != NULL && errsz > 0) {
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err, errsz, fmt, ap);
    va_end(ap);
  }
  rps3_error_hook(status);
  return status;
}

/* the name of column j, for messages */
static const char *col_name(const rps3_ident_data *dt, size_t j, char *buf,
                            size_t sz) {
  if (dt->names != NULL && dt->names[j] != NULL) return dt->names[j];
  snprintf(buf, sz, "column %lu", (unsigned long)j);
  return buf;
}

static int actuator_of(const rps3_ident_data *dt, size_t r) {
  return dt->actuator ? dt->actuator[r] : (int)(r % 3);
}

/* the checks of every estimator's data; need_act: each actuator must have
   rows (the two-pass weights) */
int rps3_ident_check_data(const rps3_ident_data *dt, const rps3_ident_opts *o,
                          int need_act, char *err, size_t errsz) {
  size_t r, j, nact[3] = {0, 0, 0};
  if (dt == NULL)
    return rps3_ident_fail(err, errsz, RPS3_EINVAL, "data is NULL");
  if (dt->p == 0 || dt->n <= dt->p)
    return rps3_ident_fail(
        err, errsz, RPS3_EINVAL,
        "data: %lu rows for %lu columns: need more rows than columns",
        (unsigned long)dt->n, (unsigned long)dt->p);
  if (dt->n > SIZE_MAX / sizeof(double) / (dt->p + 1))
    return rps3_ident_fail(err, errsz, RPS3_EINVAL,
                           "data: %lu x %lu is too large", (unsigned long)dt->n,
                           (unsigned long)dt->p);
  if (dt->Y == NULL || dt->F == NULL)
    return rps3_ident_fail(err, errsz, RPS3_EINVAL, "data.%s is NULL",
                           dt->Y == NULL ? "Y" : "F");
  if (o != NULL && (!(o->rank_tol > 0.0 && o->rank_tol < 1.0) ||
                    !(o->level > 0.0 && o->level < 1.0) || !(o->reg >= 0.0) ||
                    !isfinite(o->reg) || !(o->xtol >= 0.0) ||
                    !(o->gtol >= 0.0) || !(o->ftol >= 0.0) || o->max_iter < 1 ||
                    !(o->eig_tol >= 0.0) || !(o->eig_tol < 1.0) ||
                    !(o->opt_tol >= 0.0) || !isfinite(o->opt_tol)))
    return rps3_ident_fail(
        err, errsz, RPS3_EINVAL,
        "opts: rank_tol and level must be in (0, 1), reg, xtol, gtol, "
        "ftol, opt_tol >= 0 and finite, max_iter >= 1, eig_tol in [0, 1)");
  for (r = 0; r < dt->n; r++) {
    int a = actuator_of(dt, r);
    for (j = 0; j < dt->p; j++)
      if (!isfinite(dt->Y[r * dt->p + j]))
        return rps3_ident_fail(
            err, errsz, RPS3_EINVAL, "data.Y[%lu][%lu] = %g is not finite",
            (unsigned long)r, (unsigned long)j, dt->Y[r * dt->p + j]);
    if (!isfinite(dt->F[r]))
      return rps3_ident_fail(err, errsz, RPS3_EINVAL,
                             "data.F[%lu] = %g is not finite", (unsigned long)r,
                             dt->F[r]);
    if (dt->weight != NULL &&
        !(dt->weight[r] > 0.0 && dt->weight[r] <= DBL_MAX))
      return rps3_ident_fail(err, errsz, RPS3_EINVAL,
                             "data.weight[%lu] = %g: must be > 0 and finite",
                             (unsigned long)r, dt->weight[r]);
    if (a < 0 || a > 2)
      return rps3_ident_fail(err, errsz, RPS3_EINVAL,
                             "data.actuator[%lu] = %d: must be 0, 1 or 2",
                             (unsigned long)r, a);
    nact[a]++;
  }
  for (j = 0; need_act && j < 3; j++)
    if (nact[j] == 0)
      return rps3_ident_fail(
          err, errsz, RPS3_EINVAL,
          "data: actuator %lu has no row, so no noise variance",
          (unsigned long)j);
  return RPS3_OK;
}

/* ----------------------------------------------------- weighted LS */

/* scratch of the least-squares fit, allocated once per call */
typedef struct {
  gsl_matrix *A; /* n x p: the weighted, column-scaled regressor */
  gsl_matrix *X; /* n x p: the column-scaled regressor */
  gsl_vector *tau, *w, *y, *c, *D, *S, *sw, *r;
  gsl_matrix *R, *V, *cov;
  gsl_multifit_linear_workspace *ws;
} lsq;

static void lsq_free(lsq *L) {
  gsl_matrix_free(L->A);
  gsl_matrix_free(L->X);
  gsl_vector_free(L->tau);
  gsl_vector_free(L->w);
  gsl_vector_free(L->y);
  gsl_vector_free(L->c);
  gsl_vector_free(L->D);
  gsl_vector_free(L->S);
  gsl_vector_free(L->sw);
  gsl_vector_free(L->r);
  gsl_matrix_free(L->R);
  gsl_matrix_free(L->V);
  gsl_matrix_free(L->cov);
  if (L->ws) gsl_multifit_linear_free(L->ws);
}

static int lsq_alloc(lsq *L, size_t n, size_t p) {
  memset(L, 0, sizeof(*L));
  L->A = gsl_matrix_alloc(n, p);
  L->X = gsl_matrix_alloc(n, p);
  L->tau = gsl_vector_alloc(p);
  L->w = gsl_vector_alloc(n);
  L->y = gsl_vector_alloc(n);
  L->c = gsl_vector_alloc(p);
  L->D = gsl_vector_alloc(p);
  L->S = gsl_vector_alloc(p);
  L->sw = gsl_vector_alloc(p);
  L->r = gsl_vector_alloc(n);
  L->R = gsl_matrix_alloc(p, p);
  L->V = gsl_matrix_alloc(p, p);
  L->cov = gsl_matrix_alloc(p, p);
  L->ws = gsl_multifit_linear_alloc(n, p);
  if (!L->A || !L->X || !L->tau || !L->w || !L->y || !L->c || !L->D || !L->S ||
      !L->sw || !L->r || !L->R || !L->V || !L->cov || !L->ws) {
    lsq_free(L);
    return RPS3_ENOMEM;
  }
  return RPS3_OK;
}

/*
 * The rank of the weighted regressor (weights in L->w): its columns
 * scaled to unit norm (scales in L->D, 1 for a zero column), the R factor
 * of a QR, then the singular values of R (those of the scaled
 * regressor).  Writes cond, rank and the flags of the columns in the
 * directions below tol.
 */
static void lsq_rank(const rps3_ident_data *dt, lsq *L, double tol,
                     double *cond, size_t *rank, int *flags) {
  size_t n = dt->n, p = dt->p, r, j, k;
  double smax, dmax;
  for (j = 0; j < p; j++) gsl_vector_set(L->D, j, 0.0);
  for (r = 0; r < n; r++) {
    double sw = sqrt(gsl_vector_get(L->w, r));
    for (j = 0; j < p; j++) {
      double a = sw * dt->Y[r * p + j];
      gsl_matrix_set(L->A, r, j, a);
      L->D->data[j * L->D->stride] += a * a;
    }
  }
  /* a column below tol times the largest is rounding: zero, not scaled
     up into a column of its own */
  dmax = 0.0;
  for (j = 0; j < p; j++) {
    double s = sqrt(gsl_vector_get(L->D, j));
    gsl_vector_set(L->D, j, s);
    if (s > dmax) dmax = s;
  }
  for (j = 0; j < p; j++) {
    double s = gsl_vector_get(L->D, j);
    int zero = !(s > tol * dmax);
    gsl_vector_set(L->D, j, zero ? 1.0 : s);
    for (r = 0; r < n; r++)
      gsl_matrix_set(L->A, r, j, zero ? 0.0 : gsl_matrix_get(L->A, r, j) / s);
  }
  gsl_linalg_QR_decomp(L->A, L->tau);
  for (j = 0; j < p; j++)
    for (k = 0; k < p; k++)
      gsl_matrix_set(L->R, j, k, k >= j ? gsl_matrix_get(L->A, j, k) : 0.0);
  gsl_linalg_SV_decomp(L->R, L->V, L->S, L->sw);
  smax = gsl_vector_get(L->S, 0);
  *cond = gsl_vector_get(L->S, p - 1) > 0.0 ? smax / gsl_vector_get(L->S, p - 1)
                                            : HUGE_VAL;
  *rank = 0;
  for (k = 0; k < p; k++)
    if (gsl_vector_get(L->S, k) > tol * smax) (*rank)++;
  /* a column is not determined when a tenth of it or more lies in the
     span of the weak right singular vectors */
  for (j = 0; j < p; j++) {
    double share = 0.0;
    for (k = *rank; k < p; k++)
      share += gsl_matrix_get(L->V, j, k) * gsl_matrix_get(L->V, j, k);
    if (flags) flags[j] = smax == 0.0 || sqrt(share) >= 0.1;
  }
}

/* the weighted fit (full rank): theta and the unscaled (Y^T W Y)^-1 into
   L->cov in theta's units, chisq */
static void lsq_fit(const rps3_ident_data *dt, lsq *L, double *theta,
                    double *chisq) {
  size_t n = dt->n, p = dt->p, r, j, k;
  for (r = 0; r < n; r++) {
    for (j = 0; j < p; j++)
      gsl_matrix_set(L->X, r, j, dt->Y[r * p + j] / gsl_vector_get(L->D, j));
    gsl_vector_set(L->y, r, dt->F[r]);
  }
  gsl_multifit_wlinear(L->X, L->w, L->y, L->c, L->cov, chisq, L->ws);
  for (j = 0; j < p; j++) {
    theta[j] = gsl_vector_get(L->c, j) / gsl_vector_get(L->D, j);
    for (k = 0; k < p; k++)
      gsl_matrix_set(L->cov, j, k,
                     gsl_matrix_get(L->cov, j, k) /
                         (gsl_vector_get(L->D, j) * gsl_vector_get(L->D, k)));
  }
}

/* each actuator's residual variance |r_a|^2 / (n_a - p n_a / n) */
static void actuator_sigma(const rps3_ident_data *dt, const double *theta,
                           double var[3]) {
  size_t r, j, na[3] = {0, 0, 0};
  double ss[3] = {0, 0, 0};
  for (r = 0; r < dt->n; r++) {
    double f = dt->F[r];
    int a = actuator_of(dt, r);
    for (j = 0; j < dt->p; j++) f -= dt->Y[r * dt->p + j] * theta[j];
    ss[a] += f * f;
    na[a]++;
  }
  for (j = 0; j < 3; j++) {
    double dof = (double)na[j] * (1.0 - (double)dt->p / (double)dt->n);
    var[j] = na[j] > 0 ? ss[j] / dof : (double)NAN;
  }
}

/* room kept at the message's end for " and 4096 more" */
#define RANK_FAIL_TAIL 16

/* the message naming the columns flagged: as many as the message holds,
   then how many more (res->unident flags every one) */
static int rank_fail(const rps3_ident_data *dt, const int *flags, size_t rank,
                     double cond, double tol, char *err, size_t errsz) {
  char buf[32];
  size_t j, len, left = 0;
  if (err == NULL || errsz == 0)
    return rps3_ident_fail(NULL, 0, RPS3_ESING, "%s", "");
  snprintf(err, errsz,
           "the regressor has rank %lu < %lu columns (condition number %.3g "
           "of its unit-norm columns, rank_tol %.3g): the data do not "
           "determine",
           (unsigned long)rank, (unsigned long)dt->p, cond, tol);
  for (j = 0; j < dt->p; j++) {
    const char *name;
    if (!flags[j]) continue;
    name = col_name(dt, j, buf, sizeof(buf));
    len = strlen(err);
    if (left > 0 || len + 1 + strlen(name) + RANK_FAIL_TAIL >= errsz)
      left++;
    else
      snprintf(err + len, errsz - len, " %s", name);
  }
  if (left > 0) {
    len = strlen(err);
    snprintf(err + len, errsz - len, " and %lu more", (unsigned long)left);
  }
  return rps3_ident_fail(NULL, 0, RPS3_ESING, "%s", "");
}

int rps3_ident_wls(const rps3_ident_data *dt, const rps3_ident_opts *o,
                   rps3_ident_result *res, rps3_check *chk) {
  char *err = chk != NULL ? chk->msg : NULL;
  size_t errsz = chk != NULL ? sizeof chk->msg : 0;
  rps3_ident_opts def;
  lsq L;
  int status, *flags;
  size_t p, r, j, k, rank;
  double cond, chisq, var[3], t, msq = 0.0;
  rps3_check_clear(chk);
  if (o == NULL) {
    rps3_ident_opts_default(&def);
    o = &def;
  }
  if (res == NULL || res->theta == NULL)
    return rps3_ident_fail(err, errsz, RPS3_EINVAL,
                           "res or res->theta is NULL");
  status = rps3_ident_check_data(dt, o, dt != NULL && dt->weight == NULL, err,
                                 errsz);
  if (status != RPS3_OK) return status;
  p = dt->p;
  flags = malloc(p * sizeof(int));
  if (flags == NULL || lsq_alloc(&L, dt->n, p) != RPS3_OK) {
    free(flags);
    return rps3_ident_fail(err, errsz, RPS3_ENOMEM,
                           "wls: out of memory for %lu x %lu",
                           (unsigned long)dt->n, (unsigned long)p);
  }
  for (j = 0; j < p; j++) res->theta[j] = (double)NAN;

  /* pass 1: the given weights, or none */
  for (r = 0; r < dt->n; r++) {
    gsl_vector_set(L.w, r, dt->weight ? dt->weight[r] : 1.0);
    msq += dt->F[r] * dt->F[r] / (double)dt->n;
  }
  lsq_rank(dt, &L, o->rank_tol, &cond, &rank, flags);
  if (rank == p) {
    lsq_fit(dt, &L, res->theta, &chisq);
    actuator_sigma(dt, res->theta, var);
    if (dt->weight == NULL) {
      /* pass 2: each actuator weighted by its inverse noise variance;
         the floor keeps exact data at equal weights */
      for (j = 0; j < 3; j++)
        if (!(var[j] >= 1e-24 * msq)) var[j] = 1e-24 * msq;
      if (!(var[0] > 0.0)) var[0] = var[1] = var[2] = 1.0; /* F = 0 */
      for (r = 0; r < dt->n; r++)
        gsl_vector_set(L.w, r, 1.0 / var[actuator_of(dt, r)]);
      lsq_rank(dt, &L, o->rank_tol, &cond, &rank, flags);
      if (rank == p) lsq_fit(dt, &L, res->theta, &chisq);
    }
  }
  res->cond = cond;
  res->rank = rank;
  res->dof = dt->n - p;
  if (res->unident)
    for (j = 0; j < p; j++) res->unident[j] = flags[j];
  if (rank < p) {
    for (j = 0; j < p; j++) {
      res->theta[j] = (double)NAN;
      if (res->ci) res->ci[2 * j] = res->ci[2 * j + 1] = (double)NAN;
      for (k = 0; k < p && res->cov; k++) res->cov[j * p + k] = (double)NAN;
    }
    res->s2 = (double)NAN;
    for (j = 0; j < 3; j++) res->sigma[j] = (double)NAN;
    status = rank_fail(dt, flags, rank, cond, o->rank_tol, err, errsz);
    lsq_free(&L);
    free(flags);
    return status;
  }
  for (j = 0; j < 3; j++) res->sigma[j] = sqrt(var[j]);
  res->s2 = chisq / (double)res->dof;
  t = gsl_cdf_tdist_Pinv(0.5 * (1.0 + o->level), (double)res->dof);
  for (j = 0; j < p; j++) {
    double sd = sqrt(res->s2 * gsl_matrix_get(L.cov, j, j));
    if (res->ci) {
      res->ci[2 * j] = res->theta[j] - t * sd;
      res->ci[2 * j + 1] = res->theta[j] + t * sd;
    }
    for (k = 0; k < p && res->cov; k++)
      res->cov[j * p + k] = res->s2 * gsl_matrix_get(L.cov, j, k);
  }
  lsq_free(&L);
  free(flags);
  for (j = 0; j < p; j++)
    if (!isfinite(res->theta[j]))
      return rps3_ident_fail(err, errsz, RPS3_ERANGE,
                             "wls: theta[%lu] is not finite", (unsigned long)j);
  return RPS3_OK;
}
