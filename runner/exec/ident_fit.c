/* ident_fit.c - see ident_fit.h: one fit of the plan's rows (WLS, and the
   consistent fit of the paper layout or of the general one) and its
   held-out prediction. */
#include "ident_fit.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* the consistent fit of the chosen columns: the paper layout restricted to
   them and renumbered (python/rps3/ident_c.py paper_layout) */
static void fit_consistent(const ident_plan *p, const rps3_ident_data *data,
                           ident_fit *r) {
  const rps3_ident_layout *pl = rps3_ident_paper_layout();
  int col[2][10], kind[RPS3_NPAPER], where[RPS3_NPAPER];
  rps3_ident_layout lay;
  rps3_ident_fit fit;
  rps3_check chk;
  size_t b, j;
  int k;
  for (k = 0; k < RPS3_NPAPER; k++) where[k] = -1;
  for (j = 0; j < p->p; j++) {
    where[p->col[j]] = (int)j;
    kind[j] = pl->kind ? pl->kind[p->col[j]] : RPS3_IDENT_FREE;
  }
  for (b = 0; b < 2 && b < pl->nbody; b++)
    for (k = 0; k < 10; k++)
      col[b][k] = pl->col[b][k] >= 0 ? where[pl->col[b][k]] : -1;
  lay.nbody = pl->nbody < 2 ? pl->nbody : 2;
  lay.col = (const int(*)[10])col;
  lay.kind = kind;
  memset(&fit, 0, sizeof fit);
  fit.theta = r->ctheta;
  fit.body = &r->body[0][0];
  fit.eig = &r->eig[0][0];
  r->cstatus = rps3_ident_consistent(data, &lay, &p->opts, &fit, &chk);
  r->consistent = fit.consistent;
  r->crss = fit.rss;
  r->gap = fit.gap;
  r->niter = fit.niter;
  snprintf(r->cmsg, sizeof r->cmsg, "%s", r->cstatus == RPS3_OK ? "" : chk.msg);
}

/* the general model's consistent fit: every layout column, its bodies'
   pseudo-inertias positive semidefinite, the friction >= 0 */
static void fit_consistent_general(const ident_plan *p,
                                   const rps3_ident_data *base, ident_fit *r) {
  rps3_ident_data data = *base;
  rps3_ident_layout lay;
  rps3_ident_fit fit;
  rps3_check chk;
  data.p = p->nlay;
  data.Y = p->Ylay;
  data.names = p->lay_names;
  lay.nbody = p->nbody;
  lay.col = (const int(*)[10])p->body_col;
  lay.kind = p->lay_kind;
  memset(&fit, 0, sizeof fit);
  fit.theta = r->ctheta;
  fit.body = &r->body[0][0];
  fit.eig = &r->eig[0][0];
  r->cstatus = rps3_ident_consistent(&data, &lay, &p->opts, &fit, &chk);
  r->consistent = fit.consistent;
  r->crss = fit.rss;
  r->gap = fit.gap;
  r->niter = fit.niter;
  snprintf(r->cmsg, sizeof r->cmsg, "%s", r->cstatus == RPS3_OK ? "" : chk.msg);
}

void ident_fit_free(ident_fit *r) {
  if (!r) return;
  free(r->cov);
  r->cov = NULL;
}

void ident_fit_run(const ident_plan *p, const double *F, int consistent,
                   ident_fit *r) {
  ident_fit_rows(p, F, p->n, consistent, r);
}

void ident_fit_rows(const ident_plan *p, const double *F, size_t n,
                    int consistent, ident_fit *r) {
  rps3_ident_data data = {n, p->p, p->Y, F, NULL, NULL, p->names};
  rps3_ident_result res;
  rps3_check chk;
  size_t i, j;
  double ss = 0;
  memset(r, 0, sizeof *r);
  r->cstatus = -1;
  data.weight = p->ids.method == IDENT_OLS ? p->ones : NULL;
  memset(&res, 0, sizeof res);
  if (!(r->cov = malloc(p->p * p->p * sizeof *r->cov))) {
    r->status = RPS3_ENOMEM;
    snprintf(r->msg, sizeof r->msg, "out of memory");
    return;
  }
  res.theta = r->theta;
  res.cov = r->cov;
  res.ci = &r->ci[0][0];
  res.unident = r->unident;
  r->status = rps3_ident_wls(&data, &p->opts, &res, &chk);
  snprintf(r->msg, sizeof r->msg, "%s", r->status == RPS3_OK ? "" : chk.msg);
  for (i = 0; i < 3; i++) r->sigma[i] = res.sigma[i];
  r->s2 = res.s2;
  r->cond = res.cond;
  r->rank = res.rank;
  r->dof = res.dof;
  for (j = 0; j < p->p; j++) r->std[j] = sqrt(r->cov[j * p->p + j]);
  for (i = 0; i < n; i++) {
    double e = F[i];
    for (j = 0; j < p->p; j++) e -= p->Y[i * p->p + j] * r->theta[j];
    ss += e * e;
  }
  r->resid_rms = sqrt(ss / (double)n);
  if (consistent && r->status == RPS3_OK) {
    if (p->general)
      fit_consistent_general(p, &data, r);
    else
      fit_consistent(p, &data, r);
  }
}

/* the NRMSE of the prediction of F's rows [p->nfit, p->n) by the columns
   Y (ncol wide) times theta */
static double nrmse(const ident_plan *p, const double *Y, size_t ncol,
                    const double *theta, const double *F) {
  double se = 0, sf = 0;
  size_t i, j;
  for (i = p->nfit; i < p->n; i++) {
    double e = -F[i];
    for (j = 0; j < ncol; j++) e += Y[i * ncol + j] * theta[j];
    se += e * e;
    sf += F[i] * F[i];
  }
  return sf > 0 ? sqrt(se / sf) : (double)NAN;
}

void ident_holdout_nrmse(const ident_plan *p, const double *F,
                         const ident_fit *r, double *wls, double *cons) {
  *wls = *cons = (double)NAN;
  if (p->nfit >= p->n || r->status != RPS3_OK) return;
  *wls = nrmse(p, p->Y, p->p, r->theta, F);
  /* a consistent fit that did not converge still has its estimate: its
     prediction is said with its status */
  if (r->cstatus == RPS3_OK || r->cstatus == RPS3_ENOCONV)
    *cons = p->general ? nrmse(p, p->Ylay, p->nlay, r->ctheta, F)
                       : nrmse(p, p->Y, p->p, r->ctheta, F);
}
