/*
 * ident_consistent.c - the physically consistent fit on a stacked
 * regressor: each body's pseudo-inertia by its Cholesky factor, first
 * log-Cholesky (Rucker & Wensing 2022: the logarithms of the diagonal,
 * friction by its logarithm), then plain (the diagonal itself, friction
 * by its square root), which reaches an optimum on the boundary of the
 * cone; solved with GSL's nonlinear least squares and an analytic
 * Jacobian; where the plain stage does not finish in a few iterations
 * (an optimum inside a face of the cone), the convex problem itself by
 * the barrier method (src/ident_cbar.c); all to a KKT optimality test,
 * the eigenvalues checked after the fit.  The variables, the residual
 * and the optimality measure are src/ident_cfit.c's; this file checks
 * the layout, starts, drives the stages and checks what they reached.
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

#include "ident_cfit.h"
#include "ident_int.h"
#include "internal.h"

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
    rps3_cfit_pseudo_of(s, J);
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
      double u = U[rps3_cfit_UA[k]][rps3_cfit_UB[k]];
      x[10 * b + (size_t)k] =
          rps3_cfit_UA[k] == rps3_cfit_UB[k] ? log(fabs(u)) : u;
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

/* converged: the measure within opt_tol of the cost, or at its floor */
static int optimal(double gap, double cost, const rps3_ident_opts *o) {
  return rps3_cfit_optimal(gap, cost, o->opt_tol);
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
  const double rho2 =
      c->R[c->p * (c->p + 1) + c->p] * c->R[c->p * (c->p + 1) + c->p];
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
  fdf.f = rps3_cfit_f;
  fdf.df = rps3_cfit_df;
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
    rps3_cfit_pi_of(c, gsl_multifit_nlinear_position(w)->data, theta, body);
    *gap = rps3_cfit_optimality(c, theta, body, c->sreg * c->sreg, NULL);
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
    rps3_cfit_pi_of(c, x, theta, body);
    *gap = rps3_cfit_optimality(c, theta, body, c->sreg * c->sreg, NULL);
  }
  gsl_multifit_nlinear_free(w);
  return RPS3_OK;
}

/* the plain Cholesky variables' problem: the curvature rows after the
   residual's and the bodies' trace rows */
static void plain_mode(cfit *c) {
  size_t j;
  c->plain = 1;
  c->ncurv = 16 * c->nb;
  for (j = 0; j < c->p; j++)
    c->ncurv += c->owner[j] < 0 && rps3_cfit_is_nonneg(c, j);
  c->nf = c->p + 10 * c->nb + c->ncurv;
}

/* the plain stage's first iterations, before the barrier stage: where
   the log-Cholesky stage ended near the optimum it converges in a few
   (the paper model's fits: 0 to 10); on a face of the cone it would crawl
   for hundreds */
#define PLAIN_TRY 20

/* the plain Cholesky variables from x until the optimality test (*gst
   GSL_SUCCESS) or fit->niter reaches until (or the budget); theta, body
   and fit->gap of the last iterate; RPS3_OK or RPS3_ENOMEM */
static int plain_stage(cfit *c, double *x, const rps3_ident_opts *o,
                       size_t until, rps3_ident_fit *fit, double *body,
                       int *gst) {
  int status = RPS3_OK;
  if (until > (size_t)o->max_iter) until = (size_t)o->max_iter;
  for (;;) {
    descent d;
    status = solve(c, x, o,
                   until > (size_t)fit->niter ? until - (size_t)fit->niter : 0,
                   &fit->niter, gst, fit->theta, body, &fit->gap);
    if (status != RPS3_OK || *gst == GSL_SUCCESS || *gst == GSL_EMAXITER ||
        (size_t)fit->niter >= until)
      break;
    /* stopped short of optimality: out of the stationary point along
       the best descent step of the convex problem, and on (an
       iteration of the budget, so that this ends) */
    rps3_cfit_optimality(c, fit->theta, body, o->reg, &d);
    if (!rps3_cfit_escape(c, x, &d, body)) break;
    fit->niter++;
  }
  return status;
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
    rps3_cfit_pseudo_of(body + 10 * b, J);
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
        RPS3_CFIT_GAP_FLOOR);
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
  double *R = NULL, *x0 = NULL, *y = NULL, *body = NULL, scale = 1.0;
  cbar bw;
  rps3_check_clear(chk);
  memset(&c, 0, sizeof c);
  memset(&bw, 0, sizeof bw);
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
  y = calloc(nx, sizeof(double));
  body = calloc(10 * lay->nbody + 1, sizeof(double));
  if (!R || !x0 || !y || !body) {
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
  c.work = malloc(3 * p * sizeof(double));
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
  if (status == RPS3_OK) status = rps3_cbar_alloc(&bw, &c);
  if (status == RPS3_OK) {
    /* from the interior in the log-Cholesky variables, where Gauss-Newton
       is at its best; a few iterations in the plain Cholesky ones, which
       reach the boundary of the cone at finite values and finish where
       the log-Cholesky stage ended near the optimum (the paper model's
       fits); else the convex problem itself by the barrier method from
       there, and where that stops short (a stalled step), on in the plain
       variables to the optimality test */
    const size_t budget = (size_t)o->max_iter;
    size_t j2;
    double cost;
    status = solve(&c, x0, o, budget < LOG_ITER ? budget : LOG_ITER,
                   &fit->niter, &gst, NULL, NULL, NULL);
    if (status == RPS3_OK) {
      rps3_cfit_pi_of(&c, x0, fit->theta, body);
      plain_mode(&c);
      rps3_cfit_plain_of(&c, body, fit->theta, x0);
      status = plain_stage(&c, x0, o, (size_t)fit->niter + PLAIN_TRY, fit, body,
                           &gst);
    }
    if (status == RPS3_OK && gst != GSL_SUCCESS &&
        (size_t)fit->niter < budget) {
      memcpy(y, body, 10 * c.nb * sizeof(double));
      for (j2 = 0; j2 < p; j2++)
        if (owner[j2] < 0) y[slot[j2]] = fit->theta[j2];
      if (rps3_cbar_solve(&c, &bw, y, o->reg, o->opt_tol,
                          budget - (size_t)fit->niter, &fit->niter, fit->theta,
                          body, &fit->gap, &cost))
        goto check;
      rps3_cfit_plain_of(&c, body, fit->theta, x0);
      status = plain_stage(&c, x0, o, budget, fit, body, &gst);
    }
  }
  if (status != RPS3_OK) {
    status = rps3_ident_fail(err, errsz, status,
                             status == RPS3_ENOMEM
                                 ? "consistent: out of memory"
                                 : "consistent: no consistent start");
    goto out;
  }
check:
  status = check_fit(&c, o, scale, body, gst, fit, err, errsz);
out:
  rps3_cbar_free(&bw);
  free(c.work);
  if (c.ew) gsl_eigen_symmv_free(c.ew);
  gsl_matrix_free(c.E);
  gsl_matrix_free(c.Q);
  gsl_vector_free(c.lam);
  free(R);
  free(x0);
  free(y);
  free(body);
  free(owner);
  free(slot);
  return status;
}
